/* gen.h - deterministic procedural test scenes for pvs.h: a Vienna-like city, a forest, an indoor
   floor plan, a maze of zero-thickness walls and a triangle soup, each with view cells. Not part of
   the library; the tools, examples and tests use it.

   All scenes are Y-up (the OBJ convention), units are metres, the ground is at y = 0. The output
   depends only on the parameters: the generators use their own PRNG (splitmix64), draw at most one
   random number per C expression (argument order is unspecified), and use only +, -, *, /, sqrt,
   floor, ceil and fabs (all exact or correctly rounded in IEEE 754), never sin/cos/pow/exp. So the
   same parameters give bit-identical arrays on every platform, provided the compiler does not
   contract a*b+c into fused multiply-adds: gcc in -std=c99 mode does not, clang obeys the
   FP_CONTRACT pragma in gen.c; for gcc -std=gnu99 on FMA targets add -ffp-contract=off.
   tests/test_gen.c pins hashes of small scenes (gcc and clang, -O0..-O3, -march=native agree).

   Scenes at size = 1 (seed 1: objects / triangles / cells; generation time on one core):
   city    3575 / 457k / 1211, ~0.03 s. ~1 km x 1 km, 12 x 12 blocks on a jittered grid, streets
           6-25 m wide, one straight avenue (30-36 m) crossing the whole city along x, one block left
           empty as an open square (monument_0 and kiosks) next to the avenue.
           Objects: building_N (~540; an extruded footprint - rectangle, L, U, T, Z, courtyard ring
           or irregular star polygon - 8-40 m high: walls, flat roof, facade detail as thin boxes in
           front of the walls: cornices, ledges, window boxes, balconies up to 1.2 m deep),
           lamp_N and kiosk_N (street objects), ground_I_J (25 m tiles at y = 0, always visible).
           Below y = 3.3 a building holds only its walls and 8 cm window boxes; ledges, balconies
           and cornices are higher.
           Cells: y 0.5..2.0, only on streets and the square (never inside a block's outline),
           >= 0.3 m from every building footprint and street object: 24 m tiles, split to 12 m
           tiles and 12 x 6 m strips near buildings, merged along streets up to 24 m. Then the
           special cells described by gen_info.
   forest  3297 / 462k / 895, ~0.07 s. 300 m x 300 m, ~3000 trees on a jittered 5 m grid, a few
           round clearings and one straight 4 m path along x. Objects: tree_N (one object per tree:
           its first 16 triangles are the trunk, a tapering hexagonal prism 5-12 m high, then 3-6
           leaf clusters of 20-40 small random triangles; every leaf is above y = 2.6, so cells see
           under the crowns), ground_I_J (20 m tiles at y = 0).
           Cells: y 0.5..2.0; whole 10 m tiles inside clearings, else one 3 m box per 10 m tile
           placed between the trunks (>= 0.25 m from any trunk) when a free spot is found.
   forest --dense (gen_params.dense)  6687 / 489k / 330, ~0.6 s. A forest like Durand 2000 §7.2's
           (7,750 trees of 1,000 leaves, "coarse and made of large triangles"): same 300 m square,
           3 clearings, a 3 m path along x; trees on a jittered 4.5 m grid (tree_N: a 16-triangle
           trunk 6-14 m high, then leaves 0.7-1.5 m: conifers 4-6 clusters of 18-24 from 0.8-1.6 m
           up to the top, broadleaves 3-5 clusters of 18-24 from 1.4-3 m up), and bushes (bush_N:
           2-3 clusters of 14-20 smaller leaves on the ground) beside 95% of the trees. From a cell
           inside it ray sampling sees ~11% of the objects (~25% adding rays aimed at each object).
           Cells: 10 m tiles in clearings, else one 3 m box (y 0.5..2.0) per 10 m tile where one
           touches no triangle (0.1 m margin).
           With leaves_per_tree 1000 and cell_size 1 (the paper's density; bushes 10 times as dense):
           6687 / 4.6M / 781, ~7 s with the OBJ; ray sampling sees ~2% of the objects from the inner cells.
   indoor  783 / 6.3k / 344. An 80 m x ~45 m office floor: two bands of rooms on either side of a
           corridor, a west corridor joining the corridors, a column hall; walls 0.3 m thick and
           3 m high, doors 1 m wide and 2.1 m high. Objects: wall_N (a closed box per wall segment
           between doors), lintel_N (the box above a door), column_N, table_N, cabinet_N, chair_N,
           floor_I_J and ceiling_I_J (4 m tiles at y = 0 and y = 3).
           Cells: y 0.5..2.0; ~3 m tiles in rooms and corridors (2 m in the hall) avoiding
           furniture and columns, one cell filling each doorway (x/z inside the wall's thickness).
   walls   644 / 3.2k / 486. A 24 x 24 maze of 4 m squares made only of zero-thickness two-sided
           quads, with loops. Objects: wall_N (a quad per run of up to 4 segments; 8% low (<= 1.2 m,
           seen over), 8% raised 0.8-1.2 m above the ground (seen under)), panel_N (free-standing
           quads at random angles), box_N and pyramid_N (small objects in corners). No ground.
           Cells: y 0.5..2.0, one per maze square without a panel.
   building  ~13k objects at size 1. round(6 size) storeys (at least 2) of the indoor floor plan at twice
           the size (160 m x ~90 m at size 1), 3 m high, on closed 0.4 m slabs cut into 4 m tiles
           (slab_L_I_J); a stair well at the north end of the west corridor (16 closed steps per
           flight, s<K>_stair_N) and an open shaft at its south end go through every slab between
           storeys; the storeys' objects are the floor plan's, named s<K>_NAME, without its floor and
           ceiling tiles. No windows yet. Cells: the floor plan's on every storey, but none over the
           stairs or the shaft.
   soup    2000 / 50k / 880, ~0.015 s. Objects soup_N of 10-40 random triangles (edges 0.15-3 m,
           random orientations) in a 100 m cube; cells are 3 m cubes that touch no triangle.

   size scales the extent: the area (city blocks per side, forest, indoor, walls) or the volume
   (soup) grows with size^2 (size^3 for soup); valid sizes are (0, 8]. Every object is non-empty
   and has a unique name without spaces; no triangle is degenerate; no NaN. Cells never overlap
   each other (they may share faces). No cell touches any triangle, except the city's deliberate
   partly-inside cells (checked with an exact triangle/box test by tests/test_gen.c). The
   generators emit no "occluder" objects.

   Thread safety: no global state; concurrent calls on different meshes are fine. */
#ifndef TOOL_GEN_H
#define TOOL_GEN_H
#include <stdint.h>
#include "mesh.h"

typedef enum gen_kind { GEN_CITY = 1, GEN_FOREST, GEN_INDOOR, GEN_WALLS, GEN_SOUP, GEN_BUILDING } gen_kind;

typedef struct gen_params {
    gen_kind kind;
    uint64_t seed;
    float size;         /* scale factor, 1 = default; (0, 8] */
    uint32_t max_cells; /* 0 = all; otherwise an evenly spread subset of at most this many cells */
    int dense;          /* forest only (other kinds: bad params): the dense forest described above; 0 = the default */
    uint32_t leaves_per_tree; /* dense forest only (else bad params unless 0): leaves per tree, spread evenly over its
                                 clusters (1000: Durand 2000 §7.2's forest), and the bushes' leaves scaled by
                                 leaves_per_tree / 100; leaves_per_tree x size^2 <= 10000 (about 40M
                                 triangles); 0 = the default (~85-105) */
    float cell_size;    /* dense forest only (else bad params unless 0): the side of the inner cells, in [0.1, 8]; 0 = 3 m */
} gen_params;

/* Where the deliberate stress cells are. Cells are ordered: regular cells first, then
   touching_count cells that touch geometry (a regular cell with one horizontal face grown to within
   1 mm of a wall, a window box or a street object; they intersect nothing), then inside_count cells
   that are PARTLY INSIDE a building (a 4-8 m box centred on a footprint corner; they do intersect
   wall triangles). Only the city has special cells: up to 4 + 4 (4 + 4 at the default size) when
   max_cells is 0 or >= 16, none otherwise; other kinds have none (touching_count = inside_count = 0,
   regular_count = cells->count). Without gen_info: in a default city the last 4 cells are the
   partly-inside ones, and the cells file pvsgen writes names both ranges in '#' comments. */
typedef struct gen_info {
    uint32_t regular_count;  /* cells [0, regular_count) */
    uint32_t touching_first, touching_count;
    uint32_t inside_first, inside_count; /* inside_first + inside_count == cells->count */
} gen_info;

/* Fills an initialised, empty mesh and cells. Returns 0, or -1 on out of memory / bad params
   (NULL pointers, unknown kind, size not in (0, 8], mesh or cells not empty). Bad params leave
   mesh and cells untouched; after running out of memory they are freed back to empty. */
int gen_scene(const gen_params *p, mesh *m, mesh_cells *cells);
/* Same, and describes the special cells in *info (info may be NULL). */
int gen_scene_ex(const gen_params *p, mesh *m, mesh_cells *cells, gen_info *info);

/* "city", "forest", "indoor", "walls", "soup"; NULL for an unknown kind. */
const char *gen_kind_name(gen_kind k);
/* Parses one of the names above (exact, lower case). Returns 0, or -1 when unknown. */
int gen_kind_parse(const char *s, gen_kind *out);

#endif
