/* bench_otree.c - `make bench` figures of the otree module on the demo city (GEN_CITY, seed 1):
   BENCH <name> <value> <unit>.
   1. The bake method (2.5D c-LSS) beside `shrink` on the same cells: ms per cell and tightness =
      mean PVS / mean reference set (cli_reference_visibility: uniform and aimed rays, a lower bound
      of the exact set, so the ratio is >= 1).
   2. From-point culling with the shadow-volume occlusion tree (pvs_otree_cull) along a walk through
      the streets: ms per frame, tree nodes, kD node tests with and without hierarchy updating.
   Times are CPU time on one thread (clock()). */
#include "../tools/cli.h"
#include "test.h"
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

static uint64_t rng = 0x0b7eeull;
static double rnd(void) { return test_rnd(&rng); }

static int in_cells(const mesh_cells *cells, const float p[3]) {
    uint32_t c;
    for (c = 0; c < cells->count; ++c) {
        const float *b = cells->boxes + 6 * (size_t)c;
        if (p[0] >= b[0] && p[0] <= b[3] && p[2] >= b[2] && p[2] <= b[5]) return 1;
    }
    return 0;
}

/* A walk through the streets: 1 m steps inside the view cells at eye height 1.7, heading slowly
   turning; a new start in a random cell when the next step leaves them. */
static void walk(const mesh_cells *cells, uint32_t frames, pvs_camera *cams) {
    pvs_camera cam;
    float h = 0.0f;
    uint32_t f;
    memset(&cam, 0, sizeof(cam));
    cam.up[1] = 1; cam.fov_y = 1.0f; cam.near_plane = 0.1f;
    for (f = 0; f < frames; ++f) {
        float next[3];
        next[0] = cam.eye[0] + cosf(h); next[1] = 1.7f; next[2] = cam.eye[2] + sinf(h);
        if (f == 0 || !in_cells(cells, next)) {
            const float *b = cells->boxes + 6 * (size_t)(rnd() * cells->count);
            next[0] = 0.5f * (b[0] + b[3]); next[2] = 0.5f * (b[2] + b[5]);
            h = (float)(rnd() * 6.283);
        }
        h += 0.01f;
        cam.eye[0] = next[0]; cam.eye[1] = 1.7f; cam.eye[2] = next[2];
        cam.forward[0] = cosf(h); cam.forward[1] = -0.03f; cam.forward[2] = sinf(h);
        cams[f] = cam;
    }
}

static int bake_cells(pvs_scene *scene, const pvs_box *sub, uint32_t n, pvs_method method, double *ms, double *sum_pvs, pvs_bake **out) {
    pvs_bake_desc bd;
    pvs_bake *bake;
    pvs_error pe;
    uint32_t c, objects = pvs_scene_object_count(scene);
    double t;
    test_bake_desc(&bd, scene, sub, n, method);
    if (pvs_bake_begin(&bd, &bake, &pe) != PVS_OK) { fprintf(stderr, "%s\n", pe.message); return 1; }
    t = test_cpu_seconds();
    for (c = 0; c < n; ++c)
        if (pvs_bake_run_task(bake, c, &pe) != PVS_OK) { fprintf(stderr, "%s\n", pe.message); return 1; }
    *ms = 1000.0 * (test_cpu_seconds() - t) / n;
    *sum_pvs = 0.0;
    for (c = 0; c < n; ++c) *sum_pvs += pvs_bitset_count(pvs_bake_cell_pvs(bake, c), objects);
    *out = bake;
    return 0;
}

int main(int argc, char **argv) {
    mesh m;
    mesh_cells cells;
    pvs_scene *scene;
    tool_error te;
    pvs_box *sub;
    pvs_word *bits;
    pvs_bake *b_ot = NULL, *b_sh = NULL;
    uint32_t c, n = 40, objects, frames = 600;
    int only_frame = argc > 1 && strcmp(argv[1], "frame") == 0, only_bake = argc > 1 && strcmp(argv[1], "bake") == 0;
    double ms_ot, ms_sh, pvs_ot, pvs_sh, sum_ref = 0.0;
    if (argc > 2) n = (uint32_t)atoi(argv[2]); /* cells for the bake figures (default 40) */
    if (n < 1) n = 1;
    if (cli_demo_city(&m, &cells, &scene, &te)) { fprintf(stderr, "%s\n", te.message); return 1; }
    objects = pvs_scene_object_count(scene);
    if (!only_frame) {
        if (n > cells.count) n = cells.count;
        sub = (pvs_box *)malloc(n * sizeof(pvs_box));
        for (c = 0; c < n; ++c) memcpy(sub + c, cells.boxes + 6 * (size_t)((uint64_t)c * cells.count / n), sizeof(pvs_box));
        if (bake_cells(scene, sub, n, PVS_METHOD_OTREE, &ms_ot, &pvs_ot, &b_ot)) return 1;
        if (only_bake) {
            printf("BENCH otree_ms_per_cell %.2f ms\n", ms_ot);
            printf("BENCH otree_mean_pvs %.1f objects\n", pvs_ot / n);
            return 0;
        }
        if (bake_cells(scene, sub, n, PVS_METHOD_SHRINK, &ms_sh, &pvs_sh, &b_sh)) return 1;
        bits = (pvs_word *)calloc(PVS_BITSET_WORDS(objects), sizeof(pvs_word));
        for (c = 0; c < n; ++c) {
            memset(bits, 0, PVS_BITSET_WORDS(objects) * sizeof(pvs_word));
            cli_reference_visibility(scene, sub + c, c, bits); /* uniform and aimed rays */
            sum_ref += pvs_bitset_count(bits, objects);
        }
        printf("BENCH otree_ms_per_cell %.2f ms\n", ms_ot);  /* one core, the same cells as shrink below */
        printf("BENCH otree_shrink_ms_per_cell %.2f ms\n", ms_sh);
        printf("BENCH otree_mean_pvs %.1f objects\n", pvs_ot / n);
        printf("BENCH otree_shrink_mean_pvs %.1f objects\n", pvs_sh / n);
        printf("BENCH otree_tightness %.3f ratio\n", sum_ref > 0 ? pvs_ot / sum_ref : 0.0);
        printf("BENCH otree_shrink_tightness %.3f ratio\n", sum_ref > 0 ? pvs_sh / sum_ref : 0.0);
        free(bits);
        free(sub);
        pvs_bake_destroy(b_ot);
        pvs_bake_destroy(b_sh);
    }
    {
        pvs_camera *cams = (pvs_camera *)malloc(frames * sizeof(pvs_camera));
        pvs_otree_desc od;
        pvs_otree *ot;
        pvs_cull_params cp;
        pvs_error pe;
        pvs_word *vis = (pvs_word *)calloc(PVS_BITSET_WORDS(objects), sizeof(pvs_word));
        double best = 1e30, best_fmc = 1e30, nodes = 0, tests = 0, tests_full = 0, visible = 0, visible_fmc = 0, in_frustum = 0;
        uint32_t f, rep, flags;
        walk(&cells, frames, cams);
        memset(&cp, 0, sizeof(cp));
        cp.scene_occluders = 32;
        cp.occluder_distance = 60;
        for (flags = 0; flags < 3; ++flags) { /* FME with hierarchy updating, testing every node, FMC */
            memset(&od, 0, sizeof(od));
            od.scene = scene;
            od.aspect = 16.0f / 9.0f;
            od.flags = flags == 1 ? PVS_OTREE_NO_COHERENCE : flags == 2 ? PVS_OTREE_PLANE_ONLY : 0u;
            if (pvs_otree_create(&od, &ot, &pe) != PVS_OK) { fprintf(stderr, "%s\n", pe.message); return 1; }
            for (rep = 0; rep < (flags == 1 ? 1u : 3u); ++rep) { /* min of 3 runs (a shared, loaded machine) */
                double t;
                pvs_otree_reset(ot);
                t = test_cpu_seconds();
                for (f = 0; f < frames; ++f) {
                    pvs_cull_stats st;
                    pvs_otree_frame fi;
                    pvs_otree_cull(ot, scene, cams + f, &cp, vis, &st, &pe);
                    if (rep == 0) {
                        pvs_otree_get_frame(ot, &fi);
                        if (flags == 1) {
                            tests_full += fi.node_tests;
                            pvs_otree_cull(ot, scene, cams + f, NULL, vis, &st, &pe); /* no occluders: the frustum only */
                            in_frustum += st.visible;
                        }
                        else if (flags == 2) visible_fmc += st.visible;
                        else { tests += fi.node_tests; nodes += fi.tree_nodes; visible += st.visible; }
                    }
                }
                t = test_cpu_seconds() - t;
                if (!flags && t < best) best = t;
                if (flags == 2 && t < best_fmc) best_fmc = t;
            }
            pvs_otree_destroy(ot);
        }
        printf("BENCH otree_frame_ms %.3f ms\n", 1000.0 * best / frames); /* 32 scene occluders, one core */
        printf("BENCH otree_frame_tree_nodes %.0f nodes\n", nodes / frames);
        printf("BENCH otree_frame_node_tests %.0f tests\n", tests / frames);
        printf("BENCH otree_frame_node_tests_full %.0f tests\n", tests_full / frames); /* testing every node */
        printf("BENCH otree_frame_visible %.1f objects\n", visible / frames);
        printf("BENCH otree_frame_in_frustum %.1f objects\n", in_frustum / frames);
        printf("BENCH otree_frame_ms_fmc %.3f ms\n", 1000.0 * best_fmc / frames); /* Table 4.1's FMC: fragment planes only */
        printf("BENCH otree_frame_visible_fmc %.1f objects\n", visible_fmc / frames);
        free(vis);
        free(cams);
    }
    pvs_scene_destroy(scene);
    mesh_cells_free(&cells);
    mesh_free(&m);
    return 0;
}
