/* bench_kdtree.c - kD-tree build time and scene ray-cast throughput. Prints figures, asserts nothing.
   cc -std=c99 -O2 tests/bench_kdtree.c -lm */
#define _POSIX_C_SOURCE 199309L
#define PVS_IMPLEMENTATION
#include "../pvs.h"
#include "test.h"
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

static double now_ms(void) {
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec * 1e3 + (double)ts.tv_nsec * 1e-6;
}

static uint64_t rng_state = 12345;
static float frand(void) { return pvs__random01(&rng_state); }

int main(void) {
    const uint32_t n = 1000000;
    pvs_box *boxes = (pvs_box *)malloc(n * sizeof(pvs_box));
    pvs_kdtree_desc kd;
    pvs_kdtree *tree = NULL;
    pvs_error err;
    double t0, best = 1e30;
    uint32_t i, rep;
    for (i = 0; i < n; ++i) {
        float c[3], k;
        int a;
        for (a = 0; a < 3; ++a) c[a] = 100.0f * frand();
        boxes[i] = pvs__box_empty();
        for (k = 0; k < 3; ++k) {
            float p[3];
            for (a = 0; a < 3; ++a) p[a] = c[a] + frand() - 0.5f;
            pvs__box_add_point(&boxes[i], p);
        }
    }
    memset(&kd, 0, sizeof(kd));
    kd.boxes = boxes;
    kd.count = n;
    for (rep = 0; rep < 3; ++rep) {
        t0 = now_ms();
        if (pvs_kdtree_create(&kd, &tree, &err) != PVS_OK) { printf("build failed: %s\n", err.message); return 1; }
        t0 = now_ms() - t0;
        if (t0 < best) best = t0;
        if (rep == 0) printf("# %u boxes: %u nodes\n", n, pvs_kdtree_node_count(tree));
        pvs_kdtree_destroy(tree);
    }
    printf("BENCH kdtree_build_ms_per_mtri %.1f ms\n", best * 1e6 / n);
    free(boxes);

    {
        /* a city: g x g blocks of extruded boxes of random height on a ground plane */
        const uint32_t g = 129, boxes_n = g * g;
        float *pos = (float *)malloc((8 * (size_t)boxes_n + 8) * 3 * sizeof(float));
        uint32_t *idx = (uint32_t *)malloc((12 * (size_t)boxes_n + 12) * 3 * sizeof(uint32_t));
        pvs_object_desc *objs = (pvs_object_desc *)malloc((boxes_n + 1) * sizeof(pvs_object_desc));
        uint32_t vc = 0, tc = 0, x, z, hits = 0, rays = 1000000;
        pvs_scene_desc sd;
        pvs_scene *scene;
        float lo[3], hi[3], extent = (float)g * 10.0f;
        lo[0] = -1.0f; lo[1] = -1.0f; lo[2] = -1.0f;
        hi[0] = extent + 1.0f; hi[1] = 0.0f; hi[2] = extent + 1.0f;
        test_box_arrays(pos, &vc, idx, &tc, lo, hi);
        objs[0].first_triangle = 0; objs[0].triangle_count = 12; objs[0].flags = 0;
        for (z = 0; z < g; ++z)
            for (x = 0; x < g; ++x) {
                pvs_object_desc *o = objs + 1 + z * g + x;
                lo[0] = (float)x * 10.0f + 2.0f; lo[1] = 0.0f; lo[2] = (float)z * 10.0f + 2.0f;
                hi[0] = lo[0] + 6.0f; hi[1] = 3.0f + 40.0f * frand() * frand(); hi[2] = lo[2] + 6.0f;
                o->first_triangle = tc; o->triangle_count = 12; o->flags = 0;
                test_box_arrays(pos, &vc, idx, &tc, lo, hi);
            }
        memset(&sd, 0, sizeof(sd));
        sd.positions = pos; sd.vertex_count = vc; sd.indices = idx; sd.triangle_count = tc;
        sd.objects = objs; sd.object_count = boxes_n + 1;
        t0 = now_ms();
        if (pvs_scene_create(&sd, &scene, &err) != PVS_OK) { printf("scene failed: %s\n", err.message); return 1; }
        printf("# city: %u triangles, scene create %.1f ms\n", tc, now_ms() - t0);
        {
            float *o = (float *)malloc((size_t)rays * 6 * sizeof(float));
            for (i = 0; i < rays; ++i) {
                float *r = o + 6 * (size_t)i, len;
                r[0] = extent * frand(); r[1] = 0.5f + 20.0f * frand(); r[2] = extent * frand();
                do {
                    r[3] = 2.0f * frand() - 1.0f; r[4] = 2.0f * frand() - 1.0f; r[5] = 2.0f * frand() - 1.0f;
                    len = r[3] * r[3] + r[4] * r[4] + r[5] * r[5];
                } while (len > 1.0f || len < 1e-6f);
            }
            t0 = now_ms();
            for (i = 0; i < rays; ++i) {
                pvs_hit h;
                hits += (uint32_t)pvs_scene_raycast(scene, o + 6 * (size_t)i, o + 6 * (size_t)i + 3, 1e4f, &h);
            }
            t0 = now_ms() - t0;
            printf("# %u rays, %u hits\n", rays, hits);
            printf("BENCH rays_per_s %.0f rays/s\n", rays / (t0 * 1e-3));
            free(o);
        }
        pvs_scene_destroy(scene);
        free(pos); free(idx); free(objs);
    }

    {
        /* slivers crossing the middle in every direction (tests/test_kdtree.c's adversarial scene 2): their boxes
           overlap there, the refs pool runs out; how the pool is shared decides the leaves rays meet */
        const uint32_t m = 20000, rays = 100000;
        float *pos = (float *)malloc(9 * (size_t)m * sizeof(float));
        uint32_t *idx = (uint32_t *)malloc(3 * (size_t)m * sizeof(uint32_t)), hits = 0;
        pvs_object_desc obj;
        pvs_scene_desc sd;
        pvs_scene *scene;
        for (i = 0; i < m; ++i) {
            float a = 3.14159265f * frand(), y = 20.0f * frand(), cx = 50.0f * cosf(a), cz = 50.0f * sinf(a);
            float *v = pos + 9 * (size_t)i;
            v[0] = -cx; v[1] = y; v[2] = -cz; v[3] = cx; v[4] = y; v[5] = cz; v[6] = cx; v[7] = y + 0.001f; v[8] = cz;
            idx[3 * i] = 3 * i; idx[3 * i + 1] = 3 * i + 1; idx[3 * i + 2] = 3 * i + 2;
        }
        memset(&obj, 0, sizeof(obj));
        obj.triangle_count = m;
        memset(&sd, 0, sizeof(sd));
        sd.positions = pos; sd.vertex_count = 3 * m; sd.indices = idx; sd.triangle_count = m;
        sd.objects = &obj; sd.object_count = 1;
        if (pvs_scene_create(&sd, &scene, &err) != PVS_OK) { printf("scene failed: %s\n", err.message); return 1; }
        t0 = now_ms();
        for (i = 0; i < rays; ++i) {
            float o[3], d[3];
            pvs_hit h;
            o[0] = 100.0f * frand() - 50.0f; o[1] = 20.0f * frand(); o[2] = 100.0f * frand() - 50.0f;
            d[0] = 2.0f * frand() - 1.0f; d[1] = 0.2f * frand() - 0.1f; d[2] = 2.0f * frand() - 1.0f;
            hits += (uint32_t)pvs_scene_raycast(scene, o, d, 1e4f, &h);
        }
        t0 = now_ms() - t0;
        printf("# %u crossing slivers: %u rays, %u hits\n", m, rays, hits);
        printf("BENCH rays_per_s_slivers %.0f rays/s\n", rays / (t0 * 1e-3));
        pvs_scene_destroy(scene);
        free(pos); free(idx);
    }
    return 0;
}
