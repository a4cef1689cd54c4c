/* test_tools.c - tests for the tools' helpers: OBJ and cells loaders (tools/obj.h) and
   tools/toolutil.h (files, progress, parallel_for, option parsing, PNG, font). */
#define _POSIX_C_SOURCE 200809L
#include "test.h"
#include "../tools/obj.h"
#include "../tools/toolutil.h"
#include <dirent.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

/* ---- helpers --------------------------------------------------------------------------------- */

static int tt_has(const char *s, const char *phrase) { return strstr(s, phrase) != NULL; }

/* Parses text (length len, may hold NULs) as OBJ named "t.obj"; expects failure at `line` (0 = file
   level) with a message "t.obj:LINE: ..." containing phrase. */
static int tt_obj_fails_n(const char *text, size_t len, int line, const char *phrase) {
    mesh m;
    tool_error err;
    memset(&err, 0, sizeof(err));
    int r = obj_parse("t.obj", text, len, &m, &err);
    char prefix[64];
    if (line > 0) snprintf(prefix, sizeof(prefix), "t.obj:%d: ", line);
    else snprintf(prefix, sizeof(prefix), "t.obj: ");
    int ok = r == -1 && err.line == line && strncmp(err.message, prefix, strlen(prefix)) == 0 &&
             tt_has(err.message, phrase) && m.object_count == 0 && m.positions == NULL;
    if (!ok) fprintf(stderr, "  obj case: r=%d line=%d msg='%s' want line %d '%s'\n", r, err.line, err.message, line, phrase);
    if (r == 0) mesh_free(&m);
    return ok;
}
static int tt_obj_fails(const char *text, int line, const char *phrase) {
    return tt_obj_fails_n(text, strlen(text), line, phrase);
}

static int tt_cells_fails_n(const char *text, size_t len, int line, const char *phrase) {
    mesh_cells c;
    tool_error err;
    memset(&err, 0, sizeof(err));
    int r = cells_parse("c.txt", text, len, &c, &err);
    char prefix[64];
    if (line > 0) snprintf(prefix, sizeof(prefix), "c.txt:%d: ", line);
    else snprintf(prefix, sizeof(prefix), "c.txt: ");
    int ok = r == -1 && err.line == line && strncmp(err.message, prefix, strlen(prefix)) == 0 &&
             tt_has(err.message, phrase) && c.count == 0 && c.boxes == NULL;
    if (!ok) fprintf(stderr, "  cells case: r=%d line=%d msg='%s' want line %d '%s'\n", r, err.line, err.message, line, phrase);
    if (r == 0) mesh_cells_free(&c);
    return ok;
}
static int tt_cells_fails(const char *text, int line, const char *phrase) {
    return tt_cells_fails_n(text, strlen(text), line, phrase);
}

/* a == b as floats: a constant such as 0.001f may be held wider where FLT_EVAL_METHOD != 0 (x87, s390x); a
   parameter is rounded to float */
static int tt_feq(float a, float b) { return a == b; }

static int tt_obj_ok(const char *text, mesh *m) {
    tool_error err;
    memset(&err, 0, sizeof(err));
    int r = obj_parse("t.obj", text, strlen(text), m, &err);
    if (r) fprintf(stderr, "  unexpected OBJ error: %s\n", err.message);
    return r == 0;
}

static int tt_tri(const mesh *m, uint32_t t, uint32_t a, uint32_t b, uint32_t c) {
    if (t >= m->triangle_count) return 0;
    const uint32_t *v = m->indices + 3 * (size_t)t;
    return v[0] == a && v[1] == b && v[2] == c;
}

/* Counts directory entries whose name contains ".tmp." */
static int tt_temp_files(const char *dir) {
    DIR *d = opendir(dir);
    int n = 0;
    if (!d) return -1;
    struct dirent *e;
    while ((e = readdir(d)) != NULL)
        if (strstr(e->d_name, ".tmp.")) ++n;
    closedir(d);
    return n;
}

/* ---- OBJ: accepted forms --------------------------------------------------------------------- */

static void tt_obj_accepts(void) {
    mesh m;

    /* Minimal file: faces before any o/g form object 0 "default". */
    CHECK(tt_obj_ok("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", &m));
    CHECK(m.vertex_count == 3 && m.triangle_count == 1 && m.object_count == 1);
    CHECK(m.object_count == 1 && strcmp(m.objects[0].name, "default") == 0 && m.objects[0].flags == 0);
    CHECK(m.object_count == 1 && m.objects[0].line == 4);
    CHECK(tt_tri(&m, 0, 0, 1, 2));
    CHECK(m.positions[3] == 1.0f && m.positions[7] == 1.0f);
    mesh_free(&m);

    /* v/vt/vn, v//vn, v/vt forms, mixed; vt/vn lines ignored. */
    CHECK(tt_obj_ok("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nvt 0 0\nvt 1 0\nvn 0 0 1\n"
                    "f 1/1/1 2/2/1 3/1/1\nf 2//1 4//1 3//1\nf 1/1 2/2 4/1\n", &m));
    CHECK(m.triangle_count == 3 && tt_tri(&m, 0, 0, 1, 2) && tt_tri(&m, 1, 1, 3, 2) && tt_tri(&m, 2, 0, 1, 3));
    mesh_free(&m);

    /* Negative (relative) indices: -1 is the latest vertex defined so far. */
    CHECK(tt_obj_ok("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf -4 -3 -2 -1\nv 5 5 5\nf -1/-1/-1 -2 -3\n", &m));
    CHECK(m.triangle_count == 3 && tt_tri(&m, 0, 0, 1, 2) && tt_tri(&m, 1, 0, 2, 3) && tt_tri(&m, 2, 4, 3, 2));
    mesh_free(&m);

    /* Polygon fan triangulation. */
    CHECK(tt_obj_ok("v 0 0 0\nv 1 0 0\nv 2 1 0\nv 1 2 0\nv 0 1 0\nf 1 2 3 4 5\n", &m));
    CHECK(m.triangle_count == 3 && tt_tri(&m, 0, 0, 1, 2) && tt_tri(&m, 1, 0, 2, 3) && tt_tri(&m, 2, 0, 3, 4));
    mesh_free(&m);

    /* g without any o: each g starts an object; g without a name is "default". */
    CHECK(tt_obj_ok("v 0 0 0\nv 1 0 0\nv 0 1 0\ng first\nf 1 2 3\ng  second part \nf 1 2 3\nf 3 2 1\ng\nf 1 2 3\n", &m));
    CHECK(m.object_count == 3);
    if (m.object_count == 3) {
        CHECK(strcmp(m.objects[0].name, "first") == 0 && m.objects[0].triangle_count == 1 && m.objects[0].line == 4);
        CHECK(strcmp(m.objects[1].name, "second part") == 0 && m.objects[1].triangle_count == 2);
        CHECK(m.objects[1].first_triangle == 1 && m.objects[1].line == 6);
        CHECK(strcmp(m.objects[2].name, "default") == 0 && m.objects[2].first_triangle == 3);
    }
    mesh_free(&m);

    /* o present: g lines are ignored; faces before the first o form object 0. */
    CHECK(tt_obj_ok("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\ng grp\nf 1 2 3\no a\ng x\nf 1 2 3\ng y\nf 2 3 1\no b\nf 1 2 3\n", &m));
    CHECK(m.object_count == 3);
    if (m.object_count == 3) {
        CHECK(strcmp(m.objects[0].name, "default") == 0 && m.objects[0].triangle_count == 2);
        CHECK(strcmp(m.objects[1].name, "a") == 0 && m.objects[1].triangle_count == 2 && m.objects[1].line == 7);
        CHECK(strcmp(m.objects[2].name, "b") == 0 && m.objects[2].triangle_count == 1 && m.objects[2].first_triangle == 4);
    }
    mesh_free(&m);

    /* An o line anywhere in the file (even after the g lines) makes every g ignored. */
    CHECK(tt_obj_ok("v 0 0 0\nv 1 0 0\nv 0 1 0\ng g1\nf 1 2 3\no late\nf 1 2 3\n", &m));
    CHECK(m.object_count == 2 && strcmp(m.objects[0].name, "default") == 0 && strcmp(m.objects[1].name, "late") == 0);
    mesh_free(&m);

    /* CRLF line ends, BOM, comments, blank lines, ignored statements, 4- and 6-number vertices. */
    CHECK(tt_obj_ok("\xEF\xBB\xBF# exported\r\nmtllib a.mtl\r\n\r\no  wall \r\nv 0 0 0 1\r\nv 1 0 0 0.5 0.5 0.5\r\n"
                    "v 0 1 0 # comment\r\nvp 0.5\r\nusemtl red\r\ns off\r\nl 1 2\r\np 1\r\n\tf 1 2 3 # tri\r\n"
                    "o occluder_box\r\nf 3 2 1\r\no wall_occluder\r\nf 1 3 2\r\no Occluder\r\nf 1 2 3\r\n", &m));
    CHECK(m.vertex_count == 3 && m.triangle_count == 4 && m.object_count == 4);
    if (m.object_count == 4) {
        CHECK(strcmp(m.objects[0].name, "wall") == 0 && m.objects[0].flags == 0 && m.objects[0].line == 4);
        CHECK(strcmp(m.objects[1].name, "occluder_box") == 0 && m.objects[1].flags == MESH_OBJECT_OCCLUDER);
        CHECK(strcmp(m.objects[2].name, "wall_occluder") == 0 && m.objects[2].flags == 0);
        CHECK(strcmp(m.objects[3].name, "Occluder") == 0 && m.objects[3].flags == 0);
    }
    CHECK(m.positions[3] == 1.0f && m.positions[4] == 0.0f && m.positions[7] == 1.0f);
    mesh_free(&m);
    /* the see-through naming rule: a prefix, case as written */
    CHECK(tt_obj_ok("v 0 0 0\nv 1 0 0\nv 0 1 0\no glass_front\nf 1 2 3\no door3\nf 1 2 3\no see_through\nf 1 2 3\n"
                    "o Glass\nf 1 2 3\no the_door\nf 1 2 3\n", &m));
    CHECK(m.object_count == 5);
    if (m.object_count == 5) {
        CHECK(m.objects[0].flags == MESH_OBJECT_SEE_THROUGH && m.objects[1].flags == MESH_OBJECT_SEE_THROUGH);
        CHECK(m.objects[2].flags == MESH_OBJECT_SEE_THROUGH && m.objects[3].flags == 0 && m.objects[4].flags == 0);
    }
    mesh_free(&m);
    /* and the one-sided one (pvsimport --shaders): drawn front only */
    CHECK(tt_obj_ok("v 0 0 0\nv 1 0 0\nv 0 1 0\no one_sided_s7\nf 1 2 3\no One_sided\nf 1 2 3\n", &m));
    CHECK(m.object_count == 2 && m.objects[0].flags == MESH_OBJECT_ONE_SIDED && m.objects[1].flags == 0);
    mesh_free(&m);

    /* CR line ends (old Mac files) read as lines, mixed with LF and CRLF; lines are counted the
       same way for errors, in OBJ and cells files. */
    CHECK(tt_obj_ok("# mac\ro wall\rv 0 0 0\rv 1 0 0\r\nv 0 1 0\nf 1 2 3\ro two\r\rf 3 2 1\r", &m));
    CHECK(m.vertex_count == 3 && m.triangle_count == 2 && m.object_count == 2);
    if (m.object_count == 2) CHECK(m.objects[0].line == 2 && m.objects[1].line == 7 && strcmp(m.objects[1].name, "two") == 0);
    mesh_free(&m);
    CHECK(tt_obj_fails("v 0 0 0\rv 1 0 0\rv 0 1 0\rf 1 2 9\r", 4, "face index 9 out of range"));
    CHECK(tt_obj_fails("v 0 0 0\r\rv 1 x 0\r", 3, "bad number"));
    CHECK(tt_cells_fails("# c\r0 0 0 1 1 1\r0 0 0 1 1\r", 3, "expected 6 numbers"));
    {
        mesh_cells c;
        tool_error err;
        CHECK(cells_parse("c.txt", "# c\r0 0 0 1 1 1\r\n2 2 2 3 3 3\r", 29, &c, &err) == 0 && c.count == 2 && mesh_cells_line(&c, 1) == 3);
        mesh_cells_free(&c);
    }

    /* Exact-enough numbers: signs, exponents, leading dot, trailing dot, huge/tiny exponents. */
    CHECK(tt_obj_ok("v -1.5 +2.25e1 .5\nv 3. 1E-3 -0\nv 1e-50 0.1 123456789\nf 1 2 3\n", &m));
    CHECK(m.positions[0] == -1.5f && m.positions[1] == 22.5f && m.positions[2] == 0.5f);
    CHECK(m.positions[3] == 3.0f && tt_feq(m.positions[4], 0.001f) && m.positions[5] == 0.0f);
    CHECK(m.positions[6] == 0.0f && tt_feq(m.positions[7], 0.1f) && tt_feq(m.positions[8], 123456789.0f));
    mesh_free(&m);

    /* Degenerate faces are kept; no trailing newline. */
    CHECK(tt_obj_ok("v 0 0 0\nv 1 0 0\nf 1 1 2\nf 2 2 2", &m));
    CHECK(m.triangle_count == 2 && tt_tri(&m, 0, 0, 0, 1) && tt_tri(&m, 1, 1, 1, 1));
    mesh_free(&m);

    /* Empty objects are kept (ids follow the file) and reported by obj_check_empty_objects. */
    CHECK(tt_obj_ok("v 0 0 0\nv 1 0 0\nv 0 1 0\no empty1\no full\nf 1 2 3\no\no empty3\n", &m));
    CHECK(m.object_count == 4);
    if (m.object_count == 4) {
        CHECK(strcmp(m.objects[0].name, "empty1") == 0 && m.objects[0].triangle_count == 0);
        CHECK(strcmp(m.objects[1].name, "full") == 0 && m.objects[1].triangle_count == 1);
        CHECK(strcmp(m.objects[2].name, "unnamed") == 0 && m.objects[2].line == 7);
        tool_error warn;
        CHECK(obj_check_empty_objects("t.obj", &m, &warn) == 3);
        CHECK(warn.line == 4 && strcmp(warn.message, "t.obj:4: object 0 'empty1' has no faces") == 0);
        CHECK(obj_check_empty_objects("t.obj", &m, NULL) == 3);
    }
    mesh_free(&m);
    CHECK(tt_obj_ok("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", &m));
    CHECK(obj_check_empty_objects("t.obj", &m, NULL) == 0);
    mesh_free(&m);

    /* Not NUL-terminated input: parsing stops at len. */
    {
        const char text[] = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 2 99";
        tool_error err;
        CHECK(obj_parse("t.obj", text, sizeof(text) - 1 - 8, &m, &err) == 0 && m.triangle_count == 1);
        mesh_free(&m);
        const char text2[] = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 37";
        CHECK(obj_parse("t.obj", text2, sizeof(text2) - 2, &m, &err) == 0 && tt_tri(&m, 0, 0, 1, 2));
        mesh_free(&m);
    }
}

/* ---- OBJ: errors ----------------------------------------------------------------------------- */

static void tt_obj_errors(const char *dir) {
    mesh m;
    tool_error err;
    char path[512];

    /* File-level. */
    snprintf(path, sizeof(path), "%s/missing.obj", dir);
    CHECK(obj_load(path, &m, &err) == -1 && err.line == 0 && tt_has(err.message, "cannot open") &&
          strncmp(err.message, path, strlen(path)) == 0);
    CHECK(m.object_count == 0 && m.positions == NULL);
    CHECK(obj_load(dir, &m, &err) == -1 && err.line == 0 && tt_has(err.message, "cannot read"));
    CHECK(tt_obj_fails("", 0, "empty file"));
    CHECK(tt_obj_fails("v 1 2 3\nv 1 2 3\n# nothing else\n", 0, "no faces"));
    CHECK(tt_obj_fails("# only a comment\n\n", 0, "no faces"));
    CHECK(tt_obj_fails("o a\no b\n", 0, "no faces"));

    /* Binary data. */
    CHECK(tt_obj_fails_n("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1\0 2 3\n", 31, 4, "binary data at byte 27"));
    CHECK(tt_obj_fails("v 0 0 0\n\x01\x02\x03", 2, "binary data at byte 8"));
    CHECK(tt_obj_fails("\x7f" "ELF", 1, "binary data at byte 0"));

    /* Bad numbers and missing coordinates. */
    CHECK(tt_obj_fails("v 0 0 0\nv 1 x 3\n", 2, "bad number 'x'"));
    CHECK(tt_obj_fails("v 0 0 0\nv 1 2 3.5z\n", 2, "bad number '3.5z'"));
    CHECK(tt_obj_fails("v 1,5 2 3\n", 1, "bad number '1,5'"));
    CHECK(tt_obj_fails("v 1 2 3e\n", 1, "bad number '3e'"));
    CHECK(tt_obj_fails("v 1 2 .\n", 1, "bad number '.'"));
    CHECK(tt_obj_fails("v 1 2 0x10\n", 1, "bad number '0x10'"));
    CHECK(tt_obj_fails("v 1 2 --3\n", 1, "bad number '--3'"));
    CHECK(tt_obj_fails("v 1 2 3 abc\n", 1, "bad number 'abc'"));
    {   /* '#' ends a token: "3#x" is 3 and a comment */
        mesh m2;
        CHECK(tt_obj_ok("v 1 2 3#x\nv 0 0 0\nv 1 1 1\nf 1 2 3#x\n", &m2) && m2.positions[2] == 3.0f && m2.triangle_count == 1);
        mesh_free(&m2);
    }
    CHECK(tt_obj_fails("v\n", 1, "missing coordinates"));
    CHECK(tt_obj_fails("\n\nv 1 2\n", 3, "found 2"));
    CHECK(tt_obj_fails("v 1 2 # 3\n", 1, "missing coordinates"));

    /* Non-finite / overflowing coordinates. */
    CHECK(tt_obj_fails("v nan 0 0\n", 1, "coordinate is not finite"));
    CHECK(tt_obj_fails("v 0 -inf 0\n", 1, "coordinate is not finite"));
    CHECK(tt_obj_fails("v 0 0 Infinity\n", 1, "coordinate is not finite"));
    CHECK(tt_obj_fails("v 0 0 NaN(123)\n", 1, "coordinate is not finite"));
    CHECK(tt_obj_fails("v 0 0 0\nv 1.#INF 0 0\n", 2, "coordinate is not finite"));
    CHECK(tt_obj_fails("v 0 -1.#IND 0\n", 1, "coordinate is not finite"));
    CHECK(tt_obj_fails("v 0 0 1e39\n", 1, "out of range"));
    CHECK(tt_obj_fails("v 0 0 1e400\n", 1, "out of range"));
    CHECK(tt_obj_fails("v 0 0 infinite\n", 1, "bad number"));

    /* Faces. */
    static const char *v3 = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";
    char buf[512];
#define TT_F(face, line, phrase) (snprintf(buf, sizeof(buf), "%s%s\n", v3, face), tt_obj_fails(buf, line, phrase))
    CHECK(TT_F("f 1 2", 4, "fewer than 3 vertices"));
    CHECK(TT_F("f", 4, "fewer than 3 vertices (0)"));
    CHECK(TT_F("f 1 2 # 3", 4, "fewer than 3 vertices (2)"));
    CHECK(TT_F("f 1 0 2", 4, "face index 0"));
    CHECK(TT_F("f 1 -0 2", 4, "face index 0"));
    CHECK(TT_F("f /1 2 3", 4, "missing vertex index"));
    CHECK(TT_F("f 1 //2 3", 4, "missing vertex index"));
    CHECK(TT_F("f 1 2 4", 4, "face index 4 out of range (3 vertices defined so far)"));
    CHECK(TT_F("f 1 2 -4", 4, "face index -4 out of range"));
    CHECK(TT_F("f 1 2 99999999999999999999", 4, "too large"));
    CHECK(TT_F("f 1 2 4294967297", 4, "out of range"));
    CHECK(TT_F("f 1 2 x", 4, "bad face index 'x'"));
    CHECK(TT_F("f 1 2 3x", 4, "bad face index '3x'"));
    CHECK(TT_F("f 1 2 3/1/1/1", 4, "bad face index"));
    CHECK(TT_F("f 1 2 3/a", 4, "bad face index"));
    CHECK(TT_F("f 1 2 3.0", 4, "bad face index"));
#undef TT_F
    /* Indices count only vertices defined so far (OBJ semantics), even if more come later. */
    CHECK(tt_obj_fails("v 0 0 0\nv 1 0 0\nf 1 2 3\nv 0 1 0\n", 3, "out of range (2 vertices defined so far)"));
    CHECK(tt_obj_fails("f 1 2 3\n", 1, "out of range (0 vertices defined so far)"));
    CHECK(tt_obj_fails("f -1 -1 -1\n", 1, "face index -1 out of range"));
    /* CRLF line counting in errors. */
    CHECK(tt_obj_fails("v 0 0 0\r\nv 1 0 0\r\nv 0 1 0\r\n\r\nf 1 2 7\r\n", 5, "face index 7"));
}

/* ---- cells ----------------------------------------------------------------------------------- */

static void tt_cells(const char *dir) {
    mesh_cells c;
    tool_error err;
    const char *text = "# cells\n0 0 0 1 1 1\n\n  -1.5 2 3e0 -1 2 4 # flat in y, comment\r\n"
                       "1 1 1 2 2 2# no space before comment\n\t# indented comment\n";
    CHECK(cells_parse("c.txt", text, strlen(text), &c, &err) == 0);
    CHECK(c.count == 3);
    if (c.count == 3) {
        CHECK(c.boxes[0] == 0 && c.boxes[3] == 1);
        CHECK(c.boxes[6] == -1.5f && c.boxes[7] == 2 && c.boxes[8] == 3 && c.boxes[9] == -1 && c.boxes[10] == 2 &&
              c.boxes[11] == 4);
        CHECK(c.boxes[17] == 2);
    }
    mesh_cells_free(&c);

    char path[512];
    snprintf(path, sizeof(path), "%s/cells.txt", dir);
    CHECK(write_file_atomic(path, "0 0 0 1 1 1\n", 12, &err) == 0);
    CHECK(cells_load(path, &c, &err) == 0 && c.count == 1);
    mesh_cells_free(&c);
    snprintf(path, sizeof(path), "%s/nocells.txt", dir);
    CHECK(cells_load(path, &c, &err) == -1 && err.line == 0 && tt_has(err.message, "cannot open"));

    CHECK(tt_cells_fails("", 0, "no cells"));
    CHECK(tt_cells_fails("# nothing\n\n   \n", 0, "no cells"));
    CHECK(tt_cells_fails("0 0 0 1 1 1\n0 0 0 1 1\n", 2, "expected 6 numbers"));
    CHECK(tt_cells_fails("0 0 0 1 1 1 1\n", 1, "found 7"));
    CHECK(tt_cells_fails("0 0 0 1 1 # 1\n", 1, "found 5"));
    CHECK(tt_cells_fails("\n0 0 0 1 1 1x\n", 2, "bad number '1x'"));
    CHECK(tt_cells_fails("0 0 0 1 1 1,\n", 1, "bad number"));
    CHECK(tt_cells_fails("0 0 nan 1 1 1\n", 1, "not finite"));
    CHECK(tt_cells_fails("0 0 0 1 inf 1\n", 1, "not finite"));
    CHECK(tt_cells_fails("0 0 0 1 1 1e40\n", 1, "out of range"));
    CHECK(tt_cells_fails("0 0 0 1 1 1\n0 2 0 1 1 1\n", 2, "min greater than max on the y axis"));
    CHECK(tt_cells_fails("5 0 0 1 1 1\n", 1, "min greater than max on the x axis"));
    CHECK(tt_cells_fails_n("0 0 0 1 1 1\n\0", 13, 2, "binary data at byte 12"));
}

/* ---- files ----------------------------------------------------------------------------------- */

static void tt_files(const char *dir) {
    tool_error err;
    char path[512], bad[512];
    void *data;
    size_t size;

    snprintf(path, sizeof(path), "%s/atomic.bin", dir);
    CHECK(write_file_atomic(path, "hello", 5, &err) == 0);
    CHECK(read_file(path, &data, &size, &err) == 0 && size == 5 && memcmp(data, "hello", 5) == 0 &&
          ((char *)data)[5] == '\0');
    free(data);
    /* Overwrite with a shorter file: no leftover bytes. */
    CHECK(write_file_atomic(path, "hi", 2, &err) == 0);
    CHECK(read_file(path, &data, &size, &err) == 0 && size == 2 && memcmp(data, "hi", 2) == 0);
    free(data);
    /* Empty file. */
    CHECK(write_file_atomic(path, "", 0, &err) == 0);
    CHECK(read_file(path, &data, &size, &err) == 0 && size == 0 && ((char *)data)[0] == '\0');
    free(data);
    /* Larger than read_file's initial buffer, through a pipe-like growth path too. */
    {
        size_t n = 100000;
        char *big = (char *)malloc(n);
        for (size_t i = 0; i < n; ++i) big[i] = (char)('a' + i % 26);
        CHECK(write_file_atomic(path, big, n, &err) == 0);
        CHECK(read_file(path, &data, &size, &err) == 0 && size == n && memcmp(data, big, n) == 0);
        free(data);
        free(big);
    }
    CHECK(tt_temp_files(dir) == 0);

    /* Failure: non-existent directory - nothing created, message names the path. */
    snprintf(bad, sizeof(bad), "%s/no/such/dir/out.pvs", dir);
    CHECK(write_file_atomic(bad, "x", 1, &err) == -1 && err.line == 0 && strncmp(err.message, bad, strlen(bad)) == 0 &&
          tt_has(err.message, "cannot create"));
    CHECK(!test_exists(bad));
    /* Failure at rename (the target is a directory): the temporary file must be removed. */
    snprintf(bad, sizeof(bad), "%s/adir", dir);
    CHECK(mkdir(bad, 0777) == 0);
    CHECK(write_file_atomic(bad, "x", 1, &err) == -1 && tt_has(err.message, "cannot rename"));
    CHECK(tt_temp_files(dir) == 0);
    rmdir(bad);

    /* read_file errors. */
    snprintf(bad, sizeof(bad), "%s/nothing.bin", dir);
    CHECK(read_file(bad, &data, &size, &err) == -1 && data == NULL && tt_has(err.message, "cannot open") &&
          err.line == 0);
    CHECK(read_file(dir, &data, &size, &err) == -1 && data == NULL && tt_has(err.message, "cannot read"));
    unlink(path);

    /* tool_error_set formats. */
    tool_error_set(&err, "a.obj", 12, "bad %s", "thing");
    CHECK(err.line == 12 && strcmp(err.message, "a.obj:12: bad thing") == 0);
    tool_error_set(&err, "a.obj", 0, "no faces");
    CHECK(err.line == 0 && strcmp(err.message, "a.obj: no faces") == 0);
    tool_error_set(NULL, "a.obj", 0, "ignored");
    {
        char longname[700];
        memset(longname, 'x', sizeof(longname) - 1);
        longname[sizeof(longname) - 1] = '\0';
        tool_error_set(&err, longname, 3, "problem");
        CHECK(strlen(err.message) == sizeof(err.message) - 1 && err.line == 3);
    }

    /* OBJ through a real file. */
    snprintf(path, sizeof(path), "%s/scene.obj", dir);
    const char *obj = "o a\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 2 5\n";
    CHECK(write_file_atomic(path, obj, strlen(obj), &err) == 0);
    mesh m;
    CHECK(obj_load(path, &m, &err) == -1 && err.line == 6 && tt_has(err.message, ":6: face index 5 out of range") &&
          strncmp(err.message, path, strlen(path)) == 0);
    CHECK(write_file_atomic(path, obj, strlen(obj) - 8, &err) == 0);
    CHECK(obj_load(path, &m, &err) == 0 && m.triangle_count == 1 && m.object_count == 1);
    mesh_free(&m);
    unlink(path);
}

/* ---- threads, progress, options -------------------------------------------------------------- */

typedef struct tt_pf {
    uint32_t *hits;
    uint32_t threads;
    int bad_thread;
} tt_pf;

static void tt_pf_fn(void *user, uint32_t index, uint32_t thread) {
    tt_pf *t = (tt_pf *)user;
    t->hits[index] += 1; /* each index belongs to one call only, so no race if parallel_for is right */
    if (thread >= t->threads) t->bad_thread = 1;
}

static void tt_parallel(void) {
    static const uint32_t counts[] = {0, 1, 3, 7, 1000};
    for (uint32_t threads = 0; threads <= 4; ++threads)
        for (size_t k = 0; k < sizeof(counts) / sizeof(counts[0]); ++k) {
            uint32_t n = counts[k];
            tt_pf t;
            t.hits = (uint32_t *)calloc(n + 1, sizeof(uint32_t));
            t.threads = threads ? threads : cpu_count();
            t.bad_thread = 0;
            CHECK(parallel_for(threads, n, tt_pf_fn, &t) == 0);
            int once = 1;
            for (uint32_t i = 0; i < n; ++i)
                if (t.hits[i] != 1) once = 0;
            CHECK(once && t.hits[n] == 0 && !t.bad_thread);
            free(t.hits);
        }
    CHECK(cpu_count() >= 1);
}

static void tt_progress(void) {
    FILE *f = tmpfile();
    CHECK(f != NULL);
    if (!f) return;
    progress p;
    progress_begin_ex(&p, "baking", 200, PROGRESS_PLAIN, f);
    for (uint64_t i = 1; i <= 200; ++i) progress_update(&p, i);
    progress_update(&p, 5); /* going back is ignored */
    progress_end(&p);
    char out[4096];
    rewind(f);
    size_t n = fread(out, 1, sizeof(out) - 1, f);
    out[n] = '\0';
    CHECK(tt_has(out, "baking [") && tt_has(out, "100% 200/200 in ") && !tt_has(out, "\r"));
    CHECK(tt_has(out, " 50% 100/200"));
    int lines = 0;
    for (size_t i = 0; i < n; ++i) lines += out[i] == '\n';
    CHECK(lines >= 2 && lines <= 11); /* one per 10% step at most, plus the final line */
    fclose(f);

    f = tmpfile();
    progress_begin_ex(&p, "cells", 10, PROGRESS_TTY, f);
    for (int i = 0; i < 10; ++i) progress_add(&p, 1);
    progress_end(&p);
    rewind(f);
    n = fread(out, 1, sizeof(out) - 1, f);
    out[n] = '\0';
    CHECK(tt_has(out, "\rcells [") && tt_has(out, "100% 10/10") && tt_has(out, "ETA") && out[n - 1] == '\n');
    fclose(f);

    f = tmpfile();
    progress_begin_ex(&p, "quiet", 10, PROGRESS_QUIET | PROGRESS_TTY, f);
    progress_update(&p, 5);
    progress_end(&p);
    CHECK(ftell(f) == 0);
    fclose(f);

    f = tmpfile();
    progress_begin_ex(&p, "unknown", 0, PROGRESS_PLAIN, f);
    progress_add(&p, 3);
    progress_end(&p);
    rewind(f);
    n = fread(out, 1, sizeof(out) - 1, f);
    out[n] = '\0';
    CHECK(tt_has(out, "unknown 3 in "));
    fclose(f);
}

static void tt_options(void) {
    uint32_t t = 99;
    CHECK(parse_threads("0", &t) == 0 && t == 0);
    CHECK(parse_threads("8", &t) == 0 && t == 8);
    CHECK(parse_threads("1024", &t) == 0 && t == 1024);
    CHECK(parse_threads("1025", &t) == -1);
    CHECK(parse_threads("99999999999999999999", &t) == -1);
    CHECK(parse_threads("", &t) == -1 && parse_threads("-1", &t) == -1 && parse_threads("+2", &t) == -1);
    CHECK(parse_threads("4x", &t) == -1 && parse_threads(" 4", &t) == -1 && parse_threads("4 ", &t) == -1);
    CHECK(parse_threads(NULL, &t) == -1);
    float f = 0;
    CHECK(parse_float("0.25", &f) == 0 && f == 0.25f);
    CHECK(parse_float("-3", &f) == 0 && f == -3.0f);
    CHECK(parse_float("1e-3", &f) == 0 && tt_feq(f, 0.001f));
    CHECK(parse_float(".5", &f) == 0 && f == 0.5f && parse_float("2.", &f) == 0 && f == 2.0f);
    CHECK(parse_float("", &f) == -1 && parse_float(".", &f) == -1 && parse_float("1e", &f) == -1);
    CHECK(parse_float("nan", &f) == -1 && parse_float("inf", &f) == -1 && parse_float("-Infinity", &f) == -1);
    CHECK(parse_float("1e39", &f) == -1 && parse_float("0x1p3", &f) == -1);
    CHECK(parse_float("0.5x", &f) == -1 && parse_float(" 0.5", &f) == -1 && parse_float("0.5 ", &f) == -1);
    CHECK(parse_float(NULL, &f) == -1);
}

/* ---- PNG ------------------------------------------------------------------------------------- */

/* Minimal inflate for what png_encode produces: stored and fixed-Huffman blocks. */
typedef struct tt_in {
    const uint8_t *p;
    size_t n, bit;
} tt_in;

static int tt_bit(tt_in *in) {
    if (in->bit >= in->n * 8) return -1;
    int b = (in->p[in->bit >> 3] >> (in->bit & 7)) & 1;
    ++in->bit;
    return b;
}
static long tt_bits(tt_in *in, int n) { /* LSB-first value */
    long v = 0;
    for (int i = 0; i < n; ++i) {
        int b = tt_bit(in);
        if (b < 0) return -1;
        v |= (long)b << i;
    }
    return v;
}
static long tt_huff(tt_in *in, int n) { /* n more bits of a Huffman code, MSB-first */
    long v = 0;
    for (int i = 0; i < n; ++i) {
        int b = tt_bit(in);
        if (b < 0) return -1;
        v = (v << 1) | b;
    }
    return v;
}
static long tt_fixed_sym(tt_in *in) {
    long v = tt_huff(in, 7);
    if (v < 0) return -1;
    if (v <= 23) return 256 + v;
    long b = tt_huff(in, 1);
    if (b < 0) return -1;
    v = (v << 1) | b;
    if (v >= 0x30 && v <= 0xBF) return v - 0x30;
    if (v >= 0xC0 && v <= 0xC7) return 280 + v - 0xC0;
    b = tt_huff(in, 1);
    if (b < 0) return -1;
    v = (v << 1) | b;
    if (v >= 0x190 && v <= 0x1FF) return 144 + v - 0x190;
    return -1;
}

/* Returns the inflated size, or -1 on malformed data. */
static long tt_inflate(const uint8_t *src, size_t n, uint8_t *dst, size_t cap) {
    static const int lbase[29] = {3, 4, 5, 6, 7, 8, 9, 10, 11, 13, 15, 17, 19, 23, 27, 31, 35, 43, 51, 59, 67, 83, 99,
                                  115, 131, 163, 195, 227, 258};
    static const int lext[29] = {0, 0, 0, 0, 0, 0, 0, 0, 1, 1, 1, 1, 2, 2, 2, 2, 3, 3, 3, 3, 4, 4, 4, 4, 5, 5, 5, 5, 0};
    static const int dbase[30] = {1, 2, 3, 4, 5, 7, 9, 13, 17, 25, 33, 49, 65, 97, 129, 193, 257, 385, 513, 769,
                                  1025, 1537, 2049, 3073, 4097, 6145, 8193, 12289, 16385, 24577};
    static const int dext[30] = {0, 0, 0, 0, 1, 1, 2, 2, 3, 3, 4, 4, 5, 5, 6, 6, 7, 7, 8, 8, 9, 9, 10, 10, 11, 11, 12, 12, 13, 13};
    tt_in in = {src, n, 0};
    size_t out = 0;
    for (;;) {
        long final = tt_bits(&in, 1), type = tt_bits(&in, 2);
        if (final < 0 || type < 0) return -1;
        if (type == 0) {
            in.bit = (in.bit + 7) & ~(size_t)7;
            long len = tt_bits(&in, 16), nlen = tt_bits(&in, 16);
            if (len < 0 || nlen < 0 || (len ^ 0xffff) != nlen) return -1;
            size_t at = in.bit >> 3;
            if (at + (size_t)len > n || out + (size_t)len > cap) return -1;
            memcpy(dst + out, src + at, (size_t)len);
            out += (size_t)len;
            in.bit += (size_t)len * 8;
        } else if (type == 1) {
            for (;;) {
                long sym = tt_fixed_sym(&in);
                if (sym < 0 || sym > 285) return -1;
                if (sym < 256) {
                    if (out >= cap) return -1;
                    dst[out++] = (uint8_t)sym;
                } else if (sym == 256) {
                    break;
                } else {
                    long le = tt_bits(&in, lext[sym - 257]);
                    long ds = tt_huff(&in, 5);
                    if (le < 0 || ds < 0 || ds > 29) return -1;
                    long de = tt_bits(&in, dext[ds]);
                    if (de < 0) return -1;
                    size_t len = (size_t)(lbase[sym - 257] + le), dist = (size_t)(dbase[ds] + de);
                    if (dist > out || dist > 32768 || out + len > cap) return -1;
                    for (size_t i = 0; i < len; ++i, ++out) dst[out] = dst[out - dist];
                }
            }
        } else {
            return -1;
        }
        if (final) return (long)out;
    }
}

static uint32_t tt_be32(const uint8_t *p) {
    return ((uint32_t)p[0] << 24) | ((uint32_t)p[1] << 16) | ((uint32_t)p[2] << 8) | p[3];
}

/* Full structural check + decode of a PNG produced by png_encode; compares the pixels. */
static int tt_png_check(const uint8_t *png, size_t size, const uint8_t *rgba, uint32_t w, uint32_t h,
                        int stored_expected) {
    static const uint8_t sig[8] = {137, 80, 78, 71, 13, 10, 26, 10};
    if (size < 8 || memcmp(png, sig, 8) != 0) return 0;
    size_t pos = 8, zlen = 0;
    uint8_t *z = (uint8_t *)malloc(size);
    int seen_ihdr = 0, seen_iend = 0, ok = 1;
    while (pos + 12 <= size && !seen_iend) {
        uint32_t len = tt_be32(png + pos);
        if (pos + 12 + (size_t)len > size) { ok = 0; break; }
        const uint8_t *type = png + pos + 4, *data = png + pos + 8;
        if (tool_crc32(0, type, (size_t)len + 4) != tt_be32(data + len)) { ok = 0; break; }
        if (memcmp(type, "IHDR", 4) == 0) {
            seen_ihdr = 1;
            if (len != 13 || tt_be32(data) != w || tt_be32(data + 4) != h || data[8] != 8 || data[9] != 6 ||
                data[10] || data[11] || data[12])
                ok = 0;
        } else if (memcmp(type, "IDAT", 4) == 0) {
            memcpy(z + zlen, data, len);
            zlen += len;
        } else if (memcmp(type, "IEND", 4) == 0) {
            seen_iend = 1;
            if (len != 0) ok = 0;
        }
        pos += 12 + (size_t)len;
    }
    if (!seen_ihdr || !seen_iend || pos != size || zlen < 6) ok = 0;
    if (ok && (z[0] != 0x78 || ((z[0] << 8) | z[1]) % 31 != 0 || (z[1] & 0x20))) ok = 0;
    if (ok) {
        size_t rawsize = (size_t)h * (1 + 4 * (size_t)w);
        uint8_t *raw = (uint8_t *)malloc(rawsize + 1);
        long got = tt_inflate(z + 2, zlen - 6, raw, rawsize + 1);
        if (got != (long)rawsize || tool_adler32(1, raw, rawsize) != tt_be32(z + zlen - 4)) ok = 0;
        /* Undo the row filters in place (PNG spec 9.2), then compare with the source pixels. */
        size_t rb = 4 * (size_t)w;
        for (uint32_t y = 0; ok && y < h; ++y) {
            uint8_t *row = raw + (size_t)y * (1 + rb) + 1;
            const uint8_t *up = y ? row - (1 + rb) : NULL;
            int ft = row[-1];
            if (ft > 4) ok = 0;
            for (size_t i = 0; ok && i < rb; ++i) {
                int a = i >= 4 ? row[i - 4] : 0, b = up ? up[i] : 0, c = up && i >= 4 ? up[i - 4] : 0, pred = 0;
                if (ft == 1) pred = a;
                else if (ft == 2) pred = b;
                else if (ft == 3) pred = (a + b) / 2;
                else if (ft == 4) {
                    int p = a + b - c, pa = abs(p - a), pb = abs(p - b), pc = abs(p - c);
                    pred = pa <= pb && pa <= pc ? a : pb <= pc ? b : c;
                }
                row[i] = (uint8_t)(row[i] + pred);
            }
            if (ok && memcmp(row, rgba + (size_t)y * rb, rb) != 0) ok = 0;
            if (stored_expected && ft != 0) ok = 0;
        }
        free(raw);
    }
    free(z);
    return ok;
}

static void tt_png(const char *dir) {
    CHECK(tool_crc32(0, "123456789", 9) == 0xCBF43926u);
    CHECK(tool_adler32(1, "Wikipedia", 9) == 0x11E60398u);
    {
        /* Adler-32 over more than 5552 bytes (the modulo batching). */
        uint8_t ones[20000];
        memset(ones, 0xff, sizeof(ones));
        uint32_t a = 1, b = 0;
        for (size_t i = 0; i < sizeof(ones); ++i) a = (a + 0xff) % 65521, b = (b + a) % 65521;
        CHECK(tool_adler32(1, ones, sizeof(ones)) == ((b << 16) | a));
    }

    uint32_t sizes[][2] = {{1, 1}, {3, 2}, {64, 48}, {200, 130}, {17000, 2}};
    for (size_t k = 0; k < sizeof(sizes) / sizeof(sizes[0]); ++k) {
        uint32_t w = sizes[k][0], h = sizes[k][1];
        uint8_t *img = (uint8_t *)malloc((size_t)w * h * 4);
        uint32_t seed = 12345;
        for (uint32_t y = 0; y < h; ++y)
            for (uint32_t x = 0; x < w; ++x) {
                uint8_t *p = img + ((size_t)y * w + x) * 4;
                seed = seed * 1103515245u + 12345u;
                int noisy = (x / 8 + y / 8) % 3 == 0;
                p[0] = noisy ? (uint8_t)(seed >> 16) : (uint8_t)(x * 255 / (w > 1 ? w - 1 : 1));
                p[1] = noisy ? (uint8_t)(seed >> 24) : (uint8_t)(y * 4);
                p[2] = (uint8_t)((x ^ y) & 0xc0);
                p[3] = (uint8_t)(x == 0 ? 128 : 255);
            }
        if (w >= 64) draw_text(img, w, h, 2, 2, "PVS 0123 abc!", TOOL_RGBA(255, 255, 255, 255));
        for (int stored = 0; stored <= 1; ++stored) {
            uint8_t *png = NULL;
            size_t size = 0;
            CHECK(png_encode(img, w, h, stored, &png, &size) == 0);
            CHECK(png && tt_png_check(png, size, img, w, h, stored));
            free(png);
        }
        free(img);
    }
    /* Compression actually compresses flat images. */
    {
        uint32_t w = 256, h = 256;
        uint8_t *img = (uint8_t *)calloc((size_t)w * h, 4);
        uint8_t *png = NULL;
        size_t size = 0;
        CHECK(png_encode(img, w, h, 0, &png, &size) == 0 && size < 4000 && tt_png_check(png, size, img, w, h, 0));
        free(png);
        free(img);
    }
    uint8_t dummy[4] = {0};
    uint8_t *png = NULL;
    size_t size = 0;
    CHECK(png_encode(dummy, 0, 1, 0, &png, &size) == -1 && png == NULL);

    /* png_write: atomic, same bytes as png_encode. */
    {
        uint32_t w = 40, h = 20;
        uint8_t *img = (uint8_t *)malloc((size_t)w * h * 4);
        for (size_t i = 0; i < (size_t)w * h * 4; ++i) img[i] = (uint8_t)(i * 7);
        char path[512];
        tool_error err;
        snprintf(path, sizeof(path), "%s/img.png", dir);
        CHECK(png_write(path, img, w, h, &err) == 0);
        void *data;
        CHECK(read_file(path, &data, &size, &err) == 0 && tt_png_check((const uint8_t *)data, size, img, w, h, 0));
        CHECK(png_encode(img, w, h, 0, &png, &size) == 0 && memcmp(png, data, size) == 0);
        free(png);
        free(data);
        unlink(path);
        snprintf(path, sizeof(path), "%s/none/img.png", dir);
        CHECK(png_write(path, img, w, h, &err) == -1 && tt_has(err.message, "cannot create"));
        CHECK(png_write(path, img, 0, h, &err) == -1 && tt_has(err.message, "cannot encode"));
        free(img);
    }
}

static void tt_font(void) {
    uint32_t w = 20, h = 12;
    uint8_t img[20 * 12 * 4];
    memset(img, 0, sizeof(img));
    uint32_t red = TOOL_RGBA(255, 0, 0, 255);
    CHECK(draw_text(img, w, h, 1, 1, "A", red) == 6);
    /* 'A' row 0 is .###. and row 4 is ##### */
    const uint8_t *p = img + (1 * w + 1) * 4;
    CHECK(p[0] == 0 && p[4] == 255 && p[5] == 0 && p[7] == 255 && p[8] == 255 && p[12] == 255 && p[16] == 0);
    p = img + (5 * w + 1) * 4;
    CHECK(p[0] == 255 && p[16] == 255);
    uint8_t img2[20 * 12 * 4];
    memset(img2, 0, sizeof(img2));
    draw_text(img2, w, h, 1, 1, "a", red);
    CHECK(memcmp(img, img2, sizeof(img)) == 0); /* lowercase draws as uppercase */
    /* Clipping: far outside or partly outside never writes out of bounds (ASan would tell). */
    CHECK(draw_text(img, w, h, -3, -4, "W\nW", red) == 6);
    draw_text(img, w, h, 15, 8, "Hello, world: 42%", red);
    draw_text(img, w, h, 100000, 100000, "x", red);
    CHECK(draw_text_scaled(img, w, h, 0, 0, "ab\nabc", red, 2) == 36);
    draw_text(img, w, h, 0, 0, "\x01\x80~{|}", red);
}

void test_tools(void) {
    char dir[] = "/tmp/pvs_test_tools_XXXXXX";
    if (!mkdtemp(dir)) {
        CHECK(!"mkdtemp failed");
        return;
    }
    tt_obj_accepts();
    tt_obj_errors(dir);
    tt_cells(dir);
    tt_files(dir);
    tt_parallel();
    tt_progress();
    tt_options();
    tt_png(dir);
    tt_font();
    char path[600];
    snprintf(path, sizeof(path), "%s/cells.txt", dir);
    unlink(path);
    CHECK(rmdir(dir) == 0); /* everything cleaned up, no stray temporary files */
}
