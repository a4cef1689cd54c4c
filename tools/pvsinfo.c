/* pvsinfo - inspect a .pvs file: summary, --dump, --at X Y Z, --verify, --vocc, --raw. See --help. */
#include "cli.h"
#include <stdlib.h>
#include <string.h>

static const char *usage =
    "usage: pvsinfo OUT.pvs              summary: counts, sizes, bytes per cell and per section, method, eps\n"
    "       pvsinfo --dump OUT.pvs       one line per cell: \"CELL: OBJ OBJ ...\" (ids ascending)\n"
    "       pvsinfo --at X Y Z OUT.pvs   the cell containing the point and its PVS, same format\n"
    "       pvsinfo --verify OUT.pvs     full validation: exit 0 if sound, 1 with the reason\n"
    "       pvsinfo --vocc OUT.pvs       virtual occluders, one line per cell:\n"
    "                                    \"CELL: u0 v0 u1 v1 top, ...\" (ground end points, top height)\n"
    "       pvsinfo --raw OUT.pvs TABLE  the raw bit table: per cell in order, ceil(objects / 8) bytes,\n"
    "                                    object i in bit i % 8 of byte i / 8 (what general-purpose\n"
    "                                    compressors are compared with: make bench)\n"
    "  Files baked with --vocc-only store placeholder records (every object): --dump and --at print\n"
    "  those; the real PVS is rebuilt from the virtual occluders at run time (pvscheck checks it).\n"
    "exit status: 0 success, 1 bad input (or a point in no cell for --at), 2 usage\n";

#define TOOL "pvsinfo"

typedef struct info_options {
    const char *path;
    int dump, verify, at, vocc; /* at most one, or raw_path */
    float p[3];                 /* --at */
    const char *raw_path;       /* --raw */
} info_options;

/* -1 to go on; otherwise the exit status (0 after --help, 2 after a usage error). */
static int parse_options(int argc, char **argv, info_options *o) {
    int i;
    memset(o, 0, sizeof(*o));
    for (i = 1; i < argc; ++i) {
        const char *a = argv[i];
        if (!strcmp(a, "--help") || !strcmp(a, "-h")) {
            fputs(usage, stdout);
            return 0;
        } else if (!strcmp(a, "--dump")) {
            o->dump = 1;
        } else if (!strcmp(a, "--verify")) {
            o->verify = 1;
        } else if (!strcmp(a, "--vocc")) {
            o->vocc = 1;
        } else if (!strcmp(a, "--raw")) {
            if (i + 1 >= argc) return tool_usage_error(TOOL, "--raw needs OUT.pvs and a TABLE file");
            o->raw_path = argv[argc - 1] == argv[i + 1] ? NULL : argv[argc - 1];
            if (!o->raw_path || i + 2 != argc - 1) return tool_usage_error(TOOL, "usage: pvsinfo --raw OUT.pvs TABLE");
            o->path = argv[i + 1];
            i = argc;
        } else if (!strcmp(a, "--at")) {
            if (parse_floats(argv, i + 1, argc, 3, o->p)) return tool_usage_error(TOOL, "--at needs three numbers X Y Z");
            i += 3;
            o->at = 1;
        } else if (a[0] == '-' && a[1] && !(a[1] >= '0' && a[1] <= '9')) {
            return tool_usage_error(TOOL, "unknown option '%s'", a);
        } else if (!o->path) {
            o->path = a;
        } else {
            return tool_usage_error(TOOL, "unexpected argument '%s'", a);
        }
    }
    if (!o->path) return tool_usage_error(TOOL, "no file given");
    if (o->dump + o->verify + o->at + o->vocc + (o->raw_path != NULL) > 1)
        return tool_usage_error(TOOL, "give at most one of --dump, --at, --verify, --vocc, --raw");
    return -1;
}

static void print_cell(const pvs_file *f, uint32_t cell, pvs_word *bits, size_t words) {
    uint32_t i;
    pvs_file_decode(f, cell, bits, words, NULL);
    printf("%u:", cell);
    for (i = pvs_bitset_next(bits, f->object_count, 0); i < f->object_count; i = pvs_bitset_next(bits, f->object_count, i + 1))
        printf(" %u", i);
    printf("\n");
}

typedef struct raw_table {
    const pvs_file *f;
    pvs_word *bits;
    size_t words;
} raw_table;

/* --raw: the decoded table, cell by cell, each row ceil(objects / 8) little-endian bytes. */
static int write_raw(FILE *out, const void *ctx) {
    const raw_table *t = (const raw_table *)ctx;
    size_t row = ((size_t)t->f->object_count + 7) / 8, i;
    uint32_t c;
    for (c = 0; c < t->f->cell_count; ++c) {
        pvs_file_decode(t->f, c, t->bits, t->words, NULL);
        for (i = 0; i < row; ++i)
            if (fputc((int)(uint8_t)(t->bits[i >> 3] >> (8 * (i & 7))), out) == EOF) return -1;
    }
    return 0;
}

/* --verify: pvs_file_open already validated every byte and chain; here decoding each cell exercises
   the runtime path, and the look-up tree must find every cell at its centre and corners (a file can
   be well formed and still have a tree that disagrees with its cells). 0, or 1 after the reason. */
static int verify_file(const char *path, const pvs_file *f, size_t size, pvs_word *bits, size_t words) {
    uint32_t c, k, j;
    pvs_error pe;
    for (c = 0; c < f->cell_count; ++c) {
        pvs_box b = pvs_file_cell_box(f, c);
        if (pvs_file_decode(f, c, bits, words, &pe) != PVS_OK) {
            fprintf(stderr, "pvsinfo: %s: cell %u: %s\n", path, c, pe.message);
            return 1;
        }
        for (j = 0; j < 9 && !(f->flags & PVS_FILE_NO_LOOKUP); ++j) {
            float q[3];
            for (k = 0; k < 3; ++k) q[k] = j == 8 ? b.min[k] + 0.5f * (b.max[k] - b.min[k]) : ((j >> k) & 1) ? b.max[k] : b.min[k];
            if (pvs_file_find_cell(f, q) > c) {
                fprintf(stderr, "pvsinfo: %s: cell %u: the look-up tree misses the point %g %g %g of its box\n", path, c, q[0], q[1], q[2]);
                return 1;
            }
        }
    }
    printf("%s: ok (%u cells, %u objects, %zu bytes)\n", path, f->cell_count, f->object_count, size);
    return 0;
}

/* --vocc: each cell's virtual occluders. 0, or 1 when the file stores none. */
static int print_vocc(const char *path, const pvs_file *f) {
    uint32_t c, k;
    if (!(f->vocc_flags & PVS_VOCC_STORED)) {
        fprintf(stderr, "pvsinfo: %s: the file stores no virtual occluders\n", path);
        return 1;
    }
    for (c = 0; c < f->cell_count; ++c) {
        pvs_virtual_occluder vo[255];
        uint32_t n = pvs_file_virtual_occluders(f, c, vo, 255);
        printf("%u:", c);
        for (k = 0; k < n; ++k) printf("%s %g %g %g %g %g", k ? "," : "", vo[k].p0[0], vo[k].p0[1], vo[k].p1[0], vo[k].p1[1], vo[k].top);
        printf("\n");
    }
    return 0;
}

/* The summary's lines on the records: delta chains, object order, shards, virtual occluders. */
static void print_records(const pvs_file *f) {
    uint32_t c, deepest = 0;
    uint64_t record_bytes = 0;
    double depth_sum = 0.0;
    for (c = 0; c < f->cell_count; ++c) {
        pvs_record_info info;
        pvs_file_get_record_info(f, c, &info);
        record_bytes += info.bytes;
        depth_sum += info.depth;
        if (info.depth > deepest) deepest = info.depth;
    }
    printf("records     %llu bytes (%.1f per cell): %u key cells, %u deltas; chain mean %.2f, max %u (bound %u)\n",
           (unsigned long long)record_bytes, (double)record_bytes / f->cell_count, f->key_count, f->cell_count - f->key_count,
           depth_sum / f->cell_count, deepest, f->max_chain);
    printf("coding      context-coded bits, objects %s\n", f->private_.order_bits ? "reordered" : "in id order");
    if (f->shard_count)
        printf("part        shard %u of %u (%u cells in the whole bake): combine with pvsbake merge\n", f->shard_index + 1, f->shard_count,
               f->total_cell_count);
    if (f->vocc_flags & PVS_VOCC_STORED) {
        uint32_t most = 0;
        for (c = 0; c < f->cell_count; ++c) {
            uint32_t n = pvs_file_vocc_record(f, c, NULL, NULL);
            if (n > most) most = n;
        }
        printf("vocc        %u virtual occluders (%.2f per cell, at most %u; %.1f bytes per cell); base %g, height step %g\n",
               f->virtual_occluder_count, (double)f->virtual_occluder_count / f->cell_count, most,
               (5.0 * f->virtual_occluder_count + 2.0 * f->cell_count + 4.0 * ((f->cell_count + 15) / 16 + 1) + 16.0) / f->cell_count,
               (double)f->vocc_base, (double)f->vocc_height_step);
        if (f->vocc_flags & PVS_VOCC_ONLY)
            printf("            vocc-only: the records are placeholders (every object); rebuild each PVS with pvs_vocc_cull\n");
    }
}

/* The sections' sizes from the file's table (README, "The file": a 32-byte header, then per section its tag,
   offset, size and CRC as little-endian 32-bit words), in table order; pvs_file_open validated it. */
static void print_sections(const uint8_t *data) {
    uint32_t n = tool_get32(data + 12), k;
    printf("sections   ");
    for (k = 0; k < n; ++k) {
        const uint8_t *e = data + 32 + 16 * (size_t)k;
        printf("%s %.4s %u", k ? "," : "", (const char *)e, tool_get32(e + 8));
    }
    printf(" (bytes)\n");
}

/* No option: counts, sizes, PVS sizes, the sections, then the records. */
static void print_summary(const char *path, const pvs_file *f, const uint8_t *data, size_t size, pvs_word *bits, size_t words) {
    uint32_t c, minp = 0xffffffffu, maxp = 0;
    double sum = 0.0;
    for (c = 0; c < f->cell_count; ++c) {
        uint32_t n;
        pvs_file_decode(f, c, bits, words, NULL);
        n = pvs_bitset_count(bits, f->object_count);
        sum += n;
        if (n < minp) minp = n;
        if (n > maxp) maxp = n;
    }
    printf("file        %s\n", path);
    printf("format      version %u%s\n", f->version, (f->flags & PVS_FILE_APPROXIMATE) ? ", approximate (ray-sampled, not conservative)" : "");
    printf("method      %s\n", pvs_method_name(f->method));
    printf("eps         %g\n", f->eps);
    printf("up axis     %s\n", f->up_axis == 2 ? "z" : "y");
    if (f->scene_fingerprint) printf("scene       fingerprint %016llx\n", (unsigned long long)f->scene_fingerprint);
    else printf("scene       no fingerprint (baked before v0.8.0): a stale file cannot be told\n");
    printf("cells       %u%s\n", f->cell_count, (f->flags & PVS_FILE_NO_LOOKUP) ? ", no boxes or look-up stored (--no-lookup)" : "");
    printf("objects     %u", f->object_count);
    if (pvs_file_object_name(f, 0)) printf(", named (object 0 '%s')\n", pvs_file_object_name(f, 0));
    else printf(", no names stored (a renamed or reordered object cannot be told)\n");
    printf("pvs size    mean %.1f (%.1f%%), min %u, max %u\n", sum / f->cell_count, 100.0 * sum / f->cell_count / f->object_count, minp, maxp);
    printf("bytes       %zu (%.1f per cell; raw bitsets would be %zu)\n", size, (double)size / f->cell_count,
           (size_t)f->cell_count * ((f->object_count + 7) / 8));
    print_sections(data);
    print_records(f);
}

int main(int argc, char **argv) {
    info_options o;
    int rc = parse_options(argc, argv, &o);
    void *data = NULL;
    size_t size = 0, words;
    pvs_file f;
    pvs_error pe;
    tool_error te;
    pvs_word *bits;
    if (rc >= 0) return rc;
    if (read_file(o.path, &data, &size, &te)) {
        fprintf(stderr, "pvsinfo: %s\n", te.message);
        return 1;
    }
    if (pvs_file_open(data, size, &f, &pe) != PVS_OK) {
        if (pe.offset) fprintf(stderr, "pvsinfo: %s: byte %llu: %s\n", o.path, (unsigned long long)pe.offset, pe.message);
        else fprintf(stderr, "pvsinfo: %s: %s\n", o.path, pe.message);
        free(data);
        return 1;
    }
    words = PVS_BITSET_WORDS(f.object_count);
    bits = (pvs_word *)malloc(words * sizeof(pvs_word));
    if (!bits) {
        fprintf(stderr, "pvsinfo: out of memory\n");
        free(data);
        return 1;
    }
    rc = 0;
    if (o.verify) {
        rc = verify_file(o.path, &f, size, bits, words);
    } else if (o.dump) {
        uint32_t c;
        if (f.vocc_flags & PVS_VOCC_ONLY)
            fprintf(stderr, "pvsinfo: %s: placeholder records (vocc-only): the PVS is rebuilt from the virtual occluders at run time\n", o.path);
        for (c = 0; c < f.cell_count; ++c) print_cell(&f, c, bits, words);
    } else if (o.vocc) {
        rc = print_vocc(o.path, &f);
    } else if (o.raw_path) {
        raw_table t;
        t.f = &f;
        t.bits = bits;
        t.words = words;
        if (write_stream_atomic(o.raw_path, write_raw, &t, &te)) {
            fprintf(stderr, "pvsinfo: %s\n", te.message);
            rc = 1;
        }
    } else if (o.at) {
        uint32_t c = pvs_file_find_cell(&f, o.p);
        if (c == PVS_NO_CELL) {
            fprintf(stderr, "pvsinfo: %s: the point %g %g %g is in no cell%s\n", o.path, o.p[0], o.p[1], o.p[2],
                    (f.flags & PVS_FILE_NO_LOOKUP) ? " (the file stores no look-up: --no-lookup)" : "");
            rc = 1;
        } else {
            print_cell(&f, c, bits, words);
        }
    } else {
        print_summary(o.path, &f, data, size, bits, words);
    }
    free(bits);
    free(data);
    return rc;
}
