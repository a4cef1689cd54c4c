/* test_otree.c - occlusion trees: exact 2D from-region visibility against brute-force 2D ray
   sampling, order independence, closed rings, degenerate inputs; 2.5D c-LSS against 3D ray sampling
   and the bake method. */
#include "../pvs.h"
#include "test.h"
#include "../tools/gen.h"
#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

static uint64_t ot_rng = 0x5eed0ull;
static double rnd(void) { return test_rnd(&ot_rng); }
static float rndf(float lo, float hi) { return test_rndf(&ot_rng, lo, hi); }

/* ---- brute-force 2D reference: rays from sample points of the cell, first segment hit ---- */

/* Ray o + t d (t > 0) against segment s: returns t of the hit or -1. Touching an end counts. */
static double ray_seg(const double o[2], const double d[2], const float *s) {
    double ex = (double)s[2] - s[0], ey = (double)s[3] - s[1];
    double den = d[0] * ey - d[1] * ex;
    double wx = (double)s[0] - o[0], wy = (double)s[1] - o[1];
    double t, u;
    if (den == 0.0) return -1.0;
    t = (wx * ey - wy * ex) / den;
    u = (wx * d[1] - wy * d[0]) / den;
    if (t <= 0.0 || u < 0.0 || u > 1.0) return -1.0;
    return t;
}

/* Marks in `vis` the first segment hit by rays from `points` points of the convex cell (its
   vertices, edge points and interior points) in `dirs` directions each. */
static void ref2d(const float *cell, uint32_t nv, const float *seg, uint32_t ns, const uint8_t *flags, int points, int dirs,
                  unsigned char *vis) {
    int p, k;
    uint32_t i;
    memset(vis, 0, ns);
    for (p = 0; p < points; ++p) {
        double o[2];
        if ((uint32_t)p < nv) {
            o[0] = cell[2 * p]; o[1] = cell[2 * p + 1];
        } else if (p % 2) { /* a point on an edge */
            uint32_t e = (uint32_t)(rnd() * nv) % nv;
            double u = rnd();
            o[0] = cell[2 * e] + u * (cell[2 * ((e + 1) % nv)] - cell[2 * e]);
            o[1] = cell[2 * e + 1] + u * (cell[2 * ((e + 1) % nv) + 1] - cell[2 * e + 1]);
        } else { /* a random convex combination */
            double w = 0, acc[2] = {0, 0};
            for (i = 0; i < nv; ++i) {
                double r = rnd();
                r = r * r * r;
                acc[0] += r * cell[2 * i]; acc[1] += r * cell[2 * i + 1]; w += r;
            }
            o[0] = acc[0] / w; o[1] = acc[1] / w;
        }
        for (k = 0; k < dirs; ++k) {
            double a = 6.283185307179586 * (k + rnd()) / dirs, d[2], best = 1e300;
            uint32_t hit = 0xffffffffu;
            d[0] = cos(a); d[1] = sin(a);
            for (i = 0; i < ns; ++i) {
                double t = ray_seg(o, d, seg + 4 * i);
                if (t > 0.0 && t < best && !(flags && (flags[i] & PVS_SEGMENT_NO_OCCLUSION))) {
                    best = t; hit = i;
                }
            }
            if (hit != 0xffffffffu) vis[hit] = 1;
        }
    }
}

static uint32_t run2d_flags;

/* Runs pvs_visibility_2d and returns the visible flags. */
static int run2d(const float *cell, uint32_t nv, const float *seg, uint32_t ns, unsigned char *vis, pvs_otree_stats *st) {
    pvs_visibility_2d_desc d;
    pvs_word *bits = (pvs_word *)calloc(PVS_BITSET_WORDS(ns) + 1, sizeof(pvs_word));
    pvs_error e;
    pvs_result r;
    uint32_t i;
    memset(&d, 0, sizeof(d));
    d.cell = cell; d.cell_vertex_count = nv;
    d.segments = seg; d.segment_count = ns;
    d.object_count = ns;
    d.flags = run2d_flags;
    r = pvs_visibility_2d(&d, bits, NULL, st, &e);
    if (r != PVS_OK) fprintf(stderr, "pvs_visibility_2d: %s\n", e.message);
    for (i = 0; i < ns; ++i) vis[i] = (unsigned char)pvs_bitset_test(bits, i);
    free(bits);
    return r;
}

/* Compares with the reference: never fewer; `extra` = found but not sampled. */
static void compare2d(const char *name, const float *cell, uint32_t nv, const float *seg, uint32_t ns, int points, int dirs,
                      double max_extra_fraction) {
    unsigned char *ref = (unsigned char *)malloc(ns + 1), *got = (unsigned char *)malloc(ns + 1);
    uint32_t i, miss = 0, extra = 0, nref = 0;
    pvs_otree_stats st;
    CHECK(run2d(cell, nv, seg, ns, got, &st) == PVS_OK);
    ref2d(cell, nv, seg, ns, NULL, points, dirs, ref);
    for (i = 0; i < ns; ++i) {
        nref += ref[i];
        if (ref[i] && !got[i]) {
            ++miss;
            if (miss < 5) fprintf(stderr, "%s: segment %u (%g %g %g %g) sampled visible, otree says hidden\n", name, i, seg[4 * i],
                                  seg[4 * i + 1], seg[4 * i + 2], seg[4 * i + 3]);
        }
        if (got[i] && !ref[i]) ++extra;
    }
    CHECK(miss == 0);
    CHECK(extra <= (uint32_t)(max_extra_fraction * nref) + 2);
    if (extra > (uint32_t)(max_extra_fraction * nref) + 2) fprintf(stderr, "%s: %u sampled visible, %u extra\n", name, nref, extra);
    CHECK(!st.budget_exceeded);
    free(ref);
    free(got);
}

/* Order independence: a permuted copy must give the same visible set. */
static void shuffled2d(const float *cell, uint32_t nv, const float *seg, uint32_t ns) {
    uint32_t *perm = (uint32_t *)malloc(ns * sizeof(uint32_t)), i;
    float *s2 = (float *)malloc(4 * ns * sizeof(float) + 16);
    unsigned char *a = (unsigned char *)malloc(ns + 1), *b = (unsigned char *)malloc(ns + 1);
    uint32_t diff = 0;
    for (i = 0; i < ns; ++i) perm[i] = i;
    for (i = ns; i > 1; --i) {
        uint32_t j = (uint32_t)(rnd() * i) % i, tmp = perm[i - 1];
        perm[i - 1] = perm[j]; perm[j] = tmp;
    }
    for (i = 0; i < ns; ++i) {
        int flip = rnd() < 0.5;
        const float *s = seg + 4 * perm[i];
        s2[4 * i] = flip ? s[2] : s[0]; s2[4 * i + 1] = flip ? s[3] : s[1];
        s2[4 * i + 2] = flip ? s[0] : s[2]; s2[4 * i + 3] = flip ? s[1] : s[3];
    }
    run2d_flags = PVS_VISIBILITY_INPUT_ORDER; /* insert in the given order: exercises the late-nearer re-merge */
    run2d(cell, nv, seg, ns, a, NULL);
    run2d(cell, nv, s2, ns, b, NULL);
    run2d_flags = 0;
    for (i = 0; i < ns; ++i) {
        diff += a[perm[i]] != b[i];
        if (a[perm[i]] != b[i]) fprintf(stderr, "shuffled: segment %u (%g %g %g %g) %d vs %d\n", perm[i], seg[4 * perm[i]], seg[4 * perm[i] + 1],
                                        seg[4 * perm[i] + 2], seg[4 * perm[i] + 3], a[perm[i]], b[i]);
    }
    CHECK(diff == 0);
    if (diff) fprintf(stderr, "shuffled: %u segments differ\n", diff);
    free(perm); free(s2); free(a); free(b);
}

static uint32_t random_segments(float *seg, uint32_t n, float extent, float maxlen) {
    uint32_t i;
    for (i = 0; i < n; ++i) {
        float x = rndf(-extent, extent), y = rndf(-extent, extent), a = rndf(0, 6.2831853f), l = rndf(0.2f, maxlen);
        if (fabsf(x) < 2.5f && fabsf(y) < 2.5f) x += 5.0f; /* keep the cell free */
        seg[4 * i] = x; seg[4 * i + 1] = y;
        seg[4 * i + 2] = x + l * cosf(a); seg[4 * i + 3] = y + l * sinf(a);
    }
    return n;
}

/* Grid ground plan: square blocks (closed rings of 4 segments) with streets between. */
static uint32_t grid_plan(float *seg, int blocks, float block, float street, int jitter) {
    uint32_t n = 0;
    int i, j, k;
    float pitch = block + street, off = -0.5f * blocks * pitch;
    for (i = 0; i < blocks; ++i)
        for (j = 0; j < blocks; ++j) {
            float x0 = off + i * pitch + street * 0.5f, y0 = off + j * pitch + street * 0.5f, x1 = x0 + block, y1 = y0 + block;
            float c[8];
            if (jitter) { x1 -= rndf(0, block * 0.4f); y1 -= rndf(0, block * 0.4f); }
            c[0] = x0; c[1] = y0; c[2] = x1; c[3] = y0; c[4] = x1; c[5] = y1; c[6] = x0; c[7] = y1;
            for (k = 0; k < 4; ++k) {
                seg[4 * n] = c[2 * k]; seg[4 * n + 1] = c[2 * k + 1];
                seg[4 * n + 2] = c[(2 * k + 2) % 8]; seg[4 * n + 3] = c[(2 * k + 3) % 8];
                ++n;
            }
        }
    return n;
}

static void test_2d_random(void) {
    float cell[8] = {-1, -1, 1, -1, 1, 1, -1, 1};
    float seg[4 * 200];
    int rep;
    for (rep = 0; rep < 4; ++rep) {
        uint32_t n = random_segments(seg, 60 + 40 * rep, 12.0f, 4.0f);
        compare2d("random", cell, 4, seg, n, 160, 1500, 0.2);
        shuffled2d(cell, 4, seg, n);
    }
    {   /* a triangle cell, clockwise, off-centre */
        float tri[6] = {3, 3, 4, 5, 5, 3.2f};
        uint32_t n = random_segments(seg, 80, 15.0f, 3.0f);
        uint32_t i, keep = 0;
        for (i = 0; i < n; ++i) { /* drop segments crossing the cell's box */
            float *s = seg + 4 * i;
            if (fminf(s[0], s[2]) < 5.5f && fmaxf(s[0], s[2]) > 2.5f && fminf(s[1], s[3]) < 5.5f && fmaxf(s[1], s[3]) > 2.5f) continue;
            memmove(seg + 4 * keep++, s, 4 * sizeof(float));
        }
        compare2d("triangle", tri, 3, seg, keep, 160, 1500, 0.2);
        shuffled2d(tri, 3, seg, keep);
    }
}

/* Many small scenes inserted in input order, shuffled and with flipped ends: identical sets. */
static void test_2d_order(void) {
    float cell[8] = {-1, -1, 1, -1, 1, 1, -1, 1};
    float seg[4 * 80];
    int rep;
    for (rep = 0; rep < 60; ++rep) {
        uint32_t n = random_segments(seg, 20 + (uint32_t)rep, 12.0f, 4.0f);
        shuffled2d(cell, 4, seg, n);
    }
}

static void test_2d_grid(void) {
    float cell[8] = {-3, -3, 3, -3, 3, 3, -3, 3};
    float seg[4 * 4 * 100];
    uint32_t n = grid_plan(seg, 8, 20.0f, 10.0f, 0);
    compare2d("grid", cell, 4, seg, n, 160, 3000, 0.25);
    shuffled2d(cell, 4, seg, n);
    n = grid_plan(seg, 8, 20.0f, 10.0f, 1);
    compare2d("city plan", cell, 4, seg, n, 160, 3000, 0.25);
    shuffled2d(cell, 4, seg, n);
}

static void test_2d_rings(void) {
    float cell[8] = {-1, -1, 1, -1, 1, 1, -1, 1};
    float seg[4 * 200];
    unsigned char vis[200];
    uint32_t n = 0, i, ring;
    int k, m = 17;
    /* a closed ring of 17 segments around the cell, then objects outside it */
    for (k = 0; k < m; ++k) {
        double a0 = 6.283185307179586 * k / m, a1 = 6.283185307179586 * (k + 1) / m;
        seg[4 * n] = (float)(5 * cos(a0)); seg[4 * n + 1] = (float)(5 * sin(a0));
        seg[4 * n + 2] = (float)(5 * cos(a1)); seg[4 * n + 3] = (float)(5 * sin(a1));
        ++n;
    }
    /* the end points must be shared exactly */
    seg[4 * (m - 1) + 2] = seg[0]; seg[4 * (m - 1) + 3] = seg[1];
    ring = n;
    n += random_segments(seg + 4 * n, 60, 20.0f, 3.0f);
    for (i = ring; i < n; ++i) { /* push everything outside the ring */
        float *s = seg + 4 * i;
        float cx = 0.5f * (s[0] + s[2]), cy = 0.5f * (s[1] + s[3]), r = sqrtf(cx * cx + cy * cy) + 1e-3f;
        float f = r < 9.0f ? (9.0f + r) / r : 1.0f;
        s[0] *= f; s[1] *= f; s[2] *= f; s[3] *= f;
    }
    CHECK(run2d(cell, 4, seg, n, vis, NULL) == PVS_OK);
    for (i = 0; i < ring; ++i) CHECK(vis[i]);
    for (i = ring; i < n; ++i) CHECK(!vis[i]);
    /* the same ring as a square whose corners sit on the lines of the cell's edges */
    {
        float sq[16] = {-4, -1, 4, -1, 4, -1, 4, 4, 4, 4, -4, 4, -4, 4, -4, -1};
        float all[4 * 8];
        memcpy(all, sq, sizeof(sq));
        all[16] = -10; all[17] = 0; all[18] = 10; all[19] = 0;   /* behind? no: crosses the ring - visible */
        all[20] = -10; all[21] = 6; all[22] = 10; all[23] = 6;   /* outside */
        all[24] = 6; all[25] = -0.5f; all[26] = 6; all[27] = 0.5f; /* outside */
        CHECK(run2d(cell, 4, all, 7, vis, NULL) == PVS_OK);
        CHECK(vis[0] && vis[1] && vis[2] && vis[3]);
        CHECK(vis[4]);
        CHECK(!vis[5]);
        CHECK(!vis[6]); /* only visible below y = -1 if the ring were open there: it is (the bottom side is on y = -1) */
    }
}

static void test_2d_degenerate(void) {
    float cell[8] = {-1, -1, 1, -1, 1, 1, -1, 1};
    unsigned char vis[16];
    /* collinear overlapping segments, a zero-length segment, a segment touching the cell, a segment on
       the line of a cell edge, a segment whose line passes through a cell corner */
    float seg[4 * 8] = {
        3, -1.5f, 3, 1.5f, /* 0: wall */
        3, -1, 3, 1,       /* 1: collinear inside 0: ties count visible */
        5, 0, 5, 0,        /* 2: a point */
        1, 0.2f, 2, 0.2f,  /* 3: touches the cell */
        2, -1, 4, -1,      /* 4: on the line of the bottom edge */
        2, 2, 4, 4,        /* 5: its line passes through the corner (1, 1) */
        7, -3, 7, 3,       /* 6: behind the wall partly: visible around it */
        3.5f, -0.5f, 3.5f, 0.5f, /* 7: right behind the wall: hidden */
    };
    pvs_otree_stats st;
    CHECK(run2d(cell, 4, seg, 8, vis, &st) == PVS_OK);
    CHECK(vis[0]); CHECK(vis[1]); CHECK(vis[3]); CHECK(vis[4]); CHECK(vis[5]); CHECK(vis[6]);
    CHECK(!vis[7]);
    compare2d("degenerate", cell, 4, seg, 8, 100, 2000, 1.0);
    shuffled2d(cell, 4, seg, 8);
    /* bad input */
    {
        pvs_visibility_2d_desc d;
        pvs_error e;
        float flat[6] = {0, 0, 1, 1, 2, 2};
        memset(&d, 0, sizeof(d));
        CHECK(pvs_visibility_2d(NULL, NULL, NULL, NULL, &e) == PVS_ERROR_INVALID_ARGUMENT);
        d.cell = flat; d.cell_vertex_count = 3;
        CHECK(pvs_visibility_2d(&d, NULL, NULL, NULL, &e) == PVS_ERROR_BAD_CELL);
    }
}

static void test_2d_budget(void) {
    float cell[8] = {-1, -1, 1, -1, 1, 1, -1, 1};
    float seg[4 * 120];
    uint32_t n = random_segments(seg, 120, 12.0f, 4.0f), i, extra = 0;
    unsigned char full[120], cut[120];
    pvs_visibility_2d_desc d;
    pvs_word bits[2];
    pvs_otree_stats st;
    run2d(cell, 4, seg, n, full, NULL);
    memset(&d, 0, sizeof(d));
    d.cell = cell; d.cell_vertex_count = 4; d.segments = seg; d.segment_count = n;
    d.node_budget = 40;
    CHECK(pvs_visibility_2d(&d, bits, NULL, &st, NULL) == PVS_OK);
    CHECK(st.budget_exceeded == 1);
    for (i = 0; i < n; ++i) {
        cut[i] = (unsigned char)pvs_bitset_test(bits, i);
        CHECK(cut[i] >= full[i]); /* a smaller tree never hides more */
        extra += cut[i] > full[i];
    }
    CHECK(extra > 0);
}

/* ---- 2.5D: c-LSS against 3D ray sampling ---- */

/* Ray o + t d against a vertical wall over segment (x0,y0,x1,y1) from height 0 to top. */
static double ray_wall(const double o[3], const double d[3], const float *w) {
    double o2[2], d2[2], t, hgt, len = sqrt(d[0] * d[0] + d[1] * d[1]);
    if (len == 0.0) return -1.0;
    o2[0] = o[0]; o2[1] = o[1]; d2[0] = d[0] / len; d2[1] = d[1] / len;
    t = ray_seg(o2, d2, w);
    if (t < 0.0) return -1.0;
    t /= len;
    hgt = o[2] + t * d[2];
    return hgt >= 0.0 && hgt <= w[4] ? t : -1.0;
}
static double ray_box(const double o[3], const double d[3], const float *b) {
    double lo[3], hi[3], t0 = 0.0, t1 = 1e300;
    int k;
    lo[0] = b[0]; lo[1] = b[1]; lo[2] = 0.0; hi[0] = b[2]; hi[1] = b[3]; hi[2] = b[4];
    for (k = 0; k < 3; ++k) {
        if (d[k] == 0.0) { if (o[k] < lo[k] || o[k] > hi[k]) return -1.0; continue; }
        {
            double a = (lo[k] - o[k]) / d[k], c = (hi[k] - o[k]) / d[k];
            if (a > c) { double tmp = a; a = c; c = tmp; }
            if (a > t0) t0 = a;
            if (c < t1) t1 = c;
        }
    }
    return t0 <= t1 ? t0 : -1.0;
}

static void ref25(const float cmin[2], const float cmax[2], float ctop, const float *walls, uint32_t nw, const float *objs, uint32_t no,
                  int points, int dirs, unsigned char *vis) {
    int p, k;
    uint32_t i;
    memset(vis, 0, no);
    for (p = 0; p < points; ++p) {
        double o[3];
        o[0] = cmin[0] + (cmax[0] - cmin[0]) * (p < 8 ? (p & 1) : rnd());
        o[1] = cmin[1] + (cmax[1] - cmin[1]) * (p < 8 ? ((p >> 1) & 1) : rnd());
        o[2] = 0.5 + (ctop - 0.5) * (p < 8 ? ((p >> 2) & 1) : rnd());
        for (k = 0; k < dirs; ++k) {
            double z = 1.0 - 2.0 * (k + 0.5) / dirs, r = sqrt(1.0 - z * z), phi = 2.399963229728653 * k + rnd() * 0.01, d[3], wall = 1e300;
            d[0] = r * cos(phi); d[1] = r * sin(phi); d[2] = z;
            for (i = 0; i < nw; ++i) {
                double t = ray_wall(o, d, walls + 5 * i);
                if (t > 0.0 && t < wall) wall = t;
            }
            for (i = 0; i < no; ++i) {
                double t = ray_box(o, d, objs + 5 * i);
                if (t >= 0.0 && t < wall) vis[i] = 1;
            }
        }
    }
}

static void test_25d_random(void) {
    float cmin[2] = {-1, -1}, cmax[2] = {1, 1}, ctop = 2.0f;
    float walls[5 * 80], objs[5 * 120];
    unsigned char ref[120], got[120];
    int rep;
    for (rep = 0; rep < 3; ++rep) {
        uint32_t nw = 0, no = 0, i, miss = 0, extra = 0, nref = 0, in2d = 0;
        pvs_visibility_25d_desc d;
        pvs_word bits[2], bits2d[2];
        pvs_otree_stats st;
        pvs_error e;
        while (nw < 60) {
            float x = rndf(-20, 20), y = rndf(-20, 20), a = rndf(0, 6.2831853f), l = rndf(1, 8);
            float *w = walls + 5 * nw;
            if (fabsf(x) < 10 && fabsf(y) < 10 && rep < 2) x += x < 0 ? -10 : 10;
            w[0] = x; w[1] = y; w[2] = x + l * cosf(a); w[3] = y + l * sinf(a);
            if (fabsf(w[2]) < 2.5f && fabsf(w[3]) < 2.5f) continue;
            if (fabsf(w[0]) < 2.5f && fabsf(w[1]) < 2.5f) continue;
            w[4] = rep == 1 ? rndf(0.5f, 3.0f) : rndf(1.0f, 12.0f);
            ++nw;
        }
        while (no < 120) {
            float x = rndf(-25, 25), y = rndf(-25, 25), sx = rndf(0.1f, 2), sy = rndf(0.1f, 2);
            float *b = objs + 5 * no;
            if (fabsf(x) < 3 && fabsf(y) < 3) continue;
            b[0] = x; b[1] = y; b[2] = x + sx; b[3] = y + sy; b[4] = rndf(0.2f, 16.0f);
            ++no;
        }
        memset(&d, 0, sizeof(d));
        d.cell_min[0] = cmin[0]; d.cell_min[1] = cmin[1]; d.cell_max[0] = cmax[0]; d.cell_max[1] = cmax[1]; d.cell_top = ctop;
        d.facades = walls; d.facade_count = nw; d.objects = objs; d.object_count = no;
        CHECK(pvs_visibility_25d(&d, bits, &st, &e) == PVS_OK);
        ref25(cmin, cmax, ctop, walls, nw, objs, no, 100, 2500, ref);
        for (i = 0; i < no; ++i) {
            got[i] = (unsigned char)pvs_bitset_test(bits, i);
            nref += ref[i];
            if (ref[i] && !got[i]) {
                ++miss;
                fprintf(stderr, "25d rep %d: object %u (%g %g %g %g top %g) sampled visible, c-LSS says hidden\n", rep, i, objs[5 * i],
                        objs[5 * i + 1], objs[5 * i + 2], objs[5 * i + 3], objs[5 * i + 4]);
            }
            extra += got[i] && !ref[i];
        }
        CHECK(miss == 0);
        {   /* the witness lines of the box tests change nothing */
            pvs_word full[2];
            d.flags = PVS_VISIBILITY_25D_FULL_TESTS;
            CHECK(pvs_visibility_25d(&d, full, NULL, &e) == PVS_OK);
            CHECK(memcmp(full, bits, sizeof(full)) == 0);
            d.flags = 0;
        }
        {   /* a tree the caller builds once over pvs_visibility_25d_boxes answers the same; the boxes hold each item's
               ground rectangle and its height from the lowest top */
            pvs_box bx[60 + 120];
            pvs_kdtree_desc kd;
            pvs_kdtree *t = NULL;
            pvs_word tb[2];
            float low = FLT_MAX;
            uint32_t bad = 0;
            for (i = 0; i < nw + no; ++i) low = fminf(low, i < nw ? walls[5 * i + 4] : objs[5 * (i - nw) + 4]);
            pvs_visibility_25d_boxes(walls, nw, objs, no, bx);
            for (i = 0; i < nw + no; ++i) {
                const float *f = i < nw ? walls + 5 * i : objs + 5 * (i - nw);
                bad += bx[i].min[0] != fminf(f[0], f[2]) || bx[i].max[0] != fmaxf(f[0], f[2]);
                bad += bx[i].min[1] != fminf(f[1], f[3]) || bx[i].max[1] != fmaxf(f[1], f[3]);
                bad += bx[i].min[2] != low || bx[i].max[2] != f[4];
            }
            CHECK(bad == 0);
            memset(&kd, 0, sizeof(kd));
            kd.boxes = bx;
            kd.count = nw + no;
            CHECK(pvs_kdtree_create(&kd, &t, &e) == PVS_OK);
            d.tree = t;
            CHECK(pvs_visibility_25d(&d, tb, NULL, &e) == PVS_OK && memcmp(tb, bits, sizeof(tb)) == 0);
            d.tree = NULL;
            pvs_kdtree_destroy(t);
        }
        {   /* a node budget stops insertion: reported, and the set only grows */
            pvs_word cut[2];
            pvs_otree_stats st2;
            d.node_budget = 20;
            CHECK(pvs_visibility_25d(&d, cut, &st2, &e) == PVS_OK);
            CHECK(st2.budget_exceeded == 1);
            for (i = 0; i < no; ++i) CHECK(!pvs_bitset_test(bits, i) || pvs_bitset_test(cut, i));
            d.node_budget = 0;
        }
        /* contains the exact 2D PVS of infinitely tall facades */
        {
            float seg[4 * (80 + 4 * 120)], cell[8] = {-1, -1, 1, -1, 1, 1, -1, 1};
            uint8_t fl[80 + 4 * 120];
            uint32_t ob[80 + 4 * 120], n = 0, k;
            pvs_visibility_2d_desc d2;
            for (i = 0; i < nw; ++i) { memcpy(seg + 4 * n, walls + 5 * i, 4 * sizeof(float)); fl[n] = 0; ob[n] = PVS_NO_OBJECT; ++n; }
            for (i = 0; i < no; ++i) {
                const float *b = objs + 5 * i;
                float c[8];
                c[0] = b[0]; c[1] = b[1]; c[2] = b[2]; c[3] = b[1]; c[4] = b[2]; c[5] = b[3]; c[6] = b[0]; c[7] = b[3];
                for (k = 0; k < 4; ++k) {
                    seg[4 * n] = c[2 * k]; seg[4 * n + 1] = c[2 * k + 1]; seg[4 * n + 2] = c[(2 * k + 2) % 8]; seg[4 * n + 3] = c[(2 * k + 3) % 8];
                    fl[n] = PVS_SEGMENT_NO_OCCLUSION; ob[n] = i; ++n;
                }
            }
            memset(&d2, 0, sizeof(d2));
            d2.cell = cell; d2.cell_vertex_count = 4; d2.segments = seg; d2.segment_count = n; d2.segment_flags = fl;
            d2.segment_objects = ob; d2.object_count = no;
            CHECK(pvs_visibility_2d(&d2, NULL, bits2d, NULL, &e) == PVS_OK);
            for (i = 0; i < no; ++i) {
                in2d += pvs_bitset_test(bits2d, i);
                CHECK(!pvs_bitset_test(bits2d, i) || got[i]);
            }
        }
        fprintf(stderr, "25d rep %d: %u objects, sampled %u, c-LSS %u (+%u), exact 2D %u, nodes %u\n", rep, no, nref, nref + extra, extra,
                in2d, st.nodes);
    }
}

/* ---- the OTREE bake method on a small generated city ---- */

static void test_bake_city(void) {
    gen_params gp;
    mesh m;
    mesh_cells cells;
    pvs_scene *sc;
    pvs_bake_desc bd;
    pvs_bake *b1 = NULL, *b2 = NULL;
    pvs_error e;
    uint32_t c, t, objects, miss = 0;
    size_t n1 = 0, n2 = 0;
    void *f1, *f2;
    pvs_word *bits;
    double sum_pvs = 0, sum_ref = 0;
    gp = test_gen_params(GEN_CITY, 3, 0.3f, 24);
    CHECK(test_generate(&gp, &m, &cells, NULL) == 0);
    sc = test_scene(&m, 1);
    CHECK(sc != NULL);
    if (!sc) return;
    objects = pvs_scene_object_count(sc);
    test_bake_desc(&bd, sc, (const pvs_box *)cells.boxes, cells.count, PVS_METHOD_OTREE);
    CHECK(pvs_bake_begin(&bd, &b1, &e) == PVS_OK);
    CHECK(pvs_bake_begin(&bd, &b2, &e) == PVS_OK);
    CHECK(pvs_bake_method(b1) == PVS_METHOD_OTREE);
    for (t = 0; t < pvs_bake_task_count(b1); ++t) CHECK(pvs_bake_run_task(b1, t, &e) == PVS_OK);
    for (t = pvs_bake_task_count(b2); t-- > 0;) CHECK(pvs_bake_run_task(b2, t, &e) == PVS_OK); /* another order */
    n1 = pvs_bake_file_size(b1);
    n2 = pvs_bake_file_size(b2);
    f1 = malloc(n1);
    f2 = malloc(n2);
    CHECK(pvs_bake_write_file(b1, f1, n1, &n1, &e) == PVS_OK);
    CHECK(pvs_bake_write_file(b2, f2, n2, &n2, &e) == PVS_OK);
    CHECK(n1 == n2 && memcmp(f1, f2, n1) == 0);
    {   /* conservative: nothing the ray sampler sees is missing; the file is not marked approximate */
        pvs_file f;
        CHECK(pvs_file_open(f1, n1, &f, &e) == PVS_OK);
        CHECK(!(f.flags & PVS_FILE_APPROXIMATE) && f.method == PVS_METHOD_OTREE);
    }
    bits = (pvs_word *)calloc(PVS_BITSET_WORDS(objects), sizeof(pvs_word));
    for (c = 0; c < cells.count; ++c) {
        const pvs_word *pvs = pvs_bake_cell_pvs(b1, c);
        test_sample(sc, (const pvs_box *)(cells.boxes + 6 * (size_t)c), 24, 1024, 7 + c, 0, 0, bits);
        miss += test_misses(bits, pvs, objects, "otree bake", c);
        sum_pvs += pvs_bitset_count(pvs, objects);
        sum_ref += pvs_bitset_count(bits, objects);
    }
    CHECK(miss == 0);
    CHECK(sum_pvs < 0.5 * cells.count * objects); /* it does cull */
    {   /* contains the exact 2D ground-plan PVS with the walls made infinitely tall: walls = pairs of
           consecutive triangles standing on y = 0 over one ground segment (the bake's rule, or looser) */
        float *seg = (float *)malloc(((size_t)m.triangle_count + 4 * objects) * 4 * sizeof(float));
        uint8_t *fl = (uint8_t *)malloc((size_t)m.triangle_count + 4 * objects);
        uint32_t *ob = (uint32_t *)malloc(((size_t)m.triangle_count + 4 * objects) * sizeof(uint32_t));
        uint32_t ns = 0, tt, i, k, not_contained = 0;
        pvs_word *vis2d = (pvs_word *)calloc(PVS_BITSET_WORDS(objects), sizeof(pvs_word));
        for (tt = 0; tt + 1 < m.triangle_count; ++tt) {
            float px[2], pz[2], lo = 1e30f;
            int np = 0, ok = 1;
            for (k = 0; k < 6 && ok; ++k) {
                const float *v = m.positions + 3 * (size_t)m.indices[3 * (size_t)tt + k];
                int q;
                if (v[1] < lo) lo = v[1];
                for (q = 0; q < np; ++q) if (px[q] == v[0] && pz[q] == v[2]) break;
                if (q == np) { if (np == 2) ok = 0; else { px[np] = v[0]; pz[np] = v[2]; ++np; } }
            }
            if (!ok || np != 2 || lo > 0.0f) continue;
            seg[4 * ns] = px[0]; seg[4 * ns + 1] = pz[0]; seg[4 * ns + 2] = px[1]; seg[4 * ns + 3] = pz[1];
            fl[ns] = 0; ob[ns] = PVS_NO_OBJECT; ++ns;
            ++tt;
        }
        for (i = 0; i < objects; ++i) {
            pvs_box bx = pvs_scene_object_box(sc, i);
            float cc[8];
            cc[0] = bx.min[0]; cc[1] = bx.min[2]; cc[2] = bx.max[0]; cc[3] = bx.min[2];
            cc[4] = bx.max[0]; cc[5] = bx.max[2]; cc[6] = bx.min[0]; cc[7] = bx.max[2];
            for (k = 0; k < 4; ++k) {
                seg[4 * ns] = cc[2 * k]; seg[4 * ns + 1] = cc[2 * k + 1]; seg[4 * ns + 2] = cc[(2 * k + 2) % 8]; seg[4 * ns + 3] = cc[(2 * k + 3) % 8];
                fl[ns] = PVS_SEGMENT_NO_OCCLUSION; ob[ns] = i; ++ns;
            }
        }
        for (c = 0; c < cells.count; c += 3) {
            const float *cb = cells.boxes + 6 * (size_t)c;
            float poly[8];
            pvs_visibility_2d_desc d2;
            const pvs_word *pvs = pvs_bake_cell_pvs(b1, c);
            poly[0] = cb[0]; poly[1] = cb[2]; poly[2] = cb[3]; poly[3] = cb[2]; poly[4] = cb[3]; poly[5] = cb[5]; poly[6] = cb[0]; poly[7] = cb[5];
            memset(&d2, 0, sizeof(d2));
            d2.cell = poly; d2.cell_vertex_count = 4; d2.segments = seg; d2.segment_count = ns; d2.segment_flags = fl;
            d2.segment_objects = ob; d2.object_count = objects;
            CHECK(pvs_visibility_2d(&d2, NULL, vis2d, NULL, &e) == PVS_OK);
            for (i = 0; i < objects; ++i)
                if (pvs_bitset_test(vis2d, i) && !pvs_bitset_test(pvs, i)) ++not_contained;
        }
        CHECK(not_contained == 0);
        if (not_contained) fprintf(stderr, "otree bake: %u objects of the exact 2D PVS missing\n", not_contained);
        free(seg); free(fl); free(ob); free(vis2d);
    }
    {   /* pvs_bake_desc.otree.node_budget reaches the trees: a small one hides less, never more;
           outside 64..2^24 it is refused */
        pvs_bake *b3 = NULL;
        uint32_t wider = 0, lost = 0, i;
        bd.otree.node_budget = 64;
        CHECK(pvs_bake_begin(&bd, &b3, &e) == PVS_OK);
        for (t = 0; b3 && t < pvs_bake_task_count(b3); ++t) CHECK(pvs_bake_run_task(b3, t, &e) == PVS_OK);
        for (c = 0; b3 && c < cells.count; ++c) {
            const pvs_word *full = pvs_bake_cell_pvs(b1, c), *cut = pvs_bake_cell_pvs(b3, c);
            for (i = 0; i < objects; ++i) {
                lost += pvs_bitset_test(full, i) && !pvs_bitset_test(cut, i);
                wider += pvs_bitset_test(cut, i) && !pvs_bitset_test(full, i);
            }
        }
        CHECK(lost == 0 && wider > 0);
        {   /* the report says where the budget stopped a tree: there, not at the default */
            pvs_bake_report rp;
            pvs_bake_get_report(b3, &rp);
            CHECK(rp.cells == cells.count && rp.cells_otree_budget > 0 && rp.cells_otree_budget <= cells.count);
            CHECK(rp.cells_excluded == 0 && rp.cells_no_occluders == 0); /* a flag of its own */
            pvs_bake_get_report(b1, &rp);
            CHECK(rp.cells_otree_budget == 0);
        }
        pvs_bake_destroy(b3);
        b3 = NULL;
        bd.otree.node_budget = 63;
        CHECK(pvs_bake_begin(&bd, &b3, &e) == PVS_ERROR_INVALID_ARGUMENT && strstr(e.message, "otree.node_budget 63"));
        bd.otree.node_budget = (1u << 24) + 1u;
        CHECK(pvs_bake_begin(&bd, &b3, &e) == PVS_ERROR_INVALID_ARGUMENT);
        bd.otree.node_budget = 0;
    }
    fprintf(stderr, "otree bake: %u cells, %u objects, mean PVS %.1f, mean sampled %.1f\n", cells.count, objects, sum_pvs / cells.count,
            sum_ref / cells.count);
    free(bits);
    free(f1);
    free(f2);
    pvs_bake_destroy(b1);
    pvs_bake_destroy(b2);
    pvs_scene_destroy(sc);
    mesh_cells_free(&cells);
    mesh_free(&m);
}

/* A wall (two triangles standing on the ground), a box behind it, a box beside it, in Y-up and in
   Z-up coordinates: the same PVS. Also a wall that floats (not on the ground) blocks nothing. */
static void add_box(float *pos, uint32_t *vc, uint32_t *idx, uint32_t *tc, const float lo[3], const float hi[3], int zup) {
    static const int f[12][3] = {{0, 1, 3}, {0, 3, 2}, {4, 6, 7}, {4, 7, 5}, {0, 4, 5}, {0, 5, 1},
                                 {2, 3, 7}, {2, 7, 6}, {0, 2, 6}, {0, 6, 4}, {1, 5, 7}, {1, 7, 3}};
    uint32_t base = *vc, i;
    for (i = 0; i < 8; ++i) {
        float p[3];
        p[0] = i & 1 ? hi[0] : lo[0]; p[1] = i & 2 ? hi[1] : lo[1]; p[2] = i & 4 ? hi[2] : lo[2]; /* (u, v, height) */
        pos[3 * *vc] = p[0];
        pos[3 * *vc + 1] = zup ? p[1] : p[2];
        pos[3 * *vc + 2] = zup ? p[2] : p[1];
        ++*vc;
    }
    for (i = 0; i < 12; ++i) {
        idx[3 * *tc] = base + (uint32_t)f[i][0]; idx[3 * *tc + 1] = base + (uint32_t)f[i][1]; idx[3 * *tc + 2] = base + (uint32_t)f[i][2];
        ++*tc;
    }
}
static void add_wall(float *pos, uint32_t *vc, uint32_t *idx, uint32_t *tc, float u0, float v0, float u1, float v1, float base, float top, int zup) {
    float q[4][3] = {{0}};
    uint32_t b = *vc, i;
    q[0][0] = u0; q[0][1] = v0; q[0][2] = base;
    q[1][0] = u1; q[1][1] = v1; q[1][2] = base;
    q[2][0] = u1; q[2][1] = v1; q[2][2] = top;
    q[3][0] = u0; q[3][1] = v0; q[3][2] = top;
    for (i = 0; i < 4; ++i) {
        pos[3 * *vc] = q[i][0];
        pos[3 * *vc + 1] = zup ? q[i][1] : q[i][2];
        pos[3 * *vc + 2] = zup ? q[i][2] : q[i][1];
        ++*vc;
    }
    idx[3 * *tc] = b; idx[3 * *tc + 1] = b + 1; idx[3 * *tc + 2] = b + 2; ++*tc;
    idx[3 * *tc] = b; idx[3 * *tc + 1] = b + 2; idx[3 * *tc + 2] = b + 3; ++*tc;
}
static void test_bake_axes(void) {
    int zup;
    for (zup = 0; zup < 2; ++zup) {
        float pos[3 * 64];
        uint32_t idx[3 * 64], vc = 0, tc = 0, t;
        pvs_object_desc od[5];
        pvs_scene *sc = NULL;
        pvs_bake_desc bd;
        pvs_bake *b = NULL;
        pvs_box cell;
        const pvs_word *pvs;
        float lo[3], hi[3];
        /* object 0: the ground, object 1: a wall at u = 5 (v -10..10, 20 high) */
        lo[0] = -20; lo[1] = -20; lo[2] = 0; hi[0] = 30; hi[1] = 20; hi[2] = 0.01f;
        add_box(pos, &vc, idx, &tc, lo, hi, zup);
        od[0].first_triangle = 0; od[0].triangle_count = tc; od[0].flags = 0;
        add_wall(pos, &vc, idx, &tc, 5, -10, 5, 10, 0, 20, zup);
        od[1].first_triangle = 12; od[1].triangle_count = 2; od[1].flags = 0;
        /* object 2: a box right behind the wall (hidden), object 3: a box beside it (visible) */
        lo[0] = 8; lo[1] = -1; lo[2] = 0; hi[0] = 9; hi[1] = 1; hi[2] = 3;
        add_box(pos, &vc, idx, &tc, lo, hi, zup);
        od[2].first_triangle = 14; od[2].triangle_count = 12; od[2].flags = 0;
        lo[0] = 8; lo[1] = 14; hi[1] = 15;
        add_box(pos, &vc, idx, &tc, lo, hi, zup);
        od[3].first_triangle = 26; od[3].triangle_count = 12; od[3].flags = 0;
        /* object 4: a wall raised off the ground between the cell and a box: blocks nothing here */
        add_wall(pos, &vc, idx, &tc, -5, -10, -5, 10, 1, 20, zup);
        od[4].first_triangle = 38; od[4].triangle_count = 2; od[4].flags = 0;
        sc = test_scene_arrays(pos, vc, idx, tc, od, 5, zup ? 2 : 1);
        CHECK(sc != NULL);
        if (!sc) continue;
        cell.min[0] = -1; cell.max[0] = 1;
        cell.min[zup ? 1 : 2] = -1; cell.max[zup ? 1 : 2] = 1;
        cell.min[zup ? 2 : 1] = 0.5f; cell.max[zup ? 2 : 1] = 2;
        test_bake_desc(&bd, sc, &cell, 1, PVS_METHOD_OTREE);
        CHECK(pvs_bake_begin(&bd, &b, NULL) == PVS_OK);
        for (t = 0; t < pvs_bake_task_count(b); ++t) CHECK(pvs_bake_run_task(b, t, NULL) == PVS_OK);
        pvs = pvs_bake_cell_pvs(b, 0);
        CHECK(pvs && pvs_bitset_test(pvs, 0) && pvs_bitset_test(pvs, 1) && pvs_bitset_test(pvs, 3) && pvs_bitset_test(pvs, 4));
        CHECK(pvs && !pvs_bitset_test(pvs, 2));
        pvs_bake_destroy(b);
        pvs_scene_destroy(sc);
    }
}

/* 2.5D degenerate input: facades touching the cell, on the line of a cell edge, through a corner,
   crossing the cell, zero-length, collinear overlaps; closed rings (buildings) with objects inside.
   Never a miss against 3D ray sampling; a tall closed ring hides what it encloses. */
/* The witness-line shortcut of the box tests (lines remembered in out-leaves) against full
   tests on a city grid: streets give long open lines (witnesses), blocks of walls of random heights
   hide most objects; cells in the streets. */
static void test_25d_shortcuts(void) {
    enum { B = 7, NW = 4 * B * B, NO = B * B + 3 * B * B };
    float *walls = (float *)malloc(5 * NW * sizeof(float)), *objs = (float *)malloc(5 * NO * sizeof(float));
    uint32_t nw = 0, no = 0, i, k, c, differ = 0, seen = 0, total = 0;
    pvs_word full[PVS_BITSET_WORDS(NO)], fast[PVS_BITSET_WORDS(NO)];
    pvs_visibility_25d_desc d;
    pvs_error e;
    for (i = 0; i < B; ++i)
        for (k = 0; k < B; ++k) { /* block (i, k): x 12i .. 12i + 8, y 12k .. 12k + 8, streets 4 wide */
            float x0 = 12.0f * i, y0 = 12.0f * k, x1 = x0 + 8, y1 = y0 + 8, h = rndf(3, 20), q[8];
            uint32_t j;
            q[0] = x0; q[1] = y0; q[2] = x1; q[3] = y0; q[4] = x1; q[5] = y1; q[6] = x0; q[7] = y1;
            for (j = 0; j < 4; ++j) {
                float *w = walls + 5 * nw++;
                w[0] = q[2 * j]; w[1] = q[2 * j + 1]; w[2] = q[(2 * j + 2) % 8]; w[3] = q[(2 * j + 3) % 8]; w[4] = h;
            }
            objs[5 * no] = x0; objs[5 * no + 1] = y0; objs[5 * no + 2] = x1; objs[5 * no + 3] = y1; objs[5 * no + 4] = h; ++no;
            for (j = 0; j < 3; ++j) { /* props in the streets, some taller than the eyes */
                float px = x1 + rndf(0.2f, 3.0f), py = y0 + rndf(0, 10), *o = objs + 5 * no++;
                if (j == 1) { px = x0 + rndf(0, 10); py = y1 + rndf(0.2f, 3.0f); }
                o[0] = px; o[1] = py; o[2] = px + rndf(0.1f, 0.8f); o[3] = py + rndf(0.1f, 0.8f); o[4] = rndf(0.5f, 6.0f);
            }
        }
    memset(&d, 0, sizeof(d));
    d.facades = walls; d.facade_count = nw; d.objects = objs; d.object_count = no;
    for (c = 0; c < 12; ++c) {
        float cx = 12.0f * (float)(c % 6) + 9.0f, cy = 12.0f * (float)(c / 2 % 6) + rndf(0, 8);
        if (c & 1) { float tmp = cx; cx = cy; cy = tmp; }
        d.cell_min[0] = cx; d.cell_min[1] = cy; d.cell_max[0] = cx + 2; d.cell_max[1] = cy + 2; d.cell_top = 2.0f;
        d.flags = 0;
        CHECK(pvs_visibility_25d(&d, fast, NULL, &e) == PVS_OK);
        d.flags = PVS_VISIBILITY_25D_FULL_TESTS;
        CHECK(pvs_visibility_25d(&d, full, NULL, &e) == PVS_OK);
        for (i = 0; i < no; ++i) {
            differ += pvs_bitset_test(fast, i) != pvs_bitset_test(full, i);
            seen += pvs_bitset_test(fast, i);
        }
        total += no;
    }
    fprintf(stderr, "25d shortcuts: %u of %u object tests visible, %u differ from the full tests\n", seen, total, differ);
    CHECK(differ == 0);
    CHECK(seen > 0 && seen < total / 2);
    free(walls);
    free(objs);
}

static void test_25d_degenerate(void) {
    float cmin[2] = {-1, -1}, cmax[2] = {1, 1};
    float walls[5 * 40], objs[5 * 16];
    unsigned char ref[16];
    uint32_t nw = 0, no = 0, i, k;
    pvs_visibility_25d_desc d;
    pvs_word bits[1];
    pvs_error e;
    static const float w0[][5] = {
        {1, 0.5f, 3, 0.5f, 4},     /* touches the cell's right edge */
        {2, -1, 5, -1, 6},         /* on the line of the bottom edge */
        {2, 2, 4, 4, 3},           /* its line passes through the corner (1, 1) */
        {-3, 0, 0, 0, 5},          /* crosses into the cell: ignored */
        {6, 3, 6, 3, 9},           /* zero length */
        {8, -4, 8, 4, 5},          /* two collinear overlapping walls */
        {8, -2, 8, 6, 7},
    };
    for (i = 0; i < sizeof(w0) / sizeof(w0[0]); ++i) memcpy(walls + 5 * nw++, w0[i], sizeof(w0[i]));
    /* a closed ring (building) at x -12..-6, y -3..3, 12 high, with a small object inside */
    {
        float c[8] = {-12, -3, -6, -3, -6, 3, -12, 3};
        for (k = 0; k < 4; ++k) {
            float *w = walls + 5 * nw++;
            w[0] = c[2 * k]; w[1] = c[2 * k + 1]; w[2] = c[(2 * k + 2) % 8]; w[3] = c[(2 * k + 3) % 8]; w[4] = 12;
        }
    }
    {
        static const float o0[][5] = {
            {-10, -1, -8, 1, 6},      /* inside the ring: hidden */
            {10, -1, 11, 1, 4},       /* behind the collinear walls */
            {1.2f, 0.2f, 1.5f, 0.4f, 1}, /* near the touching wall */
            {3, -3, 4, -2, 2},        /* below the bottom-edge wall's line */
            {0.5f, 0.5f, 2, 2, 1},    /* overlaps the cell */
            {12, 12, 13, 13, 30},     /* a tower */
            {-20, -1, -19, 1, 11},    /* behind the ring, lower than it */
            {-20, -1, -19, 1, 40},    /* behind the ring, much taller */
        };
        for (i = 0; i < sizeof(o0) / sizeof(o0[0]); ++i) memcpy(objs + 5 * no++, o0[i], sizeof(o0[i]));
    }
    memset(&d, 0, sizeof(d));
    d.cell_min[0] = cmin[0]; d.cell_min[1] = cmin[1]; d.cell_max[0] = cmax[0]; d.cell_max[1] = cmax[1]; d.cell_top = 2.0f;
    d.facades = walls; d.facade_count = nw; d.objects = objs; d.object_count = no;
    CHECK(pvs_visibility_25d(&d, bits, NULL, &e) == PVS_OK);
    ref25(cmin, cmax, 2.0f, walls, nw, objs, no, 120, 3000, ref);
    for (i = 0; i < no; ++i) {
        if (ref[i] && !pvs_bitset_test(bits, i)) fprintf(stderr, "25d degenerate: object %u sampled visible, c-LSS says hidden\n", i);
        CHECK(!ref[i] || pvs_bitset_test(bits, i));
    }
    CHECK(!pvs_bitset_test(bits, 0)); /* enclosed by a closed ring taller than it */
    CHECK(pvs_bitset_test(bits, 4));  /* overlaps the cell */
    CHECK(pvs_bitset_test(bits, 7));  /* towers over the ring */
    /* bad input */
    CHECK(pvs_visibility_25d(NULL, bits, NULL, &e) == PVS_ERROR_INVALID_ARGUMENT);
    d.flags = 2u;
    CHECK(pvs_visibility_25d(&d, bits, NULL, &e) == PVS_ERROR_INVALID_ARGUMENT && strstr(e.message, "flags"));
    d.flags = 0;
    d.cell_min[0] = 2;
    CHECK(pvs_visibility_25d(&d, bits, NULL, &e) == PVS_ERROR_BAD_CELL);
}

/* ---- from-point culling with the shadow-volume occlusion tree (ch. 4) ---- */

unsigned long otree_cameras, otree_misses; /* totals for tests/verify_otree.c */

/* A test scene: a mesh, its pvs_scene and cells (camera places). */
typedef struct svscene {
    mesh m;
    mesh_cells cells;
    pvs_scene *scene;
} svscene;

static void sv_free(svscene *t) {
    pvs_scene_destroy(t->scene);
    mesh_free(&t->m);
    mesh_cells_free(&t->cells);
    t->scene = NULL;
}
static int sv_gen(svscene *t, gen_kind kind, float size, uint64_t seed) {
    gen_params gp;
    gp = test_gen_params(kind, seed, size, 0);
    if (test_generate(&gp, &t->m, &t->cells, NULL) != 0) return 0;
    t->scene = test_scene(&t->m, 1);
    return t->scene != NULL;
}
/* Random boxes and thin random walls (two triangles) on a ground quad; no cells. */
static int sv_random(svscene *t, uint32_t n) {
    uint32_t i;
    mesh_init(&t->m);
    mesh_cells_init(&t->cells);
    mesh_begin_object(&t->m, "ground", 0, 0);
    mesh_add_vertex(&t->m, -60, 0, -60); mesh_add_vertex(&t->m, 60, 0, -60);
    mesh_add_vertex(&t->m, 60, 0, 60); mesh_add_vertex(&t->m, -60, 0, 60);
    mesh_add_quad(&t->m, 0, 1, 2, 3);
    for (i = 0; i < n; ++i) {
        uint32_t base = t->m.vertex_count;
        char name[32];
        sprintf(name, "o_%u", i);
        mesh_begin_object(&t->m, name, 0, 0);
        if (rnd() < 0.7) {
            float lo[3], hi[3];
            lo[0] = rndf(-50, 48); lo[2] = rndf(-50, 48); lo[1] = rnd() < 0.8 ? 0.0f : rndf(0, 3);
            hi[0] = lo[0] + rndf(0.2f, 8); hi[2] = lo[2] + rndf(0.2f, 8); hi[1] = lo[1] + rndf(0.3f, 12);
            test_mesh_box(&t->m, lo, hi);
        } else { /* a free-standing wall at any angle, maybe tilted */
            float x = rndf(-50, 50), z = rndf(-50, 50), a = rndf(0, 6.283f), l = rndf(1, 12), h0 = rnd() < 0.7 ? 0 : rndf(0, 2);
            float h1 = h0 + rndf(1, 10), dx = l * cosf(a), dz = l * sinf(a), tilt = rnd() < 0.3 ? rndf(-2, 2) : 0;
            mesh_add_vertex(&t->m, x, h0, z); mesh_add_vertex(&t->m, x + dx, h0, z + dz);
            mesh_add_vertex(&t->m, x + dx + tilt, h1, z + dz); mesh_add_vertex(&t->m, x + tilt, h1, z);
            mesh_add_quad(&t->m, base, base + 1, base + 2, base + 3);
        }
    }
    t->scene = test_scene(&t->m, 1);
    return t->scene != NULL;
}

static void sv_camera(const svscene *t, pvs_camera *cam) {
    pvs_box b = pvs_scene_bounds(t->scene);
    int k;
    memset(cam, 0, sizeof(*cam));
    if (t->cells.count && rnd() < 0.8) {
        const float *c = t->cells.boxes + 6 * (uint32_t)(rnd() * t->cells.count);
        for (k = 0; k < 3; ++k) cam->eye[k] = c[k] + (c[3 + k] - c[k]) * (float)rnd();
    } else {
        for (k = 0; k < 3; ++k) cam->eye[k] = rndf(b.min[k], b.max[k]);
        cam->eye[1] = rnd() < 0.7 ? rndf(0.5f, 2.0f) : rndf(b.min[1], b.max[1] + 10);
    }
    if (rnd() < 0.15) { /* degenerate eyes: on a vertex, an edge or the face of a triangle (in occluder planes) */
        uint32_t tri = (uint32_t)(rnd() * t->m.triangle_count) % t->m.triangle_count, mode = (uint32_t)(rnd() * 3);
        const float *p0 = t->m.positions + 3 * t->m.indices[3 * tri], *p1 = t->m.positions + 3 * t->m.indices[3 * tri + 1];
        const float *p2 = t->m.positions + 3 * t->m.indices[3 * tri + 2];
        float w0 = mode == 0 ? 0.0f : (float)rnd(), w1 = mode == 2 ? (float)rnd() * (1 - w0) : 0.0f;
        for (k = 0; k < 3; ++k) cam->eye[k] = p0[k] + w0 * (p1[k] - p0[k]) + w1 * (p2[k] - p0[k]);
    }
    cam->forward[0] = rndf(-1, 1);
    cam->forward[2] = rndf(-1, 1);
    cam->forward[1] = rnd() < 0.1 ? rndf(-1, 1) : rndf(-0.3f, 0.3f);
    if (fabsf(cam->forward[0]) + fabsf(cam->forward[2]) < 0.05f) cam->forward[0] = 1;
    if (rnd() < 0.1) { /* axis-aligned: frustum planes parallel to walls */
        cam->forward[0] = rnd() < 0.5 ? 1.0f : -1.0f; cam->forward[1] = 0; cam->forward[2] = 0;
    }
    cam->up[1] = 1;
    cam->fov_y = rndf(0.5f, 1.8f);
    cam->near_plane = rndf(0.05f, 0.3f);
}

/* One reference ray from the near plane along direction d (forward component 1): the first object
   hit must be set in `vis` (unless it is not a candidate). Returns 1 on a miss. */
static int sv_ray(const svscene *t, const pvs_camera *cam, const double d[3], const pvs_word *vis, const pvs_word *cand, uint32_t *hits) {
    float o[3], df[3];
    pvs_hit hit;
    int k;
    for (k = 0; k < 3; ++k) { df[k] = (float)d[k]; o[k] = (float)(cam->eye[k] + cam->near_plane * d[k]); }
    if (!pvs_scene_raycast(t->scene, o, df, 1e30f, &hit) || hit.object == PVS_NO_OBJECT) return 0;
    if (pvs_scene_object_flags(t->scene, hit.object) & PVS_OBJECT_OCCLUDER_ONLY) return 0;
    ++*hits;
    if (cand && !pvs_bitset_test(cand, hit.object)) return 0;
    if (pvs_bitset_test(vis, hit.object)) return 0;
    fprintf(stderr, "otree cull miss: object %u (%s) from eye (%g %g %g) dir (%g %g %g) fov %g t %g\n", hit.object,
            t->m.objects[hit.object].name, cam->eye[0], cam->eye[1], cam->eye[2], d[0], d[1], d[2], cam->fov_y, hit.t);
    return 1;
}

/* The brute-force reference: rays from the eye through random screen points, and rays aimed at
   random points of random triangles of every object in the frustum (small far objects too). */
static uint32_t sv_check(const svscene *t, const pvs_camera *cam, float aspect, const pvs_word *vis, const pvs_word *cand,
                         uint32_t rays, uint32_t *hits) {
    double f[3], u[3], r[3], sx, sy;
    uint32_t i, misses = 0, n = pvs_scene_object_count(t->scene);
    int k;
    test_camera_frame(cam, aspect, f, u, r, &sx, &sy);
    for (i = 0; i < rays; ++i) {
        double a = (2 * rnd() - 1) * sx, b = (2 * rnd() - 1) * sy, d[3];
        for (k = 0; k < 3; ++k) d[k] = f[k] + a * r[k] + b * u[k];
        misses += (uint32_t)sv_ray(t, cam, d, vis, cand, hits);
    }
    for (i = 0; i < rays; ++i) { /* silhouette probes: just beside a random point of a random triangle's edge */
        uint32_t tri = (uint32_t)(rnd() * t->m.triangle_count) % t->m.triangle_count, e0 = (uint32_t)(rnd() * 3) % 3;
        const float *p0 = t->m.positions + 3 * t->m.indices[3 * tri + e0], *p1 = t->m.positions + 3 * t->m.indices[3 * tri + (e0 + 1) % 3];
        double w = rnd(), q[3], d[3], df, a, b, jit = (rnd() - 0.5) * (rnd() < 0.5 ? 1e-3 : 1e-6);
        for (k = 0; k < 3; ++k) q[k] = p0[k] + w * (p1[k] - p0[k]) - cam->eye[k];
        df = q[0] * f[0] + q[1] * f[1] + q[2] * f[2];
        if (!(df > cam->near_plane * 1.001)) continue;
        a = (q[0] * r[0] + q[1] * r[1] + q[2] * r[2]) / df + jit;
        b = (q[0] * u[0] + q[1] * u[1] + q[2] * u[2]) / df + (rnd() - 0.5) * fabs(jit);
        if (fabs(a) > sx || fabs(b) > sy) continue;
        for (k = 0; k < 3; ++k) d[k] = f[k] + a * r[k] + b * u[k];
        misses += (uint32_t)sv_ray(t, cam, d, vis, cand, hits);
    }
    for (i = 0; i < n; ++i) { /* aimed rays: 3 per object */
        const mesh_object *ob = t->m.objects + i;
        int j;
        if (!ob->triangle_count) continue;
        for (j = 0; j < 3; ++j) {
            uint32_t tri = ob->first_triangle + (uint32_t)(rnd() * ob->triangle_count) % ob->triangle_count;
            const float *p0 = t->m.positions + 3 * t->m.indices[3 * tri], *p1 = t->m.positions + 3 * t->m.indices[3 * tri + 1];
            const float *p2 = t->m.positions + 3 * t->m.indices[3 * tri + 2];
            double w0 = rnd(), w1 = rnd(), q[3], d[3], df, a, b;
            if (w0 + w1 > 1) { w0 = 1 - w0; w1 = 1 - w1; }
            for (k = 0; k < 3; ++k) q[k] = p0[k] + w0 * (p1[k] - p0[k]) + w1 * (p2[k] - p0[k]) - cam->eye[k];
            df = q[0] * f[0] + q[1] * f[1] + q[2] * f[2];
            if (!(df > cam->near_plane * 1.001)) continue;
            a = (q[0] * r[0] + q[1] * r[1] + q[2] * r[2]) / df;
            b = (q[0] * u[0] + q[1] * u[1] + q[2] * u[2]) / df;
            if (fabs(a) > sx || fabs(b) > sy) continue;
            for (k = 0; k < 3; ++k) d[k] = q[k] / df;
            misses += (uint32_t)sv_ray(t, cam, d, vis, cand, hits);
        }
    }
    return misses;
}

/* Random cameras over a scene: the occlusion-tree culler (fresh selection each camera, or the last
   camera's) against the reference, with and without candidates, FME and FMC. */
static void sv_cull_scene(svscene *t, uint32_t cameras, uint32_t rays, const char *label) {
    pvs_otree_desc od;
    pvs_otree *o = NULL, *oc = NULL;
    pvs_error e;
    uint32_t n = pvs_scene_object_count(t->scene), c, misses = 0, hits = 0, culled = 0, i;
    size_t words = PVS_BITSET_WORDS(n);
    pvs_word *vis = (pvs_word *)calloc(words, sizeof(pvs_word)), *cand = (pvs_word *)calloc(words, sizeof(pvs_word));
    memset(&od, 0, sizeof(od));
    od.scene = t->scene;
    od.aspect = 1.5f;
    od.max_occluders = 128;
    CHECK(pvs_otree_create(&od, &o, &e) == PVS_OK);
    od.flags = PVS_OTREE_PLANE_ONLY;
    od.node_budget = 512;
    CHECK(pvs_otree_create(&od, &oc, &e) == PVS_OK);
    if (!o || !oc) return;
    for (c = 0; c < cameras; ++c) {
        pvs_camera cam;
        pvs_cull_params cp;
        pvs_cull_stats st;
        pvs_otree *use = c % 5 == 4 ? oc : o;
        int use_cand = c % 4 == 3;
        sv_camera(t, &cam);
        memset(&cp, 0, sizeof(cp));
        cp.scene_occluders = 16 + (uint32_t)(rnd() * 112);
        cp.occluder_distance = rndf(10, 80);
        if (use_cand) {
            for (i = 0; i < n; ++i) if (rnd() < 0.5) pvs_bitset_set(cand, i); else pvs_bitset_clear(cand, i);
            cp.candidates = cand;
        }
        if (c % 3 != 2) pvs_otree_reset(use);
        CHECK(pvs_otree_cull(use, t->scene, &cam, &cp, vis, &st, &e) == PVS_OK);
        if (c % 3 == 1) CHECK(pvs_otree_cull(use, t->scene, &cam, &cp, vis, &st, &e) == PVS_OK); /* its own selection */
        if (use_cand) for (i = 0; i < words; ++i) CHECK((vis[i] & ~cand[i]) == 0);
        CHECK(st.visible == pvs_bitset_count(vis, n));
        culled += n - st.visible;
        misses += sv_check(t, &cam, 1.5f, vis, use_cand ? cand : NULL, rays, &hits);
    }
    otree_cameras += cameras;
    otree_misses += misses;
    fprintf(stderr, "otree cull %s: %u cameras, %u misses over %u hits, %.1f%% culled\n", label, cameras, misses, hits,
            100.0 * culled / ((double)cameras * n));
    CHECK(misses == 0);
    CHECK(hits > cameras);
    CHECK(culled > 0);
    pvs_otree_destroy(o);
    pvs_otree_destroy(oc);
    free(vis);
    free(cand);
}

/* A recorded walkthrough: hierarchy updating (§4.11.4) gives exactly the bitsets of testing every
   node, frame by frame, with fewer node tests; and no miss against the reference. */
static void sv_walkthrough(svscene *t, uint32_t frames, uint32_t rays, const char *label) {
    pvs_otree_desc od;
    pvs_otree *hu = NULL, *full = NULL;
    pvs_error e;
    uint32_t n = pvs_scene_object_count(t->scene), f, same = 1, misses = 0, hits = 0;
    unsigned long tests_hu = 0, tests_full = 0, skipped = 0;
    size_t words = PVS_BITSET_WORDS(n);
    pvs_word *v1 = (pvs_word *)calloc(words, sizeof(pvs_word)), *v2 = (pvs_word *)calloc(words, sizeof(pvs_word));
    pvs_camera cam;
    float a = 0.0f, step[3] = {0, 0, 0};
    memset(&od, 0, sizeof(od));
    od.scene = t->scene;
    od.aspect = 1.5f;
    CHECK(pvs_otree_create(&od, &hu, &e) == PVS_OK);
    od.flags = PVS_OTREE_NO_COHERENCE;
    CHECK(pvs_otree_create(&od, &full, &e) == PVS_OK);
    if (!hu || !full) return;
    sv_camera(t, &cam);
    cam.fov_y = 1.0f;
    for (f = 0; f < frames; ++f) {
        pvs_cull_params cp;
        pvs_otree_frame fi;
        if (f % 40 == 0) { /* a new leg: a cell to walk from, a heading */
            float h = rndf(0, 6.283f);
            sv_camera(t, &cam);
            cam.fov_y = 1.0f;
            step[0] = 0.4f * cosf(h); step[2] = 0.4f * sinf(h);
            a = h;
        }
        cam.eye[0] += step[0]; cam.eye[2] += step[2];
        a += 0.03f;
        cam.forward[0] = cosf(a); cam.forward[2] = sinf(a); cam.forward[1] = -0.05f;
        memset(&cp, 0, sizeof(cp));
        cp.scene_occluders = 32;
        cp.occluder_distance = 40;
        CHECK(pvs_otree_cull(hu, t->scene, &cam, &cp, v1, NULL, &e) == PVS_OK);
        pvs_otree_get_frame(hu, &fi);
        tests_hu += fi.node_tests;
        skipped += fi.nodes_skipped;
        CHECK(pvs_otree_cull(full, t->scene, &cam, &cp, v2, NULL, &e) == PVS_OK);
        pvs_otree_get_frame(full, &fi);
        tests_full += fi.node_tests;
        same &= memcmp(v1, v2, words * sizeof(pvs_word)) == 0;
        if (f % 4 == 0) misses += sv_check(t, &cam, 1.5f, v1, NULL, rays, &hits);
    }
    fprintf(stderr, "otree walkthrough %s: %u frames, node tests %lu with hierarchy updating, %lu testing every node (%lu skipped), %u misses\n",
            label, frames, tests_hu, tests_full, skipped, misses);
    otree_cameras += frames;
    otree_misses += misses;
    CHECK(same);
    CHECK(skipped > 0 && tests_hu < tests_full);
    CHECK(misses == 0);
    pvs_otree_destroy(hu);
    pvs_otree_destroy(full);
    free(v1);
    free(v2);
}

/* Caller occluders only (random triangles, any order: late nearer ones too) against brute force:
   an object reported hidden has every sampled point of its box blocked by a caller triangle. */
static double sv_ray_tri(const double o[3], const double d[3], const float *p0, const float *p1, const float *p2) {
    double e1[3], e2[3], pv[3], tv[3], qv[3], det, u, v, t;
    int k;
    for (k = 0; k < 3; ++k) { e1[k] = p1[k] - p0[k]; e2[k] = p2[k] - p0[k]; tv[k] = o[k] - p0[k]; }
    pv[0] = d[1] * e2[2] - d[2] * e2[1]; pv[1] = d[2] * e2[0] - d[0] * e2[2]; pv[2] = d[0] * e2[1] - d[1] * e2[0];
    det = e1[0] * pv[0] + e1[1] * pv[1] + e1[2] * pv[2];
    if (fabs(det) < 1e-14) return -1;
    u = (tv[0] * pv[0] + tv[1] * pv[1] + tv[2] * pv[2]) / det;
    if (u < 0 || u > 1) return -1;
    qv[0] = tv[1] * e1[2] - tv[2] * e1[1]; qv[1] = tv[2] * e1[0] - tv[0] * e1[2]; qv[2] = tv[0] * e1[1] - tv[1] * e1[0];
    v = (d[0] * qv[0] + d[1] * qv[1] + d[2] * qv[2]) / det;
    if (v < 0 || u + v > 1) return -1;
    t = (e2[0] * qv[0] + e2[1] * qv[1] + e2[2] * qv[2]) / det;
    return t;
}
static void sv_caller_occluders(uint32_t rounds) {
    svscene t;
    uint32_t rd, bad = 0, hidden = 0, total = 0;
    if (!sv_random(&t, 120)) { CHECK(0); return; }
    for (rd = 0; rd < rounds; ++rd) {
        enum { NT = 60 };
        float tri[NT * 9];
        pvs_otree_desc od;
        pvs_otree *o = NULL;
        pvs_camera cam;
        pvs_cull_params cp;
        uint32_t n = pvs_scene_object_count(t.scene), i, k, j;
        pvs_word *vis = (pvs_word *)calloc(PVS_BITSET_WORDS(n), sizeof(pvs_word));
        double f[3], u[3], r[3], sx, sy;
        memset(&cam, 0, sizeof(cam));
        cam.eye[0] = rndf(-10, 10); cam.eye[1] = rndf(0.5f, 6); cam.eye[2] = rndf(-10, 10);
        cam.forward[0] = rndf(-1, 1); cam.forward[1] = rndf(-0.3f, 0.3f); cam.forward[2] = rndf(-1, 1);
        cam.up[1] = 1;
        cam.fov_y = rndf(0.8f, 2.0f);
        cam.near_plane = 0.1f;
        for (i = 0; i < NT; ++i) { /* big triangles around the eye, some meeting at shared edges or crossing */
            float c[3];
            for (k = 0; k < 3; ++k) c[k] = cam.eye[k] + rndf(-25, 25);
            for (j = 0; j < 3; ++j)
                for (k = 0; k < 3; ++k) tri[9 * i + 3 * j + k] = c[k] + rndf(-12, 12);
            if (i && rnd() < 0.3) { /* share an edge with the previous one */
                memcpy(tri + 9 * i, tri + 9 * (i - 1), 6 * sizeof(float));
            }
        }
        memset(&od, 0, sizeof(od));
        od.scene = t.scene;
        od.node_budget = rd % 4 == 3 ? 200 : 0;
        od.flags = rd % 3 == 2 ? PVS_OTREE_PLANE_ONLY : 0;
        CHECK(pvs_otree_create(&od, &o, NULL) == PVS_OK);
        if (!o) { free(vis); continue; }
        memset(&cp, 0, sizeof(cp));
        cp.occluder_positions = tri;
        cp.occluder_vertex_count = 3 * NT;
        cp.occluder_triangle_count = NT;
        cp.occluder_flags = PVS_CULL_FRUSTUM_ONLY; /* the caller's triangles alone, as the check below */
        CHECK(pvs_otree_cull(o, t.scene, &cam, &cp, vis, NULL, NULL) == PVS_OK);
        test_camera_frame(&cam, 1.0f, f, u, r, &sx, &sy);
        for (i = 0; i < n; ++i) {
            pvs_box b = pvs_scene_object_box(t.scene, i);
            int s;
            ++total;
            if (pvs_bitset_test(vis, i)) continue;
            ++hidden;
            for (s = 0; s < 200; ++s) { /* points of the box in the frustum beyond the near plane must be blocked */
                double q[3], d[3], df, a, bb, tq, best = 1e300, o3[3];
                for (k = 0; k < 3; ++k) q[k] = b.min[k] + (b.max[k] - b.min[k]) * (s < 8 ? (double)((s >> k) & 1) : rnd()) - cam.eye[k];
                df = q[0] * f[0] + q[1] * f[1] + q[2] * f[2];
                if (!(df > cam.near_plane)) continue;
                a = (q[0] * r[0] + q[1] * r[1] + q[2] * r[2]) / df;
                bb = (q[0] * u[0] + q[1] * u[1] + q[2] * u[2]) / df;
                if (fabs(a) > sx || fabs(bb) > sy) continue;
                for (k = 0; k < 3; ++k) { d[k] = q[k] / df; o3[k] = cam.eye[k]; }
                for (j = 0; j < NT; ++j) {
                    double tt = sv_ray_tri(o3, d, tri + 9 * j, tri + 9 * j + 3, tri + 9 * j + 6);
                    if (tt > cam.near_plane && tt < best) best = tt;
                }
                tq = df; /* the point is at t = df along d */
                if (!(best < tq * (1 + 1e-9))) {
                    if (!bad) fprintf(stderr, "otree caller occluders: object %u reported hidden, point t %g unblocked (nearest %g)\n", i, tq, best);
                    ++bad;
                    break;
                }
            }
        }
        pvs_otree_destroy(o);
        free(vis);
    }
    fprintf(stderr, "otree caller occluders: %u rounds, %u of %u objects hidden, %u wrongly\n", rounds, hidden, total, bad);
    CHECK(bad == 0);
    CHECK(hidden > 0);
    sv_free(&t);
}

/* Small exact cases and the API's errors. */
static void sv_basic(void) {
    float pos[3 * 64];
    uint32_t idx[3 * 64], vc = 0, tc = 0;
    pvs_object_desc obd[4];
    pvs_scene *sc = NULL, *big = NULL;
    pvs_otree_desc od;
    pvs_otree *o = NULL;
    pvs_camera cam;
    pvs_cull_params cp;
    pvs_cull_stats st;
    pvs_word vis[1];
    pvs_error e;
    float lo[3], hi[3];
    /* object 0: a wall at x = 5 (z -10..10, 0..20); 1: a box behind it; 2: a box beside it; 3: a
       box behind the wall's shared edge of two walls (fusion) */
    add_wall(pos, &vc, idx, &tc, 5, -3, 5, 0, 0, 4, 0);
    add_wall(pos, &vc, idx, &tc, 5, 0, 5, 3, 0, 4, 0);
    obd[0].first_triangle = 0; obd[0].triangle_count = 4; obd[0].flags = 0;
    lo[0] = 8; lo[1] = -2; lo[2] = 0; hi[0] = 9; hi[1] = 2; hi[2] = 3; /* (u, v, height) */
    add_box(pos, &vc, idx, &tc, lo, hi, 0);
    obd[1].first_triangle = 4; obd[1].triangle_count = 12; obd[1].flags = 0;
    lo[1] = 5; hi[1] = 6;
    add_box(pos, &vc, idx, &tc, lo, hi, 0);
    obd[2].first_triangle = 16; obd[2].triangle_count = 12; obd[2].flags = 0;
    lo[0] = 20; hi[0] = 21; lo[1] = -0.5f; hi[1] = 0.5f;
    add_box(pos, &vc, idx, &tc, lo, hi, 0);
    obd[3].first_triangle = 28; obd[3].triangle_count = 12; obd[3].flags = 0;
    sc = test_scene_arrays(pos, vc, idx, tc, obd, 4, 1);
    CHECK(sc != NULL);
    if (!sc) return;
    memset(&od, 0, sizeof(od));
    od.scene = sc;
    CHECK(pvs_otree_create(&od, &o, &e) == PVS_OK);
    if (!o) { pvs_scene_destroy(sc); return; }
    memset(&cam, 0, sizeof(cam));
    cam.eye[1] = 1.5f;
    cam.forward[0] = 1; cam.up[1] = 1; cam.fov_y = 1.2f; cam.near_plane = 0.1f;
    memset(&cp, 0, sizeof(cp));
    CHECK(pvs_otree_cull(o, sc, &cam, NULL, vis, &st, &e) == PVS_OK); /* a frustum cull */
    CHECK(vis[0] == 0xf);
    cp.scene_occluders = 8;
    cp.occluder_distance = 100; /* the default, a tenth of this 21-unit scene, would not reach the wall */
    CHECK(pvs_otree_cull(o, sc, &cam, &cp, vis, &st, &e) == PVS_OK);
    CHECK(vis[0] == 0x5); /* the wall and the box beside it; both boxes behind the two walls hidden */
    CHECK(st.occluder_triangles == 8); /* the 8 best of the 40 scene triangles */
    {
        pvs_otree_frame fi;
        pvs_otree_get_frame(o, &fi);
        CHECK(fi.fragments >= 2 && fi.tree_nodes >= 5 && fi.node_tests > 0 && !fi.budget_exceeded);
        /* edge marking: the second triangle of each wall adds only its two free edges' planes, the
           two walls share an edge: at most 3 + 2 + 2 + 2 planes (two nodes each) and the root */
        CHECK(fi.tree_nodes <= 1 + 2 * 9);
    }
    cam.forward[0] = -1; /* looking away: only what lies behind the eye's back is culled */
    CHECK(pvs_otree_cull(o, sc, &cam, &cp, vis, &st, &e) == PVS_OK);
    CHECK(vis[0] == 0);
    /* errors */
    cam.forward[0] = 1;
    cam.fov_y = 0; cam.ortho_height = 10;
    CHECK(pvs_otree_cull(o, sc, &cam, &cp, vis, &st, &e) == PVS_ERROR_UNSUPPORTED);
    cam.fov_y = 1.2f; cam.near_plane = 0;
    CHECK(pvs_otree_cull(o, sc, &cam, &cp, vis, &st, &e) == PVS_ERROR_INVALID_ARGUMENT);
    cam.near_plane = 0.1f; cam.eye[0] = NAN;
    CHECK(pvs_otree_cull(o, sc, &cam, &cp, vis, &st, &e) == PVS_ERROR_NOT_FINITE);
    cam.eye[0] = 0;
    CHECK(pvs_otree_cull(o, NULL, &cam, &cp, vis, &st, &e) == PVS_ERROR_INVALID_ARGUMENT);
    CHECK(pvs_otree_cull(o, sc, &cam, &cp, NULL, &st, &e) == PVS_ERROR_INVALID_ARGUMENT);
    {
        svscene t;
        if (sv_random(&t, 30)) {
            pvs_otree *ob = NULL;
            pvs_word *vb = (pvs_word *)calloc(PVS_BITSET_WORDS(pvs_scene_object_count(t.scene)), sizeof(pvs_word));
            big = t.scene;
            CHECK(pvs_otree_cull(o, big, &cam, &cp, vis, &st, &e) == PVS_ERROR_BUFFER_TOO_SMALL);
            /* a context made for the larger scene serves the smaller one too, and back */
            od.scene = big;
            CHECK(pvs_otree_create(&od, &ob, &e) == PVS_OK);
            if (ob) {
                CHECK(pvs_otree_cull(ob, big, &cam, &cp, vb, &st, &e) == PVS_OK);
                CHECK(pvs_otree_cull(ob, sc, &cam, &cp, vis, &st, &e) == PVS_OK);
                CHECK(pvs_otree_cull(ob, sc, &cam, &cp, vis, &st, &e) == PVS_OK); /* the last frame's selection */
                CHECK(vis[0] == 0x5);
                CHECK(pvs_otree_cull(ob, big, &cam, &cp, vb, &st, &e) == PVS_OK);
                pvs_otree_destroy(ob);
            }
            free(vb);
            sv_free(&t);
        }
    }
    memset(&od, 0, sizeof(od));
    CHECK(pvs_otree_create(&od, NULL, &e) == PVS_ERROR_INVALID_ARGUMENT);
    {
        pvs_otree *x = NULL;
        CHECK(pvs_otree_create(&od, &x, &e) == PVS_ERROR_INVALID_ARGUMENT && !x); /* no scene */
        od.scene = sc;
        od.node_budget = 10;
        CHECK(pvs_otree_create(&od, &x, &e) == PVS_ERROR_INVALID_ARGUMENT && !x);
        od.node_budget = 0;
        od.aspect = NAN;
        CHECK(pvs_otree_create(&od, &x, &e) == PVS_ERROR_NOT_FINITE && !x);
    }
    pvs_otree_destroy(NULL);
    pvs_otree_destroy(o);
    pvs_scene_destroy(sc);
}

/* The from-point tests; scale 1 in make test, larger in make verify (tests/verify_otree.c). */
void otree_verify(int scale);
void otree_verify(int scale) {
    svscene t;
    uint32_t cams = 20 * (uint32_t)scale, rays = 300;
    sv_basic();
    sv_caller_occluders(8 * (uint32_t)scale);
    if (sv_random(&t, 150)) sv_cull_scene(&t, cams, rays, "random");
    sv_free(&t);
    if (sv_gen(&t, GEN_CITY, 0.25f, 1 + (uint64_t)scale)) {
        sv_cull_scene(&t, cams, rays, "city");
        sv_walkthrough(&t, 40 * (uint32_t)scale, 200, "city");
    }
    sv_free(&t);
    if (sv_gen(&t, GEN_INDOOR, 0.4f, 3)) {
        sv_cull_scene(&t, cams, rays, "indoor");
        sv_walkthrough(&t, 40 * (uint32_t)scale, 200, "indoor");
    }
    sv_free(&t);
    if (sv_gen(&t, GEN_WALLS, 0.4f, 2)) sv_cull_scene(&t, cams, rays, "walls");
    sv_free(&t);
    if (sv_gen(&t, GEN_SOUP, 0.3f, 4)) sv_cull_scene(&t, cams / 2, rays, "soup");
    sv_free(&t);
    if (sv_gen(&t, GEN_FOREST, 0.2f, 5)) sv_cull_scene(&t, cams / 2, rays, "forest");
    sv_free(&t);
}

/* ---- facades from real-world tessellations, base heights, scenes without facades ---- */

/* A Y-up mesh under construction: (u, v, height) -> (x = u, y = height, z = v). */
typedef struct fx_mesh {
    float pos[3 * 2048];
    uint32_t idx[3 * 2048];
    uint32_t vc, tc;
    pvs_object_desc od[16];
    uint32_t oc;
} fx_mesh;
static uint32_t fx_vertex(fx_mesh *m, float u, float v, float h) {
    m->pos[3 * m->vc] = u; m->pos[3 * m->vc + 1] = h; m->pos[3 * m->vc + 2] = v;
    return m->vc++;
}
static void fx_tri(fx_mesh *m, uint32_t a, uint32_t b, uint32_t c) {
    m->idx[3 * m->tc] = a; m->idx[3 * m->tc + 1] = b; m->idx[3 * m->tc + 2] = c;
    ++m->tc;
}
static void fx_begin(fx_mesh *m) { m->od[m->oc].first_triangle = m->tc; m->od[m->oc].flags = 0; }
static void fx_end(fx_mesh *m) { m->od[m->oc].triangle_count = m->tc - m->od[m->oc].first_triangle; ++m->oc; }
/* a quad of the wall u = wu: v0..v1 x h0..h1, split along one diagonal or the other */
static void fx_quad(fx_mesh *m, float wu, float v0, float v1, float h0, float h1, int flip) {
    uint32_t a = fx_vertex(m, wu, v0, h0), b = fx_vertex(m, wu, v1, h0), c = fx_vertex(m, wu, v1, h1), d = fx_vertex(m, wu, v0, h1);
    if (flip) { fx_tri(m, a, b, d); fx_tri(m, b, c, d); }
    else { fx_tri(m, a, b, c); fx_tri(m, a, c, d); }
}
static void fx_box(fx_mesh *m, float u0, float v0, float h0, float u1, float v1, float h1) {
    float lo[3], hi[3];
    lo[0] = u0; lo[1] = v0; lo[2] = h0; hi[0] = u1; hi[1] = v1; hi[2] = h1;
    fx_begin(m);
    add_box(m->pos, &m->vc, m->idx, &m->tc, lo, hi, 0);
    fx_end(m);
}
/* Bakes the cells with OTREE; checks no object seen by 3D ray sampling is missing; *info. */
static pvs_bake *fx_bake(fx_mesh *m, const pvs_box *cells, uint32_t nc, pvs_otree_bake_info *info, pvs_scene **out_sc) {
    pvs_scene *sc;
    pvs_bake_desc bd;
    pvs_bake *b = NULL;
    uint32_t t, c, miss = 0;
    pvs_word bits[4];
    sc = test_scene_arrays(m->pos, m->vc, m->idx, m->tc, m->od, m->oc, 1);
    CHECK(sc != NULL);
    *out_sc = sc;
    if (!sc) return NULL;
    test_bake_desc(&bd, sc, cells, nc, PVS_METHOD_OTREE);
    CHECK(pvs_bake_begin(&bd, &b, NULL) == PVS_OK);
    if (!b) return NULL;
    for (t = 0; t < pvs_bake_task_count(b); ++t) CHECK(pvs_bake_run_task(b, t, NULL) == PVS_OK);
    pvs_bake_get_otree_info(b, info);
    for (c = 0; c < nc; ++c) {
        test_sample(sc, cells + c, 16, 2048, 11 + c, 0, 0, bits);
        miss += test_misses(bits, pvs_bake_cell_pvs(b, c), m->oc, "otree facades", c);
    }
    CHECK(miss == 0);
    return b;
}
static pvs_box fx_cell(float u0, float v0, float h0, float u1, float v1, float h1) {
    pvs_box c;
    c.min[0] = u0; c.min[1] = h0; c.min[2] = v0;
    c.max[0] = u1; c.max[1] = h1; c.max[2] = v1;
    return c;
}

/* A wall (u = 10, v -20..20, height 0..10) between a cell and a box, tessellated in many ways (a
   grid of N x N quads, either diagonal, a fan around an inner vertex, T-junctions, uneven strips):
   the pieces are merged into one facade, so the box behind is culled as with a single quad, and
   the facade count does not depend on the tessellation. */
static void test_facades_split(void) {
    static fx_mesh m;
    int variant, n;
    uint32_t count1 = 0;
    for (variant = 0; variant < 5; ++variant)
        for (n = 1; n <= 7; n += 3) {
            pvs_otree_bake_info info;
            pvs_scene *sc = NULL;
            pvs_bake *b;
            pvs_box cell = fx_cell(0, -1, 0.5f, 2, 1, 2);
            int i, j;
            memset(&m, 0, sizeof(m));
            fx_box(&m, -20, -30, -0.01f, 40, 30, 0); /* object 0: the ground */
            fx_begin(&m);                            /* object 1: the wall */
            if (variant == 0 || variant == 1) {      /* an n x n grid, one diagonal or alternating */
                for (i = 0; i < n; ++i)
                    for (j = 0; j < n; ++j)
                        fx_quad(&m, 10, -20 + 40.0f * i / n, -20 + 40.0f * (i + 1) / n, 10.0f * j / n, 10.0f * (j + 1) / n,
                                variant == 1 && ((i + j) & 1));
            } else if (variant == 2) {               /* a fan around (v 3, h 4), n pieces per side */
                uint32_t cen = fx_vertex(&m, 10, 3, 4), prev = 0, first = 0;
                int k;
                for (k = 0; k <= 4 * n; ++k) {
                    int sdn = (k / n) % 4, q = k % n;
                    float v = 0, h = 0, f = (float)q / n;
                    uint32_t cur;
                    if (sdn == 0) { v = -20 + 40 * f; h = 0; }
                    else if (sdn == 1) { v = 20; h = 10 * f; }
                    else if (sdn == 2) { v = 20 - 40 * f; h = 10; }
                    else { v = -20; h = 10 - 10 * f; }
                    cur = k == 4 * n ? first : fx_vertex(&m, 10, v, h);
                    if (k == 0) first = cur;
                    else fx_tri(&m, cen, prev, cur);
                    prev = cur;
                }
            } else if (variant == 3) {               /* T-junctions: one quad, beside it n x n quads */
                fx_quad(&m, 10, -20, 0, 0, 10, 0);
                for (i = 0; i < n; ++i)
                    for (j = 0; j < n; ++j) fx_quad(&m, 10, 20.0f * i / n, 20.0f * (i + 1) / n, 10.0f * j / n, 10.0f * (j + 1) / n, 0);
            } else {                                 /* uneven horizontal strips, each split in n columns */
                static const float hs[4] = {0, 3.3f, 7.1f, 10};
                for (j = 0; j < 3; ++j)
                    for (i = 0; i < n; ++i) fx_quad(&m, 10, -20 + 40.0f * i / n, -20 + 40.0f * (i + 1) / n, hs[j], hs[j + 1], i & 1);
            }
            fx_end(&m);
            fx_box(&m, 15, -1, 0, 16, 1, 3);   /* object 2: behind the wall */
            fx_box(&m, 15, 60, 0, 16, 61, 3);  /* object 3: beyond its end, seen */
            b = fx_bake(&m, &cell, 1, &info, &sc);
            if (b) {
                const pvs_word *pvs = pvs_bake_cell_pvs(b, 0);
                CHECK(info.prepared == 1 && info.levels >= 1);
                CHECK(pvs_bitset_test(pvs, 1) && pvs_bitset_test(pvs, 3));
                CHECK(!pvs_bitset_test(pvs, 2));
                pvs_bake_report rep;
                pvs_bake_get_report(b, &rep);
                CHECK(rep.cells_no_occluders == 0);
                if (!count1) count1 = info.facades;
                CHECK(info.facades == count1); /* the wall is one facade however it is cut */
            }
            pvs_bake_destroy(b);
            pvs_scene_destroy(sc);
        }
    CHECK(count1 == 13); /* the ground's and the two boxes' 4 sides each, and the wall */
}

/* A wall with a door (left and right pieces, a lintel over the door): the box seen through the
   door stays visible, the box behind the full-height part is culled. */
static void test_facades_door(void) {
    static fx_mesh m;
    pvs_otree_bake_info info;
    pvs_scene *sc = NULL;
    pvs_bake *b;
    pvs_box cell = fx_cell(0, -1, 0.5f, 2, 1, 2);
    memset(&m, 0, sizeof(m));
    fx_box(&m, -20, -30, -0.01f, 40, 30, 0);
    fx_begin(&m);
    fx_quad(&m, 10, -20, -1, 0, 10, 0);
    fx_quad(&m, 10, 1, 20, 0, 10, 1);
    fx_quad(&m, 10, -1, 1, 2.5f, 10, 0);
    fx_end(&m);
    fx_box(&m, 15, -0.5f, 0, 16, 0.5f, 1); /* object 2: through the door */
    fx_box(&m, 15, 8, 0, 16, 9, 1);        /* object 3: behind the wall */
    b = fx_bake(&m, &cell, 1, &info, &sc);
    if (b) {
        const pvs_word *pvs = pvs_bake_cell_pvs(b, 0);
        CHECK(pvs_bitset_test(pvs, 2));
        CHECK(!pvs_bitset_test(pvs, 3));
    }
    pvs_bake_destroy(b);
    pvs_scene_destroy(sc);
}

/* Base heights: a wall raised to 5..15 (nothing under it) and a low wall 0..3 behind it; a cell
   above the raised wall's base (5.5..7). A box standing at 5 behind the raised wall is hidden by
   it; a box on the ground behind both is seen under the raised wall but hidden by the low one; a
   box on the ground beyond the low wall's end is seen under the raised one. */
static void test_facades_levels(void) {
    static fx_mesh m;
    pvs_otree_bake_info info;
    pvs_scene *sc = NULL;
    pvs_bake *b;
    pvs_box cell = fx_cell(0, -1, 5.5f, 2, 1, 7);
    memset(&m, 0, sizeof(m));
    fx_box(&m, -20, -30, -0.01f, 40, 30, 0);   /* 0: ground */
    fx_begin(&m); fx_quad(&m, 10, -20, 20, 5, 15, 0); fx_end(&m); /* 1: the raised wall */
    fx_begin(&m); fx_quad(&m, 12, -20, 20, 0, 3, 1); fx_end(&m);  /* 2: the low wall */
    fx_box(&m, 15, -1, 5, 16, 1, 6);           /* 3: at the raised wall's base, behind it */
    fx_box(&m, 15, -1, 0, 16, 1, 1);           /* 4: on the ground behind both */
    fx_box(&m, 15, 40, 0, 16, 41, 1);          /* 5: on the ground, far to the side */
    b = fx_bake(&m, &cell, 1, &info, &sc);
    if (b) {
        const pvs_word *pvs = pvs_bake_cell_pvs(b, 0);
        CHECK(info.levels >= 2);
        CHECK(!pvs_bitset_test(pvs, 3));
        CHECK(!pvs_bitset_test(pvs, 4));
        CHECK(pvs_bitset_test(pvs, 1) && pvs_bitset_test(pvs, 2));
    }
    pvs_bake_destroy(b);
    pvs_scene_destroy(sc);
    /* without the low wall, the ground box is seen under the raised one */
    memset(&m, 0, sizeof(m));
    fx_box(&m, -20, -30, -0.01f, 40, 30, 0);
    fx_begin(&m); fx_quad(&m, 10, -20, 20, 5, 15, 0); fx_end(&m);
    fx_box(&m, 15, -1, 5, 16, 1, 6);
    fx_box(&m, 15, -1, 0, 16, 1, 1);
    b = fx_bake(&m, &cell, 1, &info, &sc);
    if (b) {
        const pvs_word *pvs = pvs_bake_cell_pvs(b, 0);
        CHECK(!pvs_bitset_test(pvs, 2));
        CHECK(pvs_bitset_test(pvs, 3));
    }
    pvs_bake_destroy(b);
    pvs_scene_destroy(sc);
}

/* No usable facade (only floating boxes above the cells, and flat ground): the bake says so
   (pvs_bake_get_otree_info: 0 facades) and every drawable object is in every PVS. */
static void test_facades_none(void) {
    static fx_mesh m;
    pvs_otree_bake_info info;
    pvs_scene *sc = NULL;
    pvs_bake *b;
    pvs_box cell = fx_cell(0, -1, 0.5f, 2, 1, 2);
    uint32_t f0, f1, f2;
    memset(&m, 0, sizeof(m));
    fx_begin(&m);
    f0 = fx_vertex(&m, -20, -20, 0); f1 = fx_vertex(&m, 40, -20, 0); f2 = fx_vertex(&m, 40, 20, 0);
    fx_tri(&m, f0, f1, f2);
    fx_end(&m);
    fx_box(&m, 10, -5, 3, 11, 5, 9);
    fx_box(&m, 15, -1, 3, 16, 1, 4);
    b = fx_bake(&m, &cell, 1, &info, &sc);
    if (b) {
        const pvs_word *pvs = pvs_bake_cell_pvs(b, 0);
        pvs_bake_report rep;
        CHECK(info.prepared == 1 && info.facades == 0 && info.vertical_triangles == 16);
        CHECK(pvs_bitset_count(pvs, 3) == 3);
        pvs_bake_get_report(b, &rep); /* the driver's summary hears of it */
        CHECK(rep.cells == 1 && rep.cells_no_occluders == 1);
    }
    pvs_bake_destroy(b);
    pvs_scene_destroy(sc);
    {   /* a bake of another method reports nothing */
        pvs_bake_desc bd;
        pvs_bake *s = NULL;
        memset(&bd, 0, sizeof(bd));
        pvs_bake_get_otree_info(NULL, &info);
        CHECK(info.prepared == 0 && info.facades == 0);
        (void)s;
    }
}

/* AUTO where otree has facades but none for a cell, and extproj culls: a ground quad, a wall standing
   on it, a quad above it, a cell under the ground (below every facade's base) and one above it
   (which puts the wall's facade in use). Otree alone reports the cell under the ground as having no
   occluder (its PVS is every object); AUTO does not, since extproj hides the quad above the ground
   from it and its PVS is not every object. */
static void test_facades_none_auto(void) {
    static fx_mesh m;
    pvs_scene *sc = NULL;
    pvs_box cells[2];
    uint32_t f0, f1, f2, f3, k;
    cells[0] = fx_cell(0, -1, -3, 2, 1, -1.5f);
    cells[1] = fx_cell(20, -1, 0.5f, 22, 1, 2);
    memset(&m, 0, sizeof(m));
    fx_begin(&m); /* the ground, height 0 */
    f0 = fx_vertex(&m, -40, -40, 0); f1 = fx_vertex(&m, 40, -40, 0); f2 = fx_vertex(&m, 40, 40, 0); f3 = fx_vertex(&m, -40, 40, 0);
    fx_tri(&m, f0, f2, f1);
    fx_tri(&m, f0, f3, f2);
    fx_end(&m);
    fx_begin(&m); /* a wall on it: u = 10, v -5..5, height 0..5 */
    f0 = fx_vertex(&m, 10, -5, 0); f1 = fx_vertex(&m, 10, 5, 0); f2 = fx_vertex(&m, 10, 5, 5); f3 = fx_vertex(&m, 10, -5, 5);
    fx_tri(&m, f0, f1, f2);
    fx_tri(&m, f0, f2, f3);
    fx_end(&m);
    fx_begin(&m); /* above the ground, over the cell */
    f0 = fx_vertex(&m, -1, -2, 2); f1 = fx_vertex(&m, 3, -2, 2); f2 = fx_vertex(&m, 3, 2, 2); f3 = fx_vertex(&m, -1, 2, 2);
    fx_tri(&m, f0, f1, f2);
    fx_tri(&m, f0, f2, f3);
    fx_end(&m);
    sc = test_scene_arrays(m.pos, m.vc, m.idx, m.tc, m.od, m.oc, 1);
    CHECK(sc != NULL);
    for (k = 0; k < 2 && sc; ++k) {
        pvs_bake_desc bd;
        pvs_bake *b = NULL;
        pvs_bake_report rep;
        pvs_otree_bake_info info;
        test_bake_desc(&bd, sc, cells, 2, k ? PVS_METHOD_AUTO : PVS_METHOD_OTREE);
        CHECK(pvs_bake_begin(&bd, &b, NULL) == PVS_OK);
        if (!b) continue;
        CHECK(pvs_bake_run_task(b, 0, NULL) == PVS_OK);
        CHECK(pvs_bake_run_task(b, 1, NULL) == PVS_OK);
        pvs_bake_get_report(b, &rep);
        pvs_bake_get_otree_info(b, &info);
        CHECK(info.prepared == 1 && info.facades > 0);
        if (k == 0) { /* otree: nothing for this cell, every object */
            CHECK(pvs_bitset_count(pvs_bake_cell_pvs(b, 0), 3) == 3);
            CHECK(rep.cells_no_occluders == 1 && rep.cells_all_visible == 1);
        } else { /* auto: the quad above the ground is culled */
            const pvs_word *pvs = pvs_bake_cell_pvs(b, 0);
            CHECK(pvs_bitset_test(pvs, 0) && !pvs_bitset_test(pvs, 2));
            CHECK(rep.cells_no_occluders == 0 && rep.cells_all_visible == 0);
        }
        pvs_bake_destroy(b);
    }
    pvs_scene_destroy(sc);
}

/* The default node budget (PVS_OTREE_25D_BUDGET): many small facades at random angles around a cell
   (the brushes of a game map) split the trees past it; the default run stops there as an explicit
   budget of that size does, and twice the budget hides at least as much. */
static void test_25d_default_budget(void) {
    enum { NW = 9000, NO = 400 };
    float *walls = (float *)malloc(5 * NW * sizeof(float)), objs[5 * NO];
    pvs_word def[PVS_BITSET_WORDS(NO)], same[PVS_BITSET_WORDS(NO)], big[PVS_BITSET_WORDS(NO)];
    pvs_visibility_25d_desc d;
    pvs_otree_stats st, st2;
    pvs_error e;
    uint32_t nw = 0, no = 0, i;
    if (!walls) { CHECK(0); return; }
    while (nw < NW) {
        float x = rndf(-60, 60), y = rndf(-60, 60), a = rndf(0, 6.2831853f), l = rndf(0.2f, 1.5f);
        float *w = walls + 5 * nw;
        if (fabsf(x) < 3 && fabsf(y) < 3) continue;
        w[0] = x; w[1] = y; w[2] = x + l * cosf(a); w[3] = y + l * sinf(a); w[4] = rndf(0.1f, 1.2f);
        ++nw;
    }
    while (no < NO) {
        float x = rndf(-70, 70), y = rndf(-70, 70), *b = objs + 5 * no;
        if (fabsf(x) < 4 && fabsf(y) < 4) continue;
        b[0] = x; b[1] = y; b[2] = x + rndf(0.1f, 1); b[3] = y + rndf(0.1f, 1); b[4] = rndf(0.1f, 3.0f);
        ++no;
    }
    memset(&d, 0, sizeof(d));
    d.cell_min[0] = -1; d.cell_min[1] = -1; d.cell_max[0] = 1; d.cell_max[1] = 1; d.cell_top = 1.5f;
    d.facades = walls; d.facade_count = nw; d.objects = objs; d.object_count = no;
    CHECK(pvs_visibility_25d(&d, def, &st, &e) == PVS_OK);
    CHECK(st.budget_exceeded == 1 && st.nodes >= PVS_OTREE_25D_BUDGET && st.nodes < PVS_OTREE_25D_BUDGET + 4096);
    d.node_budget = PVS_OTREE_25D_BUDGET;
    CHECK(pvs_visibility_25d(&d, same, &st2, &e) == PVS_OK);
    CHECK(memcmp(def, same, sizeof(def)) == 0 && st2.nodes == st.nodes);
    d.node_budget = 2 * PVS_OTREE_25D_BUDGET;
    CHECK(pvs_visibility_25d(&d, big, &st2, &e) == PVS_OK);
    CHECK(st2.nodes > st.nodes);
    for (i = 0; i < no; ++i) CHECK(!pvs_bitset_test(big, i) || pvs_bitset_test(def, i));
    fprintf(stderr, "25d default budget: %u facades, %u nodes (%u with twice the budget), %u / %u objects visible\n", nw, st.nodes, st2.nodes,
            pvs_bitset_count(def, no), pvs_bitset_count(big, no));
    free(walls);
}

void test_otree(void);
void test_otree(void) {
    test_25d_default_budget();
    test_facades_split();
    test_facades_door();
    test_facades_levels();
    test_facades_none();
    test_facades_none_auto();
    otree_verify(1);
    test_25d_degenerate();
    test_bake_axes();
    test_bake_city();
    test_25d_random();
    test_25d_shortcuts();
    test_2d_degenerate();
    test_2d_rings();
    test_2d_random();
    test_2d_grid();
    test_2d_budget();
    test_2d_order();
}
