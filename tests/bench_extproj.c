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
   forest1000_subcells lines add pvs_bake_desc.extproj.sweep_subcells = 4 (the sweep's planes hold
   the umbrae of the cell's four quarters).
   The forest_paper lines: the same forest at the extent of the paper's (§7.2: about 7,750 trees of
   1,000 leaves, 7.8M triangles): FOREST_PAPER_SIZE times as wide, 7,339 trees (7.5M triangles)
   and 7,393 bushes, 15,261 objects, 10.6M triangles. The share culled grows with the forest's
   extent: the farther objects are the hidden ones.
   extproj_reference_visible_pct_forest: mean share of the objects the ray-sampled reference sees
   from those cells (the most any conservative method could cull is 100 minus this).
   extproj_reference_visible_pct_forest_aimed: the same on FOREST_AIMED_CELLS of those cells (1 for
   forest1000 and forest_paper) with FOREST_AIMED_RAYS more rays aimed at every object not yet seen: a
   tighter lower bound of the cells' exact visible sets (through the gaps between the leaves far more
   objects are visible from a 3 m cell than 32 aimed rays find, so 100 minus this bounds the culling
   any conservative method can reach there; it still grows with more rays).
   adaptive_cells / adaptive_bytes: the leaf cells and the file size of an adaptive bake (§6.1) of
   the city subset with a budget of ADAPTIVE_BUDGET triangles per cell. */
#include "../tools/cli.h"
#include "test.h"
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#define ADAPTIVE_BUDGET 50000u
#define FOREST_AIMED_CELLS 3u
#define FOREST_AIMED_RAYS 2048u
#define FOREST1000_CELLS 6u
#define FOREST1000_PLANES 64u
#define FOREST_PAPER_SIZE 1.5f

/* A scene and the evenly spread subset of its cells a bench bakes. */
typedef struct bench_scene {
    int paper;
    mesh m;
    mesh_cells cells;
    pvs_scene *scene;
    pvs_box *sub;
    uint32_t n;
} bench_scene;

/* `paper`: the dense forest at the paper's density with 1 m cells, baked at 1024 pixels; `size`
   scales the generator's extent (1: a forest 300 m across). The forest's inner cells are those at
   least 30 m from its edge. */
static int bench_load(bench_scene *bs, gen_kind kind, int dense, int paper, float size, const char *name, uint32_t n) {
    gen_params gp;
    tool_error te;
    uint32_t c, k = 0;
    double S = 5.0 * floor(300.0 * size / 5.0); /* the forest's side (gen__forest_grid) */
    memset(bs, 0, sizeof(*bs));
    bs->paper = paper;
    gp = test_gen_params(kind, 1, size, 0);
    gp.dense = dense;
    if (paper) {
        gp.leaves_per_tree = 1000;
        gp.cell_size = 1.0f;
    }
    if (test_generate(&gp, &bs->m, &bs->cells, NULL)) return 1;
    if (cli_make_scene(name, &bs->m, 1, &bs->scene, &te)) { fprintf(stderr, "%s\n", te.message); return 1; }
    /* the candidate cells (the forest's inner ones), then n of them evenly spread */
    bs->sub = (pvs_box *)malloc(bs->cells.count * sizeof(pvs_box));
    if (!bs->sub) return 1;
    for (c = 0; c < bs->cells.count; ++c) {
        const float *b = bs->cells.boxes + 6 * (size_t)c;
        if (kind == GEN_FOREST && (b[3] - b[0] > 5.0f || b[5] - b[2] > 5.0f)) continue; /* a clearing's tile */
        if (kind == GEN_FOREST && (b[0] < 30.0 || b[2] < 30.0 || b[3] > S - 30.0 || b[5] > S - 30.0)) continue; /* the edge */
        memcpy(bs->sub + k++, b, sizeof(pvs_box));
    }
    if (n > k) n = k;
    for (c = 0; c < n; ++c) bs->sub[c] = bs->sub[(uint64_t)c * k / n];
    bs->n = n;
    return 0;
}

static void bench_free(bench_scene *bs) {
    free(bs->sub);
    pvs_scene_destroy(bs->scene);
    mesh_free(&bs->m);
    mesh_cells_free(&bs->cells);
}

/* Bakes the subset with the sweep's `sweep` planes (0: none), `adaptive` (a budget, 0: none) and
   `subcells`, and prints its lines; `reference` adds the forest's reference lines. */
static int bench(const bench_scene *bs, const char *name, uint32_t sweep, uint32_t adaptive, uint32_t subcells, int reference) {
    pvs_bake_desc bd;
    pvs_bake *bake;
    pvs_error pe;
    pvs_word *seen;
    const pvs_box *sub = bs->sub;
    uint32_t c, n = bs->n, objects = pvs_scene_object_count(bs->scene);
    double t, pvs_sum = 0.0, seen_sum = 0.0;
    test_bake_desc(&bd, bs->scene, sub, n, PVS_METHOD_EXTPROJ);
    bd.extproj.sweep = sweep;
    bd.extproj.sweep_subcells = subcells;
    bd.adaptive.budget = adaptive;
    if (bs->paper) bd.extproj.resolution = 1024;
    t = test_cpu_seconds();
    if (pvs_bake_begin(&bd, &bake, &pe) != PVS_OK) { fprintf(stderr, "%s\n", pe.message); return 1; }
    for (c = 0; c < n; ++c)
        if (pvs_bake_run_task(bake, c, &pe) != PVS_OK) { fprintf(stderr, "%s\n", pe.message); return 1; }
    t = test_cpu_seconds() - t;
    if (adaptive) {
        printf("BENCH adaptive_cells_%s %u cells (from %u, budget %u triangles)\n", name, pvs_bake_leaf_count(bake), n, adaptive);
        printf("BENCH adaptive_bytes_%s %zu bytes\n", name, pvs_bake_file_size(bake));
        printf("BENCH adaptive_ms_per_cell_%s %.2f ms (per input cell)\n", name, 1000.0 * t / n);
    } else {
        seen = (pvs_word *)calloc(PVS_BITSET_WORDS(objects), sizeof(pvs_word));
        if (!seen) return 1;
        for (c = 0; c < n; ++c) {
            memset(seen, 0, PVS_BITSET_WORDS(objects) * sizeof(pvs_word));
            cli_reference_visibility(bs->scene, sub + c, 77 + c, seen);
            seen_sum += pvs_bitset_count(seen, objects);
            pvs_sum += pvs_bitset_count(pvs_bake_cell_pvs(bake, c), objects);
        }
        printf("BENCH extproj%s_ms_per_cell_%s %.2f ms\n", sweep ? "_sweep" : "", name, 1000.0 * t / n);
        printf("BENCH extproj%s_tightness_%s %.2f\n", sweep ? "_sweep" : "", name, seen_sum > 0.0 ? pvs_sum / seen_sum : 0.0);
        printf("BENCH extproj%s_culled_pct_%s %.1f %%\n", sweep ? "_sweep" : "", name, 100.0 * (1.0 - pvs_sum / n / objects));
        if (reference) {
            uint32_t na = n < FOREST_AIMED_CELLS ? n : FOREST_AIMED_CELLS;
            if (bs->paper) na = 1;
            printf("BENCH extproj_reference_visible_pct_%s %.1f %%\n", name, 100.0 * seen_sum / n / objects);
            seen_sum = 0.0;
            for (c = 0; c < na; ++c) { /* cells spread over the subset */
                uint32_t cc = (uint32_t)((uint64_t)c * n / na);
                memset(seen, 0, PVS_BITSET_WORDS(objects) * sizeof(pvs_word));
                cli_reference_visibility(bs->scene, sub + cc, 77 + cc, seen);
                pvs_sample_visibility_toward(bs->scene, sub + cc, NULL, FOREST_AIMED_RAYS, 991 + cc, seen);
                seen_sum += pvs_bitset_count(seen, objects);
            }
            printf("BENCH extproj_reference_visible_pct_%s_aimed %.1f %% (%u cells, %u more aimed rays per object)\n", name,
                   100.0 * seen_sum / na / objects, na, FOREST_AIMED_RAYS);
        }
        free(seen);
    }
    pvs_bake_destroy(bake);
    return 0;
}

int main(void) {
    bench_scene bs;
    if (bench_load(&bs, GEN_CITY, 0, 0, 1.0f, "city", 60)) return 1;
    if (bench(&bs, "city", 0, 0, 0, 0) || bench(&bs, "city", PVS_EXTPROJ_SWEEP_PLANES, 0, 0, 0) ||
        bench(&bs, "city_subcells", PVS_EXTPROJ_SWEEP_PLANES, 0, 4, 0))
        return 1;
    bench_free(&bs);
    if (bench_load(&bs, GEN_FOREST, 1, 0, 1.0f, "forest", 30)) return 1;
    if (bench(&bs, "forest", 0, 0, 0, 1) || bench(&bs, "forest", PVS_EXTPROJ_SWEEP_PLANES, 0, 0, 0)) return 1;
    bench_free(&bs);
    if (bench_load(&bs, GEN_FOREST, 1, 1, 1.0f, "forest1000", FOREST1000_CELLS)) return 1;
    if (bench(&bs, "forest1000", 0, 0, 0, 1) || bench(&bs, "forest1000", FOREST1000_PLANES, 0, 0, 0) ||
        bench(&bs, "forest1000_subcells", FOREST1000_PLANES, 0, 4, 0))
        return 1;
    bench_free(&bs);
    if (bench_load(&bs, GEN_FOREST, 1, 1, FOREST_PAPER_SIZE, "forest_paper", FOREST1000_CELLS)) return 1;
    if (bench(&bs, "forest_paper", 0, 0, 0, 1) || bench(&bs, "forest_paper", FOREST1000_PLANES, 0, 0, 0) ||
        bench(&bs, "forest_paper_subcells", FOREST1000_PLANES, 0, 4, 0))
        return 1;
    bench_free(&bs);
    if (bench_load(&bs, GEN_CITY, 0, 0, 1.0f, "city", 20)) return 1;
    if (bench(&bs, "city", 0, ADAPTIVE_BUDGET, 0, 0)) return 1;
    bench_free(&bs);
    return 0;
}
