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
    "  --method NAME     sample (ray sampling: an approximate PVS, NOT conservative)\n"
    "                    shrink (occluder shrinking, Wonka 2000: conservative)\n"
    "                    otree (2.5D occlusion trees: conservative; occluders = vertical walls on the ground)\n"
    "                    extproj (extended projections, Durand et al. 2000: conservative)\n"
    "  --eps E           sampling / shrinking distance (stored in the file); shrink's default is an\n"
    "                    eighth of the median cell width, printed in the summary\n"
    "  --2d5, --3d       shrink: force the 2.5D (cull map) or 3D (depth cube) path; default: 2.5D\n"
    "                    when the synthesized occluders stand on the ground\n"
    "  --voxel V         shrink: voxel size of the occluder synthesis (default eps / 1.5, capped)\n"
    "  --sweep           extproj: add the occlusion sweep (Durand 2000 §5) for scenes of many small\n"
    "                    occluders (foliage); slower\n"
    "  --adaptive N      split a cell whose PVS holds more than N triangles in two, recursively\n"
    "                    (Durand 2000 §6.1); the file holds the leaf cells. Not with --shard\n"
    "  --min-cell S      --adaptive: no cell side below S (default: an eighth of the cell's longest)\n"
    "  --points N        sample method: points per cell (default 32)\n"
    "  --rays N          sample method: rays per point (default 2048)\n"
    "  --seed N          sample method: random seed (default 1)\n"
    "  --chain K         file: decode any cell in at most K deltas (1..64, default 8)\n"
    "  --shard K/N       bake only shard K of N (cells K-1, K-1+N, ...) into a part file for merge\n"
    "  -j THREADS        worker threads (default: all CPUs); the file is identical for any count\n"
    "  -q, --quiet       no progress bar and no summary\n"
    "  --help            this text\n"
    "exit status: 0 success, 1 bad input (message names file and line), 2 usage\n";

static int usage_error(const char *fmt, const char *arg) {
    fprintf(stderr, "pvsbake: ");
    fprintf(stderr, fmt, arg);
    fprintf(stderr, "\n(see pvsbake --help)\n");
    return 2;
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

int main(int argc, char **argv) {
    const char *scene_path = NULL, *out_path = NULL, *cells_path = NULL;
    float grid = 0.0f, eps = 0.0f, voxel = 0.0f;
    pvs_shrink_mode shrink_mode = PVS_SHRINK_AUTO;
    uint32_t sweep = 0, adaptive = 0;
    float min_cell = 0.0f;
    uint32_t up = 1, threads = 0, points = 0, rays = 0, seed = 1, chain = 0, shard_k = 0, shard_n = 0;
    int quiet = 0, i;
    pvs_method method = PVS_METHOD_SAMPLE;
    mesh m;
    mesh_cells cells;
    pvs_scene *scene = NULL;
    pvs_bake *bake = NULL;
    pvs_bake_desc bd;
    pvs_error pe;
    tool_error te;
    size_t size = 0;
    double t0, t_bake;
    int rc = 1;

    if (argc > 1 && !strcmp(argv[1], "merge")) return merge_main(argc, argv);

    for (i = 1; i < argc; ++i) {
        const char *a = argv[i];
        const char *v = i + 1 < argc ? argv[i + 1] : NULL;
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
            sweep = PVS_EXTPROJ_SWEEP_PLANES;
        } else if (!strcmp(a, "-o") || !strcmp(a, "--cells") || !strcmp(a, "--grid") || !strcmp(a, "--up") ||
                   !strcmp(a, "--method") || !strcmp(a, "--eps") || !strcmp(a, "-j") || !strcmp(a, "--points") ||
                   !strcmp(a, "--rays") || !strcmp(a, "--seed") || !strcmp(a, "--chain") || !strcmp(a, "--shard") || !strcmp(a, "--voxel") ||
                   !strcmp(a, "--adaptive") || !strcmp(a, "--min-cell")) {
            if (!v) return usage_error("%s needs a value", a);
            ++i;
            if (!strcmp(a, "-o")) out_path = v;
            else if (!strcmp(a, "--cells")) cells_path = v;
            else if (!strcmp(a, "--grid")) {
                if (parse_float(v, &grid) || !(grid > 0.0f)) return usage_error("--grid needs a positive size, not '%s'", v);
            } else if (!strcmp(a, "--up")) {
                if (cli_parse_up(v, &up)) return usage_error("--up takes y or z, not '%s'", v);
            } else if (!strcmp(a, "--method")) {
                if (!strcmp(v, "sample")) method = PVS_METHOD_SAMPLE;
                else if (!strcmp(v, "shrink")) method = PVS_METHOD_SHRINK;
                else if (!strcmp(v, "otree")) method = PVS_METHOD_OTREE;
                else if (!strcmp(v, "extproj")) method = PVS_METHOD_EXTPROJ;
                else return usage_error("unknown method '%s' (available: sample, shrink, otree, extproj)", v);
            } else if (!strcmp(a, "--adaptive")) {
                if (cli_parse_u32(v, 1, 0xffffffffu, &adaptive)) return usage_error("--adaptive takes a triangle budget >= 1, not '%s'", v);
            } else if (!strcmp(a, "--min-cell")) {
                if (parse_float(v, &min_cell) || !(min_cell > 0.0f)) return usage_error("--min-cell needs a positive size, not '%s'", v);
            } else if (!strcmp(a, "--voxel")) {
                if (parse_float(v, &voxel) || !(voxel > 0.0f)) return usage_error("--voxel needs a positive size, not '%s'", v);
            } else if (!strcmp(a, "--eps")) {
                if (parse_float(v, &eps) || !(eps > 0.0f)) return usage_error("--eps needs a positive number, not '%s'", v);
            } else if (!strcmp(a, "-j")) {
                if (parse_threads(v, &threads)) return usage_error("-j takes a thread count 0..1024, not '%s'", v);
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

    mesh_init(&m);
    mesh_cells_init(&cells);
    t0 = cli_seconds();
    if (cli_load_scene(scene_path, up, &m, &scene, &te)) goto fail;
    if (cells_path ? cells_load(cells_path, &cells, &te) : cli_grid_cells(scene, grid, 10000000u, &cells, &te)) goto fail;

    memset(&bd, 0, sizeof(bd));
    bd.scene = scene;
    bd.cells = (const pvs_box *)cells.boxes;
    bd.cell_count = cells.count;
    bd.method = method;
    bd.eps = eps;
    bd.sample_points = points;
    bd.sample_rays = rays;
    bd.seed = seed;
    bd.max_chain = chain;
    bd.shrink_mode = shrink_mode;
    bd.extproj_sweep = sweep;
    bd.adaptive_budget = adaptive;
    bd.adaptive_min_size = min_cell;
    bd.voxel_size = voxel;
    if (shard_n > 1) {
        if (shard_n > cells.count) {
            tool_error_set(&te, cells_path ? cells_path : "--grid", 0, "--shard %u/%u: only %u cells", shard_k, shard_n, cells.count);
            goto fail;
        }
        bd.shard_index = shard_k - 1;
        bd.shard_count = shard_n;
    }
    if (pvs_bake_begin(&bd, &bake, &pe) != PVS_OK) {
        tool_error_set(&te, cells_path ? cells_path : "--grid", 0, "%s", pe.message);
        goto fail;
    }
    if (!quiet && pvs_bake_occluders(bake)) {
        pvs_occluders_info oi;
        pvs_occluders_get_info(pvs_bake_occluders(bake), &oi);
        fprintf(stderr, "shrink: eps %g%s, %s path; voxels %u x %u x %u of %g: %llu solid, %llu after erosion, %u boxes, %u columns\n",
                (double)pvs_bake_eps(bake), eps > 0.0f ? "" : " (default: an eighth of the median cell width)",
                pvs_bake_shrink_mode(bake) == PVS_SHRINK_2D5 ? "2.5D" : "3D", oi.dims[0], oi.dims[1], oi.dims[2],
                (double)oi.voxel_size, (unsigned long long)oi.solid, (unsigned long long)oi.eroded, oi.box_count, oi.rect_count);
        if (oi.leak_cell != PVS_NO_CELL)
            fprintf(stderr, "  cell %u reaches the outside (open to the sky, or a leak) near %g %g %g\n", oi.leak_cell,
                    (double)oi.leak_point[0], (double)oi.leak_point[1], (double)oi.leak_point[2]);
        fprintf(stderr, "  %u objects give no occluder volume (thin walls with open space on both sides, props)\n", oi.thin_objects);
        if (oi.eroded == 0)
            fprintf(stderr, "  warning: no occluder volume survives erosion by eps: every object will be visible from every cell;\n"
                            "  try a smaller --voxel or --eps, or --method extproj for thin walls\n");
    }
    t_bake = cli_seconds();
    if (cli_run_bake(bake, threads, quiet, "bake", &te)) goto fail;
    t_bake = cli_seconds() - t_bake;
    if (cli_write_bake(bake, out_path, &size, &te)) goto fail;
    if (!quiet) {
        uint32_t t, objects = pvs_scene_object_count(scene), tasks = pvs_bake_task_count(bake);
        double sum = 0.0;
        for (t = 0; t < tasks; ++t) sum += pvs_bitset_count(pvs_bake_cell_pvs(bake, pvs_bake_task_cell(bake, t)), objects);
        fprintf(stderr,
                "%s: %u objects, %u triangles, %u cells%s, method %s%s\n"
                "  mean PVS %.1f objects (%.1f%%), bake %.2f ms per cell, %.2f s total, file %zu bytes (%.1f per cell)\n",
                out_path, objects, pvs_scene_triangle_count(scene), tasks, shard_n > 1 ? " (this shard)" : "",
                pvs_method_name(pvs_bake_method(bake)),
                pvs_bake_method(bake) == PVS_METHOD_SAMPLE ? " (approximate: ray sampling, not conservative)" : " (conservative)",
                sum / tasks, 100.0 * sum / tasks / objects, 1000.0 * t_bake / tasks, cli_seconds() - t0, size, (double)size / tasks);
        if (adaptive)
            fprintf(stderr, "  adaptive: %u leaf cells in the file (budget %u triangles; the mean PVS above is of the whole cells)\n",
                    pvs_bake_leaf_count(bake), adaptive);
    }
    rc = 0;
    goto done;
fail:
    fprintf(stderr, "pvsbake: %s\n", te.message);
done:
    pvs_bake_destroy(bake);
    pvs_scene_destroy(scene);
    mesh_cells_free(&cells);
    mesh_free(&m);
    return rc;
}
