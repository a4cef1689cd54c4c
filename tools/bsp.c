/* bsp.c - Quake 3 BSP (IBSP 46) reader: surfaces, brush hulls, leaf cells, the level's PVS. See bsp.h.
   The layout follows id Software's qfiles.h (GPL Quake III Arena source), read byte by byte here so
   that the host's endianness and struct padding do not matter. */
#include "bsp.h"
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <ctype.h>

enum { L_SHADERS = 1, L_PLANES = 2, L_NODES = 3, L_LEAFS = 4, L_LEAFSURFACES = 5, L_MODELS = 7, L_BRUSHES = 8,
       L_BRUSHSIDES = 9, L_DRAWVERTS = 10, L_DRAWINDEXES = 11, L_SURFACES = 13, L_VISIBILITY = 16, L_COUNT = 17 };
static const char *const lump_names[L_COUNT] = {"entities", "shaders", "planes", "nodes", "leafs", "leafsurfaces",
                                                "leafbrushes", "models", "brushes", "brushsides", "drawverts",
                                                "drawindexes", "fogs", "surfaces", "lightmaps", "lightgrid",
                                                "visibility"};
/* record sizes of the lumps read (0: not read as records) */
static const uint32_t lump_sizes[L_COUNT] = {0, 72, 16, 36, 48, 4, 4, 40, 12, 8, 44, 4, 72, 104, 0, 0, 0};

enum { MST_PLANAR = 1, MST_PATCH = 2, MST_TRIANGLE_SOUP = 3, MST_FLARE = 4 };
#define CONTENTS_SOLID 1u
#define CONTENTS_SEE_THROUGH (8u | 16u | 32u | 64u | 0x20000000u) /* lava slime water fog translucent */
#define SURF_NODRAW 0x80u
#define SURF_SKY 0x4u
#define BSP_LIFT 0.01 /* game units a planar surface is lifted off its brush face, along its normal: the hulls stay
                        exact (touching brushes leave no crack) and never hide the surface drawn on them */
#define BSP_WELD 1e-3 /* a brush's corners closer than this are one vertex (one plane triple, rounded apart) */
#define BSP_MAX_VERTICES (1u << 26) /* the scene's vertices: a bound on what patches may expand to */

typedef struct bsp_lump {
    const uint8_t *p;
    uint32_t count;           /* records */
} bsp_lump;

typedef struct bsp_reader {
    const char *path;
    uint32_t cell_step;      /* >= 1 */
    bsp_lump l[L_COUNT];
    tool_error *err;
    uint8_t *in_world;       /* per leaf: reached from node 0, the world's tree (all when there are no nodes) */
} bsp_reader;

static int32_t rd_i32(const uint8_t *p) {
    uint32_t u = tool_get32(p);
    return u <= 0x7fffffffu ? (int32_t)u : -(int32_t)(~u) - 1;
}
static float rd_f32(const uint8_t *p) {
    uint32_t u = tool_get32(p);
    float f;
    memcpy(&f, &u, 4);
    return f;
}
static const uint8_t *rec(const bsp_reader *r, int lump, uint32_t i) {
    return r->l[lump].p + (size_t)i * lump_sizes[lump];
}

/* first..first+count must lie in [0, limit): 0, or -1 with the message. */
static int check_range(const bsp_reader *r, int lump, uint32_t i, const char *what, int32_t first, int32_t count,
                       uint32_t limit, const char *of) {
    if (first >= 0 && count >= 0 && (uint64_t)first + (uint64_t)count <= limit) return 0;
    tool_error_set(r->err, r->path, 0, "%s[%u]: %s range %d+%d past the %u %s", lump_names[lump], i, what, first,
                   count, limit, of);
    return -1;
}
static int check_index(const bsp_reader *r, int lump, uint32_t i, const char *what, int32_t v, uint32_t limit) {
    if (v >= 0 && (uint32_t)v < limit) return 0;
    tool_error_set(r->err, r->path, 0, "%s[%u]: %s %d not in [0, %u)", lump_names[lump], i, what, v, limit);
    return -1;
}

static int read_header(bsp_reader *r, const uint8_t *d, size_t size) {
    if (size < 8 + 8 * L_COUNT) {
        tool_error_set(r->err, r->path, 0, "%zu bytes: too short for a BSP header (%d)", size, 8 + 8 * L_COUNT);
        return -1;
    }
    if (memcmp(d, "IBSP", 4)) {
        tool_error_set(r->err, r->path, 0, "not a Quake 3 BSP file (magic \"%.4s\", expected \"IBSP\")", (const char *)d);
        return -1;
    }
    if (tool_get32(d + 4) != 46) {
        tool_error_set(r->err, r->path, 0, "BSP version %u: only version 46 (Quake III Arena) is read", tool_get32(d + 4));
        return -1;
    }
    for (int i = 0; i < L_COUNT; ++i) {
        uint32_t off = tool_get32(d + 8 + 8 * i), len = tool_get32(d + 12 + 8 * i);
        if ((uint64_t)off + len > size) {
            tool_error_set(r->err, r->path, 0, "lump %d (%s): bytes %u+%u past the end of the file (%zu bytes)", i,
                           lump_names[i], off, len, size);
            return -1;
        }
        if (lump_sizes[i] && len % lump_sizes[i]) {
            tool_error_set(r->err, r->path, 0, "lump %d (%s): %u bytes, not a whole number of %u-byte records", i,
                           lump_names[i], len, lump_sizes[i]);
            return -1;
        }
        r->l[i].p = d + off;
        r->l[i].count = lump_sizes[i] ? len / lump_sizes[i] : len;
    }
    if (r->l[L_MODELS].count == 0) {
        tool_error_set(r->err, r->path, 0, "lump 7 (models): empty (a level has at least the world model)");
        return -1;
    }
    return 0;
}

/* Quake Z-up to the tools' Y-up. */
static void to_y_up(const float q[3], float out[3]) {
    out[0] = q[0];
    out[1] = q[2];
    out[2] = -q[1];
}

static int finite3(const float v[3]) { return isfinite(v[0]) && isfinite(v[1]) && isfinite(v[2]); }

/* Adds drawvert `vertex`, moved by `lift` (NULL: not moved). */
static int add_vertex(const bsp_reader *r, mesh *m, uint32_t vertex, const double *lift, tool_error *err) {
    const uint8_t *v = rec(r, L_DRAWVERTS, vertex);
    float q[3] = {rd_f32(v), rd_f32(v + 4), rd_f32(v + 8)}, y[3];
    if (!finite3(q)) {
        tool_error_set(err, r->path, 0, "drawverts[%u]: position is not finite", vertex);
        return -1;
    }
    if (lift)
        for (int k = 0; k < 3; ++k) q[k] = (float)(q[k] + lift[k]);
    to_y_up(q, y);
    if (mesh_add_vertex(m, y[0], y[1], y[2])) {
        tool_error_set(err, r->path, 0, "out of memory");
        return -1;
    }
    return 0;
}

/* Planar surfaces and triangle soups: their vertices and index triples (Quake's winding). A planar surface lies
   on a brush face: it is lifted BSP_LIFT along its normal (the record's lightmap normal, when a unit vector). */
static int add_triangles(const bsp_reader *r, uint32_t s, const uint8_t *f, int flip, mesh *m, tool_error *err) {
    float nf[3] = {rd_f32(f + 84), rd_f32(f + 88), rd_f32(f + 92)};
    double lift[3], len = finite3(nf) ? sqrt((double)nf[0] * nf[0] + (double)nf[1] * nf[1] + (double)nf[2] * nf[2]) : 0;
    int lifted = rd_i32(f + 8) == MST_PLANAR && len > 0.99 && len < 1.01;
    for (int k = 0; k < 3; ++k) lift[k] = lifted ? BSP_LIFT * nf[k] / len : 0.0;
    int32_t fv = rd_i32(f + 12), nv = rd_i32(f + 16), fi = rd_i32(f + 20), ni = rd_i32(f + 24);
    if (check_range(r, L_SURFACES, s, "vertex", fv, nv, r->l[L_DRAWVERTS].count, "vertices") ||
        check_range(r, L_SURFACES, s, "index", fi, ni, r->l[L_DRAWINDEXES].count, "indices"))
        return -1;
    if (ni % 3) {
        tool_error_set(err, r->path, 0, "surfaces[%u]: %d indices, not a whole number of triangles", s, ni);
        return -1;
    }
    uint32_t base = m->vertex_count;
    for (int32_t i = 0; i < nv; ++i)
        if (add_vertex(r, m, (uint32_t)(fv + i), lifted ? lift : NULL, err)) return -1;
    for (int32_t i = 0; i < ni; i += 3) {
        uint32_t t[3];
        for (int k = 0; k < 3; ++k) {
            int32_t v = rd_i32(rec(r, L_DRAWINDEXES, (uint32_t)(fi + i + k)));
            if (v < 0 || v >= nv) {
                tool_error_set(err, r->path, 0, "surfaces[%u]: index %d not in [0, %d)", s, v, nv);
                return -1;
            }
            t[k] = base + (uint32_t)v;
        }
        if (mesh_add_triangle(m, t[0], t[1 + flip], t[2 - flip])) {
            tool_error_set(err, r->path, 0, "out of memory");
            return -1;
        }
    }
    return 0;
}

/* A Bezier patch: a grid of w x h control points (both odd, at least 3) made of 3 x 3 blocks of
   biquadratic patches; each block is tessellated into level x level quads. */
static int add_patch(const bsp_reader *r, uint32_t s, const uint8_t *f, uint32_t level, mesh *m, tool_error *err) {
    int32_t fv = rd_i32(f + 12), nv = rd_i32(f + 16), w = rd_i32(f + 96), h = rd_i32(f + 100);
    if (check_range(r, L_SURFACES, s, "vertex", fv, nv, r->l[L_DRAWVERTS].count, "vertices")) return -1;
    if (w < 3 || h < 3 || !(w & 1) || !(h & 1) || w > 65 || h > 65 || (int64_t)w * h != nv) {
        tool_error_set(err, r->path, 0, "surfaces[%u]: patch of %d x %d control points with %d vertices", s, w, h, nv);
        return -1;
    }
    for (int32_t by = 0; by + 2 < h; by += 2)
        for (int32_t bx = 0; bx + 2 < w; bx += 2) {
            float c[3][3][3];
            for (int j = 0; j < 3; ++j)
                for (int i = 0; i < 3; ++i) {
                    const uint8_t *v = rec(r, L_DRAWVERTS, (uint32_t)(fv + (by + j) * w + bx + i));
                    float q[3] = {rd_f32(v), rd_f32(v + 4), rd_f32(v + 8)};
                    if (!finite3(q)) {
                        tool_error_set(err, r->path, 0, "drawverts[%d]: position is not finite", fv + (by + j) * w + bx + i);
                        return -1;
                    }
                    to_y_up(q, c[j][i]);
                }
            uint32_t base = m->vertex_count;
            if (base > BSP_MAX_VERTICES) {
                tool_error_set(err, r->path, 0, "surfaces[%u]: over %u vertices after tessellating the patches", s,
                               BSP_MAX_VERTICES);
                return -1;
            }
            for (uint32_t y = 0; y <= level; ++y)
                for (uint32_t x = 0; x <= level; ++x) {
                    double u = (double)x / level, v = (double)y / level;
                    double bu[3] = {(1 - u) * (1 - u), 2 * u * (1 - u), u * u}, bv[3] = {(1 - v) * (1 - v), 2 * v * (1 - v), v * v};
                    double p[3] = {0, 0, 0};
                    for (int j = 0; j < 3; ++j)
                        for (int i = 0; i < 3; ++i)
                            for (int k = 0; k < 3; ++k) p[k] += bv[j] * bu[i] * c[j][i][k];
                    if (mesh_add_vertex(m, (float)p[0], (float)p[1], (float)p[2])) goto oom;
                }
            for (uint32_t y = 0; y < level; ++y)
                for (uint32_t x = 0; x < level; ++x) {
                    uint32_t a = base + y * (level + 1) + x;
                    if (mesh_add_quad(m, a, a + 1, a + level + 2, a + level + 1)) goto oom;
                }
        }
    return 0;
oom:
    tool_error_set(err, r->path, 0, "out of memory");
    return -1;
}

/* ---- one-sided surfaces: Quake 3's shader scripts ---- */

/* 1 if a[0..n) and b[0..n) are equal but for case. */
static int same_nocase(const char *a, const char *b, size_t n) {
    for (size_t i = 0; i < n; ++i)
        if (tolower((unsigned char)a[i]) != tolower((unsigned char)b[i])) return 0;
    return 1;
}

/* Next token of shader script text at *p: "{", "}" or a word (comments skipped); its length, 0 at the end. */
static size_t script_token(const char **p, const char **tok) {
    const char *c = *p;
    for (;;) {
        while (*c && isspace((unsigned char)*c)) ++c;
        if (c[0] == '/' && c[1] == '/') while (*c && *c != '\n') ++c;
        else if (c[0] == '/' && c[1] == '*') {
            const char *e = strstr(c + 2, "*/");
            c = e ? e + 2 : c + strlen(c);
        } else break;
    }
    *tok = c;
    if (*c == '{' || *c == '}') c++;
    else while (*c && !isspace((unsigned char)*c) && *c != '{' && *c != '}') ++c;
    *p = c;
    return (size_t)(c - *tok);
}

/* two[i] = 1 if a definition of the level's shader i in `scripts` draws both faces (cull none, disable, twosided or
   back: only back faces), moves its vertices (deformVertexes), is a portal or the sky (skyparms): never one-sided. */
static void two_sided_shaders(const bsp_reader *r, const char *scripts, uint8_t *two) {
    const char *p = scripts, *t, *name = NULL;
    size_t n, name_n = 0;
    int depth = 0, both = 0, cull = 0;
    while ((n = script_token(&p, &t)) > 0) {
        if (*t == '{') {
            if (++depth == 1) both = 0;
        } else if (*t == '}') {
            if (depth > 0 && --depth == 0 && both && name)
                for (uint32_t i = 0; i < r->l[L_SHADERS].count; ++i) {
                    const char *sn = (const char *)rec(r, L_SHADERS, i), *z = (const char *)memchr(sn, 0, 64);
                    if ((size_t)((z ? z : sn + 64) - sn) == name_n && same_nocase(sn, name, name_n)) two[i] = 1;
                }
        } else if (depth == 0) {
            name = t, name_n = n;
        } else {
            if (cull)
                both |= (n == 4 && (same_nocase(t, "none", 4) || same_nocase(t, "back", 4))) ||
                        (n == 7 && same_nocase(t, "disable", 7)) || (n == 8 && same_nocase(t, "twosided", 8));
            if ((n == 14 && same_nocase(t, "deformvertexes", n)) || (n == 6 && same_nocase(t, "portal", n)) ||
                (n == 8 && same_nocase(t, "skyparms", n)))
                both = 1; /* moved vertices (autosprites face the eye), a view through it, the sky */
        }
        cull = depth > 0 && *t != '{' && *t != '}' && n == 4 && same_nocase(t, "cull", 4);
    }
}

/* 1 if planar surface f's triangles all wind clockwise about its normal (Quake's front faces), each of area. */
static int planar_clockwise(const bsp_reader *r, const uint8_t *f) {
    float nf[3] = {rd_f32(f + 84), rd_f32(f + 88), rd_f32(f + 92)};
    int32_t fv = rd_i32(f + 12), nv = rd_i32(f + 16), fi = rd_i32(f + 20), ni = rd_i32(f + 24);
    if (rd_i32(f + 8) != MST_PLANAR || !finite3(nf) || ni <= 0 || ni % 3 || fv < 0 || nv < 0 || fi < 0 ||
        (uint32_t)fv + (uint32_t)nv > r->l[L_DRAWVERTS].count || (uint32_t)fi + (uint32_t)ni > r->l[L_DRAWINDEXES].count)
        return 0;
    for (int32_t i = 0; i < ni; i += 3) {
        double q[3][3], e[3], g[3];
        for (int k = 0; k < 3; ++k) {
            int32_t v = rd_i32(rec(r, L_DRAWINDEXES, (uint32_t)(fi + i + k)));
            if (v < 0 || v >= nv) return 0;
            for (int j = 0; j < 3; ++j) q[k][j] = rd_f32(rec(r, L_DRAWVERTS, (uint32_t)(fv + v)) + 4 * j);
        }
        for (int j = 0; j < 3; ++j) e[j] = q[1][j] - q[0][j], g[j] = q[2][j] - q[0][j];
        if (!((e[1] * g[2] - e[2] * g[1]) * nf[0] + (e[2] * g[0] - e[0] * g[2]) * nf[1] + (e[0] * g[1] - e[1] * g[0]) * nf[2] < 0))
            return 0;
    }
    return 1;
}

static int read_surfaces(const bsp_reader *r, uint32_t level, const char *scripts, mesh *m, bsp_stats *st,
                         tool_error *err) {
    char name[32];
    uint8_t *two = scripts ? (uint8_t *)calloc(r->l[L_SHADERS].count + 1, 1) : NULL;
    if (scripts && !two) {
        tool_error_set(err, r->path, 0, "out of memory");
        return -1;
    }
    if (two) two_sided_shaders(r, scripts, two);
    for (uint32_t s = 0; s < r->l[L_SURFACES].count; ++s) {
        const uint8_t *f = rec(r, L_SURFACES, s);
        int32_t shader = rd_i32(f), type = rd_i32(f + 8);
        if (check_index(r, L_SURFACES, s, "shader", shader, r->l[L_SHADERS].count)) goto fail;
        const uint8_t *sh = rec(r, L_SHADERS, (uint32_t)shader);
        uint32_t surface_flags = tool_get32(sh + 64), contents = tool_get32(sh + 68);
        /* a see-through shader (water, fog, glass, grates) names its surface see_through...: drawn, never
           blocking sight, in the mesh and in the OBJ written from it */
        int clear = (contents & CONTENTS_SEE_THROUGH) != 0;
        /* with the scripts: a planar opaque surface drawn front only, its triangles turned counter-clockwise */
        int one = two && !clear && !two[shader] && !(surface_flags & (SURF_NODRAW | SURF_SKY)) && planar_clockwise(r, f);
        snprintf(name, sizeof(name), clear ? "see_through_s%u" : one ? "one_sided_s%u" : "s%u", s);
        if (mesh_begin_object(m, name, clear ? MESH_OBJECT_SEE_THROUGH : one ? MESH_OBJECT_ONE_SIDED : 0, 0)) {
            tool_error_set(err, r->path, 0, "out of memory");
            goto fail;
        }
        st->one_sided_surfaces += (uint32_t)one;
        st->translucent_surfaces += (uint32_t)clear;
        int rc = 0;
        if (surface_flags & SURF_NODRAW || type == MST_FLARE)
            rc = 0;
        else if (type == MST_PLANAR || type == MST_TRIANGLE_SOUP)
            rc = add_triangles(r, s, f, one, m, err);
        else if (type == MST_PATCH) {
            rc = add_patch(r, s, f, level, m, err);
            ++st->patches;
        } else {
            tool_error_set(err, r->path, 0, "surfaces[%u]: unknown surface type %d", s, type);
            goto fail;
        }
        if (rc) goto fail;
        if (m->objects[m->object_count - 1].triangle_count == 0) ++st->empty_surfaces;
    }
    st->surfaces = r->l[L_SURFACES].count;
    free(two);
    return 0;
fail:
    free(two);
    return -1;
}

/* ---- brush hulls ---- */

typedef struct bsp_winding {
    uint32_t n;
    double p[64][3];
} bsp_winding;

/* Keeps the part of w with n.x <= d (points within a hair of the plane stay). */
static void clip_winding(bsp_winding *w, const double n[3], double d) {
    bsp_winding o;
    double dist[65];
    o.n = 0;
    for (uint32_t i = 0; i < w->n; ++i) dist[i] = n[0] * w->p[i][0] + n[1] * w->p[i][1] + n[2] * w->p[i][2] - d;
    for (uint32_t i = 0; i < w->n && o.n < 63; ++i) {
        uint32_t j = (i + 1) % w->n;
        const double eps = 1e-6;
        if (dist[i] <= eps) memcpy(o.p[o.n++], w->p[i], sizeof(w->p[i]));
        if ((dist[i] < -eps && dist[j] > eps) || (dist[i] > eps && dist[j] < -eps)) {
            double t = dist[i] / (dist[i] - dist[j]);
            for (int k = 0; k < 3; ++k) o.p[o.n][k] = w->p[i][k] + t * (w->p[j][k] - w->p[i][k]);
            ++o.n;
        }
    }
    *w = o;
}

/* The polygon of plane (n, d) inside every other side of the brush. */
static void side_winding(const double n[3], double d, bsp_winding *w) {
    const double big = 262144.0; /* twice Quake 3's largest world coordinate */
    int a = fabs(n[2]) >= fabs(n[0]) && fabs(n[2]) >= fabs(n[1]) ? 2 : (fabs(n[1]) >= fabs(n[0]) ? 1 : 0);
    double up[3] = {0, 0, 0}, right[3], o[3];
    up[a == 2 ? 0 : 2] = 1.0;
    double dot = up[0] * n[0] + up[1] * n[1] + up[2] * n[2];
    for (int k = 0; k < 3; ++k) up[k] -= dot * n[k];
    double len = sqrt(up[0] * up[0] + up[1] * up[1] + up[2] * up[2]);
    for (int k = 0; k < 3; ++k) up[k] = up[k] / len * big;
    right[0] = (up[1] * n[2] - up[2] * n[1]);
    right[1] = (up[2] * n[0] - up[0] * n[2]);
    right[2] = (up[0] * n[1] - up[1] * n[0]);
    for (int k = 0; k < 3; ++k) o[k] = n[k] * d;
    w->n = 4;
    for (int k = 0; k < 3; ++k) {
        w->p[0][k] = o[k] - right[k] + up[k];
        w->p[1][k] = o[k] + right[k] + up[k];
        w->p[2][k] = o[k] + right[k] - up[k];
        w->p[3][k] = o[k] - right[k] - up[k];
    }
}

static int read_plane(const bsp_reader *r, uint32_t side, double n[3], double *d, tool_error *err) {
    int32_t pl = rd_i32(rec(r, L_BRUSHSIDES, side));
    if (check_index(r, L_BRUSHSIDES, side, "plane", pl, r->l[L_PLANES].count)) return -1;
    const uint8_t *p = rec(r, L_PLANES, (uint32_t)pl);
    float f[4] = {rd_f32(p), rd_f32(p + 4), rd_f32(p + 8), rd_f32(p + 12)};
    if (!finite3(f) || !isfinite(f[3]) || !(fabs(f[0]) + fabs(f[1]) + fabs(f[2]) > 0.5)) {
        tool_error_set(err, r->path, 0, "planes[%d]: not a finite unit normal", pl);
        return -1;
    }
    double len = sqrt((double)f[0] * f[0] + (double)f[1] * f[1] + (double)f[2] * f[2]);
    for (int k = 0; k < 3; ++k) n[k] = f[k] / len;
    *d = f[3] / len;
    return 0;
}

/* 1 if the brush is solid and opaque: its contents and every side's shader. */
static int brush_blocks(const bsp_reader *r, uint32_t b, int32_t fs, int32_t ns) {
    int32_t shader = rd_i32(rec(r, L_BRUSHES, b) + 8);
    if (check_index(r, L_BRUSHES, b, "shader", shader, r->l[L_SHADERS].count)) return -1;
    uint32_t contents = tool_get32(rec(r, L_SHADERS, (uint32_t)shader) + 68);
    if (!(contents & CONTENTS_SOLID) || (contents & CONTENTS_SEE_THROUGH)) return 0;
    for (int32_t i = 0; i < ns; ++i) {
        int32_t ss = rd_i32(rec(r, L_BRUSHSIDES, (uint32_t)(fs + i)) + 4);
        if (check_index(r, L_BRUSHSIDES, (uint32_t)(fs + i), "shader", ss, r->l[L_SHADERS].count)) return -1;
        if (tool_get32(rec(r, L_SHADERS, (uint32_t)ss) + 68) & CONTENTS_SEE_THROUGH) return 0;
    }
    return 1;
}

/* The index of corner x among the brush's welded corners (added when new); -1 when there are too many. */
static int32_t weld_corner(double (*c)[3], uint32_t *n, uint32_t cap, const double x[3]) {
    for (uint32_t i = 0; i < *n; ++i)
        if (fabs(c[i][0] - x[0]) < BSP_WELD && fabs(c[i][1] - x[1]) < BSP_WELD && fabs(c[i][2] - x[2]) < BSP_WELD)
            return (int32_t)i;
    if (*n == cap) return -1;
    memcpy(c[*n], x, sizeof(c[0]));
    return (int32_t)(*n)++;
}

static int add_brush(const bsp_reader *r, uint32_t b, mesh *m, bsp_stats *st, tool_error *err) {
    const uint8_t *br = rec(r, L_BRUSHES, b);
    int32_t fs = rd_i32(br), ns = rd_i32(br + 4);
    if (check_range(r, L_BRUSHES, b, "side", fs, ns, r->l[L_BRUSHSIDES].count, "brush sides")) return -1;
    int blocks = brush_blocks(r, b, fs, ns);
    if (blocks <= 0) return blocks;
    if (ns < 4 || ns > 256) return 0; /* not a closed convex solid, or absurd: left out (never blocks) */
    double n[256][3], d[256];
    int32_t plane[256];
    for (int32_t i = 0; i < ns; ++i) {
        if (read_plane(r, (uint32_t)(fs + i), n[i], &d[i], err)) return -1;
        plane[i] = rd_i32(rec(r, L_BRUSHSIDES, (uint32_t)(fs + i)));
    }
    /* the hull exact (rounded to nearest once per corner) and closed: faces share the welded corners, so a
       brush is one connected closed convex mesh (what the portal method's rooms are built from) */
    enum { CORNERS = 1024, FACE_CORNERS = 8192 };
    double (*corner)[3] = malloc(CORNERS * sizeof(*corner));
    int32_t *face = malloc(FACE_CORNERS * sizeof(*face));
    uint32_t corners = 0, used = 0, faces_at[257], face_count = 0;
    int rc = 0;
    if (!corner || !face) rc = -1;
    for (int32_t i = 0; i < ns && rc == 0; ++i) {
        int dup = 0;
        for (int32_t j = 0; j < i; ++j) dup |= plane[j] == plane[i];
        if (dup) continue;
        bsp_winding w;
        side_winding(n[i], d[i], &w);
        for (int32_t j = 0; j < ns && w.n >= 3; ++j)
            if (plane[j] != plane[i]) clip_winding(&w, n[j], d[j]);
        if (w.n < 3) continue;
        faces_at[face_count++] = used;
        for (uint32_t k = 0; k < w.n && rc == 0; ++k) {
            int32_t v = used < FACE_CORNERS ? weld_corner(corner, &corners, CORNERS, w.p[k]) : -1;
            if (v < 0) rc = 1; /* absurd: left out (never blocks) */
            else if (used == faces_at[face_count - 1] || face[used - 1] != v) face[used++] = v;
        }
        if (rc == 0 && used - faces_at[face_count - 1] > 1 && face[used - 1] == face[faces_at[face_count - 1]]) --used;
        if (used - faces_at[face_count - 1] < 3) used = faces_at[--face_count]; /* welded to a sliver */
    }
    faces_at[face_count] = used;
    if (rc == 0 && face_count >= 4) {
        uint32_t base = m->vertex_count;
        ++st->occluder_brushes;
        for (uint32_t v = 0; v < corners && rc == 0; ++v) {
            float q[3] = {(float)corner[v][0], (float)corner[v][1], (float)corner[v][2]}, y[3];
            to_y_up(q, y);
            rc = mesh_add_vertex(m, y[0], y[1], y[2]) ? -1 : 0;
        }
        for (uint32_t f = 0; f < face_count && rc == 0; ++f)
            for (uint32_t k = faces_at[f] + 1; k + 1 < faces_at[f + 1] && rc == 0; ++k) {
                rc = mesh_add_triangle(m, base + (uint32_t)face[faces_at[f]], base + (uint32_t)face[k],
                                       base + (uint32_t)face[k + 1]) ? -1 : 0;
                ++st->hull_triangles;
            }
    }
    free(corner);
    free(face);
    if (rc < 0) tool_error_set(err, r->path, 0, "out of memory");
    return rc < 0 ? -1 : 0;
}

static int read_brushes(const bsp_reader *r, mesh *m, bsp_stats *st, tool_error *err) {
    const uint8_t *world = rec(r, L_MODELS, 0);
    int32_t fb = rd_i32(world + 32), nb = rd_i32(world + 36);
    if (check_range(r, L_MODELS, 0, "brush", fb, nb, r->l[L_BRUSHES].count, "brushes")) return -1;
    if (mesh_begin_object(m, "occluder_brushes", MESH_OBJECT_OCCLUDER, 0)) {
        tool_error_set(err, r->path, 0, "out of memory");
        return -1;
    }
    st->brushes = (uint32_t)nb;
    for (int32_t b = 0; b < nb; ++b)
        if (add_brush(r, (uint32_t)(fb + b), m, st, err)) return -1;
    return 0;
}

/* ---- cells and the level's PVS ---- */

/* A leaf's bounds in Quake coordinates (Z up). */
static void leaf_bounds(const uint8_t *leaf, double lo[3], double hi[3]) {
    for (int k = 0; k < 3; ++k) lo[k] = rd_i32(leaf + 8 + 4 * k), hi[k] = rd_i32(leaf + 20 + 4 * k);
}
/* Quake bounds to a Y-up box: (x, y, z) -> (x, z, -y). */
static void y_up_box(const double lo[3], const double hi[3], float box[6]) {
    box[0] = (float)lo[0];
    box[1] = (float)lo[2];
    box[2] = (float)-hi[1];
    box[3] = (float)hi[0];
    box[4] = (float)hi[2];
    box[5] = (float)-lo[1];
}
static void leaf_box(const uint8_t *leaf, float box[6]) {
    double lo[3], hi[3];
    leaf_bounds(leaf, lo, hi);
    y_up_box(lo, hi, box);
}

/* Marks r->in_world: the leaves of the world's tree, walked from node 0, each node once. Leaves outside it
   (q3map2 writes a dummy leaf 0 and the inline models' leaves, with zero bounds and cluster 0) are no place
   a camera is ever located in. A child out of range or a node reached twice is an error. */
static int read_tree(bsp_reader *r, tool_error *err) {
    uint32_t nn = r->l[L_NODES].count, nl = r->l[L_LEAFS].count, top = 0;
    uint32_t *stack = (uint32_t *)malloc(((size_t)nn + 1) * sizeof(uint32_t));
    uint8_t *seen = (uint8_t *)calloc((size_t)nn + 1, 1);
    int rc = -1;
    r->in_world = (uint8_t *)calloc((size_t)nl + 1, 1);
    if (!stack || !seen || !r->in_world) {
        tool_error_set(err, r->path, 0, "out of memory");
        goto done;
    }
    if (nn == 0) memset(r->in_world, 1, nl);
    if (nn) stack[top++] = 0, seen[0] = 1;
    while (top) {
        uint32_t n = stack[--top];
        if (check_index(r, L_NODES, n, "plane", rd_i32(rec(r, L_NODES, n)), r->l[L_PLANES].count)) goto done;
        for (int k = 0; k < 2; ++k) {
            int32_t c = rd_i32(rec(r, L_NODES, n) + 4 + 4 * k);
            if (c >= 0 && ((uint32_t)c >= nn || seen[c])) {
                tool_error_set(err, r->path, 0, "nodes[%u]: child %d %s", n, c,
                               (uint32_t)c >= nn ? "out of range" : "reached twice (not a tree)");
                goto done;
            }
            if (c < 0 && (uint32_t)(-(c + 1)) >= nl) {
                tool_error_set(err, r->path, 0, "nodes[%u]: leaf %d out of range (%u leafs)", n, -(c + 1), nl);
                goto done;
            }
            if (c >= 0) seen[c] = 1, stack[top++] = (uint32_t)c;
            else r->in_world[-(c + 1)] = 1;
        }
    }
    rc = 0;
done:
    free(stack);
    free(seen);
    return rc;
}

/* 1 if leaf i is a cell: in the world's tree, it has a cluster and is the every cell_step-th such leaf (*k
   counts them). */
static int leaf_is_cell(const bsp_reader *r, uint32_t i, uint32_t *k) {
    if (!r->in_world[i] || rd_i32(rec(r, L_LEAFS, i)) < 0) return 0;
    return (*k)++ % r->cell_step == 0;
}

/* 1 if every leaf of the world's tree that the box lo..hi (Quake coordinates) reaches has no cluster: the box lies
   in walls or in the void. A node's plane sends the box to both children unless it lies wholly on one side (a NaN
   plane: both). Each node is reached once (read_tree checked the tree), so `stack` holds the node count. */
static int box_solid(const bsp_reader *r, const double lo[3], const double hi[3], uint32_t *stack) {
    uint32_t top = 0;
    if (r->l[L_NODES].count == 0) return 0;
    stack[top++] = 0;
    while (top) {
        const uint8_t *node = rec(r, L_NODES, stack[--top]), *pl = rec(r, L_PLANES, (uint32_t)rd_i32(node));
        double m = -(double)rd_f32(pl + 12), e = 0;
        for (int k = 0; k < 3; ++k) {
            double n = rd_f32(pl + 4 * k);
            m += n * 0.5 * (lo[k] + hi[k]);
            e += fabs(n) * 0.5 * (hi[k] - lo[k]);
        }
        for (int k = 0; k < 2; ++k) { /* front (n.p >= dist), back */
            if (k == 0 ? m + e < 0 : m - e >= 0) continue;
            int32_t c = rd_i32(node + 4 + 4 * k);
            if (c >= 0) stack[top++] = (uint32_t)c;
            else if (rd_i32(rec(r, L_LEAFS, (uint32_t)-(c + 1))) >= 0) return 0;
        }
    }
    return 1;
}

/* The leaf's bounds with each face whose outside is wall kept `c` units off it: the slab from c / 4 to c beyond the
   face, inset c / 4 from its edges, reaches only leaves without a cluster. An axis whose two faces would cross keeps
   its bounds. Returns the faces moved. */
static uint32_t keep_off_walls(const bsp_reader *r, double c, double lo[3], double hi[3], uint32_t *stack) {
    double nlo[3], nhi[3], sl[3], sh[3];
    uint32_t moved = 0;
    if (!(c > 0)) return 0;
    for (int b = 0; b < 3; ++b) sl[b] = lo[b] + 0.25 * c, sh[b] = hi[b] - 0.25 * c; /* the slabs' inset sides */
    for (int a = 0; a < 3; ++a) {
        double keep_lo = sl[a], keep_hi = sh[a];
        nlo[a] = lo[a], nhi[a] = hi[a];
        if (sl[(a + 1) % 3] > sh[(a + 1) % 3] || sl[(a + 2) % 3] > sh[(a + 2) % 3]) continue; /* a face too thin */
        for (int side = 0; side < 2; ++side) {
            sl[a] = side ? hi[a] + 0.25 * c : lo[a] - c;
            sh[a] = side ? hi[a] + c : lo[a] - 0.25 * c;
            if (box_solid(r, sl, sh, stack)) *(side ? &nhi[a] : &nlo[a]) += side ? -c : c;
        }
        sl[a] = keep_lo, sh[a] = keep_hi;
    }
    for (int a = 0; a < 3; ++a) {
        if (nlo[a] > nhi[a]) continue;
        moved += (nlo[a] != lo[a]) + (nhi[a] != hi[a]);
        lo[a] = nlo[a], hi[a] = nhi[a];
    }
    return moved;
}

static int read_cells(const bsp_reader *r, double clearance, mesh_cells *cells, bsp_stats *st, tool_error *err) {
    uint32_t *stack = (uint32_t *)malloc(((size_t)r->l[L_NODES].count + 1) * sizeof(uint32_t));
    if (!stack) {
        tool_error_set(err, r->path, 0, "out of memory");
        return -1;
    }
    for (uint32_t i = 0, k = 0; i < r->l[L_LEAFS].count; ++i) {
        const uint8_t *leaf = rec(r, L_LEAFS, i);
        double lo[3], hi[3];
        float box[6];
        if (!r->in_world[i] || rd_i32(leaf) < 0) continue;
        ++st->leaves;
        leaf_bounds(leaf, lo, hi);
        if (!(lo[0] <= hi[0] && lo[1] <= hi[1] && lo[2] <= hi[2])) {
            tool_error_set(err, r->path, 0, "leafs[%u]: bounds min > max", i);
            return free(stack), -1;
        }
        if (!leaf_is_cell(r, i, &k)) continue;
        st->wall_faces += keep_off_walls(r, clearance, lo, hi, stack);
        y_up_box(lo, hi, box);
        if (cells && mesh_cells_add(cells, box)) {
            tool_error_set(err, r->path, 0, "out of memory");
            return free(stack), -1;
        }
        ++st->cells;
    }
    free(stack);
    return 0;
}

static int boxes_meet(const float a[6], const float b[6]) {
    return a[0] <= b[3] && b[0] <= a[3] && a[1] <= b[4] && b[1] <= a[4] && a[2] <= b[5] && b[2] <= a[5];
}

/* Cluster visibility from the vis lump: vis[k] row of `bytes` bytes, or NULL (everything visible). */
static int read_vis(const bsp_reader *r, const uint8_t **vis, uint32_t *clusters, uint32_t *bytes, tool_error *err) {
    uint32_t len = r->l[L_VISIBILITY].count;
    *vis = NULL;
    *clusters = *bytes = 0;
    if (len == 0) return 0;
    if (len < 8) {
        tool_error_set(err, r->path, 0, "lump 16 (visibility): %u bytes, shorter than its 8-byte header", len);
        return -1;
    }
    uint32_t n = tool_get32(r->l[L_VISIBILITY].p), b = tool_get32(r->l[L_VISIBILITY].p + 4);
    if (b < (n + 7) / 8 || (uint64_t)n * b > len - 8) {
        tool_error_set(err, r->path, 0, "lump 16 (visibility): %u clusters of %u bytes do not fit in %u bytes", n, b, len);
        return -1;
    }
    *vis = r->l[L_VISIBILITY].p + 8;
    *clusters = n;
    *bytes = b;
    return 0;
}

/* For each inline model m >= 1, the leaves with a cluster whose box meets the model's bounds:
   leaves[first[m - 1] .. first[m]) (malloc'd). Validates the models' surface ranges. */
static int model_leaf_lists(const bsp_reader *r, uint32_t **first_out, uint32_t **leaves_out, tool_error *err) {
    uint32_t nm = r->l[L_MODELS].count, nleaf = r->l[L_LEAFS].count, n = 0, cap = 64;
    uint32_t *first = (uint32_t *)calloc(nm, sizeof(uint32_t)), *leaves = (uint32_t *)malloc(cap * sizeof(uint32_t));
    if (!first || !leaves) goto oom;
    for (uint32_t mdl = 1; mdl < nm; ++mdl) {
        const uint8_t *md = rec(r, L_MODELS, mdl);
        float q0[3] = {rd_f32(md), rd_f32(md + 4), rd_f32(md + 8)}, q1[3] = {rd_f32(md + 12), rd_f32(md + 16), rd_f32(md + 20)};
        float mb[6] = {q0[0], q0[2], -q1[1], q1[0], q1[2], -q0[1]};
        if (check_range(r, L_MODELS, mdl, "surface", rd_i32(md + 24), rd_i32(md + 28), r->l[L_SURFACES].count,
                        "surfaces"))
            goto fail;
        for (uint32_t j = 0; j < nleaf; ++j) {
            const uint8_t *leaf = rec(r, L_LEAFS, j);
            float lb[6];
            if (rd_i32(leaf) < 0) continue;
            leaf_box(leaf, lb);
            if (!boxes_meet(mb, lb)) continue;
            if (n == cap) {
                uint32_t *g = (uint32_t *)realloc(leaves, 2 * (size_t)cap * sizeof(uint32_t));
                if (!g) goto oom;
                leaves = g;
                cap *= 2;
            }
            leaves[n++] = j;
        }
        first[mdl] = n;
    }
    *first_out = first;
    *leaves_out = leaves;
    return 0;
oom:
    tool_error_set(err, r->path, 0, "out of memory");
fail:
    free(first);
    free(leaves);
    return -1;
}

static int read_pvs(const bsp_reader *r, uint32_t object_count, uint32_t cell_count, bsp_pvs *pvs, bsp_stats *st,
                    tool_error *err) {
    const uint8_t *vis;
    uint32_t *model_first = NULL, *model_leaves = NULL;
    uint32_t clusters, bytes, nleaf = r->l[L_LEAFS].count, nsurf = r->l[L_SURFACES].count;
    if (read_vis(r, &vis, &clusters, &bytes, err)) return -1;
    st->has_vis = vis != NULL;
    st->clusters = clusters;
    pvs->cell_count = cell_count;
    pvs->object_count = object_count;
    pvs->words = (object_count + 63) / 64;
    pvs->bits = (uint64_t *)calloc((size_t)cell_count * pvs->words + 1, sizeof(uint64_t));
    uint8_t *seen = (uint8_t *)malloc(nleaf + 1);
    if (!pvs->bits || !seen) {
        free(seen);
        tool_error_set(err, r->path, 0, "out of memory");
        return -1;
    }
    for (uint32_t i = 0; i < nleaf; ++i) { /* every leaf's surfaces must be valid before use */
        const uint8_t *leaf = rec(r, L_LEAFS, i);
        int32_t c = rd_i32(leaf);
        if (vis && c >= (int32_t)clusters) {
            free(seen);
            return check_index(r, L_LEAFS, i, "cluster", c, clusters);
        }
        if (check_range(r, L_LEAFS, i, "surface", rd_i32(leaf + 32), rd_i32(leaf + 36), r->l[L_LEAFSURFACES].count,
                        "leaf surfaces"))
            return free(seen), -1;
    }
    for (uint32_t i = 0; i < r->l[L_LEAFSURFACES].count; ++i)
        if (check_index(r, L_LEAFSURFACES, i, "surface", rd_i32(rec(r, L_LEAFSURFACES, i)), nsurf)) return free(seen), -1;
    if (model_leaf_lists(r, &model_first, &model_leaves, err)) return free(seen), -1;
    uint32_t cell = 0;
    for (uint32_t i = 0, nth = 0; i < nleaf; ++i) {
        int32_t k = rd_i32(rec(r, L_LEAFS, i));
        if (!leaf_is_cell(r, i, &nth)) continue;
        uint64_t *row = pvs->bits + (size_t)cell++ * pvs->words;
        for (uint32_t j = 0; j < nleaf; ++j) { /* the leaves whose cluster cluster k sees */
            int32_t c = rd_i32(rec(r, L_LEAFS, j));
            seen[j] = c >= 0 && (!vis || ((vis[(size_t)k * bytes + ((uint32_t)c >> 3)] >> (c & 7)) & 1));
            if (!seen[j]) continue;
            const uint8_t *leaf = rec(r, L_LEAFS, j);
            int32_t first = rd_i32(leaf + 32), count = rd_i32(leaf + 36);
            for (int32_t s = 0; s < count; ++s) {
                uint32_t o = (uint32_t)rd_i32(rec(r, L_LEAFSURFACES, (uint32_t)(first + s)));
                row[o >> 6] |= 1ull << (o & 63);
            }
        }
        for (uint32_t mdl = 1; mdl < r->l[L_MODELS].count; ++mdl) { /* inline models: by the leaves they meet */
            const uint8_t *md = rec(r, L_MODELS, mdl);
            int32_t fsf = rd_i32(md + 24), nsf = rd_i32(md + 28);
            int meets = !vis;
            for (uint32_t j = model_first[mdl - 1]; j < model_first[mdl] && !meets; ++j) meets = seen[model_leaves[j]];
            for (int32_t s = 0; meets && s < nsf; ++s) row[(uint32_t)(fsf + s) >> 6] |= 1ull << ((uint32_t)(fsf + s) & 63);
        }
    }
    free(seen);
    free(model_first);
    free(model_leaves);
    return 0;
}

void bsp_pvs_free(bsp_pvs *pvs) {
    if (!pvs) return;
    free(pvs->bits);
    memset(pvs, 0, sizeof(*pvs));
}

/* The first player start (an entity whose classname begins with info_player_) with an origin "x y z": the entities
   lump is text, blocks of "key" "value" pairs in braces; anything malformed is passed over (no start found). */
static void read_spawn(const bsp_reader *r, bsp_stats *st) {
    const char *p = (const char *)r->l[0].p, *end = p + r->l[0].count;
    while (p < end) {
        const char *close = memchr(p, '}', (size_t)(end - p)), *q;
        int player = 0, have = 0;
        float o[3];
        if (!close) return;
        for (q = p; q + 14 < close; ++q) {
            char buf[64];
            size_t n;
            const char *v;
            if (!strncmp(q, "\"classname\"", 11)) {
                for (v = q + 11; v < close && *v != '"'; ++v) {}
                player |= close - v > 13 && !strncmp(v, "\"info_player_", 13);
            } else if (!strncmp(q, "\"origin\"", 8)) {
                for (v = q + 8; v < close && *v != '"'; ++v) {}
                for (n = 0; v + 1 + n < close && v[1 + n] != '"' && n + 1 < sizeof(buf); ++n) buf[n] = v[1 + n];
                buf[n] = '\0';
                have = sscanf(buf, "%f %f %f", o, o + 1, o + 2) == 3 && finite3(o);
            }
        }
        if (player && have) {
            to_y_up(o, st->spawn);
            st->has_spawn = 1;
            return;
        }
        p = close + 1;
    }
}

int bsp_parse(const char *path, const void *data, size_t size, const bsp_options *opt, mesh *m, mesh_cells *cells,
              bsp_pvs *pvs, bsp_stats *stats, tool_error *err) {
    bsp_reader r;
    bsp_stats st;
    mesh local;
    uint32_t level = opt && opt->patch_level ? opt->patch_level : 4;
    memset(&r, 0, sizeof(r));
    memset(&st, 0, sizeof(st));
    r.path = path;
    r.err = err;
    r.cell_step = opt && opt->cell_step > 1 ? opt->cell_step : 1;
    if (!m) m = &local;
    mesh_init(m);
    if (cells) mesh_cells_init(cells);
    if (pvs) memset(pvs, 0, sizeof(*pvs));
    int rc = -1;
    if (level > 32) {
        tool_error_set(err, path, 0, "patch level %u: at most 32", level);
        goto done;
    }
    if (opt && !(opt->clearance >= 0 && opt->clearance <= 1e6)) {
        tool_error_set(err, path, 0, "clearance %g: not a distance from 0 to 1e6", opt->clearance);
        goto done;
    }
    if (read_header(&r, (const uint8_t *)data, size) || read_surfaces(&r, level, opt ? opt->shaders : NULL, m, &st, err) ||
        read_brushes(&r, m, &st, err) || read_tree(&r, err) || read_cells(&r, opt ? opt->clearance : 0, cells, &st, err))
        goto done;
    if (pvs && read_pvs(&r, m->object_count, st.cells, pvs, &st, err)) goto done;
    read_spawn(&r, &st);
    if (st.leaves == 0) {
        tool_error_set(err, path, 0, "no leaf with a cluster: no view cells (a level without vis leaves?)");
        goto done;
    }
    rc = 0;
done:
    free(r.in_world);
    if (m == &local) mesh_free(m);
    if (rc && pvs) bsp_pvs_free(pvs);
    if (stats) *stats = st;
    return rc;
}
