/* pvsbake - bake a .pvs file from an OBJ scene and view cells. See --help and DESIGN.md. */
#include "cli.h"
#include <stdlib.h>
#include <string.h>

static const char *usage =
    "usage: pvsbake SCENE.obj -o OUT.pvs [--cells CELLS.txt | --grid SIZE] [options]\n"
    "       pvsbake merge -o OUT.pvs PART.pvs...   combine the parts of a sharded bake\n"
    "  -o OUT.pvs        output file (written to a temporary file, then renamed)\n"
    "  --cells FILE      view cells: one 'minx miny minz maxx maxy maxz' per line ('#' comments)\n"
    "  --grid SIZE       view cells: a 3D grid of SIZE cubes over the scene bounds\n"
    "  --up y|z          up axis of the scene (default y, the OBJ convention)\n"
    "  --method NAME     auto (the default: the conservative methods that apply to the scene, their PVSs\n"
    "                    intersected; the summary says which ran and what each contributed)\n"
    "                    sample (ray sampling: an approximate PVS, NOT conservative)\n"
    "                    shrink (occluder shrinking, Wonka 2000: conservative)\n"
    "                    otree (2.5D occlusion trees: conservative; occluders = vertical walls on the ground)\n"
    "                    extproj (extended projections, Durand et al. 2000: conservative)\n"
    "                    vocc (virtual occluders, Koltun et al. 2000: conservative, 2.5D; the file also\n"
    "                    stores a few occluders per cell from which pvs_vocc_cull rebuilds the PVS)\n"
    "                    A,B,...: auto over these conservative methods only (e.g. otree,extproj)\n"
    "  --preview         fast, coarse, still conservative: auto runs only the cheapest method that\n"
    "                    applies, with coarse settings\n"
    "  --max-distance D  leave out objects farther than D from every point of the cell (a draw distance)\n"
    "  --eps E           sampling / shrinking distance (stored in the file); shrink's default is an\n"
    "                    eighth of the median cell width, printed in the summary\n"
    "  --2d5, --3d       shrink: force the 2.5D (cull map) or 3D (depth cube) path; default: 2.5D\n"
    "                    when the synthesized occluders stand on the ground\n"
    "  --voxel V         shrink: voxel size of the occluder synthesis (default eps / 1.5, capped)\n"
    "  --otree-budget N  otree: nodes per occlusion tree (64..16777216, default 65536); more can\n"
    "                    only hide more, and on maps of many small facades costs far more time\n"
    "  --sweep           extproj: add the occlusion sweep (Durand 2000 §5) for scenes of many small\n"
    "                    occluders (foliage); slower. auto runs it by default (not with --preview)\n"
    "  --sweep-planes N  extproj: the sweep with N planes per direction (1..256, --sweep: 16)\n"
    "  --subcells        extproj: each sweep plane holds the umbrae of the cell's four quarters\n"
    "                    across its direction, and an object is hidden only when hidden from each\n"
    "                    (tighter; about 2.5 times the bake's time). Needs the sweep\n"
    "  --no-sweep        auto: extproj without the sweep (faster; on game maps the PVS may grow by\n"
    "                    40%, on simple scenes by about 1%)\n"
    "  --resolution N    extproj: N x N pixels per plane (16..4096, default 256, --preview 64; the\n"
    "                    sweep's planes spread them over the part of the plane the scene spans);\n"
    "                    foliage of small leaves needs 1024 and 64 sweep planes to fuse. extproj\n"
    "                    keeps about (128 + 8 x planes) x N^2 bytes per thread (0.65 GiB at 1024\n"
    "                    and 64): see --memory\n"
    "  --adaptive N      split a cell whose PVS holds more than N triangles in two, recursively\n"
    "                    (Durand 2000 §6.1); the file holds the leaf cells. Not with --shard,\n"
    "                    --method vocc, --state or --state-every (no state file: no resuming)\n"
    "  --min-cell S      --adaptive: no cell side below S (default: an eighth of the cell's longest)\n"
    "  --vocc-only       vocc: store only the occluders (the PVS records list every object; the\n"
    "                    runtime rebuilds each cell's PVS with pvs_vocc_cull)\n"
    "  --vocc-slices N   vocc: height slices per cell (1..16, default 5)\n"
    "  --vocc-max N      vocc: virtual occluders kept per cell (1..255, default 10)\n"
    "  --points N        sample method: points per cell (default 32)\n"
    "  --rays N          sample method: rays per point (default 2048)\n"
    "  --seed N          sample method: random seed (default 1)\n"
    "  --chain K         file: decode any cell in at most K deltas (1..64, default 8)\n"
    "  --shard K/N       bake only shard K of N (cells K-1, K-1+N, ...) into a part file for merge\n"
    "  -j THREADS        worker threads (default: all CPUs; -j2 works too); the file is identical\n"
    "                    for any count\n"
    "  --memory SIZE     the most the whole bake may allocate (e.g. 512M, 4G; default PVSBAKE_MEMORY, else\n"
    "                    90% of the machine's memory): threads are planned from it (a cell is measured\n"
    "                    alone first), and a bake that cannot fit one thread is refused\n"
    "  --state FILE      resumable bake: each finished cell is appended to FILE (default OUT.pvs.state),\n"
    "                    written out every --state-every N cells (default 32) or every second;\n"
    "                    rerunning the same command continues from it; it is removed when the output\n"
    "                    is written\n"
    "  --no-state        no state file\n"
    "  -q, --quiet       no progress bar and no summary\n"
    "  --help            this text\n"
    "An option for one method (shrink:, extproj:, vocc:, sample method: above) with a --method that\n"
    "does not run that method is a usage error, as are --min-cell without --adaptive and --state or\n"
    "--state-every with --no-state.\n"
    "exit status: 0 success, 1 bad input (message names file and line), 2 usage\n";

static int usage_error(const char *fmt, const char *arg) {
    fprintf(stderr, "pvsbake: ");
    fprintf(stderr, fmt, arg);
    fprintf(stderr, "\n(see pvsbake --help)\n");
    return 2;
}

/* Options that only one method reads: given with a --method that does not run it, they are usage
   errors rather than silently ignored. */
static const struct { const char *option; pvs_method method; } method_options[] = {
    {"--2d5", PVS_METHOD_SHRINK},         {"--3d", PVS_METHOD_SHRINK},          {"--voxel", PVS_METHOD_SHRINK},
    {"--sweep", PVS_METHOD_EXTPROJ},      {"--sweep-planes", PVS_METHOD_EXTPROJ}, {"--resolution", PVS_METHOD_EXTPROJ},
    {"--no-sweep", PVS_METHOD_EXTPROJ},   {"--otree-budget", PVS_METHOD_OTREE}, {"--subcells", PVS_METHOD_EXTPROJ},
    {"--vocc-slices", PVS_METHOD_VOCC},   {"--vocc-max", PVS_METHOD_VOCC},
    {"--points", PVS_METHOD_SAMPLE},      {"--rays", PVS_METHOD_SAMPLE},        {"--seed", PVS_METHOD_SAMPLE},
};
#define METHOD_OPTION_COUNT (sizeof(method_options) / sizeof(method_options[0]))

/* The methods a bake may run (bits 1 << PVS_METHOD_*): method alone, or AUTO over `mask` (0: every
   conservative method but VOCC). */
static uint32_t methods_run(pvs_method method, uint32_t mask) {
    return method != PVS_METHOD_AUTO ? 1u << method
         : mask ? mask
         : (1u << PVS_METHOD_SHRINK) | (1u << PVS_METHOD_OTREE) | (1u << PVS_METHOD_EXTPROJ);
}

/* 2 (after a message) when option k of `given` (bits over method_options) names a method the bake
   cannot run. */
static int check_method_options(uint32_t given, pvs_method method, uint32_t mask, const char *method_arg) {
    uint32_t runs = methods_run(method, mask);
    size_t k;
    for (k = 0; k < METHOD_OPTION_COUNT; ++k) {
        pvs_method m = method_options[k].method;
        if (!(given >> k & 1u) || (runs >> m & 1u)) continue;
        fprintf(stderr, "pvsbake: %s applies only to method %s, which --method %s does not run%s\n(see pvsbake --help)\n",
                method_options[k].option, pvs_method_name(m), method_arg,
                m == PVS_METHOD_VOCC && method == PVS_METHOD_AUTO ? " (auto runs vocc only when a list names it, e.g. otree,vocc)"
                : m == PVS_METHOD_SAMPLE ? " (sample is never part of auto: --method sample)" : "");
        return 2;
    }
    return 0;
}

/* The bake's memory limit: --memory, else PVSBAKE_MEMORY, else 90% of the machine's memory. 2 (after
   a message) when the value is not a size. */
static int memory_limit(const char *arg, size_t *limit, const char **source) {
    const char *env = getenv("PVSBAKE_MEMORY");
    double mem;
    if (arg) {
        *source = "--memory";
        if (cli_parse_size(arg, limit)) return usage_error("--memory takes a size in bytes (e.g. 512M or 2G), not '%s'", arg);
        return 0;
    }
    if (env && *env) {
        *source = "PVSBAKE_MEMORY";
        if (cli_parse_size(env, limit)) return usage_error("PVSBAKE_MEMORY takes a size in bytes (e.g. 512M or 2G), not '%s'", env);
        return 0;
    }
    *source = "90% of this machine's memory";
    mem = 0.9 * memory_bytes();
    *limit = mem >= 1.0 && mem < 1.8e19 ? (size_t)mem : (size_t)-1; /* unknown: no limit */
    return 0;
}

/* pvsbake merge -o OUT PART... */
static int merge_main(int argc, char **argv) {
    const char *out_path = NULL;
    const char **parts = (const char **)calloc((size_t)argc + 1, sizeof(char *));
    int n = 0, i, rc = 1;
    void *bytes = NULL;
    size_t size = 0;
    tool_error te;
    if (!parts) return 1;
    for (i = 2; i < argc; ++i) {
        if (!strcmp(argv[i], "-o")) {
            if (i + 1 >= argc) { free(parts); return usage_error("%s needs a value", "-o"); }
            out_path = argv[++i];
        } else if (!strcmp(argv[i], "--help") || !strcmp(argv[i], "-h")) {
            fputs(usage, stdout);
            free(parts);
            return 0;
        } else if (argv[i][0] == '-' && argv[i][1]) {
            free(parts);
            return usage_error("unknown merge option '%s'", argv[i]);
        } else {
            parts[n++] = argv[i];
        }
    }
    if (!out_path || !n) {
        free(parts);
        return usage_error("%s", "merge needs -o OUT.pvs and at least one part file");
    }
    if (cli_merge_parts(parts, n, &bytes, &size, &te) == 0 && write_file_atomic(out_path, bytes, size, &te) == 0) {
        fprintf(stderr, "%s: merged %d parts, %zu bytes\n", out_path, n, size);
        rc = 0;
    } else {
        fprintf(stderr, "pvsbake: %s\n", te.message);
    }
    free(bytes);
    free(parts);
    return rc;
}

/* "K/N" with 1 <= K <= N (N = 1: the whole bake). */
static int parse_shard(const char *v, uint32_t *k, uint32_t *n) {
    char a[32];
    const char *slash = strchr(v, '/');
    size_t len = slash ? (size_t)(slash - v) : 0;
    if (!slash || len == 0 || len >= sizeof(a)) return -1;
    memcpy(a, v, len);
    a[len] = 0;
    if (cli_parse_u32(a, 1, 1u << 20, k) || cli_parse_u32(slash + 1, 1, 1u << 20, n) || *k > *n) return -1;
    return 0;
}

/* "name" or "a,b,...": a method, or AUTO with a mask of conservative methods. */
static int parse_method(const char *v, pvs_method *method, uint32_t *mask) {
    char name[64];
    const char *p = v;
    uint32_t n = 0;
    *mask = 0;
    if (!strchr(v, ',')) {
        int m;
        for (m = 1; m < PVS_METHOD_COUNT; ++m)
            if (!strcmp(v, pvs_method_name((pvs_method)m))) {
                *method = (pvs_method)m;
                return 0;
            }
        return -1;
    }
    while (*p) {
        const char *end = strchr(p, ',');
        size_t len = end ? (size_t)(end - p) : strlen(p);
        int m, found = 0;
        if (!len || len >= sizeof(name)) return -1;
        memcpy(name, p, len);
        name[len] = 0;
        for (m = 1; m < PVS_METHOD_COUNT; ++m)
            if (!strcmp(name, pvs_method_name((pvs_method)m)) && m != PVS_METHOD_SAMPLE && m != PVS_METHOD_AUTO) {
                *mask |= 1u << m;
                found = 1;
            }
        if (!found) return -1;
        ++n;
        p += len + (end ? 1 : 0);
        if (end && !*p) return -1;
    }
    *method = PVS_METHOD_AUTO;
    return n ? 0 : -1;
}

static int cmp_str(const void *a, const void *b) { return strcmp(*(const char *const *)a, *(const char *const *)b); }

/* The options that take a value (the next argument, whatever it looks like). */
static const char *const value_options[] = {"-o", "--cells", "--grid", "--up", "--method", "--eps", "-j", "--points", "--rays",
                                            "--seed", "--chain", "--shard", "--voxel", "--max-distance", "--state",
                                            "--state-every", "--vocc-slices", "--vocc-max", "--adaptive", "--min-cell",
                                            "--sweep-planes", "--resolution", "--otree-budget", "--memory", NULL};

/* What identifies a bake for its state file: the scene's arrays, the cells, and every option that
   may change the result, as sorted "option=value" strings (value_options take the next argument,
   the others none). Left out: -j, -q, -o, --state, --state-every, --no-state, --memory, and --cells
   and the scene path, whose contents count instead. */
static uint64_t bake_fingerprint(int argc, char **argv, const mesh *m, const mesh_cells *cells, uint32_t up) {
    char **pairs = (char **)calloc((size_t)argc + 1, sizeof(char *));
    uint64_t h = CLI_FNV_START;
    uint32_t o;
    int i, n = 0, j;
    h = cli_fingerprint(h, m->positions, (size_t)m->vertex_count * 3 * sizeof(float));
    h = cli_fingerprint(h, m->indices, (size_t)m->triangle_count * 3 * sizeof(uint32_t));
    for (o = 0; o < m->object_count; ++o) {
        uint32_t r[3];
        r[0] = m->objects[o].first_triangle; r[1] = m->objects[o].triangle_count; r[2] = m->objects[o].flags;
        h = cli_fingerprint(h, r, sizeof(r));
    }
    h = cli_fingerprint(h, cells->boxes, (size_t)cells->count * 6 * sizeof(float));
    h = cli_fingerprint(h, &up, sizeof(up));
    if (!pairs) return h;
    for (i = 1; i < argc; ++i) {
        const char *a = argv[i], *v = i + 1 < argc && cli_is_option(a, value_options) ? argv[i + 1] : NULL;
        size_t len;
        if (a[0] != '-') continue; /* the scene path */
        if (v) ++i;
        if (!strcmp(a, "-j") || !strcmp(a, "-o") || !strcmp(a, "--state") || !strcmp(a, "--state-every") || !strcmp(a, "--cells") ||
            !strcmp(a, "-q") || !strcmp(a, "--quiet") || !strcmp(a, "--no-state") || !strcmp(a, "--memory"))
            continue;
        len = strlen(a) + (v ? strlen(v) : 0) + 2;
        if (!(pairs[n] = (char *)malloc(len))) break;
        snprintf(pairs[n++], len, "%s=%s", a, v ? v : "");
    }
    qsort(pairs, (size_t)n, sizeof(char *), cmp_str);
    for (j = 0; j < n; ++j) {
        h = cli_fingerprint(h, pairs[j], strlen(pairs[j]) + 1);
        free(pairs[j]);
    }
    free(pairs);
    return h;
}

typedef struct slow_cell { uint32_t task; double seconds; } slow_cell;
static int cmp_slow(const void *a, const void *b) {
    const slow_cell *x = (const slow_cell *)a, *y = (const slow_cell *)b;
    if (x->seconds != y->seconds) return x->seconds > y->seconds ? -1 : 1;
    return x->task < y->task ? -1 : x->task > y->task;
}

/* The statistics at the end of a bake: methods, PVS sizes, culled share, time per cell, slowest cells. */
static void print_summary(const char *out_path, const pvs_scene *scene, const pvs_bake *bake, const cli_bake_run *run, uint32_t threads,
                          const double *secs, double wall, double total, size_t size, int sharded) {
    uint32_t t, objects = pvs_scene_object_count(scene), tasks = pvs_bake_task_count(bake), max = 0, max_cell = 0, ran = 0, i;
    uint32_t drawable = 0; /* occluder-only objects are never in a PVS: shares are of the others */
    double sum = 0.0, tsum = 0.0, share;
    slow_cell *slow = (slow_cell *)malloc((size_t)tasks * sizeof(slow_cell) + 1);
    for (t = 0; t < objects; ++t) drawable += !(pvs_scene_object_flags(scene, t) & PVS_OBJECT_OCCLUDER_ONLY);
    for (t = 0; t < tasks; ++t) {
        uint32_t n = pvs_bitset_count(pvs_bake_cell_pvs(bake, pvs_bake_task_cell(bake, t)), objects);
        sum += n;
        if (n > max) { max = n; max_cell = pvs_bake_task_cell(bake, t); }
        if (secs[t] >= 0.0) {
            if (slow) { slow[ran].task = t; slow[ran].seconds = secs[t]; }
            tsum += secs[t];
            ++ran;
        }
    }
    fprintf(stderr, "%s: %u objects, %u triangles, %u cells%s, method %s%s\n", out_path, objects, pvs_scene_triangle_count(scene), tasks,
            sharded ? " (this shard)" : "", pvs_method_name(pvs_bake_method(bake)),
            pvs_bake_method(bake) == PVS_METHOD_SAMPLE ? " (approximate: ray sampling, not conservative)" : " (conservative)");
    if (pvs_bake_method(bake) == PVS_METHOD_AUTO || pvs_bake_method_count(bake) > 1)
        for (i = 0; i < pvs_bake_method_count(bake); ++i) {
            pvs_bake_method_info mi;
            if (pvs_bake_get_method_info(bake, i, &mi) != PVS_OK) continue;
            if (!mi.ran) {
                fprintf(stderr, "  %-8s skipped: %s\n", pvs_method_name(mi.method), mi.reason);
            } else if (mi.cells && mi.kept_only) {
                fprintf(stderr, "  %-8s ran (%s) on the objects the others kept: it alone culled %.1f per cell\n", pvs_method_name(mi.method),
                        mi.reason, (double)mi.sole_culls / mi.cells);
            } else if (mi.cells) {
                fprintf(stderr, "  %-8s ran (%s): its own PVS %.1f objects, it alone culled %.1f per cell\n", pvs_method_name(mi.method),
                        mi.reason, (double)mi.pvs_sum / mi.cells, (double)mi.sole_culls / mi.cells);
            } else {
                fprintf(stderr, "  %-8s ran (%s)\n", pvs_method_name(mi.method), mi.reason);
            }
        }
    share = drawable ? 100.0 * sum / tasks / drawable : 0.0;
    fprintf(stderr, "  mean PVS %.1f objects (%.1f%% of the %u drawable), max %u (cell %u); culled %.1f%% of them per cell\n", sum / tasks,
            share, drawable, max, max_cell, 100.0 - share);
    if (threads > ran) threads = ran; /* never more threads than cells to bake */
    if (ran)
        fprintf(stderr, "  time per cell %.2f ms (mean over the %u cells baked, each on one thread), bake %.2f s wall on %u thread%s, "
                        "%.2f s total\n",
                1000.0 * tsum / ran, ran, wall, threads, threads == 1 ? "" : "s", total);
    if (run->resumed) fprintf(stderr, "  resumed: %u cells came from the state file, %u were baked now\n", run->resumed, ran);
    if (slow && ran > 1) {
        uint32_t show = ran < 5 ? ran : 5;
        qsort(slow, ran, sizeof(slow_cell), cmp_slow);
        fprintf(stderr, "  slowest cells:");
        for (i = 0; i < show; ++i)
            fprintf(stderr, " %u (%.1f ms)", pvs_bake_task_cell(bake, slow[i].task), 1000.0 * slow[i].seconds);
        fprintf(stderr, "\n");
    }
    fprintf(stderr, "  file %zu bytes (%.1f per cell)\n", size, (double)size / tasks);
    {
        pvs_vocc_stats vs;
        pvs_bake_vocc_stats(bake, &vs);
        if (vs.slices)
            fprintf(stderr, "  vocc: %.2f virtual occluders per cell kept of %.1f found (%.1f slices, %.1f seeds per cell; %u dropped)%s\n",
                    (double)vs.selected / tasks, (double)vs.dense / tasks, (double)vs.slices / tasks, (double)vs.seeds / tasks, vs.dropped,
                    pvs_bake_method(bake) != PVS_METHOD_VOCC ? "; only its PVS is used (auto stores no occluders)" : "");
    }
    free(slow);
}

static int bake_main(int argc, char **argv) {
    const char *scene_path = NULL, *out_path = NULL, *cells_path = NULL, *state_path = NULL;
    float grid = 0.0f, eps = 0.0f, voxel = 0.0f, max_distance = 0.0f;
    pvs_shrink_mode shrink_mode = PVS_SHRINK_AUTO;
    uint32_t sweep = 0, adaptive = 0, resolution = 0, otree_budget = 0;
    float min_cell = 0.0f;
    uint32_t up = 1, threads = 0, points = 0, rays = 0, seed = 1, chain = 0, shard_k = 0, shard_n = 0, methods = 0, state_every = 0;
    uint32_t vocc_slices = 0, vocc_max = 0;
    int quiet = 0, i, preview = 0, no_state = 0, vocc_only = 0, no_sweep = 0, subcells = 0;
    pvs_method method = PVS_METHOD_AUTO;
    const char *method_arg = "auto";
    uint32_t given = 0, state_every_given = 0;
    size_t k;
    mesh m;
    mesh_cells cells;
    pvs_scene *scene = NULL;
    pvs_bake *bake = NULL;
    pvs_bake_desc bd;
    pvs_error pe;
    tool_error te;
    cli_bake_run run;
    double *secs = NULL;
    char *state_buf = NULL, task_what[96];
    const char *memory_arg = NULL, *limit_source = NULL;
    size_t size = 0, limit = 0;
    cli_memory mem;
    int threads_given = 0;
    double t0, t_bake;
    int rc = 1;


    for (i = 1; i < argc; ++i) {
        const char *a = argv[i];
        const char *v = i + 1 < argc ? argv[i + 1] : NULL;
        for (k = 0; k < METHOD_OPTION_COUNT; ++k)
            if (!strcmp(a, method_options[k].option)) given |= 1u << k;
        if (!strcmp(a, "--help") || !strcmp(a, "-h")) {
            fputs(usage, stdout);
            return 0;
        } else if (!strcmp(a, "-q") || !strcmp(a, "--quiet")) {
            quiet = 1;
        } else if (!strcmp(a, "--2d5")) {
            shrink_mode = PVS_SHRINK_2D5;
        } else if (!strcmp(a, "--3d")) {
            shrink_mode = PVS_SHRINK_3D;
        } else if (!strcmp(a, "--sweep")) {
            if (!sweep) sweep = PVS_EXTPROJ_SWEEP_PLANES;
        } else if (!strcmp(a, "--no-sweep")) {
            no_sweep = 1;
        } else if (!strcmp(a, "--subcells")) {
            subcells = 1;
        } else if (!strcmp(a, "--vocc-only")) {
            vocc_only = 1;
        } else if (!strcmp(a, "--preview")) {
            preview = 1;
        } else if (!strcmp(a, "--no-state")) {
            no_state = 1;
        } else if (cli_is_option(a, value_options)) {
            if (!v) return usage_error("%s needs a value", a);
            ++i;
            if (!strcmp(a, "-o")) out_path = v;
            else if (!strcmp(a, "--cells")) cells_path = v;
            else if (!strcmp(a, "--state")) state_path = v;
            else if (!strcmp(a, "--grid")) {
                if (parse_float(v, &grid) || !(grid > 0.0f)) return usage_error("--grid needs a positive size, not '%s'", v);
            } else if (!strcmp(a, "--up")) {
                if (cli_parse_up(v, &up)) return usage_error("--up takes y or z, not '%s'", v);
            } else if (!strcmp(a, "--method")) {
                if (parse_method(v, &method, &methods))
                    return usage_error("unknown method '%s' (available: auto, sample, shrink, otree, extproj, vocc, or a list such as otree,extproj)", v);
                method_arg = v;
            } else if (!strcmp(a, "--adaptive")) {
                if (cli_parse_u32(v, 1, 0xffffffffu, &adaptive)) return usage_error("--adaptive takes a triangle budget >= 1, not '%s'", v);
            } else if (!strcmp(a, "--min-cell")) {
                if (parse_float(v, &min_cell) || !(min_cell > 0.0f)) return usage_error("--min-cell needs a positive size, not '%s'", v);
            } else if (!strcmp(a, "--vocc-slices")) {
                if (cli_parse_u32(v, 1, 16, &vocc_slices)) return usage_error("--vocc-slices takes 1..16, not '%s'", v);
            } else if (!strcmp(a, "--sweep-planes")) {
                if (cli_parse_u32(v, 1, 256, &sweep)) return usage_error("--sweep-planes takes 1..256, not '%s'", v);
            } else if (!strcmp(a, "--otree-budget")) {
                if (cli_parse_u32(v, 64, 1u << 24, &otree_budget)) return usage_error("--otree-budget takes 64..16777216, not '%s'", v);
            } else if (!strcmp(a, "--resolution")) {
                if (cli_parse_u32(v, 16, 4096, &resolution)) return usage_error("--resolution takes 16..4096, not '%s'", v);
            } else if (!strcmp(a, "--vocc-max")) {
                if (cli_parse_u32(v, 1, 255, &vocc_max)) return usage_error("--vocc-max takes 1..255, not '%s'", v);
            } else if (!strcmp(a, "--voxel")) {
                if (parse_float(v, &voxel) || !(voxel > 0.0f)) return usage_error("--voxel needs a positive size, not '%s'", v);
            } else if (!strcmp(a, "--eps")) {
                if (parse_float(v, &eps) || !(eps > 0.0f)) return usage_error("--eps needs a positive number, not '%s'", v);
            } else if (!strcmp(a, "--max-distance")) {
                if (parse_float(v, &max_distance) || !(max_distance > 0.0f)) return usage_error("--max-distance needs a positive number, not '%s'", v);
            } else if (!strcmp(a, "-j")) {
                if (parse_threads(v, &threads)) return usage_error("-j takes a thread count 0..1024, not '%s'", v);
                threads_given = threads != 0;
            } else if (!strcmp(a, "--memory")) {
                memory_arg = v;
            } else if (!strcmp(a, "--points")) {
                if (cli_parse_u32(v, 1, 1u << 20, &points)) return usage_error("--points takes 1..1048576, not '%s'", v);
            } else if (!strcmp(a, "--rays")) {
                if (cli_parse_u32(v, 1, 1u << 24, &rays)) return usage_error("--rays takes 1..16777216, not '%s'", v);
            } else if (!strcmp(a, "--chain")) {
                if (cli_parse_u32(v, 1, PVS_MAX_CHAIN, &chain)) return usage_error("--chain takes 1..64, not '%s'", v);
            } else if (!strcmp(a, "--shard")) {
                if (parse_shard(v, &shard_k, &shard_n)) return usage_error("--shard takes K/N with 1 <= K <= N, not '%s'", v);
            } else if (!strcmp(a, "--seed")) {
                if (cli_parse_u32(v, 0, 0xffffffffu, &seed)) return usage_error("--seed takes an unsigned integer, not '%s'", v);
            } else if (!strcmp(a, "--state-every")) {
                if (cli_parse_u32(v, 1, 1u << 30, &state_every)) return usage_error("--state-every takes a cell count >= 1, not '%s'", v);
                state_every_given = 1;
            }
        } else if (a[0] == '-' && a[1]) {
            return usage_error("unknown option '%s'", a);
        } else if (!scene_path) {
            scene_path = a;
        } else {
            return usage_error("unexpected argument '%s'", a);
        }
    }
    if (!scene_path) return usage_error("%s", "no scene given");
    if (!out_path) return usage_error("%s", "no output given (-o OUT.pvs)");
    if (!cells_path == !(grid > 0.0f)) return usage_error("%s", "give exactly one of --cells FILE or --grid SIZE");
    if (vocc_only && method != PVS_METHOD_VOCC) return usage_error("%s", "--vocc-only needs --method vocc");
    if (check_method_options(given, method, methods, method_arg)) return 2;
    if (min_cell > 0.0f && !adaptive) return usage_error("%s", "--min-cell needs --adaptive");
    if (no_sweep && sweep) return usage_error("%s", "--no-sweep contradicts --sweep and --sweep-planes");
    if (subcells && !sweep && (method != PVS_METHOD_AUTO || preview || no_sweep))
        return usage_error("%s", "--subcells needs the sweep (--sweep or --sweep-planes; auto runs it unless --preview or --no-sweep)");
    if (adaptive && (shard_n > 1 || method == PVS_METHOD_VOCC || state_path || state_every_given))
        return usage_error("%s", "--adaptive does not go with --shard, --method vocc, --state or --state-every");
    if (no_state && (state_path || state_every_given)) return usage_error("%s", "--state and --state-every contradict --no-state");

    if (memory_limit(memory_arg, &limit, &limit_source)) return 2;
    cli_memory_init(&mem, limit, limit_source);
    mesh_init(&m);
    mesh_cells_init(&cells);
    memset(&run, 0, sizeof(run));
    t0 = cli_seconds();
    if (cli_load_scene_limited(scene_path, up, &m, &mem, &scene, &te)) goto fail;
    if (cells_path ? cells_load(cells_path, &cells, &te) : cli_grid_cells(scene, grid, 10000000u, &cells, &te)) goto fail;

    memset(&bd, 0, sizeof(bd));
    bd.scene = scene;
    bd.cells = (const pvs_box *)cells.boxes;
    bd.cell_count = cells.count;
    bd.method = method;
    bd.methods = methods;
    bd.eps = eps;
    bd.max_distance = max_distance;
    bd.flags = preview ? PVS_BAKE_PREVIEW : 0u;
    bd.sample_points = points;
    bd.sample_rays = rays;
    bd.seed = seed;
    bd.max_chain = chain;
    bd.shrink_mode = shrink_mode;
    bd.voxel_size = voxel;
    bd.vocc_slices = vocc_slices;
    bd.vocc_max_occluders = vocc_max;
    bd.vocc_only = (uint32_t)vocc_only;
    bd.extproj_sweep = no_sweep ? PVS_EXTPROJ_NO_SWEEP : sweep; /* 0: auto's default, the sweep */
    bd.extproj_resolution = resolution;
    bd.otree_node_budget = otree_budget;
    bd.extproj_sweep_subcells = subcells ? 4u : 0u;
    bd.adaptive_budget = adaptive;
    bd.adaptive_min_size = min_cell;
    bd.allocator = cli_memory_allocator(&mem);
    if (adaptive) no_state = 1; /* a cell's PVS alone does not restore its leaves */
    if (shard_n > 1) {
        if (shard_n > cells.count) {
            tool_error_set(&te, cells_path ? cells_path : "--grid", 0, "--shard %u/%u: only %u cells", shard_k, shard_n, cells.count);
            goto fail;
        }
        bd.shard_index = shard_k - 1;
        bd.shard_count = shard_n;
    }
    if (pvs_bake_begin(&bd, &bake, &pe) != PVS_OK) {
        /* a bad cell is the cells file's (at its line); a method that cannot handle the input, the
           scene's; anything else is the options' (the message says which) */
        const char *where = pe.result == PVS_ERROR_BAD_CELL ? (cells_path ? cells_path : "--grid")
                          : pe.result == PVS_ERROR_UNSUPPORTED ? scene_path : NULL;
        int line = pe.result == PVS_ERROR_BAD_CELL && pe.index >= 0 && pe.index < (int64_t)cells.count ? (int)mesh_cells_line(&cells, (uint32_t)pe.index) : 0;
        tool_error_set(&te, where, line, "%s", pe.message);
        goto fail;
    }
    if (!quiet && pvs_bake_occluders(bake)) {
        pvs_occluders_info oi;
        pvs_occluders_get_info(pvs_bake_occluders(bake), &oi);
        fprintf(stderr, "shrink: eps %g%s, %s path; voxels %u x %u x %u of %g: %llu solid, %llu after erosion, %u boxes, %u columns\n",
                (double)pvs_bake_eps(bake), eps > 0.0f ? "" : " (default: an eighth of the median cell width)",
                pvs_bake_shrink_mode(bake) == PVS_SHRINK_2D5 ? "2.5D" : "3D", oi.dims[0], oi.dims[1], oi.dims[2],
                (double)oi.voxel_size, (unsigned long long)oi.solid, (unsigned long long)oi.eroded, oi.box_count, oi.rect_count);
        fprintf(stderr, "  %u closed of %u meshes (edge-connected triangle sets), %llu open edges, %llu undecided columns\n",
                oi.closed_components, oi.components, (unsigned long long)oi.open_edges, (unsigned long long)oi.undecided_columns);
        if (oi.leak_cell != PVS_NO_CELL)
            fprintf(stderr, "  %u cell%s reach%s the outside (open to the sky, or a leak), the first cell %u near %g %g %g\n", oi.leak_cells,
                    oi.leak_cells == 1 ? "" : "s", oi.leak_cells == 1 ? "es" : "", oi.leak_cell, (double)oi.leak_point[0],
                    (double)oi.leak_point[1], (double)oi.leak_point[2]);
        if (oi.excluded_cells) {
            uint32_t nex = 0, q;
            const uint32_t *ex = pvs_occluders_excluded_cells(pvs_bake_occluders(bake), &nex);
            fprintf(stderr, "  warning: %u leaking cell%s left out of the solid proof (baked with a second synthesis that every cell\n"
                            "  seeds: little or no occlusion for them; fix the cells or seal the mesh):", nex, nex == 1 ? "" : "s");
            for (q = 0; q < nex && q < 32; ++q) fprintf(stderr, " %u", ex[q]);
            fprintf(stderr, "%s\n", nex > 32 ? " ..." : "");
        }
        fprintf(stderr, "  %u objects give no occluder volume (thin walls with open space on both sides, props)\n", oi.thin_objects);
        if (oi.eroded == 0 && pvs_bake_method(bake) == PVS_METHOD_SHRINK)
            fprintf(stderr, "  warning: no occluder volume survives erosion by eps: every object will be visible from every cell;\n"
                            "  try a smaller --voxel or --eps, or --method extproj for thin walls\n");
    }
    if (!quiet) {
        pvs_otree_bake_info oti;
        pvs_bake_otree_info(bake, &oti);
        if (oti.prepared) {
            fprintf(stderr, "otree: %u facades (2.5D occluders) from %u vertical triangles", oti.facades, oti.vertical_triangles);
            if (oti.levels) fprintf(stderr, ", %u base level%s from %g", oti.levels, oti.levels > 1 ? "s" : "", (double)oti.lowest_level);
            fprintf(stderr, "\n");
            if (!oti.facades && pvs_bake_method(bake) == PVS_METHOD_OTREE)
                fprintf(stderr, "  warning: no vertical wall gives a facade usable from the cells: every object will be visible from every cell;\n"
                                "  try --method extproj or shrink\n");
        }
    }
    secs = (double *)malloc((size_t)pvs_bake_task_count(bake) * sizeof(double) + 8);
    if (!secs) { tool_error_set(&te, NULL, 0, "out of memory"); goto fail; }
    run.task_seconds = secs;
    run.memory = &mem;
    run.threads_given = threads_given;
    run.quiet_plan = quiet;
    for (k = 0; k < pvs_bake_method_count(bake); ++k) { /* extproj's planes: what one thread needs at least */
        pvs_bake_method_info mi;
        if (pvs_bake_get_method_info(bake, (uint32_t)k, &mi) != PVS_OK || !mi.ran || mi.method != PVS_METHOD_EXTPROJ) continue;
        {
            /* the resolution and sweep planes pvs_bake_begin chose (AUTO's default: PVS_EXTPROJ_SWEEP_PLANES) */
            uint32_t res = resolution ? resolution : preview ? PVS_EXTPROJ_PREVIEW_RESOLUTION : PVS_EXTPROJ_RESOLUTION;
            uint32_t sw = sweep ? sweep : method == PVS_METHOD_AUTO && !preview && !no_sweep ? PVS_EXTPROJ_SWEEP_PLANES : 0;
            run.task_bytes = pvs_extproj_task_bytes(res, sw);
            snprintf(task_what, sizeof(task_what), "extproj at %u pixels with %u sweep planes", res, sw);
            run.task_what = task_what;
            run.task_hint = "lower --resolution or --sweep-planes, or raise --memory";
        }
    }
    run.object_count = pvs_scene_object_count(scene);
    run.state_every = state_every;
    if (!no_state) {
        if (!state_path) {
            size_t len = strlen(out_path) + 7;
            state_buf = (char *)malloc(len);
            if (!state_buf) { tool_error_set(&te, NULL, 0, "out of memory"); goto fail; }
            snprintf(state_buf, len, "%s.state", out_path);
            state_path = state_buf;
        }
        run.state_path = state_path;
        run.fingerprint = bake_fingerprint(argc, argv, &m, &cells, up);
    }
    t_bake = cli_seconds();
    i = cli_run_bake_ex(bake, threads, quiet, "bake", &run, &te);
    if (i == -2) {
        fprintf(stderr, "pvsbake: %s\n(see pvsbake --help)\n", te.message);
        rc = 2;
        goto done;
    }
    if (i) goto fail;
    t_bake = cli_seconds() - t_bake;
    if (!quiet && run.state_ignored)
        fprintf(stderr, "warning: %s is not this bake's state (another scene, cells or options, or a damaged header): ignored\n", state_path);
    if (!quiet && run.resumed) fprintf(stderr, "resumed %u of %u cells from %s\n", run.resumed, pvs_bake_task_count(bake), state_path);
    if (!quiet && run.state_torn)
        fprintf(stderr, "note: %s ended in an unfinished or damaged record (an interrupted write): the cells after it were baked again\n",
                state_path);
    if (cli_write_bake(bake, out_path, &size, &te)) goto fail;
    if (run.state_path) remove(run.state_path);
    if (!quiet) print_summary(out_path, scene, bake, &run, run.threads_used ? run.threads_used : 1, secs, t_bake, cli_seconds() - t0, size, shard_n > 1);
    if (!quiet) {
        pvs_bake_report rep;
        pvs_bake_get_report(bake, &rep);
        if (rep.cells_no_occluders)
            fprintf(stderr, "  warning: %u of %u cells had no occluder (shrink volumes or otree facades): their PVS is every object\n",
                    rep.cells_no_occluders, rep.cells);
        else if (rep.cells_all_visible)
            fprintf(stderr, "  %u of %u cells see every object\n", rep.cells_all_visible, rep.cells);
        if (rep.cells_otree_budget)
            fprintf(stderr, "  otree: in %u of %u cells a tree reached its node budget and took no more facades (conservative;\n"
                            "  --otree-budget raises it: it may cull more there, for more time)\n", rep.cells_otree_budget, rep.cells);
    }
    if (!quiet && adaptive)
        fprintf(stderr, "  adaptive: %u leaf cells in the file (budget %u triangles; the PVS figures above are of the whole cells)\n",
                pvs_bake_leaf_count(bake), adaptive);
    if (!quiet && vocc_only)
        fprintf(stderr, "  vocc-only: the PVS above is the placeholder the records store (every object); the runtime rebuilds\n"
                        "  each cell's PVS from its virtual occluders (pvs_vocc_cull; pvscheck checks that one)\n");
    rc = 0;
    goto done;
fail:
    if (mem.refused && !strstr(te.message, "memory limit")) {
        char a[32];
        fprintf(stderr, "pvsbake: %s (the memory limit of %s (%s) was reached)\n", te.message, cli_size_text((double)mem.limit, a), mem.source);
    } else {
        fprintf(stderr, "pvsbake: %s\n", te.message);
    }
done:
    free(secs);
    free(state_buf);
    pvs_bake_destroy(bake);
    pvs_scene_destroy(scene);
    mesh_cells_free(&cells);
    mesh_free(&m);
    cli_memory_destroy(&mem);
    return rc;
}

int main(int argc, char **argv) {
    char **args;
    int rc;
    if (argc > 1 && !strcmp(argv[1], "merge")) return merge_main(argc, argv);
    args = cli_split_jobs(&argc, argv, value_options); /* -j2 as well as -j 2 */
    rc = bake_main(argc, args);
    if (args != argv) free(args);
    return rc;
}
