/* test_noalloc.c - a private (PVS_STATIC) copy of the implementation whose PVS_MALLOC counts calls:
   proves that opening, looking up, decoding and walking a file with the cursor, rebuilding a cell's
   PVS from its virtual occluders and per-frame culling with the occlusion tree (pvs_otree_cull)
   allocate nothing. */
#include "test.h"
#include <stdlib.h>
#include <string.h>

static long noalloc_mallocs;
static void *noalloc_malloc(size_t n) { ++noalloc_mallocs; return malloc(n); }
#define PVS_MALLOC(n) noalloc_malloc(n)
#define PVS_FREE(p) free(p)
#define PVS_STATIC
#define PVS_IMPLEMENTATION
#include "../pvs.h"

/* A grid of boxes (12 triangles each) and walls; per-frame pvs_otree_cull with every occluder source
   along a walk: no allocation after pvs_otree_create. */
static void noalloc_otree(void) {
    enum { NB = 64 };
    static const uint32_t f[12][3] = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4},
                                      {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
    static float pos[NB * 8 * 3];
    static uint32_t idx[NB * 12 * 3];
    static pvs_object_desc od[NB];
    static pvs_word vis[PVS_BITSET_WORDS(NB)];
    static const float tri[9] = {3, 0, -4, 3, 0, 4, 3, 5, 0};
    pvs_occluder_desc vol[2];
    static const float foot[8] = {20, 20, 24, 20, 24, 26, 20, 26};
    pvs_scene_desc sd;
    pvs_scene *sc = NULL;
    pvs_otree_desc otd;
    pvs_otree *ot = NULL;
    pvs_cull_params cp;
    pvs_camera cam;
    uint32_t b, k, frame, culled = 0;
    for (b = 0; b < NB; ++b) {
        float x = (float)(b % 8) * 6.0f - 20.0f, z = (float)(b / 8) * 6.0f - 20.0f, h = 2.0f + (float)(b % 5);
        for (k = 0; k < 8; ++k) {
            pos[3 * (8 * b + k)] = x + (k & 1 ? 3.0f : 0.0f);
            pos[3 * (8 * b + k) + 1] = k & 2 ? h : 0.0f;
            pos[3 * (8 * b + k) + 2] = z + (k & 4 ? 3.0f : 0.0f);
        }
        for (k = 0; k < 36; ++k) idx[36 * b + k] = 8 * b + f[k / 3][k % 3];
        od[b].first_triangle = 12 * b; od[b].triangle_count = 12; od[b].flags = 0;
    }
    memset(vol, 0, sizeof(vol));
    vol[0].kind = PVS_OCCLUDER_BOX;
    vol[0].box.min[0] = 30; vol[0].box.min[1] = 0; vol[0].box.min[2] = -5;
    vol[0].box.max[0] = 31; vol[0].box.max[1] = 8; vol[0].box.max[2] = 5;
    vol[1].kind = PVS_OCCLUDER_EXTRUSION;
    vol[1].footprint = foot; vol[1].footprint_count = 4; vol[1].base = 0; vol[1].top = 9;
    memset(&sd, 0, sizeof(sd));
    sd.positions = pos; sd.vertex_count = NB * 8; sd.indices = idx; sd.triangle_count = NB * 12;
    sd.objects = od; sd.object_count = NB; sd.occluders = vol; sd.occluder_count = 2;
    CHECK(pvs_scene_create(&sd, &sc, NULL) == PVS_OK);
    if (!sc) return;
    memset(&otd, 0, sizeof(otd));
    otd.scene = sc;
    otd.aspect = 1.6f;
    CHECK(pvs_otree_create(&otd, &ot, NULL) == PVS_OK);
    if (!ot) { pvs_scene_destroy(sc); return; }
    memset(&cam, 0, sizeof(cam));
    cam.up[1] = 1; cam.fov_y = 1.0f; cam.near_plane = 0.1f;
    memset(&cp, 0, sizeof(cp));
    cp.occluder_positions = tri; cp.occluder_vertex_count = 3; cp.occluder_triangle_count = 1;
    cp.scene_occluders = 32; cp.occluder_distance = 30; cp.scene_volumes = 1;
    noalloc_mallocs = 0;
    for (frame = 0; frame < 60; ++frame) {
        pvs_cull_stats st;
        cam.eye[0] = -30.0f + (float)frame; cam.eye[1] = 1.5f; cam.eye[2] = -23.0f + 0.1f * (float)frame;
        cam.forward[0] = 1.0f; cam.forward[2] = 0.02f * (float)(frame % 20);
        if (frame == 30) pvs_otree_reset(ot);
        CHECK(pvs_otree_cull(ot, sc, &cam, &cp, vis, &st, NULL) == PVS_OK);
        CHECK(st.visible <= NB);
        culled += NB - st.visible;
    }
    CHECK(noalloc_mallocs == 0);
    CHECK(culled > 0);
    pvs_otree_destroy(ot);
    pvs_scene_destroy(sc);
}

void test_noalloc(void) {
    noalloc_otree();
    enum { CELLS = 40, OBJECTS = 500 };
    static pvs_box boxes[CELLS];
    static pvs_word pvs[CELLS * PVS_BITSET_WORDS(OBJECTS)], bits[PVS_BITSET_WORDS(OBJECTS)];
    pvs_file_desc d;
    pvs_file f;
    pvs_error e;
    uint8_t *buf;
    size_t bound, size;
    uint32_t c, i, sum = 0;
    for (c = 0; c < CELLS; ++c) {
        int k;
        for (k = 0; k < 3; ++k) { boxes[c].min[k] = (float)c; boxes[c].max[k] = (float)c + 1.0f; }
        for (i = c; i < OBJECTS; i += 1 + c % 7) pvs_bitset_set(pvs + c * PVS_BITSET_WORDS(OBJECTS), i);
    }
    memset(&d, 0, sizeof(d));
    d.cells = boxes; d.cell_count = CELLS; d.object_count = OBJECTS; d.pvs = pvs; d.up_axis = 1;
    CHECK(pvs_file_encode(&d, NULL, 0, &bound, &e) == PVS_OK);
    buf = (uint8_t *)malloc(bound);
    CHECK(pvs_file_encode(&d, buf, bound, &size, &e) == PVS_OK);
    noalloc_mallocs = 0;
    CHECK(pvs_file_open(buf, size, &f, &e) == PVS_OK);
    for (c = 0; c < CELLS; ++c) {
        float p[3];
        p[0] = p[1] = p[2] = (float)c + 0.5f;
        CHECK(pvs_file_find_cell(&f, p) == c);
        CHECK(pvs_file_decode(&f, c, bits, PVS_BITSET_WORDS(OBJECTS), &e) == PVS_OK);
        for (i = pvs_bitset_next(bits, OBJECTS, 0); i < OBJECTS; i = pvs_bitset_next(bits, OBJECTS, i + 1)) sum += i;
    }
    {
        static pvs_word cur[PVS_BITSET_WORDS(OBJECTS)], scratch[PVS_BITSET_WORDS(OBJECTS)];
        pvs_cursor cursor;
        CHECK(pvs_cursor_init(&cursor, &f, cur, scratch, PVS_BITSET_WORDS(OBJECTS), &e) == PVS_OK);
        for (c = 0; c < 3 * CELLS; ++c) CHECK(pvs_cursor_move(&cursor, (c * 7) % CELLS, NULL, NULL) == PVS_OK);
        for (c = 0; c < CELLS; ++c) { /* from each cell's base into it: one delta */
            pvs_record_info info;
            pvs_file_record_info(&f, c, &info);
            if (info.base != PVS_NO_CELL) CHECK(pvs_cursor_move(&cursor, info.base, NULL, NULL) == PVS_OK);
            CHECK(pvs_cursor_move(&cursor, c, NULL, NULL) == PVS_OK);
        }
        CHECK(cursor.delta_moves > 0);
    }
    CHECK(sum > 0);
    CHECK(noalloc_mallocs == 0);
    free(buf);
    { /* the virtual occluders' rebuild (pvs_vocc_cull), flat and through an object kD-tree */
        static uint8_t counts[CELLS], scales[CELLS], vo[CELLS * 2 * 5];
        static pvs_box objs[OBJECTS];
        static uint8_t scratch[1 << 18];
        pvs_kdtree *tree = NULL;
        pvs_kdtree_desc kd;
        size_t ss;
        for (c = 0; c < CELLS; ++c) {
            counts[c] = 2;
            scales[c] = 160;
            for (i = 0; i < 2; ++i) {
                uint8_t *q = vo + 10 * c + 5 * i;
                q[0] = (uint8_t)(100 + 40 * i); q[1] = 200; q[2] = (uint8_t)(140 + 40 * i); q[3] = 210; q[4] = 200;
            }
        }
        for (i = 0; i < OBJECTS; ++i) {
            int k;
            for (k = 0; k < 3; ++k) { objs[i].min[k] = (float)(i % 37) * 3.0f - 50.0f + (float)k; objs[i].max[k] = objs[i].min[k] + 2.0f; }
        }
        d.vocc_counts = counts; d.vocc_scales = scales; d.virtual_occluders = vo; d.vocc_base = -100.0f; d.vocc_height_step = 1.0f;
        CHECK(pvs_file_encode(&d, NULL, 0, &bound, &e) == PVS_OK);
        buf = (uint8_t *)malloc(bound);
        CHECK(pvs_file_encode(&d, buf, bound, &size, &e) == PVS_OK);
        memset(&kd, 0, sizeof(kd));
        kd.boxes = objs;
        kd.count = OBJECTS;
        CHECK(pvs_kdtree_create(&kd, &tree, &e) == PVS_OK);
        ss = pvs_vocc_cull_scratch_size(tree, 255);
        CHECK(ss <= sizeof(scratch));
        noalloc_mallocs = 0;
        CHECK(pvs_file_open(buf, size, &f, &e) == PVS_OK && (f.vocc_flags & PVS_VOCC_STORED));
        for (c = 0; c < CELLS; ++c) {
            pvs_virtual_occluder out[2];
            CHECK(pvs_file_virtual_occluders(&f, c, out, 2) == 2);
            CHECK(pvs_vocc_cull(&f, c, 0, objs, OBJECTS, NULL, scratch, ss, bits, &e) == PVS_OK);
            CHECK(pvs_vocc_cull(&f, c, 0, objs, OBJECTS, tree, scratch, ss, bits, &e) == PVS_OK);
            CHECK(pvs_vocc_cull_occluders(boxes + c, 1, out, 2, objs, OBJECTS, tree, scratch, ss, bits, &e) == PVS_OK);
        }
        CHECK(noalloc_mallocs == 0);
        pvs_kdtree_destroy(tree);
        free(buf);
    }
}
