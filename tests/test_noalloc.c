/* test_noalloc.c - a private (PVS_STATIC) copy of the implementation whose PVS_MALLOC counts calls:
   proves that opening, looking up, decoding and walking a file with the cursor, and rebuilding a
   cell's PVS from its virtual occluders, allocate nothing. */
#include "test.h"
#include <stdlib.h>
#include <string.h>

static long noalloc_mallocs;
static void *noalloc_malloc(size_t n) { ++noalloc_mallocs; return malloc(n); }
#define PVS_MALLOC(n) noalloc_malloc(n)
#define PVS_FREE(p) free(p)
#define PVS_STATIC
#define PVS_IMPLEMENTATION
#include "../pvs.h"

void test_noalloc(void) {
    enum { CELLS = 40, OBJECTS = 500 };
    static pvs_box boxes[CELLS];
    static pvs_word pvs[CELLS * PVS_BITSET_WORDS(OBJECTS)], bits[PVS_BITSET_WORDS(OBJECTS)];
    pvs_file_desc d;
    pvs_file f;
    pvs_error e;
    uint8_t *buf;
    size_t bound, size;
    uint32_t c, i, sum = 0;
    for (c = 0; c < CELLS; ++c) {
        int k;
        for (k = 0; k < 3; ++k) { boxes[c].min[k] = (float)c; boxes[c].max[k] = (float)c + 1.0f; }
        for (i = c; i < OBJECTS; i += 1 + c % 7) pvs_bitset_set(pvs + c * PVS_BITSET_WORDS(OBJECTS), i);
    }
    memset(&d, 0, sizeof(d));
    d.cells = boxes; d.cell_count = CELLS; d.object_count = OBJECTS; d.pvs = pvs; d.up_axis = 1;
    CHECK(pvs_file_encode(&d, NULL, 0, &bound, &e) == PVS_OK);
    buf = (uint8_t *)malloc(bound);
    CHECK(pvs_file_encode(&d, buf, bound, &size, &e) == PVS_OK);
    noalloc_mallocs = 0;
    CHECK(pvs_file_open(buf, size, &f, &e) == PVS_OK);
    for (c = 0; c < CELLS; ++c) {
        float p[3];
        p[0] = p[1] = p[2] = (float)c + 0.5f;
        CHECK(pvs_file_find_cell(&f, p) == c);
        CHECK(pvs_file_decode(&f, c, bits, PVS_BITSET_WORDS(OBJECTS), &e) == PVS_OK);
        for (i = pvs_bitset_next(bits, OBJECTS, 0); i < OBJECTS; i = pvs_bitset_next(bits, OBJECTS, i + 1)) sum += i;
    }
    {
        static pvs_word cur[PVS_BITSET_WORDS(OBJECTS)], scratch[PVS_BITSET_WORDS(OBJECTS)];
        pvs_cursor cursor;
        CHECK(pvs_cursor_init(&cursor, &f, cur, scratch, PVS_BITSET_WORDS(OBJECTS), &e) == PVS_OK);
        for (c = 0; c < 3 * CELLS; ++c) CHECK(pvs_cursor_move(&cursor, (c * 7) % CELLS, NULL, NULL) == PVS_OK);
        for (c = 0; c < CELLS; ++c) { /* from each cell's base into it: one delta */
            pvs_record_info info;
            pvs_file_record_info(&f, c, &info);
            if (info.base != PVS_NO_CELL) CHECK(pvs_cursor_move(&cursor, info.base, NULL, NULL) == PVS_OK);
            CHECK(pvs_cursor_move(&cursor, c, NULL, NULL) == PVS_OK);
        }
        CHECK(cursor.delta_moves > 0);
    }
    CHECK(sum > 0);
    CHECK(noalloc_mallocs == 0);
    free(buf);
    { /* the virtual occluders' rebuild (pvs_vocc_cull), flat and through an object kD-tree */
        static uint8_t counts[CELLS], scales[CELLS], vo[CELLS * 2 * 5];
        static pvs_box objs[OBJECTS];
        static uint8_t scratch[1 << 18];
        pvs_kdtree *tree = NULL;
        pvs_kdtree_desc kd;
        size_t ss;
        for (c = 0; c < CELLS; ++c) {
            counts[c] = 2;
            scales[c] = 160;
            for (i = 0; i < 2; ++i) {
                uint8_t *q = vo + 10 * c + 5 * i;
                q[0] = (uint8_t)(100 + 40 * i); q[1] = 200; q[2] = (uint8_t)(140 + 40 * i); q[3] = 210; q[4] = 200;
            }
        }
        for (i = 0; i < OBJECTS; ++i) {
            int k;
            for (k = 0; k < 3; ++k) { objs[i].min[k] = (float)(i % 37) * 3.0f - 50.0f + (float)k; objs[i].max[k] = objs[i].min[k] + 2.0f; }
        }
        d.vocc_counts = counts; d.vocc_scales = scales; d.virtual_occluders = vo; d.vocc_base = -100.0f; d.vocc_height_step = 1.0f;
        CHECK(pvs_file_encode(&d, NULL, 0, &bound, &e) == PVS_OK);
        buf = (uint8_t *)malloc(bound);
        CHECK(pvs_file_encode(&d, buf, bound, &size, &e) == PVS_OK);
        memset(&kd, 0, sizeof(kd));
        kd.boxes = objs;
        kd.count = OBJECTS;
        CHECK(pvs_kdtree_create(&kd, &tree, &e) == PVS_OK);
        ss = pvs_vocc_cull_scratch_size(tree, 255);
        CHECK(ss <= sizeof(scratch));
        noalloc_mallocs = 0;
        CHECK(pvs_file_open(buf, size, &f, &e) == PVS_OK && (f.vocc_flags & PVS_VOCC_STORED));
        for (c = 0; c < CELLS; ++c) {
            pvs_virtual_occluder out[2];
            CHECK(pvs_file_virtual_occluders(&f, c, out, 2) == 2);
            CHECK(pvs_vocc_cull(&f, c, 0, objs, OBJECTS, NULL, scratch, ss, bits, &e) == PVS_OK);
            CHECK(pvs_vocc_cull(&f, c, 0, objs, OBJECTS, tree, scratch, ss, bits, &e) == PVS_OK);
            CHECK(pvs_vocc_cull_occluders(boxes + c, 1, out, 2, objs, OBJECTS, tree, scratch, ss, bits, &e) == PVS_OK);
        }
        CHECK(noalloc_mallocs == 0);
        pvs_kdtree_destroy(tree);
        free(buf);
    }
}
