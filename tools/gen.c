/* gen.c - see gen.h */
#include "gen.h"
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#if defined(__clang__)
#pragma STDC FP_CONTRACT OFF
#endif

/* ------------------------------------------------------------------------------------------------
   PRNG (splitmix64), small helpers */

typedef struct gen__rng { uint64_t s; } gen__rng;

static uint64_t gen__next(gen__rng *r) {
    uint64_t z = (r->s += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}
static double gen__u(gen__rng *r) { return (double)(gen__next(r) >> 11) * (1.0 / 9007199254740992.0); }
static double gen__rf(gen__rng *r, double a, double b) { return a + (b - a) * gen__u(r); }
static uint32_t gen__ri(gen__rng *r, uint32_t n) { return (uint32_t)(((gen__next(r) >> 32) * (uint64_t)n) >> 32); }
static int gen__chance(gen__rng *r, double p) { return gen__u(r) < p; }

static double gen__min(double a, double b) { return a < b ? a : b; }
static double gen__max(double a, double b) { return a > b ? a : b; }
static double gen__clamp(double v, double a, double b) { return v < a ? a : v > b ? b : v; }
static int gen__iround(double v) { return (int)floor(v + 0.5); }

static int gen__grow(void **p, size_t *cap, size_t need, size_t elem) {
    if (need <= *cap) return 0;
    size_t n = *cap ? *cap * 2 : 64;
    while (n < need) n *= 2;
    if (n > (size_t)-1 / elem) return -1;
    void *q = realloc(*p, n * elem);
    if (!q) return -1;
    *p = q;
    *cap = n;
    return 0;
}

typedef struct gen__p2 { double x, z; } gen__p2;
typedef struct gen__r2 { double x0, z0, x1, z1; } gen__r2;

static int gen__r2_overlap(gen__r2 a, gen__r2 b, double margin) {
    return a.x0 - margin <= b.x1 && b.x0 <= a.x1 + margin && a.z0 - margin <= b.z1 && b.z0 <= a.z1 + margin;
}

/* ------------------------------------------------------------------------------------------------
   Output context: sticky error flag, so the emitters stay short. */

typedef struct gen__ctx {
    mesh *m;
    mesh_cells *cells;
    gen__rng rng;
    int err;
} gen__ctx;

static void gen__obj(gen__ctx *c, const char *fmt, ...) {
    char name[96];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(name, sizeof name, fmt, ap);
    va_end(ap);
    if (mesh_begin_object(c->m, name, 0, 0)) c->err = 1;
}
static uint32_t gen__v(gen__ctx *c, double x, double y, double z) {
    uint32_t i = c->m->vertex_count;
    if (mesh_add_vertex(c->m, (float)x, (float)y, (float)z)) c->err = 1;
    return i;
}
static void gen__tri(gen__ctx *c, uint32_t a, uint32_t b, uint32_t d) {
    if (mesh_add_triangle(c->m, a, b, d)) c->err = 1;
}
static void gen__quad(gen__ctx *c, uint32_t a, uint32_t b, uint32_t d, uint32_t e) {
    if (mesh_add_quad(c->m, a, b, d, e)) c->err = 1;
}
static void gen__cell(gen__ctx *c, double x0, double y0, double z0, double x1, double y1, double z1) {
    float b[6];
    b[0] = (float)x0; b[1] = (float)y0; b[2] = (float)z0;
    b[3] = (float)x1; b[4] = (float)y1; b[5] = (float)z1;
    if (mesh_cells_add(c->cells, b)) c->err = 1;
}

/* Parallelepiped o + a*e0 + b*e1 + c*e2, a, b, c in [0, 1]: 8 vertices, 12 outward-wound triangles. */
static void gen__box(gen__ctx *c, const double o[3], const double e0[3], const double e1[3], const double e2[3]) {
    static const unsigned char f[6][4] = {{0, 4, 6, 2}, {1, 3, 7, 5}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 2, 3, 1}, {4, 5, 7, 6}};
    double det = e0[0] * (e1[1] * e2[2] - e1[2] * e2[1]) - e0[1] * (e1[0] * e2[2] - e1[2] * e2[0]) +
                 e0[2] * (e1[0] * e2[1] - e1[1] * e2[0]);
    uint32_t base = c->m->vertex_count;
    for (int i = 0; i < 8; ++i) {
        double a = (double)(i & 1), b = (double)((i >> 1) & 1), d = (double)((i >> 2) & 1);
        gen__v(c, o[0] + a * e0[0] + b * e1[0] + d * e2[0], o[1] + a * e0[1] + b * e1[1] + d * e2[1],
               o[2] + a * e0[2] + b * e1[2] + d * e2[2]);
    }
    for (int k = 0; k < 6; ++k) {
        if (det > 0) gen__quad(c, base + f[k][0], base + f[k][1], base + f[k][2], base + f[k][3]);
        else gen__quad(c, base + f[k][0], base + f[k][3], base + f[k][2], base + f[k][1]);
    }
}
static void gen__aabox(gen__ctx *c, double x0, double y0, double z0, double x1, double y1, double z1) {
    double o[3] = {x0, y0, z0}, e0[3] = {x1 - x0, 0, 0}, e1[3] = {0, y1 - y0, 0}, e2[3] = {0, 0, z1 - z0};
    gen__box(c, o, e0, e1, e2);
}
/* Horizontal quad at height y over [x0,x1] x [z0,z1], facing up (or down). */
static void gen__hquad(gen__ctx *c, double x0, double z0, double x1, double z1, double y, int down) {
    uint32_t a = gen__v(c, x0, y, z0), b = gen__v(c, x1, y, z0), d = gen__v(c, x1, y, z1), e = gen__v(c, x0, y, z1);
    if (down) gen__quad(c, a, b, d, e); /* normal -y */
    else gen__quad(c, a, e, d, b);      /* normal +y */
}

/* Exact triangle / box overlap (separating axis test, Akenine-Moeller 2001); touching counts as overlap. */
static int gen__tri_box(const double bmin[3], const double bmax[3], const float *p0, const float *p1, const float *p2) {
    double c[3], h[3], v[3][3], e[3][3];
    for (int i = 0; i < 3; ++i) {
        c[i] = 0.5 * (bmin[i] + bmax[i]);
        h[i] = 0.5 * (bmax[i] - bmin[i]);
        v[0][i] = p0[i] - c[i]; v[1][i] = p1[i] - c[i]; v[2][i] = p2[i] - c[i];
    }
    for (int i = 0; i < 3; ++i) {
        double lo = gen__min(v[0][i], gen__min(v[1][i], v[2][i])), hi = gen__max(v[0][i], gen__max(v[1][i], v[2][i]));
        if (lo > h[i] || hi < -h[i]) return 0;
    }
    for (int k = 0; k < 3; ++k)
        for (int i = 0; i < 3; ++i) e[k][i] = v[(k + 1) % 3][i] - v[k][i];
    double axes[10][3];
    int na = 0;
    axes[na][0] = e[0][1] * e[1][2] - e[0][2] * e[1][1];
    axes[na][1] = e[0][2] * e[1][0] - e[0][0] * e[1][2];
    axes[na][2] = e[0][0] * e[1][1] - e[0][1] * e[1][0];
    ++na;
    for (int b = 0; b < 3; ++b)
        for (int k = 0; k < 3; ++k) { /* unit axis b cross edge k */
            double u[3] = {0, 0, 0}, *a = axes[na++];
            u[b] = 1;
            a[0] = u[1] * e[k][2] - u[2] * e[k][1];
            a[1] = u[2] * e[k][0] - u[0] * e[k][2];
            a[2] = u[0] * e[k][1] - u[1] * e[k][0];
        }
    for (int k = 0; k < na; ++k) {
        const double *a = axes[k];
        double d0 = a[0] * v[0][0] + a[1] * v[0][1] + a[2] * v[0][2];
        double d1 = a[0] * v[1][0] + a[1] * v[1][1] + a[2] * v[1][2];
        double d2 = a[0] * v[2][0] + a[1] * v[2][1] + a[2] * v[2][2];
        double r = h[0] * fabs(a[0]) + h[1] * fabs(a[1]) + h[2] * fabs(a[2]);
        if (gen__min(d0, gen__min(d1, d2)) > r || gen__max(d0, gen__max(d1, d2)) < -r) return 0;
    }
    return 1;
}

/* Object bounding boxes (6 floats each) for the spatial checks after a scene is built. */
static float *gen__object_boxes(const mesh *m) {
    float *bb = (float *)malloc(sizeof(float) * 6 * (m->object_count ? m->object_count : 1));
    if (!bb) return NULL;
    for (uint32_t o = 0; o < m->object_count; ++o) {
        float *b = bb + 6 * (size_t)o;
        b[0] = b[1] = b[2] = 1e30f;
        b[3] = b[4] = b[5] = -1e30f;
        const mesh_object *ob = &m->objects[o];
        for (uint32_t t = ob->first_triangle; t < ob->first_triangle + ob->triangle_count; ++t)
            for (int k = 0; k < 3; ++k) {
                const float *p = m->positions + 3 * (size_t)m->indices[3 * (size_t)t + k];
                for (int i = 0; i < 3; ++i) {
                    if (p[i] < b[i]) b[i] = p[i];
                    if (p[i] > b[3 + i]) b[3 + i] = p[i];
                }
            }
    }
    return bb;
}

/* Does box[6] touch any triangle of objects [first, m->object_count)? */
static int gen__box_hits(const mesh *m, const float *obb, uint32_t first, const double box[6]) {
    for (uint32_t o = first; o < m->object_count; ++o) {
        const float *b = obb + 6 * (size_t)o;
        if (b[0] > box[3] || b[3] < box[0] || b[1] > box[4] || b[4] < box[1] || b[2] > box[5] || b[5] < box[2]) continue;
        const mesh_object *ob = &m->objects[o];
        for (uint32_t t = ob->first_triangle; t < ob->first_triangle + ob->triangle_count; ++t) {
            const uint32_t *ix = m->indices + 3 * (size_t)t;
            if (gen__tri_box(box, box + 3, m->positions + 3 * (size_t)ix[0], m->positions + 3 * (size_t)ix[1],
                             m->positions + 3 * (size_t)ix[2]))
                return 1;
        }
    }
    return 0;
}

/* Keep an evenly spread subset of cells [first, count) so that at most keep remain there. */
static void gen__thin_cells(mesh_cells *c, uint32_t first, uint32_t keep) {
    uint32_t n = c->count - first;
    if (n <= keep) return;
    for (uint32_t i = 0; i < keep; ++i) {
        uint32_t src = first + (uint32_t)(((uint64_t)i * n) / keep);
        memmove(c->boxes + 6 * (size_t)(first + i), c->boxes + 6 * (size_t)src, 6 * sizeof(float));
    }
    c->count = first + keep;
}

/* ------------------------------------------------------------------------------------------------
   City */

typedef struct gen__bldg {
    int n;
    gen__p2 p[16]; /* outer footprint, clockwise in (x, z) (outward = left of each edge) */
    gen__r2 bb;
} gen__bldg;

typedef struct gen__city {
    gen__ctx *c;
    gen__bldg *b;
    size_t nb, capb;
    gen__r2 *obst; /* street objects' footprints (below eye height) */
    size_t nobst, capobst;
    gen__p2 *quad; /* built blocks (4 corners each): no cells in yards */
    size_t nquad, capquad;
    int max_level; /* cell tiles: split max_level times, then into strips */
    /* bucket grid over everything cells must avoid: item = kind << 30 | index (0 building, 1 street
       object, 2 block outline) */
    double gx0, gz0, gcell;
    int gnx, gnz;
    uint32_t *gstart, *gitem;
    uint32_t n_building, n_lamp, n_kiosk;
} gen__city;

static double gen__cross(gen__p2 a, gen__p2 b, gen__p2 c) { return (b.x - a.x) * (c.z - a.z) - (b.z - a.z) * (c.x - a.x); }

static double gen__area2(const gen__p2 *p, int n) {
    double s = 0;
    for (int i = 0; i < n; ++i) {
        gen__p2 a = p[i], b = p[(i + 1) % n];
        s += a.x * b.z - b.x * a.z;
    }
    return s;
}

/* Ear clipping of a simple polygon (n <= 16); writes triangles as index triples in the polygon's
   own orientation. Returns the number of triangles. */
static int gen__earclip(const gen__p2 *p, int n, int *tri) {
    int idx[16], m = n, nt = 0;
    double s = gen__area2(p, n) < 0 ? -1.0 : 1.0;
    for (int i = 0; i < n; ++i) idx[i] = i;
    while (m > 3) {
        int best = -1;
        for (int k = 0; k < m && best < 0; ++k) {
            int ip = idx[(k + m - 1) % m], ic = idx[k], in = idx[(k + 1) % m];
            if (gen__cross(p[ip], p[ic], p[in]) * s <= 1e-9) continue;
            int ok = 1;
            for (int q = 0; q < m && ok; ++q) {
                int iq = idx[q];
                if (iq == ip || iq == ic || iq == in) continue;
                if (gen__cross(p[ip], p[ic], p[iq]) * s >= 0 && gen__cross(p[ic], p[in], p[iq]) * s >= 0 &&
                    gen__cross(p[in], p[ip], p[iq]) * s >= 0)
                    ok = 0;
            }
            if (ok) best = k;
        }
        if (best < 0) { /* numerically stuck: take the most convex vertex */
            double bc = 1e-9;
            for (int k = 0; k < m; ++k) {
                double cr = gen__cross(p[idx[(k + m - 1) % m]], p[idx[k]], p[idx[(k + 1) % m]]) * s;
                if (cr > bc) { bc = cr; best = k; }
            }
            if (best < 0) return nt;
        }
        tri[3 * nt] = idx[(best + m - 1) % m];
        tri[3 * nt + 1] = idx[best];
        tri[3 * nt + 2] = idx[(best + 1) % m];
        ++nt;
        for (int k = best; k < m - 1; ++k) idx[k] = idx[k + 1];
        --m;
    }
    if (gen__cross(p[idx[0]], p[idx[1]], p[idx[2]]) * s > 1e-9) {
        tri[3 * nt] = idx[0]; tri[3 * nt + 1] = idx[1]; tri[3 * nt + 2] = idx[2];
        ++nt;
    }
    return nt;
}

/* A thin box in front of the wall a->b (unit direction d, outward normal n): along [s0, s1],
   height [y0, y1], distance from the wall [f0, f1]. */
static void gen__wallbox(gen__ctx *c, gen__p2 a, gen__p2 d, gen__p2 n, double s0, double s1, double y0, double y1,
                         double f0, double f1) {
    double o[3] = {a.x + d.x * s0 + n.x * f0, y0, a.z + d.z * s0 + n.z * f0};
    double e0[3] = {d.x * (s1 - s0), 0, d.z * (s1 - s0)}, e1[3] = {0, y1 - y0, 0}, e2[3] = {n.x * (f1 - f0), 0, n.z * (f1 - f0)};
    gen__box(c, o, e0, e1, e2);
}

static void gen__facade(gen__ctx *c, gen__rng *r, gen__p2 a, gen__p2 b, double h, int detail) {
    double dx = b.x - a.x, dz = b.z - a.z, len = sqrt(dx * dx + dz * dz);
    if (len < 2.5) return;
    gen__p2 d = {dx / len, dz / len}, n = {-dz / len, dx / len};
    const double fh = 3.5;
    int floors = (int)(h / fh);
    gen__wallbox(c, a, d, n, 0.45, len - 0.45, h - 0.55, h - 0.1, 0.01, 0.4); /* cornice */
    for (int k = 1; k < floors; ++k) /* ledges above the ground floor and every third floor */
        if (k == 1 || k % 3 == 0) gen__wallbox(c, a, d, n, 0.3, len - 0.3, k * fh - 0.15, k * fh, 0.01, 0.22);
    if (detail == 0) return;
    double sp = detail == 2 ? 3.2 : 7.0;
    int slots = (int)((len - 2.6) / sp);
    if (slots < 1) return;
    double s0 = (len - slots * sp) / 2 + sp / 2;
    for (int k = 0; k < floors; ++k) {
        if (k * fh + 2.6 > h - 0.6) break;
        for (int i = 0; i < slots; ++i) {
            double sc = s0 + i * sp, y = k * fh;
            gen__wallbox(c, a, d, n, sc - 0.6, sc + 0.6, y + 0.9, y + 2.5, 0.01, 0.08); /* window box */
            if (detail == 2 && k >= 1 && gen__chance(r, 0.12)) {                         /* balcony */
                gen__wallbox(c, a, d, n, sc - 1.1, sc + 1.1, y, y + 0.15, 0.01, 1.2);
                gen__wallbox(c, a, d, n, sc - 1.1, sc + 1.1, y + 0.15, y + 1.05, 1.12, 1.2);
            }
        }
    }
}

/* Emits building_N: walls, roof, facade detail. poly: clockwise (area2 < 0). hole: 4 inner corners
   (also clockwise, hole[k] near poly[k]) for a courtyard building. */
static int gen__building(gen__city *C, const gen__p2 *poly, int n, const gen__p2 *hole, double h, int detail) {
    gen__ctx *c = C->c;
    gen__obj(c, "building_%u", C->n_building++);
    uint32_t bot = c->m->vertex_count;
    for (int i = 0; i < n; ++i) gen__v(c, poly[i].x, 0, poly[i].z);
    uint32_t top = c->m->vertex_count;
    for (int i = 0; i < n; ++i) gen__v(c, poly[i].x, h, poly[i].z);
    for (int i = 0; i < n; ++i) {
        uint32_t j = (uint32_t)((i + 1) % n);
        gen__quad(c, bot + (uint32_t)i, bot + j, top + j, top + (uint32_t)i);
    }
    if (hole) {
        uint32_t hb = c->m->vertex_count;
        for (int i = 0; i < 4; ++i) gen__v(c, hole[i].x, 0, hole[i].z);
        uint32_t ht = c->m->vertex_count;
        for (int i = 0; i < 4; ++i) gen__v(c, hole[i].x, h, hole[i].z);
        for (uint32_t i = 0; i < 4; ++i) {
            uint32_t j = (i + 1) % 4;
            gen__quad(c, hb + j, hb + i, ht + i, ht + j);
            gen__quad(c, top + i, top + j, ht + j, ht + i);
        }
    } else {
        int tri[3 * 16];
        int nt = gen__earclip(poly, n, tri);
        for (int t = 0; t < nt; ++t) gen__tri(c, top + (uint32_t)tri[3 * t], top + (uint32_t)tri[3 * t + 1], top + (uint32_t)tri[3 * t + 2]);
    }
    for (int i = 0; i < n; ++i) gen__facade(c, &c->rng, poly[i], poly[(i + 1) % n], h, detail);
    if (gen__grow((void **)&C->b, &C->capb, C->nb + 1, sizeof(gen__bldg))) return -1;
    gen__bldg *B = &C->b[C->nb++];
    B->n = n;
    B->bb.x0 = B->bb.z0 = 1e30;
    B->bb.x1 = B->bb.z1 = -1e30;
    for (int i = 0; i < n; ++i) {
        B->p[i] = poly[i];
        B->bb.x0 = gen__min(B->bb.x0, poly[i].x); B->bb.x1 = gen__max(B->bb.x1, poly[i].x);
        B->bb.z0 = gen__min(B->bb.z0, poly[i].z); B->bb.z1 = gen__max(B->bb.z1, poly[i].z);
    }
    return c->err ? -1 : 0;
}

static int gen__add_obst(gen__city *C, double x0, double z0, double x1, double z1) {
    if (gen__grow((void **)&C->obst, &C->capobst, C->nobst + 1, sizeof(gen__r2))) return -1;
    gen__r2 r = {x0, z0, x1, z1};
    C->obst[C->nobst++] = r;
    return 0;
}

static gen__p2 gen__bilerp(const gen__p2 q[4], double u, double v) {
    gen__p2 p;
    p.x = (1 - u) * (1 - v) * q[0].x + u * (1 - v) * q[1].x + u * v * q[2].x + (1 - u) * v * q[3].x;
    p.z = (1 - u) * (1 - v) * q[0].z + u * (1 - v) * q[1].z + u * v * q[2].z + (1 - u) * v * q[3].z;
    return p;
}

static double gen__dist(gen__p2 a, gen__p2 b) { return sqrt((a.x - b.x) * (a.x - b.x) + (a.z - b.z) * (a.z - b.z)); }

/* One building on the lot [u0,u1] x [v0,v1] of block quad q (metric size lw x ld). */
static int gen__lot(gen__city *C, const gen__p2 q[4], double u0, double v0, double u1, double v1, double lw, double ld,
                    double h, int force_courtyard) {
    gen__rng *r = &C->c->rng;
    gen__p2 s[16], hole[4], w[16], wh[4];
    memset(w, 0, sizeof w);
    memset(wh, 0, sizeof wh);
    int n = 0, has_hole = 0;
    double mn = gen__min(lw, ld);
#define GEN__WING(len, lo, hi) gen__clamp(gen__rf(r, 7.0, 13.0) / (len), (lo), (hi))
#define GEN__PT(a, b) (s[n].x = (a), s[n].z = (b), ++n)
    int shape; /* 0 rect, 1 L, 2 U, 3 T, 4 Z, 5 star, 6 courtyard */
    if (force_courtyard || (mn >= 30 && gen__chance(r, 0.3))) shape = 6;
    else if (mn < 14) shape = gen__chance(r, 0.5) ? 0 : 1;
    else {
        static const unsigned char pick[20] = {0, 0, 1, 1, 1, 1, 1, 2, 2, 2, 2, 3, 3, 4, 4, 4, 5, 5, 5, 1};
        shape = pick[gen__ri(r, 20)];
    }
    switch (shape) {
    case 0: GEN__PT(0, 0); GEN__PT(1, 0); GEN__PT(1, 1); GEN__PT(0, 1); break;
    case 1: {
        double a = GEN__WING(ld, 0.3, 0.7), b = GEN__WING(lw, 0.3, 0.7);
        GEN__PT(0, 0); GEN__PT(1, 0); GEN__PT(1, a); GEN__PT(b, a); GEN__PT(b, 1); GEN__PT(0, 1);
    } break;
    case 2: {
        double wg = GEN__WING(lw, 0.2, 0.38), d = GEN__WING(ld, 0.25, 0.6);
        GEN__PT(0, 0); GEN__PT(1, 0); GEN__PT(1, 1); GEN__PT(1 - wg, 1); GEN__PT(1 - wg, d); GEN__PT(wg, d); GEN__PT(wg, 1); GEN__PT(0, 1);
    } break;
    case 3: {
        double wg = GEN__WING(lw, 0.25, 0.5), a = GEN__WING(ld, 0.25, 0.6), c0 = gen__rf(r, 0.15, 0.85 - wg);
        GEN__PT(c0, 0); GEN__PT(c0 + wg, 0); GEN__PT(c0 + wg, 1 - a); GEN__PT(1, 1 - a); GEN__PT(1, 1); GEN__PT(0, 1); GEN__PT(0, 1 - a); GEN__PT(c0, 1 - a);
    } break;
    case 4: {
        double a1 = gen__rf(r, 0.2, 0.4), a2 = gen__rf(r, 0.2, 0.4), b1 = gen__rf(r, 0.2, 0.45), b2 = gen__rf(r, 0.2, 0.45);
        GEN__PT(0, a1); GEN__PT(b1, a1); GEN__PT(b1, 0); GEN__PT(1, 0); GEN__PT(1, 1 - a2); GEN__PT(1 - b2, 1 - a2); GEN__PT(1 - b2, 1); GEN__PT(0, 1);
    } break;
    case 5: {
        int k = 7 + (int)gen__ri(r, 6);
        for (int i = 0; i < k; ++i) {
            double tp = (i + 0.15 + 0.7 * gen__u(r)) / k * 4.0, f, x, z, pull = gen__rf(r, 0.55, 1.0);
            int seg = (int)tp;
            f = tp - seg;
            if (seg == 0) { x = f; z = 0; }
            else if (seg == 1) { x = 1; z = f; }
            else if (seg == 2) { x = 1 - f; z = 1; }
            else { x = 0; z = 1 - f; }
            GEN__PT(0.5 + (x - 0.5) * pull, 0.5 + (z - 0.5) * pull);
        }
    } break;
    default: {
        double a0 = gen__rf(r, 8, 13) / lw, a1 = gen__rf(r, 8, 13) / lw, b0 = gen__rf(r, 8, 13) / ld, b1 = gen__rf(r, 8, 13) / ld;
        if (a0 + a1 > 0.8) a0 = a1 = 0.3;
        if (b0 + b1 > 0.8) b0 = b1 = 0.3;
        has_hole = 1;
        GEN__PT(0, 0); GEN__PT(1, 0); GEN__PT(1, 1); GEN__PT(0, 1);
        hole[0].x = a0; hole[0].z = b0; hole[1].x = 1 - a1; hole[1].z = b0;
        hole[2].x = 1 - a1; hole[2].z = 1 - b1; hole[3].x = a0; hole[3].z = 1 - b1;
    } break;
    }
#undef GEN__PT
#undef GEN__WING
    /* random symmetry, then map lot space -> block parameter space -> world */
    int fx = gen__chance(r, 0.5), fz = gen__chance(r, 0.5);
    for (int i = 0; i < n + (has_hole ? 4 : 0); ++i) {
        gen__p2 *p = i < n ? &s[i] : &hole[i - n];
        double x = fx ? 1 - p->x : p->x, z = fz ? 1 - p->z : p->z;
        gen__p2 wp = gen__bilerp(q, u0 + x * (u1 - u0), v0 + z * (v1 - v0));
        if (i < n) w[i] = wp;
        else wh[i - n] = wp;
    }
    if (gen__area2(w, n) > 0) { /* make clockwise */
        for (int i = 0; i < n / 2; ++i) { gen__p2 t = w[i]; w[i] = w[n - 1 - i]; w[n - 1 - i] = t; }
        if (has_hole) { gen__p2 t = wh[0]; wh[0] = wh[3]; wh[3] = t; t = wh[1]; wh[1] = wh[2]; wh[2] = t; }
    }
    double dr = gen__u(r);
    int detail = dr < 0.55 ? 0 : dr < 0.92 ? 1 : 2; /* cornices + ledges / + windows / + dense windows, balconies */
    return gen__building(C, w, n, has_hole ? wh : NULL, h, detail);
}

/* Offset line intersection: lines p1 + t d1 and p2 + s d2. */
static gen__p2 gen__isect(gen__p2 p1, gen__p2 d1, gen__p2 p2, gen__p2 d2) {
    double den = d1.x * d2.z - d1.z * d2.x;
    double t = ((p2.x - p1.x) * d2.z - (p2.z - p1.z) * d2.x) / den;
    gen__p2 p = {p1.x + d1.x * t, p1.z + d1.z * t};
    return p;
}

static void gen__lamp(gen__city *C, gen__p2 p, gen__p2 out) {
    gen__ctx *c = C->c;
    gen__obj(c, "lamp_%u", C->n_lamp++);
    gen__aabox(c, p.x - 0.08, 0, p.z - 0.08, p.x + 0.08, 4.6, p.z + 0.08);
    gen__p2 side = {-out.z, out.x};
    double o[3] = {p.x + out.x * 0.08 - side.x * 0.04, 4.4, p.z + out.z * 0.08 - side.z * 0.04};
    double e0[3] = {out.x * 1.1, 0, out.z * 1.1}, e1[3] = {0, 0.08, 0}, e2[3] = {side.x * 0.08, 0, side.z * 0.08};
    gen__box(c, o, e0, e1, e2);
    double hx = p.x + out.x * 1.05, hz = p.z + out.z * 1.05;
    gen__aabox(c, hx - 0.2, 4.1, hz - 0.2, hx + 0.2, 4.4, hz + 0.2);
    if (gen__add_obst(C, p.x - 0.08, p.z - 0.08, p.x + 0.08, p.z + 0.08)) c->err = 1;
}

static void gen__kiosk(gen__city *C, gen__p2 p) {
    gen__ctx *c = C->c;
    gen__obj(c, "kiosk_%u", C->n_kiosk++);
    gen__aabox(c, p.x - 1.1, 0, p.z - 1.1, p.x + 1.1, 2.6, p.z + 1.1);
    gen__aabox(c, p.x - 1.4, 2.6, p.z - 1.4, p.x + 1.4, 2.9, p.z + 1.4);
    if (gen__add_obst(C, p.x - 1.4, p.z - 1.4, p.x + 1.4, p.z + 1.4)) c->err = 1;
}

/* Segment / closed rectangle intersection. */
static int gen__seg_rect(gen__p2 a, gen__p2 b, gen__r2 R) {
    if (gen__max(a.x, b.x) < R.x0 || gen__min(a.x, b.x) > R.x1 || gen__max(a.z, b.z) < R.z0 || gen__min(a.z, b.z) > R.z1) return 0;
    gen__p2 cs[4] = {{R.x0, R.z0}, {R.x1, R.z0}, {R.x1, R.z1}, {R.x0, R.z1}};
    int pos = 0, neg = 0;
    for (int i = 0; i < 4; ++i) {
        double cr = gen__cross(a, b, cs[i]);
        if (cr >= 0) ++pos;
        if (cr <= 0) ++neg;
    }
    return pos && neg;
}

static int gen__poly_rect(const gen__p2 *p, int n, gen__r2 R) {
    for (int i = 0; i < n; ++i) {
        if (p[i].x >= R.x0 && p[i].x <= R.x1 && p[i].z >= R.z0 && p[i].z <= R.z1) return 1;
        if (gen__seg_rect(p[i], p[(i + 1) % n], R)) return 1;
    }
    double cx = 0.5 * (R.x0 + R.x1), cz = 0.5 * (R.z0 + R.z1);
    int in = 0;
    for (int i = 0, j = n - 1; i < n; j = i++)
        if ((p[i].z > cz) != (p[j].z > cz) && cx < (p[j].x - p[i].x) * (cz - p[i].z) / (p[j].z - p[i].z) + p[i].x) in = !in;
    return in;
}

static gen__r2 gen__city_item_box(const gen__city *C, int kind, size_t i) {
    if (kind == 0) return C->b[i].bb;
    if (kind == 1) return C->obst[i];
    gen__r2 r = {1e30, 1e30, -1e30, -1e30};
    for (int k = 0; k < 4; ++k) {
        gen__p2 p = C->quad[4 * i + k];
        r.x0 = gen__min(r.x0, p.x); r.x1 = gen__max(r.x1, p.x);
        r.z0 = gen__min(r.z0, p.z); r.z1 = gen__max(r.z1, p.z);
    }
    return r;
}

static void gen__city_range(const gen__city *C, gen__r2 r, int *i0, int *j0, int *i1, int *j1) {
    *i0 = (int)floor((r.x0 - C->gx0) / C->gcell); *i1 = (int)floor((r.x1 - C->gx0) / C->gcell);
    *j0 = (int)floor((r.z0 - C->gz0) / C->gcell); *j1 = (int)floor((r.z1 - C->gz0) / C->gcell);
    if (*i0 < 0) *i0 = 0;
    if (*j0 < 0) *j0 = 0;
    if (*i1 > C->gnx - 1) *i1 = C->gnx - 1;
    if (*j1 > C->gnz - 1) *j1 = C->gnz - 1;
}

/* Buckets every building, street object and block outline by its bounding box (0.5 m margin). */
static int gen__city_grid(gen__city *C, double x0, double z0, double x1, double z1) {
    C->gcell = 32.0;
    C->gx0 = x0;
    C->gz0 = z0;
    C->gnx = (int)ceil((x1 - x0) / C->gcell) + 1;
    C->gnz = (int)ceil((z1 - z0) / C->gcell) + 1;
    size_t nbk = (size_t)C->gnx * (size_t)C->gnz, counts[3] = {C->nb, C->nobst, C->nquad};
    C->gstart = (uint32_t *)calloc(nbk + 1, sizeof(uint32_t));
    if (!C->gstart) return -1;
    for (int pass = 0; pass < 2; ++pass) {
        for (int kind = 0; kind < 3; ++kind)
            for (size_t i = 0; i < counts[kind]; ++i) {
                gen__r2 r = gen__city_item_box(C, kind, i);
                int i0, j0, i1, j1;
                r.x0 -= 0.5; r.z0 -= 0.5; r.x1 += 0.5; r.z1 += 0.5;
                gen__city_range(C, r, &i0, &j0, &i1, &j1);
                for (int j = j0; j <= j1; ++j)
                    for (int k = i0; k <= i1; ++k) {
                        size_t b = (size_t)j * C->gnx + k;
                        if (pass == 0) ++C->gstart[b + 1];
                        else C->gitem[C->gstart[b]++] = (uint32_t)kind << 30 | (uint32_t)i;
                    }
            }
        if (pass == 0) {
            for (size_t b = 0; b < nbk; ++b) C->gstart[b + 1] += C->gstart[b];
            C->gitem = (uint32_t *)malloc(sizeof(uint32_t) * (C->gstart[nbk] ? C->gstart[nbk] : 1));
            if (!C->gitem) return -1;
        }
    }
    /* after the fill gstart[b] is the end of bucket b: shift back to starts */
    for (size_t b = nbk; b > 0; --b) C->gstart[b] = C->gstart[b - 1];
    C->gstart[0] = 0;
    return 0;
}

static int gen__city_free(const gen__city *C, gen__r2 R) {
    /* Below y = 3.3 a building has only its walls and the ground floor's window boxes (8 cm deep);
       ledges, balconies and cornices start higher, above the cells (y <= 2). */
    const double margin = 0.3;
    gen__r2 E = {R.x0 - margin, R.z0 - margin, R.x1 + margin, R.z1 + margin};
    int i0, j0, i1, j1;
    gen__city_range(C, E, &i0, &j0, &i1, &j1);
    for (int j = j0; j <= j1; ++j)
        for (int k = i0; k <= i1; ++k) {
            size_t b = (size_t)j * C->gnx + k;
            for (uint32_t it = C->gstart[b]; it < C->gstart[b + 1]; ++it) {
                uint32_t kind = C->gitem[it] >> 30, i = C->gitem[it] & 0x3fffffffu;
                if (kind == 0) {
                    if (gen__r2_overlap(E, C->b[i].bb, 0) && gen__poly_rect(C->b[i].p, C->b[i].n, E)) return 0;
                } else if (kind == 1) {
                    if (gen__r2_overlap(R, C->obst[i], margin)) return 0;
                } else if (gen__poly_rect(C->quad + 4 * (size_t)i, 4, R)) return 0;
            }
        }
    return 1;
}

static void gen__city_tile(gen__city *C, gen__r2 R, int level) {
    if (R.x1 - R.x0 < 2.0 || R.z1 - R.z0 < 2.0) return;
    if (gen__city_free(C, R)) {
        gen__cell(C->c, R.x0, 0.5, R.z0, R.x1, 2.0, R.z1);
        return;
    }
    double mx = 0.5 * (R.x0 + R.x1), mz = 0.5 * (R.z0 + R.z1);
    if (level >= C->max_level) { /* last level: half-tile strips along narrow streets */
        gen__r2 h[4] = {{R.x0, R.z0, R.x1, mz}, {R.x0, mz, R.x1, R.z1}, {R.x0, R.z0, mx, R.z1}, {mx, R.z0, R.x1, R.z1}};
        for (int pair = 0; pair < 2; ++pair) {
            int f0 = gen__city_free(C, h[2 * pair]), f1 = gen__city_free(C, h[2 * pair + 1]);
            if (f0) gen__cell(C->c, h[2 * pair].x0, 0.5, h[2 * pair].z0, h[2 * pair].x1, 2.0, h[2 * pair].z1);
            if (f1) gen__cell(C->c, h[2 * pair + 1].x0, 0.5, h[2 * pair + 1].z0, h[2 * pair + 1].x1, 2.0, h[2 * pair + 1].z1);
            if (f0 || f1) break;
        }
        return;
    }
    gen__r2 q[4] = {{R.x0, R.z0, mx, mz}, {mx, R.z0, R.x1, mz}, {R.x0, mz, mx, R.z1}, {mx, mz, R.x1, R.z1}};
    for (int i = 0; i < 4; ++i) gen__city_tile(C, q[i], level + 1);
}

static int gen__cmp_cell_x(const void *pa, const void *pb) { /* by y, z range, then x */
    const float *a = (const float *)pa, *b = (const float *)pb;
    static const int key[5] = {1, 4, 2, 5, 0};
    for (int k = 0; k < 5; ++k)
        if (a[key[k]] != b[key[k]]) return a[key[k]] < b[key[k]] ? -1 : 1;
    return 0;
}
static int gen__cmp_cell_z(const void *pa, const void *pb) { /* by y, x range, then z */
    const float *a = (const float *)pa, *b = (const float *)pb;
    static const int key[5] = {1, 4, 0, 3, 2};
    for (int k = 0; k < 5; ++k)
        if (a[key[k]] != b[key[k]]) return a[key[k]] < b[key[k]] ? -1 : 1;
    return 0;
}

/* Merge face-adjacent cells with the same cross-section into runs along x, then along z, while the
   merged side stays <= maxlen. The keys are unique (cells do not overlap), so the order is defined. */
static void gen__merge_cells(mesh_cells *cs, double maxlen) {
    for (int ax = 0; ax <= 2; ax += 2) {
        qsort(cs->boxes, cs->count, 6 * sizeof(float), ax == 0 ? gen__cmp_cell_x : gen__cmp_cell_z);
        uint32_t out = 0;
        for (uint32_t i = 0; i < cs->count; ++i) {
            const float *b = cs->boxes + 6 * (size_t)i;
            float *a = out ? cs->boxes + 6 * (size_t)(out - 1) : NULL;
            int o = 2 - ax; /* the other horizontal axis */
            if (a && a[1] == b[1] && a[4] == b[4] && a[o] == b[o] && a[3 + o] == b[3 + o] && a[3 + ax] == b[ax] &&
                b[3 + ax] - a[ax] <= maxlen) {
                a[3 + ax] = b[3 + ax];
                continue;
            }
            memmove(cs->boxes + 6 * (size_t)out++, b, 6 * sizeof(float));
        }
        cs->count = out;
    }
}

static int gen__cells_overlap(const mesh_cells *cs, uint32_t skip, const double b[6]) {
    for (uint32_t i = 0; i < cs->count; ++i) {
        if (i == skip) continue;
        const float *o = cs->boxes + 6 * (size_t)i;
        if (b[0] < o[3] && o[0] < b[3] && b[1] < o[4] && o[1] < b[4] && b[2] < o[5] && o[2] < b[5]) return 1;
    }
    return 0;
}

/* The deliberate stress cells at the end (see gen_info in gen.h). */
static int gen__city_special(gen__city *C, uint32_t ground_objects, gen_info *info) {
    gen__ctx *c = C->c;
    mesh_cells *cs = c->cells;
    const uint32_t K = 4;
    float *obb = gen__object_boxes(c->m);
    if (!obb) return -1;
    uint32_t nreg = cs->count, found = 0;
    /* Touching cells: grow one horizontal face of a regular cell until it is within 1 mm of geometry,
       then move the cell to the end. */
    float *moved = (float *)malloc(6 * sizeof(float) * K);
    if (!moved) { free(obb); return -1; }
    for (uint32_t t = 0; t < K && nreg > 0; ++t) {
        uint32_t start = (uint32_t)(((uint64_t)(2 * t + 1) * nreg) / (2 * K));
        for (uint32_t tries = 0; tries < nreg && found == t; ++tries) {
            uint32_t ci = (start + tries * 7u) % nreg;
            const float *cb = cs->boxes + 6 * (size_t)ci;
            for (int dd = 0; dd < 4 && found == t; ++dd) {
                int dir = (dd + (int)t) % 4, axis = (dir & 2) ? 2 : 0, up = !(dir & 1);
                double box[6], lo = 0, hi = 40;
                int k;
                for (k = 0; k < 6; ++k) box[k] = cb[k];
#define GEN__SET(e) (box[up ? 3 + axis : axis] = (double)(float)(up ? cb[3 + axis] + (e) : cb[axis] - (e)))
                GEN__SET(hi);
                if (!gen__box_hits(c->m, obb, ground_objects, box) && !gen__cells_overlap(cs, ci, box)) continue;
                while (hi - lo > 2e-4) {
                    double mid = 0.5 * (lo + hi);
                    GEN__SET(mid);
                    if (gen__box_hits(c->m, obb, ground_objects, box) || gen__cells_overlap(cs, ci, box)) hi = mid;
                    else lo = mid;
                }
                GEN__SET(lo + 1e-3); /* the stop must come from geometry, not from another cell */
                if (!gen__box_hits(c->m, obb, ground_objects, box)) continue;
                GEN__SET(lo);
                if (gen__box_hits(c->m, obb, ground_objects, box) || gen__cells_overlap(cs, ci, box) || lo < 0.05) continue;
#undef GEN__SET
                for (k = 0; k < 6; ++k) moved[6 * found + k] = (float)box[k];
                /* remove cell ci from the regular cells (keeps order) */
                memmove(cs->boxes + 6 * (size_t)ci, cs->boxes + 6 * (size_t)(ci + 1), 6 * sizeof(float) * (cs->count - ci - 1));
                --cs->count;
                --nreg;
                ++found;
            }
        }
    }
    for (uint32_t i = 0; i < found; ++i)
        if (mesh_cells_add(cs, moved + 6 * i)) c->err = 1;
    free(moved);
    info->regular_count = nreg;
    info->touching_first = nreg;
    info->touching_count = found;
    /* Partly inside: a box centred on a footprint corner, not overlapping any other cell. */
    uint32_t inside = 0;
    for (size_t tries = 0; tries < C->nb * 4 && inside < K && C->nb; ++tries) {
        size_t bi = (size_t)((((uint64_t)(2 * inside + 1) * C->nb) / (2 * K) + tries * 13) % C->nb);
        const gen__bldg *B = &C->b[bi];
        gen__p2 p = B->p[(tries + inside) % (size_t)B->n];
        double hs = 2.0 + (double)(tries % 3), box[6] = {p.x - hs, 0.5, p.z - hs, p.x + hs, 2.0, p.z + hs};
        for (int k = 0; k < 6; ++k) box[k] = (double)(float)box[k];
        if (gen__cells_overlap(cs, (uint32_t)-1, box) || !gen__box_hits(c->m, obb, ground_objects, box)) continue;
        gen__cell(c, box[0], box[1], box[2], box[3], box[4], box[5]);
        ++inside;
    }
    info->inside_first = cs->count - inside;
    info->inside_count = inside;
    free(obb);
    return c->err ? -1 : 0;
}

/* Street furniture along block q's sides (street half-widths hw, inward normals nrm, directions od):
   lamps every 22-34 m, and a kiosk on a side along the avenue (street line ja) now and then. */
static void gen__block_furniture(gen__city *C, const gen__p2 q[4], const double hw[4], const gen__p2 nrm[4], const gen__p2 od[4], int j, int ja) {
    gen__rng *r = &C->c->rng;
    for (int k = 0; k < 4; ++k) {
        if (hw[k] < 4.5) continue;
        gen__p2 a = q[k], b = q[(k + 1) % 4], out = {-nrm[k].x, -nrm[k].z};
        double len = gen__dist(a, b), kiosk_at = -100;
        int avenue = (k == 2 && j + 1 == ja) || (k == 0 && j == ja);
        if (avenue && gen__chance(r, 0.6)) {
            kiosk_at = gen__rf(r, 0.3, 0.7) * len;
            gen__p2 kp = {a.x + od[k].x * kiosk_at + out.x * 5.0, a.z + od[k].z * kiosk_at + out.z * 5.0};
            gen__kiosk(C, kp);
        }
        for (double s = gen__rf(r, 3, 12); s < len - 3; s += gen__rf(r, 22, 34)) {
            if (fabs(s - kiosk_at) < 3) continue;
            gen__p2 lp = {a.x + od[k].x * s + out.x * 1.8, a.z + od[k].z * s + out.z * 1.8};
            gen__lamp(C, lp, out);
        }
    }
}

/* The open square in block q: a monument and a few kiosks. */
static void gen__city_square(gen__city *C, const gen__p2 q[4]) {
    gen__ctx *c = C->c;
    gen__rng *r = &c->rng;
    gen__p2 m = gen__bilerp(q, 0.5, 0.5);
    gen__obj(c, "monument_0");
    gen__aabox(c, m.x - 2.5, 0, m.z - 2.5, m.x + 2.5, 1.5, m.z + 2.5);
    gen__aabox(c, m.x - 0.6, 1.5, m.z - 0.6, m.x + 0.6, 10.5, m.z + 0.6);
    gen__aabox(c, m.x - 1.0, 10.5, m.z - 1.0, m.x + 1.0, 13.0, m.z + 1.0);
    if (gen__add_obst(C, m.x - 2.5, m.z - 2.5, m.x + 2.5, m.z + 2.5)) c->err = 1;
    gen__p2 placed[8];
    int nk = 0, want = 3 + (int)gen__ri(r, 3);
    for (int tries = 0; tries < 60 && nk < want; ++tries) {
        double ku = gen__rf(r, 0.12, 0.88), kv = gen__rf(r, 0.12, 0.88); /* one draw per statement: */
        gen__p2 kp = gen__bilerp(q, ku, kv); /* argument order is unspecified in C */
        int ok = fabs(kp.x - m.x) > 6 || fabs(kp.z - m.z) > 6;
        for (int t = 0; t < nk && ok; ++t)
            if (fabs(kp.x - placed[t].x) < 6 && fabs(kp.z - placed[t].z) < 6) ok = 0;
        if (!ok) continue;
        placed[nk++] = kp;
        gen__kiosk(C, kp);
    }
}

/* Block q's buildings (the block Wb x Db metres): now and then a Vienna perimeter block, else a grid
   of up to 3 x 2 lots, some left empty (yards). 0, or -1 when out of memory. */
static int gen__block_lots(gen__city *C, const gen__p2 q[4], double Wb, double Db) {
    gen__rng *r = &C->c->rng;
    double base = gen__rf(r, 12, 28);
#define GEN__H() gen__clamp(gen__chance(r, 0.05) ? gen__rf(r, 30, 40) : base + gen__rf(r, -6, 8), 8, 40)
    if (Wb >= 45 && Db >= 45 && gen__chance(r, 0.18)) /* Vienna perimeter block */
        return gen__lot(C, q, 0, 0, 1, 1, Wb, Db, GEN__H(), 1) ? -1 : 0;
    int nu = Wb > 62 ? 3 : Wb > 34 ? 2 : 1, nv = Db > 40 ? 2 : 1;
    if (nu > 2 && gen__chance(r, 0.25)) --nu;
    double us[4], vs[3];
    us[0] = 0; us[nu] = 1;
    vs[0] = 0; vs[nv] = 1;
    for (int k = 1; k < nu; ++k) us[k] = (k + gen__rf(r, -0.2, 0.2)) / nu;
    for (int k = 1; k < nv; ++k) vs[k] = (k + gen__rf(r, -0.15, 0.15)) / nv;
    for (int lv = 0; lv < nv; ++lv)
        for (int lu = 0; lu < nu; ++lu) {
            if (nu * nv >= 3 && gen__chance(r, 0.06)) continue; /* an empty lot: a yard */
            double g[4];                           /* inset in metres: setback at streets, gap inside */
            g[0] = lu == 0 ? gen__rf(r, 0, 2) : (gen__chance(r, 0.4) ? 0.0 : gen__rf(r, 1, 2.5));
            g[1] = lu == nu - 1 ? gen__rf(r, 0, 2) : (gen__chance(r, 0.4) ? 0.0 : gen__rf(r, 1, 2.5));
            g[2] = lv == 0 ? gen__rf(r, 0, 2) : (gen__chance(r, 0.4) ? 0.0 : gen__rf(r, 1, 2.5));
            g[3] = lv == nv - 1 ? gen__rf(r, 0, 2) : (gen__chance(r, 0.4) ? 0.0 : gen__rf(r, 1, 2.5));
            double u0 = us[lu] + g[0] / Wb, u1 = us[lu + 1] - g[1] / Wb, v0 = vs[lv] + g[2] / Db, v1 = vs[lv + 1] - g[3] / Db;
            if (u1 - u0 < 0.05 || v1 - v0 < 0.05) continue;
            if (gen__lot(C, q, u0, v0, u1, v1, (u1 - u0) * Wb, (v1 - v0) * Db, GEN__H(), 0)) return -1;
        }
#undef GEN__H
    return 0;
}

/* Block (i, j) between the jittered street crossings Pt ((nb + 1)^2 of them) and street widths wx, wz:
   its outline inset by half the streets, the furniture along it, then the square (square != 0) or
   the buildings. 0, or -1 when out of memory. */
static int gen__city_block(gen__city *C, const gen__p2 *Pt, int nb, const double *wx, const double *wz, int i, int j, int ja, int square) {
    gen__p2 A = Pt[(size_t)j * (nb + 1) + i], B = Pt[(size_t)j * (nb + 1) + i + 1];
    gen__p2 Cc = Pt[(size_t)(j + 1) * (nb + 1) + i + 1], D = Pt[(size_t)(j + 1) * (nb + 1) + i];
    gen__p2 cor[4] = {A, B, Cc, D};
    double hw[4] = {wz[j] / 2, wx[i + 1] / 2, wz[j + 1] / 2, wx[i] / 2};
    gen__p2 cen = {(A.x + B.x + Cc.x + D.x) / 4, (A.z + B.z + Cc.z + D.z) / 4}, op[4], od[4], q[4], nrm[4];
    for (int k = 0; k < 4; ++k) {
        gen__p2 a = cor[k], b = cor[(k + 1) % 4];
        double len = gen__dist(a, b);
        gen__p2 d = {(b.x - a.x) / len, (b.z - a.z) / len}, n = {-d.z, d.x};
        if ((cen.x - a.x) * n.x + (cen.z - a.z) * n.z < 0) { n.x = -n.x; n.z = -n.z; }
        nrm[k] = n;
        od[k] = d;
        op[k].x = a.x + n.x * hw[k];
        op[k].z = a.z + n.z * hw[k];
    }
    for (int k = 0; k < 4; ++k) q[k] = gen__isect(op[(k + 3) % 4], od[(k + 3) % 4], op[k], od[k]);
    double Wb = 0.5 * (gen__dist(q[0], q[1]) + gen__dist(q[3], q[2]));
    double Db = 0.5 * (gen__dist(q[0], q[3]) + gen__dist(q[1], q[2]));
    gen__block_furniture(C, q, hw, nrm, od, j, ja);
    if (square) {
        gen__city_square(C, q);
        return 0;
    }
    if (gen__grow((void **)&C->quad, &C->capquad, 4 * (C->nquad + 1), sizeof(gen__p2))) return -1;
    memcpy(C->quad + 4 * C->nquad++, q, sizeof q);
    return gen__block_lots(C, q, Wb, Db);
}

/* The city's view cells: 24 m tiles over the free street area out to the ring road's outer edge
   (split near buildings, merged along streets), thinned to max_cells, then the special cells. 0, or
   -1 when out of memory. */
static int gen__city_cells(gen__city *C, const gen_params *P, const gen__p2 *Pt, int nb, const double *wx, const double *wz, uint32_t ground,
                           gen_info *info) {
    gen__ctx *c = C->c;
    double rx0 = 1e30, rz0 = 1e30, rx1 = -1e30, rz1 = -1e30;
    for (int k = 0; k <= nb; ++k) {
        rx0 = gen__min(rx0, Pt[(size_t)k * (nb + 1)].x - wx[0] / 2);
        rx1 = gen__max(rx1, Pt[(size_t)k * (nb + 1) + nb].x + wx[nb] / 2);
        rz0 = gen__min(rz0, Pt[k].z - wz[0] / 2);
        rz1 = gen__max(rz1, Pt[(size_t)nb * (nb + 1) + k].z + wz[nb] / 2);
    }
    const double TC = 24.0;
    if (gen__city_grid(C, rx0, rz0, rx1, rz1)) return -1;
    for (double z = rz0; z < rz1 - 1e-9; z += TC)
        for (double x = rx0; x < rx1 - 1e-9; x += TC) {
            gen__r2 R = {x, z, gen__min(x + TC, rx1), gen__min(z + TC, rz1)};
            gen__city_tile(C, R, 0);
        }
    gen__merge_cells(c->cells, TC + 1e-3);
    if (c->err) return -1;
    int special = P->max_cells == 0 || P->max_cells >= 16;
    if (P->max_cells) gen__thin_cells(c->cells, 0, special ? P->max_cells - 4 : P->max_cells);
    info->regular_count = info->touching_first = info->inside_first = c->cells->count;
    if (special && gen__city_special(C, ground, info)) return -1;
    return c->err ? -1 : 0;
}

static int gen__city_scene(gen__ctx *c, const gen_params *P, gen_info *info) {
    gen__rng *r = &c->rng;
    gen__city C;
    memset(&C, 0, sizeof C);
    C.c = c;
    C.max_level = 1;
    int nb = gen__iround(12.0 * P->size);
    if (nb < 2) nb = 2;
    int ja = nb / 2, si = (nb - 1) / 2, sj = ja - 1, ret = -1;
    size_t np = (size_t)(nb + 1) * (size_t)(nb + 1);
    double *X = (double *)malloc(sizeof(double) * (size_t)(nb + 1) * 4);
    gen__p2 *Pt = (gen__p2 *)malloc(sizeof(gen__p2) * np);
    if (!X || !Pt) goto done;
    double *Z = X + (nb + 1), *wx = Z + (nb + 1), *wz = wx + (nb + 1);
    /* street lines: irregular widths, irregular block depths */
    for (int pass = 0; pass < 2; ++pass) {
        double *L = pass ? Z : X, *wd = pass ? wz : wx;
        for (int i = 0; i <= nb; ++i) wd[i] = (i == 0 || i == nb) ? gen__rf(r, 10, 16) : gen__rf(r, 6, 25);
        if (pass) wd[ja] = gen__rf(r, 30, 36);
        L[0] = 0;
        for (int i = 1; i <= nb; ++i) L[i] = L[i - 1] + wd[i - 1] / 2 + gen__rf(r, 48, 80) + wd[i] / 2;
    }
    for (int j = 0; j <= nb; ++j)
        for (int i = 0; i <= nb; ++i) {
            gen__p2 *p = &Pt[(size_t)j * (nb + 1) + i];
            p->x = X[i] + gen__rf(r, -5, 5);
            p->z = Z[j] + (j == ja ? 0.0 : gen__rf(r, -5, 5));
        }
    /* extent and ground tiles (objects [0, ground)) */
    double ex0 = -20, ez0 = -20, ex1 = X[nb] + 20, ez1 = Z[nb] + 20;
    const double T = 25.0;
    int ntx = (int)ceil((ex1 - ex0) / T), ntz = (int)ceil((ez1 - ez0) / T);
    ex1 = ex0 + ntx * T;
    ez1 = ez0 + ntz * T;
    for (int j = 0; j < ntz; ++j)
        for (int i = 0; i < ntx; ++i) {
            gen__obj(c, "ground_%d_%d", i, j);
            gen__hquad(c, ex0 + i * T, ez0 + j * T, ex0 + (i + 1) * T, ez0 + (j + 1) * T, 0, 0);
        }
    uint32_t ground = c->m->object_count;
    for (int j = 0; j < nb && !c->err; ++j)
        for (int i = 0; i < nb && !c->err; ++i)
            if (gen__city_block(&C, Pt, nb, wx, wz, i, j, ja, i == si && j == sj)) goto done;
    if (c->err) goto done;
    ret = gen__city_cells(&C, P, Pt, nb, wx, wz, ground, info);
done:
    free(X);
    free(Pt);
    free(C.b);
    free(C.obst);
    free(C.quad);
    free(C.gstart);
    free(C.gitem);
    return ret;
}

/* ------------------------------------------------------------------------------------------------
   Forest */

typedef struct gen__tree { float x, z, r; } gen__tree; /* r < 0: no tree in this slot */

static void gen__leaves(gen__ctx *c, double cx, double cy, double cz, double rad, int count, double ts) {
    gen__rng *r = &c->rng;
    for (int t = 0; t < count; ++t) {
        double px = 0, py = 0, pz = 0;
        for (int tries = 0; tries < 16; ++tries) {
            px = gen__rf(r, -1, 1); py = gen__rf(r, -1, 1); pz = gen__rf(r, -1, 1);
            if (px * px + py * py + pz * pz <= 1) break;
        }
        px = cx + px * rad; py = cy + py * rad; pz = cz + pz * rad;
        double v[3][3];
        int ok = 0;
        for (int tries = 0; tries < 8 && !ok; ++tries) {
            for (int k = 0; k < 3; ++k)
                for (int i = 0; i < 3; ++i) v[k][i] = gen__rf(r, -ts, ts);
            double a[3] = {v[1][0] - v[0][0], v[1][1] - v[0][1], v[1][2] - v[0][2]};
            double b[3] = {v[2][0] - v[0][0], v[2][1] - v[0][1], v[2][2] - v[0][2]};
            double n0 = a[1] * b[2] - a[2] * b[1], n1 = a[2] * b[0] - a[0] * b[2], n2 = a[0] * b[1] - a[1] * b[0];
            ok = n0 * n0 + n1 * n1 + n2 * n2 > 0.04 * ts * ts * ts * ts;
        }
        if (!ok) {
            v[0][0] = 0; v[0][1] = 0; v[0][2] = 0;
            v[1][0] = ts; v[1][1] = 0; v[1][2] = 0;
            v[2][0] = 0; v[2][1] = ts; v[2][2] = 0;
        }
        uint32_t a = gen__v(c, px + v[0][0], py + v[0][1], pz + v[0][2]);
        uint32_t b = gen__v(c, px + v[1][0], py + v[1][1], pz + v[1][2]);
        uint32_t d = gen__v(c, px + v[2][0], py + v[2][1], pz + v[2][2]);
        gen__tri(c, a, b, d);
    }
}

static int gen__forest_free(const gen__tree *tr, int ng, double sp, gen__r2 R) {
    int i0 = (int)floor(R.x0 / sp) - 1, i1 = (int)floor(R.x1 / sp) + 1, j0 = (int)floor(R.z0 / sp) - 1, j1 = (int)floor(R.z1 / sp) + 1;
    for (int j = j0 < 0 ? 0 : j0; j <= j1 && j < ng; ++j)
        for (int i = i0 < 0 ? 0 : i0; i <= i1 && i < ng; ++i) {
            const gen__tree *t = &tr[(size_t)j * ng + i];
            double m = t->r + 0.25;
            if (t->r < 0) continue;
            if (t->x >= R.x0 - m && t->x <= R.x1 + m && t->z >= R.z0 - m && t->z <= R.z1 + m) return 0;
        }
    return 1;
}

/* The forests' clearings: n = round(density size^2) (1..256) circles (x, z, radius) with radii in
   [rmin, rmax] (at most S / 4) and centres in the middle 70% of the S x S square. Returns n. */
static int gen__clearings(gen__rng *r, const gen_params *P, double S, double density, double rmin, double rmax, double cl[256][3]) {
    int ncl = gen__iround(density * P->size * P->size);
    if (ncl < 1) ncl = 1;
    if (ncl > 256) ncl = 256;
    for (int k = 0; k < ncl; ++k) {
        cl[k][2] = gen__min(gen__rf(r, rmin, rmax), S / 4);
        cl[k][0] = gen__rf(r, 0.15 * S, 0.85 * S);
        cl[k][1] = gen__rf(r, 0.15 * S, 0.85 * S);
    }
    return ncl;
}

/* The forests' ground: 20 m tiles over the S x S square, one object each. */
static void gen__ground_tiles(gen__ctx *c, double S) {
    const double T = 20.0;
    int nt = (int)ceil(S / T);
    for (int j = 0; j < nt; ++j)
        for (int i = 0; i < nt; ++i) {
            gen__obj(c, "ground_%d_%d", i, j);
            gen__hquad(c, i * T, j * T, gen__min((i + 1) * T, S), gen__min((j + 1) * T, S), 0, 0);
        }
}

/* A tree trunk: a hexagonal frustum from radius r0 on the ground to r1 at height ht, open at the
   bottom (it stands on the ground), capped at the top. */
static void gen__trunk(gen__ctx *c, double x, double z, double r0, double r1, double ht) {
    static const double hex[6][2] = {{1, 0}, {0.5, 0.8660254037844386}, {-0.5, 0.8660254037844386},
                                     {-1, 0}, {-0.5, -0.8660254037844386}, {0.5, -0.8660254037844386}};
    uint32_t b = c->m->vertex_count;
    for (int k = 0; k < 6; ++k) gen__v(c, x + hex[k][0] * r0, 0, z + hex[k][1] * r0);
    for (int k = 0; k < 6; ++k) gen__v(c, x + hex[k][0] * r1, ht, z + hex[k][1] * r1);
    for (uint32_t k = 0; k < 6; ++k) gen__quad(c, b + k, b + 6 + k, b + 6 + (k + 1) % 6, b + (k + 1) % 6);
    gen__tri(c, b + 6, b + 11, b + 10); gen__tri(c, b + 6, b + 10, b + 9);
    gen__tri(c, b + 6, b + 9, b + 8); gen__tri(c, b + 6, b + 8, b + 7);
}

/* The forests' grid: ng x ng slots of sp = 5 m (at least min_ng) over the 300 m x size square,
   whose side ng sp goes to *S. */
static int gen__forest_grid(const gen_params *P, int min_ng, double *S) {
    int ng = (int)floor(300.0 * P->size / 5.0);
    if (ng < min_ng) ng = min_ng;
    *S = ng * 5.0;
    return ng;
}

static int gen__forest(gen__ctx *c, const gen_params *P) {
    gen__rng *r = &c->rng;
    const double sp = 5.0;
    double S;
    int ng = gen__forest_grid(P, 2, &S);
    gen__tree *tr = (gen__tree *)malloc(sizeof(gen__tree) * (size_t)ng * (size_t)ng);
    if (!tr) return -1;
    /* clearings and a straight path along x */
    double cl[256][3];
    int ncl = gen__clearings(r, P, S, 6.0, 10, 22, cl);
    double pz0 = gen__rf(r, 0.3 * S, 0.6 * S), pz1 = pz0 + 4.0;
    gen__ground_tiles(c, S);
    uint32_t ntree = 0;
    for (int j = 0; j < ng && !c->err; ++j)
        for (int i = 0; i < ng && !c->err; ++i) {
            gen__tree *t = &tr[(size_t)j * ng + i];
            double x = (i + 0.5) * sp + gen__rf(r, -0.35, 0.35) * sp, z = (j + 0.5) * sp + gen__rf(r, -0.35, 0.35) * sp;
            double tr_r = gen__rf(r, 0.12, 0.35), ht = gen__rf(r, 5, 12);
            int conifer = gen__chance(r, 0.35), keep = gen__chance(r, 0.92);
            t->x = (float)x; t->z = (float)z; t->r = -1;
            for (int k = 0; k < ncl; ++k)
                if ((x - cl[k][0]) * (x - cl[k][0]) + (z - cl[k][1]) * (z - cl[k][1]) < cl[k][2] * cl[k][2]) keep = 0;
            if (z + tr_r + 3.0 > pz0 && z - tr_r - 3.0 < pz1) keep = 0;
            if (!keep) continue;
            t->r = (float)tr_r;
            gen__obj(c, "tree_%u", ntree++);
            gen__trunk(c, x, z, tr_r, tr_r * 0.6, ht);
            int ncu = 3 + (int)gen__ri(r, 4);
            for (int k = 0; k < ncu; ++k) {
                double rad, cx, cy, cz, ts = gen__rf(r, 0.25, 0.45);
                if (conifer) {
                    double f = ncu > 1 ? (double)k / (ncu - 1) : 0.5;
                    rad = gen__rf(r, 1.8, 2.4) * (1.0 - 0.6 * f);
                    cx = x; cz = z; cy = ht * (0.45 + 0.5 * f);
                } else {
                    rad = gen__rf(r, 0.8, 1.6);
                    cx = x + gen__rf(r, -1.6, 1.6); cz = z + gen__rf(r, -1.6, 1.6); cy = ht + gen__rf(r, -1.5, 0.8);
                }
                cy = gen__max(cy, 2.7 + rad + ts); /* leaves stay above eye height */
                gen__leaves(c, cx, cy, cz, rad, 20 + (int)gen__ri(r, 21), ts);
            }
        }
    /* cells: whole 10 m tiles in clearings, 3 m boxes between trunks elsewhere */
    int nc = (int)floor(S / 10.0);
    for (int j = 0; j < nc && !c->err; ++j)
        for (int i = 0; i < nc; ++i) {
            gen__r2 R = {i * 10.0, j * 10.0, i * 10.0 + 10, j * 10.0 + 10};
            int in_clearing = 0;
            for (int k = 0; k < ncl && !in_clearing; ++k) {
                double dx = gen__max(fabs(R.x0 - cl[k][0]), fabs(R.x1 - cl[k][0])), dz = gen__max(fabs(R.z0 - cl[k][1]), fabs(R.z1 - cl[k][1]));
                in_clearing = dx * dx + dz * dz < cl[k][2] * cl[k][2];
            }
            if (in_clearing && gen__forest_free(tr, ng, sp, R)) {
                gen__cell(c, R.x0, 0.5, R.z0, R.x1, 2.0, R.z1);
                continue;
            }
            for (int tries = 0; tries < 16; ++tries) {
                double x0 = i * 10.0 + gen__rf(r, 0, 7), z0 = j * 10.0 + gen__rf(r, 0, 7);
                gen__r2 Q = {x0, z0, x0 + 3, z0 + 3};
                if (!gen__forest_free(tr, ng, sp, Q)) continue;
                gen__cell(c, Q.x0, 0.5, Q.z0, Q.x1, 2.0, Q.z1);
                break;
            }
        }
    free(tr);
    if (P->max_cells) gen__thin_cells(c->cells, 0, P->max_cells);
    return c->err ? -1 : 0;
}

/* Leaves of cluster k of a tree's ncu: `drawn` (the default forest's count, drawn either way so
   the random stream stays the same), or leaves_per_tree spread evenly over the clusters. */
static int gen__cluster_leaves(const gen_params *P, int drawn, int ncu, int k) {
    if (!P->leaves_per_tree) return drawn;
    return (int)(P->leaves_per_tree / (uint32_t)ncu + ((uint32_t)k < P->leaves_per_tree % (uint32_t)ncu));
}

/* The dense forest (gen_params.dense), after Durand 2000 §7.2's test scene (7,750 trees of 1,000
   leaves, "coarse and made of large triangles"): trees 4.5 m apart whose foliage reaches down to
   eye height, and bushes between them, so that from inside the forest only the nearest few percent
   of the objects can be seen, through the gaps between many leaves. Conifers: a column of leaf
   clusters from 0.8-1.6 m up to the top, widest at the bottom; broadleaves: clusters from 1.4-3 m
   up, spread around the top of the trunk. Bushes (bush_N): 2-3 clusters of smaller leaves on the
   ground. Cells are 3 m boxes (cell_size) at y 0.5..2.0 where one fits without touching any leaf
   or trunk (exact test, 0.1 m margin). leaves_per_tree sets the leaves per tree and scales the
   bushes' (the paper's 1,000). Uses its own random stream: the default forest is unchanged. */
static int gen__forest_dense(gen__ctx *c, const gen_params *P) {
    const double LT = 2.0; /* leaf size: coarse, large triangles (0.7-1.5 m), as in Durand 2000 §7.2 */
    gen__rng *r = &c->rng;
    const double sp = 5.0;
    double S;
    int ng = gen__forest_grid(P, 3, &S);
    /* first object of each slot (objects are emitted slot by slot), for the cells' search */
    uint32_t *first = (uint32_t *)malloc(sizeof(uint32_t) * ((size_t)ng * (size_t)ng + 1));
    float *obb = NULL;
    if (!first) return -1;
    double cl[256][3];
    int ncl = gen__clearings(r, P, S, 3.0, 8, 16, cl);
    double pz0 = gen__rf(r, 0.3 * S, 0.6 * S), pz1 = pz0 + 3.0;
    gen__ground_tiles(c, S);
    uint32_t ntree = 0, nbush = 0;
    for (int j = 0; j < ng && !c->err; ++j)
        for (int i = 0; i < ng && !c->err; ++i) {
            first[(size_t)j * ng + i] = c->m->object_count;
            double x = (i + 0.5) * sp + gen__rf(r, -0.3, 0.3) * sp, z = (j + 0.5) * sp + gen__rf(r, -0.3, 0.3) * sp;
            double tr_r = gen__rf(r, 0.1, 0.3), ht = gen__rf(r, 6, 14);
            int conifer = gen__chance(r, 0.45), keep = gen__chance(r, 0.94), bush = gen__chance(r, 0.95);
            double ba = gen__rf(r, 0, 4), bd = gen__rf(r, 1.6, 2.4); /* the bush: side (0..4 around a square) and distance */
            for (int k = 0; k < ncl; ++k)
                if ((x - cl[k][0]) * (x - cl[k][0]) + (z - cl[k][1]) * (z - cl[k][1]) < cl[k][2] * cl[k][2]) keep = bush = 0;
            if (z + 3.0 > pz0 && z - 3.0 < pz1) keep = bush = 0;
            if (keep) {
                gen__obj(c, "tree_%u", ntree++);
                gen__trunk(c, x, z, tr_r, tr_r * 0.5, ht);
                if (conifer) {
                    double y0 = gen__rf(r, 0.8, 1.6), R = gen__rf(r, 1.6, 2.2);
                    int ncu = 4 + (int)gen__ri(r, 3);
                    for (int k = 0; k < ncu; ++k) {
                        double f = (double)k / (ncu - 1), rad = R * (1.0 - 0.7 * f) * gen__rf(r, 0.85, 1.0);
                        double cy = y0 + rad * 0.6 + f * (ht - y0 - rad * 0.6), ts = LT * gen__rf(r, 0.5, 0.75);
                        int nl = gen__cluster_leaves(P, 18 + (int)gen__ri(r, 7), ncu, k);
                        gen__leaves(c, x, cy, z, rad, nl, ts);
                    }
                } else {
                    double y0 = gen__rf(r, 1.4, 3.0);
                    int ncu = 3 + (int)gen__ri(r, 3);
                    for (int k = 0; k < ncu; ++k) {
                        double rad = gen__rf(r, 1.2, 1.9), ts = LT * gen__rf(r, 0.5, 0.75);
                        double cx = x + gen__rf(r, -1.4, 1.4), cz = z + gen__rf(r, -1.4, 1.4);
                        double cy = gen__rf(r, y0 + rad * 0.7, gen__max(y0 + rad * 0.7, ht - 0.5));
                        int nl = gen__cluster_leaves(P, 18 + (int)gen__ri(r, 7), ncu, k);
                        gen__leaves(c, cx, cy, cz, rad, nl, ts);
                    }
                }
            }
            if (bush) {
                double bx = x, bz = z, t = ba - floor(ba), u = 2.0 * t - 1.0;
                if (ba < 1) { bx += bd; bz += u * bd; }
                else if (ba < 2) { bx -= bd; bz += u * bd; }
                else if (ba < 3) { bz += bd; bx += u * bd; }
                else { bz -= bd; bx += u * bd; }
                gen__obj(c, "bush_%u", nbush++);
                int ncu = 2 + (int)gen__ri(r, 2);
                for (int k = 0; k < ncu; ++k) {
                    double rad = gen__rf(r, 0.6, 1.1), ts = LT * gen__rf(r, 0.35, 0.55);
                    double cx = bx + gen__rf(r, -0.5, 0.5), cz = bz + gen__rf(r, -0.5, 0.5), cy = rad * gen__rf(r, 0.8, 1.2) + ts;
                    int nl = 14 + (int)gen__ri(r, 7);
                    if (P->leaves_per_tree) nl = (int)((uint64_t)nl * P->leaves_per_tree / 100u); /* as dense as the trees */
                    gen__leaves(c, cx, cy, cz, rad, nl > 1 ? nl : 1, ts);
                }
            }
        }
    first[(size_t)ng * ng] = c->m->object_count;
    if (!c->err) obb = gen__object_boxes(c->m);
    if (!obb) c->err = 1;
    /* cells: whole 10 m tiles in clearings, else a 3 m (cell_size) box per 10 m tile where one is free */
    int nc = (int)floor(S / 10.0);
    for (int j = 0; j < nc && !c->err; ++j)
        for (int i = 0; i < nc && !c->err; ++i) {
            gen__r2 R = {i * 10.0, j * 10.0, i * 10.0 + 10, j * 10.0 + 10};
            int in_clearing = 0;
            for (int k = 0; k < ncl && !in_clearing; ++k) {
                double dx = gen__max(fabs(R.x0 - cl[k][0]), fabs(R.x1 - cl[k][0])), dz = gen__max(fabs(R.z0 - cl[k][1]), fabs(R.z1 - cl[k][1]));
                in_clearing = dx * dx + dz * dz < cl[k][2] * cl[k][2];
            }
            for (int tries = 0; tries < (in_clearing ? 1 : 24); ++tries) {
                double x0 = R.x0, z0 = R.z0, w = 10.0;
                if (!in_clearing) { w = P->cell_size > 0 ? P->cell_size : 3.0; x0 += gen__rf(r, 0, 10.0 - w); z0 += gen__rf(r, 0, 10.0 - w); }
                double box[6] = {x0 - 0.1, 0.4, z0 - 0.1, x0 + w + 0.1, 2.1, z0 + w + 0.1};
                int i0 = (int)floor(box[0] / sp) - 2, i1 = (int)floor(box[3] / sp) + 2, j0 = (int)floor(box[2] / sp) - 2, j1 = (int)floor(box[5] / sp) + 2;
                int hit = 0;
                for (int sj = j0 < 0 ? 0 : j0; sj <= j1 && sj < ng && !hit; ++sj) {
                    int si0 = i0 < 0 ? 0 : i0, si1 = i1 < ng ? i1 : ng - 1;
                    if (si0 > si1) continue;
                    /* objects of slots si0..si1 of row sj are contiguous */
                    mesh sub = *c->m;
                    sub.object_count = first[(size_t)sj * ng + si1 + 1];
                    hit = gen__box_hits(&sub, obb, first[(size_t)sj * ng + si0], box);
                }
                if (hit) continue;
                gen__cell(c, x0, 0.5, z0, x0 + w, 2.0, z0 + w);
                break;
            }
        }
    free(first);
    free(obb);
    if (P->max_cells) gen__thin_cells(c->cells, 0, P->max_cells);
    return c->err ? -1 : 0;
}

/* ------------------------------------------------------------------------------------------------
   Indoor */

typedef struct gen__door { int axis; double f0, f1, a, b; } gen__door; /* axis 0: wall along x at z in [f0,f1] */
typedef struct gen__room { gen__r2 r; int kind; } gen__room;           /* kind 0 room, 1 corridor, 2 hall */

typedef struct gen__indoor {
    gen__ctx *c;
    gen__door *d;
    size_t nd, capd;
    gen__room *rm;
    size_t nr, caprm;
    gen__r2 *furn;
    size_t nf, capf;
    uint32_t n_wall, n_lintel, n_column, n_table, n_cabinet, n_chair;
} gen__indoor;

static const double gen__T = 0.3, gen__H = 3.0, gen__DOOR_H = 2.1;

static int gen__add_door(gen__indoor *I, int axis, double f0, double f1, double a, double b) {
    if (gen__grow((void **)&I->d, &I->capd, I->nd + 1, sizeof(gen__door))) return -1;
    gen__door d = {axis, f0, f1, a, b};
    I->d[I->nd++] = d;
    return 0;
}
static int gen__add_room(gen__indoor *I, double x0, double z0, double x1, double z1, int kind) {
    if (gen__grow((void **)&I->rm, &I->caprm, I->nr + 1, sizeof(gen__room))) return -1;
    gen__room rm;
    rm.r.x0 = x0; rm.r.z0 = z0; rm.r.x1 = x1; rm.r.z1 = z1;
    rm.kind = kind;
    I->rm[I->nr++] = rm;
    return 0;
}

/* A straight wall along `axis` spanning [a, b], thickness range [f0, f1], cut by the doors recorded
   on it (same axis, same f0). Each piece is one wall_N object, each door gets a lintel_N. */
static void gen__wall_line(gen__indoor *I, int axis, double f0, double f1, double a, double b) {
    gen__ctx *c = I->c;
    double cur = a;
    for (;;) {
        double best = 1e300, bend = 0;
        for (size_t k = 0; k < I->nd; ++k) {
            const gen__door *d = &I->d[k];
            if (d->axis == axis && d->f0 == f0 && d->a >= cur && d->a < best && d->b <= b) { best = d->a; bend = d->b; }
        }
        double e = best < 1e300 ? best : b;
        if (e - cur > 1e-6) {
            gen__obj(c, "wall_%u", I->n_wall++);
            if (axis == 0) gen__aabox(c, cur, 0, f0, e, gen__H, f1);
            else gen__aabox(c, f0, 0, cur, f1, gen__H, e);
        }
        if (best >= 1e300) break;
        gen__obj(c, "lintel_%u", I->n_lintel++);
        if (axis == 0) gen__aabox(c, best, gen__DOOR_H, f0, bend, gen__H, f1);
        else gen__aabox(c, f0, gen__DOOR_H, best, f1, gen__H, bend);
        cur = bend;
    }
}

static int gen__furn_ok(const gen__indoor *I, gen__r2 f) {
    for (size_t k = 0; k < I->nd; ++k) {
        const gen__door *d = &I->d[k];
        gen__r2 z = d->axis == 0 ? (gen__r2){d->a - 0.3, d->f0 - 1.2, d->b + 0.3, d->f1 + 1.2}
                                 : (gen__r2){d->f0 - 1.2, d->a - 0.3, d->f1 + 1.2, d->b + 0.3};
        if (gen__r2_overlap(f, z, 0)) return 0;
    }
    for (size_t k = 0; k < I->nf; ++k)
        if (gen__r2_overlap(f, I->furn[k], 0.3)) return 0;
    return 1;
}

static void gen__furniture(gen__indoor *I, const gen__room *rm) {
    gen__ctx *c = I->c;
    gen__rng *r = &c->rng;
    int n = 1 + (int)gen__ri(r, 3);
    for (int k = 0; k < n; ++k) {
        int type = (int)gen__ri(r, 3);
        for (int tries = 0; tries < 20; ++tries) {
            double w, d, x0, z0;
            gen__r2 R = rm->r;
            if (type == 0) { w = gen__rf(r, 1.2, 2.0); d = gen__rf(r, 0.7, 1.0); }
            else if (type == 1) { w = gen__rf(r, 0.9, 1.8); d = 0.5; }
            else { w = 0.45; d = 0.45; }
            if (gen__chance(r, 0.5)) { double t = w; w = d; d = t; }
            if (R.x1 - R.x0 < w + 0.4 || R.z1 - R.z0 < d + 0.4) continue;
            x0 = gen__rf(r, R.x0 + 0.15, R.x1 - 0.15 - w);
            z0 = gen__rf(r, R.z0 + 0.15, R.z1 - 0.15 - d);
            if (type == 1) { /* cabinets stand against a wall */
                switch (gen__ri(r, 4)) {
                case 0: x0 = R.x0 + 0.02; break;
                case 1: x0 = R.x1 - 0.02 - w; break;
                case 2: z0 = R.z0 + 0.02; break;
                default: z0 = R.z1 - 0.02 - d; break;
                }
            }
            gen__r2 F = {x0, z0, x0 + w, z0 + d};
            if (!gen__furn_ok(I, F)) continue;
            if (gen__grow((void **)&I->furn, &I->capf, I->nf + 1, sizeof(gen__r2))) { c->err = 1; return; }
            I->furn[I->nf++] = F;
            if (type == 0) {
                gen__obj(c, "table_%u", I->n_table++);
                gen__aabox(c, x0, 0.70, z0, x0 + w, 0.75, z0 + d);
                gen__aabox(c, x0 + 0.03, 0, z0 + 0.03, x0 + 0.09, 0.70, z0 + 0.09);
                gen__aabox(c, x0 + w - 0.09, 0, z0 + 0.03, x0 + w - 0.03, 0.70, z0 + 0.09);
                gen__aabox(c, x0 + 0.03, 0, z0 + d - 0.09, x0 + 0.09, 0.70, z0 + d - 0.03);
                gen__aabox(c, x0 + w - 0.09, 0, z0 + d - 0.09, x0 + w - 0.03, 0.70, z0 + d - 0.03);
            } else if (type == 1) {
                gen__obj(c, "cabinet_%u", I->n_cabinet++);
                gen__aabox(c, x0, 0, z0, x0 + w, gen__rf(r, 1.6, 2.0), z0 + d);
            } else {
                gen__obj(c, "chair_%u", I->n_chair++);
                gen__aabox(c, x0, 0, z0, x0 + w, 0.45, z0 + d);
                gen__aabox(c, x0, 0.45, z0, x0 + w, 0.95, z0 + 0.06);
            }
            break;
        }
    }
}

static void gen__tile_space(gen__indoor *I, gen__r2 R, double target) {
    const double in = 0.05;
    double w = R.x1 - R.x0 - 2 * in, d = R.z1 - R.z0 - 2 * in;
    int nx = gen__iround(w / target), nz = gen__iround(d / target);
    if (nx < 1) nx = 1;
    if (nz < 1) nz = 1;
    for (int j = 0; j < nz; ++j)
        for (int i = 0; i < nx; ++i) {
            gen__r2 t = {R.x0 + in + w * i / nx, R.z0 + in + d * j / nz, R.x0 + in + w * (i + 1) / nx, R.z0 + in + d * (j + 1) / nz};
            int ok = 1;
            for (size_t k = 0; k < I->nf && ok; ++k)
                if (gen__r2_overlap(t, I->furn[k], 0.05)) ok = 0;
            if (ok) gen__cell(I->c, t.x0, 0.5, t.z0, t.x1, 2.0, t.z1);
        }
}

/* The doors of the rooms in the strips (sz: each strip's z range, cz: each band's corridor, first_room:
   each strip's first room, cw: the west corridor's width): one or two into the band's corridor, now
   and then one to the next room, through the wall between bands and from the west corridor. 0, or
   -1 when out of memory. */
static int gen__indoor_doors(gen__indoor *I, const double *sz, const double *cz, const size_t *first_room, int nstrips, double cw) {
    gen__rng *r = &I->c->rng;
    const double t = gen__T;
    for (int s = 0; s < nstrips; ++s) {
        int south = (s & 1) == 0; /* strip south of its band corridor: the corridor wall is its north side */
        double wf0 = south ? sz[2 * s + 1] : cz[2 * (s / 2) + 1], wf1 = wf0 + t;
        for (size_t k = first_room[s]; k < first_room[s + 1]; ++k) {
            gen__r2 R = I->rm[k].r;
            if (I->rm[k].kind == 2) {
                double third = (R.x1 - R.x0) / 3;
                double a0 = gen__rf(r, R.x0 + 0.5, R.x0 + third - 1.0), a1 = gen__rf(r, R.x0 + 2 * third, R.x1 - 1.5);
                if (gen__add_door(I, 0, wf0, wf1, a0, a0 + 1.0) || gen__add_door(I, 0, wf0, wf1, a1, a1 + 1.0)) return -1;
            } else {
                double a = gen__rf(r, R.x0 + 0.3, R.x1 - 1.3);
                if (gen__add_door(I, 0, wf0, wf1, a, a + 1.0)) return -1;
            }
            if (k + 1 < first_room[s + 1] && gen__chance(r, 0.35)) { /* to the next room in the strip */
                double a = gen__rf(r, R.z0 + 0.3, R.z1 - 1.3);
                if (gen__add_door(I, 1, R.x1, R.x1 + t, a, a + 1.0)) return -1;
            }
            if (!south && s + 1 < nstrips && gen__chance(r, 0.3)) { /* through the wall between bands */
                for (int tries = 0; tries < 4; ++tries) {
                    double a = gen__rf(r, R.x0 + 0.3, R.x1 - 1.3);
                    int ok = 0;
                    for (size_t q = first_room[s + 1]; q < first_room[s + 2]; ++q)
                        if (a >= I->rm[q].r.x0 + 0.3 && a + 1.0 <= I->rm[q].r.x1 - 0.3) ok = 1;
                    if (!ok) continue;
                    if (gen__add_door(I, 0, R.z1, R.z1 + t, a, a + 1.0)) return -1;
                    break;
                }
            }
        }
        if (gen__chance(r, 0.6)) { /* from the west corridor into the first room */
            double a = gen__rf(r, sz[2 * s] + 0.3, sz[2 * s + 1] - 1.3);
            if (gen__add_door(I, 1, cw, cw + t, a, a + 1.0)) return -1;
        }
    }
    return 0;
}

/* The walls: the outline (W x D), along the corridors and between bands, the west corridor's and
   the rooms' dividers. */
static void gen__indoor_walls(gen__indoor *I, const double *sz, const double *cz, const size_t *first_room, int nbands, double W, double D,
                              double cw) {
    const double t = gen__T;
    int nstrips = 2 * nbands;
    gen__wall_line(I, 0, -t, 0, -t, W + t);
    gen__wall_line(I, 0, D, D + t, -t, W + t);
    gen__wall_line(I, 1, -t, 0, 0, D);
    gen__wall_line(I, 1, W, W + t, 0, D);
    for (int b = 0; b < nbands; ++b) {
        gen__wall_line(I, 0, sz[4 * b + 1], sz[4 * b + 1] + t, cw, W);
        gen__wall_line(I, 0, cz[2 * b + 1], cz[2 * b + 1] + t, cw, W);
        if (b + 1 < nbands) gen__wall_line(I, 0, sz[4 * b + 3], sz[4 * b + 3] + t, cw, W);
    }
    for (int s = 0; s < nstrips; ++s) {
        gen__wall_line(I, 1, cw, cw + t, sz[2 * s], sz[2 * s + 1]);
        for (size_t k = first_room[s]; k + 1 < first_room[s + 1]; ++k)
            gen__wall_line(I, 1, I->rm[k].r.x1, I->rm[k].r.x1 + t, sz[2 * s], sz[2 * s + 1]);
    }
}

/* The columns of the hall (kind 2) and the furniture of the other rooms [0, nrooms). 0, or -1 when
   out of memory. */
static int gen__indoor_furnish(gen__indoor *I, size_t nrooms) {
    gen__ctx *c = I->c;
    for (size_t k = 0; k < nrooms && !c->err; ++k) {
        gen__room *rm = &I->rm[k];
        if (rm->kind == 2) {
            for (double zc = rm->r.z0 + 2.0; zc <= rm->r.z1 - 2.0 + 1e-9; zc += 4.0)
                for (double xc = rm->r.x0 + 2.5; xc <= rm->r.x1 - 2.5 + 1e-9; xc += 4.0) {
                    gen__obj(c, "column_%u", I->n_column++);
                    gen__aabox(c, xc - 0.25, 0, zc - 0.25, xc + 0.25, gen__H, zc + 0.25);
                    gen__r2 F = {xc - 0.25, zc - 0.25, xc + 0.25, zc + 0.25};
                    if (gen__grow((void **)&I->furn, &I->capf, I->nf + 1, sizeof(gen__r2))) return -1;
                    I->furn[I->nf++] = F;
                }
        } else gen__furniture(I, rm);
    }
    return 0;
}

static int gen__indoor_scene(gen__ctx *c, const gen_params *P) {
    gen__rng *r = &c->rng;
    gen__indoor I;
    memset(&I, 0, sizeof I);
    I.c = c;
    const double t = gen__T, cw = 2.8;
    double W = gen__iround(80.0 * P->size);
    if (W < 20) W = 20;
    int nbands = gen__iround(2.0 * P->size), ret = -1;
    if (nbands < 1) nbands = 1;
    /* strips of rooms (z ranges), corridors between them */
    int nstrips = 2 * nbands;
    double *sz = (double *)malloc(sizeof(double) * (size_t)nstrips * 2), *cz = (double *)malloc(sizeof(double) * (size_t)nbands * 2);
    size_t *first_room = (size_t *)malloc(sizeof(size_t) * (size_t)(nstrips + 1));
    if (!sz || !cz || !first_room) goto done;
    double z = 0;
    for (int b = 0; b < nbands; ++b) {
        double dS = gen__rf(r, 7, 11), dc = gen__rf(r, 2.4, 3.2), dN = (b == 0 && W >= 40) ? 12.0 : gen__rf(r, 7, 11);
        /* every wall's position is stored once and reused, so doors match their wall exactly */
        sz[4 * b] = z; sz[4 * b + 1] = z + dS;
        cz[2 * b] = sz[4 * b + 1] + t; cz[2 * b + 1] = cz[2 * b] + dc;
        sz[4 * b + 2] = cz[2 * b + 1] + t; sz[4 * b + 3] = sz[4 * b + 2] + dN;
        z = sz[4 * b + 3];
        if (b + 1 < nbands) z += t;
    }
    double D = z;
    /* rooms and dividers (dividers are recorded as rooms' gaps; doors decided per room) */
    for (int s = 0; s < nstrips; ++s) {
        double z0 = sz[2 * s], z1 = sz[2 * s + 1], x = cw + t;
        int hall_strip = s == 1 && W >= 40, hall_done = !hall_strip;
        first_room[s] = I.nr;
        for (;;) {
            double rw = gen__rf(r, 4, 9);
            int kind = 0;
            if (!hall_done && x > cw + t + 0.25 * (W - cw - t) && W - x > 30) { rw = gen__rf(r, 16, 22); kind = 2; hall_done = 1; }
            int last = W - (x + rw) < 4 + t;
            if (last) rw = W - x;
            if (gen__add_room(&I, x, z0, x + rw, z1, kind)) goto done;
            if (last) break;
            x += rw + t;
        }
    }
    first_room[nstrips] = I.nr;
    if (gen__indoor_doors(&I, sz, cz, first_room, nstrips, cw)) goto done;
    gen__indoor_walls(&I, sz, cz, first_room, nbands, W, D, cw);
    /* corridors as spaces */
    size_t nrooms = I.nr;
    if (gen__add_room(&I, 0, 0, cw, D, 1)) goto done;
    for (int b = 0; b < nbands; ++b)
        if (gen__add_room(&I, cw, cz[2 * b], W, cz[2 * b + 1], 1)) goto done;
    if (gen__indoor_furnish(&I, nrooms)) goto done;
    /* floor and ceiling tiles */
    {
        const double T = 4.0;
        int nx = (int)ceil((W + 2 * t) / T), nz = (int)ceil((D + 2 * t) / T);
        for (int pass = 0; pass < 2; ++pass)
            for (int j = 0; j < nz; ++j)
                for (int i = 0; i < nx; ++i) {
                    gen__obj(c, pass ? "ceiling_%d_%d" : "floor_%d_%d", i, j);
                    gen__hquad(c, -t + i * T, -t + j * T, gen__min(-t + (i + 1) * T, W + t), gen__min(-t + (j + 1) * T, D + t),
                               pass ? gen__H : 0, pass);
                }
    }
    /* cells: tiles in rooms and corridors, one per doorway */
    for (size_t k = 0; k < I.nr; ++k) gen__tile_space(&I, I.rm[k].r, I.rm[k].kind == 2 ? 2.0 : 3.0);
    for (size_t k = 0; k < I.nd; ++k) {
        const gen__door *d = &I.d[k];
        if (d->axis == 0) gen__cell(c, d->a + 0.05, 0.5, d->f0, d->b - 0.05, 2.0, d->f1);
        else gen__cell(c, d->f0, 0.5, d->a + 0.05, d->f1, 2.0, d->b - 0.05);
    }
    if (P->max_cells) gen__thin_cells(c->cells, 0, P->max_cells);
    ret = c->err ? -1 : 0;
done:
    free(sz);
    free(cz);
    free(first_room);
    free(I.d);
    free(I.rm);
    free(I.furn);
    return ret;
}

/* ------------------------------------------------------------------------------------------------
   Building: storeys of the office floor joined by a stair well and a shaft, closed slabs between */

static const double gen__SLAB = 0.4;

/* Box [x0,x1] x [y0,y1] x [z0,z1] cut into 4 m tiles (closed boxes, one object each), except where a tile meets a
   hole (holes: nh rectangles x0 z0 x1 z1); the tiles are clipped to the holes' x or z range so the opening is the
   hole itself. */
static void gen__slab(gen__ctx *c, int level, double x0, double z0, double x1, double z1, double y0, double y1,
                      const gen__r2 *holes, int nh) {
    /* cut lines: 4 m steps plus every hole edge, on both axes */
    double xs[128], zs[128];
    int nx = 0, nz = 0;
    for (double x = x0; x < x1 - 1e-9 && nx < 100; x += 4.0) xs[nx++] = x;
    for (double z = z0; z < z1 - 1e-9 && nz < 100; z += 4.0) zs[nz++] = z;
    for (int h = 0; h < nh; ++h) {
        xs[nx++] = holes[h].x0; xs[nx++] = holes[h].x1;
        zs[nz++] = holes[h].z0; zs[nz++] = holes[h].z1;
    }
    xs[nx++] = x1;
    zs[nz++] = z1;
    for (int i = 1; i < nx; ++i) /* sort, drop duplicates */
        for (int j = i; j > 0 && xs[j] < xs[j - 1]; --j) { double t = xs[j]; xs[j] = xs[j - 1]; xs[j - 1] = t; }
    for (int i = 1; i < nz; ++i)
        for (int j = i; j > 0 && zs[j] < zs[j - 1]; --j) { double t = zs[j]; zs[j] = zs[j - 1]; zs[j - 1] = t; }
    for (int j = 0; j + 1 < nz; ++j)
        for (int i = 0; i + 1 < nx; ++i) {
            double a = xs[i], b = xs[i + 1], d = zs[j], e = zs[j + 1];
            int open = 0;
            if (b - a < 1e-6 || e - d < 1e-6) continue;
            for (int h = 0; h < nh; ++h)
                open |= a >= holes[h].x0 - 1e-9 && b <= holes[h].x1 + 1e-9 && d >= holes[h].z0 - 1e-9 && e <= holes[h].z1 + 1e-9;
            if (open) continue;
            gen__obj(c, "slab_%d_%d_%d", level, i, j);
            gen__aabox(c, a, y0, d, b, y1, e);
        }
}

static int gen__building_scene(gen__ctx *c, const gen_params *P) {
    mesh plan;
    mesh_cells fcells;
    gen__ctx fc;
    gen_params fp = *P;
    const double t = gen__T, cw = 2.8, storey = gen__H + gen__SLAB;
    int storeys = (int)floor(6.0 * P->size + 0.5), ret = -1;
    uint32_t *copy = NULL;
    if (storeys < 2) storeys = 2;
    mesh_init(&plan);
    mesh_cells_init(&fcells);
    memset(&fc, 0, sizeof fc);
    fc.m = &plan;
    fc.cells = &fcells;
    fc.rng = c->rng;
    fp.size = 2.0f * P->size > 8.0f ? 8.0f : 2.0f * P->size;
    fp.max_cells = 0;
    if (gen__indoor_scene(&fc, &fp) || fc.err) goto done;
    double W = -1e300, D = -1e300;
    for (uint32_t v = 0; v < plan.vertex_count; ++v) {
        W = gen__max(W, plan.positions[3 * v] - t);
        D = gen__max(D, plan.positions[3 * v + 2] - t);
    }
    /* the stair well at the north end of the west corridor, the shaft at its south end */
    gen__r2 holes[2] = {{0.0, D - 7.6, cw, D - 0.6}, {0.4, 1.0, cw - 0.4, 3.0}};
    copy = (uint32_t *)malloc((plan.vertex_count + 1) * sizeof(uint32_t)); /* plan vertex -> this storey's */
    if (!copy) c->err = 1;
    for (int k = 0; k < storeys && !c->err; ++k) {
        double y = k * storey;
        for (uint32_t v = 0; v < plan.vertex_count; ++v) copy[v] = UINT32_MAX;
        for (uint32_t o = 0; o < plan.object_count; ++o) { /* the floor plan without its floor and ceiling tiles */
            const mesh_object *ob = &plan.objects[o];
            if (!strncmp(ob->name, "floor_", 6) || !strncmp(ob->name, "ceiling_", 8)) continue;
            gen__obj(c, "s%d_%s", k, ob->name);
            for (uint32_t tr = ob->first_triangle; tr < ob->first_triangle + ob->triangle_count; ++tr) {
                uint32_t id[3];
                for (int q = 0; q < 3; ++q) { /* shared as in the plan: its closed boxes stay closed meshes */
                    uint32_t pi = plan.indices[3 * tr + q];
                    const float *pv = plan.positions + 3 * pi;
                    if (copy[pi] == UINT32_MAX) copy[pi] = gen__v(c, pv[0], pv[1] + y, pv[2]);
                    id[q] = copy[pi];
                }
                gen__tri(c, id[0], id[1], id[2]);
            }
        }
        if (k + 1 < storeys) /* a flight of 16 steps from this floor to the next, rising northward */
            for (int st = 0; st < 16; ++st) {
                double z0 = holes[0].z0 + st * (holes[0].z1 - holes[0].z0 - 0.4) / 16.0;
                gen__obj(c, "s%d_stair_%d", k, st);
                gen__aabox(c, 0.2, y, z0, cw - 0.2, y + (st + 1) * storey / 16.0, z0 + (holes[0].z1 - holes[0].z0 - 0.4) / 16.0);
            }
        for (uint32_t i = 0; i < fcells.count; ++i) { /* the cells, but not over the stairs or the shaft */
            const float *b = fcells.boxes + 6 * (size_t)i;
            int clear = 1;
            for (int h = 0; h < 2; ++h)
                clear &= b[3] < holes[h].x0 - 0.2 || b[0] > holes[h].x1 + 0.2 || b[5] < holes[h].z0 - 0.2 || b[2] > holes[h].z1 + 0.2;
            if (clear) gen__cell(c, b[0], b[1] + y, b[2], b[3], b[4] + y, b[5]);
        }
    }
    /* slabs: the ground floor's, one between storeys (with the well and the shaft), the roof */
    for (int k = 0; k <= storeys && !c->err; ++k) {
        double y0 = k == 0 ? -gen__SLAB : (k - 1) * storey + gen__H; /* under storey k, or the roof */
        gen__slab(c, k, -t, -t, W + t, D + t, y0, y0 + gen__SLAB, holes, k == 0 || k == storeys ? 0 : 2);
    }
    if (P->max_cells) gen__thin_cells(c->cells, 0, P->max_cells);
    ret = c->err ? -1 : 0;
done:
    free(copy);
    mesh_free(&plan);
    mesh_cells_free(&fcells);
    return ret;
}

/* ------------------------------------------------------------------------------------------------
   Walls: a maze of zero-thickness quads */

/* The maze: every wall segment standing at first (hw[j * M + i] on z = j * S between x = i * S and
   (i + 1) * S, vw[j * (M + 1) + i] on x = i * S); a perfect maze by randomized depth-first search
   from square 0 (seen and stack hold M * M), then a tenth of the inner walls opened (loops). */
static void gen__walls_maze(gen__rng *r, int M, unsigned char *hw, unsigned char *vw, unsigned char *seen, uint32_t *stack) {
    size_t sp = 0;
    stack[sp++] = 0;
    seen[0] = 1;
    while (sp) {
        uint32_t cur = stack[sp - 1];
        int ci = (int)(cur % (uint32_t)M), cj = (int)(cur / (uint32_t)M), opts[4], no = 0;
        static const int dx[4] = {1, -1, 0, 0}, dz[4] = {0, 0, 1, -1};
        for (int k = 0; k < 4; ++k) {
            int ni = ci + dx[k], nj = cj + dz[k];
            if (ni >= 0 && nj >= 0 && ni < M && nj < M && !seen[(size_t)nj * M + ni]) opts[no++] = k;
        }
        if (!no) { --sp; continue; }
        int k = opts[gen__ri(r, (uint32_t)no)], ni = ci + dx[k], nj = cj + dz[k];
        if (k == 0) vw[(size_t)cj * (M + 1) + ci + 1] = 0;
        else if (k == 1) vw[(size_t)cj * (M + 1) + ci] = 0;
        else if (k == 2) hw[(size_t)(cj + 1) * M + ci] = 0;
        else hw[(size_t)cj * M + ci] = 0;
        seen[(size_t)nj * M + ni] = 1;
        stack[sp++] = (uint32_t)((size_t)nj * M + ni);
    }
    for (int j = 1; j < M; ++j) /* some loops */
        for (int i = 0; i < M; ++i)
            if (gen__chance(r, 0.1)) hw[(size_t)j * M + i] = 0;
    for (int j = 0; j < M; ++j)
        for (int i = 1; i < M; ++i)
            if (gen__chance(r, 0.1)) vw[(size_t)j * (M + 1) + i] = 0;
}

/* The walls left standing as runs of up to 4 segments, one quad each (wall_N): 8% low (seen over),
   8% raised (seen under). */
static void gen__walls_quads(gen__ctx *c, int M, double S, const unsigned char *hw, const unsigned char *vw) {
    gen__rng *r = &c->rng;
    uint32_t nwall = 0;
    for (int pass = 0; pass < 2; ++pass) {
        int lines = M + 1;
        for (int l = 0; l < lines; ++l) {
            int i = 0;
            while (i < M) {
                int on = pass == 0 ? hw[(size_t)l * M + i] : vw[(size_t)i * (M + 1) + l];
                if (!on) { ++i; continue; }
                int i1 = i;
                while (i1 < M && i1 - i < 4 && (pass == 0 ? hw[(size_t)l * M + i1] : vw[(size_t)i1 * (M + 1) + l])) ++i1;
                double y0 = 0, y1 = gen__rf(r, 2.5, 4.0), u = gen__u(r);
                if (u < 0.08) y1 = gen__rf(r, 0.8, 1.2);                          /* low: seen over */
                else if (u < 0.16) { y0 = gen__rf(r, 0.8, 1.2); y1 = gen__rf(r, 3.0, 4.0); } /* raised: seen under */
                gen__obj(c, "wall_%u", nwall++);
                uint32_t a, b, d, e;
                if (pass == 0) {
                    double zz = l * S;
                    a = gen__v(c, i * S, y0, zz); b = gen__v(c, i1 * S, y0, zz); d = gen__v(c, i1 * S, y1, zz); e = gen__v(c, i * S, y1, zz);
                } else {
                    double xx = l * S;
                    a = gen__v(c, xx, y0, i * S); b = gen__v(c, xx, y0, i1 * S); d = gen__v(c, xx, y1, i1 * S); e = gen__v(c, xx, y1, i * S);
                }
                gen__quad(c, a, b, d, e);
                i = i1;
            }
        }
    }
}

static int gen__walls(gen__ctx *c, const gen_params *P) {
    gen__rng *r = &c->rng;
    int M = gen__iround(24.0 * P->size);
    if (M < 2) M = 2;
    const double S = 4.0;
    size_t nh = (size_t)(M + 1) * M, ncell = (size_t)M * M;
    /* hw[j*M+i]: wall on z = j*S between x = i*S and (i+1)*S; vw[j*(M+1)+i]: wall on x = i*S, z in [j*S, (j+1)*S] */
    unsigned char *hw = (unsigned char *)malloc(nh * 2 + ncell);
    uint32_t *stack = (uint32_t *)malloc(sizeof(uint32_t) * ncell);
    if (!hw || !stack) { free(hw); free(stack); return -1; }
    unsigned char *vw = hw + nh, *seen = vw + nh;
    memset(hw, 1, nh * 2);
    memset(seen, 0, ncell);
    gen__walls_maze(r, M, hw, vw, seen, stack);
    gen__walls_quads(c, M, S, hw, vw);
    uint32_t npanel = 0, nbox = 0, npyr = 0;
    /* contents of each square: a free-standing panel, a small object in a corner, or nothing */
    for (int j = 0; j < M && !c->err; ++j)
        for (int i = 0; i < M; ++i) {
            double x = i * S, z = j * S, u = gen__u(r);
            if (u < 0.15) {
                double px = 0, pz = 0, len2 = 0;
                for (int tries = 0; tries < 32 && len2 < 0.04; ++tries) {
                    px = gen__rf(r, -1, 1); pz = gen__rf(r, -1, 1);
                    len2 = px * px + pz * pz;
                    if (len2 > 1) len2 = 0;
                }
                if (len2 < 0.04) { px = 1; pz = 0; len2 = 1; }
                double l = sqrt(len2), hx = px / l * 1.4, hz = pz / l * 1.4, cx = x + 2, czz = z + 2, y1 = gen__rf(r, 1.5, 3.5);
                gen__obj(c, "panel_%u", npanel++);
                uint32_t a = gen__v(c, cx - hx, 0, czz - hz), b = gen__v(c, cx + hx, 0, czz + hz);
                uint32_t d = gen__v(c, cx + hx, y1, czz + hz), e = gen__v(c, cx - hx, y1, czz - hz);
                gen__quad(c, a, b, d, e);
                continue;
            }
            double c0x = x + 0.3, c0z = z + 0.3, c1x = x + S - 0.3, c1z = z + S - 0.3;
            if (u < 0.55) {
                int cx = gen__chance(r, 0.5), cz2 = gen__chance(r, 0.5);
                double w = gen__rf(r, 0.3, 0.6), h = gen__rf(r, 0.3, 1.2);
                double ox = cx ? x + S - 0.3 - w : x + 0.3, oz = cz2 ? z + S - 0.3 - w : z + 0.3;
                if (gen__chance(r, 0.6)) {
                    gen__obj(c, "box_%u", nbox++);
                    gen__aabox(c, ox, 0, oz, ox + w, h, oz + w);
                } else {
                    gen__obj(c, "pyramid_%u", npyr++);
                    uint32_t a = gen__v(c, ox, 0, oz), b = gen__v(c, ox + w, 0, oz), d = gen__v(c, ox + w, 0, oz + w), e = gen__v(c, ox, 0, oz + w);
                    uint32_t tp = gen__v(c, ox + w / 2, h, oz + w / 2);
                    gen__quad(c, a, b, d, e);
                    gen__tri(c, a, tp, b); gen__tri(c, b, tp, d); gen__tri(c, d, tp, e); gen__tri(c, e, tp, a);
                }
                if (cx) c1x = x + S - 1.1;
                else c0x = x + 1.1;
                if (cz2) c1z = z + S - 1.1;
                else c0z = z + 1.1;
            }
            gen__cell(c, c0x, 0.5, c0z, c1x, 2.0, c1z);
        }
    free(hw);
    free(stack);
    if (P->max_cells) gen__thin_cells(c->cells, 0, P->max_cells);
    return c->err ? -1 : 0;
}

/* ------------------------------------------------------------------------------------------------
   Soup */

static int gen__soup(gen__ctx *c, const gen_params *P) {
    gen__rng *r = &c->rng;
    double L = 100.0 * P->size;
    double nobj_d = 2000.0 * P->size * P->size * P->size;
    uint32_t nobj = nobj_d < 1 ? 1u : (uint32_t)gen__iround(nobj_d);
    for (uint32_t o = 0; o < nobj && !c->err; ++o) {
        double cx = gen__rf(r, 0, L), cy = gen__rf(r, 0, L), cz = gen__rf(r, 0, L), R = gen__rf(r, 0.5, 4);
        int nt = 10 + (int)gen__ri(r, 31);
        gen__obj(c, "soup_%u", o);
        for (int t = 0; t < nt; ++t) {
            double px = 0, py = 0, pz = 0, s = gen__u(r), v[3][3];
            s = 0.15 + 2.85 * s * s * s; /* mostly small, a few up to 3 m */
            for (int tries = 0; tries < 16; ++tries) {
                px = gen__rf(r, -1, 1); py = gen__rf(r, -1, 1); pz = gen__rf(r, -1, 1);
                if (px * px + py * py + pz * pz <= 1) break;
            }
            px = cx + px * R; py = cy + py * R; pz = cz + pz * R;
            int ok = 0;
            for (int tries = 0; tries < 8 && !ok; ++tries) {
                for (int k = 0; k < 3; ++k)
                    for (int i = 0; i < 3; ++i) v[k][i] = gen__rf(r, -s, s);
                double a[3] = {v[1][0] - v[0][0], v[1][1] - v[0][1], v[1][2] - v[0][2]};
                double b[3] = {v[2][0] - v[0][0], v[2][1] - v[0][1], v[2][2] - v[0][2]};
                double n0 = a[1] * b[2] - a[2] * b[1], n1 = a[2] * b[0] - a[0] * b[2], n2 = a[0] * b[1] - a[1] * b[0];
                ok = n0 * n0 + n1 * n1 + n2 * n2 > 0.04 * s * s * s * s;
            }
            if (!ok) {
                memset(v, 0, sizeof v);
                v[1][0] = s; v[2][1] = s;
            }
            uint32_t a = gen__v(c, px + v[0][0], py + v[0][1], pz + v[0][2]);
            uint32_t b = gen__v(c, px + v[1][0], py + v[1][1], pz + v[1][2]);
            uint32_t d = gen__v(c, px + v[2][0], py + v[2][1], pz + v[2][2]);
            gen__tri(c, a, b, d);
        }
    }
    if (c->err) return -1;
    /* cells: one 3 m cube per 10 m slot if a free spot is found; triangles bucketed per slot */
    int ns = (int)floor(L / 10.0);
    if (ns < 1) ns = 1;
    double cs = L / ns;
    size_t nslot = (size_t)ns * ns * ns;
    uint32_t *cnt = (uint32_t *)calloc(nslot + 1, sizeof(uint32_t)), *list = NULL;
    int ret = -1;
    if (!cnt) return -1;
    const mesh *m = c->m;
    for (int pass = 0; pass < 2; ++pass) {
        for (uint32_t t = 0; t < m->triangle_count; ++t) {
            float lo[3] = {1e30f, 1e30f, 1e30f}, hi[3] = {-1e30f, -1e30f, -1e30f};
            for (int k = 0; k < 3; ++k) {
                const float *p = m->positions + 3 * (size_t)m->indices[3 * (size_t)t + k];
                for (int i = 0; i < 3; ++i) { lo[i] = p[i] < lo[i] ? p[i] : lo[i]; hi[i] = p[i] > hi[i] ? p[i] : hi[i]; }
            }
            int a0[3], a1[3];
            for (int i = 0; i < 3; ++i) {
                a0[i] = (int)floor(lo[i] / cs); a1[i] = (int)floor(hi[i] / cs);
                if (a0[i] < 0) a0[i] = 0;
                if (a1[i] > ns - 1) a1[i] = ns - 1;
            }
            for (int zz = a0[2]; zz <= a1[2]; ++zz)
                for (int yy = a0[1]; yy <= a1[1]; ++yy)
                    for (int xx = a0[0]; xx <= a1[0]; ++xx) {
                        size_t sidx = ((size_t)zz * ns + yy) * ns + xx;
                        if (pass == 0) ++cnt[sidx + 1];
                        else list[cnt[sidx]++] = t;
                    }
        }
        if (pass == 0) {
            for (size_t i = 0; i < nslot; ++i) cnt[i + 1] += cnt[i];
            list = (uint32_t *)malloc(sizeof(uint32_t) * (cnt[nslot] ? cnt[nslot] : 1));
            if (!list) goto done;
        }
    }
    /* after pass 1, cnt[s] is the end of slot s, cnt[s-1] (or 0) its start */
    for (size_t sidx = 0; sidx < nslot && !c->err; ++sidx) {
        size_t xx = sidx % (size_t)ns, yy = (sidx / (size_t)ns) % (size_t)ns, zz = sidx / ((size_t)ns * ns);
        uint32_t b0 = sidx ? cnt[sidx - 1] : 0, b1 = cnt[sidx];
        for (int tries = 0; tries < 6; ++tries) {
            double box[6];
            box[0] = (double)(float)(xx * cs + gen__rf(r, 0, cs - 3));
            box[1] = (double)(float)(yy * cs + gen__rf(r, 0, cs - 3));
            box[2] = (double)(float)(zz * cs + gen__rf(r, 0, cs - 3));
            box[3] = (double)(float)(box[0] + 3); box[4] = (double)(float)(box[1] + 3); box[5] = (double)(float)(box[2] + 3);
            int hit = 0;
            for (uint32_t k = b0; k < b1 && !hit; ++k) {
                const uint32_t *ix = m->indices + 3 * (size_t)list[k];
                hit = gen__tri_box(box, box + 3, m->positions + 3 * (size_t)ix[0], m->positions + 3 * (size_t)ix[1],
                                   m->positions + 3 * (size_t)ix[2]);
            }
            if (hit) continue;
            gen__cell(c, box[0], box[1], box[2], box[3], box[4], box[5]);
            break;
        }
    }
    if (P->max_cells) gen__thin_cells(c->cells, 0, P->max_cells);
    ret = c->err ? -1 : 0;
done:
    free(cnt);
    free(list);
    return ret;
}

/* ------------------------------------------------------------------------------------------------
   API */

const char *gen_kind_name(gen_kind k) {
    switch (k) {
    case GEN_CITY: return "city";
    case GEN_FOREST: return "forest";
    case GEN_INDOOR: return "indoor";
    case GEN_WALLS: return "walls";
    case GEN_SOUP: return "soup";
    case GEN_BUILDING: return "building";
    }
    return NULL;
}

int gen_kind_parse(const char *s, gen_kind *out) {
    for (int k = GEN_CITY; k <= GEN_BUILDING && s; ++k) {
        const char *n = gen_kind_name((gen_kind)k);
        if (n && strcmp(n, s) == 0) {
            if (out) *out = (gen_kind)k;
            return 0;
        }
    }
    return -1;
}

int gen_scene_ex(const gen_params *p, mesh *m, mesh_cells *cells, gen_info *info) {
    gen_info dummy;
    if (!info) info = &dummy;
    memset(info, 0, sizeof *info);
    if (!p || !m || !cells || !gen_kind_name(p->kind)) return -1;
    if (!(p->size > 0.0f && p->size <= 8.0f)) return -1;
    if (p->dense && p->kind != GEN_FOREST) return -1;
    if ((p->leaves_per_tree || p->cell_size != 0) && !p->dense) return -1;
    if (p->cell_size != 0 && !(p->cell_size >= 0.1f && p->cell_size <= 8.0f)) return -1;
    /* about 3600 size^2 trees: at most ~40M leaf triangles */
    if (p->leaves_per_tree > 10000 || (double)p->leaves_per_tree * p->size * p->size > 10000.0) return -1;
    if (m->vertex_count || m->triangle_count || m->object_count || cells->count) return -1;
    gen__ctx c;
    memset(&c, 0, sizeof c);
    c.m = m;
    c.cells = cells;
    c.rng.s = p->seed ^ (0xA0761D6478BD642Full * (uint64_t)p->kind);
    gen__next(&c.rng);
    int rc;
    switch (p->kind) {
    case GEN_CITY: rc = gen__city_scene(&c, p, info); break;
    case GEN_FOREST: rc = p->dense ? gen__forest_dense(&c, p) : gen__forest(&c, p); break;
    case GEN_INDOOR: rc = gen__indoor_scene(&c, p); break;
    case GEN_BUILDING: rc = gen__building_scene(&c, p); break;
    case GEN_WALLS: rc = gen__walls(&c, p); break;
    default: rc = gen__soup(&c, p); break;
    }
    if (rc || c.err) {
        mesh_free(m);
        mesh_cells_free(cells);
        memset(info, 0, sizeof *info);
        return -1;
    }
    if (p->kind != GEN_CITY) {
        info->regular_count = info->touching_first = info->inside_first = cells->count;
    }
    return 0;
}

int gen_scene(const gen_params *p, mesh *m, mesh_cells *cells) { return gen_scene_ex(p, m, cells, NULL); }
