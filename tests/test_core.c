/* test_core.c - result strings, errors, allocator hooks, bitsets, scene validation */
#include "test.h"
#include "../pvs.h"
#include <math.h>
#include <stdlib.h>
#include <string.h>

/* An allocator that counts calls and bytes, checks sizes on free and can fail on demand. */
typedef struct counting_allocator {
    long allocs, frees;
    size_t live;
    long fail_after; /* -1: never */
} counting_allocator;

static void *count_alloc(size_t size, size_t align, void *user) {
    counting_allocator *c = (counting_allocator *)user;
    void *p;
    if (c->fail_after >= 0 && c->allocs >= c->fail_after) return NULL;
    if (align > 16) return NULL; /* pvs.h asks for at most 16 here; malloc gives 16 on the test platforms */
    p = malloc(size);
    if (p) {
        c->allocs++;
        c->live += size;
    }
    return p;
}
static void count_free(void *p, size_t size, void *user) {
    counting_allocator *c = (counting_allocator *)user;
    c->frees++;
    c->live -= size;
    free(p);
}

static void test_results(void) {
    int r;
    for (r = 0; r > PVS_RESULT_MIN; --r) {
        const char *s = pvs_result_string((pvs_result)r);
        CHECK(s && strcmp(s, "unknown result") != 0);
    }
    CHECK(strcmp(pvs_result_string(PVS_RESULT_MIN), "unknown result") == 0);
    CHECK(pvs_version() == PVS_VERSION);
}

static void test_bitsets(void) {
    pvs_word bits[PVS_BITSET_WORDS(300)];
    unsigned char ref[300];
    uint64_t state = 7;
    int round;
    for (round = 0; round < 200; ++round) {
        uint32_t n = 1 + (uint32_t)(rand() % 300), i, count = 0, next;
        memset(bits, 0, sizeof(bits));
        memset(ref, 0, sizeof(ref));
        for (i = 0; i < n; ++i) {
            state = state * 6364136223846793005ull + 1442695040888963407ull;
            if ((state >> 33) % (1 + round % 5) == 0) {
                pvs_bitset_set(bits, i);
                ref[i] = 1;
            }
        }
        if (n > 3) {
            pvs_bitset_clear(bits, 3);
            ref[3] = 0;
        }
        for (i = 0; i < n; ++i) {
            CHECK(pvs_bitset_test(bits, i) == ref[i]);
            count += ref[i];
        }
        CHECK(pvs_bitset_count(bits, n) == count);
        /* iteration visits exactly the set bits, ascending */
        next = pvs_bitset_next(bits, n, 0);
        for (i = 0; i < n; ++i)
            if (ref[i]) {
                CHECK(next == i);
                next = pvs_bitset_next(bits, n, i + 1);
            }
        CHECK(next == n);
    }
    /* bits past bit_count are ignored */
    memset(bits, 0xff, sizeof(bits));
    CHECK(pvs_bitset_count(bits, 70) == 70);
    CHECK(pvs_bitset_next(bits, 70, 70) == 70);
}

/* A unit cube as one object: 8 vertices, 12 triangles. */
static const float cube_v[] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 0, 0, 1, 1, 0, 1, 1, 1, 1, 0, 1, 1};
static const uint32_t cube_i[] = {0, 2, 1, 0, 3, 2, 4, 5, 6, 4, 6, 7, 0, 1, 5, 0, 5, 4,
                                  2, 3, 7, 2, 7, 6, 1, 2, 6, 1, 6, 5, 0, 4, 7, 0, 7, 3};

static pvs_result make(pvs_scene_desc *d, pvs_error *e) {
    pvs_scene *s = NULL;
    pvs_result r = pvs_scene_create(d, &s, e);
    CHECK((r == PVS_OK) == (s != NULL));
    CHECK(e->result == r);
    pvs_scene_destroy(s);
    return r;
}

static void test_scene_validation(void) {
    float v[24];
    uint32_t idx[36];
    pvs_object_desc ob[2];
    pvs_scene_desc d;
    pvs_error e;
    pvs_occluder_desc oc;
    float planes[7 * 4];
    float fp[10];
    counting_allocator ca;
    int k;

    memcpy(v, cube_v, sizeof(v));
    memcpy(idx, cube_i, sizeof(idx));
    memset(&d, 0, sizeof(d));
    d.positions = v;
    d.vertex_count = 8;
    d.indices = idx;
    d.triangle_count = 12;
    ob[0].first_triangle = 0; ob[0].triangle_count = 6; ob[0].flags = 0;
    ob[1].first_triangle = 6; ob[1].triangle_count = 6; ob[1].flags = PVS_OBJECT_OCCLUDER_ONLY;
    d.objects = ob;
    d.object_count = 2;
    CHECK(make(&d, &e) == PVS_OK);
    {
        pvs_scene *s;
        CHECK(pvs_scene_create(&d, &s, NULL) == PVS_OK);
        CHECK(pvs_scene_object_count(s) == 2);
        CHECK(pvs_scene_triangle_count(s) == 12);
        CHECK(pvs_scene_up_axis(s) == 1);
        CHECK(pvs_scene_object_flags(s, 1) == PVS_OBJECT_OCCLUDER_ONLY);
        CHECK(pvs_scene_triangle_object(s, 7) == 1);
        CHECK(pvs_scene_bounds(s).max[2] == 1.0f);
        pvs_scene_destroy(s);
    }
    pvs_scene_destroy(NULL);

    /* NULL arguments */
    CHECK(pvs_scene_create(NULL, NULL, &e) == PVS_ERROR_INVALID_ARGUMENT);
    d.object_count = 0;
    CHECK(make(&d, &e) == PVS_ERROR_INVALID_ARGUMENT);
    d.object_count = 2;
    d.up_axis = 3;
    CHECK(make(&d, &e) == PVS_ERROR_INVALID_ARGUMENT);
    d.up_axis = 2;
    CHECK(make(&d, &e) == PVS_OK);
    d.up_axis = 0;

    /* NaN and infinity in a vertex */
    v[3 * 5 + 1] = NAN;
    CHECK(make(&d, &e) == PVS_ERROR_NOT_FINITE && e.index == 5 && strstr(e.message, "vertex 5"));
    v[3 * 5 + 1] = INFINITY;
    CHECK(make(&d, &e) == PVS_ERROR_NOT_FINITE);
    v[3 * 5 + 1] = cube_v[3 * 5 + 1];

    /* vertex index out of range */
    idx[3 * 4 + 2] = 8;
    CHECK(make(&d, &e) == PVS_ERROR_INDEX_OUT_OF_RANGE && e.index == 4 && strstr(e.message, "triangle 4"));
    idx[3 * 4 + 2] = cube_i[3 * 4 + 2];

    /* object range past the triangles, overlapping, empty, degenerate */
    ob[1].triangle_count = 7;
    CHECK(make(&d, &e) == PVS_ERROR_INDEX_OUT_OF_RANGE && e.index == 1);
    ob[1].first_triangle = 5; ob[1].triangle_count = 6;
    CHECK(make(&d, &e) == PVS_ERROR_OVERLAPPING_OBJECTS && strstr(e.message, "triangle 5"));
    ob[1].first_triangle = 6; ob[1].triangle_count = 0;
    CHECK(make(&d, &e) == PVS_ERROR_EMPTY_OBJECT && e.index == 1);
    d.flags = PVS_SCENE_ALLOW_EMPTY_OBJECTS;
    CHECK(make(&d, &e) == PVS_OK);
    d.flags = 0;
    ob[1].triangle_count = 6;
    for (k = 0; k < 6; ++k) idx[3 * (6 + k) + 1] = idx[3 * (6 + k)]; /* collapse object 1 */
    CHECK(make(&d, &e) == PVS_ERROR_DEGENERATE_OBJECT && e.index == 1);
    memcpy(idx, cube_i, sizeof(idx));
    /* a degenerate triangle inside a good object is fine */
    idx[1] = idx[0];
    CHECK(make(&d, &e) == PVS_OK);
    memcpy(idx, cube_i, sizeof(idx));

    /* count overflow */
    d.triangle_count = 0xffffffffu;
    CHECK(make(&d, &e) == PVS_ERROR_COUNT_OVERFLOW);
    d.triangle_count = 12;

    /* explicit occluders */
    memset(&oc, 0, sizeof(oc));
    d.occluders = &oc;
    d.occluder_count = 1;
    CHECK(make(&d, &e) == PVS_ERROR_BAD_OCCLUDER); /* kind 0 */
    oc.kind = PVS_OCCLUDER_BOX;
    oc.box.min[0] = oc.box.min[1] = oc.box.min[2] = 2;
    oc.box.max[0] = oc.box.max[1] = oc.box.max[2] = 3;
    CHECK(make(&d, &e) == PVS_OK);
    oc.box.max[1] = 2;
    CHECK(make(&d, &e) == PVS_ERROR_BAD_OCCLUDER);
    oc.box.max[1] = NAN;
    CHECK(make(&d, &e) == PVS_ERROR_NOT_FINITE);
    /* convex: the unit cube as 6 planes, plus a redundant 7th */
    oc.kind = PVS_OCCLUDER_CONVEX;
    {
        static const float cube_planes[7 * 4] = {1, 0, 0, -1, -1, 0, 0, 0, 0, 1, 0, -1, 0, -1, 0, 0,
                                                 0, 0, 1, -1, 0, 0, -1, 0, 1, 1, 1, -10};
        memcpy(planes, cube_planes, sizeof(planes));
    }
    oc.planes = planes;
    oc.plane_count = 7;
    {
        pvs_scene *s;
        CHECK(pvs_scene_create(&d, &s, &e) == PVS_OK);
        if (s) {
            pvs_box b = pvs_scene_bounds(s);
            CHECK(fabsf(b.max[0] - 1.0f) < 1e-5f && fabsf(b.min[0]) < 1e-5f);
            CHECK(pvs_scene_occluder(s, 0)->plane_count == 7 && pvs_scene_occluder(s, 0)->planes != planes);
            CHECK(pvs_scene_occluder_count(s) == 1 && pvs_scene_object_count(s) == d.object_count);
            pvs_scene_destroy(s);
        }
    }
    oc.plane_count = 5; /* drop -z and the 7th: unbounded */
    CHECK(make(&d, &e) == PVS_ERROR_BAD_OCCLUDER && strstr(e.message, "unbounded"));
    oc.plane_count = 7;
    planes[4 * 6 + 3] = 10; /* x + y + z <= -10: empty */
    CHECK(make(&d, &e) == PVS_ERROR_BAD_OCCLUDER && strstr(e.message, "empty"));
    planes[4 * 6 + 3] = -10;
    planes[0] = planes[1] = planes[2] = 0;
    CHECK(make(&d, &e) == PVS_ERROR_BAD_OCCLUDER && strstr(e.message, "zero normal"));
    planes[0] = 1;
    planes[5] = NAN;
    CHECK(make(&d, &e) == PVS_ERROR_NOT_FINITE);
    planes[5] = 0;
    oc.plane_count = 3;
    CHECK(make(&d, &e) == PVS_ERROR_BAD_OCCLUDER);
    /* extrusion: an L shape, then a bow tie */
    oc.kind = PVS_OCCLUDER_EXTRUSION;
    {
        static const float l_shape[10] = {0, 0, 2, 0, 2, 1, 1, 1, 1, 2};
        memcpy(fp, l_shape, sizeof(fp));
    }
    oc.footprint = fp;
    oc.footprint_count = 5;
    oc.base = 0;
    oc.top = 4;
    CHECK(make(&d, &e) == PVS_OK);
    oc.top = 0;
    CHECK(make(&d, &e) == PVS_ERROR_BAD_OCCLUDER);
    oc.top = 4;
    fp[2] = 0; fp[3] = 2; fp[8] = 2; fp[9] = 0; /* edges cross */
    oc.footprint_count = 4;
    {
        static const float bow[8] = {0, 0, 3, 2, 3, 0, 0, 1};
        memcpy(fp, bow, sizeof(bow));
    }
    CHECK(make(&d, &e) == PVS_ERROR_BAD_OCCLUDER && strstr(e.message, "cross"));
    fp[2] = 0; fp[3] = 0;
    CHECK(make(&d, &e) == PVS_ERROR_BAD_OCCLUDER && strstr(e.message, "coincide"));
    oc.footprint_count = 2;
    CHECK(make(&d, &e) == PVS_ERROR_BAD_OCCLUDER);
    d.occluders = NULL;
    d.occluder_count = 0;
    {
        pvs_scene *s = NULL;
        CHECK(pvs_scene_create(&d, &s, &e) == PVS_OK && pvs_scene_occluder_count(s) == 0);
        pvs_scene_destroy(s);
    }
    {   /* the fingerprint: the same scene gives the same, never 0; a corner moved by one float step, another object
           split, another flag or an explicit occluder each give another */
        pvs_scene *s = NULL;
        uint64_t f[6];
        int a, b;
        for (k = 0; k < 6; ++k) {
            float keep = v[5];
            if (k == 2) v[5] = nextafterf(v[5], 2.0f);
            if (k == 3) { ob[0].triangle_count = 4; ob[1].first_triangle = 4; ob[1].triangle_count = 8; }
            if (k == 4) ob[1].flags = 0;
            if (k == 5) {
                memset(&oc, 0, sizeof(oc));
                oc.kind = PVS_OCCLUDER_BOX;
                oc.box.min[0] = oc.box.min[1] = oc.box.min[2] = 2;
                oc.box.max[0] = oc.box.max[1] = oc.box.max[2] = 3;
                d.occluders = &oc;
                d.occluder_count = 1;
            }
            f[k] = 0;
            if (pvs_scene_create(&d, &s, &e) == PVS_OK) f[k] = pvs_scene_fingerprint(s);
            CHECK(f[k] != 0);
            pvs_scene_destroy(s);
            s = NULL;
            v[5] = keep;
            ob[0].triangle_count = 6; ob[1].first_triangle = 6; ob[1].triangle_count = 6;
            ob[1].flags = PVS_OBJECT_OCCLUDER_ONLY;
            d.occluders = NULL; d.occluder_count = 0;
        }
        CHECK(f[0] == f[1]);
        for (a = 1; a < 6; ++a)
            for (b = a + 1; b < 6; ++b) CHECK(f[a] != f[b]);
    }

    /* every allocation goes through the hooks and is freed; each failure point is handled */
    memset(&ca, 0, sizeof(ca));
    ca.fail_after = -1;
    d.allocator.alloc = count_alloc;
    d.allocator.free = count_free;
    d.allocator.user = &ca;
    CHECK(make(&d, &e) == PVS_OK);
    CHECK(ca.allocs > 0 && ca.allocs == ca.frees && ca.live == 0);
    {
        long total = ca.allocs, f;
        for (f = 0; f < total; ++f) {
            memset(&ca, 0, sizeof(ca));
            ca.fail_after = f;
            CHECK(make(&d, &e) == PVS_ERROR_OUT_OF_MEMORY);
            CHECK(ca.allocs == ca.frees && ca.live == 0);
        }
    }
}

void test_core(void) {
    test_results();
    test_bitsets();
    test_scene_validation();
}
