/* test_auto.c - the bake driver's AUTO method and conveniences: AUTO's PVS is exactly the
   intersection of the PVSs of the methods it ran, each baked alone (and their statistics add up),
   with 0 misses against ray sampling on several generators; the methods mask; PREVIEW; the
   max_distance cut against a brute-force box distance (also at the exact threshold); restoring tasks
   (resumable bakes) gives the bytes of an uninterrupted bake; bad arguments. */
#include "../pvs.h"
#include "../tools/cli.h"
#include "test.h"
#include <math.h>
#include <stdlib.h>
#include <string.h>

/* A generator scene of the given kind (mesh and cells left for the caller to free); NULL on failure. */
static pvs_scene *gen_auto_scene(const char *name, gen_kind kind, uint64_t seed, float size, uint32_t max_cells, mesh *m, mesh_cells *cells) {
    gen_params gp;
    pvs_scene *s = NULL;
    tool_error te;
    gp = test_gen_params(kind, seed, size, max_cells);
    CHECK(test_generate(&gp, m, cells, NULL) == 0);
    CHECK(cli_make_scene(name, m, 1, &s, &te) == 0);
    return s;
}

/* Bakes every task of bd (scene and cells set by the caller); NULL (after a message) on failure. */
static pvs_bake *bake_all(pvs_bake_desc *bd, const pvs_scene *s, const mesh_cells *cells) {
    pvs_bake *b = NULL;
    pvs_error e;
    uint32_t t;
    bd->scene = s;
    bd->cells = (const pvs_box *)cells->boxes;
    bd->cell_count = cells->count;
    if (pvs_bake_begin(bd, &b, &e) != PVS_OK) {
        fprintf(stderr, "auto: bake_begin: %s\n", e.message);
        return NULL;
    }
    for (t = 0; t < pvs_bake_task_count(b); ++t)
        if (pvs_bake_run_task(b, t, &e) != PVS_OK) {
            fprintf(stderr, "auto: task %u: %s\n", t, e.message);
            pvs_bake_destroy(b);
            return NULL;
        }
    return b;
}

static pvs_bake *bake_with(const pvs_scene *s, const mesh_cells *cells, pvs_method method, uint32_t methods, uint32_t flags,
                           float max_distance) {
    pvs_bake_desc bd;
    memset(&bd, 0, sizeof(bd));
    bd.method = method;
    bd.methods = methods;
    bd.flags = flags;
    bd.max_distance = max_distance;
    /* EXTPROJ as AUTO runs it: with the occlusion sweep, except in a preview */
    if (method == PVS_METHOD_EXTPROJ && !(flags & PVS_BAKE_PREVIEW)) bd.extproj.sweep = PVS_EXTPROJ_SWEEP_PLANES;
    return bake_all(&bd, s, cells);
}

/* AUTO against its members baked alone and against ray sampling. */
static void check_auto(gen_kind kind, float size, uint64_t seed, uint32_t max_cells, int expect_cull) {
    mesh m;
    mesh_cells cells;
    pvs_scene *s = gen_auto_scene("auto-test", kind, seed, size, max_cells, &m, &cells);
    pvs_bake *a, *single[PVS_METHOD_COUNT];
    pvs_word *ref, *and_bits;
    uint32_t n, words, c, i, k, misses = 0, mismatches = 0, stat_bad = 0, ran = 0;
    uint64_t in_auto = 0;
    memset(single, 0, sizeof(single));
    if (!s) return;
    n = pvs_scene_object_count(s);
    words = (uint32_t)PVS_BITSET_WORDS(n);
    a = bake_with(s, &cells, PVS_METHOD_DEFAULT, 0, 0, 0.0f); /* DEFAULT is AUTO */
    CHECK(a != NULL);
    ref = (pvs_word *)calloc(words, sizeof(pvs_word));
    and_bits = (pvs_word *)calloc(words, sizeof(pvs_word));
    if (a) {
        CHECK(pvs_bake_method(a) == PVS_METHOD_AUTO);
        CHECK(pvs_bake_method_count(a) >= 1);
        for (k = 0; k < pvs_bake_method_count(a); ++k) {
            pvs_bake_method_info mi;
            CHECK(pvs_bake_get_method_info(a, k, &mi) == PVS_OK);
            CHECK(mi.method != PVS_METHOD_SAMPLE && mi.method != PVS_METHOD_AUTO && mi.reason != NULL);
            if (!mi.ran) continue;
            ++ran;
            single[mi.method] = bake_with(s, &cells, mi.method, 0, 0, 0.0f);
            CHECK(single[mi.method] != NULL);
            CHECK(mi.cells == cells.count);
        }
        CHECK(ran >= 1);
        CHECK(pvs_bake_get_method_info(a, pvs_bake_method_count(a), NULL) == PVS_ERROR_INVALID_ARGUMENT);
        for (c = 0; c < cells.count; ++c) {
            const pvs_word *pv = pvs_bake_cell_pvs(a, c);
            if (!pv) { CHECK(0); continue; }
            /* exactly the intersection of the members */
            for (i = 0; i < words; ++i) and_bits[i] = ~(pvs_word)0;
            for (k = 0; k < PVS_METHOD_COUNT; ++k)
                if (single[k]) {
                    const pvs_word *sp = pvs_bake_cell_pvs(single[k], c);
                    for (i = 0; i < words; ++i) and_bits[i] &= sp ? sp[i] : 0;
                }
            if (n & 63u) and_bits[words - 1] &= ((pvs_word)1 << (n & 63u)) - 1;
            mismatches += memcmp(and_bits, pv, words * sizeof(pvs_word)) != 0;
            /* 0 misses against ray sampling */
            test_sample(s, (const pvs_box *)cells.boxes + c, 24, 512, 1234 + c, 8, 4321 + c, ref);
            misses += test_misses(ref, pv, n, "auto", c);
            in_auto += pvs_bitset_count(pv, n);
        }
        /* the statistics: each member's own sum and what it alone left out, recomputed. A member that
           tested only what the members run before it kept (kept_only: SHRINK after others) counts
           every other drawable object as kept. */
        {
            pvs_bake_method_info ran_info[PVS_METHOD_COUNT]; /* the members that ran, in run order */
            uint32_t nr = 0, r;
            for (k = 0; k < pvs_bake_method_count(a); ++k) {
                pvs_bake_method_info mi;
                pvs_bake_get_method_info(a, k, &mi);
                if (!mi.ran || !single[mi.method]) continue;
                CHECK(mi.kept_only == (nr > 0 && mi.method == PVS_METHOD_SHRINK));
                ran_info[nr++] = mi;
            }
            for (r = 0; r < nr; ++r) {
                uint64_t own = 0, sole = 0;
                for (c = 0; c < cells.count; ++c)
                    for (i = 0; i < n; ++i) {
                        pvs_box ob = pvs_scene_object_box(s, i);
                        int drawable = !(pvs_scene_object_flags(s, i) & PVS_OBJECT_OCCLUDER_ONLY) && ob.min[0] <= ob.max[0] &&
                                       ob.min[1] <= ob.max[1] && ob.min[2] <= ob.max[2];
                        int eff[PVS_METHOD_COUNT], prior = 1, others = 1;
                        uint32_t j;
                        for (j = 0; j < nr; ++j) {
                            eff[j] = pvs_bitset_test(pvs_bake_cell_pvs(single[ran_info[j].method], c), i);
                            if (ran_info[j].kept_only && !prior && drawable) eff[j] = 1;
                            prior &= eff[j];
                        }
                        for (j = 0; j < nr; ++j)
                            if (j != r) others &= eff[j];
                        own += (uint64_t)eff[r];
                        sole += others && !eff[r] && drawable; /* occluder-only objects count for no method */
                    }
                stat_bad += own != ran_info[r].pvs_sum || sole != ran_info[r].sole_culls;
            }
        }
    }
    if (misses || mismatches || stat_bad)
        fprintf(stderr, "auto: %s size %g: %u misses, %u cells differ from the intersection, %u bad statistics\n", gen_kind_name(kind),
                (double)size, misses, mismatches, stat_bad);
    CHECK(misses == 0);
    CHECK(mismatches == 0);
    CHECK(stat_bad == 0);
    if (expect_cull) CHECK(in_auto < (uint64_t)n * cells.count);
    /* at least as tight as each member */
    for (k = 0; k < PVS_METHOD_COUNT; ++k)
        if (single[k]) {
            uint64_t sum = 0;
            for (c = 0; c < cells.count; ++c) sum += pvs_bitset_count(pvs_bake_cell_pvs(single[k], c), n);
            CHECK(in_auto <= sum);
            pvs_bake_destroy(single[k]);
        }
    free(ref);
    free(and_bits);
    pvs_bake_destroy(a);
    pvs_scene_destroy(s);
    mesh_cells_free(&cells);
    mesh_free(&m);
}

/* The methods mask, PREVIEW, and descs AUTO refuses. */
static void check_mask_preview(void) {
    mesh m;
    mesh_cells cells;
    pvs_scene *s = gen_auto_scene("auto-mask", GEN_WALLS, 2, 0.3f, 12, &m, &cells);
    pvs_bake_desc bd;
    pvs_bake *b = NULL;
    pvs_bake_method_info mi;
    pvs_error e;
    pvs_word *ref;
    uint32_t c, misses = 0, k, ran = 0;
    if (!s) return;
    b = bake_with(s, &cells, PVS_METHOD_AUTO, (1u << PVS_METHOD_OTREE) | (1u << PVS_METHOD_EXTPROJ), 0, 0.0f);
    CHECK(b && pvs_bake_method_count(b) == 2);
    if (b) {
        CHECK(pvs_bake_get_method_info(b, 0, &mi) == PVS_OK && mi.method == PVS_METHOD_EXTPROJ); /* cheapest first */
        CHECK(pvs_bake_get_method_info(b, 1, &mi) == PVS_OK && mi.method == PVS_METHOD_OTREE && mi.ran);
    }
    pvs_bake_destroy(b);
    /* preview: one method runs, the others are listed as skipped; still conservative, on several
       generators (its coarse occludee test decides whole kD-tree nodes: pvs__ep_visit) */
    {
        static const gen_kind kinds[4] = {GEN_WALLS, GEN_CITY, GEN_INDOOR, GEN_FOREST};
        static const float sizes[4] = {0.3f, 0.5f, 0.5f, 0.3f};
        int g;
        for (g = 0; g < 4; ++g) {
            mesh gm;
            mesh_cells gc;
            pvs_scene *gs = g ? gen_auto_scene("auto-preview", kinds[g], 3, sizes[g], 12, &gm, &gc) : s;
            uint32_t gn, kept = 0;
            if (!gs) continue;
            gn = pvs_scene_object_count(gs);
            b = bake_with(gs, g ? &gc : &cells, PVS_METHOD_AUTO, 0, PVS_BAKE_PREVIEW, 0.0f);
            CHECK(b != NULL);
            ref = (pvs_word *)calloc(PVS_BITSET_WORDS(gn), sizeof(pvs_word));
            ran = misses = 0;
            if (b) {
                for (k = 0; k < pvs_bake_method_count(b); ++k) {
                    pvs_bake_get_method_info(b, k, &mi);
                    ran += (uint32_t)mi.ran;
                }
                CHECK(ran == 1);
                for (c = 0; c < (g ? gc.count : cells.count); ++c) {
                    const pvs_box *cb = (const pvs_box *)(g ? gc.boxes : cells.boxes) + c;
                    test_sample(gs, cb, 24, 512, 77 + c, 8, 7 + c, ref);
                    misses += test_misses(ref, pvs_bake_cell_pvs(b, c), gn, "auto preview", c);
                    kept += pvs_bitset_count(pvs_bake_cell_pvs(b, c), gn);
                }
                CHECK(misses == 0);
                if (kinds[g] == GEN_CITY) CHECK(kept < gn * gc.count * 3 / 4); /* coarse, but it culls */
                if (misses) fprintf(stderr, "preview: %s: %u misses\n", gen_kind_name(kinds[g]), misses);
            }
            pvs_bake_destroy(b);
            free(ref);
            if (g) {
                pvs_scene_destroy(gs);
                mesh_cells_free(&gc);
                mesh_free(&gm);
            }
        }
    }
    /* single-method bakes report themselves */
    b = bake_with(s, &cells, PVS_METHOD_OTREE, 0, 0, 0.0f);
    CHECK(b && pvs_bake_method_count(b) == 1 && pvs_bake_get_method_info(b, 0, &mi) == PVS_OK && mi.method == PVS_METHOD_OTREE && mi.ran);
    pvs_bake_destroy(b);
    /* refused descs */
    test_bake_desc(&bd, s, (const pvs_box *)cells.boxes, cells.count, PVS_METHOD_AUTO);
    bd.methods = 1u << PVS_METHOD_SAMPLE; /* never sample */
    CHECK(pvs_bake_begin(&bd, &b, &e) == PVS_ERROR_INVALID_ARGUMENT && strstr(e.message, "sample"));
    bd.methods = 1u << PVS_METHOD_COUNT;
    CHECK(pvs_bake_begin(&bd, &b, &e) == PVS_ERROR_INVALID_ARGUMENT);
    bd.method = PVS_METHOD_OTREE;
    bd.methods = 1u << PVS_METHOD_OTREE; /* a mask is for AUTO only */
    CHECK(pvs_bake_begin(&bd, &b, &e) == PVS_ERROR_INVALID_ARGUMENT);
    bd.methods = 0;
    bd.max_distance = -1.0f;
    CHECK(pvs_bake_begin(&bd, &b, &e) == PVS_ERROR_INVALID_ARGUMENT);
    bd.max_distance = NAN;
    CHECK(pvs_bake_begin(&bd, &b, &e) == PVS_ERROR_INVALID_ARGUMENT);
    bd.max_distance = 0.0f;
    bd.flags = 0x80u;
    CHECK(pvs_bake_begin(&bd, &b, &e) == PVS_ERROR_INVALID_ARGUMENT);
    bd.flags = PVS_BAKE_NO_LOOKUP; /* no boxes: not for shards (merge needs them) nor VOCC (its occluders do) */
    bd.shard_count = 2;
    CHECK(pvs_bake_begin(&bd, &b, &e) == PVS_ERROR_INVALID_ARGUMENT);
    bd.shard_count = 0;
    bd.method = PVS_METHOD_VOCC;
    CHECK(pvs_bake_begin(&bd, &b, &e) == PVS_ERROR_INVALID_ARGUMENT);
    bd.method = PVS_METHOD_OTREE;
    bd.adaptive.budget = 1000; /* leaf cells: only the file knows their boxes */
    CHECK(pvs_bake_begin(&bd, &b, &e) == PVS_ERROR_INVALID_ARGUMENT);
    bd.adaptive.budget = 0;
    CHECK(b == NULL);
    CHECK(strcmp(pvs_method_name(PVS_METHOD_AUTO), "auto") == 0);
    pvs_scene_destroy(s);
    mesh_cells_free(&cells);
    mesh_free(&m);
}

/* A scene where no conservative method can cull: a single small triangle high above the cell (no
   wall on the ground, no volume, and no occluder between cell and anything). AUTO says so. */
static void check_nothing_applies(void) {
    static const float v[9] = {0, 10, 0, 1, 10, 0, 0, 10, 1};
    static const uint32_t idx[3] = {0, 1, 2};
    pvs_object_desc o = {0, 1, 0};
    pvs_scene_desc sd;
    pvs_scene *s = NULL;
    pvs_bake_desc bd;
    pvs_bake *b = NULL;
    pvs_box cell = {{-5, 0, -5}, {-4, 1, -4}};
    pvs_error e;
    memset(&sd, 0, sizeof(sd));
    sd.positions = v; sd.vertex_count = 3; sd.indices = idx; sd.triangle_count = 1; sd.objects = &o; sd.object_count = 1;
    CHECK(pvs_scene_create(&sd, &s, NULL) == PVS_OK);
    memset(&bd, 0, sizeof(bd));
    bd.scene = s; bd.cells = &cell; bd.cell_count = 1;
    bd.methods = 1u << PVS_METHOD_OTREE;
    CHECK(pvs_bake_begin(&bd, &b, &e) == PVS_ERROR_UNSUPPORTED && strstr(e.message, "auto") && b == NULL);
    pvs_scene_destroy(s);
}

/* Box distance (double, exact for these inputs) for the brute-force reference. */
static double box_dist(const pvs_box *a, const pvs_box *b) {
    double s = 0.0;
    int k;
    for (k = 0; k < 3; ++k) {
        double g = 0.0;
        if (a->min[k] > b->max[k]) g = (double)a->min[k] - b->max[k];
        if (b->min[k] > a->max[k]) g = (double)b->min[k] - a->max[k];
        s += g * g;
    }
    return sqrt(s);
}

/* max_distance: the PVS is the unlimited PVS minus exactly the objects clearly beyond D. */
static void check_max_distance(void) {
    mesh m;
    mesh_cells cells;
    pvs_scene *s = gen_auto_scene("auto-dist", GEN_INDOOR, 1, 0.4f, 10, &m, &cells);
    pvs_bake *full, *cut;
    const float D = 12.5f;
    uint32_t n, c, i, bad = 0, removed = 0;
    if (!s) return;
    n = pvs_scene_object_count(s);
    full = bake_with(s, &cells, PVS_METHOD_OTREE, 0, 0, 0.0f);
    cut = bake_with(s, &cells, PVS_METHOD_OTREE, 0, 0, D);
    CHECK(full && cut);
    for (c = 0; full && cut && c < cells.count; ++c)
        for (i = 0; i < n; ++i) {
            pvs_box ob = pvs_scene_object_box(s, i);
            double d = box_dist((const pvs_box *)cells.boxes + c, &ob);
            int in_full = pvs_bitset_test(pvs_bake_cell_pvs(full, c), i), in_cut = pvs_bitset_test(pvs_bake_cell_pvs(cut, c), i);
            if (in_cut && !in_full) ++bad;                    /* never adds */
            if (in_full && d <= D && !in_cut) ++bad;          /* within D: kept */
            if (in_full && d > D * 1.000001 && in_cut) ++bad; /* clearly beyond: cut */
            removed += in_full && !in_cut;
        }
    CHECK(bad == 0);
    CHECK(removed > 0);
    pvs_bake_destroy(full);
    pvs_bake_destroy(cut);
    pvs_scene_destroy(s);
    mesh_cells_free(&cells);
    mesh_free(&m);
    /* the exact threshold: a box at distance exactly D (an inexact square: 0.1) stays */
    {
        float pos[24];
        static const uint32_t box[36] = {0,2,1, 0,3,2, 4,5,6, 4,6,7, 0,1,5, 0,5,4, 2,3,7, 2,7,6, 1,2,6, 1,6,5, 0,4,7, 0,7,3};
        pvs_object_desc o = {0, 12, 0};
        pvs_scene_desc sd;
        pvs_bake_desc bd;
        pvs_bake *b = NULL;
        pvs_box cell = {{0, 0, 0}, {1, 1, 1}};
        float gap = 0.1f, x0 = 1.0f + gap;
        int k, pass;
        for (k = 0; k < 8; ++k) {
            pos[3 * k + 0] = (k == 1 || k == 2 || k == 5 || k == 6) ? x0 + 1.0f : x0;
            pos[3 * k + 1] = (float)(k == 2 || k == 3 || k == 6 || k == 7);
            pos[3 * k + 2] = (float)(k >= 4);
        }
        memset(&sd, 0, sizeof(sd));
        sd.positions = pos; sd.vertex_count = 8; sd.indices = box; sd.triangle_count = 12; sd.objects = &o; sd.object_count = 1;
        CHECK(pvs_scene_create(&sd, &s, NULL) == PVS_OK);
        for (pass = 0; pass < 2; ++pass) {
            float d = pass == 0 ? x0 - 1.0f : 0.5f * (x0 - 1.0f);
            test_bake_desc(&bd, s, &cell, 1, PVS_METHOD_SAMPLE);
            bd.max_distance = d;
            bd.sample.points = 16; bd.sample.rays = 256;
            CHECK(pvs_bake_begin(&bd, &b, NULL) == PVS_OK);
            if (b) {
                CHECK(pvs_bake_run_task(b, 0, NULL) == PVS_OK);
                /* at exactly D it is kept (rounding toward keeping); beyond D it is gone */
                CHECK(pvs_bitset_test(pvs_bake_cell_pvs(b, 0), 0) == (pass == 0));
            }
            pvs_bake_destroy(b);
            b = NULL;
        }
        pvs_scene_destroy(s);
    }
}

/* Restoring tasks from an earlier run gives the uninterrupted bake's bytes; bad restores refused. */
static void check_restore(void) {
    gen_params gp;
    mesh m;
    mesh_cells cells;
    pvs_scene *s = NULL;
    tool_error te;
    pvs_bake *whole, *part = NULL;
    pvs_bake_desc bd;
    pvs_error e;
    uint32_t n, words, t;
    size_t sa = 0, sb = 0;
    uint8_t *fa = NULL, *fb = NULL;
    gp = test_gen_params(GEN_WALLS, 5, 0.3f, 16);
    CHECK(test_generate(&gp, &m, &cells, NULL) == 0);
    m.objects[3].flags |= MESH_OBJECT_OCCLUDER;
    CHECK(cli_make_scene("auto-restore", &m, 1, &s, &te) == 0);
    if (!s) return;
    n = pvs_scene_object_count(s);
    words = (uint32_t)PVS_BITSET_WORDS(n);
    whole = bake_with(s, &cells, PVS_METHOD_AUTO, 0, 0, 0.0f);
    CHECK(whole != NULL);
    memset(&bd, 0, sizeof(bd));
    bd.scene = s;
    bd.cells = (const pvs_box *)cells.boxes;
    bd.cell_count = cells.count;
    CHECK(pvs_bake_begin(&bd, &part, &e) == PVS_OK);
    if (whole && part) {
        pvs_word *bits = (pvs_word *)calloc(words + 1, sizeof(pvs_word));
        for (t = 0; t < pvs_bake_task_count(part); t += 2) /* half restored, in any order */
            CHECK(pvs_bake_restore_task(part, t, pvs_bake_cell_pvs(whole, pvs_bake_task_cell(whole, t)), words, &e) == PVS_OK);
        CHECK(pvs_bake_task_done(part, 0) && !pvs_bake_task_done(part, 1));
        CHECK(pvs_bake_file_size(part) == 0); /* not done yet */
        for (t = 1; t < pvs_bake_task_count(part); t += 2) CHECK(pvs_bake_run_task(part, t, &e) == PVS_OK);
        sa = pvs_bake_file_size(whole);
        sb = pvs_bake_file_size(part);
        fa = (uint8_t *)malloc(sa + 1);
        fb = (uint8_t *)malloc(sb + 1);
        CHECK(sa == sb && sa > 0);
        CHECK(pvs_bake_write_file(whole, fa, sa, &sa, NULL) == PVS_OK && pvs_bake_write_file(part, fb, sb, &sb, NULL) == PVS_OK);
        CHECK(sa == sb && memcmp(fa, fb, sa) == 0);
        /* bad restores */
        CHECK(pvs_bake_restore_task(part, pvs_bake_task_count(part), bits, words, &e) == PVS_ERROR_INVALID_ARGUMENT);
        CHECK(pvs_bake_restore_task(part, 0, NULL, words, &e) == PVS_ERROR_INVALID_ARGUMENT);
        CHECK(pvs_bake_restore_task(part, 0, bits, words - 1, &e) == PVS_ERROR_BUFFER_TOO_SMALL);
        if (n & 63u) {
            bits[words - 1] = (pvs_word)1 << 63;
            CHECK(pvs_bake_restore_task(part, 0, bits, words, &e) == PVS_ERROR_INVALID_ARGUMENT && strstr(e.message, "past"));
            bits[words - 1] = 0;
        }
        pvs_bitset_set(bits, 3);
        CHECK(pvs_bake_restore_task(part, 0, bits, words, &e) == PVS_ERROR_INVALID_ARGUMENT && strstr(e.message, "occluder"));
        free(bits);
    }
    free(fa);
    free(fb);
    pvs_bake_destroy(whole);
    pvs_bake_destroy(part);
    pvs_scene_destroy(s);
    mesh_cells_free(&cells);
    mesh_free(&m);
}

/* AUTO's extproj runs the occlusion sweep unless told not to (PVS_EXTPROJ_NO_SWEEP) or previewing:
   the default bake equals one with extproj.sweep = PVS_EXTPROJ_SWEEP_PLANES, and the method info says
   so; PVS_EXTPROJ_NO_SWEEP equals the bake of before (EXTPROJ alone with 0: no sweep). */
static pvs_bake *bake_sweep(const pvs_scene *s, const mesh_cells *cells, pvs_method method, uint32_t sweep, uint32_t flags) {
    pvs_bake_desc bd;
    memset(&bd, 0, sizeof(bd));
    bd.method = method;
    bd.extproj.sweep = sweep;
    bd.flags = flags;
    return bake_all(&bd, s, cells);
}

static int same_pvs(const pvs_bake *a, const pvs_bake *b, uint32_t cells, uint32_t objects) {
    uint32_t c, differ = 0;
    if (!a || !b) return 0;
    for (c = 0; c < cells; ++c) differ += memcmp(pvs_bake_cell_pvs(a, c), pvs_bake_cell_pvs(b, c), PVS_BITSET_WORDS(objects) * sizeof(pvs_word)) != 0;
    return differ == 0;
}

/* The reason AUTO gives for extproj (the first method, the cheapest). */
static const char *extproj_reason(const pvs_bake *b) {
    pvs_bake_method_info mi;
    uint32_t k;
    for (k = 0; b && k < pvs_bake_method_count(b); ++k)
        if (pvs_bake_get_method_info(b, k, &mi) == PVS_OK && mi.method == PVS_METHOD_EXTPROJ) return mi.reason;
    return "";
}

static void check_sweep_default(void) {
    mesh m;
    mesh_cells cells;
    pvs_scene *s = gen_auto_scene("auto-sweep", GEN_CITY, 4, 0.15f, TEST_FULL ? 4 : 2, &m, &cells);
    pvs_bake *def, *with, *without, *alone0, *alone_off, *preview;
    uint32_t n;
    if (!s) return;
    n = pvs_scene_object_count(s);
    def = bake_sweep(s, &cells, PVS_METHOD_AUTO, 0, 0);
    with = bake_sweep(s, &cells, PVS_METHOD_AUTO, PVS_EXTPROJ_SWEEP_PLANES, 0);
    without = bake_sweep(s, &cells, PVS_METHOD_AUTO, PVS_EXTPROJ_NO_SWEEP, 0);
    alone0 = bake_sweep(s, &cells, PVS_METHOD_EXTPROJ, 0, 0);
    alone_off = bake_sweep(s, &cells, PVS_METHOD_EXTPROJ, PVS_EXTPROJ_NO_SWEEP, 0);
    preview = bake_sweep(s, &cells, PVS_METHOD_AUTO, 0, PVS_BAKE_PREVIEW);
    CHECK(def && with && without && alone0 && alone_off && preview);
    CHECK(same_pvs(def, with, cells.count, n));
    CHECK(!same_pvs(def, without, cells.count, n)); /* the sweep changes something on this city */
    CHECK(same_pvs(alone0, alone_off, cells.count, n));
    CHECK(strstr(extproj_reason(def), "sweep") != NULL);
    CHECK(strstr(extproj_reason(without), "sweep") == NULL);
    CHECK(strstr(extproj_reason(preview), "sweep") == NULL);
    CHECK(bake_sweep(s, &cells, PVS_METHOD_AUTO, 257, 0) == NULL); /* still refused */
    pvs_bake_destroy(def);
    pvs_bake_destroy(with);
    pvs_bake_destroy(without);
    pvs_bake_destroy(alone0);
    pvs_bake_destroy(alone_off);
    pvs_bake_destroy(preview);
    pvs_scene_destroy(s);
    mesh_cells_free(&cells);
    mesh_free(&m);
}

/* AUTO pays for what culls: on a small city of 4 times PVS_AUTO_SAMPLE_CELLS cells every method that runs was
   kept by the sample; each skipped one says so; the PVS is the kept methods' intersection (brute force: each kept
   method baked alone), never larger than the best kept method alone; one skipped as costly (not even prepared: rays
   prove too much of the kept PVS visible) would have culled less than PVS_AUTO_MIN_GAIN of it (baked alone); shards
   decide alike (two shards give the same PVSs); an explicit method set and a small bake run every method that
   applies. */
static void check_sample_policy(void) {
    mesh m;
    mesh_cells cells;
    pvs_scene *s = gen_auto_scene("sample-policy", GEN_CITY, 2, 0.15f, 4 * PVS_AUTO_SAMPLE_CELLS, &m, &cells);
    pvs_bake *a, *alone[PVS_METHOD_COUNT], *part[2];
    uint32_t n, words, c, k, w, skipped = 0, ran = 0, differ = 0, wrong = 0, costly = 0;
    memset(alone, 0, sizeof(alone));
    if (!s) return;
    CHECK(cells.count >= 4 * PVS_AUTO_SAMPLE_CELLS);
    n = pvs_scene_object_count(s);
    words = (uint32_t)PVS_BITSET_WORDS(n);
    a = bake_with(s, &cells, PVS_METHOD_AUTO, 0, 0, 0.0f);
    CHECK(a != NULL);
    if (!a) return;
    for (k = 0; k < pvs_bake_method_count(a); ++k) {
        pvs_bake_method_info mi;
        CHECK(pvs_bake_get_method_info(a, k, &mi) == PVS_OK);
        if (mi.ran) {
            ++ran;
            CHECK(mi.sample_cells == PVS_AUTO_SAMPLE_CELLS);
            alone[mi.method] = bake_with(s, &cells, mi.method, 0, 0, 0.0f);
            CHECK(alone[mi.method] != NULL);
        } else if (strstr(mi.reason, "negligible")) {
            ++skipped;
        } else if (strstr(mi.reason, "costly")) { /* what it would have culled, on every fourth cell */
            mesh_cells sub = cells;
            pvs_bake *b;
            double kept = 0.0, gain = 0.0;
            sub.boxes = (float *)malloc(6 * sizeof(float) * ((cells.count + 3) / 4));
            for (sub.count = 0; sub.boxes && 4 * sub.count < cells.count; ++sub.count)
                memcpy(sub.boxes + 6 * sub.count, cells.boxes + 6 * 4 * sub.count, 6 * sizeof(float));
            b = sub.boxes ? bake_with(s, &sub, mi.method, 0, 0, 0.0f) : NULL;
            CHECK(mi.sample_cells == 0 && b != NULL);
            for (c = 0; b && c < sub.count; ++c)
                for (w = 0; w < n; ++w) {
                    kept += pvs_bitset_test(pvs_bake_cell_pvs(a, 4 * c), w);
                    gain += pvs_bitset_test(pvs_bake_cell_pvs(a, 4 * c), w) && !pvs_bitset_test(pvs_bake_cell_pvs(b, c), w);
                }
            free(sub.boxes);
            CHECK(gain < PVS_AUTO_MIN_GAIN * kept);
            fprintf(stderr, "  %s skipped as costly: it culls %.0f of AUTO's %.0f\n", pvs_method_name(mi.method), gain, kept);
            pvs_bake_destroy(b);
            ++costly;
        }
    }
    CHECK(ran >= 1);
    for (c = 0; c < cells.count; ++c) {
        const pvs_word *got = pvs_bake_cell_pvs(a, c);
        for (w = 0; w < words; ++w) {
            pvs_word want = ~(pvs_word)0;
            for (k = 0; k < PVS_METHOD_COUNT; ++k)
                if (alone[k]) want &= pvs_bake_cell_pvs(alone[k], c)[w];
            wrong += got[w] != want;
        }
    }
    CHECK(wrong == 0);
    for (k = 0; k < 2; ++k) { /* shards: the same sample, the same decision */
        pvs_bake_desc bd;
        memset(&bd, 0, sizeof(bd));
        bd.shard_index = k;
        bd.shard_count = 2;
        part[k] = bake_all(&bd, s, &cells);
        CHECK(part[k] != NULL);
    }
    for (c = 0; c < cells.count && part[0] && part[1]; ++c)
        differ += memcmp(pvs_bake_cell_pvs(part[c % 2], c), pvs_bake_cell_pvs(a, c), words * sizeof(pvs_word)) != 0;
    CHECK(differ == 0);
    fprintf(stderr, "  sample policy on %u cells: %u methods ran, %u skipped as negligible, %u as costly\n", cells.count, ran,
            skipped, costly);
    for (k = 0; k < 2; ++k) pvs_bake_destroy(part[k]);
    for (k = 0; k < PVS_METHOD_COUNT; ++k) pvs_bake_destroy(alone[k]);
    pvs_bake_destroy(a);
    /* an explicit set runs every method in it that applies (only begin: the choice is made there) */
    {
        pvs_bake_desc bd;
        pvs_error e;
        memset(&bd, 0, sizeof(bd));
        bd.scene = s;
        bd.cells = (const pvs_box *)cells.boxes;
        bd.cell_count = cells.count;
        bd.methods = (1u << PVS_METHOD_OTREE) | (1u << PVS_METHOD_EXTPROJ);
        CHECK(pvs_bake_begin(&bd, &a, &e) == PVS_OK);
        for (k = 0; k < pvs_bake_method_count(a); ++k) {
            pvs_bake_method_info mi;
            CHECK(pvs_bake_get_method_info(a, k, &mi) == PVS_OK && mi.ran && mi.sample_cells == 0);
        }
        pvs_bake_destroy(a);
    }
    pvs_scene_destroy(s);
    mesh_free(&m);
    mesh_cells_free(&cells);
}

/* AUTO does not even prepare a method priced past any gain: with an eps so small that SHRINK would sample about
   11,000 points per cell (cost class 7, pvs__shrink_price), the sample skips it as costly, unsampled (it would have
   to cull 3.2 times the kept PVS), while with the default eps on the same cells it is sampled like the others or
   skipped only where rays prove the kept PVS so visible that it could not pay (check_sample_policy). */
static void check_costly(void) {
    mesh m;
    mesh_cells cells;
    pvs_scene *s = gen_auto_scene("costly", GEN_CITY, 2, 0.15f, 4 * PVS_AUTO_SAMPLE_CELLS, &m, &cells);
    uint32_t pass, k;
    if (!s) return;
    for (pass = 0; pass < 2; ++pass) {
        pvs_bake_desc bd;
        pvs_bake *a;
        pvs_error e;
        int seen = 0;
        memset(&bd, 0, sizeof(bd));
        bd.scene = s;
        bd.cells = (const pvs_box *)cells.boxes;
        bd.cell_count = cells.count;
        bd.eps = pass ? 0.0f : 0.05f;
        CHECK(pvs_bake_begin(&bd, &a, &e) == PVS_OK);
        if (!a) continue;
        for (k = 0; k < pvs_bake_method_count(a); ++k) {
            pvs_bake_method_info mi;
            CHECK(pvs_bake_get_method_info(a, k, &mi) == PVS_OK);
            if (mi.method != PVS_METHOD_SHRINK) continue;
            seen = 1;
            if (pass)
                CHECK(mi.sample_cells == PVS_AUTO_SAMPLE_CELLS || strstr(mi.reason, "beyond what rays prove visible"));
            else
                CHECK(!mi.ran && mi.sample_cells == 0 && strstr(mi.reason, "costly"));
        }
        CHECK(seen);
        pvs_bake_destroy(a);
    }
    pvs_scene_destroy(s);
    mesh_free(&m);
    mesh_cells_free(&cells);
}

/* PVS_BAKE_COMPACT (memory that grows with the PVSs): the same files and PVSs as the dense table, for AUTO (two
   methods), one method and adaptive cells, and when half the tasks are restored from a dense bake. */
static void check_compact(gen_kind kind, uint64_t seed, pvs_method method, uint32_t methods, uint32_t adaptive) {
    mesh m;
    mesh_cells cells;
    pvs_scene *s = gen_auto_scene("compact", kind, seed, 0.15f, 8, &m, &cells);
    pvs_bake *dense = NULL, *compact = NULL, *part = NULL;
    pvs_bake_desc bd;
    pvs_error e;
    uint8_t *f[3] = {NULL, NULL, NULL};
    size_t sz[3] = {0, 0, 0};
    uint32_t t, k, words;
    if (!s) return;
    words = (uint32_t)PVS_BITSET_WORDS(pvs_scene_object_count(s));
    memset(&bd, 0, sizeof(bd));
    bd.method = method;
    bd.methods = methods;
    bd.adaptive.budget = adaptive;
    dense = bake_all(&bd, s, &cells);
    bd.flags = PVS_BAKE_COMPACT;
    compact = bake_all(&bd, s, &cells);
    CHECK(dense && compact);
    if (dense && compact) {
        for (t = 0; t < cells.count; ++t)
            CHECK(memcmp(pvs_bake_cell_pvs(dense, t), pvs_bake_cell_pvs(compact, t), words * sizeof(pvs_word)) == 0);
        CHECK(pvs_bake_leaf_count(dense) == pvs_bake_leaf_count(compact));
        if (!adaptive) {
            CHECK(pvs_bake_begin(&bd, &part, &e) == PVS_OK);
            for (t = 0; part && t < pvs_bake_task_count(part); ++t)
                CHECK((t & 1 ? pvs_bake_run_task(part, t, &e)
                             : pvs_bake_restore_task(part, t, pvs_bake_cell_pvs(dense, t), words, &e)) == PVS_OK);
        }
        for (k = 0; k < 3; ++k) {
            pvs_bake *b = k == 0 ? dense : k == 1 ? compact : part;
            if (!b) continue;
            sz[k] = pvs_bake_file_size(b);
            f[k] = (uint8_t *)malloc(sz[k] + 1);
            CHECK(sz[k] > 0 && f[k] && pvs_bake_write_file(b, f[k], sz[k], &sz[k], NULL) == PVS_OK);
            CHECK(sz[k] == sz[0] && memcmp(f[k], f[0], sz[0]) == 0);
        }
    }
    for (k = 0; k < 3; ++k) free(f[k]);
    pvs_bake_destroy(dense);
    pvs_bake_destroy(compact);
    pvs_bake_destroy(part);
    pvs_scene_destroy(s);
    mesh_cells_free(&cells);
    mesh_free(&m);
}

void test_auto(void) {
    check_compact(GEN_WALLS, 4, PVS_METHOD_AUTO, (1u << PVS_METHOD_OTREE) | (1u << PVS_METHOD_PORTAL), 0);
    check_compact(GEN_INDOOR, 5, PVS_METHOD_OTREE, 0, 0);
    check_compact(GEN_WALLS, 6, PVS_METHOD_OTREE, 0, 24);
    check_sweep_default();
    check_mask_preview();
    check_nothing_applies();
    check_max_distance();
    check_restore();
    check_sample_policy();
    check_costly();
    check_auto(GEN_CITY, 0.1f, 1, TEST_FULL ? 6 : 3, 1);
    check_auto(GEN_INDOOR, 0.3f, 2, 10, 1);
    check_auto(GEN_WALLS, 0.3f, 3, 10, 1);
    check_auto(GEN_FOREST, 0.12f, 1, 6, 0);
    check_auto(GEN_SOUP, 0.2f, 1, 6, 0);
}
