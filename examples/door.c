/* door.c - the door recipe for see-through objects (PVS_OBJECT_SEE_THROUGH; OBJ names beginning with
   "glass", "door" or "see_through"). Two rooms share a wall with a doorway, a door in it and a glass
   window; a statue stands behind the door, a plant behind the glass, a crate behind the solid wall.
     1. Bake with the door and the glass see-through (the door open): the statue and the plant are in
        the PVS of the view cell in the first room, the crate is not. Baked as walls instead, the door
        would hide the statue: a miss in the game the moment it opens.
     2. Per frame, pvs_raster_cull with the closed door's triangles as the caller's occluders, drawn as
        meshes (PVS_CULL_OCCLUDER_MESH, PVS_CULL_SCENE_MESH: no cracks along shared edges) and overlapping
        the door frame: the statue is culled while the door is closed and drawn when it opens; the glass
        never hides the plant.
   Writes OUTDIR/door.obj and door.cells (for pvsbake and pvscheck) and OUTDIR/door.png: the view with
   the door open (left) and closed (right), culled objects in red.
   Usage: pvsdoor [-o OUTDIR] */
#include "../pvs.h"
#include "cli.h"
#include "mesh.h"
#include "render.h"
#include "toolutil.h"
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

enum { FLOOR, WALLS, DOOR, GLASS, STATUE, PLANT, CRATE, OBJECTS };
static const char *const names[OBJECTS] = {"floor", "walls", "door", "glass_window", "statue", "plant", "crate"};
static const uint32_t colors[OBJECTS] = {RENDER_RGBA(120, 120, 110, 255), RENDER_RGBA(200, 190, 170, 255),
                                         RENDER_RGBA(150, 90, 40, 255),   RENDER_RGBA(140, 200, 255, 90),
                                         RENDER_RGBA(230, 200, 60, 255),  RENDER_RGBA(60, 170, 60, 255),
                                         RENDER_RGBA(90, 120, 200, 255)};
static const uint32_t box_tris[12][3] = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4},
                                         {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};

static int add_box(mesh *m, float x0, float y0, float z0, float x1, float y1, float z1) {
    uint32_t base = m->vertex_count, i;
    int r = 0;
    for (i = 0; i < 8; ++i) r |= mesh_add_vertex(m, i & 1 ? x1 : x0, i & 2 ? y1 : y0, i & 4 ? z1 : z0);
    for (i = 0; i < 12; ++i) r |= mesh_add_triangle(m, base + box_tris[i][0], base + box_tris[i][1], base + box_tris[i][2]);
    return r;
}

/* Two rooms x -10..0 and 0..10, z -5..5, 3 high; the shared wall at x -0.1..0.1 has a doorway at z -2..-1
   (2.2 high) and a window at z 1..3. The door overlaps its frame by 5 cm, so that drawn as an occluder it
   leaves no crack along the frame. Y up, metres. */
static int build(mesh *m) {
    int r = mesh_begin_object(m, names[FLOOR], 0, 0);
    uint32_t base = m->vertex_count;
    r |= mesh_add_vertex(m, -10, 0, -5) | mesh_add_vertex(m, 10, 0, -5) | mesh_add_vertex(m, 10, 0, 5) |
         mesh_add_vertex(m, -10, 0, 5);
    r |= mesh_add_quad(m, base, base + 1, base + 2, base + 3);
    r |= mesh_begin_object(m, names[WALLS], 0, 0);
    r |= add_box(m, -10.2f, 0, -5.2f, -10, 3, 5.2f) | add_box(m, 10, 0, -5.2f, 10.2f, 3, 5.2f);
    r |= add_box(m, -10, 0, -5.2f, 10, 3, -5) | add_box(m, -10, 0, 5, 10, 3, 5.2f);
    r |= add_box(m, -0.1f, 0, -5, 0.1f, 3, -2) | add_box(m, -0.1f, 2.2f, -2, 0.1f, 3, -1);
    r |= add_box(m, -0.1f, 0, -1, 0.1f, 3, 1) | add_box(m, -0.1f, 0, 3, 0.1f, 3, 5);
    r |= mesh_begin_object(m, names[DOOR], MESH_OBJECT_SEE_THROUGH, 0) | add_box(m, -0.05f, 0, -2.05f, 0.05f, 2.25f, -0.95f);
    r |= mesh_begin_object(m, names[GLASS], MESH_OBJECT_SEE_THROUGH, 0) | add_box(m, -0.02f, 0, 1, 0.02f, 3, 3);
    r |= mesh_begin_object(m, names[STATUE], 0, 0) | add_box(m, 3, 0, -2, 4, 2, -1);
    r |= mesh_begin_object(m, names[PLANT], 0, 0) | add_box(m, 3, 0, 1.5f, 4, 1.5f, 2.5f);
    r |= mesh_begin_object(m, names[CRATE], 0, 0) | add_box(m, 2, 0, -0.5f, 3, 1, 0.5f);
    return r;
}

/* The view from `cam` into im's half `half` (0 left, 1 right): objects in `visible` in their colours,
   the others in red over them (X-ray); the door drawn when closed. */
static void draw(render_image *im, render_image *over, const pvs_camera *cam, const mesh *m, const pvs_word *visible,
                 int door_closed) {
    render_view v;
    uint32_t o;
    render_clear(im, RENDER_RGBA(30, 30, 40, 255));
    render_clear(over, 0);
    if (render_view_init(&v, cam, im) != 0) return;
    for (o = 0; o < OBJECTS; ++o) {
        const mesh_object *ob = m->objects + o;
        if (o == GLASS || (o == DOOR && !door_closed)) continue;
        if (pvs_bitset_test(visible, o) || o == DOOR)
            render_triangles(im, &v, m->positions, m->indices, ob->first_triangle, ob->triangle_count, colors[o], 0);
        else
            render_triangles(over, &v, m->positions, m->indices, ob->first_triangle, ob->triangle_count,
                             RENDER_RGBA(230, 40, 40, 255), 0);
    }
    render_triangles(im, &v, m->positions, m->indices, m->objects[GLASS].first_triangle,
                     m->objects[GLASS].triangle_count, colors[GLASS], RENDER_BLEND | RENDER_NO_DEPTH_WRITE);
    render_composite(im, over, 0.6f);
}

int main(int argc, char **argv) {
    const char *dir = "build/demo";
    const pvs_box cell = {{-7, 1, -1}, {-5, 2, 1}};
    mesh m;
    pvs_scene *scene = NULL, *walls = NULL;
    pvs_bake_desc bd;
    pvs_bake *bake = NULL;
    pvs_raster *raster = NULL;
    pvs_raster_desc rd;
    pvs_cull_params cp;
    pvs_camera cam;
    pvs_error e;
    tool_error te;
    pvs_word pvs[1], wall_pvs[1], seen[1], open_vis[1], closed_vis[1];
    float door[36 * 3];
    render_image im, over, out;
    char path[1024];
    uint32_t i, j, t, misses;
    int rc = 1;
    FILE *f;
    for (i = 1; i < (uint32_t)argc; ++i) {
        if (!strcmp(argv[i], "-o") && i + 1 < (uint32_t)argc) dir = argv[++i];
        else return tool_usage_error("pvsdoor", "usage: pvsdoor [-o OUTDIR]");
    }
    mesh_init(&m);
    memset(&im, 0, sizeof(im));
    memset(&over, 0, sizeof(over));
    memset(&out, 0, sizeof(out));
    if (build(&m) || cli_make_scene("door", &m, 1, &scene, &te)) {
        fprintf(stderr, "pvsdoor: %s\n", te.message);
        goto done;
    }
    snprintf(path, sizeof(path), "%s/door.obj", dir);
    if (!(f = fopen(path, "wb")) || mesh_write_obj(&m, f) || fclose(f)) {
        fprintf(stderr, "pvsdoor: cannot write %s\n", path);
        goto done;
    }
    snprintf(path, sizeof(path), "%s/door.cells", dir);
    if (!(f = fopen(path, "wb")) || fprintf(f, "%g %g %g %g %g %g\n", cell.min[0], cell.min[1], cell.min[2], cell.max[0],
                                            cell.max[1], cell.max[2]) < 0 || fclose(f)) {
        fprintf(stderr, "pvsdoor: cannot write %s\n", path);
        goto done;
    }

    /* 1. the bake, door open: what the cell may see, against the same scene with the door and glass as walls */
    for (j = 0; j < 2; ++j) {
        pvs_scene *s = scene;
        if (j == 1) {
            m.objects[DOOR].flags = m.objects[GLASS].flags = 0;
            if (cli_make_scene("door", &m, 1, &walls, &te)) goto done;
            m.objects[DOOR].flags = m.objects[GLASS].flags = MESH_OBJECT_SEE_THROUGH;
            s = walls;
        }
        memset(&bd, 0, sizeof(bd));
        bd.scene = s;
        bd.cells = &cell;
        bd.cell_count = 1;
        if (pvs_bake_begin(&bd, &bake, &e) != PVS_OK || pvs_bake_run_task(bake, 0, &e) != PVS_OK) {
            fprintf(stderr, "pvsdoor: bake: %s\n", e.message);
            goto done;
        }
        (j ? wall_pvs : pvs)[0] = pvs_bake_cell_pvs(bake, 0)[0];
        pvs_bake_destroy(bake);
        bake = NULL;
    }
    printf("baked PVS of the cell (door open, glass see-through):");
    for (i = 0; i < OBJECTS; ++i) if (pvs_bitset_test(pvs, i)) printf(" %s", names[i]);
    printf("\nthe same with door and glass baked as walls:          ");
    for (i = 0; i < OBJECTS; ++i) if (pvs_bitset_test(wall_pvs, i)) printf(" %s", names[i]);
    seen[0] = 0;
    cli_reference_visibility(scene, &cell, 5, seen);
    misses = 0;
    for (i = 0; i < OBJECTS; ++i) misses += pvs_bitset_test(seen, i) && !pvs_bitset_test(pvs, i);
    printf("\nray sampling from the cell sees the statue %s, the plant %s; misses of the PVS: %u\n",
           pvs_bitset_test(seen, STATUE) ? "yes" : "no", pvs_bitset_test(seen, PLANT) ? "yes" : "no", misses);

    /* 2. per frame from the cell's centre toward the wall: door open, then closed (its triangles as occluders) */
    memset(&rd, 0, sizeof(rd));
    rd.width = 320;
    rd.height = 160;
    rd.scene = scene;
    memset(&cam, 0, sizeof(cam));
    cam.eye[0] = -6; cam.eye[1] = 1.6f;
    cam.forward[0] = 1; cam.forward[2] = -0.15f;
    cam.up[1] = 1;
    cam.fov_y = 1.1f;
    cam.near_plane = 0.05f;
    memset(&cp, 0, sizeof(cp));
    cp.scene_occluders = 64;
    cp.occluder_distance = 30;
    cp.candidates = pvs;
    cp.occluder_flags = PVS_CULL_SCENE_MESH | PVS_CULL_OCCLUDER_MESH; /* no cracks along shared edges */
    t = m.objects[DOOR].first_triangle;
    for (i = 0; i < 36; ++i) memcpy(door + 3 * i, m.positions + 3 * m.indices[3 * t + i], 3 * sizeof(float));
    if (pvs_raster_create(&rd, &raster, &e) != PVS_OK ||
        pvs_raster_cull(raster, scene, &cam, &cp, open_vis, NULL, &e) != PVS_OK) {
        fprintf(stderr, "pvsdoor: cull: %s\n", e.message);
        goto done;
    }
    cp.occluder_positions = door;
    cp.occluder_vertex_count = 36;
    cp.occluder_triangle_count = 12;
    if (pvs_raster_cull(raster, scene, &cam, &cp, closed_vis, NULL, &e) != PVS_OK) {
        fprintf(stderr, "pvsdoor: cull: %s\n", e.message);
        goto done;
    }
    printf("per frame, door open:   statue %s, plant %s\n", pvs_bitset_test(open_vis, STATUE) ? "drawn" : "culled",
           pvs_bitset_test(open_vis, PLANT) ? "drawn" : "culled");
    printf("per frame, door closed: statue %s, plant %s\n", pvs_bitset_test(closed_vis, STATUE) ? "drawn" : "culled",
           pvs_bitset_test(closed_vis, PLANT) ? "drawn" : "culled");

    if (render_image_init(&im, 480, 300) || render_image_init(&over, 480, 300) || render_image_init(&out, 968, 300))
        goto done;
    render_clear(&out, RENDER_RGBA(0, 0, 0, 255));
    for (j = 0; j < 2; ++j) {
        uint32_t y;
        draw(&im, &over, &cam, &m, j ? closed_vis : open_vis, (int)j);
        for (y = 0; y < im.height; ++y)
            memcpy(out.rgba + 4 * ((size_t)y * out.width + j * 488), im.rgba + 4 * (size_t)y * im.width, 4 * (size_t)im.width);
    }
    snprintf(path, sizeof(path), "%s/door.png", dir);
    if (png_write(path, out.rgba, out.width, out.height, &te)) {
        fprintf(stderr, "pvsdoor: %s\n", te.message);
        goto done;
    }
    printf("wrote %s (door open | door closed; culled objects red)\n", path);
    rc = misses != 0 || !pvs_bitset_test(open_vis, STATUE) || pvs_bitset_test(closed_vis, STATUE);
done:
    render_image_free(&im);
    render_image_free(&over);
    render_image_free(&out);
    pvs_raster_destroy(raster);
    pvs_bake_destroy(bake);
    pvs_scene_destroy(scene);
    pvs_scene_destroy(walls);
    mesh_free(&m);
    return rc;
}
