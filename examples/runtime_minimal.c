/* runtime_minimal.c - what a constrained platform does with a .pvs file: no heap, no tool code,
   only pvs.h and libc. The file's bytes sit in a static buffer (in a real engine: memory-mapped,
   loaded into a pool, or in ROM); pvs_file_open validates them in place; each step of a camera path
   finds the cell and moves a cursor, which reports only the objects that enter or leave the set,
   and the example toggles one draw flag per report. pvs.h's allocator hooks are routed to counters
   here: they must stay at zero.

   The path is a walk through the file's own cells: from the first cell's centre, steps of 1.5 m
   along a heading on the ground axes, turning when the next step would leave every cell (a viewer
   staying on the streets) and now and then at random; deterministic. At the end the draw flags must equal the current cell's decoded PVS.

   Usage: pvsruntime FILE.pvs [STEPS]   (make demo runs it on build/demo/city.pvs)
   Exit status: 0 ok, 1 bad file or inconsistent flags, 2 usage. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static unsigned long pvs_allocations, pvs_frees;
static void *counting_malloc(size_t size) { ++pvs_allocations; return malloc(size); }
static void counting_free(void *p) { ++pvs_frees; free(p); }
#define PVS_MALLOC(sz) counting_malloc(sz)
#define PVS_FREE(p) counting_free(p)
#define PVS_RUNTIME_ONLY /* the run-time part alone: reader, cell look-up, decoding, cursor (about 30 KB of code) */
#define PVS_IMPLEMENTATION
#include "../pvs.h"

#define MAX_FILE (4u << 20)        /* bytes */
#define MAX_OBJECTS 65536u
#define WORDS PVS_BITSET_WORDS(MAX_OBJECTS)

static uint64_t file_storage[MAX_FILE / 8];   /* 8-byte aligned, like a mapped file */
static pvs_word visible[WORDS], scratch[WORDS], check[WORDS];
static unsigned char draw_flag[MAX_OBJECTS];

typedef struct counts {
    unsigned long shown, hidden, drawn;
} counts;

/* The cursor's report: one object appears or disappears. */
static void on_change(void *user, uint32_t object, int is_visible) {
    counts *c = (counts *)user;
    draw_flag[object] = (unsigned char)is_visible;
    if (is_visible) { ++c->shown; ++c->drawn; }
    else { ++c->hidden; --c->drawn; }
}

int main(int argc, char **argv) {
    FILE *f;
    size_t size;
    pvs_file file;
    pvs_error err;
    pvs_cursor cursor;
    counts cnt = {0, 0, 0};
    unsigned long steps = 4000, s, changes = 0, max_drawn = 0, sum_drawn = 0, no_cell = 0;
    uint32_t cell, i, visited_cells = 0, heading = 0;
    uint64_t rng = 0x2545f4914f6cdd1dull;
    float p[3];
    pvs_box box;
    static unsigned char seen_cell[1u << 16];

    if (argc < 2 || argc > 3) {
        fprintf(stderr, "usage: pvsruntime FILE.pvs [STEPS]\n");
        return 2;
    }
    if (argc == 3) steps = strtoul(argv[2], NULL, 10);
    f = fopen(argv[1], "rb");
    if (!f) { fprintf(stderr, "pvsruntime: cannot open %s\n", argv[1]); return 1; }
    size = fread(file_storage, 1, sizeof(file_storage), f);
    if (!feof(f) && size == sizeof(file_storage)) { fprintf(stderr, "pvsruntime: %s is larger than %u bytes\n", argv[1], MAX_FILE); fclose(f); return 1; }
    fclose(f);

    /* ---- from here on: the runtime, no allocation ---- */
    if (pvs_file_open(file_storage, size, &file, &err) != PVS_OK) {
        fprintf(stderr, "pvsruntime: %s: %s\n", argv[1], err.message);
        return 1;
    }
    if (file.object_count > MAX_OBJECTS) { fprintf(stderr, "pvsruntime: %u objects > %u\n", file.object_count, MAX_OBJECTS); return 1; }
    if (pvs_cursor_init(&cursor, &file, visible, scratch, WORDS, &err) != PVS_OK) { fprintf(stderr, "pvsruntime: %s\n", err.message); return 1; }

    box = pvs_file_cell_box(&file, 0);
    for (i = 0; i < 3; ++i) p[i] = 0.5f * (box.min[i] + box.max[i]);
    cell = PVS_NO_CELL;
    for (s = 0; s < steps; ++s) {
        uint32_t c = pvs_file_find_cell(&file, p), tries;
        if (c == PVS_NO_CELL) { ++no_cell; c = cell; } /* left every cell: keep the last set (an engine's choice) */
        if (c != cell) {
            pvs_cursor_move(&cursor, c, on_change, &cnt);
            ++changes;
            cell = c;
            if (c < sizeof(seen_cell) && !seen_cell[c]) { seen_cell[c] = 1; ++visited_cells; }
        }
        sum_drawn += cnt.drawn;
        if (cnt.drawn > max_drawn) max_drawn = cnt.drawn;
        /* the next step: 1.5 m along the current heading (+-x or +-z); a new random heading when that
           leaves every cell, and now and then at will (a viewer turning at a crossing) */
        rng ^= rng << 13; rng ^= rng >> 7; rng ^= rng << 17;
        if ((rng >> 40) % 50u == 0) heading = (uint32_t)(rng >> 20) % 4u;
        for (tries = 0; tries < 12; ++tries) {
            float q[3];
            q[0] = p[0]; q[1] = p[1]; q[2] = p[2];
            if (heading == 0) q[0] += 1.5f; else if (heading == 1) q[0] -= 1.5f; else if (heading == 2) q[2] += 1.5f; else q[2] -= 1.5f;
            if (pvs_file_find_cell(&file, q) != PVS_NO_CELL) { p[0] = q[0]; p[1] = q[1]; p[2] = q[2]; break; }
            rng ^= rng << 13; rng ^= rng >> 7; rng ^= rng << 17;
            heading = (uint32_t)(rng >> 33) % 4u;
        }
    }
    /* the draw flags are the current cell's PVS */
    {
        unsigned long bad = 0;
        pvs_file_decode(&file, cell, check, WORDS, NULL);
        for (i = 0; i < file.object_count; ++i) bad += (unsigned long)(draw_flag[i] != pvs_bitset_test(check, i));
        printf("pvsruntime: %s, %zu bytes in a static buffer: %u cells, %u objects\n", argv[1], size, file.cell_count, file.object_count);
        printf("  path            %lu steps of 1.5 m, %lu cell changes, %u distinct cells\n", steps, changes, visited_cells);
        printf("  cursor moves    %llu by one delta, %llu by a full decode\n", (unsigned long long)cursor.delta_moves,
               (unsigned long long)cursor.full_moves);
        printf("  draw flags      %lu set, %lu cleared; drawn objects mean %.1f, max %lu\n", cnt.shown, cnt.hidden,
               steps ? (double)sum_drawn / steps : 0.0, max_drawn);
        printf("  check           draw flags equal the decoded PVS of the last cell: %s\n", bad ? "NO" : "yes");
        printf("  allocations     %lu through pvs.h's hooks (frees %lu), none in this program\n", pvs_allocations, pvs_frees);
        return bad || pvs_allocations ? 1 : 0;
    }
}
