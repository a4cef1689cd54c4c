/* pvscheck - check a .pvs file against ray sampling: misses (must be 0) and tightness. See --help. */
#include "cli.h"
#include <stdlib.h>
#include <string.h>

static const char *usage =
    "usage: pvscheck SCENE.obj OUT.pvs [options]\n"
    "  Casts rays from points in every cell and reports objects they hit that the cell's PVS lacks\n"
    "  (misses: a conservative PVS has none) and the tightness (mean PVS size / mean ray-sampled size).\n"
    "  A file with virtual occluders (pvsbake --method vocc) is checked through the PVS rebuilt from\n"
    "  them (pvs_vocc_cull); its stored records must not hold an object that PVS leaves out.\n"
    "  --up y|z      up axis of the scene (default: the one stored in the file)\n"
    "  --points N    points per cell (default 32)\n"
    "  --rays N      rays per point (default 4096)\n"
    "  --aim N       then up to N rays aimed at each object not yet seen, from random points of the cell\n"
    "                to random points of its triangles (default 32; 0 = off): finds small, far objects\n"
    "  --seed N      random seed (default 7; use another seed than the bake)\n"
    "  -j THREADS    worker threads (default: all CPUs; -j2 works too)\n"
    "  --max-distance D  the bake's draw distance (pvsbake --max-distance): objects farther than D from\n"
    "                the cell are not misses\n"
    "  -q, --quiet   no progress bar\n"
    "exit status: 0 no misses, 1 bad input, 2 usage, 3 misses found (or stored and rebuilt PVS differ)\n";

/* The options that take a value (the next argument, whatever it looks like). */
static const char *const value_options[] = {"--max-distance", "--up", "--points", "--rays", "--aim", "--seed", "-j", NULL};

#define TOOL "pvscheck"

typedef struct check_options {
    const char *scene_path, *pvs_path;
    uint32_t up, points, rays, aim, seed, threads;
    float max_distance;
    int quiet;
} check_options;

/* -1 to go on; otherwise the exit status (0 after --help, 2 after a usage error). */
static int parse_options(int argc, char **argv, check_options *o) {
    int i;
    memset(o, 0, sizeof(*o));
    o->points = 32;
    o->rays = 4096;
    o->aim = 32;
    o->seed = 7;
    for (i = 1; i < argc; ++i) {
        const char *a = argv[i], *v = i + 1 < argc ? argv[i + 1] : NULL;
        if (!strcmp(a, "--help") || !strcmp(a, "-h")) {
            fputs(usage, stdout);
            return 0;
        } else if (!strcmp(a, "-q") || !strcmp(a, "--quiet")) {
            o->quiet = 1;
        } else if (!strcmp(a, "--max-distance")) {
            if (!v || parse_float(v, &o->max_distance) || !(o->max_distance > 0.0f))
                return tool_usage_error(TOOL, "--max-distance needs a positive number");
            ++i;
        } else if (cli_is_option(a, value_options)) {
            if (!v) return tool_usage_error(TOOL, "%s needs a value", a);
            ++i;
            if (!strcmp(a, "--up") && cli_parse_up(v, &o->up)) return tool_usage_error(TOOL, "--up takes y or z, not '%s'", v);
            if (!strcmp(a, "--points") && cli_parse_u32(v, 1, 1u << 20, &o->points)) return tool_usage_error(TOOL, "bad --points '%s'", v);
            if (!strcmp(a, "--rays") && cli_parse_u32(v, 1, 1u << 24, &o->rays)) return tool_usage_error(TOOL, "bad --rays '%s'", v);
            if (!strcmp(a, "--aim") && cli_parse_u32(v, 0, 1u << 20, &o->aim)) return tool_usage_error(TOOL, "bad --aim '%s'", v);
            if (!strcmp(a, "--seed") && cli_parse_u32(v, 0, 0xffffffffu, &o->seed)) return tool_usage_error(TOOL, "bad --seed '%s'", v);
            if (!strcmp(a, "-j") && parse_threads(v, &o->threads)) return tool_usage_error(TOOL, "bad -j '%s'", v);
        } else if (a[0] == '-' && a[1]) {
            return tool_usage_error(TOOL, "unknown option '%s'", a);
        } else if (!o->scene_path) {
            o->scene_path = a;
        } else if (!o->pvs_path) {
            o->pvs_path = a;
        } else {
            return tool_usage_error(TOOL, "unexpected argument '%s'", a);
        }
    }
    if (!o->scene_path || !o->pvs_path) return tool_usage_error(TOOL, "give SCENE.obj and OUT.pvs");
    return -1;
}

static int check_main(int argc, char **argv) {
    check_options o;
    int rc = parse_options(argc, argv, &o);
    mesh m;
    pvs_scene *scene = NULL;
    void *data = NULL;
    pvs_file f;
    tool_error te;
    cli_check chk;
    if (rc >= 0) return rc;
    mesh_init(&m);
    if (cli_load_pvs_scene(o.pvs_path, o.scene_path, o.up, &data, &f, &m, &scene, &te) ||
        cli_check_file_ex(scene, &f, o.points, o.rays, o.aim, o.seed, o.threads, o.quiet, o.max_distance, &chk, &te)) {
        fprintf(stderr, "pvscheck: %s\n", te.message);
        rc = 1;
        goto done;
    }
    printf("cells %u  rays %llu  misses %llu in %u cells  mean pvs %.2f  mean sampled %.2f  tightness %.3f%s\n", chk.cells,
           (unsigned long long)chk.rays, (unsigned long long)chk.misses, chk.cells_with_misses, chk.pvs_sum / chk.cells,
           chk.seen_sum / chk.cells, chk.seen_sum > 0 ? chk.pvs_sum / chk.seen_sum : 1.0,
           chk.rebuilt ? "  (PVS rebuilt from the virtual occluders)" : "");
    if (chk.stored_differs)
        printf("the stored records hold objects the PVS rebuilt from the virtual occluders leaves out, in %u cells\n", chk.stored_differs);
    if (chk.misses) {
        printf("first miss: cell %u object %u '%s'%s\n", chk.first_miss_cell, chk.first_miss_object,
               m.objects[chk.first_miss_object].name,
               (f.flags & PVS_FILE_APPROXIMATE) ? " (the file is approximate: ray-sampled bakes miss objects)" : "");
        rc = 3;
    } else {
        rc = chk.stored_differs ? 3 : 0;
    }
done:
    pvs_scene_destroy(scene);
    mesh_free(&m);
    free(data);
    return rc;
}

int main(int argc, char **argv) {
    char **args;
    int rc;
    args = cli_split_jobs(&argc, argv, value_options); /* -j2 as well as -j 2 */
    rc = check_main(argc, args);
    if (args != argv) free(args);
    return rc;
}
