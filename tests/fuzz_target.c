/* fuzz_target.c - what the fuzzer and the corpus replay do with one input: open it as a .pvs file
   and, when it opens, exercise every runtime path on it (decode each cell, walk the cursor, look up
   points, decode the virtual occluders and rebuild cells from them). Returns the open result;
   crashes and sanitizer reports are the failures. */
#include "../pvs.h"
#include <stdlib.h>
#include <string.h>

int pvs_fuzz_one(const uint8_t *data, size_t size);
void pvs_fuzz_fix_checksums(uint8_t *f, size_t size);

/* Reference CRC-32 (IEEE), bit by bit: independent of the header's table version. */
static uint32_t fuzz_crc32(const uint8_t *p, size_t n, uint32_t c) {
    size_t i;
    int k;
    c = ~c;
    for (i = 0; i < n; ++i) {
        c ^= p[i];
        for (k = 0; k < 8; ++k) c = (c >> 1) ^ (0xedb88320u & (0u - (c & 1u)));
    }
    return ~c;
}
static uint32_t rd(const uint8_t *p) { return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24; }
static void wr(uint8_t *p, uint32_t v) { p[0] = (uint8_t)v; p[1] = (uint8_t)(v >> 8); p[2] = (uint8_t)(v >> 16); p[3] = (uint8_t)(v >> 24); }

/* Rewrites every checksum so that mutations reach the checks behind them. */
void pvs_fuzz_fix_checksums(uint8_t *f, size_t size) {
    uint32_t n, i, c;
    if (size < 32) return;
    n = rd(f + 12);
    if (n > 64 || 32 + 16 * (size_t)n > size) return;
    for (i = 0; i < n; ++i) {
        uint8_t *e = f + 32 + 16 * i;
        uint32_t off = rd(e + 4), sz = rd(e + 8);
        if ((uint64_t)off + sz <= size) wr(e + 12, fuzz_crc32(f + off, sz, 0));
    }
    c = fuzz_crc32(f, 20, 0);
    wr(f + 20, fuzz_crc32(f + 32, 16 * (size_t)n, c));
}

static int fuzz_open(const uint8_t *data, size_t size);

/* The file's object order (MODL) names every object once. Open accepts a repeated id (it only garbles PVSs); then
   decode, which works in the file's order, and the cursor's one-delta moves, in object ids, may garble differently. */
static int order_is_permutation(const pvs_file *f) {
    uint32_t w = f->private_.order_bits, k, j, o;
    uint8_t *seen;
    int ok = 1;
    if (!w) return 1;
    seen = (uint8_t *)calloc(f->object_count, 1);
    if (!seen) return 0;
    for (k = 0; ok && k < f->object_count; ++k) {
        uint64_t at = (uint64_t)k * w;
        for (o = 0, j = 0; j < w; ++j, ++at) o |= (uint32_t)(f->private_.order[at >> 3] >> (at & 7u) & 1u) << j;
        ok = o < f->object_count && !seen[o];
        if (ok) seen[o] = 1;
    }
    free(seen);
    return ok;
}

/* The input as it is, then with repaired checksums. Returns the first result. */
int pvs_fuzz_one(const uint8_t *data, size_t size) {
    int r = fuzz_open(data, size);
    if (size >= 32) {
        uint8_t *copy = (uint8_t *)malloc(size);
        if (copy) {
            memcpy(copy, data, size);
            pvs_fuzz_fix_checksums(copy, size);
            fuzz_open(copy, size);
            free(copy);
        }
    }
    return r;
}

static int fuzz_open(const uint8_t *data, size_t size) {
    pvs_file f;
    pvs_error e;
    pvs_result r = pvs_file_open(data, size, &f, &e);
    if (r != e.result || r > 0 || r <= PVS_RESULT_MIN) abort(); /* every result is a defined code */
    if (r == PVS_OK && f.object_count <= (1u << 20)) { /* huge (valid) object counts: opening is the test */
        size_t words = PVS_BITSET_WORDS(f.object_count);
        pvs_word *bits = (pvs_word *)malloc(words * sizeof(pvs_word)), *cur = (pvs_word *)malloc(words * sizeof(pvs_word)),
                 *scratch = (pvs_word *)malloc(words * sizeof(pvs_word));
        pvs_cursor cursor;
        /* cells exercised: at most 4096, and about 2^23 bits decoded each way (a decode reads up to K + 1
           records of object_count bits): inputs declaring 459,133 objects took 2 s a unit under ASan */
        uint64_t fit = ((uint64_t)1 << 23) / ((uint64_t)f.object_count * (f.max_chain + 1u));
        uint32_t c, n = f.cell_count < 4096 ? f.cell_count : 4096;
        int agree = order_is_permutation(&f);
        if (n > fit) n = fit ? (uint32_t)fit : 1u;
        if (bits && cur && scratch && pvs_cursor_init(&cursor, &f, cur, scratch, words, NULL) == PVS_OK) {
            for (c = 0; c < n; ++c) {
                pvs_box b = pvs_file_cell_box(&f, c);
                float mid[3];
                pvs_record_info info;
                int k;
                for (k = 0; k < 3; ++k) mid[k] = b.min[k] + 0.5f * (b.max[k] - b.min[k]);
                (void)pvs_file_find_cell(&f, mid); /* a mutated tree may answer wrongly, never unsafely */
                if (pvs_file_decode(&f, c, bits, words, NULL) != PVS_OK) abort();
                pvs_file_get_record_info(&f, c, &info);
                if (info.depth > f.max_chain) abort();
                if (pvs_cursor_move(&cursor, (c * 7919u) % f.cell_count, NULL, NULL) != PVS_OK) abort();
                if (pvs_cursor_move(&cursor, c, NULL, NULL) != PVS_OK) abort();
                if (agree && memcmp(cur, bits, words * sizeof(pvs_word))) abort(); /* the cursor agrees with decode */
            }
            if (f.vocc_flags & PVS_VOCC_STORED) { /* virtual occluders: decode them, rebuild a few cells */
                static uint8_t vscratch[1 << 17];
                pvs_box *boxes = (pvs_box *)malloc(((size_t)f.object_count + 1) * sizeof(pvs_box));
                uint32_t i, total = 0;
                for (i = 0; boxes && i < f.object_count; ++i) {
                    int k;
                    for (k = 0; k < 3; ++k) { boxes[i].min[k] = (float)(i % 13) - 6.0f; boxes[i].max[k] = boxes[i].min[k] + (float)(i % 3); }
                }
                for (c = 0; c < n; ++c) {
                    pvs_virtual_occluder vo[8];
                    uint32_t m = pvs_file_virtual_occluders(&f, c, vo, 8);
                    if (m > 255 || pvs_file_vocc_record(&f, c, NULL, NULL) != m) abort();
                    total += m;
                    if (boxes && c < 64 && f.object_count <= 4096 &&
                        pvs_vocc_cull(&f, c, 0, boxes, f.object_count, NULL, vscratch, sizeof(vscratch), bits, NULL) != PVS_OK)
                        abort();
                }
                if (n == f.cell_count && total != f.virtual_occluder_count) abort();
                free(boxes);
            }
        }
        free(bits);
        free(cur);
        free(scratch);
    }
    return (int)r;
}
