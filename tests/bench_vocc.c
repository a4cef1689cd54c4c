/* bench_vocc.c - `make bench` figures of the virtual occluders (Koltun, Chrysanthou, Cohen-Or 2000)
   on the demo city (generator city, seed 1, size 1), over an evenly spread subset of BENCH_CELLS
   cells (default 60):
     BENCH vocc_occluded_pct_k1 .. k8       objects culled by the first k kept occluders (Table 1)
     BENCH vocc_occluded_pct_slices1 .. 5   objects culled with 1..5 height slices (Table 2)
     BENCH vocc_occluded_pct                with every kept occluder (default 5 slices, <= 10 kept)
     BENCH vocc_occluders_per_cell          kept per cell (the selection of Fig. 6 stops when paying stops)
     BENCH vocc_vs_shrink_pct               culled objects as a percentage of what shrink culls (same cells)
     BENCH vocc_bytes_per_cell              the VOCC section per cell (5 bytes per occluder + 2.25)
     BENCH vocc_rebuild_us                  pvs_vocc_cull of one cell (object kD-tree walk), min of 5 runs
     BENCH vocc_tightness                   mean rebuilt PVS / mean ray-sampled set (>= 1)
     BENCH vocc_ms_per_cell                 bake time per cell, one core
   "Culled" counts drawable objects left out of the PVS, in percent of all objects. Times are CPU
   seconds of this (single-threaded) process, still noisy on a loaded shared machine. Never asserts
   on time. */
#include "../tools/cli.h"
#include "test.h"
#include <stdlib.h>
#include <string.h>
#include <time.h>

typedef struct bench_run {
    void *file;
    size_t size;
    pvs_file f;
    double ms_per_cell;
    pvs_vocc_stats st;
} bench_run;

static int bake(pvs_scene *scene, const pvs_box *cells, uint32_t n, pvs_method method, uint32_t slices, bench_run *out) {
    pvs_bake_desc bd;
    pvs_bake *b = NULL;
    pvs_error e;
    uint32_t c;
    double t;
    memset(out, 0, sizeof(*out));
    test_bake_desc(&bd, scene, cells, n, method);
    bd.vocc.slices = slices;
    if (pvs_bake_begin(&bd, &b, &e) != PVS_OK) { fprintf(stderr, "%s\n", e.message); return 1; }
    t = test_cpu_seconds();
    for (c = 0; c < n; ++c)
        if (pvs_bake_run_task(b, c, &e) != PVS_OK) { fprintf(stderr, "%s\n", e.message); return 1; }
    out->ms_per_cell = 1000.0 * (test_cpu_seconds() - t) / n;
    pvs_bake_get_vocc_stats(b, &out->st);
    out->size = pvs_bake_file_size(b);
    out->file = malloc(out->size);
    if (!out->file || pvs_bake_write_file(b, out->file, out->size, &out->size, &e) != PVS_OK ||
        pvs_file_open(out->file, out->size, &out->f, &e) != PVS_OK) {
        fprintf(stderr, "%s\n", e.message);
        return 1;
    }
    pvs_bake_destroy(b);
    return 0;
}

int main(void) {
    mesh m;
    mesh_cells cells;
    pvs_scene *scene;
    tool_error te;
    const char *env = getenv("BENCH_CELLS");
    uint32_t n = env ? (uint32_t)atoi(env) : 60u, objects, words, c, k, i;
    pvs_box *sub, *boxes;
    pvs_word *bits, *ref;
    pvs_kdtree *tree = NULL;
    pvs_kdtree_desc kd;
    void *scratch;
    size_t scratch_size;
    bench_run run, sh;
    double culled[9] = {0}, in_pvs = 0.0, sampled = 0.0, shrink_culled = 0.0, best_us = 1e30;
    if (n == 0) n = 60;
    if (cli_demo_city(&m, &cells, &scene, &te)) { fprintf(stderr, "%s\n", te.message); return 1; }
    objects = pvs_scene_object_count(scene);
    words = (uint32_t)PVS_BITSET_WORDS(objects);
    if (n > cells.count) n = cells.count;
    sub = (pvs_box *)malloc(n * sizeof(pvs_box));
    boxes = (pvs_box *)malloc(objects * sizeof(pvs_box));
    bits = (pvs_word *)malloc(words * sizeof(pvs_word));
    ref = (pvs_word *)malloc(words * sizeof(pvs_word));
    for (c = 0; c < n; ++c) memcpy(sub + c, cells.boxes + 6 * (size_t)((uint64_t)c * cells.count / n), sizeof(pvs_box));
    for (i = 0; i < objects; ++i) {
        boxes[i] = pvs_scene_object_box(scene, i);
        if (pvs_scene_object_flags(scene, i) & PVS_OBJECT_OCCLUDER_ONLY) boxes[i].min[0] = 1.0f, boxes[i].max[0] = 0.0f;
    }
    memset(&kd, 0, sizeof(kd));
    kd.boxes = boxes;
    kd.count = objects;
    kd.leaf_size = 16; /* few, fuller leaves: the walk visits fewer nodes */
    if (pvs_kdtree_create(&kd, &tree, NULL) != PVS_OK) return 1;
    scratch_size = pvs_vocc_cull_scratch_size(tree, 255);
    scratch = malloc(scratch_size);

    /* Table 2: slices 1..5 */
    for (k = 1; k <= 5; ++k) {
        double cul = 0.0;
        if (bake(scene, sub, n, PVS_METHOD_VOCC, k, &run)) return 1;
        for (c = 0; c < n; ++c) {
            pvs_vocc_cull(&run.f, c, 0, boxes, objects, tree, scratch, scratch_size, bits, NULL);
            cul += objects - pvs_bitset_count(bits, objects);
        }
        printf("BENCH vocc_occluded_pct_slices%u %.1f %% (%.1f ms per cell)\n", k, 100.0 * cul / ((double)n * objects), run.ms_per_cell);
        fflush(stdout);
        if (k < 5) free(run.file);
    }
    /* Table 1 and the rest on the default bake (5 slices, at most 10 kept) */
    for (c = 0; c < n; ++c) {
        for (k = 1; k <= 8; ++k) {
            pvs_vocc_cull(&run.f, c, k, boxes, objects, tree, scratch, scratch_size, bits, NULL);
            culled[k] += objects - pvs_bitset_count(bits, objects);
        }
        pvs_vocc_cull(&run.f, c, 0, boxes, objects, tree, scratch, scratch_size, bits, NULL);
        culled[0] += objects - pvs_bitset_count(bits, objects);
        in_pvs += pvs_bitset_count(bits, objects);
        memset(ref, 0, words * sizeof(pvs_word));
        cli_reference_visibility(scene, sub + c, 11 + c, ref);
        sampled += pvs_bitset_count(ref, objects);
    }
    for (k = 1; k <= 8; ++k) printf("BENCH vocc_occluded_pct_k%u %.1f %%\n", k, 100.0 * culled[k] / ((double)n * objects));
    printf("BENCH vocc_occluded_pct %.1f %%\n", 100.0 * culled[0] / ((double)n * objects));
    printf("BENCH vocc_occluders_per_cell %.2f (of %.1f in the dense set)\n", (double)run.f.virtual_occluder_count / n, (double)run.st.dense / n);
    {
        /* the VOCC section's size: the file with it minus the same file without it */
        size_t with = run.size, without = 0;
        pvs_file_desc fd;
        pvs_word *table = (pvs_word *)malloc((size_t)n * words * sizeof(pvs_word));
        for (c = 0; c < n; ++c) pvs_file_decode(&run.f, c, table + (size_t)c * words, words, NULL);
        memset(&fd, 0, sizeof(fd));
        fd.cells = sub;
        fd.cell_count = n;
        fd.object_count = objects;
        fd.pvs = table;
        fd.method = PVS_METHOD_VOCC;
        fd.up_axis = 1;
        pvs_file_encode(&fd, NULL, 0, &without, NULL);
        printf("BENCH vocc_bytes_per_cell %.1f bytes (the delta-PVS records of the same cells: %.1f)\n", (double)(with - without) / n,
               (double)without / n);
        free(table);
    }
    {
        double best_flat = 1e30;
        for (k = 0; k < 5; ++k) { /* rebuild time: min over 5 passes of the mean per cell */
            double t = test_cpu_seconds();
            for (c = 0; c < n; ++c) pvs_vocc_cull(&run.f, c, 0, boxes, objects, tree, scratch, scratch_size, bits, NULL);
            t = 1e6 * (test_cpu_seconds() - t) / n;
            if (t < best_us) best_us = t;
            t = test_cpu_seconds();
            for (c = 0; c < n; ++c) pvs_vocc_cull(&run.f, c, 0, boxes, objects, NULL, scratch, scratch_size, bits, NULL);
            t = 1e6 * (test_cpu_seconds() - t) / n;
            if (t < best_flat) best_flat = t;
        }
        printf("BENCH vocc_rebuild_us %.1f us (kD-tree walk, leaves of 16, %u objects; every box tested: %.1f us)\n", best_us, objects,
               best_flat);
    }
    printf("BENCH vocc_tightness %.3f ratio (mean PVS %.1f, mean sampled %.1f)\n", sampled > 0 ? in_pvs / sampled : 0.0, in_pvs / n, sampled / n);
    printf("BENCH vocc_ms_per_cell %.2f ms\n", run.ms_per_cell);
    fflush(stdout);
    if (bake(scene, sub, n, PVS_METHOD_SHRINK, 0, &sh)) return 1;
    for (c = 0; c < n; ++c) {
        pvs_file_decode(&sh.f, c, bits, words, NULL);
        shrink_culled += objects - pvs_bitset_count(bits, objects);
    }
    printf("BENCH vocc_vs_shrink_pct %.1f %% (shrink culls %.1f %% of the objects)\n", shrink_culled > 0 ? 100.0 * culled[0] / shrink_culled : 0.0,
           100.0 * shrink_culled / ((double)n * objects));
    free(sh.file);
    free(run.file);
    free(scratch);
    free(sub);
    free(boxes);
    free(bits);
    free(ref);
    pvs_kdtree_destroy(tree);
    pvs_scene_destroy(scene);
    mesh_cells_free(&cells);
    mesh_free(&m);
    return 0;
}
