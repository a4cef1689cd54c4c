/* bench_bounded.c - bounded time and memory on any input (issue 26): the kD-tree's memory on fans of
   slivers, the resume journal's cost against a bake without one, the preview among 200,000 objects;
   a bake's peak memory against the size of its answer on 100,000 cells x 100,000 objects (issue 29).
   Prints BENCH lines; asserts nothing. Runs build/pvsbake for the whole-tool figures (run it from the
   project root, after make tools). */
#include "../tools/cli.h"
#include "test.h"
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#define TMP "build/bench-bounded"

/* Peak bytes per triangle on one polygon of n sides around a vertex (an OBJ `f` line of n vertices,
   fan-triangulated: n - 2 slivers): of pvs_kdtree_create over the slivers' boxes (*tree) and of
   pvs_scene_create (the return). */
static double fan_bytes_per_triangle(uint32_t n, double *tree) {
    float *pos = (float *)malloc((size_t)n * 3 * sizeof(float));
    uint32_t *idx = (uint32_t *)malloc((size_t)(n - 2) * 3 * sizeof(uint32_t)), i;
    pvs_box *bx = (pvs_box *)malloc((size_t)(n - 2) * sizeof(pvs_box));
    pvs_object_desc od;
    pvs_scene_desc sd;
    pvs_kdtree_desc kd;
    pvs_scene *s = NULL;
    pvs_kdtree *t = NULL;
    test_peak pk, pt;
    double r = -1.0;
    for (i = 0; i < n; ++i) {
        double a = 6.283185307179586 * i / n;
        pos[3 * i] = (float)(50 * cos(a));
        pos[3 * i + 1] = 5;
        pos[3 * i + 2] = (float)(50 * sin(a));
    }
    for (i = 0; i + 2 < n; ++i) {
        int k, c;
        idx[3 * i] = 0;
        idx[3 * i + 1] = i + 1;
        idx[3 * i + 2] = i + 2;
        for (k = 0; k < 3; ++k) {
            bx[i].min[k] = bx[i].max[k] = pos[k];
            for (c = 1; c < 3; ++c) {
                float v = pos[3 * idx[3 * i + c] + k];
                if (v < bx[i].min[k]) bx[i].min[k] = v;
                if (v > bx[i].max[k]) bx[i].max[k] = v;
            }
        }
    }
    memset(&kd, 0, sizeof(kd));
    kd.boxes = bx;
    kd.count = n - 2;
    kd.allocator = test_peak_allocator(&pt);
    *tree = pvs_kdtree_create(&kd, &t, NULL) == PVS_OK ? (double)pt.peak / (n - 2) : -1.0;
    pvs_kdtree_destroy(t);
    od.first_triangle = 0;
    od.triangle_count = n - 2;
    od.flags = 0;
    memset(&sd, 0, sizeof(sd));
    sd.positions = pos;
    sd.vertex_count = n;
    sd.indices = idx;
    sd.triangle_count = n - 2;
    sd.objects = &od;
    sd.object_count = 1;
    sd.allocator = test_peak_allocator(&pk);
    if (pvs_scene_create(&sd, &s, NULL) == PVS_OK) r = (double)pk.peak / (n - 2);
    pvs_scene_destroy(s);
    free(pos);
    free(idx);
    free(bx);
    return r;
}

/* Seconds of a command, the best of `runs`. */
static double timed(const char *cmd, int runs) {
    double best = 1e30;
    int r;
    for (r = 0; r < runs; ++r) {
        double t0 = cli_seconds(), dt;
        if (system(cmd) != 0) return -1.0;
        dt = cli_seconds() - t0;
        if (dt < best) best = dt;
    }
    return best;
}

/* n boxes (12 triangles each) on a grid of pitch `pitch`, a third of them tall; Y up. */
static void boxes(mesh *m, uint32_t n, float pitch, uint64_t seed) {
    uint32_t side = (uint32_t)ceil(sqrt((double)n)), i;
    mesh_init(m);
    for (i = 0; i < n; ++i) {
        float lo[3], hi[3], s, h;
        seed = seed * 6364136223846793005ull + 1442695040888963407ull;
        s = 0.3f + 0.9f * (float)((seed >> 33) % 1000) / 1000.0f;
        h = (seed >> 20) % 3 == 0 ? 0.5f + 5.5f * (float)((seed >> 40) % 1000) / 1000.0f : 0.2f + 1.3f * (float)((seed >> 45) % 1000) / 1000.0f;
        lo[0] = (float)(i % side) * pitch; lo[1] = 0.0f; lo[2] = (float)(i / side) * pitch;
        hi[0] = lo[0] + s; hi[1] = h; hi[2] = lo[2] + s;
        mesh_begin_object(m, "b", 0, 0);
        test_mesh_box(m, lo, hi);
    }
}

/* A g x g grid of cells 1.5 wide spread over a square of side `extent`. */
static void cell_grid(mesh_cells *c, uint32_t g, float extent) {
    uint32_t i, j;
    mesh_cells_init(c);
    for (i = 0; i < g; ++i)
        for (j = 0; j < g; ++j) {
            float b[6];
            b[0] = ((float)i + 0.5f) * extent / (float)g;
            b[2] = ((float)j + 0.5f) * extent / (float)g;
            b[1] = 0.1f;
            b[3] = b[0] + 1.5f;
            b[4] = 2.0f;
            b[5] = b[2] + 1.5f;
            mesh_cells_add(c, b);
        }
}

static int write_scene(const mesh *m, const mesh_cells *c, const char *obj, const char *cells) {
    FILE *f = fopen(obj, "w"), *g;
    int ok = f && mesh_write_obj(m, f) == 0;
    if (f) fclose(f);
    g = fopen(cells, "w");
    ok = ok && g && mesh_cells_write(c, g) == 0;
    if (g) fclose(g);
    return ok;
}

/* Issue 29's memory figure: a bake's peak bytes on a synthetic level of n cells and n objects (a small triangle each
   on a line), every cell's PVS restored as `visible` random objects (the bake's storage and the file's encoder, not a
   method's), against the sum of the PVS sizes. Returns the peak; *answer gets the PVSs' bytes as 4-byte ids. */
static double bake_peak_bytes(uint32_t n, uint32_t visible, double *answer, double *seconds) {
    float *pos = (float *)malloc((size_t)n * 9 * sizeof(float));
    uint32_t *idx = (uint32_t *)malloc((size_t)n * 3 * sizeof(uint32_t)), i, k;
    pvs_object_desc *obs = (pvs_object_desc *)malloc(n * sizeof(pvs_object_desc));
    pvs_box *cells = (pvs_box *)malloc(n * sizeof(pvs_box));
    pvs_word *bits = (pvs_word *)calloc(PVS_BITSET_WORDS(n), sizeof(pvs_word));
    pvs_scene *s = NULL;
    pvs_bake *b = NULL;
    pvs_bake_desc bd;
    test_peak pk;
    uint64_t rng = 5;
    double peak = -1.0, t0 = cli_seconds();
    void *file = NULL;
    size_t size = 0;
    if (!pos || !idx || !obs || !cells || !bits) goto done;
    for (i = 0; i < n; ++i) {
        float x = (float)i;
        float v[9] = {x, 0, 0, x + 0.5f, 0, 0, x, 0.5f, 0};
        memcpy(pos + 9 * (size_t)i, v, sizeof(v));
        for (k = 0; k < 3; ++k) idx[3 * (size_t)i + k] = 3 * i + k;
        obs[i].first_triangle = i;
        obs[i].triangle_count = 1;
        obs[i].flags = 0;
        cells[i].min[0] = x; cells[i].min[1] = 1; cells[i].min[2] = 1;
        cells[i].max[0] = x + 1; cells[i].max[1] = 2; cells[i].max[2] = 2;
    }
    s = test_scene_arrays(pos, 3 * n, idx, n, obs, n, 1);
    memset(&bd, 0, sizeof(bd));
    bd.scene = s;
    bd.cells = cells;
    bd.cell_count = n;
    bd.method = PVS_METHOD_SAMPLE;
    bd.allocator = test_peak_allocator(&pk);
    if (!s || pvs_bake_begin(&bd, &b, NULL) != PVS_OK) goto done;
    for (i = 0; i < n; ++i) {
        memset(bits, 0, PVS_BITSET_WORDS(n) * sizeof(pvs_word));
        for (k = 0; k < visible; ++k) pvs_bitset_set(bits, (i + (uint32_t)(test_splitmix64(&rng) % (4 * visible))) % n);
        if (pvs_bake_restore_task(b, i, bits, PVS_BITSET_WORDS(n), NULL) != PVS_OK) goto done;
    }
    size = pvs_bake_file_size(b);
    file = malloc(size ? size : 1);
    if (!file || pvs_bake_write_file(b, file, size, &size, NULL) != PVS_OK) goto done;
    peak = (double)pk.peak;
    *answer = 4.0 * visible * n;
    *seconds = cli_seconds() - t0;
done:
    free(file);
    pvs_bake_destroy(b);
    pvs_scene_destroy(s);
    free(pos); free(idx); free(obs); free(cells); free(bits);
    return peak;
}

int main(void) {
    static const uint32_t fans[4] = {5002, 10002, 20002, 40002};
    double per[4];
    int k;
    mkdir("build", 0777);
    mkdir(TMP, 0777);
    /* the kD-tree on a fan: bytes per triangle flat from 5k to 40k (quadratic before the pools) */
    for (k = 0; k < 4; ++k) {
        double scene = fan_bytes_per_triangle(fans[k], per + k);
        printf("BENCH kdtree_bytes_per_tri_fan%uk %.0f bytes\n", (fans[k] - 2) / 1000, per[k]);
        if (k == 3) printf("BENCH scene_bytes_per_tri_fan %.0f bytes\n", scene);
    }
    printf("BENCH kdtree_bytes_per_tri_fan %.0f bytes\n", per[3]);
    {   /* issue 29: a bake's memory against its answer (100,000 cells x 100,000 objects, 200 visible per cell) */
        double answer = 0, secs = 0, peak = bake_peak_bytes(100000, 200, &answer, &secs);
        printf("BENCH bake_peak_bytes_100k_cells_100k_objects %.0f bytes\n", peak);
        printf("BENCH bake_peak_over_answer_100k %.1f x\n", peak / answer);
        printf("BENCH bake_restore_write_seconds_100k %.1f s\n", secs);
    }
    printf("BENCH kdtree_fan_growth_40k_over_5k %.2f x\n", per[3] / per[0]);
    { /* the resume journal: 40,000 cells of a 17-object scene, otree, 2 threads */
        mesh m;
        mesh_cells c;
        double with, without;
        boxes(&m, 17, 20.0f, 3);
        cell_grid(&c, 200, 100.0f);
        if (write_scene(&m, &c, TMP "/small.obj", TMP "/small40k.txt")) {
            without = timed("./build/pvsbake " TMP "/small.obj --cells " TMP "/small40k.txt -o " TMP "/a.pvs --method otree -q -j 2 --no-state", 3);
            with = timed("./build/pvsbake " TMP "/small.obj --cells " TMP "/small40k.txt -o " TMP "/b.pvs --method otree -q -j 2", 3);
            printf("BENCH state_seconds_40k_cells %.2f s\n", with);
            printf("BENCH state_overhead_ratio_40k_cells %.2f x\n", with / without);
        }
        mesh_free(&m);
        mesh_cells_free(&c);
    }
    { /* the preview among 200,000 objects: per cell on one thread (the library), and pvsbake's whole
         run over 2,025 cells on 2 threads (loading the 97 MB OBJ included) */
        mesh m;
        mesh_cells c;
        pvs_scene *s = NULL;
        tool_error te;
        boxes(&m, 200000, 2.0f, 7);
        cell_grid(&c, 45, 894.0f);
        if (cli_make_scene("boxes", &m, 1, &s, &te) == 0) {
            pvs_bake_desc bd;
            pvs_bake *b = NULL;
            memset(&bd, 0, sizeof(bd));
            bd.scene = s;
            bd.cells = (const pvs_box *)c.boxes;
            bd.cell_count = 400;
            bd.flags = PVS_BAKE_PREVIEW;
            if (pvs_bake_begin(&bd, &b, NULL) == PVS_OK) {
                double t0 = cli_seconds();
                uint32_t t;
                for (t = 0; t < pvs_bake_task_count(b); ++t) pvs_bake_run_task(b, t, NULL);
                printf("BENCH preview_ms_per_cell_200k_objects %.2f ms\n", 1000.0 * (cli_seconds() - t0) / pvs_bake_task_count(b));
                pvs_bake_destroy(b);
            }
            pvs_scene_destroy(s);
        }
        if (write_scene(&m, &c, TMP "/s200k.obj", TMP "/s200k.txt"))
            printf("BENCH preview_seconds_200k_objects_2025_cells %.1f s\n",
                   timed("./build/pvsbake " TMP "/s200k.obj --cells " TMP "/s200k.txt -o " TMP "/p.pvs --preview -q -j 2", 1));
        mesh_free(&m);
        mesh_cells_free(&c);
    }
    return 0;
}
