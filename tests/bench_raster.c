/* bench_raster.c - the raster module's figures on the generated city (gen_scene city, size 1, seed 1)
   from a fixed street camera, its best path, scalar (PVS_RASTER_SCALAR) and, where the CPU runs AVX2, SSE2
   (PVS_RASTER_SSE2) in the same binary:
     raster_frame_ms_1080p  clear + 50,000 occluder triangles at 1920x1080 + pyramid + 10,000 box tests
                            (_avx2, _sse2, _neon: the same, the path by name; _backface: back faces culled)
     raster_frame_ms_1080p_2threads  the same frame on two threads: pvs_raster_clear_band, then pvs_raster_bin and
                            pvs_raster_draw_band in two rounds (the 1,000 nearest triangles, then the rest),
                            pvs_raster_pyramid_band, the box tests split (the map is checked against one thread's)
     raster_mesh_frame_ms_1080p  the same with the triangles drawn as one occluder mesh (pvs_raster_mesh:
                            welded by position, no cracks along shared edges)
     raster_mesh_over_triangles  the mesh frame over the triangle frame, the two in alternating blocks
     raster_tris_per_ms     the rasterization part alone
     box_tests_per_ms       the box tests alone (pyramid built)
     cullmap_frame_ms       pvs_raster_cull_map with 1,000 facades at 256x256 (build + grid scan)
   Best of several repetitions. Prints figures, asserts nothing. Any argument: the SIMD pass only. */
#define _POSIX_C_SOURCE 199309L
#include "../pvs.h"
#include "../tools/gen.h"
#include "../tools/mesh.h"
#include "test.h"
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <pthread.h>
#include <time.h>

static double now_ms(void) {
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec * 1e3 + (double)ts.tv_nsec * 1e-6;
}

typedef struct keyed {
    float d;
    uint32_t i;
} keyed;
static int by_d(const void *a, const void *b) {
    float x = ((const keyed *)a)->d, y = ((const keyed *)b)->d;
    return x < y ? -1 : x > y;
}

/* Two threads for one frame: this one and a worker, meeting at spinning barriers (a frame is about a millisecond),
   taking parts, bands and blocks of boxes as a job system would (the faster thread takes more), from opposite ends:
   this thread from the first up, the worker from the last down, so a band stays on its thread from clear to draw to
   pyramid and its tiles in that core's cache (one shared counter, either thread taking the next: as fast while the VM's
   cores run alike, mostly 1 to 11% slower in its slow spells) */
typedef struct frame2 {
    pvs_raster *r;
    const pvs_raster_draw_desc *d;
    const pvs_box *boxes;
    uint32_t n_box, vis[2], next; /* next: the phase's parts taken from the low end (low 16 bits), from the high end */
    int phase, go, done; /* phase: 0 bin, 1 draw, 2 boxes, 3 clear, 4 pyramid; go, done: generation counters */
} frame2;
/* Takes thread w's next part of n into *k: w 0 from the low end, 1 from the high end; 0 when all are taken. */
static int frame2_take(frame2 *f, uint32_t w, uint32_t n, uint32_t *k) {
    uint32_t v = __atomic_load_n(&f->next, __ATOMIC_RELAXED), lo, hi;
    do {
        lo = v & 0xffffu, hi = n - (v >> 16);
        if (lo >= hi) return 0;
    } while (!__atomic_compare_exchange_n(&f->next, &v, v + (w ? 0x10000u : 1u), 1, __ATOMIC_RELAXED, __ATOMIC_RELAXED));
    *k = w ? hi - 1 : lo;
    return 1;
}
static void frame2_run(frame2 *f, uint32_t w) {
    uint32_t i, k, v = 0, blocks = f->phase == 2 ? 32u : PVS_RASTER_PARTS;
    while (frame2_take(f, w, blocks, &k)) {
        if (f->phase == 0) pvs_raster_bin(f->r, f->d, 1, k);
        else if (f->phase == 1) pvs_raster_draw_band(f->r, f->d, 1, k);
        else if (f->phase == 3) pvs_raster_clear_band(f->r, k);
        else if (f->phase == 4) pvs_raster_pyramid_band(f->r, k);
        else
            for (i = f->n_box * k / blocks; i < f->n_box * (k + 1) / blocks; ++i)
                v += (uint32_t)pvs_raster_test_box(f->r, f->boxes + i);
    }
    f->vis[w] = v;
}
static void *frame2_worker(void *arg) {
    frame2 *f = (frame2 *)arg;
    int seen = 0, g;
    for (;;) {
        while ((g = __atomic_load_n(&f->go, __ATOMIC_ACQUIRE)) == seen) continue;
        if (g < 0) return NULL;
        seen = g;
        frame2_run(f, 1);
        __atomic_store_n(&f->done, g, __ATOMIC_RELEASE);
    }
}
static void frame2_phase(frame2 *f, int phase) {
    int g = __atomic_load_n(&f->go, __ATOMIC_RELAXED) + 1;
    f->phase = phase;
    f->next = 0;
    __atomic_store_n(&f->go, g, __ATOMIC_RELEASE);
    frame2_run(f, 0);
    while (__atomic_load_n(&f->done, __ATOMIC_ACQUIRE) != g) continue;
}

int main(int argc, char **argv) {
    mesh m;
    mesh_cells cells;
    gen_params gp;
    pvs_scene_desc sd;
    pvs_object_desc *obs;
    pvs_scene *scene;
    pvs_error err;
    pvs_camera cam;
    float matrix[16], *occ, *fpts;
    pvs_box *boxes;
    keyed *key;
    pvs_facade_chain *fac;
    uint32_t i, n_occ = 50000, n_box = 10000, nf = 0, pass, nobj;
    const char *path0;
    double best_c = 1.0e30;
    (void)argv;
    gp = test_gen_params(GEN_CITY, 1, 1.0f, 0);
    if (test_generate(&gp, &m, &cells, NULL) != 0) { printf("gen failed\n"); return 1; }
    obs = (pvs_object_desc *)malloc(m.object_count * sizeof(pvs_object_desc));
    for (i = 0; i < m.object_count; ++i) {
        obs[i].first_triangle = m.objects[i].first_triangle;
        obs[i].triangle_count = m.objects[i].triangle_count;
        obs[i].flags = 0;
    }
    memset(&sd, 0, sizeof(sd));
    sd.positions = m.positions; sd.vertex_count = m.vertex_count; sd.indices = m.indices; sd.triangle_count = m.triangle_count;
    sd.objects = obs; sd.object_count = m.object_count; sd.up_axis = 1;
    if (pvs_scene_create(&sd, &scene, &err) != PVS_OK) { printf("scene: %s\n", err.message); return 1; }
    nobj = m.object_count;
    /* the fixed camera: the cell nearest the city's centre, looking along +x (the avenue's direction) */
    {
        pvs_box b = pvs_scene_bounds(scene);
        float cx = 0.5f * (b.min[0] + b.max[0]), cz = 0.5f * (b.min[2] + b.max[2]), bd = 1e30f;
        memset(&cam, 0, sizeof(cam));
        for (i = 0; i < cells.count; ++i) {
            const float *c = cells.boxes + 6 * i;
            float x = 0.5f * (c[0] + c[3]), z = 0.5f * (c[2] + c[5]), d = (x - cx) * (x - cx) + (z - cz) * (z - cz);
            if (d < bd) { bd = d; cam.eye[0] = x; cam.eye[1] = 1.7f; cam.eye[2] = z; }
        }
        cam.forward[0] = 1; cam.up[1] = 1; cam.fov_y = 1.0f; cam.near_plane = 0.1f;
        pvs_camera_matrix(&cam, 1920.0f / 1080.0f, matrix);
    }
    /* the occluder set: the 50,000 triangles nearest the eye */
    key = (keyed *)malloc(m.triangle_count * sizeof(keyed));
    for (i = 0; i < m.triangle_count; ++i) {
        const float *a = m.positions + 3 * m.indices[3 * i], *b = m.positions + 3 * m.indices[3 * i + 1], *c = m.positions + 3 * m.indices[3 * i + 2];
        float x = (a[0] + b[0] + c[0]) / 3 - cam.eye[0], y = (a[1] + b[1] + c[1]) / 3 - cam.eye[1], z = (a[2] + b[2] + c[2]) / 3 - cam.eye[2];
        key[i].d = x * x + y * y + z * z;
        key[i].i = i;
    }
    qsort(key, m.triangle_count, sizeof(keyed), by_d);
    occ = (float *)malloc((size_t)n_occ * 9 * sizeof(float));
    for (i = 0; i < n_occ; ++i) {
        int k;
        for (k = 0; k < 3; ++k) memcpy(occ + 9 * i + 3 * k, m.positions + 3 * m.indices[3 * key[i].i + k], 3 * sizeof(float));
    }
    boxes = (pvs_box *)malloc(n_box * sizeof(pvs_box));
    for (i = 0; i < n_box; ++i) boxes[i] = pvs_scene_object_box(scene, i % nobj);
    /* 1,000 facades: upright wall triangles on the ground nearest the eye (the halves of wall quads) */
    fac = (pvs_facade_chain *)malloc(1000 * sizeof(pvs_facade_chain));
    fpts = (float *)malloc(1000 * 4 * sizeof(float));
    for (i = 0; i < m.triangle_count && nf < 1000; ++i) {
        const float *p[3];
        int k, low = 0, lo1 = -1, lo2 = -1, hi = -1;
        for (k = 0; k < 3; ++k) {
            p[k] = m.positions + 3 * m.indices[3 * key[i].i + k];
            if (p[k][1] == 0.0f) { ++low; if (lo1 < 0) lo1 = k; else lo2 = k; } else hi = k;
        }
        if (low != 2 || !((p[hi][0] == p[lo1][0] && p[hi][2] == p[lo1][2]) || (p[hi][0] == p[lo2][0] && p[hi][2] == p[lo2][2]))) continue;
        fpts[4 * nf] = p[lo1][0]; fpts[4 * nf + 1] = p[lo1][2]; fpts[4 * nf + 2] = p[lo2][0]; fpts[4 * nf + 3] = p[lo2][2];
        fac[nf].points = fpts + 4 * nf; fac[nf].point_count = 2; fac[nf].closed = 0; fac[nf].base = 0; fac[nf].top = p[hi][1];
        ++nf;
    }
    printf("# city: %u objects, %u triangles; eye (%.1f %.1f %.1f) looking +x; %u occluder triangles, %u boxes, %u facades\n", nobj,
           m.triangle_count, cam.eye[0], cam.eye[1], cam.eye[2], n_occ, n_box, nf);
    for (pass = 0, path0 = ""; pass < (argc > 1 ? 1u : 3u); ++pass) {
        pvs_raster_desc rd;
        pvs_raster *r, *rc;
        pvs_word *vis = (pvs_word *)calloc(PVS_BITSET_WORDS(nobj), sizeof(pvs_word));
        double best_f = 1e30, best_r = 1e30, best_b = 1e30;
        const char *sfx = pass == 1 ? "_scalar" : pass ? "_sse2" : "";
        uint32_t rep, vis_boxes = 0, covered = 0;
        memset(&rd, 0, sizeof(rd));
        rd.width = 1920; rd.height = 1080; rd.flags = pass == 1 ? PVS_RASTER_SCALAR : pass ? PVS_RASTER_SSE2 : 0;
        if (pvs_raster_create(&rd, &r, &err) != PVS_OK) { printf("raster: %s\n", err.message); return 1; }
        if (!pass) path0 = pvs_raster_path(r);
        if (pass == 2 && strcmp(path0, "avx2")) { /* no AVX2 here: pass 0 ran the SSE2 path (or NEON) */
            pvs_raster_destroy(r);
            free(vis);
            break;
        }
        pvs_raster_set_matrix(r, matrix);
        for (rep = 0; rep < 7; ++rep) {
            double t0 = now_ms(), t1, t2, t3;
            pvs_raster_clear(r);
            pvs_raster_triangles(r, occ, 3 * n_occ, NULL, n_occ, PVS_RASTER_OCCLUDER);
            t1 = now_ms();
            pvs_raster_build_pyramid(r);
            t2 = now_ms();
            vis_boxes = 0;
            for (i = 0; i < n_box; ++i) vis_boxes += (uint32_t)pvs_raster_test_box(r, boxes + i);
            t3 = now_ms();
            if (t3 - t0 < best_f) best_f = t3 - t0;
            if (t1 - t0 < best_r) best_r = t1 - t0;
            if (t3 - t2 < best_b) best_b = t3 - t2;
        }
        {
            const float *d = pvs_raster_depth(r, NULL, NULL);
            for (i = 0; i < 1920u * 1080u; ++i) covered += d[i] != PVS_DEPTH_EMPTY;
        }
        if (!pass) printf("# %.1f%% of the pixels covered, %u of %u boxes visible\n", 100.0 * covered / (1920.0 * 1080.0), vis_boxes, n_box);
        printf("BENCH raster_frame_ms_1080p%s %.3f ms\n", sfx, best_f);
        if (!pass && strcmp(pvs_raster_path(r), "scalar")) /* the path by its name */
            printf("BENCH raster_frame_ms_1080p_%s %.3f ms\n", pvs_raster_path(r), best_f);
        if (!pass) { /* the same frame on two threads */
            pvs_raster_desc qd = rd;
            pvs_raster *q;
            pvs_raster_draw_desc dd = {occ, 0, 3 * n_occ, NULL, n_occ, PVS_RASTER_OCCLUDER, 0}, d1 = dd, d2 = dd;
            frame2 f;
            pthread_t th;
            double best_2 = 1e30, best_1 = 1e30;
            int same;
            qd.bin_triangles = n_occ;
            if (pvs_raster_create(&qd, &q, &err) != PVS_OK) { printf("raster: %s\n", err.message); return 1; }
            pvs_raster_set_matrix(q, matrix);
            memset(&f, 0, sizeof(f));
            f.r = q; f.boxes = boxes; f.n_box = n_box;
            d1.triangle_count = 1000, d1.vertex_count = 3000;
            d2.positions = occ + 9000, d2.vertex_count = 3 * (n_occ - 1000), d2.triangle_count = n_occ - 1000;
            pthread_create(&th, NULL, frame2_worker, &f);
            for (rep = 0; rep < 4000; ++rep) { /* alternating blocks of ten frames, about 3 s: the VM changes speed
                                                     for seconds (over 400 frames, 1.49 to 2.06 in 20 runs; 4,000: 1.68
                                                     to 1.80) */
                double t0 = now_ms();
                if (rep / 10 % 2 == 0) { /* cleared in bands; two rounds: the 1,000 nearest triangles, then the rest */
                    frame2_phase(&f, 3);
                    f.d = &d1;
                    frame2_phase(&f, 0);
                    frame2_phase(&f, 1);
                    f.d = &d2;
                    frame2_phase(&f, 0);
                    frame2_phase(&f, 1);
                    frame2_phase(&f, 4); /* the pyramid in bands, then its top */
                    pvs_raster_pyramid_band(q, PVS_RASTER_PARTS);
                    frame2_phase(&f, 2);
                } else {
                    pvs_raster_clear(r);
                    pvs_raster_triangles(r, occ, 3 * n_occ, NULL, n_occ, PVS_RASTER_OCCLUDER);
                    pvs_raster_build_pyramid(r);
                    for (i = 0; i < n_box; ++i) (void)pvs_raster_test_box(r, boxes + i);
                }
                t0 = now_ms() - t0;
                if (rep % 10 == 0) continue; /* warms the caches */
                if (rep / 10 % 2 == 0 && t0 < best_2) best_2 = t0;
                if (rep / 10 % 2 == 1 && t0 < best_1) best_1 = t0;
            }
            __atomic_store_n(&f.go, -1, __ATOMIC_RELEASE);
            pthread_join(th, NULL);
            pvs_raster_clear(r);
            pvs_raster_triangles(r, occ, 3 * n_occ, NULL, n_occ, PVS_RASTER_OCCLUDER);
            same = !memcmp(pvs_raster_depth(r, NULL, NULL), pvs_raster_depth(q, NULL, NULL), 1920u * 1080u * sizeof(float));
            printf("# two threads: the same map as one thread's: %s; %u of %u boxes visible\n", same ? "yes" : "NO",
                   f.vis[0] + f.vis[1], n_box);
            printf("BENCH raster_frame_ms_1080p_2threads %.3f ms\n", best_2);
            printf("BENCH raster_frame_2threads_speedup %.2f x\n", best_1 / best_2); /* over one thread, in alternating blocks */
            pvs_raster_destroy(q);
        }
        { /* the same frame with back faces culled (pvs_raster_draw; the city's walls are closed, wound outward) */
            pvs_raster_draw_desc dd = {occ, 0, 3 * n_occ, NULL, n_occ, PVS_RASTER_OCCLUDER, PVS_DRAW_CULL_CW};
            double best_bf = 1e30;
            for (rep = 0; rep < 7; ++rep) {
                double t0 = now_ms();
                pvs_raster_clear(r);
                pvs_raster_draw(r, &dd);
                pvs_raster_build_pyramid(r);
                for (i = 0; i < n_box; ++i) (void)pvs_raster_test_box(r, boxes + i);
                t0 = now_ms() - t0;
                if (t0 < best_bf) best_bf = t0;
            }
            printf("BENCH raster_frame_ms_1080p_backface%s %.3f ms\n", sfx, best_bf);
        }
        { /* the mesh frame and the triangle frame in alternating blocks of four (the VM changes speed for seconds) */
            double best_m = 1e30, best_t = 1e30;
            uint32_t mvis = 0, mcov = 0;
            const float *d;
            for (rep = 0; rep < 40; ++rep) { /* the last block the mesh's: its map is counted below */
                int as_mesh = rep / 4 % 2;
                double t0 = now_ms();
                pvs_raster_clear(r);
                if (as_mesh) pvs_raster_mesh(r, occ, 3 * n_occ, NULL, n_occ);
                else pvs_raster_triangles(r, occ, 3 * n_occ, NULL, n_occ, PVS_RASTER_OCCLUDER);
                pvs_raster_build_pyramid(r);
                mvis = 0;
                for (i = 0; i < n_box; ++i) mvis += (uint32_t)pvs_raster_test_box(r, boxes + i);
                t0 = now_ms() - t0;
                if (rep % 4 == 0) continue; /* warms the caches */
                if (as_mesh && t0 < best_m) best_m = t0;
                if (!as_mesh && t0 < best_t) best_t = t0;
            }
            d = pvs_raster_depth(r, NULL, NULL);
            for (i = 0; i < 1920u * 1080u; ++i) mcov += d[i] != PVS_DEPTH_EMPTY;
            if (!pass) printf("# as one mesh: %.1f%% of the pixels covered, %u of %u boxes visible\n", 100.0 * mcov / (1920.0 * 1080.0), mvis, n_box);
            printf("BENCH raster_mesh_frame_ms_1080p%s %.3f ms\n", sfx, best_m);
            printf("BENCH raster_mesh_over_triangles%s %.2f x\n", sfx, best_m / best_t); /* alternating blocks */
        }
        printf("BENCH raster_tris_per_ms%s %.0f tris/ms\n", sfx, n_occ / best_r);
        printf("BENCH box_tests_per_ms%s %.0f boxes/ms\n", sfx, n_box / best_b);
        pvs_raster_destroy(r);
        /* cull map: 1,000 facades at 256 x 256, build and grid scan (small depth map for the frustum) */
        rd.width = 64; rd.height = 36; rd.scene = scene; rd.cull_map_width = 256; rd.cull_map_height = 256;
        if (pvs_raster_create(&rd, &rc, &err) != PVS_OK) { printf("raster: %s\n", err.message); return 1; }
        best_c = 1e30;
        for (rep = 0; rep < 7; ++rep) {
            pvs_cull_params cp;
            pvs_cull_stats st;
            double t0 = now_ms();
            memset(&cp, 0, sizeof(cp));
            cp.facades = fac; cp.facade_count = nf;
            pvs_raster_cull_map(rc, scene, &cam, &cp, vis, &st, &err);
            t0 = now_ms() - t0;
            if (t0 < best_c) best_c = t0;
            if (rep == 0 && !pass) printf("# cull map: %u of %u objects visible\n", st.visible, nobj);
        }
        printf("BENCH cullmap_frame_ms%s %.3f ms\n", sfx, best_c);
        pvs_raster_destroy(rc);
        free(vis);
    }
    pvs_scene_destroy(scene);
    mesh_free(&m);
    mesh_cells_free(&cells);
    free(obs); free(key); free(occ); free(boxes); free(fac); free(fpts);
    return 0;
}
