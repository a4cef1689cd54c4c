/* bench_extproj.c - `make bench` figures of the extended-projection bake (Durand et al. 2000) on the
   demo city (gen city seed 1 size 1) and the dense forest (gen forest --dense, seed 1 size 1: the
   forest of Durand 2000 §7.2, foliage down to eye height), one core, over an evenly spread subset
   of cells: BENCH <name> <value> <unit>.
   extproj_ms_per_cell: bake time per cell in CPU seconds (clock()), the bake's preparation of the
   occluders included (amortized over the subset: over the whole demo city it is a tenth of this).
   extproj_tightness: mean PVS / mean ray-sampled visible set (cli_reference_visibility: uniform and
   aimed rays).
   extproj_culled_pct: mean share of the objects left out of a cell's PVS.
   The _sweep lines add the occlusion sweep (§5, PVS_EXTPROJ_SWEEP_PLANES planes per direction).
   The forest lines count only the cells inside the forest (the 3 m boxes between the trees, not
   the 10 m tiles of the clearings, and at least 30 m from its edge).
   The forest1000 lines: the dense forest at the paper's density (gen leaves_per_tree 1000, bushes
   as dense, 4.6M triangles) with 1 m cells, baked at 1024 pixels and FOREST1000_PLANES sweep planes
   per direction (at the defaults, 256 and 16, the sweep culls about 8% there); the
   forest1000_subcells lines add pvs_bake_desc.extproj_sweep_subcells = 4 (the sweep's planes hold
   the umbrae of the cell's four quarters).
   extproj_reference_visible_pct_forest: mean share of the objects the ray-sampled reference sees
   from those cells (the most any conservative method could cull is 100 minus this).
   extproj_reference_visible_pct_forest_aimed: the same on FOREST_AIMED_CELLS of those cells (1 for
   forest1000) with FOREST_AIMED_RAYS more rays aimed at every object not yet seen: a tighter lower
   bound of the cells' exact visible sets (through the gaps between the leaves far more objects are
   visible from a 3 m cell than 32 aimed rays find, so 100 minus this bounds the culling any
   conservative method can reach there; it still grows with more rays).
   adaptive_cells / adaptive_bytes: the leaf cells and the file size of an adaptive bake (§6.1) of
   the city subset with a budget of ADAPTIVE_BUDGET triangles per cell. */
#include "../tools/cli.h"
#include <stdlib.h>
#include <string.h>
#include <time.h>

static double cpu_seconds(void) { return (double)clock() / CLOCKS_PER_SEC; }

#define ADAPTIVE_BUDGET 50000u
#define FOREST_AIMED_CELLS 3u
#define FOREST_AIMED_RAYS 2048u
#define FOREST1000_CELLS 6u
#define FOREST1000_PLANES 64u

/* `paper`: the dense forest at the paper's density with 1 m cells, baked at 1024 pixels. */
static int bench(gen_kind kind, int dense, int paper, const char *name, uint32_t n, uint32_t sweep, uint32_t adaptive, uint32_t subcells) {
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
    uint32_t c, objects, k = 0;
    double t, pvs_sum = 0.0, seen_sum = 0.0;
    memset(&gp, 0, sizeof(gp));
    gp.kind = kind;
    gp.seed = 1;
    gp.size = 1.0f;
    gp.dense = dense;
    if (paper) {
        gp.leaves_per_tree = 1000;
        gp.cell_size = 1.0f;
    }
    mesh_init(&m);
    mesh_cells_init(&cells);
    if (gen_scene(&gp, &m, &cells)) return 1;
    if (cli_make_scene(name, &m, 1, &scene, &te)) { fprintf(stderr, "%s\n", te.message); return 1; }
    objects = pvs_scene_object_count(scene);
    /* the candidate cells (the forest's inner ones), then n of them evenly spread */
    sub = (pvs_box *)malloc(cells.count * sizeof(pvs_box));
    for (c = 0; c < cells.count; ++c) {
        const float *b = cells.boxes + 6 * (size_t)c;
        if (kind == GEN_FOREST && (b[3] - b[0] > 5.0f || b[5] - b[2] > 5.0f)) continue; /* a clearing's tile */
        if (kind == GEN_FOREST && (b[0] < 30.0f || b[2] < 30.0f || b[3] > 270.0f || b[5] > 270.0f)) continue; /* the edge */
        memcpy(sub + k++, b, sizeof(pvs_box));
    }
    if (n > k) n = k;
    for (c = 0; c < n; ++c) sub[c] = sub[(uint64_t)c * k / n];
    memset(&bd, 0, sizeof(bd));
    bd.scene = scene;
    bd.cells = sub;
    bd.cell_count = n;
    bd.method = PVS_METHOD_EXTPROJ;
    bd.extproj_sweep = sweep;
    bd.extproj_sweep_subcells = subcells;
    bd.adaptive_budget = adaptive;
    if (paper) bd.extproj_resolution = 1024;
    t = cpu_seconds();
    if (pvs_bake_begin(&bd, &bake, &pe) != PVS_OK) { fprintf(stderr, "%s\n", pe.message); return 1; }
    for (c = 0; c < n; ++c)
        if (pvs_bake_run_task(bake, c, &pe) != PVS_OK) { fprintf(stderr, "%s\n", pe.message); return 1; }
    t = cpu_seconds() - t;
    if (adaptive) {
        printf("BENCH adaptive_cells_%s %u cells (from %u, budget %u triangles)\n", name, pvs_bake_leaf_count(bake), n, adaptive);
        printf("BENCH adaptive_bytes_%s %zu bytes\n", name, pvs_bake_file_size(bake));
        printf("BENCH adaptive_ms_per_cell_%s %.2f ms (per input cell)\n", name, 1000.0 * t / n);
    } else {
        seen = (pvs_word *)calloc(PVS_BITSET_WORDS(objects), sizeof(pvs_word));
        for (c = 0; c < n; ++c) {
            memset(seen, 0, PVS_BITSET_WORDS(objects) * sizeof(pvs_word));
            cli_reference_visibility(scene, sub + c, 77 + c, seen);
            seen_sum += pvs_bitset_count(seen, objects);
            pvs_sum += pvs_bitset_count(pvs_bake_cell_pvs(bake, c), objects);
        }
        printf("BENCH extproj%s_ms_per_cell_%s %.2f ms\n", sweep ? "_sweep" : "", name, 1000.0 * t / n);
        printf("BENCH extproj%s_tightness_%s %.2f\n", sweep ? "_sweep" : "", name, seen_sum > 0.0 ? pvs_sum / seen_sum : 0.0);
        printf("BENCH extproj%s_culled_pct_%s %.1f %%\n", sweep ? "_sweep" : "", name, 100.0 * (1.0 - pvs_sum / n / objects));
        if (kind == GEN_FOREST && !sweep && !subcells) {
            uint32_t na = n < FOREST_AIMED_CELLS ? n : FOREST_AIMED_CELLS;
            if (paper) na = 1;
            printf("BENCH extproj_reference_visible_pct_%s %.1f %%\n", name, 100.0 * seen_sum / n / objects);
            seen_sum = 0.0;
            for (c = 0; c < na; ++c) { /* cells spread over the subset */
                uint32_t cc = (uint32_t)((uint64_t)c * n / na);
                memset(seen, 0, PVS_BITSET_WORDS(objects) * sizeof(pvs_word));
                cli_reference_visibility(scene, sub + cc, 77 + cc, seen);
                pvs_sample_visibility_toward(scene, sub + cc, NULL, FOREST_AIMED_RAYS, 991 + cc, seen);
                seen_sum += pvs_bitset_count(seen, objects);
            }
            printf("BENCH extproj_reference_visible_pct_%s_aimed %.1f %% (%u cells, %u more aimed rays per object)\n", name,
                   100.0 * seen_sum / na / objects, na, FOREST_AIMED_RAYS);
        }
        free(seen);
    }
    free(sub);
    pvs_bake_destroy(bake);
    pvs_scene_destroy(scene);
    mesh_free(&m);
    mesh_cells_free(&cells);
    return 0;
}

int main(void) {
    if (bench(GEN_CITY, 0, 0, "city", 60, 0, 0, 0)) return 1;
    if (bench(GEN_CITY, 0, 0, "city", 60, PVS_EXTPROJ_SWEEP_PLANES, 0, 0)) return 1;
    if (bench(GEN_CITY, 0, 0, "city_subcells", 60, PVS_EXTPROJ_SWEEP_PLANES, 0, 4)) return 1;
    if (bench(GEN_FOREST, 1, 0, "forest", 30, 0, 0, 0)) return 1;
    if (bench(GEN_FOREST, 1, 0, "forest", 30, PVS_EXTPROJ_SWEEP_PLANES, 0, 0)) return 1;
    if (bench(GEN_FOREST, 1, 1, "forest1000", FOREST1000_CELLS, 0, 0, 0)) return 1;
    if (bench(GEN_FOREST, 1, 1, "forest1000", FOREST1000_CELLS, FOREST1000_PLANES, 0, 0)) return 1;
    if (bench(GEN_FOREST, 1, 1, "forest1000_subcells", FOREST1000_CELLS, FOREST1000_PLANES, 0, 4)) return 1;
    if (bench(GEN_CITY, 0, 0, "city", 20, 0, ADAPTIVE_BUDGET, 0)) return 1;
    return 0;
}
