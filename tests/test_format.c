/* test_format.c - the .pvs file: round trips, look-up, chains, the cursor, every truncation,
   corruptions with valid checksums, shards, the golden file and the fuzzing corpus */
#define _POSIX_C_SOURCE 200809L
#include "test.h"
#include "../pvs.h"
#include <dirent.h>
#include <stdint.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

static uint64_t rng_state = 12345;
static uint32_t rnd(void) { return test_lcg31(&rng_state); }

/* A random table. Cells lie on a 3D grid (nx x ny x nz, unit size, optional overlap and gaps); each
   cell's PVS is its grid predecessor's with `change_pct` of the objects flipped (coherence), or a
   fresh random set of `density_pct` when change_pct is 100. */
static void make_table(uint32_t cells, uint32_t objects, uint32_t density_pct, uint32_t change_pct, int overlap, pvs_box *boxes,
                       pvs_word *pvs) {
    size_t words = PVS_BITSET_WORDS(objects);
    uint32_t c, o, nx = 1 + (uint32_t)(rnd() % 12), ny = 1 + (uint32_t)(rnd() % 3);
    memset(pvs, 0, cells * words * sizeof(pvs_word));
    for (c = 0; c < cells; ++c) {
        uint32_t g[3];
        int k;
        g[0] = c % nx;
        g[1] = (c / nx) % ny;
        g[2] = c / (nx * ny);
        for (k = 0; k < 3; ++k) {
            boxes[c].min[k] = (float)g[k] * 2.0f - (k == 1 ? 0.0f : 7.5f);
            boxes[c].max[k] = boxes[c].min[k] + (overlap ? 2.5f : (rnd() % 3 ? 2.0f : 1.0f));
        }
        for (o = 0; o < objects; ++o) {
            int on;
            if (c > 0 && change_pct < 100) on = pvs_bitset_test(pvs + (c - 1) * words, o) ^ (rnd() % 1000 < change_pct * 10u);
            else on = rnd() % 100 < density_pct;
            if (on) pvs_bitset_set(pvs + c * words, o);
        }
        if (change_pct < 100 && rnd() % 50 == 0) /* a contiguous run now and then */
            for (o = rnd() % objects; o < objects && rnd() % 40; ++o) pvs_bitset_set(pvs + c * words, o);
    }
}

static int expect_open(const uint8_t *data, size_t size, pvs_result want) {
    pvs_file f;
    pvs_error e;
    pvs_result r = pvs_file_open(data, size, &f, &e);
    if (r != want) fprintf(stderr, "open: got %d (%s), want %d\n", (int)r, e.message, (int)want);
    return r == want && e.result == r;
}

static uint8_t *encode(const pvs_file_desc *d, size_t *size) {
    pvs_error e;
    uint8_t *buf;
    *size = 0;
    if (pvs_file_encode(d, NULL, 0, size, &e) != PVS_OK || !*size) { fprintf(stderr, "encode: %s\n", e.message); return NULL; }
    buf = (uint8_t *)malloc(*size);
    if (pvs_file_encode(d, buf, *size, size, &e) != PVS_OK) { fprintf(stderr, "encode: %s\n", e.message); free(buf); return NULL; }
    return buf;
}

static void desc_init(pvs_file_desc *d, const pvs_box *boxes, uint32_t cells, uint32_t objects, const pvs_word *pvs) {
    memset(d, 0, sizeof(*d));
    d->cells = boxes;
    d->cell_count = cells;
    d->object_count = objects;
    d->pvs = pvs;
    d->method = PVS_METHOD_SAMPLE;
    d->eps = 0.5f;
    d->up_axis = 1;
    d->flags = PVS_FILE_APPROXIMATE;
}

typedef struct change_log {
    pvs_word *expect;   /* the set the cursor should reach, applied by the callback */
    uint32_t last[2], count[2];
    int ordered;        /* removals ascending, additions ascending */
} change_log;
static void on_change(void *user, uint32_t object, int visible) {
    change_log *l = (change_log *)user;
    if (l->count[visible] && object <= l->last[visible]) l->ordered = 0;
    l->last[visible] = object;
    ++l->count[visible];
    if (visible) pvs_bitset_set(l->expect, object);
    else pvs_bitset_clear(l->expect, object);
}

static uint32_t linear_find(const pvs_file *f, const float p[3]) {
    uint32_t c;
    for (c = 0; c < f->cell_count; ++c) {
        pvs_box b = pvs_file_cell_box(f, c);
        if (p[0] >= b.min[0] && p[0] <= b.max[0] && p[1] >= b.min[1] && p[1] <= b.max[1] && p[2] >= b.min[2] && p[2] <= b.max[2]) return c;
    }
    return PVS_NO_CELL;
}

static int orders_seen[2]; /* files with objects in id order, reordered */

/* pvs_file_desc.pvs_row over a table: odd cells copied into the encoder's buffer, even ones given in place. */
typedef struct row_table {
    const pvs_word *pvs;
    size_t words;
    uint32_t calls;
} row_table;
static const pvs_word *table_row(const void *user, uint32_t cell, pvs_word *buffer) {
    row_table *t = (row_table *)(uintptr_t)user;
    ++t->calls;
    if (!(cell & 1)) return t->pvs + cell * t->words;
    memcpy(buffer, t->pvs + cell * t->words, t->words * sizeof(pvs_word));
    return buffer;
}

/* Round trip, look-up against a linear scan, chains within K, cursor against decode. */
static void check_table(uint32_t cells, uint32_t objects, uint32_t density, uint32_t change, int overlap, uint32_t max_chain, int truncations) {
    size_t words = PVS_BITSET_WORDS(objects), size, size2;
    pvs_box *boxes = (pvs_box *)malloc(cells * sizeof(pvs_box));
    pvs_word *pvs = (pvs_word *)malloc(cells * words * sizeof(pvs_word));
    pvs_word *got = (pvs_word *)malloc((words + 1) * sizeof(pvs_word)), *cur = (pvs_word *)malloc(words * sizeof(pvs_word));
    pvs_word *scratch = (pvs_word *)malloc(words * sizeof(pvs_word)), *expect = (pvs_word *)calloc(words, sizeof(pvs_word));
    pvs_file_desc d;
    pvs_file f;
    pvs_error e;
    pvs_cursor cursor;
    uint8_t *buf, *again;
    uint32_t c, keys = 0, i;
    make_table(cells, objects, density, change, overlap, boxes, pvs);
    desc_init(&d, boxes, cells, objects, pvs);
    d.max_chain = max_chain;
    buf = encode(&d, &size);
    CHECK(buf != NULL);
    if (!buf) return;
    CHECK(size % 8 == 0);
    CHECK(pvs_file_encode(&d, buf, size - 1, &size2, &e) == PVS_ERROR_BUFFER_TOO_SMALL && size2 == size);
    again = encode(&d, &size2); /* deterministic */
    CHECK(again && size2 == size && memcmp(buf, again, size) == 0);
    free(again);
    {   /* rows on demand (a compact bake, a merge): the same bytes */
        row_table t;
        t.pvs = pvs;
        t.words = words;
        t.calls = 0;
        d.pvs = NULL;
        d.pvs_row = table_row;
        d.pvs_user = &t;
        again = encode(&d, &size2);
        CHECK(again && size2 == size && memcmp(buf, again, size) == 0 && t.calls >= 2 * cells);
        free(again);
        d.pvs = pvs;
        d.pvs_row = NULL;
    }
    CHECK(pvs_file_open(buf, size, &f, &e) == PVS_OK);
    CHECK(f.cell_count == cells && f.object_count == objects && f.method == PVS_METHOD_SAMPLE && f.eps == 0.5f);
    CHECK(f.flags == PVS_FILE_APPROXIMATE && f.up_axis == 1 && f.max_chain == (max_chain ? max_chain : PVS_DEFAULT_CHAIN));
    for (c = 0; c < cells; ++c) {
        pvs_box b = pvs_file_cell_box(&f, c);
        pvs_record_info info;
        CHECK(memcmp(&b, &boxes[c], sizeof(b)) == 0);
        got[words] = 12345;
        CHECK(pvs_file_decode(&f, c, got, words + 1, &e) == PVS_OK);
        CHECK(memcmp(got, pvs + c * words, words * sizeof(pvs_word)) == 0 && got[words] == 0);
        pvs_file_get_record_info(&f, c, &info);
        CHECK(info.depth <= f.max_chain && info.bytes > 0);
        CHECK((info.depth == 0) == (info.base == PVS_NO_CELL));
        if (info.base != PVS_NO_CELL) {
            pvs_record_info bi;
            pvs_file_get_record_info(&f, info.base, &bi);
            CHECK(bi.depth + 1 == info.depth);
        }
        keys += info.depth == 0;
    }
    CHECK(keys == f.key_count);
    orders_seen[f.private_.order_bits != 0] = 1;
    /* look-up: random points, cell corners (shared faces), points outside */
    for (i = 0; i < 2000; ++i) {
        float p[3];
        int k;
        if (i % 2) {
            pvs_box b = pvs_file_cell_box(&f, rnd() % cells);
            for (k = 0; k < 3; ++k) p[k] = rnd() % 2 ? b.min[k] : b.max[k];
        } else {
            for (k = 0; k < 3; ++k) p[k] = (float)((int)(rnd() % 6000) - 1000) * 0.01f;
        }
        CHECK(pvs_file_find_cell(&f, p) == linear_find(&f, p));
    }
    {
        float nan3[3] = {NAN, 0, 0};
        CHECK(pvs_file_find_cell(&f, nan3) == PVS_NO_CELL);
    }
    /* cursor: a walk of neighbours and jumps; callbacks give exactly the differences, ascending */
    CHECK(pvs_cursor_init(&cursor, &f, cur, scratch, words, &e) == PVS_OK);
    c = 0;
    for (i = 0; i < 200; ++i) {
        change_log log;
        uint32_t next = rnd() % 4 ? (c + 1) % cells : rnd() % cells;
        if (i == 100) next = PVS_NO_CELL;
        memset(&log, 0, sizeof(log));
        log.expect = expect;
        log.ordered = 1;
        CHECK(pvs_cursor_move(&cursor, next, on_change, &log) == PVS_OK);
        CHECK(cursor.cell == next && log.ordered);
        if (next != PVS_NO_CELL) CHECK(memcmp(cur, pvs + next * words, words * sizeof(pvs_word)) == 0);
        else CHECK(pvs_bitset_count(cur, objects) == 0);
        CHECK(memcmp(cur, expect, words * sizeof(pvs_word)) == 0);
        c = next == PVS_NO_CELL ? 0 : next;
    }
    CHECK(cursor.delta_moves + cursor.full_moves > 0);
    CHECK(pvs_cursor_move(&cursor, cells, NULL, NULL) == PVS_ERROR_INVALID_ARGUMENT);
    CHECK(pvs_file_decode(&f, cells, got, words, &e) == PVS_ERROR_INVALID_ARGUMENT);
    if (words > 1) CHECK(pvs_file_decode(&f, 0, got, words - 1, &e) == PVS_ERROR_BUFFER_TOO_SMALL);
    if (truncations) { /* every truncated prefix is rejected, from a buffer flush against its allocation's end */
        size_t n;
        for (n = 0; n < size; n += (size > 4000 ? 7 : 1)) {
            uint8_t *cut = (uint8_t *)malloc(n ? n : 1);
            pvs_result r;
            memcpy(cut, buf, n);
            r = pvs_file_open(cut, n, &f, &e);
            CHECK(r == PVS_ERROR_TRUNCATED || r == PVS_ERROR_BAD_HEADER);
            free(cut);
        }
    }
    free(buf);
    free(boxes);
    free(pvs);
    free(got);
    free(cur);
    free(scratch);
    free(expect);
}

static void test_round_trip(void) {
    static const uint32_t shapes[][7] = {
        /* cells, objects, density %, change %, overlap, K, truncations */
        {1, 1, 50, 100, 0, 0, 1},   {1, 64, 0, 100, 0, 0, 1},   {3, 64, 100, 100, 0, 1, 1},  {17, 65, 10, 5, 0, 0, 1},
        {100, 1000, 5, 2, 0, 0, 1}, {50, 3000, 60, 100, 0, 2, 0}, {7, 130, 100, 0, 1, 0, 1},  {300, 700, 20, 1, 0, 0, 0},
        {300, 700, 3, 1, 1, 1, 0},  {257, 2000, 1, 100, 0, 64, 0}, {120, 5000, 40, 3, 0, 3, 0}, {1000, 100, 30, 10, 0, 0, 0},
    };
    size_t s;
    int k;
    for (s = 0; s < sizeof(shapes) / sizeof(shapes[0]); ++s)
        check_table(shapes[s][0], shapes[s][1], shapes[s][2], shapes[s][3], (int)shapes[s][4], shapes[s][5], (int)shapes[s][6]);
    for (k = 0; k < 2; ++k) CHECK(orders_seen[k]); /* the object order pays somewhere, not everywhere */
}

/* Tables that force particular codings and layouts: whole ranges of objects leaving and entering
   (runs of removal ranks), all or nothing, and crossing cells (long rows over long columns, where a
   median split alone cannot divide them). */
static void test_special_tables(void) {
    enum { CELLS = 64, OBJECTS = 700 };
    size_t words = PVS_BITSET_WORDS(OBJECTS), size;
    static pvs_box boxes[CELLS];
    static pvs_word pvs[CELLS * PVS_BITSET_WORDS(OBJECTS)], cur[PVS_BITSET_WORDS(OBJECTS)], scratch[PVS_BITSET_WORDS(OBJECTS)],
        got[PVS_BITSET_WORDS(OBJECTS)];
    uint32_t c, o, i, deltas;
    int layout;
    for (layout = 0; layout < 2; ++layout) {
        pvs_file_desc d;
        pvs_file f;
        pvs_cursor cursor;
        uint8_t *buf;
        memset(pvs, 0, sizeof(pvs));
        for (c = 0; c < CELLS; ++c) {
            int k;
            uint32_t lo = (c * 37u) % OBJECTS, hi = lo + (c % 5 == 0 ? 0u : c % 5 == 1 ? OBJECTS : 1u + (c * 53u) % 300u);
            if (layout == 0) { /* a line of cells */
                for (k = 0; k < 3; ++k) {
                    boxes[c].min[k] = k == 0 ? (float)c : 0.0f;
                    boxes[c].max[k] = k == 0 ? (float)c + 1.0f : 1.0f;
                }
            } else { /* crossing: rows over the whole x range, columns over the whole z range */
                uint32_t h = CELLS / 2, j = c % h;
                boxes[c].min[1] = 0.0f;
                boxes[c].max[1] = 1.0f;
                boxes[c].min[0] = c < h ? 0.0f : (float)j;
                boxes[c].max[0] = c < h ? (float)h : (float)j + 1.0f;
                boxes[c].min[2] = c < h ? (float)j : 0.0f;
                boxes[c].max[2] = c < h ? (float)j + 1.0f : (float)h;
            }
            for (o = lo; o < hi && o < OBJECTS; ++o) pvs_bitset_set(pvs + c * words, o);
        }
        desc_init(&d, boxes, CELLS, OBJECTS, pvs);
        buf = encode(&d, &size);
        CHECK(buf && pvs_file_open(buf, size, &f, NULL) == PVS_OK);
        if (!buf) continue;
        CHECK(pvs_cursor_init(&cursor, &f, cur, scratch, words, NULL) == PVS_OK);
        deltas = 0;
        for (c = 0; c < CELLS; ++c) {
            pvs_record_info info;
            CHECK(pvs_file_decode(&f, c, got, words, NULL) == PVS_OK && memcmp(got, pvs + c * words, sizeof(got)) == 0);
            pvs_file_get_record_info(&f, c, &info);
            if (info.base != PVS_NO_CELL) { /* base -> cell: one delta */
                uint64_t before;
                ++deltas;
                CHECK(pvs_cursor_move(&cursor, info.base, NULL, NULL) == PVS_OK);
                before = cursor.delta_moves;
                CHECK(pvs_cursor_move(&cursor, c, NULL, NULL) == PVS_OK && memcmp(cur, pvs + c * words, sizeof(cur)) == 0);
                CHECK(cursor.delta_moves == before + 1);
            }
        }
        CHECK(cursor.delta_moves >= deltas);
        for (i = 0; i < 3000; ++i) {
            float p[3];
            p[0] = (float)(rnd() % 3400) * 0.01f - 0.5f;
            p[1] = (float)(rnd() % 100) * 0.01f;
            p[2] = (float)(rnd() % 3400) * 0.01f - 0.5f;
            if (i % 3 == 0) p[0] = (float)(rnd() % 34); /* on cell faces */
            CHECK(pvs_file_find_cell(&f, p) == linear_find(&f, p));
        }
        free(buf);
    }
}

/* Chain bound: K = 1 gives depth <= 1 everywhere; a long corridor of similar cells needs keys. */
static void test_chain_bound(void) {
    enum { CELLS = 200, OBJECTS = 300 };
    size_t words = PVS_BITSET_WORDS(OBJECTS), size, sizes[3];
    pvs_box *boxes = (pvs_box *)malloc(CELLS * sizeof(pvs_box));
    pvs_word *pvs = (pvs_word *)malloc(CELLS * words * sizeof(pvs_word));
    uint32_t ks[3] = {1, 4, 32}, j, c;
    make_table(CELLS, OBJECTS, 30, 2, 0, boxes, pvs);
    for (j = 0; j < 3; ++j) {
        pvs_file_desc d;
        pvs_file f;
        uint8_t *buf;
        uint32_t deepest = 0;
        desc_init(&d, boxes, CELLS, OBJECTS, pvs);
        d.max_chain = ks[j];
        buf = encode(&d, &size);
        sizes[j] = size;
        CHECK(buf && pvs_file_open(buf, size, &f, NULL) == PVS_OK);
        if (!buf) continue;
        for (c = 0; c < CELLS; ++c) {
            pvs_record_info info;
            pvs_file_get_record_info(&f, c, &info);
            if (info.depth > deepest) deepest = info.depth;
        }
        CHECK(deepest <= ks[j] && deepest >= 1);
        free(buf);
    }
    CHECK(sizes[0] >= sizes[1] && sizes[1] >= sizes[2]); /* a looser bound never costs bytes here */
    {
        pvs_file_desc d;
        desc_init(&d, boxes, CELLS, OBJECTS, pvs);
        d.max_chain = PVS_MAX_CHAIN + 1;
        CHECK(pvs_file_encode(&d, NULL, 0, &size, NULL) == PVS_ERROR_INVALID_ARGUMENT);
        d.max_chain = 0;
        d.shard_count = 1;
        CHECK(pvs_file_encode(&d, NULL, 0, &size, NULL) == PVS_ERROR_INVALID_ARGUMENT);
        d.shard_count = 3;
        d.shard_index = 0;
        d.total_cell_count = CELLS; /* 200 cells in 3 shards: shard 0 holds 67, not 200 */
        CHECK(pvs_file_encode(&d, NULL, 0, &size, NULL) == PVS_ERROR_INVALID_ARGUMENT);
        d.shard_count = 0;
        boxes[5].min[1] = NAN;
        CHECK(pvs_file_encode(&d, NULL, 0, &size, NULL) == PVS_ERROR_BAD_CELL);
    }
    free(boxes);
    free(pvs);
}

/* A small valid file into a fresh buffer of exactly its size: 40 cells, so there are deltas, a tree
   with inner nodes and several record blocks. */
static uint8_t *small_file(size_t *size) {
    enum { CELLS = 40, OBJECTS = 100 };
    static pvs_box boxes[CELLS];
    static pvs_word pvs[CELLS * 2];
    pvs_file_desc d;
    rng_state = 777;
    make_table(CELLS, OBJECTS, 30, 5, 0, boxes, pvs);
    desc_init(&d, boxes, CELLS, OBJECTS, pvs);
    d.up_axis = 2;
    d.flags = 0;
    d.scene_fingerprint = 0x0123456789abcdefull; /* an SCNE section */
    return encode(&d, size);
}

/* Offset of the section with this tag (0 if none). */
static uint32_t section(const uint8_t *b, const char *tag) {
    uint32_t n = test_rd32(b + 12), i;
    for (i = 0; i < n; ++i)
        if (memcmp(b + 32 + 16 * i, tag, 4) == 0) return test_rd32(b + 32 + 16 * i + 4);
    return 0;
}

/* Packed LSB-first fields, as the file's: w bits at bit pos. */
static uint32_t tbits(const uint8_t *s, uint64_t pos, uint32_t w) {
    uint32_t i, v = 0;
    for (i = 0; i < w; ++i) v |= (uint32_t)((s[(pos + i) >> 3] >> ((pos + i) & 7u)) & 1u) << i;
    return v;
}
static void tbits_put(uint8_t *s, uint64_t pos, uint32_t v, uint32_t w) {
    uint32_t i;
    for (i = 0; i < w; ++i) {
        s[(pos + i) >> 3] &= (uint8_t)~(1u << ((pos + i) & 7u));
        s[(pos + i) >> 3] |= (uint8_t)(((v >> i) & 1u) << ((pos + i) & 7u));
    }
}

/* Objects in groups seen together, ids interleaved: the order pays. Decoded in file order on decode's stack (up to
   16,384 objects) and through the order above that, both against the table and the cursor. */
static void test_grouped_order(void) {
    static const uint32_t counts[] = {5000, 20000};
    enum { CELLS = 40, GROUPS = 60 };
    size_t n;
    for (n = 0; n < sizeof(counts) / sizeof(counts[0]); ++n) {
        uint32_t objects = counts[n], c, o, i, seen[GROUPS];
        size_t words = PVS_BITSET_WORDS(objects), size;
        pvs_word *pvs = (pvs_word *)calloc(CELLS * words, sizeof(pvs_word)), *got = (pvs_word *)malloc(words * sizeof(pvs_word)),
                 *cur = (pvs_word *)malloc(words * sizeof(pvs_word)), *scratch = (pvs_word *)malloc(words * sizeof(pvs_word));
        pvs_box boxes[CELLS];
        pvs_file_desc d;
        pvs_file f;
        pvs_error e;
        pvs_cursor cursor;
        uint8_t *buf;
        for (i = 0; i < GROUPS; ++i) seen[i] = rnd() % 3 == 0;
        for (c = 0; c < CELLS; ++c) {
            int k;
            for (k = 0; k < 3; ++k) {
                boxes[c].min[k] = (float)(k == 0 ? c : 0) * 2.0f;
                boxes[c].max[k] = boxes[c].min[k] + 2.0f;
            }
            for (i = 0; i < GROUPS; ++i)
                if (rnd() % 8 == 0) seen[i] ^= 1u; /* a neighbour sees much the same */
            for (o = 0; o < objects; ++o)
                if (seen[(o * 7919u) % GROUPS]) pvs_bitset_set(pvs + c * words, o);
        }
        desc_init(&d, boxes, CELLS, objects, pvs);
        buf = encode(&d, &size);
        CHECK(buf && pvs_file_open(buf, size, &f, &e) == PVS_OK && f.private_.order_bits != 0);
        CHECK(buf && pvs_cursor_init(&cursor, &f, cur, scratch, words, &e) == PVS_OK);
        for (c = 0; buf && c < CELLS; ++c) {
            uint32_t next = (c * 17u) % CELLS;
            CHECK(pvs_file_decode(&f, c, got, words, &e) == PVS_OK && memcmp(got, pvs + c * words, words * sizeof(pvs_word)) == 0);
            CHECK(pvs_cursor_move(&cursor, next, NULL, NULL) == PVS_OK && memcmp(cur, pvs + next * words, words * sizeof(pvs_word)) == 0);
        }
        CHECK(cursor.full_moves > 0);
        if (buf) { /* a repeated id in the order (open accepts it): garbled sets of valid ids, decode and cursor safe */
            uint32_t md = section(buf, "MODL"), w = f.private_.order_bits;
            CHECK(md != 0 && w != 0);
            tbits_put(buf + md + 8 + 2 * 88, w, tbits(buf + md + 8 + 2 * 88, 0, w), w); /* position 1 names 0's object */
            pvs_fuzz_fix_checksums(buf, size);
            CHECK(pvs_file_open(buf, size, &f, &e) == PVS_OK);
            CHECK(pvs_cursor_init(&cursor, &f, cur, scratch, words, &e) == PVS_OK);
            for (c = 0; c < CELLS; ++c) {
                CHECK(pvs_file_decode(&f, c, got, words, &e) == PVS_OK);
                CHECK(objects % 64 == 0 || !(got[words - 1] >> (objects % 64)));
                CHECK(pvs_cursor_move(&cursor, (c * 17u) % CELLS, NULL, NULL) == PVS_OK);
            }
        }
        free(buf);
        free(pvs);
        free(got);
        free(cur);
        free(scratch);
    }
}

/* TREE at tr: depth, leaf offset width, and where the axes, the leaf offsets and the items start (manual's layout). */
static uint32_t tree_layout(const uint8_t *f, uint32_t tr, uint32_t *ow, uint32_t *axes, uint32_t *starts, uint32_t *items) {
    uint32_t depth = test_rd32(f + tr), inner = (1u << depth) - 1;
    *ow = test_rd32(f + tr + 4);
    *axes = tr + 8 + 4 * inner, *starts = *axes + inner, *items = *starts + ((inner + 2) * *ow + 7) / 8;
    return depth;
}

/* CELL's coordinate tables: a grid one (40 cells in a row on quarters: 41 x values; the 2-value tables stay f32) and
   f32 ones (boxes scaled by 0.1). */
static void test_cell_tables(void) {
    enum { ROW = 40 };
    static pvs_box row[ROW];
    static pvs_word rp[ROW * 2];
    pvs_file_desc rd;
    size_t size;
    uint8_t *good, *b;
    uint32_t cl, k, at, w0, c;
    pvs_file f;
    rng_state = 779;
    make_table(ROW, 100, 30, 5, 0, row, rp);
    for (c = 0; c < ROW; ++c) {
        row[c].min[0] = (float)c * 8.0f - 7.25f, row[c].max[0] = row[c].min[0] + 8.0f; /* quarters: 1,280 steps */
        row[c].min[1] = row[c].min[2] = 0.0f, row[c].max[1] = row[c].max[2] = 2.0f;
    }
    desc_init(&rd, row, ROW, 100, rp);
    good = encode(&rd, &size);
    b = good ? (uint8_t *)malloc(size) : NULL;
    CHECK(good && b);
    if (!good || !b) return;
    cl = section(good, "CELL");
    at = cl + 44;
    w0 = good[cl + 24];
    CHECK(w0 == 16 && test_rd32(good + cl + 24) >> 8 == 0xfffeu && good[cl + 32] == 255); /* step 2^-2; f32 */
    for (k = 0; k < 3; ++k) { /* each table's bytes, then the indices: all of the section */
        uint32_t w = good[cl + 24 + 8 * k], n = test_rd32(good + cl + 4 * k);
        at += (w == 255 ? 4 : 2) * n;
    }
    CHECK(pvs_file_open(good, size, &f, NULL) == PVS_OK && at + (f.private_.cell_bits * f.cell_count + 7) / 8 == cl + test_rd32(good + 32 + 16 * 1 + 8));
#define BAD(code) do { pvs_fuzz_fix_checksums(b, size); CHECK(expect_open(b, size, code)); memcpy(b, good, size); } while (0)
    memcpy(b, good, size);
    CHECK(pvs_file_open(good, size, &f, NULL) == PVS_OK);
    for (c = 0; c < ROW; ++c) {
        pvs_box x = pvs_file_cell_box(&f, c);
        for (k = 0; k < 3; ++k) CHECK(x.min[k] == row[c].min[k] && x.max[k] == row[c].max[k]);
    }
    for (c = 0; c < 2000; ++c) { /* the look-up's grid steps against the boxes (cell faces every other time) */
        float p[3];
        p[0] = c % 2 ? (float)(rnd() % 41) * 8.0f - 7.25f : (float)(rnd() % 34000) * 0.01f - 10.0f;
        p[1] = (float)(rnd() % 250) * 0.01f - 0.2f;
        p[2] = (float)(rnd() % 250) * 0.01f - 0.2f;
        CHECK(pvs_file_find_cell(&f, p) == linear_find(&f, p));
    }
    b[cl + 24] = 8; BAD(PVS_ERROR_BAD_SECTION);                                    /* width 8: neither grid nor f32 */
    b[cl + 27] = 1; BAD(PVS_ERROR_BAD_SECTION);                                    /* the grid word's top byte */
    b[cl + 24] = (uint8_t)(w0 + 1); BAD(PVS_ERROR_BAD_SECTION);                    /* the size then disagrees */
    b[cl + 25] = 0xff; b[cl + 26] = 0x7f; BAD(PVS_ERROR_BAD_CELL);                 /* step 2^32767: not finite */
    tbits_put(b + cl + 44, w0, tbits(b + cl + 44, 0, w0), w0); BAD(PVS_ERROR_BAD_CELL); /* two equal: not ascending */
    test_wr32(b + cl + 20, 0xffffffffu); b[cl + 25] = 0x38; b[cl + 26] = 0xff; /* -1 * 2^-200: -0 as a float */
    tbits_put(b + cl + 44, 0, 0, w0); BAD(PVS_ERROR_BAD_CELL);
    free(b);
    free(good);
    { /* f32 tables */
        enum { CELLS = 40, OBJECTS = 100 };
        static pvs_box boxes[CELLS];
        static pvs_word pvs[CELLS * 2];
        pvs_file_desc d;
        size_t rs;
        uint8_t *r, *rb;
        uint32_t rc;
        rng_state = 777;
        make_table(CELLS, OBJECTS, 30, 5, 0, boxes, pvs);
        for (c = 0; c < CELLS; ++c)
            for (k = 0; k < 3; ++k) boxes[c].min[k] *= 0.1f, boxes[c].max[k] *= 0.1f;
        boxes[CELLS - 1].max[0] = boxes[CELLS - 1].max[1] = boxes[CELLS - 1].max[2] = 1e9f; /* no grid spans these */
        desc_init(&d, boxes, CELLS, OBJECTS, pvs);
        r = encode(&d, &rs);
        rb = r ? (uint8_t *)malloc(rs) : NULL;
        CHECK(r && rb);
        if (!r || !rb) return;
        rc = section(r, "CELL");
        CHECK(r[rc + 24] == 255 && test_rd32(r + rc + 20) == 0 && test_rd32(r + rc + 24) == 255);
        CHECK(pvs_file_open(r, rs, &f, NULL) == PVS_OK);
        for (c = 0; c < CELLS; ++c) {
            pvs_box x = pvs_file_cell_box(&f, c);
            for (k = 0; k < 3; ++k) CHECK(x.min[k] == boxes[c].min[k] + 0.0f && x.max[k] == boxes[c].max[k]);
        }
#define RBAD(code) do { pvs_fuzz_fix_checksums(rb, rs); CHECK(expect_open(rb, rs, code)); memcpy(rb, r, rs); } while (0)
        memcpy(rb, r, rs);
        test_wr32(rb + rc + 44, 0x7fc00000u); RBAD(PVS_ERROR_BAD_CELL);            /* NaN */
        test_wr32(rb + rc + 44, 0x80000000u); RBAD(PVS_ERROR_BAD_CELL);            /* -0 */
        memcpy(rb + rc + 48, rb + rc + 44, 4); RBAD(PVS_ERROR_BAD_CELL);          /* not ascending */
        test_wr32(rb + rc + 20, 1); RBAD(PVS_ERROR_BAD_SECTION);                  /* an f32 table with a grid base */
        rb[rc + 25] = 1; RBAD(PVS_ERROR_BAD_SECTION);                             /* or a grid step */
#undef RBAD
        free(rb);
        free(r);
    }
#undef BAD
}

/* Flat cells (zero thickness) on every candidate split, which neither side's count holds (the split's copies are
   then none, not fewer): 64 unit boxes in a row and a flat cell at each of their 65 faces. Leaves stay small (a rule
   refusing such splits makes one leaf of 129 cells), look-ups right. */
static void test_tree_flat_cells(void) {
    enum { N = 64, CELLS = 2 * N + 1 };
    static pvs_box b[CELLS];
    static pvs_word t[CELLS];
    pvs_file_desc d;
    pvs_file f;
    size_t size;
    uint8_t *buf;
    uint32_t c, depth, w, j, most = 0, axes, at, items;
    for (c = 0; c < CELLS; ++c) {
        b[c].min[0] = (float)(c < N ? c : c - N), b[c].max[0] = (float)(c < N ? c + 1 : c - N);
        b[c].min[1] = b[c].min[2] = 0.0f, b[c].max[1] = b[c].max[2] = 1.0f;
        t[c] = (pvs_word)c * 0x9e3779b97f4a7c15ull;
    }
    desc_init(&d, b, CELLS, 64, t);
    buf = encode(&d, &size);
    CHECK(buf && pvs_file_open(buf, size, &f, NULL) == PVS_OK);
    if (!buf) return;
    depth = tree_layout(buf, section(buf, "TREE"), &w, &axes, &at, &items);
    for (j = 0; j < (1u << depth); ++j) { /* a leaf's cells: its items' varints, whose last bytes are < 0x80 */
        uint32_t k, n = 0, o0 = tbits(buf + at, (uint64_t)j * w, w), o1 = tbits(buf + at, (uint64_t)(j + 1) * w, w);
        for (k = o0; k < o1; ++k) n += buf[items + k] < 0x80;
        most = n > most ? n : most;
    }
    CHECK(depth >= 4 && most <= 8);
    for (c = 0; c <= 4 * N; ++c) {
        float p[3];
        p[0] = (float)c * 0.25f, p[1] = (float)(c % 5) * 0.25f, p[2] = 0.5f;
        CHECK(pvs_file_find_cell(&f, p) == linear_find(&f, p));
    }
    free(buf);
}

/* A cycle: in a file of many keys (K = 1), a key made a delta of a cell based on it (META's key count one less, so
   that only the chain rule can refuse it). */
static void test_cycle(void) {
    enum { CELLS = 40, OBJECTS = 100 };
    static pvs_box boxes[CELLS];
    static pvs_word pvs[CELLS * 2];
    pvs_file_desc d;
    pvs_file f;
    size_t size;
    uint8_t *good, *b;
    uint32_t c, rc, m;
    rng_state = 778;
    make_table(CELLS, OBJECTS, 30, 5, 0, boxes, pvs);
    desc_init(&d, boxes, CELLS, OBJECTS, pvs);
    d.max_chain = 1;
    good = encode(&d, &size);
    b = good ? (uint8_t *)malloc(size) : NULL;
    CHECK(good && b && pvs_file_open(good, size, &f, NULL) == PVS_OK && f.key_count >= 2);
    if (!good || !b) return;
    rc = section(good, "RECS");
    m = section(good, "META");
    for (c = 0; c < f.cell_count; ++c) {
        pvs_record_info info;
        pvs_file_get_record_info(&f, c, &info);
        if (info.depth == 1 && info.base + 60 > c && c + 60 > info.base) {
            /* locate the key's record: block start, then skip records by their length varints */
            const uint8_t *p = good + rc + test_rd32(good + rc + 4 * (info.base / 16));
            uint32_t j, at;
            for (j = info.base - info.base % 16; j < info.base; ++j) p += 1 + p[0]; /* one-byte lengths */
            at = (uint32_t)(p - good);
            if (good[at] < 0x80 && good[at + 1] == 0) {
                memcpy(b, good, size);
                b[at + 1] = (uint8_t)(info.base >= c ? 2 * (info.base - c) : 2 * (c - info.base) - 1);
                test_wr32(b + m + 24, test_rd32(b + m + 24) - 1);
                pvs_fuzz_fix_checksums(b, size);
                CHECK(expect_open(b, size, PVS_ERROR_BAD_CHAIN));
                break;
            }
        }
    }
    CHECK(c < f.cell_count);
    free(b);
    free(good);
}

static void test_corruptions(void) {
    size_t size, i;
    uint8_t *good = small_file(&size), *b = (uint8_t *)malloc(size);
    pvs_word bits[2], scratch[2];
    pvs_file f0;
    int round;
    uint32_t m = section(good, "META"), cl = section(good, "CELL"), tr = section(good, "TREE"), rc = section(good, "RECS");
    CHECK(expect_open(good, size, PVS_OK));
    CHECK(m && cl && tr && rc);
#define RESET() memcpy(b, good, size)
    { /* SCNE: read back; 0 is BAD_SECTION */
        uint32_t sc = section(good, "SCNE");
        CHECK(sc && pvs_file_open(good, size, &f0, NULL) == PVS_OK && f0.scene_fingerprint == 0x0123456789abcdefull);
        RESET(); test_wr32(b + sc, 0); test_wr32(b + sc + 4, 0); pvs_fuzz_fix_checksums(b, size);
        CHECK(expect_open(b, size, PVS_ERROR_BAD_SECTION));
    }
    RESET(); b[0] = 'X';                       CHECK(expect_open(b, size, PVS_ERROR_BAD_MAGIC));
    RESET(); test_wr32(b + 4, 5);                   CHECK(expect_open(b, size, PVS_ERROR_BAD_VERSION));
    RESET(); test_wr32(b + 4, 3);                   CHECK(expect_open(b, size, PVS_ERROR_BAD_VERSION));
    RESET(); test_wr32(b + 8, (uint32_t)size - 8); pvs_fuzz_fix_checksums(b, size); CHECK(expect_open(b, size, PVS_ERROR_BAD_HEADER));
    RESET(); b[16] ^= 0x80;                    CHECK(expect_open(b, size, PVS_ERROR_CHECKSUM));
    RESET(); test_wr32(b + 12, 0); pvs_fuzz_fix_checksums(b, size); CHECK(expect_open(b, size, PVS_ERROR_BAD_HEADER));
    RESET(); test_wr32(b + 12, 65); pvs_fuzz_fix_checksums(b, size); CHECK(expect_open(b, size, PVS_ERROR_BAD_HEADER));
    RESET(); test_wr32(b + 24, 1); pvs_fuzz_fix_checksums(b, size); CHECK(expect_open(b, size, PVS_ERROR_BAD_HEADER));
    /* section table: misaligned, out of the file, overlapping, repeated tag, missing tag */
    RESET(); test_wr32(b + 32 + 4, test_rd32(b + 32 + 4) + 4); pvs_fuzz_fix_checksums(b, size); CHECK(expect_open(b, size, PVS_ERROR_BAD_SECTION));
    RESET(); test_wr32(b + 32 + 8, (uint32_t)size); pvs_fuzz_fix_checksums(b, size); CHECK(expect_open(b, size, PVS_ERROR_TRUNCATED));
    RESET(); test_wr32(b + 48 + 4, test_rd32(b + 32 + 4)); pvs_fuzz_fix_checksums(b, size); CHECK(expect_open(b, size, PVS_ERROR_BAD_SECTION));
    RESET(); test_wr32(b + 48, test_rd32(b + 32)); pvs_fuzz_fix_checksums(b, size); CHECK(expect_open(b, size, PVS_ERROR_BAD_SECTION));
    RESET(); b[48] = 'Z'; pvs_fuzz_fix_checksums(b, size); CHECK(expect_open(b, size, PVS_ERROR_BAD_SECTION));
    RESET(); b[m + 2] ^= 1;                    CHECK(expect_open(b, size, PVS_ERROR_CHECKSUM));
    /* META fields */
    RESET(); test_wr32(b + m, 0); pvs_fuzz_fix_checksums(b, size); CHECK(expect_open(b, size, PVS_ERROR_BAD_HEADER));
    RESET(); test_wr32(b + m, test_rd32(b + m) + 1); pvs_fuzz_fix_checksums(b, size); CHECK(expect_open(b, size, PVS_ERROR_BAD_RECORD)); /* records are read first */
    RESET(); test_wr32(b + m + 4, 0); pvs_fuzz_fix_checksums(b, size); CHECK(expect_open(b, size, PVS_ERROR_BAD_HEADER));
    RESET(); test_wr32(b + m, 0x40000000u); pvs_fuzz_fix_checksums(b, size); CHECK(expect_open(b, size, PVS_ERROR_COUNT_OVERFLOW));
    RESET(); test_wr32(b + m + 4, 0xffffffffu); pvs_fuzz_fix_checksums(b, size); CHECK(expect_open(b, size, PVS_ERROR_COUNT_OVERFLOW));
    RESET(); test_wr32(b + m + 4, 50); pvs_fuzz_fix_checksums(b, size); /* MODL's order no longer fits */
    CHECK(expect_open(b, size, f0.private_.order_bits ? PVS_ERROR_BAD_SECTION : PVS_OK));
    RESET(); test_wr32(b + m + 8, 99); pvs_fuzz_fix_checksums(b, size); CHECK(expect_open(b, size, PVS_ERROR_BAD_HEADER));
    RESET(); test_wr32(b + m + 12, 0x7fc00000u); pvs_fuzz_fix_checksums(b, size); CHECK(expect_open(b, size, PVS_ERROR_BAD_HEADER));
    RESET(); test_wr32(b + m + 16, 0); pvs_fuzz_fix_checksums(b, size); CHECK(expect_open(b, size, PVS_ERROR_BAD_HEADER));
    RESET(); test_wr32(b + m + 20, 0); pvs_fuzz_fix_checksums(b, size); CHECK(expect_open(b, size, PVS_ERROR_BAD_HEADER));
    RESET(); test_wr32(b + m + 20, 65); pvs_fuzz_fix_checksums(b, size); CHECK(expect_open(b, size, PVS_ERROR_BAD_HEADER));
    RESET(); test_wr32(b + m + 20, 1); pvs_fuzz_fix_checksums(b, size); CHECK(expect_open(b, size, PVS_ERROR_BAD_CHAIN)); /* K smaller than the chains */
    RESET(); test_wr32(b + m + 24, test_rd32(b + m + 24) + 1); pvs_fuzz_fix_checksums(b, size); CHECK(expect_open(b, size, PVS_ERROR_BAD_HEADER));
    RESET(); test_wr32(b + m + 28, 1); pvs_fuzz_fix_checksums(b, size); CHECK(expect_open(b, size, PVS_ERROR_BAD_HEADER));
    /* CELL: counts, widths, reserved bytes, the tables (test_cell_tables), an index out of range */
    RESET(); test_wr32(b + cl, 0); pvs_fuzz_fix_checksums(b, size); CHECK(expect_open(b, size, PVS_ERROR_BAD_SECTION));
    RESET(); b[cl + 12] += 1; pvs_fuzz_fix_checksums(b, size); CHECK(expect_open(b, size, PVS_ERROR_BAD_SECTION));
    RESET(); b[cl + 15] = 30; pvs_fuzz_fix_checksums(b, size); CHECK(expect_open(b, size, PVS_ERROR_BAD_SECTION));
    RESET(); b[cl + 18] = 1; pvs_fuzz_fix_checksums(b, size); CHECK(expect_open(b, size, PVS_ERROR_BAD_SECTION));
    test_cell_tables();
    {
        /* set every index bit of cell 0 on axis 0: index 2^w - 1 is out of range unless the table
           is a power of two long; then min > max or in range; only a defined code is required */
        uint32_t at = cl + 44;
        for (i = 0; i < 3; ++i) {
            uint32_t w = good[cl + 24 + 8 * i], n = test_rd32(good + cl + 4 * i);
            at += (w == 255 ? 4 : 2) * n;
        }
        RESET(); b[at] = 0xff; pvs_fuzz_fix_checksums(b, size);
        {
            pvs_result r = pvs_file_open(b, size, &f0, NULL);
            CHECK(r == PVS_ERROR_BAD_CELL || r == PVS_OK);
        }
    }
    /* TREE: depth, offset width, a NaN split, a bad axis, leaf offsets, their unused bits, an item past the cells */
    {
        uint32_t ow, axes, starts, items, depth = tree_layout(b, tr, &ow, &axes, &starts, &items), leaves = 1u << depth;
        CHECK(depth >= 2 && ow >= 1 && ow <= 32 && tbits(b + starts, (uint64_t)leaves * ow, ow) + items == tr + test_rd32(good + 32 + 16 * 2 + 8)); /* 40 cells */
        RESET(); test_wr32(b + tr, depth + 1); pvs_fuzz_fix_checksums(b, size); CHECK(expect_open(b, size, PVS_ERROR_BAD_TREE));
        RESET(); test_wr32(b + tr, 25); pvs_fuzz_fix_checksums(b, size); CHECK(expect_open(b, size, PVS_ERROR_BAD_TREE));
        RESET(); test_wr32(b + tr + 4, 0); pvs_fuzz_fix_checksums(b, size); CHECK(expect_open(b, size, PVS_ERROR_BAD_TREE));
        RESET(); test_wr32(b + tr + 4, 33); pvs_fuzz_fix_checksums(b, size); CHECK(expect_open(b, size, PVS_ERROR_BAD_TREE));
        RESET(); test_wr32(b + tr + 8, 0x7fc00000u); pvs_fuzz_fix_checksums(b, size); CHECK(expect_open(b, size, PVS_ERROR_BAD_TREE));
        RESET(); b[axes] = 4; pvs_fuzz_fix_checksums(b, size); CHECK(expect_open(b, size, PVS_ERROR_BAD_TREE));
        RESET(); tbits_put(b + starts, 0, 1, ow); pvs_fuzz_fix_checksums(b, size); CHECK(expect_open(b, size, PVS_ERROR_BAD_TREE));
        RESET(); tbits_put(b + starts, ow, tbits(b + starts, 2 * ow, ow) + 1, ow); pvs_fuzz_fix_checksums(b, size); CHECK(expect_open(b, size, PVS_ERROR_BAD_TREE));
        if ((leaves + 1) * ow % 8) {
            RESET(); b[items - 1] |= 0x80; pvs_fuzz_fix_checksums(b, size); CHECK(expect_open(b, size, PVS_ERROR_BAD_TREE));
        }
        RESET(); b[items] = 100; pvs_fuzz_fix_checksums(b, size); CHECK(expect_open(b, size, PVS_ERROR_BAD_TREE));
        /* a changed split is still a well-formed tree: look-ups may then miss, never read out of bounds */
        RESET(); test_wr32(b + tr + 8, 0x4f000000u); pvs_fuzz_fix_checksums(b, size);
        {
            pvs_file ft;
            float q[3] = {1, 1, 1};
            CHECK(pvs_file_open(b, size, &ft, NULL) == PVS_OK);
            (void)pvs_file_find_cell(&ft, q);
        }
    }
    /* RECS: block offsets, lengths, chains, ids */
    {
        uint32_t first = test_rd32(b + rc);
        RESET(); test_wr32(b + rc, first + 1); pvs_fuzz_fix_checksums(b, size); CHECK(expect_open(b, size, PVS_ERROR_BAD_RECORD));
        RESET(); test_wr32(b + rc + 4, test_rd32(b + rc + 4) - 1); pvs_fuzz_fix_checksums(b, size); CHECK(pvs_file_open(b, size, &f0, NULL) < 0);
        RESET(); b[rc + first] = 0xff; pvs_fuzz_fix_checksums(b, size); CHECK(pvs_file_open(b, size, &f0, NULL) < 0);
        /* record 0: L, base (zigzag; 0: a key), body. Its base past the cells (40: z = 79, one byte) */
        RESET(); b[rc + first + 1] = 79; pvs_fuzz_fix_checksums(b, size);
        CHECK(expect_open(b, size, PVS_ERROR_BAD_CHAIN));
    }
    { /* MODL: context count, probabilities 0 and 4096, order width (the size then disagrees), an order entry
         past the objects */
        uint32_t md = section(good, "MODL"), w = test_rd32(good + md + 4);
        CHECK(md != 0);
        RESET(); test_wr32(b + md, test_rd32(b + md) + 1); pvs_fuzz_fix_checksums(b, size); CHECK(expect_open(b, size, PVS_ERROR_BAD_SECTION));
        RESET(); b[md + 8] = 0; b[md + 9] = 0; pvs_fuzz_fix_checksums(b, size); CHECK(expect_open(b, size, PVS_ERROR_BAD_SECTION));
        RESET(); b[md + 10] = 0; b[md + 11] = 16; pvs_fuzz_fix_checksums(b, size); CHECK(expect_open(b, size, PVS_ERROR_BAD_SECTION));
        RESET(); test_wr32(b + md + 4, w ? 0 : 7); pvs_fuzz_fix_checksums(b, size); CHECK(expect_open(b, size, PVS_ERROR_BAD_SECTION));
        RESET(); test_wr32(b + md + 4, w ? w + 1 : 1); pvs_fuzz_fix_checksums(b, size); CHECK(expect_open(b, size, PVS_ERROR_BAD_SECTION));
        if (w == 7) { /* 100 objects: ids up to 127 fit the width */
            RESET(); b[md + 8 + 2 * 88] |= 0x7f; pvs_fuzz_fix_checksums(b, size); CHECK(expect_open(b, size, PVS_ERROR_OBJECT_OUT_OF_RANGE));
        }
        CHECK(w == 0 || w == 7);
    }
    /* a non-zero padding byte */
    if ((test_rd32(b + 32 + 16 * 3 + 4) + test_rd32(b + 32 + 16 * 3 + 8)) % 8) { /* after RECS, before SCNE */
        RESET(); b[test_rd32(b + 32 + 16 * 3 + 4) + test_rd32(b + 32 + 16 * 3 + 8)] = 1;
        CHECK(expect_open(b, size, PVS_ERROR_BAD_SECTION));
    }
    /* random corruptions with repaired checksums: never a crash, always a defined code, and an
       accepted file always decodes and walks */
    for (round = 0; round < 100000; ++round) {
        pvs_file f;
        pvs_error e;
        pvs_result res;
        int flips = 1 + (int)(rnd() % 4), k;
        RESET();
        for (k = 0; k < flips; ++k) {
            size_t at = rnd() % size;
            if (rnd() % 4) b[at] ^= (uint8_t)(1u << (rnd() % 8));
            else b[at] = (uint8_t)rnd();
        }
        if (rnd() % 8) pvs_fuzz_fix_checksums(b, size);
        res = pvs_file_open(b, size, &f, &e);
        CHECK(res <= 0 && res > PVS_RESULT_MIN && e.result == res);
        if (res == PVS_OK && PVS_BITSET_WORDS(f.object_count) <= 2) {
            pvs_cursor cur;
            float p[3] = {0.5f, 0.5f, 0.5f};
            CHECK(pvs_cursor_init(&cur, &f, bits, scratch, 2, NULL) == PVS_OK);
            for (i = 0; i < f.cell_count; ++i) {
                CHECK(pvs_file_decode(&f, (uint32_t)i, bits, 2, NULL) == PVS_OK);
                CHECK(pvs_cursor_move(&cur, (uint32_t)i, NULL, NULL) == PVS_OK);
            }
            (void)pvs_file_find_cell(&f, p);
        }
    }
    CHECK(expect_open(NULL, 0, PVS_ERROR_TRUNCATED));
    CHECK(pvs_file_open(good, size, NULL, NULL) == PVS_ERROR_INVALID_ARGUMENT);
#undef RESET
    free(good);
    free(b);
}

/* Part files: every shard split of a table, decoded and re-encoded whole, gives the bytes of the
   direct encoding (what `pvsbake merge` does). */
static void test_shards(void) {
    enum { CELLS = 23, OBJECTS = 400 };
    size_t words = PVS_BITSET_WORDS(OBJECTS), size_whole;
    pvs_box boxes[CELLS], part_boxes[CELLS], merged_boxes[CELLS];
    static pvs_word pvs[CELLS * PVS_BITSET_WORDS(OBJECTS)], part_pvs[CELLS * PVS_BITSET_WORDS(OBJECTS)],
        merged[CELLS * PVS_BITSET_WORDS(OBJECTS)];
    pvs_file_desc d;
    uint8_t *whole;
    uint32_t ns[4] = {2, 3, 7, 23}, j, k, c;
    make_table(CELLS, OBJECTS, 20, 3, 0, boxes, pvs);
    boxes[3].min[0] = -0.0f; /* stored as +0 in every file */
    if (boxes[3].max[0] < 1.0f) boxes[3].max[0] = 1.0f;
    desc_init(&d, boxes, CELLS, OBJECTS, pvs);
    whole = encode(&d, &size_whole);
    for (j = 0; j < 4; ++j) {
        uint32_t n = ns[j];
        uint8_t *again;
        size_t size_again;
        for (k = 0; k < n; ++k) {
            pvs_file_desc pd = d;
            pvs_file pf;
            uint8_t *part;
            size_t part_size;
            uint32_t m = 0;
            for (c = k; c < CELLS; c += n, ++m) {
                part_boxes[m] = boxes[c];
                memcpy(part_pvs + m * words, pvs + c * words, words * sizeof(pvs_word));
            }
            pd.cells = part_boxes;
            pd.pvs = part_pvs;
            pd.cell_count = m;
            pd.shard_index = k;
            pd.shard_count = n;
            pd.total_cell_count = CELLS;
            part = encode(&pd, &part_size);
            CHECK(part && expect_open(part, part_size, PVS_OK) && pvs_file_open(part, part_size, &pf, NULL) == PVS_OK);
            if (!part) continue;
            CHECK(pf.shard_index == k && pf.shard_count == n && pf.total_cell_count == CELLS && pf.cell_count == m);
            for (c = 0; c < m; ++c) {
                merged_boxes[k + c * n] = pvs_file_cell_box(&pf, c);
                pvs_file_decode(&pf, c, merged + (k + c * n) * words, words, NULL);
            }
            free(part);
        }
        desc_init(&d, merged_boxes, CELLS, OBJECTS, merged);
        again = encode(&d, &size_again);
        CHECK(again && size_again == size_whole && memcmp(again, whole, size_whole) == 0);
        free(again);
        desc_init(&d, boxes, CELLS, OBJECTS, pvs);
    }
    free(whole);
}

/* The golden file of format version 4 (tests/golden/v4.pvs) must stay readable and decode to its
   table, tests/golden/table.txt (the `pvsinfo --dump` listing). v4.pvs holds the table of the older
   golden files, v1.pvs to v3.pvs, which are refused with a message that says to re-bake. */
static void test_golden(void) {
    FILE *fp = fopen("../tests/golden/v4.pvs", "rb"), *tp = fopen("../tests/golden/table.txt", "rb");
    int v;
    static uint8_t data[1 << 16];
    static char text[1 << 16], line[4096];
    size_t size = 0, tsize = 0;
    pvs_file f;
    pvs_error e;
    uint32_t c;
    CHECK(fp != NULL && tp != NULL);
    if (!fp || !tp) {
        if (fp) fclose(fp);
        if (tp) fclose(tp);
        return;
    }
    size = fread(data, 1, sizeof(data), fp);
    tsize = fread(text, 1, sizeof(text) - 1, tp);
    text[tsize] = 0;
    fclose(fp);
    fclose(tp);
    CHECK(pvs_file_open(data, size, &f, &e) == PVS_OK);
    if (e.result != PVS_OK) { fprintf(stderr, "golden: %s\n", e.message); return; }
    for (v = 1; v <= 3; ++v) {
        char path[64];
        snprintf(path, sizeof(path), "../tests/golden/v%d.pvs", v);
        if ((fp = fopen(path, "rb")) != NULL) {
            static uint8_t old[1 << 16];
            size_t n = fread(old, 1, sizeof(old), fp);
            pvs_file g;
            fclose(fp);
            CHECK(pvs_file_open(old, n, &g, &e) == PVS_ERROR_BAD_VERSION && strstr(e.message, "re-bake") != NULL);
        } else {
            CHECK(!"tests/golden/v1.pvs to v3.pvs");
        }
    }
    {
        char *out = (char *)malloc(1 << 16);
        size_t pos = 0;
        pvs_word bits[64];
        CHECK(f.object_count <= 64 * 64);
        for (c = 0; c < f.cell_count && f.object_count <= 64 * 64; ++c) {
            uint32_t i;
            size_t n;
            pvs_file_decode(&f, c, bits, 64, NULL);
            n = (size_t)snprintf(line, sizeof(line), "%u:", c);
            for (i = pvs_bitset_next(bits, f.object_count, 0); i < f.object_count && n < sizeof(line) - 16; i = pvs_bitset_next(bits, f.object_count, i + 1))
                n += (size_t)snprintf(line + n, sizeof(line) - n, " %u", i);
            if (pos + n + 2 < (1 << 16)) {
                memcpy(out + pos, line, n);
                pos += n;
                out[pos++] = '\n';
            }
        }
        out[pos] = 0;
        CHECK(strcmp(out, text) == 0);
        free(out);
    }
}

/* The fuzzing corpus (tests/corpus): files named ok-* open, bad-* are rejected, all run through
   the fuzz target (every runtime path on each file that opens). */
static void test_corpus(void) {
    DIR *dir = opendir("../tests/corpus");
    struct dirent *ent;
    int files = 0;
    CHECK(dir != NULL);
    if (!dir) return;
    while ((ent = readdir(dir)) != NULL) {
        char path[512];
        FILE *fp;
        static uint8_t data[1 << 20];
        size_t size;
        int r;
        if (ent->d_name[0] == '.') continue;
        snprintf(path, sizeof(path), "../tests/corpus/%s", ent->d_name);
        fp = fopen(path, "rb");
        CHECK(fp != NULL);
        if (!fp) continue;
        size = fread(data, 1, sizeof(data), fp);
        fclose(fp);
        r = pvs_fuzz_one(data, size);
        if (!strncmp(ent->d_name, "ok-", 3)) CHECK(r == PVS_OK);
        else CHECK(r < 0);
        ++files;
    }
    closedir(dir);
    CHECK(files >= 10);
}

/* NAME: names read back in place (a NULL one as ""), the lookup by name, a file without names, and each
   malformed section refused with BAD_SECTION (checksums fixed, so the NAME check itself decides). */
/* PVS_FILE_NO_LOOKUP: the same records without CELL and TREE; no cell found, empty boxes; the flag and the sections
   must agree; virtual occluders and unknown flags refused by the encoder. */
static void test_no_lookup(void) {
    enum { CELLS = 40, OBJECTS = 100 };
    static pvs_box boxes[CELLS];
    static pvs_word pvs[CELLS * 2];
    static const uint8_t counts[CELLS], scales[CELLS];
    pvs_file_desc d;
    pvs_file f, g;
    pvs_error e;
    pvs_word bits[2], want[2];
    size_t size, nsize;
    uint8_t *full, *nol;
    uint32_t c;
    float p[3];
    rng_state = 778;
    make_table(CELLS, OBJECTS, 30, 5, 0, boxes, pvs);
    desc_init(&d, boxes, CELLS, OBJECTS, pvs);
    full = encode(&d, &size);
    d.flags = PVS_FILE_NO_LOOKUP;
    nol = encode(&d, &nsize);
    CHECK(full && nol && nsize < size && !section(nol, "CELL") && !section(nol, "TREE") && section(nol, "RECS"));
    if (!full || !nol) return;
    CHECK(pvs_file_open(full, size, &f, NULL) == PVS_OK && pvs_file_open(nol, nsize, &g, NULL) == PVS_OK);
    CHECK(g.flags == PVS_FILE_NO_LOOKUP && !(f.flags & PVS_FILE_NO_LOOKUP));
    for (c = 0; c < CELLS; ++c) {
        pvs_box b = pvs_file_cell_box(&g, c), fb = pvs_file_cell_box(&f, c);
        CHECK(pvs_file_decode(&g, c, bits, 2, NULL) == PVS_OK && pvs_file_decode(&f, c, want, 2, NULL) == PVS_OK);
        CHECK(!memcmp(bits, want, sizeof(bits)) && b.min[0] > b.max[0] && b.min[2] > b.max[2]);
        p[0] = 0.5f * (fb.min[0] + fb.max[0]), p[1] = 0.5f * (fb.min[1] + fb.max[1]), p[2] = 0.5f * (fb.min[2] + fb.max[2]);
        CHECK(pvs_file_find_cell(&g, p) == PVS_NO_CELL && pvs_file_find_cell(&f, p) != PVS_NO_CELL);
    }
    test_wr32(full + 16, PVS_FILE_NO_LOOKUP); /* the flag with CELL and TREE present */
    pvs_fuzz_fix_checksums(full, size);
    CHECK(expect_open(full, size, PVS_ERROR_BAD_SECTION));
    test_wr32(nol + 16, 0); /* CELL and TREE missing without the flag */
    pvs_fuzz_fix_checksums(nol, nsize);
    CHECK(expect_open(nol, nsize, PVS_ERROR_BAD_SECTION));
    d.shard_index = 1, d.shard_count = 2, d.total_cell_count = 2 * CELLS; /* a part file: SHRD after RECS, MODL */
    free(nol);
    nol = encode(&d, &nsize);
    CHECK(nol && pvs_file_open(nol, nsize, &g, NULL) == PVS_OK && g.shard_count == 2 && g.shard_index == 1 &&
          g.total_cell_count == 2 * CELLS && !section(nol, "CELL") && section(nol, "SHRD"));
    CHECK(nol && pvs_file_decode(&g, 3, bits, 2, NULL) == PVS_OK && !memcmp(bits, pvs + 2 * 3, sizeof(bits)));
    d.shard_index = d.shard_count = d.total_cell_count = 0;
    d.flags = 8u;
    CHECK(pvs_file_encode(&d, NULL, 0, &size, &e) == PVS_ERROR_INVALID_ARGUMENT);
    d.flags = PVS_FILE_NO_LOOKUP;
    d.vocc_counts = counts, d.vocc_scales = scales, d.vocc_height_step = 1.0f;
    CHECK(pvs_file_encode(&d, NULL, 0, &size, &e) == PVS_ERROR_INVALID_ARGUMENT);
    d.flags = 0;
    CHECK(pvs_file_encode(&d, NULL, 0, &size, &e) == PVS_OK); /* the same occluders with the look-up */
    free(full);
    free(nol);
}

static void test_names(void) {
    enum { CELLS = 12, OBJECTS = 5 };
    static pvs_box boxes[CELLS];
    static pvs_word pvs[CELLS];
    static const char *const names[OBJECTS] = {"floor", "crate_1", NULL, "crate_1", "glass window"};
    pvs_file_desc d;
    pvs_file f;
    size_t size, plain_size;
    uint8_t *good, *plain, *b;
    uint32_t nm, i;
    rng_state = 4242;
    make_table(CELLS, OBJECTS, 50, 10, 0, boxes, pvs);
    desc_init(&d, boxes, CELLS, OBJECTS, pvs);
    plain = encode(&d, &plain_size);
    d.object_names = names;
    good = encode(&d, &size);
    CHECK(plain && good && size == plain_size + 16 + 64); /* a table entry; the count, 5 ends, 36 bytes of text */
    if (!plain || !good) return;
    CHECK(pvs_file_open(plain, plain_size, &f, NULL) == PVS_OK && !pvs_file_object_name(&f, 0) &&
          pvs_file_find_object(&f, "floor") == PVS_NO_OBJECT);
    CHECK(pvs_file_open(good, size, &f, NULL) == PVS_OK);
    CHECK(!strcmp(pvs_file_object_name(&f, 0), "floor") && !strcmp(pvs_file_object_name(&f, 2), "") &&
          !strcmp(pvs_file_object_name(&f, 4), "glass window") && !pvs_file_object_name(&f, OBJECTS));
    CHECK(pvs_file_find_object(&f, "crate_1") == 1 && pvs_file_find_object(&f, "") == 2 &&
          pvs_file_find_object(&f, "crate") == PVS_NO_OBJECT && pvs_file_find_object(&f, NULL) == PVS_NO_OBJECT);
    nm = section(good, "NAME");
    b = (uint8_t *)malloc(size);
    CHECK(nm && b);
    if (nm && b) {
        uint32_t text = nm + 4 + 4 * OBJECTS;
        for (i = 0; i < 6; ++i) {
            memcpy(b, good, size);
            if (i == 0) test_wr32(b + nm, OBJECTS - 1);                         /* not one name per object */
            if (i == 1) test_wr32(b + nm + 8, test_rd32(b + nm + 4));           /* an empty name: ends not ascending */
            if (i == 2) b[text + 2] = 0;                                        /* a zero inside a name */
            if (i == 3) b[text + 5] = 'x';                                      /* a name without its zero */
            if (i == 4) test_wr32(b + nm + 4 * OBJECTS, test_rd32(b + nm + 4 * OBJECTS) - 1); /* a byte after the last */
            if (i == 5) test_wr32(b + nm + 4, 0xfffffff0u);                     /* past the section */
            pvs_fuzz_fix_checksums(b, size);
            CHECK(expect_open(b, size, PVS_ERROR_BAD_SECTION));
        }
    }
    free(b);
    free(good);
    free(plain);
}

void test_format(void) {
    test_round_trip();
    test_grouped_order();
    test_special_tables();
    test_chain_bound();
    test_corruptions();
    test_cycle();
    test_tree_flat_cells();
    test_shards();
    test_golden();
    test_corpus();
    test_names();
    test_no_lookup();
}
