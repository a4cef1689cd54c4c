/* test_cli.c - the command-line tools end to end: exit codes, file:line messages on malformed
   input, no partial output, the --dump listing format, determinism across thread counts.
   Runs from build/ (make test does `cd build && ./pvstest`), where the tools are. */
#define _POSIX_C_SOURCE 200809L
#include "test.h"
#include "../tools/cli.h"
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#define DIR "cli-test"

static void write_text(const char *path, const char *text, size_t len) {
    FILE *f = fopen(path, "wb");
    if (!f) return;
    fwrite(text, 1, len, f);
    fclose(f);
}

static void write_str(const char *path, const char *text) { write_text(path, text, strlen(text)); }

/* Runs a shell command with stdout and stderr captured; returns the exit status, *out the text. */
static int run(const char *cmd, char **out) { return test_run(DIR, cmd, out); }

/* Bakes DIR/NAME.obj over DIR/NAME.txt by method M alone, then as "M BUDGET-OPTION N" (`how`): the first run's summary
   without the note `says`, the second's with it, another file, no miss. */
static void check_budget(const char *name, const char *how, const char *says) {
    char cmd[512], f1[256], f2[256], *out = NULL;
    size_t m = strcspn(how, " ");
    snprintf(cmd, sizeof(cmd), "./pvsbake " DIR "/%s.obj -o " DIR "/%s1.pvs --cells " DIR "/%s.txt --method %.*s", name, name,
             name, (int)m, how);
    CHECK(run(cmd, &out) == 0 && out && !strstr(out, says)); free(out);
    snprintf(cmd, sizeof(cmd), "./pvsbake " DIR "/%s.obj -o " DIR "/%s2.pvs --cells " DIR "/%s.txt --method %s", name, name, name, how);
    CHECK(run(cmd, &out) == 0 && out && strstr(out, says)); free(out);
    snprintf(f1, sizeof(f1), DIR "/%s1.pvs", name);
    snprintf(f2, sizeof(f2), DIR "/%s2.pvs", name);
    CHECK(test_exists(f2) && !test_same_files(f1, f2));
    snprintf(cmd, sizeof(cmd), "./pvscheck -q " DIR "/%s.obj " DIR "/%s2.pvs", name, name);
    CHECK(run(cmd, &out) == 0 && out && strstr(out, "misses 0 ")); free(out);
}

/* A box of 12 triangles, as OBJ lines, with vertex offset base (1-based). */
static void box_obj(char *dst, size_t cap, const char *name, float x0, float y0, float z0, float x1, float y1, float z1, int base) {
    snprintf(dst, cap,
             "o %s\nv %g %g %g\nv %g %g %g\nv %g %g %g\nv %g %g %g\nv %g %g %g\nv %g %g %g\nv %g %g %g\nv %g %g %g\n"
             "f %d %d %d %d\nf %d %d %d %d\nf %d %d %d %d\nf %d %d %d %d\nf %d %d %d %d\nf %d %d %d %d\n",
             name, x0, y0, z0, x1, y0, z0, x1, y1, z0, x0, y1, z0, x0, y0, z1, x1, y0, z1, x1, y1, z1, x0, y1, z1, base, base + 1,
             base + 2, base + 3, base + 4, base + 5, base + 6, base + 7, base, base + 1, base + 5, base + 4, base + 2, base + 3,
             base + 7, base + 6, base + 1, base + 2, base + 6, base + 5, base, base + 4, base + 7, base + 3);
}

/* Expect exit 1, a message naming file:line with a phrase, and no output file. */
static void expect_bad(const char *cmd, const char *where, const char *phrase, const char *out_path) {
    char *out;
    int rc = run(cmd, &out);
    CHECK(rc == 1);
    CHECK(strstr(out, where) != NULL);
    CHECK(strstr(out, phrase) != NULL);
    if (rc != 1 || !strstr(out, where) || !strstr(out, phrase)) fprintf(stderr, "  command: %s\n  output: %s\n", cmd, out);
    CHECK(!test_exists(out_path));
    free(out);
}

/* The demo city's table (a quick, coarse bake) survives encode + decode exactly, and a walk with the
   cursor through every cell agrees with decoding. */
static void test_city_round_trip(void) {
    mesh m;
    mesh_cells cells;
    pvs_scene *scene = NULL;
    pvs_bake *bake = NULL;
    pvs_bake_desc bd;
    pvs_file f;
    tool_error te;
    uint8_t *bytes = NULL;
    size_t size = 0;
    CHECK(cli_demo_city(&m, &cells, &scene, &te) == 0);
    test_bake_desc(&bd, scene, (const pvs_box *)cells.boxes, cells.count, PVS_METHOD_SAMPLE);
    bd.sample.points = 2;
    bd.sample.rays = 256;
    if (scene && pvs_bake_begin(&bd, &bake, NULL) == PVS_OK && cli_run_bake(bake, 2, 1, "bake", &te) == 0) {
        size = pvs_bake_file_size(bake);
        bytes = (uint8_t *)malloc(size);
        CHECK(pvs_bake_write_file(bake, bytes, size, &size, NULL) == PVS_OK);
        CHECK(pvs_file_open(bytes, size, &f, NULL) == PVS_OK);
        if (f.data) {
            uint32_t words = (uint32_t)PVS_BITSET_WORDS(f.object_count), c, bad = 0;
            pvs_word *bits = (pvs_word *)malloc(words * sizeof(pvs_word)), *cur = (pvs_word *)malloc(words * sizeof(pvs_word)),
                     *scratch = (pvs_word *)malloc(words * sizeof(pvs_word));
            pvs_cursor cursor;
            CHECK(f.cell_count == cells.count);
            CHECK(pvs_cursor_init(&cursor, &f, cur, scratch, words, NULL) == PVS_OK);
            for (c = 0; c < f.cell_count; ++c) {
                pvs_box b = pvs_file_cell_box(&f, c);
                float mid[3];
                int k;
                pvs_file_decode(&f, c, bits, words, NULL);
                bad += memcmp(bits, pvs_bake_cell_pvs(bake, c), words * sizeof(pvs_word)) != 0;
                pvs_cursor_move(&cursor, c, NULL, NULL);
                bad += memcmp(cur, bits, words * sizeof(pvs_word)) != 0;
                bad += memcmp(&b, cells.boxes + 6 * (size_t)c, sizeof(b)) != 0;
                for (k = 0; k < 3; ++k) mid[k] = 0.5f * (b.min[k] + b.max[k]);
                bad += pvs_file_find_cell(&f, mid) > c;
            }
            CHECK(bad == 0);
            CHECK(cursor.delta_moves > 0);
            free(bits);
            free(cur);
            free(scratch);
        }
    } else {
        CHECK(0);
    }
    free(bytes);
    pvs_bake_destroy(bake);
    pvs_scene_destroy(scene);
    mesh_cells_free(&cells);
    mesh_free(&m);
}

/* The CLI tests' scene into dst: a wall of top `wall_top` between two small boxes, and a hidden occluder-only box. */
static void wall_scene(char *dst, size_t cap, float wall_top) {
    char a[1024], b[1024];
    box_obj(a, sizeof(a), "left", -6, 0, -1, -4, 2, 1, 1);
    box_obj(b, sizeof(b), "wall", -1, 0, -10, 1, wall_top, 10, 9);
    snprintf(dst, cap, "%s%s", a, b);
    box_obj(a, sizeof(a), "right", 4, 0, -1, 6, 2, 1, 17);
    strncat(dst, a, cap - strlen(dst) - 1);
    box_obj(a, sizeof(a), "occluder_hidden", 10, 0, -1, 11, 2, 1, 25);
    strncat(dst, a, cap - strlen(dst) - 1);
}

void test_cli(void) {
    char scene[4096], *out;
    int rc;
    system("rm -rf " DIR " && mkdir -p " DIR);

    /* a wall between two small boxes, three view cells */
    wall_scene(scene, sizeof(scene), 5);
    write_text(DIR "/scene.obj", scene, strlen(scene));
    write_str(DIR "/cells.txt", "# left, right, both sides\n-3 0.5 -0.5 -2 1.5 0.5\n2 0.5 -0.5 3 1.5 0.5\n\n-3 3 -0.5 3 4 0.5  # straddles\n");

    /* usage */
    CHECK(run("./pvsbake", &out) == 2); free(out);
    CHECK(run("./pvsbake --help", &out) == 0 && strstr(out, "usage")); free(out);
    {
        /* pvsbake SCENE -o x.pvs --cells CELLS with bad options: usage errors (2) naming the problem;
           an option for a method the bake does not run is one too, not silently ignored */
        static const struct { const char *options, *says; } bad[] = {
            {"--bogus", "--bogus"},
            {"--method nope", "unknown method 'nope'"},
            {"-j -3", "-j"},
            {"--method extproj --sweep-planes 0", "--sweep-planes takes 1..256"},
            {"--method extproj --sweep-planes 257", "--sweep-planes takes 1..256"},
            {"--method extproj --resolution 8", "--resolution takes 16..4096"},
            {"--method otree --sweep", "--sweep applies only to method extproj, which --method otree does not run"},
            {"--method otree --no-sweep", "--no-sweep applies only to method extproj"},
            {"--no-sweep --sweep-planes 8", "--no-sweep contradicts --sweep"},
            {"--method otree --otree-budget 63", "--otree-budget takes 64..16777216"},
            {"--method extproj --otree-budget 4096", "--otree-budget applies only to method otree"},
            {"--method portal --portal-budget 999", "--portal-budget takes 1000..4294967295"},
            {"--method otree --portal-budget 5000", "--portal-budget applies only to method portal"},
            {"--method extproj --subcells", "--subcells needs the sweep"},
            {"--no-sweep --subcells", "--subcells needs the sweep"},
            {"--method otree --subcells", "--subcells applies only to method extproj"},
            {"--method otree,extproj --voxel 0.5", "--voxel applies only to method shrink"},
            {"--vocc-max 3", "auto runs vocc only when a list names it"},
            {"--method extproj --rays 16", "--rays applies only to method sample"},
            {"--seed 4", "sample is never part of auto"},
            {"--method shrink --min-cell 1", "--min-cell needs --adaptive"},
            {"--no-state --state-every 4", "contradict --no-state"},
            {"--adaptive 100 --method vocc", "--adaptive does not go with"},
            {"--adaptive 100 --shard 1/2", "--adaptive does not go with"},
            {"--adaptive 100 --state-every 2", "--adaptive does not go with"},
            {"--no-lookup --adaptive 100", "--no-lookup: not with"},
            {"--no-lookup --method vocc", "--no-lookup: not with"},
        };
        size_t k;
        for (k = 0; k < sizeof(bad) / sizeof(bad[0]); ++k) {
            char cmd[512];
            snprintf(cmd, sizeof(cmd), "./pvsbake " DIR "/scene.obj -o " DIR "/x.pvs --cells " DIR "/cells.txt %s", bad[k].options);
            rc = run(cmd, &out);
            CHECK(rc == 2 && strstr(out, bad[k].says));
            if (rc != 2 || !strstr(out, bad[k].says)) fprintf(stderr, "  pvsbake %s: exit %d, %s\n", bad[k].options, rc, out);
            free(out);
        }
    }
    CHECK(run("./pvsbake " DIR "/scene.obj -o " DIR "/x.pvs", &out) == 2); free(out);
    CHECK(run("./pvsinfo", &out) == 2); free(out);
    CHECK(run("./pvscheck " DIR "/scene.obj", &out) == 2); free(out);
    CHECK(run("./pvsgen forest --leaves-per-tree 1000 -o " DIR "/f.obj", &out) == 2 && strstr(out, "--dense only")); free(out);
    CHECK(run("./pvsgen forest --dense --cell-size 0.01 -o " DIR "/f.obj", &out) == 2 && strstr(out, "[0.1, 8]")); free(out);
    CHECK(run("./pvsgen forest --dense --leaves-per-tree 0 -o " DIR "/f.obj", &out) == 2); free(out);
    CHECK(run("./pvsgen forest --dense --leaves-per-tree 5000 --size 2 -o " DIR "/f.obj", &out) == 2 && strstr(out, "at most 10000")); free(out);
    /* the bake-wide memory limit (--memory, else PVSBAKE_MEMORY, else 90% of the machine's): every
       method's allocations go through it, so at 1 byte each is refused at the scene, by name; a
       thread that does not fit, or a -j that does not, is a usage error with the figures; without
       -j the threads that fit run, after one cell measured alone */
    {
        static const char *const methods[] = {"sample", "otree", "extproj", "shrink", "vocc", "auto"};
        size_t k;
        for (k = 0; k < sizeof(methods) / sizeof(methods[0]); ++k) {
            char cmd[512];
            snprintf(cmd, sizeof(cmd), "PVSBAKE_MEMORY=1 ./pvsbake " DIR "/scene.obj -o " DIR "/x.pvs --cells " DIR "/cells.txt --method %s",
                     methods[k]);
            CHECK(run(cmd, &out) == 1 && strstr(out, "scene.obj: out of memory") &&
                  strstr(out, "the memory limit of 1 byte (PVSBAKE_MEMORY) was reached"));
            free(out);
        }
    }
    CHECK(!test_exists(DIR "/x.pvs"));
    CHECK(run("./pvsbake " DIR "/scene.obj -o " DIR "/x.pvs --cells " DIR "/cells.txt --method extproj --memory 1G "
              "--resolution 4096 --sweep", &out) == 2 &&
          strstr(out, "extproj at 4096 pixels with 16 sweep planes needs about 4.1 GiB per thread, more than the") &&
          strstr(out, "memory limit of 1.0 GiB (--memory)") && strstr(out, "lower --resolution or --sweep-planes"));
    free(out);
    CHECK(run("PVSBAKE_MEMORY=1000000000 ./pvsbake " DIR "/scene.obj -o " DIR "/x.pvs --cells " DIR "/cells.txt "
              "--resolution 1024 --sweep-planes 64 -j 2", &out) == 2 && strstr(out, "use -j 1 or fewer") && strstr(out, "(PVSBAKE_MEMORY)"));
    free(out);
    rc = run("./pvsbake " DIR "/scene.obj -o " DIR "/fit.pvs --cells " DIR "/cells.txt --method extproj --sweep --resolution 512 "
             "--memory 160M", &out);
    CHECK(rc == 0 && (sysconf(_SC_NPROCESSORS_ONLN) < 2 || (strstr(out, "pvsbake: 1 thread, not ") && strstr(out, "wall on 1 thread,"))));
    free(out);
    CHECK(run("./pvsbake -q " DIR "/scene.obj -o " DIR "/fit1.pvs --cells " DIR "/cells.txt --method extproj --sweep --resolution 512 -j 1", &out) == 0);
    free(out);
    CHECK(test_same_files(DIR "/fit.pvs", DIR "/fit1.pvs"));
    CHECK(run("./pvsbake -q " DIR "/scene.obj -o " DIR "/fit2.pvs --cells " DIR "/cells.txt --method extproj --sweep --resolution 512 -j 2 "
              "--memory 1G", &out) == 0);
    free(out);
    CHECK(test_same_files(DIR "/fit.pvs", DIR "/fit2.pvs"));
    CHECK(run("PVSBAKE_MEMORY=lots ./pvsbake " DIR "/scene.obj -o " DIR "/x.pvs --cells " DIR "/cells.txt --method extproj", &out) == 2 &&
          strstr(out, "PVSBAKE_MEMORY takes a size in bytes (e.g. 512M or 2G), not 'lots'"));
    free(out);
    CHECK(run("./pvsbake " DIR "/scene.obj -o " DIR "/x.pvs --cells " DIR "/cells.txt --memory 0", &out) == 2 && strstr(out, "--memory takes a size"));
    free(out);
    CHECK(run("./pvsbake " DIR "/scene.obj -o " DIR "/x.pvs --cells " DIR "/cells.txt --memory -5M", &out) == 2); free(out);
    /* cells far bigger than the scene, or far smaller, are valid: shrink's derived eps stays within
       the scene's scale (it overflowed, or underflowed to 0, before: "eps must be > 0") */
    write_str(DIR "/huge.txt", "-3e38 0 -3e38 3e38 10 3e38\n");
    write_str(DIR "/tiny.txt", "-3 1 0 -3 1.00001 1e-45\n");
    CHECK(run("./pvsbake " DIR "/scene.obj -o " DIR "/huge.pvs --cells " DIR "/huge.txt", &out) == 0 && !strstr(out, "pvsbake: pvsbake")); free(out);
    CHECK(run("./pvsbake " DIR "/scene.obj -o " DIR "/tiny.pvs --cells " DIR "/tiny.txt", &out) == 0); free(out);
    CHECK(run("./pvscheck -q " DIR "/scene.obj " DIR "/tiny.pvs --points 8 --rays 512", &out) == 0 && strstr(out, "misses 0")); free(out);
    CHECK(run("./pvsbake " DIR "/scene.obj -o " DIR "/e.pvs --cells " DIR "/cells.txt --method shrink --eps 1e-30", &out) == 0); free(out);
    /* threads beyond the cells to bake are not counted: -j 2 with one cell needs one thread's memory */
    write_str(DIR "/one.txt", "-3 0.5 -0.5 -2 1.5 0.5\n");
    CHECK(run("PVSBAKE_MEMORY=250000000 ./pvsbake -q " DIR "/scene.obj -o " DIR "/one.pvs --cells " DIR "/one.txt --method extproj "
              "--resolution 512 --sweep-planes 64 -j 2", &out) == 0);
    free(out);
    CHECK(run("./pvsbake -q " DIR "/scene.obj -o " DIR "/fit1.pvs --cells " DIR "/cells.txt --method extproj --sweep "
              "--resolution 64 -j 1", &out) == 0);
    free(out);
    CHECK(test_same_files(DIR "/fit.pvs", DIR "/fit1.pvs"));
    /* a method that cannot handle the scene names the scene file, not the cells file */
    write_str(DIR "/tri.obj", "o t\nv 0 0 0\nv 4 0 0\nv 0 4 0\nf 1 2 3\n");
    CHECK(run("./pvsbake " DIR "/tri.obj -o " DIR "/x.pvs --cells " DIR "/cells.txt --method vocc", &out) == 1 &&
          strstr(out, "tri.obj: unsupported: vocc")); free(out);
    CHECK(!test_exists(DIR "/x.pvs"));
    /* --sweep is --sweep-planes 16 at the default resolution 256; other values bake another PVS */
    CHECK(run("./pvsgen walls --size 0.3 --max-cells 12 -o " DIR "/w.obj --cells " DIR "/w.txt", &out) == 0); free(out);
    CHECK(run("./pvsbake -q " DIR "/w.obj -o " DIR "/sw1.pvs --cells " DIR "/w.txt --method extproj --sweep", &out) == 0); free(out);
    CHECK(run("./pvsbake -q " DIR "/w.obj -o " DIR "/sw2.pvs --cells " DIR "/w.txt --method extproj --sweep-planes 16 --resolution 256", &out) == 0);
    free(out);
    CHECK(run("./pvsbake -q " DIR "/w.obj -o " DIR "/sw3.pvs --cells " DIR "/w.txt --method extproj --sweep --resolution 32 --sweep-planes 2", &out) == 0);
    free(out);
    CHECK(run("./pvscheck -q " DIR "/w.obj " DIR "/sw3.pvs", &out) == 0 && strstr(out, "misses 0 ")); free(out);
    CHECK(test_same_files(DIR "/sw1.pvs", DIR "/sw2.pvs"));
    CHECK(test_exists(DIR "/sw3.pvs") && !test_same_files(DIR "/sw1.pvs", DIR "/sw3.pvs")); /* the options reach the bake */
    /* --subcells reaches the bake: a different file, no miss */
    CHECK(run("./pvsbake -q " DIR "/w.obj -o " DIR "/sw4.pvs --cells " DIR "/w.txt --method extproj --sweep --subcells", &out) == 0);
    free(out);
    CHECK(run("./pvscheck -q " DIR "/w.obj " DIR "/sw4.pvs", &out) == 0 && strstr(out, "misses 0 ")); free(out);
    CHECK(test_exists(DIR "/sw4.pvs") && !test_same_files(DIR "/sw1.pvs", DIR "/sw4.pvs"));
    /* --otree-budget and --portal-budget reach the bake: a tiny tree culls less, a flow cut at 1,000 clips takes
       every room, still with no miss; auto takes --portal-budget too (it runs portal) */
    check_budget("w", "otree --otree-budget 64", "a tree reached its node budget and took no more facades");
    CHECK(run("./pvsgen indoor --size 0.3 --max-cells 12 -o " DIR "/in.obj --cells " DIR "/in.txt", &out) == 0); free(out);
    check_budget("in", "portal --portal-budget 1000", "the flow reached its budget and took every room");
    CHECK(run("./pvsbake -q " DIR "/in.obj -o " DIR "/pb3.pvs --cells " DIR "/in.txt --portal-budget 5000", &out) == 0); free(out);

    /* a good bake; options in any order; identical bytes for 1 and 2 threads (-j2 spelt as make does) */
    rc = run("./pvsbake --method sample -q --cells " DIR "/cells.txt -o " DIR "/a.pvs -j 1 " DIR "/scene.obj --rays 256 --points 16", &out);
    CHECK(rc == 0); free(out);
    rc = run("./pvsbake --method sample " DIR "/scene.obj -o " DIR "/b.pvs --cells " DIR "/cells.txt -j2 --rays 256 --points 16", &out);
    CHECK(rc == 0 && strstr(out, "approximate")); free(out);
    /* a method's own PVS and what it alone culled add up to the drawable objects: the occluder_*
       object, in no PVS, is culled by none (auto --preview runs one method) */
    rc = run("./pvsbake " DIR "/scene.obj -o " DIR "/p.pvs --cells " DIR "/cells.txt --preview", &out);
    {
        const char *at = out ? strstr(out, "its own PVS ") : NULL;
        double own = -1.0, culled = -1.0;
        CHECK(rc == 0 && at && sscanf(at, "its own PVS %lf objects, it alone culled %lf", &own, &culled) == 2);
        CHECK(own >= 0.0 && culled >= 0.0 && own + culled > 2.95 && own + culled < 3.05);
        if (!(own + culled > 2.95 && own + culled < 3.05)) fprintf(stderr, "  output: %s\n", out ? out : "");
    }
    free(out);
    /* the summary's share is of the drawable objects: occluder_* objects are never in a PVS (a
       conservative bake that culls nothing reads 100%, not 75%) */
    rc = run("./pvsbake " DIR "/scene.obj -o " DIR "/s.pvs --cells " DIR "/cells.txt --method shrink --eps 100", &out);
    CHECK(rc == 0 && strstr(out, "mean PVS 3.0 objects (100.0% of the 3 drawable)"));
    if (rc != 0 || !strstr(out, "(100.0% of the 3 drawable)")) fprintf(stderr, "  output: %s\n", out);
    free(out);
    CHECK(test_same_files(DIR "/a.pvs", DIR "/b.pvs"));
    /* an option's value is never split as -jN: files named -j3.txt and -j4.pvs */
    CHECK(run("cp " DIR "/cells.txt " DIR "/-j3.txt", &out) == 0); free(out);
    rc = run("(cd " DIR " && ../pvsbake --method sample -q --cells -j3.txt -o -j4.pvs -j 1 scene.obj --rays 256 --points 16)", &out);
    CHECK(rc == 0);
    if (rc != 0) fprintf(stderr, "  output: %s\n", out);
    free(out);
    CHECK(test_same_files(DIR "/-j4.pvs", DIR "/a.pvs"));
    rc = run("./pvscheck -q --seed -j5 " DIR "/scene.obj " DIR "/a.pvs", &out);
    CHECK(rc == 2 && strstr(out, "bad --seed '-j5'"));
    if (rc != 2 || !strstr(out, "bad --seed '-j5'")) fprintf(stderr, "  output: %s\n", out);
    free(out);
    /* sharded bakes: parts merge into the bytes of the whole bake for N = 1, 2, 3, 7 */
    CHECK(run("./pvsgen indoor --seed 3 --size 0.3 --max-cells 30 -o " DIR "/in.obj --cells " DIR "/in.txt", &out) == 0); free(out);
    CHECK(run("./pvsbake --method sample -q " DIR "/in.obj --cells " DIR "/in.txt -o " DIR "/whole.pvs --rays 64 --points 4 -j 2", &out) == 0); free(out);
    {
        static const int ns[4] = {1, 2, 3, 7};
        int j, k;
        CHECK(test_exists(DIR "/whole.pvs"));
        for (j = 0; j < 4; ++j) {
            char cmd[4096];
            int len = snprintf(cmd, sizeof(cmd), "./pvsbake merge -o " DIR "/merged.pvs");
            for (k = ns[j]; k >= 1; --k) { /* parts in any order */
                char bake[512];
                snprintf(bake, sizeof(bake), "./pvsbake --method sample -q " DIR "/in.obj --cells " DIR "/in.txt -o " DIR "/part%d.pvs --rays 64 --points 4 -j 1 --shard %d/%d",
                         k, k, ns[j]);
                CHECK(run(bake, &out) == 0); free(out);
                len += snprintf(cmd + len, sizeof(cmd) - (size_t)len, " " DIR "/part%d.pvs", k);
            }
            CHECK(run(cmd, &out) == 0); free(out);
            CHECK(test_same_files(DIR "/merged.pvs", DIR "/whole.pvs"));
            if (ns[j] == 3) {
                CHECK(run("./pvsinfo " DIR "/part2.pvs", &out) == 0 && strstr(out, "shard 2 of 3")); free(out);
                /* a missing shard, a repeated one, a part of another bake */
                CHECK(run("./pvsbake merge -o " DIR "/m2.pvs " DIR "/part1.pvs " DIR "/part2.pvs", &out) == 1 && strstr(out, "shard 3/3 is missing")); free(out);
                CHECK(run("./pvsbake merge -o " DIR "/m2.pvs " DIR "/part1.pvs " DIR "/part1.pvs " DIR "/part3.pvs", &out) == 1 && strstr(out, "also in")); free(out);
                CHECK(run("./pvsbake merge -o " DIR "/m2.pvs " DIR "/part1.pvs " DIR "/whole.pvs", &out) == 1 && strstr(out, "not a part file")); free(out);
                CHECK(!test_exists(DIR "/m2.pvs"));
            }
        }
        CHECK(run("./pvsbake " DIR "/in.obj --cells " DIR "/in.txt -o " DIR "/x.pvs --shard 4/3", &out) == 2); free(out);
        CHECK(run("./pvsbake " DIR "/in.obj --cells " DIR "/in.txt -o " DIR "/x.pvs --shard 31/31", &out) == 1 && strstr(out, "only 30 cells")); free(out);
        CHECK(run("./pvsbake merge " DIR "/part1.pvs", &out) == 2); free(out);
        /* --no-lookup: the bake's records without boxes, as merge --no-lookup writes them; the tools that need boxes
           say so; not with shards */
        CHECK(run("./pvsbake --method sample -q " DIR "/in.obj --cells " DIR "/in.txt -o " DIR "/nl.pvs --rays 64 --points 4 -j 2 --no-lookup", &out) == 0); free(out);
        CHECK(run("./pvsbake merge --no-lookup -o " DIR "/nlm.pvs " DIR "/whole.pvs", &out) == 0); free(out);
        CHECK(test_same_files(DIR "/nl.pvs", DIR "/nlm.pvs"));
        CHECK(run("./pvsinfo " DIR "/nl.pvs", &out) == 0 && strstr(out, "no boxes or look-up") && !strstr(out, "CELL")); free(out);
        {
            char *o2 = NULL;
            CHECK(run("./pvsinfo --dump " DIR "/nl.pvs", &out) == 0 && run("./pvsinfo --dump " DIR "/whole.pvs", &o2) == 0);
            CHECK(out && o2 && strlen(out) > 100 && !strcmp(out, o2));
            free(out);
            free(o2);
        }
        CHECK(run("./pvscheck -q " DIR "/in.obj " DIR "/nl.pvs", &out) == 1 && strstr(out, "no cell boxes")); free(out);
        CHECK(run("./pvsinfo --at 1 1 1 " DIR "/nl.pvs", &out) == 1 && strstr(out, "stores no look-up")); free(out);
        CHECK(run("./pvsbake merge -o " DIR "/m3.pvs " DIR "/nl.pvs", &out) == 1 && strstr(out, "no cell boxes")); free(out);
        CHECK(run("./pvsbake " DIR "/in.obj --cells " DIR "/in.txt -o " DIR "/x.pvs --shard 1/2 --no-lookup", &out) == 2); free(out);
        CHECK(run("./pvsinfo " DIR "/whole.pvs", &out) == 0 && strstr(out, "key cells") && strstr(out, "chain mean"));
        { /* the sections' sizes: the file's header, table, sections and padding (< 8 bytes after each) */
            const char *at = strstr(out, "sections    META ");
            size_t fsize = 0, sum = 0, count = 0;
            char *whole = test_slurp(DIR "/whole.pvs", &fsize);
            CHECK(at && strstr(at, ", CELL ") && strstr(at, ", RECS ") && whole);
            for (at = at ? at + 12 : NULL; at && *at != '(';) {
                char tag[5];
                unsigned long sz;
                int used = 0;
                if (sscanf(at, " %4s %lu%n", tag, &sz, &used) != 2) break;
                sum += sz, ++count, at += used;
                if (*at == ',') ++at;
            }
            CHECK(count >= 5 && sum + 32 + 16 * count <= fsize && sum + 32 + 16 * count + 8 * count > fsize);
            free(whole);
        }
        free(out);
    }
    /* --dump: exactly "CELL: OBJ OBJ ..." per cell; the wall hides the far box; occluders never listed */
    CHECK(run("./pvsinfo --dump " DIR "/a.pvs", &out) == 0);
    CHECK(strcmp(out, "0: 0 1\n1: 1 2\n2: 0 1 2\n") == 0);
    if (strcmp(out, "0: 0 1\n1: 1 2\n2: 0 1 2\n")) fprintf(stderr, "  dump: %s\n", out);
    free(out);
    CHECK(run("./pvsinfo --at 2.5 1 0 " DIR "/a.pvs", &out) == 0 && strcmp(out, "1: 1 2\n") == 0); free(out);
    CHECK(run("./pvsinfo --at 100 1 0 " DIR "/a.pvs", &out) == 1 && strstr(out, "no cell")); free(out);
    CHECK(run("./pvsinfo --verify " DIR "/a.pvs", &out) == 0); free(out);
    CHECK(run("./pvsinfo " DIR "/a.pvs", &out) == 0 && strstr(out, "cells       3") && strstr(out, "approximate")); free(out);
    CHECK(run("./pvscheck -q -j2 " DIR "/scene.obj " DIR "/a.pvs", &out) == 0 && strstr(out, "misses 0")); free(out);
    /* a damaged file: --verify fails with the reason; a file of another scene is refused */
    {
        size_t na = 0;
        char *fa = test_slurp(DIR "/a.pvs", &na);
        if (fa && na > 40) {
            fa[na - 20] ^= 0x40;
            write_text(DIR "/bad.pvs", fa, na);
            CHECK(run("./pvsinfo --verify " DIR "/bad.pvs", &out) == 1 && strstr(out, "checksum")); free(out);
            write_text(DIR "/short.pvs", fa, 40);
            CHECK(run("./pvsinfo " DIR "/short.pvs", &out) == 1 && strstr(out, "truncated")); free(out);
        }
        free(fa);
        write_str(DIR "/other.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
        CHECK(run("./pvscheck " DIR "/other.obj " DIR "/a.pvs", &out) == 1 && strstr(out, "not the same scene")); free(out);
    }
    { /* the same objects, the wall half a unit taller: the file's scene fingerprint tells it is stale */
        char edited[4096];
        wall_scene(edited, sizeof(edited), 5.5f);
        write_text(DIR "/edited.obj", edited, strlen(edited));
        CHECK(run("./pvsinfo " DIR "/a.pvs", &out) == 0 && strstr(out, "scene       fingerprint ")); free(out);
        CHECK(run("./pvscheck " DIR "/edited.obj " DIR "/a.pvs", &out) == 1 && strstr(out, "stale: baked from another version"));
        free(out);
        CHECK(run("./pvsview " DIR "/edited.obj " DIR "/a.pvs -o " DIR "/e.png", &out) == 1 && strstr(out, "stale")); free(out);
    }
    { /* renamed objects, same geometry (the same fingerprint): told by the names the bake stores, unless --no-names */
        char renamed[4096], *at;
        wall_scene(renamed, sizeof(renamed), 5);
        at = strstr(renamed, "o right");
        CHECK(at != NULL);
        if (at) memcpy(at + 2, "rigid", 5);
        write_text(DIR "/renamed.obj", renamed, strlen(renamed));
        CHECK(run("./pvsinfo " DIR "/a.pvs", &out) == 0 && strstr(out, "named (object 0 'left')")); free(out);
        {   /* --raw: a byte per cell for 4 objects, bit i object i, as the file decodes */
            size_t rs = 0, fs = 0;
            char *raw, *fb;
            pvs_file f;
            pvs_word bits[1];
            uint32_t c;
            CHECK(run("./pvsinfo --raw " DIR "/a.pvs " DIR "/a.raw", &out) == 0); free(out);
            CHECK(run("./pvsinfo --raw " DIR "/a.pvs", &out) == 2); free(out);
            raw = test_slurp(DIR "/a.raw", &rs);
            fb = test_slurp(DIR "/a.pvs", &fs);
            CHECK(raw && fb && pvs_file_open(fb, fs, &f, NULL) == PVS_OK && rs == f.cell_count);
            for (c = 0; raw && fb && c < f.cell_count && c < rs; ++c)
                CHECK(pvs_file_decode(&f, c, bits, 1, NULL) == PVS_OK && (uint8_t)raw[c] == (uint8_t)bits[0]);
            free(raw);
            free(fb);
        }
        CHECK(run("./pvscheck " DIR "/renamed.obj " DIR "/a.pvs", &out) == 1 &&
              strstr(out, "stale: object 2 is 'right' in the file but 'rigid' in") && strstr(out, "renamed or reordered"));
        free(out);
        CHECK(run("./pvsbake --method sample -q --no-names --cells " DIR "/cells.txt -o " DIR "/nn.pvs -j 1 " DIR
                  "/scene.obj --rays 256 --points 16", &out) == 0);
        free(out);
        CHECK(run("./pvsinfo " DIR "/nn.pvs", &out) == 0 && strstr(out, "no names stored")); free(out);
        CHECK(run("./pvscheck -q " DIR "/renamed.obj " DIR "/nn.pvs", &out) == 0); free(out);
    }
    /* --grid */
    CHECK(run("./pvsbake --method sample -q " DIR "/scene.obj -o " DIR "/g.pvs --grid 4 --rays 64 --points 4", &out) == 0); free(out);
    CHECK(run("./pvsinfo --verify " DIR "/g.pvs", &out) == 0); free(out);
    CHECK(run("./pvsbake -q " DIR "/scene.obj -o " DIR "/g2.pvs --grid 0.0001", &out) == 1 && strstr(out, "exceed")); free(out);
    CHECK(!test_exists(DIR "/g2.pvs"));

    /* malformed OBJ and cells files: exit 1, file:line, a specific phrase, no output file */
    {
        static const struct {
            const char *name; /* written under DIR; ".obj" files are scenes, ".txt" files cells */
            const char *text;
            size_t len; /* 0: strlen(text) */
            const char *where, *phrase;
        } bad[] = {
            {"m1.obj", "v 0 0 0\nv 1 0 0\nf 1 2\n", 0, "m1.obj:3:", "fewer than 3"},
            {"m2.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n", 0, "m2.obj:4:", "out of range"},
            {"m3.obj", "v 0 0 0\nv 1 zero 0\nv 0 1 0\nf 1 2 3\n", 0, "m3.obj:2:", "bad number"},
            {"m4.obj", "", 0, "m4.obj", "empty"},
            {"m5.obj", "v 0 0 0\n\x01\x02\x00\xff binary", 17, "m5.obj:2:", "binary"},
            {"m6.obj", "v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n", 0, "m6.obj:2:", "not finite"},
            {"m7.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 0 3\n", 0, "m7.obj:4:", "index 0"},
            {"m8.obj", "# nothing\nv 0 0 0\n", 0, "m8.obj", "no faces"},
            {"missing.obj", NULL, 0, "missing.obj", "cannot open"},
            {"c1.txt", "0 0 0 1 1 1\n0 0 0 1 1\n", 0, "c1.txt:2:", "6 numbers"},
            {"c2.txt", "0 0 0 1 1 1\n# c\n0 0 0 1 x 1\n", 0, "c2.txt:3:", "bad number"},
            {"c3.txt", "0 0 0 1 inf 1\n", 0, "c3.txt:1:", "not finite"},
            {"c4.txt", "0 2 0 1 1 1\n", 0, "c4.txt:1:", "min greater than max"},
            {"c5.txt", "# only a comment\n", 0, "c5.txt", "no cells"},
            {"c6.txt", "0 0 0 1 1 1\n\x7f\x01\x00", 15, "c6.txt:2:", "binary"},
        };
        size_t k;
        for (k = 0; k < sizeof(bad) / sizeof(bad[0]); ++k) {
            char path[256], cmd[1024], where[256];
            int is_obj = strstr(bad[k].name, ".obj") != NULL;
            snprintf(path, sizeof(path), DIR "/%s", bad[k].name);
            snprintf(where, sizeof(where), DIR "/%s", bad[k].where);
            if (bad[k].text) write_text(path, bad[k].text, bad[k].len ? bad[k].len : strlen(bad[k].text));
            snprintf(cmd, sizeof(cmd), "./pvsbake %s -o " DIR "/o.pvs --cells %s", is_obj ? path : DIR "/scene.obj",
                     is_obj ? DIR "/cells.txt" : path);
            expect_bad(cmd, where, bad[k].phrase, DIR "/o.pvs");
        }
    }
    write_str(DIR "/m9.obj", "o flat\nv 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n");
    /* an object of zero-area triangles only is kept (ids follow the file) with a warning naming it */
    CHECK(run("./pvsbake --method sample " DIR "/m9.obj -o " DIR "/o9.pvs --cells " DIR "/cells.txt --rays 16 --points 2", &out) == 0 &&
          strstr(out, DIR "/m9.obj:1:") && strstr(out, "zero-area"));
    free(out);
    /* an output into a missing directory leaves nothing behind */
    rc = run("./pvsbake --method sample -q " DIR "/scene.obj -o " DIR "/nodir/o.pvs --cells " DIR "/cells.txt --rays 16 --points 2", &out);
    CHECK(rc == 1 && strstr(out, DIR "/nodir/o.pvs")); free(out);
    {
        char *ls;
        run("ls " DIR " | grep -c tmp", &ls);
        CHECK(atoi(ls) == 0);
        free(ls);
    }
    /* the tools link only libc, libm, libpthread and the loader */
    if (system("command -v ldd >/dev/null 2>&1") == 0) {
        rc = run("ldd ./pvsbake | grep -v -E 'linux-vdso|libc\\.so|libm\\.so|libpthread\\.so|ld-linux|ld-musl' | grep -c .", &out);
        CHECK(atoi(out) == 0);
        free(out);
    }
    system("rm -rf " DIR);
    test_city_round_trip();
}
