/* pvsimport - turn a Quake 3 level (IBSP 46) into a scene, view cells and the level's own PVS, or a Doom map (WAD)
   into a scene and view cells. See --help. */
#include "bsp.h"
#include "wad.h"
#include "cli.h"
#include <stdlib.h>
#include <string.h>

#define TOOL "pvsimport"

static const char *usage =
    "usage: pvsimport MAP.bsp -o OUT.obj [--cells OUT.cells] [--pvs OUT.pvs] [options]\n"
    "  Reads a compiled Quake 3 level (IBSP version 46: Quake III Arena, OpenArena) and writes:\n"
    "  -o OUT.obj        the scene, Y up: object i is the level's drawn surface i (patches tessellated;\n"
    "                    flares and nodraw surfaces have no faces), then one object 'occluder_brushes',\n"
    "                    the hulls of the world's solid opaque brushes (blocks sight, never drawn);\n"
    "                    in the map's units: a player's eye is 50 over the floor, a step 18 (pvsbake\n"
    "                    --cells walkable --eye-height 50 --step-height 18; its defaults are metres)\n"
    "  --cells OUT.cells one view cell per BSP leaf with a cluster, its bounding box, in leaf order;\n"
    "                    faces whose outside is all wall kept --clearance units off it\n"
    "  --pvs OUT.pvs     the level's own PVS (q3map2's vis) expanded to those objects, one record per\n"
    "                    cell, as a .pvs file: compare it with a bake (pvsinfo, pvscheck, make bench)\n"
    "  --patch-level N   quads per side of each 3x3 patch block (default 4, at most 32)\n"
    "  --clearance U     how far cells keep off walls (default 1; 0: the leaves' boxes). A camera is\n"
    "                    never on a wall; a box touching one holds points from which a ray grazes\n"
    "                    into the wall and sees what is drawn on its far side, which the bake must keep\n"
    "  --cell-step N     keep every N-th cell only (in --cells and --pvs alike), for quick measurements\n"
    "  --shaders FILE    the game's shader scripts (its scripts/NAME.shader in one file): planar surfaces\n"
    "                    drawn front only become one-sided objects ('one_sided_sN', counter-clockwise):\n"
    "                    a cell behind all of one leaves it out of its PVS. Without it, all are two-sided\n"
    "  -q, --quiet       no summary\n"
    "  A .pk3 is a zip archive: extract the .bsp first (unzip -p PAK.pk3 maps/NAME.bsp > NAME.bsp).\n"
    "usage: pvsimport FILE.wad -o OUT.obj [--cells OUT.cells] [--map NAME] [--no-solids] [--cell-step N]\n"
    "       pvsimport FILE.wad --list\n"
    "  Reads a Doom map (Doom, Doom II, Freedoom; Doom's binary map format) at its start (doors closed):\n"
    "  -o OUT.obj        object 'wN' per linedef (its walls), then per sector 'floorN' and 'ceilN' (a sky\n"
    "                    ceiling: 'occluder_skyN', blocks sight, never drawn), then 'occluder_solids': the\n"
    "                    solid space (under floors, over ceilings, outside the map) as convex prisms, Y up;\n"
    "                    in the map's units: a player's eye is 41 over the floor, a step 24 (pvsbake\n"
    "                    --cells walkable --eye-height 41 --step-height 24; its defaults are metres)\n"
    "  --cells OUT.cells one view cell per subsector of an open sector: its polygon's box grown out to the\n"
    "                    8-unit grid, floor to ceiling\n"
    "  --map NAME        the map (E1M1, MAP01, ...; default: the first); --list prints the WAD's maps\n"
    "  --no-solids       leave out occluder_solids: the map as drawn surfaces and sky alone\n"
    "  --cell-step N     keep every N-th cell only\n"
    "exit status: 0 written, 1 bad input or I/O error, 2 usage\n";

typedef struct import_options {
    const char *bsp, *obj, *cells, *pvs, *shaders, *map;
    uint32_t patch_level, cell_step;
    double clearance;
    int quiet, list, no_solids;
} import_options;

static int parse_options(int argc, char **argv, import_options *o) {
    memset(o, 0, sizeof(*o));
    o->clearance = 1;
    for (int i = 1; i < argc; ++i) {
        const char *a = argv[i], *v = i + 1 < argc ? argv[i + 1] : NULL;
        if (!strcmp(a, "--help") || !strcmp(a, "-h")) {
            fputs(usage, stdout);
            return 0;
        } else if (!strcmp(a, "-q") || !strcmp(a, "--quiet")) {
            o->quiet = 1;
        } else if (!strcmp(a, "-o") || !strcmp(a, "--cells") || !strcmp(a, "--pvs")) {
            if (!v) return tool_usage_error(TOOL, "%s needs a file name", a);
            *(a[1] == 'o' ? &o->obj : a[2] == 'c' ? &o->cells : &o->pvs) = v;
            ++i;
        } else if (!strcmp(a, "--map")) {
            if (!v || !v[0] || strlen(v) > 8) return tool_usage_error(TOOL, "--map takes a map name of 1 to 8 characters");
            o->map = v;
            ++i;
        } else if (!strcmp(a, "--list")) {
            o->list = 1;
        } else if (!strcmp(a, "--no-solids")) {
            o->no_solids = 1;
        } else if (!strcmp(a, "--shaders")) {
            if (!v) return tool_usage_error(TOOL, "--shaders needs a file name");
            o->shaders = v;
            ++i;
        } else if (!strcmp(a, "--patch-level")) {
            if (!v || cli_parse_u32(v, 1, 32, &o->patch_level))
                return tool_usage_error(TOOL, "--patch-level takes a number from 1 to 32");
            ++i;
        } else if (!strcmp(a, "--clearance")) {
            float c;
            if (parse_float(v, &c) || !(c >= 0.0f && c <= 1e6f))
                return tool_usage_error(TOOL, "--clearance takes a distance from 0 to 1e6");
            o->clearance = c;
            ++i;
        } else if (!strcmp(a, "--cell-step")) {
            if (!v || cli_parse_u32(v, 1, 1u << 30, &o->cell_step))
                return tool_usage_error(TOOL, "--cell-step takes a positive number");
            ++i;
        } else if (a[0] == '-' && a[1]) {
            return tool_usage_error(TOOL, "unknown option '%s'", a);
        } else if (o->bsp) {
            return tool_usage_error(TOOL, "more than one map ('%s' and '%s')", o->bsp, a);
        } else {
            o->bsp = a;
        }
    }
    if (!o->bsp) return tool_usage_error(TOOL, "missing MAP.bsp");
    if (!o->obj && !o->list) return tool_usage_error(TOOL, "missing -o OUT.obj");
    return -1;
}

static int write_obj(FILE *f, const void *ctx) { return mesh_write_obj((const mesh *)ctx, f); }
static int write_cells(FILE *f, const void *ctx) {
    const mesh_cells *c = (const mesh_cells *)ctx;
    fprintf(f, "# pvsimport: %u cells, one per BSP leaf with a cluster, minx miny minz maxx maxy maxz, Y up\n", c->count);
    return mesh_cells_write(c, f);
}

static int write_wad_cells(FILE *f, const void *ctx) {
    const mesh_cells *c = (const mesh_cells *)ctx;
    fprintf(f, "# pvsimport: %u cells, one per subsector of an open sector, minx miny minz maxx maxy maxz, Y up\n",
            c->count);
    return mesh_cells_write(c, f);
}

/* The level's PVS as a .pvs file (method "default": computed by no method of pvs.h). */
static int write_pvs(const char *path, const mesh_cells *cells, const bsp_pvs *pvs, tool_error *err) {
    pvs_file_desc d;
    pvs_error pe;
    size_t size = 0;
    memset(&d, 0, sizeof(d));
    d.cells = (const pvs_box *)cells->boxes;
    d.cell_count = cells->count;
    d.object_count = pvs->object_count;
    d.pvs = pvs->bits;
    d.up_axis = 1;
    if (pvs_file_encode(&d, NULL, 0, &size, &pe) != PVS_OK) {
        tool_error_set(err, path, 0, "%s", pe.message);
        return -1;
    }
    void *bytes = malloc(size ? size : 1);
    if (!bytes) {
        tool_error_set(err, path, 0, "out of memory");
        return -1;
    }
    int rc = 0;
    if (pvs_file_encode(&d, bytes, size, &size, &pe) != PVS_OK) {
        tool_error_set(err, path, 0, "%s", pe.message);
        rc = -1;
    } else {
        rc = write_file_atomic(path, bytes, size, err);
    }
    free(bytes);
    return rc;
}

/* A Doom map: the scene and its subsector cells (--list: the maps' names). */
static int import_wad(const import_options *o, const void *data, size_t size) {
    tool_error err;
    mesh m;
    mesh_cells cells;
    wad_stats st;
    wad_options wo;
    int rc;
    if (o->list) {
        char names[8192];
        rc = wad_list_maps(o->bsp, data, size, names, sizeof(names), &err);
        if (rc < 0) {
            fprintf(stderr, "%s: %s\n", TOOL, err.message);
            return 1;
        }
        fputs(names, stdout);
        return 0;
    }
    if (o->pvs || o->shaders || o->patch_level)
        return tool_usage_error(TOOL, "--pvs, --shaders and --patch-level are for a BSP file");
    wo.cell_step = o->cell_step;
    wo.no_solids = o->no_solids;
    rc = wad_parse(o->bsp, data, size, o->map, &wo, &m, &cells, &st, &err);
    if (!rc) rc = write_stream_atomic(o->obj, write_obj, &m, &err);
    if (!rc && o->cells) rc = write_stream_atomic(o->cells, write_wad_cells, &cells, &err);
    if (rc) fprintf(stderr, "%s: %s\n", TOOL, err.message);
    else if (!o->quiet)
        fprintf(stderr, "%s: %s %s: %u linedefs (%u wall quads), %u sectors (%u with sky), %u subsectors (%u lost), "
                "%u solid prisms, %u triangles, %u cells\n", TOOL, o->bsp, st.map, st.linedefs, st.wall_quads, st.sectors,
                st.sky_sectors, st.subsectors, st.lost_subsectors, st.solids, m.triangle_count, st.cells);
    mesh_free(&m);
    mesh_cells_free(&cells);
    return rc ? 1 : 0;
}

int main(int argc, char **argv) {
    import_options o;
    int rc = parse_options(argc, argv, &o);
    if (rc >= 0) return rc;
    void *data = NULL;
    size_t size = 0;
    tool_error err;
    mesh m;
    mesh_cells cells;
    bsp_pvs pvs;
    bsp_stats st;
    bsp_options bo;
    char *scripts = NULL;
    memset(&bo, 0, sizeof(bo));
    bo.patch_level = o.patch_level;
    bo.cell_step = o.cell_step;
    bo.clearance = o.clearance;
    if (o.shaders) {
        void *text;
        size_t n;
        if (read_file(o.shaders, &text, &n, &err)) {
            fprintf(stderr, "%s: %s\n", TOOL, err.message);
            return 1;
        }
        scripts = (char *)realloc(text, n + 1); /* as a string */
        if (!scripts) {
            free(text);
            fprintf(stderr, "%s: out of memory\n", TOOL);
            return 1;
        }
        scripts[n] = '\0';
        bo.shaders = scripts;
    }
    if (read_file(o.bsp, &data, &size, &err)) {
        fprintf(stderr, "%s: %s\n", TOOL, err.message);
        free(scripts);
        return 1;
    }
    if (size >= 4 && (!memcmp(data, "IWAD", 4) || !memcmp(data, "PWAD", 4))) {
        rc = import_wad(&o, data, size);
        free(data);
        free(scripts);
        return rc;
    }
    if (o.list || o.map || o.no_solids) {
        free(data);
        free(scripts);
        return tool_usage_error(TOOL, "--map, --list and --no-solids are for a WAD file; %s is not one", o.bsp);
    }
    rc = bsp_parse(o.bsp, data, size, &bo, &m, &cells, o.pvs ? &pvs : NULL, &st, &err);
    free(data);
    free(scripts);
    if (!rc) rc = write_stream_atomic(o.obj, write_obj, &m, &err);
    if (!rc && o.cells) rc = write_stream_atomic(o.cells, write_cells, &cells, &err);
    if (!rc && o.pvs) rc = write_pvs(o.pvs, &cells, &pvs, &err);
    if (rc) fprintf(stderr, "%s: %s\n", TOOL, err.message);
    else if (!o.quiet)
        fprintf(stderr,
                "%s: %s: %u surfaces (%u patches, %u without faces, %u see-through, %u one-sided), %u triangles; "
                "%u of %u world brushes solid and opaque (%u hull triangles); %u cells (of %u leaves with a cluster; "
                "%u faces kept %g off walls), %u clusters, %s\n",
                TOOL, o.bsp, st.surfaces, st.patches, st.empty_surfaces, st.translucent_surfaces, st.one_sided_surfaces, m.triangle_count,
                st.occluder_brushes, st.brushes, st.hull_triangles, st.cells, st.leaves, st.wall_faces, o.clearance,
                st.clusters,
                st.has_vis ? "vis data" : "no vis data (its PVS is everything)");
    if (!rc && !o.quiet && st.has_spawn)
        fprintf(stderr, "%s: view cells where players stand: pvsbake --cells walkable:128 --eye-height 50 --step-height 18; "
                "--walk-from %g,%g,%g (a player start) keeps the floors walked to from it (drops, no jumps)\n", TOOL,
                st.spawn[0], st.spawn[1], st.spawn[2]);
    mesh_free(&m);
    mesh_cells_free(&cells);
    if (o.pvs) bsp_pvs_free(&pvs);
    return rc ? 1 : 0;
}
