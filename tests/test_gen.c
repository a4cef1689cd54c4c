/* test_gen.c - the scene generators (tools/gen.h): determinism, counts, mesh validity, and view
   cells that are proper boxes, never overlap and touch no triangle (checked with an exact
   triangle/box test, independent of the one inside gen.c). */
#include "test.h"
#include "../tools/gen.h"
#include <math.h>
#include <stdlib.h>
#include <string.h>

/* ---- helpers --------------------------------------------------------------------------------- */

static double tg_min3(double a, double b, double c) { return a < b ? (a < c ? a : c) : (b < c ? b : c); }
static double tg_max3(double a, double b, double c) { return a > b ? (a > c ? a : c) : (b > c ? b : c); }

/* Separating axis test of a triangle against a closed box (touching counts as overlap). */
static int tg_tri_box(const double lo[3], const double hi[3], const float *p0, const float *p1, const float *p2) {
    double c[3], h[3], v[3][3], e[3][3], n[3];
    int i, j, k;
    for (i = 0; i < 3; ++i) {
        c[i] = 0.5 * (lo[i] + hi[i]);
        h[i] = 0.5 * (hi[i] - lo[i]);
        v[0][i] = p0[i] - c[i];
        v[1][i] = p1[i] - c[i];
        v[2][i] = p2[i] - c[i];
    }
    for (i = 0; i < 3; ++i)
        if (tg_min3(v[0][i], v[1][i], v[2][i]) > h[i] || tg_max3(v[0][i], v[1][i], v[2][i]) < -h[i]) return 0;
    for (k = 0; k < 3; ++k)
        for (i = 0; i < 3; ++i) e[k][i] = v[(k + 1) % 3][i] - v[k][i];
    for (j = -1; j < 9; ++j) {
        double a[3], d0, d1, d2, r;
        if (j < 0) {
            n[0] = e[0][1] * e[1][2] - e[0][2] * e[1][1];
            n[1] = e[0][2] * e[1][0] - e[0][0] * e[1][2];
            n[2] = e[0][0] * e[1][1] - e[0][1] * e[1][0];
            a[0] = n[0]; a[1] = n[1]; a[2] = n[2];
        } else { /* box axis j/3 cross edge j%3 */
            const double *f = e[j % 3];
            int b = j / 3;
            a[0] = b == 0 ? 0 : b == 1 ? f[2] : -f[1];
            a[1] = b == 0 ? -f[2] : b == 1 ? 0 : f[0];
            a[2] = b == 0 ? f[1] : b == 1 ? -f[0] : 0;
        }
        d0 = a[0] * v[0][0] + a[1] * v[0][1] + a[2] * v[0][2];
        d1 = a[0] * v[1][0] + a[1] * v[1][1] + a[2] * v[1][2];
        d2 = a[0] * v[2][0] + a[1] * v[2][1] + a[2] * v[2][2];
        r = h[0] * fabs(a[0]) + h[1] * fabs(a[1]) + h[2] * fabs(a[2]);
        if (tg_min3(d0, d1, d2) > r || tg_max3(d0, d1, d2) < -r) return 0;
    }
    return 1;
}

/* Object bounding boxes, 6 floats each. */
static float *tg_object_boxes(const mesh *m) {
    float *bb = (float *)malloc(sizeof(float) * 6 * (m->object_count + 1));
    uint32_t o, t;
    int k, i;
    if (!bb) return NULL;
    for (o = 0; o < m->object_count; ++o) {
        float *b = bb + 6 * (size_t)o;
        const mesh_object *ob = &m->objects[o];
        b[0] = b[1] = b[2] = 1e30f;
        b[3] = b[4] = b[5] = -1e30f;
        for (t = ob->first_triangle; t < ob->first_triangle + ob->triangle_count; ++t)
            for (k = 0; k < 3; ++k) {
                const float *p = m->positions + 3 * (size_t)m->indices[3 * (size_t)t + k];
                for (i = 0; i < 3; ++i) {
                    if (p[i] < b[i]) b[i] = p[i];
                    if (p[i] > b[3 + i]) b[3 + i] = p[i];
                }
            }
    }
    return bb;
}

/* Number of triangles touching the box (stops counting at 1 if first_only). */
static uint32_t tg_box_hits(const mesh *m, const float *obb, const double box[6], int first_only) {
    uint32_t o, t, hits = 0;
    for (o = 0; o < m->object_count; ++o) {
        const float *b = obb + 6 * (size_t)o;
        const mesh_object *ob = &m->objects[o];
        if (b[0] > box[3] || b[3] < box[0] || b[1] > box[4] || b[4] < box[1] || b[2] > box[5] || b[5] < box[2]) continue;
        for (t = ob->first_triangle; t < ob->first_triangle + ob->triangle_count; ++t) {
            const uint32_t *ix = m->indices + 3 * (size_t)t;
            if (tg_tri_box(box, box + 3, m->positions + 3 * (size_t)ix[0], m->positions + 3 * (size_t)ix[1],
                           m->positions + 3 * (size_t)ix[2])) {
                ++hits;
                if (first_only) return hits;
            }
        }
    }
    return hits;
}

static int tg_cmp_str(const void *a, const void *b) { return strcmp(*(const char *const *)a, *(const char *const *)b); }

static uint64_t tg_hash(uint64_t h, const void *p, size_t n) {
    const unsigned char *s = (const unsigned char *)p;
    size_t i;
    for (i = 0; i < n; ++i) h = (h ^ s[i]) * 0x100000001B3ull;
    return h;
}

/* tg_hash over n 4-byte values (floats or uint32), each as its little-endian bytes: the same on any byte order */
static uint64_t tg_hash32(uint64_t h, const void *p, size_t n) {
    size_t i;
    for (i = 0; i < n; ++i) {
        uint32_t v;
        unsigned char b[4];
        memcpy(&v, (const unsigned char *)p + 4 * i, 4);
        b[0] = (unsigned char)v; b[1] = (unsigned char)(v >> 8);
        b[2] = (unsigned char)(v >> 16); b[3] = (unsigned char)(v >> 24);
        h = tg_hash(h, b, 4);
    }
    return h;
}

/* FNV-1a over every array the generator fills (positions as IEEE bits, so any last-bit
   difference between platforms shows; values as little-endian bytes, so byte order does not). */
static uint64_t tg_scene_hash(const mesh *m, const mesh_cells *cs) {
    uint64_t h = 0xCBF29CE484222325ull;
    uint32_t o;
    h = tg_hash32(h, m->positions, 3 * (size_t)m->vertex_count);
    h = tg_hash32(h, m->indices, 3 * (size_t)m->triangle_count);
    for (o = 0; o < m->object_count; ++o) {
        h = tg_hash(h, m->objects[o].name, strlen(m->objects[o].name) + 1);
        h = tg_hash32(h, &m->objects[o].first_triangle, 1);
        h = tg_hash32(h, &m->objects[o].triangle_count, 1);
    }
    return tg_hash32(h, cs->boxes, 6 * (size_t)cs->count);
}

static int tg_make(gen_kind kind, uint64_t seed, float size, uint32_t max_cells, mesh *m, mesh_cells *cs, gen_info *info) {
    gen_params p = test_gen_params(kind, seed, size, max_cells);
    return test_generate(&p, m, cs, info);
}

/* Everything that must hold for any generated scene. */
static void tg_validate(const char *what, const mesh *m, const mesh_cells *cs, const gen_info *info) {
    uint32_t o, t, i, j, next = 0, empty = 0, badname = 0, badidx = 0, nonfinite = 0, degenerate = 0, dup = 0;
    uint32_t badbox = 0, overlap = 0, blocked = 0, not_inside = 0, not_touching = 0;
    const char **names;
    float *obb;
    CHECK(m->object_count > 0 && m->triangle_count > 0 && m->vertex_count > 0 && cs->count > 0);
    for (o = 0; o < m->object_count; ++o) {
        const mesh_object *ob = &m->objects[o];
        const char *s = ob->name;
        if (ob->triangle_count == 0 || ob->first_triangle != next) ++empty;
        next = ob->first_triangle + ob->triangle_count;
        if (!s[0] || strncmp(s, "occluder", 8) == 0 || ob->flags != 0) ++badname;
        for (; *s; ++s)
            if (*s <= ' ' || *s > '~') ++badname;
    }
    CHECK(next == m->triangle_count);
    CHECK(empty == 0);
    CHECK(badname == 0);
    names = (const char **)malloc(sizeof(char *) * m->object_count);
    CHECK(names != NULL);
    if (names) {
        for (o = 0; o < m->object_count; ++o) names[o] = m->objects[o].name;
        qsort(names, m->object_count, sizeof(char *), tg_cmp_str);
        for (o = 1; o < m->object_count; ++o)
            if (strcmp(names[o - 1], names[o]) == 0) ++dup;
        CHECK(dup == 0);
        free(names);
    }
    for (i = 0; i < 3 * m->vertex_count; ++i)
        if (!isfinite(m->positions[i])) ++nonfinite;
    CHECK(nonfinite == 0);
    for (t = 0; t < m->triangle_count; ++t) {
        const uint32_t *ix = m->indices + 3 * (size_t)t;
        if (ix[0] >= m->vertex_count || ix[1] >= m->vertex_count || ix[2] >= m->vertex_count) {
            ++badidx;
            continue;
        }
        {
            const float *a = m->positions + 3 * (size_t)ix[0], *b = m->positions + 3 * (size_t)ix[1], *c = m->positions + 3 * (size_t)ix[2];
            double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, v[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
            double n0 = u[1] * v[2] - u[2] * v[1], n1 = u[2] * v[0] - u[0] * v[2], n2 = u[0] * v[1] - u[1] * v[0];
            if (!(n0 * n0 + n1 * n1 + n2 * n2 > 1e-10)) ++degenerate; /* area > 5e-6 m^2 */
        }
    }
    CHECK(badidx == 0);
    CHECK(degenerate == 0);
    /* cells */
    CHECK(info->regular_count == info->touching_first);
    CHECK(info->touching_first + info->touching_count == info->inside_first);
    CHECK(info->inside_first + info->inside_count == cs->count);
    for (i = 0; i < cs->count; ++i) {
        const float *b = cs->boxes + 6 * (size_t)i;
        for (j = 0; j < 6; ++j)
            if (!isfinite(b[j])) ++badbox;
        if (!(b[0] < b[3] && b[1] < b[4] && b[2] < b[5])) ++badbox;
    }
    CHECK(badbox == 0);
    for (i = 0; i < cs->count; ++i)
        for (j = i + 1; j < cs->count; ++j) {
            const float *a = cs->boxes + 6 * (size_t)i, *b = cs->boxes + 6 * (size_t)j;
            if (a[0] < b[3] && b[0] < a[3] && a[1] < b[4] && b[1] < a[4] && a[2] < b[5] && b[2] < a[5]) ++overlap;
        }
    CHECK(overlap == 0);
    obb = tg_object_boxes(m);
    CHECK(obb != NULL);
    if (obb) {
        for (i = 0; i < cs->count; ++i) {
            const float *b = cs->boxes + 6 * (size_t)i;
            double box[6];
            for (j = 0; j < 6; ++j) box[j] = b[j];
            if (i < info->inside_first) {
                if (tg_box_hits(m, obb, box, 1)) ++blocked;
            } else if (!tg_box_hits(m, obb, box, 1)) ++not_inside;
            if (i >= info->touching_first && i < info->inside_first) { /* within 1 mm of geometry */
                box[0] -= 1e-3; box[2] -= 1e-3; box[3] += 1e-3; box[5] += 1e-3;
                if (!tg_box_hits(m, obb, box, 1)) ++not_touching;
            }
        }
        free(obb);
    }
    CHECK(blocked == 0);
    CHECK(not_inside == 0);
    CHECK(not_touching == 0);
    if (blocked || not_inside || not_touching || overlap || degenerate)
        fprintf(stderr, "test_gen: %s: %u cells touch triangles, %u inside cells free, %u touching cells free, %u overlaps, %u degenerate\n",
                what, blocked, not_inside, not_touching, overlap, degenerate);
}

/* ---- groups ---------------------------------------------------------------------------------- */

static void tg_names(void) {
    gen_kind k = (gen_kind)0;
    int i;
    for (i = GEN_CITY; i <= GEN_BUILDING; ++i) {
        const char *n = gen_kind_name((gen_kind)i);
        CHECK(n != NULL);
        CHECK(n && gen_kind_parse(n, &k) == 0 && k == (gen_kind)i);
    }
    CHECK(gen_kind_name((gen_kind)0) == NULL);
    CHECK(gen_kind_name((gen_kind)99) == NULL);
    CHECK(gen_kind_parse("City", &k) == -1);
    CHECK(gen_kind_parse("", &k) == -1);
    CHECK(gen_kind_parse("cities", &k) == -1);
    CHECK(gen_kind_parse(NULL, &k) == -1);
}

static void tg_bad_params(void) {
    static const float sizes[] = {0.0f, -1.0f, 8.5f, 1e30f};
    gen_params p;
    mesh m;
    mesh_cells cs;
    size_t i;
    memset(&p, 0, sizeof p);
    mesh_init(&m);
    mesh_cells_init(&cs);
    p.kind = GEN_WALLS;
    p.size = 0.2f;
    CHECK(gen_scene(NULL, &m, &cs) == -1);
    CHECK(gen_scene(&p, NULL, &cs) == -1);
    CHECK(gen_scene(&p, &m, NULL) == -1);
    for (i = 0; i < sizeof sizes / sizeof sizes[0]; ++i) {
        p.size = sizes[i];
        CHECK(gen_scene(&p, &m, &cs) == -1);
    }
    p.size = (float)sqrt(-1.0 + 0.0 * p.size); /* NaN */
    CHECK(gen_scene(&p, &m, &cs) == -1);
    p.size = 0.2f;
    p.kind = (gen_kind)0;
    CHECK(gen_scene(&p, &m, &cs) == -1);
    p.kind = (gen_kind)(GEN_BUILDING + 1);
    CHECK(gen_scene(&p, &m, &cs) == -1);
    CHECK(m.object_count == 0 && m.vertex_count == 0 && cs.count == 0);
    p.kind = GEN_WALLS;
    CHECK(gen_scene(&p, &m, &cs) == 0);
    CHECK(m.object_count > 0);
    /* not empty any more: refused, and left alone */
    {
        uint32_t objects = m.object_count;
        CHECK(gen_scene(&p, &m, &cs) == -1);
        CHECK(m.object_count == objects);
    }
    mesh_free(&m);
    mesh_cells_free(&cs);
}

static void tg_determinism(void) {
    int kind;
    for (kind = GEN_CITY; kind <= GEN_SOUP; ++kind) {
        mesh a, b, c;
        mesh_cells ca, cb, cc;
        gen_info ia, ib, ic;
        float size = kind == GEN_SOUP ? 0.4f : 0.3f;
        CHECK(tg_make((gen_kind)kind, 7, size, 0, &a, &ca, &ia) == 0);
        CHECK(tg_make((gen_kind)kind, 7, size, 0, &b, &cb, &ib) == 0);
        CHECK(tg_make((gen_kind)kind, 8, size, 0, &c, &cc, &ic) == 0);
        CHECK(a.vertex_count == b.vertex_count && a.triangle_count == b.triangle_count && a.object_count == b.object_count);
        CHECK(ca.count == cb.count && memcmp(&ia, &ib, sizeof ia) == 0);
        if (a.vertex_count == b.vertex_count && a.triangle_count == b.triangle_count && a.object_count == b.object_count &&
            ca.count == cb.count) {
            uint32_t o, same_names = 1;
            CHECK(memcmp(a.positions, b.positions, sizeof(float) * 3 * (size_t)a.vertex_count) == 0);
            CHECK(memcmp(a.indices, b.indices, sizeof(uint32_t) * 3 * (size_t)a.triangle_count) == 0);
            CHECK(memcmp(ca.boxes, cb.boxes, sizeof(float) * 6 * (size_t)ca.count) == 0);
            for (o = 0; o < a.object_count; ++o)
                if (strcmp(a.objects[o].name, b.objects[o].name) || a.objects[o].first_triangle != b.objects[o].first_triangle)
                    same_names = 0;
            CHECK(same_names);
        }
        CHECK(tg_scene_hash(&a, &ca) != tg_scene_hash(&c, &cc));
        tg_validate(gen_kind_name((gen_kind)kind), &a, &ca, &ia);
        mesh_free(&a); mesh_free(&b); mesh_free(&c);
        mesh_cells_free(&ca); mesh_cells_free(&cb); mesh_cells_free(&cc);
    }
}

/* The default scenes: counts and validity. */
static void tg_defaults(void) {
    int kind;
    for (kind = GEN_CITY; kind <= GEN_SOUP; ++kind) {
        mesh m;
        mesh_cells cs;
        gen_info info;
        uint32_t o, buildings = 0, ground = 0, street = 0;
        CHECK(tg_make((gen_kind)kind, 1, 1.0f, 0, &m, &cs, &info) == 0);
        tg_validate(gen_kind_name((gen_kind)kind), &m, &cs, &info);
        for (o = 0; o < m.object_count; ++o) {
            const char *n = m.objects[o].name;
            buildings += strncmp(n, "building_", 9) == 0;
            ground += strncmp(n, "ground_", 7) == 0;
            street += strncmp(n, "lamp_", 5) == 0 || strncmp(n, "kiosk_", 6) == 0;
        }
        switch (kind) {
        case GEN_CITY:
            CHECK(m.object_count >= 2000);
            CHECK(m.triangle_count >= 200000);
            CHECK(buildings >= 300 && ground >= 1000 && street >= 300);
            CHECK(cs.count >= 300 && cs.count <= 2000);
            CHECK(info.touching_count == 4 && info.inside_count == 4);
            break;
        case GEN_FOREST:
            CHECK(m.object_count - ground >= 2500 && ground >= 100);
            CHECK(cs.count >= 300);
            break;
        case GEN_INDOOR: CHECK(m.object_count >= 300 && cs.count >= 200); break;
        case GEN_WALLS: CHECK(m.object_count >= 300 && cs.count >= 200); break;
        default: CHECK(m.object_count == 2000 && cs.count >= 300); break;
        }
        if (kind != GEN_CITY) CHECK(info.touching_count == 0 && info.inside_count == 0 && info.regular_count == cs.count);
        mesh_free(&m);
        mesh_cells_free(&cs);
    }
}

static void tg_max_cells(void) {
    mesh m;
    mesh_cells cs;
    gen_info info;
    /* a subset keeps the special cells at the end */
    CHECK(tg_make(GEN_CITY, 3, 0.4f, 40, &m, &cs, &info) == 0);
    CHECK(cs.count <= 40 && cs.count >= 30);
    CHECK(info.inside_count == 4 && info.inside_first + 4 == cs.count);
    tg_validate("city max 40", &m, &cs, &info);
    mesh_free(&m);
    mesh_cells_free(&cs);
    /* below 16 cells: regular cells only */
    CHECK(tg_make(GEN_CITY, 3, 0.4f, 10, &m, &cs, &info) == 0);
    CHECK(cs.count == 10 && info.regular_count == 10 && info.touching_count == 0 && info.inside_count == 0);
    mesh_free(&m);
    mesh_cells_free(&cs);
    CHECK(tg_make(GEN_FOREST, 3, 0.3f, 7, &m, &cs, &info) == 0);
    CHECK(cs.count == 7);
    mesh_free(&m);
    mesh_cells_free(&cs);
    CHECK(tg_make(GEN_INDOOR, 3, 0.3f, 1, &m, &cs, &info) == 0);
    CHECK(cs.count == 1);
    mesh_free(&m);
    mesh_cells_free(&cs);
}

/* Small and large sizes stay valid. */
static void tg_sizes(void) {
    static const float sizes[] = {0.01f, 0.12f, 0.55f};
    size_t i;
    int kind;
    for (kind = GEN_CITY; kind <= GEN_SOUP; ++kind)
        for (i = 0; i < sizeof sizes / sizeof sizes[0]; ++i) {
            mesh m;
            mesh_cells cs;
            gen_info info;
            CHECK(tg_make((gen_kind)kind, 11 + i, sizes[i], 0, &m, &cs, &info) == 0);
            if (cs.count) tg_validate(gen_kind_name((gen_kind)kind), &m, &cs, &info);
            mesh_free(&m);
            mesh_cells_free(&cs);
        }
}

/* Bit-identical output on every platform: pinned hashes of small scenes. Update them only when a
   generator changes on purpose (run with TEST_GEN_PRINT_HASHES=1 to print the new values). */
static void tg_golden(void) {
    static const uint64_t expect[5] = {0x5ae989a3d6da400eull, 0x24e803d55028eb01ull, 0x5700ddc30f928841ull,
                                       0x9ff11297b543a258ull, 0x2d978340fd66cdb9ull};
    int kind, print = getenv("TEST_GEN_PRINT_HASHES") != NULL;
    for (kind = GEN_CITY; kind <= GEN_SOUP; ++kind) {
        mesh m;
        mesh_cells cs;
        gen_info info;
        uint64_t h;
        CHECK(tg_make((gen_kind)kind, 42, 0.25f, 0, &m, &cs, &info) == 0);
        h = tg_scene_hash(&m, &cs);
        if (print) fprintf(stderr, "test_gen: %s 0x%016llxull\n", gen_kind_name((gen_kind)kind), (unsigned long long)h);
        CHECK(h == expect[kind - 1]);
        mesh_free(&m);
        mesh_cells_free(&cs);
    }
}

/* The dense forest (gen_params.dense): deterministic, valid, pinned, foliage down to eye height, and
   the option leaves the default forest (and the other kinds) alone. */
static void tg_dense(void) {
    mesh a, b, c, d;
    mesh_cells ca, cb, cc, cd;
    gen_params p;
    gen_info ia, id;
    uint32_t o, trees = 0, bushes = 0, low_trees = 0;
    uint64_t h;
    int print = getenv("TEST_GEN_PRINT_HASHES") != NULL;
    memset(&p, 0, sizeof p);
    p.kind = GEN_FOREST;
    p.seed = 42;
    p.size = 0.25f;
    p.dense = 1;
    mesh_init(&a); mesh_cells_init(&ca);
    mesh_init(&b); mesh_cells_init(&cb);
    mesh_init(&c); mesh_cells_init(&cc);
    mesh_init(&d); mesh_cells_init(&cd);
    CHECK(gen_scene_ex(&p, &a, &ca, &ia) == 0);
    CHECK(gen_scene(&p, &b, &cb) == 0);
    CHECK(tg_scene_hash(&a, &ca) == tg_scene_hash(&b, &cb));
    h = tg_scene_hash(&a, &ca);
    if (print) fprintf(stderr, "test_gen: forest --dense 0x%016llxull\n", (unsigned long long)h);
    CHECK(h == 0x716932b4cbc742ecull);
    tg_validate("forest --dense", &a, &ca, &ia);
    /* the default forest of the same parameters: unchanged (tg_golden's pinned value) and different */
    p.dense = 0;
    CHECK(gen_scene(&p, &c, &cc) == 0);
    CHECK(tg_scene_hash(&c, &cc) == 0x24e803d55028eb01ull);
    CHECK(tg_scene_hash(&c, &cc) != h);
    /* only the forest takes it */
    p.dense = 1;
    p.kind = GEN_CITY;
    CHECK(gen_scene(&p, &d, &cd) == -1);
    CHECK(d.object_count == 0 && cd.count == 0);
    mesh_free(&a); mesh_free(&b); mesh_free(&c);
    mesh_cells_free(&ca); mesh_cells_free(&cb); mesh_cells_free(&cc);
    /* the default size: trees and bushes, foliage reaching below eye height, a moderate size */
    p.kind = GEN_FOREST;
    p.seed = 1;
    p.size = 1.0f;
    CHECK(gen_scene_ex(&p, &d, &cd, &id) == 0);
    for (o = 0; o < d.object_count; ++o) {
        const mesh_object *ob = &d.objects[o];
        uint32_t t;
        float low = 1e30f;
        if (strncmp(ob->name, "bush_", 5) == 0) ++bushes;
        if (strncmp(ob->name, "tree_", 5) != 0) continue;
        ++trees;
        for (t = ob->first_triangle + 16; t < ob->first_triangle + ob->triangle_count; ++t) { /* the leaves */
            const float *q = d.positions + 3 * (size_t)d.indices[3 * (size_t)t];
            if (q[1] < low) low = q[1];
        }
        low_trees += low < 1.5f;
    }
    CHECK(trees >= 3000 && bushes >= 2000);
    CHECK(low_trees * 4 >= trees);
    CHECK(d.triangle_count >= 200000 && d.triangle_count <= 800000);
    CHECK(cd.count >= 300);
    tg_validate("forest --dense size 1", &d, &cd, &id);
    mesh_free(&d);
    mesh_cells_free(&cd);
}

/* The dense forest at the paper's density (gen_params.leaves_per_tree, cell_size): every tree holds
   exactly that many leaves after its 16 trunk triangles, the bushes scale with it, the inner cells
   have the asked side, and the options are refused outside the dense forest or out of range. */
static void tg_leaves_per_tree(void) {
    gen_params p;
    mesh a, b;
    mesh_cells ca, cb;
    uint32_t o, trees = 0, bushes = 0, bad = 0, small = 0, sized = 0;
    gen_info info;
    memset(&p, 0, sizeof p);
    p.kind = GEN_FOREST;
    p.seed = 3;
    p.size = 0.15f;
    p.dense = 1;
    p.leaves_per_tree = 1000;
    p.cell_size = 1.0f;
    mesh_init(&a); mesh_cells_init(&ca);
    mesh_init(&b); mesh_cells_init(&cb);
    CHECK(gen_scene_ex(&p, &b, &cb, &info) == 0);
    for (o = 0; o < b.object_count; ++o) {
        uint32_t n = b.objects[o].triangle_count;
        if (strncmp(b.objects[o].name, "tree_", 5) == 0) {
            ++trees;
            bad += n != 16 + 1000;
        } else if (strncmp(b.objects[o].name, "bush_", 5) == 0) { /* 2-3 clusters of 14-20 leaves, times 10 */
            ++bushes;
            bad += n < 280 || n > 600;
        }
    }
    CHECK(trees > 0 && bushes > 0 && bad == 0);
    for (o = 0; o < cb.count; ++o) {
        const float *q = cb.boxes + 6 * (size_t)o;
        if (q[3] - q[0] < 5.0f) { ++small; sized += fabsf(q[3] - q[0] - 1.0f) < 1e-4f && fabsf(q[5] - q[2] - 1.0f) < 1e-4f; }
    }
    CHECK(small > 0 && sized == small);
    tg_validate("forest --dense --leaves-per-tree 1000 --cell-size 1", &b, &cb, &info);
    mesh_free(&a); mesh_free(&b);
    mesh_cells_free(&ca); mesh_cells_free(&cb);
    /* refused: outside the dense forest, cell size out of range or NaN, too many leaves */
    p.dense = 0;
    CHECK(gen_scene(&p, &a, &ca) == -1);
    p.dense = 1;
    p.cell_size = 0.05f;
    CHECK(gen_scene(&p, &a, &ca) == -1);
    p.cell_size = 9.0f;
    CHECK(gen_scene(&p, &a, &ca) == -1);
    p.cell_size = (float)sqrt(-1.0 + 0.0 * p.size);
    CHECK(gen_scene(&p, &a, &ca) == -1);
    p.cell_size = 0.0f;
    p.leaves_per_tree = 10001;
    CHECK(gen_scene(&p, &a, &ca) == -1);
    p.leaves_per_tree = 1000; /* 1000 x 4^2 > 10000: about 600M triangles */
    p.size = 4.0f;
    CHECK(gen_scene(&p, &a, &ca) == -1);
    CHECK(a.object_count == 0 && ca.count == 0);
}

/* The building: valid (cells clear of every triangle, names unique) on a small one; storeys, slabs, stairs; the
   same scene twice; over 10,000 objects at size 1 (issue 28). */
static void tg_building(void) {
    mesh a, b;
    mesh_cells ca, cb;
    gen_info ia, ib;
    uint32_t o, storey1 = 0, slab = 0, stairs = 0;
    CHECK(tg_make(GEN_BUILDING, 3, 0.3f, 0, &a, &ca, &ia) == 0);
    tg_validate("building", &a, &ca, &ia);
    for (o = 0; o < a.object_count; ++o) {
        storey1 += strncmp(a.objects[o].name, "s1_", 3) == 0;
        slab += strncmp(a.objects[o].name, "slab_1_", 7) == 0;
        stairs += strstr(a.objects[o].name, "_stair_") != NULL;
    }
    CHECK(storey1 >= 50 && slab >= 10 && stairs == 16);
    if (!(storey1 >= 50 && slab >= 10 && stairs == 16)) fprintf(stderr, "  building: %u %u %u\n", storey1, slab, stairs);
    CHECK(tg_make(GEN_BUILDING, 3, 0.3f, 0, &b, &cb, &ib) == 0);
    CHECK(tg_scene_hash(&a, &ca) == tg_scene_hash(&b, &cb));
    mesh_free(&a);
    mesh_free(&b);
    mesh_cells_free(&ca);
    mesh_cells_free(&cb);
    CHECK(tg_make(GEN_BUILDING, 1, 1.0f, 0, &a, &ca, &ia) == 0);
    CHECK(a.object_count >= 10000 && ca.count >= 1000);
    mesh_free(&a);
    mesh_cells_free(&ca);
}

void test_gen(void);
void test_gen(void) {
    tg_building();
    tg_names();
    tg_bad_params();
    tg_determinism();
    tg_defaults();
    tg_max_cells();
    tg_sizes();
    tg_golden();
    tg_dense();
    tg_leaves_per_tree();
}
