/* bench_otree.c - `make bench` figures of the otree method (2.5D c-LSS) on the demo city (GEN_CITY,
   seed 1): BENCH <name> <value> <unit>. Tightness = mean PVS / mean ray-sampled set (>= 1; the
   sampled set is a lower bound of the exact one). */
#include "../tools/cli.h"
#include <stdlib.h>
#include <string.h>

int main(void) {
    gen_params gp;
    mesh m;
    mesh_cells cells;
    pvs_scene *scene;
    tool_error te;
    pvs_bake_desc bd;
    pvs_bake *bake;
    pvs_error pe;
    pvs_box *sub;
    pvs_word *bits;
    uint32_t c, n = 40, objects;
    double t, t_prep, sum_pvs = 0.0, sum_ref = 0.0;
    memset(&gp, 0, sizeof(gp));
    gp.kind = GEN_CITY;
    gp.seed = 1;
    gp.size = 1.0f;
    mesh_init(&m);
    mesh_cells_init(&cells);
    if (gen_scene(&gp, &m, &cells)) return 1;
    if (cli_make_scene("city", &m, 1, &scene, &te)) { fprintf(stderr, "%s\n", te.message); return 1; }
    objects = pvs_scene_object_count(scene);
    if (n > cells.count) n = cells.count;
    sub = (pvs_box *)malloc(n * sizeof(pvs_box));
    for (c = 0; c < n; ++c) memcpy(sub + c, cells.boxes + 6 * (size_t)((uint64_t)c * cells.count / n), sizeof(pvs_box));
    memset(&bd, 0, sizeof(bd));
    bd.scene = scene;
    bd.cells = sub;
    bd.cell_count = n;
    bd.method = PVS_METHOD_OTREE;
    t = cli_seconds();
    if (pvs_bake_begin(&bd, &bake, &pe) != PVS_OK) { fprintf(stderr, "%s\n", pe.message); return 1; }
    t_prep = cli_seconds() - t;
    t = cli_seconds();
    for (c = 0; c < n; ++c)
        if (pvs_bake_run_task(bake, c, &pe) != PVS_OK) { fprintf(stderr, "%s\n", pe.message); return 1; }
    t = cli_seconds() - t;
    printf("BENCH otree_prepare_ms %.1f ms\n", 1000.0 * t_prep); /* facade extraction + kD-tree, once per bake */
    printf("BENCH otree_ms_per_cell %.2f ms\n", 1000.0 * t / n);  /* one core */
    bits = (pvs_word *)calloc(PVS_BITSET_WORDS(objects), sizeof(pvs_word));
    for (c = 0; c < n; ++c) {
        memset(bits, 0, PVS_BITSET_WORDS(objects) * sizeof(pvs_word));
        cli_reference_visibility(scene, sub + c, c, bits);
        sum_ref += pvs_bitset_count(bits, objects);
        sum_pvs += pvs_bitset_count(pvs_bake_cell_pvs(bake, c), objects);
    }
    printf("BENCH otree_mean_pvs %.1f objects\n", sum_pvs / n);
    printf("BENCH otree_tightness %.3f ratio\n", sum_ref > 0 ? sum_pvs / sum_ref : 0.0);
    free(bits);
    free(sub);
    pvs_bake_destroy(bake);
    pvs_scene_destroy(scene);
    mesh_cells_free(&cells);
    mesh_free(&m);
    return 0;
}
