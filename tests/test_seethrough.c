/* test_seethrough.c - PVS_OBJECT_SEE_THROUGH (glass, foliage, doors baked open): such an object is
   drawn and appears in PVSs but blocks sight nowhere. A wall stands between a view cell and a box.
   Opaque, every method that culls the box shows the test can fail; see-through, every method and
   AUTO keep the box and the wall (0 misses against ray sampling, which now sees through the wall),
   the ray casts pass the wall, and per-frame culling sees the box until the caller draws the wall
   (a closed door) as its own occluder. Also: flags out of range are refused. */
#include "../pvs.h"
#include "test.h"
#include <stdlib.h>
#include <string.h>

enum { ST_GROUND, ST_LEFT, ST_WALL, ST_RIGHT, ST_OBJECTS };

/* Ground, a box left of the wall, the wall (x -1..1, 5 high, z -10..10), a box right of it. */
static pvs_scene *st_scene(uint32_t wall_flags) {
    static float pos[3 * 40];
    static uint32_t idx[3 * 40];
    static const float box[3][2][3] = {{{-6, 0, -1}, {-4, 2, 1}}, {{-1, 0, -10}, {1, 5, 10}}, {{4, 0, -1}, {6, 2, 1}}};
    pvs_object_desc obs[ST_OBJECTS];
    uint32_t vc = 4, tc = 2, k;
    const float ground[4][3] = {{-30, 0, -30}, {30, 0, -30}, {30, 0, 30}, {-30, 0, 30}};
    memcpy(pos, ground, sizeof(ground));
    idx[0] = 0; idx[1] = 1; idx[2] = 2; idx[3] = 0; idx[4] = 2; idx[5] = 3;
    memset(obs, 0, sizeof(obs));
    obs[ST_GROUND].triangle_count = 2;
    for (k = 0; k < 3; ++k) {
        obs[ST_LEFT + k].first_triangle = tc;
        obs[ST_LEFT + k].triangle_count = 12;
        test_box_arrays(pos, &vc, idx, &tc, box[k][0], box[k][1]);
    }
    obs[ST_WALL].flags = wall_flags;
    return test_scene_arrays(pos, vc, idx, tc, obs, ST_OBJECTS, 1);
}

/* The cell's PVS by `method` into pvs (one word: 4 objects); 0 when the bake fails. */
static int st_bake(const pvs_scene *s, const pvs_box *cell, pvs_method method, pvs_word *pvs) {
    pvs_bake_desc bd;
    pvs_bake *b = NULL;
    pvs_error e;
    int ok;
    test_bake_desc(&bd, s, cell, 1, method);
    if (method == PVS_METHOD_EXTPROJ) bd.extproj.sweep = PVS_EXTPROJ_SWEEP_PLANES;
    ok = pvs_bake_begin(&bd, &b, &e) == PVS_OK && pvs_bake_run_task(b, 0, &e) == PVS_OK;
    if (!ok) fprintf(stderr, "seethrough: %s: %s\n", pvs_method_name(method), e.message);
    else *pvs = pvs_bake_cell_pvs(b, 0)[0];
    pvs_bake_destroy(b);
    return ok;
}

/* PVS_OBJECT_ONE_SIDED: upright quads in plane x = qx (z in [z0, z1], 3 high) facing +x or -x (counter-clockwise
   front). Seen from the cell (x in [-3, -2]): quad 1 faces it, quad 2 (x = 2) faces away (dropped from the PVS,
   its back hits not counted), quad 3 (x = -2.5) has the cell on both sides of its plane (kept). */
static void test_one_sided(void) {
    static const float q[3][4] = {{2, -6, -2, -1}, {2, 2, 6, 1}, {-2.5f, 5, 8, 1}}; /* x, z0, z1, facing */
    static const pvs_method methods[] = {PVS_METHOD_SAMPLE, PVS_METHOD_PORTAL, PVS_METHOD_OTREE, PVS_METHOD_AUTO};
    const pvs_box cell = {{-3, 0.5f, -0.5f}, {-2, 1.5f, 0.5f}};
    float pos[3 * 16];
    uint32_t idx[3 * 8], vc = 0, tc = 0, k, m, one;
    pvs_object_desc obs[4];
    pvs_word seen[1], pvs[1];
    memset(obs, 0, sizeof(obs));
    for (k = 0; k < 4; ++k) { /* ground (y = 0, facing up), then the quads: (x, 0, a) (x, 3, a) (x, 3, b) (x, 0, b) */
        float a = k ? q[k - 1][q[k - 1][3] > 0 ? 1 : 2] : 0, b = k ? q[k - 1][q[k - 1][3] > 0 ? 2 : 1] : 0;
        const float ground[12] = {-10, 0, 10, 10, 0, 10, 10, 0, -10, -10, 0, -10};
        float quad[12] = {0, 0, 0, 0, 3, 0, 0, 3, 0, 0, 0, 0};
        uint32_t j;
        for (j = 0; j < 4; ++j) quad[3 * j] = k ? q[k - 1][0] : 0, quad[3 * j + 2] = j < 2 ? a : b;
        memcpy(pos + 3 * vc, k ? quad : ground, sizeof(quad));
        obs[k].first_triangle = tc;
        obs[k].triangle_count = 2;
        idx[3 * tc] = vc, idx[3 * tc + 1] = vc + 1, idx[3 * tc + 2] = vc + 2, ++tc;
        idx[3 * tc] = vc, idx[3 * tc + 1] = vc + 2, idx[3 * tc + 2] = vc + 3, ++tc;
        vc += 4;
    }
    for (one = 0; one < 2; ++one) {
        pvs_scene *s;
        for (k = 0; k < 4; ++k) obs[k].flags = one ? PVS_OBJECT_ONE_SIDED : 0u;
        s = test_scene_arrays(pos, vc, idx, tc, obs, 4, 1);
        CHECK(s != NULL);
        if (!s) return;
        test_sample(s, &cell, 64, 512, 7, 64, 9, seen); /* the back of quad 2 counts only when two-sided */
        CHECK((seen[0] & 0xfu) == (one ? 0xbu : 0xfu));
        for (m = 0; m < sizeof(methods) / sizeof(methods[0]); ++m) {
            CHECK(st_bake(s, &cell, methods[m], pvs));
            if ((pvs[0] & 0xfu) != (one ? 0xbu : 0xfu))
                fprintf(stderr, "seethrough: one-sided %u, %s: PVS %#x\n", one, pvs_method_name(methods[m]), (unsigned)pvs[0]);
            CHECK((pvs[0] & 0xfu) == (one ? 0xbu : 0xfu));
        }
        pvs_scene_destroy(s);
    }
    obs[1].flags = PVS_OBJECT_ONE_SIDED | PVS_OBJECT_OCCLUDER_ONLY; /* refused: never drawn */
    CHECK(test_scene_arrays(pos, vc, idx, tc, obs, 4, 1) == NULL);
}

void test_seethrough(void) {
    static const pvs_method methods[] = {PVS_METHOD_PORTAL, PVS_METHOD_OTREE, PVS_METHOD_EXTPROJ,
                                         PVS_METHOD_SHRINK, PVS_METHOD_VOCC,  PVS_METHOD_AUTO};
    const pvs_box cell = {{-3, 0.5f, -0.5f}, {-2, 1.5f, 0.5f}};
    pvs_scene *opaque = st_scene(0), *clear = st_scene(PVS_OBJECT_SEE_THROUGH);
    pvs_word seen[1], pvs[1];
    uint32_t k, culled = 0;
    CHECK(opaque && clear);
    if (!opaque || !clear) goto done;

    /* the reference: sampling stops at the opaque wall, passes the see-through one and reports it */
    test_sample(opaque, &cell, 64, 512, 7, 64, 9, seen);
    CHECK(pvs_bitset_test(seen, ST_WALL) && !pvs_bitset_test(seen, ST_RIGHT));
    test_sample(clear, &cell, 64, 512, 7, 64, 9, seen);
    CHECK(pvs_bitset_test(seen, ST_WALL) && pvs_bitset_test(seen, ST_RIGHT) && pvs_bitset_test(seen, ST_LEFT));
    {
        const float o[3] = {-2.5f, 1, 0}, d[3] = {1, 0, 0}, b[3] = {3, 1, 0};
        pvs_hit h;
        CHECK(pvs_scene_raycast(opaque, o, d, 100, &h) && h.object == ST_WALL);
        CHECK(pvs_scene_raycast(clear, o, d, 100, &h) && h.object == ST_RIGHT);
        CHECK(pvs_scene_segment_blocked(opaque, o, b) && !pvs_scene_segment_blocked(clear, o, b));
    }

    for (k = 0; k < sizeof(methods) / sizeof(methods[0]); ++k) {
        if (st_bake(opaque, &cell, methods[k], pvs) && !(pvs[0] >> ST_RIGHT & 1u)) ++culled;
        CHECK(st_bake(clear, &cell, methods[k], pvs));
        if (!(pvs[0] >> ST_RIGHT & 1u) || !(pvs[0] >> ST_WALL & 1u))
            fprintf(stderr, "seethrough: %s hides what the see-through wall shows (PVS %#x)\n",
                    pvs_method_name(methods[k]), (unsigned)pvs[0]);
        CHECK(pvs[0] >> ST_RIGHT & 1u && pvs[0] >> ST_WALL & 1u && pvs[0] >> ST_LEFT & 1u);
        CHECK(test_misses(seen, pvs, ST_OBJECTS, pvs_method_name(methods[k]), 0) == 0);
    }
    CHECK(culled >= 4); /* the opaque wall hides the box from most methods: the checks above can fail */

    /* per frame: the see-through wall hides nothing; drawn by the caller (a closed door), it does */
    {
        pvs_raster_desc rd;
        pvs_raster *r = NULL;
        pvs_camera cam;
        pvs_cull_params cp;
        pvs_word vis[1];
        float wall[36 * 3];
        uint32_t i, vc = 0, tc = 0, widx[36];
        const float lo[3] = {-1, 0, -10}, hi[3] = {1, 5, 10};
        float wpos[8 * 3];
        memset(&rd, 0, sizeof(rd));
        rd.width = 256;
        rd.height = 128;
        rd.scene = opaque;
        CHECK(pvs_raster_create(&rd, &r, NULL) == PVS_OK);
        memset(&cam, 0, sizeof(cam));
        cam.eye[0] = -2.5f; cam.eye[1] = 1; cam.forward[0] = 1; cam.up[1] = 1;
        cam.fov_y = 1.2f; cam.near_plane = 0.1f; cam.far_plane = 100;
        memset(&cp, 0, sizeof(cp));
        cp.scene_occluders = 64;
        cp.occluder_distance = 50;
        CHECK(pvs_raster_cull(r, opaque, &cam, &cp, vis, NULL, NULL) == PVS_OK && !(vis[0] >> ST_RIGHT & 1u));
        CHECK(pvs_raster_cull(r, clear, &cam, &cp, vis, NULL, NULL) == PVS_OK && vis[0] >> ST_RIGHT & 1u &&
              vis[0] >> ST_WALL & 1u);
        test_box_arrays(wpos, &vc, widx, &tc, lo, hi);
        for (i = 0; i < 36; ++i) memcpy(wall + 3 * i, wpos + 3 * widx[i], 3 * sizeof(float));
        cp.occluder_positions = wall;
        cp.occluder_vertex_count = 36;
        cp.occluder_triangle_count = 12;
        CHECK(pvs_raster_cull(r, clear, &cam, &cp, vis, NULL, NULL) == PVS_OK && !(vis[0] >> ST_RIGHT & 1u) &&
              vis[0] >> ST_WALL & 1u);
        pvs_raster_destroy(r);
    }

    /* flags: OCCLUDER_ONLY | SEE_THROUGH (neither drawn nor blocking) and unknown bits are refused */
    {
        pvs_scene *bad = st_scene(PVS_OBJECT_OCCLUDER_ONLY | PVS_OBJECT_SEE_THROUGH);
        CHECK(bad == NULL);
        bad = st_scene(8u);
        CHECK(bad == NULL);
    }
done:
    pvs_scene_destroy(opaque);
    pvs_scene_destroy(clear);
    test_one_sided();
}
