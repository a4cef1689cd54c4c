/* bench_shrink.c - `make bench` figures of the shrink method (Wonka 2000) on the demo city and the
   indoor plan, for eps at 0.5x, 1x and 2x the default (the paper's Fig. 5 study):
     BENCH shrink_ms_per_cell_<scene>_<f>x    bake time per cell, one core (synthesis excluded)
     BENCH shrink_synthesis_ms_<scene>_<f>x   occluder synthesis, once per bake
     BENCH shrink_tightness_<scene>_<f>x      mean PVS / mean ray-sampled visible set (>= 1 when conservative)
     BENCH shrink_culled_pct_<scene>_<f>x     objects left out of the PVS, percent
   Over an evenly spread subset of BENCH_CELLS cells (default 60). Never asserts on time. */
#include "../tools/cli.h"
#include <stdlib.h>
#include <string.h>

static int run(const char *name, gen_kind kind, uint32_t max_cells) {
    gen_params gp;
    mesh m;
    mesh_cells cells;
    pvs_scene *scene;
    tool_error te;
    pvs_error e;
    pvs_word *ref;
    uint32_t objects, c;
    float base_eps = 0.0f;
    static const float factors[3] = {0.5f, 1.0f, 2.0f};
    int f;
    memset(&gp, 0, sizeof(gp));
    gp.kind = kind;
    gp.seed = 1;
    gp.size = 1.0f;
    gp.max_cells = max_cells;
    mesh_init(&m);
    mesh_cells_init(&cells);
    if (gen_scene(&gp, &m, &cells)) return 1;
    if (cli_make_scene(name, &m, 1, &scene, &te)) { fprintf(stderr, "%s\n", te.message); return 1; }
    objects = pvs_scene_object_count(scene);
    ref = (pvs_word *)calloc(PVS_BITSET_WORDS(objects) * (size_t)cells.count, sizeof(pvs_word));
    {   /* the ray-sampled visible sets, once */
        double sampled = 0.0;
        for (c = 0; c < cells.count; ++c) {
            pvs_word *r = ref + PVS_BITSET_WORDS(objects) * (size_t)c;
            cli_reference_visibility(scene, (const pvs_box *)(cells.boxes + 6 * (size_t)c), 7 + c, r);
            sampled += pvs_bitset_count(r, objects);
        }
        for (f = 0; f < 3; ++f) {
            pvs_bake_desc bd;
            pvs_bake *b = NULL;
            double t, t_syn, in_pvs = 0.0;
            uint32_t misses = 0, i;
            memset(&bd, 0, sizeof(bd));
            bd.scene = scene;
            bd.cells = (const pvs_box *)cells.boxes;
            bd.cell_count = cells.count;
            bd.method = PVS_METHOD_SHRINK;
            bd.eps = base_eps * factors[f];
            t = cli_seconds();
            if (pvs_bake_begin(&bd, &b, &e) != PVS_OK) { fprintf(stderr, "%s\n", e.message); return 1; }
            t_syn = cli_seconds() - t;
            if (f == 0 && base_eps == 0.0f) { /* learn the default, then redo at 0.5x */
                base_eps = pvs_bake_eps(b);
                pvs_bake_destroy(b);
                --f;
                continue;
            }
            t = cli_seconds();
            for (c = 0; c < cells.count; ++c)
                if (pvs_bake_run_task(b, c, &e) != PVS_OK) { fprintf(stderr, "%s\n", e.message); return 1; }
            t = cli_seconds() - t;
            for (c = 0; c < cells.count; ++c) {
                const pvs_word *p = pvs_bake_cell_pvs(b, c), *r = ref + PVS_BITSET_WORDS(objects) * (size_t)c;
                in_pvs += pvs_bitset_count(p, objects);
                for (i = 0; i < objects; ++i) misses += pvs_bitset_test(r, i) && !pvs_bitset_test(p, i);
            }
            printf("BENCH shrink_ms_per_cell_%s_%gx %.2f ms (eps %g, %s)\n", name, (double)factors[f], 1000.0 * t / cells.count,
                   (double)pvs_bake_eps(b), pvs_bake_shrink_mode(b) == PVS_SHRINK_2D5 ? "2.5D" : "3D");
            printf("BENCH shrink_synthesis_ms_%s_%gx %.1f ms\n", name, (double)factors[f], 1000.0 * t_syn);
            printf("BENCH shrink_tightness_%s_%gx %.3f (misses %u)\n", name, (double)factors[f], sampled > 0 ? in_pvs / sampled : 0.0, misses);
            printf("BENCH shrink_culled_pct_%s_%gx %.1f %%\n", name, (double)factors[f],
                   100.0 * (1.0 - in_pvs / ((double)cells.count * objects)));
            fflush(stdout);
            pvs_bake_destroy(b);
        }
    }
    free(ref);
    pvs_scene_destroy(scene);
    mesh_cells_free(&cells);
    mesh_free(&m);
    return 0;
}

int main(void) {
    const char *env = getenv("BENCH_CELLS");
    uint32_t n = env ? (uint32_t)atoi(env) : 60u;
    if (n == 0) n = 60;
    if (run("city", GEN_CITY, n)) return 1;
    if (run("indoor", GEN_INDOOR, n)) return 1;
    return 0;
}
