/* test_raster.c - the >>raster module against brute force: conservative coverage and depth with
   16 x 16 sub-samples per pixel (plus the pixel's edges) and exact depth in double, SIMD against
   scalar, the depth pyramid against a scan, culling against ray casting from the camera, the cull
   map against segment tests, no allocation per frame. raster_verify(scale) runs the same with more
   cases (tests/verify_raster.c). */
#include "../pvs.h"
#include "../tools/gen.h"
#include "../tools/mesh.h"
#include "test.h"
#include <float.h>
#include <math.h>
#include <pthread.h>
#include <stdlib.h>
#include <string.h>

/* The SIMD and scalar paths give the same bits where both evaluate floats as floats. Where the scalar path is
   evaluated wider (FLT_EVAL_METHOD != 0 beside SSE2: make test-x87's -msse2 run) they differ in the last bits; each
   stays conservative (this file's exact references and ray checks hold), so checks of their sameness are left out. */
#if defined(FLT_EVAL_METHOD) && FLT_EVAL_METHOD != 0 && !defined(PVS_NO_SIMD) && \
    (defined(__SSE2__) || defined(__ARM_NEON) || defined(__ARM_NEON__))
#define SAME_BITS 0
#else
#define SAME_BITS 1
#endif

static uint64_t rs_state = 0x51ab3c9dull;
static double rnd(void) { return test_rnd(&rs_state); }
static float rndf(float lo, float hi) { return test_rndf(&rs_state, lo, hi); }

/* The occluder representation the tests below use: PVS_RASTER_PER_PIXEL or PVS_RASTER_TILED (the
   maps here are small, which would pick per pixel). raster_verify runs them with both. */
static uint32_t mode_flag = PVS_RASTER_PER_PIXEL;

/* ---- brute-force coverage ---- */

/* Clip coordinates of a point under a row-major matrix, in double. */
static void clip_of(const float *m, const float *p, double c[4]) {
    int r;
    for (r = 0; r < 4; ++r) c[r] = (double)m[4 * r] * p[0] + (double)m[4 * r + 1] * p[1] + (double)m[4 * r + 2] * p[2] + m[4 * r + 3];
}

/* Barycentric point-in-triangle with a relative tolerance tol (tol > 0: points on or a hair outside an
   edge count; the union test must not see a crack on a shared edge from the solve's own rounding). A
   (nearly) degenerate projection covers no sample (its sliver is narrower than 1e-9 of its size). */
static int tri_at_tol(const double C[3][4], double x, double y, double tol, double *depth) {
    double a[3][3], det, l[3], n0, n1, n2;
    int i;
    for (i = 0; i < 3; ++i) {
        a[0][i] = C[i][0] - x * C[i][3];
        a[1][i] = C[i][1] - y * C[i][3];
        a[2][i] = C[i][3];
    }
    det = a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1]) - a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0]) +
          a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0]);
    n0 = fabs(a[0][0]) + fabs(a[0][1]) + fabs(a[0][2]);
    n1 = fabs(a[1][0]) + fabs(a[1][1]) + fabs(a[1][2]);
    n2 = fabs(a[2][0]) + fabs(a[2][1]) + fabs(a[2][2]);
    if (!(fabs(det) > 1e-9 * n0 * n1 * n2)) return 0;
    l[0] = (a[0][1] * a[1][2] - a[0][2] * a[1][1]) / det;
    l[1] = -(a[0][0] * a[1][2] - a[0][2] * a[1][0]) / det;
    l[2] = (a[0][0] * a[1][1] - a[0][1] * a[1][0]) / det;
    if (l[0] < -tol || l[1] < -tol || l[2] < -tol) return 0;
    *depth = l[0] * C[0][2] + l[1] * C[1][2] + l[2] * C[2][2];
    return *depth <= 1.0 + tol; /* in front of the near plane (z <= w = 1) */
}

/* Is screen point (x_ndc, y_ndc) on the triangle (visible part: w > 0, in front of the near plane)?
   Returns 1 and the exact depth z/w. */
static int tri_at(const double C[3][4], double x, double y, double *depth) { return tri_at_tol(C, x, y, 0.0, depth); }

/* A random test matrix: a camera (perspective or orthographic) or an off-axis perspective. */
static void random_matrix(float m[16], float aspect, int kind) {
    pvs_camera cam;
    memset(&cam, 0, sizeof(cam));
    cam.eye[0] = rndf(-1, 1); cam.eye[1] = rndf(-1, 1); cam.eye[2] = rndf(-1, 1);
    cam.forward[0] = rndf(-1, 1); cam.forward[1] = rndf(-1, 1); cam.forward[2] = rndf(-1, 1);
    if (fabsf(cam.forward[0]) + fabsf(cam.forward[1]) + fabsf(cam.forward[2]) < 0.1f) cam.forward[2] = 1;
    cam.up[1] = 1; cam.up[0] = rndf(-0.3f, 0.3f);
    cam.near_plane = rndf(0.05f, 0.5f);
    cam.fov_y = kind == 1 ? 0.0f : rndf(0.5f, 2.0f);
    cam.ortho_height = rndf(2, 10);
    cam.far_plane = 40.0f;
    CHECK(pvs_camera_matrix(&cam, aspect, m) == PVS_OK);
    if (kind == 2) { /* off-axis: shear x and y by multiples of w (a projection plane not centred) */
        int k;
        float sx = rndf(-1, 1), sy = rndf(-1, 1);
        for (k = 0; k < 4; ++k) { m[k] += sx * m[12 + k]; m[4 + k] += sy * m[12 + k]; }
    }
}

/* A random triangle of one of several kinds around the origin. */
static void random_triangle(float p[9], int kind) {
    int k;
    float s = kind == 2 ? rndf(100, 1e5f) : rndf(0.5f, 8.0f);
    for (k = 0; k < 9; ++k) p[k] = rndf(-s, s);
    switch (kind) {
    case 1: /* sliver: third vertex near the segment between the first two */
        for (k = 0; k < 3; ++k) p[6 + k] = 0.5f * (p[k] + p[3 + k]) + rndf(-1e-3f, 1e-3f) * (rnd() < 0.5 ? 1.0f : 1e-4f);
        break;
    case 3: /* degenerate: collinear or a point */
        for (k = 0; k < 3; ++k) p[6 + k] = rnd() < 0.5 ? p[k] : 2.0f * p[3 + k] - p[k];
        if (rnd() < 0.3) for (k = 0; k < 3; ++k) p[3 + k] = p[k];
        break;
    case 4: /* tiny */
        for (k = 3; k < 9; ++k) p[k] = p[k % 3] + rndf(-0.05f, 0.05f);
        break;
    default: break;
    }
}

/* Rasterizes one triangle alone and checks every pixel against 17 x 17 samples (the 16 x 16 grid of
   sub-pixels and the pixel's edges). Returns the number of violations. */
static int check_triangle(pvs_raster *r, const float m[16], const float p[9], pvs_raster_mode mode) {
    uint32_t w, h, i, j, si, sj;
    const float *d;
    double C[3][4];
    int bad = 0;
    pvs_raster_clear(r);
    pvs_raster_set_matrix(r, m);
    pvs_raster_triangles(r, p, 3, NULL, 1, mode);
    d = pvs_raster_depth(r, &w, &h);
    for (i = 0; i < 3; ++i) clip_of(m, p + 3 * i, C[i]);
    for (j = 0; j < h; ++j)
        for (i = 0; i < w; ++i) {
            float stored = d[j * w + i];
            int inside = 0, outside = 0;
            double dmin = 1e300, dmax = -1e300;
            for (sj = 0; sj <= 16; ++sj)
                for (si = 0; si <= 16; ++si) {
                    double x = ((double)i + si / 16.0) / w * 2.0 - 1.0, y = ((double)j + sj / 16.0) / h * 2.0 - 1.0, z;
                    if (tri_at(C, x, y, &z)) {
                        ++inside;
                        if (z < dmin) dmin = z;
                        if (z > dmax) dmax = z;
                    } else {
                        ++outside;
                    }
                }
            if (mode == PVS_RASTER_OCCLUDER) {
                if (stored != PVS_DEPTH_EMPTY && (outside || (double)stored > dmin)) ++bad;
            } else {
                if (inside && (stored == PVS_DEPTH_EMPTY || (double)stored < dmax)) ++bad;
            }
        }
    return bad;
}

/* Adversarial cases on a pixel grid: an orthographic identity projection (pixel (i, j) spans x_ndc
   2 i / W - 1 .. 2 (i + 1) / W - 1), vertices on pixel corners, edges along pixel boundaries and
   through corners, depth planes with exact values; and perspective vertices on the eye plane (w = 0)
   or exactly on the near plane. Returns violations. */
static int adversarial(pvs_raster *r, uint32_t W, uint32_t H) {
    float m[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1}, p[9];
    int bad = 0, t, k;
    for (t = 0; t < 60; ++t) {
        for (k = 0; k < 3; ++k) {
            int gi = (int)(rnd() * (W + 3)) - 1, gj = (int)(rnd() * (H + 3)) - 1;
            float fx = t % 3 == 0 ? 0.5f * (float)(int)(rnd() * 3) : 0.0f; /* corners or half pixels */
            p[3 * k] = 2.0f * ((float)gi + fx) / (float)W - 1.0f;
            p[3 * k + 1] = 2.0f * ((float)gj + fx) / (float)H - 1.0f;
            p[3 * k + 2] = t % 2 ? 0.5f : rndf(-1, 1);
        }
        if (t % 5 == 4) { p[3] = p[0]; p[6] = p[0]; } /* a vertical edge pair */
        k = check_triangle(r, m, p, PVS_RASTER_OCCLUDER) + 100 * check_triangle(r, m, p, PVS_RASTER_OCCLUDEE);
        if (k) fprintf(stderr, "adversarial grid %d: %d (%.9g %.9g %.9g) (%.9g %.9g %.9g) (%.9g %.9g %.9g)\n", t, k, p[0], p[1], p[2], p[3], p[4], p[5], p[6], p[7], p[8]);
        bad += k;
    }
    for (t = 0; t < 60; ++t) {
        /* a camera at the origin looking along +z: w = z; vertices on w = 0 or on the near plane */
        pvs_camera cam;
        memset(&cam, 0, sizeof(cam));
        cam.forward[2] = 1; cam.up[1] = 1; cam.fov_y = 1.2f; cam.near_plane = 0.25f;
        CHECK(pvs_camera_matrix(&cam, (float)W / (float)H, m) == PVS_OK);
        for (k = 0; k < 9; ++k) p[k] = rndf(-3, 3);
        p[2] = t % 3 == 0 ? 0.0f : t % 3 == 1 ? 0.25f : -p[5]; /* on the eye plane, on the near plane, mirrored */
        if (t % 4 == 0) p[5] = 0.25f;
        k = check_triangle(r, m, p, PVS_RASTER_OCCLUDER) + 100 * check_triangle(r, m, p, PVS_RASTER_OCCLUDEE);
        if (k) fprintf(stderr, "adversarial eye %d: %d (%.9g %.9g %.9g) (%.9g %.9g %.9g) (%.9g %.9g %.9g)\n", t, k, p[0], p[1], p[2], p[3], p[4], p[5], p[6], p[7], p[8]);
        bad += k;
    }
    return bad;
}

static void test_coverage(int scale) {
    pvs_raster_desc rd;
    pvs_raster *r;
    pvs_error e;
    int t, bad = 0, claimed = 0, n = 300 * scale;
    memset(&rd, 0, sizeof(rd));
    rd.width = 13; rd.height = 9; rd.flags = mode_flag;
    CHECK(pvs_raster_create(&rd, &r, &e) == PVS_OK);
    for (t = 0; t < n; ++t) {
        float m[16], p[9];
        int kind = t % 5, mk = (t / 5) % 3, b1, b2;
        random_matrix(m, 13.0f / 9.0f, mk);
        random_triangle(p, kind);
        if (t % 7 == 0) { /* one vertex right at the eye plane or behind */
            int k;
            for (k = 0; k < 3; ++k) p[k] = rndf(-2, 2);
        }
        b1 = check_triangle(r, m, p, PVS_RASTER_OCCLUDER);
        {
            uint32_t i;
            const float *d = pvs_raster_depth(r, NULL, NULL);
            for (i = 0; i < 13 * 9; ++i) claimed += d[i] != PVS_DEPTH_EMPTY;
        }
        b2 = check_triangle(r, m, p, PVS_RASTER_OCCLUDEE);
        if (b1 || b2) {
            fprintf(stderr, "coverage: triangle %d kind %d matrix %d: %d occluder, %d occludee violations\n", t, kind, mk, b1, b2);
            bad += b1 + b2;
        }
    }
    for (t = 0; t < scale; ++t) bad += adversarial(r, 13, 9);
    CHECK(bad == 0);
    CHECK(claimed > n / 10); /* the occluder mode does claim pixels */
    pvs_raster_destroy(r);
}

/* ---- occluder meshes (pvs_raster_mesh): brute-force union coverage ---- */

#define MESH_MAXV 400
#define MESH_MAXT 640
typedef struct tmesh {
    float pos[3 * MESH_MAXV];
    uint32_t idx[3 * MESH_MAXT];
    uint32_t nv, nt;
    int planar_quad; /* the union is the quad of vertices 0..3 (for the "covers what the quad covers" check) */
} tmesh;

/* A point of the frame o + u a + v b (+ h n). */
static void frame_point(const float fr[12], float u, float v, float h, float *out) {
    int k;
    for (k = 0; k < 3; ++k) out[k] = fr[k] + u * fr[3 + k] + v * fr[6 + k] + h * fr[9 + k];
}

static void random_frame(float fr[12], float s) {
    int k;
    for (k = 0; k < 3; ++k) fr[k] = rndf(-2, 2);
    for (k = 3; k < 12; ++k) fr[k] = rndf(-s, s);
}

/* Random meshes: 0 grid (planar or bent, random diagonals), 1 fan (star-shaped, closed or open), 2 a
   quad split T-free into 2..64 triangles, 3 slivers (a strip of near-collinear points), 4 a grid with
   flipped triangles and a T-junction, 5 a closed box. Some as a triangle soup (welded by position). */
static void random_mesh(tmesh *m, int kind) {
    float fr[12], s = rnd() < 0.3 ? rndf(4, 12) : rndf(0.5f, 3);
    uint32_t i, j, nu, nv;
    int k;
    m->nv = m->nt = 0;
    m->planar_quad = 0;
    random_frame(fr, s);
    switch (kind) {
    case 0:
    case 2:
    case 4: {
        float bend = kind == 0 && rnd() < 0.5 ? rndf(-0.4f, 0.4f) : 0.0f;
        if (kind == 2) { /* 2 a b triangles, a b <= 32 */
            nu = 1 + (uint32_t)(rnd() * 8);
            nv = 1 + (uint32_t)(rnd() * (32 / nu));
        } else {
            nu = 2 + (uint32_t)(rnd() * 10);
            nv = 2 + (uint32_t)(rnd() * 10);
        }
        /* vertices 0..3 the corners (so the quad is vertices 0..3), then the rest row by row */
        for (j = 0; j <= nv; ++j)
            for (i = 0; i <= nu; ++i) {
                float u = (float)i / (float)nu, v = (float)j / (float)nv, h = 0.0f;
                if (kind == 2 && i > 0 && i < nu && j > 0 && j < nv) { /* interior vertices may move */
                    u += rndf(-0.3f, 0.3f) / (float)nu;
                    v += rndf(-0.3f, 0.3f) / (float)nv;
                }
                if (bend != 0.0f) h = bend * ((u - 0.5f) * (u - 0.5f) + rndf(-0.1f, 0.1f));
                frame_point(fr, u, v, h, m->pos + 3 * (j * (nu + 1) + i));
            }
        m->nv = (nu + 1) * (nv + 1);
        for (j = 0; j < nv; ++j)
            for (i = 0; i < nu; ++i) {
                uint32_t a = j * (nu + 1) + i, b = a + 1, c = a + nu + 1, d = c + 1, *t = m->idx + 3 * m->nt;
                if (rnd() < 0.5) {
                    t[0] = a; t[1] = b; t[2] = d; t[3] = a; t[4] = d; t[5] = c;
                } else {
                    t[0] = a; t[1] = b; t[2] = c; t[3] = b; t[4] = d; t[5] = c;
                }
                if (kind == 4 && rnd() < 0.1) { uint32_t x = t[1]; t[1] = t[2]; t[2] = x; } /* inconsistent winding */
                m->nt += 2;
            }
        if (kind == 4 && m->nv + 1 < MESH_MAXV) { /* a T-junction: split one triangle at its edge's midpoint */
            uint32_t *t = m->idx + 3 * (uint32_t)(rnd() * m->nt), mid = m->nv++;
            for (k = 0; k < 3; ++k) m->pos[3 * mid + k] = 0.5f * (m->pos[3 * t[0] + k] + m->pos[3 * t[1] + k]);
            m->idx[3 * m->nt] = mid; m->idx[3 * m->nt + 1] = t[1]; m->idx[3 * m->nt + 2] = t[2];
            t[1] = mid;
            ++m->nt;
        }
        m->planar_quad = kind == 2;
        break;
    }
    case 1: {
        uint32_t rim = 3 + (uint32_t)(rnd() * 20), closed = rnd() < 0.7;
        frame_point(fr, 0, 0, 0, m->pos);
        for (i = 0; i < rim; ++i) {
            float ang = 6.2831853f * ((float)i + rndf(-0.3f, 0.3f)) / (float)rim * (closed ? 1.0f : 0.8f), rad = rndf(0.3f, 1.0f);
            frame_point(fr, rad * cosf(ang), rad * sinf(ang), rndf(-0.2f, 0.2f) * (rnd() < 0.5), m->pos + 3 * (i + 1));
        }
        m->nv = rim + 1;
        for (i = 0; i < rim - (closed ? 0 : 1); ++i) {
            m->idx[3 * m->nt] = 0; m->idx[3 * m->nt + 1] = 1 + i; m->idx[3 * m->nt + 2] = 1 + (i + 1) % rim;
            ++m->nt;
        }
        break;
    }
    case 3: { /* a strip along a line: points almost on it, alternating sides by tiny offsets */
        uint32_t n = 4 + (uint32_t)(rnd() * 30);
        float off = rnd() < 0.5 ? 1e-4f : 1e-2f;
        for (i = 0; i < n; ++i) frame_point(fr, (float)(i / 2) / (float)(n / 2), (i & 1) ? off * rndf(0.5f, 1.5f) : 0.0f, 0.0f, m->pos + 3 * i);
        m->nv = n;
        for (i = 0; i + 2 < n; ++i) {
            uint32_t *t = m->idx + 3 * m->nt++;
            t[0] = i; t[1] = i & 1 ? i + 2 : i + 1; t[2] = i & 1 ? i + 1 : i + 2;
        }
        break;
    }
    default: { /* a closed box: front and back faces meet at silhouettes */
        static const uint32_t q[36] = {0, 1, 3, 0, 3, 2, 4, 6, 7, 4, 7, 5, 0, 4, 5, 0, 5, 1,
                                       2, 3, 7, 2, 7, 6, 0, 2, 6, 0, 6, 4, 1, 5, 7, 1, 7, 3};
        for (i = 0; i < 8; ++i) frame_point(fr, (float)(i & 1), (float)((i >> 1) & 1), (float)((i >> 2) & 1), m->pos + 3 * i);
        m->nv = 8;
        for (i = 0; i < 36; ++i) m->idx[i] = q[i];
        m->nt = 12;
        break;
    }
    }
}

/* A mesh as a triangle soup: three vertices per triangle, welded by position in the raster. */
static void mesh_soup(const tmesh *m, float *soup) {
    uint32_t t, k, c;
    for (t = 0; t < m->nt; ++t)
        for (k = 0; k < 3; ++k)
            for (c = 0; c < 3; ++c) soup[9 * t + 3 * k + c] = m->pos[3 * m->idx[3 * t + k] + c];
}

/* Checks every claimed pixel against 9 x 9 samples of the union: each sample is on some triangle
   (the visible part), and the stored depth is at most the nearest covering triangle's depth at every
   sample (the surface seen there). Counts the claimed pixels and, for a planar quad, the pixels the
   quad covers whole. Returns violations. */
static int check_mesh(pvs_raster *r, const float mat[16], const tmesh *m, uint32_t *claimed, uint32_t *quad_full) {
    static double C[MESH_MAXT][3][4];
    uint32_t w, h, i, j, si, sj, t, k;
    const float *d = pvs_raster_depth(r, &w, &h);
    int bad = 0;
    for (t = 0; t < m->nt; ++t)
        for (k = 0; k < 3; ++k) clip_of(mat, m->pos + 3 * m->idx[3 * t + k], C[t][k]);
    for (j = 0; j < h; ++j)
        for (i = 0; i < w; ++i) {
            float stored = d[j * w + i];
            int full = m->planar_quad, ok = 1;
            if (stored == PVS_DEPTH_EMPTY && !full) continue;
            for (sj = 0; sj <= 8 && (ok || full); ++sj)
                for (si = 0; si <= 8 && (ok || full); ++si) {
                    double x = ((double)i + si / 8.0) / w * 2.0 - 1.0, y = ((double)j + sj / 8.0) / h * 2.0 - 1.0, z, zn = -1e300;
                    int in = 0;
                    for (t = 0; t < m->nt; ++t)
                        if (tri_at_tol(C[t], x, y, 1e-9, &z)) {
                            in = 1;
                            if (z > zn) zn = z;
                        }
                    full &= in; /* a planar quad's union is the quad */
                    if (stored != PVS_DEPTH_EMPTY && ok && (!in || (double)stored > zn)) ok = 0;
                }
            if (stored != PVS_DEPTH_EMPTY) {
                ++*claimed;
                if (!ok) ++bad;
            }
            if (full) ++*quad_full;
        }
    return bad;
}

/* On W x H maps: 23 x 17 (the row pass's small triangles), and 61 x 45 tiled, where triangles over 32 pixels across
   take the fast pass (pvs__mesh_edge, pvs__mesh_fan), fewer meshes (each checks 7 times the pixels). */
static void test_mesh(int scale, uint32_t W, uint32_t H, int n) {
    pvs_raster_desc rd;
    pvs_raster *r, *rs, *rp;
    pvs_error e;
    static tmesh m;
    static float soup[9 * MESH_MAXT];
    int t, bad = 0, same = 1, superset = 1;
    uint32_t claimed = 0, quad_full = 0, quad_claimed = 0, quad_tri = 0;
    memset(&rd, 0, sizeof(rd));
    rd.width = W; rd.height = H; rd.flags = mode_flag;
    rd.max_mesh_triangles = 200; /* bigger meshes go in pieces */
    CHECK(pvs_raster_create(&rd, &r, &e) == PVS_OK);
    rd.flags = mode_flag | PVS_RASTER_SCALAR;
    CHECK(pvs_raster_create(&rd, &rs, &e) == PVS_OK);
    rd.flags = mode_flag;
    CHECK(pvs_raster_create(&rd, &rp, &e) == PVS_OK);
    for (t = 0; t < n; ++t) {
        float mat[16];
        int kind = t % 6, b, soupy = t % 4 == 3;
        uint32_t c0 = 0, qf = 0, px, ct = 0;
        const float *d, *dp;
        random_mesh(&m, kind);
        random_matrix(mat, (float)W / (float)H, (t / 6) % 3);
        if (t % 2 == 0) { /* looking at the mesh from a random point around it */
            pvs_camera cam;
            uint32_t v;
            float c[3] = {0, 0, 0};
            memset(&cam, 0, sizeof(cam));
            for (v = 0; v < m.nv; ++v)
                for (px = 0; px < 3; ++px) c[px] += m.pos[3 * v + px] / (float)m.nv;
            for (px = 0; px < 3; ++px) { cam.eye[px] = c[px] + rndf(-6, 6); cam.forward[px] = c[px] - cam.eye[px] + rndf(-0.5f, 0.5f); }
            cam.up[1] = 1; cam.up[0] = rndf(-0.3f, 0.3f);
            cam.near_plane = rndf(0.05f, 0.5f);
            cam.fov_y = t % 6 == 0 ? 0.0f : rndf(0.5f, 2.0f);
            cam.ortho_height = rndf(2, 10);
            if (pvs_camera_matrix(&cam, (float)W / (float)H, mat) != PVS_OK) random_matrix(mat, (float)W / (float)H, 0);
        }
        pvs_raster_clear(r); pvs_raster_set_matrix(r, mat);
        pvs_raster_clear(rs); pvs_raster_set_matrix(rs, mat);
        pvs_raster_clear(rp); pvs_raster_set_matrix(rp, mat);
        if (soupy) {
            mesh_soup(&m, soup);
            CHECK(pvs_raster_mesh(r, soup, 3 * m.nt, NULL, m.nt) == PVS_OK);
            CHECK(pvs_raster_mesh(rs, soup, 3 * m.nt, NULL, m.nt) == PVS_OK);
        } else {
            CHECK(pvs_raster_mesh(r, m.pos, m.nv, m.idx, m.nt) == PVS_OK);
            CHECK(pvs_raster_mesh(rs, m.pos, m.nv, m.idx, m.nt) == PVS_OK);
        }
        pvs_raster_triangles(rp, m.pos, m.nv, m.idx, m.nt, PVS_RASTER_OCCLUDER);
        b = check_mesh(r, mat, &m, &c0, &qf);
        d = pvs_raster_depth(r, NULL, NULL);
        same &= memcmp(d, pvs_raster_depth(rs, NULL, NULL), (size_t)W * H * sizeof(float)) == 0;
        dp = pvs_raster_depth(rp, NULL, NULL);
        for (px = 0; px < W * H; ++px) { /* never less than its triangles one at a time (per pixel) */
            if (mode_flag == PVS_RASTER_PER_PIXEL && dp[px] != PVS_DEPTH_EMPTY && !(d[px] >= dp[px] - 1e-3f * fabsf(dp[px])))
                superset = 0; /* the same pixels; the depth up to the planes' float evaluation (from other origins) */
            ct += dp[px] != PVS_DEPTH_EMPTY;
        }
        if (b) {
            fprintf(stderr, "mesh %d kind %d matrix %d soup %d: %d violations\n", t, kind, (t / 6) % 3, soupy, b);
            bad += b;
        }
        claimed += c0;
        if (m.planar_quad) { quad_full += qf; quad_claimed += c0; quad_tri += ct; }
    }
    CHECK(bad == 0);
    CHECK(same || !SAME_BITS);
    CHECK(superset);
    CHECK(claimed > 0);
    /* a quad split into 2..64 triangles claims (nearly) every pixel the quad covers whole, far more
       than its triangles one at a time */
    CHECK(quad_claimed * 100 >= quad_full * 90);
    if (scale == 1) fprintf(stderr, "  mesh (%s, %u x %u): quads cover %u pixels whole, mesh claims %u, triangles alone %u\n",
                            mode_flag == PVS_RASTER_TILED ? "tiled" : "per pixel", W, H, quad_full, quad_claimed, quad_tri);
    /* errors */
    CHECK(pvs_raster_mesh(NULL, m.pos, 3, NULL, 1) == PVS_ERROR_INVALID_ARGUMENT);
    CHECK(pvs_raster_mesh(r, NULL, 3, NULL, 1) == PVS_ERROR_INVALID_ARGUMENT);
    CHECK(pvs_raster_mesh(r, NULL, 0, NULL, 0) == PVS_OK);
    pvs_raster_destroy(r);
    pvs_raster_destroy(rs);
    pvs_raster_destroy(rp);
}

/* The fast pass on its own (tiled; triangles over 32 pixels across): random fans, closed or open, of 3 to 9
   triangles with a vertex depth each (folds along every edge), in clip space on a 64 x 64 map; every claimed pixel
   checked against the union (check_mesh). */
static void test_mesh_fast(int scale) {
    pvs_raster_desc rd;
    pvs_raster *r;
    pvs_error e;
    static tmesh m;
    static const float id[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
    int t, bad = 0, n = 120 * scale;
    uint32_t claimed = 0, full = 0, i, alone = 0, w, h;
    memset(&rd, 0, sizeof(rd));
    rd.width = rd.height = 64; rd.flags = PVS_RASTER_TILED;
    CHECK(pvs_raster_create(&rd, &r, &e) == PVS_OK);
    for (t = 0; t < n; ++t) {
        uint32_t rim = 3 + (uint32_t)(rnd() * 7), closed = rnd() < 0.7, c0 = 0;
        float a = rndf(0, 6.2831853f), cx = rndf(-0.3f, 0.3f), cy = rndf(-0.3f, 0.3f);
        const float *d;
        m.pos[0] = cx; m.pos[1] = cy; m.pos[2] = rndf(0.1f, 0.9f);
        for (i = 0; i < rim; ++i) { /* angles increasing: counter-clockwise, gaps up to 170 degrees */
            float rad = rndf(0.3f, 0.95f);
            a += (closed ? 6.2831853f / (float)rim : 3.0f / (float)rim) * rndf(0.4f, 1.6f);
            m.pos[3 * (i + 1)] = cx + rad * cosf(a); m.pos[3 * (i + 1) + 1] = cy + rad * sinf(a);
            m.pos[3 * (i + 1) + 2] = rndf(0.1f, 0.9f);
        }
        m.nv = rim + 1; m.nt = 0; m.planar_quad = 0;
        for (i = 0; i < rim - (closed ? 0 : 1); ++i) {
            m.idx[3 * m.nt] = 0; m.idx[3 * m.nt + 1] = 1 + i; m.idx[3 * m.nt + 2] = 1 + (i + 1) % rim;
            ++m.nt;
        }
        pvs_raster_clear(r); pvs_raster_set_matrix(r, id);
        pvs_raster_triangles(r, m.pos, m.nv, m.idx, m.nt, PVS_RASTER_OCCLUDER);
        d = pvs_raster_depth(r, &w, &h);
        for (i = 0; i < w * h; ++i) alone += d[i] != PVS_DEPTH_EMPTY;
        pvs_raster_clear(r); pvs_raster_set_matrix(r, id);
        CHECK(pvs_raster_mesh(r, m.pos, m.nv, m.idx, m.nt) == PVS_OK);
        bad += check_mesh(r, id, &m, &c0, &full);
        claimed += c0;
    }
    CHECK(bad == 0);
    CHECK(claimed > alone + alone / 20); /* the edges' and fans' pixels */
    if (scale == 1) fprintf(stderr, "  mesh fast pass: %d fans, %u pixels claimed, triangles alone %u\n", n, claimed, alone);
    pvs_raster_destroy(r);
}

/* SIMD and scalar give identical depth maps; many triangles on one map. Per pixel, the map is the
   nearest of what the triangles give one at a time; tiled occluders merge (Masked Occlusion Culling's
   two layers): each pixel is at most that. */
static void test_simd_identical(int scale) {
    pvs_raster_desc rd;
    pvs_raster *a, *b;
    pvs_error e;
    int t, mode, same = 1, farther = 1;
    uint32_t kept = 0, alone = 0;
    float *tris;
    int n = 400 * scale;
    memset(&rd, 0, sizeof(rd));
    rd.width = 67; rd.height = 45; rd.flags = mode_flag;
    CHECK(pvs_raster_create(&rd, &a, &e) == PVS_OK);
    rd.flags = PVS_RASTER_SCALAR | mode_flag;
    CHECK(pvs_raster_create(&rd, &b, &e) == PVS_OK);
    tris = (float *)malloc((size_t)n * 9 * sizeof(float));
    for (mode = 0; mode < 2; ++mode) {
        float m[16];
        random_matrix(m, 67.0f / 45.0f, mode);
        for (t = 0; t < n; ++t) random_triangle(tris + 9 * t, t % 5);
        pvs_raster_clear(a); pvs_raster_clear(b);
        pvs_raster_set_matrix(a, m); pvs_raster_set_matrix(b, m);
        pvs_raster_triangles(a, tris, 3 * (uint32_t)n, NULL, (uint32_t)n, (pvs_raster_mode)mode);
        pvs_raster_triangles(b, tris, 3 * (uint32_t)n, NULL, (uint32_t)n, (pvs_raster_mode)mode);
        same &= memcmp(pvs_raster_depth(a, NULL, NULL), pvs_raster_depth(b, NULL, NULL), 67 * 45 * sizeof(float)) == 0;
        /* one triangle at a time, combined by hand */
        {
            float *ref = (float *)malloc(67 * 45 * sizeof(float));
            const float *d;
            uint32_t px;
            for (px = 0; px < 67 * 45; ++px) ref[px] = PVS_DEPTH_EMPTY;
            for (t = 0; t < n; ++t) {
                pvs_raster_clear(b);
                pvs_raster_triangles(b, tris + 9 * t, 3, NULL, 1, (pvs_raster_mode)mode);
                d = pvs_raster_depth(b, NULL, NULL);
                for (px = 0; px < 67 * 45; ++px) ref[px] = d[px] > ref[px] ? d[px] : ref[px];
            }
            d = pvs_raster_depth(a, NULL, NULL);
            if (mode == PVS_RASTER_OCCLUDEE || mode_flag == PVS_RASTER_PER_PIXEL) same &= memcmp(d, ref, 67 * 45 * sizeof(float)) == 0;
            for (px = 0; px < 67 * 45; ++px) {
                farther &= d[px] <= ref[px];
                if (mode == PVS_RASTER_OCCLUDER) { alone += ref[px] != PVS_DEPTH_EMPTY; kept += d[px] != PVS_DEPTH_EMPTY; }
            }
            free(ref);
        }
    }
    CHECK(same || !SAME_BITS);
    CHECK(farther || !SAME_BITS);
    CHECK(kept * 10 >= alone * 9); /* the merge keeps most of the coverage */
    free(tris);
    pvs_raster_destroy(a);
    pvs_raster_destroy(b);
}

/* Box tests against the exact projection: under random cameras (some far from the origin, where
   float rounding is large), every box whose exact screen rectangle holds a pixel storing a depth at
   most the box's exact nearest depth is reported visible; SIMD and scalar agree box by box. */
static void test_boxes(int scale) {
    pvs_raster_desc rd;
    pvs_raster *a, *b;
    pvs_error e;
    int t, missed = 0, differ = 0, checked = 0, hidden = 0, view_culled = 0, wrong_view = 0;
    const uint32_t W = 64, H = 48;
    memset(&rd, 0, sizeof(rd));
    rd.width = W; rd.height = H; rd.flags = mode_flag;
    CHECK(pvs_raster_create(&rd, &a, &e) == PVS_OK);
    rd.flags = PVS_RASTER_SCALAR | mode_flag;
    CHECK(pvs_raster_create(&rd, &b, &e) == PVS_OK);
    for (t = 0; t < 40 * scale; ++t) {
        float m[16], off[3], tri[9 * 40];
        const float *d;
        int k, q;
        pvs_camera cam;
        memset(&cam, 0, sizeof(cam));
        for (k = 0; k < 3; ++k) off[k] = t % 3 == 0 ? 0.0f : rndf(-1, 1) * (t % 3 == 1 ? 1e3f : 3e4f);
        for (k = 0; k < 3; ++k) { cam.eye[k] = off[k] + rndf(-1, 1); cam.forward[k] = rndf(-1, 1); }
        cam.forward[2] += 0.5f;
        cam.up[1] = 1;
        cam.near_plane = rndf(0.05f, 0.5f);
        cam.fov_y = t % 4 == 3 ? 0.0f : rndf(0.5f, 2.0f);
        cam.ortho_height = rndf(2, 10);
        cam.far_plane = 40.0f;
        if (pvs_camera_matrix(&cam, (float)W / (float)H, m) != PVS_OK) continue;
        for (k = 0; k < 40; ++k) {
            int c;
            random_triangle(tri + 9 * k, 0);
            for (c = 0; c < 9; ++c) tri[9 * k + c] += off[c % 3];
        }
        if (t % 2) { /* a wall in the plane z = off[2] + 2 with a hole; boxes below touch it from behind */
            static const float sq[6][2] = {{-6, -6}, {6, -6}, {6, 6}, {-6, -6}, {6, 6}, {-6, 6}};
            float hx = rndf(-3, 3), hy = rndf(-3, 3);
            for (k = 0; k < 6; ++k) {
                tri[3 * k] = off[0] + sq[k][0]; tri[3 * k + 1] = off[1] + sq[k][1]; tri[3 * k + 2] = off[2] + 2.0f;
                tri[18 + 3 * k] = off[0] + hx + 0.1f * sq[k][0]; tri[18 + 3 * k + 1] = off[1] + hy + 0.1f * sq[k][1];
                tri[18 + 3 * k + 2] = off[2] + 3.0f; /* a smaller square behind the wall */
            }
            for (k = 36; k < 9 * 40; ++k) tri[k] = 0.0f; /* degenerate: nothing */
            if (cam.eye[2] > off[2] + 1.5f) cam.eye[2] = off[2] + 1.5f - rndf(0, 3);
            cam.forward[2] = 1.0f;
            if (t % 4 == 1) cam.forward[0] = cam.forward[1] = 0.0f; /* facing the wall: one depth over it */
            if (pvs_camera_matrix(&cam, (float)W / (float)H, m) != PVS_OK) continue;
        }
        pvs_raster_clear(a); pvs_raster_clear(b);
        pvs_raster_set_matrix(a, m); pvs_raster_set_matrix(b, m);
        pvs_raster_triangles(a, tri, 120, NULL, 40, PVS_RASTER_OCCLUDER);
        pvs_raster_triangles(b, tri, 120, NULL, 40, PVS_RASTER_OCCLUDER);
        d = pvs_raster_depth(a, NULL, NULL);
        for (q = 0; q < 200; ++q) {
            pvs_box bx;
            double C[8][4], xmin = 1e300, xmax = -1e300, ymin = 1e300, ymax = -1e300, zmax = -1e300;
            int front = 1, va, vb, x, y, expect = 0;
            float sz = rnd() < 0.3 ? rndf(1e-4f, 0.05f) : rndf(0.05f, 4.0f);
            for (k = 0; k < 3; ++k) {
                bx.min[k] = off[k] + rndf(-6, 6);
                bx.max[k] = bx.min[k] + sz * rndf(0.1f, 1.0f);
            }
            if (t % 2 && q % 2) { /* touching the wall from behind */
                bx.min[2] = off[2] + 2.0f;
                bx.max[2] = bx.min[2] + sz;
            }
            va = pvs_raster_test_box(a, &bx);
            vb = pvs_raster_classify_box(b, &bx);
            differ += va != (vb == PVS_BOX_VISIBLE) || vb != pvs_raster_classify_box(a, &bx);
            view_culled += vb == PVS_BOX_VIEW_CULLED;
            for (k = 0; k < 8; ++k) {
                float p[3];
                p[0] = k & 1 ? bx.max[0] : bx.min[0];
                p[1] = k & 2 ? bx.max[1] : bx.min[1];
                p[2] = k & 4 ? bx.max[2] : bx.min[2];
                clip_of(m, p, C[k]);
                if (!(C[k][3] > 1e-9 && C[k][3] - C[k][2] > 0.0)) front = 0;
            }
            if (!front) continue;
            for (k = 0; k < 8; ++k) {
                double sx = (C[k][0] / C[k][3] + 1.0) * 0.5 * W, sy = (C[k][1] / C[k][3] + 1.0) * 0.5 * H, z = C[k][2] / C[k][3];
                xmin = sx < xmin ? sx : xmin; xmax = sx > xmax ? sx : xmax;
                ymin = sy < ymin ? sy : ymin; ymax = sy > ymax ? sy : ymax;
                zmax = z > zmax ? z : zmax;
            }
            if (xmax < 0 || ymax < 0 || xmin > W || ymin > H) continue;
            wrong_view += vb == PVS_BOX_VIEW_CULLED; /* in front and on screen: not view-culled */
            for (y = ymin < 0 ? 0 : (int)floor(ymin); y <= (int)floor(ymax) && y < (int)H; ++y)
                for (x = xmin < 0 ? 0 : (int)floor(xmin); x <= (int)floor(xmax) && x < (int)W; ++x) expect |= (double)d[y * (int)W + x] <= zmax;
            ++checked;
            hidden += !va;
            if (expect && !va) {
                ++missed;
                fprintf(stderr, "box test missed: camera %d box %d (%.9g %.9g %.9g)-(%.9g %.9g %.9g)\n", t, q, bx.min[0], bx.min[1], bx.min[2],
                        bx.max[0], bx.max[1], bx.max[2]);
            }
        }
    }
    CHECK(missed == 0);
    CHECK(differ == 0);
    CHECK(checked > 100 * scale);
    CHECK(hidden > 0);
    CHECK(view_culled > 0 && wrong_view == 0);
    pvs_raster_destroy(a);
    pvs_raster_destroy(b);
}

/* Rectangle queries against a scan of the depth map, on odd and degenerate map sizes. */
static void test_pyramid(int scale) {
    static const uint32_t sizes[][2] = {{37, 21}, {1, 1}, {1, 7}, {7, 1}, {64, 64}, {33, 17}};
    uint32_t z;
    int wrong = 0, hidden = 0;
    for (z = 0; z < sizeof(sizes) / sizeof(sizes[0]); ++z) {
        uint32_t W = sizes[z][0], H = sizes[z][1];
        pvs_raster_desc rd;
        pvs_raster *r;
        pvs_error e;
        float m[16], p[9];
        int t, q;
        memset(&rd, 0, sizeof(rd));
        rd.width = W; rd.height = H; rd.flags = mode_flag;
        CHECK(pvs_raster_create(&rd, &r, &e) == PVS_OK);
        for (t = 0; t < 10 * scale; ++t) {
            const float *d;
            uint32_t k;
            random_matrix(m, (float)W / (float)H, t % 3);
            pvs_raster_clear(r);
            pvs_raster_set_matrix(r, m);
            for (k = 0; k < 30; ++k) {
                random_triangle(p, 0);
                pvs_raster_triangles(r, p, 3, NULL, 1, k % 4 ? PVS_RASTER_OCCLUDER : PVS_RASTER_OCCLUDEE);
            }
            d = pvs_raster_depth(r, NULL, NULL);
            for (q = 0; q < 200; ++q) {
                int32_t x0 = (int32_t)(rnd() * (W + 8)) - 4, y0 = (int32_t)(rnd() * (H + 8)) - 4;
                int32_t x1 = x0 + (int32_t)(rnd() * W), y1 = y0 + (int32_t)(rnd() * H);
                float depth = rnd() < 0.3 ? PVS_DEPTH_EMPTY : d[(uint32_t)(rnd() * W * H)] + rndf(-1e-3f, 1e-3f);
                int expect = 0, x, y;
                for (y = y0 < 0 ? 0 : y0; y <= y1 && y < (int32_t)H; ++y)
                    for (x = x0 < 0 ? 0 : x0; x <= x1 && x < (int32_t)W; ++x) expect |= d[y * (int32_t)W + x] <= depth;
                wrong += pvs_raster_test_rect(r, x0, y0, x1, y1, depth) != expect;
                hidden += !expect;
            }
        }
        pvs_raster_destroy(r);
    }
    CHECK(wrong == 0);
    CHECK(hidden > 0);
}

/* ---- scenes ---- */

typedef struct tscene {
    mesh m;
    pvs_scene *scene;
    pvs_facade_chain *chains; /* one open 2-point chain per upright wall triangle standing on the ground */
    float *chain_pts;
    uint32_t chain_count;
    mesh_cells cells;
} tscene;

static const pvs_occluder_desc *ts_occluders; /* explicit occluders for the next tscene_make */
static uint32_t ts_occluder_count;
static int tscene_make(tscene *t, uint32_t up) {
    pvs_scene_desc d;
    pvs_object_desc *obs = (pvs_object_desc *)malloc(t->m.object_count * sizeof(pvs_object_desc));
    pvs_error e;
    uint32_t i, tri;
    int ok;
    for (i = 0; i < t->m.object_count; ++i) {
        obs[i].first_triangle = t->m.objects[i].first_triangle;
        obs[i].triangle_count = t->m.objects[i].triangle_count;
        obs[i].flags = 0;
    }
    memset(&d, 0, sizeof(d));
    d.positions = t->m.positions; d.vertex_count = t->m.vertex_count;
    d.indices = t->m.indices; d.triangle_count = t->m.triangle_count;
    d.objects = obs; d.object_count = t->m.object_count;
    d.up_axis = up;
    d.flags = PVS_SCENE_ALLOW_EMPTY_OBJECTS;
    d.occluders = ts_occluders;
    d.occluder_count = ts_occluder_count;
    ok = pvs_scene_create(&d, &t->scene, &e) == PVS_OK;
    if (!ok) fprintf(stderr, "scene: %s\n", e.message);
    free(obs);
    /* facades: a triangle with two corners on the ground (height = the scene's minimum) and the third
       straight above one of them is half of an upright quad (the generators emit walls as quads) */
    t->chains = (pvs_facade_chain *)malloc((t->m.triangle_count + 1) * sizeof(pvs_facade_chain));
    t->chain_pts = (float *)malloc((t->m.triangle_count + 1) * 4 * sizeof(float));
    t->chain_count = 0;
    if (ok) {
        float g = pvs_scene_bounds(t->scene).min[up];
        int u = 0, v = up == 2 ? 1 : 2;
        for (tri = 0; tri < t->m.triangle_count; ++tri) {
            const float *p[3];
            int k, low = 0, hi = -1, lo1 = -1, lo2 = -1;
            for (k = 0; k < 3; ++k) {
                p[k] = t->m.positions + 3 * t->m.indices[3 * tri + k];
                if (p[k][up] == g) { ++low; if (lo1 < 0) lo1 = k; else lo2 = k; }
                else hi = k;
            }
            if (low != 2 || !(p[hi][up] > g)) continue;
            if (!((p[hi][u] == p[lo1][u] && p[hi][v] == p[lo1][v]) || (p[hi][u] == p[lo2][u] && p[hi][v] == p[lo2][v]))) continue;
            {
                /* the quad's other triangle must exist for the full rectangle: the generators always emit
                   it, and both halves give the same facade, which is harmless */
                pvs_facade_chain *c = t->chains + t->chain_count;
                float *q = t->chain_pts + 4 * t->chain_count;
                q[0] = p[lo1][u]; q[1] = p[lo1][v]; q[2] = p[lo2][u]; q[3] = p[lo2][v];
                c->points = q; c->point_count = 2; c->closed = 0; c->base = g; c->top = p[hi][up];
                ++t->chain_count;
            }
        }
    }
    return ok;
}
static void tscene_free(tscene *t) {
    pvs_scene_destroy(t->scene);
    mesh_free(&t->m);
    mesh_cells_free(&t->cells);
    free(t->chains);
    free(t->chain_pts);
}
static int tscene_gen(tscene *t, gen_kind kind, float size, uint64_t seed) {
    gen_params gp;
    gp = test_gen_params(kind, seed, size, 0);
    if (test_generate(&gp, &t->m, &t->cells, NULL) != 0) return 0;
    return tscene_make(t, 1);
}
/* Random boxes (Z up when up == 2) on a ground quad. */
static int tscene_boxes(tscene *t, uint32_t n, uint32_t up) {
    uint32_t i;
    int v = up == 2 ? 1 : 2;
    mesh_init(&t->m);
    mesh_cells_init(&t->cells);
    mesh_begin_object(&t->m, "ground", 0, 0);
    {
        float q[4][3] = {{-60, 0, -60}, {60, 0, -60}, {60, 0, 60}, {-60, 0, 60}};
        uint32_t k;
        for (k = 0; k < 4; ++k) {
            float p[3];
            p[0] = q[k][0]; p[up] = 0; p[v] = q[k][2];
            mesh_add_vertex(&t->m, p[0], p[1], p[2]);
        }
        mesh_add_quad(&t->m, 0, 1, 2, 3);
    }
    for (i = 0; i < n; ++i) {
        float lo[3], hi[3];
        char name[32];
        sprintf(name, "box_%u", i);
        mesh_begin_object(&t->m, name, 0, 0);
        lo[0] = rndf(-50, 48); lo[v] = rndf(-50, 48); lo[up] = rnd() < 0.8 ? 0.0f : rndf(0, 3);
        hi[0] = lo[0] + rndf(0.2f, 8); hi[v] = lo[v] + rndf(0.2f, 8); hi[up] = lo[up] + rndf(0.3f, 12);
        test_mesh_box(&t->m, lo, hi);
    }
    return tscene_make(t, up);
}

/* A camera at a random place from which to look: a cell centre when the scene has cells, else a
   random point above the ground. */
static void random_camera(const tscene *t, pvs_camera *cam, uint32_t up) {
    pvs_box b = pvs_scene_bounds(t->scene);
    int k, v = up == 2 ? 1 : 2;
    memset(cam, 0, sizeof(*cam));
    if (t->cells.count) {
        const float *c = t->cells.boxes + 6 * (uint32_t)(rnd() * t->cells.count);
        for (k = 0; k < 3; ++k) cam->eye[k] = c[k] + (c[3 + k] - c[k]) * (float)rnd();
    } else {
        for (k = 0; k < 3; ++k) cam->eye[k] = rndf(b.min[k], b.max[k]);
        cam->eye[up] = rnd() < 0.7 ? rndf(0.5f, 2.0f) : rndf(b.min[up], b.max[up] + 10);
    }
    cam->forward[0] = rndf(-1, 1);
    cam->forward[v] = rndf(-1, 1);
    cam->forward[up] = rndf(-0.4f, 0.4f);
    if (fabsf(cam->forward[0]) + fabsf(cam->forward[v]) < 0.05f) cam->forward[0] = 1;
    cam->up[up] = 1;
    cam->fov_y = rndf(0.6f, 1.8f);
    cam->near_plane = rndf(0.05f, 0.3f);
    if (rnd() < 0.1) { cam->fov_y = 0; cam->ortho_height = rndf(5, 40); }
}

static pvs_raster *dbg_r;
extern unsigned long raster_cameras, raster_misses;
unsigned long raster_cameras, raster_misses; /* totals for tests/verify_raster.c */
/* Rays through random screen points from the near plane; every object hit must be visible.
   Returns misses. */
static uint32_t check_rays(const tscene *t, const pvs_camera *cam, float aspect, const pvs_word *visible, const pvs_word *cand,
                           uint32_t rays, uint32_t *hits) {
    double f[3], u[3], rt[3], sy, sx;
    uint32_t i, misses = 0;
    int k;
    test_camera_frame(cam, aspect, f, u, rt, &sx, &sy);
    for (i = 0; i < rays; ++i) {
        double a = (2 * rnd() - 1) * sx, b = (2 * rnd() - 1) * sy;
        float o[3], d[3];
        pvs_hit hit;
        for (k = 0; k < 3; ++k) {
            if (cam->fov_y > 0) {
                double dir = f[k] + a * rt[k] + b * u[k];
                d[k] = (float)dir;
                o[k] = (float)(cam->eye[k] + cam->near_plane * dir);
            } else {
                d[k] = (float)f[k];
                o[k] = (float)(cam->eye[k] + a * rt[k] + b * u[k] + cam->near_plane * f[k]);
            }
        }
        if (pvs_scene_raycast(t->scene, o, d, 1e30f, &hit) && hit.object != PVS_NO_OBJECT) {
            ++*hits;
            if (cand && !pvs_bitset_test(cand, hit.object)) continue;
            if (!pvs_bitset_test(visible, hit.object)) {
                if (misses == 0) {
                    fprintf(stderr, "miss: object %u from eye (%g %g %g) fov %g, hit t %g\n", hit.object, cam->eye[0], cam->eye[1],
                            cam->eye[2], cam->fov_y, hit.t);
                    if (dbg_r) {
                        pvs_box ob = pvs_scene_object_box(t->scene, hit.object);
                        float reg[4], hp[3];
                        uint32_t w, h, ii, jj;
                        const float *cm = pvs_cull_map(dbg_r, &w, &h, reg);
                        for (k = 0; k < 3; ++k) hp[k] = o[k] + d[k] * hit.t;
                        fprintf(stderr, " box %g %g %g / %g %g %g hit %g %g %g\n", ob.min[0], ob.min[1], ob.min[2], ob.max[0], ob.max[1], ob.max[2], hp[0], hp[1], hp[2]);
                        ii = (uint32_t)((hp[0] - reg[0]) / (reg[2] - reg[0]) * w);
                        jj = (uint32_t)((hp[2] - reg[1]) / (reg[3] - reg[1]) * h);
                        if (ii < w && jj < h) fprintf(stderr, " cell %u %u cm %g\n", ii, jj, cm[jj * w + ii]);
                    }
                }
                ++misses;
            }
        }
    }
    return misses;
}

/* Culling (depth pyramid and cull map) against ray casting. */
static void cull_scene(tscene *t, uint32_t up, uint32_t cameras, uint32_t rays, const char *label) {
    pvs_raster_desc rd;
    pvs_raster *r, *rs, *ctx[4];
    pvs_error e;
    pvs_word *vis, *vis_s, *cand;
    uint32_t n = pvs_scene_object_count(t->scene), c, same = 1, misses = 0, cm_misses = 0, hits = 0, culled = 0, cm_culled = 0, outside = 0;
    size_t words = PVS_BITSET_WORDS(n);
    memset(&rd, 0, sizeof(rd));
    rd.width = 96; rd.height = 64;
    rd.scene = t->scene;
    rd.max_occluders = 400;
    rd.cull_map_width = 128; rd.cull_map_height = 96;
    for (c = 0; c < 4; ++c) { /* per pixel and tiled, each SIMD and scalar */
        rd.flags = (c & 1 ? PVS_RASTER_SCALAR : 0u) | (c & 2 ? PVS_RASTER_TILED : PVS_RASTER_PER_PIXEL);
        CHECK(pvs_raster_create(&rd, &ctx[c], &e) == PVS_OK);
    }
    vis = (pvs_word *)calloc(words, sizeof(pvs_word));
    vis_s = (pvs_word *)calloc(words, sizeof(pvs_word));
    cand = (pvs_word *)calloc(words, sizeof(pvs_word));
    for (c = 0; c < cameras; ++c) {
        pvs_camera cam;
        pvs_cull_params cp;
        pvs_cull_stats st;
        uint32_t i, use_cand = c % 4 == 3;
        r = ctx[2 * (c & 1)];
        rs = ctx[2 * (c & 1) + 1];
        random_camera(t, &cam, up);
        memset(&cp, 0, sizeof(cp));
        cp.scene_occluders = 64 + (uint32_t)(rnd() * 300);
        cp.occluder_distance = rndf(10, 80);
        cp.occluder_flags = c % 3 == 2 ? PVS_CULL_SEPARATE_TRIANGLES : PVS_CULL_SCENE_MESH; /* or one triangle at a time */
        if (use_cand) {
            for (i = 0; i < n; ++i) if (rnd() < 0.5) pvs_bitset_set(cand, i); else pvs_bitset_clear(cand, i);
            cp.candidates = cand;
        }
        CHECK(pvs_raster_cull(r, t->scene, &cam, &cp, vis, &st, &e) == PVS_OK);
        CHECK(pvs_raster_cull(rs, t->scene, &cam, &cp, vis_s, NULL, &e) == PVS_OK); /* the scalar reference */
        same &= memcmp(vis, vis_s, words * sizeof(pvs_word)) == 0;
        culled += n - st.visible;
        if (use_cand)
            for (i = 0; i < words; ++i) CHECK((vis[i] & ~cand[i]) == 0);
        misses += check_rays(t, &cam, 96.0f / 64.0f, vis, use_cand ? cand : NULL, rays, &hits);
        /* the 2.5D entry point with the scene's upright walls as facades */
        if (cam.eye[up] >= pvs_scene_bounds(t->scene).min[up]) {
            cp.facades = t->chains;
            cp.facade_count = t->chain_count;
            CHECK(pvs_raster_cull_map(r, t->scene, &cam, &cp, vis, &st, &e) == PVS_OK);
            CHECK(pvs_raster_cull_map(rs, t->scene, &cam, &cp, vis_s, NULL, &e) == PVS_OK);
            same &= memcmp(vis, vis_s, words * sizeof(pvs_word)) == 0;
            {
                uint32_t cw, chh;
                const float *m1 = pvs_cull_map(r, &cw, &chh, NULL), *m2 = pvs_cull_map(rs, NULL, NULL, NULL);
                same &= memcmp(m1, m2, (size_t)cw * chh * sizeof(float)) == 0;
            }
            dbg_r = up == 1 ? r : NULL;
            cm_culled += n - st.visible;
            cm_misses += check_rays(t, &cam, 96.0f / 64.0f, vis, use_cand ? cand : NULL, rays, &hits);
            dbg_r = NULL;
        } else {
            ++outside;
        }
    }
    raster_cameras += cameras;
    raster_misses += misses + cm_misses;
    if (misses || cm_misses) fprintf(stderr, "%s: %u pyramid misses, %u cull map misses over %u hits\n", label, misses, cm_misses, hits);
    CHECK(same || !SAME_BITS);
    CHECK(misses == 0);
    CHECK(cm_misses == 0);
    CHECK(hits > cameras);
    CHECK(culled > 0);
    (void)outside;
    if (getenv("PVS_RASTER_VERBOSE"))
        fprintf(stderr, "%s: %u cameras, %u rays each, %u hits, culled per frame: pyramid %.1f, cull map %.1f of %u\n", label, cameras,
                rays, hits, (double)culled / cameras, (double)cm_culled / cameras, n);
    free(vis);
    free(vis_s);
    free(cand);
    for (c = 0; c < 4; ++c) pvs_raster_destroy(ctx[c]);
}

static void test_culling(int scale) {
    tscene t;
    uint32_t cams = 40 * (uint32_t)scale, rays = 300;
    if (tscene_boxes(&t, 150, 1)) cull_scene(&t, 1, cams, rays, "boxes");
    tscene_free(&t);
    if (tscene_boxes(&t, 150, 2)) cull_scene(&t, 2, cams, rays, "boxes z-up");
    tscene_free(&t);
    if (tscene_gen(&t, GEN_CITY, 0.25f, 1 + (uint64_t)scale)) cull_scene(&t, 1, cams, rays, "city");
    tscene_free(&t);
    if (tscene_gen(&t, GEN_WALLS, 0.4f, 2)) cull_scene(&t, 1, cams, rays, "walls");
    tscene_free(&t);
    if (tscene_gen(&t, GEN_INDOOR, 0.4f, 3)) cull_scene(&t, 1, cams / 2, rays, "indoor");
    tscene_free(&t);
    if (tscene_gen(&t, GEN_SOUP, 0.3f, 4)) cull_scene(&t, 1, cams / 2, rays, "soup");
    tscene_free(&t);
}

/* Every cull map cell's height lies below the shadows: a point just under it is hidden from the eye
   by a facade (segment test against the facades as quads). Random closed footprints (star-shaped,
   either winding: back faces culled, seams between neighbours) and open polylines (two-sided). */
static void test_cull_map_cells(int scale) {
    enum { CLOSED = 25, OPEN = 15, MAXP = 8 };
    pvs_facade_chain ch[CLOSED + OPEN];
    float pts[CLOSED + OPEN][2 * MAXP];
    mesh fm;
    pvs_scene_desc d;
    pvs_object_desc ob;
    pvs_scene *fs;
    pvs_raster_desc rd;
    pvs_raster *r;
    pvs_error e;
    uint32_t c, k, cells = 0, blocked = 0, samples = 0, box_tests = 0, box_wrong = 0, box_hidden = 0, box_seen = 0;
    mesh_init(&fm);
    mesh_begin_object(&fm, "f", 0, 0);
    for (c = 0; c < CLOSED + OPEN; ++c) {
        uint32_t n = c < CLOSED ? 3 + (uint32_t)(rnd() * 6) : 2 + (uint32_t)(rnd() * 5), i;
        float cx = rndf(-45, 45), cz = rndf(-45, 45), top = rndf(2, 12);
        for (i = 0; i < n; ++i) {
            if (c < CLOSED) {
                double ang = 6.283185307179586 * (i + 0.8 * rnd()) / n, rad = rndf(1, 7);
                uint32_t j = (c & 1) ? n - 1 - i : i; /* odd chains wind the other way */
                pts[c][2 * j] = cx + (float)(rad * cos(ang));
                pts[c][2 * j + 1] = cz + (float)(rad * sin(ang));
            } else {
                pts[c][2 * i] = i ? pts[c][2 * i - 2] + rndf(-8, 8) : cx;
                pts[c][2 * i + 1] = i ? pts[c][2 * i - 1] + rndf(-8, 8) : cz;
            }
        }
        ch[c].points = pts[c]; ch[c].point_count = n; ch[c].closed = c < CLOSED; ch[c].base = 0; ch[c].top = top;
        for (i = 0; i + (c < CLOSED ? 0u : 1u) < n; ++i) {
            const float *p0 = pts[c] + 2 * i, *p1 = pts[c] + 2 * ((i + 1) % n);
            uint32_t b = fm.vertex_count;
            mesh_add_vertex(&fm, p0[0], 0, p0[1]);
            mesh_add_vertex(&fm, p1[0], 0, p1[1]);
            mesh_add_vertex(&fm, p1[0], top, p1[1]);
            mesh_add_vertex(&fm, p0[0], top, p0[1]);
            mesh_add_quad(&fm, b, b + 1, b + 2, b + 3);
        }
    }
    memset(&d, 0, sizeof(d));
    ob.first_triangle = 0; ob.triangle_count = fm.triangle_count; ob.flags = 0;
    d.positions = fm.positions; d.vertex_count = fm.vertex_count; d.indices = fm.indices; d.triangle_count = fm.triangle_count;
    d.objects = &ob; d.object_count = 1;
    CHECK(pvs_scene_create(&d, &fs, &e) == PVS_OK);
    memset(&rd, 0, sizeof(rd));
    rd.width = 8; rd.height = 8; rd.scene = fs; rd.cull_map_width = 80; rd.cull_map_height = 64;
    CHECK(pvs_raster_create(&rd, &r, &e) == PVS_OK);
    for (k = 0; k < 30 * (uint32_t)scale; ++k) {
        float eye[3], reg[4];
        uint32_t w, h, i;
        const float *cm;
        eye[0] = rndf(-55, 55); eye[2] = rndf(-55, 55); eye[1] = rnd() < 0.7 ? rndf(0.2f, 3) : rndf(3, 20);
        CHECK(pvs_cull_map_build(r, eye, ch, CLOSED + OPEN, 0) == PVS_OK);
        cm = pvs_cull_map(r, &w, &h, reg);
        for (i = 0; i < w * h; ++i) {
            uint32_t sm;
            if (cm[i] == PVS_DEPTH_EMPTY) continue;
            ++cells;
            for (sm = 0; sm < 3; ++sm) {
                float p[3];
                p[0] = reg[0] + (reg[2] - reg[0]) * ((float)(i % w) + (float)rnd()) / (float)w;
                p[2] = reg[1] + (reg[3] - reg[1]) * ((float)(i / w) + (float)rnd()) / (float)h;
                p[1] = cm[i] - 1e-3f - 1e-5f * fabsf(cm[i]);
                if (p[1] < 0) continue;
                ++samples;
                if (pvs_scene_segment_blocked(fs, eye, p)) ++blocked;
                else if (samples - blocked < 4)
                    fprintf(stderr, "cull map: (%g %g %g) under height %g is visible from (%g %g %g)\n", p[0], p[1], p[2], cm[i], eye[0],
                            eye[1], eye[2]);
            }
        }
        /* pvs_cull_map_test_box against its reference: visible if a cell its footprint meets holds a height <= its
           top (NaN too) or it leaves the region; cells met only within 1e-5 of a cell side may go either way. A box
           it calls hidden is hidden: sampled points of it are blocked from the eye. */
        for (i = 0; i < 60; ++i) {
            pvs_box b;
            double su = ((double)reg[2] - reg[0]) / w, sv = ((double)reg[3] - reg[1]) / h, a0, a1, b0, b1;
            int got, lo = 0, hi = 0, inside, s2;
            uint32_t ci, cj;
            b.min[0] = rndf(reg[0] - 3, reg[2]); b.max[0] = b.min[0] + rndf(0, 3);
            b.min[2] = rndf(reg[1] - 3, reg[3]); b.max[2] = b.min[2] + rndf(0, 3);
            b.min[1] = rndf(0, 6); b.max[1] = b.min[1] + rndf(0, 3);
            got = pvs_cull_map_test_box(r, &b);
            inside = b.min[0] >= reg[0] && b.max[0] <= reg[2] && b.min[2] >= reg[1] && b.max[2] <= reg[3];
            a0 = (b.min[0] - (double)reg[0]) / su; a1 = (b.max[0] - (double)reg[0]) / su;
            b0 = (b.min[2] - (double)reg[1]) / sv; b1 = (b.max[2] - (double)reg[1]) / sv;
            for (cj = 0; cj < h; ++cj)
                for (ci = 0; ci < w; ++ci) {
                    int under = !(cm[cj * w + ci] > b.max[1]);
                    hi |= under && ci + 1 >= a0 - 1e-5 && ci <= a1 + 1e-5 && cj + 1 >= b0 - 1e-5 && cj <= b1 + 1e-5;
                    lo |= under && ci + 1 > a0 + 1e-5 && ci < a1 - 1e-5 && cj + 1 > b0 + 1e-5 && cj < b1 - 1e-5;
                }
            ++box_tests;
            box_wrong += inside ? (lo && !got) || (got && !hi) : !got;
            if (got) continue;
            ++box_hidden;
            for (s2 = 0; s2 < 8; ++s2) {
                float q[3];
                int a3;
                for (a3 = 0; a3 < 3; ++a3) q[a3] = s2 < 4 ? ((s2 >> (a3 & 1)) & 1 ? b.max[a3] : b.min[a3]) : rndf(b.min[a3], b.max[a3]);
                box_seen += !pvs_scene_segment_blocked(fs, eye, q);
            }
        }
    }
    CHECK(box_wrong == 0 && box_seen == 0 && box_hidden > 50 && box_hidden < box_tests);
    if (box_wrong || box_seen || box_hidden <= 50 || box_hidden >= box_tests)
        fprintf(stderr, "cull map: %u of %u box tests wrong, %u of %u hidden boxes seen\n", box_wrong, box_tests, box_seen,
                box_hidden);
    {
        pvs_box b = {{0, 0, 0}, {1, 1, 1}};
        pvs_raster *r2;
        rd.cull_map_width = rd.cull_map_height = 0;
        CHECK(pvs_raster_create(&rd, &r2, &e) == PVS_OK && pvs_cull_map_test_box(r2, &b) == 1); /* no cull map */
        pvs_raster_destroy(r2);
    }
    CHECK(cells > 0);
    CHECK(blocked == samples);
    if (blocked != samples) fprintf(stderr, "cull map: %u of %u points under the map are visible\n", samples - blocked, samples);
    pvs_raster_destroy(r);
    pvs_scene_destroy(fs);
    mesh_free(&fm);
}

/* Closed chains built from the boxes' own footprints, and the same as scene occluders. */
static void test_cull_map_footprints(int scale) {
    tscene t;
    uint32_t up;
    for (up = 1; up <= 2; ++up) {
        int v = up == 2 ? 1 : 2;
        uint32_t o, n, nch = 0, c, misses = 0, hits = 0, culled[2] = {0, 0}, culled_py = 0, mode;
        pvs_occluder_desc *occ;
        pvs_facade_chain *ch;
        float *fp;
        if (!tscene_boxes(&t, 100, up)) { CHECK(0); return; }
        n = pvs_scene_object_count(t.scene);
        occ = (pvs_occluder_desc *)calloc(n, sizeof(pvs_occluder_desc));
        ch = (pvs_facade_chain *)calloc(n, sizeof(pvs_facade_chain));
        fp = (float *)calloc((size_t)n * 8, sizeof(float));
        for (o = 1; o < n; ++o) { /* object 0 is the ground */
            pvs_box b = pvs_scene_object_box(t.scene, o);
            float *q = fp + 8 * nch;
            if (b.min[up] != 0.0f) continue;
            q[0] = b.min[0]; q[1] = b.min[v]; q[2] = b.max[0]; q[3] = b.min[v];
            q[4] = b.max[0]; q[5] = b.max[v]; q[6] = b.min[0]; q[7] = b.max[v];
            if (nch % 3 == 0) { float s0 = q[2], s1 = q[3]; q[2] = q[6]; q[3] = q[7]; q[6] = s0; q[7] = s1; } /* other winding */
            ch[nch].points = q; ch[nch].point_count = 4; ch[nch].closed = 1; ch[nch].base = 0; ch[nch].top = b.max[up];
            if (nch % 2) { occ[nch].kind = PVS_OCCLUDER_BOX; occ[nch].box = b; }
            else { occ[nch].kind = PVS_OCCLUDER_EXTRUSION; occ[nch].footprint = q; occ[nch].footprint_count = 4; occ[nch].base = 0; occ[nch].top = b.max[up]; }
            ++nch;
        }
        /* the same scene again, with the footprints as explicit occluders */
        {
            tscene t2;
            pvs_raster_desc rd;
            pvs_raster *r;
            pvs_error e;
            pvs_word *vis = (pvs_word *)calloc(PVS_BITSET_WORDS(n), sizeof(pvs_word));
            memset(&t2, 0, sizeof(t2));
            mesh_init(&t2.m);
            mesh_cells_init(&t2.cells);
            t2.m = t.m; /* shares the arrays: only the scene is rebuilt */
            ts_occluders = occ;
            ts_occluder_count = nch;
            CHECK(tscene_make(&t2, up));
            ts_occluders = NULL;
            ts_occluder_count = 0;
            memset(&rd, 0, sizeof(rd));
            rd.width = 64; rd.height = 48; rd.scene = t2.scene; rd.cull_map_width = 100; rd.cull_map_height = 90;
            CHECK(pvs_raster_create(&rd, &r, &e) == PVS_OK);
            for (c = 0; c < 20 * (uint32_t)scale; ++c) {
                pvs_camera cam;
                random_camera(&t2, &cam, up);
                cam.fov_y = rndf(0.6f, 1.8f);
                for (mode = 0; mode < 2; ++mode) {
                    pvs_cull_params cp;
                    pvs_cull_stats st;
                    memset(&cp, 0, sizeof(cp));
                    if (mode == 0) { cp.facades = ch; cp.facade_count = nch; }
                    else cp.cull_map_flags = PVS_CULL_MAP_SCENE_OCCLUDERS;
                    CHECK(pvs_raster_cull_map(r, t2.scene, &cam, &cp, vis, &st, &e) == PVS_OK);
                    culled[mode] += n - st.visible;
                    misses += check_rays(&t2, &cam, 64.0f / 48.0f, vis, NULL, 200, &hits);
                }
                {   /* the depth pyramid with the same occluders as volumes (and no scene triangles) */
                    pvs_cull_params cp;
                    pvs_cull_stats st;
                    memset(&cp, 0, sizeof(cp));
                    cp.scene_volumes = 1;
                    cp.occluder_distance = 1000.0f;
                    if (rnd() < 0.3) cp.occluder_flags = PVS_CULL_SEPARATE_TRIANGLES; /* else as meshes */
                    CHECK(pvs_raster_cull(r, t2.scene, &cam, &cp, vis, &st, &e) == PVS_OK);
                    CHECK(st.occluder_triangles > 0);
                    culled_py += n - st.visible;
                    misses += check_rays(&t2, &cam, 64.0f / 48.0f, vis, NULL, 200, &hits);
                }
            }
            pvs_raster_destroy(r);
            pvs_scene_destroy(t2.scene);
            free(t2.chains);
            free(t2.chain_pts);
            free(vis);
        }
        CHECK(misses == 0);
        /* the same footprints either way (a seam may pick the other facade's plane: not bit-identical) */
        CHECK(culled[0] > 0 && culled[1] > 0);
        CHECK(culled[0] <= culled[1] + culled[1] / 10 + 5 && culled[1] <= culled[0] + culled[0] / 10 + 5);
        CHECK(culled_py > 0);
        free(occ); free(ch); free(fp);
        tscene_free(&t);
    }
}

/* ---- no allocation per frame, errors ---- */

/* The crack of issue 4 (realmaps repro raster_crack, extproj_fragmented): a wall in front of the
   camera as a grid of k x k quads (two triangles each) hides a box straight behind it when drawn as a
   mesh, per pixel and tiled, by pvs_raster_mesh and by pvs_raster_cull's caller triangles; drawn one
   triangle at a time, the diagonals' cracks leave it visible. */
static void test_mesh_crack(void) {
    static float pos[3 * 33 * 33];
    static uint32_t idx[6 * 32 * 32];
    pvs_box obj = {{10, -0.5f, -0.5f}, {11, 0.5f, 0.5f}};
    pvs_raster_desc rd;
    pvs_raster *r;
    pvs_error e;
    pvs_camera cam;
    float m[16];
    uint32_t k, i, j, tiled, hidden_mesh = 0, hidden_tri = 0, cases = 0;
    memset(&cam, 0, sizeof(cam));
    cam.forward[0] = 1; cam.up[1] = 1; cam.fov_y = 1.6f; cam.near_plane = 0.0125f;
    for (tiled = 0; tiled < 2; ++tiled) {
        memset(&rd, 0, sizeof(rd));
        rd.width = rd.height = 64; rd.flags = tiled ? PVS_RASTER_TILED : PVS_RASTER_PER_PIXEL;
        CHECK(pvs_raster_create(&rd, &r, &e) == PVS_OK);
        CHECK(pvs_camera_matrix(&cam, 1.0f, m) == PVS_OK);
        for (k = 1; k <= 32; k *= 2) {
            float S = k == 32 ? 100.0f : 1.0f; /* the last wall covers the whole view */
            uint32_t nt = 0;
            for (j = 0; j <= k; ++j)
                for (i = 0; i <= k; ++i) {
                    float *p = pos + 3 * (j * (k + 1) + i);
                    p[0] = 1.5f; p[1] = -S + 2.0f * S * (float)i / (float)k; p[2] = -S + 2.0f * S * (float)j / (float)k;
                }
            for (j = 0; j < k; ++j)
                for (i = 0; i < k; ++i) {
                    uint32_t a = j * (k + 1) + i, *t = idx + 3 * nt;
                    t[0] = a; t[1] = a + 1; t[2] = a + k + 2; t[3] = a; t[4] = a + k + 2; t[5] = a + k + 1;
                    nt += 2;
                }
            pvs_raster_clear(r); pvs_raster_set_matrix(r, m);
            pvs_raster_triangles(r, pos, (k + 1) * (k + 1), idx, nt, PVS_RASTER_OCCLUDER);
            hidden_tri += !pvs_raster_test_box(r, &obj);
            pvs_raster_clear(r); pvs_raster_set_matrix(r, m);
            CHECK(pvs_raster_mesh(r, pos, (k + 1) * (k + 1), idx, nt) == PVS_OK);
            hidden_mesh += !pvs_raster_test_box(r, &obj);
            ++cases;
        }
        pvs_raster_destroy(r);
    }
    CHECK(hidden_mesh == cases);
    CHECK(hidden_tri == 0); /* the crack the mesh closes (if this changes, the test needs a new case) */
    /* tiled, half the wall behind a nearer occluder: the triangles it hides are left out of the mesh pieces (the
       prefilter's), the crack in the other half still closes; pieces of 1 triangle are pieces of 4 */
    for (k = 0; k < 2; ++k) {
        float near_q[12] = {1.0f, -100, -100, 1.0f, 0, -100, 1.0f, 0, 100, 1.0f, -100, 100};
        uint32_t qi[6] = {0, 1, 2, 0, 2, 3}, nt = 0, n = 32;
        pvs_box seen = {{10, 0.5f, 0.5f}, {11, 0.9f, 0.9f}}, behind = {{10, -0.9f, -0.9f}, {11, -0.5f, -0.5f}};
        pvs_box front = {{1.2f, 0.3f, 0.3f}, {1.3f, 0.4f, 0.4f}};
        for (j = 0; j <= n; ++j)
            for (i = 0; i <= n; ++i) {
                float *p = pos + 3 * (j * (n + 1) + i);
                p[0] = 1.5f; p[1] = -100.0f + 200.0f * (float)i / (float)n; p[2] = -100.0f + 200.0f * (float)j / (float)n;
            }
        for (j = 0; j < n; ++j)
            for (i = 0; i < n; ++i) {
                uint32_t a = j * (n + 1) + i, *t = idx + 3 * nt;
                t[0] = a; t[1] = a + 1; t[2] = a + n + 2; t[3] = a; t[4] = a + n + 2; t[5] = a + n + 1;
                nt += 2;
            }
        memset(&rd, 0, sizeof(rd));
        rd.width = rd.height = 64; rd.flags = PVS_RASTER_TILED; rd.max_mesh_triangles = k ? 1 : 0;
        CHECK(pvs_raster_create(&rd, &r, &e) == PVS_OK);
        pvs_raster_clear(r); pvs_raster_set_matrix(r, m);
        pvs_raster_triangles(r, near_q, 4, qi, 2, PVS_RASTER_OCCLUDER);
        pvs_raster_triangles(r, pos, (n + 1) * (n + 1), idx, nt, PVS_RASTER_OCCLUDER);
        CHECK(pvs_raster_test_box(r, &seen)); /* the crack, one triangle at a time */
        pvs_raster_clear(r);
        pvs_raster_triangles(r, near_q, 4, qi, 2, PVS_RASTER_OCCLUDER);
        CHECK(pvs_raster_mesh(r, pos, (n + 1) * (n + 1), idx, nt) == PVS_OK);
        if (!k) CHECK(!pvs_raster_test_box(r, &seen)); /* closed */
        CHECK(!pvs_raster_test_box(r, &behind));
        CHECK(pvs_raster_test_box(r, &front));
        pvs_raster_destroy(r);
    }
    /* through pvs_raster_cull: a scene of one object box behind the wall, the wall as caller triangles */
    {
        tscene t;
        pvs_word vis[1];
        pvs_cull_params cp;
        pvs_cull_stats st;
        float wall[12] = {3, -50, -50, 3, 50, -50, 3, 50, 50, 3, -50, 50};
        uint32_t q[6] = {0, 1, 2, 0, 2, 3}, f;
        if (!tscene_boxes(&t, 1, 1)) { CHECK(0); return; }
        memset(&rd, 0, sizeof(rd));
        rd.width = 64; rd.height = 48; rd.scene = t.scene;
        CHECK(pvs_raster_create(&rd, &r, &e) == PVS_OK);
        {
            pvs_box b = pvs_scene_object_box(t.scene, 1);
            memset(&cam, 0, sizeof(cam));
            cam.eye[0] = b.min[0] - 10.0f; cam.eye[1] = 0.5f * (b.min[1] + b.max[1]); cam.eye[2] = 0.5f * (b.min[2] + b.max[2]);
            cam.forward[0] = 1; cam.up[1] = 1; cam.fov_y = 1.6f; cam.near_plane = 0.05f;
            for (i = 0; i < 4; ++i) { wall[3 * i] = cam.eye[0] + 3.0f; wall[3 * i + 1] += cam.eye[1]; wall[3 * i + 2] += cam.eye[2]; }
        }
        for (f = 0; f < 2; ++f) {
            memset(&cp, 0, sizeof(cp));
            cp.occluder_positions = wall; cp.occluder_vertex_count = 4; cp.occluder_indices = q; cp.occluder_triangle_count = 2;
            cp.occluder_flags = f ? PVS_CULL_OCCLUDER_MESH : 0;
            CHECK(pvs_raster_cull(r, t.scene, &cam, &cp, vis, &st, &e) == PVS_OK);
            CHECK(pvs_bitset_test(vis, 1) == (f ? 0 : 1)); /* object 1: the box (0 is the ground) */
        }
        pvs_raster_destroy(r);
        tscene_free(&t);
    }
}

static long ra_allocs;
static void *ra_alloc(size_t n, size_t align, void *user) { (void)align; (void)user; ++ra_allocs; return malloc(n); }
static void ra_free(void *p, size_t n, void *user) { (void)n; (void)user; free(p); }

static void test_noalloc_and_errors(void) {
    tscene t, big;
    pvs_raster_desc rd;
    pvs_raster *r, *rt;
    pvs_error e;
    pvs_word *vis;
    uint32_t k;
    long before;
    if (!tscene_boxes(&t, 40, 1)) { CHECK(0); return; }
    memset(&rd, 0, sizeof(rd));
    rd.width = 64; rd.height = 48; rd.scene = t.scene; rd.cull_map_width = 32; rd.cull_map_height = 32;
    rd.allocator.alloc = ra_alloc; rd.allocator.free = ra_free;
    CHECK(pvs_raster_create(&rd, &r, &e) == PVS_OK);
    rd.flags = PVS_RASTER_TILED; rd.bin_triangles = 4;
    CHECK(pvs_raster_create(&rd, &rt, &e) == PVS_OK);
    rd.flags = 0; rd.bin_triangles = 0;
    vis = (pvs_word *)calloc(PVS_BITSET_WORDS(pvs_scene_object_count(t.scene)), sizeof(pvs_word));
    before = ra_allocs;
    CHECK(before > 0);
    for (k = 0; k < 20; ++k) {
        pvs_camera cam;
        pvs_cull_params cp;
        float tri[9] = {-1, 0, 5, 1, 0, 5, 0, 2, 5};
        random_camera(&t, &cam, 1);
        memset(&cp, 0, sizeof(cp));
        cp.occluder_positions = tri; cp.occluder_vertex_count = 3; cp.occluder_triangle_count = 1;
        cp.scene_occluders = 100;
        cp.scene_volumes = 1;
        cp.occluder_flags = k & 1u ? PVS_CULL_SCENE_MESH | PVS_CULL_OCCLUDER_MESH : 0; /* the mesh paths too */
        cp.facades = t.chains; cp.facade_count = t.chain_count;
        CHECK(pvs_raster_cull(r, t.scene, &cam, &cp, vis, NULL, &e) == PVS_OK);
        CHECK(pvs_raster_cull_map(r, t.scene, &cam, &cp, vis, NULL, &e) == PVS_OK);
        CHECK(pvs_raster_test_rect(r, 0, 0, 10, 10, 0.5f) >= 0);
        CHECK(pvs_raster_cull(rt, t.scene, &cam, &cp, vis, NULL, &e) == PVS_OK);
        CHECK(pvs_raster_test_rect(rt, 0, 0, 10, 10, 0.5f) >= 0);
        CHECK(pvs_raster_depth(rt, NULL, NULL) != NULL);
        { /* pvs_raster_draw: culled, strided, as a mesh, with an engine's matrix */
            float wide[24] = {-1, 0, 5, 0, 1, 0, 5, 0, 0, 2, 5, 0, 0, 0, 6, 0, 3, 1, 6, 0, 0, 4, 6, 0};
            pvs_raster_draw_desc d = {wide, 16, 6, NULL, 2, PVS_RASTER_OCCLUDER, PVS_DRAW_MESH | PVS_DRAW_CULL_CW};
            float gl[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, -1, -1, 0, 0, -0.1f, 0};
            CHECK(pvs_raster_set_clip_matrix(rt, gl, PVS_CLIP_COLUMN_MAJOR | PVS_CLIP_DEPTH_MINUS_ONE_ONE) == PVS_OK);
            CHECK(pvs_raster_draw(rt, &d) == PVS_OK);
            d.flags = PVS_DRAW_CULL_CCW;
            CHECK(pvs_raster_draw(r, &d) == PVS_OK);
            { /* threads' calls: bins, bands (clears, draws, pyramids; on the untiled raster too) */
                pvs_raster_draw_desc two[2];
                uint32_t p;
                for (p = 0; p < PVS_RASTER_PARTS; ++p) pvs_raster_clear_band(rt, p), pvs_raster_clear_band(r, p);
                d.flags = PVS_DRAW_CULL_CW;
                two[0] = two[1] = d;
                for (p = 0; p < PVS_RASTER_PARTS; ++p) CHECK(pvs_raster_bin(rt, two, 2, p) == PVS_OK);
                for (p = 0; p < PVS_RASTER_PARTS; ++p) pvs_raster_draw_band(rt, two, 2, p);
                CHECK(pvs_raster_draw(r, two) == PVS_OK);
                for (p = 0; p <= PVS_RASTER_PARTS; ++p) pvs_raster_pyramid_band(rt, p), pvs_raster_pyramid_band(r, p);
                CHECK(pvs_raster_test_rect(rt, 0, 0, 10, 10, 0.5f) >= 0 && pvs_raster_test_rect(r, 0, 0, 10, 10, 0.5f) >= 0);
                pvs_raster_clear_band(NULL, 0), pvs_raster_clear_band(rt, PVS_RASTER_PARTS); /* nothing, no crash */
                pvs_raster_pyramid_band(NULL, 0), pvs_raster_pyramid_band(rt, PVS_RASTER_PARTS + 1);
                two[1].triangle_count = 3;
                CHECK(pvs_raster_bin(rt, two, 2, 0) == PVS_ERROR_BUFFER_TOO_SMALL);
            }
        }
    }
    CHECK(ra_allocs == before);
    pvs_raster_destroy(rt);
    /* errors */
    {
        pvs_camera cam;
        memset(&cam, 0, sizeof(cam));
        CHECK(pvs_raster_cull(r, t.scene, &cam, NULL, vis, NULL, &e) == PVS_ERROR_INVALID_ARGUMENT); /* near 0 */
        cam.near_plane = 0.1f; cam.forward[2] = 1; cam.up[1] = 1; cam.fov_y = 1;
        cam.eye[0] = NAN;
        CHECK(pvs_raster_cull(r, t.scene, &cam, NULL, vis, NULL, &e) == PVS_ERROR_NOT_FINITE);
        cam.eye[0] = 0;
        CHECK(pvs_raster_cull(r, NULL, &cam, NULL, vis, NULL, &e) == PVS_ERROR_INVALID_ARGUMENT);
        if (tscene_boxes(&big, 100, 1)) {
            CHECK(pvs_raster_cull(r, big.scene, &cam, NULL, vis, NULL, &e) == PVS_ERROR_BUFFER_TOO_SMALL);
            CHECK(pvs_raster_cull_map(r, big.scene, &cam, NULL, vis, NULL, &e) == PVS_ERROR_INVALID_ARGUMENT);
        }
        tscene_free(&big);
        CHECK(pvs_raster_cull(r, t.scene, &cam, NULL, vis, NULL, &e) == PVS_OK); /* no occluders: a frustum cull */
    }
    pvs_raster_destroy(r);
    memset(&rd, 0, sizeof(rd));
    CHECK(pvs_raster_create(&rd, &r, &e) == PVS_ERROR_INVALID_ARGUMENT && r == NULL);
    rd.width = 10; rd.height = 10; rd.cull_map_width = 10;
    CHECK(pvs_raster_create(&rd, &r, &e) == PVS_ERROR_INVALID_ARGUMENT);
    rd.cull_map_height = 10;
    CHECK(pvs_raster_create(&rd, &r, &e) == PVS_ERROR_INVALID_ARGUMENT); /* no scene */
    rd.cull_map_width = rd.cull_map_height = 0;
    CHECK(pvs_raster_create(&rd, &r, &e) == PVS_OK);
    {
        float m[16] = {0};
        m[0] = NAN;
        CHECK(pvs_raster_set_matrix(r, m) == PVS_ERROR_NOT_FINITE);
        CHECK(pvs_raster_triangles(r, NULL, 0, NULL, 1, PVS_RASTER_OCCLUDER) == PVS_ERROR_INVALID_ARGUMENT);
        CHECK(pvs_raster_triangles(r, m, 0, NULL, 0, PVS_RASTER_MODE_COUNT) == PVS_ERROR_INVALID_ARGUMENT);
        CHECK(pvs_cull_map(r, NULL, NULL, NULL) == NULL);
        CHECK(pvs_cull_map_build(r, m + 1, NULL, 0, 0) == PVS_ERROR_INVALID_ARGUMENT);
    }
    pvs_raster_destroy(r);
    pvs_raster_destroy(NULL);
    free(vis);
    tscene_free(&t);
}

void raster_verify_coverage(int scale);
void raster_verify_coverage(int scale) { test_coverage(scale); }
void raster_verify(int scale);
void raster_verify(int scale) {
    int k, n = (getenv("MESHN") ? atoi(getenv("MESHN")) : 60) * scale;
    for (k = 0; k < 2; ++k) {
        mode_flag = k ? PVS_RASTER_TILED : PVS_RASTER_PER_PIXEL;
        test_coverage(scale);
        test_mesh(scale, 23, 17, n);
        if (k) test_mesh(scale, 61, 45, n / 4), test_mesh_fast(scale);
        test_simd_identical(scale);
        test_boxes(scale);
        test_pyramid(scale);
    }
    test_cull_map_cells(scale);
    test_cull_map_footprints(scale);
    test_culling(scale);
}


/* pvs_raster_draw (issue 31): a vertex stride gives the packed draw's depth map bit for bit; back-face culling gives
   the map of the other-facing triangles drawn alone (facing from det(x, y, w) in double, triangles of uncertain
   facing left out of the case), as triangles and as a mesh, SIMD and scalar, per pixel and tiled; bad draws are
   refused. pvs_raster_set_clip_matrix: engine matrices (column-major, zero-one and minus-one-one depth) made from a
   raster matrix with exact float steps draw the same map; a real OpenGL and Direct3D projection hide a box behind a
   wall and view-cull one behind the eye. */
static float draw_det(const float m[16], const float *p) {
    double c[3][4], d;
    int k;
    for (k = 0; k < 3; ++k) clip_of(m, p + 3 * k, c[k]);
    d = c[0][0] * (c[1][1] * c[2][3] - c[2][1] * c[1][3]) - c[0][1] * (c[1][0] * c[2][3] - c[2][0] * c[1][3]) +
        c[0][3] * (c[1][0] * c[2][1] - c[2][0] * c[1][1]);
    return (float)d;
}

static void clip_wall_boxes(pvs_raster *r, const float m[16], uint32_t flags, int z_sign) {
    /* eye at the origin looking down z_sign * z: a wall at distance 10, boxes at 20 (hidden), 5 (seen), -5 (behind) */
    float wall[12] = {-50, -50, 0, 50, -50, 0, 50, 50, 0, -50, 50, 0};
    uint32_t idx[6] = {0, 1, 2, 0, 2, 3}, k;
    pvs_box far_box = {{-1, -1, 19}, {1, 1, 21}}, near_box = {{-1, -1, 4}, {1, 1, 6}}, back = {{-1, -1, -6}, {1, 1, -4}};
    for (k = 0; k < 4; ++k) wall[3 * k + 2] = 10.0f * (float)z_sign;
    if (z_sign < 0) {
        float t;
        t = far_box.min[2]; far_box.min[2] = -far_box.max[2]; far_box.max[2] = -t;
        t = near_box.min[2]; near_box.min[2] = -near_box.max[2]; near_box.max[2] = -t;
        t = back.min[2]; back.min[2] = -back.max[2]; back.max[2] = -t;
    }
    pvs_raster_clear(r);
    CHECK(pvs_raster_set_clip_matrix(r, m, flags) == PVS_OK);
    pvs_raster_mesh(r, wall, 4, idx, 2); /* no crack along the diagonal, through the boxes */
    CHECK(pvs_raster_classify_box(r, &far_box) == PVS_BOX_OCCLUDED);
    CHECK(pvs_raster_classify_box(r, &near_box) == PVS_BOX_VISIBLE);
    CHECK(pvs_raster_classify_box(r, &back) == PVS_BOX_VIEW_CULLED);
}

static void test_draw_options(void) {
    enum { W = 61, H = 43, N = 300 };
    pvs_raster_desc rd;
    pvs_raster *r, *ref;
    pvs_raster_draw_desc d;
    float *tris = (float *)malloc(N * 9 * sizeof(float)), *wide = (float *)malloc(N * 3 * 8 * sizeof(float));
    float *front = (float *)malloc(N * 9 * sizeof(float)), m[16];
    uint32_t cfg, k, t, n, nf;
    int same = 1, culled_some = 1;
    memset(&rd, 0, sizeof(rd));
    rd.width = W; rd.height = H;
    for (cfg = 0; cfg < 4; ++cfg) {
        rd.flags = (cfg & 1 ? PVS_RASTER_TILED : PVS_RASTER_PER_PIXEL) | (cfg & 2 ? PVS_RASTER_SCALAR : 0);
        CHECK(pvs_raster_create(&rd, &r, NULL) == PVS_OK);
        CHECK(pvs_raster_create(&rd, &ref, NULL) == PVS_OK);
        random_matrix(m, (float)W / H, (int)cfg % 3);
        for (n = t = 0; t < 4 * N && n < N; ++t) { /* definite facing only */
            float *p = tris + 9 * n, M = 0;
            random_triangle(p, (int)t % 3 == 1 ? 4 : 0);
            for (k = 0; k < 9; ++k) M = fabsf(p[k]) > M ? fabsf(p[k]) : M;
            if (fabsf(draw_det(m, p)) > 1e-3f * (1.0f + M * M * M)) ++n;
        }
        for (k = 0; k < 3 * n; ++k) { /* stride 32: x, y, z, then five floats of the caller's */
            memcpy(wide + 8 * k, tris + 3 * k, 3 * sizeof(float));
            wide[8 * k + 3] = wide[8 * k + 4] = NAN;
        }
        pvs_raster_set_matrix(r, m); pvs_raster_set_matrix(ref, m);
        for (k = 0; k < 6; ++k) { /* stride; cull CW, CCW; each as triangles, then as a mesh */
            uint32_t cull = k % 3 == 1 ? PVS_DRAW_CULL_CW : k % 3 == 2 ? PVS_DRAW_CULL_CCW : 0, as_mesh = k >= 3;
            memset(&d, 0, sizeof(d));
            d.positions = k % 3 ? tris : wide; d.stride = k % 3 ? 0 : 32; d.vertex_count = 3 * n;
            d.triangle_count = n; d.mode = PVS_RASTER_OCCLUDER; d.flags = cull | (as_mesh ? PVS_DRAW_MESH : 0);
            for (nf = t = 0; t < n; ++t) {
                float f = draw_det(m, tris + 9 * t);
                if (!cull || (cull == PVS_DRAW_CULL_CW ? f > 0 : f < 0)) memcpy(front + 9 * nf++, tris + 9 * t, 36);
            }
            culled_some &= !cull || (nf > 0 && nf < n);
            pvs_raster_clear(r); pvs_raster_clear(ref);
            CHECK(pvs_raster_draw(r, &d) == PVS_OK);
            if (as_mesh) pvs_raster_mesh(ref, front, 3 * nf, NULL, nf);
            else pvs_raster_triangles(ref, front, 3 * nf, NULL, nf, PVS_RASTER_OCCLUDER);
            same &= !memcmp(pvs_raster_depth(r, NULL, NULL), pvs_raster_depth(ref, NULL, NULL), W * H * sizeof(float));
        }
        for (k = 0; k < 6; ++k) { /* connected meshes (grids, flipped grids, boxes) culled, against their other-facing part */
            static tmesh tm;
            uint32_t fidx[3 * MESH_MAXT], ok = 1;
            random_mesh(&tm, k % 3 == 2 ? 5 : k % 3 == 1 ? 4 : 0);
            for (nf = t = 0; t < tm.nt; ++t) {
                float p[9], f;
                uint32_t c;
                for (c = 0; c < 9; ++c) p[c] = tm.pos[3 * tm.idx[3 * t + c / 3] + c % 3];
                f = draw_det(m, p);
                ok &= fabsf(f) > 1e-4f;
                if (k < 3 ? f < 0 : f > 0) memcpy(fidx + 3 * nf++, tm.idx + 3 * t, 3 * sizeof(uint32_t));
            }
            if (!ok) continue;
            memset(&d, 0, sizeof(d));
            d.positions = tm.pos; d.vertex_count = tm.nv; d.indices = tm.idx; d.triangle_count = tm.nt;
            d.flags = PVS_DRAW_MESH | (k < 3 ? PVS_DRAW_CULL_CCW : PVS_DRAW_CULL_CW);
            pvs_raster_clear(r); pvs_raster_clear(ref);
            CHECK(pvs_raster_draw(r, &d) == PVS_OK);
            pvs_raster_mesh(ref, tm.pos, tm.nv, fidx, nf);
            same &= !memcmp(pvs_raster_depth(r, NULL, NULL), pvs_raster_depth(ref, NULL, NULL), W * H * sizeof(float));
        }
        /* occludees with a stride */
        memset(&d, 0, sizeof(d));
        d.positions = wide; d.stride = 32; d.vertex_count = 3 * n; d.triangle_count = n; d.mode = PVS_RASTER_OCCLUDEE;
        pvs_raster_clear(r); pvs_raster_clear(ref);
        CHECK(pvs_raster_draw(r, &d) == PVS_OK);
        pvs_raster_triangles(ref, tris, 3 * n, NULL, n, PVS_RASTER_OCCLUDEE);
        same &= !memcmp(pvs_raster_depth(r, NULL, NULL), pvs_raster_depth(ref, NULL, NULL), W * H * sizeof(float));
        /* refused */
        CHECK(pvs_raster_draw(NULL, &d) == PVS_ERROR_INVALID_ARGUMENT);
        CHECK(pvs_raster_draw(r, NULL) == PVS_ERROR_INVALID_ARGUMENT);
        d.flags = PVS_DRAW_CULL_CW;
        CHECK(pvs_raster_draw(r, &d) == PVS_ERROR_INVALID_ARGUMENT); /* culling occludees */
        d.mode = PVS_RASTER_OCCLUDER; d.flags = PVS_DRAW_CULL_CW | PVS_DRAW_CULL_CCW;
        CHECK(pvs_raster_draw(r, &d) == PVS_ERROR_INVALID_ARGUMENT);
        d.flags = 8;
        CHECK(pvs_raster_draw(r, &d) == PVS_ERROR_INVALID_ARGUMENT);
        d.flags = 0; d.stride = 14;
        CHECK(pvs_raster_draw(r, &d) == PVS_ERROR_INVALID_ARGUMENT);
        d.stride = 8;
        CHECK(pvs_raster_draw(r, &d) == PVS_ERROR_INVALID_ARGUMENT);
        d.stride = 0; d.positions = NULL;
        CHECK(pvs_raster_draw(r, &d) == PVS_ERROR_INVALID_ARGUMENT);
        /* clip conventions from a matrix of exact steps: entries k / 4 */
        {
            float nat[16], eng[16], tr[16];
            uint32_t conv;
            for (k = 0; k < 16; ++k) nat[k] = (float)((int)(rnd() * 17) - 8) / 4.0f;
            nat[12] = nat[13] = 0; nat[14] = 1; nat[15] = 0.25f; /* w = z + 1/4 */
            for (conv = 0; conv < 6; ++conv) {
                uint32_t depth = conv % 3 == 1 ? PVS_CLIP_DEPTH_ZERO_ONE : conv % 3 == 2 ? PVS_CLIP_DEPTH_MINUS_ONE_ONE : 0;
                memcpy(eng, nat, sizeof(eng));
                for (t = 8; t < 12; ++t) /* z such that w - z (or (w - z) / 2) is the raster's */
                    eng[t] = depth == PVS_CLIP_DEPTH_ZERO_ONE ? nat[t + 4] - nat[t]
                           : depth ? nat[t + 4] - 2.0f * nat[t] : nat[t];
                for (t = 0; t < 16; ++t) tr[t] = conv >= 3 ? eng[4 * (t % 4) + t / 4] : eng[t];
                pvs_raster_clear(r); pvs_raster_clear(ref);
                CHECK(pvs_raster_set_clip_matrix(r, tr, depth | (conv >= 3 ? PVS_CLIP_COLUMN_MAJOR : 0)) == PVS_OK);
                pvs_raster_set_matrix(ref, nat);
                pvs_raster_triangles(r, tris, 3 * n, NULL, n, PVS_RASTER_OCCLUDER);
                pvs_raster_triangles(ref, tris, 3 * n, NULL, n, PVS_RASTER_OCCLUDER);
                same &= !memcmp(pvs_raster_depth(r, NULL, NULL), pvs_raster_depth(ref, NULL, NULL), W * H * sizeof(float));
            }
            CHECK(pvs_raster_set_clip_matrix(r, nat, PVS_CLIP_DEPTH_ZERO_ONE | PVS_CLIP_DEPTH_MINUS_ONE_ONE) ==
                  PVS_ERROR_INVALID_ARGUMENT);
            CHECK(pvs_raster_set_clip_matrix(r, nat, 8) == PVS_ERROR_INVALID_ARGUMENT);
            CHECK(pvs_raster_set_clip_matrix(NULL, nat, 0) == PVS_ERROR_INVALID_ARGUMENT);
            nat[5] = NAN;
            CHECK(pvs_raster_set_clip_matrix(r, nat, PVS_CLIP_COLUMN_MAJOR) == PVS_ERROR_NOT_FINITE);
        }
        { /* OpenGL: gluPerspective(90 degrees, near 0.5, far 100), eye looking down -z, column-major */
            float gl[16] = {0}, dx[16] = {0};
            float nr = 0.5f, fr = 100.0f;
            gl[0] = 1.0f; gl[5] = 1.0f; gl[10] = -(fr + nr) / (fr - nr); gl[11] = -1.0f; gl[14] = -2.0f * fr * nr / (fr - nr);
            clip_wall_boxes(r, gl, PVS_CLIP_COLUMN_MAJOR | PVS_CLIP_DEPTH_MINUS_ONE_ONE, -1);
            /* Direct3D: PerspectiveFovLH (looking down +z), clip = m * p row-major here */
            dx[0] = 1.0f; dx[5] = 1.0f; dx[10] = fr / (fr - nr); dx[11] = -nr * fr / (fr - nr); dx[14] = 1.0f;
            clip_wall_boxes(r, dx, PVS_CLIP_DEPTH_ZERO_ONE, 1);
        }
        pvs_raster_destroy(r);
        pvs_raster_destroy(ref);
    }
    CHECK(same);
    CHECK(culled_some);
    free(tris); free(wide); free(front);
}


/* Issue 31's defaults: all-zero params cull with the 64 best scene occluders within a tenth of the scene. The same
   city in metres and in centimetres (x 100): about as many objects left in both (before, the default 100 units
   selected nothing much in centimetres), fewer than the frustum alone (PVS_CULL_FRUSTUM_ONLY); ray casting finds no
   miss (check_rays). */
static void test_cull_units(void) {
    tscene a, b;
    pvs_raster_desc rd;
    pvs_raster *ra, *rb;
    pvs_word *va, *vb, *vf;
    uint32_t k, cam_i, na = 0, nb = 0, nf = 0, misses = 0, hits = 0;
    if (!tscene_gen(&a, GEN_CITY, 0.3f, 5)) { CHECK(0); return; }
    memset(&b, 0, sizeof(b));
    {
        gen_params gp = test_gen_params(GEN_CITY, 5, 0.3f, 0);
        if (test_generate(&gp, &b.m, &b.cells, NULL) != 0) { CHECK(0); tscene_free(&a); return; }
        for (k = 0; k < 3 * b.m.vertex_count; ++k) b.m.positions[k] *= 100.0f;
        for (k = 0; k < 6 * b.cells.count; ++k) b.cells.boxes[k] *= 100.0f;
        if (!tscene_make(&b, 1)) { CHECK(0); tscene_free(&a); return; }
    }
    memset(&rd, 0, sizeof(rd));
    rd.width = 160; rd.height = 90; rd.max_occluders = 64;
    rd.scene = a.scene;
    CHECK(pvs_raster_create(&rd, &ra, NULL) == PVS_OK);
    rd.scene = b.scene;
    CHECK(pvs_raster_create(&rd, &rb, NULL) == PVS_OK);
    k = pvs_scene_object_count(a.scene);
    va = (pvs_word *)calloc(PVS_BITSET_WORDS(k), sizeof(pvs_word));
    vb = (pvs_word *)calloc(PVS_BITSET_WORDS(k), sizeof(pvs_word));
    vf = (pvs_word *)calloc(PVS_BITSET_WORDS(k), sizeof(pvs_word));
    for (cam_i = 0; cam_i < 12; ++cam_i) {
        pvs_camera cm, cc;
        pvs_cull_params cp, none;
        uint32_t o;
        random_camera(&a, &cm, 1);
        cm.fov_y = 1.2f; /* perspective */
        cc = cm;
        for (o = 0; o < 3; ++o) cc.eye[o] *= 100.0f;
        cc.near_plane *= 100.0f;
        memset(&cp, 0, sizeof(cp));
        memset(&none, 0, sizeof(none));
        none.occluder_flags = PVS_CULL_FRUSTUM_ONLY;
        CHECK(pvs_raster_cull(ra, a.scene, &cm, &cp, va, NULL, NULL) == PVS_OK);
        CHECK(pvs_raster_cull(rb, b.scene, &cc, &cp, vb, NULL, NULL) == PVS_OK);
        CHECK(pvs_raster_cull(rb, b.scene, &cc, &none, vf, NULL, NULL) == PVS_OK);
        misses += check_rays(&b, &cc, 160.0f / 90.0f, vb, NULL, 2000, &hits);
        for (o = 0; o < k; ++o) {
            na += pvs_bitset_test(va, o);
            nb += pvs_bitset_test(vb, o);
            nf += pvs_bitset_test(vf, o);
        }
    }
    fprintf(stderr, "  cull units: %u objects left in metres, %u in centimetres, %u in the frustum\n", na, nb, nf);
    CHECK(misses == 0);
    CHECK(nb <= na + na / 10 + 12 && 10 * nb < 9 * nf);
    free(va); free(vb); free(vf);
    pvs_raster_destroy(ra);
    pvs_raster_destroy(rb);
    tscene_free(&a);
    tscene_free(&b);
}

/* Threads (pvs_raster_clear_band, _bin, _draw_band, _pyramid_band): several draws (strided, indexed, culled, with
   triangles across the near plane) over the last frame's map, cleared, binned, drawn and reduced to the pyramid in
   bands in shuffled orders and on two threads, give the map pvs_raster_draw gives, byte for byte, and a pyramid whose
   every rectangle test is brute force's over the map, on SIMD and scalar rasters; bad draws are refused. */
typedef struct band_job { pvs_raster *r; const pvs_raster_draw_desc *d; uint32_t first, ok, phase; } band_job;
static void *band_thread(void *arg) { /* phase 0: clear, 1: bin, 2: draw, 3: pyramid */
    band_job *j = (band_job *)arg;
    uint32_t p;
    for (p = j->first; p < PVS_RASTER_PARTS; p += 2)
        if (j->phase == 0) pvs_raster_clear_band(j->r, p);
        else if (j->phase == 1) j->ok &= pvs_raster_bin(j->r, j->d, 3, p) == PVS_OK;
        else if (j->phase == 2) pvs_raster_draw_band(j->r, j->d, 3, p);
        else pvs_raster_pyramid_band(j->r, p);
    return NULL;
}
static void band_phase(band_job *jb, uint32_t phase) {
    pthread_t th[2];
    uint32_t k;
    for (k = 0; k < 2; ++k) jb[k].phase = phase, pthread_create(th + k, NULL, band_thread, jb + k);
    for (k = 0; k < 2; ++k) pthread_join(th[k], NULL);
}
/* The pyramid's answers to rectangles over the map, at depths from it, are brute force's over the map. */
static int pyramid_right(pvs_raster *r, uint32_t w, uint32_t h) {
    const float *dm = pvs_raster_depth(r, NULL, NULL);
    int same = 1, k;
    for (k = 0; k < 2000; ++k) { /* sides of 1 to 128 pixels, whole texels of the levels or not */
        int32_t sx = 1 << k % 8, sy = 1 << (k / 8) % 8, al = k % 3 != 0, x, y, seen = 0;
        int32_t x0 = ((int32_t)(rnd() * (w + 4)) - 2) & (al ? -sx : -1), y0 = ((int32_t)(rnd() * (h + 4)) - 2) & (al ? -sy : -1);
        float z = dm[(uint32_t)(rnd() * w) % w + (uint32_t)(rnd() * h) % h * w] * (k % 2 ? 1.0f : 0.999f);
        int32_t x1 = x0 + sx - al, y1 = y0 + sy - al;
        for (y = y0 > 0 ? y0 : 0; y <= y1 && y < (int32_t)h; ++y)
            for (x = x0 > 0 ? x0 : 0; x <= x1 && x < (int32_t)w; ++x) seen |= dm[(uint32_t)y * w + (uint32_t)x] <= z;
        same &= pvs_raster_test_rect(r, x0, y0, x1, y1, z) == seen;
    }
    return same;
}
static void test_threads(void) {
    enum { N = 400 };
    static const uint32_t sizes[3][2] = {{61, 43}, {320, 200}, {7, 300}};
    pvs_raster_desc rd;
    pvs_raster *r, *ref;
    pvs_raster_draw_desc d[3];
    float *tris = (float *)malloc(N * 9 * sizeof(float)), *wide = (float *)malloc(N * 3 * 8 * sizeof(float)), m[16];
    uint32_t *idx = (uint32_t *)malloc(N * 3 * sizeof(uint32_t)), cfg, k, rep, order[PVS_RASTER_PARTS];
    int same = 1, drew = 0;
    for (cfg = 0; cfg < 6; ++cfg) {
        memset(&rd, 0, sizeof(rd));
        rd.width = sizes[cfg % 3][0]; rd.height = sizes[cfg % 3][1];
        rd.flags = PVS_RASTER_TILED | (cfg >= 3 ? PVS_RASTER_SCALAR : 0);
        CHECK(pvs_raster_create(&rd, &ref, NULL) == PVS_OK);
        rd.bin_triangles = 3 * N;
        CHECK(pvs_raster_create(&rd, &r, NULL) == PVS_OK);
        for (rep = 0; rep < 8; ++rep) {
            band_job jb[2];
            random_matrix(m, (float)rd.width / rd.height, (int)rep % 3);
            for (k = 0; k < N; ++k) random_triangle(tris + 9 * k, (int)(k % 5) == 4 ? 2 : (int)(k % 5) == 3 ? 4 : 0);
            for (k = 0; k < 3 * N; ++k) {
                memcpy(wide + 8 * k, tris + 3 * k, 3 * sizeof(float));
                wide[8 * k + 3] = NAN;
                idx[k] = (uint32_t)(rnd() * 3 * N) % (3 * N);
            }
            memset(d, 0, sizeof(d));
            d[0].positions = tris; d[0].vertex_count = 3 * N; d[0].triangle_count = N; /* as pvs_raster_triangles */
            d[1].positions = wide; d[1].stride = 32; d[1].vertex_count = 3 * N; d[1].indices = idx;
            d[1].triangle_count = N / 2 + rep; d[1].flags = rep & 1 ? PVS_DRAW_CULL_CW : PVS_DRAW_CULL_CCW;
            d[2].positions = tris + 9 * (rep % 7); d[2].vertex_count = 7 + rep; d[2].triangle_count = 3 + rep % 3;
            pvs_raster_set_matrix(r, m); pvs_raster_set_matrix(ref, m);
            pvs_raster_clear(ref);
            for (k = 0; k < 3; ++k) CHECK(pvs_raster_draw(ref, d + k) == PVS_OK);
            pvs_raster_build_pyramid(ref);
            for (k = 0; k < PVS_RASTER_PARTS; ++k) order[k] = k;
            for (k = PVS_RASTER_PARTS - 1; k > 0; --k) { /* shuffled */
                uint32_t j = (uint32_t)(rnd() * (k + 1)) % (k + 1), t = order[k];
                order[k] = order[j]; order[j] = t;
            }
            for (k = 0; k < 2; ++k) jb[k].r = r, jb[k].d = d, jb[k].first = k, jb[k].ok = 1;
            if (rep % 4 == 1) pvs_raster_clear(r);
            else if (rep % 2) /* the last frame's map, cleared in bands */
                for (k = 0; k < PVS_RASTER_PARTS; ++k) pvs_raster_clear_band(r, order[k]);
            else band_phase(jb, 0);
            if (rep % 4 == 3) { /* two rounds: the first draw, then the others (their bins drop what it hides) */
                for (k = 0; k < PVS_RASTER_PARTS; ++k) CHECK(pvs_raster_bin(r, d, 1, order[k]) == PVS_OK);
                for (k = 0; k < PVS_RASTER_PARTS; ++k) pvs_raster_draw_band(r, d, 1, order[PVS_RASTER_PARTS - 1 - k]);
                for (k = 0; k < PVS_RASTER_PARTS; ++k) CHECK(pvs_raster_bin(r, d + 1, 2, order[k]) == PVS_OK);
                for (k = 0; k < PVS_RASTER_PARTS; ++k) pvs_raster_draw_band(r, d + 1, 2, order[k]);
            } else if (rep % 2) {
                for (k = 0; k < PVS_RASTER_PARTS; ++k) CHECK(pvs_raster_bin(r, d, 3, order[k]) == PVS_OK);
                for (k = 0; k < PVS_RASTER_PARTS; ++k) pvs_raster_draw_band(r, d, 3, order[PVS_RASTER_PARTS - 1 - k]);
            } else { /* two threads */
                band_phase(jb, 1);
                CHECK(jb[0].ok && jb[1].ok);
                band_phase(jb, 2);
            }
            if (rep % 2) { /* the pyramid in bands, then its top */
                for (k = 0; k < PVS_RASTER_PARTS; ++k) pvs_raster_pyramid_band(r, order[k]);
                pvs_raster_pyramid_band(r, PVS_RASTER_PARTS);
            } else if (rep % 4) {
                band_phase(jb, 3);
                pvs_raster_pyramid_band(r, PVS_RASTER_PARTS);
            } else if (rep == 4) { /* misuse: the top after half the bands makes the others (rep 0: test_rect builds it) */
                for (k = 0; k < PVS_RASTER_PARTS / 2; ++k) pvs_raster_pyramid_band(r, order[k]);
                pvs_raster_pyramid_band(r, PVS_RASTER_PARTS);
            }
            {
                const float *dm = pvs_raster_depth(r, NULL, NULL);
                same &= !memcmp(dm, pvs_raster_depth(ref, NULL, NULL), (size_t)rd.width * rd.height * sizeof(float));
                for (k = 0; k < rd.width * rd.height; ++k) drew |= dm[k] != PVS_DEPTH_EMPTY;
                same &= pyramid_right(r, rd.width, rd.height) && pyramid_right(ref, rd.width, rd.height);
            }
        }
        /* misuse, the pyramid still right: the bands' pyramid, then more drawn (directly, in bands after a clear or in
           a second round) or only a clear, then the top alone: draws and clears forget the bands' pyramid */
        for (k = 0; k < PVS_RASTER_PARTS; ++k) pvs_raster_pyramid_band(r, k);
        CHECK(pvs_raster_draw(r, d + 1) == PVS_OK);
        pvs_raster_pyramid_band(r, PVS_RASTER_PARTS);
        same &= pyramid_right(r, rd.width, rd.height);
        for (k = 0; k < PVS_RASTER_PARTS; ++k) pvs_raster_pyramid_band(r, k);
        for (k = 0; k < PVS_RASTER_PARTS; ++k) pvs_raster_clear_band(r, k);
        for (k = 0; k < PVS_RASTER_PARTS; ++k) CHECK(pvs_raster_bin(r, d, 1, k) == PVS_OK);
        for (k = 0; k < PVS_RASTER_PARTS; ++k) pvs_raster_draw_band(r, d, 1, k);
        pvs_raster_pyramid_band(r, PVS_RASTER_PARTS);
        same &= pyramid_right(r, rd.width, rd.height);
        for (k = 0; k < PVS_RASTER_PARTS; ++k) pvs_raster_pyramid_band(r, k);
        for (k = 0; k < PVS_RASTER_PARTS; ++k) CHECK(pvs_raster_bin(r, d + 1, 1, k) == PVS_OK);
        for (k = 0; k < PVS_RASTER_PARTS; ++k) pvs_raster_draw_band(r, d + 1, 1, k); /* a second round, no clear */
        pvs_raster_pyramid_band(r, PVS_RASTER_PARTS);
        same &= pyramid_right(r, rd.width, rd.height);
        for (k = 0; k < PVS_RASTER_PARTS; ++k) pvs_raster_pyramid_band(r, k);
        pvs_raster_clear(r); /* nothing drawn after */
        pvs_raster_pyramid_band(r, PVS_RASTER_PARTS);
        same &= pyramid_right(r, rd.width, rd.height);
        /* a bin that fails leaves its part empty: the bands then draw nothing of the earlier bins */
        pvs_raster_clear(r);
        for (k = 0; k < PVS_RASTER_PARTS; ++k) CHECK(pvs_raster_bin(r, d, 3, k) == PVS_OK);
        d[0].flags = PVS_DRAW_MESH;
        for (k = 0; k < PVS_RASTER_PARTS; ++k) CHECK(pvs_raster_bin(r, d, 3, k) == PVS_ERROR_INVALID_ARGUMENT);
        d[0].flags = 0;
        for (k = 0; k < PVS_RASTER_PARTS; ++k) pvs_raster_draw_band(r, d, 3, k);
        {
            const float *dm = pvs_raster_depth(r, NULL, NULL);
            for (k = 0; k < rd.width * rd.height; ++k) same &= dm[k] == PVS_DEPTH_EMPTY;
        }
        /* refused: too many triangles, meshes, occludees, bad strides, bad parts, untiled or binless rasters */
        pvs_raster_clear(r);
        d[0].triangle_count = 3 * N + 1;
        CHECK(pvs_raster_bin(r, d, 1, 0) == PVS_ERROR_BUFFER_TOO_SMALL);
        d[0].triangle_count = N; d[0].flags = PVS_DRAW_MESH;
        CHECK(pvs_raster_bin(r, d, 3, 1) == PVS_ERROR_INVALID_ARGUMENT);
        d[0].flags = 0; d[0].mode = PVS_RASTER_OCCLUDEE;
        CHECK(pvs_raster_bin(r, d, 3, 2) == PVS_ERROR_INVALID_ARGUMENT);
        d[0].mode = PVS_RASTER_OCCLUDER; d[0].stride = 6;
        CHECK(pvs_raster_bin(r, d, 3, 3) == PVS_ERROR_INVALID_ARGUMENT);
        d[0].stride = 0;
        CHECK(pvs_raster_bin(NULL, d, 3, 0) == PVS_ERROR_INVALID_ARGUMENT);
        CHECK(pvs_raster_bin(r, NULL, 3, 0) == PVS_ERROR_INVALID_ARGUMENT);
        CHECK(pvs_raster_bin(r, d, 3, PVS_RASTER_PARTS) == PVS_ERROR_INVALID_ARGUMENT);
        CHECK(pvs_raster_bin(ref, d, 3, 0) == PVS_ERROR_BUFFER_TOO_SMALL);
        CHECK(pvs_raster_bin(ref, d, 0, 0) == PVS_OK); /* nothing to bin */
        pvs_raster_draw_band(ref, d, 3, 0); pvs_raster_draw_band(r, d, 3, PVS_RASTER_PARTS); /* nothing, no crash */
        {
            const float *dm = pvs_raster_depth(r, NULL, NULL);
            for (k = 0; k < rd.width * rd.height; ++k) same &= dm[k] == PVS_DEPTH_EMPTY;
        }
        pvs_raster_destroy(r);
        rd.flags = PVS_RASTER_PER_PIXEL;
        CHECK(pvs_raster_create(&rd, &r, NULL) == PVS_OK);
        CHECK(pvs_raster_bin(r, d, 3, 0) == PVS_ERROR_INVALID_ARGUMENT);
        pvs_raster_destroy(r);
        pvs_raster_destroy(ref);
    }
    CHECK(same);
    CHECK(drew);
    free(tris); free(wide); free(idx);
}

/* The paths agree bit for bit (issue 31): the best one (AVX2 where the CPU has it), PVS_RASTER_SSE2 and
   PVS_RASTER_SCALAR draw the same maps (per pixel and tiled; triangles, back faces culled, meshes; occludees) and
   classify the same boxes; pvs_raster_path names each. */
static void test_paths(void) {
    enum { W = 97, H = 61, N = 600, NO = 450, NB = 400 };
    static const uint32_t flags[3] = {0, PVS_RASTER_SSE2, PVS_RASTER_SCALAR};
    pvs_raster_desc rd;
    pvs_raster *r[3];
    pvs_box *boxes = (pvs_box *)malloc(NB * sizeof(pvs_box));
    float *tris = (float *)malloc(N * 9 * sizeof(float)), m[16];
    uint32_t cfg, p, k, t, seen = 0, hidden = 0, drawn = 0;
    int same = 1;
    for (cfg = 0; cfg < 12; ++cfg) {
        memset(&rd, 0, sizeof(rd));
        rd.width = W; rd.height = H;
        for (p = 0; p < 3; ++p) {
            rd.flags = flags[p] | (cfg & 1 ? PVS_RASTER_TILED : PVS_RASTER_PER_PIXEL);
            CHECK(pvs_raster_create(&rd, &r[p], NULL) == PVS_OK);
        }
        CHECK(!strcmp(pvs_raster_path(r[2]), "scalar"));
#if defined(__x86_64__) && defined(__GNUC__) && !defined(PVS_NO_SIMD)
        CHECK(!strcmp(pvs_raster_path(r[0]), __builtin_cpu_supports("avx2") ? "avx2" : "sse2"));
        CHECK(!strcmp(pvs_raster_path(r[1]), "sse2") || !strcmp(pvs_raster_path(r[1]), "avx2")); /* -mavx2: both */
#endif
        random_matrix(m, (float)W / H, (int)cfg % 3);
        for (t = 0; t < N; ++t) random_triangle(tris + 9 * t, (int)(t % 5));
        for (k = 0; k < NB; ++k) {
            float h = rndf(0.01f, 2.0f);
            for (t = 0; t < 3; ++t) {
                boxes[k].min[t] = rndf(-8, 8);
                boxes[k].max[t] = boxes[k].min[t] + h;
            }
        }
        for (p = 0; p < 3; ++p) {
            pvs_raster_draw_desc d = {tris, 0, 3 * NO, NULL, NO, PVS_RASTER_OCCLUDER, 0};
            d.triangle_count = NO - cfg % 7; /* last eight-lane group of 2, 1, 8, 7, 6, 5, 4 triangles */
            d.flags = cfg & 2 ? PVS_DRAW_MESH : cfg & 4 ? PVS_DRAW_CULL_CW : 0;
            pvs_raster_clear(r[p]);
            CHECK(pvs_raster_set_matrix(r[p], m) == PVS_OK);
            CHECK(pvs_raster_draw(r[p], &d) == PVS_OK);
            if (cfg >= 8) { /* and occludees */
                d.positions = tris + 9 * NO, d.vertex_count = d.triangle_count = N - NO, d.indices = NULL;
                d.vertex_count *= 3, d.mode = PVS_RASTER_OCCLUDEE, d.flags = 0;
                CHECK(pvs_raster_draw(r[p], &d) == PVS_OK);
            }
        }
        for (p = 1; p < 3; ++p)
            same &= !memcmp(pvs_raster_depth(r[0], NULL, NULL), pvs_raster_depth(r[p], NULL, NULL), W * H * sizeof(float));
        for (k = 0; k < W * H; ++k) drawn += pvs_raster_depth(r[0], NULL, NULL)[k] != PVS_DEPTH_EMPTY;
        for (k = 0; k < NB; ++k) {
            int c = pvs_raster_classify_box(r[0], boxes + k);
            seen += c == PVS_BOX_VISIBLE, hidden += c == PVS_BOX_OCCLUDED;
            for (p = 1; p < 3; ++p) same &= pvs_raster_classify_box(r[p], boxes + k) == c;
        }
        for (p = 0; p < 3; ++p) pvs_raster_destroy(r[p]);
    }
    CHECK(same || !SAME_BITS);
    CHECK(drawn > 1000 && seen > 100 && hidden > 100); /* not vacuous */
    free(tris); free(boxes);
}

/* Occluders across the near plane still occlude on every path (the prefilter drops only those past a side plane): a
   side wall and a floor reaching behind the eye hide a box behind each; a third quad, behind and off to the side, is
   dropped; a box in the open stays visible. */
static void test_near_walls(void) {
    static const float quads[3][4][3] = {{{-20, -20, 1}, {40, -20, 1}, {40, 20, 1}, {-20, 20, 1}},
                                         {{-20, -1, -20}, {40, -1, -20}, {40, -1, 20}, {-20, -1, 20}},
                                         {{-20, -5, -200}, {-1, -5, -200}, {-1, 5, -300}, {-20, 5, -300}}};
    static const uint32_t idx[6] = {0, 1, 2, 0, 2, 3};
    /* hidden boxes past the quads' far ends (tiles keep the farthest depth) and off their diagonals (cracks) */
    pvs_box behind_wall = {{60, -0.5f, 20}, {61, 0.5f, 22}}, below_floor = {{60, -5, -6}, {61, -4, -5}};
    pvs_box open = {{20, 2, -1}, {21, 3, 0}};
    pvs_raster_desc rd;
    pvs_raster *r;
    pvs_camera cam;
    float m[16];
    uint32_t cfg, q;
    memset(&cam, 0, sizeof(cam));
    cam.forward[0] = 1; cam.up[1] = 1; cam.fov_y = 1.6f; cam.near_plane = 0.0125f;
    CHECK(pvs_camera_matrix(&cam, 1.5f, m) == PVS_OK);
    for (cfg = 0; cfg < 6; ++cfg) {
        memset(&rd, 0, sizeof(rd));
        rd.width = 96; rd.height = 64;
        rd.flags = (cfg & 1 ? PVS_RASTER_TILED : PVS_RASTER_PER_PIXEL) | (cfg / 2 == 1 ? PVS_RASTER_SSE2 : 0) |
                   (cfg / 2 == 2 ? PVS_RASTER_SCALAR : 0);
        CHECK(pvs_raster_create(&rd, &r, NULL) == PVS_OK);
        pvs_raster_set_matrix(r, m);
        pvs_raster_clear(r);
        for (q = 0; q < 3; ++q) pvs_raster_triangles(r, &quads[q][0][0], 4, idx, 2, PVS_RASTER_OCCLUDER);
        CHECK(pvs_raster_classify_box(r, &behind_wall) == PVS_BOX_OCCLUDED);
        CHECK(pvs_raster_classify_box(r, &below_floor) == PVS_BOX_OCCLUDED);
        CHECK(pvs_raster_classify_box(r, &open) == PVS_BOX_VISIBLE);
        pvs_raster_destroy(r);
    }
}

void test_raster(void);
void test_raster(void) {
    test_near_walls();
    raster_verify(1);
    test_mesh_crack();
    test_draw_options();
    test_paths();
    test_threads();
    test_cull_units();
    test_noalloc_and_errors();
}
