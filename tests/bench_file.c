/* bench_file.c - `make bench` figures of the .pvs file on the demo city (baked as `make demo` does):
   size against raw bitsets and Quake-style zero-run rows, look-up, decode and cursor speed.
   Prints BENCH <name> <value> <unit>; asserts nothing. `bench_file --explore` also prints the size
   for other chain bounds. */
#include "../tools/cli.h"
#include "test.h"
#include <stdlib.h>
#include <string.h>

static uint64_t rng = 99;
static uint32_t rnd(void) { return test_lcg31(&rng); }

/* Quake's PVS rows: every byte of the bit row, a zero byte followed by the count of zero bytes. */
static size_t quake_rle_size(const pvs_word *bits, uint32_t n) {
    size_t bytes = (n + 7) / 8, i, out = 0;
    for (i = 0; i < bytes;) {
        uint8_t b = (uint8_t)(bits[i >> 3] >> (8 * (i & 7)));
        if (b) { ++out; ++i; continue; }
        {
            size_t run = 0;
            while (i < bytes && run < 255 && !(uint8_t)(bits[i >> 3] >> (8 * (i & 7)))) { ++run; ++i; }
            out += 2;
        }
    }
    return out;
}

static size_t encode(const pvs_file_desc *d, void **out) {
    size_t size = 0;
    pvs_error e;
    *out = NULL;
    if (pvs_file_encode(d, NULL, 0, &size, &e) != PVS_OK) { fprintf(stderr, "%s\n", e.message); return 0; }
    *out = malloc(size);
    if (pvs_file_encode(d, *out, size, &size, &e) != PVS_OK) { fprintf(stderr, "%s\n", e.message); return 0; }
    return size;
}

static volatile uint32_t sink;
static void count_change(void *user, uint32_t object, int visible) { (void)user; sink += object + (uint32_t)visible; }

/* Microseconds a decode of one cell takes, every cell of the file 50 times. */
static double decode_us(const pvs_file *f, pvs_word *bits, size_t words) {
    uint32_t i, c;
    double t = cli_seconds();
    for (i = 0; i < 50; ++i)
        for (c = 0; c < f->cell_count; ++c) {
            pvs_file_decode(f, c, bits, words, NULL);
            sink += (uint32_t)bits[0];
        }
    return 1e6 * (cli_seconds() - t) / (50.0 * f->cell_count);
}

/* Seconds 10 look-ups of each of 100,000 points take: the best of 5 such runs (a shared machine's noise) */
static double find_cell_s(const pvs_file *f, float (*pts)[3], uint32_t *hits) {
    double best = 1e30;
    int r, c, i;
    for (r = 0; r < 5; ++r) {
        double t = cli_seconds();
        for (c = 0; c < 10; ++c)
            for (i = 0; i < 100000; ++i) *hits += pvs_file_find_cell(f, pts[i]) != PVS_NO_CELL;
        t = cli_seconds() - t;
        if (t < best) best = t;
    }
    return best;
}

int main(int argc, char **argv) {
    int explore = argc > 1 && !strcmp(argv[1], "--explore");
    mesh m;
    mesh_cells cells;
    pvs_scene *scene;
    pvs_bake *bake;
    pvs_bake_desc bd;
    pvs_file_desc fd;
    pvs_file f;
    pvs_error pe;
    tool_error te;
    pvs_word *table, *bits, *scratch;
    uint32_t c, objects, words, i;
    size_t size, raw, rle = 0;
    void *bytes;
    double t;
    if (cli_demo_city(&m, &cells, &scene, &te)) return 1;
    test_bake_desc(&bd, scene, (const pvs_box *)cells.boxes, cells.count, PVS_METHOD_SAMPLE);
    bd.sample.points = 16;
    bd.sample.rays = 1024;
    bd.sample.seed = 1;
    if (pvs_bake_begin(&bd, &bake, &pe) != PVS_OK || cli_run_bake(bake, 2, 1, "bake", &te)) return 1;
    objects = pvs_scene_object_count(scene);
    words = (uint32_t)PVS_BITSET_WORDS(objects);
    table = (pvs_word *)malloc((size_t)cells.count * words * sizeof(pvs_word));
    for (c = 0; c < cells.count; ++c) {
        memcpy(table + (size_t)c * words, pvs_bake_cell_pvs(bake, c), words * sizeof(pvs_word));
        rle += quake_rle_size(table + (size_t)c * words, objects);
    }
    memset(&fd, 0, sizeof(fd));
    fd.cells = (const pvs_box *)cells.boxes;
    fd.cell_count = cells.count;
    fd.object_count = objects;
    fd.pvs = table;
    fd.method = PVS_METHOD_SAMPLE;
    fd.up_axis = 1;
    t = cli_seconds();
    size = encode(&fd, &bytes);
    t = cli_seconds() - t;
    raw = (size_t)cells.count * ((objects + 7) / 8);
    printf("BENCH file_bytes_per_cell %.1f bytes\n", (double)size / cells.count);
    printf("BENCH file_ratio_raw %.3f ratio\n", (double)size / raw);
    printf("BENCH file_ratio_rle %.3f ratio\n", (double)size / rle);
    printf("BENCH file_encode_ms %.1f ms\n", 1000.0 * t);
    if (explore) {
        uint32_t ks[] = {1, 2, 4, 8, 16, 32, 64};
        for (i = 0; i < sizeof(ks) / sizeof(ks[0]); ++i) {
            void *b2;
            fd.max_chain = ks[i];
            printf("explore K=%u: %zu bytes\n", ks[i], encode(&fd, &b2));
            free(b2);
        }
        fd.max_chain = 0;
    }
    if (pvs_file_open(bytes, size, &f, &pe) != PVS_OK) { fprintf(stderr, "%s\n", pe.message); return 1; }
    bits = (pvs_word *)malloc(words * sizeof(pvs_word));
    scratch = (pvs_word *)malloc(words * sizeof(pvs_word));
    /* decode: bitset bytes produced per second */
    {
        double us = decode_us(&f, bits, words);
        printf("BENCH decode_gbps %.2f GB/s\n", (double)words * 8 / us / 1e3);
        printf("BENCH decode_us_per_cell %.2f us\n", us);
    }
    /* decode_cell_us (issue 30's yardstick): the same cells, the first 2,000 objects only */
    if (objects >= 2000) {
        uint32_t n2 = 2000, w2 = (uint32_t)PVS_BITSET_WORDS(2000);
        pvs_word *sub = (pvs_word *)calloc((size_t)cells.count * w2, sizeof(pvs_word));
        void *b2;
        size_t s2;
        pvs_file f2;
        for (c = 0; c < cells.count; ++c) {
            memcpy(sub + (size_t)c * w2, table + (size_t)c * words, w2 * sizeof(pvs_word));
            sub[(size_t)c * w2 + w2 - 1] &= ((pvs_word)1 << (n2 & 63)) - 1u;
        }
        fd.object_count = n2;
        fd.pvs = sub;
        s2 = encode(&fd, &b2);
        if (pvs_file_open(b2, s2, &f2, &pe) != PVS_OK) { fprintf(stderr, "%s\n", pe.message); return 1; }
        printf("BENCH decode_cell_us %.2f us\n", decode_us(&f2, bits, w2));
        fd.object_count = objects;
        fd.pvs = table;
        free(b2);
        free(sub);
    }
    /* cursor: moves between touching cells (a walk), with a change callback */
    {
        uint32_t *path = (uint32_t *)malloc(200000 * sizeof(uint32_t)), steps = 200000, cur = 0;
        pvs_cursor cursor;
        for (i = 0; i < steps; ++i) {
            /* a random touching neighbour of cur, found by a scan from a random start */
            pvs_box a = pvs_file_cell_box(&f, cur);
            uint32_t start = rnd() % cells.count, j, next = cur;
            for (j = 0; j < cells.count; ++j) {
                uint32_t k = (start + j) % cells.count;
                pvs_box b = pvs_file_cell_box(&f, k);
                if (k != cur && a.min[0] <= b.max[0] && b.min[0] <= a.max[0] && a.min[2] <= b.max[2] && b.min[2] <= a.max[2]) {
                    next = k;
                    break;
                }
            }
            path[i] = cur = next;
            if (i > 2000) { /* after a warm-up of real walking, repeat it */
                path[i] = path[i % 2000];
            }
        }
        pvs_cursor_init(&cursor, &f, bits, scratch, words, NULL);
        t = cli_seconds();
        for (i = 0; i < steps; ++i) pvs_cursor_move(&cursor, path[i], count_change, NULL);
        t = cli_seconds() - t;
        printf("BENCH cursor_step_ns %.0f ns\n", 1e9 * t / steps);
        printf("BENCH cursor_delta_moves_pct %.1f %%\n", 100.0 * (double)cursor.delta_moves / (double)(cursor.delta_moves + cursor.full_moves));
        free(path);
    }
    free(bytes);
    /* look-up with 10,000 cells: a 100 x 100 street-level grid over the city, random points */
    {
        enum { G = 100 };
        pvs_box sb = pvs_scene_bounds(scene), *grid = (pvs_box *)malloc(G * G * sizeof(pvs_box));
        pvs_word *t2 = (pvs_word *)calloc((size_t)G * G, sizeof(pvs_word));
        float (*pts)[3] = (float (*)[3])malloc(100000 * sizeof(float[3]));
        uint32_t x, z, hits = 0;
        for (z = 0; z < G; ++z)
            for (x = 0; x < G; ++x) {
                pvs_box *b = grid + z * G + x;
                b->min[0] = sb.min[0] + (sb.max[0] - sb.min[0]) * (float)x / G;
                b->max[0] = sb.min[0] + (sb.max[0] - sb.min[0]) * (float)(x + 1) / G;
                b->min[2] = sb.min[2] + (sb.max[2] - sb.min[2]) * (float)z / G;
                b->max[2] = sb.min[2] + (sb.max[2] - sb.min[2]) * (float)(z + 1) / G;
                b->min[1] = 0.5f;
                b->max[1] = 2.0f;
                t2[z * G + x] = (pvs_word)rnd();
            }
        memset(&fd, 0, sizeof(fd));
        fd.cells = grid;
        fd.cell_count = G * G;
        fd.object_count = 64;
        fd.pvs = t2;
        fd.up_axis = 1;
        size = encode(&fd, &bytes);
        if (pvs_file_open(bytes, size, &f, &pe) != PVS_OK) { fprintf(stderr, "%s\n", pe.message); return 1; }
        for (i = 0; i < 100000; ++i) {
            pts[i][0] = sb.min[0] + (sb.max[0] - sb.min[0]) * (float)(rnd() % 100000) / 100000.0f;
            pts[i][1] = 0.5f + 1.5f * (float)(rnd() % 1000) / 1000.0f;
            pts[i][2] = sb.min[2] + (sb.max[2] - sb.min[2]) * (float)(rnd() % 100000) / 100000.0f;
        }
        t = find_cell_s(&f, pts, &hits);
        printf("BENCH find_cell_ns %.1f ns\n", 1e9 * t / 1e6); /* random points: the worst case for caches */
        /* a viewer's path: steps of about a metre, as a camera moves between frames */
        for (i = 1; i < 100000; ++i) {
            int k;
            for (k = 0; k < 3; k += 2) {
                float step = ((float)(rnd() % 2001) - 1000.0f) * 0.001f, lo = k ? sb.min[2] : sb.min[0], hi = k ? sb.max[2] : sb.max[0];
                pts[i][k] = pts[i - 1][k] + step;
                if (pts[i][k] < lo || pts[i][k] > hi) pts[i][k] = pts[i - 1][k] - step;
            }
            pts[i][1] = pts[i - 1][1];
        }
        t = find_cell_s(&f, pts, &hits);
        printf("BENCH find_cell_walk_ns %.1f ns\n", 1e9 * t / 1e6);
        printf("BENCH grid10k_file_bytes_per_cell %.1f bytes\n", (double)size / (G * G));
        sink += hits;
        free(bytes);
        free(grid);
        free(t2);
        free(pts);
    }
    free(table);
    free(bits);
    free(scratch);
    pvs_bake_destroy(bake);
    pvs_scene_destroy(scene);
    mesh_cells_free(&cells);
    mesh_free(&m);
    return 0;
}
