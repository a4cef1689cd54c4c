/* test_wad.c - the Doom map reader (tools/wad.c) on a map built here byte by byte: what it makes of walls, steps,
   a sky, subsectors and the solid space, and malformed files (part of the bsp group). */
#define _POSIX_C_SOURCE 200809L
#include "test.h"
#include "../tools/wad.h"
#include <sys/stat.h>

/* A square room 256 x 256 split at x = 128 into sector 0 (floor 0, ceiling 128) and sector 1 (floor 16, sky at
   128): six one-sided walls, one two-sided line, two subsectors, one node. */
typedef struct tw_wad {
    uint8_t b[2048];
    uint32_t size, lumps, at[16], len[16];
    char name[16][9];
} tw_wad;

static void tw_put16(uint8_t *p, uint32_t v) {
    p[0] = (uint8_t)v;
    p[1] = (uint8_t)(v >> 8);
}
static void tw_put32(uint8_t *p, uint32_t v) {
    tw_put16(p, v & 0xffffu);
    tw_put16(p + 2, v >> 16);
}
static uint8_t *tw_lump(tw_wad *w, const char *name, uint32_t n) {
    uint8_t *p = w->b + w->size;
    w->at[w->lumps] = w->size;
    w->len[w->lumps] = n;
    snprintf(w->name[w->lumps++], 9, "%s", name);
    memset(p, 0, n);
    w->size += n;
    return p;
}
static void tw_u16s(uint8_t *p, const int *v, int n) {
    int i;
    for (i = 0; i < n; ++i) tw_put16(p + 2 * i, (uint32_t)v[i] & 0xffffu);
}
static void tw_finish(tw_wad *w) {
    uint32_t i;
    memcpy(w->b, "PWAD", 4);
    tw_put32(w->b + 4, w->lumps);
    tw_put32(w->b + 8, w->size);
    for (i = 0; i < w->lumps; ++i) {
        uint8_t *e = w->b + w->size + 16 * i;
        tw_put32(e, w->at[i]);
        tw_put32(e + 4, w->len[i]);
        memset(e + 8, 0, 8);
        memcpy(e + 8, w->name[i], strlen(w->name[i]));
    }
    w->size += 16 * w->lumps;
}
/* extra: NULL, "TEXTMAP" (after the marker: a UDMF map) or another lump name (appended: "BEHAVIOR", Hexen's). */
static void tw_build(tw_wad *w, const char *extra) {
    static const int v[] = {0, 0, 128, 0, 256, 0, 256, 256, 128, 256, 0, 256};
    static const int lines[7][3] = {{0, 5, 0}, {5, 4, 1}, {1, 0, 2}, {4, 3, 3}, {3, 2, 4}, {2, 1, 5}, {1, 4, 6}};
    static const int segs[8][4] = {{0, 5, 0, 0}, {5, 4, 1, 0}, {1, 0, 2, 0}, {4, 1, 6, 1},
                                   {4, 3, 3, 0}, {3, 2, 4, 0}, {2, 1, 5, 0}, {1, 4, 6, 0}};
    static const int node[14] = {128, 0, 0, 256, 0, 0, 0, 0, 0, 0, 0, 0, 0x8001, 0x8000};
    uint8_t *p;
    int i;
    memset(w, 0, sizeof(*w));
    w->size = 12;
    tw_lump(w, "MAP01", 0);
    if (extra && !strcmp(extra, "TEXTMAP")) tw_lump(w, extra, 0);
    tw_lump(w, "THINGS", 0);
    p = tw_lump(w, "LINEDEFS", 7 * 14);
    for (i = 0; i < 7; ++i) {
        int r[7] = {lines[i][0], lines[i][1], 0, 0, 0, lines[i][2], i == 6 ? 7 : 0xffff};
        tw_u16s(p + 14 * i, r, 7);
    }
    p = tw_lump(w, "SIDEDEFS", 8 * 30);
    for (i = 0; i < 8; ++i) tw_put16(p + 30 * i + 28, i < 3 || i == 7 ? 0u : 1u);
    p = tw_lump(w, "VERTEXES", 6 * 4);
    tw_u16s(p, v, 12);
    p = tw_lump(w, "SEGS", 8 * 12);
    for (i = 0; i < 8; ++i) {
        int r[6] = {segs[i][0], segs[i][1], 0, segs[i][2], segs[i][3], 0};
        tw_u16s(p + 12 * i, r, 6);
    }
    p = tw_lump(w, "SSECTORS", 8);
    tw_put16(p, 4), tw_put16(p + 2, 0), tw_put16(p + 4, 4), tw_put16(p + 6, 4);
    p = tw_lump(w, "NODES", 28);
    tw_u16s(p, node, 14);
    p = tw_lump(w, "SECTORS", 2 * 26);
    tw_put16(p + 2, 128);
    tw_put16(p + 26, 16), tw_put16(p + 28, 128);
    memcpy(p + 26 + 12, "F_SKY1", 6);
    if (extra && strcmp(extra, "TEXTMAP")) tw_lump(w, extra, 0);
    tw_finish(w);
}

static const mesh_object *tw_object(const mesh *m, const char *name) {
    uint32_t i;
    for (i = 0; i < m->object_count; ++i)
        if (!strcmp(m->objects[i].name, name)) return m->objects + i;
    return NULL;
}

static void tw_reads(void) {
    tw_wad w;
    mesh m;
    mesh_cells c;
    wad_stats st;
    tool_error err;
    char list[64];
    const mesh_object *o;
    wad_options opt = {2, 1};
    tw_build(&w, NULL);
    CHECK(wad_list_maps("t.wad", w.b, w.size, list, sizeof(list), &err) == 1 && !strcmp(list, "MAP01\n"));
    CHECK(wad_parse("t.wad", w.b, w.size, NULL, NULL, &m, &c, &st, &err) == 0);
    CHECK(!strcmp(st.map, "MAP01") && st.linedefs == 7 && st.sectors == 2 && st.subsectors == 2);
    CHECK(st.wall_quads == 7);        /* six walls, the step between floors 0 and 16; ceilings equal: none */
    CHECK(st.sky_sectors == 1 && st.lost_subsectors == 0);
    CHECK(st.solids == 2 * 2 + 6);    /* under and over each subsector; the void: a strip past each outer wall */
    CHECK(m.object_count == 7 + 4 + 1);
    CHECK(m.objects[6].triangle_count == 2); /* the two-sided line: its step */
    o = tw_object(&m, "occluder_sky1");
    CHECK(o && (o->flags & MESH_OBJECT_OCCLUDER) && o->triangle_count == 2);
    o = tw_object(&m, "ceil0");
    CHECK(o && o->flags == 0 && o->triangle_count == 2);
    o = tw_object(&m, "occluder_solids");
    CHECK(o && (o->flags & MESH_OBJECT_OCCLUDER) && o->triangle_count == 10 * 12);
    CHECK(c.count == 2 && st.cells == 2);
    if (c.count == 2) {
        static const float want[12] = {0, 0, -256, 128, 128, 0, 128, 16, -256, 256, 128, 0};
        int k, same = 1;
        for (k = 0; k < 12; ++k) same &= c.boxes[k] == want[k];
        CHECK(same);
    }
    mesh_free(&m);
    mesh_cells_free(&c);
    CHECK(wad_parse("t.wad", w.b, w.size, "map01", &opt, &m, &c, &st, &err) == 0); /* names ignore case */
    CHECK(c.count == 1 && st.solids == 0 && !tw_object(&m, "occluder_solids")); /* every 2nd cell, no solids */
    mesh_cells_free(&c);
    mesh_free(&m);
}

/* parse of w fails with a message holding `what`. */
static void tw_fails(const tw_wad *w, const char *map, const char *what) {
    mesh m;
    mesh_cells c;
    tool_error err;
    int rc = wad_parse("t.wad", w->b, w->size, map, NULL, &m, &c, NULL, &err);
    CHECK(rc == -1 && strstr(err.message, what) != NULL);
    if (rc != -1 || !strstr(err.message, what)) fprintf(stderr, "  wanted '%s', got '%s'\n", what, err.message);
    mesh_free(&m);
    mesh_cells_free(&c);
}

static uint8_t *tw_find(tw_wad *w, const char *name) {
    uint32_t i;
    for (i = 0; i < w->lumps; ++i)
        if (!strcmp(w->name[i], name)) return w->b + w->at[i];
    return NULL;
}

static void tw_errors(void) {
    tw_wad w;
    tw_build(&w, NULL);
    tw_fails(&w, "MAP02", "no map named MAP02");
    w.b[0] = 'X';
    tw_fails(&w, NULL, "not a WAD file");
    tw_build(&w, NULL);
    tw_put32(w.b + 4, 1000); /* directory past the end */
    tw_fails(&w, NULL, "directory of 1000 lumps");
    tw_build(&w, NULL);
    tw_put16(tw_find(&w, "LINEDEFS") + 14 * 3, 600); /* linedef 3's first vertex */
    tw_fails(&w, NULL, "LINEDEFS[3]: vertex 600 past the 6 allowed");
    tw_build(&w, NULL);
    tw_put16(tw_find(&w, "SIDEDEFS") + 30 * 2 + 28, 9);
    tw_fails(&w, NULL, "SIDEDEFS[2]: sector 9 past the 2 allowed");
    tw_build(&w, NULL);
    tw_put16(tw_find(&w, "SEGS") + 12 * 5 + 6, 70);
    tw_fails(&w, NULL, "SEGS[5]: linedef 70");
    tw_build(&w, NULL);
    tw_put16(tw_find(&w, "SEGS") + 12 * 2 + 8, 1); /* a seg on linedef 2's back: it has none */
    tw_fails(&w, NULL, "SEGS[2]: side (none on its linedef)");
    tw_build(&w, NULL);
    tw_put16(tw_find(&w, "SSECTORS") + 4, 9);
    tw_fails(&w, NULL, "SSECTORS[1]: seg range end 13");
    tw_build(&w, NULL);
    tw_put16(tw_find(&w, "SSECTORS"), 0);
    tw_fails(&w, NULL, "SSECTORS[0]: no segs");
    tw_build(&w, NULL);
    tw_put16(tw_find(&w, "NODES") + 24, 0); /* node 0's child is node 0: a cycle */
    tw_fails(&w, NULL, "NODES[0]: child node (not below it)");
    tw_build(&w, NULL);
    tw_put16(tw_find(&w, "NODES") + 4, 0), tw_put16(tw_find(&w, "NODES") + 6, 0);
    tw_fails(&w, NULL, "NODES[0]: a partition line of length 0");
    tw_build(&w, NULL);
    memcpy(tw_find(&w, "NODES"), "XNOD", 4);
    tw_fails(&w, NULL, "extended (ZDoom) nodes");
    tw_build(&w, NULL);
    tw_put32(w.b + w.size - 16 * w.lumps + 16 * 2 + 4, 15); /* directory entry 2, LINEDEFS: 15 bytes */
    tw_fails(&w, NULL, "LINEDEFS of 15 bytes");
    tw_build(&w, "BEHAVIOR");
    tw_fails(&w, NULL, "Hexen-format");
    tw_build(&w, "TEXTMAP");
    tw_fails(&w, NULL, "UDMF");
}

/* 5,000 copies of the map with 1 to 4 random bytes changed (lumps, directory, header): each parses or fails with a
   message, never reads outside the bytes (the sanitizer build) or leaks. */
static void tw_mutations(void) {
    tw_wad w, x;
    uint64_t state = 12345;
    uint32_t k, ok = 0, failed = 0;
    tw_build(&w, NULL);
    for (k = 0; k < 5000; ++k) {
        mesh m;
        mesh_cells c;
        tool_error err;
        uint32_t j, n;
        int rc;
        x = w;
        state = state * 6364136223846793005ull + 1442695040888963407ull;
        n = 1 + (uint32_t)(state >> 62);
        for (j = 0; j < n; ++j) {
            state = state * 6364136223846793005ull + 1442695040888963407ull;
            x.b[(state >> 33) % x.size] = (uint8_t)(state >> 20);
        }
        err.message[0] = 0;
        rc = wad_parse("t.wad", x.b, x.size, NULL, NULL, &m, &c, NULL, &err);
        ok += rc == 0;
        failed += rc == -1 && err.message[0] != 0;
        mesh_free(&m);
        mesh_cells_free(&c);
    }
    CHECK(ok + failed == 5000 && ok > 0 && failed > 0);
}

/* pvsimport on the map: a WAD is told by its header; the BSP-only options and a missing map are refused. */
static void tw_tool(void) {
    tw_wad w;
    char *out;
    FILE *f;
    tw_build(&w, NULL);
    mkdir("bsp-test", 0777);
    f = fopen("bsp-test/t.wad", "wb");
    CHECK(f && fwrite(w.b, 1, w.size, f) == w.size);
    if (f) fclose(f);
    CHECK(test_run("bsp-test", "./pvsimport bsp-test/t.wad --list", &out) == 0 && !strcmp(out, "MAP01\n"));
    free(out);
    CHECK(test_run("bsp-test", "./pvsimport bsp-test/t.wad -o bsp-test/w.obj --cells bsp-test/w.cells", &out) == 0 &&
          strstr(out, "MAP01: 7 linedefs (7 wall quads), 2 sectors (1 with sky), 2 subsectors (0 lost), 10 solid prisms"));
    free(out);
    CHECK(test_run("bsp-test", "./pvsbake -q bsp-test/w.obj --cells bsp-test/w.cells -o bsp-test/w.pvs --method portal",
                   &out) == 0);
    free(out);
    CHECK(test_run("bsp-test", "./pvscheck -q bsp-test/w.obj bsp-test/w.pvs --points 8 --rays 256", &out) == 0 &&
          strstr(out, "misses 0"));
    free(out);
    CHECK(test_run("bsp-test", "./pvsimport bsp-test/t.wad --map MAP07 -o bsp-test/x.obj", &out) == 1 &&
          strstr(out, "no map named MAP07") && !test_exists("bsp-test/x.obj"));
    free(out);
    CHECK(test_run("bsp-test", "./pvsimport bsp-test/t.wad -o bsp-test/x.obj --pvs bsp-test/x.pvs", &out) == 2 &&
          strstr(out, "for a BSP file"));
    free(out);
    CHECK(test_run("bsp-test", "./pvsimport bsp-test/t.bsp -o bsp-test/x.obj --map MAP01", &out) == 2 &&
          strstr(out, "for a WAD file"));
    free(out);
    CHECK(test_run("bsp-test", "./pvsimport bsp-test/t.wad -o x.obj --map NINECHARS", &out) == 2);
    free(out);
}

void test_wad(void) {
    tw_reads();
    tw_errors();
    tw_mutations();
    tw_tool();
}
