/* test_extproj.c - the extended projections of Durand et al. 2000 (PVS_METHOD_EXTPROJ) against
   brute force: the occluder Projection (every marked pixel is covered by the occluder from random
   points of the cell, checked by ray casts in double), the occludee Projection (random points of the
   box seen from random points of the cell land inside the rectangle, no nearer than its Depth), and
   the bake against ray sampling on small generated scenes (0 misses). */
#include "../pvs.h"
#include "../tools/gen.h"
#include "../tools/mesh.h"
#include "test.h"
#include <math.h>
#include <stdlib.h>
#include <string.h>

static uint64_t ep_state = 0x7e57e97dull;
static double ep_rnd(void) {
    uint64_t z = (ep_state += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    z ^= z >> 31;
    return (double)(z >> 11) * (1.0 / 9007199254740992.0);
}
static float ep_rndf(float lo, float hi) { return lo + (hi - lo) * (float)ep_rnd(); }

/* A random plane of a random cell. */
static void ep_random_plane(pvs_extproj_plane *pl, uint32_t res) {
    int k, u, v;
    memset(pl, 0, sizeof(*pl));
    for (k = 0; k < 3; ++k) {
        pl->cell.min[k] = ep_rndf(-2.0f, 2.0f);
        pl->cell.max[k] = pl->cell.min[k] + ep_rndf(0.0f, 3.0f);
    }
    pl->axis = (uint32_t)(ep_rnd() * 3.0) % 3;
    pl->side = ep_rnd() < 0.5 ? 1 : -1;
    pl->distance = ep_rndf(0.5f, 10.0f);
    u = (int)(pl->axis + 1) % 3;
    v = (int)(pl->axis + 2) % 3;
    pl->rect[0] = pl->cell.min[u] - ep_rndf(0.5f, 15.0f);
    pl->rect[1] = pl->cell.min[v] - ep_rndf(0.5f, 15.0f);
    pl->rect[2] = pl->cell.max[u] + ep_rndf(0.5f, 15.0f);
    pl->rect[3] = pl->cell.max[v] + ep_rndf(0.5f, 15.0f);
    pl->width = res;
    pl->height = res + (uint32_t)(ep_rnd() * 8.0);
}

/* World point of plane position (pu, pv) (world units) on the plane. */
static void ep_plane_point(const pvs_extproj_plane *pl, double pu, double pv, double out[3]) {
    int a = (int)pl->axis;
    out[a] = pl->side > 0 ? (double)pl->cell.max[a] + pl->distance : (double)pl->cell.min[a] - pl->distance;
    out[(a + 1) % 3] = pu;
    out[(a + 2) % 3] = pv;
}

/* Ray o + t d, t in (0, 1], against triangle (double, two-sided): returns t or -1. */
static double ep_ray_tri(const double *o, const double *d, const float *a, const float *b, const float *c) {
    double e1[3], e2[3], p[3], q[3], s[3], det, u, v, t;
    int k;
    for (k = 0; k < 3; ++k) { e1[k] = (double)b[k] - a[k]; e2[k] = (double)c[k] - a[k]; s[k] = o[k] - a[k]; }
    p[0] = d[1] * e2[2] - d[2] * e2[1]; p[1] = d[2] * e2[0] - d[0] * e2[2]; p[2] = d[0] * e2[1] - d[1] * e2[0];
    det = e1[0] * p[0] + e1[1] * p[1] + e1[2] * p[2];
    if (fabs(det) < 1e-300) return -1.0;
    u = (s[0] * p[0] + s[1] * p[1] + s[2] * p[2]) / det;
    q[0] = s[1] * e1[2] - s[2] * e1[1]; q[1] = s[2] * e1[0] - s[0] * e1[2]; q[2] = s[0] * e1[1] - s[1] * e1[0];
    v = (d[0] * q[0] + d[1] * q[1] + d[2] * q[2]) / det;
    t = (e2[0] * q[0] + e2[1] * q[1] + e2[2] * q[2]) / det;
    if (u < 0.0 || v < 0.0 || u + v > 1.0 || t < 0.0) return -1.0;
    return t;
}

/* The occluder Projection: each marked pixel is covered from random points of the cell, and the
   first hit is no deeper than the stored Depth. */
static void test_occluder_projection(void) {
    int iter, bad = 0, marked_total = 0, checked = 0;
    for (iter = 0; iter < 300; ++iter) {
        pvs_extproj_plane pl;
        float pts[8 * 3], *map;
        uint32_t n, i, j, k, written, count = 0;
        int a, kind = iter % 3, tris[12][3], ntris = 0;
        ep_random_plane(&pl, 32);
        a = (int)pl.axis;
        map = (float *)malloc(sizeof(float) * pl.width * pl.height);
        for (i = 0; i < pl.width * pl.height; ++i) map[i] = PVS_EXTPROJ_EMPTY;
        {
            /* an occluder somewhere in front of the cell (sometimes straddling the face) */
            double face = pl.side > 0 ? pl.cell.max[a] : pl.cell.min[a], c[3];
            double depth = ep_rndf(-0.5f, 12.0f), size = ep_rndf(0.5f, 8.0f);
            int u = (a + 1) % 3, v = (a + 2) % 3;
            c[a] = face + pl.side * depth;
            c[u] = 0.5 * (pl.cell.min[u] + pl.cell.max[u]) + ep_rndf(-3.0f, 3.0f);
            c[v] = 0.5 * (pl.cell.min[v] + pl.cell.max[v]) + ep_rndf(-3.0f, 3.0f);
            if (kind == 0) { /* triangle */
                n = 3;
                for (i = 0; i < 3; ++i)
                    for (k = 0; k < 3; ++k) pts[3 * i + k] = (float)(c[k] + size * ep_rndf(-1.0f, 1.0f));
                tris[0][0] = 0; tris[0][1] = 1; tris[0][2] = 2; ntris = 1;
            } else if (kind == 1) { /* planar convex quad: a parallelogram */
                float e1[3], e2[3];
                n = 4;
                for (k = 0; k < 3; ++k) { e1[k] = (float)size * ep_rndf(-1.0f, 1.0f); e2[k] = (float)size * ep_rndf(-1.0f, 1.0f); }
                for (k = 0; k < 3; ++k) {
                    pts[k] = (float)c[k];
                    pts[3 + k] = (float)c[k] + e1[k];
                    pts[6 + k] = (float)c[k] + e1[k] + e2[k];
                    pts[9 + k] = (float)c[k] + e2[k];
                }
                tris[0][0] = 0; tris[0][1] = 1; tris[0][2] = 2; tris[1][0] = 0; tris[1][1] = 2; tris[1][2] = 3; ntris = 2;
            } else { /* box solid */
                float h[3];
                static const int bt[12][3] = {{0, 1, 3}, {0, 3, 2}, {4, 5, 7}, {4, 7, 6}, {0, 1, 5}, {0, 5, 4},
                                              {2, 3, 7}, {2, 7, 6}, {0, 2, 6}, {0, 6, 4}, {1, 3, 7}, {1, 7, 5}};
                n = 8;
                for (k = 0; k < 3; ++k) h[k] = (float)size * ep_rndf(0.1f, 1.0f);
                for (i = 0; i < 8; ++i)
                    for (k = 0; k < 3; ++k) pts[3 * i + k] = (float)c[k] + ((i >> k) & 1 ? h[k] : -h[k]);
                memcpy(tris, bt, sizeof(bt));
                ntris = 12;
            }
        }
        written = pvs_extproj_occluder(&pl, pts, n, map);
        for (j = 0; j < pl.height; ++j)
            for (i = 0; i < pl.width; ++i) {
                float dstored = map[j * pl.width + i];
                int s;
                if (dstored == PVS_EXTPROJ_EMPTY) continue;
                ++count;
                for (s = 0; s < 12; ++s) {
                    double V[3], P[3], dir[3], best = 2.0, face = pl.side > 0 ? pl.cell.max[a] : pl.cell.min[a], hitw;
                    double pu = pl.rect[0] + ((double)i + ep_rnd()) * ((double)pl.rect[2] - pl.rect[0]) / pl.width;
                    double pv = pl.rect[1] + ((double)j + ep_rnd()) * ((double)pl.rect[3] - pl.rect[1]) / pl.height;
                    int t2;
                    if (s < 4) { /* pixel corners, cell corners */
                        pu = pl.rect[0] + (double)(i + (s & 1)) * ((double)pl.rect[2] - pl.rect[0]) / pl.width;
                        pv = pl.rect[1] + (double)(j + ((s >> 1) & 1)) * ((double)pl.rect[3] - pl.rect[1]) / pl.height;
                    }
                    for (k = 0; k < 3; ++k) V[k] = s < 8 ? ((ep_rnd() < 0.5) ? pl.cell.min[k] : pl.cell.max[k]) : pl.cell.min[k] + ep_rnd() * ((double)pl.cell.max[k] - pl.cell.min[k]);
                    ep_plane_point(&pl, pu, pv, P);
                    for (k = 0; k < 3; ++k) dir[k] = (P[k] - V[k]) * 1000.0; /* well past the plane */
                    for (t2 = 0; t2 < ntris; ++t2) {
                        double t = ep_ray_tri(V, dir, pts + 3 * tris[t2][0], pts + 3 * tris[t2][1], pts + 3 * tris[t2][2]);
                        if (t >= 0.0 && t < best) best = t;
                    }
                    ++checked;
                    if (best > 1.0) { ++bad; continue; }
                    hitw = pl.side * (V[a] + best * dir[a] - face);
                    if (hitw > (double)dstored + 1e-9 * (1.0 + fabs(hitw))) ++bad;
                }
            }
        CHECK(count <= written && (count > 0) == (written > 0));
        marked_total += (int)count;
        free(map);
    }
    CHECK(bad == 0);
    CHECK(marked_total > 1000); /* the test exercises something */
    CHECK(checked > 10000);
    if (bad) fprintf(stderr, "extproj: %d occluder samples not covered of %d\n", bad, checked);
}

/* The occludee Projection holds every view of the box from the cell. */
static void test_occludee_projection(void) {
    int iter, bad = 0, tested = 0;
    for (iter = 0; iter < 2000; ++iter) {
        pvs_extproj_plane pl;
        pvs_box b;
        int32_t r[4];
        float depth;
        int a, u, v, k, s;
        double face;
        ep_random_plane(&pl, 64);
        a = (int)pl.axis;
        u = (a + 1) % 3;
        v = (a + 2) % 3;
        face = pl.side > 0 ? pl.cell.max[a] : pl.cell.min[a];
        for (k = 0; k < 3; ++k) {
            float c = 0.5f * (pl.cell.min[k] + pl.cell.max[k]) + ep_rndf(-6.0f, 6.0f), h = ep_rndf(0.0f, 2.0f);
            if (k == a) c = (float)(face + pl.side * ep_rndf(-1.0f, 15.0f));
            b.min[k] = c - h;
            b.max[k] = c + h;
        }
        if (!pvs_extproj_occludee(&pl, &b, r, &depth)) {
            /* refused only when the box reaches the face */
            double w0 = pl.side > 0 ? (double)b.min[a] - face : face - (double)b.max[a];
            CHECK(!(w0 > 0.0));
            continue;
        }
        ++tested;
        CHECK(r[0] <= r[2] && r[1] <= r[3]);
        for (s = 0; s < 40; ++s) {
            double V[3], Q[3], t, x, y, w, Vw, Qw;
            for (k = 0; k < 3; ++k) {
                V[k] = s < 8 ? ((s >> k) & 1 ? pl.cell.max[k] : pl.cell.min[k]) : pl.cell.min[k] + ep_rnd() * ((double)pl.cell.max[k] - pl.cell.min[k]);
                Q[k] = s < 16 ? ((ep_rnd() < 0.5) ? b.min[k] : b.max[k]) : b.min[k] + ep_rnd() * ((double)b.max[k] - b.min[k]);
            }
            Vw = pl.side * (V[a] - face);
            Qw = pl.side * (Q[a] - face);
            w = pl.distance;
            t = (w - Vw) / (Qw - Vw);
            x = (V[u] + (Q[u] - V[u]) * t - pl.rect[0]) * pl.width / ((double)pl.rect[2] - pl.rect[0]);
            y = (V[v] + (Q[v] - V[v]) * t - pl.rect[1]) * pl.height / ((double)pl.rect[3] - pl.rect[1]);
            /* inside the rectangle's pixels (clamped rectangles stand for "beyond the map") */
            if (!((x >= r[0] || r[0] == -1) && (x <= r[2] + 1 || r[2] == (int32_t)pl.width))) ++bad;
            if (!((y >= r[1] || r[1] == -1) && (y <= r[3] + 1 || r[3] == (int32_t)pl.height))) ++bad;
            if (Qw < depth) ++bad;
        }
    }
    CHECK(tested > 500);
    CHECK(bad == 0);
    if (bad) fprintf(stderr, "extproj: %d occludee samples outside the Projection\n", bad);
}

/* A mesh as a scene (every object drawable). */
static pvs_scene *ep_scene(const mesh *m) {
    pvs_scene_desc d;
    pvs_object_desc *obs = (pvs_object_desc *)malloc(m->object_count * sizeof(pvs_object_desc));
    pvs_scene *s = NULL;
    pvs_error e;
    uint32_t i;
    for (i = 0; i < m->object_count; ++i) {
        obs[i].first_triangle = m->objects[i].first_triangle;
        obs[i].triangle_count = m->objects[i].triangle_count;
        obs[i].flags = 0;
    }
    memset(&d, 0, sizeof(d));
    d.positions = m->positions;
    d.vertex_count = m->vertex_count;
    d.indices = m->indices;
    d.triangle_count = m->triangle_count;
    d.objects = obs;
    d.object_count = m->object_count;
    if (pvs_scene_create(&d, &s, &e) != PVS_OK) fprintf(stderr, "extproj scene: %s\n", e.message);
    free(obs);
    return s;
}

/* Bake a generated scene with EXTPROJ and compare every cell with ray sampling: no misses. */
static void ep_check_scene(gen_kind kind, uint64_t seed, float size, uint32_t max_cells, uint32_t points, uint32_t rays) {
    gen_params gp;
    mesh m;
    mesh_cells cells;
    pvs_scene *s;
    pvs_bake_desc bd;
    pvs_bake *bake = NULL;
    pvs_error e;
    uint32_t t, objects, misses = 0;
    double pvs_sum = 0.0, seen_sum = 0.0;
    pvs_word *seen;
    memset(&gp, 0, sizeof(gp));
    gp.kind = kind;
    gp.seed = seed;
    gp.size = size;
    gp.max_cells = max_cells;
    mesh_init(&m);
    mesh_cells_init(&cells);
    CHECK(gen_scene(&gp, &m, &cells) == 0);
    s = ep_scene(&m);
    CHECK(s != NULL);
    if (!s) return;
    objects = pvs_scene_object_count(s);
    memset(&bd, 0, sizeof(bd));
    bd.scene = s;
    bd.cells = (const pvs_box *)cells.boxes;
    bd.cell_count = cells.count;
    bd.method = PVS_METHOD_EXTPROJ;
    CHECK(pvs_bake_begin(&bd, &bake, &e) == PVS_OK);
    seen = (pvs_word *)calloc(PVS_BITSET_WORDS(objects), sizeof(pvs_word));
    for (t = 0; t < pvs_bake_task_count(bake); ++t) {
        const pvs_word *pvs;
        uint32_t o;
        CHECK(pvs_bake_run_task(bake, t, &e) == PVS_OK);
        pvs = pvs_bake_cell_pvs(bake, t);
        memset(seen, 0, PVS_BITSET_WORDS(objects) * sizeof(pvs_word));
        pvs_sample_visibility(s, (const pvs_box *)cells.boxes + t, points, rays, 1000 + t, seen);
        for (o = pvs_bitset_next(seen, objects, 0); o < objects; o = pvs_bitset_next(seen, objects, o + 1))
            if (!pvs_bitset_test(pvs, o)) {
                if (misses < 5) fprintf(stderr, "extproj %s: cell %u misses object %u\n", gen_kind_name(kind), t, o);
                ++misses;
            }
        pvs_sum += pvs_bitset_count(pvs, objects);
        seen_sum += pvs_bitset_count(seen, objects);
    }
    CHECK(misses == 0);
    {
        /* the same bake with the tasks in reverse order writes the same bytes */
        pvs_bake *b2 = NULL;
        size_t n1 = pvs_bake_file_size(bake), n2;
        void *f1 = malloc(n1 ? n1 : 1), *f2;
        CHECK(pvs_bake_begin(&bd, &b2, &e) == PVS_OK);
        for (t = pvs_bake_task_count(b2); t-- > 0;) CHECK(pvs_bake_run_task(b2, t, &e) == PVS_OK);
        n2 = pvs_bake_file_size(b2);
        f2 = malloc(n2 ? n2 : 1);
        CHECK(n1 > 0 && n1 == n2);
        CHECK(pvs_bake_write_file(bake, f1, n1, &n1, &e) == PVS_OK && pvs_bake_write_file(b2, f2, n2, &n2, &e) == PVS_OK);
        CHECK(n1 == n2 && memcmp(f1, f2, n1) == 0);
        free(f1);
        free(f2);
        pvs_bake_destroy(b2);
    }
    if (kind == GEN_CITY || kind == GEN_WALLS || kind == GEN_INDOOR) CHECK(pvs_sum < 0.9 * objects * pvs_bake_task_count(bake)); /* culls */
    fprintf(stderr, "  extproj %-6s %3u cells: mean PVS %.1f, sampled %.1f, of %u objects\n", gen_kind_name(kind), pvs_bake_task_count(bake),
            pvs_sum / pvs_bake_task_count(bake), seen_sum / pvs_bake_task_count(bake), objects);
    free(seen);
    pvs_bake_destroy(bake);
    pvs_scene_destroy(s);
    mesh_free(&m);
    mesh_cells_free(&cells);
}

/* Thin two-sided walls: a wall between the cell and an object hides it; a wall with a gap does not. */
static void test_thin_wall(void) {
    /* object 0: a wall quad at x = 5 (y 0..4, z -4..4); object 1: a small box behind it at x = 10 */
    static const float pos[] = {5, 0, -4, 5, 0, 4, 5, 4, 4, 5, 4, -4, 10, 1, -0.5f, 11, 1, -0.5f, 11, 2, -0.5f, 10, 2, -0.5f,
                                10, 1, 0.5f, 11, 1, 0.5f, 11, 2, 0.5f, 10, 2, 0.5f};
    static const uint32_t idx[] = {0, 1, 2, 0, 2, 3, 4, 5, 6, 4, 6, 7, 8, 9, 10, 8, 10, 11, 4, 5, 9, 4, 9, 8, 7, 6, 10, 7, 10, 11,
                                   4, 7, 11, 4, 11, 8, 5, 6, 10, 5, 10, 9};
    pvs_object_desc obs[2] = {{0, 2, 0}, {2, 12, 0}};
    pvs_scene_desc d;
    pvs_scene *s;
    pvs_box cells[2] = {{{0, 1, -1}, {1, 3, 1}}, {{0, 1, -1}, {1, 3, 9}}};
    pvs_bake_desc bd;
    pvs_bake *b;
    pvs_error e;
    memset(&d, 0, sizeof(d));
    d.positions = pos;
    d.vertex_count = 12;
    d.indices = idx;
    d.triangle_count = 14;
    d.objects = obs;
    d.object_count = 2;
    CHECK(pvs_scene_create(&d, &s, &e) == PVS_OK);
    memset(&bd, 0, sizeof(bd));
    bd.scene = s;
    bd.cells = cells;
    bd.cell_count = 2;
    bd.method = PVS_METHOD_EXTPROJ;
    CHECK(pvs_bake_begin(&bd, &b, &e) == PVS_OK);
    CHECK(pvs_bake_run_task(b, 0, &e) == PVS_OK);
    CHECK(pvs_bake_run_task(b, 1, &e) == PVS_OK);
    CHECK(pvs_bitset_test(pvs_bake_cell_pvs(b, 0), 0));
    CHECK(!pvs_bitset_test(pvs_bake_cell_pvs(b, 0), 1)); /* hidden behind the thin wall */
    CHECK(pvs_bitset_test(pvs_bake_cell_pvs(b, 1), 1));  /* a cell reaching past the wall's end sees it */
    CHECK(strcmp(pvs_method_name(PVS_METHOD_EXTPROJ), "extproj") == 0);
    pvs_bake_destroy(b);
    pvs_scene_destroy(s);
}

void test_extproj(void) {
    test_occluder_projection();
    test_occludee_projection();
    test_thin_wall();
    ep_check_scene(GEN_CITY, 1, 0.3f, 24, 16, 1024);
    ep_check_scene(GEN_WALLS, 2, 0.4f, 30, 16, 1024);
    ep_check_scene(GEN_INDOOR, 1, 0.3f, 30, 16, 1024);
    ep_check_scene(GEN_FOREST, 1, 0.25f, 20, 16, 1024);
    ep_check_scene(GEN_SOUP, 3, 0.3f, 20, 16, 1024);
}
