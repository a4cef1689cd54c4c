/* pvsview - look at a .pvs file with its scene: a top-down PNG. See --help.
     map     the scene from above (grey; flat objects such as ground tiles dark), every cell filled with a heat colour by its PVS size (cells
             stacked over one spot show the largest), a legend with the sizes
     --cell  one cell outlined in white and the objects of its PVS drawn green (the rest grey)
     --frame a first-person view from a point beside the map: objects in the PVS of the point's cell
             in their shade, objects outside it in red; a conservative PVS shows no red (the count of
             red pixels is printed: they are objects the PVS misses from that point) */
#include "cli.h"
#include "render.h"
#include <math.h>
#include <stdlib.h>
#include <string.h>

static const char *usage =
    "usage: pvsview SCENE.obj FILE.pvs -o OUT.png [options]\n"
    "  -o OUT.png             the image\n"
    "  --cell C               highlight cell C and its PVS\n"
    "  --cell-at X Y Z        highlight the cell containing the point\n"
    "  --frame X Y Z DX DY DZ also a first-person view from (X, Y, Z) looking along (DX, DY, DZ); the PVS is\n"
    "                         that of the point's cell\n"
    "  --region U0 V0 U1 V1   the ground rectangle shown (default: the cells' bounds and a margin)\n"
    "  --size N               map height in pixels (default 900)\n"
    "  --up y|z               up axis (default: the file's)\n"
    "exit status: 0 success, 1 bad input, 2 usage, 3 the frame shows objects outside the PVS\n";

static int usage_error(const char *fmt, const char *arg) {
    fprintf(stderr, "pvsview: ");
    fprintf(stderr, fmt, arg);
    fprintf(stderr, "\n(see pvsview --help)\n");
    return 2;
}

static int parse_floats(char **argv, int at, int argc, int n, float *out) {
    int k;
    if (at + n > argc) return -1;
    for (k = 0; k < n; ++k)
        if (parse_float(argv[at + k], out + k)) return -1;
    return 0;
}

typedef struct sized { uint32_t cell, size; } sized;
static int cmp_sized(const void *a, const void *b) {
    const sized *x = (const sized *)a, *y = (const sized *)b;
    if (x->size != y->size) return x->size < y->size ? -1 : 1;
    return x->cell < y->cell ? -1 : x->cell > y->cell;
}

int main(int argc, char **argv) {
    const char *scene_path = NULL, *pvs_path = NULL, *out_path = NULL;
    uint32_t up = 0, map_h = 900, cell = PVS_NO_CELL, i, c, n, words, smin = 0xffffffffu, smax = 0;
    float at[3], frame[6], region[4];
    int has_at = 0, has_frame = 0, has_region = 0, a, rc = 1, ui, vi;
    mesh m;
    pvs_scene *scene = NULL;
    void *data = NULL;
    size_t size;
    pvs_file f;
    pvs_error pe;
    tool_error te;
    render_image map, fp, out;
    render_view view;
    pvs_camera cam;
    pvs_word *bits = NULL, *chosen = NULL;
    sized *order = NULL;
    uint64_t red = 0;
    double mean = 0.0;
    char text[256];

    memset(&map, 0, sizeof(map));
    memset(&fp, 0, sizeof(fp));
    memset(&out, 0, sizeof(out));
    for (a = 1; a < argc; ++a) {
        const char *s = argv[a];
        if (!strcmp(s, "--help") || !strcmp(s, "-h")) {
            fputs(usage, stdout);
            return 0;
        } else if (!strcmp(s, "-o") || !strcmp(s, "--cell") || !strcmp(s, "--size") || !strcmp(s, "--up")) {
            const char *v = a + 1 < argc ? argv[a + 1] : NULL;
            if (!v) return usage_error("%s needs a value", s);
            ++a;
            if (!strcmp(s, "-o")) out_path = v;
            else if (!strcmp(s, "--cell") && cli_parse_u32(v, 0, 0xfffffffeu, &cell)) return usage_error("bad --cell '%s'", v);
            else if (!strcmp(s, "--size") && cli_parse_u32(v, 64, 8192, &map_h)) return usage_error("--size takes 64..8192, not '%s'", v);
            else if (!strcmp(s, "--up") && cli_parse_up(v, &up)) return usage_error("--up takes y or z, not '%s'", v);
        } else if (!strcmp(s, "--cell-at")) {
            if (parse_floats(argv, a + 1, argc, 3, at)) return usage_error("%s needs three numbers X Y Z", s);
            has_at = 1;
            a += 3;
        } else if (!strcmp(s, "--frame")) {
            if (parse_floats(argv, a + 1, argc, 6, frame)) return usage_error("%s needs six numbers X Y Z DX DY DZ", s);
            has_frame = 1;
            a += 6;
        } else if (!strcmp(s, "--region")) {
            if (parse_floats(argv, a + 1, argc, 4, region) || !(region[2] > region[0]) || !(region[3] > region[1]))
                return usage_error("%s needs U0 V0 U1 V1 with U0 < U1, V0 < V1", s);
            has_region = 1;
            a += 4;
        } else if (s[0] == '-' && s[1]) {
            return usage_error("unknown option '%s'", s);
        } else if (!scene_path) {
            scene_path = s;
        } else if (!pvs_path) {
            pvs_path = s;
        } else {
            return usage_error("unexpected argument '%s'", s);
        }
    }
    if (!scene_path || !pvs_path) return usage_error("%s", "give SCENE.obj and FILE.pvs");
    if (!out_path) return usage_error("%s", "no output given (-o OUT.png)");
    if (has_at && cell != PVS_NO_CELL) return usage_error("%s", "give at most one of --cell and --cell-at");

    mesh_init(&m);
    if (read_file(pvs_path, &data, &size, &te)) goto fail;
    if (pvs_file_open(data, size, &f, &pe) != PVS_OK) {
        tool_error_set(&te, pvs_path, 0, "%s", pe.message);
        goto fail;
    }
    if (cli_load_scene(scene_path, up ? up : f.up_axis, &m, &scene, &te)) goto fail;
    n = pvs_scene_object_count(scene);
    if (f.object_count != n) {
        tool_error_set(&te, pvs_path, 0, "the file has %u objects but the scene has %u: not the same scene", f.object_count, n);
        goto fail;
    }
    if (has_at) {
        cell = pvs_file_find_cell(&f, at);
        if (cell == PVS_NO_CELL) {
            tool_error_set(&te, pvs_path, 0, "no cell contains %g %g %g", (double)at[0], (double)at[1], (double)at[2]);
            goto fail;
        }
    }
    if (cell != PVS_NO_CELL && cell >= f.cell_count) {
        tool_error_set(&te, pvs_path, 0, "cell %u: the file has %u cells", cell, f.cell_count);
        goto fail;
    }
    up = pvs_scene_up_axis(scene);
    ui = 0;
    vi = up == 2 ? 1 : 2;
    words = (uint32_t)PVS_BITSET_WORDS(n);
    bits = (pvs_word *)calloc(words, sizeof(pvs_word));
    chosen = (pvs_word *)calloc(words, sizeof(pvs_word));
    order = (sized *)malloc((size_t)f.cell_count * sizeof(sized));
    if (!bits || !chosen || !order) { tool_error_set(&te, NULL, 0, "out of memory"); goto fail; }
    if (!has_region) {
        region[0] = region[1] = 1e30f;
        region[2] = region[3] = -1e30f;
    }
    for (c = 0; c < f.cell_count; ++c) {
        pvs_box b = pvs_file_cell_box(&f, c);
        pvs_file_decode(&f, c, bits, words, NULL);
        order[c].cell = c;
        order[c].size = pvs_bitset_count(bits, n);
        smin = order[c].size < smin ? order[c].size : smin;
        smax = order[c].size > smax ? order[c].size : smax;
        mean += order[c].size;
        if (!has_region) {
            region[0] = b.min[ui] < region[0] ? b.min[ui] : region[0];
            region[1] = b.min[vi] < region[1] ? b.min[vi] : region[1];
            region[2] = b.max[ui] > region[2] ? b.max[ui] : region[2];
            region[3] = b.max[vi] > region[3] ? b.max[vi] : region[3];
        }
    }
    mean /= f.cell_count;
    if (!has_region) {
        float mu = 0.05f * (region[2] - region[0]) + 1.0f, mv = 0.05f * (region[3] - region[1]) + 1.0f;
        region[0] -= mu; region[2] += mu; region[1] -= mv; region[3] += mv;
    }
    qsort(order, f.cell_count, sizeof(sized), cmp_sized);
    if (cell != PVS_NO_CELL) pvs_file_decode(&f, cell, chosen, words, NULL);

    /* ---- the map ---- */
    {
        uint32_t map_w = (uint32_t)((double)map_h * (region[2] - region[0]) / (region[3] - region[1]) + 0.5);
        pvs_box sb = pvs_scene_bounds(scene);
        if (map_w < 64) map_w = 64;
        if (map_w > 8192) map_w = 8192;
        if (render_image_init(&map, map_w, map_h)) { tool_error_set(&te, NULL, 0, "out of memory"); goto fail; }
        render_top_camera(&cam, up, region[0], region[1], region[2], region[3], sb.max[up], map_w, map_h);
        render_view_init(&view, &cam, &map);
        render_clear(&map, RENDER_RGBA(24, 24, 28, 255));
        for (i = 0; i < n; ++i) {
            /* flat objects (ground tiles, floors) dim, the others bright: green in the chosen PVS, grey not */
            pvs_box ob = pvs_scene_object_box(scene, i);
            int flat = !(ob.max[up] - ob.min[up] > 0.25f), in = cell != PVS_NO_CELL && pvs_bitset_test(chosen, i);
            uint32_t col = in ? (flat ? RENDER_RGBA(40, 100, 50, 255) : RENDER_RGBA(80, 235, 90, 255))
                              : (flat ? RENDER_RGBA(58, 58, 62, 255) : RENDER_RGBA(160, 160, 165, 255));
            render_triangles(&map, &view, m.positions, m.indices, m.objects[i].first_triangle, m.objects[i].triangle_count, col, 0);
        }
        /* cells: smallest PVS first, so the largest of a stack shows */
        for (c = 0; c < f.cell_count; ++c) {
            pvs_box b = pvs_file_cell_box(&f, order[c].cell);
            float p0[3], p1[3], x0, y0, x1, y1, t = smax > smin ? (float)(order[c].size - smin) / (float)(smax - smin) : 0.0f;
            memcpy(p0, b.min, sizeof(p0));
            memcpy(p1, b.max, sizeof(p1));
            p0[up] = p1[up] = b.max[up];
            if (render_project(&view, &map, p0, &x0, &y0, NULL) && render_project(&view, &map, p1, &x1, &y1, NULL)) {
                uint32_t col = render_heat(t);
                render_fill_rect(&map, (int)floorf(x0 < x1 ? x0 : x1), (int)floorf(y0 < y1 ? y0 : y1), (int)ceilf(x0 < x1 ? x1 : x0) - 1,
                                 (int)ceilf(y0 < y1 ? y1 : y0) - 1, (col & 0xffffff00u) | 200u);
            }
        }
        if (cell != PVS_NO_CELL) {
            pvs_box b = pvs_file_cell_box(&f, cell);
            float p0[3], p1[3], x0, y0, x1, y1;
            memcpy(p0, b.min, sizeof(p0));
            memcpy(p1, b.max, sizeof(p1));
            if (render_project(&view, &map, p0, &x0, &y0, NULL) && render_project(&view, &map, p1, &x1, &y1, NULL)) {
                int k;
                for (k = 0; k < 3; ++k)
                    render_rect(&map, (int)(x0 < x1 ? x0 : x1) - k, (int)(y0 < y1 ? y0 : y1) - k, (int)(x0 < x1 ? x1 : x0) + k,
                                (int)(y0 < y1 ? y1 : y0) + k, RENDER_RGBA(255, 255, 255, 255));
            }
        }
        if (has_frame) {
            float e[3], x, y;
            memcpy(e, frame, sizeof(e));
            if (render_project(&view, &map, e, &x, &y, NULL)) {
                double yaw = atan2(frame[3 + vi], frame[3 + ui]), k;
                float q[3], qx, qy;
                for (k = -0.785; k <= 0.79; k += 1.57) {
                    memcpy(q, e, sizeof(q));
                    q[ui] += 40.0f * (float)cos(yaw + k);
                    q[vi] += 40.0f * (float)sin(yaw + k);
                    if (render_project(&view, &map, q, &qx, &qy, NULL)) render_line(&map, x, y, qx, qy, RENDER_RGBA(255, 255, 255, 255), 2);
                }
                render_fill_rect(&map, (int)x - 4, (int)y - 4, (int)x + 4, (int)y + 4, RENDER_RGBA(255, 255, 255, 255));
            }
        }
        /* legend */
        {
            int lx = 10, ly = (int)map_h - 46, lw = 260, k;
            render_fill_rect(&map, lx - 6, ly - 20, lx + lw + 70, (int)map_h - 4, RENDER_RGBA(0, 0, 0, 200));
            for (k = 0; k < lw; ++k) render_fill_rect(&map, lx + k, ly, lx + k, ly + 14, render_heat((float)k / (float)(lw - 1)));
            snprintf(text, sizeof(text), "PVS size per cell (objects), mean %.0f", mean);
            draw_text(map.rgba, map.width, map.height, lx, ly - 14, text, TOOL_RGBA(255, 255, 255, 255));
            snprintf(text, sizeof(text), "%u", smin);
            draw_text(map.rgba, map.width, map.height, lx, ly + 20, text, TOOL_RGBA(255, 255, 255, 255));
            snprintf(text, sizeof(text), "%u", smax);
            draw_text(map.rgba, map.width, map.height, lx + lw - 6 * (int)strlen(text), ly + 20, text, TOOL_RGBA(255, 255, 255, 255));
        }
        snprintf(text, sizeof(text), "%s: %u cells, %u objects, method %s", pvs_path, f.cell_count, n, pvs_method_name(f.method));
        draw_text_scaled(map.rgba, map.width, map.height, 8, 8, text, TOOL_RGBA(255, 255, 255, 255), 2);
        if (cell != PVS_NO_CELL) {
            snprintf(text, sizeof(text), "cell %u (white outline): the %u objects of its PVS in green (ground dark green)", cell,
                     pvs_bitset_count(chosen, n));
            draw_text(map.rgba, map.width, map.height, 8, 30, text, TOOL_RGBA(120, 255, 130, 255));
        }
    }

    /* ---- the first-person frame ---- */
    if (has_frame) {
        uint32_t fc = pvs_file_find_cell(&f, frame), x, y;
        float l = sqrtf(frame[3] * frame[3] + frame[4] * frame[4] + frame[5] * frame[5]);
        render_image ids;
        if (fc == PVS_NO_CELL) {
            tool_error_set(&te, pvs_path, 0, "--frame: no cell contains %g %g %g", (double)frame[0], (double)frame[1], (double)frame[2]);
            goto fail;
        }
        if (!(l > 0.0f)) { tool_error_set(&te, NULL, 0, "--frame: the direction is zero"); goto fail; }
        pvs_file_decode(&f, fc, bits, words, NULL);
        if (render_image_init(&fp, map_h * 16 / 9, map_h) || render_image_init(&ids, map_h * 16 / 9, map_h)) { tool_error_set(&te, NULL, 0, "out of memory"); goto fail; }
        memset(&cam, 0, sizeof(cam));
        memcpy(cam.eye, frame, sizeof(cam.eye));
        memcpy(cam.forward, frame + 3, sizeof(cam.forward));
        cam.up[up] = 1.0f;
        cam.fov_y = 1.0f;
        cam.near_plane = 0.05f;
        render_view_init(&view, &cam, &fp);
        render_clear(&fp, RENDER_RGBA(150, 185, 225, 255));
        render_clear(&ids, RENDER_RGBA(0, 0, 0, 255));
        for (i = 0; i < n; ++i) {
            int in = pvs_bitset_test(bits, i);
            uint32_t h = i * 2654435761u;
            pvs_box ob = pvs_scene_object_box(scene, i);
            uint32_t col = !in ? RENDER_RGBA(255, 0, 0, 255)
                           : !(ob.max[up] - ob.min[up] > 0.25f) ? RENDER_RGBA(125, 125, 118, 255)
                           : RENDER_RGBA(170 + (h >> 27), 165 + ((h >> 22) & 31), 140 + ((h >> 17) & 31), 255);
            render_triangles(&fp, &view, m.positions, m.indices, m.objects[i].first_triangle, m.objects[i].triangle_count, col, 0);
            /* the same in flat marker colours: which pixels belong to objects outside the PVS */
            render_triangles(&ids, &view, m.positions, m.indices, m.objects[i].first_triangle, m.objects[i].triangle_count,
                             in ? RENDER_RGBA(0, 0, 255, 255) : RENDER_RGBA(255, 0, 0, 255), RENDER_UNLIT);
        }
        for (y = 0; y < ids.height; ++y)
            for (x = 0; x < ids.width; ++x) red += ids.rgba[4 * ((size_t)y * ids.width + x)] == 255;
        render_image_free(&ids);
        render_fill_rect(&fp, 0, 0, (int)fp.width - 1, 34, RENDER_RGBA(0, 0, 0, 170));
        snprintf(text, sizeof(text), "from %g %g %g (cell %u, PVS %u objects)", (double)frame[0], (double)frame[1], (double)frame[2], fc,
                 pvs_bitset_count(bits, n));
        draw_text(fp.rgba, fp.width, fp.height, 6, 4, text, TOOL_RGBA(255, 255, 255, 255));
        snprintf(text, sizeof(text), "red = objects outside the PVS; visible red pixels: %llu (0 for a conservative PVS)", (unsigned long long)red);
        draw_text(fp.rgba, fp.width, fp.height, 6, 18, text, red ? TOOL_RGBA(255, 90, 90, 255) : TOOL_RGBA(160, 255, 160, 255));
    }

    /* ---- side by side ---- */
    {
        uint32_t w = map.width + (has_frame ? fp.width + 6 : 0), y;
        if (render_image_init(&out, w, map_h)) { tool_error_set(&te, NULL, 0, "out of memory"); goto fail; }
        for (y = 0; y < map_h; ++y) {
            memcpy(out.rgba + 4 * (size_t)y * w, map.rgba + 4 * (size_t)y * map.width, 4 * (size_t)map.width);
            if (has_frame) memcpy(out.rgba + 4 * ((size_t)y * w + map.width + 6), fp.rgba + 4 * (size_t)y * fp.width, 4 * (size_t)fp.width);
        }
        if (png_write(out_path, out.rgba, w, map_h, &te)) goto fail;
    }
    printf("%s: %u cells, PVS size min %u, mean %.1f, max %u", out_path, f.cell_count, smin, mean, smax);
    if (cell != PVS_NO_CELL) printf("; cell %u: %u objects", cell, pvs_bitset_count(chosen, n));
    if (has_frame) printf("; frame: %llu pixels of objects outside the PVS", (unsigned long long)red);
    printf("\n");
    rc = has_frame && red ? 3 : 0;
    goto done;
fail:
    fprintf(stderr, "pvsview: %s\n", te.message);
done:
    render_image_free(&map);
    render_image_free(&fp);
    render_image_free(&out);
    free(bits);
    free(chosen);
    free(order);
    pvs_scene_destroy(scene);
    mesh_free(&m);
    free(data);
    return rc;
}
