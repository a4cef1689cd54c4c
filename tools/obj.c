/* obj.c - see obj.h */
#define _POSIX_C_SOURCE 200809L
#include "obj.h"
#include <limits.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#define OBJ__MAX_COUNT 0xfffffffeu /* vertex / triangle ids must stay below 2^32 - 1 */

/* ---- shared text helpers --------------------------------------------------------------------- */

static int obj__ws(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f'; }

static int obj__lower(int c) { return c >= 'A' && c <= 'Z' ? c - 'A' + 'a' : c; }

/* Case-insensitive: does [s, e) start with the NUL-terminated word w? */
static int obj__starts(const char *s, const char *e, const char *w) {
    for (; *w; ++s, ++w)
        if (s >= e || obj__lower((unsigned char)*s) != *w) return 0;
    return 1;
}

/* The line starting at p (before end) ends at the returned pointer; *next is where the next begins.
   LF, CRLF and a lone CR (old Mac files) all end a line. */
static const char *obj__line(const char *p, const char *end, const char **next) {
    const char *lf = (const char *)memchr(p, '\n', (size_t)(end - p)), *stop = lf ? lf : end;
    const char *cr = (const char *)memchr(p, '\r', (size_t)(stop - p));
    if (cr && cr + 1 != lf) { /* a lone CR ends this line */
        *next = cr + 1;
        return cr;
    }
    *next = lf ? lf + 1 : end;
    return cr ? cr : stop;
}

/* Rejects NUL bytes and control characters other than tab, LF, CR, VT and FF (and DEL). */
static int obj__check_binary(const char *name, const char *text, size_t len, tool_error *err) {
    int line = 1;
    for (size_t i = 0; i < len; ++i) {
        unsigned char c = (unsigned char)text[i];
        if (c == '\n' || (c == '\r' && (i + 1 == len || text[i + 1] != '\n'))) { /* LF, CRLF, CR */
            if (line < INT_MAX) ++line;
        } else if ((c < 0x20 && c != '\t' && c != '\r' && c != '\v' && c != '\f') || c == 0x7f) {
            tool_error_set(err, name, line, "binary data at byte %llu (0x%02x): not a text file",
                           (unsigned long long)i, c);
            return -1;
        }
    }
    return 0;
}

/* Next token in [*p, e): skips whitespace; stops at a comment ('#' at the start of a token, or inside
   one unless it is an MSVC-style "1.#INF" / "1.#IND" / "1.#QNAN" / "1.#SNAN"). Returns 0 when the line
   has no more tokens. */
static int obj__token(const char **p, const char *e, const char **ts, const char **te) {
    const char *s = *p;
    while (s < e && obj__ws(*s)) ++s;
    if (s >= e || *s == '#') {
        *p = e;
        return 0;
    }
    const char *t = s;
    while (t < e && !obj__ws(*t)) {
        if (*t == '#' && !(obj__starts(t + 1, e, "inf") || obj__starts(t + 1, e, "ind") ||
                           obj__starts(t + 1, e, "qnan") || obj__starts(t + 1, e, "snan")))
            break;
        ++t;
    }
    *ts = s;
    *te = t;
    *p = t < e && *t == '#' ? e : t;
    return 1;
}

enum { NUM_OK, NUM_BAD, NUM_NONFINITE, NUM_RANGE };

/* Strict decimal number [+-](digits[.digits*]|.digits)[(e|E)[+-]digits] -> float. */
static int obj__number(const char *s, const char *e, float *out) {
    const char *c = s;
    if (c < e && (*c == '+' || *c == '-')) ++c;
    /* Non-finite spellings: nan, nan(...), inf, infinity, and MSVC's 1.#INF / -1.#IND / 1.#QNAN. */
    if (obj__starts(c, e, "nan") || obj__starts(c, e, "inf")) {
        size_t n = (size_t)(e - c);
        if (n == 3 || (n == 8 && obj__starts(c, e, "infinity")) ||
            (obj__starts(c, e, "nan(") && e[-1] == ')'))
            return NUM_NONFINITE;
        return NUM_BAD;
    }
    for (const char *h = c; h < e; ++h)
        if (*h == '#') return NUM_NONFINITE; /* the tokenizer only lets '#' through for #INF etc. */
    int digits = 0;
    while (c < e && *c >= '0' && *c <= '9') ++c, ++digits;
    if (c < e && *c == '.') {
        ++c;
        while (c < e && *c >= '0' && *c <= '9') ++c, ++digits;
    }
    if (!digits) return NUM_BAD;
    if (c < e && (*c == 'e' || *c == 'E')) {
        ++c;
        if (c < e && (*c == '+' || *c == '-')) ++c;
        if (c >= e || *c < '0' || *c > '9') return NUM_BAD;
        while (c < e && *c >= '0' && *c <= '9') ++c;
    }
    if (c != e) return NUM_BAD;
    /* Valid syntax: let strtod (C locale) do the exact conversion on a NUL-terminated copy. */
    char small[72], *buf = small;
    size_t n = (size_t)(e - s);
    if (n >= sizeof(small)) {
        buf = (char *)malloc(n + 1);
        if (!buf) return NUM_BAD;
    }
    memcpy(buf, s, n);
    buf[n] = '\0';
    char *end = NULL;
    double d = strtod(buf, &end);
    int consumed = end == buf + n;
    if (buf != small) free(buf);
    if (!consumed) return NUM_BAD; /* e.g. a locale whose decimal point is not '.' */
    float f = (float)d;
    if (!isfinite(d) || !isfinite(f)) return NUM_RANGE;
    *out = f;
    return NUM_OK;
}

/* Prints at most 40 characters of a token for messages. */
#define OBJ__TOK(s, e) ((e) - (s) > 40 ? 40 : (int)((e) - (s))), (s)

static int obj__number_error(const char *name, int line, int r, const char *s, const char *e, tool_error *err) {
    if (r == NUM_NONFINITE) tool_error_set(err, name, line, "coordinate is not finite ('%.*s')", OBJ__TOK(s, e));
    else if (r == NUM_RANGE) tool_error_set(err, name, line, "number out of range ('%.*s' overflows a float)", OBJ__TOK(s, e));
    else tool_error_set(err, name, line, "bad number '%.*s'", OBJ__TOK(s, e));
    return -1;
}

/* ---- OBJ ------------------------------------------------------------------------------------- */

/* Does any line start with the statement "o"? */
static int obj__has_o(const char *text, size_t len) {
    const char *p = text, *end = text + len;
    while (p < end) {
        const char *next, *le = obj__line(p, end, &next);
        const char *s = p;
        while (s < le && obj__ws(*s)) ++s;
        if (s < le && *s == 'o' && (s + 1 == le || obj__ws(s[1]) || s[1] == '#')) return 1;
        p = next;
    }
    return 0;
}

static int obj__begin(mesh *m, const char *name, const char *s, const char *e, const char *fallback, int line,
                      tool_error *err) {
    while (s < e && obj__ws(*s)) ++s;
    while (e > s && obj__ws(e[-1])) --e;
    size_t n = (size_t)(e - s);
    const char *src = n ? s : fallback;
    if (!n) n = strlen(fallback);
    char *copy = (char *)malloc(n + 1);
    if (!copy) {
        tool_error_set(err, name, line, "out of memory");
        return -1;
    }
    memcpy(copy, src, n);
    copy[n] = '\0';
    uint32_t flags = strncmp(copy, "occluder", 8) == 0 ? MESH_OBJECT_OCCLUDER
                     : !strncmp(copy, "glass", 5) || !strncmp(copy, "door", 4) || !strncmp(copy, "see_through", 11)
                         ? MESH_OBJECT_SEE_THROUGH
                     : !strncmp(copy, "one_sided", 9) ? MESH_OBJECT_ONE_SIDED
                                                      : 0;
    int r = mesh_begin_object(m, copy, flags, (uint32_t)line);
    free(copy);
    if (r) tool_error_set(err, name, line, "out of memory");
    return r;
}

/* Parses one face vertex "v", "v/vt", "v//vn", "v/vt/vn" into a 0-based position index. */
static int obj__face_vertex(const char *name, int line, const char *s, const char *e, uint32_t vcount,
                            uint32_t *out, tool_error *err) {
    const char *c = s;
    int neg = 0;
    if (c < e && (*c == '+' || *c == '-')) neg = *c++ == '-';
    const char *ds = c;
    uint64_t v = 0;
    int big = 0;
    while (c < e && *c >= '0' && *c <= '9') {
        v = v * 10 + (uint64_t)(*c - '0');
        if (v > 0xffffffffffull) big = 1, v = 0xffffffffffull;
        ++c;
    }
    if (c == ds) {
        if (c == s && (c == e || *c == '/')) {
            tool_error_set(err, name, line, "missing vertex index in '%.*s'", OBJ__TOK(s, e));
            return -1;
        }
        tool_error_set(err, name, line, "bad face index '%.*s'", OBJ__TOK(s, e));
        return -1;
    }
    /* Optional /vt and /vn parts: integers or empty, not range-checked. */
    for (int part = 0; part < 2 && c < e; ++part) {
        if (*c != '/') break;
        ++c;
        if (c < e && (*c == '+' || *c == '-')) {
            ++c;
            if (c >= e || *c < '0' || *c > '9') break;
        }
        while (c < e && *c >= '0' && *c <= '9') ++c;
    }
    if (c != e) {
        tool_error_set(err, name, line, "bad face index '%.*s'", OBJ__TOK(s, e));
        return -1;
    }
    if (big) {
        tool_error_set(err, name, line, "face index '%.*s' out of range (number too large)", OBJ__TOK(s, e));
        return -1;
    }
    if (v == 0) {
        tool_error_set(err, name, line, "face index 0 is invalid (OBJ indices start at 1)");
        return -1;
    }
    if (v > vcount) {
        tool_error_set(err, name, line, "face index %s%llu out of range (%u vertices defined so far)",
                       neg ? "-" : "", (unsigned long long)v, vcount);
        return -1;
    }
    *out = neg ? (uint32_t)(vcount - v) : (uint32_t)(v - 1);
    return 0;
}

int obj_parse(const char *name, const char *text, size_t len, mesh *m, tool_error *err) {
    mesh_init(m);
    if (len == 0) {
        tool_error_set(err, name, 0, "empty file");
        return -1;
    }
    if (obj__check_binary(name, text, len, err)) return -1;
    const char *p = text, *end = text + len;
    if (len >= 3 && (unsigned char)p[0] == 0xEF && (unsigned char)p[1] == 0xBB && (unsigned char)p[2] == 0xBF)
        p += 3;
    int has_o = obj__has_o(p, (size_t)(end - p));
    int line = 0;
    while (p < end) {
        const char *next, *le = obj__line(p, end, &next);
        if (line < INT_MAX) ++line;
        const char *q = p, *ks, *ke;
        p = next;
        if (!obj__token(&q, le, &ks, &ke)) continue;
        size_t kn = (size_t)(ke - ks);
        if (kn == 1 && ks[0] == 'v') {
            float xyz[3];
            int n = 0;
            const char *ts, *te;
            while (obj__token(&q, le, &ts, &te)) {
                float f = 0;
                int r = obj__number(ts, te, &f);
                if (r != NUM_OK && !(n >= 3 && r != NUM_BAD)) /* extras (w, colour) need only be numbers */
                    return mesh_free(m), obj__number_error(name, line, r, ts, te, err);
                if (n < 3) xyz[n] = f;
                ++n;
            }
            if (n < 3) {
                mesh_free(m);
                tool_error_set(err, name, line, "missing coordinates: a vertex needs 3 numbers, found %d", n);
                return -1;
            }
            if (m->vertex_count >= OBJ__MAX_COUNT) {
                mesh_free(m);
                tool_error_set(err, name, line, "too many vertices (more than %u)", OBJ__MAX_COUNT);
                return -1;
            }
            if (mesh_add_vertex(m, xyz[0], xyz[1], xyz[2])) {
                mesh_free(m);
                tool_error_set(err, name, line, "out of memory");
                return -1;
            }
        } else if (kn == 1 && ks[0] == 'f') {
            uint32_t first = 0, prev = 0, idx;
            int n = 0;
            const char *ts, *te;
            while (obj__token(&q, le, &ts, &te)) {
                if (obj__face_vertex(name, line, ts, te, m->vertex_count, &idx, err)) return mesh_free(m), -1;
                if (n >= 2) {
                    if (m->object_count == 0 && obj__begin(m, name, NULL, NULL, "default", line, err))
                        return mesh_free(m), -1;
                    if (m->triangle_count >= 0xffffffffu / 3) {
                        mesh_free(m);
                        tool_error_set(err, name, line, "too many triangles (more than %u)", 0xffffffffu / 3);
                        return -1;
                    }
                    if (mesh_add_triangle(m, first, prev, idx)) {
                        mesh_free(m);
                        tool_error_set(err, name, line, "out of memory");
                        return -1;
                    }
                } else if (n == 0) {
                    first = idx;
                }
                prev = idx;
                if (n < INT_MAX) ++n;
            }
            if (n < 3) {
                mesh_free(m);
                tool_error_set(err, name, line, "face has fewer than 3 vertices (%d)", n);
                return -1;
            }
        } else if (kn == 1 && (ks[0] == 'o' || (ks[0] == 'g' && !has_o))) {
            /* The name is the raw rest of the line (it may contain '#' or spaces). */
            if (obj__begin(m, name, ke, le, ks[0] == 'o' ? "unnamed" : "default", line, err))
                return mesh_free(m), -1;
        }
        /* Everything else (vt, vn, vp, g with o present, s, l, p, usemtl, mtllib, ...) is ignored. */
    }
    if (m->triangle_count == 0) {
        mesh_free(m);
        tool_error_set(err, name, 0, "no faces");
        return -1;
    }
    return 0;
}

int obj_load(const char *path, mesh *m, tool_error *err) {
    void *data;
    size_t size;
    mesh_init(m);
    if (read_file(path, &data, &size, err)) return -1;
    int r = obj_parse(path, (const char *)data, size, m, err);
    free(data);
    return r;
}

uint32_t obj_check_empty_objects(const char *path, const mesh *m, tool_error *first) {
    uint32_t count = 0;
    for (uint32_t i = 0; i < m->object_count; ++i) {
        const mesh_object *o = &m->objects[i];
        if (o->triangle_count) continue;
        if (count++ == 0)
            tool_error_set(first, path, (int)(o->line > INT_MAX ? INT_MAX : o->line),
                           "object %u '%.60s' has no faces", i, o->name);
    }
    return count;
}

/* ---- cells ----------------------------------------------------------------------------------- */

int cells_parse(const char *name, const char *text, size_t len, mesh_cells *c, tool_error *err) {
    mesh_cells_init(c);
    if (obj__check_binary(name, text, len, err)) return -1;
    const char *p = text, *end = text + len;
    if (len >= 3 && (unsigned char)p[0] == 0xEF && (unsigned char)p[1] == 0xBB && (unsigned char)p[2] == 0xBF)
        p += 3;
    int line = 0;
    while (p < end) {
        const char *next, *le = obj__line(p, end, &next);
        if (line < INT_MAX) ++line;
        const char *q = p, *ts, *te;
        p = next;
        float box[6];
        int n = 0;
        while (obj__token(&q, le, &ts, &te)) {
            float f = 0;
            int r = obj__number(ts, te, &f);
            if (r != NUM_OK) return mesh_cells_free(c), obj__number_error(name, line, r, ts, te, err);
            if (n < 6) box[n] = f;
            ++n;
        }
        if (n == 0) continue;
        if (n != 6) {
            mesh_cells_free(c);
            tool_error_set(err, name, line, "expected 6 numbers (minx miny minz maxx maxy maxz), found %d", n);
            return -1;
        }
        for (int a = 0; a < 3; ++a)
            if (box[a] > box[a + 3]) {
                mesh_cells_free(c);
                tool_error_set(err, name, line, "min greater than max on the %c axis (%.9g > %.9g)", "xyz"[a],
                               (double)box[a], (double)box[a + 3]);
                return -1;
            }
        if (c->count >= OBJ__MAX_COUNT) {
            mesh_cells_free(c);
            tool_error_set(err, name, line, "too many cells");
            return -1;
        }
        if (mesh_cells_add_line(c, box, (uint32_t)line)) {
            mesh_cells_free(c);
            tool_error_set(err, name, line, "out of memory");
            return -1;
        }
    }
    if (c->count == 0) {
        mesh_cells_free(c);
        tool_error_set(err, name, 0, "no cells");
        return -1;
    }
    return 0;
}

int cells_load(const char *path, mesh_cells *c, tool_error *err) {
    void *data;
    size_t size;
    mesh_cells_init(c);
    if (read_file(path, &data, &size, err)) return -1;
    int r = cells_parse(path, (const char *)data, size, c, err);
    free(data);
    return r;
}
