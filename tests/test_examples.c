/* test_examples.c - the software renderer of the examples against a ray-casting reference; the
   resumable bake (a pvsbake killed half-way with SIGKILL and rerun gives the bytes of an
   uninterrupted bake; a state of another bake is ignored); pvsbake's new options and statistics;
   pvsview (the map, the frame's count of pixels of objects outside the PVS, which flags a PVS that
   misses, bad input); the runtime example (no allocation). Runs from build/ like test_cli. */
#define _POSIX_C_SOURCE 200809L
#include "test.h"
#include "../tools/cli.h"
#include "../tools/render.h"
#include <math.h>
#include <signal.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#define EDIR "examples-test"

static int ex_run(const char *cmd, char **out) { return test_run(EDIR, cmd, out); }

/* ---- the renderer ---- */

static uint64_t rs = 0x5eed;
static double rnd(void) { return test_rnd(&rs); }

/* Random triangles, some crossing the near plane or behind the eye, drawn one per image and
   compared per pixel with a ray cast through the pixel centre (double): a pixel is drawn exactly
   when the ray hits the triangle in front of the near plane (pixels within a hair of an edge are
   not judged), and its depth is near / distance along the view axis. Then depth order: two
   overlapping triangles give the nearer one's colour in either drawing order. */
static void test_renderer(void) {
    render_image im;
    render_view view;
    pvs_camera cam;
    uint32_t t, x, y, bad_cover = 0, bad_depth = 0, judged = 0, drawn = 0;
    CHECK(render_image_init(&im, 96, 64) == 0);
    memset(&cam, 0, sizeof(cam));
    cam.eye[0] = 0.5f; cam.eye[1] = 1.0f; cam.eye[2] = -0.25f;
    cam.forward[0] = 0.2f; cam.forward[1] = -0.1f; cam.forward[2] = 1.0f;
    cam.up[1] = 1.0f;
    cam.fov_y = 1.1f;
    cam.near_plane = 0.5f;
    CHECK(render_view_init(&view, &cam, &im) == 0);
    for (t = 0; t < 300; ++t) {
        float v[9];
        double f[3], r[3], u[3], fl, ul, th = tan(0.5 * cam.fov_y), asp = 96.0 / 64.0;
        int k;
        for (k = 0; k < 9; ++k) v[k] = (float)((k % 3 == 2 ? -2.0 : -6.0) + (k % 3 == 2 ? 10.0 : 12.0) * rnd());
        render_clear(&im, RENDER_RGBA(0, 0, 0, 255));
        render_triangles(&im, &view, v, NULL, 0, 1, RENDER_RGBA(255, 255, 255, 255), RENDER_UNLIT);
        /* the camera frame, as pvs_camera_matrix builds it */
        for (k = 0; k < 3; ++k) f[k] = cam.forward[k];
        fl = sqrt(f[0] * f[0] + f[1] * f[1] + f[2] * f[2]);
        for (k = 0; k < 3; ++k) f[k] /= fl;
        for (k = 0; k < 3; ++k) u[k] = cam.up[k] - f[k] * (f[1] * 1.0);
        ul = sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]);
        for (k = 0; k < 3; ++k) u[k] /= ul;
        r[0] = f[1] * u[2] - f[2] * u[1]; r[1] = f[2] * u[0] - f[0] * u[2]; r[2] = f[0] * u[1] - f[1] * u[0];
        for (y = 0; y < im.height; ++y)
            for (x = 0; x < im.width; ++x) {
                double sx = ((x + 0.5) / im.width * 2.0 - 1.0) * th * asp, sy = (1.0 - (y + 0.5) / im.height * 2.0) * th, d[3],
                       eye[3], h[3], bu, bv, tt, margin;
                int hit, got;
                for (k = 0; k < 3; ++k) {
                    d[k] = f[k] + sx * r[k] + sy * u[k]; /* a unit step along the view axis */
                    eye[k] = cam.eye[k];
                }
                if (!test_ray_triangle(eye, d, v, v + 3, v + 6, 1e-12, h)) continue;
                bu = h[0];
                bv = h[1];
                tt = h[2]; /* distance along the view axis */
                margin = fmin(fmin(fabs(bu), fabs(bv)), fmin(fabs(1.0 - bu - bv), fabs(tt - cam.near_plane)));
                if (margin < 1e-4) continue;
                hit = bu > 0.0 && bv > 0.0 && bu + bv < 1.0 && tt > cam.near_plane;
                got = im.rgba[4 * ((size_t)y * im.width + x)] == 255;
                ++judged;
                drawn += (uint32_t)got;
                bad_cover += (uint32_t)(hit != got);
                if (hit && got && fabs(im.depth[(size_t)y * im.width + x] - cam.near_plane / tt) > 1e-4 * (cam.near_plane / tt)) ++bad_depth;
            }
    }
    CHECK(judged > 100000 && drawn > 10000);
    CHECK(bad_cover == 0);
    CHECK(bad_depth == 0);
    if (bad_cover || bad_depth) fprintf(stderr, "renderer: %u coverage and %u depth mismatches of %u pixels\n", bad_cover, bad_depth, judged);
    {
        /* two parallel quads facing the camera: the nearer one wins in both orders */
        static const float q[24] = {-3, -2, 4, 3, -2, 4, 3, 3, 4, -3, 3, 4, -3, -2, 6, 3, -2, 6, 3, 3, 6, -3, 3, 6};
        static const uint32_t idx[12] = {0, 1, 2, 0, 2, 3, 4, 5, 6, 4, 6, 7};
        size_t centre = (size_t)(im.height / 2) * im.width + im.width / 2;
        render_clear(&im, 0);
        render_triangles(&im, &view, q, idx, 0, 2, RENDER_RGBA(255, 0, 0, 255), RENDER_UNLIT);
        render_triangles(&im, &view, q, idx, 2, 2, RENDER_RGBA(0, 255, 0, 255), RENDER_UNLIT);
        CHECK(im.rgba[4 * centre] == 255 && im.rgba[4 * centre + 1] == 0);
        render_clear(&im, 0);
        render_triangles(&im, &view, q, idx, 2, 2, RENDER_RGBA(0, 255, 0, 255), RENDER_UNLIT);
        render_triangles(&im, &view, q, idx, 0, 2, RENDER_RGBA(255, 0, 0, 255), RENDER_UNLIT);
        CHECK(im.rgba[4 * centre] == 255 && im.rgba[4 * centre + 1] == 0);
        /* blending and the X-ray composite */
        render_fill_rect(&im, 0, 0, 0, 0, RENDER_RGBA(0, 0, 255, 128));
        CHECK(im.rgba[2] == 128 || im.rgba[2] == 127);
    }
    CHECK(render_heat(0.0f) != render_heat(1.0f));
    render_image_free(&im);
}

/* ---- pvsbake: resume after SIGKILL, statistics, options ---- */

/* Starts pvsbake (otree, one thread, a record flushed per cell) writing `out`, and kills it (SIGKILL,
   no chance to clean up) once its state journal holds more than `bytes` bytes. Returns 1 when the
   bake was killed before finishing. */
static int ex_bake_and_kill(const char *out, long bytes) {
    char state[256];
    pid_t pid;
    int status = 0, waited = 0;
    snprintf(state, sizeof(state), "%s.state", out);
    pid = fork();
    if (pid == 0) {
        execl("./pvsbake", "pvsbake", EDIR "/in.obj", "--cells", EDIR "/in.txt", "--method", "otree", "-q", "-j", "1", "--state-every", "1", "-o",
              out, (char *)NULL);
        _exit(127);
    }
    if (pid <= 0) return 0;
    for (;;) {
        struct timespec ts = {0, 1000000};
        struct stat st;
        if ((stat(state, &st) == 0 && st.st_size > bytes) || waited++ > 60000) break;
        nanosleep(&ts, NULL);
    }
    kill(pid, SIGKILL);
    waitpid(pid, &status, 0);
    return WIFSIGNALED(status) && WTERMSIG(status) == SIGKILL && !test_exists(out) && test_exists(state);
}

static void test_resume(void) {
    char *out, *st = NULL;
    size_t n = 0, whole = 0;
    const char *bake = "./pvsbake " EDIR "/in.obj --cells " EDIR "/in.txt --method otree";
    char cmd[1024];
    CHECK(ex_run("./pvsgen indoor --seed 4 -o " EDIR "/in.obj --cells " EDIR "/in.txt", &out) == 0); free(out);
    snprintf(cmd, sizeof(cmd), "%s -q --no-state -j 1 -o " EDIR "/whole.pvs", bake);
    CHECK(ex_run(cmd, &out) == 0); free(out);
    free(test_slurp(EDIR "/whole.pvs", &whole));
    /* a bake killed once its journal holds a few cells */
    CHECK(ex_bake_and_kill(EDIR "/resumed.pvs", 400));
    st = test_slurp(EDIR "/resumed.pvs.state", &n);
    /* rerun (another thread count: the fingerprint ignores -j): continues, same bytes */
    snprintf(cmd, sizeof(cmd), "%s -j 2 --state-every 2 -o " EDIR "/resumed.pvs", bake);
    CHECK(ex_run(cmd, &out) == 0);
    CHECK(strstr(out, "resumed") != NULL && !strstr(out, "damaged"));
    CHECK(strstr(out, "mean PVS") && strstr(out, "culled") && strstr(out, "slowest cells") && strstr(out, "time per cell"));
    free(out);
    CHECK(test_same_files(EDIR "/whole.pvs", EDIR "/resumed.pvs"));
    CHECK(!test_exists(EDIR "/resumed.pvs.state")); /* removed once the output is written */
    /* a torn journal (a write cut short at any byte): the whole records before the cut are used,
       the rest is baked again, the same bytes */
    if (st && n > 120) {
        size_t cuts[5], c;
        cuts[0] = 32;          /* the header alone */
        cuts[1] = 33;          /* a record's first byte */
        cuts[2] = n - 1;       /* the last record one byte short */
        cuts[3] = n / 2;       /* anywhere */
        cuts[4] = 32 + (n - 32) / 3;
        for (c = 0; c < 5; ++c) {
            FILE *f = fopen(EDIR "/torn.pvs.state", "wb");
            if (f) { fwrite(st, 1, cuts[c], f); fclose(f); }
            snprintf(cmd, sizeof(cmd), "%s -j 2 -o " EDIR "/torn.pvs", bake);
            CHECK(ex_run(cmd, &out) == 0);
            CHECK(!strstr(out, "not this bake's state"));
            CHECK(c == 0 ? !strstr(out, "damaged") : strstr(out, "damaged") != NULL);
            CHECK(c < 2 ? !strstr(out, "resumed") : strstr(out, "resumed") != NULL);
            free(out);
            CHECK(test_same_files(EDIR "/whole.pvs", EDIR "/torn.pvs"));
        }
        /* a flipped bit in the last record: the CRC catches it; the records before it are used */
        {
            FILE *f = fopen(EDIR "/torn.pvs.state", "wb");
            st[n - 6] ^= 0x10;
            if (f) { fwrite(st, 1, n, f); fclose(f); }
            snprintf(cmd, sizeof(cmd), "%s -j 1 -o " EDIR "/torn.pvs", bake);
            CHECK(ex_run(cmd, &out) == 0 && strstr(out, "damaged") && strstr(out, "resumed")); free(out);
            CHECK(test_same_files(EDIR "/whole.pvs", EDIR "/torn.pvs"));
            st[n - 6] ^= 0x10;
        }
        /* the journal's size is of the order of the file's: a record per cell, its PVS as runs */
        {
            uint32_t cells = 0, records = 0;
            size_t at = 32;
            char *txt = test_slurp(EDIR "/in.txt", NULL), *q;
            for (q = txt; q && *q; ++q) cells += *q == '\n';
            free(txt);
            while (at + 12 <= n) {
                const unsigned char *r = (const unsigned char *)st + at;
                size_t p = (size_t)r[4] | (size_t)r[5] << 8 | (size_t)r[6] << 16 | (size_t)r[7] << 24;
                if (at + 12 + p > n) break;
                at += 12 + p;
                ++records;
            }
            CHECK(cells > 100 && records >= 4 && at == n);
            if (!(cells > 100 && records >= 4 && at == n)) fprintf(stderr, "journal: %u cells, %u records, %zu of %zu bytes\n", cells, records, at, n);
            CHECK((double)(n - 32) / records < 4.0 * (double)whole / cells);
        }
        /* a damaged header is not this bake's state: ignored, with a warning */
        {
            FILE *f = fopen(EDIR "/torn.pvs.state", "wb");
            st[20] ^= 0x01;
            if (f) { fwrite(st, 1, n, f); fclose(f); }
            snprintf(cmd, sizeof(cmd), "%s -j 1 -o " EDIR "/torn.pvs", bake);
            CHECK(ex_run(cmd, &out) == 0 && strstr(out, "not this bake's state") && !strstr(out, "resumed")); free(out);
            CHECK(test_same_files(EDIR "/whole.pvs", EDIR "/torn.pvs"));
        }
    } else {
        CHECK(0);
    }
    free(st);
    /* a state file of another bake (other options) is ignored, with a warning */
    CHECK(ex_bake_and_kill(EDIR "/other.pvs", 100));
    snprintf(cmd, sizeof(cmd), "%s -j 2 --max-distance 20 -o " EDIR "/other.pvs", bake);
    CHECK(ex_run(cmd, &out) == 0 && strstr(out, "not this bake's state") && !strstr(out, "resumed")); free(out);
    snprintf(cmd, sizeof(cmd), "%s -q --no-state -j 1 --max-distance 20 -o " EDIR "/fresh.pvs", bake);
    CHECK(ex_run(cmd, &out) == 0); free(out);
    CHECK(test_same_files(EDIR "/fresh.pvs", EDIR "/other.pvs"));
    CHECK(!test_same_files(EDIR "/whole.pvs", EDIR "/other.pvs")); /* the distance did cut */
}

static void test_bake_options(void) {
    char *out;
    const char *base = "./pvsbake -q " EDIR "/in.obj --cells " EDIR "/in.txt -o " EDIR "/opt.pvs";
    char cmd[1024];
    snprintf(cmd, sizeof(cmd), "%s --method otree,sample", base);
    CHECK(ex_run(cmd, &out) == 2 && strstr(out, "unknown method")); free(out);
    snprintf(cmd, sizeof(cmd), "%s --method otree,", base);
    CHECK(ex_run(cmd, &out) == 2); free(out);
    snprintf(cmd, sizeof(cmd), "%s --max-distance -3", base);
    CHECK(ex_run(cmd, &out) == 2); free(out);
    snprintf(cmd, sizeof(cmd), "%s --max-distance nan", base);
    CHECK(ex_run(cmd, &out) == 2); free(out);
    snprintf(cmd, sizeof(cmd), "%s --state-every 0", base);
    CHECK(ex_run(cmd, &out) == 2); free(out);
    snprintf(cmd, sizeof(cmd), "%s --state x --no-state", base);
    CHECK(ex_run(cmd, &out) == 2); free(out);
    /* a list: auto over those methods; the summary names each with its contribution */
    /* view cells from walkable space: baked, written beside the file, checked (0 misses); misuse refused */
    CHECK(ex_run("./pvsbake " EDIR "/in.obj --cells walkable:4 -o " EDIR "/walk.pvs -j 2 --method portal", &out) == 0 &&
          strstr(out, "walkable: ") && strstr(out, "walk.walkable.cells"));
    free(out);
    CHECK(test_exists(EDIR "/walk.walkable.cells"));
    /* pvscheck here with 8 aimed rays per unseen object (default 32): these check the options' plumbing; the methods'
       own groups check conservativeness with dense rays */
    CHECK(ex_run("./pvscheck -q " EDIR "/in.obj " EDIR "/walk.pvs --points 8 --rays 512 --aim 8", &out) == 0 && strstr(out, "misses 0")); free(out);
    CHECK(ex_run("./pvsbake " EDIR "/in.obj --cells walkable:0 -o " EDIR "/w2.pvs", &out) == 2 && strstr(out, "walkable:SIZE")); free(out);
    CHECK(ex_run("./pvsbake " EDIR "/in.obj --cells walkable --step-height 0 -o " EDIR "/w2.pvs", &out) == 2 &&
          strstr(out, "--step-height needs a positive height"));
    free(out);
    CHECK(ex_run("./pvsbake " EDIR "/in.obj --cells walkable --volumes " EDIR "/none.cells -o " EDIR "/w2.pvs", &out) == 1 &&
          strstr(out, "none.cells"));
    free(out);
    CHECK(ex_run("./pvsbake " EDIR "/in.obj --cells walkable --walk-from 1,2 -o " EDIR "/w2.pvs", &out) == 2 && strstr(out, "X,Y,Z"));
    free(out);
    CHECK(ex_run("./pvsbake " EDIR "/in.obj --cells " EDIR "/in.txt --eye-height 2 -o " EDIR "/w2.pvs", &out) == 2 &&
          strstr(out, "need --cells walkable"));
    free(out);
    CHECK(ex_run("./pvsbake " EDIR "/in.obj --cells walkable --walk-from 0,-1e6,0 -o " EDIR "/w2.pvs", &out) == 1 &&
          strstr(out, "no floor with head room"));
    free(out);
    CHECK(!test_exists(EDIR "/w2.pvs"));
    CHECK(ex_run("./pvsbake " EDIR "/in.obj --cells " EDIR "/in.txt -o " EDIR "/opt.pvs -j 2 --method otree,extproj --no-sweep "
                 "--resolution 64", &out) == 0); /* extproj's cheapest: the named set is what is tested */
    CHECK(strstr(out, "method auto") && strstr(out, "otree    ran") && strstr(out, "extproj  ran") && strstr(out, "alone culled") &&
          !strstr(out, "shrink"));
    free(out);
    CHECK(ex_run("./pvsinfo " EDIR "/opt.pvs", &out) == 0 && strstr(out, "auto")); free(out);
    CHECK(ex_run("./pvscheck -q " EDIR "/in.obj " EDIR "/opt.pvs --points 8 --rays 512 --aim 8", &out) == 0 && strstr(out, "misses 0")); free(out);
    /* the default is auto; preview runs one method and is still conservative */
    CHECK(ex_run("./pvsbake " EDIR "/in.obj --cells " EDIR "/in.txt -o " EDIR "/pre.pvs -j 2 --preview", &out) == 0);
    CHECK(strstr(out, "method auto") && strstr(out, "preview runs only"));
    free(out);
    CHECK(ex_run("./pvscheck -q " EDIR "/in.obj " EDIR "/pre.pvs --points 8 --rays 512 --aim 8", &out) == 0 && strstr(out, "misses 0")); free(out);
    /* max distance: pvscheck counts only objects within the distance */
    CHECK(ex_run("./pvsbake -q " EDIR "/in.obj --cells " EDIR "/in.txt -o " EDIR "/far.pvs -j 2 --method otree --max-distance 15", &out) == 0);
    free(out);
    CHECK(ex_run("./pvscheck -q " EDIR "/in.obj " EDIR "/far.pvs --points 8 --rays 512 --aim 8 --max-distance 15", &out) == 0 && strstr(out, "misses 0"));
    free(out);
    CHECK(ex_run("./pvscheck -q " EDIR "/in.obj " EDIR "/far.pvs --points 8 --rays 512 --aim 8", &out) == 3); free(out);
}

/* ---- pvsview and the runtime example ---- */

static void test_view_runtime(void) {
    char *out, *png;
    size_t n = 0;
    CHECK(ex_run("./pvsview " EDIR "/in.obj " EDIR "/whole.pvs -o " EDIR "/v.png --size 300 --cell 5 --frame 10 1.2 10 1 0 0.2", &out) != 2);
    free(out);
    /* a point inside a cell of the file for the frame: the centre of cell 7 */
    {
        pvs_file f;
        size_t sz = 0;
        char *bytes = test_slurp(EDIR "/whole.pvs", &sz), cmd[512];
        if (bytes && pvs_file_open(bytes, sz, &f, NULL) == PVS_OK) {
            pvs_box b = pvs_file_cell_box(&f, 7);
            snprintf(cmd, sizeof(cmd), "./pvsview " EDIR "/in.obj " EDIR "/whole.pvs -o " EDIR "/v.png --size 300 --cell 7 --frame %g %g %g 1 0 0.3",
                     0.5 * (b.min[0] + b.max[0]), 0.5 * (b.min[1] + b.max[1]), 0.5 * (b.min[2] + b.max[2]));
            CHECK(ex_run(cmd, &out) == 0 && strstr(out, "0 pixels of objects outside the PVS") && strstr(out, "cell 7")); free(out);
            png = test_slurp(EDIR "/v.png", &n);
            CHECK(png && n > 100 && memcmp(png, "\x89PNG", 4) == 0);
            free(png);
            /* a PVS that misses: the same cells, every set empty: the frame shows red pixels, exit 3 */
            {
                uint32_t c, words = (uint32_t)PVS_BITSET_WORDS(f.object_count);
                pvs_box *boxes = (pvs_box *)malloc(f.cell_count * sizeof(pvs_box));
                pvs_word *table = (pvs_word *)calloc((size_t)f.cell_count * words, sizeof(pvs_word));
                pvs_file_desc d;
                size_t need = 0;
                void *enc = NULL;
                for (c = 0; c < f.cell_count; ++c) boxes[c] = pvs_file_cell_box(&f, c);
                memset(&d, 0, sizeof(d));
                d.cells = boxes;
                d.cell_count = f.cell_count;
                d.object_count = f.object_count;
                d.pvs = table;
                d.method = PVS_METHOD_OTREE;
                d.up_axis = 1;
                CHECK(pvs_file_encode(&d, NULL, 0, &need, NULL) == PVS_OK && (enc = malloc(need)) != NULL &&
                      pvs_file_encode(&d, enc, need, &need, NULL) == PVS_OK);
                if (enc) {
                    FILE *fo = fopen(EDIR "/empty.pvs", "wb");
                    if (fo) { fwrite(enc, 1, need, fo); fclose(fo); }
                }
                snprintf(cmd, sizeof(cmd), "./pvsview " EDIR "/in.obj " EDIR "/empty.pvs -o " EDIR "/e.png --size 200 --frame %g %g %g 1 0 0.3",
                         0.5 * (b.min[0] + b.max[0]), 0.5 * (b.min[1] + b.max[1]), 0.5 * (b.min[2] + b.max[2]));
                CHECK(ex_run(cmd, &out) == 3 && !strstr(out, " 0 pixels of objects outside")); free(out);
                free(enc);
                free(boxes);
                free(table);
            }
        } else {
            CHECK(0);
        }
        free(bytes);
    }
    /* occluder-only objects block the frame but are never red; see-through ones block nothing: a quad 'a' behind
       a see-through pane, both behind an occluder wall that hides them from the cell: 0 red pixels */
    {
        FILE *fo = fopen(EDIR "/occ.obj", "w");
        if (fo) {
            fputs("o a\nv 10 0 -1\nv 10 0 1\nv 10 2 1\nv 10 2 -1\nf 1 2 3 4\n"
                  "o glass_pane\nv 8 -1 -2\nv 8 -1 2\nv 8 3 2\nv 8 3 -2\nf 5 6 7 8\n"
                  "o occluder_wall\nv 5 -9 -9\nv 5 -9 9\nv 5 9 9\nv 5 9 -9\nf 9 10 11 12\n", fo);
            fclose(fo);
        }
        fo = fopen(EDIR "/occ.txt", "w");
        if (fo) {
            fputs("-0.5 0.5 -0.5 0.5 1.5 0.5\n", fo);
            fclose(fo);
        }
        CHECK(ex_run("./pvsbake -q " EDIR "/occ.obj --cells " EDIR "/occ.txt -o " EDIR "/occ.pvs --method otree", &out) == 0);
        free(out);
        CHECK(ex_run("./pvsview " EDIR "/occ.obj " EDIR "/occ.pvs -o " EDIR "/o.png --size 200 --frame 0 1 0 1 0 0", &out) == 0 &&
              strstr(out, " 0 pixels of objects outside")); free(out);
        /* the wall behind them and a PVS keeping nothing: the pane and 'a' show red, exit 3 */
        fo = fopen(EDIR "/occ2.obj", "w");
        if (fo) {
            fputs("o a\nv 10 0 -1\nv 10 0 1\nv 10 2 1\nv 10 2 -1\nf 1 2 3 4\n"
                  "o glass_pane\nv 8 -1 -2\nv 8 -1 2\nv 8 3 2\nv 8 3 -2\nf 5 6 7 8\n"
                  "o occluder_wall\nv 12 -9 -9\nv 12 -9 9\nv 12 9 9\nv 12 9 -9\nf 9 10 11 12\n", fo);
            fclose(fo);
        }
        {
            pvs_box cell = {{-0.5f, 0.5f, -0.5f}, {0.5f, 1.5f, 0.5f}};
            pvs_word none = 0;
            pvs_file_desc d;
            size_t need = 0;
            void *enc = NULL;
            memset(&d, 0, sizeof(d));
            d.cells = &cell;
            d.cell_count = 1;
            d.object_count = 3;
            d.pvs = &none;
            d.method = PVS_METHOD_OTREE;
            d.up_axis = 1;
            CHECK(pvs_file_encode(&d, NULL, 0, &need, NULL) == PVS_OK && (enc = malloc(need)) != NULL &&
                  pvs_file_encode(&d, enc, need, &need, NULL) == PVS_OK);
            if (enc && (fo = fopen(EDIR "/occ2.pvs", "wb")) != NULL) {
                fwrite(enc, 1, need, fo);
                fclose(fo);
            }
            free(enc);
        }
        CHECK(ex_run("./pvsview " EDIR "/occ2.obj " EDIR "/occ2.pvs -o " EDIR "/o.png --size 200 --frame 0 1 0 1 0 0", &out) == 3 &&
              !strstr(out, " 0 pixels of objects outside")); free(out);
    }
    CHECK(ex_run("./pvsview " EDIR "/in.obj " EDIR "/whole.pvs", &out) == 2); free(out);
    CHECK(ex_run("./pvsview " EDIR "/in.obj " EDIR "/whole.pvs -o " EDIR "/v.png --cell 99999", &out) == 1 && strstr(out, "cells")); free(out);
    CHECK(ex_run("./pvsview " EDIR "/in.obj " EDIR "/whole.pvs -o " EDIR "/v.png --cell-at 1e6 0 0", &out) == 1 && strstr(out, "no cell")); free(out);
    CHECK(ex_run("./pvsview " EDIR "/in.obj " EDIR "/whole.pvs -o " EDIR "/v.png --frame 1 2 3", &out) == 2); free(out);
    CHECK(ex_run("./pvsgen walls --size 0.2 -o " EDIR "/w.obj --cells " EDIR "/w.txt", &out) == 0); free(out);
    CHECK(ex_run("./pvsview " EDIR "/w.obj " EDIR "/whole.pvs -o " EDIR "/v.png", &out) == 1 && strstr(out, "not the same scene")); free(out);
    /* the runtime example: a memory buffer, a cursor walk, no allocation */
    CHECK(ex_run("./pvsruntime " EDIR "/whole.pvs 3000", &out) == 0 && strstr(out, "allocations     0") && strstr(out, "equal the decoded PVS of the last cell: yes"));
    free(out);
    CHECK(ex_run("./pvsruntime " EDIR "/in.obj", &out) == 1 && strstr(out, "bad magic")); free(out);
    /* the door recipe: baked open (see-through), culled per frame when closed; its OBJ, read back by the
       naming rule (door..., glass...), bakes a PVS with 0 misses against pvscheck's see-through rays */
    CHECK(ex_run("./pvsdoor -o " EDIR, &out) == 0 && strstr(out, "door closed: statue culled, plant drawn") &&
          strstr(out, "door open:   statue drawn") && strstr(out, "glass_window statue plant\n"));
    free(out);
    CHECK(test_exists(EDIR "/door.png"));
    CHECK(ex_run("./pvsbake -q " EDIR "/door.obj --cells " EDIR "/door.cells -o " EDIR "/door.pvs", &out) == 0); free(out);
    CHECK(ex_run("./pvscheck -q " EDIR "/door.obj " EDIR "/door.pvs", &out) == 0 && strstr(out, "misses 0")); free(out);
}

void test_examples(void) {
    test_renderer();
    if (system("rm -rf " EDIR " && mkdir -p " EDIR) != 0) { CHECK(0); return; }
    test_resume();
    test_bake_options();
    test_view_runtime();
    if (!getenv("PVSTEST_KEEP") && system("rm -rf " EDIR) != 0) CHECK(0);
}
