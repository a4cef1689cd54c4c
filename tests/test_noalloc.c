/* test_noalloc.c - a private (PVS_STATIC) copy of the implementation whose PVS_MALLOC counts calls:
   proves that opening, looking up, decoding and walking a file with the cursor, rebuilding a cell's
   PVS from its virtual occluders and per-frame culling with the occlusion tree (pvs_otree_cull)
   allocate nothing. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

static long noalloc_mallocs;
static void *noalloc_malloc(size_t n) { ++noalloc_mallocs; return malloc(n); }
#define PVS_MALLOC(n) noalloc_malloc(n)
#define PVS_FREE(p) free(p)
#define PVS_STATIC
#define PVS_IMPLEMENTATION
#include "../pvs.h"
#include "test.h" /* after pvs.h: its helpers call this copy */

/* A grid of boxes (12 triangles each) and walls; per-frame pvs_otree_cull with every occluder source
   along a walk: no allocation after pvs_otree_create. */
static void noalloc_otree(void) {
    enum { NB = 64 };
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
    uint32_t b, frame, culled = 0, vc = 0, tc = 0;
    for (b = 0; b < NB; ++b) {
        float lo[3], hi[3];
        lo[0] = (float)(b % 8) * 6.0f - 20.0f; lo[1] = 0.0f; lo[2] = (float)(b / 8) * 6.0f - 20.0f;
        hi[0] = lo[0] + 3.0f; hi[1] = 2.0f + (float)(b % 5); hi[2] = lo[2] + 3.0f;
        test_box_arrays(pos, &vc, idx, &tc, lo, hi);
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
        memset(&st, 0, sizeof(st)); /* aarch64 gcc -O1 cannot see it set */
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

/* d's file in a fresh buffer of *size bytes (malloc'd), encoded before the count restarts. */
static uint8_t *noalloc_encode(const pvs_file_desc *d, size_t *size) {
    size_t bound = 0;
    uint8_t *buf;
    CHECK(pvs_file_encode(d, NULL, 0, &bound, NULL) == PVS_OK);
    buf = (uint8_t *)malloc(bound ? bound : 1);
    CHECK(buf && pvs_file_encode(d, buf, bound, size, NULL) == PVS_OK);
    return buf;
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
    size_t size;
    uint32_t c, i, sum = 0;
    for (c = 0; c < CELLS; ++c) {
        int k;
        for (k = 0; k < 3; ++k) { boxes[c].min[k] = (float)c; boxes[c].max[k] = (float)c + 1.0f; }
        for (i = c; i < OBJECTS; i += 1 + c % 7) pvs_bitset_set(pvs + c * PVS_BITSET_WORDS(OBJECTS), i);
    }
    memset(&d, 0, sizeof(d));
    d.cells = boxes; d.cell_count = CELLS; d.object_count = OBJECTS; d.pvs = pvs; d.up_axis = 1;
    buf = noalloc_encode(&d, &size);
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
            pvs_file_get_record_info(&f, c, &info);
            if (info.base != PVS_NO_CELL) CHECK(pvs_cursor_move(&cursor, info.base, NULL, NULL) == PVS_OK);
            CHECK(pvs_cursor_move(&cursor, c, NULL, NULL) == PVS_OK);
        }
        CHECK(cursor.delta_moves > 0);
    }
    CHECK(sum > 0);
    CHECK(noalloc_mallocs == 0);
    free(buf);
    d.flags = PVS_FILE_NO_LOOKUP; /* the same without cell boxes and look-up */
    buf = noalloc_encode(&d, &size);
    noalloc_mallocs = 0;
    CHECK(pvs_file_open(buf, size, &f, &e) == PVS_OK);
    for (c = 0; c < CELLS; ++c) {
        float p[3];
        pvs_box b = pvs_file_cell_box(&f, c);
        p[0] = p[1] = p[2] = (float)c + 0.5f;
        CHECK(pvs_file_find_cell(&f, p) == PVS_NO_CELL && b.min[0] > b.max[0]);
        CHECK(pvs_file_decode(&f, c, bits, PVS_BITSET_WORDS(OBJECTS), &e) == PVS_OK);
        CHECK(memcmp(bits, pvs + c * PVS_BITSET_WORDS(OBJECTS), sizeof(bits)) == 0);
    }
    CHECK(noalloc_mallocs == 0);
    free(buf);
    d.flags = 0;
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
        buf = noalloc_encode(&d, &size);
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

/* ---- bounded time on adversarial input: the fast paths against their brute-force references ----

   This private copy also tests two internals that replaced bounding-box loops and a quadratic walk
   (a fan of long slivers around one vertex made them quadratic): pvs__vx_scan (the occluder
   synthesis visits only the voxels or columns near a triangle or an edge, by slab and row clips)
   against every cell of the bounding box with an exact test, and pvs__ep_walk_loop (extproj's
   boundary loop, through sorted edge ends) against the old walk that searched every unused edge. */

static uint64_t bd_state = 0x5eed0b0d5ull;
static double bd_rnd(void) { return test_rnd(&bd_state); }

typedef struct bd_scan_log {
    uint32_t n[3];
    unsigned char *hit;        /* per cell: visits */
    int outside;
} bd_scan_log;
static void bd_scan_visit(void *user, const uint32_t idx[3]) {
    bd_scan_log *lg = (bd_scan_log *)user;
    int k;
    for (k = 0; k < 3; ++k)
        if (idx[k] >= lg->n[k]) { lg->outside = 1; return; }
    ++lg->hit[idx[0] + (size_t)lg->n[0] * (idx[1] + (size_t)lg->n[1] * idx[2])];
}

/* Does segment p-q meet the 2D box [lo, hi] (axes u, v)? Liang-Barsky in double, exact enough. */
static int bd_segment_box(const double *p, const double *q, int u, int v, const double lo[2], const double hi[2]) {
    double t0 = 0.0, t1 = 1.0, d[2], o[2];
    int k;
    d[0] = q[u] - p[u]; d[1] = q[v] - p[v];
    o[0] = p[u]; o[1] = p[v];
    for (k = 0; k < 2; ++k) {
        if (d[k] == 0.0) {
            if (o[k] < lo[k] || o[k] > hi[k]) return 0;
            continue;
        }
        {
            double a = (lo[k] - o[k]) / d[k], b = (hi[k] - o[k]) / d[k];
            if (a > b) { double x = a; a = b; b = x; }
            if (a > t0) t0 = a;
            if (b < t1) t1 = b;
            if (t0 > t1) return 0;
        }
    }
    return 1;
}
/* Does the triangle projected on (u, v) meet the 2D box? Its edges meet it, or it holds the box's centre. */
static int bd_tri_box2(const double p[3][3], int u, int v, const double lo[2], const double hi[2]) {
    double c[2], s[3];
    int e;
    for (e = 0; e < 3; ++e)
        if (bd_segment_box(p[e], p[(e + 1) % 3], u, v, lo, hi)) return 1;
    c[0] = 0.5 * (lo[0] + hi[0]);
    c[1] = 0.5 * (lo[1] + hi[1]);
    for (e = 0; e < 3; ++e) {
        const double *a = p[e], *b = p[(e + 1) % 3];
        s[e] = (b[u] - a[u]) * (c[1] - a[v]) - (b[v] - a[v]) * (c[0] - a[u]);
    }
    return (s[0] > 0 && s[1] > 0 && s[2] > 0) || (s[0] < 0 && s[1] < 0 && s[2] < 0);
}

static void bd_test_scan(void) {
    int trial, missed = 0, twice = 0, outside = 0;
    size_t visited = 0, boxed = 0;
    for (trial = 0; trial < 3000; ++trial) {
        pvs__vx_grid g;
        bd_scan_log lg;
        uint32_t r0[3], r1[3], a, b, c;
        double p[3][3], m;
        int k, kind = trial % 6, dims = trial % 3 == 0 ? 2 : 3, npts = trial % 7 == 0 && dims == 2 ? 2 : 3, axes[3], up = trial % 2 ? 1 : 2;
        size_t cells;
        g.h = 0.1 + 2.0 * bd_rnd();
        for (k = 0; k < 3; ++k) {
            g.origin[k] = -20.0 + 10.0 * bd_rnd();
            g.n[k] = 4 + (uint32_t)(26 * bd_rnd());
        }
        m = bd_rnd() < 0.2 ? 0.0 : g.h * bd_rnd();
        for (k = 0; k < 3; ++k) {
            double lo = g.origin[k] - 2.0, span = g.n[k] * g.h + 4.0;
            p[0][k] = lo + span * bd_rnd();
            p[1][k] = kind == 1 ? p[0][k] + 1e-3 * bd_rnd() : lo + span * bd_rnd();  /* a sliver */
            p[2][k] = kind == 4 ? p[0][k] + 1e-4 * g.h * bd_rnd() : lo + span * bd_rnd(); /* tiny or degenerate */
        }
        if (kind == 2) p[2][0] = p[1][0], p[2][2 - (trial % 2)] = p[1][2 - (trial % 2)]; /* vertical or axis-aligned */
        if (kind == 3) for (k = 0; k < 3; ++k) p[1][k] = p[0][k] + 0.5 * (p[2][k] - p[0][k]); /* collinear */
        if (kind == 5) for (k = 0; k < 3; ++k) p[1][k] = p[0][k], p[2][k] = p[0][k]; /* a point */
        for (k = 0; k < 3; ++k) {
            r0[k] = (uint32_t)(g.n[k] * 0.3 * bd_rnd());
            r1[k] = g.n[k] - 1 - (uint32_t)(g.n[k] * 0.3 * bd_rnd());
        }
        axes[0] = up == 1 ? 0 : 0; axes[1] = up == 1 ? 2 : 1; axes[2] = up;
        if (dims == 3) { axes[0] = 0; axes[1] = 1; axes[2] = 2; }
        if (dims == 2) r0[up] = r1[up] = 0;
        cells = (size_t)g.n[0] * g.n[1] * g.n[2];
        memset(&lg, 0, sizeof(lg));
        memcpy(lg.n, g.n, sizeof(lg.n));
        lg.hit = (unsigned char *)calloc(cells, 1);
        pvs__vx_scan(&g, p[0], npts, axes, dims, m, r0, r1, bd_scan_visit, &lg);
        outside |= lg.outside;
        for (c = r0[2]; c <= r1[2]; ++c)
            for (b = r0[1]; b <= r1[1]; ++b)
                for (a = r0[0]; a <= r1[0]; ++a) {
                    size_t x = a + (size_t)g.n[0] * (b + (size_t)g.n[1] * c);
                    uint32_t idx[3];
                    int need;
                    idx[0] = a; idx[1] = b; idx[2] = c;
                    if (dims == 3) {
                        double cc[3];
                        for (k = 0; k < 3; ++k) cc[k] = g.origin[k] + (idx[k] + 0.5) * g.h;
                        need = npts == 3 ? pvs__tri_box(cc, 0.5 * g.h + m, p[0], p[1], p[2]) : 0;
                    } else {
                        double lo[2], hi[2];
                        lo[0] = g.origin[axes[0]] + idx[axes[0]] * g.h - m; hi[0] = lo[0] + g.h + 2 * m;
                        lo[1] = g.origin[axes[1]] + idx[axes[1]] * g.h - m; hi[1] = lo[1] + g.h + 2 * m;
                        need = npts == 3 ? bd_tri_box2((const double(*)[3])p, axes[0], axes[1], lo, hi)
                                         : bd_segment_box(p[0], p[1], axes[0], axes[1], lo, hi);
                    }
                    ++boxed;
                    if (need && !lg.hit[x]) ++missed;
                }
        for (a = 0; a < cells; ++a) {
            twice += lg.hit[a] > 1;
            visited += lg.hit[a];
            if (lg.hit[a]) { /* within the ranges */
                uint32_t i0 = a % g.n[0], i1 = (a / g.n[0]) % g.n[1], i2 = a / (g.n[0] * g.n[1]);
                if (i0 < r0[0] || i0 > r1[0] || i1 < r0[1] || i1 > r1[1] || i2 < r0[2] || i2 > r1[2]) outside = 1;
            }
        }
        free(lg.hit);
    }
    CHECK(missed == 0);
    CHECK(twice == 0);
    CHECK(outside == 0);
    CHECK(visited * 4 < boxed); /* the point of it: far fewer than the bounding boxes' cells */
    fprintf(stderr, "  voxel scan: %zu cells visited where the bounding boxes hold %zu, none missed\n", visited, boxed);
}

/* The walk before pvs__ep_walk_loop: every step searched the unused edges (quadratic). */
static int bd_old_walk(pvs__epedge2 *e, uint32_t nb, float *q) {
    float cur[2];
    uint32_t n, m;
    q[0] = e[0].a[0]; q[1] = e[0].a[1];
    cur[0] = e[0].b[0]; cur[1] = e[0].b[1];
    n = 1;
    for (m = 1; m < nb; ++m) {
        uint32_t found = nb, k;
        int end = 0;
        pvs__epedge2 tmp;
        q[2 * n] = cur[0];
        q[2 * n + 1] = cur[1];
        ++n;
        for (k = m; k < nb; ++k) {
            int ea = pvs__fpoint_cmp(e[k].a, cur, 2) == 0, eb = pvs__fpoint_cmp(e[k].b, cur, 2) == 0;
            if (!ea && !eb) continue;
            if (found != nb) return 0;
            found = k;
            end = ea;
        }
        if (found == nb) return 0;
        cur[0] = end ? e[found].b[0] : e[found].a[0];
        cur[1] = end ? e[found].b[1] : e[found].a[1];
        tmp = e[m];
        e[m] = e[found];
        e[found] = tmp;
    }
    return pvs__fpoint_cmp(cur, q, 2) == 0;
}

static void bd_test_walk(void) {
    enum { MAXE = 600 };
    static pvs__epedge2 e[MAXE], e2[MAXE];
    static pvs__epend ends[2 * MAXE];
    static float q1[2 * MAXE + 2], q2[2 * MAXE + 2], pts[2 * MAXE];
    int trial, agree = 0, ok = 0;
    for (trial = 0; trial < 2000; ++trial) {
        uint32_t n = 3 + (uint32_t)(bd_rnd() * (trial % 10 == 0 ? 500 : 30)), nb = 0, i, kind = (uint32_t)trial % 7;
        int r1, r2, same = 1;
        for (i = 0; i < n; ++i) { /* a star polygon: simple, any turns */
            double a = 6.283185307179586 * (i + 0.5 * bd_rnd()) / n, r = 1.0 + 9.0 * bd_rnd();
            pts[2 * i] = (float)(r * cos(a));
            pts[2 * i + 1] = (float)(r * sin(a));
        }
        for (i = 0; i < n; ++i) {
            const float *p0 = pts + 2 * i, *p1 = pts + 2 * ((i + 1) % n);
            if (kind == 1 && i == n / 2) continue;                       /* a loose end */
            if (kind == 2 && i + 1 == n) p1 = pts + 2 * (n / 2);         /* a point on three edges */
            if (pvs__fpoint_cmp(p0, p1, 2) <= 0) { memcpy(e[nb].a, p0, 8); memcpy(e[nb].b, p1, 8); }
            else { memcpy(e[nb].a, p1, 8); memcpy(e[nb].b, p0, 8); }
            e[nb++].tri = i;
        }
        if (kind == 3 && n >= 6) { /* two loops: a triangle of its own */
            float t[3][2] = {{20, 20}, {21, 20}, {20, 22}};
            for (i = 0; i < 3; ++i) {
                const float *p0 = t[i], *p1 = t[(i + 1) % 3];
                if (pvs__fpoint_cmp(p0, p1, 2) <= 0) { memcpy(e[nb].a, p0, 8); memcpy(e[nb].b, p1, 8); }
                else { memcpy(e[nb].a, p1, 8); memcpy(e[nb].b, p0, 8); }
                e[nb++].tri = 0;
            }
        }
        if (kind == 4) { memcpy(e[nb].a, pts, 8); memcpy(e[nb].b, pts, 8); ++nb; } /* a zero-length edge */
        for (i = nb; i > 1; --i) { /* shuffled, as the sort of the caller leaves them in any order */
            uint32_t j = (uint32_t)(bd_rnd() * i);
            pvs__epedge2 t = e[i - 1];
            e[i - 1] = e[j];
            e[j] = t;
        }
        memcpy(e2, e, nb * sizeof(e[0]));
        if (kind == 4) { /* pvs__ep_sheet_polygon drops zero-length edges before the walk (the old
                            walk took them only when it happened to reach them last) */
            uint32_t w = 0;
            for (i = 0; i < nb; ++i)
                if (pvs__fpoint_cmp(e[i].a, e[i].b, 2) != 0) e[w++] = e[i];
            nb = w;
            memcpy(e2, e, nb * sizeof(e[0]));
        }
        r1 = pvs__ep_walk_loop(e, nb, q1, ends);
        r2 = bd_old_walk(e2, nb, q2);
        if (r1 && r2) same = memcmp(q1, q2, 2 * nb * sizeof(float)) == 0;
        agree += r1 == r2 && same;
        ok += r1;
    }
    CHECK(agree == 2000);
    CHECK(ok > 500 && ok < 1800);
    { /* big loops (the 100,000-sided polygon of the issue, smaller): a square of 20,000 rim points
         (collinear ones dropped: 4 corners, with or without the hull), and a circle of as many,
         whose hull the caller would not take (more than PVS__EP_MAXP points: refused early) */
        enum { N = 20000 };
        pvs__epedge2 *big = (pvs__epedge2 *)malloc(6 * N * sizeof(pvs__epedge2));
        float *q = (float *)malloc(2 * (3 * N + 1) * sizeof(float));
        unsigned char *keep = (unsigned char *)malloc(3 * N + 1);
        pvs__epend *be = (pvs__epend *)malloc(6 * N * sizeof(pvs__epend));
        double (*hp)[2] = (double(*)[2])malloc((3 * N + 1) * sizeof(double[2]));
        double (*hh)[2] = (double(*)[2])malloc((3 * N + 1) * sizeof(double[2]));
        int shape;
        for (shape = 0; shape < 2; ++shape) {
            double area = 0.0, dent = 0.0;
            uint32_t i, ne = 0, k;
            for (i = 0; i < N; ++i) { /* a fan: centre, rim i, rim i + 1 */
                float c[2] = {0, 0}, p[2][2], *tri[3];
                uint32_t j;
                for (j = 0; j < 2; ++j) {
                    uint32_t r = (i + j) % N, side = r / (N / 4), at = r % (N / 4);
                    float t = -50.0f + 100.0f * (float)at / (float)(N / 4);
                    double a = 6.283185307179586 * r / N;
                    if (shape == 1) { p[j][0] = (float)(50 * cos(a)); p[j][1] = (float)(50 * sin(a)); }
                    else if (side == 0) { p[j][0] = t; p[j][1] = -50; }
                    else if (side == 1) { p[j][0] = 50; p[j][1] = t; }
                    else if (side == 2) { p[j][0] = -t; p[j][1] = 50; }
                    else { p[j][0] = -50; p[j][1] = -t; }
                }
                tri[0] = c; tri[1] = p[0]; tri[2] = p[1];
                area += 0.5 * ((double)p[0][0] * p[1][1] - (double)p[1][0] * p[0][1]);
                for (k = 0; k < 3; ++k) {
                    const float *x = tri[k], *y = tri[(k + 1) % 3];
                    if (pvs__fpoint_cmp(x, y, 2) <= 0) { memcpy(big[ne].a, x, 8); memcpy(big[ne].b, y, 8); }
                    else { memcpy(big[ne].a, y, 8); memcpy(big[ne].b, x, 8); }
                    big[ne++].tri = i;
                }
            }
            memcpy(big + ne, big, ne * sizeof(pvs__epedge2)); /* the call sorts and compacts its edges */
            if (shape == 0) {
                CHECK(pvs__ep_sheet_polygon(big, ne, area, q, keep, ne, be, 0.0, NULL, NULL, 0, NULL) == 4);
                memcpy(big, big + ne, ne * sizeof(pvs__epedge2));
                CHECK(pvs__ep_sheet_polygon(big, ne, area, q, keep, ne, be, 1e-4, hp, hh, PVS__EP_MAXP, &dent) == 4 && dent == 0.0);
            } else {
                CHECK(pvs__ep_sheet_polygon(big, ne, area, q, keep, ne, be, 1e-4, hp, hh, PVS__EP_MAXP, &dent) == 0);
            }
        }
        free(big); free(q); free(keep); free(be); free(hp); free(hh);
    }
}

/* The core heaps against brute force: pvs__heap_sort gives the order of an insertion sort under the
   same "ranks before" (24-byte records, many ties broken by index), and pvs__topk_offer keeps the k
   best scores of a stream. */
typedef struct bd_rec {
    float score;
    uint32_t id;
    double pad[2];
} bd_rec;
static int bd_rec_before(const void *pa, const void *pb) {
    const bd_rec *a = (const bd_rec *)pa, *b = (const bd_rec *)pb;
    return a->score < b->score || (a->score == b->score && a->id < b->id);
}
static int bd_rec_better(const void *pa, const void *pb) { return ((const bd_rec *)pa)->score > ((const bd_rec *)pb)->score; }
static void bd_test_heaps(void) {
    enum { N = 300 };
    static bd_rec a[N], ref[N], heap[N];
    uint32_t trial, i, j;
    for (trial = 0; trial < 200; ++trial) {
        uint32_t n = (uint32_t)(N * bd_rnd()), k = (uint32_t)(40 * bd_rnd()), count = 0, levels = 1 + (uint32_t)(20 * bd_rnd());
        for (i = 0; i < n; ++i) {
            a[i].score = (float)(uint32_t)(levels * bd_rnd());
            a[i].id = i;
            a[i].pad[0] = a[i].pad[1] = 0.0;
        }
        memcpy(ref, a, n * sizeof(bd_rec));
        for (i = 1; i < n; ++i) /* insertion sort: the reference order */
            for (j = i; j > 0 && bd_rec_before(ref + j, ref + j - 1); --j) {
                bd_rec t = ref[j];
                ref[j] = ref[j - 1];
                ref[j - 1] = t;
            }
        memcpy(heap, a, n * sizeof(bd_rec));
        pvs__heap_sort(heap, n, sizeof(bd_rec), bd_rec_before);
        CHECK(memcmp(heap, ref, n * sizeof(bd_rec)) == 0);
        /* top-k by score alone: the kept scores are the k highest (which of the equal scores at the cut
           stay depends on the heap, deterministically) */
        for (i = 0; i < n; ++i) pvs__topk_offer(heap, &count, k, sizeof(bd_rec), a + i, bd_rec_better);
        CHECK(count == (n < k ? n : k));
        for (i = 0; i < count; ++i) {
            uint32_t better = 0, kept_equal = 0, all_equal = 0;
            for (j = 0; j < n; ++j) {
                better += a[j].score > heap[i].score;
                all_equal += a[j].score == heap[i].score;
            }
            for (j = 0; j < count; ++j) kept_equal += heap[j].score == heap[i].score;
            CHECK(better < k && kept_equal <= all_equal && (better + all_equal > count || kept_equal == all_equal));
        }
    }
}

/* pvs__key_index_sort (insertion up to 16 keys, the heap above) against qsort under the same total order: (key,
   index) pairs with tied keys and indices in random order. */
static int bd_key_cmp(const void *a, const void *b) {
    return pvs__key_index_before(a, b) ? -1 : pvs__key_index_before(b, a) ? 1 : 0;
}
static void bd_test_key_sort(void) {
    pvs__key_index a[40], ref[40]; /* 0 to 40 keys */
    uint32_t trial, i, bad = 0;
    for (trial = 0; trial < 400; ++trial) {
        uint32_t n = trial % 41, levels = 1 + (uint32_t)(6 * bd_rnd());
        for (i = 0; i < n; ++i) a[i].key = (double)(uint32_t)(levels * bd_rnd()) - 2.0, a[i].index = i;
        for (i = n; i > 1; --i) { /* shuffled indices: ties fall back to them */
            uint32_t j = (uint32_t)(i * bd_rnd()) % i, t = a[i - 1].index;
            a[i - 1].index = a[j].index, a[j].index = t;
        }
        memcpy(ref, a, n * sizeof(a[0]));
        if (n) qsort(ref, n, sizeof(ref[0]), bd_key_cmp);
        pvs__key_index_sort(a, n);
        for (i = 0; i < n; ++i) bad += a[i].key != ref[i].key || a[i].index != ref[i].index;
    }
    CHECK(bad == 0);
}

void test_bounded(void) {
    bd_test_scan();
    bd_test_walk();
    bd_test_heaps();
    bd_test_key_sort();
}
