/* test_vocc.c - virtual occluders (Koltun, Chrysanthou, Cohen-Or 2000). Brute-force references:
   every 2D virtual occluder is hidden (segments from many cell points to many points of it all
   cross the input segments, in long double); every stored 2.5D occluder is hidden in the scene
   (3D segments from the cell box to its rectangle all hit scene triangles, pvs_scene_segment_blocked);
   the box test against segment sampling; the rebuilt PVS against ray sampling (0 misses); the tree
   walk against the flat test; the VOCC section's round trip, validation and skipping; determinism;
   the paper's fusion cases (§3, Fig. 5) on hand-made scenes. */
#include "../pvs.h"
#include "../tools/gen.h"
#include "../tools/mesh.h"
#include "test.h"
#include <math.h>
#include <stdlib.h>
#include <string.h>

static uint64_t vo_rng = 0x0cc1de5ull;
static double rnd(void) { return test_rnd(&vo_rng); }

/* ---- 2D brute force ---- */

static long double orient2(const long double *a, const long double *b, const long double *c) {
    return (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
}
/* 1 if segment p-q properly crosses one of the segments, decided in long double with the sign of
   each orientation trusted only beyond its rounding bound (a touch or a near-touch counts as not
   blocked: the reference rounds against the construction). Random sample points never pass
   exactly through a wall's end, where touching chains would also block. */
static int blocked2d(const long double *p, const long double *q, const float *seg, uint32_t n) {
    uint32_t i;
    for (i = 0; i < n; ++i) {
        long double a[2], b[2], o1, o2, o3, o4, s1, s2;
        a[0] = seg[4 * i]; a[1] = seg[4 * i + 1]; b[0] = seg[4 * i + 2]; b[1] = seg[4 * i + 3];
        o1 = orient2(p, q, a); o2 = orient2(p, q, b); o3 = orient2(a, b, p); o4 = orient2(a, b, q);
        s1 = 1e-15L * (fabsl(q[0] - p[0]) + fabsl(q[1] - p[1])) * (fabsl(b[0] - a[0]) + fabsl(b[1] - a[1]) + fabsl(a[0] - p[0]) + fabsl(a[1] - p[1]) + 1.0L);
        s2 = s1;
        if (((o1 > s1 && o2 < -s1) || (o1 < -s1 && o2 > s1)) && ((o3 > s2 && o4 < -s2) || (o3 < -s2 && o4 > s2))) return 1;
    }
    return 0;
}
/* A cell point: corners, points on the edges, interior points. */
static void cell_point(const float *cmin, const float *cmax, int i, long double *p) {
    double u = rnd(), w = cmax[0] - cmin[0], h = cmax[1] - cmin[1];
    if (i < 4) {
        p[0] = (i & 1) ? cmax[0] : cmin[0];
        p[1] = (i & 2) ? cmax[1] : cmin[1];
    } else if (i < 24) {
        switch (i & 3) {
        case 0: p[0] = cmin[0] + u * w; p[1] = cmin[1]; break;
        case 1: p[0] = cmax[0]; p[1] = cmin[1] + u * h; break;
        case 2: p[0] = cmin[0] + u * w; p[1] = cmax[1]; break;
        default: p[0] = cmin[0]; p[1] = cmin[1] + u * h; break;
        }
    } else {
        p[0] = cmin[0] + rnd() * w;
        p[1] = cmin[1] + rnd() * h;
    }
}
/* Number of virtual occluders some brute-force segment reaches unblocked. */
static uint32_t check2d(const float *cmin, const float *cmax, const float *seg, uint32_t ns, const float *occ, uint32_t n, int samples) {
    uint32_t i, bad = 0;
    for (i = 0; i < n; ++i) {
        int a, b, fail = 0;
        for (a = 0; a < samples && !fail; ++a) {
            long double p[2];
            cell_point(cmin, cmax, a, p);
            for (b = 0; b < samples && !fail; ++b) {
                long double u = b == 0 ? 0.0L : b == 1 ? 1.0L : (long double)rnd(), q[2];
                q[0] = occ[4 * i] + u * ((long double)occ[4 * i + 2] - occ[4 * i]);
                q[1] = occ[4 * i + 1] + u * ((long double)occ[4 * i + 3] - occ[4 * i + 1]);
                if (!blocked2d(p, q, seg, ns)) fail = 1;
            }
        }
        bad += (uint32_t)fail;
    }
    return bad;
}

static uint32_t add_rect(float *seg, uint32_t n, double cx, double cy, double w, double h, double ang, int ring) {
    double ca = cos(ang), sa = sin(ang), px[4], py[4], dx[4], dy[4];
    int k;
    dx[0] = -w / 2; dx[1] = w / 2; dx[2] = w / 2; dx[3] = -w / 2;
    dy[0] = -h / 2; dy[1] = -h / 2; dy[2] = h / 2; dy[3] = h / 2;
    for (k = 0; k < 4; ++k) {
        px[k] = cx + ca * dx[k] - sa * dy[k];
        py[k] = cy + sa * dx[k] + ca * dy[k];
    }
    if (!ring) { /* one diagonal wall */
        seg[4 * n] = (float)px[0]; seg[4 * n + 1] = (float)py[0]; seg[4 * n + 2] = (float)px[2]; seg[4 * n + 3] = (float)py[2];
        return n + 1;
    }
    for (k = 0; k < 4; ++k, ++n) {
        seg[4 * n] = (float)px[k]; seg[4 * n + 1] = (float)py[k];
        seg[4 * n + 2] = (float)px[(k + 1) % 4]; seg[4 * n + 3] = (float)py[(k + 1) % 4];
    }
    return n;
}

/* Random scenes of wall loops and free walls around a cell: every virtual occluder hidden. */
static void test_2d_random(void) {
    int trial;
    uint32_t total = 0, bad = 0;
    for (trial = 0; trial < 12; ++trial) {
        static float seg[4 * 600], occ[4 * 1024];
        float cmin[2] = {-5.0f, -3.0f}, cmax[2] = {5.0f, 3.0f};
        uint32_t ns = 0, n = 0, b, nb = 25 + (uint32_t)(rnd() * 45);
        pvs_vocc_2d_desc d;
        pvs_vocc_stats st;
        pvs_error e;
        for (b = 0; b < nb; ++b) {
            double cx = (rnd() - 0.5) * 100, cy = (rnd() - 0.5) * 100, w = 2 + rnd() * 14, h = 2 + rnd() * 14;
            double ang = rnd() < 0.5 ? 0.0 : rnd() * 3.14;
            if (fabs(cx) < 5 + w + h && fabs(cy) < 3 + w + h) continue;
            ns = add_rect(seg, ns, cx, cy, w, h, ang, rnd() < 0.8);
        }
        memset(&d, 0, sizeof(d));
        d.cell_min[0] = cmin[0]; d.cell_min[1] = cmin[1]; d.cell_max[0] = cmax[0]; d.cell_max[1] = cmax[1];
        d.segments = seg;
        d.segment_count = ns;
        d.max_seeds = 8;
        CHECK(pvs_vocc_2d(&d, occ, 1024, &n, &st, &e) == PVS_OK);
        if (n > 1024) n = 1024;
        total += n;
        bad += check2d(cmin, cmax, seg, ns, occ, n, 24);
        CHECK(st.seeds > 0);
    }
    if (bad) fprintf(stderr, "vocc 2d: %u of %u virtual occluders are visible\n", bad, total);
    CHECK(bad == 0);
    CHECK(total > 50);
}

/* §3's cases on purpose-made scenes. (a) a wall facing the cell: its occluder lies behind it; (b) a
   row of walls with gaps, seen at a grazing angle: one occluder spans several of them (fusion
   through overlapping angular intervals, Fig. 2); (c) Fig. 5: walls whose single umbrae are
   disjoint but whose aggregate umbra is one region; (d) a wall loop (a building): points inside are
   hidden; (e) a gap in front of the cell lets sight through: nothing behind it is claimed. */
static void test_2d_cases(void) {
    static float seg[4 * 64], occ[4 * 256];
    float cmin[2] = {-2.0f, -2.0f}, cmax[2] = {2.0f, 2.0f};
    pvs_vocc_2d_desc d;
    uint32_t n = 0, ns, i;
    double longest;
    memset(&d, 0, sizeof(d));
    d.cell_min[0] = cmin[0]; d.cell_min[1] = cmin[1]; d.cell_max[0] = cmax[0]; d.cell_max[1] = cmax[1];
    d.segments = seg;
    /* (a) */
    seg[0] = -20; seg[1] = 10; seg[2] = 20; seg[3] = 10;
    d.segment_count = 1;
    CHECK(pvs_vocc_2d(&d, occ, 256, &n, NULL, NULL) == PVS_OK);
    CHECK(n >= 1);
    CHECK(check2d(cmin, cmax, seg, 1, occ, n < 256 ? n : 256, 20) == 0);
    for (i = 0; i < n && i < 256; ++i) CHECK(occ[4 * i + 1] > 10.0f && occ[4 * i + 3] > 10.0f);
    /* (b) walls along y = 6 from x = 10 to 60 with 0.5 gaps, each closed into a 5-deep building */
    ns = 0;
    for (i = 0; i < 10; ++i) ns = add_rect(seg, ns, 12.5 + 5.0 * i, 8.5, 4.5, 5.0, 0.0, 1);
    d.segment_count = ns;
    CHECK(pvs_vocc_2d(&d, occ, 256, &n, NULL, NULL) == PVS_OK);
    CHECK(check2d(cmin, cmax, seg, ns, occ, n < 256 ? n : 256, 20) == 0);
    longest = 0.0;
    for (i = 0; i < n && i < 256; ++i) {
        double l = hypot(occ[4 * i + 2] - occ[4 * i], occ[4 * i + 3] - occ[4 * i + 1]);
        if (l > longest) longest = l;
    }
    CHECK(longest > 12.0); /* longer than two buildings: fused across a gap */
    /* (c) Fig. 5: three walls staggered in depth; the middle one covers the gap between the others */
    seg[0] = -6; seg[1] = 8; seg[2] = -1; seg[3] = 8;
    seg[4] = -2; seg[5] = 12; seg[6] = 3; seg[7] = 12;
    seg[8] = 2; seg[9] = 8; seg[10] = 7; seg[11] = 8;
    d.segment_count = 3;
    CHECK(pvs_vocc_2d(&d, occ, 256, &n, NULL, NULL) == PVS_OK);
    CHECK(check2d(cmin, cmax, seg, 3, occ, n < 256 ? n : 256, 24) == 0);
    /* (d) a building: its inside is hidden, an occluder may lie in it */
    ns = add_rect(seg, 0, 0.0, 12.0, 16.0, 6.0, 0.0, 1);
    d.segment_count = ns;
    CHECK(pvs_vocc_2d(&d, occ, 256, &n, NULL, NULL) == PVS_OK);
    CHECK(n >= 1);
    CHECK(check2d(cmin, cmax, seg, ns, occ, n < 256 ? n : 256, 20) == 0);
    /* (e) two walls with a gap right in front of the cell */
    seg[0] = -30; seg[1] = 5; seg[2] = -0.5f; seg[3] = 5;
    seg[4] = 0.5f; seg[5] = 5; seg[6] = 30; seg[7] = 5;
    d.segment_count = 2;
    CHECK(pvs_vocc_2d(&d, occ, 256, &n, NULL, NULL) == PVS_OK);
    CHECK(check2d(cmin, cmax, seg, 2, occ, n < 256 ? n : 256, 24) == 0);
    for (i = 0; i < n && i < 256; ++i) { /* nothing straight behind the gap */
        float lo = occ[4 * i] < occ[4 * i + 2] ? occ[4 * i] : occ[4 * i + 2], hi = occ[4 * i] < occ[4 * i + 2] ? occ[4 * i + 2] : occ[4 * i];
        CHECK(!(lo < 0.0f && hi > 0.0f && occ[4 * i + 1] < 8.0f));
    }
    /* bad input */
    d.cell_max[0] = d.cell_min[0];
    CHECK(pvs_vocc_2d(&d, occ, 256, &n, NULL, NULL) == PVS_ERROR_BAD_CELL);
    d.cell_max[0] = 2.0f;
    seg[0] = NAN;
    CHECK(pvs_vocc_2d(&d, occ, 256, &n, NULL, NULL) == PVS_ERROR_NOT_FINITE);
    CHECK(pvs_vocc_2d(NULL, occ, 256, &n, NULL, NULL) == PVS_ERROR_INVALID_ARGUMENT);
    d.segment_count = 0;
    CHECK(pvs_vocc_2d(&d, NULL, 0, &n, NULL, NULL) == PVS_OK && n == 0);
}

/* ---- the box test against 3D segment sampling ---- */

/* 1 if segment p-q crosses the vertical rectangle over a-b (ground axes 0, 2; up 1), heights lo..hi. */
static int crosses_rect(const double *p, const double *q, const float *a, const float *b, double lo, double hi) {
    double ex = b[0] - a[0], ez = b[1] - a[1], nx = -ez, nz = ex;
    double dp = nx * (p[0] - a[0]) + nz * (p[2] - a[1]), dq = nx * (q[0] - a[0]) + nz * (q[2] - a[1]), t, x, z, y, s;
    if (dp * dq > 0 || dp == dq) return 0;
    t = dp / (dp - dq);
    x = p[0] + t * (q[0] - p[0]);
    y = p[1] + t * (q[1] - p[1]);
    z = p[2] + t * (q[2] - p[2]);
    s = ((x - a[0]) * ex + (z - a[1]) * ez) / (ex * ex + ez * ez);
    return s >= 0 && s <= 1 && y >= lo && y <= hi;
}
static void box_point(const pvs_box *b, double *p) {
    int k;
    for (k = 0; k < 3; ++k) {
        double u = rnd();
        if (rnd() < 0.3) u = u < 0.5 ? 0.0 : 1.0; /* faces and corners often */
        p[k] = b->min[k] + u * (b->max[k] - b->min[k]);
    }
}
static void test_box_hidden(void) {
    int trial, hidden = 0, bad = 0;
    for (trial = 0; trial < 3000; ++trial) {
        pvs_box cell, box;
        pvs_virtual_occluder o;
        int k, s;
        cell.min[0] = (float)(rnd() * 4 - 2); cell.max[0] = cell.min[0] + (float)(0.5 + rnd() * 6);
        cell.min[2] = (float)(rnd() * 4 - 2); cell.max[2] = cell.min[2] + (float)(0.5 + rnd() * 6);
        cell.min[1] = (float)(rnd() * 1.5); cell.max[1] = cell.min[1] + (float)(rnd() * 3);
        o.p0[0] = (float)(-30 + rnd() * 60); o.p0[1] = (float)(8 + rnd() * 10);
        o.p1[0] = (float)(-30 + rnd() * 60); o.p1[1] = (float)(8 + rnd() * 10);
        if (rnd() < 0.3) { float t = o.p0[1]; o.p0[1] = -o.p1[1]; o.p1[1] = -t; }
        o.base = 0.0f;
        o.top = (float)(1 + rnd() * 20);
        box.min[0] = (float)(-40 + rnd() * 80); box.max[0] = box.min[0] + (float)(rnd() * 8);
        box.min[2] = (float)(-40 + rnd() * 80); box.max[2] = box.min[2] + (float)(rnd() * 8);
        box.min[1] = (float)(rnd() * 2); box.max[1] = box.min[1] + (float)(rnd() * 30);
        if (rnd() < 0.5) { /* right behind the occluder, often hidden */
            float mx = 0.5f * (o.p0[0] + o.p1[0]), mz = 0.5f * (o.p0[1] + o.p1[1]);
            box.min[0] = mx * 1.6f - 1.0f; box.max[0] = box.min[0] + 2.0f;
            box.min[2] = mz * 1.6f - 1.0f; box.max[2] = box.min[2] + 2.0f;
        }
        if (!pvs_vocc_box_hidden(&cell, 1, &o, &box)) continue;
        ++hidden;
        for (s = 0; s < 200; ++s) {
            double p[3], q[3];
            box_point(&cell, p);
            box_point(&box, q);
            if (!crosses_rect(p, q, o.p0, o.p1, o.base, o.top)) { ++bad; break; }
        }
        (void)k;
    }
    CHECK(hidden > 100);
    CHECK(bad == 0);
    { /* obvious answers */
        pvs_box cell = {{-1, 0.5f, -1}, {1, 2, 1}}, far_box = {{-1, 0, 20}, {1, 5, 22}}, tall = {{-1, 0, 20}, {1, 500, 22}};
        pvs_box empty = {{1, 0, 0}, {0, 1, 1}};
        pvs_virtual_occluder o = {{-10, 10}, {10, 10}, 0, 8};
        CHECK(pvs_vocc_box_hidden(&cell, 1, &o, &far_box) == 1);
        CHECK(pvs_vocc_box_hidden(&cell, 1, &o, &tall) == 0);
        CHECK(pvs_vocc_box_hidden(&cell, 1, &o, &empty) == 0);
        o.top = 0.0f;
        CHECK(pvs_vocc_box_hidden(&cell, 1, &o, &far_box) == 0);
    }
}

/* ---- the rebuild: flat and tree walks ---- */

static void test_cull(void) {
    enum { N = 400 };
    static pvs_box boxes[N];
    static pvs_word flat[PVS_BITSET_WORDS(N)], walk[PVS_BITSET_WORDS(N)];
    pvs_virtual_occluder occ[6];
    pvs_box cell = {{-2, 0.5f, -2}, {2, 2, 2}};
    pvs_kdtree *tree = NULL;
    pvs_kdtree_desc kd;
    pvs_error e;
    size_t size;
    void *scratch;
    uint32_t i, k, tighter = 0;
    for (i = 0; i < N; ++i) {
        double x = -60 + rnd() * 120, z = -60 + rnd() * 120, w = 0.2 + rnd() * 6;
        boxes[i].min[0] = (float)x; boxes[i].max[0] = (float)(x + w);
        boxes[i].min[2] = (float)z; boxes[i].max[2] = (float)(z + w);
        boxes[i].min[1] = 0.0f; boxes[i].max[1] = (float)(rnd() * 12);
    }
    boxes[7].min[0] = 1.0f; boxes[7].max[0] = 0.0f; /* empty: never set */
    for (k = 0; k < 6; ++k) { /* a ring of occluders around the cell */
        double a0 = k * 1.047, a1 = a0 + 1.2, r = 9.0;
        occ[k].p0[0] = (float)(r * cos(a0)); occ[k].p0[1] = (float)(r * sin(a0));
        occ[k].p1[0] = (float)(r * cos(a1)); occ[k].p1[1] = (float)(r * sin(a1));
        occ[k].base = 0.0f;
        occ[k].top = 6.0f;
    }
    memset(&kd, 0, sizeof(kd));
    kd.boxes = boxes;
    kd.count = N;
    CHECK(pvs_kdtree_create(&kd, &tree, NULL) == PVS_OK);
    size = pvs_vocc_cull_scratch_size(tree, 6);
    scratch = malloc(size + 8);
    CHECK(pvs_vocc_cull_occluders(&cell, 1, occ, 6, boxes, N, NULL, scratch, size, flat, &e) == PVS_OK);
    CHECK(pvs_vocc_cull_occluders(&cell, 1, occ, 6, boxes, N, tree, (char *)scratch + 8, size, walk, &e) == PVS_ERROR_BUFFER_TOO_SMALL ||
          pvs_vocc_cull_occluders(&cell, 1, occ, 6, boxes, N, tree, scratch, size, walk, &e) == PVS_OK);
    CHECK(pvs_vocc_cull_occluders(&cell, 1, occ, 6, boxes, N, tree, scratch, size, walk, &e) == PVS_OK);
    CHECK(!pvs_bitset_test(flat, 7) && !pvs_bitset_test(walk, 7));
    for (i = 0; i < N; ++i) {
        int by_one = 0;
        for (k = 0; k < 6; ++k) by_one |= pvs_vocc_box_hidden(&cell, 1, occ + k, boxes + i);
        if (i != 7) CHECK(pvs_bitset_test(flat, i) == !by_one);
        if (pvs_bitset_test(walk, i)) CHECK(pvs_bitset_test(flat, i)); /* the walk only ever culls more */
        if (pvs_bitset_test(flat, i) && !pvs_bitset_test(walk, i)) {
            /* culled by the walk through parts behind different occluders: every point is hidden */
            int s, ok = 1;
            ++tighter;
            for (s = 0; s < 300 && ok; ++s) {
                double q[3];
                pvs_box pt;
                box_point(boxes + i, q);
                for (k = 0; k < 3; ++k) pt.min[k] = pt.max[k] = (float)q[k];
                ok = 0;
                for (k = 0; k < 6 && !ok; ++k) ok = pvs_vocc_box_hidden(&cell, 1, occ + k, &pt);
            }
            CHECK(ok);
        }
    }
    CHECK(pvs_bitset_count(flat, N) < N - 20);
    CHECK(pvs_vocc_cull_occluders(&cell, 1, occ, 6, boxes, N, tree, scratch, 16, walk, &e) == PVS_ERROR_BUFFER_TOO_SMALL);
    CHECK(pvs_vocc_cull_occluders(NULL, 1, occ, 6, boxes, N, tree, scratch, size, walk, &e) == PVS_ERROR_INVALID_ARGUMENT);
    (void)tighter;
    free(scratch);
    pvs_kdtree_destroy(tree);
}

/* ---- the bake on a generated city ---- */

static void *bake_file(pvs_scene *s, const pvs_box *cells, uint32_t n, uint32_t only, uint32_t slices, int reverse, size_t *size) {
    pvs_bake_desc bd;
    pvs_bake *b = NULL;
    pvs_error e;
    void *out = NULL;
    uint32_t t;
    test_bake_desc(&bd, s, cells, n, PVS_METHOD_VOCC);
    bd.vocc.only = only;
    bd.vocc.slices = slices;
    if (pvs_bake_begin(&bd, &b, &e) != PVS_OK) { fprintf(stderr, "%s\n", e.message); return NULL; }
    for (t = 0; t < n; ++t) CHECK(pvs_bake_run_task(b, reverse ? n - 1 - t : t, &e) == PVS_OK);
    *size = pvs_bake_file_size(b);
    out = malloc(*size);
    CHECK(pvs_bake_write_file(b, out, *size, size, &e) == PVS_OK);
    pvs_bake_destroy(b);
    return out;
}

static void test_bake(void) {
    gen_params gp;
    mesh m;
    mesh_cells cells;
    pvs_scene *s;
    pvs_file f, fo;
    pvs_error e;
    void *data, *again, *only;
    size_t size, size2, size3;
    uint32_t n, c, i, objects, words, misses = 0, bad_vo = 0, vo_total = 0, diff = 0;
    pvs_word *pvs, *ref, *dec;
    pvs_box *boxes;
    pvs_kdtree *tree = NULL;
    pvs_kdtree_desc kd;
    void *scratch;
    size_t ss;
    double culled = 0.0;
    gp = test_gen_params(GEN_CITY, 2, 0.3f, TEST_FULL ? 24 : 12);
    CHECK(test_generate(&gp, &m, &cells, NULL) == 0);
    s = test_scene(&m, 1);
    CHECK(s != NULL);
    if (!s) return;
    n = cells.count;
    objects = pvs_scene_object_count(s);
    words = (uint32_t)PVS_BITSET_WORDS(objects);
    data = bake_file(s, (const pvs_box *)cells.boxes, n, 0, 0, 0, &size);
    again = bake_file(s, (const pvs_box *)cells.boxes, n, 0, 0, 1, &size2);
    only = bake_file(s, (const pvs_box *)cells.boxes, n, 1, 2, 0, &size3);
    CHECK(data && again && size == size2 && !memcmp(data, again, size)); /* any task order: the same bytes */
    CHECK(pvs_file_open(data, size, &f, &e) == PVS_OK);
    CHECK(f.method == PVS_METHOD_VOCC && (f.vocc_flags & PVS_VOCC_STORED) && !(f.vocc_flags & PVS_VOCC_ONLY));
    CHECK(pvs_file_open(only, size3, &fo, &e) == PVS_OK);
    CHECK((fo.vocc_flags & PVS_VOCC_ONLY) != 0);
    pvs = (pvs_word *)malloc(words * sizeof(pvs_word));
    ref = (pvs_word *)malloc(words * sizeof(pvs_word));
    dec = (pvs_word *)malloc(words * sizeof(pvs_word));
    boxes = (pvs_box *)malloc(objects * sizeof(pvs_box));
    for (i = 0; i < objects; ++i) boxes[i] = pvs_scene_object_box(s, i);
    memset(&kd, 0, sizeof(kd));
    kd.boxes = boxes;
    kd.count = objects;
    CHECK(pvs_kdtree_create(&kd, &tree, NULL) == PVS_OK);
    ss = pvs_vocc_cull_scratch_size(tree, 255);
    scratch = malloc(ss);
    for (c = 0; c < n; ++c) {
        const pvs_box *cell = (const pvs_box *)cells.boxes + c;
        pvs_virtual_occluder vo[255];
        uint32_t k = pvs_file_virtual_occluders(&f, c, vo, 255), j;
        /* every stored occluder (decoded to float, a hair off the stored one) is hidden in 3D */
        for (j = 0; j < k; ++j) {
            int smp, fail = 0;
            for (smp = 0; smp < 160 && !fail; ++smp) {
                double p[3], u = smp == 0 ? 0.0 : smp == 1 ? 1.0 : rnd(), h = rnd();
                float a[3], b[3];
                box_point(cell, p);
                a[0] = (float)p[0]; a[1] = (float)p[1]; a[2] = (float)p[2];
                b[0] = vo[j].p0[0] + (float)u * (vo[j].p1[0] - vo[j].p0[0]);
                b[2] = vo[j].p0[1] + (float)u * (vo[j].p1[1] - vo[j].p0[1]);
                b[1] = vo[j].base + (float)(0.001 + 0.998 * h) * (vo[j].top - vo[j].base);
                if (!pvs_scene_segment_blocked(s, a, b)) fail = 1;
            }
            bad_vo += (uint32_t)fail;
        }
        vo_total += k;
        CHECK(k <= 10);
        /* the rebuilt PVS: the stored one without the tree, tighter or equal with it, 0 misses */
        CHECK(pvs_vocc_cull(&f, c, 0, boxes, objects, NULL, scratch, ss, pvs, &e) == PVS_OK);
        pvs_file_decode(&f, c, dec, words, NULL);
        diff += memcmp(pvs, dec, words * sizeof(pvs_word)) != 0;
        CHECK(pvs_vocc_cull(&f, c, 0, boxes, objects, tree, scratch, ss, pvs, &e) == PVS_OK);
        for (i = 0; i < objects; ++i)
            if (pvs_bitset_test(pvs, i)) CHECK(pvs_bitset_test(dec, i));
        test_sample(s, cell, 16, 1024, 5 + c, 8, 77 + c, ref);
        misses += test_misses(ref, pvs, objects, "vocc bake", c);
        culled += objects - pvs_bitset_count(pvs, objects);
        /* vocc-only: the same occluders, placeholder records (every object) */
        CHECK(pvs_file_vocc_record(&fo, c, NULL, NULL) <= 10);
        pvs_file_decode(&fo, c, dec, words, NULL);
        CHECK(pvs_bitset_count(dec, objects) == objects);
    }
    if (bad_vo || misses || diff) fprintf(stderr, "vocc bake: %u of %u occluders visible, %u misses, %u cells stored != rebuilt\n", bad_vo, vo_total, misses, diff);
    CHECK(bad_vo == 0);
    CHECK(misses == 0);
    CHECK(diff == 0);
    CHECK(vo_total > n);                  /* occluders are found ... */
    CHECK(culled > 0.3 * n * objects);    /* ... and they cull */
    /* errors */
    CHECK(pvs_vocc_cull(&f, n, 0, boxes, objects, tree, scratch, ss, pvs, &e) == PVS_ERROR_INVALID_ARGUMENT);
    CHECK(pvs_vocc_cull(&f, 0, 0, boxes, objects - 1, tree, scratch, ss, pvs, &e) == PVS_ERROR_INVALID_ARGUMENT);
    CHECK(pvs_vocc_cull(&f, 0, 0, boxes, objects, tree, scratch, 8, pvs, &e) == PVS_ERROR_BUFFER_TOO_SMALL);
    {
        pvs_bake_desc bd;
        pvs_bake *b = NULL;
        test_bake_desc(&bd, s, (const pvs_box *)cells.boxes, n, PVS_METHOD_VOCC);
        bd.vocc.slices = 17;
        CHECK(pvs_bake_begin(&bd, &b, &e) == PVS_ERROR_INVALID_ARGUMENT);
        bd.vocc.slices = 0;
        bd.vocc.max_occluders = 256;
        CHECK(pvs_bake_begin(&bd, &b, &e) == PVS_ERROR_INVALID_ARGUMENT);
        CHECK(b == NULL);
        bd.vocc.max_occluders = 0;
        bd.method = PVS_METHOD_OTREE;
        bd.vocc.only = 1; /* needs the vocc method */
        CHECK(pvs_bake_begin(&bd, &b, &e) == PVS_ERROR_INVALID_ARGUMENT);
        bd.method = PVS_METHOD_VOCC;
        bd.vocc.only = 0;
        CHECK(pvs_bake_begin(&bd, &b, &e) == PVS_OK);
        if (b) { /* a vocc bake cannot resume from a PVS: its occluders must be baked */
            pvs_file_decode(&f, 0, dec, words, NULL);
            CHECK(pvs_bake_restore_task(b, 0, dec, words, &e) == PVS_ERROR_UNSUPPORTED);
            pvs_bake_destroy(b);
        }
    }
    { /* AUTO intersects vocc's PVS when the mask names it, and stores no occluders */
        pvs_bake_desc bd;
        pvs_bake *b = NULL;
        pvs_bake_method_info mi;
        test_bake_desc(&bd, s, (const pvs_box *)cells.boxes, n, PVS_METHOD_AUTO);
        bd.methods = 1u << PVS_METHOD_VOCC;
        CHECK(pvs_bake_begin(&bd, &b, &e) == PVS_OK);
        if (b) {
            void *out;
            size_t sz;
            pvs_file fa;
            CHECK(pvs_bake_method_count(b) == 1 && pvs_bake_get_method_info(b, 0, &mi) == PVS_OK && mi.method == PVS_METHOD_VOCC && mi.ran);
            for (c = 0; c < n; ++c) CHECK(pvs_bake_run_task(b, c, &e) == PVS_OK);
            sz = pvs_bake_file_size(b);
            out = malloc(sz);
            CHECK(pvs_bake_write_file(b, out, sz, &sz, &e) == PVS_OK && pvs_file_open(out, sz, &fa, &e) == PVS_OK);
            CHECK(fa.vocc_flags == 0);
            for (c = 0; c < n; ++c) { /* the same PVS as the vocc bake's records */
                pvs_file_decode(&f, c, dec, words, NULL);
                CHECK(memcmp(pvs_bake_cell_pvs(b, c), dec, words * sizeof(pvs_word)) == 0);
            }
            free(out);
            pvs_bake_destroy(b);
        }
        bd.methods = 0; /* left out of AUTO's default candidates */
        CHECK(pvs_bake_begin(&bd, &b, &e) == PVS_OK);
        if (b) {
            uint32_t k;
            for (k = 0; k < pvs_bake_method_count(b); ++k) CHECK(pvs_bake_get_method_info(b, k, &mi) == PVS_OK && mi.method != PVS_METHOD_VOCC);
            pvs_bake_destroy(b);
        }
    }
    CHECK(strcmp(pvs_method_name(PVS_METHOD_VOCC), "vocc") == 0);
    free(scratch);
    pvs_kdtree_destroy(tree);
    free(boxes);
    free(pvs);
    free(ref);
    free(dec);
    free(data);
    free(again);
    free(only);
    pvs_scene_destroy(s);
    mesh_cells_free(&cells);
    mesh_free(&m);
}

/* The same city turned Z-up ((x, y, z) -> (x, -z, y)): ground axes x, y. */
static void test_zup(void) {
    gen_params gp;
    mesh m;
    mesh_cells cells;
    pvs_scene *s;
    pvs_file f;
    pvs_error e;
    pvs_box *cb, *boxes;
    void *data;
    size_t size, ss;
    void *scratch;
    pvs_word *pvs, *ref;
    uint32_t c, i, objects, words, misses = 0, vos = 0;
    double culled = 0.0;
    gp = test_gen_params(GEN_CITY, 3, 0.2f, 10);
    CHECK(test_generate(&gp, &m, &cells, NULL) == 0);
    for (i = 0; i < m.vertex_count; ++i) {
        float y = m.positions[3 * i + 1], z = m.positions[3 * i + 2];
        m.positions[3 * i + 1] = -z;
        m.positions[3 * i + 2] = y;
    }
    cb = (pvs_box *)malloc(cells.count * sizeof(pvs_box));
    for (c = 0; c < cells.count; ++c) {
        const float *b = cells.boxes + 6 * c;
        cb[c].min[0] = b[0]; cb[c].max[0] = b[3];
        cb[c].min[1] = -b[5]; cb[c].max[1] = -b[2];
        cb[c].min[2] = b[1]; cb[c].max[2] = b[4];
    }
    s = test_scene(&m, 2);
    CHECK(s != NULL);
    if (!s) return;
    objects = pvs_scene_object_count(s);
    words = (uint32_t)PVS_BITSET_WORDS(objects);
    data = bake_file(s, cb, cells.count, 0, 3, 0, &size);
    CHECK(data && pvs_file_open(data, size, &f, &e) == PVS_OK && f.up_axis == 2);
    boxes = (pvs_box *)malloc(objects * sizeof(pvs_box));
    for (i = 0; i < objects; ++i) boxes[i] = pvs_scene_object_box(s, i);
    ss = pvs_vocc_cull_scratch_size(NULL, 255);
    scratch = malloc(ss);
    pvs = (pvs_word *)malloc(words * sizeof(pvs_word));
    ref = (pvs_word *)malloc(words * sizeof(pvs_word));
    for (c = 0; c < cells.count; ++c) {
        vos += pvs_file_virtual_occluders(&f, c, NULL, 0);
        CHECK(pvs_vocc_cull(&f, c, 0, boxes, objects, NULL, scratch, ss, pvs, &e) == PVS_OK);
        test_sample(s, cb + c, 16, 1024, 9 + c, 8, 19 + c, ref);
        misses += test_misses(ref, pvs, objects, "vocc z-up", c);
        culled += objects - pvs_bitset_count(pvs, objects);
    }
    CHECK(misses == 0);
    CHECK(vos > 0 && culled > 0.0);
    free(scratch); free(pvs); free(ref); free(boxes); free(data); free(cb);
    pvs_scene_destroy(s);
    mesh_cells_free(&cells);
    mesh_free(&m);
}

/* A scene without walls on the ground: the method says it cannot help. */
static void test_unsupported(void) {
    gen_params gp;
    mesh m;
    mesh_cells cells;
    pvs_scene *s;
    pvs_bake_desc bd;
    pvs_bake *b = NULL;
    pvs_error e;
    gp = test_gen_params(GEN_SOUP, 1, 0.2f, 4);
    CHECK(test_generate(&gp, &m, &cells, NULL) == 0);
    s = test_scene(&m, 1);
    test_bake_desc(&bd, s, (const pvs_box *)cells.boxes, cells.count, PVS_METHOD_VOCC);
    CHECK(pvs_bake_begin(&bd, &b, &e) == PVS_ERROR_UNSUPPORTED);
    CHECK(b == NULL && strstr(e.message, "vertical walls") != NULL);
    pvs_scene_destroy(s);
    mesh_cells_free(&cells);
    mesh_free(&m);
}

/* ---- the VOCC section ---- */

static void test_section(void) {
    enum { CELLS = 20, OBJECTS = 70 };
    static pvs_box boxes[CELLS];
    static pvs_word table[CELLS * PVS_BITSET_WORDS(OBJECTS)];
    static uint8_t counts[CELLS], scales[CELLS], bytes[CELLS * 3 * 5];
    pvs_file_desc d;
    pvs_file f;
    pvs_error e;
    uint8_t *buf, *copy;
    size_t size, plain_size, at = 0, vsz = 0, k;
    uint32_t c, i, n = 0, sections, j;
    for (c = 0; c < CELLS; ++c) {
        for (k = 0; k < 3; ++k) { boxes[c].min[k] = (float)c * 3.0f; boxes[c].max[k] = (float)c * 3.0f + 2.0f; }
        for (i = c; i < OBJECTS; i += 3) pvs_bitset_set(table + c * PVS_BITSET_WORDS(OBJECTS), i);
        counts[c] = (uint8_t)(c % 4);
        scales[c] = (uint8_t)(120 + c);
        for (i = 0; i < counts[c]; ++i, ++n)
            for (k = 0; k < 5; ++k) bytes[5 * n + k] = (uint8_t)(17 * c + 5 * i + 3 * k + 1);
    }
    memset(&d, 0, sizeof(d));
    d.cells = boxes; d.cell_count = CELLS; d.object_count = OBJECTS; d.pvs = table; d.up_axis = 1; d.method = PVS_METHOD_VOCC;
    CHECK(pvs_file_encode(&d, NULL, 0, &plain_size, &e) == PVS_OK);
    d.vocc_counts = counts; d.vocc_scales = scales; d.virtual_occluders = bytes; d.vocc_base = 0.0f; d.vocc_height_step = 0.25f;
    CHECK(pvs_file_encode(&d, NULL, 0, &size, &e) == PVS_OK);
    CHECK(size > plain_size);
    buf = (uint8_t *)malloc(size);
    copy = (uint8_t *)malloc(size);
    CHECK(pvs_file_encode(&d, buf, size, &size, &e) == PVS_OK);
    CHECK(pvs_file_open(buf, size, &f, &e) == PVS_OK);
    CHECK(f.vocc_flags == PVS_VOCC_STORED && f.virtual_occluder_count == n);
    for (c = 0, n = 0; c < CELLS; ++c) { /* round trip */
        const uint8_t *p;
        uint32_t sc, cnt = pvs_file_vocc_record(&f, c, &sc, &p);
        pvs_virtual_occluder vo[4];
        CHECK(cnt == counts[c] && sc == scales[c]);
        CHECK(cnt == 0 || !memcmp(p, bytes + 5 * n, 5 * cnt));
        CHECK(pvs_file_virtual_occluders(&f, c, vo, 4) == cnt);
        for (i = 0; i < cnt; ++i) CHECK(vo[i].base == 0.0f && vo[i].top == 0.25f * bytes[5 * (n + i) + 4]);
        n += cnt;
    }
    /* find the section; every truncated size is rejected, every header field checked */
    sections = (uint32_t)buf[12];
    for (j = 0; j < sections; ++j)
        if (!memcmp(buf + 32 + 16 * j, "VOCC", 4)) {
            at = (size_t)buf[32 + 16 * j + 4] | (size_t)buf[32 + 16 * j + 5] << 8 | (size_t)buf[32 + 16 * j + 6] << 16;
            vsz = (size_t)buf[32 + 16 * j + 8] | (size_t)buf[32 + 16 * j + 9] << 8;
        }
    CHECK(at > 0 && vsz > 16);
    {
        /* unknown flags, a wrong total, a NaN base, a NaN or zero step, block offsets */
        static const size_t offsets[] = {0, 4, 8, 12, 12, 16, 20, 24};
        static const uint32_t values[] = {2, 1000, 0x7fc00000u, 0xffffffffu, 0, 1, 0, 0};
        for (k = 0; k < sizeof(offsets) / sizeof(offsets[0]); ++k) {
            memcpy(copy, buf, size);
            if (k < 5) test_wr32(copy + at + offsets[k], values[k]);
            else copy[at + offsets[k]] ^= 1;
            pvs_fuzz_fix_checksums(copy, size);
            CHECK(pvs_file_open(copy, size, &f, &e) == PVS_ERROR_BAD_SECTION);
        }
        for (k = 0; k + 1 < vsz; k += 7) { /* the section cut short: the file's sizes no longer add up */
            memcpy(copy, buf, size);
            for (j = 0; j < sections; ++j)
                if (!memcmp(copy + 32 + 16 * j, "VOCC", 4)) test_wr32(copy + 32 + 16 * j + 8, (uint32_t)k);
            pvs_fuzz_fix_checksums(copy, size);
            CHECK(pvs_file_open(copy, size, &f, &e) != PVS_OK);
        }
        memcpy(copy, buf, size); /* a count that no longer matches its block */
        copy[at + vsz - 5 * n - 2 * CELLS] ^= 1;
        pvs_fuzz_fix_checksums(copy, size);
        CHECK(pvs_file_open(copy, size, &f, &e) == PVS_ERROR_BAD_SECTION);
        memcpy(copy, buf, size); /* an unknown tag is skipped: the file opens without occluders */
        for (j = 0; j < sections; ++j)
            if (!memcmp(copy + 32 + 16 * j, "VOCC", 4)) copy[32 + 16 * j + 3] = 'X';
        pvs_fuzz_fix_checksums(copy, size);
        CHECK(pvs_file_open(copy, size, &f, &e) == PVS_OK && f.vocc_flags == 0);
        CHECK(pvs_file_virtual_occluders(&f, 0, NULL, 0) == 0);
        {
            pvs_word bits[PVS_BITSET_WORDS(OBJECTS)];
            char scratch[64];
            pvs_box ob[OBJECTS];
            memset(ob, 0, sizeof(ob));
            CHECK(pvs_vocc_cull(&f, 0, 0, ob, OBJECTS, NULL, scratch, sizeof(scratch), bits, &e) == PVS_ERROR_INVALID_ARGUMENT);
        }
    }
    /* encoder input checks */
    d.vocc_height_step = 0.0f;
    CHECK(pvs_file_encode(&d, NULL, 0, &size, &e) == PVS_ERROR_INVALID_ARGUMENT);
    d.vocc_height_step = 1.0f;
    d.vocc_scales = NULL;
    CHECK(pvs_file_encode(&d, NULL, 0, &size, &e) == PVS_ERROR_INVALID_ARGUMENT);
    free(buf);
    free(copy);
}

void test_vocc(void) {
    test_2d_cases();
    test_2d_random();
    test_box_hidden();
    test_cull();
    test_section();
    test_unsupported();
    test_bake();
    test_zup();
}
