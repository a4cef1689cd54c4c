/* test_kdtree.c - the kD-tree, scene ray casts and the ray sampler against brute-force references. */
#include "../pvs.h"
#include "test.h"
#include <math.h>
#include <stdlib.h>
#include <string.h>

/* ---- helpers ---- */

static uint64_t kd_rng = 0x1234567ull;
static double rnd(void) { return test_rnd(&kd_rng); }
static float rndf(float lo, float hi) { return test_rndf(&kd_rng, lo, hi); }

static void random_dir(float d[3]) {
    double len;
    do {
        d[0] = rndf(-1, 1); d[1] = rndf(-1, 1); d[2] = rndf(-1, 1);
        len = (double)d[0] * d[0] + (double)d[1] * d[1] + (double)d[2] * d[2];
    } while (len > 1.0 || len < 1e-4);
}

/* A growing triangle mesh. */
typedef struct tmesh {
    float *pos;
    uint32_t *idx;
    uint32_t vc, tc, vcap, tcap;
} tmesh;

static uint32_t tm_vertex(tmesh *m, float x, float y, float z) {
    if (m->vc == m->vcap) {
        m->vcap = m->vcap ? 2 * m->vcap : 64;
        m->pos = (float *)realloc(m->pos, (size_t)m->vcap * 3 * sizeof(float));
    }
    m->pos[3 * m->vc] = x; m->pos[3 * m->vc + 1] = y; m->pos[3 * m->vc + 2] = z;
    return m->vc++;
}
static void tm_tri(tmesh *m, uint32_t a, uint32_t b, uint32_t c) {
    if (m->tc == m->tcap) {
        m->tcap = m->tcap ? 2 * m->tcap : 64;
        m->idx = (uint32_t *)realloc(m->idx, (size_t)m->tcap * 3 * sizeof(uint32_t));
    }
    m->idx[3 * m->tc] = a; m->idx[3 * m->tc + 1] = b; m->idx[3 * m->tc + 2] = c;
    m->tc++;
}
/* A closed box: 8 shared corners, 12 triangles. */
static void tm_box(tmesh *m, const float lo[3], const float hi[3]) {
    uint32_t base = m->vc, i;
    for (i = 0; i < 8; ++i) tm_vertex(m, i & 1 ? hi[0] : lo[0], i & 2 ? hi[1] : lo[1], i & 4 ? hi[2] : lo[2]);
    for (i = 0; i < 12; ++i) tm_tri(m, base + test_box_tris[i][0], base + test_box_tris[i][1], base + test_box_tris[i][2]);
}
static void tm_free(tmesh *m) {
    free(m->pos);
    free(m->idx);
    memset(m, 0, sizeof(*m));
}

/* Brute-force ray-triangle test: Moller-Trumbore in double. Returns 1 and t; *margin is the smallest
   barycentric distance to an edge (tiny margins are ambiguous and skipped by the comparisons). */
static int bf_triangle(const float *p0, const float *p1, const float *p2, const double o[3], const double d[3], double tmax,
                       double *t_out, double *margin) {
    double e1[3], e2[3], pv[3], tv[3], qv[3], det, inv, u, v, t;
    int k;
    for (k = 0; k < 3; ++k) {
        e1[k] = (double)p1[k] - p0[k];
        e2[k] = (double)p2[k] - p0[k];
        tv[k] = o[k] - p0[k];
    }
    pv[0] = d[1] * e2[2] - d[2] * e2[1]; pv[1] = d[2] * e2[0] - d[0] * e2[2]; pv[2] = d[0] * e2[1] - d[1] * e2[0];
    det = e1[0] * pv[0] + e1[1] * pv[1] + e1[2] * pv[2];
    *margin = 1.0;
    if (fabs(det) < 1e-300) return 0;
    inv = 1.0 / det;
    u = (tv[0] * pv[0] + tv[1] * pv[1] + tv[2] * pv[2]) * inv;
    qv[0] = tv[1] * e1[2] - tv[2] * e1[1]; qv[1] = tv[2] * e1[0] - tv[0] * e1[2]; qv[2] = tv[0] * e1[1] - tv[1] * e1[0];
    v = (d[0] * qv[0] + d[1] * qv[1] + d[2] * qv[2]) * inv;
    t = (e2[0] * qv[0] + e2[1] * qv[1] + e2[2] * qv[2]) * inv;
    /* the distance to the nearest edge: 0 or negative (outside) by a little is ambiguous */
    *margin = u;
    if (v < *margin) *margin = v;
    if (1.0 - u - v < *margin) *margin = 1.0 - u - v;
    *margin = fabs(*margin);
    if (u >= -1e-7 && v >= -1e-7 && u + v <= 1.0 + 1e-7 && (fabs(t) < 1e-9 * (1.0 + fabs(tmax)) || fabs(t - tmax) < 1e-9 * (1.0 + fabs(tmax))))
        *margin = 0.0; /* at an end of the ray */
    if (u < 0.0 || v < 0.0 || u + v > 1.0 || t < 0.0 || t > tmax) return 0;
    *t_out = t;
    return 1;
}

static int zero_area(const float *a, const float *b, const float *c) {
    double e1[3], e2[3];
    int k;
    for (k = 0; k < 3; ++k) {
        e1[k] = (double)b[k] - a[k];
        e2[k] = (double)c[k] - a[k];
    }
    return e1[1] * e2[2] - e1[2] * e2[1] == 0.0 && e1[2] * e2[0] - e1[0] * e2[2] == 0.0 && e1[0] * e2[1] - e1[1] * e2[0] == 0.0;
}

/* Closest hit by brute force; returns -1 when ambiguous (a hit within 1e-7 of an edge or an end). */
static int bf_raycast(const tmesh *m, const float o[3], const float d[3], double tmax, double *t_out, uint32_t *tri_out) {
    double od[3], dd[3], best = tmax, margin;
    int found = 0, ambiguous = 0, k;
    uint32_t t;
    for (k = 0; k < 3; ++k) { od[k] = o[k]; dd[k] = d[k]; }
    for (t = 0; t < m->tc; ++t) {
        const float *a = m->pos + 3 * m->idx[3 * t], *b = m->pos + 3 * m->idx[3 * t + 1], *c = m->pos + 3 * m->idx[3 * t + 2];
        double th;
        int h;
        if (zero_area(a, b, c)) continue;
        h = bf_triangle(a, b, c, od, dd, tmax, &th, &margin);
        if (margin < 1e-7) ambiguous = 1;
        if (h && (!found || th < best)) {
            best = th;
            *tri_out = t;
            found = 1;
        }
    }
    *t_out = best;
    return ambiguous ? -1 : found;
}

static pvs_scene *make_scene(const tmesh *m, const pvs_object_desc *objs, uint32_t n) {
    return test_scene_arrays(m->pos, m->vc, m->idx, m->tc, objs, n, 0);
}

/* Compares pvs_scene_raycast and pvs_scene_segment_blocked with brute force over `rays` random rays
   (at least a tenth of them hitting something unless any_hits). */
static void compare_rays_ex(const tmesh *m, const pvs_scene *s, const float lo[3], const float hi[3], int rays, int any_hits) {
    int i, mismatches = 0, seg_mismatches = 0, compared = 0, hits = 0;
    for (i = 0; i < rays; ++i) {
        float o[3], d[3], b[3], tmax;
        double tb;
        uint32_t trib = 0;
        pvs_hit h;
        int k, hk, hb;
        for (k = 0; k < 3; ++k) o[k] = rndf(lo[k], hi[k]);
        random_dir(d);
        if (i % 3 == 0) { /* axis-parallel and zero components */
            d[i % 2] = 0.0f;
            if (i % 9 == 0) d[(i / 9) % 3] = -0.0f;
        }
        if (d[0] == 0.0f && d[1] == 0.0f && d[2] == 0.0f) d[2] = 1.0f;
        tmax = i % 4 == 0 ? rndf(0.0f, 10.0f) : 1e6f;
        hb = bf_raycast(m, o, d, tmax, &tb, &trib);
        hk = pvs_scene_raycast(s, o, d, tmax, &h);
        if (hb >= 0) {
            ++compared;
            hits += hb;
            if (hk != hb) ++mismatches;
            else if (hk) {
                if (fabs((double)h.t - tb) > 1e-5 * (1.0 + tb)) ++mismatches;
                else if (h.triangle != trib) {
                    /* a tie: the other triangle must be hit at the same distance */
                    double od[3], dd[3], t2, mg;
                    for (k = 0; k < 3; ++k) { od[k] = o[k]; dd[k] = d[k]; }
                    if (!bf_triangle(m->pos + 3 * m->idx[3 * h.triangle], m->pos + 3 * m->idx[3 * h.triangle + 1],
                                     m->pos + 3 * m->idx[3 * h.triangle + 2], od, dd, tmax, &t2, &mg) ||
                        fabs(t2 - tb) > 1e-5 * (1.0 + tb))
                        ++mismatches;
                }
            }
        }
        /* segment: o to b, blocked exactly when a ray hit lies within the segment */
        for (k = 0; k < 3; ++k) b[k] = o[k] + d[k] * rndf(0.0f, 8.0f);
        {
            float sd[3];
            double ts;
            uint32_t trs;
            int hs;
            for (k = 0; k < 3; ++k) sd[k] = b[k] - o[k];
            if (sd[0] == 0.0f && sd[1] == 0.0f && sd[2] == 0.0f) continue;
            hs = bf_raycast(m, o, sd, 1.0, &ts, &trs);
            if (hs >= 0 && hs != pvs_scene_segment_blocked(s, o, b)) ++seg_mismatches;
        }
    }
    CHECK(mismatches == 0);
    CHECK(seg_mismatches == 0);
    CHECK(compared > rays * 9 / 10);
    CHECK(any_hits ? hits > 0 : hits > compared / 10);
    if (mismatches || seg_mismatches) fprintf(stderr, "  ray mismatches %d, segment mismatches %d of %d\n", mismatches, seg_mismatches, rays);
}

static void compare_rays(const tmesh *m, const pvs_scene *s, const float lo[3], const float hi[3], int rays) {
    compare_rays_ex(m, s, lo, hi, rays, 0);
}

/* ---- ray casts on a triangle soup and on a city ---- */

static void test_raycast_soup(void) {
    tmesh m;
    pvs_object_desc obj[2];
    pvs_scene *s;
    float lo[3] = {-3, -3, -3}, hi[3] = {13, 13, 13};
    int i, k;
    memset(&m, 0, sizeof(m));
    for (i = 0; i < 3000; ++i) {
        float c[3], sz = rndf(0.1f, 2.0f);
        uint32_t v[3];
        for (k = 0; k < 3; ++k) c[k] = rndf(0, 10);
        for (k = 0; k < 3; ++k) v[k] = tm_vertex(&m, c[0] + rndf(-sz, sz), c[1] + rndf(-sz, sz), c[2] + rndf(-sz, sz));
        tm_tri(&m, v[0], v[1], v[2]);
    }
    /* axis-aligned and flat triangles, shared edges (a fan) */
    for (i = 0; i < 200; ++i) {
        float c[3];
        uint32_t v0, v1, v2, v3;
        for (k = 0; k < 3; ++k) c[k] = (float)(int)rndf(0, 10);
        v0 = tm_vertex(&m, c[0], c[1], c[2]);
        v1 = tm_vertex(&m, c[0] + 1, c[1], c[2]);
        v2 = tm_vertex(&m, c[0], c[1] + 1, c[2]);
        v3 = tm_vertex(&m, c[0] + 1, c[1] + 1, c[2]);
        tm_tri(&m, v0, v1, v2);
        tm_tri(&m, v1, v3, v2);
    }
    obj[0].first_triangle = 0; obj[0].triangle_count = m.tc; obj[0].flags = 0;
    /* zero-area triangles in no object: never hit */
    for (i = 0; i < 50; ++i) {
        float c[3];
        uint32_t a, b;
        for (k = 0; k < 3; ++k) c[k] = rndf(0, 10);
        a = tm_vertex(&m, c[0], c[1], c[2]);
        b = tm_vertex(&m, c[0] + 1, c[1] + 2, c[2] + 3);
        tm_tri(&m, a, b, tm_vertex(&m, c[0] + 2, c[1] + 4, c[2] + 6));
        tm_tri(&m, a, a, b);
    }
    s = make_scene(&m, obj, 1);
    CHECK(s != NULL);
    if (s) {
        compare_rays(&m, s, lo, hi, 5000);
        /* a ray straight at a zero-area triangle hits nothing when nothing else is there */
        {
            float o[3] = {-100, -100, -100}, d[3] = {-1, 0, 0};
            pvs_hit h;
            CHECK(pvs_scene_raycast(s, o, d, 1e6f, &h) == 0);
        }
        pvs_scene_destroy(s);
    }
    tm_free(&m);
}

static void build_city(tmesh *m, pvs_object_desc *objs, uint32_t *object_count, int g) {
    float lo[3], hi[3];
    int x, z;
    *object_count = 0;
    lo[0] = -1; lo[1] = -1; lo[2] = -1;
    hi[0] = (float)g * 10 + 1; hi[1] = 0; hi[2] = (float)g * 10 + 1;
    objs[0].first_triangle = m->tc;
    tm_box(m, lo, hi);
    objs[0].triangle_count = 12;
    objs[0].flags = 0;
    *object_count = 1;
    for (z = 0; z < g; ++z)
        for (x = 0; x < g; ++x) {
            pvs_object_desc *o = objs + (*object_count)++;
            lo[0] = (float)x * 10 + 2; lo[1] = 0; lo[2] = (float)z * 10 + 2;
            hi[0] = lo[0] + 6; hi[1] = (float)(3 + (int)(20 * rnd() * rnd())); hi[2] = lo[2] + 6;
            o->first_triangle = m->tc;
            o->triangle_count = 12;
            o->flags = 0;
            tm_box(m, lo, hi);
        }
}

static void test_raycast_city(void) {
    tmesh m;
    pvs_object_desc objs[1 + 24 * 24];
    uint32_t n;
    pvs_scene *s;
    float lo[3] = {-5, 0.5f, -5}, hi[3] = {245, 25, 245};
    memset(&m, 0, sizeof(m));
    build_city(&m, objs, &n, 24);
    s = make_scene(&m, objs, n);
    CHECK(s != NULL);
    if (s) {
        CHECK(pvs_scene_object_count(s) == n);
        compare_rays(&m, s, lo, hi, 5000);
        pvs_scene_destroy(s);
    }
    tm_free(&m);
}

/* Rays from outside aimed exactly at corners, edge points and face-diagonal points of closed box
   meshes must hit the surface at the aimed point, never slip through to the back. */
static void test_raycast_watertight(void) {
    tmesh m;
    pvs_object_desc obj;
    pvs_scene *s;
    float lo[3] = {0, 0, 0}, hi[3] = {4, 2, 8}, lo2[3] = {4, 0, 0}, hi2[3] = {6, 2, 8};
    int i, misses = 0, wrong = 0;
    memset(&m, 0, sizeof(m));
    tm_box(&m, lo, hi);
    tm_box(&m, lo2, hi2); /* a second box sharing a face: coplanar neighbours */
    obj.first_triangle = 0; obj.triangle_count = m.tc; obj.flags = 0;
    s = make_scene(&m, &obj, 1);
    CHECK(s != NULL);
    if (!s) { tm_free(&m); return; }
    for (i = 0; i < 20000; ++i) {
        float x[3], o[3], d[3];
        int k, face = i % 3;
        pvs_hit h;
        /* a target on the union's surface: corners, edges (incl. the face diagonals of the triangulation) */
        for (k = 0; k < 3; ++k) x[k] = (float)((int)(rnd() * 3)) * (k == 0 ? 3.0f : k == 1 ? 1.0f : 4.0f);
        x[face] = rnd() < 0.5 ? 0.0f : (face == 0 ? 6.0f : face == 1 ? 2.0f : 8.0f);
        if (i % 4 == 1) { /* along a face diagonal: t (hi - lo) from a corner */
            int a = (face + 1) % 3, b = (face + 2) % 3;
            float f = (float)((int)(rnd() * 16)) / 16.0f, ext[3] = {4, 2, 8};
            x[a] = f * ext[a];
            x[b] = f * ext[b];
        }
        /* the origin: outside on the target face's side, offsets in 1/8 so that d = x - o is exact */
        for (k = 0; k < 3; ++k) o[k] = x[k] + (float)((int)(rnd() * 64) - 32) / 8.0f;
        o[face] = x[face] == 0.0f ? x[face] - (float)(1 + (int)(rnd() * 40)) / 8.0f : x[face] + (float)(1 + (int)(rnd() * 40)) / 8.0f;
        for (k = 0; k < 3; ++k) d[k] = x[k] - o[k];
        /* the ray must enter the solid at x: skip targets where it only grazes (leaves the union) */
        {
            float p[3], q = 1.0f + 1.0f / 1024.0f;
            for (k = 0; k < 3; ++k) p[k] = o[k] + d[k] * q;
            if (p[0] < 0 || p[0] > 6 || p[1] < 0 || p[1] > 2 || p[2] < 0 || p[2] > 8) continue;
            if (p[0] <= 0 || p[0] >= 6 || p[1] <= 0 || p[1] >= 2 || p[2] <= 0 || p[2] >= 8) continue;
        }
        if (!pvs_scene_raycast(s, o, d, 10.0f, &h)) ++misses;
        else if (fabsf(h.t - 1.0f) > 1e-5f) ++wrong;
    }
    CHECK(misses == 0);
    CHECK(wrong == 0);
    if (misses || wrong) fprintf(stderr, "  watertight: %d misses, %d hits past the surface\n", misses, wrong);
    /* segments ending exactly on the surface are blocked, stopping just short is not */
    {
        float a[3] = {-1, 1, 1}, b[3] = {0, 1, 1}, c[3] = {-0.0001f, 1, 1};
        CHECK(pvs_scene_segment_blocked(s, a, b) == 1);
        CHECK(pvs_scene_segment_blocked(s, b, a) == 1);
        CHECK(pvs_scene_segment_blocked(s, a, c) == 0);
        CHECK(pvs_scene_segment_blocked(s, a, a) == 0);
    }
    pvs_scene_destroy(s);
    tm_free(&m);
}

/* ---- the kD-tree itself ---- */

static void random_boxes(pvs_box *boxes, uint32_t n, int with_special) {
    uint32_t i;
    int k;
    for (i = 0; i < n; ++i) {
        for (k = 0; k < 3; ++k) {
            float c = rndf(0, 100), e = rndf(0, 6) * (float)rnd();
            if (with_special && i % 7 == 0) c = (float)(int)c; /* grid-aligned */
            boxes[i].min[k] = c;
            boxes[i].max[k] = c + e;
            if (with_special && i % 5 == 0 && k == (int)(i % 3)) boxes[i].max[k] = c; /* flat */
        }
        if (with_special && i % 97 == 3) { /* empty: ignored */
            boxes[i].min[0] = 5;
            boxes[i].max[0] = 4;
        }
    }
}

static int box_empty(const pvs_box *b) { return b->min[0] > b->max[0] || b->min[1] > b->max[1] || b->min[2] > b->max[2]; }
static int box_overlap(const pvs_box *a, const pvs_box *b) {
    int k;
    for (k = 0; k < 3; ++k)
        if (a->min[k] > b->max[k] || b->min[k] > a->max[k]) return 0;
    return 1;
}
static int box_inside(const pvs_box *inner, const pvs_box *outer) {
    int k;
    for (k = 0; k < 3; ++k)
        if (inner->min[k] < outer->min[k] || inner->max[k] > outer->max[k]) return 0;
    return 1;
}
static float box_dist(const pvs_box *a, const pvs_box *b) {
    double d2 = 0;
    int k;
    for (k = 0; k < 3; ++k) {
        double g = 0;
        if (b->min[k] > a->max[k]) g = (double)b->min[k] - a->max[k];
        else if (a->min[k] > b->max[k]) g = (double)a->min[k] - b->max[k];
        d2 += g * g;
    }
    return (float)sqrt(d2);
}

typedef struct sweep_log {
    const pvs_box *boxes;
    uint32_t count;
    const pvs_box *source;
    unsigned char *reached;
    int visits, leaves, order_ok, dist_ok, leaf_ok;
    float last;
    int skip_at, stop_at;      /* visit index to SKIP / STOP at, -1 for none */
    pvs_box skipped;
    int skipped_set, skip_violations;
    int all_at, all_stop_after; /* visit index to answer ALL at (-1: none); STOP after that many of its leaves */
    pvs_box accepted;
    int accepted_set, accepted_leaves, accepted_outside, all_index;
    pvs_box leaf_boxes[4096];  /* first leaves seen */
    int leaf_box_count;
    pvs_box all_boxes[16384];  /* every node box, in visit order */
    int all_count;
} sweep_log;

static pvs_visit sweep_visit(void *user, const pvs_box *node_box, float distance, const uint32_t *items, uint32_t item_count) {
    sweep_log *lg = (sweep_log *)user;
    uint32_t i;
    int index;
    if (distance < 0.0f) { /* a leaf of the subtree answered ALL: no order, every item reached */
        ++lg->accepted_leaves;
        if (!lg->accepted_set || !box_inside(node_box, &lg->accepted) || !items) ++lg->accepted_outside;
        for (i = 0; i < item_count; ++i)
            if (items[i] < lg->count) lg->reached[items[i]] = 1;
        return lg->accepted_leaves == lg->all_stop_after ? PVS_VISIT_STOP : PVS_VISIT_SKIP; /* answers but STOP are ignored */
    }
    index = lg->visits++;
    if (distance < lg->last) lg->order_ok = 0;
    lg->last = distance;
    if (fabsf(distance - box_dist(lg->source, node_box)) > 1e-4f * (1.0f + distance)) lg->dist_ok = 0;
    if (lg->skipped_set && box_inside(node_box, &lg->skipped)) lg->skip_violations++;
    if (items) {
        lg->leaves++;
        if (lg->leaf_box_count < 4096) lg->leaf_boxes[lg->leaf_box_count++] = *node_box;
        for (i = 0; i < item_count; ++i) {
            if (items[i] >= lg->count || !box_overlap(lg->boxes + items[i], node_box)) lg->leaf_ok = 0;
            else lg->reached[items[i]] = 1;
        }
        /* every item overlapping the leaf's cell is referenced from it */
        if (lg->leaves % 7 == 0) {
            for (i = 0; i < lg->count; ++i) {
                uint32_t j;
                int found = 0;
                if (box_empty(lg->boxes + i) || !box_overlap(lg->boxes + i, node_box)) continue;
                for (j = 0; j < item_count; ++j) found |= items[j] == i;
                if (!found) lg->leaf_ok = 0;
            }
        }
    }
    if (index == lg->stop_at) return PVS_VISIT_STOP;
    if (lg->all_count < 16384) lg->all_boxes[lg->all_count++] = *node_box;
    if (lg->all_at >= 0 && index >= lg->all_at && !lg->accepted_set && !items) { /* the first inner node from there */
        lg->accepted = *node_box;
        lg->accepted_set = 1;
        lg->all_index = index;
        return PVS_VISIT_ALL;
    }
    if (index >= lg->skip_at && lg->skip_at >= 0 && !lg->skipped_set && !items && distance > 0.0f) {
        lg->skipped = *node_box;
        lg->skipped_set = 1;
        return PVS_VISIT_SKIP;
    }
    return PVS_VISIT_DESCEND;
}

static void sweep_log_init(sweep_log *lg, const pvs_box *boxes, uint32_t count, const pvs_box *source, unsigned char *reached) {
    memset(lg, 0, sizeof(*lg));
    lg->boxes = boxes;
    lg->count = count;
    lg->source = source;
    lg->reached = reached;
    memset(reached, 0, count);
    lg->order_ok = lg->dist_ok = lg->leaf_ok = 1;
    lg->last = -1.0f;
    lg->skip_at = lg->stop_at = lg->all_at = lg->all_stop_after = -1;
}

static void test_kdtree_sweep(void) {
    enum { N = 4000 };
    static pvs_box boxes[N];
    static unsigned char reached[N];
    static sweep_log lg;
    pvs_kdtree_desc kd;
    pvs_kdtree *t = NULL;
    pvs_error err;
    size_t scratch_size;
    void *scratch;
    int trial;
    random_boxes(boxes, N, 1);
    memset(&kd, 0, sizeof(kd));
    kd.boxes = boxes;
    kd.count = N;
    CHECK(pvs_kdtree_create(&kd, &t, &err) == PVS_OK);
    if (!t) return;
    CHECK(pvs_kdtree_node_count(t) > 100);
    scratch_size = pvs_kdtree_sweep_scratch_size(t);
    scratch = malloc(scratch_size);
    for (trial = 0; trial < 12; ++trial) {
        pvs_box src;
        uint32_t i;
        int k, all = 1;
        for (k = 0; k < 3; ++k) {
            src.min[k] = rndf(-20, 120);
            src.max[k] = trial % 2 ? src.min[k] : src.min[k] + rndf(0, 30); /* points and boxes */
        }
        sweep_log_init(&lg, boxes, N, &src, reached);
        CHECK(pvs_kdtree_sweep(t, &src, scratch, scratch_size, sweep_visit, &lg) == PVS_OK);
        CHECK(lg.order_ok);
        CHECK(lg.dist_ok);
        CHECK(lg.leaf_ok);
        CHECK((uint32_t)lg.visits == pvs_kdtree_node_count(t));
        for (i = 0; i < N; ++i)
            if (!box_empty(boxes + i) && !reached[i]) all = 0;
        CHECK(all);
        /* SKIP prunes exactly the subtree: the nodes whose cells lie in the skipped cell */
        {
            static pvs_box full[16384];
            int full_count = lg.all_count, inside = 0, j;
            CHECK(full_count == lg.visits);
            memcpy(full, lg.all_boxes, (size_t)full_count * sizeof(pvs_box));
            sweep_log_init(&lg, boxes, N, &src, reached);
            lg.skip_at = 3 + trial;
            CHECK(pvs_kdtree_sweep(t, &src, scratch, scratch_size, sweep_visit, &lg) == PVS_OK);
            CHECK(lg.skipped_set);
            CHECK(lg.skip_violations == 0);
            for (j = 0; j < full_count; ++j) inside += box_inside(full + j, &lg.skipped);
            CHECK(inside >= 1);
            CHECK(lg.visits == full_count - (inside - 1));
            CHECK(lg.order_ok);
        }
        /* STOP ends at once */
        sweep_log_init(&lg, boxes, N, &src, reached);
        lg.stop_at = 10 + trial * 7;
        CHECK(pvs_kdtree_sweep(t, &src, scratch, scratch_size, sweep_visit, &lg) == PVS_OK);
        CHECK(lg.visits == 11 + trial * 7);
        /* ALL: the node's non-empty leaves come at once (distance -1, inside its cell), nothing below it
           is visited in order, every item is still reached; STOP among them ends the sweep */
        {
            static pvs_box full[16384];
            int full_count, inside = 0, j;
            sweep_log_init(&lg, boxes, N, &src, reached);
            CHECK(pvs_kdtree_sweep(t, &src, scratch, scratch_size, sweep_visit, &lg) == PVS_OK);
            full_count = lg.all_count;
            memcpy(full, lg.all_boxes, (size_t)full_count * sizeof(pvs_box));
            sweep_log_init(&lg, boxes, N, &src, reached);
            lg.all_at = 2 + trial;
            CHECK(pvs_kdtree_sweep(t, &src, scratch, scratch_size, sweep_visit, &lg) == PVS_OK);
            if (lg.accepted_set) {
                for (j = 0; j < full_count; ++j) inside += box_inside(full + j, &lg.accepted);
                CHECK(lg.accepted_outside == 0);
                CHECK(lg.accepted_leaves > 0);
                CHECK(lg.visits == full_count - (inside - 1)); /* the node itself was visited, nothing below it */
                for (i = 0, all = 1; i < N; ++i)
                    if (!box_empty(boxes + i) && !reached[i]) all = 0;
                CHECK(all);
                CHECK(lg.order_ok);
                sweep_log_init(&lg, boxes, N, &src, reached);
                lg.all_at = 2 + trial;
                lg.all_stop_after = 1;
                CHECK(pvs_kdtree_sweep(t, &src, scratch, scratch_size, sweep_visit, &lg) == PVS_OK);
                CHECK(lg.accepted_leaves == 1 && lg.visits == lg.all_index + 1);
            } else {
                CHECK(0);
            }
        }
    }
    {
        pvs_box src = boxes[0];
        sweep_log_init(&lg, boxes, N, &src, reached);
        CHECK(pvs_kdtree_sweep(t, &src, scratch, scratch_size - 1, sweep_visit, &lg) == PVS_ERROR_BUFFER_TOO_SMALL);
        CHECK(lg.visits == 0);
        src.min[1] = NAN;
        CHECK(pvs_kdtree_sweep(t, &src, scratch, scratch_size, sweep_visit, &lg) == PVS_ERROR_NOT_FINITE);
    }
    /* determinism: the same boxes give the same tree (node count and sweep order) */
    {
        pvs_kdtree *t2 = NULL;
        CHECK(pvs_kdtree_create(&kd, &t2, NULL) == PVS_OK);
        if (t2) {
            CHECK(pvs_kdtree_node_count(t2) == pvs_kdtree_node_count(t));
            pvs_kdtree_destroy(t2);
        }
    }
    free(scratch);
    pvs_kdtree_destroy(t);
}

/* Every box containing p is among the leaf's items. */
static int leaf_has_all(const pvs_kdtree *t, const pvs_box *boxes, uint32_t n, const float p[3]) {
    uint32_t count = 0, i, j;
    const uint32_t *items = pvs_kdtree_leaf_items(t, p, &count);
    pvs_box bounds = pvs_kdtree_bounds(t);
    int inside = p[0] >= bounds.min[0] && p[0] <= bounds.max[0] && p[1] >= bounds.min[1] && p[1] <= bounds.max[1] &&
                 p[2] >= bounds.min[2] && p[2] <= bounds.max[2];
    if (!inside && items) return 0;
    for (i = 0; i < n; ++i) {
        const pvs_box *b = boxes + i;
        int found = 0;
        if (!(p[0] >= b->min[0] && p[0] <= b->max[0] && p[1] >= b->min[1] && p[1] <= b->max[1] && p[2] >= b->min[2] &&
              p[2] <= b->max[2]))
            continue;
        if (box_empty(b)) continue;
        for (j = 0; j < count; ++j) found |= items[j] == i;
        if (!found) return 0;
    }
    return 1;
}

static pvs_visit collect_leaves(void *user, const pvs_box *node_box, float distance, const uint32_t *items, uint32_t item_count) {
    sweep_log *lg = (sweep_log *)user;
    (void)distance;
    (void)items;
    (void)item_count;
    if (lg->leaf_box_count < 4096) lg->leaf_boxes[lg->leaf_box_count++] = *node_box;
    return PVS_VISIT_DESCEND;
}

static void test_kdtree_point_location(void) {
    enum { N = 3000 };
    static pvs_box boxes[N];
    static sweep_log lg;
    pvs_kdtree_desc kd;
    pvs_kdtree *t = NULL;
    int i, bad = 0;
    random_boxes(boxes, N, 1);
    memset(&kd, 0, sizeof(kd));
    kd.boxes = boxes;
    kd.count = N;
    kd.leaf_size = 2;
    CHECK(pvs_kdtree_create(&kd, &t, NULL) == PVS_OK);
    if (!t) return;
    memset(&lg, 0, sizeof(lg));
    {
        void *scratch = malloc(pvs_kdtree_sweep_scratch_size(t));
        pvs_box src;
        memset(&src, 0, sizeof(src));
        pvs_kdtree_sweep(t, &src, scratch, pvs_kdtree_sweep_scratch_size(t), collect_leaves, &lg);
        free(scratch);
    }
    for (i = 0; i < 20000; ++i) {
        float p[3];
        int k, kind = i % 4;
        if (kind == 0) { /* anywhere, also outside */
            for (k = 0; k < 3; ++k) p[k] = rndf(-5, 110);
        } else if (kind == 1) { /* on an item's face or corner */
            const pvs_box *b = boxes + (uint32_t)(rnd() * N);
            for (k = 0; k < 3; ++k) p[k] = rnd() < 0.3 ? b->min[k] : rnd() < 0.5 ? b->max[k] : rndf(b->min[k], b->max[k]);
        } else { /* on a node cell's face or corner: split planes */
            const pvs_box *b = lg.leaf_boxes + (int)(rnd() * lg.leaf_box_count);
            for (k = 0; k < 3; ++k) p[k] = rnd() < 0.5 ? (rnd() < 0.5 ? b->min[k] : b->max[k]) : rndf(b->min[k], b->max[k]);
        }
        if (!leaf_has_all(t, boxes, N, p)) ++bad;
    }
    CHECK(bad == 0);
    {
        float p[3] = {-1000, 0, 0};
        uint32_t count = 7;
        CHECK(pvs_kdtree_leaf_items(t, p, &count) == NULL && count == 0);
    }
    pvs_kdtree_destroy(t);
}

/* The ray walk: leaves front to back, and every box the ray meets is passed (slab test, double). */
typedef struct walk_log {
    unsigned char *seen;
    float last_enter;
    int order_ok, leaves, stop_after;
    float shorten_to;
} walk_log;

static float walk_leaf(void *user, const uint32_t *items, uint32_t count, float t_enter, float t_exit) {
    walk_log *w = (walk_log *)user;
    uint32_t i;
    if (t_enter < w->last_enter - 1e-4f * (1.0f + fabsf(w->last_enter)) || t_exit < t_enter) w->order_ok = 0;
    w->last_enter = t_enter;
    for (i = 0; i < count; ++i) w->seen[items[i]] = 1;
    if (++w->leaves == w->stop_after) return -1.0f;
    return w->shorten_to;
}

static int slab_hit(const pvs_box *b, const float o[3], const float d[3], double tmax) {
    double tn = 0.0, tf = tmax;
    int k;
    for (k = 0; k < 3; ++k) {
        if (d[k] == 0.0f) {
            if (o[k] < b->min[k] || o[k] > b->max[k]) return 0;
        } else {
            double t0 = ((double)b->min[k] - o[k]) / d[k], t1 = ((double)b->max[k] - o[k]) / d[k];
            if (t0 > t1) { double x = t0; t0 = t1; t1 = x; }
            if (t0 > tn) tn = t0;
            if (t1 < tf) tf = t1;
        }
    }
    return tn <= tf;
}

static void test_kdtree_ray(void) {
    enum { N = 3000 };
    static pvs_box boxes[N];
    static unsigned char seen[N];
    pvs_kdtree_desc kd;
    pvs_kdtree *t = NULL;
    int i, missing = 0, order = 1;
    random_boxes(boxes, N, 1);
    memset(&kd, 0, sizeof(kd));
    kd.boxes = boxes;
    kd.count = N;
    CHECK(pvs_kdtree_create(&kd, &t, NULL) == PVS_OK);
    if (!t) return;
    for (i = 0; i < 3000; ++i) {
        float o[3], d[3], tmax = i % 2 ? 1000.0f : rndf(0, 60);
        walk_log w;
        uint32_t j;
        int k;
        for (k = 0; k < 3; ++k) o[k] = rndf(-30, 130);
        random_dir(d);
        if (i % 5 == 0) d[i % 3] = i % 10 ? 0.0f : -0.0f;
        if (i % 7 == 0) { /* start on a box face / corner */
            const pvs_box *b = boxes + (uint32_t)(rnd() * N);
            for (k = 0; k < 3; ++k) o[k] = rnd() < 0.5 ? b->min[k] : b->max[k];
        }
        memset(seen, 0, sizeof(seen));
        memset(&w, 0, sizeof(w));
        w.seen = seen;
        w.last_enter = -1.0f;
        w.order_ok = 1;
        w.shorten_to = 1e30f;
        pvs_kdtree_ray(t, o, d, tmax, walk_leaf, &w);
        order &= w.order_ok;
        for (j = 0; j < N; ++j)
            if (!box_empty(boxes + j) && slab_hit(boxes + j, o, d, tmax) && !seen[j]) ++missing;
    }
    CHECK(missing == 0);
    CHECK(order);
    /* stopping and shortening */
    {
        float o[3] = {-10, 50, 50}, d[3] = {1, 0, 0};
        walk_log w;
        memset(&w, 0, sizeof(w));
        w.seen = seen;
        w.order_ok = 1;
        w.stop_after = 2;
        w.shorten_to = 1e30f;
        pvs_kdtree_ray(t, o, d, 1000.0f, walk_leaf, &w);
        CHECK(w.leaves == 2);
        memset(&w, 0, sizeof(w));
        w.seen = seen;
        w.order_ok = 1;
        w.shorten_to = 0.0f; /* nothing past the first leaf's entry (tolerance aside) */
        pvs_kdtree_ray(t, o, d, 1000.0f, walk_leaf, &w);
        CHECK(w.leaves >= 1 && w.leaves <= 3);
    }
    pvs_kdtree_destroy(t);
}

static pvs_visit count_visit(void *user, const pvs_box *node_box, float distance, const uint32_t *items, uint32_t item_count) {
    (void)node_box; (void)distance; (void)items; (void)item_count;
    ++*(int *)user;
    return PVS_VISIT_DESCEND;
}
static float count_leaf(void *user, const uint32_t *items, uint32_t count, float t_enter, float t_exit) {
    (void)items; (void)count; (void)t_enter; (void)t_exit;
    ++*(int *)user;
    return 1e30f;
}

static void test_kdtree_edge_cases(void) {
    pvs_kdtree_desc kd;
    pvs_kdtree *t = NULL;
    pvs_error err;
    pvs_box boxes[3];
    float p[3] = {0, 0, 0}, d[3] = {1, 0, 0};
    uint32_t count = 5;
    int visits = 0;
    char scratch[64];
    /* empty trees: no boxes, and only empty boxes */
    memset(&kd, 0, sizeof(kd));
    CHECK(pvs_kdtree_create(&kd, &t, &err) == PVS_OK);
    CHECK(t != NULL);
    if (t) {
        pvs_box src;
        memset(&src, 0, sizeof(src));
        CHECK(pvs_kdtree_node_count(t) >= 1);
        CHECK(pvs_kdtree_sweep(t, &src, scratch, sizeof(scratch), count_visit, &visits) == PVS_OK);
        CHECK(visits == 0);
        pvs_kdtree_ray(t, p, d, 100.0f, count_leaf, &visits);
        CHECK(visits == 0);
        CHECK(pvs_kdtree_leaf_items(t, p, &count) == NULL && count == 0);
        pvs_kdtree_destroy(t);
    }
    boxes[0].min[0] = 1; boxes[0].max[0] = 0;
    boxes[0].min[1] = boxes[0].min[2] = 0; boxes[0].max[1] = boxes[0].max[2] = 1;
    kd.boxes = boxes;
    kd.count = 1;
    t = NULL;
    CHECK(pvs_kdtree_create(&kd, &t, &err) == PVS_OK);
    if (t) {
        CHECK(pvs_kdtree_leaf_items(t, p, &count) == NULL);
        pvs_kdtree_destroy(t);
    }
    /* NaN and infinity */
    memset(boxes, 0, sizeof(boxes));
    boxes[2].max[1] = NAN;
    kd.count = 3;
    t = NULL;
    CHECK(pvs_kdtree_create(&kd, &t, &err) == PVS_ERROR_NOT_FINITE);
    CHECK(t == NULL);
    CHECK(err.index == 2);
    boxes[2].max[1] = INFINITY;
    CHECK(pvs_kdtree_create(&kd, &t, &err) == PVS_ERROR_NOT_FINITE);
    CHECK(pvs_kdtree_create(NULL, &t, &err) == PVS_ERROR_INVALID_ARGUMENT);
    kd.boxes = NULL;
    CHECK(pvs_kdtree_create(&kd, &t, &err) == PVS_ERROR_INVALID_ARGUMENT);
    /* all boxes the same point: one leaf holds them */
    {
        static pvs_box same[100];
        int i;
        for (i = 0; i < 100; ++i) {
            same[i].min[0] = same[i].max[0] = 1;
            same[i].min[1] = same[i].max[1] = 2;
            same[i].min[2] = same[i].max[2] = 3;
        }
        kd.boxes = same;
        kd.count = 100;
        CHECK(pvs_kdtree_create(&kd, &t, &err) == PVS_OK);
        if (t) {
            float q[3] = {1, 2, 3}, o[3] = {0, 2, 3};
            CHECK(pvs_kdtree_leaf_items(t, q, &count) != NULL && count == 100);
            visits = 0;
            pvs_kdtree_ray(t, o, d, 10.0f, count_leaf, &visits);
            CHECK(visits == 1);
            pvs_kdtree_destroy(t);
        }
    }
}

/* ---- the ray sampler ---- */

/* A scene of boxes, one object each: box i spans box[i] = {min x, y, z, max x, y, z}, its object
   occluder-only when bit i of occluder_only is set. */
static pvs_scene *box_scene(tmesh *m, const float (*box)[6], uint32_t n, uint32_t occluder_only, pvs_object_desc *obj) {
    uint32_t i;
    memset(m, 0, sizeof(*m));
    for (i = 0; i < n; ++i) {
        obj[i].first_triangle = m->tc;
        obj[i].triangle_count = 12;
        obj[i].flags = (occluder_only >> i & 1u) ? PVS_OBJECT_OCCLUDER_ONLY : 0u;
        tm_box(m, box[i], box[i] + 3);
    }
    return make_scene(m, obj, n);
}

static void test_sample_visibility(void) {
    /* a cell at x in [0, 2]; a closed wall box at x in [4, 5]; object 2 behind it at x = 8; object 3
       in plain view beside the wall; object 4 in plain view but occluder-only */
    static const float box[5][6] = {{-20, -1, -20, 20, 0, 20}, /* ground */
                                    {4, 0, -10, 5, 30, 10},    /* wall */
                                    {7, 0, -1, 8, 2, 1},       /* hidden */
                                    {1, 0, 5, 2, 1, 6},        /* visible */
                                    {1, 0, -6, 2, 1, -5}};     /* occluder only */
    tmesh m;
    pvs_object_desc obj[5];
    pvs_box cell = {{0, 0.5f, -1}, {2, 2.0f, 1}};
    pvs_scene *s = box_scene(&m, box, 5, 1u << 4, obj);
    CHECK(s != NULL);
    if (s) {
        pvs_word a[1] = {0}, b[1] = {0}, c[1] = {0};
        uint64_t n;
        n = pvs_sample_visibility(s, &cell, 40, 500, 77, a);
        CHECK(n == 40u * 500u);
        CHECK(pvs_sample_visibility(s, &cell, 40, 500, 77, b) == n);
        CHECK(a[0] == b[0]); /* deterministic */
        CHECK(pvs_bitset_test(a, 0));
        CHECK(pvs_bitset_test(a, 1));
        CHECK(!pvs_bitset_test(a, 2));
        CHECK(pvs_bitset_test(a, 3));
        CHECK(!pvs_bitset_test(a, 4));
        /* a flat cell (a floor patch) and a point cell */
        cell.min[1] = cell.max[1] = 1.0f;
        CHECK(pvs_sample_visibility(s, &cell, 20, 300, 5, c) == 20u * 300u);
        CHECK(pvs_bitset_test(c, 3) && pvs_bitset_test(c, 1) && !pvs_bitset_test(c, 2) && !pvs_bitset_test(c, 4));
        cell.max[0] = cell.min[0];
        cell.max[2] = cell.min[2];
        c[0] = 0;
        CHECK(pvs_sample_visibility(s, &cell, 3, 300, 5, c) == 3u * 300u);
        CHECK(!pvs_bitset_test(c, 2) && !pvs_bitset_test(c, 4));
        /* fewer than 14 points, no rays, bad input */
        c[0] = 0;
        CHECK(pvs_sample_visibility(s, &cell, 5, 0, 5, c) == 0 && c[0] == 0);
        cell.min[0] = NAN;
        CHECK(pvs_sample_visibility(s, &cell, 5, 10, 5, c) == 0);
        /* scene queries: a ray from the cell towards the hidden object stops at the wall */
        {
            float o[3] = {1, 1, 0}, d[3] = {1, 0, 0}, e[3] = {7.5f, 1, 0};
            pvs_hit h;
            CHECK(pvs_scene_raycast(s, o, d, 100.0f, &h) == 1);
            CHECK(h.object == 1 && fabsf(h.t - 3.0f) < 1e-6f);
            CHECK(pvs_scene_triangle_object(s, h.triangle) == 1);
            CHECK(pvs_scene_segment_blocked(s, o, e) == 1);
            CHECK(pvs_scene_raycast(s, o, d, 2.9f, &h) == 0);
            e[0] = 3.9f;
            CHECK(pvs_scene_segment_blocked(s, o, e) == 0);
        }
        pvs_scene_destroy(s);
    }
    tm_free(&m);
}

/* The aimed sampler: a small object seen only through a slit in a wall, which uniform directions
   almost never hit; an object behind the solid part of the wall is never set (a lower bound). */
static void test_sample_visibility_toward(void) {
    static const float box[5][6] = {{4, 0, -10, 5, 30, -0.05f},             /* wall, left of the slit */
                                    {4, 0, 0.05f, 5, 30, 10},               /* wall, right of the slit */
                                    {30, 0.9f, -0.1f, 30.2f, 1.1f, 0.1f},   /* seen through the slit */
                                    {30, 0.9f, 5, 30.2f, 1.1f, 5.2f},       /* behind the wall */
                                    {1, 0, 3, 2, 1, 4}};                    /* occluder only, in plain view */
    tmesh m;
    pvs_object_desc obj[5];
    pvs_box cell = {{0, 0.5f, -1}, {2, 1.5f, 1}};
    pvs_scene *s = box_scene(&m, box, 5, 1u << 4, obj);
    CHECK(s != NULL);
    if (s) {
        pvs_word a[1] = {0}, b[1] = {0}, t[1] = {0};
        uint64_t n;
        pvs_sample_visibility(s, &cell, 20, 300, 3, a);
        CHECK(!pvs_bitset_test(a, 2)); /* 6,000 uniform rays pass the slit by */
        n = pvs_sample_visibility_toward(s, &cell, NULL, 256, 11, a);
        CHECK(n > 0 && n <= 4u * 256u);
        CHECK(pvs_bitset_test(a, 0) && pvs_bitset_test(a, 1) && pvs_bitset_test(a, 2));
        CHECK(!pvs_bitset_test(a, 3) && !pvs_bitset_test(a, 4));
        CHECK(pvs_sample_visibility_toward(s, &cell, NULL, 256, 11, b) == pvs_sample_visibility_toward(s, &cell, NULL, 256, 11, t));
        CHECK(b[0] == t[0]); /* deterministic */
        /* only the targets are aimed at; objects already set are skipped (no rays) */
        b[0] = 0; t[0] = 0;
        pvs_bitset_set(t, 3);
        pvs_sample_visibility_toward(s, &cell, t, 64, 5, b);
        CHECK(b[0] == 0 || b[0] == 1u || b[0] == 2u || b[0] == 3u); /* rays at 3 may stop on the wall only */
        b[0] = 0x1f;
        CHECK(pvs_sample_visibility_toward(s, &cell, NULL, 64, 5, b) == 0);
        CHECK(pvs_sample_visibility_toward(s, &cell, NULL, 0, 5, b) == 0);
        cell.min[0] = NAN;
        CHECK(pvs_sample_visibility_toward(s, &cell, NULL, 8, 5, a) == 0);
        pvs_scene_destroy(s);
    }
    tm_free(&m);
}

/* ---- bounded memory on adversarial input ---- */

/* The adversarial scenes of the bounded-memory tests, n triangles each:
   0 a fan (one polygon around a vertex: long slivers all meeting at one point), 1 the same standing
   up, 2 slivers crossing the scene in every direction through its middle, 3 one huge triangle and
   n - 1 tiny ones, 4 n copies of one triangle. per_object: every triangle its own object. */
static void adversarial_mesh(tmesh *m, int kind, uint32_t n) {
    uint32_t i;
    memset(m, 0, sizeof(*m));
    if (kind <= 1) {
        uint32_t c = kind ? tm_vertex(m, 0, 50, 0) : tm_vertex(m, 0, 5, 0);
        for (i = 0; i <= n; ++i) {
            double a = 6.283185307179586 * i / n;
            if (kind) tm_vertex(m, (float)(50 * cos(a)), (float)(50 + 50 * sin(a)), 0);
            else tm_vertex(m, (float)(50 * cos(a)), 5, (float)(50 * sin(a)));
        }
        for (i = 0; i < n; ++i) tm_tri(m, c, c + 1 + i, c + 2 + i);
    } else if (kind == 2) {
        for (i = 0; i < n; ++i) {
            double a = 3.141592653589793 * rnd(), y = 20 * rnd();
            float cx = (float)(50 * cos(a)), cz = (float)(50 * sin(a));
            uint32_t v = tm_vertex(m, -cx, (float)y, -cz);
            tm_vertex(m, cx, (float)y, cz);
            tm_vertex(m, cx, (float)y + 0.001f, cz);
            tm_tri(m, v, v + 1, v + 2);
        }
    } else if (kind == 3) {
        tm_tri(m, tm_vertex(m, -1e6f, 0, -1e6f), tm_vertex(m, 1e6f, 0, -1e6f), tm_vertex(m, 0, 0, 1e6f));
        for (i = 1; i < n; ++i) {
            float x = rndf(-50, 50), y = rndf(0, 20), z = rndf(-50, 50);
            uint32_t v = tm_vertex(m, x, y, z);
            tm_vertex(m, x + 1e-3f, y, z);
            tm_vertex(m, x, y + 1e-3f, z);
            tm_tri(m, v, v + 1, v + 2);
        }
    } else {
        uint32_t v = tm_vertex(m, -10, 0, -10);
        tm_vertex(m, 10, 0, -10);
        tm_vertex(m, 0, 10, 10);
        for (i = 0; i < n; ++i) tm_tri(m, v, v + 1, v + 2);
    }
}

/* The kD-tree's pools (pvs_kdtree_create): on the boxes of a fan's slivers, which overlap at its
   centre and duplicate at every split, the tree stays within PVS_KDTREE_MAX_REFS_PER_BOX and
   PVS_KDTREE_MAX_NODES_PER_BOX, its build within PVS_KDTREE_BUILD_BYTES_PER_BOX (linear, not
   the quadratic growth of an unbounded build: 1.07 GB at 20,000 before), and every query still
   finds every box (big leaves where the pools ran out). */
static void test_kdtree_pools(void) {
    static const uint32_t sizes[4] = {5000, 10000, 20000, 40000};
    double per_box[4];
    int si;
    for (si = 0; si < 4; ++si) {
        uint32_t n = sizes[si], i;
        pvs_box *boxes = (pvs_box *)malloc(n * sizeof(pvs_box));
        test_peak pc;
        pvs_kdtree_desc kd;
        pvs_kdtree *t = NULL;
        for (i = 0; i < n; ++i) { /* the triangle (0, 0, 0), rim i, rim i + 1 of a fan of radius 50 */
            double a0 = 6.283185307179586 * i / n, a1 = 6.283185307179586 * (i + 1) / n;
            float x0 = (float)(50 * cos(a0)), z0 = (float)(50 * sin(a0)), x1 = (float)(50 * cos(a1)), z1 = (float)(50 * sin(a1));
            boxes[i].min[0] = fminf(0, fminf(x0, x1)); boxes[i].max[0] = fmaxf(0, fmaxf(x0, x1));
            boxes[i].min[1] = boxes[i].max[1] = 5;
            boxes[i].min[2] = fminf(0, fminf(z0, z1)); boxes[i].max[2] = fmaxf(0, fmaxf(z0, z1));
        }
        memset(&kd, 0, sizeof(kd));
        kd.boxes = boxes;
        kd.count = n;
        kd.allocator = test_peak_allocator(&pc);
        CHECK(pvs_kdtree_create(&kd, &t, NULL) == PVS_OK);
        if (!t) { free(boxes); return; }
        per_box[si] = (double)pc.peak / n;
        CHECK(pc.peak <= (size_t)PVS_KDTREE_BUILD_BYTES_PER_BOX * n + PVS_KDTREE_BUILD_BYTES_FIXED);
        CHECK(pvs_kdtree_node_count(t) <= (uint64_t)PVS_KDTREE_MAX_NODES_PER_BOX * n + 1);
        CHECK(pc.now <= ((size_t)PVS_KDTREE_MAX_REFS_PER_BOX * 4 + PVS_KDTREE_MAX_NODES_PER_BOX * 8) * n + PVS_KDTREE_BUILD_BYTES_FIXED);
        fprintf(stderr, "  kdtree fan of %5u slivers: build peak %.0f bytes per box, tree %.0f, %u nodes\n", n, per_box[si],
                (double)pc.now / n, pvs_kdtree_node_count(t));
        if (si == 0) { /* every query still finds every box */
            static sweep_log lg;
            static unsigned char reached[5000];
            void *scratch = malloc(pvs_kdtree_sweep_scratch_size(t));
            pvs_box src;
            int bad = 0, all = 1;
            for (i = 0; i < 1500; ++i) {
                float p[3];
                p[0] = rndf(-50, 50); p[1] = i % 2 ? 5.0f : rndf(4, 6); p[2] = rndf(-50, 50);
                if (i % 8 == 0) p[0] = p[2] = 0.0f; /* the centre, in every box */
                if (!leaf_has_all(t, boxes, n, p)) ++bad;
            }
            CHECK(bad == 0);
            src.min[0] = src.max[0] = 60; src.min[1] = src.max[1] = 5; src.min[2] = src.max[2] = 3;
            sweep_log_init(&lg, boxes, n, &src, reached);
            CHECK(pvs_kdtree_sweep(t, &src, scratch, pvs_kdtree_sweep_scratch_size(t), sweep_visit, &lg) == PVS_OK);
            CHECK(lg.order_ok && lg.dist_ok && lg.leaf_ok);
            for (i = 0; i < n; ++i) all &= reached[i];
            CHECK(all);
            free(scratch);
        }
        pvs_kdtree_destroy(t);
        CHECK(pc.now == 0);
        free(boxes);
    }
    CHECK(per_box[3] <= per_box[0] * 1.25); /* linear: the bytes per box do not grow with the fan */
}

/* Where the pools run out, every part of the tree gets its share: slivers crossing the scene's middle in
   every direction (boxes 100 wide, 0.001 high) exhaust the refs pool, and a pool spent in build order
   (right children first) left the last-built side in a few huge leaves: rays met a leaf of 2,454 boxes
   of 5,000, 9,943 of 20,000 (a Nexuiz map's triangle tree: one of 48,319, its rays about 400 times slower).
   Shared by the children's ref counts, the largest leaf rays meet is under n / 16 (74 and 1,058). */
static float largest_leaf(void *user, const uint32_t *items, uint32_t count, float t_enter, float t_exit) {
    uint32_t *most = (uint32_t *)user;
    (void)items; (void)t_enter; (void)t_exit;
    if (count > *most) *most = count;
    return 1e30f;
}
static void test_kdtree_pools_shared(void) {
    static const uint32_t sizes[2] = {5000, 20000};
    uint64_t rng = 30; /* its own: the later tests' rays stay as they were */
    int si;
    for (si = 0; si < 2; ++si) {
        uint32_t n = sizes[si], i, most = 0;
        pvs_box *boxes = (pvs_box *)malloc(n * sizeof(pvs_box));
        pvs_kdtree_desc kd;
        pvs_kdtree *t = NULL;
        for (i = 0; i < n; ++i) {
            double a = 3.141592653589793 * test_rnd(&rng);
            float cx = (float)(50 * cos(a)), cz = (float)(50 * sin(a)), y = test_rndf(&rng, 0, 20);
            boxes[i].min[0] = fminf(-cx, cx); boxes[i].max[0] = fmaxf(-cx, cx);
            boxes[i].min[1] = y; boxes[i].max[1] = y + 0.001f;
            boxes[i].min[2] = fminf(-cz, cz); boxes[i].max[2] = fmaxf(-cz, cz);
        }
        memset(&kd, 0, sizeof(kd));
        kd.boxes = boxes;
        kd.count = n;
        CHECK(pvs_kdtree_create(&kd, &t, NULL) == PVS_OK);
        if (!t) { free(boxes); return; }
        CHECK(pvs_kdtree_node_count(t) > n); /* the pools ran out after real splitting, not at the root */
        for (i = 0; i < 1000; ++i) {
            float o[3], d[3] = {120, 0, 0};
            o[0] = -60; o[1] = test_rndf(&rng, 0, 20); o[2] = test_rndf(&rng, -50, 50); d[2] = test_rndf(&rng, -10, 10);
            pvs_kdtree_ray(t, o, d, 1.0f, largest_leaf, &most);
        }
        CHECK(most < n / 16);
        fprintf(stderr, "  kdtree %u crossing slivers: rays met a leaf of %u boxes\n", n, most);
        pvs_kdtree_destroy(t);
        free(boxes);
    }
}

/* pvs_scene_create on the adversarial scenes: within the documented bound (PVS_SCENE_BYTES_PER_*),
   and ray casts that agree with brute force through the big leaves. */
static void test_scene_adversarial(void) {
    int kind, per_object;
    for (kind = 0; kind < 5; ++kind)
        for (per_object = 0; per_object < 2; ++per_object) {
            uint32_t n = per_object ? 1000 : 3000, i, nobj = per_object ? n : 1;
            tmesh m;
            pvs_object_desc *od;
            pvs_scene_desc sd;
            pvs_scene *s = NULL;
            test_peak pc;
            pvs_error err;
            size_t bound;
            adversarial_mesh(&m, kind, n);
            od = (pvs_object_desc *)calloc(nobj, sizeof(pvs_object_desc));
            for (i = 0; i < nobj; ++i) {
                od[i].first_triangle = per_object ? i : 0;
                od[i].triangle_count = per_object ? 1 : m.tc;
            }
            memset(&sd, 0, sizeof(sd));
            sd.positions = m.pos;
            sd.vertex_count = m.vc;
            sd.indices = m.idx;
            sd.triangle_count = m.tc;
            sd.objects = od;
            sd.object_count = nobj;
            sd.flags = PVS_SCENE_ALLOW_EMPTY_OBJECTS; /* the tiny triangles may round to zero area */
            sd.allocator = test_peak_allocator(&pc);
            CHECK(pvs_scene_create(&sd, &s, &err) == PVS_OK);
            bound = (size_t)PVS_SCENE_BYTES_PER_TRIANGLE * m.tc + (size_t)PVS_SCENE_BYTES_PER_OBJECT * nobj + 12 * (size_t)m.vc +
                    PVS_SCENE_BYTES_FIXED;
            CHECK(pc.peak <= bound);
            if (pc.peak > bound) fprintf(stderr, "  scene kind %d: peak %zu > bound %zu\n", kind, pc.peak, bound);
            if (s && !per_object) {
                float lo[3] = {-60, -2, -60}, hi[3] = {60, 60, 60};
                compare_rays_ex(&m, s, lo, hi, 400, 1);
            }
            pvs_scene_destroy(s);
            CHECK(pc.now == 0);
            free(od);
            tm_free(&m);
        }
}

void test_kdtree(void) {
    test_kdtree_pools();
    test_kdtree_pools_shared();
    test_scene_adversarial();
    test_kdtree_edge_cases();
    test_kdtree_sweep();
    test_kdtree_point_location();
    test_kdtree_ray();
    test_raycast_soup();
    test_raycast_city();
    test_raycast_watertight();
    test_sample_visibility();
    test_sample_visibility_toward();
}
