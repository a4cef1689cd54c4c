/* bench_extproj.c - `make bench` figures of the extended-projection bake (Durand et al. 2000) on the
   demo city (gen city seed 1 size 1) and the forest (seed 1 size 1), one core, over an evenly
   spread subset of cells: BENCH <name> <value> <unit>.
   extproj_ms_per_cell: bake time per cell (the bake's preparation of the occluders included).
   extproj_tightness: mean PVS / mean ray-sampled visible set (16 points x 1024 rays per cell).
   extproj_culled_pct: mean share of the objects left out of a cell's PVS. */
#include "../tools/cli.h"
#include <stdlib.h>
#include <string.h>

static int bench(gen_kind kind, const char *name, uint32_t n) {
    gen_params gp;
    mesh m;
    mesh_cells cells;
    pvs_scene *scene;
    tool_error te;
    pvs_bake_desc bd;
    pvs_bake *bake;
    pvs_error pe;
    pvs_word *seen;
    pvs_box *sub;
    uint32_t c, objects;
    double t, pvs_sum = 0.0, seen_sum = 0.0;
    memset(&gp, 0, sizeof(gp));
    gp.kind = kind;
    gp.seed = 1;
    gp.size = 1.0f;
    mesh_init(&m);
    mesh_cells_init(&cells);
    if (gen_scene(&gp, &m, &cells)) return 1;
    if (cli_make_scene(name, &m, 1, &scene, &te)) { fprintf(stderr, "%s\n", te.message); return 1; }
    objects = pvs_scene_object_count(scene);
    if (n > cells.count) n = cells.count;
    sub = (pvs_box *)malloc(n * sizeof(pvs_box));
    for (c = 0; c < n; ++c) memcpy(sub + c, cells.boxes + 6 * (size_t)((uint64_t)c * cells.count / n), sizeof(pvs_box));
    memset(&bd, 0, sizeof(bd));
    bd.scene = scene;
    bd.cells = sub;
    bd.cell_count = n;
    bd.method = PVS_METHOD_EXTPROJ;
    t = cli_seconds();
    if (pvs_bake_begin(&bd, &bake, &pe) != PVS_OK) { fprintf(stderr, "%s\n", pe.message); return 1; }
    for (c = 0; c < n; ++c)
        if (pvs_bake_run_task(bake, c, &pe) != PVS_OK) { fprintf(stderr, "%s\n", pe.message); return 1; }
    t = cli_seconds() - t;
    seen = (pvs_word *)calloc(PVS_BITSET_WORDS(objects), sizeof(pvs_word));
    for (c = 0; c < n; ++c) {
        memset(seen, 0, PVS_BITSET_WORDS(objects) * sizeof(pvs_word));
        cli_reference_visibility(scene, sub + c, 77 + c, seen);
        seen_sum += pvs_bitset_count(seen, objects);
        pvs_sum += pvs_bitset_count(pvs_bake_cell_pvs(bake, c), objects);
    }
    printf("BENCH extproj_ms_per_cell_%s %.2f ms\n", name, 1000.0 * t / n);
    printf("BENCH extproj_tightness_%s %.2f\n", name, seen_sum > 0.0 ? pvs_sum / seen_sum : 0.0);
    printf("BENCH extproj_culled_pct_%s %.1f %%\n", name, 100.0 * (1.0 - pvs_sum / n / objects));
    free(seen);
    free(sub);
    pvs_bake_destroy(bake);
    pvs_scene_destroy(scene);
    mesh_free(&m);
    mesh_cells_free(&cells);
    return 0;
}

int main(void) {
    if (bench(GEN_CITY, "city", 60)) return 1;
    if (bench(GEN_FOREST, "forest", 30)) return 1;
    return 0;
}
