/* pvs.h - v0.3.0 - conservative potentially visible sets: bake, store, look up, cull - public domain or MIT (see end of file)

   QUICK START
   ===========
   Do this:
       #define PVS_IMPLEMENTATION
   before you include this file in *one* C or C++ file to create the implementation.

       #define PVS_IMPLEMENTATION
       #include "pvs.h"

       // positions: 3 floats per vertex; indices: 3 per triangle; one range of triangles per object
       pvs_object_desc objects[2] = {{0, 12, 0}, {12, 12, 0}};
       pvs_scene_desc sd = {0};
       sd.positions = positions; sd.vertex_count = vertex_count;
       sd.indices = indices;     sd.triangle_count = triangle_count;
       sd.objects = objects;     sd.object_count = 2;
       pvs_scene *scene; pvs_error err;
       if (pvs_scene_create(&sd, &scene, &err) != PVS_OK) { puts(err.message); return 1; }

       pvs_box cells[1] = {{{-1, 0, -1}, {1, 2, 1}}};
       pvs_bake_desc bd = {0};
       bd.scene = scene; bd.cells = cells; bd.cell_count = 1;
       pvs_bake *bake;
       pvs_bake_begin(&bd, &bake, &err);
       for (uint32_t t = 0; t < pvs_bake_task_count(bake); ++t)   // any order, any thread
           pvs_bake_run_task(bake, t, &err);
       size_t size = pvs_bake_file_size(bake);
       void *file_bytes = my_alloc(size);                        // your memory
       pvs_bake_write_file(bake, file_bytes, size, &size, &err);  // the .pvs file, ready to save
       pvs_bake_destroy(bake);

       // runtime: no allocation, safe on untrusted bytes
       pvs_file file;
       pvs_file_open(file_bytes, size, &file, &err);
       uint32_t cell = pvs_file_find_cell(&file, eye);           // PVS_NO_CELL outside every cell
       pvs_word visible[PVS_BITSET_WORDS(2)];
       pvs_file_decode(&file, cell, visible, PVS_BITSET_WORDS(2), &err);
       if (pvs_bitset_test(visible, 1)) draw(1);

   WHAT IT DOES NOT DO
   ===================
   - No rendering API: it hands you object ids; you draw.
   - No mesh-file loading: the scene comes from your arrays (the tools/ folder has an OBJ loader).
   - No threads of its own: a bake is split into tasks you run on your job system (see THREADS).
   - No file I/O: it writes into and reads from memory you own.

   TABLE OF CONTENTS (search for the banner, e.g. ">>kdtree")
   =================
   >>docs       this manual
   >>api        the declarations, one block per module
   >>core       result codes, allocator hooks, vec3/box/plane math, bitsets
   >>scene      scene description, object bounds, triangle storage, explicit occluders
   >>kdtree     kD-tree over boxes: build, front-to-back sweep, ray cast, point location
   >>raster     conservative rasterizer, depth pyramid, cull map, per-frame culling
   >>otree      occlusion trees: line-space BSP; exact 2D and conservative 2.5D (c-LSS) region visibility;
                from-point shadow-volume tree culling (pvs_otree_cull)
   >>occluders  occluder synthesis: voxelize, flood from the cells, erode by eps, boxes / columns
   >>vocc       virtual occluders (Koltun 2000): aggregate umbrae, height slices, selection, the VOCC
                section, the PVS rebuilt on cell entry (pvs_vocc_cull)
   >>methods    region methods: `shrink` (Wonka 2000), extended projections `extproj`, the estimator `sample`
   >>bake       bake driver: tasks, AUTO (methods intersected), draw distance, resuming, determinism
   >>format     the .pvs file: writer and validating zero-copy reader
   >>runtime    cell look-up and decoding

   CONFIGURATION (define before including the implementation)
   =============
   | macro                 | default            | what it changes                                          |
   |-----------------------|--------------------|----------------------------------------------------------|
   | PVS_IMPLEMENTATION    | undefined          | emit the implementation in this translation unit         |
   | PVS_STATIC            | undefined          | make every function static (private copy per unit)       |
   | PVS_API               | extern / static    | decoration of every public function                     |
   | PVS_MALLOC(sz)        | malloc(sz)         | fallback allocator when a desc's allocator is zero;     |
   | PVS_FREE(p)           | free(p)            |   define both or neither                                 |
   | PVS_ASSERT(x)         | assert(x)          | checks of programmer misuse only, never of input data    |
   | PVS_NO_STDIO          | undefined          | error messages without snprintf (reason strings only)    |
   | PVS_NO_SIMD           | undefined          | scalar code paths only (identical results)               |

   CONCEPTS
   ========
   Coordinates. Any right- or left-handed frame; `up_axis` in the scene (1 = Y, the OBJ default, or
   2 = Z) tells the 2.5D methods which axis is height. Cells are axis-aligned boxes in scene units.

   Conservative. A PVS lists every object visible from any point of its cell (a superset of the exact
   set). Methods with a sampling or shrinking distance `eps` are conservative for every eps; smaller eps
   is tighter and slower. The `sample` method (ray sampling) is the exception: it is an estimate from
   below, the yardstick the tests measure the conservative methods against, and files baked with it
   carry PVS_FILE_APPROXIMATE.

   Methods. AUTO, the default, picks the conservative methods that can cull in the scene: OTREE when
   vertical walls stand on the ground (2.5D), EXTPROJ when there are planar occluders or convex solids
   (3D), SHRINK when closed geometry leaves occluder volume after erosion by eps (VOCC, which adds
   little tightness, only when pvs_bake_desc.methods names it); it runs them cheapest
   first and intersects their PVSs (an intersection of conservative sets is conservative, and at least
   as tight as each). pvs_bake_get_method_info says which ran, which were skipped and why, and what
   each contributed; pvs_bake_desc.methods restricts the candidates. SAMPLE is never among them.
   PVS_BAKE_PREVIEW keeps only the cheapest with coarse settings. max_distance (a draw distance) drops
   objects whose box is farther than it from every point of the cell (box to box, rounded toward
   keeping). pvs_bake_restore_task resumes an interrupted bake from the PVSs it had finished (not a
   VOCC bake: its virtual occluders are baked again). Only a VOCC bake stores virtual occluders; AUTO
   uses vocc's PVS in the intersection and stores none.

   Memory. Every desc struct has a `pvs_allocator`; left at zero, PVS_MALLOC/PVS_FREE are used. An object
   remembers its allocator. Size arithmetic is overflow-checked. The runtime (pvs_file_*) and the
   kD-tree queries allocate nothing: they use the caller's memory.

   Threads. pvs.h starts no thread and keeps no global mutable state. Read-only objects (a created
   pvs_scene, pvs_kdtree, an opened pvs_file) may be used from any number of threads at once. A bake
   is split into tasks: pvs_bake_run_task may run concurrently for distinct task indices (the allocator
   must then be thread-safe; malloc is). Output is byte-identical whatever the order or thread count.

   Errors. Functions return pvs_result (0 = PVS_OK, negative = error); pvs_result_string() names it.
   Most take an optional `pvs_error *` that receives the code, the index of the offending element
   (object, triangle, vertex, cell, occluder, record) or byte offset, and a message. NULL is allowed.
   PVS_ASSERT guards programmer misuse only; bad data is always a result code.

   Trust. pvs_scene_create validates every index, count and coordinate. pvs_file_open is safe on
   untrusted bytes: it checks every offset, size, count and checksum before use, never reads outside
   the buffer, and later calls on an opened file cannot fail on the file's content.

   Culling. pvs_raster_create allocates a context once (depth map, pyramid, cull map, scratch); then
   each frame pvs_raster_cull (3D: occluder triangles -> depth pyramid -> front-to-back kD-tree walk)
   or pvs_raster_cull_map (2.5D: facade shadows -> cull map -> grid scan) sets the visible objects and
   allocates nothing. Both are conservative: every object seen through the screen from the near
   plane on is reported, whatever the rounding (>>raster explains the margins). Depth is reversed
   (larger is nearer). Pass a cell's decoded PVS as `candidates` to cull inside it. Depth maps above
   65,536 pixels keep occluders in Masked Occlusion Culling's tiles (fast, a little coarser); smaller
   ones per pixel; PVS_RASTER_TILED / PVS_RASTER_PER_PIXEL choose. The object-space twin,
   pvs_otree_create / pvs_otree_cull (Bittner 2002 ch. 4), takes the same camera, parameters and
   outputs: a shadow-volume occlusion tree of a few dozen occluder polygons instead of a depth map,
   exact box tests, and temporal coherence (it remembers the last frame's occluders and node
   states); it too allocates nothing per frame.

   Virtual occluders. A file baked with the vocc method (Koltun 2000) also stores a few vertical
   rectangles per cell (about 50 bytes) that are hidden from the whole cell; on cell entry
   pvs_vocc_cull tests the engine's object boxes against them (top-down through a kD-tree, no
   allocation) and sets the cell's PVS: a platform short of storage can bake --vocc-only and keep
   only them.

   MEMORY
   ======
   Allocates (through the desc's allocator): pvs_scene_create (triangles, object and triangle
   kD-trees: about 100 bytes per triangle), pvs_bake_begin (the cells and one bitset per cell:
   cell_count * object_count / 8 bytes, and 40 bytes of statistics per cell), pvs_bake_run_task
   (AUTO: one bitset per method it runs, freed before returning), pvs_file_encode (scratch about 40 bytes per cell plus one
   bitset), pvs_raster_create (the depth map and pyramid, the cull map), pvs_otree_create (about 250
   bytes per tree node of its budget, 5 bytes per kD node and object). Allocates nothing: every
   pvs_file_* and pvs_cursor_* call, kD-tree queries (caller scratch), pvs_raster_cull,
   pvs_raster_cull_map and pvs_otree_cull per frame, pvs_vocc_cull (caller scratch:
   pvs_vocc_cull_scratch_size). A .pvs file is used in place; it needs no copy.

   PERFORMANCE (`make bench`, 2026-11-22, one core of a shared 2-core AMD EPYC VM, release build)
   ===========
   kD-tree build 0.8 s per million triangles; 0.55 M closest-hit rays/s (200k-triangle boxes);
   demo city (3,575 objects, 457k triangles, 1,211 cells): file 0.099 of raw bitsets, 44 bytes per
   cell, encode 0.1 s; decode of a cell 3-5 us; a cursor move 0.2-1.3 us (one delta or a full
   decode); pvs_file_find_cell with 10,000 cells about 90 ns along a camera path, 130 ns at random
   points; per-frame culling of 50,000 occluder triangles at 1920x1080 with 10,000 box tests about
   1.0 ms (SSE2; 2.0 ms scalar), 1,000 facades into a 256 x 256 cull map about 0.8 ms; from-point
   culling with the occlusion tree (pvs_otree_cull, 32 occluders) about 0.2 ms of CPU per frame
   along a street walk; bake methods per cell on the demo city: extproj about 45 ms, otree about
   9 ms of CPU (2026-11-24), shrink about 260 ms (default eps), vocc about 60 ms of CPU (10 virtual
   occluders per cell, 52 bytes, 88% of the objects culled: 98% of what shrink culls; rebuilding a
   cell's PVS from them about 70 us testing every box, 110 us walking a kD-tree of 16-item leaves).

   ALGORITHMS (each cited again where it is implemented)
   ==========
   kD-tree, front-to-back sweep by priority queue, occlusion trees: Bittner 2002 (§3.2, §4.4,
   ch. 4, 6, 7). Delta-PVS storage, extended projections, hierarchical depth map: Durand et al.
   2000 (§2.4, §3, §5, §6). Cull maps and occluder shadows: Wonka and Schmalstieg 1999 (§3-4).
   Occluder shrinking and point sampling: Wonka, Wimmer and Schmalstieg 2000. Virtual occluders:
   Koltun, Chrysanthou and Cohen-Or 2000. Watertight ray-triangle test: Woop, Benthin and Wald
   2013. Masked occlusion culling (tiles of coverage masks): Hasselgren, Andersson and Akenine-Moller
   2016. Rice codes: Golomb 1966, Rice 1979.

   FILE FORMAT (version 1; all integers little-endian; offsets from the start of the file)
   ===========
   A .pvs file is the delta-PVS of Durand et al. 2000 (§6.2): a few key cells store their PVS whole,
   every other cell stores the objects that differ from a base cell, with a bound K on chain length.
   pvs_file_open checks every rule below and rejects a file that breaks any (the code in brackets);
   it is safe on untrusted bytes.
   header, 32 bytes:
     0  u8[4]  magic "PVS\x1a"                                             [BAD_MAGIC]
     4  u32    format version (PVS_FORMAT_VERSION); a reader rejects any other [BAD_VERSION]. A
               version changes only when a version-1 reader would misread a file; new optional
               sections do not change it.
     8  u32    file size in bytes (must equal the buffer size)                [TRUNCATED, BAD_HEADER]
     12 u32    section count S (1..64)                                        [BAD_HEADER]
     16 u32    flags (PVS_FILE_APPROXIMATE = 1); unknown bits are ignored
     20 u32    CRC-32 (IEEE) of bytes 0..19 and of the section table          [CHECKSUM]
     24 u32[2] reserved, zero                                                 [BAD_HEADER]
   section table at 32: S entries of 16 bytes: u32 tag, u32 offset, u32 size, u32 CRC-32 of the
     section's bytes [CHECKSUM]. Sections start 8-byte aligned, lie inside the file, do not overlap
     and no tag repeats [BAD_SECTION, TRUNCATED]; every byte outside the header, the table and the
     sections is zero padding [BAD_SECTION]. Tags are four ASCII characters; a reader skips tags it
     does not know (room for later optional sections: object names, ...). The writer emits META,
     CELL, TREE, RECS, then SHRD for part files, then VOCC when the bake made virtual occluders.
   "META" (required, 32 bytes; another size is BAD_SECTION) [BAD_HEADER; COUNT_OVERFLOW for counts
     past the limits]:
     0 u32 cell_count (1..2^30-1)   4 u32 object_count (1..2^32-2)   8 u32 method (pvs_method)
     12 f32 eps (finite, >= 0)      16 u32 up_axis (1 = Y, 2 = Z)    20 u32 K, the chain bound (1..64)
     24 u32 key cell count (1..cell_count, equal to the records' count)   28 u32 reserved zero
   "CELL" (required): the cell boxes, as indices into per-axis coordinate tables [BAD_SECTION, BAD_CELL]:
     0 u32 n[3]: distinct coordinates per axis (1..2 * cell_count)
     12 u8 w[3]: min index widths in bits, w = the bits needed for n - 1 (0 when n = 1)
     15 u8 x[3]: extent widths in bits (<= w)      18 u8[2] zero
     20 f32 tables: n[0] values of axis 0, then axis 1, then axis 2; each finite, strictly
        ascending, never -0 (the writer stores -0 as +0)
     then the packed fields: per cell, in cell order, min0 min1 min2 of widths w0 w1 w2 and the
        extents e0 e1 e2 of widths x0 x1 x2 (max index = min index + extent < n), least
        significant bit first, back to back; the unused high bits of the last byte are zero. The
        section ends there.
   "TREE" (required): the cell look-up kD-tree, a complete binary tree of depth D stored implicitly
     (the children of node k are 2k + 1 and 2k + 2; leaf j is node 2^D - 1 + j) [BAD_TREE]:
     0 u32 D (0..24)   4 u32 zero   8 f32 splits[2^D - 1] (finite)   then u32 leaf offsets[2^D + 1]
     (offsets[0] = 0, ascending, the last = the item bytes' size)   then u8 axes[2^D - 1] (0..2; a
     node whose cells all go left has split FLT_MAX)   then the item bytes: leaf j's cell ids in offsets[j] ..
     offsets[j + 1], varints, the first id then the gaps minus one between ascending ids, each id
     < cell_count. The section ends there.
     Look-up of a point p: at an inner node p[axis] < split goes left, > split right, == split
     both; in a leaf the lowest id whose closed box contains p. The writer puts a cell on the left
     when min < split or max <= split and on the right when max > split, so every cell containing
     p is found (pvsinfo --verify checks a file's tree against its cells).
   "RECS" (required): the PVS records [BAD_SECTION, BAD_RECORD, OBJECT_OUT_OF_RANGE, BAD_CHAIN]:
     0 u32 block offsets[B + 1], B = ceil(cell_count / 16), from the section start: offsets[0] =
       4 (B + 1), ascending, offsets[B] = the section size. Block b holds the records of cells
       16b .. 16b + 15 back to back and nothing else.
     A record: varint R, the byte count of the rest; varint head: coding = head & 3 (of the added
       ids), depth = head >> 2 (0 = a key cell, else a delta, depth <= K). A key: the set of its
       PVS's ids (universe object_count) in that coding. A delta: varint z, the base cell =
       cell - (z even ? z / 2 : -(z + 1) / 2) (zigzag), another cell whose depth is one less (so
       chains end at a key within K steps and cannot cycle); u8 coding of the removed objects (0..3);
       varint m, the size of the base's PVS (<= object_count); the removed objects as a set of
       ranks in the base's PVS (universe m: rank r = the base's (r+1)-th smallest id); then the
       added ids (universe object_count, never in the base's PVS) in the head's coding. The sets
       must fill the record exactly. A set is coded one of four ways, each self-delimiting:
         0 gap varints: varint count, then count varints: the first id, then gaps minus one.
         1 run lengths: varint pairs, then per pair varint zeros, varint ones - 1: alternating runs
           from id 0 (zero runs after the first are >= 1); the set ends after the last ones run.
         2 Rice codes: u8 k (0..24), varint count, then count codes, least significant bit first:
           gap >> k as that many 1 bits and a 0 bit, then the k low bits of gap (gaps as in coding
           0); the codes end at a byte boundary, the unused high bits are zero.
         3 raw bitset: ceil(universe / 8) bytes, bit i of byte j = id 8j + i; bits past the
           universe are zero.
       The writer picks the smallest coding of each set, ties to the lower number. A decoder takes
       the key at the end of the chain and applies the deltas from there (removals, then additions).
       A reader cannot check that m matches the base's PVS without decoding; pvsinfo --verify does.
       Ranks past the base's PVS in a damaged file are ignored, never read out of bounds.
     Varints everywhere are LEB128, at most 5 bytes, the value fits 32 bits, no needless 0x80 bytes.
   "SHRD" (optional, 16 bytes, else BAD_SECTION; part files of a sharded bake) [BAD_HEADER]: u32 shard index (0-based),
     u32 shard count (>= 2), u32 total cell count, u32 zero. Cell j of the part is cell
     index + j * count of the whole; cell_count must be the number of such cells.
   "VOCC" (optional; virtual occluders, Koltun et al. 2000, >>vocc) [BAD_SECTION]: per cell a few
     vertical rectangles, each hidden from every point of the cell, most effective first; the
     runtime rebuilds the cell's PVS from them (pvs_vocc_cull).
     0  u32 flags: bit 0 = the records are placeholders (pvsbake --vocc-only: every drawable
        object); other bits zero
     4  u32 N, the occluders of all cells (<= 255 * cell_count)
     8  f32 base, every occluder's bottom height    12 f32 step (> 0); both finite, base + 255 step too
     16 u32 first[B + 1], B = ceil(cell_count / 16): first[b] = the index of the first occluder of
        cell 16b; first[0] = 0, first[B] = N, first[b + 1] - first[b] = the sum of block b's counts
     then u8 count[cell_count]: occluders per cell (0..255)
     then u8 scale[cell_count]: the cell's coordinate scale S = 2^((scale - 128) / 8), exactly the
        double nearest 2^(k / 8) for k = scale mod 8 times 2^(scale div 8 - 16)
     then N occluders of 5 bytes, cell by cell: u8 q0 q1 (end point 0), q2 q3 (end point 1), q4 (top).
        Ground coordinate (u, v along the up axis' ground axes) = centre + S (q - 128) |q - 128| /
        16384, in double, where centre = 0.5f min + 0.5f max of the cell's box computed in float
        (finer steps near the cell: the perspective); top = base + q4 step (in double).
     The section ends there: its size is exactly 16 + 4 (B + 1) + 2 cell_count + 5 N. The bake rounds
     each occluder toward a smaller one (end points pulled inward and away from the cell, the top
     down) and proves the rounded occluder hidden, so the stored bytes are conservative as they are.
     A reader that does not know VOCC skips it; the records stay a valid PVS.

   RECENT HISTORY
   ==============
   next               PVS_METHOD_AUTO, the default (the applicable conservative methods, intersected),
                      bake max_distance, PVS_BAKE_PREVIEW, resumable bakes (pvs_bake_restore_task);
                      virtual occluders (Koltun 2000): bake method vocc, the optional VOCC section,
                      pvs_vocc_cull rebuilds a cell's PVS from them; pvsbake --vocc-only.
   0.3.0 (2026-11-22) conservative rasterizer, depth pyramid, cull maps and per-frame culling;
                      bake methods shrink (with occluder synthesis), otree (c-LSS) and extproj.
   0.2.0 (2026-11-22) the delta-PVS file (format 1): key cells and depth-bounded deltas, four set
                      codings, compact cell tables and look-up tree, cursor, sharded bakes.
   0.1.0 (2026-11-22) scene, kD-tree, ray-sampling estimator, bake tasks, .pvs container.
*/
// >>api
#ifndef PVS_H
#define PVS_H

#include <stddef.h>
#include <stdint.h>

#define PVS_VERSION_MAJOR 0
#define PVS_VERSION_MINOR 3
#define PVS_VERSION_PATCH 0
/* (major << 16) | (minor << 8) | patch */
#define PVS_VERSION ((PVS_VERSION_MAJOR << 16) | (PVS_VERSION_MINOR << 8) | PVS_VERSION_PATCH)
/* The .pvs file format version this header writes and reads. */
#define PVS_FORMAT_VERSION 1

#ifndef PVS_API
#ifdef PVS_STATIC
#if defined(__GNUC__) || defined(__clang__)
#define PVS_API static __attribute__((unused))
#else
#define PVS_API static
#endif
#else
#define PVS_API extern
#endif
#endif

#ifdef __cplusplus
extern "C" {
#endif

/* ---- core ------------------------------------------------------------------------------------ */

/* Result of every fallible call. 0 is success, errors are negative. */
typedef enum pvs_result {
    PVS_OK = 0,
    PVS_ERROR_INVALID_ARGUMENT = -1,   /* NULL where not allowed, impossible parameter */
    PVS_ERROR_OUT_OF_MEMORY = -2,      /* the allocator returned NULL */
    PVS_ERROR_COUNT_OVERFLOW = -3,     /* a count or size does not fit the index or size type */
    PVS_ERROR_INDEX_OUT_OF_RANGE = -4, /* a vertex, triangle or object index past its array */
    PVS_ERROR_NOT_FINITE = -5,         /* NaN or infinity in a coordinate or parameter */
    PVS_ERROR_EMPTY_OBJECT = -6,       /* an object with no triangles */
    PVS_ERROR_DEGENERATE_OBJECT = -7,  /* an object whose triangles all have zero area */
    PVS_ERROR_OVERLAPPING_OBJECTS = -8,/* two objects claim the same triangle */
    PVS_ERROR_BAD_OCCLUDER = -9,       /* an explicit occluder volume that is empty, unbounded or malformed */
    PVS_ERROR_BAD_CELL = -10,          /* a cell box with NaN or min > max */
    PVS_ERROR_BUFFER_TOO_SMALL = -11,  /* the caller's output buffer is smaller than needed */
    PVS_ERROR_BAD_MAGIC = -12,         /* not a .pvs file */
    PVS_ERROR_BAD_VERSION = -13,       /* a .pvs file of another format version */
    PVS_ERROR_TRUNCATED = -14,         /* the buffer ends before the data it declares */
    PVS_ERROR_BAD_SECTION = -15,       /* a section missing, repeated, misaligned, overlapping or outside the file */
    PVS_ERROR_CHECKSUM = -16,          /* stored and computed checksums differ */
    PVS_ERROR_BAD_RECORD = -17,        /* a malformed PVS record (varint, order, length) */
    PVS_ERROR_OBJECT_OUT_OF_RANGE = -18,/* a record names an object id >= object count */
    PVS_ERROR_BAD_HEADER = -19,        /* a header or META field with an impossible value */
    PVS_ERROR_NOT_DONE = -20,          /* a bake result asked for before every task ran */
    PVS_ERROR_UNSUPPORTED = -21,       /* the method cannot handle this input (the message says why) */
    PVS_ERROR_BAD_CHAIN = -22,         /* a delta record whose base chain is cyclic, too long or inconsistent */
    PVS_ERROR_BAD_TREE = -23,          /* a malformed cell look-up tree in a .pvs file */
    PVS_ERROR_SHARD_MISMATCH = -24,    /* part files that do not make up one bake (missing, repeated, different) */
    PVS_RESULT_MIN = -25               /* sentinel: every result is > PVS_RESULT_MIN */
} pvs_result;

/* Where and why a call failed. Every fallible call takes an optional pvs_error* (NULL allowed). */
typedef struct pvs_error {
    pvs_result result;   /* same as the return value */
    int64_t index;       /* offending object/triangle/vertex/cell/occluder/record index, or -1 */
    uint64_t offset;     /* byte offset into a file for format errors, else 0 */
    char message[200];   /* NUL-terminated, human-readable: what and where */
} pvs_error;

/* A short constant English description of a result code ("out of memory"). Never NULL. */
PVS_API const char *pvs_result_string(pvs_result result);

/* The library version at run time: PVS_VERSION of the implementation. */
PVS_API uint32_t pvs_version(void);

/* Allocation hooks. alloc returns memory aligned to `align` (a power of two <= 64) or NULL; free gets
   the size given to alloc. Zero-initialised (both NULL) means PVS_MALLOC/PVS_FREE. Objects created with
   an allocator keep a copy and free through it. Must be thread-safe when bake tasks run in parallel. */
typedef struct pvs_allocator {
    void *(*alloc)(size_t size, size_t align, void *user);
    void (*free)(void *ptr, size_t size, void *user);
    void *user;
} pvs_allocator;

/* An axis-aligned box. A box with min == max on some axis is flat, still valid. */
typedef struct pvs_box {
    float min[3];
    float max[3];
} pvs_box;

/* Bitsets: bit i of word i/64 stands for object id i. Size with PVS_BITSET_WORDS(object_count). */
typedef uint64_t pvs_word;
#define PVS_BITSET_WORDS(bits) (((size_t)(bits) + 63u) / 64u)
/* 1 if bit i is set. No bounds check: i < the bitset's bit count. */
PVS_API int pvs_bitset_test(const pvs_word *bits, uint32_t i);
/* Set / clear bit i. */
PVS_API void pvs_bitset_set(pvs_word *bits, uint32_t i);
PVS_API void pvs_bitset_clear(pvs_word *bits, uint32_t i);
/* Number of set bits among the first `bit_count` bits. */
PVS_API uint32_t pvs_bitset_count(const pvs_word *bits, uint32_t bit_count);
/* The first set bit >= `from`, or `bit_count` when none: for (i = next(b,n,0); i < n; i = next(b,n,i+1)). */
PVS_API uint32_t pvs_bitset_next(const pvs_word *bits, uint32_t bit_count, uint32_t from);

/* ---- scene ----------------------------------------------------------------------------------- */

/* Object flags. */
#define PVS_OBJECT_OCCLUDER_ONLY 1u /* blocks sight but is never drawn: never appears in a PVS */

/* One object (a unit of visibility): a range of triangles. Ranges of distinct objects must not overlap;
   triangles in no range block sight but belong to no object. */
typedef struct pvs_object_desc {
    uint32_t first_triangle;
    uint32_t triangle_count;
    uint32_t flags;          /* PVS_OBJECT_* */
} pvs_object_desc;

/* Kinds of explicit occluder volume (geometry known to be solid). */
typedef enum pvs_occluder_kind {
    PVS_OCCLUDER_INVALID = 0,
    PVS_OCCLUDER_BOX,        /* `box` */
    PVS_OCCLUDER_CONVEX,     /* intersection of half-spaces: `planes` */
    PVS_OCCLUDER_EXTRUSION,  /* a simple polygon in the ground plane extruded along the up axis */
    PVS_OCCLUDER_KIND_COUNT
} pvs_occluder_kind;

/* An explicit occluder volume. The arrays are copied by pvs_scene_create. */
typedef struct pvs_occluder_desc {
    pvs_occluder_kind kind;
    pvs_box box;                /* BOX: the volume */
    const float *planes;        /* CONVEX: plane_count x (nx, ny, nz, d); inside is n.p + d <= 0 */
    uint32_t plane_count;       /* CONVEX: 4..PVS_MAX_OCCLUDER_PLANES, bounded, non-empty */
    const float *footprint;     /* EXTRUSION: footprint_count 2D points (u, v) in the ground plane, */
    uint32_t footprint_count;   /*   either winding, simple (may be concave), 3..PVS_MAX_FOOTPRINT_POINTS */
    float base, top;            /* EXTRUSION: heights along the up axis, base < top */
} pvs_occluder_desc;
#define PVS_MAX_OCCLUDER_PLANES 64
#define PVS_MAX_FOOTPRINT_POINTS 4096

/* Scene flags. */
#define PVS_SCENE_ALLOW_EMPTY_OBJECTS 1u /* keep objects with no (or only zero-area) triangles: never visible */

/* Everything pvs_scene_create needs. Left at zero, optional fields get defaults. The ground-plane
   coordinates (u, v) of an extrusion are (x, z) for up_axis 1 and (x, y) for up_axis 2. */
typedef struct pvs_scene_desc {
    const float *positions;      /* vertex_count x (x, y, z) */
    uint32_t vertex_count;
    const uint32_t *indices;     /* triangle_count x 3 vertex indices */
    uint32_t triangle_count;
    const pvs_object_desc *objects;
    uint32_t object_count;       /* >= 1 */
    const pvs_occluder_desc *occluders; /* may be NULL when occluder_count is 0 */
    uint32_t occluder_count;
    uint32_t up_axis;            /* 0 or 1: Y up (default); 2: Z up */
    uint32_t flags;              /* PVS_SCENE_* */
    uint32_t leaf_size;          /* kD-tree leaf size for triangles, 0 = default (4) */
    pvs_allocator allocator;
} pvs_scene_desc;

/* A validated, immutable scene with its kD-trees. Read-only after creation: thread-safe. */
typedef struct pvs_scene pvs_scene;

/* Copies and validates the arrays, computes object bounds, builds the triangle and object kD-trees.
   Errors: INVALID_ARGUMENT, INDEX_OUT_OF_RANGE, NOT_FINITE, EMPTY_OBJECT, DEGENERATE_OBJECT,
   OVERLAPPING_OBJECTS, BAD_OCCLUDER, COUNT_OVERFLOW, OUT_OF_MEMORY; err->index names the element. */
PVS_API pvs_result pvs_scene_create(const pvs_scene_desc *desc, pvs_scene **out_scene, pvs_error *err);
/* Frees the scene through its allocator. NULL is allowed. */
PVS_API void pvs_scene_destroy(pvs_scene *scene);

/* Counts and bounds. */
PVS_API uint32_t pvs_scene_object_count(const pvs_scene *scene);
PVS_API uint32_t pvs_scene_triangle_count(const pvs_scene *scene);
PVS_API uint32_t pvs_scene_occluder_count(const pvs_scene *scene);
PVS_API uint32_t pvs_scene_up_axis(const pvs_scene *scene);         /* 1 or 2 */
PVS_API pvs_box pvs_scene_bounds(const pvs_scene *scene);           /* of all triangles and occluders */
PVS_API pvs_box pvs_scene_object_box(const pvs_scene *scene, uint32_t object); /* object < count */
PVS_API uint32_t pvs_scene_object_flags(const pvs_scene *scene, uint32_t object);
/* The object a triangle belongs to, or PVS_NO_OBJECT. */
PVS_API uint32_t pvs_scene_triangle_object(const pvs_scene *scene, uint32_t triangle);
#define PVS_NO_OBJECT 0xffffffffu
/* The stored copy of explicit occluder i (its arrays point into the scene). */
PVS_API const pvs_occluder_desc *pvs_scene_occluder(const pvs_scene *scene, uint32_t i);

/* A ray hit. */
typedef struct pvs_hit {
    float t;             /* distance along dir (in units of |dir|) */
    uint32_t triangle;
    uint32_t object;     /* PVS_NO_OBJECT for triangles in no object */
} pvs_hit;

/* Closest hit of the ray origin + t dir, 0 <= t <= tmax, with the scene's triangles (two-sided).
   Returns 1 and fills *hit (NULL allowed), or 0. dir need not be normalised but must be non-zero.
   Watertight (Woop, Benthin, Wald 2013, in double): a ray cannot pass between triangles sharing an
   edge or a corner. Zero-area triangles are never hit. Ties in t go to the lowest triangle index.
   Thread-safe, allocates nothing. */
PVS_API int pvs_scene_raycast(const pvs_scene *scene, const float origin[3], const float dir[3], float tmax, pvs_hit *hit);
/* 1 if any triangle crosses the segment a-b (endpoints included), else 0; 0 when a == b. The test is
   watertight like pvs_scene_raycast. Thread-safe, no allocation. */
PVS_API int pvs_scene_segment_blocked(const pvs_scene *scene, const float a[3], const float b[3]);

/* ---- kdtree ---------------------------------------------------------------------------------- */

/* A kD-tree over a set of boxes (objects, triangles or cells): binned SAH build, items referenced
   from every leaf they overlap. Immutable after creation: thread-safe. */
typedef struct pvs_kdtree pvs_kdtree;

typedef struct pvs_kdtree_desc {
    const pvs_box *boxes;    /* count item boxes; item i is box i */
    uint32_t count;
    uint32_t leaf_size;      /* stop splitting at this many items, 0 = default (4) */
    uint32_t max_depth;      /* 0 = automatic (about 1.3 log2 count + 8), capped at PVS_KDTREE_MAX_DEPTH */
    pvs_allocator allocator;
} pvs_kdtree_desc;
#define PVS_KDTREE_MAX_DEPTH 48

/* Builds the tree; deterministic (the same boxes give the same tree). Boxes with min > max on some
   axis are left out; flat boxes (min == max) are fine; count 0 gives an empty tree. Errors:
   INVALID_ARGUMENT, NOT_FINITE (err->index = the box), COUNT_OVERFLOW, OUT_OF_MEMORY. */
PVS_API pvs_result pvs_kdtree_create(const pvs_kdtree_desc *desc, pvs_kdtree **out_tree, pvs_error *err);
/* Frees the tree through its allocator. NULL is allowed. */
PVS_API void pvs_kdtree_destroy(pvs_kdtree *tree);
/* The union of the non-empty item boxes; an empty box (min > max) when there are none. */
PVS_API pvs_box pvs_kdtree_bounds(const pvs_kdtree *tree);
/* Nodes, inner and leaves (every inner node has two children); at least 1. */
PVS_API uint32_t pvs_kdtree_node_count(const pvs_kdtree *tree);

/* What a sweep visitor tells the traversal. */
typedef enum pvs_visit {
    PVS_VISIT_DESCEND = 0,   /* go on into this node's children */
    PVS_VISIT_SKIP,          /* cull this node's subtree */
    PVS_VISIT_STOP           /* end the sweep */
} pvs_visit;

/* Called once per node reached, in order of increasing `distance` (minimum distance from the
   sweep's source box to the node box; 0 where they meet). `node_box` is the node's cell: the
   tree's bounds cut by the split planes above it. Leaves pass their items, inner nodes (and empty
   leaves) items == NULL and item_count == 0. An item overlapping several leaves is passed once per
   leaf. */
typedef pvs_visit (*pvs_kdtree_visit_fn)(void *user, const pvs_box *node_box, float distance,
                                         const uint32_t *items, uint32_t item_count);

/* Bytes of scratch pvs_kdtree_sweep needs for this tree: 32 bytes per leaf ((node_count + 1) / 2). */
PVS_API size_t pvs_kdtree_sweep_scratch_size(const pvs_kdtree *tree);
/* The approximate occlusion sweep (Bittner 2002, §3.2): nodes front to back from `source` (a box; a
   point is a box with min == max) by a priority queue on minimum distance. `scratch` is caller memory
   of at least pvs_kdtree_sweep_scratch_size bytes, aligned to 8. Ties are broken by node index, so
   the order is deterministic. An empty tree visits nothing. Returns PVS_OK, BUFFER_TOO_SMALL,
   INVALID_ARGUMENT (NULL tree, source or visit) or NOT_FINITE (source). Allocates nothing. */
PVS_API pvs_result pvs_kdtree_sweep(const pvs_kdtree *tree, const pvs_box *source, void *scratch, size_t scratch_size,
                                    pvs_kdtree_visit_fn visit, void *user);

/* Called for the non-empty leaves a ray passes, nearest first; [t_enter, t_exit] is the ray's interval
   in the leaf, widened by a relative 1e-7 so that no leaf the ray touches is skipped. Return a new
   tmax (larger values are ignored) to shorten the ray, or a negative value to stop. */
typedef float (*pvs_kdtree_ray_fn)(void *user, const uint32_t *items, uint32_t item_count, float t_enter, float t_exit);
/* Walks the leaves the ray origin + t dir, 0 <= t <= tmax, passes, front to back. Any dir component
   may be 0 or -0 (not all three); the origin may lie inside or outside the bounds. Non-finite input
   walks nothing. Allocates nothing; thread-safe. */
PVS_API void pvs_kdtree_ray(const pvs_kdtree *tree, const float origin[3], const float dir[3], float tmax,
                            pvs_kdtree_ray_fn fn, void *user);

/* The items of the leaf containing point p (their boxes may or may not contain p: test them), or
   NULL with *count = 0 outside the tree's bounds or in an empty leaf. Every item whose box contains p
   is listed, also for p on a split plane. Allocates nothing. */
PVS_API const uint32_t *pvs_kdtree_leaf_items(const pvs_kdtree *tree, const float p[3], uint32_t *count);

/* ---- raster ---------------------------------------------------------------------------------- */

/* Depth convention (reversed Z). A depth value is z_clip / w_clip of a 4x4 projection and LARGER IS
   NEARER: pvs_camera_matrix maps the near plane to 1 and infinity to 0 (orthographic: 1 at the near
   plane, decreasing linearly with distance, negative past `far`). A point is in front of the near
   plane when z_clip <= w_clip and w_clip > 0; the rest of a triangle is clipped away. There is no far
   clipping. Pixel (i, j) covers the screen square [i, i+1] x [j, j+1]; x = (x_ndc + 1) / 2 * width,
   y = (y_ndc + 1) / 2 * height (row 0 at y_ndc = -1). A depth map pixel holds the nearest of what was
   drawn into it, PVS_DEPTH_EMPTY when nothing was. */
#define PVS_DEPTH_EMPTY (-3.402823466e+38f)

/* How a triangle is rasterized (Durand 2000 §2.2, §3.1-3.2: occluders by intersection, occludees by union). */
typedef enum pvs_raster_mode {
    PVS_RASTER_OCCLUDER = 0,  /* inner coverage: only pixels the triangle covers entirely; each gets a
                                 depth no nearer than the triangle's farthest point over the pixel */
    PVS_RASTER_OCCLUDEE,      /* outer coverage: every pixel the triangle touches; each gets a depth no
                                 farther than the triangle's nearest point over the pixel */
    PVS_RASTER_MODE_COUNT
} pvs_raster_mode;

/* A camera for the culling calls. `forward` and `up` need not be unit length nor orthogonal (up is
   made orthogonal to forward); the image x axis is forward x up (right-handed: to the right). */
typedef struct pvs_camera {
    float eye[3];
    float forward[3];
    float up[3];
    float fov_y;         /* vertical field of view in radians, in (0, pi); 0 = orthographic */
    float near_plane;    /* distance of the near plane, > 0 */
    float ortho_height;  /* orthographic: height of the view volume, > 0 */
    float far_plane;     /* orthographic: where depth reaches 0 (not a clip plane); 0 = near + 1e4 */
} pvs_camera;

/* The row-major 4x4 clip matrix of a camera for an image of aspect width / height (clip = m * (x, y,
   z, 1), m[4 * row + col]). Perspective: z_clip = near, w_clip = distance along forward, so depth =
   near / distance. Returns INVALID_ARGUMENT or NOT_FINITE for an unusable camera, else PVS_OK. */
PVS_API pvs_result pvs_camera_matrix(const pvs_camera *camera, float aspect, float m[16]);

/* Raster flags. Occluder-mode depth is kept one of two ways: per pixel (exact per pixel; the default
   for maps of at most 65,536 pixels) or per tile of 32 x 4 pixels as a coverage mask and two depths
   (Masked Occlusion Culling: several times faster, each tile's depth the farthest of what covers it;
   the default for larger maps). Both are conservative. */
#define PVS_RASTER_SCALAR 1u     /* use the scalar code even where SIMD is compiled in (identical results) */
#define PVS_RASTER_PER_PIXEL 2u  /* occluders keep a depth per pixel */
#define PVS_RASTER_TILED 4u      /* occluders go to tiles (wins over PVS_RASTER_PER_PIXEL) */

/* What pvs_raster_create needs. Left at zero, optional fields get defaults. */
typedef struct pvs_raster_desc {
    uint32_t width, height;       /* depth map size in pixels, 1..16384 each */
    const pvs_scene *scene;       /* optional: sizes the culling buffers for this scene and builds the
                                     cull map's object grid over it; pvs_raster_cull* then accept this
                                     scene (or one with no more objects, triangles and kD-tree nodes) */
    uint32_t max_occluders;       /* scene triangles pvs_raster_cull may select per frame, 0 = 1024 */
    uint32_t cull_map_width;      /* cull map cells over the scene's ground rectangle, 0 = no cull map */
    uint32_t cull_map_height;     /*   (both or neither; 1..4096; needs `scene`) */
    uint32_t flags;               /* PVS_RASTER_* */
    uint32_t max_mesh_triangles;  /* triangles pvs_raster_mesh connects in one piece, 0 = 4096 (scratch:
                                     about 400 bytes each) */
    pvs_allocator allocator;
} pvs_raster_desc;

/* A rasterizer context: depth map, depth pyramid, cull map and every per-frame buffer, allocated once.
   Nothing after pvs_raster_create allocates. One context per thread (calls on one context are not
   thread-safe; distinct contexts are independent). */
typedef struct pvs_raster pvs_raster;

/* Allocates the context. Errors: INVALID_ARGUMENT (sizes), COUNT_OVERFLOW, OUT_OF_MEMORY. */
PVS_API pvs_result pvs_raster_create(const pvs_raster_desc *desc, pvs_raster **out_raster, pvs_error *err);
/* Frees the context through its allocator. NULL is allowed. */
PVS_API void pvs_raster_destroy(pvs_raster *raster);

/* Sets every depth map pixel to PVS_DEPTH_EMPTY. */
PVS_API void pvs_raster_clear(pvs_raster *raster);
/* Sets the projection used by the next pvs_raster_triangles and box tests (row-major, see
   pvs_camera_matrix). Any 4x4 works: perspective, orthographic, off-axis (Durand 2000's projection
   planes shared by every point of a cell). Returns NOT_FINITE for a non-finite entry. */
PVS_API pvs_result pvs_raster_set_matrix(pvs_raster *raster, const float m[16]);
/* Rasterizes `count` triangles (vertices: 3 floats each in `positions`; `indices` 3 per triangle, or
   NULL for consecutive vertices) into the depth map, keeping per pixel the nearer of the stored and
   the new depth (tiled occluders merge per tile: a pixel may keep a farther depth, never one nearer
   than its nearest occluder). Conservative under floating-point rounding (see >>raster). Triangles
   are two-sided;
   ones with a non-finite coordinate are skipped. Returns INVALID_ARGUMENT for NULL positions or a bad
   mode, else PVS_OK. `vertex_count` bounds the indices (an index >= it skips the triangle). */
PVS_API pvs_result pvs_raster_triangles(pvs_raster *raster, const float *positions, uint32_t vertex_count,
                                        const uint32_t *indices, uint32_t count, pvs_raster_mode mode);
/* Rasterizes `count` triangles as one connected occluder mesh (Durand 2000 §3.3: per-triangle inner
   coverage loses the connectivity of occluders, leaving a crack of unclaimed pixels along every edge
   two triangles share). The triangles are drawn as by pvs_raster_triangles (occluder mode), then
   every pixel along their edges that the union of the mesh's triangles covers whole: a pixel that
   no boundary edge of the union touches and that some triangle touches. Boundary edges are the edges
   not shared by exactly two triangles, the silhouettes between a front- and a back-facing triangle,
   the edges of triangles wound against their neighbour, the edges cut by the near plane and the cuts
   themselves; a crack remains only along them. Such a pixel stores the farthest depth over the pixel
   of every triangle of its facing that touches it, so never a depth nearer than the mesh's farthest
   over it. Vertices are shared by index and by equal position (a triangle soup is welded). Meshes of
   more than the context's max_mesh_triangles are drawn in consecutive pieces of that many triangles
   (edges between pieces stay boundary edges). Skips triangles with an index >= vertex_count or a
   non-finite coordinate. Returns INVALID_ARGUMENT for a NULL raster or NULL positions with count > 0,
   else PVS_OK. Conservative under rounding like pvs_raster_triangles (>>raster explains the
   argument). Allocates nothing; the same result with and without SIMD. */
PVS_API pvs_result pvs_raster_mesh(pvs_raster *raster, const float *positions, uint32_t vertex_count, const uint32_t *indices,
                                   uint32_t count);
/* The depth map: width * height floats, row-major, row 0 first. Valid until the next raster call.
   A tiled context writes it from the tiles on this call (a pass over the map). */
PVS_API const float *pvs_raster_depth(const pvs_raster *raster, uint32_t *width, uint32_t *height);

/* Builds the hierarchical depth map (Durand 2000 §2.4, after Greene, Kass and Miller 1993): per
   level each texel holds the farthest (smallest) and nearest (largest) depth of its 2 x 2 children
   (tiled: above the tiles, whose two depths and mask decide per pixel). The tests below build it
   when the depth map changed since the last build. */
PVS_API void pvs_raster_build_pyramid(pvs_raster *raster);
/* 1 if an occludee whose nearest depth is `depth` may be visible somewhere in the pixel rectangle
   [x0, x1] x [y0, y1] (inclusive, clamped to the map): some pixel stores a depth <= `depth`. 0 when
   every pixel holds something strictly nearer, or the rectangle misses the map. Descends the pyramid
   from the coarsest level and stops where a level decides. */
PVS_API int pvs_raster_test_rect(pvs_raster *raster, int32_t x0, int32_t y0, int32_t x1, int32_t y1, float depth);
/* 1 if the box may be visible under the current matrix: it reaches in front of the near plane, it
   touches the screen and the depth pyramid does not hide its projection. Conservative. */
PVS_API int pvs_raster_test_box(pvs_raster *raster, const pvs_box *box);

/* A chain of connected facades for the cull map (Wonka 1999 §3.1, §4.1): vertical quads standing on
   consecutive ground-plane segments, from `base` to `top` along the up axis. Ground-plane coordinates
   (u, v) are (x, z) for up axis 1 (Y) and (x, y) for up axis 2 (Z). */
typedef struct pvs_facade_chain {
    const float *points;   /* point_count points (u, v) */
    uint32_t point_count;  /* >= 2 */
    uint32_t closed;       /* 1: the last point joins the first and the facades are back-face culled
                              (a closed footprint, either winding); 0: open and two-sided */
    float base, top;       /* heights, base < top; chains with base above the ground are ignored */
} pvs_facade_chain;

/* Cull map flags. */
#define PVS_CULL_MAP_SCENE_OCCLUDERS 1u /* also the scene's EXTRUSION and BOX occluders as closed chains */

/* Builds the cull map from the eye (Wonka & Schmalstieg 1999 §3-4): every front-facing facade casts
   its occluder shadow, rasterized top-down into a height buffer over the scene's ground rectangle,
   fused by keeping the highest shadow per cell. A cell holds a height below which everything in its
   column is hidden from the eye (PVS_DEPTH_EMPTY when no shadow covers the whole cell). Facades count
   only when base <= min(eye height, the scene's lowest point), so the sight line to any hidden point
   crosses the facade. Needs a context created with a scene and a cull map size; INVALID_ARGUMENT
   otherwise, NOT_FINITE for a non-finite eye. Skips malformed chains. No allocation. */
PVS_API pvs_result pvs_cull_map_build(pvs_raster *raster, const float eye[3], const pvs_facade_chain *chains,
                                      uint32_t chain_count, uint32_t flags);
/* The cull map: width * height heights, row-major; cell (i, j) covers u in region[0] + [i, i+1] * (region[2]
   - region[0]) / width, v likewise from region[1] to region[3]. NULL without a cull map. */
PVS_API const float *pvs_cull_map(const pvs_raster *raster, uint32_t *width, uint32_t *height, float region[4]);
/* 1 if a box may be visible in the cull map: some cell it overlaps holds a height <= the box top
   (Wonka 1999 §4.3). Boxes outside the region count as visible. */
PVS_API int pvs_cull_map_test_box(const pvs_raster *raster, const pvs_box *box);

/* Per-frame culling inputs. Left at zero: no occluders (a frustum cull). */
typedef struct pvs_cull_params {
    const float *occluder_positions;  /* caller occluder triangles (dynamic occluders): 3 floats per */
    uint32_t occluder_vertex_count;   /*   vertex; indices 3 per triangle, or NULL for consecutive */
    const uint32_t *occluder_indices; /*   vertices */
    uint32_t occluder_triangle_count;
    uint32_t scene_occluders;         /* also rasterize the best this many scene triangles (capped at the
                                         context's max_occluders) ... */
    float occluder_distance;          /*   ... within this distance of the eye (0 = 100 units), ranked
                                         by Bittner's area-angle measure (2002 §4.5) */
    uint32_t scene_volumes;           /* pvs_raster_cull: 1 = also the scene's explicit BOX occluders and
                                         EXTRUSION occluders' walls within occluder_distance (CONVEX
                                         occluders are not used) */
    const pvs_facade_chain *facades;  /* pvs_raster_cull_map only: facade chains ... */
    uint32_t facade_count;
    uint32_t cull_map_flags;          /*   ... and PVS_CULL_MAP_* flags for pvs_cull_map_build */
    const pvs_word *candidates;       /* optional: only objects set here are tested and reported (inside
                                         a cell's PVS); PVS_BITSET_WORDS(object_count) words */
    uint32_t occluder_flags;          /* PVS_CULL_* below */
} pvs_cull_params;

/* Occluder flags of pvs_raster_cull. */
#define PVS_CULL_OCCLUDER_MESH 1u      /* the caller's occluder triangles are connected meshes: drawn with
                                          pvs_raster_mesh (no cracks along shared edges) */
#define PVS_CULL_SEPARATE_TRIANGLES 2u /* the scene's selected triangles and occluder volumes one triangle
                                          at a time, as before 0.4 (by default they are drawn as meshes) */

/* What a culling call did (for statistics and tests). */
typedef struct pvs_cull_stats {
    uint32_t occluder_triangles;  /* triangles rasterized (caller + selected scene triangles) */
    uint32_t nodes_visited;       /* kD-tree nodes reached by the sweep */
    uint32_t boxes_tested;        /* node and object boxes tested */
    uint32_t visible;             /* objects reported */
} pvs_cull_stats;

/* From-point occlusion culling with the depth pyramid: clears the depth map, sets the camera's matrix
   (aspect width / height), rasterizes the caller's and the selected scene occluders (occluder mode;
   the selected scene triangles as one mesh, each box or extrusion volume as a mesh, the caller's
   triangles as meshes with PVS_CULL_OCCLUDER_MESH: see pvs_raster_mesh), builds the pyramid, then sweeps the scene's object kD-tree front to back from the eye (Bittner 2002
   §3.2), skipping subtrees whose box is hidden, and sets in `visible` (PVS_BITSET_WORDS(object_count)
   words, cleared first) every object whose box may be visible. Occluder-only objects are never set.
   Conservative: every object seen through the screen from the eye is set. `stats` may be NULL.
   Errors: INVALID_ARGUMENT, NOT_FINITE (camera), BUFFER_TOO_SMALL (a scene larger than the context
   was created for). Allocates nothing. */
PVS_API pvs_result pvs_raster_cull(pvs_raster *raster, const pvs_scene *scene, const pvs_camera *camera,
                                   const pvs_cull_params *params, pvs_word *visible, pvs_cull_stats *stats,
                                   pvs_error *err);
/* The 2.5D entry point (Wonka 1999): builds the cull map from the camera's eye with params->facades
   (and the scene's occluders with PVS_CULL_MAP_SCENE_OCCLUDERS), then scans the object grid with the
   two-level bounding-height test of §4.3 and sets every object that is inside the camera's frustum
   and not under the shadows. Shadows are cast from a point: an orthographic camera gets the frustum
   test only. `scene` must be the context's scene. Same outputs and errors as
   pvs_raster_cull. Allocates nothing. */
PVS_API pvs_result pvs_raster_cull_map(pvs_raster *raster, const pvs_scene *scene, const pvs_camera *camera,
                                       const pvs_cull_params *params, pvs_word *visible, pvs_cull_stats *stats,
                                       pvs_error *err);
/* ---- otree ---------------------------------------------------------------------------------- */

/* Occlusion trees (Bittner 2002): a BSP over oriented 2D line space whose leaves are "out" (lines
   that reach nothing yet) or "in" (lines blocked by a stored occluder). Built front to back by an
   occlusion sweep; conservative everywhere floating point has to decide. */

/* What an occlusion-tree computation reports. */
typedef struct pvs_otree_stats {
    uint32_t nodes;              /* tree nodes at the end (the largest tree for several trees) */
    uint32_t occluders_inserted; /* occluders merged into the tree(s) */
    uint32_t visible_segments;   /* 2D: segments found visible */
    uint32_t budget_exceeded;    /* 1 when node_budget stopped insertion: the rest counted as not blocking (still conservative) */
} pvs_otree_stats;

/* Segment flags for pvs_visibility_2d. */
#define PVS_SEGMENT_NO_OCCLUSION 1u /* tested for visibility but never blocks sight */

/* Exact 2D from-region visibility (Bittner 2002, ch. 6). Left at zero, optional fields get defaults. */
typedef struct pvs_visibility_2d_desc {
    const float *cell;               /* cell_vertex_count x (x, y): a convex polygon, either winding */
    uint32_t cell_vertex_count;      /* >= 3 */
    const float *segments;           /* segment_count x (x0, y0, x1, y1): occluders, opaque from both sides */
    uint32_t segment_count;
    const uint8_t *segment_flags;    /* NULL or segment_count PVS_SEGMENT_* flags */
    const uint32_t *segment_objects; /* NULL (segment i is object i) or the object of each segment, or PVS_NO_OBJECT */
    uint32_t object_count;           /* bits in visible_objects */
    uint32_t node_budget;            /* stop inserting past this many tree nodes (0 = 2^20); see pvs_otree_stats */
    uint32_t flags;                  /* PVS_VISIBILITY_* */
    pvs_allocator allocator;
} pvs_visibility_2d_desc;
#define PVS_VISIBILITY_INPUT_ORDER 1u /* insert occluders in input order, not front to back (tests order independence) */

/* Which segments (and objects) are visible from some point of the cell: a segment is visible when a
   line segment from a cell point reaches it without crossing another segment (touching an end point
   does not block; segments crossing the cell are visible). Exact up to floating point, rounded
   toward visible. visible_segments (PVS_BITSET_WORDS(segment_count) words) and visible_objects
   (PVS_BITSET_WORDS(object_count) words) may each be NULL; both are cleared first. stats may be
   NULL. Errors: INVALID_ARGUMENT, NOT_FINITE, INDEX_OUT_OF_RANGE, BAD_CELL (no area, not convex),
   OUT_OF_MEMORY. Thread-safe; allocates through desc->allocator. */
PVS_API pvs_result pvs_visibility_2d(const pvs_visibility_2d_desc *desc, pvs_word *visible_segments, pvs_word *visible_objects,
                                     pvs_otree_stats *stats, pvs_error *err);

/* Conservative 2.5D from-region visibility, c-LSS (Bittner 2002, ch. 7). Coordinates (u, v) are the
   ground plane, h the height. Left at zero, optional fields get defaults. */
typedef struct pvs_visibility_25d_desc {
    float cell_min[2], cell_max[2]; /* the cell's ground rectangle */
    float cell_top;                 /* the highest eye height in the cell */
    const float *facades;           /* facade_count x (u0, v0, u1, v1, top): opaque vertical walls that */
    uint32_t facade_count;          /*   stand on the ground: they block every height below `top` */
    const float *objects;           /* object_count x (umin, vmin, umax, vmax, top): object bounds; umin > umax = empty */
    uint32_t object_count;
    uint32_t node_budget;           /* per tree (0 = 2^18); see pvs_otree_stats */
    const pvs_kdtree *tree;         /* NULL, or a kD-tree over pvs_visibility_25d_boxes (reused across cells) */
    pvs_allocator allocator;
} pvs_visibility_25d_desc;

/* Fills boxes[facade_count + object_count] for the kD-tree of pvs_visibility_25d_desc.tree: facade i
   is item i, object j is item facade_count + j; axes (u, v, height), the height range ending at the
   top. Build it once with pvs_kdtree_create and share it between cells (read-only, thread-safe). */
PVS_API void pvs_visibility_25d_boxes(const float *facades, uint32_t facade_count, const float *objects, uint32_t object_count,
                                      pvs_box *boxes);

/* The objects that may be visible from the cell box (ground rectangle x heights up to cell_top), given
   that facades reach down below every cell and object. Conservative: never misses a visible object.
   Facades crossing the cell's rectangle are ignored. visible_objects: PVS_BITSET_WORDS(object_count)
   words, cleared first. stats may be NULL. Errors: INVALID_ARGUMENT, NOT_FINITE, OUT_OF_MEMORY.
   Thread-safe; allocates through desc->allocator. */
PVS_API pvs_result pvs_visibility_25d(const pvs_visibility_25d_desc *desc, pvs_word *visible_objects, pvs_otree_stats *stats,
                                      pvs_error *err);

/* From-point occlusion culling with a shadow-volume occlusion tree (Bittner 2002, ch. 4), the
   object-space twin of pvs_raster_cull: same camera, parameters, outputs and errors. Each frame the
   selected occluder polygons, in eye space, are merged front to back into a BSP tree whose planes
   pass through the eye and an occluder edge (in-leaves keep the occluder fragment); then the scene's
   object kD-tree is walked front to back with frustum culling and the conservative no-split box test
   of §4.10.2 refined by an exact box / fragment-pyramid test at the in-leaves ("FME", Table 4.1);
   temporal coherence by hierarchy updating with pull-up (§4.11.4) gives exactly the result of testing
   every node. Occluders (§4.5): the caller's triangles, then the best `scene_occluders` polygons by
   the area-angle measure among the triangles of the objects seen within `occluder_distance` in the
   previous frame (after pvs_otree_create or pvs_otree_reset: the scene's triangles within that
   distance), plus, with `scene_volumes`, the faces of BOX occluders and the walls of EXTRUSION
   occluders within that distance. */
typedef struct pvs_otree_desc {
    const pvs_scene *scene;       /* required: sizes the per-node state; pvs_otree_cull then accepts this
                                     scene (or one with no more objects, triangles and kD-tree nodes) */
    float aspect;                 /* image width / height for the frustum's side planes, 0 = 1 */
    uint32_t max_occluders;       /* scene polygons inserted per frame at most, 0 = 64; <= 65536 */
    uint32_t node_budget;         /* occlusion tree nodes per frame, 0 = 8192; 64..2^24 (see pvs_otree_frame) */
    uint32_t flags;               /* PVS_OTREE_* */
    pvs_allocator allocator;
} pvs_otree_desc;
#define PVS_OTREE_NO_COHERENCE 1u /* test every reached kD node every frame (the classical traversal, §4.11.2) */
#define PVS_OTREE_PLANE_ONLY 2u   /* in-leaves test the fragment's plane only ("FMC"), no box / fragment test */

/* A from-point culling context: the tree's node pool, the kD nodes' visibility states of the last
   frame, the occluder selection. Allocated once; pvs_otree_cull allocates nothing. One context per
   thread (calls on one context are not thread-safe; distinct contexts are independent). */
typedef struct pvs_otree pvs_otree;

/* What the last pvs_otree_cull did, beyond pvs_cull_stats. */
typedef struct pvs_otree_frame {
    uint32_t tree_nodes;          /* occlusion tree nodes (inner and leaves) */
    uint32_t fragments;           /* occluder fragments stored at in-leaves */
    uint32_t occluders;           /* polygons offered to the tree (caller triangles + scene polygons) */
    uint32_t node_tests;          /* kD nodes whose visibility was tested (frustum + tree) */
    uint32_t nodes_skipped;       /* opened kD nodes whose test hierarchy updating skipped */
    uint32_t object_tests;        /* object boxes tested in partly visible leaves */
    uint32_t budget_exceeded;     /* 1 when the node budget or the polygon size stopped an insertion: the
                                     rest counted as not blocking (still conservative) */
} pvs_otree_frame;

/* Allocates the context for desc->scene. Errors: INVALID_ARGUMENT, NOT_FINITE (aspect), COUNT_OVERFLOW,
   OUT_OF_MEMORY. */
PVS_API pvs_result pvs_otree_create(const pvs_otree_desc *desc, pvs_otree **out_otree, pvs_error *err);
/* Frees the context through its allocator. NULL is allowed. */
PVS_API void pvs_otree_destroy(pvs_otree *otree);
/* Forgets the previous frame (a camera cut): the next frame selects its occluders by distance and
   tests every node it reaches. */
PVS_API void pvs_otree_reset(pvs_otree *otree);
/* From-point occlusion culling (see pvs_otree_desc): sets in `visible` (PVS_BITSET_WORDS(object_count)
   words, cleared first) every object whose box may be seen from the eye through the screen from the
   near plane on; occluder-only objects are never set; params->candidates restricts the objects.
   Conservative whatever the rounding: every plane test leans toward "visible". `params` may be NULL
   (a frustum cull); params->facades are ignored. `stats` may be NULL. Errors: INVALID_ARGUMENT,
   NOT_FINITE (camera), UNSUPPORTED (an orthographic camera: shadow volumes need an eye point),
   BUFFER_TOO_SMALL (a scene larger than the context was created for). Allocates nothing. */
PVS_API pvs_result pvs_otree_cull(pvs_otree *otree, const pvs_scene *scene, const pvs_camera *camera,
                                  const pvs_cull_params *params, pvs_word *visible, pvs_cull_stats *stats, pvs_error *err);
/* Fills *frame with the figures of the last pvs_otree_cull. */
PVS_API void pvs_otree_get_frame(const pvs_otree *otree, pvs_otree_frame *frame);

/* ---- occluders ------------------------------------------------------------------------------- */

/* Occluder synthesis: volumes that are certainly solid, for the shrink method (Wonka 2000 §2: the
   theorem of its appendix needs volumetric occluders). The scene is voxelized; a voxel is solid only
   if no triangle touches it (a conservative triangle/box test rounding toward "touched") and it
   cannot be reached from any view cell through untouched voxels (a 26-connected flood fill from the
   cells; a scene open to the sky is flooded from outside its bounds through the cells that reach
   it), or if it lies inside an explicit occluder volume. Below the lowest point of the scene and of
   the cells lies the ground. The solid set is eroded by eps (rounding toward less solid), then merged
   into boxes (3D) and into per-column solid heights standing on the ground (2.5D), returned as
   rectangles. Limitation: free space is followed voxel to voxel, so an opening narrower than about
   two voxels may be taken as sealed; choose voxel_size well below the narrowest door or gap. */
typedef struct pvs_occluders_desc {
    const pvs_scene *scene;   /* required; must outlive the occluders */
    const pvs_box *cells;     /* cell_count view cells: the flood starts from them (required, >= 1) */
    uint32_t cell_count;
    float eps;                /* erosion distance, > 0 */
    float voxel_size;         /* 0 = derived: eps / 1.5, grown until the grid fits max_voxels */
    uint32_t max_voxels;      /* 0 = 1 << 24 */
    pvs_allocator allocator;
} pvs_occluders_desc;

/* The synthesized occluders: immutable after creation, thread-safe to read. */
typedef struct pvs_occluders pvs_occluders;

/* What the synthesis found. */
typedef struct pvs_occluders_info {
    uint32_t dims[3];         /* voxels per axis (one voxel of padding around the scene and cells) */
    float origin[3];          /* the grid's min corner */
    float voxel_size;
    float eps;
    uint64_t touched;         /* voxels a triangle touches */
    uint64_t solid;           /* solid voxels before erosion (explicit volumes included) */
    uint64_t eroded;          /* solid voxels after erosion */
    uint64_t column_voxels;   /* solid voxels in runs standing on the ground (the 2.5D part) */
    uint32_t box_count;       /* eroded 3D boxes */
    uint32_t rect_count;      /* eroded 2.5D column rectangles */
    int is_2d5;               /* 1 when the column runs hold the solid voxels (>= 90%): use the 2.5D path */
    uint32_t leak_cell;       /* the first cell whose flood reaches the outside, PVS_NO_CELL if sealed */
    float leak_point[3];      /* a voxel centre on its way out (valid when leak_cell != PVS_NO_CELL) */
    uint32_t thin_objects;    /* drawable objects with no solid voxel in their box: thin walls with open
                                 space on both sides and small props give no volume */
} pvs_occluders_info;

/* Voxel classes pvs_occluders_voxel returns. */
#define PVS_VOXEL_EMPTY 0u    /* untouched and reached from a cell */
#define PVS_VOXEL_TOUCHED 1u  /* a triangle touches it */
#define PVS_VOXEL_SOLID 2u    /* solid (before erosion) */
#define PVS_VOXEL_GROUND 3u   /* the padding layer below the ground */

/* Runs the synthesis. Errors: INVALID_ARGUMENT (NULL, no cells, eps <= 0 or not finite), BAD_CELL,
   COUNT_OVERFLOW, OUT_OF_MEMORY. Deterministic; not thread-safe on one desc only in the sense that it
   allocates: concurrent calls on distinct outputs are fine. */
PVS_API pvs_result pvs_occluders_create(const pvs_occluders_desc *desc, pvs_occluders **out_occluders, pvs_error *err);
/* Frees through the allocator. NULL is allowed. */
PVS_API void pvs_occluders_destroy(pvs_occluders *occluders);
/* Fills *info. */
PVS_API void pvs_occluders_get_info(const pvs_occluders *occluders, pvs_occluders_info *info);
/* The class of voxel (i, j, k) (i along x, j along y, k along z; each < dims), PVS_VOXEL_*. */
PVS_API uint32_t pvs_occluders_voxel(const pvs_occluders *occluders, uint32_t i, uint32_t j, uint32_t k);
/* 1 if voxel (i, j, k) survived the erosion. */
PVS_API int pvs_occluders_eroded_voxel(const pvs_occluders *occluders, uint32_t i, uint32_t j, uint32_t k);
/* The eroded 3D boxes (*count of them); every point within eps of a box is solid. Owned by occluders. */
PVS_API const pvs_box *pvs_occluders_boxes(const pvs_occluders *occluders, uint32_t *count);
/* The eroded 2.5D occluders as closed facade chains (4 points each, base = the ground, top already
   lowered by eps): every point within eps of such a prism is solid or below the ground. Owned by
   occluders. */
PVS_API const pvs_facade_chain *pvs_occluders_columns(const pvs_occluders *occluders, uint32_t *count);

/* ---- vocc ------------------------------------------------------------------------------------ */

/* Virtual occluders (Koltun, Chrysanthou, Cohen-Or 2000): per cell a few large vertical rectangles,
   each hidden from every point of the cell (it lies in the umbra of the real occluders), that
   together represent the cell's aggregate occlusion. They are stored in five bytes each (the VOCC
   section of a .pvs file) and the cell's PVS is rebuilt from them on cell entry (pvs_vocc_cull). */
struct pvs_file; /* >>format */

/* pvs_file.vocc_flags */
#define PVS_VOCC_STORED 1u /* the file has a VOCC section (virtual occluders per cell) */
#define PVS_VOCC_ONLY 2u   /* ... and its PVS records are placeholders (every drawable object): rebuild
                              each cell's PVS with pvs_vocc_cull (pvsbake --vocc-only) */

/* A virtual occluder: the vertical rectangle over the ground segment p0-p1, from `base` to `top`
   along the up axis. Ground coordinates (u, v) are (x, z) for up axis 1 (Y) and (x, y) for 2 (Z). */
typedef struct pvs_virtual_occluder {
    float p0[2], p1[2];
    float base, top;
} pvs_virtual_occluder;

/* What a virtual-occluder construction did (sums over cells and slices where several ran). */
typedef struct pvs_vocc_stats {
    uint32_t slices;        /* height slices (§3.1) */
    uint32_t seeds;         /* seed objects grown (§3) */
    uint32_t umbra;         /* objects that augmented an aggregate umbra (cases 1 and 3 of §3) */
    uint32_t separating;    /* objects that only bent a separating line (case 2) */
    uint32_t dense;         /* certified virtual occluders put into the dense set */
    uint32_t dropped;       /* candidates that failed the final check (e.g. after quantization) */
    uint32_t selected;      /* kept by the greedy selection (Fig. 6) */
} pvs_vocc_stats;

/* The 2D construction of §3 on its own. Left at zero, optional fields get defaults. */
typedef struct pvs_vocc_2d_desc {
    float cell_min[2], cell_max[2]; /* the view cell: an axis-aligned rectangle with area */
    const float *segments;          /* segment_count x (x0, y0, x1, y1): opaque occluders. Segments whose end
                                       points coincide exactly and close a ring (every point of it on two
                                       segments) form a wall loop: a closed curve of walls */
    uint32_t segment_count;
    uint32_t max_seeds;             /* seed objects grown, 0 = 16 */
    float range;                    /* analysis radius from the cell centre, 0 = reach every segment */
    pvs_allocator allocator;
} pvs_vocc_2d_desc;

/* Builds the dense set of 2D virtual occluders of the cell (§3): seeds by the angle they subtend
   from the cell's centre; from each, an aggregate umbra grown along active supporting and separating
   lines on both sides; virtual occluders placed behind it and dumped as it grows. Every segment
   written is hidden from every point of the cell by the input segments: each is checked exactly
   (up to a relative 1e-9 of rounding, toward "not hidden") before it is kept. Writes up to
   `capacity` segments (x0, y0, x1, y1) to `occluders` (NULL to count), *count the number found.
   Segments meeting the cell are ignored. stats may be NULL. Errors: INVALID_ARGUMENT, NOT_FINITE,
   BAD_CELL, OUT_OF_MEMORY. Thread-safe; allocates through desc->allocator. */
PVS_API pvs_result pvs_vocc_2d(const pvs_vocc_2d_desc *desc, float *occluders, uint32_t capacity, uint32_t *count,
                               pvs_vocc_stats *stats, pvs_error *err);

/* 1 if the box is hidden from every point of the cell by the single virtual occluder `o` (the test of
   the runtime rebuild): every sight line from the cell box to the box crosses the rectangle. The 2D
   part needs every segment between the cell's and the box's ground rectangles to cross p0-p1; the
   heights use the crossing fraction t of those segments (perspective: a sight line crosses the
   occluder's plane at height (1 - t) eye + t target). Conservative under rounding; 0 for empty boxes
   or a degenerate occluder. */
PVS_API int pvs_vocc_box_hidden(const pvs_box *cell, uint32_t up_axis, const pvs_virtual_occluder *o, const pvs_box *box);

/* Bytes of scratch pvs_vocc_cull and pvs_vocc_cull_occluders need for up to max_occluders occluders
   (a file stores at most 255 per cell) and the object tree (may be NULL). */
PVS_API size_t pvs_vocc_cull_scratch_size(const pvs_kdtree *tree, uint32_t max_occluders);

/* Rebuilds a PVS from virtual occluders (Koltun 2000 §2, §4): sets in `visible`
   (PVS_BITSET_WORDS(object_count) words, cleared first) every object whose box is not hidden by a
   single occluder (pvs_vocc_box_hidden; the occluders are tried in order, so put the most effective
   first). With a `tree` over the same object boxes (pvs_kdtree_create, item i = object i; leaves of
   16 or more items keep the walk short) the scene is traversed top-down and hidden subtrees are
   skipped: a subtree is hidden when one occluder hides its whole node box, so an object whose parts
   lie behind different occluders may be left out too (the walk's PVS is a subset of the flat one,
   still conservative); with tree NULL every box is tested. Objects with an empty box (min > max)
   are never set. scratch: pvs_vocc_cull_scratch_size bytes, any alignment. About 0.1 ms for 3,575
   objects and 10 occluders. Errors: INVALID_ARGUMENT, BUFFER_TOO_SMALL. Allocates nothing;
   thread-safe. */
PVS_API pvs_result pvs_vocc_cull_occluders(const pvs_box *cell, uint32_t up_axis, const pvs_virtual_occluder *occluders, uint32_t count,
                                           const pvs_box *object_boxes, uint32_t object_count, const pvs_kdtree *tree,
                                           void *scratch, size_t scratch_size, pvs_word *visible, pvs_error *err);

/* The virtual occluders a file stores for a cell (< cell_count), decoded, most effective first:
   returns their number (0 without a VOCC section) and writes up to `capacity` of them. The float
   end points are the stored ones rounded to float; pvs_vocc_cull uses the exact stored values. */
PVS_API uint32_t pvs_file_virtual_occluders(const struct pvs_file *file, uint32_t cell, pvs_virtual_occluder *out, uint32_t capacity);

struct pvs_bake; /* >>bake */
/* A VOCC bake's statistics: sums over the cells baked so far (zeros for other methods). */
PVS_API void pvs_bake_vocc_stats(const struct pvs_bake *bake, pvs_vocc_stats *out);

/* A cell's stored record: returns its occluder count (0 without a VOCC section), *bytes their five
   bytes each (in the file), *scale_code the cell's coordinate scale (manual: "VOCC"). Either output
   may be NULL. For tools that copy occluders between files (pvsbake merge). */
PVS_API uint32_t pvs_file_vocc_record(const struct pvs_file *file, uint32_t cell, uint32_t *scale_code, const uint8_t **bytes);

/* Rebuilds cell `cell`'s PVS on the fly from the file's virtual occluders (the first max_occluders of
   them; 0 = all), as pvs_vocc_cull_occluders does: object_boxes/tree are the engine's (the same scene
   the file was baked for). A file without a VOCC section gives INVALID_ARGUMENT. Allocates nothing;
   thread-safe. Errors: INVALID_ARGUMENT, BUFFER_TOO_SMALL. */
PVS_API pvs_result pvs_vocc_cull(const struct pvs_file *file, uint32_t cell, uint32_t max_occluders, const pvs_box *object_boxes,
                                 uint32_t object_count, const pvs_kdtree *tree, void *scratch, size_t scratch_size,
                                 pvs_word *visible, pvs_error *err);

/* ---- methods --------------------------------------------------------------------------------- */

/* Region methods. 0 is the default: AUTO. */
typedef enum pvs_method {
    PVS_METHOD_DEFAULT = 0,
    PVS_METHOD_SAMPLE,       /* ray sampling: an estimate from below, NOT conservative */
    PVS_METHOD_OTREE,        /* 2.5D occlusion trees, c-LSS (Bittner 2002, ch. 7): conservative; occluders are the
                                scene's vertical rectangles standing on the ground (see pvs_visibility_25d) */
    PVS_METHOD_EXTPROJ,      /* extended projections (Durand et al. 2000): conservative, 3D, planar occluders */
    PVS_METHOD_SHRINK,       /* occluder shrinking + point sampling (Wonka 2000): conservative */
    PVS_METHOD_AUTO,         /* the conservative methods that apply to the scene, their PVSs intersected (see
                                pvs_bake_desc.methods and pvs_bake_method_info); never SAMPLE */
    PVS_METHOD_VOCC,         /* virtual occluders (Koltun 2000): conservative, 2.5D (vertical walls on the ground);
                                stores the occluders too, the PVS is what they rebuild (pvs_vocc_cull) */
    PVS_METHOD_COUNT
} pvs_method;

/* Name of a method ("sample"), or "unknown". */
PVS_API const char *pvs_method_name(pvs_method method);

/* The shrink method's paths. */
typedef enum pvs_shrink_mode {
    PVS_SHRINK_AUTO = 0,     /* 2.5D when the occluders are 2.5D (pvs_occluders_info.is_2d5), else 3D */
    PVS_SHRINK_2D5,          /* Wonka 2000 §3: column occluders, samples on the cell's top face, cull maps */
    PVS_SHRINK_3D,           /* samples on the six faces, from-point depth maps of the eroded boxes */
    PVS_SHRINK_MODE_COUNT
} pvs_shrink_mode;

/* The shrink method for one cell (Wonka, Wimmer, Schmalstieg 2000): the occluders, eroded by their
   eps, are point-sampled from the cell every eps; an object is left out only when every sample sees
   it hidden (appendix theorem: then every point of the cell does). Objects meeting the cell, or
   standing under its top face, are always set. Sets bits in `visible` (PVS_BITSET_WORDS(object_count)
   words, not cleared first); occluder-only objects are never set. `occluders` must have been made
   for this scene. Scratch is allocated through the occluders' allocator and freed before returning:
   thread-safe. Errors: INVALID_ARGUMENT, BAD_CELL, UNSUPPORTED (a path this build cannot run, with
   the reason), OUT_OF_MEMORY. */
PVS_API pvs_result pvs_shrink_cell(const pvs_scene *scene, const pvs_occluders *occluders, const pvs_box *cell,
                                   pvs_shrink_mode mode, pvs_word *visible, pvs_error *err);

/* The ray-sampling estimator: `points` stratified points in `cell` (its 8 corners and 6 face centres
   first, then a jittered grid), `rays_per_point` uniformly distributed directions from each, and the
   first object each ray hits is set in `visible` (PVS_BITSET_WORDS(object_count) words, not cleared
   first; occluder-only objects are never set). A lower bound of the exact visible set: the yardstick
   of the tests and pvscheck, never a conservative PVS. Deterministic in `seed`. Thread-safe, no
   allocation. Returns the number of rays cast. */
PVS_API uint64_t pvs_sample_visibility(const pvs_scene *scene, const pvs_box *cell, uint32_t points,
                                       uint32_t rays_per_point, uint64_t seed, pvs_word *visible);

/* Object-directed ray sampling, a stronger lower bound than pvs_sample_visibility for small and far
   objects (uniform directions pass them by): for each object set in `targets` (NULL: every object)
   and not yet set in `visible`, up to `rays_per_object` segments from a uniformly random point of
   `cell` to a random point of one of the object's triangles (chosen uniformly among its triangles,
   the point pulled 1% toward the triangle's centroid). The first object each segment hits is set in
   `visible` (it is seen from that point, whichever object it is); the object's rays stop at the first
   that reaches it. Occluder-only objects are never set nor aimed at. Still a lower bound of the exact
   visible set, never a PVS. Deterministic in `seed`. Thread-safe, no allocation. Returns the number
   of rays cast. */
PVS_API uint64_t pvs_sample_visibility_toward(const pvs_scene *scene, const pvs_box *cell, const pvs_word *targets,
                                              uint32_t rays_per_object, uint64_t seed, pvs_word *visible);

/* ---- extended projections (Durand, Drettakis, Thollot, Puech 2000) ---- */

/* A projection plane of a cell (Durand 2000 §2.4, §6.1): perpendicular to `axis` (0..2), on the
   cell's side `side` (+1 beyond cell.max[axis], -1 below cell.min[axis]), at `distance` > 0 from that
   face of the cell. Depth (§2.3) is the distance beyond the face, along the axis away from the cell.
   The plane is the rectangle rect = (u0, v0, u1, v1) over the other two axes u = (axis + 1) % 3 and
   v = (axis + 2) % 3, split into width x height pixels: pixel (i, j) covers u in u0 + [i, i + 1] *
   (u1 - u0) / width and v likewise. A depth map is width * height floats, row j first, holding per
   pixel the Depth of the nearest occluder Projection, PVS_EXTPROJ_EMPTY where there is none. */
typedef struct pvs_extproj_plane {
    pvs_box cell;
    uint32_t axis;
    int32_t side;
    float distance;
    float rect[4];
    uint32_t width, height;   /* 1..4096 each */
} pvs_extproj_plane;
#define PVS_EXTPROJ_EMPTY 3.402823466e+38f

/* Adds the extended Projection of one convex occluder (§3.2): `points` (count x (x, y, z), 1..16) are
   the vertices of a planar convex polygon or of a closed convex solid (a solid whose bounding box
   meets the cell is left out: it could hold the viewer). The occluder is clipped to the depths > 0
   (beyond the cell's face) and split at the plane; the Projection of each part is the intersection
   of its views from the cell's 8 corners, rasterized conservatively: a pixel is written only when
   the part covers it entirely from every point of the cell. Such pixels get min(stored, Depth),
   Depth being the part's greatest depth (no nearer than any of its points, §2.3). Returns the
   number of pixel writes (a pixel covered by both parts counts twice), 0 when nothing is covered or
   the arguments are bad. Thread-safe on distinct maps; no allocation. */
PVS_API uint32_t pvs_extproj_occluder(const pvs_extproj_plane *plane, const float *points, uint32_t count, float *depth_map);

/* The extended Projection of an occludee box (§3.1): the bounding rectangle of its views from every
   point of the cell (from the supporting and separating lines, i.e. the extremes over the cell's and
   the box's corners) as inclusive pixel bounds rect = (i0, j0, i1, j1), which may reach outside the
   map, and its least Depth in *depth. Returns 1, or 0 when the box is not entirely beyond the cell's
   face (depth <= 0 somewhere: this plane cannot decide it). Conservative: the rectangle holds every
   pixel the box touches from any point of the cell. No allocation. */
PVS_API int pvs_extproj_occludee(const pvs_extproj_plane *plane, const pvs_box *box, int32_t rect[4], float *depth);

/* 1 if an occludee with Projection rect (pvs_extproj_occludee) and least Depth `depth` may be visible
   in the depth map: some pixel of the rectangle lies outside the map or stores a Depth >= depth.
   0 when every pixel holds an occluder strictly nearer: hidden from the whole cell (§2.2). */
PVS_API int pvs_extproj_test(const pvs_extproj_plane *plane, const float *depth_map, const int32_t rect[4], float depth);

/* ---- bake ------------------------------------------------------------------------------------ */

/* What to bake. Left at zero, optional fields get defaults. */
typedef struct pvs_bake_desc {
    const pvs_scene *scene;   /* must outlive the bake */
    const pvs_box *cells;     /* cell_count view cells, copied */
    uint32_t cell_count;
    pvs_method method;        /* PVS_METHOD_DEFAULT = AUTO */
    float eps;                /* sampling / shrinking distance; 0 = derived from the cells */
    uint32_t sample_points;   /* SAMPLE: points per cell, 0 = 32 */
    uint32_t sample_rays;     /* SAMPLE: rays per point, 0 = 2048 */
    uint64_t seed;            /* SAMPLE: random seed */
    uint32_t max_chain;       /* file: bound K on delta chains, 0 = PVS_DEFAULT_CHAIN */
    uint32_t extproj_resolution; /* EXTPROJ: depth map pixels per side, 0 = 256; 16..4096 */
    uint32_t extproj_occluders;  /* EXTPROJ: occluders projected per plane, 0 = 128; <= 65536 */
    pvs_shrink_mode shrink_mode; /* SHRINK: path, AUTO picks */
    uint32_t vocc_slices;     /* VOCC: height slices per cell (§3.1), 0 = 5; 1..16 */
    uint32_t vocc_max_occluders; /* VOCC: virtual occluders kept per cell (Fig. 6), 0 = 10; 1..255 */
    uint32_t vocc_only;       /* VOCC: 1 = store only the occluders: the PVS records are placeholders (every
                                 drawable object) and the runtime rebuilds each PVS with pvs_vocc_cull */
    float voxel_size;         /* SHRINK: occluder synthesis voxel size, 0 = derived */
    /* Sharded bakes (build farms): with shard_count >= 2 this bake runs only cells shard_index,
       shard_index + shard_count, ... and writes a part file; the parts of shard_index 0..shard_count-1
       merge (decode them, pvs_file_encode the whole table) into the file an unsharded bake writes. */
    uint32_t shard_index, shard_count;
    uint32_t methods;         /* AUTO: the methods to consider, a mask of (1u << PVS_METHOD_*) of conservative
                                 methods (not SAMPLE, DEFAULT or AUTO); 0 = every conservative method but
                                 VOCC (name it to intersect its PVS too) */
    float max_distance;       /* > 0: an object whose box is farther than this from every point of the cell
                                 box is left out (a draw distance); 0 = no limit */
    uint32_t flags;           /* PVS_BAKE_* */
    pvs_allocator allocator;
} pvs_bake_desc;

/* Bake flags. */
#define PVS_BAKE_PREVIEW 1u   /* fast and coarse, still conservative: AUTO runs only the cheapest method that
                                 applies; EXTPROJ uses 64 pixels and 32 occluders per plane unless set; SHRINK's
                                 derived eps is doubled */

typedef struct pvs_bake pvs_bake;

/* Validates the desc and prepares the tasks. Errors: INVALID_ARGUMENT, BAD_CELL (err->index = cell),
   NOT_FINITE, OUT_OF_MEMORY. */
PVS_API pvs_result pvs_bake_begin(const pvs_bake_desc *desc, pvs_bake **out_bake, pvs_error *err);
/* Number of tasks (today one per cell of the shard). */
PVS_API uint32_t pvs_bake_task_count(const pvs_bake *bake);
/* The cell a task bakes. */
PVS_API uint32_t pvs_bake_task_cell(const pvs_bake *bake, uint32_t task);
/* Runs one task. Thread-safe for distinct task indices; each task uses its own scratch. */
PVS_API pvs_result pvs_bake_run_task(pvs_bake *bake, uint32_t task, pvs_error *err);
/* The resolved parameters (method, eps). */
PVS_API pvs_method pvs_bake_method(const pvs_bake *bake);
PVS_API float pvs_bake_eps(const pvs_bake *bake);
/* The methods a bake considered, in the order it runs them: one for a single-method bake; for AUTO
   every candidate, also those it skipped (ran = 0) because they cannot cull anything in this scene. */
PVS_API uint32_t pvs_bake_method_count(const pvs_bake *bake);
/* What method i (< pvs_bake_method_count) did (pvs_bake_get_method_info). The sums cover the tasks
   run so far (not the restored ones). */
typedef struct pvs_bake_method_info {
    pvs_method method;
    int ran;                  /* 1: every task runs it; 0: skipped */
    const char *reason;       /* why it runs or was skipped (a constant string, never NULL) */
    uint32_t cells;           /* tasks that ran it */
    uint64_t pvs_sum;         /* sum over those cells of the PVS size this method found alone */
    uint64_t sole_culls;      /* (cell, object) pairs this method alone left out of the intersection: its
                                 contribution (for one method: every object it left out) */
} pvs_bake_method_info;
/* Fills *info. Errors: INVALID_ARGUMENT (i out of range, NULL). Call after the tasks ran (not
   concurrently with pvs_bake_run_task). */
PVS_API pvs_result pvs_bake_get_method_info(const pvs_bake *bake, uint32_t i, pvs_bake_method_info *info);
/* 1 if the task has run (or was restored). */
PVS_API int pvs_bake_task_done(const pvs_bake *bake, uint32_t task);
/* Resumable bakes: marks a task done with a PVS kept from an earlier run of the same bake (same scene,
   cells and parameters), e.g. read back from a state file. `bits` has word_count >=
   PVS_BITSET_WORDS(object_count) words; bits past object_count must be zero. Thread-safe like
   pvs_bake_run_task. Errors: INVALID_ARGUMENT (task out of range, NULL, a set bit past the objects or
   of an occluder-only object), BUFFER_TOO_SMALL, UNSUPPORTED (a VOCC bake: its occluders must be baked). */
PVS_API pvs_result pvs_bake_restore_task(pvs_bake *bake, uint32_t task, const pvs_word *bits, size_t word_count, pvs_error *err);
/* SHRINK (alone or within AUTO): the occluders pvs_bake_begin synthesized (owned by the bake; for the
   summary: leaks, thin objects, 2.5D or 3D) and the path the tasks run; NULL / PVS_SHRINK_AUTO when
   SHRINK was not prepared. */
PVS_API const pvs_occluders *pvs_bake_occluders(const pvs_bake *bake);
PVS_API pvs_shrink_mode pvs_bake_shrink_mode(const pvs_bake *bake);
/* The PVS of a cell whose task has run, or NULL (also for cells of other shards).
   PVS_BITSET_WORDS(object_count) words. */
PVS_API const pvs_word *pvs_bake_cell_pvs(const pvs_bake *bake, uint32_t cell);
/* The exact size of the file (0 if not every task has run or on error). Encodes to measure: keep
   the number rather than calling it twice. */
PVS_API size_t pvs_bake_file_size(const pvs_bake *bake);
/* Writes the .pvs file (a part file for a shard) into out[0..capacity); *out_size receives the size,
   also with BUFFER_TOO_SMALL. Errors: NOT_DONE, BUFFER_TOO_SMALL, COUNT_OVERFLOW, OUT_OF_MEMORY. */
PVS_API pvs_result pvs_bake_write_file(const pvs_bake *bake, void *out, size_t capacity, size_t *out_size, pvs_error *err);
PVS_API void pvs_bake_destroy(pvs_bake *bake);

/* ---- format ---------------------------------------------------------------------------------- */

/* File flags. */
#define PVS_FILE_APPROXIMATE 1u /* baked by an estimator (SAMPLE): not conservative */

#define PVS_DEFAULT_CHAIN 8u    /* default bound K on a cell's delta chain */
#define PVS_MAX_CHAIN 64u       /* largest K a file may declare */

/* A PVS table to encode: cell_count bitsets of PVS_BITSET_WORDS(object_count) words each.
   The encoder (Durand et al. 2000, §6.2, delta-PVS) stores a few key cells whole and every other cell
   as the ids that differ from a base cell; bases come from a depth-bounded minimum spanning tree over
   the cells' nearest neighbours weighted by the coded delta size, each record in the smallest of four
   codings. */
typedef struct pvs_file_desc {
    const pvs_box *cells;
    uint32_t cell_count;
    uint32_t object_count;
    const pvs_word *pvs;       /* cell-major */
    pvs_method method;
    float eps;
    uint32_t up_axis;          /* 1 or 2 */
    uint32_t flags;            /* PVS_FILE_* */
    uint32_t max_chain;        /* K, the most deltas a decode applies: 0 = PVS_DEFAULT_CHAIN, else 1..PVS_MAX_CHAIN */
    /* A part file of a sharded bake (shard_count >= 2): the table holds cells shard_index,
       shard_index + shard_count, ... of total_cell_count, in that order. Zero for a whole file. */
    uint32_t shard_index, shard_count, total_cell_count;
    /* Optional virtual occluders (the VOCC section, >>vocc), NULL vocc_counts for none: per cell (in
       table order) vocc_counts[c] occluders of five bytes, back to back in virtual_occluders, and the
       coordinate scale code vocc_scales[c]; heights vocc_base + byte * vocc_height_step (finite,
       step > 0); vocc_flags PVS_VOCC_ONLY when the table is placeholders. */
    const uint8_t *vocc_counts, *vocc_scales, *virtual_occluders;
    uint32_t vocc_stride;      /* bytes from one cell's occluders to the next; 0 = back to back */
    float vocc_base, vocc_height_step;
    uint32_t vocc_flags;
    pvs_allocator allocator;   /* the encoder's scratch */
} pvs_file_desc;

/* Encodes the table into out[0..capacity). *out_size receives the exact size, also when the buffer
   is too small (BUFFER_TOO_SMALL). With out == NULL it only measures (returns PVS_OK): call once
   with NULL to learn the size. The output is a deterministic function of the desc; the encoder's
   scratch comes from desc->allocator. Thread-safe for distinct outputs. Errors: INVALID_ARGUMENT, BAD_CELL, BUFFER_TOO_SMALL,
   COUNT_OVERFLOW (a file over 4 GiB), OUT_OF_MEMORY. */
PVS_API pvs_result pvs_file_encode(const pvs_file_desc *desc, void *out, size_t capacity, size_t *out_size, pvs_error *err);

/* An opened file: a view of the caller's bytes, which must stay alive and unchanged. Plain data,
   no allocation; copy freely. Fields are read-only to the caller; those after `private_` are the
   reader's own. */
typedef struct pvs_file {
    const uint8_t *data;
    size_t size;
    uint32_t version, flags;
    uint32_t cell_count, object_count;
    pvs_method method;
    float eps;
    uint32_t up_axis;
    uint32_t max_chain;        /* K: no decode applies more deltas */
    uint32_t key_count;        /* cells stored whole */
    uint32_t shard_index, shard_count, total_cell_count; /* a part file when shard_count >= 2 */
    uint32_t vocc_flags;       /* PVS_VOCC_*: 0 when the file has no virtual occluders (>>vocc) */
    uint32_t virtual_occluder_count;     /* VOCC: occluders stored, all cells */
    float vocc_base, vocc_height_step;   /* VOCC: the occluders' base height, top = base + byte * step */
    struct {
        const uint8_t *values[3];   /* CELL: per-axis coordinate tables */
        const uint8_t *indices;     /* CELL: packed per-cell indices */
        uint32_t value_count[3], index_bits[6], cell_bits; /* widths: min indices, then extents */
        size_t index_bytes;
        const uint8_t *tree;        /* TREE: nodes, leaf offsets, items */
        uint32_t tree_depth;
        const uint8_t *records;     /* RECS */
        uint32_t records_size, block_count;
        const uint8_t *vocc;        /* VOCC */
        uint32_t vocc_size;
    } private_;
} pvs_file;

/* Validates everything (time linear in the size, no allocation, never reads outside data[0..size))
   and fills *file. Safe on untrusted input: every offset, size, count, checksum, coordinate, tree
   link, record and base chain is checked, and later calls on an opened file cannot fail on the
   file's content. Errors: INVALID_ARGUMENT, BAD_MAGIC, BAD_VERSION, TRUNCATED, BAD_HEADER,
   BAD_SECTION, CHECKSUM, BAD_CELL, BAD_TREE, BAD_RECORD, OBJECT_OUT_OF_RANGE, BAD_CHAIN; err->offset
   is the offending byte and err->index the cell or section where one applies. */
PVS_API pvs_result pvs_file_open(const void *data, size_t size, pvs_file *file, pvs_error *err);

/* How a cell's record is stored (pvsinfo prints these). */
typedef struct pvs_record_info {
    uint32_t base;             /* the cell the delta applies to, PVS_NO_CELL for a key cell */
    uint32_t depth;            /* deltas applied to decode this cell (0 for a key cell) */
    uint32_t coding;           /* of the (added) ids: 0 gap varints, 1 run lengths, 2 Rice codes, 3 raw bitset */
    uint32_t bytes;            /* size of the record */
    uint32_t base_size;        /* a delta: the size of the base's PVS its removal ranks count in */
} pvs_record_info;
#define PVS_CODING_COUNT 4
/* Fills *info for cell < cell_count. No allocation. */
PVS_API void pvs_file_record_info(const pvs_file *file, uint32_t cell, pvs_record_info *info);

/* ---- runtime --------------------------------------------------------------------------------- */

#define PVS_NO_CELL 0xffffffffu
/* The cell containing point p (boundaries included), found through the file's look-up kD-tree. Of
   overlapping cells the lowest id; PVS_NO_CELL when p is in no cell or not finite. No allocation. */
PVS_API uint32_t pvs_file_find_cell(const pvs_file *file, const float p[3]);
/* The box of a cell (< cell_count). */
PVS_API pvs_box pvs_file_cell_box(const pvs_file *file, uint32_t cell);
/* Decodes a cell's PVS into bits[0..word_count), clearing it first: the key at the end of the cell's
   chain, then at most max_chain deltas. word_count must be at least PVS_BITSET_WORDS(object_count).
   Iterate the set ids with pvs_bitset_next. Errors: INVALID_ARGUMENT, BUFFER_TOO_SMALL. No allocation. */
PVS_API pvs_result pvs_file_decode(const pvs_file *file, uint32_t cell, pvs_word *bits, size_t word_count, pvs_error *err);

/* Called by the cursor for each object whose visibility changes: visible = 1 added, 0 removed. */
typedef void (*pvs_change_fn)(void *user, uint32_t object, int visible);

/* Follows a viewer from cell to cell and reports only the objects that change (Durand et al. 2000,
   §6.2). Moving to a cell whose base is the current cell applies that one delta; any other move
   decodes the new cell into the scratch bitset and compares. Plain data over caller memory; no
   allocation. */
typedef struct pvs_cursor {
    const pvs_file *file;
    uint32_t cell;             /* current cell, PVS_NO_CELL before the first move */
    pvs_word *bits;            /* the current PVS (read it, do not write it) */
    pvs_word *scratch;
    size_t word_count;
    uint64_t delta_moves, full_moves; /* statistics: moves by one delta, by a full decode */
} pvs_cursor;

/* Starts a cursor with an empty set. bits and scratch: word_count >= PVS_BITSET_WORDS(object_count)
   words each, distinct. Errors: INVALID_ARGUMENT, BUFFER_TOO_SMALL. */
PVS_API pvs_result pvs_cursor_init(pvs_cursor *cursor, const pvs_file *file, pvs_word *bits, pvs_word *scratch,
                                   size_t word_count, pvs_error *err);
/* Moves to `cell` (PVS_NO_CELL empties the set), calling on_change (may be NULL) once per object that
   enters or leaves the set: in ascending id order after a full decode, removals (ascending) then
   additions (ascending) after one delta. Errors: INVALID_ARGUMENT (cell out of range). */
PVS_API pvs_result pvs_cursor_move(pvs_cursor *cursor, uint32_t cell, pvs_change_fn on_change, void *user);

#ifdef __cplusplus
}
#endif
#endif /* PVS_H */

/* ============================================================================================== */
/* Stop reading here if you only use the API.                                                     */
/* ============================================================================================== */

#ifdef PVS_IMPLEMENTATION
#ifndef PVS_IMPLEMENTATION_ONCE
#define PVS_IMPLEMENTATION_ONCE

#include <float.h>
#include <math.h>
#include <string.h>
#ifndef PVS_NO_STDIO
#include <stdarg.h>
#include <stdio.h>
#endif

#if defined(PVS_MALLOC) != defined(PVS_FREE)
#error "pvs.h: define both PVS_MALLOC and PVS_FREE, or neither"
#endif
#ifndef PVS_MALLOC
#include <stdlib.h>
#define PVS_MALLOC(sz) malloc(sz)
#define PVS_FREE(p) free(p)
#endif
#ifndef PVS_ASSERT
#include <assert.h>
#define PVS_ASSERT(x) assert(x)
#endif

#if defined(__GNUC__) || defined(__clang__)
#define PVS__UNUSED __attribute__((unused))
#else
#define PVS__UNUSED
#endif
#define PVS__STATIC static PVS__UNUSED

// >>core
/* ---------------------------------------------------------------------------------------------- */
/* core: result strings, allocator, errors, math, bitsets                                         */
/* ---------------------------------------------------------------------------------------------- */

PVS_API const char *pvs_result_string(pvs_result r) {
    switch (r) {
    case PVS_OK: return "success";
    case PVS_ERROR_INVALID_ARGUMENT: return "invalid argument";
    case PVS_ERROR_OUT_OF_MEMORY: return "out of memory";
    case PVS_ERROR_COUNT_OVERFLOW: return "count overflow";
    case PVS_ERROR_INDEX_OUT_OF_RANGE: return "index out of range";
    case PVS_ERROR_NOT_FINITE: return "value is not finite";
    case PVS_ERROR_EMPTY_OBJECT: return "empty object";
    case PVS_ERROR_DEGENERATE_OBJECT: return "degenerate object";
    case PVS_ERROR_OVERLAPPING_OBJECTS: return "overlapping objects";
    case PVS_ERROR_BAD_OCCLUDER: return "bad occluder";
    case PVS_ERROR_BAD_CELL: return "bad cell";
    case PVS_ERROR_BUFFER_TOO_SMALL: return "buffer too small";
    case PVS_ERROR_BAD_MAGIC: return "bad magic";
    case PVS_ERROR_BAD_VERSION: return "unknown format version";
    case PVS_ERROR_TRUNCATED: return "truncated";
    case PVS_ERROR_BAD_SECTION: return "bad section";
    case PVS_ERROR_CHECKSUM: return "checksum mismatch";
    case PVS_ERROR_BAD_RECORD: return "bad record";
    case PVS_ERROR_OBJECT_OUT_OF_RANGE: return "object id out of range";
    case PVS_ERROR_BAD_HEADER: return "bad header";
    case PVS_ERROR_NOT_DONE: return "not done";
    case PVS_ERROR_UNSUPPORTED: return "unsupported";
    case PVS_ERROR_BAD_CHAIN: return "bad delta chain";
    case PVS_ERROR_BAD_TREE: return "bad cell look-up tree";
    case PVS_ERROR_SHARD_MISMATCH: return "shard mismatch";
    default: return "unknown result";
    }
}

PVS_API uint32_t pvs_version(void) { return PVS_VERSION; }

/* Fills *err (if any) and returns `code`. The message is "<reason>: <formatted detail>". */
PVS__STATIC pvs_result pvs__fail(pvs_error *err, pvs_result code, int64_t index, uint64_t offset, const char *fmt, ...) {
    if (err) {
        err->result = code;
        err->index = index;
        err->offset = offset;
#ifndef PVS_NO_STDIO
        {
            va_list ap;
            int n = snprintf(err->message, sizeof(err->message), "%s: ", pvs_result_string(code));
            va_start(ap, fmt);
            if (n > 0 && (size_t)n < sizeof(err->message))
                vsnprintf(err->message + n, sizeof(err->message) - (size_t)n, fmt, ap);
            va_end(ap);
        }
#else
        {
            const char *s = pvs_result_string(code);
            size_t n = strlen(s);
            (void)fmt;
            if (n >= sizeof(err->message)) n = sizeof(err->message) - 1;
            memcpy(err->message, s, n);
            err->message[n] = 0;
        }
#endif
    }
    return code;
}

PVS__STATIC void pvs__ok(pvs_error *err) {
    if (err) {
        err->result = PVS_OK;
        err->index = -1;
        err->offset = 0;
        err->message[0] = 0;
    }
}

/* Overflow-checked size arithmetic: return 0 on overflow. */
PVS__STATIC int pvs__mul(size_t a, size_t b, size_t *out) {
    if (b && a > (size_t)-1 / b) return 0;
    *out = a * b;
    return 1;
}
PVS__STATIC int pvs__add(size_t a, size_t b, size_t *out) {
    if (a > (size_t)-1 - b) return 0;
    *out = a + b;
    return 1;
}

/* Allocation through a desc's hooks; align is a power of two <= 64. The default path over-allocates
   for alignments above what malloc guarantees and keeps the offset in the byte before the block. */
PVS__STATIC void *pvs__alloc(const pvs_allocator *a, size_t size, size_t align) {
    if (size == 0) size = 1;
    if (a->alloc) return a->alloc(size, align, a->user);
    if (align <= 16) return PVS_MALLOC(size);
    {
        size_t total;
        unsigned char *raw, *p;
        if (!pvs__add(size, align, &total)) return NULL;
        raw = (unsigned char *)PVS_MALLOC(total);
        if (!raw) return NULL;
        p = (unsigned char *)(((uintptr_t)raw + align) & ~(uintptr_t)(align - 1));
        p[-1] = (unsigned char)(p - raw);
        return p;
    }
}
PVS__STATIC void pvs__free(const pvs_allocator *a, void *p, size_t size, size_t align) {
    if (!p) return;
    if (size == 0) size = 1;
    if (a->free) {
        (*a->free)(p, size, a->user);
        return;
    }
    if (align <= 16) {
        PVS_FREE(p);
        return;
    }
    PVS_FREE((unsigned char *)p - ((unsigned char *)p)[-1]);
}
/* Array allocation with overflow check: n elements of `elem` bytes, 16-byte aligned. */
PVS__STATIC void *pvs__alloc_array(const pvs_allocator *a, size_t n, size_t elem) {
    size_t bytes;
    if (!pvs__mul(n, elem, &bytes)) return NULL;
    return pvs__alloc(a, bytes, 16);
}
PVS__STATIC void pvs__free_array(const pvs_allocator *a, void *p, size_t n, size_t elem) {
    pvs__free(a, p, n * elem, 16);
}

/* ---- math (private: generic names must not leak into an engine) ---- */

typedef struct pvs__v3 {
    float x, y, z;
} pvs__v3;

PVS__STATIC pvs__v3 pvs__v3_make(float x, float y, float z) {
    pvs__v3 r;
    r.x = x; r.y = y; r.z = z;
    return r;
}
PVS__STATIC pvs__v3 pvs__v3_load(const float *p) { return pvs__v3_make(p[0], p[1], p[2]); }
PVS__STATIC pvs__v3 pvs__v3_add(pvs__v3 a, pvs__v3 b) { return pvs__v3_make(a.x + b.x, a.y + b.y, a.z + b.z); }
PVS__STATIC pvs__v3 pvs__v3_sub(pvs__v3 a, pvs__v3 b) { return pvs__v3_make(a.x - b.x, a.y - b.y, a.z - b.z); }
PVS__STATIC pvs__v3 pvs__v3_scale(pvs__v3 a, float s) { return pvs__v3_make(a.x * s, a.y * s, a.z * s); }
PVS__STATIC float pvs__v3_dot(pvs__v3 a, pvs__v3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
PVS__STATIC pvs__v3 pvs__v3_cross(pvs__v3 a, pvs__v3 b) {
    return pvs__v3_make(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x);
}
PVS__STATIC float pvs__v3_length(pvs__v3 a) { return sqrtf(pvs__v3_dot(a, a)); }
PVS__STATIC float pvs__v3_get(pvs__v3 a, int axis) { return axis == 0 ? a.x : axis == 1 ? a.y : a.z; }

PVS__STATIC int pvs__finite(float f) { return f == f && f - f == 0.0f; }

PVS__STATIC pvs_box pvs__box_empty(void) {
    pvs_box b;
    b.min[0] = b.min[1] = b.min[2] = FLT_MAX;
    b.max[0] = b.max[1] = b.max[2] = -FLT_MAX;
    return b;
}
PVS__STATIC void pvs__box_add_point(pvs_box *b, const float *p) {
    int i;
    for (i = 0; i < 3; ++i) {
        if (p[i] < b->min[i]) b->min[i] = p[i];
        if (p[i] > b->max[i]) b->max[i] = p[i];
    }
}
PVS__STATIC void pvs__box_add_box(pvs_box *b, const pvs_box *o) {
    int i;
    for (i = 0; i < 3; ++i) {
        if (o->min[i] < b->min[i]) b->min[i] = o->min[i];
        if (o->max[i] > b->max[i]) b->max[i] = o->max[i];
    }
}
PVS__STATIC int pvs__box_valid(const pvs_box *b) {
    int i;
    for (i = 0; i < 3; ++i)
        if (!pvs__finite(b->min[i]) || !pvs__finite(b->max[i]) || b->min[i] > b->max[i]) return 0;
    return 1;
}
PVS__STATIC int pvs__box_contains_point(const pvs_box *b, const float *p) {
    return p[0] >= b->min[0] && p[0] <= b->max[0] && p[1] >= b->min[1] && p[1] <= b->max[1] && p[2] >= b->min[2] &&
           p[2] <= b->max[2];
}
PVS__STATIC int pvs__box_overlap(const pvs_box *a, const pvs_box *b) {
    return a->min[0] <= b->max[0] && b->min[0] <= a->max[0] && a->min[1] <= b->max[1] && b->min[1] <= a->max[1] &&
           a->min[2] <= b->max[2] && b->min[2] <= a->max[2];
}
/* Squared minimum distance between two boxes (0 where they meet). */
PVS__STATIC float pvs__box_distance2(const pvs_box *a, const pvs_box *b) {
    float d2 = 0.0f;
    int i;
    for (i = 0; i < 3; ++i) {
        float g = 0.0f;
        if (b->min[i] > a->max[i]) g = b->min[i] - a->max[i];
        else if (a->min[i] > b->max[i]) g = a->min[i] - b->max[i];
        d2 += g * g;
    }
    return d2;
}

/* A plane n.p + d = 0; the positive side is n.p + d > 0. */
typedef struct pvs__plane {
    pvs__v3 n;
    float d;
} pvs__plane;
PVS__STATIC float pvs__plane_eval(pvs__plane pl, pvs__v3 p) { return pvs__v3_dot(pl.n, p) + pl.d; }

/* ---- bitsets ---- */

PVS_API int pvs_bitset_test(const pvs_word *bits, uint32_t i) { return (int)((bits[i >> 6] >> (i & 63)) & 1u); }
PVS_API void pvs_bitset_set(pvs_word *bits, uint32_t i) { bits[i >> 6] |= (pvs_word)1 << (i & 63); }
PVS_API void pvs_bitset_clear(pvs_word *bits, uint32_t i) { bits[i >> 6] &= ~((pvs_word)1 << (i & 63)); }

PVS__STATIC uint32_t pvs__popcount64(uint64_t x) {
#if (defined(__GNUC__) || defined(__clang__)) && (defined(__POPCNT__) || defined(__ARM_NEON))
    return (uint32_t)__builtin_popcountll(x); /* one instruction; elsewhere the builtin is a library call */
#else
    x = x - ((x >> 1) & 0x5555555555555555ull);
    x = (x & 0x3333333333333333ull) + ((x >> 2) & 0x3333333333333333ull);
    x = (x + (x >> 4)) & 0x0f0f0f0f0f0f0f0full;
    return (uint32_t)((x * 0x0101010101010101ull) >> 56);
#endif
}
PVS__STATIC uint32_t pvs__ctz64(uint64_t x) { /* x != 0 */
#if defined(__GNUC__) || defined(__clang__)
    return (uint32_t)__builtin_ctzll(x);
#else
    uint32_t n = 0;
    while (!(x & 1u)) { x >>= 1; ++n; }
    return n;
#endif
}

PVS_API uint32_t pvs_bitset_count(const pvs_word *bits, uint32_t bit_count) {
    uint32_t n = 0, full = bit_count >> 6, i;
    for (i = 0; i < full; ++i) n += pvs__popcount64(bits[i]);
    if (bit_count & 63) n += pvs__popcount64(bits[full] & (((pvs_word)1 << (bit_count & 63)) - 1));
    return n;
}

PVS_API uint32_t pvs_bitset_next(const pvs_word *bits, uint32_t bit_count, uint32_t from) {
    uint32_t w, words;
    pvs_word cur;
    if (from >= bit_count) return bit_count;
    w = from >> 6;
    words = (uint32_t)PVS_BITSET_WORDS(bit_count);
    cur = bits[w] & (~(pvs_word)0 << (from & 63));
    for (;;) {
        if (cur) {
            uint32_t i = (w << 6) + pvs__ctz64(cur);
            return i < bit_count ? i : bit_count;
        }
        if (++w >= words) return bit_count;
        cur = bits[w];
    }
}

/* Deterministic random numbers: splitmix64 (Steele et al. 2014). Used by the samplers. */
PVS__STATIC uint64_t pvs__splitmix64(uint64_t *state) {
    uint64_t z = (*state += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
}
/* Uniform float in [0, 1). */
PVS__STATIC float pvs__random01(uint64_t *state) { return (float)(pvs__splitmix64(state) >> 40) * (1.0f / 16777216.0f); }

/* CRC-32 (IEEE 802.3, reflected polynomial 0xEDB88320), two nibble-table steps per byte: a 64-byte
   constant table keeps the code small; validation stays linear in the file size. */
PVS__STATIC uint32_t pvs__crc32(uint32_t crc, const uint8_t *p, size_t n) {
    static const uint32_t t[16] = {0x00000000u, 0x1db71064u, 0x3b6e20c8u, 0x26d930acu, 0x76dc4190u, 0x6b6b51f4u,
                                   0x4db26158u, 0x5005713cu, 0xedb88320u, 0xf00f9344u, 0xd6d6a3e8u, 0xcb61b38cu,
                                   0x9b64c2b0u, 0x86d3d2d4u, 0xa00ae278u, 0xbdbdf21cu};
    size_t i;
    crc = ~crc;
    for (i = 0; i < n; ++i) {
        crc ^= p[i];
        crc = (crc >> 4) ^ t[crc & 15];
        crc = (crc >> 4) ^ t[crc & 15];
    }
    return ~crc;
}

// >>scene
/* ---------------------------------------------------------------------------------------------- */
/* scene: validated copies of the caller's arrays, object bounds, explicit occluders              */
/* ---------------------------------------------------------------------------------------------- */

struct pvs_scene {
    pvs_allocator allocator;
    uint32_t vertex_count, triangle_count, object_count, occluder_count;
    uint32_t up_axis;            /* 1 or 2 */
    uint32_t flags;
    float *positions;            /* vertex_count * 3 */
    uint32_t *indices;           /* triangle_count * 3 */
    uint32_t *triangle_object;   /* triangle_count: object id or PVS_NO_OBJECT */
    pvs_box *object_boxes;       /* object_count; empty box (min > max) for empty objects */
    uint32_t *object_flags;      /* object_count */
    uint32_t *object_triangles;  /* object_count * 2: first triangle, triangle count */
    pvs_box bounds;
    pvs_occluder_desc *occluders;/* occluder_count, arrays pointing into occluder_data */
    pvs_box *occluder_boxes;     /* occluder_count */
    float *occluder_data;        /* planes and footprints of all occluders */
    size_t occluder_data_count;  /* floats in occluder_data */
    pvs_kdtree *triangle_tree;   /* over triangle boxes (zero-area triangles left out) */
    pvs_kdtree *object_tree;     /* over object boxes (empty objects left out) */
    float *triangle_corners;     /* triangle_count * 9: corners sorted lexicographically, for ray casts */
};

/* Fills s->triangle_corners and empties the boxes of zero-area triangles (>>kdtree). */
PVS__STATIC pvs_result pvs__scene_prepare_rays(pvs_scene *s, pvs_box *tri_boxes, pvs_error *err);

/* Double-precision 3x3 solve of three planes n_i.p + d_i = 0; returns 0 when (nearly) parallel. */
PVS__STATIC int pvs__three_planes(const float *a, const float *b, const float *c, double out[3]) {
    double n1[3], n2[3], n3[3], x[3], det;
    int i;
    for (i = 0; i < 3; ++i) { n1[i] = a[i]; n2[i] = b[i]; n3[i] = c[i]; }
    /* x = n2 x n3 */
    x[0] = n2[1] * n3[2] - n2[2] * n3[1];
    x[1] = n2[2] * n3[0] - n2[0] * n3[2];
    x[2] = n2[0] * n3[1] - n2[1] * n3[0];
    det = n1[0] * x[0] + n1[1] * x[1] + n1[2] * x[2];
    {
        double l1 = sqrt(n1[0] * n1[0] + n1[1] * n1[1] + n1[2] * n1[2]);
        double l2 = sqrt(n2[0] * n2[0] + n2[1] * n2[1] + n2[2] * n2[2]);
        double l3 = sqrt(n3[0] * n3[0] + n3[1] * n3[1] + n3[2] * n3[2]);
        if (fabs(det) <= 1e-9 * l1 * l2 * l3) return 0;
    }
    {
        double d1 = -a[3], d2 = -b[3], d3 = -c[3];
        double c31[3], c12[3];
        c31[0] = n3[1] * n1[2] - n3[2] * n1[1];
        c31[1] = n3[2] * n1[0] - n3[0] * n1[2];
        c31[2] = n3[0] * n1[1] - n3[1] * n1[0];
        c12[0] = n1[1] * n2[2] - n1[2] * n2[1];
        c12[1] = n1[2] * n2[0] - n1[0] * n2[2];
        c12[2] = n1[0] * n2[1] - n1[1] * n2[0];
        for (i = 0; i < 3; ++i) out[i] = (d1 * x[i] + d2 * c31[i] + d3 * c12[i]) / det;
    }
    return 1;
}

/* Bounds of a convex occluder by vertex enumeration, clipped to a box far larger than any vertex:
   a vertex on that box means the half-spaces are unbounded; no vertex means empty. */
PVS__STATIC pvs_result pvs__convex_bounds(const float *planes, uint32_t n, pvs_box *out, int64_t index, pvs_error *err) {
    float all[(PVS_MAX_OCCLUDER_PLANES + 6) * 4];
    double reach = 1.0, tol;
    uint32_t i, j, k, m, total, found = 0, on_guard = 0;
    pvs_box b = pvs__box_empty();
    for (i = 0; i < n; ++i) {
        const float *p = planes + 4 * i;
        double len = sqrt((double)p[0] * p[0] + (double)p[1] * p[1] + (double)p[2] * p[2]);
        if (!pvs__finite(p[0]) || !pvs__finite(p[1]) || !pvs__finite(p[2]) || !pvs__finite(p[3]))
            return pvs__fail(err, PVS_ERROR_NOT_FINITE, index, 0, "occluder %lld: plane %u is not finite", (long long)index, i);
        if (len == 0.0 || !(len < 1e30))
            return pvs__fail(err, PVS_ERROR_BAD_OCCLUDER, index, 0, "occluder %lld: plane %u has a zero normal", (long long)index, i);
        for (k = 0; k < 4; ++k) all[4 * i + k] = (float)(p[k] / len);
        if (fabs(p[3] / len) + 1.0 > reach) reach = fabs(p[3] / len) + 1.0;
    }
    /* Every vertex of a bounded polyhedron lies within sum of |d| ... bound it generously. */
    for (i = 0; i + 2 < n; ++i)
        for (j = i + 1; j + 1 < n; ++j)
            for (k = j + 1; k < n; ++k) {
                double v[3];
                if (pvs__three_planes(all + 4 * i, all + 4 * j, all + 4 * k, v)) {
                    double r = fabs(v[0]) + fabs(v[1]) + fabs(v[2]);
                    if (r < 1e30 && r + 1.0 > reach) reach = r + 1.0;
                }
            }
    reach *= 4.0;
    for (k = 0; k < 6; ++k) {
        float *g = all + 4 * (n + k);
        g[0] = g[1] = g[2] = 0.0f;
        g[k % 3] = k < 3 ? 1.0f : -1.0f;
        g[3] = (float)-reach;
    }
    total = n + 6;
    tol = 1e-5 * reach;
    for (i = 0; i + 2 < total; ++i)
        for (j = i + 1; j + 1 < total; ++j)
            for (k = j + 1; k < total; ++k) {
                double v[3];
                int inside = 1;
                if (!pvs__three_planes(all + 4 * i, all + 4 * j, all + 4 * k, v)) continue;
                for (m = 0; m < total && inside; ++m) {
                    const float *q = all + 4 * m;
                    if (q[0] * v[0] + q[1] * v[1] + q[2] * v[2] + q[3] > tol) inside = 0;
                }
                if (!inside) continue;
                ++found;
                if (k >= n) {
                    on_guard = 1;
                } else {
                    float f[3];
                    f[0] = (float)v[0]; f[1] = (float)v[1]; f[2] = (float)v[2];
                    pvs__box_add_point(&b, f);
                }
            }
    if (!found) return pvs__fail(err, PVS_ERROR_BAD_OCCLUDER, index, 0, "occluder %lld: the half-spaces are empty", (long long)index);
    if (on_guard) return pvs__fail(err, PVS_ERROR_BAD_OCCLUDER, index, 0, "occluder %lld: the half-spaces are unbounded", (long long)index);
    for (k = 0; k < 3; ++k)
        if (!(b.min[k] < b.max[k]))
            return pvs__fail(err, PVS_ERROR_BAD_OCCLUDER, index, 0, "occluder %lld: the volume is flat", (long long)index);
    *out = b;
    return PVS_OK;
}

/* 1 if segments p1-p2 and p3-p4 (2D) intersect or touch, in double precision. */
PVS__STATIC int pvs__segments_meet_2d(const float *p1, const float *p2, const float *p3, const float *p4) {
    double d1x = (double)p2[0] - p1[0], d1y = (double)p2[1] - p1[1];
    double d2x = (double)p4[0] - p3[0], d2y = (double)p4[1] - p3[1];
    double o1 = d1x * ((double)p3[1] - p1[1]) - d1y * ((double)p3[0] - p1[0]);
    double o2 = d1x * ((double)p4[1] - p1[1]) - d1y * ((double)p4[0] - p1[0]);
    double o3 = d2x * ((double)p1[1] - p3[1]) - d2y * ((double)p1[0] - p3[0]);
    double o4 = d2x * ((double)p2[1] - p3[1]) - d2y * ((double)p2[0] - p3[0]);
    if (((o1 > 0 && o2 < 0) || (o1 < 0 && o2 > 0)) && ((o3 > 0 && o4 < 0) || (o3 < 0 && o4 > 0))) return 1;
    if (o1 == 0 || o2 == 0 || o3 == 0 || o4 == 0) {
        /* collinear touching: compare bounding intervals */
        double ax0 = p1[0] < p2[0] ? p1[0] : p2[0], ax1 = p1[0] < p2[0] ? p2[0] : p1[0];
        double ay0 = p1[1] < p2[1] ? p1[1] : p2[1], ay1 = p1[1] < p2[1] ? p2[1] : p1[1];
        double bx0 = p3[0] < p4[0] ? p3[0] : p4[0], bx1 = p3[0] < p4[0] ? p4[0] : p3[0];
        double by0 = p3[1] < p4[1] ? p3[1] : p4[1], by1 = p3[1] < p4[1] ? p4[1] : p3[1];
        if ((o1 == 0 && p3[0] >= ax0 && p3[0] <= ax1 && p3[1] >= ay0 && p3[1] <= ay1) ||
            (o2 == 0 && p4[0] >= ax0 && p4[0] <= ax1 && p4[1] >= ay0 && p4[1] <= ay1) ||
            (o3 == 0 && p1[0] >= bx0 && p1[0] <= bx1 && p1[1] >= by0 && p1[1] <= by1) ||
            (o4 == 0 && p2[0] >= bx0 && p2[0] <= bx1 && p2[1] >= by0 && p2[1] <= by1))
            return 1;
    }
    return 0;
}

/* The two ground-plane axes for an up axis. */
PVS__STATIC void pvs__ground_axes(uint32_t up, int *u, int *v) {
    *u = 0;
    *v = up == 2 ? 1 : 2;
}

PVS__STATIC pvs_result pvs__validate_occluder(const pvs_occluder_desc *o, uint32_t up, int64_t index, pvs_box *box, pvs_error *err) {
    uint32_t i, j, n;
    switch (o->kind) {
    case PVS_OCCLUDER_BOX:
        for (i = 0; i < 3; ++i)
            if (!pvs__finite(o->box.min[i]) || !pvs__finite(o->box.max[i]))
                return pvs__fail(err, PVS_ERROR_NOT_FINITE, index, 0, "occluder %lld: box is not finite", (long long)index);
        for (i = 0; i < 3; ++i)
            if (!(o->box.min[i] < o->box.max[i]))
                return pvs__fail(err, PVS_ERROR_BAD_OCCLUDER, index, 0, "occluder %lld: box min >= max on axis %u", (long long)index, i);
        *box = o->box;
        return PVS_OK;
    case PVS_OCCLUDER_CONVEX:
        if (!o->planes || o->plane_count < 4 || o->plane_count > PVS_MAX_OCCLUDER_PLANES)
            return pvs__fail(err, PVS_ERROR_BAD_OCCLUDER, index, 0, "occluder %lld: convex needs 4..%d planes, has %u",
                             (long long)index, PVS_MAX_OCCLUDER_PLANES, o->plane_count);
        return pvs__convex_bounds(o->planes, o->plane_count, box, index, err);
    case PVS_OCCLUDER_EXTRUSION: {
        double area2 = 0.0;
        int u, v;
        n = o->footprint_count;
        if (!o->footprint || n < 3 || n > PVS_MAX_FOOTPRINT_POINTS)
            return pvs__fail(err, PVS_ERROR_BAD_OCCLUDER, index, 0, "occluder %lld: footprint needs 3..%d points, has %u",
                             (long long)index, PVS_MAX_FOOTPRINT_POINTS, n);
        if (!pvs__finite(o->base) || !pvs__finite(o->top))
            return pvs__fail(err, PVS_ERROR_NOT_FINITE, index, 0, "occluder %lld: base or top is not finite", (long long)index);
        if (!(o->base < o->top))
            return pvs__fail(err, PVS_ERROR_BAD_OCCLUDER, index, 0, "occluder %lld: base >= top", (long long)index);
        for (i = 0; i < 2 * n; ++i)
            if (!pvs__finite(o->footprint[i]))
                return pvs__fail(err, PVS_ERROR_NOT_FINITE, index, 0, "occluder %lld: footprint point %u is not finite",
                                 (long long)index, i / 2);
        for (i = 0; i < n; ++i) {
            const float *a = o->footprint + 2 * i, *b = o->footprint + 2 * ((i + 1) % n);
            area2 += (double)a[0] * b[1] - (double)b[0] * a[1];
            if (a[0] == b[0] && a[1] == b[1])
                return pvs__fail(err, PVS_ERROR_BAD_OCCLUDER, index, 0, "occluder %lld: footprint points %u and %u coincide",
                                 (long long)index, i, (i + 1) % n);
        }
        if (area2 == 0.0) return pvs__fail(err, PVS_ERROR_BAD_OCCLUDER, index, 0, "occluder %lld: footprint has zero area", (long long)index);
        for (i = 0; i < n; ++i)
            for (j = i + 2; j < n; ++j) {
                if (i == 0 && j == n - 1) continue; /* adjacent through the wrap */
                if (pvs__segments_meet_2d(o->footprint + 2 * i, o->footprint + 2 * ((i + 1) % n), o->footprint + 2 * j,
                                          o->footprint + 2 * ((j + 1) % n)))
                    return pvs__fail(err, PVS_ERROR_BAD_OCCLUDER, index, 0, "occluder %lld: footprint edges %u and %u cross",
                                     (long long)index, i, j);
            }
        pvs__ground_axes(up, &u, &v);
        *box = pvs__box_empty();
        for (i = 0; i < n; ++i) {
            float p[3];
            p[u] = o->footprint[2 * i];
            p[v] = o->footprint[2 * i + 1];
            p[up] = o->base;
            pvs__box_add_point(box, p);
            p[up] = o->top;
            pvs__box_add_point(box, p);
        }
        return PVS_OK;
    }
    default:
        return pvs__fail(err, PVS_ERROR_BAD_OCCLUDER, index, 0, "occluder %lld: unknown kind %d", (long long)index, (int)o->kind);
    }
}

PVS_API void pvs_scene_destroy(pvs_scene *s) {
    pvs_allocator a;
    if (!s) return;
    a = s->allocator;
    pvs_kdtree_destroy(s->triangle_tree);
    pvs_kdtree_destroy(s->object_tree);
    pvs__free_array(&a, s->triangle_corners, (size_t)s->triangle_count * 9, sizeof(float));
    pvs__free_array(&a, s->positions, (size_t)s->vertex_count * 3, sizeof(float));
    pvs__free_array(&a, s->indices, (size_t)s->triangle_count * 3, sizeof(uint32_t));
    pvs__free_array(&a, s->triangle_object, s->triangle_count, sizeof(uint32_t));
    pvs__free_array(&a, s->object_boxes, s->object_count, sizeof(pvs_box));
    pvs__free_array(&a, s->object_flags, s->object_count, sizeof(uint32_t));
    pvs__free_array(&a, s->object_triangles, (size_t)s->object_count * 2, sizeof(uint32_t));
    pvs__free_array(&a, s->occluders, s->occluder_count, sizeof(pvs_occluder_desc));
    pvs__free_array(&a, s->occluder_boxes, s->occluder_count, sizeof(pvs_box));
    pvs__free_array(&a, s->occluder_data, s->occluder_data_count, sizeof(float));
    pvs__free(&a, s, sizeof(*s), 16);
}

PVS_API pvs_result pvs_scene_create(const pvs_scene_desc *desc, pvs_scene **out, pvs_error *err) {
    pvs_scene *s;
    pvs_allocator a;
    pvs_result r;
    size_t n3, i, floats = 0;
    uint32_t t, o;
    pvs_box *tri_boxes = NULL;
    if (out) *out = NULL;
    if (!desc || !out) return pvs__fail(err, PVS_ERROR_INVALID_ARGUMENT, -1, 0, "desc and out_scene must not be NULL");
    if (desc->object_count == 0 || !desc->objects)
        return pvs__fail(err, PVS_ERROR_INVALID_ARGUMENT, -1, 0, "the scene has no objects");
    if (desc->triangle_count && (!desc->indices || !desc->positions))
        return pvs__fail(err, PVS_ERROR_INVALID_ARGUMENT, -1, 0, "indices and positions must not be NULL");
    if (desc->occluder_count && !desc->occluders)
        return pvs__fail(err, PVS_ERROR_INVALID_ARGUMENT, -1, 0, "occluders must not be NULL when occluder_count > 0");
    if (desc->up_axis > 2) return pvs__fail(err, PVS_ERROR_INVALID_ARGUMENT, -1, 0, "up_axis %u is not 0, 1 or 2", desc->up_axis);
    if (desc->triangle_count > 0xfffffffeu / 3 || desc->vertex_count == 0xffffffffu || desc->object_count == 0xffffffffu)
        return pvs__fail(err, PVS_ERROR_COUNT_OVERFLOW, -1, 0, "more than 2^32 - 2 triangle indices, vertices or objects");
    if (!pvs__mul(desc->vertex_count, 3 * sizeof(float), &n3) || !pvs__mul(desc->triangle_count, 3 * sizeof(uint32_t), &n3) ||
        !pvs__mul(desc->triangle_count, sizeof(pvs_box), &n3))
        return pvs__fail(err, PVS_ERROR_COUNT_OVERFLOW, -1, 0, "the arrays do not fit in memory");

    /* validate before allocating: vertices, indices, object ranges */
    for (i = 0; i < (size_t)desc->vertex_count * 3; ++i)
        if (!pvs__finite(desc->positions[i]))
            return pvs__fail(err, PVS_ERROR_NOT_FINITE, (int64_t)(i / 3), 0, "vertex %llu has a coordinate that is not finite",
                             (unsigned long long)(i / 3));
    for (i = 0; i < (size_t)desc->triangle_count * 3; ++i)
        if (desc->indices[i] >= desc->vertex_count)
            return pvs__fail(err, PVS_ERROR_INDEX_OUT_OF_RANGE, (int64_t)(i / 3), 0,
                             "triangle %llu uses vertex %u but there are %u vertices", (unsigned long long)(i / 3),
                             desc->indices[i], desc->vertex_count);
    for (o = 0; o < desc->object_count; ++o) {
        const pvs_object_desc *ob = desc->objects + o;
        if (ob->first_triangle > desc->triangle_count || ob->triangle_count > desc->triangle_count - ob->first_triangle)
            return pvs__fail(err, PVS_ERROR_INDEX_OUT_OF_RANGE, o, 0, "object %u: triangles %u..%u are past the %u triangles", o,
                             ob->first_triangle, ob->first_triangle + ob->triangle_count, desc->triangle_count);
        if (ob->triangle_count == 0 && !(desc->flags & PVS_SCENE_ALLOW_EMPTY_OBJECTS))
            return pvs__fail(err, PVS_ERROR_EMPTY_OBJECT, o, 0, "object %u has no triangles", o);
    }
    for (o = 0; o < desc->occluder_count; ++o) {
        const pvs_occluder_desc *oc = desc->occluders + o;
        if (oc->kind == PVS_OCCLUDER_CONVEX && oc->plane_count <= PVS_MAX_OCCLUDER_PLANES) floats += 4 * (size_t)oc->plane_count;
        if (oc->kind == PVS_OCCLUDER_EXTRUSION && oc->footprint_count <= PVS_MAX_FOOTPRINT_POINTS)
            floats += 2 * (size_t)oc->footprint_count;
    }

    a = desc->allocator;
    s = (pvs_scene *)pvs__alloc(&a, sizeof(pvs_scene), 16);
    if (!s) return pvs__fail(err, PVS_ERROR_OUT_OF_MEMORY, -1, 0, "scene");
    memset(s, 0, sizeof(*s));
    s->allocator = a;
    s->up_axis = desc->up_axis == 2 ? 2 : 1;
    s->flags = desc->flags;
    s->vertex_count = desc->vertex_count;
    s->triangle_count = desc->triangle_count;
    s->object_count = desc->object_count;
    s->occluder_count = desc->occluder_count;
    s->occluder_data_count = floats;
    s->positions = (float *)pvs__alloc_array(&a, (size_t)desc->vertex_count * 3, sizeof(float));
    s->indices = (uint32_t *)pvs__alloc_array(&a, (size_t)desc->triangle_count * 3, sizeof(uint32_t));
    s->triangle_object = (uint32_t *)pvs__alloc_array(&a, desc->triangle_count, sizeof(uint32_t));
    s->object_boxes = (pvs_box *)pvs__alloc_array(&a, desc->object_count, sizeof(pvs_box));
    s->object_flags = (uint32_t *)pvs__alloc_array(&a, desc->object_count, sizeof(uint32_t));
    s->object_triangles = (uint32_t *)pvs__alloc_array(&a, (size_t)desc->object_count * 2, sizeof(uint32_t));
    s->occluders = (pvs_occluder_desc *)pvs__alloc_array(&a, desc->occluder_count, sizeof(pvs_occluder_desc));
    s->occluder_boxes = (pvs_box *)pvs__alloc_array(&a, desc->occluder_count, sizeof(pvs_box));
    s->occluder_data = (float *)pvs__alloc_array(&a, floats, sizeof(float));
    tri_boxes = (pvs_box *)pvs__alloc_array(&a, desc->triangle_count, sizeof(pvs_box));
    if (!s->positions || !s->indices || !s->triangle_object || !s->object_boxes || !s->object_flags || !s->object_triangles || !s->occluders ||
        !s->occluder_boxes || !s->occluder_data || !tri_boxes) {
        r = pvs__fail(err, PVS_ERROR_OUT_OF_MEMORY, -1, 0, "scene arrays");
        goto fail;
    }
    if (desc->vertex_count) memcpy(s->positions, desc->positions, (size_t)desc->vertex_count * 3 * sizeof(float));
    if (desc->triangle_count) memcpy(s->indices, desc->indices, (size_t)desc->triangle_count * 3 * sizeof(uint32_t));
    for (t = 0; t < desc->triangle_count; ++t) s->triangle_object[t] = PVS_NO_OBJECT;
    s->bounds = pvs__box_empty();

    for (o = 0; o < desc->object_count; ++o) {
        const pvs_object_desc *ob = desc->objects + o;
        int any_area = 0;
        s->object_flags[o] = ob->flags;
        s->object_triangles[2 * (size_t)o] = ob->first_triangle;
        s->object_triangles[2 * (size_t)o + 1] = ob->triangle_count;
        s->object_boxes[o] = pvs__box_empty();
        for (t = ob->first_triangle; t < ob->first_triangle + ob->triangle_count; ++t) {
            const uint32_t *tri = s->indices + 3 * (size_t)t;
            pvs__v3 p0 = pvs__v3_load(s->positions + 3 * (size_t)tri[0]);
            pvs__v3 p1 = pvs__v3_load(s->positions + 3 * (size_t)tri[1]);
            pvs__v3 p2 = pvs__v3_load(s->positions + 3 * (size_t)tri[2]);
            double e1[3], e2[3], c[3];
            if (s->triangle_object[t] != PVS_NO_OBJECT) {
                r = pvs__fail(err, PVS_ERROR_OVERLAPPING_OBJECTS, o, 0, "objects %u and %u both claim triangle %u",
                              s->triangle_object[t], o, t);
                goto fail;
            }
            s->triangle_object[t] = o;
            e1[0] = (double)p1.x - p0.x; e1[1] = (double)p1.y - p0.y; e1[2] = (double)p1.z - p0.z;
            e2[0] = (double)p2.x - p0.x; e2[1] = (double)p2.y - p0.y; e2[2] = (double)p2.z - p0.z;
            c[0] = e1[1] * e2[2] - e1[2] * e2[1];
            c[1] = e1[2] * e2[0] - e1[0] * e2[2];
            c[2] = e1[0] * e2[1] - e1[1] * e2[0];
            if (c[0] != 0.0 || c[1] != 0.0 || c[2] != 0.0) any_area = 1;
            pvs__box_add_point(&s->object_boxes[o], s->positions + 3 * (size_t)tri[0]);
            pvs__box_add_point(&s->object_boxes[o], s->positions + 3 * (size_t)tri[1]);
            pvs__box_add_point(&s->object_boxes[o], s->positions + 3 * (size_t)tri[2]);
        }
        if (!any_area && ob->triangle_count && !(desc->flags & PVS_SCENE_ALLOW_EMPTY_OBJECTS)) {
            r = pvs__fail(err, PVS_ERROR_DEGENERATE_OBJECT, o, 0, "object %u: all %u triangles have zero area", o, ob->triangle_count);
            goto fail;
        }
        if (!any_area) s->object_boxes[o] = pvs__box_empty(); /* never visible: nothing to see */
    }
    for (t = 0; t < desc->triangle_count; ++t) {
        const uint32_t *tri = s->indices + 3 * (size_t)t;
        tri_boxes[t] = pvs__box_empty();
        pvs__box_add_point(&tri_boxes[t], s->positions + 3 * (size_t)tri[0]);
        pvs__box_add_point(&tri_boxes[t], s->positions + 3 * (size_t)tri[1]);
        pvs__box_add_point(&tri_boxes[t], s->positions + 3 * (size_t)tri[2]);
        pvs__box_add_box(&s->bounds, &tri_boxes[t]);
    }

    floats = 0;
    for (o = 0; o < desc->occluder_count; ++o) {
        pvs_occluder_desc *dst = s->occluders + o;
        r = pvs__validate_occluder(desc->occluders + o, s->up_axis, o, &s->occluder_boxes[o], err);
        if (r != PVS_OK) goto fail;
        *dst = desc->occluders[o];
        if (dst->kind == PVS_OCCLUDER_CONVEX) {
            memcpy(s->occluder_data + floats, dst->planes, 4 * (size_t)dst->plane_count * sizeof(float));
            dst->planes = s->occluder_data + floats;
            floats += 4 * (size_t)dst->plane_count;
        } else {
            dst->planes = NULL;
            dst->plane_count = 0;
        }
        if (dst->kind == PVS_OCCLUDER_EXTRUSION) {
            memcpy(s->occluder_data + floats, dst->footprint, 2 * (size_t)dst->footprint_count * sizeof(float));
            dst->footprint = s->occluder_data + floats;
            floats += 2 * (size_t)dst->footprint_count;
        } else {
            dst->footprint = NULL;
            dst->footprint_count = 0;
        }
        pvs__box_add_box(&s->bounds, &s->occluder_boxes[o]);
    }
    if (s->bounds.min[0] > s->bounds.max[0]) {
        r = pvs__fail(err, PVS_ERROR_EMPTY_OBJECT, -1, 0, "the scene has no geometry");
        goto fail;
    }

    r = pvs__scene_prepare_rays(s, tri_boxes, err);
    if (r != PVS_OK) goto fail;
    {
        pvs_kdtree_desc kd;
        memset(&kd, 0, sizeof(kd));
        kd.allocator = a;
        kd.boxes = tri_boxes;
        kd.count = desc->triangle_count;
        kd.leaf_size = desc->leaf_size;
        r = pvs_kdtree_create(&kd, &s->triangle_tree, err);
        if (r != PVS_OK) goto fail;
        kd.boxes = s->object_boxes;
        kd.count = desc->object_count;
        kd.leaf_size = 0;
        r = pvs_kdtree_create(&kd, &s->object_tree, err);
        if (r != PVS_OK) goto fail;
    }
    pvs__free_array(&a, tri_boxes, desc->triangle_count, sizeof(pvs_box));
    *out = s;
    pvs__ok(err);
    return PVS_OK;
fail:
    pvs__free_array(&a, tri_boxes, desc->triangle_count, sizeof(pvs_box));
    pvs_scene_destroy(s);
    return r;
}

PVS_API uint32_t pvs_scene_object_count(const pvs_scene *s) { return s->object_count; }
PVS_API uint32_t pvs_scene_triangle_count(const pvs_scene *s) { return s->triangle_count; }
PVS_API uint32_t pvs_scene_occluder_count(const pvs_scene *s) { return s->occluder_count; }
PVS_API uint32_t pvs_scene_up_axis(const pvs_scene *s) { return s->up_axis; }
PVS_API pvs_box pvs_scene_bounds(const pvs_scene *s) { return s->bounds; }
PVS_API pvs_box pvs_scene_object_box(const pvs_scene *s, uint32_t object) {
    PVS_ASSERT(object < s->object_count);
    return s->object_boxes[object];
}
PVS_API uint32_t pvs_scene_object_flags(const pvs_scene *s, uint32_t object) {
    PVS_ASSERT(object < s->object_count);
    return s->object_flags[object];
}
PVS_API uint32_t pvs_scene_triangle_object(const pvs_scene *s, uint32_t triangle) {
    PVS_ASSERT(triangle < s->triangle_count);
    return s->triangle_object[triangle];
}
PVS_API const pvs_occluder_desc *pvs_scene_occluder(const pvs_scene *s, uint32_t i) {
    PVS_ASSERT(i < s->occluder_count);
    return s->occluders + i;
}

/* The scene's 2.5D facades (shared by the 2.5D methods, >>bake OTREE and >>vocc): pairs of
   consecutive triangles that form a vertical rectangle (two ground positions x two heights, split
   along a diagonal) whose bottom is at or below the lowest point of the scene, so it certainly
   blocks every height from the ground to its top. Anything else is left out (never blocks:
   conservative). Writes *count facades of 6 floats (u0 v0 u1 v1 top bottom) in triangle order into
   a new array *out (6 * count + 6 floats, through allocator a; NULL on failure). */
PVS__STATIC pvs_result pvs__scene_facades(const pvs_scene *s, const pvs_allocator *a, float **out, uint32_t *count) {
    int up = s->up_axis == 2 ? 2 : 1, u = 0, v = up == 2 ? 1 : 2;
    float ground = s->bounds.min[up];
    uint32_t t, n = 0, pass, i = 0;
    *out = NULL;
    *count = 0;
    for (pass = 0; pass < 2; ++pass) {
        n = 0;
        for (t = 0; t + 1 < s->triangle_count; ++t) {
            const float *c[6];
            float pu[2], pv[2], h[2];
            int np = 0, nh = 0, k, m, shared = 0, diag = 1;
            for (k = 0; k < 6; ++k) c[k] = s->positions + 3 * (size_t)s->indices[3 * (size_t)(t + (uint32_t)(k / 3)) + (uint32_t)(k % 3)];
            for (k = 0; k < 6 && np <= 2 && nh <= 2; ++k) {
                for (m = 0; m < np; ++m) if (pu[m] == c[k][u] && pv[m] == c[k][v]) break;
                if (m == np) { if (np < 2) { pu[np] = c[k][u]; pv[np] = c[k][v]; } ++np; }
                for (m = 0; m < nh; ++m) if (h[m] == c[k][up]) break;
                if (m == nh) { if (nh < 2) h[nh] = c[k][up]; ++nh; }
            }
            if (np != 2 || nh != 2) continue;
            /* each triangle has three distinct corners; they share exactly two, on a diagonal */
            for (k = 0; k < 3; ++k)
                if (c[k] == c[(k + 1) % 3] || c[3 + k] == c[3 + (k + 1) % 3] ||
                    !memcmp(c[k], c[(k + 1) % 3], 12) || !memcmp(c[3 + k], c[3 + (k + 1) % 3], 12)) break;
            if (k < 3) continue;
            for (k = 0; k < 3; ++k)
                for (m = 3; m < 6; ++m)
                    if (!memcmp(c[k], c[m], 12)) {
                        ++shared;
                        if (shared == 1) i = (uint32_t)k; else {
                            const float *p0 = c[i], *p1 = c[k];
                            diag = (p0[u] != p1[u] || p0[v] != p1[v]) && p0[up] != p1[up];
                        }
                    }
            if (shared != 2 || !diag) continue;
            {
                float lo = h[0] < h[1] ? h[0] : h[1], hi = h[0] < h[1] ? h[1] : h[0];
                if (!(lo <= ground)) continue;
                if (pass) {
                    float *f = *out + 6 * (size_t)n;
                    f[0] = pu[0]; f[1] = pv[0]; f[2] = pu[1]; f[3] = pv[1]; f[4] = hi; f[5] = lo;
                }
            }
            ++n;
            ++t; /* the pair is used up */
        }
        if (!pass) {
            *out = (float *)pvs__alloc_array(a, (size_t)n * 6 + 6, sizeof(float));
            if (!*out) return PVS_ERROR_OUT_OF_MEMORY;
        }
    }
    *count = n;
    return PVS_OK;
}

// >>kdtree
/* ---------------------------------------------------------------------------------------------- */
/* kdtree: binned-SAH build over boxes; sweep (Bittner 2002 §3.2); ray walk; point location;     */
/* scene ray casts                                                                                */
/* ---------------------------------------------------------------------------------------------- */

/* Layout. A node is 8 bytes: `bits` holds the axis in its low 2 bits (3 = leaf) and an index above
   them; an inner node's index is its left child (the right child follows it), a leaf's index is the
   offset of its item list in `items`, and the union holds the split plane or the leaf's item count.
   Node 0 is the root. Every inner node has two children, so a tree of N nodes has (N + 1) / 2 leaves.
   Items are referenced from every leaf whose closed cell box overlaps their closed box: a point on a
   split plane finds every box touching it on either side. */
#define PVS__KD_BINS 32                 /* SAH candidate planes per axis: PVS__KD_BINS - 1 */
#define PVS__KD_SAMPLE 256            /* most refs binned per node (an even stride through bigger ones) */
#define PVS__KD_LEAF 3u                 /* axis value of a leaf */
#define PVS__KD_MAX_INDEX 0x3fffffffu   /* largest child index or item offset in 30 bits */
#define PVS__KD_COST_TRAVERSE 1.0f      /* SAH cost of one inner node ... */
#define PVS__KD_COST_ITEM 1.5f          /* ... and of one item test */
#define PVS__KD_EMPTY_BONUS 0.8f        /* factor for splits that cut off empty space */
#define PVS__KD_RAY_TOL 1e-7            /* leaf t-intervals widen by this fraction of coordinate size */

typedef struct pvs__kdnode {
    union {
        float split;     /* inner node */
        uint32_t count;  /* leaf: number of items */
    } u;
    uint32_t bits;       /* (index << 2) | axis */
} pvs__kdnode;

struct pvs_kdtree {
    pvs_allocator allocator;
    pvs_box bounds;          /* of the non-empty item boxes; the empty box when there are none */
    pvs__kdnode *nodes;
    uint32_t *items;         /* leaf item lists, one after another */
    uint32_t node_count, item_count;
    size_t node_capacity, item_capacity;
};

/* An item reference during the build: the item's box clipped to the node's cell. */
typedef struct pvs__kdref {
    float min[3], max[3];
    uint32_t item;
} pvs__kdref;

typedef struct pvs__kdbuild {
    pvs_kdtree *tree;
    pvs__kdref *refs;        /* a stack: the node being split is on top, pending left children below */
    size_t ref_capacity;
    uint32_t leaf_size, max_depth;
    pvs_error *err;
    float planes[3][PVS__KD_BINS + 1];    /* candidate planes of the node being split */
    uint32_t starts[3][PVS__KD_BINS + 1]; /* [s]: refs whose min is <= planes[s] first */
    uint32_t ends[3][PVS__KD_BINS + 1];   /* [e]: refs whose max is >= planes[e] last */
} pvs__kdbuild;

/* Grows an array of `elem`-byte elements to hold at least `need`, keeping the first `used`. Returns
   the (possibly new) array, or NULL with *r set (the old array is then still owned by the caller). */
PVS__STATIC void *pvs__kd_grow(const pvs_allocator *a, void *p, size_t *capacity, size_t used, size_t need, size_t elem,
                          pvs_result *r) {
    size_t cap = *capacity ? *capacity : 64, bytes;
    void *q;
    if (need <= *capacity) return p;
    while (cap < need) {
        if (cap > (size_t)-1 / 2) { *r = PVS_ERROR_COUNT_OVERFLOW; return NULL; }
        cap *= 2;
    }
    if (!pvs__mul(cap, elem, &bytes)) { *r = PVS_ERROR_COUNT_OVERFLOW; return NULL; }
    q = pvs__alloc_array(a, cap, elem);
    if (!q) { *r = PVS_ERROR_OUT_OF_MEMORY; return NULL; }
    if (used) memcpy(q, p, used * elem);
    pvs__free_array(a, p, *capacity, elem);
    *capacity = cap;
    return q;
}

PVS__STATIC pvs_result pvs__kd_make_leaf(pvs__kdbuild *b, uint32_t node, size_t base, size_t n) {
    pvs_kdtree *t = b->tree;
    pvs_result r = PVS_OK;
    size_t i;
    uint32_t *items;
    if (t->item_count > PVS__KD_MAX_INDEX || n > (size_t)0xffffffffu - t->item_count)
        return pvs__fail(b->err, PVS_ERROR_COUNT_OVERFLOW, -1, 0, "kD-tree: more than 2^30 item references");
    items = (uint32_t *)pvs__kd_grow(&t->allocator, t->items, &t->item_capacity, t->item_count, t->item_count + n,
                                     sizeof(uint32_t), &r);
    if (!items) return pvs__fail(b->err, r, -1, 0, "kD-tree leaf items (%llu)", (unsigned long long)(t->item_count + n));
    t->items = items;
    for (i = 0; i < n; ++i) items[t->item_count + i] = b->refs[base + i].item;
    t->nodes[node].u.count = (uint32_t)n;
    t->nodes[node].bits = (n ? t->item_count << 2 : 0u) | PVS__KD_LEAF;
    t->item_count += (uint32_t)n;
    return PVS_OK;
}

/* Splits node `node` (its refs are refs[base .. base + n), on top of the stack, its cell is `box`) or
   makes it a leaf. Binned SAH over all three axes (Bittner 2002 §4.4 uses SAH or fewest cut objects;
   binning after Wald 2007): up to 31 planes per axis, fewer in small nodes. The counts are exact for
   the closed-interval distribution below (up to sampling in big nodes), so straddlers and boxes
   lying in a plane are costed as they will be stored. */
PVS__STATIC pvs_result pvs__kd_build(pvs__kdbuild *b, uint32_t node, size_t base, size_t n, const pvs_box *box, uint32_t depth) {
    pvs_kdtree *t = b->tree;
    float ext[3], k0[3], k1[3], scale[3], inv_measure, inv_nb, best_cost, count_scale, split;
    int axis, best_axis = -1, best_k = 0, area, nb, valid[3];
    size_t i, j, w, top, sampled;
    uint32_t child;
    pvs_result r = PVS_OK;
    pvs_box lbox, rbox;
    if (n <= b->leaf_size || depth >= b->max_depth) return pvs__kd_make_leaf(b, node, base, n);

    /* the SAH measure of a box is linear in its extent along one axis: k1[axis] * extent + k0[axis];
       half the surface area, or the edge sum for boxes with no area */
    for (axis = 0; axis < 3; ++axis) ext[axis] = box->max[axis] - box->min[axis];
    area = ext[0] * ext[1] + ext[1] * ext[2] + ext[2] * ext[0] > 0.0f;
    for (axis = 0; axis < 3; ++axis) {
        float eb = ext[(axis + 1) % 3], ec = ext[(axis + 2) % 3];
        k1[axis] = area ? eb + ec : 1.0f;
        k0[axis] = area ? eb * ec : eb + ec;
    }
    inv_measure = 1.0f / (k1[0] * ext[0] + k0[0]);
    if (!(inv_measure > 0.0f && inv_measure < FLT_MAX)) return pvs__kd_make_leaf(b, node, base, n);

    /* planes[a][1 .. nb-1] are the candidates; [0] = -inf and [nb] = +inf bound the searches below */
    nb = n <= 16 ? 8 : n <= 64 ? 16 : PVS__KD_BINS;
    inv_nb = 1.0f / (float)nb;
    for (axis = 0; axis < 3; ++axis) {
        float lo = box->min[axis], width = ext[axis];
        int k;
        scale[axis] = (float)nb / width; /* +inf when width is 0 or tiny: not a split axis */
        valid[axis] = scale[axis] < FLT_MAX;
        if (!valid[axis]) scale[axis] = 0.0f;
        for (k = 0; k <= nb; ++k) b->starts[axis][k] = b->ends[axis][k] = 0;
        for (k = 1; k < nb; ++k) b->planes[axis][k] = lo + width * ((float)k * inv_nb); /* k / nb exactly */
        b->planes[axis][0] = -INFINITY;
        b->planes[axis][nb] = INFINITY;
    }
    /* big nodes bin an evenly strided sample of PVS__KD_SAMPLE refs: the plane barely changes */
    sampled = n > PVS__KD_SAMPLE ? PVS__KD_SAMPLE : n;
    for (j = 0; j < sampled; ++j) {
        const pvs__kdref *ref = b->refs + base + (sampled == n ? j : (size_t)((uint64_t)j * n / sampled));
        for (axis = 0; axis < 3; ++axis) {
            const float *pl = b->planes[axis];
            float lo = box->min[axis], mn = ref->min[axis], mx = ref->max[axis];
            int s, e;
            /* s = the first k in 1..nb with mn <= planes[k]; e = the last k in 0..nb-1 with mx >= planes[k].
               The refs lie in the cell, so the bin estimates are in [0, nb] and off by at most one
               near a plane: one exact comparison each way fixes them. */
            s = (int)((mn - lo) * scale[axis]);
            e = (int)((mx - lo) * scale[axis]);
            s = s < nb - 1 ? s : nb - 1;
            e = e < nb - 1 ? e : nb - 1;
            s = s + 1 - (mn <= pl[s]) + (mn > pl[s + 1]);
            e = e + (mx >= pl[e + 1]) - (mx < pl[e]);
            ++b->starts[axis][s];
            ++b->ends[axis][e];
        }
    }

    /* cost of each inner plane; ties keep the first (lowest axis, then lowest plane): deterministic */
    best_cost = PVS__KD_COST_ITEM * (float)n;
    count_scale = (float)n / (float)sampled;
    for (axis = 0; axis < 3; ++axis) {
        uint32_t left = 0, right = (uint32_t)sampled - b->ends[axis][0];
        int k;
        if (!valid[axis]) continue;
        for (k = 1; k < nb; ++k) {
            float p = b->planes[axis][k], cost;
            left += b->starts[axis][k];
            if (k > 1) right -= b->ends[axis][k - 1];
            if (!(p > box->min[axis] && p < box->max[axis])) continue;
            cost = PVS__KD_COST_TRAVERSE +
                   PVS__KD_COST_ITEM * inv_measure * count_scale *
                       ((k1[axis] * (p - box->min[axis]) + k0[axis]) * (float)left +
                        (k1[axis] * (box->max[axis] - p) + k0[axis]) * (float)right);
            if (left == 0 || right == 0) cost *= PVS__KD_EMPTY_BONUS;
            if (cost < best_cost) {
                best_cost = cost;
                best_axis = axis;
                best_k = k;
            }
        }
    }
    if (best_axis < 0) return pvs__kd_make_leaf(b, node, base, n);
    axis = best_axis;
    split = b->planes[axis][best_k];

    /* distribute with closed intervals: a ref touching the plane goes to both sides, clipped. The
       left refs are compacted in place, the right ones written above the node's: right of base + n. */
    {
        pvs__kdref *refs = (pvs__kdref *)pvs__kd_grow(&t->allocator, b->refs, &b->ref_capacity, base + n, base + 2 * n,
                                                      sizeof(pvs__kdref), &r);
        if (!refs) return pvs__fail(b->err, r, -1, 0, "kD-tree build references");
        b->refs = refs;
    }
    for (i = 0, w = base, top = base + n; i < n; ++i) {
        const pvs__kdref *src = b->refs + base + i;
        float mn = src->min[axis], mx = src->max[axis];
        int to_left = mn <= split, to_right = mx >= split;
        /* both slots are free whether or not they are kept: write, then advance (no branches; the
           clipped coordinate is stored last, so no wide load waits on a narrow store) */
        b->refs[top] = *src;
        b->refs[top].min[axis] = mn < split ? split : mn;
        top += (size_t)to_right;
        if (w != base + i) b->refs[w] = *src;
        b->refs[w].max[axis] = mx > split ? split : mx;
        w += (size_t)to_left;
    }

    if (t->node_count > PVS__KD_MAX_INDEX - 1)
        return pvs__fail(b->err, PVS_ERROR_COUNT_OVERFLOW, -1, 0, "kD-tree: more than 2^30 nodes");
    {
        pvs__kdnode *nodes = (pvs__kdnode *)pvs__kd_grow(&t->allocator, t->nodes, &t->node_capacity, t->node_count,
                                                         (size_t)t->node_count + 2, sizeof(pvs__kdnode), &r);
        if (!nodes) return pvs__fail(b->err, r, -1, 0, "kD-tree nodes (%u)", t->node_count + 2);
        t->nodes = nodes;
    }
    child = t->node_count;
    t->node_count += 2;
    t->nodes[node].u.split = split;
    t->nodes[node].bits = (child << 2) | (uint32_t)axis;
    lbox = *box;
    rbox = *box;
    lbox.max[axis] = split;
    rbox.min[axis] = split;
    /* the right refs are on top of the stack: build them first, then the left ones below */
    r = pvs__kd_build(b, child + 1, base + n, top - (base + n), &rbox, depth + 1);
    if (r != PVS_OK) return r;
    return pvs__kd_build(b, child, base, w - base, &lbox, depth + 1);
}

PVS_API void pvs_kdtree_destroy(pvs_kdtree *t) {
    pvs_allocator a;
    if (!t) return;
    a = t->allocator;
    pvs__free_array(&a, t->nodes, t->node_capacity, sizeof(pvs__kdnode));
    pvs__free_array(&a, t->items, t->item_capacity, sizeof(uint32_t));
    pvs__free(&a, t, sizeof(*t), 16);
}

PVS_API pvs_result pvs_kdtree_create(const pvs_kdtree_desc *desc, pvs_kdtree **out, pvs_error *err) {
    pvs_kdtree *t;
    pvs__kdbuild *b = NULL;
    pvs_allocator a;
    pvs_result r = PVS_OK;
    uint32_t i, m = 0, lg = 0;
    if (out) *out = NULL;
    if (!desc || !out) return pvs__fail(err, PVS_ERROR_INVALID_ARGUMENT, -1, 0, "desc and out_tree must not be NULL");
    if (desc->count && !desc->boxes) return pvs__fail(err, PVS_ERROR_INVALID_ARGUMENT, -1, 0, "boxes must not be NULL");
    for (i = 0; i < desc->count; ++i) {
        const pvs_box *bx = desc->boxes + i;
        int k, empty = 0;
        for (k = 0; k < 3; ++k) {
            if (!pvs__finite(bx->min[k]) || !pvs__finite(bx->max[k]))
                return pvs__fail(err, PVS_ERROR_NOT_FINITE, i, 0, "kD-tree box %u has a coordinate that is not finite", i);
            if (bx->min[k] > bx->max[k]) empty = 1;
        }
        m += !empty;
    }
    a = desc->allocator;
    t = (pvs_kdtree *)pvs__alloc(&a, sizeof(pvs_kdtree), 16);
    if (!t) return pvs__fail(err, PVS_ERROR_OUT_OF_MEMORY, -1, 0, "kD-tree");
    memset(t, 0, sizeof(*t));
    t->allocator = a;
    t->bounds = pvs__box_empty();
    b = (pvs__kdbuild *)pvs__alloc(&a, sizeof(pvs__kdbuild), 16);
    if (!b) { r = pvs__fail(err, PVS_ERROR_OUT_OF_MEMORY, -1, 0, "kD-tree builder"); goto done; }
    memset(b, 0, sizeof(*b));
    b->tree = t;
    b->err = err;
    b->leaf_size = desc->leaf_size ? desc->leaf_size : 4;
    while (lg < 31 && ((uint32_t)2 << lg) <= m) ++lg; /* floor(log2 m) */
    b->max_depth = desc->max_depth ? desc->max_depth : 8 + (13 * lg + 9) / 10;
    if (b->max_depth > PVS_KDTREE_MAX_DEPTH) b->max_depth = PVS_KDTREE_MAX_DEPTH;

    /* first guesses; everything grows on demand */
    t->nodes = (pvs__kdnode *)pvs__kd_grow(&a, NULL, &t->node_capacity, 0, 1 + (size_t)m / 2, sizeof(pvs__kdnode), &r);
    if (t->nodes) t->items = (uint32_t *)pvs__kd_grow(&a, NULL, &t->item_capacity, 0, 1 + (size_t)m + m / 2, sizeof(uint32_t), &r);
    if (t->items) b->refs = (pvs__kdref *)pvs__kd_grow(&a, NULL, &b->ref_capacity, 0, 1 + (size_t)m + m / 2, sizeof(pvs__kdref), &r);
    if (!b->refs) { r = pvs__fail(err, r, -1, 0, "kD-tree arrays for %u boxes", m); goto done; }
    m = 0;
    for (i = 0; i < desc->count; ++i) {
        const pvs_box *bx = desc->boxes + i;
        if (bx->min[0] > bx->max[0] || bx->min[1] > bx->max[1] || bx->min[2] > bx->max[2]) continue;
        memcpy(b->refs[m].min, bx->min, sizeof(bx->min));
        memcpy(b->refs[m].max, bx->max, sizeof(bx->max));
        b->refs[m].item = i;
        pvs__box_add_box(&t->bounds, bx);
        ++m;
    }
    t->node_count = 1;
    r = pvs__kd_build(b, 0, 0, m, &t->bounds, 0);
done:
    if (b) {
        pvs__free_array(&a, b->refs, b->ref_capacity, sizeof(pvs__kdref));
        pvs__free(&a, b, sizeof(*b), 16);
    }
    if (r != PVS_OK) {
        pvs_kdtree_destroy(t);
        return r;
    }
    *out = t;
    pvs__ok(err);
    return PVS_OK;
}

PVS_API pvs_box pvs_kdtree_bounds(const pvs_kdtree *t) { return t->bounds; }
PVS_API uint32_t pvs_kdtree_node_count(const pvs_kdtree *t) { return t->node_count; }

/* ---- sweep ---- */

typedef struct pvs__kdsweep {
    float d2;         /* squared minimum distance from the source */
    uint32_t node;
    pvs_box box;      /* the node's cell */
} pvs__kdsweep;

PVS__STATIC int pvs__kdsweep_before(const pvs__kdsweep *a, const pvs__kdsweep *b) {
    return a->d2 < b->d2 || (a->d2 == b->d2 && a->node < b->node);
}

/* The heap only ever holds nodes none of which is an ancestor of another (popping a node pushes its
   children), and such a set has at most as many nodes as the tree has leaves. */
PVS_API size_t pvs_kdtree_sweep_scratch_size(const pvs_kdtree *t) {
    return ((size_t)t->node_count + 1) / 2 * sizeof(pvs__kdsweep);
}

/* Bittner 2002 §3.2 (approximate occlusion sweep): a priority queue on the nodes' minimum distance
   to the source. A child's cell lies inside its parent's, so its distance is never smaller and the
   visit order is non-decreasing in distance. */
PVS_API pvs_result pvs_kdtree_sweep(const pvs_kdtree *t, const pvs_box *source, void *scratch, size_t scratch_size,
                                    pvs_kdtree_visit_fn visit, void *user) {
    pvs__kdsweep *heap = (pvs__kdsweep *)scratch;
    size_t n = 0, cap;
    int k;
    if (!t || !source || !visit) return PVS_ERROR_INVALID_ARGUMENT;
    for (k = 0; k < 3; ++k)
        if (!pvs__finite(source->min[k]) || !pvs__finite(source->max[k])) return PVS_ERROR_NOT_FINITE;
    if (t->bounds.min[0] > t->bounds.max[0]) return PVS_OK; /* no items: nothing to visit */
    cap = scratch ? scratch_size / sizeof(pvs__kdsweep) : 0;
    if (cap < ((size_t)t->node_count + 1) / 2) return PVS_ERROR_BUFFER_TOO_SMALL;
    heap[0].d2 = pvs__box_distance2(source, &t->bounds);
    heap[0].node = 0;
    heap[0].box = t->bounds;
    n = 1;
    while (n) {
        pvs__kdsweep top = heap[0];
        const pvs__kdnode *nd = t->nodes + top.node;
        uint32_t axis = nd->bits & 3u;
        pvs_visit v;
        size_t i, c;
        /* pop: move the last entry down from the root */
        --n;
        if (n) {
            pvs__kdsweep last = heap[n];
            i = 0;
            while ((c = 2 * i + 1) < n) {
                if (c + 1 < n && pvs__kdsweep_before(heap + c + 1, heap + c)) ++c;
                if (!pvs__kdsweep_before(heap + c, &last)) break;
                heap[i] = heap[c];
                i = c;
            }
            heap[i] = last;
        }
        if (axis == PVS__KD_LEAF) {
            uint32_t count = nd->u.count;
            v = visit(user, &top.box, sqrtf(top.d2), count ? t->items + (nd->bits >> 2) : NULL, count);
        } else {
            v = visit(user, &top.box, sqrtf(top.d2), NULL, 0);
        }
        if (v == PVS_VISIT_STOP) break;
        if (v != PVS_VISIT_DESCEND || axis == PVS__KD_LEAF) continue;
        for (k = 0; k < 2; ++k) {
            pvs__kdsweep e;
            e.node = (nd->bits >> 2) + (uint32_t)k;
            e.box = top.box;
            if (k == 0) e.box.max[axis] = nd->u.split;
            else e.box.min[axis] = nd->u.split;
            e.d2 = pvs__box_distance2(source, &e.box);
            /* push: sift up */
            i = n++;
            while (i > 0 && pvs__kdsweep_before(&e, heap + (i - 1) / 2)) {
                heap[i] = heap[(i - 1) / 2];
                i = (i - 1) / 2;
            }
            heap[i] = e;
        }
    }
    return PVS_OK;
}

/* ---- ray walk ---- */

/* Front-to-back stack traversal (the classic recursive ray traversal, Havran's TA_rec_B family) in
   double. Leaf intervals are widened by PVS__KD_RAY_TOL of the coordinates' size, so a leaf the ray
   touches is never skipped: only visiting an extra neighbour can happen. */
PVS_API void pvs_kdtree_ray(const pvs_kdtree *t, const float origin[3], const float dir[3], float tmax_f,
                            pvs_kdtree_ray_fn fn, void *user) {
    struct {
        uint32_t node;
        double tn, tf;
    } stack[PVS_KDTREE_MAX_DEPTH + 2];
    double o[3], d[3], inv[3], tn = 0.0, tf, tmax;
    uint32_t node = 0;
    int sp = 0, k;
    if (!t || !origin || !dir || !fn || t->bounds.min[0] > t->bounds.max[0]) return;
    if (!(tmax_f >= 0.0f)) return; /* negative or NaN */
    for (k = 0; k < 3; ++k)
        if (!pvs__finite(origin[k]) || !pvs__finite(dir[k])) return;
    if (dir[0] == 0.0f && dir[1] == 0.0f && dir[2] == 0.0f) return;
    tmax = tf = (double)tmax_f;
    for (k = 0; k < 3; ++k) {
        double lo = t->bounds.min[k], hi = t->bounds.max[k];
        o[k] = origin[k];
        d[k] = dir[k];
        if (d[k] == 0.0) {
            inv[k] = 0.0;
            if (o[k] < lo || o[k] > hi) return;
        } else {
            double t0, t1, tol;
            inv[k] = 1.0 / d[k];
            t0 = (lo - o[k]) * inv[k];
            t1 = (hi - o[k]) * inv[k];
            if (t0 > t1) { double s = t0; t0 = t1; t1 = s; }
            tol = PVS__KD_RAY_TOL * (fabs(lo) + fabs(hi) + 2.0 * fabs(o[k])) * fabs(inv[k]);
            if (t0 - tol > tn) tn = t0 - tol;
            if (t1 + tol < tf) tf = t1 + tol;
        }
    }
    if (tn > tf) return;
    for (;;) {
        if (tn <= tmax) {
            const pvs__kdnode *nd = t->nodes + node;
            uint32_t axis;
            while ((axis = nd->bits & 3u) != PVS__KD_LEAF) {
                double s = nd->u.split, ts, tol;
                uint32_t left = nd->bits >> 2, near_child, far_child;
                if (d[axis] == 0.0) {
                    /* parallel to the plane: the side of the origin, both when it lies in the plane */
                    if (o[axis] < s) node = left;
                    else if (o[axis] > s) node = left + 1;
                    else {
                        stack[sp].node = left + 1;
                        stack[sp].tn = tn;
                        stack[sp].tf = tf;
                        ++sp;
                        node = left;
                    }
                    nd = t->nodes + node;
                    continue;
                }
                /* near = the side holding the origin; on the plane, the side the ray moves into */
                near_child = (o[axis] < s || (o[axis] == s && d[axis] < 0.0)) ? left : left + 1;
                far_child = near_child == left ? left + 1 : left;
                ts = (s - o[axis]) * inv[axis];
                tol = PVS__KD_RAY_TOL * (fabs(s) + fabs(o[axis])) * fabs(inv[axis]);
                if (ts <= 0.0 || ts > tf + tol) {
                    node = near_child;
                } else if (ts < tn - tol) {
                    node = far_child;
                } else {
                    stack[sp].node = far_child;
                    stack[sp].tn = ts - tol > tn ? ts - tol : tn;
                    stack[sp].tf = tf;
                    ++sp;
                    node = near_child;
                    if (ts + tol < tf) tf = ts + tol;
                }
                nd = t->nodes + node;
            }
            if (nd->u.count) {
                float r = fn(user, t->items + (nd->bits >> 2), nd->u.count, (float)tn, (float)tf);
                if (!(r >= 0.0f)) return; /* negative (or NaN): stop */
                if ((double)r < tmax) tmax = r;
            }
        }
        if (sp == 0) return;
        --sp;
        node = stack[sp].node;
        tn = stack[sp].tn;
        tf = stack[sp].tf;
    }
}

/* ---- point location ---- */

/* A point on a split plane goes left. That leaf holds every item whose box contains the point: the
   build stored each box touching the plane on both sides. */
PVS_API const uint32_t *pvs_kdtree_leaf_items(const pvs_kdtree *t, const float p[3], uint32_t *count) {
    const pvs__kdnode *nd;
    uint32_t axis;
    if (count) *count = 0;
    if (!t || !p || !count || !pvs__box_contains_point(&t->bounds, p)) return NULL;
    nd = t->nodes;
    while ((axis = nd->bits & 3u) != PVS__KD_LEAF) nd = t->nodes + (nd->bits >> 2) + (p[axis] <= nd->u.split ? 0u : 1u);
    if (!nd->u.count) return NULL;
    *count = nd->u.count;
    return t->items + (nd->bits >> 2);
}

/* ---- scene ray casts ---- */

/* Lexicographic order of points. */
PVS__STATIC int pvs__point_less(const float *a, const float *b) {
    if (a[0] != b[0]) return a[0] < b[0];
    if (a[1] != b[1]) return a[1] < b[1];
    return a[2] < b[2];
}

PVS__STATIC pvs_result pvs__scene_prepare_rays(pvs_scene *s, pvs_box *tri_boxes, pvs_error *err) {
    uint32_t t;
    s->triangle_corners = (float *)pvs__alloc_array(&s->allocator, (size_t)s->triangle_count * 9, sizeof(float));
    if (!s->triangle_corners) return pvs__fail(err, PVS_ERROR_OUT_OF_MEMORY, -1, 0, "triangle corners");
    for (t = 0; t < s->triangle_count; ++t) {
        const float *c[3], *x;
        const uint32_t *tri = s->indices + 3 * (size_t)t;
        double e1[3], e2[3];
        int k;
        for (k = 0; k < 3; ++k) c[k] = s->positions + 3 * (size_t)tri[k];
        if (pvs__point_less(c[1], c[0])) { x = c[0]; c[0] = c[1]; c[1] = x; }
        if (pvs__point_less(c[2], c[1])) { x = c[1]; c[1] = c[2]; c[2] = x; }
        if (pvs__point_less(c[1], c[0])) { x = c[0]; c[0] = c[1]; c[1] = x; }
        for (k = 0; k < 3; ++k) {
            memcpy(s->triangle_corners + 9 * (size_t)t + 3 * k, c[k], 3 * sizeof(float));
            e1[k] = (double)c[1][k] - c[0][k];
            e2[k] = (double)c[2][k] - c[0][k];
        }
        if (e1[1] * e2[2] - e1[2] * e2[1] == 0.0 && e1[2] * e2[0] - e1[0] * e2[2] == 0.0 && e1[0] * e2[1] - e1[1] * e2[0] == 0.0)
            tri_boxes[t] = pvs__box_empty(); /* zero area: never hit, left out of the tree */
    }
    return PVS_OK;
}

/* A ray prepared for the watertight test of Woop, Benthin and Wald (JCGT 2013): the axis kz of the
   largest direction component, the shear taking dir to +-z, in double. */
typedef struct pvs__ray {
    double o[3];
    double sx, sy, sz;
    int kx, ky, kz;
} pvs__ray;

PVS__STATIC int pvs__ray_setup(pvs__ray *r, const double o[3], const double d[3]) {
    double ax = fabs(d[0]), ay = fabs(d[1]), az = fabs(d[2]);
    r->kz = ax >= ay ? (ax >= az ? 0 : 2) : (ay >= az ? 1 : 2);
    if (d[r->kz] == 0.0 || !(d[r->kz] == d[r->kz])) return 0;
    r->kx = (r->kz + 1) % 3;
    r->ky = (r->kz + 2) % 3;
    r->sx = d[r->kx] / d[r->kz];
    r->sy = d[r->ky] / d[r->kz];
    r->sz = 1.0 / d[r->kz];
    r->o[0] = o[0]; r->o[1] = o[1]; r->o[2] = o[2];
    return 1;
}

/* 2D edge function of the sheared corners p, q: its sign says on which side of p-q the ray passes.
   Triangles store their corners sorted, so a shared edge is always evaluated as (p, q) in the same
   order, bit for bit the same in both triangles: a ray cannot slip between them. */
PVS__STATIC double pvs__edge(const double *p, const double *q) { return p[0] * q[1] - p[1] * q[0]; }

/* Two-sided watertight ray-triangle test: 1 and *t when the ray meets the triangle at 0 <= t <= tmax. */
PVS__STATIC int pvs__ray_triangle(const pvs__ray *r, const float *c, double tmax, double *t_out) {
    double p[3][2], z[3], u, v, w, det, t;
    int k;
    for (k = 0; k < 3; ++k) {
        double ax = (double)c[3 * k + r->kx] - r->o[r->kx];
        double ay = (double)c[3 * k + r->ky] - r->o[r->ky];
        double az = (double)c[3 * k + r->kz] - r->o[r->kz];
        p[k][0] = ax - r->sx * az;
        p[k][1] = ay - r->sy * az;
        z[k] = r->sz * az;
    }
    u = pvs__edge(p[1], p[2]);
    v = -pvs__edge(p[0], p[2]);
    w = pvs__edge(p[0], p[1]);
    if ((u < 0.0 || v < 0.0 || w < 0.0) && (u > 0.0 || v > 0.0 || w > 0.0)) return 0;
    det = u + v + w;
    if (det == 0.0) return 0; /* the ray lies in the triangle's plane */
    t = (u * z[0] + v * z[1] + w * z[2]) / det;
    if (!(t >= 0.0 && t <= tmax)) return 0;
    *t_out = t;
    return 1;
}

typedef struct pvs__raycast {
    const pvs_scene *scene;
    pvs__ray ray;
    double tmax;        /* closest hit so far, or the ray's end */
    uint32_t triangle;  /* of the closest hit, or 0xffffffff */
    int any;            /* stop at the first hit */
} pvs__raycast;

PVS__STATIC float pvs__raycast_leaf(void *user, const uint32_t *items, uint32_t count, float t_enter, float t_exit) {
    pvs__raycast *rc = (pvs__raycast *)user;
    uint32_t i;
    float f;
    (void)t_enter;
    (void)t_exit;
    for (i = 0; i < count; ++i) {
        uint32_t tri = items[i];
        double t;
        if (!pvs__ray_triangle(&rc->ray, rc->scene->triangle_corners + 9 * (size_t)tri, rc->tmax, &t)) continue;
        /* equal distances: the lowest triangle index wins, whatever the leaf order */
        if (t < rc->tmax || rc->triangle == 0xffffffffu || tri < rc->triangle) {
            rc->tmax = t;
            rc->triangle = tri;
            if (rc->any) return -1.0f;
        }
    }
    if (rc->any) return FLT_MAX;
    /* shorten the walk to the closest hit, rounding up so no leaf at that distance is skipped */
    f = (float)rc->tmax;
    if ((double)f < rc->tmax) f = nextafterf(f, FLT_MAX);
    return f;
}

PVS_API int pvs_scene_raycast(const pvs_scene *s, const float origin[3], const float dir[3], float tmax, pvs_hit *hit) {
    pvs__raycast rc;
    double o[3], d[3];
    int k;
    if (!s || !origin || !dir || !(tmax >= 0.0f)) return 0;
    for (k = 0; k < 3; ++k) {
        o[k] = origin[k];
        d[k] = dir[k];
    }
    if (!pvs__ray_setup(&rc.ray, o, d)) return 0;
    rc.scene = s;
    rc.tmax = tmax;
    rc.triangle = 0xffffffffu;
    rc.any = 0;
    pvs_kdtree_ray(s->triangle_tree, origin, dir, tmax, pvs__raycast_leaf, &rc);
    if (rc.triangle == 0xffffffffu) return 0;
    if (hit) {
        hit->t = (float)rc.tmax;
        hit->triangle = rc.triangle;
        hit->object = s->triangle_object[rc.triangle];
    }
    return 1;
}

/* The segment is the ray a + t (b - a), 0 <= t <= 1, with b - a in double. A zero-length segment
   is never blocked. */
PVS_API int pvs_scene_segment_blocked(const pvs_scene *s, const float a[3], const float b[3]) {
    pvs__raycast rc;
    double o[3], d[3];
    float df[3];
    int k;
    if (!s || !a || !b) return 0;
    for (k = 0; k < 3; ++k) {
        o[k] = a[k];
        d[k] = (double)b[k] - (double)a[k];
        df[k] = b[k] - a[k];
        /* the walk's direction in float must not lose a component the exact one has */
        if (df[k] == 0.0f && d[k] != 0.0) df[k] = d[k] > 0.0 ? FLT_MIN : -FLT_MIN;
    }
    if (!pvs__ray_setup(&rc.ray, o, d)) return 0;
    rc.scene = s;
    rc.tmax = 1.0;
    rc.triangle = 0xffffffffu;
    rc.any = 1;
    /* the walk goes a little past b: its float direction may fall short; the test itself stops at 1 */
    pvs_kdtree_ray(s->triangle_tree, a, df, 1.0f + 1e-6f, pvs__raycast_leaf, &rc);
    return rc.triangle != 0xffffffffu;
}

// >>raster
/* ---------------------------------------------------------------------------------------------- */
/* raster: conservative rasterizer (Durand 2000 §3.1-3.2), depth pyramid (Durand 2000 §2.4),     */
/* cull map (Wonka & Schmalstieg 1999 §3-4), per-frame culling (Bittner 2002 §3.2, §4.5)          */
/* ---------------------------------------------------------------------------------------------- */

/* How the guarantee survives rounding. Per polygon (a triangle clipped to the near plane), the setup
   runs in double: vertices are projected to pixel coordinates, each edge function E(x, y) (>= 0
   inside, normalised so |a| + |b| = 1) is evaluated at the corner of the pixel range, and the
   per-pixel extreme over a pixel square is added exactly as min(0, a) + min(0, b) (inner coverage,
   the occluder test: the whole pixel inside) or max(0, a) + max(0, b) (outer coverage, the occludee
   test: some of the pixel inside). This is the sampling correction of Wonka 1999 §4.4 - edges moved
   by (|nx| + |ny|) half-pixels and a pixel-centre sample - written at the pixel corner. Then a bound
   on every rounding error is subtracted (occluder) or added (occludee) before the coefficients are
   rounded to float: 2^-40 of the coordinates' size for the double setup and the projection (far
   above double's 2^-53, with the edge's length in the denominator so short edges far off screen get
   wide margins), and 2^-20 of the terms' size for the float evaluation c + a i + b j (four roundings
   of 2^-24 each, i and j exact small integers). Depth is z/w, affine in screen space; over a pixel its
   extremes are at the pixel's corners (inner coverage) or inside the pixel's corners and the
   polygon's vertices (outer coverage), so the plane's corner extreme with the same kind of margin,
   clamped by the vertices' extreme depth, bounds it from the safe side even when the plane is ill
   conditioned. Degenerate polygons cover nothing as occluders and their whole bounding rectangle
   (at their nearest vertex depth) as occludees. The scalar and the SIMD loops perform the same float
   operations in the same order, so they agree bit for bit; that needs the compiler not to contract
   a * b + c into fused multiply-adds (GCC's default with -std=c99; clang is told by the pragma
   below). Contraction only removes roundings, so every margin still holds.

   Two places keep occluder depth. Per pixel (above; exact per pixel, the default for maps of at
   most 65,536 pixels, which the bake methods use) and, for larger maps, Masked Occlusion Culling's
   tiles (Hasselgren, Andersson and Akenine-Moller 2016): 32 x 4 pixels with a coverage mask and two
   depths (pvs__tile), filled row by row from the same double edge setup turned into per-row
   column bounds with a float margin (pvs__tile_poly), after a float prefilter that drops whole
   triangles four at a time (behind the eye, no whole pixel, or behind every tile's base: dropping
   an occluder is always safe). Box tests then run in float on the eight corners with explicit
   error bounds (pvs__raster_box_f). A tile's depth is the farthest its occluders reach over it, so
   tiles are coarser than pixels: about a tenth more objects pass on the test scenes at 1152 x 768,
   a fifth at 384 x 256.

   Limits. Near-plane clipping cuts in double without a margin: an occludee may lose a sliver some
   1e-12 pixels wide where it crosses the near plane (its depth there is the near plane's). The
   occluder selection uses the direction to the occluder as V in Bittner's measure (the solid angle),
   not the view direction. The cull map needs facades standing on the ground and a perspective
   camera (shadows are cast from a point). Speed (bench_raster, 2 shared cores under load,
   2026-11-24, min of 7): 1080p frame of 50,000 city triangles, pyramid and 10,000 box tests about
   1.0 ms with SSE2 and 2.0 ms scalar (Masked Occlusion Culling: about 1.06 ms on one 2013 desktop
   core with AVX2); 1,000 facades into a 256 x 256 cull map and its scan about 0.8 ms (1.2 scalar). */

#if !defined(PVS_NO_SIMD) && (defined(__SSE2__) || defined(_M_X64) || (defined(_M_IX86_FP) && _M_IX86_FP >= 2))
#define PVS__SSE2 1
#include <emmintrin.h>
#elif !defined(PVS_NO_SIMD) && (defined(__ARM_NEON) || defined(__ARM_NEON__))
#define PVS__NEON 1
#include <arm_neon.h>
#endif
#if defined(__clang__)
#pragma STDC FP_CONTRACT OFF
#endif

#define PVS__RASTER_MAXV 8                   /* polygon vertices after clipping a triangle: 5 */
#define PVS__RASTER_ERR_D 9.094947017729282e-13 /* 2^-40 */
#define PVS__RASTER_ERR_F 9.5367431640625e-07   /* 2^-20 */
#define PVS__RASTER_MAX_LEVELS 16
#define PVS__RASTER_BIG 1e30

/* One tile of the occluder buffer: 32 x 4 pixels (Hasselgren, Andersson and Akenine-Moller 2016,
   "Masked Software Occlusion Culling": a coverage mask and two depths per tile instead of a depth
   per pixel). Reversed Z: every pixel of the tile has occluders at least as near as z0; the pixels of
   the working layer `mask` have them at least as near as z1 (z1 > z0 while mask != 0). */
typedef struct pvs__tile {
    uint32_t mask[4]; /* bit k of mask[r]: pixel (32 tx + k, 4 ty + r) */
    float z0, z1;
    float pad[2];
} pvs__tile;

typedef struct pvs__occsel {
    float score;
    uint32_t triangle;
} pvs__occsel;

struct pvs_raster {
    pvs_allocator allocator;
    uint32_t width, height, flags;
    float *depth;                               /* width * height */
    float *tile_min;                            /* farthest depth per 8 x 8 tile */
    size_t tiles;
    uint32_t levels;                            /* pyramid levels above the depth map */
    uint32_t lw[PVS__RASTER_MAX_LEVELS + 1], lh[PVS__RASTER_MAX_LEVELS + 1];
    float *lmin[PVS__RASTER_MAX_LEVELS + 1], *lmax[PVS__RASTER_MAX_LEVELS + 1];
    float *pyramid;
    size_t pyramid_floats;
    int pyramid_valid;                          /* 1: the per-pixel pyramid is current, 2: the tile pyramid */
    /* the occluder buffer: tiles of 32 x 4 pixels (see pvs__tile) */
    pvs__tile *tile;
    uint32_t tw, th;                            /* tile grid */
    uint32_t xpad;                              /* bits of the last tile column past the map's right side */
    uint32_t ypad;                              /* rows of the last tile row inside the map (1..4) */
    int tiled;                                  /* occluders go to the tiles (else to `depth`) */
    int mixed;                                  /* `depth` holds pixels drawn since the clear (occludees, or all
                                                   triangles when not tiled) */
    float *bmin;                                /* per block of 8 x 8 tiles: at most the least base (z0) */
    uint8_t *bdirty;                            /*   and 1 when a base grew since bmin was taken */
    uint32_t bw, bh;                            /* block grid */
    uint32_t tlevels;                           /* tile pyramid levels above the tile grid */
    uint32_t tlw[PVS__RASTER_MAX_LEVELS * 2 + 1], tlh[PVS__RASTER_MAX_LEVELS * 2 + 1];
    uint8_t tsx[PVS__RASTER_MAX_LEVELS * 2 + 1], tsy[PVS__RASTER_MAX_LEVELS * 2 + 1]; /* tiles per texel: 1 << tsx by 1 << tsy */
    float *tlmin[PVS__RASTER_MAX_LEVELS * 2 + 1], *tlmax[PVS__RASTER_MAX_LEVELS * 2 + 1];
    float *tpyramid;
    size_t tpyramid_floats;
    double m[16];                               /* current projection */
    double mabs[2];                             /* max row sum of |m| over x, y, z; max |translation| */
    float mf[16], hwf, hhf;                     /* the projection as given, half the map's size (prefilter) */
    float mb[16][4];                            /* mf broadcast to four lanes */
    double rowa[4], rowt[4];                    /* per row of m: |m_r0| + |m_r1| + |m_r2|, |m_r3| */
    /* occluder meshes (pvs_raster_mesh): scratch for mesh_cap triangles and four rows of pixels */
    uint32_t mesh_cap, mesh_hash;               /* triangles per piece; hash slots (a power of two) */
    struct pvs__mtri *mt;                       /* mesh_cap prepared triangles */
    uint32_t *mcid, *mpart;                     /* 3 mesh_cap: welded vertex per corner, partner half-edge */
    uint8_t *mvst;                              /* 3 mesh_cap: corner in front of both clip planes / behind */
    int8_t *mgrp;                               /* mesh_cap: facing +1 / -1, 0 = left out */
    uint32_t *mtab, *morder, *mact, *mband;     /* hash slots; mesh_cap; mesh_cap; th + 1 */
    float *mzmin, *mzin;                        /* 4 width: least bound of the touching triangles, inner */
    uint8_t *mflag;                             /* 4 width: 1 a triangle surely meets the pixel, 2 a boundary edge may */
    uint8_t *mdirty;                            /* 4 tw: the 32-pixel words of the band's rows the scratch holds */
    /* culling */
    const pvs_scene *scene;
    uint32_t max_objects, max_triangles;
    void *sweep;
    size_t sweep_size;
    pvs__occsel *occ;
    uint32_t max_occluders;
    pvs_word *tri_seen;                         /* max_triangles bits */
    pvs_word *obj_done;                         /* max_objects bits */
    /* cull map */
    uint32_t cm_w, cm_h;
    float *cm;                                  /* cm_w * cm_h heights */
    float *cm_tile_min;                         /* lowest height per 8 x 8 tile */
    size_t cm_tiles;
    float region[4];                            /* u0, v0, u1, v1 */
    uint32_t *cm_start;                         /* cm_w * cm_h + 1 */
    uint32_t *cm_items;
    uint32_t cm_item_count;
    float *cm_bound;                            /* highest object top per cell (Wonka 1999 §4.3) */
    float ground;                               /* the scene's lowest point along the up axis */
};

/* Float bounds of a double from below / above (clamped to the finite floats). */
PVS__STATIC float pvs__f_down(double v) {
    float f;
    if (!(v > -FLT_MAX)) return -FLT_MAX;
    if (v >= FLT_MAX) return FLT_MAX;
    f = (float)v;
    if ((double)f > v) f = nextafterf(f, -FLT_MAX);
    return f;
}
PVS__STATIC float pvs__f_up(double v) {
    float f;
    if (!(v < FLT_MAX)) return FLT_MAX;
    if (v <= -FLT_MAX) return -FLT_MAX;
    f = (float)v;
    if ((double)f < v) f = nextafterf(f, FLT_MAX);
    return f;
}
PVS__STATIC double pvs__dabs(double v) { return v < 0 ? -v : v; }
PVS__STATIC double pvs__dmin(double a, double b) { return a < b ? a : b; }
PVS__STATIC double pvs__dmax(double a, double b) { return a > b ? a : b; }
/* Clamp a double to [lo, hi] and convert (NaN gives lo). */
PVS__STATIC int32_t pvs__clampi(double v, int32_t lo, int32_t hi) {
    if (!(v > (double)lo)) return lo;
    if (v > (double)hi) return hi;
    return (int32_t)v;
}

/* One prepared polygon: float edge and depth coefficients over the pixel range [i0, i1] x [j0, j1],
   relative to its corner (i0, j0). */
typedef struct pvs__rsetup {
    int32_t i0, i1, j0, j1;   /* the polygon's pixel range; (i0, j0) is the coefficients' origin */
    int32_t li0, li1, lj0, lj1; /* the part a loop covers (a tile of the range) */
    int edges;
    float a[PVS__RASTER_MAXV], b[PVS__RASTER_MAXV], k[PVS__RASTER_MAXV];
    float za, zb, zk;     /* depth plane bound */
    float zclamp;         /* occluder: max(plane, zclamp); occludee: min(plane, zclamp) */
} pvs__rsetup;

/* One pixel by the reference rule, shared by the scalar loop and the SIMD tails: inside every edge
   (rk: the edge values at the row's column i0), then the clamped plane depth, kept if nearer.
   Returns 1 when it wrote. */
PVS__STATIC int pvs__raster_pixel(const pvs__rsetup *s, const float *rk, float rz, float *row, int32_t i, int occluder) {
    float fi = (float)(i - s->i0), d;
    int e;
    for (e = 0; e < s->edges; ++e)
        if (!(rk[e] + s->a[e] * fi >= 0.0f)) return 0;
    d = rz + s->za * fi;
    if (occluder) d = d < s->zclamp ? s->zclamp : d;
    else d = d > s->zclamp ? s->zclamp : d;
    if (!(d > row[i])) return 0;
    row[i] = d;
    return 1;
}

/* Scalar reference loop. */
PVS__STATIC int pvs__raster_rows_scalar(const pvs__rsetup *s, float *buf, uint32_t stride, int occluder) {
    int32_t i, j;
    int e, wrote = 0;
    for (j = s->lj0; j <= s->lj1; ++j) {
        float fj = (float)(j - s->j0), rk[PVS__RASTER_MAXV], rz = s->zk + s->zb * fj;
        float *row = buf + (size_t)j * stride;
        for (e = 0; e < s->edges; ++e) rk[e] = s->k[e] + s->b[e] * fj;
        for (i = s->li0; i <= s->li1; ++i) wrote |= pvs__raster_pixel(s, rk, rz, row, i, occluder);
    }
    return wrote;
}

#if defined(PVS__SSE2)
/* Four pixels at a time; the same operations as the scalar loop, lane by lane. */
PVS__STATIC int pvs__raster_rows_simd(const pvs__rsetup *s, float *buf, uint32_t stride, int occluder) {
    int32_t i, j;
    int e, wrote = 0;
    const __m128 step = _mm_set_ps(3.0f, 2.0f, 1.0f, 0.0f), zero = _mm_setzero_ps();
    __m128 va[PVS__RASTER_MAXV];
    const __m128 vza = _mm_set1_ps(s->za), vclamp = _mm_set1_ps(s->zclamp);
    for (e = 0; e < s->edges; ++e) va[e] = _mm_set1_ps(s->a[e]);
    for (j = s->lj0; j <= s->lj1; ++j) {
        float fj = (float)(j - s->j0), rz = s->zk + s->zb * fj;
        __m128 rk[PVS__RASTER_MAXV], vrz = _mm_set1_ps(rz);
        float *row = buf + (size_t)j * stride;
        for (e = 0; e < s->edges; ++e) rk[e] = _mm_set1_ps(s->k[e] + s->b[e] * fj);
        for (i = s->li0; i + 3 <= s->li1; i += 4) {
            __m128 fi = _mm_add_ps(_mm_set1_ps((float)(i - s->i0)), step);
            __m128 mask = _mm_castsi128_ps(_mm_set1_epi32(-1)), d, old, gt;
            for (e = 0; e < s->edges; ++e) mask = _mm_and_ps(mask, _mm_cmpge_ps(_mm_add_ps(rk[e], _mm_mul_ps(va[e], fi)), zero));
            if (!_mm_movemask_ps(mask)) continue;
            d = _mm_add_ps(vrz, _mm_mul_ps(vza, fi));
            if (occluder) d = _mm_or_ps(_mm_and_ps(_mm_cmplt_ps(d, vclamp), vclamp), _mm_andnot_ps(_mm_cmplt_ps(d, vclamp), d));
            else d = _mm_or_ps(_mm_and_ps(_mm_cmpgt_ps(d, vclamp), vclamp), _mm_andnot_ps(_mm_cmpgt_ps(d, vclamp), d));
            old = _mm_loadu_ps(row + i);
            gt = _mm_and_ps(mask, _mm_cmpgt_ps(d, old));
            wrote |= _mm_movemask_ps(gt);
            _mm_storeu_ps(row + i, _mm_or_ps(_mm_and_ps(gt, d), _mm_andnot_ps(gt, old)));
        }
        if (i <= s->li1) { /* the tail, by the scalar rule */
            float rkf[PVS__RASTER_MAXV];
            for (e = 0; e < s->edges; ++e) rkf[e] = s->k[e] + s->b[e] * fj;
            for (; i <= s->li1; ++i) wrote |= pvs__raster_pixel(s, rkf, rz, row, i, occluder);
        }
    }
    return wrote;
}
#define PVS__HAVE_SIMD 1
#elif defined(PVS__NEON)
PVS__STATIC int pvs__raster_rows_simd(const pvs__rsetup *s, float *buf, uint32_t stride, int occluder) {
    int32_t i, j;
    int e, wrote = 0;
    static const float stepf[4] = {0.0f, 1.0f, 2.0f, 3.0f};
    const float32x4_t step = vld1q_f32(stepf), zero = vdupq_n_f32(0.0f);
    float32x4_t va[PVS__RASTER_MAXV];
    const float32x4_t vza = vdupq_n_f32(s->za), vclamp = vdupq_n_f32(s->zclamp);
    for (e = 0; e < s->edges; ++e) va[e] = vdupq_n_f32(s->a[e]);
    for (j = s->lj0; j <= s->lj1; ++j) {
        float fj = (float)(j - s->j0), rz = s->zk + s->zb * fj, rkf[PVS__RASTER_MAXV];
        float32x4_t rk[PVS__RASTER_MAXV], vrz = vdupq_n_f32(rz);
        float *row = buf + (size_t)j * stride;
        for (e = 0; e < s->edges; ++e) { rkf[e] = s->k[e] + s->b[e] * fj; rk[e] = vdupq_n_f32(rkf[e]); }
        for (i = s->li0; i + 3 <= s->li1; i += 4) {
            float32x4_t fi = vaddq_f32(vdupq_n_f32((float)(i - s->i0)), step), d, old;
            uint32x4_t mask = vdupq_n_u32(0xffffffffu), gt;
            for (e = 0; e < s->edges; ++e) mask = vandq_u32(mask, vcgeq_f32(vaddq_f32(rk[e], vmulq_f32(va[e], fi)), zero));
            if ((vgetq_lane_u32(mask, 0) | vgetq_lane_u32(mask, 1) | vgetq_lane_u32(mask, 2) | vgetq_lane_u32(mask, 3)) == 0) continue;
            d = vaddq_f32(vrz, vmulq_f32(vza, fi));
            if (occluder) d = vbslq_f32(vcltq_f32(d, vclamp), vclamp, d);
            else d = vbslq_f32(vcgtq_f32(d, vclamp), vclamp, d);
            old = vld1q_f32(row + i);
            gt = vandq_u32(mask, vcgtq_f32(d, old));
            wrote |= (vgetq_lane_u32(gt, 0) | vgetq_lane_u32(gt, 1) | vgetq_lane_u32(gt, 2) | vgetq_lane_u32(gt, 3)) != 0;
            vst1q_f32(row + i, vbslq_f32(gt, d, old));
        }
        for (; i <= s->li1; ++i) wrote |= pvs__raster_pixel(s, rkf, rz, row, i, occluder);
    }
    return wrote;
}
#define PVS__HAVE_SIMD 1
#endif

/* Tiles of 8 x 8 pixels remember their farthest depth, so a polygon that cannot be nearer than
   everything in a tile skips it (the occluders of a culling frame come roughly front to back), and
   tiles outside one of the polygon's edges are skipped. Only the pixels visited change, never a
   result. */
#define PVS__TILE_SHIFT 3
#define PVS__TILE (1 << PVS__TILE_SHIFT)

PVS__STATIC void pvs__tile_update(float *buf, uint32_t W, uint32_t H, float *tile_min, uint32_t tx, uint32_t ty) {
    uint32_t x0 = tx << PVS__TILE_SHIFT, y0 = ty << PVS__TILE_SHIFT, x1 = x0 + PVS__TILE, y1 = y0 + PVS__TILE, x, y;
    float lo = FLT_MAX;
    if (x1 > W) x1 = W;
    if (y1 > H) y1 = H;
    for (y = y0; y < y1; ++y) {
        const float *row = buf + (size_t)y * W;
        for (x = x0; x < x1; ++x) lo = row[x] < lo ? row[x] : lo;
    }
    tile_min[ty * ((W + PVS__TILE - 1) >> PVS__TILE_SHIFT) + tx] = lo;
}

/* Where the pixels [i0 + a0, i0 + a1] x [j0 + b0, j0 + b1] stand against the polygon's edges as the
   float loops will evaluate them: -1 all fail some edge, 1 all pass every edge, 0 undecided. The
   bounds are exact in double with a slack above the loops' float rounding (2^-18 of the terms). */
PVS__STATIC int pvs__raster_classify(const pvs__rsetup *s, int32_t a0, int32_t a1, int32_t b0, int32_t b1) {
    int e, inside = 1;
    for (e = 0; e < s->edges; ++e) {
        double k = s->k[e], a = s->a[e], b = s->b[e];
        double hi = k + pvs__dmax(a * a0, a * a1) + pvs__dmax(b * b0, b * b1);
        double lo = k + pvs__dmin(a * a0, a * a1) + pvs__dmin(b * b0, b * b1);
        double slack = 3.814697265625e-06 * (pvs__dabs(k) + pvs__dabs(a) * a1 + pvs__dabs(b) * b1) + 1e-30;
        if (hi + slack < 0.0) return -1;
        if (lo - slack < 0.0) inside = 0;
    }
    return inside;
}

/* The most the pixel loops can write over pixels [a0, a1] x [b0, b1] (relative to the polygon's
   corner): the plane's largest value there plus a slack above their float rounding, clamped as they
   clamp. */
PVS__STATIC double pvs__raster_zbound(const pvs__rsetup *s, int32_t a0, int32_t a1, int32_t b0, int32_t b1, int occluder) {
    double pa = s->za, pb = s->zb, hi = (double)s->zk + pvs__dmax(pa * a0, pa * a1) + pvs__dmax(pb * b0, pb * b1);
    hi += 3.814697265625e-06 * (pvs__dabs(s->zk) + pvs__dabs(pa) * a1 + pvs__dabs(pb) * b1) + 1e-30;
    return occluder ? pvs__dmax(hi, s->zclamp) : pvs__dmin(hi, s->zclamp);
}

/* Runs the pixel loops over the prepared polygon: blocks of 4 x 4 tiles, skipped when every tile
   already holds at least what the polygon could write there, classified against the edges; then
   tiles (skipped likewise or when outside, without edge tests when inside). */
PVS__STATIC void pvs__raster_run(pvs__rsetup *s, float *buf, uint32_t W, uint32_t H, float *tile_min, int occluder, int simd, float zbound) {
    uint32_t tw = (W + PVS__TILE - 1) >> PVS__TILE_SHIFT, tx, ty, bx, by;
    int wrote, inside, edges, block;
    const int bs = PVS__TILE_SHIFT + 2; /* block = 4 x 4 tiles */
    (void)simd;
    if (!tile_min) {
        s->li0 = s->i0; s->li1 = s->i1; s->lj0 = s->j0; s->lj1 = s->j1;
#if defined(PVS__HAVE_SIMD)
        if (simd) { pvs__raster_rows_simd(s, buf, W, occluder); return; }
#endif
        (void)pvs__raster_rows_scalar(s, buf, W, occluder);
        return;
    }
    for (by = (uint32_t)s->j0 >> bs; by <= (uint32_t)s->j1 >> bs; ++by)
        for (bx = (uint32_t)s->i0 >> bs; bx <= (uint32_t)s->i1 >> bs; ++bx) {
            int32_t c0 = (int32_t)(bx << bs), c1 = c0 + (1 << bs) - 1, d0 = (int32_t)(by << bs), d1 = d0 + (1 << bs) - 1;
            uint32_t tx0, tx1, ty0, ty1;
            if (c0 < s->i0) c0 = s->i0;
            if (c1 > s->i1) c1 = s->i1;
            if (d0 < s->j0) d0 = s->j0;
            if (d1 > s->j1) d1 = s->j1;
            tx0 = (uint32_t)c0 >> PVS__TILE_SHIFT; tx1 = (uint32_t)c1 >> PVS__TILE_SHIFT;
            ty0 = (uint32_t)d0 >> PVS__TILE_SHIFT; ty1 = (uint32_t)d1 >> PVS__TILE_SHIFT;
            {
                float lo = FLT_MAX;
                for (ty = ty0; ty <= ty1; ++ty) {
                    const float *t = tile_min + ty * tw;
                    if (tx1 - tx0 == 3) { /* a whole block row, without a loop */
                        float a = t[tx0] < t[tx0 + 1] ? t[tx0] : t[tx0 + 1], b = t[tx0 + 2] < t[tx0 + 3] ? t[tx0 + 2] : t[tx0 + 3];
                        a = a < b ? a : b;
                        lo = a < lo ? a : lo;
                    } else {
                        for (tx = tx0; tx <= tx1; ++tx) lo = t[tx] < lo ? t[tx] : lo;
                    }
                }
                if (lo >= zbound || (double)lo >= pvs__raster_zbound(s, c0 - s->i0, c1 - s->i0, d0 - s->j0, d1 - s->j0, occluder)) continue;
            }
            block = pvs__raster_classify(s, c0 - s->i0, c1 - s->i0, d0 - s->j0, d1 - s->j0);
            if (block < 0) continue;
            for (ty = ty0; ty <= ty1; ++ty)
                for (tx = tx0; tx <= tx1; ++tx) {
                    if (tile_min[ty * tw + tx] >= zbound) continue; /* nothing here can get nearer */
                    s->li0 = (int32_t)(tx << PVS__TILE_SHIFT); if (s->li0 < s->i0) s->li0 = s->i0;
                    s->li1 = (int32_t)(tx << PVS__TILE_SHIFT) + PVS__TILE - 1; if (s->li1 > s->i1) s->li1 = s->i1;
                    s->lj0 = (int32_t)(ty << PVS__TILE_SHIFT); if (s->lj0 < s->j0) s->lj0 = s->j0;
                    s->lj1 = (int32_t)(ty << PVS__TILE_SHIFT) + PVS__TILE - 1; if (s->lj1 > s->j1) s->lj1 = s->j1;
                    if ((double)tile_min[ty * tw + tx] >= pvs__raster_zbound(s, s->li0 - s->i0, s->li1 - s->i0, s->lj0 - s->j0, s->lj1 - s->j0, occluder))
                        continue;
                    inside = block ? 1 : pvs__raster_classify(s, s->li0 - s->i0, s->li1 - s->i0, s->lj0 - s->j0, s->lj1 - s->j0);
                    if (inside < 0) continue;
                    edges = s->edges;
                    if (inside) s->edges = 0; /* every pixel passes every edge: the same result without the tests */
#if defined(PVS__HAVE_SIMD)
                    if (simd) wrote = pvs__raster_rows_simd(s, buf, W, occluder);
                    else
#endif
                        wrote = pvs__raster_rows_scalar(s, buf, W, occluder);
                    s->edges = edges;
                    if (!wrote) continue;
                    if (inside && s->li1 - s->li0 == PVS__TILE - 1 && s->lj1 - s->lj0 == PVS__TILE - 1) {
                        /* the whole tile got at least the polygon's depth: its least value over the
                           tile's corners (depth is affine), less a rounding slack, bounds the tile
                           from below; a lower bound is all the skipping needs */
                        double lo = DBL_MAX, za = s->za, zb = s->zb, zk = s->zk, slack;
                        int ci;
                        for (ci = 0; ci < 4; ++ci) {
                            double fi = (double)((ci & 1 ? s->li1 : s->li0) - s->i0), fj = (double)((ci & 2 ? s->lj1 : s->lj0) - s->j0);
                            lo = pvs__dmin(lo, zk + za * fi + zb * fj);
                        }
                        slack = 3.814697265625e-06 * (pvs__dabs(zk) + pvs__dabs(za) * (s->li1 - s->i0) + pvs__dabs(zb) * (s->lj1 - s->j0)) + 1e-30;
                        lo -= slack;
                        if (occluder) lo = pvs__dmax(lo, s->zclamp);
                        else lo = pvs__dmin(lo, s->zclamp);
                        if (lo > tile_min[ty * tw + tx]) tile_min[ty * tw + tx] = pvs__f_down(lo);
                    } else {
                        pvs__tile_update(buf, W, H, tile_min, tx, ty);
                    }
                }
        }
}

/* Fills the pixel rectangle with `d` where it is nearer (the degenerate occludee case). */
PVS__STATIC void pvs__raster_fill(float *buf, uint32_t W, uint32_t H, float *tile_min, int32_t i0, int32_t i1, int32_t j0, int32_t j1, float d) {
    int32_t i, j;
    uint32_t tx, ty;
    for (j = j0; j <= j1; ++j) {
        float *row = buf + (size_t)j * W;
        for (i = i0; i <= i1; ++i)
            if (d > row[i]) row[i] = d;
    }
    if (tile_min)
        for (ty = (uint32_t)j0 >> PVS__TILE_SHIFT; ty <= (uint32_t)j1 >> PVS__TILE_SHIFT; ++ty)
            for (tx = (uint32_t)i0 >> PVS__TILE_SHIFT; tx <= (uint32_t)i1 >> PVS__TILE_SHIFT; ++tx) pvs__tile_update(buf, W, H, tile_min, tx, ty);
}

/* The depth plane bound of a polygon (pixel coordinates x, y, depth z, n vertices; span, mag, zmag its
   extents, perr, zerr its vertices' errors) over the pixels (ox + fi, oy + fj), fi in [0, iw], fj in
   [0, jh]: the float evaluation (zk + zb fj) + za fi is at most (occluder) or at least (occludee) the
   plane's extreme over the pixel [ox + fi, +1] x [oy + fj, +1]. The plane comes from the largest fan
   triangle; without one (or beyond float) zk is -FLT_MAX (occluder) or FLT_MAX, za = zb = 0. */
PVS__STATIC void pvs__raster_zplane(const double *x, const double *y, const double *z, int n, double ox, double oy, double iw,
                                    double jh, double span, double mag, double zmag, double perr, double zerr, int occluder,
                                    float *za_out, float *zb_out, float *zk_out) {
    int i, best = -1;
    double amax = 0.0;
    for (i = 1; i + 1 < n; ++i) {
        double a2 = pvs__dabs((x[i] - x[0]) * (y[i + 1] - y[0]) - (x[i + 1] - x[0]) * (y[i] - y[0]));
        if (a2 > amax) { amax = a2; best = i; }
    }
    *za_out = *zb_out = 0.0f;
    *zk_out = occluder ? -FLT_MAX : FLT_MAX;
    if (best > 0) {
        double x1 = x[best] - x[0], y1 = y[best] - y[0], z1 = z[best] - z[0];
        double x2 = x[best + 1] - x[0], y2 = y[best + 1] - y[0], z2 = z[best + 1] - z[0];
        double det = x1 * y2 - x2 * y1;
        double za = (z1 * y2 - z2 * y1) / det, zb = (x1 * z2 - x2 * z1) / det;
        double zk = z[0] + za * (ox - x[0]) + zb * (oy - y[0]), err, dy;
        zk += occluder ? pvs__dmin(0.0, za) + pvs__dmin(0.0, zb) : pvs__dmax(0.0, za) + pvs__dmax(0.0, zb);
        err = zerr + (pvs__dabs(za) + pvs__dabs(zb)) * perr * (1.0 + (span + iw + jh + 2.0) * span / pvs__dabs(det)) +
              PVS__RASTER_ERR_D * (zmag + (pvs__dabs(za) + pvs__dabs(zb)) * (mag + ox + oy + iw + jh + 2.0)) *
                  (1.0 + (span + ox + oy + iw + jh + 2.0) * span / pvs__dabs(det)) +
              PVS__RASTER_ERR_F * (pvs__dabs(zk) + pvs__dabs(za) * iw + pvs__dabs(zb) * jh + 1e-30);
        zk += occluder ? -err : err;
        dy = pvs__dabs(zk) + pvs__dabs(za) * iw + pvs__dabs(zb) * jh;
        if (dy < 1e30 && err < 1e30) {
            *za_out = (float)za;
            *zb_out = (float)zb;
            *zk_out = (float)zk;
        }
    }
}

/* Rasterizes a convex polygon given in pixel coordinates (x, y) with depth z (affine over it) into a
   W x H float buffer, keeping the larger (nearer) depth per pixel. See the comment at the top. */
PVS__STATIC void pvs__raster_poly(float *buf, uint32_t W, uint32_t H, float *tile_min, const double *x, const double *y,
                                  const double *z, int n, int occluder, int simd, double perr, double zerr) {
    pvs__rsetup s;
    double xmin = x[0], xmax = x[0], ymin = y[0], ymax = y[0], zmin = z[0], zmax = z[0], area2 = 0.0, mag = 0.0, zmag = 0.0;
    double span, dx, ox, oy, iw, jh, zlo, zhi;
    int i;
    if (n < 3) return;
    for (i = 0; i < n; ++i) {
        int j = i + 1 == n ? 0 : i + 1;
        if (!(x[i] == x[i] && y[i] == y[i] && z[i] == z[i])) return; /* NaN */
        xmin = pvs__dmin(xmin, x[i]); xmax = pvs__dmax(xmax, x[i]);
        ymin = pvs__dmin(ymin, y[i]); ymax = pvs__dmax(ymax, y[i]);
        zmin = pvs__dmin(zmin, z[i]); zmax = pvs__dmax(zmax, z[i]);
        area2 += x[i] * y[j] - x[j] * y[i];
        mag = pvs__dmax(mag, pvs__dabs(x[i]) + pvs__dabs(y[i]));
        zmag = pvs__dmax(zmag, pvs__dabs(z[i]));
    }
    dx = PVS__RASTER_ERR_D * (mag + 1.0) + perr; /* perr, zerr: the vertices' own error (projection) */
    zlo = zmin - PVS__RASTER_ERR_D * zmag - zerr;
    zhi = zmax + PVS__RASTER_ERR_D * zmag + zerr;
    /* pixel range: inner (pixels inside the bounding box) or outer (pixels touching it) */
    if (occluder) {
        s.i0 = pvs__clampi(ceil(xmin + dx), 0, (int32_t)W);
        s.i1 = pvs__clampi(floor(xmax - dx) - 1.0, -1, (int32_t)W - 1);
        s.j0 = pvs__clampi(ceil(ymin + dx), 0, (int32_t)H);
        s.j1 = pvs__clampi(floor(ymax - dx) - 1.0, -1, (int32_t)H - 1);
    } else {
        s.i0 = pvs__clampi(floor(xmin - dx), 0, (int32_t)W);
        s.i1 = pvs__clampi(floor(xmax + dx), -1, (int32_t)W - 1);
        s.j0 = pvs__clampi(floor(ymin - dx), 0, (int32_t)H);
        s.j1 = pvs__clampi(floor(ymax + dx), -1, (int32_t)H - 1);
    }
    if (s.i0 > s.i1 || s.j0 > s.j1) return;
    if (tile_min) { /* hidden behind everything already drawn in every tile it overlaps: done */
        uint32_t tw = (W + PVS__TILE - 1) >> PVS__TILE_SHIFT, tx, ty, open = 0;
        float zb = pvs__f_up(zhi);
        for (ty = (uint32_t)s.j0 >> PVS__TILE_SHIFT; ty <= (uint32_t)s.j1 >> PVS__TILE_SHIFT && !open; ++ty)
            for (tx = (uint32_t)s.i0 >> PVS__TILE_SHIFT; tx <= (uint32_t)s.i1 >> PVS__TILE_SHIFT; ++tx)
                if (tile_min[ty * tw + tx] < zb) { open = 1; break; }
        if (!open) return;
    }
    if (!(mag < PVS__RASTER_BIG * PVS__RASTER_BIG)) { /* beyond any useful precision */
        if (!occluder) pvs__raster_fill(buf, W, H, tile_min, s.i0, s.i1, s.j0, s.j1, pvs__f_up(zhi));
        return;
    }
    span = (xmax - xmin) + (ymax - ymin);
    if (!(pvs__dabs(area2) > 1e-9 * span * span) || !(pvs__dabs(area2) > 1e-300)) {
        /* degenerate: nothing inside as an occluder, the whole box as an occludee */
        if (!occluder) pvs__raster_fill(buf, W, H, tile_min, s.i0, s.i1, s.j0, s.j1, pvs__f_up(zhi));
        return;
    }
    ox = (double)s.i0;
    oy = (double)s.j0;
    iw = (double)(s.i1 - s.i0);
    jh = (double)(s.j1 - s.j0);
    s.edges = 0;
    for (i = 0; i < n; ++i) {
        int j = i + 1 == n ? 0 : i + 1;
        double a = y[i] - y[j], b = x[j] - x[i], len, k, err, lo, hi;
        if (area2 < 0) { a = -a; b = -b; }
        len = pvs__dabs(a) + pvs__dabs(b);
        if (len == 0.0) continue;
        a /= len;
        b /= len;
        k = a * (ox - x[i]) + b * (oy - y[i]);
        k += occluder ? pvs__dmin(0.0, a) + pvs__dmin(0.0, b) : pvs__dmax(0.0, a) + pvs__dmax(0.0, b);
        err = (PVS__RASTER_ERR_D * (1.0 + mag) + perr) * (1.0 + (pvs__dabs(ox - x[i]) + pvs__dabs(oy - y[i]) + iw + jh + 2.0) / len) +
              PVS__RASTER_ERR_F * (pvs__dabs(k) + pvs__dabs(a) * iw + pvs__dabs(b) * jh + 1e-30);
        lo = k + pvs__dmin(0.0, a * iw) + pvs__dmin(0.0, b * jh); /* the extremes over the range */
        hi = k + pvs__dmax(0.0, a * iw) + pvs__dmax(0.0, b * jh);
        if (occluder) {
            if (lo - err >= 0.0) continue;  /* every pixel passes this edge */
            if (hi - err < 0.0) return;     /* no pixel does */
            k -= err;
        } else {
            if (lo + err >= 0.0) continue;
            if (hi + err < 0.0) return;
            k += err;
        }
        if (!(pvs__dabs(k) < PVS__RASTER_BIG)) return; /* cannot happen once the trivial cases are gone */
        s.a[s.edges] = (float)a;
        s.b[s.edges] = (float)b;
        s.k[s.edges] = (float)k;
        ++s.edges;
    }
    s.zclamp = occluder ? pvs__f_down(zlo) : pvs__f_up(zhi);
    pvs__raster_zplane(x, y, z, n, ox, oy, iw, jh, span, mag, zmag, perr, zerr, occluder, &s.za, &s.zb, &s.zk);
    pvs__raster_run(&s, buf, W, H, tile_min, occluder, simd, pvs__f_up(zhi));
}

/* ---- the occluder buffer: Masked Occlusion Culling (Hasselgren, Andersson and Akenine-Moller 2016)
   with inner coverage. Occluder-mode polygons go into tiles of 32 x 4 pixels (pvs__tile): per row of
   a tile the polygon's inner pixels are one run of columns, found from each edge's intercept with the
   row (the paper's per-scanline edge events turned into bit masks by shifts), and the tile keeps a
   working layer (mask, z1) over a base depth z0, merged by the paper's layer heuristic. A tile costs about as much as one pixel
   did, and a polygon drawn behind z0 costs one compare per tile. ---- */

#define PVS__TW_SHIFT 5
#define PVS__TH_SHIFT 2
#define PVS__TH 4
#define PVS__BLOCK_SHIFT 3 /* blocks of 8 x 8 tiles (256 x 32 pixels) for the prefilter's hidden test */
#define PVS__U_2_20 9.5367431640625e-07        /* 2^-20 */
#define PVS__U_2_21 4.76837158203125e-07       /* 2^-21 */
#define PVS__U_2_44 5.684341886080802e-14      /* 2^-44 */
#define PVS__U_2_48 3.552713678800501e-15      /* 2^-48 */

/* One occluder polygon prepared for the tile loops; columns i and rows j relative to (i0, j0).
   Pixel i of row j is inside edge e when i >= X_e(j) (e < nl: a left edge) or i <= X_e(j) (a right
   edge), X_e(j) = xi + s j: the exact line of the double edge function, pixel corner shift and
   setup margin included. The loops compute X in float; m bounds that rounding. */
typedef struct pvs__tpoly {
    int32_t i0, i1, j0, j1;    /* inner pixel range (absolute) */
    int32_t jlo, jhi;          /* rows (relative) left by the near-horizontal edges */
    int nl, ne;                /* edges [0, nl) bound from the left, [nl, ne) from the right */
    double xi[PVS__RASTER_MAXV], s[PVS__RASTER_MAXV], cl[PVS__RASTER_MAXV];
    float sf[PVS__RASTER_MAXV], m[PVS__RASTER_MAXV];
    float zk, za, zb, zm, zlo; /* depth plane at pixel corner (i0, j0), less its float margin zm, no
                                  farther than the vertices' farthest zlo */
} pvs__tpoly;

/* Columns L[d] .. R[d] (absolute; L > R when empty) of rows jrow + d (d = 0..3, relative) inside
   every edge, from xr[e] = X_e(jrow) in float. The reference loop; the SIMD ones do the same float
   operations lane by lane. */
PVS__STATIC void pvs__tile_rows_scalar(const pvs__tpoly *t, int32_t jrow, const float *xr, int32_t *L, int32_t *R) {
    const float fw = (float)(t->i1 - t->i0), fw1 = fw + 1.0f;
    int d, e;
    for (d = 0; d < PVS__TH; ++d) {
        float lf = 0.0f, rf = fw, fd = (float)d, v;
        int32_t l, r, j = jrow + d;
        for (e = 0; e < t->nl; ++e) {
            v = xr[e] + t->sf[e] * fd;
            v = v + t->m[e];
            lf = v > lf ? v : lf;
        }
        for (; e < t->ne; ++e) {
            v = xr[e] + t->sf[e] * fd;
            v = v - t->m[e];
            rf = v < rf ? v : rf;
        }
        lf = lf < fw1 ? lf : fw1;
        rf = rf > -1.0f ? rf : -1.0f;
        l = (int32_t)lf;
        if ((float)l < lf) ++l; /* ceil */
        r = (int32_t)rf;
        if ((float)r > rf) --r; /* floor */
        if (j < t->jlo || j > t->jhi) { l = 1; r = 0; }
        L[d] = l + t->i0;
        R[d] = r + t->i0;
    }
}

/* Mask bits of one tile row: columns L .. R of the tile starting at column x0 (bit k = column x0 + k). */
PVS__STATIC uint32_t pvs__tile_bits(int32_t L, int32_t R, int32_t x0) {
    int32_t lo = L - x0, hi = R - x0 + 1;
    uint32_t a, b;
    lo = lo < 0 ? 0 : lo;
    hi = hi < 0 ? 0 : hi;
    a = lo >= 32 ? 0u : ~0u << lo;
    b = hi >= 32 ? 0u : ~0u << hi;
    return a & ~b;
}

#if defined(PVS__SSE2)
PVS__STATIC void pvs__tile_rows_simd(const pvs__tpoly *t, int32_t jrow, const float *xr, int32_t *L, int32_t *R) {
    const __m128 d = _mm_set_ps(3.0f, 2.0f, 1.0f, 0.0f), fw = _mm_set1_ps((float)(t->i1 - t->i0));
    __m128 lf = _mm_setzero_ps(), rf = fw, v;
    __m128i l, r, j, bad;
    int e;
    for (e = 0; e < t->nl; ++e) {
        v = _mm_add_ps(_mm_set1_ps(xr[e]), _mm_mul_ps(_mm_set1_ps(t->sf[e]), d));
        v = _mm_add_ps(v, _mm_set1_ps(t->m[e]));
        lf = _mm_max_ps(v, lf);
    }
    for (; e < t->ne; ++e) {
        v = _mm_add_ps(_mm_set1_ps(xr[e]), _mm_mul_ps(_mm_set1_ps(t->sf[e]), d));
        v = _mm_sub_ps(v, _mm_set1_ps(t->m[e]));
        rf = _mm_min_ps(v, rf);
    }
    lf = _mm_min_ps(lf, _mm_add_ps(fw, _mm_set1_ps(1.0f)));
    rf = _mm_max_ps(rf, _mm_set1_ps(-1.0f));
    l = _mm_cvttps_epi32(lf);
    l = _mm_sub_epi32(l, _mm_castps_si128(_mm_cmplt_ps(_mm_cvtepi32_ps(l), lf)));
    r = _mm_cvttps_epi32(rf);
    r = _mm_add_epi32(r, _mm_castps_si128(_mm_cmpgt_ps(_mm_cvtepi32_ps(r), rf)));
    j = _mm_add_epi32(_mm_set1_epi32(jrow), _mm_set_epi32(3, 2, 1, 0));
    bad = _mm_or_si128(_mm_cmplt_epi32(j, _mm_set1_epi32(t->jlo)), _mm_cmpgt_epi32(j, _mm_set1_epi32(t->jhi)));
    l = _mm_or_si128(_mm_andnot_si128(bad, l), _mm_and_si128(bad, _mm_set1_epi32(1)));
    r = _mm_andnot_si128(bad, r);
    _mm_storeu_si128((__m128i *)L, _mm_add_epi32(l, _mm_set1_epi32(t->i0)));
    _mm_storeu_si128((__m128i *)R, _mm_add_epi32(r, _mm_set1_epi32(t->i0)));
}
/* ~0 << n per lane for n >= 0 (0 for n >= 32): 2^n built in a float's exponent, converted (2^31
   converts to 0x80000000, which is 1 << 31), negated. */
PVS__STATIC __m128i pvs__sh_sse2(__m128i n) {
    __m128i p = _mm_cvttps_epi32(_mm_castsi128_ps(_mm_slli_epi32(_mm_add_epi32(n, _mm_set1_epi32(127)), 23)));
    return _mm_and_si128(_mm_sub_epi32(_mm_setzero_si128(), p), _mm_cmplt_epi32(n, _mm_set1_epi32(32)));
}
/* The four rows' bits of the tile at column x0; returns 0 when all are empty. */
PVS__STATIC int pvs__tile_mask_simd(const int32_t *L, const int32_t *R, int32_t x0, uint32_t *out) {
    __m128i vx = _mm_set1_epi32(x0), lo, hi, m;
    lo = _mm_sub_epi32(_mm_loadu_si128((const __m128i *)L), vx);
    hi = _mm_sub_epi32(_mm_add_epi32(_mm_loadu_si128((const __m128i *)R), _mm_set1_epi32(1)), vx);
    lo = _mm_andnot_si128(_mm_srai_epi32(lo, 31), lo);
    hi = _mm_andnot_si128(_mm_srai_epi32(hi, 31), hi);
    m = _mm_andnot_si128(pvs__sh_sse2(hi), pvs__sh_sse2(lo));
    _mm_storeu_si128((__m128i *)out, m);
    return _mm_movemask_epi8(_mm_cmpeq_epi32(m, _mm_setzero_si128())) != 0xffff;
}
#define PVS__HAVE_TILE_SIMD 1
#elif defined(PVS__NEON)
PVS__STATIC void pvs__tile_rows_simd(const pvs__tpoly *t, int32_t jrow, const float *xr, int32_t *L, int32_t *R) {
    static const float df[4] = {0.0f, 1.0f, 2.0f, 3.0f};
    static const int32_t di[4] = {0, 1, 2, 3};
    const float32x4_t d = vld1q_f32(df), fw = vdupq_n_f32((float)(t->i1 - t->i0));
    float32x4_t lf = vdupq_n_f32(0.0f), rf = fw, v;
    int32x4_t l, r, j;
    uint32x4_t bad;
    int e;
    for (e = 0; e < t->nl; ++e) {
        v = vaddq_f32(vdupq_n_f32(xr[e]), vmulq_f32(vdupq_n_f32(t->sf[e]), d));
        v = vaddq_f32(v, vdupq_n_f32(t->m[e]));
        lf = vbslq_f32(vcgtq_f32(v, lf), v, lf);
    }
    for (; e < t->ne; ++e) {
        v = vaddq_f32(vdupq_n_f32(xr[e]), vmulq_f32(vdupq_n_f32(t->sf[e]), d));
        v = vsubq_f32(v, vdupq_n_f32(t->m[e]));
        rf = vbslq_f32(vcltq_f32(v, rf), v, rf);
    }
    v = vaddq_f32(fw, vdupq_n_f32(1.0f));
    lf = vbslq_f32(vcltq_f32(lf, v), lf, v);
    v = vdupq_n_f32(-1.0f);
    rf = vbslq_f32(vcgtq_f32(rf, v), rf, v);
    l = vcvtq_s32_f32(lf);
    l = vsubq_s32(l, vreinterpretq_s32_u32(vcltq_f32(vcvtq_f32_s32(l), lf)));
    r = vcvtq_s32_f32(rf);
    r = vaddq_s32(r, vreinterpretq_s32_u32(vcgtq_f32(vcvtq_f32_s32(r), rf)));
    j = vaddq_s32(vdupq_n_s32(jrow), vld1q_s32(di));
    bad = vorrq_u32(vcltq_s32(j, vdupq_n_s32(t->jlo)), vcgtq_s32(j, vdupq_n_s32(t->jhi)));
    l = vbslq_s32(bad, vdupq_n_s32(1), l);
    r = vbslq_s32(bad, vdupq_n_s32(0), r);
    vst1q_s32(L, vaddq_s32(l, vdupq_n_s32(t->i0)));
    vst1q_s32(R, vaddq_s32(r, vdupq_n_s32(t->i0)));
}
PVS__STATIC int pvs__tile_mask_simd(const int32_t *L, const int32_t *R, int32_t x0, uint32_t *out) {
    int32x4_t vx = vdupq_n_s32(x0), zero = vdupq_n_s32(0), top = vdupq_n_s32(32), lo, hi;
    uint32x4_t ones = vdupq_n_u32(~0u), m;
    lo = vsubq_s32(vld1q_s32(L), vx);
    hi = vsubq_s32(vaddq_s32(vld1q_s32(R), vdupq_n_s32(1)), vx);
    lo = vminq_s32(vmaxq_s32(lo, zero), top); /* a register shift by >= 32 gives 0 */
    hi = vminq_s32(vmaxq_s32(hi, zero), top);
    m = vbicq_u32(vshlq_u32(ones, lo), vshlq_u32(ones, hi));
    vst1q_u32(out, m);
    return (vgetq_lane_u32(m, 0) | vgetq_lane_u32(m, 1) | vgetq_lane_u32(m, 2) | vgetq_lane_u32(m, 3)) != 0;
}
#define PVS__HAVE_TILE_SIMD 1
#endif

/* Merges polygon coverage T (at least as near as zt, zt > z0) into a tile (Hasselgren et al.'s
   two-layer update, in reversed depth): a polygon covering the tile becomes its base; otherwise the
   working layer takes the union at the farther of the two depths, unless the polygon is nearer than
   the working layer by more than the working layer is nearer than the base, which drops the working
   layer; a full working layer becomes the base. Every step keeps each pixel's value a lower bound of
   its nearest occluder. `pad`: bits outside the map. */
PVS__STATIC void pvs__tile_merge(pvs__tile *tl, const uint32_t *T, float zt, const uint32_t *pad) {
    uint32_t full = ~0u, any = 0, m;
    int k;
    for (k = 0; k < PVS__TH; ++k) {
        full &= T[k] | pad[k];
        any |= tl->mask[k];
    }
    if (full == ~0u) {
        if (!(any && tl->z1 > zt))
            for (k = 0; k < PVS__TH; ++k) tl->mask[k] = 0;
        tl->z0 = zt;
        return;
    }
    if (!any || zt - tl->z1 > tl->z1 - tl->z0) {
        for (k = 0; k < PVS__TH; ++k) tl->mask[k] = T[k];
        tl->z1 = zt;
        return;
    }
    full = ~0u;
    for (k = 0; k < PVS__TH; ++k) {
        m = tl->mask[k] | T[k];
        tl->mask[k] = m;
        full &= m | pad[k];
    }
    if (zt < tl->z1) tl->z1 = zt;
    if (full == ~0u) {
        for (k = 0; k < PVS__TH; ++k) tl->mask[k] = 0;
        tl->z0 = tl->z1;
    }
}

/* Walks the tile rows of a prepared polygon: per row the runs of the four pixel rows, then per tile
   the polygon's farthest depth over the run's rectangle (the plane at its corners, less the margin,
   clamped by the vertices); tiles whose base is already at least that near are skipped before any
   coverage is computed. */
PVS__STATIC void pvs__tile_run(pvs_raster *r, const pvs__tpoly *t, int simd) {
    int32_t ty, ty0 = (t->j0 + t->jlo) >> PVS__TH_SHIFT, ty1 = (t->j0 + t->jhi) >> PVS__TH_SHIFT;
    float xr[PVS__RASTER_MAXV];
    (void)simd;
    for (ty = ty0; ty <= ty1; ++ty) {
        int32_t jr = ty << PVS__TH_SHIFT, jrow = jr - t->j0, L[PVS__TH], R[PVS__TH], lmin = INT32_MAX, rmax = -1, tx;
        int32_t fl = -1, fr = INT32_MAX; /* columns every row of the tile row covers */
        int d, e, da = -1, db = -1;
        uint32_t pad[PVS__TH], cov[PVS__TH];
        float ya, yb, zy, p, zt, z0;
        pvs__tile *row = r->tile + (size_t)ty * r->tw;
        for (e = 0; e < t->ne; ++e) {
            double X = t->xi[e] + t->s[e] * (double)jrow;
            X = X < -t->cl[e] ? -t->cl[e] : X > t->cl[e] ? t->cl[e] : X;
            xr[e] = (float)X;
        }
#if defined(PVS__HAVE_TILE_SIMD)
        if (simd) pvs__tile_rows_simd(t, jrow, xr, L, R);
        else
#endif
            pvs__tile_rows_scalar(t, jrow, xr, L, R);
        for (d = 0; d < PVS__TH; ++d) {
            if (L[d] > R[d]) {
                if (jr + d < (int32_t)r->height) fr = -2; /* an empty row inside the map: no tile is full */
                continue;
            }
            lmin = L[d] < lmin ? L[d] : lmin;
            rmax = R[d] > rmax ? R[d] : rmax;
            fl = L[d] > fl ? L[d] : fl;
            fr = R[d] < fr ? R[d] : fr;
            if (da < 0) da = d;
            db = d;
        }
        if (da < 0) continue;
        ya = (float)(jr + da - t->j0);
        yb = (float)(jr + db + 1 - t->j0);
        ya = t->zb * ya;
        yb = t->zb * yb;
        zy = ya < yb ? ya : yb;
        for (d = 0; d < PVS__TH; ++d) pad[d] = (uint32_t)ty == r->th - 1 && (uint32_t)d >= r->ypad ? ~0u : 0u;
        for (tx = lmin >> PVS__TW_SHIFT; tx <= rmax >> PVS__TW_SHIFT; ++tx) {
            pvs__tile *tl = row + tx;
            int32_t x0 = tx << PVS__TW_SHIFT, xa = x0 > lmin ? x0 : lmin, xb = (x0 + 31 < rmax ? x0 + 31 : rmax) + 1;
            float fa = t->za * (float)(xa - t->i0), fb = t->za * (float)(xb - t->i0);
            p = t->zk + (fa < fb ? fa : fb);
            p = p + zy;
            p = p - t->zm;
            zt = p > t->zlo ? p : t->zlo;
            if (!(zt > tl->z0)) continue; /* nothing nearer than the tile's base */
            if (x0 >= fl && (x0 + 31 < (int32_t)r->width ? x0 + 31 : (int32_t)r->width - 1) <= fr) {
                /* the polygon covers the tile: pvs__tile_merge's first case */
                if (!((tl->mask[0] | tl->mask[1] | tl->mask[2] | tl->mask[3]) && tl->z1 > zt))
                    tl->mask[0] = tl->mask[1] = tl->mask[2] = tl->mask[3] = 0;
                tl->z0 = zt;
                r->bdirty[(size_t)(ty >> PVS__BLOCK_SHIFT) * r->bw + (uint32_t)(tx >> PVS__BLOCK_SHIFT)] = 1;
                continue;
            }
#if defined(PVS__HAVE_TILE_SIMD)
            if (simd) {
                if (!pvs__tile_mask_simd(L, R, x0, cov)) continue;
            } else
#endif
            {
                uint32_t any = 0;
                for (d = 0; d < PVS__TH; ++d) any |= cov[d] = pvs__tile_bits(L[d], R[d], x0);
                if (!any) continue;
            }
            z0 = tl->z0;
            if ((uint32_t)tx == r->tw - 1) {
                uint32_t q[PVS__TH];
                for (d = 0; d < PVS__TH; ++d) q[d] = pad[d] | r->xpad;
                pvs__tile_merge(tl, cov, zt, q);
            } else {
                pvs__tile_merge(tl, cov, zt, pad);
            }
            if (tl->z0 != z0) r->bdirty[(size_t)(ty >> PVS__BLOCK_SHIFT) * r->bw + (uint32_t)(tx >> PVS__BLOCK_SHIFT)] = 1;
        }
    }
}

/* Prepares an occluder polygon given in pixel coordinates (x, y), depth z, with the vertices' own
   error perr (pixels) and zerr (depth), and draws it into the tiles. The edge and plane setup and its
   margins are pvs__raster_poly's; see the comment at the top. */
PVS__STATIC void pvs__tile_poly(pvs_raster *r, const double *x, const double *y, const double *z, int n, double perr, double zerr) {
    pvs__tpoly t;
    double xmin = x[0], xmax = x[0], ymin = y[0], ymax = y[0], zmin = z[0], zmax = z[0], area2 = 0.0, mag = 0.0, zmag = 0.0;
    double span, dx, ox, oy, iw, jh, zlo, rxi[PVS__RASTER_MAXV], rs[PVS__RASTER_MAXV], rcl[PVS__RASTER_MAXV];
    float rsf[PVS__RASTER_MAXV], rm[PVS__RASTER_MAXV];
    int i, best = -1, nr = 0;
    if (n < 3) return;
    for (i = 0; i < n; ++i) {
        int j = i + 1 == n ? 0 : i + 1;
        if (!(x[i] == x[i] && y[i] == y[i] && z[i] == z[i])) return; /* NaN */
        xmin = pvs__dmin(xmin, x[i]); xmax = pvs__dmax(xmax, x[i]);
        ymin = pvs__dmin(ymin, y[i]); ymax = pvs__dmax(ymax, y[i]);
        zmin = pvs__dmin(zmin, z[i]); zmax = pvs__dmax(zmax, z[i]);
        area2 += x[i] * y[j] - x[j] * y[i];
        mag = pvs__dmax(mag, pvs__dabs(x[i]) + pvs__dabs(y[i]));
        zmag = pvs__dmax(zmag, pvs__dabs(z[i]));
    }
    dx = PVS__RASTER_ERR_D * (mag + 1.0) + perr;
    zlo = zmin - PVS__RASTER_ERR_D * zmag - zerr;
    t.i0 = pvs__clampi(ceil(xmin + dx), 0, (int32_t)r->width);
    t.i1 = pvs__clampi(floor(xmax - dx) - 1.0, -1, (int32_t)r->width - 1);
    t.j0 = pvs__clampi(ceil(ymin + dx), 0, (int32_t)r->height);
    t.j1 = pvs__clampi(floor(ymax - dx) - 1.0, -1, (int32_t)r->height - 1);
    if (t.i0 > t.i1 || t.j0 > t.j1) return;
    if (!(mag < PVS__RASTER_BIG * PVS__RASTER_BIG)) return;
    span = (xmax - xmin) + (ymax - ymin);
    if (!(pvs__dabs(area2) > 1e-9 * span * span) || !(pvs__dabs(area2) > 1e-300)) return; /* degenerate: covers nothing */
    ox = (double)t.i0;
    oy = (double)t.j0;
    iw = (double)(t.i1 - t.i0);
    jh = (double)(t.j1 - t.j0);
    t.jlo = 0;
    t.jhi = t.j1 - t.j0;
    t.nl = 0;
    for (i = 0; i < n; ++i) {
        int j = i + 1 == n ? 0 : i + 1;
        double a = y[i] - y[j], b = x[j] - x[i], len, k, err, lo, hi;
        if (area2 < 0) { a = -a; b = -b; }
        len = pvs__dabs(a) + pvs__dabs(b);
        if (len == 0.0) continue;
        a /= len;
        b /= len;
        /* inner coverage: the edge function at the pixel's worst corner, less the setup error */
        k = a * (ox - x[i]) + b * (oy - y[i]) + pvs__dmin(0.0, a) + pvs__dmin(0.0, b);
        err = (PVS__RASTER_ERR_D * (1.0 + mag) + perr) * (1.0 + (pvs__dabs(ox - x[i]) + pvs__dabs(oy - y[i]) + iw + jh + 2.0) / len);
        lo = k + pvs__dmin(0.0, a * iw) + pvs__dmin(0.0, b * jh);
        hi = k + pvs__dmax(0.0, a * iw) + pvs__dmax(0.0, b * jh);
        if (lo - err >= 0.0) continue; /* every pixel passes this edge */
        if (hi - err < 0.0) return;    /* no pixel does */
        k -= err;
        if (!(pvs__dabs(k) < PVS__RASTER_BIG)) return;
        if (pvs__dabs(a) > pvs__dabs(b) * PVS__U_2_20) {
            /* pixel i of row j passes when a i + b j + k >= 0: i >= X(j) for a > 0, i <= X(j) for a < 0.
               The loops clamp X(jrow) to +-cl (beyond it every row of the tile row falls on the same
               side of the range) and evaluate X in float: at most 3 cl + 13 |s| units of 2^-24 and
               the double part 2^-51 (|xi| + |s| |jrow|), below m. */
            double xi = -k / a, sl = -b / a, sa = pvs__dabs(sl), cl = iw + 3.0 + 3.0 * sa;
            float m = pvs__f_up(PVS__U_2_21 * cl + PVS__U_2_48 * (pvs__dabs(xi) + sa * (jh + 4.0)));
            if (a > 0.0) {
                t.xi[t.nl] = xi; t.s[t.nl] = sl; t.cl[t.nl] = cl; t.sf[t.nl] = (float)sl; t.m[t.nl] = m;
                ++t.nl;
            } else {
                rxi[nr] = xi; rs[nr] = sl; rcl[nr] = cl; rsf[nr] = (float)sl; rm[nr] = m;
                ++nr;
            }
        } else {
            /* near-horizontal: the rows where the edge passes for every column of the range */
            double wk = k + pvs__dmin(0.0, a * iw), tq = -wk / b, pad = PVS__U_2_44 * (pvs__dabs(k) + pvs__dabs(a) * iw + 1.0);
            if (b > 0.0) {
                int32_t jl = pvs__clampi(ceil(tq + pad), 0, t.jhi + 1);
                if (jl > t.jlo) t.jlo = jl;
            } else {
                int32_t jm = pvs__clampi(floor(tq - pad), -1, t.jhi);
                if (jm < t.jhi) t.jhi = jm;
            }
        }
    }
    if (t.jlo > t.jhi) return;
    t.ne = t.nl + nr;
    for (i = 0; i < nr; ++i) {
        t.xi[t.nl + i] = rxi[i]; t.s[t.nl + i] = rs[i]; t.cl[t.nl + i] = rcl[i]; t.sf[t.nl + i] = rsf[i]; t.m[t.nl + i] = rm[i];
    }
    /* depth plane from the largest fan triangle, at pixel corner (i0, j0), lowered by its setup error */
    {
        double amax = 0.0;
        for (i = 1; i + 1 < n; ++i) {
            double a2 = pvs__dabs((x[i] - x[0]) * (y[i + 1] - y[0]) - (x[i + 1] - x[0]) * (y[i] - y[0]));
            if (a2 > amax) { amax = a2; best = i; }
        }
    }
    t.zlo = pvs__f_down(zlo);
    t.za = t.zb = t.zm = 0.0f;
    t.zk = -FLT_MAX;
    if (best > 0) {
        double x1 = x[best] - x[0], y1 = y[best] - y[0], z1 = z[best] - z[0];
        double x2 = x[best + 1] - x[0], y2 = y[best + 1] - y[0], z2 = z[best + 1] - z[0];
        double det = x1 * y2 - x2 * y1;
        double za = (z1 * y2 - z2 * y1) / det, zb = (x1 * z2 - x2 * z1) / det;
        double zk = z[0] + za * (ox - x[0]) + zb * (oy - y[0]), err, size;
        err = zerr + (pvs__dabs(za) + pvs__dabs(zb)) * perr * (1.0 + (span + iw + jh + 2.0) * span / pvs__dabs(det)) +
              PVS__RASTER_ERR_D * (zmag + (pvs__dabs(za) + pvs__dabs(zb)) * (mag + ox + oy + iw + jh + 2.0)) *
                  (1.0 + (span + ox + oy + iw + jh + 2.0) * span / pvs__dabs(det));
        zk -= err;
        /* the loops' float evaluation zk + za x + zb y - zm over x <= iw + 1, y <= jh + 1: coefficient
           rounding and four operations, at most 6 units of 2^-24 of `size` */
        size = pvs__dabs(zk) + pvs__dabs(za) * (iw + 1.0) + pvs__dabs(zb) * (jh + 1.0);
        if (size < 1e30 && err < 1e30) {
            t.za = (float)za;
            t.zb = (float)zb;
            t.zk = (float)zk;
            t.zm = pvs__f_up(PVS__U_2_20 * size);
        }
    }
    pvs__tile_run(r, &t, !(r->flags & PVS_RASTER_SCALAR));
}

/* Occludee triangles (and all triangles when not tiled) go to the per-pixel map, cleared on the first
   one after pvs_raster_clear. */
PVS__STATIC void pvs__raster_occludee_begin(pvs_raster *r) {
    size_t i, n = (size_t)r->width * r->height;
    if (r->mixed) return;
    for (i = 0; i < n; ++i) r->depth[i] = PVS_DEPTH_EMPTY;
    for (i = 0; i < r->tiles; ++i) r->tile_min[i] = PVS_DEPTH_EMPTY;
    r->mixed = 1;
}

/* The per-pixel depth map from the tiles: overwritten, or where occludee triangles were drawn into it
   (r->mixed) the nearer of the two. */
PVS__STATIC void pvs__tile_resolve(pvs_raster *r) {
    uint32_t ty, tx, d, k;
    if (!r->tiled) {
        pvs__raster_occludee_begin(r); /* nothing drawn yet: the cleared map */
        return;
    }
    for (ty = 0; ty < r->th; ++ty)
        for (d = 0; d < PVS__TH && (ty << PVS__TH_SHIFT) + d < r->height; ++d) {
            float *row = r->depth + (size_t)((ty << PVS__TH_SHIFT) + d) * r->width;
            for (tx = 0; tx < r->tw; ++tx) {
                const pvs__tile *tl = r->tile + (size_t)ty * r->tw + tx;
                for (k = 0; k < 32 && (tx << PVS__TW_SHIFT) + k < r->width; ++k) {
                    float v = (tl->mask[d] >> k) & 1u ? tl->z1 : tl->z0, *px = row + (tx << PVS__TW_SHIFT) + k;
                    if (!r->mixed || v > *px) *px = v;
                }
            }
        }
}


/* Clip-space vertex (double). */
typedef struct pvs__cv {
    double c[4];
    double e;  /* a bound on the rounding error of each coordinate */
} pvs__cv;

PVS__STATIC pvs__cv pvs__raster_transform(const pvs_raster *rs, const float *p) {
    const double *m = rs->m;
    pvs__cv v;
    int r;
    double pm = pvs__dmax(pvs__dabs(p[0]), pvs__dmax(pvs__dabs(p[1]), pvs__dabs(p[2])));
    for (r = 0; r < 4; ++r)
        v.c[r] = m[4 * r] * (double)p[0] + m[4 * r + 1] * (double)p[1] + m[4 * r + 2] * (double)p[2] + m[4 * r + 3];
    /* 2^-50 of the terms' size (four products summed in double need 2^-51): see pvs_raster_set_matrix */
    v.e = 8.881784197001252e-16 * (rs->mabs[0] * pm + rs->mabs[1]);
    return v;
}

/* Sutherland-Hodgman against f(v) >= 0 with f = w - z (near plane) or f = w - tiny (w > 0). With
   labels (lin[i]: what the edge from vertex i to i + 1 is; NULL for none), lout gets the output edges'
   labels: a part of input edge i keeps lin[i], an edge along the plane gets PVS__MESH_CLIP; and a cut
   point is interpolated from the edge's inside vertex, so two polygons sharing an edge cut it at the
   same point bit for bit. */
#define PVS__MESH_CLIP 3
PVS__STATIC int pvs__raster_clip(const pvs__cv *in, int n, pvs__cv *out, int plane, const uint8_t *lin, uint8_t *lout) {
    int i, m = 0;
    for (i = 0; i < n; ++i) {
        const pvs__cv *a = in + i, *b = in + (i + 1 == n ? 0 : i + 1);
        double fa = plane == 0 ? a->c[3] - a->c[2] : a->c[3] - 1e-30;
        double fb = plane == 0 ? b->c[3] - b->c[2] : b->c[3] - 1e-30;
        if (fa >= 0.0) {
            if (lin) lout[m] = lin[i];
            out[m++] = *a;
        }
        if ((fa >= 0.0) != (fb >= 0.0)) {
            double t = fa / (fa - fb);
            int k;
            if (lin) {
                lout[m] = fa >= 0.0 ? (uint8_t)PVS__MESH_CLIP : lin[i];
                if (fa < 0.0) { /* from the inside vertex b */
                    const pvs__cv *c = a;
                    a = b;
                    b = c;
                    t = fb / (fb - fa);
                }
            }
            for (k = 0; k < 4; ++k) out[m].c[k] = a->c[k] + (b->c[k] - a->c[k]) * t;
            out[m].e = 2.0 * pvs__dmax(a->e, b->e);
            if (plane == 0) out[m].c[2] = out[m].c[3]; /* exactly on the near plane */
            else if (out[m].c[3] < 1e-30) out[m].c[3] = 1e-30;
            ++m;
        }
    }
    return m;
}

/* Projects a clipped polygon to pixel coordinates and rasterizes it. */
PVS__STATIC void pvs__raster_clipped(pvs_raster *r, const pvs__cv *v, int n, int occluder) {
    pvs__cv t1[PVS__RASTER_MAXV], t2[PVS__RASTER_MAXV];
    double x[PVS__RASTER_MAXV], y[PVS__RASTER_MAXV], z[PVS__RASTER_MAXV];
    double hw = 0.5 * (double)r->width, hh = 0.5 * (double)r->height, perr = 0.0, zerr = 0.0;
    int i;
    const pvs__cv *t = v;
    for (i = 0; i < n; ++i)
        if (!(v[i].c[3] - v[i].c[2] >= 0.0) || !(v[i].c[3] >= 1e-30)) break;
    if (i < n) { /* something to clip */
        n = pvs__raster_clip(v, n, t1, 0, NULL, NULL);
        if (n < 3) return;
        n = pvs__raster_clip(t1, n, t2, 1, NULL, NULL);
        if (n < 3) return;
        t = t2;
    }
    for (i = 0; i < n; ++i) {
        double iw = 1.0 / t[i].c[3], e = t[i].e * iw;
        x[i] = (t[i].c[0] * iw + 1.0) * hw;
        y[i] = (t[i].c[1] * iw + 1.0) * hh;
        z[i] = t[i].c[2] * iw;
        /* the coordinates' error after the division, in pixels and in depth */
        perr = pvs__dmax(perr, 2.0 * e * (1.0 + pvs__dabs(t[i].c[0] * iw) + pvs__dabs(t[i].c[1] * iw)) * pvs__dmax(hw, hh));
        zerr = pvs__dmax(zerr, 2.0 * e * (1.0 + pvs__dabs(z[i])));
    }
    if (occluder && r->tiled) {
        pvs__tile_poly(r, x, y, z, n, perr, zerr);
    } else {
        pvs__raster_occludee_begin(r);
        pvs__raster_poly(r->depth, r->width, r->height, r->tile_min, x, y, z, n, occluder, !(r->flags & PVS_RASTER_SCALAR), perr, zerr);
    }
}

PVS__STATIC void pvs__raster_tri(pvs_raster *r, const float *p0, const float *p1, const float *p2, int occluder) {
    pvs__cv v[3];
    int k;
    for (k = 0; k < 3; ++k)
        if (!pvs__finite(p0[k]) || !pvs__finite(p1[k]) || !pvs__finite(p2[k])) return;
    v[0] = pvs__raster_transform(r, p0);
    v[1] = pvs__raster_transform(r, p1);
    v[2] = pvs__raster_transform(r, p2);
    /* all three behind the near plane or w <= 0: nothing to draw */
    if (v[0].c[3] - v[0].c[2] < 0 && v[1].c[3] - v[1].c[2] < 0 && v[2].c[3] - v[2].c[2] < 0) return;
    if (v[0].c[3] <= 0 && v[1].c[3] <= 0 && v[2].c[3] <= 0) return;
    pvs__raster_clipped(r, v, 3, occluder);
    r->pyramid_valid = 0;
}

/* ---- occluder prefilter: four triangles at a time in float, as Masked Occlusion Culling sets up
   triangles in SIMD lanes. It only drops triangles: ones behind the near plane, outside a side
   of the screen, without a whole pixel in their bounding box, or no nearer than the base of every
   tile under that box. Dropping an occluder is always conservative, so these tests need no error
   margins; rounding at their borders drops at most a sliver the exact path might have drawn. The
   rest go to the exact path (pvs__raster_tri). The scalar and SIMD loops do the same float
   operations and decide the same. ---- */

#define PVS__PF_TILES 16 /* the hidden test looks at tiles one by one in boxes up to this size */

/* Returns the lanes to draw (bit l); those in *test (a subset) only when their box is not hidden:
   box[0..3][l] = i0, i1, j0, j1 hold the whole pixels of the float bounding box clamped to the map
   (not empty) and zmax[l] the nearest vertex depth. Lanes with a vertex behind the near plane or the
   eye plane are drawn untested (the exact path clips them) unless all three are behind one of them;
   lanes in front are dropped when their clamped box holds no whole pixel (which includes being off
   the map). */
PVS__STATIC unsigned pvs__pf_scalar(const pvs_raster *r, const float *const v[4][3], unsigned *test, int32_t box[4][4], float *zmax) {
    const float *m = r->mf, hw = r->hwf, hh = r->hhf, fw = (float)r->width, fh = (float)r->height;
    int l, k;
    unsigned draw = 0;
    *test = 0;
    for (l = 0; l < 4; ++l) {
        float cz[3], cw[3], x, y, z, xmin = 0.0f, xmax = 0.0f, ymin = 0.0f, ymax = 0.0f, zm = 0.0f, f;
        int behind = 0, nonpos = 0, fin = 1;
        int32_t i0, i1, j0, j1;
        for (k = 0; k < 3; ++k) {
            float X = v[l][k][0], Y = v[l][k][1], Z = v[l][k][2];
            cz[k] = m[8] * X + m[9] * Y + m[10] * Z + m[11];
            cw[k] = m[12] * X + m[13] * Y + m[14] * Z + m[15];
            behind += cz[k] > cw[k];
            nonpos += cw[k] <= 0.0f;
        }
        if (behind == 3 || nonpos == 3) continue;
        draw |= 1u << l;
        if (behind || nonpos) continue;
        for (k = 0; k < 3; ++k) {
            float X = v[l][k][0], Y = v[l][k][1], Z = v[l][k][2], rw = 1.0f / cw[k];
            x = (m[0] * X + m[1] * Y + m[2] * Z + m[3]) * rw * hw + hw;
            y = (m[4] * X + m[5] * Y + m[6] * Z + m[7]) * rw * hh + hh;
            z = cz[k] * rw;
            if (k == 0) {
                xmin = xmax = x; ymin = ymax = y; zm = z;
            } else {
                xmin = x < xmin ? x : xmin; xmax = x > xmax ? x : xmax;
                ymin = y < ymin ? y : ymin; ymax = y > ymax ? y : ymax;
                zm = z > zm ? z : zm;
            }
        }
        fin = (xmin < 0.0f ? 0.0f - xmin : xmin) < 1e30f && (xmax < 0.0f ? 0.0f - xmax : xmax) < 1e30f;
        fin &= (ymin < 0.0f ? 0.0f - ymin : ymin) < 1e30f && (ymax < 0.0f ? 0.0f - ymax : ymax) < 1e30f;
        fin &= (zm < 0.0f ? 0.0f - zm : zm) < 1e30f;
        if (!fin) continue;
        xmin = xmin > 0.0f ? xmin : 0.0f; xmax = xmax < fw ? xmax : fw;
        ymin = ymin > 0.0f ? ymin : 0.0f; ymax = ymax < fh ? ymax : fh;
        /* ceil of the mins, floor of the maxes less one */
        f = (float)(int32_t)xmin; i0 = (int32_t)xmin + (f < xmin);
        f = (float)(int32_t)xmax; i1 = (int32_t)xmax - (f > xmax) - 1;
        f = (float)(int32_t)ymin; j0 = (int32_t)ymin + (f < ymin);
        f = (float)(int32_t)ymax; j1 = (int32_t)ymax - (f > ymax) - 1;
        if (i0 > i1 || j0 > j1) { draw &= ~(1u << l); continue; }
        box[0][l] = i0; box[1][l] = i1; box[2][l] = j0; box[3][l] = j1;
        zmax[l] = zm;
        *test |= 1u << l;
    }
    return draw;
}

#if defined(PVS__SSE2)
/* Each v[l][k] has 4 readable floats (the caller copies a last vertex); mb: the matrix broadcast. */
PVS__STATIC unsigned pvs__pf_simd(const pvs_raster *r, const __m128 *mb, const float *const v[4][3], unsigned *test, int32_t box[4][4], float *zmax) {
    const __m128 zero = _mm_setzero_ps(), absm = _mm_castsi128_ps(_mm_set1_epi32(0x7fffffff)), big = _mm_set1_ps(1e30f);
    __m128 X0, Y0, Z0, X1, Y1, Z1, X2, Y2, Z2, cz0, cz1, cz2, cw0, cw1, cw2, t, anyb, allb, fin;
    __m128 x, y, z, xmin, xmax, ymin, ymax, zm, rw;
    __m128i i0, i1, j0, j1, empty;
    unsigned all, any, tst;
#define PVS__LOAD3(k, X, Y, Z) do { /* four vertices (x, y, z, -) to X, Y, Z lanes */ \
        __m128 a = _mm_loadu_ps(v[0][k]), b = _mm_loadu_ps(v[1][k]), c = _mm_loadu_ps(v[2][k]), d = _mm_loadu_ps(v[3][k]); \
        __m128 ab0 = _mm_unpacklo_ps(a, b), cd0 = _mm_unpacklo_ps(c, d), ab1 = _mm_unpackhi_ps(a, b), cd1 = _mm_unpackhi_ps(c, d); \
        X = _mm_movelh_ps(ab0, cd0); Y = _mm_movehl_ps(cd0, ab0); Z = _mm_movelh_ps(ab1, cd1); } while (0)
#define PVS__ROW(o, X, Y, Z) _mm_add_ps(_mm_add_ps(_mm_add_ps(_mm_mul_ps(mb[o], X), _mm_mul_ps(mb[o + 1], Y)), _mm_mul_ps(mb[o + 2], Z)), mb[o + 3])
    PVS__LOAD3(0, X0, Y0, Z0);
    PVS__LOAD3(1, X1, Y1, Z1);
    PVS__LOAD3(2, X2, Y2, Z2);
    cz0 = PVS__ROW(8, X0, Y0, Z0); cw0 = PVS__ROW(12, X0, Y0, Z0);
    cz1 = PVS__ROW(8, X1, Y1, Z1); cw1 = PVS__ROW(12, X1, Y1, Z1);
    cz2 = PVS__ROW(8, X2, Y2, Z2); cw2 = PVS__ROW(12, X2, Y2, Z2);
    t = _mm_cmpgt_ps(cz0, cw0); anyb = t; allb = t;
    t = _mm_cmpgt_ps(cz1, cw1); anyb = _mm_or_ps(anyb, t); allb = _mm_and_ps(allb, t);
    t = _mm_cmpgt_ps(cz2, cw2); anyb = _mm_or_ps(anyb, t); allb = _mm_and_ps(allb, t);
    t = _mm_and_ps(_mm_and_ps(_mm_cmple_ps(cw0, zero), _mm_cmple_ps(cw1, zero)), _mm_cmple_ps(cw2, zero));
    allb = _mm_or_ps(allb, t);
    anyb = _mm_or_ps(anyb, _mm_or_ps(_mm_or_ps(_mm_cmple_ps(cw0, zero), _mm_cmple_ps(cw1, zero)), _mm_cmple_ps(cw2, zero)));
    all = (unsigned)_mm_movemask_ps(allb);
    *test = 0;
    if (all == 15u) return 0; /* all four behind the near plane or the eye */
    any = (unsigned)_mm_movemask_ps(anyb);
    if (any == 15u) return all ^ 15u;
#define PVS__PROJ(X, Y, Z, cz, cw) do { \
        rw = _mm_div_ps(_mm_set1_ps(1.0f), cw); \
        x = _mm_add_ps(_mm_mul_ps(_mm_mul_ps(PVS__ROW(0, X, Y, Z), rw), _mm_set1_ps(r->hwf)), _mm_set1_ps(r->hwf)); \
        y = _mm_add_ps(_mm_mul_ps(_mm_mul_ps(PVS__ROW(4, X, Y, Z), rw), _mm_set1_ps(r->hhf)), _mm_set1_ps(r->hhf)); \
        z = _mm_mul_ps(cz, rw); } while (0)
    PVS__PROJ(X0, Y0, Z0, cz0, cw0);
    xmin = xmax = x; ymin = ymax = y; zm = z;
    PVS__PROJ(X1, Y1, Z1, cz1, cw1);
    xmin = _mm_min_ps(x, xmin); xmax = _mm_max_ps(x, xmax); ymin = _mm_min_ps(y, ymin); ymax = _mm_max_ps(y, ymax); zm = _mm_max_ps(z, zm);
    PVS__PROJ(X2, Y2, Z2, cz2, cw2);
    xmin = _mm_min_ps(x, xmin); xmax = _mm_max_ps(x, xmax); ymin = _mm_min_ps(y, ymin); ymax = _mm_max_ps(y, ymax); zm = _mm_max_ps(z, zm);
#undef PVS__PROJ
#undef PVS__ROW
#undef PVS__LOAD3
    /* finite extremes (a NaN coordinate can drop out of the min and max: the triangle may be dropped,
       which the scalar loop does alike and which is conservative) */
    fin = _mm_and_ps(_mm_cmplt_ps(_mm_and_ps(xmin, absm), big), _mm_cmplt_ps(_mm_and_ps(xmax, absm), big));
    fin = _mm_and_ps(fin, _mm_and_ps(_mm_cmplt_ps(_mm_and_ps(ymin, absm), big), _mm_cmplt_ps(_mm_and_ps(ymax, absm), big)));
    fin = _mm_and_ps(fin, _mm_cmplt_ps(_mm_and_ps(zm, absm), big));
    xmin = _mm_max_ps(xmin, zero); xmax = _mm_min_ps(xmax, _mm_set1_ps((float)r->width));
    ymin = _mm_max_ps(ymin, zero); ymax = _mm_min_ps(ymax, _mm_set1_ps((float)r->height));
    /* only the tested lanes matter: keep the others' conversions in range */
    t = _mm_andnot_ps(anyb, fin);
    xmin = _mm_and_ps(xmin, t); xmax = _mm_and_ps(xmax, t); ymin = _mm_and_ps(ymin, t); ymax = _mm_and_ps(ymax, t);
    i0 = _mm_cvttps_epi32(xmin);
    i0 = _mm_sub_epi32(i0, _mm_castps_si128(_mm_cmplt_ps(_mm_cvtepi32_ps(i0), xmin)));
    i1 = _mm_cvttps_epi32(xmax);
    i1 = _mm_sub_epi32(_mm_add_epi32(i1, _mm_castps_si128(_mm_cmpgt_ps(_mm_cvtepi32_ps(i1), xmax))), _mm_set1_epi32(1));
    j0 = _mm_cvttps_epi32(ymin);
    j0 = _mm_sub_epi32(j0, _mm_castps_si128(_mm_cmplt_ps(_mm_cvtepi32_ps(j0), ymin)));
    j1 = _mm_cvttps_epi32(ymax);
    j1 = _mm_sub_epi32(_mm_add_epi32(j1, _mm_castps_si128(_mm_cmpgt_ps(_mm_cvtepi32_ps(j1), ymax))), _mm_set1_epi32(1));
    empty = _mm_or_si128(_mm_cmpgt_epi32(i0, i1), _mm_cmpgt_epi32(j0, j1));
    _mm_storeu_si128((__m128i *)box[0], i0);
    _mm_storeu_si128((__m128i *)box[1], i1);
    _mm_storeu_si128((__m128i *)box[2], j0);
    _mm_storeu_si128((__m128i *)box[3], j1);
    _mm_storeu_ps(zmax, zm);
    tst = (unsigned)_mm_movemask_ps(t);
    *test = tst & ~(unsigned)_mm_movemask_ps(_mm_castsi128_ps(empty));
    return (all ^ 15u) & ~(tst & ~*test);
}
#define PVS__HAVE_PF_SIMD 1
#elif defined(PVS__NEON) && defined(__aarch64__) /* vdivq_f32 */
PVS__STATIC unsigned pvs__pf_simd(const pvs_raster *r, const float *const v[4][3], unsigned *test, int32_t box[4][4], float *zmax) {
    const float *mf = r->mf;
    const float32x4_t zero = vdupq_n_f32(0.0f), big = vdupq_n_f32(1e30f), hw = vdupq_n_f32(r->hwf), hh = vdupq_n_f32(r->hhf);
    float32x4_t X[3], Y[3], Z[3], cz[3], cw[3], x, y, z, xmin, xmax, ymin, ymax, zm, rw, fv;
    uint32x4_t anyb = vdupq_n_u32(0), behind = vdupq_n_u32(~0u), nonpos = behind, allb, fin = behind, t, c, empty;
    int32x4_t i0, i1, j0, j1;
    uint32_t lanes[4], tl[4], el[4];
    unsigned all = 0, any = 0, tst = 0, emp = 0;
    int k, l;
    for (k = 0; k < 3; ++k) {
        float xs[4], ys[4], zs[4];
        for (l = 0; l < 4; ++l) { xs[l] = v[l][k][0]; ys[l] = v[l][k][1]; zs[l] = v[l][k][2]; }
        X[k] = vld1q_f32(xs); Y[k] = vld1q_f32(ys); Z[k] = vld1q_f32(zs);
    }
#define PVS__ROW(o, k) vaddq_f32(vaddq_f32(vaddq_f32(vmulq_f32(vdupq_n_f32(mf[o]), X[k]), vmulq_f32(vdupq_n_f32(mf[o + 1]), Y[k])), \
                                           vmulq_f32(vdupq_n_f32(mf[o + 2]), Z[k])), vdupq_n_f32(mf[o + 3]))
    for (k = 0; k < 3; ++k) {
        cz[k] = PVS__ROW(8, k);
        cw[k] = PVS__ROW(12, k);
        t = vcgtq_f32(cz[k], cw[k]);
        behind = vandq_u32(behind, t);
        anyb = vorrq_u32(anyb, t);
        t = vcleq_f32(cw[k], zero);
        nonpos = vandq_u32(nonpos, t);
        anyb = vorrq_u32(anyb, t);
    }
    allb = vorrq_u32(behind, nonpos);
    vst1q_u32(lanes, allb);
    for (l = 0; l < 4; ++l) all |= (lanes[l] & 1u) << l;
    *test = 0;
    if (all == 15u) return 0;
    vst1q_u32(lanes, anyb);
    for (l = 0; l < 4; ++l) any |= (lanes[l] & 1u) << l;
    if (any == 15u) return all ^ 15u;
    xmin = xmax = ymin = ymax = zm = zero;
    for (k = 0; k < 3; ++k) {
        rw = vdivq_f32(vdupq_n_f32(1.0f), cw[k]);
        x = vaddq_f32(vmulq_f32(vmulq_f32(PVS__ROW(0, k), rw), hw), hw);
        y = vaddq_f32(vmulq_f32(vmulq_f32(PVS__ROW(4, k), rw), hh), hh);
        z = vmulq_f32(cz[k], rw);
        if (k == 0) {
            xmin = xmax = x; ymin = ymax = y; zm = z;
        } else {
            xmin = vbslq_f32(vcltq_f32(x, xmin), x, xmin); xmax = vbslq_f32(vcgtq_f32(x, xmax), x, xmax);
            ymin = vbslq_f32(vcltq_f32(y, ymin), y, ymin); ymax = vbslq_f32(vcgtq_f32(y, ymax), y, ymax);
            zm = vbslq_f32(vcgtq_f32(z, zm), z, zm);
        }
    }
#undef PVS__ROW
    fin = vandq_u32(vcltq_f32(vabsq_f32(xmin), big), vcltq_f32(vabsq_f32(xmax), big));
    fin = vandq_u32(fin, vandq_u32(vcltq_f32(vabsq_f32(ymin), big), vcltq_f32(vabsq_f32(ymax), big)));
    fin = vandq_u32(fin, vcltq_f32(vabsq_f32(zm), big));
    xmin = vbslq_f32(vcgtq_f32(xmin, zero), xmin, zero); fv = vdupq_n_f32((float)r->width); xmax = vbslq_f32(vcltq_f32(xmax, fv), xmax, fv);
    ymin = vbslq_f32(vcgtq_f32(ymin, zero), ymin, zero); fv = vdupq_n_f32((float)r->height); ymax = vbslq_f32(vcltq_f32(ymax, fv), ymax, fv);
    t = vbicq_u32(fin, anyb);
    xmin = vreinterpretq_f32_u32(vandq_u32(vreinterpretq_u32_f32(xmin), t));
    xmax = vreinterpretq_f32_u32(vandq_u32(vreinterpretq_u32_f32(xmax), t));
    ymin = vreinterpretq_f32_u32(vandq_u32(vreinterpretq_u32_f32(ymin), t));
    ymax = vreinterpretq_f32_u32(vandq_u32(vreinterpretq_u32_f32(ymax), t));
    i0 = vcvtq_s32_f32(xmin);
    c = vcltq_f32(vcvtq_f32_s32(i0), xmin);
    i0 = vsubq_s32(i0, vreinterpretq_s32_u32(c));
    i1 = vcvtq_s32_f32(xmax);
    c = vcgtq_f32(vcvtq_f32_s32(i1), xmax);
    i1 = vsubq_s32(vaddq_s32(i1, vreinterpretq_s32_u32(c)), vdupq_n_s32(1));
    j0 = vcvtq_s32_f32(ymin);
    c = vcltq_f32(vcvtq_f32_s32(j0), ymin);
    j0 = vsubq_s32(j0, vreinterpretq_s32_u32(c));
    j1 = vcvtq_s32_f32(ymax);
    c = vcgtq_f32(vcvtq_f32_s32(j1), ymax);
    j1 = vsubq_s32(vaddq_s32(j1, vreinterpretq_s32_u32(c)), vdupq_n_s32(1));
    empty = vorrq_u32(vcgtq_s32(i0, i1), vcgtq_s32(j0, j1));
    vst1q_s32(box[0], i0);
    vst1q_s32(box[1], i1);
    vst1q_s32(box[2], j0);
    vst1q_s32(box[3], j1);
    vst1q_f32(zmax, zm);
    vst1q_u32(tl, t);
    vst1q_u32(el, empty);
    for (l = 0; l < 4; ++l) {
        tst |= (tl[l] & 1u) << l;
        emp |= (el[l] & 1u) << l;
    }
    *test = tst & ~emp;
    return (all ^ 15u) & ~(tst & emp);
}
#define PVS__HAVE_PF_SIMD 1
#endif

/* 1 when every tile of [tx0, tx1] x [ty0, ty1] has a base at least as near as zmax. */
PVS__STATIC int pvs__pf_tiles(const pvs_raster *r, uint32_t tx0, uint32_t tx1, uint32_t ty0, uint32_t ty1, float zmax) {
    uint32_t tx, ty;
    for (ty = ty0; ty <= ty1; ++ty)
        for (tx = tx0; tx <= tx1; ++tx)
            if (!(r->tile[(size_t)ty * r->tw + tx].z0 >= zmax)) return 0;
    return 1;
}

/* 1 when every tile under the pixel box [i0, i1] x [j0, j1] already has a base at least as near as
   zmax (the triangle would change nothing). Large boxes look at the blocks first: bases only grow,
   so a block's stale least base is still a lower bound; it is retaken when it fails the test. */
PVS__STATIC int pvs__pf_hidden(pvs_raster *r, int32_t box[4][4], int l, float zmax) {
    uint32_t tx0 = (uint32_t)box[0][l] >> PVS__TW_SHIFT, tx1 = (uint32_t)box[1][l] >> PVS__TW_SHIFT;
    uint32_t ty0 = (uint32_t)box[2][l] >> PVS__TH_SHIFT, ty1 = (uint32_t)box[3][l] >> PVS__TH_SHIFT, bx, by;
    if ((tx1 - tx0 + 1) * (ty1 - ty0 + 1) <= PVS__PF_TILES) return pvs__pf_tiles(r, tx0, tx1, ty0, ty1, zmax);
    for (by = ty0 >> PVS__BLOCK_SHIFT; by <= ty1 >> PVS__BLOCK_SHIFT; ++by)
        for (bx = tx0 >> PVS__BLOCK_SHIFT; bx <= tx1 >> PVS__BLOCK_SHIFT; ++bx) {
            size_t k = (size_t)by * r->bw + bx;
            uint32_t x0 = bx << PVS__BLOCK_SHIFT, y0 = by << PVS__BLOCK_SHIFT, x1 = x0 + (1u << PVS__BLOCK_SHIFT) - 1, y1 = y0 + (1u << PVS__BLOCK_SHIFT) - 1;
            if (x1 >= r->tw) x1 = r->tw - 1;
            if (y1 >= r->th) y1 = r->th - 1;
            if (!(r->bmin[k] >= zmax) && r->bdirty[k]) {
                uint32_t tx, ty;
                float lo = FLT_MAX;
                for (ty = y0; ty <= y1; ++ty)
                    for (tx = x0; tx <= x1; ++tx) {
                        float z = r->tile[(size_t)ty * r->tw + tx].z0;
                        lo = z < lo ? z : lo;
                    }
                r->bmin[k] = lo;
                r->bdirty[k] = 0;
            }
            if (r->bmin[k] >= zmax) continue;
            if (!pvs__pf_tiles(r, x0 > tx0 ? x0 : tx0, x1 < tx1 ? x1 : tx1, y0 > ty0 ? y0 : ty0, y1 < ty1 ? y1 : ty1, zmax)) return 0;
        }
    return 1;
}

/* Occluder-mode triangles: `count` triangles of vertices `positions` (indices 3 per triangle or NULL)
   or, with `tris`, the scene triangles tris[0 .. count). Four at a time through the prefilter. */
PVS__STATIC void pvs__raster_occluders(pvs_raster *r, const float *positions, uint32_t vertex_count, const uint32_t *indices,
                                       const pvs__occsel *tris, uint32_t count) {
    uint32_t t, l, k;
    const float *v[4][3];
    float last[4], zmax[4];
    unsigned draw, test;
    int n;
    int32_t box[4][4];
#if defined(PVS__SSE2)
    __m128 mb[16];
    for (k = 0; k < 16; ++k) mb[k] = _mm_set1_ps(r->mf[k]);
#endif
    if (!vertex_count) return;
    last[0] = positions[3 * ((size_t)vertex_count - 1)]; /* the SIMD loads read 4 floats: a copy of the last vertex */
    last[1] = positions[3 * ((size_t)vertex_count - 1) + 1];
    last[2] = positions[3 * ((size_t)vertex_count - 1) + 2];
    last[3] = 0.0f;
    for (t = 0; t < count; t += 4) {
        n = 0;
        for (l = 0; l < 4 && t + l < count; ++l) {
            uint32_t q0, q1, q2;
            const uint32_t *ix = tris ? indices + 3 * (size_t)tris[t + l].triangle : indices ? indices + 3 * (size_t)(t + l) : NULL;
            if (ix) {
                q0 = ix[0]; q1 = ix[1]; q2 = ix[2];
            } else {
                q0 = 3 * (t + l); q1 = q0 + 1; q2 = q0 + 2;
            }
            if (q0 >= vertex_count || q1 >= vertex_count || q2 >= vertex_count) continue;
            v[n][0] = q0 + 1 == vertex_count ? last : positions + 3 * (size_t)q0;
            v[n][1] = q1 + 1 == vertex_count ? last : positions + 3 * (size_t)q1;
            v[n][2] = q2 + 1 == vertex_count ? last : positions + 3 * (size_t)q2;
            ++n;
        }
        if (!n) continue;
        for (l = (uint32_t)n; l < 4; ++l)
            for (k = 0; k < 3; ++k) v[l][k] = v[0][k];
#if defined(PVS__HAVE_PF_SIMD)
#if defined(PVS__SSE2)
        if (!(r->flags & PVS_RASTER_SCALAR)) draw = pvs__pf_simd(r, mb, (const float *const(*)[3])v, &test, box, zmax);
#else
        if (!(r->flags & PVS_RASTER_SCALAR)) draw = pvs__pf_simd(r, (const float *const(*)[3])v, &test, box, zmax);
#endif
        else
#endif
            draw = pvs__pf_scalar(r, (const float *const(*)[3])v, &test, box, zmax);
        draw &= (1u << n) - 1u;
        for (l = 0; draw; ++l, draw >>= 1) {
            if (!(draw & 1u)) continue;
            if ((test >> l) & 1u && pvs__pf_hidden(r, box, (int)l, zmax[l])) continue;
            pvs__raster_tri(r, v[l][0], v[l][1], v[l][2], 1);
        }
    }
}

/* ---- occluder meshes: the connectivity of occluders (Durand 2000 §3.3) ----

   Inner coverage per triangle loses every pixel that an edge shared by two triangles of one occluder
   crosses: neither triangle covers it alone, so a quad, a box or any game mesh has a crack along each
   internal edge (§3.3 calls it the loss of the connectivity of occluders). pvs__mesh claims the pixels
   the union of a mesh's triangles covers whole. The argument, on the exact projection (every computed
   quantity used below is off by less than its margin, so each test below decides about the exact
   geometry, with the near-plane cut's own limit stated at the top of >>raster):

   Groups. A triangle's facing is the sign of D = det(x, y, w) of its three clip-space vertices, which
   is the orientation of the visible (w > 0) part of its projection. A triangle whose sign is not
   certain (|D| within its rounding bound), whose visible polygon is empty or beyond float joins no
   group. An edge of a triangle is internal when (i) exactly two triangles of the piece have it
   (vertices welded by index and by equal position), (ii) both are in one group and run it in opposite
   directions (consistent winding), and (iii) an end point is surely in front of both clip planes and
   neither end point is within rounding of one. Every other edge, and every edge of a visible polygon
   that lies on a clip plane, is a boundary edge; B is their union, per group.
   Claim: the boundary of a group's union U (of its visible polygons) lies in B. Take q on it; q is on
   an edge or a vertex of some polygon P, since an interior point of P is interior to U. (a) q inside
   the visible part of an internal edge ab: for points p of triangle abc near ab, det(a, b, p) =
   gamma det(a, b, c) with gamma > 0, and one facing with opposite directions makes det(a, b, c1) and
   det(a, b, c2) of opposite signs, so the two triangles lie on opposite sides of ab in projection; by
   (iii) q is strictly in front of both planes, so each covers a half-disk at q: q is interior. (b) q a
   vertex made by clipping: it ends a clip edge, in B. (c) q an original vertex v: if an edge at v is a
   boundary edge, q is in B; else every edge at v is internal, v's triangles form closed fans whose
   consecutive sectors lie on opposite sides of their shared edge (a), so each fan turns about v by a
   positive multiple of 2 pi, and v is strictly in front (iii): a neighbourhood of q is covered.
   So a closed pixel square that no boundary edge meets and that meets U lies inside U (it is
   connected and U's boundary does not cross it): "meets" by separating-axis tests (the pixel's axes
   and the edge normals) with the margins on the safe side, "may meet" for B, "surely meets" for U.
   Depth: every point of such a pixel lies in a polygon of the group that touches the pixel, whose
   depth there is at least its plane's least value over the pixel and at least its least vertex depth;
   the least of these bounds over the group's polygons that may touch the pixel is no nearer than the
   mesh there. Folds, back faces, non-manifold edges, inconsistent winding, T-junctions and near-plane
   cuts only add boundary edges: the union is claimed in smaller pieces, never beyond itself.
   Two passes: the triangles first, one at a time through the ordinary occluder path (its inner
   pixels, its depth, SIMD; so a mesh never claims less than its triangles drawn alone), then the
   mesh pass over the pixels some edge may meet only (a strip widened beyond the first pass's float
   margins). A pixel of the strips that no edge meets lies inside one polygon P; P surely meets it, so
   P's bound is in the minimum; otherwise every point of the pixel lies in a polygon with an edge
   meeting it (the edges cut the pixel into regions, each on the inner side of one of them), whose
   strip holds the pixel: the minimum over the strips' polygons is a lower bound there too. Tiled, a
   band's claimed pixels join a tile's working layer only at no cost to it (at most as near as it, or
   as the first layer; a full tile becomes the base). A triangle whose box the tiles already hide at
   its nearest depth (the prefilter's test) is left out of the mesh pass: it changes nothing, and its
   edges become boundary edges. Rows are processed four at a time over an active list of the group's
   polygons, in double with the same float depth evaluation as the pixel loops; the mesh pass has one
   code path, so SIMD and scalar builds agree bit for bit. ---- */

#define PVS__MESH_NONE 0xffffffffu
#define PVS__MESH_MULTI 0xfffffffeu
#define PVS__MESH_DEFAULT 4096u
#define PVS__MESH_MAXV 5 /* a triangle clipped by two planes */

/* One triangle of a mesh piece, clipped, projected and prepared. */
typedef struct pvs__mtri {
    int32_t i0, i1, j0, j1;         /* pixels that may meet the polygon, clamped to the map (empty: i0 > i1 or j0 > j1) */
    int n;                          /* polygon vertices, 3..5 */
    int full;                       /* edges of non-zero length (the inner test needs 3) */
    uint8_t lab[PVS__MESH_MAXV];    /* edge k (vertex k to k + 1): triangle edge 0..2 or PVS__MESH_CLIP */
    uint8_t bnd[PVS__MESH_MAXV];    /* 1: a boundary edge */
    double x[PVS__MESH_MAXV], y[PVS__MESH_MAXV];
    double a[PVS__MESH_MAXV], b[PVS__MESH_MAXV], k[PVS__MESH_MAXV], e[PVS__MESH_MAXV]; /* E = a x + b y + k >= 0
                                       inside, |a| + |b| = 1 (a = b = 0: a zero-length edge); |E - exact| < e */
    double xmin, xmax, ymin, ymax, dx; /* extents; dx bounds the vertices' error */
    double wide;                    /* the edge strips' extra width: far above the triangle pass's float
                                       rounding, so a pixel it leaves out beside an edge is in the strip */
    float za, zb, zk, zclamp;       /* depth bound over pixel (i0 + fi, j0 + fj): max((zk + zb fj) + za fi, zclamp) */
} pvs__mtri;

/* Clips, projects and prepares triangle v (clip space) of facing `orient` (+1 / -1, the orientation of
   its projection); 0 when nothing usable is left. */
PVS__STATIC int pvs__mesh_setup(const pvs_raster *r, const pvs__cv *v, int orient, pvs__mtri *t) {
    pvs__cv t1[PVS__RASTER_MAXV], t2[PVS__RASTER_MAXV];
    uint8_t l0[PVS__RASTER_MAXV] = {0, 1, 2}, l1[PVS__RASTER_MAXV], l2[PVS__RASTER_MAXV];
    const pvs__cv *p = v;
    const uint8_t *lab = l0;
    double hw = 0.5 * (double)r->width, hh = 0.5 * (double)r->height, perr = 0.0, zerr = 0.0, z[PVS__MESH_MAXV];
    double mag = 0.0, zmag = 0.0, zmin = 0.0, ox, oy, iw, jh, span, noise;
    int i, n = 3;
    for (i = 0; i < 3; ++i)
        if (!(v[i].c[3] - v[i].c[2] >= 0.0) || !(v[i].c[3] >= 1e-30)) break;
    if (i < 3) {
        n = pvs__raster_clip(v, 3, t1, 0, l0, l1);
        if (n < 3) return 0;
        n = pvs__raster_clip(t1, n, t2, 1, l1, l2);
        if (n < 3 || n > PVS__MESH_MAXV) return 0;
        p = t2;
        lab = l2;
    }
    t->n = n;
    for (i = 0; i < n; ++i) {
        double iwv = 1.0 / p[i].c[3], e = p[i].e * iwv;
        t->x[i] = (p[i].c[0] * iwv + 1.0) * hw;
        t->y[i] = (p[i].c[1] * iwv + 1.0) * hh;
        z[i] = p[i].c[2] * iwv;
        if (!(t->x[i] == t->x[i] && t->y[i] == t->y[i] && z[i] == z[i])) return 0;
        perr = pvs__dmax(perr, 2.0 * e * (1.0 + pvs__dabs(p[i].c[0] * iwv) + pvs__dabs(p[i].c[1] * iwv)) * pvs__dmax(hw, hh));
        zerr = pvs__dmax(zerr, 2.0 * e * (1.0 + pvs__dabs(z[i])));
        t->lab[i] = lab[i];
        t->bnd[i] = 1;
        if (i == 0) {
            t->xmin = t->xmax = t->x[0]; t->ymin = t->ymax = t->y[0]; zmin = z[0];
        } else {
            t->xmin = pvs__dmin(t->xmin, t->x[i]); t->xmax = pvs__dmax(t->xmax, t->x[i]);
            t->ymin = pvs__dmin(t->ymin, t->y[i]); t->ymax = pvs__dmax(t->ymax, t->y[i]);
            zmin = pvs__dmin(zmin, z[i]);
        }
        mag = pvs__dmax(mag, pvs__dabs(t->x[i]) + pvs__dabs(t->y[i]));
        zmag = pvs__dmax(zmag, pvs__dabs(z[i]));
    }
    if (!(mag < PVS__RASTER_BIG * PVS__RASTER_BIG) || !(perr < PVS__RASTER_BIG) || !(zerr < PVS__RASTER_BIG)) return 0;
    t->dx = PVS__RASTER_ERR_D * (mag + 1.0) + perr;
    t->wide = (mag + (double)r->width + (double)r->height + 1.0) * (1.0 / 16384.0);
    /* pixels whose closed square meets [xmin - dx, xmax + dx] x [ymin - dx, ymax + dx] */
    t->i0 = pvs__clampi(ceil(t->xmin - t->dx) - 1.0, 0, (int32_t)r->width);
    t->i1 = pvs__clampi(floor(t->xmax + t->dx), -1, (int32_t)r->width - 1);
    t->j0 = pvs__clampi(ceil(t->ymin - t->dx) - 1.0, 0, (int32_t)r->height);
    t->j1 = pvs__clampi(floor(t->ymax + t->dx), -1, (int32_t)r->height - 1);
    ox = (double)t->i0;
    oy = (double)t->j0;
    iw = pvs__dmax(0.0, (double)(t->i1 - t->i0));
    jh = pvs__dmax(0.0, (double)(t->j1 - t->j0));
    /* the evaluation a X + b Y + k at pixel corners (X, Y <= mag + map size) in double: far below this */
    noise = PVS__RASTER_ERR_D * (mag + (double)r->width + (double)r->height + 4.0);
    t->full = 0;
    for (i = 0; i < n; ++i) {
        int j = i + 1 == n ? 0 : i + 1;
        double a = t->y[i] - t->y[j], b = t->x[j] - t->x[i], len;
        if (orient < 0) { a = -a; b = -b; }
        len = pvs__dabs(a) + pvs__dabs(b);
        if (len == 0.0) {
            t->a[i] = t->b[i] = t->k[i] = t->e[i] = 0.0;
            continue;
        }
        a /= len;
        b /= len;
        t->a[i] = a;
        t->b[i] = b;
        t->k[i] = -(a * t->x[i] + b * t->y[i]);
        /* the line through vertices off by dx (pvs__raster_poly's bound, for every pixel corner of the
           range), and the evaluation */
        t->e[i] = (PVS__RASTER_ERR_D * (1.0 + mag) + perr) *
                      (1.0 + (pvs__dabs(ox - t->x[i]) + pvs__dabs(oy - t->y[i]) + iw + jh + 2.0) / len) + noise;
        ++t->full;
    }
    span = (t->xmax - t->xmin) + (t->ymax - t->ymin);
    t->zclamp = pvs__f_down(zmin - PVS__RASTER_ERR_D * zmag - zerr);
    pvs__raster_zplane(t->x, t->y, z, n, ox, oy, iw, jh, span, mag, zmag, perr, zerr, 1, &t->za, &t->zb, &t->zk);
    return 1;
}

/* Restricts the columns [*lo, *hi] to those where a i + c >= t evaluated in double. outer: may keep
   more, never drops a column that passes; else may keep fewer, never one that fails. The bound found
   is checked against its neighbour, so with the threshold's margin it holds for the real-valued
   a i + c, which is monotonic in i. */
PVS__STATIC void pvs__mesh_cut(double a, double c, double t, int outer, int32_t *lo, int32_t *hi) {
    int32_t i;
    int s;
    double X;
    if (*lo > *hi) return;
    if (a == 0.0) {
        if (!(c >= t)) *hi = *lo - 1;
        return;
    }
    X = (t - c) / a;
    if (a > 0.0) { /* keep i >= X */
        i = X > (double)*hi ? *hi + 1 : X > (double)*lo ? (int32_t)ceil(X) : *lo;
        for (s = 0; s < 3 && i > *lo && a * (double)(i - 1) + c >= t; ++s) --i;
        for (s = 0; s < 3 && i <= *hi && !(a * (double)i + c >= t); ++s) ++i;
        if (outer) {
            if (i > *lo && !(a * (double)(i - 1) + c < t)) i = *lo; /* not settled: keep all */
        } else if (i <= *hi && !(a * (double)i + c >= t)) {
            i = *hi + 1; /* not settled: keep none */
        }
        *lo = i;
    } else { /* keep i <= X */
        i = X < (double)*lo ? *lo - 1 : X < (double)*hi ? (int32_t)floor(X) : *hi;
        for (s = 0; s < 3 && i < *hi && a * (double)(i + 1) + c >= t; ++s) ++i;
        for (s = 0; s < 3 && i >= *lo && !(a * (double)i + c >= t); ++s) --i;
        if (outer) {
            if (i < *hi && !(a * (double)(i + 1) + c < t)) i = *hi;
        } else if (i >= *lo && !(a * (double)i + c >= t)) {
            i = *lo - 1;
        }
        *hi = i;
    }
}

/* One polygon over row j of the four-row band starting at row jb, along its edges only (its inner
   pixels were drawn by the triangle pass): over the pixels an edge may meet, the polygon's least depth
   bound, whether the polygon surely meets the pixel (1) and whether a boundary edge may meet it (2).
   rlo, rhi: the columns touched per row of the band. */
PVS__STATIC void pvs__mesh_row(pvs_raster *r, const pvs__mtri *t, int32_t j, int32_t jb, int32_t *rlo, int32_t *rhi) {
    const uint32_t W = r->width;
    float *zm = r->mzmin + (size_t)(j - jb) * W;
    uint8_t *fl = r->mflag + (size_t)(j - jb) * W, *dw = r->mdirty + (size_t)(j - jb) * r->tw;
    float fj = (float)(j - t->j0), rz = t->zk + t->zb * fj, d;
    double dj = (double)j;
    int32_t lo, hi, clo = 0, chi = -1, i;
    int e;
    /* surely meets: the x and y extents overlap the pixel and no edge separates */
    if (dj + 1.0 >= t->ymin + t->dx && dj <= t->ymax - t->dx) {
        clo = pvs__clampi(ceil(t->xmin + t->dx) - 1.0, t->i0, t->i1 + 1);
        chi = pvs__clampi(floor(t->xmax - t->dx), t->i0 - 1, t->i1);
        for (e = 0; e < t->n; ++e)
            if (t->a[e] != 0.0 || t->b[e] != 0.0)
                pvs__mesh_cut(t->a[e], t->b[e] * dj + t->k[e] + pvs__dmax(0.0, t->a[e]) + pvs__dmax(0.0, t->b[e]), t->e[e], 0, &clo, &chi);
    }
    /* each edge: the pixels whose closed square the segment may meet (its extents and its line) */
    for (e = 0; e < t->n; ++e) {
        int f = e + 1 == t->n ? 0 : e + 1;
        double sx0, sx1, sy0, sy1;
        uint8_t bit = t->bnd[e] ? 2u : 0u;
        sy0 = pvs__dmin(t->y[e], t->y[f]) - t->dx - t->wide;
        sy1 = pvs__dmax(t->y[e], t->y[f]) + t->dx + t->wide;
        if (dj + 1.0 < sy0 || dj > sy1) continue;
        sx0 = pvs__dmin(t->x[e], t->x[f]) - t->dx - t->wide;
        sx1 = pvs__dmax(t->x[e], t->x[f]) + t->dx + t->wide;
        lo = pvs__clampi(ceil(sx0) - 1.0, t->i0, t->i1 + 1);
        hi = pvs__clampi(floor(sx1), t->i0 - 1, t->i1);
        if (t->a[e] != 0.0 || t->b[e] != 0.0) {
            double m = t->e[e] + t->wide;
            pvs__mesh_cut(t->a[e], t->b[e] * dj + t->k[e] + pvs__dmax(0.0, t->a[e]) + pvs__dmax(0.0, t->b[e]), -m, 1, &lo, &hi);
            pvs__mesh_cut(-t->a[e], -(t->b[e] * dj + t->k[e] + pvs__dmin(0.0, t->a[e]) + pvs__dmin(0.0, t->b[e])), -m, 1, &lo, &hi);
        }
        if (lo > hi) continue;
        for (i = lo; i <= hi; ++i) {
            d = rz + t->za * (float)(i - t->i0);
            d = d < t->zclamp ? t->zclamp : d;
            if (d < zm[i]) zm[i] = d;
            fl[i] |= (uint8_t)(bit | (i >= clo && i <= chi ? 1u : 0u));
        }
        rlo[j - jb] = lo < rlo[j - jb] ? lo : rlo[j - jb];
        rhi[j - jb] = hi > rhi[j - jb] ? hi : rhi[j - jb];
        for (i = lo >> PVS__TW_SHIFT; i <= hi >> PVS__TW_SHIFT; ++i) dw[i] = 1;
    }
}

/* The claimed depth of a band pixel (PVS_DEPTH_EMPTY: none), resetting its scratch. */
PVS__STATIC float pvs__mesh_take(pvs_raster *r, size_t q) {
    float z = r->mzin[q];
    if (r->mflag[q] == 1u && r->mzmin[q] < FLT_MAX && r->mzmin[q] > z) z = r->mzmin[q];
    r->mzin[q] = PVS_DEPTH_EMPTY;
    r->mzmin[q] = FLT_MAX;
    r->mflag[q] = 0;
    return z;
}

/* Writes the claimed pixels of band b (rows 4 b .. 4 b + 3) into the depth map or, tiled, per tile as
   a coverage mask at the least claimed depth (pvs__tile_merge). */
PVS__STATIC void pvs__mesh_claim(pvs_raster *r, uint32_t b, const int32_t *rlo, const int32_t *rhi) {
    const uint32_t W = r->width;
    int32_t lo = INT32_MAX, hi = -1, i, d, tx;
    float z;
    for (d = 0; d < PVS__TH; ++d) {
        lo = rlo[d] < lo ? rlo[d] : lo;
        hi = rhi[d] > hi ? rhi[d] : hi;
    }
    if (lo > hi) return;
    if (!r->tiled) {
        for (d = 0; d < PVS__TH; ++d) {
            float *row = r->depth + (size_t)(PVS__TH * b + (uint32_t)d) * W;
            uint8_t *dw = r->mdirty + (size_t)d * r->tw;
            for (i = rlo[d]; i <= rhi[d]; ++i) {
                if (!dw[i >> PVS__TW_SHIFT]) { /* nothing in this word: on to the next */
                    i |= 31;
                    continue;
                }
                z = pvs__mesh_take(r, (size_t)d * W + (size_t)i);
                if (z > row[i]) row[i] = z;
            }
            if (rlo[d] <= rhi[d])
                for (tx = rlo[d] >> PVS__TW_SHIFT; tx <= rhi[d] >> PVS__TW_SHIFT; ++tx) dw[tx] = 0;
        }
        return;
    }
    for (tx = lo >> PVS__TW_SHIFT; tx <= hi >> PVS__TW_SHIFT; ++tx) {
        int32_t x0 = tx << PVS__TW_SHIFT;
        uint32_t cov[PVS__TH], any = 0, pad[PVS__TH];
        float zt = FLT_MAX, z0;
        pvs__tile *tl = r->tile + (size_t)b * r->tw + (size_t)tx;
        for (d = 0; d < PVS__TH; ++d) {
            int32_t a0 = rlo[d] > x0 ? rlo[d] : x0, a1 = rhi[d] < x0 + 31 ? rhi[d] : x0 + 31;
            uint8_t *dw = r->mdirty + (size_t)d * r->tw + (uint32_t)tx;
            cov[d] = 0;
            pad[d] = (b == r->th - 1 && (uint32_t)d >= r->ypad ? ~0u : 0u) | ((uint32_t)tx == r->tw - 1 ? r->xpad : 0u);
            if (!*dw) continue;
            *dw = 0;
            for (i = a0; i <= a1; ++i) {
                z = pvs__mesh_take(r, (size_t)d * W + (size_t)i);
                if (z == PVS_DEPTH_EMPTY) continue;
                cov[d] |= 1u << (i - x0);
                zt = z < zt ? z : zt;
            }
            any |= cov[d];
        }
        if (!any || !(zt > tl->z0)) continue;
        /* unlike pvs__tile_merge, hardly at the cost of the working layer (the pixels along edges are
           a thin set, often farther than it): the union at the farther depth when zt is no farther, the
           tile fills up or the layer loses at most 1/8 of its lead over the base; a new working layer
           when there is none; else nothing */
        {
            uint32_t full = ~0u, have = 0;
            for (d = 0; d < PVS__TH; ++d) {
                have |= tl->mask[d];
                full &= tl->mask[d] | cov[d] | pad[d];
            }
            /* farther than the working layer: only when the tile fills up or the layer loses little */
            if (have && zt < tl->z1 && full != ~0u && (double)tl->z1 - zt > 0.125 * ((double)tl->z1 - tl->z0)) continue;
            z0 = have && tl->z1 < zt ? tl->z1 : zt;
            if (full == ~0u) {
                for (d = 0; d < PVS__TH; ++d) tl->mask[d] = 0;
                tl->z0 = z0;
                r->bdirty[(size_t)(b >> PVS__BLOCK_SHIFT) * r->bw + (uint32_t)(tx >> PVS__BLOCK_SHIFT)] = 1;
            } else {
                for (d = 0; d < PVS__TH; ++d) tl->mask[d] |= cov[d];
                tl->z1 = z0;
            }
        }
    }
}

/* Draws the prepared polygons of facing g among the piece's n triangles: band by band (four rows, a
   tile row) over an active list sorted by first band. */
PVS__STATIC void pvs__mesh_draw(pvs_raster *r, uint32_t n, int g) {
    uint32_t *cnt = r->mband, *order = r->morder, *act = r->mact, t, m = 0, pos = 0, na = 0, b = 0, k, keep;
    int32_t rlo[PVS__TH], rhi[PVS__TH], j;
    int d;
    for (b = 0; b <= r->th; ++b) cnt[b] = 0;
    for (t = 0; t < n; ++t) {
        const pvs__mtri *p = r->mt + t;
        if (r->mgrp[t] != g || p->i0 > p->i1 || p->j0 > p->j1) continue;
        ++cnt[((uint32_t)p->j0 >> PVS__TH_SHIFT) + 1];
        ++m;
    }
    if (!m) return;
    for (b = 0; b < r->th; ++b) cnt[b + 1] += cnt[b];
    for (t = 0; t < n; ++t) {
        const pvs__mtri *p = r->mt + t;
        if (r->mgrp[t] != g || p->i0 > p->i1 || p->j0 > p->j1) continue;
        order[cnt[(uint32_t)p->j0 >> PVS__TH_SHIFT]++] = t;
    }
    while (pos < m || na) {
        if (!na) b = (uint32_t)r->mt[order[pos]].j0 >> PVS__TH_SHIFT;
        while (pos < m && (uint32_t)r->mt[order[pos]].j0 >> PVS__TH_SHIFT == b) act[na++] = order[pos++];
        for (d = 0; d < PVS__TH; ++d) { rlo[d] = INT32_MAX; rhi[d] = -1; }
        for (k = 0; k < na; ++k) {
            const pvs__mtri *p = r->mt + act[k];
            int32_t jb = (int32_t)(b << PVS__TH_SHIFT), ja = p->j0 > jb ? p->j0 : jb, jz = p->j1 < jb + 3 ? p->j1 : jb + 3;
            for (j = ja; j <= jz; ++j) pvs__mesh_row(r, p, j, jb, rlo, rhi);
        }
        pvs__mesh_claim(r, b, rlo, rhi);
        for (k = keep = 0; k < na; ++k)
            if ((uint32_t)r->mt[act[k]].j1 >> PVS__TH_SHIFT > b) act[keep++] = act[k];
        na = keep;
        ++b;
    }
}

/* Facing of a clip-space triangle: the sign of det(x, y, w), 0 when within its rounding bound (each
   entry off by at most e: 48 M^2 e covers the first- and higher-order terms for e <= M, 1e-14 M^3 the
   evaluation). */
PVS__STATIC int pvs__mesh_facing(const pvs__cv *v) {
    const double *p = v[0].c, *q = v[1].c, *s = v[2].c;
    double d = p[0] * (q[1] * s[3] - s[1] * q[3]) - p[1] * (q[0] * s[3] - s[0] * q[3]) + p[3] * (q[0] * s[1] - s[0] * q[1]);
    double M = 0.0, e = pvs__dmax(v[0].e, pvs__dmax(v[1].e, v[2].e)), bound;
    int i;
    for (i = 0; i < 3; ++i) M = pvs__dmax(M, pvs__dmax(pvs__dabs(v[i].c[0]), pvs__dmax(pvs__dabs(v[i].c[1]), pvs__dabs(v[i].c[3]))));
    bound = 48.0 * M * M * e + 1e-14 * M * M * M + 1e-300;
    if (d > bound) return 1;
    if (d < -bound) return -1;
    return 0;
}

PVS__STATIC uint32_t pvs__mesh_fbits(float f) {
    uint32_t u;
    f += 0.0f; /* -0 and 0 weld */
    memcpy(&u, &f, 4);
    return u;
}

/* One piece of a mesh: triangles first .. first + n - 1 (n <= mesh_cap) of `indices` (NULL:
   consecutive vertices) or of tris[]. */
PVS__STATIC void pvs__mesh_piece(pvs_raster *r, const float *pos, uint32_t vc, const uint32_t *indices, const pvs__occsel *tris,
                                 uint32_t first, uint32_t n) {
    uint32_t hs = 16, t, k, h, *tab = r->mtab, *cid = r->mcid, *part = r->mpart;
    while (hs < 6 * n && hs < r->mesh_hash) hs <<= 1;
    for (h = 0; h < hs; ++h) tab[h] = 0;
    /* weld, transform, facing, clip and prepare */
    for (t = 0; t < n; ++t) {
        uint32_t q[3];
        const float *p[3];
        pvs__cv v[3];
        int ok = 1, g;
        r->mgrp[t] = 0;
        if (tris || indices) {
            const uint32_t *ix = tris ? indices + 3 * (size_t)tris[first + t].triangle : indices + 3 * (size_t)(first + t);
            q[0] = ix[0]; q[1] = ix[1]; q[2] = ix[2];
        } else {
            q[0] = 3 * (first + t); q[1] = q[0] + 1; q[2] = q[0] + 2;
        }
        for (k = 0; k < 3 && ok; ++k) {
            ok = q[k] < vc;
            if (ok) {
                p[k] = pos + 3 * (size_t)q[k];
                ok = pvs__finite(p[k][0]) && pvs__finite(p[k][1]) && pvs__finite(p[k][2]);
            }
        }
        if (!ok) continue;
        if (r->tiled) { /* hidden behind what earlier pieces drew: left out (its edges become boundary edges) */
            const float *pv[4][3];
            unsigned test, l;
            int32_t box[4][4];
            float zmax[4];
            for (l = 0; l < 4; ++l) { pv[l][0] = p[0]; pv[l][1] = p[1]; pv[l][2] = p[2]; }
            if ((pvs__pf_scalar(r, (const float *const(*)[3])pv, &test, box, zmax) & test & 1u) && pvs__pf_hidden(r, box, 0, zmax[0])) continue;
        }
        for (k = 0; k < 3; ++k) { /* the first vertex with the same position (open addressing) */
            uint32_t x = pvs__mesh_fbits(p[k][0]), y = pvs__mesh_fbits(p[k][1]), z = pvs__mesh_fbits(p[k][2]);
            h = (x * 0x9E3779B1u) ^ (y * 0x85EBCA77u) ^ (z * 0xC2B2AE3Du);
            h = (h ^ (h >> 15)) & (hs - 1);
            for (;;) {
                if (!tab[h]) {
                    tab[h] = q[k] + 1;
                    cid[3 * t + k] = q[k];
                    break;
                }
                {
                    const float *o = pos + 3 * (size_t)(tab[h] - 1);
                    if (o[0] == p[k][0] && o[1] == p[k][1] && o[2] == p[k][2]) {
                        cid[3 * t + k] = tab[h] - 1;
                        break;
                    }
                }
                h = (h + 1) & (hs - 1);
            }
        }
        if (cid[3 * t] == cid[3 * t + 1] || cid[3 * t + 1] == cid[3 * t + 2] || cid[3 * t + 2] == cid[3 * t]) continue;
        for (k = 0; k < 3; ++k) v[k] = pvs__raster_transform(r, p[k]);
        if (v[0].c[3] - v[0].c[2] < 0 && v[1].c[3] - v[1].c[2] < 0 && v[2].c[3] - v[2].c[2] < 0) continue;
        if (v[0].c[3] <= 0 && v[1].c[3] <= 0 && v[2].c[3] <= 0) continue;
        g = pvs__mesh_facing(v);
        if (!g || !pvs__mesh_setup(r, v, g, r->mt + t)) continue;
        for (k = 0; k < 3; ++k) { /* 1: surely in front of both clip planes, 2: surely behind one, 0: neither */
            double w = v[k].c[3], zc = v[k].c[2], e = v[k].e;
            double m1 = 2.0 * e + 4.5e-16 * (pvs__dabs(w) + pvs__dabs(zc)), m2 = e + 4.5e-16 * pvs__dabs(w) + 1e-45;
            r->mvst[3 * t + k] = (uint8_t)(w - zc > m1 && w - 1e-30 > m2 ? 1 : w - zc < -m1 || w - 1e-30 < -m2 ? 2 : 0);
        }
        r->mgrp[t] = (int8_t)g;
    }
    /* edges by their welded end points: the partner half-edge, NONE or MULTI */
    for (h = 0; h < hs; ++h) tab[h] = 0;
    for (t = 0; t < n; ++t) {
        if (!r->mgrp[t]) continue;
        for (k = 0; k < 3; ++k) {
            uint32_t he = 3 * t + k, a = cid[he], b = cid[3 * t + (k + 1) % 3], lo = a < b ? a : b, hi2 = a < b ? b : a;
            part[he] = PVS__MESH_NONE;
            h = (lo * 0x9E3779B1u) ^ (hi2 * 0x85EBCA77u);
            h = (h ^ (h >> 16)) & (hs - 1);
            for (;;) {
                uint32_t o, oa, ob;
                if (!tab[h]) {
                    tab[h] = he + 1;
                    break;
                }
                o = tab[h] - 1;
                oa = cid[o];
                ob = cid[3 * (o / 3) + (o % 3 + 1) % 3];
                if ((oa == lo && ob == hi2) || (oa == hi2 && ob == lo)) {
                    if (part[o] == PVS__MESH_NONE) {
                        part[o] = he;
                        part[he] = o;
                    } else {
                        if (part[o] != PVS__MESH_MULTI) part[part[o]] = PVS__MESH_MULTI;
                        part[o] = part[he] = PVS__MESH_MULTI;
                    }
                    break;
                }
                h = (h + 1) & (hs - 1);
            }
        }
    }
    /* which polygon edges are boundary edges (conditions (i)-(iii) above) */
    for (t = 0; t < n; ++t) {
        pvs__mtri *p = r->mt + t;
        int e;
        if (!r->mgrp[t]) continue;
        for (e = 0; e < p->n; ++e) {
            uint32_t L = p->lab[e], he, o;
            uint8_t sa, sb;
            if (L == PVS__MESH_CLIP) continue;
            he = 3 * t + L;
            o = part[he];
            sa = r->mvst[he];
            sb = r->mvst[3 * t + (L + 1) % 3];
            if (o >= PVS__MESH_MULTI || r->mgrp[o / 3] != r->mgrp[t]) continue;
            if (cid[he] != cid[3 * (o / 3) + (o % 3 + 1) % 3]) continue; /* both run it the same way */
            if (!(sa == 1 || sb == 1) || !sa || !sb) continue;
            p->bnd[e] = 0;
        }
    }
    pvs__mesh_draw(r, n, 1);
    pvs__mesh_draw(r, n, -1);
}

/* Occluder meshes: `count` triangles of `indices` (NULL: consecutive vertices) or of tris[], in pieces
   of mesh_cap triangles. */
PVS__STATIC void pvs__mesh(pvs_raster *r, const float *pos, uint32_t vc, const uint32_t *indices, const pvs__occsel *tris, uint32_t count) {
    uint32_t first;
    if (!count || !vc) return;
    /* the triangles' own inner pixels (the fast paths); then the pixels along their edges */
    if (r->tiled) {
        pvs__raster_occluders(r, pos, vc, indices, tris, count);
    } else {
        for (first = 0; first < count; ++first) {
            const uint32_t *ix = tris ? indices + 3 * (size_t)tris[first].triangle : indices ? indices + 3 * (size_t)first : NULL;
            uint32_t q0 = ix ? ix[0] : 3 * first, q1 = ix ? ix[1] : 3 * first + 1, q2 = ix ? ix[2] : 3 * first + 2;
            if (q0 < vc && q1 < vc && q2 < vc) pvs__raster_tri(r, pos + 3 * (size_t)q0, pos + 3 * (size_t)q1, pos + 3 * (size_t)q2, 1);
        }
        pvs__raster_occludee_begin(r); /* the per-pixel map, cleared on first use */
    }
    for (first = 0; first < count; first += r->mesh_cap)
        pvs__mesh_piece(r, pos, vc, indices, tris, first, count - first < r->mesh_cap ? count - first : r->mesh_cap);
    r->pyramid_valid = 0;
}

PVS_API pvs_result pvs_camera_matrix(const pvs_camera *c, float aspect, float m[16]) {
    double f[3], u[3], rt[3], len, fu, e[3], sx, sy;
    int k;
    if (!c || !m) return PVS_ERROR_INVALID_ARGUMENT;
    for (k = 0; k < 3; ++k)
        if (!pvs__finite(c->eye[k]) || !pvs__finite(c->forward[k]) || !pvs__finite(c->up[k])) return PVS_ERROR_NOT_FINITE;
    if (!pvs__finite(c->fov_y) || !pvs__finite(c->near_plane) || !pvs__finite(aspect) || !pvs__finite(c->ortho_height) ||
        !pvs__finite(c->far_plane))
        return PVS_ERROR_NOT_FINITE;
    if (!(aspect > 0.0f) || !(c->near_plane > 0.0f) || c->fov_y < 0.0f || !(c->fov_y < 3.14159f))
        return PVS_ERROR_INVALID_ARGUMENT;
    if (c->fov_y == 0.0f && !(c->ortho_height > 0.0f)) return PVS_ERROR_INVALID_ARGUMENT;
    for (k = 0; k < 3; ++k) { f[k] = c->forward[k]; u[k] = c->up[k]; e[k] = c->eye[k]; }
    len = sqrt(f[0] * f[0] + f[1] * f[1] + f[2] * f[2]);
    if (!(len > 0.0)) return PVS_ERROR_INVALID_ARGUMENT;
    for (k = 0; k < 3; ++k) f[k] /= len;
    fu = f[0] * u[0] + f[1] * u[1] + f[2] * u[2];
    for (k = 0; k < 3; ++k) u[k] -= fu * f[k];
    len = sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]);
    if (!(len > 1e-12)) return PVS_ERROR_INVALID_ARGUMENT; /* up parallel to forward */
    for (k = 0; k < 3; ++k) u[k] /= len;
    rt[0] = f[1] * u[2] - f[2] * u[1];
    rt[1] = f[2] * u[0] - f[0] * u[2];
    rt[2] = f[0] * u[1] - f[1] * u[0];
    if (c->fov_y > 0.0f) {
        sy = 1.0 / tan(0.5 * (double)c->fov_y);
        sx = sy / (double)aspect;
        for (k = 0; k < 3; ++k) {
            m[k] = (float)(sx * rt[k]);
            m[4 + k] = (float)(sy * u[k]);
            m[8 + k] = 0.0f;
            m[12 + k] = (float)f[k];
        }
        m[3] = (float)(-sx * (rt[0] * e[0] + rt[1] * e[1] + rt[2] * e[2]));
        m[7] = (float)(-sy * (u[0] * e[0] + u[1] * e[1] + u[2] * e[2]));
        m[11] = c->near_plane;
        m[15] = (float)-(f[0] * e[0] + f[1] * e[1] + f[2] * e[2]);
    } else {
        double far_d = c->far_plane > c->near_plane ? c->far_plane : (double)c->near_plane + 1e4;
        double range = far_d - c->near_plane;
        sy = 2.0 / c->ortho_height;
        sx = sy / (double)aspect;
        for (k = 0; k < 3; ++k) {
            m[k] = (float)(sx * rt[k]);
            m[4 + k] = (float)(sy * u[k]);
            m[8 + k] = (float)(-f[k] / range);
            m[12 + k] = 0.0f;
        }
        m[3] = (float)(-sx * (rt[0] * e[0] + rt[1] * e[1] + rt[2] * e[2]));
        m[7] = (float)(-sy * (u[0] * e[0] + u[1] * e[1] + u[2] * e[2]));
        /* depth = 1 - (distance - near) / range */
        m[11] = (float)(1.0 + ((f[0] * e[0] + f[1] * e[1] + f[2] * e[2]) + c->near_plane) / range);
        m[15] = 1.0f;
    }
    for (k = 0; k < 16; ++k)
        if (!pvs__finite(m[k])) return PVS_ERROR_NOT_FINITE;
    return PVS_OK;
}

PVS_API pvs_result pvs_raster_set_matrix(pvs_raster *r, const float m[16]) {
    int k;
    if (!r || !m) return PVS_ERROR_INVALID_ARGUMENT;
    for (k = 0; k < 16; ++k)
        if (!pvs__finite(m[k])) return PVS_ERROR_NOT_FINITE;
    for (k = 0; k < 16; ++k) {
        r->m[k] = r->mf[k] = m[k];
        r->mb[k][0] = r->mb[k][1] = r->mb[k][2] = r->mb[k][3] = m[k];
    }
    r->mabs[0] = r->mabs[1] = 0.0;
    for (k = 0; k < 4; ++k) {
        r->rowa[k] = pvs__dabs(r->m[4 * k]) + pvs__dabs(r->m[4 * k + 1]) + pvs__dabs(r->m[4 * k + 2]);
        r->rowt[k] = pvs__dabs(r->m[4 * k + 3]);
    }
    for (k = 0; k < 4; ++k) { /* the largest row sums of |m|: bounds of the transform's terms */
        r->mabs[0] = pvs__dmax(r->mabs[0], pvs__dabs(r->m[4 * k]) + pvs__dabs(r->m[4 * k + 1]) + pvs__dabs(r->m[4 * k + 2]));
        r->mabs[1] = pvs__dmax(r->mabs[1], pvs__dabs(r->m[4 * k + 3]));
    }
    return PVS_OK;
}

PVS_API void pvs_raster_clear(pvs_raster *r) {
    size_t i, n = r->tiled ? (size_t)r->tw * r->th : 0;
    for (i = 0; i < n; ++i) {
        pvs__tile *t = r->tile + i;
        t->mask[0] = t->mask[1] = t->mask[2] = t->mask[3] = 0;
        t->z0 = t->z1 = PVS_DEPTH_EMPTY;
    }
    n = r->tiled ? (size_t)r->bw * r->bh : 0;
    for (i = 0; i < n; ++i) {
        r->bmin[i] = PVS_DEPTH_EMPTY;
        r->bdirty[i] = 0;
    }
    r->mixed = 0; /* the per-pixel map is cleared by the first occludee triangle */
    r->pyramid_valid = 0;
}

PVS_API pvs_result pvs_raster_triangles(pvs_raster *r, const float *positions, uint32_t vertex_count, const uint32_t *indices,
                                        uint32_t count, pvs_raster_mode mode) {
    uint32_t t;
    if (!r || (!positions && count) || (int)mode < 0 || mode >= PVS_RASTER_MODE_COUNT) return PVS_ERROR_INVALID_ARGUMENT;
    if (mode == PVS_RASTER_OCCLUDER && r->tiled) {
        pvs__raster_occluders(r, positions, vertex_count, indices, NULL, count);
        return PVS_OK;
    }
    for (t = 0; t < count; ++t) {
        uint32_t a, b, c;
        if (indices) { a = indices[3 * t]; b = indices[3 * t + 1]; c = indices[3 * t + 2]; }
        else { a = 3 * t; b = a + 1; c = a + 2; }
        if (a >= vertex_count || b >= vertex_count || c >= vertex_count) continue;
        pvs__raster_tri(r, positions + 3 * (size_t)a, positions + 3 * (size_t)b, positions + 3 * (size_t)c,
                        mode == PVS_RASTER_OCCLUDER);
    }
    return PVS_OK;
}

PVS_API pvs_result pvs_raster_mesh(pvs_raster *r, const float *positions, uint32_t vertex_count, const uint32_t *indices,
                                   uint32_t count) {
    if (!r || (!positions && count)) return PVS_ERROR_INVALID_ARGUMENT;
    pvs__mesh(r, positions, vertex_count, indices, NULL, count);
    return PVS_OK;
}

PVS_API const float *pvs_raster_depth(const pvs_raster *r, uint32_t *w, uint32_t *h) {
    if (w) *w = r->width;
    if (h) *h = r->height;
    pvs__tile_resolve((pvs_raster *)r); /* the map is a cache the context owns */
    return r->depth;
}

/* ---- depth pyramid: Durand 2000 §2.4 "Hierarchical Depth Map" (after Greene, Kass, Miller 1993),
   queried top-down, stopping where a level decides hidden or visible (§6.1) ---- */

/* One texel: the farthest and nearest of the (up to) 2 x 2 texels at (x0, y0) of the level below. */
PVS__STATIC void pvs__pyramid_texel(const float *pmin, const float *pmax, uint32_t pw, uint32_t ph, uint32_t x0, uint32_t y0,
                                    float *out_min, float *out_max) {
    uint32_t x1 = x0 + 1 < pw ? x0 + 1 : x0, y1 = y0 + 1 < ph ? y0 + 1 : y0;
    float a = pmin[y0 * pw + x0], b = pmin[y0 * pw + x1], c = pmin[y1 * pw + x0], d = pmin[y1 * pw + x1];
    float lo = a < b ? a : b, lo2 = c < d ? c : d;
    *out_min = lo < lo2 ? lo : lo2;
    a = pmax[y0 * pw + x0]; b = pmax[y0 * pw + x1]; c = pmax[y1 * pw + x0]; d = pmax[y1 * pw + x1];
    a = a > b ? a : b;
    c = c > d ? c : d;
    *out_max = a > c ? a : c;
}

/* The pyramid over the tiles: level 0 holds per tile the farthest (its base) and the nearest value of
   its pixels, each level above the extremes of 1 x 2, 2 x 1 or 2 x 2 texels below (texels kept about
   square in pixels). */
PVS__STATIC void pvs__tile_pyramid(pvs_raster *r) {
    uint32_t l, x, y, n = r->tw * r->th, i;
    float *lo = r->tlmin[0], *hi = r->tlmax[0];
    for (i = 0; i < n; ++i) {
        const pvs__tile *t = r->tile + i;
        lo[i] = t->z0;
        hi[i] = (t->mask[0] | t->mask[1] | t->mask[2] | t->mask[3]) ? t->z1 : t->z0;
    }
    for (l = 1; l <= r->tlevels; ++l) {
        uint32_t pw = r->tlw[l - 1], ph = r->tlh[l - 1], w = r->tlw[l], h = r->tlh[l];
        uint32_t mx = r->tsx[l] != r->tsx[l - 1], my = r->tsy[l] != r->tsy[l - 1];
        const float *pmin = r->tlmin[l - 1], *pmax = r->tlmax[l - 1];
        float *dmin = r->tlmin[l], *dmax = r->tlmax[l];
        for (y = 0; y < h; ++y) {
            uint32_t y0 = y << my, y1 = (y << my) + my < ph ? (y << my) + my : y0;
            for (x = 0; x < w; ++x) {
                uint32_t x0 = x << mx, x1 = (x << mx) + mx < pw ? (x << mx) + mx : x0;
                float a = pmin[y0 * pw + x0], b = pmin[y0 * pw + x1], c = pmin[y1 * pw + x0], d = pmin[y1 * pw + x1];
                a = a < b ? a : b;
                c = c < d ? c : d;
                dmin[y * w + x] = a < c ? a : c;
                a = pmax[y0 * pw + x0]; b = pmax[y0 * pw + x1]; c = pmax[y1 * pw + x0]; d = pmax[y1 * pw + x1];
                a = a > b ? a : b;
                c = c > d ? c : d;
                dmax[y * w + x] = a > c ? a : c;
            }
        }
    }
    r->pyramid_valid = 2;
}

PVS_API void pvs_raster_build_pyramid(pvs_raster *r) {
    uint32_t l, x, y;
    if (r->tiled && !r->mixed) {
        pvs__tile_pyramid(r);
        return;
    }
    pvs__tile_resolve(r);
    r->lmin[0] = r->lmax[0] = r->depth;
    for (l = 1; l <= r->levels; ++l) {
        uint32_t pw = r->lw[l - 1], ph = r->lh[l - 1], w = r->lw[l], h = r->lh[l];
        const float *pmin = r->lmin[l - 1], *pmax = r->lmax[l - 1];
        float *dmin = r->lmin[l], *dmax = r->lmax[l];
        for (y = 0; y < h; ++y)
            for (x = 0; x < w; ++x) {
#if defined(PVS__SSE2)
                if (!(r->flags & PVS_RASTER_SCALAR) && 2 * x + 8 <= pw) { /* four texels from a 2 x 8 block */
                    const float *a0 = pmin + (size_t)(2 * y) * pw + 2 * x, *b0 = pmax + (size_t)(2 * y) * pw + 2 * x;
                    const float *a1 = 2 * y + 1 < ph ? a0 + pw : a0, *b1 = 2 * y + 1 < ph ? b0 + pw : b0;
                    __m128 v0 = _mm_min_ps(_mm_loadu_ps(a0), _mm_loadu_ps(a1)), v1 = _mm_min_ps(_mm_loadu_ps(a0 + 4), _mm_loadu_ps(a1 + 4));
                    __m128 u0 = _mm_max_ps(_mm_loadu_ps(b0), _mm_loadu_ps(b1)), u1 = _mm_max_ps(_mm_loadu_ps(b0 + 4), _mm_loadu_ps(b1 + 4));
                    _mm_storeu_ps(dmin + y * w + x, _mm_min_ps(_mm_shuffle_ps(v0, v1, _MM_SHUFFLE(2, 0, 2, 0)), _mm_shuffle_ps(v0, v1, _MM_SHUFFLE(3, 1, 3, 1))));
                    _mm_storeu_ps(dmax + y * w + x, _mm_max_ps(_mm_shuffle_ps(u0, u1, _MM_SHUFFLE(2, 0, 2, 0)), _mm_shuffle_ps(u0, u1, _MM_SHUFFLE(3, 1, 3, 1))));
                    x += 3;
                    continue;
                }
#endif
                pvs__pyramid_texel(pmin, pmax, pw, ph, 2 * x, 2 * y, dmin + y * w + x, dmax + y * w + x);
            }
    }
    r->pyramid_valid = 1;
}

/* 1 if some pixel of [x0, x1] x [y0, y1] (level-0 pixels, inside the map) under texel (tx, ty) of
   level l stores a depth <= d. */
PVS__STATIC int pvs__pyramid_visible(const pvs_raster *r, uint32_t l, uint32_t tx, uint32_t ty, int32_t x0, int32_t y0,
                                     int32_t x1, int32_t y1, float d) {
    uint32_t w = r->lw[l];
    float lo = r->lmin[l][ty * w + tx], hi = r->lmax[l][ty * w + tx];
    uint32_t cx, cy, cx0, cx1, cy0, cy1, pw, ph;
    if (lo > d) return 0;   /* everything under the texel is nearer: hidden */
    if (hi <= d) return 1;  /* everything under the texel is farther: visible (the texel meets the rect) */
    /* l > 0 here: a level-0 texel has lo == hi */
    pw = r->lw[l - 1];
    ph = r->lh[l - 1];
    cx0 = 2 * tx; cx1 = cx0 + 1 < pw ? cx0 + 1 : cx0;
    cy0 = 2 * ty; cy1 = cy0 + 1 < ph ? cy0 + 1 : cy0;
    for (cy = cy0; cy <= cy1; ++cy)
        for (cx = cx0; cx <= cx1; ++cx) {
            int32_t px0 = (int32_t)(cx << (l - 1)), py0 = (int32_t)(cy << (l - 1));
            int32_t px1 = px0 + (int32_t)(1u << (l - 1)) - 1, py1 = py0 + (int32_t)(1u << (l - 1)) - 1;
            if (px1 < x0 || px0 > x1 || py1 < y0 || py0 > y1) continue;
            if (pvs__pyramid_visible(r, l - 1, cx, cy, x0, y0, x1, y1, d)) return 1;
        }
    return 0;
}

/* pvs__pyramid_visible over the tile pyramid; at a tile, the pixels of the rectangle in and out of the
   working layer decide exactly. px: the pixel rectangle, tr: its tile range. */
PVS__STATIC int pvs__tpyr_visible(const pvs_raster *r, uint32_t l, uint32_t tx, uint32_t ty, const int32_t *px, const uint32_t *tr, float d) {
    uint32_t w = r->tlw[l], cx, cy, cx0, cx1, cy0, cy1;
    float lo = r->tlmin[l][ty * w + tx], hi = r->tlmax[l][ty * w + tx];
    if (lo > d) return 0;  /* every pixel under the texel is nearer: hidden */
    if (hi <= d) return 1; /* every pixel under it is farther (the texel meets the rectangle) */
    if (l == 0) {          /* z0 <= d < z1: visible where the rectangle leaves the working layer */
        const pvs__tile *t = r->tile + (size_t)ty * r->tw + tx;
        int32_t bx = (int32_t)(tx << PVS__TW_SHIFT), by = (int32_t)(ty << PVS__TH_SHIFT);
        int32_t a0 = (px[0] > bx ? px[0] : bx) - bx, a1 = (px[2] < bx + 31 ? px[2] : bx + 31) - bx;
        int32_t b0 = (px[1] > by ? px[1] : by) - by, b1 = (px[3] < by + 3 ? px[3] : by + 3) - by, k;
        uint32_t bits = (~0u << a0) & (~0u >> (31 - a1));
        for (k = b0; k <= b1; ++k)
            if (bits & ~t->mask[k]) return 1;
        return 0;
    }
    cx0 = cx1 = tx;
    cy0 = cy1 = ty;
    if (r->tsx[l] != r->tsx[l - 1]) {
        cx0 = 2 * tx;
        cx1 = cx0 + 1 < r->tlw[l - 1] ? cx0 + 1 : cx0;
    }
    if (r->tsy[l] != r->tsy[l - 1]) {
        cy0 = 2 * ty;
        cy1 = cy0 + 1 < r->tlh[l - 1] ? cy0 + 1 : cy0;
    }
    for (cy = cy0; cy <= cy1; ++cy)
        for (cx = cx0; cx <= cx1; ++cx) {
            uint32_t sx = r->tsx[l - 1], sy = r->tsy[l - 1];
            if (((cx + 1) << sx) - 1 < tr[0] || (cx << sx) > tr[2] || ((cy + 1) << sy) - 1 < tr[1] || (cy << sy) > tr[3]) continue;
            if (pvs__tpyr_visible(r, l - 1, cx, cy, px, tr, d)) return 1;
        }
    return 0;
}

PVS_API int pvs_raster_test_rect(pvs_raster *r, int32_t x0, int32_t y0, int32_t x1, int32_t y1, float depth) {
    uint32_t l = 0, tx, ty;
    if (x0 < 0) x0 = 0;
    if (y0 < 0) y0 = 0;
    if (x1 > (int32_t)r->width - 1) x1 = (int32_t)r->width - 1;
    if (y1 > (int32_t)r->height - 1) y1 = (int32_t)r->height - 1;
    if (x0 > x1 || y0 > y1) return 0;
    if (!r->pyramid_valid) pvs_raster_build_pyramid(r);
    if (r->pyramid_valid == 2) {
        int32_t px[4];
        uint32_t tr[4];
        px[0] = x0; px[1] = y0; px[2] = x1; px[3] = y1;
        tr[0] = (uint32_t)x0 >> PVS__TW_SHIFT; tr[1] = (uint32_t)y0 >> PVS__TH_SHIFT;
        tr[2] = (uint32_t)x1 >> PVS__TW_SHIFT; tr[3] = (uint32_t)y1 >> PVS__TH_SHIFT;
        /* the finest level where the rectangle spans at most 2 x 2 texels */
        while (l < r->tlevels && ((tr[2] >> r->tsx[l]) - (tr[0] >> r->tsx[l]) > 1 || (tr[3] >> r->tsy[l]) - (tr[1] >> r->tsy[l]) > 1)) ++l;
        for (ty = tr[1] >> r->tsy[l]; ty <= tr[3] >> r->tsy[l]; ++ty)
            for (tx = tr[0] >> r->tsx[l]; tx <= tr[2] >> r->tsx[l]; ++tx)
                if (pvs__tpyr_visible(r, l, tx, ty, px, tr, depth)) return 1;
        return 0;
    }
    /* the coarsest level where the rectangle spans at most 2 x 2 texels */
    while (l < r->levels && (((uint32_t)x1 >> l) - ((uint32_t)x0 >> l) > 1 || ((uint32_t)y1 >> l) - ((uint32_t)y0 >> l) > 1)) ++l;
    for (ty = (uint32_t)y0 >> l; ty <= (uint32_t)y1 >> l; ++ty)
        for (tx = (uint32_t)x0 >> l; tx <= (uint32_t)x1 >> l; ++tx)
            if (pvs__pyramid_visible(r, l, tx, ty, x0, y0, x1, y1, depth)) return 1;
    return 0;
}

/* ---- box tests in float: the eight corners in two SIMD registers (Masked Occlusion Culling tests
   boxes by their screen rectangle and nearest depth the same way), with error bounds. Each
   clip coordinate c_r = m_r . (p, 1) is computed in float with four roundings, at most 4.01 u S_r
   (u = 2^-24, S_r = |m_r0| + |m_r1| + |m_r2| times the box's largest |coordinate|, plus |m_r3|);
   E_r = 8 u S_r is twice that, which also covers rounding the differences the tests compare
   (|c| <= 1.01 S, so u |c_a - c_b| < (E_a + E_b) / 8). A corner with w > 2 E_w has a true w of at
   least 3/4 of the computed one, so x/w is off by at most 2/3 (E_x + |x/w| E_w) / w plus the
   division's rounding; the per-box maxima of those terms widen the rectangle and raise the depth.
   Boxes too large for float (S_r > 1e30) take the double path. ---- */

/* What the corners give, all in front of the near plane: screen extremes, the nearest depth, the
   largest 1 / w and |x / w|, |y / w|, |z / w|. */
typedef struct pvs__boxf {
    float xmin, xmax, ymin, ymax, zmax, rmax, nx, ny, nz;
} pvs__boxf;

/* The thresholds of one box: E_x, E_y, E_z, E_w, E_w + E_z, E_x + E_w, E_y + E_w, 2 E_w. */
typedef struct pvs__boxe {
    float e[4], nz, xw, yw, w2;
} pvs__boxe;

/* 0 = surely invisible, 1 = may reach behind the near plane (visible, no depth test), 2 = *o filled,
   -1 = not finite (the caller falls back). */
PVS__STATIC int pvs__box_scalar(const pvs_raster *r, const pvs_box *b, const pvs__boxe *E, pvs__boxf *o) {
    const float *m = r->mf;
    float c[8][4];
    int k, bn = 0, bw = 0, mb = 0, s0 = 0, s1 = 0, s2 = 0, s3 = 0;
    memset(o, 0, sizeof(*o));
    for (k = 0; k < 8; ++k) {
        float X = k & 1 ? b->max[0] : b->min[0], Y = k & 2 ? b->max[1] : b->min[1], Z = k & 4 ? b->max[2] : b->min[2];
        int rr;
        for (rr = 0; rr < 4; ++rr) {
            float a = m[4 * rr] * X + m[4 * rr + 1] * Y;
            c[k][rr] = a + m[4 * rr + 2] * Z + m[4 * rr + 3];
        }
        bn += c[k][3] - c[k][2] < 0.0f - E->nz;
        bw += c[k][3] < 0.0f - E->e[3];
        mb += c[k][3] - c[k][2] < E->nz || c[k][3] <= E->w2;
        s0 += c[k][0] - c[k][3] > E->xw;
        s1 += 0.0f - c[k][0] - c[k][3] > E->xw;
        s2 += c[k][1] - c[k][3] > E->yw;
        s3 += 0.0f - c[k][1] - c[k][3] > E->yw;
    }
    if (bn == 8 || bw == 8 || s0 == 8 || s1 == 8 || s2 == 8 || s3 == 8) return 0;
    if (mb) return 1;
    for (k = 0; k < 8; ++k) {
        float rw = 1.0f / c[k][3], xn = c[k][0] * rw, yn = c[k][1] * rw, z = c[k][2] * rw;
        float x = xn * r->hwf + r->hwf, y = yn * r->hhf + r->hhf;
        xn = xn < 0.0f ? 0.0f - xn : xn;
        yn = yn < 0.0f ? 0.0f - yn : yn;
        if (k == 0) {
            o->xmin = o->xmax = x; o->ymin = o->ymax = y; o->zmax = z; o->rmax = rw; o->nx = xn; o->ny = yn;
            o->nz = z < 0.0f ? 0.0f - z : z;
        } else {
            o->xmin = x < o->xmin ? x : o->xmin; o->xmax = x > o->xmax ? x : o->xmax;
            o->ymin = y < o->ymin ? y : o->ymin; o->ymax = y > o->ymax ? y : o->ymax;
            o->zmax = z > o->zmax ? z : o->zmax;
            o->rmax = rw > o->rmax ? rw : o->rmax;
            o->nx = xn > o->nx ? xn : o->nx;
            o->ny = yn > o->ny ? yn : o->ny;
            z = z < 0.0f ? 0.0f - z : z;
            o->nz = z > o->nz ? z : o->nz;
        }
    }
    return 2;
}

#if defined(PVS__SSE2)
PVS__STATIC float pvs__hmin_sse2(__m128 v) {
    v = _mm_min_ps(v, _mm_movehl_ps(v, v));
    return _mm_cvtss_f32(_mm_min_ss(v, _mm_shuffle_ps(v, v, 1)));
}
PVS__STATIC float pvs__hmax_sse2(__m128 v) {
    v = _mm_max_ps(v, _mm_movehl_ps(v, v));
    return _mm_cvtss_f32(_mm_max_ss(v, _mm_shuffle_ps(v, v, 1)));
}
PVS__STATIC int pvs__box_simd(const pvs_raster *r, const pvs_box *b, const pvs__boxe *E, pvs__boxf *o) {
    const __m128 X = _mm_setr_ps(b->min[0], b->max[0], b->min[0], b->max[0]), Y = _mm_setr_ps(b->min[1], b->min[1], b->max[1], b->max[1]);
    const __m128 Z0 = _mm_set1_ps(b->min[2]), Z1 = _mm_set1_ps(b->max[2]), zero = _mm_setzero_ps();
    const __m128 absm = _mm_castsi128_ps(_mm_set1_epi32(0x7fffffff));
    __m128 c0[4], c1[4], t0, t1, q0, q1, v0, v1, rw0, rw1;
    int all, any;
#define PVS__ROW(rr) do { \
        __m128 a = _mm_add_ps(_mm_mul_ps(_mm_loadu_ps(r->mb[4 * rr]), X), _mm_mul_ps(_mm_loadu_ps(r->mb[4 * rr + 1]), Y)); \
        c0[rr] = _mm_add_ps(_mm_add_ps(a, _mm_mul_ps(_mm_loadu_ps(r->mb[4 * rr + 2]), Z0)), _mm_loadu_ps(r->mb[4 * rr + 3])); \
        c1[rr] = _mm_add_ps(_mm_add_ps(a, _mm_mul_ps(_mm_loadu_ps(r->mb[4 * rr + 2]), Z1)), _mm_loadu_ps(r->mb[4 * rr + 3])); } while (0)
    PVS__ROW(0);
    PVS__ROW(1);
    PVS__ROW(2);
    PVS__ROW(3);
#undef PVS__ROW
    q0 = _mm_sub_ps(c0[3], c0[2]);
    q1 = _mm_sub_ps(c1[3], c1[2]);
    t0 = _mm_set1_ps(0.0f - E->nz);
    all = _mm_movemask_ps(_mm_and_ps(_mm_cmplt_ps(q0, t0), _mm_cmplt_ps(q1, t0)));
    t0 = _mm_set1_ps(0.0f - E->e[3]);
    all |= _mm_movemask_ps(_mm_and_ps(_mm_cmplt_ps(c0[3], t0), _mm_cmplt_ps(c1[3], t0))) << 4;
    t0 = _mm_set1_ps(E->xw);
    all |= _mm_movemask_ps(_mm_and_ps(_mm_cmpgt_ps(_mm_sub_ps(c0[0], c0[3]), t0), _mm_cmpgt_ps(_mm_sub_ps(c1[0], c1[3]), t0))) << 8;
    all |= _mm_movemask_ps(_mm_and_ps(_mm_cmpgt_ps(_mm_sub_ps(_mm_sub_ps(zero, c0[0]), c0[3]), t0),
                                      _mm_cmpgt_ps(_mm_sub_ps(_mm_sub_ps(zero, c1[0]), c1[3]), t0))) << 12;
    t0 = _mm_set1_ps(E->yw);
    all |= _mm_movemask_ps(_mm_and_ps(_mm_cmpgt_ps(_mm_sub_ps(c0[1], c0[3]), t0), _mm_cmpgt_ps(_mm_sub_ps(c1[1], c1[3]), t0))) << 16;
    all |= _mm_movemask_ps(_mm_and_ps(_mm_cmpgt_ps(_mm_sub_ps(_mm_sub_ps(zero, c0[1]), c0[3]), t0),
                                      _mm_cmpgt_ps(_mm_sub_ps(_mm_sub_ps(zero, c1[1]), c1[3]), t0))) << 20;
    if ((all & 15) == 15 || (all & 0xf0) == 0xf0 || (all & 0xf00) == 0xf00 || (all & 0xf000) == 0xf000 || (all & 0xf0000) == 0xf0000 ||
        (all & 0xf00000) == 0xf00000)
        return 0;
    t0 = _mm_set1_ps(E->nz);
    t1 = _mm_set1_ps(E->w2);
    any = _mm_movemask_ps(_mm_or_ps(_mm_or_ps(_mm_cmplt_ps(q0, t0), _mm_cmple_ps(c0[3], t1)), _mm_or_ps(_mm_cmplt_ps(q1, t0), _mm_cmple_ps(c1[3], t1))));
    if (any) return 1;
    rw0 = _mm_div_ps(_mm_set1_ps(1.0f), c0[3]);
    rw1 = _mm_div_ps(_mm_set1_ps(1.0f), c1[3]);
    o->rmax = pvs__hmax_sse2(_mm_max_ps(rw1, rw0));
    v0 = _mm_mul_ps(c0[0], rw0); /* x / w */
    v1 = _mm_mul_ps(c1[0], rw1);
    o->nx = pvs__hmax_sse2(_mm_max_ps(_mm_and_ps(v1, absm), _mm_and_ps(v0, absm)));
    t0 = _mm_set1_ps(r->hwf);
    v0 = _mm_add_ps(_mm_mul_ps(v0, t0), t0);
    v1 = _mm_add_ps(_mm_mul_ps(v1, t0), t0);
    o->xmin = pvs__hmin_sse2(_mm_min_ps(v1, v0));
    o->xmax = pvs__hmax_sse2(_mm_max_ps(v1, v0));
    v0 = _mm_mul_ps(c0[1], rw0);
    v1 = _mm_mul_ps(c1[1], rw1);
    o->ny = pvs__hmax_sse2(_mm_max_ps(_mm_and_ps(v1, absm), _mm_and_ps(v0, absm)));
    t0 = _mm_set1_ps(r->hhf);
    v0 = _mm_add_ps(_mm_mul_ps(v0, t0), t0);
    v1 = _mm_add_ps(_mm_mul_ps(v1, t0), t0);
    o->ymin = pvs__hmin_sse2(_mm_min_ps(v1, v0));
    o->ymax = pvs__hmax_sse2(_mm_max_ps(v1, v0));
    v0 = _mm_mul_ps(c0[2], rw0);
    v1 = _mm_mul_ps(c1[2], rw1);
    o->zmax = pvs__hmax_sse2(_mm_max_ps(v1, v0));
    o->nz = pvs__hmax_sse2(_mm_max_ps(_mm_and_ps(v1, absm), _mm_and_ps(v0, absm)));
    return 2;
}
#define PVS__HAVE_BOX_SIMD 1
#elif defined(PVS__NEON) && defined(__aarch64__)
PVS__STATIC int pvs__box_simd(const pvs_raster *r, const pvs_box *b, const pvs__boxe *E, pvs__boxf *o) {
    const float xs[4] = {b->min[0], b->max[0], b->min[0], b->max[0]}, ys[4] = {b->min[1], b->min[1], b->max[1], b->max[1]};
    const float32x4_t X = vld1q_f32(xs), Y = vld1q_f32(ys), Z0 = vdupq_n_f32(b->min[2]), Z1 = vdupq_n_f32(b->max[2]), zero = vdupq_n_f32(0.0f);
    float32x4_t c0[4], c1[4], t0, t1, q0, q1, v0, v1, rw0, rw1, one = vdupq_n_f32(1.0f);
    const float *mf = r->mf;
    int rr;
    for (rr = 0; rr < 4; ++rr) {
        float32x4_t a = vaddq_f32(vmulq_f32(vdupq_n_f32(mf[4 * rr]), X), vmulq_f32(vdupq_n_f32(mf[4 * rr + 1]), Y));
        c0[rr] = vaddq_f32(vaddq_f32(a, vmulq_f32(vdupq_n_f32(mf[4 * rr + 2]), Z0)), vdupq_n_f32(mf[4 * rr + 3]));
        c1[rr] = vaddq_f32(vaddq_f32(a, vmulq_f32(vdupq_n_f32(mf[4 * rr + 2]), Z1)), vdupq_n_f32(mf[4 * rr + 3]));
    }
    q0 = vsubq_f32(c0[3], c0[2]);
    q1 = vsubq_f32(c1[3], c1[2]);
#define PVS__ALL(m) (vminvq_u32(m) != 0)
#define PVS__ANY(m) (vmaxvq_u32(m) != 0)
    t0 = vdupq_n_f32(0.0f - E->nz);
    if (PVS__ALL(vandq_u32(vcltq_f32(q0, t0), vcltq_f32(q1, t0)))) return 0;
    t0 = vdupq_n_f32(0.0f - E->e[3]);
    if (PVS__ALL(vandq_u32(vcltq_f32(c0[3], t0), vcltq_f32(c1[3], t0)))) return 0;
    t0 = vdupq_n_f32(E->xw);
    if (PVS__ALL(vandq_u32(vcgtq_f32(vsubq_f32(c0[0], c0[3]), t0), vcgtq_f32(vsubq_f32(c1[0], c1[3]), t0)))) return 0;
    if (PVS__ALL(vandq_u32(vcgtq_f32(vsubq_f32(vsubq_f32(zero, c0[0]), c0[3]), t0), vcgtq_f32(vsubq_f32(vsubq_f32(zero, c1[0]), c1[3]), t0)))) return 0;
    t0 = vdupq_n_f32(E->yw);
    if (PVS__ALL(vandq_u32(vcgtq_f32(vsubq_f32(c0[1], c0[3]), t0), vcgtq_f32(vsubq_f32(c1[1], c1[3]), t0)))) return 0;
    if (PVS__ALL(vandq_u32(vcgtq_f32(vsubq_f32(vsubq_f32(zero, c0[1]), c0[3]), t0), vcgtq_f32(vsubq_f32(vsubq_f32(zero, c1[1]), c1[3]), t0)))) return 0;
    t0 = vdupq_n_f32(E->nz);
    t1 = vdupq_n_f32(E->w2);
    if (PVS__ANY(vorrq_u32(vorrq_u32(vcltq_f32(q0, t0), vcleq_f32(c0[3], t1)), vorrq_u32(vcltq_f32(q1, t0), vcleq_f32(c1[3], t1))))) return 1;
#undef PVS__ALL
#undef PVS__ANY
    rw0 = vdivq_f32(one, c0[3]);
    rw1 = vdivq_f32(one, c1[3]);
    o->rmax = vmaxvq_f32(vmaxq_f32(rw1, rw0));
    v0 = vmulq_f32(c0[0], rw0);
    v1 = vmulq_f32(c1[0], rw1);
    o->nx = vmaxvq_f32(vmaxq_f32(vabsq_f32(v1), vabsq_f32(v0)));
    t0 = vdupq_n_f32(r->hwf);
    v0 = vaddq_f32(vmulq_f32(v0, t0), t0);
    v1 = vaddq_f32(vmulq_f32(v1, t0), t0);
    o->xmin = vminvq_f32(vminq_f32(v1, v0));
    o->xmax = vmaxvq_f32(vmaxq_f32(v1, v0));
    v0 = vmulq_f32(c0[1], rw0);
    v1 = vmulq_f32(c1[1], rw1);
    o->ny = vmaxvq_f32(vmaxq_f32(vabsq_f32(v1), vabsq_f32(v0)));
    t0 = vdupq_n_f32(r->hhf);
    v0 = vaddq_f32(vmulq_f32(v0, t0), t0);
    v1 = vaddq_f32(vmulq_f32(v1, t0), t0);
    o->ymin = vminvq_f32(vminq_f32(v1, v0));
    o->ymax = vmaxvq_f32(vmaxq_f32(v1, v0));
    v0 = vmulq_f32(c0[2], rw0);
    v1 = vmulq_f32(c1[2], rw1);
    o->zmax = vmaxvq_f32(vmaxq_f32(v1, v0));
    o->nz = vmaxvq_f32(vmaxq_f32(vabsq_f32(v1), vabsq_f32(v0)));
    return 2;
}
#define PVS__HAVE_BOX_SIMD 1
#endif

/* Double to a float at least as large without a library call: for margins (v >= 0, tiny slack) and
   for a finite v (when rounding went down, one step up: |f| 2^-23 plus the least subnormal is at
   least the gap to the next float, and rounding is monotonic). */
PVS__STATIC float pvs__f_up_pos(double v) { return (float)(v * (1.0 + 4.76837158203125e-07) + 1e-37); }
PVS__STATIC float pvs__f_up_fast(double v) {
    float f = (float)v;
    if ((double)f < v) f = (float)((double)f + pvs__dabs((double)f) * 1.1920928955078125e-07 + 1.5e-45);
    return f;
}

/* The float box test; returns -1 when the box needs the double path. */
PVS__STATIC int pvs__raster_box_f(const pvs_raster *r, const pvs_box *b, int32_t rect[4], float *dnear) {
    pvs__boxe E;
    pvs__boxf o = {0, 0, 0, 0, 0, 0, 0, 0, 0};
    double pm = 0.0, e[4], ex, ey, ez, hw = 0.5 * (double)r->width, hh = 0.5 * (double)r->height;
    int k, res, nan = 0;
    float pf = 0.0f;
#if defined(PVS__SSE2) /* the largest |coordinate| (exact either way; min and max are the struct's six floats) */
    {
        const __m128 absm = _mm_castsi128_ps(_mm_set1_epi32(0x7fffffff));
        __m128 a = _mm_loadu_ps(b->min), c = _mm_loadu_ps(b->min + 2);
        nan = _mm_movemask_ps(_mm_or_ps(_mm_cmpunord_ps(a, a), _mm_cmpunord_ps(c, c)));
        pf = pvs__hmax_sse2(_mm_max_ps(_mm_and_ps(a, absm), _mm_and_ps(c, absm)));
    }
#else
    for (k = 0; k < 3; ++k) {
        float lo = b->min[k] < 0.0f ? -b->min[k] : b->min[k], hi = b->max[k] < 0.0f ? -b->max[k] : b->max[k];
        nan |= !(lo == lo) || !(hi == hi);
        lo = lo > hi ? lo : hi;
        pf = lo > pf ? lo : pf;
    }
#endif
    pm = pf;
    if (nan || !(pm < 1e30)) return -1;
    for (k = 0; k < 4; ++k) {
        double sr = r->rowa[k] * pm + r->rowt[k];
        e[k] = 1.1920928955078125e-07 * sr; /* 2^-23 */
        E.e[k] = pvs__f_up_pos(e[k]);
    }
    if (!(e[0] + e[1] + e[2] + e[3] < 1e23)) return -1;
    E.nz = pvs__f_up_pos(e[3] + e[2]);
    E.xw = pvs__f_up_pos(e[0] + e[3]);
    E.yw = pvs__f_up_pos(e[1] + e[3]);
    E.w2 = pvs__f_up_pos(2.0 * e[3]);
#if defined(PVS__HAVE_BOX_SIMD)
    if (!(r->flags & PVS_RASTER_SCALAR)) res = pvs__box_simd(r, b, &E, &o);
    else
#endif
        res = pvs__box_scalar(r, b, &E, &o);
    if (res != 2) return res;
    if (!(o.rmax < 1e30f && o.nx < 1e30f && o.ny < 1e30f && o.nz < 1e30f && o.xmin > -1e30f && o.xmax < 1e30f && o.ymin > -1e30f && o.ymax < 1e30f))
        return -1;
    ex = hw * (0.7 * (e[0] + o.nx * e[3]) * o.rmax + 3e-7 * (o.nx + 1.0));
    ey = hh * (0.7 * (e[1] + o.ny * e[3]) * o.rmax + 3e-7 * (o.ny + 1.0));
    ez = 0.7 * (e[2] + o.nz * e[3]) * o.rmax + 2e-7 * o.nz;
    if (!((double)o.xmax + ex >= 0.0) || !((double)o.ymax + ey >= 0.0) || !((double)o.xmin - ex <= (double)r->width) ||
        !((double)o.ymin - ey <= (double)r->height))
        return 0;
    rect[0] = pvs__clampi(floor((double)o.xmin - ex), 0, (int32_t)r->width - 1);
    rect[1] = pvs__clampi(floor((double)o.ymin - ey), 0, (int32_t)r->height - 1);
    rect[2] = pvs__clampi(floor((double)o.xmax + ex), 0, (int32_t)r->width - 1);
    rect[3] = pvs__clampi(floor((double)o.ymax + ey), 0, (int32_t)r->height - 1);
    *dnear = pvs__f_up_fast((double)o.zmax + ez);
    return 2;
}

/* Projects a box: 0 = invisible (behind the near plane or off the screen), 1 = may be visible without
   a depth test (reaches behind the near plane), 2 = *rect and *dnear hold its pixel rectangle
   (clamped to the map) and nearest depth. */
PVS__STATIC int pvs__raster_box(const pvs_raster *r, const pvs_box *b, int32_t rect[4], float *dnear) {
    double xmin = DBL_MAX, xmax = -DBL_MAX, ymin = DBL_MAX, ymax = -DBL_MAX, dmax = -DBL_MAX, mag = 0.0, dx, perr = 0.0, zerr = 0.0;
    double hw = 0.5 * (double)r->width, hh = 0.5 * (double)r->height;
    int k, behind_near = 0, behind_w = 0, maybe_behind = 0;
    pvs__cv v[8];
    if (r->tiled) { /* float, the tiles' speed; the per-pixel mode keeps the double test */
        k = pvs__raster_box_f(r, b, rect, dnear);
        if (k >= 0) return k;
    }
    {
        /* the corners as the min corner plus the transformed edges (the margins cover the rounding) */
        pvs__cv base = pvs__raster_transform(r, b->min);
        double e[3][4];
        int ax, c;
        for (ax = 0; ax < 3; ++ax) {
            double len = (double)b->max[ax] - b->min[ax];
            for (c = 0; c < 4; ++c) e[ax][c] = r->m[4 * c + ax] * len;
        }
        double ebig = 0.0;
        for (c = 0; c < 4; ++c) ebig = pvs__dmax(ebig, pvs__dabs(e[0][c]) + pvs__dabs(e[1][c]) + pvs__dabs(e[2][c]));
        for (k = 0; k < 8; ++k) {
            for (c = 0; c < 4; ++c)
                v[k].c[c] = base.c[c] + (k & 1 ? e[0][c] : 0.0) + (k & 2 ? e[1][c] : 0.0) + (k & 4 ? e[2][c] : 0.0);
            v[k].e = 2.0 * base.e + 8.881784197001252e-16 * ebig;
            /* surely behind (beyond the rounding) / maybe behind */
            if (v[k].c[3] - v[k].c[2] < -2.0 * v[k].e) ++behind_near;
            if (v[k].c[3] < -v[k].e) ++behind_w;
            if (v[k].c[3] - v[k].c[2] < 2.0 * v[k].e || v[k].c[3] <= v[k].e) ++maybe_behind;
        }
    }
    if (behind_near == 8 || behind_w == 8) return 0;
    {
        /* the screen's side planes in clip space (-w <= x <= w, -w <= y <= w): a box wholly outside one
           is off the screen whatever its w (points with w <= 0 are invisible anyway) */
        int side;
        for (side = 0; side < 4; ++side) {
            int out = 0, ax = side >> 1;
            double sg = side & 1 ? -1.0 : 1.0;
            for (k = 0; k < 8; ++k) {
                double q = sg * v[k].c[ax] - v[k].c[3];
                double tol = PVS__RASTER_ERR_D * (pvs__dabs(v[k].c[ax]) + pvs__dabs(v[k].c[3])) + 2.0 * v[k].e;
                out += q > tol;
            }
            if (out == 8) return 0;
        }
    }
    if (maybe_behind) return 1;
    for (k = 0; k < 8; ++k) {
        double iw = 1.0 / v[k].c[3], x = (v[k].c[0] * iw + 1.0) * hw, y = (v[k].c[1] * iw + 1.0) * hh, z = v[k].c[2] * iw;
        double e = v[k].e * iw;
        perr = pvs__dmax(perr, 2.0 * e * (1.0 + pvs__dabs(v[k].c[0] * iw) + pvs__dabs(v[k].c[1] * iw)) * pvs__dmax(hw, hh));
        zerr = pvs__dmax(zerr, 2.0 * e * (1.0 + pvs__dabs(z)));
        xmin = pvs__dmin(xmin, x); xmax = pvs__dmax(xmax, x);
        ymin = pvs__dmin(ymin, y); ymax = pvs__dmax(ymax, y);
        dmax = pvs__dmax(dmax, z);
        mag = pvs__dmax(mag, pvs__dabs(x) + pvs__dabs(y) + pvs__dabs(z));
    }
    dx = PVS__RASTER_ERR_D * (mag + 1.0) + perr;
    if (!(xmax + dx >= 0.0) || !(ymax + dx >= 0.0) || !(xmin - dx <= (double)r->width) || !(ymin - dx <= (double)r->height))
        return 0;
    rect[0] = pvs__clampi(floor(xmin - dx), 0, (int32_t)r->width - 1);
    rect[1] = pvs__clampi(floor(ymin - dx), 0, (int32_t)r->height - 1);
    rect[2] = pvs__clampi(floor(xmax + dx), 0, (int32_t)r->width - 1);
    rect[3] = pvs__clampi(floor(ymax + dx), 0, (int32_t)r->height - 1);
    *dnear = pvs__f_up(dmax + PVS__RASTER_ERR_D * (mag + 1e-30) + zerr);
    return 2;
}

PVS_API int pvs_raster_test_box(pvs_raster *r, const pvs_box *b) {
    int32_t rect[4];
    float d;
    int k = r->tiled ? pvs__raster_box_f(r, b, rect, &d) : -1;
    if (k < 0) k = pvs__raster_box(r, b, rect, &d);
    if (k != 2) return k;
    return pvs_raster_test_rect(r, rect[0], rect[1], rect[2], rect[3], d);
}

/* ---- context ---- */

PVS_API void pvs_raster_destroy(pvs_raster *r) {
    pvs_allocator a;
    size_t cells;
    if (!r) return;
    a = r->allocator;
    cells = (size_t)r->cm_w * r->cm_h;
    pvs__free_array(&a, r->depth, (size_t)r->width * r->height, sizeof(float));
    pvs__free_array(&a, r->pyramid, r->pyramid_floats, sizeof(float));
    pvs__free_array(&a, r->tile_min, r->tiles, sizeof(float));
    pvs__free_array(&a, r->tile, (size_t)r->tw * r->th, sizeof(pvs__tile));
    pvs__free_array(&a, r->tpyramid, r->tpyramid_floats, sizeof(float));
    pvs__free_array(&a, r->bmin, (size_t)r->bw * r->bh, sizeof(float));
    pvs__free_array(&a, r->bdirty, (size_t)r->bw * r->bh, 1);
    pvs__free(&a, r->sweep, r->sweep_size, 16);
    pvs__free_array(&a, r->occ, r->max_occluders, sizeof(pvs__occsel));
    pvs__free_array(&a, r->tri_seen, PVS_BITSET_WORDS(r->max_triangles), sizeof(pvs_word));
    pvs__free_array(&a, r->obj_done, PVS_BITSET_WORDS(r->max_objects), sizeof(pvs_word));
    pvs__free_array(&a, r->cm, cells, sizeof(float));
    pvs__free_array(&a, r->cm_tile_min, r->cm_tiles, sizeof(float));
    pvs__free_array(&a, r->cm_bound, cells, sizeof(float));
    pvs__free_array(&a, r->cm_start, cells + (r->cm_start ? 1 : 0), sizeof(uint32_t));
    pvs__free_array(&a, r->cm_items, r->cm_item_count, sizeof(uint32_t));
    pvs__free_array(&a, r->mt, r->mesh_cap, sizeof(pvs__mtri));
    pvs__free_array(&a, r->mcid, 3 * (size_t)r->mesh_cap, sizeof(uint32_t));
    pvs__free_array(&a, r->mpart, 3 * (size_t)r->mesh_cap, sizeof(uint32_t));
    pvs__free_array(&a, r->mvst, 3 * (size_t)r->mesh_cap, 1);
    pvs__free_array(&a, r->mgrp, r->mesh_cap, 1);
    pvs__free_array(&a, r->mtab, r->mesh_hash, sizeof(uint32_t));
    pvs__free_array(&a, r->morder, r->mesh_cap, sizeof(uint32_t));
    pvs__free_array(&a, r->mact, r->mesh_cap, sizeof(uint32_t));
    pvs__free_array(&a, r->mband, (size_t)r->th + 1, sizeof(uint32_t));
    pvs__free_array(&a, r->mzmin, (size_t)PVS__TH * r->width, sizeof(float));
    pvs__free_array(&a, r->mzin, (size_t)PVS__TH * r->width, sizeof(float));
    pvs__free_array(&a, r->mflag, (size_t)PVS__TH * r->width, 1);
    pvs__free_array(&a, r->mdirty, (size_t)PVS__TH * r->tw, 1);
    pvs__free(&a, r, sizeof(*r), 16);
}

/* Ground-plane cell range of a box in the cull map (clamped); returns 0 when the box is not entirely
   inside the region. */
PVS__STATIC int pvs__cm_range(const pvs_raster *r, const pvs_box *b, int up, int32_t *i0, int32_t *j0, int32_t *i1, int32_t *j1) {
    int u, v;
    double su, sv, a0, a1, b0, b1, eu, ev;
    pvs__ground_axes((uint32_t)up, &u, &v);
    su = ((double)r->region[2] - r->region[0]) / r->cm_w;
    sv = ((double)r->region[3] - r->region[1]) / r->cm_h;
    eu = 1e-6 * su;
    ev = 1e-6 * sv;
    a0 = ((double)b->min[u] - r->region[0]) / su;
    a1 = ((double)b->max[u] - r->region[0]) / su;
    b0 = ((double)b->min[v] - r->region[1]) / sv;
    b1 = ((double)b->max[v] - r->region[1]) / sv;
    *i0 = pvs__clampi(floor(a0 - eu), 0, (int32_t)r->cm_w - 1);
    *i1 = pvs__clampi(floor(a1 + eu), 0, (int32_t)r->cm_w - 1);
    *j0 = pvs__clampi(floor(b0 - ev), 0, (int32_t)r->cm_h - 1);
    *j1 = pvs__clampi(floor(b1 + ev), 0, (int32_t)r->cm_h - 1);
    return b->min[u] >= r->region[0] && b->max[u] <= r->region[2] && b->min[v] >= r->region[1] && b->max[v] <= r->region[3];
}

PVS_API pvs_result pvs_raster_create(const pvs_raster_desc *desc, pvs_raster **out, pvs_error *err) {
    pvs_raster *r;
    pvs_allocator a;
    uint32_t l, w, h;
    size_t floats = 0, i;
    if (out) *out = NULL;
    if (!desc || !out) return pvs__fail(err, PVS_ERROR_INVALID_ARGUMENT, -1, 0, "desc and out_raster must not be NULL");
    if (desc->width < 1 || desc->height < 1 || desc->width > 16384 || desc->height > 16384)
        return pvs__fail(err, PVS_ERROR_INVALID_ARGUMENT, -1, 0, "depth map size %ux%u is not in 1..16384", desc->width, desc->height);
    if ((desc->cull_map_width == 0) != (desc->cull_map_height == 0) || desc->cull_map_width > 4096 || desc->cull_map_height > 4096)
        return pvs__fail(err, PVS_ERROR_INVALID_ARGUMENT, -1, 0, "cull map size %ux%u is not in 1..4096 (or 0x0)",
                         desc->cull_map_width, desc->cull_map_height);
    if (desc->cull_map_width && !desc->scene)
        return pvs__fail(err, PVS_ERROR_INVALID_ARGUMENT, -1, 0, "a cull map needs the scene");
    a = desc->allocator;
    r = (pvs_raster *)pvs__alloc(&a, sizeof(*r), 16);
    if (!r) return pvs__fail(err, PVS_ERROR_OUT_OF_MEMORY, -1, 0, "raster context");
    memset(r, 0, sizeof(*r));
    r->allocator = a;
    r->width = desc->width;
    r->height = desc->height;
    r->flags = desc->flags;
    for (l = 0; l < 16; ++l) {
        r->m[l] = r->mf[l] = (l % 5 == 0) ? 1.0f : 0.0f;
        r->mb[l][0] = r->mb[l][1] = r->mb[l][2] = r->mb[l][3] = r->mf[l];
    }
    r->hwf = 0.5f * (float)r->width;
    r->hhf = 0.5f * (float)r->height;
    for (l = 0; l < 4; ++l) {
        r->rowa[l] = 1.0;
        r->rowt[l] = 0.0;
    }
    r->mabs[0] = 1.0;
    r->lw[0] = w = r->width;
    r->lh[0] = h = r->height;
    while ((w > 1 || h > 1) && r->levels < PVS__RASTER_MAX_LEVELS) {
        w = (w + 1) / 2;
        h = (h + 1) / 2;
        ++r->levels;
        r->lw[r->levels] = w;
        r->lh[r->levels] = h;
        floats += 2 * (size_t)w * h;
    }
    r->depth = (float *)pvs__alloc_array(&a, (size_t)r->width * r->height, sizeof(float));
    r->pyramid_floats = floats;
    r->pyramid = (float *)pvs__alloc_array(&a, floats, sizeof(float));
    r->tiles = (size_t)((r->width + PVS__TILE - 1) >> PVS__TILE_SHIFT) * ((r->height + PVS__TILE - 1) >> PVS__TILE_SHIFT);
    r->tile_min = (float *)pvs__alloc_array(&a, r->tiles, sizeof(float));
    if (!r->depth || !r->pyramid || !r->tile_min) goto oom;
    /* the occluder tiles and their pyramid */
    r->tiled = (r->flags & PVS_RASTER_TILED) || (!(r->flags & PVS_RASTER_PER_PIXEL) && (size_t)r->width * r->height > 65536);
    r->tw = (r->width + 31) >> PVS__TW_SHIFT;
    r->th = (r->height + PVS__TH - 1) >> PVS__TH_SHIFT;
    r->xpad = r->width & 31 ? ~0u << (r->width & 31) : 0u;
    r->ypad = r->height & (PVS__TH - 1) ? r->height & (PVS__TH - 1) : PVS__TH;
    r->tlw[0] = w = r->tw;
    r->tlh[0] = h = r->th;
    floats = 2 * (size_t)w * h;
    while (w > 1 || h > 1) {
        uint32_t pxw = 32u << r->tsx[r->tlevels], pxh = (uint32_t)PVS__TH << r->tsy[r->tlevels];
        uint32_t mx = w > 1 && (pxw <= pxh || h == 1), my = h > 1 && (pxh <= pxw || w == 1);
        if (mx) w = (w + 1) / 2;
        if (my) h = (h + 1) / 2;
        ++r->tlevels;
        r->tlw[r->tlevels] = w;
        r->tlh[r->tlevels] = h;
        r->tsx[r->tlevels] = (uint8_t)(r->tsx[r->tlevels - 1] + mx);
        r->tsy[r->tlevels] = (uint8_t)(r->tsy[r->tlevels - 1] + my);
        floats += 2 * (size_t)w * h;
    }
    r->tile = (pvs__tile *)pvs__alloc_array(&a, (size_t)r->tw * r->th, sizeof(pvs__tile));
    r->tpyramid_floats = floats;
    r->tpyramid = (float *)pvs__alloc_array(&a, floats, sizeof(float));
    r->bw = (r->tw + (1u << PVS__BLOCK_SHIFT) - 1) >> PVS__BLOCK_SHIFT;
    r->bh = (r->th + (1u << PVS__BLOCK_SHIFT) - 1) >> PVS__BLOCK_SHIFT;
    r->bmin = (float *)pvs__alloc_array(&a, (size_t)r->bw * r->bh, sizeof(float));
    r->bdirty = (uint8_t *)pvs__alloc_array(&a, (size_t)r->bw * r->bh, 1);
    if (!r->tile || !r->tpyramid || !r->bmin || !r->bdirty) goto oom;
    floats = 0;
    for (l = 0; l <= r->tlevels; ++l) {
        r->tlmin[l] = r->tpyramid + floats;
        floats += (size_t)r->tlw[l] * r->tlh[l];
        r->tlmax[l] = r->tpyramid + floats;
        floats += (size_t)r->tlw[l] * r->tlh[l];
    }
    floats = 0;
    for (l = 1; l <= r->levels; ++l) {
        r->lmin[l] = r->pyramid + floats;
        floats += (size_t)r->lw[l] * r->lh[l];
        r->lmax[l] = r->pyramid + floats;
        floats += (size_t)r->lw[l] * r->lh[l];
    }
    r->lmin[0] = r->lmax[0] = r->depth;
    pvs_raster_clear(r);
    r->max_occluders = desc->max_occluders ? desc->max_occluders : 1024;
    r->occ = (pvs__occsel *)pvs__alloc_array(&a, r->max_occluders, sizeof(pvs__occsel));
    if (!r->occ) goto oom;
    /* occluder meshes: a piece's triangles, its hash (load <= 1/2), four rows of pixels */
    r->mesh_cap = desc->max_mesh_triangles ? (desc->max_mesh_triangles < (1u << 24) ? desc->max_mesh_triangles : 1u << 24) : PVS__MESH_DEFAULT;
    for (r->mesh_hash = 16; r->mesh_hash < 6 * r->mesh_cap; r->mesh_hash <<= 1) {}
    r->mt = (pvs__mtri *)pvs__alloc_array(&a, r->mesh_cap, sizeof(pvs__mtri));
    r->mcid = (uint32_t *)pvs__alloc_array(&a, 3 * (size_t)r->mesh_cap, sizeof(uint32_t));
    r->mpart = (uint32_t *)pvs__alloc_array(&a, 3 * (size_t)r->mesh_cap, sizeof(uint32_t));
    r->mvst = (uint8_t *)pvs__alloc_array(&a, 3 * (size_t)r->mesh_cap, 1);
    r->mgrp = (int8_t *)pvs__alloc_array(&a, r->mesh_cap, 1);
    r->mtab = (uint32_t *)pvs__alloc_array(&a, r->mesh_hash, sizeof(uint32_t));
    r->morder = (uint32_t *)pvs__alloc_array(&a, r->mesh_cap, sizeof(uint32_t));
    r->mact = (uint32_t *)pvs__alloc_array(&a, r->mesh_cap, sizeof(uint32_t));
    r->mband = (uint32_t *)pvs__alloc_array(&a, (size_t)r->th + 1, sizeof(uint32_t));
    r->mzmin = (float *)pvs__alloc_array(&a, (size_t)PVS__TH * r->width, sizeof(float));
    r->mzin = (float *)pvs__alloc_array(&a, (size_t)PVS__TH * r->width, sizeof(float));
    r->mflag = (uint8_t *)pvs__alloc_array(&a, (size_t)PVS__TH * r->width, 1);
    r->mdirty = (uint8_t *)pvs__alloc_array(&a, (size_t)PVS__TH * r->tw, 1);
    if (!r->mdirty) goto oom;
    memset(r->mdirty, 0, (size_t)PVS__TH * r->tw);
    if (!r->mt || !r->mcid || !r->mpart || !r->mvst || !r->mgrp || !r->mtab || !r->morder || !r->mact || !r->mband || !r->mzmin ||
        !r->mzin || !r->mflag)
        goto oom;
    for (i = 0; i < (size_t)PVS__TH * r->width; ++i) {
        r->mzmin[i] = FLT_MAX;
        r->mzin[i] = PVS_DEPTH_EMPTY;
        r->mflag[i] = 0;
    }
    if (desc->scene) {
        const pvs_scene *s = desc->scene;
        size_t s1 = pvs_kdtree_sweep_scratch_size(s->object_tree), s2 = pvs_kdtree_sweep_scratch_size(s->triangle_tree);
        r->scene = s;
        r->max_objects = s->object_count;
        r->max_triangles = s->triangle_count;
        r->sweep_size = s1 > s2 ? s1 : s2;
        r->sweep = pvs__alloc(&a, r->sweep_size, 16);
        r->tri_seen = (pvs_word *)pvs__alloc_array(&a, PVS_BITSET_WORDS(r->max_triangles), sizeof(pvs_word));
        r->obj_done = (pvs_word *)pvs__alloc_array(&a, PVS_BITSET_WORDS(r->max_objects), sizeof(pvs_word));
        if (!r->sweep || !r->tri_seen || !r->obj_done) goto oom;
    }
    if (desc->cull_map_width) {
        /* the object grid of Wonka 1999 §4.1: every object entered into every cell it overlaps */
        const pvs_scene *s = desc->scene;
        int u, v, up = (int)s->up_axis;
        size_t cells = (size_t)desc->cull_map_width * desc->cull_map_height, total = 0;
        uint32_t o;
        pvs__ground_axes(s->up_axis, &u, &v);
        r->cm_w = desc->cull_map_width;
        r->cm_h = desc->cull_map_height;
        r->ground = s->bounds.min[up];
        r->region[0] = s->bounds.min[u];
        r->region[1] = s->bounds.min[v];
        r->region[2] = s->bounds.max[u];
        r->region[3] = s->bounds.max[v];
        for (l = 0; l < 2; ++l) /* never a zero-size region */
            if (!(r->region[2 + l] > r->region[l])) {
                r->region[l] -= 0.5f;
                r->region[2 + l] += 0.5f;
            }
        if (!(r->ground <= r->ground + 0.0f)) r->ground = 0.0f; /* empty scene bounds */
        r->cm = (float *)pvs__alloc_array(&a, cells, sizeof(float));
        r->cm_tiles = (size_t)((r->cm_w + PVS__TILE - 1) >> PVS__TILE_SHIFT) * ((r->cm_h + PVS__TILE - 1) >> PVS__TILE_SHIFT);
        r->cm_tile_min = (float *)pvs__alloc_array(&a, r->cm_tiles, sizeof(float));
        if (!r->cm_tile_min) goto oom;
        r->cm_bound = (float *)pvs__alloc_array(&a, cells, sizeof(float));
        r->cm_start = (uint32_t *)pvs__alloc_array(&a, cells + 1, sizeof(uint32_t));
        if (!r->cm || !r->cm_bound || !r->cm_start) goto oom;
        for (i = 0; i <= cells; ++i) r->cm_start[i] = 0;
        for (i = 0; i < cells; ++i) { r->cm[i] = PVS_DEPTH_EMPTY; r->cm_bound[i] = PVS_DEPTH_EMPTY; }
        for (o = 0; o < s->object_count; ++o) {
            const pvs_box *b = s->object_boxes + o;
            int32_t i0, j0, i1, j1, ii, jj;
            if (b->min[0] > b->max[0]) continue;
            pvs__cm_range(r, b, up, &i0, &j0, &i1, &j1);
            total += (size_t)(i1 - i0 + 1) * (size_t)(j1 - j0 + 1);
            if (total > 0xffffffffu) {
                pvs_raster_destroy(r);
                return pvs__fail(err, PVS_ERROR_COUNT_OVERFLOW, -1, 0, "the cull map grid holds more than 2^32 object entries");
            }
            for (jj = j0; jj <= j1; ++jj)
                for (ii = i0; ii <= i1; ++ii) {
                    size_t c = (size_t)jj * r->cm_w + (size_t)ii;
                    r->cm_start[c + 1]++;
                    if (b->max[up] > r->cm_bound[c]) r->cm_bound[c] = b->max[up];
                }
        }
        for (i = 0; i < cells; ++i) r->cm_start[i + 1] += r->cm_start[i];
        r->cm_item_count = (uint32_t)total;
        r->cm_items = (uint32_t *)pvs__alloc_array(&a, total, sizeof(uint32_t));
        if (!r->cm_items) goto oom;
        for (o = 0; o < s->object_count; ++o) { /* fill, using cm_start[c] as the cursor, then shift back */
            const pvs_box *b = s->object_boxes + o;
            int32_t i0, j0, i1, j1, ii, jj;
            if (b->min[0] > b->max[0]) continue;
            pvs__cm_range(r, b, up, &i0, &j0, &i1, &j1);
            for (jj = j0; jj <= j1; ++jj)
                for (ii = i0; ii <= i1; ++ii) r->cm_items[r->cm_start[(size_t)jj * r->cm_w + (size_t)ii]++] = o;
        }
        for (i = cells; i > 0; --i) r->cm_start[i] = r->cm_start[i - 1];
        r->cm_start[0] = 0;
    }
    *out = r;
    pvs__ok(err);
    return PVS_OK;
oom:
    pvs_raster_destroy(r);
    return pvs__fail(err, PVS_ERROR_OUT_OF_MEMORY, -1, 0, "raster buffers");
}

/* ---- occluder selection (Bittner 2002 §4.5) ---- */

typedef struct pvs__selctx {
    pvs_raster *r;
    const pvs_scene *s;
    double eye[3], fwd[3], near_d;
    float max_dist;
    uint32_t k, n;
} pvs__selctx;

/* Min-heap on score: the root is the weakest of the k kept. */
PVS__STATIC void pvs__occ_push(pvs__occsel *h, uint32_t *n, uint32_t k, float score, uint32_t tri) {
    uint32_t i, c;
    if (*n < k) {
        i = (*n)++;
        while (i > 0 && h[(i - 1) / 2].score > score) {
            h[i] = h[(i - 1) / 2];
            i = (i - 1) / 2;
        }
        h[i].score = score;
        h[i].triangle = tri;
        return;
    }
    if (!(score > h[0].score)) return;
    i = 0;
    while ((c = 2 * i + 1) < *n) {
        if (c + 1 < *n && h[c + 1].score < h[c].score) ++c;
        if (!(h[c].score < score)) break;
        h[i] = h[c];
        i = c;
    }
    h[i].score = score;
    h[i].triangle = tri;
}

/* Area-angle measure M = A |N . V| / |D|^2 (Bittner 2002 §4.5), with V the unit direction from the
   eye to the triangle's centre D (two-sided triangles: the absolute value); A |N . V| / |D|^2 is the
   solid angle the triangle subtends, approximately. */
PVS__STATIC pvs_visit pvs__select_visit(void *user, const pvs_box *node_box, float distance, const uint32_t *items, uint32_t count) {
    pvs__selctx *c = (pvs__selctx *)user;
    uint32_t i;
    (void)node_box;
    if (distance > c->max_dist) return PVS_VISIT_STOP;
    for (i = 0; i < count; ++i) {
        uint32_t t = items[i], k;
        const float *p[3];
        double e1[3], e2[3], n[3], d[3], dd, nd, front = 0.0, fr[3];
        if (pvs_bitset_test(c->r->tri_seen, t)) continue;
        pvs_bitset_set(c->r->tri_seen, t);
        for (k = 0; k < 3; ++k) p[k] = c->s->positions + 3 * (size_t)c->s->indices[3 * (size_t)t + k];
        for (k = 0; k < 3; ++k) {
            e1[k] = (double)p[1][k] - p[0][k];
            e2[k] = (double)p[2][k] - p[0][k];
            d[k] = ((double)p[0][k] + p[1][k] + p[2][k]) / 3.0 - c->eye[k];
        }
        for (k = 0; k < 3; ++k) fr[k] = c->fwd[0] * ((double)p[k][0] - c->eye[0]) + c->fwd[1] * ((double)p[k][1] - c->eye[1]) +
                                        c->fwd[2] * ((double)p[k][2] - c->eye[2]);
        front = pvs__dmax(fr[0], pvs__dmax(fr[1], fr[2]));
        if (front < c->near_d) continue; /* wholly behind the near plane */
        n[0] = e1[1] * e2[2] - e1[2] * e2[1];
        n[1] = e1[2] * e2[0] - e1[0] * e2[2];
        n[2] = e1[0] * e2[1] - e1[1] * e2[0];
        dd = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
        nd = pvs__dabs(n[0] * d[0] + n[1] * d[1] + n[2] * d[2]);
        if (!(dd > 0.0)) dd = 1e-30;
        pvs__occ_push(c->r->occ, &c->n, c->k, (float)(0.5 * nd / (dd * sqrt(dd))), t);
    }
    return PVS_VISIT_DESCEND;
}

/* ---- per-frame culling ---- */

typedef struct pvs__cullctx {
    pvs_raster *r;
    const pvs_scene *s;
    const pvs_word *candidates;
    pvs_word *visible;
    pvs_cull_stats st;
} pvs__cullctx;

PVS__STATIC pvs_visit pvs__cull_visit(void *user, const pvs_box *node_box, float distance, const uint32_t *items, uint32_t count) {
    pvs__cullctx *c = (pvs__cullctx *)user;
    uint32_t i;
    (void)distance;
    ++c->st.nodes_visited;
    ++c->st.boxes_tested;
    if (!pvs_raster_test_box(c->r, node_box)) return PVS_VISIT_SKIP;
    for (i = 0; i < count; ++i) {
        uint32_t o = items[i];
        if (pvs_bitset_test(c->r->obj_done, o)) continue;
        pvs_bitset_set(c->r->obj_done, o);
        if (c->s->object_flags[o] & PVS_OBJECT_OCCLUDER_ONLY) continue;
        if (c->candidates && !pvs_bitset_test(c->candidates, o)) continue;
        ++c->st.boxes_tested;
        if (pvs_raster_test_box(c->r, c->s->object_boxes + o)) {
            pvs_bitset_set(c->visible, o);
            ++c->st.visible;
        }
    }
    return PVS_VISIT_DESCEND;
}

/* Checks shared by both culling calls; sets the camera matrix. */
PVS__STATIC pvs_result pvs__cull_begin(pvs_raster *r, const pvs_scene *s, const pvs_camera *cam, pvs_word *visible, pvs_error *err) {
    float m[16];
    pvs_result res;
    if (!r || !s || !cam || !visible) return pvs__fail(err, PVS_ERROR_INVALID_ARGUMENT, -1, 0, "raster, scene, camera and visible must not be NULL");
    if (s->object_count > r->max_objects || s->triangle_count > r->max_triangles ||
        pvs_kdtree_sweep_scratch_size(s->object_tree) > r->sweep_size || pvs_kdtree_sweep_scratch_size(s->triangle_tree) > r->sweep_size)
        return pvs__fail(err, PVS_ERROR_BUFFER_TOO_SMALL, -1, 0, "the context was created for a smaller scene (or none)");
    res = pvs_camera_matrix(cam, (float)r->width / (float)r->height, m);
    if (res != PVS_OK) return pvs__fail(err, res, -1, 0, "unusable camera");
    pvs_raster_set_matrix(r, m);
    memset(visible, 0, PVS_BITSET_WORDS(s->object_count) * sizeof(pvs_word));
    memset(r->obj_done, 0, PVS_BITSET_WORDS(s->object_count) * sizeof(pvs_word));
    return PVS_OK;
}

PVS_API pvs_result pvs_raster_cull(pvs_raster *r, const pvs_scene *s, const pvs_camera *cam, const pvs_cull_params *p,
                                   pvs_word *visible, pvs_cull_stats *stats, pvs_error *err) {
    pvs__cullctx cc;
    pvs_box src;
    pvs_result res = pvs__cull_begin(r, s, cam, visible, err);
    uint32_t i;
    int k;
    if (res != PVS_OK) return res;
    memset(&cc, 0, sizeof(cc));
    pvs_raster_clear(r);
    if (p && p->occluder_triangle_count && p->occluder_positions) {
        if (p->occluder_flags & PVS_CULL_OCCLUDER_MESH)
            pvs_raster_mesh(r, p->occluder_positions, p->occluder_vertex_count, p->occluder_indices, p->occluder_triangle_count);
        else
            pvs_raster_triangles(r, p->occluder_positions, p->occluder_vertex_count, p->occluder_indices, p->occluder_triangle_count,
                                 PVS_RASTER_OCCLUDER);
        cc.st.occluder_triangles += p->occluder_triangle_count;
    }
    if (p && p->scene_occluders) {
        pvs__selctx sc;
        double len;
        sc.r = r;
        sc.s = s;
        sc.k = p->scene_occluders < r->max_occluders ? p->scene_occluders : r->max_occluders;
        sc.n = 0;
        sc.max_dist = p->occluder_distance > 0.0f ? p->occluder_distance : 100.0f;
        sc.near_d = cam->near_plane;
        for (k = 0; k < 3; ++k) { sc.eye[k] = cam->eye[k]; sc.fwd[k] = cam->forward[k]; }
        len = sqrt(sc.fwd[0] * sc.fwd[0] + sc.fwd[1] * sc.fwd[1] + sc.fwd[2] * sc.fwd[2]);
        for (k = 0; k < 3; ++k) sc.fwd[k] /= len;
        if (cam->fov_y == 0.0f) sc.near_d = -DBL_MAX; /* orthographic: the near plane test is the matrix's */
        memset(r->tri_seen, 0, PVS_BITSET_WORDS(s->triangle_count) * sizeof(pvs_word));
        for (k = 0; k < 3; ++k) src.min[k] = src.max[k] = cam->eye[k];
        pvs_kdtree_sweep(s->triangle_tree, &src, r->sweep, r->sweep_size, pvs__select_visit, &sc);
        if (!(p->occluder_flags & PVS_CULL_SEPARATE_TRIANGLES)) {
            pvs__mesh(r, s->positions, s->vertex_count, s->indices, r->occ, sc.n); /* welded: walls fuse (Durand 2000 §3.3) */
        } else if (r->tiled) {
            pvs__raster_occluders(r, s->positions, s->vertex_count, s->indices, r->occ, sc.n);
        } else {
            for (i = 0; i < sc.n; ++i) {
                const uint32_t *t = s->indices + 3 * (size_t)r->occ[i].triangle;
                pvs__raster_tri(r, s->positions + 3 * (size_t)t[0], s->positions + 3 * (size_t)t[1], s->positions + 3 * (size_t)t[2], 1);
            }
        }
        cc.st.occluder_triangles += sc.n;
    }
    if (p && p->scene_volumes) { /* explicit occluder volumes as triangles: a box's faces, an extrusion's walls */
        float dist = p->occluder_distance > 0.0f ? p->occluder_distance : 100.0f;
        int u, v, up = (int)s->up_axis;
        pvs__ground_axes(s->up_axis, &u, &v);
        for (k = 0; k < 3; ++k) src.min[k] = src.max[k] = cam->eye[k];
        for (i = 0; i < s->occluder_count; ++i) {
            const pvs_occluder_desc *o = s->occluders + i;
            float q[8][3];
            uint32_t j;
            if (pvs__box_distance2(&src, s->occluder_boxes + i) > dist * dist) continue;
            if (o->kind == PVS_OCCLUDER_BOX) {
                static const uint32_t f[12][3] = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4},
                                                 {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
                for (j = 0; j < 8; ++j)
                    for (k = 0; k < 3; ++k) q[j][k] = (j >> k) & 1u ? o->box.max[k] : o->box.min[k];
                if (p->occluder_flags & PVS_CULL_SEPARATE_TRIANGLES)
                    for (j = 0; j < 12; ++j) pvs__raster_tri(r, q[f[j][0]], q[f[j][1]], q[f[j][2]], 1);
                else
                    pvs__mesh(r, &q[0][0], 8, &f[0][0], NULL, 12);
                cc.st.occluder_triangles += 12;
            } else if (o->kind == PVS_OCCLUDER_EXTRUSION) {
                if (!(p->occluder_flags & PVS_CULL_SEPARATE_TRIANGLES)) {
                    /* the walls as meshes of up to 32 walls (two triangles each, neighbours sharing
                       their vertical edge) */
                    float wp[2 * 33][3];
                    uint32_t wi[32 * 6], c, nw;
                    for (j = 0; j < o->footprint_count; j += 32) {
                        nw = o->footprint_count - j < 32 ? o->footprint_count - j : 32;
                        for (c = 0; c <= nw; ++c) {
                            const float *a = o->footprint + 2 * ((j + c) % o->footprint_count);
                            wp[2 * c][u] = a[0]; wp[2 * c][v] = a[1]; wp[2 * c][up] = o->base;
                            wp[2 * c + 1][u] = a[0]; wp[2 * c + 1][v] = a[1]; wp[2 * c + 1][up] = o->top;
                        }
                        for (c = 0; c < nw; ++c) { /* (a0 b0 b1) (a0 b1 a1), as drawn one by one */
                            wi[6 * c] = 2 * c; wi[6 * c + 1] = 2 * c + 2; wi[6 * c + 2] = 2 * c + 3;
                            wi[6 * c + 3] = 2 * c; wi[6 * c + 4] = 2 * c + 3; wi[6 * c + 5] = 2 * c + 1;
                        }
                        pvs__mesh(r, &wp[0][0], 2 * (nw + 1), wi, NULL, 2 * nw);
                        cc.st.occluder_triangles += 2 * nw;
                    }
                } else {
                    for (j = 0; j < o->footprint_count; ++j) {
                        const float *a = o->footprint + 2 * j, *b = o->footprint + 2 * ((j + 1) % o->footprint_count);
                        q[0][u] = a[0]; q[0][v] = a[1]; q[0][up] = o->base;
                        q[1][u] = b[0]; q[1][v] = b[1]; q[1][up] = o->base;
                        q[2][u] = b[0]; q[2][v] = b[1]; q[2][up] = o->top;
                        q[3][u] = a[0]; q[3][v] = a[1]; q[3][up] = o->top;
                        pvs__raster_tri(r, q[0], q[1], q[2], 1);
                        pvs__raster_tri(r, q[0], q[2], q[3], 1);
                        cc.st.occluder_triangles += 2;
                    }
                }
            }
        }
    }
    pvs_raster_build_pyramid(r);
    cc.r = r;
    cc.s = s;
    cc.visible = visible;
    cc.candidates = p ? p->candidates : NULL;
    for (k = 0; k < 3; ++k) src.min[k] = src.max[k] = cam->eye[k];
    /* Bittner 2002 §3.2: front to back, so a hidden node culls its subtree */
    pvs_kdtree_sweep(s->object_tree, &src, r->sweep, r->sweep_size, pvs__cull_visit, &cc);
    if (stats) *stats = cc.st;
    pvs__ok(err);
    return PVS_OK;
}

/* ---- cull map (Wonka & Schmalstieg 1999) ---- */

/* The occluder shadow of the facade a-b (ground points) with top height `top` from the eye (ou, ov,
   eh) (§3.1): the quadrilateral a, b, b + t (b - o), a + t (a - o) in the ground plane, its height the
   plane through the eye and the top edge. The far edge lies outside the map (§4.2). Rasterized with
   inner coverage and the lowest height over each cell: §4.4's sampling correction (see the top). */
PVS__STATIC void pvs__cm_shadow(pvs_raster *r, double ou, double ov, double eh, const float *a, const float *b, double top, int simd) {
    double su = ((double)r->region[2] - r->region[0]) / r->cm_w, sv = ((double)r->region[3] - r->region[1]) / r->cm_h;
    double da[2], db[2], la, lb, reach, sa, sb, x[4], y[4], z[4];
    da[0] = (double)a[0] - ou; da[1] = (double)a[1] - ov;
    db[0] = (double)b[0] - ou; db[1] = (double)b[1] - ov;
    la = sqrt(da[0] * da[0] + da[1] * da[1]);
    lb = sqrt(db[0] * db[0] + db[1] * db[1]);
    if (!(la > 0.0) || !(lb > 0.0)) return;
    reach = 2.0 * ((double)r->region[2] - r->region[0] + (double)r->region[3] - r->region[1] + pvs__dabs(ou - r->region[0]) +
                   pvs__dabs(ov - r->region[1]));
    sa = 1.0 + reach / la;
    sb = 1.0 + reach / lb;
    x[0] = a[0]; y[0] = a[1]; z[0] = top;
    x[1] = b[0]; y[1] = b[1]; z[1] = top;
    x[2] = ou + db[0] * sb; y[2] = ov + db[1] * sb; z[2] = eh + (top - eh) * sb;
    x[3] = ou + da[0] * sa; y[3] = ov + da[1] * sa; z[3] = eh + (top - eh) * sa;
    {
        int k;
        for (k = 0; k < 4; ++k) {
            x[k] = (x[k] - r->region[0]) / su;
            y[k] = (y[k] - r->region[1]) / sv;
        }
    }
    pvs__raster_poly(r->cm, r->cm_w, r->cm_h, r->cm_tile_min, x, y, z, 4, 1, simd, 0.0, 0.0);
}

/* Height over ground point (x, y) of the plane through the eye (ou, ov, eh) and the horizontal edge
   a-b at height `top`; 0 when the plane is vertical (the eye on the edge's line). */
PVS__STATIC int pvs__cm_plane(double ou, double ov, double eh, const double *a, const double *b, double top, double pl[3]) {
    double a0 = a[0] - ou, a1 = a[1] - ov, b0 = b[0] - ou, b1 = b[1] - ov, dh = top - eh;
    /* n = (a - o) x (b - o) with both at height dh above the eye */
    double nx = a1 * dh - dh * b1, ny = dh * b0 - a0 * dh, nz = a0 * b1 - a1 * b0;
    if (!(pvs__dabs(nz) > 1e-12 * (pvs__dabs(a0) + pvs__dabs(a1)) * (pvs__dabs(b0) + pvs__dabs(b1)))) return 0;
    pl[0] = -nx / nz; /* h(x, y) = eh + pl[0] (x - ou) + pl[1] (y - ov) */
    pl[1] = -ny / nz;
    pl[2] = eh;
    return 1;
}
PVS__STATIC double pvs__cm_height(const double pl[3], double ou, double ov, double x, double y) {
    return pl[2] + pl[0] * (x - ou) + pl[1] * (y - ov);
}

/* The seam at a vertex v shared by two casting facades p-v and v-q. Each facade's shadow shrinks by
   the sampling correction, so cells straddling the shadow ray through v would be covered by neither:
   Wonka 1999 §5 extends the correction to connected occluders. The wedge between the rays through a'
   on p-v and b' on v-q (about two cells from v) beyond the chain a'-v-b' lies in the union of both
   shadows; its true height is plane A on A's side of the ray through v and plane B on B's side. Both
   planes contain that ray, so their difference changes sign across it: when A >= B on A's side (a
   ridge), plane A is at most the true height on both sides; otherwise min(A, B) is concave and its
   least value at the wedge's corners bounds it from below. Rasterized like a shadow. */
PVS__STATIC void pvs__cm_seam(pvs_raster *r, double ou, double ov, double eh, const float *pf, const float *vf, const float *qf,
                              double top, int simd) {
    double su = ((double)r->region[2] - r->region[0]) / r->cm_w, sv = ((double)r->region[3] - r->region[1]) / r->cm_h;
    double delta = 2.0 * sqrt(su * su + sv * sv), reach, x[5], y[5], z[5], pa[3], pb[3], pt[2], vt[2], qt[2], lp, lq, cross0 = 0.0;
    int k;
    pt[0] = pf[0]; pt[1] = pf[1]; vt[0] = vf[0]; vt[1] = vf[1]; qt[0] = qf[0]; qt[1] = qf[1];
    lp = sqrt((pt[0] - vt[0]) * (pt[0] - vt[0]) + (pt[1] - vt[1]) * (pt[1] - vt[1]));
    lq = sqrt((qt[0] - vt[0]) * (qt[0] - vt[0]) + (qt[1] - vt[1]) * (qt[1] - vt[1]));
    if (!(lp > 0.0) || !(lq > 0.0)) return;
    if (!pvs__cm_plane(ou, ov, eh, pt, vt, top, pa) || !pvs__cm_plane(ou, ov, eh, vt, qt, top, pb)) return;
    reach = 2.0 * ((double)r->region[2] - r->region[0] + (double)r->region[3] - r->region[1] + pvs__dabs(ou - r->region[0]) +
                   pvs__dabs(ov - r->region[1]));
    x[0] = vt[0] + (pt[0] - vt[0]) * pvs__dmin(1.0, delta / lp);
    y[0] = vt[1] + (pt[1] - vt[1]) * pvs__dmin(1.0, delta / lp);
    x[1] = vt[0]; y[1] = vt[1];
    x[2] = vt[0] + (qt[0] - vt[0]) * pvs__dmin(1.0, delta / lq);
    y[2] = vt[1] + (qt[1] - vt[1]) * pvs__dmin(1.0, delta / lq);
    for (k = 0; k < 2; ++k) { /* the far ends of the rays through b' and a' */
        int from = k == 0 ? 2 : 0;
        double dx = x[from] - ou, dy = y[from] - ov, l = sqrt(dx * dx + dy * dy), sc;
        if (!(l > 0.0)) return;
        sc = 1.0 + reach / l;
        x[3 + k] = ou + dx * sc;
        y[3 + k] = ov + dy * sc;
    }
    for (k = 0; k < 5; ++k) { /* convex, one orientation, or nothing */
        int j = (k + 1) % 5, l = (k + 2) % 5;
        double c = (x[j] - x[k]) * (y[l] - y[j]) - (y[j] - y[k]) * (x[l] - x[j]);
        if (c == 0.0) continue;
        if (cross0 == 0.0) cross0 = c;
        else if ((c > 0.0) != (cross0 > 0.0)) return;
    }
    if (pvs__cm_height(pa, ou, ov, x[4], y[4]) >= pvs__cm_height(pb, ou, ov, x[4], y[4])) {
        for (k = 0; k < 5; ++k) z[k] = pvs__cm_height(pa, ou, ov, x[k], y[k]);
    } else {
        double c = DBL_MAX;
        for (k = 0; k < 5; ++k) c = pvs__dmin(c, pvs__dmin(pvs__cm_height(pa, ou, ov, x[k], y[k]), pvs__cm_height(pb, ou, ov, x[k], y[k])));
        for (k = 0; k < 5; ++k) z[k] = c;
    }
    for (k = 0; k < 5; ++k) {
        x[k] = (x[k] - r->region[0]) / su;
        y[k] = (y[k] - r->region[1]) / sv;
    }
    pvs__raster_poly(r->cm, r->cm_w, r->cm_h, r->cm_tile_min, x, y, z, 5, 1, simd, 0.0, 0.0);
}

/* 1 if facade a-b casts a shadow: front-facing for closed chains (§4.2), not nearer than min_dist. */
PVS__STATIC int pvs__cm_casts(const double eye[3], const float *a, const float *b, int closed, double area2, double min_dist) {
    if (closed) {
        /* outward normal: right of a->b for a counter-clockwise footprint */
        double nx = (double)b[1] - a[1], ny = -((double)b[0] - a[0]);
        if (area2 < 0) { nx = -nx; ny = -ny; }
        if (!((eye[0] - a[0]) * nx + (eye[1] - a[1]) * ny > 0.0)) return 0; /* back-facing */
    }
    if (min_dist > 0.0) { /* a facade nearer than the near plane is clipped away by the renderer */
        double ex = eye[0] - a[0], ey = eye[1] - a[1], sx = (double)b[0] - a[0], sy = (double)b[1] - a[1];
        double ss = sx * sx + sy * sy, t = ss > 0.0 ? (ex * sx + ey * sy) / ss : 0.0, qx, qy;
        t = t < 0.0 ? 0.0 : t > 1.0 ? 1.0 : t;
        qx = ex - t * sx;
        qy = ey - t * sy;
        if (qx * qx + qy * qy < min_dist * min_dist) return 0;
    }
    return 1;
}

/* One chain: every casting facade's shadow, and the seams between consecutive casting facades. */
PVS__STATIC void pvs__cm_chain(pvs_raster *r, const double eye[3], const float *pts, uint32_t n, int closed, float base, float top,
                                int simd, double min_dist) {
    double area2 = 0.0, limit = pvs__dmin(eye[2], r->ground);
    uint32_t i, segs;
    int first_casts = 0, prev_casts = 0;
    if (!pts || n < 2 || !pvs__finite(base) || !pvs__finite(top) || !(base < top)) return;
    if ((double)base > limit) return; /* the facade does not reach down to everything it would hide */
    for (i = 0; i < 2 * n; ++i)
        if (!pvs__finite(pts[i])) return;
    if (closed) {
        for (i = 0; i < n; ++i) {
            const float *a = pts + 2 * i, *b = pts + 2 * ((i + 1) % n);
            area2 += (double)a[0] * b[1] - (double)b[0] * a[1];
        }
        if (area2 == 0.0 || n < 3) closed = 0;
    }
    segs = closed ? n : n - 1;
    for (i = 0; i < segs; ++i) {
        const float *a = pts + 2 * i, *b = pts + 2 * ((i + 1) % n);
        int casts = pvs__cm_casts(eye, a, b, closed, area2, min_dist);
        if (casts) pvs__cm_shadow(r, eye[0], eye[1], eye[2], a, b, top, simd);
        if (casts && prev_casts && i > 0) pvs__cm_seam(r, eye[0], eye[1], eye[2], pts + 2 * (i - 1), a, b, top, simd);
        if (i == 0) first_casts = casts;
        prev_casts = casts;
    }
    if (closed && prev_casts && first_casts) /* the seam where the loop closes */
        pvs__cm_seam(r, eye[0], eye[1], eye[2], pts + 2 * (n - 1), pts, pts + 2, top, simd);
}

/* The cull map build; facades nearer than min_dist to the eye (in the ground plane) are left out. */
PVS__STATIC pvs_result pvs__cull_map_build(pvs_raster *r, const float eye[3], const pvs_facade_chain *chains, uint32_t chain_count,
                                           uint32_t flags, double min_dist) {
    double e[3];
    size_t i, cells;
    uint32_t c;
    int u, v, simd;
    const pvs_scene *s;
    if (!r || !eye || !r->cm || (chain_count && !chains)) return PVS_ERROR_INVALID_ARGUMENT;
    if (!pvs__finite(eye[0]) || !pvs__finite(eye[1]) || !pvs__finite(eye[2])) return PVS_ERROR_NOT_FINITE;
    s = r->scene;
    pvs__ground_axes(s->up_axis, &u, &v);
    e[0] = eye[u];
    e[1] = eye[v];
    e[2] = eye[s->up_axis];
    simd = !(r->flags & PVS_RASTER_SCALAR);
    cells = (size_t)r->cm_w * r->cm_h;
    for (i = 0; i < cells; ++i) r->cm[i] = PVS_DEPTH_EMPTY;
    for (i = 0; i < r->cm_tiles; ++i) r->cm_tile_min[i] = PVS_DEPTH_EMPTY;
    for (c = 0; c < chain_count; ++c)
        pvs__cm_chain(r, e, chains[c].points, chains[c].point_count, chains[c].closed != 0, chains[c].base, chains[c].top, simd, min_dist);
    if (flags & PVS_CULL_MAP_SCENE_OCCLUDERS) {
        for (c = 0; c < s->occluder_count; ++c) {
            const pvs_occluder_desc *o = s->occluders + c;
            if (o->kind == PVS_OCCLUDER_EXTRUSION) {
                pvs__cm_chain(r, e, o->footprint, o->footprint_count, 1, o->base, o->top, simd, min_dist);
            } else if (o->kind == PVS_OCCLUDER_BOX) {
                float q[8];
                q[0] = o->box.min[u]; q[1] = o->box.min[v];
                q[2] = o->box.max[u]; q[3] = o->box.min[v];
                q[4] = o->box.max[u]; q[5] = o->box.max[v];
                q[6] = o->box.min[u]; q[7] = o->box.max[v];
                pvs__cm_chain(r, e, q, 4, 1, o->box.min[s->up_axis], o->box.max[s->up_axis], simd, min_dist);
            }
        }
    }
    return PVS_OK;
}

PVS_API pvs_result pvs_cull_map_build(pvs_raster *r, const float eye[3], const pvs_facade_chain *chains, uint32_t chain_count,
                                      uint32_t flags) {
    return pvs__cull_map_build(r, eye, chains, chain_count, flags, 0.0);
}

PVS_API const float *pvs_cull_map(const pvs_raster *r, uint32_t *w, uint32_t *h, float region[4]) {
    int k;
    if (w) *w = r->cm_w;
    if (h) *h = r->cm_h;
    if (region)
        for (k = 0; k < 4; ++k) region[k] = r->region[k];
    return r->cm;
}

PVS_API int pvs_cull_map_test_box(const pvs_raster *r, const pvs_box *b) {
    int32_t i0, j0, i1, j1, i, j;
    float top;
    if (!r->cm) return 1;
    if (!pvs__cm_range(r, b, (int)r->scene->up_axis, &i0, &j0, &i1, &j1)) return 1;
    top = b->max[r->scene->up_axis];
    for (j = j0; j <= j1; ++j)
        for (i = i0; i <= i1; ++i)
            if (!(r->cm[(size_t)j * r->cm_w + (size_t)i] > top)) return 1;
    return 0;
}

PVS_API pvs_result pvs_raster_cull_map(pvs_raster *r, const pvs_scene *s, const pvs_camera *cam, const pvs_cull_params *p,
                                       pvs_word *visible, pvs_cull_stats *stats, pvs_error *err) {
    pvs_cull_stats st;
    pvs_result res;
    size_t c, cells;
    int up;
    if (r && s && r->scene != s) return pvs__fail(err, PVS_ERROR_INVALID_ARGUMENT, -1, 0, "the scene is not the context's scene");
    if (r && !r->cm) return pvs__fail(err, PVS_ERROR_INVALID_ARGUMENT, -1, 0, "the context has no cull map");
    res = pvs__cull_begin(r, s, cam, visible, err);
    if (res != PVS_OK) return res;
    if (p && p->facade_count && !p->facades) return pvs__fail(err, PVS_ERROR_INVALID_ARGUMENT, -1, 0, "facades must not be NULL");
    memset(&st, 0, sizeof(st));
    if (cam->fov_y > 0.0f) {
        /* sight lines start at the near plane: facades nearer than it, at the frustum's widest angle,
           are clipped away by the renderer and must not hide anything */
        double ty = tan(0.5 * (double)cam->fov_y), tx = ty * (double)r->width / (double)r->height;
        pvs__cull_map_build(r, cam->eye, p ? p->facades : NULL, p ? p->facade_count : 0, p ? p->cull_map_flags : 0,
                            (double)cam->near_plane * sqrt(1.0 + tx * tx + ty * ty) * (1.0 + 1e-6));
    } else { /* shadows are cast from a point: an orthographic view gets the frustum test only */
        for (c = 0; c < (size_t)r->cm_w * r->cm_h; ++c) r->cm[c] = PVS_DEPTH_EMPTY;
    }
    pvs_raster_clear(r); /* the frustum test below sees an empty depth map */
    up = (int)s->up_axis;
    cells = (size_t)r->cm_w * r->cm_h;
    /* §4.3: the cell's bounding height first, then each object's */
    for (c = 0; c < cells; ++c) {
        float h = r->cm[c];
        uint32_t k;
        ++st.nodes_visited;
        if (r->cm_bound[c] < h) continue; /* every object here is under the shadows */
        for (k = r->cm_start[c]; k < r->cm_start[c + 1]; ++k) {
            uint32_t o = r->cm_items[k];
            int32_t rect[4];
            float d;
            if (pvs_bitset_test(r->obj_done, o)) continue;
            if (s->object_boxes[o].max[up] < h) continue; /* hidden in this cell; may show in another */
            pvs_bitset_set(r->obj_done, o);
            if (s->object_flags[o] & PVS_OBJECT_OCCLUDER_ONLY) continue;
            if (p && p->candidates && !pvs_bitset_test(p->candidates, o)) continue;
            ++st.boxes_tested;
            if (pvs__raster_box(r, s->object_boxes + o, rect, &d)) { /* in the frustum */
                pvs_bitset_set(visible, o);
                ++st.visible;
            }
        }
    }
    if (stats) *stats = st;
    pvs__ok(err);
    return PVS_OK;
}


// >>otree
/* ---------------------------------------------------------------------------------------------- */
/* otree: occlusion trees over oriented 2D line space (Bittner 2002, ch. 3, 6, 7)                 */
/* ---------------------------------------------------------------------------------------------- */
/* One BSP kernel (§3.3, §6.8): a tree whose interior nodes are planes through the origin of R^3,
   each the image p* of a primal point p (§6.4: the oriented line l* = (u,1) x (v,1) has
   l*.(p,1) = orient(u, v, p), > 0 when p lies left of the line), and whose leaves are out (rays not
   blocked) or in (blocked; the payload names the nearest occluder in 2D, or the set of occluders
   that may be seen over in 2.5D). Sets of lines are convex polygons of unit vectors (vertices =
   extremal lines); every polygon edge remembers the primal point whose plane carries it and whether
   that plane is already on the path (edge marking, §4.10.1), so an out-leaf becomes the elementary
   tree e-OT of only the unmarked edges (§3.3.3).

   Conservative rounding. Regions of the tree are defined by exact planes through stored points, so
   an in-leaf never claims lines outside the blocker that created it; insertion classifies with a
   tolerance that can only drop blocked slivers; read-only tests split with slack so both sides see
   a little more than their share; ambiguous depth orders count as "in front" (visible). All
   geometry is in double, relative to the cell's centre.

   Users: pvs_visibility_2d (exact 2D from-region, ch. 6), pvs_visibility_25d (conservative 2.5D,
   c-LSS, ch. 7) and the OTREE bake method. The from-point shadow-volume tree (ch. 4, pvs_otree_cull)
   at the end of this section has its own 3D kernel (planes through the eye). */

#define PVS__OT_MAXV 16
#define PVS__OT_OUT 1u
#define PVS__OT_IN 2u
#define PVS__OT_NONE 0xffffffffu

typedef struct pvs__otpoly {
    int n;
    int xsplit;                     /* already split at a crossing point X (§6.5.1 case 3) */
    double v[PVS__OT_MAXV][3];      /* extremal lines, unit length */
    double e[PVS__OT_MAXV][2];      /* edge i (v[i] -> v[i+1]) lies in the plane of point e[i] */
    unsigned char mark[PVS__OT_MAXV];
} pvs__otpoly;

typedef struct pvs__otnode {
    double p[2];        /* interior: the plane is sign * (p.x, p.y, 1) */
    double n[3];        /* ... as a unit normal */
    int32_t sign;
    uint32_t kind;      /* 0 interior, PVS__OT_OUT, PVS__OT_IN */
    uint32_t child[2];  /* [0] negative side, [1] positive side */
    uint32_t first, count; /* in-leaf payload: occluders seq[first .. first + count) */
    uint32_t parent;    /* PVS__OT_NONE at the root */
    double mvd;         /* 2D: maximum visibility distance of the subtree (§6.5.5); DBL_MAX above out-leaves */
    double mr, ms;      /* 2.5D: the subtree's hidden-height bound (pvs__ot25_bound); mr DBL_MAX: none */
} pvs__otnode;

typedef struct pvs__otree {
    const pvs_allocator *a;
    pvs__otnode *nodes;
    size_t node_count, node_cap;
    uint32_t *seq;
    size_t seq_count, seq_cap;
    pvs__otpoly *stack;             /* work stack of polygons */
    uint32_t *stack_node;
    uint32_t *stack_pend;           /* read-only tests: a clip still owed, (node << 1) | side, or PVS__OT_NONE */
    size_t stack_count, stack_cap;
    int oom;
    const double *seg;              /* occluder segments, 4 doubles each (local coordinates) */
    const double *top;              /* 2.5D: occluder top heights; NULL in 2D */
    const double *reach;            /* 2D: per occluder, the largest distance between it and a cell point */
    double sa[2], sb[2];            /* the source edge (cell edge or top edge) */
    double eye;                     /* 2.5D: height of the source edge */
    const double *corners;          /* 2.5D: the cell's 4 ground corners (every possible eye position) */
    double *jd;                     /* 2.5D: per occluder, its line and umbra data in this tree (pvs__ot25_prepare) */
    double len_eps;                 /* distances below this are ties */
} pvs__otree;

PVS__STATIC int pvs__ot_grow(const pvs_allocator *a, void **p, size_t *cap, size_t need, size_t elem) {
    size_t ncap, bytes;
    void *q;
    if (need <= *cap) return 1;
    ncap = *cap ? *cap * 2 : 64;
    while (ncap < need) ncap *= 2;
    if (!pvs__mul(ncap, elem, &bytes)) return 0;
    q = pvs__alloc(a, bytes, 16);
    if (!q) return 0;
    if (*p) {
        memcpy(q, *p, *cap * elem);
        pvs__free(a, *p, *cap * elem, 16);
    }
    *p = q;
    *cap = ncap;
    return 1;
}

PVS__STATIC void pvs__ot_free(pvs__otree *t) {
    pvs__free(t->a, t->nodes, t->node_cap * sizeof(pvs__otnode), 16);
    pvs__free(t->a, t->seq, t->seq_cap * sizeof(uint32_t), 16);
    pvs__free(t->a, t->stack, t->stack_cap * sizeof(pvs__otpoly), 16);
    pvs__free(t->a, t->stack_node, t->stack_cap * sizeof(uint32_t), 16);
    pvs__free(t->a, t->stack_pend, t->stack_cap * sizeof(uint32_t), 16);
    t->nodes = NULL; t->seq = NULL; t->stack = NULL; t->stack_node = NULL; t->stack_pend = NULL;
    t->node_cap = t->seq_cap = t->stack_cap = 0;
}

/* Resets to the whole line set: a single out-leaf (§3.3.2). */
PVS__STATIC int pvs__ot_reset(pvs__otree *t) {
    t->node_count = t->seq_count = t->stack_count = 0;
    if (!pvs__ot_grow(t->a, (void **)&t->nodes, &t->node_cap, 1, sizeof(pvs__otnode))) { t->oom = 1; return 0; }
    memset(t->nodes, 0, sizeof(pvs__otnode));
    t->nodes[0].kind = PVS__OT_OUT;
    t->nodes[0].mvd = DBL_MAX;
    t->nodes[0].mr = DBL_MAX;
    t->nodes[0].parent = PVS__OT_NONE;
    t->node_count = 1;
    return 1;
}

PVS__STATIC uint32_t pvs__ot_new_node(pvs__otree *t) {
    if (!pvs__ot_grow(t->a, (void **)&t->nodes, &t->node_cap, t->node_count + 1, sizeof(pvs__otnode))) {
        t->oom = 1;
        return PVS__OT_NONE;
    }
    memset(t->nodes + t->node_count, 0, sizeof(pvs__otnode));
    return (uint32_t)t->node_count++;
}

/* Copies the live part of a polygon. */
PVS__STATIC void pvs__ot_copy(pvs__otpoly *d, const pvs__otpoly *s) {
    int n = s->n;
    d->n = n;
    d->xsplit = s->xsplit;
    memcpy(d->v, s->v, (size_t)n * sizeof(s->v[0]));
    memcpy(d->e, s->e, (size_t)n * sizeof(s->e[0]));
    memcpy(d->mark, s->mark, (size_t)n);
}

/* Makes room for `need` work items (the three stack arrays grow together). */
PVS__STATIC int pvs__ot_reserve(pvs__otree *t, size_t need) {
    size_t c1 = t->stack_cap, c2 = t->stack_cap, c3 = t->stack_cap;
    if (need <= t->stack_cap) return 1;
    if (!pvs__ot_grow(t->a, (void **)&t->stack, &c1, need, sizeof(pvs__otpoly)) ||
        !pvs__ot_grow(t->a, (void **)&t->stack_node, &c2, need, sizeof(uint32_t)) ||
        !pvs__ot_grow(t->a, (void **)&t->stack_pend, &c3, need, sizeof(uint32_t))) {
        t->oom = 1;
        return 0;
    }
    t->stack_cap = c1 < c2 ? (c1 < c3 ? c1 : c3) : (c2 < c3 ? c2 : c3);
    return 1;
}

PVS__STATIC int pvs__ot_push(pvs__otree *t, uint32_t node, const pvs__otpoly *poly) {
    if (!pvs__ot_reserve(t, t->stack_count + 1)) return 0;
    pvs__ot_copy(t->stack + t->stack_count, poly);
    t->stack_pend[t->stack_count] = PVS__OT_NONE;
    t->stack_node[t->stack_count++] = node;
    return 1;
}
/* Pops the top of the work stack into *q; returns its node. */
PVS__STATIC uint32_t pvs__ot_pop(pvs__otree *t, pvs__otpoly *q) {
    --t->stack_count;
    pvs__ot_copy(q, t->stack + t->stack_count);
    return t->stack_node[t->stack_count];
}

/* ---- line-space kernel (§6.4, §6.8) ---- */

/* The oriented line u -> v, (u,1) x (v,1), normalised; 0 when u == v. */
PVS__STATIC double pvs__ot_line(const double u[2], const double v[2], double l[3]) {
    double len;
    l[0] = u[1] - v[1];
    l[1] = v[0] - u[0];
    l[2] = u[0] * v[1] - u[1] * v[0];
    len = sqrt(l[0] * l[0] + l[1] * l[1] + l[2] * l[2]);
    if (len > 0.0) { l[0] /= len; l[1] /= len; l[2] /= len; }
    return len;
}
/* Signed "side" of primal point p for line l, scaled so that unit lines give comparable values. */
PVS__STATIC double pvs__ot_side(const double l[3], const double p[2]) {
    return (l[0] * p[0] + l[1] * p[1] + l[2]) / sqrt(p[0] * p[0] + p[1] * p[1] + 1.0);
}
PVS__STATIC void pvs__ot_normalize(double v[3]) {
    double len = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    if (len > 0.0) { double f = 1.0 / len; v[0] *= f; v[1] *= f; v[2] *= f; }
}

#define PVS__OT_EPS 1e-12

/* The unit normal of the plane sign * p* = sign * (p.x, p.y, 1): n . l = sign * side(l, p). */
PVS__STATIC void pvs__ot_normal(const double p[2], double sign, double n[3]) {
    double f = sign / sqrt(p[0] * p[0] + p[1] * p[1] + 1.0);
    n[0] = p[0] * f;
    n[1] = p[1] * f;
    n[2] = f;
}

/* Keeps the part of `in` where n . l >= -slack (slack 0: the exact half), n the unit normal of the
   plane of p. New edges lie in the plane of p and get mark `mark`. Returns the vertex count of the
   result (0 = empty, -1 = too many vertices). */
PVS__STATIC int pvs__ot_clip_n(const pvs__otpoly *in, const double nn[3], const double p[2], double slack, int mark, pvs__otpoly *out) {
    double d[PVS__OT_MAXV];
    int i, n = in->n, m = 0, any_in = 0;
    for (i = 0; i < n; ++i) {
        d[i] = nn[0] * in->v[i][0] + nn[1] * in->v[i][1] + nn[2] * in->v[i][2] + slack;
        if (d[i] > PVS__OT_EPS) any_in = 1;
    }
    out->xsplit = in->xsplit;
    if (!any_in) { out->n = 0; return 0; }
    for (i = 0; i < n; ++i) {
        int j = i + 1 == n ? 0 : i + 1;
        int in_i = d[i] >= 0.0, in_j = d[j] >= 0.0;
        if (in_i) {
            if (m >= PVS__OT_MAXV) { out->n = 0; return -1; }
            memcpy(out->v[m], in->v[i], sizeof(out->v[m]));
            memcpy(out->e[m], in->e[i], sizeof(out->e[m]));
            out->mark[m] = in->mark[i];
            ++m;
        }
        if (in_i != in_j) {
            double tt = d[i] / (d[i] - d[j]);
            int k;
            if (m >= PVS__OT_MAXV) { out->n = 0; return -1; }
            for (k = 0; k < 3; ++k) out->v[m][k] = in->v[i][k] + tt * (in->v[j][k] - in->v[i][k]);
            pvs__ot_normalize(out->v[m]);
            if (in_i) { /* leaving: the new edge runs along p's plane */
                out->e[m][0] = p[0]; out->e[m][1] = p[1];
                out->mark[m] = (unsigned char)mark;
            } else {    /* entering: the rest of edge i */
                memcpy(out->e[m], in->e[i], sizeof(out->e[m]));
                out->mark[m] = in->mark[i];
            }
            ++m;
        }
    }
    out->n = m;
    return m;
}
/* Both halves at once: *pos = pvs__ot_clip_n(in, n, p, slack) and *neg = the same with -n. Returns
   the two vertex counts in r[0] (pos) and r[1] (neg), as pvs__ot_clip_n would. */
PVS__STATIC void pvs__ot_split2(const pvs__otpoly *in, const double nn[3], const double p[2], double slack, int mark, pvs__otpoly *pos,
                                pvs__otpoly *neg, int r[2]) {
    double d[PVS__OT_MAXV];
    int i, n = in->n, m[2] = {0, 0}, any[2] = {0, 0}, side;
    for (i = 0; i < n; ++i) {
        d[i] = nn[0] * in->v[i][0] + nn[1] * in->v[i][1] + nn[2] * in->v[i][2];
        if (d[i] + slack > PVS__OT_EPS) any[0] = 1;
        if (-d[i] + slack > PVS__OT_EPS) any[1] = 1;
    }
    pos->xsplit = neg->xsplit = in->xsplit;
    r[0] = r[1] = 0;
    for (side = 0; side < 2; ++side) {
        pvs__otpoly *out = side ? neg : pos;
        double sg = side ? -1.0 : 1.0;
        if (!any[side]) { out->n = 0; continue; }
        for (i = 0; i < n; ++i) {
            int j = i + 1 == n ? 0 : i + 1;
            double di = sg * d[i] + slack, dj = sg * d[j] + slack;
            int in_i = di >= 0.0, in_j = dj >= 0.0;
            if (in_i) {
                if (m[side] >= PVS__OT_MAXV) { m[side] = -1; break; }
                memcpy(out->v[m[side]], in->v[i], sizeof(out->v[0]));
                out->e[m[side]][0] = in->e[i][0]; out->e[m[side]][1] = in->e[i][1];
                out->mark[m[side]] = in->mark[i];
                ++m[side];
            }
            if (in_i != in_j) {
                double tt = di / (di - dj), *v;
                int k;
                if (m[side] >= PVS__OT_MAXV) { m[side] = -1; break; }
                v = out->v[m[side]];
                for (k = 0; k < 3; ++k) v[k] = in->v[i][k] + tt * (in->v[j][k] - in->v[i][k]);
                pvs__ot_normalize(v);
                if (in_i) { /* leaving: the new edge runs along p's plane */
                    out->e[m[side]][0] = p[0]; out->e[m[side]][1] = p[1];
                    out->mark[m[side]] = (unsigned char)mark;
                } else {    /* entering: the rest of edge i */
                    out->e[m[side]][0] = in->e[i][0]; out->e[m[side]][1] = in->e[i][1];
                    out->mark[m[side]] = in->mark[i];
                }
                ++m[side];
            }
        }
        if (m[side] < 0) { out->n = 0; r[side] = -1; }
        else { out->n = m[side]; r[side] = m[side]; }
    }
}

/* pvs__ot_clip_n for the plane sign * p*. */
PVS__STATIC int pvs__ot_clip(const pvs__otpoly *in, const double p[2], double sign, double slack, int mark, pvs__otpoly *out) {
    double n[3];
    pvs__ot_normal(p, sign, n);
    return pvs__ot_clip_n(in, n, p, slack, mark, out);
}

/* Min and max of side(p) over the polygon's vertices. */
PVS__STATIC void pvs__ot_range(const pvs__otpoly *q, const double p[2], double *lo, double *hi) {
    int i;
    *lo = DBL_MAX; *hi = -DBL_MAX;
    for (i = 0; i < q->n; ++i) {
        double s = pvs__ot_side(q->v[i], p);
        if (s < *lo) *lo = s;
        if (s > *hi) *hi = s;
    }
}

/* 2.5D: 1 when the subtree of nd hides every point no nearer than `near` to the cell and no higher
   than h (the hidden-height bound, pvs__ot25_bound); near < 0: no bound (2D). */
PVS__STATIC int pvs__ot25_hidden_below(const pvs__otree *t, const pvs__otnode *nd, double near, double h) {
    return near >= 0.0 && nd->mr < DBL_MAX && near > nd->mr && h < t->eye + nd->ms * near - 1e-9 * (fabs(t->eye) + nd->ms * near + 1.0);
}

/* Insertion at an inner node (§3.3.3), on the top of the work stack in place: the polygon's edges
   lying on the node's line are marked (§4.10.1), then it goes to the child it lies in, or is split
   between both; a child whose subtree hides the occluder (2.5D bound, near >= 0) gets nothing. */
PVS__STATIC void pvs__ot_insert_inner(pvs__otree *t, size_t top, double near, double h) {
    pvs__otpoly *q = t->stack + top, a, b;
    const pvs__otnode *nd = t->nodes + t->stack_node[top];
    double lo = DBL_MAX, hi = -DBL_MAX;
    uint32_t c0 = nd->child[0], c1 = nd->child[1];
    int i, na, nb;
    for (i = 0; i < q->n; ++i) {
        double d = nd->n[0] * q->v[i][0] + nd->n[1] * q->v[i][1] + nd->n[2] * q->v[i][2];
        if (d < lo) lo = d;
        if (d > hi) hi = d;
        if (q->e[i][0] == nd->p[0] && q->e[i][1] == nd->p[1]) q->mark[i] = 1;
    }
    if (lo >= -1e-12) { t->stack_node[top] = c1; return; }
    if (hi <= 1e-12) { t->stack_node[top] = c0; return; }
    {
        int r[2], h0 = pvs__ot25_hidden_below(t, t->nodes + c0, near, h), h1 = pvs__ot25_hidden_below(t, t->nodes + c1, near, h);
        if (h0 && h1) { t->stack_count = top; return; }
        if (h0 || h1) { /* only one side matters */
            double nf[3];
            for (i = 0; i < 3; ++i) nf[i] = h0 ? nd->n[i] : -nd->n[i];
            na = pvs__ot_clip_n(q, nf, nd->p, 0.0, 1, &a);
            t->stack_count = top;
            if (na >= 3) pvs__ot_push(t, h0 ? c1 : c0, &a);
            return;
        }
        pvs__ot_split2(q, nd->n, nd->p, 0.0, 1, &a, &b, r);
        na = r[0]; nb = r[1];
    }
    t->stack_count = top;
    if (na >= 3) pvs__ot_push(t, c1, &a);
    if (nb >= 3) pvs__ot_push(t, c0, &b);
}

/* A read-only test at an inner node (§3.3.4), on the top of the work stack in place: the polygon,
   or its parts, go on to the children. A polygon whose vertices sit on the plane within 1e-12 (an
   edge on the plane) goes to one side; otherwise both sides get their part widened by the same
   1e-12. Returns 1 when the query is visible for sure (2.5D: a straddled child is an out-leaf) or a
   push failed (out of memory): the caller then counts it as visible. */
PVS__STATIC int pvs__ot_test_inner(pvs__otree *t, size_t top, double near, double h) {
    pvs__otpoly *q;
    const pvs__otnode *nd;
    double lo = DBL_MAX, hi = -DBL_MAX, nf[3];
    uint32_t c0, c1, node = t->stack_node[top];
    int i, r, first;
    if (!pvs__ot_reserve(t, top + 2)) return 1;
    q = t->stack + top;
    nd = t->nodes + node;
    c0 = nd->child[0];
    c1 = nd->child[1];
    for (i = 0; i < q->n; ++i) {
        double d = nd->n[0] * q->v[i][0] + nd->n[1] * q->v[i][1] + nd->n[2] * q->v[i][2];
        if (d < lo) lo = d;
        if (d > hi) hi = d;
    }
    if (lo >= -1e-12) { t->stack_node[top] = c1; return 0; }
    if (hi <= 1e-12) { t->stack_node[top] = c0; return 0; }
    /* 2.5D (no sliver rule): both parts hold a vertex strictly off the plane, so an out-leaf child
       answers at once */
    if (near >= 0.0 && (t->nodes[c0].kind == PVS__OT_OUT || t->nodes[c1].kind == PVS__OT_OUT)) return 1;
    {   /* a child whose subtree hides the query (2.5D bound) gets nothing */
        int h0 = pvs__ot25_hidden_below(t, t->nodes + c0, near, h), h1 = pvs__ot25_hidden_below(t, t->nodes + c1, near, h);
        if (h0 && h1) { t->stack_count = top; return 0; }
        if (h0 || h1) {
            for (i = 0; i < 3; ++i) nf[i] = h0 ? nd->n[i] : -nd->n[i];
            r = pvs__ot_clip_n(q, nf, nd->p, 1e-12, 0, t->stack + top + 1);
            if (r == 0) { t->stack_count = top; return 0; }
            if (r > 0) pvs__ot_copy(q, t->stack + top + 1);
            t->stack_node[top] = h0 ? c1 : c0;
            return 0;
        }
    }
    /* the child without a hidden-height bound (out-leaves below, likely visible) goes first; the
       other keeps the polygon as it is and clips it only if the test gets there (pvs__ot_owed) */
    first = t->nodes[c1].mr == DBL_MAX && t->nodes[c0].mr != DBL_MAX ? 1 : 0;
    for (i = 0; i < 3; ++i) nf[i] = first ? nd->n[i] : -nd->n[i];
    r = pvs__ot_clip_n(q, nf, nd->p, 1e-12, 0, t->stack + top + 1);
    if (r < 0) pvs__ot_copy(t->stack + top + 1, q); /* too many vertices: the whole polygon (conservative) */
    t->stack_node[top] = first ? c0 : c1;
    t->stack_pend[top] = (node << 1) | (uint32_t)(1 - first);
    if (r != 0) {
        t->stack_node[top + 1] = first ? c1 : c0;
        t->stack_pend[top + 1] = PVS__OT_NONE;
        t->stack_count = top + 2;
    }
    return 0;
}

/* Pays the clip owed by the work item at `top` (pvs__ot_test_inner): its part on side `side` of the
   node's plane, widened by 1e-12. Returns 0 when nothing is left (the caller pops it). */
PVS__STATIC int pvs__ot_owed(pvs__otree *t, size_t top) {
    uint32_t pend = t->stack_pend[top];
    const pvs__otnode *nd = t->nodes + (pend >> 1);
    pvs__otpoly part;
    double nf[3];
    int i, r;
    t->stack_pend[top] = PVS__OT_NONE;
    for (i = 0; i < 3; ++i) nf[i] = (pend & 1u) ? nd->n[i] : -nd->n[i];
    r = pvs__ot_clip_n(t->stack + top, nf, nd->p, 1e-12, 0, &part);
    if (r == 0) return 0;
    if (r > 0) pvs__ot_copy(t->stack + top, &part);
    return 1;
}


/* The blocker polygon B(S, O) (§6.4.3): oriented lines through S = a b and then O = c d, vertices in
   the cyclic order a->c, a->d, b->d, b->c; each edge lies in the plane of the two lines' shared
   point. Coincident vertices (O's supporting line through an end of S, O touching S) merge into
   the triangle of Fig. 6.5. Returns 0 when the polygon is degenerate (no line set of positive
   measure). */
PVS__STATIC int pvs__ot_blocker(const double a[2], const double b[2], const double c[2], const double d[2], pvs__otpoly *q) {
    const double *from[4], *to[4], *pt[4];
    double v[4][3], len[4];
    int i, n = 0, k;
    from[0] = a; to[0] = c; pt[0] = a;
    from[1] = a; to[1] = d; pt[1] = d;
    from[2] = b; to[2] = d; pt[2] = b;
    from[3] = b; to[3] = c; pt[3] = c;
    for (i = 0; i < 4; ++i) len[i] = pvs__ot_line(from[i], to[i], v[i]);
    q->xsplit = 0;
    for (i = 0; i < 4; ++i) {
        double dx = to[i][0] - from[i][0], dy = to[i][1] - from[i][1];
        double scale = fabs(from[i][0]) + fabs(from[i][1]) + fabs(to[i][0]) + fabs(to[i][1]) + 1.0;
        if (sqrt(dx * dx + dy * dy) <= 1e-12 * scale || len[i] == 0.0) continue; /* u == v: no line */
        if (n > 0) {
            double *w = q->v[n - 1];
            double dd = fabs(w[0] - v[i][0]) + fabs(w[1] - v[i][1]) + fabs(w[2] - v[i][2]);
            if (dd <= 1e-12) {
                /* same line as the previous vertex: keep the edge plane through a point on both neighbours */
                continue;
            }
        }
        memcpy(q->v[n], v[i], sizeof(q->v[n]));
        q->e[n][0] = pt[i][0]; q->e[n][1] = pt[i][1];
        q->mark[n] = 0;
        ++n;
    }
    if (n >= 2) {
        double *w = q->v[n - 1], *f = q->v[0];
        double dd = fabs(w[0] - f[0]) + fabs(w[1] - f[1]) + fabs(w[2] - f[2]);
        if (dd <= 1e-12) --n;
    }
    q->n = n;
    if (n < 3) return 0;
    /* fix each edge's plane: the point of the candidates that lies on both end lines */
    {
        const double *cand[4];
        double cn[4][3], en[PVS__OT_MAXV][3], cen[3] = {0, 0, 0};
        cand[0] = a; cand[1] = b; cand[2] = c; cand[3] = d;
        for (k = 0; k < 4; ++k) pvs__ot_normal(cand[k], 1.0, cn[k]);
        for (i = 0; i < n; ++i) {
            const double *v0 = q->v[i], *v1 = q->v[(i + 1) % n];
            int best = -1;
            double best_err = DBL_MAX;
            for (k = 0; k < 4; ++k) {
                double e0 = fabs(cn[k][0] * v0[0] + cn[k][1] * v0[1] + cn[k][2] * v0[2]);
                double e1 = fabs(cn[k][0] * v1[0] + cn[k][1] * v1[1] + cn[k][2] * v1[2]);
                double err = e0 > e1 ? e0 : e1;
                if (err < best_err) { best_err = err; best = k; }
            }
            if (best < 0 || best_err > 1e-9) return 0;
            q->e[i][0] = cand[best][0]; q->e[i][1] = cand[best][1];
            memcpy(en[i], cn[best], sizeof(en[i]));
        }
        /* convexity: every vertex on the inner side of every edge plane */
        for (i = 0; i < n; ++i) for (k = 0; k < 3; ++k) cen[k] += q->v[i][k];
        for (i = 0; i < n; ++i) {
            double s = (en[i][0] * cen[0] + en[i][1] * cen[1] + en[i][2] * cen[2]) / sqrt(cen[0] * cen[0] + cen[1] * cen[1] + cen[2] * cen[2]);
            if (!(fabs(s) > 1e-12)) return 0;
            for (k = 0; k < n; ++k)
                if ((s > 0 ? 1.0 : -1.0) * (en[i][0] * q->v[k][0] + en[i][1] * q->v[k][1] + en[i][2] * q->v[k][2]) < -1e-9) return 0;
        }
    }
    return 1;
}

/* Parameter along line l (unit direction (l1, -l0)) of its crossing with the line through segment
   `s` (4 doubles); 0 when (nearly) parallel or the same line. */
PVS__STATIC int pvs__ot_hit(const double l[3], const double *s, double *t) {
    double m[3], x, y, w, dx = l[1], dy = -l[0], dn;
    m[0] = s[1] - s[3];
    m[1] = s[2] - s[0];
    m[2] = s[0] * s[3] - s[1] * s[2];
    x = l[1] * m[2] - l[2] * m[1];
    y = l[2] * m[0] - l[0] * m[2];
    w = l[0] * m[1] - l[1] * m[0];
    dn = sqrt(m[0] * m[0] + m[1] * m[1]);
    if (!(fabs(w) > 1e-12 * dn)) return 0;
    *t = (x * dx + y * dy) / (w * sqrt(dx * dx + dy * dy));
    return 1;
}

/* Parameter on segment s (4 doubles, 0 at the first end, 1 at the second) where line l crosses its
   supporting line; 0 when parallel. */
PVS__STATIC int pvs__ot_param(const double l[3], const double *s, double *u) {
    double dx = s[2] - s[0], dy = s[3] - s[1];
    double a = l[0] * s[0] + l[1] * s[1] + l[2], b = l[0] * dx + l[1] * dy;
    if (!(fabs(b) > 1e-14 * (fabs(a) + 1e-300))) return 0;
    *u = -a / b;
    return 1;
}

/* The crossing X of the supporting lines of two segments; 0 when parallel. */
PVS__STATIC int pvs__ot_cross(const double *s, const double *r, double x[2]) {
    double d1x = s[2] - s[0], d1y = s[3] - s[1], d2x = r[2] - r[0], d2y = r[3] - r[1];
    double den = d1x * d2y - d1y * d2x, u;
    if (!(fabs(den) > 1e-14 * (fabs(d1x) + fabs(d1y)) * (fabs(d2x) + fabs(d2y)))) return 0;
    u = ((r[0] - s[0]) * d2y - (r[1] - s[1]) * d2x) / den;
    x[0] = s[0] + u * d1x;
    x[1] = s[1] + u * d1y;
    return 1;
}

/* Depth order of occluders j and k along the lines of q (§6.5.1): counts vertices where k is
   clearly in front of j, clearly behind; ties (the line through X or a shared end point) count as
   neither, and so do vertex lines that miss either segment: they lie outside the leaf's region by
   a rounding sliver (a polygon clipped with slack), where the order means nothing. */
PVS__STATIC void pvs__ot_depth(const pvs__otree *t, const pvs__otpoly *q, const double *sj, const double *sk, int *front, int *behind) {
    int i, have_x;
    double x[2];
    *front = *behind = 0;
    /* after a split at the crossing X the lines through X are ties, whatever rounding says */
    have_x = q->xsplit && pvs__ot_cross(sj, sk, x);
    for (i = 0; i < q->n; ++i) {
        double tj, tk, uj, uk;
        if (have_x && fabs(pvs__ot_side(q->v[i], x)) <= 1e-9) continue;
        if (!pvs__ot_hit(q->v[i], sj, &tj) || !pvs__ot_hit(q->v[i], sk, &tk)) continue;
        if (!pvs__ot_param(q->v[i], sj, &uj) || !pvs__ot_param(q->v[i], sk, &uk)) continue;
        if (uj < -1e-7 || uj > 1.0 + 1e-7 || uk < -1e-7 || uk > 1.0 + 1e-7) continue;
        if (tk < tj - t->len_eps) ++*front;
        else if (tk > tj + t->len_eps) ++*behind;
    }
}

/* Turns leaf `node` into the chain of the polygon's unmarked edges (the e-OT, §3.3.3): the sides
   away from the polygon keep the leaf's old kind and payload; returns the node whose region is the
   polygon (the old leaf payload is still on it), or PVS__OT_NONE when out of memory. */
PVS__STATIC uint32_t pvs__ot_refine(pvs__otree *t, uint32_t node, const pvs__otpoly *q) {
    double cen[3] = {0, 0, 0};
    int i, k;
    for (i = 0; i < q->n; ++i) for (k = 0; k < 3; ++k) cen[k] += q->v[i][k];
    for (i = 0; i < q->n; ++i) {
        pvs__otnode old;
        uint32_t outside, inside;
        double s;
        if (q->mark[i]) continue;
        s = pvs__ot_side(cen, q->e[i]);
        outside = pvs__ot_new_node(t);
        inside = pvs__ot_new_node(t);
        if (outside == PVS__OT_NONE || inside == PVS__OT_NONE) return PVS__OT_NONE;
        old = t->nodes[node];
        t->nodes[outside] = old;
        t->nodes[inside] = old;
        t->nodes[outside].parent = t->nodes[inside].parent = node;
        t->nodes[node].kind = 0;
        t->nodes[node].p[0] = q->e[i][0];
        t->nodes[node].p[1] = q->e[i][1];
        t->nodes[node].sign = s > 0 ? 1 : -1;
        pvs__ot_normal(q->e[i], (double)t->nodes[node].sign, t->nodes[node].n);
        t->nodes[node].child[0] = outside;
        t->nodes[node].child[1] = inside;
        node = inside;
    }
    return node;
}

/* Splits leaf `node` by the plane of p; the side `sign * side(p) > 0` continues. Returns that child. */
PVS__STATIC uint32_t pvs__ot_split_leaf(pvs__otree *t, uint32_t node, const double p[2], double sign) {
    uint32_t neg = pvs__ot_new_node(t), pos = pvs__ot_new_node(t);
    pvs__otnode old;
    if (neg == PVS__OT_NONE || pos == PVS__OT_NONE) return PVS__OT_NONE;
    old = t->nodes[node];
    t->nodes[neg] = old;
    t->nodes[pos] = old;
    t->nodes[neg].parent = t->nodes[pos].parent = node;
    t->nodes[node].kind = 0;
    t->nodes[node].p[0] = p[0];
    t->nodes[node].p[1] = p[1];
    t->nodes[node].sign = sign > 0 ? 1 : -1;
    pvs__ot_normal(p, (double)t->nodes[node].sign, t->nodes[node].n);
    t->nodes[node].child[0] = neg;
    t->nodes[node].child[1] = pos;
    return pos;
}

/* Gives leaf `node` the payload seq[old_first .. + old_count) followed by `add`. */
PVS__STATIC int pvs__ot_set_payload(pvs__otree *t, uint32_t node, uint32_t old_first, uint32_t old_count, uint32_t add) {
    size_t first = t->seq_count;
    if (!pvs__ot_grow(t->a, (void **)&t->seq, &t->seq_cap, t->seq_count + old_count + 1, sizeof(uint32_t))) return t->oom = 1, 0;
    if (old_count) memmove(t->seq + first, t->seq + old_first, old_count * sizeof(uint32_t));
    t->seq[first + old_count] = add;
    t->seq_count = first + old_count + 1;
    t->nodes[node].kind = PVS__OT_IN;
    t->nodes[node].first = (uint32_t)first;
    t->nodes[node].count = old_count + 1;
    return 1;
}

/* ---- 2D from-region (ch. 6): insertion with the four depth cases of §6.5.1 ---- */

/* Inserts blocker polygon q of occluder k (§3.3.3 with the 2D in-leaf cases). */
PVS__STATIC void pvs__ot2_insert(pvs__otree *t, const pvs__otpoly *blocker, uint32_t k, double near) {
    size_t base = t->stack_count;
    const double *sk = t->seg + 4 * (size_t)k;
    if (!pvs__ot_push(t, 0, blocker)) return;
    while (t->stack_count > base && !t->oom) {
        pvs__otpoly q, part;
        uint32_t node = t->stack_node[t->stack_count - 1];
        pvs__otnode *nd = t->nodes + node;
        /* the maximum visibility distance shortcut (§6.5.5): every line of this subtree meets a
           stored occluder closer to any cell point than k is to the cell: k is hidden here */
        if (near > nd->mvd) { --t->stack_count; continue; }
        if (nd->kind == 0) { pvs__ot_insert_inner(t, t->stack_count - 1, -1.0, 0.0); continue; }
        pvs__ot_pop(t, &q);
        if (nd->kind == PVS__OT_OUT) {
            uint32_t leaf = pvs__ot_refine(t, node, &q);
            if (leaf != PVS__OT_NONE) pvs__ot_set_payload(t, leaf, 0, 0, k);
        } else {
            uint32_t j = t->seq[nd->first];
            const double *sj = t->seg + 4 * (size_t)j;
            int front, behind;
            if (j == k) continue;
            pvs__ot_depth(t, &q, sj, sk, &front, &behind);
            if (!front) continue;                        /* case 1 (behind) and case 4 (collinear) */
            if (behind && !q.xsplit) {                   /* case 3: split at the crossing X */
                double x[2];
                if (pvs__ot_cross(sj, sk, x)) {
                    q.xsplit = 1;
                    if (pvs__ot_clip(&q, x, 1.0, 0.0, 0, &part) >= 3) pvs__ot_push(t, node, &part);
                    if (pvs__ot_clip(&q, x, -1.0, 0.0, 0, &part) >= 3) pvs__ot_push(t, node, &part);
                    continue;
                }
            }
            /* case 2 (or an unresolved crossing, counted as in front: conservative) */
            {
                uint32_t leaf = pvs__ot_refine(t, node, &q);
                if (leaf != PVS__OT_NONE) pvs__ot_set_payload(t, leaf, 0, 0, k);
            }
        }
    }
    t->stack_count = base;
}

/* Thickness of a line-space polygon: the smallest over its edges of the largest vertex distance
   from the edge's plane. Insertion leaves slivers about 1e-12 thick where it rounded; line sets
   thinner than PVS__OT_SLIVER (radians, at unit distance) are below the resolution of the method. */
#define PVS__OT_SLIVER 1e-10
PVS__STATIC double pvs__ot_thickness(const pvs__otpoly *q) {
    double th = DBL_MAX;
    int i, k;
    if (q->n < 3) return 0.0;
    for (i = 0; i < q->n; ++i) {
        double mx = 0.0;
        for (k = 0; k < q->n; ++k) {
            double d = fabs(pvs__ot_side(q->v[k], q->e[i]));
            if (d > mx) mx = d;
        }
        if (mx < th) th = mx;
    }
    return th;
}

/* Read-only test (§3.3.4, §6.5.3): 1 when some line of q reaches occluder k before any stored
   occluder. Splits with slack (both sides see a little more), stops at the first visible leaf;
   slivers (see pvs__ot_thickness) do not count, so the answer does not depend on where insertion
   rounded, i.e. on the insertion order. */
PVS__STATIC int pvs__ot2_visible(pvs__otree *t, const pvs__otpoly *blocker, uint32_t k, double near) {
    size_t base = t->stack_count;
    const double *sk = t->seg + 4 * (size_t)k;
    int vis = 0;
    if (!pvs__ot_push(t, 0, blocker)) return 1;
    while (t->stack_count > base && !vis) {
        pvs__otpoly q, part;
        uint32_t node = t->stack_node[t->stack_count - 1];
        const pvs__otnode *nd = t->nodes + node;
        if (near > nd->mvd) { --t->stack_count; continue; } /* §6.5.5 */
        if (t->stack_pend[t->stack_count - 1] != PVS__OT_NONE && !pvs__ot_owed(t, t->stack_count - 1)) { --t->stack_count; continue; }
        if (nd->kind == 0) { vis |= pvs__ot_test_inner(t, t->stack_count - 1, -1.0, 0.0); continue; }
        pvs__ot_pop(t, &q);
        if (pvs__ot_thickness(&q) < PVS__OT_SLIVER) {
            continue;
        } else if (nd->kind == PVS__OT_OUT) {
            vis = 1;
        } else {
            uint32_t j = t->seq[nd->first];
            int front, behind;
            if (j == k) { vis = 1; break; }
            pvs__ot_depth(t, &q, t->seg + 4 * (size_t)j, sk, &front, &behind);
            if (front && behind && !q.xsplit) { /* the exact test splits at the crossing X (§6.5.1 case 3) */
                double x[2];
                if (pvs__ot_cross(t->seg + 4 * (size_t)j, sk, x)) {
                    q.xsplit = 1;
                    if (pvs__ot_clip(&q, x, 1.0, 0.0, 0, &part) >= 3) vis |= !pvs__ot_push(t, node, &part);
                    if (pvs__ot_clip(&q, x, -1.0, 0.0, 0, &part) >= 3) vis |= !pvs__ot_push(t, node, &part);
                    continue;
                }
            }
            if (front || !behind) vis = 1; /* in front somewhere, or all ties (collinear): visible */
        }
    }
    t->stack_count = base;
    return vis || t->oom;
}

/* ---- shared driver pieces ---- */

/* Clips segment s (4 doubles) to the open half-plane right of a -> b (the outer side of a CCW
   edge). Returns 0 when nothing is left; *on_line tells which clipped end (1 = first, 2 = second)
   was moved onto the line. */
PVS__STATIC int pvs__ot_clip_segment(const double a[2], const double b[2], const double *s, double out[4], int *on_line) {
    double ex = b[0] - a[0], ey = b[1] - a[1], len = sqrt(ex * ex + ey * ey);
    double f0 = (ex * (s[1] - a[1]) - ey * (s[0] - a[0])) / len;
    double f1 = (ex * (s[3] - a[1]) - ey * (s[2] - a[0])) / len;
    *on_line = 0;
    memcpy(out, s, 4 * sizeof(double));
    if (f0 >= 0.0 && f1 >= 0.0) return 0;
    if (f0 >= 0.0) {
        double u = f0 / (f0 - f1);
        out[0] = s[0] + u * (s[2] - s[0]);
        out[1] = s[1] + u * (s[3] - s[1]);
        *on_line = 1;
    } else if (f1 >= 0.0) {
        double u = f1 / (f1 - f0);
        out[2] = s[2] + u * (s[0] - s[2]);
        out[3] = s[3] + u * (s[1] - s[3]);
        *on_line = 2;
    }
    return !(out[0] == out[2] && out[1] == out[3]);
}

/* The blockers of source edge a -> b (lines leaving to its right) and the clipped segment o: one,
   or two when o's supporting line crosses the edge at x (Fig. 6.5). Returns how many were built
   (0..2); *degenerate is set when a non-empty line set could not be represented. */
PVS__STATIC int pvs__ot_blockers(const double a[2], const double b[2], const double o[4], int on_line, pvs__otpoly out[2], int *degenerate) {
    double x[2], ex = b[0] - a[0], ey = b[1] - a[1], u = -1.0;
    int n = 0, have_x = 0;
    *degenerate = 0;
    if (on_line) {
        x[0] = on_line == 1 ? o[0] : o[2];
        x[1] = on_line == 1 ? o[1] : o[3];
        u = ((x[0] - a[0]) * ex + (x[1] - a[1]) * ey) / (ex * ex + ey * ey);
        have_x = 1;
    } else {
        double seg[4];
        seg[0] = a[0]; seg[1] = a[1]; seg[2] = b[0]; seg[3] = b[1];
        if (pvs__ot_cross(seg, o, x)) {
            u = ((x[0] - a[0]) * ex + (x[1] - a[1]) * ey) / (ex * ex + ey * ey);
            have_x = 1;
        }
    }
    if (have_x && u > 1e-12 && u < 1.0 - 1e-12) {
        if (pvs__ot_blocker(a, x, o, o + 2, &out[n])) ++n; else *degenerate = 1;
        if (pvs__ot_blocker(x, b, o, o + 2, &out[n])) ++n; else *degenerate = 1;
    } else {
        if (pvs__ot_blocker(a, b, o, o + 2, &out[n])) ++n; else *degenerate = 1;
    }
    return n;
}

typedef struct pvs__ot_order {
    double key;
    uint32_t index;
} pvs__ot_order;
PVS__STATIC int pvs__ot_order_less(const pvs__ot_order *a, const pvs__ot_order *b) {
    return a->key < b->key || (a->key == b->key && a->index < b->index);
}
/* Heap sort by (key, index): no libc qsort (stdlib.h is optional when PVS_MALLOC is defined). */
PVS__STATIC void pvs__ot_sort(pvs__ot_order *o, uint32_t n) {
    uint32_t i, end;
    for (end = n; end > 1; --end) {
        if (end == n)
            for (i = n / 2; i-- > 0;) { /* heapify */
                uint32_t r = i;
                for (;;) {
                    uint32_t c = 2 * r + 1;
                    pvs__ot_order tmp;
                    if (c >= n) break;
                    if (c + 1 < n && pvs__ot_order_less(o + c, o + c + 1)) ++c;
                    if (!pvs__ot_order_less(o + r, o + c)) break;
                    tmp = o[r]; o[r] = o[c]; o[c] = tmp;
                    r = c;
                }
            }
        {
            pvs__ot_order tmp = o[0];
            uint32_t r = 0, m = end - 1;
            o[0] = o[m]; o[m] = tmp;
            for (;;) {
                uint32_t c = 2 * r + 1;
                if (c >= m) break;
                if (c + 1 < m && pvs__ot_order_less(o + c, o + c + 1)) ++c;
                if (!pvs__ot_order_less(o + r, o + c)) break;
                tmp = o[r]; o[r] = o[c]; o[c] = tmp;
                r = c;
            }
        }
    }
}
/* Squared distance from point p to segment s. */
PVS__STATIC double pvs__ot_dist2(const double p[2], const double *s) {
    double dx = s[2] - s[0], dy = s[3] - s[1], l2 = dx * dx + dy * dy, u = 0.0, qx, qy;
    if (l2 > 0.0) {
        u = ((p[0] - s[0]) * dx + (p[1] - s[1]) * dy) / l2;
        if (u < 0.0) u = 0.0;
        if (u > 1.0) u = 1.0;
    }
    qx = s[0] + u * dx - p[0];
    qy = s[1] + u * dy - p[1];
    return qx * qx + qy * qy;
}
/* 1 when segment s meets the closed convex CCW polygon poly (n vertices). */
PVS__STATIC int pvs__ot_segment_meets_polygon(const double *s, const double *poly, uint32_t n) {
    double t0 = 0.0, t1 = 1.0, dx = s[2] - s[0], dy = s[3] - s[1];
    uint32_t i;
    for (i = 0; i < n; ++i) {
        const double *a = poly + 2 * i, *b = poly + 2 * ((i + 1) % n);
        double ex = b[0] - a[0], ey = b[1] - a[1];
        double f = ex * (s[1] - a[1]) - ey * (s[0] - a[0]); /* >= 0 inside */
        double g = ex * dy - ey * dx;                        /* change of f along s */
        if (g == 0.0) {
            if (f < 0.0) return 0;
        } else {
            double u = -f / g;
            if (g > 0.0) { if (u > t0) t0 = u; }
            else if (u < t1) t1 = u;
            if (t0 > t1) return 0;
        }
    }
    return 1;
}

/* Recomputes the maximum visibility distances bottom-up (§6.5.5): children always have larger
   indices than their parent, so one backward pass suffices. Out-leaves: unbounded; in-leaves: the
   largest distance between the stored occluder and a cell point (so along any line the stored
   occluder is at most that far from where the line leaves the cell). */
PVS__STATIC void pvs__ot2_update_mvd(pvs__otree *t) {
    size_t i;
    for (i = t->node_count; i-- > 0;) {
        pvs__otnode *nd = t->nodes + i;
        if (nd->kind == PVS__OT_OUT) nd->mvd = DBL_MAX;
        else if (nd->kind == PVS__OT_IN) nd->mvd = t->reach[t->seq[nd->first]];
        else {
            double a = t->nodes[nd->child[0]].mvd, b = t->nodes[nd->child[1]].mvd;
            nd->mvd = a > b ? a : b;
        }
    }
}

/* Distance between segments s and r (0 when they meet). */
PVS__STATIC double pvs__ot_seg_dist(const double *s, const double *r) {
    double x[2], d, best;
    int i;
    if (pvs__ot_cross(s, r, x)) {
        double us, ur, dx = s[2] - s[0], dy = s[3] - s[1], ex = r[2] - r[0], ey = r[3] - r[1];
        us = dx * dx + dy * dy > 0 ? ((x[0] - s[0]) * dx + (x[1] - s[1]) * dy) / (dx * dx + dy * dy) : -1.0;
        ur = ex * ex + ey * ey > 0 ? ((x[0] - r[0]) * ex + (x[1] - r[1]) * ey) / (ex * ex + ey * ey) : -1.0;
        if (us >= 0.0 && us <= 1.0 && ur >= 0.0 && ur <= 1.0) return 0.0;
    }
    best = DBL_MAX;
    for (i = 0; i < 2; ++i) {
        d = pvs__ot_dist2(s + 2 * i, r);
        if (d < best) best = d;
        d = pvs__ot_dist2(r + 2 * i, s);
        if (d < best) best = d;
    }
    return sqrt(best);
}

/* ---- 2D from-region API (ch. 6) ---- */

PVS_API pvs_result pvs_visibility_2d(const pvs_visibility_2d_desc *desc, pvs_word *visible_segments, pvs_word *visible_objects,
                                     pvs_otree_stats *stats, pvs_error *err) {
    pvs__otree t;
    pvs_allocator al;
    double *cell = NULL, *seg = NULL, *reach = NULL, *near = NULL, cx = 0.0, cy = 0.0, area = 0.0;
    pvs__ot_order *order = NULL;
    uint32_t n, i, k, budget, count;
    pvs_result r = PVS_OK;
    pvs_otree_stats st;
    memset(&st, 0, sizeof(st));
    memset(&t, 0, sizeof(t));
    if (stats) *stats = st;
    if (!desc || !desc->cell || desc->cell_vertex_count < 3 || (desc->segment_count && !desc->segments))
        return pvs__fail(err, PVS_ERROR_INVALID_ARGUMENT, -1, 0, "desc, a cell of >= 3 vertices and the segments are required");
    n = desc->cell_vertex_count;
    count = desc->segment_count;
    for (i = 0; i < 2 * n; ++i)
        if (!pvs__finite(desc->cell[i])) return pvs__fail(err, PVS_ERROR_NOT_FINITE, i / 2, 0, "cell vertex %u is not finite", i / 2);
    for (i = 0; i < 4 * count; ++i)
        if (!pvs__finite(desc->segments[i])) return pvs__fail(err, PVS_ERROR_NOT_FINITE, i / 4, 0, "segment %u is not finite", i / 4);
    if (desc->segment_objects)
        for (i = 0; i < count; ++i)
            if (desc->segment_objects[i] != PVS_NO_OBJECT && desc->segment_objects[i] >= desc->object_count)
                return pvs__fail(err, PVS_ERROR_INDEX_OUT_OF_RANGE, i, 0, "segment %u names object %u of %u", i, desc->segment_objects[i], desc->object_count);
    al = desc->allocator;
    t.a = &al;
    cell = (double *)pvs__alloc_array(&al, 2 * (size_t)n, sizeof(double));
    seg = (double *)pvs__alloc_array(&al, 4 * (size_t)count + 4, sizeof(double));
    order = (pvs__ot_order *)pvs__alloc_array(&al, (size_t)count + 1, sizeof(pvs__ot_order));
    reach = (double *)pvs__alloc_array(&al, (size_t)count + 1, sizeof(double));
    near = (double *)pvs__alloc_array(&al, (size_t)count + 1, sizeof(double));
    if (!cell || !seg || !order || !reach || !near) { r = pvs__fail(err, PVS_ERROR_OUT_OF_MEMORY, -1, 0, "2D visibility arrays"); goto done; }
    for (i = 0; i < n; ++i) { cx += desc->cell[2 * i]; cy += desc->cell[2 * i + 1]; }
    cx /= n; cy /= n;
    for (i = 0; i < n; ++i) {
        cell[2 * i] = (double)desc->cell[2 * i] - cx;
        cell[2 * i + 1] = (double)desc->cell[2 * i + 1] - cy;
    }
    for (i = 0; i < n; ++i) {
        const double *a = cell + 2 * i, *b = cell + 2 * ((i + 1) % n);
        area += a[0] * b[1] - a[1] * b[0];
    }
    if (!(fabs(area) > 0.0)) { r = pvs__fail(err, PVS_ERROR_BAD_CELL, -1, 0, "the cell polygon has no area"); goto done; }
    if (area < 0.0) /* make it counter-clockwise */
        for (i = 0; i < n / 2; ++i) {
            double tx = cell[2 * i], ty = cell[2 * i + 1];
            cell[2 * i] = cell[2 * (n - 1 - i)]; cell[2 * i + 1] = cell[2 * (n - 1 - i) + 1];
            cell[2 * (n - 1 - i)] = tx; cell[2 * (n - 1 - i) + 1] = ty;
        }
    for (i = 0; i < n; ++i) { /* convex: no right turn */
        const double *a = cell + 2 * i, *b = cell + 2 * ((i + 1) % n), *c = cell + 2 * ((i + 2) % n);
        if ((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]) < 0.0) {
            r = pvs__fail(err, PVS_ERROR_BAD_CELL, -1, 0, "the cell polygon is not convex");
            goto done;
        }
    }
    {
        double ext = 1.0, o[2] = {0.0, 0.0};
        for (i = 0; i < 4 * count; ++i) {
            seg[i] = (double)desc->segments[i] - (i & 1 ? cy : cx);
            if (fabs(seg[i]) > ext) ext = fabs(seg[i]);
        }
        t.len_eps = 1e-9 * ext;
        for (i = 0; i < count; ++i) {
            order[i].key = desc->flags & PVS_VISIBILITY_INPUT_ORDER ? 0.0 : pvs__ot_dist2(o, seg + 4 * i);
            order[i].index = i;
        }
    }
    pvs__ot_sort(order, count);
    for (i = 0; i < count; ++i) { /* distances for the MVD shortcut, rounded outward */
        const double *sg = seg + 4 * i;
        double far2 = 0.0, nr = DBL_MAX;
        for (k = 0; k < n; ++k) {
            double e[4], d0, d1;
            int m;
            e[0] = cell[2 * k]; e[1] = cell[2 * k + 1]; e[2] = cell[2 * ((k + 1) % n)]; e[3] = cell[2 * ((k + 1) % n) + 1];
            for (m = 0; m < 2; ++m) {
                d0 = (sg[2 * m] - e[0]) * (sg[2 * m] - e[0]) + (sg[2 * m + 1] - e[1]) * (sg[2 * m + 1] - e[1]);
                if (d0 > far2) far2 = d0;
            }
            d1 = pvs__ot_seg_dist(sg, e);
            if (d1 < nr) nr = d1;
        }
        reach[i] = sqrt(far2) * (1.0 + 1e-9) + t.len_eps;
        near[i] = pvs__ot_segment_meets_polygon(sg, cell, n) ? 0.0 : nr * (1.0 - 1e-9) - t.len_eps;
    }
    t.reach = reach;
    t.seg = seg;
    budget = desc->node_budget ? desc->node_budget : 1u << 20;
    if (!pvs__ot_reset(&t)) { r = pvs__fail(err, PVS_ERROR_OUT_OF_MEMORY, -1, 0, "occlusion tree"); goto done; }
    /* the sweep (§6.6): occluders by distance to the cell's centre, one tree for all edges (§6.5.2) */
    for (i = 0; i < count && !t.oom; ++i) {
        uint32_t j = order[i].index;
        const double *s = seg + 4 * j;
        if (desc->segment_flags && (desc->segment_flags[j] & PVS_SEGMENT_NO_OCCLUSION)) continue;
        if (s[0] == s[2] && s[1] == s[3]) continue;
        if (t.node_count >= budget) { st.budget_exceeded = 1; break; }
        ++st.occluders_inserted;
        for (k = 0; k < n; ++k) {
            double o[4];
            pvs__otpoly bl[2];
            int on, nb, deg, m;
            if (!pvs__ot_clip_segment(cell + 2 * k, cell + 2 * ((k + 1) % n), s, o, &on)) continue;
            /* an occluder crossing the cell is visible anyway; its outside parts still block */
            nb = pvs__ot_blockers(cell + 2 * ((k + 1) % n), cell + 2 * k, o, on, bl, &deg);
            for (m = 0; m < nb; ++m) pvs__ot2_insert(&t, &bl[m], j, near[j]);
        }
        pvs__ot2_update_mvd(&t);
    }
    if (t.oom) { r = pvs__fail(err, PVS_ERROR_OUT_OF_MEMORY, -1, 0, "occlusion tree nodes"); goto done; }
    /* exact re-test of every segment against the final tree (§6.6) */
    if (visible_segments) memset(visible_segments, 0, PVS_BITSET_WORDS(count) * sizeof(pvs_word));
    if (visible_objects) memset(visible_objects, 0, PVS_BITSET_WORDS(desc->object_count) * sizeof(pvs_word));
    for (i = 0; i < count; ++i) {
        const double *s = seg + 4 * i;
        int vis = 0;
        if (pvs__ot_segment_meets_polygon(s, cell, n)) vis = 1;
        else if (s[0] == s[2] && s[1] == s[3]) vis = 1; /* a point: no line set to test, count it visible */
        for (k = 0; k < n && !vis; ++k) {
            double o[4];
            pvs__otpoly bl[2];
            int on, nb, deg, m;
            if (!pvs__ot_clip_segment(cell + 2 * k, cell + 2 * ((k + 1) % n), s, o, &on)) continue;
            nb = pvs__ot_blockers(cell + 2 * ((k + 1) % n), cell + 2 * k, o, on, bl, &deg);
            if (deg) vis = 1;
            for (m = 0; m < nb && !vis; ++m) vis = pvs__ot2_visible(&t, &bl[m], i, near[i]);
        }
        if (t.oom) { r = pvs__fail(err, PVS_ERROR_OUT_OF_MEMORY, -1, 0, "occlusion tree test"); goto done; }
        if (!vis) continue;
        ++st.visible_segments;
        if (visible_segments) pvs_bitset_set(visible_segments, i);
        if (visible_objects) {
            uint32_t obj = desc->segment_objects ? desc->segment_objects[i] : i;
            if (obj != PVS_NO_OBJECT && obj < desc->object_count) pvs_bitset_set(visible_objects, obj);
        }
    }
    st.nodes = (uint32_t)t.node_count;
    if (stats) *stats = st;
    pvs__ok(err);
done:
    pvs__ot_free(&t);
    pvs__free_array(&al, cell, 2 * (size_t)n, sizeof(double));
    pvs__free_array(&al, seg, 4 * (size_t)count + 4, sizeof(double));
    pvs__free_array(&al, order, (size_t)count + 1, sizeof(pvs__ot_order));
    pvs__free_array(&al, reach, (size_t)count + 1, sizeof(double));
    pvs__free_array(&al, near, (size_t)count + 1, sizeof(double));
    return r;
}

/* ---- 2.5D from-region, c-LSS (ch. 7) ---- */

/* Cost (bench_auto and bench_otree, demo city, 2026-11-24, shared machine): about 9 ms of CPU time
   per cell (110 M instructions, callgrind), five times less than the first version, from: unit plane
   normals stored in the nodes (no square root per classification), the work stack used in place,
   per-occluder umbra data computed once per tree, an umbra covering the whole far edge ending the
   funnel test early, the hidden-height bound below (most hidden queries stop high in the tree), clips
   of read-only tests paid only where the test goes, and no box tests of kD nodes holding fewer than
   PVS__OT25_TEST_MIN items. What remains is the depth of the tree (leaves about 35 levels down): the
   splitting of facade blockers on insertion and the descent of visible kD boxes to an out-leaf. */

#define PVS__OT25_MAX_UMBRAE 96
#define PVS__OT25_JD 10 /* doubles of per-occluder data (pvs__ot25_prepare) */
#define PVS__OT25_TEST_MIN 48 /* kD nodes with fewer item references are not tested (cf. §4.12.1: none below 50 polygons) */

/* The hidden-height bound (a 2.5D form of the maximum visibility distance, §6.5.5, which alone
   is not valid in 2.5D: occluders are seen over). Every line of an in-leaf crosses each member j
   (its region lies in j's blocker). A ray from an eye no higher than H = t->eye over such a line
   that passes over j (top h_j > H) is, at a point q with |pq| >= n > reach_j >= |pc| (p the eye's
   ground point, c the crossing with j), at least H + (h_j - H) n / reach_j high: rising, it climbs
   at least that slope. So a query point no nearer than n to the cell and lower than H + s n, s =
   (h_j - H) / reach_j, is hidden in the leaf. A leaf keeps its steepest member (mr = reach, ms =
   slope); an inner node the largest reach and the least slope of its children, so the bound holds
   for its whole subtree. Out-leaves and leaves without a member taller than the eyes have none. */
PVS__STATIC void pvs__ot25_leaf_bound(const pvs__otree *t, pvs__otnode *nd) {
    uint32_t m;
    nd->mr = DBL_MAX;
    nd->ms = 0.0;
    if (nd->kind != PVS__OT_IN) return;
    for (m = 0; m < nd->count; ++m) {
        const double *jd = t->jd + PVS__OT25_JD * (size_t)t->seq[nd->first + m];
        if (jd[9] > nd->ms) { nd->ms = jd[9]; nd->mr = jd[8]; }
    }
}
/* Recomputes the bound of the subtree at `node` (just rebuilt from a leaf: a short chain) and of its
   ancestors while they change. */
PVS__STATIC void pvs__ot25_bound_subtree(pvs__otree *t, uint32_t node) {
    pvs__otnode *nd = t->nodes + node;
    if (nd->kind) { pvs__ot25_leaf_bound(t, nd); return; }
    pvs__ot25_bound_subtree(t, nd->child[0]);
    pvs__ot25_bound_subtree(t, nd->child[1]);
    nd = t->nodes + node;
    {
        const pvs__otnode *a = t->nodes + nd->child[0], *b = t->nodes + nd->child[1];
        nd->mr = a->mr > b->mr ? a->mr : b->mr;
        nd->ms = a->ms < b->ms ? a->ms : b->ms;
    }
}
PVS__STATIC void pvs__ot25_bound(pvs__otree *t, uint32_t node) {
    uint32_t p;
    pvs__ot25_bound_subtree(t, node);
    for (p = t->nodes[node].parent; p != PVS__OT_NONE; p = t->nodes[p].parent) {
        pvs__otnode *nd = t->nodes + p;
        const pvs__otnode *a = t->nodes + nd->child[0], *b = t->nodes + nd->child[1];
        double mr = a->mr > b->mr ? a->mr : b->mr, ms = a->ms < b->ms ? a->ms : b->ms;
        if (mr == nd->mr && ms == nd->ms) break;
        nd->mr = mr;
        nd->ms = ms;
    }
}
/* A lower bound of the distance between the (grown) cell rectangle and segment e: the distance
   between the rectangle and e's bounding box (exact for axis-parallel segments), rounded down. */
PVS__STATIC double pvs__ot25_near(const pvs__otree *t, const double *e) {
    double dx = 0.0, dy = 0.0, d;
    double lx = e[0] < e[2] ? e[0] : e[2], hx = e[0] < e[2] ? e[2] : e[0];
    double ly = e[1] < e[3] ? e[1] : e[3], hy = e[1] < e[3] ? e[3] : e[1];
    if (lx > t->corners[2]) dx = lx - t->corners[2];
    else if (hx < t->corners[0]) dx = t->corners[0] - hx;
    if (ly > t->corners[5]) dy = ly - t->corners[5];
    else if (hy < t->corners[1]) dy = t->corners[1] - hy;
    d = sqrt(dx * dx + dy * dy) * (1.0 - 1e-9) - t->len_eps;
    return d > 0.0 ? d : 0.0;
}

/* Extended umbra (§7.5.1) of occluder j on the top edge of a far segment e (height h) for 3D rays
   from eyes at height H = t->eye anywhere over the cell (§7.1: a descending ray is seen at least as
   well from where its 2D line leaves the cell, an ascending one from where it enters; both lie on
   the cell's top edges) over j's top edge: the parameters u on e where every such ray passes below
   j's top, as an open interval (u0, u1). For one eye p the rays over j's top line form a plane; a
   point q of e lies below it when (h - H) D(p) < (h_j - H) (D(p) - D(q)), D the signed distance to
   j's supporting line (> 0 on the side the lines come from). The bound is monotone in D(p), so the
   extreme distances of the cell's corners (clamped at 0: eyes behind j's line do not look over j)
   cover every eye; this is the plane pair pi_o / pi_s of the thesis, taken over the whole cell so
   that one tree per edge serves both kinds of rays. Returns 0 when the umbra is empty. */
PVS__STATIC int pvs__ot25_umbra(const pvs__otree *t, const double *jd, double q0, double q1, double h, double *u0, double *u1) {
    double hj = jd[6], hn = h - t->eye, lo = -DBL_MAX, hi = DBL_MAX;
    int i;
    /* constraints alpha + beta u > margin; q0, q1: the distances D of e's ends */
    for (i = 0; i < 3; ++i) {
        double alpha, beta, margin, lim;
        if (i < 2) {
            double d = jd[3 + i];
            alpha = hj * (d - q0) - hn * d;
            beta = -hj * (q1 - q0);
            margin = 1e-9 * (fabs(hj) + fabs(hn) + 1.0) * (d + fabs(q0) + fabs(q1) + 1.0);
        } else { /* q strictly beyond j's line */
            alpha = -q0;
            beta = -(q1 - q0);
            margin = t->len_eps;
        }
        if (beta == 0.0) {
            if (!(alpha > margin)) return 0;
            continue;
        }
        lim = (margin - alpha) / beta;
        if (beta > 0.0) { if (lim > lo) lo = lim; }
        else if (lim < hi) hi = lim;
    }
    if (!(lo < hi)) return 0;
    *u0 = lo; *u1 = hi;
    return 1;
}

/* What pvs__ot25_umbra and the depth order need of occluder j in the current tree, once per tree:
   jd[0..2] its line as D(x) = jd[0] x + jd[1] y + jd[2] (unit normal, > 0 on the source edge's
   side), jd[3..4] the least and largest D of the cell's corners (clamped at 0), jd[5] 1 when the
   whole source edge lies on one side, jd[6] its top above the eyes, jd[7] 0 when no umbra exists
   (the source edge's midpoint on its line, or a point segment); jd[8] its reach (the largest
   distance between a cell point and it, rounded up) and jd[9] the slope (top - eyes) / reach of
   its shadow's floor when it is taller than the eyes, else 0 (pvs__ot25_bound). */
PVS__STATIC void pvs__ot25_prepare(pvs__otree *t, uint32_t j) {
    const double *sg = t->seg + 4 * (size_t)j;
    double *jd = t->jd + PVS__OT25_JD * (size_t)j, dx = sg[2] - sg[0], dy = sg[3] - sg[1], len = sqrt(dx * dx + dy * dy), sa, da, db;
    double far2 = 0.0;
    int i, k;
    memset(jd, 0, PVS__OT25_JD * sizeof(double));
    for (i = 0; i < 4; ++i)
        for (k = 0; k < 2; ++k) {
            double ex = sg[2 * k] - t->corners[2 * i], ey = sg[2 * k + 1] - t->corners[2 * i + 1];
            if (ex * ex + ey * ey > far2) far2 = ex * ex + ey * ey;
        }
    jd[8] = sqrt(far2) * (1.0 + 1e-9) + t->len_eps;
    if (t->top[j] > t->eye) jd[9] = (t->top[j] - t->eye) / jd[8] * (1.0 - 1e-9);
    if (!(len > 0.0)) return;
    sa = dx * (0.5 * (t->sa[1] + t->sb[1]) - sg[1]) - dy * (0.5 * (t->sa[0] + t->sb[0]) - sg[0]);
    if (sa == 0.0) return;
    sa = sa > 0.0 ? 1.0 : -1.0;
    jd[0] = -sa * dy / len;
    jd[1] = sa * dx / len;
    jd[2] = sa * (dy * sg[0] - dx * sg[1]) / len;
    jd[3] = DBL_MAX;
    jd[4] = -DBL_MAX;
    for (i = 0; i < 4; ++i) {
        double d = jd[0] * t->corners[2 * i] + jd[1] * t->corners[2 * i + 1] + jd[2];
        if (d < 0.0) d = 0.0;
        if (d < jd[3]) jd[3] = d;
        if (d > jd[4]) jd[4] = d;
    }
    da = jd[0] * t->sa[0] + jd[1] * t->sa[1] + jd[2];
    db = jd[0] * t->sb[0] + jd[1] * t->sb[1] + jd[2];
    jd[5] = (da > t->len_eps && db > t->len_eps) || (da < -t->len_eps && db < -t->len_eps);
    jd[6] = t->top[j] - t->eye;
    jd[7] = 1.0;
}

/* The part of far segment e (height h) seen over the front members of leaf payload
   seq[first..+count) within the funnel of polygon q: its parameter hull [*v0, *v1] inside the
   funnel range [*f0, *f1]. Members that cross `skip_box` (a 2D box, or NULL) or that are not
   clearly in front are ignored (conservative). Returns 0 when nothing is left. */
PVS__STATIC int pvs__ot25_open(const pvs__otree *t, const pvs__otpoly *q, uint32_t first, uint32_t count, uint32_t self,
                               const double *e, double h, const double *skip_box, double *f0, double *f1, double *v0, double *v1) {
    double flo = DBL_MAX, fhi = -DBL_MAX;
    double um[PVS__OT25_MAX_UMBRAE][2];
    int i, nu = 0, changed;
    uint32_t m;
    *f0 = *v0 = 0.0; *f1 = *v1 = 1.0;
    for (m = 0; m < count && nu < PVS__OT25_MAX_UMBRAE; ++m) {
        uint32_t j = t->seq[first + m];
        const double *sj = t->seg + 4 * (size_t)j, *jd = t->jd + PVS__OT25_JD * (size_t)j;
        double s0, s1, tol = t->len_eps;
        int front, behind;
        if (j == self || !jd[7]) continue;
        if (skip_box) {
            double sb4[4];
            sb4[0] = skip_box[0]; sb4[1] = skip_box[1]; sb4[2] = skip_box[2]; sb4[3] = skip_box[3];
            if (fmin(sj[0], sj[2]) <= sb4[2] + t->len_eps && fmax(sj[0], sj[2]) >= sb4[0] - t->len_eps &&
                fmin(sj[1], sj[3]) <= sb4[3] + t->len_eps && fmax(sj[1], sj[3]) >= sb4[1] - t->len_eps) {
                double poly[8];
                poly[0] = sb4[0] - t->len_eps; poly[1] = sb4[1] - t->len_eps;
                poly[2] = sb4[2] + t->len_eps; poly[3] = sb4[1] - t->len_eps;
                poly[4] = sb4[2] + t->len_eps; poly[5] = sb4[3] + t->len_eps;
                poly[6] = sb4[0] - t->len_eps; poly[7] = sb4[3] + t->len_eps;
                if (pvs__ot_segment_meets_polygon(sj, poly, 4)) continue;
            }
        }
        /* quick order: e wholly beyond j's line (seen from the source) puts j in front on every
           line that crosses both; e wholly on the source side puts j behind */
        s0 = jd[0] * e[0] + jd[1] * e[1] + jd[2];
        s1 = jd[0] * e[2] + jd[1] * e[3] + jd[2];
        if (jd[5]) { /* the whole source edge on one side */
            if (s0 >= -tol && s1 >= -tol) continue;       /* e on the source side: j is behind */
            if (!(s0 < -tol && s1 < -tol)) {               /* e crosses j's line: vertex test */
                pvs__ot_depth(t, q, e, sj, &front, &behind);
                if (!front || behind) continue;
            }
        } else {
            pvs__ot_depth(t, q, e, sj, &front, &behind);
            if (!front || behind) continue;
        }
        if (pvs__ot25_umbra(t, jd, s0, s1, h, &um[nu][0], &um[nu][1])) {
            if (um[nu][0] <= 0.0 && um[nu][1] >= 1.0) return 0; /* one umbra covers all of e: hidden whatever the funnel */
            ++nu;
        }
    }
    for (i = 0; i < q->n; ++i) { /* the funnel: the parameters on e of the polygon's lines */
        double u;
        if (pvs__ot_param(q->v[i], e, &u)) { if (u < flo) flo = u; if (u > fhi) fhi = u; }
        else { flo = -DBL_MAX; fhi = DBL_MAX; }
    }
    if (flo < 0.0) flo = 0.0;
    if (fhi > 1.0) fhi = 1.0;
    *f0 = flo; *f1 = fhi;
    *v0 = flo; *v1 = fhi;
    /* the first and the last parameter of [flo, fhi] outside every umbra (touching umbrae join) */
    do {
        changed = 0;
        for (i = 0; i < nu; ++i)
            if (um[i][0] <= *v0 && um[i][1] > *v0) { *v0 = um[i][1]; changed = 1; }
    } while (changed && *v0 < fhi);
    if (*v0 >= fhi) return 0;
    do {
        changed = 0;
        for (i = 0; i < nu; ++i)
            if (um[i][1] >= *v1 && um[i][0] < *v1) { *v1 = um[i][0]; changed = 1; }
    } while (changed && *v1 > *v0);
    return *v1 > *v0;
}

#define PVS__OT25_MAX_SEQ 32

/* Inserts the blocker of occluder k (c-LSS, §7.5.2): out-leaves become in-leaves holding k; at an
   in-leaf the funnel test clips k's top edge by the extended umbrae of the members in front and,
   when a part stays visible, splits the leaf into at most three: the primary funnel (rays through
   the visible part) gets the members and k, the secondary funnels keep the members. */
PVS__STATIC void pvs__ot25_insert(pvs__otree *t, const pvs__otpoly *blocker, uint32_t k) {
    size_t base = t->stack_count;
    const double *sk = t->seg + 4 * (size_t)k;
    double near = pvs__ot25_near(t, sk), top = t->top[k];
    if (!pvs__ot_push(t, 0, blocker)) return;
    while (t->stack_count > base && !t->oom) {
        pvs__otpoly q;
        uint32_t node = t->stack_node[t->stack_count - 1];
        pvs__otnode *nd = t->nodes + node;
        if (pvs__ot25_hidden_below(t, nd, near, top)) { --t->stack_count; continue; } /* k hidden in this subtree */
        if (nd->kind == 0) { pvs__ot_insert_inner(t, t->stack_count - 1, near, top); continue; }
        pvs__ot_pop(t, &q);
        if (nd->kind == PVS__OT_OUT) {
            uint32_t leaf = pvs__ot_refine(t, node, &q);
            if (leaf != PVS__OT_NONE) pvs__ot_set_payload(t, leaf, 0, 0, k);
            pvs__ot25_bound(t, node);
        } else {
            uint32_t first = nd->first, count = nd->count, leaf;
            double f0, f1, v0, v1, cen[3] = {0, 0, 0};
            int i, c;
            if (count >= PVS__OT25_MAX_SEQ) continue; /* a full leaf keeps its members: conservative */
            if (!pvs__ot25_open(t, &q, first, count, k, sk, t->top[k], NULL, &f0, &f1, &v0, &v1)) continue; /* hidden here */
            leaf = pvs__ot_refine(t, node, &q);
            if (leaf == PVS__OT_NONE) break;
            for (i = 0; i < q.n; ++i) for (c = 0; c < 3; ++c) cen[c] += q.v[i][c];
            if (v0 > f0 + 1e-9) { /* lines through k before v0 see only the old members */
                double x[2];
                x[0] = sk[0] + v0 * (sk[2] - sk[0]); x[1] = sk[1] + v0 * (sk[3] - sk[1]);
                /* the primary side (lines crossing k beyond x) has x on the side of k's first end */
                double sgn = pvs__ot_side(cen, sk);
                if (sgn != 0.0) {
                    uint32_t nx = pvs__ot_split_leaf(t, leaf, x, sgn > 0 ? 1.0 : -1.0);
                    if (nx == PVS__OT_NONE) break;
                    leaf = nx;
                }
            }
            if (v1 < f1 - 1e-9) {
                double x[2], sgn;
                x[0] = sk[0] + v1 * (sk[2] - sk[0]); x[1] = sk[1] + v1 * (sk[3] - sk[1]);
                sgn = pvs__ot_side(cen, sk + 2);
                if (sgn != 0.0) {
                    uint32_t nx = pvs__ot_split_leaf(t, leaf, x, sgn > 0 ? 1.0 : -1.0);
                    if (nx == PVS__OT_NONE) break;
                    leaf = nx;
                }
            }
            pvs__ot_set_payload(t, leaf, first, count, k);
            pvs__ot25_bound(t, node);
        }
    }
    t->stack_count = base;
}

/* Read-only c-LSS test of a far edge e (height h) of an object box `box` (umin, vmin, umax, vmax):
   1 when some part of it may be seen through the lines of the blocker. */
PVS__STATIC int pvs__ot25_visible(pvs__otree *t, const pvs__otpoly *blocker, const double *e, double h, const double *box) {
    size_t base = t->stack_count;
    double near = pvs__ot25_near(t, e);
    int vis = 0;
    if (!pvs__ot_push(t, 0, blocker)) return 1;
    while (t->stack_count > base && !vis) {
        uint32_t node = t->stack_node[t->stack_count - 1];
        const pvs__otnode *nd = t->nodes + node;
        if (pvs__ot25_hidden_below(t, nd, near, h)) { --t->stack_count; continue; } /* hidden in this subtree */
        if (t->stack_pend[t->stack_count - 1] != PVS__OT_NONE && !pvs__ot_owed(t, t->stack_count - 1)) { --t->stack_count; continue; }
        if (nd->kind == 0) { vis |= pvs__ot_test_inner(t, t->stack_count - 1, near, h); continue; }
        --t->stack_count; /* the polygon stays readable in its slot until the next push */
        if (nd->kind == PVS__OT_OUT) {
            vis = 1;
        } else {
            double f0, f1, v0, v1;
            if (pvs__ot25_open(t, t->stack + t->stack_count, nd->first, nd->count, PVS__OT_NONE, e, h, box, &f0, &f1, &v0, &v1)) vis = 1;
        }
    }
    t->stack_count = base;
    return vis || t->oom;
}

/* 1 when some part of box bx (umin, vmin, umax, vmax in local coordinates, top) beyond the source
   edge a -> b may be seen through the tree: its top edges as far segments (§7.7). */
PVS__STATIC int pvs__ot25_box_visible(pvs__otree *t, const double *bx, double top, const double a[2], const double b[2], int *any_far) {
    double c4[8], nx = 0.5 * (a[0] + b[0]), ny = 0.5 * (a[1] + b[1]); /* the source edge's outward direction */
    int i, vis = 0, far_edge, order[4];
    c4[0] = bx[0]; c4[1] = bx[1]; c4[2] = bx[2]; c4[3] = bx[1]; c4[4] = bx[2]; c4[5] = bx[3]; c4[6] = bx[0]; c4[7] = bx[3];
    if (any_far) *any_far = 0;
    /* A box taller than the eyes is seen (if at all) along a rising ray, at least as well at the
       point where the ray's 2D line enters the box; no line of this tree enters through the box
       edge that faces the same way as the source edge (edges 0..3: -v, +u, +v, -u). The edge facing
       the source goes first: the likeliest to be seen, and a visible box ends the test. */
    if (fabs(nx) > fabs(ny)) far_edge = nx > 0 ? 1 : 3;
    else far_edge = ny > 0 ? 2 : 0;
    order[0] = (far_edge + 2) & 3; order[1] = (far_edge + 1) & 3; order[2] = (far_edge + 3) & 3;
    order[3] = top > t->eye ? -1 : far_edge;
    for (i = 0; i < 4 && !vis; ++i) {
        int edge = order[i], on, nb, deg, m;
        double sg[4], o[4];
        pvs__otpoly bl[2];
        if (edge < 0) continue;
        sg[0] = c4[2 * edge]; sg[1] = c4[2 * edge + 1]; sg[2] = c4[(2 * edge + 2) & 7]; sg[3] = c4[(2 * edge + 3) & 7];
        if (sg[0] == sg[2] && sg[1] == sg[3]) sg[2] += t->len_eps; /* a box flat on both axes: its corner */
        if (!pvs__ot_clip_segment(b, a, sg, o, &on)) continue;
        if (any_far) *any_far = 1;
        nb = pvs__ot_blockers(a, b, o, on, bl, &deg);
        if (deg) vis = 1;
        for (m = 0; m < nb && !vis; ++m) vis = pvs__ot25_visible(t, &bl[m], o, top, bx);
    }
    return vis;
}

typedef struct pvs__ot25_sweep {
    pvs__otree *t;
    const pvs_visibility_25d_desc *desc;
    const double *all;       /* facades, local, 4 doubles each */
    const double *box;       /* objects, local, 5 doubles each */
    const double *cell;      /* the grown cell, CCW */
    unsigned char *state;    /* facades: 1 + side when handled in this tree; objects: see done */
    unsigned char *done;     /* objects: 0 unknown, 1 visible, 2 never, 3 + side: candidate in this tree */
    const double *a, *b;
    double cx, cy;
    uint32_t side, budget;
    pvs_otree_stats *st;
    const uint32_t *refs;    /* per kD node: item references in its subtree */
    uint32_t node;           /* the node being visited */
    uint32_t test_min;       /* inner nodes with fewer references are not tested */
} pvs__ot25_sweep;

/* The sweep visitor (§7.7): nodes front to back; a node whose box meets the cell is visible; else, if
   it holds at least PVS__OT25_TEST_MIN item references, its box is tested as a virtual occluder (its
   footprint's edges at its top height) and culled when hidden; leaves insert their facades and mark
   their objects for the test after the sweep. */
PVS__STATIC pvs_visit pvs__ot25_visit(void *user, const pvs_box *node_box, float distance, const uint32_t *items, uint32_t item_count) {
    pvs__ot25_sweep *w = (pvs__ot25_sweep *)user;
    pvs__otree *t = w->t;
    const pvs_visibility_25d_desc *d = w->desc;
    double bx[4];
    uint32_t i;
    (void)distance;
    if (t->oom) return PVS_VISIT_STOP;
    bx[0] = (double)node_box->min[0] - w->cx; bx[1] = (double)node_box->min[1] - w->cy;
    bx[2] = (double)node_box->max[0] - w->cx; bx[3] = (double)node_box->max[1] - w->cy;
    /* leaves are not tested: inserting their facades and testing their objects after the sweep
       costs less than the box test (the thesis likewise skips tests of small nodes, §4.12.1) */
    if (!items && w->refs[w->node] >= w->test_min &&
        !(bx[0] <= w->cell[2] && bx[2] >= w->cell[0] && bx[1] <= w->cell[5] && bx[3] >= w->cell[1])) {
        int far;
        if (!pvs__ot25_box_visible(t, bx, (double)node_box->max[2], w->a, w->b, &far)) return PVS_VISIT_SKIP;
        (void)far;
    }
    for (i = 0; i < item_count; ++i) {
        uint32_t it = items[i];
        if (it < d->facade_count) {
            double o[4];
            int on, nb, deg, m;
            pvs__otpoly bl[2];
            const double *sg = w->all + 4 * (size_t)it;
            if (w->state[it] == 1 + w->side) continue; /* already inserted from another leaf */
            w->state[it] = (unsigned char)(1 + w->side);
            if (sg[0] == sg[2] && sg[1] == sg[3]) continue;
            if (pvs__ot_segment_meets_polygon(sg, w->cell, 4)) continue; /* facades in the cell are ignored */
            if (!pvs__ot_clip_segment(w->b, w->a, sg, o, &on)) continue;
            if (t->node_count >= w->budget) { w->st->budget_exceeded = 1; continue; }
            memcpy((double *)t->seg + 4 * (size_t)it, o, sizeof(o));
            ((double *)t->top)[it] = d->facades[5 * (size_t)it + 4];
            pvs__ot25_prepare(t, it);
            nb = pvs__ot_blockers(w->a, w->b, o, on, bl, &deg);
            for (m = 0; m < nb; ++m) pvs__ot25_insert(t, &bl[m], it);
            ++w->st->occluders_inserted;
        } else if (it - d->facade_count < d->object_count) {
            uint32_t ob = it - d->facade_count;
            if (w->done[ob] == 0 || (w->done[ob] >= 3 && w->done[ob] != 3 + w->side)) w->done[ob] = (unsigned char)(3 + w->side);
        }
    }
    return PVS_VISIT_DESCEND;
}

/* The approximate occlusion sweep (§3.2) over the kD-tree, as pvs_kdtree_sweep, telling the visitor
   which node it visits (w->node). */
PVS__STATIC void pvs__ot25_sweep_tree(const pvs_kdtree *t, const pvs_box *source, pvs__kdsweep *heap, pvs__ot25_sweep *w) {
    size_t n = 1;
    int k;
    if (t->bounds.min[0] > t->bounds.max[0]) return;
    heap[0].d2 = pvs__box_distance2(source, &t->bounds);
    heap[0].node = 0;
    heap[0].box = t->bounds;
    while (n) {
        pvs__kdsweep top = heap[0];
        const pvs__kdnode *nd = t->nodes + top.node;
        uint32_t axis = nd->bits & 3u;
        pvs_visit v;
        size_t i, c;
        if (--n) {
            pvs__kdsweep last = heap[n];
            i = 0;
            while ((c = 2 * i + 1) < n) {
                if (c + 1 < n && pvs__kdsweep_before(heap + c + 1, heap + c)) ++c;
                if (!pvs__kdsweep_before(heap + c, &last)) break;
                heap[i] = heap[c];
                i = c;
            }
            heap[i] = last;
        }
        w->node = top.node;
        if (axis == PVS__KD_LEAF) v = pvs__ot25_visit(w, &top.box, 0.0f, nd->u.count ? t->items + (nd->bits >> 2) : NULL, nd->u.count);
        else v = pvs__ot25_visit(w, &top.box, 0.0f, NULL, 0);
        if (v == PVS_VISIT_STOP) break;
        if (v != PVS_VISIT_DESCEND || axis == PVS__KD_LEAF) continue;
        for (k = 0; k < 2; ++k) {
            pvs__kdsweep e;
            e.node = (nd->bits >> 2) + (uint32_t)k;
            e.box = top.box;
            if (k == 0) e.box.max[axis] = nd->u.split;
            else e.box.min[axis] = nd->u.split;
            e.d2 = pvs__box_distance2(source, &e.box);
            i = n++;
            while (i > 0 && pvs__kdsweep_before(&e, heap + (i - 1) / 2)) {
                heap[i] = heap[(i - 1) / 2];
                i = (i - 1) / 2;
            }
            heap[i] = e;
        }
    }
}

PVS_API void pvs_visibility_25d_boxes(const float *facades, uint32_t facade_count, const float *objects, uint32_t object_count,
                                      pvs_box *boxes);
PVS_API pvs_result pvs_visibility_25d(const pvs_visibility_25d_desc *desc, pvs_word *visible_objects, pvs_otree_stats *stats,
                                      pvs_error *err) {
    pvs__otree t;
    pvs_allocator al;
    double cell[8], cx, cy, ext = 1.0, margin;
    double *all = NULL, *top = NULL, *seg = NULL, *box = NULL, *jd = NULL;
    unsigned char *done = NULL, *state = NULL;
    uint32_t *refs = NULL, kd_nodes = 0;
    void *scratch = NULL;
    size_t scratch_size = 0;
    pvs_kdtree *own_tree = NULL;
    const pvs_kdtree *tree;
    uint32_t nf, no, i, k, side;
    pvs_result r = PVS_OK;
    pvs_otree_stats st;
    pvs__ot25_sweep w;
    memset(&st, 0, sizeof(st));
    memset(&t, 0, sizeof(t));
    if (stats) *stats = st;
    if (!desc || !visible_objects || (desc->facade_count && !desc->facades) || (desc->object_count && !desc->objects))
        return pvs__fail(err, PVS_ERROR_INVALID_ARGUMENT, -1, 0, "desc, facades, objects and visible_objects are required");
    nf = desc->facade_count;
    no = desc->object_count;
    if ((uint64_t)nf + no >= 0xffffffffu) return pvs__fail(err, PVS_ERROR_COUNT_OVERFLOW, -1, 0, "too many facades and objects");
    for (i = 0; i < 2; ++i)
        if (!pvs__finite(desc->cell_min[i]) || !pvs__finite(desc->cell_max[i]) || desc->cell_min[i] > desc->cell_max[i])
            return pvs__fail(err, PVS_ERROR_BAD_CELL, -1, 0, "the cell rectangle is not finite or has min > max");
    if (!pvs__finite(desc->cell_top)) return pvs__fail(err, PVS_ERROR_NOT_FINITE, -1, 0, "cell_top is not finite");
    for (i = 0; i < 5 * nf; ++i)
        if (!pvs__finite(desc->facades[i])) return pvs__fail(err, PVS_ERROR_NOT_FINITE, i / 5, 0, "facade %u is not finite", i / 5);
    for (i = 0; i < 5 * no; ++i)
        if (!pvs__finite(desc->objects[i])) return pvs__fail(err, PVS_ERROR_NOT_FINITE, i / 5, 0, "object %u is not finite", i / 5);
    memset(visible_objects, 0, PVS_BITSET_WORDS(no) * sizeof(pvs_word));
    al = desc->allocator;
    t.a = &al;
    tree = desc->tree;
    if (!tree) { /* a kD-tree over the facades and objects for the sweep */
        pvs_kdtree_desc kd;
        pvs_box *boxes = (pvs_box *)pvs__alloc_array(&al, (size_t)nf + no + 1, sizeof(pvs_box));
        if (!boxes) { r = pvs__fail(err, PVS_ERROR_OUT_OF_MEMORY, -1, 0, "2.5D boxes"); goto done; }
        pvs_visibility_25d_boxes(desc->facades, nf, desc->objects, no, boxes);
        memset(&kd, 0, sizeof(kd));
        kd.boxes = boxes;
        kd.count = nf + no;
        kd.allocator = al;
        r = pvs_kdtree_create(&kd, &own_tree, err);
        pvs__free_array(&al, boxes, (size_t)nf + no + 1, sizeof(pvs_box));
        if (r != PVS_OK) goto done;
        tree = own_tree;
    }
    all = (double *)pvs__alloc_array(&al, 4 * (size_t)nf + 4, sizeof(double));
    seg = (double *)pvs__alloc_array(&al, 4 * (size_t)nf + 4, sizeof(double));
    top = (double *)pvs__alloc_array(&al, (size_t)nf + 1, sizeof(double));
    jd = (double *)pvs__alloc_array(&al, PVS__OT25_JD * ((size_t)nf + 1), sizeof(double));
    box = (double *)pvs__alloc_array(&al, 5 * (size_t)no + 5, sizeof(double));
    done = (unsigned char *)pvs__alloc_array(&al, (size_t)no + 1, 1);
    state = (unsigned char *)pvs__alloc_array(&al, (size_t)nf + 1, 1);
    scratch_size = pvs_kdtree_sweep_scratch_size(tree);
    scratch = pvs__alloc(&al, scratch_size, 16);
    kd_nodes = tree->node_count;
    refs = (uint32_t *)pvs__alloc_array(&al, (size_t)kd_nodes + 1, sizeof(uint32_t));
    if (!all || !seg || !top || !jd || !box || !done || !state || !scratch || !refs) { r = pvs__fail(err, PVS_ERROR_OUT_OF_MEMORY, -1, 0, "2.5D visibility arrays"); goto done; }
    memset(state, 0, (size_t)nf + 1);
    cx = 0.5 * ((double)desc->cell_min[0] + desc->cell_max[0]);
    cy = 0.5 * ((double)desc->cell_min[1] + desc->cell_max[1]);
    for (i = 0; i < 4 * nf; ++i) {
        all[i] = (double)desc->facades[5 * (i / 4) + (i % 4)] - (i & 1 ? cy : cx);
        if (fabs(all[i]) > ext) ext = fabs(all[i]);
    }
    for (i = 0; i < no; ++i) {
        for (k = 0; k < 4; ++k) box[5 * i + k] = (double)desc->objects[5 * i + k] - (k & 1 ? cy : cx);
        box[5 * i + 4] = desc->objects[5 * i + 4];
    }
    /* grow the cell a little: a larger cell sees more (conservative) and is never degenerate */
    margin = 1e-6 * ext + 1e-4;
    {
        double hx = 0.5 * ((double)desc->cell_max[0] - desc->cell_min[0]) + margin;
        double hy = 0.5 * ((double)desc->cell_max[1] - desc->cell_min[1]) + margin;
        cell[0] = -hx; cell[1] = -hy; cell[2] = hx; cell[3] = -hy; cell[4] = hx; cell[5] = hy; cell[6] = -hx; cell[7] = hy;
    }
    t.len_eps = 1e-9 * ext;
    t.eye = (double)desc->cell_top + margin;
    t.top = top;
    t.seg = seg;
    t.jd = jd;
    /* objects meeting the cell's rectangle are visible; empty ones never */
    for (i = 0; i < no; ++i) {
        const double *bb = box + 5 * i;
        done[i] = 0;
        if (bb[0] > bb[2] || bb[1] > bb[3]) { done[i] = 2; continue; }
        if (bb[0] <= cell[2] && bb[2] >= cell[0] && bb[1] <= cell[5] && bb[3] >= cell[1]) {
            done[i] = 1;
            pvs_bitset_set(visible_objects, i);
        }
    }
    memset(&w, 0, sizeof(w));
    w.t = &t;
    w.desc = desc;
    w.all = all;
    w.box = box;
    w.cell = cell;
    w.state = state;
    w.done = done;
    w.cx = cx;
    w.cy = cy;
    w.budget = desc->node_budget ? desc->node_budget : 1u << 18;
    w.st = &st;
    w.refs = refs;
    w.test_min = PVS__OT25_TEST_MIN;
    for (i = tree->node_count; i-- > 0;) { /* children follow their parent */
        const pvs__kdnode *kn = tree->nodes + i;
        if ((kn->bits & 3u) == PVS__KD_LEAF) refs[i] = kn->u.count;
        else {
            uint32_t c = kn->bits >> 2;
            refs[i] = c + 1 < tree->node_count && c > i ? refs[c] + refs[c + 1] : 0xffffffffu;
        }
    }
    /* one tree per top edge (§7.1), holding the lines that leave the cell through it */
    t.corners = cell;
    for (side = 0; side < 4 && !t.oom; ++side) {
        const double *a = cell + 2 * ((side + 1) & 3), *b = cell + 2 * side;
        pvs_box src;
        uint32_t live = 0;
        for (i = 0; i < no; ++i) live += done[i] == 0 || done[i] >= 3;
        if (!live) break;
        t.sa[0] = a[0]; t.sa[1] = a[1]; t.sb[0] = b[0]; t.sb[1] = b[1];
        if (!pvs__ot_reset(&t)) break;
        {   /* the root region: the lines crossing the source edge, bounded by the planes of its end points
               (every blocker's edges on them are then marked, §4.10.1, instead of adding the two planes
               again in every branch); the other sides hold lines that miss the edge, never asked about */
            double m[2], m2[2], l[3], sa_, sb_;
            uint32_t pos;
            m[0] = 0.5 * (a[0] + b[0]); m[1] = 0.5 * (a[1] + b[1]);
            m2[0] = 2.0 * m[0]; m2[1] = 2.0 * m[1]; /* the cell is centred at the origin: m points outward */
            pvs__ot_line(m, m2, l);
            sa_ = pvs__ot_side(l, a);
            sb_ = pvs__ot_side(l, b);
            pos = pvs__ot_split_leaf(&t, 0, a, sa_ > 0 ? 1.0 : -1.0);
            if (pos != PVS__OT_NONE) pvs__ot_split_leaf(&t, pos, b, sb_ > 0 ? 1.0 : -1.0);
            t.nodes[0].parent = PVS__OT_NONE;
            if (t.oom) break;
        }
        w.a = a;
        w.b = b;
        w.side = side;
        src.min[0] = (float)(cx + cell[0]); src.min[1] = (float)(cy + cell[1]); src.min[2] = desc->cell_top;
        src.max[0] = (float)(cx + cell[4]); src.max[1] = (float)(cy + cell[5]); src.max[2] = desc->cell_top;
        pvs__ot25_sweep_tree(tree, &src, (pvs__kdsweep *)scratch, &w);
        if (t.node_count > st.nodes) st.nodes = (uint32_t)t.node_count;
        if (t.oom) break;
        /* objects of the visible leaves, after the sweep (§7.7) */
        for (i = 0; i < no; ++i) {
            if (done[i] != 3 + side) continue;
            if (pvs__ot25_box_visible(&t, box + 5 * i, box[5 * i + 4], a, b, NULL)) {
                done[i] = 1;
                pvs_bitset_set(visible_objects, i);
            } else {
                done[i] = 0;
            }
        }
    }
    if (t.oom) { r = pvs__fail(err, PVS_ERROR_OUT_OF_MEMORY, -1, 0, "occlusion tree nodes"); goto done; }
    if (stats) *stats = st;
    pvs__ok(err);
done:
    pvs__ot_free(&t);
    pvs_kdtree_destroy(own_tree);
    pvs__free(&al, scratch, scratch_size, 16);
    pvs__free_array(&al, refs, (size_t)kd_nodes + 1, sizeof(uint32_t));
    pvs__free_array(&al, all, 4 * (size_t)nf + 4, sizeof(double));
    pvs__free_array(&al, seg, 4 * (size_t)nf + 4, sizeof(double));
    pvs__free_array(&al, top, (size_t)nf + 1, sizeof(double));
    pvs__free_array(&al, jd, PVS__OT25_JD * ((size_t)nf + 1), sizeof(double));
    pvs__free_array(&al, box, 5 * (size_t)no + 5, sizeof(double));
    pvs__free_array(&al, done, (size_t)no + 1, 1);
    pvs__free_array(&al, state, (size_t)nf + 1, 1);
    return r;
}

PVS_API void pvs_visibility_25d_boxes(const float *facades, uint32_t facade_count, const float *objects, uint32_t object_count,
                                      pvs_box *boxes) {
    uint32_t i;
    float low = FLT_MAX;
    for (i = 0; i < facade_count; ++i) if (facades[5 * i + 4] < low) low = facades[5 * i + 4];
    for (i = 0; i < object_count; ++i) if (objects[5 * i + 4] < low) low = objects[5 * i + 4];
    for (i = 0; i < facade_count + object_count; ++i) {
        const float *f = i < facade_count ? facades + 5 * (size_t)i : objects + 5 * (size_t)(i - facade_count);
        pvs_box *b = boxes + i;
        if (i < facade_count) {
            b->min[0] = f[0] < f[2] ? f[0] : f[2]; b->max[0] = f[0] < f[2] ? f[2] : f[0];
            b->min[1] = f[1] < f[3] ? f[1] : f[3]; b->max[1] = f[1] < f[3] ? f[3] : f[1];
        } else {
            b->min[0] = f[0]; b->max[0] = f[2]; b->min[1] = f[1]; b->max[1] = f[3]; /* empty stays empty */
        }
        b->min[2] = low < f[4] ? low : f[4];
        b->max[2] = f[4];
    }
}

/* ---- from-point culling: the shadow-volume occlusion tree (ch. 4) ---- */

/* The tree of §4.7 (Chin and Feiner's SVBSP, App. C.1.4) in eye space: every inner node is a plane
   through the eye (unit normal, child[1] on the positive side), built from an occluder edge; an
   in-leaf keeps the fragment of the occluder that blocks its pyramid of rays. Every polygon edge
   carries the unit normal of the plane through the eye it lies in (the polygon on the positive
   side) and a mark (§4.10.1): the edge lies in a plane already on the path, so the e-OT of an
   out-leaf is made of the unmarked edges only.

   Conservative rounding. An in-leaf's region is the intersection of exact planes (stored doubles)
   built from the occluder's own edges or from planes on the path, so every ray in it meets the
   occluder polygon: insertion may drop slivers thinner than its tolerance (less occlusion) but never
   claims more. Tests widen: a box goes down every side it reaches within `tol` (1e-10 of the
   eye-relative scene size, far above the error of a unit-normal dot product), is "behind" a fragment
   only beyond its tolerance, and is separated from a fragment's pyramid only by a gap above it.
   Every box test evaluates a plane at the box corner the normal's signs pick, with the same
   operations for every box: the result is monotone in the box, so a child is never found more
   visible than its parent would be hidden; that makes hierarchy updating exact (§4.11.4). */

#define PVS__SV_MAXV 16
#define PVS__SV_STACK 256
#define PVS__SV_I 0u   /* visibility states (Table 3.1): invisible, visible, partly visible */
#define PVS__SV_V 1u
#define PVS__SV_P 2u
#define PVS__SV_TRIANGLE 0xffffffffu

typedef struct pvs__svpoly {
    int n;
    double v[PVS__SV_MAXV][3];   /* vertices, eye at the origin */
    double e[PVS__SV_MAXV][3];   /* edge v[i] -> v[i + 1]: unit normal of its plane through the eye */
    unsigned char mark[PVS__SV_MAXV];
} pvs__svpoly;

typedef struct pvs__svnode {
    double n[3];
    uint32_t kind;      /* 0 inner, PVS__OT_OUT, PVS__OT_IN */
    uint32_t child[2];  /* [0] negative side, [1] positive side */
    uint32_t frag;      /* in-leaf: its fragment */
} pvs__svnode;

/* A fragment: the occluder's plane (n.x + d > 0 on the eye's side) and the polygon's vertices f with
   the inward normals m of the pyramid faces (0, f_i, f_i+1), for the box / fragment test. */
typedef struct pvs__svfrag {
    double plane[4];
    double tol;          /* depth and separation tolerance for this fragment */
    uint32_t first, count;
} pvs__svfrag;
typedef struct pvs__svvert {
    double f[3], m[3];
} pvs__svvert;

/* An occluder candidate: score (area-angle, later distance for the order), triangle or volume face. */
typedef struct pvs__svsel {
    double key;
    uint32_t a, b;       /* b == PVS__SV_TRIANGLE: triangle a; else face b of scene occluder a */
} pvs__svsel;

struct pvs_otree {
    pvs_allocator allocator;
    uint32_t flags, max_occluders, node_budget, frag_budget, vert_budget;
    float aspect;
    uint32_t max_objects, max_triangles, max_kd_nodes;
    size_t sweep_size;
    /* the tree of the current frame */
    pvs__svnode *nodes;
    uint32_t node_count;
    pvs__svfrag *frags;
    uint32_t frag_count;
    pvs__svvert *verts;
    uint32_t vert_count;
    pvs__svpoly *stack;            /* PVS__SV_STACK insertion work items */
    uint32_t *stack_node;
    uint32_t *tstack;              /* node_budget + 2: the test traversal */
    /* occluder selection (§4.5) */
    pvs__svsel *sel;               /* max_occluders: min-heap on key while selecting */
    uint32_t sel_count;
    uint32_t *prev;                /* max_occluders triangles chosen at the end of the last frame */
    uint32_t prev_count;
    int have_prev;
    void *sweep;
    pvs_word *tri_seen;
    uint32_t *obj_first, *obj_tris;/* each object's triangle range */
    /* the kD nodes' visibility and frame of the last visit (§4.11.4) */
    uint8_t *kd_vis;
    uint32_t *kd_frame;
    uint32_t frame;
    const pvs_scene *last_scene;
    const pvs_scene *ranges_scene; /* the scene obj_first / obj_tris describe */
    uint8_t *obj_flag;             /* per object this frame: 1 in a visible leaf, 2 in a partly visible
                                      leaf, 4 in a leaf within the selection distance */
    uint32_t *touched;
    uint32_t touched_count;
    /* this frame */
    const pvs_scene *s;
    double eye[3], fw[3], near_d;
    double fr[5][4];               /* frustum planes n.x + d >= 0 inside: near, then the four sides */
    double tol, lambda;
    pvs_otree_frame info;
    pvs_cull_stats st;
};

PVS__STATIC double pvs__sv_dot(const double a[3], const double b[3]) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
PVS__STATIC void pvs__sv_cross(const double a[3], const double b[3], double c[3]) {
    c[0] = a[1] * b[2] - a[2] * b[1];
    c[1] = a[2] * b[0] - a[0] * b[2];
    c[2] = a[0] * b[1] - a[1] * b[0];
}
PVS__STATIC double pvs__sv_unit(double v[3]) {
    double len = sqrt(pvs__sv_dot(v, v));
    if (len > 0.0) { v[0] /= len; v[1] /= len; v[2] /= len; }
    return len;
}
/* Largest / smallest of n.x over the box [lo, hi] (eye-relative): the corner the signs pick, always
   the same operations, so the value is monotone in the box. */
PVS__STATIC double pvs__sv_hi(const double n[3], const double lo[3], const double hi[3]) {
    return (n[0] * (n[0] >= 0.0 ? hi[0] : lo[0]) + n[1] * (n[1] >= 0.0 ? hi[1] : lo[1])) + n[2] * (n[2] >= 0.0 ? hi[2] : lo[2]);
}
PVS__STATIC double pvs__sv_lo(const double n[3], const double lo[3], const double hi[3]) {
    return (n[0] * (n[0] >= 0.0 ? lo[0] : hi[0]) + n[1] * (n[1] >= 0.0 ? lo[1] : hi[1])) + n[2] * (n[2] >= 0.0 ? lo[2] : hi[2]);
}

/* Keeps the part of `in` where n.x + d >= 0. The new edge lies in the plane `en` (a plane through
   the eye; NULL: the plane through the eye and the new edge's end points) with mark `mark`.
   Returns the vertex count (0 = nothing left, -1 = too many vertices). */
PVS__STATIC int pvs__sv_clip(const pvs__svpoly *in, const double n[3], double d, const double *en, int mark, pvs__svpoly *out) {
    double s[PVS__SV_MAXV];
    int i, m = 0, any = 0, newedge = -1;
    for (i = 0; i < in->n; ++i) {
        s[i] = pvs__sv_dot(n, in->v[i]) + d;
        if (s[i] > 0.0) any = 1;
    }
    if (!any) { out->n = 0; return 0; }
    for (i = 0; i < in->n; ++i) {
        int j = (i + 1) % in->n, k;
        int ii = s[i] >= 0.0, ij = s[j] >= 0.0;
        if (ii) {
            if (m >= PVS__SV_MAXV) return out->n = 0, -1;
            memcpy(out->v[m], in->v[i], sizeof(out->v[m]));
            memcpy(out->e[m], in->e[i], sizeof(out->e[m]));
            out->mark[m] = in->mark[i];
            ++m;
        }
        if (ii != ij) {
            double t = s[i] / (s[i] - s[j]);
            if (m >= PVS__SV_MAXV) return out->n = 0, -1;
            for (k = 0; k < 3; ++k) out->v[m][k] = in->v[i][k] + t * (in->v[j][k] - in->v[i][k]);
            if (ii) { /* leaving: the new edge starts here */
                if (en) memcpy(out->e[m], en, sizeof(out->e[m]));
                newedge = m;
                out->mark[m] = (unsigned char)mark;
            } else {
                memcpy(out->e[m], in->e[i], sizeof(out->e[m]));
                out->mark[m] = in->mark[i];
            }
            ++m;
        }
    }
    out->n = m;
    if (m < 3) return out->n = 0, 0;
    if (!en && newedge >= 0) { /* the plane through the eye and the new edge, the polygon on its positive side */
        double c[3] = {0, 0, 0}, *e = out->e[newedge];
        int k;
        pvs__sv_cross(out->v[newedge], out->v[(newedge + 1) % m], e);
        if (!(pvs__sv_unit(e) > 0.0)) return out->n = 0, 0;
        for (i = 0; i < m; ++i) for (k = 0; k < 3; ++k) c[k] += out->v[i][k];
        if (pvs__sv_dot(e, c) < 0.0) { e[0] = -e[0]; e[1] = -e[1]; e[2] = -e[2]; }
    }
    return m;
}

PVS__STATIC int pvs__sv_same(const double a[3], const double b[3]) { return a[0] == b[0] && a[1] == b[1] && a[2] == b[2]; }

/* Builds the eye-space polygon of an occluder (n world points, planar, convex) with its plane and
   edge planes, clipped to the near plane and the frustum's sides (less occluder: conservative).
   Returns 0 when nothing usable is left (seen edge-on, behind the eye, outside the frustum). */
PVS__STATIC int pvs__sv_polygon(pvs_otree *o, const float *const *p, int n, pvs__svpoly *q, double plane[4]) {
    pvs__svpoly a, b;
    double c[3] = {0, 0, 0}, nrm[3] = {0, 0, 0}, len, size = 0.0;
    int i, k;
    a.n = n;
    for (i = 0; i < n; ++i)
        for (k = 0; k < 3; ++k) {
            a.v[i][k] = (double)p[i][k] - o->eye[k];
            c[k] += a.v[i][k] / n;
            if (fabs(a.v[i][k]) > size) size = fabs(a.v[i][k]);
        }
    for (i = 0; i < n; ++i) { /* Newell's normal */
        const double *u = a.v[i], *w = a.v[(i + 1) % n];
        nrm[0] += (u[1] - w[1]) * (u[2] + w[2]);
        nrm[1] += (u[2] - w[2]) * (u[0] + w[0]);
        nrm[2] += (u[0] - w[0]) * (u[1] + w[1]);
    }
    len = pvs__sv_unit(nrm);
    if (!(len > 1e-12 * size * size)) return 0;                    /* no area */
    plane[0] = nrm[0]; plane[1] = nrm[1]; plane[2] = nrm[2];
    plane[3] = -pvs__sv_dot(nrm, c);
    if (plane[3] < 0.0) for (k = 0; k < 4; ++k) plane[k] = -plane[k]; /* the eye on the positive side */
    if (!(plane[3] > 1e-9 * size)) return 0;                        /* the eye (nearly) in its plane */
    for (i = 0; i < n; ++i) {
        double *e = a.e[i];
        pvs__sv_cross(a.v[i], a.v[(i + 1) % n], e);
        if (!(pvs__sv_unit(e) > 1e-12 * size * size)) return 0;     /* an edge pointing at the eye */
        if (pvs__sv_dot(e, c) < 0.0) { e[0] = -e[0]; e[1] = -e[1]; e[2] = -e[2]; }
        if (!(pvs__sv_dot(e, c) > 1e-9 * size)) return 0;
        a.mark[i] = 0;
    }
    if (pvs__sv_clip(&a, o->fr[0], o->fr[0][3], NULL, 0, &b) < 3) return 0;
    for (k = 1; k < 5; ++k) {
        if (pvs__sv_clip(&b, o->fr[k], 0.0, o->fr[k], 0, &a) < 3) return 0;
        b = a;
    }
    *q = b;
    return 1;
}

/* Stores q as a new fragment of the occluder with `plane`; PVS__OT_NONE when the pools are full. */
PVS__STATIC uint32_t pvs__sv_fragment(pvs_otree *o, const pvs__svpoly *q, const double plane[4]) {
    pvs__svfrag *f;
    double size = 0.0;
    int i, k;
    if (o->frag_count >= o->frag_budget || o->vert_count + (uint32_t)q->n > o->vert_budget) return PVS__OT_NONE;
    f = o->frags + o->frag_count;
    memcpy(f->plane, plane, sizeof(f->plane));
    f->first = o->vert_count;
    f->count = (uint32_t)q->n;
    for (i = 0; i < q->n; ++i) {
        pvs__svvert *v = o->verts + f->first + i;
        memcpy(v->f, q->v[i], sizeof(v->f));
        pvs__sv_cross(q->v[i], q->v[(i + 1) % q->n], v->m);
        pvs__sv_unit(v->m);
        if (pvs__sv_dot(v->m, q->v[(i + 2) % q->n]) < 0.0) for (k = 0; k < 3; ++k) v->m[k] = -v->m[k];
        for (k = 0; k < 3; ++k) if (fabs(q->v[i][k]) > size) size = fabs(q->v[i][k]);
    }
    f->tol = 1e-10 * (o->tol * 1e10 + 3.0 * size + fabs(plane[3]));
    o->vert_count += (uint32_t)q->n;
    return o->frag_count++;
}

/* Turns leaf `node` into the chain of q's unmarked edges (the e-OT, §3.3.3, §4.10.1); the sides away
   from q keep the leaf's kind and fragment. Returns the node whose region is q's pyramid, or
   PVS__OT_NONE when the node budget is spent (the leaf is then unchanged). */
PVS__STATIC uint32_t pvs__sv_refine(pvs_otree *o, uint32_t node, const pvs__svpoly *q) {
    uint32_t need = 0;
    int i;
    for (i = 0; i < q->n; ++i) need += !q->mark[i];
    if (o->node_count + 2 * need > o->node_budget) return PVS__OT_NONE;
    for (i = 0; i < q->n; ++i) {
        pvs__svnode old = o->nodes[node];
        uint32_t out = o->node_count++, in = o->node_count++;
        if (q->mark[i]) { o->node_count -= 2; continue; }
        o->nodes[out] = old;
        o->nodes[in] = old;
        memcpy(o->nodes[node].n, q->e[i], sizeof(o->nodes[node].n));
        o->nodes[node].kind = 0;
        o->nodes[node].child[0] = out;
        o->nodes[node].child[1] = in;
        node = in;
    }
    return node;
}

/* Merges occluder polygon q (plane `plane`) into the tree (§3.3.3, App. C.1.4): filtered down with
   splitting and edge marking; out-leaves become its e-OT; at an in-leaf it replaces the stored
   fragment where it lies in front (a late nearer occluder of the approximate sweep), split along the
   stored occluder's plane when it crosses it. */
PVS__STATIC void pvs__sv_insert(pvs_otree *o, const pvs__svpoly *poly, const double plane[4]) {
    uint32_t sp = 0;
    o->stack[0] = *poly;
    o->stack_node[0] = 0;
    sp = 1;
    while (sp) {
        pvs__svpoly *q = o->stack + --sp, part;
        uint32_t node = o->stack_node[sp];
        pvs__svnode *nd = o->nodes + node;
        int i;
        if (nd->kind == 0) {
            double lo = DBL_MAX, hi = -DBL_MAX, ins = 1e-12 * o->tol * 1e10;
            for (i = 0; i < q->n; ++i) {
                double d = pvs__sv_dot(nd->n, q->v[i]);
                if (d < lo) lo = d;
                if (d > hi) hi = d;
            }
            if (lo >= -ins || hi <= ins) { /* one side; its edges lying in this plane (same side) are marked */
                int side = lo >= -ins ? 1 : 0;
                for (i = 0; i < q->n; ++i)
                    if (side ? pvs__sv_same(q->e[i], nd->n)
                             : (q->e[i][0] == -nd->n[0] && q->e[i][1] == -nd->n[1] && q->e[i][2] == -nd->n[2]))
                        q->mark[i] = 1;
                o->stack_node[sp++] = nd->child[side]; /* q stays in place */
            } else {
                double neg[3];
                uint32_t c0 = nd->child[0], c1 = nd->child[1];
                int r1, r0;
                pvs__svpoly qq = *q;
                neg[0] = -nd->n[0]; neg[1] = -nd->n[1]; neg[2] = -nd->n[2];
                r1 = pvs__sv_clip(&qq, nd->n, 0.0, nd->n, 1, &part);
                if (r1 < 0) o->info.budget_exceeded = 1;
                if (r1 >= 3) { o->stack[sp] = part; o->stack_node[sp++] = c1; }
                r0 = pvs__sv_clip(&qq, neg, 0.0, neg, 1, &part);
                if (r0 < 0) o->info.budget_exceeded = 1;
                if (r0 >= 3) {
                    if (sp >= PVS__SV_STACK) { o->info.budget_exceeded = 1; continue; }
                    o->stack[sp] = part; o->stack_node[sp++] = c0;
                }
            }
            if (sp >= PVS__SV_STACK - 1) { /* no room for the next split: drop the deepest work (conservative) */
                o->info.budget_exceeded = 1;
                --sp;
            }
        } else {
            const pvs__svpoly *use = q;
            uint32_t leaf, fr;
            if (nd->kind == PVS__OT_IN) {
                const pvs__svfrag *f = o->frags + nd->frag;
                double smin = DBL_MAX, smax = -DBL_MAX;
                for (i = 0; i < q->n; ++i) {
                    double s = pvs__sv_dot(f->plane, q->v[i]) + f->plane[3];
                    if (s < smin) smin = s;
                    if (s > smax) smax = s;
                }
                if (smax <= f->tol) continue;  /* behind the stored fragment (or in its plane): hidden here */
                if (smin < -f->tol) {          /* crossing: keep the part in front */
                    if (pvs__sv_clip(q, f->plane, f->plane[3], NULL, 0, &part) < 3) continue;
                    use = &part;
                }
            }
            fr = pvs__sv_fragment(o, use, plane);
            if (fr == PVS__OT_NONE) { o->info.budget_exceeded = 1; continue; }
            leaf = pvs__sv_refine(o, node, use);
            if (leaf == PVS__OT_NONE) { o->info.budget_exceeded = 1; --o->frag_count; o->vert_count -= (uint32_t)use->n; continue; }
            o->nodes[leaf].kind = PVS__OT_IN;
            o->nodes[leaf].frag = fr;
        }
    }
}

/* Box [lo, hi] (eye-relative) against fragment f at an in-leaf (§4.10.2): invisible when wholly
   behind the occluder's plane or (unless PLANE_ONLY) separated from the pyramid eye + fragment, the
   only place where a box can be seen through this leaf (exact box / fragment test, "E"); visible
   when wholly in front; partly visible otherwise. */
PVS__STATIC uint32_t pvs__sv_leaf_test(const pvs_otree *o, const pvs__svfrag *f, const double lo[3], const double hi[3]) {
    const pvs__svvert *v = o->verts + f->first;
    double smin = pvs__sv_lo(f->plane, lo, hi) + f->plane[3], smax = pvs__sv_hi(f->plane, lo, hi) + f->plane[3], t = f->tol;
    uint32_t i, j;
    int k;
    if (smax < -t) return PVS__SV_I;
    if (!(o->flags & PVS_OTREE_PLANE_ONLY)) {
        /* separating axes: the box's axes, the pyramid's side faces, its base, the edge pairs */
        for (k = 0; k < 3; ++k) {
            double plo = 0.0, phi = 0.0;
            for (i = 0; i < f->count; ++i) {
                if (v[i].f[k] < plo) plo = v[i].f[k];
                if (v[i].f[k] > phi) phi = v[i].f[k];
            }
            if (hi[k] < plo - t || lo[k] > phi + t) return PVS__SV_I;
        }
        for (i = 0; i < f->count; ++i) { /* the pyramid's extent is taken over its points: valid for any axis */
            double plo = 0.0, phi = 0.0, bh = pvs__sv_hi(v[i].m, lo, hi);
            if (bh < -t) {
                for (j = 0; j < f->count; ++j) {
                    double d = pvs__sv_dot(v[i].m, v[j].f);
                    if (d < plo) plo = d;
                }
                if (bh < plo - t) return PVS__SV_I;
            } else {
                for (j = 0; j < f->count; ++j) {
                    double d = pvs__sv_dot(v[i].m, v[j].f);
                    if (d > phi) phi = d;
                }
                if (pvs__sv_lo(v[i].m, lo, hi) > phi + t) return PVS__SV_I;
            }
        }
        {   /* the base's plane: the pyramid spans from the eye (d) to its base (about 0) */
            double plo = f->plane[3], phi = f->plane[3];
            for (i = 0; i < f->count; ++i) {
                double d = pvs__sv_dot(f->plane, v[i].f) + f->plane[3];
                if (d < plo) plo = d;
                if (d > phi) phi = d;
            }
            if (smin > phi + t || smax < plo - t) return PVS__SV_I;
        }
        for (k = 0; k < 3; ++k)
            for (i = 0; i < 2 * f->count; ++i) {
                double edge[3], ax[3], plo = 0.0, phi = 0.0, len;
                uint32_t m;
                if (i < f->count) memcpy(edge, v[i].f, sizeof(edge));
                else {
                    const double *p0 = v[i - f->count].f, *p1 = v[(i - f->count + 1) % f->count].f;
                    edge[0] = p1[0] - p0[0]; edge[1] = p1[1] - p0[1]; edge[2] = p1[2] - p0[2];
                }
                ax[k] = 0.0;
                ax[(k + 1) % 3] = -edge[(k + 2) % 3];
                ax[(k + 2) % 3] = edge[(k + 1) % 3];
                len = pvs__sv_unit(ax);
                if (!(len > 1e-12 * (fabs(edge[0]) + fabs(edge[1]) + fabs(edge[2])))) continue;
                for (m = 0; m < f->count; ++m) {
                    double d = pvs__sv_dot(ax, v[m].f);
                    if (d < plo) plo = d;
                    if (d > phi) phi = d;
                }
                if (pvs__sv_hi(ax, lo, hi) < plo - t || pvs__sv_lo(ax, lo, hi) > phi + t) return PVS__SV_I;
            }
    }
    return smin > t ? PVS__SV_V : PVS__SV_P;
}

/* The conservative visibility of box [lo, hi] in the tree (§4.10.2): descends, without splitting,
   every side the box reaches; combines the leaves by Table 3.1 and stops at the first partly
   visible result. */
PVS__STATIC uint32_t pvs__sv_tree_test(const pvs_otree *o, const double lo[3], const double hi[3]) {
    uint32_t sp = 1, *stk = o->tstack;
    int vis = 0, inv = 0;
    stk[0] = 0;
    while (sp) {
        const pvs__svnode *nd = o->nodes + stk[--sp];
        if (nd->kind == 0) {
            if (pvs__sv_hi(nd->n, lo, hi) > -o->tol) stk[sp++] = nd->child[1];
            if (pvs__sv_lo(nd->n, lo, hi) < o->tol) stk[sp++] = nd->child[0];
        } else if (nd->kind == PVS__OT_OUT) {
            vis = 1;
        } else {
            uint32_t r = pvs__sv_leaf_test(o, o->frags + nd->frag, lo, hi);
            if (r == PVS__SV_P) return PVS__SV_P;
            if (r == PVS__SV_V) vis = 1; else inv = 1;
        }
        if (vis && inv) return PVS__SV_P;
    }
    return vis ? PVS__SV_V : PVS__SV_I;
}

/* A box's visibility: frustum culling first (outside any plane: invisible; crossing one: at most
   partly visible), then the tree. */
PVS__STATIC uint32_t pvs__sv_box_test(pvs_otree *o, const pvs_box *b) {
    double lo[3], hi[3];
    int k, cross = 0;
    uint32_t r;
    for (k = 0; k < 3; ++k) {
        lo[k] = (double)b->min[k] - o->eye[k];
        hi[k] = (double)b->max[k] - o->eye[k];
    }
    for (k = 0; k < 5; ++k) {
        if (pvs__sv_hi(o->fr[k], lo, hi) + o->fr[k][3] < -o->tol) return PVS__SV_I;
        if (pvs__sv_lo(o->fr[k], lo, hi) + o->fr[k][3] < o->tol) cross = 1;
    }
    r = pvs__sv_tree_test(o, lo, hi);
    return r == PVS__SV_I ? r : cross ? PVS__SV_P : r;
}

/* ---- occluder selection (§4.5) ---- */

/* Keeps the best max_occluders candidates in a min-heap on key. */
PVS__STATIC void pvs__sv_offer(pvs_otree *o, uint32_t k, double key, uint32_t a, uint32_t b) {
    pvs__svsel *h = o->sel, e;
    uint32_t i, c, n;
    e.key = key; e.a = a; e.b = b;
    if (o->sel_count < k) {
        i = o->sel_count++;
        while (i > 0 && h[(i - 1) / 2].key > key) { h[i] = h[(i - 1) / 2]; i = (i - 1) / 2; }
        h[i] = e;
        return;
    }
    if (!k || !(key > h[0].key)) return;
    n = o->sel_count;
    i = 0;
    while ((c = 2 * i + 1) < n) {
        if (c + 1 < n && h[c + 1].key < h[c].key) ++c;
        if (!(h[c].key < key)) break;
        h[i] = h[c];
        i = c;
    }
    h[i] = e;
}

/* The world points of candidate (a, b): a triangle or a face of a BOX / wall of an EXTRUSION occluder. */
PVS__STATIC int pvs__sv_points(const pvs_scene *s, uint32_t a, uint32_t b, float q[4][3], const float *p[4]) {
    int k, n;
    if (b == PVS__SV_TRIANGLE) {
        for (k = 0; k < 3; ++k) p[k] = s->positions + 3 * (size_t)s->indices[3 * (size_t)a + k];
        return 3;
    } else {
        const pvs_occluder_desc *oc = s->occluders + a;
        if (oc->kind == PVS_OCCLUDER_BOX) {
            static const uint8_t f[6][4] = {{0, 2, 6, 4}, {1, 5, 7, 3}, {0, 4, 5, 1}, {2, 3, 7, 6}, {0, 1, 3, 2}, {4, 6, 7, 5}};
            for (n = 0; n < 4; ++n)
                for (k = 0; k < 3; ++k) q[n][k] = (f[b][n] >> k) & 1u ? oc->box.max[k] : oc->box.min[k];
        } else {
            int u, v, up = (int)s->up_axis;
            const float *f0 = oc->footprint + 2 * b, *f1 = oc->footprint + 2 * ((b + 1) % oc->footprint_count);
            pvs__ground_axes(s->up_axis, &u, &v);
            q[0][u] = f0[0]; q[0][v] = f0[1]; q[0][up] = oc->base;
            q[1][u] = f1[0]; q[1][v] = f1[1]; q[1][up] = oc->base;
            q[2][u] = f1[0]; q[2][v] = f1[1]; q[2][up] = oc->top;
            q[3][u] = f0[0]; q[3][v] = f0[1]; q[3][up] = oc->top;
        }
        for (n = 0; n < 4; ++n) p[n] = q[n];
        return 4;
    }
}

/* Bittner's area-angle measure M = A |N . V| / |D|^2 (§4.5) of a polygon, with V the unit direction
   from the eye to its centre D (the solid angle it subtends, approximately; the thesis uses the view
   direction), or -1 when it lies wholly outside the frustum. */
PVS__STATIC double pvs__sv_score(const pvs_otree *o, const float *const *p, int n) {
    double v[4][3], c[3] = {0, 0, 0}, area[3] = {0, 0, 0}, dd;
    int i, k;
    for (i = 0; i < n; ++i)
        for (k = 0; k < 3; ++k) { v[i][k] = (double)p[i][k] - o->eye[k]; c[k] += v[i][k] / n; }
    for (k = 0; k < 5; ++k) {
        for (i = 0; i < n; ++i) if (pvs__sv_dot(o->fr[k], v[i]) + o->fr[k][3] >= 0.0) break;
        if (i == n) return -1.0;
    }
    for (i = 0; i < n; ++i) {
        const double *u = v[i], *w = v[(i + 1) % n];
        area[0] += (u[1] - w[1]) * (u[2] + w[2]);
        area[1] += (u[2] - w[2]) * (u[0] + w[0]);
        area[2] += (u[0] - w[0]) * (u[1] + w[1]);
    }
    dd = pvs__sv_dot(c, c);
    if (!(dd > 0.0)) return -1.0;
    return 0.5 * fabs(pvs__sv_dot(area, c)) / (dd * sqrt(dd));
}

PVS__STATIC int pvs__sv_before(const pvs__svsel *x, const pvs__svsel *y) {
    return x->key < y->key || (x->key == y->key && (x->a < y->a || (x->a == y->a && x->b < y->b)));
}
/* Heap sort by (key, a, b): a deterministic order whatever the heap held. */
PVS__STATIC void pvs__sv_sort(pvs__svsel *h, uint32_t n) {
    uint32_t i, end;
    for (i = n / 2; i-- > 0;) {
        uint32_t r = i, c;
        while ((c = 2 * r + 1) < n) {
            pvs__svsel tmp;
            if (c + 1 < n && pvs__sv_before(h + c, h + c + 1)) ++c;
            if (!pvs__sv_before(h + r, h + c)) break;
            tmp = h[r]; h[r] = h[c]; h[c] = tmp;
            r = c;
        }
    }
    for (end = n; end > 1; --end) {
        pvs__svsel tmp = h[0];
        uint32_t r = 0, c, m = end - 1;
        h[0] = h[m]; h[m] = tmp;
        while ((c = 2 * r + 1) < m) {
            if (c + 1 < m && pvs__sv_before(h + c, h + c + 1)) ++c;
            if (!pvs__sv_before(h + r, h + c)) break;
            tmp = h[r]; h[r] = h[c]; h[c] = tmp;
            r = c;
        }
    }
}

PVS__STATIC void pvs__sv_offer_triangle(pvs_otree *o, uint32_t k, uint32_t t) {
    float q[4][3];
    const float *p[4];
    double m;
    int n = pvs__sv_points(o->s, t, PVS__SV_TRIANGLE, q, p);
    m = pvs__sv_score(o, p, n);
    if (m > 0.0) pvs__sv_offer(o, k, m, t, PVS__SV_TRIANGLE);
}

typedef struct pvs__svboot {
    pvs_otree *o;
    uint32_t k;
} pvs__svboot;
PVS__STATIC pvs_visit pvs__sv_boot_visit(void *user, const pvs_box *node_box, float distance, const uint32_t *items, uint32_t count) {
    pvs__svboot *w = (pvs__svboot *)user;
    uint32_t i;
    (void)node_box;
    if (distance > w->o->lambda) return PVS_VISIT_STOP;
    for (i = 0; i < count; ++i) {
        if (pvs_bitset_test(w->o->tri_seen, items[i])) continue;
        pvs_bitset_set(w->o->tri_seen, items[i]);
        pvs__sv_offer_triangle(w->o, w->k, items[i]);
    }
    return PVS_VISIT_DESCEND;
}

/* ---- the kD-tree walk with hierarchy updating (§4.11.4, Fig. 4.5) ---- */

PVS__STATIC void pvs__sv_touch(pvs_otree *o, uint32_t obj, uint8_t flag) {
    if (!o->obj_flag[obj]) o->touched[o->touched_count++] = obj;
    o->obj_flag[obj] |= flag;
}

/* Marks the objects of every leaf below `node` with `flag` (a visible subtree: no tests). */
PVS__STATIC void pvs__sv_emit(pvs_otree *o, uint32_t node, const pvs_box *box, uint8_t flag) {
    const pvs_kdtree *t = o->s->object_tree;
    const pvs__kdnode *nd = t->nodes + node;
    uint32_t axis = nd->bits & 3u, i;
    ++o->st.nodes_visited;
    if (axis == PVS__KD_LEAF) {
        const uint32_t *items = t->items + (nd->bits >> 2);
        pvs_box eyebox;
        uint8_t near = 0;
        int k;
        for (k = 0; k < 3; ++k) eyebox.min[k] = eyebox.max[k] = (float)o->eye[k];
        if (pvs__box_distance2(&eyebox, box) <= o->lambda * o->lambda) near = 4;
        for (i = 0; i < nd->u.count; ++i) pvs__sv_touch(o, items[i], (uint8_t)(flag | near));
        return;
    } else {
        pvs_box c0 = *box, c1 = *box;
        float sp = nd->u.split;
        c0.max[axis] = sp < box->max[axis] ? (sp > box->min[axis] ? sp : box->min[axis]) : box->max[axis];
        c1.min[axis] = sp > box->min[axis] ? (sp < box->max[axis] ? sp : box->max[axis]) : box->min[axis];
        pvs__sv_emit(o, nd->bits >> 2, &c0, flag);
        pvs__sv_emit(o, (nd->bits >> 2) + 1, &c1, flag);
    }
}

/* Fig. 4.5: termination nodes of the last frame (leaves, nodes not partly visible, nodes not visited
   in the last frame) are tested; opened nodes are skipped and their children visited, near child
   first; a node whose children all agree takes their state (pull-up). */
PVS__STATIC void pvs__sv_walk(pvs_otree *o, uint32_t node, const pvs_box *box) {
    const pvs_kdtree *t = o->s->object_tree;
    const pvs__kdnode *nd = t->nodes + node;
    uint32_t axis = nd->bits & 3u, st = o->kd_vis[node];
    ++o->st.nodes_visited;
    if ((o->flags & PVS_OTREE_NO_COHERENCE) || axis == PVS__KD_LEAF || st != PVS__SV_P || o->kd_frame[node] + 1 < o->frame) {
        st = pvs__sv_box_test(o, box);
        ++o->info.node_tests;
        ++o->st.boxes_tested;
    } else {
        ++o->info.nodes_skipped;
    }
    o->kd_vis[node] = (uint8_t)st;
    o->kd_frame[node] = o->frame;
    if (st == PVS__SV_V) {
        --o->st.nodes_visited;
        pvs__sv_emit(o, node, box, 1);
    } else if (st == PVS__SV_P) {
        if (axis == PVS__KD_LEAF) {
            --o->st.nodes_visited;
            pvs__sv_emit(o, node, box, 2);
        } else {
            pvs_box c[2];
            float sp = nd->u.split;
            uint32_t first = o->eye[axis] < (double)sp ? 0u : 1u, ch = nd->bits >> 2, v0, v1;
            c[0] = *box; c[1] = *box;
            c[0].max[axis] = sp < box->max[axis] ? (sp > box->min[axis] ? sp : box->min[axis]) : box->max[axis];
            c[1].min[axis] = sp > box->min[axis] ? (sp < box->max[axis] ? sp : box->max[axis]) : box->min[axis];
            pvs__sv_walk(o, ch + first, c + first); /* front to back */
            pvs__sv_walk(o, ch + (1u - first), c + (1u - first));
            v0 = o->kd_vis[ch];
            v1 = o->kd_vis[ch + 1];
            if (v0 == v1 && v0 != PVS__SV_P) o->kd_vis[node] = (uint8_t)v0; /* pull-up */
        }
    }
}

/* ---- context and per-frame API ---- */

PVS_API void pvs_otree_destroy(pvs_otree *o) {
    pvs_allocator a;
    if (!o) return;
    a = o->allocator;
    pvs__free_array(&a, o->nodes, o->node_budget, sizeof(pvs__svnode));
    pvs__free_array(&a, o->frags, o->frag_budget, sizeof(pvs__svfrag));
    pvs__free_array(&a, o->verts, o->vert_budget, sizeof(pvs__svvert));
    pvs__free_array(&a, o->stack, PVS__SV_STACK, sizeof(pvs__svpoly));
    pvs__free_array(&a, o->stack_node, PVS__SV_STACK, sizeof(uint32_t));
    pvs__free_array(&a, o->tstack, (size_t)o->node_budget + 2, sizeof(uint32_t));
    pvs__free_array(&a, o->sel, o->max_occluders, sizeof(pvs__svsel));
    pvs__free_array(&a, o->prev, o->max_occluders, sizeof(uint32_t));
    pvs__free(&a, o->sweep, o->sweep_size, 16);
    pvs__free_array(&a, o->tri_seen, PVS_BITSET_WORDS(o->max_triangles) + 1, sizeof(pvs_word));
    pvs__free_array(&a, o->obj_first, (size_t)o->max_objects + 1, sizeof(uint32_t));
    pvs__free_array(&a, o->obj_tris, (size_t)o->max_objects + 1, sizeof(uint32_t));
    pvs__free_array(&a, o->kd_vis, (size_t)o->max_kd_nodes + 1, 1);
    pvs__free_array(&a, o->kd_frame, (size_t)o->max_kd_nodes + 1, sizeof(uint32_t));
    pvs__free_array(&a, o->obj_flag, (size_t)o->max_objects + 1, 1);
    pvs__free_array(&a, o->touched, (size_t)o->max_objects + 1, sizeof(uint32_t));
    pvs__free(&a, o, sizeof(*o), 16);
}

PVS_API void pvs_otree_reset(pvs_otree *o) {
    if (!o) return;
    o->have_prev = 0;
    o->prev_count = 0;
    o->last_scene = NULL; /* every kD node's state is stale */
}

PVS_API pvs_result pvs_otree_create(const pvs_otree_desc *desc, pvs_otree **out, pvs_error *err) {
    pvs_otree *o;
    pvs_allocator a;
    const pvs_scene *s;
    if (out) *out = NULL;
    if (!desc || !out || !desc->scene) return pvs__fail(err, PVS_ERROR_INVALID_ARGUMENT, -1, 0, "desc, desc->scene and out_otree must not be NULL");
    if (!pvs__finite(desc->aspect) || desc->aspect < 0.0f) return pvs__fail(err, PVS_ERROR_NOT_FINITE, -1, 0, "aspect must be finite and >= 0");
    if (desc->max_occluders > 65536) return pvs__fail(err, PVS_ERROR_INVALID_ARGUMENT, -1, 0, "max_occluders %u is over 65536", desc->max_occluders);
    if (desc->node_budget && (desc->node_budget < 64 || desc->node_budget > (1u << 24)))
        return pvs__fail(err, PVS_ERROR_INVALID_ARGUMENT, -1, 0, "node_budget %u is not in 64..2^24", desc->node_budget);
    s = desc->scene;
    a = desc->allocator;
    o = (pvs_otree *)pvs__alloc(&a, sizeof(*o), 16);
    if (!o) return pvs__fail(err, PVS_ERROR_OUT_OF_MEMORY, -1, 0, "otree context");
    memset(o, 0, sizeof(*o));
    o->allocator = a;
    o->flags = desc->flags;
    o->aspect = desc->aspect > 0.0f ? desc->aspect : 1.0f;
    o->max_occluders = desc->max_occluders ? desc->max_occluders : 64;
    o->node_budget = desc->node_budget ? desc->node_budget : 8192;
    o->frag_budget = o->node_budget / 2 + 1;
    o->vert_budget = 4 * o->node_budget;
    o->max_objects = s->object_count;
    o->max_triangles = s->triangle_count;
    o->max_kd_nodes = s->object_tree->node_count;
    o->sweep_size = pvs_kdtree_sweep_scratch_size(s->triangle_tree);
    o->nodes = (pvs__svnode *)pvs__alloc_array(&a, o->node_budget, sizeof(pvs__svnode));
    o->frags = (pvs__svfrag *)pvs__alloc_array(&a, o->frag_budget, sizeof(pvs__svfrag));
    o->verts = (pvs__svvert *)pvs__alloc_array(&a, o->vert_budget, sizeof(pvs__svvert));
    o->stack = (pvs__svpoly *)pvs__alloc_array(&a, PVS__SV_STACK, sizeof(pvs__svpoly));
    o->stack_node = (uint32_t *)pvs__alloc_array(&a, PVS__SV_STACK, sizeof(uint32_t));
    o->tstack = (uint32_t *)pvs__alloc_array(&a, (size_t)o->node_budget + 2, sizeof(uint32_t));
    o->sel = (pvs__svsel *)pvs__alloc_array(&a, o->max_occluders, sizeof(pvs__svsel));
    o->prev = (uint32_t *)pvs__alloc_array(&a, o->max_occluders, sizeof(uint32_t));
    o->sweep = pvs__alloc(&a, o->sweep_size ? o->sweep_size : 16, 16);
    o->tri_seen = (pvs_word *)pvs__alloc_array(&a, PVS_BITSET_WORDS(o->max_triangles) + 1, sizeof(pvs_word));
    o->obj_first = (uint32_t *)pvs__alloc_array(&a, (size_t)o->max_objects + 1, sizeof(uint32_t));
    o->obj_tris = (uint32_t *)pvs__alloc_array(&a, (size_t)o->max_objects + 1, sizeof(uint32_t));
    o->kd_vis = (uint8_t *)pvs__alloc_array(&a, (size_t)o->max_kd_nodes + 1, 1);
    o->kd_frame = (uint32_t *)pvs__alloc_array(&a, (size_t)o->max_kd_nodes + 1, sizeof(uint32_t));
    o->obj_flag = (uint8_t *)pvs__alloc_array(&a, (size_t)o->max_objects + 1, 1);
    o->touched = (uint32_t *)pvs__alloc_array(&a, (size_t)o->max_objects + 1, sizeof(uint32_t));
    if (!o->sweep_size) o->sweep_size = 16;
    if (!o->nodes || !o->frags || !o->verts || !o->stack || !o->stack_node || !o->tstack || !o->sel || !o->prev || !o->sweep ||
        !o->tri_seen || !o->obj_first || !o->obj_tris || !o->kd_vis || !o->kd_frame || !o->obj_flag || !o->touched) {
        pvs_otree_destroy(o);
        return pvs__fail(err, PVS_ERROR_OUT_OF_MEMORY, -1, 0, "otree buffers");
    }
    memset(o->obj_flag, 0, (size_t)o->max_objects + 1);
    memset(o->kd_vis, 0, (size_t)o->max_kd_nodes + 1);
    memset(o->kd_frame, 0, ((size_t)o->max_kd_nodes + 1) * sizeof(uint32_t));
    o->frame = 2;
    *out = o;
    pvs__ok(err);
    return PVS_OK;
}

PVS_API void pvs_otree_get_frame(const pvs_otree *o, pvs_otree_frame *frame) {
    if (o && frame) *frame = o->info;
}

PVS_API pvs_result pvs_otree_cull(pvs_otree *o, const pvs_scene *s, const pvs_camera *cam, const pvs_cull_params *p,
                                  pvs_word *visible, pvs_cull_stats *stats, pvs_error *err) {
    float m[16];
    double u[3], r[3], len, ty, tx, size = 0.0;
    uint32_t i, k, nocc = 0;
    int j;
    pvs_result res;
    if (!o || !s || !cam || !visible) return pvs__fail(err, PVS_ERROR_INVALID_ARGUMENT, -1, 0, "otree, scene, camera and visible must not be NULL");
    if (s->object_count > o->max_objects || s->triangle_count > o->max_triangles || s->object_tree->node_count > o->max_kd_nodes ||
        pvs_kdtree_sweep_scratch_size(s->triangle_tree) > o->sweep_size)
        return pvs__fail(err, PVS_ERROR_BUFFER_TOO_SMALL, -1, 0, "the context was created for a smaller scene");
    res = pvs_camera_matrix(cam, o->aspect, m);
    if (res != PVS_OK) return pvs__fail(err, res, -1, 0, "unusable camera");
    if (cam->fov_y == 0.0f) return pvs__fail(err, PVS_ERROR_UNSUPPORTED, -1, 0, "an orthographic camera: shadow volumes need an eye point");
    memset(&o->info, 0, sizeof(o->info));
    memset(&o->st, 0, sizeof(o->st));
    memset(visible, 0, PVS_BITSET_WORDS(s->object_count) * sizeof(pvs_word));
    if (s != o->last_scene || o->frame > 0xfffffff0u) { /* stale states everywhere */
        memset(o->kd_frame, 0, ((size_t)o->max_kd_nodes + 1) * sizeof(uint32_t));
        o->frame = 2;
        if (s != o->last_scene) o->have_prev = 0;
        if (s != o->ranges_scene) {
            o->ranges_scene = s;
            for (i = 0; i < s->object_count; ++i) { o->obj_first[i] = 0; o->obj_tris[i] = 0; }
            for (i = s->triangle_count; i-- > 0;) { /* objects are ranges of triangles */
                uint32_t ob = s->triangle_object[i];
                if (ob == PVS_NO_OBJECT) continue;
                o->obj_first[ob] = i;
                ++o->obj_tris[ob];
            }
        }
        o->last_scene = s;
    }
    ++o->frame;
    o->s = s;
    /* the eye frame (as pvs_camera_matrix) and the frustum: near plane, then the four sides */
    for (j = 0; j < 3; ++j) { o->eye[j] = cam->eye[j]; o->fw[j] = cam->forward[j]; u[j] = cam->up[j]; }
    pvs__sv_unit(o->fw);
    len = pvs__sv_dot(o->fw, u);
    for (j = 0; j < 3; ++j) u[j] -= len * o->fw[j];
    pvs__sv_unit(u);
    pvs__sv_cross(o->fw, u, r);
    ty = tan(0.5 * (double)cam->fov_y);
    tx = ty * o->aspect;
    o->near_d = cam->near_plane;
    for (j = 0; j < 3; ++j) {
        o->fr[0][j] = o->fw[j];
        o->fr[1][j] = tx * o->fw[j] - r[j];
        o->fr[2][j] = tx * o->fw[j] + r[j];
        o->fr[3][j] = ty * o->fw[j] - u[j];
        o->fr[4][j] = ty * o->fw[j] + u[j];
    }
    o->fr[0][3] = -o->near_d;
    for (k = 1; k < 5; ++k) { pvs__sv_unit(o->fr[k]); o->fr[k][3] = 0.0; }
    for (j = 0; j < 3; ++j) { /* the size of the eye-relative scene */
        double a = fabs((double)s->bounds.min[j] - o->eye[j]), b = fabs((double)s->bounds.max[j] - o->eye[j]);
        if (s->bounds.min[j] > s->bounds.max[j]) a = b = 0.0;
        size += (a > b ? a : b);
    }
    o->tol = 1e-10 * (size + o->near_d + 1e-20);
    o->lambda = p && p->occluder_distance > 0.0f ? p->occluder_distance : 100.0;
    /* the tree: one out-leaf, then the occluders front to back (§4.3) */
    o->node_count = 1;
    o->frag_count = 0;
    o->vert_count = 0;
    memset(o->nodes, 0, sizeof(pvs__svnode));
    o->nodes[0].kind = PVS__OT_OUT;
    if (p && p->occluder_triangle_count && p->occluder_positions) { /* the caller's, in the caller's order */
        for (i = 0; i < p->occluder_triangle_count; ++i) {
            const float *pt[3];
            pvs__svpoly q;
            double plane[4];
            int bad = 0;
            for (j = 0; j < 3; ++j) {
                uint32_t vi = p->occluder_indices ? p->occluder_indices[3 * (size_t)i + (uint32_t)j] : 3 * i + (uint32_t)j;
                if (vi >= p->occluder_vertex_count) { bad = 1; break; }
                pt[j] = p->occluder_positions + 3 * (size_t)vi;
                if (!pvs__finite(pt[j][0]) || !pvs__finite(pt[j][1]) || !pvs__finite(pt[j][2])) bad = 1;
            }
            if (bad) continue;
            ++nocc;
            if (pvs__sv_polygon(o, pt, 3, &q, plane)) pvs__sv_insert(o, &q, plane);
        }
    }
    o->sel_count = 0;
    if (p && (p->scene_occluders || p->scene_volumes)) {
        uint32_t kk = p->scene_occluders < o->max_occluders ? p->scene_occluders : o->max_occluders;
        if (p->scene_volumes) kk = o->max_occluders;
        if (p->scene_occluders) {
            if (o->have_prev) {
                for (i = 0; i < o->prev_count; ++i)
                    if (o->prev[i] < s->triangle_count) pvs__sv_offer_triangle(o, kk, o->prev[i]);
            } else {
                pvs__svboot w;
                pvs_box src;
                w.o = o;
                w.k = kk;
                memset(o->tri_seen, 0, PVS_BITSET_WORDS(s->triangle_count) * sizeof(pvs_word));
                for (j = 0; j < 3; ++j) src.min[j] = src.max[j] = cam->eye[j];
                pvs_kdtree_sweep(s->triangle_tree, &src, o->sweep, o->sweep_size, pvs__sv_boot_visit, &w);
            }
        }
        if (p->scene_volumes) {
            pvs_box src;
            for (j = 0; j < 3; ++j) src.min[j] = src.max[j] = cam->eye[j];
            for (i = 0; i < s->occluder_count; ++i) {
                const pvs_occluder_desc *oc = s->occluders + i;
                uint32_t faces = oc->kind == PVS_OCCLUDER_BOX ? 6u : oc->kind == PVS_OCCLUDER_EXTRUSION ? oc->footprint_count : 0u, f;
                if (!faces || pvs__box_distance2(&src, s->occluder_boxes + i) > o->lambda * o->lambda) continue;
                for (f = 0; f < faces; ++f) {
                    float q[4][3];
                    const float *pt[4];
                    int n = pvs__sv_points(s, i, f, q, pt);
                    double sc = pvs__sv_score(o, pt, n);
                    if (sc > 0.0) pvs__sv_offer(o, kk, sc, i, f);
                }
            }
        }
        /* insert in order of distance from the eye (the approximate occlusion sweep, §3.2) */
        for (i = 0; i < o->sel_count; ++i) {
            float q[4][3];
            const float *pt[4];
            double c[3] = {0, 0, 0};
            int n = pvs__sv_points(s, o->sel[i].a, o->sel[i].b, q, pt);
            for (j = 0; j < n; ++j) for (k = 0; k < 3; ++k) c[k] += ((double)pt[j][k] - o->eye[k]) / n;
            o->sel[i].key = pvs__sv_dot(c, c);
        }
        pvs__sv_sort(o->sel, o->sel_count);
        for (i = 0; i < o->sel_count; ++i) {
            float q4[4][3];
            const float *pt[4];
            pvs__svpoly q;
            double plane[4];
            int n = pvs__sv_points(s, o->sel[i].a, o->sel[i].b, q4, pt);
            ++nocc;
            if (pvs__sv_polygon(o, pt, n, &q, plane)) pvs__sv_insert(o, &q, plane);
        }
    }
    o->info.occluders = nocc;
    o->info.tree_nodes = o->node_count;
    o->info.fragments = o->frag_count;
    o->st.occluder_triangles = nocc;
    /* the hierarchical visibility walk (§4.3, Fig. 4.5) */
    o->touched_count = 0;
    if (s->object_tree->bounds.min[0] <= s->object_tree->bounds.max[0]) pvs__sv_walk(o, 0, &s->object_tree->bounds);
    /* objects: those of visible leaves, and those of partly visible leaves whose own box may be seen */
    for (i = 0; i < o->touched_count; ++i) {
        uint32_t ob = o->touched[i], fl = o->obj_flag[ob];
        if ((s->object_flags[ob] & PVS_OBJECT_OCCLUDER_ONLY) || (p && p->candidates && !pvs_bitset_test(p->candidates, ob))) continue;
        if (!(fl & 1u)) {
            ++o->info.object_tests;
            ++o->st.boxes_tested;
            if (pvs__sv_box_test(o, s->object_boxes + ob) == PVS__SV_I) continue;
        }
        pvs_bitset_set(visible, ob);
        ++o->st.visible;
    }
    /* the next frame's occluders: the best triangles of the objects seen within the distance (§4.5) */
    if (p && p->scene_occluders) {
        uint32_t kk = p->scene_occluders < o->max_occluders ? p->scene_occluders : o->max_occluders;
        o->sel_count = 0;
        for (i = 0; i < o->touched_count; ++i) {
            uint32_t ob = o->touched[i], t;
            if (!(o->obj_flag[ob] & 4u)) continue; /* not within the distance */
            if (s->object_flags[ob] & PVS_OBJECT_OCCLUDER_ONLY) {
                if (!(o->obj_flag[ob] & 1u) && pvs__sv_box_test(o, s->object_boxes + ob) == PVS__SV_I) continue;
            } else if (!pvs_bitset_test(visible, ob)) {
                continue;
            }
            for (t = o->obj_first[ob]; t < o->obj_first[ob] + o->obj_tris[ob]; ++t) pvs__sv_offer_triangle(o, kk, t);
        }
        o->prev_count = o->sel_count;
        for (i = 0; i < o->sel_count; ++i) o->prev[i] = o->sel[i].a;
        o->have_prev = 1;
    }
    for (i = 0; i < o->touched_count; ++i) o->obj_flag[o->touched[i]] = 0;
    if (stats) *stats = o->st;
    pvs__ok(err);
    return PVS_OK;
}

// >>occluders
/* ---------------------------------------------------------------------------------------------- */
/* occluders: synthesis of certainly-solid volumes (for Wonka 2000's shrinking, §2 and appendix)  */
/* ---------------------------------------------------------------------------------------------- */

enum { PVS__VX_FREE = 0, PVS__VX_TOUCHED = 1, PVS__VX_REACHED = 2, PVS__VX_EXPLICIT = 3, PVS__VX_GROUND = 4 };

struct pvs_occluders {
    pvs_allocator allocator;
    const pvs_scene *scene;
    pvs_occluders_info info;
    double origin[3], h;        /* grid */
    uint32_t n[3];
    size_t total;
    uint8_t *state;             /* total: PVS__VX_* ; solid = FREE (never reached) or EXPLICIT */
    uint8_t *eroded;            /* total: 1 where solid survives the erosion */
    pvs_box *boxes;
    uint32_t box_count;
    pvs_facade_chain *chains;
    float *chain_points;        /* 8 per chain */
    uint32_t chain_count;
    float ground;
    float *column_top;          /* n[u] * n[v]: top of each column's solid run before erosion (ground: none) */
    size_t column_count;
};

PVS__STATIC size_t pvs__vx_index(const pvs_occluders *o, uint32_t i, uint32_t j, uint32_t k) {
    return (size_t)i + (size_t)o->n[0] * ((size_t)j + (size_t)o->n[1] * (size_t)k);
}
PVS__STATIC int pvs__vx_solid_state(uint8_t s) { return s == PVS__VX_FREE || s == PVS__VX_EXPLICIT; }

/* Triangle / box overlap by the separating axis theorem (Akenine-Moller 2001), in double, with the
   box half size `hs` already grown by a margin: rounding errs toward "touched". */
PVS__STATIC int pvs__tri_box(const double c[3], double hs, const double *a, const double *b, const double *d) {
    double v[3][3], e[3][3], n[3], p, q, r, lo, hi, rad;
    int i, j;
    for (i = 0; i < 3; ++i) { v[0][i] = a[i] - c[i]; v[1][i] = b[i] - c[i]; v[2][i] = d[i] - c[i]; }
    for (i = 0; i < 3; ++i) {
        lo = hi = v[0][i];
        for (j = 1; j < 3; ++j) { if (v[j][i] < lo) lo = v[j][i]; if (v[j][i] > hi) hi = v[j][i]; }
        if (lo > hs || hi < -hs) return 0;
    }
    for (i = 0; i < 3; ++i) { e[0][i] = v[1][i] - v[0][i]; e[1][i] = v[2][i] - v[1][i]; e[2][i] = v[0][i] - v[2][i]; }
    n[0] = e[0][1] * e[1][2] - e[0][2] * e[1][1];
    n[1] = e[0][2] * e[1][0] - e[0][0] * e[1][2];
    n[2] = e[0][0] * e[1][1] - e[0][1] * e[1][0];
    p = n[0] * v[0][0] + n[1] * v[0][1] + n[2] * v[0][2];
    rad = hs * (pvs__dabs(n[0]) + pvs__dabs(n[1]) + pvs__dabs(n[2]));
    if (p > rad * (1.0 + 1e-9) + 1e-300 || p < -rad * (1.0 + 1e-9) - 1e-300) return 0;
    for (i = 0; i < 3; ++i)       /* edge i x box axis j */
        for (j = 0; j < 3; ++j) {
            double ax[3] = {0, 0, 0};
            int k;
            ax[(j + 1) % 3] = -e[i][(j + 2) % 3];
            ax[(j + 2) % 3] = e[i][(j + 1) % 3];
            /* axis = unit_j x e_i */
            lo = hi = ax[0] * v[0][0] + ax[1] * v[0][1] + ax[2] * v[0][2];
            for (k = 1; k < 3; ++k) {
                q = ax[0] * v[k][0] + ax[1] * v[k][1] + ax[2] * v[k][2];
                if (q < lo) lo = q;
                if (q > hi) hi = q;
            }
            r = hs * (pvs__dabs(ax[0]) + pvs__dabs(ax[1]) + pvs__dabs(ax[2]));
            r = r * (1.0 + 1e-9) + 1e-300;
            if (lo > r || hi < -r) return 0;
        }
    return 1;
}

/* 1 if point (x, y) is inside the polygon (even-odd rule). */
PVS__STATIC int pvs__point_in_poly(const float *pts, uint32_t n, double x, double y) {
    uint32_t i, j;
    int in = 0;
    for (i = 0, j = n - 1; i < n; j = i++) {
        double xi = pts[2 * i], yi = pts[2 * i + 1], xj = pts[2 * j], yj = pts[2 * j + 1];
        if ((yi > y) != (yj > y) && x < (xj - xi) * (y - yi) / (yj - yi) + xi) in = !in;
    }
    return in;
}
/* 1 if segments p0-p1 and q0-q1 meet (touching counts). */
PVS__STATIC int pvs__seg_meet(double ax, double ay, double bx, double by, double cx, double cy, double dx, double dy) {
    double d1 = (bx - ax) * (cy - ay) - (by - ay) * (cx - ax), d2 = (bx - ax) * (dy - ay) - (by - ay) * (dx - ax);
    double d3 = (dx - cx) * (ay - cy) - (dy - cy) * (ax - cx), d4 = (dx - cx) * (by - cy) - (dy - cy) * (bx - cx);
    if (((d1 > 0 && d2 > 0) || (d1 < 0 && d2 < 0))) return 0;
    if (((d3 > 0 && d4 > 0) || (d3 < 0 && d4 < 0))) return 0;
    if (d1 == 0 && d2 == 0 && d3 == 0 && d4 == 0) /* collinear: overlap of the projections */
        return pvs__dmax(pvs__dmin(ax, bx), pvs__dmin(cx, dx)) <= pvs__dmin(pvs__dmax(ax, bx), pvs__dmax(cx, dx)) &&
               pvs__dmax(pvs__dmin(ay, by), pvs__dmin(cy, dy)) <= pvs__dmin(pvs__dmax(ay, by), pvs__dmax(cy, dy));
    return 1;
}

/* 1 if the closed voxel box lies inside the explicit occluder volume (rounding toward "not inside"). */
PVS__STATIC int pvs__vx_in_occluder(const pvs_occluder_desc *oc, uint32_t up, const double lo[3], const double hi[3]) {
    int k, u, v;
    uint32_t i, j;
    switch (oc->kind) {
    case PVS_OCCLUDER_BOX:
        for (k = 0; k < 3; ++k)
            if (lo[k] < oc->box.min[k] || hi[k] > oc->box.max[k]) return 0;
        return 1;
    case PVS_OCCLUDER_CONVEX:
        for (i = 0; i < oc->plane_count; ++i) {
            const float *pl = oc->planes + 4 * i;
            for (j = 0; j < 8; ++j) {
                double x = j & 1 ? hi[0] : lo[0], y = j & 2 ? hi[1] : lo[1], z = j & 4 ? hi[2] : lo[2];
                if (pl[0] * x + pl[1] * y + pl[2] * z + pl[3] > -1e-6 * (pvs__dabs(pl[3]) + 1.0)) return 0;
            }
        }
        return 1;
    case PVS_OCCLUDER_EXTRUSION:
        pvs__ground_axes(up, &u, &v);
        if (lo[up] < oc->base || hi[up] > oc->top) return 0;
        for (j = 0; j < 4; ++j)
            if (!pvs__point_in_poly(oc->footprint, oc->footprint_count, j & 1 ? hi[u] : lo[u], j & 2 ? hi[v] : lo[v])) return 0;
        for (i = 0; i < oc->footprint_count; ++i) {
            const float *a = oc->footprint + 2 * i, *b = oc->footprint + 2 * ((i + 1) % oc->footprint_count);
            if (pvs__seg_meet(a[0], a[1], b[0], b[1], lo[u], lo[v], hi[u], lo[v]) ||
                pvs__seg_meet(a[0], a[1], b[0], b[1], hi[u], lo[v], hi[u], hi[v]) ||
                pvs__seg_meet(a[0], a[1], b[0], b[1], hi[u], hi[v], lo[u], hi[v]) ||
                pvs__seg_meet(a[0], a[1], b[0], b[1], lo[u], hi[v], lo[u], lo[v]))
                return 0;
        }
        return 1;
    default: return 0;
    }
}

PVS_API void pvs_occluders_destroy(pvs_occluders *o) {
    pvs_allocator a;
    if (!o) return;
    a = o->allocator;
    pvs__free_array(&a, o->state, o->total, 1);
    pvs__free_array(&a, o->eroded, o->total, 1);
    pvs__free_array(&a, o->boxes, o->box_count, sizeof(pvs_box));
    pvs__free_array(&a, o->chains, o->chain_count, sizeof(pvs_facade_chain));
    pvs__free_array(&a, o->chain_points, (size_t)o->chain_count * 8, sizeof(float));
    pvs__free_array(&a, o->column_top, o->column_count, sizeof(float));
    pvs__free(&a, o, sizeof(*o), 16);
}

/* Voxel index range [*i0, *i1] on axis k of the closed interval [lo, hi] grown by `m`. */
PVS__STATIC void pvs__vx_range(const pvs_occluders *o, int k, double lo, double hi, double m, uint32_t *i0, uint32_t *i1) {
    double a = floor((lo - m - o->origin[k]) / o->h), b = floor((hi + m - o->origin[k]) / o->h);
    if (a < 0) a = 0;
    if (b > (double)o->n[k] - 1) b = (double)o->n[k] - 1;
    if (b < a) { *i0 = 1; *i1 = 0; return; }
    *i0 = (uint32_t)a;
    *i1 = (uint32_t)b;
}

/* One-dimensional min filter of radius r along axis k over a byte grid (outside counts as 0):
   Chebyshev erosion is separable. */
PVS__STATIC void pvs__vx_erode_axis(const pvs_occluders *o, uint8_t *g, uint8_t *line, int k, uint32_t r) {
    uint32_t n = o->n[k], a, b, c, i;
    size_t stride = k == 0 ? 1 : k == 1 ? o->n[0] : (size_t)o->n[0] * o->n[1];
    int ka = k == 0 ? 1 : 0, kb = k == 2 ? 1 : 2;
    for (a = 0; a < o->n[ka]; ++a)
        for (b = 0; b < o->n[kb]; ++b) {
            size_t base;
            uint32_t idx[3];
            idx[k] = 0; idx[ka] = a; idx[kb] = b;
            base = pvs__vx_index(o, idx[0], idx[1], idx[2]);
            for (i = 0; i < n; ++i) line[i] = g[base + i * stride];
            for (i = 0; i < n; ++i) {
                uint32_t lo = i >= r ? i - r : 0, hi = i + r < n ? i + r : n - 1, ok = i >= r && i + r < n;
                for (c = lo; ok && c <= hi; ++c) ok = line[c] != 0;
                g[base + i * stride] = (uint8_t)ok;
            }
        }
}

/* Greedy merge of the set cells of a 3D byte grid into boxes (consumes the grid copy). */
PVS__STATIC uint32_t pvs__vx_merge(const pvs_occluders *o, uint8_t *g, pvs_box *out) {
    uint32_t i, j, k, i1, j1, k1, a, b, count = 0;
    for (k = 0; k < o->n[2]; ++k)
        for (j = 0; j < o->n[1]; ++j)
            for (i = 0; i < o->n[0]; ++i) {
                int full;
                if (!g[pvs__vx_index(o, i, j, k)]) continue;
                for (i1 = i; i1 + 1 < o->n[0] && g[pvs__vx_index(o, i1 + 1, j, k)]; ++i1) {}
                for (j1 = j, full = 1; full && j1 + 1 < o->n[1];) {
                    for (a = i; a <= i1 && full; ++a) full = g[pvs__vx_index(o, a, j1 + 1, k)] != 0;
                    if (full) ++j1;
                }
                for (k1 = k, full = 1; full && k1 + 1 < o->n[2];) {
                    for (b = j; b <= j1 && full; ++b)
                        for (a = i; a <= i1 && full; ++a) full = g[pvs__vx_index(o, a, b, k1 + 1)] != 0;
                    if (full) ++k1;
                }
                for (b = k; b <= k1; ++b)
                    for (a = j; a <= j1; ++a) memset(g + pvs__vx_index(o, i, a, b), 0, i1 - i + 1);
                if (out) {
                    pvs_box *bx = out + count;
                    bx->min[0] = pvs__f_up(o->origin[0] + i * o->h);
                    bx->min[1] = pvs__f_up(o->origin[1] + j * o->h);
                    bx->min[2] = pvs__f_up(o->origin[2] + k * o->h);
                    bx->max[0] = pvs__f_down(o->origin[0] + (i1 + 1) * o->h);
                    bx->max[1] = pvs__f_down(o->origin[1] + (j1 + 1) * o->h);
                    bx->max[2] = pvs__f_down(o->origin[2] + (k1 + 1) * o->h);
                }
                ++count;
            }
    return count;
}

PVS_API pvs_result pvs_occluders_create(const pvs_occluders_desc *d, pvs_occluders **out, pvs_error *err) {
    pvs_occluders *o;
    pvs_allocator a;
    const pvs_scene *s;
    pvs_box ext;
    double g, h, m;
    uint32_t up, i, j, k, c, r, *queue = NULL, qh, qt;
    size_t total, vi, cols;
    uint8_t *tmp = NULL, *line = NULL;
    float *colh = NULL;
    int u, v, kk;
    if (out) *out = NULL;
    if (!d || !out || !d->scene || !d->cells || !d->cell_count)
        return pvs__fail(err, PVS_ERROR_INVALID_ARGUMENT, -1, 0, "desc, scene, cells and out must be given");
    if (!pvs__finite(d->eps) || !(d->eps > 0.0f) || !pvs__finite(d->voxel_size) || d->voxel_size < 0.0f)
        return pvs__fail(err, PVS_ERROR_INVALID_ARGUMENT, -1, 0, "eps must be finite and > 0, voxel_size finite and >= 0");
    for (c = 0; c < d->cell_count; ++c)
        if (!pvs__box_valid(d->cells + c)) return pvs__fail(err, PVS_ERROR_BAD_CELL, c, 0, "cell %u is not a valid box", c);
    s = d->scene;
    up = s->up_axis;
    pvs__ground_axes(up, &u, &v);
    ext = s->bounds;
    for (c = 0; c < d->cell_count; ++c)
        for (kk = 0; kk < 3; ++kk) {
            if (d->cells[c].min[kk] < ext.min[kk]) ext.min[kk] = d->cells[c].min[kk];
            if (d->cells[c].max[kk] > ext.max[kk]) ext.max[kk] = d->cells[c].max[kk];
        }
    g = ext.min[up];
    h = d->voxel_size > 0.0f ? d->voxel_size : d->eps / 1.5; /* erosion by 2 voxels = 1.33 eps */
    for (;;) { /* grow the voxel until the grid fits */
        double cnt = 1.0, lim = d->max_voxels ? (double)d->max_voxels : (double)(1u << 24);
        for (kk = 0; kk < 3; ++kk) cnt *= floor(((double)ext.max[kk] - ext.min[kk]) / h) + 3.0;
        if (cnt <= lim) break;
        h *= 1.08;
    }
    a = d->allocator;
    o = (pvs_occluders *)pvs__alloc(&a, sizeof(*o), 16);
    if (!o) return pvs__fail(err, PVS_ERROR_OUT_OF_MEMORY, -1, 0, "occluders");
    memset(o, 0, sizeof(*o));
    o->allocator = a;
    o->scene = s;
    o->h = h;
    o->ground = (float)g;
    total = 1;
    for (kk = 0; kk < 3; ++kk) {
        o->n[kk] = (uint32_t)(floor(((double)ext.max[kk] - ext.min[kk]) / h) + 3.0);
        o->origin[kk] = (double)ext.min[kk] - h;
        total *= o->n[kk];
    }
    o->origin[up] = g - h; /* layer 0 lies below the ground, layer 1 starts at it */
    o->total = total;
    o->state = (uint8_t *)pvs__alloc_array(&a, total, 1);
    o->eroded = (uint8_t *)pvs__alloc_array(&a, total, 1);
    tmp = (uint8_t *)pvs__alloc_array(&a, total, 1);
    queue = (uint32_t *)pvs__alloc_array(&a, total, sizeof(uint32_t));
    line = (uint8_t *)pvs__alloc_array(&a, 1u + o->n[0] + o->n[1] + o->n[2], 1);
    cols = (size_t)o->n[u] * o->n[v];
    colh = (float *)pvs__alloc_array(&a, cols, sizeof(float));
    if (!o->state || !o->eroded || !tmp || !queue || !line || !colh || total > 0xffffffffu) {
        pvs__free_array(&a, tmp, total, 1);
        pvs__free_array(&a, queue, total, sizeof(uint32_t));
        pvs__free_array(&a, line, 1u + o->n[0] + o->n[1] + o->n[2], 1);
        pvs__free_array(&a, colh, cols, sizeof(float));
        pvs_occluders_destroy(o);
        return pvs__fail(err, PVS_ERROR_OUT_OF_MEMORY, -1, 0, "voxel grid %u x %u x %u", o->n[0], o->n[1], o->n[2]);
    }
    memset(o->state, PVS__VX_FREE, total);
    for (k = 0; k < o->n[2]; ++k)
        for (j = 0; j < o->n[1]; ++j)
            for (i = 0; i < o->n[0]; ++i) {
                uint32_t idx[3];
                idx[0] = i; idx[1] = j; idx[2] = k;
                if (idx[up] == 0) o->state[pvs__vx_index(o, i, j, k)] = PVS__VX_GROUND;
            }
    /* 1. touched voxels: every triangle against the voxels of its box (SAT, margin toward touched).
       Triangles lying flat on the ground (the lowest height) touch nothing above it. */
    m = h * 1e-4 + 1e-6 * (pvs__dabs(g) + 1.0);
    for (c = 0; c < s->triangle_count; ++c) {
        double p[3][3], lo[3], hi[3];
        uint32_t r0[3], r1[3];
        for (kk = 0; kk < 3; ++kk) {
            p[0][kk] = s->positions[3 * s->indices[3 * c] + kk];
            p[1][kk] = s->positions[3 * s->indices[3 * c + 1] + kk];
            p[2][kk] = s->positions[3 * s->indices[3 * c + 2] + kk];
            lo[kk] = pvs__dmin(p[0][kk], pvs__dmin(p[1][kk], p[2][kk]));
            hi[kk] = pvs__dmax(p[0][kk], pvs__dmax(p[1][kk], p[2][kk]));
        }
        if (hi[up] <= g) continue;
        for (kk = 0; kk < 3; ++kk) pvs__vx_range(o, kk, lo[kk], hi[kk], m, r0 + kk, r1 + kk);
        for (k = r0[2]; k <= r1[2]; ++k)
            for (j = r0[1]; j <= r1[1]; ++j)
                for (i = r0[0]; i <= r1[0]; ++i) {
                    double cc[3];
                    size_t x = pvs__vx_index(o, i, j, k);
                    if (o->state[x] != PVS__VX_FREE) continue;
                    cc[0] = o->origin[0] + (i + 0.5) * h;
                    cc[1] = o->origin[1] + (j + 0.5) * h;
                    cc[2] = o->origin[2] + (k + 0.5) * h;
                    if (pvs__tri_box(cc, 0.5 * h + m, p[0], p[1], p[2])) o->state[x] = PVS__VX_TOUCHED;
                }
    }
    for (vi = 0; vi < total; ++vi) o->info.touched += o->state[vi] == PVS__VX_TOUCHED;
    /* 2. explicit occluder volumes are solid: voxels wholly inside one */
    for (c = 0; c < s->occluder_count; ++c) {
        const pvs_box *ob = s->occluder_boxes + c;
        uint32_t r0[3], r1[3];
        for (kk = 0; kk < 3; ++kk) pvs__vx_range(o, kk, ob->min[kk], ob->max[kk], 0.0, r0 + kk, r1 + kk);
        for (k = r0[2]; k <= r1[2]; ++k)
            for (j = r0[1]; j <= r1[1]; ++j)
                for (i = r0[0]; i <= r1[0]; ++i) {
                    double lo[3], hi[3];
                    size_t x = pvs__vx_index(o, i, j, k);
                    if (o->state[x] == PVS__VX_GROUND) continue;
                    lo[0] = o->origin[0] + i * h; hi[0] = lo[0] + h;
                    lo[1] = o->origin[1] + j * h; hi[1] = lo[1] + h;
                    lo[2] = o->origin[2] + k * h; hi[2] = lo[2] + h;
                    if (pvs__vx_in_occluder(s->occluders + c, up, lo, hi)) o->state[x] = PVS__VX_EXPLICIT;
                }
    }
    /* 3. flood fill, 26-connected, from every cell through untouched voxels; a cell reaching the
       grid's border (outside the scene) floods the outside too and is reported as the leak */
    o->info.leak_cell = PVS_NO_CELL;
    for (c = 0; c < d->cell_count; ++c) {
        uint32_t r0[3], r1[3];
        const pvs_box *cb = d->cells + c;
        qh = qt = 0;
        for (kk = 0; kk < 3; ++kk) pvs__vx_range(o, kk, cb->min[kk], cb->max[kk], m, r0 + kk, r1 + kk);
        for (k = r0[2]; k <= r1[2]; ++k)
            for (j = r0[1]; j <= r1[1]; ++j)
                for (i = r0[0]; i <= r1[0]; ++i) {
                    size_t x = pvs__vx_index(o, i, j, k);
                    if (o->state[x] == PVS__VX_FREE) { o->state[x] = PVS__VX_REACHED; queue[qt++] = (uint32_t)x; }
                }
        while (qh < qt) {
            uint32_t x = queue[qh++], ci = x % o->n[0], cj = (x / o->n[0]) % o->n[1], ck = x / o->n[0] / o->n[1];
            int di, dj, dk;
            if (o->info.leak_cell == PVS_NO_CELL &&
                (ci == 0 || cj == 0 || ck == 0 || ci + 1 == o->n[0] || cj + 1 == o->n[1] || ck + 1 == o->n[2])) {
                o->info.leak_cell = c;
                o->info.leak_point[0] = (float)(o->origin[0] + (ci + 0.5) * h);
                o->info.leak_point[1] = (float)(o->origin[1] + (cj + 0.5) * h);
                o->info.leak_point[2] = (float)(o->origin[2] + (ck + 0.5) * h);
            }
            for (dk = -1; dk <= 1; ++dk)
                for (dj = -1; dj <= 1; ++dj)
                    for (di = -1; di <= 1; ++di) {
                        int64_t ni = (int64_t)ci + di, nj = (int64_t)cj + dj, nk = (int64_t)ck + dk;
                        size_t y;
                        if (ni < 0 || nj < 0 || nk < 0 || ni >= o->n[0] || nj >= o->n[1] || nk >= o->n[2]) continue;
                        y = pvs__vx_index(o, (uint32_t)ni, (uint32_t)nj, (uint32_t)nk);
                        if (o->state[y] == PVS__VX_FREE) { o->state[y] = PVS__VX_REACHED; queue[qt++] = (uint32_t)y; }
                    }
        }
    }
    for (vi = 0; vi < total; ++vi) {
        o->eroded[vi] = (uint8_t)pvs__vx_solid_state(o->state[vi]);
        o->info.solid += o->eroded[vi];
    }
    /* thin objects: no solid voxel inside their box */
    for (c = 0; c < s->object_count; ++c) {
        const pvs_box *ob = s->object_boxes + c;
        uint32_t r0[3], r1[3];
        int found = 0;
        if ((s->object_flags[c] & PVS_OBJECT_OCCLUDER_ONLY) || !pvs__box_valid(ob)) continue;
        for (kk = 0; kk < 3; ++kk) pvs__vx_range(o, kk, ob->min[kk], ob->max[kk], 0.0, r0 + kk, r1 + kk);
        for (k = r0[2]; k <= r1[2] && !found; ++k)
            for (j = r0[1]; j <= r1[1] && !found; ++j)
                for (i = r0[0]; i <= r1[0] && !found; ++i) found = o->eroded[pvs__vx_index(o, i, j, k)];
        o->info.thin_objects += !found;
    }
    /* 4. 2.5D: per column the run of solid voxels standing on the ground (layer 1 up) */
    r = (uint32_t)floor(d->eps / h) + 1u; /* strictly more than eps: rounding toward less solid */
    for (vi = 0; vi < cols; ++vi) {
        uint32_t cu = (uint32_t)(vi % o->n[u]), cv = (uint32_t)(vi / o->n[u]), run = 0, idx[3];
        idx[u] = cu; idx[v] = cv;
        for (idx[up] = 1; idx[up] < o->n[up]; ++idx[up]) {
            if (!o->eroded[pvs__vx_index(o, idx[0], idx[1], idx[2])]) break;
            ++run;
        }
        o->info.column_voxels += run;
        colh[vi] = run ? (float)run : 0.0f; /* in voxel layers for now */
    }
    o->column_top = (float *)pvs__alloc_array(&a, cols, sizeof(float));
    if (o->column_top) {
        o->column_count = cols;
        for (vi = 0; vi < cols; ++vi) o->column_top[vi] = colh[vi] > 0.0f ? pvs__f_up(g + (double)colh[vi] * h) : (float)g;
    }
    o->info.is_2d5 = o->info.solid > 0 && (double)o->info.column_voxels >= 0.9 * (double)o->info.solid;
    /* 2.5D erosion: column height = min over the (2r+1)^2 neighbourhood (outside: 0), minus eps */
    {
        float *t2 = (float *)tmp; /* reuse only if large enough */
        float *buf = NULL;
        size_t ii;
        uint32_t a0, b0, q;
        if (total >= cols * sizeof(float)) buf = t2;
        else buf = (float *)pvs__alloc_array(&a, cols, sizeof(float));
        if (!buf) {
            pvs__free_array(&a, tmp, total, 1);
            pvs__free_array(&a, queue, total, sizeof(uint32_t));
            pvs__free_array(&a, line, 1u + o->n[0] + o->n[1] + o->n[2], 1);
            pvs__free_array(&a, colh, cols, sizeof(float));
            pvs_occluders_destroy(o);
            return pvs__fail(err, PVS_ERROR_OUT_OF_MEMORY, -1, 0, "columns");
        }
        for (b0 = 0; b0 < o->n[v]; ++b0)
            for (a0 = 0; a0 < o->n[u]; ++a0) {
                float mn = colh[(size_t)b0 * o->n[u] + a0];
                if (a0 < r || a0 + r >= o->n[u]) mn = 0.0f;
                for (q = a0 >= r ? a0 - r : 0; mn > 0.0f && q <= a0 + r && q < o->n[u]; ++q)
                    if (colh[(size_t)b0 * o->n[u] + q] < mn) mn = colh[(size_t)b0 * o->n[u] + q];
                buf[(size_t)b0 * o->n[u] + a0] = mn;
            }
        for (b0 = 0; b0 < o->n[v]; ++b0)
            for (a0 = 0; a0 < o->n[u]; ++a0) {
                float mn = buf[(size_t)b0 * o->n[u] + a0];
                if (b0 < r || b0 + r >= o->n[v]) mn = 0.0f;
                for (q = b0 >= r ? b0 - r : 0; mn > 0.0f && q <= b0 + r && q < o->n[v]; ++q)
                    if (buf[(size_t)q * o->n[u] + a0] < mn) mn = buf[(size_t)q * o->n[u] + a0];
                colh[(size_t)b0 * o->n[u] + a0] = mn;
            }
        if (buf != t2) pvs__free_array(&a, buf, cols, sizeof(float));
        /* heights in scene units: top of the run lowered by eps, rounded down; <= ground: none */
        for (ii = 0; ii < cols; ++ii) {
            double top = colh[ii] > 0.0f ? g + (double)colh[ii] * h - d->eps : g;
            float f = pvs__f_down(top);
            colh[ii] = top > g && f > (float)g ? f : -FLT_MAX;
        }
        /* merge equal columns into rectangles (greedy: along u, then v) */
        {
            uint32_t pass, count = 0;
            uint8_t *used = tmp;
            for (pass = 0; pass < 2; ++pass) {
                memset(used, 0, cols);
                count = 0;
                for (b0 = 0; b0 < o->n[v]; ++b0)
                    for (a0 = 0; a0 < o->n[u]; ++a0) {
                        size_t x0 = (size_t)b0 * o->n[u] + a0;
                        float hv = colh[x0];
                        uint32_t a1, b1, t;
                        int full = 1;
                        if (used[x0] || hv == -FLT_MAX) continue;
                        for (a1 = a0; a1 + 1 < o->n[u] && !used[x0 + (a1 + 1 - a0)] && colh[x0 + (a1 + 1 - a0)] == hv; ++a1) {}
                        for (b1 = b0; full && b1 + 1 < o->n[v];) {
                            for (t = a0; t <= a1 && full; ++t) {
                                size_t y = (size_t)(b1 + 1) * o->n[u] + t;
                                full = !used[y] && colh[y] == hv;
                            }
                            if (full) ++b1;
                        }
                        for (t = b0; t <= b1; ++t) memset(used + (size_t)t * o->n[u] + a0, 1, a1 - a0 + 1);
                        if (pass == 1) {
                            float *pt = o->chain_points + 8 * (size_t)count;
                            float u0 = pvs__f_up(o->origin[u] + a0 * h), u1 = pvs__f_down(o->origin[u] + (a1 + 1) * h);
                            float v0 = pvs__f_up(o->origin[v] + b0 * h), v1 = pvs__f_down(o->origin[v] + (b1 + 1) * h);
                            pt[0] = u0; pt[1] = v0; pt[2] = u1; pt[3] = v0; pt[4] = u1; pt[5] = v1; pt[6] = u0; pt[7] = v1;
                            o->chains[count].points = pt;
                            o->chains[count].point_count = 4;
                            o->chains[count].closed = 1;
                            o->chains[count].base = (float)g;
                            o->chains[count].top = hv;
                        }
                        ++count;
                    }
                if (pass == 0) {
                    o->chain_count = count;
                    o->chains = (pvs_facade_chain *)pvs__alloc_array(&a, count ? count : 1, sizeof(pvs_facade_chain));
                    o->chain_points = (float *)pvs__alloc_array(&a, (size_t)(count ? count : 1) * 8, sizeof(float));
                    if (!o->chains || !o->chain_points) break;
                }
            }
            o->info.rect_count = o->chain_count;
        }
    }
    /* 5. 3D erosion by r voxels (Chebyshev; outside the grid and the ground count as empty), then boxes */
    if (o->chains && o->chain_points) {
        for (kk = 0; kk < 3; ++kk) pvs__vx_erode_axis(o, o->eroded, line, kk, r);
        for (vi = 0; vi < total; ++vi) o->info.eroded += o->eroded[vi];
        memcpy(tmp, o->eroded, total);
        o->box_count = pvs__vx_merge(o, tmp, NULL);
        o->boxes = (pvs_box *)pvs__alloc_array(&a, o->box_count ? o->box_count : 1, sizeof(pvs_box));
        if (o->boxes) {
            memcpy(tmp, o->eroded, total);
            pvs__vx_merge(o, tmp, o->boxes);
        }
        o->info.box_count = o->box_count;
    }
    pvs__free_array(&a, tmp, total, 1);
    pvs__free_array(&a, queue, total, sizeof(uint32_t));
    pvs__free_array(&a, line, 1u + o->n[0] + o->n[1] + o->n[2], 1);
    pvs__free_array(&a, colh, cols, sizeof(float));
    if (!o->chains || !o->chain_points || !o->boxes || !o->column_top) {
        pvs_occluders_destroy(o);
        return pvs__fail(err, PVS_ERROR_OUT_OF_MEMORY, -1, 0, "occluder boxes");
    }
    for (kk = 0; kk < 3; ++kk) {
        o->info.dims[kk] = o->n[kk];
        o->info.origin[kk] = (float)o->origin[kk];
    }
    o->info.voxel_size = (float)h;
    o->info.eps = d->eps;
    *out = o;
    pvs__ok(err);
    return PVS_OK;
}

PVS_API void pvs_occluders_get_info(const pvs_occluders *o, pvs_occluders_info *info) { *info = o->info; }
PVS_API uint32_t pvs_occluders_voxel(const pvs_occluders *o, uint32_t i, uint32_t j, uint32_t k) {
    uint8_t st;
    if (i >= o->n[0] || j >= o->n[1] || k >= o->n[2]) return PVS_VOXEL_EMPTY;
    st = o->state[pvs__vx_index(o, i, j, k)];
    return st == PVS__VX_GROUND ? PVS_VOXEL_GROUND : st == PVS__VX_TOUCHED ? PVS_VOXEL_TOUCHED
           : pvs__vx_solid_state(st)                  ? PVS_VOXEL_SOLID
                                                      : PVS_VOXEL_EMPTY;
}
PVS_API int pvs_occluders_eroded_voxel(const pvs_occluders *o, uint32_t i, uint32_t j, uint32_t k) {
    if (i >= o->n[0] || j >= o->n[1] || k >= o->n[2]) return 0;
    return o->eroded[pvs__vx_index(o, i, j, k)] != 0;
}
PVS_API const pvs_box *pvs_occluders_boxes(const pvs_occluders *o, uint32_t *count) {
    if (count) *count = o->box_count;
    return o->boxes;
}
PVS_API const pvs_facade_chain *pvs_occluders_columns(const pvs_occluders *o, uint32_t *count) {
    if (count) *count = o->chain_count;
    return o->chains;
}

// >>vocc
/* ---------------------------------------------------------------------------------------------- */
/* vocc: virtual occluders (Koltun, Chrysanthou, Cohen-Or 2000): aggregate umbrae grown from seeds */
/* along active supporting and separating lines (§3), 2.5D by height slices (§3.1), the greedy    */
/* selection (Fig. 6), five quantized bytes per occluder, the PVS rebuilt on cell entry (§2, §4)  */
/* ---------------------------------------------------------------------------------------------- */
/* The 2D problem (§3). The view cell C is a rectangle; the occluders are opaque segments. Segments
   whose end points coincide exactly and close a ring form a wall loop: a closed curve, so (i) a
   point inside it (odd crossing number) is hidden from every point outside, and (ii) a segment that
   runs from outside the loop's convex hull through the hull to outside it crosses the loop. So a
   loop whose hull misses the cell acts as a solid convex blocker (its hull) for every point outside
   the hull: the "objects" of §3 are these hulls (buildings) and the remaining single segments.

   Conservativeness. A point x is hidden from the cell when every segment from C to x meets a
   blocker. From x, the cell subtends an angular fan; a convex blocker O disjoint from C and not
   containing x covers an angular interval, and along every ray of that interval it lies either
   entirely before C or entirely behind it (two disjoint convex sets seen from one point never swap
   order), so one ray decides. x is hidden when the union of the intervals of the blockers before C
   covers the fan (pvs__vo_hidden). Intervals that end on the same vertex join exactly (walls of an
   open chain); other joins need an overlap beyond a tolerance, so rounding only ever says "not
   hidden". Along a line, the answer changes only where the order of the interval ends changes or
   a blocker starts or stops counting: where the line crosses a common tangent of two objects (or of
   an object and C) whose direction passes through C, or an object's boundary. Between two such
   events one point decides the whole open interval, and the hidden set is closed, so the hidden
   parts of any line are found exactly up to rounding (pvs__vo_line_hidden). Every virtual occluder
   is checked this way, after its final rounding (float, or the file's quantization), against the
   blockers of the aggregate that made it: a subset of the occluders, which is conservative.

   The construction of §3 decides where to look: seeds by the angle they subtend from the cell's
   centre; from a seed, the aggregate grows on both sides along the active supporting line P (the
   outer common tangent of C and the aggregate) and the active separating polyline Q (starting as
   the inner common tangent). An object B met by an active line is tested: (1) B meets the current
   aggregate umbra U (a probe point of B is hidden by the aggregate without B): it augments U, P and
   Q move to it, and a new virtual occluder is placed behind B (found on P), or (3) found on Q, the
   furthest occluder is extended; (2) B meets only Q: it bends Q and joins the aggregate's blockers
   so that later objects can fuse through it. The occluder in use is dumped into the dense set when
   a new one is placed ("periodically dumped", §3). */

#define PVS__VO_NONE 0xffffffffu
#define PVS__VO_MAXH 64u        /* most hull vertices of a loop used as a solid blocker */
#define PVS__VO_ATOL 1e-11      /* pseudo-angle overlap needed to join intervals of different vertices */
#define PVS__VO_RTOL 1e-9       /* lengths: times the context's scale */
#define PVS__VO_MAXG 64u        /* most objects in one aggregate */
#define PVS__VO_MAXSTEP 96u     /* most candidates examined per seed */

typedef struct pvs__vo_key {
    double k;
    uint32_t i;
} pvs__vo_key;

PVS__STATIC int pvs__vo_key_less(const pvs__vo_key *a, const pvs__vo_key *b) { return a->k < b->k || (a->k == b->k && a->i < b->i); }
PVS__STATIC void pvs__vo_sift(pvs__vo_key *o, uint32_t r, uint32_t n) {
    for (;;) {
        uint32_t c = 2 * r + 1;
        pvs__vo_key t;
        if (c >= n) return;
        if (c + 1 < n && pvs__vo_key_less(o + c, o + c + 1)) ++c;
        if (!pvs__vo_key_less(o + r, o + c)) return;
        t = o[r]; o[r] = o[c]; o[c] = t;
        r = c;
    }
}
/* Heap sort by (k, i): deterministic, no libc. */
PVS__STATIC void pvs__vo_sort(pvs__vo_key *o, uint32_t n) {
    uint32_t i;
    if (n < 2) return;
    for (i = n / 2; i-- > 0;) pvs__vo_sift(o, i, n);
    for (i = n - 1; i > 0; --i) {
        pvs__vo_key t = o[0];
        o[0] = o[i]; o[i] = t;
        pvs__vo_sift(o, 0, i);
    }
}

/* Grows a caller array to hold `need` elements (doubling). */
PVS__STATIC int pvs__vo_reserve(const pvs_allocator *a, void **p, uint32_t *cap, size_t need, size_t elem) {
    size_t ncap, bytes;
    void *q;
    if (need <= *cap) return 1;
    if (need > 0x7fffffffu) return 0;
    ncap = *cap ? (size_t)*cap * 2 : 16;
    while (ncap < need) ncap *= 2;
    if (ncap > 0x7fffffffu) ncap = 0x7fffffffu;
    if (!pvs__mul(ncap, elem, &bytes)) return 0;
    q = pvs__alloc(a, bytes, 16);
    if (!q) return 0;
    if (*p) {
        memcpy(q, *p, (size_t)*cap * elem);
        pvs__free(a, *p, (size_t)*cap * elem, 16);
    }
    *p = q;
    *cap = (uint32_t)ncap;
    return 1;
}
#define PVS__VO_FREE(a, p, cap, T) pvs__free((a), (p), (size_t)(cap) * sizeof(T), 16)

PVS__STATIC double pvs__vo_cross(const double *o, const double *a, const double *b) {
    return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0]);
}

/* A monotone stand-in for the angle of direction (cos-like d, sin-like c): (-2, 2], 0 along d. */
PVS__STATIC double pvs__vo_pangle(double d, double c) {
    double den = fabs(c) + fabs(d), p;
    if (!(den > 0.0)) return 0.0;
    p = c / den;
    if (d >= 0.0) return p;
    return c >= 0.0 ? 2.0 - p : -2.0 - p;
}
/* A direction (d, c) of pseudo-angle p in [-1, 1]. */
PVS__STATIC void pvs__vo_pangle_dir(double p, double *d, double *c) {
    *d = 1.0 - fabs(p);
    *c = p;
}

/* ---- the prepared occluders: segments with heights, wall loops, objects, a grid ---- */

typedef struct pvs__vprep {
    pvs_allocator a;
    uint32_t nseg;
    double *seg;          /* nseg x (u0 v0 u1 v1) */
    float *seg_top;       /* nseg */
    uint32_t *seg_vid;    /* nseg x 2 vertex ids (equal ids = the same point exactly) */
    int32_t *seg_loop;    /* the loop of the segment, -1 */
    uint32_t nloop;
    uint32_t *loop_start; /* nloop + 1: ring of loop l is ring_seg / ring_pt [loop_start[l], loop_start[l + 1]) */
    uint32_t *ring_seg;   /* segments in ring order */
    double *ring_pt;      /* ring points (the start of each ring segment) */
    uint32_t *hull_start; /* nloop + 1 into hull_pt, hull_vid (counter-clockwise) */
    double *hull_pt;
    uint32_t *hull_vid;
    float *loop_top;      /* the lowest top of its walls */
    double *loop_bb;      /* 4 per loop */
    uint32_t nobj;        /* objects: the usable loops, then the segments of no usable loop */
    uint32_t *obj_ref;    /* obj < nloop: the loop; else the segment */
    double *obj_bb;       /* 4 per object */
    float *obj_top;
    double bb[4];         /* of everything */
    double g0[2], gcell;  /* bucket grid over the objects */
    uint32_t gw, gh;
    uint32_t *gstart, *gitem;
    size_t gitems;
} pvs__vprep;

PVS__STATIC void pvs__vprep_destroy(pvs__vprep *p) {
    const pvs_allocator *a;
    if (!p) return;
    a = &p->a;
    pvs__free_array(a, p->seg, 4 * (size_t)p->nseg + 4, sizeof(double));
    pvs__free_array(a, p->seg_top, (size_t)p->nseg + 1, sizeof(float));
    pvs__free_array(a, p->seg_vid, 2 * (size_t)p->nseg + 2, sizeof(uint32_t));
    pvs__free_array(a, p->seg_loop, (size_t)p->nseg + 1, sizeof(int32_t));
    pvs__free_array(a, p->loop_start, (size_t)p->nseg + 2, sizeof(uint32_t));
    pvs__free_array(a, p->ring_seg, (size_t)p->nseg + 1, sizeof(uint32_t));
    pvs__free_array(a, p->ring_pt, 2 * (size_t)p->nseg + 2, sizeof(double));
    pvs__free_array(a, p->hull_start, (size_t)p->nseg + 2, sizeof(uint32_t));
    pvs__free_array(a, p->hull_pt, 2 * (size_t)p->nseg + 2, sizeof(double));
    pvs__free_array(a, p->hull_vid, (size_t)p->nseg + 1, sizeof(uint32_t));
    pvs__free_array(a, p->loop_top, (size_t)p->nseg + 1, sizeof(float));
    pvs__free_array(a, p->loop_bb, 4 * (size_t)p->nseg + 4, sizeof(double));
    pvs__free_array(a, p->obj_ref, (size_t)p->nseg + 1, sizeof(uint32_t));
    pvs__free_array(a, p->obj_bb, 4 * (size_t)p->nseg + 4, sizeof(double));
    pvs__free_array(a, p->obj_top, (size_t)p->nseg + 1, sizeof(float));
    pvs__free_array(a, p->gstart, (size_t)p->gw * p->gh + 1, sizeof(uint32_t));
    pvs__free_array(a, p->gitem, p->gitems + 1, sizeof(uint32_t));
    pvs__free(a, p, sizeof(*p), 16);
}

PVS__STATIC void pvs__vo_bb_add(double *bb, const double *p) {
    if (p[0] < bb[0]) bb[0] = p[0];
    if (p[1] < bb[1]) bb[1] = p[1];
    if (p[0] > bb[2]) bb[2] = p[0];
    if (p[1] > bb[3]) bb[3] = p[1];
}

/* Convex hull (Andrew's monotone chain) of n points, counter-clockwise, collinear points dropped;
   idx receives the indices of the hull points. Returns the hull size. keys: n scratch. */
PVS__STATIC uint32_t pvs__vo_hull(const double *pts, uint32_t n, pvs__vo_key *keys, uint32_t *idx) {
    uint32_t i, k = 0, t;
    for (i = 0; i < n; ++i) { keys[i].k = pts[2 * i]; keys[i].i = i; }
    pvs__vo_sort(keys, n); /* by x, then y (ties in x: sort the run by y) */
    for (i = 0; i < n;) {
        uint32_t j = i, m;
        while (j < n && keys[j].k == keys[i].k) ++j;
        for (m = i; m < j; ++m) keys[m].k = pts[2 * keys[m].i + 1];
        pvs__vo_sort(keys + i, j - i);
        for (m = i; m < j; ++m) keys[m].k = pts[2 * keys[m].i];
        i = j;
    }
    if (n < 3) {
        for (i = 0; i < n; ++i) idx[i] = keys[i].i;
        return n;
    }
    for (i = 0; i < n; ++i) { /* lower hull */
        while (k >= 2 && pvs__vo_cross(pts + 2 * idx[k - 2], pts + 2 * idx[k - 1], pts + 2 * keys[i].i) <= 0.0) --k;
        idx[k++] = keys[i].i;
    }
    for (i = n - 1, t = k + 1; i-- > 0;) { /* upper hull */
        while (k >= t && pvs__vo_cross(pts + 2 * idx[k - 2], pts + 2 * idx[k - 1], pts + 2 * keys[i].i) <= 0.0) --k;
        idx[k++] = keys[i].i;
    }
    return k > 1 ? k - 1 : k;
}

/* Builds the prepared occluders from segments (4 doubles each, ground coordinates) with their
   heights: vertex ids by exact coordinates, wall loops (components whose every vertex joins
   exactly two segments), loop hulls, objects and the grid. Zero-length segments are dropped. */
PVS__STATIC pvs_result pvs__vprep_create(const pvs_allocator *al, const double *seg, const float *top, uint32_t n, pvs__vprep **out) {
    pvs__vprep *p;
    pvs__vo_key *keys = NULL;
    uint32_t *deg = NULL, *adj = NULL, *uf = NULL, *idx = NULL, *hidx = NULL, i, nv = 0, m = 0;
    pvs_result r = PVS_ERROR_OUT_OF_MEMORY;
    *out = NULL;
    p = (pvs__vprep *)pvs__alloc(al, sizeof(pvs__vprep), 16);
    if (!p) return PVS_ERROR_OUT_OF_MEMORY;
    memset(p, 0, sizeof(*p));
    p->a = *al;
    for (i = 0; i < n; ++i) m += !(seg[4 * i] == seg[4 * i + 2] && seg[4 * i + 1] == seg[4 * i + 3]);
    p->nseg = m;
    p->seg = (double *)pvs__alloc_array(al, 4 * (size_t)m + 4, sizeof(double));
    p->seg_top = (float *)pvs__alloc_array(al, (size_t)m + 1, sizeof(float));
    p->seg_vid = (uint32_t *)pvs__alloc_array(al, 2 * (size_t)m + 2, sizeof(uint32_t));
    p->seg_loop = (int32_t *)pvs__alloc_array(al, (size_t)m + 1, sizeof(int32_t));
    p->loop_start = (uint32_t *)pvs__alloc_array(al, (size_t)m + 2, sizeof(uint32_t));
    p->ring_seg = (uint32_t *)pvs__alloc_array(al, (size_t)m + 1, sizeof(uint32_t));
    p->ring_pt = (double *)pvs__alloc_array(al, 2 * (size_t)m + 2, sizeof(double));
    p->hull_start = (uint32_t *)pvs__alloc_array(al, (size_t)m + 2, sizeof(uint32_t));
    p->hull_pt = (double *)pvs__alloc_array(al, 2 * (size_t)m + 2, sizeof(double));
    p->hull_vid = (uint32_t *)pvs__alloc_array(al, (size_t)m + 1, sizeof(uint32_t));
    p->loop_top = (float *)pvs__alloc_array(al, (size_t)m + 1, sizeof(float));
    p->loop_bb = (double *)pvs__alloc_array(al, 4 * (size_t)m + 4, sizeof(double));
    p->obj_ref = (uint32_t *)pvs__alloc_array(al, (size_t)m + 1, sizeof(uint32_t));
    p->obj_bb = (double *)pvs__alloc_array(al, 4 * (size_t)m + 4, sizeof(double));
    p->obj_top = (float *)pvs__alloc_array(al, (size_t)m + 1, sizeof(float));
    keys = (pvs__vo_key *)pvs__alloc_array(al, 2 * (size_t)m + 2, sizeof(pvs__vo_key));
    deg = (uint32_t *)pvs__alloc_array(al, 2 * (size_t)m + 2, sizeof(uint32_t));
    adj = (uint32_t *)pvs__alloc_array(al, 4 * (size_t)m + 4, sizeof(uint32_t));
    uf = (uint32_t *)pvs__alloc_array(al, 2 * (size_t)m + 2, sizeof(uint32_t));
    idx = (uint32_t *)pvs__alloc_array(al, 2 * (size_t)m + 2, sizeof(uint32_t));
    hidx = (uint32_t *)pvs__alloc_array(al, 2 * (size_t)m + 2, sizeof(uint32_t));
    if (!p->seg || !p->seg_top || !p->seg_vid || !p->seg_loop || !p->loop_start || !p->ring_seg || !p->ring_pt || !p->hull_start ||
        !p->hull_pt || !p->hull_vid || !p->loop_top || !p->loop_bb || !p->obj_ref || !p->obj_bb || !p->obj_top || !keys || !deg ||
        !adj || !uf || !idx || !hidx)
        goto done;
    for (i = 0, m = 0; i < n; ++i) {
        if (seg[4 * i] == seg[4 * i + 2] && seg[4 * i + 1] == seg[4 * i + 3]) continue;
        memcpy(p->seg + 4 * (size_t)m, seg + 4 * (size_t)i, 4 * sizeof(double));
        p->seg_top[m++] = top[i];
    }
    /* vertex ids: sort the 2m end points by (x, y) */
    for (i = 0; i < 2 * m; ++i) { keys[i].k = p->seg[2 * i]; keys[i].i = i; }
    pvs__vo_sort(keys, 2 * m);
    for (i = 0; i < 2 * m;) {
        uint32_t j = i, t;
        while (j < 2 * m && keys[j].k == keys[i].k) ++j;
        for (t = i; t < j; ++t) keys[t].k = p->seg[2 * keys[t].i + 1];
        pvs__vo_sort(keys + i, j - i);
        for (t = i; t < j; ++t) {
            if (t > i && keys[t].k != keys[t - 1].k) ++nv;
            p->seg_vid[keys[t].i] = nv;
        }
        ++nv;
        i = j;
    }
    for (i = 0; i < nv; ++i) { deg[i] = 0; uf[i] = i; }
    for (i = 0; i < m; ++i) {
        uint32_t e;
        for (e = 0; e < 2; ++e) {
            uint32_t v = p->seg_vid[2 * i + e];
            if (deg[v] < 2) adj[2 * v + deg[v]] = i;
            ++deg[v];
        }
        { /* union the two end vertices */
            uint32_t x = p->seg_vid[2 * i], y = p->seg_vid[2 * i + 1];
            while (uf[x] != x) x = uf[x] = uf[uf[x]];
            while (uf[y] != y) y = uf[y] = uf[uf[y]];
            if (x != y) uf[x < y ? y : x] = x < y ? x : y;
        }
    }
    for (i = 0; i < m; ++i) p->seg_loop[i] = -1;
    /* a component is a loop when all its vertices have degree 2: walk it from its lowest segment */
    for (i = 0; i < nv; ++i) { /* component root -> bad flag in idx */
        uint32_t x = i;
        while (uf[x] != x) x = uf[x];
        uf[i] = x;
    }
    for (i = 0; i < nv; ++i) idx[i] = 0;
    for (i = 0; i < nv; ++i)
        if (deg[i] != 2) idx[uf[i]] = 1;
    p->nloop = 0;
    p->loop_start[0] = 0;
    {
        uint32_t ring = 0, h = 0;
        for (i = 0; i < m; ++i) {
            uint32_t root = uf[p->seg_vid[2 * i]], s, v, count = 0, l, hn, k;
            if (idx[root] || p->seg_loop[i] >= 0) continue;
            l = p->nloop;
            s = i;
            v = p->seg_vid[2 * i];
            do { /* from vertex v along segment s */
                uint32_t w = p->seg_vid[2 * s] == v ? p->seg_vid[2 * s + 1] : p->seg_vid[2 * s];
                const double *pt = p->seg + 4 * (size_t)s + (p->seg_vid[2 * s] == v ? 0 : 2);
                p->seg_loop[s] = (int32_t)l;
                p->ring_seg[ring + count] = s;
                p->ring_pt[2 * (ring + count)] = pt[0];
                p->ring_pt[2 * (ring + count) + 1] = pt[1];
                ++count;
                v = w;
                s = adj[2 * v] == s ? adj[2 * v + 1] : adj[2 * v];
            } while (s != i && count <= m);
            if (count < 3) { /* two segments joining the same two points: not a ring with an inside */
                for (k = 0; k < count; ++k) p->seg_loop[p->ring_seg[ring + k]] = -1;
                idx[root] = 1;
                continue;
            }
            p->loop_top[l] = FLT_MAX;
            p->loop_bb[4 * l] = p->loop_bb[4 * l + 1] = DBL_MAX;
            p->loop_bb[4 * l + 2] = p->loop_bb[4 * l + 3] = -DBL_MAX;
            for (k = 0; k < count; ++k) {
                if (p->seg_top[p->ring_seg[ring + k]] < p->loop_top[l]) p->loop_top[l] = p->seg_top[p->ring_seg[ring + k]];
                pvs__vo_bb_add(p->loop_bb + 4 * l, p->ring_pt + 2 * (ring + k));
            }
            hn = pvs__vo_hull(p->ring_pt + 2 * ring, count, keys, hidx);
            p->hull_start[l] = h;
            /* ring point q starts ring segment q: its id is the vertex q shares with segment q - 1 */
            for (k = 0; k < hn; ++k) {
                uint32_t q = hidx[k], sq = p->ring_seg[ring + q], sp = p->ring_seg[ring + (q + count - 1) % count];
                uint32_t a0 = p->seg_vid[2 * sq], a1 = p->seg_vid[2 * sq + 1];
                p->hull_pt[2 * (h + k)] = p->ring_pt[2 * (ring + q)];
                p->hull_pt[2 * (h + k) + 1] = p->ring_pt[2 * (ring + q) + 1];
                p->hull_vid[h + k] = (a0 == p->seg_vid[2 * sp] || a0 == p->seg_vid[2 * sp + 1]) ? a0 : a1;
            }
            h += hn;
            ring += count;
            p->loop_start[++p->nloop] = ring;
            p->hull_start[p->nloop] = h;
        }
    }
    /* objects: loops with a usable hull, then every segment of no such loop */
    p->nobj = 0;
    for (i = 0; i < p->nloop; ++i) {
        uint32_t hn = p->hull_start[i + 1] - p->hull_start[i];
        if (hn < 3 || hn > PVS__VO_MAXH) continue;
        p->obj_ref[p->nobj] = i;
        memcpy(p->obj_bb + 4 * (size_t)p->nobj, p->loop_bb + 4 * (size_t)i, 4 * sizeof(double));
        p->obj_top[p->nobj++] = p->loop_top[i];
    }
    for (i = 0; i < m; ++i) {
        int32_t l = p->seg_loop[i];
        if (l >= 0) {
            uint32_t hn = p->hull_start[l + 1] - p->hull_start[l];
            if (hn >= 3 && hn <= PVS__VO_MAXH) continue;
        }
        p->obj_ref[p->nobj] = p->nloop + i;
        p->obj_bb[4 * (size_t)p->nobj] = p->obj_bb[4 * (size_t)p->nobj + 1] = DBL_MAX;
        p->obj_bb[4 * (size_t)p->nobj + 2] = p->obj_bb[4 * (size_t)p->nobj + 3] = -DBL_MAX;
        pvs__vo_bb_add(p->obj_bb + 4 * (size_t)p->nobj, p->seg + 4 * (size_t)i);
        pvs__vo_bb_add(p->obj_bb + 4 * (size_t)p->nobj, p->seg + 4 * (size_t)i + 2);
        p->obj_top[p->nobj++] = p->seg_top[i];
    }
    /* the bucket grid: about two objects per bucket, at most 1024 x 1024 */
    p->bb[0] = p->bb[1] = DBL_MAX;
    p->bb[2] = p->bb[3] = -DBL_MAX;
    for (i = 0; i < p->nobj; ++i) {
        pvs__vo_bb_add(p->bb, p->obj_bb + 4 * (size_t)i);
        pvs__vo_bb_add(p->bb, p->obj_bb + 4 * (size_t)i + 2);
    }
    if (!p->nobj) { p->bb[0] = p->bb[1] = 0.0; p->bb[2] = p->bb[3] = 1.0; }
    {
        double w = p->bb[2] - p->bb[0], hh = p->bb[3] - p->bb[1], cs = sqrt((w * hh > 0.0 ? w * hh : (w + hh) * (w + hh) + 1.0) / (0.5 * (p->nobj + 1)));
        size_t total = 0, cells;
        uint32_t j;
        if (!(cs > 0.0)) cs = 1.0;
        if (w / cs > 1024.0) cs = w / 1024.0;
        if (hh / cs > 1024.0) cs = hh / 1024.0;
        p->gcell = cs;
        p->g0[0] = p->bb[0];
        p->g0[1] = p->bb[1];
        p->gw = (uint32_t)(w / cs) + 1;
        p->gh = (uint32_t)(hh / cs) + 1;
        cells = (size_t)p->gw * p->gh;
        p->gstart = (uint32_t *)pvs__alloc_array(al, cells + 1, sizeof(uint32_t));
        if (!p->gstart) goto done;
        memset(p->gstart, 0, (cells + 1) * sizeof(uint32_t));
        for (j = 0; j < 2; ++j) {
            for (i = 0; i < p->nobj; ++i) {
                const double *b = p->obj_bb + 4 * (size_t)i;
                uint32_t x0 = (uint32_t)((b[0] - p->g0[0]) / cs), y0 = (uint32_t)((b[1] - p->g0[1]) / cs);
                uint32_t x1 = (uint32_t)((b[2] - p->g0[0]) / cs), y1 = (uint32_t)((b[3] - p->g0[1]) / cs), x, y;
                if (x1 >= p->gw) x1 = p->gw - 1;
                if (y1 >= p->gh) y1 = p->gh - 1;
                if (p->obj_ref[i] >= p->nloop && (uint64_t)(x1 - x0 + 1) * (y1 - y0 + 1) > 16) {
                    /* a long wall: the buckets along it (samples a quarter bucket apart), not its box; a
                       bucket missed only hides the wall from the growth's search (never from a check) */
                    const double *sg = p->seg + 4 * (size_t)(p->obj_ref[i] - p->nloop);
                    double len = sqrt((sg[2] - sg[0]) * (sg[2] - sg[0]) + (sg[3] - sg[1]) * (sg[3] - sg[1]));
                    uint32_t steps = (uint32_t)(4.0 * len / cs) + 1, t, last = 0xffffffffu;
                    for (t = 0; t <= steps; ++t) {
                        double u = (double)t / steps;
                        uint32_t bx = (uint32_t)((sg[0] + u * (sg[2] - sg[0]) - p->g0[0]) / cs), by = (uint32_t)((sg[1] + u * (sg[3] - sg[1]) - p->g0[1]) / cs), at;
                        if (bx >= p->gw) bx = p->gw - 1;
                        if (by >= p->gh) by = p->gh - 1;
                        at = by * p->gw + bx;
                        if (at == last) continue;
                        last = at;
                        if (j) p->gitem[--p->gstart[(size_t)at + 1]] = i;
                        else ++total, ++p->gstart[(size_t)at + 1];
                    }
                    continue;
                }
                for (y = y0; y <= y1; ++y)
                    for (x = x0; x <= x1; ++x) {
                        if (j) p->gitem[--p->gstart[(size_t)y * p->gw + x + 1]] = i;
                        else ++total, ++p->gstart[(size_t)y * p->gw + x + 1];
                    }
            }
            if (!j) {
                size_t c2;
                p->gitems = total;
                p->gitem = (uint32_t *)pvs__alloc_array(al, total + 1, sizeof(uint32_t));
                if (!p->gitem) goto done;
                /* prefix sums: gstart[c + 1] is the end of bucket c; filling decrements it to its start */
                for (c2 = 0; c2 < cells; ++c2) p->gstart[c2 + 1] += p->gstart[c2];
            }
        }
        /* ... so after filling, gstart[c + 1] is the start of bucket c: shift back into place */
        for (i = 0; i < (uint32_t)cells; ++i) p->gstart[i] = p->gstart[i + 1];
        p->gstart[cells] = (uint32_t)total;
    }
    r = PVS_OK;
done:
    pvs__free_array(al, keys, 2 * (size_t)m + 2, sizeof(pvs__vo_key));
    pvs__free_array(al, deg, 2 * (size_t)m + 2, sizeof(uint32_t));
    pvs__free_array(al, adj, 4 * (size_t)m + 4, sizeof(uint32_t));
    pvs__free_array(al, uf, 2 * (size_t)m + 2, sizeof(uint32_t));
    pvs__free_array(al, idx, 2 * (size_t)m + 2, sizeof(uint32_t));
    pvs__free_array(al, hidx, 2 * (size_t)m + 2, sizeof(uint32_t));
    if (r != PVS_OK) {
        p->nseg = m; /* sizes for the frees */
        pvs__vprep_destroy(p);
        return r;
    }
    *out = p;
    return PVS_OK;
}

/* ---- one cell and one height slice: blockers in the cell's frame (centre at the origin) ---- */

typedef struct pvs__vobj {
    uint32_t first, n;      /* vertices vx[first .. first + n): n = 2 a segment, else a counter-clockwise hull */
    int32_t loop;           /* the wall loop of a hull (inside test), -1 */
    uint32_t mark, visit;   /* growth and query stamps */
    uint32_t used;          /* already in an aggregate of this slice (not a seed again) */
    double bb[4];
    double angle;           /* subtended from the cell's centre: the seed order */
} pvs__vobj;

typedef struct pvs__vo_span {
    double s, e;            /* pseudo-angles */
    uint32_t is, ie;        /* vertex ids of the ends (PVS__VO_NONE: none) */
} pvs__vo_span;

/* A virtual occluder of the dense set: end points in the cell's frame as rounded (exactly what was
   checked), the stored bytes and heights. */
typedef struct pvs__vo_cand {
    double a[2], b[2];
    float f[4];             /* pvs_vocc_2d: the world end points */
    uint8_t q[5];           /* the file's bytes */
} pvs__vo_cand;

typedef struct pvs__vo_side {
    double po[2], pd[2];    /* active supporting line: the aggregate's vertex, direction away from the cell */
    double qo[2], qd[2];    /* active separating line: the polyline's last vertex and direction */
    int done;
} pvs__vo_side;

typedef struct pvs__vo_cur {
    double p[2], d[2];      /* the line p + t d (d unit) */
    double t0, t1;          /* the occluder's interval on it */
    int valid;
} pvs__vo_cur;

typedef struct pvs__vctx {
    const pvs_allocator *al;
    const pvs__vprep *p;
    double centre[2];       /* world coordinates of the frame's origin */
    double cmin[2], cmax[2], corner[8];
    double scale, tol, range;
    float h;                /* the slice height */
    pvs__vobj *obj;
    uint32_t nobj, capobj;
    double *vx;
    uint32_t *vid;
    uint32_t nvx, capvx, capvid;
    uint32_t *pfirst, *pcount; /* per prep object: its blockers in this slice */
    uint32_t epoch, visit;
    uint32_t *g, ng, capg;     /* the aggregate's blockers */
    uint32_t *k, nk, capk;     /* the objects fused into its umbra (seed, cases 1 and 3) */
    double *lines;             /* event lines of the aggregate: 4 doubles each */
    uint32_t nlines, caplines;
    pvs__vo_span *span;
    uint32_t capspan;
    pvs__vo_key *ev;
    uint32_t capev;
    uint32_t *sub, capsub;
    double *iv;
    uint32_t capiv;
    double *pts;
    uint32_t cappts;
    pvs__vo_key *hkeys;
    uint32_t caphkeys;
    uint32_t *hidx, caphidx;
    /* output: the dense set */
    int quantize;              /* 0: float end points (pvs_vocc_2d); 1: the file's bytes */
    double qscale, qground, qhstep; /* quantization (>>vocc file notes) */
    pvs__vo_cand *out;
    uint32_t nout, capout;
    uint32_t max_seeds;
    pvs_vocc_stats st;
    int oom;
} pvs__vctx;

PVS__STATIC void pvs__vctx_free(pvs__vctx *c) {
    const pvs_allocator *a = c->al;
    PVS__VO_FREE(a, c->obj, c->capobj, pvs__vobj);
    PVS__VO_FREE(a, c->vx, c->capvx, double);
    PVS__VO_FREE(a, c->vid, c->capvid, uint32_t);
    if (c->p) {
        pvs__free_array(a, c->pfirst, (size_t)c->p->nobj + 1, sizeof(uint32_t));
        pvs__free_array(a, c->pcount, (size_t)c->p->nobj + 1, sizeof(uint32_t));
    }
    PVS__VO_FREE(a, c->g, c->capg, uint32_t);
    PVS__VO_FREE(a, c->k, c->capk, uint32_t);
    PVS__VO_FREE(a, c->lines, c->caplines, double);
    PVS__VO_FREE(a, c->span, c->capspan, pvs__vo_span);
    PVS__VO_FREE(a, c->ev, c->capev, pvs__vo_key);
    PVS__VO_FREE(a, c->sub, c->capsub, uint32_t);
    PVS__VO_FREE(a, c->iv, c->capiv, double);
    PVS__VO_FREE(a, c->pts, c->cappts, double);
    PVS__VO_FREE(a, c->hkeys, c->caphkeys, pvs__vo_key);
    PVS__VO_FREE(a, c->hidx, c->caphidx, uint32_t);
    PVS__VO_FREE(a, c->out, c->capout, pvs__vo_cand);
    memset(c, 0, sizeof(*c));
}

/* Sets up the frame of a cell (ground rectangle, world coordinates) over prepared occluders. */
PVS__STATIC int pvs__vctx_init(pvs__vctx *c, const pvs_allocator *al, const pvs__vprep *p, const double cmin[2], const double cmax[2],
                               double range) {
    int k;
    double ext = 1.0;
    memset(c, 0, sizeof(*c));
    c->al = al;
    c->p = p;
    for (k = 0; k < 2; ++k) {
        c->centre[k] = 0.5 * cmin[k] + 0.5 * cmax[k];
        c->cmin[k] = cmin[k] - c->centre[k];
        c->cmax[k] = cmax[k] - c->centre[k];
    }
    c->corner[0] = c->cmin[0]; c->corner[1] = c->cmin[1];
    c->corner[2] = c->cmax[0]; c->corner[3] = c->cmin[1];
    c->corner[4] = c->cmax[0]; c->corner[5] = c->cmax[1];
    c->corner[6] = c->cmin[0]; c->corner[7] = c->cmax[1];
    for (k = 0; k < 4; ++k) { /* the frame's extent: the occluders and the cell */
        double v = fabs(p->bb[k] - c->centre[k & 1]);
        if (v > ext) ext = v;
    }
    if (fabs(c->cmax[0]) > ext) ext = fabs(c->cmax[0]);
    if (fabs(c->cmax[1]) > ext) ext = fabs(c->cmax[1]);
    c->scale = ext;
    c->tol = PVS__VO_RTOL * ext;
    c->range = range > 0.0 ? range : 4.0 * ext;
    c->pfirst = (uint32_t *)pvs__alloc_array(al, (size_t)p->nobj + 1, sizeof(uint32_t));
    c->pcount = (uint32_t *)pvs__alloc_array(al, (size_t)p->nobj + 1, sizeof(uint32_t));
    if (!c->pfirst || !c->pcount) { c->oom = 1; return 0; }
    return 1;
}

/* 1 if segment a-b meets the cell grown by tol. */
PVS__STATIC int pvs__vo_seg_meets_cell(const pvs__vctx *c, const double *a, const double *b) {
    double t0 = 0.0, t1 = 1.0, d[2];
    int k;
    d[0] = b[0] - a[0];
    d[1] = b[1] - a[1];
    for (k = 0; k < 2; ++k) {
        double lo = c->cmin[k] - c->tol, hi = c->cmax[k] + c->tol;
        if (d[k] == 0.0) {
            if (a[k] < lo || a[k] > hi) return 0;
        } else {
            double u0 = (lo - a[k]) / d[k], u1 = (hi - a[k]) / d[k];
            if (u0 > u1) { double t = u0; u0 = u1; u1 = t; }
            if (u0 > t0) t0 = u0;
            if (u1 < t1) t1 = u1;
            if (t0 > t1) return 0;
        }
    }
    return 1;
}
/* 1 if the counter-clockwise convex polygon v (n >= 3) meets the cell grown by tol (separating axes). */
PVS__STATIC int pvs__vo_poly_meets_cell(const pvs__vctx *c, const double *v, uint32_t n) {
    double lo[2] = {DBL_MAX, DBL_MAX}, hi[2] = {-DBL_MAX, -DBL_MAX};
    uint32_t i, k;
    for (i = 0; i < n; ++i)
        for (k = 0; k < 2; ++k) {
            if (v[2 * i + k] < lo[k]) lo[k] = v[2 * i + k];
            if (v[2 * i + k] > hi[k]) hi[k] = v[2 * i + k];
        }
    for (k = 0; k < 2; ++k)
        if (lo[k] > c->cmax[k] + c->tol || hi[k] < c->cmin[k] - c->tol) return 0;
    for (i = 0; i < n; ++i) { /* an edge with every corner strictly outside */
        const double *a = v + 2 * i, *b = v + 2 * ((i + 1) % n);
        double len = sqrt((b[0] - a[0]) * (b[0] - a[0]) + (b[1] - a[1]) * (b[1] - a[1]));
        int j, out = 1;
        for (j = 0; j < 4 && out; ++j) out = pvs__vo_cross(a, b, c->corner + 2 * j) < -c->tol * len;
        if (out) return 0;
    }
    return 1;
}

PVS__STATIC uint32_t pvs__vo_add_obj(pvs__vctx *c, const double *pts, const uint32_t *ids, uint32_t n, int32_t loop) {
    pvs__vobj *o;
    uint32_t i, lo = 0, hi = 0;
    double origin[2] = {0.0, 0.0};
    if (!pvs__vo_reserve(c->al, (void **)&c->obj, &c->capobj, (size_t)c->nobj + 1, sizeof(pvs__vobj)) ||
        !pvs__vo_reserve(c->al, (void **)&c->vx, &c->capvx, 2 * ((size_t)c->nvx + n), sizeof(double)) ||
        !pvs__vo_reserve(c->al, (void **)&c->vid, &c->capvid, (size_t)c->nvx + n, sizeof(uint32_t))) {
        c->oom = 1;
        return PVS__VO_NONE;
    }
    o = c->obj + c->nobj;
    memset(o, 0, sizeof(*o));
    o->first = c->nvx;
    o->n = n;
    o->loop = loop;
    o->bb[0] = o->bb[1] = DBL_MAX;
    o->bb[2] = o->bb[3] = -DBL_MAX;
    for (i = 0; i < n; ++i) {
        double *q = c->vx + 2 * ((size_t)c->nvx + i);
        q[0] = pts[2 * i] - c->centre[0];
        q[1] = pts[2 * i + 1] - c->centre[1];
        c->vid[c->nvx + i] = ids[i];
        pvs__vo_bb_add(o->bb, q);
    }
    for (i = 1; i < n; ++i) { /* the tangent vertices from the centre: the subtended angle */
        const double *q = c->vx + 2 * ((size_t)c->nvx + i);
        if (pvs__vo_cross(origin, c->vx + 2 * ((size_t)c->nvx + lo), q) < 0.0) lo = i;
        if (pvs__vo_cross(origin, c->vx + 2 * ((size_t)c->nvx + hi), q) > 0.0) hi = i;
    }
    {
        const double *a = c->vx + 2 * ((size_t)c->nvx + lo), *b = c->vx + 2 * ((size_t)c->nvx + hi);
        o->angle = atan2(a[0] * b[1] - a[1] * b[0], a[0] * b[0] + a[1] * b[1]);
        if (o->angle < 0.0) o->angle = 0.0;
    }
    c->nvx += n;
    return c->nobj++;
}

/* The blockers of slice height h: loops reaching h whose hull misses the cell as hulls; every other
   wall reaching h as a segment unless it meets the cell. */
PVS__STATIC int pvs__vctx_slice(pvs__vctx *c, float h) {
    const pvs__vprep *p = c->p;
    uint32_t i, j;
    double loc[2 * PVS__VO_MAXH];
    c->h = h;
    c->nobj = c->nvx = 0;
    for (i = 0; i < p->nobj && !c->oom; ++i) {
        uint32_t ref = p->obj_ref[i];
        c->pfirst[i] = c->nobj;
        c->pcount[i] = 0;
        if (ref < p->nloop) {
            uint32_t hs = p->hull_start[ref], hn = p->hull_start[ref + 1] - hs;
            if (p->loop_top[ref] >= h) {
                for (j = 0; j < hn; ++j) {
                    loc[2 * j] = p->hull_pt[2 * (hs + j)] - c->centre[0];
                    loc[2 * j + 1] = p->hull_pt[2 * (hs + j) + 1] - c->centre[1];
                }
                if (!pvs__vo_poly_meets_cell(c, loc, hn)) {
                    pvs__vo_add_obj(c, p->hull_pt + 2 * hs, p->hull_vid + hs, hn, (int32_t)ref);
                    c->pcount[i] = c->nobj - c->pfirst[i];
                    continue;
                }
            }
            for (j = p->loop_start[ref]; j < p->loop_start[ref + 1]; ++j) { /* its walls one by one */
                uint32_t s = p->ring_seg[j];
                double a[2], b[2];
                if (p->seg_top[s] < h) continue;
                a[0] = p->seg[4 * s] - c->centre[0]; a[1] = p->seg[4 * s + 1] - c->centre[1];
                b[0] = p->seg[4 * s + 2] - c->centre[0]; b[1] = p->seg[4 * s + 3] - c->centre[1];
                if (!pvs__vo_seg_meets_cell(c, a, b)) pvs__vo_add_obj(c, p->seg + 4 * s, p->seg_vid + 2 * s, 2, -1);
            }
        } else {
            uint32_t s = ref - p->nloop;
            double a[2], b[2];
            if (p->seg_top[s] >= h) {
                a[0] = p->seg[4 * s] - c->centre[0]; a[1] = p->seg[4 * s + 1] - c->centre[1];
                b[0] = p->seg[4 * s + 2] - c->centre[0]; b[1] = p->seg[4 * s + 3] - c->centre[1];
                if (!pvs__vo_seg_meets_cell(c, a, b)) pvs__vo_add_obj(c, p->seg + 4 * s, p->seg_vid + 2 * s, 2, -1);
            }
        }
        c->pcount[i] = c->nobj - c->pfirst[i];
    }
    return !c->oom;
}

/* ---- exact hidden tests ---- */

/* 1 if x lies inside wall loop l (odd crossing number) farther than tol from its walls. The cell is
   outside every loop used this way (its hull misses the cell). */
PVS__STATIC int pvs__vo_in_loop(const pvs__vctx *c, uint32_t l, const double *x) {
    const pvs__vprep *p = c->p;
    uint32_t s = p->loop_start[l], n = p->loop_start[l + 1] - s, i, odd = 0;
    double px = x[0] + c->centre[0], py = x[1] + c->centre[1];
    for (i = 0; i < n; ++i) {
        const double *a = p->ring_pt + 2 * (s + i), *b = p->ring_pt + 2 * (s + (i + 1) % n);
        double ex = b[0] - a[0], ey = b[1] - a[1], l2 = ex * ex + ey * ey, u, dx, dy;
        u = l2 > 0.0 ? ((px - a[0]) * ex + (py - a[1]) * ey) / l2 : 0.0;
        if (u < 0.0) u = 0.0;
        if (u > 1.0) u = 1.0;
        dx = a[0] + u * ex - px;
        dy = a[1] + u * ey - py;
        if (dx * dx + dy * dy <= c->tol * c->tol) return 0;
        if ((a[1] > py) != (b[1] > py) && px < a[0] + (py - a[1]) * ex / ey) odd ^= 1u;
    }
    return (int)odd;
}

/* Entry distance of the ray x + s w into object o (convex polygon or segment), -1 when it misses. */
PVS__STATIC double pvs__vo_ray_obj(const pvs__vctx *c, const pvs__vobj *o, const double *x, const double *w) {
    const double *v = c->vx + 2 * (size_t)o->first;
    if (o->n == 2) {
        double ex = v[2] - v[0], ey = v[3] - v[1], den = w[0] * ey - w[1] * ex, qx = v[0] - x[0], qy = v[1] - x[1], s, u;
        if (den == 0.0) return -1.0;
        s = (qx * ey - qy * ex) / den;
        u = (qx * w[1] - qy * w[0]) / den;
        if (s < 0.0 || u < 0.0 || u > 1.0) return -1.0;
        return s;
    } else {
        double s0 = 0.0, s1 = DBL_MAX;
        uint32_t i;
        for (i = 0; i < o->n; ++i) {
            const double *a = v + 2 * i, *b = v + 2 * ((i + 1) % o->n);
            double nx = b[1] - a[1], ny = a[0] - b[0]; /* outward normal of a counter-clockwise edge */
            double f = nx * (x[0] - a[0]) + ny * (x[1] - a[1]), g = nx * w[0] + ny * w[1];
            if (g == 0.0) {
                if (f > 0.0) return -1.0;
            } else {
                double u = -f / g;
                if (g < 0.0) { if (u > s0) s0 = u; }
                else if (u < s1) s1 = u;
            }
        }
        return s0 <= s1 ? s0 : -1.0;
    }
}
/* Entry distance of the ray into the cell, -1 when it misses. */
PVS__STATIC double pvs__vo_ray_cell(const pvs__vctx *c, const double *x, const double *w) {
    double s0 = 0.0, s1 = DBL_MAX;
    int k;
    for (k = 0; k < 2; ++k) {
        if (w[k] == 0.0) {
            if (x[k] < c->cmin[k] || x[k] > c->cmax[k]) return -1.0;
        } else {
            double u0 = (c->cmin[k] - x[k]) / w[k], u1 = (c->cmax[k] - x[k]) / w[k];
            if (u0 > u1) { double t = u0; u0 = u1; u1 = t; }
            if (u0 > s0) s0 = u0;
            if (u1 < s1) s1 = u1;
        }
    }
    return s0 <= s1 ? s0 : -1.0;
}

/* 1 if x is inside convex object o or within tol of it (then o cannot be used from x). */
PVS__STATIC int pvs__vo_near_obj(const pvs__vctx *c, const pvs__vobj *o, const double *x) {
    const double *v = c->vx + 2 * (size_t)o->first;
    uint32_t i;
    if (o->n == 2) {
        double ex = v[2] - v[0], ey = v[3] - v[1], l2 = ex * ex + ey * ey, u, dx, dy;
        u = l2 > 0.0 ? ((x[0] - v[0]) * ex + (x[1] - v[1]) * ey) / l2 : 0.0;
        if (u < 0.0) u = 0.0;
        if (u > 1.0) u = 1.0;
        dx = v[0] + u * ex - x[0];
        dy = v[1] + u * ey - x[1];
        return dx * dx + dy * dy <= c->tol * c->tol;
    }
    for (i = 0; i < o->n; ++i) {
        const double *a = v + 2 * i, *b = v + 2 * ((i + 1) % o->n);
        double len = sqrt((b[0] - a[0]) * (b[0] - a[0]) + (b[1] - a[1]) * (b[1] - a[1]));
        if (pvs__vo_cross(a, b, x) < -c->tol * len) return 0;
    }
    return 1;
}

/* The from-point test of the header comment: 1 if every segment from the cell to x meets one of the
   blockers set[0..n). Rounding only ever answers 0. */
PVS__STATIC int pvs__vo_hidden(pvs__vctx *c, const uint32_t *set, uint32_t n, const double *x) {
    const double *cl, *ch;
    double f[2], len, aL, aR, bb[4], tol = c->tol, reach;
    uint32_t i, k, ns = 0, rid;
    if (x[0] > c->cmin[0] - tol && x[0] < c->cmax[0] + tol && x[1] > c->cmin[1] - tol && x[1] < c->cmax[1] + tol) return 0;
    if (!pvs__vo_reserve(c->al, (void **)&c->span, &c->capspan, 2 * (size_t)n + 2, sizeof(pvs__vo_span))) {
        c->oom = 1;
        return 0;
    }
    cl = ch = c->corner;
    for (k = 1; k < 4; ++k) { /* the fan: its extreme corners (every direction within a half-plane) */
        const double *q = c->corner + 2 * k;
        if (pvs__vo_cross(x, cl, q) < 0.0) cl = q;
        if (pvs__vo_cross(x, ch, q) > 0.0) ch = q;
    }
    {
        double a0 = cl[0] - x[0], a1 = cl[1] - x[1], b0 = ch[0] - x[0], b1 = ch[1] - x[1];
        double la = sqrt(a0 * a0 + a1 * a1), lb = sqrt(b0 * b0 + b1 * b1);
        f[0] = a0 / la + b0 / lb;
        f[1] = a1 / la + b1 / lb;
        len = sqrt(f[0] * f[0] + f[1] * f[1]);
        if (!(len > 0.0)) return 0;
        f[0] /= len;
        f[1] /= len;
        aL = pvs__vo_pangle(f[0] * a0 + f[1] * a1, f[0] * a1 - f[1] * a0);
        aR = pvs__vo_pangle(f[0] * b0 + f[1] * b1, f[0] * b1 - f[1] * b0);
    }
    bb[0] = (x[0] < c->cmin[0] ? x[0] : c->cmin[0]) - tol;
    bb[1] = (x[1] < c->cmin[1] ? x[1] : c->cmin[1]) - tol;
    bb[2] = (x[0] > c->cmax[0] ? x[0] : c->cmax[0]) + tol;
    bb[3] = (x[1] > c->cmax[1] ? x[1] : c->cmax[1]) + tol;
    for (i = 0; i < n; ++i) {
        const pvs__vobj *o = c->obj + set[i];
        const double *v = c->vx + 2 * (size_t)o->first;
        uint32_t lo = 0, hi = 0, j, pieces;
        double plo, phi, sp[2][2];
        int near_box;
        if (o->loop >= 0 && x[0] >= o->bb[0] && x[0] <= o->bb[2] && x[1] >= o->bb[1] && x[1] <= o->bb[3] &&
            pvs__vo_in_loop(c, (uint32_t)o->loop, x))
            return 1;
        if (o->bb[0] > bb[2] || o->bb[2] < bb[0] || o->bb[1] > bb[3] || o->bb[3] < bb[1]) continue;
        { /* a box wholly outside the fan (beyond one of its edge lines) cannot help */
            /* cross(x, q, p) = e0 p1 - e1 p0 - e0 x1 + e1 x0 with e = q - x: linear in p, so its extremes
               over the box come from its corners (support functions) */
            double e0 = cl[0] - x[0], e1 = cl[1] - x[1], g0 = ch[0] - x[0], g1 = ch[1] - x[1], mx, mn;
            mx = (e0 > 0.0 ? e0 * o->bb[3] : e0 * o->bb[1]) + (e1 > 0.0 ? -e1 * o->bb[0] : -e1 * o->bb[2]) - e0 * x[1] + e1 * x[0];
            if (mx < -tol * (fabs(e0) + fabs(e1))) continue; /* wholly clockwise of the fan's edge x -> cl */
            mn = (g0 > 0.0 ? g0 * o->bb[1] : g0 * o->bb[3]) + (g1 > 0.0 ? -g1 * o->bb[2] : -g1 * o->bb[0]) - g0 * x[1] + g1 * x[0];
            if (mn > tol * (fabs(g0) + fabs(g1))) continue; /* wholly counter-clockwise of x -> ch */
        }
        near_box = x[0] >= o->bb[0] - tol && x[0] <= o->bb[2] + tol && x[1] >= o->bb[1] - tol && x[1] <= o->bb[3] + tol;
        if (near_box && pvs__vo_near_obj(c, o, x)) continue;
        for (j = 1; j < o->n; ++j) {
            if (pvs__vo_cross(x, v + 2 * lo, v + 2 * j) < 0.0) lo = j;
            if (pvs__vo_cross(x, v + 2 * hi, v + 2 * j) > 0.0) hi = j;
        }
        {
            double a0 = v[2 * lo] - x[0], a1 = v[2 * lo + 1] - x[1], b0 = v[2 * hi] - x[0], b1 = v[2 * hi + 1] - x[1];
            plo = pvs__vo_pangle(f[0] * a0 + f[1] * a1, f[0] * a1 - f[1] * a0);
            phi = pvs__vo_pangle(f[0] * b0 + f[1] * b1, f[0] * b1 - f[1] * b0);
        }
        if (plo <= phi) {
            pieces = 1;
            sp[0][0] = plo; sp[0][1] = phi;
        } else { /* through the back direction */
            pieces = 2;
            sp[0][0] = plo; sp[0][1] = phi + 4.0;
            sp[1][0] = plo - 4.0; sp[1][1] = phi;
        }
        for (j = 0; j < pieces; ++j) {
            double os = sp[j][0] > aL ? sp[j][0] : aL, oe = sp[j][1] < aR ? sp[j][1] : aR, mid, w[2], wd, wc, so, sc;
            if (oe - os <= PVS__VO_ATOL) continue;
            mid = 0.5 * (os + oe);
            pvs__vo_pangle_dir(mid, &wd, &wc);
            w[0] = f[0] * wd - f[1] * wc;
            w[1] = f[1] * wd + f[0] * wc;
            len = sqrt(w[0] * w[0] + w[1] * w[1]);
            w[0] /= len;
            w[1] /= len;
            so = pvs__vo_ray_obj(c, o, x, w);
            sc = pvs__vo_ray_cell(c, x, w);
            if (!(so >= 0.0 && sc >= 0.0 && so < sc - tol)) continue; /* behind the cell, or undecided */
            c->span[ns].s = sp[j][0];
            c->span[ns].e = sp[j][1];
            c->span[ns].is = c->vid[o->first + lo];
            c->span[ns].ie = c->vid[o->first + hi];
            ++ns;
        }
    }
    for (i = 1; i < ns; ++i) { /* insertion sort by start */
        pvs__vo_span t = c->span[i];
        k = i;
        while (k > 0 && (c->span[k - 1].s > t.s || (c->span[k - 1].s == t.s && c->span[k - 1].e < t.e))) {
            c->span[k] = c->span[k - 1];
            --k;
        }
        c->span[k] = t;
    }
    reach = aL;
    rid = PVS__VO_NONE;
    for (i = 0; i < ns; ++i) {
        const pvs__vo_span *s = c->span + i;
        if (s->e <= reach) continue;
        if (s->s < reach - PVS__VO_ATOL || (s->s <= reach && rid != PVS__VO_NONE && s->is == rid)) {
            reach = s->e;
            rid = s->ie;
            if (reach > aR + PVS__VO_ATOL) return 1;
        } else if (s->s > reach) {
            return 0;
        }
    }
    return 0;
}

/* ---- the aggregate: blockers, and the lines where hidden answers can change ---- */

/* Common tangent lines of two convex vertex sets (a segment has two vertices) that pass through the
   cell (only those can change a hidden answer); `need_cell` 0 when one of the sets is the cell. */
PVS__STATIC void pvs__vo_tangent_lines(pvs__vctx *c, const double *a, uint32_t na, const double *b, uint32_t nb, int need_cell) {
    uint32_t i, j, k;
    for (i = 0; i < na; ++i)
        for (j = 0; j < nb; ++j) {
            const double *p = a + 2 * i, *q = b + 2 * j;
            double ex = q[0] - p[0], ey = q[1] - p[1], len = sqrt(ex * ex + ey * ey), t, mn, mx;
            int ok = 1;
            if (!(len > c->tol)) continue;
            t = c->tol * len;
            mn = DBL_MAX; mx = -DBL_MAX;
            for (k = 0; k < na; ++k) {
                double s = pvs__vo_cross(p, q, a + 2 * k);
                if (s < mn) mn = s;
                if (s > mx) mx = s;
            }
            if (mn < -t && mx > t) ok = 0;
            if (ok) {
                mn = DBL_MAX; mx = -DBL_MAX;
                for (k = 0; k < nb; ++k) {
                    double s = pvs__vo_cross(p, q, b + 2 * k);
                    if (s < mn) mn = s;
                    if (s > mx) mx = s;
                }
                if (mn < -t && mx > t) ok = 0;
            }
            if (ok && need_cell) {
                mn = DBL_MAX; mx = -DBL_MAX;
                for (k = 0; k < 4; ++k) {
                    double s = pvs__vo_cross(p, q, c->corner + 2 * k);
                    if (s < mn) mn = s;
                    if (s > mx) mx = s;
                }
                ok = mn <= t && mx >= -t;
            }
            if (!ok) continue;
            if (!pvs__vo_reserve(c->al, (void **)&c->lines, &c->caplines, 4 * ((size_t)c->nlines + 1), sizeof(double))) {
                c->oom = 1;
                return;
            }
            c->lines[4 * c->nlines] = p[0];
            c->lines[4 * c->nlines + 1] = p[1];
            c->lines[4 * c->nlines + 2] = q[0];
            c->lines[4 * c->nlines + 3] = q[1];
            ++c->nlines;
        }
}

/* Adds object o to the aggregate's blockers (and its event lines). */
PVS__STATIC void pvs__vo_g_add(pvs__vctx *c, uint32_t o) {
    const pvs__vobj *b = c->obj + o;
    uint32_t i;
    if (!pvs__vo_reserve(c->al, (void **)&c->g, &c->capg, (size_t)c->ng + 1, sizeof(uint32_t))) {
        c->oom = 1;
        return;
    }
    pvs__vo_tangent_lines(c, c->corner, 4, c->vx + 2 * (size_t)b->first, b->n, 0);
    for (i = 0; i < c->ng; ++i) {
        const pvs__vobj *a = c->obj + c->g[i];
        pvs__vo_tangent_lines(c, c->vx + 2 * (size_t)a->first, a->n, c->vx + 2 * (size_t)b->first, b->n, 1);
    }
    c->g[c->ng++] = o;
    c->obj[o].mark = c->epoch;
    c->obj[o].used = 1;
}

PVS__STATIC void pvs__vo_ev_push(pvs__vctx *c, uint32_t *n, double t, double t0, double t1) {
    if (!(t > t0 && t < t1)) return;
    if (!pvs__vo_reserve(c->al, (void **)&c->ev, &c->capev, (size_t)*n + 1, sizeof(pvs__vo_key))) {
        c->oom = 1;
        return;
    }
    c->ev[*n].k = t;
    c->ev[*n].i = *n;
    ++*n;
}
/* Where segment a-b (infinite line when `line`) crosses the line p + t d. */
PVS__STATIC void pvs__vo_ev_seg(pvs__vctx *c, uint32_t *n, const double *p, const double *d, const double *a, const double *b, int line,
                                double t0, double t1) {
    double ex = b[0] - a[0], ey = b[1] - a[1], den = d[0] * ey - d[1] * ex, qx = a[0] - p[0], qy = a[1] - p[1], t, u;
    if (!(fabs(den) > 1e-15 * (fabs(ex) + fabs(ey)) * (fabs(d[0]) + fabs(d[1])))) return;
    t = (qx * ey - qy * ex) / den;
    if (!line) {
        u = (qx * d[1] - qy * d[0]) / den;
        if (u < -1e-9 || u > 1.0 + 1e-9) return;
    }
    pvs__vo_ev_push(c, n, t, t0, t1);
}

/* The hidden parts of the segment p + t d, t in [t0, t1], for the aggregate's blockers: closed
   intervals written to out (2 doubles each, at most cap). Returns their number. */
PVS__STATIC uint32_t pvs__vo_line_hidden(pvs__vctx *c, const double *p, const double *d, double t0, double t1, double *out, uint32_t cap) {
    double bb[4], a[2], b[2], span = t1 - t0, eps;
    uint32_t i, j, ne = 0, nsub = 0, nout = 0, run = 0;
    double run_start = 0.0;
    if (!(t1 > t0)) return 0;
    a[0] = p[0] + t0 * d[0]; a[1] = p[1] + t0 * d[1];
    b[0] = p[0] + t1 * d[0]; b[1] = p[1] + t1 * d[1];
    bb[0] = (a[0] < b[0] ? a[0] : b[0]);
    bb[1] = (a[1] < b[1] ? a[1] : b[1]);
    bb[2] = (a[0] > b[0] ? a[0] : b[0]);
    bb[3] = (a[1] > b[1] ? a[1] : b[1]);
    if (c->cmin[0] < bb[0]) bb[0] = c->cmin[0];
    if (c->cmin[1] < bb[1]) bb[1] = c->cmin[1];
    if (c->cmax[0] > bb[2]) bb[2] = c->cmax[0];
    if (c->cmax[1] > bb[3]) bb[3] = c->cmax[1];
    if (!pvs__vo_reserve(c->al, (void **)&c->sub, &c->capsub, (size_t)c->ng + 1, sizeof(uint32_t))) { c->oom = 1; return 0; }
    for (i = 0; i < c->ng; ++i) { /* the blockers that can stand between the cell and the segment */
        const pvs__vobj *o = c->obj + c->g[i];
        if (o->bb[0] > bb[2] + c->tol || o->bb[2] < bb[0] - c->tol || o->bb[1] > bb[3] + c->tol || o->bb[3] < bb[1] - c->tol) continue;
        c->sub[nsub++] = c->g[i];
    }
    /* events: the cell's edges, the aggregate's tangent lines, the blockers' boundaries and loops */
    for (i = 0; i < 4; ++i) pvs__vo_ev_seg(c, &ne, p, d, c->corner + 2 * i, c->corner + 2 * ((i + 1) % 4), 0, t0, t1);
    for (i = 0; i < c->nlines; ++i) pvs__vo_ev_seg(c, &ne, p, d, c->lines + 4 * i, c->lines + 4 * i + 2, 1, t0, t1);
    for (i = 0; i < nsub; ++i) {
        const pvs__vobj *o = c->obj + c->sub[i];
        const double *v = c->vx + 2 * (size_t)o->first;
        if (o->n == 2) {
            pvs__vo_ev_seg(c, &ne, p, d, v, v + 2, 1, t0, t1);
        } else {
            for (j = 0; j < o->n; ++j) pvs__vo_ev_seg(c, &ne, p, d, v + 2 * j, v + 2 * ((j + 1) % o->n), 0, t0, t1);
        }
        if (o->loop >= 0) {
            const pvs__vprep *pp = c->p;
            uint32_t s = pp->loop_start[o->loop], m = pp->loop_start[o->loop + 1] - s;
            for (j = 0; j < m; ++j) {
                double la[2], lb[2];
                la[0] = pp->ring_pt[2 * (s + j)] - c->centre[0];
                la[1] = pp->ring_pt[2 * (s + j) + 1] - c->centre[1];
                lb[0] = pp->ring_pt[2 * (s + (j + 1) % m)] - c->centre[0];
                lb[1] = pp->ring_pt[2 * (s + (j + 1) % m) + 1] - c->centre[1];
                pvs__vo_ev_seg(c, &ne, p, d, la, lb, 0, t0, t1);
            }
        }
    }
    if (c->oom) return 0;
    pvs__vo_ev_push(c, &ne, t0, t0 - 1.0, t1 + 1.0);
    pvs__vo_ev_push(c, &ne, t1, t0 - 1.0, t1 + 1.0);
    pvs__vo_sort(c->ev, ne);
    eps = 1e-12 * (span + c->scale / (fabs(d[0]) + fabs(d[1]) + 1e-300));
    for (i = 0, j = 0; i < ne; ++i) /* merge coincident events */
        if (!j || c->ev[i].k - c->ev[j - 1].k > eps) c->ev[j++] = c->ev[i];
    c->ev[j - 1].k = t1;
    c->ev[0].k = t0;
    ne = j;
    for (i = 0; i + 1 < ne; ++i) {
        double m = 0.5 * (c->ev[i].k + c->ev[i + 1].k), x[2];
        int hid;
        x[0] = p[0] + m * d[0];
        x[1] = p[1] + m * d[1];
        hid = pvs__vo_hidden(c, c->sub, nsub, x);
        if (hid && !run) { run = 1; run_start = c->ev[i].k; }
        if (!hid && run) {
            run = 0;
            if (nout < cap) { out[2 * nout] = run_start; out[2 * nout + 1] = c->ev[i].k; ++nout; }
        }
    }
    if (run && nout < cap) { out[2 * nout] = run_start; out[2 * nout + 1] = c->ev[ne - 1].k; ++nout; }
    return c->oom ? 0 : nout;
}

/* 1 if the whole segment a-b is hidden (checked with a small margin past both ends). */
PVS__STATIC int pvs__vo_segment_hidden(pvs__vctx *c, const double *a, const double *b) {
    double d[2], iv[2], len, mu;
    d[0] = b[0] - a[0];
    d[1] = b[1] - a[1];
    len = sqrt(d[0] * d[0] + d[1] * d[1]);
    if (!(len > c->tol)) return 0;
    mu = 1e-7 + c->tol / len;
    if (pvs__vo_line_hidden(c, a, d, -mu, 1.0 + mu, iv, 1) != 1) return 0;
    return iv[0] <= -mu && iv[1] >= 1.0 + mu;
}

/* ---- growth (§3) ---- */

/* The first object (not yet in the aggregate nor refused by it) that the ray o + s w (w unit) meets
   for 0 < s <= smax, walking the bucket grid; PVS__VO_NONE when none. *s_hit receives s. */
PVS__STATIC uint32_t pvs__vo_ray_first(pvs__vctx *c, const double *o, const double *w, double smax, double *s_hit) {
    const pvs__vprep *p = c->p;
    double ox = o[0] + c->centre[0] - p->g0[0], oy = o[1] + c->centre[1] - p->g0[1], cs = p->gcell, best = DBL_MAX, s = 0.0;
    double tx, ty, dtx, dty, s_in = 0.0, s_out = smax;
    int32_t ix, iy, sx, sy, gw = (int32_t)p->gw, gh = (int32_t)p->gh;
    uint32_t hit = PVS__VO_NONE;
    ++c->visit;
    { /* clip the ray to the grid */
        double lo[2], hi[2], org[2], dir[2];
        int k;
        lo[0] = 0.0; lo[1] = 0.0;
        hi[0] = cs * gw; hi[1] = cs * gh;
        org[0] = ox; org[1] = oy;
        dir[0] = w[0]; dir[1] = w[1];
        for (k = 0; k < 2; ++k) {
            if (dir[k] == 0.0) {
                if (org[k] < lo[k] || org[k] > hi[k]) return PVS__VO_NONE;
            } else {
                double u0 = (lo[k] - org[k]) / dir[k], u1 = (hi[k] - org[k]) / dir[k];
                if (u0 > u1) { double t = u0; u0 = u1; u1 = t; }
                if (u0 > s_in) s_in = u0;
                if (u1 < s_out) s_out = u1;
            }
        }
        if (s_in > s_out) return PVS__VO_NONE;
    }
    s = s_in;
    ix = (int32_t)((ox + s * w[0]) / cs);
    iy = (int32_t)((oy + s * w[1]) / cs);
    if (ix >= gw) ix = gw - 1;
    if (iy >= gh) iy = gh - 1;
    if (ix < 0) ix = 0;
    if (iy < 0) iy = 0;
    sx = w[0] > 0.0 ? 1 : -1;
    sy = w[1] > 0.0 ? 1 : -1;
    dtx = w[0] != 0.0 ? cs / fabs(w[0]) : DBL_MAX;
    dty = w[1] != 0.0 ? cs / fabs(w[1]) : DBL_MAX;
    tx = w[0] != 0.0 ? ((ix + (sx > 0)) * cs - ox) / w[0] : DBL_MAX;
    ty = w[1] != 0.0 ? ((iy + (sy > 0)) * cs - oy) / w[1] : DBL_MAX;
    for (;;) {
        uint32_t b = (uint32_t)iy * p->gw + (uint32_t)ix, q;
        double cell_end = tx < ty ? tx : ty;
        for (q = p->gstart[b]; q < p->gstart[b + 1]; ++q) {
            uint32_t po = p->gitem[q], k;
            for (k = 0; k < c->pcount[po]; ++k) {
                uint32_t oi = c->pfirst[po] + k;
                pvs__vobj *ob = c->obj + oi;
                double sh;
                if (ob->visit == c->visit || ob->mark == c->epoch) continue;
                ob->visit = c->visit;
                sh = pvs__vo_ray_obj(c, ob, o, w);
                if (sh > c->tol && sh <= smax && sh < best) { best = sh; hit = oi; }
            }
        }
        if (best <= cell_end || cell_end > s_out) break;
        if (tx < ty) { ix += sx; tx += dtx; if (ix < 0 || ix >= gw) break; }
        else { iy += sy; ty += dty; if (iy < 0 || iy >= gh) break; }
    }
    *s_hit = best;
    return hit;
}

/* How far a ray from o along w may go: to the analysis radius. */
PVS__STATIC double pvs__vo_ray_len(const pvs__vctx *c, const double *o, const double *w) {
    double b = o[0] * w[0] + o[1] * w[1], cc = o[0] * o[0] + o[1] * o[1] - c->range * c->range, disc = b * b - cc;
    return disc > 0.0 ? -b + sqrt(disc) : 0.0;
}

PVS__STATIC int pvs__vo_unit(double *w) {
    double l = sqrt(w[0] * w[0] + w[1] * w[1]);
    if (!(l > 0.0)) return 0;
    w[0] /= l;
    w[1] /= l;
    return 1;
}

/* Collects the vertices of the fused objects (after the cell's 4 corners) into c->pts. */
PVS__STATIC uint32_t pvs__vo_k_points(pvs__vctx *c, int with_cell) {
    uint32_t i, j, n = with_cell ? 4 : 0, total = n;
    for (i = 0; i < c->nk; ++i) total += c->obj[c->k[i]].n;
    if (!pvs__vo_reserve(c->al, (void **)&c->pts, &c->cappts, 2 * (size_t)total + 2, sizeof(double)) ||
        !pvs__vo_reserve(c->al, (void **)&c->hkeys, &c->caphkeys, (size_t)total + 1, sizeof(pvs__vo_key)) ||
        !pvs__vo_reserve(c->al, (void **)&c->hidx, &c->caphidx, 2 * (size_t)total + 2, sizeof(uint32_t))) {
        c->oom = 1;
        return 0;
    }
    if (with_cell) memcpy(c->pts, c->corner, 8 * sizeof(double));
    for (i = 0; i < c->nk; ++i) {
        const pvs__vobj *o = c->obj + c->k[i];
        for (j = 0; j < o->n; ++j) {
            c->pts[2 * n] = c->vx[2 * ((size_t)o->first + j)];
            c->pts[2 * n + 1] = c->vx[2 * ((size_t)o->first + j) + 1];
            ++n;
        }
    }
    return n;
}

/* The active lines of both sides from the fused objects: the supporting lines are the bridges of
   the hull of the cell and the aggregate, the separating lines the inner common tangents. Side 0
   is the left (counter-clockwise) side seen from the cell. `which`: bit s resets side s's
   separating line. Returns 0 when the aggregate surrounds the cell. */
PVS__STATIC int pvs__vo_tangents(pvs__vctx *c, pvs__vo_side *sd, int which) {
    uint32_t n = pvs__vo_k_points(c, 1), hn, i, found = 0, s;
    if (!n) return 0;
    hn = pvs__vo_hull(c->pts, n, c->hkeys, c->hidx);
    for (i = 0; i < hn; ++i) {
        uint32_t a = c->hidx[i], b = c->hidx[(i + 1) % hn];
        if (a >= 4 && b < 4) { /* aggregate -> cell (counter-clockwise): the left supporting line */
            sd[0].po[0] = c->pts[2 * a]; sd[0].po[1] = c->pts[2 * a + 1];
            sd[0].pd[0] = c->pts[2 * a] - c->pts[2 * b]; sd[0].pd[1] = c->pts[2 * a + 1] - c->pts[2 * b + 1];
            found |= pvs__vo_unit(sd[0].pd) ? 1u : 0u;
        } else if (a < 4 && b >= 4) { /* cell -> aggregate: the right one */
            sd[1].po[0] = c->pts[2 * b]; sd[1].po[1] = c->pts[2 * b + 1];
            sd[1].pd[0] = c->pts[2 * b] - c->pts[2 * a]; sd[1].pd[1] = c->pts[2 * b + 1] - c->pts[2 * a + 1];
            found |= pvs__vo_unit(sd[1].pd) ? 2u : 0u;
        }
    }
    if (found != 3u) return 0;
    /* inner tangents: a cell corner and a vertex of the aggregate's hull, the cell on one side and
       the aggregate on the other */
    n = pvs__vo_k_points(c, 0);
    hn = pvs__vo_hull(c->pts, n, c->hkeys, c->hidx);
    for (s = 0; s < 2; ++s) {
        double sign = s ? -1.0 : 1.0, best = -1.0;
        uint32_t j, k;
        if (!(which & (1 << s))) continue;
        for (i = 0; i < 4; ++i)
            for (j = 0; j < hn; ++j) {
                const double *cp = c->corner + 2 * i, *kp = c->pts + 2 * c->hidx[j];
                double len = sqrt((kp[0] - cp[0]) * (kp[0] - cp[0]) + (kp[1] - cp[1]) * (kp[1] - cp[1])), t = c->tol * len;
                int ok = len > c->tol;
                for (k = 0; k < 4 && ok; ++k) ok = sign * pvs__vo_cross(cp, kp, c->corner + 2 * k) >= -t;
                for (k = 0; k < hn && ok; ++k) ok = sign * pvs__vo_cross(cp, kp, c->pts + 2 * c->hidx[k]) <= t;
                if (ok && len > best) {
                    best = len;
                    sd[s].qo[0] = kp[0]; sd[s].qo[1] = kp[1];
                    sd[s].qd[0] = kp[0] - cp[0]; sd[s].qd[1] = kp[1] - cp[1];
                }
            }
        if (best < 0.0 || !pvs__vo_unit(sd[s].qd)) { /* none (degenerate): follow the supporting line */
            memcpy(sd[s].qo, sd[s].po, sizeof(sd[s].qo));
            memcpy(sd[s].qd, sd[s].pd, sizeof(sd[s].qd));
        }
    }
    return 1;
}

/* Case 2: the separating polyline of side s bends around object b: from its last vertex to the
   vertex of b that keeps all of b on the aggregate's side. */
PVS__STATIC void pvs__vo_bend(pvs__vctx *c, pvs__vo_side *sd, uint32_t s, uint32_t b) {
    const pvs__vobj *o = c->obj + b;
    const double *v = c->vx + 2 * (size_t)o->first, *q = sd->qo;
    double sign = s ? -1.0 : 1.0;
    uint32_t i, k;
    for (i = 0; i < o->n; ++i) {
        const double *t = v + 2 * i;
        double d[2];
        int ok = 1;
        d[0] = t[0] - q[0];
        d[1] = t[1] - q[1];
        if (!pvs__vo_unit(d)) continue;
        for (k = 0; k < o->n && ok; ++k) ok = sign * pvs__vo_cross(q, t, v + 2 * k) <= c->tol * c->scale;
        if (!ok) continue;
        sd->qo[0] = t[0];
        sd->qo[1] = t[1];
        sd->qd[0] = d[0];
        sd->qd[1] = d[1];
        return;
    }
}

/* 1 if some probe point of object b (vertices, edge midpoints, `extra`) is hidden by the aggregate
   (without b): b meets the aggregate umbra U (cases 1 and 3). */
PVS__STATIC int pvs__vo_meets_umbra(pvs__vctx *c, uint32_t b, const double *extra, int nextra) {
    const pvs__vobj *o = c->obj + b;
    const double *v = c->vx + 2 * (size_t)o->first;
    uint32_t i;
    int e;
    for (e = 0; e < nextra; ++e)
        if (pvs__vo_hidden(c, c->g, c->ng, extra + 2 * e)) return 1;
    for (i = 0; i < o->n; ++i) {
        const double *a = v + 2 * i, *bb = v + 2 * ((i + 1) % o->n);
        double m[2];
        if (pvs__vo_hidden(c, c->g, c->ng, a)) return 1;
        if (o->n == 2 && i == 1) break;
        m[0] = 0.5 * (a[0] + bb[0]);
        m[1] = 0.5 * (a[1] + bb[1]);
        if (pvs__vo_hidden(c, c->g, c->ng, m)) return 1;
    }
    return 0;
}

/* The angle the segment from p + t0 d to p + t1 d subtends from the cell's centre. */
PVS__STATIC double pvs__vo_angle(const double *p, const double *d, double t0, double t1) {
    double a0 = p[0] + t0 * d[0], a1 = p[1] + t0 * d[1], b0 = p[0] + t1 * d[0], b1 = p[1] + t1 * d[1];
    return fabs(atan2(a0 * b1 - a1 * b0, a0 * b0 + a1 * b1));
}

/* The hidden parts of the line p + t d (d unit) within the aggregate's wedge (between the two
   supporting lines, widened by a quarter, within the analysis radius): keeps in *cur the interval
   that subtends the largest angle from the cell (or, keep_t in range, the one around keep_t).
   Returns that angle, 0 when nothing is hidden. */
PVS__STATIC double pvs__vo_try_line(pvs__vctx *c, const pvs__vo_side *sd, const double *p, const double *d, double keep_t, int keep,
                                    pvs__vo_cur *cur) {
    double lo = DBL_MAX, hi = -DBL_MAX, iv[64], best = 0.0, b, cc, disc, w;
    uint32_t s, n, i;
    for (s = 0; s < 2; ++s) { /* where the line meets the supporting lines */
        double den = d[0] * sd[s].pd[1] - d[1] * sd[s].pd[0], t;
        if (fabs(den) < 1e-9) continue;
        t = ((sd[s].po[0] - p[0]) * sd[s].pd[1] - (sd[s].po[1] - p[1]) * sd[s].pd[0]) / den;
        if (t < lo) lo = t;
        if (t > hi) hi = t;
    }
    b = p[0] * d[0] + p[1] * d[1];
    cc = p[0] * p[0] + p[1] * p[1] - c->range * c->range;
    disc = b * b - cc;
    if (!(disc > 0.0)) return 0.0;
    disc = sqrt(disc);
    if (lo > hi) { lo = -b - disc; hi = -b + disc; }
    w = hi - lo;
    lo -= 0.25 * w + c->tol;
    hi += 0.25 * w + c->tol;
    if (lo < -b - disc) lo = -b - disc;
    if (hi > -b + disc) hi = -b + disc;
    if (!(hi > lo)) return 0.0;
    n = pvs__vo_line_hidden(c, p, d, lo, hi, iv, 32);
    for (i = 0; i < n; ++i) {
        double ang;
        if (iv[2 * i + 1] - iv[2 * i] <= 4.0 * c->tol) continue;
        if (keep && !(iv[2 * i] <= keep_t && keep_t <= iv[2 * i + 1])) continue;
        ang = pvs__vo_angle(p, d, iv[2 * i], iv[2 * i + 1]);
        if (ang > best) {
            best = ang;
            memcpy(cur->p, p, sizeof(cur->p));
            memcpy(cur->d, d, sizeof(cur->d));
            cur->t0 = iv[2 * i];
            cur->t1 = iv[2 * i + 1];
            cur->valid = 1;
        }
    }
    return best;
}

/* Places a virtual occluder behind object b (§3) on the best of three lines: across the umbra
   (perpendicular to the bisector of the supporting lines) just beyond b; along the aggregate's
   silhouette chord (through the two supporting lines' contact points) just behind it; across the
   view of b from the cell's centre just beyond b. Keeps the hidden interval that subtends the
   largest angle. `keep`: case 3, the current occluder's line again, the interval around its middle. */
PVS__STATIC int pvs__vo_place(pvs__vctx *c, const pvs__vo_side *sd, uint32_t b, pvs__vo_cur *cur, int keep) {
    const pvs__vobj *o = c->obj + b;
    const double *v = c->vx + 2 * (size_t)o->first;
    double best = 0.0, dir[2], p[2], cen[2] = {0.0, 0.0};
    pvs__vo_cur out;
    uint32_t i, k;
    memset(&out, 0, sizeof(out));
    if (keep && cur->valid) {
        double line_p[2], line_d[2], mid = 0.5 * (cur->t0 + cur->t1);
        memcpy(line_p, cur->p, sizeof(line_p));
        memcpy(line_d, cur->d, sizeof(line_d));
        if (pvs__vo_try_line(c, sd, line_p, line_d, mid, 1, &out) > 0.0) {
            *cur = out;
            return 1;
        }
        return 0;
    }
    for (i = 0; i < o->n; ++i) {
        cen[0] += v[2 * i] / o->n;
        cen[1] += v[2 * i + 1] / o->n;
    }
    for (k = 0; k < 3; ++k) {
        double depth = -DBL_MAX, nrm[2];
        if (k == 0) { nrm[0] = sd[0].pd[0] + sd[1].pd[0]; nrm[1] = sd[0].pd[1] + sd[1].pd[1]; }
        else if (k == 1) { nrm[0] = sd[1].po[1] - sd[0].po[1]; nrm[1] = sd[0].po[0] - sd[1].po[0]; }
        else { nrm[0] = cen[0]; nrm[1] = cen[1]; }
        if (!pvs__vo_unit(nrm)) continue;
        if (k == 1 && nrm[0] * sd[0].po[0] + nrm[1] * sd[0].po[1] < 0.0) { nrm[0] = -nrm[0]; nrm[1] = -nrm[1]; } /* away from the cell */
        if (k == 1) {
            depth = nrm[0] * sd[0].po[0] + nrm[1] * sd[0].po[1];
        } else {
            for (i = 0; i < o->n; ++i) {
                double dd = nrm[0] * v[2 * i] + nrm[1] * v[2 * i + 1];
                if (dd > depth) depth = dd;
            }
        }
        depth += 1e-3 * fabs(depth) + 2.0 * c->tol; /* strictly behind */
        if (!(depth > 0.0) || depth >= c->range) continue;
        p[0] = nrm[0] * depth;
        p[1] = nrm[1] * depth;
        dir[0] = -nrm[1];
        dir[1] = nrm[0];
        {
            double a = pvs__vo_try_line(c, sd, p, dir, 0.0, 0, &out);
            if (a > best) {
                best = a;
                *cur = out;
            }
        }
    }
    if (!(best > 0.0)) cur->valid = 0;
    return cur->valid;
}

/* ---- quantization: five bytes per occluder, relative to the cell (the VOCC section) ---- */

/* A cell's coordinate scale S = 2^((code - 128) / 8) for code 0..255 (exact: a constant times a power
   of two). An end point coordinate is centre + S (q - 128) |q - 128| / 16384 for its byte q, finer
   near the cell (perspective: a metre matters more there), from -S to 0.98 S. */
PVS__STATIC double pvs__vo_scale(uint32_t code) {
    static const double mant[8] = {1.0, 1.0905077326652577, 1.189207115002721, 1.2968395546510096,
                                   1.4142135623730951, 1.5422108254079407, 1.681792830507429, 1.8340080864093424};
    return ldexp(mant[code & 7u], (int)(code >> 3) - 16);
}
PVS__STATIC double pvs__vo_offset(double scale, uint32_t q) {
    int32_t d = (int32_t)q - 128;
    return scale * (double)(d * (d < 0 ? -d : d)) / 16384.0;
}
/* The largest byte whose offset is <= x (0 when x is below every offset). */
PVS__STATIC uint32_t pvs__vo_floor_code(double scale, double x) {
    double r = x / scale * 16384.0, d = r < 0.0 ? -sqrt(-r) : sqrt(r);
    int32_t q = (int32_t)floor(d) + 128;
    if (q < 0) q = 0;
    if (q > 255) q = 255;
    while (q < 255 && pvs__vo_offset(scale, (uint32_t)q + 1) <= x) ++q;
    while (q > 0 && pvs__vo_offset(scale, (uint32_t)q) > x) --q;
    return (uint32_t)q;
}
/* The cell's frame origin as the file reader computes it: float centre of the stored float box. */
PVS__STATIC void pvs__vo_cell_centre(const pvs_box *cell, int u, int v, double centre[2]) {
    centre[0] = (double)(0.5f * cell->min[u] + 0.5f * cell->max[u]);
    centre[1] = (double)(0.5f * cell->min[v] + 0.5f * cell->max[v]);
}
/* The smallest scale code whose range holds every point within `reach` of the centre. */
PVS__STATIC uint32_t pvs__vo_scale_code(double reach) {
    uint32_t code;
    for (code = 0; code < 255; ++code)
        if (pvs__vo_offset(pvs__vo_scale(code), 255) >= reach && pvs__vo_offset(pvs__vo_scale(code), 0) <= -reach) break;
    return code;
}

/* Rounds a found occluder a-b (cell frame) to the stored bytes, shrinking it and moving its ends
   away from the cell ("toward smaller occluders", §4), and checks the rounded one exactly. Up to six
   tries, each shrinking a little more. Returns 1 with *out filled. */
PVS__STATIC int pvs__vo_quantize(pvs__vctx *c, const double *a0, const double *b0, pvs__vo_cand *out) {
    static const double shrink[6] = {0.0, 0.03, 0.08, 0.15, 0.25, 0.38};
    double a[2], b[2], u[2], nrm[2], len, lo = pvs__vo_offset(c->qscale, 0), hi = pvs__vo_offset(c->qscale, 255);
    double t0 = 0.0, t1 = 1.0, d[2], hq;
    uint32_t qh, attempt;
    int k;
    d[0] = b0[0] - a0[0];
    d[1] = b0[1] - a0[1];
    for (k = 0; k < 2; ++k) { /* clip to the representable square */
        if (d[k] == 0.0) {
            if (a0[k] < lo || a0[k] > hi) return 0;
        } else {
            double v0 = (lo - a0[k]) / d[k], v1 = (hi - a0[k]) / d[k];
            if (v0 > v1) { double t = v0; v0 = v1; v1 = t; }
            if (v0 > t0) t0 = v0;
            if (v1 < t1) t1 = v1;
        }
    }
    if (!(t1 > t0)) return 0;
    a[0] = a0[0] + t0 * d[0]; a[1] = a0[1] + t0 * d[1];
    b[0] = a0[0] + t1 * d[0]; b[1] = a0[1] + t1 * d[1];
    u[0] = b[0] - a[0];
    u[1] = b[1] - a[1];
    len = sqrt(u[0] * u[0] + u[1] * u[1]);
    if (!pvs__vo_unit(u)) return 0;
    nrm[0] = -u[1];
    nrm[1] = u[0];
    if (nrm[0] * (a[0] + b[0]) + nrm[1] * (a[1] + b[1]) < 0.0) { nrm[0] = -nrm[0]; nrm[1] = -nrm[1]; } /* away from the cell */
    /* the height: rounded down */
    hq = ((double)c->h - c->qground) / c->qhstep;
    qh = hq >= 255.0 ? 255u : hq <= 0.0 ? 0u : (uint32_t)hq;
    while (qh > 0 && c->qground + (double)qh * c->qhstep > (double)c->h) --qh;
    if (!qh) return 0;
    for (attempt = 0; attempt < 6; ++attempt) {
        double e[2][2], g[2][2];
        uint32_t q[2][2], end;
        for (k = 0; k < 2; ++k) {
            e[0][k] = a[k] + shrink[attempt] * len * u[k];
            e[1][k] = b[k] - shrink[attempt] * len * u[k];
        }
        for (end = 0; end < 2; ++end) { /* the grid corner around the end: inward, then behind, then nearest */
            double best = DBL_MAX, inward = end ? -1.0 : 1.0;
            uint32_t f0 = pvs__vo_floor_code(c->qscale, e[end][0]), f1 = pvs__vo_floor_code(c->qscale, e[end][1]), m;
            for (m = 0; m < 4; ++m) {
                uint32_t c0 = f0 + (m & 1u), c1 = f1 + (m >> 1);
                double gx, gy, along, side, dist, score;
                if (c0 > 255 || c1 > 255) continue;
                gx = pvs__vo_offset(c->qscale, c0);
                gy = pvs__vo_offset(c->qscale, c1);
                along = inward * ((gx - e[end][0]) * u[0] + (gy - e[end][1]) * u[1]);
                side = (gx - e[end][0]) * nrm[0] + (gy - e[end][1]) * nrm[1];
                dist = (gx - e[end][0]) * (gx - e[end][0]) + (gy - e[end][1]) * (gy - e[end][1]);
                score = dist + (along < 0.0 ? 1e30 : 0.0) + (side < 0.0 ? 1e20 : 0.0);
                if (score < best) {
                    best = score;
                    q[end][0] = c0;
                    q[end][1] = c1;
                    g[end][0] = gx;
                    g[end][1] = gy;
                }
            }
            if (best == DBL_MAX) return 0;
        }
        if (q[0][0] == q[1][0] && q[0][1] == q[1][1]) return 0;
        /* the stored geometry: exactly as the reader decodes it */
        {
            double ca[2], cb[2];
            for (k = 0; k < 2; ++k) {
                ca[k] = (c->centre[k] + g[0][k]) - c->centre[k];
                cb[k] = (c->centre[k] + g[1][k]) - c->centre[k];
            }
            if (!pvs__vo_segment_hidden(c, ca, cb)) continue;
            memcpy(out->a, ca, sizeof(ca));
            memcpy(out->b, cb, sizeof(cb));
        }
        out->q[0] = (uint8_t)q[0][0];
        out->q[1] = (uint8_t)q[0][1];
        out->q[2] = (uint8_t)q[1][0];
        out->q[3] = (uint8_t)q[1][1];
        out->q[4] = (uint8_t)qh;
        return 1;
    }
    return 0;
}

PVS__STATIC void pvs__vo_emit(pvs__vctx *c, const double *a, const double *b);

/* Puts the current virtual occluder into the dense set. */
PVS__STATIC void pvs__vo_dump(pvs__vctx *c, pvs__vo_cur *cur) {
    double a[2], b[2], m;
    if (!cur->valid) return;
    m = 1e-6 * (cur->t1 - cur->t0); /* a little inside the hidden interval */
    a[0] = cur->p[0] + (cur->t0 + m) * cur->d[0];
    a[1] = cur->p[1] + (cur->t0 + m) * cur->d[1];
    b[0] = cur->p[0] + (cur->t1 - m) * cur->d[0];
    b[1] = cur->p[1] + (cur->t1 - m) * cur->d[1];
    pvs__vo_emit(c, a, b);
    cur->valid = 0;
}

/* Grows the aggregate umbra of one seed (§3, Fig. 3, Fig. 4: both sides at once). */
PVS__STATIC void pvs__vo_grow(pvs__vctx *c, uint32_t seed) {
    pvs__vo_side sd[2];
    pvs__vo_cur cur;
    uint32_t step = 0, s;
    ++c->epoch;
    c->ng = c->nk = c->nlines = 0;
    memset(&cur, 0, sizeof(cur));
    memset(sd, 0, sizeof(sd));
    pvs__vo_g_add(c, seed);
    if (!pvs__vo_reserve(c->al, (void **)&c->k, &c->capk, PVS__VO_MAXG + 1, sizeof(uint32_t))) { c->oom = 1; return; }
    c->k[c->nk++] = seed;
    ++c->st.seeds;
    if (!pvs__vo_tangents(c, sd, 3)) return;
    pvs__vo_place(c, sd, seed, &cur, 0);
    while (step < PVS__VO_MAXSTEP && c->ng < PVS__VO_MAXG && !c->oom) {
        int progressed = 0;
        for (s = 0; s < 2 && c->ng < PVS__VO_MAXG && !c->oom; ++s) {
            double sp = DBL_MAX, sq = DBL_MAX, probe[4], hitp[2];
            uint32_t bp, bq, b;
            int via_q, on_q, in_u;
            if (sd[s].done) continue;
            bp = pvs__vo_ray_first(c, sd[s].po, sd[s].pd, pvs__vo_ray_len(c, sd[s].po, sd[s].pd), &sp);
            bq = pvs__vo_ray_first(c, sd[s].qo, sd[s].qd, pvs__vo_ray_len(c, sd[s].qo, sd[s].qd), &sq);
            if (bp == PVS__VO_NONE && bq == PVS__VO_NONE) { sd[s].done = 1; continue; }
            progressed = 1;
            ++step;
            via_q = bp == PVS__VO_NONE || (bq != PVS__VO_NONE && sq < sp);
            b = via_q ? bq : bp;
            if (via_q) {
                hitp[0] = sd[s].qo[0] + sq * sd[s].qd[0];
                hitp[1] = sd[s].qo[1] + sq * sd[s].qd[1];
                on_q = 1;
            } else {
                double t = pvs__vo_ray_obj(c, c->obj + b, sd[s].qo, sd[s].qd);
                hitp[0] = sd[s].po[0] + sp * sd[s].pd[0];
                hitp[1] = sd[s].po[1] + sp * sd[s].pd[1];
                on_q = t >= 0.0;
            }
            { /* probes: the hit point pushed a little into the umbra side and along the ray */
                double nx = s ? sd[s].pd[1] : -sd[s].pd[1], ny = s ? -sd[s].pd[0] : sd[s].pd[0];
                double sz = 0.02 * ((c->obj[b].bb[2] - c->obj[b].bb[0]) + (c->obj[b].bb[3] - c->obj[b].bb[1])) + c->tol;
                const double *rd = via_q ? sd[s].qd : sd[s].pd;
                probe[0] = hitp[0] - nx * sz + rd[0] * sz;
                probe[1] = hitp[1] - ny * sz + rd[1] * sz;
                probe[2] = hitp[0] + rd[0] * sz;
                probe[3] = hitp[1] + rd[1] * sz;
            }
            in_u = pvs__vo_meets_umbra(c, b, probe, 2);
            if (in_u) { /* cases 1 and 3: B augments U; P and Q move to it */
                pvs__vo_g_add(c, b);
                if (c->nk < PVS__VO_MAXG) c->k[c->nk++] = b;
                ++c->st.umbra;
                if (!pvs__vo_tangents(c, sd, 1 << s)) break;
                sd[0].done = sd[1].done = 0;
                if (!via_q) { /* case 1: a new virtual occluder behind B; the old one is dumped */
                    pvs__vo_cur next;
                    memset(&next, 0, sizeof(next));
                    if (pvs__vo_place(c, sd, b, &next, 0)) {
                        pvs__vo_dump(c, &cur);
                        cur = next;
                    }
                } else if (!pvs__vo_place(c, sd, b, &cur, 1)) { /* case 3: the furthest one extends */
                    pvs__vo_place(c, sd, b, &cur, 0);
                }
            } else if (on_q) { /* case 2: B only meets the separating line: it bends it */
                pvs__vo_g_add(c, b);
                ++c->st.separating;
                pvs__vo_bend(c, sd + s, s, b);
            } else {
                c->obj[b].mark = c->epoch; /* met by the supporting line only, outside U: no help */
            }
        }
        if (!progressed) break;
    }
    pvs__vo_dump(c, &cur);
    /* the whole aggregate: one more occluder behind the seed, now that every object is in */
    if (c->ng > 1 && pvs__vo_place(c, sd, seed, &cur, 0)) pvs__vo_dump(c, &cur);
}

/* Grows up to max_seeds seeds of the current slice, largest subtended angle first. */
PVS__STATIC void pvs__vo_run_slice(pvs__vctx *c) {
    pvs__vo_key *order;
    uint32_t i, n = c->nobj, grown = 0;
    order = (pvs__vo_key *)pvs__alloc_array(c->al, (size_t)n + 1, sizeof(pvs__vo_key));
    if (!order) { c->oom = 1; return; }
    for (i = 0; i < n; ++i) {
        order[i].k = -c->obj[i].angle;
        order[i].i = i;
        c->obj[i].used = 0;
        c->obj[i].mark = 0;
    }
    c->epoch = 0;
    pvs__vo_sort(order, n);
    for (i = 0; i < n && grown < c->max_seeds && !c->oom; ++i) {
        uint32_t o = order[i].i;
        if (c->obj[o].used || !(c->obj[o].angle > 1e-4)) continue;
        pvs__vo_grow(c, o);
        ++grown;
    }
    pvs__free_array(c->al, order, (size_t)n + 1, sizeof(pvs__vo_key));
}

/* A virtual occluder found by the growth: rounded as it will be stored, checked, then kept. */
PVS__STATIC void pvs__vo_emit(pvs__vctx *c, const double *a, const double *b) {
    pvs__vo_cand cand;
    memset(&cand, 0, sizeof(cand));
    if (!c->quantize) {
        int k;
        for (k = 0; k < 2; ++k) { /* float end points, as pvs_vocc_2d returns them */
            cand.f[k] = (float)(a[k] + c->centre[k]);
            cand.f[2 + k] = (float)(b[k] + c->centre[k]);
            cand.a[k] = (double)cand.f[k] - c->centre[k];
            cand.b[k] = (double)cand.f[2 + k] - c->centre[k];
        }
        if (!pvs__vo_segment_hidden(c, cand.a, cand.b)) {
            ++c->st.dropped;
            return;
        }
    } else if (!pvs__vo_quantize(c, a, b, &cand)) {
        ++c->st.dropped;
        return;
    }
    if (!pvs__vo_reserve(c->al, (void **)&c->out, &c->capout, (size_t)c->nout + 1, sizeof(pvs__vo_cand))) {
        c->oom = 1;
        return;
    }
    c->out[c->nout++] = cand;
    ++c->st.dense;
}

/* ---- the runtime test: one box against one virtual occluder (pvs_vocc_box_hidden) ---- */

typedef struct pvs__vo_rt {
    double o[2];              /* frame origin (world) */
    double n[2], off;         /* the occluder's line n.x = off (frame, n unit), the cell on the side n.x < off */
    double h[8][3];           /* the 2D umbra's other sides: h[0..8) . (x, y, 1) >= 0 (unit normals) */
    double dcmin, dcmax;      /* the cell's ground corners' distances from the line (> 0) */
    double base, top, cbot, ctop;
    double m, mh;             /* margins: lengths, heights */
    int u_axis, v_axis, up, ok;
} pvs__vo_rt;

/* Prepares the test of occluder a-b (world ground coordinates, heights base..top) for a cell. The 2D
   part: a box is hidden when every segment from the cell's ground rectangle to the box's crosses
   a-b, i.e. the box lies in the occluder's umbra (§3 for one convex occluder): beyond its line, and
   for every cell corner c, on the far side of the lines c-a and c-b (the segment from c crosses the
   occluder's line between a and b). Both rectangles are convex, so corners decide, and the box's
   corners are tested at once with support functions. Margins m (1e-7 of the frame's extent) make
   every rounding answer "not hidden". */
PVS__STATIC void pvs__vo_rt_init(pvs__vo_rt *r, const pvs_box *cell, uint32_t up, const double *a, const double *b, double base, double top) {
    double la[2], lb[2], cc[4][2], u[2], len, ext = 1.0, dmin = DBL_MAX, dmax = -DBL_MAX;
    int k, e;
    memset(r, 0, sizeof(*r));
    r->up = up == 2 ? 2 : 1;
    pvs__ground_axes((uint32_t)r->up, &r->u_axis, &r->v_axis);
    pvs__vo_cell_centre(cell, r->u_axis, r->v_axis, r->o);
    for (k = 0; k < 2; ++k) {
        la[k] = a[k] - r->o[k];
        lb[k] = b[k] - r->o[k];
        if (fabs(la[k]) > ext) ext = fabs(la[k]);
        if (fabs(lb[k]) > ext) ext = fabs(lb[k]);
    }
    for (k = 0; k < 4; ++k) {
        cc[k][0] = (double)((k & 1) ? cell->max[r->u_axis] : cell->min[r->u_axis]) - r->o[0];
        cc[k][1] = (double)((k & 2) ? cell->max[r->v_axis] : cell->min[r->v_axis]) - r->o[1];
        if (fabs(cc[k][0]) > ext) ext = fabs(cc[k][0]);
        if (fabs(cc[k][1]) > ext) ext = fabs(cc[k][1]);
    }
    r->m = 1e-7 * ext;
    u[0] = lb[0] - la[0];
    u[1] = lb[1] - la[1];
    len = sqrt(u[0] * u[0] + u[1] * u[1]);
    if (!(len > 4.0 * r->m) || !(top > base) || !(fabs(top) < 1e30) || !(fabs(base) < 1e30)) return;
    u[0] /= len;
    u[1] /= len;
    r->n[0] = -u[1];
    r->n[1] = u[0];
    r->off = r->n[0] * la[0] + r->n[1] * la[1];
    for (k = 0; k < 4; ++k) {
        double d = r->off - (r->n[0] * cc[k][0] + r->n[1] * cc[k][1]);
        if (d < dmin) dmin = d;
        if (d > dmax) dmax = d;
    }
    if (dmax < 0.0) { /* the cell on the other side: flip the normal */
        double t = dmin;
        r->n[0] = -r->n[0];
        r->n[1] = -r->n[1];
        r->off = -r->off;
        dmin = -dmax;
        dmax = -t;
    }
    if (!(dmin > r->m)) return; /* the line meets the cell: it hides nothing */
    for (e = 0; e < 2; ++e) { /* through each end, a line from each cell corner, the occluder's side kept */
        const double *p = e ? lb : la;
        double inward[2];
        inward[0] = e ? -u[0] : u[0];
        inward[1] = e ? -u[1] : u[1];
        for (k = 0; k < 4; ++k) {
            double *h = r->h[4 * e + k], dx = p[0] - cc[k][0], dy = p[1] - cc[k][1], l = sqrt(dx * dx + dy * dy);
            h[0] = -dy / l;
            h[1] = dx / l;
            if (h[0] * inward[0] + h[1] * inward[1] < 0.0) { h[0] = -h[0]; h[1] = -h[1]; }
            h[2] = -(h[0] * p[0] + h[1] * p[1]);
        }
    }
    r->dcmin = dmin;
    r->dcmax = dmax;
    r->base = base;
    r->top = top;
    r->cbot = cell->min[r->up];
    r->ctop = cell->max[r->up];
    r->mh = 1e-7 * (fabs(base) + fabs(top) + fabs(r->cbot) + fabs(r->ctop) + 1.0);
    r->ok = 1;
}

/* 1 if every sight line from the cell box to box b crosses the occluder (see pvs_vocc_box_hidden). */
PVS__STATIC int pvs__vo_rt_hides(const pvs__vo_rt *r, const pvs_box *b) {
    double x0 = (double)b->min[r->u_axis] - r->o[0], x1 = (double)b->max[r->u_axis] - r->o[0];
    double y0 = (double)b->min[r->v_axis] - r->o[1], y1 = (double)b->max[r->v_axis] - r->o[1];
    double dbmin, dbmax, tmin, tmax, btop, bbot;
    int k;
    if (!r->ok) return 0;
    /* beyond the line: the smallest n.x - off over the box (a support function) */
    dbmin = (r->n[0] > 0.0 ? r->n[0] * x0 : r->n[0] * x1) + (r->n[1] > 0.0 ? r->n[1] * y0 : r->n[1] * y1) - r->off;
    if (!(dbmin > r->m)) return 0;
    for (k = 0; k < 8; ++k) {
        const double *h = r->h[k];
        if (!((h[0] > 0.0 ? h[0] * x0 : h[0] * x1) + (h[1] > 0.0 ? h[1] * y0 : h[1] * y1) + h[2] > r->m)) return 0;
    }
    /* heights: a sight line crosses the occluder's plane at (1 - t) eye + t target, where t = dc / (dc
       + db) (distances of its ends from the line) lies in [tmin, tmax]; the bounds are linear in t */
    dbmax = (r->n[0] > 0.0 ? r->n[0] * x1 : r->n[0] * x0) + (r->n[1] > 0.0 ? r->n[1] * y1 : r->n[1] * y0) - r->off;
    tmin = r->dcmin / (r->dcmin + dbmax);
    tmax = r->dcmax / (r->dcmax + dbmin);
    btop = b->max[r->up];
    bbot = b->min[r->up];
    if (r->ctop + tmin * (btop - r->ctop) > r->top - r->mh || r->ctop + tmax * (btop - r->ctop) > r->top - r->mh) return 0;
    if (r->cbot + tmin * (bbot - r->cbot) < r->base + r->mh || r->cbot + tmax * (bbot - r->cbot) < r->base + r->mh) return 0;
    return 1;
}

PVS__STATIC int pvs__vo_box_ok(const pvs_box *b) {
    int k;
    for (k = 0; k < 3; ++k)
        if (!(b->min[k] <= b->max[k]) || !pvs__finite(b->min[k]) || !pvs__finite(b->max[k])) return 0;
    return 1;
}

PVS_API int pvs_vocc_box_hidden(const pvs_box *cell, uint32_t up_axis, const pvs_virtual_occluder *o, const pvs_box *box) {
    pvs__vo_rt r;
    double a[2], b[2];
    if (!cell || !o || !box || !pvs__vo_box_ok(cell) || !pvs__vo_box_ok(box)) return 0;
    if (!pvs__finite(o->p0[0]) || !pvs__finite(o->p0[1]) || !pvs__finite(o->p1[0]) || !pvs__finite(o->p1[1])) return 0;
    a[0] = o->p0[0]; a[1] = o->p0[1];
    b[0] = o->p1[0]; b[1] = o->p1[1];
    pvs__vo_rt_init(&r, cell, up_axis, a, b, o->base, o->top);
    return pvs__vo_rt_hides(&r, box);
}

/* ---- the rebuild: a top-down walk of the object kD-tree ---- */

typedef struct pvs__vo_walk {
    const pvs__vo_rt *rt;
    uint32_t count;
    const pvs_box *boxes;
    uint32_t object_count;
    pvs_word *visible;
} pvs__vo_walk;

PVS__STATIC int pvs__vo_walk_hidden(const pvs__vo_walk *w, const pvs_box *b) {
    uint32_t i;
    for (i = 0; i < w->count; ++i)
        if (pvs__vo_rt_hides(w->rt + i, b)) return 1;
    return 0;
}
PVS__STATIC pvs_visit pvs__vo_walk_visit(void *user, const pvs_box *node_box, float distance, const uint32_t *items, uint32_t count) {
    pvs__vo_walk *w = (pvs__vo_walk *)user;
    uint32_t i;
    (void)distance;
    if (pvs__vo_walk_hidden(w, node_box)) return PVS_VISIT_SKIP; /* the whole subtree lies behind one occluder */
    for (i = 0; i < count; ++i) {
        uint32_t id = items[i];
        if (id >= w->object_count || pvs_bitset_test(w->visible, id) || !pvs__vo_box_ok(w->boxes + id)) continue;
        if (!pvs__vo_walk_hidden(w, w->boxes + id)) pvs_bitset_set(w->visible, id);
    }
    return PVS_VISIT_DESCEND;
}

PVS_API size_t pvs_vocc_cull_scratch_size(const pvs_kdtree *tree, uint32_t max_occluders) {
    size_t rt = (size_t)max_occluders * sizeof(pvs__vo_rt);
    return (rt + 15u) / 16u * 16u + (tree ? pvs_kdtree_sweep_scratch_size(tree) : 0) + 16u;
}

/* The walk over prepared occluders (rt[0..count) in the scratch's front). */
PVS__STATIC pvs_result pvs__vo_cull(const pvs_box *cell, pvs__vo_rt *rt, uint32_t count, const pvs_box *boxes, uint32_t object_count,
                                    const pvs_kdtree *tree, uint8_t *rest, size_t rest_size, pvs_word *visible, pvs_error *err) {
    pvs__vo_walk w;
    uint32_t i;
    memset(visible, 0, PVS_BITSET_WORDS(object_count) * sizeof(pvs_word));
    w.rt = rt;
    w.count = count;
    w.boxes = boxes;
    w.object_count = object_count;
    w.visible = visible;
    if (tree) {
        pvs_result r = pvs_kdtree_sweep(tree, cell, rest, rest_size, pvs__vo_walk_visit, &w);
        if (r != PVS_OK) return pvs__fail(err, r, -1, 0, "object tree walk (scratch %llu bytes)", (unsigned long long)rest_size);
    } else {
        for (i = 0; i < object_count; ++i)
            if (pvs__vo_box_ok(boxes + i) && !pvs__vo_walk_hidden(&w, boxes + i)) pvs_bitset_set(visible, i);
    }
    pvs__ok(err);
    return PVS_OK;
}

/* Splits caller scratch into the occluder array and the rest (8-aligned). */
PVS__STATIC pvs_result pvs__vo_scratch(void *scratch, size_t size, uint32_t count, const pvs_kdtree *tree, pvs__vo_rt **rt, uint8_t **rest,
                                       size_t *rest_size, pvs_error *err) {
    size_t need = pvs_vocc_cull_scratch_size(tree, count), head = ((size_t)count * sizeof(pvs__vo_rt) + 15u) / 16u * 16u;
    uint8_t *p = (uint8_t *)scratch;
    size_t skew;
    if (!scratch) return pvs__fail(err, PVS_ERROR_INVALID_ARGUMENT, -1, 0, "scratch is NULL");
    skew = (size_t)(-(intptr_t)p) & 15u; /* align to 16 */
    if (size < need || size - skew < need - 16u)
        return pvs__fail(err, PVS_ERROR_BUFFER_TOO_SMALL, -1, 0, "scratch of %llu bytes, need %llu", (unsigned long long)size, (unsigned long long)need);
    p += skew;
    *rt = (pvs__vo_rt *)(void *)p;
    *rest = p + head;
    *rest_size = size - skew - head;
    return PVS_OK;
}

PVS_API pvs_result pvs_vocc_cull_occluders(const pvs_box *cell, uint32_t up_axis, const pvs_virtual_occluder *occ, uint32_t count,
                                           const pvs_box *boxes, uint32_t object_count, const pvs_kdtree *tree, void *scratch,
                                           size_t scratch_size, pvs_word *visible, pvs_error *err) {
    pvs__vo_rt *rt;
    uint8_t *rest;
    size_t rest_size;
    uint32_t i;
    pvs_result r;
    if (!cell || (count && !occ) || (object_count && !boxes) || !visible)
        return pvs__fail(err, PVS_ERROR_INVALID_ARGUMENT, -1, 0, "cell, occluders, boxes and visible must not be NULL");
    if (!pvs__vo_box_ok(cell)) return pvs__fail(err, PVS_ERROR_INVALID_ARGUMENT, -1, 0, "the cell box is empty or not finite");
    r = pvs__vo_scratch(scratch, scratch_size, count, tree, &rt, &rest, &rest_size, err);
    if (r != PVS_OK) return r;
    for (i = 0; i < count; ++i) {
        double a[2], b[2];
        a[0] = occ[i].p0[0]; a[1] = occ[i].p0[1];
        b[0] = occ[i].p1[0]; b[1] = occ[i].p1[1];
        pvs__vo_rt_init(rt + i, cell, up_axis, a, b, occ[i].base, occ[i].top);
        if (!pvs__finite(occ[i].p0[0]) || !pvs__finite(occ[i].p0[1]) || !pvs__finite(occ[i].p1[0]) || !pvs__finite(occ[i].p1[1]))
            rt[i].ok = 0;
    }
    return pvs__vo_cull(cell, rt, count, boxes, object_count, tree, rest, rest_size, visible, err);
}

/* ---- the VOCC section of a .pvs file (layout in the manual) ---- */

#define PVS__VO_TAG ((uint32_t)'V' | ((uint32_t)'O' << 8) | ((uint32_t)'C' << 16) | ((uint32_t)'C' << 24))
#define PVS__VO_HEAD 16u
#define PVS__VO_BLOCK 16u

PVS__STATIC uint32_t pvs__vo_rd32(const uint8_t *p) {
    return (uint32_t)p[0] | ((uint32_t)p[1] << 8) | ((uint32_t)p[2] << 16) | ((uint32_t)p[3] << 24);
}
PVS__STATIC void pvs__vo_wr32(uint8_t *p, uint32_t v) {
    p[0] = (uint8_t)v; p[1] = (uint8_t)(v >> 8); p[2] = (uint8_t)(v >> 16); p[3] = (uint8_t)(v >> 24);
}
PVS__STATIC float pvs__vo_rdf(const uint8_t *p) {
    uint32_t u = pvs__vo_rd32(p);
    float f;
    memcpy(&f, &u, 4);
    return f;
}

/* Bytes of a VOCC section for cells cells holding n occluders (0 when it does not fit 32 bits). */
PVS__STATIC size_t pvs__vo_section_size(uint32_t cells, uint64_t n) {
    uint64_t blocks = ((uint64_t)cells + PVS__VO_BLOCK - 1) / PVS__VO_BLOCK, size = PVS__VO_HEAD + 4 * (blocks + 1) + 2 * (uint64_t)cells + 5 * n;
    return size > 0xfffffff0ull ? 0 : (size_t)size;
}

/* Writes the section (pvs__vo_section_size bytes) from per-cell counts and scale codes and the
   occluders' bytes in cell order. */
PVS__STATIC void pvs__vo_section_write(uint8_t *o, uint32_t flags, float base, float hstep, uint32_t cells, const uint8_t *counts,
                                       const uint8_t *scales, const uint8_t *bytes, uint32_t stride) {
    uint32_t blocks = (cells + PVS__VO_BLOCK - 1) / PVS__VO_BLOCK, b, i, n = 0;
    uint32_t bu, bh;
    for (i = 0; i < cells; ++i) n += counts[i];
    pvs__vo_wr32(o, flags);
    pvs__vo_wr32(o + 4, n);
    memcpy(&bu, &base, 4);
    memcpy(&bh, &hstep, 4);
    pvs__vo_wr32(o + 8, bu);
    pvs__vo_wr32(o + 12, bh);
    for (b = 0, n = 0; b <= blocks; ++b) {
        pvs__vo_wr32(o + PVS__VO_HEAD + 4 * b, n);
        for (i = b * PVS__VO_BLOCK; b < blocks && i < cells && i < (b + 1) * PVS__VO_BLOCK; ++i) n += counts[i];
    }
    memcpy(o + PVS__VO_HEAD + 4 * ((size_t)blocks + 1), counts, cells);
    memcpy(o + PVS__VO_HEAD + 4 * ((size_t)blocks + 1) + cells, scales, cells);
    if (!stride) {
        if (n) memcpy(o + PVS__VO_HEAD + 4 * ((size_t)blocks + 1) + 2 * (size_t)cells, bytes, 5 * (size_t)n);
    } else {
        uint8_t *q = o + PVS__VO_HEAD + 4 * ((size_t)blocks + 1) + 2 * (size_t)cells;
        for (i = 0; i < cells; ++i) {
            memcpy(q, bytes + (size_t)i * stride, 5 * (size_t)counts[i]);
            q += 5 * (size_t)counts[i];
        }
    }
}

/* Validates a VOCC section for a file of f->cell_count cells (called by pvs_file_open once META is
   read) and records it in *f. Linear in the section's size; reads nothing outside it. */
PVS__STATIC pvs_result pvs__vo_open_section(pvs_file *f, const uint8_t *file, const uint8_t *sec, uint32_t size, pvs_error *err) {
    uint64_t so = (uint64_t)(sec - file);
    uint32_t cells = f->cell_count, blocks = (cells + PVS__VO_BLOCK - 1) / PVS__VO_BLOCK, flags, n, b, i;
    size_t need;
    float base, hstep;
    const uint8_t *counts;
    if (size < PVS__VO_HEAD) return pvs__fail(err, PVS_ERROR_BAD_SECTION, -1, so, "VOCC has %u bytes, fewer than its 16-byte header", size);
    flags = pvs__vo_rd32(sec);
    n = pvs__vo_rd32(sec + 4);
    base = pvs__vo_rdf(sec + 8);
    hstep = pvs__vo_rdf(sec + 12);
    if (flags & ~1u) return pvs__fail(err, PVS_ERROR_BAD_SECTION, -1, so, "VOCC: unknown flags 0x%x", flags);
    if ((uint64_t)n > 255ull * cells) return pvs__fail(err, PVS_ERROR_BAD_SECTION, -1, so + 4, "VOCC: %u occluders for %u cells", n, cells);
    if (!pvs__finite(base) || !pvs__finite(hstep) || !(hstep > 0.0f) || !pvs__finite(base + 255.0f * hstep))
        return pvs__fail(err, PVS_ERROR_BAD_SECTION, -1, so + 8, "VOCC: base %g or height step %g is not usable", (double)base, (double)hstep);
    need = pvs__vo_section_size(cells, n);
    if (!need || need != size)
        return pvs__fail(err, PVS_ERROR_BAD_SECTION, -1, so, "VOCC has %u bytes, %u cells and %u occluders need %llu", size, cells, n,
                         (unsigned long long)need);
    counts = sec + PVS__VO_HEAD + 4 * ((size_t)blocks + 1);
    if (pvs__vo_rd32(sec + PVS__VO_HEAD) != 0 || pvs__vo_rd32(sec + PVS__VO_HEAD + 4 * (size_t)blocks) != n)
        return pvs__fail(err, PVS_ERROR_BAD_SECTION, -1, so + PVS__VO_HEAD, "VOCC: block offsets must run from 0 to %u", n);
    for (b = 0; b < blocks; ++b) {
        uint32_t sum = 0, lo = pvs__vo_rd32(sec + PVS__VO_HEAD + 4 * (size_t)b), hi = pvs__vo_rd32(sec + PVS__VO_HEAD + 4 * (size_t)b + 4);
        for (i = b * PVS__VO_BLOCK; i < cells && i < (b + 1) * PVS__VO_BLOCK; ++i) sum += counts[i];
        if (hi < lo || hi - lo != sum)
            return pvs__fail(err, PVS_ERROR_BAD_SECTION, b * PVS__VO_BLOCK, so + PVS__VO_HEAD + 4 * (uint64_t)b,
                             "VOCC: block %u holds %u occluders, its cells count %u", b, hi - lo, sum);
    }
    f->vocc_flags = PVS_VOCC_STORED | ((flags & 1u) ? PVS_VOCC_ONLY : 0u);
    f->virtual_occluder_count = n;
    f->vocc_base = base;
    f->vocc_height_step = hstep;
    f->private_.vocc = sec;
    f->private_.vocc_size = size;
    return PVS_OK;
}

/* A cell's stored occluders: returns the count, *bytes their 5-byte records, *scale its code. */
PVS__STATIC uint32_t pvs__vo_file_cell(const pvs_file *f, uint32_t cell, const uint8_t **bytes, uint32_t *scale) {
    const uint8_t *sec = f->private_.vocc;
    uint32_t cells = f->cell_count, blocks = (cells + PVS__VO_BLOCK - 1) / PVS__VO_BLOCK, b = cell / PVS__VO_BLOCK, first, i;
    const uint8_t *counts = sec + PVS__VO_HEAD + 4 * ((size_t)blocks + 1);
    first = pvs__vo_rd32(sec + PVS__VO_HEAD + 4 * (size_t)b);
    for (i = b * PVS__VO_BLOCK; i < cell; ++i) first += counts[i];
    *scale = counts[cells + cell];
    *bytes = counts + 2 * (size_t)cells + 5 * (size_t)first;
    return counts[cell];
}

/* The stored geometry of one occluder: world ground end points and heights. */
PVS__STATIC void pvs__vo_decode(const pvs_box *cell, uint32_t up, uint32_t scale_code, const uint8_t *q, float base, float hstep, double *a,
                                double *b, double *vbase, double *vtop) {
    double centre[2], sc = pvs__vo_scale(scale_code);
    int u, v;
    pvs__ground_axes(up == 2 ? 2u : 1u, &u, &v);
    pvs__vo_cell_centre(cell, u, v, centre);
    a[0] = centre[0] + pvs__vo_offset(sc, q[0]);
    a[1] = centre[1] + pvs__vo_offset(sc, q[1]);
    b[0] = centre[0] + pvs__vo_offset(sc, q[2]);
    b[1] = centre[1] + pvs__vo_offset(sc, q[3]);
    *vbase = (double)base;
    *vtop = (double)base + (double)q[4] * (double)hstep;
}

PVS_API uint32_t pvs_file_virtual_occluders(const pvs_file *f, uint32_t cell, pvs_virtual_occluder *out, uint32_t capacity) {
    const uint8_t *bytes;
    uint32_t scale, n, i;
    pvs_box box;
    if (!f || !f->data || !(f->vocc_flags & PVS_VOCC_STORED) || cell >= f->cell_count) return 0;
    n = pvs__vo_file_cell(f, cell, &bytes, &scale);
    box = pvs_file_cell_box(f, cell);
    for (i = 0; i < n && i < capacity && out; ++i) {
        double a[2], b[2], lo, hi;
        pvs__vo_decode(&box, f->up_axis, scale, bytes + 5 * (size_t)i, f->vocc_base, f->vocc_height_step, a, b, &lo, &hi);
        out[i].p0[0] = (float)a[0]; out[i].p0[1] = (float)a[1];
        out[i].p1[0] = (float)b[0]; out[i].p1[1] = (float)b[1];
        out[i].base = (float)lo;
        out[i].top = (float)hi;
    }
    return n;
}

PVS_API uint32_t pvs_file_vocc_record(const pvs_file *f, uint32_t cell, uint32_t *scale_code, const uint8_t **bytes) {
    const uint8_t *p = NULL;
    uint32_t sc = 0, n = 0;
    if (f && f->data && (f->vocc_flags & PVS_VOCC_STORED) && cell < f->cell_count) n = pvs__vo_file_cell(f, cell, &p, &sc);
    if (scale_code) *scale_code = sc;
    if (bytes) *bytes = p;
    return n;
}

PVS_API pvs_result pvs_vocc_cull(const pvs_file *f, uint32_t cell, uint32_t max_occluders, const pvs_box *boxes, uint32_t object_count,
                                 const pvs_kdtree *tree, void *scratch, size_t scratch_size, pvs_word *visible, pvs_error *err) {
    const uint8_t *bytes;
    uint32_t scale, n, i;
    pvs_box box;
    pvs__vo_rt *rt;
    uint8_t *rest;
    size_t rest_size;
    pvs_result r;
    if (!f || !f->data || !visible || (object_count && !boxes))
        return pvs__fail(err, PVS_ERROR_INVALID_ARGUMENT, -1, 0, "file, boxes and visible must not be NULL");
    if (!(f->vocc_flags & PVS_VOCC_STORED)) return pvs__fail(err, PVS_ERROR_INVALID_ARGUMENT, -1, 0, "the file stores no virtual occluders");
    if (cell >= f->cell_count) return pvs__fail(err, PVS_ERROR_INVALID_ARGUMENT, cell, 0, "cell %u of %u", cell, f->cell_count);
    if (object_count != f->object_count)
        return pvs__fail(err, PVS_ERROR_INVALID_ARGUMENT, -1, 0, "%u object boxes for a file of %u objects", object_count, f->object_count);
    n = pvs__vo_file_cell(f, cell, &bytes, &scale);
    if (max_occluders && n > max_occluders) n = max_occluders;
    r = pvs__vo_scratch(scratch, scratch_size, n, tree, &rt, &rest, &rest_size, err);
    if (r != PVS_OK) return r;
    box = pvs_file_cell_box(f, cell);
    for (i = 0; i < n; ++i) {
        double a[2], b[2], lo, hi;
        pvs__vo_decode(&box, f->up_axis, scale, bytes + 5 * (size_t)i, f->vocc_base, f->vocc_height_step, a, b, &lo, &hi);
        pvs__vo_rt_init(rt + i, &box, f->up_axis, a, b, lo, hi);
    }
    return pvs__vo_cull(&box, rt, n, boxes, object_count, tree, rest, rest_size, visible, err);
}

/* ---- 2.5D per cell (§3.1), the selection (Fig. 6), the bake's part ---- */

/* What a bake shares between its cells: the prepared facades, quantization, object boxes. */
typedef struct pvs__vbake {
    pvs_allocator a;
    pvs__vprep *prep;
    uint32_t up;
    float base, hstep;          /* the VOCC section's heights */
    pvs_box *boxes;             /* object boxes, empty for objects never drawn */
    uint32_t object_count;
    uint32_t slices, max_keep, max_seeds;
} pvs__vbake;

PVS__STATIC void pvs__vbake_destroy(pvs__vbake *vb) {
    pvs_allocator a;
    if (!vb) return;
    a = vb->a;
    pvs__vprep_destroy(vb->prep);
    pvs__free_array(&a, vb->boxes, (size_t)vb->object_count + 1, sizeof(pvs_box));
    pvs__free(&a, vb, sizeof(*vb), 16);
}

/* Facades of the scene (pvs__scene_facades) and walls of its EXTRUSION and BOX occluders standing
   on the ground, as prepared occluders; object boxes. */
PVS__STATIC pvs_result pvs__vbake_create(const pvs_scene *s, const pvs_allocator *a, uint32_t slices, uint32_t max_keep, pvs__vbake **out) {
    pvs__vbake *vb;
    float *fac = NULL, *top = NULL, ground, tmax;
    double *seg = NULL;
    uint32_t nf = 0, n = 0, i, j, extra = 0;
    int u, v, up;
    pvs_result r;
    *out = NULL;
    vb = (pvs__vbake *)pvs__alloc(a, sizeof(pvs__vbake), 16);
    if (!vb) return PVS_ERROR_OUT_OF_MEMORY;
    memset(vb, 0, sizeof(*vb));
    vb->a = *a;
    vb->up = s->up_axis == 2 ? 2u : 1u;
    vb->slices = slices;
    vb->max_keep = max_keep;
    vb->max_seeds = 16;
    vb->object_count = s->object_count;
    up = (int)vb->up;
    pvs__ground_axes(vb->up, &u, &v);
    ground = s->bounds.min[up];
    r = pvs__scene_facades(s, a, &fac, &nf);
    if (r != PVS_OK) goto done;
    for (i = 0; i < s->occluder_count; ++i) {
        const pvs_occluder_desc *o = s->occluders + i;
        if (o->kind == PVS_OCCLUDER_EXTRUSION && o->base <= ground) extra += o->footprint_count;
        if (o->kind == PVS_OCCLUDER_BOX && o->box.min[up] <= ground) extra += 4;
    }
    seg = (double *)pvs__alloc_array(a, 4 * ((size_t)nf + extra) + 4, sizeof(double));
    top = (float *)pvs__alloc_array(a, (size_t)nf + extra + 1, sizeof(float));
    vb->boxes = (pvs_box *)pvs__alloc_array(a, (size_t)s->object_count + 1, sizeof(pvs_box));
    r = PVS_ERROR_OUT_OF_MEMORY;
    if (!seg || !top || !vb->boxes) goto done;
    tmax = ground;
    for (i = 0; i < nf; ++i, ++n) {
        for (j = 0; j < 4; ++j) seg[4 * (size_t)n + j] = fac[6 * (size_t)i + j];
        top[n] = fac[6 * (size_t)i + 4];
    }
    for (i = 0; i < s->occluder_count; ++i) {
        const pvs_occluder_desc *o = s->occluders + i;
        float pts[8];
        const float *fp = NULL;
        uint32_t cnt = 0;
        float t = 0.0f;
        if (o->kind == PVS_OCCLUDER_EXTRUSION && o->base <= ground) {
            fp = o->footprint;
            cnt = o->footprint_count;
            t = o->top;
        } else if (o->kind == PVS_OCCLUDER_BOX && o->box.min[up] <= ground) {
            pts[0] = o->box.min[u]; pts[1] = o->box.min[v];
            pts[2] = o->box.max[u]; pts[3] = o->box.min[v];
            pts[4] = o->box.max[u]; pts[5] = o->box.max[v];
            pts[6] = o->box.min[u]; pts[7] = o->box.max[v];
            fp = pts;
            cnt = 4;
            t = o->box.max[up];
        }
        for (j = 0; j < cnt; ++j, ++n) {
            seg[4 * (size_t)n] = fp[2 * j];
            seg[4 * (size_t)n + 1] = fp[2 * j + 1];
            seg[4 * (size_t)n + 2] = fp[2 * ((j + 1) % cnt)];
            seg[4 * (size_t)n + 3] = fp[2 * ((j + 1) % cnt) + 1];
            top[n] = t;
        }
    }
    for (i = 0; i < n; ++i)
        if (top[i] > tmax) tmax = top[i];
    vb->base = ground;
    vb->hstep = (tmax - ground) / 255.0f;
    if (!(vb->hstep > 0.0f) || !pvs__finite(vb->hstep)) vb->hstep = 1.0f;
    while (!((double)ground + 255.0 * (double)vb->hstep >= (double)tmax)) vb->hstep = nextafterf(vb->hstep, FLT_MAX);
    for (i = 0; i < s->object_count; ++i) {
        vb->boxes[i] = s->object_boxes[i];
        if (s->object_flags[i] & PVS_OBJECT_OCCLUDER_ONLY) vb->boxes[i] = pvs__box_empty();
    }
    r = pvs__vprep_create(a, seg, top, n, &vb->prep);
done:
    pvs__free_array(a, fac, (size_t)nf * 6 + 6, sizeof(float));
    pvs__free_array(a, seg, 4 * ((size_t)nf + extra) + 4, sizeof(double));
    pvs__free_array(a, top, (size_t)nf + extra + 1, sizeof(float));
    if (r != PVS_OK) {
        pvs__vbake_destroy(vb);
        return r;
    }
    *out = vb;
    return PVS_OK;
}

/* The slice heights of a cell (§3.1): a histogram of the tops of the occluders that reach above the
   cell, each weighted by the angle it subtends from the cell's centre (its perspective size: a near
   wall counts more than a far one); n heights at the weighted quantiles (i + 0.2) / (n + 0.2), each
   snapped down to an occluder's top (so that occluder takes part). Low slices keep most occluders
   and fuse best, higher ones hide what stands behind lower walls; one slice sits at the 1/6 quantile.
   Ascending, distinct. Returns their number (<= n). */
PVS__STATIC uint32_t pvs__vo_slice_heights(const pvs__vbake *vb, const double *centre, float ctop, uint32_t n, float *h, const pvs_allocator *al) {
    const pvs__vprep *p = vb->prep;
    pvs__vo_key *key;
    double *w, total = 0.0, acc = 0.0;
    uint32_t i, m = 0, j = 0, out = 0;
    key = (pvs__vo_key *)pvs__alloc_array(al, (size_t)p->nobj + 1, sizeof(pvs__vo_key));
    w = (double *)pvs__alloc_array(al, (size_t)p->nobj + 1, sizeof(double));
    if (!key || !w) {
        pvs__free_array(al, key, (size_t)p->nobj + 1, sizeof(pvs__vo_key));
        pvs__free_array(al, w, (size_t)p->nobj + 1, sizeof(double));
        return 0;
    }
    for (i = 0; i < p->nobj; ++i) {
        uint32_t ref = p->obj_ref[i], cnt, k, lo = 0, hi = 0;
        const double *pts;
        double o[2] = {0.0, 0.0}, loc[2 * PVS__VO_MAXH], ang;
        if (!(p->obj_top[i] >= ctop)) continue;
        if (ref < p->nloop) {
            pts = p->hull_pt + 2 * (size_t)p->hull_start[ref];
            cnt = p->hull_start[ref + 1] - p->hull_start[ref];
        } else {
            pts = p->seg + 4 * (size_t)(ref - p->nloop);
            cnt = 2;
        }
        for (k = 0; k < cnt; ++k) {
            loc[2 * k] = pts[2 * k] - centre[0];
            loc[2 * k + 1] = pts[2 * k + 1] - centre[1];
        }
        for (k = 1; k < cnt; ++k) {
            if (pvs__vo_cross(o, loc + 2 * lo, loc + 2 * k) < 0.0) lo = k;
            if (pvs__vo_cross(o, loc + 2 * hi, loc + 2 * k) > 0.0) hi = k;
        }
        ang = atan2(loc[2 * lo] * loc[2 * hi + 1] - loc[2 * lo + 1] * loc[2 * hi], loc[2 * lo] * loc[2 * hi] + loc[2 * lo + 1] * loc[2 * hi + 1]);
        if (!(ang > 0.0)) continue;
        key[m].k = p->obj_top[i];
        key[m].i = m;
        w[m] = ang;
        total += ang;
        ++m;
    }
    pvs__vo_sort(key, m);
    for (i = 0; i < n && m; ++i) {
        double target = total * ((double)i + 0.2) / ((double)n + 0.2);
        float hh;
        while (j + 1 < m && acc + w[key[j].i] < target) acc += w[key[j++].i];
        hh = (float)key[j].k;
        if (!out || hh > h[out - 1]) h[out++] = hh;
    }
    pvs__free_array(al, key, (size_t)p->nobj + 1, sizeof(pvs__vo_key));
    pvs__free_array(al, w, (size_t)p->nobj + 1, sizeof(double));
    return out;
}

/* One cell of a bake: the dense set over the slices, the greedy selection of Fig. 6, and the PVS
   rebuilt from the kept occluders exactly as pvs_vocc_cull will (object boxes of the scene, never-
   drawn objects empty). Writes *count occluders (<= max_keep) of 5 bytes to bytes, the scale code,
   and the PVS (cleared first). */
PVS__STATIC pvs_result pvs__vo_bake_cell(const pvs__vbake *vb, const pvs_box *cell, uint8_t *bytes, uint8_t *count, uint8_t *scale,
                                         pvs_word *pvs, pvs_vocc_stats *stats, pvs_error *err) {
    const pvs_allocator *al = &vb->a;
    pvs__vctx c;
    double centre[2], cmin[2], cmax[2], reach = 0.0;
    float h[16];
    uint32_t ns, i, j, keep = 0, words = (uint32_t)PVS_BITSET_WORDS(vb->object_count), code;
    int u, v, k;
    pvs__vo_rt *rt = NULL, *sel = NULL;
    pvs_word *hid = NULL, *covered = NULL;
    pvs_result r = PVS_OK;
    *count = 0;
    *scale = 128;
    pvs__ground_axes(vb->up, &u, &v);
    pvs__vo_cell_centre(cell, u, v, centre);
    cmin[0] = cell->min[u]; cmin[1] = cell->min[v];
    cmax[0] = cell->max[u]; cmax[1] = cell->max[v];
    for (k = 0; k < 4; ++k) { /* the analysis radius: every occluder */
        double dx = ((k & 1) ? vb->prep->bb[2] : vb->prep->bb[0]) - centre[0], dy = ((k & 2) ? vb->prep->bb[3] : vb->prep->bb[1]) - centre[1];
        double d = sqrt(dx * dx + dy * dy);
        if (d > reach) reach = d;
    }
    reach = reach * 1.01 + 1.0;
    code = pvs__vo_scale_code(reach);
    *scale = (uint8_t)code;
    memset(&c, 0, sizeof(c));
    /* virtual occluders need the cell above their base and within an occluder-free rectangle with area */
    if (cell->min[vb->up] >= vb->base && cmax[0] > cmin[0] && cmax[1] > cmin[1] && vb->prep->nobj) {
        if (!pvs__vctx_init(&c, al, vb->prep, cmin, cmax, reach)) { r = PVS_ERROR_OUT_OF_MEMORY; goto done; }
        c.centre[0] = centre[0]; /* the file's frame (float centre) */
        c.centre[1] = centre[1];
        for (k = 0; k < 2; ++k) {
            c.cmin[k] = cmin[k] - centre[k];
            c.cmax[k] = cmax[k] - centre[k];
        }
        c.corner[0] = c.cmin[0]; c.corner[1] = c.cmin[1];
        c.corner[2] = c.cmax[0]; c.corner[3] = c.cmin[1];
        c.corner[4] = c.cmax[0]; c.corner[5] = c.cmax[1];
        c.corner[6] = c.cmin[0]; c.corner[7] = c.cmax[1];
        c.quantize = 1;
        c.qscale = pvs__vo_scale(code);
        c.qground = vb->base;
        c.qhstep = vb->hstep;
        c.max_seeds = vb->max_seeds;
        ns = pvs__vo_slice_heights(vb, centre, cell->max[vb->up], vb->slices < 16 ? vb->slices : 16, h, al);
        c.st.slices = ns;
        for (i = 0; i < ns && !c.oom; ++i) {
            if (!pvs__vctx_slice(&c, h[i])) break;
            pvs__vo_run_slice(&c);
        }
        if (c.oom) { r = PVS_ERROR_OUT_OF_MEMORY; goto done; }
    }
    /* the selection (Fig. 6): weights = objects each occluder hides; take the heaviest, discount
       what it hides from the others, until the next one stops paying (hides fewer than min_gain new
       objects) or max_keep are kept */
    if (c.nout) {
        uint32_t min_gain = vb->object_count / 1000u + 1u;
        rt = (pvs__vo_rt *)pvs__alloc_array(al, c.nout, sizeof(pvs__vo_rt));
        hid = (pvs_word *)pvs__alloc_array(al, (size_t)c.nout * words, sizeof(pvs_word));
        covered = (pvs_word *)pvs__alloc_array(al, words, sizeof(pvs_word));
        sel = (pvs__vo_rt *)pvs__alloc_array(al, (size_t)vb->max_keep + 1, sizeof(pvs__vo_rt));
        if (!rt || !hid || !covered || !sel) { r = PVS_ERROR_OUT_OF_MEMORY; goto done; }
        memset(hid, 0, (size_t)c.nout * words * sizeof(pvs_word));
        memset(covered, 0, words * sizeof(pvs_word));
        for (i = 0; i < c.nout; ++i) {
            double a[2], b[2], lo, hi;
            for (j = 0; j < i; ++j)
                if (!memcmp(c.out[j].q, c.out[i].q, 5)) break;
            if (j < i) { /* the same bytes twice: hides nothing more */
                memset(rt + i, 0, sizeof(pvs__vo_rt));
                continue;
            }
            pvs__vo_decode(cell, vb->up, code, c.out[i].q, vb->base, vb->hstep, a, b, &lo, &hi);
            pvs__vo_rt_init(rt + i, cell, vb->up, a, b, lo, hi);
        }
        for (j = 0; j < vb->object_count; ++j) {
            if (!pvs__vo_box_ok(vb->boxes + j)) continue;
            for (i = 0; i < c.nout; ++i)
                if (pvs__vo_rt_hides(rt + i, vb->boxes + j)) hid[(size_t)i * words + (j >> 6)] |= (pvs_word)1 << (j & 63);
        }
        while (keep < vb->max_keep) {
            uint32_t best = PVS__VO_NONE, best_gain = 0;
            for (i = 0; i < c.nout; ++i) {
                uint32_t gain = 0;
                const pvs_word *hw = hid + (size_t)i * words;
                for (j = 0; j < words; ++j) gain += pvs__popcount64(hw[j] & ~covered[j]);
                if (gain > best_gain) { best_gain = gain; best = i; }
            }
            if (best == PVS__VO_NONE || best_gain < min_gain) break;
            for (j = 0; j < words; ++j) covered[j] |= hid[(size_t)best * words + j];
            memcpy(bytes + 5 * (size_t)keep, c.out[best].q, 5);
            sel[keep++] = rt[best];
        }
    }
    *count = (uint8_t)keep;
    {
        pvs__vo_walk w;
        w.rt = sel;
        w.count = keep;
        w.boxes = vb->boxes;
        w.object_count = vb->object_count;
        w.visible = pvs;
        memset(pvs, 0, words * sizeof(pvs_word));
        for (j = 0; j < vb->object_count; ++j)
            if (pvs__vo_box_ok(vb->boxes + j) && !pvs__vo_walk_hidden(&w, vb->boxes + j)) pvs_bitset_set(pvs, j);
    }
    c.st.selected = keep;
    if (stats) {
        stats->slices += c.st.slices;
        stats->seeds += c.st.seeds;
        stats->umbra += c.st.umbra;
        stats->separating += c.st.separating;
        stats->dense += c.st.dense;
        stats->dropped += c.st.dropped;
        stats->selected += c.st.selected;
    }
done:
    if (rt) pvs__free_array(al, rt, c.nout, sizeof(pvs__vo_rt));
    if (hid) pvs__free_array(al, hid, (size_t)c.nout * words, sizeof(pvs_word));
    if (covered) pvs__free_array(al, covered, words, sizeof(pvs_word));
    if (sel) pvs__free_array(al, sel, (size_t)vb->max_keep + 1, sizeof(pvs__vo_rt));
    if (c.al) pvs__vctx_free(&c);
    if (r != PVS_OK) return pvs__fail(err, r, -1, 0, "virtual occluders: out of memory");
    return PVS_OK;
}

/* ---- the 2D entry point ---- */

PVS_API pvs_result pvs_vocc_2d(const pvs_vocc_2d_desc *d, float *occ, uint32_t capacity, uint32_t *count, pvs_vocc_stats *stats, pvs_error *err) {
    pvs_allocator al;
    pvs__vprep *p = NULL;
    pvs__vctx c;
    double *seg = NULL, cmin[2], cmax[2];
    float *top = NULL;
    uint32_t i, k;
    pvs_result r = PVS_OK;
    if (count) *count = 0;
    if (stats) memset(stats, 0, sizeof(*stats));
    if (!d || !count || (d->segment_count && !d->segments))
        return pvs__fail(err, PVS_ERROR_INVALID_ARGUMENT, -1, 0, "desc, count and the segments must not be NULL");
    for (k = 0; k < 2; ++k) {
        if (!pvs__finite(d->cell_min[k]) || !pvs__finite(d->cell_max[k])) return pvs__fail(err, PVS_ERROR_NOT_FINITE, -1, 0, "the cell is not finite");
        if (!(d->cell_min[k] < d->cell_max[k])) return pvs__fail(err, PVS_ERROR_BAD_CELL, -1, 0, "the cell has no area (min >= max on axis %u)", k);
    }
    if (!pvs__finite(d->range) || d->range < 0.0f) return pvs__fail(err, PVS_ERROR_INVALID_ARGUMENT, -1, 0, "range must be finite and >= 0");
    for (i = 0; i < 4 * d->segment_count; ++i)
        if (!pvs__finite(d->segments[i])) return pvs__fail(err, PVS_ERROR_NOT_FINITE, i / 4, 0, "segment %u is not finite", i / 4);
    al = d->allocator;
    seg = (double *)pvs__alloc_array(&al, 4 * (size_t)d->segment_count + 4, sizeof(double));
    top = (float *)pvs__alloc_array(&al, (size_t)d->segment_count + 1, sizeof(float));
    if (!seg || !top) { r = PVS_ERROR_OUT_OF_MEMORY; goto done; }
    for (i = 0; i < 4 * d->segment_count; ++i) seg[i] = d->segments[i];
    for (i = 0; i < d->segment_count; ++i) top[i] = 1.0f;
    r = pvs__vprep_create(&al, seg, top, d->segment_count, &p);
    if (r != PVS_OK) goto done;
    for (k = 0; k < 2; ++k) { cmin[k] = d->cell_min[k]; cmax[k] = d->cell_max[k]; }
    if (!pvs__vctx_init(&c, &al, p, cmin, cmax, d->range)) { pvs__vctx_free(&c); r = PVS_ERROR_OUT_OF_MEMORY; goto done; }
    c.max_seeds = d->max_seeds ? d->max_seeds : 16;
    if (pvs__vctx_slice(&c, 0.5f)) pvs__vo_run_slice(&c);
    if (c.oom) {
        pvs__vctx_free(&c);
        r = PVS_ERROR_OUT_OF_MEMORY;
        goto done;
    }
    *count = c.nout;
    for (i = 0; occ && i < c.nout && i < capacity; ++i) memcpy(occ + 4 * (size_t)i, c.out[i].f, 4 * sizeof(float));
    if (stats) *stats = c.st;
    pvs__vctx_free(&c);
done:
    pvs__free_array(&al, seg, 4 * (size_t)d->segment_count + 4, sizeof(double));
    pvs__free_array(&al, top, (size_t)d->segment_count + 1, sizeof(float));
    pvs__vprep_destroy(p);
    if (r != PVS_OK) return pvs__fail(err, r, -1, 0, "virtual occluders: out of memory");
    pvs__ok(err);
    return PVS_OK;
}

// >>methods
/* ---------------------------------------------------------------------------------------------- */
/* methods: region visibility: the ray-sampling estimator; extended projections (at the end)      */
/* ---------------------------------------------------------------------------------------------- */

PVS_API const char *pvs_method_name(pvs_method m) {
    switch (m) {
    case PVS_METHOD_DEFAULT: return "default";
    case PVS_METHOD_SAMPLE: return "sample";
    case PVS_METHOD_OTREE: return "otree";
    case PVS_METHOD_EXTPROJ: return "extproj";
    case PVS_METHOD_SHRINK: return "shrink";
    case PVS_METHOD_AUTO: return "auto";
    case PVS_METHOD_VOCC: return "vocc";
    default: return "unknown";
    }
}

/* Sample point i of `points` in the cell: the 8 corners, the 6 face centres, then one jittered point
   in each of `points - 14` strata spread evenly over a g^k grid on the cell's k non-flat axes. */
PVS__STATIC void pvs__sample_point(const pvs_box *cell, uint32_t i, uint32_t points, uint64_t *state, float p[3]) {
    int k;
    if (i < 8) {
        for (k = 0; k < 3; ++k) p[k] = (i >> k) & 1u ? cell->max[k] : cell->min[k];
    } else if (i < 14) {
        int axis = (int)(i - 8) / 2;
        for (k = 0; k < 3; ++k) p[k] = 0.5f * (cell->min[k] + cell->max[k]);
        p[axis] = (i - 8) & 1u ? cell->max[axis] : cell->min[axis];
    } else {
        uint64_t m = points - 14u, j = i - 14u, g = 1, strata = 1, stratum;
        int axes = 0;
        for (k = 0; k < 3; ++k) axes += cell->max[k] > cell->min[k];
        if (axes) {
            /* the smallest g with g^axes >= m */
            for (;;) {
                uint64_t total = 1;
                for (k = 0; k < axes; ++k) total *= g;
                if (total >= m) { strata = total; break; }
                ++g;
            }
        }
        stratum = j * strata / m;
        for (k = 0; k < 3; ++k) {
            float lo = cell->min[k], hi = cell->max[k], f;
            if (!(hi > lo)) { p[k] = lo; continue; }
            f = ((float)(stratum % g) + pvs__random01(state)) / (float)g;
            stratum /= g;
            p[k] = lo + f * (hi - lo);
            if (p[k] > hi) p[k] = hi;
        }
    }
}

PVS_API uint64_t pvs_sample_visibility(const pvs_scene *scene, const pvs_box *cell, uint32_t points, uint32_t rays_per_point,
                                       uint64_t seed, pvs_word *visible) {
    uint64_t state = seed, rays = 0;
    pvs_box bounds;
    float diagonal;
    uint32_t i, j;
    int k;
    if (!scene || !cell || !visible || !pvs__box_valid(cell)) return 0;
    bounds = scene->bounds;
    diagonal = pvs__v3_length(pvs__v3_sub(pvs__v3_load(bounds.max), pvs__v3_load(bounds.min)));
    for (i = 0; i < points; ++i) {
        float p[3], rot[3][3], tmax, q0, q1, q2, q3, u1, u2, u3;
        pvs_box pb;
        pvs__sample_point(cell, i, points, &state, p);
        /* a uniformly random rotation per point (Shoemake 1992, a random unit quaternion) ... */
        u1 = pvs__random01(&state);
        u2 = 6.2831853f * pvs__random01(&state);
        u3 = 6.2831853f * pvs__random01(&state);
        q0 = sqrtf(1.0f - u1) * sinf(u2);
        q1 = sqrtf(1.0f - u1) * cosf(u2);
        q2 = sqrtf(u1) * sinf(u3);
        q3 = sqrtf(u1) * cosf(u3);
        rot[0][0] = 1.0f - 2.0f * (q1 * q1 + q2 * q2);
        rot[0][1] = 2.0f * (q0 * q1 - q2 * q3);
        rot[0][2] = 2.0f * (q0 * q2 + q1 * q3);
        rot[1][0] = 2.0f * (q0 * q1 + q2 * q3);
        rot[1][1] = 1.0f - 2.0f * (q0 * q0 + q2 * q2);
        rot[1][2] = 2.0f * (q1 * q2 - q0 * q3);
        rot[2][0] = 2.0f * (q0 * q2 - q1 * q3);
        rot[2][1] = 2.0f * (q1 * q2 + q0 * q3);
        rot[2][2] = 1.0f - 2.0f * (q0 * q0 + q1 * q1);
        for (k = 0; k < 3; ++k) pb.min[k] = pb.max[k] = p[k];
        tmax = 2.0f * diagonal + sqrtf(pvs__box_distance2(&pb, &bounds));
        /* ... of a spherical Fibonacci set: rays_per_point directions of equal solid angle */
        for (j = 0; j < rays_per_point; ++j) {
            float z = 1.0f - (2.0f * (float)j + 1.0f) / (float)rays_per_point, r, phi, f[3], dir[3];
            double turns = (double)j * 0.6180339887498949;
            pvs_hit hit;
            r = sqrtf(1.0f - z * z > 0.0f ? 1.0f - z * z : 0.0f);
            phi = 6.2831853f * (float)(turns - floor(turns));
            f[0] = r * cosf(phi);
            f[1] = r * sinf(phi);
            f[2] = z;
            for (k = 0; k < 3; ++k) dir[k] = rot[k][0] * f[0] + rot[k][1] * f[1] + rot[k][2] * f[2];
            ++rays;
            if (pvs_scene_raycast(scene, p, dir, tmax, &hit) && hit.object != PVS_NO_OBJECT &&
                !(scene->object_flags[hit.object] & PVS_OBJECT_OCCLUDER_ONLY))
                pvs_bitset_set(visible, hit.object);
        }
    }
    return rays;
}

PVS_API uint64_t pvs_sample_visibility_toward(const pvs_scene *scene, const pvs_box *cell, const pvs_word *targets,
                                              uint32_t rays_per_object, uint64_t seed, pvs_word *visible) {
    uint64_t state = seed, rays = 0;
    uint32_t o, r;
    int k;
    if (!scene || !cell || !visible || !pvs__box_valid(cell)) return 0;
    for (o = 0; o < scene->object_count; ++o) {
        uint32_t first = scene->object_triangles[2 * (size_t)o], count = scene->object_triangles[2 * (size_t)o + 1];
        if ((targets && !pvs_bitset_test(targets, o)) || pvs_bitset_test(visible, o) || !count ||
            (scene->object_flags[o] & PVS_OBJECT_OCCLUDER_ONLY))
            continue;
        for (r = 0; r < rays_per_object; ++r) {
            const uint32_t *tri = scene->indices + 3 * (size_t)(first + (uint32_t)(pvs__splitmix64(&state) % count));
            const float *v0 = scene->positions + 3 * (size_t)tri[0], *v1 = scene->positions + 3 * (size_t)tri[1],
                        *v2 = scene->positions + 3 * (size_t)tri[2];
            float p[3], q[3], dir[3], su = sqrtf(pvs__random01(&state)), b = pvs__random01(&state), len = 0.0f;
            float w1 = su * (1.0f - b), w2 = su * b, w0 = 1.0f - w1 - w2;
            pvs_hit hit;
            for (k = 0; k < 3; ++k) {
                float c = (v0[k] + v1[k] + v2[k]) * (1.0f / 3.0f);
                p[k] = cell->min[k] + pvs__random01(&state) * (cell->max[k] - cell->min[k]);
                q[k] = 0.99f * (w0 * v0[k] + w1 * v1[k] + w2 * v2[k]) + 0.01f * c;
                dir[k] = q[k] - p[k];
                len += dir[k] * dir[k];
            }
            len = sqrtf(len);
            if (!(len > 0.0f)) continue;
            for (k = 0; k < 3; ++k) dir[k] /= len;
            ++rays;
            if (pvs_scene_raycast(scene, p, dir, len * 1.001f + 1e-6f, &hit) && hit.object != PVS_NO_OBJECT &&
                !(scene->object_flags[hit.object] & PVS_OBJECT_OCCLUDER_ONLY)) {
                pvs_bitset_set(visible, hit.object);
                if (hit.object == o) break;
            }
        }
    }
    return rays;
}

/* ---- extended projections (Durand et al. 2000) ---- */

/* How the guarantee survives rounding. Everything runs in double from float inputs. A plane's frame
   maps a point to (u, v, w): w is the Depth beyond the cell's face (§2.3, positive leaving the cell);
   the cell spans w in [-extent, 0]. The view of a point P from a cell corner V on the plane w = W is
   V + (P - V) (W - Vw) / (Pw - Vw), defined for Pw > Vw, which is why occluders are clipped to w >= a
   small positive margin and occludees must lie entirely at w > 0. The Projection of a convex
   occluder is the intersection of its views from the 8 corners (§3.2: by convexity of the cell and
   the occluder the intersection over the corners is the one over the cell); each view is the convex
   hull of the projected vertices, so the Projection is an intersection of half-planes. It is
   scan-converted row by row: a pixel square is kept only when its worst corner passes every edge
   function by a margin above every rounding error (the conservative rasterization of §3.2, exact
   instead of shifted edges). The Depth written is the greatest w of the clipped occluder, rounded up:
   flat, no nearer than any point of the occluder (§2.3). An occludee box's Projection is the bounding
   rectangle of its views (§3.1); per axis its extremes are at a corner of the cell and a corner of
   the box (the projection is linear-fractional in each, so extremes sit at vertices), widened by the
   same kind of margin; its Depth is its least w, rounded down. A box is hidden when every pixel of
   its rectangle holds an occluder strictly nearer (§2.2); pixels outside the plane count as visible.

   The bake method (§6.1). Occluders are prepared once per bake: an object whose triangles close a
   convex surface becomes one convex solid, two consecutive coplanar triangles forming a convex quad
   one polygon, any other triangle itself; explicit BOX occluders are solids, EXTRUSION walls quads.
   Per cell and direction: the PVS__EP_DEFAULT_OCC occluders of largest solid angle (area seen along
   the axis over squared distance), a plane just behind the candidate filling the most pixels and a
   second one just behind the largest occluder, 256 x 256 depth maps with a max pyramid; then the
   object kD-tree front to back, skipping hidden nodes, an object visible when a part of its box cut
   by a leaf is. Objects meeting the cell are always visible.
   Limits: not done yet are the improved occludee Projection (§4), the slicing of concave closed
   meshes (§3.3), the occlusion sweep (§5) and adaptive cells; occluders are never fused across
   polygons except through the depth map, so gaps open at building corners and T-junctions, and in
   big street cells of a city or a forest of small leaves the PVS stays loose (see make bench). */

#define PVS__EP_MAXP 16                               /* vertices of one convex occluder */
#define PVS__EP_CLIPN (PVS__EP_MAXP * PVS__EP_MAXP)
#define PVS__EP_EXTEND 1.5                            /* planes extended beyond the cell (§6.1) */
#define PVS__EP_DEFAULT_RES 256
#define PVS__EP_DEFAULT_OCC 128
#define PVS__EP_PLANE_CANDIDATES 16
#define PVS__EP_PLANES 2                              /* planes per direction */

typedef struct pvs__epframe {
    int a, u, v;
    double s, face, W, u0, v0, su, sv;
    double cu[2], cv[2], cw[2];
    uint32_t width, height;
} pvs__epframe;

PVS__STATIC int pvs__ep_frame(const pvs_extproj_plane *pl, pvs__epframe *f) {
    int k;
    if (!pl || pl->axis > 2 || (pl->side != 1 && pl->side != -1) || !pvs__box_valid(&pl->cell)) return 0;
    if (!pvs__finite(pl->distance) || !(pl->distance > 0.0f)) return 0;
    for (k = 0; k < 4; ++k)
        if (!pvs__finite(pl->rect[k])) return 0;
    if (!(pl->rect[2] > pl->rect[0]) || !(pl->rect[3] > pl->rect[1])) return 0;
    if (pl->width < 1 || pl->width > 4096 || pl->height < 1 || pl->height > 4096) return 0;
    f->a = (int)pl->axis;
    f->u = (f->a + 1) % 3;
    f->v = (f->a + 2) % 3;
    f->s = pl->side > 0 ? 1.0 : -1.0;
    f->face = pl->side > 0 ? pl->cell.max[f->a] : pl->cell.min[f->a];
    f->W = pl->distance;
    f->u0 = pl->rect[0];
    f->v0 = pl->rect[1];
    f->su = (double)pl->width / ((double)pl->rect[2] - pl->rect[0]);
    f->sv = (double)pl->height / ((double)pl->rect[3] - pl->rect[1]);
    f->cu[0] = pl->cell.min[f->u]; f->cu[1] = pl->cell.max[f->u];
    f->cv[0] = pl->cell.min[f->v]; f->cv[1] = pl->cell.max[f->v];
    f->cw[0] = -((double)pl->cell.max[f->a] - pl->cell.min[f->a]);
    f->cw[1] = 0.0;
    f->width = pl->width;
    f->height = pl->height;
    return 1;
}

PVS__STATIC double pvs__ep_tri_normal(const float *a, const float *b, const float *c, double n[3]) {
    double e1[3], e2[3];
    int k;
    for (k = 0; k < 3; ++k) { e1[k] = (double)b[k] - a[k]; e2[k] = (double)c[k] - a[k]; }
    n[0] = e1[1] * e2[2] - e1[2] * e2[1];
    n[1] = e1[2] * e2[0] - e1[0] * e2[2];
    n[2] = e1[0] * e2[1] - e1[1] * e2[0];
    return sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
}

/* 2D cross product of (b - a) and (c - a). */
PVS__STATIC double pvs__ep_orient(const double *a, const double *b, const double *c) {
    return (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
}

/* Convex hull (Andrew's monotone chain), counter-clockwise, collinear points dropped. pts: n x 2,
   sorted in place; hull receives up to n + 1 points. Returns the hull's size. */
PVS__STATIC int pvs__ep_hull(double (*pts)[2], int n, double (*hull)[2]) {
    int i, j, k = 0, lower;
    for (i = 1; i < n; ++i) { /* insertion sort: n is small */
        double x = pts[i][0], y = pts[i][1];
        for (j = i - 1; j >= 0 && (pts[j][0] > x || (pts[j][0] == x && pts[j][1] > y)); --j) {
            pts[j + 1][0] = pts[j][0];
            pts[j + 1][1] = pts[j][1];
        }
        pts[j + 1][0] = x;
        pts[j + 1][1] = y;
    }
    if (n < 3) return 0;
    for (i = 0; i < n; ++i) {
        while (k >= 2 && pvs__ep_orient(hull[k - 2], hull[k - 1], pts[i]) <= 0.0) --k;
        hull[k][0] = pts[i][0]; hull[k][1] = pts[i][1]; ++k;
    }
    lower = k + 1;
    for (i = n - 2; i >= 0; --i) {
        while (k >= lower && pvs__ep_orient(hull[k - 2], hull[k - 1], pts[i]) <= 0.0) --k;
        hull[k][0] = pts[i][0]; hull[k][1] = pts[i][1]; ++k;
    }
    return k - 1; /* the last point repeats the first */
}

/* The Projection of the part of a convex occluder inside the depth slab [lo, hi]: the views are
   convex hulls of the projected vertices of the clipped part. The clipped part's vertices are among
   the points inside the slab and the ends of the clipped segments between any two points. */
PVS__STATIC uint32_t pvs__ep_occluder_part(const pvs__epframe *fp, const double (*src)[3], int count, double wlo, double whi, float *map) {
    pvs__epframe f = *fp;
    double P[PVS__EP_CLIPN][3], pts[PVS__EP_CLIPN][2], hull[PVS__EP_CLIPN + 1][2];
    double ea[8 * PVS__EP_CLIPN], eb[8 * PVS__EP_CLIPN], ec[8 * PVS__EP_CLIPN];
    double dmax = 0.0, xlo = -DBL_MAX, xhi = DBL_MAX, ylo = -DBL_MAX, yhi = DBL_MAX, perr, mag = 0.0, base;
    int n = 0, i, j, c, edges = 0;
    int32_t i0, i1, j0, j1, row;
    uint32_t written = 0;
    float depth;
    for (i = 0; i < count; ++i)
        if (src[i][2] >= wlo && src[i][2] <= whi) {
            P[n][0] = src[i][0]; P[n][1] = src[i][1]; P[n][2] = src[i][2];
            ++n;
        }
    for (i = 0; i < count; ++i)
        for (j = i + 1; j < count; ++j) {
            double wi = src[i][2], wj = src[j][2], cut[2];
            int m;
            cut[0] = wlo;
            cut[1] = whi;
            for (m = 0; m < 2; ++m) {
                double t, w = cut[m];
                int k;
                if (!((wi < w && wj > w) || (wi > w && wj < w))) continue;
                t = (w - wi) / (wj - wi);
                for (k = 0; k < 2; ++k) P[n][k] = src[i][k] + (src[j][k] - src[i][k]) * t;
                P[n][2] = w;
                ++n;
            }
        }
    if (n < 3) return 0;
    for (i = 0; i < n; ++i) dmax = pvs__dmax(dmax, P[i][2]);
    base = pvs__dabs(f.u0) * f.su + pvs__dabs(f.v0) * f.sv;
    /* the intersection of the views from the 8 corners of the cell (§3.2) */
    for (c = 0; c < 8; ++c) {
        double Vu = f.cu[c & 1], Vv = f.cv[(c >> 1) & 1], Vw = f.cw[(c >> 2) & 1], h;
        double bx0 = DBL_MAX, bx1 = -DBL_MAX, by0 = DBL_MAX, by1 = -DBL_MAX, area2 = 0.0;
        int k;
        for (i = 0; i < n; ++i) {
            double t = (f.W - Vw) / (P[i][2] - Vw);
            pts[i][0] = (Vu + (P[i][0] - Vu) * t - f.u0) * f.su;
            pts[i][1] = (Vv + (P[i][1] - Vv) * t - f.v0) * f.sv;
            bx0 = pvs__dmin(bx0, pts[i][0]); bx1 = pvs__dmax(bx1, pts[i][0]);
            by0 = pvs__dmin(by0, pts[i][1]); by1 = pvs__dmax(by1, pts[i][1]);
            mag = pvs__dmax(mag, pvs__dabs(pts[i][0]) + pvs__dabs(pts[i][1]) + (pvs__dabs(Vu) + pvs__dabs(P[i][0])) * t * f.su +
                                     (pvs__dabs(Vv) + pvs__dabs(P[i][1])) * t * f.sv);
        }
        if (!(bx1 - bx0 < 1e15) || !(by1 - by0 < 1e15)) return 0; /* beyond any useful precision */
        xlo = pvs__dmax(xlo, bx0); xhi = pvs__dmin(xhi, bx1);
        ylo = pvs__dmax(ylo, by0); yhi = pvs__dmin(yhi, by1);
        if (xhi - xlo < 1.0 || yhi - ylo < 1.0) return 0; /* no whole pixel fits */
        k = pvs__ep_hull(pts, n, hull);
        if (k < 3) return 0;
        for (i = 0; i < k; ++i) area2 += hull[i][0] * hull[i + 1 < k ? i + 1 : 0][1] - hull[i + 1 < k ? i + 1 : 0][0] * hull[i][1];
        h = (bx1 - bx0) + (by1 - by0);
        if (!(area2 > 1e-9 * h * h)) return 0; /* a sliver: covers no pixel */
        for (i = 0; i < k; ++i) {
            const double *p = hull[i], *q = hull[i + 1 < k ? i + 1 : 0];
            double a = -(q[1] - p[1]), b = q[0] - p[0], len = pvs__dabs(a) + pvs__dabs(b);
            if (!(len > 0.0)) continue;
            ea[edges] = a / len;
            eb[edges] = b / len;
            ec[edges] = -(ea[edges] * p[0] + eb[edges] * p[1]);
            ++edges;
        }
    }
    /* a bound on the vertices' rounding errors, in pixels (projection and frame change: a few ulps
       of the terms' size), widened for the edges' rotation over the raster's span */
    perr = 1e-12 * (mag + base + 1.0);
    i0 = pvs__clampi(ceil(xlo), 0, (int32_t)f.width);
    i1 = pvs__clampi(floor(xhi) - 1.0, -1, (int32_t)f.width - 1);
    j0 = pvs__clampi(ceil(ylo), 0, (int32_t)f.height);
    j1 = pvs__clampi(floor(yhi) - 1.0, -1, (int32_t)f.height - 1);
    if (i0 > i1 || j0 > j1) return 0;
    depth = pvs__f_up(dmax + 1e-12 * dmax);
    for (row = j0; row <= j1; ++row) {
        double lo = i0, hi = i1, y = row;
        int e;
        for (e = 0; e < edges && lo <= hi; ++e) {
            double a = ea[e], b = eb[e];
            /* the pixel's worst corner: a (i + [a < 0]) + b (y + [b < 0]) + c >= err */
            double r = ec[e] + b * y + (b < 0.0 ? b : 0.0) + (a < 0.0 ? a : 0.0);
            double err = 1e-6 + perr * (4.0 + 4.0 * (mag + (double)f.width + (double)f.height)) + 1e-12 * (pvs__dabs(ec[e]) + pvs__dabs(b * y));
            r -= err;
            if (a > 1e-12) {
                double x = -r / a;
                lo = pvs__dmax(lo, ceil(x + 1e-9 * (1.0 + pvs__dabs(x))));
            } else if (a < -1e-12) {
                double x = r / -a;
                hi = pvs__dmin(hi, floor(x - 1e-9 * (1.0 + pvs__dabs(x))));
            } else {
                /* nearly horizontal: test the worst of the row's two ends */
                double worst = r + pvs__dmin(a * lo, a * hi) - pvs__dabs(a);
                if (worst < 0.0) hi = lo - 1.0;
            }
        }
        if (lo > hi) continue;
        {
            float *px = map + (size_t)row * f.width;
            int32_t x0 = (int32_t)lo, x1 = (int32_t)hi, x;
            for (x = x0; x <= x1; ++x)
                if (px[x] > depth) px[x] = depth;
            written += (uint32_t)(x1 - x0 + 1);
        }
    }
    return written;
}

PVS_API uint32_t pvs_extproj_occluder(const pvs_extproj_plane *pl, const float *points, uint32_t count, float *map) {
    pvs__epframe f;
    double P[PVS__EP_MAXP][3], margin, wmax = -DBL_MAX;
    uint32_t i, written;
    if (!pvs__ep_frame(pl, &f) || !points || !map || count < 1 || count > PVS__EP_MAXP) return 0;
    for (i = 0; i < count * 3; ++i)
        if (!pvs__finite(points[i])) return 0;
    for (i = 0; i < count; ++i) {
        P[i][0] = points[3 * i + f.u];
        P[i][1] = points[3 * i + f.v];
        P[i][2] = f.s * ((double)points[3 * i + f.a] - f.face);
        wmax = pvs__dmax(wmax, P[i][2]);
    }
    if (count > 3) {
        /* a solid that meets the cell could hold the viewer: its Depth would not bound the first
           hit. Such occluders are left out (conservative); planar ones never hold a viewer. */
        double n[3], len = 0.0, scale = 0.0;
        int planar = 1;
        pvs_box b = pvs__box_empty();
        for (i = 0; i < count; ++i) pvs__box_add_point(&b, points + 3 * i);
        for (i = 2; i < count && !(len > 0.0); ++i) len = pvs__ep_tri_normal(points, points + 3, points + 3 * i, n);
        for (i = 0; i < 3; ++i) scale = pvs__dmax(scale, (double)b.max[i] - b.min[i]);
        for (i = 0; i < count && planar; ++i) {
            double d = n[0] * ((double)points[3 * i] - points[0]) + n[1] * ((double)points[3 * i + 1] - points[1]) +
                       n[2] * ((double)points[3 * i + 2] - points[2]);
            planar = pvs__dabs(d) <= 1e-7 * len * scale;
        }
        if (!(len > 0.0) || (!planar && pvs__box_overlap(&b, &pl->cell))) return 0;
    }
    /* clipped to depths >= a small margin (views are defined beyond the cell), and split at the
       plane: the set of cell points that see a pixel through the part in front of the plane (or
       through the part behind it) is convex, so the corners decide for the whole cell; for a part
       straddling the plane it would not be */
    margin = 1e-4 * (f.W - f.cw[0]);
    written = pvs__ep_occluder_part(&f, (const double(*)[3])P, (int)count, margin, f.W, map);
    if (wmax > f.W) written += pvs__ep_occluder_part(&f, (const double(*)[3])P, (int)count, f.W, DBL_MAX, map);
    return written;
}

/* Pixel bounds of the views of the box's (k, w) extent from the cell's (k, w) corners; t[c][b] =
   (W - cw[c]) / (bw[b] - cw[c]), shared by both axes. */
PVS__STATIC void pvs__ep_occludee_axis(const double *cell_k, double bk0, double bk1, const double t[2][2], double k0, double sk,
                                       uint32_t size, int32_t *lo, int32_t *hi) {
    double mn = DBL_MAX, mx = -DBL_MAX, mag = 0.0, err;
    int a, b, c;
    for (a = 0; a < 2; ++a)
        for (c = 0; c < 2; ++c)
            for (b = 0; b < 4; ++b) {
                double Vk = cell_k[a], Pk = b & 1 ? bk1 : bk0, tt = t[c][b >> 1];
                double x = (Vk + (Pk - Vk) * tt - k0) * sk;
                mn = pvs__dmin(mn, x);
                mx = pvs__dmax(mx, x);
                mag = pvs__dmax(mag, (pvs__dabs(Vk) + (pvs__dabs(Pk) + pvs__dabs(Vk)) * tt + pvs__dabs(k0)) * sk);
            }
    err = 1e-6 + 1e-12 * mag;
    *lo = pvs__clampi(floor(mn - err), -1, (int32_t)size);
    *hi = pvs__clampi(floor(mx + err), -1, (int32_t)size);
}

/* pvs_extproj_occludee with a prepared frame and a valid box. */
PVS__STATIC int pvs__ep_occludee(const pvs__epframe *f, const pvs_box *box, int32_t rect[4], float *depth) {
    double bw[2], t[2][2];
    int c, b;
    bw[0] = f->s > 0 ? (double)box->min[f->a] - f->face : f->face - (double)box->max[f->a];
    bw[1] = f->s > 0 ? (double)box->max[f->a] - f->face : f->face - (double)box->min[f->a];
    if (!(bw[0] > 0.0)) return 0;
    for (c = 0; c < 2; ++c)
        for (b = 0; b < 2; ++b) t[c][b] = (f->W - f->cw[c]) / (bw[b] - f->cw[c]);
    pvs__ep_occludee_axis(f->cu, box->min[f->u], box->max[f->u], (const double(*)[2])t, f->u0, f->su, f->width, &rect[0], &rect[2]);
    pvs__ep_occludee_axis(f->cv, box->min[f->v], box->max[f->v], (const double(*)[2])t, f->v0, f->sv, f->height, &rect[1], &rect[3]);
    *depth = pvs__f_down(bw[0] - 1e-12 * bw[0]);
    return 1;
}

PVS_API int pvs_extproj_occludee(const pvs_extproj_plane *pl, const pvs_box *box, int32_t rect[4], float *depth) {
    pvs__epframe f;
    if (!pvs__ep_frame(pl, &f) || !box || !rect || !depth || !pvs__box_valid(box)) return 0;
    return pvs__ep_occludee(&f, box, rect, depth);
}

PVS_API int pvs_extproj_test(const pvs_extproj_plane *pl, const float *map, const int32_t rect[4], float depth) {
    int32_t i, j;
    if (!pl || !map || !rect) return 1;
    if (rect[0] < 0 || rect[1] < 0 || rect[2] >= (int32_t)pl->width || rect[3] >= (int32_t)pl->height) return 1;
    for (j = rect[1]; j <= rect[3]; ++j)
        for (i = rect[0]; i <= rect[2]; ++i)
            if (!(map[(size_t)j * pl->width + i] < depth)) return 1;
    return 0;
}

/* ---- the bake method: occluders prepared once per bake, then per cell six planes ---- */

/* One convex occluder: a planar convex polygon (a triangle, or coplanar triangles merged) or a
   closed convex solid (an object whose triangles bound their convex hull). */
typedef struct pvs__epocc {
    pvs_box box;
    float area[3];         /* area seen along each axis: of the polygon projected, of a solid's box face */
    uint32_t first, count; /* points */
} pvs__epocc;

typedef struct pvs__extproj_prep {
    pvs_allocator allocator;
    pvs__epocc *occ;
    uint32_t occ_count, occ_capacity;
    float *pts;            /* 3 floats per point */
    size_t pt_count, pt_capacity;
} pvs__extproj_prep;

PVS__STATIC void pvs__extproj_prep_destroy(pvs__extproj_prep *p) {
    pvs_allocator a;
    if (!p) return;
    a = p->allocator;
    pvs__free_array(&a, p->occ, p->occ_capacity, sizeof(pvs__epocc));
    pvs__free_array(&a, p->pts, p->pt_capacity * 3, sizeof(float));
    pvs__free(&a, p, sizeof(*p), 16);
}

/* Adds a convex occluder. A polygon's area along axis k is its area times |n_k| (n, its unit
   normal: the area of its shadow on a plane of that axis); a solid's is its box's face. */
PVS__STATIC void pvs__ep_add(pvs__extproj_prep *p, const float *const *pts, uint32_t n, int solid) {
    pvs__epocc *o = p->occ + p->occ_count++;
    uint32_t i;
    int k;
    o->box = pvs__box_empty();
    o->first = (uint32_t)p->pt_count;
    o->count = n;
    for (i = 0; i < n; ++i) {
        memcpy(p->pts + 3 * p->pt_count, pts[i], 3 * sizeof(float));
        pvs__box_add_point(&o->box, pts[i]);
        ++p->pt_count;
    }
    if (solid) {
        for (k = 0; k < 3; ++k)
            o->area[k] = (o->box.max[(k + 1) % 3] - o->box.min[(k + 1) % 3]) * (o->box.max[(k + 2) % 3] - o->box.min[(k + 2) % 3]);
    } else {
        double a[3] = {0.0, 0.0, 0.0};
        for (i = 1; i + 1 < n; ++i) { /* fan: twice the vector area */
            double e1[3], e2[3];
            for (k = 0; k < 3; ++k) { e1[k] = (double)pts[i][k] - pts[0][k]; e2[k] = (double)pts[i + 1][k] - pts[0][k]; }
            a[0] += e1[1] * e2[2] - e1[2] * e2[1];
            a[1] += e1[2] * e2[0] - e1[0] * e2[2];
            a[2] += e1[0] * e2[1] - e1[1] * e2[0];
        }
        for (k = 0; k < 3; ++k) o->area[k] = (float)(0.5 * pvs__dabs(a[k]));
    }
}

PVS__STATIC int pvs__ep_same(const float *a, const float *b) { return a[0] == b[0] && a[1] == b[1] && a[2] == b[2]; }


/* Two triangles sharing an edge, coplanar, whose union is a convex quad: fills q[4] and returns 1. */
PVS__STATIC int pvs__ep_quad(const float *const *A, const float *const *B, const float **q) {
    int i, j, k;
    double n[3], len = pvs__ep_tri_normal(A[0], A[1], A[2], n), scale = 0.0;
    if (!(len > 0.0)) return 0;
    for (i = 0; i < 3; ++i)
        for (j = 0; j < 3; ++j) {
            const float *a0 = A[i], *a1 = A[(i + 1) % 3], *x;
            if (!(pvs__ep_same(a0, B[j]) && pvs__ep_same(a1, B[(j + 2) % 3])) && !(pvs__ep_same(a0, B[(j + 2) % 3]) && pvs__ep_same(a1, B[j])))
                continue;
            x = B[(j + 1) % 3];
            q[0] = a0; q[1] = x; q[2] = a1; q[3] = A[(i + 2) % 3];
            for (k = 0; k < 3; ++k) scale = pvs__dmax(scale, pvs__dabs((double)x[k] - a0[k]));
            /* coplanar up to float precision of the input */
            if (pvs__dabs(n[0] * ((double)x[0] - a0[0]) + n[1] * ((double)x[1] - a0[1]) + n[2] * ((double)x[2] - a0[2])) > 1e-7 * len * scale)
                return 0;
            for (k = 0; k < 4; ++k) { /* strictly convex at every corner, turning like the triangle */
                const float *p0 = q[k], *p1 = q[(k + 1) % 4], *p2 = q[(k + 2) % 4];
                double m[3];
                pvs__ep_tri_normal(p0, p1, p2, m);
                if (!(m[0] * n[0] + m[1] * n[1] + m[2] * n[2] > 0.0)) return 0;
            }
            return 1;
        }
    return 0;
}

/* An object whose triangles form a closed surface in convex position bounds a convex solid: its
   unique vertices (<= PVS__EP_MAXP) go to pts. Returns the count, or 0. Every edge must be shared by
   exactly two of the object's triangles (by position) and every vertex must lie on one side of
   every triangle's plane. */
PVS__STATIC uint32_t pvs__ep_convex_object(const pvs_scene *s, uint32_t t0, uint32_t tn, const float **pts) {
    uint32_t t, n = 0, i, k;
    double scale = 0.0;
    if (tn < 4 || tn > 2 * PVS__EP_MAXP) return 0;
    for (t = t0; t < t0 + tn; ++t)
        for (k = 0; k < 3; ++k) {
            const float *p = s->positions + 3 * (size_t)s->indices[3 * (size_t)t + k];
            for (i = 0; i < n && !pvs__ep_same(pts[i], p); ++i) {}
            if (i == n) {
                if (n == PVS__EP_MAXP) return 0;
                pts[n++] = p;
            }
        }
    for (i = 0; i < n; ++i)
        for (k = 0; k < 3; ++k) scale = pvs__dmax(scale, pvs__dabs((double)pts[i][k] - pts[0][k]));
    for (t = t0; t < t0 + tn; ++t) {
        const float *c[3];
        double nrm[3], len, lo = 0.0, hi = 0.0;
        uint32_t e, u;
        for (k = 0; k < 3; ++k) c[k] = s->positions + 3 * (size_t)s->indices[3 * (size_t)t + k];
        len = pvs__ep_tri_normal(c[0], c[1], c[2], nrm);
        if (!(len > 0.0)) return 0;
        for (i = 0; i < n; ++i) {
            double d = nrm[0] * ((double)pts[i][0] - c[0][0]) + nrm[1] * ((double)pts[i][1] - c[0][1]) + nrm[2] * ((double)pts[i][2] - c[0][2]);
            lo = pvs__dmin(lo, d);
            hi = pvs__dmax(hi, d);
        }
        if (lo < -1e-9 * len * scale && hi > 1e-9 * len * scale) return 0;
        for (e = 0; e < 3; ++e) { /* each edge shared by exactly one other triangle */
            const float *a = c[e], *b = c[(e + 1) % 3];
            uint32_t shared = 0;
            for (u = t0; u < t0 + tn; ++u) {
                const float *d[3];
                int m, has_a = 0, has_b = 0;
                if (u == t) continue;
                for (m = 0; m < 3; ++m) {
                    d[m] = s->positions + 3 * (size_t)s->indices[3 * (size_t)u + m];
                    has_a |= pvs__ep_same(d[m], a);
                    has_b |= pvs__ep_same(d[m], b);
                }
                shared += (uint32_t)(has_a && has_b);
            }
            if (shared != 1) return 0;
        }
    }
    return n;
}

/* Builds the occluder list of a scene (§6.1 picks among it per cell). */
PVS__STATIC pvs_result pvs__extproj_prepare(const pvs_scene *s, const pvs_allocator *a, pvs__extproj_prep **out, pvs_error *err) {
    pvs__extproj_prep *p;
    size_t occ_cap = (size_t)s->triangle_count + 1, pt_cap = 3 * (size_t)s->triangle_count + 1;
    uint32_t o, t, i;
    *out = NULL;
    for (i = 0; i < s->occluder_count; ++i) {
        const pvs_occluder_desc *d = s->occluders + i;
        if (d->kind == PVS_OCCLUDER_BOX) { occ_cap += 1; pt_cap += 8; }
        if (d->kind == PVS_OCCLUDER_EXTRUSION) { occ_cap += d->footprint_count; pt_cap += 4 * (size_t)d->footprint_count; }
    }
    if (occ_cap > 0xffffffffu || pt_cap > 0xffffffffu) return pvs__fail(err, PVS_ERROR_COUNT_OVERFLOW, -1, 0, "extproj: too many occluders");
    p = (pvs__extproj_prep *)pvs__alloc(a, sizeof(*p), 16);
    if (!p) return pvs__fail(err, PVS_ERROR_OUT_OF_MEMORY, -1, 0, "extproj occluders");
    memset(p, 0, sizeof(*p));
    p->allocator = *a;
    p->occ_capacity = (uint32_t)occ_cap;
    p->pt_capacity = pt_cap;
    p->occ = (pvs__epocc *)pvs__alloc_array(a, occ_cap, sizeof(pvs__epocc));
    p->pts = (float *)pvs__alloc_array(a, pt_cap * 3, sizeof(float));
    if (!p->occ || !p->pts) {
        pvs__extproj_prep_destroy(p);
        return pvs__fail(err, PVS_ERROR_OUT_OF_MEMORY, -1, 0, "extproj occluders (%llu)", (unsigned long long)occ_cap);
    }
    /* triangles in object order; an object that is a closed convex surface becomes one solid,
       consecutive coplanar triangles forming a convex quad become one polygon (fewer cracks between
       Projections, §3.2-3.3) */
    for (t = 0; t < s->triangle_count;) {
        uint32_t obj = s->triangle_object[t], end = t + 1;
        const float *tri[3], *nxt[3], *q[PVS__EP_MAXP];
        double nrm[3], len;
        int k;
        if (obj != PVS_NO_OBJECT) {
            /* the object's range starts here when t is its first triangle */
            uint32_t n;
            while (end < s->triangle_count && s->triangle_object[end] == obj) ++end;
            n = pvs__ep_convex_object(s, t, end - t, q);
            if (n >= 4) {
                pvs__ep_add(p, q, n, 1);
                t = end;
                continue;
            }
        }
        for (; t < end; ++t) {
            for (k = 0; k < 3; ++k) tri[k] = s->positions + 3 * (size_t)s->indices[3 * (size_t)t + k];
            len = pvs__ep_tri_normal(tri[0], tri[1], tri[2], nrm);
            if (!(len > 0.0)) continue;
            if (t + 1 < end) {
                for (k = 0; k < 3; ++k) nxt[k] = s->positions + 3 * (size_t)s->indices[3 * (size_t)(t + 1) + k];
                if (pvs__ep_quad(tri, nxt, q)) {
                    pvs__ep_add(p, q, 4, 0);
                    ++t;
                    continue;
                }
            }
            pvs__ep_add(p, tri, 3, 0);
        }
    }
    for (o = 0; o < s->occluder_count; ++o) {
        const pvs_occluder_desc *d = s->occluders + o;
        float c[8][3];
        const float *q[8];
        if (d->kind == PVS_OCCLUDER_BOX) {
            for (i = 0; i < 8; ++i) {
                c[i][0] = i & 1 ? d->box.max[0] : d->box.min[0];
                c[i][1] = i & 2 ? d->box.max[1] : d->box.min[1];
                c[i][2] = i & 4 ? d->box.max[2] : d->box.min[2];
                q[i] = c[i];
            }
            pvs__ep_add(p, q, 8, 1);
        } else if (d->kind == PVS_OCCLUDER_EXTRUSION) { /* its walls, each a planar quad */
            int u, v, up = (int)s->up_axis;
            pvs__ground_axes(s->up_axis, &u, &v);
            for (i = 0; i < d->footprint_count; ++i) {
                const float *f0 = d->footprint + 2 * i, *f1 = d->footprint + 2 * ((i + 1) % d->footprint_count);
                int k;
                for (k = 0; k < 4; ++k) {
                    const float *f = k == 0 || k == 3 ? f0 : f1;
                    c[k][u] = f[0];
                    c[k][v] = f[1];
                    c[k][up] = k < 2 ? d->base : d->top;
                    q[k] = c[k];
                }
                pvs__ep_add(p, q, 4, 0);
            }
        }
        /* CONVEX occluders are not used (leaving an occluder out is conservative) */
    }
    *out = p;
    return PVS_OK;
}

/* A depth map with its max pyramid (§2.4): level l texel = the greatest Depth of its 2 x 2 children. */
typedef struct pvs__epmap {
    pvs_extproj_plane plane;
    pvs__epframe frame;
    int active;
    uint32_t levels;
    uint32_t lw[14], lh[14];
    float *lv[14];
} pvs__epmap;

PVS__STATIC void pvs__ep_build_pyramid(pvs__epmap *m) {
    uint32_t l, x, y;
    for (l = 1; l <= m->levels; ++l) {
        uint32_t pw = m->lw[l - 1], ph = m->lh[l - 1];
        const float *src = m->lv[l - 1];
        float *dst = m->lv[l];
        for (y = 0; y < m->lh[l]; ++y)
            for (x = 0; x < m->lw[l]; ++x) {
                uint32_t x0 = 2 * x, y0 = 2 * y, x1 = x0 + 1 < pw ? x0 + 1 : x0, y1 = y0 + 1 < ph ? y0 + 1 : y0;
                float a = src[y0 * pw + x0], b = src[y0 * pw + x1], c = src[y1 * pw + x0], d = src[y1 * pw + x1];
                a = a > b ? a : b;
                c = c > d ? c : d;
                dst[y * m->lw[l] + x] = a > c ? a : c;
            }
    }
}

/* 1 if some level-0 pixel of rect under texel (tx, ty) of level l holds a Depth >= d. */
PVS__STATIC int pvs__ep_visible_at(const pvs__epmap *m, uint32_t l, uint32_t tx, uint32_t ty, const int32_t *r, float d) {
    uint32_t cx, cy;
    if (m->lv[l][ty * m->lw[l] + tx] < d) return 0;
    if (l == 0) return 1;
    for (cy = 2 * ty; cy <= 2 * ty + 1 && cy < m->lh[l - 1]; ++cy)
        for (cx = 2 * tx; cx <= 2 * tx + 1 && cx < m->lw[l - 1]; ++cx) {
            int32_t px0 = (int32_t)(cx << (l - 1)), py0 = (int32_t)(cy << (l - 1));
            int32_t px1 = px0 + (int32_t)(1u << (l - 1)) - 1, py1 = py0 + (int32_t)(1u << (l - 1)) - 1;
            if (px1 < r[0] || px0 > r[2] || py1 < r[1] || py0 > r[3]) continue;
            if (pvs__ep_visible_at(m, l - 1, cx, cy, r, d)) return 1;
        }
    return 0;
}

PVS__STATIC int pvs__ep_visible(const pvs__epmap *m, const int32_t *r, float d) {
    uint32_t l = 0, tx, ty;
    if (r[0] < 0 || r[1] < 0 || r[2] >= (int32_t)m->plane.width || r[3] >= (int32_t)m->plane.height) return 1;
    while (l < m->levels && (((uint32_t)r[2] >> l) - ((uint32_t)r[0] >> l) > 1 || ((uint32_t)r[3] >> l) - ((uint32_t)r[1] >> l) > 1)) ++l;
    for (ty = (uint32_t)r[1] >> l; ty <= (uint32_t)r[3] >> l; ++ty)
        for (tx = (uint32_t)r[0] >> l; tx <= (uint32_t)r[2] >> l; ++tx)
            if (pvs__ep_visible_at(m, l, tx, ty, r, d)) return 1;
    return 0;
}

typedef struct pvs__epsel {
    float score;
    uint32_t occ;
} pvs__epsel;

typedef struct pvs__epcell {
    const pvs_scene *scene;
    const pvs__extproj_prep *prep;
    pvs_box cell;
    pvs__epmap maps[6 * PVS__EP_PLANES];
    pvs_word *bits;
    uint32_t tested;
} pvs__epcell;

/* 1 if the box is hidden from the whole cell on one of the planes. Boxes meeting the cell are visible. */
PVS__STATIC int pvs__ep_box_hidden(pvs__epcell *c, const pvs_box *b) {
    int d;
    if (pvs__box_overlap(b, &c->cell)) return 0;
    ++c->tested;
    for (d = 0; d < 6 * PVS__EP_PLANES; ++d) {
        int32_t r[4];
        float depth;
        if (!c->maps[d].active) continue;
        if (!pvs__ep_occludee(&c->maps[d].frame, b, r, &depth)) continue;
        if (!pvs__ep_visible(&c->maps[d], r, depth)) return 1;
    }
    return 0;
}

/* §6.1: the occludees tested top-down through the object kD-tree, stopping at hidden nodes. An
   object is visible when a part of its box (its box cut by a leaf's cell) is. */
PVS__STATIC pvs_visit pvs__ep_visit(void *user, const pvs_box *node_box, float distance, const uint32_t *items, uint32_t count) {
    pvs__epcell *c = (pvs__epcell *)user;
    uint32_t i;
    (void)distance;
    if (pvs__ep_box_hidden(c, node_box)) return PVS_VISIT_SKIP;
    for (i = 0; i < count; ++i) {
        uint32_t o = items[i];
        pvs_box b = c->scene->object_boxes[o];
        int k;
        if (pvs_bitset_test(c->bits, o) || (c->scene->object_flags[o] & PVS_OBJECT_OCCLUDER_ONLY)) continue;
        for (k = 0; k < 3; ++k) {
            if (node_box->min[k] > b.min[k]) b.min[k] = node_box->min[k];
            if (node_box->max[k] < b.max[k]) b.max[k] = node_box->max[k];
        }
        if (b.min[0] > b.max[0] || b.min[1] > b.max[1] || b.min[2] > b.max[2]) continue; /* not in this leaf */
        if (!pvs__ep_box_hidden(c, &b)) pvs_bitset_set(c->bits, o);
    }
    return PVS_VISIT_DESCEND;
}

/* Local depth range of a box on plane direction d of the cell: w0, w1 (beyond the face). */
PVS__STATIC void pvs__ep_box_w(const pvs_box *cell, const pvs_box *b, int d, double *w0, double *w1) {
    int a = d >> 1;
    if (d & 1) { *w0 = (double)cell->min[a] - b->max[a]; *w1 = (double)cell->min[a] - b->min[a]; }
    else { *w0 = (double)b->min[a] - cell->max[a]; *w1 = (double)b->max[a] - cell->max[a]; }
}

/* §6.1 plane placement: an estimate of the pixels an occluder's box fills on the plane at distance
   W (the Projection of the box, axis by axis). */
PVS__STATIC double pvs__ep_fill_estimate(const pvs_box *cell, const pvs_box *b, int d, double W) {
    int a = d >> 1, ax[2], k, i, j;
    double w0, w1, ext = (double)cell->max[a] - cell->min[a], len[2];
    pvs__ep_box_w(cell, b, d, &w0, &w1);
    if (w0 < 1e-4 * (W + ext)) w0 = 1e-4 * (W + ext);
    if (!(w1 > w0)) w1 = w0;
    ax[0] = (a + 1) % 3;
    ax[1] = (a + 2) % 3;
    for (k = 0; k < 2; ++k) {
        double lo = -DBL_MAX, hi = DBL_MAX, c0 = cell->min[ax[k]], c1 = cell->max[ax[k]];
        for (i = 0; i < 4; ++i) {
            double Vk = i & 1 ? c1 : c0, Vw = i & 2 ? -ext : 0.0, mn = DBL_MAX, mx = -DBL_MAX;
            for (j = 0; j < 4; ++j) {
                double Pk = j & 1 ? b->max[ax[k]] : b->min[ax[k]], Pw = j & 2 ? w1 : w0;
                double x = Vk + (Pk - Vk) * (W - Vw) / (Pw - Vw);
                mn = pvs__dmin(mn, x);
                mx = pvs__dmax(mx, x);
            }
            lo = pvs__dmax(lo, mn);
            hi = pvs__dmin(hi, mx);
        }
        len[k] = hi - lo;
        if (!(len[k] > 0.0)) return 0.0;
    }
    /* in pixels of that plane: its extent grows with W */
    return len[0] * len[1] /
           (((double)cell->max[ax[0]] - cell->min[ax[0]] + 2.0 * PVS__EP_EXTEND * (W + ext)) *
            ((double)cell->max[ax[1]] - cell->min[ax[1]] + 2.0 * PVS__EP_EXTEND * (W + ext)));
}

/* The PVS of one cell (Durand 2000 §6.1): per direction, the occluders with the largest solid angle,
   a plane just behind the one that fills the most pixels, their Projections, then the occludees. */
PVS__STATIC pvs_result pvs__extproj_cell(const pvs_scene *s, const pvs__extproj_prep *p, const pvs_box *cell, uint32_t res,
                                         uint32_t max_occ, const pvs_allocator *al, pvs_word *bits, uint32_t cell_id, pvs_error *err) {
    pvs__epcell c;
    pvs__epsel *sel = NULL;
    uint32_t nsel[6], d, i, levels = 0;
    size_t level_floats = 0, map_floats, sweep_size;
    float *mem = NULL;
    void *sweep = NULL;
    double r2 = 0.0;
    pvs_result r = PVS_OK;
    memset(&c, 0, sizeof(c));
    c.scene = s;
    c.prep = p;
    c.cell = *cell;
    c.bits = bits;
    {
        uint32_t w = res, h = res;
        level_floats = (size_t)w * h;
        while ((w > 1 || h > 1) && levels < 13) {
            w = (w + 1) / 2;
            h = (h + 1) / 2;
            level_floats += (size_t)w * h;
            ++levels;
        }
    }
    map_floats = level_floats;
    sweep_size = pvs_kdtree_sweep_scratch_size(s->object_tree);
    sel = (pvs__epsel *)pvs__alloc_array(al, 6 * (size_t)max_occ, sizeof(pvs__epsel));
    mem = (float *)pvs__alloc_array(al, 6 * PVS__EP_PLANES * map_floats, sizeof(float));
    sweep = pvs__alloc(al, sweep_size, 16);
    if (!sel || !mem || !sweep) {
        r = pvs__fail(err, PVS_ERROR_OUT_OF_MEMORY, cell_id, 0, "extproj scratch for cell %u", cell_id);
        goto done;
    }
    for (i = 0; i < 3; ++i) r2 += 0.25 * ((double)cell->max[i] - cell->min[i]) * ((double)cell->max[i] - cell->min[i]);
    /* occluder selection by solid angle (§6.1): area over squared distance, per direction the
       max_occ best among those reaching beyond the face (a min-heap on the score) */
    for (d = 0; d < 6; ++d) nsel[d] = 0;
    for (i = 0; i < p->occ_count; ++i) {
        const pvs__epocc *o = p->occ + i;
        double dist2 = pvs__box_distance2(cell, &o->box) + r2;
        for (d = 0; d < 6; ++d) {
            double w0, w1;
            pvs__epsel *h = sel + (size_t)d * max_occ;
            uint32_t k, ch;
            float score = (float)(o->area[d >> 1] / dist2);
            pvs__ep_box_w(cell, &o->box, (int)d, &w0, &w1);
            if (!(w1 > 0.0) || !(score > 0.0f)) continue;
            if (nsel[d] == max_occ) {
                if (!(score > h[0].score)) continue;
                k = 0; /* replace the root, sift down */
                for (;;) {
                    ch = 2 * k + 1;
                    if (ch >= max_occ) break;
                    if (ch + 1 < max_occ && h[ch + 1].score < h[ch].score) ++ch;
                    if (!(h[ch].score < score)) break;
                    h[k] = h[ch];
                    k = ch;
                }
            } else {
                k = nsel[d]++;
                while (k > 0 && h[(k - 1) / 2].score > score) {
                    h[k] = h[(k - 1) / 2];
                    k = (k - 1) / 2;
                }
            }
            h[k].score = score;
            h[k].occ = i;
        }
    }
    for (d = 0; d < 6; ++d) {
        pvs__epsel *h = sel + (size_t)d * max_occ;
        int a = (int)(d >> 1), u = (a + 1) % 3, v = (a + 2) % 3, q;
        double bestW = 0.0, bestFill = 0.0, firstW = 0.0, ext = (double)cell->max[a] - cell->min[a];
        uint32_t k, j, w, hh;
        if (!nsel[d]) continue;
        /* §6.1 plane placement: a candidate just behind each of the best occluders, keep the one
           that fills the most pixels (sorted by score, best first, for the candidates) */
        for (k = 0; k < nsel[d]; ++k) /* sort descending by score, then by index: deterministic */
            for (j = k + 1; j < nsel[d]; ++j)
                if (h[j].score > h[k].score || (h[j].score == h[k].score && h[j].occ < h[k].occ)) {
                    pvs__epsel t = h[k];
                    h[k] = h[j];
                    h[j] = t;
                }
        for (k = 0; k < nsel[d] && k < PVS__EP_PLANE_CANDIDATES; ++k) {
            double w0, w1, W, fill = 0.0;
            pvs__ep_box_w(cell, &p->occ[h[k].occ].box, (int)d, &w0, &w1);
            W = w1 + 1e-3 * (w1 + ext);
            if (k == 0) firstW = W;
            for (j = 0; j < nsel[d]; ++j) fill += pvs__ep_fill_estimate(cell, &p->occ[h[j].occ].box, (int)d, W);
            if (fill > bestFill || (fill == bestFill && bestW > 0.0 && W < bestW)) {
                bestFill = fill;
                bestW = W;
            }
        }
        if (!(bestFill > 0.0)) continue;
        /* a second plane just behind the occluder of largest solid angle: the plane holding the
           most pixels loses the near occluders' edges to their penumbrae (§7.3, Fig. 16) */
        for (q = 0; q < PVS__EP_PLANES; ++q) {
        pvs__epmap *m = c.maps + PVS__EP_PLANES * d + (uint32_t)q;
        float *base = mem + (size_t)(PVS__EP_PLANES * d + (uint32_t)q) * map_floats;
        if (q == 1) {
            if (!(firstW > 0.0) || !(pvs__dabs(firstW - bestW) > 0.05 * (bestW + ext))) continue;
            bestW = firstW;
        }
        m->plane.cell = *cell;
        m->plane.axis = (uint32_t)a;
        m->plane.side = d & 1 ? -1 : 1;
        m->plane.distance = pvs__f_up(bestW);
        /* the plane reaches PVS__EP_EXTEND times as far sideways as it lies from the cell's far side
           (§6.1: extended planes catch the corner directions) */
        m->plane.rect[0] = pvs__f_down(cell->min[u] - PVS__EP_EXTEND * (bestW + ext));
        m->plane.rect[1] = pvs__f_down(cell->min[v] - PVS__EP_EXTEND * (bestW + ext));
        m->plane.rect[2] = pvs__f_up(cell->max[u] + PVS__EP_EXTEND * (bestW + ext));
        m->plane.rect[3] = pvs__f_up(cell->max[v] + PVS__EP_EXTEND * (bestW + ext));
        m->plane.width = m->plane.height = res;
        m->levels = levels;
        w = hh = res;
        for (k = 0; k <= levels; ++k) {
            m->lw[k] = w;
            m->lh[k] = hh;
            m->lv[k] = base;
            base += (size_t)w * hh;
            w = (w + 1) / 2;
            hh = (hh + 1) / 2;
        }
        for (k = 0; k < res * res; ++k) m->lv[0][k] = PVS_EXTPROJ_EMPTY;
        for (k = 0; k < nsel[d]; ++k) {
            const pvs__epocc *o = p->occ + h[k].occ;
            pvs_extproj_occluder(&m->plane, p->pts + 3 * (size_t)o->first, o->count, m->lv[0]);
        }
        pvs__ep_build_pyramid(m);
        m->active = pvs__ep_frame(&m->plane, &m->frame);
        }
    }
    r = pvs_kdtree_sweep(s->object_tree, cell, sweep, sweep_size, pvs__ep_visit, &c);
    if (r != PVS_OK) r = pvs__fail(err, r, cell_id, 0, "extproj: object sweep of cell %u", cell_id);
done:
    pvs__free_array(al, sel, 6 * (size_t)max_occ, sizeof(pvs__epsel));
    pvs__free_array(al, mem, 6 * PVS__EP_PLANES * map_floats, sizeof(float));
    pvs__free(al, sweep, sweep_size, 16);
    return r;
}

/* ---- shrink (Wonka, Wimmer, Schmalstieg 2000) ---- */

typedef struct pvs__shrink_walk {
    const pvs_scene *scene;
    const pvs_raster *raster;
    const pvs_box *cell;
    pvs_word *visible;
    int u, v;
} pvs__shrink_walk;

/* 1 if the box meets the cell or stands (partly) under its top face: always visible. */
PVS__STATIC int pvs__shrink_near(const pvs__shrink_walk *w, const pvs_box *b) {
    return b->min[w->u] <= w->cell->max[w->u] && b->max[w->u] >= w->cell->min[w->u] && b->min[w->v] <= w->cell->max[w->v] &&
           b->max[w->v] >= w->cell->min[w->v];
}

/* §3.4 hierarchical rejection: a kD-tree node under the joint umbra is skipped with all it holds. */
PVS__STATIC pvs_visit pvs__shrink_visit(void *user, const pvs_box *node_box, float distance, const uint32_t *items, uint32_t count) {
    pvs__shrink_walk *w = (pvs__shrink_walk *)user;
    uint32_t i;
    (void)distance;
    if (!pvs__shrink_near(w, node_box) && !pvs_cull_map_test_box(w->raster, node_box)) return PVS_VISIT_SKIP;
    for (i = 0; i < count; ++i) {
        uint32_t ob = items[i];
        const pvs_box *b = w->scene->object_boxes + ob;
        if (w->scene->object_flags[ob] & PVS_OBJECT_OCCLUDER_ONLY) continue;
        if (pvs__shrink_near(w, b) || pvs_cull_map_test_box(w->raster, b)) pvs_bitset_set(w->visible, ob);
    }
    return PVS_VISIT_DESCEND;
}

typedef struct pvs__shrink_key {
    double d;
    uint32_t i;
} pvs__shrink_key;
PVS__STATIC int pvs__shrink_key_cmp(const void *x, const void *y) {
    const pvs__shrink_key *a = (const pvs__shrink_key *)x, *b = (const pvs__shrink_key *)y;
    return a->d < b->d ? -1 : a->d > b->d ? 1 : a->i < b->i ? -1 : a->i > b->i;
}

/* One sample's cull map (Wonka 1999 §3-4, via the raster module's shadow rasterizer), occluders front
   to back; an occluder whose prism is already under the shadows is skipped (§3.4: an occluded occluder
   hides nothing more from this point). */
PVS__STATIC void pvs__shrink_sample_map(pvs_raster *r, const float eye[3], const pvs_facade_chain *chains,
                                        const pvs__shrink_key *order, uint32_t n, int u, int v, uint32_t up) {
    double e[3];
    size_t i, cells = (size_t)r->cm_w * r->cm_h;
    uint32_t c;
    int simd = !(r->flags & PVS_RASTER_SCALAR);
    e[0] = eye[u];
    e[1] = eye[v];
    e[2] = eye[up];
    for (i = 0; i < cells; ++i) r->cm[i] = PVS_DEPTH_EMPTY;
    for (i = 0; i < r->cm_tiles; ++i) r->cm_tile_min[i] = PVS_DEPTH_EMPTY;
    for (c = 0; c < n; ++c) {
        const pvs_facade_chain *ch = chains + order[c].i;
        pvs_box bx;
        bx.min[u] = ch->points[0]; bx.min[v] = ch->points[1]; bx.min[up] = ch->base;
        bx.max[u] = ch->points[4]; bx.max[v] = ch->points[5]; bx.max[up] = ch->top;
        if (c > 0 && !pvs_cull_map_test_box(r, &bx)) continue;
        pvs__cm_chain(r, e, ch->points, ch->point_count, 1, ch->base, ch->top, simd, 0.0);
    }
}

/* §3: "sample points need only be placed on the edges of the top of the view cells". Why, for a
   heightfield occluder O (the columns before erosion) and a point P whose ground position lies
   outside the cell's footprint R (the others are set anyway): say V on the top face (height H) sees
   P. In the vertical plane through P and V, the segment from P's ground position to V's crosses the
   boundary of R at W'. If P is not above H, the segment P-W' lies above P-V at every ground distance
   from P, so W' sees P. If P is above H, move V away from P to the boundary point W: P-W lies above
   P-V up to V and above H after it, where no column of O inside R reaches (the condition tested here).
   Either way a boundary point sees P; with the theorem (appendix) the edge samples decide. */
PVS__STATIC int pvs__shrink_edges_suffice(const pvs_occluders *o, const pvs_box *cell, int u, int v, uint32_t up) {
    uint32_t i0, i1, j0, j1, i, j;
    float top = cell->max[up];
    pvs__vx_range(o, u, cell->min[u], cell->max[u], o->h, &i0, &i1);
    pvs__vx_range(o, v, cell->min[v], cell->max[v], o->h, &j0, &j1);
    for (j = j0; j <= j1; ++j)
        for (i = i0; i <= i1; ++i)
            if (o->column_top[(size_t)j * o->n[u] + i] > top) return 0;
    return 1;
}

/* The 2.5D path (§3): the eroded column prisms (tops lowered by eps, footprints shrunk by eps) cast
   occluder shadows from samples on the cell's top face (a 2.5D occluder hides from a point only what
   it hides from every point above it, so the top face stands for the cell), spaced so that every
   point of the face is within eps of a sample. Each sample's shadows go into the raster module's
   cull map (Wonka 1999); the joint umbra is the per-cell minimum over the samples (§3.4, the
   stencil intersection); objects are tested by box footprint and top through the kD-tree. The paper
   samples only the top face's edges; where a column inside the cell rises above its top the whole
   face is sampled instead, which is conservative without needing the
   argument for the interior; the edges suffice when pvs__shrink_edges_suffice says so. */
PVS__STATIC pvs_result pvs__shrink_2d5(const pvs_scene *s, const pvs_occluders *o, const pvs_box *cell, pvs_word *visible,
                                       pvs_error *err) {
    pvs_raster_desc rd;
    pvs_raster *r = NULL;
    pvs_result res;
    pvs__shrink_walk w;
    float *joint = NULL, eps = o->info.eps, spacing, eye[3];
    size_t cells = 0, x, sweep_size;
    void *sweep = NULL;
    uint32_t nu, nv, a, b, chain_count, up = s->up_axis;
    const pvs_facade_chain *chains = pvs_occluders_columns(o, &chain_count);
    double eu, ev, cm_res, cu, cv;
    int edges;
    pvs__shrink_key *order = NULL;
    int u, v, any = 1;
    pvs__ground_axes(up, &u, &v);
    memset(&rd, 0, sizeof(rd));
    rd.width = rd.height = 1;
    rd.scene = s;
    eu = (double)s->bounds.max[u] - s->bounds.min[u];
    ev = (double)s->bounds.max[v] - s->bounds.min[v];
    cm_res = pvs__dmax(pvs__dmax(o->h, 0.75 * eps), pvs__dmax(eu, ev) / 1024.0);
    rd.cull_map_width = (uint32_t)pvs__dmin(2048.0, pvs__dmax(16.0, ceil(eu / cm_res)));
    rd.cull_map_height = (uint32_t)pvs__dmin(2048.0, pvs__dmax(16.0, ceil(ev / cm_res)));
    rd.allocator = o->allocator;
    res = pvs_raster_create(&rd, &r, err);
    if (res != PVS_OK) return res;
    cells = (size_t)r->cm_w * r->cm_h;
    joint = (float *)pvs__alloc_array(&o->allocator, cells, sizeof(float));
    sweep_size = pvs_kdtree_sweep_scratch_size(s->object_tree);
    sweep = pvs__alloc(&o->allocator, sweep_size, 16);
    order = (pvs__shrink_key *)pvs__alloc_array(&o->allocator, chain_count ? chain_count : 1, sizeof(pvs__shrink_key));
    if (!joint || !sweep || !order) {
        pvs__free_array(&o->allocator, order, chain_count ? chain_count : 1, sizeof(pvs__shrink_key));
        pvs__free_array(&o->allocator, joint, cells, sizeof(float));
        pvs__free(&o->allocator, sweep, sweep_size, 16);
        pvs_raster_destroy(r);
        return pvs__fail(err, PVS_ERROR_OUT_OF_MEMORY, -1, 0, "shrink scratch");
    }
    /* samples: the top face's edges every 1.9 eps when no solid column inside the cell's footprint
       rises above the top face (see pvs__shrink_edges_suffice), else a grid on the whole top face
       with spacing <= eps * sqrt(2) (1.4 leaves a margin) */
    edges = pvs__shrink_edges_suffice(o, cell, u, v, up);
    spacing = edges ? 1.9f * eps : 1.4f * eps;
    nu = (uint32_t)ceil(((double)cell->max[u] - cell->min[u]) / spacing) + 1u;
    nv = (uint32_t)ceil(((double)cell->max[v] - cell->min[v]) / spacing) + 1u;
    /* front to back from the cell's centre: only speed depends on the order */
    cu = 0.5 * ((double)cell->min[u] + cell->max[u]);
    cv = 0.5 * ((double)cell->min[v] + cell->max[v]);
    for (a = 0; a < chain_count; ++a) {
        const float *pt = chains[a].points;
        double du = pvs__dmax(0.0, pvs__dmax(pt[0] - cu, cu - pt[4])), dv = pvs__dmax(0.0, pvs__dmax(pt[1] - cv, cv - pt[5]));
        order[a].d = du * du + dv * dv;
        order[a].i = a;
    }
    qsort(order, chain_count, sizeof(pvs__shrink_key), pvs__shrink_key_cmp);
    if (nu > 4096u || nv > 4096u) {
        pvs__free_array(&o->allocator, order, chain_count ? chain_count : 1, sizeof(pvs__shrink_key));
        pvs__free_array(&o->allocator, joint, cells, sizeof(float));
        pvs__free(&o->allocator, sweep, sweep_size, 16);
        pvs_raster_destroy(r);
        return pvs__fail(err, PVS_ERROR_UNSUPPORTED, -1, 0, "a cell of %u x %u samples: eps too small for the cell", nu, nv);
    }
    eye[up] = cell->max[up];
    for (b = 0; b < nv && any; ++b)
        for (a = 0; a < nu && any; ++a) {
            const float *cm;
            if (edges && a > 0 && a + 1 < nu && b > 0 && b + 1 < nv) continue; /* interior: not sampled */
            eye[u] = nu > 1 ? cell->min[u] + (float)((double)a * ((double)cell->max[u] - cell->min[u]) / (nu - 1)) : cell->min[u];
            eye[v] = nv > 1 ? cell->min[v] + (float)((double)b * ((double)cell->max[v] - cell->min[v]) / (nv - 1)) : cell->min[v];
            if (a + 1 == nu) eye[u] = cell->max[u];
            if (b + 1 == nv) eye[v] = cell->max[v];
            pvs__shrink_sample_map(r, eye, chains, order, chain_count, u, v, up);
            cm = r->cm;
            any = 0;
            if (a == 0 && b == 0) {
                memcpy(joint, cm, cells * sizeof(float));
                for (x = 0; x < cells; ++x) any |= joint[x] != PVS_DEPTH_EMPTY;
            } else {
                for (x = 0; x < cells; ++x) {
                    if (cm[x] < joint[x]) joint[x] = cm[x];
                    any |= joint[x] != PVS_DEPTH_EMPTY;
                }
            }
        }
    if (!any) for (x = 0; x < cells; ++x) joint[x] = PVS_DEPTH_EMPTY;
    memcpy(r->cm, joint, cells * sizeof(float));
    w.scene = s;
    w.raster = r;
    w.cell = cell;
    w.visible = visible;
    w.u = u;
    w.v = v;
    res = pvs_kdtree_sweep(s->object_tree, cell, sweep, sweep_size, pvs__shrink_visit, &w);
    pvs__free_array(&o->allocator, order, chain_count ? chain_count : 1, sizeof(pvs__shrink_key));
    pvs__free_array(&o->allocator, joint, cells, sizeof(float));
    pvs__free(&o->allocator, sweep, sweep_size, 16);
    pvs_raster_destroy(r);
    if (res != PVS_OK) return pvs__fail(err, res, -1, 0, "object sweep");
    return PVS_OK;
}

#define PVS__SHRINK_RES 64u

/* The 3D path (§2.1, 2.3): samples on each of the cell's six faces, on a grid with spacing <= eps *
   sqrt(2), so every boundary point is within eps of one (a sight line from inside the cell leaves
   it through the boundary, so the boundary stands for the cell). Per sample a cube of six depth maps
   of the eroded boxes (occluder mode: inner coverage, farthest depth), objects tested in occludee
   mode against the depth pyramid; the PVS is the union over the samples. Objects within twice the
   near distance of the cell are set outright (the cube does not see nearer than its near plane). */
PVS__STATIC pvs_result pvs__shrink_3d(const pvs_scene *s, const pvs_occluders *o, const pvs_box *cell, pvs_word *visible,
                                      pvs_error *err) {
    pvs_raster_desc rd;
    pvs_raster *r = NULL;
    pvs_result res;
    float *pos = NULL, eps = o->info.eps, spacing = 1.4f * eps, nearp = 0.05f * eps;
    uint32_t *idx = NULL, nb = o->box_count, i, face, a, b, dir, ob;
    pvs_word *seen = NULL;
    size_t words = PVS_BITSET_WORDS(s->object_count);
    static const uint32_t quad[36] = {0, 1, 3, 0, 3, 2, 4, 6, 7, 4, 7, 5, 0, 4, 5, 0, 5, 1,
                                      2, 3, 7, 2, 7, 6, 0, 2, 6, 0, 6, 4, 1, 5, 7, 1, 7, 3};
    pvs_box grown;
    int k;
    memset(&rd, 0, sizeof(rd));
    rd.width = rd.height = PVS__SHRINK_RES;
    rd.max_mesh_triangles = nb ? (nb < 4096u ? 12 * nb : 49152u) : 12u; /* the boxes as one occluder mesh */
    rd.allocator = o->allocator;
    res = pvs_raster_create(&rd, &r, err);
    if (res != PVS_OK) return res;
    pos = (float *)pvs__alloc_array(&o->allocator, (size_t)(nb ? nb : 1) * 24, sizeof(float));
    idx = (uint32_t *)pvs__alloc_array(&o->allocator, (size_t)(nb ? nb : 1) * 36, sizeof(uint32_t));
    seen = (pvs_word *)pvs__alloc_array(&o->allocator, words ? words : 1, sizeof(pvs_word));
    if (!pos || !idx || !seen) {
        res = pvs__fail(err, PVS_ERROR_OUT_OF_MEMORY, -1, 0, "shrink 3D scratch");
        goto done;
    }
    memset(seen, 0, (words ? words : 1) * sizeof(pvs_word));
    for (i = 0; i < nb; ++i) {
        const pvs_box *bx = o->boxes + i;
        uint32_t c;
        for (c = 0; c < 8; ++c) {
            pos[24 * i + 3 * c + 0] = c & 1 ? bx->max[0] : bx->min[0];
            pos[24 * i + 3 * c + 1] = c & 2 ? bx->max[1] : bx->min[1];
            pos[24 * i + 3 * c + 2] = c & 4 ? bx->max[2] : bx->min[2];
        }
        for (c = 0; c < 36; ++c) idx[36 * i + c] = 8 * i + quad[c];
    }
    /* objects near or in the cell */
    grown = *cell;
    for (k = 0; k < 3; ++k) { grown.min[k] -= 2.0f * nearp + 1e-4f * eps; grown.max[k] += 2.0f * nearp + 1e-4f * eps; }
    for (ob = 0; ob < s->object_count; ++ob)
        if (pvs__box_valid(s->object_boxes + ob) && pvs__box_overlap(s->object_boxes + ob, &grown)) pvs_bitset_set(seen, ob);
    for (face = 0; face < 6; ++face) {
        int ax = (int)face / 2, a1 = (ax + 1) % 3, a2 = (ax + 2) % 3;
        uint32_t n1 = (uint32_t)ceil(((double)cell->max[a1] - cell->min[a1]) / spacing) + 1u;
        uint32_t n2 = (uint32_t)ceil(((double)cell->max[a2] - cell->min[a2]) / spacing) + 1u;
        if (n1 > 1024u || n2 > 1024u) {
            res = pvs__fail(err, PVS_ERROR_UNSUPPORTED, -1, 0, "a cell face of %u x %u samples: eps too small for the cell", n1, n2);
            goto done;
        }
        for (a = 0; a < n1; ++a)
            for (b = 0; b < n2; ++b) {
                float p[3];
                p[ax] = face & 1 ? cell->max[ax] : cell->min[ax];
                p[a1] = n1 > 1 ? cell->min[a1] + (float)((double)a * ((double)cell->max[a1] - cell->min[a1]) / (n1 - 1)) : cell->min[a1];
                p[a2] = n2 > 1 ? cell->min[a2] + (float)((double)b * ((double)cell->max[a2] - cell->min[a2]) / (n2 - 1)) : cell->min[a2];
                if (a + 1 == n1) p[a1] = cell->max[a1];
                if (b + 1 == n2) p[a2] = cell->max[a2];
                for (dir = 0; dir < 6; ++dir) {
                    pvs_camera cam;
                    float m[16];
                    int dax = (int)dir / 2;
                    memset(&cam, 0, sizeof(cam));
                    for (k = 0; k < 3; ++k) cam.eye[k] = p[k];
                    cam.forward[dax] = dir & 1 ? 1.0f : -1.0f;
                    cam.up[(dax + 1) % 3] = 1.0f;
                    cam.fov_y = 1.6f; /* a little over 90 degrees: the six frusta overlap */
                    cam.near_plane = nearp;
                    if (pvs_camera_matrix(&cam, 1.0f, m) != PVS_OK) continue;
                    pvs_raster_clear(r);
                    pvs_raster_set_matrix(r, m);
                    if (nb) pvs_raster_mesh(r, pos, 8 * nb, idx, 12 * nb); /* no cracks along the faces' diagonals */
                    pvs_raster_build_pyramid(r);
                    for (ob = 0; ob < s->object_count; ++ob) {
                        if (pvs_bitset_test(seen, ob) || !pvs__box_valid(s->object_boxes + ob)) continue;
                        if (pvs_raster_test_box(r, s->object_boxes + ob)) pvs_bitset_set(seen, ob);
                    }
                }
            }
    }
    for (ob = 0; ob < s->object_count; ++ob)
        if (pvs_bitset_test(seen, ob) && !(s->object_flags[ob] & PVS_OBJECT_OCCLUDER_ONLY)) pvs_bitset_set(visible, ob);
    res = PVS_OK;
done:
    pvs__free_array(&o->allocator, pos, (size_t)(nb ? nb : 1) * 24, sizeof(float));
    pvs__free_array(&o->allocator, idx, (size_t)(nb ? nb : 1) * 36, sizeof(uint32_t));
    pvs__free_array(&o->allocator, seen, words ? words : 1, sizeof(pvs_word));
    pvs_raster_destroy(r);
    return res;
}

PVS_API pvs_result pvs_shrink_cell(const pvs_scene *s, const pvs_occluders *o, const pvs_box *cell, pvs_shrink_mode mode,
                                   pvs_word *visible, pvs_error *err) {
    pvs_result res;
    if (!s || !o || !cell || !visible || o->scene != s) return pvs__fail(err, PVS_ERROR_INVALID_ARGUMENT, -1, 0, "NULL argument or occluders of another scene");
    if (!pvs__box_valid(cell)) return pvs__fail(err, PVS_ERROR_BAD_CELL, -1, 0, "cell is not a valid box");
    if ((int)mode < 0 || mode >= PVS_SHRINK_MODE_COUNT) return pvs__fail(err, PVS_ERROR_INVALID_ARGUMENT, -1, 0, "unknown mode %d", (int)mode);
    if (mode == PVS_SHRINK_AUTO) mode = o->info.is_2d5 ? PVS_SHRINK_2D5 : PVS_SHRINK_3D;
    if (mode == PVS_SHRINK_2D5 ? o->chain_count == 0 : o->box_count == 0) {
        /* nothing survived the erosion: nothing can hide anything, every drawable object is set */
        uint32_t i;
        for (i = 0; i < s->object_count; ++i)
            if (!(s->object_flags[i] & PVS_OBJECT_OCCLUDER_ONLY) && pvs__box_valid(s->object_boxes + i)) pvs_bitset_set(visible, i);
        pvs__ok(err);
        return PVS_OK;
    }
    if (mode == PVS_SHRINK_2D5) res = pvs__shrink_2d5(s, o, cell, visible, err);
    else res = pvs__shrink_3d(s, o, cell, visible, err);
    if (res == PVS_OK) pvs__ok(err);
    return res;
}


// >>bake
/* ---------------------------------------------------------------------------------------------- */
/* bake: validated cells, one task per cell, results in cell order whatever the run order         */
/* ---------------------------------------------------------------------------------------------- */

struct pvs_bake {
    pvs_allocator allocator;
    const pvs_scene *scene;
    pvs_box *cells;            /* per task: the shard's cells in id order */
    uint32_t cell_count;       /* the shard's (task_count) */
    uint32_t total_cell_count, shard_index, shard_count;
    uint32_t object_count;
    size_t words;              /* per cell */
    pvs_word *pvs;             /* cell_count * words */
    unsigned char *done;       /* cell_count flags, each written by its own task only */
    pvs_method method;
    float eps;
    uint32_t sample_points, sample_rays, max_chain;
    uint64_t seed;
    float *ot_facades;         /* OTREE: facade_count x (u0 v0 u1 v1 top), then facade_count bases */
    uint32_t ot_facade_count;
    float *ot_objects;         /* OTREE: object_count x (umin vmin umax vmax top) */
    pvs_kdtree *ot_tree;       /* OTREE: over pvs_visibility_25d_boxes */
    struct pvs__extproj_prep *extproj;        /* EXTPROJ: the scene's occluders, read-only in tasks */
    uint32_t extproj_resolution, extproj_occluders;
    pvs_occluders *occluders;  /* SHRINK */
    pvs_shrink_mode shrink_mode;
    /* the methods considered (AUTO: every candidate, in run order) and those each task runs; a task's
       PVS is the intersection of theirs (an intersection of conservative sets is conservative) */
    pvs_method considered[PVS_METHOD_COUNT];
    const char *reason[PVS_METHOD_COUNT];
    unsigned char ran[PVS_METHOD_COUNT];
    uint32_t considered_count;
    pvs_method run[PVS_METHOD_COUNT];
    uint32_t run_count;
    uint32_t *stats;           /* per task: run_count own PVS sizes, then run_count sole-cull counts */
    unsigned char *restored;   /* per task: done by pvs_bake_restore_task (no stats) */
    float max_distance;
    uint32_t flags;
    struct pvs__vbake *vocc;   /* VOCC: prepared facades (>>vocc), read-only in tasks */
    uint8_t *vocc_bytes;       /* VOCC: per task max_occluders x 5 bytes, */
    uint8_t *vocc_count, *vocc_scale; /* its count and scale code */
    pvs_vocc_stats *vocc_stats;/* per task */
    uint32_t vocc_only;
};

PVS_API void pvs_bake_destroy(pvs_bake *b) {
    pvs_allocator a;
    if (!b) return;
    a = b->allocator;
    pvs__free_array(&a, b->cells, b->cell_count, sizeof(pvs_box));
    pvs__free_array(&a, b->pvs, (size_t)b->cell_count * b->words, sizeof(pvs_word));
    pvs__free_array(&a, b->done, b->cell_count, 1);
    pvs__free_array(&a, b->restored, b->cell_count, 1);
    pvs__free_array(&a, b->stats, (size_t)b->cell_count * 2 * PVS_METHOD_COUNT, sizeof(uint32_t));
    pvs__free_array(&a, b->ot_facades, (size_t)b->ot_facade_count * 6 + 6, sizeof(float));
    pvs__free_array(&a, b->ot_objects, (size_t)b->object_count * 5 + 5, sizeof(float));
    pvs_kdtree_destroy(b->ot_tree);
    pvs__extproj_prep_destroy(b->extproj);
    pvs_occluders_destroy(b->occluders);
    if (b->vocc) {
        pvs__free_array(&a, b->vocc_bytes, (size_t)b->cell_count * b->vocc->max_keep * 5, 1);
        pvs__free_array(&a, b->vocc_count, b->cell_count, 1);
        pvs__free_array(&a, b->vocc_scale, b->cell_count, 1);
        pvs__free_array(&a, b->vocc_stats, b->cell_count, sizeof(pvs_vocc_stats));
        pvs__vbake_destroy(b->vocc);
    }
    pvs__free(&a, b, sizeof(*b), 16);
}

/* Checks a cell box: finite, min <= max. */
PVS__STATIC pvs_result pvs__check_cell(const pvs_box *c, uint32_t i, pvs_error *err) {
    int k;
    for (k = 0; k < 3; ++k) {
        if (!pvs__finite(c->min[k]) || !pvs__finite(c->max[k]))
            return pvs__fail(err, PVS_ERROR_BAD_CELL, i, 0, "cell %u has a coordinate that is not finite", i);
        if (c->min[k] > c->max[k])
            return pvs__fail(err, PVS_ERROR_BAD_CELL, i, 0, "cell %u has min > max on axis %d", i, k);
    }
    return PVS_OK;
}

/* ---- the OTREE bake method ---- */

/* Facades for c-LSS (§7.1): pairs of consecutive triangles that form a vertical rectangle (two
   ground positions x two heights, split along a diagonal) whose bottom is at or below the lowest
   point of the scene, so it certainly blocks every height from the ground to its top. Anything
   else is ignored (never blocks: conservative). */
PVS__STATIC pvs_result pvs__otree_prepare(pvs_bake *b) {
    const pvs_scene *s = b->scene;
    int up = s->up_axis == 2 ? 2 : 1, u = 0, v = up == 2 ? 1 : 2;
    float ground = s->bounds.min[up];
    uint32_t t, n = 0, pass, i = 0;
    for (pass = 0; pass < 2; ++pass) {
        n = 0;
        for (t = 0; t + 1 < s->triangle_count; ++t) {
            const float *c[6];
            float pu[2], pv[2], h[2];
            int np = 0, nh = 0, k, m, shared = 0, diag = 1;
            for (k = 0; k < 6; ++k) c[k] = s->positions + 3 * (size_t)s->indices[3 * (size_t)(t + (uint32_t)(k / 3)) + (uint32_t)(k % 3)];
            for (k = 0; k < 6 && np <= 2 && nh <= 2; ++k) {
                for (m = 0; m < np; ++m) if (pu[m] == c[k][u] && pv[m] == c[k][v]) break;
                if (m == np) { if (np < 2) { pu[np] = c[k][u]; pv[np] = c[k][v]; } ++np; }
                for (m = 0; m < nh; ++m) if (h[m] == c[k][up]) break;
                if (m == nh) { if (nh < 2) h[nh] = c[k][up]; ++nh; }
            }
            if (np != 2 || nh != 2) continue;
            /* each triangle has three distinct corners; they share exactly two, on a diagonal */
            for (k = 0; k < 3; ++k)
                if (c[k] == c[(k + 1) % 3] || c[3 + k] == c[3 + (k + 1) % 3] ||
                    !memcmp(c[k], c[(k + 1) % 3], 12) || !memcmp(c[3 + k], c[3 + (k + 1) % 3], 12)) break;
            if (k < 3) continue;
            for (k = 0; k < 3; ++k)
                for (m = 3; m < 6; ++m)
                    if (!memcmp(c[k], c[m], 12)) {
                        ++shared;
                        if (shared == 1) i = (uint32_t)k; else {
                            const float *p0 = c[i], *p1 = c[k];
                            diag = (p0[u] != p1[u] || p0[v] != p1[v]) && p0[up] != p1[up];
                        }
                    }
            if (shared != 2 || !diag) continue;
            {
                float lo = h[0] < h[1] ? h[0] : h[1], hi = h[0] < h[1] ? h[1] : h[0];
                if (!(lo <= ground)) continue;
                if (pass) {
                    float *f = b->ot_facades + 5 * (size_t)n;
                    f[0] = pu[0]; f[1] = pv[0]; f[2] = pu[1]; f[3] = pv[1]; f[4] = hi;
                    b->ot_facades[5 * (size_t)b->ot_facade_count + n] = lo;
                }
            }
            ++n;
            ++t; /* the pair is used up */
        }
        if (!pass) {
            b->ot_facade_count = n;
            b->ot_facades = (float *)pvs__alloc_array(&b->allocator, (size_t)n * 6 + 6, sizeof(float));
            b->ot_objects = (float *)pvs__alloc_array(&b->allocator, (size_t)b->object_count * 5 + 5, sizeof(float));
            if (!b->ot_facades || !b->ot_objects) return PVS_ERROR_OUT_OF_MEMORY;
        }
    }
    for (i = 0; i < b->object_count; ++i) {
        const pvs_box *bx = s->object_boxes + i;
        float *o = b->ot_objects + 5 * (size_t)i;
        o[0] = bx->min[u]; o[1] = bx->min[v]; o[2] = bx->max[u]; o[3] = bx->max[v]; o[4] = bx->max[up];
        if (bx->min[0] > bx->max[0] || (s->object_flags[i] & PVS_OBJECT_OCCLUDER_ONLY)) { o[0] = 1.0f; o[2] = 0.0f; } /* never visible */
    }
    {
        pvs_kdtree_desc kd;
        pvs_result r;
        pvs_box *boxes = (pvs_box *)pvs__alloc_array(&b->allocator, (size_t)n + b->object_count + 1, sizeof(pvs_box));
        if (!boxes) return PVS_ERROR_OUT_OF_MEMORY;
        pvs_visibility_25d_boxes(b->ot_facades, n, b->ot_objects, b->object_count, boxes);
        memset(&kd, 0, sizeof(kd));
        kd.boxes = boxes;
        kd.count = n + b->object_count;
        kd.allocator = b->allocator;
        r = pvs_kdtree_create(&kd, &b->ot_tree, NULL);
        pvs__free_array(&b->allocator, boxes, (size_t)n + b->object_count + 1, sizeof(pvs_box));
        if (r != PVS_OK) return r;
    }
    return PVS_OK;
}

/* One cell with pvs_visibility_25d; facades whose base is above the cell's bottom are left out. */
PVS__STATIC pvs_result pvs__otree_cell(pvs_bake *b, uint32_t task, uint32_t cell, pvs_word *bits, pvs_error *err) {
    const pvs_scene *s = b->scene;
    const pvs_box *c = b->cells + task; /* the bake keeps its (shard's) cells by task */
    int up = s->up_axis == 2 ? 2 : 1, u = 0, v = up == 2 ? 1 : 2;
    pvs_visibility_25d_desc d;
    float *own = NULL;
    uint32_t i, n = b->ot_facade_count;
    pvs_result r;
    memset(&d, 0, sizeof(d));
    d.cell_min[0] = c->min[u]; d.cell_min[1] = c->min[v];
    d.cell_max[0] = c->max[u]; d.cell_max[1] = c->max[v];
    d.cell_top = c->max[up];
    d.facades = b->ot_facades;
    d.facade_count = n;
    d.objects = b->ot_objects;
    d.object_count = b->object_count;
    d.allocator = b->allocator;
    d.tree = b->ot_tree;
    for (i = 0; i < n; ++i)
        if (b->ot_facades[5 * (size_t)n + i] > c->min[up]) break;
    if (i < n) { /* a cell reaching below some facade's base: keep only the facades under it */
        uint32_t m = 0;
        own = (float *)pvs__alloc_array(&b->allocator, (size_t)n * 5 + 5, sizeof(float));
        if (!own) return pvs__fail(err, PVS_ERROR_OUT_OF_MEMORY, cell, 0, "cell %u facades", cell);
        d.tree = NULL; /* the shared tree indexes every facade */
        for (i = 0; i < n; ++i)
            if (b->ot_facades[5 * (size_t)n + i] <= c->min[up]) memcpy(own + 5 * (size_t)m++, b->ot_facades + 5 * (size_t)i, 5 * sizeof(float));
        d.facades = own;
        d.facade_count = m;
    }
    r = pvs_visibility_25d(&d, bits, NULL, err);
    if (own) pvs__free_array(&b->allocator, own, (size_t)n * 5 + 5, sizeof(float));
    if (r != PVS_OK) {
        if (err) err->index = cell;
        return r;
    }
    for (i = 0; i < b->object_count; ++i) /* occluder-only and empty objects never appear */
        if (b->ot_objects[5 * (size_t)i] > b->ot_objects[5 * (size_t)i + 2]) pvs_bitset_clear(bits, i);
    return PVS_OK;
}

/* The default eps of the shrink method: an eighth of the median of the cells' smallest ground-plane
   extent (Wonka 2000 §4.1 used 1 m for cells of several metres: 6-8 samples per edge). */
PVS__STATIC float pvs__cell_ground_extent(const pvs_box *c, int u, int v) {
    float e = c->max[u] - c->min[u], f = c->max[v] - c->min[v];
    return f < e ? f : e;
}
PVS__STATIC float pvs__shrink_default_eps(const pvs_box *cells, uint32_t n, uint32_t up) {
    uint32_t i, j, below, equal, m = n < 2048u ? n : 2048u; /* the median of the first 2048 cells, by counting */
    int u, v;
    float med = 0.0f;
    pvs__ground_axes(up, &u, &v);
    for (i = 0; i < m; ++i) {
        float e = pvs__cell_ground_extent(cells + i, u, v);
        below = equal = 0;
        for (j = 0; j < m; ++j) {
            float f = pvs__cell_ground_extent(cells + j, u, v);
            below += f < e;
            equal += f == e;
        }
        if (2 * below <= m && 2 * (below + equal) > m) { med = e; break; }
    }
    if (!(med > 0.0f)) med = 4.0f;
    return 0.125f * med;
}

/* ---- the driver's methods: preparation, applicability (AUTO), one cell ---- */

/* 1 for the conservative methods AUTO may intersect (never SAMPLE: an estimate from below). */
PVS__STATIC int pvs__method_conservative(pvs_method m) {
    return m > PVS_METHOD_DEFAULT && m < PVS_METHOD_COUNT && m != PVS_METHOD_SAMPLE && m != PVS_METHOD_AUTO;
}
/* Rough cost per cell on the demo city, cheapest first (the PERFORMANCE figures): AUTO runs the
   methods in this order and PREVIEW keeps the first that applies. Methods not listed come last. */
PVS__STATIC int pvs__method_cost_rank(pvs_method m) {
    switch (m) {
    case PVS_METHOD_EXTPROJ: return 1;
    case PVS_METHOD_OTREE: return 2;
    case PVS_METHOD_VOCC: return 2; /* about 60-90 ms per cell */
    case PVS_METHOD_SHRINK: return 3;
    default: return 4;
    }
}

/* Prepares method m's per-bake data (read-only in the tasks). UNSUPPORTED for a method the driver
   has no cell function for. */
PVS__STATIC pvs_result pvs__bake_prepare(pvs_bake *b, pvs_method m, const pvs_bake_desc *desc, pvs_error *err) {
    switch (m) {
    case PVS_METHOD_SAMPLE: return PVS_OK;
    case PVS_METHOD_EXTPROJ: return pvs__extproj_prepare(b->scene, &b->allocator, &b->extproj, err);
    case PVS_METHOD_OTREE:
        if (pvs__otree_prepare(b) != PVS_OK) return pvs__fail(err, PVS_ERROR_OUT_OF_MEMORY, -1, 0, "otree facades");
        return PVS_OK;
    case PVS_METHOD_SHRINK: {
        /* occluder synthesis over every cell of the bake (not only the shard's): shards agree */
        pvs_occluders_desc od;
        pvs_result r;
        if ((int)desc->shrink_mode < 0 || desc->shrink_mode >= PVS_SHRINK_MODE_COUNT)
            return pvs__fail(err, PVS_ERROR_INVALID_ARGUMENT, -1, 0, "unknown shrink mode %d", (int)desc->shrink_mode);
        if (!(b->eps > 0.0f)) {
            b->eps = pvs__shrink_default_eps(desc->cells, desc->cell_count, pvs_scene_up_axis(desc->scene));
            if (b->flags & PVS_BAKE_PREVIEW) b->eps *= 2.0f;
        }
        memset(&od, 0, sizeof(od));
        od.scene = desc->scene;
        od.cells = desc->cells;
        od.cell_count = desc->cell_count;
        od.eps = b->eps;
        od.voxel_size = desc->voxel_size;
        od.allocator = b->allocator;
        r = pvs_occluders_create(&od, &b->occluders, err);
        if (r != PVS_OK) return r;
        b->shrink_mode = desc->shrink_mode;
        if (b->shrink_mode == PVS_SHRINK_AUTO) b->shrink_mode = b->occluders->info.is_2d5 ? PVS_SHRINK_2D5 : PVS_SHRINK_3D;
        return PVS_OK;
    }
    case PVS_METHOD_VOCC: { /* >>vocc: facades and loops once, per-task occluder records */
        uint32_t slices = desc->vocc_slices ? desc->vocc_slices : 5, keep = desc->vocc_max_occluders ? desc->vocc_max_occluders : 10;
        pvs_result r;
        if (slices > 16 || keep > 255)
            return pvs__fail(err, PVS_ERROR_INVALID_ARGUMENT, -1, 0, "vocc: slices %u (1..16), occluders per cell %u (1..255)", slices, keep);
        r = pvs__vbake_create(b->scene, &b->allocator, slices, keep, &b->vocc);
        if (r != PVS_OK) return pvs__fail(err, r, -1, 0, "vocc: facades");
        if (!b->vocc->prep->nobj && b->method == PVS_METHOD_VOCC)
            return pvs__fail(err, PVS_ERROR_UNSUPPORTED, -1, 0,
                             "vocc: the scene has no vertical walls standing on the ground (2.5D occluders): virtual occluders cannot be built");
        b->vocc_only = desc->vocc_only;
        b->vocc_bytes = (uint8_t *)pvs__alloc_array(&b->allocator, (size_t)b->cell_count * keep * 5, 1);
        b->vocc_count = (uint8_t *)pvs__alloc_array(&b->allocator, b->cell_count, 1);
        b->vocc_scale = (uint8_t *)pvs__alloc_array(&b->allocator, b->cell_count, 1);
        b->vocc_stats = (pvs_vocc_stats *)pvs__alloc_array(&b->allocator, b->cell_count, sizeof(pvs_vocc_stats));
        if (!b->vocc_bytes || !b->vocc_count || !b->vocc_scale || !b->vocc_stats)
            return pvs__fail(err, PVS_ERROR_OUT_OF_MEMORY, -1, 0, "vocc: per-cell occluders");
        memset(b->vocc_count, 0, b->cell_count);
        memset(b->vocc_scale, 0, b->cell_count);
        memset(b->vocc_stats, 0, b->cell_count * sizeof(pvs_vocc_stats));
        return PVS_OK;
    }
    default: return pvs__fail(err, PVS_ERROR_UNSUPPORTED, -1, 0, "the bake driver cannot run method %s", pvs_method_name(m));
    }
}

/* AUTO: 1 if the prepared method m can leave anything out in this scene (2.5D or not, planar
   occluders or volumes), with the reason in *why either way. */
PVS__STATIC int pvs__bake_applies(const pvs_bake *b, pvs_method m, const char **why) {
    switch (m) {
    case PVS_METHOD_EXTPROJ:
        *why = b->extproj && b->extproj->occ_count ? "3D: planar occluders and convex solids" : "no planar occluder or convex solid";
        return b->extproj && b->extproj->occ_count;
    case PVS_METHOD_OTREE:
        *why = b->ot_facade_count ? "2.5D: vertical walls standing on the ground" : "not 2.5D: no vertical wall stands on the ground";
        return b->ot_facade_count != 0;
    case PVS_METHOD_SHRINK:
        if (!b->occluders || !b->occluders->info.eroded) {
            *why = "no occluder volume survives erosion by eps (thin walls or open geometry)";
            return 0;
        }
        *why = b->shrink_mode == PVS_SHRINK_2D5 ? "volumes: 2.5D columns synthesized from closed geometry"
                                                : "volumes: 3D boxes synthesized from closed geometry";
        return 1;
    case PVS_METHOD_VOCC:
        *why = b->vocc && b->vocc->prep->nobj ? "2.5D: virtual occluders behind walls standing on the ground"
                                              : "not 2.5D: no vertical wall stands on the ground";
        return b->vocc && b->vocc->prep->nobj;
    default: *why = "conservative"; return 1;
    }
}

/* One method's PVS of a task's cell: sets bits (cleared by the caller). */
PVS__STATIC pvs_result pvs__bake_method_cell(pvs_bake *b, pvs_method m, uint32_t task, uint32_t cell, pvs_word *bits, pvs_error *err) {
    switch (m) {
    case PVS_METHOD_SAMPLE: {
        /* per-cell seed: independent of the order and thread the tasks run in */
        uint64_t state = b->seed ^ ((uint64_t)cell * 0x9e3779b97f4a7c15ull);
        pvs_sample_visibility(b->scene, b->cells + task, b->sample_points, b->sample_rays, pvs__splitmix64(&state), bits);
        break;
    }
    case PVS_METHOD_OTREE: {
        pvs_result r = pvs__otree_cell(b, task, cell, bits, err);
        if (r != PVS_OK) return r;
        break;
    }
    case PVS_METHOD_EXTPROJ: {
        pvs_result r = pvs__extproj_cell(b->scene, b->extproj, b->cells + task, b->extproj_resolution, b->extproj_occluders,
                                         &b->allocator, bits, cell, err);
        if (r != PVS_OK) return r;
        break;
    }
    case PVS_METHOD_SHRINK: {
        pvs_result r = pvs_shrink_cell(b->scene, b->occluders, b->cells + task, b->shrink_mode, bits, err);
        if (r != PVS_OK) {
            if (err) err->index = cell;
            return r;
        }
        break;
    }
    case PVS_METHOD_VOCC: {
        const pvs__vbake *vb = b->vocc;
        pvs_result r;
        memset(b->vocc_stats + task, 0, sizeof(pvs_vocc_stats));
        r = pvs__vo_bake_cell(vb, b->cells + task, b->vocc_bytes + (size_t)task * vb->max_keep * 5, b->vocc_count + task,
                              b->vocc_scale + task, bits, b->vocc_stats + task, err);
        if (r != PVS_OK) {
            if (err) err->index = cell;
            return r;
        }
        if (b->vocc_only) { /* placeholder records: every drawable object */
            uint32_t i;
            memset(bits, 0, b->words * sizeof(pvs_word));
            for (i = 0; i < b->object_count; ++i)
                if (pvs__vo_box_ok(vb->boxes + i)) pvs_bitset_set(bits, i);
        }
        break;
    }
    default: return pvs__fail(err, PVS_ERROR_UNSUPPORTED, cell, 0, "method %d", (int)m);
    }
    return PVS_OK;
}

/* The squared distance between two boxes exceeds d^2, with a margin: 1 only when every point of a
   is certainly farther than d from every point of b. The per-axis gaps of float coordinates are
   exact in double, the sum rounds by a few 1e-16 relative; the 1e-9 margin covers it, so a box at
   distance d or a rounding hair beyond stays (conservative). */
PVS__STATIC int pvs__box_beyond(const pvs_box *a, const pvs_box *b, float d) {
    double sum = 0.0;
    int k;
    for (k = 0; k < 3; ++k) {
        double g = 0.0;
        if ((double)a->min[k] > (double)b->max[k]) g = (double)a->min[k] - (double)b->max[k];
        else if ((double)b->min[k] > (double)a->max[k]) g = (double)b->min[k] - (double)a->max[k];
        sum += g * g;
    }
    return sum > (double)d * (double)d * (1.0 + 1e-9);
}

PVS_API pvs_result pvs_bake_begin(const pvs_bake_desc *desc, pvs_bake **out, pvs_error *err) {
    pvs_bake *b;
    pvs_allocator a;
    size_t total, i;
    pvs_result r;
    pvs_method method;
    uint32_t k, mask = 0;
    if (out) *out = NULL;
    if (!desc || !out || !desc->scene) return pvs__fail(err, PVS_ERROR_INVALID_ARGUMENT, -1, 0, "desc, scene and out_bake must not be NULL");
    if (!desc->cells || desc->cell_count == 0) return pvs__fail(err, PVS_ERROR_INVALID_ARGUMENT, -1, 0, "no cells");
    if (desc->cell_count == 0xffffffffu) return pvs__fail(err, PVS_ERROR_COUNT_OVERFLOW, -1, 0, "too many cells");
    if (desc->shard_count == 1 || (desc->shard_count && desc->shard_index >= desc->shard_count) || desc->shard_count > desc->cell_count)
        return pvs__fail(err, PVS_ERROR_INVALID_ARGUMENT, -1, 0, "shard %u of %u for %u cells", desc->shard_index, desc->shard_count,
                         desc->cell_count);
    if (desc->max_chain > PVS_MAX_CHAIN) return pvs__fail(err, PVS_ERROR_INVALID_ARGUMENT, -1, 0, "max_chain %u > %u", desc->max_chain, PVS_MAX_CHAIN);
    if ((int)desc->method < 0 || desc->method >= PVS_METHOD_COUNT)
        return pvs__fail(err, PVS_ERROR_INVALID_ARGUMENT, -1, 0, "unknown method %d", (int)desc->method);
    if (!pvs__finite(desc->eps) || desc->eps < 0.0f)
        return pvs__fail(err, PVS_ERROR_INVALID_ARGUMENT, -1, 0, "eps must be finite and >= 0");
    if (!pvs__finite(desc->max_distance) || desc->max_distance < 0.0f)
        return pvs__fail(err, PVS_ERROR_INVALID_ARGUMENT, -1, 0, "max_distance must be finite and >= 0");
    if (desc->flags & ~PVS_BAKE_PREVIEW) return pvs__fail(err, PVS_ERROR_INVALID_ARGUMENT, -1, 0, "unknown bake flags 0x%x", desc->flags);
    if (desc->extproj_resolution && (desc->extproj_resolution < 16 || desc->extproj_resolution > 4096))
        return pvs__fail(err, PVS_ERROR_INVALID_ARGUMENT, -1, 0, "extproj_resolution %u is not in 16..4096", desc->extproj_resolution);
    if (desc->extproj_occluders > 65536)
        return pvs__fail(err, PVS_ERROR_INVALID_ARGUMENT, -1, 0, "extproj_occluders %u > 65536", desc->extproj_occluders);
    method = desc->method == PVS_METHOD_DEFAULT ? PVS_METHOD_AUTO : desc->method;
    if (method == PVS_METHOD_AUTO) {
        for (k = 0; k < (uint32_t)PVS_METHOD_COUNT; ++k)
            if (pvs__method_conservative((pvs_method)k)) mask |= 1u << k;
        if (desc->methods & ~mask)
            return pvs__fail(err, PVS_ERROR_INVALID_ARGUMENT, -1, 0, "methods mask 0x%x names a method that is not conservative or unknown "
                             "(auto never intersects sample)", desc->methods);
        /* vocc is for storage and the runtime rebuild, not tightness (about 0.2% on the demo city for
           20% more time): only when the mask names it */
        if (desc->methods) mask = desc->methods;
        else mask &= ~(1u << PVS_METHOD_VOCC);
    } else if (desc->methods) {
        return pvs__fail(err, PVS_ERROR_INVALID_ARGUMENT, -1, 0, "methods is for PVS_METHOD_AUTO only");
    }
    if (desc->vocc_only && (method != PVS_METHOD_VOCC || desc->vocc_only > 1))
        return pvs__fail(err, PVS_ERROR_INVALID_ARGUMENT, -1, 0, "vocc_only is 0 or 1, and 1 needs PVS_METHOD_VOCC");
    for (i = 0; i < desc->cell_count; ++i) {
        r = pvs__check_cell(desc->cells + i, (uint32_t)i, err);
        if (r != PVS_OK) return r;
    }
    a = desc->allocator;
    b = (pvs_bake *)pvs__alloc(&a, sizeof(pvs_bake), 16);
    if (!b) return pvs__fail(err, PVS_ERROR_OUT_OF_MEMORY, -1, 0, "bake");
    memset(b, 0, sizeof(*b));
    b->allocator = a;
    b->scene = desc->scene;
    b->total_cell_count = desc->cell_count;
    b->shard_count = desc->shard_count;
    b->shard_index = desc->shard_count ? desc->shard_index : 0;
    b->cell_count = desc->shard_count ? (desc->cell_count - desc->shard_index + desc->shard_count - 1) / desc->shard_count : desc->cell_count;
    b->max_chain = desc->max_chain;
    b->object_count = pvs_scene_object_count(desc->scene);
    b->words = PVS_BITSET_WORDS(b->object_count);
    b->method = method;
    b->eps = desc->eps;
    b->max_distance = desc->max_distance;
    b->flags = desc->flags;
    b->sample_points = desc->sample_points ? desc->sample_points : 32;
    b->sample_rays = desc->sample_rays ? desc->sample_rays : 2048;
    b->seed = desc->seed;
    if (!pvs__mul(b->words, b->cell_count, &total) || !pvs__mul(total, sizeof(pvs_word), &i)) {
        pvs_bake_destroy(b);
        return pvs__fail(err, PVS_ERROR_COUNT_OVERFLOW, -1, 0, "%u cells x %u objects do not fit in memory", desc->cell_count,
                         b->object_count);
    }
    b->cells = (pvs_box *)pvs__alloc_array(&a, b->cell_count, sizeof(pvs_box));
    b->pvs = (pvs_word *)pvs__alloc_array(&a, total, sizeof(pvs_word));
    b->done = (unsigned char *)pvs__alloc_array(&a, b->cell_count, 1);
    b->restored = (unsigned char *)pvs__alloc_array(&a, b->cell_count, 1);
    b->stats = (uint32_t *)pvs__alloc_array(&a, (size_t)b->cell_count * 2 * PVS_METHOD_COUNT, sizeof(uint32_t));
    if (!b->cells || !b->pvs || !b->done || !b->restored || !b->stats) {
        pvs_bake_destroy(b);
        return pvs__fail(err, PVS_ERROR_OUT_OF_MEMORY, -1, 0, "bake arrays for %u cells", desc->cell_count);
    }
    for (i = 0; i < b->cell_count; ++i) b->cells[i] = desc->cells[pvs_bake_task_cell(b, (uint32_t)i)];
    b->extproj_resolution = desc->extproj_resolution ? desc->extproj_resolution : (b->flags & PVS_BAKE_PREVIEW) ? 64u : PVS__EP_DEFAULT_RES;
    b->extproj_occluders = desc->extproj_occluders ? desc->extproj_occluders : (b->flags & PVS_BAKE_PREVIEW) ? 32u : PVS__EP_DEFAULT_OCC;
    memset(b->pvs, 0, total * sizeof(pvs_word));
    memset(b->done, 0, b->cell_count);
    memset(b->restored, 0, b->cell_count);
    memset(b->stats, 0, (size_t)b->cell_count * 2 * PVS_METHOD_COUNT * sizeof(uint32_t));
    if (method != PVS_METHOD_AUTO) {
        b->considered[0] = b->run[0] = method;
        b->ran[0] = 1;
        b->reason[0] = "requested";
        b->considered_count = b->run_count = 1;
        r = pvs__bake_prepare(b, method, desc, err);
        if (r != PVS_OK) {
            pvs_bake_destroy(b);
            return r;
        }
    } else {
        /* AUTO: the candidates cheapest first; each is prepared, then kept if it can cull anything
           in this scene; PREVIEW stops at the first kept */
        int rank;
        for (rank = 1; rank <= 4; ++rank)
            for (k = 0; k < (uint32_t)PVS_METHOD_COUNT; ++k) {
                pvs_method m = (pvs_method)k;
                const char *why = "preview runs only the cheapest method that applies";
                if (!(mask & (1u << k)) || pvs__method_cost_rank(m) != rank) continue;
                b->considered[b->considered_count] = m;
                if (!((b->flags & PVS_BAKE_PREVIEW) && b->run_count)) {
                    r = pvs__bake_prepare(b, m, desc, err);
                    if (r == PVS_ERROR_UNSUPPORTED) {
                        why = "not available in the bake driver";
                    } else if (r != PVS_OK) {
                        pvs_bake_destroy(b);
                        return r;
                    } else if (pvs__bake_applies(b, m, &why)) {
                        b->ran[b->considered_count] = 1;
                        b->run[b->run_count++] = m;
                    }
                }
                b->reason[b->considered_count++] = why;
            }
        if (!b->run_count) {
            pvs_bake_destroy(b);
            return pvs__fail(err, PVS_ERROR_UNSUPPORTED, -1, 0, "auto: no conservative method can cull anything in this scene");
        }
    }
    *out = b;
    pvs__ok(err);
    return PVS_OK;
}

PVS_API uint32_t pvs_bake_task_count(const pvs_bake *b) { return b->cell_count; }
PVS_API uint32_t pvs_bake_task_cell(const pvs_bake *b, uint32_t task) {
    PVS_ASSERT(task < b->cell_count);
    return b->shard_count ? b->shard_index + task * b->shard_count : task;
}
PVS_API pvs_method pvs_bake_method(const pvs_bake *b) { return b->method; }
PVS_API float pvs_bake_eps(const pvs_bake *b) { return b->eps; }
PVS_API const pvs_occluders *pvs_bake_occluders(const pvs_bake *b) { return b->occluders; }
PVS_API pvs_shrink_mode pvs_bake_shrink_mode(const pvs_bake *b) { return b->occluders ? b->shrink_mode : PVS_SHRINK_AUTO; }
PVS_API void pvs_bake_vocc_stats(const pvs_bake *b, pvs_vocc_stats *out) {
    uint32_t i;
    memset(out, 0, sizeof(*out));
    for (i = 0; b && b->vocc && i < b->cell_count; ++i) {
        const pvs_vocc_stats *t = b->vocc_stats + i;
        out->slices += t->slices; out->seeds += t->seeds; out->umbra += t->umbra; out->separating += t->separating;
        out->dense += t->dense; out->dropped += t->dropped; out->selected += t->selected;
    }
}


PVS_API pvs_result pvs_bake_run_task(pvs_bake *b, uint32_t task, pvs_error *err) {
    uint32_t cell, k, i, n, *own, *sole;
    pvs_word *bits, *each = NULL;
    pvs_result r = PVS_OK;
    size_t w;
    if (!b || task >= b->cell_count) return pvs__fail(err, PVS_ERROR_INVALID_ARGUMENT, task, 0, "task %u out of range", task);
    cell = pvs_bake_task_cell(b, task);
    bits = b->pvs + (size_t)task * b->words;
    n = b->run_count;
    own = b->stats + (size_t)task * 2 * PVS_METHOD_COUNT;
    sole = own + PVS_METHOD_COUNT;
    memset(bits, 0, b->words * sizeof(pvs_word));
    if (n == 1) {
        r = pvs__bake_method_cell(b, b->run[0], task, cell, bits, err);
        if (r != PVS_OK) return r;
        own[0] = pvs_bitset_count(bits, b->object_count);
        sole[0] = b->object_count - own[0];
    } else {
        /* AUTO: each method's PVS, then their intersection; a method's contribution is what it
           alone leaves out */
        each = (pvs_word *)pvs__alloc_array(&b->allocator, (size_t)n * b->words, sizeof(pvs_word));
        if (!each) return pvs__fail(err, PVS_ERROR_OUT_OF_MEMORY, cell, 0, "cell %u: auto scratch", cell);
        memset(each, 0, (size_t)n * b->words * sizeof(pvs_word));
        for (k = 0; k < n && r == PVS_OK; ++k) r = pvs__bake_method_cell(b, b->run[k], task, cell, each + (size_t)k * b->words, err);
        if (r == PVS_OK) {
            for (w = 0; w < b->words; ++w) {
                pvs_word all = ~(pvs_word)0;
                for (k = 0; k < n; ++k) all &= each[(size_t)k * b->words + w];
                bits[w] = all;
            }
            for (k = 0; k < n; ++k) {
                uint32_t c = 0;
                own[k] = pvs_bitset_count(each + (size_t)k * b->words, b->object_count);
                for (w = 0; w < b->words; ++w) {
                    pvs_word others = ~(pvs_word)0;
                    for (i = 0; i < n; ++i)
                        if (i != k) others &= each[(size_t)i * b->words + w];
                    c += pvs__popcount64(others & ~each[(size_t)k * b->words + w]);
                }
                sole[k] = c;
            }
        }
        pvs__free_array(&b->allocator, each, (size_t)n * b->words, sizeof(pvs_word));
        if (r != PVS_OK) return r;
    }
    if (b->max_distance > 0.0f) /* a draw distance: box to box, rounded toward keeping */
        for (i = pvs_bitset_next(bits, b->object_count, 0); i < b->object_count; i = pvs_bitset_next(bits, b->object_count, i + 1))
            if (pvs__box_beyond(b->cells + task, b->scene->object_boxes + i, b->max_distance)) pvs_bitset_clear(bits, i);
    b->done[task] = 1;
    pvs__ok(err);
    return PVS_OK;
}

PVS_API int pvs_bake_task_done(const pvs_bake *b, uint32_t task) { return b && task < b->cell_count && b->done[task]; }

PVS_API pvs_result pvs_bake_restore_task(pvs_bake *b, uint32_t task, const pvs_word *bits, size_t word_count, pvs_error *err) {
    uint32_t i;
    if (!b || !bits || task >= b->cell_count) return pvs__fail(err, PVS_ERROR_INVALID_ARGUMENT, task, 0, "restore: task %u out of range or NULL", task);
    if (word_count < b->words) return pvs__fail(err, PVS_ERROR_BUFFER_TOO_SMALL, task, 0, "restore: %zu words < %zu", word_count, b->words);
    if (b->method == PVS_METHOD_VOCC) /* the file stores the cell's virtual occluders too, which a PVS does not carry */
        return pvs__fail(err, PVS_ERROR_UNSUPPORTED, task, 0, "restore: a vocc bake cannot resume from PVSs: run task %u again", task);
    if ((b->object_count & 63u) && (bits[b->words - 1] >> (b->object_count & 63u)))
        return pvs__fail(err, PVS_ERROR_INVALID_ARGUMENT, task, 0, "restore: task %u sets a bit past the %u objects", task, b->object_count);
    for (i = pvs_bitset_next(bits, b->object_count, 0); i < b->object_count; i = pvs_bitset_next(bits, b->object_count, i + 1))
        if (b->scene->object_flags[i] & PVS_OBJECT_OCCLUDER_ONLY)
            return pvs__fail(err, PVS_ERROR_INVALID_ARGUMENT, task, 0, "restore: task %u sets occluder-only object %u", task, i);
    memcpy(b->pvs + (size_t)task * b->words, bits, b->words * sizeof(pvs_word));
    b->restored[task] = 1;
    b->done[task] = 1;
    pvs__ok(err);
    return PVS_OK;
}

PVS_API uint32_t pvs_bake_method_count(const pvs_bake *b) { return b ? b->considered_count : 0; }

PVS_API pvs_result pvs_bake_get_method_info(const pvs_bake *b, uint32_t i, pvs_bake_method_info *info) {
    uint32_t t, k, slot = 0;
    if (!b || !info || i >= b->considered_count) return PVS_ERROR_INVALID_ARGUMENT;
    memset(info, 0, sizeof(*info));
    info->method = b->considered[i];
    info->ran = b->ran[i];
    info->reason = b->reason[i] ? b->reason[i] : "";
    if (!info->ran) return PVS_OK;
    for (k = 0; k < b->run_count; ++k)
        if (b->run[k] == info->method) slot = k;
    for (t = 0; t < b->cell_count; ++t) {
        const uint32_t *own = b->stats + (size_t)t * 2 * PVS_METHOD_COUNT;
        if (!b->done[t] || b->restored[t]) continue;
        info->cells++;
        info->pvs_sum += own[slot];
        info->sole_culls += own[PVS_METHOD_COUNT + slot];
    }
    return PVS_OK;
}

PVS_API const pvs_word *pvs_bake_cell_pvs(const pvs_bake *b, uint32_t cell) {
    uint32_t task = cell;
    if (b->shard_count) {
        if (cell < b->shard_index || (cell - b->shard_index) % b->shard_count) return NULL;
        task = (cell - b->shard_index) / b->shard_count;
    }
    if (task >= b->cell_count || !b->done[task]) return NULL;
    return b->pvs + (size_t)task * b->words;
}

PVS__STATIC void pvs__bake_file_desc(const pvs_bake *b, pvs_file_desc *fd) {
    memset(fd, 0, sizeof(*fd));
    fd->cells = b->cells;
    fd->cell_count = b->cell_count;
    fd->object_count = b->object_count;
    fd->pvs = b->pvs;
    fd->method = b->method;
    fd->eps = b->eps;
    fd->up_axis = pvs_scene_up_axis(b->scene);
    fd->flags = b->method == PVS_METHOD_SAMPLE ? PVS_FILE_APPROXIMATE : 0u;
    fd->max_chain = b->max_chain;
    fd->shard_index = b->shard_index;
    fd->shard_count = b->shard_count;
    fd->total_cell_count = b->shard_count ? b->total_cell_count : 0;
    fd->allocator = b->allocator;
    if (b->vocc && b->method == PVS_METHOD_VOCC) { /* AUTO intersects vocc's PVS but stores no occluders */
        fd->vocc_counts = b->vocc_count;
        fd->vocc_scales = b->vocc_scale;
        fd->virtual_occluders = b->vocc_bytes;
        fd->vocc_stride = b->vocc->max_keep * 5;
        fd->vocc_base = b->vocc->base;
        fd->vocc_height_step = b->vocc->hstep;
        fd->vocc_flags = b->vocc_only ? PVS_VOCC_ONLY : 0u;
    }
}

PVS__STATIC int pvs__bake_all_done(const pvs_bake *b) {
    uint32_t i;
    for (i = 0; i < b->cell_count; ++i)
        if (!b->done[i]) return 0;
    return 1;
}

PVS_API size_t pvs_bake_file_size(const pvs_bake *b) {
    pvs_file_desc fd;
    size_t size = 0;
    if (!b || !pvs__bake_all_done(b)) return 0;
    pvs__bake_file_desc(b, &fd);
    return pvs_file_encode(&fd, NULL, 0, &size, NULL) == PVS_OK ? size : 0;
}

PVS_API pvs_result pvs_bake_write_file(const pvs_bake *b, void *out, size_t capacity, size_t *out_size, pvs_error *err) {
    pvs_file_desc fd;
    uint32_t i;
    if (!b) return pvs__fail(err, PVS_ERROR_INVALID_ARGUMENT, -1, 0, "bake is NULL");
    if (out_size) *out_size = 0;
    for (i = 0; i < b->cell_count; ++i)
        if (!b->done[i]) return pvs__fail(err, PVS_ERROR_NOT_DONE, pvs_bake_task_cell(b, i), 0, "cell %u has not been baked", pvs_bake_task_cell(b, i));
    pvs__bake_file_desc(b, &fd);
    return pvs_file_encode(&fd, out, capacity, out_size, err);
}

// >>format
/* ---------------------------------------------------------------------------------------------- */
/* format: the .pvs file (layout in the manual at the top): delta-PVS encoder (Durand et al. 2000,  */
/* §6.2), set codings, validating zero-copy reader                                                */
/* ---------------------------------------------------------------------------------------------- */

#define PVS__HEADER_SIZE 32u
#define PVS__SECTION_ENTRY 16u
#define PVS__MAX_SECTIONS 64u
#define PVS__META_SIZE 32u
#define PVS__CELL_HEAD 20u
#define PVS__TREE_HEAD 8u
#define PVS__TREE_MAX_DEPTH 24u        /* deepest look-up tree a reader accepts */
#define PVS__SHRD_SIZE 16u
#define PVS__BLOCK 16u                  /* records per block of the RECS offset table */
#define PVS__CANDIDATES 8u              /* base candidates per cell: nearest cells by the sweep */
#define PVS__TREE_LEAF 4u               /* most cells per look-up leaf */
#define PVS__RICE_MAX_K 24u
#define PVS__TAG(a, b, c, d) ((uint32_t)(a) | ((uint32_t)(b) << 8) | ((uint32_t)(c) << 16) | ((uint32_t)(d) << 24))
#define PVS__TAG_META PVS__TAG('M', 'E', 'T', 'A')
#define PVS__TAG_CELL PVS__TAG('C', 'E', 'L', 'L')
#define PVS__TAG_TREE PVS__TAG('T', 'R', 'E', 'E')
#define PVS__TAG_RECS PVS__TAG('R', 'E', 'C', 'S')
#define PVS__TAG_SHRD PVS__TAG('S', 'H', 'R', 'D')
enum { PVS__CODING_GAPS = 0, PVS__CODING_RUNS = 1, PVS__CODING_RICE = 2, PVS__CODING_BITMAP = 3 };

PVS__STATIC void pvs__put32(uint8_t *p, uint32_t v) {
    p[0] = (uint8_t)v; p[1] = (uint8_t)(v >> 8); p[2] = (uint8_t)(v >> 16); p[3] = (uint8_t)(v >> 24);
}
PVS__STATIC uint32_t pvs__get32(const uint8_t *p) {
    return (uint32_t)p[0] | ((uint32_t)p[1] << 8) | ((uint32_t)p[2] << 16) | ((uint32_t)p[3] << 24);
}
PVS__STATIC void pvs__putf32(uint8_t *p, float f) {
    uint32_t u;
    memcpy(&u, &f, 4);
    pvs__put32(p, u);
}
PVS__STATIC float pvs__getf32(const uint8_t *p) {
    uint32_t u = pvs__get32(p);
    float f;
    memcpy(&f, &u, 4);
    return f;
}
PVS__STATIC size_t pvs__align8(size_t n) { return (n + 7u) & ~(size_t)7u; }

/* LEB128 varint, at most 5 bytes. */
PVS__STATIC size_t pvs__put_varint(uint8_t *p, uint32_t v) {
    size_t n = 0;
    while (v >= 0x80u) {
        p[n++] = (uint8_t)(v | 0x80u);
        v >>= 7;
    }
    p[n++] = (uint8_t)v;
    return n;
}
PVS__STATIC size_t pvs__varint_size(uint32_t v) { return v < (1u << 7) ? 1 : v < (1u << 14) ? 2 : v < (1u << 21) ? 3 : v < (1u << 28) ? 4 : 5; }
/* Reads a varint from p[0..end); returns bytes used, 0 if malformed (overlong, > 32 bits, cut off). */
PVS__STATIC size_t pvs__get_varint(const uint8_t *p, const uint8_t *end, uint32_t *v) {
    uint32_t r = 0;
    size_t n;
    for (n = 0; n < 5; ++n) {
        uint8_t c;
        if (p + n >= end) return 0;
        c = p[n];
        if (n == 4 && c > 0x0fu) return 0;
        r |= (uint32_t)(c & 0x7fu) << (7 * n);
        if (!(c & 0x80u)) {
            if (n > 0 && c == 0) return 0; /* overlong: one canonical encoding per value */
            *v = r;
            return n + 1;
        }
    }
    return 0;
}
/* A varint known to be well formed (validated by pvs_file_open). */
PVS__STATIC const uint8_t *pvs__skip_varint(const uint8_t *p, uint32_t *v) {
    uint32_t r = 0;
    int s = 0;
    if (p[0] < 0x80u) { /* the common short forms first */
        *v = p[0];
        return p + 1;
    }
    if (p[1] < 0x80u) {
        *v = (p[0] & 0x7fu) | ((uint32_t)p[1] << 7);
        return p + 2;
    }
    while (*p & 0x80u) {
        r |= (uint32_t)(*p++ & 0x7fu) << s;
        s += 7;
    }
    *v = r | ((uint32_t)*p++ << s);
    return p;
}

/* Bit fields, least significant bit first. w <= 32; the reader touches only the bytes that hold
   bits [pos, pos + w). */
PVS__STATIC void pvs__put_bits(uint8_t *s, uint64_t pos, uint32_t v, uint32_t w) {
    uint32_t i;
    for (i = 0; i < w; ++i)
        if ((v >> i) & 1u) s[(pos + i) >> 3] |= (uint8_t)(1u << ((pos + i) & 7u));
}
PVS__STATIC uint32_t pvs__get_bits(const uint8_t *s, uint64_t pos, uint32_t w) {
    uint64_t v = 0;
    size_t at = (size_t)(pos >> 3), i, n;
    uint32_t shift = (uint32_t)(pos & 7u);
    if (!w) return 0;
    n = (shift + w + 7u) >> 3;
    for (i = 0; i < n; ++i) v |= (uint64_t)s[at + i] << (8 * i);
    return (uint32_t)((v >> shift) & (((uint64_t)1 << w) - 1u));
}
PVS__STATIC uint32_t pvs__bits_for(uint32_t max_value) { /* bits to hold 0..max_value */
    uint32_t w = 0;
    while (w < 32 && (max_value >> w)) ++w;
    return w;
}

PVS__STATIC uint64_t pvs__load64(const uint8_t *s) { /* little-endian; compilers make it one load */
    return (uint64_t)s[0] | (uint64_t)s[1] << 8 | (uint64_t)s[2] << 16 | (uint64_t)s[3] << 24 | (uint64_t)s[4] << 32 |
           (uint64_t)s[5] << 40 | (uint64_t)s[6] << 48 | (uint64_t)s[7] << 56;
}

/* Bits [bit, bit + 56) of a stream of nbits bits (zeros past its end), least significant first. */
PVS__STATIC uint64_t pvs__peek56(const uint8_t *s, uint64_t nbits, uint64_t bit) {
    size_t at = (size_t)(bit >> 3), n = (size_t)((nbits + 7) >> 3), i;
    uint64_t v = 0;
    if (at + 8 <= n) {
        v = pvs__load64(s + at);
    } else {
        for (i = 0; at + i < n; ++i) v |= (uint64_t)s[at + i] << (8 * i);
    }
    return (v >> (bit & 7u)) & (((uint64_t)1 << 56) - 1u);
}

/* The first clear bit at or after `from`, or bit_count. */
PVS__STATIC uint32_t pvs__bitset_next_clear(const pvs_word *bits, uint32_t bit_count, uint32_t from) {
    uint32_t w;
    pvs_word x;
    if (from >= bit_count) return bit_count;
    w = from >> 6;
    x = ~bits[w] & (~(pvs_word)0 << (from & 63));
    while (!x) {
        if ((++w << 6) >= bit_count) return bit_count;
        x = ~bits[w];
    }
    w = (w << 6) + pvs__ctz64(x);
    return w < bit_count ? w : bit_count;
}

/* ---- set codings ---- */

/* A set of ids in [0, n) is coded four ways (the manual gives the bytes); the encoder keeps the
   smallest, ties to the lowest coding. Rice codes (Golomb codes with a power-of-two divisor) suit the
   geometric gaps of sparse random sets; run lengths suit the contiguous id ranges that spatially
   ordered objects give; the raw bitset caps the worst case at n / 8 bytes. */
typedef struct pvs__coded {
    uint32_t coding, rice_k;
    size_t bytes;              /* body size */
} pvs__coded;

PVS__STATIC pvs__coded pvs__set_measure(const pvs_word *bits, uint32_t n) {
    uint64_t rice_bits[PVS__RICE_MAX_K + 1];
    size_t gaps = 0, runs = 0;
    uint32_t count = 0, pairs = 0, i, prev = 0, k, pos = 0;
    pvs__coded best;
    memset(rice_bits, 0, sizeof(rice_bits));
    for (i = pvs_bitset_next(bits, n, 0); i < n; i = pvs_bitset_next(bits, n, i + 1)) {
        uint32_t g = count ? i - prev - 1 : i;
        gaps += pvs__varint_size(g);
        for (k = 0; k <= PVS__RICE_MAX_K; ++k) rice_bits[k] += 1u + k + (g >> k);
        prev = i;
        ++count;
    }
    while (pos < n) { /* (zeros, ones) pairs */
        uint32_t one = pvs_bitset_next(bits, n, pos), zero;
        if (one >= n) break;
        zero = pvs__bitset_next_clear(bits, n, one);
        runs += pvs__varint_size(one - pos) + pvs__varint_size(zero - one - 1);
        ++pairs;
        pos = zero;
    }
    best.coding = PVS__CODING_GAPS;
    best.rice_k = 0;
    best.bytes = pvs__varint_size(count) + gaps;
    if (pvs__varint_size(pairs) + runs < best.bytes) {
        best.coding = PVS__CODING_RUNS;
        best.bytes = pvs__varint_size(pairs) + runs;
    }
    for (k = 0; k <= PVS__RICE_MAX_K; ++k) {
        size_t b = 1 + pvs__varint_size(count) + (size_t)((rice_bits[k] + 7) / 8);
        if (b < best.bytes) {
            best.coding = PVS__CODING_RICE;
            best.rice_k = k;
            best.bytes = b;
        }
    }
    if (((size_t)n + 7) / 8 < best.bytes) {
        best.coding = PVS__CODING_BITMAP;
        best.bytes = ((size_t)n + 7) / 8;
    }
    return best;
}

/* Writes the body (best.bytes bytes, zeroed first). */
PVS__STATIC void pvs__set_write(const pvs_word *bits, uint32_t n, const pvs__coded *c, uint8_t *out) {
    uint8_t *o = out;
    uint32_t i, prev = 0, count = 0, pos = 0;
    memset(out, 0, c->bytes);
    switch (c->coding) {
    case PVS__CODING_GAPS:
        o += pvs__put_varint(o, pvs_bitset_count(bits, n));
        for (i = pvs_bitset_next(bits, n, 0); i < n; i = pvs_bitset_next(bits, n, i + 1)) {
            o += pvs__put_varint(o, count ? i - prev - 1 : i);
            prev = i;
            ++count;
        }
        break;
    case PVS__CODING_RUNS: {
        uint32_t pairs = 0;
        while (pos < n) {
            uint32_t one = pvs_bitset_next(bits, n, pos);
            if (one >= n) break;
            pos = pvs__bitset_next_clear(bits, n, one);
            ++pairs;
        }
        o += pvs__put_varint(o, pairs);
        pos = 0;
        while (pairs--) {
            uint32_t one = pvs_bitset_next(bits, n, pos), zero = pvs__bitset_next_clear(bits, n, one);
            o += pvs__put_varint(o, one - pos);
            o += pvs__put_varint(o, zero - one - 1);
            pos = zero;
        }
        break;
    }
    case PVS__CODING_RICE: {
        uint64_t bit = 0;
        uint32_t k = c->rice_k;
        *o++ = (uint8_t)k;
        o += pvs__put_varint(o, pvs_bitset_count(bits, n));
        for (i = pvs_bitset_next(bits, n, 0); i < n; i = pvs_bitset_next(bits, n, i + 1)) {
            uint32_t g = count ? i - prev - 1 : i, q = g >> k, j;
            for (j = 0; j < q; ++j, ++bit) o[bit >> 3] |= (uint8_t)(1u << (bit & 7u));
            ++bit; /* the terminating zero */
            pvs__put_bits(o, bit, g & (k ? (uint32_t)((((uint64_t)1) << k) - 1u) : 0u), k);
            bit += k;
            prev = i;
            ++count;
        }
        break;
    }
    default: /* bitmap */
        for (i = 0; i < (n + 7) / 8; ++i) out[i] = (uint8_t)(bits[i >> 3] >> (8 * (i & 7)));
        break;
    }
}

/* What a decoded set does to a bitset. */
enum { PVS__SET_CHECK = 0, PVS__SET_ADD = 1, PVS__SET_REMOVE_RANKS = 2 };
typedef struct pvs__sink {
    int action;
    pvs_word *bits;            /* the PVS being built (not for CHECK) */
    uint32_t words;
    pvs_change_fn fn;          /* optional change reports */
    void *user;
    uint32_t w, before, removed; /* REMOVE_RANKS: scan position, set bits before word w, ranks removed */
} pvs__sink;

/* Adds id, or removes the set bit of rank id in the PVS as it was before this set (ranks ascend). */
/* Removes `count` consecutive ranks starting at rank `first` (of the PVS before this set), word by
   word: work in words plus bits actually removed, whatever the run's length. */
PVS__STATIC void pvs__sink_remove_run(pvs__sink *s, uint32_t first, uint64_t count) {
    uint32_t target = first - s->removed;
    while (s->w < s->words && s->before + pvs__popcount64(s->bits[s->w]) <= target) s->before += pvs__popcount64(s->bits[s->w++]);
    while (count && s->w < s->words) {
        pvs_word x = s->bits[s->w], take;
        uint32_t skip = target - s->before, k;
        for (k = 0; k < skip; ++k) x &= x - 1u; /* the set bits from the target on */
        take = x;
        if (pvs__popcount64(take) > count) { /* only the lowest `count` of them */
            pvs_word keep = take;
            uint64_t c;
            for (c = 0; c < count; ++c) keep &= keep - 1u;
            take ^= keep;
        }
        if (s->fn) {
            pvs_word y = take;
            while (y) {
                s->fn(s->user, s->w * 64 + pvs__ctz64(y), 0);
                y &= y - 1u;
            }
        }
        k = pvs__popcount64(take);
        s->bits[s->w] &= ~take;
        s->removed += k;
        count -= k;
        if (count) { /* the run goes on in the next words: nothing before them is left to skip */
            s->before += pvs__popcount64(s->bits[s->w]);
            ++s->w;
            target = s->before;
        }
    }
}

PVS__STATIC void pvs__sink_id(pvs__sink *s, uint32_t id) {
    if (s->action == PVS__SET_ADD) {
        pvs_word m = (pvs_word)1 << (id & 63);
        if (!(s->bits[id >> 6] & m)) {
            s->bits[id >> 6] |= m;
            if (s->fn) s->fn(s->user, id, 1);
        }
    } else if (s->action == PVS__SET_REMOVE_RANKS) {
        uint32_t target = id - s->removed, k;
        pvs_word x;
        while (s->w < s->words && s->before + pvs__popcount64(s->bits[s->w]) <= target) s->before += pvs__popcount64(s->bits[s->w++]);
        if (s->w == s->words) return; /* only in a damaged file: no such rank */
        x = s->bits[s->w];
        for (k = target - s->before; k; --k) x &= x - 1u;
        k = pvs__ctz64(x);
        s->bits[s->w] &= ~((pvs_word)1 << k);
        ++s->removed;
        if (s->fn) s->fn(s->user, s->w * 64 + k, 0);
    }
}

/* Decodes one coded set of ids in [0, n) that starts at p (bytes up to end are available) and feeds
   its ids, ascending, to the sink. *used receives the body's size: every coding is self-delimiting.
   Returns PVS_OK, or BAD_RECORD / OBJECT_OUT_OF_RANGE with *bad_at = the offending byte's offset. */
PVS__STATIC pvs_result pvs__set_apply(const uint8_t *p, const uint8_t *end, uint32_t coding, uint32_t n, pvs__sink *s, size_t *used_out,
                                      size_t *bad_at) {
    const uint8_t *q = p;
    uint32_t count, k;
    int act = s->action;
    switch (coding) {
    case PVS__CODING_GAPS: {
        uint64_t id = 0;
        size_t used = pvs__get_varint(q, end, &count);
        if (!used) goto bad;
        q += used;
        if (count > n) { *bad_at = 0; return PVS_ERROR_OBJECT_OUT_OF_RANGE; }
        for (k = 0; k < count; ++k) {
            uint32_t g;
            used = pvs__get_varint(q, end, &g);
            if (!used) goto bad;
            id = k ? id + 1u + g : g;
            if (id >= n) { *bad_at = (size_t)(q - p); return PVS_ERROR_OBJECT_OUT_OF_RANGE; }
            if (act == PVS__SET_ADD && !s->fn) s->bits[id >> 6] |= (pvs_word)1 << (id & 63); /* the decode's hot path */
            else if (act) pvs__sink_id(s, (uint32_t)id);
            q += used;
        }
        break;
    }
    case PVS__CODING_RUNS: {
        uint64_t pos = 0;
        size_t used = pvs__get_varint(q, end, &count);
        if (!used) goto bad;
        q += used;
        for (k = 0; k < count; ++k) {
            uint32_t z, o;
            uint64_t i;
            used = pvs__get_varint(q, end, &z);
            if (!used) goto bad;
            if (k && !z) goto bad; /* runs of ones are maximal */
            q += used;
            used = pvs__get_varint(q, end, &o);
            if (!used) goto bad;
            if (pos + z + o + 1u > n) { *bad_at = (size_t)(q - p); return PVS_ERROR_OBJECT_OUT_OF_RANGE; }
            q += used;
            pos += z;
            if (act == PVS__SET_ADD && !s->fn) { /* whole words at a time */
                uint64_t e = pos + o + 1u;
                while (pos < e && (pos & 63)) { s->bits[pos >> 6] |= (pvs_word)1 << (pos & 63); ++pos; }
                while (pos + 64 <= e) { s->bits[pos >> 6] = ~(pvs_word)0; pos += 64; }
                while (pos < e) { s->bits[pos >> 6] |= (pvs_word)1 << (pos & 63); ++pos; }
            } else if (act == PVS__SET_REMOVE_RANKS) {
                pvs__sink_remove_run(s, (uint32_t)pos, (uint64_t)o + 1u);
                pos += (uint64_t)o + 1u;
            } else {
                if (act) /* validation must stay linear in the record's bytes */
                    for (i = 0; i <= o; ++i) pvs__sink_id(s, (uint32_t)(pos + i));
                pos += (uint64_t)o + 1u;
            }
        }
        break;
    }
    case PVS__CODING_RICE: {
        uint64_t bit = 0, nbits, id = 0, bytes;
        size_t used;
        uint32_t c;
        if (q >= end) goto bad;
        k = *q++;
        if (k > PVS__RICE_MAX_K) goto bad;
        used = pvs__get_varint(q, end, &count);
        if (!used) goto bad;
        q += used;
        if (count > n) { *bad_at = 0; return PVS_ERROR_OBJECT_OUT_OF_RANGE; }
        nbits = (uint64_t)(end - q) * 8u;
        for (c = 0; c < count; ++c) {
            uint64_t quot = 0, g, w = pvs__peek56(q, nbits, bit);
            uint32_t ones;
            if (~w & (((uint64_t)1 << 56) - 1u)) { /* the quotient's terminating zero is in the window */
                ones = pvs__ctz64(~w);
                quot = ones;
                if (bit + ones + 1u + k > nbits) goto bad;
                if (quot > n) { *bad_at = (size_t)(q - p) + (size_t)(bit >> 3); return PVS_ERROR_OBJECT_OUT_OF_RANGE; }
                g = ones + 1u + k <= 56u ? (w >> (ones + 1u)) & (((uint64_t)1 << k) - 1u) : pvs__get_bits(q, bit + ones + 1u, k);
                bit += ones + 1u + k;
            } else {
                for (;;) { /* a long unary run: bit by bit */
                    uint32_t b1;
                    if (bit >= nbits) goto bad;
                    b1 = (q[bit >> 3] >> (bit & 7u)) & 1u;
                    ++bit;
                    if (!b1) break;
                    if (++quot > n) { *bad_at = (size_t)(q - p) + (size_t)(bit >> 3); return PVS_ERROR_OBJECT_OUT_OF_RANGE; }
                }
                if (bit + k > nbits) goto bad;
                g = pvs__get_bits(q, bit, k);
                bit += k;
            }
            g |= quot << k;
            id = c ? id + 1u + g : g;
            if (id >= n) { *bad_at = (size_t)(q - p) + (size_t)(bit >> 3); return PVS_ERROR_OBJECT_OUT_OF_RANGE; }
            if (act == PVS__SET_ADD && !s->fn) s->bits[id >> 6] |= (pvs_word)1 << (id & 63); /* the decode's hot path */
            else if (act) pvs__sink_id(s, (uint32_t)id);
        }
        /* the codes fill whole bytes; the unused high bits of the last one are zero */
        bytes = (bit + 7) / 8;
        if ((bit & 7u) && (q[bit >> 3] >> (bit & 7u))) { q += (size_t)(bit >> 3); goto bad; }
        q += (size_t)bytes;
        break;
    }
    case PVS__CODING_BITMAP: {
        size_t nb = ((size_t)n + 7) / 8, i;
        if ((size_t)(end - q) < nb) goto bad;
        if ((n & 7u) && (q[nb - 1] >> (n & 7u))) { *bad_at = nb - 1; return PVS_ERROR_OBJECT_OUT_OF_RANGE; }
        if (act == PVS__SET_ADD && !s->fn) {
            for (i = 0; i < nb; ++i) s->bits[i >> 3] |= (pvs_word)q[i] << (8 * (i & 7));
        } else if (act) {
            for (i = 0; i < nb; ++i) {
                uint32_t b = q[i];
                while (b) {
                    uint32_t id = (uint32_t)(8 * i) + pvs__ctz64(b);
                    b &= b - 1u;
                    pvs__sink_id(s, id);
                }
            }
        }
        q += nb;
        break;
    }
    default: goto bad;
    }
    *used_out = (size_t)(q - p);
    return PVS_OK;
bad:
    *bad_at = (size_t)(q - p);
    return PVS_ERROR_BAD_RECORD;
}

/* ---- encoder ---- */

typedef struct pvs__heapent {
    uint32_t weight, node, from; /* from: the base cell + 1, 0 for the virtual root (a key cell) */
} pvs__heapent;

PVS__STATIC int pvs__heap_less(const pvs__heapent *a, const pvs__heapent *b) {
    if (a->weight != b->weight) return a->weight < b->weight;
    if (a->node != b->node) return a->node < b->node;
    return a->from < b->from;
}
PVS__STATIC void pvs__heap_push(pvs__heapent *h, size_t *n, pvs__heapent e) {
    size_t i = (*n)++;
    while (i > 0) {
        size_t parent = (i - 1) / 2;
        if (!pvs__heap_less(&e, h + parent)) break;
        h[i] = h[parent];
        i = parent;
    }
    h[i] = e;
}
PVS__STATIC pvs__heapent pvs__heap_pop(pvs__heapent *h, size_t *n) {
    pvs__heapent top = h[0], last = h[--*n];
    size_t i = 0;
    for (;;) {
        size_t c = 2 * i + 1;
        if (c >= *n) break;
        if (c + 1 < *n && pvs__heap_less(h + c + 1, h + c)) ++c;
        if (!pvs__heap_less(h + c, &last)) break;
        h[i] = h[c];
        i = c;
    }
    if (*n) h[i] = last;
    return top;
}

PVS__STATIC int pvs__float_cmp(const void *a, const void *b) {
    float x = *(const float *)a, y = *(const float *)b;
    return x < y ? -1 : x > y;
}
/* Index of v in the sorted unique table t[0..n). */
PVS__STATIC uint32_t pvs__value_index(const float *t, uint32_t n, float v) {
    uint32_t lo = 0, hi = n - 1;
    while (lo < hi) {
        uint32_t mid = lo + (hi - lo) / 2;
        if (t[mid] < v) lo = mid + 1;
        else hi = mid;
    }
    return lo;
}

/* ---- the stored cell look-up tree ---- */

/* The file's look-up tree is a complete binary kD-tree of depth D over the cells, stored implicitly
   (children of node k are 2k + 1 and 2k + 2, as in a binary heap) so that a look-up reads no
   pointers: one split per level, then one leaf's cell list. Splits are cell coordinates (indices
   into the CELL tables) and the split rule never copies touching neighbours: p < split goes left,
   p > split right, p == split both ways; left holds the cells with min < split or max <= split, right
   those with max > split. Each node splits at the median cell edge of the axis that halves its cells
   best; a node no split can divide passes all its cells to the left. D is the smallest depth giving
   leaves of about PVS__TREE_LEAF cells. */
typedef struct pvs__tbuild {
    const pvs_allocator *a;
    const pvs_box *boxes;
    uint32_t depth;
    uint32_t *nodes;           /* 2^D - 1 */
    uint32_t *leaf_start;      /* 2^D + 1 offsets into items */
    uint8_t *items;            /* per leaf: gap-coded ascending cell ids */
    size_t item_bytes, item_capacity;
    uint32_t leaves_done;
    float *keys;               /* scratch: 2n floats */
    const float *values[3];
    const uint32_t *value_count;
} pvs__tbuild;

PVS__STATIC pvs_result pvs__tree_node(pvs__tbuild *b, const uint32_t *ids, uint32_t n, uint32_t level, uint32_t k) {
    pvs_result r = PVS_OK;
    uint32_t i, best_axis = 3, best_score = n, axis;
    float best_v = 0.0f;
    if (level == b->depth) { /* leaf */
        b->items = (uint8_t *)pvs__kd_grow(b->a, b->items, &b->item_capacity, b->item_bytes, b->item_bytes + 5 * (size_t)n, 1, &r);
        if (!b->items) return r;
        b->leaf_start[b->leaves_done++] = (uint32_t)b->item_bytes;
        for (i = 0; i < n; ++i) b->item_bytes += pvs__put_varint(b->items + b->item_bytes, i ? ids[i] - ids[i - 1] - 1 : ids[0]);
        return PVS_OK;
    }
    if (n > 1) {
        /* every cell edge is a candidate: with the sorted mins and maxes, the cells going left (min <
           v; flat cells at v aside) and right (max > v) are counted by binary search; the candidate
           with the smaller larger side wins, ties to the first. Crossing cells (long rows over long
           columns) thus still split, where a median alone would not. */
        float *mins = b->keys, *maxs = b->keys + n;
        for (axis = 0; axis < 3; ++axis) {
            int side;
            for (i = 0; i < n; ++i) {
                mins[i] = b->boxes[ids[i]].min[axis];
                maxs[i] = b->boxes[ids[i]].max[axis];
            }
            qsort(mins, n, sizeof(float), pvs__float_cmp);
            qsort(maxs, n, sizeof(float), pvs__float_cmp);
            for (side = 0; side < 2; ++side)
                for (i = 0; i < n; ++i) {
                    float v = side ? maxs[i] : mins[i];
                    uint32_t lo = 0, hi = n, left, right, score;
                    if (i && v == (side ? maxs[i - 1] : mins[i - 1])) continue;
                    while (lo < hi) { /* mins < v */
                        uint32_t mid = lo + (hi - lo) / 2;
                        if (mins[mid] < v) lo = mid + 1;
                        else hi = mid;
                    }
                    left = lo;
                    lo = 0;
                    hi = n;
                    while (lo < hi) { /* maxs <= v */
                        uint32_t mid = lo + (hi - lo) / 2;
                        if (maxs[mid] <= v) lo = mid + 1;
                        else hi = mid;
                    }
                    right = n - lo;
                    score = left > right ? left : right;
                    if (left > 0 && right > 0 && left < n && right < n && score < best_score) {
                        best_score = score;
                        best_axis = axis;
                        best_v = v;
                    }
                }
        }
        if (best_axis != 3) { /* the exact counts (flat cells at the split go left) must still make progress */
            uint32_t left = 0, right = 0;
            for (i = 0; i < n; ++i) {
                const pvs_box *c = b->boxes + ids[i];
                left += c->min[best_axis] < best_v || c->max[best_axis] <= best_v;
                right += c->max[best_axis] > best_v;
            }
            if (left == n || right == n) best_axis = 3;
        }
    }
    if (best_axis == 3) { /* no split divides these cells: all go left */
        b->nodes[k] = 3u;
        r = pvs__tree_node(b, ids, n, level + 1, 2 * k + 1);
        return r == PVS_OK ? pvs__tree_node(b, ids, 0, level + 1, 2 * k + 2) : r;
    }
    {
        uint32_t *sub = (uint32_t *)pvs__alloc_array(b->a, n, sizeof(uint32_t)), m = 0;
        if (!sub) return PVS_ERROR_OUT_OF_MEMORY;
        b->nodes[k] = best_axis | (pvs__value_index(b->values[best_axis], b->value_count[best_axis], best_v) << 2);
        for (i = 0; i < n; ++i) {
            const pvs_box *c = b->boxes + ids[i];
            if (c->min[best_axis] < best_v || c->max[best_axis] <= best_v) sub[m++] = ids[i];
        }
        r = pvs__tree_node(b, sub, m, level + 1, 2 * k + 1);
        if (r == PVS_OK) {
            for (i = 0, m = 0; i < n; ++i)
                if (b->boxes[ids[i]].max[best_axis] > best_v) sub[m++] = ids[i];
            r = pvs__tree_node(b, sub, m, level + 1, 2 * k + 2);
        }
        pvs__free_array(b->a, sub, n, sizeof(uint32_t));
        return r;
    }
}

typedef struct pvs__candidates {
    uint32_t self, count, list[PVS__CANDIDATES];
} pvs__candidates;

PVS__STATIC pvs_visit pvs__collect_candidates(void *user, const pvs_box *node_box, float distance, const uint32_t *items,
                                              uint32_t item_count) {
    pvs__candidates *c = (pvs__candidates *)user;
    uint32_t i, j;
    (void)node_box;
    (void)distance;
    for (i = 0; i < item_count; ++i) {
        uint32_t it = items[i];
        if (it == c->self) continue;
        for (j = 0; j < c->count && c->list[j] != it; ++j) {}
        if (j < c->count) continue;
        c->list[c->count++] = it;
        if (c->count == PVS__CANDIDATES) return PVS_VISIT_STOP;
    }
    return PVS_VISIT_DESCEND;
}

typedef struct pvs__link {
    uint32_t a, b, weight;
} pvs__link;
PVS__STATIC int pvs__edge_cmp(const void *x, const void *y) {
    const pvs__link *e = (const pvs__link *)x, *f = (const pvs__link *)y;
    if (e->a != f->a) return e->a < f->a ? -1 : 1;
    if (e->b != f->b) return e->b < f->b ? -1 : 1;
    return 0;
}

PVS__STATIC uint32_t pvs__zigzag(int64_t d) { return (uint32_t)(d >= 0 ? 2 * (uint64_t)d : 2 * (uint64_t)(-d) - 1u); }
PVS__STATIC int64_t pvs__unzigzag(uint32_t z) { return (z & 1u) ? -(int64_t)((z >> 1) + 1u) : (int64_t)(z >> 1); }

/* Everything the encoder allocates, freed in one place. */
typedef struct pvs__encoder {
    pvs_allocator a;
    const pvs_file_desc *d;
    uint32_t n, cells;
    size_t words;
    pvs_box *boxes;            /* the cells with -0 replaced by +0 (what the file stores) */
    float *values[3];
    uint32_t value_count[3], index_bits[6]; /* widths: min indices, then extents */
    pvs_kdtree *tree;          /* over the cells: base candidates */
    uint8_t *tree_stream;      /* the TREE section's nodes */
    size_t tree_bytes;
    uint32_t tree_depth;
    void *sweep;
    size_t sweep_size;
    pvs__link *edges;
    size_t edge_count, edge_capacity;
    uint32_t *adj_start;       /* CSR over the symmetric candidate graph */
    uint32_t *adj;             /* (neighbour, weight) pairs */
    pvs__heapent *heap;
    size_t heap_capacity;
    uint32_t *base, *depth;    /* base = PVS_NO_CELL for keys */
    unsigned char *placed;
    pvs_word *tmp, *ranks;
    uint8_t *recs;
    size_t recs_capacity;
} pvs__encoder;

PVS__STATIC void pvs__encoder_free(pvs__encoder *e) {
    const pvs_allocator *a = &e->a;
    int k;
    for (k = 0; k < 3; ++k) pvs__free_array(a, e->values[k], 2 * (size_t)e->cells, sizeof(float));
    pvs__free_array(a, e->boxes, e->cells, sizeof(pvs_box));
    pvs_kdtree_destroy(e->tree);
    pvs__free_array(a, e->tree_stream, e->tree_bytes, 1);
    pvs__free(a, e->sweep, e->sweep_size, 16);
    pvs__free_array(a, e->edges, e->edge_capacity, sizeof(pvs__link));
    pvs__free_array(a, e->adj_start, (size_t)e->cells + 1, sizeof(uint32_t));
    pvs__free_array(a, e->adj, 4 * e->edge_capacity, sizeof(uint32_t));
    pvs__free_array(a, e->heap, e->heap_capacity, sizeof(pvs__heapent));
    pvs__free_array(a, e->base, e->cells, sizeof(uint32_t));
    pvs__free_array(a, e->depth, e->cells, sizeof(uint32_t));
    pvs__free_array(a, e->placed, e->cells, 1);
    pvs__free_array(a, e->tmp, e->words, sizeof(pvs_word));
    pvs__free_array(a, e->ranks, e->words, sizeof(pvs_word));
    pvs__free_array(a, e->recs, e->recs_capacity, 1);
}

/* tmp = cell i's set (masked to n bits), XOR base j's when j != PVS_NO_CELL. */
/* The sets of cell i's record against base j (PVS_NO_CELL: a key): e->tmp = the ids to add (all of
   the PVS for a key); for a delta e->ranks = the ids to remove, as ranks in the base's PVS (Durand et
   al. 2000, §6.2: a delta is the objects added and removed; removed ones are cheaper to name by
   their position among the base's few visible objects). Returns the base's PVS size. */
PVS__STATIC uint32_t pvs__encoder_sets(pvs__encoder *e, uint32_t i, uint32_t j) {
    const pvs_word *x = e->d->pvs + (size_t)i * e->words;
    pvs_word last = (e->n & 63) ? ((pvs_word)1 << (e->n & 63)) - 1u : ~(pvs_word)0;
    uint32_t m = 0;
    size_t w;
    if (j == PVS_NO_CELL) {
        memcpy(e->tmp, x, e->words * sizeof(pvs_word));
    } else {
        const pvs_word *y = e->d->pvs + (size_t)j * e->words;
        memset(e->ranks, 0, e->words * sizeof(pvs_word));
        for (w = 0; w < e->words; ++w) {
            pvs_word base = y[w] & (w + 1 == e->words ? last : ~(pvs_word)0), gone = base & ~x[w];
            e->tmp[w] = x[w] & ~y[w];
            while (base) { /* rank m of the base's set bits */
                pvs_word low = base & (0u - base);
                if (gone & low) e->ranks[m >> 6] |= (pvs_word)1 << (m & 63);
                base ^= low;
                ++m;
            }
        }
    }
    e->tmp[e->words - 1] &= last;
    return m;
}
/* The record's size of cell i against base j. */
PVS__STATIC uint32_t pvs__encoder_cost(pvs__encoder *e, uint32_t i, uint32_t j) {
    size_t b;
    uint32_t m = pvs__encoder_sets(e, i, j);
    b = pvs__set_measure(e->tmp, e->n).bytes + 2u;
    if (j != PVS_NO_CELL) b += 2u + pvs__varint_size(m) + pvs__set_measure(e->ranks, m).bytes;
    return b > 0xffffffffu ? 0xffffffffu : (uint32_t)b;
}

/* Bases: candidate edges from each cell to its nearest cells (the kD-tree sweep); a virtual root
   joined to every cell by its key size; then Prim's minimum spanning tree from the root, each edge
   weighed when it is reached by the coded size of the delta in that direction, and taken only while
   the chain stays within K deltas (a greedy depth-bounded minimum arborescence). A cell whose cheapest admissible link is the root
   becomes a key: "key cells where a delta does not pay". Ties break by (weight, cell, base), so the
   result is a function of the table alone. */
PVS__STATIC pvs_result pvs__encoder_bases(pvs__encoder *e, uint32_t max_chain, pvs_error *err) {
    const pvs_allocator *a = &e->a;
    uint32_t i, c;
    size_t k, m, heap_n = 0;
    pvs_result r = PVS_OK;
    e->edge_capacity = (size_t)e->cells * PVS__CANDIDATES;
    e->edges = (pvs__link *)pvs__alloc_array(a, e->edge_capacity, sizeof(pvs__link));
    e->adj_start = (uint32_t *)pvs__alloc_array(a, (size_t)e->cells + 1, sizeof(uint32_t));
    e->adj = (uint32_t *)pvs__alloc_array(a, 4 * e->edge_capacity, sizeof(uint32_t));
    e->base = (uint32_t *)pvs__alloc_array(a, e->cells, sizeof(uint32_t));
    e->depth = (uint32_t *)pvs__alloc_array(a, e->cells, sizeof(uint32_t));
    e->placed = (unsigned char *)pvs__alloc_array(a, e->cells, 1);
    e->sweep_size = pvs_kdtree_sweep_scratch_size(e->tree);
    e->sweep = pvs__alloc(a, e->sweep_size ? e->sweep_size : 1, 16);
    if (!e->edges || !e->adj_start || !e->adj || !e->base || !e->depth || !e->placed || !e->sweep)
        return pvs__fail(err, PVS_ERROR_OUT_OF_MEMORY, -1, 0, "encoder graph for %u cells", e->cells);
    for (i = 0; i < e->cells; ++i) {
        pvs__candidates cand;
        cand.self = i;
        cand.count = 0;
        r = pvs_kdtree_sweep(e->tree, e->boxes + i, e->sweep, e->sweep_size, pvs__collect_candidates, &cand);
        if (r != PVS_OK) return pvs__fail(err, r, i, 0, "base candidates of cell %u", i);
        for (c = 0; c < cand.count; ++c) {
            pvs__link *ed = e->edges + e->edge_count++;
            ed->a = i < cand.list[c] ? i : cand.list[c];
            ed->b = i < cand.list[c] ? cand.list[c] : i;
            ed->weight = 0;
        }
    }
    /* unique undirected edges, weighted */
    qsort(e->edges, e->edge_count, sizeof(pvs__link), pvs__edge_cmp);
    for (k = 0, m = 0; k < e->edge_count; ++k)
        if (!m || e->edges[k].a != e->edges[m - 1].a || e->edges[k].b != e->edges[m - 1].b) e->edges[m++] = e->edges[k];
    e->edge_count = m;
    memset(e->adj_start, 0, ((size_t)e->cells + 1) * sizeof(uint32_t));
    for (k = 0; k < m; ++k) {
        ++e->adj_start[e->edges[k].a + 1];
        ++e->adj_start[e->edges[k].b + 1];
    }
    for (i = 0; i < e->cells; ++i) e->adj_start[i + 1] += e->adj_start[i];
    {
        /* fill: a second cursor per cell in depth[] (reused as scratch before Prim) */
        for (i = 0; i < e->cells; ++i) e->depth[i] = e->adj_start[i];
        for (k = 0; k < m; ++k) {
            uint32_t x = e->edges[k].a, y = e->edges[k].b, w = e->edges[k].weight;
            e->adj[2 * (size_t)e->depth[x]] = y;
            e->adj[2 * (size_t)e->depth[x] + 1] = w;
            ++e->depth[x];
            e->adj[2 * (size_t)e->depth[y]] = x;
            e->adj[2 * (size_t)e->depth[y] + 1] = w;
            ++e->depth[y];
        }
    }
    e->heap_capacity = (size_t)e->cells + 2 * m + 1;
    e->heap = (pvs__heapent *)pvs__alloc_array(a, e->heap_capacity, sizeof(pvs__heapent));
    if (!e->heap) return pvs__fail(err, PVS_ERROR_OUT_OF_MEMORY, -1, 0, "encoder heap");
    memset(e->placed, 0, e->cells);
    for (i = 0; i < e->cells; ++i) {
        pvs__heapent h;
        h.weight = pvs__encoder_cost(e, i, PVS_NO_CELL);
        h.node = i;
        h.from = 0;
        pvs__heap_push(e->heap, &heap_n, h);
    }
    while (heap_n) {
        pvs__heapent h = pvs__heap_pop(e->heap, &heap_n);
        uint32_t v = h.node, j;
        if (e->placed[v]) continue;
        if (h.from && e->depth[h.from - 1] >= max_chain) continue; /* the chain would grow past K */
        e->placed[v] = 1;
        e->base[v] = h.from ? h.from - 1 : PVS_NO_CELL;
        e->depth[v] = h.from ? e->depth[h.from - 1] + 1 : 0;
        for (j = e->adj_start[v]; j < e->adj_start[v + 1]; ++j) {
            uint32_t u = e->adj[2 * (size_t)j];
            if (!e->placed[u]) {
                pvs__heapent g;
                g.weight = pvs__encoder_cost(e, u, v);
                g.node = u;
                g.from = v + 1;
                pvs__heap_push(e->heap, &heap_n, g);
            }
        }
    }
    return PVS_OK;
}

/* Writes the RECS section body into e->recs (or measures it when e->recs is NULL). */
PVS__STATIC size_t pvs__encoder_records(pvs__encoder *e, uint8_t *out) {
    uint32_t blocks = (e->cells + PVS__BLOCK - 1) / PVS__BLOCK, i;
    size_t pos = 4 * ((size_t)blocks + 1);
    for (i = 0; i < e->cells; ++i) {
        pvs__coded c, cr;
        uint32_t head, zz = 0, m = pvs__encoder_sets(e, i, e->base[i]);
        int delta = e->base[i] != PVS_NO_CELL;
        size_t inner;
        if (out && i % PVS__BLOCK == 0) pvs__put32(out + 4 * (size_t)(i / PVS__BLOCK), (uint32_t)pos);
        c = pvs__set_measure(e->tmp, e->n);
        head = c.coding | (e->depth[i] << 2);
        inner = pvs__varint_size(head) + c.bytes;
        if (delta) {
            zz = pvs__zigzag((int64_t)i - (int64_t)e->base[i]);
            cr = pvs__set_measure(e->ranks, m);
            inner += pvs__varint_size(zz) + 1u + pvs__varint_size(m) + cr.bytes;
        }
        if (out) {
            uint8_t *o = out + pos;
            o += pvs__put_varint(o, (uint32_t)inner);
            o += pvs__put_varint(o, head);
            if (delta) {
                o += pvs__put_varint(o, zz);
                *o++ = (uint8_t)cr.coding;
                o += pvs__put_varint(o, m);
                pvs__set_write(e->ranks, m, &cr, o);
                o += cr.bytes;
            }
            pvs__set_write(e->tmp, e->n, &c, o);
        }
        pos += pvs__varint_size((uint32_t)inner) + inner;
    }
    if (out) pvs__put32(out + 4 * (size_t)blocks, (uint32_t)pos);
    return pos;
}

PVS_API pvs_result pvs_file_encode(const pvs_file_desc *d, void *out, size_t capacity, size_t *out_size, pvs_error *err) {
    pvs__encoder e;
    pvs_result r = PVS_OK;
    uint32_t i, k, max_chain, sections, keys = 0;
    size_t at[6], sz[6], total, cell_bytes, recs_size, index_bits_total, vocc_size = 0;
    uint32_t tags[6];
    uint8_t *o = (uint8_t *)out;
    if (out_size) *out_size = 0;
    if (!d || !d->cells || !d->pvs || !d->cell_count || !d->object_count)
        return pvs__fail(err, PVS_ERROR_INVALID_ARGUMENT, -1, 0, "desc, cells and pvs must not be NULL or empty");
    if (d->up_axis != 1 && d->up_axis != 2) return pvs__fail(err, PVS_ERROR_INVALID_ARGUMENT, -1, 0, "up_axis must be 1 or 2");
    if ((int)d->method < 0 || d->method >= PVS_METHOD_COUNT || !pvs__finite(d->eps) || d->eps < 0.0f)
        return pvs__fail(err, PVS_ERROR_INVALID_ARGUMENT, -1, 0, "bad method or eps");
    if (d->cell_count == PVS_NO_CELL || d->object_count == 0xffffffffu || d->cell_count > 0x3fffffffu)
        return pvs__fail(err, PVS_ERROR_COUNT_OVERFLOW, -1, 0, "too many cells or objects");
    max_chain = d->max_chain ? d->max_chain : PVS_DEFAULT_CHAIN;
    if (max_chain > PVS_MAX_CHAIN) return pvs__fail(err, PVS_ERROR_INVALID_ARGUMENT, -1, 0, "max_chain %u > %u", max_chain, PVS_MAX_CHAIN);
    if (d->shard_count == 1 || (d->shard_count && (d->shard_index >= d->shard_count || d->total_cell_count > 0x3fffffffu ||
                                                   d->cell_count != (d->total_cell_count - d->shard_index + d->shard_count - 1) / d->shard_count)))
        return pvs__fail(err, PVS_ERROR_INVALID_ARGUMENT, -1, 0, "shard %u of %u does not hold %u of %u cells", d->shard_index,
                         d->shard_count, d->cell_count, d->total_cell_count);
    for (i = 0; i < d->cell_count; ++i) {
        r = pvs__check_cell(d->cells + i, i, err);
        if (r != PVS_OK) return r;
    }
    if (d->vocc_counts) { /* the optional VOCC section (>>vocc) */
        uint64_t n = 0;
        for (i = 0; i < d->cell_count; ++i) n += d->vocc_counts[i];
        vocc_size = pvs__vo_section_size(d->cell_count, n);
        if (!d->vocc_scales || (n && !d->virtual_occluders) || !pvs__finite(d->vocc_base) || !pvs__finite(d->vocc_height_step) ||
            !(d->vocc_height_step > 0.0f) || (d->vocc_flags & ~PVS_VOCC_ONLY) || !vocc_size)
            return pvs__fail(err, PVS_ERROR_INVALID_ARGUMENT, -1, 0, "virtual occluders: missing arrays, bad heights or flags");
    }
    memset(&e, 0, sizeof(e));
    e.a = d->allocator;
    e.d = d;
    e.n = d->object_count;
    e.cells = d->cell_count;
    e.words = PVS_BITSET_WORDS(d->object_count);

    /* CELL: per-axis tables of the distinct coordinates (-0 stored as +0), bit-packed indices */
    e.boxes = (pvs_box *)pvs__alloc_array(&e.a, e.cells, sizeof(pvs_box));
    if (!e.boxes) { r = pvs__fail(err, PVS_ERROR_OUT_OF_MEMORY, -1, 0, "cell boxes"); goto done; }
    for (i = 0; i < e.cells; ++i)
        for (k = 0; k < 3; ++k) {
            e.boxes[i].min[k] = d->cells[i].min[k] + 0.0f;
            e.boxes[i].max[k] = d->cells[i].max[k] + 0.0f;
        }
    for (k = 0; k < 3; ++k) {
        float *v = (float *)pvs__alloc_array(&e.a, 2 * (size_t)e.cells, sizeof(float));
        uint32_t n = 0;
        if (!v) { r = pvs__fail(err, PVS_ERROR_OUT_OF_MEMORY, -1, 0, "cell coordinate tables"); goto done; }
        e.values[k] = v;
        for (i = 0; i < e.cells; ++i) {
            v[2 * i] = e.boxes[i].min[k];
            v[2 * i + 1] = e.boxes[i].max[k];
        }
        qsort(v, 2 * (size_t)e.cells, sizeof(float), pvs__float_cmp);
        for (i = 0; i < 2 * e.cells; ++i)
            if (!n || v[i] != v[n - 1]) v[n++] = v[i];
        e.value_count[k] = n;
        e.index_bits[k] = pvs__bits_for(n - 1);
        {
            uint32_t widest = 0;
            for (i = 0; i < e.cells; ++i) {
                uint32_t ext = pvs__value_index(v, n, e.boxes[i].max[k]) - pvs__value_index(v, n, e.boxes[i].min[k]);
                if (ext > widest) widest = ext;
            }
            e.index_bits[3 + k] = pvs__bits_for(widest);
        }
    }
    index_bits_total = (size_t)(e.index_bits[0] + e.index_bits[1] + e.index_bits[2] + e.index_bits[3] + e.index_bits[4] + e.index_bits[5]) * e.cells;
    cell_bytes = PVS__CELL_HEAD + 4 * ((size_t)e.value_count[0] + e.value_count[1] + e.value_count[2]) + (index_bits_total + 7) / 8;

    /* the library's kD-tree over the cells finds base candidates (touching cells first); when big
       overlapping cells would be copied into too many leaves, a tree over the cells' centres instead.
       TREE is the compact look-up tree built further down. */
    {
        pvs_kdtree_desc td;
        uint32_t long_cells = 0;
        memset(&td, 0, sizeof(td));
        td.boxes = e.boxes;
        td.count = e.cells;
        td.allocator = e.a;
        { /* cells more than 16 times the lower-quartile extent on some axis cross many split planes */
            float *ext = (float *)pvs__alloc_array(&e.a, e.cells, sizeof(float)), med[3];
            if (!ext) { r = pvs__fail(err, PVS_ERROR_OUT_OF_MEMORY, -1, 0, "cell extents"); goto done; }
            for (k = 0; k < 3; ++k) {
                for (i = 0; i < e.cells; ++i) ext[i] = e.boxes[i].max[k] - e.boxes[i].min[k];
                qsort(ext, e.cells, sizeof(float), pvs__float_cmp);
                med[k] = ext[e.cells / 4]; /* the lower quartile: half the cells may be long */
            }
            for (i = 0; i < e.cells; ++i)
                for (k = 0; k < 3; ++k)
                    if (e.boxes[i].max[k] - e.boxes[i].min[k] > 16.0f * med[k]) {
                        ++long_cells;
                        break;
                    }
            pvs__free_array(&e.a, ext, e.cells, sizeof(float));
        }
        if (long_cells <= e.cells / 16) r = pvs_kdtree_create(&td, &e.tree, err);
        if (r == PVS_OK && (!e.tree || e.tree->item_count > 16u * e.cells)) {
            pvs_box *centres = (pvs_box *)pvs__alloc_array(&e.a, e.cells, sizeof(pvs_box));
            pvs_kdtree_destroy(e.tree);
            e.tree = NULL;
            if (!centres) { r = pvs__fail(err, PVS_ERROR_OUT_OF_MEMORY, -1, 0, "cell centres"); goto done; }
            for (i = 0; i < e.cells; ++i)
                for (k = 0; k < 3; ++k) centres[i].min[k] = centres[i].max[k] = 0.5f * e.boxes[i].min[k] + 0.5f * e.boxes[i].max[k]; /* no overflow */
            td.boxes = centres;
            r = pvs_kdtree_create(&td, &e.tree, err);
            pvs__free_array(&e.a, centres, e.cells, sizeof(pvs_box));
        }
        if (r != PVS_OK) goto done;
    }
    {
        pvs__tbuild tb;
        uint32_t *ids = (uint32_t *)pvs__alloc_array(&e.a, e.cells, sizeof(uint32_t)), leaves;
        memset(&tb, 0, sizeof(tb));
        tb.a = &e.a;
        tb.boxes = e.boxes;
        while (tb.depth < 20 && (e.cells >> tb.depth) > PVS__TREE_LEAF) ++tb.depth;
        leaves = 1u << tb.depth;
        tb.keys = (float *)pvs__alloc_array(&e.a, 2 * (size_t)e.cells, sizeof(float));
        tb.nodes = (uint32_t *)pvs__alloc_array(&e.a, leaves, sizeof(uint32_t));
        tb.leaf_start = (uint32_t *)pvs__alloc_array(&e.a, (size_t)leaves + 1, sizeof(uint32_t));
        for (k = 0; k < 3; ++k) tb.values[k] = e.values[k];
        tb.value_count = e.value_count;
        if (ids && tb.keys && tb.nodes && tb.leaf_start) {
            for (i = 0; i < e.cells; ++i) ids[i] = i;
            r = pvs__tree_node(&tb, ids, e.cells, 0, 0);
        } else {
            r = PVS_ERROR_OUT_OF_MEMORY;
        }
        if (r == PVS_OK) {
            uint8_t *t;
            tb.leaf_start[leaves] = (uint32_t)tb.item_bytes;
            e.tree_bytes = 5 * (size_t)(leaves - 1) + 4 * ((size_t)leaves + 1) + tb.item_bytes;
            e.tree_depth = tb.depth;
            e.tree_stream = t = (uint8_t *)pvs__alloc_array(&e.a, e.tree_bytes, 1);
            if (!t) {
                r = PVS_ERROR_OUT_OF_MEMORY;
            } else {
                /* split values, then leaf offsets, then axes; a node that passes everything left is
                   axis 0 at FLT_MAX (no finite point lies beyond it) */
                for (i = 0; i + 1 < leaves; ++i, t += 4)
                    pvs__putf32(t, (tb.nodes[i] & 3u) == 3u ? FLT_MAX : tb.values[tb.nodes[i] & 3u][tb.nodes[i] >> 2]);
                for (i = 0; i <= leaves; ++i, t += 4) pvs__put32(t, tb.leaf_start[i]);
                for (i = 0; i + 1 < leaves; ++i) *t++ = (uint8_t)((tb.nodes[i] & 3u) == 3u ? 0u : tb.nodes[i] & 3u);
                if (tb.item_bytes) memcpy(t, tb.items, tb.item_bytes);
            }
        }
        pvs__free_array(&e.a, ids, e.cells, sizeof(uint32_t));
        pvs__free_array(&e.a, tb.keys, 2 * (size_t)e.cells, sizeof(float));
        pvs__free_array(&e.a, tb.nodes, leaves, sizeof(uint32_t));
        pvs__free_array(&e.a, tb.leaf_start, (size_t)leaves + 1, sizeof(uint32_t));
        pvs__free_array(&e.a, tb.items, tb.item_capacity, 1);
        if (r != PVS_OK) { r = pvs__fail(err, r, -1, 0, "cell look-up tree"); goto done; }
    }

    /* RECS */
    e.tmp = (pvs_word *)pvs__alloc_array(&e.a, e.words, sizeof(pvs_word));
    e.ranks = (pvs_word *)pvs__alloc_array(&e.a, e.words, sizeof(pvs_word));
    if (!e.tmp || !e.ranks) { r = pvs__fail(err, PVS_ERROR_OUT_OF_MEMORY, -1, 0, "encoder bitset"); goto done; }
    r = pvs__encoder_bases(&e, max_chain, err);
    if (r != PVS_OK) goto done;
    for (i = 0; i < e.cells; ++i) keys += e.base[i] == PVS_NO_CELL;
    recs_size = pvs__encoder_records(&e, NULL);

    /* layout: header, table, META, CELL, TREE, RECS, [SHRD], [VOCC], each 8-aligned */
    sections = d->shard_count ? 5u : 4u;
    tags[0] = PVS__TAG_META; sz[0] = PVS__META_SIZE;
    tags[1] = PVS__TAG_CELL; sz[1] = cell_bytes;
    tags[2] = PVS__TAG_TREE; sz[2] = PVS__TREE_HEAD + e.tree_bytes;
    tags[3] = PVS__TAG_RECS; sz[3] = recs_size;
    tags[4] = PVS__TAG_SHRD; sz[4] = PVS__SHRD_SIZE;
    if (d->vocc_counts) { /* then VOCC */
        tags[sections] = PVS__VO_TAG;
        sz[sections++] = vocc_size;
    }
    total = pvs__align8(PVS__HEADER_SIZE + PVS__SECTION_ENTRY * (size_t)sections);
    for (k = 0; k < sections; ++k) {
        at[k] = total;
        total = pvs__align8(total + sz[k]);
    }
    if (total > 0xffffffffu) { r = pvs__fail(err, PVS_ERROR_COUNT_OVERFLOW, -1, 0, "the file would exceed 4 GiB"); goto done; }
    if (out_size) *out_size = total;
    if (!o) { /* a size query */
        pvs__ok(err);
        goto done;
    }
    if (capacity < total) {
        r = pvs__fail(err, PVS_ERROR_BUFFER_TOO_SMALL, -1, 0, "need %llu bytes, have %llu", (unsigned long long)total, (unsigned long long)capacity);
        goto done;
    }
    memset(o, 0, total);
    { /* META */
        uint8_t *m = o + at[0];
        pvs__put32(m + 0, e.cells);
        pvs__put32(m + 4, e.n);
        pvs__put32(m + 8, (uint32_t)d->method);
        pvs__putf32(m + 12, d->eps);
        pvs__put32(m + 16, d->up_axis);
        pvs__put32(m + 20, max_chain);
        pvs__put32(m + 24, keys);
    }
    { /* CELL */
        uint8_t *c = o + at[1], *v, *bits;
        uint64_t pos = 0;
        for (k = 0; k < 3; ++k) pvs__put32(c + 4 * k, e.value_count[k]);
        for (k = 0; k < 6; ++k) c[12 + k] = (uint8_t)e.index_bits[k];
        v = c + PVS__CELL_HEAD;
        for (k = 0; k < 3; ++k)
            for (i = 0; i < e.value_count[k]; ++i, v += 4) pvs__putf32(v, e.values[k][i]);
        bits = v;
        for (i = 0; i < e.cells; ++i) {
            uint32_t lo[3];
            for (k = 0; k < 3; ++k) {
                lo[k] = pvs__value_index(e.values[k], e.value_count[k], e.boxes[i].min[k]);
                pvs__put_bits(bits, pos, lo[k], e.index_bits[k]);
                pos += e.index_bits[k];
            }
            for (k = 0; k < 3; ++k) {
                pvs__put_bits(bits, pos, pvs__value_index(e.values[k], e.value_count[k], e.boxes[i].max[k]) - lo[k], e.index_bits[3 + k]);
                pos += e.index_bits[3 + k];
            }
        }
    }
    { /* TREE */
        pvs__put32(o + at[2], e.tree_depth);
        memcpy(o + at[2] + PVS__TREE_HEAD, e.tree_stream, e.tree_bytes);
    }
    (void)pvs__encoder_records(&e, o + at[3]);
    if (d->shard_count) {
        uint8_t *s = o + at[4];
        pvs__put32(s + 0, d->shard_index);
        pvs__put32(s + 4, d->shard_count);
        pvs__put32(s + 8, d->total_cell_count);
    }
    if (d->vocc_counts)
        pvs__vo_section_write(o + at[sections - 1], (d->vocc_flags & PVS_VOCC_ONLY) ? 1u : 0u, d->vocc_base, d->vocc_height_step, d->cell_count,
                              d->vocc_counts, d->vocc_scales, d->virtual_occluders, d->vocc_stride);
    /* header and section table */
    memcpy(o, "PVS\x1a", 4);
    pvs__put32(o + 4, PVS_FORMAT_VERSION);
    pvs__put32(o + 8, (uint32_t)total);
    pvs__put32(o + 12, sections);
    pvs__put32(o + 16, d->flags);
    for (k = 0; k < sections; ++k) {
        uint8_t *en = o + PVS__HEADER_SIZE + PVS__SECTION_ENTRY * k;
        pvs__put32(en + 0, tags[k]);
        pvs__put32(en + 4, (uint32_t)at[k]);
        pvs__put32(en + 8, (uint32_t)sz[k]);
        pvs__put32(en + 12, pvs__crc32(0, o + at[k], sz[k]));
    }
    {
        uint32_t crc = pvs__crc32(0, o, 20);
        crc = pvs__crc32(crc, o + PVS__HEADER_SIZE, (size_t)sections * PVS__SECTION_ENTRY);
        pvs__put32(o + 20, crc);
    }
    pvs__ok(err);
done:
    pvs__encoder_free(&e);
    return r;
}

/* ---- reader ---- */

/* A record located by the reader. Only for files that passed pvs_file_open. */
typedef struct pvs__rec {
    const uint8_t *start, *body, *end; /* body: the removed ranks of a delta, else the added ids */
    uint32_t coding, depth, base;      /* coding of the added ids */
    uint32_t removed_coding, base_size;
} pvs__rec;

PVS__STATIC void pvs__record_at(const pvs_file *f, uint32_t cell, pvs__rec *r) {
    const uint8_t *recs = f->private_.records, *p;
    uint32_t j, len, head, zz;
    p = recs + pvs__get32(recs + 4 * (size_t)(cell / PVS__BLOCK));
    for (j = cell - cell % PVS__BLOCK; j < cell; ++j) {
        p = pvs__skip_varint(p, &len);
        p += len;
    }
    r->start = p;
    p = pvs__skip_varint(p, &len);
    r->end = p + len;
    p = pvs__skip_varint(p, &head);
    r->coding = head & 3u;
    r->depth = head >> 2;
    r->base = PVS_NO_CELL;
    if (r->depth) {
        p = pvs__skip_varint(p, &zz);
        r->base = (uint32_t)((int64_t)cell - pvs__unzigzag(zz));
        r->removed_coding = *p++;
        p = pvs__skip_varint(p, &r->base_size);
    }
    r->body = p;
}

/* Applies a record to bits: a key's ids are added (bits start empty); a delta first removes its
   ranks (counted in the base's PVS, which bits holds), then adds its ids. Changes go to fn. Only for
   records of an opened file. */
PVS__STATIC void pvs__record_apply(const pvs_file *f, const pvs__rec *r, pvs_word *bits, pvs_change_fn fn, void *user) {
    pvs__sink s;
    size_t used = 0, bad;
    const uint8_t *p = r->body;
    memset(&s, 0, sizeof(s));
    s.bits = bits;
    s.words = (uint32_t)PVS_BITSET_WORDS(f->object_count);
    s.fn = fn;
    s.user = user;
    if (r->depth) {
        s.action = PVS__SET_REMOVE_RANKS;
        (void)pvs__set_apply(p, r->end, r->removed_coding, r->base_size, &s, &used, &bad);
        p += used;
    }
    s.action = PVS__SET_ADD;
    (void)pvs__set_apply(p, r->end, r->coding, f->object_count, &s, &used, &bad);
}

PVS__STATIC pvs_result pvs__open_cells(pvs_file *f, const uint8_t *base, const uint8_t *c, uint32_t size, pvs_error *err) {
    uint64_t off = (uint64_t)(c - base), need, nbits, pos = 0;
    uint32_t k, i, total = 0;
    const uint8_t *v;
    if (size < PVS__CELL_HEAD) return pvs__fail(err, PVS_ERROR_BAD_SECTION, -1, off, "CELL has %u bytes, fewer than its 20-byte head", size);
    for (k = 0; k < 3; ++k) {
        uint32_t n = pvs__get32(c + 4 * k);
        if (n == 0 || n > 2 * (uint64_t)f->cell_count)
            return pvs__fail(err, PVS_ERROR_BAD_SECTION, -1, off + 4 * k, "CELL: %u coordinates on axis %u for %u cells", n, k, f->cell_count);
        if (c[12 + k] != pvs__bits_for(n - 1))
            return pvs__fail(err, PVS_ERROR_BAD_SECTION, -1, off + 12 + k, "CELL: index width %u on axis %u, %u values need %u", c[12 + k], k, n,
                             pvs__bits_for(n - 1));
        if (c[15 + k] > pvs__bits_for(n - 1))
            return pvs__fail(err, PVS_ERROR_BAD_SECTION, -1, off + 15 + k, "CELL: extent width %u on axis %u exceeds %u", c[15 + k], k,
                             pvs__bits_for(n - 1));
        f->private_.value_count[k] = n;
        f->private_.index_bits[k] = c[12 + k];
        f->private_.index_bits[3 + k] = c[15 + k];
        total += n;
    }
    if (c[18] || c[19]) return pvs__fail(err, PVS_ERROR_BAD_SECTION, -1, off + 18, "CELL: reserved bytes are not zero");
    f->private_.cell_bits = f->private_.index_bits[0] + f->private_.index_bits[1] + f->private_.index_bits[2] + f->private_.index_bits[3] +
                            f->private_.index_bits[4] + f->private_.index_bits[5];
    nbits = (uint64_t)f->private_.cell_bits * f->cell_count;
    need = PVS__CELL_HEAD + 4 * (uint64_t)total + (nbits + 7) / 8;
    if (need != size)
        return pvs__fail(err, PVS_ERROR_BAD_SECTION, -1, off, "CELL has %u bytes, its tables and indices need %llu", size, (unsigned long long)need);
    v = c + PVS__CELL_HEAD;
    for (k = 0; k < 3; ++k) {
        f->private_.values[k] = v;
        for (i = 0; i < f->private_.value_count[k]; ++i, v += 4) {
            float x = pvs__getf32(v);
            if (!pvs__finite(x) || pvs__get32(v) == 0x80000000u || (i && !(pvs__getf32(v - 4) < x)))
                return pvs__fail(err, PVS_ERROR_BAD_CELL, -1, (uint64_t)(v - base),
                                 "CELL: coordinate %u on axis %u is not finite, is -0 or does not ascend", i, k);
        }
    }
    f->private_.indices = v;
    f->private_.index_bytes = (size_t)((nbits + 7) / 8);
    for (i = 0; i < f->cell_count; ++i) {
        uint32_t idx[6];
        for (k = 0; k < 6; ++k) {
            idx[k] = pvs__get_bits(v, pos, f->private_.index_bits[k]);
            pos += f->private_.index_bits[k];
        }
        for (k = 0; k < 3; ++k)
            if ((uint64_t)idx[k] + idx[k + 3] >= f->private_.value_count[k])
                return pvs__fail(err, PVS_ERROR_BAD_CELL, i, (uint64_t)(v - base) + pos / 8, "cell %u: coordinate index %u + %u out of range on axis %u",
                                 i, idx[k], idx[k + 3], k);
    }
    if ((nbits & 7u) && (v[nbits / 8] >> (nbits & 7u)))
        return pvs__fail(err, PVS_ERROR_BAD_SECTION, -1, (uint64_t)(v - base) + nbits / 8, "CELL: unused index bits are not zero");
    return PVS_OK;
}

/* The TREE section: u32 depth D (0..24), u32 zero, f32 splits[2^D - 1], u32 leaf offsets[2^D + 1]
   into the items, u8 axes[2^D - 1] (0..2), then the items: per leaf its
   ascending cell ids, gap-coded varints, filling its offset range exactly. Splits and axes sit in
   separate arrays so a look-up level costs one dependent load. */
PVS__STATIC pvs_result pvs__open_tree(pvs_file *f, const uint8_t *base, const uint8_t *t, uint32_t size, pvs_error *err) {
    uint64_t off = (uint64_t)(t - base), need;
    uint32_t depth, inner, leaves, i;
    const uint8_t *nodes, *starts, *items;
    if (size < PVS__TREE_HEAD) return pvs__fail(err, PVS_ERROR_BAD_TREE, -1, off, "TREE has %u bytes, fewer than its 8-byte head", size);
    depth = pvs__get32(t);
    if (depth > PVS__TREE_MAX_DEPTH) return pvs__fail(err, PVS_ERROR_BAD_TREE, -1, off, "TREE depth %u > %u", depth, PVS__TREE_MAX_DEPTH);
    if (pvs__get32(t + 4)) return pvs__fail(err, PVS_ERROR_BAD_TREE, -1, off + 4, "TREE reserved field is not zero");
    leaves = 1u << depth;
    inner = leaves - 1u;
    need = PVS__TREE_HEAD + 5 * (uint64_t)inner + 4 * ((uint64_t)leaves + 1);
    if (need > size) return pvs__fail(err, PVS_ERROR_BAD_TREE, -1, off, "TREE has %u bytes, depth %u needs %llu before its items", size, depth,
                                      (unsigned long long)need);
    nodes = t + PVS__TREE_HEAD;
    starts = nodes + 4 * (size_t)inner;
    items = starts + 4 * ((size_t)leaves + 1) + inner;
    for (i = 0; i < inner; ++i) {
        uint8_t axis = starts[4 * ((size_t)leaves + 1) + i];
        if (axis > 2u || !pvs__finite(pvs__getf32(nodes + 4 * (size_t)i)))
            return pvs__fail(err, PVS_ERROR_BAD_TREE, i, off + PVS__TREE_HEAD + 4 * (uint64_t)i, "TREE node %u: axis %u or split not finite", i, axis);
    }
    if (pvs__get32(starts) != 0 || pvs__get32(starts + 4 * (size_t)leaves) != size - need)
        return pvs__fail(err, PVS_ERROR_BAD_TREE, -1, (uint64_t)(starts - base), "TREE leaf offsets do not span its items");
    for (i = 0; i < leaves; ++i) {
        uint32_t lo = pvs__get32(starts + 4 * (size_t)i), hi = pvs__get32(starts + 4 * (size_t)i + 4);
        const uint8_t *p = items + lo, *end = items + hi;
        uint64_t id = 0;
        int first = 1;
        if (hi < lo || hi > size - need)
            return pvs__fail(err, PVS_ERROR_BAD_TREE, i, (uint64_t)(starts - base) + 4 * (uint64_t)i, "TREE leaf %u offsets do not ascend", i);
        while (p < end) {
            uint32_t g;
            size_t used = pvs__get_varint(p, end, &g);
            if (!used) return pvs__fail(err, PVS_ERROR_BAD_TREE, i, (uint64_t)(p - base), "TREE leaf %u: bad cell id", i);
            id = first ? g : id + 1u + g;
            first = 0;
            if (id >= f->cell_count)
                return pvs__fail(err, PVS_ERROR_BAD_TREE, i, (uint64_t)(p - base), "TREE leaf %u names cell %llu of %u", i, (unsigned long long)id,
                                 f->cell_count);
            p += used;
        }
    }
    f->private_.tree = nodes;
    f->private_.tree_depth = depth;
    return PVS_OK;
}

/* Records: first every record's own structure, then, with every record known to be well formed, the
   chains: a delta's base must have depth one less, so depths fall strictly along a chain, which
   therefore ends at a key within max_chain steps and cannot cycle. Linear in the section size. */
PVS__STATIC pvs_result pvs__open_records(pvs_file *f, const uint8_t *base, const uint8_t *rs, uint32_t size, pvs_error *err) {
    uint64_t off = (uint64_t)(rs - base);
    uint32_t blocks = (f->cell_count + PVS__BLOCK - 1) / PVS__BLOCK, b, keys = 0, i;
    if ((uint64_t)4 * (blocks + 1) > size) return pvs__fail(err, PVS_ERROR_BAD_SECTION, -1, off, "RECS is too small for %u block offsets", blocks + 1);
    if (pvs__get32(rs) != 4 * (blocks + 1)) return pvs__fail(err, PVS_ERROR_BAD_RECORD, 0, off, "block 0 does not start after the offset table");
    if (pvs__get32(rs + 4 * (size_t)blocks) != size)
        return pvs__fail(err, PVS_ERROR_BAD_RECORD, -1, off + 4 * (uint64_t)blocks, "the last block offset is not the section size");
    for (b = 0; b < blocks; ++b) {
        uint32_t lo = pvs__get32(rs + 4 * (size_t)b), hi = pvs__get32(rs + 4 * (size_t)b + 4), cell;
        const uint8_t *p = rs + lo, *end = rs + hi;
        if (hi < lo || hi > size) return pvs__fail(err, PVS_ERROR_BAD_RECORD, -1, off + 4 * (uint64_t)b, "block %u offsets do not ascend", b);
        for (cell = b * PVS__BLOCK; cell < f->cell_count && cell < (b + 1) * PVS__BLOCK; ++cell) {
            uint32_t len, head, zz, depth;
            const uint8_t *rend;
            size_t used = pvs__get_varint(p, end, &len), bad = 0;
            pvs_result r;
            if (!used || len > (size_t)(end - p) - used)
                return pvs__fail(err, PVS_ERROR_BAD_RECORD, cell, (uint64_t)(p - base), "record of cell %u: bad length", cell);
            p += used;
            rend = p + len;
            used = pvs__get_varint(p, rend, &head);
            if (!used) return pvs__fail(err, PVS_ERROR_BAD_RECORD, cell, (uint64_t)(p - base), "record of cell %u: bad head", cell);
            p += used;
            depth = head >> 2;
            if (depth > f->max_chain)
                return pvs__fail(err, PVS_ERROR_BAD_CHAIN, cell, (uint64_t)(p - base), "cell %u: chain depth %u > %u", cell, depth, f->max_chain);
            if (depth) {
                int64_t bc;
                used = pvs__get_varint(p, rend, &zz);
                if (!used) return pvs__fail(err, PVS_ERROR_BAD_RECORD, cell, (uint64_t)(p - base), "record of cell %u: bad base", cell);
                bc = (int64_t)cell - pvs__unzigzag(zz);
                if (bc < 0 || bc >= (int64_t)f->cell_count || bc == (int64_t)cell)
                    return pvs__fail(err, PVS_ERROR_BAD_CHAIN, cell, (uint64_t)(p - base), "cell %u: base %lld is itself or no cell", cell, (long long)bc);
                p += used;
            } else {
                ++keys;
            }
            {
                pvs__sink check;
                size_t body = 0;
                memset(&check, 0, sizeof(check));
                if (depth) { /* the removed ranks: coding byte, base PVS size, ranks below it */
                    uint32_t m;
                    if (p >= rend || *p > 3u) return pvs__fail(err, PVS_ERROR_BAD_RECORD, cell, (uint64_t)(p - base), "record of cell %u: bad coding", cell);
                    used = pvs__get_varint(p + 1, rend, &m);
                    if (!used || m > f->object_count)
                        return pvs__fail(err, PVS_ERROR_BAD_RECORD, cell, (uint64_t)(p - base), "record of cell %u: bad base size", cell);
                    r = pvs__set_apply(p + 1 + used, rend, *p, m, &check, &body, &bad);
                    if (r != PVS_OK) return pvs__fail(err, r, cell, (uint64_t)(p + 1 + used - base) + bad, "record of cell %u (removed)", cell);
                    p += 1 + used + body;
                }
                r = pvs__set_apply(p, rend, head & 3u, f->object_count, &check, &body, &bad);
                if (r != PVS_OK) return pvs__fail(err, r, cell, (uint64_t)(p - base) + bad, "record of cell %u", cell);
                if (p + body != rend)
                    return pvs__fail(err, PVS_ERROR_BAD_RECORD, cell, (uint64_t)(p + body - base), "record of cell %u: bytes after its sets", cell);
            }
            p = rend;
        }
        if (p != end) return pvs__fail(err, PVS_ERROR_BAD_RECORD, -1, (uint64_t)(p - base), "block %u has bytes after its last record", b);
    }
    if (keys != f->key_count)
        return pvs__fail(err, PVS_ERROR_BAD_HEADER, -1, 0, "META says %u key cells, the records have %u", f->key_count, keys);
    for (i = 0; i < f->cell_count; ++i) {
        pvs__rec r, rb;
        pvs__record_at(f, i, &r);
        if (!r.depth) continue;
        pvs__record_at(f, r.base, &rb);
        if (rb.depth + 1 != r.depth)
            return pvs__fail(err, PVS_ERROR_BAD_CHAIN, i, (uint64_t)(r.start - base), "cell %u: depth %u, its base %u has depth %u", i, r.depth,
                             r.base, rb.depth);
    }
    return PVS_OK;
}

PVS_API pvs_result pvs_file_open(const void *data, size_t size, pvs_file *f, pvs_error *err) {
    const uint8_t *p = (const uint8_t *)data;
    uint32_t count, i, j, crc;
    const uint8_t *meta = NULL, *cells = NULL, *tree = NULL, *recs = NULL, *shrd = NULL, *vocc = NULL;
    uint32_t meta_size = 0, cells_size = 0, tree_size = 0, recs_size = 0, shrd_size = 0, vocc_size = 0;
    pvs_result r;
    if (!f) return pvs__fail(err, PVS_ERROR_INVALID_ARGUMENT, -1, 0, "file must not be NULL");
    memset(f, 0, sizeof(*f));
    if (!p && size) return pvs__fail(err, PVS_ERROR_INVALID_ARGUMENT, -1, 0, "data is NULL");
    if (size < 4 || memcmp(p, "PVS\x1a", 4) != 0)
        return pvs__fail(err, size < 4 ? PVS_ERROR_TRUNCATED : PVS_ERROR_BAD_MAGIC, -1, 0, "not a .pvs file (magic)");
    if (size < PVS__HEADER_SIZE) return pvs__fail(err, PVS_ERROR_TRUNCATED, -1, size, "the header needs 32 bytes, have %llu", (unsigned long long)size);
    if (pvs__get32(p + 4) != PVS_FORMAT_VERSION)
        return pvs__fail(err, PVS_ERROR_BAD_VERSION, -1, 4, "format version %u, this reader knows %d", pvs__get32(p + 4), PVS_FORMAT_VERSION);
    if (pvs__get32(p + 8) != size) {
        pvs_result code = pvs__get32(p + 8) > size ? PVS_ERROR_TRUNCATED : PVS_ERROR_BAD_HEADER;
        return pvs__fail(err, code, -1, 8, "the header says %u bytes, the buffer has %llu", pvs__get32(p + 8), (unsigned long long)size);
    }
    count = pvs__get32(p + 12);
    if (count == 0 || count > PVS__MAX_SECTIONS)
        return pvs__fail(err, PVS_ERROR_BAD_HEADER, -1, 12, "section count %u is not in 1..%u", count, PVS__MAX_SECTIONS);
    if (PVS__HEADER_SIZE + (size_t)count * PVS__SECTION_ENTRY > size)
        return pvs__fail(err, PVS_ERROR_TRUNCATED, -1, PVS__HEADER_SIZE, "the section table runs past the end");
    crc = pvs__crc32(0, p, 20);
    crc = pvs__crc32(crc, p + PVS__HEADER_SIZE, (size_t)count * PVS__SECTION_ENTRY);
    if (crc != pvs__get32(p + 20)) return pvs__fail(err, PVS_ERROR_CHECKSUM, -1, 20, "header checksum");
    if (pvs__get32(p + 24) || pvs__get32(p + 28)) return pvs__fail(err, PVS_ERROR_BAD_HEADER, -1, 24, "reserved header bytes are not zero");
    for (i = 0; i < count; ++i) {
        const uint8_t *e = p + PVS__HEADER_SIZE + PVS__SECTION_ENTRY * (size_t)i;
        uint32_t tag = pvs__get32(e), off = pvs__get32(e + 4), sz = pvs__get32(e + 8);
        uint64_t at = PVS__HEADER_SIZE + PVS__SECTION_ENTRY * (uint64_t)i;
        if ((off & 7u) || off < PVS__HEADER_SIZE + count * PVS__SECTION_ENTRY)
            return pvs__fail(err, PVS_ERROR_BAD_SECTION, i, at, "section %u: offset %u is misaligned or inside the header", i, off);
        if ((uint64_t)off + sz > size)
            return pvs__fail(err, PVS_ERROR_TRUNCATED, i, at, "section %u: bytes %u..%llu run past the end", i, off, (unsigned long long)off + sz);
        for (j = 0; j < i; ++j) {
            const uint8_t *e2 = p + PVS__HEADER_SIZE + PVS__SECTION_ENTRY * (size_t)j;
            uint32_t off2 = pvs__get32(e2 + 4), sz2 = pvs__get32(e2 + 8);
            if (pvs__get32(e2) == tag)
                return pvs__fail(err, PVS_ERROR_BAD_SECTION, i, at, "section %u repeats the tag of section %u", i, j);
            if (off < off2 + sz2 && off2 < off + sz)
                return pvs__fail(err, PVS_ERROR_BAD_SECTION, i, at, "sections %u and %u overlap", j, i);
        }
        if (pvs__crc32(0, p + off, sz) != pvs__get32(e + 12))
            return pvs__fail(err, PVS_ERROR_CHECKSUM, i, off, "section %u checksum", i);
        if (tag == PVS__TAG_META) { meta = p + off; meta_size = sz; }
        else if (tag == PVS__TAG_CELL) { cells = p + off; cells_size = sz; }
        else if (tag == PVS__TAG_TREE) { tree = p + off; tree_size = sz; }
        else if (tag == PVS__TAG_RECS) { recs = p + off; recs_size = sz; }
        else if (tag == PVS__TAG_SHRD) { shrd = p + off; shrd_size = sz; }
        else if (tag == PVS__VO_TAG) { vocc = p + off; vocc_size = sz; }
    }
    {
        /* bytes outside the header, the table and the sections (alignment padding) must be zero,
           so that every byte of a valid file is either checksummed or fixed */
        uint32_t order[PVS__MAX_SECTIONS], k;
        size_t pos = PVS__HEADER_SIZE + (size_t)count * PVS__SECTION_ENTRY;
        for (i = 0; i < count; ++i) { /* insertion sort by offset; count <= 64 */
            uint32_t off = pvs__get32(p + PVS__HEADER_SIZE + PVS__SECTION_ENTRY * (size_t)i + 4);
            for (j = i; j > 0 && pvs__get32(p + PVS__HEADER_SIZE + PVS__SECTION_ENTRY * (size_t)order[j - 1] + 4) > off; --j)
                order[j] = order[j - 1];
            order[j] = i;
        }
        for (k = 0; k <= count; ++k) {
            const uint8_t *e = k < count ? p + PVS__HEADER_SIZE + PVS__SECTION_ENTRY * (size_t)order[k] : NULL;
            size_t next = e ? pvs__get32(e + 4) : size;
            for (; pos < next; ++pos)
                if (p[pos]) return pvs__fail(err, PVS_ERROR_BAD_SECTION, -1, pos, "padding byte %llu is not zero", (unsigned long long)pos);
            if (e && (size_t)pvs__get32(e + 4) + pvs__get32(e + 8) > pos) pos = (size_t)pvs__get32(e + 4) + pvs__get32(e + 8);
        }
    }
    if (!meta || !cells || !tree || !recs)
        return pvs__fail(err, PVS_ERROR_BAD_SECTION, -1, 0, "missing required section %s",
                         !meta ? "META" : !cells ? "CELL" : !tree ? "TREE" : "RECS");
    if (meta_size != PVS__META_SIZE) return pvs__fail(err, PVS_ERROR_BAD_SECTION, -1, (uint64_t)(meta - p), "META has %u bytes, not 32", meta_size);
    f->cell_count = pvs__get32(meta);
    f->object_count = pvs__get32(meta + 4);
    f->method = (pvs_method)pvs__get32(meta + 8);
    f->eps = pvs__getf32(meta + 12);
    f->up_axis = pvs__get32(meta + 16);
    f->max_chain = pvs__get32(meta + 20);
    f->key_count = pvs__get32(meta + 24);
    {
        uint64_t mo = (uint64_t)(meta - p);
        if (f->cell_count == 0) return pvs__fail(err, PVS_ERROR_BAD_HEADER, -1, mo, "cell count 0");
        if (f->cell_count > 0x3fffffffu) return pvs__fail(err, PVS_ERROR_COUNT_OVERFLOW, -1, mo, "cell count %u > 2^30 - 1", f->cell_count);
        if (f->object_count == 0) return pvs__fail(err, PVS_ERROR_BAD_HEADER, -1, mo + 4, "object count 0");
        if (f->object_count == 0xffffffffu) return pvs__fail(err, PVS_ERROR_COUNT_OVERFLOW, -1, mo + 4, "object count 2^32 - 1");
        if (pvs__get32(meta + 8) >= (uint32_t)PVS_METHOD_COUNT) return pvs__fail(err, PVS_ERROR_BAD_HEADER, -1, mo + 8, "unknown method %u", pvs__get32(meta + 8));
        if (!pvs__finite(f->eps) || f->eps < 0.0f) return pvs__fail(err, PVS_ERROR_BAD_HEADER, -1, mo + 12, "eps is not a finite number >= 0");
        if (f->up_axis != 1 && f->up_axis != 2) return pvs__fail(err, PVS_ERROR_BAD_HEADER, -1, mo + 16, "up axis %u", f->up_axis);
        if (f->max_chain == 0 || f->max_chain > PVS_MAX_CHAIN)
            return pvs__fail(err, PVS_ERROR_BAD_HEADER, -1, mo + 20, "chain bound %u is not in 1..%u", f->max_chain, PVS_MAX_CHAIN);
        if (f->key_count == 0 || f->key_count > f->cell_count)
            return pvs__fail(err, PVS_ERROR_BAD_HEADER, -1, mo + 24, "%u key cells of %u", f->key_count, f->cell_count);
        if (pvs__get32(meta + 28)) return pvs__fail(err, PVS_ERROR_BAD_HEADER, -1, mo + 28, "reserved META bytes are not zero");
    }
    if (shrd) {
        uint64_t so = (uint64_t)(shrd - p);
        if (shrd_size != PVS__SHRD_SIZE) return pvs__fail(err, PVS_ERROR_BAD_SECTION, -1, so, "SHRD has %u bytes, not 16", shrd_size);
        f->shard_index = pvs__get32(shrd);
        f->shard_count = pvs__get32(shrd + 4);
        f->total_cell_count = pvs__get32(shrd + 8);
        if (f->shard_count < 2 || f->shard_index >= f->shard_count || f->total_cell_count > 0x3fffffffu || pvs__get32(shrd + 12) ||
            f->cell_count != (f->total_cell_count - f->shard_index + f->shard_count - 1) / f->shard_count)
            return pvs__fail(err, PVS_ERROR_BAD_HEADER, -1, so, "SHRD: shard %u of %u cannot hold %u of %u cells", f->shard_index, f->shard_count,
                             f->cell_count, f->total_cell_count);
    }
    /* records first: each takes at least 3 bytes, so a valid RECS bounds the cell count by the file
       size, and the cell checks after it stay linear in the file (a cell index can be 0 bits wide) */
    f->private_.records = recs;
    f->private_.records_size = recs_size;
    f->private_.block_count = (f->cell_count + PVS__BLOCK - 1) / PVS__BLOCK;
    r = pvs__open_records(f, p, recs, recs_size, err);
    if (r == PVS_OK) r = pvs__open_cells(f, p, cells, cells_size, err);
    if (r == PVS_OK) r = pvs__open_tree(f, p, tree, tree_size, err);
    if (r == PVS_OK && vocc) r = pvs__vo_open_section(f, p, vocc, vocc_size, err);
    if (r != PVS_OK) {
        memset(f, 0, sizeof(*f));
        return r;
    }
    f->data = p;
    f->size = size;
    f->version = PVS_FORMAT_VERSION;
    f->flags = pvs__get32(p + 16);
    pvs__ok(err);
    return PVS_OK;
}

PVS_API void pvs_file_record_info(const pvs_file *f, uint32_t cell, pvs_record_info *info) {
    pvs__rec r;
    PVS_ASSERT(f && info && cell < f->cell_count);
    pvs__record_at(f, cell, &r);
    info->base = r.base;
    info->depth = r.depth;
    info->coding = r.coding;
    info->bytes = (uint32_t)(r.end - r.start);
    info->base_size = r.depth ? r.base_size : 0;
}

// >>runtime
/* ---------------------------------------------------------------------------------------------- */
/* runtime: cell look-up through the stored kD-tree, decoding, the cursor; no allocation          */
/* ---------------------------------------------------------------------------------------------- */

/* A cell's coordinate indices: min then max per axis. One 64-bit read holds all six fields when
   they fit (the usual case). */
PVS__STATIC void pvs__cell_indices(const pvs_file *f, uint32_t c, uint32_t idx[6]) {
    uint64_t pos = (uint64_t)c * f->private_.cell_bits;
    int k;
    if (f->private_.cell_bits <= 56 && (size_t)(pos >> 3) + 8 <= f->private_.index_bytes) {
        uint64_t w = pvs__load64(f->private_.indices + (size_t)(pos >> 3)) >> (pos & 7u);
        for (k = 0; k < 6; ++k) {
            uint32_t bits = f->private_.index_bits[k];
            idx[k] = (uint32_t)(w & (((uint64_t)1 << bits) - 1u));
            w >>= bits;
        }
    } else {
        for (k = 0; k < 6; ++k) {
            idx[k] = pvs__get_bits(f->private_.indices, pos, f->private_.index_bits[k]);
            pos += f->private_.index_bits[k];
        }
    }
    for (k = 0; k < 3; ++k) idx[k + 3] += idx[k];
}

PVS_API pvs_box pvs_file_cell_box(const pvs_file *f, uint32_t cell) {
    pvs_box b;
    uint32_t idx[6];
    int k;
    PVS_ASSERT(cell < f->cell_count);
    pvs__cell_indices(f, cell, idx);
    for (k = 0; k < 3; ++k) {
        b.min[k] = pvs__getf32(f->private_.values[k] + 4 * (size_t)idx[k]);
        b.max[k] = pvs__getf32(f->private_.values[k] + 4 * (size_t)idx[k + 3]);
    }
    return b;
}

/* Does cell `c` contain p? The fast path reads the six fields from one 64-bit word and compares
   axis by axis (the look-up's inner loop). */
PVS__STATIC int pvs__cell_contains(const pvs_file *f, uint32_t c, const float p[3]) {
    uint32_t idx[6];
    int k;
    uint64_t pos = (uint64_t)c * f->private_.cell_bits;
    if (f->private_.cell_bits <= 56 && (size_t)(pos >> 3) + 8 <= f->private_.index_bytes) {
        const uint32_t *wb = f->private_.index_bits;
        uint64_t w = pvs__load64(f->private_.indices + (size_t)(pos >> 3)) >> (pos & 7u);
        uint32_t lo0, lo1, lo2, e0, e1;
        lo0 = (uint32_t)(w & (((uint64_t)1 << wb[0]) - 1u)); w >>= wb[0];
        lo1 = (uint32_t)(w & (((uint64_t)1 << wb[1]) - 1u)); w >>= wb[1];
        lo2 = (uint32_t)(w & (((uint64_t)1 << wb[2]) - 1u)); w >>= wb[2];
        e0 = (uint32_t)(w & (((uint64_t)1 << wb[3]) - 1u)); w >>= wb[3];
        if (p[0] < pvs__getf32(f->private_.values[0] + 4 * (size_t)lo0) || p[0] > pvs__getf32(f->private_.values[0] + 4 * (size_t)(lo0 + e0))) return 0;
        e1 = (uint32_t)(w & (((uint64_t)1 << wb[4]) - 1u)); w >>= wb[4];
        if (p[1] < pvs__getf32(f->private_.values[1] + 4 * (size_t)lo1) || p[1] > pvs__getf32(f->private_.values[1] + 4 * (size_t)(lo1 + e1))) return 0;
        e0 = (uint32_t)(w & (((uint64_t)1 << wb[5]) - 1u));
        return !(p[2] < pvs__getf32(f->private_.values[2] + 4 * (size_t)lo2) || p[2] > pvs__getf32(f->private_.values[2] + 4 * (size_t)(lo2 + e0)));
    }
    pvs__cell_indices(f, c, idx);
    for (k = 0; k < 3; ++k)
        if (p[k] < pvs__getf32(f->private_.values[k] + 4 * (size_t)idx[k]) || p[k] > pvs__getf32(f->private_.values[k] + 4 * (size_t)idx[k + 3]))
            return 0;
    return 1;
}

/* Point location in the stored tree: p < split left, p > split right, p == split both (pending
   subtrees on a stack no deeper than the tree); in a leaf the first cell containing p is its lowest. */
PVS_API uint32_t pvs_file_find_cell(const pvs_file *f, const float p[3]) {
    uint32_t stack[PVS__TREE_MAX_DEPTH + 1], depth = 0, best = PVS_NO_CELL, k = 0, d, inner;
    const uint8_t *nodes, *starts, *axes, *items;
    float p0, p1, p2;
    if (!f || !p || !f->data || !pvs__finite(p[0]) || !pvs__finite(p[1]) || !pvs__finite(p[2])) return PVS_NO_CELL;
    p0 = p[0];
    p1 = p[1];
    p2 = p[2];
    d = f->private_.tree_depth;
    inner = (1u << d) - 1u;
    nodes = f->private_.tree;
    starts = nodes + 4 * (size_t)inner;
    axes = starts + 4 * ((size_t)inner + 2);
    items = axes + inner;
    for (;;) {
        if (k < inner) {
            /* the children of k sit side by side: both are loaded while k's comparison runs, so a
               level costs one load latency, not a load plus a compare (a branch-free descent) */
            float v = pvs__getf32(nodes + 4 * (size_t)k);
            uint32_t axis = axes[k];
            for (;;) {
                uint32_t l = 2 * k + 1, right;
                float x = axis == 0 ? p0 : axis == 1 ? p1 : p2, vl = 0.0f, vr = 0.0f;
                uint32_t al = 0, ar = 0;
                if (l < inner) {
                    vl = pvs__getf32(nodes + 4 * (size_t)l);
                    vr = pvs__getf32(nodes + 4 * (size_t)l + 4);
                    al = axes[l];
                    ar = axes[l + 1];
                }
                if (x == v) stack[depth++] = l + 1; /* rare: both sides */
                right = (uint32_t)(x > v);
                k = l + right;
                if (k >= inner) break;
                v = right ? vr : vl;
                axis = right ? ar : al;
            }
        }
        {
            const uint8_t *q = items + pvs__get32(starts + 4 * (size_t)(k - inner)), *end = items + pvs__get32(starts + 4 * (size_t)(k - inner) + 4);
            uint32_t id = 0, g;
            int first = 1;
            while (q < end) {
                q = pvs__skip_varint(q, &g);
                id = first ? g : id + 1u + g;
                first = 0;
                if (id >= best) break;
                if (pvs__cell_contains(f, id, p)) {
                    best = id;
                    break;
                }
            }
        }
        if (!depth) break;
        k = stack[--depth];
    }
    return best;
}

PVS__STATIC void pvs__file_decode(const pvs_file *f, uint32_t cell, pvs_word *bits, size_t word_count) {
    uint32_t chain[PVS_MAX_CHAIN + 1], n = 0;
    pvs__rec r;
    memset(bits, 0, word_count * sizeof(pvs_word));
    for (;;) { /* the chain from the cell to its key: at most max_chain + 1 records (checked by open) */
        pvs__record_at(f, cell, &r);
        chain[n++] = cell;
        if (!r.depth) break;
        cell = r.base;
    }
    pvs__record_apply(f, &r, bits, NULL, NULL); /* the key */
    while (--n) {                                /* then each delta on top of its base */
        pvs__record_at(f, chain[n - 1], &r);
        pvs__record_apply(f, &r, bits, NULL, NULL);
    }
}

PVS_API pvs_result pvs_file_decode(const pvs_file *f, uint32_t cell, pvs_word *bits, size_t word_count, pvs_error *err) {
    if (!f || !bits || !f->data) return pvs__fail(err, PVS_ERROR_INVALID_ARGUMENT, -1, 0, "file and bits must not be NULL");
    if (cell >= f->cell_count) return pvs__fail(err, PVS_ERROR_INVALID_ARGUMENT, cell, 0, "cell %u of %u", cell, f->cell_count);
    if (word_count < PVS_BITSET_WORDS(f->object_count))
        return pvs__fail(err, PVS_ERROR_BUFFER_TOO_SMALL, -1, 0, "%llu words, %u objects need %llu", (unsigned long long)word_count,
                         f->object_count, (unsigned long long)PVS_BITSET_WORDS(f->object_count));
    pvs__file_decode(f, cell, bits, word_count);
    pvs__ok(err);
    return PVS_OK;
}

PVS_API pvs_result pvs_cursor_init(pvs_cursor *c, const pvs_file *f, pvs_word *bits, pvs_word *scratch, size_t word_count, pvs_error *err) {
    if (!c || !f || !f->data || !bits || !scratch || bits == scratch)
        return pvs__fail(err, PVS_ERROR_INVALID_ARGUMENT, -1, 0, "cursor, file, bits and scratch must be given, bits != scratch");
    if (word_count < PVS_BITSET_WORDS(f->object_count))
        return pvs__fail(err, PVS_ERROR_BUFFER_TOO_SMALL, -1, 0, "%llu words, %u objects need %llu", (unsigned long long)word_count,
                         f->object_count, (unsigned long long)PVS_BITSET_WORDS(f->object_count));
    memset(c, 0, sizeof(*c));
    c->file = f;
    c->cell = PVS_NO_CELL;
    c->bits = bits;
    c->scratch = scratch;
    c->word_count = word_count;
    memset(bits, 0, word_count * sizeof(pvs_word));
    pvs__ok(err);
    return PVS_OK;
}

PVS_API pvs_result pvs_cursor_move(pvs_cursor *c, uint32_t cell, pvs_change_fn fn, void *user) {
    const pvs_file *f;
    size_t w;
    if (!c || !c->file) return PVS_ERROR_INVALID_ARGUMENT;
    f = c->file;
    if (cell != PVS_NO_CELL && cell >= f->cell_count) return PVS_ERROR_INVALID_ARGUMENT;
    if (cell == c->cell) return PVS_OK;
    if (cell != PVS_NO_CELL && c->cell != PVS_NO_CELL) {
        /* one delta when the new cell's base is the current cell */
        pvs__rec r;
        pvs__record_at(f, cell, &r);
        if (r.base == c->cell) {
            pvs__record_apply(f, &r, c->bits, fn, user);
            c->cell = cell;
            ++c->delta_moves;
            return PVS_OK;
        }
    }
    if (cell == PVS_NO_CELL) memset(c->scratch, 0, c->word_count * sizeof(pvs_word));
    else pvs__file_decode(f, cell, c->scratch, c->word_count);
    for (w = 0; w < c->word_count; ++w) {
        pvs_word x = c->bits[w] ^ c->scratch[w];
        if (fn)
            while (x) {
                uint32_t id = (uint32_t)(w * 64) + pvs__ctz64(x);
                x &= x - 1u;
                fn(user, id, pvs_bitset_test(c->scratch, id));
            }
        c->bits[w] = c->scratch[w];
    }
    c->cell = cell;
    ++c->full_moves;
    return PVS_OK;
}

#endif /* PVS_IMPLEMENTATION_ONCE */
#endif /* PVS_IMPLEMENTATION */

/*
   FULL HISTORY
   ============
   0.3.0 (2026-11-22) the raster module (conservative occluder/occludee rasterization, hierarchical
                      depth map, cull maps, pvs_raster_cull); occlusion trees (exact 2D, c-LSS 2.5D);
                      occluder synthesis; bake methods shrink, otree and extproj (all conservative).
   0.2.0 (2026-11-22) delta-PVS file format 1 (keys + bounded delta chains, four set codings, compact
                      cells and look-up tree), cursor, record info, sharded bakes and merge.
   0.1.0 (2026-11-22) first version: scene, kD-tree, ray-sampling estimator, bake tasks, .pvs container v1.

------------------------------------------------------------------------------
This software is available under 2 licenses -- choose whichever you prefer.
------------------------------------------------------------------------------
ALTERNATIVE A - MIT License
Copyright (c) 2026 the pvs.h authors
Permission is hereby granted, free of charge, to any person obtaining a copy of
this software and associated documentation files (the "Software"), to deal in
the Software without restriction, including without limitation the rights to
use, copy, modify, merge, publish, distribute, sublicense, and/or sell copies
of the Software, and to permit persons to whom the Software is furnished to do
so, subject to the following conditions:
The above copyright notice and this permission notice shall be included in all
copies or substantial portions of the Software.
THE SOFTWARE IS PROVIDED "AS IS", WITHOUT WARRANTY OF ANY KIND, EXPRESS OR
IMPLIED, INCLUDING BUT NOT LIMITED TO THE WARRANTIES OF MERCHANTABILITY,
FITNESS FOR A PARTICULAR PURPOSE AND NONINFRINGEMENT. IN NO EVENT SHALL THE
AUTHORS OR COPYRIGHT HOLDERS BE LIABLE FOR ANY CLAIM, DAMAGES OR OTHER
LIABILITY, WHETHER IN AN ACTION OF CONTRACT, TORT OR OTHERWISE, ARISING FROM,
OUT OF OR IN CONNECTION WITH THE SOFTWARE OR THE USE OR OTHER DEALINGS IN THE
SOFTWARE.
------------------------------------------------------------------------------
ALTERNATIVE B - Public Domain (www.unlicense.org)
This is free and unencumbered software released into the public domain.
Anyone is free to copy, modify, publish, use, compile, sell, or distribute this
software, either in source code form or as a compiled binary, for any purpose,
commercial or non-commercial, and by any means.
In jurisdictions that recognize copyright laws, the author or authors of this
software dedicate any and all copyright interest in the software to the public
domain. We make this dedication for the benefit of the public at large and to
the detriment of our heirs and successors. We intend this dedication to be an
overt act of relinquishment in perpetuity of all present and future rights to
this software under copyright law.
THE SOFTWARE IS PROVIDED "AS IS", WITHOUT WARRANTY OF ANY KIND, EXPRESS OR
IMPLIED, INCLUDING BUT NOT LIMITED TO THE WARRANTIES OF MERCHANTABILITY,
FITNESS FOR A PARTICULAR PURPOSE AND NONINFRINGEMENT. IN NO EVENT SHALL THE
AUTHORS BE LIABLE FOR ANY CLAIM, DAMAGES OR OTHER LIABILITY, WHETHER IN AN
ACTION OF CONTRACT, TORT OR OTHERWISE, ARISING FROM, OUT OF OR IN CONNECTION
WITH THE SOFTWARE OR THE USE OR OTHER DEALINGS IN THE SOFTWARE.
------------------------------------------------------------------------------
*/
