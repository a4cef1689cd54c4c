/* bsp.h - a reader for Quake 3 BSP files (IBSP version 46: Quake III Arena, OpenArena, most
   id Tech 3 games) that turns a compiled level into what the tools take: a mesh, view cells and the
   level's own PVS. Not part of the library.

   What it makes of a level (issue 28):
   - Objects: one per drawn surface, in the file's surface order, so object i is surface i. Planar
     surfaces and triangle meshes keep their triangles; Bezier patches are tessellated (each 3 x 3
     control block into `patch_level` x `patch_level` quads); flares, and surfaces whose shader says
     `nodraw`, are objects with no triangles (they keep their id and are never visible). A patch has at most
     65 x 65 control points and the scene at most 2^26 vertices: bounded memory on any input.
   - One more object, last, named `occluder_brushes`: the hulls of the world's solid brushes (the
     convex polyhedra of model 0's brushes whose contents are solid and not translucent, water,
     lava, slime or fog), each a closed mesh whose faces share its corners (rounded to float once), so
     brushes that touch leave no crack. It blocks sight and is never drawn. Planar surfaces lie on brush
     faces: they are lifted 0.01 units along their normal, so a hull never hides the surface drawn on it.
   - View cells: one per BSP leaf with a cluster (leaves in solid space have none), in leaf order,
     each the leaf's bounding box, except that a face whose outside is all wall (or void: leaves without
     a cluster) moves `clearance` units inward. A camera is never on a wall (the near plane and the
     player's hull keep it off: Quake 3's near plane is 4 units, its player 15 units wide each side of
     the eye), and a box that touches a wall holds points on the wall's surface, from which a ray grazes
     into the brush and sees what is drawn on its far side: the bake must then keep the next room's
     walls (q3map2's vis, working from portals, never does). A face is wall when the slab from 1/4 to 1
     clearance beyond it, inset 1/4 from its edges, reaches only such leaves; faces partly on portals
     stay, so the cells cover every point of the leaves more than 1.3 clearances from a wall (a camera
     nearer may be in no cell: pvs_file_find_cell returns PVS_NO_CELL).
   - The level's PVS (what q3map2's vis computed) expanded to objects: cell c sees every surface of
     every leaf whose cluster is visible from c's cluster, and the surfaces of the inline models
     (doors, platforms) whose bounds meet such a leaf's box. A level compiled without vis sees all.
   Coordinates turn from Quake's Z-up into the tools' Y-up: (x, y, z) -> (x, z, -y).

   Surfaces whose shader's contents say see-through (water, slime, lava, fog, translucent: glass,
   grates, foliage) are see-through objects (MESH_OBJECT_SEE_THROUGH, named "see_through_sN" so the
   OBJ keeps the flag): drawn, never blocking sight; `bsp_stats.translucent_surfaces` counts them.
   Given the game's shader scripts (`bsp_options.shaders`), planar opaque surfaces that Quake 3 draws
   front only (its default; no `cull none`, `disable`, `twosided` or `back`, no `deformVertexes`,
   `portal` or sky) and whose triangles all wind clockwise about the surface's normal (Quake's front
   faces; a few do not) are one-sided (MESH_OBJECT_ONE_SIDED, "one_sided_sN"), written counter-clockwise
   as the library takes them: a cell behind all of such a surface leaves it out. Patches and triangle
   meshes (models) stay two-sided: their stored normals do not say which side is drawn.

   The reader trusts nothing in the file: every lump, count, index and range is checked, and a bad
   one is an error naming the lump and the record ("PATH: faces[12]: vertex range 90+12 past the 95
   vertices"). */
#ifndef TOOL_BSP_H
#define TOOL_BSP_H
#include <stddef.h>
#include <stdint.h>
#include "mesh.h"
#include "toolutil.h"

typedef struct bsp_options {
    uint32_t patch_level;     /* quads per side of each 3 x 3 patch block: 0 = 4, at most 32 */
    uint32_t cell_step;       /* keep every cell_step-th cell only (0 or 1: every cell), for quick measurements */
    double clearance;         /* cells keep this far off walls (0: the leaves' boxes; pvsimport's default: 1) */
    const char *shaders;      /* the game's shader scripts (its .shader files in one text): with them, a planar opaque
                                 surface whose shader culls back faces (no cull none, disable, twosided, back or
                                 deformVertexes) and whose triangles all wind as Quake's front faces is one-sided
                                 (MESH_OBJECT_ONE_SIDED, "one_sided_sN", turned counter-clockwise); NULL: none is */
} bsp_options;

typedef struct bsp_stats {
    uint32_t surfaces, patches, empty_surfaces, translucent_surfaces, one_sided_surfaces;
    uint32_t brushes, occluder_brushes, hull_triangles;
    uint32_t leaves, clusters;  /* leaves with a cluster, clusters in the vis data */
    uint32_t cells;             /* cells made: the leaves with a cluster, every cell_step-th */
    uint32_t wall_faces;        /* cell faces kept `clearance` off a wall */
    int has_vis;                /* the level has vis data (else its PVS is everything) */
    int has_spawn;              /* the entities name a player start (info_player_*) with an origin */
    float spawn[3];             /* the first one's origin, Y up: a seed for pvsbake --walk-from */
} bsp_stats;

/* The level's own PVS, cell-major bitsets of `words` 64-bit words per cell (malloc'd). */
typedef struct bsp_pvs {
    uint64_t *bits;
    uint32_t cell_count, object_count, words;
} bsp_pvs;

/* Reads the BSP file in data[0..size) (`path` names it in messages) into m, cells and pvs (each may
   be NULL when not wanted; those given are initialised here and must be freed, also after a
   failure). Returns 0, or -1 with err set. */
int bsp_parse(const char *path, const void *data, size_t size, const bsp_options *opt, mesh *m, mesh_cells *cells,
              bsp_pvs *pvs, bsp_stats *stats, tool_error *err);
void bsp_pvs_free(bsp_pvs *pvs);

#endif
