/* bench_shrink.c - `make bench` figures of the shrink method (Wonka 2000) on the demo city and the
   indoor plan (seed 1, size 1, every cell of the scene in the bake, so the occluder synthesis and
   the default eps are the ones pvsbake uses), for eps at 0.5x, 1x and 2x the default (the paper's
   Fig. 5 study):
     BENCH shrink_ms_per_cell_<scene>_<f>x    bake time per cell, one core (synthesis excluded)
     BENCH shrink_synthesis_ms_<scene>_<f>x   occluder synthesis, once per bake
     BENCH shrink_tightness_<scene>_<f>x      mean PVS / mean reference set (ray sampling, uniform and
                                              aimed at every object: a lower bound of the exact set)
     BENCH shrink_culled_pct_<scene>_<f>x     objects left out of the PVS, percent
     BENCH shrink_misses_<scene>_<f>x         reference objects missing from the PVS (must be 0)
   Time and tightness over an evenly spread subset of BENCH_CELLS cells (default 60). Never asserts
   on time. */
#include "../tools/cli.h"
#include "test.h"
#include <stdlib.h>
#include <string.h>

static int run(const char *name, gen_kind kind, uint32_t n) {
    gen_params gp;
    mesh m;
    mesh_cells cells;
    pvs_scene *scene;
    tool_error te;
    pvs_error e;
    pvs_word *ref;
    uint32_t objects, c, *task;
    float base_eps = 0.0f;
    static const float factors[3] = {0.5f, 1.0f, 2.0f};
    double sampled = 0.0;
    size_t words;
    int f;
    gp = test_gen_params(kind, 1, 1.0f, 0);
    if (test_generate(&gp, &m, &cells, NULL)) return 1;
    if (cli_make_scene(name, &m, 1, &scene, &te)) { fprintf(stderr, "%s\n", te.message); return 1; }
    objects = pvs_scene_object_count(scene);
    words = PVS_BITSET_WORDS(objects);
    if (n > cells.count) n = cells.count;
    task = (uint32_t *)malloc(n * sizeof(uint32_t));
    ref = (pvs_word *)calloc(words * n, sizeof(pvs_word));
    for (c = 0; c < n; ++c) { /* the reference sets, once */
        task[c] = (uint32_t)((uint64_t)c * cells.count / n);
        cli_reference_visibility(scene, (const pvs_box *)(cells.boxes + 6 * (size_t)task[c]), 7 + c, ref + words * c);
        sampled += pvs_bitset_count(ref + words * c, objects);
    }
    for (f = 0; f < 3; ++f) {
        pvs_bake_desc bd;
        pvs_bake *b = NULL;
        pvs_bake_report rep;
        double t, t_syn, in_pvs = 0.0;
        uint32_t misses = 0, i;
        test_bake_desc(&bd, scene, (const pvs_box *)cells.boxes, cells.count, PVS_METHOD_SHRINK);
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
        for (c = 0; c < n; ++c)
            if (pvs_bake_run_task(b, task[c], &e) != PVS_OK) { fprintf(stderr, "%s\n", e.message); return 1; }
        t = cli_seconds() - t;
        for (c = 0; c < n; ++c) {
            const pvs_word *p = pvs_bake_cell_pvs(b, task[c]), *r = ref + words * c;
            in_pvs += pvs_bitset_count(p, objects);
            for (i = 0; i < objects; ++i) misses += pvs_bitset_test(r, i) && !pvs_bitset_test(p, i);
        }
        pvs_bake_get_report(b, &rep);
        printf("# shrink %s %gx: eps %g, %s path, %u of %u cells%s\n", name, (double)factors[f], (double)pvs_bake_eps(b),
               pvs_bake_shrink_mode(b) == PVS_SHRINK_2D5 ? "2.5D" : "3D", n, cells.count,
               rep.cells_no_occluders ? " (no occluder survives: nothing culled)" : "");
        printf("BENCH shrink_ms_per_cell_%s_%gx %.2f ms\n", name, (double)factors[f], 1000.0 * t / n);
        printf("BENCH shrink_synthesis_ms_%s_%gx %.1f ms\n", name, (double)factors[f], 1000.0 * t_syn);
        printf("BENCH shrink_tightness_%s_%gx %.3f ratio\n", name, (double)factors[f], sampled > 0 ? in_pvs / sampled : 0.0);
        printf("BENCH shrink_culled_pct_%s_%gx %.1f %%\n", name, (double)factors[f], 100.0 * (1.0 - in_pvs / ((double)n * objects)));
        printf("BENCH shrink_misses_%s_%gx %u objects\n", name, (double)factors[f], misses);
        fflush(stdout);
        pvs_bake_destroy(b);
    }
    free(ref);
    free(task);
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
