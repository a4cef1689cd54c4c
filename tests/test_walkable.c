/* test_walkable.c - pvs_walkable_cells (view cells from walkable space) on a generated multi-storey
   building (every floor; its stacked stair flights leave no head room, so a walk could not climb
   them) and a city (the floors a walk reaches from a street, not roofs, ledges or courtyards), each
   against the generator's own hand-placed cells: every point a player stands on in them (random, on
   the floor below a hand-placed cell) has its eye half a metre and 1.75 m up in a walkable cell; no
   cell lies mostly inside solid geometry (brute force: a ray from each of 16 points at the cell's
   mid-height crosses the triangles of the objects around it an even number of times for most); the
   count stays within 2x of the hand-placed cells. Then merging, a walk that drops but never climbs a wall, view
   volumes and bad parameters. */
#include "../pvs.h"
#include "../tools/cli.h"
#include "test.h"
#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Crossings of the ray p + t d (t > 0) with the triangles of the objects whose box holds p (double, Moller-Trumbore). */
static uint32_t wk_crossings(const mesh *m, const pvs_scene *s, const double p[3], const double d[3]) {
    uint32_t o, t, n = 0;
    for (o = 0; o < m->object_count; ++o) {
        pvs_box b = pvs_scene_object_box(s, o);
        if (p[0] < b.min[0] || p[0] > b.max[0] || p[1] < b.min[1] || p[1] > b.max[1] || p[2] < b.min[2] || p[2] > b.max[2])
            continue;
        for (t = m->objects[o].first_triangle; t < m->objects[o].first_triangle + m->objects[o].triangle_count; ++t) {
            double h[3];
            if (test_ray_triangle(p, d, m->positions + 3 * m->indices[3 * t], m->positions + 3 * m->indices[3 * t + 1],
                                  m->positions + 3 * m->indices[3 * t + 2], 1e-12, h))
                n += h[0] >= 0 && h[1] >= 0 && h[0] + h[1] <= 1 && h[2] > 0;
        }
    }
    return n;
}

static int wk_in_cells(const pvs_box *cells, uint32_t n, const float p[3]) {
    uint32_t i;
    for (i = 0; i < n; ++i)
        if (p[0] >= cells[i].min[0] && p[0] <= cells[i].max[0] && p[1] >= cells[i].min[1] && p[1] <= cells[i].max[1] &&
            p[2] >= cells[i].min[2] && p[2] <= cells[i].max[2])
            return 1;
    return 0;
}

/* The checks on one generated scene with cells of `size`. */
static void wk_check(const char *label, gen_kind kind, float gsize, float size, int seeded, int solids) {
    mesh m;
    mesh_cells hand;
    pvs_scene *s = NULL;
    tool_error te;
    gen_params gp = test_gen_params(kind, 1, gsize, 0);
    pvs_walkable_desc wd;
    pvs_box *cells = NULL, bounds;
    float seed[3];
    uint32_t n = 0, n2 = 0, i, tried = 0, standing = 0, outside = 0, solid = 0;
    uint64_t rng = 99;
    CHECK(test_generate(&gp, &m, &hand, NULL) == 0);
    CHECK(cli_make_scene(label, &m, 1, &s, &te) == 0);
    if (!s) return;
    memset(&wd, 0, sizeof(wd));
    wd.cell_size = size;
    seed[0] = 0.5f * (hand.boxes[0] + hand.boxes[3]); /* on the floor under the first hand-placed cell */
    seed[1] = hand.boxes[1];
    seed[2] = 0.5f * (hand.boxes[2] + hand.boxes[5]);
    if (seeded) wd.seed = seed;
    CHECK(pvs_walkable_cells(s, &wd, NULL, 0, &n, NULL) == PVS_OK && n > 0);
    cells = (pvs_box *)malloc((n ? n : 1) * sizeof(pvs_box));
    CHECK(pvs_walkable_cells(s, &wd, cells, n, &n2, NULL) == PVS_OK && n2 == n);
    bounds = pvs_scene_bounds(s);
    (void)bounds;
    /* standing points: anywhere in the generator's hand-placed cells (on streets, in rooms, clear of furniture), on
       the floor half a metre below them; the eye half a metre and 1.75 m up must be in a walkable cell */
    for (tried = 0; tried < 4000; ++tried) {
        const float *hb = hand.boxes + 6 * (test_splitmix64(&rng) % hand.count);
        float eye[3], floor_y = hb[1] - 0.5f;
        eye[0] = test_rndf(&rng, hb[0], hb[3]);
        eye[2] = test_rndf(&rng, hb[2], hb[5]);
        ++standing;
        eye[1] = floor_y + 0.5f;
        if (!wk_in_cells(cells, n, eye) || (eye[1] = floor_y + 1.75f, !wk_in_cells(cells, n, eye))) {
            if (outside < 5) fprintf(stderr, "walkable %s: eye (%g %g %g) in no cell\n", label, eye[0], eye[1], eye[2]);
            ++outside;
        }
    }
    for (i = 0; solids && i < n; ++i) { /* at mid-height, most of a 4 x 4 grid of points outside every closed solid */
        uint32_t a, b, in = 0;
        for (a = 0; a < 4; ++a)
            for (b = 0; b < 4; ++b) {
                double hs = size / 4.0, u0 = cells[i].min[0] + hs, v0 = cells[i].min[2] + hs; /* column centres */
                double p[3] = {u0 + a / 3.0 * ((double)cells[i].max[0] - hs - u0), 0.5 * ((double)cells[i].min[1] + cells[i].max[1]),
                               v0 + b / 3.0 * ((double)cells[i].max[2] - hs - v0)};
                double d[3] = {0.8017837, 0.0112, 0.5976143};
                in += wk_crossings(&m, s, p, d) & 1u;
            }
        if (in > 8) {
            if (solid < 5) fprintf(stderr, "walkable %s: cell %u (%g %g %g .. %g %g %g) is mostly inside solid geometry\n", label,
                                   i, cells[i].min[0], cells[i].min[1], cells[i].min[2], cells[i].max[0], cells[i].max[1],
                                   cells[i].max[2]);
            ++solid;
        }
    }
    fprintf(stderr, "  walkable %s: %u cells (hand-placed %u), %u standing points, %u outside cells, %u in solids\n", label, n,
            hand.count, standing, outside, solid);
    CHECK(standing > 100 && outside == 0 && solid == 0);
    CHECK(n <= 2 * hand.count);
    free(cells);
    pvs_scene_destroy(s);
    mesh_free(&m);
    mesh_cells_free(&hand);
}

/* View volumes bound the cells; bad parameters are refused with their codes. */
static void wk_params(void) {
    mesh m;
    mesh_cells hand;
    pvs_scene *s = NULL;
    tool_error te;
    gen_params gp = test_gen_params(GEN_INDOOR, 2, 0.5f, 0);
    pvs_walkable_desc wd;
    pvs_box cells[256], vol = {{0, -1, 0}, {12, 5, 9}};
    uint32_t n = 0, i;
    float bad_seed[3] = {0, NAN, 0};
    CHECK(test_generate(&gp, &m, &hand, NULL) == 0);
    CHECK(cli_make_scene("indoor", &m, 1, &s, &te) == 0);
    if (!s) return;
    memset(&wd, 0, sizeof(wd));
    wd.volumes = &vol;
    wd.volume_count = 1;
    CHECK(pvs_walkable_cells(s, &wd, cells, 256, &n, NULL) == PVS_OK && n > 0 && n < 256);
    for (i = 0; i < n && i < 256; ++i)
        CHECK(cells[i].min[0] >= 0 && cells[i].max[0] <= 12 && cells[i].min[2] >= 0 && cells[i].max[2] <= 9);
    wd.volumes = NULL;
    CHECK(pvs_walkable_cells(s, &wd, NULL, 0, &n, NULL) == PVS_ERROR_INVALID_ARGUMENT); /* volume_count 1, none */
    wd.volume_count = 0;
    wd.max_slope = 1.6f;
    CHECK(pvs_walkable_cells(s, &wd, NULL, 0, &n, NULL) == PVS_ERROR_INVALID_ARGUMENT);
    wd.max_slope = 0;
    wd.cell_size = -1;
    CHECK(pvs_walkable_cells(s, &wd, NULL, 0, &n, NULL) == PVS_ERROR_INVALID_ARGUMENT);
    wd.cell_size = 1e-4f; /* over 2^26 sample columns */
    CHECK(pvs_walkable_cells(s, &wd, NULL, 0, &n, NULL) == PVS_ERROR_COUNT_OVERFLOW);
    wd.cell_size = 0;
    wd.seed = bad_seed;
    CHECK(pvs_walkable_cells(s, &wd, NULL, 0, &n, NULL) == PVS_ERROR_NOT_FINITE);
    CHECK(pvs_walkable_cells(NULL, NULL, NULL, 0, &n, NULL) == PVS_ERROR_INVALID_ARGUMENT);
    pvs_scene_destroy(s);
    mesh_free(&m);
    mesh_cells_free(&hand);
}

/* A 40 x 40 floor, with a closed 4 x 10 x 4 box on it centred at the origin when `box`. */
static pvs_scene *wk_floor(int box) {
    static float pos[3 * 12];
    static uint32_t idx[3 * 14];
    const float lo[3] = {-2, 0, -2}, hi[3] = {2, 10, 2};
    pvs_object_desc obs[2];
    uint32_t vc = 4, tc = 2;
    const float g[12] = {-20, 0, -20, 20, 0, -20, 20, 0, 20, -20, 0, 20};
    memcpy(pos, g, sizeof(g));
    idx[0] = 0; idx[1] = 1; idx[2] = 2; idx[3] = 0; idx[4] = 2; idx[5] = 3;
    memset(obs, 0, sizeof(obs));
    obs[0].triangle_count = 2;
    obs[1].first_triangle = 2;
    obs[1].triangle_count = 12;
    if (box) test_box_arrays(pos, &vc, idx, &tc, lo, hi);
    return test_scene_arrays(pos, vc, idx, tc, obs, box ? 2 : 1, 1);
}

/* Open floor merges (fewer cells for a larger max_merge, the same floor covered); a closed box whose edges fall on
   sample columns holds no cell; two view volumes sharing a face leave no sliver cell at it. */
static void wk_merge(void) {
    pvs_scene *flat = wk_floor(0), *boxed = wk_floor(1);
    pvs_walkable_desc wd;
    pvs_box cells[512], vols[2] = {{{-20, -1, -20}, {0, 5, 20}}, {{0, -1, -20}, {20, 5, 20}}};
    uint32_t n[4], i, m;
    CHECK(flat && boxed);
    if (!flat || !boxed) return;
    memset(&wd, 0, sizeof(wd));
    wd.cell_size = 4;
    for (m = 0; m < 4; ++m) {
        double area = 0;
        wd.max_merge = 1u << m;
        CHECK(pvs_walkable_cells(flat, &wd, cells, 512, n + m, NULL) == PVS_OK);
        for (i = 0; i < n[m] && i < 512; ++i)
            area += ((double)cells[i].max[0] - cells[i].min[0]) * ((double)cells[i].max[2] - cells[i].min[2]);
        CHECK(area >= 40.0 * 40.0); /* the floor, covered */
        if (m) CHECK(n[m] < n[m - 1]);
    }
    wd.max_merge = 0;
    CHECK(pvs_walkable_cells(boxed, &wd, cells, 512, n, NULL) == PVS_OK && n[0] < 512);
    for (i = 0; i < n[0] && i < 512; ++i) { /* no cell centred in the box (its roof is a floor: cells over it) */
        float cx = 0.5f * (cells[i].min[0] + cells[i].max[0]), cz = 0.5f * (cells[i].min[2] + cells[i].max[2]);
        CHECK(!(cx > -2 && cx < 2 && cz > -2 && cz < 2 && cells[i].min[1] < 10));
    }
    {   /* a walk from the ground never reaches the box's roof; one from the roof drops to the ground */
        float ground[3] = {10, 0, 10}, roof[3] = {0, 10, 0};
        uint32_t up = 0, down = 0;
        wd.seed = ground;
        CHECK(pvs_walkable_cells(boxed, &wd, cells, 512, n, NULL) == PVS_OK && n[0] > 0 && n[0] < 512);
        for (i = 0; i < n[0] && i < 512; ++i) up += cells[i].min[1] > 5;
        CHECK(up == 0);
        wd.seed = roof;
        CHECK(pvs_walkable_cells(boxed, &wd, cells, 512, n, NULL) == PVS_OK && n[0] < 512);
        for (i = 0, up = 0; i < n[0] && i < 512; ++i) {
            up += cells[i].min[1] > 5;
            down += cells[i].max[1] < 5;
        }
        CHECK(up > 0 && down > 0);
        wd.seed = NULL;
    }
    wd.volumes = vols;
    wd.volume_count = 2;
    CHECK(pvs_walkable_cells(flat, &wd, cells, 512, n, NULL) == PVS_OK && n[0] < 512);
    for (i = 0; i < n[0] && i < 512; ++i) CHECK(cells[i].max[0] - cells[i].min[0] >= 1.0f); /* a sample spacing */
    pvs_scene_destroy(flat);
    pvs_scene_destroy(boxed);
}

void test_walkable(void) {
    wk_merge();
    wk_check("building", GEN_BUILDING, 0.3f, 3.0f, 0, 1);
    wk_check("city", GEN_CITY, 0.3f, 24.0f, 1, 1);
    wk_params();
}
