/* methods_view.h - shared by examples/forest.c and examples/indoor.c: bake one cell of a generated
   scene with every bake method and show the PVSs side by side, from above.

   For the chosen cell (the regular cell nearest the scene's centre) each method of pvs.h (every
   pvs_method, AUTO included) bakes the cell (the bake gets all the scene's cells, so occluder
   synthesis sees the same free space as a full bake, but runs only this cell's task). Each PVS is
   checked against ray sampling from the cell (64 points x 4096 rays, then 64 rays aimed at each object
   not seen yet): objects the rays see that the
   PVS lacks are misses (a conservative method has none; SAMPLE, an estimate from below, may).
   One PNG, one panel per method: objects in the PVS green, the others grey, misses magenta, flat
   objects (ground, floors) darker, the cell white; objects entirely above the cell (ceilings,
   lintels) are left out of the picture so the rooms show. Under each panel: the PVS size, the share
   culled, the time and the misses. With a max_distance, one more panel shows AUTO with that draw
   distance (its misses count only objects within the distance). */
#ifndef METHODS_VIEW_H
#define METHODS_VIEW_H
#include "../tools/cli.h"
#include "../tools/render.h"
#include <math.h>
#include <stdlib.h>
#include <string.h>

typedef struct methods_view_opts {
    gen_kind kind;
    float size;
    uint64_t seed;
    float radius;          /* ground half-extent shown around the cell; 0 = the whole scene */
    const char *title;
    const char *png_name;  /* written into the output directory */
    float max_distance;    /* > 0: one more panel, AUTO with this draw distance (pvs_bake_desc.max_distance) */
} methods_view_opts;

typedef struct methods_view_result {
    pvs_method method;
    float max_distance;
    int ok;
    char note[200];        /* the error, or the methods AUTO ran */
    uint32_t pvs, misses;
    double ms;
    pvs_word *bits;
} methods_view_result;

static int methods_view_main(const methods_view_opts *o, int argc, char **argv) {
    const char *dir = "build/demo";
    uint32_t n, words, c, cell = 0, best_i, i, panels = 0, regular;
    int a, k;
    gen_params gp;
    gen_info info;
    mesh m;
    mesh_cells cells;
    pvs_scene *scene = NULL;
    tool_error te;
    pvs_word *seen;
    methods_view_result res[PVS_METHOD_COUNT + 1];
    pvs_box sb, cb;
    float region[4], best;
    uint32_t pw = 460, ph, W, H, label_h = 64;
    render_image panel, out;
    char path[1024], text[256];

    for (a = 1; a < argc; ++a) {
        if (!strcmp(argv[a], "-o") && a + 1 < argc) dir = argv[++a];
        else {
            fprintf(stderr, "usage: %s [-o OUTDIR]\n", argv[0]);
            return 2;
        }
    }
    memset(&gp, 0, sizeof(gp));
    gp.kind = o->kind;
    gp.seed = o->seed;
    gp.size = o->size;
    mesh_init(&m);
    mesh_cells_init(&cells);
    if (gen_scene_ex(&gp, &m, &cells, &info) || cli_make_scene(o->title, &m, 1, &scene, &te)) {
        fprintf(stderr, "%s: cannot build the scene\n", o->title);
        return 1;
    }
    n = pvs_scene_object_count(scene);
    words = (uint32_t)PVS_BITSET_WORDS(n);
    sb = pvs_scene_bounds(scene);
    regular = info.regular_count ? info.regular_count : cells.count;
    best = 1e30f;
    best_i = 0;
    for (c = 0; c < regular; ++c) { /* the cell nearest the centre of the scene */
        const float *b = cells.boxes + 6 * (size_t)c;
        float dx = 0.5f * (b[0] + b[3]) - 0.5f * (sb.min[0] + sb.max[0]), dz = 0.5f * (b[2] + b[5]) - 0.5f * (sb.min[2] + sb.max[2]);
        if (dx * dx + dz * dz < best) { best = dx * dx + dz * dz; best_i = c; }
    }
    cell = best_i;
    memcpy(&cb, cells.boxes + 6 * (size_t)cell, sizeof(cb));
    seen = (pvs_word *)calloc(words, sizeof(pvs_word));
    pvs_sample_visibility(scene, &cb, 64, 4096, 4242, seen);
    pvs_sample_visibility_toward(scene, &cb, NULL, 64, 2424, seen);
    printf("%s: %u objects, %u triangles, %u cells; cell %u (%.1f x %.1f x %.1f m); ray sampling sees %u objects\n", o->title, n,
           pvs_scene_triangle_count(scene), cells.count, cell, (double)(cb.max[0] - cb.min[0]), (double)(cb.max[1] - cb.min[1]),
           (double)(cb.max[2] - cb.min[2]), pvs_bitset_count(seen, n));
    printf("  %-8s %8s %8s %10s %7s  %s\n", "method", "PVS", "culled", "ms", "misses", "notes");

    /* ---- one bake per method, only this cell's task ---- */
    memset(res, 0, sizeof(res));
    for (k = 1; k <= PVS_METHOD_COUNT; ++k) {
        methods_view_result *r = res + panels;
        float dist = 0.0f;
        if (k == PVS_METHOD_COUNT) { /* the extra panel: AUTO with a draw distance */
            if (!(o->max_distance > 0.0f)) break;
            k = PVS_METHOD_AUTO;
            dist = o->max_distance;
        }
        r->max_distance = dist;
        pvs_bake_desc bd;
        pvs_bake *b = NULL;
        pvs_error pe;
        double t0 = cli_seconds();
        r->method = (pvs_method)k;
        r->bits = (pvs_word *)calloc(words, sizeof(pvs_word));
        memset(&bd, 0, sizeof(bd));
        bd.scene = scene;
        bd.cells = (const pvs_box *)cells.boxes;
        bd.cell_count = cells.count;
        bd.method = (pvs_method)k;
        bd.sample.points = 64;
        bd.sample.rays = 4096;
        bd.sample.seed = 99;
        bd.max_distance = dist;
        if (pvs_bake_begin(&bd, &b, &pe) != PVS_OK || pvs_bake_run_task(b, cell, &pe) != PVS_OK) {
            snprintf(r->note, sizeof(r->note), "%s", pe.message);
        } else {
            r->ok = 1;
            memcpy(r->bits, pvs_bake_cell_pvs(b, cell), words * sizeof(pvs_word));
            r->pvs = pvs_bitset_count(r->bits, n);
            for (i = 0; i < n; ++i) r->misses += pvs_bitset_test(seen, i) && !pvs_bitset_test(r->bits, i);
            if (k == PVS_METHOD_AUTO) {
                uint32_t j, len = 0;
                len += (uint32_t)snprintf(r->note + len, sizeof(r->note) - len, "ran:");
                for (j = 0; j < pvs_bake_method_count(b) && len < sizeof(r->note); ++j) {
                    pvs_bake_method_info mi;
                    pvs_bake_get_method_info(b, j, &mi);
                    if (mi.ran) len += (uint32_t)snprintf(r->note + len, sizeof(r->note) - len, " %s", pvs_method_name(mi.method));
                }
            } else if (k == PVS_METHOD_SAMPLE) {
                snprintf(r->note, sizeof(r->note), "approximate (not conservative)");
            } else if (k == PVS_METHOD_SHRINK) {
                snprintf(r->note, sizeof(r->note), "eps %.2g (default)", (double)pvs_bake_eps(b));
            }
        }
        r->ms = 1000.0 * (cli_seconds() - t0);
        if (dist > 0.0f) { /* misses only count within the draw distance */
            pvs_box ob;
            r->misses = 0;
            for (i = 0; r->ok && i < n; ++i) {
                double g2 = 0.0;
                int ax;
                ob = pvs_scene_object_box(scene, i);
                for (ax = 0; ax < 3; ++ax) {
                    double g = ob.min[ax] > cb.max[ax] ? (double)ob.min[ax] - cb.max[ax] : cb.min[ax] > ob.max[ax] ? (double)cb.min[ax] - ob.max[ax] : 0.0;
                    g2 += g * g;
                }
                r->misses += g2 <= (double)dist * dist && pvs_bitset_test(seen, i) && !pvs_bitset_test(r->bits, i);
            }
        }
        printf("  %-8s %8u %7.1f%% %10.1f %7u  %s%s\n", pvs_method_name(r->method), r->ok ? r->pvs : 0, r->ok ? 100.0 - 100.0 * r->pvs / n : 0.0,
               r->ms, r->misses, r->note, dist > 0.0f ? " (with --max-distance)" : "");
        pvs_bake_destroy(b);
        ++panels;
        if (dist > 0.0f) break;
    }

    /* ---- the panels ---- */
    if (o->radius > 0.0f) {
        float cx = 0.5f * (cb.min[0] + cb.max[0]), cz = 0.5f * (cb.min[2] + cb.max[2]);
        region[0] = cx - o->radius; region[1] = cz - o->radius; region[2] = cx + o->radius; region[3] = cz + o->radius;
    } else {
        region[0] = sb.min[0]; region[1] = sb.min[2]; region[2] = sb.max[0]; region[3] = sb.max[2];
    }
    ph = (uint32_t)(pw * (region[3] - region[1]) / (region[2] - region[0]) + 0.5f);
    W = panels * (pw + 4);
    H = ph + label_h + 30;
    if (render_image_init(&panel, pw, ph) || render_image_init(&out, W, H)) return 1;
    render_clear(&out, RENDER_RGBA(0, 0, 0, 255));
    snprintf(text, sizeof(text), "%s: one cell's PVS from above, per method (green: in the PVS, grey: culled, magenta: missed, white: the cell)",
             o->title);
    draw_text_scaled(out.rgba, W, H, 6, 6, text, TOOL_RGBA(255, 255, 255, 255), 2);
    for (k = 0; k < (int)panels; ++k) {
        const methods_view_result *r = res + k;
        render_view view;
        pvs_camera cam;
        float p0[3], p1[3], x0, y0, x1, y1;
        uint32_t y, ox = (uint32_t)k * (pw + 4);
        render_top_camera(&cam, 1, region[0], region[1], region[2], region[3], sb.max[1], pw, ph);
        render_view_init(&view, &cam, &panel);
        render_clear(&panel, RENDER_RGBA(20, 20, 24, 255));
        for (i = 0; i < n; ++i) {
            pvs_box ob = pvs_scene_object_box(scene, i);
            int flat = !(ob.max[1] - ob.min[1] > 0.25f), in = r->ok && pvs_bitset_test(r->bits, i);
            int miss = r->ok && !in && pvs_bitset_test(seen, i) && !(r->max_distance > 0.0f);
            uint32_t col;
            if (ob.min[1] > cb.max[1]) continue; /* ceilings and lintels: above the cell */
            if (miss) col = RENDER_RGBA(255, 0, 255, 255);
            else if (in) col = flat ? RENDER_RGBA(40, 100, 50, 255) : RENDER_RGBA(80, 235, 90, 255);
            else col = flat ? RENDER_RGBA(55, 55, 60, 255) : RENDER_RGBA(150, 150, 155, 255);
            render_triangles(&panel, &view, m.positions, m.indices, m.objects[i].first_triangle, m.objects[i].triangle_count, col, 0);
        }
        memcpy(p0, cb.min, sizeof(p0));
        memcpy(p1, cb.max, sizeof(p1));
        if (render_project(&view, &panel, p0, &x0, &y0, NULL) && render_project(&view, &panel, p1, &x1, &y1, NULL)) {
            render_fill_rect(&panel, (int)(x0 < x1 ? x0 : x1), (int)(y0 < y1 ? y0 : y1), (int)(x0 < x1 ? x1 : x0), (int)(y0 < y1 ? y1 : y0),
                             RENDER_RGBA(255, 255, 255, 255));
            render_rect(&panel, (int)(x0 < x1 ? x0 : x1) - 3, (int)(y0 < y1 ? y0 : y1) - 3, (int)(x0 < x1 ? x1 : x0) + 3, (int)(y0 < y1 ? y1 : y0) + 3,
                        RENDER_RGBA(255, 255, 255, 255));
        }
        for (y = 0; y < ph; ++y) memcpy(out.rgba + 4 * ((size_t)(y + 30) * W + ox), panel.rgba + 4 * (size_t)y * pw, 4 * (size_t)pw);
        if (r->max_distance > 0.0f) snprintf(text, sizeof(text), "%s, max distance %g m", pvs_method_name(r->method), (double)r->max_distance);
        else snprintf(text, sizeof(text), "%s", pvs_method_name(r->method));
        draw_text_scaled(out.rgba, W, H, (int)ox + 4, (int)(ph + 34), text, TOOL_RGBA(255, 255, 255, 255), 2);
        if (r->ok) {
            snprintf(text, sizeof(text), "PVS %u of %u (%.0f%% culled)\n%.0f ms, misses %u\n%s", r->pvs, n, 100.0 - 100.0 * r->pvs / n, r->ms,
                     r->misses, r->note);
        } else {
            snprintf(text, sizeof(text), "not available:\n%.60s", r->note);
        }
        draw_text(out.rgba, W, H, (int)ox + 4, (int)(ph + 54), text, r->ok ? TOOL_RGBA(200, 200, 200, 255) : TOOL_RGBA(255, 140, 140, 255));
    }
    snprintf(path, sizeof(path), "%s/%s", dir, o->png_name);
    if (png_write(path, out.rgba, W, H, &te)) { fprintf(stderr, "%s: %s\n", o->title, te.message); return 1; }
    printf("wrote %s\n", path);
    for (k = 0; k < (int)panels; ++k) free(res[k].bits);
    free(seen);
    render_image_free(&panel);
    render_image_free(&out);
    pvs_scene_destroy(scene);
    mesh_cells_free(&cells);
    mesh_free(&m);
    return 0;
}

#endif
