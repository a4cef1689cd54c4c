/* wad.c - Doom map reader (WAD: vanilla and Boom binary maps): walls, flats, subsector cells. See wad.h.
   The layout follows the Doom source's doomdata.h (id Software, GPL), read byte by byte here so that the host's
   endianness and struct padding do not matter. */
#include "wad.h"
#include <ctype.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

enum { M_LINEDEFS, M_SIDEDEFS, M_VERTEXES, M_SEGS, M_SSECTORS, M_NODES, M_SECTORS, M_COUNT };
static const char *const map_lumps[M_COUNT] = {"LINEDEFS", "SIDEDEFS", "VERTEXES", "SEGS", "SSECTORS", "NODES",
                                               "SECTORS"};
static const uint32_t map_sizes[M_COUNT] = {14, 30, 4, 12, 4, 28, 26};
#define WAD_NONE 0xffffu
#define WAD_MAXV 64      /* vertices of a subsector polygon; more: the subsector is lost (counted) */
#define WAD_MAX_DEPTH 256 /* node tree depth; deeper: an error (Doom's are a few dozen deep) */
#define WAD_CELL_GRID 8.0f /* cell boxes grow out to this grid (Doom maps are drawn on one): 16-bit coordinate
                              tables in the .pvs file, smaller files, a PVS 0.3% larger on Freedoom's maps */
#define WAD_LIFT 0.01     /* units a drawn wall or flat stands off the solid it lies on (as bsp.c's BSP_LIFT): the
                             solids stay exact (touching prisms leave no crack) and never hide what is drawn on them */

typedef struct wad_map {
    const char *path;
    char name[9];
    const uint8_t *l[M_COUNT];
    uint32_t n[M_COUNT];
    tool_error *err;
} wad_map;

typedef struct wad_poly {
    uint32_t n;
    double p[WAD_MAXV][2];
} wad_poly;

static uint16_t rd_u16(const uint8_t *p) { return (uint16_t)(p[0] | p[1] << 8); }
static int16_t rd_i16(const uint8_t *p) {
    uint16_t u = rd_u16(p);
    return u <= 0x7fffu ? (int16_t)u : (int16_t)(-(int32_t)(uint16_t)~u - 1);
}
static const uint8_t *rec(const wad_map *w, int lump, uint32_t i) { return w->l[lump] + (size_t)i * map_sizes[lump]; }

/* Lump name (8 bytes, NUL-padded) equals s, ignoring case. */
static int name_is(const uint8_t *name, const char *s) {
    size_t i;
    for (i = 0; i < 8 && s[i]; ++i)
        if (toupper(name[i]) != toupper((unsigned char)s[i])) return 0;
    return i == 8 || name[i] == 0;
}
static void name_copy(char out[9], const uint8_t *name) {
    int i;
    for (i = 0; i < 8 && name[i]; ++i) out[i] = isprint(name[i]) ? (char)toupper(name[i]) : '?';
    out[i] = 0;
}

/* The directory: 0 with *dir, *count, or -1 with err set. */
static int read_directory(const char *path, const uint8_t *d, size_t size, const uint8_t **dir, uint32_t *count,
                          tool_error *err) {
    uint32_t n, at;
    if (size < 12 || (memcmp(d, "IWAD", 4) && memcmp(d, "PWAD", 4))) {
        tool_error_set(err, path, 0, "not a WAD file (no IWAD or PWAD header)");
        return -1;
    }
    n = tool_get32(d + 4);
    at = tool_get32(d + 8);
    if (n > 0x7fffffffu || at > size || (uint64_t)n * 16 > size - at) {
        tool_error_set(err, path, 0, "directory of %u lumps at %u passes the file's %zu bytes", n, at, size);
        return -1;
    }
    *dir = d + at;
    *count = n;
    return 0;
}

/* Entry i opens a map: it is not THINGS, the next is THINGS, LINEDEFS or TEXTMAP. */
static int is_map_marker(const uint8_t *dir, uint32_t count, uint32_t i) {
    const uint8_t *next = dir + 16 * ((size_t)i + 1) + 8;
    return i + 1 < count && !name_is(next - 16, "THINGS") &&
           (name_is(next, "THINGS") || name_is(next, "LINEDEFS") || name_is(next, "TEXTMAP"));
}

int wad_list_maps(const char *path, const void *data, size_t size, char *list, size_t cap, tool_error *err) {
    const uint8_t *dir;
    uint32_t count, i;
    size_t used = 0;
    int maps = 0;
    if (read_directory(path, (const uint8_t *)data, size, &dir, &count, err)) return -1;
    if (cap) list[0] = 0;
    for (i = 0; i < count; ++i)
        if (is_map_marker(dir, count, i)) {
            char name[9];
            size_t len;
            name_copy(name, dir + 16 * (size_t)i + 8);
            len = strlen(name);
            if (used + len + 2 <= cap) {
                memcpy(list + used, name, len);
                list[used + len] = '\n';
                list[used + len + 1] = 0;
                used += len + 1;
            }
            ++maps;
        }
    return maps;
}

/* Finds map (NULL: the first) and its lumps. */
static int find_map(wad_map *w, const uint8_t *d, size_t size, const char *map) {
    const uint8_t *dir;
    uint32_t count, i, k;
    if (read_directory(w->path, d, size, &dir, &count, w->err)) return -1;
    for (i = 0; i < count; ++i)
        if (is_map_marker(dir, count, i) && (!map || name_is(dir + 16 * (size_t)i + 8, map))) break;
    if (i == count) {
        tool_error_set(w->err, w->path, 0, map ? "no map named %s" : "no map in the file", map);
        return -1;
    }
    name_copy(w->name, dir + 16 * (size_t)i + 8);
    for (k = i + 1; k < count && k < i + 16; ++k) { /* the map's lumps: another format's first */
        const uint8_t *e = dir + 16 * (size_t)k + 8;
        if (name_is(e, "TEXTMAP") || name_is(e, "BEHAVIOR")) {
            tool_error_set(w->err, w->path, 0, "%s: a %s map (lump %s): only Doom's binary format is read", w->name,
                           name_is(e, "TEXTMAP") ? "UDMF" : "Hexen-format", name_is(e, "TEXTMAP") ? "TEXTMAP" : "BEHAVIOR");
            return -1;
        }
        if (is_map_marker(dir, count, k)) break;
    }
    for (++i; i < count; ++i) {
        const uint8_t *e = dir + 16 * (size_t)i;
        uint32_t at = tool_get32(e), len = tool_get32(e + 4);
        int known = 0;
        for (k = 0; k < M_COUNT; ++k)
            if (name_is(e + 8, map_lumps[k])) {
                known = 1;
                if (at > size || len > size - at || len % map_sizes[k]) {
                    tool_error_set(w->err, w->path, 0, "%s: lump %s of %u bytes at %u: %s", w->name, map_lumps[k], len,
                                   at, len % map_sizes[k] ? "not whole records" : "past the file's end");
                    return -1;
                }
                if (k == M_NODES && len >= 4 && (!memcmp(d + at, "XNOD", 4) || !memcmp(d + at, "ZNOD", 4))) {
                    tool_error_set(w->err, w->path, 0, "%s: extended (ZDoom) nodes: only Doom's are read", w->name);
                    return -1;
                }
                w->l[k] = d + at;
                w->n[k] = len / map_sizes[k];
            }
        if (!known && !name_is(e + 8, "THINGS") && !name_is(e + 8, "REJECT") && !name_is(e + 8, "BLOCKMAP")) break;
    }
    if (!w->n[M_NODES] && w->n[M_SSECTORS] > 1) {
        tool_error_set(w->err, w->path, 0, "%s: %u subsectors and no NODES", w->name, w->n[M_SSECTORS]);
        return -1;
    }
    for (k = 0; k < M_COUNT; ++k)
        if (!w->l[k] && k != M_NODES) {
            tool_error_set(w->err, w->path, 0, "%s: no %s lump", w->name, map_lumps[k]);
            return -1;
        }
    if (!w->n[M_SSECTORS] || !w->n[M_SECTORS] || !w->n[M_VERTEXES]) {
        tool_error_set(w->err, w->path, 0, "%s: no %s", w->name,
                       !w->n[M_SSECTORS] ? "subsectors" : !w->n[M_SECTORS] ? "sectors" : "vertices");
        return -1;
    }
    return 0;
}

/* Checks every index the reader follows: 0, or -1 naming the record. */
static int check_indices(const wad_map *w) {
    uint32_t i, nv = w->n[M_VERTEXES], nl = w->n[M_LINEDEFS], ns = w->n[M_SIDEDEFS], nsg = w->n[M_SEGS];
    const char *bad = NULL;
    uint32_t what = 0, lump = 0, limit = 0;
    for (i = 0; i < nl && !bad; ++i) {
        const uint8_t *r = rec(w, M_LINEDEFS, i);
        uint32_t v1 = rd_u16(r), v2 = rd_u16(r + 2), s1 = rd_u16(r + 10), s2 = rd_u16(r + 12);
        if (v1 >= nv || v2 >= nv) bad = "vertex", what = v1 >= nv ? v1 : v2, limit = nv;
        else if ((s1 != WAD_NONE && s1 >= ns) || (s2 != WAD_NONE && s2 >= ns))
            bad = "sidedef", what = s1 != WAD_NONE && s1 >= ns ? s1 : s2, limit = ns;
        lump = M_LINEDEFS;
    }
    if (bad) goto fail;
    for (i = 0; i < ns && !bad; ++i)
        if (rd_u16(rec(w, M_SIDEDEFS, i) + 28) >= w->n[M_SECTORS])
            bad = "sector", what = rd_u16(rec(w, M_SIDEDEFS, i) + 28), limit = w->n[M_SECTORS], lump = M_SIDEDEFS;
    if (bad) goto fail;
    for (i = 0; i < nsg && !bad; ++i) {
        const uint8_t *r = rec(w, M_SEGS, i);
        uint32_t v1 = rd_u16(r), v2 = rd_u16(r + 2), l = rd_u16(r + 6);
        lump = M_SEGS;
        if (v1 >= nv || v2 >= nv) bad = "vertex", what = v1 >= nv ? v1 : v2, limit = nv;
        else if (l >= nl) bad = "linedef", what = l, limit = nl;
        else if (rd_u16(r + 8) > 1) bad = "side", what = rd_u16(r + 8), limit = 2;
        else if (rd_u16(rec(w, M_LINEDEFS, l) + 10 + 2 * rd_u16(r + 8)) == WAD_NONE)
            bad = "side (none on its linedef)", what = rd_u16(r + 8), limit = 2;
    }
    if (bad) goto fail;
    for (i = 0; i < w->n[M_SSECTORS] && !bad; ++i) {
        const uint8_t *r = rec(w, M_SSECTORS, i);
        uint32_t c = rd_u16(r), f = rd_u16(r + 2);
        lump = M_SSECTORS;
        if (c == 0) bad = "no segs", limit = 0;
        else if (f + c > nsg) bad = "seg range end", what = f + c, limit = nsg;
    }
    if (bad) goto fail;
    for (i = 0; i < w->n[M_NODES] && !bad; ++i) {
        const uint8_t *r = rec(w, M_NODES, i);
        int k;
        lump = M_NODES;
        for (k = 0; k < 2 && !bad; ++k) {
            uint32_t c = rd_u16(r + 24 + 2 * k);
            if (c & 0x8000u ? (c & 0x7fffu) >= w->n[M_SSECTORS] : c >= i)
                bad = c & 0x8000u ? "subsector" : "child node (not below it)", what = c & 0x7fffu,
                limit = c & 0x8000u ? w->n[M_SSECTORS] : i;
        }
        if (!bad && rd_i16(r + 4) == 0 && rd_i16(r + 6) == 0) bad = "a partition line of length 0", limit = 0;
    }
    if (!bad) return 0;
fail:
    if (!limit) tool_error_set(w->err, w->path, 0, "%s %s[%u]: %s", w->name, map_lumps[lump], i - 1, bad);
    else tool_error_set(w->err, w->path, 0, "%s %s[%u]: %s %u past the %u allowed", w->name, map_lumps[lump], i - 1,
                        bad, what, limit);
    return -1;
}

/* Clips q to the side of line (o, o + d) Doom calls front (right of d: dy (x - ox) - dx (y - oy) >= 0), or the
   other side when back. 0 if more than WAD_MAXV vertices would result (q then unchanged but for n = 0). */
static int clip_side(wad_poly *q, double ox, double oy, double dx, double dy, int back) {
    wad_poly r;
    uint32_t i;
    double s[WAD_MAXV], len = sqrt(dx * dx + dy * dy), tol = 1e-9 * len;
    r.n = 0;
    for (i = 0; i < q->n; ++i) {
        s[i] = dy * (q->p[i][0] - ox) - dx * (q->p[i][1] - oy);
        if (back) s[i] = -s[i];
    }
    for (i = 0; i < q->n; ++i) {
        uint32_t j = (i + 1) % q->n;
        if (s[i] >= -tol) {
            if (r.n == WAD_MAXV) return q->n = 0, 0;
            r.p[r.n][0] = q->p[i][0], r.p[r.n][1] = q->p[i][1], ++r.n;
        }
        if ((s[i] < -tol && s[j] > tol) || (s[i] > tol && s[j] < -tol)) {
            double t = s[i] / (s[i] - s[j]);
            if (r.n == WAD_MAXV) return q->n = 0, 0;
            r.p[r.n][0] = q->p[i][0] + t * (q->p[j][0] - q->p[i][0]);
            r.p[r.n][1] = q->p[i][1] + t * (q->p[j][1] - q->p[i][1]);
            ++r.n;
        }
    }
    *q = r;
    return 1;
}

static double poly_area(const wad_poly *q) {
    double a = 0.0;
    uint32_t i;
    for (i = 0; i < q->n; ++i) {
        uint32_t j = (i + 1) % q->n;
        a += q->p[i][0] * q->p[j][1] - q->p[j][0] * q->p[i][1];
    }
    return 0.5 * a;
}

typedef struct wad_polys {
    wad_poly *ss;     /* per subsector (n = 0: lost) */
    uint32_t lost;
    wad_poly *vo;     /* void: the parts of node regions outside their subsectors */
    uint32_t void_count, void_cap;
    int oom;
} wad_polys;

/* Appends q to the void pieces (if it has area). */
static void add_void(wad_polys *out, const wad_poly *q) {
    if (q->n < 3 || !(fabs(poly_area(q)) > 1e-6)) return;
    if (out->void_count == out->void_cap) {
        uint32_t cap = out->void_cap ? 2 * out->void_cap : 256;
        wad_poly *v = realloc(out->vo, (size_t)cap * sizeof(wad_poly));
        if (!v) {
            out->oom = 1;
            return;
        }
        out->vo = v, out->void_cap = cap;
    }
    out->vo[out->void_count++] = *q;
}

/* Subsector ss's polygon: region q (its node region) clipped by its segs' lines; what each clip cuts off is void. */
static void finish_subsector(const wad_map *w, uint32_t ss, wad_poly *q, wad_polys *out) {
    const uint8_t *r = rec(w, M_SSECTORS, ss);
    uint32_t c = rd_u16(r), f = rd_u16(r + 2), i;
    for (i = 0; i < c && q->n; ++i) {
        const uint8_t *sg = rec(w, M_SEGS, f + i), *a = rec(w, M_VERTEXES, rd_u16(sg)), *b = rec(w, M_VERTEXES, rd_u16(sg + 2));
        double ax = rd_i16(a), ay = rd_i16(a + 2), bx = rd_i16(b), by = rd_i16(b + 2);
        if (ax != bx || ay != by) {
            wad_poly back = *q;
            if (clip_side(&back, ax, ay, bx - ax, by - ay, 1)) add_void(out, &back);
            clip_side(q, ax, ay, bx - ax, by - ay, 0);
        }
    }
    if (q->n < 3 || !(fabs(poly_area(q)) > 1e-6)) q->n = 0, ++out->lost;
    out->ss[ss] = *q;
}

/* Node k's region q split by its partition down to the subsectors (depth: levels above). */
static int walk_nodes(const wad_map *w, uint32_t child, const wad_poly *q, uint32_t depth, wad_polys *out) {
    const uint8_t *r;
    double ox, oy, dx, dy;
    int side;
    if (child & 0x8000u) {
        wad_poly c = *q;
        finish_subsector(w, child & 0x7fffu, &c, out);
        return 0;
    }
    if (depth >= WAD_MAX_DEPTH) {
        tool_error_set(w->err, w->path, 0, "%s NODES: deeper than %d levels", w->name, WAD_MAX_DEPTH);
        return -1;
    }
    r = rec(w, M_NODES, child);
    ox = rd_i16(r), oy = rd_i16(r + 2), dx = rd_i16(r + 4), dy = rd_i16(r + 6);
    for (side = 0; side < 2; ++side) {
        wad_poly c = *q;
        clip_side(&c, ox, oy, dx, dy, side);
        if (walk_nodes(w, rd_u16(r + 24 + 2 * side), &c, depth + 1, out)) return -1;
    }
    return 0;
}

/* Sector of subsector ss: its first seg's side's. */
static uint32_t subsector_sector(const wad_map *w, uint32_t ss) {
    const uint8_t *sg = rec(w, M_SEGS, rd_u16(rec(w, M_SSECTORS, ss) + 2));
    const uint8_t *ld = rec(w, M_LINEDEFS, rd_u16(sg + 6));
    return rd_u16(rec(w, M_SIDEDEFS, rd_u16(ld + 10 + 2 * rd_u16(sg + 8))) + 28);
}

static int sector_sky(const wad_map *w, uint32_t s) {
    const uint8_t *c = rec(w, M_SECTORS, s) + 12;
    return toupper(c[0]) == 'F' && c[1] == '_' && toupper(c[2]) == 'S' && toupper(c[3]) == 'K' &&
           toupper(c[4]) == 'Y';
}

/* Vertical quad over map segment a-b from height lo to hi (Y up: (x, z, -y)), WAD_LIFT off the solid prism face it
   lies on, toward its open side (side 1: the line's front, on the right of a-b; -1: its back). */
static int add_wall(mesh *m, const uint8_t *a, const uint8_t *b, double lo, double hi, int side) {
    uint32_t v = m->vertex_count;
    double dx = rd_i16(b) - rd_i16(a), dy = rd_i16(b + 2) - rd_i16(a + 2), l = sqrt(dx * dx + dy * dy);
    double ox = l > 0.0 ? side * WAD_LIFT * dy / l : 0.0, oy = l > 0.0 ? -side * WAD_LIFT * dx / l : 0.0;
    float ax = (float)(rd_i16(a) + ox), ay = (float)(rd_i16(a + 2) + oy), bx = (float)(rd_i16(b) + ox),
          by = (float)(rd_i16(b + 2) + oy);
    if (mesh_add_vertex(m, ax, (float)lo, -ay) || mesh_add_vertex(m, bx, (float)lo, -by) ||
        mesh_add_vertex(m, bx, (float)hi, -by) || mesh_add_vertex(m, ax, (float)hi, -ay))
        return -1;
    return mesh_add_quad(m, v, v + 1, v + 2, v + 3);
}

static int add_walls(const wad_map *w, mesh *m, wad_stats *st) {
    uint32_t i;
    for (i = 0; i < w->n[M_LINEDEFS]; ++i) {
        const uint8_t *r = rec(w, M_LINEDEFS, i), *a = rec(w, M_VERTEXES, rd_u16(r)), *b = rec(w, M_VERTEXES, rd_u16(r + 2));
        uint32_t s1 = rd_u16(r + 10), s2 = rd_u16(r + 12);
        char name[24];
        snprintf(name, sizeof(name), "w%u", i);
        if (mesh_begin_object(m, name, 0, 0)) return -1;
        int front = 1; /* the side s1 is on: 1 front (right), -1 back (a line with a back side only) */
        if (s1 == WAD_NONE) s1 = s2, s2 = WAD_NONE, front = -1;
        if (s1 == WAD_NONE) continue;
        {
            uint32_t f = rd_u16(rec(w, M_SIDEDEFS, s1) + 28);
            const uint8_t *fs = rec(w, M_SECTORS, f);
            double ff = rd_i16(fs), fc = rd_i16(fs + 2);
            if (s2 == WAD_NONE) {
                if (fc > ff) {
                    if (add_wall(m, a, b, ff, fc, front)) return -1;
                    ++st->wall_quads;
                }
            } else {
                uint32_t k = rd_u16(rec(w, M_SIDEDEFS, s2) + 28);
                const uint8_t *ks = rec(w, M_SECTORS, k);
                double kf = rd_i16(ks), kc = rd_i16(ks + 2);
                if (ff != kf) {
                    if (add_wall(m, a, b, fmin(ff, kf), fmax(ff, kf), ff < kf ? 1 : -1)) return -1;
                    ++st->wall_quads;
                }
                if (fc != kc && !(sector_sky(w, f) && sector_sky(w, k))) {
                    if (add_wall(m, a, b, fmin(fc, kc), fmax(fc, kc), fc > kc ? 1 : -1)) return -1;
                    ++st->wall_quads;
                }
            }
        }
    }
    return 0;
}

/* Per sector: its subsectors' polygons at floor height, then at ceiling height (sky: occluder). */
static int add_flats(const wad_map *w, const wad_polys *pp, mesh *m, wad_stats *st) {
    uint32_t ns = w->n[M_SECTORS], nss = w->n[M_SSECTORS], s, i, k, *first = calloc((size_t)ns + 1, sizeof(uint32_t)),
             *list = malloc((size_t)nss * sizeof(uint32_t));
    int rc = first && list ? 0 : -1;
    for (i = 0; i < nss && !rc; ++i) ++first[subsector_sector(w, i) + 1];
    for (s = 0; s < ns && !rc; ++s) first[s + 1] += first[s];
    for (i = 0; i < nss && !rc; ++i) list[first[subsector_sector(w, i)]++] = i;
    for (s = ns; s > 0 && !rc; --s) first[s] = first[s - 1];
    if (!rc) first[0] = 0;
    for (s = 0; s < ns && !rc; ++s) {
        const uint8_t *sr = rec(w, M_SECTORS, s);
        int side, sky = sector_sky(w, s);
        st->sky_sectors += (uint32_t)sky;
        for (side = 0; side < 2 && !rc; ++side) {
            char name[32];
            float h = (float)(rd_i16(sr + 2 * side) + (side ? -WAD_LIFT : WAD_LIFT)); /* off the solid */
            snprintf(name, sizeof(name), side ? (sky ? "occluder_sky%u" : "ceil%u") : "floor%u", s);
            rc = mesh_begin_object(m, name, side && sky ? MESH_OBJECT_OCCLUDER : 0, 0);
            for (i = first[s]; i < first[s + 1] && !rc; ++i) {
                const wad_poly *q = pp->ss + list[i];
                uint32_t v = m->vertex_count;
                for (k = 0; k < q->n && !rc; ++k) rc = mesh_add_vertex(m, (float)q->p[k][0], h, (float)-q->p[k][1]);
                for (k = 1; k + 1 < q->n && !rc; ++k) rc = mesh_add_triangle(m, v, v + k, v + k + 1);
            }
        }
    }
    free(first);
    free(list);
    return rc;
}

/* Closed convex prism over polygon q from height lo to hi: its own corners, faces fanned (Y up). */
static int add_prism(mesh *m, const wad_poly *q, float lo, float hi) {
    uint32_t v = m->vertex_count, k, n = q->n;
    for (k = 0; k < n; ++k)
        if (mesh_add_vertex(m, (float)q->p[k][0], lo, (float)-q->p[k][1]) ||
            mesh_add_vertex(m, (float)q->p[k][0], hi, (float)-q->p[k][1]))
            return -1;
    for (k = 1; k + 1 < n; ++k)
        if (mesh_add_triangle(m, v, v + 2 * (k + 1), v + 2 * k) || mesh_add_triangle(m, v + 1, v + 2 * k + 1, v + 2 * (k + 1) + 1))
            return -1;
    for (k = 0; k < n; ++k) {
        uint32_t j = (k + 1) % n;
        if (mesh_add_quad(m, v + 2 * k, v + 2 * j, v + 2 * j + 1, v + 2 * k + 1)) return -1;
    }
    return 0;
}

/* The solid space, as closed convex prisms (what the portal method's rooms are built from): under each subsector's
   floor and over its ceiling (a sky too, as Doom draws it), and the void, floor to ceiling of the whole map and 64
   units beyond. */
static int add_solids(const wad_map *w, const wad_polys *pp, mesh *m, wad_stats *st) {
    float lo = 1e9f, hi = -1e9f;
    uint32_t i;
    for (i = 0; i < w->n[M_SECTORS]; ++i) {
        lo = fminf(lo, rd_i16(rec(w, M_SECTORS, i)));
        hi = fmaxf(hi, rd_i16(rec(w, M_SECTORS, i) + 2));
    }
    lo -= 64.0f, hi += 64.0f;
    if (mesh_begin_object(m, "occluder_solids", MESH_OBJECT_OCCLUDER, 0)) return -1;
    for (i = 0; i < w->n[M_SSECTORS]; ++i) {
        const uint8_t *sr = rec(w, M_SECTORS, subsector_sector(w, i));
        if (!pp->ss[i].n) continue;
        if (add_prism(m, pp->ss + i, lo, rd_i16(sr)) || add_prism(m, pp->ss + i, rd_i16(sr + 2), hi)) return -1;
        st->solids += 2;
    }
    for (i = 0; i < pp->void_count; ++i) {
        if (add_prism(m, pp->vo + i, lo, hi)) return -1;
        ++st->solids;
    }
    return 0;
}

static int add_cells(const wad_map *w, const wad_polys *pp, uint32_t step, mesh_cells *cells, wad_stats *st) {
    uint32_t i, k, open = 0;
    for (i = 0; i < w->n[M_SSECTORS]; ++i) {
        const wad_poly *q = pp->ss + i;
        const uint8_t *sr = rec(w, M_SECTORS, subsector_sector(w, i));
        float lo = rd_i16(sr), hi = rd_i16(sr + 2), box[6];
        double b[6];
        if (!q->n || !(hi > lo) || open++ % step) continue;
        b[0] = b[3] = q->p[0][0];
        b[2] = b[5] = -q->p[0][1];
        for (k = 1; k < q->n; ++k) {
            b[0] = fmin(b[0], q->p[k][0]), b[3] = fmax(b[3], q->p[k][0]);
            b[2] = fmin(b[2], -q->p[k][1]), b[5] = fmax(b[5], -q->p[k][1]);
        }
        /* out to the grid; a vertex within 1e-6 of a grid step of a grid line (clipping's rounding, which differs
           between FLT_EVAL_METHODs: x87 keeps a vertex on a line at -1e-13) counts as on it */
        for (k = 0; k < 3; k += 2) {
            box[k] = (float)(WAD_CELL_GRID * floor(b[k] / WAD_CELL_GRID + 1e-6));
            box[k + 3] = (float)(WAD_CELL_GRID * ceil(b[k + 3] / WAD_CELL_GRID - 1e-6));
        }
        box[1] = lo, box[4] = hi;
        if (mesh_cells_add(cells, box)) return -1;
        ++st->cells;
    }
    return 0;
}

int wad_parse(const char *path, const void *data, size_t size, const char *map, const wad_options *opt, mesh *m,
              mesh_cells *cells, wad_stats *stats, tool_error *err) {
    wad_map w;
    wad_polys pp;
    wad_stats st;
    int rc = 0;
    memset(&w, 0, sizeof(w));
    memset(&pp, 0, sizeof(pp));
    memset(&st, 0, sizeof(st));
    w.path = path;
    w.err = err;
    mesh_init(m);
    if (cells) mesh_cells_init(cells);
    if (find_map(&w, (const uint8_t *)data, size, map) || check_indices(&w)) return -1;
    pp.ss = calloc(w.n[M_SSECTORS], sizeof(wad_poly));
    if (!pp.ss) rc = 1;
    if (!rc) { /* the region: the map's vertices' box, a unit out */
        wad_poly q;
        double lo[2] = {1e9, 1e9}, hi[2] = {-1e9, -1e9};
        uint32_t i;
        int k;
        for (i = 0; i < w.n[M_VERTEXES]; ++i)
            for (k = 0; k < 2; ++k) {
                double x = rd_i16(rec(&w, M_VERTEXES, i) + 2 * k);
                lo[k] = fmin(lo[k], x - 1.0), hi[k] = fmax(hi[k], x + 1.0);
            }
        q.n = 4;
        q.p[0][0] = lo[0], q.p[0][1] = lo[1], q.p[1][0] = hi[0], q.p[1][1] = lo[1];
        q.p[2][0] = hi[0], q.p[2][1] = hi[1], q.p[3][0] = lo[0], q.p[3][1] = hi[1];
        if (poly_area(&q) < 0) { /* counter-clockwise in map coordinates */
            wad_poly t = q;
            for (k = 0; k < 4; ++k) q.p[k][0] = t.p[3 - k][0], q.p[k][1] = t.p[3 - k][1];
        }
        rc = w.n[M_NODES] ? walk_nodes(&w, w.n[M_NODES] - 1, &q, 0, &pp) : (finish_subsector(&w, 0, &q, &pp), 0);
        if (rc) rc = -1;
    }
    if (!rc) rc = add_walls(&w, m, &st) ? 1 : 0;
    if (!rc) rc = add_flats(&w, &pp, m, &st) ? 1 : 0;
    if (!rc && pp.oom) rc = 1;
    if (!rc && !(opt && opt->no_solids)) rc = add_solids(&w, &pp, m, &st) ? 1 : 0;
    if (!rc && cells) rc = add_cells(&w, &pp, opt && opt->cell_step > 1 ? opt->cell_step : 1, cells, &st) ? 1 : 0;
    if (rc > 0) tool_error_set(err, path, 0, "out of memory");
    memcpy(st.map, w.name, sizeof(st.map));
    st.linedefs = w.n[M_LINEDEFS];
    st.sectors = w.n[M_SECTORS];
    st.subsectors = w.n[M_SSECTORS];
    st.lost_subsectors = pp.lost;
    if (stats) *stats = st;
    free(pp.ss);
    free(pp.vo);
    return rc ? -1 : 0;
}
