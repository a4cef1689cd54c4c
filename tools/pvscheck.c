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

static int usage_error(const char *fmt, const char *arg) {
    fprintf(stderr, "pvscheck: ");
    fprintf(stderr, fmt, arg);
    fprintf(stderr, "\n(see pvscheck --help)\n");
    return 2;
}

static int check_main(int argc, char **argv) {
    const char *scene_path = NULL, *pvs_path = NULL;
    uint32_t up = 0, points = 32, rays = 4096, aim = 32, seed = 7, threads = 0;
    float max_distance = 0.0f;
    int quiet = 0, i, rc = 1;
    mesh m;
    pvs_scene *scene = NULL;
    void *data = NULL;
    size_t size;
    pvs_file f;
    pvs_error pe;
    tool_error te;
    cli_check chk;

    for (i = 1; i < argc; ++i) {
        const char *a = argv[i], *v = i + 1 < argc ? argv[i + 1] : NULL;
        if (!strcmp(a, "--help") || !strcmp(a, "-h")) {
            fputs(usage, stdout);
            return 0;
        } else if (!strcmp(a, "-q") || !strcmp(a, "--quiet")) {
            quiet = 1;
        } else if (!strcmp(a, "--max-distance")) {
            if (!v || parse_float(v, &max_distance) || !(max_distance > 0.0f)) return usage_error("--max-distance needs a positive number%s", "");
            ++i;
        } else if (cli_is_option(a, value_options)) {
            if (!v) return usage_error("%s needs a value", a);
            ++i;
            if (!strcmp(a, "--up") && cli_parse_up(v, &up)) return usage_error("--up takes y or z, not '%s'", v);
            if (!strcmp(a, "--points") && cli_parse_u32(v, 1, 1u << 20, &points)) return usage_error("bad --points '%s'", v);
            if (!strcmp(a, "--rays") && cli_parse_u32(v, 1, 1u << 24, &rays)) return usage_error("bad --rays '%s'", v);
            if (!strcmp(a, "--aim") && cli_parse_u32(v, 0, 1u << 20, &aim)) return usage_error("bad --aim '%s'", v);
            if (!strcmp(a, "--seed") && cli_parse_u32(v, 0, 0xffffffffu, &seed)) return usage_error("bad --seed '%s'", v);
            if (!strcmp(a, "-j") && parse_threads(v, &threads)) return usage_error("bad -j '%s'", v);
        } else if (a[0] == '-' && a[1]) {
            return usage_error("unknown option '%s'", a);
        } else if (!scene_path) {
            scene_path = a;
        } else if (!pvs_path) {
            pvs_path = a;
        } else {
            return usage_error("unexpected argument '%s'", a);
        }
    }
    if (!scene_path || !pvs_path) return usage_error("%s", "give SCENE.obj and OUT.pvs");
    mesh_init(&m);
    if (read_file(pvs_path, &data, &size, &te)) goto fail;
    if (pvs_file_open(data, size, &f, &pe) != PVS_OK) {
        tool_error_set(&te, pvs_path, 0, "%s", pe.message);
        goto fail;
    }
    if (cli_load_scene(scene_path, up ? up : f.up_axis, &m, &scene, &te)) goto fail;
    if (cli_check_file_ex(scene, &f, points, rays, aim, seed, threads, quiet, max_distance, &chk, &te)) goto fail;
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
    goto done;
fail:
    fprintf(stderr, "pvscheck: %s\n", te.message);
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
