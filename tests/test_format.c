/* test_format.c - the .pvs container: round trips, every truncation, corruptions with valid
   checksums (reference CRC below), decode safety */
#include "test.h"
#include "../pvs.h"
#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Reference CRC-32 (IEEE), bit by bit: independent of the header's table version. */
static uint32_t ref_crc32(const uint8_t *p, size_t n) {
    uint32_t c = 0xffffffffu;
    size_t i;
    int k;
    for (i = 0; i < n; ++i) {
        c ^= p[i];
        for (k = 0; k < 8; ++k) c = (c >> 1) ^ (0xedb88320u & (0u - (c & 1u)));
    }
    return ~c;
}
static uint32_t rd32(const uint8_t *p) { return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24; }
static void wr32(uint8_t *p, uint32_t v) { p[0] = (uint8_t)v; p[1] = (uint8_t)(v >> 8); p[2] = (uint8_t)(v >> 16); p[3] = (uint8_t)(v >> 24); }

/* Recompute every checksum so that a corruption reaches the deeper checks. */
static void fix_checksums(uint8_t *f, size_t size) {
    uint32_t n, i;
    if (size < 32) return;
    n = rd32(f + 12);
    if (n > 64 || 32 + 16 * (size_t)n > size) return;
    for (i = 0; i < n; ++i) {
        uint8_t *e = f + 32 + 16 * i;
        uint32_t off = rd32(e + 4), sz = rd32(e + 8);
        if ((uint64_t)off + sz <= size) wr32(e + 12, ref_crc32(f + off, sz));
    }
    {
        uint8_t *tmp = (uint8_t *)malloc(20 + 16 * (size_t)n);
        memcpy(tmp, f, 20);
        memcpy(tmp + 20, f + 32, 16 * (size_t)n);
        wr32(f + 20, ref_crc32(tmp, 20 + 16 * (size_t)n));
        free(tmp);
    }
}

static uint64_t rng_state = 12345;
static uint32_t rnd(void) {
    rng_state = rng_state * 6364136223846793005ull + 1442695040888963407ull;
    return (uint32_t)(rng_state >> 33);
}

/* A random table: cells on a line with spatially coherent PVSs of the given density. */
static void make_table(uint32_t cells, uint32_t objects, uint32_t density_pct, pvs_box *boxes, pvs_word *pvs) {
    size_t words = PVS_BITSET_WORDS(objects);
    uint32_t c, o;
    memset(pvs, 0, cells * words * sizeof(pvs_word));
    for (c = 0; c < cells; ++c) {
        int k;
        for (k = 0; k < 3; ++k) {
            boxes[c].min[k] = (float)c * 2.0f + (float)k;
            boxes[c].max[k] = boxes[c].min[k] + 1.0f + (float)(rnd() % 4);
        }
        for (o = 0; o < objects; ++o) {
            int on = c > 0 && rnd() % 100 < 80 ? pvs_bitset_test(pvs + (c - 1) * words, o) : rnd() % 100 < density_pct;
            if (on) pvs_bitset_set(pvs + c * words, o);
        }
    }
}

static int expect_open(const uint8_t *data, size_t size, pvs_result want) {
    pvs_file f;
    pvs_error e;
    pvs_result r = pvs_file_open(data, size, &f, &e);
    if (r != want) fprintf(stderr, "open: got %d (%s), want %d\n", (int)r, e.message, (int)want);
    return r == want && e.result == r;
}

static void test_round_trip(void) {
    static const uint32_t shapes[][3] = {{1, 1, 50}, {1, 64, 0}, {3, 64, 100}, {17, 65, 10}, {100, 1000, 5}, {50, 3000, 60}, {7, 130, 100}};
    size_t s;
    for (s = 0; s < sizeof(shapes) / sizeof(shapes[0]); ++s) {
        uint32_t cells = shapes[s][0], objects = shapes[s][1], c;
        size_t words = PVS_BITSET_WORDS(objects), bound, size;
        pvs_box *boxes = (pvs_box *)malloc(cells * sizeof(pvs_box));
        pvs_word *pvs = (pvs_word *)malloc(cells * words * sizeof(pvs_word));
        pvs_word *got = (pvs_word *)malloc((words + 1) * sizeof(pvs_word));
        pvs_file_desc d;
        pvs_file f;
        pvs_error e;
        uint8_t *buf;
        make_table(cells, objects, shapes[s][2], boxes, pvs);
        memset(&d, 0, sizeof(d));
        d.cells = boxes;
        d.cell_count = cells;
        d.object_count = objects;
        d.pvs = pvs;
        d.method = PVS_METHOD_SAMPLE;
        d.eps = 0.5f;
        d.up_axis = 1;
        d.flags = PVS_FILE_APPROXIMATE;
        bound = pvs_file_bound(&d);
        CHECK(bound > 0);
        buf = (uint8_t *)malloc(bound);
        CHECK(pvs_file_encode(&d, buf, 10, &size, &e) == PVS_ERROR_BUFFER_TOO_SMALL);
        CHECK(pvs_file_encode(&d, buf, bound, &size, &e) == PVS_OK);
        CHECK(size <= bound && size % 8 == 0);
        CHECK(pvs_file_open(buf, size, &f, &e) == PVS_OK);
        CHECK(f.cell_count == cells && f.object_count == objects && f.method == PVS_METHOD_SAMPLE && f.eps == 0.5f);
        CHECK(f.flags == PVS_FILE_APPROXIMATE && f.up_axis == 1);
        for (c = 0; c < cells; ++c) {
            pvs_box b = pvs_file_cell_box(&f, c);
            float mid[3];
            int k;
            CHECK(memcmp(&b, &boxes[c], sizeof(b)) == 0);
            CHECK(pvs_file_decode(&f, c, got, words + 1, &e) == PVS_OK);
            CHECK(memcmp(got, pvs + c * words, words * sizeof(pvs_word)) == 0 && got[words] == 0);
            for (k = 0; k < 3; ++k) mid[k] = 0.5f * (b.min[k] + b.max[k]);
            CHECK(pvs_file_find_cell(&f, mid) <= c); /* overlapping cells: lowest id */
        }
        {
            float far_away[3] = {-1000, -1000, -1000};
            CHECK(pvs_file_find_cell(&f, far_away) == PVS_NO_CELL);
        }
        CHECK(pvs_file_decode(&f, cells, got, words, &e) == PVS_ERROR_INVALID_ARGUMENT);
        if (words > 1) CHECK(pvs_file_decode(&f, 0, got, words - 1, &e) == PVS_ERROR_BUFFER_TOO_SMALL);
        /* deterministic */
        {
            uint8_t *again = (uint8_t *)malloc(bound);
            size_t size2;
            CHECK(pvs_file_encode(&d, again, bound, &size2, &e) == PVS_OK && size2 == size && memcmp(buf, again, size) == 0);
            free(again);
        }
        /* every truncated prefix is rejected, from a buffer placed flush against its allocation's end */
        {
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
    }
}

/* Encode a small valid file into a fresh buffer of exactly its size. */
static uint8_t *small_file(size_t *size) {
    pvs_box boxes[5];
    pvs_word pvs[5 * 2];
    pvs_file_desc d;
    uint8_t *buf;
    size_t bound;
    make_table(5, 100, 30, boxes, pvs);
    memset(&d, 0, sizeof(d));
    d.cells = boxes;
    d.cell_count = 5;
    d.object_count = 100;
    d.pvs = pvs;
    d.method = PVS_METHOD_SAMPLE;
    d.up_axis = 2;
    bound = pvs_file_bound(&d);
    buf = (uint8_t *)malloc(bound);
    pvs_file_encode(&d, buf, bound, size, NULL);
    return buf;
}

static void test_corruptions(void) {
    size_t size, i;
    uint8_t *good = small_file(&size), *b = (uint8_t *)malloc(size);
    pvs_word bits[2];
    pvs_file f0;
    int round;
    CHECK(expect_open(good, size, PVS_OK));
#define RESET() memcpy(b, good, size)
    RESET(); b[0] = 'X';                       CHECK(expect_open(b, size, PVS_ERROR_BAD_MAGIC));
    RESET(); wr32(b + 4, 2);                   CHECK(expect_open(b, size, PVS_ERROR_BAD_VERSION));
    RESET(); wr32(b + 8, (uint32_t)size - 8); fix_checksums(b, size); CHECK(expect_open(b, size, PVS_ERROR_BAD_HEADER));
    RESET(); b[16] ^= 0x80;                    CHECK(expect_open(b, size, PVS_ERROR_CHECKSUM));
    RESET(); wr32(b + 12, 0); fix_checksums(b, size); CHECK(expect_open(b, size, PVS_ERROR_BAD_HEADER));
    RESET(); wr32(b + 12, 65); fix_checksums(b, size); CHECK(expect_open(b, size, PVS_ERROR_BAD_HEADER));
    RESET(); wr32(b + 24, 1); fix_checksums(b, size); CHECK(expect_open(b, size, PVS_ERROR_BAD_HEADER));
    /* section table: misaligned, out of the file, overlapping, repeated tag, missing tag */
    RESET(); wr32(b + 32 + 4, rd32(b + 32 + 4) + 4); fix_checksums(b, size); CHECK(expect_open(b, size, PVS_ERROR_BAD_SECTION));
    RESET(); wr32(b + 32 + 8, (uint32_t)size); fix_checksums(b, size); CHECK(expect_open(b, size, PVS_ERROR_TRUNCATED));
    RESET(); wr32(b + 48 + 4, rd32(b + 32 + 4)); fix_checksums(b, size); CHECK(expect_open(b, size, PVS_ERROR_BAD_SECTION));
    RESET(); wr32(b + 48, rd32(b + 32)); fix_checksums(b, size); CHECK(expect_open(b, size, PVS_ERROR_BAD_SECTION));
    RESET(); b[48] = 'Z'; fix_checksums(b, size); CHECK(expect_open(b, size, PVS_ERROR_BAD_SECTION));
    RESET(); b[rd32(b + 32 + 4) + 2] ^= 1;    CHECK(expect_open(b, size, PVS_ERROR_CHECKSUM));
    /* META fields */
    {
        uint32_t m = rd32(b + 32 + 4);
        RESET(); wr32(b + m, 0); fix_checksums(b, size); CHECK(expect_open(b, size, PVS_ERROR_BAD_HEADER));
        RESET(); wr32(b + m, 6); fix_checksums(b, size); CHECK(expect_open(b, size, PVS_ERROR_BAD_SECTION));
        RESET(); wr32(b + m + 4, 0); fix_checksums(b, size); CHECK(expect_open(b, size, PVS_ERROR_BAD_HEADER));
        RESET(); wr32(b + m + 4, 50); fix_checksums(b, size); CHECK(expect_open(b, size, PVS_ERROR_OBJECT_OUT_OF_RANGE));
        RESET(); wr32(b + m + 8, 99); fix_checksums(b, size); CHECK(expect_open(b, size, PVS_ERROR_BAD_HEADER));
        RESET(); wr32(b + m + 12, 0x7fc00000u); fix_checksums(b, size); CHECK(expect_open(b, size, PVS_ERROR_BAD_HEADER));
        RESET(); wr32(b + m + 16, 0); fix_checksums(b, size); CHECK(expect_open(b, size, PVS_ERROR_BAD_HEADER));
        RESET(); wr32(b + m + 20, 7); fix_checksums(b, size); CHECK(expect_open(b, size, PVS_ERROR_BAD_HEADER));
    }
    /* a NaN cell box, min > max */
    {
        uint32_t c = rd32(b + 48 + 4);
        RESET(); wr32(b + c + 4, 0x7fc00000u); fix_checksums(b, size); CHECK(expect_open(b, size, PVS_ERROR_BAD_CELL));
        RESET(); wr32(b + c + 0, 0x7f000000u); fix_checksums(b, size); CHECK(expect_open(b, size, PVS_ERROR_BAD_CELL));
    }
    /* records: offsets, varints, ids */
    {
        uint32_t r = rd32(b + 64 + 4), first = rd32(b + r), second;
        RESET(); wr32(b + r, first + 1); fix_checksums(b, size); CHECK(expect_open(b, size, PVS_ERROR_BAD_RECORD));
        RESET(); second = rd32(b + r + 4); wr32(b + r + 8, second - 1); fix_checksums(b, size); CHECK(expect_open(b, size, PVS_ERROR_BAD_RECORD));
        RESET(); b[r + first] = 0xff; fix_checksums(b, size); CHECK(pvs_file_open(b, size, &f0, NULL) < 0);
        RESET(); b[r + first + 1] = 120; fix_checksums(b, size); CHECK(expect_open(b, size, PVS_ERROR_OBJECT_OUT_OF_RANGE));
    }
    /* a non-zero padding byte: the CELL section (5 * 24 = 120 bytes) ends 8-aligned, so look for a gap */
    {
        uint32_t r = rd32(b + 64 + 4), rs = rd32(b + 64 + 8);
        if ((size_t)r + rs < size) {
            RESET(); b[size - 1] = 1; CHECK(expect_open(b, size, PVS_ERROR_BAD_SECTION));
        }
    }
    /* random corruptions with repaired checksums: never a crash, always a defined code, and an
       accepted file always decodes */
    for (round = 0; round < 20000; ++round) {
        pvs_file f;
        pvs_error e;
        pvs_result res;
        int flips = 1 + (int)(rnd() % 4), k;
        RESET();
        for (k = 0; k < flips; ++k) b[rnd() % size] ^= (uint8_t)(1u << (rnd() % 8));
        if (rnd() % 4) fix_checksums(b, size);
        res = pvs_file_open(b, size, &f, &e);
        CHECK(res <= 0 && res > PVS_RESULT_MIN && e.result == res);
        if (res == PVS_OK)
            for (i = 0; i < f.cell_count; ++i)
                CHECK(pvs_file_decode(&f, (uint32_t)i, bits, 2, NULL) ==
                      (PVS_BITSET_WORDS(f.object_count) <= 2 ? PVS_OK : PVS_ERROR_BUFFER_TOO_SMALL));
    }
    CHECK(expect_open(NULL, 0, PVS_ERROR_TRUNCATED));
    CHECK(pvs_file_open(good, size, NULL, NULL) == PVS_ERROR_INVALID_ARGUMENT);
#undef RESET
    free(good);
    free(b);
}

void test_format(void) {
    test_round_trip();
    test_corruptions();
}
