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

#define TOOL "pvsview"

typedef struct view_options {
    const char *scene_path, *pvs_path, *out_path;
    uint32_t up, map_h, cell; /* up 0: the file's; cell PVS_NO_CELL: none */
    float at[3], frame[6], region[4];
    int has_at, has_frame, has_region;
} view_options;

typedef struct sized { uint32_t cell, size; } sized;
static int cmp_sized(const void *a, const void *b) {
    const sized *x = (const sized *)a, *y = (const sized *)b;
    if (x->size != y->size) return x->size < y->size ? -1 : 1;
    return x->cell < y->cell ? -1 : x->cell > y->cell;
}

/* What the images are drawn from: the scene, the file, the cells by PVS size and the region shown. */
typedef struct view_data {
    mesh m;
    pvs_scene *scene;
    void *data;
    pvs_file f;
    uint32_t n, words, cell, up, ui, vi; /* ui, vi: the ground axes */
    uint32_t smin, smax;                 /* PVS sizes */
    double mean;
    float region[4];
    pvs_word *bits, *chosen;             /* scratch; the chosen cell's PVS */
    sized *order;                        /* the cells, smallest PVS first */
} view_data;

/* -1 to go on; otherwise the exit status (0 after --help, 2 after a usage error). */
static int parse_options(int argc, char **argv, view_options *o) {
    int a;
    memset(o, 0, sizeof(*o));
    o->map_h = 900;
    o->cell = PVS_NO_CELL;
    for (a = 1; a < argc; ++a) {
        const char *s = argv[a];
        if (!strcmp(s, "--help") || !strcmp(s, "-h")) {
            fputs(usage, stdout);
            return 0;
        } else if (!strcmp(s, "-o") || !strcmp(s, "--cell") || !strcmp(s, "--size") || !strcmp(s, "--up")) {
            const char *v = a + 1 < argc ? argv[a + 1] : NULL;
            if (!v) return tool_usage_error(TOOL, "%s needs a value", s);
            ++a;
            if (!strcmp(s, "-o")) o->out_path = v;
            else if (!strcmp(s, "--cell") && cli_parse_u32(v, 0, 0xfffffffeu, &o->cell)) return tool_usage_error(TOOL, "bad --cell '%s'", v);
            else if (!strcmp(s, "--size") && cli_parse_u32(v, 64, 8192, &o->map_h))
                return tool_usage_error(TOOL, "--size takes 64..8192, not '%s'", v);
            else if (!strcmp(s, "--up") && cli_parse_up(v, &o->up)) return tool_usage_error(TOOL, "--up takes y or z, not '%s'", v);
        } else if (!strcmp(s, "--cell-at")) {
            if (parse_floats(argv, a + 1, argc, 3, o->at)) return tool_usage_error(TOOL, "%s needs three numbers X Y Z", s);
            o->has_at = 1;
            a += 3;
        } else if (!strcmp(s, "--frame")) {
            if (parse_floats(argv, a + 1, argc, 6, o->frame)) return tool_usage_error(TOOL, "%s needs six numbers X Y Z DX DY DZ", s);
            o->has_frame = 1;
            a += 6;
        } else if (!strcmp(s, "--region")) {
            if (parse_floats(argv, a + 1, argc, 4, o->region) || !(o->region[2] > o->region[0]) || !(o->region[3] > o->region[1]))
                return tool_usage_error(TOOL, "%s needs U0 V0 U1 V1 with U0 < U1, V0 < V1", s);
            o->has_region = 1;
            a += 4;
        } else if (s[0] == '-' && s[1]) {
            return tool_usage_error(TOOL, "unknown option '%s'", s);
        } else if (!o->scene_path) {
            o->scene_path = s;
        } else if (!o->pvs_path) {
            o->pvs_path = s;
        } else {
            return tool_usage_error(TOOL, "unexpected argument '%s'", s);
        }
    }
    if (!o->scene_path || !o->pvs_path) return tool_usage_error(TOOL, "give SCENE.obj and FILE.pvs");
    if (!o->out_path) return tool_usage_error(TOOL, "no output given (-o OUT.png)");
    if (o->has_at && o->cell != PVS_NO_CELL) return tool_usage_error(TOOL, "give at most one of --cell and --cell-at");
    return -1;
}

/* Loads the file and the scene, finds the chosen cell and allocates the bitsets. 0, or -1 with te set. */
static int view_load(view_data *v, const view_options *o, tool_error *te) {
    if (cli_load_pvs_scene(o->pvs_path, o->scene_path, o->up, &v->data, &v->f, &v->m, &v->scene, te)) return -1;
    v->n = pvs_scene_object_count(v->scene);
    if (v->f.object_count != v->n) {
        tool_error_set(te, o->pvs_path, 0, "the file has %u objects but the scene has %u: not the same scene", v->f.object_count, v->n);
        return -1;
    }
    v->cell = o->cell;
    if (o->has_at) {
        v->cell = pvs_file_find_cell(&v->f, o->at);
        if (v->cell == PVS_NO_CELL) {
            tool_error_set(te, o->pvs_path, 0, "no cell contains %g %g %g", (double)o->at[0], (double)o->at[1], (double)o->at[2]);
            return -1;
        }
    }
    if (v->cell != PVS_NO_CELL && v->cell >= v->f.cell_count) {
        tool_error_set(te, o->pvs_path, 0, "cell %u: the file has %u cells", v->cell, v->f.cell_count);
        return -1;
    }
    v->up = pvs_scene_up_axis(v->scene);
    v->ui = 0;
    v->vi = v->up == 2 ? 1 : 2;
    v->words = (uint32_t)PVS_BITSET_WORDS(v->n);
    v->bits = (pvs_word *)calloc(v->words, sizeof(pvs_word));
    v->chosen = (pvs_word *)calloc(v->words, sizeof(pvs_word));
    v->order = (sized *)malloc((size_t)v->f.cell_count * sizeof(sized));
    if (!v->bits || !v->chosen || !v->order) {
        tool_error_set(te, NULL, 0, "out of memory");
        return -1;
    }
    return 0;
}

/* The PVS size of every cell, the cells in order of it, and the region: the one given, else the
   cells' ground bounds and a margin. */
static void view_sizes(view_data *v, const view_options *o) {
    float *r = v->region;
    uint32_t c;
    memcpy(r, o->region, sizeof(v->region));
    if (!o->has_region) {
        r[0] = r[1] = 1e30f;
        r[2] = r[3] = -1e30f;
    }
    v->smin = 0xffffffffu;
    v->smax = 0;
    v->mean = 0.0;
    for (c = 0; c < v->f.cell_count; ++c) {
        pvs_box b = pvs_file_cell_box(&v->f, c);
        pvs_file_decode(&v->f, c, v->bits, v->words, NULL);
        v->order[c].cell = c;
        v->order[c].size = pvs_bitset_count(v->bits, v->n);
        v->smin = v->order[c].size < v->smin ? v->order[c].size : v->smin;
        v->smax = v->order[c].size > v->smax ? v->order[c].size : v->smax;
        v->mean += v->order[c].size;
        if (!o->has_region) {
            r[0] = b.min[v->ui] < r[0] ? b.min[v->ui] : r[0];
            r[1] = b.min[v->vi] < r[1] ? b.min[v->vi] : r[1];
            r[2] = b.max[v->ui] > r[2] ? b.max[v->ui] : r[2];
            r[3] = b.max[v->vi] > r[3] ? b.max[v->vi] : r[3];
        }
    }
    v->mean /= v->f.cell_count;
    if (!o->has_region) {
        float mu = 0.05f * (r[2] - r[0]) + 1.0f, mv = 0.05f * (r[3] - r[1]) + 1.0f;
        r[0] -= mu; r[2] += mu; r[1] -= mv; r[3] += mv;
    }
    qsort(v->order, v->f.cell_count, sizeof(sized), cmp_sized);
    if (v->cell != PVS_NO_CELL) pvs_file_decode(&v->f, v->cell, v->chosen, v->words, NULL);
}

/* The map's scene and cells: flat objects (ground tiles, floors) dim, the others bright, green in the
   chosen PVS, grey not; then every cell in its heat colour, smallest PVS first, so the largest of a
   stack shows. */
static void draw_map_scene(const view_data *v, render_image *map, const render_view *view) {
    uint32_t i, c, up = v->up;
    for (i = 0; i < v->n; ++i) {
        pvs_box ob = pvs_scene_object_box(v->scene, i);
        int flat = !(ob.max[up] - ob.min[up] > 0.25f), in = v->cell != PVS_NO_CELL && pvs_bitset_test(v->chosen, i);
        uint32_t col = in ? (flat ? RENDER_RGBA(40, 100, 50, 255) : RENDER_RGBA(80, 235, 90, 255))
                          : (flat ? RENDER_RGBA(58, 58, 62, 255) : RENDER_RGBA(160, 160, 165, 255));
        render_triangles(map, view, v->m.positions, v->m.indices, v->m.objects[i].first_triangle, v->m.objects[i].triangle_count, col, 0);
    }
    for (c = 0; c < v->f.cell_count; ++c) {
        pvs_box b = pvs_file_cell_box(&v->f, v->order[c].cell);
        float p0[3], p1[3], x0, y0, x1, y1, t = v->smax > v->smin ? (float)(v->order[c].size - v->smin) / (float)(v->smax - v->smin) : 0.0f;
        memcpy(p0, b.min, sizeof(p0));
        memcpy(p1, b.max, sizeof(p1));
        p0[up] = p1[up] = b.max[up];
        if (render_project(view, map, p0, &x0, &y0, NULL) && render_project(view, map, p1, &x1, &y1, NULL)) {
            uint32_t col = render_heat(t);
            render_fill_rect(map, (int)floorf(x0 < x1 ? x0 : x1), (int)floorf(y0 < y1 ? y0 : y1), (int)ceilf(x0 < x1 ? x1 : x0) - 1,
                             (int)ceilf(y0 < y1 ? y1 : y0) - 1, (col & 0xffffff00u) | 200u);
        }
    }
}

/* The map's marks: the chosen cell outlined in white, the frame's eye and its field of view. */
static void draw_map_marks(const view_data *v, const view_options *o, render_image *map, const render_view *view) {
    if (v->cell != PVS_NO_CELL) {
        pvs_box b = pvs_file_cell_box(&v->f, v->cell);
        float p0[3], p1[3], x0, y0, x1, y1;
        memcpy(p0, b.min, sizeof(p0));
        memcpy(p1, b.max, sizeof(p1));
        if (render_project(view, map, p0, &x0, &y0, NULL) && render_project(view, map, p1, &x1, &y1, NULL)) {
            int k;
            for (k = 0; k < 3; ++k)
                render_rect(map, (int)(x0 < x1 ? x0 : x1) - k, (int)(y0 < y1 ? y0 : y1) - k, (int)(x0 < x1 ? x1 : x0) + k,
                            (int)(y0 < y1 ? y1 : y0) + k, RENDER_RGBA(255, 255, 255, 255));
        }
    }
    if (o->has_frame) {
        float e[3], x, y;
        memcpy(e, o->frame, sizeof(e));
        if (render_project(view, map, e, &x, &y, NULL)) {
            double yaw = atan2(o->frame[3 + v->vi], o->frame[3 + v->ui]), k;
            float q[3], qx, qy;
            for (k = -0.785; k <= 0.79; k += 1.57) {
                memcpy(q, e, sizeof(q));
                q[v->ui] += 40.0f * (float)cos(yaw + k);
                q[v->vi] += 40.0f * (float)sin(yaw + k);
                if (render_project(view, map, q, &qx, &qy, NULL)) render_line(map, x, y, qx, qy, RENDER_RGBA(255, 255, 255, 255), 2);
            }
            render_fill_rect(map, (int)x - 4, (int)y - 4, (int)x + 4, (int)y + 4, RENDER_RGBA(255, 255, 255, 255));
        }
    }
}

/* The map's legend (the heat scale of PVS sizes) and its title lines. */
static void draw_map_legend(const view_data *v, const view_options *o, render_image *map) {
    int lx = 10, ly = (int)o->map_h - 46, lw = 260, k;
    char text[256];
    render_fill_rect(map, lx - 6, ly - 20, lx + lw + 70, (int)o->map_h - 4, RENDER_RGBA(0, 0, 0, 200));
    for (k = 0; k < lw; ++k) render_fill_rect(map, lx + k, ly, lx + k, ly + 14, render_heat((float)k / (float)(lw - 1)));
    snprintf(text, sizeof(text), "PVS size per cell (objects), mean %.0f", v->mean);
    draw_text(map->rgba, map->width, map->height, lx, ly - 14, text, TOOL_RGBA(255, 255, 255, 255));
    snprintf(text, sizeof(text), "%u", v->smin);
    draw_text(map->rgba, map->width, map->height, lx, ly + 20, text, TOOL_RGBA(255, 255, 255, 255));
    snprintf(text, sizeof(text), "%u", v->smax);
    draw_text(map->rgba, map->width, map->height, lx + lw - 6 * (int)strlen(text), ly + 20, text, TOOL_RGBA(255, 255, 255, 255));
    snprintf(text, sizeof(text), "%s: %u cells, %u objects, method %s", o->pvs_path, v->f.cell_count, v->n, pvs_method_name(v->f.method));
    draw_text_scaled(map->rgba, map->width, map->height, 8, 8, text, TOOL_RGBA(255, 255, 255, 255), 2);
    if (v->cell != PVS_NO_CELL) {
        snprintf(text, sizeof(text), "cell %u (white outline): the %u objects of its PVS in green (ground dark green)", v->cell,
                 pvs_bitset_count(v->chosen, v->n));
        draw_text(map->rgba, map->width, map->height, 8, 30, text, TOOL_RGBA(120, 255, 130, 255));
    }
}

/* The top-down map of the region, map_h pixels high. 0, or -1 with te set. */
static int draw_map(const view_data *v, const view_options *o, render_image *map, tool_error *te) {
    const float *r = v->region;
    uint32_t map_w = (uint32_t)((double)o->map_h * (r[2] - r[0]) / (r[3] - r[1]) + 0.5);
    pvs_box sb = pvs_scene_bounds(v->scene);
    pvs_camera cam;
    render_view view;
    if (map_w < 64) map_w = 64;
    if (map_w > 8192) map_w = 8192;
    if (render_image_init(map, map_w, o->map_h)) {
        tool_error_set(te, NULL, 0, "out of memory");
        return -1;
    }
    render_top_camera(&cam, v->up, r[0], r[1], r[2], r[3], sb.max[v->up], map_w, o->map_h);
    render_view_init(&view, &cam, map);
    render_clear(map, RENDER_RGBA(24, 24, 28, 255));
    draw_map_scene(v, map, &view);
    draw_map_marks(v, o, map, &view);
    draw_map_legend(v, o, map);
    return 0;
}

/* The first-person frame (--frame) into fp: objects in the PVS of the eye's cell in their shade, the
   others red; *red gets the pixels showing objects outside the PVS. 0, or -1 with te set. */
static int draw_frame(view_data *v, const view_options *o, render_image *fp, uint64_t *red, tool_error *te) {
    const float *frame = o->frame;
    uint32_t fc = pvs_file_find_cell(&v->f, frame), x, y, i, w = o->map_h * 16 / 9, pass;
    float l = sqrtf(frame[3] * frame[3] + frame[4] * frame[4] + frame[5] * frame[5]);
    render_image ids;
    render_view view;
    pvs_camera cam;
    char text[256];
    if (fc == PVS_NO_CELL) {
        tool_error_set(te, o->pvs_path, 0, "--frame: no cell contains %g %g %g", (double)frame[0], (double)frame[1], (double)frame[2]);
        return -1;
    }
    if (!(l > 0.0f)) {
        tool_error_set(te, NULL, 0, "--frame: the direction is zero");
        return -1;
    }
    pvs_file_decode(&v->f, fc, v->bits, v->words, NULL);
    if (render_image_init(fp, w, o->map_h) || render_image_init(&ids, w, o->map_h)) {
        tool_error_set(te, NULL, 0, "out of memory");
        return -1;
    }
    memset(&cam, 0, sizeof(cam));
    memcpy(cam.eye, frame, sizeof(cam.eye));
    memcpy(cam.forward, frame + 3, sizeof(cam.forward));
    cam.up[v->up] = 1.0f;
    cam.fov_y = 1.0f;
    cam.near_plane = 0.05f;
    render_view_init(&view, &cam, fp);
    render_clear(fp, RENDER_RGBA(150, 185, 225, 255));
    render_clear(&ids, RENDER_RGBA(0, 0, 0, 255));
    /* pass 0: what blocks sight (occluders dark, never counted); pass 1, the marker image only: see-through objects
       outside the PVS over a fresh image of what blocks (they block nothing, so each is seen where nothing opaque
       hides it) */
    for (pass = 0; pass < 2; ++pass) {
        if (pass) render_clear(&ids, RENDER_RGBA(0, 0, 0, 255));
        for (i = 0; i < v->n; ++i) {
            int in = pvs_bitset_test(v->bits, i);
            uint32_t h = i * 2654435761u, first = v->m.objects[i].first_triangle, count = v->m.objects[i].triangle_count;
            uint32_t fl = v->m.objects[i].flags, marker = fl & MESH_OBJECT_OCCLUDER ? RENDER_RGBA(0, 255, 0, 255)
                                                        : in ? RENDER_RGBA(0, 0, 255, 255) : RENDER_RGBA(255, 0, 0, 255);
            pvs_box ob = pvs_scene_object_box(v->scene, i);
            uint32_t col = fl & MESH_OBJECT_OCCLUDER ? RENDER_RGBA(70, 70, 80, 255)
                           : !in ? RENDER_RGBA(255, 0, 0, 255)
                           : !(ob.max[v->up] - ob.min[v->up] > 0.25f) ? RENDER_RGBA(125, 125, 118, 255)
                           : RENDER_RGBA(170 + (h >> 27), 165 + ((h >> 22) & 31), 140 + ((h >> 17) & 31), 255);
            unsigned front = fl & MESH_OBJECT_ONE_SIDED ? RENDER_FRONT_ONLY : 0u; /* as drawn */
            int see = (fl & MESH_OBJECT_SEE_THROUGH) != 0;
            if (pass && see && in) continue;
            if (!pass) render_triangles(fp, &view, v->m.positions, v->m.indices, first, count, col, front);
            /* the same in flat marker colours: which pixels belong to objects outside the PVS */
            if (see == (int)pass || (pass && !see))
                render_triangles(&ids, &view, v->m.positions, v->m.indices, first, count, pass && !see ?
                                 RENDER_RGBA(0, 255, 0, 255) : marker, RENDER_UNLIT | front);
        }
        for (y = 0; y < ids.height; ++y)
            for (x = 0; x < ids.width; ++x) *red += ids.rgba[4 * ((size_t)y * ids.width + x)] == 255;
    }
    render_image_free(&ids);
    render_fill_rect(fp, 0, 0, (int)fp->width - 1, 34, RENDER_RGBA(0, 0, 0, 170));
    snprintf(text, sizeof(text), "from %g %g %g (cell %u, PVS %u objects)", (double)frame[0], (double)frame[1], (double)frame[2], fc,
             pvs_bitset_count(v->bits, v->n));
    draw_text(fp->rgba, fp->width, fp->height, 6, 4, text, TOOL_RGBA(255, 255, 255, 255));
    snprintf(text, sizeof(text), "red = objects outside the PVS; visible red pixels: %llu (0 for a conservative PVS)", (unsigned long long)*red);
    draw_text(fp->rgba, fp->width, fp->height, 6, 18, text, *red ? TOOL_RGBA(255, 90, 90, 255) : TOOL_RGBA(160, 255, 160, 255));
    return 0;
}

/* The map and, with a frame, the frame beside it (6 pixels apart) as one PNG. 0, or -1 with te set. */
static int write_image(const render_image *map, const render_image *fp, int has_frame, const char *path, tool_error *te) {
    render_image out;
    uint32_t w = map->width + (has_frame ? fp->width + 6 : 0), y;
    int r;
    memset(&out, 0, sizeof(out));
    if (render_image_init(&out, w, map->height)) {
        tool_error_set(te, NULL, 0, "out of memory");
        return -1;
    }
    for (y = 0; y < map->height; ++y) {
        memcpy(out.rgba + 4 * (size_t)y * w, map->rgba + 4 * (size_t)y * map->width, 4 * (size_t)map->width);
        if (has_frame) memcpy(out.rgba + 4 * ((size_t)y * w + map->width + 6), fp->rgba + 4 * (size_t)y * fp->width, 4 * (size_t)fp->width);
    }
    r = png_write(path, out.rgba, w, map->height, te);
    render_image_free(&out);
    return r;
}

int main(int argc, char **argv) {
    view_options o;
    view_data v;
    render_image map, fp;
    tool_error te;
    uint64_t red = 0;
    int rc = parse_options(argc, argv, &o);
    if (rc >= 0) return rc;
    memset(&v, 0, sizeof(v));
    memset(&map, 0, sizeof(map));
    memset(&fp, 0, sizeof(fp));
    mesh_init(&v.m);
    if (view_load(&v, &o, &te)) goto fail;
    view_sizes(&v, &o);
    if (draw_map(&v, &o, &map, &te)) goto fail;
    if (o.has_frame && draw_frame(&v, &o, &fp, &red, &te)) goto fail;
    if (write_image(&map, &fp, o.has_frame, o.out_path, &te)) goto fail;
    printf("%s: %u cells, PVS size min %u, mean %.1f, max %u", o.out_path, v.f.cell_count, v.smin, v.mean, v.smax);
    if (v.cell != PVS_NO_CELL) printf("; cell %u: %u objects", v.cell, pvs_bitset_count(v.chosen, v.n));
    if (o.has_frame) printf("; frame: %llu pixels of objects outside the PVS", (unsigned long long)red);
    printf("\n");
    rc = o.has_frame && red ? 3 : 0;
    goto done;
fail:
    fprintf(stderr, "pvsview: %s\n", te.message);
    rc = 1;
done:
    render_image_free(&map);
    render_image_free(&fp);
    free(v.bits);
    free(v.chosen);
    free(v.order);
    pvs_scene_destroy(v.scene);
    mesh_free(&v.m);
    free(v.data);
    return rc;
}
