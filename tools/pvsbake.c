/* pvsbake - bake a .pvs file from an OBJ scene and view cells. See --help and DESIGN.md. */
#include "cli.h"
#include <math.h>
#include <stdlib.h>
#include <string.h>

static const char *usage =
    "usage: pvsbake SCENE.obj -o OUT.pvs [--cells CELLS.txt | --cells walkable[:SIZE] | --grid SIZE] [options]\n"
    "       pvsbake merge [--no-lookup] -o OUT.pvs PART.pvs...   combine the parts of a sharded bake\n"
    "                    (one whole file: encoded again, e.g. without its look-up)\n"
    "  -o OUT.pvs        output file (written to a temporary file, then renamed)\n"
    "  --cells FILE      view cells: one 'minx miny minz maxx maxy maxz' per line ('#' comments)\n"
    "  --cells walkable[:SIZE]  view cells where the camera can go (pvs_walkable_cells): floors with\n"
    "                    head room, covered by cells of SIZE (default 4) up to eye height, merged over\n"
    "                    open floor; also written to OUT.walkable.cells (OUT without .pvs)\n"
    "  --walk-from X,Y,Z walkable: only the floors a walk (up a step, or dropping) reaches from the\n"
    "                    nearest one at most a step above this point (not roofs or closed courtyards)\n"
    "  --eye-height H    walkable: the camera's height over the floor and the head room (default 1.8)\n"
    "  --step-height H   walkable: the highest step a walk climbs (default 0.5, scaled with --eye-height)\n"
    "  --volumes FILE    walkable: only in these view volumes (boxes, as a cells file)\n"
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
    "                    portal (cells and portals, Teller and Sequin 1991: conservative; rooms between\n"
    "                    the scene's closed convex meshes, e.g. a level's brush hulls)\n"
    "                    A,B,...: auto over these conservative methods only (e.g. otree,extproj)\n"
    "  --preview         fast, coarse, still conservative: auto runs only the cheapest method that\n"
    "                    applies, with coarse settings\n"
    "  --max-distance D  leave out objects farther than D from every point of the cell (a draw distance)\n"
    "  --eps E           sampling / shrinking distance (stored in the file); shrink's default is an\n"
    "                    eighth of the median cell width, printed in the summary\n"
    "  --2d5, --3d       shrink: force the 2.5D (cull map) or 3D (depth cube) path; default: 2.5D\n"
    "                    when the synthesized occluders stand on the ground\n"
    "  --voxel V         shrink: voxel size of the occluder synthesis (default eps / 1.5, capped)\n"
    "  --portal-budget N portal: clips of the portal flow per cell (1000..4294967295, default 2000000);\n"
    "                    past it the flow takes every room it reaches. More can only cull more, for\n"
    "                    more time (maps of many small rooms)\n"
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
    "  --chain K         file: decode any cell in at most K deltas (1..64, default 16)\n"
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
    "  --no-names        leave the objects' names out of the file (stored, they let pvscheck and pvsview\n"
    "                    tell a renamed or reordered object)\n"
    "  --no-lookup       leave the cell boxes and look-up tree out (an engine that finds its cells\n"
    "                    itself, e.g. from its BSP leaves: a quarter to a third smaller on game maps);\n"
    "                    pvs_file_find_cell then finds none, and pvscheck and pvsview need the full file\n"
    "  -q, --quiet       no progress bar and no summary\n"
    "  --help            this text\n"
    "An option for one method (shrink:, extproj:, vocc:, sample method: above) with a --method that\n"
    "does not run that method is a usage error, as are --min-cell without --adaptive and --state or\n"
    "--state-every with --no-state.\n"
    "exit status: 0 success, 1 bad input (message names file and line), 2 usage\n";

#define TOOL "pvsbake"

/* Options that only one method reads: given with a --method that does not run it, they are usage
   errors rather than silently ignored. */
static const struct { const char *option; pvs_method method; } method_options[] = {
    {"--2d5", PVS_METHOD_SHRINK},         {"--3d", PVS_METHOD_SHRINK},          {"--voxel", PVS_METHOD_SHRINK},
    {"--sweep", PVS_METHOD_EXTPROJ},      {"--sweep-planes", PVS_METHOD_EXTPROJ}, {"--resolution", PVS_METHOD_EXTPROJ},
    {"--no-sweep", PVS_METHOD_EXTPROJ},   {"--otree-budget", PVS_METHOD_OTREE}, {"--subcells", PVS_METHOD_EXTPROJ},
    {"--portal-budget", PVS_METHOD_PORTAL},
    {"--vocc-slices", PVS_METHOD_VOCC},   {"--vocc-max", PVS_METHOD_VOCC},
    {"--points", PVS_METHOD_SAMPLE},      {"--rays", PVS_METHOD_SAMPLE},        {"--seed", PVS_METHOD_SAMPLE},
};
#define METHOD_OPTION_COUNT (sizeof(method_options) / sizeof(method_options[0]))

/* The methods a bake may run (bits 1 << PVS_METHOD_*): method alone, or AUTO over `mask` (0: every
   conservative method but VOCC). */
static uint32_t methods_run(pvs_method method, uint32_t mask) {
    return method != PVS_METHOD_AUTO ? 1u << method
         : mask ? mask
         : (1u << PVS_METHOD_SHRINK) | (1u << PVS_METHOD_OTREE) | (1u << PVS_METHOD_EXTPROJ) | (1u << PVS_METHOD_PORTAL);
}

/* 2 (after a message) when option k of `given` (bits over method_options) names a method the bake
   cannot run. */
static int check_method_options(uint32_t given, pvs_method method, uint32_t mask, const char *method_arg) {
    uint32_t runs = methods_run(method, mask);
    size_t k;
    for (k = 0; k < METHOD_OPTION_COUNT; ++k) {
        pvs_method m = method_options[k].method;
        if (!(given >> k & 1u) || (runs >> m & 1u)) continue;
        return tool_usage_error(TOOL, "%s applies only to method %s, which --method %s does not run%s", method_options[k].option,
                                pvs_method_name(m), method_arg,
                                m == PVS_METHOD_VOCC && method == PVS_METHOD_AUTO ? " (auto runs vocc only when a list names it, e.g. otree,vocc)"
                                : m == PVS_METHOD_SAMPLE ? " (sample is never part of auto: --method sample)" : "");
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
        if (cli_parse_size(arg, limit)) return tool_usage_error(TOOL, "--memory takes a size in bytes (e.g. 512M or 2G), not '%s'", arg);
        return 0;
    }
    if (env && *env) {
        *source = "PVSBAKE_MEMORY";
        if (cli_parse_size(env, limit)) return tool_usage_error(TOOL, "PVSBAKE_MEMORY takes a size in bytes (e.g. 512M or 2G), not '%s'", env);
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
    int n = 0, i, rc = 1, no_lookup = 0;
    void *bytes = NULL;
    size_t size = 0;
    tool_error te;
    if (!parts) return 1;
    for (i = 2; i < argc; ++i) {
        if (!strcmp(argv[i], "-o")) {
            if (i + 1 >= argc) { free(parts); return tool_usage_error(TOOL, "%s needs a value", "-o"); }
            out_path = argv[++i];
        } else if (!strcmp(argv[i], "--no-lookup")) {
            no_lookup = 1;
        } else if (!strcmp(argv[i], "--help") || !strcmp(argv[i], "-h")) {
            fputs(usage, stdout);
            free(parts);
            return 0;
        } else if (argv[i][0] == '-' && argv[i][1]) {
            free(parts);
            return tool_usage_error(TOOL, "unknown merge option '%s'", argv[i]);
        } else {
            parts[n++] = argv[i];
        }
    }
    if (!out_path || !n) {
        free(parts);
        return tool_usage_error(TOOL, "merge needs -o OUT.pvs and at least one part file");
    }
    if (cli_merge_parts(parts, n, no_lookup, &bytes, &size, &te) == 0 && write_file_atomic(out_path, bytes, size, &te) == 0) {
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
static const char *const value_options[] = {"-o", "--cells", "--walk-from", "--eye-height", "--step-height", "--volumes", "--grid",
                                            "--up", "--method", "--eps", "-j", "--points", "--rays",
                                            "--seed", "--chain", "--shard", "--voxel", "--max-distance", "--state",
                                            "--state-every", "--vocc-slices", "--vocc-max", "--adaptive", "--min-cell",
                                            "--sweep-planes", "--resolution", "--otree-budget", "--portal-budget", "--memory", NULL};

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
                fprintf(stderr, "  %-8s skipped: %s", pvs_method_name(mi.method), mi.reason);
                if (mi.sample_cells) fprintf(stderr, " (%.1f objects per cell on %u sample cells)", (double)mi.sample_gain, mi.sample_cells);
                fprintf(stderr, "\n");
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
        pvs_bake_get_vocc_stats(bake, &vs);
        if (vs.slices)
            fprintf(stderr, "  vocc: %.2f virtual occluders per cell kept of %.1f found (%.1f slices, %.1f seeds per cell; %u dropped)%s\n",
                    (double)vs.selected / tasks, (double)vs.dense / tasks, (double)vs.slices / tasks, (double)vs.seeds / tasks, vs.dropped,
                    pvs_bake_method(bake) != PVS_METHOD_VOCC ? "; only its PVS is used (auto stores no occluders)" : "");
    }
    free(slow);
}

/* What the command line asks for. */
typedef struct bake_options {
    const char *scene_path, *out_path, *cells_path, *state_path, *memory_arg, *method_arg, *volumes_path;
    float grid, eps, voxel, max_distance, min_cell, walk_size, walk_from[3], eye_height, step_height;
    int walkable, walk_from_given;
    pvs_shrink_mode shrink_mode;
    pvs_method method;
    uint32_t methods, up, threads, points, rays, seed, chain, shard_k, shard_n, state_every;
    uint32_t sweep, adaptive, resolution, otree_budget, portal_budget, vocc_slices, vocc_max;
    uint32_t given; /* bits over method_options: the options given */
    int quiet, preview, no_state, no_names, no_lookup, vocc_only, no_sweep, subcells, state_every_given, threads_given;
} bake_options;

/* One option of value_options with its value v. 0, or 2 after a usage error. */
static int parse_value(bake_options *o, const char *a, const char *v) {
    if (!strcmp(a, "-o")) o->out_path = v;
    else if (!strcmp(a, "--cells") && !strncmp(v, "walkable", 8) && (!v[8] || v[8] == ':')) {
        o->walkable = 1;
        o->cells_path = v;
        if (v[8] && (parse_float(v + 9, &o->walk_size) || !(o->walk_size > 0.0f)))
            return tool_usage_error(TOOL, "--cells walkable:SIZE needs a positive size, not '%s'", v + 9);
    } else if (!strcmp(a, "--cells")) o->cells_path = v;
    else if (!strcmp(a, "--volumes")) o->volumes_path = v;
    else if (!strcmp(a, "--walk-from")) {
        char extra;
        if (sscanf(v, "%f,%f,%f%c", o->walk_from, o->walk_from + 1, o->walk_from + 2, &extra) != 3 ||
            !isfinite(o->walk_from[0]) || !isfinite(o->walk_from[1]) || !isfinite(o->walk_from[2]))
            return tool_usage_error(TOOL, "--walk-from takes X,Y,Z, not '%s'", v);
        o->walk_from_given = 1;
    } else if (!strcmp(a, "--eye-height") || !strcmp(a, "--step-height")) {
        float *h = a[2] == 'e' ? &o->eye_height : &o->step_height;
        if (parse_float(v, h) || !(*h > 0.0f)) return tool_usage_error(TOOL, "%s needs a positive height, not '%s'", a, v);
    }
    else if (!strcmp(a, "--state")) o->state_path = v;
    else if (!strcmp(a, "--memory")) o->memory_arg = v;
    else if (!strcmp(a, "--grid")) {
        if (parse_float(v, &o->grid) || !(o->grid > 0.0f)) return tool_usage_error(TOOL, "--grid needs a positive size, not '%s'", v);
    } else if (!strcmp(a, "--up")) {
        if (cli_parse_up(v, &o->up)) return tool_usage_error(TOOL, "--up takes y or z, not '%s'", v);
    } else if (!strcmp(a, "--method")) {
        if (parse_method(v, &o->method, &o->methods))
            return tool_usage_error(TOOL, "unknown method '%s' (available: auto, sample, shrink, otree, extproj, vocc, or a list such as "
                                          "otree,extproj)", v);
        o->method_arg = v;
    } else if (!strcmp(a, "--adaptive")) {
        if (cli_parse_u32(v, 1, 0xffffffffu, &o->adaptive)) return tool_usage_error(TOOL, "--adaptive takes a triangle budget >= 1, not '%s'", v);
    } else if (!strcmp(a, "--min-cell")) {
        if (parse_float(v, &o->min_cell) || !(o->min_cell > 0.0f)) return tool_usage_error(TOOL, "--min-cell needs a positive size, not '%s'", v);
    } else if (!strcmp(a, "--vocc-slices")) {
        if (cli_parse_u32(v, 1, 16, &o->vocc_slices)) return tool_usage_error(TOOL, "--vocc-slices takes 1..16, not '%s'", v);
    } else if (!strcmp(a, "--sweep-planes")) {
        if (cli_parse_u32(v, 1, 256, &o->sweep)) return tool_usage_error(TOOL, "--sweep-planes takes 1..256, not '%s'", v);
    } else if (!strcmp(a, "--portal-budget")) {
        if (cli_parse_u32(v, 1000, 0xffffffffu, &o->portal_budget))
            return tool_usage_error(TOOL, "--portal-budget takes 1000..4294967295, not '%s'", v);
    } else if (!strcmp(a, "--otree-budget")) {
        if (cli_parse_u32(v, 64, 1u << 24, &o->otree_budget)) return tool_usage_error(TOOL, "--otree-budget takes 64..16777216, not '%s'", v);
    } else if (!strcmp(a, "--resolution")) {
        if (cli_parse_u32(v, 16, 4096, &o->resolution)) return tool_usage_error(TOOL, "--resolution takes 16..4096, not '%s'", v);
    } else if (!strcmp(a, "--vocc-max")) {
        if (cli_parse_u32(v, 1, 255, &o->vocc_max)) return tool_usage_error(TOOL, "--vocc-max takes 1..255, not '%s'", v);
    } else if (!strcmp(a, "--voxel")) {
        if (parse_float(v, &o->voxel) || !(o->voxel > 0.0f)) return tool_usage_error(TOOL, "--voxel needs a positive size, not '%s'", v);
    } else if (!strcmp(a, "--eps")) {
        if (parse_float(v, &o->eps) || !(o->eps > 0.0f)) return tool_usage_error(TOOL, "--eps needs a positive number, not '%s'", v);
    } else if (!strcmp(a, "--max-distance")) {
        if (parse_float(v, &o->max_distance) || !(o->max_distance > 0.0f))
            return tool_usage_error(TOOL, "--max-distance needs a positive number, not '%s'", v);
    } else if (!strcmp(a, "-j")) {
        if (parse_threads(v, &o->threads)) return tool_usage_error(TOOL, "-j takes a thread count 0..1024, not '%s'", v);
        o->threads_given = o->threads != 0;
    } else if (!strcmp(a, "--points")) {
        if (cli_parse_u32(v, 1, 1u << 20, &o->points)) return tool_usage_error(TOOL, "--points takes 1..1048576, not '%s'", v);
    } else if (!strcmp(a, "--rays")) {
        if (cli_parse_u32(v, 1, 1u << 24, &o->rays)) return tool_usage_error(TOOL, "--rays takes 1..16777216, not '%s'", v);
    } else if (!strcmp(a, "--chain")) {
        if (cli_parse_u32(v, 1, PVS_MAX_CHAIN, &o->chain)) return tool_usage_error(TOOL, "--chain takes 1..64, not '%s'", v);
    } else if (!strcmp(a, "--shard")) {
        if (parse_shard(v, &o->shard_k, &o->shard_n)) return tool_usage_error(TOOL, "--shard takes K/N with 1 <= K <= N, not '%s'", v);
    } else if (!strcmp(a, "--seed")) {
        if (cli_parse_u32(v, 0, 0xffffffffu, &o->seed)) return tool_usage_error(TOOL, "--seed takes an unsigned integer, not '%s'", v);
    } else if (!strcmp(a, "--state-every")) {
        if (cli_parse_u32(v, 1, 1u << 30, &o->state_every)) return tool_usage_error(TOOL, "--state-every takes a cell count >= 1, not '%s'", v);
        o->state_every_given = 1;
    }
    return 0;
}

/* The options that go together or not. 0, or 2 after a usage error. */
static int check_options(const bake_options *o) {
    if (!o->scene_path) return tool_usage_error(TOOL, "no scene given");
    if (!o->out_path) return tool_usage_error(TOOL, "no output given (-o OUT.pvs)");
    if (!o->cells_path == !(o->grid > 0.0f)) return tool_usage_error(TOOL, "give exactly one of --cells FILE or --grid SIZE");
    if (o->vocc_only && o->method != PVS_METHOD_VOCC) return tool_usage_error(TOOL, "--vocc-only needs --method vocc");
    if (o->no_lookup && (o->method == PVS_METHOD_VOCC || o->shard_n > 1 || o->adaptive))
        return tool_usage_error(TOOL, "--no-lookup: not with --method vocc (its occluders need the cell boxes), --adaptive (the file "
                                "alone knows its cells' boxes) or --shard (use merge --no-lookup)");
    if (!o->walkable && (o->walk_from_given || o->eye_height > 0.0f || o->step_height > 0.0f || o->volumes_path))
        return tool_usage_error(TOOL, "--walk-from, --eye-height, --step-height and --volumes need --cells walkable");
    if (check_method_options(o->given, o->method, o->methods, o->method_arg)) return 2;
    if (o->min_cell > 0.0f && !o->adaptive) return tool_usage_error(TOOL, "--min-cell needs --adaptive");
    if (o->no_sweep && o->sweep) return tool_usage_error(TOOL, "--no-sweep contradicts --sweep and --sweep-planes");
    if (o->subcells && !o->sweep && (o->method != PVS_METHOD_AUTO || o->preview || o->no_sweep))
        return tool_usage_error(TOOL, "--subcells needs the sweep (--sweep or --sweep-planes; auto runs it unless --preview or --no-sweep)");
    if (o->adaptive && (o->shard_n > 1 || o->method == PVS_METHOD_VOCC || o->state_path || o->state_every_given))
        return tool_usage_error(TOOL, "--adaptive does not go with --shard, --method vocc, --state or --state-every");
    if (o->no_state && (o->state_path || o->state_every_given)) return tool_usage_error(TOOL, "--state and --state-every contradict --no-state");
    return 0;
}

/* -1 to go on; otherwise the exit status (0 after --help, 2 after a usage error). */
static int parse_options(int argc, char **argv, bake_options *o) {
    int i, rc;
    size_t k;
    memset(o, 0, sizeof(*o));
    o->shrink_mode = PVS_SHRINK_AUTO;
    o->method = PVS_METHOD_AUTO;
    o->method_arg = "auto";
    o->up = 1;
    o->seed = 1;
    for (i = 1; i < argc; ++i) {
        const char *a = argv[i];
        const char *v = i + 1 < argc ? argv[i + 1] : NULL;
        for (k = 0; k < METHOD_OPTION_COUNT; ++k)
            if (!strcmp(a, method_options[k].option)) o->given |= 1u << k;
        if (!strcmp(a, "--help") || !strcmp(a, "-h")) {
            fputs(usage, stdout);
            return 0;
        } else if (!strcmp(a, "-q") || !strcmp(a, "--quiet")) {
            o->quiet = 1;
        } else if (!strcmp(a, "--2d5")) {
            o->shrink_mode = PVS_SHRINK_2D5;
        } else if (!strcmp(a, "--3d")) {
            o->shrink_mode = PVS_SHRINK_3D;
        } else if (!strcmp(a, "--sweep")) {
            if (!o->sweep) o->sweep = PVS_EXTPROJ_SWEEP_PLANES;
        } else if (!strcmp(a, "--no-sweep")) {
            o->no_sweep = 1;
        } else if (!strcmp(a, "--subcells")) {
            o->subcells = 1;
        } else if (!strcmp(a, "--vocc-only")) {
            o->vocc_only = 1;
        } else if (!strcmp(a, "--preview")) {
            o->preview = 1;
        } else if (!strcmp(a, "--no-state")) {
            o->no_state = 1;
        } else if (!strcmp(a, "--no-names")) {
            o->no_names = 1;
        } else if (!strcmp(a, "--no-lookup")) {
            o->no_lookup = 1;
        } else if (cli_is_option(a, value_options)) {
            if (!v) return tool_usage_error(TOOL, "%s needs a value", a);
            ++i;
            if ((rc = parse_value(o, a, v)) != 0) return rc;
        } else if (a[0] == '-' && a[1]) {
            return tool_usage_error(TOOL, "unknown option '%s'", a);
        } else if (!o->scene_path) {
            o->scene_path = a;
        } else {
            return tool_usage_error(TOOL, "unexpected argument '%s'", a);
        }
    }
    return check_options(o) ? 2 : -1;
}

static int write_cells(FILE *f, const void *cells) { return mesh_cells_write((const mesh_cells *)cells, f); }

/* --cells walkable: the cells pvs_walkable_cells finds, also written to OUT.walkable.cells (OUT.pvs without .pvs). */
static int walkable_cells(const bake_options *o, const pvs_scene *scene, mesh_cells *cells, tool_error *te) {
    pvs_walkable_desc wd;
    mesh_cells vols;
    pvs_error pe;
    uint32_t n = 0, i, cap = 1u << 16;
    pvs_box *boxes = (pvs_box *)malloc(cap * sizeof(pvs_box));
    size_t len = strlen(o->out_path);
    char *path = (char *)malloc(len + 16);
    int rc = -1;
    memset(&wd, 0, sizeof(wd));
    mesh_cells_init(&vols);
    wd.cell_size = o->walk_size;
    wd.eye_height = o->eye_height;
    wd.step_height = o->step_height;
    if (o->walk_from_given) wd.seed = o->walk_from;
    if (o->volumes_path) {
        if (cells_load(o->volumes_path, &vols, te)) goto done;
        wd.volumes = (const pvs_box *)vols.boxes;
        wd.volume_count = vols.count;
    }
    if (!path || !boxes) {
        tool_error_set(te, o->scene_path, 0, "--cells walkable: out of memory");
        goto done;
    }
    if (pvs_walkable_cells(scene, &wd, boxes, cap, &n, &pe) != PVS_OK || !n) {
        tool_error_set(te, o->scene_path, 0, "--cells walkable: %s",
                       pe.result != PVS_OK ? pe.message
                                           : "no floor with head room found (check --up, --eye-height and --walk-from)");
        goto done;
    }
    if (n > cap) { /* more cells than the first guess: once more, with room for all */
        free(boxes);
        if (!(boxes = (pvs_box *)malloc(n * sizeof(pvs_box))) || pvs_walkable_cells(scene, &wd, boxes, n, &n, &pe)) {
            tool_error_set(te, o->scene_path, 0, "--cells walkable: out of memory");
            goto done;
        }
    }
    for (i = 0; i < n; ++i)
        if (mesh_cells_add(cells, (const float *)(boxes + i))) {
            tool_error_set(te, o->scene_path, 0, "--cells walkable: out of memory");
            goto done;
        }
    memcpy(path, o->out_path, len + 1);
    if (len > 4 && !strcmp(path + len - 4, ".pvs")) path[len - 4] = '\0';
    strcat(path, ".walkable.cells");
    if (write_stream_atomic(path, write_cells, cells, te)) goto done;
    if (!o->quiet) /* pvs_walkable_desc's defaults are metres: say so where they ran */
        fprintf(stderr, "walkable: %u cells%s, written to %s\n", n,
                o->eye_height > 0.0f ? "" : " (sizes for a scene in metres: in other units give --eye-height)", path);
    rc = 0;
done:
    free(path);
    free(boxes);
    mesh_cells_free(&vols);
    return rc;
}

/* The bake's description from the options (scene, cells and allocator given). */
static void bake_desc_init(pvs_bake_desc *bd, const bake_options *o, const pvs_scene *scene, const mesh_cells *cells, cli_memory *mem) {
    memset(bd, 0, sizeof(*bd));
    bd->scene = scene;
    bd->cells = (const pvs_box *)cells->boxes;
    bd->cell_count = cells->count;
    bd->method = o->method;
    bd->methods = o->methods;
    bd->eps = o->eps;
    bd->max_distance = o->max_distance;
    bd->flags = (o->preview ? PVS_BAKE_PREVIEW : 0u) | (o->no_lookup ? PVS_BAKE_NO_LOOKUP : 0u);
    bd->sample.points = o->points;
    bd->sample.rays = o->rays;
    bd->sample.seed = o->seed;
    bd->max_chain = o->chain;
    bd->shrink.mode = o->shrink_mode;
    bd->shrink.voxel_size = o->voxel;
    bd->vocc.slices = o->vocc_slices;
    bd->vocc.max_occluders = o->vocc_max;
    bd->vocc.only = (uint32_t)o->vocc_only;
    bd->extproj.sweep = o->no_sweep ? PVS_EXTPROJ_NO_SWEEP : o->sweep; /* 0: auto's default, the sweep */
    bd->extproj.resolution = o->resolution;
    bd->otree.node_budget = o->otree_budget;
    bd->portal.budget = o->portal_budget;
    bd->extproj.sweep_subcells = o->subcells ? 4u : 0u;
    bd->adaptive.budget = o->adaptive;
    bd->adaptive.min_size = o->min_cell;
    bd->allocator = cli_memory_allocator(mem);
}

/* What the shrink method's occluder synthesis made of the scene (before the bake). */
static void print_shrink_info(const pvs_bake *bake, float eps) {
    pvs_occluders_info oi;
    pvs_occluders_get_info(pvs_bake_occluders(bake), &oi);
    fprintf(stderr, "shrink: eps %g%s, %s path; voxels %u x %u x %u of %g: %llu solid, %llu after erosion, %u boxes, %u columns\n",
            (double)pvs_bake_eps(bake), eps > 0.0f ? "" : " (default: an eighth of the median cell width)",
            pvs_bake_shrink_mode(bake) == PVS_SHRINK_2D5 ? "2.5D" : "3D", oi.dims[0], oi.dims[1], oi.dims[2], (double)oi.voxel_size,
            (unsigned long long)oi.solid, (unsigned long long)oi.eroded, oi.box_count, oi.rect_count);
    fprintf(stderr, "  %u closed of %u meshes (edge-connected triangle sets), %llu open edges, %llu undecided columns\n", oi.closed_components,
            oi.components, (unsigned long long)oi.open_edges, (unsigned long long)oi.undecided_columns);
    if (oi.leak_cell != PVS_NO_CELL)
        fprintf(stderr, "  %u cell%s reach%s the outside (open to the sky, or a leak), the first cell %u near %g %g %g\n", oi.leak_cells,
                oi.leak_cells == 1 ? "" : "s", oi.leak_cells == 1 ? "es" : "", oi.leak_cell, (double)oi.leak_point[0], (double)oi.leak_point[1],
                (double)oi.leak_point[2]);
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

/* What the portal method built (before the bake), when it runs. */
static void print_portal_info(const pvs_bake *bake) {
    pvs_portal_info pi;
    pvs_bake_get_portal_info(bake, &pi);
    if (!pi.leaves) return;
    fprintf(stderr, "portal: %u closed convex solids, %u planes: %u rooms (empty BSP leaves of %u), %u portals\n",
            pi.solids, pi.planes, pi.rooms, pi.leaves, pi.portals);
    if (pi.deep_leaves) fprintf(stderr, "  %u leaves left open at the depth limit\n", pi.deep_leaves);
}

/* What the otree method found in the scene (before the bake), when it runs. */
static void print_otree_info(const pvs_bake *bake) {
    pvs_otree_bake_info oti;
    pvs_bake_get_otree_info(bake, &oti);
    if (!oti.prepared) return;
    fprintf(stderr, "otree: %u facades (2.5D occluders) from %u vertical triangles", oti.facades, oti.vertical_triangles);
    if (oti.levels) fprintf(stderr, ", %u base level%s from %g", oti.levels, oti.levels > 1 ? "s" : "", (double)oti.lowest_level);
    fprintf(stderr, "\n");
    if (!oti.facades && pvs_bake_method(bake) == PVS_METHOD_OTREE)
        fprintf(stderr, "  warning: no vertical wall gives a facade usable from the cells: every object will be visible from every cell;\n"
                        "  try --method extproj or shrink\n");
}

/* When extproj runs: what one thread needs at least (its planes), for the thread plan. */
static void plan_task_bytes(const pvs_bake *bake, const bake_options *o, cli_bake_run *run, char *task_what, size_t what_size) {
    uint32_t k;
    for (k = 0; k < pvs_bake_method_count(bake); ++k) {
        pvs_bake_method_info mi;
        /* the resolution and sweep planes pvs_bake_begin chose (AUTO's default: PVS_EXTPROJ_SWEEP_PLANES) */
        uint32_t res = o->resolution ? o->resolution : o->preview ? PVS_EXTPROJ_PREVIEW_RESOLUTION : PVS_EXTPROJ_RESOLUTION;
        uint32_t sw = o->sweep ? o->sweep : o->method == PVS_METHOD_AUTO && !o->preview && !o->no_sweep ? PVS_EXTPROJ_SWEEP_PLANES : 0;
        if (pvs_bake_get_method_info(bake, k, &mi) != PVS_OK || !mi.ran || mi.method != PVS_METHOD_EXTPROJ) continue;
        run->task_bytes = pvs_extproj_task_bytes(res, sw);
        snprintf(task_what, what_size, "extproj at %u pixels with %u sweep planes", res, sw);
        run->task_what = task_what;
        run->task_hint = "lower --resolution or --sweep-planes, or raise --memory";
    }
}

/* The notes after the summary: cells without occluders or seeing everything, otree budgets, adaptive
   leaves, vocc-only placeholders. */
static void print_notes(const pvs_bake *bake, const bake_options *o) {
    pvs_bake_report rep;
    pvs_bake_get_report(bake, &rep);
    if (rep.cells_no_occluders)
        fprintf(stderr, "  warning: %u of %u cells had no occluder (shrink volumes or otree facades): their PVS is every object\n",
                rep.cells_no_occluders, rep.cells);
    else if (rep.cells_all_visible)
        fprintf(stderr, "  %u of %u cells see every object\n", rep.cells_all_visible, rep.cells);
    {
        pvs_portal_info pi;
        pvs_bake_get_portal_info(bake, &pi);
        if (pi.cut_cells)
            fprintf(stderr, "  portal: in %u of %u cells the flow reached its budget and took every room it reaches (conservative;\n"
                            "  --portal-budget raises it: it may cull more there, for more time)\n",
                    pi.cut_cells, rep.cells);
    }
    if (rep.cells_otree_budget)
        fprintf(stderr, "  otree: in %u of %u cells a tree reached its node budget and took no more facades (conservative;\n"
                        "  --otree-budget raises it: it may cull more there, for more time)\n", rep.cells_otree_budget, rep.cells);
    if (o->adaptive)
        fprintf(stderr, "  adaptive: %u leaf cells in the file (budget %u triangles; the PVS figures above are of the whole cells)\n",
                pvs_bake_leaf_count(bake), o->adaptive);
    if (o->vocc_only)
        fprintf(stderr, "  vocc-only: the PVS above is the placeholder the records store (every object); the runtime rebuilds\n"
                        "  each cell's PVS from its virtual occluders (pvs_vocc_cull; pvscheck checks that one)\n");
}

/* The state file's messages after the bake ran. */
static void print_state_notes(const pvs_bake *bake, const cli_bake_run *run, const char *state_path) {
    if (run->state_ignored)
        fprintf(stderr, "warning: %s is not this bake's state (another scene, cells or options, or a damaged header): ignored\n", state_path);
    if (run->resumed) fprintf(stderr, "resumed %u of %u cells from %s\n", run->resumed, pvs_bake_task_count(bake), state_path);
    if (run->state_torn)
        fprintf(stderr, "note: %s ended in an unfinished or damaged record (an interrupted write): the cells after it were baked again\n",
                state_path);
}

/* pvs_bake_begin's refusal as a message: a bad cell is the cells file's (at its line); a method that
   cannot handle the input, the scene's; anything else is the options' (the message says which). */
static void begin_error(const bake_options *o, const mesh_cells *cells, const pvs_error *pe, tool_error *te) {
    const char *where = pe->result == PVS_ERROR_BAD_CELL ? (o->cells_path ? o->cells_path : "--grid")
                      : pe->result == PVS_ERROR_UNSUPPORTED ? o->scene_path : NULL;
    int bad_cell = pe->result == PVS_ERROR_BAD_CELL && pe->index >= 0 && pe->index < (int64_t)cells->count;
    int line = bad_cell ? (int)mesh_cells_line(cells, (uint32_t)pe->index) : 0;
    tool_error_set(te, where, line, "%s", pe->message);
}

static int bake_main(int argc, char **argv) {
    bake_options o;
    mesh m;
    mesh_cells cells;
    pvs_scene *scene = NULL;
    pvs_bake *bake = NULL;
    pvs_bake_desc bd;
    pvs_error pe;
    tool_error te;
    cli_bake_run run;
    double *secs = NULL, t0, t_bake;
    char *state_buf = NULL, task_what[96];
    const char **names = NULL;
    const char *limit_source = NULL;
    size_t size = 0, limit = 0;
    cli_memory mem;
    int rc = parse_options(argc, argv, &o), r;

    if (rc >= 0) return rc;
    if (memory_limit(o.memory_arg, &limit, &limit_source)) return 2;
    rc = 1;
    cli_memory_init(&mem, limit, limit_source);
    mesh_init(&m);
    mesh_cells_init(&cells);
    memset(&run, 0, sizeof(run));
    t0 = cli_seconds();
    if (cli_load_scene_limited(o.scene_path, o.up, &m, &mem, &scene, &te)) goto fail;
    if (o.walkable ? walkable_cells(&o, scene, &cells, &te)
        : o.cells_path ? cells_load(o.cells_path, &cells, &te) : cli_grid_cells(scene, o.grid, 10000000u, &cells, &te))
        goto fail;
    bake_desc_init(&bd, &o, scene, &cells, &mem);
    if (!o.no_names) { /* the OBJ's object names, for pvscheck and pvsview to tell a renamed or reordered object */
        uint32_t i;
        if (!(names = (const char **)malloc(m.object_count * sizeof(char *)))) {
            tool_error_set(&te, o.scene_path, 0, "out of memory");
            goto fail;
        }
        for (i = 0; i < m.object_count; ++i) names[i] = m.objects[i].name;
        bd.object_names = names;
    }
    if (o.adaptive) o.no_state = 1; /* a cell's PVS alone does not restore its leaves */
    if (o.shard_n > 1) {
        if (o.shard_n > cells.count) {
            tool_error_set(&te, o.cells_path ? o.cells_path : "--grid", 0, "--shard %u/%u: only %u cells", o.shard_k, o.shard_n, cells.count);
            goto fail;
        }
        bd.shard_index = o.shard_k - 1;
        bd.shard_count = o.shard_n;
    }
    if (pvs_bake_begin(&bd, &bake, &pe) != PVS_OK) {
        begin_error(&o, &cells, &pe, &te);
        goto fail;
    }
    if (!o.quiet && pvs_bake_occluders(bake)) print_shrink_info(bake, o.eps);
    if (!o.quiet) print_otree_info(bake);
    if (!o.quiet) print_portal_info(bake);
    secs = (double *)malloc((size_t)pvs_bake_task_count(bake) * sizeof(double) + 8);
    if (!secs) { tool_error_set(&te, NULL, 0, "out of memory"); goto fail; }
    run.task_seconds = secs;
    run.memory = &mem;
    run.threads_given = o.threads_given;
    run.quiet_plan = o.quiet;
    plan_task_bytes(bake, &o, &run, task_what, sizeof(task_what));
    run.object_count = pvs_scene_object_count(scene);
    run.state_every = o.state_every;
    if (!o.no_state) {
        if (!o.state_path) {
            size_t len = strlen(o.out_path) + 7;
            state_buf = (char *)malloc(len);
            if (!state_buf) { tool_error_set(&te, NULL, 0, "out of memory"); goto fail; }
            snprintf(state_buf, len, "%s.state", o.out_path);
            o.state_path = state_buf;
        }
        run.state_path = o.state_path;
        run.fingerprint = bake_fingerprint(argc, argv, &m, &cells, o.up);
    }
    t_bake = cli_seconds();
    r = cli_run_bake_ex(bake, o.threads, o.quiet, "bake", &run, &te);
    if (r == -2) {
        rc = tool_usage_error(TOOL, "%s", te.message);
        goto done;
    }
    if (r) goto fail;
    t_bake = cli_seconds() - t_bake;
    if (!o.quiet) print_state_notes(bake, &run, o.state_path);
    if (cli_write_bake(bake, o.out_path, &size, &te)) goto fail;
    if (run.state_path) remove(run.state_path);
    if (!o.quiet) {
        print_summary(o.out_path, scene, bake, &run, run.threads_used ? run.threads_used : 1, secs, t_bake, cli_seconds() - t0, size, o.shard_n > 1);
        print_notes(bake, &o);
    }
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
    free(names);
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
