/* wad.h - a reader for Doom maps (WAD files: Doom, Doom II, Freedoom, FreeDM; the vanilla and Boom binary map
   format) that turns one map into what the tools take: a mesh and view cells. Not part of the library.

   What it makes of a map (its state at the start: doors closed, lifts up):
   - Objects, in this order: per linedef one object "wN" with its walls (a one-sided line: the front sector's floor
     to its ceiling; a two-sided line: the step between the two floors and the step between the two ceilings,
     none between two sky ceilings, as Doom draws them), empty when it has none; then per sector "floorN" and
     "ceilN", the convex polygons of its subsectors at its floor and ceiling heights (a sky ceiling is
     "occluder_skyN" instead: it blocks sight, as Doom's sky does, and is never drawn). Walls and flats are
     two-sided, each 0.01 units off the solid it lies on, toward the open side. A subsector's polygon is its BSP
     node region (the NODES partitions from the root down) clipped by its segs' lines. Last, "occluder_solids":
     the solid space as closed convex prisms (blocks sight, never drawn), as the portal method takes it: under
     each subsector's floor and over its ceiling, and the void (what the segs cut off the node regions) over the
     map's full height, each 64 units beyond the map's lowest floor and highest ceiling.
   - View cells, one per subsector whose sector is open (ceiling above floor): the box of its polygon from its
     floor to its ceiling, grown out to the 8-unit grid across (the file then stores 16-bit coordinates), in
     subsector order.
   Doom's coordinates (x, y on the map, z up) turn into the tools' Y-up: (x, y, z) -> (x, z, -y).

   The reader trusts nothing in the file: the directory, every lump's size, count and index are checked, and a bad
   one is an error naming the lump and the record ("PATH: MAP01 linedefs[12]: vertex 900 past the 880
   vertices"). Hexen-format maps (a BEHAVIOR lump) and UDMF maps (TEXTMAP) are refused with a message. */
#ifndef TOOL_WAD_H
#define TOOL_WAD_H
#include <stddef.h>
#include <stdint.h>
#include "mesh.h"
#include "toolutil.h"

typedef struct wad_stats {
    char map[9];               /* the map read */
    uint32_t linedefs, sectors, subsectors, wall_quads, sky_sectors;
    uint32_t cells;            /* subsectors with an open sector */
    uint32_t lost_subsectors;  /* subsectors whose polygon clipped away (no flats, no cell) */
    uint32_t solids;           /* closed convex prisms in occluder_solids */
} wad_stats;

typedef struct wad_options {
    uint32_t cell_step;        /* keep every cell_step-th cell only (0 or 1: every cell), for quick measurements */
    int no_solids;             /* 1: no occluder_solids (the map as its drawn surfaces and sky alone) */
} wad_options;

/* Names of the maps in the WAD in data[0..size), in directory order, written as "NAME\n" into list (at most cap
   bytes, NUL-terminated). Returns the map count, or -1 with err set. */
int wad_list_maps(const char *path, const void *data, size_t size, char *list, size_t cap, tool_error *err);

/* Reads map `map` (NULL: the first) of the WAD in data[0..size) (`path` names it in messages) into m and cells
   (cells may be NULL; those given are initialised here and must be freed, also after a failure); opt NULL: the
   defaults. Returns 0, or -1 with err set. */
int wad_parse(const char *path, const void *data, size_t size, const char *map, const wad_options *opt, mesh *m,
              mesh_cells *cells, wad_stats *stats, tool_error *err);

#endif
