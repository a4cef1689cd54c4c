/* cullmap.c - `make examples`: per-frame occlusion culling of the generated city from a street
   viewpoint with a cull map (Wonka & Schmalstieg 1999) and with the depth pyramid. Writes two images:
     OUTDIR/cullmap.png  the cull map seen from above: cells under an occluder shadow shaded by the
                         shadow's height (blue low .. yellow high), black where no shadow covers the
                         whole cell, facades in white, the eye and the view frustum in red
     OUTDIR/culled.png   the objects from above: green visible, red occluded (culled by the cull map),
                         dark grey outside the view frustum; the eye and frustum in white
   Usage: pvscullmap [-o OUTDIR] [--size S]   (default build/cullmap, which must exist; city size 0.5)
   `make examples` builds it, `make cullmap-images` runs it. */
#include "../tools/cli.h"
#include <math.h>
#include <stdlib.h>
#include <string.h>

#define IMG 512

static void put(uint8_t *img, int x, int y, uint8_t r, uint8_t g, uint8_t b) {
    uint8_t *p;
    if (x < 0 || y < 0 || x >= IMG || y >= IMG) return;
    p = img + 4 * ((size_t)(IMG - 1 - y) * IMG + (size_t)x); /* v grows upwards in the image */
    p[0] = r; p[1] = g; p[2] = b; p[3] = 255;
}
static void line(uint8_t *img, double x0, double y0, double x1, double y1, uint8_t r, uint8_t g, uint8_t b) {
    int k, n = (int)(fabs(x1 - x0) + fabs(y1 - y0)) + 1;
    for (k = 0; k <= n; ++k) put(img, (int)(x0 + (x1 - x0) * k / n), (int)(y0 + (y1 - y0) * k / n), r, g, b);
}

/* The building footprints of the generated city: a building's first triangles are its wall quads
   (bottom i, bottom i+1, top i+1), the bottom ring first (tools/gen.c gen__building). */
static uint32_t city_facades(const mesh *m, pvs_facade_chain *chains, float *pts) {
    uint32_t o, n = 0, used = 0;
    for (o = 0; o < m->object_count; ++o) {
        const mesh_object *ob = m->objects + o;
        const uint32_t *idx = m->indices + 3 * (size_t)ob->first_triangle;
        uint32_t bot, i, k;
        if (strncmp(ob->name, "building_", 9) != 0 || ob->triangle_count < 6) continue;
        bot = idx[0];
        for (i = 0; 2 * i < ob->triangle_count; ++i) {
            if (idx[6 * i] != bot + i) { i = 0; break; }
            if (idx[6 * i + 1] == bot) { ++i; break; }
        }
        if (i < 3) continue;
        for (k = 0; k < i; ++k) {
            pts[2 * (used + k)] = m->positions[3 * (bot + k)];
            pts[2 * (used + k) + 1] = m->positions[3 * (bot + k) + 2];
        }
        chains[n].points = pts + 2 * used;
        chains[n].point_count = i;
        chains[n].closed = 1;
        chains[n].base = m->positions[3 * bot + 1];
        chains[n].top = m->positions[3 * idx[2] + 1];
        used += i;
        ++n;
    }
    return n;
}

int main(int argc, char **argv) {
    const char *dir = "build/cullmap";
    float size = 0.5f;
    gen_params gp;
    mesh m;
    mesh_cells cells;
    pvs_scene *scene;
    tool_error te;
    pvs_error pe;
    pvs_raster_desc rd;
    pvs_raster *r;
    pvs_camera cam;
    pvs_cull_params cp;
    pvs_cull_stats st_cm, st_py, st_fr;
    pvs_facade_chain *chains;
    float *pts, region[4];
    pvs_word *vis_cm, *vis_py, *vis_fr;
    uint8_t *img;
    uint32_t nchains, nobj, i, w, h;
    const float *cm;
    char path[1024];
    int a;
    for (a = 1; a < argc; ++a) {
        if (!strcmp(argv[a], "-o") && a + 1 < argc) dir = argv[++a];
        else if (!strcmp(argv[a], "--size") && a + 1 < argc) size = (float)atof(argv[++a]);
        else { fprintf(stderr, "usage: cullmap [-o OUTDIR] [--size S]\n"); return 2; }
    }
    mesh_init(&m);
    mesh_cells_init(&cells);
    memset(&gp, 0, sizeof(gp));
    gp.kind = GEN_CITY; gp.seed = 1; gp.size = size;
    if (gen_scene(&gp, &m, &cells) != 0) { fprintf(stderr, "cullmap: generating the city failed\n"); return 1; }
    if (cli_make_scene("city", &m, 1, &scene, &te) != 0) { fprintf(stderr, "cullmap: %s\n", te.message); return 1; }
    nobj = pvs_scene_object_count(scene);
    chains = (pvs_facade_chain *)malloc(m.object_count * sizeof(pvs_facade_chain));
    pts = (float *)malloc((size_t)m.triangle_count * 2 * sizeof(float));
    nchains = city_facades(&m, chains, pts);

    memset(&rd, 0, sizeof(rd));
    rd.width = 640; rd.height = 360;
    rd.scene = scene;
    rd.cull_map_width = 256; rd.cull_map_height = 256;
    rd.max_occluders = 2048;
    if (pvs_raster_create(&rd, &r, &pe) != PVS_OK) { fprintf(stderr, "cullmap: %s\n", pe.message); return 1; }

    /* a street viewpoint: the regular cell nearest the city's centre, eye height 1.7, looking along +x */
    memset(&cam, 0, sizeof(cam));
    {
        pvs_box b = pvs_scene_bounds(scene);
        float cx = 0.5f * (b.min[0] + b.max[0]), cz = 0.5f * (b.min[2] + b.max[2]), best = 1e30f;
        for (i = 0; i < cells.count; ++i) {
            const float *c = cells.boxes + 6 * i;
            float x = 0.5f * (c[0] + c[3]), z = 0.5f * (c[2] + c[5]), d = (x - cx) * (x - cx) + (z - cz) * (z - cz);
            if (d < best) { best = d; cam.eye[0] = x; cam.eye[2] = z; }
        }
    }
    cam.eye[1] = 1.7f;
    cam.forward[0] = 1.0f; cam.forward[2] = 0.35f;
    cam.up[1] = 1.0f;
    cam.fov_y = 1.0f;
    cam.near_plane = 0.1f;

    vis_cm = (pvs_word *)calloc(PVS_BITSET_WORDS(nobj), sizeof(pvs_word));
    vis_py = (pvs_word *)calloc(PVS_BITSET_WORDS(nobj), sizeof(pvs_word));
    vis_fr = (pvs_word *)calloc(PVS_BITSET_WORDS(nobj), sizeof(pvs_word));
    memset(&cp, 0, sizeof(cp));
    cp.occluder_flags = PVS_CULL_FRUSTUM_ONLY;
    pvs_raster_cull(r, scene, &cam, &cp, vis_fr, &st_fr, &pe); /* no occluders: the frustum alone */
    cp.occluder_flags = 0;
    cp.scene_occluders = 2048;
    cp.occluder_distance = 150.0f;
    pvs_raster_cull(r, scene, &cam, &cp, vis_py, &st_py, &pe);
    cp.facades = chains;
    cp.facade_count = nchains;
    if (pvs_raster_cull_map(r, scene, &cam, &cp, vis_cm, &st_cm, &pe) != PVS_OK) { fprintf(stderr, "cullmap: %s\n", pe.message); return 1; }
    printf("city: %u objects, %u building footprints; eye (%.1f, %.1f, %.1f)\n", nobj, nchains, cam.eye[0], cam.eye[1], cam.eye[2]);
    printf("in the view frustum: %u objects\n", st_fr.visible);
    printf("depth pyramid (%u scene triangles as occluders): %u visible\n", st_py.occluder_triangles, st_py.visible);
    printf("cull map (%u facade chains): %u visible\n", nchains, st_cm.visible);

    cm = pvs_cull_map(r, &w, &h, region);
    img = (uint8_t *)calloc((size_t)IMG * IMG * 4, 1);
    {
        float lo = 1e30f, hi = -1e30f;
        int x, y;
        for (i = 0; i < w * h; ++i)
            if (cm[i] != PVS_DEPTH_EMPTY) {
                float v = cm[i] > 60.0f ? 60.0f : cm[i];
                lo = v < lo ? v : lo;
                hi = v > hi ? v : hi;
            }
        for (y = 0; y < IMG; ++y)
            for (x = 0; x < IMG; ++x) {
                float v = cm[(size_t)(y * (int)h / IMG) * w + (size_t)(x * (int)w / IMG)], t;
                if (v == PVS_DEPTH_EMPTY) { put(img, x, y, 0, 0, 0); continue; }
                t = ((v > 60.0f ? 60.0f : v) - lo) / (hi > lo ? hi - lo : 1.0f);
                put(img, x, y, (uint8_t)(40 + 215 * t), (uint8_t)(60 + 180 * t), (uint8_t)(200 - 180 * t));
            }
    }
#define IX(u) (((u) - region[0]) / (region[2] - region[0]) * IMG)
#define IY(v) (((v) - region[1]) / (region[3] - region[1]) * IMG)
    for (i = 0; i < nchains; ++i) {
        uint32_t k, n = chains[i].point_count;
        for (k = 0; k < n; ++k) {
            const float *p = chains[i].points + 2 * k, *q = chains[i].points + 2 * ((k + 1) % n);
            line(img, IX(p[0]), IY(p[1]), IX(q[0]), IY(q[1]), 255, 255, 255);
        }
    }
    {
        /* the frustum's ground trace: two rays at +-half the horizontal field of view */
        double hx = atan(tan(0.5 * cam.fov_y) * 640.0 / 360.0), yaw = atan2(cam.forward[2], cam.forward[0]), len = 2000.0;
        double ex = IX(cam.eye[0]), ey = IY(cam.eye[2]);
        int k;
        for (k = -1; k <= 1; k += 2)
            line(img, ex, ey, IX(cam.eye[0] + len * cos(yaw + k * hx)), IY(cam.eye[2] + len * sin(yaw + k * hx)), 255, 0, 0);
        for (k = -3; k <= 3; ++k) { line(img, ex - 3, ey + k, ex + 3, ey + k, 255, 0, 0); }
    }
    snprintf(path, sizeof(path), "%s/cullmap.png", dir);
    if (png_write(path, img, IMG, IMG, &te) != 0) { fprintf(stderr, "cullmap: %s\n", te.message); return 1; }
    printf("wrote %s\n", path);

    /* objects from above, lowest tops first so buildings cover the ground tiles */
    memset(img, 0, (size_t)IMG * IMG * 4);
    {
        uint32_t pass;
        for (pass = 0; pass < 2; ++pass)
            for (i = 0; i < nobj; ++i) {
                pvs_box b = pvs_scene_object_box(scene, i);
                int x, y, x0 = (int)IX(b.min[0]), x1 = (int)IX(b.max[0]), y0 = (int)IY(b.min[2]), y1 = (int)IY(b.max[2]);
                uint8_t cr, cg, cb;
                if ((b.max[1] > 0.05f) != (pass == 1)) continue; /* ground tiles first */
                if (pvs_bitset_test(vis_cm, i)) { cr = 40; cg = 200; cb = 60; }
                else if (pvs_bitset_test(vis_fr, i)) { cr = 210; cg = 40; cb = 40; }
                else { cr = 60; cg = 60; cb = 60; }
                if (pass == 0) { cr = (uint8_t)(cr / 2); cg = (uint8_t)(cg / 2); cb = (uint8_t)(cb / 2); }
                for (y = y0; y <= y1; ++y)
                    for (x = x0; x <= x1; ++x) {
                        int edge = pass == 0 && (x == x0 || y == y0);
                        put(img, x, y, edge ? 20 : cr, edge ? 20 : cg, edge ? 20 : cb);
                    }
            }
    }
    {
        double hx = atan(tan(0.5 * cam.fov_y) * 640.0 / 360.0), yaw = atan2(cam.forward[2], cam.forward[0]), len = 2000.0;
        double ex = IX(cam.eye[0]), ey = IY(cam.eye[2]);
        int k;
        for (k = -1; k <= 1; k += 2)
            line(img, ex, ey, IX(cam.eye[0] + len * cos(yaw + k * hx)), IY(cam.eye[2] + len * sin(yaw + k * hx)), 255, 255, 255);
        for (k = -3; k <= 3; ++k) line(img, ex - 3, ey + k, ex + 3, ey + k, 255, 255, 255);
    }
    snprintf(path, sizeof(path), "%s/culled.png", dir);
    if (png_write(path, img, IMG, IMG, &te) != 0) { fprintf(stderr, "cullmap: %s\n", te.message); return 1; }
    printf("wrote %s\n", path);

    free(img); free(vis_cm); free(vis_py); free(vis_fr); free(chains); free(pts);
    pvs_raster_destroy(r);
    pvs_scene_destroy(scene);
    mesh_free(&m);
    mesh_cells_free(&cells);
    return 0;
}
