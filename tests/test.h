/* test.h - what the tests and the benches share, one copy each: the CHECK macro; the random
   generators; file bytes, whole files and (with _POSIX_C_SOURCE) commands run through the shell; a
   CPU clock; an allocator that counts its peak; boxes, arrays and meshes as a pvs_scene, generated
   scenes and bake descriptions; a camera's frame; and the ray-sampling check of a PVS.

   It includes pvs.h: a file that builds its own copy of the implementation (PVS_STATIC,
   PVS_IMPLEMENTATION, PVS_MALLOC, ...) includes pvs.h first, so that the helpers below call that
   copy. The helpers are static inline: a file compiles those it calls, against the pvs.h it sees;
   they CHECK nothing (the benches link no test runner), they return what the caller CHECKs. */
#ifndef TEST_H
#define TEST_H
#undef NDEBUG
/* the library's test-only desc flags (pvs.h: PVS__VISIBILITY_*) */
#define PVS_VISIBILITY_INPUT_ORDER 1u    /* pvs_visibility_2d: occluders in input order, not front to back */
#define PVS_VISIBILITY_25D_FULL_TESTS 1u /* pvs_visibility_25d: box tests walk the tree without witnesses */
#include "../pvs.h"
#include "../tools/gen.h"
#include "../tools/mesh.h"
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

extern int test_failures, test_checks;
/* make test runs some long checks smaller (about 3 minutes on 2 cores); make verify sets PVSTEST_FULL=1 and runs
   them at full size: such a check sizes its cells, scenes or seeds as TEST_FULL ? full : smaller */
#define TEST_FULL (getenv("PVSTEST_FULL") != NULL && atoi(getenv("PVSTEST_FULL")) > 0)
#define CHECK(c) do { ++test_checks; if (!(c)) { ++test_failures; fprintf(stderr, "%s:%d: CHECK failed: %s\n", __FILE__, __LINE__, #c); } } while (0)

/* ---- random numbers ---- */

/* splitmix64 (Steele, Lea and Flood 2014), the generator of the tests' random scenes, rays and
   cameras. Each file keeps its own state and seed, so a file's stream does not depend on what the
   others draw. */
static inline uint64_t test_splitmix64(uint64_t *state) {
    uint64_t z = (*state += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
}
/* Uniform in [0, 1), 53 bits. */
static inline double test_rnd(uint64_t *state) { return (double)(test_splitmix64(state) >> 11) * (1.0 / 9007199254740992.0); }
/* Uniform in [lo, hi). */
static inline float test_rndf(uint64_t *state, float lo, float hi) { return lo + (hi - lo) * (float)test_rnd(state); }
/* Knuth's MMIX linear congruential generator, its top 31 bits: the stream of the file-format tables
   (test_format.c's expected sizes and bench_file.c's figures were measured on it). */
static inline uint32_t test_lcg31(uint64_t *state) {
    *state = *state * 6364136223846793005ull + 1442695040888963407ull;
    return (uint32_t)(*state >> 33);
}

/* ---- bytes ---- */

/* The file format's little-endian 32-bit words. */
static inline uint32_t test_rd32(const uint8_t *p) { return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24; }
static inline void test_wr32(uint8_t *p, uint32_t v) {
    p[0] = (uint8_t)v; p[1] = (uint8_t)(v >> 8); p[2] = (uint8_t)(v >> 16); p[3] = (uint8_t)(v >> 24);
}

/* A whole file in a malloc'd buffer with a NUL after its bytes (*size, when size is not NULL, gets
   their count); NULL when it cannot be read. */
static inline char *test_slurp(const char *path, size_t *size) {
    FILE *f = fopen(path, "rb");
    char *buf = NULL;
    long n;
    if (!f) return NULL;
    if (fseek(f, 0, SEEK_END) == 0 && (n = ftell(f)) >= 0 && fseek(f, 0, SEEK_SET) == 0 && (buf = (char *)malloc((size_t)n + 1))) {
        n = (long)fread(buf, 1, (size_t)n, f);
        buf[n] = 0;
        if (size) *size = (size_t)n;
    }
    fclose(f);
    return buf;
}
/* 1 when both files can be read and hold the same bytes. */
static inline int test_same_files(const char *path_a, const char *path_b) {
    size_t na = 0, nb = 0;
    char *a = test_slurp(path_a, &na), *b = test_slurp(path_b, &nb);
    int same = a && b && na == nb && memcmp(a, b, na) == 0;
    free(a);
    free(b);
    return same;
}

#ifdef _POSIX_C_SOURCE
/* ---- commands (the files that define _POSIX_C_SOURCE: the tools and examples as processes) ---- */
#include <sys/stat.h>
#include <sys/wait.h>

/* Runs a shell command with stdout and stderr captured in DIR/out.txt; returns its exit status (-1
   when it did not exit), *out its output (malloc'd, never NULL). */
static inline int test_run(const char *dir, const char *cmd, char **out) {
    char full[4096], path[512];
    int status;
    snprintf(path, sizeof(path), "%s/out.txt", dir);
    snprintf(full, sizeof(full), "%s >%s 2>&1", cmd, path);
    status = system(full);
    *out = test_slurp(path, NULL);
    if (!*out) *out = (char *)calloc(1, 1);
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}
static inline int test_exists(const char *path) {
    struct stat st;
    return stat(path, &st) == 0;
}
#endif

/* tests/fuzz_target.c (linked into pvstest): rewrites every checksum of a file, with a reference CRC
   independent of the header's, so that a corruption reaches the checks behind them; and what the
   fuzzer does with one input. */
void pvs_fuzz_fix_checksums(uint8_t *f, size_t size);
int pvs_fuzz_one(const uint8_t *data, size_t size);

/* ---- the benches' clock ---- */

/* CPU seconds of this process (clock()): steadier than the wall clock on a shared machine; the benches
   that time one thread use it. */
static inline double test_cpu_seconds(void) { return (double)clock() / CLOCKS_PER_SEC; }

/* ---- an allocator that counts ---- */

/* The bytes a pvs_allocator holds now and at most (the bounded-memory tests and bench_bounded). */
typedef struct test_peak {
    size_t now, peak;
} test_peak;
static inline void *test_peak_alloc(size_t size, size_t align, void *user) {
    test_peak *p = (test_peak *)user;
    (void)align;
    p->now += size;
    if (p->now > p->peak) p->peak = p->now;
    return malloc(size ? size : 1);
}
static inline void test_peak_free(void *ptr, size_t size, void *user) {
    test_peak *p = (test_peak *)user;
    if (!ptr) return;
    p->now -= size;
    free(ptr);
}
/* Zeroes *p and returns an allocator counting into it. */
static inline pvs_allocator test_peak_allocator(test_peak *p) {
    pvs_allocator a;
    memset(p, 0, sizeof(*p));
    memset(&a, 0, sizeof(a));
    a.alloc = test_peak_alloc;
    a.free = test_peak_free;
    a.user = p;
    return a;
}

/* ---- ray casting ---- */

/* Moller-Trumbore in double: ray o + t d against triangle a, b, c (float corners, subtracted in double). 0 when
   |det| < min_det (ray parallel to the plane); else 1 and uvt = (u, v, t): inside when u, v >= 0 and u + v <= 1. The
   tests' brute-force references share it and keep their own acceptance rules. */
static inline int test_ray_triangle(const double o[3], const double d[3], const float *a, const float *b,
                                    const float *c, double min_det, double uvt[3]) {
    double e1[3], e2[3], p[3], q[3], s[3], det;
    int k;
    for (k = 0; k < 3; ++k) { e1[k] = (double)b[k] - a[k]; e2[k] = (double)c[k] - a[k]; s[k] = o[k] - a[k]; }
    p[0] = d[1] * e2[2] - d[2] * e2[1]; p[1] = d[2] * e2[0] - d[0] * e2[2]; p[2] = d[0] * e2[1] - d[1] * e2[0];
    det = e1[0] * p[0] + e1[1] * p[1] + e1[2] * p[2];
    if (fabs(det) < min_det) return 0;
    q[0] = s[1] * e1[2] - s[2] * e1[1]; q[1] = s[2] * e1[0] - s[0] * e1[2]; q[2] = s[0] * e1[1] - s[1] * e1[0];
    uvt[0] = (s[0] * p[0] + s[1] * p[1] + s[2] * p[2]) / det;
    uvt[1] = (d[0] * q[0] + d[1] * q[1] + d[2] * q[2]) / det;
    uvt[2] = (e2[0] * q[0] + e2[1] * q[1] + e2[2] * q[2]) / det;
    return 1;
}

/* ---- scenes ---- */

/* A closed box as 12 triangles over its 8 corners, corner c at the box's max along axis k when bit k
   of c is set, at its min otherwise (the boxes of the tests' and benches' scenes). */
static const uint32_t test_box_tris[12][3] = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4},
                                              {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
/* Appends the box [lo, hi] to caller arrays: 8 vertices at pos + 3 * *vc, 12 triangles at
   idx + 3 * *tc; *vc and *tc grow by 8 and 12. */
static inline void test_box_arrays(float *pos, uint32_t *vc, uint32_t *idx, uint32_t *tc, const float lo[3], const float hi[3]) {
    uint32_t base = *vc, i;
    for (i = 0; i < 8; ++i, ++*vc) {
        pos[3 * *vc] = i & 1 ? hi[0] : lo[0];
        pos[3 * *vc + 1] = i & 2 ? hi[1] : lo[1];
        pos[3 * *vc + 2] = i & 4 ? hi[2] : lo[2];
    }
    for (i = 0; i < 12; ++i, ++*tc) {
        idx[3 * *tc] = base + test_box_tris[i][0];
        idx[3 * *tc + 1] = base + test_box_tris[i][1];
        idx[3 * *tc + 2] = base + test_box_tris[i][2];
    }
}
/* Appends the box [lo, hi] to the mesh's last object. */
static inline void test_mesh_box(mesh *m, const float lo[3], const float hi[3]) {
    uint32_t base = m->vertex_count, i;
    for (i = 0; i < 8; ++i) mesh_add_vertex(m, i & 1 ? hi[0] : lo[0], i & 2 ? hi[1] : lo[1], i & 4 ? hi[2] : lo[2]);
    for (i = 0; i < 12; ++i) mesh_add_triangle(m, base + test_box_tris[i][0], base + test_box_tris[i][1], base + test_box_tris[i][2]);
}

/* A scene from caller arrays (up_axis 0 or 1: Y, 2: Z); NULL, with the message on stderr, when
   pvs_scene_create refuses it. */
static inline pvs_scene *test_scene_arrays(const float *positions, uint32_t vertex_count, const uint32_t *indices, uint32_t triangle_count,
                                           const pvs_object_desc *objects, uint32_t object_count, uint32_t up_axis) {
    pvs_scene_desc d;
    pvs_scene *s = NULL;
    pvs_error e;
    memset(&d, 0, sizeof(d));
    d.positions = positions;
    d.vertex_count = vertex_count;
    d.indices = indices;
    d.triangle_count = triangle_count;
    d.objects = objects;
    d.object_count = object_count;
    d.up_axis = up_axis;
    if (pvs_scene_create(&d, &s, &e) != PVS_OK) fprintf(stderr, "scene: %s\n", e.message);
    return s;
}

/* A mesh's objects as a scene (MESH_OBJECT_OCCLUDER objects occluder-only, as the tools load them;
   the generators make none); NULL as above. */
static inline pvs_scene *test_scene(const mesh *m, uint32_t up_axis) {
    pvs_object_desc *obs = (pvs_object_desc *)malloc((m->object_count ? m->object_count : 1) * sizeof(pvs_object_desc));
    pvs_scene *s;
    uint32_t i;
    if (!obs) return NULL;
    for (i = 0; i < m->object_count; ++i) {
        obs[i].first_triangle = m->objects[i].first_triangle;
        obs[i].triangle_count = m->objects[i].triangle_count;
        obs[i].flags = ((m->objects[i].flags & MESH_OBJECT_OCCLUDER) ? PVS_OBJECT_OCCLUDER_ONLY : 0u) |
                       ((m->objects[i].flags & MESH_OBJECT_SEE_THROUGH) ? PVS_OBJECT_SEE_THROUGH : 0u);
    }
    s = test_scene_arrays(m->positions, m->vertex_count, m->indices, m->triangle_count, obs, m->object_count, up_axis);
    free(obs);
    return s;
}

/* The parameters of a generated scene (gen.h), the other fields zero. */
static inline gen_params test_gen_params(gen_kind kind, uint64_t seed, float size, uint32_t max_cells) {
    gen_params p;
    memset(&p, 0, sizeof(p));
    p.kind = kind;
    p.seed = seed;
    p.size = size;
    p.max_cells = max_cells;
    return p;
}
/* Initialises m and cells and generates the scene into them (info may be NULL): gen_scene_ex's result. */
static inline int test_generate(const gen_params *p, mesh *m, mesh_cells *cells, gen_info *info) {
    mesh_init(m);
    mesh_cells_init(cells);
    return gen_scene_ex(p, m, cells, info);
}

/* A bake of `count` cells of the scene by `method` (PVS_METHOD_AUTO: the automatic choice); the other
   fields zero, the defaults, for the caller to set. */
static inline void test_bake_desc(pvs_bake_desc *bd, const pvs_scene *s, const pvs_box *cells, uint32_t count, pvs_method method) {
    memset(bd, 0, sizeof(*bd));
    bd->scene = s;
    bd->cells = cells;
    bd->cell_count = count;
    bd->method = method;
}

/* ---- cameras ---- */

/* A camera's frame (pvs_camera's conventions): unit forward f, up u (the camera's up made orthogonal
   to f) and right r = f x u, and the screen's half-extents: at distance 1 for a perspective camera
   (sy = tan(fov_y / 2)), in units for an orthographic one (fov_y 0: sy = ortho_height / 2); sx = sy *
   aspect. The reference rays of the per-frame culling tests go through the screen in this frame. */
static inline void test_camera_frame(const pvs_camera *cam, float aspect, double f[3], double u[3], double r[3], double *sx, double *sy) {
    double len, fu;
    int k;
    for (k = 0; k < 3; ++k) { f[k] = cam->forward[k]; u[k] = cam->up[k]; }
    len = sqrt(f[0] * f[0] + f[1] * f[1] + f[2] * f[2]);
    for (k = 0; k < 3; ++k) f[k] /= len;
    fu = f[0] * u[0] + f[1] * u[1] + f[2] * u[2];
    for (k = 0; k < 3; ++k) u[k] -= fu * f[k];
    len = sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]);
    for (k = 0; k < 3; ++k) u[k] /= len;
    r[0] = f[1] * u[2] - f[2] * u[1]; r[1] = f[2] * u[0] - f[0] * u[2]; r[2] = f[0] * u[1] - f[1] * u[0];
    *sy = cam->fov_y > 0 ? tan(0.5 * cam->fov_y) : 0.5 * cam->ortho_height;
    *sx = *sy * aspect;
}

/* ---- the ray-sampling check ---- */

/* What ray sampling sees from `cell`, a lower bound of its exact visible set: clears `seen`
   (PVS_BITSET_WORDS of the scene's objects), then sets the objects hit by `points` x `rays` uniform
   rays (seed) and, unless aim is 0, by up to `aim` rays aimed at each object not yet seen (aim_seed). */
static inline void test_sample(const pvs_scene *s, const pvs_box *cell, uint32_t points, uint32_t rays, uint64_t seed, uint32_t aim,
                               uint64_t aim_seed, pvs_word *seen) {
    memset(seen, 0, PVS_BITSET_WORDS(pvs_scene_object_count(s)) * sizeof(pvs_word));
    pvs_sample_visibility(s, cell, points, rays, seed, seen);
    if (aim) pvs_sample_visibility_toward(s, cell, NULL, aim, aim_seed, seen);
}
/* The misses of a PVS: objects of [0, n) set in `seen` and not in `pvs`. With a label, each is
   printed as "LABEL: cell C misses object O" (a conservative PVS has none, so this is the failure's
   detail). */
static inline uint32_t test_misses(const pvs_word *seen, const pvs_word *pvs, uint32_t n, const char *label, uint32_t cell) {
    uint32_t o, misses = 0;
    for (o = pvs_bitset_next(seen, n, 0); o < n; o = pvs_bitset_next(seen, n, o + 1))
        if (!pvs_bitset_test(pvs, o)) {
            if (label) fprintf(stderr, "%s: cell %u misses object %u\n", label, cell, o);
            ++misses;
        }
    return misses;
}

#endif
