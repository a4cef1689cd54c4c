/* pvsgen - write a procedural test scene (OBJ) and its view cells.
   usage: pvsgen city|forest|indoor|walls|soup|building [--seed N] [--size S] [--max-cells N] [--dense] -o OUT.obj [--cells OUT_CELLS.txt]
   Exit codes: 0 ok, 1 I/O error or out of memory, 2 usage. */
#if !defined(_WIN32) && !defined(_POSIX_C_SOURCE)
#define _POSIX_C_SOURCE 200809L
#endif
#include "gen.h"
#include "toolutil.h"
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static void usage(FILE *f) {
    fprintf(f,
            "usage: pvsgen city|forest|indoor|walls|soup|building [--seed N] [--size S] [--max-cells N] [--dense]\n"
            "              [--leaves-per-tree N] [--cell-size M] -o OUT.obj [--cells OUT_CELLS.txt]\n"
            "\n"
            "Writes a deterministic procedural test scene as OBJ (Y up, metres, ground at y = 0) and its\n"
            "view cells (one 'minx miny minz maxx maxy maxz' box per line, '#' comments).\n"
            "  --seed N        PRNG seed (default 1)\n"
            "  --size S        scale factor in (0, 8], 1 = default (city ~1 km^2, forest ~300 m square)\n"
            "  --max-cells N   keep at most N cells, evenly spread (0 = all, the default)\n"
            "  --dense         forest only: the dense forest (foliage down to eye height, bushes; from\n"
            "                  inside it only a few percent of the trees can be seen; Durand et al. 2000)\n"
            "  --leaves-per-tree N  with --dense: N leaves per tree (default ~85-105), bushes N / 100 times\n"
            "                  as dense; 1000 is the forest of Durand 2000 §7.2 (1,000 coarse, large leaf\n"
            "                  triangles per tree); N x size^2 <= 10000 (about 40M triangles)\n"
            "  --cell-size M   with --dense: the side of the cells between the trees (default 3 m)\n"
            "  -o OUT.obj      the scene (written to a temporary file, then renamed)\n"
            "  --cells FILE    the view cells (same)\n"
            "Exit codes: 0 ok, 1 I/O error, 2 usage.\n");
}

static int bad_usage(const char *msg, const char *arg) {
    fprintf(stderr, "pvsgen: %s%s%s\n", msg, arg ? ": " : "", arg ? arg : "");
    usage(stderr);
    return 2;
}

typedef int (*writer_fn)(FILE *f, const void *ctx);

typedef struct cells_ctx {
    const mesh_cells *cells;
    const gen_info *info;
    const char *kind;
    int dense;
    unsigned long long seed;
    double size;
} cells_ctx;

static int write_obj(FILE *f, const void *ctx) { return mesh_write_obj((const mesh *)ctx, f); }

static int write_cells(FILE *f, const void *ctx) {
    const cells_ctx *c = (const cells_ctx *)ctx;
    fprintf(f, "# pvsgen %s%s --seed %llu --size %g: %u cells, minx miny minz maxx maxy maxz, Y up\n", c->kind, c->dense ? " --dense" : "", c->seed,
            c->size, c->cells->count);
    if (c->info->touching_count)
        fprintf(f, "# cells %u..%u touch geometry (a face within 1 mm of a wall)\n", c->info->touching_first,
                c->info->touching_first + c->info->touching_count - 1);
    if (c->info->inside_count)
        fprintf(f, "# cells %u..%u are deliberately partly inside buildings\n", c->info->inside_first,
                c->info->inside_first + c->info->inside_count - 1);
    return mesh_cells_write(c->cells, f);
}

/* Writes through write_stream_atomic; prints the error. */
static int write_atomic(const char *path, writer_fn fn, const void *ctx) {
    tool_error err;
    if (write_stream_atomic(path, fn, ctx, &err) == 0) return 0;
    fprintf(stderr, "pvsgen: %s\n", err.message);
    return -1;
}

static int parse_u64(const char *s, unsigned long long *out) {
    char *end;
    if (!s || !*s || *s == '-') return -1;
    errno = 0;
    unsigned long long v = strtoull(s, &end, 0);
    if (errno || *end) return -1;
    *out = v;
    return 0;
}

/* What the command line asks for. */
typedef struct pvsgen_options {
    const char *kind_s, *out, *cells_out, *v_leaves;
    unsigned long long seed, max_cells, leaves;
    int dense;
    double size, cell_size;
    gen_params p;
} pvsgen_options;

/* -1 to go on; otherwise the exit status (0 after --help, 2 after a usage error). */
static int parse_options(int argc, char **argv, pvsgen_options *o) {
    memset(o, 0, sizeof(*o));
    o->seed = 1;
    o->size = 1.0;
    for (int i = 1; i < argc; ++i) {
        const char *a = argv[i];
        const char *v = i + 1 < argc ? argv[i + 1] : NULL;
        if (!strcmp(a, "--help") || !strcmp(a, "-h")) {
            usage(stdout);
            return 0;
        } else if (!strcmp(a, "--seed")) {
            if (parse_u64(v, &o->seed)) return bad_usage("--seed needs a non-negative integer", v);
            ++i;
        } else if (!strcmp(a, "--size")) {
            char *end;
            if (!v) return bad_usage("--size needs a number", NULL);
            o->size = strtod(v, &end);
            if (*end || !(o->size > 0 && o->size <= 8)) return bad_usage("--size must be in (0, 8]", v);
            ++i;
        } else if (!strcmp(a, "--max-cells")) {
            if (parse_u64(v, &o->max_cells) || o->max_cells > 0xffffffffull) return bad_usage("--max-cells needs a non-negative integer", v);
            ++i;
        } else if (!strcmp(a, "--dense")) {
            o->dense = 1;
        } else if (!strcmp(a, "--leaves-per-tree")) {
            if (parse_u64(v, &o->leaves) || o->leaves < 1 || o->leaves > 10000)
                return bad_usage("--leaves-per-tree needs an integer in [1, 10000]", v);
            o->v_leaves = v;
            ++i;
        } else if (!strcmp(a, "--cell-size")) {
            char *end;
            if (!v) return bad_usage("--cell-size needs a number", NULL);
            o->cell_size = strtod(v, &end);
            if (*end || !(o->cell_size >= 0.1 && o->cell_size <= 8)) return bad_usage("--cell-size must be in [0.1, 8]", v);
            ++i;
        } else if (!strcmp(a, "-o")) {
            if (!v) return bad_usage("-o needs a file name", NULL);
            o->out = v;
            ++i;
        } else if (!strcmp(a, "--cells")) {
            if (!v) return bad_usage("--cells needs a file name", NULL);
            o->cells_out = v;
            ++i;
        } else if (a[0] == '-' && a[1]) {
            return bad_usage("unknown option", a);
        } else if (!o->kind_s) {
            o->kind_s = a;
        } else {
            return bad_usage("more than one scene kind", a);
        }
    }
    gen_params *p = &o->p;
    if (!o->kind_s) return bad_usage("missing scene kind", NULL);
    if (gen_kind_parse(o->kind_s, &p->kind)) return bad_usage("unknown scene kind", o->kind_s);
    if (o->dense && p->kind != GEN_FOREST) return bad_usage("--dense is for the forest only", o->kind_s);
    if ((o->leaves || o->cell_size != 0.0) && !o->dense)
        return bad_usage("--leaves-per-tree and --cell-size are for forest --dense only", o->kind_s);
    if ((double)o->leaves * o->size * o->size > 10000.0)
        return bad_usage("--leaves-per-tree times --size squared must be at most 10000", o->v_leaves);
    if (!o->out) return bad_usage("missing -o OUT.obj", NULL);
    p->seed = o->seed;
    p->size = (float)o->size;
    p->max_cells = (uint32_t)o->max_cells;
    p->dense = o->dense;
    p->leaves_per_tree = (uint32_t)o->leaves;
    p->cell_size = (float)o->cell_size;
    return -1;
}

int main(int argc, char **argv) {
    pvsgen_options o;
    int rc = parse_options(argc, argv, &o);
    if (rc >= 0) return rc;
    mesh m;
    mesh_cells cells;
    gen_info info;
    mesh_init(&m);
    mesh_cells_init(&cells);
    if (gen_scene_ex(&o.p, &m, &cells, &info)) {
        fprintf(stderr, "pvsgen: %s: out of memory generating the scene\n", o.out);
        return 1;
    }
    rc = 0;
    if (write_atomic(o.out, write_obj, &m)) rc = 1;
    if (!rc && o.cells_out) {
        cells_ctx cc;
        cc.cells = &cells;
        cc.info = &info;
        cc.kind = o.kind_s;
        cc.dense = o.dense;
        cc.seed = o.seed;
        cc.size = o.size;
        if (write_atomic(o.cells_out, write_cells, &cc)) rc = 1;
    }
    if (!rc) {
        fprintf(stderr, "pvsgen: %s%s seed %llu size %g: %u objects, %u triangles, %u vertices, %u cells", o.kind_s, o.dense ? " (dense)" : "",
                o.seed, o.size, m.object_count, m.triangle_count, m.vertex_count, cells.count);
        if (info.touching_count || info.inside_count)
            fprintf(stderr, " (%u touching a wall at %u, %u partly inside buildings at %u)", info.touching_count,
                    info.touching_first, info.inside_count, info.inside_first);
        fprintf(stderr, "\n");
    }
    mesh_free(&m);
    mesh_cells_free(&cells);
    return rc;
}
