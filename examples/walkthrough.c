/* walkthrough.c - a recorded walkthrough of the demo city with baked PVSs and per-frame culling, the
   experiment of Wonka, Wimmer & Schmalstieg 2000 (Fig. 5) on the two-part path of Wonka &
   Schmalstieg 1999 (§6: part 1 along closed streets, part 2 in a wide-open area: here the open
   square and the straight avenue).

   Per frame it counts the objects and triangles an engine would draw
     frustum   with view-frustum culling only,
     pvs       with the cell's PVS (and the frustum),
     pvs+cull  with the PVS and per-frame occlusion culling (pvs_raster_cull: the nearest scene
               triangles as occluders into a depth pyramid, the PVS as candidates).
   The PVS comes from a .pvs file opened in place and followed with a cursor (the runtime path of an
   engine): --pvs FILE (a bake of the demo city, e.g. build/demo/city.pvs from make demo), or else
   the cells the path visits are baked here with --method (default otree).

   Writes into OUTDIR (default build/demo):
     walkthrough.csv   one line per frame: the three curves in objects and triangles
     walkthrough.png   the curves on a log scale (objects above, triangles below), part 2 shaded
     frame_1_street.png, frame_2_street.png, frame_3_square.png, frame_4_avenue.png: four frames
                       rendered with the software renderer (tools/render.h), each in three panels:
                       what is drawn; the same with an X-ray of the objects in the frustum that are
                       not drawn (red = culled by the cell's PVS, orange = in the PVS but culled per
                       frame); the surroundings from above. The caption counts the pixels that differ
                       from drawing everything in the frustum (0: nothing visible was culled)
     path.png          the city from above with the path, part 1 blue, part 2 orange
   --bench prints BENCH lines instead (walkthrough_speedup = frustum triangles / pvs+cull triangles,
   averaged over the path) and writes nothing.
   Usage: pvswalkthrough [-o OUTDIR] [--pvs FILE | --method NAME] [-j THREADS] [--step METRES] [--bench] */
#include "../tools/cli.h"
#include "../tools/render.h"
#include <math.h>
#include <stdlib.h>
#include <string.h>

#define FRAME_W 960
#define FRAME_H 540
#define EYE_HEIGHT 1.7f

typedef struct cellgraph {
    uint32_t n;
    uint32_t *first, *adj;  /* CSR adjacency */
    float *portal;          /* per adjacency entry: the shared face's centre (x, z) */
} cellgraph;

/* Cells touching along a face segment of at least 0.5 m on the ground are neighbours. */
static int build_graph(const mesh_cells *cells, uint32_t n, cellgraph *g) {
    uint32_t i, j, cap = 16 * n + 16, used = 0;
    memset(g, 0, sizeof(*g));
    g->n = n;
    g->first = (uint32_t *)calloc((size_t)n + 1, sizeof(uint32_t));
    g->adj = (uint32_t *)malloc(cap * sizeof(uint32_t));
    g->portal = (float *)malloc(2 * (size_t)cap * sizeof(float));
    if (!g->first || !g->adj || !g->portal) return -1;
    for (i = 0; i < n; ++i) {
        const float *a = cells->boxes + 6 * (size_t)i;
        g->first[i] = used;
        for (j = 0; j < n; ++j) {
            const float *b = cells->boxes + 6 * (size_t)j;
            float ox = (a[3] < b[3] ? a[3] : b[3]) - (a[0] > b[0] ? a[0] : b[0]);
            float oz = (a[5] < b[5] ? a[5] : b[5]) - (a[2] > b[2] ? a[2] : b[2]);
            float px, pz;
            if (i == j) continue;
            if (ox > -1e-3f && ox < 1e-3f && oz > 0.5f) {
                px = a[3] < b[3] ? a[3] : b[3];
                pz = 0.5f * ((a[2] > b[2] ? a[2] : b[2]) + (a[5] < b[5] ? a[5] : b[5]));
            } else if (oz > -1e-3f && oz < 1e-3f && ox > 0.5f) {
                pz = a[5] < b[5] ? a[5] : b[5];
                px = 0.5f * ((a[0] > b[0] ? a[0] : b[0]) + (a[3] < b[3] ? a[3] : b[3]));
            } else {
                continue;
            }
            if (used == cap) {
                cap *= 2;
                g->adj = (uint32_t *)realloc(g->adj, cap * sizeof(uint32_t));
                g->portal = (float *)realloc(g->portal, 2 * (size_t)cap * sizeof(float));
                if (!g->adj || !g->portal) return -1;
            }
            g->adj[used] = j;
            g->portal[2 * used] = px;
            g->portal[2 * used + 1] = pz;
            ++used;
        }
    }
    g->first[n] = used;
    return 0;
}

static void free_graph(cellgraph *g) {
    free(g->first);
    free(g->adj);
    free(g->portal);
}

static void cell_centre(const mesh_cells *cells, uint32_t c, float *x, float *z) {
    const float *b = cells->boxes + 6 * (size_t)c;
    *x = 0.5f * (b[0] + b[3]);
    *z = 0.5f * (b[2] + b[5]);
}

static uint32_t nearest_cell(const mesh_cells *cells, uint32_t n, float x, float z) {
    uint32_t c, best = 0;
    float bd = 1e30f;
    for (c = 0; c < n; ++c) {
        float cx, cz, d;
        cell_centre(cells, c, &cx, &cz);
        d = (cx - x) * (cx - x) + (cz - z) * (cz - z);
        if (d < bd) { bd = d; best = c; }
    }
    return best;
}

/* Shortest path a -> b over the cell graph (Dijkstra on centre distances, O(n^2): ~1200 cells),
   appended to the polyline pts (x, z pairs) through the portals between consecutive cells. */
static int route(const cellgraph *g, const mesh_cells *cells, uint32_t a, uint32_t b, float **pts, uint32_t *np, uint32_t *cap) {
    float *dist = (float *)malloc(g->n * sizeof(float));
    uint32_t *prev = (uint32_t *)malloc(g->n * sizeof(uint32_t)), *via = (uint32_t *)malloc(g->n * sizeof(uint32_t)), i, k;
    uint32_t *chain = (uint32_t *)malloc(g->n * sizeof(uint32_t)), len = 0;
    unsigned char *fixed = (unsigned char *)calloc(g->n, 1);
    if (!dist || !prev || !via || !chain || !fixed) return -1;
    for (i = 0; i < g->n; ++i) { dist[i] = 1e30f; prev[i] = 0xffffffffu; }
    dist[a] = 0.0f;
    for (;;) {
        uint32_t u = 0xffffffffu;
        float ux, uz;
        for (i = 0; i < g->n; ++i)
            if (!fixed[i] && dist[i] < 1e29f && (u == 0xffffffffu || dist[i] < dist[u])) u = i;
        if (u == 0xffffffffu || u == b) break;
        fixed[u] = 1;
        cell_centre(cells, u, &ux, &uz);
        for (k = g->first[u]; k < g->first[u + 1]; ++k) {
            uint32_t v = g->adj[k];
            float vx, vz, d;
            cell_centre(cells, v, &vx, &vz);
            d = dist[u] + sqrtf((vx - ux) * (vx - ux) + (vz - uz) * (vz - uz));
            if (d < dist[v]) { dist[v] = d; prev[v] = u; via[v] = k; }
        }
    }
    if (prev[b] == 0xffffffffu && a != b) {
        free(dist); free(prev); free(via); free(chain); free(fixed);
        return -1;
    }
    for (i = b; i != a; i = prev[i]) chain[len++] = i;
    /* the polyline: the portals in order, then b's centre */
    for (k = len; k-- > 0;) {
        uint32_t e = via[chain[k]];
        if (*np + 2 > *cap) {
            *cap = 2 * *cap + 64;
            *pts = (float *)realloc(*pts, 2 * (size_t)*cap * sizeof(float));
            if (!*pts) return -1;
        }
        (*pts)[2 * *np] = g->portal[2 * e];
        (*pts)[2 * *np + 1] = g->portal[2 * e + 1];
        ++*np;
    }
    if (*np + 1 > *cap) {
        *cap = 2 * *cap + 64;
        *pts = (float *)realloc(*pts, 2 * (size_t)*cap * sizeof(float));
        if (!*pts) return -1;
    }
    cell_centre(cells, b, &(*pts)[2 * *np], &(*pts)[2 * *np + 1]);
    ++*np;
    free(dist); free(prev); free(via); free(chain); free(fixed);
    return 0;
}

/* The point at arc length s along the polyline. */
static void along(const float *pts, uint32_t np, const double *arc, double s, float *x, float *z) {
    uint32_t i = 1;
    double t;
    if (s <= 0.0) { *x = pts[0]; *z = pts[1]; return; }
    while (i < np - 1 && arc[i] < s) ++i;
    if (s >= arc[np - 1]) { *x = pts[2 * (np - 1)]; *z = pts[2 * (np - 1) + 1]; return; }
    t = arc[i] > arc[i - 1] ? (s - arc[i - 1]) / (arc[i] - arc[i - 1]) : 0.0;
    *x = (float)(pts[2 * (i - 1)] + t * (pts[2 * i] - pts[2 * (i - 1)]));
    *z = (float)(pts[2 * (i - 1) + 1] + t * (pts[2 * i + 1] - pts[2 * (i - 1) + 1]));
}

typedef struct frame {
    float eye[3], fwd[3];
    int part;                 /* 1 or 2 */
    uint32_t cell;
    uint32_t obj[3];          /* frustum, pvs, pvs+cull */
    uint64_t tri[3];
    double cull_ms;
} frame;

/* A colour per object kind (by name), varied per id. */
static uint32_t object_colour(const mesh *m, uint32_t o) {
    const char *n = m->objects[o].name;
    uint32_t h = o * 2654435761u;
    if (!strncmp(n, "ground", 6)) return RENDER_RGBA(118, 118, 110, 255);
    if (!strncmp(n, "lamp", 4)) return RENDER_RGBA(70, 70, 80, 255);
    if (!strncmp(n, "kiosk", 5)) return RENDER_RGBA(60, 120, 90, 255);
    if (!strncmp(n, "monument", 8)) return RENDER_RGBA(215, 200, 150, 255);
    return RENDER_RGBA(190 + (h >> 27), 170 + ((h >> 22) & 31), 140 + ((h >> 17) & 31), 255);
}

static void camera_of(const frame *f, pvs_camera *cam) {
    memset(cam, 0, sizeof(*cam));
    memcpy(cam->eye, f->eye, sizeof(cam->eye));
    memcpy(cam->forward, f->fwd, sizeof(cam->forward));
    cam->up[1] = 1.0f;
    cam->fov_y = 1.0f; /* about 57 degrees vertically, 90 horizontally at 16:9 */
    cam->near_plane = 0.1f;
}

#define PANEL_W 640
#define PANEL_H 360
#define MAP_W 360
#define CAPTION_H 58

/* Draws the objects whose bit is set in `set` (all when NULL) into im. */
static void draw_objects(render_image *im, const render_view *v, const mesh *m, const pvs_word *set, uint32_t n) {
    uint32_t o;
    for (o = 0; o < n; ++o)
        if (!set || pvs_bitset_test(set, o))
            render_triangles(im, v, m->positions, m->indices, m->objects[o].first_triangle, m->objects[o].triangle_count, object_colour(m, o), 0);
}

/* One frame as three panels: what is drawn (PVS + per-frame culling); the same with an X-ray of
   what is not drawn although in the frustum (red: culled by the cell's PVS, orange: in the PVS but
   culled per frame); the surroundings from above. The drawn image is compared with a render of
   everything in the frustum: a conservative PVS and culling leave no pixel different. */
static int write_frame(const char *path, const mesh *m, const pvs_scene *scene, const frame *f, const pvs_word *vis_f, const pvs_word *pvs,
                       const pvs_word *vis_c, int index, uint64_t *diff_out, tool_error *te) {
    render_image drawn, ref, ghost, map, out;
    render_view view, mview;
    pvs_camera cam, top;
    uint32_t o, n = pvs_scene_object_count(scene), ghost_pvs = 0, ghost_frame = 0, x, y;
    uint64_t diff = 0;
    const uint32_t W = 2 * PANEL_W + MAP_W + 8, H = PANEL_H + CAPTION_H;
    char text[512];
    int rc;
    if (render_image_init(&drawn, PANEL_W, PANEL_H) || render_image_init(&ref, PANEL_W, PANEL_H) || render_image_init(&ghost, PANEL_W, PANEL_H) ||
        render_image_init(&map, MAP_W, PANEL_H) || render_image_init(&out, W, H))
        return -1;
    camera_of(f, &cam);
    render_view_init(&view, &cam, &drawn);
    render_clear(&drawn, RENDER_RGBA(150, 185, 225, 255));
    render_clear(&ref, RENDER_RGBA(150, 185, 225, 255));
    draw_objects(&drawn, &view, m, vis_c, n);
    draw_objects(&ref, &view, m, vis_f, n);
    for (x = 0; x < PANEL_W * PANEL_H; ++x) diff += memcmp(drawn.rgba + 4 * (size_t)x, ref.rgba + 4 * (size_t)x, 4) != 0;
    /* the X-ray: hidden objects in their own z-buffer, blended over the drawn image */
    for (o = 0; o < n; ++o) {
        const mesh_object *ob = m->objects + o;
        int in_pvs;
        if (pvs_bitset_test(vis_c, o) || !pvs_bitset_test(vis_f, o)) continue;
        in_pvs = pvs_bitset_test(pvs, o);
        render_triangles(&ghost, &view, m->positions, m->indices, ob->first_triangle, ob->triangle_count,
                         in_pvs ? RENDER_RGBA(255, 150, 20, 255) : RENDER_RGBA(235, 30, 30, 255), 0);
        if (in_pvs) ++ghost_frame; else ++ghost_pvs;
    }
    memcpy(ref.rgba, drawn.rgba, (size_t)PANEL_W * PANEL_H * 4);
    render_composite(&ref, &ghost, 0.6f);
    /* from above: 240 m around the eye, the frustum's ground trace */
    render_top_camera(&top, 1, f->eye[0] - 120.0f * MAP_W / PANEL_H, f->eye[2] - 120.0f, f->eye[0] + 120.0f * MAP_W / PANEL_H, f->eye[2] + 120.0f,
                      60.0f, MAP_W, PANEL_H);
    render_view_init(&mview, &top, &map);
    render_clear(&map, RENDER_RGBA(40, 40, 40, 255));
    for (o = 0; o < n; ++o) {
        const mesh_object *ob = m->objects + o;
        uint32_t col;
        if (!strncmp(ob->name, "ground", 6)) col = RENDER_RGBA(70, 70, 70, 255);
        else if (pvs_bitset_test(vis_c, o)) col = RENDER_RGBA(235, 235, 235, 255);
        else if (!pvs_bitset_test(vis_f, o)) col = RENDER_RGBA(110, 110, 120, 255);
        else if (pvs_bitset_test(pvs, o)) col = RENDER_RGBA(255, 150, 20, 255);
        else col = RENDER_RGBA(235, 30, 30, 255);
        render_triangles(&map, &mview, m->positions, m->indices, ob->first_triangle, ob->triangle_count, col, RENDER_UNLIT);
    }
    {
        float ex, ey, k;
        double yaw = atan2(f->fwd[2], f->fwd[0]), hx = atan(tan(0.5 * cam.fov_y) * PANEL_W / PANEL_H);
        if (render_project(&mview, &map, f->eye, &ex, &ey, NULL)) {
            for (k = -1.0f; k <= 1.0f; k += 2.0f) {
                float p[3], px, py;
                p[0] = f->eye[0] + 400.0f * (float)cos(yaw + k * hx);
                p[1] = f->eye[1];
                p[2] = f->eye[2] + 400.0f * (float)sin(yaw + k * hx);
                if (render_project(&mview, &map, p, &px, &py, NULL)) render_line(&map, ex, ey, px, py, RENDER_RGBA(80, 200, 255, 255), 1);
            }
            render_fill_rect(&map, (int)ex - 3, (int)ey - 3, (int)ex + 3, (int)ey + 3, RENDER_RGBA(80, 200, 255, 255));
        }
    }
    /* assemble */
    render_clear(&out, RENDER_RGBA(0, 0, 0, 255));
    for (y = 0; y < PANEL_H; ++y) {
        memcpy(out.rgba + 4 * ((size_t)(y + CAPTION_H) * W), drawn.rgba + 4 * (size_t)y * PANEL_W, 4 * PANEL_W);
        memcpy(out.rgba + 4 * ((size_t)(y + CAPTION_H) * W + PANEL_W + 4), ref.rgba + 4 * (size_t)y * PANEL_W, 4 * PANEL_W);
        memcpy(out.rgba + 4 * ((size_t)(y + CAPTION_H) * W + 2 * PANEL_W + 8), map.rgba + 4 * (size_t)y * MAP_W, 4 * MAP_W);
    }
    snprintf(text, sizeof(text), "frame %d, part %d (%s), cell %u", index, f->part, f->part == 1 ? "closed streets" : "open square and avenue",
             f->cell);
    draw_text_scaled(out.rgba, W, H, 6, 4, text, TOOL_RGBA(255, 255, 255, 255), 2);
    snprintf(text, sizeof(text), "left: drawn with the PVS + per-frame culling: %u objects, %llu triangles (frustum culling: %u, %llu); "
             "pixels differing from drawing the whole frustum: %llu",
             f->obj[2], (unsigned long long)f->tri[2], f->obj[0], (unsigned long long)f->tri[0], (unsigned long long)diff);
    draw_text(out.rgba, W, H, 6, 24, text, TOOL_RGBA(255, 255, 255, 255));
    snprintf(text, sizeof(text), "middle: x-ray of the objects in the frustum not drawn: red = culled by the cell's PVS (%u), orange = in the PVS, "
             "culled per frame (%u)", ghost_pvs, ghost_frame);
    draw_text(out.rgba, W, H, 6, 36, text, TOOL_RGBA(255, 200, 160, 255));
    snprintf(text, sizeof(text), "right: from above, 240 m: white drawn, red/orange culled, grey outside the frustum; blue: eye and frustum");
    draw_text(out.rgba, W, H, 6, 48, text, TOOL_RGBA(170, 220, 255, 255));
    rc = png_write(path, out.rgba, W, H, te);
    if (diff_out) *diff_out = diff;
    render_image_free(&drawn);
    render_image_free(&ref);
    render_image_free(&ghost);
    render_image_free(&map);
    render_image_free(&out);
    return rc;
}

/* The three curves on a log scale: objects (top panel) and triangles (bottom panel). */
static int write_plot(const char *path, const frame *fr, uint32_t nf, uint32_t part2, tool_error *te) {
    const uint32_t W = 1000, H = 760, L = 70, R = 20, T = 40, PH = 300, GAP = 44;
    static const uint32_t colours[3] = {RENDER_RGBA(120, 120, 120, 255), RENDER_RGBA(40, 110, 220, 255), RENDER_RGBA(220, 60, 40, 255)};
    static const char *names[3] = {"frustum culling only", "the cell's PVS", "PVS + per-frame culling"};
    render_image im;
    int panel, k, rc;
    uint32_t i;
    char text[128];
    if (render_image_init(&im, W, H)) return -1;
    render_clear(&im, RENDER_RGBA(255, 255, 255, 255));
    draw_text_scaled(im.rgba, W, H, L, 8, "walkthrough of the demo city: drawn per frame (log scale)", TOOL_RGBA(0, 0, 0, 255), 2);
    for (panel = 0; panel < 2; ++panel) {
        int y0 = (int)(T + (uint32_t)panel * (PH + GAP)), y1 = y0 + (int)PH;
        double lo = 1e30, hi = 1.0, llo, lhi;
        for (i = 0; i < nf; ++i)
            for (k = 0; k < 3; ++k) {
                double v = panel ? (double)fr[i].tri[k] : (double)fr[i].obj[k];
                if (v < 1.0) v = 1.0;
                lo = v < lo ? v : lo;
                hi = v > hi ? v : hi;
            }
        llo = floor(log10(lo));
        lhi = ceil(log10(hi));
        if (lhi <= llo) lhi = llo + 1;
        /* part 2 shaded, decade grid lines and labels */
        render_fill_rect(&im, L + (int)((double)part2 / nf * (W - L - R)), y0, (int)W - (int)R, y1, RENDER_RGBA(255, 236, 200, 255));
        for (k = (int)llo; k <= (int)lhi; ++k) {
            int y = y1 - (int)((k - llo) / (lhi - llo) * PH);
            render_fill_rect(&im, L, y, (int)W - (int)R, y, RENDER_RGBA(210, 210, 210, 255));
            snprintf(text, sizeof(text), "1e%d", k);
            draw_text(im.rgba, W, H, 8, y - 4, text, TOOL_RGBA(0, 0, 0, 255));
        }
        render_rect(&im, L, y0, (int)W - (int)R, y1, RENDER_RGBA(0, 0, 0, 255));
        for (i = 0; i < nf; i += 100) { /* frame ticks */
            int x = L + (int)((double)i / (nf - 1) * (W - L - R));
            render_fill_rect(&im, x, y1, x, y1 + 4, RENDER_RGBA(0, 0, 0, 255));
            snprintf(text, sizeof(text), "%u", i);
            draw_text(im.rgba, W, H, x - 3 * (int)strlen(text), y1 + 7, text, TOOL_RGBA(0, 0, 0, 255));
        }
        draw_text(im.rgba, W, H, L + 6, y0 + 6, panel ? "triangles" : "objects", TOOL_RGBA(0, 0, 0, 255));
        draw_text(im.rgba, W, H, L + (int)((double)part2 / nf * (W - L - R)) + 6, y0 + 6, "part 2: open square, avenue",
                  TOOL_RGBA(150, 90, 0, 255));
        for (k = 0; k < 3; ++k)
            for (i = 1; i < nf; ++i) {
                double a = panel ? (double)fr[i - 1].tri[k] : (double)fr[i - 1].obj[k], b = panel ? (double)fr[i].tri[k] : (double)fr[i].obj[k];
                float xa = (float)(L + (double)(i - 1) / (nf - 1) * (W - L - R)), xb = (float)(L + (double)i / (nf - 1) * (W - L - R));
                float ya = (float)(y1 - (log10(a < 1 ? 1 : a) - llo) / (lhi - llo) * PH), yb = (float)(y1 - (log10(b < 1 ? 1 : b) - llo) / (lhi - llo) * PH);
                render_line(&im, xa, ya, xb, yb, colours[k], 2);
            }
    }
    for (k = 0; k < 3; ++k) {
        int x = L + 10 + k * 300, y = (int)(T + 2 * PH + GAP) + 26;
        render_fill_rect(&im, x, y + 2, x + 24, y + 4, colours[k]);
        draw_text(im.rgba, W, H, x + 30, y, names[k], TOOL_RGBA(0, 0, 0, 255));
    }
    draw_text(im.rgba, W, H, L, (int)H - 14, "frame (2 m per frame along the path)", TOOL_RGBA(0, 0, 0, 255));
    rc = png_write(path, im.rgba, W, H, te);
    render_image_free(&im);
    return rc;
}

/* The city from above with the path. */
static int write_path_png(const char *path, const mesh *m, const pvs_scene *scene, const frame *fr, uint32_t nf, tool_error *te) {
    render_image im;
    render_view view;
    pvs_camera cam;
    pvs_box b = pvs_scene_bounds(scene);
    uint32_t o, i;
    int rc;
    if (render_image_init(&im, 800, 800)) return -1;
    render_top_camera(&cam, 1, b.min[0], b.min[2], b.max[0], b.max[2], b.max[1], 800, 800);
    render_view_init(&view, &cam, &im);
    render_clear(&im, RENDER_RGBA(30, 30, 30, 255));
    for (o = 0; o < m->object_count; ++o)
        render_triangles(&im, &view, m->positions, m->indices, m->objects[o].first_triangle, m->objects[o].triangle_count, object_colour(m, o), 0);
    for (i = 1; i < nf; ++i) {
        float xa, ya, xb, yb;
        if (render_project(&view, &im, fr[i - 1].eye, &xa, &ya, NULL) && render_project(&view, &im, fr[i].eye, &xb, &yb, NULL))
            render_line(&im, xa, ya, xb, yb, fr[i].part == 1 ? RENDER_RGBA(30, 90, 255, 255) : RENDER_RGBA(255, 120, 0, 255), 3);
    }
    draw_text_scaled(im.rgba, 800, 800, 8, 8, "walkthrough path: part 1 blue, part 2 orange", TOOL_RGBA(255, 255, 255, 255), 2);
    rc = png_write(path, im.rgba, 800, 800, te);
    render_image_free(&im);
    return rc;
}

static uint64_t triangles_of(const mesh *m, const pvs_word *bits, uint32_t n) {
    uint64_t t = 0;
    uint32_t i;
    for (i = pvs_bitset_next(bits, n, 0); i < n; i = pvs_bitset_next(bits, n, i + 1)) t += m->objects[i].triangle_count;
    return t;
}

int main(int argc, char **argv) {
    const char *dir = "build/demo", *pvs_path = NULL;
    pvs_method method = PVS_METHOD_OTREE;
    uint32_t threads = 2, n, words, c, i, np = 0, cap = 0, nf, part2 = 0, regular;
    int bench = 0, a;
    uint32_t occluders = 512;
    float occluder_distance = 150.0f;
    float step = 2.0f;
    gen_params gp;
    gen_info info;
    mesh m;
    mesh_cells cells;
    pvs_scene *scene = NULL;
    tool_error te;
    pvs_error pe;
    cellgraph g;
    float *pts = NULL, mx = 0, mz = 0, avenue_z = 0;
    double *arc, len, t0;
    frame *fr;
    void *file_bytes = NULL;
    size_t file_size = 0;
    pvs_file file;
    pvs_cursor cursor;
    pvs_word *cur, *scratch, *vis_f, *vis_p, *vis_c;
    pvs_raster *raster;
    pvs_raster_desc rd;
    char path[1024];
    double sum[3][2] = {{0}}, sum_part[2][3] = {{0}}, cull_ms = 0.0;
    uint32_t frames_part[2] = {0, 0};
    uint64_t diff_total = 0;

    for (a = 1; a < argc; ++a) {
        if (!strcmp(argv[a], "-o") && a + 1 < argc) dir = argv[++a];
        else if (!strcmp(argv[a], "--pvs") && a + 1 < argc) pvs_path = argv[++a];
        else if (!strcmp(argv[a], "--bench")) bench = 1;
        else if (!strcmp(argv[a], "-j") && a + 1 < argc) {
            if (parse_threads(argv[++a], &threads)) { fprintf(stderr, "walkthrough: bad -j\n"); return 2; }
        } else if (!strcmp(argv[a], "--step") && a + 1 < argc) {
            if (parse_float(argv[++a], &step) || !(step >= 0.25f)) { fprintf(stderr, "walkthrough: --step takes metres >= 0.25\n"); return 2; }
        } else if (!strcmp(argv[a], "--method") && a + 1 < argc) {
            int k;
            ++a;
            for (k = 1; k < PVS_METHOD_COUNT; ++k)
                if (!strcmp(argv[a], pvs_method_name((pvs_method)k))) method = (pvs_method)k;
            if (strcmp(argv[a], pvs_method_name(method))) { fprintf(stderr, "walkthrough: unknown method '%s'\n", argv[a]); return 2; }
        } else {
            fprintf(stderr, "usage: pvswalkthrough [-o OUTDIR] [--pvs FILE | --method NAME] [-j THREADS] [--step METRES] [--bench]\n");
            return 2;
        }
    }
    t0 = cli_seconds();
    memset(&gp, 0, sizeof(gp));
    gp.kind = GEN_CITY;
    gp.seed = 1;
    gp.size = 1.0f;
    mesh_init(&m);
    mesh_cells_init(&cells);
    if (gen_scene_ex(&gp, &m, &cells, &info) || cli_make_scene("city", &m, 1, &scene, &te)) {
        fprintf(stderr, "walkthrough: cannot build the demo city\n");
        return 1;
    }
    n = pvs_scene_object_count(scene);
    words = (uint32_t)PVS_BITSET_WORDS(n);
    regular = info.regular_count;

    /* ---- the path ---- */
    for (i = 0; i < m.object_count; ++i)
        if (!strcmp(m.objects[i].name, "monument_0")) {
            pvs_box mb = pvs_scene_object_box(scene, i);
            mx = 0.5f * (mb.min[0] + mb.max[0]);
            mz = 0.5f * (mb.min[2] + mb.max[2]);
        }
    {
        /* the avenue: the first line north (+z) of the square that cells cover along most of the city */
        pvs_box sb = pvs_scene_bounds(scene);
        float width = sb.max[0] - sb.min[0], z, best = 0.0f, run0 = 0.0f;
        int in_run = 0;
        for (z = mz; z < mz + 200.0f; z += 0.5f) {
            float covered = 0.0f;
            for (c = 0; c < regular; ++c) {
                const float *bx = cells.boxes + 6 * (size_t)c;
                if (bx[2] <= z && z <= bx[5]) covered += bx[3] - bx[0];
            }
            if (covered > 0.6f * width) {
                if (!in_run) { in_run = 1; run0 = z; }
            } else if (in_run) {
                best = 0.5f * (run0 + z);
                break;
            }
        }
        avenue_z = best > 0.0f ? best : mz + 60.0f;
        if (build_graph(&cells, regular, &g)) { fprintf(stderr, "walkthrough: out of memory\n"); return 1; }
        {
            uint32_t p0 = nearest_cell(&cells, regular, sb.min[0] + 0.22f * width, sb.min[2] + 0.2f * (sb.max[2] - sb.min[2]));
            uint32_t p1 = nearest_cell(&cells, regular, mx - 18.0f, mz);
            uint32_t p2 = nearest_cell(&cells, regular, mx, avenue_z);
            uint32_t p3 = nearest_cell(&cells, regular, sb.max[0] - 0.1f * width, avenue_z);
            cap = 64;
            pts = (float *)malloc(2 * (size_t)cap * sizeof(float));
            cell_centre(&cells, p0, &pts[0], &pts[1]);
            np = 1;
            if (route(&g, &cells, p0, p1, &pts, &np, &cap) || route(&g, &cells, p1, p2, &pts, &np, &cap) ||
                route(&g, &cells, p2, p3, &pts, &np, &cap)) {
                fprintf(stderr, "walkthrough: the cells do not connect the path's waypoints\n");
                return 1;
            }
        }
        free_graph(&g);
    }
    arc = (double *)malloc(np * sizeof(double));
    arc[0] = 0.0;
    for (i = 1; i < np; ++i)
        arc[i] = arc[i - 1] + sqrt((double)(pts[2 * i] - pts[2 * i - 2]) * (pts[2 * i] - pts[2 * i - 2]) +
                                   (double)(pts[2 * i + 1] - pts[2 * i - 1]) * (pts[2 * i + 1] - pts[2 * i - 1]));
    len = arc[np - 1];
    nf = (uint32_t)(len / step) + 1;
    fr = (frame *)calloc(nf, sizeof(frame));
    for (i = 0; i < nf; ++i) {
        float x, z, ax, az, dx, dz, l;
        along(pts, np, arc, i * (double)step, &x, &z);
        along(pts, np, arc, i * (double)step + 12.0, &ax, &az); /* look 12 m ahead: a smooth heading */
        dx = ax - x;
        dz = az - z;
        l = sqrtf(dx * dx + dz * dz);
        if (!(l > 1e-3f)) { dx = i ? fr[i - 1].fwd[0] : 1.0f; dz = i ? fr[i - 1].fwd[2] : 0.0f; l = 1.0f; }
        fr[i].eye[0] = x; fr[i].eye[1] = EYE_HEIGHT; fr[i].eye[2] = z;
        fr[i].fwd[0] = dx / l; fr[i].fwd[1] = -0.03f; fr[i].fwd[2] = dz / l;
        fr[i].part = (part2 || (x - mx) * (x - mx) + (z - mz) * (z - mz) < 45.0f * 45.0f) ? 2 : 1;
        if (fr[i].part == 2 && !part2) part2 = i;
    }
    if (!part2) part2 = nf;

    /* ---- the PVS: a given file, or a bake of the cells the path visits ---- */
    if (pvs_path) {
        tool_error fe;
        if (read_file(pvs_path, &file_bytes, &file_size, &fe)) { fprintf(stderr, "walkthrough: %s\n", fe.message); return 1; }
    } else {
        pvs_box *vis_cells = (pvs_box *)malloc(cells.count * sizeof(pvs_box));
        unsigned char *used = (unsigned char *)calloc(cells.count, 1);
        uint32_t nc = 0;
        pvs_bake_desc bd;
        pvs_bake *bake = NULL;
        for (i = 0; i < nf; ++i) /* every cell containing a frame's eye */
            for (c = 0; c < cells.count; ++c) {
                const float *b = cells.boxes + 6 * (size_t)c;
                if (!used[c] && b[0] <= fr[i].eye[0] && fr[i].eye[0] <= b[3] && b[1] <= fr[i].eye[1] && fr[i].eye[1] <= b[4] &&
                    b[2] <= fr[i].eye[2] && fr[i].eye[2] <= b[5])
                    used[c] = 1;
            }
        for (c = 0; c < cells.count; ++c)
            if (used[c]) memcpy(vis_cells + nc++, cells.boxes + 6 * (size_t)c, sizeof(pvs_box));
        memset(&bd, 0, sizeof(bd));
        bd.scene = scene;
        bd.cells = vis_cells;
        bd.cell_count = nc;
        bd.method = method;
        if (!bench) fprintf(stderr, "walkthrough: baking the %u cells along the path with %s (%u threads)\n", nc, pvs_method_name(method), threads);
        if (pvs_bake_begin(&bd, &bake, &pe) != PVS_OK) { fprintf(stderr, "walkthrough: %s\n", pe.message); return 1; }
        if (cli_run_bake(bake, threads, bench, "bake", &te)) { fprintf(stderr, "walkthrough: %s\n", te.message); return 1; }
        file_size = pvs_bake_file_size(bake);
        file_bytes = malloc(file_size);
        if (!file_bytes || pvs_bake_write_file(bake, file_bytes, file_size, &file_size, &pe) != PVS_OK) {
            fprintf(stderr, "walkthrough: cannot encode the bake\n");
            return 1;
        }
        if (!bench) {
            snprintf(path, sizeof(path), "%s/walkthrough.pvs", dir);
            if (write_file_atomic(path, file_bytes, file_size, &te)) { fprintf(stderr, "walkthrough: %s\n", te.message); return 1; }
        }
        pvs_bake_destroy(bake);
        free(vis_cells);
        free(used);
    }
    if (pvs_file_open(file_bytes, file_size, &file, &pe) != PVS_OK) { fprintf(stderr, "walkthrough: %s\n", pe.message); return 1; }
    if (file.object_count != n) { fprintf(stderr, "walkthrough: the .pvs file is not of the demo city (%u objects)\n", file.object_count); return 1; }

    /* ---- the frames ---- */
    cur = (pvs_word *)calloc(words, sizeof(pvs_word));
    scratch = (pvs_word *)calloc(words, sizeof(pvs_word));
    vis_f = (pvs_word *)calloc(words, sizeof(pvs_word));
    vis_p = (pvs_word *)calloc(words, sizeof(pvs_word));
    vis_c = (pvs_word *)calloc(words, sizeof(pvs_word));
    pvs_cursor_init(&cursor, &file, cur, scratch, words, NULL);
    memset(&rd, 0, sizeof(rd));
    rd.width = 640;
    rd.height = 360;
    rd.scene = scene;
    rd.max_occluders = 2048;
    if (pvs_raster_create(&rd, &raster, &pe) != PVS_OK) { fprintf(stderr, "walkthrough: %s\n", pe.message); return 1; }
    {
        int shots[4], s;
        shots[0] = (int)(part2 * 0.3);
        shots[1] = (int)(part2 * 0.8);
        shots[2] = (int)part2;
        { /* in the square: the frame looking most directly at the monument, 10 m away or more */
            double best = -2.0;
            for (i = part2; i < nf && i < part2 + 80; ++i) {
                double dx = mx - fr[i].eye[0], dz = mz - fr[i].eye[2], d = sqrt(dx * dx + dz * dz), cs;
                if (d < 10.0) continue;
                cs = (dx * fr[i].fwd[0] + dz * fr[i].fwd[2]) / d;
                if (cs > best) { best = cs; shots[2] = (int)i; }
            }
        }
        shots[3] = (int)(part2 + (nf - part2) * 0.6);
        for (i = 0; i < nf; ++i) {
            pvs_camera cam;
            pvs_cull_params cp;
            pvs_cull_stats st;
            double tc;
            frame *f = fr + i;
            camera_of(f, &cam);
            f->cell = pvs_file_find_cell(&file, f->eye);
            pvs_cursor_move(&cursor, f->cell, NULL, NULL);
            if (f->cell == PVS_NO_CELL) { /* not in a baked cell (a gap between cells): everything */
                memset(cur, 0xff, words * sizeof(pvs_word));
                if (n & 63u) cur[words - 1] &= ((pvs_word)1 << (n & 63u)) - 1;
            }
            memset(&cp, 0, sizeof(cp));
            cp.occluder_flags = PVS_CULL_FRUSTUM_ONLY;
            pvs_raster_cull(raster, scene, &cam, &cp, vis_f, NULL, NULL);   /* frustum only */
            cp.candidates = cur;
            pvs_raster_cull(raster, scene, &cam, &cp, vis_p, NULL, NULL);   /* PVS and frustum */
            cp.occluder_flags = 0;
            cp.scene_occluders = occluders;
            cp.occluder_distance = occluder_distance;
            tc = cli_seconds();
            pvs_raster_cull(raster, scene, &cam, &cp, vis_c, &st, NULL);    /* PVS + per-frame culling */
            f->cull_ms = 1000.0 * (cli_seconds() - tc);
            cull_ms += f->cull_ms;
            f->obj[0] = pvs_bitset_count(vis_f, n); f->tri[0] = triangles_of(&m, vis_f, n);
            f->obj[1] = pvs_bitset_count(vis_p, n); f->tri[1] = triangles_of(&m, vis_p, n);
            f->obj[2] = pvs_bitset_count(vis_c, n); f->tri[2] = triangles_of(&m, vis_c, n);
            for (a = 0; a < 3; ++a) {
                sum[a][0] += f->obj[a];
                sum[a][1] += (double)f->tri[a];
                sum_part[f->part - 1][a] += (double)f->tri[a];
            }
            frames_part[f->part - 1]++;
            if (!bench)
                for (s = 0; s < 4; ++s)
                    if ((int)i == shots[s]) {
                        static const char *names[4] = {"frame_1_street", "frame_2_street", "frame_3_square", "frame_4_avenue"};
                        snprintf(path, sizeof(path), "%s/%s.png", dir, names[s]);
                        uint64_t diff = 0;
                        if (write_frame(path, &m, scene, f, vis_f, cur, vis_c, (int)i, &diff, &te)) { fprintf(stderr, "walkthrough: %s\n", te.message); return 1; }
                        printf("wrote %s (%llu pixels differ from drawing everything in the frustum)\n", path, (unsigned long long)diff);
                        diff_total += diff;
                    }
        }
    }
    if (bench) {
        printf("BENCH walkthrough_speedup %.2f x\n", sum[0][1] / (sum[2][1] > 0 ? sum[2][1] : 1));
        printf("BENCH walkthrough_pvs_speedup %.2f x\n", sum[0][1] / (sum[1][1] > 0 ? sum[1][1] : 1));
        printf("BENCH walkthrough_triangles_pvs_cull %.0f triangles\n", sum[2][1] / nf);
        printf("BENCH walkthrough_cull_ms %.2f ms\n", cull_ms / nf);
    } else {
        FILE *csv;
        snprintf(path, sizeof(path), "%s/walkthrough.csv", dir);
        csv = fopen(path, "w");
        if (!csv) { fprintf(stderr, "walkthrough: cannot write %s\n", path); return 1; }
        fprintf(csv, "frame,part,x,z,cell,frustum_objects,frustum_triangles,pvs_objects,pvs_triangles,pvs_cull_objects,pvs_cull_triangles,cull_ms\n");
        for (i = 0; i < nf; ++i)
            fprintf(csv, "%u,%d,%.2f,%.2f,%d,%u,%llu,%u,%llu,%u,%llu,%.3f\n", i, fr[i].part, (double)fr[i].eye[0], (double)fr[i].eye[2],
                    fr[i].cell == PVS_NO_CELL ? -1 : (int)fr[i].cell, fr[i].obj[0], (unsigned long long)fr[i].tri[0], fr[i].obj[1],
                    (unsigned long long)fr[i].tri[1], fr[i].obj[2], (unsigned long long)fr[i].tri[2], fr[i].cull_ms);
        fclose(csv);
        printf("wrote %s\n", path);
        snprintf(path, sizeof(path), "%s/walkthrough.png", dir);
        if (write_plot(path, fr, nf, part2, &te)) { fprintf(stderr, "walkthrough: %s\n", te.message); return 1; }
        printf("wrote %s\n", path);
        snprintf(path, sizeof(path), "%s/path.png", dir);
        if (write_path_png(path, &m, scene, fr, nf, &te)) { fprintf(stderr, "walkthrough: %s\n", te.message); return 1; }
        printf("wrote %s\n", path);
        printf("\nwalkthrough of the demo city: %u frames (%.0f m, part 1 %u frames, part 2 %u), PVS %s\n", nf, len, frames_part[0], frames_part[1],
               pvs_path ? pvs_path : pvs_method_name(method));
        printf("  per frame, mean         objects    triangles   part 1 tris  part 2 tris\n");
        for (a = 0; a < 3; ++a)
            printf("  %-22s %8.1f %12.0f %13.0f %12.0f\n", a == 0 ? "frustum culling" : a == 1 ? "PVS" : "PVS + per-frame culling", sum[a][0] / nf,
                   sum[a][1] / nf, frames_part[0] ? sum_part[0][a] / frames_part[0] : 0.0, frames_part[1] ? sum_part[1][a] / frames_part[1] : 0.0);
        printf("  speed-up in triangles over frustum culling: PVS %.1fx, PVS + per-frame culling %.1fx; culling %.2f ms per frame\n",
               sum[0][1] / (sum[1][1] > 0 ? sum[1][1] : 1), sum[0][1] / (sum[2][1] > 0 ? sum[2][1] : 1), cull_ms / nf);
        printf("  %.1f s\n", cli_seconds() - t0);
        if (diff_total) {
            fprintf(stderr, "walkthrough: %llu pixels of the rendered frames differ from drawing everything in the frustum: a missed object\n",
                    (unsigned long long)diff_total);
            return 3;
        }
    }
    pvs_raster_destroy(raster);
    free(cur); free(scratch); free(vis_f); free(vis_p); free(vis_c); free(fr); free(arc); free(pts); free(file_bytes);
    pvs_scene_destroy(scene);
    mesh_cells_free(&cells);
    mesh_free(&m);
    return 0;
}
