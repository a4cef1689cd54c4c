/* test_bsp.c - the Quake 3 BSP reader (tools/bsp.c) on a level built here byte by byte: what it
   makes of surfaces, patches, brushes, leaves and vis data, and every kind of malformed file. */
#define _POSIX_C_SOURCE 200809L
#include "test.h"
#include "../tools/bsp.h"

/* A tiny level: one solid box brush (the world), a quad, a 3 x 3 patch, a flare, three leaves (two
   with clusters, one solid) and vis data in which cluster 0 sees only itself and cluster 1 sees both;
   an inline model (a door) holds the flare, its bounds inside leaf 1. */
typedef struct tb_level {
    uint8_t bytes[4096];
    uint32_t size;
    uint32_t at[17], len[17];
} tb_level;

static void tb_put32(uint8_t *p, uint32_t v) {
    p[0] = (uint8_t)v;
    p[1] = (uint8_t)(v >> 8);
    p[2] = (uint8_t)(v >> 16);
    p[3] = (uint8_t)(v >> 24);
}
static void tb_putf(uint8_t *p, float f) {
    uint32_t u;
    memcpy(&u, &f, 4);
    tb_put32(p, u);
}
/* Appends lump `l` of n bytes (zeroed) and returns where it starts. */
static uint8_t *tb_lump(tb_level *t, int l, uint32_t n) {
    uint8_t *p = t->bytes + t->size;
    t->at[l] = t->size;
    t->len[l] = n;
    memset(p, 0, n);
    t->size += (n + 3) & ~3u;
    return p;
}
static void tb_i32s(uint8_t *p, const int32_t *v, int n) {
    for (int i = 0; i < n; ++i) tb_put32(p + 4 * i, (uint32_t)v[i]);
}

static void tb_build(tb_level *t) {
    memset(t, 0, sizeof(*t));
    t->size = 8 + 8 * 17;
    static const char ents[] = "{\n\"classname\" \"worldspawn\"\n}\n{\n\"origin\" \"10 20 30\"\n"
                               "\"classname\" \"info_player_deathmatch\"\n}\n";
    memcpy(tb_lump(t, 0, sizeof(ents) - 1), ents, sizeof(ents) - 1); /* entities: a player start */
    uint8_t *p = tb_lump(t, 1, 2 * 72); /* shaders: 0 solid, 1 water */
    memcpy(p, "textures/wall", 13);
    tb_put32(p + 68, 1);
    memcpy(p + 72, "textures/water", 14);
    tb_put32(p + 72 + 68, 32);
    p = tb_lump(t, 2, 6 * 16); /* planes of the box [0,64]^3 (Z up), normals outward */
    for (int i = 0; i < 6; ++i) {
        tb_putf(p + 16 * i + 4 * (i >> 1), (i & 1) ? 1.0f : -1.0f);
        tb_putf(p + 16 * i + 12, (i & 1) ? 64.0f : 0.0f);
    }
    p = tb_lump(t, 3, 2 * 36); /* nodes: 0 splits leaf 0 from node 1, which splits leaf 1 from leaf 2 */
    int32_t nodes[2][3] = {{0, -1, 1}, {1, -2, -3}};
    for (int i = 0; i < 2; ++i) tb_i32s(p + 36 * i, nodes[i], 3);
    p = tb_lump(t, 4, 4 * 48); /* leaves: cluster, area, mins, maxs, surfaces; leaf 3 outside the tree (q3map2's
                                  inline models' leaves: cluster 0, zero bounds), never a cell */
    int32_t leaves[4][12] = {{0, 0, -100, -100, 64, 0, 100, 200, 0, 2, 0, 0},
                             {1, 0, 0, -100, 64, 100, 100, 200, 2, 1, 0, 0},
                             {-1, 0, 0, 0, 0, 64, 64, 64, 0, 0, 0, 0},
                             {0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0}};
    for (int i = 0; i < 4; ++i) tb_i32s(p + 48 * i, leaves[i], 12);
    p = tb_lump(t, 5, 3 * 4); /* leaf surfaces: leaf 0 has surfaces 0 and 1, leaf 1 has 1 */
    int32_t ls[3] = {0, 1, 1};
    tb_i32s(p, ls, 3);
    p = tb_lump(t, 7, 2 * 40); /* models: the world (surfaces 0..2, brush 0), a door (surface 2) */
    int32_t world[4] = {0, 2, 0, 1}, door[4] = {2, 1, 0, 0};
    float dmin[3] = {10, -50, 70}, dmax[3] = {20, -40, 80};
    for (int k = 0; k < 3; ++k) {
        tb_putf(p + 4 * k, -1000.0f);
        tb_putf(p + 12 + 4 * k, 1000.0f);
        tb_putf(p + 40 + 4 * k, dmin[k]);
        tb_putf(p + 52 + 4 * k, dmax[k]);
    }
    tb_i32s(p + 24, world, 4);
    tb_i32s(p + 40 + 24, door, 4);
    p = tb_lump(t, 8, 12); /* one brush: sides 0..6, shader 0 */
    int32_t brush[3] = {0, 6, 0};
    tb_i32s(p, brush, 3);
    p = tb_lump(t, 9, 6 * 8);
    for (int i = 0; i < 6; ++i) tb_put32(p + 8 * i, (uint32_t)i);
    p = tb_lump(t, 10, 14 * 44); /* a quad at z = 70, then the 3 x 3 patch, then the flare's vertex */
    float quad[4][3] = {{0, -10, 70}, {50, -10, 70}, {50, -60, 70}, {0, -60, 70}};
    for (int i = 0; i < 4; ++i)
        for (int k = 0; k < 3; ++k) tb_putf(p + 44 * i + 4 * k, quad[i][k]);
    for (int i = 0; i < 9; ++i) {
        tb_putf(p + 44 * (4 + i), (float)(10 * (i % 3)));
        tb_putf(p + 44 * (4 + i) + 4, 80.0f);
        tb_putf(p + 44 * (4 + i) + 8, (float)(70 + 10 * (i / 3)));
    }
    p = tb_lump(t, 11, 6 * 4);
    int32_t idx[6] = {0, 1, 2, 0, 2, 3};
    tb_i32s(p, idx, 6);
    p = tb_lump(t, 13, 3 * 104); /* surfaces: planar quad, patch, flare (shader 1: water) */
    int32_t s0[7] = {0, -1, 1, 0, 4, 0, 6}, s1[7] = {0, -1, 2, 4, 9, 0, 0}, s2[7] = {1, -1, 4, 13, 1, 0, 0};
    tb_i32s(p, s0, 7);
    tb_putf(p + 92, 1.0f); /* the quad's normal: Quake +z */
    tb_i32s(p + 104, s1, 7);
    tb_put32(p + 104 + 96, 3);
    tb_put32(p + 104 + 100, 3);
    tb_i32s(p + 208, s2, 7);
    p = tb_lump(t, 16, 8 + 2); /* vis: 2 clusters of 1 byte */
    tb_put32(p, 2);
    tb_put32(p + 4, 1);
    p[8] = 1;
    p[9] = 3;
    memcpy(t->bytes, "IBSP", 4);
    tb_put32(t->bytes + 4, 46);
    for (int l = 0; l < 17; ++l) {
        if (!t->len[l]) t->at[l] = t->size;
        tb_put32(t->bytes + 8 + 8 * l, t->at[l]);
        tb_put32(t->bytes + 12 + 8 * l, t->len[l]);
    }
}

static int tb_parse(const tb_level *t, size_t size, mesh *m, mesh_cells *c, bsp_pvs *pvs, bsp_stats *st,
                    tool_error *err) {
    /* a copy flush against the end of an allocation, so the sanitizer sees any overrun */
    uint8_t *copy = (uint8_t *)malloc(size ? size : 1);
    memcpy(copy, t->bytes, size);
    int rc = bsp_parse("t.bsp", copy, size, NULL, m, c, pvs, st, err);
    free(copy);
    return rc;
}

static int tb_bit(const bsp_pvs *p, uint32_t cell, uint32_t o) { return (int)((p->bits[cell * p->words + o / 64] >> (o % 64)) & 1); }

static void tb_reads(void) {
    tb_level t;
    mesh m;
    mesh_cells c;
    bsp_pvs pvs;
    bsp_stats st;
    tool_error err;
    tb_build(&t);
    CHECK(tb_parse(&t, t.size, &m, &c, &pvs, &st, &err) == 0);
    CHECK(m.object_count == 4);                 /* three surfaces, then the brushes */
    CHECK(m.objects[0].triangle_count == 2);    /* the quad */
    CHECK(m.objects[1].triangle_count == 4 * 4 * 2); /* the patch, level 4 */
    CHECK(m.objects[2].triangle_count == 0);    /* the flare */
    CHECK(m.objects[3].flags == MESH_OBJECT_OCCLUDER && m.objects[3].triangle_count == 12); /* a box's hull */
    CHECK(st.surfaces == 3 && st.patches == 1 && st.empty_surfaces == 1 && st.translucent_surfaces == 1);
    {   /* the translucent one is see-through, by flag and by name (the OBJ keeps it) */
        uint32_t k, clear = 0;
        for (k = 0; k < m.object_count; ++k)
            if (m.objects[k].flags == MESH_OBJECT_SEE_THROUGH && !strncmp(m.objects[k].name, "see_through_s", 13)) ++clear;
        CHECK(clear == 1);
    }
    CHECK(st.brushes == 1 && st.occluder_brushes == 1 && st.hull_triangles == 12);
    CHECK(c.count == 2 && st.leaves == 2 && st.clusters == 2 && st.has_vis);
    CHECK(st.has_spawn && st.spawn[0] == 10 && st.spawn[1] == 30 && st.spawn[2] == -20); /* Quake (x, y, z): Y up */
    /* leaf 0 box: Quake (-100,-100,64)..(0,100,200) -> Y up (-100,64,-100)..(0,200,100) */
    CHECK(c.boxes[0] == -100 && c.boxes[1] == 64 && c.boxes[2] == -100 && c.boxes[3] == 0 && c.boxes[4] == 200 &&
          c.boxes[5] == 100);
    /* the hull is the box [0,64]^3 exactly (Y up: y in [0, 64], z in [-64, 0]), its 6 faces sharing 8 corners */
    float lo[3] = {1e9f, 1e9f, 1e9f}, hi[3] = {-1e9f, -1e9f, -1e9f};
    uint32_t vlo = UINT32_MAX, vhi = 0;
    for (uint32_t i = 0; i < 36; ++i) {
        uint32_t vi = m.indices[3 * m.objects[3].first_triangle + i];
        const float *v = m.positions + 3 * vi;
        for (int k = 0; k < 3; ++k) lo[k] = fminf(lo[k], v[k]), hi[k] = fmaxf(hi[k], v[k]);
        vlo = vi < vlo ? vi : vlo;
        vhi = vi > vhi ? vi : vhi;
    }
    CHECK(lo[0] == 0 && hi[0] == 64 && lo[1] == 0 && hi[1] == 64 && lo[2] == -64 && hi[2] == 0 && vhi - vlo == 7);
    /* the planar quad is lifted BSP_LIFT (0.01) along its normal, Quake +z (Y up +y) */
    for (uint32_t i = 0; i < 6; ++i)
        CHECK(fabsf(m.positions[3 * m.indices[3 * m.objects[0].first_triangle + i] + 1] - 70.01f) < 1e-4f);
    /* a patch vertex: the corner control point (0, 80, 70) -> (0, 70, -80) */
    const float *pv = m.positions + 3 * m.indices[3 * m.objects[1].first_triangle];
    CHECK(pv[0] == 0 && pv[1] == 70 && pv[2] == -80);
    /* PVS: cell 0 (cluster 0) sees leaf 0's surfaces 0, 1; cell 1 (cluster 1) also leaf 1's and the
       door's flare (its bounds meet leaf 1's box); nothing sees the brushes */
    CHECK(pvs.cell_count == 2 && pvs.object_count == 4);
    CHECK(tb_bit(&pvs, 0, 0) && tb_bit(&pvs, 0, 1) && !tb_bit(&pvs, 0, 2) && !tb_bit(&pvs, 0, 3));
    CHECK(tb_bit(&pvs, 1, 0) && tb_bit(&pvs, 1, 1) && tb_bit(&pvs, 1, 2) && !tb_bit(&pvs, 1, 3));
    mesh_free(&m);
    mesh_cells_free(&c);
    bsp_pvs_free(&pvs);
    /* every second cell: cell 0 only, its PVS row kept */
    {
        bsp_options o;
        memset(&o, 0, sizeof(o));
        o.cell_step = 2;
        CHECK(bsp_parse("t.bsp", t.bytes, t.size, &o, &m, &c, &pvs, &st, &err) == 0);
        CHECK(c.count == 1 && st.cells == 1 && st.leaves == 2 && pvs.cell_count == 1 && !tb_bit(&pvs, 0, 2));
        mesh_free(&m);
        mesh_cells_free(&c);
        bsp_pvs_free(&pvs);
    }
    /* clearance 1: leaf 0's +x face (Quake x = 0) has only the solid leaf 2 beyond it (node 0's back, node 1's
       back), so it moves 1 unit in (Y up: max x 0 -> -1); its other faces open on leaf 0 itself, leaf 1's on leaf 0
       or itself; a clearance that is not a distance is refused */
    {
        bsp_options o;
        memset(&o, 0, sizeof(o));
        o.clearance = 1;
        CHECK(bsp_parse("t.bsp", t.bytes, t.size, &o, &m, &c, NULL, &st, &err) == 0);
        CHECK(c.count == 2 && st.wall_faces == 1 && c.boxes[3] == -1 && c.boxes[0] == -100 && c.boxes[1] == 64 &&
              c.boxes[2] == -100 && c.boxes[4] == 200 && c.boxes[5] == 100 && c.boxes[6] == 0 && c.boxes[9] == 100);
        mesh_free(&m);
        mesh_cells_free(&c);
        o.clearance = 200; /* leaf 0 is 100 wide: its x faces would cross, so it keeps them */
        CHECK(bsp_parse("t.bsp", t.bytes, t.size, &o, &m, &c, NULL, &st, &err) == 0);
        CHECK(st.wall_faces == 0 && c.boxes[3] == 0);
        mesh_free(&m);
        mesh_cells_free(&c);
        o.clearance = NAN;
        CHECK(bsp_parse("t.bsp", t.bytes, t.size, &o, &m, &c, NULL, &st, &err) == -1 && strstr(err.message, "clearance"));
        mesh_free(&m);
        mesh_cells_free(&c);
    }
    /* the game's shader scripts: the quad's shader culls back faces (no script for it, or one without cull or
       deformVertexes), so it is one-sided, its triangles turned counter-clockwise about its normal (Y up +y); cull
       none, disable, twosided or back, deformVertexes (autosprites face the eye), portal, skyparms or the sky's surface
       flag keep it two-sided */
    {
        static const char *const scripts[] = {
            "// nothing about it\ntextures/other { cull none }\n", "textures/WALL\n{\n\tsurfaceparm nomarks\n\t{ map $lightmap }\n}\n",
            "/* { */ textures/wall { cull disable }", "textures/wall {\n deformVertexes autosprite\n}",
            "textures/wall { cull twosided } textures/wall { }", "textures/wall{cull back}", "textures/wall { portal }",
            "textures/wall\n{\n\tskyparms - 512 -\n}\n", NULL};
        bsp_options o;
        memset(&o, 0, sizeof(o));
        for (uint32_t k = 0; k < 9; ++k) {
            o.shaders = scripts[k < 8 ? k : 1];
            if (k == 8) tb_put32(t.bytes + t.at[1] + 64, 4); /* the sky by its surface flags */
            CHECK(bsp_parse("t.bsp", t.bytes, t.size, &o, &m, &c, NULL, &st, &err) == 0);
            const uint32_t *q = m.indices + 3 * m.objects[0].first_triangle;
            const float *a = m.positions + 3 * q[0], *b = m.positions + 3 * q[1], *d = m.positions + 3 * q[2];
            float ny = (b[2] - a[2]) * (d[0] - a[0]) - (b[0] - a[0]) * (d[2] - a[2]); /* y of (b - a) x (d - a) */
            int one = k < 2;
            CHECK(st.one_sided_surfaces == (uint32_t)one && m.objects[1].flags == 0 && (ny > 0) == one);
            CHECK(m.objects[0].flags == (one ? MESH_OBJECT_ONE_SIDED : 0u) &&
                  !strcmp(m.objects[0].name, one ? "one_sided_s0" : "s0"));
            mesh_free(&m);
            mesh_cells_free(&c);
        }
        tb_put32(t.bytes + t.at[1] + 64, 0);
    }
    /* without vis data every cell sees everything; a water brush does not block */
    t.len[16] = 0;
    tb_put32(t.bytes + 12 + 8 * 16, 0);
    tb_put32(t.bytes + t.at[8] + 8, 1);
    CHECK(tb_parse(&t, t.size, &m, &c, &pvs, &st, &err) == 0);
    CHECK(!st.has_vis && tb_bit(&pvs, 0, 2) && tb_bit(&pvs, 1, 0) && st.occluder_brushes == 0);
    CHECK(m.objects[3].triangle_count == 0);
    mesh_free(&m);
    mesh_cells_free(&c);
    bsp_pvs_free(&pvs);
}

/* One corruption: patch 4 bytes at offset `at` with `v`; the parse must fail naming `what`. */
static void tb_bad(uint32_t at, uint32_t v, const char *what) {
    tb_level t;
    mesh m;
    mesh_cells c;
    bsp_pvs pvs;
    tool_error err;
    tb_build(&t);
    tb_put32(t.bytes + at, v);
    memset(&err, 0, sizeof(err));
    int rc = tb_parse(&t, t.size, &m, &c, &pvs, NULL, &err);
    CHECK(rc == -1);
    CHECK(strstr(err.message, what) != NULL);
    if (rc != -1 || !strstr(err.message, what)) fprintf(stderr, "  expected '%s', got '%s'\n", what, err.message);
    mesh_free(&m);
    mesh_cells_free(&c);
    bsp_pvs_free(&pvs);
}

static void tb_errors(void) {
    tb_level t;
    tb_build(&t);
    float nan = NAN;
    uint32_t nan_bits;
    memcpy(&nan_bits, &nan, 4);
    tb_bad(0, 0x50534256u, "IBSP");                        /* magic */
    tb_bad(4, 47, "version 47");
    tb_bad(8 + 8 * 13, 4000, "lump 13 (surfaces): bytes");   /* past the end */
    tb_bad(12 + 8 * 13, 100, "not a whole number");
    tb_bad(t.at[13], 7, "surfaces[0]: shader 7");
    tb_bad(t.at[13] + 8, 9, "unknown surface type 9");
    tb_bad(t.at[13] + 16, 40, "surfaces[0]: vertex range 0+40");
    tb_bad(t.at[11] + 8, 5, "index 5 not in [0, 4)");
    tb_bad(t.at[13] + 104 + 96, 4, "patch of 4 x 3");
    tb_bad(t.at[13] + 104 + 96, 67, "patch of 67 x 3");
    tb_bad(t.at[10], nan_bits, "drawverts[0]: position is not finite");
    tb_bad(t.at[9], 99, "brushsides[0]: plane 99");
    tb_bad(t.at[8] + 4, 60, "brushes[0]: side range");
    tb_bad(t.at[4] + 48, 5, "leafs[1]: cluster 5");
    tb_bad(t.at[4] + 32, 2, "leafs[0]: surface range 2+2");
    tb_bad(t.at[5], 3, "leafsurfaces[0]: surface 3");
    tb_bad(t.at[16], 9, "9 clusters of 1 bytes do not fit");
    tb_bad(t.at[7] + 40 + 28, 5, "models[1]: surface range 2+5");
    tb_bad(t.at[4] + 8, 500, "leafs[0]: bounds min > max");
    tb_bad(t.at[3] + 8, 7, "nodes[0]: child 7 out of range");
    tb_bad(t.at[3], 9, "nodes[0]: plane 9 not in [0, 6)");
    tb_bad(t.at[3] + 36 + 8, (uint32_t)-10, "nodes[1]: leaf 9 out of range");
    tb_bad(t.at[3] + 36 + 8, 0, "nodes[1]: child 0 reached twice");
    /* every truncated prefix fails cleanly (no crash, no leak) */
    for (uint32_t n = 0; n < t.size; n += n < 200 ? 1 : 7) {
        mesh m;
        tool_error err;
        CHECK(tb_parse(&t, n, &m, NULL, NULL, NULL, &err) == -1);
        mesh_free(&m);
    }
}

/* pvsimport as a process: writes the scene, cells and the level's PVS; refuses bad input and usage. */
static void tb_tool(void) {
    tb_level t;
    char *out;
    FILE *f;
    tb_build(&t);
    mkdir("bsp-test", 0777);
    f = fopen("bsp-test/t.bsp", "wb");
    CHECK(f && fwrite(t.bytes, 1, t.size, f) == t.size);
    if (f) fclose(f);
    CHECK(test_run("bsp-test", "./pvsimport bsp-test/t.bsp -o bsp-test/t.obj --cells bsp-test/t.cells --pvs bsp-test/t.pvs",
                   &out) == 0);
    CHECK(strstr(out, "3 surfaces (1 patches") && strstr(out, "2 cells") && strstr(out, "1 faces kept 1 off walls"));
    free(out);
    CHECK(test_run("bsp-test", "./pvsimport bsp-test/t.bsp -o bsp-test/t0.obj --clearance 0", &out) == 0 &&
          strstr(out, "0 faces kept 0 off walls"));
    free(out);
    CHECK(test_run("bsp-test", "./pvsimport bsp-test/t.bsp -o x.obj --clearance -1", &out) == 2 &&
          strstr(out, "--clearance takes a distance"));
    free(out);
    /* shader scripts: a missing file is bad input naming it (nothing written), no file name a usage error */
    CHECK(test_run("bsp-test", "./pvsimport bsp-test/t.bsp -o bsp-test/s.obj --shaders bsp-test/none.shader", &out) == 1 &&
          strstr(out, "none.shader"));
    free(out);
    CHECK(!test_exists("bsp-test/s.obj"));
    CHECK(test_run("bsp-test", "./pvsimport bsp-test/t.bsp -o x.obj --shaders", &out) == 2 && strstr(out, "--shaders"));
    free(out);
    CHECK(test_run("bsp-test", "./pvsinfo --dump bsp-test/t.pvs", &out) == 0);
    CHECK(strstr(out, "0: 0 1\n") && strstr(out, "1: 0 1 2\n"));
    free(out);
    CHECK(test_run("bsp-test", "./pvsinfo --verify bsp-test/t.pvs", &out) == 0);
    free(out);
    CHECK(test_run("bsp-test", "./pvsimport bsp-test/t.obj -o bsp-test/u.obj", &out) == 1 && strstr(out, "IBSP"));
    free(out);
    CHECK(!test_exists("bsp-test/u.obj"));
    CHECK(test_run("bsp-test", "./pvsimport bsp-test/t.bsp", &out) == 2 && strstr(out, "missing -o"));
    free(out);
    CHECK(test_run("bsp-test", "./pvsimport bsp-test/t.bsp -o x.obj --patch-level 33", &out) == 2);
    free(out);
}

void test_wad(void); /* test_wad.c: the Doom map reader */

void test_bsp(void) {
    tb_reads();
    tb_errors();
    tb_tool();
    test_wad();
}
