/* pvs.h - v0.5.0 - conservative potentially visible sets: bake, store, look up, cull - public domain or MIT (see end)

   QUICK START
   ===========
   Define PVS_IMPLEMENTATION before including this file in *one* C or C++ file:

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
   >>otree      occlusion trees: exact 2D and conservative 2.5D (c-LSS) region visibility, from-point culling
   >>occluders  occluder synthesis: voxelize, flood from the cells, erode by eps, boxes / columns
   >>vocc       virtual occluders (Koltun 2000): construction, VOCC section, PVS rebuilt on cell entry
   >>methods    region methods: `shrink` (Wonka 2000), `extproj` (Durand 2000), the estimator `sample`
   >>bake       bake driver: tasks, AUTO, draw distance, resuming, adaptive cells, determinism
   >>format     the .pvs file: writer and validating zero-copy reader
   >>runtime    cell look-up and decoding

   CONFIGURATION (define before including the implementation)
   =============
   macro                   default             what it changes
   PVS_IMPLEMENTATION      undefined           emit the implementation in this translation unit
   PVS_STATIC              undefined           make every function static (private copy per unit)
   PVS_API                 extern / static     decoration of every public function
   PVS_MALLOC(sz)          malloc(sz)          fallback allocator when a desc's allocator is zero; define both
   PVS_FREE(p)             free(p)               or neither
   PVS_QSORT(b, n, sz, f)  qsort(b, n, sz, f)  every sort, with qsort's contract; the order of equal elements
												 changes no result
   PVS_ASSERT(x)           assert(x)           checks of programmer misuse only, never of input data
   PVS_NO_STDIO            undefined           error messages without snprintf (reason strings only)
   PVS_NO_SIMD             undefined           scalar code paths only (identical results)
   PVS_TEST_HOOKS          undefined           internal, the library's own tests: declares their flags
												 (PVS_VISIBILITY_INPUT_ORDER, PVS_VISIBILITY_25D_FULL_TESTS)

   CONCEPTS
   ========
   Coordinates. Any right- or left-handed frame; the scene's `up_axis` (1 = Y, the OBJ default, or 2 = Z) is the
   2.5D methods' height axis. Cells are axis-aligned boxes in scene units.

   Conservative. A PVS lists every object visible from any point of its cell (a superset of the exact set),
   for every eps (the sampling or shrinking distance; smaller is tighter and slower). The exception, `sample`
   (ray sampling), estimates from below: the tests' yardstick; its files carry PVS_FILE_APPROXIMATE. One
   stated tolerance: OTREE's facade extraction closes cracks and offsets of up to eight float epsilons of the
   scene's coordinates between pieces of one wall (real meshes' T-junction cracks, about 1 mm at 1 km); an
   opening meant to be seen through must be wider.

   Methods. AUTO, the default, runs the conservative methods that can cull in the scene, cheapest first, and
   intersects their PVSs (conservative, and at least as tight as each of them): OTREE when vertical walls give
   facades (2.5D); EXTPROJ when there are planar occluders or convex solids (3D; an object's coplanar
   edge-connected triangles act as one occluder, so a wall in pieces hides what the whole wall hides);
   SHRINK when closed geometry leaves volume after erosion by eps. SHRINK, the costliest, runs last on what
   the others kept: the same intersection, in little time. AUTO pays only for what culls: with the default set
   and at least 4 x PVS_AUTO_SAMPLE_CELLS cells, pvs_bake_begin bakes PVS_AUTO_SAMPLE_CELLS cells spread over all
   cells with each method and keeps, greedily, those that cull at least PVS_AUTO_MIN_GAIN of what the others kept
   (pvs_bake_method_info says which and why; counts decide, so every thread count and shard decides alike). A
   named set (pvs_bake_desc.methods) runs in full. VOCC, adding little tightness, runs only when
   pvs_bake_desc.methods names it. Under AUTO, EXTPROJ runs the occlusion sweep of Durand 2000 §5, fusing
   walls and floors the planes of §6.1 do not: on indoor maps a smaller PVS for more time
   (tests/BENCHMARKS.md, bake). max_distance, a draw distance, drops objects whose box is farther from every
   point of the cell (box to box, rounded toward keeping). pvs_bake_restore_task resumes an interrupted bake.

   Adaptive cells (Durand 2000 §6.1). A cell whose PVS holds more than adaptive.budget triangles is split in
   two across its longest side, recursively down to adaptive.min_size; each half is baked by the bake's
   methods from its parent's PVS and intersected with it (EXTPROJ also drops the occluders it hides). The
   file holds the leaf cells (pvs_bake_leaf_count) in cell order, each cell's leaves depth first;
   pvs_bake_cell_pvs gives a whole cell's PVS. Deterministic for any thread count; not with shards, VOCC or
   resuming.

   Memory. Each desc has a `pvs_allocator`; left at zero, PVS_MALLOC/PVS_FREE. Objects remember theirs. Size
   arithmetic is overflow-checked.

   Threads. pvs.h starts no thread and keeps no global mutable state. Read-only objects (a created pvs_scene,
   pvs_kdtree, an opened pvs_file) may be shared by any threads. pvs_bake_run_task may run concurrently for
   distinct tasks (with a thread-safe allocator; malloc is); output is byte-identical for any order or
   thread count.

   Errors. Functions return pvs_result (0 = PVS_OK, negative = error; pvs_result_string names it); most fill
   an optional `pvs_error *` with the code, the offending index or byte offset, and a message. PVS_ASSERT
   guards programmer misuse only; bad data is always a result code.

   Trust. pvs_scene_create validates every index, count and coordinate. pvs_file_open is safe on untrusted
   bytes: it checks every offset, size, count and checksum before use, never reads outside the buffer, and
   later calls on an opened file cannot fail on its content.

   Culling. Per frame, from a context allocated once, pvs_raster_cull (3D: depth pyramid), pvs_raster_cull_map
   (2.5D: cull map) or pvs_otree_cull (an occlusion tree of a few dozen occluders) report every object seen
   through the screen from the near plane on, whatever the rounding. Depth is reversed (larger is nearer).
   Pass a cell's PVS as `candidates` to cull inside it.

   Virtual occluders (Koltun 2000). A vocc bake also stores a few vertical rectangles per cell (about 50
   bytes) from which pvs_vocc_cull rebuilds the PVS on cell entry; --vocc-only keeps only them.

   MEMORY
   ======
   Allocates through the desc's allocator: pvs_scene_create (triangles, kD-trees: 105 to 430 bytes per
   triangle on the generator's scenes, at most PVS_SCENE_BYTES_PER_TRIANGLE, 2.4 KB, per triangle and per
   object); pvs_bake_begin (a bitset per cell: cell_count * object_count / 8 bytes, 40 of statistics per cell);
   pvs_bake_run_task (AUTO: a bitset per method; EXTPROJ: (128 + 8 x sweep planes) x N^2 bytes of N x N
   depth maps and sweep masks, plus summed-area tables of 4 (N^2 + N + 1 + min(16 N, 16384)) bytes per
   plane of a direction up to 64 MiB, at least two (pvs_extproj_task_bytes): 8 MB at 256 pixels, 21 MB with
   16 sweep planes, 0.7 GB at 1024 and 64, freed on return; adaptive cells: a box and a bitset per leaf,
   kept); pvs_file_encode (about 40 bytes per cell plus a bitset); pvs_raster_create (depth map, pyramid,
   cull map); pvs_otree_create (about 250 bytes per node of its budget, 5 per kD node and object). Allocate
   nothing: the pvs_file_* readers, pvs_cursor_*, kD-tree queries, pvs_raster_cull*, pvs_otree_cull,
   pvs_vocc_cull. A .pvs file is used in place.

   PERFORMANCE (`make bench`, 2026-11-24, one core of a 2-core AMD EPYC VM, release build)
   ===========
   kD-tree build 0.36 s per million triangles; 1.1 M closest-hit rays/s (200k-triangle boxes). Demo city (3,575
   objects, 457k triangles, 1,211 cells): file 0.099 of raw bitsets (44 bytes per cell); cursor move 0.3 us;
   pvs_file_find_cell (10,000 cells) 40 to 65 ns. Per frame: 50,000 occluder triangles at 1920x1080 and 10,000 box
   tests 0.9 ms (SSE2; scalar 1.9); pvs_otree_cull (32 occluders) 0.2 ms. Bake per cell (demo city): otree 4.3 ms;
   shrink 4.5 ms (plus 4 s of synthesis per bake); extproj 15 ms, 55 ms with the sweep; vocc 60 ms (96% of
   shrink's culling in 52 bytes). tests/BENCHMARKS.md gives each figure's bench and the measurements behind
   the design choices.

   ALGORITHMS (each cited again where it is implemented)
   ==========
   kD-tree, front-to-back sweep by priority queue, occlusion trees: Bittner 2002 (§3.2, §4.4, ch. 4, 6, 7).
   Delta-PVS storage, extended projections, hierarchical depth map: Durand et al. 2000 (§2.4, §3, §5, §6).
   Cull maps and occluder shadows: Wonka and Schmalstieg 1999 (§3-4). Occluder shrinking and point sampling:
   Wonka, Wimmer and Schmalstieg 2000. Virtual occluders: Koltun, Chrysanthou and Cohen-Or 2000. Watertight
   ray-triangle test: Woop, Benthin and Wald 2013. Masked occlusion culling (tiles of coverage masks):
   Hasselgren, Andersson and Akenine-Moller 2016. Rice codes: Golomb 1966, Rice 1979.

   FILE FORMAT (version 1; integers little-endian; offsets from the start of the file)
   ===========
   The delta-PVS of Durand et al. 2000 (§6.2): a few key cells store their PVS whole, the others the objects
   that differ from a base cell, chains bounded by K. pvs_file_open rejects a file breaking a rule below
   with the code in brackets.
   header, 32 bytes:
	 0  u8[4]  magic "PVS\x1a"                                             [BAD_MAGIC]
	 4  u32    format version (PVS_FORMAT_VERSION); any other is rejected     [BAD_VERSION]; it changes
			   only when a version-1 reader would misread a file, not for new optional sections
	 8  u32    file size in bytes (must equal the buffer size)                [TRUNCATED, BAD_HEADER]
	 12 u32    section count S (1..64)                                        [BAD_HEADER]
	 16 u32    flags (PVS_FILE_APPROXIMATE = 1); unknown bits are ignored
	 20 u32    CRC-32 (IEEE) of bytes 0..19 and of the section table          [CHECKSUM]
	 24 u32[2] reserved, zero                                                 [BAD_HEADER]
   section table at 32: S entries of u32 tag, offset, size, CRC-32 of the section's bytes [CHECKSUM].
	 Sections are 8-byte aligned, inside the file, disjoint, tags unique [BAD_SECTION, TRUNCATED]; other
	 bytes after the table are zero [BAD_SECTION]. Tags are four ASCII characters; readers skip unknown ones
	 (room for optional sections). The writer emits META, CELL, TREE, RECS, then SHRD (part files), VOCC.
   "META" (required, 32 bytes, else BAD_SECTION) [BAD_HEADER; COUNT_OVERFLOW for counts past the limits]:
	 0 u32 cell_count (1..2^30-1)   4 u32 object_count (1..2^32-2)   8 u32 method (pvs_method)
	 12 f32 eps (finite, >= 0)      16 u32 up_axis (1 = Y, 2 = Z)    20 u32 K, the chain bound (1..64)
	 24 u32 key cell count (1..cell_count, equal to the records' count)   28 u32 reserved zero
   "CELL" (required): cell boxes as indices into per-axis coordinate tables [BAD_SECTION, BAD_CELL]:
	 0 u32 n[3]: distinct coordinates per axis (1..2 * cell_count)
	 12 u8 w[3]: min index widths in bits, the bits needed for n - 1 (0 when n = 1)
	 15 u8 x[3]: extent widths in bits (<= w)      18 u8[2] zero
	 20 f32 tables: n[0] values of axis 0, n[1] of axis 1, n[2] of axis 2; finite, strictly ascending,
		never -0 (written as +0)
	 then per cell, in cell order, min0 min1 min2 (widths w) and extents e0 e1 e2 (widths x; max index = min +
		extent < n), packed least significant bit first; the last byte's unused high bits are zero; the section
		ends there.
   "TREE" (required): the cell look-up kD-tree, complete, depth D, implicit (node k's children 2k + 1 and
	 2k + 2; leaf j is node 2^D - 1 + j) [BAD_TREE]:
	 0 u32 D (0..24)   4 u32 zero   8 f32 splits[2^D - 1] (finite)   then u32 leaf offsets[2^D + 1]
	 (offsets[0] = 0, ascending, the last = the item bytes' size)   then u8 axes[2^D - 1] (0..2; a node
	 whose cells all go left has split FLT_MAX)   then the items: leaf j's cell ids in offsets[j] ..
	 offsets[j + 1], ascending ids < cell_count as varints of the first and the gaps minus one; the
	 section ends there.
	 Look-up of p: at an inner node p[axis] < split goes left, > split right, == split both; in a leaf the
	 lowest id whose closed box contains p. The writer puts a cell left when min < split or max <= split
	 and right when max > split, so every cell containing p is found (pvsinfo --verify checks this).
   "RECS" (required): the PVS records [BAD_SECTION, BAD_RECORD, OBJECT_OUT_OF_RANGE, BAD_CHAIN]:
	 0 u32 block offsets[B + 1], B = ceil(cell_count / 16), from the section start: offsets[0] = 4 (B + 1),
	   ascending, offsets[B] = the section size; block b holds cells 16b .. 16b + 15's records back to back.
	 A record: varint R, the rest's byte count; varint head: coding = head & 3 (of the added ids), depth =
	   head >> 2 (0 = a key cell, else a delta, <= K). A key: its PVS's ids (universe object_count) so coded.
	   A delta: varint z, the base cell = cell - (z even ? z / 2 : -(z + 1) / 2) (zigzag), of depth one less (so
	   chains reach a key within K steps and cannot cycle); u8 coding of the removed objects (0..3); varint m, the
	   base's PVS size (<= object_count); the removed objects as ranks in the base's PVS (universe m: rank r = the
	   base's (r+1)-th smallest id); then the added ids (universe object_count, never in the base's PVS) in the
	   head's coding. The sets fill the record exactly. Set codings, each self-delimiting:
		 0 gap varints: varint count, then count varints: the first id, then the gaps minus one.
		 1 run lengths: varint pairs, then per pair varint zeros, varint ones - 1: alternating runs from
		   id 0 (zero runs after the first >= 1); the set ends after the last ones run.
		 2 Rice codes: u8 k (0..24), varint count, then count codes, least significant bit first, per gap
		   (as in 0): gap >> k 1 bits, a 0 bit, the k low bits; zero bits pad the last byte.
		 3 raw bitset: ceil(universe / 8) bytes, bit i of byte j = id 8j + i; bits past the universe zero.
	   The writer picks the smallest coding, ties to the lower. A decoder applies the deltas from the
	   chain's key (removals, then additions). Only decoding checks m against the base's PVS (pvsinfo
	   --verify); ranks past it in a damaged file are ignored, never read out of bounds.
	 Varints are LEB128: at most 5 bytes, the value fits 32 bits, no needless 0x80 bytes.
   "SHRD" (optional, 16 bytes, else BAD_SECTION; part files of a sharded bake) [BAD_HEADER]: u32 shard
	 index (0-based), u32 shard count (>= 2), u32 total cell count, u32 zero. Part cell j is whole cell
	 index + j * count; cell_count must be the number of such cells.
   "VOCC" (optional; virtual occluders, >>vocc) [BAD_SECTION]: per cell vertical rectangles, each hidden
	 from the whole cell, most effective first:
	 0  u32 flags: bit 0 = the records are placeholders (--vocc-only: every drawable object); others zero
	 4  u32 N, the occluders of all cells (<= 255 * cell_count)
	 8  f32 base, every occluder's bottom height    12 f32 step (> 0); both finite, base + 255 step too
	 16 u32 first[B + 1], B = ceil(cell_count / 16): index of cell 16b's first occluder; first[0] = 0,
		first[B] = N, first[b + 1] - first[b] = block b's count sum
	 then u8 count[cell_count] (0..255), then u8 scale[cell_count]: the cell's coordinate scale
		S = 2^((scale - 128) / 8), exactly the double nearest 2^(k / 8) for k = scale mod 8, times
		2^(scale div 8 - 16)
	 then N occluders of 5 bytes, cell by cell: u8 q0 q1 (end point 0), q2 q3 (end point 1), q4 (top).
		Ground coordinate (u, v) = centre + S (q - 128) |q - 128| / 16384 in double, centre = 0.5f min +
		0.5f max of the cell's box in float (finer steps near the cell: the perspective); top = base +
		q4 step in double.
	 The section is exactly 16 + 4 (B + 1) + 2 cell_count + 5 N bytes. The bake rounds each occluder
	 smaller (end points inward and away from the cell, top down) and proves the rounded one hidden, so
	 the stored bytes are conservative. Readers may skip VOCC; the records stay a valid PVS.

   RECENT HISTORY
   ==============
   0.5.0 (2026-11-28) AUTO keeps only the methods that cull on a sample of cells (PVS_AUTO_SAMPLE_CELLS,
					  PVS_AUTO_MIN_GAIN; pvs_bake_method_info.sample_cells, sample_gain). File format unchanged.
   0.4.0 (2026-11-28) API: per-method parameter structs in pvs_bake_desc (extproj_sweep is now extproj.sweep);
					  getters renamed pvs_*_get_* (pvs_bake_otree_info is now pvs_bake_get_otree_info, ...);
					  test-only flags need PVS_TEST_HOOKS. New: AUTO, resuming, virtual occluders, adaptive
					  cells, the sweep, bounded memory (FULL HISTORY). File format unchanged.
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
#define PVS_VERSION_MINOR 5
#define PVS_VERSION_PATCH 0
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

/* ---- core ---- */

/* Result of every fallible call: 0 success, errors negative. */
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

/* Where and why a call failed, for calls whose last argument is a `pvs_error *` (NULL allowed). */
typedef struct pvs_error {
	pvs_result result;   /* same as the return value */
	int64_t index;       /* offending object/triangle/vertex/cell/occluder/record index, or -1 */
	uint64_t offset;     /* byte offset into a file for format errors, else 0 */
	char message[200];   /* NUL-terminated, human-readable: what and where */
} pvs_error;

/* A constant English description ("out of memory"), never NULL. */
PVS_API const char *pvs_result_string(pvs_result result);

/* The implementation's PVS_VERSION. */
PVS_API uint32_t pvs_version(void);

/* Allocation hooks: alloc returns memory aligned to `align` (a power of two <= 64) or NULL; free gets the
   size given to alloc. All zero: PVS_MALLOC/PVS_FREE. Objects keep a copy. Thread-safe for parallel bakes. */
typedef struct pvs_allocator {
	void *(*alloc)(size_t size, size_t align, void *user);
	void (*free)(void *ptr, size_t size, void *user);
	void *user;
} pvs_allocator;

/* An axis-aligned box; min == max on an axis (flat) is valid. */
typedef struct pvs_box {
	float min[3];
	float max[3];
} pvs_box;

/* Bitsets: bit i of word i/64 is object id i; PVS_BITSET_WORDS(object_count) words. */
typedef uint64_t pvs_word;
#define PVS_BITSET_WORDS(bits) (((size_t)(bits) + 63u) / 64u)
/* Test (1 if set), set, clear bit i; no bounds check. */
PVS_API int pvs_bitset_test(const pvs_word *bits, uint32_t i);
PVS_API void pvs_bitset_set(pvs_word *bits, uint32_t i);
PVS_API void pvs_bitset_clear(pvs_word *bits, uint32_t i);
/* Set bits among the first `bit_count`. */
PVS_API uint32_t pvs_bitset_count(const pvs_word *bits, uint32_t bit_count);
/* The first set bit >= `from`, or `bit_count`: for (i = next(b,n,0); i < n; i = next(b,n,i+1)). */
PVS_API uint32_t pvs_bitset_next(const pvs_word *bits, uint32_t bit_count, uint32_t from);

/* ---- scene ---- */

/* Object flags. */
#define PVS_OBJECT_OCCLUDER_ONLY 1u /* blocks sight but is never drawn: never appears in a PVS */

/* An object, the unit of visibility: a range of triangles overlapping no other object's. Triangles in no
   range block sight only. */
typedef struct pvs_object_desc {
	uint32_t first_triangle;
	uint32_t triangle_count;
	uint32_t flags;          /* PVS_OBJECT_* */
} pvs_object_desc;

/* Kinds of explicit occluder volume (geometry known solid). */
typedef enum pvs_occluder_kind {
	PVS_OCCLUDER_INVALID = 0,
	PVS_OCCLUDER_BOX,        /* `box` */
	PVS_OCCLUDER_CONVEX,     /* intersection of half-spaces: `planes` */
	PVS_OCCLUDER_EXTRUSION,  /* a simple polygon in the ground plane extruded along the up axis */
	PVS_OCCLUDER_KIND_COUNT
} pvs_occluder_kind;

/* An explicit occluder volume; pvs_scene_create copies the arrays. */
typedef struct pvs_occluder_desc {
	pvs_occluder_kind kind;
	pvs_box box;                /* BOX: the volume */
	const float *planes;        /* CONVEX: plane_count x (nx, ny, nz, d); inside is n.p + d <= 0 */
	uint32_t plane_count;       /* CONVEX: 4..PVS_MAX_OCCLUDER_PLANES, bounded, non-empty */
	const float *footprint;     /* EXTRUSION: footprint_count ground points (u, v), a simple polygon, */
	uint32_t footprint_count;   /*   either winding, may be concave; 3..PVS_MAX_FOOTPRINT_POINTS */
	float base, top;            /* EXTRUSION: heights along the up axis, base < top */
} pvs_occluder_desc;
#define PVS_MAX_OCCLUDER_PLANES 64
#define PVS_MAX_FOOTPRINT_POINTS 4096

/* Scene flags. */
#define PVS_SCENE_ALLOW_EMPTY_OBJECTS 1u /* keep objects with no (or only zero-area) triangles: never visible */

/* What pvs_scene_create needs; zero fields get defaults. Ground coordinates (u, v): (x, z) for up_axis 1,
   (x, y) for 2. */
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

/* A validated scene with its kD-trees; immutable, so thread-safe. */
typedef struct pvs_scene pvs_scene;

/* Copies and validates the arrays, builds object bounds and kD-trees. Errors: INVALID_ARGUMENT,
   INDEX_OUT_OF_RANGE, NOT_FINITE, EMPTY_OBJECT, DEGENERATE_OBJECT, OVERLAPPING_OBJECTS, BAD_OCCLUDER,
   COUNT_OVERFLOW, OUT_OF_MEMORY; err->index names the element. Holds at most these bytes per triangle and
   object, 12 per vertex and _FIXED at once, whatever the shapes (MEMORY). */
#define PVS_SCENE_BYTES_PER_TRIANGLE 2432
#define PVS_SCENE_BYTES_PER_OBJECT 2400
#define PVS_SCENE_BYTES_FIXED 16384
PVS_API pvs_result pvs_scene_create(const pvs_scene_desc *desc, pvs_scene **out_scene, pvs_error *err);
/* Frees through its allocator; NULL allowed. */
PVS_API void pvs_scene_destroy(pvs_scene *scene);

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
/* The scene's copy of explicit occluder i (arrays inside the scene). */
PVS_API const pvs_occluder_desc *pvs_scene_occluder(const pvs_scene *scene, uint32_t i);

typedef struct pvs_hit {
	float t;             /* distance along dir, in units of |dir| */
	uint32_t triangle;
	uint32_t object;     /* PVS_NO_OBJECT for triangles in no object */
} pvs_hit;

/* Closest hit of origin + t dir, 0 <= t <= tmax (dir non-zero), with the two-sided triangles: 1 and *hit
   (may be NULL), or 0. Watertight (Woop, Benthin, Wald 2013, in double): no ray slips between triangles
   sharing an edge or corner. Zero-area triangles are never hit; ties go to the lowest triangle index.
   Thread-safe, allocates nothing. */
PVS_API int pvs_scene_raycast(const pvs_scene *scene, const float origin[3], const float dir[3], float tmax,
							  pvs_hit *hit);
/* 1 if a triangle crosses segment a-b (ends included), 0 when a == b; as watertight, thread-safe and
   allocation-free as pvs_scene_raycast. */
PVS_API int pvs_scene_segment_blocked(const pvs_scene *scene, const float a[3], const float b[3]);

/* ---- kdtree ---- */

/* A kD-tree over boxes (objects, triangles or cells): binned SAH, items in every leaf they overlap.
   Immutable, so thread-safe. */
typedef struct pvs_kdtree pvs_kdtree;

typedef struct pvs_kdtree_desc {
	const pvs_box *boxes;    /* count item boxes; item i is box i */
	uint32_t count;
	uint32_t leaf_size;      /* stop splitting at this many items, 0 = default (4) */
	uint32_t max_depth;      /* 0 = automatic (about 1.3 log2 count + 8), capped at PVS_KDTREE_MAX_DEPTH */
	pvs_allocator allocator;
} pvs_kdtree_desc;
#define PVS_KDTREE_MAX_DEPTH 48
/* Memory bounds per box, for any boxes: item references (4 bytes each), nodes (8 bytes each), build bytes
   (plus _BUILD_BYTES_FIXED at once). Boxes overlapping everywhere (a fan of slivers) get bigger leaves
   instead of more memory; ordinary sets stay far below (tests/BENCHMARKS.md, kdtree). */
#define PVS_KDTREE_MAX_REFS_PER_BOX 64
#define PVS_KDTREE_MAX_NODES_PER_BOX 32
#define PVS_KDTREE_BUILD_BYTES_PER_BOX 2336
#define PVS_KDTREE_BUILD_BYTES_FIXED 4096

/* Builds the tree, deterministically. Boxes with min > max are left out; count 0 gives an empty tree.
   Errors: INVALID_ARGUMENT, NOT_FINITE (err->index = the box), COUNT_OVERFLOW, OUT_OF_MEMORY. */
PVS_API pvs_result pvs_kdtree_create(const pvs_kdtree_desc *desc, pvs_kdtree **out_tree, pvs_error *err);
/* Frees through its allocator; NULL allowed. */
PVS_API void pvs_kdtree_destroy(pvs_kdtree *tree);
/* The union of the non-empty item boxes, or an empty box (min > max). */
PVS_API pvs_box pvs_kdtree_bounds(const pvs_kdtree *tree);
/* Nodes, inner (two children each) and leaves; at least 1. */
PVS_API uint32_t pvs_kdtree_node_count(const pvs_kdtree *tree);

/* What a sweep visitor tells the traversal. */
typedef enum pvs_visit {
	PVS_VISIT_DESCEND = 0,   /* go on into this node's children */
	PVS_VISIT_SKIP,          /* cull this node's subtree */
	PVS_VISIT_STOP,          /* end the sweep */
	PVS_VISIT_ALL,           /* take the subtree whole (see below); only STOP is heeded below it */
	PVS_VISIT_COUNT
} pvs_visit;

/* Called per node reached, by increasing `distance` from the source box (0 where they meet); `node_box`:
   the bounds cut by the splits above. Leaves pass their items (an item once per leaf it is in), other
   nodes NULL, 0. After PVS_VISIT_ALL, each non-empty leaf below comes at once, depth first, with distance
   -1 (unordered), before the sweep goes on. */
typedef pvs_visit (*pvs_kdtree_visit_fn)(void *user, const pvs_box *node_box, float distance,
										 const uint32_t *items, uint32_t item_count);

/* Scratch bytes pvs_kdtree_sweep needs: 32 per leaf ((node_count + 1) / 2). */
PVS_API size_t pvs_kdtree_sweep_scratch_size(const pvs_kdtree *tree);
/* The approximate occlusion sweep (Bittner 2002, §3.2): nodes front to back from the box `source` (a
   point: min == max) by a priority queue on minimum distance, ties by node index (deterministic).
   `scratch`: pvs_kdtree_sweep_scratch_size bytes, 8-aligned. Errors: BUFFER_TOO_SMALL, INVALID_ARGUMENT
   (NULL tree, source or visit), NOT_FINITE (source). Allocates nothing. */
PVS_API pvs_result pvs_kdtree_sweep(const pvs_kdtree *tree, const pvs_box *source, void *scratch, size_t scratch_size,
									pvs_kdtree_visit_fn visit, void *user);

/* Called per non-empty leaf a ray passes, nearest first; [t_enter, t_exit] is widened by a relative 1e-7
   so no touched leaf is skipped. Returns a smaller tmax to shorten the ray (larger is ignored), < 0 to stop. */
typedef float (*pvs_kdtree_ray_fn)(void *user, const uint32_t *items, uint32_t item_count, float t_enter, float t_exit);
/* Walks the leaves origin + t dir, 0 <= t <= tmax, passes, front to back; dir may have 0 or -0 components
   (not all three), the origin lie anywhere; non-finite input walks nothing. Thread-safe, no allocation. */
PVS_API void pvs_kdtree_ray(const pvs_kdtree *tree, const float origin[3], const float dir[3], float tmax,
							pvs_kdtree_ray_fn fn, void *user);

/* The items of p's leaf: all whose box contains p (also on a split plane) and maybe more, to test. NULL
   and *count = 0 outside the bounds or in an empty leaf. No allocation. */
PVS_API const uint32_t *pvs_kdtree_leaf_items(const pvs_kdtree *tree, const float p[3], uint32_t *count);

/* ---- raster ---- */

/* Depth (reversed Z): z_clip / w_clip, LARGER IS NEARER. pvs_camera_matrix maps the near plane to 1,
   infinity to 0 (orthographic: 1 at near, falling linearly, negative past `far`). Points with z_clip <=
   w_clip and w_clip > 0 are in front of the near plane, the rest is clipped; no far clipping. Pixel (i, j)
   covers [i, i+1] x [j, j+1] for x = (x_ndc + 1) / 2 * width, y likewise (row 0 at y_ndc = -1), and holds
   the nearest depth drawn, else PVS_DEPTH_EMPTY. */
#define PVS_DEPTH_EMPTY (-3.402823466e+38f)

/* How a triangle is rasterized (Durand 2000 §2.2, §3.1-3.2: occluders by intersection, occludees by union). */
typedef enum pvs_raster_mode {
	PVS_RASTER_OCCLUDER = 0,  /* pixels covered entirely, no nearer than the triangle's farthest over them */
	PVS_RASTER_OCCLUDEE,      /* pixels touched, no farther than the triangle's nearest over them */
	PVS_RASTER_MODE_COUNT
} pvs_raster_mode;

/* A camera. `forward`, `up` need not be unit or orthogonal (up is orthogonalized); image x = forward x up. */
typedef struct pvs_camera {
	float eye[3];
	float forward[3];
	float up[3];
	float fov_y;         /* vertical field of view in radians, in (0, pi); 0 = orthographic */
	float near_plane;    /* distance of the near plane, > 0 */
	float ortho_height;  /* orthographic: height of the view volume, > 0 */
	float far_plane;     /* orthographic: where depth reaches 0 (not a clip plane); 0 = near + 1e4 */
} pvs_camera;

/* The row-major clip matrix (clip = m * (x, y, z, 1), m[4 * row + col]) for aspect width / height;
   perspective depth = near / distance along forward. INVALID_ARGUMENT or NOT_FINITE for a bad camera. */
PVS_API pvs_result pvs_camera_matrix(const pvs_camera *camera, float aspect, float m[16]);

/* Raster flags. Occluder depth is kept per pixel (the default up to 65,536 pixels) or per 32 x 4 tile as
   a coverage mask and two depths (Masked Occlusion Culling: several times faster, a tile's depth the
   farthest of what covers it; the default above). Both are conservative. */
#define PVS_RASTER_SCALAR 1u     /* use the scalar code even where SIMD is compiled in (identical results) */
#define PVS_RASTER_PER_PIXEL 2u  /* occluders keep a depth per pixel */
#define PVS_RASTER_TILED 4u      /* occluders go to tiles (wins over PVS_RASTER_PER_PIXEL) */

/* What pvs_raster_create needs; zero fields get defaults. */
typedef struct pvs_raster_desc {
	uint32_t width, height;       /* depth map size in pixels, 1..16384 each */
	/* Optional: sizes the culling buffers and cull map grid; pvs_raster_cull* accept a scene no larger
	   (objects, triangles, kD-tree nodes). */
	const pvs_scene *scene;
	uint32_t max_occluders;       /* scene triangles pvs_raster_cull may select per frame, 0 = 1024 */
	uint32_t cull_map_width;      /* cull map cells over the scene's ground rectangle, 0 = no cull map */
	uint32_t cull_map_height;     /*   (both or neither; 1..4096; needs `scene`) */
	uint32_t flags;               /* PVS_RASTER_* */
	uint32_t max_mesh_triangles;  /* pvs_raster_mesh's piece size, 0 = 4096 (about 400 bytes each) */
	pvs_allocator allocator;
} pvs_raster_desc;

/* A rasterizer context holding every buffer; nothing allocates after create. One per thread. */
typedef struct pvs_raster pvs_raster;

/* Errors: INVALID_ARGUMENT (sizes), COUNT_OVERFLOW, OUT_OF_MEMORY. */
PVS_API pvs_result pvs_raster_create(const pvs_raster_desc *desc, pvs_raster **out_raster, pvs_error *err);
/* Frees through its allocator; NULL allowed. */
PVS_API void pvs_raster_destroy(pvs_raster *raster);

/* Sets every depth map pixel to PVS_DEPTH_EMPTY. */
PVS_API void pvs_raster_clear(pvs_raster *raster);
/* Sets the row-major projection of the next draws and box tests: any 4x4 (perspective, orthographic,
   off-axis as Durand 2000's planes shared by a cell). NOT_FINITE for a non-finite entry. */
PVS_API pvs_result pvs_raster_set_matrix(pvs_raster *raster, const float m[16]);
/* Draws `count` two-sided triangles (3 floats per vertex; 3 `indices` per triangle, NULL: consecutive),
   keeping per pixel the nearer depth (tiles merge: a pixel may keep a farther depth, never one nearer than
   its nearest occluder); conservative under rounding (>>raster). Skips triangles with a non-finite
   coordinate or an index >= vertex_count. INVALID_ARGUMENT for NULL positions or a bad mode. */
PVS_API pvs_result pvs_raster_triangles(pvs_raster *raster, const float *positions, uint32_t vertex_count,
										const uint32_t *indices, uint32_t count, pvs_raster_mode mode);
/* Draws `count` triangles as one occluder (Durand 2000 §3.3: per-triangle inner coverage leaves cracks
   along shared edges): as pvs_raster_triangles, plus every pixel a triangle touches and no boundary edge
   does, at the farthest depth over it of the touching triangles of its facing. Boundary edges, where
   cracks remain: edges not shared by exactly two triangles, silhouettes, edges between triangles wound
   against each other, near-plane cuts and the edges they cut. Vertices are shared by index or equal
   position. Longer meshes go in pieces of max_mesh_triangles, edges between pieces staying boundary.
   INVALID_ARGUMENT for a NULL raster, or NULL positions with count > 0; skips and rounding as
   pvs_raster_triangles; same result with or without SIMD. */
PVS_API pvs_result pvs_raster_mesh(pvs_raster *raster, const float *positions, uint32_t vertex_count,
								   const uint32_t *indices, uint32_t count);
/* The depth map, width * height floats from row 0, valid until the next raster call (tiled: built here). */
PVS_API const float *pvs_raster_depth(const pvs_raster *raster, uint32_t *width, uint32_t *height);

/* The hierarchical depth map (Durand 2000 §2.4, after Greene, Kass and Miller 1993): per texel the
   farthest and nearest depth of its 2 x 2 children (tiled: above the tiles). The tests build it when the
   map changed. */
PVS_API void pvs_raster_build_pyramid(pvs_raster *raster);
/* 1 if an occludee of nearest depth `depth` may be visible in pixels [x0, x1] x [y0, y1] (inclusive,
   clamped): some pixel stores a depth <= `depth`; 0 if all are strictly nearer or the rectangle is off
   the map. */
PVS_API int pvs_raster_test_rect(pvs_raster *raster, int32_t x0, int32_t y0, int32_t x1, int32_t y1, float depth);
/* 1 if the box may be visible under the matrix: in front of the near plane, on screen, not hidden. */
PVS_API int pvs_raster_test_box(pvs_raster *raster, const pvs_box *box);

/* Connected facades for the cull map (Wonka 1999 §3.1, §4.1): vertical quads on consecutive ground
   segments (u, v), from `base` to `top`. */
typedef struct pvs_facade_chain {
	const float *points;   /* point_count points (u, v) */
	uint32_t point_count;  /* >= 2 */
	uint32_t closed;       /* 1: a closed footprint (either winding), back-face culled; 0: open, two-sided */
	float base, top;       /* heights, base < top; chains with base above the ground are ignored */
} pvs_facade_chain;

/* Cull map flags. */
#define PVS_CULL_MAP_SCENE_OCCLUDERS 1u /* also the scene's EXTRUSION and BOX occluders as closed chains */

/* Builds the cull map from the eye (Wonka & Schmalstieg 1999 §3-4): front-facing facades' occluder
   shadows, rasterized top-down over the ground rectangle, the highest per cell; a cell hides its column
   below that height (PVS_DEPTH_EMPTY: not wholly shadowed). Facades count only when base <= min(eye
   height, the scene's lowest point), so sight lines to hidden points cross them. Skips malformed chains.
   INVALID_ARGUMENT without a scene and cull map, NOT_FINITE (eye). */
PVS_API pvs_result pvs_cull_map_build(pvs_raster *raster, const float eye[3], const pvs_facade_chain *chains,
									  uint32_t chain_count, uint32_t flags);
/* The cull map, width * height heights, row-major; cell (i, j) covers u in region[0] + [i, i+1] * (region[2]
   - region[0]) / width, v likewise. NULL without a cull map. */
PVS_API const float *pvs_cull_map(const pvs_raster *raster, uint32_t *width, uint32_t *height, float region[4]);
/* 1 if some cell the box overlaps holds a height <= its top (Wonka 1999 §4.3); outside the region: 1. */
PVS_API int pvs_cull_map_test_box(const pvs_raster *raster, const pvs_box *box);

/* Per-frame culling inputs. All zero: a frustum cull. */
typedef struct pvs_cull_params {
	const float *occluder_positions;  /* the caller's (dynamic) occluder triangles: 3 floats per vertex; */
	uint32_t occluder_vertex_count;   /*   indices 3 per triangle, or NULL for consecutive vertices */
	const uint32_t *occluder_indices;
	uint32_t occluder_triangle_count;
	uint32_t scene_occluders;         /* also the best this many scene triangles (<= max_occluders) ... */
	float occluder_distance;          /*   ... within this distance (0 = 100) by area-angle (Bittner 2002 §4.5) */
	uint32_t scene_volumes;           /* 1: also BOX occluders and EXTRUSION walls within it (no CONVEX) */
	const pvs_facade_chain *facades;  /* pvs_raster_cull_map only: facade chains ... */
	uint32_t facade_count;
	uint32_t cull_map_flags;          /*   ... and PVS_CULL_MAP_* flags */
	const pvs_word *candidates;       /* optional, PVS_BITSET_WORDS(object_count): test only these (a cell's PVS) */
	uint32_t occluder_flags;          /* PVS_CULL_* */
} pvs_cull_params;

/* pvs_raster_cull: occluders drawn as meshes (pvs_raster_mesh: no cracks, a cost per frame;
   tests/BENCHMARKS.md, raster). */
#define PVS_CULL_OCCLUDER_MESH 1u      /* the caller's triangles, as connected meshes */
#define PVS_CULL_SCENE_MESH 2u         /* the selected scene triangles, welded (tighter on many-triangle walls) */
#define PVS_CULL_SEPARATE_TRIANGLES 4u /* scene_volumes per triangle; by default each is a mesh (small cost) */

/* What a culling call did. */
typedef struct pvs_cull_stats {
	uint32_t occluder_triangles;  /* triangles rasterized (caller + selected scene triangles) */
	uint32_t nodes_visited;       /* kD-tree nodes reached by the sweep */
	uint32_t boxes_tested;        /* node and object boxes tested */
	uint32_t visible;             /* objects reported */
} pvs_cull_stats;

/* From-point culling with the depth pyramid: clears, sets the camera (aspect width / height), draws the
   occluders, builds the pyramid, sweeps the object kD-tree front to back (Bittner 2002 §3.2) skipping
   hidden subtrees. Sets in `visible` (PVS_BITSET_WORDS(object_count) words, cleared first) every object
   whose box may be seen through the screen from the eye, never occluder-only ones. `stats` may be NULL.
   Errors: INVALID_ARGUMENT, NOT_FINITE (camera), BUFFER_TOO_SMALL (a scene larger than the context's). */
PVS_API pvs_result pvs_raster_cull(pvs_raster *raster, const pvs_scene *scene, const pvs_camera *camera,
								   const pvs_cull_params *params, pvs_word *visible, pvs_cull_stats *stats,
								   pvs_error *err);
/* The 2.5D twin (Wonka 1999): builds the cull map from the eye with params->facades (and, per flag, the
   scene's occluders), scans the object grid with §4.3's two-level bounding-height test and sets every
   object in the frustum not under the shadows; orthographic cameras (no eye point) get the frustum test.
   `scene`: the context's. Outputs and errors as pvs_raster_cull. */
PVS_API pvs_result pvs_raster_cull_map(pvs_raster *raster, const pvs_scene *scene, const pvs_camera *camera,
									   const pvs_cull_params *params, pvs_word *visible, pvs_cull_stats *stats,
									   pvs_error *err);
/* ---- otree ---- */

/* Occlusion trees (Bittner 2002): BSPs over line space built front to back; every floating-point
   decision is conservative. */

/* What an occlusion-tree computation reports. */
typedef struct pvs_otree_stats {
	uint32_t nodes;              /* tree nodes at the end (the largest tree for several trees) */
	uint32_t occluders_inserted; /* occluders merged into the tree(s) */
	uint32_t visible_segments;   /* 2D: segments found visible */
	uint32_t budget_exceeded; /* 1: node_budget stopped insertion, the rest counted as not blocking */
} pvs_otree_stats;

/* Segment flags for pvs_visibility_2d. */
#define PVS_SEGMENT_NO_OCCLUSION 1u /* tested for visibility but never blocks sight */

/* Exact 2D from-region visibility (Bittner 2002, ch. 6). Zero fields get defaults. */
typedef struct pvs_visibility_2d_desc {
	const float *cell;               /* cell_vertex_count x (x, y): a convex polygon, either winding */
	uint32_t cell_vertex_count;      /* >= 3 */
	const float *segments;           /* segment_count x (x0, y0, x1, y1): occluders, opaque from both sides */
	uint32_t segment_count;
	const uint8_t *segment_flags;    /* NULL or segment_count PVS_SEGMENT_* flags */
	const uint32_t *segment_objects; /* NULL (segment i is object i) or each segment's object or PVS_NO_OBJECT */
	uint32_t object_count;           /* bits in visible_objects */
	uint32_t node_budget;            /* stop inserting past this many tree nodes (0 = 2^20) */
	uint32_t flags;                  /* 0 (the test hook PVS_VISIBILITY_INPUT_ORDER) */
	pvs_allocator allocator;
} pvs_visibility_2d_desc;
#ifdef PVS_TEST_HOOKS /* internal: the library's own tests (CONFIGURATION) */
/* insert occluders in input order, not front to back (tests order independence) */
#define PVS_VISIBILITY_INPUT_ORDER 1u
#endif

/* The segments (and objects) reached from some cell point by a line segment crossing no other segment
   (touching an end point does not block; segments crossing the cell are visible): exact, rounding toward
   visible. visible_segments, visible_objects (PVS_BITSET_WORDS of segment_count, object_count words) are
   cleared first; they and stats may be NULL. Errors: INVALID_ARGUMENT, NOT_FINITE, INDEX_OUT_OF_RANGE,
   BAD_CELL (no area, not convex), OUT_OF_MEMORY. Thread-safe; allocates through desc->allocator. */
PVS_API pvs_result pvs_visibility_2d(const pvs_visibility_2d_desc *desc, pvs_word *visible_segments,
									 pvs_word *visible_objects, pvs_otree_stats *stats, pvs_error *err);

/* Conservative 2.5D from-region visibility, c-LSS (Bittner 2002, ch. 7), over ground (u, v) and height.
   Zero fields get defaults. */
typedef struct pvs_visibility_25d_desc {
	float cell_min[2], cell_max[2]; /* the cell's ground rectangle */
	float cell_top;                 /* the highest eye height in the cell */
	const float *facades;           /* facade_count x (u0, v0, u1, v1, top): opaque walls standing on the */
	uint32_t facade_count;          /*   ground, blocking every height below `top` */
	const float *objects; /* object_count x (umin, vmin, umax, vmax, top): object bounds; umin > umax = empty */
	uint32_t object_count;
	uint32_t node_budget;           /* per tree (0 = PVS_OTREE_25D_BUDGET) */
	const pvs_kdtree *tree;         /* NULL, or a kD-tree over pvs_visibility_25d_boxes (reused across cells) */
	pvs_allocator allocator;
	uint32_t flags;                 /* 0; other bits INVALID_ARGUMENT but the test hook PVS_VISIBILITY_25D_FULL_TESTS */
} pvs_visibility_25d_desc;

/* The default node budget of a 2.5D occlusion tree. Once spent, the remaining facades are not inserted
   (conservative); objects are still tested. It bounds the time per cell on maps of thousands of small
   facades (Quake 3 brushes) at almost no cost in tightness (tests/BENCHMARKS.md, otree). */
#define PVS_OTREE_25D_BUDGET (1u << 16)

#ifdef PVS_TEST_HOOKS /* internal: the library's own tests (CONFIGURATION) */
/* pvs_visibility_25d_desc.flags: box tests always walk the tree, without the witness-line shortcut (a
   remembered out-leaf line crossing the box): its slower reference, with the same result. */
#define PVS_VISIBILITY_25D_FULL_TESTS 1u
#endif

/* Fills boxes[facade_count + object_count] for pvs_visibility_25d_desc.tree: facade i is item i, object j
   item facade_count + j; axes (u, v, height up to the top). Build the tree once and share it between cells. */
PVS_API void pvs_visibility_25d_boxes(const float *facades, uint32_t facade_count, const float *objects,
									  uint32_t object_count, pvs_box *boxes);

/* The objects possibly visible from the cell (ground rectangle x heights up to cell_top), facades reaching
   down below every cell and object; never misses one. Facades crossing the cell are ignored.
   visible_objects: PVS_BITSET_WORDS(object_count) words, cleared first; stats may be NULL. Errors:
   INVALID_ARGUMENT, NOT_FINITE, OUT_OF_MEMORY. Thread-safe; allocates through desc->allocator. */
PVS_API pvs_result pvs_visibility_25d(const pvs_visibility_25d_desc *desc, pvs_word *visible_objects,
									  pvs_otree_stats *stats, pvs_error *err);

/* From-point culling with a shadow-volume occlusion tree (Bittner 2002, ch. 4), pvs_raster_cull's
   object-space twin: each frame the occluders are merged front to back into a BSP of planes through the eye;
   the object kD-tree is walked front to back against it (§4.10.2's conservative box test, refined at
   in-leaves by the exact "FME" test, Table 4.1), with hierarchy updating (§4.11.4) giving exactly the result
   of testing every node. Occluders (§4.5): the caller's triangles, the best `scene_occluders` by area-angle
   among the triangles of objects seen within `occluder_distance` last frame (after create or reset: all
   within it), and per `scene_volumes` BOX faces and EXTRUSION walls within it. */
typedef struct pvs_otree_desc {
	/* Required: sizes the per-node state; pvs_otree_cull accepts a scene no larger (objects, triangles,
	   kD-tree nodes). */
	const pvs_scene *scene;
	float aspect;                 /* image width / height for the frustum's side planes, 0 = 1 */
	uint32_t max_occluders;       /* scene polygons inserted per frame at most, 0 = 64; <= 65536 */
	uint32_t node_budget;         /* occlusion tree nodes per frame, 0 = 8192; 64..2^24 */
	uint32_t flags;               /* PVS_OTREE_* */
	pvs_allocator allocator;
} pvs_otree_desc;
#define PVS_OTREE_NO_COHERENCE 1u /* test every reached kD node every frame (the classical traversal, §4.11.2) */
#define PVS_OTREE_PLANE_ONLY 2u   /* in-leaves test the fragment's plane only ("FMC"), no box / fragment test */

/* A from-point culling context (node pool, last frame's kD node states), allocated once. One per thread. */
typedef struct pvs_otree pvs_otree;

/* What the last pvs_otree_cull did, beyond pvs_cull_stats. */
typedef struct pvs_otree_frame {
	uint32_t tree_nodes;          /* occlusion tree nodes (inner and leaves) */
	uint32_t fragments;           /* occluder fragments stored at in-leaves */
	uint32_t occluders;           /* polygons offered to the tree (caller triangles + scene polygons) */
	uint32_t node_tests;          /* kD nodes whose visibility was tested (frustum + tree) */
	uint32_t nodes_skipped;       /* opened kD nodes whose test hierarchy updating skipped */
	uint32_t object_tests;        /* object boxes tested in partly visible leaves */
	uint32_t budget_exceeded;     /* 1: the budget or a polygon's size stopped an insertion (conservative) */
} pvs_otree_frame;

/* Errors: INVALID_ARGUMENT, NOT_FINITE (aspect), COUNT_OVERFLOW, OUT_OF_MEMORY. */
PVS_API pvs_result pvs_otree_create(const pvs_otree_desc *desc, pvs_otree **out_otree, pvs_error *err);
/* Frees through its allocator; NULL allowed. */
PVS_API void pvs_otree_destroy(pvs_otree *otree);
/* Forgets the last frame (a camera cut): the next selects occluders by distance, tests every node. */
PVS_API void pvs_otree_reset(pvs_otree *otree);
/* Outputs as pvs_raster_cull (every plane test leans toward "visible"); `params` may be NULL, facades are
   ignored. Errors: INVALID_ARGUMENT, NOT_FINITE (camera), UNSUPPORTED (orthographic: shadow volumes need
   an eye point), BUFFER_TOO_SMALL (a scene larger than the context's). Allocates nothing. */
PVS_API pvs_result pvs_otree_cull(pvs_otree *otree, const pvs_scene *scene, const pvs_camera *camera,
								  const pvs_cull_params *params, pvs_word *visible, pvs_cull_stats *stats,
								  pvs_error *err);
/* Fills *frame with the figures of the last pvs_otree_cull. */
PVS_API void pvs_otree_get_frame(const pvs_otree *otree, pvs_otree_frame *frame);

/* ---- occluders ---- */

/* Occluder synthesis: certainly-solid volumes for the shrink method (Wonka 2000 §2: its appendix theorem
   needs volumetric occluders). A voxel is solid only when no viewer in any cell reaches it by a path
   touching no triangle, so sight lines through it meet a triangle first. This is proved per edge-connected
   component by crossing-parity floods from the cells (>>occluders, "certified solid"), never guessed from
   connectivity (a touched voxel may hide a narrower slit); voxels inside explicit occluder volumes are
   solid too. Openings narrower than a voxel stay open; a crack or T-junction (an open edge, used by an odd
   number of triangles) gives no volume along the vertical sheet below it; an enclosure made only by
   several meshes together is not recognised. The ground lies below the lowest point of scene and cells (no
   sight line between points above passes below). The solid set is eroded by eps (rounding toward less
   solid) into boxes (3D) and per-column heights on the ground (2.5D rectangles). Leaks: the few cells
   reaching the outside of a component's box that most cells lie in (poking through a wall into a faceless
   void) are left out of later floods, so the others keep their walls (pvs_occluders_excluded_cells). A
   flood of untouched voxels from the grid's border reports the cells it reaches (face-adjacent untouched
   voxels are a real free path). */
typedef struct pvs_occluders_desc {
	const pvs_scene *scene;   /* required; must outlive the occluders */
	const pvs_box *cells;     /* cell_count >= 1 view cells, the flood's sources (required) */
	uint32_t cell_count;
	float eps;                /* erosion distance, > 0 */
	float voxel_size;         /* 0 = derived: eps / 1.5, grown until the grid fits max_voxels */
	uint32_t max_voxels;      /* 0 = 1 << 24 */
	uint32_t flags;           /* PVS_OCCLUDERS_* */
	pvs_allocator allocator;
} pvs_occluders_desc;

/* Flag: every cell seeds the floods, leaking ones too (a leak then costs every cell the walls it opens).
   The bake uses it for a second synthesis that bakes the left-out cells. */
#define PVS_OCCLUDERS_KEEP_LEAKS 1u

/* The synthesized occluders: immutable, thread-safe to read. */
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
	int is_2d5;               /* 1 when column runs hold >= 90% of the solid voxels: use the 2.5D path */
	uint32_t leak_cell;       /* lowest cell reaching the grid's border (sky or leak), or PVS_NO_CELL */
	float leak_point[3];      /* a voxel centre of that cell on such a path */
	uint32_t leak_cells;      /* cells reaching the border */
	uint32_t excluded_cells;  /* leaking cells left out, with no occluder (< half of those in a component's box) */
	uint32_t thin_objects;    /* drawable objects with no solid voxel in their box (thin walls, props) */
	uint32_t components;      /* edge-connected triangle sets flooded (3 triangles or more) */
	uint32_t closed_components; /* of them, those without an open edge */
	uint64_t open_edges;      /* edges used by an odd number of triangles, off the ground level */
	uint64_t undecided_columns; /* voxel columns of a component where no test ray gave a certain parity */
} pvs_occluders_info;

/* Voxel classes pvs_occluders_voxel returns. */
#define PVS_VOXEL_EMPTY 0u    /* untouched and not solid */
#define PVS_VOXEL_TOUCHED 1u  /* a triangle touches it (and it is not solid) */
#define PVS_VOXEL_SOLID 2u    /* solid (before erosion); may hold triangles of another component */
#define PVS_VOXEL_GROUND 3u   /* the padding layer below the ground */

/* Deterministic; concurrent calls on distinct outputs are fine. Errors: INVALID_ARGUMENT (NULL, no cells,
   eps <= 0 or not finite), BAD_CELL, COUNT_OVERFLOW, OUT_OF_MEMORY. */
PVS_API pvs_result pvs_occluders_create(const pvs_occluders_desc *desc, pvs_occluders **out_occluders, pvs_error *err);
/* Frees through its allocator; NULL allowed. */
PVS_API void pvs_occluders_destroy(pvs_occluders *occluders);
/* Fills *info. */
PVS_API void pvs_occluders_get_info(const pvs_occluders *occluders, pvs_occluders_info *info);
/* The PVS_VOXEL_* class of voxel (i, j, k) along x, y, z (each < dims). */
PVS_API uint32_t pvs_occluders_voxel(const pvs_occluders *occluders, uint32_t i, uint32_t j, uint32_t k);
/* 1 if voxel (i, j, k) survived the erosion. */
PVS_API int pvs_occluders_eroded_voxel(const pvs_occluders *occluders, uint32_t i, uint32_t j, uint32_t k);
/* The eroded 3D boxes (*count), owned by occluders; every point within eps of one is solid. */
PVS_API const pvs_box *pvs_occluders_boxes(const pvs_occluders *occluders, uint32_t *count);
/* The shrunk 2.5D occluders as facade chains owned by occluders (base the ground, top lowered by eps):
   boundaries of the column map's regions at or above a height, closed, and of their holes, open back to
   the first point. Every point within eps of such a prism is unreachable or below the ground. */
PVS_API const pvs_facade_chain *pvs_occluders_columns(const pvs_occluders *occluders, uint32_t *count);
/* The column map at ground point (u, v): *solid the height below which the column is proved solid (else
   the ground), returns the shrunk occluder height (else -FLT_MAX); outside the map the ground and
   -FLT_MAX. On a square's edge the lower neighbour counts. */
PVS_API float pvs_occluders_column_height(const pvs_occluders *occluders, float u, float v, float *solid);
/* The left-out leaking cells (increasing indices into desc->cells) or NULL, owned by occluders:
   pvs_shrink_cell sets every object for them and boxes inside them. */
PVS_API const uint32_t *pvs_occluders_excluded_cells(const pvs_occluders *occluders, uint32_t *count);

/* ---- vocc ---- */

/* Virtual occluders (Koltun, Chrysanthou, Cohen-Or 2000): per cell a few large vertical rectangles in the
   umbra of the real occluders from the whole cell, together standing for its aggregate occlusion; five
   bytes each in the VOCC section, from which pvs_vocc_cull rebuilds the PVS on cell entry. */
struct pvs_file; /* >>format */

/* pvs_file.vocc_flags */
#define PVS_VOCC_STORED 1u /* the file has a VOCC section */
#define PVS_VOCC_ONLY 2u   /* ... and its records are placeholders (every drawable object): use pvs_vocc_cull */

/* The vertical rectangle over the ground segment p0-p1 (u, v as in pvs_scene_desc), from `base` to `top`. */
typedef struct pvs_virtual_occluder {
	float p0[2], p1[2];
	float base, top;
} pvs_virtual_occluder;

/* What a virtual-occluder construction did (sums over cells and slices). */
typedef struct pvs_vocc_stats {
	uint32_t slices;        /* height slices (§3.1) */
	uint32_t seeds;         /* seed objects grown (§3) */
	uint32_t umbra;         /* objects that augmented an aggregate umbra (cases 1 and 3 of §3) */
	uint32_t separating;    /* objects that only bent a separating line (case 2) */
	uint32_t dense;         /* certified virtual occluders put into the dense set */
	uint32_t dropped;       /* candidates that failed the final check (e.g. after quantization) */
	uint32_t selected;      /* kept by the greedy selection (Fig. 6) */
} pvs_vocc_stats;

/* The 2D construction of §3 on its own. Zero fields get defaults. */
typedef struct pvs_vocc_2d_desc {
	float cell_min[2], cell_max[2]; /* the view cell: an axis-aligned rectangle with area */
	/* segment_count x (x0, y0, x1, y1): opaque occluders; segments whose end points coincide exactly in a
	   ring (every point on two) are a wall loop. */
	const float *segments;
	uint32_t segment_count;
	uint32_t max_seeds;             /* seed objects grown, 0 = 16 */
	float range;                    /* analysis radius from the cell centre, 0 = reach every segment */
	pvs_allocator allocator;
} pvs_vocc_2d_desc;

/* The cell's dense set of 2D virtual occluders (§3: aggregate umbrae grown from seeds along supporting
   and separating lines), each kept only once checked exactly hidden from the whole cell (rounding up to a
   relative 1e-9, toward "not hidden"). Writes up to `capacity` (x0, y0, x1, y1) to `occluders` (NULL:
   count only), *count the number found. Segments meeting the cell are ignored; stats may be NULL.
   Errors: INVALID_ARGUMENT, NOT_FINITE, BAD_CELL, OUT_OF_MEMORY. Thread-safe; allocates through
   desc->allocator. */
PVS_API pvs_result pvs_vocc_2d(const pvs_vocc_2d_desc *desc, float *occluders, uint32_t capacity, uint32_t *count,
							   pvs_vocc_stats *stats, pvs_error *err);

/* 1 if `o` alone hides the box from the whole cell (the runtime's test): every segment between the
   ground rectangles crosses p0-p1, and the heights hold at each crossing fraction t (a sight line meets
   the occluder's plane at height (1 - t) eye + t target). Conservative under rounding; 0 for an empty box
   or a degenerate occluder. */
PVS_API int pvs_vocc_box_hidden(const pvs_box *cell, uint32_t up_axis, const pvs_virtual_occluder *o,
								const pvs_box *box);

/* Scratch bytes of pvs_vocc_cull* for up to max_occluders (a file stores <= 255 per cell) and the tree
   (may be NULL). */
PVS_API size_t pvs_vocc_cull_scratch_size(const pvs_kdtree *tree, uint32_t max_occluders);

/* Rebuilds a PVS (Koltun 2000 §2, §4): sets in `visible` (PVS_BITSET_WORDS(object_count) words, cleared
   first) every object with a non-empty box no single occluder hides (tried in order: most effective
   first). With a `tree` over the same boxes (item i = object i; leaves of 16+ items keep the walk short)
   a subtree is skipped when one occluder hides its node box, so an object whose parts lie behind
   different occluders may drop out too (still conservative); tree NULL tests every box. scratch:
   pvs_vocc_cull_scratch_size bytes, any alignment. Errors: INVALID_ARGUMENT, BUFFER_TOO_SMALL. Allocates
   nothing; thread-safe. */
PVS_API pvs_result pvs_vocc_cull_occluders(const pvs_box *cell, uint32_t up_axis, const pvs_virtual_occluder *occluders,
										   uint32_t count, const pvs_box *object_boxes, uint32_t object_count,
										   const pvs_kdtree *tree, void *scratch, size_t scratch_size,
										   pvs_word *visible, pvs_error *err);

/* pvs_vocc_cull_occluders on the file's first max_occluders (0 = all) of `cell`, with the engine's boxes
   and tree of the scene baked. INVALID_ARGUMENT also without a VOCC section. */
PVS_API pvs_result pvs_vocc_cull(const struct pvs_file *file, uint32_t cell, uint32_t max_occluders,
								 const pvs_box *object_boxes, uint32_t object_count, const pvs_kdtree *tree,
								 void *scratch, size_t scratch_size, pvs_word *visible, pvs_error *err);

/* ---- methods ---- */

/* Region methods (CONCEPTS, Methods); all but SAMPLE are conservative. 0 is the default: AUTO. */
typedef enum pvs_method {
	PVS_METHOD_DEFAULT = 0,
	PVS_METHOD_SAMPLE,       /* ray sampling: an estimate from below, NOT conservative */
	PVS_METHOD_OTREE,        /* 2.5D occlusion trees, c-LSS (Bittner 2002, ch. 7) on facades of vertical triangles */
	PVS_METHOD_EXTPROJ,      /* extended projections (Durand et al. 2000): 3D, planar occluders */
	PVS_METHOD_SHRINK,       /* occluder shrinking + point sampling (Wonka 2000) */
	PVS_METHOD_AUTO,         /* the conservative methods that apply, their PVSs intersected */
	PVS_METHOD_VOCC,         /* virtual occluders (Koltun 2000), 2.5D: stored, the PVS is what they rebuild */
	PVS_METHOD_COUNT
} pvs_method;

/* Name of a method ("sample"), or "unknown". */
PVS_API const char *pvs_method_name(pvs_method method);

/* The shrink method's paths. */
typedef enum pvs_shrink_mode {
	PVS_SHRINK_AUTO = 0,     /* 2.5D when the occluders are (pvs_occluders_info.is_2d5), else 3D */
	PVS_SHRINK_2D5,          /* Wonka 2000 §3: column occluders, samples on the cell's top face, cull maps */
	PVS_SHRINK_3D,           /* samples on the six faces, from-point depth maps of the eroded boxes */
	PVS_SHRINK_MODE_COUNT
} pvs_shrink_mode;

/* What one pvs_shrink_cell call did. */
typedef struct pvs_shrink_stats {
	pvs_shrink_mode mode;     /* the path that ran */
	uint32_t occluders;       /* occluders of that path: column prisms (2.5D) or boxes (3D) */
	int no_occluders;         /* 1: none survived erosion, every drawable object set without sampling */
	int excluded;             /* 1: the cell lies in a left-out leaking cell, every drawable object set */
	uint32_t samples;         /* sample points */
	uint64_t occluders_drawn; /* occluders rasterized, summed over the samples (after §3.4's rejection) */
	uint32_t hidden;          /* drawable objects left out of the PVS */
} pvs_shrink_stats;

/* The shrink method for one cell (Wonka, Wimmer, Schmalstieg 2000): occluders eroded by eps, sampled from
   the cell every eps; an object is left out only when every sample sees it hidden (appendix theorem: then
   every point of the cell does). Objects meeting the cell or under its top face stay. Sets bits in
   `visible` (PVS_BITSET_WORDS(object_count) words, not cleared), never occluder-only ones; objects set on
   entry are not tested (AUTO presets what the others culled). `occluders` must be this scene's; `stats`
   may be NULL; no occluders is no error. Scratch from the occluders' allocator, freed on return:
   thread-safe. Errors: INVALID_ARGUMENT, BAD_CELL, UNSUPPORTED (a path this build cannot run, with the
   reason), OUT_OF_MEMORY. */
PVS_API pvs_result pvs_shrink_cell(const pvs_scene *scene, const pvs_occluders *occluders, const pvs_box *cell,
								   pvs_shrink_mode mode, pvs_word *visible, pvs_shrink_stats *stats, pvs_error *err);

/* The estimator: `points` stratified points in `cell` (corners and face centres, then a jittered grid),
   `rays_per_point` uniform directions each; sets the first object each ray hits in `visible`
   (PVS_BITSET_WORDS(object_count) words, not cleared; never occluder-only ones). A lower bound, the
   tests' and pvscheck's yardstick. Deterministic in `seed`; thread-safe, no allocation. Returns the rays. */
PVS_API uint64_t pvs_sample_visibility(const pvs_scene *scene, const pvs_box *cell, uint32_t points,
									   uint32_t rays_per_point, uint64_t seed, pvs_word *visible);

/* Aimed sampling, a better lower bound for small and far objects: for each object of `targets` (NULL: all)
   not in `visible`, up to `rays_per_object` segments from a uniform point of `cell` to a point of one of
   its triangles (uniform, pulled 1% toward the centroid) until one reaches it; each sets the first object
   it hits. Occluder-only objects are neither set nor aimed at. Otherwise as pvs_sample_visibility. */
PVS_API uint64_t pvs_sample_visibility_toward(const pvs_scene *scene, const pvs_box *cell, const pvs_word *targets,
											  uint32_t rays_per_object, uint64_t seed, pvs_word *visible);

/* ---- extended projections (Durand, Drettakis, Thollot, Puech 2000) ---- */

/* A projection plane (Durand 2000 §2.4, §6.1) perpendicular to `axis`, `distance` > 0 beyond the cell's
   face on `side` (+1: max, -1: min); Depth (§2.3) is the distance past that face. rect = (u0, v0, u1, v1)
   over u = (axis + 1) % 3, v = (axis + 2) % 3 in width x height pixels (pixel (i, j): u0 + [i, i + 1] *
   (u1 - u0) / width, v likewise). A depth map: width * height floats, row j first, per pixel the nearest
   occluder Projection's Depth or PVS_EXTPROJ_EMPTY. */
typedef struct pvs_extproj_plane {
	pvs_box cell;
	uint32_t axis;
	int32_t side;
	float distance;
	float rect[4];
	uint32_t width, height;   /* 1..4096 each */
} pvs_extproj_plane;
#define PVS_EXTPROJ_EMPTY 3.402823466e+38f
#define PVS_EXTPROJ_SWEEP_PLANES 16u /* sweep planes per direction pvsbake --sweep asks for, and AUTO's default */
#define PVS_EXTPROJ_NO_SWEEP 0xffffffffu /* pvs_bake_desc.extproj.sweep: AUTO without the sweep */
#define PVS_EXTPROJ_RESOLUTION 256u /* pixels per plane side when pvs_bake_desc.extproj.resolution is 0 */
#define PVS_EXTPROJ_PREVIEW_RESOLUTION 64u /* the same with PVS_BAKE_PREVIEW */

/* Adds one convex occluder's extended Projection (§3.2): `points` (1..16 x (x, y, z)), a planar convex
   polygon or a closed convex solid (skipped if its box meets the cell: it could hold the viewer); clipped
   to depths > 0 and split at the plane. Only pixels a part covers from every point of the cell (its views
   from the 8 corners intersected) get min(stored, the part's greatest depth, §2.3). Returns the pixel
   writes per part, 0 if none or on bad arguments. Thread-safe on distinct maps; no allocation. */
PVS_API uint32_t pvs_extproj_occluder(const pvs_extproj_plane *plane, const float *points, uint32_t count,
									  float *depth_map);

/* An occludee box's extended Projection (§3.1): the bounding rectangle of its views from the whole cell,
   holding every pixel the box touches from any cell point, as inclusive pixel bounds rect = (i0, j0, i1, j1),
   maybe off the map, and its least Depth. Returns 0 when the box is not wholly beyond the face (this plane
   cannot decide it), else 1. No allocation. */
PVS_API int pvs_extproj_occludee(const pvs_extproj_plane *plane, const pvs_box *box, int32_t rect[4], float *depth);

/* 1 if some pixel of the occludee's rect is off the map or stores a Depth >= depth; 0: hidden (§2.2). */
PVS_API int pvs_extproj_test(const pvs_extproj_plane *plane, const float *depth_map, const int32_t rect[4],
							 float depth);

/* Bytes an EXTPROJ task allocates for its planes at `resolution` (0 = 256) and `sweep` planes per direction
   (0: none; MEMORY), not counting scratch that grows with the occluders; 0 outside 16..4096 or past 256 planes. For
   tools fitting their threads to the memory. */
PVS_API size_t pvs_extproj_task_bytes(uint32_t resolution, uint32_t sweep);

/* ---- bake ---- */

/* SAMPLE's parameters (pvs_bake_desc.sample). */
typedef struct pvs_bake_sample_params {
	uint32_t points;          /* points per cell, 0 = 32 */
	uint32_t rays;            /* rays per point, 0 = 2048 */
	uint64_t seed;            /* random seed */
} pvs_bake_sample_params;

/* EXTPROJ's parameters (also under AUTO). */
typedef struct pvs_bake_extproj_params {
	/* Pixels per plane side, 16..4096; 0 = PVS_EXTPROJ_RESOLUTION, with PREVIEW PVS_EXTPROJ_PREVIEW_RESOLUTION.
	   Sweep planes spread them square over what cell and scene span. */
	uint32_t resolution;
	uint32_t occluders;       /* occluders on the planes of §6.1, 0 = 128; <= 65536 (sweep planes take all) */
	/* Occlusion sweep (Durand 2000 §5) planes per direction, <= 256, 0 = none; under AUTO 0 =
	   PVS_EXTPROJ_SWEEP_PLANES (PREVIEW: none), PVS_EXTPROJ_NO_SWEEP = none. An object whose box is not
	   hidden is then kept only if a part of its triangles may be seen (over 16,384 triangles: by box). */
	uint32_t sweep;
	/* With the sweep, 4: each plane holds the union of the umbrae of the cell's four quarters, and an object
	   must be hidden from each (tighter on foliage, for a few times the time: tests/BENCHMARKS.md,
	   extproj); 0 or 1: the cell's umbra. */
	uint32_t sweep_subcells;
} pvs_bake_extproj_params;

/* Adaptive cells (CONCEPTS): split while a PVS holds more than `budget` triangles and the halves are at
   least `min_size`; leaves low half first. Not with shards. */
typedef struct pvs_bake_adaptive_params {
	uint32_t budget;          /* triangles per leaf cell's PVS; 0 = off */
	float min_size;           /* shortest half, 0 = an eighth of the cell's longest side */
} pvs_bake_adaptive_params;

/* SHRINK's parameters (also under AUTO). */
typedef struct pvs_bake_shrink_params {
	pvs_shrink_mode mode;     /* path, PVS_SHRINK_AUTO picks */
	float voxel_size;         /* occluder synthesis voxel size, 0 = derived */
} pvs_bake_shrink_params;

/* VOCC's parameters. */
typedef struct pvs_bake_vocc_params {
	uint32_t slices;          /* height slices per cell (§3.1), 0 = 5; 1..16 */
	uint32_t max_occluders;   /* virtual occluders kept per cell (Fig. 6), 0 = 10; 1..255 */
	uint32_t only;            /* 1 = store only the occluders (PVS_VOCC_ONLY) */
} pvs_bake_vocc_params;

/* OTREE's parameters (also under AUTO). */
typedef struct pvs_bake_otree_params {
	uint32_t node_budget;     /* per tree, 0 = PVS_OTREE_25D_BUDGET; 64..2^24. More never hides less; with
								 many small facades time grows faster than it */
} pvs_bake_otree_params;

/* What to bake. Zero fields and per-method parameters get defaults. */
typedef struct pvs_bake_desc {
	const pvs_scene *scene;   /* must outlive the bake */
	const pvs_box *cells;     /* cell_count view cells, copied */
	uint32_t cell_count;
	pvs_method method;        /* PVS_METHOD_DEFAULT = AUTO */
	float eps;                /* sampling / shrinking distance; 0 = derived from the cells */
	uint32_t max_chain;       /* file: bound K on delta chains, 0 = PVS_DEFAULT_CHAIN */
	/* Shards (build farms), shard_count >= 2: bakes cells shard_index, shard_index + shard_count, ... into a
	   part file; parts 0..shard_count-1 decoded and encoded whole (pvs_file_encode) give the unsharded file. */
	uint32_t shard_index, shard_count;
	uint32_t methods;         /* AUTO's candidates: 1u << PVS_METHOD_* (not SAMPLE, DEFAULT, AUTO); 0: all but VOCC */
	float max_distance;       /* draw distance: drop objects whose box is farther from every cell point; 0: none */
	uint32_t flags;           /* PVS_BAKE_* */
	pvs_bake_sample_params sample;
	pvs_bake_extproj_params extproj;
	pvs_bake_adaptive_params adaptive;
	pvs_bake_shrink_params shrink;
	pvs_bake_vocc_params vocc;
	pvs_bake_otree_params otree;
	pvs_allocator allocator;
} pvs_bake_desc;

/* AUTO's sample (pvs_bake_begin): cells baked with every applicable method to choose those worth running, and the
   least share of the kept PVS a method must cull beyond the methods kept to be run on every cell. */
#define PVS_AUTO_SAMPLE_CELLS 8u
#define PVS_AUTO_MIN_GAIN 0.02

/* PVS_BAKE_PREVIEW: fast, coarse, conservative. AUTO runs only the cheapest applicable method. EXTPROJ
   uses 64 pixels and 32 occluders per plane unless set, no sweep, and decides object kD-tree nodes whole
   once under a quarter radian or past 4,096 box tests: a few milliseconds per cell at any scene size
   (tests/BENCHMARKS.md, bake). SHRINK doubles its derived eps. */
#define PVS_BAKE_PREVIEW 1u

typedef struct pvs_bake pvs_bake;

/* Validates the desc and prepares the tasks. Errors: INVALID_ARGUMENT, BAD_CELL (err->index = cell),
   NOT_FINITE, OUT_OF_MEMORY. */
PVS_API pvs_result pvs_bake_begin(const pvs_bake_desc *desc, pvs_bake **out_bake, pvs_error *err);
/* Tasks: today one per cell of the shard. */
PVS_API uint32_t pvs_bake_task_count(const pvs_bake *bake);
/* The cell a task bakes. */
PVS_API uint32_t pvs_bake_task_cell(const pvs_bake *bake, uint32_t task);
/* Runs one task. Thread-safe for distinct tasks; each has its own scratch. */
PVS_API pvs_result pvs_bake_run_task(pvs_bake *bake, uint32_t task, pvs_error *err);
/* The resolved method and eps. */
PVS_API pvs_method pvs_bake_method(const pvs_bake *bake);
PVS_API float pvs_bake_eps(const pvs_bake *bake);
/* The methods considered, in run order; AUTO lists those skipped (ran = 0) as unable to cull here. */
PVS_API uint32_t pvs_bake_method_count(const pvs_bake *bake);
/* What method i did, summed over the tasks run (not restored). */
typedef struct pvs_bake_method_info {
	pvs_method method;
	int ran;                  /* 1: every task runs it; 0: skipped */
	const char *reason;       /* why it runs or was skipped (a constant string, never NULL) */
	uint32_t cells;           /* tasks that ran it */
	uint64_t pvs_sum;         /* sum over those cells of the PVS size this method found alone */
	/* (cell, drawable object) pairs only it left out of the intersection; one a later method did not test
	   (kept_only) counts for those that culled it. */
	uint64_t sole_culls;
	/* 1: it tested only what earlier methods kept (AUTO runs SHRINK last: the same intersection, far less
	   time); pvs_sum counts their culls as kept. */
	int kept_only;
	/* AUTO's sample (sample_cells > 0): objects per sample cell it culled beyond the methods kept before it (a
	   skipped one: beyond all those kept) */
	uint32_t sample_cells;
	float sample_gain;
} pvs_bake_method_info;
/* Fills *info for i < pvs_bake_method_count, else INVALID_ARGUMENT (also for NULL). Not concurrently with
   pvs_bake_run_task. */
PVS_API pvs_result pvs_bake_get_method_info(const pvs_bake *bake, uint32_t i, pvs_bake_method_info *info);
/* 1 if the task has run (or was restored). */
PVS_API int pvs_bake_task_done(const pvs_bake *bake, uint32_t task);
/* Resumes: marks a task done with its PVS from an earlier run of the same scene, cells and parameters;
   `bits`: word_count >= PVS_BITSET_WORDS(object_count), zero past object_count. Thread-safe like
   pvs_bake_run_task. Errors: INVALID_ARGUMENT (task out of range, NULL, a bit past the objects or of an
   occluder-only object), BUFFER_TOO_SMALL, UNSUPPORTED (VOCC bakes its occluders). */
PVS_API pvs_result pvs_bake_restore_task(pvs_bake *bake, uint32_t task, const pvs_word *bits, size_t word_count,
										 pvs_error *err);
/* SHRINK (alone or in AUTO): the synthesized occluders (the bake's) and the tasks' path; NULL /
   PVS_SHRINK_AUTO when SHRINK was not prepared. */
PVS_API const pvs_occluders *pvs_bake_occluders(const pvs_bake *bake);
PVS_API pvs_shrink_mode pvs_bake_shrink_mode(const pvs_bake *bake);
/* The facades OTREE found: merged coplanar vertical triangles, each a wall segment with the height range
   [base, top] it covers along its length. A cell uses a facade only toward objects whose bottom, like its
   own, is at or above the facade's level (the lowest of at most eight base heights at or above its base):
   a ray could pass under it. facades == 0: nothing is culled. All zero when OTREE was not prepared. */
typedef struct pvs_otree_bake_info {
	uint32_t prepared;           /* 1 when the bake prepared OTREE */
	uint32_t vertical_triangles; /* triangles of the scene standing vertical */
	uint32_t facades;            /* facades in use (base no higher than the highest cell bottom) */
	uint32_t levels;             /* distinct base heights in use */
	float lowest_level;          /* the lowest of them (when levels > 0) */
} pvs_otree_bake_info;
PVS_API void pvs_bake_get_otree_info(const pvs_bake *bake, pvs_otree_bake_info *info);
/* A VOCC bake's statistics summed over the cells baked so far (zeros for other methods). */
PVS_API void pvs_bake_get_vocc_stats(const pvs_bake *bake, pvs_vocc_stats *out);
/* Counts over the tasks run: culling nothing is conservative, not an error, but worth reporting. */
typedef struct pvs_bake_report {
	uint32_t cells;              /* tasks run so far */
	uint32_t cells_all_visible;  /* cells whose PVS holds every drawable object */
	/* Cells without occluders: SHRINK, none survived erosion (thin walls, or eps too large); OTREE, no usable
	   facade; AUTO, neither and nothing culled. */
	uint32_t cells_no_occluders;
	uint32_t cells_excluded;     /* SHRINK: leaking cells left out, baked with a second synthesis */
	uint32_t cells_otree_budget; /* OTREE: cells whose tree hit otree.node_budget (more may cull more) */
} pvs_bake_report;
/* Fills *report. Not concurrently with the tasks. */
PVS_API void pvs_bake_get_report(const pvs_bake *bake, pvs_bake_report *report);
/* A run cell's PVS (PVS_BITSET_WORDS(object_count) words; adaptive: the whole cell's), else NULL. */
PVS_API const pvs_word *pvs_bake_cell_pvs(const pvs_bake *bake, uint32_t cell);
/* The cells the file will hold: cell_count, or the adaptive leaves of the tasks run so far. */
PVS_API uint32_t pvs_bake_leaf_count(const pvs_bake *bake);
/* The exact file size, 0 before every task has run or on error. It encodes to measure: keep the number. */
PVS_API size_t pvs_bake_file_size(const pvs_bake *bake);
/* Writes the file (a part file for a shard) into out[0..capacity); *out_size gets the size, also with
   BUFFER_TOO_SMALL. Errors: NOT_DONE, BUFFER_TOO_SMALL, COUNT_OVERFLOW, OUT_OF_MEMORY. */
PVS_API pvs_result pvs_bake_write_file(const pvs_bake *bake, void *out, size_t capacity, size_t *out_size,
									   pvs_error *err);
/* Frees through its allocator; NULL allowed. */
PVS_API void pvs_bake_destroy(pvs_bake *bake);

/* ---- format ---- */

/* File flags. */
#define PVS_FILE_APPROXIMATE 1u /* baked by an estimator (SAMPLE): not conservative */

#define PVS_DEFAULT_CHAIN 8u    /* default bound K on a cell's delta chain */
#define PVS_MAX_CHAIN 64u       /* largest K a file may declare */

/* A PVS table to encode: cell_count bitsets of PVS_BITSET_WORDS(object_count) words. The encoder (Durand
   et al. 2000, §6.2; FILE FORMAT) picks bases by a depth-bounded minimum spanning tree over nearest
   neighbours weighted by coded delta size. */
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
	/* A part file (shard_count >= 2) holds cells shard_index, shard_index + shard_count, ... of
	   total_cell_count, in order. Zero for a whole file. */
	uint32_t shard_index, shard_count, total_cell_count;
	/* Optional VOCC section (NULL vocc_counts: none): per cell, in table order, vocc_counts[c] five-byte
	   occluders in virtual_occluders, scale code vocc_scales[c]; heights vocc_base + byte * vocc_height_step
	   (finite, step > 0); vocc_flags PVS_VOCC_ONLY for a placeholder table. */
	const uint8_t *vocc_counts, *vocc_scales, *virtual_occluders;
	uint32_t vocc_stride;      /* bytes from one cell's occluders to the next; 0 = back to back */
	float vocc_base, vocc_height_step;
	uint32_t vocc_flags;
	pvs_allocator allocator;   /* the encoder's scratch */
} pvs_file_desc;

/* Encodes the table into out[0..capacity), deterministically; *out_size gets the exact size, also with
   BUFFER_TOO_SMALL; out == NULL only measures. Scratch from desc->allocator; thread-safe for distinct
   outputs. Errors: INVALID_ARGUMENT, BAD_CELL, BUFFER_TOO_SMALL, COUNT_OVERFLOW (over 4 GiB), OUT_OF_MEMORY. */
PVS_API pvs_result pvs_file_encode(const pvs_file_desc *desc, void *out, size_t capacity, size_t *out_size,
								   pvs_error *err);

/* An opened file: a view of the caller's bytes, which must stay alive and unchanged. Plain data, copy
   freely; read-only to the caller, `private_` the reader's. */
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
	uint32_t vocc_flags;       /* PVS_VOCC_*: 0 when the file has no virtual occluders */
	uint32_t virtual_occluder_count;     /* VOCC: occluders stored, all cells */
	float vocc_base, vocc_height_step;   /* VOCC: top = base + byte * step */
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

/* Checks every FILE FORMAT rule (Trust; linear time, no allocation, no read outside data[0..size)), fills
   *file. Errors: INVALID_ARGUMENT, BAD_MAGIC, BAD_VERSION, TRUNCATED, BAD_HEADER, BAD_SECTION, CHECKSUM,
   BAD_CELL, BAD_TREE, BAD_RECORD, OBJECT_OUT_OF_RANGE, BAD_CHAIN; err->offset the offending byte,
   err->index the cell or section. */
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
PVS_API void pvs_file_get_record_info(const pvs_file *file, uint32_t cell, pvs_record_info *info);

/* A cell's virtual occluders, most effective first: returns their number (0 without VOCC), writes up to
   `capacity`. End points rounded to float; pvs_vocc_cull uses the exact ones. */
PVS_API uint32_t pvs_file_virtual_occluders(const pvs_file *file, uint32_t cell, pvs_virtual_occluder *out,
											uint32_t capacity);

/* A cell's raw VOCC record: returns its occluder count (0 without VOCC), *bytes their five bytes each in
   the file, *scale_code its scale (FILE FORMAT); either output may be NULL. For pvsbake merge. */
PVS_API uint32_t pvs_file_vocc_record(const pvs_file *file, uint32_t cell, uint32_t *scale_code, const uint8_t **bytes);

/* ---- runtime ---- */

#define PVS_NO_CELL 0xffffffffu
/* The lowest cell whose closed box contains p, or PVS_NO_CELL (also for non-finite p). No allocation. */
PVS_API uint32_t pvs_file_find_cell(const pvs_file *file, const float p[3]);
/* The box of a cell (< cell_count). */
PVS_API pvs_box pvs_file_cell_box(const pvs_file *file, uint32_t cell);
/* Decodes a cell's PVS into bits[0..word_count) (>= PVS_BITSET_WORDS(object_count), cleared first): the
   chain's key, then at most max_chain deltas. Errors: INVALID_ARGUMENT, BUFFER_TOO_SMALL. No allocation. */
PVS_API pvs_result pvs_file_decode(const pvs_file *file, uint32_t cell, pvs_word *bits, size_t word_count,
								   pvs_error *err);

/* Called per object whose visibility changes: visible = 1 added, 0 removed. */
typedef void (*pvs_change_fn)(void *user, uint32_t object, int visible);

/* Follows a viewer, reporting only the objects that change (Durand et al. 2000, §6.2): moving to a cell
   whose base is the current one applies that delta; other moves decode into scratch and compare. Plain
   data over caller memory; no allocation. */
typedef struct pvs_cursor {
	const pvs_file *file;
	uint32_t cell;             /* current cell, PVS_NO_CELL before the first move */
	pvs_word *bits;            /* the current PVS (read it, do not write it) */
	pvs_word *scratch;
	size_t word_count;
	uint64_t delta_moves, full_moves; /* statistics: moves by one delta, by a full decode */
} pvs_cursor;

/* Starts with an empty set. bits, scratch: distinct, word_count >= PVS_BITSET_WORDS(object_count) words
   each. Errors: INVALID_ARGUMENT, BUFFER_TOO_SMALL. */
PVS_API pvs_result pvs_cursor_init(pvs_cursor *cursor, const pvs_file *file, pvs_word *bits, pvs_word *scratch,
								   size_t word_count, pvs_error *err);
/* Moves to `cell` (PVS_NO_CELL empties the set), calling on_change (may be NULL) once per object entering
   or leaving: ascending ids after a full decode, removals then additions (each ascending) after a delta.
   INVALID_ARGUMENT for a cell out of range. */
PVS_API pvs_result pvs_cursor_move(pvs_cursor *cursor, uint32_t cell, pvs_change_fn on_change, void *user);

#ifdef __cplusplus
}
#endif
#endif /* PVS_H */

/* ======== Stop reading here if you only use the API. ======== */

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
#ifndef PVS_QSORT
#include <stdlib.h>
#define PVS_QSORT(base, n, size, cmp) qsort(base, n, size, cmp)
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
/* the test hooks' flags (PVS_TEST_HOOKS), under private names the implementation always knows */
#define PVS__VISIBILITY_INPUT_ORDER 1u
#define PVS__VISIBILITY_25D_FULL_TESTS 1u

// >>core
/* ---------------------------------------------------------------------------------------------- */
/* core: result strings, allocator, errors, math, bitsets                                         */
/* ---------------------------------------------------------------------------------------------- */

/* The shared kernels, written once for every module:
   - errors and checked sizes: pvs__fail, pvs__ok, pvs__mul; allocation through the hooks: pvs__alloc, pvs__free,
	 pvs__alloc_array, pvs__free_array; growable arrays: pvs__grow_capped, pvs__grow_array, pvs__grow;
   - math and boxes (pvs__dmin, pvs__clampi, pvs__finite, pvs__box_distance2, ...), bitsets, random numbers
	 (pvs__splitmix64, pvs__random01);
   - allocation-free heaps: pvs__heap_sort, pvs__topk_offer, pvs__pq_push / pvs__pq_pop, pvs__key_index_sort (big
	 bake-time sorts use PVS_QSORT); union-find: pvs__uf_find;
   - little-endian bytes (pvs__get32, pvs__put32, pvs__getf32, pvs__putf32) and pvs__crc32;
   - the bake's method-table interface (pvs__bake_method; the table is in >>bake).
   One kD-tree and its front-to-back sweep (pvs__kd_sweep) live in >>kdtree; one depth-pyramid level builder
   (pvs__pyramid_level) in >>raster. */

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
PVS__STATIC pvs_result pvs__fail(pvs_error *err, pvs_result code, int64_t index, uint64_t offset, const char *fmt,
								 ...) {
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
PVS__STATIC pvs__v3 pvs__v3_sub(pvs__v3 a, pvs__v3 b) { return pvs__v3_make(a.x - b.x, a.y - b.y, a.z - b.z); }
PVS__STATIC float pvs__v3_dot(pvs__v3 a, pvs__v3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
PVS__STATIC float pvs__v3_length(pvs__v3 a) { return sqrtf(pvs__v3_dot(a, a)); }

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
/* Cuts b to `by`; 1 if something (a point at least) is left. */
PVS__STATIC int pvs__box_clip(pvs_box *b, const pvs_box *by) {
	int i;
	for (i = 0; i < 3; ++i) {
		if (by->min[i] > b->min[i]) b->min[i] = by->min[i];
		if (by->max[i] < b->max[i]) b->max[i] = by->max[i];
	}
	return b->min[0] <= b->max[0] && b->min[1] <= b->max[1] && b->min[2] <= b->max[2];
}
PVS__STATIC double pvs__box_diagonal(const pvs_box *b) {
	double dx = (double)b->max[0] - b->min[0], dy = (double)b->max[1] - b->min[1], dz = (double)b->max[2] - b->min[2];
	return sqrt(dx * dx + dy * dy + dz * dz);
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

/* splitmix64 (Steele et al. 2014): deterministic random numbers for the samplers. */
PVS__STATIC uint64_t pvs__splitmix64(uint64_t *state) {
	uint64_t z = (*state += 0x9e3779b97f4a7c15ull);
	z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
	z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
	return z ^ (z >> 31);
}
/* Uniform float in [0, 1). */
PVS__STATIC float pvs__random01(uint64_t *state) {
	return (float)(pvs__splitmix64(state) >> 40) * (1.0f / 16777216.0f);
}

/* ---- growable arrays ---- */

/* Grows an array of `elem`-byte elements to hold `need` (doubling), keeping the first `used`, capped at `limit`
   when limit >= need (a bound the caller proved). Returns the array, or NULL with *r set (the old one still the
   caller's). */
PVS__STATIC void *pvs__grow_capped(const pvs_allocator *a, void *p, size_t *capacity, size_t used, size_t need,
								   size_t limit, size_t elem, pvs_result *r) {
	size_t cap = *capacity ? *capacity : 64, bytes;
	void *q;
	if (need <= *capacity) return p;
	while (cap < need) {
		if (cap > (size_t)-1 / 2) { *r = PVS_ERROR_COUNT_OVERFLOW; return NULL; }
		cap *= 2;
	}
	if (limit >= need && cap > limit) cap = limit;
	if (!pvs__mul(cap, elem, &bytes)) { *r = PVS_ERROR_COUNT_OVERFLOW; return NULL; }
	q = pvs__alloc_array(a, cap, elem);
	if (!q) { *r = PVS_ERROR_OUT_OF_MEMORY; return NULL; }
	if (used) memcpy(q, p, used * elem);
	pvs__free_array(a, p, *capacity, elem);
	*capacity = cap;
	return q;
}
/* The same without a limit. */
PVS__STATIC void *pvs__grow_array(const pvs_allocator *a, void *p, size_t *capacity, size_t used, size_t need,
								  size_t elem, pvs_result *r) {
	return pvs__grow_capped(a, p, capacity, used, need, 0, elem, r);
}
/* The same for a fully used array (*p, *capacity elements): 1 when it holds `need`, 0 on overflow or out of memory
   (*p unchanged, still the caller's). */
PVS__STATIC int pvs__grow(const pvs_allocator *a, void **p, size_t *capacity, size_t need, size_t elem) {
	pvs_result r;
	void *q;
	if (need <= *capacity) return 1;
	q = pvs__grow_capped(a, *p, capacity, *capacity, need, 0, elem, &r);
	if (!q) return 0;
	*p = q;
	return 1;
}

/* ---- heaps: sorting and top-k, allocation-free ---- */

/* 1 when a ranks before b: the order of a sort (ascending) or of a top-k selection (the best first). */
typedef int (*pvs__before_fn)(const void *a, const void *b);

/* Sifts element r of heap h (n elements of `size` <= 64 bytes) down: the root ranks last. */
PVS__STATIC void pvs__heap_sift(unsigned char *h, size_t size, size_t r, size_t n, pvs__before_fn before) {
	unsigned char t[64];
	for (;;) {
		size_t c = 2 * r + 1;
		if (c >= n) return;
		if (c + 1 < n && before(h + c * size, h + (c + 1) * size)) ++c;
		if (!before(h + r * size, h + c * size)) return;
		memcpy(t, h + r * size, size);
		memcpy(h + r * size, h + c * size, size);
		memcpy(h + c * size, t, size);
		r = c;
	}
}

/* Heap sort (Williams 1964) of base[0 .. n) (elements of `size` <= 64 bytes) in `before` order: no allocation and
   no libc, so the per-frame and file paths use it too. With a total order (ties broken by an index) the result is
   the same on every platform. */
PVS__STATIC void pvs__heap_sort(void *base, size_t n, size_t size, pvs__before_fn before) {
	unsigned char *h = (unsigned char *)base, t[64];
	size_t i;
	PVS_ASSERT(size <= sizeof(t));
	if (n < 2) return;
	for (i = n / 2; i-- > 0;) pvs__heap_sift(h, size, i, n, before);
	for (i = n - 1; i > 0; --i) {
		memcpy(t, h, size);
		memcpy(h, h + i * size, size);
		memcpy(h + i * size, t, size);
		pvs__heap_sift(h, size, 0, i, before);
	}
}

/* Top-k: `heap` holds *count <= k elements of `size` <= 64 bytes, its root ranking last. e is kept when there is
   room, or when it ranks before the root, which it replaces (an equal one does not). */
PVS__STATIC void pvs__topk_offer(void *heap, uint32_t *count, uint32_t k, size_t size, const void *e,
								 pvs__before_fn before) {
	unsigned char *h = (unsigned char *)heap;
	size_t i, c, n = *count;
	if (n < k) {
		for (i = (*count)++; i > 0 && before(h + (i - 1) / 2 * size, e); i = (i - 1) / 2)
			memcpy(h + i * size, h + (i - 1) / 2 * size, size);
		memcpy(h + i * size, e, size);
		return;
	}
	if (!k || !before(e, h)) return;
	for (i = 0; (c = 2 * i + 1) < n; i = c) {
		if (c + 1 < n && before(h + c * size, h + (c + 1) * size)) ++c; /* the child that ranks last */
		if (!before(e, h + c * size)) break;
		memcpy(h + i * size, h + c * size, size);
	}
	memcpy(h + i * size, e, size);
}

/* Priority queue: a binary heap of *n elements of `size` <= 64 bytes with the one ranking first at the root. push adds
   e; pop removes the root into *top. Equal elements leave in an order fixed by the pushes, the same everywhere. */
PVS__STATIC void pvs__pq_push(void *heap, size_t *n, size_t size, const void *e, pvs__before_fn before) {
	unsigned char *h = (unsigned char *)heap;
	size_t i;
	for (i = (*n)++; i > 0 && before(e, h + (i - 1) / 2 * size); i = (i - 1) / 2)
		memcpy(h + i * size, h + (i - 1) / 2 * size, size);
	memcpy(h + i * size, e, size);
}
PVS__STATIC void pvs__pq_pop(void *heap, size_t *n, size_t size, void *top, pvs__before_fn before) {
	unsigned char *h = (unsigned char *)heap, *last;
	size_t i = 0, c;
	memcpy(top, h, size);
	if (!--*n) return;
	last = h + *n * size;
	while ((c = 2 * i + 1) < *n) {
		if (c + 1 < *n && before(h + (c + 1) * size, h + c * size)) ++c;
		if (!before(h + c * size, last)) break;
		memcpy(h + i * size, h + c * size, size);
		i = c;
	}
	memcpy(h + i * size, last, size);
}

/* Union-find: the root of x's set, halving the path on the way (Tarjan and van Leeuwen 1984). */
PVS__STATIC uint32_t pvs__uf_find(uint32_t *parent, uint32_t x) {
	while (parent[x] != x) {
		parent[x] = parent[parent[x]];
		x = parent[x];
	}
	return x;
}

/* A sort key and the index of what it sorts. */
typedef struct pvs__key_index {
	double key;
	uint32_t index;
} pvs__key_index;

/* (key, index) ascending: a total order for keys that are not NaN. */
PVS__STATIC int pvs__key_index_before(const void *pa, const void *pb) {
	const pvs__key_index *a = (const pvs__key_index *)pa, *b = (const pvs__key_index *)pb;
	return a->key < b->key || (a->key == b->key && a->index < b->index);
}
PVS__STATIC void pvs__key_index_sort(pvs__key_index *o, uint32_t n) {
	pvs__heap_sort(o, n, sizeof(*o), pvs__key_index_before);
}

/* ---- little-endian bytes: the file format and the VOCC section ---- */

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

/* CRC-32 (IEEE 802.3, reflected polynomial 0xEDB88320), two nibble-table steps per byte: a 64-byte table
   keeps the code small. */
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

/* ---- the bake's method table: what >>bake's driver knows of a method ---- */

/* A bake method is one row of >>bake's table (pvs__bake_methods): functions over a per-bake state the driver holds
   behind one pointer. The driver checks every method's parameters, prepares those the bake may run, keeps those
   that can cull something in the scene (AUTO), runs each on every cell and intersects their PVSs (an intersection
   of conservative sets is conservative). Adding a method is its module plus one table row. */

/* What a method sees of the bake: `cells` every cell of the bake, not only the shard's (so what prepare
   derives agrees between shards; the caller's, set during prepare only); `task_cells` the shard's, one per
   task. */
typedef struct pvs__bake_env {
	const pvs_scene *scene;
	pvs_allocator allocator;
	const pvs_box *cells;
	uint32_t cell_count;
	const pvs_box *task_cells;
	uint32_t task_count;
	uint32_t object_count;
	size_t words;              /* per PVS */
	float eps;                 /* the bake's eps (stored in the file): a method's prepare may derive it */
	uint32_t flags;            /* PVS_BAKE_* */
	int is_auto;               /* 1: AUTO (this method's PVS may be intersected with others) */
} pvs__bake_env;

/* What the run of a cell found (per task, for pvs_bake_report). */
#define PVS__BAKE_ALL_VISIBLE 1u
#define PVS__BAKE_NO_OCCLUDERS 2u
#define PVS__BAKE_EXCLUDED 4u
#define PVS__BAKE_OTREE_BUDGET 8u

/* Traits of a method (pvs__bake_method.traits). */
#define PVS__METHOD_CONSERVATIVE 1u /* AUTO may intersect it (never an estimate from below) */
#define PVS__METHOD_AUTO_DEFAULT 2u /* AUTO considers it when pvs_bake_desc.methods is 0 */
#define PVS__METHOD_APPROXIMATE 4u  /* its file is flagged PVS_FILE_APPROXIMATE */
#define PVS__METHOD_WHOLE_CELLS 8u  /* run alone, it stores data of whole cells beyond their PVSs: no
									   adaptive cells, no resuming from PVSs */
#define PVS__METHOD_SETS_OTHERS 16u /* it sets every object outside its candidates (pvs_bake_method_info's
									   kept_only when it runs after others) */

typedef struct pvs__bake_method {
	pvs_method method;
	uint32_t traits;            /* PVS__METHOD_* */
	int cost_rank;              /* AUTO runs the methods cheapest first (1..4); PREVIEW keeps the first
								   that applies */
	/* Checks desc's parameters of this method, whichever method the bake runs. NULL: none. */
	pvs_result (*check)(const pvs_bake_desc *desc, pvs_error *err);
	/* Makes *state, read-only in the tasks but for per-task slots. UNSUPPORTED: the method cannot
	   run on this scene (AUTO then skips it). *state is destroyed even when this fails. */
	pvs_result (*prepare)(pvs__bake_env *env, const pvs_bake_desc *desc, void **state, pvs_error *err);
	/* 1 if the prepared method can leave anything out in this scene, with the reason in *why either
	   way. NULL: always ("conservative"). */
	int (*applies)(const void *state, const char **why);
	/* The method's PVS of a task's box (its cell or an adaptive part) into `bits`, cleared by the caller.
	   `candidates`, when not NULL, are the objects the caller intersects with (an adaptive sub-cell's
	   parent PVS, earlier methods): a method may test only those. Adds PVS__BAKE_* to *flags.
	   Thread-safe for distinct tasks. */
	pvs_result (*cell)(const pvs__bake_env *env, void *state, uint32_t task, uint32_t cell, const pvs_box *box,
					   const pvs_word *candidates, pvs_word *bits, unsigned *flags, pvs_error *err);
	/* Fills the file's sections of the method's own when the bake runs it alone. NULL: none. */
	void (*file)(const void *state, pvs_file_desc *fd);
	/* Frees the state (NULL is fine). */
	void (*destroy)(const pvs__bake_env *env, void *state);
} pvs__bake_method;

struct pvs_bake;
/* The state of method m in a bake, NULL when the bake did not prepare it (>>bake). */
PVS__STATIC void *pvs__bake_method_state(const struct pvs_bake *b, pvs_method m);

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
	double max_triangle_area;    /* the largest triangle's area (occluder selection's bound) */
};

/* Fills s->triangle_corners and empties the boxes of zero-area triangles (>>kdtree). */
PVS__STATIC pvs_result pvs__scene_prepare_rays(pvs_scene *s, pvs_box *tri_boxes, pvs_error *err);

/* Double-precision 3x3 solve of three planes n_i.p + d_i = 0; returns 0 when (nearly) parallel. */
PVS__STATIC int pvs__three_planes(const float *a, const float *b, const float *c, double out[3]) {
	double n1[3], n2[3], n3[3], x[3], det;
	int i;
	for (i = 0; i < 3; ++i) { n1[i] = a[i]; n2[i] = b[i]; n3[i] = c[i]; }
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
PVS__STATIC pvs_result pvs__convex_bounds(const float *planes, uint32_t n, pvs_box *out, int64_t index,
										  pvs_error *err) {
	float all[(PVS_MAX_OCCLUDER_PLANES + 6) * 4];
	double reach = 1.0, tol;
	uint32_t i, j, k, m, total, found = 0, on_guard = 0;
	pvs_box b = pvs__box_empty();
	for (i = 0; i < n; ++i) {
		const float *p = planes + 4 * i;
		double len = sqrt((double)p[0] * p[0] + (double)p[1] * p[1] + (double)p[2] * p[2]);
		if (!pvs__finite(p[0]) || !pvs__finite(p[1]) || !pvs__finite(p[2]) || !pvs__finite(p[3]))
			return pvs__fail(err, PVS_ERROR_NOT_FINITE, index, 0, "occluder %lld: plane %u is not finite",
							 (long long)index, i);
		if (len == 0.0 || !(len < 1e30))
			return pvs__fail(err, PVS_ERROR_BAD_OCCLUDER, index, 0, "occluder %lld: plane %u has a zero normal",
							 (long long)index, i);
		for (k = 0; k < 4; ++k) all[4 * i + k] = (float)(p[k] / len);
		if (fabs(p[3] / len) + 1.0 > reach) reach = fabs(p[3] / len) + 1.0;
	}
	/* every vertex is some triple's intersection: reach bounds them all, generously */
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
	if (!found)
		return pvs__fail(err, PVS_ERROR_BAD_OCCLUDER, index, 0, "occluder %lld: the half-spaces are empty",
						 (long long)index);
	if (on_guard)
		return pvs__fail(err, PVS_ERROR_BAD_OCCLUDER, index, 0, "occluder %lld: the half-spaces are unbounded",
						 (long long)index);
	for (k = 0; k < 3; ++k)
		if (!(b.min[k] < b.max[k]))
			return pvs__fail(err, PVS_ERROR_BAD_OCCLUDER, index, 0, "occluder %lld: the volume is flat",
							 (long long)index);
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

PVS__STATIC pvs_result pvs__validate_occluder(const pvs_occluder_desc *o, uint32_t up, int64_t index, pvs_box *box,
											  pvs_error *err) {
	uint32_t i, j, n;
	switch (o->kind) {
	case PVS_OCCLUDER_BOX:
		for (i = 0; i < 3; ++i)
			if (!pvs__finite(o->box.min[i]) || !pvs__finite(o->box.max[i]))
				return pvs__fail(err, PVS_ERROR_NOT_FINITE, index, 0, "occluder %lld: box is not finite",
								 (long long)index);
		for (i = 0; i < 3; ++i)
			if (!(o->box.min[i] < o->box.max[i]))
				return pvs__fail(err, PVS_ERROR_BAD_OCCLUDER, index, 0, "occluder %lld: box min >= max on axis %u",
								 (long long)index, i);
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
			return pvs__fail(err, PVS_ERROR_BAD_OCCLUDER, index, 0,
							 "occluder %lld: footprint needs 3..%d points, has %u", (long long)index,
							 PVS_MAX_FOOTPRINT_POINTS, n);
		if (!pvs__finite(o->base) || !pvs__finite(o->top))
			return pvs__fail(err, PVS_ERROR_NOT_FINITE, index, 0, "occluder %lld: base or top is not finite",
							 (long long)index);
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
				return pvs__fail(err, PVS_ERROR_BAD_OCCLUDER, index, 0,
								 "occluder %lld: footprint points %u and %u coincide", (long long)index, i,
								 (i + 1) % n);
		}
		if (area2 == 0.0)
			return pvs__fail(err, PVS_ERROR_BAD_OCCLUDER, index, 0, "occluder %lld: footprint has zero area",
							 (long long)index);
		for (i = 0; i < n; ++i)
			for (j = i + 2; j < n; ++j) {
				if (i == 0 && j == n - 1) continue; /* adjacent through the wrap */
				if (pvs__segments_meet_2d(o->footprint + 2 * i, o->footprint + 2 * ((i + 1) % n), o->footprint + 2 * j,
										  o->footprint + 2 * ((j + 1) % n)))
					return pvs__fail(err, PVS_ERROR_BAD_OCCLUDER, index, 0,
									 "occluder %lld: footprint edges %u and %u cross", (long long)index, i, j);
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
		return pvs__fail(err, PVS_ERROR_BAD_OCCLUDER, index, 0, "occluder %lld: unknown kind %d", (long long)index,
						 (int)o->kind);
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

/* pvs_scene_create's checks, before anything is allocated; *floats gets the floats the occluders' planes and
   footprints need. */
PVS__STATIC pvs_result pvs__scene_check_desc(const pvs_scene_desc *desc, size_t *floats, pvs_error *err) {
	size_t n3, i;
	uint32_t o;
	if (desc->object_count == 0 || !desc->objects)
		return pvs__fail(err, PVS_ERROR_INVALID_ARGUMENT, -1, 0, "the scene has no objects");
	if (desc->triangle_count && (!desc->indices || !desc->positions))
		return pvs__fail(err, PVS_ERROR_INVALID_ARGUMENT, -1, 0, "indices and positions must not be NULL");
	if (desc->occluder_count && !desc->occluders)
		return pvs__fail(err, PVS_ERROR_INVALID_ARGUMENT, -1, 0, "occluders must not be NULL when occluder_count > 0");
	if (desc->up_axis > 2)
		return pvs__fail(err, PVS_ERROR_INVALID_ARGUMENT, -1, 0, "up_axis %u is not 0, 1 or 2", desc->up_axis);
	if (desc->triangle_count > 0xfffffffeu / 3 || desc->vertex_count == 0xffffffffu ||
		desc->object_count == 0xffffffffu)
		return pvs__fail(err, PVS_ERROR_COUNT_OVERFLOW, -1, 0,
						 "more than 2^32 - 2 triangle indices, vertices or objects");
	if (!pvs__mul(desc->vertex_count, 3 * sizeof(float), &n3) ||
		!pvs__mul(desc->triangle_count, 3 * sizeof(uint32_t), &n3) ||
		!pvs__mul(desc->triangle_count, sizeof(pvs_box), &n3))
		return pvs__fail(err, PVS_ERROR_COUNT_OVERFLOW, -1, 0, "the arrays do not fit in memory");

	for (i = 0; i < (size_t)desc->vertex_count * 3; ++i)
		if (!pvs__finite(desc->positions[i]))
			return pvs__fail(err, PVS_ERROR_NOT_FINITE, (int64_t)(i / 3), 0,
							 "vertex %llu has a coordinate that is not finite", (unsigned long long)(i / 3));
	for (i = 0; i < (size_t)desc->triangle_count * 3; ++i)
		if (desc->indices[i] >= desc->vertex_count)
			return pvs__fail(err, PVS_ERROR_INDEX_OUT_OF_RANGE, (int64_t)(i / 3), 0,
							 "triangle %llu uses vertex %u but there are %u vertices", (unsigned long long)(i / 3),
							 desc->indices[i], desc->vertex_count);
	for (o = 0; o < desc->object_count; ++o) {
		const pvs_object_desc *ob = desc->objects + o;
		if (ob->first_triangle > desc->triangle_count || ob->triangle_count > desc->triangle_count - ob->first_triangle)
			return pvs__fail(err, PVS_ERROR_INDEX_OUT_OF_RANGE, o, 0,
							 "object %u: triangles %u..%u are past the %u triangles", o, ob->first_triangle,
							 ob->first_triangle + ob->triangle_count, desc->triangle_count);
		if (ob->triangle_count == 0 && !(desc->flags & PVS_SCENE_ALLOW_EMPTY_OBJECTS))
			return pvs__fail(err, PVS_ERROR_EMPTY_OBJECT, o, 0, "object %u has no triangles", o);
	}
	*floats = 0;
	for (o = 0; o < desc->occluder_count; ++o) {
		const pvs_occluder_desc *oc = desc->occluders + o;
		if (oc->kind == PVS_OCCLUDER_CONVEX && oc->plane_count <= PVS_MAX_OCCLUDER_PLANES)
			*floats += 4 * (size_t)oc->plane_count;
		if (oc->kind == PVS_OCCLUDER_EXTRUSION && oc->footprint_count <= PVS_MAX_FOOTPRINT_POINTS)
			*floats += 2 * (size_t)oc->footprint_count;
	}
	return PVS_OK;
}

/* The objects' flags, triangle ranges and boxes (empty when every triangle has zero area: never visible); each
   triangle is claimed by one object only (s->triangle_object). */
PVS__STATIC pvs_result pvs__scene_objects(pvs_scene *s, const pvs_scene_desc *desc, pvs_error *err) {
	uint32_t o, t;
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
			if (s->triangle_object[t] != PVS_NO_OBJECT)
				return pvs__fail(err, PVS_ERROR_OVERLAPPING_OBJECTS, o, 0, "objects %u and %u both claim triangle %u",
								 s->triangle_object[t], o, t);
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
		if (!any_area && ob->triangle_count && !(desc->flags & PVS_SCENE_ALLOW_EMPTY_OBJECTS))
			return pvs__fail(err, PVS_ERROR_DEGENERATE_OBJECT, o, 0, "object %u: all %u triangles have zero area", o,
							 ob->triangle_count);
		if (!any_area) s->object_boxes[o] = pvs__box_empty();
	}
	return PVS_OK;
}

/* The explicit occluders, validated (pvs__validate_occluder) and copied with their planes and
   footprints into s->occluder_data; their boxes grow the scene's bounds. */
PVS__STATIC pvs_result pvs__scene_occluders(pvs_scene *s, const pvs_scene_desc *desc, pvs_error *err) {
	size_t floats = 0;
	uint32_t o;
	for (o = 0; o < desc->occluder_count; ++o) {
		pvs_occluder_desc *dst = s->occluders + o;
		pvs_result r = pvs__validate_occluder(desc->occluders + o, s->up_axis, o, &s->occluder_boxes[o], err);
		if (r != PVS_OK) return r;
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
	return PVS_OK;
}

/* The scene's kD-trees over the triangles' boxes (zero-area ones emptied) and the objects' boxes. */
PVS__STATIC pvs_result pvs__scene_trees(pvs_scene *s, const pvs_scene_desc *desc, const pvs_box *tri_boxes,
										pvs_error *err) {
	pvs_kdtree_desc kd;
	pvs_result r;
	memset(&kd, 0, sizeof(kd));
	kd.allocator = s->allocator;
	kd.boxes = tri_boxes;
	kd.count = desc->triangle_count;
	kd.leaf_size = desc->leaf_size;
	r = pvs_kdtree_create(&kd, &s->triangle_tree, err);
	if (r != PVS_OK) return r;
	kd.boxes = s->object_boxes;
	kd.count = desc->object_count;
	kd.leaf_size = 0;
	return pvs_kdtree_create(&kd, &s->object_tree, err);
}

PVS_API pvs_result pvs_scene_create(const pvs_scene_desc *desc, pvs_scene **out, pvs_error *err) {
	pvs_scene *s;
	pvs_allocator a;
	pvs_result r;
	size_t floats = 0;
	uint32_t t;
	pvs_box *tri_boxes = NULL;
	if (out) *out = NULL;
	if (!desc || !out) return pvs__fail(err, PVS_ERROR_INVALID_ARGUMENT, -1, 0, "desc and out_scene must not be NULL");
	r = pvs__scene_check_desc(desc, &floats, err);
	if (r != PVS_OK) return r;

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
	if (!s->positions || !s->indices || !s->triangle_object || !s->object_boxes || !s->object_flags ||
		!s->object_triangles || !s->occluders || !s->occluder_boxes || !s->occluder_data || !tri_boxes) {
		r = pvs__fail(err, PVS_ERROR_OUT_OF_MEMORY, -1, 0, "scene arrays");
		goto fail;
	}
	if (desc->vertex_count) memcpy(s->positions, desc->positions, (size_t)desc->vertex_count * 3 * sizeof(float));
	if (desc->triangle_count) memcpy(s->indices, desc->indices, (size_t)desc->triangle_count * 3 * sizeof(uint32_t));
	for (t = 0; t < desc->triangle_count; ++t) s->triangle_object[t] = PVS_NO_OBJECT;
	s->bounds = pvs__box_empty();

	r = pvs__scene_objects(s, desc, err);
	if (r != PVS_OK) goto fail;
	for (t = 0; t < desc->triangle_count; ++t) {
		const uint32_t *tri = s->indices + 3 * (size_t)t;
		tri_boxes[t] = pvs__box_empty();
		pvs__box_add_point(&tri_boxes[t], s->positions + 3 * (size_t)tri[0]);
		pvs__box_add_point(&tri_boxes[t], s->positions + 3 * (size_t)tri[1]);
		pvs__box_add_point(&tri_boxes[t], s->positions + 3 * (size_t)tri[2]);
		pvs__box_add_box(&s->bounds, &tri_boxes[t]);
	}
	r = pvs__scene_occluders(s, desc, err);
	if (r != PVS_OK) goto fail;
	if (s->bounds.min[0] > s->bounds.max[0]) {
		r = pvs__fail(err, PVS_ERROR_EMPTY_OBJECT, -1, 0, "the scene has no geometry");
		goto fail;
	}

	r = pvs__scene_prepare_rays(s, tri_boxes, err);
	if (r == PVS_OK) r = pvs__scene_trees(s, desc, tri_boxes, err);
	if (r != PVS_OK) goto fail;
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

/* The scene's 2.5D facades for >>vocc: pairs of consecutive triangles forming a vertical rectangle (two ground
   positions x two heights, split along a diagonal) whose bottom is at or below the scene's lowest point, so it
   blocks every height from the ground to its top; anything else is left out (conservative). vocc keeps this rather
   than pvs__facades_extract (>>otree), which would change its results. Writes *count facades of 6 floats (u0 v0 u1
   v1 top bottom), in triangle order, into a new array *out (6 count + 6 floats, allocator a; NULL on failure). */
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
			for (k = 0; k < 6; ++k)
				c[k] = s->positions + 3 * (size_t)s->indices[3 * (size_t)(t + (uint32_t)(k / 3)) + (uint32_t)(k % 3)];
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

/* Layout: a node is 8 bytes; `bits` holds the axis in its low 2 bits (3 = leaf) and above them an index: an
   inner node's left child (the right one follows) or a leaf's item list offset in `items`; the union holds
   the split plane or the leaf's item count. Node 0 is the root; inner nodes have two children, so N nodes
   have (N + 1) / 2 leaves. Items are referenced from every leaf whose closed cell overlaps their closed box:
   a point on a split plane finds every box touching it on either side. */
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

/* An item reference during the build: its box clipped to the node's cell. */
typedef struct pvs__kdref {
	float min[3], max[3];
	uint32_t item;
} pvs__kdref;

typedef struct pvs__kdbuild {
	pvs_kdtree *tree;
	pvs__kdref *refs;        /* a stack: the node being split is on top, pending left children below */
	size_t ref_capacity;
	size_t refs_left, nodes_left;   /* the pools (pvs__kd_build) */
	size_t ref_limit, item_limit, node_limit; /* the most the arrays can need (pvs_kdtree_create) */
	uint32_t leaf_size, max_depth;
	pvs_error *err;
	float planes[3][PVS__KD_BINS + 1];    /* candidate planes of the node being split */
	uint32_t starts[3][PVS__KD_BINS + 1]; /* [s]: refs whose min is <= planes[s] first */
	uint32_t ends[3][PVS__KD_BINS + 1];   /* [e]: refs whose max is >= planes[e] last */
} pvs__kdbuild;

PVS__STATIC pvs_result pvs__kd_make_leaf(pvs__kdbuild *b, uint32_t node, size_t base, size_t n) {
	pvs_kdtree *t = b->tree;
	pvs_result r = PVS_OK;
	size_t i;
	uint32_t *items;
	if (t->item_count > PVS__KD_MAX_INDEX || n > (size_t)0xffffffffu - t->item_count)
		return pvs__fail(b->err, PVS_ERROR_COUNT_OVERFLOW, -1, 0, "kD-tree: more than 2^30 item references");
	items = (uint32_t *)pvs__grow_capped(&t->allocator, t->items, &t->item_capacity, t->item_count, t->item_count + n,
										 b->item_limit, sizeof(uint32_t), &r);
	if (!items)
		return pvs__fail(b->err, r, -1, 0, "kD-tree leaf items (%llu)", (unsigned long long)(t->item_count + n));
	t->items = items;
	for (i = 0; i < n; ++i) items[t->item_count + i] = b->refs[base + i].item;
	t->nodes[node].u.count = (uint32_t)n;
	t->nodes[node].bits = (n ? t->item_count << 2 : 0u) | PVS__KD_LEAF;
	t->item_count += (uint32_t)n;
	return PVS_OK;
}

/* Splits node `node` (refs[base .. base + n) on top of the stack, cell `box`) or makes it a leaf. Binned SAH
   over all three axes (Bittner 2002 §4.4 uses SAH or fewest cut objects; binning after Wald 2007): up to 31
   planes per axis, fewer in small nodes. The counts are exact for the closed-interval distribution below (up
   to sampling in big nodes): straddlers and boxes in a plane are costed as they will be stored.

   Budgets. A straddling box goes to both sides, so boxes that overlap everywhere (a fan of slivers around
   one vertex) would multiply references at every level: memory quadratic in the count. So the build draws
   from two pools set by pvs_kdtree_create, the references a split adds (l + r - n) and the nodes (two per
   split); a split the pools cannot pay for is not taken (a bigger leaf). Pools are spent in build order, so
   a tree within them is the tree built without them: ordinary scenes use about half (tests/BENCHMARKS.md,
   kdtree), adversarial ones get big leaves instead of more memory. */
PVS__STATIC pvs_result pvs__kd_build(pvs__kdbuild *b, uint32_t node, size_t base, size_t n, const pvs_box *box,
									 uint32_t depth) {
	pvs_kdtree *t = b->tree;
	float ext[3], k0[3], k1[3], scale[3], inv_measure, inv_nb, best_cost, count_scale, split;
	int axis, best_axis = -1, best_k = 0, area, nb, valid[3];
	size_t i, j, w, top, sampled, nl, nr;
	uint32_t child;
	pvs_result r = PVS_OK;
	pvs_box lbox, rbox;
	if (n <= b->leaf_size || depth >= b->max_depth || b->nodes_left < 2) return pvs__kd_make_leaf(b, node, base, n);

	/* a box's SAH measure is linear in its extent along one axis, k1[axis] * extent + k0[axis]: half the
	   surface area, or the edge sum for boxes with no area */
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
	/* big nodes bin an even stride of PVS__KD_SAMPLE refs: the plane barely changes */
	sampled = n > PVS__KD_SAMPLE ? PVS__KD_SAMPLE : n;
	for (j = 0; j < sampled; ++j) {
		const pvs__kdref *ref = b->refs + base + (sampled == n ? j : (size_t)((uint64_t)j * n / sampled));
		for (axis = 0; axis < 3; ++axis) {
			const float *pl = b->planes[axis];
			float lo = box->min[axis], mn = ref->min[axis], mx = ref->max[axis];
			int s, e;
			/* s = the first k in 1..nb with mn <= planes[k], e = the last k in 0..nb-1 with mx >= planes[k].
			   The refs lie in the cell, so the estimates are in [0, nb] and off by at most one near a
			   plane: one exact comparison each way fixes them. */
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

	/* cost of each inner plane; ties keep the first (lowest axis, then plane): deterministic */
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
			if ((float)(left + right) * count_scale > (float)(n + b->refs_left)) continue; /* estimate: checked below */
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
	nr = n; /* a split adds at most n references: room unless the pool is nearly spent */
	if (n > b->refs_left) { /* then the exact sides decide */
		for (i = 0, nl = 0, nr = 0; i < n; ++i) {
			nl += b->refs[base + i].min[axis] <= split;
			nr += b->refs[base + i].max[axis] >= split;
		}
		if (nl + nr > n + b->refs_left) return pvs__kd_make_leaf(b, node, base, n);
	}

	/* distribute with closed intervals: a ref touching the plane goes to both sides, clipped; left refs are
	   compacted in place, right ones written above base + n (the loop writes one slot past them) */
	{
		pvs__kdref *refs = (pvs__kdref *)pvs__grow_capped(&t->allocator, b->refs, &b->ref_capacity, base + n,
														  base + n + nr + 1, b->ref_limit, sizeof(pvs__kdref), &r);
		if (!refs) return pvs__fail(b->err, r, -1, 0, "kD-tree build references");
		b->refs = refs;
	}
	for (i = 0, w = base, top = base + n; i < n; ++i) {
		const pvs__kdref *src = b->refs + base + i;
		float mn = src->min[axis], mx = src->max[axis];
		int to_left = mn <= split, to_right = mx >= split;
		/* both slots are free: write, then advance (no branches; the clipped coordinate is stored last,
		   so no wide load waits on a narrow store) */
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
		pvs__kdnode *nodes =
			(pvs__kdnode *)pvs__grow_capped(&t->allocator, t->nodes, &t->node_capacity, t->node_count,
											(size_t)t->node_count + 2, b->node_limit, sizeof(pvs__kdnode), &r);
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
	nl = w - base;
	nr = top - (base + n);
	b->refs_left -= nl + nr - n;
	b->nodes_left -= 2;
	/* the right refs are on top of the stack: build them first */
	r = pvs__kd_build(b, child + 1, base + n, nr, &rbox, depth + 1);
	if (r != PVS_OK) return r;
	return pvs__kd_build(b, child, base, nl, &lbox, depth + 1);
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
				return pvs__fail(err, PVS_ERROR_NOT_FINITE, i, 0, "kD-tree box %u has a coordinate that is not finite",
								 i);
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

	/* The pools: PVS_KDTREE_MAX_REFS_PER_BOX references and PVS_KDTREE_MAX_NODES_PER_BOX nodes per box (K, N). The
	   stack holds the refs of leaves still to build, plus a node being split: its n and its right side above, at
	   most the pool's total plus one node's count and a slot. So the build holds at most 4 K + 8 N + 28 (K + 1)
	   bytes per box, PVS_KDTREE_BUILD_BYTES_PER_BOX. */
	b->refs_left = (size_t)(PVS_KDTREE_MAX_REFS_PER_BOX - 1) * m;
	b->nodes_left = (size_t)PVS_KDTREE_MAX_NODES_PER_BOX * m;
	b->item_limit = (size_t)PVS_KDTREE_MAX_REFS_PER_BOX * m;
	b->node_limit = (size_t)PVS_KDTREE_MAX_NODES_PER_BOX * m + 1;
	b->ref_limit = (size_t)(PVS_KDTREE_MAX_REFS_PER_BOX + 1) * m + 2;
	/* first guesses; all grow on demand, within the limits */
	t->nodes = (pvs__kdnode *)pvs__grow_capped(&a, NULL, &t->node_capacity, 0, 1 + (size_t)m / 2, b->node_limit,
											   sizeof(pvs__kdnode), &r);
	if (t->nodes)
		t->items = (uint32_t *)pvs__grow_capped(&a, NULL, &t->item_capacity, 0, 1 + (size_t)m + m / 2, b->item_limit,
												sizeof(uint32_t), &r);
	if (t->items)
		b->refs = (pvs__kdref *)pvs__grow_capped(&a, NULL, &b->ref_capacity, 0, 1 + (size_t)m + m / 2, b->ref_limit,
												 sizeof(pvs__kdref), &r);
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

PVS__STATIC int pvs__kdsweep_before(const void *pa, const void *pb) {
	const pvs__kdsweep *a = (const pvs__kdsweep *)pa, *b = (const pvs__kdsweep *)pb;
	return a->d2 < b->d2 || (a->d2 == b->d2 && a->node < b->node);
}

/* The heap holds nodes none of which is another's ancestor (a pop pushes the children): at most the leaves. */
PVS_API size_t pvs_kdtree_sweep_scratch_size(const pvs_kdtree *t) {
	return ((size_t)t->node_count + 1) / 2 * sizeof(pvs__kdsweep);
}

/* PVS_VISIT_ALL: the non-empty leaves under inner node `node` (cell `box`), depth first, distance -1.
   PVS_VISIT_STOP when the visitor said so. */
PVS__STATIC pvs_visit pvs__kd_visit_all(const pvs_kdtree *t, uint32_t node, const pvs_box *box,
										pvs_kdtree_visit_fn visit, void *user) {
	struct {
		uint32_t node;
		pvs_box box;
	} stack[PVS_KDTREE_MAX_DEPTH + 2];
	int sp = 1;
	stack[0].node = node;
	stack[0].box = *box;
	while (sp) {
		const pvs__kdnode *nd;
		uint32_t axis, child;
		pvs_box b;
		--sp;
		nd = t->nodes + stack[sp].node;
		b = stack[sp].box;
		axis = nd->bits & 3u;
		if (axis == PVS__KD_LEAF) {
			if (nd->u.count && visit(user, &b, -1.0f, t->items + (nd->bits >> 2), nd->u.count) == PVS_VISIT_STOP)
				return PVS_VISIT_STOP;
			continue;
		}
		child = nd->bits >> 2; /* the right child below the left: the left is taken first */
		stack[sp].node = child + 1;
		stack[sp].box = b;
		stack[sp].box.min[axis] = nd->u.split;
		stack[sp + 1].node = child;
		stack[sp + 1].box = b;
		stack[sp + 1].box.max[axis] = nd->u.split;
		sp += 2;
	}
	return PVS_VISIT_DESCEND;
}

/* The approximate occlusion sweep (Bittner 2002 §3.2): a priority queue on the nodes' minimum distance to the
   source. A child's cell lies in its parent's, so its distance is never smaller: the visit order is non-decreasing.
   `heap` holds (node_count + 1) / 2 entries; `node`, when not NULL, receives the visited node's index during each
   `visit` (the otree bake keeps per-node counts). */
PVS__STATIC void pvs__kd_sweep(const pvs_kdtree *t, const pvs_box *source, pvs__kdsweep *heap,
							   pvs_kdtree_visit_fn visit, void *user, uint32_t *node) {
	size_t n = 1;
	int k;
	if (t->bounds.min[0] > t->bounds.max[0]) return; /* no items: nothing to visit */
	heap[0].d2 = pvs__box_distance2(source, &t->bounds);
	heap[0].node = 0;
	heap[0].box = t->bounds;
	while (n) {
		pvs__kdsweep top;
		const pvs__kdnode *nd;
		uint32_t axis;
		pvs_visit v;
		pvs__pq_pop(heap, &n, sizeof(top), &top, pvs__kdsweep_before);
		nd = t->nodes + top.node;
		axis = nd->bits & 3u;
		if (node) *node = top.node;
		if (axis == PVS__KD_LEAF) {
			uint32_t count = nd->u.count;
			v = visit(user, &top.box, sqrtf(top.d2), count ? t->items + (nd->bits >> 2) : NULL, count);
		} else {
			v = visit(user, &top.box, sqrtf(top.d2), NULL, 0);
		}
		if (v == PVS_VISIT_STOP) break;
		if (v == PVS_VISIT_ALL && axis != PVS__KD_LEAF &&
			pvs__kd_visit_all(t, top.node, &top.box, visit, user) == PVS_VISIT_STOP)
			break;
		if (v != PVS_VISIT_DESCEND || axis == PVS__KD_LEAF) continue;
		for (k = 0; k < 2; ++k) {
			pvs__kdsweep e;
			e.node = (nd->bits >> 2) + (uint32_t)k;
			e.box = top.box;
			if (k == 0) e.box.max[axis] = nd->u.split;
			else e.box.min[axis] = nd->u.split;
			e.d2 = pvs__box_distance2(source, &e.box);
			pvs__pq_push(heap, &n, sizeof(e), &e, pvs__kdsweep_before);
		}
	}
}

PVS_API pvs_result pvs_kdtree_sweep(const pvs_kdtree *t, const pvs_box *source, void *scratch, size_t scratch_size,
									pvs_kdtree_visit_fn visit, void *user) {
	size_t cap;
	int k;
	if (!t || !source || !visit) return PVS_ERROR_INVALID_ARGUMENT;
	for (k = 0; k < 3; ++k)
		if (!pvs__finite(source->min[k]) || !pvs__finite(source->max[k])) return PVS_ERROR_NOT_FINITE;
	if (t->bounds.min[0] > t->bounds.max[0]) return PVS_OK;
	cap = scratch ? scratch_size / sizeof(pvs__kdsweep) : 0;
	if (cap < ((size_t)t->node_count + 1) / 2) return PVS_ERROR_BUFFER_TOO_SMALL;
	pvs__kd_sweep(t, source, (pvs__kdsweep *)scratch, visit, user, NULL);
	return PVS_OK;
}

/* ---- ray walk ---- */

/* Front-to-back stack traversal (the classic recursive ray traversal, Havran's TA_rec_B family) in double. Leaf
   intervals widen by PVS__KD_RAY_TOL of the coordinates' size: a touched leaf is never skipped, at worst an extra
   neighbour is visited. */
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

/* A point on a split plane goes left; that leaf holds every item whose box contains it, as the build stores a box
   touching the plane on both sides. */
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
		if (e1[1] * e2[2] - e1[2] * e2[1] == 0.0 && e1[2] * e2[0] - e1[0] * e2[2] == 0.0 &&
			e1[0] * e2[1] - e1[1] * e2[0] == 0.0)
			tri_boxes[t] = pvs__box_empty(); /* zero area: never hit, left out of the tree */
		else {
			double n0 = e1[1] * e2[2] - e1[2] * e2[1], n1 = e1[2] * e2[0] - e1[0] * e2[2],
				   n2 = e1[0] * e2[1] - e1[1] * e2[0];
			double area = 0.5 * sqrt(n0 * n0 + n1 * n1 + n2 * n2);
			if (area > s->max_triangle_area) s->max_triangle_area = area;
		}
	}
	return PVS_OK;
}

/* A ray prepared for the watertight test of Woop, Benthin and Wald (JCGT 2013), in double: kz the axis of the
   largest direction component, the shear taking dir to +-z. */
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

/* 2D edge function of sheared corners p, q: its sign tells the side of p-q the ray passes. Corners are stored
   sorted, so a shared edge is evaluated as the same (p, q), bit for bit, in both triangles: no ray slips between. */
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

/* The segment is the ray a + t (b - a), 0 <= t <= 1, b - a in double; a zero-length one is never blocked. */
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
	/* the float direction may fall short of b: walk a little past; the test itself stops at 1 */
	pvs_kdtree_ray(s->triangle_tree, a, df, 1.0f + 1e-6f, pvs__raycast_leaf, &rc);
	return rc.triangle != 0xffffffffu;
}

// >>raster
/* ==== raster: conservative rasterizer (Durand 2000 §3.1-3.2), depth pyramid (Durand 2000 §2.4), cull map (Wonka &
   Schmalstieg 1999 §3-4), per-frame culling (Bittner 2002 §3.2, §4.5) ==== */

/* Rounding. Per polygon (a triangle clipped to the near plane) the setup is in double: edge functions E (>= 0 inside,
   |a| + |b| = 1) at the range's corner plus their exact extreme over a pixel, min(0, a) + min(0, b) for inner coverage
   (occluders) or max(0, a) + max(0, b) for outer (occludees): Wonka 1999 §4.4's sampling correction. Every error bound
   is then subtracted (occluder) or added (occludee) before rounding to float: 2^-40 of the coordinates' size for setup
   and projection, over the edge length (short edges far off screen get wide margins), and 2^-20 of the terms for the
   float c + a i + b j (four roundings of 2^-24; i, j exact). Depth z/w is affine: the plane's extreme at the pixel
   corners (inner) or among corners and vertices (outer), plus margin and clamped by the vertices' extreme depth, is
   safe even for an ill-conditioned plane. Degenerate polygons cover nothing as occluders, their rectangle at the
   nearest depth as occludees. Scalar and SIMD do the same float operations in order: bit-identical without FMA
   contraction (GCC's -std=c99 default; the pragma below for clang), which would only remove roundings. Limit: the
   near-plane cut has no margin (an occludee may lose a sliver about 2^-51 |b - a| / near wide, under 1e-8 pixels at 4K
   for edges below 10^4 near distances). */

#if !defined(PVS_NO_SIMD) && (defined(__SSE2__) || defined(_M_X64) || (defined(_M_IX86_FP) && _M_IX86_FP >= 2))
#define PVS__SSE2 1
#include <emmintrin.h>
#elif !defined(PVS_NO_SIMD) && (defined(__ARM_NEON) || defined(__ARM_NEON__))
#define PVS__NEON 1
#include <arm_neon.h>
#endif

/* Lanes: four floats (pvs__f4), four int32 (pvs__i4) and a mask (pvs__m4: each lane all ones or zero) with the few
   operations the SIMD kernels below are written on once, each the instruction they used before per set: min and max
   are a < b ? a : b and a > b ? a : b (SSE2's minps and maxps; NEON compares and selects, vminq differs on NaN and
   signed zeros); float to int truncates (NEON saturates where SSE2 gives INT_MIN: kernels keep lanes in range);
   shl_ones is ~0 << clamp(n, 0, 32). PVS__LANES_DIV adds div, hmin2 and hmax2 (over two vectors' eight lanes). */
#if defined(PVS__SSE2)
#define PVS__LANES 1
#define PVS__LANES_DIV 1
typedef __m128 pvs__f4;
typedef __m128i pvs__i4;
typedef __m128 pvs__m4;
#define pvs__f4_load _mm_loadu_ps
#define pvs__f4_store _mm_storeu_ps
#define pvs__f4_set1 _mm_set1_ps
#define pvs__f4_set4 _mm_setr_ps
#define pvs__f4_add _mm_add_ps
#define pvs__f4_sub _mm_sub_ps
#define pvs__f4_mul _mm_mul_ps
#define pvs__f4_div _mm_div_ps
#define pvs__f4_min _mm_min_ps
#define pvs__f4_max _mm_max_ps
#define pvs__f4_lt _mm_cmplt_ps
#define pvs__f4_le _mm_cmple_ps
#define pvs__f4_gt _mm_cmpgt_ps
#define pvs__f4_ge _mm_cmpge_ps
#define pvs__f4_abs(a) _mm_and_ps(a, _mm_castsi128_ps(_mm_set1_epi32(0x7fffffff)))
#define pvs__f4_trunc _mm_cvttps_epi32
#define pvs__f4_from_i4 _mm_cvtepi32_ps
#define pvs__i4_load(p) _mm_loadu_si128((const __m128i *)(p))
#define pvs__i4_store(p, a) _mm_storeu_si128((__m128i *)(p), a)
#define pvs__i4_set1 _mm_set1_epi32
#define pvs__i4_add _mm_add_epi32
#define pvs__i4_sub _mm_sub_epi32
#define pvs__i4_andn(a, b) _mm_andnot_si128(b, a) /* a & ~b */
#define pvs__i4_lt(a, b) _mm_castsi128_ps(_mm_cmplt_epi32(a, b))
#define pvs__i4_gt(a, b) _mm_castsi128_ps(_mm_cmpgt_epi32(a, b))
#define pvs__i4_eq(a, b) _mm_castsi128_ps(_mm_cmpeq_epi32(a, b))
#define pvs__i4_from_m4 _mm_castps_si128
#define pvs__m4_true() _mm_castsi128_ps(_mm_set1_epi32(-1))
#define pvs__m4_and _mm_and_ps
#define pvs__m4_or _mm_or_ps
#define pvs__m4_andn(a, b) _mm_andnot_ps(b, a) /* a & ~b */
#define pvs__m4_bits _mm_movemask_ps
PVS__STATIC __m128 pvs__f4_sel(__m128 m, __m128 a, __m128 b) {
	return _mm_or_ps(_mm_and_ps(m, a), _mm_andnot_ps(m, b));
}
PVS__STATIC __m128i pvs__i4_sel(__m128 m, __m128i a, __m128i b) {
	__m128i k = _mm_castps_si128(m);
	return _mm_or_si128(_mm_and_si128(k, a), _mm_andnot_si128(k, b));
}
/* 2^n built in a float's exponent, converted (2^31 gives 1 << 31), negated; 0 for n >= 32 */
PVS__STATIC __m128i pvs__i4_shl_ones(__m128i n) {
	__m128i p;
	n = _mm_andnot_si128(_mm_srai_epi32(n, 31), n);
	p = _mm_cvttps_epi32(_mm_castsi128_ps(_mm_slli_epi32(_mm_add_epi32(n, _mm_set1_epi32(127)), 23)));
	return _mm_and_si128(_mm_sub_epi32(_mm_setzero_si128(), p), _mm_cmplt_epi32(n, _mm_set1_epi32(32)));
}
PVS__STATIC float pvs__f4_hmin2(__m128 a, __m128 b) {
	__m128 v = _mm_min_ps(a, b);
	v = _mm_min_ps(v, _mm_movehl_ps(v, v));
	return _mm_cvtss_f32(_mm_min_ss(v, _mm_shuffle_ps(v, v, 1)));
}
PVS__STATIC float pvs__f4_hmax2(__m128 a, __m128 b) {
	__m128 v = _mm_max_ps(a, b);
	v = _mm_max_ps(v, _mm_movehl_ps(v, v));
	return _mm_cvtss_f32(_mm_max_ss(v, _mm_shuffle_ps(v, v, 1)));
}
/* four (x, y, z, -) vertices, each with 4 readable floats, to X, Y, Z lanes */
PVS__STATIC void pvs__f4_xyz(const float *a, const float *b, const float *c, const float *d, __m128 *X, __m128 *Y,
							 __m128 *Z) {
	__m128 va = _mm_loadu_ps(a), vb = _mm_loadu_ps(b), vc = _mm_loadu_ps(c), vd = _mm_loadu_ps(d);
	__m128 ab0 = _mm_unpacklo_ps(va, vb), cd0 = _mm_unpacklo_ps(vc, vd);
	*X = _mm_movelh_ps(ab0, cd0);
	*Y = _mm_movehl_ps(cd0, ab0);
	*Z = _mm_movelh_ps(_mm_unpackhi_ps(va, vb), _mm_unpackhi_ps(vc, vd));
}
#elif defined(PVS__NEON)
#define PVS__LANES 1
typedef float32x4_t pvs__f4;
typedef int32x4_t pvs__i4;
typedef uint32x4_t pvs__m4;
#define pvs__f4_load vld1q_f32
#define pvs__f4_store vst1q_f32
#define pvs__f4_set1 vdupq_n_f32
#define pvs__f4_add vaddq_f32
#define pvs__f4_sub vsubq_f32
#define pvs__f4_mul vmulq_f32
#define pvs__f4_lt vcltq_f32
#define pvs__f4_le vcleq_f32
#define pvs__f4_gt vcgtq_f32
#define pvs__f4_ge vcgeq_f32
#define pvs__f4_abs vabsq_f32
#define pvs__f4_sel vbslq_f32
#define pvs__f4_trunc vcvtq_s32_f32
#define pvs__f4_from_i4 vcvtq_f32_s32
#define pvs__i4_load(p) vld1q_s32((const int32_t *)(p))
#define pvs__i4_store(p, a) vst1q_s32((int32_t *)(p), a)
#define pvs__i4_set1 vdupq_n_s32
#define pvs__i4_add vaddq_s32
#define pvs__i4_sub vsubq_s32
#define pvs__i4_andn vbicq_s32
#define pvs__i4_lt vcltq_s32
#define pvs__i4_gt vcgtq_s32
#define pvs__i4_eq vceqq_s32
#define pvs__i4_sel vbslq_s32
#define pvs__i4_from_m4 vreinterpretq_s32_u32
#define pvs__m4_true() vdupq_n_u32(~0u)
#define pvs__m4_and vandq_u32
#define pvs__m4_or vorrq_u32
#define pvs__m4_andn vbicq_u32
PVS__STATIC float32x4_t pvs__f4_set4(float a, float b, float c, float d) {
	const float v[4] = {a, b, c, d};
	return vld1q_f32(v);
}
PVS__STATIC float32x4_t pvs__f4_min(float32x4_t a, float32x4_t b) { return vbslq_f32(vcltq_f32(a, b), a, b); }
PVS__STATIC float32x4_t pvs__f4_max(float32x4_t a, float32x4_t b) { return vbslq_f32(vcgtq_f32(a, b), a, b); }
PVS__STATIC int pvs__m4_bits(uint32x4_t m) {
	return (int)((vgetq_lane_u32(m, 0) & 1u) | (vgetq_lane_u32(m, 1) & 2u) | (vgetq_lane_u32(m, 2) & 4u) |
				 (vgetq_lane_u32(m, 3) & 8u));
}
PVS__STATIC int32x4_t pvs__i4_shl_ones(int32x4_t n) { /* a shift by >= 32 gives 0 */
	n = vminq_s32(vmaxq_s32(n, vdupq_n_s32(0)), vdupq_n_s32(32));
	return vreinterpretq_s32_u32(vshlq_u32(vdupq_n_u32(~0u), n));
}
PVS__STATIC void pvs__f4_xyz(const float *a, const float *b, const float *c, const float *d, float32x4_t *X,
							 float32x4_t *Y, float32x4_t *Z) {
	*X = pvs__f4_set4(a[0], b[0], c[0], d[0]);
	*Y = pvs__f4_set4(a[1], b[1], c[1], d[1]);
	*Z = pvs__f4_set4(a[2], b[2], c[2], d[2]);
}
#if defined(__aarch64__)
#define PVS__LANES_DIV 1
#define pvs__f4_div vdivq_f32
#define pvs__f4_hmin2(a, b) vminvq_f32(vminq_f32(a, b))
#define pvs__f4_hmax2(a, b) vmaxvq_f32(vmaxq_f32(a, b))
#endif
#endif
#if defined(PVS__LANES)
/* ceil and floor to int, as the scalar (float)(int32_t)f < f tests */
PVS__STATIC pvs__i4 pvs__f4_ceili(pvs__f4 f) {
	pvs__i4 i = pvs__f4_trunc(f);
	return pvs__i4_sub(i, pvs__i4_from_m4(pvs__f4_lt(pvs__f4_from_i4(i), f)));
}
PVS__STATIC pvs__i4 pvs__f4_floori(pvs__f4 f) {
	pvs__i4 i = pvs__f4_trunc(f);
	return pvs__i4_add(i, pvs__i4_from_m4(pvs__f4_gt(pvs__f4_from_i4(i), f)));
}
#endif
#if defined(__clang__)
#pragma STDC FP_CONTRACT OFF
#endif

#define PVS__RASTER_MAXV 8                   /* a clipped triangle has at most 5 */
#define PVS__RASTER_ERR_D 9.094947017729282e-13 /* 2^-40 */
#define PVS__RASTER_ERR_F 9.5367431640625e-07   /* 2^-20 */
#define PVS__RASTER_MAX_LEVELS 16
#define PVS__RASTER_BIG 1e30

/* A context's buffers listed once, for both its creation and its destruction: entry k's *p gets n elements of `size`
   bytes (pvs__bufs_alloc, in order and on past a failure, as one call each would; 0 when one failed) or is freed
   (pvs__bufs_free; NULL entries are skipped). PVS__BUF appends an entry. */
typedef struct pvs__buf {
	void **p;
	size_t n, size;
} pvs__buf;
#define PVS__BUF(b, k, ptr, count, elem) ((b)[k].p = (void **)&(ptr), (b)[k].n = (count), (b)[k].size = (elem), ++(k))
PVS__STATIC int pvs__bufs_alloc(const pvs_allocator *a, const pvs__buf *b, int k) {
	int i, ok = 1;
	for (i = 0; i < k; ++i) ok &= (*b[i].p = pvs__alloc_array(a, b[i].n, b[i].size)) != NULL;
	return ok;
}
PVS__STATIC void pvs__bufs_free(const pvs_allocator *a, const pvs__buf *b, int k) {
	int i;
	for (i = 0; i < k; ++i) pvs__free_array(a, *b[i].p, b[i].n, b[i].size);
}

/* Occluder tile (Hasselgren et al. 2016), reversed Z: occluders at least as near as z0 on every pixel, z1 on `mask` (z1
   > z0 while mask != 0). */
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
	uint32_t levels;                            /* pyramid levels above `depth` */
	uint32_t lw[PVS__RASTER_MAX_LEVELS + 1], lh[PVS__RASTER_MAX_LEVELS + 1];
	float *lmin[PVS__RASTER_MAX_LEVELS + 1], *lmax[PVS__RASTER_MAX_LEVELS + 1];
	float *pyramid;
	size_t pyramid_floats;
	int pyramid_valid;                          /* 1: per-pixel pyramid current, 2: tile pyramid */
	pvs__tile *tile;
	uint32_t tw, th;                            /* tile grid */
	uint32_t xpad;                              /* bits of the last tile column past the map */
	uint32_t ypad;                              /* rows of the last tile row in the map (1..4) */
	int tiled;                                  /* occluders go to the tiles, else to `depth` */
	int mixed;                                  /* `depth` holds occludees drawn since the clear (untiled: all) */
	float *bmin;                                /* per block of 8 x 8 tiles: <= the least base z0 */
	uint8_t *bdirty;                            /* 1: a base grew since bmin was taken */
	uint32_t bw, bh;                            /* block grid */
	uint32_t tlevels;                           /* tile pyramid levels above the tile grid */
	uint32_t tlw[PVS__RASTER_MAX_LEVELS * 2 + 1], tlh[PVS__RASTER_MAX_LEVELS * 2 + 1];
	uint8_t tsx[PVS__RASTER_MAX_LEVELS * 2 + 1],
		tsy[PVS__RASTER_MAX_LEVELS * 2 + 1]; /* tiles per texel: 1 << tsx by 1 << tsy */
	float *tlmin[PVS__RASTER_MAX_LEVELS * 2 + 1], *tlmax[PVS__RASTER_MAX_LEVELS * 2 + 1];
	float *tpyramid;
	size_t tpyramid_floats;
	double m[16];                               /* current projection */
	double mabs[2];                             /* max row sum of |m| over x, y, z; max |m_r3| */
	float mf[16], hwf, hhf;                     /* the projection as given; half the map size (prefilter) */
	float mb[16][4];                            /* mf broadcast to four lanes */
	double rowa[4], rowt[4];                    /* per row of m: |m_r0| + |m_r1| + |m_r2|, |m_r3| */
	/* occluder meshes (pvs_raster_mesh): scratch for mesh_cap triangles, four pixel rows */
	uint32_t mesh_cap, mesh_hash;               /* triangles per piece; hash slots (a power of two) */
	struct pvs__mtri *mt;                       /* mesh_cap prepared triangles */
	uint32_t *mcid, *mpart;                     /* 3 mesh_cap: welded vertex per corner; partner half-edge */
	uint8_t *mvst;                              /* 3 mesh_cap: corner state against the clip planes */
	int8_t *mgrp;                               /* mesh_cap: facing +1 / -1, 0 = left out */
	uint32_t *mtab, *morder, *mact, *mband;     /* hash slots; mesh_cap; mesh_cap; th + 1 */
	float *mzmin;                               /* 4 width: least bound of the touching triangles */
	uint8_t *mflag; /* 4 width: 1 a triangle surely meets the pixel, 2 a boundary edge may */
	uint8_t *mdirty;                            /* 4 tw: band words the scratch holds */
	const pvs_scene *scene;
	uint32_t max_objects, max_triangles;
	void *sweep;
	size_t sweep_size;
	pvs__occsel *occ;
	uint32_t max_occluders;
	pvs_word *tri_seen;                         /* max_triangles bits */
	pvs_word *obj_done;                         /* max_objects bits */
	uint32_t cm_w, cm_h;
	float *cm;                                  /* cm_w * cm_h heights */
	float *cm_tile_min;                         /* lowest height per 8 x 8 tile */
	size_t cm_tiles;
	float region[4];                            /* u0, v0, u1, v1 */
	uint32_t *cm_start;                         /* cm_w * cm_h + 1 */
	uint32_t *cm_items;
	uint32_t cm_item_count;
	float *cm_bound;                            /* highest object top per cell (Wonka 1999 §4.3) */
	float ground;                               /* the scene's lowest point on the up axis */
};

typedef struct pvs__rsetup {
	int32_t i0, i1, j0, j1;   /* pixel range; (i0, j0) is the coefficients' origin */
	int32_t li0, li1, lj0, lj1; /* the part a loop covers (one tile) */
	int edges;
	float a[PVS__RASTER_MAXV], b[PVS__RASTER_MAXV], k[PVS__RASTER_MAXV];
	float za, zb, zk;     /* depth plane bound */
	float zclamp;         /* occluder: max(plane, zclamp); occludee: min(plane, zclamp) */
} pvs__rsetup;

/* Reference pixel rule (scalar loop, SIMD tails): inside every edge (rk: at column i0), clamped plane depth if nearer.
   1 when written. */
PVS__STATIC int pvs__raster_pixel(const pvs__rsetup *s, const float *rk, float rz, float *row, int32_t i,
								  int occluder) {
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

#if defined(PVS__LANES)
PVS__STATIC int pvs__raster_rows_simd(const pvs__rsetup *s, float *buf, uint32_t stride, int occluder) {
	int32_t i, j;
	int e, wrote = 0;
	const pvs__f4 step = pvs__f4_set4(0.0f, 1.0f, 2.0f, 3.0f), zero = pvs__f4_set1(0.0f);
	const pvs__f4 vza = pvs__f4_set1(s->za), vclamp = pvs__f4_set1(s->zclamp);
	pvs__f4 va[PVS__RASTER_MAXV];
	for (e = 0; e < s->edges; ++e) va[e] = pvs__f4_set1(s->a[e]);
	for (j = s->lj0; j <= s->lj1; ++j) {
		float fj = (float)(j - s->j0), rz = s->zk + s->zb * fj, rkf[PVS__RASTER_MAXV];
		pvs__f4 rk[PVS__RASTER_MAXV], vrz = pvs__f4_set1(rz);
		float *row = buf + (size_t)j * stride;
		for (e = 0; e < s->edges; ++e) { rkf[e] = s->k[e] + s->b[e] * fj; rk[e] = pvs__f4_set1(rkf[e]); }
		for (i = s->li0; i + 3 <= s->li1; i += 4) {
			pvs__f4 fi = pvs__f4_add(pvs__f4_set1((float)(i - s->i0)), step), d, old;
			pvs__m4 mask = pvs__m4_true(), gt;
			for (e = 0; e < s->edges; ++e)
				mask = pvs__m4_and(mask, pvs__f4_ge(pvs__f4_add(rk[e], pvs__f4_mul(va[e], fi)), zero));
			if (!pvs__m4_bits(mask)) continue;
			d = pvs__f4_add(vrz, pvs__f4_mul(vza, fi));
			d = pvs__f4_sel(occluder ? pvs__f4_lt(d, vclamp) : pvs__f4_gt(d, vclamp), vclamp, d);
			old = pvs__f4_load(row + i);
			gt = pvs__m4_and(mask, pvs__f4_gt(d, old));
			wrote |= pvs__m4_bits(gt);
			pvs__f4_store(row + i, pvs__f4_sel(gt, d, old));
		}
		for (; i <= s->li1; ++i) wrote |= pvs__raster_pixel(s, rkf, rz, row, i, occluder);
	}
	return wrote;
}
#endif

/* 8 x 8 tiles keep their farthest depth: a polygon skips tiles it cannot be nearer than or lies outside (occluders come
   roughly front to back). Skipping never changes a result. */
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

/* -1: all pixels of [i0 + a0, i0 + a1] x [j0 + b0, j0 + b1] fail an edge as the float loops see it, 1: all pass, 0:
   undecided (in double with slack 2^-18 of the terms). */
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

/* The most (least: the least) the loops can write over pixels [a0, a1] x [b0, b1] (relative), slack included: the
   affine depth's extreme corner (rounding is monotone, so the corner of the extreme terms). */
PVS__STATIC double pvs__raster_zbound(const pvs__rsetup *s, int32_t a0, int32_t a1, int32_t b0, int32_t b1,
									  int occluder, int least) {
	double pa = s->za, pb = s->zb, z,
		   sl = 3.814697265625e-06 * (pvs__dabs(s->zk) + pvs__dabs(pa) * a1 + pvs__dabs(pb) * b1) + 1e-30;
	if (least) z = (double)s->zk + pvs__dmin(pa * a0, pa * a1) + pvs__dmin(pb * b0, pb * b1) - sl;
	else z = (double)s->zk + pvs__dmax(pa * a0, pa * a1) + pvs__dmax(pb * b0, pb * b1) + sl;
	return occluder ? pvs__dmax(z, s->zclamp) : pvs__dmin(z, s->zclamp);
}

/* Pixel loops by 4 x 4 tile blocks, then tiles, skipping those as near as the polygon can write or outside an edge. */
PVS__STATIC void pvs__raster_run(pvs__rsetup *s, float *buf, uint32_t W, uint32_t H, float *tile_min, int occluder,
								 int simd, float zbound) {
	uint32_t tw = (W + PVS__TILE - 1) >> PVS__TILE_SHIFT, tx, ty, bx, by;
	int32_t a0, a1, b0, b1;
	int wrote, inside, edges, block;
	const int bs = PVS__TILE_SHIFT + 2;
	(void)simd;
	if (!tile_min) {
		s->li0 = s->i0; s->li1 = s->i1; s->lj0 = s->j0; s->lj1 = s->j1;
#if defined(PVS__LANES)
		if (simd) { pvs__raster_rows_simd(s, buf, W, occluder); return; }
#endif
		(void)pvs__raster_rows_scalar(s, buf, W, occluder);
		return;
	}
	for (by = (uint32_t)s->j0 >> bs; by <= (uint32_t)s->j1 >> bs; ++by)
		for (bx = (uint32_t)s->i0 >> bs; bx <= (uint32_t)s->i1 >> bs; ++bx) {
			int32_t c0 = (int32_t)(bx << bs), c1 = c0 + (1 << bs) - 1, d0 = (int32_t)(by << bs),
					d1 = d0 + (1 << bs) - 1;
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
					if (tx1 - tx0 == 3) {
						float a = t[tx0] < t[tx0 + 1] ? t[tx0] : t[tx0 + 1],
							  b = t[tx0 + 2] < t[tx0 + 3] ? t[tx0 + 2] : t[tx0 + 3];
						a = a < b ? a : b;
						lo = a < lo ? a : lo;
					} else {
						for (tx = tx0; tx <= tx1; ++tx) lo = t[tx] < lo ? t[tx] : lo;
					}
				}
				if (lo >= zbound ||
					(double)lo >= pvs__raster_zbound(s, c0 - s->i0, c1 - s->i0, d0 - s->j0, d1 - s->j0, occluder, 0))
					continue;
			}
			block = pvs__raster_classify(s, c0 - s->i0, c1 - s->i0, d0 - s->j0, d1 - s->j0);
			if (block < 0) continue;
			for (ty = ty0; ty <= ty1; ++ty)
				for (tx = tx0; tx <= tx1; ++tx) {
					if (tile_min[ty * tw + tx] >= zbound) continue;
					s->li0 = (int32_t)(tx << PVS__TILE_SHIFT); if (s->li0 < s->i0) s->li0 = s->i0;
					s->li1 = (int32_t)(tx << PVS__TILE_SHIFT) + PVS__TILE - 1; if (s->li1 > s->i1) s->li1 = s->i1;
					s->lj0 = (int32_t)(ty << PVS__TILE_SHIFT); if (s->lj0 < s->j0) s->lj0 = s->j0;
					s->lj1 = (int32_t)(ty << PVS__TILE_SHIFT) + PVS__TILE - 1; if (s->lj1 > s->j1) s->lj1 = s->j1;
					a0 = s->li0 - s->i0; a1 = s->li1 - s->i0; b0 = s->lj0 - s->j0; b1 = s->lj1 - s->j0;
					if ((double)tile_min[ty * tw + tx] >= pvs__raster_zbound(s, a0, a1, b0, b1, occluder, 0)) continue;
					inside = block ? 1 : pvs__raster_classify(s, a0, a1, b0, b1);
					if (inside < 0) continue;
					edges = s->edges;
					if (inside) s->edges = 0; /* inside: the same result without edge tests */
#if defined(PVS__LANES)
					if (simd) wrote = pvs__raster_rows_simd(s, buf, W, occluder);
					else
#endif
						wrote = pvs__raster_rows_scalar(s, buf, W, occluder);
					s->edges = edges;
					if (!wrote) continue;
					if (inside && a1 - a0 == PVS__TILE - 1 && b1 - b0 == PVS__TILE - 1) {
						/* full tile: the least depth written, a lower bound, all skipping needs */
						double lo = pvs__raster_zbound(s, a0, a1, b0, b1, occluder, 1);
						if (lo > tile_min[ty * tw + tx]) tile_min[ty * tw + tx] = pvs__f_down(lo);
					} else {
						pvs__tile_update(buf, W, H, tile_min, tx, ty);
					}
				}
		}
}

/* Fills the pixel rectangle with `d` where nearer (degenerate occludees). */
PVS__STATIC void pvs__raster_fill(float *buf, uint32_t W, uint32_t H, float *tile_min, int32_t i0, int32_t i1,
								  int32_t j0, int32_t j1, float d) {
	int32_t i, j;
	uint32_t tx, ty;
	for (j = j0; j <= j1; ++j) {
		float *row = buf + (size_t)j * W;
		for (i = i0; i <= i1; ++i)
			if (d > row[i]) row[i] = d;
	}
	if (tile_min)
		for (ty = (uint32_t)j0 >> PVS__TILE_SHIFT; ty <= (uint32_t)j1 >> PVS__TILE_SHIFT; ++ty)
			for (tx = (uint32_t)i0 >> PVS__TILE_SHIFT; tx <= (uint32_t)i1 >> PVS__TILE_SHIFT; ++tx)
				pvs__tile_update(buf, W, H, tile_min, tx, ty);
}

/* The depth plane of polygon x, y, z (span, mag, zmag: extents; perr, zerr: vertex errors) over pixels (ox + fi, oy +
   fj), fi <= iw, fj <= jh, from its largest fan triangle: p = za, zb, zk with z = zk + za fi + zb fj, and the bound
   on the setup error. 0 when no fan triangle has an area. */
PVS__STATIC int pvs__raster_plane(const double *x, const double *y, const double *z, int n, double ox, double oy,
								  double iw, double jh, double span, double mag, double zmag, double perr, double zerr,
								  double p[4]) {
	int i, best = -1;
	double amax = 0.0, x1, y1, z1, x2, y2, z2, det, za, zb;
	for (i = 1; i + 1 < n; ++i) {
		double a2 = pvs__dabs((x[i] - x[0]) * (y[i + 1] - y[0]) - (x[i + 1] - x[0]) * (y[i] - y[0]));
		if (a2 > amax) { amax = a2; best = i; }
	}
	if (best <= 0) return 0;
	x1 = x[best] - x[0]; y1 = y[best] - y[0]; z1 = z[best] - z[0];
	x2 = x[best + 1] - x[0]; y2 = y[best + 1] - y[0]; z2 = z[best + 1] - z[0];
	det = x1 * y2 - x2 * y1;
	p[0] = za = (z1 * y2 - z2 * y1) / det;
	p[1] = zb = (x1 * z2 - x2 * z1) / det;
	p[2] = z[0] + za * (ox - x[0]) + zb * (oy - y[0]);
	p[3] = zerr + (pvs__dabs(za) + pvs__dabs(zb)) * perr * (1.0 + (span + iw + jh + 2.0) * span / pvs__dabs(det)) +
		   PVS__RASTER_ERR_D * (zmag + (pvs__dabs(za) + pvs__dabs(zb)) * (mag + ox + oy + iw + jh + 2.0)) *
			   (1.0 + (span + ox + oy + iw + jh + 2.0) * span / pvs__dabs(det));
	return 1;
}

/* Depth plane bound over those pixels (pvs__raster_plane): (zk + zb fj) + za fi in float is at most (occluder) or
   at least (occludee) the plane's extreme over the pixel. None: zk = -FLT_MAX (occluder) or FLT_MAX, za = zb = 0. */
PVS__STATIC void pvs__raster_zplane(const double *x, const double *y, const double *z, int n, double ox, double oy,
									double iw, double jh, double span, double mag, double zmag, double perr,
									double zerr, int occluder, float *za_out, float *zb_out, float *zk_out) {
	double p[4];
	*za_out = *zb_out = 0.0f;
	*zk_out = occluder ? -FLT_MAX : FLT_MAX;
	if (pvs__raster_plane(x, y, z, n, ox, oy, iw, jh, span, mag, zmag, perr, zerr, p)) {
		double za = p[0], zb = p[1], zk = p[2], err = p[3], dy;
		zk += occluder ? pvs__dmin(0.0, za) + pvs__dmin(0.0, zb) : pvs__dmax(0.0, za) + pvs__dmax(0.0, zb);
		err += PVS__RASTER_ERR_F * (pvs__dabs(zk) + pvs__dabs(za) * iw + pvs__dabs(zb) * jh + 1e-30);
		zk += occluder ? -err : err;
		dy = pvs__dabs(zk) + pvs__dabs(za) * iw + pvs__dabs(zb) * jh;
		if (dy < 1e30 && err < 1e30) {
			*za_out = (float)za;
			*zb_out = (float)zb;
			*zk_out = (float)zk;
		}
	}
}

/* Bounds, doubled signed area, largest |x| + |y| and |z|; 0 when n < 3 or NaN. */
typedef struct pvs__polyext {
	double xmin, xmax, ymin, ymax, zmin, zmax, area2, mag, zmag;
} pvs__polyext;
PVS__STATIC int pvs__poly_extent(const double *x, const double *y, const double *z, int n, pvs__polyext *e) {
	int i;
	if (n < 3) return 0;
	e->xmin = e->xmax = x[0]; e->ymin = e->ymax = y[0]; e->zmin = e->zmax = z[0];
	e->area2 = e->mag = e->zmag = 0.0;
	for (i = 0; i < n; ++i) {
		int j = i + 1 == n ? 0 : i + 1;
		if (!(x[i] == x[i] && y[i] == y[i] && z[i] == z[i])) return 0; /* NaN */
		e->xmin = pvs__dmin(e->xmin, x[i]); e->xmax = pvs__dmax(e->xmax, x[i]);
		e->ymin = pvs__dmin(e->ymin, y[i]); e->ymax = pvs__dmax(e->ymax, y[i]);
		e->zmin = pvs__dmin(e->zmin, z[i]); e->zmax = pvs__dmax(e->zmax, z[i]);
		e->area2 += x[i] * y[j] - x[j] * y[i];
		e->mag = pvs__dmax(e->mag, pvs__dabs(x[i]) + pvs__dabs(y[i]));
		e->zmag = pvs__dmax(e->zmag, pvs__dabs(z[i]));
	}
	return 1;
}

/* 0 when the polygon (extent e, span its width plus height) is beyond useful precision or degenerate. */
PVS__STATIC int pvs__poly_usable(const pvs__polyext *e, double span) {
	return e->mag < PVS__RASTER_BIG * PVS__RASTER_BIG && pvs__dabs(e->area2) > 1e-9 * span * span &&
		pvs__dabs(e->area2) > 1e-300;
}

/* Edge i of polygon x, y (flip: clockwise) over pixels (ox + fi, oy + fj), fi <= iw, fj <= jh, as the rounding argument
   says: e = a, b, k, E = a fi + b fj + k. Mode 0 occludee, 1 occluder, 2 tile loops (their own float margin). 1: an
   edge to test, 0: every pixel passes it (or no length), -1: none does. */
PVS__STATIC int pvs__raster_edge(const double *x, const double *y, int i, int n, int flip, double ox, double oy,
								 double iw, double jh, double mag, double perr, int mode, double e[3]) {
	int j = i + 1 == n ? 0 : i + 1;
	double a = y[i] - y[j], b = x[j] - x[i], len, k, err, lo, hi;
	if (flip) { a = -a; b = -b; }
	len = pvs__dabs(a) + pvs__dabs(b);
	if (len == 0.0) return 0;
	a /= len;
	b /= len;
	k = a * (ox - x[i]) + b * (oy - y[i]);
	if (mode == 2) k = k + pvs__dmin(0.0, a) + pvs__dmin(0.0, b);
	else k += mode ? pvs__dmin(0.0, a) + pvs__dmin(0.0, b) : pvs__dmax(0.0, a) + pvs__dmax(0.0, b);
	err = (PVS__RASTER_ERR_D * (1.0 + mag) + perr) *
		(1.0 + (pvs__dabs(ox - x[i]) + pvs__dabs(oy - y[i]) + iw + jh + 2.0) / len);
	if (mode != 2) err += PVS__RASTER_ERR_F * (pvs__dabs(k) + pvs__dabs(a) * iw + pvs__dabs(b) * jh + 1e-30);
	if (mode) err = -err; /* x - err == x + -err */
	lo = k + pvs__dmin(0.0, a * iw) + pvs__dmin(0.0, b * jh);
	hi = k + pvs__dmax(0.0, a * iw) + pvs__dmax(0.0, b * jh);
	if (lo + err >= 0.0) return 0; /* every pixel passes this edge */
	if (hi + err < 0.0) return -1; /* no pixel does */
	k += err;
	if (!(pvs__dabs(k) < PVS__RASTER_BIG)) return -1; /* impossible once the trivial cases are gone */
	e[0] = a; e[1] = b; e[2] = k;
	return 1;
}

/* Rasterizes a convex polygon (pixels x, y; affine depth z) into a W x H buffer, keeping the nearer depth. */
PVS__STATIC void pvs__raster_poly(float *buf, uint32_t W, uint32_t H, float *tile_min, const double *x, const double *y,
								  const double *z, int n, int occluder, int simd, double perr, double zerr) {
	pvs__rsetup s;
	pvs__polyext e;
	int i;
	double span, dx, ox, oy, iw, jh, zlo, zhi;
	if (!pvs__poly_extent(x, y, z, n, &e)) return;
	dx = PVS__RASTER_ERR_D * (e.mag + 1.0) + perr; /* perr, zerr: the vertices' projection error */
	zlo = e.zmin - PVS__RASTER_ERR_D * e.zmag - zerr;
	zhi = e.zmax + PVS__RASTER_ERR_D * e.zmag + zerr;
	/* inner pixels (inside the box) or outer (touching it) */
	if (occluder) {
		s.i0 = pvs__clampi(ceil(e.xmin + dx), 0, (int32_t)W);
		s.i1 = pvs__clampi(floor(e.xmax - dx) - 1.0, -1, (int32_t)W - 1);
		s.j0 = pvs__clampi(ceil(e.ymin + dx), 0, (int32_t)H);
		s.j1 = pvs__clampi(floor(e.ymax - dx) - 1.0, -1, (int32_t)H - 1);
	} else {
		s.i0 = pvs__clampi(floor(e.xmin - dx), 0, (int32_t)W);
		s.i1 = pvs__clampi(floor(e.xmax + dx), -1, (int32_t)W - 1);
		s.j0 = pvs__clampi(floor(e.ymin - dx), 0, (int32_t)H);
		s.j1 = pvs__clampi(floor(e.ymax + dx), -1, (int32_t)H - 1);
	}
	if (s.i0 > s.i1 || s.j0 > s.j1) return;
	if (tile_min) { /* behind everything in every tile it overlaps */
		uint32_t tw = (W + PVS__TILE - 1) >> PVS__TILE_SHIFT, tx, ty, open = 0;
		float zb = pvs__f_up(zhi);
		for (ty = (uint32_t)s.j0 >> PVS__TILE_SHIFT; ty <= (uint32_t)s.j1 >> PVS__TILE_SHIFT && !open; ++ty)
			for (tx = (uint32_t)s.i0 >> PVS__TILE_SHIFT; tx <= (uint32_t)s.i1 >> PVS__TILE_SHIFT; ++tx)
				if (tile_min[ty * tw + tx] < zb) { open = 1; break; }
		if (!open) return;
	}
	span = (e.xmax - e.xmin) + (e.ymax - e.ymin);
	if (!pvs__poly_usable(&e, span)) {
		if (!occluder) pvs__raster_fill(buf, W, H, tile_min, s.i0, s.i1, s.j0, s.j1, pvs__f_up(zhi));
		return;
	}
	ox = (double)s.i0;
	oy = (double)s.j0;
	iw = (double)(s.i1 - s.i0);
	jh = (double)(s.j1 - s.j0);
	s.edges = 0;
	for (i = 0; i < n; ++i) {
		double ed[3];
		int r = pvs__raster_edge(x, y, i, n, e.area2 < 0, ox, oy, iw, jh, e.mag, perr, occluder, ed);
		if (r < 0) return;
		if (!r) continue;
		s.a[s.edges] = (float)ed[0];
		s.b[s.edges] = (float)ed[1];
		s.k[s.edges] = (float)ed[2];
		++s.edges;
	}
	s.zclamp = occluder ? pvs__f_down(zlo) : pvs__f_up(zhi);
	pvs__raster_zplane(x, y, z, n, ox, oy, iw, jh, span, e.mag, e.zmag, perr, zerr, occluder, &s.za, &s.zb, &s.zk);
	pvs__raster_run(&s, buf, W, H, tile_min, occluder, simd, pvs__f_up(zhi));
}

/* ---- occluder buffer: Masked Occlusion Culling (Hasselgren, Andersson and Akenine-Moller 2016), inner coverage. A
   polygon's inner pixels in a 32 x 4 tile row are one run of columns from the edges' intercepts (the paper's scanline
   events, as shifted masks); the working layer merges over the base by the paper's heuristic. ---- */

#define PVS__TW_SHIFT 5
#define PVS__TH_SHIFT 2
#define PVS__TH 4
#define PVS__BLOCK_SHIFT 3 /* blocks of 8 x 8 tiles (256 x 32 pixels): prefilter's hidden test */
#define PVS__U_2_20 9.5367431640625e-07        /* 2^-20 */
#define PVS__U_2_21 4.76837158203125e-07       /* 2^-21 */
#define PVS__U_2_44 5.684341886080802e-14      /* 2^-44 */
#define PVS__U_2_48 3.552713678800501e-15      /* 2^-48 */

/* Occluder polygon for the tile loops (i, j relative to (i0, j0)): pixel i of row j is inside edge e if i >= X_e(j)
   (left) or i <= X_e(j) (right); X_e(j) = xi + s j is the double edge line with margins; m: its float error bound. */
typedef struct pvs__tpoly {
	int32_t i0, i1, j0, j1;    /* inner pixel range (absolute) */
	int32_t jlo, jhi;          /* rows (relative) the near-horizontal edges leave */
	int nl, ne;                /* edges [0, nl) bound from the left, [nl, ne) from the right */
	double xi[PVS__RASTER_MAXV], s[PVS__RASTER_MAXV], cl[PVS__RASTER_MAXV];
	float sf[PVS__RASTER_MAXV], m[PVS__RASTER_MAXV];
	float zk, za, zb, zm, zlo; /* plane at (i0, j0) less float margin zm, clamped to the farthest vertex zlo */
} pvs__tpoly;

/* Columns L[d] .. R[d] (absolute; L > R: empty) of rows jrow + d inside every edge, from xr = X(jrow); reference for
   the SIMD versions. */
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

/* Mask bits of columns L .. R in the tile row starting at column x0 (bit k: column x0 + k). */
PVS__STATIC uint32_t pvs__tile_bits(int32_t L, int32_t R, int32_t x0) {
	int32_t lo = L - x0, hi = R - x0 + 1;
	uint32_t a, b;
	lo = lo < 0 ? 0 : lo;
	hi = hi < 0 ? 0 : hi;
	a = lo >= 32 ? 0u : ~0u << lo;
	b = hi >= 32 ? 0u : ~0u << hi;
	return a & ~b;
}

#if defined(PVS__LANES)
PVS__STATIC void pvs__tile_rows_simd(const pvs__tpoly *t, int32_t jrow, const float *xr, int32_t *L, int32_t *R) {
	const pvs__f4 d = pvs__f4_set4(0.0f, 1.0f, 2.0f, 3.0f), fw = pvs__f4_set1((float)(t->i1 - t->i0));
	pvs__f4 lf = pvs__f4_set1(0.0f), rf = fw, v;
	pvs__i4 l, r, j;
	pvs__m4 bad;
	int e;
	for (e = 0; e < t->nl; ++e) {
		v = pvs__f4_add(pvs__f4_set1(xr[e]), pvs__f4_mul(pvs__f4_set1(t->sf[e]), d));
		lf = pvs__f4_max(pvs__f4_add(v, pvs__f4_set1(t->m[e])), lf);
	}
	for (; e < t->ne; ++e) {
		v = pvs__f4_add(pvs__f4_set1(xr[e]), pvs__f4_mul(pvs__f4_set1(t->sf[e]), d));
		rf = pvs__f4_min(pvs__f4_sub(v, pvs__f4_set1(t->m[e])), rf);
	}
	l = pvs__f4_ceili(pvs__f4_min(lf, pvs__f4_add(fw, pvs__f4_set1(1.0f))));
	r = pvs__f4_floori(pvs__f4_max(rf, pvs__f4_set1(-1.0f)));
	j = pvs__i4_add(pvs__i4_set1(jrow), pvs__f4_trunc(d));
	bad = pvs__m4_or(pvs__i4_lt(j, pvs__i4_set1(t->jlo)), pvs__i4_gt(j, pvs__i4_set1(t->jhi)));
	pvs__i4_store(L, pvs__i4_add(pvs__i4_sel(bad, pvs__i4_set1(1), l), pvs__i4_set1(t->i0)));
	pvs__i4_store(R, pvs__i4_add(pvs__i4_sel(bad, pvs__i4_set1(0), r), pvs__i4_set1(t->i0)));
}
/* The four rows' bits of the tile at column x0; 0 when all are empty. */
PVS__STATIC int pvs__tile_mask_simd(const int32_t *L, const int32_t *R, int32_t x0, uint32_t *out) {
	pvs__i4 vx = pvs__i4_set1(x0), m;
	m = pvs__i4_andn(pvs__i4_shl_ones(pvs__i4_sub(pvs__i4_load(L), vx)),
					 pvs__i4_shl_ones(pvs__i4_sub(pvs__i4_add(pvs__i4_load(R), pvs__i4_set1(1)), vx)));
	pvs__i4_store(out, m);
	return pvs__m4_bits(pvs__i4_eq(m, pvs__i4_set1(0))) != 15;
}
#endif

/* Merges coverage T (as near as zt > z0) into a tile, Hasselgren et al.'s two-layer update: T covering the tile becomes
   the base; else the layer takes the union at the farther depth, or T replaces it if T leads it by more than it leads
   the base; a full layer becomes the base. Each step keeps every pixel a lower bound of its nearest occluder. `pad`:
   bits off the map. */
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

/* Tile rows of a polygon: runs of its four pixel rows, then per tile its farthest depth over the run; skips tiles
   already that near. */
PVS__STATIC void pvs__tile_run(pvs_raster *r, const pvs__tpoly *t, int simd) {
	int32_t ty, ty0 = (t->j0 + t->jlo) >> PVS__TH_SHIFT, ty1 = (t->j0 + t->jhi) >> PVS__TH_SHIFT;
	float xr[PVS__RASTER_MAXV];
	(void)simd;
	for (ty = ty0; ty <= ty1; ++ty) {
		int32_t jr = ty << PVS__TH_SHIFT, jrow = jr - t->j0, L[PVS__TH], R[PVS__TH], lmin = INT32_MAX, rmax = -1, tx;
		int32_t fl = -1, fr = INT32_MAX; /* columns all four rows cover */
		int d, e, da = -1, db = -1;
		uint32_t pad[PVS__TH], cov[PVS__TH], q[PVS__TH];
		float ya, yb, zy, p, zt, z0;
		pvs__tile *row = r->tile + (size_t)ty * r->tw;
		for (e = 0; e < t->ne; ++e) {
			double X = t->xi[e] + t->s[e] * (double)jrow;
			X = X < -t->cl[e] ? -t->cl[e] : X > t->cl[e] ? t->cl[e] : X;
			xr[e] = (float)X;
		}
#if defined(PVS__LANES)
		if (simd) pvs__tile_rows_simd(t, jrow, xr, L, R);
		else
#endif
			pvs__tile_rows_scalar(t, jrow, xr, L, R);
		for (d = 0; d < PVS__TH; ++d) {
			if (L[d] > R[d]) {
				if (jr + d < (int32_t)r->height) fr = -2; /* an empty row in the map: no tile is full */
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
			if (!(zt > tl->z0)) continue; /* not nearer than the base */
			if (x0 >= fl && (x0 + 31 < (int32_t)r->width ? x0 + 31 : (int32_t)r->width - 1) <= fr) {
				cov[0] = cov[1] = cov[2] = cov[3] = ~0u; /* covers the tile: pvs__tile_merge's first case */
			} else
#if defined(PVS__LANES)
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
			for (d = 0; d < PVS__TH; ++d) q[d] = pad[d] | ((uint32_t)tx == r->tw - 1 ? r->xpad : 0u);
			pvs__tile_merge(tl, cov, zt, q);
			if (tl->z0 != z0)
				r->bdirty[(size_t)(ty >> PVS__BLOCK_SHIFT) * r->bw + (uint32_t)(tx >> PVS__BLOCK_SHIFT)] = 1;
		}
	}
}

/* Edges over t's inner range, as pvs__raster_poly: steep ones become left [0, nl) and right [nl, ne) edges,
   near-horizontal ones narrow rows [jlo, jhi]. 0 when no pixel passes an edge. */
PVS__STATIC int pvs__tile_edges(pvs__tpoly *t, const double *x, const double *y, int n, double area2, double mag,
								double perr) {
	double ox = (double)t->i0, oy = (double)t->j0, iw = (double)(t->i1 - t->i0), jh = (double)(t->j1 - t->j0);
	double rxi[PVS__RASTER_MAXV], rs[PVS__RASTER_MAXV], rcl[PVS__RASTER_MAXV];
	float rsf[PVS__RASTER_MAXV], rm[PVS__RASTER_MAXV];
	int i, nr = 0;
	t->jlo = 0;
	t->jhi = t->j1 - t->j0;
	t->nl = 0;
	for (i = 0; i < n; ++i) {
		double ed[3], a, b, k;
		int r = pvs__raster_edge(x, y, i, n, area2 < 0, ox, oy, iw, jh, mag, perr, 2, ed);
		if (r < 0) return 0;
		if (!r) continue;
		a = ed[0]; b = ed[1]; k = ed[2];
		if (pvs__dabs(a) > pvs__dabs(b) * PVS__U_2_20) {
			/* i >= X(j) for a > 0, i <= X(j) for a < 0; X(jrow) is clamped to +-cl (beyond, all four rows fall on one
			   side); float error at most 3 cl + 13 |s| units of 2^-24 plus 2^-51 (|xi| + |s| |jrow|), below m */
			double xi = -k / a, sl = -b / a, sa = pvs__dabs(sl), cl = iw + 3.0 + 3.0 * sa;
			float m = pvs__f_up(PVS__U_2_21 * cl + PVS__U_2_48 * (pvs__dabs(xi) + sa * (jh + 4.0)));
			if (a > 0.0) {
				t->xi[t->nl] = xi; t->s[t->nl] = sl; t->cl[t->nl] = cl; t->sf[t->nl] = (float)sl; t->m[t->nl] = m;
				++t->nl;
			} else {
				rxi[nr] = xi; rs[nr] = sl; rcl[nr] = cl; rsf[nr] = (float)sl; rm[nr] = m;
				++nr;
			}
		} else {
			/* near-horizontal: the rows where every column of the range passes */
			double wk = k + pvs__dmin(0.0, a * iw), tq = -wk / b,
				   pad = PVS__U_2_44 * (pvs__dabs(k) + pvs__dabs(a) * iw + 1.0);
			if (b > 0.0) {
				int32_t jl = pvs__clampi(ceil(tq + pad), 0, t->jhi + 1);
				if (jl > t->jlo) t->jlo = jl;
			} else {
				int32_t jm = pvs__clampi(floor(tq - pad), -1, t->jhi);
				if (jm < t->jhi) t->jhi = jm;
			}
		}
	}
	if (t->jlo > t->jhi) return 0;
	t->ne = t->nl + nr;
	for (i = 0; i < nr; ++i) {
		t->xi[t->nl + i] = rxi[i];
		t->s[t->nl + i] = rs[i];
		t->cl[t->nl + i] = rcl[i];
		t->sf[t->nl + i] = rsf[i];
		t->m[t->nl + i] = rm[i];
	}
	return 1;
}

/* Depth plane over t's range (as pvs__raster_zplane) less its setup error, zm the loops' float margin, zlo the clamp;
   unusable: zk = -FLT_MAX. */
PVS__STATIC void pvs__tile_zplane(pvs__tpoly *t, const double *x, const double *y, const double *z, int n, double span,
								  double mag, double zmag, double perr, double zerr, double zlo) {
	double iw = (double)(t->i1 - t->i0), jh = (double)(t->j1 - t->j0), p[4];
	t->zlo = pvs__f_down(zlo);
	t->za = t->zb = t->zm = 0.0f;
	t->zk = -FLT_MAX;
	if (pvs__raster_plane(x, y, z, n, (double)t->i0, (double)t->j0, iw, jh, span, mag, zmag, perr, zerr, p)) {
		double za = p[0], zb = p[1], zk = p[2] - p[3], err = p[3], size;
		/* float zk + za x + zb y - zm, x <= iw + 1, y <= jh + 1: at most 6 units of 2^-24 of `size` */
		size = pvs__dabs(zk) + pvs__dabs(za) * (iw + 1.0) + pvs__dabs(zb) * (jh + 1.0);
		if (size < 1e30 && err < 1e30) {
			t->za = (float)za;
			t->zb = (float)zb;
			t->zk = (float)zk;
			t->zm = pvs__f_up(PVS__U_2_20 * size);
		}
	}
}

/* Draws an occluder polygon into the tiles; setup and margins as pvs__raster_poly's. */
PVS__STATIC void pvs__tile_poly(pvs_raster *r, const double *x, const double *y, const double *z, int n, double perr,
								double zerr) {
	pvs__tpoly t;
	pvs__polyext e;
	double span, dx, zlo;
	if (!pvs__poly_extent(x, y, z, n, &e)) return;
	dx = PVS__RASTER_ERR_D * (e.mag + 1.0) + perr;
	zlo = e.zmin - PVS__RASTER_ERR_D * e.zmag - zerr;
	t.i0 = pvs__clampi(ceil(e.xmin + dx), 0, (int32_t)r->width);
	t.i1 = pvs__clampi(floor(e.xmax - dx) - 1.0, -1, (int32_t)r->width - 1);
	t.j0 = pvs__clampi(ceil(e.ymin + dx), 0, (int32_t)r->height);
	t.j1 = pvs__clampi(floor(e.ymax - dx) - 1.0, -1, (int32_t)r->height - 1);
	if (t.i0 > t.i1 || t.j0 > t.j1) return;
	span = (e.xmax - e.xmin) + (e.ymax - e.ymin);
	if (!pvs__poly_usable(&e, span)) return;
	if (!pvs__tile_edges(&t, x, y, n, e.area2, e.mag, perr)) return;
	pvs__tile_zplane(&t, x, y, z, n, span, e.mag, e.zmag, perr, zerr, zlo);
	pvs__tile_run(r, &t, !(r->flags & PVS_RASTER_SCALAR));
}

/* Occludees go to the per-pixel map, cleared on first use (see `mixed`). */
PVS__STATIC void pvs__raster_occludee_begin(pvs_raster *r) {
	size_t i, n = (size_t)r->width * r->height;
	if (r->mixed) return;
	for (i = 0; i < n; ++i) r->depth[i] = PVS_DEPTH_EMPTY;
	for (i = 0; i < r->tiles; ++i) r->tile_min[i] = PVS_DEPTH_EMPTY;
	r->mixed = 1;
}

/* Per-pixel map from the tiles: overwritten, or the nearer where occludees were drawn. */
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
	double e;  /* bound on each coordinate's rounding error */
} pvs__cv;

PVS__STATIC pvs__cv pvs__raster_transform(const pvs_raster *rs, const float *p) {
	const double *m = rs->m;
	pvs__cv v;
	int r;
	double pm = pvs__dmax(pvs__dabs(p[0]), pvs__dmax(pvs__dabs(p[1]), pvs__dabs(p[2])));
	for (r = 0; r < 4; ++r)
		v.c[r] = m[4 * r] * (double)p[0] + m[4 * r + 1] * (double)p[1] + m[4 * r + 2] * (double)p[2] + m[4 * r + 3];
	/* 2^-50 of the terms' size (four products summed in double: 2^-51) */
	v.e = 8.881784197001252e-16 * (rs->mabs[0] * pm + rs->mabs[1]);
	return v;
}

/* Clip-space vertex v to pixels *x, *y (map half sizes hw, hh) and depth *z; *perr, *zerr grow to its error after the
   division, in pixels and in depth. */
PVS__STATIC void pvs__raster_project(const pvs__cv *v, double hw, double hh, double *x, double *y, double *z,
									 double *perr, double *zerr) {
	double iw = 1.0 / v->c[3], e = v->e * iw;
	*x = (v->c[0] * iw + 1.0) * hw;
	*y = (v->c[1] * iw + 1.0) * hh;
	*z = v->c[2] * iw;
	*perr = pvs__dmax(*perr, 2.0 * e * (1.0 + pvs__dabs(v->c[0] * iw) + pvs__dabs(v->c[1] * iw)) * pvs__dmax(hw, hh));
	*zerr = pvs__dmax(*zerr, 2.0 * e * (1.0 + pvs__dabs(*z)));
}

/* Sutherland-Hodgman against w - z >= 0 (near) or w - tiny >= 0; lout gets lin's labels (edge i: vertex i to i + 1;
   NULL: none), PVS__MESH_CLIP along the plane. Cutting from the inside vertex keeps shared edges' cuts identical. */
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

PVS__STATIC void pvs__raster_clipped(pvs_raster *r, const pvs__cv *v, int n, int occluder) {
	pvs__cv t1[PVS__RASTER_MAXV], t2[PVS__RASTER_MAXV];
	double x[PVS__RASTER_MAXV], y[PVS__RASTER_MAXV], z[PVS__RASTER_MAXV];
	double hw = 0.5 * (double)r->width, hh = 0.5 * (double)r->height, perr = 0.0, zerr = 0.0;
	int i;
	const pvs__cv *t = v;
	for (i = 0; i < n; ++i)
		if (!(v[i].c[3] - v[i].c[2] >= 0.0) || !(v[i].c[3] >= 1e-30)) break;
	if (i < n) {
		n = pvs__raster_clip(v, n, t1, 0, NULL, NULL);
		if (n < 3) return;
		n = pvs__raster_clip(t1, n, t2, 1, NULL, NULL);
		if (n < 3) return;
		t = t2;
	}
	for (i = 0; i < n; ++i) pvs__raster_project(t + i, hw, hh, x + i, y + i, z + i, &perr, &zerr);
	if (occluder && r->tiled) {
		pvs__tile_poly(r, x, y, z, n, perr, zerr);
	} else {
		pvs__raster_occludee_begin(r);
		pvs__raster_poly(r->depth, r->width, r->height, r->tile_min, x, y, z, n, occluder,
						 !(r->flags & PVS_RASTER_SCALAR), perr, zerr);
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
	/* all behind the near plane, or all w <= 0 */
	if (v[0].c[3] - v[0].c[2] < 0 && v[1].c[3] - v[1].c[2] < 0 && v[2].c[3] - v[2].c[2] < 0) return;
	if (v[0].c[3] <= 0 && v[1].c[3] <= 0 && v[2].c[3] <= 0) return;
	pvs__raster_clipped(r, v, 3, occluder);
	r->pyramid_valid = 0;
}

/* ---- occluder prefilter: four triangles at a time in float (as Masked Occlusion Culling fills SIMD lanes), dropping
   those behind the near plane, off screen, without a whole pixel or behind every tile's base; the rest go to
   pvs__raster_tri. Dropping an occluder is conservative, so no margins; scalar and SIMD decide alike. ---- */

#define PVS__PF_TILES 16 /* hidden test: tiles one by one in boxes up to this size */

/* Lanes to draw (bit l), those in *test only if not hidden; box, zmax: their whole pixels in the map and nearest vertex
   depth. Lanes partly behind the near or eye plane are drawn untested (clipped later) unless wholly behind one. */
PVS__STATIC unsigned pvs__pf_scalar(const pvs_raster *r, const float *const v[4][3], unsigned *test, int32_t box[4][4],
									float *zmax) {
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

#if defined(PVS__LANES_DIV)
/* v[l][k]: 4 readable floats (the caller copies the last vertex). */
PVS__STATIC unsigned pvs__pf_simd(const pvs_raster *r, const float *const v[4][3], unsigned *test, int32_t box[4][4],
								  float *zmax) {
	const pvs__f4 zero = pvs__f4_set1(0.0f), big = pvs__f4_set1(1e30f), one = pvs__f4_set1(1.0f);
	const pvs__f4 hw = pvs__f4_set1(r->hwf), hh = pvs__f4_set1(r->hhf);
	pvs__f4 X[3], Y[3], Z[3], cz[3], cw[3], x, y, z, xmin, xmax, ymin, ymax, zm, rw;
	pvs__m4 anyb, allb, nonpos, t, fin;
	pvs__i4 i0, i1, j0, j1;
	unsigned all, tst;
	int k;
#define PVS__ROW(o, k) /* mf's row o on vertex k (mb: mf broadcast) */ \
	pvs__f4_add(pvs__f4_add(pvs__f4_add(pvs__f4_mul(pvs__f4_load(r->mb[o]), X[k]), \
										pvs__f4_mul(pvs__f4_load(r->mb[o + 1]), Y[k])), \
							pvs__f4_mul(pvs__f4_load(r->mb[o + 2]), Z[k])), \
				pvs__f4_load(r->mb[o + 3]))
	for (k = 0; k < 3; ++k) {
		pvs__f4_xyz(v[0][k], v[1][k], v[2][k], v[3][k], &X[k], &Y[k], &Z[k]);
		cz[k] = PVS__ROW(8, k);
		cw[k] = PVS__ROW(12, k);
	}
	allb = pvs__f4_gt(cz[0], cw[0]);
	nonpos = pvs__f4_le(cw[0], zero);
	anyb = pvs__m4_or(allb, nonpos);
	for (k = 1; k < 3; ++k) {
		t = pvs__f4_gt(cz[k], cw[k]);
		fin = pvs__f4_le(cw[k], zero);
		allb = pvs__m4_and(allb, t);
		nonpos = pvs__m4_and(nonpos, fin);
		anyb = pvs__m4_or(anyb, pvs__m4_or(t, fin));
	}
	all = (unsigned)pvs__m4_bits(pvs__m4_or(allb, nonpos));
	*test = 0;
	if (all == 15u) return 0; /* all four behind the near plane or the eye */
	if ((unsigned)pvs__m4_bits(anyb) == 15u) return all ^ 15u;
	xmin = xmax = ymin = ymax = zm = zero;
	for (k = 0; k < 3; ++k) {
		rw = pvs__f4_div(one, cw[k]);
		x = pvs__f4_add(pvs__f4_mul(pvs__f4_mul(PVS__ROW(0, k), rw), hw), hw);
		y = pvs__f4_add(pvs__f4_mul(pvs__f4_mul(PVS__ROW(4, k), rw), hh), hh);
		z = pvs__f4_mul(cz[k], rw);
		if (k == 0) {
			xmin = xmax = x; ymin = ymax = y; zm = z;
		} else {
			xmin = pvs__f4_min(x, xmin); xmax = pvs__f4_max(x, xmax);
			ymin = pvs__f4_min(y, ymin); ymax = pvs__f4_max(y, ymax);
			zm = pvs__f4_max(z, zm);
		}
	}
#undef PVS__ROW
	/* a NaN can drop out of min and max, dropping the triangle as the scalar loop does (conservative) */
	fin = pvs__m4_and(pvs__f4_lt(pvs__f4_abs(xmin), big), pvs__f4_lt(pvs__f4_abs(xmax), big));
	fin = pvs__m4_and(fin, pvs__m4_and(pvs__f4_lt(pvs__f4_abs(ymin), big), pvs__f4_lt(pvs__f4_abs(ymax), big)));
	fin = pvs__m4_and(fin, pvs__f4_lt(pvs__f4_abs(zm), big));
	/* clamped to the map; the untested lanes zeroed to keep their conversions in range */
	t = pvs__m4_andn(fin, anyb);
	xmin = pvs__f4_sel(t, pvs__f4_max(xmin, zero), zero);
	xmax = pvs__f4_sel(t, pvs__f4_min(xmax, pvs__f4_set1((float)r->width)), zero);
	ymin = pvs__f4_sel(t, pvs__f4_max(ymin, zero), zero);
	ymax = pvs__f4_sel(t, pvs__f4_min(ymax, pvs__f4_set1((float)r->height)), zero);
	i0 = pvs__f4_ceili(xmin);
	i1 = pvs__i4_sub(pvs__f4_floori(xmax), pvs__i4_set1(1));
	j0 = pvs__f4_ceili(ymin);
	j1 = pvs__i4_sub(pvs__f4_floori(ymax), pvs__i4_set1(1));
	pvs__i4_store(box[0], i0);
	pvs__i4_store(box[1], i1);
	pvs__i4_store(box[2], j0);
	pvs__i4_store(box[3], j1);
	pvs__f4_store(zmax, zm);
	tst = (unsigned)pvs__m4_bits(t);
	*test = tst & ~(unsigned)pvs__m4_bits(pvs__m4_or(pvs__i4_gt(i0, i1), pvs__i4_gt(j0, j1)));
	return (all ^ 15u) & ~(tst & ~*test);
}
#endif

PVS__STATIC int pvs__pf_tiles(const pvs_raster *r, uint32_t tx0, uint32_t tx1, uint32_t ty0, uint32_t ty1, float zmax) {
	uint32_t tx, ty;
	for (ty = ty0; ty <= ty1; ++ty)
		for (tx = tx0; tx <= tx1; ++tx)
			if (!(r->tile[(size_t)ty * r->tw + tx].z0 >= zmax)) return 0;
	return 1;
}

/* 1 when every tile under box [i0, i1] x [j0, j1] has a base as near as zmax. Large boxes try blocks first (bases only
   grow: a stale block minimum is a lower bound, retaken on failure). */
PVS__STATIC int pvs__pf_hidden(pvs_raster *r, int32_t box[4][4], int l, float zmax) {
	uint32_t tx0 = (uint32_t)box[0][l] >> PVS__TW_SHIFT, tx1 = (uint32_t)box[1][l] >> PVS__TW_SHIFT;
	uint32_t ty0 = (uint32_t)box[2][l] >> PVS__TH_SHIFT, ty1 = (uint32_t)box[3][l] >> PVS__TH_SHIFT, bx, by;
	if ((tx1 - tx0 + 1) * (ty1 - ty0 + 1) <= PVS__PF_TILES) return pvs__pf_tiles(r, tx0, tx1, ty0, ty1, zmax);
	for (by = ty0 >> PVS__BLOCK_SHIFT; by <= ty1 >> PVS__BLOCK_SHIFT; ++by)
		for (bx = tx0 >> PVS__BLOCK_SHIFT; bx <= tx1 >> PVS__BLOCK_SHIFT; ++bx) {
			size_t k = (size_t)by * r->bw + bx;
			uint32_t x0 = bx << PVS__BLOCK_SHIFT, y0 = by << PVS__BLOCK_SHIFT, x1 = x0 + (1u << PVS__BLOCK_SHIFT) - 1,
					 y1 = y0 + (1u << PVS__BLOCK_SHIFT) - 1;
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
			if (!pvs__pf_tiles(r, x0 > tx0 ? x0 : tx0, x1 < tx1 ? x1 : tx1, y0 > ty0 ? y0 : ty0, y1 < ty1 ? y1 : ty1,
							   zmax))
				return 0;
		}
	return 1;
}

/* Triangle t's vertices: those of scene triangle tris[t].triangle (tris not NULL), indices[3 t ..] or 3 t ... */
PVS__STATIC void pvs__tri_corners(const uint32_t *indices, const pvs__occsel *tris, uint32_t t, uint32_t q[3]) {
	const uint32_t *ix = tris ? indices + 3 * (size_t)tris[t].triangle : indices ? indices + 3 * (size_t)t : NULL;
	q[0] = ix ? ix[0] : 3 * t;
	q[1] = ix ? ix[1] : 3 * t + 1;
	q[2] = ix ? ix[2] : 3 * t + 2;
}

/* Occluder triangles through the prefilter, four at a time: `count` of `positions` (indices or NULL) or scene triangles
   tris[0 .. count). */
PVS__STATIC void pvs__raster_occluders(pvs_raster *r, const float *positions, uint32_t vertex_count,
									   const uint32_t *indices, const pvs__occsel *tris, uint32_t count) {
	uint32_t t, l, k;
	const float *v[4][3];
	float last[4], zmax[4];
	unsigned draw, test;
	int n;
	int32_t box[4][4];
	if (!vertex_count) return;
	last[0] = positions[3 * ((size_t)vertex_count - 1)]; /* SIMD loads read 4 floats: copy the last vertex */
	last[1] = positions[3 * ((size_t)vertex_count - 1) + 1];
	last[2] = positions[3 * ((size_t)vertex_count - 1) + 2];
	last[3] = 0.0f;
	for (t = 0; t < count; t += 4) {
		n = 0;
		for (l = 0; l < 4 && t + l < count; ++l) {
			uint32_t q[3];
			pvs__tri_corners(indices, tris, t + l, q);
			if (q[0] >= vertex_count || q[1] >= vertex_count || q[2] >= vertex_count) continue;
			for (k = 0; k < 3; ++k) v[n][k] = q[k] + 1 == vertex_count ? last : positions + 3 * (size_t)q[k];
			++n;
		}
		if (!n) continue;
		for (l = (uint32_t)n; l < 4; ++l)
			for (k = 0; k < 3; ++k) v[l][k] = v[0][k];
#if defined(PVS__LANES_DIV)
		if (!(r->flags & PVS_RASTER_SCALAR)) draw = pvs__pf_simd(r, (const float *const(*)[3])v, &test, box, zmax);
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

/* Triangles one by one (pvs__tri_corners; those with a vertex out of range are left out); tiled occluders through the
   prefilter. */
PVS__STATIC void pvs__raster_tris(pvs_raster *r, const float *pos, uint32_t vc, const uint32_t *indices,
								  const pvs__occsel *tris, uint32_t count, int occluder) {
	uint32_t t, q[3];
	if (occluder && r->tiled) {
		pvs__raster_occluders(r, pos, vc, indices, tris, count);
		return;
	}
	for (t = 0; t < count; ++t) {
		pvs__tri_corners(indices, tris, t, q);
		if (q[0] < vc && q[1] < vc && q[2] < vc)
			pvs__raster_tri(r, pos + 3 * (size_t)q[0], pos + 3 * (size_t)q[1], pos + 3 * (size_t)q[2], occluder);
	}
}

/* ---- occluder meshes (Durand 2000 §3.3; contract: pvs_raster_mesh) ----

   An edge is internal when (i) exactly two triangles of the piece share it (welded by index and position), (ii) both
   have the same certain facing (sign of det(x, y, w) in clip space) and run it in opposite directions, (iii) an end
   is surely in front of both clip planes, neither within rounding of one; the others, and clip-plane edges, form the
   group's boundary B. Then the boundary of the group's union U lies in B: along an internal edge the two triangles lie
   on opposite sides (det(a, b, p) = gamma det(a, b, c), gamma > 0), each covering a half-disk by (iii); clipping
   vertices end clip edges; at an original vertex with only internal edges the closed fans turn by positive multiples
   of 2 pi, covering a neighbourhood by (iii). So a (connected) pixel that surely meets U and that no B edge may meet
   (separating-axis tests with margins) lies in U, no nearer than the least plane minimum or vertex depth of the group
   polygons that may touch it. Folds, back faces, non-manifold edges, bad winding, T-junctions and near-plane cuts
   only add boundary edges.

   Two passes: the triangles through the ordinary occluder path, then the mesh pass over strips where an edge may
   meet a pixel (wider than the first pass's float margins): a strip pixel no edge meets lies in one polygon that
   surely meets it, else the edges split it among polygons whose strips hold it. One code path (double, the pixel
   loops' float depth): SIMD and scalar agree. ---- */

#define PVS__MESH_NONE 0xffffffffu
#define PVS__MESH_MULTI 0xfffffffeu
#define PVS__MESH_DEFAULT 4096u
#define PVS__MESH_MAXV 5 /* a triangle clipped by two planes */

typedef struct pvs__mtri {
	int32_t i0, i1, j0, j1; /* pixels that may meet it, clamped to the map (empty: i0 > i1 or j0 > j1) */
	int n;                          /* polygon vertices, 3..5 */
	int full;                       /* edges of non-zero length (the inner test needs 3) */
	uint8_t lab[PVS__MESH_MAXV];    /* edge k (vertex k to k + 1): triangle edge 0..2 or PVS__MESH_CLIP */
	uint8_t bnd[PVS__MESH_MAXV];    /* 1: a boundary edge */
	double x[PVS__MESH_MAXV], y[PVS__MESH_MAXV];
	double a[PVS__MESH_MAXV], b[PVS__MESH_MAXV], k[PVS__MESH_MAXV], e[PVS__MESH_MAXV]; /* E = a x + b y + k >= 0
									   inside, |a| + |b| = 1 (0, 0: zero length); |E - exact| < e */
	double xmin, xmax, ymin, ymax, dx; /* dx bounds the vertices' error */
	double wide;                    /* beyond the first pass's rounding: what it misses by an edge is in the strip */
	float za, zb, zk, zclamp;       /* over pixel (i0 + fi, j0 + fj): max((zk + zb fj) + za fi, zclamp) */
} pvs__mtri;

/* Clips, projects and prepares clip-space triangle v of facing `orient` (+1 / -1); 0 when nothing is left. */
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
		pvs__raster_project(p + i, hw, hh, t->x + i, t->y + i, z + i, &perr, &zerr);
		if (!(t->x[i] == t->x[i] && t->y[i] == t->y[i] && z[i] == z[i])) return 0;
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
	/* pixels whose closed square meets the box widened by dx */
	t->i0 = pvs__clampi(ceil(t->xmin - t->dx) - 1.0, 0, (int32_t)r->width);
	t->i1 = pvs__clampi(floor(t->xmax + t->dx), -1, (int32_t)r->width - 1);
	t->j0 = pvs__clampi(ceil(t->ymin - t->dx) - 1.0, 0, (int32_t)r->height);
	t->j1 = pvs__clampi(floor(t->ymax + t->dx), -1, (int32_t)r->height - 1);
	ox = (double)t->i0;
	oy = (double)t->j0;
	iw = pvs__dmax(0.0, (double)(t->i1 - t->i0));
	jh = pvs__dmax(0.0, (double)(t->j1 - t->j0));
	/* double rounding at pixel corners (X, Y <= mag + map size) is far below this */
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
		/* line through vertices off by dx (pvs__raster_poly's bound), plus evaluation */
		t->e[i] = (PVS__RASTER_ERR_D * (1.0 + mag) + perr) *
					  (1.0 + (pvs__dabs(ox - t->x[i]) + pvs__dabs(oy - t->y[i]) + iw + jh + 2.0) / len) + noise;
		++t->full;
	}
	span = (t->xmax - t->xmin) + (t->ymax - t->ymin);
	t->zclamp = pvs__f_down(zmin - PVS__RASTER_ERR_D * zmag - zerr);
	pvs__raster_zplane(t->x, t->y, z, n, ox, oy, iw, jh, span, mag, zmag, perr, zerr, 1, &t->za, &t->zb, &t->zk);
	return 1;
}

/* Narrows columns [*lo, *hi] to a i + c >= t (double). outer: may keep failing columns, never drops passing ones; else
   the reverse. Bounds are checked against neighbours: with t's margin they hold for the exact a i + c. */
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
			if (i > *lo && !(a * (double)(i - 1) + c < t)) i = *lo; /* unsettled: keep all */
		} else if (i <= *hi && !(a * (double)i + c >= t)) {
			i = *hi + 1; /* unsettled: keep none */
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

/* Polygon t on row j of band jb, along its edges: over pixels an edge may meet, its least depth bound; flag 1: surely
   meets the pixel, 2: a boundary edge may. rlo, rhi: touched columns per row. */
PVS__STATIC void pvs__mesh_row(pvs_raster *r, const pvs__mtri *t, int32_t j, int32_t jb, int32_t *rlo, int32_t *rhi) {
	const uint32_t W = r->width;
	float *zm = r->mzmin + (size_t)(j - jb) * W;
	uint8_t *fl = r->mflag + (size_t)(j - jb) * W, *dw = r->mdirty + (size_t)(j - jb) * r->tw;
	float fj = (float)(j - t->j0), rz = t->zk + t->zb * fj, d;
	double dj = (double)j;
	int32_t lo, hi, clo = 0, chi = -1, i;
	int e;
	/* surely meets: extents overlap the pixel and no edge separates */
	if (dj + 1.0 >= t->ymin + t->dx && dj <= t->ymax - t->dx) {
		clo = pvs__clampi(ceil(t->xmin + t->dx) - 1.0, t->i0, t->i1 + 1);
		chi = pvs__clampi(floor(t->xmax - t->dx), t->i0 - 1, t->i1);
		for (e = 0; e < t->n; ++e)
			if (t->a[e] != 0.0 || t->b[e] != 0.0)
				pvs__mesh_cut(t->a[e], t->b[e] * dj + t->k[e] + pvs__dmax(0.0, t->a[e]) + pvs__dmax(0.0, t->b[e]),
							  t->e[e], 0, &clo, &chi);
	}
	/* each edge: the pixels whose closed square it may meet (extents and line) */
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
			pvs__mesh_cut(t->a[e], t->b[e] * dj + t->k[e] + pvs__dmax(0.0, t->a[e]) + pvs__dmax(0.0, t->b[e]), -m, 1,
						  &lo, &hi);
			pvs__mesh_cut(-t->a[e], -(t->b[e] * dj + t->k[e] + pvs__dmin(0.0, t->a[e]) + pvs__dmin(0.0, t->b[e])), -m,
						  1, &lo, &hi);
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

/* A band pixel's claimed depth (PVS_DEPTH_EMPTY: none); resets its scratch. */
PVS__STATIC float pvs__mesh_take(pvs_raster *r, size_t q) {
	float z = PVS_DEPTH_EMPTY;
	if (r->mflag[q] == 1u && r->mzmin[q] < FLT_MAX && r->mzmin[q] > z) z = r->mzmin[q];
	r->mzmin[q] = FLT_MAX;
	r->mflag[q] = 0;
	return z;
}

/* Writes band b's claimed pixels to the depth map or, tiled, per tile as a mask at the least claimed depth. */
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
				if (!dw[i >> PVS__TW_SHIFT]) { /* empty word: skip it */
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
		/* unlike pvs__tile_merge, spare the layer (edge pixels are few, often farther): union at the farther depth if
		   zt is no farther, the tile fills or the layer loses at most 1/8 of its lead; a new layer if none */
		{
			uint32_t full = ~0u, have = 0;
			for (d = 0; d < PVS__TH; ++d) {
				have |= tl->mask[d];
				full &= tl->mask[d] | cov[d] | pad[d];
			}
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

/* Draws the piece's polygons of facing g by bands of four rows over an active list sorted by first band. */
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
			int32_t jb = (int32_t)(b << PVS__TH_SHIFT), ja = p->j0 > jb ? p->j0 : jb,
					jz = p->j1 < jb + 3 ? p->j1 : jb + 3;
			for (j = ja; j <= jz; ++j) pvs__mesh_row(r, p, j, jb, rlo, rhi);
		}
		pvs__mesh_claim(r, b, rlo, rhi);
		for (k = keep = 0; k < na; ++k)
			if ((uint32_t)r->mt[act[k]].j1 >> PVS__TH_SHIFT > b) act[keep++] = act[k];
		na = keep;
		++b;
	}
}

/* Facing: sign of det(x, y, w), 0 within rounding: entries off by e move it at most 6 ((M + e)^3 - M^3), evaluation
   1e-14 (M + e)^3. */
PVS__STATIC int pvs__mesh_facing(const pvs__cv *v) {
	const double *p = v[0].c, *q = v[1].c, *s = v[2].c;
	double d =
		p[0] * (q[1] * s[3] - s[1] * q[3]) - p[1] * (q[0] * s[3] - s[0] * q[3]) + p[3] * (q[0] * s[1] - s[0] * q[1]);
	double M = 0.0, e = pvs__dmax(v[0].e, pvs__dmax(v[1].e, v[2].e)), bound;
	int i;
	for (i = 0; i < 3; ++i)
		M = pvs__dmax(M, pvs__dmax(pvs__dabs(v[i].c[0]), pvs__dmax(pvs__dabs(v[i].c[1]), pvs__dabs(v[i].c[3]))));
	/* = e (3 M^2 + 3 M e + e^2): no cancellation */
	bound =
		6.0 * e * (3.0 * M * M + 3.0 * M * e + e * e) * (1.0 + 1e-14) + 1e-14 * (M + e) * (M + e) * (M + e) + 1e-300;
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

/* The piece's first vertex at position p, found or entered (open addressing in hs slots; 0 empty, else vertex + 1). */
PVS__STATIC uint32_t pvs__mesh_weld(uint32_t *tab, uint32_t hs, const float *pos, uint32_t q, const float *p) {
	uint32_t x = pvs__mesh_fbits(p[0]), y = pvs__mesh_fbits(p[1]), z = pvs__mesh_fbits(p[2]), h;
	h = (x * 0x9E3779B1u) ^ (y * 0x85EBCA77u) ^ (z * 0xC2B2AE3Du);
	h = (h ^ (h >> 15)) & (hs - 1);
	for (;;) {
		if (!tab[h]) {
			tab[h] = q + 1;
			return q;
		}
		{
			const float *o = pos + 3 * (size_t)(tab[h] - 1);
			if (o[0] == p[0] && o[1] == p[1] && o[2] == p[2]) return tab[h] - 1;
		}
		h = (h + 1) & (hs - 1);
	}
}

/* Triangle t (q: vertex indices): welds corners (r->mcid), transforms, clips and prepares (r->mt[t]), marks corners
   against the clip planes (r->mvst). r->mgrp[t]: facing, or 0 (bad, hidden, degenerate, clipped, unsure). */
PVS__STATIC void pvs__mesh_tri(pvs_raster *r, const float *pos, uint32_t vc, const uint32_t q[3], uint32_t hs,
							   uint32_t t) {
	uint32_t k, *cid = r->mcid;
	const float *p[3];
	pvs__cv v[3];
	int ok = 1, g;
	r->mgrp[t] = 0;
	for (k = 0; k < 3 && ok; ++k) {
		ok = q[k] < vc;
		if (ok) {
			p[k] = pos + 3 * (size_t)q[k];
			ok = pvs__finite(p[k][0]) && pvs__finite(p[k][1]) && pvs__finite(p[k][2]);
		}
	}
	if (!ok) return;
	if (r->tiled) { /* hidden behind earlier pieces: changes nothing; its edges become boundary edges */
		const float *pv[4][3];
		unsigned test, l;
		int32_t box[4][4];
		float zmax[4];
		for (l = 0; l < 4; ++l) { pv[l][0] = p[0]; pv[l][1] = p[1]; pv[l][2] = p[2]; }
		if ((pvs__pf_scalar(r, (const float *const(*)[3])pv, &test, box, zmax) & test & 1u) &&
			pvs__pf_hidden(r, box, 0, zmax[0]))
			return;
	}
	for (k = 0; k < 3; ++k) cid[3 * t + k] = pvs__mesh_weld(r->mtab, hs, pos, q[k], p[k]);
	if (cid[3 * t] == cid[3 * t + 1] || cid[3 * t + 1] == cid[3 * t + 2] || cid[3 * t + 2] == cid[3 * t]) return;
	for (k = 0; k < 3; ++k) v[k] = pvs__raster_transform(r, p[k]);
	if (v[0].c[3] - v[0].c[2] < 0 && v[1].c[3] - v[1].c[2] < 0 && v[2].c[3] - v[2].c[2] < 0) return;
	if (v[0].c[3] <= 0 && v[1].c[3] <= 0 && v[2].c[3] <= 0) return;
	g = pvs__mesh_facing(v);
	if (!g || !pvs__mesh_setup(r, v, g, r->mt + t)) return;
	for (k = 0; k < 3; ++k) { /* 1: surely in front of both clip planes, 2: surely behind one, 0: unsure */
		double w = v[k].c[3], zc = v[k].c[2], e = v[k].e;
		double m1 = 2.0 * e + 4.5e-16 * (pvs__dabs(w) + pvs__dabs(zc)), m2 = e + 4.5e-16 * pvs__dabs(w) + 1e-45;
		r->mvst[3 * t + k] = (uint8_t)(w - zc > m1 && w - 1e-30 > m2 ? 1 : w - zc < -m1 || w - 1e-30 < -m2 ? 2 : 0);
	}
	r->mgrp[t] = (int8_t)g;
}

/* Pairs half-edges by welded end points: r->mpart[he] = partner, PVS__MESH_NONE or PVS__MESH_MULTI (3 or more). */
PVS__STATIC void pvs__mesh_partners(pvs_raster *r, uint32_t n, uint32_t hs) {
	uint32_t t, k, h, *tab = r->mtab, *cid = r->mcid, *part = r->mpart;
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
}

/* Clears the boundary flag of internal edges (conditions (i)-(iii) above). */
PVS__STATIC void pvs__mesh_internal(pvs_raster *r, uint32_t n) {
	uint32_t t, *cid = r->mcid, *part = r->mpart;
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
			if (cid[he] != cid[3 * (o / 3) + (o % 3 + 1) % 3]) continue; /* same direction */
			if (!(sa == 1 || sb == 1) || !sa || !sb) continue;
			p->bnd[e] = 0;
		}
	}
}

/* One mesh piece: triangles first .. first + n - 1 (n <= mesh_cap). */
PVS__STATIC void pvs__mesh_piece(pvs_raster *r, const float *pos, uint32_t vc, const uint32_t *indices,
								 const pvs__occsel *tris, uint32_t first, uint32_t n) {
	uint32_t hs = 16, t, h;
	while (hs < 6 * n && hs < r->mesh_hash) hs <<= 1;
	for (h = 0; h < hs; ++h) r->mtab[h] = 0;
	for (t = 0; t < n; ++t) {
		uint32_t q[3];
		pvs__tri_corners(indices, tris, first + t, q);
		pvs__mesh_tri(r, pos, vc, q, hs, t);
	}
	pvs__mesh_partners(r, n, hs);
	pvs__mesh_internal(r, n);
	pvs__mesh_draw(r, n, 1);
	pvs__mesh_draw(r, n, -1);
}

/* Occluder meshes in pieces of mesh_cap triangles (`indices` NULL: consecutive vertices). */
PVS__STATIC void pvs__mesh(pvs_raster *r, const float *pos, uint32_t vc, const uint32_t *indices,
						   const pvs__occsel *tris, uint32_t count) {
	uint32_t first;
	if (!count || !vc) return;
	pvs__raster_tris(r, pos, vc, indices, tris, count, 1);
	if (!r->tiled) pvs__raster_occludee_begin(r);
	for (first = 0; first < count; first += r->mesh_cap)
		pvs__mesh_piece(r, pos, vc, indices, tris, first, count - first < r->mesh_cap ? count - first : r->mesh_cap);
	r->pyramid_valid = 0;
}

PVS_API pvs_result pvs_camera_matrix(const pvs_camera *c, float aspect, float m[16]) {
	double f[3], u[3], rt[3], len, fu, e[3], sx, sy;
	int k;
	if (!c || !m) return PVS_ERROR_INVALID_ARGUMENT;
	for (k = 0; k < 3; ++k)
		if (!pvs__finite(c->eye[k]) || !pvs__finite(c->forward[k]) || !pvs__finite(c->up[k]))
			return PVS_ERROR_NOT_FINITE;
	if (!pvs__finite(c->fov_y) || !pvs__finite(c->near_plane) || !pvs__finite(aspect) ||
		!pvs__finite(c->ortho_height) || !pvs__finite(c->far_plane))
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
	sy = c->fov_y > 0.0f ? 1.0 / tan(0.5 * (double)c->fov_y) : 2.0 / c->ortho_height;
	sx = sy / (double)aspect;
	for (k = 0; k < 3; ++k) {
		m[k] = (float)(sx * rt[k]);
		m[4 + k] = (float)(sy * u[k]);
	}
	m[3] = (float)(-sx * (rt[0] * e[0] + rt[1] * e[1] + rt[2] * e[2]));
	m[7] = (float)(-sy * (u[0] * e[0] + u[1] * e[1] + u[2] * e[2]));
	if (c->fov_y > 0.0f) {
		for (k = 0; k < 3; ++k) {
			m[8 + k] = 0.0f;
			m[12 + k] = (float)f[k];
		}
		m[11] = c->near_plane;
		m[15] = (float)-(f[0] * e[0] + f[1] * e[1] + f[2] * e[2]);
	} else {
		double far_d = c->far_plane > c->near_plane ? c->far_plane : (double)c->near_plane + 1e4;
		double range = far_d - c->near_plane;
		for (k = 0; k < 3; ++k) {
			m[8 + k] = (float)(-f[k] / range);
			m[12 + k] = 0.0f;
		}
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
		r->mabs[0] = pvs__dmax(r->mabs[0], r->rowa[k]);
		r->mabs[1] = pvs__dmax(r->mabs[1], r->rowt[k]);
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
	r->mixed = 0;
	r->pyramid_valid = 0;
}

PVS_API pvs_result pvs_raster_triangles(pvs_raster *r, const float *positions, uint32_t vertex_count,
										const uint32_t *indices, uint32_t count, pvs_raster_mode mode) {
	if (!r || (!positions && count) || (int)mode < 0 || mode >= PVS_RASTER_MODE_COUNT)
		return PVS_ERROR_INVALID_ARGUMENT;
	pvs__raster_tris(r, positions, vertex_count, indices, NULL, count, mode == PVS_RASTER_OCCLUDER);
	return PVS_OK;
}

PVS_API pvs_result pvs_raster_mesh(pvs_raster *r, const float *positions, uint32_t vertex_count,
								   const uint32_t *indices, uint32_t count) {
	if (!r || (!positions && count)) return PVS_ERROR_INVALID_ARGUMENT;
	pvs__mesh(r, positions, vertex_count, indices, NULL, count);
	return PVS_OK;
}

PVS_API const float *pvs_raster_depth(const pvs_raster *r, uint32_t *w, uint32_t *h) {
	if (w) *w = r->width;
	if (h) *h = r->height;
	pvs__tile_resolve((pvs_raster *)r); /* a cache the context owns */
	return r->depth;
}

/* ---- depth pyramid (Durand 2000 §2.4; Greene et al. 1993), queried top-down until a level decides (§6.1) ---- */

/* One pyramid level, the kernel of all pyramids in pvs.h: texel (x, y) gets the least smin (into dmin; both may be
   NULL) and the greatest smax (into dmax) of texels [x << mx, (x << mx) + mx] x [y << my, (y << my) + my] of the pw x
   ph level below, clamped (mx, my: 1 halves that axis). `simd` (SSE2, both halved) pairs in another order: equal
   results but for ties of zeros of opposite sign (or NaN). */
PVS__STATIC void pvs__pyramid_level(const float *smin, const float *smax, uint32_t pw, uint32_t ph, float *dmin,
									float *dmax, uint32_t w, uint32_t h, uint32_t mx, uint32_t my, int simd) {
	uint32_t x, y;
	(void)simd;
	for (y = 0; y < h; ++y) {
		uint32_t y0 = y << my, y1 = y0 + my < ph ? y0 + my : y0;
		const float *n0 = smin ? smin + (size_t)y0 * pw : NULL, *n1 = smin ? smin + (size_t)y1 * pw : NULL;
		const float *m0 = smax + (size_t)y0 * pw, *m1 = smax + (size_t)y1 * pw;
		float *on = dmin ? dmin + (size_t)y * w : NULL, *om = dmax + (size_t)y * w;
		x = 0;
#if defined(PVS__SSE2)
		if (simd && mx && my)
			for (; 2 * x + 8 <= pw; x += 4) { /* the two rows, then even and odd columns */
				__m128 v0, v1;
				if (on) {
					v0 = _mm_min_ps(_mm_loadu_ps(n0 + 2 * x), _mm_loadu_ps(n1 + 2 * x));
					v1 = _mm_min_ps(_mm_loadu_ps(n0 + 2 * x + 4), _mm_loadu_ps(n1 + 2 * x + 4));
					_mm_storeu_ps(on + x, _mm_min_ps(_mm_shuffle_ps(v0, v1, _MM_SHUFFLE(2, 0, 2, 0)),
													 _mm_shuffle_ps(v0, v1, _MM_SHUFFLE(3, 1, 3, 1))));
				}
				v0 = _mm_max_ps(_mm_loadu_ps(m0 + 2 * x), _mm_loadu_ps(m1 + 2 * x));
				v1 = _mm_max_ps(_mm_loadu_ps(m0 + 2 * x + 4), _mm_loadu_ps(m1 + 2 * x + 4));
				_mm_storeu_ps(om + x, _mm_max_ps(_mm_shuffle_ps(v0, v1, _MM_SHUFFLE(2, 0, 2, 0)),
												 _mm_shuffle_ps(v0, v1, _MM_SHUFFLE(3, 1, 3, 1))));
			}
#endif
		for (; x < w; ++x) {
			uint32_t x0 = x << mx, x1 = x0 + mx < pw ? x0 + mx : x0;
			float a, c;
			if (on) {
				a = n0[x0] < n0[x1] ? n0[x0] : n0[x1];
				c = n1[x0] < n1[x1] ? n1[x0] : n1[x1];
				on[x] = a < c ? a : c;
			}
			a = m0[x0] > m0[x1] ? m0[x0] : m0[x1];
			c = m1[x0] > m1[x1] ? m1[x0] : m1[x1];
			om[x] = a > c ? a : c;
		}
	}
}

/* Tile pyramid: level 0 per tile its base and nearest value; each level above merges 1 x 2, 2 x 1 or 2 x 2 texels
   (about square in pixels). */
PVS__STATIC void pvs__tile_pyramid(pvs_raster *r) {
	uint32_t l, n = r->tw * r->th, i;
	float *lo = r->tlmin[0], *hi = r->tlmax[0];
	for (i = 0; i < n; ++i) {
		const pvs__tile *t = r->tile + i;
		lo[i] = t->z0;
		hi[i] = (t->mask[0] | t->mask[1] | t->mask[2] | t->mask[3]) ? t->z1 : t->z0;
	}
	for (l = 1; l <= r->tlevels; ++l)
		pvs__pyramid_level(r->tlmin[l - 1], r->tlmax[l - 1], r->tlw[l - 1], r->tlh[l - 1], r->tlmin[l], r->tlmax[l],
						   r->tlw[l], r->tlh[l], r->tsx[l] != r->tsx[l - 1], r->tsy[l] != r->tsy[l - 1], 0);
	r->pyramid_valid = 2;
}

PVS_API void pvs_raster_build_pyramid(pvs_raster *r) {
	uint32_t l;
	if (r->tiled && !r->mixed) {
		pvs__tile_pyramid(r);
		return;
	}
	pvs__tile_resolve(r);
	r->lmin[0] = r->lmax[0] = r->depth;
	for (l = 1; l <= r->levels; ++l)
		pvs__pyramid_level(r->lmin[l - 1], r->lmax[l - 1], r->lw[l - 1], r->lh[l - 1], r->lmin[l], r->lmax[l], r->lw[l],
						   r->lh[l], 1, 1, !(r->flags & PVS_RASTER_SCALAR));
	r->pyramid_valid = 1;
}

/* 1 if a level-0 pixel of [x0, x1] x [y0, y1] under texel (tx, ty) of level l stores a depth <= d. */
PVS__STATIC int pvs__pyramid_visible(const pvs_raster *r, uint32_t l, uint32_t tx, uint32_t ty, int32_t x0, int32_t y0,
									 int32_t x1, int32_t y1, float d) {
	uint32_t w = r->lw[l];
	float lo = r->lmin[l][ty * w + tx], hi = r->lmax[l][ty * w + tx];
	uint32_t cx, cy, cx0, cx1, cy0, cy1, pw, ph;
	if (lo > d) return 0;   /* all nearer: hidden */
	if (hi <= d) return 1;  /* all farther: visible (the texel meets the rect) */
	/* l > 0 here: level-0 texels have lo == hi */
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

/* pvs__pyramid_visible on the tile pyramid; at a tile the layer mask decides exactly. px: pixels, tr: their tiles. */
PVS__STATIC int pvs__tpyr_visible(const pvs_raster *r, uint32_t l, uint32_t tx, uint32_t ty, const int32_t *px,
								  const uint32_t *tr, float d) {
	uint32_t w = r->tlw[l], cx, cy, cx0, cx1, cy0, cy1;
	float lo = r->tlmin[l][ty * w + tx], hi = r->tlmax[l][ty * w + tx];
	if (lo > d) return 0;
	if (hi <= d) return 1;
	if (l == 0) { /* z0 <= d < z1: visible where the rectangle leaves the layer */
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
			if (((cx + 1) << sx) - 1 < tr[0] || (cx << sx) > tr[2] || ((cy + 1) << sy) - 1 < tr[1] ||
				(cy << sy) > tr[3])
				continue;
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
		while (l < r->tlevels &&
			   ((tr[2] >> r->tsx[l]) - (tr[0] >> r->tsx[l]) > 1 || (tr[3] >> r->tsy[l]) - (tr[1] >> r->tsy[l]) > 1))
			++l;
		for (ty = tr[1] >> r->tsy[l]; ty <= tr[3] >> r->tsy[l]; ++ty)
			for (tx = tr[0] >> r->tsx[l]; tx <= tr[2] >> r->tsx[l]; ++tx)
				if (pvs__tpyr_visible(r, l, tx, ty, px, tr, depth)) return 1;
		return 0;
	}
	while (l < r->levels &&
		   (((uint32_t)x1 >> l) - ((uint32_t)x0 >> l) > 1 || ((uint32_t)y1 >> l) - ((uint32_t)y0 >> l) > 1))
		++l;
	for (ty = (uint32_t)y0 >> l; ty <= (uint32_t)y1 >> l; ++ty)
		for (tx = (uint32_t)x0 >> l; tx <= (uint32_t)x1 >> l; ++tx)
			if (pvs__pyramid_visible(r, l, tx, ty, x0, y0, x1, y1, depth)) return 1;
	return 0;
}

/* ---- float box tests: eight corners in two SIMD registers, with error bounds. A clip coordinate c_r = m_r . (p, 1)
   errs by at most 4.01 u S_r (u = 2^-24, S_r = (|m_r0| + |m_r1| + |m_r2|) max |p| + |m_r3|); E_r = 8 u S_r also covers
   the compared differences. A corner with w > 2 E_w has true w >= 3/4 of the computed one, so x/w errs by at most 2/3
   (E_x + |x/w| E_w) / w plus the division; the per-box maxima widen the rectangle and raise the depth. S_r > 1e30: the
   double path. ---- */

/* From the corners, all in front: screen extremes, nearest depth, largest 1 / w, |x / w|, |y / w|, |z / w|. */
typedef struct pvs__boxf {
	float xmin, xmax, ymin, ymax, zmax, rmax, nx, ny, nz;
} pvs__boxf;

/* One box's thresholds: E_x, E_y, E_z, E_w, E_w + E_z, E_x + E_w, E_y + E_w, 2 E_w. */
typedef struct pvs__boxe {
	float e[4], nz, xw, yw, w2;
} pvs__boxe;

/* 0 surely invisible, 1 may reach behind the near plane (visible), 2 *o filled, -1 not finite (caller falls back). */
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

#if defined(PVS__LANES_DIV)
PVS__STATIC int pvs__box_simd(const pvs_raster *r, const pvs_box *b, const pvs__boxe *E, pvs__boxf *o) {
	const pvs__f4 X = pvs__f4_set4(b->min[0], b->max[0], b->min[0], b->max[0]),
				  Y = pvs__f4_set4(b->min[1], b->min[1], b->max[1], b->max[1]);
	const pvs__f4 Z0 = pvs__f4_set1(b->min[2]), Z1 = pvs__f4_set1(b->max[2]), zero = pvs__f4_set1(0.0f);
	pvs__f4 c0[4], c1[4], t0, t1, q0, q1, v0, v1, rw0, rw1;
	int k;
	for (k = 0; k < 4; ++k) { /* mb: mf broadcast */
		const float(*m)[4] = r->mb + 4 * k;
		pvs__f4 a = pvs__f4_add(pvs__f4_mul(pvs__f4_load(m[0]), X), pvs__f4_mul(pvs__f4_load(m[1]), Y));
		c0[k] = pvs__f4_add(pvs__f4_add(a, pvs__f4_mul(pvs__f4_load(m[2]), Z0)), pvs__f4_load(m[3]));
		c1[k] = pvs__f4_add(pvs__f4_add(a, pvs__f4_mul(pvs__f4_load(m[2]), Z1)), pvs__f4_load(m[3]));
	}
	q0 = pvs__f4_sub(c0[3], c0[2]);
	q1 = pvs__f4_sub(c1[3], c1[2]);
#define PVS__ALL(m0, m1) (pvs__m4_bits(pvs__m4_and(m0, m1)) == 15) /* all eight corners */
#define PVS__OUT(a0, a1) PVS__ALL(pvs__f4_gt(a0, t0), pvs__f4_gt(a1, t0))
	t0 = pvs__f4_set1(0.0f - E->nz);
	if (PVS__ALL(pvs__f4_lt(q0, t0), pvs__f4_lt(q1, t0))) return 0;
	t0 = pvs__f4_set1(0.0f - E->e[3]);
	if (PVS__ALL(pvs__f4_lt(c0[3], t0), pvs__f4_lt(c1[3], t0))) return 0;
	t0 = pvs__f4_set1(E->xw);
	if (PVS__OUT(pvs__f4_sub(c0[0], c0[3]), pvs__f4_sub(c1[0], c1[3]))) return 0;
	if (PVS__OUT(pvs__f4_sub(pvs__f4_sub(zero, c0[0]), c0[3]), pvs__f4_sub(pvs__f4_sub(zero, c1[0]), c1[3]))) return 0;
	t0 = pvs__f4_set1(E->yw);
	if (PVS__OUT(pvs__f4_sub(c0[1], c0[3]), pvs__f4_sub(c1[1], c1[3]))) return 0;
	if (PVS__OUT(pvs__f4_sub(pvs__f4_sub(zero, c0[1]), c0[3]), pvs__f4_sub(pvs__f4_sub(zero, c1[1]), c1[3]))) return 0;
#undef PVS__OUT
#undef PVS__ALL
	t0 = pvs__f4_set1(E->nz);
	t1 = pvs__f4_set1(E->w2);
	if (pvs__m4_bits(pvs__m4_or(pvs__m4_or(pvs__f4_lt(q0, t0), pvs__f4_le(c0[3], t1)),
								pvs__m4_or(pvs__f4_lt(q1, t0), pvs__f4_le(c1[3], t1)))))
		return 1;
	rw0 = pvs__f4_div(pvs__f4_set1(1.0f), c0[3]);
	rw1 = pvs__f4_div(pvs__f4_set1(1.0f), c1[3]);
	o->rmax = pvs__f4_hmax2(rw1, rw0);
#define PVS__AXIS(k, half, n, lo, hi) /* x / w (y / w): its largest |.|, then in pixels */ \
	do { \
		v0 = pvs__f4_mul(c0[k], rw0); \
		v1 = pvs__f4_mul(c1[k], rw1); \
		o->n = pvs__f4_hmax2(pvs__f4_abs(v1), pvs__f4_abs(v0)); \
		t0 = pvs__f4_set1(half); \
		v0 = pvs__f4_add(pvs__f4_mul(v0, t0), t0); \
		v1 = pvs__f4_add(pvs__f4_mul(v1, t0), t0); \
		o->lo = pvs__f4_hmin2(v1, v0); \
		o->hi = pvs__f4_hmax2(v1, v0); \
	} while (0)
	PVS__AXIS(0, r->hwf, nx, xmin, xmax);
	PVS__AXIS(1, r->hhf, ny, ymin, ymax);
#undef PVS__AXIS
	v0 = pvs__f4_mul(c0[2], rw0);
	v1 = pvs__f4_mul(c1[2], rw1);
	o->zmax = pvs__f4_hmax2(v1, v0);
	o->nz = pvs__f4_hmax2(pvs__f4_abs(v1), pvs__f4_abs(v0));
	return 2;
}
#endif

/* Double to a float >= it, no libm: margins (v >= 0); any finite v (rounded down: up one step; |f| 2^-23 plus the least
   subnormal covers the gap). */
PVS__STATIC float pvs__f_up_pos(double v) { return (float)(v * (1.0 + 4.76837158203125e-07) + 1e-37); }
PVS__STATIC float pvs__f_up_fast(double v) {
	float f = (float)v;
	if ((double)f < v) f = (float)((double)f + pvs__dabs((double)f) * 1.1920928955078125e-07 + 1.5e-45);
	return f;
}

/* Float box test; -1 when the box needs the double path. */
PVS__STATIC int pvs__raster_box_f(const pvs_raster *r, const pvs_box *b, int32_t rect[4], float *dnear) {
	pvs__boxe E;
	pvs__boxf o = {0, 0, 0, 0, 0, 0, 0, 0, 0};
	double pm = 0.0, e[4], ex, ey, ez, hw = 0.5 * (double)r->width, hh = 0.5 * (double)r->height;
	int k, res, nan = 0;
	float pf = 0.0f;
#if defined(PVS__SSE2) /* largest |coordinate| (exact; min and max are six floats in a row) */
	{
		__m128 a = _mm_loadu_ps(b->min), c = _mm_loadu_ps(b->min + 2);
		nan = _mm_movemask_ps(_mm_or_ps(_mm_cmpunord_ps(a, a), _mm_cmpunord_ps(c, c)));
		pf = pvs__f4_hmax2(pvs__f4_abs(a), pvs__f4_abs(c));
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
#if defined(PVS__LANES_DIV)
	if (!(r->flags & PVS_RASTER_SCALAR)) res = pvs__box_simd(r, b, &E, &o);
	else
#endif
		res = pvs__box_scalar(r, b, &E, &o);
	if (res != 2) return res;
	if (!(o.rmax < 1e30f && o.nx < 1e30f && o.ny < 1e30f && o.nz < 1e30f && o.xmin > -1e30f && o.xmax < 1e30f &&
		  o.ymin > -1e30f && o.ymax < 1e30f))
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

/* Projects a box: 0 invisible, 1 maybe visible, no depth test (behind the near plane), 2 *rect (clamped pixels) and
   *dnear (nearest depth) set. */
PVS__STATIC int pvs__raster_box(const pvs_raster *r, const pvs_box *b, int32_t rect[4], float *dnear) {
	double xmin = DBL_MAX, xmax = -DBL_MAX, ymin = DBL_MAX, ymax = -DBL_MAX, dmax = -DBL_MAX, mag = 0.0, dx, perr = 0.0,
		   zerr = 0.0;
	double hw = 0.5 * (double)r->width, hh = 0.5 * (double)r->height;
	int k, behind_near = 0, behind_w = 0, maybe_behind = 0;
	pvs__cv v[8];
	if (r->tiled) { /* float at the tiles' speed; per-pixel keeps the double test */
		k = pvs__raster_box_f(r, b, rect, dnear);
		if (k >= 0) return k;
	}
	{
		/* corners as the min corner plus transformed edges (the margins cover the rounding) */
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
			/* surely behind / maybe behind */
			if (v[k].c[3] - v[k].c[2] < -2.0 * v[k].e) ++behind_near;
			if (v[k].c[3] < -v[k].e) ++behind_w;
			if (v[k].c[3] - v[k].c[2] < 2.0 * v[k].e || v[k].c[3] <= v[k].e) ++maybe_behind;
		}
	}
	if (behind_near == 8 || behind_w == 8) return 0;
	{
		/* a box wholly outside a side plane (-w <= x, y <= w) is off screen, whatever its w */
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
		double x, y, z;
		pvs__raster_project(v + k, hw, hh, &x, &y, &z, &perr, &zerr);
		xmin = pvs__dmin(xmin, x); xmax = pvs__dmax(xmax, x);
		ymin = pvs__dmin(ymin, y); ymax = pvs__dmax(ymax, y);
		dmax = pvs__dmax(dmax, z);
		mag = pvs__dmax(mag, pvs__dabs(x) + pvs__dabs(y) + pvs__dabs(z));
	}
	dx = PVS__RASTER_ERR_D * (mag + 1.0) + perr;
	if (!(xmax + dx >= 0.0) || !(ymax + dx >= 0.0) || !(xmin - dx <= (double)r->width) ||
		!(ymin - dx <= (double)r->height))
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

/* The context's buffers (pvs__buf) of the `groups` (bits): 1 pixels, 2 tiles, 4 occluder selection, 8 meshes, 16 scene
   sweeps, 32 cull map, 64 its items; sized by the fields the creation sets before each group. */
#define PVS__RASTER_BUFS 28
PVS__STATIC int pvs__raster_bufs(pvs_raster *r, pvs__buf *b, unsigned groups) {
	int k = 0;
	size_t cells = (size_t)r->cm_w * r->cm_h, mc = r->mesh_cap, band = (size_t)PVS__TH * r->width;
	if (groups & 1u) {
		PVS__BUF(b, k, r->depth, (size_t)r->width * r->height, sizeof(float));
		PVS__BUF(b, k, r->pyramid, r->pyramid_floats, sizeof(float));
		PVS__BUF(b, k, r->tile_min, r->tiles, sizeof(float));
	}
	if (groups & 2u) {
		PVS__BUF(b, k, r->tile, (size_t)r->tw * r->th, sizeof(pvs__tile));
		PVS__BUF(b, k, r->tpyramid, r->tpyramid_floats, sizeof(float));
		PVS__BUF(b, k, r->bmin, (size_t)r->bw * r->bh, sizeof(float));
		PVS__BUF(b, k, r->bdirty, (size_t)r->bw * r->bh, 1);
	}
	if (groups & 4u) PVS__BUF(b, k, r->occ, r->max_occluders, sizeof(pvs__occsel));
	if (groups & 8u) {
		PVS__BUF(b, k, r->mt, mc, sizeof(pvs__mtri));
		PVS__BUF(b, k, r->mcid, 3 * mc, sizeof(uint32_t));
		PVS__BUF(b, k, r->mpart, 3 * mc, sizeof(uint32_t));
		PVS__BUF(b, k, r->mvst, 3 * mc, 1);
		PVS__BUF(b, k, r->mgrp, mc, 1);
		PVS__BUF(b, k, r->mtab, r->mesh_hash, sizeof(uint32_t));
		PVS__BUF(b, k, r->morder, mc, sizeof(uint32_t));
		PVS__BUF(b, k, r->mact, mc, sizeof(uint32_t));
		PVS__BUF(b, k, r->mband, (size_t)r->th + 1, sizeof(uint32_t));
		PVS__BUF(b, k, r->mzmin, band, sizeof(float));
		PVS__BUF(b, k, r->mflag, band, 1);
		PVS__BUF(b, k, r->mdirty, (size_t)PVS__TH * r->tw, 1);
	}
	if (groups & 16u) {
		PVS__BUF(b, k, r->sweep, r->sweep_size, 1);
		PVS__BUF(b, k, r->tri_seen, PVS_BITSET_WORDS(r->max_triangles), sizeof(pvs_word));
		PVS__BUF(b, k, r->obj_done, PVS_BITSET_WORDS(r->max_objects), sizeof(pvs_word));
	}
	if (groups & 32u) {
		PVS__BUF(b, k, r->cm, cells, sizeof(float));
		PVS__BUF(b, k, r->cm_tile_min, r->cm_tiles, sizeof(float));
		PVS__BUF(b, k, r->cm_bound, cells, sizeof(float));
		PVS__BUF(b, k, r->cm_start, cells + 1, sizeof(uint32_t));
	}
	if (groups & 64u) PVS__BUF(b, k, r->cm_items, r->cm_item_count, sizeof(uint32_t));
	return k;
}
PVS__STATIC int pvs__raster_alloc(pvs_raster *r, unsigned groups) {
	pvs__buf b[PVS__RASTER_BUFS];
	return pvs__bufs_alloc(&r->allocator, b, pvs__raster_bufs(r, b, groups));
}

PVS_API void pvs_raster_destroy(pvs_raster *r) {
	pvs_allocator a;
	pvs__buf b[PVS__RASTER_BUFS];
	if (!r) return;
	a = r->allocator;
	pvs__bufs_free(&a, b, pvs__raster_bufs(r, b, 127u));
	pvs__free(&a, r, sizeof(*r), 16);
}

/* Cull map cell range of a box (clamped); 0 when the box is not wholly inside the region. */
PVS__STATIC int pvs__cm_range(const pvs_raster *r, const pvs_box *b, int up, int32_t *i0, int32_t *j0, int32_t *i1,
							  int32_t *j1) {
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
	return b->min[u] >= r->region[0] && b->max[u] <= r->region[2] && b->min[v] >= r->region[1] &&
		b->max[v] <= r->region[3];
}

/* Per-pixel map, 8 x 8 tile minima, pyramid (Durand 2000 §2.4: levels halve to 1 x 1; min and max planes). 0 when out
   of memory; pvs_raster_destroy frees the rest (also below). */
PVS__STATIC int pvs__raster_init_pixels(pvs_raster *r) {
	uint32_t l, w, h;
	size_t floats = 0;
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
	r->pyramid_floats = floats;
	r->tiles =
		(size_t)((r->width + PVS__TILE - 1) >> PVS__TILE_SHIFT) * ((r->height + PVS__TILE - 1) >> PVS__TILE_SHIFT);
	if (!pvs__raster_alloc(r, 1u)) return 0;
	floats = 0;
	for (l = 1; l <= r->levels; ++l) {
		r->lmin[l] = r->pyramid + floats;
		floats += (size_t)r->lw[l] * r->lh[l];
		r->lmax[l] = r->pyramid + floats;
		floats += (size_t)r->lw[l] * r->lh[l];
	}
	r->lmin[0] = r->lmax[0] = r->depth;
	return 1;
}

/* Tiles, their 8 x 8 blocks, the tile pyramid (levels halve x, y or both, texels about square in pixels). */
PVS__STATIC int pvs__raster_init_tiles(pvs_raster *r) {
	uint32_t l, w, h;
	size_t floats;
	r->tiled =
		(r->flags & PVS_RASTER_TILED) || (!(r->flags & PVS_RASTER_PER_PIXEL) && (size_t)r->width * r->height > 65536);
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
	r->tpyramid_floats = floats;
	r->bw = (r->tw + (1u << PVS__BLOCK_SHIFT) - 1) >> PVS__BLOCK_SHIFT;
	r->bh = (r->th + (1u << PVS__BLOCK_SHIFT) - 1) >> PVS__BLOCK_SHIFT;
	if (!pvs__raster_alloc(r, 2u)) return 0;
	floats = 0;
	for (l = 0; l <= r->tlevels; ++l) {
		r->tlmin[l] = r->tpyramid + floats;
		floats += (size_t)r->tlw[l] * r->tlh[l];
		r->tlmax[l] = r->tpyramid + floats;
		floats += (size_t)r->tlw[l] * r->tlh[l];
	}
	return 1;
}

/* Mesh scratch for pieces of `max_triangles` (0: default; at most 2^24); hash load <= 1/2. */
PVS__STATIC int pvs__raster_init_mesh(pvs_raster *r, uint32_t max_triangles) {
	size_t i;
	r->mesh_cap = max_triangles ? (max_triangles < (1u << 24) ? max_triangles : 1u << 24) : PVS__MESH_DEFAULT;
	for (r->mesh_hash = 16; r->mesh_hash < 6 * r->mesh_cap; r->mesh_hash <<= 1) {}
	if (!pvs__raster_alloc(r, 8u)) return 0;
	memset(r->mdirty, 0, (size_t)PVS__TH * r->tw);
	for (i = 0; i < (size_t)PVS__TH * r->width; ++i) {
		r->mzmin[i] = FLT_MAX;
		r->mflag[i] = 0;
	}
	return 1;
}

/* Cull map object grid: w x h ground cells (Wonka 1999 §4.1), highest top per cell (§4.3). */
PVS__STATIC pvs_result pvs__raster_init_cull_map(pvs_raster *r, const pvs_scene *s, uint32_t w, uint32_t h,
												 pvs_error *err) {
	int u, v, up = (int)s->up_axis;
	size_t cells = (size_t)w * h, total = 0, i;
	uint32_t o, l;
	pvs__ground_axes(s->up_axis, &u, &v);
	r->cm_w = w;
	r->cm_h = h;
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
	r->cm_tiles =
		(size_t)((r->cm_w + PVS__TILE - 1) >> PVS__TILE_SHIFT) * ((r->cm_h + PVS__TILE - 1) >> PVS__TILE_SHIFT);
	if (!pvs__raster_alloc(r, 32u)) goto oom;
	for (i = 0; i <= cells; ++i) r->cm_start[i] = 0;
	for (i = 0; i < cells; ++i) { r->cm[i] = PVS_DEPTH_EMPTY; r->cm_bound[i] = PVS_DEPTH_EMPTY; }
	for (o = 0; o < s->object_count; ++o) {
		const pvs_box *b = s->object_boxes + o;
		int32_t i0, j0, i1, j1, ii, jj;
		if (b->min[0] > b->max[0]) continue;
		pvs__cm_range(r, b, up, &i0, &j0, &i1, &j1);
		total += (size_t)(i1 - i0 + 1) * (size_t)(j1 - j0 + 1);
		if (total > 0xffffffffu)
			return pvs__fail(err, PVS_ERROR_COUNT_OVERFLOW, -1, 0,
							 "the cull map grid holds more than 2^32 object entries");
		for (jj = j0; jj <= j1; ++jj)
			for (ii = i0; ii <= i1; ++ii) {
				size_t c = (size_t)jj * r->cm_w + (size_t)ii;
				r->cm_start[c + 1]++;
				if (b->max[up] > r->cm_bound[c]) r->cm_bound[c] = b->max[up];
			}
	}
	for (i = 0; i < cells; ++i) r->cm_start[i + 1] += r->cm_start[i];
	r->cm_item_count = (uint32_t)total;
	if (!pvs__raster_alloc(r, 64u)) goto oom;
	for (o = 0; o < s->object_count; ++o) { /* fill with cm_start[c] as cursor, then shift back */
		const pvs_box *b = s->object_boxes + o;
		int32_t i0, j0, i1, j1, ii, jj;
		if (b->min[0] > b->max[0]) continue;
		pvs__cm_range(r, b, up, &i0, &j0, &i1, &j1);
		for (jj = j0; jj <= j1; ++jj)
			for (ii = i0; ii <= i1; ++ii) r->cm_items[r->cm_start[(size_t)jj * r->cm_w + (size_t)ii]++] = o;
	}
	for (i = cells; i > 0; --i) r->cm_start[i] = r->cm_start[i - 1];
	r->cm_start[0] = 0;
	return PVS_OK;
oom:
	return pvs__fail(err, PVS_ERROR_OUT_OF_MEMORY, -1, 0, "raster buffers");
}

PVS_API pvs_result pvs_raster_create(const pvs_raster_desc *desc, pvs_raster **out, pvs_error *err) {
	pvs_raster *r;
	pvs_allocator a;
	pvs_result res;
	uint32_t l;
	if (out) *out = NULL;
	if (!desc || !out) return pvs__fail(err, PVS_ERROR_INVALID_ARGUMENT, -1, 0, "desc and out_raster must not be NULL");
	if (desc->width < 1 || desc->height < 1 || desc->width > 16384 || desc->height > 16384)
		return pvs__fail(err, PVS_ERROR_INVALID_ARGUMENT, -1, 0, "depth map size %ux%u is not in 1..16384", desc->width,
						 desc->height);
	if ((desc->cull_map_width == 0) != (desc->cull_map_height == 0) || desc->cull_map_width > 4096 ||
		desc->cull_map_height > 4096)
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
	if (!pvs__raster_init_pixels(r) || !pvs__raster_init_tiles(r)) goto oom;
	pvs_raster_clear(r);
	r->max_occluders = desc->max_occluders ? desc->max_occluders : 1024;
	if (!pvs__raster_alloc(r, 4u) || !pvs__raster_init_mesh(r, desc->max_mesh_triangles)) goto oom;
	if (desc->scene) {
		const pvs_scene *s = desc->scene;
		size_t s1 = pvs_kdtree_sweep_scratch_size(s->object_tree), s2 = pvs_kdtree_sweep_scratch_size(s->triangle_tree);
		r->scene = s;
		r->max_objects = s->object_count;
		r->max_triangles = s->triangle_count;
		r->sweep_size = s1 > s2 ? s1 : s2;
		if (!pvs__raster_alloc(r, 16u)) goto oom;
	}
	if (desc->cull_map_width) {
		res = pvs__raster_init_cull_map(r, desc->scene, desc->cull_map_width, desc->cull_map_height, err);
		if (res != PVS_OK) {
			pvs_raster_destroy(r);
			return res;
		}
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

/* The k best triangles (pvs__topk_offer: the root is the weakest kept). */
PVS__STATIC int pvs__occsel_before(const void *a, const void *b) {
	return ((const pvs__occsel *)a)->score > ((const pvs__occsel *)b)->score;
}
PVS__STATIC void pvs__occ_push(pvs__occsel *h, uint32_t *n, uint32_t k, float score, uint32_t tri) {
	pvs__occsel e;
	e.score = score;
	e.triangle = tri;
	pvs__topk_offer(h, n, k, sizeof(e), &e, pvs__occsel_before);
}

/* Area-angle measure A |N . V| / |D|^2 (Bittner 2002 §4.5), V the unit direction to centre D, two-sided. */
PVS__STATIC pvs_visit pvs__select_visit(void *user, const pvs_box *node_box, float distance, const uint32_t *items,
										uint32_t count) {
	pvs__selctx *c = (pvs__selctx *)user;
	uint32_t i;
	if (distance > c->max_dist) return PVS_VISIT_STOP;
	/* heap full and nothing unseen can enter: an unseen triangle's centre lies beyond `distance` (every leaf its box
	   overlaps lists it), so it scores at most area / distance^2 (rounded up) */
	if (c->n == c->k && distance > 0.0f &&
		c->s->max_triangle_area * 1.0001 / ((double)distance * distance * 0.9999) < (double)c->r->occ[0].score)
		return PVS_VISIT_STOP;
	/* outside the view or behind drawn occluders, a node hides nothing seen */
	if (!pvs_raster_test_box(c->r, node_box)) return PVS_VISIT_SKIP;
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
		for (k = 0; k < 3; ++k)
			fr[k] = c->fwd[0] * ((double)p[k][0] - c->eye[0]) + c->fwd[1] * ((double)p[k][1] - c->eye[1]) +
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

PVS__STATIC pvs_visit pvs__cull_visit(void *user, const pvs_box *node_box, float distance, const uint32_t *items,
									  uint32_t count) {
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
PVS__STATIC pvs_result pvs__cull_begin(pvs_raster *r, const pvs_scene *s, const pvs_camera *cam, pvs_word *visible,
									   pvs_error *err) {
	float m[16];
	pvs_result res;
	if (!r || !s || !cam || !visible)
		return pvs__fail(err, PVS_ERROR_INVALID_ARGUMENT, -1, 0, "raster, scene, camera and visible must not be NULL");
	if (s->object_count > r->max_objects || s->triangle_count > r->max_triangles ||
		pvs_kdtree_sweep_scratch_size(s->object_tree) > r->sweep_size ||
		pvs_kdtree_sweep_scratch_size(s->triangle_tree) > r->sweep_size)
		return pvs__fail(err, PVS_ERROR_BUFFER_TOO_SMALL, -1, 0,
						 "the context was created for a smaller scene (or none)");
	res = pvs_camera_matrix(cam, (float)r->width / (float)r->height, m);
	if (res != PVS_OK) return pvs__fail(err, res, -1, 0, "unusable camera");
	pvs_raster_set_matrix(r, m);
	memset(visible, 0, PVS_BITSET_WORDS(s->object_count) * sizeof(pvs_word));
	memset(r->obj_done, 0, PVS_BITSET_WORDS(s->object_count) * sizeof(pvs_word));
	return PVS_OK;
}

/* Draws up to p->scene_occluders triangles within p->occluder_distance, best first by Bittner 2002 §4.5's measure;
   meshes with PVS_CULL_SCENE_MESH. Returns the count. */
PVS__STATIC uint32_t pvs__cull_scene_occluders(pvs_raster *r, const pvs_scene *s, const pvs_camera *cam,
											   const pvs_cull_params *p) {
	pvs__selctx sc;
	pvs_box src;
	double len;
	int k;
	sc.r = r;
	sc.s = s;
	sc.k = p->scene_occluders < r->max_occluders ? p->scene_occluders : r->max_occluders;
	sc.n = 0;
	sc.max_dist = p->occluder_distance > 0.0f ? p->occluder_distance : 100.0f;
	sc.near_d = cam->near_plane;
	for (k = 0; k < 3; ++k) { sc.eye[k] = cam->eye[k]; sc.fwd[k] = cam->forward[k]; }
	len = sqrt(sc.fwd[0] * sc.fwd[0] + sc.fwd[1] * sc.fwd[1] + sc.fwd[2] * sc.fwd[2]);
	for (k = 0; k < 3; ++k) sc.fwd[k] /= len;
	if (cam->fov_y == 0.0f) sc.near_d = -DBL_MAX; /* orthographic: the matrix does the near test */
	memset(r->tri_seen, 0, PVS_BITSET_WORDS(s->triangle_count) * sizeof(pvs_word));
	for (k = 0; k < 3; ++k) src.min[k] = src.max[k] = cam->eye[k];
	pvs_kdtree_sweep(s->triangle_tree, &src, r->sweep, r->sweep_size, pvs__select_visit, &sc);
	if (p->occluder_flags & PVS_CULL_SCENE_MESH) /* welded: walls fuse (Durand 2000 §3.3) */
		pvs__mesh(r, s->positions, s->vertex_count, s->indices, r->occ, sc.n);
	else
		pvs__raster_tris(r, s->positions, s->vertex_count, s->indices, r->occ, sc.n, 1);
	return sc.n;
}

/* Wall j of extrusion o (footprint edge j to j + 1, base to top) as the quad a0 b0 b1 a1 (u, v ground axes). */
PVS__STATIC void pvs__wall_quad(const pvs_occluder_desc *o, uint32_t j, int u, int v, int up, float q[4][3]) {
	const float *a = o->footprint + 2 * j, *b = o->footprint + 2 * ((j + 1) % o->footprint_count);
	q[0][u] = a[0]; q[0][v] = a[1]; q[0][up] = o->base;
	q[1][u] = b[0]; q[1][v] = b[1]; q[1][up] = o->base;
	q[2][u] = b[0]; q[2][v] = b[1]; q[2][up] = o->top;
	q[3][u] = a[0]; q[3][v] = a[1]; q[3][up] = o->top;
}

/* Extrusion walls as occluders: meshes of <= 32 walls sharing vertical edges, unless `separate`. Returns triangles. */
PVS__STATIC uint32_t pvs__cull_extrusion(pvs_raster *r, const pvs_occluder_desc *o, int u, int v, int up,
										 int separate) {
	uint32_t j, drawn = 0;
	if (!separate) {
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
			drawn += 2 * nw;
		}
		return drawn;
	}
	for (j = 0; j < o->footprint_count; ++j) {
		float q[4][3];
		pvs__wall_quad(o, j, u, v, up, q);
		pvs__raster_tri(r, q[0], q[1], q[2], 1);
		pvs__raster_tri(r, q[0], q[2], q[3], 1);
		drawn += 2;
	}
	return drawn;
}

/* Occluder volumes within p->occluder_distance (meshes unless PVS_CULL_SEPARATE_TRIANGLES); returns triangles drawn. */
PVS__STATIC uint32_t pvs__cull_volumes(pvs_raster *r, const pvs_scene *s, const pvs_camera *cam,
									   const pvs_cull_params *p) {
	static const uint32_t f[12][3] = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4},
									 {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
	float dist = p->occluder_distance > 0.0f ? p->occluder_distance : 100.0f;
	int u, v, k, up = (int)s->up_axis, separate = (p->occluder_flags & PVS_CULL_SEPARATE_TRIANGLES) != 0;
	uint32_t i, j, drawn = 0;
	pvs_box src;
	pvs__ground_axes(s->up_axis, &u, &v);
	for (k = 0; k < 3; ++k) src.min[k] = src.max[k] = cam->eye[k];
	for (i = 0; i < s->occluder_count; ++i) {
		const pvs_occluder_desc *o = s->occluders + i;
		float q[8][3];
		if (pvs__box_distance2(&src, s->occluder_boxes + i) > dist * dist) continue;
		if (o->kind == PVS_OCCLUDER_BOX) {
			for (j = 0; j < 8; ++j)
				for (k = 0; k < 3; ++k) q[j][k] = (j >> k) & 1u ? o->box.max[k] : o->box.min[k];
			if (separate)
				for (j = 0; j < 12; ++j) pvs__raster_tri(r, q[f[j][0]], q[f[j][1]], q[f[j][2]], 1);
			else
				pvs__mesh(r, &q[0][0], 8, &f[0][0], NULL, 12);
			drawn += 12;
		} else if (o->kind == PVS_OCCLUDER_EXTRUSION) {
			drawn += pvs__cull_extrusion(r, o, u, v, up, separate);
		}
	}
	return drawn;
}

PVS_API pvs_result pvs_raster_cull(pvs_raster *r, const pvs_scene *s, const pvs_camera *cam, const pvs_cull_params *p,
								   pvs_word *visible, pvs_cull_stats *stats, pvs_error *err) {
	pvs__cullctx cc;
	pvs_box src;
	pvs_result res = pvs__cull_begin(r, s, cam, visible, err);
	int k;
	if (res != PVS_OK) return res;
	memset(&cc, 0, sizeof(cc));
	pvs_raster_clear(r);
	if (p && p->occluder_triangle_count && p->occluder_positions) {
		if (p->occluder_flags & PVS_CULL_OCCLUDER_MESH)
			pvs_raster_mesh(r, p->occluder_positions, p->occluder_vertex_count, p->occluder_indices,
							p->occluder_triangle_count);
		else
			pvs_raster_triangles(r, p->occluder_positions, p->occluder_vertex_count, p->occluder_indices,
								 p->occluder_triangle_count, PVS_RASTER_OCCLUDER);
		cc.st.occluder_triangles += p->occluder_triangle_count;
	}
	if (p && p->scene_occluders) cc.st.occluder_triangles += pvs__cull_scene_occluders(r, s, cam, p);
	if (p && p->scene_volumes) cc.st.occluder_triangles += pvs__cull_volumes(r, s, cam, p);
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

/* Ground polygon x, y (scene units, overwritten) at heights z into the cull map, inner coverage (§4.4). */
PVS__STATIC void pvs__cm_draw(pvs_raster *r, double *x, double *y, const double *z, int n, int simd) {
	double su = ((double)r->region[2] - r->region[0]) / r->cm_w, sv = ((double)r->region[3] - r->region[1]) / r->cm_h;
	int k;
	for (k = 0; k < n; ++k) {
		x[k] = (x[k] - r->region[0]) / su;
		y[k] = (y[k] - r->region[1]) / sv;
	}
	pvs__raster_poly(r->cm, r->cm_w, r->cm_h, r->cm_tile_min, x, y, z, n, 1, simd, 0.0, 0.0);
}
/* Farther from eye (ou, ov) than any map point (§4.2). */
PVS__STATIC double pvs__cm_reach(const pvs_raster *r, double ou, double ov) {
	return 2.0 * ((double)r->region[2] - r->region[0] + (double)r->region[3] - r->region[1] +
				  pvs__dabs(ou - r->region[0]) + pvs__dabs(ov - r->region[1]));
}

/* Shadow of facade a-b (height `top`) from eye o = (ou, ov, eh) (§3.1): ground quadrilateral a, b, b + t (b - o), a +
   t (a - o), far edge off the map (§4.2), height the plane through eye and top edge; inner coverage at each cell's
   lowest height (§4.4). */
PVS__STATIC void pvs__cm_shadow(pvs_raster *r, double ou, double ov, double eh, const float *a, const float *b,
								double top, int simd) {
	double da[2], db[2], la, lb, reach, sa, sb, x[4], y[4], z[4];
	da[0] = (double)a[0] - ou; da[1] = (double)a[1] - ov;
	db[0] = (double)b[0] - ou; db[1] = (double)b[1] - ov;
	la = sqrt(da[0] * da[0] + da[1] * da[1]);
	lb = sqrt(db[0] * db[0] + db[1] * db[1]);
	if (!(la > 0.0) || !(lb > 0.0)) return;
	reach = pvs__cm_reach(r, ou, ov);
	sa = 1.0 + reach / la;
	sb = 1.0 + reach / lb;
	x[0] = a[0]; y[0] = a[1]; z[0] = top;
	x[1] = b[0]; y[1] = b[1]; z[1] = top;
	x[2] = ou + db[0] * sb; y[2] = ov + db[1] * sb; z[2] = eh + (top - eh) * sb;
	x[3] = ou + da[0] * sa; y[3] = ov + da[1] * sa; z[3] = eh + (top - eh) * sa;
	pvs__cm_draw(r, x, y, z, 4, simd);
}

/* Plane through the eye and horizontal edge a-b at height `top`, as heights over the ground; 0 when vertical. */
PVS__STATIC int pvs__cm_plane(double ou, double ov, double eh, const double *a, const double *b, double top,
							  double pl[3]) {
	double a0 = a[0] - ou, a1 = a[1] - ov, b0 = b[0] - ou, b1 = b[1] - ov, dh = top - eh;
	/* n = (a - o) x (b - o), both dh above the eye */
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

/* Seam at v between casting facades p-v, v-q: the sampling correction shrinks both shadows, uncovering cells along the
   shadow ray through v (Wonka 1999 §5). The wedge between the rays through a' on p-v and b' on v-q (about two cells
   from v), beyond a'-v-b', lies in the union, at height A on A's side of the ray, B on B's. A - B changes sign across
   the ray: A bounds it from below if A >= B on A's side (a ridge), else the least corner value of concave min(A, B). */
PVS__STATIC void pvs__cm_seam(pvs_raster *r, double ou, double ov, double eh, const float *pf, const float *vf,
							  const float *qf, double top, int simd) {
	double su = ((double)r->region[2] - r->region[0]) / r->cm_w, sv = ((double)r->region[3] - r->region[1]) / r->cm_h;
	double delta = 2.0 * sqrt(su * su + sv * sv), reach, x[5], y[5], z[5], pa[3], pb[3], pt[2], vt[2], qt[2], lp, lq,
		   cross0 = 0.0;
	int k;
	pt[0] = pf[0]; pt[1] = pf[1]; vt[0] = vf[0]; vt[1] = vf[1]; qt[0] = qf[0]; qt[1] = qf[1];
	lp = sqrt((pt[0] - vt[0]) * (pt[0] - vt[0]) + (pt[1] - vt[1]) * (pt[1] - vt[1]));
	lq = sqrt((qt[0] - vt[0]) * (qt[0] - vt[0]) + (qt[1] - vt[1]) * (qt[1] - vt[1]));
	if (!(lp > 0.0) || !(lq > 0.0)) return;
	if (!pvs__cm_plane(ou, ov, eh, pt, vt, top, pa) || !pvs__cm_plane(ou, ov, eh, vt, qt, top, pb)) return;
	reach = pvs__cm_reach(r, ou, ov);
	x[0] = vt[0] + (pt[0] - vt[0]) * pvs__dmin(1.0, delta / lp);
	y[0] = vt[1] + (pt[1] - vt[1]) * pvs__dmin(1.0, delta / lp);
	x[1] = vt[0]; y[1] = vt[1];
	x[2] = vt[0] + (qt[0] - vt[0]) * pvs__dmin(1.0, delta / lq);
	y[2] = vt[1] + (qt[1] - vt[1]) * pvs__dmin(1.0, delta / lq);
	for (k = 0; k < 2; ++k) { /* far ends of the rays through b' and a' */
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
		for (k = 0; k < 5; ++k)
			c = pvs__dmin(c, pvs__dmin(pvs__cm_height(pa, ou, ov, x[k], y[k]), pvs__cm_height(pb, ou, ov, x[k], y[k])));
		for (k = 0; k < 5; ++k) z[k] = c;
	}
	pvs__cm_draw(r, x, y, z, 5, simd);
}

/* 1 if facade a-b casts: front-facing for closed chains (§4.2), not nearer than min_dist. */
PVS__STATIC int pvs__cm_casts(const double eye[3], const float *a, const float *b, int closed, double area2,
							  double min_dist) {
	if (closed) {
		/* outward: right of a->b for a counter-clockwise footprint */
		double nx = (double)b[1] - a[1], ny = -((double)b[0] - a[0]);
		if (area2 < 0) { nx = -nx; ny = -ny; }
		if (!((eye[0] - a[0]) * nx + (eye[1] - a[1]) * ny > 0.0)) return 0; /* back-facing */
	}
	if (min_dist > 0.0) { /* nearer than the near plane: the renderer clips it away */
		double ex = eye[0] - a[0], ey = eye[1] - a[1], sx = (double)b[0] - a[0], sy = (double)b[1] - a[1];
		double ss = sx * sx + sy * sy, t = ss > 0.0 ? (ex * sx + ey * sy) / ss : 0.0, qx, qy;
		t = t < 0.0 ? 0.0 : t > 1.0 ? 1.0 : t;
		qx = ex - t * sx;
		qy = ey - t * sy;
		if (qx * qx + qy * qy < min_dist * min_dist) return 0;
	}
	return 1;
}

/* One chain: each casting facade's shadow and the seams between consecutive ones. */
PVS__STATIC void pvs__cm_chain(pvs_raster *r, const double eye[3], const float *pts, uint32_t n, int closed, float base,
							   float top, int simd, double min_dist) {
	double area2 = 0.0, limit = pvs__dmin(eye[2], r->ground);
	uint32_t i, segs;
	int first_casts = 0, prev_casts = 0;
	if (!pts || n < 2 || !pvs__finite(base) || !pvs__finite(top) || !(base < top)) return;
	if ((double)base > limit) return; /* the facade does not reach down to all it would hide */
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
	if (closed && prev_casts && first_casts) /* the seam closing the loop */
		pvs__cm_seam(r, eye[0], eye[1], eye[2], pts + 2 * (n - 1), pts, pts + 2, top, simd);
}

/* Builds the cull map without facades nearer than min_dist to the eye (ground plane). */
PVS__STATIC pvs_result pvs__cull_map_build(pvs_raster *r, const float eye[3], const pvs_facade_chain *chains,
										   uint32_t chain_count, uint32_t flags, double min_dist) {
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
		pvs__cm_chain(r, e, chains[c].points, chains[c].point_count, chains[c].closed != 0, chains[c].base,
					  chains[c].top, simd, min_dist);
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

PVS_API pvs_result pvs_cull_map_build(pvs_raster *r, const float eye[3], const pvs_facade_chain *chains,
									  uint32_t chain_count, uint32_t flags) {
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

PVS_API pvs_result pvs_raster_cull_map(pvs_raster *r, const pvs_scene *s, const pvs_camera *cam,
									   const pvs_cull_params *p, pvs_word *visible, pvs_cull_stats *stats,
									   pvs_error *err) {
	pvs_cull_stats st;
	pvs_result res;
	size_t c, cells;
	int up;
	if (r && s && r->scene != s)
		return pvs__fail(err, PVS_ERROR_INVALID_ARGUMENT, -1, 0, "the scene is not the context's scene");
	if (r && !r->cm) return pvs__fail(err, PVS_ERROR_INVALID_ARGUMENT, -1, 0, "the context has no cull map");
	res = pvs__cull_begin(r, s, cam, visible, err);
	if (res != PVS_OK) return res;
	if (p && p->facade_count && !p->facades)
		return pvs__fail(err, PVS_ERROR_INVALID_ARGUMENT, -1, 0, "facades must not be NULL");
	memset(&st, 0, sizeof(st));
	if (cam->fov_y > 0.0f) {
		/* facades nearer than the near plane (at the frustum's widest angle) are clipped: they hide nothing */
		double ty = tan(0.5 * (double)cam->fov_y), tx = ty * (double)r->width / (double)r->height;
		pvs__cull_map_build(r, cam->eye, p ? p->facades : NULL, p ? p->facade_count : 0, p ? p->cull_map_flags : 0,
							(double)cam->near_plane * sqrt(1.0 + tx * tx + ty * ty) * (1.0 + 1e-6));
	} else { /* shadows are cast from a point: orthographic gets the frustum test only */
		for (c = 0; c < (size_t)r->cm_w * r->cm_h; ++c) r->cm[c] = PVS_DEPTH_EMPTY;
	}
	pvs_raster_clear(r); /* the frustum test sees an empty depth map */
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
			if (s->object_boxes[o].max[up] < h) continue; /* hidden here; may show in another cell */
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
/* One BSP kernel (§3.3, §6.8) over oriented 2D lines: inner nodes are planes through the origin of R^3, the images
   p* of primal points p (§6.4: l* = (u,1) x (v,1) has l*.(p,1) = orient(u, v, p), > 0 when p is left of the line);
   leaves are out (unblocked) or in (blocked by the payload: the nearest occluder in 2D, those that may be seen over
   in 2.5D). Line sets are convex polygons of unit vectors (vertices: extremal lines); each edge keeps the point
   whose plane carries it and a mark when that plane is on the path (§4.10.1), so an out-leaf becomes the e-OT of
   the unmarked edges (§3.3.3).

   Conservative rounding: regions are bounded by exact planes through stored points, so an in-leaf never claims
   lines outside its blocker; insertion's tolerance can only drop blocked slivers; read-only tests split with slack
   (both sides see a little more); ambiguous depth orders count as visible. Geometry is double, relative to the
   cell's centre. Users: pvs_visibility_2d (exact, ch. 6), pvs_visibility_25d (c-LSS, ch. 7), the OTREE bake;
   pvs_otree_cull (ch. 4, at the end) has its own 3D kernel. */

#define PVS__OT_MAXV 16
#define PVS__OT25_WITNESSES 16
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
	double ml, mls;     /* 2.5D: a second one, from the member of least reach; ml DBL_MAX: none */
} pvs__otnode;

typedef struct pvs__otree {
	const pvs_allocator *a;
	pvs__otnode *nodes;
	size_t node_count, node_cap;
	uint32_t *seq;
	size_t seq_count, seq_cap;
	pvs__otpoly *stack;             /* work stack: item i is stack[stack_slot[i]] (PVS__OT_ITEM) */
	uint32_t *stack_slot;           /* a permutation: a clip writes into a free slot, then swaps */
	uint32_t *stack_node;
	uint32_t *stack_pend;           /* read-only tests: the clip owed, (node << 1) | side, or PVS__OT_NONE */
	size_t stack_count, stack_cap;
	int oom;
	const double *seg;              /* occluder segments, 4 local doubles each */
	const double *top;              /* 2.5D: occluder top heights; NULL in 2D */
	const double *reach;            /* 2D: per occluder, its largest distance to a cell point */
	double sa[2], sb[2];            /* the source edge (cell edge or top edge) */
	double eye;                     /* 2.5D: height of the source edge */
	const double *corners;          /* 2.5D: the cell's 4 ground corners (every eye position) */
	double *jd;                     /* 2.5D: per occluder, PVS__OT25_JD doubles (pvs__ot25_prepare) */
	double len_eps;                 /* distances below this are ties */
	uint32_t root_in;               /* 2.5D: the node of the lines leaving through the source edge */
	int full_tests;                 /* 2.5D: PVS__VISIBILITY_25D_FULL_TESTS (no witness lines) */
	int nwit;                       /* 2.5D: witness lines, most recently useful first */
	double wit[PVS__OT25_WITNESSES][3];
} pvs__otree;

PVS__STATIC void pvs__ot_free(pvs__otree *t) {
	pvs__free(t->a, t->nodes, t->node_cap * sizeof(pvs__otnode), 16);
	pvs__free(t->a, t->seq, t->seq_cap * sizeof(uint32_t), 16);
	pvs__free(t->a, t->stack, t->stack_cap * sizeof(pvs__otpoly), 16);
	pvs__free(t->a, t->stack_node, t->stack_cap * sizeof(uint32_t), 16);
	pvs__free(t->a, t->stack_pend, t->stack_cap * sizeof(uint32_t), 16);
	pvs__free(t->a, t->stack_slot, t->stack_cap * sizeof(uint32_t), 16);
	t->nodes = NULL; t->seq = NULL; t->stack = NULL; t->stack_node = NULL; t->stack_pend = NULL; t->stack_slot = NULL;
	t->node_cap = t->seq_cap = t->stack_cap = 0;
}

/* Resets to the whole line set: a single out-leaf (§3.3.2). */
PVS__STATIC int pvs__ot_reset(pvs__otree *t) {
	t->node_count = t->seq_count = t->stack_count = 0;
	if (!pvs__grow(t->a, (void **)&t->nodes, &t->node_cap, 1, sizeof(pvs__otnode))) { t->oom = 1; return 0; }
	memset(t->nodes, 0, sizeof(pvs__otnode));
	t->nodes[0].kind = PVS__OT_OUT;
	t->nodes[0].mvd = DBL_MAX;
	t->nodes[0].mr = DBL_MAX;
	t->nodes[0].ml = DBL_MAX;
	t->nodes[0].parent = PVS__OT_NONE;
	t->node_count = 1;
	t->root_in = PVS__OT_NONE;
	t->nwit = 0;
	return 1;
}

PVS__STATIC uint32_t pvs__ot_new_node(pvs__otree *t) {
	if (!pvs__grow(t->a, (void **)&t->nodes, &t->node_cap, t->node_count + 1, sizeof(pvs__otnode))) {
		t->oom = 1;
		return PVS__OT_NONE;
	}
	memset(t->nodes + t->node_count, 0, sizeof(pvs__otnode));
	return (uint32_t)t->node_count++;
}

PVS__STATIC void pvs__ot_copy(pvs__otpoly *d, const pvs__otpoly *s) {
	int n = s->n, i;
	d->n = n;
	d->xsplit = s->xsplit;
	for (i = 0; i < n; ++i) { /* n is small: a loop beats a library call */
		d->v[i][0] = s->v[i][0]; d->v[i][1] = s->v[i][1]; d->v[i][2] = s->v[i][2];
		d->e[i][0] = s->e[i][0]; d->e[i][1] = s->e[i][1];
		d->mark[i] = s->mark[i];
	}
}

/* Room for `need` work items (all four arrays; new items get new slots). */
PVS__STATIC int pvs__ot_reserve(pvs__otree *t, size_t need) {
	size_t c1 = t->stack_cap, c2 = t->stack_cap, c3 = t->stack_cap, c4 = t->stack_cap, i;
	if (need <= t->stack_cap) return 1;
	if (!pvs__grow(t->a, (void **)&t->stack, &c1, need, sizeof(pvs__otpoly)) ||
		!pvs__grow(t->a, (void **)&t->stack_node, &c2, need, sizeof(uint32_t)) ||
		!pvs__grow(t->a, (void **)&t->stack_pend, &c3, need, sizeof(uint32_t)) ||
		!pvs__grow(t->a, (void **)&t->stack_slot, &c4, need, sizeof(uint32_t))) {
		t->oom = 1;
		return 0;
	}
	for (i = t->stack_cap; i < c4; ++i) t->stack_slot[i] = (uint32_t)i;
	t->stack_cap = c1 < c2 ? (c1 < c3 ? c1 : c3) : (c2 < c3 ? c2 : c3);
	if (c4 < t->stack_cap) t->stack_cap = c4;
	return 1;
}
/* Work item i's polygon. */
#define PVS__OT_ITEM(t, i) ((t)->stack + (t)->stack_slot[i])
/* Items i and j trade polygons (no copy). */
PVS__STATIC void pvs__ot_swap(pvs__otree *t, size_t i, size_t j) {
	uint32_t s = t->stack_slot[i];
	t->stack_slot[i] = t->stack_slot[j];
	t->stack_slot[j] = s;
}

PVS__STATIC int pvs__ot_push(pvs__otree *t, uint32_t node, const pvs__otpoly *poly) {
	if (!pvs__ot_reserve(t, t->stack_count + 1)) return 0;
	pvs__ot_copy(PVS__OT_ITEM(t, t->stack_count), poly);
	t->stack_pend[t->stack_count] = PVS__OT_NONE;
	t->stack_node[t->stack_count++] = node;
	return 1;
}
/* Pops the top item into *q; returns its node. */
PVS__STATIC uint32_t pvs__ot_pop(pvs__otree *t, pvs__otpoly *q) {
	--t->stack_count;
	pvs__ot_copy(q, PVS__OT_ITEM(t, t->stack_count));
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
/* Signed side of point p for line l, scaled so that unit lines give comparable values. */
PVS__STATIC double pvs__ot_side(const double l[3], const double p[2]) {
	return (l[0] * p[0] + l[1] * p[1] + l[2]) / sqrt(p[0] * p[0] + p[1] * p[1] + 1.0);
}

#define PVS__OT_EPS 1e-12

/* out = normalised a + t (b - a), stored last: out may alias a or b. */
PVS__STATIC void pvs__ot_lerp_unit(const double *a, const double *b, double t, double *out) {
	double x0 = a[0] + t * (b[0] - a[0]), x1 = a[1] + t * (b[1] - a[1]), x2 = a[2] + t * (b[2] - a[2]);
	double len = sqrt(x0 * x0 + x1 * x1 + x2 * x2);
	if (len > 0.0) { double f = 1.0 / len; x0 *= f; x1 *= f; x2 *= f; }
	out[0] = x0; out[1] = x1; out[2] = x2;
}

/* The unit normal of the plane sign * p* = sign * (p.x, p.y, 1): n . l = sign * side(l, p). */
PVS__STATIC void pvs__ot_normal(const double p[2], double sign, double n[3]) {
	double f = sign / sqrt(p[0] * p[0] + p[1] * p[1] + 1.0);
	n[0] = p[0] * f;
	n[1] = p[1] * f;
	n[2] = f;
}

/* Keeps the part of `in` where n . l >= -slack (slack 0: the exact half), n the unit normal of p's plane; new edges
   lie in that plane, with mark `mark`. Returns the vertex count (0 empty, -1 too many). */
PVS__STATIC int pvs__ot_clip_n(const pvs__otpoly *in, const double nn[3], const double p[2], double slack, int mark,
							   pvs__otpoly *out) {
	double d[PVS__OT_MAXV + 1];
	unsigned char ins[PVS__OT_MAXV + 1];
	int i, n = in->n, m = 0, any_in = 0;
	for (i = 0; i < n; ++i) {
		d[i] = nn[0] * in->v[i][0] + nn[1] * in->v[i][1] + nn[2] * in->v[i][2] + slack;
		ins[i] = d[i] >= 0.0;
		if (d[i] > PVS__OT_EPS) any_in = 1;
	}
	out->xsplit = in->xsplit;
	if (!any_in) { out->n = 0; return 0; }
	d[n] = d[0]; ins[n] = ins[0];
	for (i = 0; i < n; ++i) {
		int j = i + 1 == n ? 0 : i + 1;
		int in_i = ins[i], in_j = ins[i + 1];
		if (in_i) {
			if (m >= PVS__OT_MAXV) { out->n = 0; return -1; }
			memcpy(out->v[m], in->v[i], sizeof(out->v[m]));
			memcpy(out->e[m], in->e[i], sizeof(out->e[m]));
			out->mark[m] = in->mark[i];
			++m;
		}
		if (in_i != in_j) {
			if (m >= PVS__OT_MAXV) { out->n = 0; return -1; }
			pvs__ot_lerp_unit(in->v[i], in->v[j], d[i] / (d[i] - d[i + 1]), out->v[m]);
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
/* pvs__ot_clip_n for the plane sign * p*. */
PVS__STATIC int pvs__ot_clip(const pvs__otpoly *in, const double p[2], double sign, double slack, int mark,
							 pvs__otpoly *out) {
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

/* 2.5D witness lines: a read-only test reaching an out-leaf keeps a line inside its polygon there (the normalised
   vertex sum); out-leaves only become in-leaves, so a witness later found in an in-leaf is dropped. */
PVS__STATIC void pvs__ot25_witness_add(pvs__otree *t, const pvs__otpoly *q) {
	double w[3] = {0, 0, 0}, len;
	int i;
	for (i = 0; i < q->n; ++i) { w[0] += q->v[i][0]; w[1] += q->v[i][1]; w[2] += q->v[i][2]; }
	len = sqrt(w[0] * w[0] + w[1] * w[1] + w[2] * w[2]);
	if (!(len > 0.0)) return;
	if (t->nwit < PVS__OT25_WITNESSES) ++t->nwit;
	for (i = t->nwit - 1; i > 0; --i) memcpy(t->wit[i], t->wit[i - 1], sizeof(t->wit[i]));
	t->wit[0][0] = w[0] / len; t->wit[0][1] = w[1] / len; t->wit[0][2] = w[2] / len;
}

/* 2.5D: 1 when nd's subtree hides every point no nearer than `near` to the cell and no higher than h
   (pvs__ot25_bound); near < 0 (2D): 0. The macro skips the call where neither bound applies (most nodes);
   it evaluates nd twice. */
#define PVS__OT25_HIDDEN(t, nd, near, h) \
	(((near) > (nd)->mr || (near) > (nd)->ml) && pvs__ot25_hidden_below_at(t, nd, near, h))
PVS__STATIC int pvs__ot25_hidden_below_at(const pvs__otree *t, const pvs__otnode *nd, double near, double h) {
	double x;
	if (!(near >= 0.0)) return 0;
	/* a bound of DBL_MAX fails `near > mr` by itself (near is finite) */
	if (near > nd->mr) {
		x = nd->ms * near;
		if (h < t->eye + x - 1e-9 * (fabs(t->eye) + x + 1.0)) return 1;
	}
	if (near > nd->ml) {
		x = nd->mls * near;
		if (h < t->eye + x - 1e-9 * (fabs(t->eye) + x + 1.0)) return 1;
	}
	return 0;
}

/* Insertion at an inner node (§3.3.3) on the top item, in place: edges on the node's plane are marked (§4.10.1),
   the polygon goes to its child or is split; a child whose subtree hides the occluder (2.5D, near >= 0) gets
   nothing. 2.5D goes on down one-sided nodes here, to a leaf or a hidden subtree. */
PVS__STATIC void pvs__ot_insert_inner(pvs__otree *t, size_t top, double near, double h) {
	pvs__otpoly *q = PVS__OT_ITEM(t, top);
	const pvs__otnode *nd;
	uint32_t c0, c1;
	int i, na, nb, nv = q->n;
	for (;;) {
		double lo = DBL_MAX, hi = -DBL_MAX, n0, n1, n2, p0, p1;
		uint32_t c;
		nd = t->nodes + t->stack_node[top];
		n0 = nd->n[0]; n1 = nd->n[1]; n2 = nd->n[2]; p0 = nd->p[0]; p1 = nd->p[1];
		c0 = nd->child[0]; c1 = nd->child[1];
		for (i = 0; i < nv; ++i) { /* locals: the mark stores may alias everything */
			const double *v = q->v[i];
			double d = n0 * v[0] + n1 * v[1] + n2 * v[2];
			if (d < lo) lo = d;
			if (d > hi) hi = d;
			if (q->e[i][0] == p0 && q->e[i][1] == p1) q->mark[i] = 1;
		}
		if (lo >= -1e-12) c = c1;
		else if (hi <= 1e-12) c = c0;
		else break;
		t->stack_node[top] = c;
		if (near < 0.0 || t->nodes[c].kind != 0 || PVS__OT25_HIDDEN(t, t->nodes + c, near, h)) return;
	}
	{
		int h0 = PVS__OT25_HIDDEN(t, t->nodes + c0, near, h), h1 = PVS__OT25_HIDDEN(t, t->nodes + c1, near, h);
		double nf[3];
		uint32_t s0, s1, s2;
		size_t m = top;
		if (h0 && h1) { t->stack_count = top; return; }
		/* the parts go into the free slots above the top, which then trade places */
		if (!pvs__ot_reserve(t, top + 3)) { t->stack_count = top; return; }
		q = PVS__OT_ITEM(t, top);
		/* the positive part unless c1 hides, the negative one (the normal negated: each distance exactly so) unless c0
		   hides */
		for (i = 0; i < 3; ++i) nf[i] = -nd->n[i];
		na = h1 ? 0 : pvs__ot_clip_n(q, nd->n, nd->p, 0.0, 1, PVS__OT_ITEM(t, top + 1));
		nb = h0 ? 0 : pvs__ot_clip_n(q, nf, nd->p, 0.0, 1, PVS__OT_ITEM(t, top + 2));
		/* items top.. become the positive part (c1), then the negative (c0), as two pushes would leave
		   them; unused slots go above (the slots stay a permutation) */
		s0 = t->stack_slot[top]; s1 = t->stack_slot[top + 1]; s2 = t->stack_slot[top + 2];
		if (na >= 3) { t->stack_slot[m] = s1; t->stack_node[m] = c1; t->stack_pend[m] = PVS__OT_NONE; ++m; }
		if (nb >= 3) { t->stack_slot[m] = s2; t->stack_node[m] = c0; t->stack_pend[m] = PVS__OT_NONE; ++m; }
		t->stack_count = m;
		t->stack_slot[m++] = s0;
		if (na < 3) t->stack_slot[m++] = s1;
		if (nb < 3) t->stack_slot[m++] = s2;
	}
}

/* Read-only test at an inner node (§3.3.4) on the top item, in place: a polygon within 1e-12 of the plane on one
   side (an edge on it) goes to that side, else both sides get their part widened by 1e-12. 1 when the query is
   visible for sure (2.5D: a straddled child is an out-leaf) or out of memory: the caller counts it visible. */
PVS__STATIC int pvs__ot_test_inner(pvs__otree *t, size_t top, double near, double h) {
	pvs__otpoly *q;
	const pvs__otnode *nd;
	double nf[3];
	uint32_t c0, c1, node;
	int i, r, first, nv;
	if (top + 2 > t->stack_cap && !pvs__ot_reserve(t, top + 2)) return 1;
	q = PVS__OT_ITEM(t, top);
	nv = q->n;
	for (;;) { /* 2.5D: down through one-sided nodes here, as in pvs__ot_insert_inner */
		double lo = DBL_MAX, hi = -DBL_MAX, n0, n1, n2;
		uint32_t c;
		node = t->stack_node[top];
		nd = t->nodes + node;
		c0 = nd->child[0];
		c1 = nd->child[1];
		n0 = nd->n[0]; n1 = nd->n[1]; n2 = nd->n[2];
		for (i = 0; i < nv; ++i) {
			const double *v = q->v[i];
			double d = n0 * v[0] + n1 * v[1] + n2 * v[2];
			if (d < lo) lo = d;
			if (d > hi) hi = d;
			if (lo < -1e-12 && hi > 1e-12) break; /* straddles: the rest cannot change the answer */
		}
		if (lo >= -1e-12) c = c1;
		else if (hi <= 1e-12) c = c0;
		else break;
		t->stack_node[top] = c;
		if (near < 0.0 || t->nodes[c].kind != 0 || PVS__OT25_HIDDEN(t, t->nodes + c, near, h)) return 0;
	}
	/* 2.5D (no sliver rule): both parts hold a vertex strictly off the plane, so an out-leaf child answers at
	   once; that part's line is kept as a witness (pvs__ot25_witnessed) */
	if (near >= 0.0 && (t->nodes[c0].kind == PVS__OT_OUT || t->nodes[c1].kind == PVS__OT_OUT)) {
		int out1 = t->nodes[c1].kind == PVS__OT_OUT;
		for (i = 0; i < 3; ++i) nf[i] = out1 ? nd->n[i] : -nd->n[i];
		if (pvs__ot_clip_n(q, nf, nd->p, 0.0, 0, PVS__OT_ITEM(t, top + 1)) >= 3)
			pvs__ot25_witness_add(t, PVS__OT_ITEM(t, top + 1));
		return 1;
	}
	{   /* a child whose subtree hides the query (2.5D bound) gets nothing */
		int h0 = PVS__OT25_HIDDEN(t, t->nodes + c0, near, h), h1 = PVS__OT25_HIDDEN(t, t->nodes + c1, near, h);
		if (h0 && h1) { t->stack_count = top; return 0; }
		if (h0 || h1) {
			for (i = 0; i < 3; ++i) nf[i] = h0 ? nd->n[i] : -nd->n[i];
			r = pvs__ot_clip_n(q, nf, nd->p, 1e-12, 0, PVS__OT_ITEM(t, top + 1));
			if (r == 0) { t->stack_count = top; return 0; }
			if (r > 0) pvs__ot_swap(t, top, top + 1);
			t->stack_node[top] = h0 ? c1 : c0;
			return 0;
		}
	}
	/* the child without a hidden-height bound (likely visible) goes first; the other keeps the polygon
	   unclipped and clips it only if the test gets there (pvs__ot_owed) */
	first = t->nodes[c1].mr == DBL_MAX && t->nodes[c0].mr != DBL_MAX ? 1 : 0;
	for (i = 0; i < 3; ++i) nf[i] = first ? nd->n[i] : -nd->n[i];
	r = pvs__ot_clip_n(q, nf, nd->p, 1e-12, 0, PVS__OT_ITEM(t, top + 1));
	if (r < 0) pvs__ot_copy(PVS__OT_ITEM(t, top + 1), q); /* too many vertices: the whole polygon (conservative) */
	t->stack_node[top] = first ? c0 : c1;
	t->stack_pend[top] = (node << 1) | (uint32_t)(1 - first);
	if (r != 0) {
		t->stack_node[top + 1] = first ? c1 : c0;
		t->stack_pend[top + 1] = PVS__OT_NONE;
		t->stack_count = top + 2;
	}
	return 0;
}

/* Pays the clip owed by item `top` (pvs__ot_test_inner): its part on side `side` of the node's plane, widened by
   1e-12. 0 when nothing is left (the caller pops it). */
PVS__STATIC int pvs__ot_owed(pvs__otree *t, size_t top) {
	uint32_t pend = t->stack_pend[top];
	const pvs__otnode *nd = t->nodes + (pend >> 1);
	pvs__otpoly part;
	double nf[3];
	int i, r;
	t->stack_pend[top] = PVS__OT_NONE;
	for (i = 0; i < 3; ++i) nf[i] = (pend & 1u) ? nd->n[i] : -nd->n[i];
	if (top + 2 <= t->stack_cap) { /* into the free slot above, then trade places */
		r = pvs__ot_clip_n(PVS__OT_ITEM(t, top), nf, nd->p, 1e-12, 0, PVS__OT_ITEM(t, top + 1));
		if (r > 0) pvs__ot_swap(t, top, top + 1);
		return r != 0;
	}
	r = pvs__ot_clip_n(PVS__OT_ITEM(t, top), nf, nd->p, 1e-12, 0, &part);
	if (r == 0) return 0;
	if (r > 0) pvs__ot_copy(PVS__OT_ITEM(t, top), &part);
	return 1;
}

/* The blocker polygon B(S, O) (§6.4.3): lines through S = a b, then O = c d; vertices a->c, a->d, b->d, b->c, each
   edge in the plane of its lines' shared point. Coincident vertices (O's line through an end of S, O touching S)
   merge into the triangle of Fig. 6.5. 0 when degenerate (no line set of positive measure). */
PVS__STATIC int pvs__ot_blocker(const double a[2], const double b[2], const double c[2], const double d[2],
								pvs__otpoly *q) {
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
		double cn[4][3], en[PVS__OT_MAXV][3], cen[3] = {0, 0, 0}, clen;
		cand[0] = a; cand[1] = b; cand[2] = c; cand[3] = d;
		for (k = 0; k < 4; ++k) pvs__ot_normal(cand[k], 1.0, cn[k]);
		for (i = 0; i < n; ++i) {
			const double *v0 = q->v[i], *v1 = q->v[(i + 1) % n];
			int best = -1;
			double best_err = DBL_MAX;
			if (n == 4) { /* no vertex merged: edge i lies in the plane of pt[i] (a, d, b, c = cand 0, 3, 1, 2) */
				static const int pick[4] = {0, 3, 1, 2};
				const double *c0 = cn[pick[i]];
				double e0 = fabs(c0[0] * v0[0] + c0[1] * v0[1] + c0[2] * v0[2]);
				double e1 = fabs(c0[0] * v1[0] + c0[1] * v1[1] + c0[2] * v1[2]);
				if ((e0 > e1 ? e0 : e1) <= 1e-9) {
					q->e[i][0] = cand[pick[i]][0]; q->e[i][1] = cand[pick[i]][1];
					memcpy(en[i], c0, sizeof(en[i]));
					continue;
				}
			}
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
		clen = sqrt(cen[0] * cen[0] + cen[1] * cen[1] + cen[2] * cen[2]);
		for (i = 0; i < n; ++i) {
			double s = (en[i][0] * cen[0] + en[i][1] * cen[1] + en[i][2] * cen[2]) / clen;
			int i1 = i + 1 == n ? 0 : i + 1;
			if (!(fabs(s) > 1e-12)) return 0;
			for (k = 0; k < n; ++k) /* the edge's own ends lie within 1e-9 of its plane (checked above) */
				if (k != i && k != i1 &&
					(s > 0 ? 1.0 : -1.0) * (en[i][0] * q->v[k][0] + en[i][1] * q->v[k][1] + en[i][2] * q->v[k][2]) <
						-1e-9)
					return 0;
		}
	}
	return 1;
}

/* The line through segment s (4 doubles) for pvs__ot_hit_m: m[0..2] = (s0, 1) x (s1, 1), m[3] = |(m0, m1)|. */
PVS__STATIC void pvs__ot_hit_line(const double *s, double m[4]) {
	m[0] = s[1] - s[3];
	m[1] = s[2] - s[0];
	m[2] = s[0] * s[3] - s[1] * s[2];
	m[3] = sqrt(m[0] * m[0] + m[1] * m[1]);
}
/* Parameter along line l (unit direction (l1, -l0)) of its crossing with the line m of a segment
   (pvs__ot_hit_line); 0 when (nearly) parallel or the same line. */
PVS__STATIC int pvs__ot_hit_m(const double l[3], const double m[4], double *t) {
	double x, y, w, dx = l[1], dy = -l[0], dn = m[3];
	x = l[1] * m[2] - l[2] * m[1];
	y = l[2] * m[0] - l[0] * m[2];
	w = l[0] * m[1] - l[1] * m[0];
	if (!(fabs(w) > 1e-12 * dn)) return 0;
	*t = (x * dx + y * dy) / (w * sqrt(dx * dx + dy * dy));
	return 1;
}

/* Parameter on segment s (0 at its first end, 1 at its second) where line l crosses its line; 0 when parallel. */
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

/* Depth order of occluders j, k along q's lines (§6.5.1): counts vertices where k is clearly in front of j, and
   clearly behind. Ties (lines through X or a shared end) count as neither, as do vertex lines missing either
   segment: they lie outside the leaf by a rounding sliver (q clipped with slack). */
PVS__STATIC void pvs__ot_depth(const pvs__otree *t, const pvs__otpoly *q, const double *sj, const double *sk,
							   int *front, int *behind) {
	int i, have_x;
	double x[2], mj[4], mk[4];
	*front = *behind = 0;
	/* after a split at the crossing X the lines through X are ties, whatever rounding says */
	have_x = q->xsplit && pvs__ot_cross(sj, sk, x);
	pvs__ot_hit_line(sj, mj);
	pvs__ot_hit_line(sk, mk);
	for (i = 0; i < q->n; ++i) {
		double tj, tk, uj, uk;
		if (have_x && fabs(pvs__ot_side(q->v[i], x)) <= 1e-9) continue;
		if (!pvs__ot_hit_m(q->v[i], mj, &tj) || !pvs__ot_hit_m(q->v[i], mk, &tk)) continue;
		if (!pvs__ot_param(q->v[i], sj, &uj) || !pvs__ot_param(q->v[i], sk, &uk)) continue;
		if (uj < -1e-7 || uj > 1.0 + 1e-7 || uk < -1e-7 || uk > 1.0 + 1e-7) continue;
		if (tk < tj - t->len_eps) ++*front;
		else if (tk > tj + t->len_eps) ++*behind;
	}
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

/* Turns leaf `node` into the chain of q's unmarked edges (the e-OT, §3.3.3): split by each edge's plane, q's side
   continuing; the sides away from q keep the leaf's kind and payload. Returns the node of q's region (old payload
   still on), PVS__OT_NONE when out of memory. */
PVS__STATIC uint32_t pvs__ot_refine(pvs__otree *t, uint32_t node, const pvs__otpoly *q) {
	double cen[3] = {0, 0, 0};
	int i, k;
	for (i = 0; i < q->n; ++i) for (k = 0; k < 3; ++k) cen[k] += q->v[i][k];
	for (i = 0; i < q->n && node != PVS__OT_NONE; ++i)
		if (!q->mark[i]) node = pvs__ot_split_leaf(t, node, q->e[i], pvs__ot_side(cen, q->e[i]));
	return node;
}

/* Gives leaf `node` the payload seq[old_first .. + old_count) followed by `add`. */
PVS__STATIC int pvs__ot_set_payload(pvs__otree *t, uint32_t node, uint32_t old_first, uint32_t old_count,
									uint32_t add) {
	size_t first = t->seq_count;
	if (!pvs__grow(t->a, (void **)&t->seq, &t->seq_cap, t->seq_count + old_count + 1, sizeof(uint32_t)))
		return t->oom = 1, 0;
	if (old_count) memmove(t->seq + first, t->seq + old_first, old_count * sizeof(uint32_t));
	t->seq[first + old_count] = add;
	t->seq_count = first + old_count + 1;
	t->nodes[node].kind = PVS__OT_IN;
	t->nodes[node].first = (uint32_t)first;
	t->nodes[node].count = old_count + 1;
	return 1;
}

/* ---- 2D from-region (ch. 6): insertion with the four depth cases of §6.5.1 ---- */

/* §6.5.1 case 3: q, split at the crossing X = x (marked so), goes back on the stack at `node` as its two halves. 0
   when out of memory. */
PVS__STATIC int pvs__ot2_xsplit(pvs__otree *t, uint32_t node, pvs__otpoly *q, const double x[2]) {
	pvs__otpoly part;
	int ok = 1;
	q->xsplit = 1;
	if (pvs__ot_clip(q, x, 1.0, 0.0, 0, &part) >= 3) ok &= pvs__ot_push(t, node, &part);
	if (pvs__ot_clip(q, x, -1.0, 0.0, 0, &part) >= 3) ok &= pvs__ot_push(t, node, &part);
	return ok;
}

/* Inserts blocker polygon q of occluder k (§3.3.3 with the 2D in-leaf cases). */
PVS__STATIC void pvs__ot2_insert(pvs__otree *t, const pvs__otpoly *blocker, uint32_t k, double near) {
	size_t base = t->stack_count;
	const double *sk = t->seg + 4 * (size_t)k;
	if (!pvs__ot_push(t, 0, blocker)) return;
	while (t->stack_count > base && !t->oom) {
		pvs__otpoly q;
		uint32_t node = t->stack_node[t->stack_count - 1];
		pvs__otnode *nd = t->nodes + node;
		/* §6.5.5: every line of this subtree meets a stored occluder nearer to any cell point than k is */
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
					(void)pvs__ot2_xsplit(t, node, &q, x);
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

/* Thickness of a line-space polygon: the least over its edges of the largest vertex distance from the edge's plane.
   Insertion leaves slivers about 1e-12 thick where it rounded; line sets thinner than PVS__OT_SLIVER (radians at
   unit distance) are below the method's resolution. */
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

/* The read-only test (§3.3.4), after the 2.5D pieces (pvs__ot25_open). */
PVS__STATIC int pvs__ot_visible(pvs__otree *t, const pvs__otpoly *blocker, uint32_t k, double near, double h,
								const double *e, const double *box);

/* ---- shared driver pieces ---- */

/* Clips segment s to the open half-plane right of a -> b (outside a CCW edge). 0 when nothing is left; *on_line:
   which end (1 first, 2 second) was moved onto the line. */
PVS__STATIC int pvs__ot_clip_segment(const double a[2], const double b[2], const double *s, double out[4],
									 int *on_line) {
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

/* The blockers of source edge a -> b (lines leaving to its right) and clipped segment o: one, or two when o's line
   crosses the edge at x (Fig. 6.5). Returns how many; *degenerate: a non-empty line set was not representable. */
PVS__STATIC int pvs__ot_blockers(const double a[2], const double b[2], const double o[4], int on_line,
								 pvs__otpoly out[2], int *degenerate) {
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
/* The largest squared distance from the n points pts (2 doubles each) to an end of segment s. */
PVS__STATIC double pvs__ot_far2(const double *pts, uint32_t n, const double *s) {
	double far2 = 0.0;
	uint32_t i, m;
	for (i = 0; i < n; ++i)
		for (m = 0; m < 2; ++m) {
			double ex = s[2 * m] - pts[2 * i], ey = s[2 * m + 1] - pts[2 * i + 1];
			if (ex * ex + ey * ey > far2) far2 = ex * ex + ey * ey;
		}
	return far2;
}
/* The CCW corners of rectangle b (umin vmin umax vmax) grown by g > 0 on each side. */
PVS__STATIC void pvs__ot_rect(const double *b, double g, double c[8]) {
	c[0] = b[0] - g; c[1] = b[1] - g; c[2] = b[2] + g; c[3] = b[1] - g;
	c[4] = b[2] + g; c[5] = b[3] + g; c[6] = b[0] - g; c[7] = b[3] + g;
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

/* Maximum visibility distances (§6.5.5), bottom-up in one backward pass (children follow their parent): out-leaves
   unbounded, in-leaves the stored occluder's largest distance to a cell point (along any line, at most that far
   from where the line leaves the cell). */
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

/* The cell polygon `in` (n >= 3 vertices) centred at its vertex mean (*cx, *cy), made CCW, into `cell` (2 n
   doubles). PVS_OK, or PVS_ERROR_BAD_CELL (in err) when it has no area or is not convex. */
PVS__STATIC pvs_result pvs__ot2_cell(const float *in, uint32_t n, double *cell, double *cx, double *cy,
									 pvs_error *err) {
	double area = 0.0;
	uint32_t i;
	*cx = *cy = 0.0;
	for (i = 0; i < n; ++i) { *cx += in[2 * i]; *cy += in[2 * i + 1]; }
	*cx /= n; *cy /= n;
	for (i = 0; i < n; ++i) {
		cell[2 * i] = (double)in[2 * i] - *cx;
		cell[2 * i + 1] = (double)in[2 * i + 1] - *cy;
	}
	for (i = 0; i < n; ++i) {
		const double *a = cell + 2 * i, *b = cell + 2 * ((i + 1) % n);
		area += a[0] * b[1] - a[1] * b[0];
	}
	if (!(fabs(area) > 0.0)) return pvs__fail(err, PVS_ERROR_BAD_CELL, -1, 0, "the cell polygon has no area");
	if (area < 0.0)
		for (i = 0; i < n / 2; ++i) {
			double tx = cell[2 * i], ty = cell[2 * i + 1];
			cell[2 * i] = cell[2 * (n - 1 - i)]; cell[2 * i + 1] = cell[2 * (n - 1 - i) + 1];
			cell[2 * (n - 1 - i)] = tx; cell[2 * (n - 1 - i) + 1] = ty;
		}
	for (i = 0; i < n; ++i) { /* convex: no right turn */
		const double *a = cell + 2 * i, *b = cell + 2 * ((i + 1) % n), *c = cell + 2 * ((i + 2) % n);
		if ((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]) < 0.0)
			return pvs__fail(err, PVS_ERROR_BAD_CELL, -1, 0, "the cell polygon is not convex");
	}
	return PVS_OK;
}

/* The MVD shortcut's distances (§6.5.5) of the `count` segments to the cell (n vertices), rounded outward by
   len_eps: reach[i] the largest distance from segment i to a cell point, near[i] the least (0 when they meet). */
PVS__STATIC void pvs__ot2_distances(const double *seg, uint32_t count, const double *cell, uint32_t n, double len_eps,
									double *reach, double *near) {
	uint32_t i, k;
	for (i = 0; i < count; ++i) {
		const double *sg = seg + 4 * i;
		double nr = DBL_MAX;
		for (k = 0; k < n; ++k) {
			double e[4], d1;
			e[0] = cell[2 * k];
			e[1] = cell[2 * k + 1];
			e[2] = cell[2 * ((k + 1) % n)];
			e[3] = cell[2 * ((k + 1) % n) + 1];
			d1 = pvs__ot_seg_dist(sg, e);
			if (d1 < nr) nr = d1;
		}
		reach[i] = sqrt(pvs__ot_far2(cell, n, sg)) * (1.0 + 1e-9) + len_eps;
		near[i] = pvs__ot_segment_meets_polygon(sg, cell, n) ? 0.0 : nr * (1.0 - 1e-9) - len_eps;
	}
}

/* Segment i (s, `near` from the cell) through the blockers of each cell edge (§6.6). test 0: inserted (an occluder
   crossing the cell is visible anyway; its outside parts still block). test 1, the exact re-test: 1 when it meets the
   cell, is a point, is degenerate as seen from a cell edge, or a line from an edge reaches it past the occluders. */
PVS__STATIC int pvs__ot2_segment(pvs__otree *t, const double *cell, uint32_t n, const double *s, uint32_t i,
								 double near, int test) {
	uint32_t k;
	/* a point: no line set to test, count it visible */
	int vis = test && (pvs__ot_segment_meets_polygon(s, cell, n) || (s[0] == s[2] && s[1] == s[3]));
	for (k = 0; k < n && !vis; ++k) {
		double o[4];
		pvs__otpoly bl[2];
		int on, nb, deg, m;
		if (!pvs__ot_clip_segment(cell + 2 * k, cell + 2 * ((k + 1) % n), s, o, &on)) continue;
		nb = pvs__ot_blockers(cell + 2 * ((k + 1) % n), cell + 2 * k, o, on, bl, &deg);
		vis = test && deg;
		for (m = 0; m < nb && !vis; ++m)
			if (test) vis = pvs__ot_visible(t, &bl[m], i, near, 0.0, NULL, NULL);
			else pvs__ot2_insert(t, &bl[m], i, near);
	}
	return vis;
}

PVS_API pvs_result pvs_visibility_2d(const pvs_visibility_2d_desc *desc, pvs_word *visible_segments,
									 pvs_word *visible_objects, pvs_otree_stats *stats, pvs_error *err) {
	pvs__otree t;
	pvs_allocator al;
	double *cell = NULL, *seg = NULL, *reach = NULL, *near = NULL, cx = 0.0, cy = 0.0;
	pvs__key_index *order = NULL;
	uint32_t n, i, budget, count;
	pvs_result r = PVS_OK;
	pvs_otree_stats st;
	pvs__buf b[5];
	int nbuf = 0;
	memset(&st, 0, sizeof(st));
	memset(&t, 0, sizeof(t));
	if (stats) *stats = st;
	if (!desc || !desc->cell || desc->cell_vertex_count < 3 || (desc->segment_count && !desc->segments))
		return pvs__fail(err, PVS_ERROR_INVALID_ARGUMENT, -1, 0,
						 "desc, a cell of >= 3 vertices and the segments are required");
	n = desc->cell_vertex_count;
	count = desc->segment_count;
	for (i = 0; i < 2 * n; ++i)
		if (!pvs__finite(desc->cell[i]))
			return pvs__fail(err, PVS_ERROR_NOT_FINITE, i / 2, 0, "cell vertex %u is not finite", i / 2);
	for (i = 0; i < 4 * count; ++i)
		if (!pvs__finite(desc->segments[i]))
			return pvs__fail(err, PVS_ERROR_NOT_FINITE, i / 4, 0, "segment %u is not finite", i / 4);
	if (desc->segment_objects)
		for (i = 0; i < count; ++i)
			if (desc->segment_objects[i] != PVS_NO_OBJECT && desc->segment_objects[i] >= desc->object_count)
				return pvs__fail(err, PVS_ERROR_INDEX_OUT_OF_RANGE, i, 0, "segment %u names object %u of %u", i,
								 desc->segment_objects[i], desc->object_count);
	al = desc->allocator;
	t.a = &al;
	PVS__BUF(b, nbuf, cell, 2 * (size_t)n, sizeof(double));
	PVS__BUF(b, nbuf, seg, 4 * (size_t)count + 4, sizeof(double));
	PVS__BUF(b, nbuf, order, (size_t)count + 1, sizeof(pvs__key_index));
	PVS__BUF(b, nbuf, reach, (size_t)count + 1, sizeof(double));
	PVS__BUF(b, nbuf, near, (size_t)count + 1, sizeof(double));
	if (!pvs__bufs_alloc(&al, b, nbuf)) {
		r = pvs__fail(err, PVS_ERROR_OUT_OF_MEMORY, -1, 0, "2D visibility arrays");
		goto done;
	}
	r = pvs__ot2_cell(desc->cell, n, cell, &cx, &cy, err);
	if (r != PVS_OK) goto done;
	{
		double ext = 1.0, o[2] = {0.0, 0.0};
		for (i = 0; i < 4 * count; ++i) {
			seg[i] = (double)desc->segments[i] - (i & 1 ? cy : cx);
			if (fabs(seg[i]) > ext) ext = fabs(seg[i]);
		}
		t.len_eps = 1e-9 * ext;
		for (i = 0; i < count; ++i) {
			order[i].key = desc->flags & PVS__VISIBILITY_INPUT_ORDER ? 0.0 : pvs__ot_dist2(o, seg + 4 * i);
			order[i].index = i;
		}
	}
	pvs__key_index_sort(order, count);
	pvs__ot2_distances(seg, count, cell, n, t.len_eps, reach, near);
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
		(void)pvs__ot2_segment(&t, cell, n, s, j, near[j], 0);
		pvs__ot2_update_mvd(&t);
	}
	if (t.oom) { r = pvs__fail(err, PVS_ERROR_OUT_OF_MEMORY, -1, 0, "occlusion tree nodes"); goto done; }
	/* exact re-test of every segment against the final tree (§6.6) */
	if (visible_segments) memset(visible_segments, 0, PVS_BITSET_WORDS(count) * sizeof(pvs_word));
	if (visible_objects) memset(visible_objects, 0, PVS_BITSET_WORDS(desc->object_count) * sizeof(pvs_word));
	for (i = 0; i < count; ++i) {
		int vis = pvs__ot2_segment(&t, cell, n, seg + 4 * i, i, near[i], 1);
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
	pvs__bufs_free(&al, b, nbuf);
	return r;
}

/* ---- facades: the scene's vertical walls as 2.5D occluders (§7.1, the input of c-LSS) ---- */

/* Facade extraction, any tessellation (T-junction splits, strips, fans; floors at several heights):
   1. vertical triangles are grouped by ground line (direction, then offset, within tolerances), dropping members
	  farther than tol from the longest member's line;
   2. in (s, h), s along the line, the vertices' s cut slabs with no vertex inside, where cross-section bounds are
	  linear: triangles overlapping (within tol) at both slab ends overlap across it, so a connected set covers
	  [min_j max(lo_j), max_j min(hi_j)] (member bounds at the ends) all over the slab;
   3. consecutive slabs with the same interval (within tol) make a facade: a segment and the heights [bottom, top]
	  it fully covers.
   Conservative up to cracks and offsets of tol (8 float epsilons of the scene's coordinates: T-junction cracks);
   heights round inward, ends are vertex floats. Writes *count facades (u0 v0 u1 v1 top bottom) into a new *out
   (allocator a, *out_floats floats), *vertical the vertical triangles; OUT_OF_MEMORY leaves *out NULL. */
#define PVS__FX_MAX_COVER 512 /* a slab covered by more triangles is left out (conservative) */
#define PVS__OT25_LEVELS 8    /* base heights of facades the OTREE bake tells apart (pvs__otree_prepare) */

typedef struct pvs__fxopen {
	double s0, s1, bot, top;
	double g0[2], g1[2]; /* the ground points of the mesh vertices at s0 and s1 */
} pvs__fxopen;

PVS__STATIC int pvs__fx_emit(const pvs_allocator *a, float **out, size_t *cap, uint32_t *count, const pvs__fxopen *f) {
	float *o, bot, top;
	int k;
	if (!(f->s1 > f->s0) || !(f->top > f->bot)) return 1;
	bot = (float)f->bot;
	if ((double)bot < f->bot) bot = nextafterf(bot, FLT_MAX);
	top = (float)f->top;
	if ((double)top > f->top) top = nextafterf(top, -FLT_MAX);
	if (!(top > bot) || *count >= 0x7fffffffu) return 1;
	if (!pvs__grow(a, (void **)out, cap, 6 * ((size_t)*count + 2), sizeof(float))) return 0;
	o = *out + 6 * (size_t)*count;
	for (k = 0; k < 2; ++k) { o[k] = (float)f->g0[k]; o[2 + k] = (float)f->g1[k]; } /* the vertices' own floats */
	o[4] = top;
	o[5] = bot;
	++*count;
	return 1;
}

/* Cross-section [lo, hi] at s of triangle (ts, th). Edges are evaluated from their smaller-s end, so both
   triangles of a shared edge get the same values. */
PVS__STATIC void pvs__fx_section(const double *ts, const double *th, double s, double *lo, double *hi) {
	int i;
	*lo = DBL_MAX; *hi = -DBL_MAX;
	for (i = 0; i < 3; ++i) {
		int j = i == 2 ? 0 : i + 1, p = i, q = j;
		double h;
		if (ts[q] < ts[p] || (ts[q] == ts[p] && th[q] < th[p])) { p = j; q = i; }
		if (s < ts[p] || s > ts[q]) continue;
		if (ts[q] == ts[p]) {
			if (th[p] < *lo) *lo = th[p];
			if (th[q] > *hi) *hi = th[q];
			continue;
		}
		h = s == ts[p] ? th[p] : s == ts[q] ? th[q] : th[p] + (th[q] - th[p]) * ((s - ts[p]) / (ts[q] - ts[p]));
		if (h < *lo) *lo = h;
		if (h > *hi) *hi = h;
	}
}

/* The extraction's scratch (sized for nv vertical triangles) and its output. */
typedef struct pvs__fxwork {
	const pvs_scene *sc;
	const pvs_allocator *a;
	int u, v, up;           /* ground axes, up axis */
	double tol;
	pvs__key_index *so;      /* 3 nv: a line's members by smallest s, then its vertices by s */
	double *sv;             /* 14 nv: per member s[3], h[3], smin, smax, ground[3][2] */
	double *sec;            /* 4 PVS__FX_MAX_COVER: per slab member lo(sa), lo(sb), hi(sa), hi(sb) */
	uint32_t *ins, *act;    /* nv: members in order of smallest s; the members over the slab */
	uint32_t *comp, *que;   /* PVS__FX_MAX_COVER + 1: connected set per slab member; its queue */
	pvs__fxopen *opn, *nxt; /* PVS__FX_MAX_COVER + 1: facades open at the slab's start; those it continues */
	uint32_t nopen;
	float **out;            /* the facades (6 floats each), cap floats allocated, *count written */
	size_t cap;
	uint32_t *count;
} pvs__fxwork;

/* Step 1's test, vertical: ground points collinear within tol, ground length and height > tol. Per vertical
   triangle a slot tl = (theta in [0, pi), offset n . g with n = (-d1, d0), d0, d1, ground length), vt = the
   triangle. Returns the slot count. */
PVS__STATIC uint32_t pvs__fx_vertical(const pvs_scene *sc, int u, int v, int up, double tol, double *tl, uint32_t *vt) {
	uint32_t t, k, nv = 0;
	for (t = 0; t < sc->triangle_count; ++t) {
		double gx[3], gy[3], h[3], best = 0.0, dx, dy, len, hmin, hmax, *q;
		int bi = 0, bj = 1, m;
		for (k = 0; k < 3; ++k) {
			const float *p = sc->positions + 3 * (size_t)sc->indices[3 * (size_t)t + k];
			gx[k] = p[u]; gy[k] = p[v]; h[k] = p[up];
		}
		for (k = 0; k < 3; ++k) {
			uint32_t l = k == 2 ? 0 : k + 1;
			double ex = gx[l] - gx[k], ey = gy[l] - gy[k], e2 = ex * ex + ey * ey;
			if (e2 > best) { best = e2; bi = (int)k; bj = (int)l; }
		}
		len = sqrt(best);
		if (!(len > tol)) continue;
		dx = (gx[bj] - gx[bi]) / len; dy = (gy[bj] - gy[bi]) / len;
		m = 3 - bi - bj;
		if (!(fabs(-dy * (gx[m] - gx[bi]) + dx * (gy[m] - gy[bi])) <= tol)) continue; /* not vertical */
		hmin = pvs__dmin(pvs__dmin(h[0], h[1]), h[2]);
		hmax = pvs__dmax(pvs__dmax(h[0], h[1]), h[2]);
		if (!(hmax - hmin > tol)) continue;
		if (dy < 0.0 || (dy == 0.0 && dx < 0.0)) { dx = -dx; dy = -dy; } /* one direction per line: theta in [0, pi) */
		q = tl + 5 * (size_t)nv;
		q[0] = atan2(dy, dx);
		q[1] = -dy * gx[bi] + dx * gy[bi];
		q[2] = dx;
		q[3] = dy;
		q[4] = len;
		vt[nv++] = t;
	}
	return nv;
}

/* Step 1's group: mem's slots as (s, h) triangles into w->sv on the line of the longest member (ties: lower slot),
   less those farther than tol from it. Returns the count kept. */
PVS__STATIC uint32_t pvs__fx_members(pvs__fxwork *w, const double *tl, const uint32_t *vt, const pvs__key_index *mem,
									 uint32_t n) {
	uint32_t ref = mem[0].index, nm = 0, i, k;
	double d[2], c;
	for (i = 1; i < n; ++i) {
		uint32_t sl = mem[i].index;
		if (tl[5 * (size_t)sl + 4] > tl[5 * (size_t)ref + 4] ||
			(tl[5 * (size_t)sl + 4] == tl[5 * (size_t)ref + 4] && sl < ref))
			ref = sl;
	}
	d[0] = tl[5 * (size_t)ref + 2]; d[1] = tl[5 * (size_t)ref + 3]; c = tl[5 * (size_t)ref + 1];
	for (i = 0; i < n; ++i) {
		uint32_t tri = vt[mem[i].index];
		double *q = w->sv + 14 * (size_t)nm;
		int ok = 1;
		for (k = 0; k < 3; ++k) {
			const float *p = w->sc->positions + 3 * (size_t)w->sc->indices[3 * (size_t)tri + k];
			double gx = p[w->u], gy = p[w->v];
			if (!(fabs(-d[1] * gx + d[0] * gy - c) <= w->tol)) ok = 0;
			q[k] = d[0] * gx + d[1] * gy;
			q[3 + k] = p[w->up];
			q[8 + 2 * k] = gx;
			q[9 + 2 * k] = gy;
		}
		if (!ok) continue;
		q[6] = pvs__dmin(pvs__dmin(q[0], q[1]), q[2]);
		q[7] = pvs__dmax(pvs__dmax(q[0], q[1]), q[2]);
		++nm;
	}
	return nm;
}

/* Steps 2-3 on slab [sa, sb] (ground points ga, gb) with members w->act[0..use): the connected sets (overlap within
   tol at both ends, breadth first) and their intervals, each continuing the open facade ending at sa with the same
   interval (within tol) or opening one; those not continued are emitted. 0 when out of memory. */
PVS__STATIC int pvs__fx_slab(pvs__fxwork *w, uint32_t use, double sa, double sb, const double ga[2],
							 const double gb[2]) {
	double tol = w->tol, *sec = w->sec;
	uint32_t *comp = w->comp, *que = w->que, j, nc, seen, nn = 0;
	pvs__fxopen *opn = w->opn, *nxt = w->nxt;
	for (j = 0; j < use; ++j) {
		const double *q = w->sv + 14 * (size_t)w->act[j];
		pvs__fx_section(q, q + 3, sa, sec + 4 * j, sec + 4 * j + 2);
		pvs__fx_section(q, q + 3, sb, sec + 4 * j + 1, sec + 4 * j + 3);
		comp[j] = 0xffffffffu;
	}
	for (seen = 0, nc = 0; seen < use; ++seen) {
		uint32_t qh = 0, qt = 1;
		double bot = DBL_MAX, top = -DBL_MAX;
		if (comp[seen] != 0xffffffffu) continue;
		comp[seen] = nc;
		que[0] = seen;
		while (qh < qt) {
			const double *x = sec + 4 * que[qh++];
			double lo = x[0] > x[1] ? x[0] : x[1], hi = x[2] < x[3] ? x[2] : x[3];
			if (lo < bot) bot = lo;
			if (hi > top) top = hi;
			for (j = seen + 1; j < use; ++j) {
				const double *y = sec + 4 * j;
				if (comp[j] != 0xffffffffu) continue;
				if (y[0] <= x[2] + tol && y[1] <= x[3] + tol && x[0] <= y[2] + tol && x[1] <= y[3] + tol) {
					comp[j] = nc;
					que[qt++] = j;
				}
			}
		}
		++nc;
		if (top - bot > tol) {
			uint32_t f;
			for (f = 0; f < w->nopen; ++f)
				if (opn[f].s1 == sa && fabs(opn[f].bot - bot) <= tol && fabs(opn[f].top - top) <= tol) break;
			if (f < w->nopen) { /* continued: the common interval */
				nxt[nn] = opn[f];
				bot = bot > nxt[nn].bot ? bot : nxt[nn].bot;
				top = top < nxt[nn].top ? top : nxt[nn].top;
				opn[f] = opn[--w->nopen];
			} else {
				nxt[nn].s0 = sa; nxt[nn].g0[0] = ga[0]; nxt[nn].g0[1] = ga[1];
			}
			nxt[nn].s1 = sb; nxt[nn].bot = bot; nxt[nn].top = top;
			nxt[nn].g1[0] = gb[0]; nxt[nn].g1[1] = gb[1];
			++nn;
		}
	}
	for (j = 0; j < w->nopen; ++j) /* not continued: done */
		if (!pvs__fx_emit(w->a, w->out, &w->cap, w->count, opn + j)) return 0;
	w->opn = nxt;
	w->nxt = opn;
	w->nopen = nn;
	return 1;
}

/* Steps 2 and 3 along a line of nm members (w->sv): the slabs between consecutive vertex s, each with the members
   spanning it (more than PVS__FX_MAX_COVER: left out), then the facades still open emitted. 0 when out of memory. */
PVS__STATIC int pvs__fx_line(pvs__fxwork *w, uint32_t nm) {
	pvs__key_index *so = w->so;
	const double *sv = w->sv;
	uint32_t i, k, ns = 0, na = 0, next = 0, slab;
	w->nopen = 0;
	for (i = 0; i < nm; ++i) { so[i].key = sv[14 * (size_t)i + 6]; so[i].index = i; }
	pvs__key_index_sort(so, nm);
	for (i = 0; i < nm; ++i) w->ins[i] = so[i].index; /* members in order of their smallest s */
	for (i = 0; i < nm; ++i)
		for (k = 0; k < 3; ++k) { so[ns].key = sv[14 * (size_t)i + k]; so[ns].index = 3 * i + k; ++ns; }
	pvs__key_index_sort(so, ns); /* every vertex s: the slab boundaries */
	for (slab = 0; slab + 1 < ns; ++slab) {
		double sa = so[slab].key, sb = so[slab + 1].key, ga[2], gb[2];
		uint32_t m = 0, j;
		if (!(sb > sa)) continue;
		ga[0] = sv[14 * (size_t)(so[slab].index / 3) + 8 + 2 * (so[slab].index % 3)];
		ga[1] = sv[14 * (size_t)(so[slab].index / 3) + 9 + 2 * (so[slab].index % 3)];
		gb[0] = sv[14 * (size_t)(so[slab + 1].index / 3) + 8 + 2 * (so[slab + 1].index % 3)];
		gb[1] = sv[14 * (size_t)(so[slab + 1].index / 3) + 9 + 2 * (so[slab + 1].index % 3)];
		while (next < nm && sv[14 * (size_t)w->ins[next] + 6] <= sa) w->act[na++] = w->ins[next++];
		for (j = 0; j < na; ++j) /* members whose range ends before the slab leave */
			if (sv[14 * (size_t)w->act[j] + 7] >= sb) w->act[m++] = w->act[j];
		na = m;
		if (!pvs__fx_slab(w, na > PVS__FX_MAX_COVER ? 0 : na, sa, sb, ga, gb)) return 0;
	}
	for (i = 0; i < w->nopen; ++i)
		if (!pvs__fx_emit(w->a, w->out, &w->cap, w->count, w->opn + i)) return 0;
	return 1;
}

PVS__STATIC pvs_result pvs__facades_extract(const pvs_scene *sc, const pvs_allocator *a, float **out,
											size_t *out_floats, uint32_t *count, uint32_t *vertical) {
	pvs__fxwork w;
	uint32_t nv = 0, i, k, g0, g1, c0, c1, nt = sc->triangle_count;
	double ext = 1.0, tol_a = 1e-7, *tl = NULL;
	pvs__key_index *ord = NULL, *sord = NULL;
	uint32_t *vt = NULL;
	pvs_result r = PVS_ERROR_OUT_OF_MEMORY;
	pvs__buf b[13];
	int nb = 0;
	memset(&w, 0, sizeof(w));
	w.sc = sc;
	w.a = a;
	w.out = out;
	w.count = count;
	*out = NULL;
	*out_floats = 0;
	*count = 0;
	*vertical = 0;
	w.up = sc->up_axis == 2 ? 2 : 1;
	pvs__ground_axes((uint32_t)w.up, &w.u, &w.v);
	if (nt)
		for (k = 0; k < 3; ++k) {
			if (fabs((double)sc->bounds.min[k]) > ext) ext = fabs((double)sc->bounds.min[k]);
			if (fabs((double)sc->bounds.max[k]) > ext) ext = fabs((double)sc->bounds.max[k]);
		}
	w.tol = 8.0 * FLT_EPSILON * ext;
	PVS__BUF(b, nb, tl, 5 * (size_t)nt + 5, sizeof(double));
	PVS__BUF(b, nb, vt, (size_t)nt + 1, sizeof(uint32_t));
	if (!pvs__bufs_alloc(a, b, nb)) goto done;
	*vertical = nv = pvs__fx_vertical(sc, w.u, w.v, w.up, w.tol, tl, vt);
	PVS__BUF(b, nb, ord, (size_t)nv + 1, sizeof(pvs__key_index));
	PVS__BUF(b, nb, sord, (size_t)nv + 1, sizeof(pvs__key_index));
	PVS__BUF(b, nb, w.so, 3 * (size_t)nv + 3, sizeof(pvs__key_index));
	PVS__BUF(b, nb, w.sv, 14 * (size_t)nv + 14, sizeof(double));
	PVS__BUF(b, nb, w.sec, 4 * (size_t)PVS__FX_MAX_COVER, sizeof(double));
	PVS__BUF(b, nb, w.ins, (size_t)nv + 1, sizeof(uint32_t));
	PVS__BUF(b, nb, w.act, (size_t)nv + 1, sizeof(uint32_t));
	PVS__BUF(b, nb, w.comp, (size_t)PVS__FX_MAX_COVER + 1, sizeof(uint32_t));
	PVS__BUF(b, nb, w.que, (size_t)PVS__FX_MAX_COVER + 1, sizeof(uint32_t));
	PVS__BUF(b, nb, w.opn, (size_t)PVS__FX_MAX_COVER + 1, sizeof(pvs__fxopen));
	PVS__BUF(b, nb, w.nxt, (size_t)PVS__FX_MAX_COVER + 1, sizeof(pvs__fxopen));
	if (!pvs__bufs_alloc(a, b + 2, nb - 2)) goto done;
	for (i = 0; i < nv; ++i) { ord[i].key = tl[5 * (size_t)i]; ord[i].index = i; }
	pvs__key_index_sort(ord, nv); /* by direction (ties by slot: deterministic) */
	for (g0 = 0; g0 < nv; g0 = g1) {
		for (g1 = g0 + 1; g1 < nv && ord[g1].key - ord[g0].key <= tol_a; ++g1) ;
		for (i = g0; i < g1; ++i) {
			sord[i - g0].key = tl[5 * (size_t)ord[i].index + 1];
			sord[i - g0].index = ord[i].index;
		}
		pvs__key_index_sort(sord, g1 - g0); /* then by offset */
		for (c0 = 0; c0 < g1 - g0; c0 = c1) {
			uint32_t nm;
			for (c1 = c0 + 1; c1 < g1 - g0 && sord[c1].key - sord[c0].key <= w.tol; ++c1) ;
			nm = pvs__fx_members(&w, tl, vt, sord + c0, c1 - c0);
			if (nm && !pvs__fx_line(&w, nm)) goto done;
		}
	}
	if (!*out && !pvs__grow(a, (void **)out, &w.cap, 6, sizeof(float))) goto done;
	*out_floats = w.cap;
	r = PVS_OK;
done:
	if (r != PVS_OK && *out) { pvs__free(a, *out, w.cap * sizeof(float), 16); *out = NULL; *count = 0; }
	pvs__bufs_free(a, b, nb);
	return r;
}

/* ---- 2.5D from-region, c-LSS (ch. 7) ---- */

/* Proving hidden things hidden dominates the cost; each shortcut below paid for itself (bench_otree;
   tests/BENCHMARKS.md, otree). */

#define PVS__OT25_MAX_UMBRAE 96
#define PVS__OT25_JD 10 /* doubles of per-occluder data (pvs__ot25_prepare) */
/* kD nodes with fewer item references are not tested (cf. §4.12.1: none below 50 polygons) */
#define PVS__OT25_TEST_MIN 48

/* Hidden-height bound (§6.5.5's maximum visibility distance, made valid in 2.5D where occluders are seen over):
   each line of an in-leaf crosses every member j. A ray on it from an eye p no higher than H = t->eye passing over
   j (top h_j > H) rises at slope >= s = (h_j - H) / reach_j (|pc| <= reach_j, c the crossing), so points no nearer
   than n > reach_j to the cell and lower than H + s n are hidden. Leaves keep the steepest member (mr = reach, ms =
   s), inner nodes the children's largest reach and least slope; none (DBL_MAX) above out-leaves and members no
   taller than the eyes. */
PVS__STATIC void pvs__ot25_leaf_bound(const pvs__otree *t, pvs__otnode *nd) {
	(void)t;
	if (nd->kind == PVS__OT_IN) return; /* set as members join (pvs__ot25_join), inherited by parts */
	nd->mr = nd->ml = DBL_MAX;
	nd->ms = nd->mls = 0.0;
}
/* Member k joins in-leaf `node` whose lines cross k within [f0, f1] only: its reach there (a cell corner to an end
   of that part) is <= jd[8], its slope >= jd[9]. The leaf keeps the steepest member (mr, ms) and the one of least
   reach (ml, mls), valid for later splits' parts too. */
PVS__STATIC void pvs__ot25_join(pvs__otree *t, uint32_t node, uint32_t k, double f0, double f1) {
	const double *sg = t->seg + 4 * (size_t)k, *jd = t->jd + PVS__OT25_JD * (size_t)k;
	pvs__otnode *nd = t->nodes + node;
	double r = jd[8], sl = jd[9], far2, e[4];
	if (!(sl > 0.0)) return; /* not taller than the eyes: no bound */
	f0 -= 1e-9; f1 += 1e-9;
	if (f0 < 0.0) f0 = 0.0;
	if (f1 > 1.0) f1 = 1.0;
	if (f0 <= f1) {
		e[0] = sg[0] + f0 * (sg[2] - sg[0]); e[1] = sg[1] + f0 * (sg[3] - sg[1]);
		e[2] = sg[0] + f1 * (sg[2] - sg[0]); e[3] = sg[1] + f1 * (sg[3] - sg[1]);
		far2 = sqrt(pvs__ot_far2(t->corners, 4, e)) * (1.0 + 1e-9) + 2.0 * t->len_eps;
		if (far2 < r) {
			sl = (t->top[k] - t->eye) / far2 * (1.0 - 1e-9);
			r = far2;
		}
	}
	if (sl > nd->ms || (sl == nd->ms && r < nd->mr)) { nd->ms = sl; nd->mr = r; }
	if (r < nd->ml) { nd->ml = r; nd->mls = sl; }
}
/* The parameter hull on segment e of the lines of polygon q (its vertices), clamped to [0, 1]. */
PVS__STATIC void pvs__ot25_funnel(const pvs__otpoly *q, const double *e, double *f0, double *f1) {
	double lo = DBL_MAX, hi = -DBL_MAX, u;
	int i;
	for (i = 0; i < q->n; ++i) {
		if (pvs__ot_param(q->v[i], e, &u)) { if (u < lo) lo = u; if (u > hi) hi = u; }
		else { lo = -DBL_MAX; hi = DBL_MAX; }
	}
	*f0 = lo < 0.0 ? 0.0 : lo;
	*f1 = hi > 1.0 ? 1.0 : hi;
}
/* Inner node `node`'s bound from its children's; 0 when it did not change. */
PVS__STATIC int pvs__ot25_inner_bound(pvs__otree *t, uint32_t node) {
	pvs__otnode *nd = t->nodes + node;
	const pvs__otnode *a = t->nodes + nd->child[0], *b = t->nodes + nd->child[1];
	double mr = a->mr > b->mr ? a->mr : b->mr, ms = a->ms < b->ms ? a->ms : b->ms;
	double ml = a->ml > b->ml ? a->ml : b->ml, mls = a->mls < b->mls ? a->mls : b->mls;
	if (mr == nd->mr && ms == nd->ms && ml == nd->ml && mls == nd->mls) return 0;
	nd->mr = mr;
	nd->ms = ms;
	nd->ml = ml;
	nd->mls = mls;
	return 1;
}
/* Recomputes the bound of the subtree at `node` (just rebuilt from a leaf: a short chain) and of its
   ancestors while they change. */
PVS__STATIC void pvs__ot25_bound_subtree(pvs__otree *t, uint32_t node) {
	pvs__otnode *nd = t->nodes + node;
	if (nd->kind) { pvs__ot25_leaf_bound(t, nd); return; }
	pvs__ot25_bound_subtree(t, nd->child[0]);
	pvs__ot25_bound_subtree(t, nd->child[1]);
	(void)pvs__ot25_inner_bound(t, node);
}
PVS__STATIC void pvs__ot25_bound(pvs__otree *t, uint32_t node) {
	uint32_t p;
	pvs__ot25_bound_subtree(t, node);
	for (p = t->nodes[node].parent; p != PVS__OT_NONE && pvs__ot25_inner_bound(t, p); p = t->nodes[p].parent) {}
}
/* Lower bound of the distance from the grown cell rectangle to segment e: to e's bounding box (exact when
   axis-parallel), rounded down. */
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

/* Extended umbra (§7.5.1) of occluder j on far segment e's top edge (height h), for rays over j's top edge from
   eyes at height H = t->eye anywhere over the cell (§7.1: a falling ray is seen at least as well from where its 2D
   line leaves the cell, a rising one from where it enters; both on top edges): the open interval (u0, u1) of
   parameters on e where every such ray passes below j's top. For eye p, q is below when (h - H) D(p) < (h_j - H)
   (D(p) - D(q)), D the signed distance to j's line (> 0 where the lines come from); monotone in D(p), so the
   corners' extreme D (clamped at 0: eyes behind j's line do not look over it) cover every eye: the thesis's pi_o /
   pi_s over the whole cell, so one tree per edge serves both kinds of rays. 0 when empty. */
PVS__STATIC int pvs__ot25_umbra(const pvs__otree *t, const double *jd, double q0, double q1, double h, double *u0,
								double *u1) {
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

/* Occluder j's per-tree data: jd[0..2] its line D(x) = jd[0] x + jd[1] y + jd[2] (unit normal, > 0 on the source
   edge's side); jd[3..4] the cell corners' least and largest D (clamped at 0); jd[5] 1 when the source edge lies on
   one side; jd[6] top - eyes; jd[7] 0: no umbra (source edge midpoint on its line, or a point); jd[8] reach
   (largest distance to a cell point, rounded up); jd[9] (top - eyes) / reach when taller than the eyes, else 0. */
PVS__STATIC void pvs__ot25_prepare(pvs__otree *t, uint32_t j) {
	const double *sg = t->seg + 4 * (size_t)j;
	double *jd = t->jd + PVS__OT25_JD * (size_t)j, dx = sg[2] - sg[0], dy = sg[3] - sg[1],
		   len = sqrt(dx * dx + dy * dy), sa, da, db;
	int i;
	memset(jd, 0, PVS__OT25_JD * sizeof(double));
	jd[8] = sqrt(pvs__ot_far2(t->corners, 4, sg)) * (1.0 + 1e-9) + t->len_eps;
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

/* Part of far segment e (height h) seen over the front members of payload seq[first..+count) within q's funnel: its
   parameter hull [*v0, *v1] in the funnel range [*f0, *f1]. Members crossing `skip_box` (2D, or NULL) or not
   clearly in front are ignored (conservative). 0 when nothing is left. */
PVS__STATIC int pvs__ot25_open(const pvs__otree *t, const pvs__otpoly *q, uint32_t first, uint32_t count, uint32_t self,
							   const double *e, double h, const double *skip_box, double *f0, double *f1, double *v0,
							   double *v1) {
	double flo, fhi;
	double um[PVS__OT25_MAX_UMBRAE][2];
	int i, nu = 0, changed;
	uint32_t m;
	*f0 = *v0 = 0.0; *f1 = *v1 = 1.0;
	pvs__ot25_funnel(q, e, &flo, &fhi);
	for (m = 0; m < count && nu < PVS__OT25_MAX_UMBRAE; ++m) {
		uint32_t j = t->seq[first + m];
		const double *sj = t->seg + 4 * (size_t)j, *jd = t->jd + PVS__OT25_JD * (size_t)j;
		double s0, s1, tol = t->len_eps;
		int front, behind;
		if (j == self || !jd[7]) continue;
		if (skip_box) {
			double poly[8];
			pvs__ot_rect(skip_box, t->len_eps, poly);
			if (fmin(sj[0], sj[2]) <= poly[2] && fmax(sj[0], sj[2]) >= poly[0] && fmin(sj[1], sj[3]) <= poly[5] &&
				fmax(sj[1], sj[3]) >= poly[1] && pvs__ot_segment_meets_polygon(sj, poly, 4))
				continue;
		}
		/* quick order: e wholly beyond j's line puts j in front on every line crossing both; wholly on the
		   source side, behind */
		s0 = jd[0] * e[0] + jd[1] * e[1] + jd[2];
		s1 = jd[0] * e[2] + jd[1] * e[3] + jd[2];
		/* the umbra first (cheap): one missing the open funnel range never moves v0 or v1, so needs no
		   depth order; one covering it hides e here once j is found in front */
		if (!pvs__ot25_umbra(t, jd, s0, s1, h, &um[nu][0], &um[nu][1]) || um[nu][1] <= flo || um[nu][0] >= fhi)
			continue;
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
		if (um[nu][0] <= flo && um[nu][1] >= fhi) return 0; /* one umbra covers the funnel's part of e: hidden */
		++nu;
	}
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
/* Lazy funnel splitting: below this many members a leaf takes a partly visible occluder whole. Conservative: each
   line of the leaf crosses the occluder, whose extended umbra holds there, seen or not (the thesis keeps hidden
   occluders in S_L too, §7.5.2); the leaf answers at least as tightly, with a longer sequence. From this length
   splitting (at most three, §7.5.2) bounds it; cheaper than splitting at once, and culls as much
   (tests/BENCHMARKS.md, otree). */
#define PVS__OT25_SPLIT_MIN 16

/* Inserts occluder k's blocker (c-LSS, §7.5.2): out-leaves become in-leaves holding k; at an in-leaf the funnel
   test clips k's top edge by the front members' extended umbrae and, if a part stays visible, the leaf gets k,
   split (from PVS__OT25_SPLIT_MIN members) into at most three: the primary funnel (rays through the visible part)
   with members and k, the secondary ones with the members. */
PVS__STATIC void pvs__ot25_insert(pvs__otree *t, const pvs__otpoly *blocker, uint32_t k) {
	size_t base = t->stack_count;
	const double *sk = t->seg + 4 * (size_t)k;
	double near = pvs__ot25_near(t, sk), top = t->top[k];
	if (!pvs__ot_push(t, 0, blocker)) return;
	while (t->stack_count > base && !t->oom) {
		const pvs__otpoly *q;
		uint32_t node = t->stack_node[t->stack_count - 1];
		pvs__otnode *nd = t->nodes + node;
		if (PVS__OT25_HIDDEN(t, nd, near, top)) { --t->stack_count; continue; } /* k hidden in this subtree */
		if (nd->kind == 0) { pvs__ot_insert_inner(t, t->stack_count - 1, near, top); continue; }
		q = PVS__OT_ITEM(t, --t->stack_count); /* read in its slot: nothing is pushed before the next pop */
		if (nd->kind == PVS__OT_OUT) {
			uint32_t leaf = pvs__ot_refine(t, node, q);
			if (leaf != PVS__OT_NONE && pvs__ot_set_payload(t, leaf, 0, 0, k)) {
				double f0, f1;
				pvs__ot25_funnel(q, sk, &f0, &f1);
				pvs__ot25_join(t, leaf, k, f0, f1);
			}
			pvs__ot25_bound(t, node);
		} else {
			uint32_t first = nd->first, count = nd->count, leaf;
			double f0, f1, v0, v1, cen[3] = {0, 0, 0};
			int i, c;
			if (count >= PVS__OT25_MAX_SEQ) continue; /* a full leaf keeps its members: conservative */
			if (!pvs__ot25_open(t, q, first, count, k, sk, t->top[k], NULL, &f0, &f1, &v0, &v1))
				continue; /* hidden here */
			leaf = pvs__ot_refine(t, node, q);
			if (leaf == PVS__OT_NONE) break;
			for (i = 0; i < q->n; ++i) for (c = 0; c < 3; ++c) cen[c] += q->v[i][c];
			/* lines through k before v0 (after v1) see only the old members: the primary side (lines crossing k
			   beyond x, the point at v0) has x on the side of k's first end (at v1: of its second) */
			for (c = 0; c < 2 && count >= PVS__OT25_SPLIT_MIN; ++c) {
				double x[2], u = c ? v1 : v0, sgn;
				if (c ? !(v1 < f1 - 1e-9) : !(v0 > f0 + 1e-9)) continue;
				x[0] = sk[0] + u * (sk[2] - sk[0]); x[1] = sk[1] + u * (sk[3] - sk[1]);
				sgn = pvs__ot_side(cen, sk + 2 * c);
				if (sgn == 0.0) continue;
				leaf = pvs__ot_split_leaf(t, leaf, x, sgn);
				if (leaf == PVS__OT_NONE) break;
			}
			if (leaf == PVS__OT_NONE) break;
			if (pvs__ot_set_payload(t, leaf, first, count, k)) pvs__ot25_join(t, leaf, k, f0, f1);
			pvs__ot25_bound(t, node);
		}
	}
	t->stack_count = base;
}

/* The kind of the leaf holding line w (unit), found by descending with w alone; 0 when w lies within
   1e-9 of a plane on its path (no answer) or outside the lines leaving through the source edge. */
PVS__STATIC uint32_t pvs__ot25_locate(const pvs__otree *t, const double w[3]) {
	uint32_t node = 0;
	int in_root = 0;
	while (t->nodes[node].kind == 0) {
		const pvs__otnode *nd = t->nodes + node;
		double d = nd->n[0] * w[0] + nd->n[1] * w[1] + nd->n[2] * w[2];
		if (node == t->root_in) in_root = 1;
		if (d > 1e-9) node = nd->child[1];
		else if (d < -1e-9) node = nd->child[0];
		else return 0;
	}
	return in_root ? t->nodes[node].kind : 0;
}

/* Early exit of pvs__ot25_box_visible (§3.3.4): 1 when a witness line still in an out-leaf crosses the interior of
   box bx (wholly beyond source edge a -> b): it leaves through the source edge, meets no occluder, then two box
   sides, one of which pvs__ot25_box_visible tests and would reach that out-leaf. Margins of 1e-6 of the scene size
   keep rounding out; 0: run the full test. */
PVS__STATIC int pvs__ot25_witnessed(pvs__otree *t, const double *bx, const double a[2], const double b[2]) {
	double nx = a[1] - b[1], ny = b[0] - a[0], mg = 1e3 * t->len_eps, near;
	int i, k;
	if (!t->nwit || !(bx[0] < bx[2] && bx[1] < bx[3])) return 0;
	near = nx * (nx > 0 ? bx[0] : bx[2]) + ny * (ny > 0 ? bx[1] : bx[3]) - (nx * a[0] + ny * a[1]);
	if (!(near > mg * sqrt(nx * nx + ny * ny))) return 0;
	for (i = 0; i < t->nwit; ++i) {
		const double *w = t->wit[i];
		double m = mg * sqrt(w[0] * w[0] + w[1] * w[1]), s0, s1, s2, s3, lo, hi;
		uint32_t kind;
		s0 = w[0] * bx[0] + w[1] * bx[1] + w[2];
		s1 = w[0] * bx[2] + w[1] * bx[1] + w[2];
		s2 = w[0] * bx[2] + w[1] * bx[3] + w[2];
		s3 = w[0] * bx[0] + w[1] * bx[3] + w[2];
		lo = s0 < s1 ? s0 : s1;
		hi = s0 < s1 ? s1 : s0;
		if (s2 < lo) lo = s2;
		if (s2 > hi) hi = s2;
		if (s3 < lo) lo = s3;
		if (s3 > hi) hi = s3;
		if (!(lo < -m && hi > m)) continue;
		kind = pvs__ot25_locate(t, w);
		if (kind == PVS__OT_OUT) {
			double keep[3];
			memcpy(keep, w, sizeof(keep));
			for (k = i; k > 0; --k) memcpy(t->wit[k], t->wit[k - 1], sizeof(t->wit[k]));
			memcpy(t->wit[0], keep, sizeof(keep));
			return 1;
		}
		if (kind == PVS__OT_IN) { /* in for good */
			for (k = i; k + 1 < t->nwit; ++k) memcpy(t->wit[k], t->wit[k + 1], sizeof(t->wit[k]));
			--t->nwit;
			--i;
		}
	}
	return 0;
}

/* Read-only test (§3.3.4): 1 when a line of the blocker may get past the stored occluders (or out of memory). Splits
   with slack, stops at the first visible leaf. 2D (§6.5.3; e NULL, h unused): a line reaches occluder k before any
   stored one; slivers (pvs__ot_thickness) do not count, so the answer does not depend on where insertion rounded,
   i.e. on the insertion order. 2.5D (c-LSS): part of far edge e (height h) of object box `box` may be seen. near:
   the subtree bounds' distance (§6.5.5; 2.5D pvs__ot25_near). */
PVS__STATIC int pvs__ot_visible(pvs__otree *t, const pvs__otpoly *blocker, uint32_t k, double near, double h,
								const double *e, const double *box) {
	size_t base = t->stack_count, top;
	const double *sk = e ? NULL : t->seg + 4 * (size_t)k;
	int vis = 0;
	if (!pvs__ot_push(t, 0, blocker)) return 1;
	while ((top = t->stack_count) > base && !vis) {
		uint32_t node = t->stack_node[--top], j;
		const pvs__otnode *nd = t->nodes + node;
		pvs__otpoly q;
		double x[2], f0, f1, v0, v1;
		int front, behind;
		if ((e ? PVS__OT25_HIDDEN(t, nd, near, h) : near > nd->mvd) || /* hidden in this subtree */
			(t->stack_pend[top] != PVS__OT_NONE && !pvs__ot_owed(t, top))) {
			t->stack_count = top;
			continue;
		}
		if (nd->kind == 0) { vis |= pvs__ot_test_inner(t, top, e ? near : -1.0, h); continue; }
		t->stack_count = top; /* the polygon stays readable in its slot until the next push */
		if (e) {
			if (nd->kind == PVS__OT_OUT) pvs__ot25_witness_add(t, PVS__OT_ITEM(t, top));
			vis = nd->kind == PVS__OT_OUT || pvs__ot25_open(t, PVS__OT_ITEM(t, top), nd->first, nd->count, PVS__OT_NONE,
															 e, h, box, &f0, &f1, &v0, &v1);
			continue;
		}
		pvs__ot_copy(&q, PVS__OT_ITEM(t, top));
		if (pvs__ot_thickness(&q) < PVS__OT_SLIVER) continue;
		if (nd->kind == PVS__OT_OUT || (j = t->seq[nd->first]) == k) { vis = 1; break; }
		pvs__ot_depth(t, &q, t->seg + 4 * (size_t)j, sk, &front, &behind);
		/* the exact test splits at the crossing X (§6.5.1 case 3) */
		if (front && behind && !q.xsplit && pvs__ot_cross(t->seg + 4 * (size_t)j, sk, x)) {
			vis |= !pvs__ot2_xsplit(t, node, &q, x);
			continue;
		}
		if (front || !behind) vis = 1; /* in front somewhere, or all ties (collinear): visible */
	}
	t->stack_count = base;
	return vis || t->oom;
}

/* 1 when part of box bx (local umin, vmin, umax, vmax; top) beyond source edge a -> b may be seen: its top edges
   as far segments (§7.7). */
PVS__STATIC int pvs__ot25_box_visible(pvs__otree *t, const double *bx, double top, const double a[2], const double b[2],
									  int *any_far) {
	double c4[8], nx = 0.5 * (a[0] + b[0]), ny = 0.5 * (a[1] + b[1]); /* the source edge's outward direction */
	/* the bound counts every member, also those crossing the box that pvs__ot25_open ignores (a wall on a ground
	   tile would hide the tile's far edge): with the whole box's nearness, a member of smaller reach lies wholly
	   nearer */
	double near = pvs__ot25_near(t, bx);
	int i, vis = 0, far_edge, order[3];
	c4[0] = c4[6] = bx[0];
	c4[1] = c4[3] = bx[1];
	c4[2] = c4[4] = bx[2];
	c4[5] = c4[7] = bx[3];
	if (any_far) *any_far = 0;
	if (!any_far && !t->full_tests && pvs__ot25_witnessed(t, bx, a, b)) return 1;
	/* A box taller than the eyes is seen, if at all, along a rising ray, at least as well where its 2D line enters
	   the box; a lower one along a falling ray, where the line leaves it (a farther point at equal height is higher
	   over every occluder in front; members crossing the box are ignored, pvs__ot25_open). No line enters through
	   the box edge facing the source edge's way or leaves through the one facing the source (edges 0..3: -v, +u,
	   +v, -u): test the entry (exit) edge first, the likeliest seen, then the two sides. */
	if (fabs(nx) > fabs(ny)) far_edge = nx > 0 ? 1 : 3;
	else far_edge = ny > 0 ? 2 : 0;
	order[0] = top > t->eye ? (far_edge + 2) & 3 : far_edge;
	order[1] = (far_edge + 1) & 3;
	order[2] = (far_edge + 3) & 3;
	for (i = 0; i < 3 && !vis; ++i) {
		int edge = order[i], on, nb, deg, m;
		double sg[4], o[4], pa, pb, c;
		pvs__otpoly bl[2];
		/* an edge no line enters (tall box) or leaves (low box) is skipped: with outward normal m and
		   m.x = c on it, a line from p enters when m.p > c, leaves when m.p < c (exact compares) */
		if (edge & 1) { pa = a[0]; pb = b[0]; c = edge == 1 ? bx[2] : bx[0]; }
		else { pa = a[1]; pb = b[1]; c = edge == 2 ? bx[3] : bx[1]; }
		if (edge == 0 || edge == 3) { pa = -pa; pb = -pb; c = -c; }
		if (top > t->eye ? !(pa > c || pb > c) : !(pa < c || pb < c)) continue;
		sg[0] = c4[2 * edge]; sg[1] = c4[2 * edge + 1]; sg[2] = c4[(2 * edge + 2) & 7]; sg[3] = c4[(2 * edge + 3) & 7];
		if (sg[0] == sg[2] && sg[1] == sg[3]) sg[2] += t->len_eps; /* a box flat on both axes: its corner */
		if (!pvs__ot_clip_segment(b, a, sg, o, &on)) continue;
		if (any_far) *any_far = 1;
		nb = pvs__ot_blockers(a, b, o, on, bl, &deg);
		if (deg) vis = 1;
		for (m = 0; m < nb && !vis; ++m) vis = pvs__ot_visible(t, &bl[m], PVS__OT_NONE, near, top, o, bx);
	}
	return vis;
}

typedef struct pvs__ot25_sweep {
	pvs__otree *t;
	const pvs_visibility_25d_desc *desc;
	const double *all;       /* facades, local, 4 doubles each */
	const double *box;       /* objects, local, 5 doubles each */
	const double *cell;      /* the grown cell, CCW */
	unsigned char *state;    /* per facade: 1 + side once handled in this side's tree */
	unsigned char *done;     /* objects: 0 unknown, 1 visible, 2 never, 3 + side: candidate in this tree */
	const double *a, *b;
	double cx, cy;
	uint32_t side, budget;
	pvs_otree_stats *st;
	const uint32_t *refs;    /* per kD node: item references in its subtree */
	uint32_t node;           /* the node being visited */
	uint32_t test_min;       /* inner nodes with fewer references are not tested */
} pvs__ot25_sweep;

/* Sweep visitor (§7.7), front to back: a node meeting the cell is visible; an inner node with >= w->test_min item
   references has its box (footprint edges at its top) tested like an object's and is culled when hidden; leaves
   insert their facades and mark their objects for the test after the sweep. */
PVS__STATIC pvs_visit pvs__ot25_visit(void *user, const pvs_box *node_box, float distance, const uint32_t *items,
									  uint32_t item_count) {
	pvs__ot25_sweep *w = (pvs__ot25_sweep *)user;
	pvs__otree *t = w->t;
	const pvs_visibility_25d_desc *d = w->desc;
	double bx[4];
	uint32_t i;
	(void)distance;
	if (t->oom) return PVS_VISIT_STOP;
	bx[0] = (double)node_box->min[0] - w->cx; bx[1] = (double)node_box->min[1] - w->cy;
	bx[2] = (double)node_box->max[0] - w->cx; bx[3] = (double)node_box->max[1] - w->cy;
	{ /* a node wholly behind the source edge's line is skipped; a -> b runs clockwise: (-ey, ex) outward */
		double ex = w->b[0] - w->a[0], ey = w->b[1] - w->a[1], nx = -ey, ny = ex, far;
		far = nx * (nx > 0 ? bx[2] : bx[0]) + ny * (ny > 0 ? bx[3] : bx[1]) - (nx * w->a[0] + ny * w->a[1]);
		if (far < -t->len_eps * (fabs(nx) + fabs(ny) + 1.0)) return PVS_VISIT_SKIP;
	}
	/* leaves are not tested: inserting their facades and testing their objects after the sweep costs
	   less (the thesis likewise skips small nodes, §4.12.1) */
	if (!items && w->refs[w->node] >= w->test_min &&
		!(bx[0] <= w->cell[2] && bx[2] >= w->cell[0] && bx[1] <= w->cell[5] && bx[3] >= w->cell[1])) {
		if (!pvs__ot25_box_visible(t, bx, (double)node_box->max[2], w->a, w->b, NULL)) return PVS_VISIT_SKIP;
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
			if (w->done[ob] == 0 || (w->done[ob] >= 3 && w->done[ob] != 3 + w->side))
				w->done[ob] = (unsigned char)(3 + w->side);
		}
	}
	return PVS_VISIT_DESCEND;
}

/* The approximate occlusion sweep (§3.2, pvs__kd_sweep), telling the visitor its node (w->node). */
PVS__STATIC void pvs__ot25_sweep_tree(const pvs_kdtree *t, const pvs_box *source, pvs__kdsweep *heap,
									  pvs__ot25_sweep *w) {
	pvs__kd_sweep(t, source, heap, pvs__ot25_visit, w, &w->node);
}

/* A balanced top for a source edge's tree: front-to-back insertion carves the open region (lines down a street)
   into a chain as deep as the occluders along it, walked by every later query. Splitting the root first by the
   planes of PVS__OT25_PRESPLIT far points spread over the directions (exact planes like any other) leaves short
   chains, one per direction sector (tests/BENCHMARKS.md, otree). Reorders pts[lo..hi): each point goes with the
   child holding its line from m. */
#define PVS__OT25_PRESPLIT 16
PVS__STATIC void pvs__ot25_presplit(pvs__otree *t, uint32_t leaf, const double m[2], double (*pts)[2], int lo, int hi) {
	double l[3], tmp[PVS__OT25_PRESPLIT][2];
	int mid, j, na = 0, nb = 0, pass;
	uint32_t pos, neg;
	if (hi <= lo || t->oom) return;
	mid = (lo + hi) / 2;
	pos = pvs__ot_split_leaf(t, leaf, pts[mid], 1.0);
	if (pos == PVS__OT_NONE) return;
	neg = t->nodes[leaf].child[0];
	for (pass = 0; pass < 2; ++pass)
		for (j = lo; j < hi; ++j) {
			int positive;
			if (j == mid) continue;
			pvs__ot_line(m, pts[j], l);
			positive = pvs__ot_side(l, pts[mid]) > 0;
			if (positive != (pass == 0)) continue;
			tmp[na + nb][0] = pts[j][0];
			tmp[na + nb][1] = pts[j][1];
			if (pass == 0) ++na; else ++nb;
		}
	for (j = 0; j < na + nb; ++j) { pts[lo + j][0] = tmp[j][0]; pts[lo + j][1] = tmp[j][1]; }
	pvs__ot25_presplit(t, pos, m, pts, lo, lo + na);
	pvs__ot25_presplit(t, neg, m, pts, lo + na, lo + na + nb);
}

PVS_API void pvs_visibility_25d_boxes(const float *facades, uint32_t facade_count, const float *objects,
									  uint32_t object_count, pvs_box *boxes);

/* pvs_visibility_25d's argument checks: every error it returns but OUT_OF_MEMORY (in err). */
PVS__STATIC pvs_result pvs__ot25_check(const pvs_visibility_25d_desc *desc, const pvs_word *visible_objects,
									   pvs_error *err) {
	uint32_t nf, no, i;
	if (!desc || !visible_objects || (desc->facade_count && !desc->facades) || (desc->object_count && !desc->objects))
		return pvs__fail(err, PVS_ERROR_INVALID_ARGUMENT, -1, 0,
						 "desc, facades, objects and visible_objects are required");
	if (desc->flags & ~PVS__VISIBILITY_25D_FULL_TESTS)
		return pvs__fail(err, PVS_ERROR_INVALID_ARGUMENT, -1, 0, "unknown 2.5D flags 0x%x", desc->flags);
	nf = desc->facade_count;
	no = desc->object_count;
	if ((uint64_t)nf + no >= 0xffffffffu)
		return pvs__fail(err, PVS_ERROR_COUNT_OVERFLOW, -1, 0, "too many facades and objects");
	for (i = 0; i < 2; ++i)
		if (!pvs__finite(desc->cell_min[i]) || !pvs__finite(desc->cell_max[i]) || desc->cell_min[i] > desc->cell_max[i])
			return pvs__fail(err, PVS_ERROR_BAD_CELL, -1, 0, "the cell rectangle is not finite or has min > max");
	if (!pvs__finite(desc->cell_top)) return pvs__fail(err, PVS_ERROR_NOT_FINITE, -1, 0, "cell_top is not finite");
	for (i = 0; i < 5 * nf; ++i)
		if (!pvs__finite(desc->facades[i]))
			return pvs__fail(err, PVS_ERROR_NOT_FINITE, i / 5, 0, "facade %u is not finite", i / 5);
	for (i = 0; i < 5 * no; ++i)
		if (!pvs__finite(desc->objects[i]))
			return pvs__fail(err, PVS_ERROR_NOT_FINITE, i / 5, 0, "object %u is not finite", i / 5);
	return PVS_OK;
}

/* A 2.5D query's input relative to the cell centre (cx, cy): facade segments into all (4 doubles), objects into box
   (u0 v0 u1 v1 top), the cell rectangle grown by *margin into cell (4 CCW corners; a larger cell sees more,
   conservative, and is never degenerate). Returns the facades' largest coordinate magnitude, at least 1. */
PVS__STATIC double pvs__ot25_input(const pvs_visibility_25d_desc *desc, double cx, double cy, double *all, double *box,
								   double cell[8], double *margin) {
	double ext = 1.0, hx, hy;
	uint32_t i, k;
	for (i = 0; i < desc->facade_count; ++i) {
		const float *f = desc->facades + 5 * (size_t)i;
		double *o = all + 4 * (size_t)i;
		o[0] = (double)f[0] - cx; o[1] = (double)f[1] - cy; o[2] = (double)f[2] - cx; o[3] = (double)f[3] - cy;
		for (k = 0; k < 4; ++k) if (fabs(o[k]) > ext) ext = fabs(o[k]);
	}
	for (i = 0; i < desc->object_count; ++i) {
		for (k = 0; k < 4; ++k) box[5 * i + k] = (double)desc->objects[5 * i + k] - (k & 1 ? cy : cx);
		box[5 * i + 4] = desc->objects[5 * i + 4];
	}
	*margin = 1e-6 * ext + 1e-4;
	hx = 0.5 * ((double)desc->cell_max[0] - desc->cell_min[0]) + *margin;
	hy = 0.5 * ((double)desc->cell_max[1] - desc->cell_min[1]) + *margin;
	cell[0] = -hx; cell[1] = -hy; cell[2] = hx; cell[3] = -hy; cell[4] = hx; cell[5] = hy; cell[6] = -hx; cell[7] = hy;
	return ext;
}

/* Root region of a fresh tree for source edge a-b (cell centred at the origin): the lines crossing the edge,
   bounded by its ends' planes (blockers' edges on them are then marked, §4.10.1, not re-added per branch), then
   pvs__ot25_presplit. Lines missing the edge are never asked about. Out of memory sets t->oom. */
PVS__STATIC void pvs__ot25_root(pvs__otree *t, const double *cell, const double a[2], const double b[2]) {
	double m[2], m2[2], l[3], sa_, sb_;
	uint32_t pos;
	m[0] = 0.5 * (a[0] + b[0]); m[1] = 0.5 * (a[1] + b[1]);
	m2[0] = 2.0 * m[0]; m2[1] = 2.0 * m[1]; /* the cell is centred at the origin: m points outward */
	pvs__ot_line(m, m2, l);
	sa_ = pvs__ot_side(l, a);
	sb_ = pvs__ot_side(l, b);
	pos = pvs__ot_split_leaf(t, 0, a, sa_);
	if (pos != PVS__OT_NONE) pos = pvs__ot_split_leaf(t, pos, b, sb_);
	if (pos != PVS__OT_NONE) {
		double pts[PVS__OT25_PRESPLIT][2], dd = 10.0 * (cell[4] - cell[0] + cell[5] - cell[1]) + 1.0;
		double nx = m[0], ny = m[1], nl = sqrt(nx * nx + ny * ny);
		int q;
		nx /= nl; ny /= nl;
		for (q = 0; q < PVS__OT25_PRESPLIT; ++q) {
			double th = (-80.0 + 160.0 * (q + 0.5) / PVS__OT25_PRESPLIT) * (3.14159265358979323846 / 180.0),
				   tt = dd * tan(th);
			pts[q][0] = m[0] + nx * dd - ny * tt;
			pts[q][1] = m[1] + ny * dd + nx * tt;
		}
		pvs__ot25_presplit(t, pos, m, pts, 0, PVS__OT25_PRESPLIT);
	}
	t->nodes[0].parent = PVS__OT_NONE;
	t->root_in = pos;
}

/* One tree per top edge (§7.1): the lines leaving the cell through edge `side` (corner side + 1 to corner side),
   built by sweeping `tree` (scratch: its sweep scratch); then the candidates its visible leaves left are tested
   (§7.7) into visible_objects. 0 when no object is left to decide or the tree stopped (t->oom on out of memory). */
PVS__STATIC int pvs__ot25_side(pvs__ot25_sweep *w, const pvs_kdtree *tree, void *scratch, uint32_t side,
							   pvs_word *visible_objects) {
	pvs__otree *t = w->t;
	const double *cell = w->cell, *a = cell + 2 * ((side + 1) & 3), *b = cell + 2 * side;
	uint32_t i, live = 0, no = w->desc->object_count;
	unsigned char *done = w->done;
	pvs_box src;
	for (i = 0; i < no; ++i) live += done[i] == 0 || done[i] >= 3;
	if (!live) return 0;
	t->sa[0] = a[0]; t->sa[1] = a[1]; t->sb[0] = b[0]; t->sb[1] = b[1];
	if (!pvs__ot_reset(t)) return 0;
	pvs__ot25_root(t, cell, a, b);
	if (t->oom) return 0;
	w->a = a;
	w->b = b;
	w->side = side;
	src.min[0] = (float)(w->cx + cell[0]); src.min[1] = (float)(w->cy + cell[1]); src.min[2] = w->desc->cell_top;
	src.max[0] = (float)(w->cx + cell[4]); src.max[1] = (float)(w->cy + cell[5]); src.max[2] = w->desc->cell_top;
	pvs__ot25_sweep_tree(tree, &src, (pvs__kdsweep *)scratch, w);
	if (t->node_count > w->st->nodes) w->st->nodes = (uint32_t)t->node_count;
	if (t->oom) return 0;
	for (i = 0; i < no; ++i) {
		if (done[i] != 3 + side) continue;
		if (pvs__ot25_box_visible(t, w->box + 5 * i, w->box[5 * i + 4], a, b, NULL)) {
			done[i] = 1;
			pvs_bitset_set(visible_objects, i);
		} else {
			done[i] = 0;
		}
	}
	return 1;
}

/* The 2.5D query's kD-tree over pvs_visibility_25d_boxes, through al into *out. PVS_OK or the error (in err). */
PVS__STATIC pvs_result pvs__ot25_tree(const pvs_visibility_25d_desc *desc, const pvs_allocator *al, pvs_kdtree **out,
									  pvs_error *err) {
	pvs_kdtree_desc kd;
	uint32_t nf = desc->facade_count, no = desc->object_count;
	pvs_box *boxes = (pvs_box *)pvs__alloc_array(al, (size_t)nf + no + 1, sizeof(pvs_box));
	pvs_result r;
	if (!boxes) return pvs__fail(err, PVS_ERROR_OUT_OF_MEMORY, -1, 0, "2.5D boxes");
	pvs_visibility_25d_boxes(desc->facades, nf, desc->objects, no, boxes);
	memset(&kd, 0, sizeof(kd));
	kd.boxes = boxes;
	kd.count = nf + no;
	kd.allocator = *al;
	r = pvs_kdtree_create(&kd, out, err);
	pvs__free_array(al, boxes, (size_t)nf + no + 1, sizeof(pvs_box));
	return r;
}

/* Per kD node: item references in its subtree (0xffffffff where children do not follow their parent); the sweep
   tests only nodes with at least PVS__OT25_TEST_MIN. */
PVS__STATIC void pvs__ot25_refs(const pvs_kdtree *tree, uint32_t *refs) {
	uint32_t i;
	for (i = tree->node_count; i-- > 0;) { /* children follow their parent */
		const pvs__kdnode *kn = tree->nodes + i;
		if ((kn->bits & 3u) == PVS__KD_LEAF) refs[i] = kn->u.count;
		else {
			uint32_t c = kn->bits >> 2;
			refs[i] = c + 1 < tree->node_count && c > i ? refs[c] + refs[c + 1] : 0xffffffffu;
		}
	}
}

PVS_API pvs_result pvs_visibility_25d(const pvs_visibility_25d_desc *desc, pvs_word *visible_objects,
									  pvs_otree_stats *stats, pvs_error *err) {
	pvs__otree t;
	pvs_allocator al;
	double cell[8], cx, cy, ext, margin;
	double *all = NULL, *top = NULL, *seg = NULL, *box = NULL, *jd = NULL;
	unsigned char *done = NULL, *state = NULL;
	uint32_t *refs = NULL;
	void *scratch = NULL;
	pvs__buf b[9];
	int nb = 0;
	pvs_kdtree *own_tree = NULL;
	const pvs_kdtree *tree;
	uint32_t nf, no, i, side;
	pvs_result r;
	pvs_otree_stats st;
	pvs__ot25_sweep w;
	memset(&st, 0, sizeof(st));
	memset(&t, 0, sizeof(t));
	if (stats) *stats = st;
	r = pvs__ot25_check(desc, visible_objects, err);
	if (r != PVS_OK) return r;
	nf = desc->facade_count;
	no = desc->object_count;
	memset(visible_objects, 0, PVS_BITSET_WORDS(no) * sizeof(pvs_word));
	al = desc->allocator;
	t.a = &al;
	tree = desc->tree;
	if (!tree) {
		r = pvs__ot25_tree(desc, &al, &own_tree, err);
		if (r != PVS_OK) goto done;
		tree = own_tree;
	}
	PVS__BUF(b, nb, all, 4 * (size_t)nf + 4, sizeof(double));
	PVS__BUF(b, nb, seg, 4 * (size_t)nf + 4, sizeof(double));
	PVS__BUF(b, nb, top, (size_t)nf + 1, sizeof(double));
	PVS__BUF(b, nb, jd, PVS__OT25_JD * ((size_t)nf + 1), sizeof(double));
	PVS__BUF(b, nb, box, 5 * (size_t)no + 5, sizeof(double));
	PVS__BUF(b, nb, done, (size_t)no + 1, 1);
	PVS__BUF(b, nb, state, (size_t)nf + 1, 1);
	PVS__BUF(b, nb, scratch, pvs_kdtree_sweep_scratch_size(tree), 1);
	PVS__BUF(b, nb, refs, (size_t)tree->node_count + 1, sizeof(uint32_t));
	if (!pvs__bufs_alloc(&al, b, nb)) {
		r = pvs__fail(err, PVS_ERROR_OUT_OF_MEMORY, -1, 0, "2.5D visibility arrays");
		goto done;
	}
	memset(state, 0, (size_t)nf + 1);
	cx = 0.5 * ((double)desc->cell_min[0] + desc->cell_max[0]);
	cy = 0.5 * ((double)desc->cell_min[1] + desc->cell_max[1]);
	ext = pvs__ot25_input(desc, cx, cy, all, box, cell, &margin);
	t.len_eps = 1e-9 * ext;
	t.full_tests = (desc->flags & PVS__VISIBILITY_25D_FULL_TESTS) != 0;
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
	w.budget = desc->node_budget ? desc->node_budget : PVS_OTREE_25D_BUDGET;
	w.st = &st;
	w.refs = refs;
	w.test_min = PVS__OT25_TEST_MIN;
	pvs__ot25_refs(tree, refs);
	t.corners = cell;
	for (side = 0; side < 4 && !t.oom; ++side)
		if (!pvs__ot25_side(&w, tree, scratch, side, visible_objects)) break;
	if (t.oom) { r = pvs__fail(err, PVS_ERROR_OUT_OF_MEMORY, -1, 0, "occlusion tree nodes"); goto done; }
	if (stats) *stats = st;
	pvs__ok(err);
done:
	pvs__ot_free(&t);
	pvs__bufs_free(&al, b, nb);
	pvs_kdtree_destroy(own_tree);
	return r;
}

PVS_API void pvs_visibility_25d_boxes(const float *facades, uint32_t facade_count, const float *objects,
									  uint32_t object_count, pvs_box *boxes) {
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

/* The tree of §4.7 (Chin and Feiner's SVBSP, App. C.1.4) in eye space: inner nodes are planes through the eye (unit
   normal, child[1] positive) from occluder edges; an in-leaf keeps the occluder fragment blocking its pyramid of
   rays. Polygon edges carry their plane's unit normal (polygon on the positive side) and a mark (§4.10.1).

   Conservative rounding: an in-leaf's region is an intersection of exact stored planes from the occluder's edges or
   the path, so each of its rays meets the occluder; insertion may drop slivers below its tolerance, never claim
   more. Tests widen: a box descends every side it reaches within `tol` (1e-10 of the eye-relative scene size, far
   above a unit-normal dot product's error), and is behind a fragment or apart from its pyramid only beyond the
   fragment's tolerance. A box test takes each plane at the corner its normal's signs pick, with the same operations
   for every box: monotone in the box, so a hidden node's child never tests visible and hierarchy updating is exact
   (§4.11.4). */

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

/* A fragment: the occluder's plane (n.x + d > 0 on the eye's side), its vertices f and the inward normals m of the
   pyramid faces (0, f_i, f_i+1). */
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
/* Largest / smallest n.x over box [lo, hi], at the corner the signs pick: monotone in the box. */
PVS__STATIC double pvs__sv_hi(const double n[3], const double lo[3], const double hi[3]) {
	return (n[0] * (n[0] >= 0.0 ? hi[0] : lo[0]) + n[1] * (n[1] >= 0.0 ? hi[1] : lo[1])) +
		n[2] * (n[2] >= 0.0 ? hi[2] : lo[2]);
}
PVS__STATIC double pvs__sv_lo(const double n[3], const double lo[3], const double hi[3]) {
	return (n[0] * (n[0] >= 0.0 ? lo[0] : hi[0]) + n[1] * (n[1] >= 0.0 ? lo[1] : hi[1])) +
		n[2] * (n[2] >= 0.0 ? lo[2] : hi[2]);
}

/* Keeps the part of `in` where n.x + d >= 0; the new edge gets plane `en` (through the eye; NULL: the
   plane through the eye and the new edge) and `mark`. Returns the vertex count (0 empty, -1 too many). */
PVS__STATIC int pvs__sv_clip(const pvs__svpoly *in, const double n[3], double d, const double *en, int mark,
							 pvs__svpoly *out) {
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

/* Points p (n <= PVS__SV_MAXV) relative to the eye into v, their mean into c, Newell's normal (twice the area
   vector) into nrm. */
PVS__STATIC void pvs__sv_eye_points(const pvs_otree *o, const float *const *p, int n, double (*v)[3], double c[3],
									double nrm[3]) {
	int i, k;
	for (k = 0; k < 3; ++k) c[k] = nrm[k] = 0.0;
	for (i = 0; i < n; ++i)
		for (k = 0; k < 3; ++k) { v[i][k] = (double)p[i][k] - o->eye[k]; c[k] += v[i][k] / n; }
	for (i = 0; i < n; ++i) {
		const double *u = v[i], *w = v[(i + 1) % n];
		nrm[0] += (u[1] - w[1]) * (u[2] + w[2]);
		nrm[1] += (u[2] - w[2]) * (u[0] + w[0]);
		nrm[2] += (u[0] - w[0]) * (u[1] + w[1]);
	}
}

PVS__STATIC int pvs__sv_same(const double a[3], const double b[3]) {
	return a[0] == b[0] && a[1] == b[1] && a[2] == b[2];
}

/* The eye-space polygon of occluder points p (planar, convex) with its plane and edge planes, clipped to the
   frustum (less occluder: conservative); 0 when nothing usable is left (edge-on, behind the eye, outside). */
PVS__STATIC int pvs__sv_polygon(pvs_otree *o, const float *const *p, int n, pvs__svpoly *q, double plane[4]) {
	pvs__svpoly a, b;
	double c[3], nrm[3], len, size = 0.0;
	int i, k;
	a.n = n;
	pvs__sv_eye_points(o, p, n, a.v, c, nrm);
	for (i = 0; i < n; ++i)
		for (k = 0; k < 3; ++k)
			if (fabs(a.v[i][k]) > size) size = fabs(a.v[i][k]);
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

/* As pvs__ot_refine, for q's pyramid (§4.10.1). PVS__OT_NONE when the node budget is spent (the leaf
   unchanged). */
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

/* Merges occluder polygon q into the tree (§3.3.3, App. C.1.4): filtered down with splitting and edge marking;
   out-leaves become its e-OT; at an in-leaf it replaces the stored fragment where it lies in front (the approximate
   sweep may insert a nearer occluder late). */
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
			} else { /* the positive part, then the negative one */
				double nf[2][3];
				pvs__svpoly qq = *q;
				for (i = 0; i < 3; ++i) { nf[1][i] = nd->n[i]; nf[0][i] = -nd->n[i]; }
				for (i = 1; i >= 0; --i) {
					int r = pvs__sv_clip(&qq, nf[i], 0.0, nf[i], 1, &part);
					if (r < 0 || (r >= 3 && sp >= PVS__SV_STACK)) o->info.budget_exceeded = 1;
					if (r >= 3 && sp < PVS__SV_STACK) { o->stack[sp] = part; o->stack_node[sp++] = nd->child[i]; }
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
			if (leaf == PVS__OT_NONE) {
				o->info.budget_exceeded = 1;
				--o->frag_count;
				o->vert_count -= (uint32_t)use->n;
				continue;
			}
			o->nodes[leaf].kind = PVS__OT_IN;
			o->nodes[leaf].frag = fr;
		}
	}
}

/* The least and the largest of 0 (the eye) and n . f over the count points v. */
PVS__STATIC void pvs__sv_extent(const pvs__svvert *v, uint32_t count, const double n[3], double *plo, double *phi) {
	uint32_t m;
	*plo = *phi = 0.0;
	for (m = 0; m < count; ++m) {
		double d = pvs__sv_dot(n, v[m].f);
		if (d < *plo) *plo = d;
		if (d > *phi) *phi = d;
	}
}

/* Box [lo, hi] (eye-relative) against in-leaf fragment f (§4.10.2): invisible when wholly behind the
   occluder's plane or (unless PLANE_ONLY) apart from the pyramid eye + fragment, the only place it can
   be seen through this leaf (exact test "E"); visible when wholly in front; else partly visible. */
PVS__STATIC uint32_t pvs__sv_leaf_test(const pvs_otree *o, const pvs__svfrag *f, const double lo[3],
									   const double hi[3]) {
	const pvs__svvert *v = o->verts + f->first;
	double smin = pvs__sv_lo(f->plane, lo, hi) + f->plane[3], smax = pvs__sv_hi(f->plane, lo, hi) + f->plane[3],
		   t = f->tol;
	uint32_t i;
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
			double plo, phi, bh = pvs__sv_hi(v[i].m, lo, hi);
			pvs__sv_extent(v, f->count, v[i].m, &plo, &phi);
			if (bh < -t ? bh < plo - t : pvs__sv_lo(v[i].m, lo, hi) > phi + t) return PVS__SV_I;
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
				double edge[3], ax[3], plo, phi, len;
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
				pvs__sv_extent(v, f->count, ax, &plo, &phi);
				if (pvs__sv_hi(ax, lo, hi) < plo - t || pvs__sv_lo(ax, lo, hi) > phi + t) return PVS__SV_I;
			}
	}
	return smin > t ? PVS__SV_V : PVS__SV_P;
}

/* Box [lo, hi] in the tree (§4.10.2): descends, without splitting, every side it reaches; leaves
   combine by Table 3.1, stopping at the first partly visible result. */
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

/* A box's visibility: the frustum first (outside a plane: invisible; crossing one: at most partly
   visible), then the tree. */
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

/* Top-k by key (pvs__topk_offer: the root is the weakest kept). */
PVS__STATIC int pvs__svsel_better(const void *a, const void *b) {
	return ((const pvs__svsel *)a)->key > ((const pvs__svsel *)b)->key;
}
PVS__STATIC void pvs__sv_offer(pvs_otree *o, uint32_t k, double key, uint32_t a, uint32_t b) {
	pvs__svsel e;
	e.key = key;
	e.a = a;
	e.b = b;
	pvs__topk_offer(o->sel, &o->sel_count, k, sizeof(e), &e, pvs__svsel_better);
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
			static const uint8_t f[6][4] = {{0, 2, 6, 4}, {1, 5, 7, 3}, {0, 4, 5, 1},
											{2, 3, 7, 6}, {0, 1, 3, 2}, {4, 6, 7, 5}};
			for (n = 0; n < 4; ++n)
				for (k = 0; k < 3; ++k) q[n][k] = (f[b][n] >> k) & 1u ? oc->box.max[k] : oc->box.min[k];
		} else {
			int u, v;
			pvs__ground_axes(s->up_axis, &u, &v);
			pvs__wall_quad(oc, b, u, v, (int)s->up_axis, q);
		}
		for (n = 0; n < 4; ++n) p[n] = q[n];
		return 4;
	}
}

/* Area-angle measure M = A |N . V| / |D|^2 (§4.5), V the unit direction from the eye to the centre D
   (about the solid angle; the thesis uses the view direction); -1 when wholly outside the frustum. */
PVS__STATIC double pvs__sv_score(const pvs_otree *o, const float *const *p, int n) {
	double v[4][3], c[3], area[3], dd;
	int i, k;
	pvs__sv_eye_points(o, p, n, v, c, area);
	for (k = 0; k < 5; ++k) {
		for (i = 0; i < n; ++i) if (pvs__sv_dot(o->fr[k], v[i]) + o->fr[k][3] >= 0.0) break;
		if (i == n) return -1.0;
	}
	dd = pvs__sv_dot(c, c);
	if (!(dd > 0.0)) return -1.0;
	return 0.5 * fabs(pvs__sv_dot(area, c)) / (dd * sqrt(dd));
}

/* (key, a, b) ascending: a deterministic order whatever the heap held. */
PVS__STATIC int pvs__sv_before(const void *pa, const void *pb) {
	const pvs__svsel *x = (const pvs__svsel *)pa, *y = (const pvs__svsel *)pb;
	return x->key < y->key || (x->key == y->key && (x->a < y->a || (x->a == y->a && x->b < y->b)));
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
PVS__STATIC pvs_visit pvs__sv_boot_visit(void *user, const pvs_box *node_box, float distance, const uint32_t *items,
										 uint32_t count) {
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

/* The boxes of kD node nd's children within its box (the split clamped to it). */
PVS__STATIC void pvs__sv_child_boxes(const pvs__kdnode *nd, const pvs_box *box, pvs_box c[2]) {
	uint32_t axis = nd->bits & 3u;
	float sp = nd->u.split;
	c[0] = *box;
	c[1] = *box;
	c[0].max[axis] = sp < box->max[axis] ? (sp > box->min[axis] ? sp : box->min[axis]) : box->max[axis];
	c[1].min[axis] = sp > box->min[axis] ? (sp < box->max[axis] ? sp : box->max[axis]) : box->min[axis];
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
		pvs_box c[2];
		pvs__sv_child_boxes(nd, box, c);
		pvs__sv_emit(o, nd->bits >> 2, c, flag);
		pvs__sv_emit(o, (nd->bits >> 2) + 1, c + 1, flag);
	}
}

/* Fig. 4.5: last frame's termination nodes (leaves, nodes not partly visible or not visited last
   frame) are tested; opened nodes are skipped and their children visited, near child first; a node
   whose children agree takes their state (pull-up). */
PVS__STATIC void pvs__sv_walk(pvs_otree *o, uint32_t node, const pvs_box *box) {
	const pvs_kdtree *t = o->s->object_tree;
	const pvs__kdnode *nd = t->nodes + node;
	uint32_t axis = nd->bits & 3u, st = o->kd_vis[node];
	++o->st.nodes_visited;
	if ((o->flags & PVS_OTREE_NO_COHERENCE) || axis == PVS__KD_LEAF || st != PVS__SV_P ||
		o->kd_frame[node] + 1 < o->frame) {
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
			uint32_t first = o->eye[axis] < (double)nd->u.split ? 0u : 1u, ch = nd->bits >> 2, v0, v1;
			pvs__sv_child_boxes(nd, box, c);
			pvs__sv_walk(o, ch + first, c + first); /* front to back */
			pvs__sv_walk(o, ch + (1u - first), c + (1u - first));
			v0 = o->kd_vis[ch];
			v1 = o->kd_vis[ch + 1];
			if (v0 == v1 && v0 != PVS__SV_P) o->kd_vis[node] = (uint8_t)v0;
		}
	}
}

/* ---- context and per-frame API ---- */

/* The context's buffers (pvs__buf), sized by its budgets. */
PVS__STATIC int pvs__sv_bufs(pvs_otree *o, pvs__buf *b) {
	int k = 0;
	size_t no = (size_t)o->max_objects + 1, nk = (size_t)o->max_kd_nodes + 1;
	PVS__BUF(b, k, o->nodes, o->node_budget, sizeof(pvs__svnode));
	PVS__BUF(b, k, o->frags, o->frag_budget, sizeof(pvs__svfrag));
	PVS__BUF(b, k, o->verts, o->vert_budget, sizeof(pvs__svvert));
	PVS__BUF(b, k, o->stack, PVS__SV_STACK, sizeof(pvs__svpoly));
	PVS__BUF(b, k, o->stack_node, PVS__SV_STACK, sizeof(uint32_t));
	PVS__BUF(b, k, o->tstack, (size_t)o->node_budget + 2, sizeof(uint32_t));
	PVS__BUF(b, k, o->sel, o->max_occluders, sizeof(pvs__svsel));
	PVS__BUF(b, k, o->prev, o->max_occluders, sizeof(uint32_t));
	PVS__BUF(b, k, o->sweep, o->sweep_size, 1);
	PVS__BUF(b, k, o->tri_seen, PVS_BITSET_WORDS(o->max_triangles) + 1, sizeof(pvs_word));
	PVS__BUF(b, k, o->obj_first, no, sizeof(uint32_t));
	PVS__BUF(b, k, o->obj_tris, no, sizeof(uint32_t));
	PVS__BUF(b, k, o->kd_vis, nk, 1);
	PVS__BUF(b, k, o->kd_frame, nk, sizeof(uint32_t));
	PVS__BUF(b, k, o->obj_flag, no, 1);
	PVS__BUF(b, k, o->touched, no, sizeof(uint32_t));
	return k;
}

PVS_API void pvs_otree_destroy(pvs_otree *o) {
	pvs_allocator a;
	pvs__buf b[16];
	if (!o) return;
	a = o->allocator;
	pvs__bufs_free(&a, b, pvs__sv_bufs(o, b));
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
	if (!desc || !out || !desc->scene)
		return pvs__fail(err, PVS_ERROR_INVALID_ARGUMENT, -1, 0, "desc, desc->scene and out_otree must not be NULL");
	if (!pvs__finite(desc->aspect) || desc->aspect < 0.0f)
		return pvs__fail(err, PVS_ERROR_NOT_FINITE, -1, 0, "aspect must be finite and >= 0");
	if (desc->max_occluders > 65536)
		return pvs__fail(err, PVS_ERROR_INVALID_ARGUMENT, -1, 0, "max_occluders %u is over 65536", desc->max_occluders);
	if (desc->node_budget && (desc->node_budget < 64 || desc->node_budget > (1u << 24)))
		return pvs__fail(err, PVS_ERROR_INVALID_ARGUMENT, -1, 0, "node_budget %u is not in 64..2^24",
						 desc->node_budget);
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
	if (!o->sweep_size) o->sweep_size = 16;
	{
		pvs__buf b[16];
		if (!pvs__bufs_alloc(&a, b, pvs__sv_bufs(o, b))) {
			pvs_otree_destroy(o);
			return pvs__fail(err, PVS_ERROR_OUT_OF_MEMORY, -1, 0, "otree buffers");
		}
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

/* Starts a frame on s. A new scene, or a frame counter about to wrap, makes every kD node's state
   stale; a new scene also rebuilds the per-object triangle ranges and forgets last frame's occluders. */
PVS__STATIC void pvs__sv_frame_begin(pvs_otree *o, const pvs_scene *s) {
	uint32_t i;
	if (s != o->last_scene || o->frame > 0xfffffff0u) {
		memset(o->kd_frame, 0, ((size_t)o->max_kd_nodes + 1) * sizeof(uint32_t));
		o->frame = 2;
		if (s != o->last_scene) o->have_prev = 0;
		if (s != o->ranges_scene) {
			o->ranges_scene = s;
			for (i = 0; i < s->object_count; ++i) { o->obj_first[i] = 0; o->obj_tris[i] = 0; }
			for (i = s->triangle_count; i-- > 0;) {
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
}

/* The eye frame (as pvs_camera_matrix), the frustum's planes (near, then the four sides; unit normals
   inward) and o->tol from the eye-relative scene size. */
PVS__STATIC void pvs__sv_frustum(pvs_otree *o, const pvs_scene *s, const pvs_camera *cam) {
	double u[3], r[3], len, ty, tx, size = 0.0;
	uint32_t k;
	int j;
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
	for (j = 0; j < 3; ++j) {
		double a = fabs((double)s->bounds.min[j] - o->eye[j]), b = fabs((double)s->bounds.max[j] - o->eye[j]);
		if (s->bounds.min[j] > s->bounds.max[j]) a = b = 0.0;
		size += (a > b ? a : b);
	}
	o->tol = 1e-10 * (size + o->near_d + 1e-20);
}

/* Inserts the caller's triangles (p->occluder_*) in their order, skipping those with an index or a
   coordinate out of range. Returns the triangles offered. */
PVS__STATIC uint32_t pvs__sv_caller_occluders(pvs_otree *o, const pvs_cull_params *p) {
	uint32_t i, nocc = 0;
	int j;
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
	return nocc;
}

/* Occluder selection (§4.5) and insertion: the best polygons by area-angle among last frame's triangles (after a
   reset: the scene's, swept from the eye) and, with p->scene_volumes, occluder-volume faces within the distance,
   inserted nearest first (the approximate occlusion sweep, §3.2). Returns the polygons offered. */
PVS__STATIC uint32_t pvs__sv_scene_occluders(pvs_otree *o, const pvs_scene *s, const pvs_camera *cam,
											 const pvs_cull_params *p) {
	uint32_t i, kk = p->scene_occluders < o->max_occluders ? p->scene_occluders : o->max_occluders;
	pvs_box src;
	int j;
	if (p->scene_volumes) kk = o->max_occluders;
	for (j = 0; j < 3; ++j) src.min[j] = src.max[j] = cam->eye[j];
	if (p->scene_occluders) {
		if (o->have_prev) {
			for (i = 0; i < o->prev_count; ++i)
				if (o->prev[i] < s->triangle_count) pvs__sv_offer_triangle(o, kk, o->prev[i]);
		} else {
			pvs__svboot w;
			w.o = o;
			w.k = kk;
			memset(o->tri_seen, 0, PVS_BITSET_WORDS(s->triangle_count) * sizeof(pvs_word));
			pvs_kdtree_sweep(s->triangle_tree, &src, o->sweep, o->sweep_size, pvs__sv_boot_visit, &w);
		}
	}
	if (p->scene_volumes)
		for (i = 0; i < s->occluder_count; ++i) {
			const pvs_occluder_desc *oc = s->occluders + i;
			uint32_t faces = oc->kind == PVS_OCCLUDER_BOX ? 6u
				: oc->kind == PVS_OCCLUDER_EXTRUSION      ? oc->footprint_count
														  : 0u,
					 f;
			if (!faces || pvs__box_distance2(&src, s->occluder_boxes + i) > o->lambda * o->lambda) continue;
			for (f = 0; f < faces; ++f) {
				float q[4][3];
				const float *pt[4];
				int n = pvs__sv_points(s, i, f, q, pt);
				double sc = pvs__sv_score(o, pt, n);
				if (sc > 0.0) pvs__sv_offer(o, kk, sc, i, f);
			}
		}
	for (i = 0; i < o->sel_count; ++i) {
		float q[4][3];
		const float *pt[4];
		double v[4][3], c[3], nrm[3];
		int n = pvs__sv_points(s, o->sel[i].a, o->sel[i].b, q, pt);
		pvs__sv_eye_points(o, pt, n, v, c, nrm);
		o->sel[i].key = pvs__sv_dot(c, c);
	}
	pvs__heap_sort(o->sel, o->sel_count, sizeof(pvs__svsel), pvs__sv_before);
	for (i = 0; i < o->sel_count; ++i) {
		float q4[4][3];
		const float *pt[4];
		pvs__svpoly q;
		double plane[4];
		int n = pvs__sv_points(s, o->sel[i].a, o->sel[i].b, q4, pt);
		if (pvs__sv_polygon(o, pt, n, &q, plane)) pvs__sv_insert(o, &q, plane);
	}
	return o->sel_count;
}

/* The next frame's occluder candidates (§4.5), into o->prev: the triangles of the objects seen within
   the distance this frame (occluder-only objects: whose box may be seen). */
PVS__STATIC void pvs__sv_next_occluders(pvs_otree *o, const pvs_scene *s, const pvs_cull_params *p,
										const pvs_word *visible) {
	uint32_t i, kk = p->scene_occluders < o->max_occluders ? p->scene_occluders : o->max_occluders;
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

PVS_API pvs_result pvs_otree_cull(pvs_otree *o, const pvs_scene *s, const pvs_camera *cam, const pvs_cull_params *p,
								  pvs_word *visible, pvs_cull_stats *stats, pvs_error *err) {
	float m[16];
	uint32_t i, nocc = 0;
	pvs_result res;
	if (!o || !s || !cam || !visible)
		return pvs__fail(err, PVS_ERROR_INVALID_ARGUMENT, -1, 0, "otree, scene, camera and visible must not be NULL");
	if (s->object_count > o->max_objects || s->triangle_count > o->max_triangles ||
		s->object_tree->node_count > o->max_kd_nodes || pvs_kdtree_sweep_scratch_size(s->triangle_tree) > o->sweep_size)
		return pvs__fail(err, PVS_ERROR_BUFFER_TOO_SMALL, -1, 0, "the context was created for a smaller scene");
	res = pvs_camera_matrix(cam, o->aspect, m);
	if (res != PVS_OK) return pvs__fail(err, res, -1, 0, "unusable camera");
	if (cam->fov_y == 0.0f)
		return pvs__fail(err, PVS_ERROR_UNSUPPORTED, -1, 0, "an orthographic camera: shadow volumes need an eye point");
	memset(&o->info, 0, sizeof(o->info));
	memset(&o->st, 0, sizeof(o->st));
	memset(visible, 0, PVS_BITSET_WORDS(s->object_count) * sizeof(pvs_word));
	pvs__sv_frame_begin(o, s);
	pvs__sv_frustum(o, s, cam);
	o->lambda = p && p->occluder_distance > 0.0f ? p->occluder_distance : 100.0;
	/* the tree: one out-leaf, then the occluders front to back (§4.3) */
	o->node_count = 1;
	o->frag_count = 0;
	o->vert_count = 0;
	memset(o->nodes, 0, sizeof(pvs__svnode));
	o->nodes[0].kind = PVS__OT_OUT;
	if (p && p->occluder_triangle_count && p->occluder_positions) nocc += pvs__sv_caller_occluders(o, p);
	o->sel_count = 0;
	if (p && (p->scene_occluders || p->scene_volumes)) nocc += pvs__sv_scene_occluders(o, s, cam, p);
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
		if ((s->object_flags[ob] & PVS_OBJECT_OCCLUDER_ONLY) ||
			(p && p->candidates && !pvs_bitset_test(p->candidates, ob)))
			continue;
		if (!(fl & 1u)) {
			++o->info.object_tests;
			++o->st.boxes_tested;
			if (pvs__sv_box_test(o, s->object_boxes + ob) == PVS__SV_I) continue;
		}
		pvs_bitset_set(visible, ob);
		++o->st.visible;
	}
	if (p && p->scene_occluders) pvs__sv_next_occluders(o, s, p, visible);
	for (i = 0; i < o->touched_count; ++i) o->obj_flag[o->touched[i]] = 0;
	if (stats) *stats = o->st;
	pvs__ok(err);
	return PVS_OK;
}

/* ---- the OTREE bake method (a row of >>bake's table) ---- */

/* The OTREE method's per-bake state. */
typedef struct pvs__otree_bake {
	pvs_allocator allocator;
	uint32_t object_count;
	uint32_t budget;           /* pvs_visibility_25d_desc.node_budget (0 = its default) */
	float *facades;            /* facade_count x (u0 v0 u1 v1 top), by level */
	uint32_t facade_count, facade_cap, vertical, level_count;
	float level[PVS__OT25_LEVELS];        /* base heights, ascending */
	uint32_t level_end[PVS__OT25_LEVELS]; /* the facades of levels <= k: [0, level_end[k]) */
	float *objects;            /* object_count x (umin vmin umax vmax top) */
	pvs_kdtree *tree[PVS__OT25_LEVELS];   /* per level, over pvs_visibility_25d_boxes */
} pvs__otree_bake;

/* Facades for c-LSS (§7.1) from the scene's walls (pvs__facades_extract). c-LSS takes occluders as standing on the
   ground (a ray over one's 2D line passes it only above its top); a ray's height being linear, a facade of base b
   is one for rays whose ends are no lower than b: from a cell of bottom c to an object of bottom o, those with b <=
   min(c, o). Bases merge into at most PVS__OT25_LEVELS levels (a facade joins the lowest at or above its base:
   conservative); level k's kD-tree holds the objects and the facades of levels <= k. */
PVS__STATIC pvs_result pvs__otree_prepare(pvs__otree_bake *ot, const pvs_scene *s, const pvs_box *cells,
										  uint32_t cell_count) {
	int up = s->up_axis == 2 ? 2 : 1, u, v;
	float *fac = NULL, maxc = -FLT_MAX;
	size_t fac_floats = 0;
	uint32_t n = 0, i, k, nl = 0, m = 0, total;
	pvs__key_index *ord = NULL;
	pvs_result r;
	pvs__ground_axes((uint32_t)up, &u, &v);
	r = pvs__facades_extract(s, &ot->allocator, &fac, &fac_floats, &n, &ot->vertical);
	if (r != PVS_OK) return r;
	r = PVS_ERROR_OUT_OF_MEMORY;
	total = n;
	ot->facade_cap = n;
	ot->facades = (float *)pvs__alloc_array(&ot->allocator, (size_t)n * 5 + 5, sizeof(float));
	ot->objects = (float *)pvs__alloc_array(&ot->allocator, (size_t)ot->object_count * 5 + 5, sizeof(float));
	ord = (pvs__key_index *)pvs__alloc_array(&ot->allocator, (size_t)n + 1, sizeof(pvs__key_index));
	if (!ot->facades || !ot->objects || !ord) goto done;
	/* only facades some cell can use: base <= the highest cell bottom of the whole bake (shards agree) */
	for (i = 0; i < cell_count; ++i)
		if (i == 0 || cells[i].min[up] > maxc) maxc = cells[i].min[up];
	for (i = 0; i < n; ++i) {
		const float *f = fac + 6 * (size_t)i;
		if (!(f[5] <= maxc)) continue;
		ord[m].key = f[5];
		ord[m].index = i;
		++m;
	}
	pvs__key_index_sort(ord, m); /* by base, then extraction order */
	/* the levels: the PVS__OT25_LEVELS distinct bases holding the most wall area (ties: the lower) */
	{
		double area[PVS__OT25_LEVELS];
		float cand[PVS__OT25_LEVELS];
		uint32_t nc = 0, j;
		for (i = 0; i < m;) {
			float base = (float)ord[i].key;
			double sum = 0.0;
			for (j = i; j < m && (float)ord[j].key == base; ++j) {
				const float *f = fac + 6 * (size_t)ord[j].index;
				double dx = (double)f[2] - f[0], dy = (double)f[3] - f[1];
				sum += sqrt(dx * dx + dy * dy) * ((double)f[4] - f[5]);
			}
			i = j;
			if (nc < PVS__OT25_LEVELS) { cand[nc] = base; area[nc] = sum; ++nc; continue; }
			for (j = 0, k = 1; k < nc; ++k) if (area[k] < area[j] || (area[k] == area[j] && cand[k] > cand[j])) j = k;
			if (sum > area[j]) { cand[j] = base; area[j] = sum; }
		}
		for (i = 0; i < nc; ++i) { /* ascending */
			for (j = i + 1; j < nc; ++j)
				if (cand[j] < cand[i]) {
					float tf = cand[i];
					double ta = area[i];
					cand[i] = cand[j];
					area[i] = area[j];
					cand[j] = tf;
					area[j] = ta;
				}
			ot->level[i] = cand[i];
		}
		nl = nc;
	}
	ot->level_count = nl;
	/* facades by level, 5 floats each; those above the highest level are left out */
	for (i = 0, k = 0, n = 0; i < m && k < nl; ++i) {
		const float *f = fac + 6 * (size_t)ord[i].index;
		while (k < nl && ot->level[k] < f[5]) ot->level_end[k++] = n;
		if (k == nl) break;
		memcpy(ot->facades + 5 * (size_t)n++, f, 5 * sizeof(float));
	}
	for (; k < nl; ++k) ot->level_end[k] = n;
	ot->facade_count = n;
	for (i = 0; i < ot->object_count; ++i) {
		const pvs_box *bx = s->object_boxes + i;
		float *o = ot->objects + 5 * (size_t)i;
		o[0] = bx->min[u]; o[1] = bx->min[v]; o[2] = bx->max[u]; o[3] = bx->max[v]; o[4] = bx->max[up];
		if (bx->min[0] > bx->max[0] || (s->object_flags[i] & PVS_OBJECT_OCCLUDER_ONLY)) {
			o[0] = 1.0f;
			o[2] = 0.0f;
		} /* never visible */
	}
	for (k = 0; k < nl; ++k) { /* level k's tree, as pvs_visibility_25d would build it */
		pvs_visibility_25d_desc d;
		memset(&d, 0, sizeof(d));
		d.facades = ot->facades;
		d.facade_count = ot->level_end[k];
		d.objects = ot->objects;
		d.object_count = ot->object_count;
		r = pvs__ot25_tree(&d, &ot->allocator, &ot->tree[k], NULL);
		if (r != PVS_OK) goto done;
	}
	r = PVS_OK;
done:
	pvs__free(&ot->allocator, fac, fac_floats * sizeof(float), 16);
	pvs__free_array(&ot->allocator, ord, (size_t)total + 1, sizeof(pvs__key_index));
	return r;
}

/* A cell (or its adaptive part c): pvs_visibility_25d once per level some object needs, testing the objects with
   min(cell bottom, object bottom) in [level k, level k + 1) against the facades of levels <= k; objects below the
   lowest level are visible. May add PVS__BAKE_NO_OCCLUDERS and PVS__BAKE_OTREE_BUDGET to *flags. */
PVS__STATIC pvs_result pvs__otree_cell(const pvs__otree_bake *ot, const pvs_scene *s, const pvs_box *c, uint32_t cell,
									   pvs_word *bits, unsigned *flags, pvs_error *err) {
	pvs_otree_stats st;
	int up = s->up_axis == 2 ? 2 : 1, u, v;
	pvs_visibility_25d_desc d;
	float *own = NULL;
	pvs_word *part = NULL;
	unsigned char *grp = NULL;
	uint32_t i, k, no = ot->object_count, used = 0, below = 0;
	pvs_result r = PVS_OK;
	pvs__ground_axes((uint32_t)up, &u, &v);
	memset(&d, 0, sizeof(d));
	d.cell_min[0] = c->min[u]; d.cell_min[1] = c->min[v];
	d.cell_max[0] = c->max[u]; d.cell_max[1] = c->max[v];
	d.cell_top = c->max[up];
	d.allocator = ot->allocator;
	d.node_budget = ot->budget;
	grp = (unsigned char *)pvs__alloc_array(&ot->allocator, (size_t)no + 1, 1);
	if (!grp) return pvs__fail(err, PVS_ERROR_OUT_OF_MEMORY, cell, 0, "cell %u object levels", cell);
	for (i = 0; i < no; ++i) { /* the level of each drawable object: the highest one at or below its floor */
		float fl = s->object_boxes[i].min[up];
		if (c->min[up] < fl) fl = c->min[up];
		grp[i] = 0xff;
		if (ot->objects[5 * (size_t)i] > ot->objects[5 * (size_t)i + 2]) continue; /* never visible */
		for (k = ot->level_count; k-- > 0;)
			if (ot->level[k] <= fl) { grp[i] = (unsigned char)k; used |= 1u << k; break; }
		if (grp[i] == 0xff) { pvs_bitset_set(bits, i); below = 1; } /* below every facade's base: seen under them */
	}
	if (!used) *flags |= PVS__BAKE_NO_OCCLUDERS; /* no object had a facade to be hidden by */
	for (k = 0; k < ot->level_count && r == PVS_OK; ++k) {
		if (!(used & (1u << k))) continue;
		d.facades = ot->facades;
		d.facade_count = ot->level_end[k];
		d.tree = ot->tree[k];
		d.objects = ot->objects;
		d.object_count = no;
		if (used != 1u << k || below) { /* other levels' objects are left out of this run */
			if (!own) {
				own = (float *)pvs__alloc_array(&ot->allocator, (size_t)no * 5 + 5, sizeof(float));
				part = (pvs_word *)pvs__alloc_array(&ot->allocator, PVS_BITSET_WORDS(no) + 1, sizeof(pvs_word));
				if (!own || !part) {
					r = pvs__fail(err, PVS_ERROR_OUT_OF_MEMORY, cell, 0, "cell %u objects", cell);
					break;
				}
			}
			memcpy(own, ot->objects, (size_t)no * 5 * sizeof(float));
			for (i = 0; i < no; ++i)
				if (grp[i] != k) { own[5 * (size_t)i] = 1.0f; own[5 * (size_t)i + 2] = 0.0f; }
			d.objects = own;
			r = pvs_visibility_25d(&d, part, &st, err);
			if (r == PVS_OK)
				for (i = 0; i < (uint32_t)PVS_BITSET_WORDS(no); ++i) bits[i] |= part[i];
		} else {
			r = pvs_visibility_25d(&d, bits, &st, err); /* the only run, every object: into bits directly */
		}
		if (r == PVS_OK && st.budget_exceeded) *flags |= PVS__BAKE_OTREE_BUDGET;
	}
	if (own) pvs__free_array(&ot->allocator, own, (size_t)no * 5 + 5, sizeof(float));
	if (part) pvs__free_array(&ot->allocator, part, PVS_BITSET_WORDS(no) + 1, sizeof(pvs_word));
	pvs__free_array(&ot->allocator, grp, (size_t)no + 1, 1);
	if (r != PVS_OK) {
		if (err) err->index = cell;
		return r;
	}
	for (i = 0; i < no; ++i) /* occluder-only and empty objects never appear */
		if (ot->objects[5 * (size_t)i] > ot->objects[5 * (size_t)i + 2]) pvs_bitset_clear(bits, i);
	return PVS_OK;
}

PVS__STATIC void pvs__otree_bake_destroy(const pvs__bake_env *env, void *state) {
	pvs__otree_bake *ot = (pvs__otree_bake *)state;
	uint32_t k;
	(void)env;
	if (!ot) return;
	pvs__free_array(&ot->allocator, ot->facades, (size_t)ot->facade_cap * 5 + 5, sizeof(float));
	pvs__free_array(&ot->allocator, ot->objects, (size_t)ot->object_count * 5 + 5, sizeof(float));
	for (k = 0; k < PVS__OT25_LEVELS; ++k) pvs_kdtree_destroy(ot->tree[k]);
	pvs__free(&ot->allocator, ot, sizeof(*ot), 16);
}

PVS__STATIC pvs_result pvs__otree_bake_check(const pvs_bake_desc *desc, pvs_error *err) {
	if (desc->otree.node_budget && (desc->otree.node_budget < 64 || desc->otree.node_budget > (1u << 24)))
		return pvs__fail(err, PVS_ERROR_INVALID_ARGUMENT, -1, 0, "otree.node_budget %u is not in 64..2^24",
						 desc->otree.node_budget);
	return PVS_OK;
}

PVS__STATIC pvs_result pvs__otree_bake_prepare(pvs__bake_env *env, const pvs_bake_desc *desc, void **state,
											   pvs_error *err) {
	pvs__otree_bake *ot = (pvs__otree_bake *)pvs__alloc(&env->allocator, sizeof(pvs__otree_bake), 16);
	*state = ot;
	if (!ot) return pvs__fail(err, PVS_ERROR_OUT_OF_MEMORY, -1, 0, "otree facades");
	memset(ot, 0, sizeof(*ot));
	ot->allocator = env->allocator;
	ot->object_count = env->object_count;
	ot->budget = desc->otree.node_budget;
	if (pvs__otree_prepare(ot, env->scene, env->cells, env->cell_count) != PVS_OK)
		return pvs__fail(err, PVS_ERROR_OUT_OF_MEMORY, -1, 0, "otree facades");
	return PVS_OK;
}

PVS__STATIC int pvs__otree_bake_applies(const void *state, const char **why) {
	const pvs__otree_bake *ot = (const pvs__otree_bake *)state;
	*why = ot->facade_count ? "2.5D: facades (vertical walls)" : "no vertical wall gives a facade (2.5D occluder)";
	return ot->facade_count != 0;
}

PVS__STATIC pvs_result pvs__otree_bake_cell(const pvs__bake_env *env, void *state, uint32_t task, uint32_t cell,
											const pvs_box *box, const pvs_word *candidates, pvs_word *bits,
											unsigned *flags, pvs_error *err) {
	(void)task;
	(void)candidates;
	return pvs__otree_cell((const pvs__otree_bake *)state, env->scene, box, cell, bits, flags, err);
}

PVS__STATIC const pvs__bake_method pvs__otree_method = {PVS_METHOD_OTREE,
														PVS__METHOD_CONSERVATIVE | PVS__METHOD_AUTO_DEFAULT,
														2,
														pvs__otree_bake_check,
														pvs__otree_bake_prepare,
														pvs__otree_bake_applies,
														pvs__otree_bake_cell,
														NULL,
														pvs__otree_bake_destroy};

PVS_API void pvs_bake_get_otree_info(const pvs_bake *b, pvs_otree_bake_info *info) {
	const pvs__otree_bake *ot = b ? (const pvs__otree_bake *)pvs__bake_method_state(b, PVS_METHOD_OTREE) : NULL;
	memset(info, 0, sizeof(*info));
	if (!ot) return;
	info->prepared = 1;
	info->vertical_triangles = ot->vertical;
	info->facades = ot->facade_count;
	info->levels = ot->level_count;
	info->lowest_level = ot->level_count ? ot->level[0] : 0.0f;
}

// >>occluders
/* ---------------------------------------------------------------------------------------------- */
/* occluders: synthesis of certainly-solid volumes (for Wonka 2000's shrinking, §2 and appendix)  */
/* ---------------------------------------------------------------------------------------------- */

/* Voxel state flags (pvs_occluders.state). */
enum {
	PVS__VX_TOUCHED = 1,   /* a triangle within the margin */
	PVS__VX_REACHED = 2,   /* reached by the leak flood */
	PVS__VX_GROUND = 4,    /* layer 0, below the scene and the cells */
	PVS__VX_SOLID = 8,     /* certainly solid: proved by a parity flood, or explicit */
	PVS__VX_EXPLICIT = 16  /* inside an explicit occluder volume */
};
/* What stops the leak diagnostic's flood. */
#define PVS__VX_LEAK_STOP (PVS__VX_TOUCHED | PVS__VX_REACHED | PVS__VX_GROUND | PVS__VX_EXPLICIT)

/* Voxel (i, j, k) is origin + h ([i, i + 1] x [j, j + 1] x [k, k + 1]); n voxels per axis. */
typedef struct pvs__vx_grid {
	double origin[3], h;
	uint32_t n[3];
} pvs__vx_grid;

/* The 2.5D column map: squares of side grid.h on the ground (n[up] = 1) and min-pyramids (level l: squares of side
   grid.h 2^l; level 0: the map). */
#define PVS__VX_LEVELS 24
typedef struct pvs__vx_cols {
	pvs__vx_grid grid;
	uint32_t nu, nv;
	float *solid;               /* nu * nv: top of the proved-solid runs on the ground (ground: none) */
	float *top;                 /* nu * nv: occluder height, shrunk by eps (-FLT_MAX: none) */
	uint32_t levels;            /* pyramid levels (>= 1) */
	uint32_t lw[PVS__VX_LEVELS], lh[PVS__VX_LEVELS];
	float *ptop[PVS__VX_LEVELS], *psolid[PVS__VX_LEVELS]; /* level 0: top, solid; others allocated */
} pvs__vx_cols;

/* A BVH with tight boxes over the drawable objects or the chains, each in one leaf. */
typedef struct pvs__obvh_node {
	pvs_box box;
	uint32_t first, count;      /* leaf: items[first .. first + count); inner: count == 0, children first, first + 1 */
	uint32_t parent;
} pvs__obvh_node;
typedef struct pvs__obvh {
	pvs__obvh_node *nodes;
	uint32_t *items, *leaf_of; /* leaf_of: per object, its leaf (or 0xffffffff) */
	uint32_t *count_below;     /* per node: objects under it */
	uint32_t node_count, item_count, object_count;
} pvs__obvh;

struct pvs_occluders {
	pvs_allocator allocator;
	pvs__vx_grid grid;          /* the same as origin, h, n below */
	const pvs_scene *scene;
	pvs_occluders_info info;
	double origin[3], h;
	uint32_t n[3];
	size_t total;
	uint8_t *state;             /* total: PVS__VX_* flags */
	uint8_t *eroded;            /* total: 1 where solid survives the erosion */
	pvs_box *boxes;
	uint32_t box_count;
	pvs_facade_chain *chains;   /* the 2.5D occluders */
	pvs_box *chain_boxes;       /* per chain: ground bounding rectangle x [base, top] */
	float *chain_points;        /* 2 floats per point */
	uint32_t chain_count;
	size_t chain_point_count;
	float ground;
	pvs__vx_cols cols;          /* the 2.5D column map */
	pvs__obvh bvh;              /* drawable objects, for the 2.5D walks */
	pvs__obvh chain_bvh;        /* the chains' boxes */
	uint32_t *excluded;         /* info.excluded_cells: leaking cells left out, */
	pvs_box *excluded_boxes;    /* and their boxes */
};

PVS__STATIC size_t pvs__vx_index(const pvs_occluders *o, uint32_t i, uint32_t j, uint32_t k) {
	return (size_t)i + (size_t)o->n[0] * ((size_t)j + (size_t)o->n[1] * (size_t)k);
}
PVS__STATIC int pvs__vx_solid_state(uint8_t s) { return (s & PVS__VX_SOLID) != 0; }

/* Triangle-box overlap by separating axes (Akenine-Moller 2001) in double; hs includes the margin, radii are scaled up
   a hair: rounding errs toward "touched". */
PVS__STATIC int pvs__tri_aabb(const double c[3], const double hs[3], const double *a, const double *b,
							  const double *d) {
	double v[3][3], e[3][3], n[3], p, q, r, lo, hi, rad;
	int i, j;
	for (i = 0; i < 3; ++i) { v[0][i] = a[i] - c[i]; v[1][i] = b[i] - c[i]; v[2][i] = d[i] - c[i]; }
	for (i = 0; i < 3; ++i) {
		lo = hi = v[0][i];
		for (j = 1; j < 3; ++j) { if (v[j][i] < lo) lo = v[j][i]; if (v[j][i] > hi) hi = v[j][i]; }
		if (lo > hs[i] || hi < -hs[i]) return 0;
	}
	for (i = 0; i < 3; ++i) { e[0][i] = v[1][i] - v[0][i]; e[1][i] = v[2][i] - v[1][i]; e[2][i] = v[0][i] - v[2][i]; }
	n[0] = e[0][1] * e[1][2] - e[0][2] * e[1][1];
	n[1] = e[0][2] * e[1][0] - e[0][0] * e[1][2];
	n[2] = e[0][0] * e[1][1] - e[0][1] * e[1][0];
	p = n[0] * v[0][0] + n[1] * v[0][1] + n[2] * v[0][2];
	rad = hs[0] * pvs__dabs(n[0]) + hs[1] * pvs__dabs(n[1]) + hs[2] * pvs__dabs(n[2]);
	if (p > rad * (1.0 + 1e-9) + 1e-300 || p < -rad * (1.0 + 1e-9) - 1e-300) return 0;
	for (i = 0; i < 3; ++i)       /* edge i x box axis j */
		for (j = 0; j < 3; ++j) {
			double ax[3] = {0, 0, 0};
			int k;
			ax[(j + 1) % 3] = -e[i][(j + 2) % 3];
			ax[(j + 2) % 3] = e[i][(j + 1) % 3];
			lo = hi = ax[0] * v[0][0] + ax[1] * v[0][1] + ax[2] * v[0][2];
			for (k = 1; k < 3; ++k) {
				q = ax[0] * v[k][0] + ax[1] * v[k][1] + ax[2] * v[k][2];
				if (q < lo) lo = q;
				if (q > hi) hi = q;
			}
			r = hs[0] * pvs__dabs(ax[0]) + hs[1] * pvs__dabs(ax[1]) + hs[2] * pvs__dabs(ax[2]);
			r = r * (1.0 + 1e-9) + 1e-300;
			if (lo > r || hi < -r) return 0;
		}
	return 1;
}
PVS__STATIC int pvs__tri_box(const double c[3], double hs, const double *a, const double *b, const double *d) {
	double h3[3];
	h3[0] = h3[1] = h3[2] = hs;
	return pvs__tri_aabb(c, h3, a, b, d);
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
/* 1 if segments a-b and c-d meet (touching counts). */
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
			if (!pvs__point_in_poly(oc->footprint, oc->footprint_count, j & 1 ? hi[u] : lo[u], j & 2 ? hi[v] : lo[v]))
				return 0;
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

typedef struct pvs__obvh_key {
	double d;
	uint32_t i;
} pvs__obvh_key;
PVS__STATIC int pvs__obvh_key_cmp(const void *x, const void *y) {
	const pvs__obvh_key *a = (const pvs__obvh_key *)x, *b = (const pvs__obvh_key *)y;
	return a->d < b->d ? -1 : a->d > b->d ? 1 : a->i < b->i ? -1 : a->i > b->i;
}

/* A hierarchy over boxes[0 .. count) (keep NULL: all, else those kept): median splits on the centres' longest axis,
   leaves of at most 4. */
PVS__STATIC pvs_result pvs__obvh_build(const pvs_allocator *al, const pvs_box *boxes, uint32_t count,
									   const uint8_t *keep, pvs__obvh *h) {
	uint32_t i, n = 0, *stack = NULL, sp = 0;
	pvs__obvh_key *keys = NULL;
	memset(h, 0, sizeof(*h));
	h->object_count = count;
	h->items = (uint32_t *)pvs__alloc_array(al, count ? count : 1, sizeof(uint32_t));
	h->leaf_of = (uint32_t *)pvs__alloc_array(al, count ? count : 1, sizeof(uint32_t));
	if (!h->items || !h->leaf_of) return PVS_ERROR_OUT_OF_MEMORY;
	for (i = 0; i < count; ++i) {
		h->leaf_of[i] = 0xffffffffu;
		if (!keep || keep[i]) h->items[n++] = i;
	}
	h->item_count = n;
	h->nodes = (pvs__obvh_node *)pvs__alloc_array(al, 2 * (size_t)n + 1, sizeof(pvs__obvh_node));
	h->count_below = (uint32_t *)pvs__alloc_array(al, 2 * (size_t)n + 1, sizeof(uint32_t));
	stack = (uint32_t *)pvs__alloc_array(al, 2 * (size_t)n + 2, sizeof(uint32_t));
	keys = (pvs__obvh_key *)pvs__alloc_array(al, n ? n : 1, sizeof(pvs__obvh_key));
	if (!h->nodes || !h->count_below || !stack || !keys || !n) {
		pvs__free_array(al, stack, 2 * (size_t)n + 2, sizeof(uint32_t));
		pvs__free_array(al, keys, n ? n : 1, sizeof(pvs__obvh_key));
		return h->nodes && h->count_below && stack && keys ? PVS_OK : PVS_ERROR_OUT_OF_MEMORY;
	}
	h->node_count = 1;
	h->nodes[0].first = 0;
	h->nodes[0].count = n;
	h->nodes[0].parent = 0xffffffffu;
	stack[sp++] = 0;
	while (sp) {
		uint32_t nd = stack[--sp], f = h->nodes[nd].first, c = h->nodes[nd].count, k, ax = 0, mid;
		pvs_box bb, cb;
		int kk;
		bb = boxes[h->items[f]];
		for (kk = 0; kk < 3; ++kk) cb.min[kk] = cb.max[kk] = 0.5f * (bb.min[kk] + bb.max[kk]);
		for (k = f; k < f + c; ++k) {
			const pvs_box *ob = boxes + h->items[k];
			for (kk = 0; kk < 3; ++kk) {
				float mm = 0.5f * (ob->min[kk] + ob->max[kk]);
				if (ob->min[kk] < bb.min[kk]) bb.min[kk] = ob->min[kk];
				if (ob->max[kk] > bb.max[kk]) bb.max[kk] = ob->max[kk];
				if (mm < cb.min[kk]) cb.min[kk] = mm;
				if (mm > cb.max[kk]) cb.max[kk] = mm;
			}
		}
		h->nodes[nd].box = bb;
		h->count_below[nd] = c;
		if (c <= 4) {
			for (k = f; k < f + c; ++k) h->leaf_of[h->items[k]] = nd;
			continue;
		}
		for (kk = 1; kk < 3; ++kk)
			if (cb.max[kk] - cb.min[kk] > cb.max[ax] - cb.min[ax]) ax = (uint32_t)kk;
		for (k = 0; k < c; ++k) {
			const pvs_box *ob = boxes + h->items[f + k];
			keys[k].d = (double)ob->min[ax] + ob->max[ax];
			keys[k].i = h->items[f + k];
		}
		PVS_QSORT(keys, c, sizeof(pvs__obvh_key), pvs__obvh_key_cmp);
		for (k = 0; k < c; ++k) h->items[f + k] = keys[k].i;
		mid = f + c / 2;
		h->nodes[nd].first = h->node_count;
		h->nodes[nd].count = 0;
		h->nodes[h->node_count].first = f;
		h->nodes[h->node_count].count = mid - f;
		h->nodes[h->node_count].parent = nd;
		h->nodes[h->node_count + 1].first = mid;
		h->nodes[h->node_count + 1].count = f + c - mid;
		h->nodes[h->node_count + 1].parent = nd;
		stack[sp++] = h->node_count;
		stack[sp++] = h->node_count + 1;
		h->node_count += 2;
	}
	pvs__free_array(al, stack, 2 * (size_t)n + 2, sizeof(uint32_t));
	pvs__free_array(al, keys, n ? n : 1, sizeof(pvs__obvh_key));
	return PVS_OK;
}
PVS__STATIC void pvs__obvh_free(const pvs_allocator *a, pvs__obvh *h) {
	pvs__free_array(a, h->items, h->object_count ? h->object_count : 1, sizeof(uint32_t));
	pvs__free_array(a, h->leaf_of, h->object_count ? h->object_count : 1, sizeof(uint32_t));
	pvs__free_array(a, h->nodes, 2 * (size_t)h->item_count + 1, sizeof(pvs__obvh_node));
	pvs__free_array(a, h->count_below, 2 * (size_t)h->item_count + 1, sizeof(uint32_t));
	memset(h, 0, sizeof(*h));
}

PVS__STATIC pvs_result pvs__occluders_hierarchies(pvs_occluders *o) {
	const pvs_scene *s = o->scene;
	uint8_t *keep = (uint8_t *)pvs__alloc_array(&o->allocator, s->object_count ? s->object_count : 1, 1);
	uint32_t i;
	pvs_result r;
	if (!keep) return PVS_ERROR_OUT_OF_MEMORY;
	for (i = 0; i < s->object_count; ++i)
		keep[i] = !(s->object_flags[i] & PVS_OBJECT_OCCLUDER_ONLY) && pvs__box_valid(s->object_boxes + i);
	r = pvs__obvh_build(&o->allocator, s->object_boxes, s->object_count, keep, &o->bvh);
	pvs__free_array(&o->allocator, keep, s->object_count ? s->object_count : 1, 1);
	if (r == PVS_OK) r = pvs__obvh_build(&o->allocator, o->chain_boxes, o->chain_count, NULL, &o->chain_bvh);
	return r;
}

PVS_API void pvs_occluders_destroy(pvs_occluders *o) {
	pvs_allocator a;
	if (!o) return;
	a = o->allocator;
	pvs__obvh_free(&a, &o->bvh);
	pvs__obvh_free(&a, &o->chain_bvh);
	pvs__free_array(&a, o->excluded, o->info.excluded_cells, sizeof(uint32_t));
	pvs__free_array(&a, o->excluded_boxes, o->info.excluded_cells, sizeof(pvs_box));
	pvs__free_array(&a, o->state, o->total, 1);
	pvs__free_array(&a, o->eroded, o->total, 1);
	pvs__free_array(&a, o->boxes, o->box_count, sizeof(pvs_box));
	pvs__free_array(&a, o->chains, o->chain_count ? o->chain_count : 1, sizeof(pvs_facade_chain));
	pvs__free_array(&a, o->chain_boxes, o->chain_count ? o->chain_count : 1, sizeof(pvs_box));
	pvs__free_array(&a, o->chain_points, o->chain_point_count ? 2 * o->chain_point_count : 1, sizeof(float));
	pvs__free_array(&a, o->cols.solid, (size_t)o->cols.nu * o->cols.nv, sizeof(float));
	pvs__free_array(&a, o->cols.top, (size_t)o->cols.nu * o->cols.nv, sizeof(float));
	{
		uint32_t l;
		for (l = 1; l < o->cols.levels; ++l) {
			pvs__free_array(&a, o->cols.ptop[l], (size_t)o->cols.lw[l] * o->cols.lh[l], sizeof(float));
			pvs__free_array(&a, o->cols.psolid[l], (size_t)o->cols.lw[l] * o->cols.lh[l], sizeof(float));
		}
	}
	pvs__free(&a, o, sizeof(*o), 16);
}

/* Voxel range [*i0, *i1] on axis k of [lo - m, hi + m] (empty: 1, 0). */
PVS__STATIC void pvs__vx_grange(const pvs__vx_grid *gr, int k, double lo, double hi, double m, uint32_t *i0,
								uint32_t *i1) {
	double a = floor((lo - m - gr->origin[k]) / gr->h), b = floor((hi + m - gr->origin[k]) / gr->h);
	if (a < 0) a = 0;
	if (b > (double)gr->n[k] - 1) b = (double)gr->n[k] - 1;
	if (!(b >= a)) { *i0 = 1; *i1 = 0; return; }
	*i0 = (uint32_t)a;
	*i1 = (uint32_t)b;
}
PVS__STATIC void pvs__vx_range(const pvs_occluders *o, int k, double lo, double hi, double m, uint32_t *i0,
							   uint32_t *i1) {
	pvs__vx_grange(&o->grid, k, lo, hi, m, i0, i1);
}

/* Sutherland-Hodgman: convex polygon in (n points of 3 doubles; n = 2 a segment) clipped to sign (x[k] - c) >= 0 into
   out (n + 1 points). Returns the count. */
PVS__STATIC int pvs__vx_clip_half(const double *in, int n, int k, double c, double sign, double *out) {
	int i, r = 0;
	for (i = 0; i < n; ++i) {
		const double *a = in + 3 * i, *b = in + 3 * ((i + 1) % n);
		double da = sign * (a[k] - c), db = sign * (b[k] - c);
		if (da >= 0.0) { memcpy(out + 3 * r, a, 3 * sizeof(double)); ++r; }
		if ((da >= 0.0) != (db >= 0.0)) {
			double t = da / (da - db);
			int q;
			for (q = 0; q < 3; ++q) out[3 * r + q] = a[q] + t * (b[q] - a[q]);
			out[3 * r + k] = c; /* exactly on the plane */
			++r;
		}
	}
	return r;
}

/* The cells along axis k within [r0, r1] whose extent grown by g meets polygon p's (n points); empty when *i0 > *i1. */
PVS__STATIC void pvs__vx_poly_range(const pvs__vx_grid *gr, const double *p, int n, int k, double g, uint32_t r0,
									uint32_t r1, uint32_t *i0, uint32_t *i1) {
	double lo = p[k], hi = p[k], a, b;
	int i;
	for (i = 1; i < n; ++i) {
		lo = pvs__dmin(lo, p[3 * i + k]);
		hi = pvs__dmax(hi, p[3 * i + k]);
	}
	a = floor((lo - g - gr->origin[k]) / gr->h);
	b = floor((hi + g - gr->origin[k]) / gr->h);
	a = a > (double)r0 ? a : (double)r0;
	b = b < (double)r1 ? b : (double)r1;
	if (!(b >= a)) { *i0 = 1; *i1 = 0; return; }
	*i0 = (uint32_t)a;
	*i1 = (uint32_t)b;
}

typedef void (*pvs__vx_visit_fn)(void *user, const uint32_t idx[3]);

/* Calls visit for the cells of gr within [r0, r1] that convex polygon p (3 points, or 2: a segment) grown by m may
   meet: clipped to slabs along k[2] (dims 2: the k[0], k[1] plane only), then rows along k[1] whose clips give the k[0]
   ranges, so a long sliver costs its cells, not its box. Candidates only; slabs grow by 1e-3 cell beyond m, far above
   the clips' rounding, so every cell an exact test with margin m accepts is visited. */
PVS__STATIC void pvs__vx_scan(const pvs__vx_grid *gr, const double *p, int n, const int k[3], int dims, double m,
							  const uint32_t r0[3], const uint32_t r1[3], pvs__vx_visit_fn visit, void *user) {
	double slab[3 * 8], tmp[3 * 8], row[3 * 8], g = m + 1e-3 * gr->h, h = gr->h;
	uint32_t idx[3], c, c0 = 0, c1 = 0, b, b0, b1, a, a0, a1;
	idx[0] = idx[1] = idx[2] = 0;
	if (dims == 3) pvs__vx_poly_range(gr, p, n, k[2], g, r0[k[2]], r1[k[2]], &c0, &c1);
	for (c = c0; c <= c1 && c0 <= c1; ++c) {
		const double *sp = p;
		int sn = n, rn;
		if (dims == 3) {
			sn = pvs__vx_clip_half(p, n, k[2], gr->origin[k[2]] + c * h - g, 1.0, tmp);
			sn = pvs__vx_clip_half(tmp, sn, k[2], gr->origin[k[2]] + (c + 1) * h + g, -1.0, slab);
			if (!sn) continue;
			sp = slab;
			idx[k[2]] = c;
		}
		pvs__vx_poly_range(gr, sp, sn, k[1], g, r0[k[1]], r1[k[1]], &b0, &b1);
		for (b = b0; b <= b1 && b0 <= b1; ++b) {
			rn = pvs__vx_clip_half(sp, sn, k[1], gr->origin[k[1]] + b * h - g, 1.0, tmp);
			rn = pvs__vx_clip_half(tmp, rn, k[1], gr->origin[k[1]] + (b + 1) * h + g, -1.0, row);
			if (!rn) continue;
			pvs__vx_poly_range(gr, row, rn, k[0], g, r0[k[0]], r1[k[0]], &a0, &a1);
			idx[k[1]] = b;
			for (a = a0; a <= a1 && a0 <= a1; ++a) {
				idx[k[0]] = a;
				visit(user, idx);
			}
		}
		if (dims != 3) break;
	}
}

/* Min filter of radius r along axis k (outside counts as 0): Chebyshev erosion is separable. */
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

/* Greedy merge of the set voxels of g (cleared) into boxes rounded inward to float; out NULL: count only. Returns the
   count. */
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

/* ---- certified solid: crossing parity floods per edge-connected component ----

   Why it is conservative. For triangles K and x above the ground level g, w(x) is the parity of K's triangles that the
   upward ray from x crosses. If K's edges have even use counts (those at up = g excepted: no sight line between points
   above g dips below it), w is constant on each connected piece of space minus K; an odd (open) edge flips w across the
   vertical sheet below it. A voxel is pure if no triangle of K or sheet comes within the margin m (one w), mixed if
   only a triangle does (nodes w = 0 and 1: joining parts of equal w over-approximates connectivity), bad if a sheet
   does (one node). Free space is open, so a path avoiding K can be moved to pass between voxels through faces only,
   carrying the face point's w: the graph linking face neighbours' nodes of equal w (any node of a bad voxel) holds
   every such path, and outside K's voxel box (sheets end at g, inside it) is one region of w = 0. The flood from the
   voxels meeting a cell, and from the outside when a cell lies outside the box, reaches all a viewer can walk to
   without touching K: a pure voxel it misses is seen from no cell, so a sight line through it meets a triangle first.
   Solid for some triangles is solid for all, so each component is flooded alone (overlapping meshes keep their parity).
   w is read per column on a vertical line whose orientation signs are certain (pvs__vx_cross). A slit or door narrower
   than a voxel makes mixed or bad voxels, which keep both sides joined. */

/* orient2d (b - a) x (p - a); *bound bounds its rounding (each difference and product rounded once: <=
   4.5e-16 (|t1| + |t2|)), so its sign is certain when |value| > *bound. No underflow for floats. */
PVS__STATIC double pvs__vx_orient(double ax, double ay, double bx, double by, double px, double py, double *bound) {
	double t1 = (bx - ax) * (py - ay), t2 = (by - ay) * (px - ax);
	*bound = 1e-15 * (pvs__dabs(t1) + pvs__dabs(t2));
	return t1 - t2;
}

/* The vertical line through (pu, pv) against triangle a, b, c: 0 certainly misses, 1 certainly crosses inside at height
   *z (within *dz), -1 undecidable (near an edge or vertex, or uncertain height). */
PVS__STATIC int pvs__vx_cross(const float *a, const float *b, const float *c, int u, int v, int up, double pu,
							  double pv, double *z, double *dz) {
	const float *p[3];
	double o[3], bd[3], r = 0.0, zlo, zhi, w0, w1, w2;
	int i, pos = 0, neg = 0, unsure = 0;
	p[0] = a; p[1] = b; p[2] = c;
	for (i = 0; i < 3; ++i) { /* zero-length projected edge: no area, a segment or a point */
		const float *q = p[i], *s = p[(i + 1) % 3], *t = p[(i + 2) % 3];
		if (q[u] == s[u] && q[v] == s[v]) {
			if (t[u] == q[u] && t[v] == q[v]) return pu == (double)q[u] && pv == (double)q[v] ? -1 : 0;
			o[0] = pvs__vx_orient(q[u], q[v], t[u], t[v], pu, pv, bd);
			return pvs__dabs(o[0]) <= bd[0] ? -1 : 0;
		}
	}
	for (i = 0; i < 3; ++i) {
		const float *q = p[i], *s = p[(i + 1) % 3];
		o[i] = pvs__vx_orient(q[u], q[v], s[u], s[v], pu, pv, bd + i);
		if (pvs__dabs(o[i]) <= bd[i]) unsure = 1;
		else if (o[i] > 0.0) pos = 1;
		else neg = 1;
	}
	if (pos && neg) return 0;
	if (unsure) return -1;
	/* inside: barycentric weights |o| (o[1], o[2], o[0] for a, b, c), each within relative error r: the weighted mean
	   height errs by <= range 2r / (1 - r) */
	for (i = 0; i < 3; ++i) r = pvs__dmax(r, bd[i] / pvs__dabs(o[i]));
	if (r >= 0.25) return -1;
	w0 = pvs__dabs(o[1]); w1 = pvs__dabs(o[2]); w2 = pvs__dabs(o[0]);
	*z = (w0 * a[up] + w1 * b[up] + w2 * c[up]) / (w0 + w1 + w2);
	zlo = pvs__dmin(a[up], pvs__dmin(b[up], c[up]));
	zhi = pvs__dmax(a[up], pvs__dmax(b[up], c[up]));
	*dz = (zhi - zlo) * 2.0 * r / (1.0 - r) + 1e-15 * (pvs__dabs(zlo) + pvs__dabs(zhi));
	return 1;
}

/* Flood voxel bits: T touched by K, B bad, F odd crossings in the layer, W w = 1 (pure), R0 / R1 node 0 / 1 reached. */
enum { PVS__G_T = 1, PVS__G_B = 2, PVS__G_F = 4, PVS__G_W = 8, PVS__G_R0 = 16, PVS__G_R1 = 32 };

typedef struct pvs__vx_vkey {
	float p[3];
	uint32_t i;
} pvs__vx_vkey;
PVS__STATIC int pvs__vx_vkey_cmp(const void *x, const void *y) {
	const pvs__vx_vkey *a = (const pvs__vx_vkey *)x, *b = (const pvs__vx_vkey *)y;
	int k;
	for (k = 0; k < 3; ++k) {
		if (a->p[k] < b->p[k]) return -1;
		if (a->p[k] > b->p[k]) return 1;
	}
	return a->i < b->i ? -1 : a->i > b->i;
}
PVS__STATIC int pvs__vx_vkey_cmp_pos(const pvs__vx_vkey *a, const pvs__vx_vkey *b) {
	return a->p[0] != b->p[0] || a->p[1] != b->p[1] || a->p[2] != b->p[2];
}
typedef struct pvs__vx_edge {
	uint64_t key;  /* canonical vertex ids, smaller first */
	uint32_t tri;
} pvs__vx_edge;
PVS__STATIC int pvs__vx_edge_cmp(const void *x, const void *y) {
	const pvs__vx_edge *a = (const pvs__vx_edge *)x, *b = (const pvs__vx_edge *)y;
	if (a->key != b->key) return a->key < b->key ? -1 : 1;
	return a->tri < b->tri ? -1 : a->tri > b->tri;
}

typedef struct pvs__vx_topo {
	uint32_t *tris;          /* included triangles grouped by component: comp_first[c] .. comp_first[c + 1] */
	uint32_t *comp_first;    /* comp_count + 1 */
	uint32_t comp_count;
	uint32_t tri_count;      /* included triangles */
	uint32_t *open_first;    /* comp_count + 1: ranges of open_edges per component */
	float *open_edges;       /* 6 floats per open edge (two corners), grouped by component */
	uint32_t open_count;
} pvs__vx_topo;

PVS__STATIC void pvs__vx_topo_free(const pvs_allocator *a, pvs__vx_topo *t, uint32_t triangle_count) {
	pvs__free_array(a, t->tris, triangle_count ? triangle_count : 1, sizeof(uint32_t));
	pvs__free_array(a, t->comp_first, (size_t)triangle_count + 2, sizeof(uint32_t));
	pvs__free_array(a, t->open_first, (size_t)triangle_count + 2, sizeof(uint32_t));
	pvs__free_array(a, t->open_edges, (size_t)(t->open_count ? t->open_count : 1) * 6, sizeof(float));
	memset(t, 0, sizeof(*t));
}

/* 1 if the triangle lies flat on the ground level g (left out: it bounds nothing above g). */
PVS__STATIC int pvs__vx_flat_on_ground(const pvs_scene *s, uint32_t t, float g) {
	uint32_t up = s->up_axis, k;
	for (k = 0; k < 3; ++k)
		if (s->positions[3 * (size_t)s->indices[3 * (size_t)t + k] + up] != g) return 0;
	return 1;
}

/* Edge-connected components of the triangles (vertices matched by exact position) and their open edges (odd use, not
   both corners at ground level g). */
PVS__STATIC pvs_result pvs__vx_topology(const pvs_scene *s, float g, const pvs_allocator *a, pvs__vx_topo *t) {
	uint32_t nv = s->vertex_count, nt = s->triangle_count, i, k, up = s->up_axis, ne = 0, c;
	pvs__vx_vkey *vk = NULL;
	pvs__vx_edge *ed = NULL;
	uint32_t *canon = NULL, *parent = NULL, *cid = NULL;
	size_t e0, e1;
	pvs_result res = PVS_ERROR_OUT_OF_MEMORY;
	memset(t, 0, sizeof(*t));
	vk = (pvs__vx_vkey *)pvs__alloc_array(a, nv ? nv : 1, sizeof(pvs__vx_vkey));
	canon = (uint32_t *)pvs__alloc_array(a, nv ? nv : 1, sizeof(uint32_t));
	ed = (pvs__vx_edge *)pvs__alloc_array(a, (size_t)(nt ? nt : 1) * 3, sizeof(pvs__vx_edge));
	parent = (uint32_t *)pvs__alloc_array(a, nt ? nt : 1, sizeof(uint32_t));
	cid = (uint32_t *)pvs__alloc_array(a, nt ? nt : 1, sizeof(uint32_t));
	t->tris = (uint32_t *)pvs__alloc_array(a, nt ? nt : 1, sizeof(uint32_t));
	t->comp_first = (uint32_t *)pvs__alloc_array(a, (size_t)nt + 2, sizeof(uint32_t));
	t->open_first = (uint32_t *)pvs__alloc_array(a, (size_t)nt + 2, sizeof(uint32_t));
	if (!vk || !canon || !ed || !parent || !cid || !t->tris || !t->comp_first || !t->open_first) goto done;
	for (i = 0; i < nv; ++i) {
		for (k = 0; k < 3; ++k) vk[i].p[k] = s->positions[3 * (size_t)i + k];
		vk[i].i = i;
	}
	PVS_QSORT(vk, nv, sizeof(pvs__vx_vkey), pvs__vx_vkey_cmp);
	for (i = 0; i < nv; ++i)
		canon[vk[i].i] = i > 0 && !pvs__vx_vkey_cmp_pos(vk + i - 1, vk + i) ? canon[vk[i - 1].i] : i;
	for (i = 0; i < nt; ++i) {
		parent[i] = i;
		if (pvs__vx_flat_on_ground(s, i, g)) { parent[i] = 0xffffffffu; continue; }
		for (k = 0; k < 3; ++k) {
			uint32_t x = canon[s->indices[3 * (size_t)i + k]], y = canon[s->indices[3 * (size_t)i + (k + 1) % 3]];
			if (x == y) continue;
			ed[ne].key = x < y ? ((uint64_t)x << 32) | y : ((uint64_t)y << 32) | x;
			ed[ne].tri = i;
			++ne;
		}
	}
	PVS_QSORT(ed, ne, sizeof(pvs__vx_edge), pvs__vx_edge_cmp);
	for (e0 = 0; e0 < ne; e0 = e1) {
		for (e1 = e0 + 1; e1 < ne && ed[e1].key == ed[e0].key; ++e1) {
			uint32_t ra = pvs__uf_find(parent, ed[e0].tri), rb = pvs__uf_find(parent, ed[e1].tri);
			if (ra != rb) parent[ra > rb ? ra : rb] = ra < rb ? ra : rb; /* the smaller root wins: deterministic */
		}
	}
	/* components numbered by their first triangle */
	t->comp_count = 0;
	for (i = 0; i < nt; ++i) {
		if (parent[i] == 0xffffffffu) { cid[i] = 0xffffffffu; continue; }
		k = pvs__uf_find(parent, i);
		cid[i] = k == i ? t->comp_count++ : cid[k];
	}
	memset(t->comp_first, 0, ((size_t)t->comp_count + 2) * sizeof(uint32_t));
	for (i = 0; i < nt; ++i)
		if (cid[i] != 0xffffffffu) ++t->comp_first[cid[i] + 1];
	for (c = 0; c < t->comp_count; ++c) t->comp_first[c + 1] += t->comp_first[c];
	t->tri_count = t->comp_first[t->comp_count];
	{
		uint32_t *fill = parent;
		for (c = 0; c < t->comp_count; ++c) fill[c] = t->comp_first[c];
		for (i = 0; i < nt; ++i)
			if (cid[i] != 0xffffffffu) t->tris[fill[cid[i]]++] = i;
	}
	/* open edges: odd runs; corners from vk (canon id = index into the sorted keys) */
	t->open_count = 0;
	for (e0 = 0; e0 < ne; e0 = e1) {
		const float *p0, *p1;
		for (e1 = e0 + 1; e1 < ne && ed[e1].key == ed[e0].key; ++e1) {}
		if (!((e1 - e0) & 1)) continue;
		p0 = vk[(uint32_t)(ed[e0].key >> 32)].p;
		p1 = vk[(uint32_t)ed[e0].key].p;
		if (p0[up] == g && p1[up] == g) continue;
		ed[t->open_count++] = ed[e0]; /* in place: open_count <= e0 */
	}
	t->open_edges = (float *)pvs__alloc_array(a, (size_t)(t->open_count ? t->open_count : 1) * 6, sizeof(float));
	if (!t->open_edges) goto done;
	memset(t->open_first, 0, ((size_t)t->comp_count + 2) * sizeof(uint32_t));
	for (i = 0; i < t->open_count; ++i) ++t->open_first[cid[ed[i].tri] + 1];
	for (c = 0; c < t->comp_count; ++c) t->open_first[c + 1] += t->open_first[c];
	{
		uint32_t *fill = parent;
		for (c = 0; c < t->comp_count; ++c) fill[c] = t->open_first[c];
		for (i = 0; i < t->open_count; ++i) {
			float *dst = t->open_edges + 6 * (size_t)fill[cid[ed[i].tri]]++;
			memcpy(dst, vk[(uint32_t)(ed[i].key >> 32)].p, 3 * sizeof(float));
			memcpy(dst + 3, vk[(uint32_t)ed[i].key].p, 3 * sizeof(float));
		}
	}
	res = PVS_OK;
done:
	pvs__free_array(a, vk, nv ? nv : 1, sizeof(pvs__vx_vkey));
	pvs__free_array(a, canon, nv ? nv : 1, sizeof(uint32_t));
	pvs__free_array(a, ed, (size_t)(nt ? nt : 1) * 3, sizeof(pvs__vx_edge));
	pvs__free_array(a, parent, nt ? nt : 1, sizeof(uint32_t));
	pvs__free_array(a, cid, nt ? nt : 1, sizeof(uint32_t));
	if (res != PVS_OK) pvs__vx_topo_free(a, t, nt);
	return res;
}

/* Scratch of the component floods, sized for the largest box. */
typedef struct pvs__vx_flood {
	uint8_t *bits;           /* box voxels: PVS__G_* */
	uint8_t *col;            /* box columns: candidate line index, 0x80 = undecided in this pass, 0xff = failed */
	uint32_t *queue;         /* 2 nodes per box voxel */
	size_t cap_vox, cap_col;
	const pvs_box *cells;    /* the cells and a bucket grid over them (ground plane) */
	uint32_t cell_count;
	uint32_t *bucket_first;  /* bnu * bnv + 1 */
	uint32_t *bucket_cells;
	uint32_t *stamp;         /* per cell: 1 + the last component that looked at it */
	uint32_t bnu, bnv;
	uint32_t stamp_next;     /* the next stamp value */
	pvs__vx_grid bucket_grid;/* the buckets as a grid */
	uint8_t *cellbuf;        /* per cell 7 bytes, the four arrays below */
	uint8_t *excluded;       /* per cell: 1 = left out of the floods (leaking) */
	uint32_t excluded_count;
	int keep_leaks;          /* PVS_OCCLUDERS_KEEP_LEAKS: never exclude */
	uint32_t *near_cells;    /* per component: the cells meeting its box, */
	signed char *near_w;     /* their w (-1: every node), */
	uint8_t *near_flag;      /* 1 = sticks out of the box, 2 = the outside reaches its nodes */
} pvs__vx_flood;
#define PVS__VX_BUCKET 8u    /* voxel columns per bucket side */

/* Test line positions in a column, as voxel fractions (no structure on purpose). */
static const double pvs__vx_line_u[8] = {0.4142, 0.7071, 0.2360, 0.8660, 0.5773, 0.1547, 0.6458, 0.3183};
static const double pvs__vx_line_v[8] = {0.6180, 0.2679, 0.7937, 0.4472, 0.1213, 0.8944, 0.3660, 0.5403};

PVS__STATIC void pvs__vx_push(uint8_t *bits, uint32_t *queue, size_t *qt, size_t vi, int x) {
	uint8_t f = (uint8_t)(x ? PVS__G_R1 : PVS__G_R0);
	if (bits[vi] & f) return;
	bits[vi] |= f;
	queue[(*qt)++] = (uint32_t)(2 * vi + (size_t)x);
}
PVS__STATIC void pvs__vx_push_all(uint8_t *bits, uint32_t *queue, size_t *qt, size_t vi) {
	uint8_t f = bits[vi];
	if (f & PVS__G_B) pvs__vx_push(bits, queue, qt, vi, 0);
	else if (f & PVS__G_T) { pvs__vx_push(bits, queue, qt, vi, 0); pvs__vx_push(bits, queue, qt, vi, 1); }
	else pvs__vx_push(bits, queue, qt, vi, (f & PVS__G_W) != 0);
}
/* The node of voxel vi the outside (w = 0) enters. */
PVS__STATIC void pvs__vx_push_entry(uint8_t *bits, uint32_t *queue, size_t *qt, size_t vi) {
	uint8_t f = bits[vi];
	pvs__vx_push(bits, queue, qt, vi, (f & (PVS__G_B | PVS__G_T)) ? 0 : (f & PVS__G_W) != 0);
}

/* w of cell cb, clear of K by m (its points share it): the parity of K's crossings above a point of cb on a vertical
   line (none within m). -1 when eight lines fail. */
PVS__STATIC int pvs__vx_point_parity(const pvs_scene *s, const pvs__vx_topo *tp, uint32_t comp, const pvs_box *cb) {
	uint32_t up = s->up_axis, t, line;
	int u, v;
	pvs__ground_axes(up, &u, &v);
	for (line = 0; line < 8; ++line) {
		double pu = cb->min[u] + pvs__vx_line_u[line] * ((double)cb->max[u] - cb->min[u]);
		double pv = cb->min[v] + pvs__vx_line_v[line] * ((double)cb->max[v] - cb->min[v]);
		double z0 = 0.5 * ((double)cb->min[up] + cb->max[up]);
		int w = 0, ok = 1;
		for (t = tp->comp_first[comp]; t < tp->comp_first[comp + 1] && ok; ++t) {
			uint32_t tri = tp->tris[t];
			double z, dz;
			int r = pvs__vx_cross(s->positions + 3 * (size_t)s->indices[3 * (size_t)tri],
								  s->positions + 3 * (size_t)s->indices[3 * (size_t)tri + 1],
								  s->positions + 3 * (size_t)s->indices[3 * (size_t)tri + 2], u, v, (int)up, pu, pv, &z,
								  &dz);
			if (r < 0 || (r == 1 && pvs__dabs(z - z0) <= dz)) ok = 0;
			else if (r == 1 && z > z0) w ^= 1;
		}
		if (ok) return w;
	}
	return -1;
}

/* Pushes cell cb's sources in a flood: for its box voxels the node of w = wc (all where wc < 0); test = 1: pushes
   nothing, returns 1 when one is already reached. */
PVS__STATIC int pvs__vx_seed(const pvs__vx_grid *gr, const pvs_box *cb, const uint32_t lo[3], const uint32_t hi[3],
							 const size_t stride[3], double m, int wc, uint8_t *bits, uint32_t *queue, size_t *qt,
							 int test) {
	uint32_t r0[3], r1[3], a, b, c;
	int kk;
	for (kk = 0; kk < 3; ++kk) {
		pvs__vx_grange(gr, kk, cb->min[kk], cb->max[kk], m, r0 + kk, r1 + kk);
		if (r0[kk] < lo[kk]) r0[kk] = lo[kk];
		if (r1[kk] > hi[kk]) r1[kk] = hi[kk];
	}
	for (c = r0[2]; c <= r1[2]; ++c)
		for (b = r0[1]; b <= r1[1]; ++b)
			for (a = r0[0]; a <= r1[0]; ++a) {
				size_t x = (a - lo[0]) + stride[1] * (b - lo[1]) + stride[2] * (c - lo[2]);
				uint8_t f = bits[x], need;
				if (!test) {
					if (wc < 0) pvs__vx_push_all(bits, queue, qt, x);
					else if (f & PVS__G_B) pvs__vx_push(bits, queue, qt, x, 0);
					else if (f & PVS__G_T) pvs__vx_push(bits, queue, qt, x, wc);
					else pvs__vx_push(bits, queue, qt, x, (f & PVS__G_W) != 0);
					continue;
				}
				if (f & PVS__G_B) need = PVS__G_R0;
				else if (f & PVS__G_T) need = wc < 0 ? (PVS__G_R0 | PVS__G_R1) : wc ? PVS__G_R1 : PVS__G_R0;
				else need = (f & PVS__G_W) ? PVS__G_R1 : PVS__G_R0;
				if (f & need) return 1;
			}
	return 0;
}

/* Floods a box's nodes from the queue, entering from the outside when ext is 1 or on reaching a box face through a node
   joined to it. Returns 0 when the outside was never entered. */
PVS__STATIC int pvs__vx_flood_run(uint8_t *bits, uint32_t *queue, size_t *qh_io, size_t *qt_io, const uint32_t d[3],
								  const size_t stride[3], const uint32_t lo[3], uint32_t up, int ext) {
	size_t qh = *qh_io, qt = *qt_io;
	uint32_t i, j, k;
	for (;;) {
		uint32_t node, idx[3], kk;
		size_t a;
		int x, dir;
		uint8_t fa;
		if (ext == 1) { /* enter through every box face but the ground */
			for (k = 0; k < d[2]; ++k)
				for (j = 0; j < d[1]; ++j)
					for (i = 0; i < d[0]; ++i) {
						int face = 0;
						idx[0] = i; idx[1] = j; idx[2] = k;
						for (kk = 0; kk < 3; ++kk)
							face |= idx[kk] + 1 == d[kk] || (idx[kk] == 0 && (kk != up || lo[up] > 1));
						if (face) pvs__vx_push_entry(bits, queue, &qt, i + stride[1] * j + stride[2] * k);
					}
			ext = 2;
		}
		if (qh == qt) break;
		node = queue[qh++];
		a = node >> 1;
		x = (int)(node & 1u);
		fa = bits[a];
		idx[0] = (uint32_t)(a % d[0]);
		idx[1] = (uint32_t)((a / d[0]) % d[1]);
		idx[2] = (uint32_t)(a / stride[2]);
		for (dir = 0; dir < 6; ++dir) {
			size_t b;
			uint8_t fb;
			kk = (uint32_t)dir >> 1;
			if (dir & 1 ? idx[kk] + 1 == d[kk] : idx[kk] == 0) { /* a face of the box */
				if (kk == up && !(dir & 1) && lo[up] == 1) continue; /* the ground */
				if (!ext && ((fa & PVS__G_B) || !(fa & PVS__G_T) || x == 0)) ext = 1;
				continue;
			}
			b = dir & 1 ? a + stride[kk] : a - stride[kk];
			fb = bits[b];
			if (fa & PVS__G_B) pvs__vx_push_all(bits, queue, &qt, b);
			else if (fb & PVS__G_B) pvs__vx_push(bits, queue, &qt, b, 0);
			else if (!(fa & PVS__G_T)) pvs__vx_push(bits, queue, &qt, b, (fb & PVS__G_T) ? x : (fb & PVS__G_W) != 0);
			else if ((fb & PVS__G_T) || ((fb & PVS__G_W) != 0) == x) pvs__vx_push(bits, queue, &qt, b, x);
		}
	}
	*qh_io = qh;
	*qt_io = qt;
	return ext;
}

/* pvs__vx_scan's visitor: the voxels a triangle touches (separating axes, margin toward touched). */
typedef struct pvs__vx_touch {
	pvs_occluders *o;          /* non-NULL: sets PVS__VX_TOUCHED (gr is its grid) */
	const pvs__vx_grid *gr;
	uint8_t *bits;             /* non-NULL: sets PVS__G_T in a component's box; */
	const uint32_t *lo;        /* NULL: skips the grid's touched or ground voxels */
	const size_t *stride;
	double p[3][3], hs;        /* the triangle; voxel half size plus margin */
} pvs__vx_touch;
PVS__STATIC void pvs__vx_touch_visit(void *user, const uint32_t idx[3]) {
	pvs__vx_touch *tv = (pvs__vx_touch *)user;
	size_t x = 0;
	double cc[3];
	int kk;
	if (tv->bits) {
		x = (idx[0] - tv->lo[0]) + tv->stride[1] * (idx[1] - tv->lo[1]) + tv->stride[2] * (idx[2] - tv->lo[2]);
		if (tv->bits[x] & PVS__G_T) return;
	} else if (tv->o->state[pvs__vx_index(tv->o, idx[0], idx[1], idx[2])] & (PVS__VX_TOUCHED | PVS__VX_GROUND)) {
		return;
	}
	for (kk = 0; kk < 3; ++kk) cc[kk] = tv->gr->origin[kk] + (idx[kk] + 0.5) * tv->gr->h;
	if (pvs__tri_box(cc, tv->hs, tv->p[0], tv->p[1], tv->p[2])) {
		if (tv->bits) tv->bits[x] |= PVS__G_T;
		if (tv->o) tv->o->state[pvs__vx_index(tv->o, idx[0], idx[1], idx[2])] |= PVS__VX_TOUCHED;
	}
}

PVS__STATIC void pvs__vx_tri_points(const pvs_scene *s, uint32_t tri, double p[3][3]) {
	int e, kk;
	for (e = 0; e < 3; ++e)
		for (kk = 0; kk < 3; ++kk)
			p[e][kk] = s->positions[3 * (size_t)s->indices[3 * (size_t)tri + (size_t)e] + (size_t)kk];
}

/* pvs__vx_scan's visitors of steps 2 and 3: one column of the box at a time. */
typedef struct pvs__vx_colvisit {
	const pvs__vx_grid *gr;
	uint8_t *bits, *col;       /* the box's voxels from lo, its columns (rows of d[u]) */
	const uint32_t *lo, *hi, *d;
	const size_t *stride;
	int u, v, up;
	double m;
	const float *e;            /* step 2: the open edge (two points) */
	const float *tri[3];       /* step 3: the triangle's corners */
	uint32_t pass;             /* step 3: the line's position in the column */
} pvs__vx_colvisit;

/* Step 2 at column (a, b): the sheet below the part of the edge over the square grown by m. */
PVS__STATIC void pvs__vx_sheet_visit(void *user, const uint32_t at[3]) {
	const pvs__vx_colvisit *cv = (const pvs__vx_colvisit *)user;
	const float *e = cv->e;
	const double *org = cv->gr->origin;
	int u = cv->u, v = cv->v, up = cv->up, side, ok = 1;
	double h = cv->gr->h, m = cv->m, a0 = e[u], b0 = e[v], da = (double)e[3 + u] - e[u], db = (double)e[3 + v] - e[v];
	double t0 = 0.0, t1 = 1.0, q[4], pp[4], zt;
	uint32_t a = at[u], b = at[v], top, c, idx[3];
	pp[0] = -da; q[0] = a0 - (org[u] + a * h - m);
	pp[1] = da;  q[1] = org[u] + (a + 1) * h + m - a0;
	pp[2] = -db; q[2] = b0 - (org[v] + b * h - m);
	pp[3] = db;  q[3] = org[v] + (b + 1) * h + m - b0;
	for (side = 0; side < 4 && ok; ++side) {
		if (pp[side] == 0.0) { ok = q[side] >= 0.0; continue; }
		zt = q[side] / pp[side];
		if (pp[side] < 0.0) { if (zt > t0) t0 = zt; } else if (zt < t1) t1 = zt;
		ok = t0 <= t1;
	}
	if (!ok) return;
	zt = pvs__dmax((double)e[up] + t0 * ((double)e[3 + up] - e[up]), (double)e[up] + t1 * ((double)e[3 + up] - e[up]));
	zt = pvs__dmin(zt + m + 1e-6 * pvs__dabs(zt), (double)pvs__dmax(e[up], e[3 + up]) + m);
	top = (uint32_t)pvs__clampi(floor((zt - org[up]) / h), (int32_t)cv->lo[up], (int32_t)cv->hi[up]);
	idx[u] = a; idx[v] = b;
	for (c = cv->lo[up]; c <= top; ++c) {
		idx[up] = c;
		cv->bits[(idx[0] - cv->lo[0]) + cv->stride[1] * (idx[1] - cv->lo[1]) + cv->stride[2] * (idx[2] - cv->lo[2])] |=
			PVS__G_B;
	}
}

/* Step 3 at column (a, b): the crossing of its line (position pass) with the triangle. */
PVS__STATIC void pvs__vx_cross_visit(void *user, const uint32_t at[3]) {
	const pvs__vx_colvisit *cv = (const pvs__vx_colvisit *)user;
	int u = cv->u, v = cv->v, up = cv->up, r;
	uint32_t a = at[u], b = at[v], idx[3];
	size_t ci = (a - cv->lo[u]) + (size_t)cv->d[u] * (b - cv->lo[v]);
	double z, dz, h = cv->gr->h;
	if (cv->col[ci] != cv->pass) return;
	r = pvs__vx_cross(cv->tri[0], cv->tri[1], cv->tri[2], u, v, up,
					  cv->gr->origin[u] + (a + pvs__vx_line_u[cv->pass]) * h,
					  cv->gr->origin[v] + (b + pvs__vx_line_v[cv->pass]) * h, &z, &dz);
	if (r == 1 && dz >= 0.5 * cv->m) r = -1;
	if (r < 0) cv->col[ci] |= 0x80;
	if (r == 1) {
		idx[u] = a - cv->lo[u]; idx[v] = b - cv->lo[v];
		idx[up] =
			(uint32_t)pvs__clampi(floor((z - cv->gr->origin[up]) / h) - (double)cv->lo[up], 0, (int32_t)cv->d[up] - 1);
		cv->bits[idx[0] + cv->stride[1] * idx[1] + cv->stride[2] * idx[2]] ^= PVS__G_F;
	}
}

/* A component's box, shared by its flood's steps. */
typedef struct pvs__vx_fbox {
	pvs_occluders *o;
	const pvs_scene *s;
	const pvs__vx_grid *gr;
	const pvs__vx_topo *tp;
	uint32_t comp;             /* component K */
	const uint32_t *lo, *hi;   /* the box in voxels of gr (inclusive) */
	uint32_t d[3], up;         /* its voxels per axis */
	int u, v;
	size_t stride[3], nvox, ncol; /* of fl->bits; voxel and column counts */
	double m;
	pvs__vx_flood *fl;
} pvs__vx_fbox;

/* Step 1: PVS__G_T on the box voxels K touches (margin toward touched); with mark_touched also PVS__VX_TOUCHED on the
   occluders' grid. */
PVS__STATIC void pvs__vx_flood_touched(const pvs__vx_fbox *fb, int mark_touched) {
	static const int xyz[3] = {0, 1, 2};
	pvs__vx_touch tv;
	uint32_t t;
	memset(&tv, 0, sizeof(tv));
	tv.o = mark_touched ? fb->o : NULL;
	tv.gr = fb->gr;
	tv.bits = fb->fl->bits;
	tv.lo = fb->lo;
	tv.stride = fb->stride;
	tv.hs = 0.5 * fb->gr->h + fb->m;
	for (t = fb->tp->comp_first[fb->comp]; t < fb->tp->comp_first[fb->comp + 1]; ++t) {
		pvs__vx_tri_points(fb->s, fb->tp->tris[t], tv.p);
		pvs__vx_scan(fb->gr, tv.p[0], 3, xyz, 3, fb->m, fb->lo, fb->hi, pvs__vx_touch_visit, &tv);
	}
}

PVS__STATIC void pvs__vx_flood_colvisit(const pvs__vx_fbox *fb, pvs__vx_colvisit *cv, int axes[3]) {
	memset(cv, 0, sizeof(*cv));
	cv->gr = fb->gr;
	cv->bits = fb->fl->bits;
	cv->col = fb->fl->col;
	cv->lo = fb->lo;
	cv->hi = fb->hi;
	cv->d = fb->d;
	cv->stride = fb->stride;
	cv->u = fb->u;
	cv->v = fb->v;
	cv->up = (int)fb->up;
	cv->m = fb->m;
	axes[0] = fb->u;
	axes[1] = fb->v;
	axes[2] = (int)fb->up;
}

/* Step 2, the bad voxels: below each open edge, from it plus m to the ground, in the columns whose square grown by m
   the projected edge meets (Liang-Barsky). */
PVS__STATIC void pvs__vx_flood_sheets(const pvs__vx_fbox *fb) {
	const pvs__vx_topo *tp = fb->tp;
	pvs__vx_colvisit cv;
	int axes[3];
	uint32_t t, k;
	pvs__vx_flood_colvisit(fb, &cv, axes);
	for (t = tp->open_first[fb->comp]; t < tp->open_first[fb->comp + 1]; ++t) {
		double pe[2][3];
		for (k = 0; k < 6; ++k) pe[k / 3][k % 3] = tp->open_edges[6 * (size_t)t + k];
		cv.e = tp->open_edges + 6 * (size_t)t;
		pvs__vx_scan(fb->gr, pe[0], 2, axes, 2, fb->m, fb->lo, fb->hi, pvs__vx_sheet_visit, &cv);
	}
}

/* Step 3, pure voxels' w: a column's crossings with one vertical line toggle PVS__G_F at their layer; all 8 line
   positions failing make it bad (info.undecided_columns). PVS__G_W where the crossings above are odd. */
PVS__STATIC void pvs__vx_flood_parity(const pvs__vx_fbox *fb) {
	const pvs_scene *s = fb->s;
	const pvs__vx_topo *tp = fb->tp;
	const uint32_t *d = fb->d;
	const size_t *stride = fb->stride;
	uint8_t *bits = fb->fl->bits, *col = fb->fl->col;
	uint32_t up = fb->up, pass, t, k;
	int u = fb->u, v = fb->v, axes[3], any;
	size_t vi;
	pvs__vx_colvisit cv;
	pvs__vx_flood_colvisit(fb, &cv, axes);
	memset(col, 0, fb->ncol);
	for (pass = 0, any = 1; any && pass < 8; ++pass) {
		cv.pass = pass;
		for (t = tp->comp_first[fb->comp]; t < tp->comp_first[fb->comp + 1]; ++t) {
			uint32_t tri = tp->tris[t];
			double pt[3][3];
			for (k = 0; k < 3; ++k) cv.tri[k] = s->positions + 3 * (size_t)s->indices[3 * (size_t)tri + k];
			pvs__vx_tri_points(s, tri, pt);
			pvs__vx_scan(fb->gr, pt[0], 3, axes, 2, fb->m, fb->lo, fb->hi, pvs__vx_cross_visit, &cv);
		}
		any = 0;
		for (vi = 0; vi < fb->ncol; ++vi) {
			uint32_t idx[3];
			if (!(col[vi] & 0x80)) continue;
			idx[u] = (uint32_t)(vi % d[u]); idx[v] = (uint32_t)(vi / d[u]);
			for (idx[up] = 0; idx[up] < d[up]; ++idx[up]) {
				size_t x = idx[0] + stride[1] * idx[1] + stride[2] * idx[2];
				bits[x] &= (uint8_t)~PVS__G_F;
				if (pass + 1 == 8) bits[x] |= PVS__G_B;
			}
			if (pass + 1 == 8) { col[vi] = 0xff; ++fb->o->info.undecided_columns; }
			else { col[vi] = (uint8_t)(pass + 1); any = 1; }
		}
	}
	for (vi = 0; vi < fb->ncol; ++vi) {
		uint32_t idx[3], acc = 0;
		idx[u] = (uint32_t)(vi % d[u]); idx[v] = (uint32_t)(vi / d[u]);
		for (idx[up] = d[up]; idx[up]-- > 0;) {
			size_t x = idx[0] + stride[1] * idx[1] + stride[2] * idx[2];
			if (acc && !(bits[x] & (PVS__G_T | PVS__G_B))) bits[x] |= PVS__G_W;
			acc ^= (bits[x] & PVS__G_F) != 0;
		}
	}
}

/* 1 if cell cb grown by m meets a triangle of K. */
PVS__STATIC int pvs__vx_flood_cell_touches(const pvs__vx_fbox *fb, const pvs_box *cb) {
	const pvs_scene *s = fb->s;
	const pvs__vx_topo *tp = fb->tp;
	double cc[3], hs[3];
	uint32_t t;
	int kk, touches = 0;
	for (kk = 0; kk < 3; ++kk) {
		cc[kk] = 0.5 * ((double)cb->min[kk] + cb->max[kk]);
		hs[kk] = 0.5 * ((double)cb->max[kk] - cb->min[kk]) + fb->m;
	}
	for (t = tp->comp_first[fb->comp]; t < tp->comp_first[fb->comp + 1] && !touches; ++t) {
		uint32_t tri = tp->tris[t], e;
		double pt[3][3];
		int out = 0;
		for (e = 0; e < 3; ++e)
			for (kk = 0; kk < 3; ++kk) pt[e][kk] = s->positions[3 * (size_t)s->indices[3 * (size_t)tri + e] + kk];
		for (kk = 0; kk < 3 && !out; ++kk)
			out = pvs__dmin(pt[0][kk], pvs__dmin(pt[1][kk], pt[2][kk])) > cc[kk] + hs[kk] ||
				  pvs__dmax(pt[0][kk], pvs__dmax(pt[1][kk], pt[2][kk])) < cc[kk] - hs[kk];
		if (!out) touches = pvs__tri_aabb(cc, hs, pt[0], pt[1], pt[2]);
	}
	return touches;
}

/* Step 4's w of cell cb (box voxels r0..r1): -1 (all nodes) when cb grown by m meets K; else 0 with out_w0 (it leaves
   the box above ground); else a pure voxel's it overlaps by over m, or its own ray's. */
PVS__STATIC int pvs__vx_flood_cell_w(const pvs__vx_fbox *fb, const pvs_box *cb, const uint32_t r0[3],
									 const uint32_t r1[3], int out_w0) {
	const uint8_t *bits = fb->fl->bits;
	const uint32_t *lo = fb->lo, *hi = fb->hi;
	const size_t *stride = fb->stride;
	uint32_t s0[3], s1[3], a, b, c;
	int touches = 0, maybe = 0, wc = -1, kk;
	for (c = r0[2]; c <= r1[2] && !maybe; ++c)
		for (b = r0[1]; b <= r1[1] && !maybe; ++b)
			for (a = r0[0]; a <= r1[0] && !maybe; ++a)
				maybe = (bits[(a - lo[0]) + stride[1] * (b - lo[1]) + stride[2] * (c - lo[2])] &
						 (PVS__G_T | PVS__G_B)) != 0;
	if (maybe) touches = pvs__vx_flood_cell_touches(fb, cb);
	if (!touches && out_w0) wc = 0;
	if (!touches && !out_w0) {
		for (kk = 0; kk < 3; ++kk) {
			pvs__vx_grange(fb->gr, kk, cb->min[kk], cb->max[kk], -fb->m, s0 + kk, s1 + kk);
			if (s0[kk] < lo[kk]) s0[kk] = lo[kk];
			if (s1[kk] > hi[kk]) s1[kk] = hi[kk];
		}
		for (c = s0[2]; c <= s1[2] && wc < 0; ++c)
			for (b = s0[1]; b <= s1[1] && wc < 0; ++b)
				for (a = s0[0]; a <= s1[0] && wc < 0; ++a) {
					uint8_t f = bits[(a - lo[0]) + stride[1] * (b - lo[1]) + stride[2] * (c - lo[2])];
					if (!(f & (PVS__G_T | PVS__G_B))) wc = (f & PVS__G_W) != 0;
				}
		if (wc < 0) wc = pvs__vx_point_parity(fb->s, fb->tp, fb->comp, cb);
	}
	return wc;
}

/* Step 4's cells: the unexcluded ones of the buckets under the box that meet it (grown by m), each once (fl->stamp:
   stamp; stamp + 1 if it meets), into fl->near_cells with their w, near_flag 1 when sticking out. Returns their
   number. */
PVS__STATIC uint32_t pvs__vx_flood_near(const pvs__vx_fbox *fb, uint32_t stamp) {
	pvs__vx_flood *fl = fb->fl;
	const pvs__vx_grid *gr = fb->gr;
	const uint32_t *lo = fb->lo, *hi = fb->hi;
	uint32_t up = fb->up, bu, bv, bu0, bu1, bv0, bv1, q, nnear = 0;
	int u = fb->u, v = fb->v;
	double h = gr->h, m = fb->m;
	pvs__vx_grange(&fl->bucket_grid, u, gr->origin[u] + lo[u] * h, gr->origin[u] + (hi[u] + 1) * h, m, &bu0, &bu1);
	pvs__vx_grange(&fl->bucket_grid, v, gr->origin[v] + lo[v] * h, gr->origin[v] + (hi[v] + 1) * h, m, &bv0, &bv1);
	for (bv = bv0; bv <= bv1; ++bv)
		for (bu = bu0; bu <= bu1; ++bu) {
			size_t bk = (size_t)bv * fl->bnu + bu;
			for (q = fl->bucket_first[bk]; q < fl->bucket_first[bk + 1]; ++q) {
				uint32_t cid = fl->bucket_cells[q], r0[3], r1[3];
				const pvs_box *cb = fl->cells + cid;
				int kk, out_w0 = 0, stick = 0;
				if (fl->stamp[cid] >= stamp || fl->excluded[cid]) continue;
				fl->stamp[cid] = stamp;
				for (kk = 0; kk < 3; ++kk) {
					pvs__vx_grange(gr, kk, cb->min[kk], cb->max[kk], m, r0 + kk, r1 + kk);
					if (r0[kk] > r1[kk] || r1[kk] < lo[kk] || r0[kk] > hi[kk]) break;
				}
				if (kk < 3) continue;
				fl->stamp[cid] = stamp + 1;
				for (kk = 0; kk < 3; ++kk) {
					if (r0[kk] < lo[kk] || r1[kk] > hi[kk]) stick = 1;
					if (r1[kk] > hi[kk] || (r0[kk] < lo[kk] && ((uint32_t)kk != up || lo[up] > 1))) out_w0 = 1;
					if (r0[kk] < lo[kk]) r0[kk] = lo[kk];
					if (r1[kk] > hi[kk]) r1[kk] = hi[kk];
				}
				fl->near_cells[nnear] = cid;
				fl->near_w[nnear] = (signed char)pvs__vx_flood_cell_w(fb, cb, r0, r1, out_w0);
				fl->near_flag[nnear] = (uint8_t)stick;
				++nnear;
			}
		}
	return nnear;
}

/* Step 4, the sources: the cells meeting the box (one clear of K by m is convex and free: its voxels get the node of
   its one w; else every node), and the outside when a cell lies partly outside. Leaking cells, boxes poking through
   a wall of a closed level into a mesh's faceless void, would join every wall's interior to the flood. So when
   under half the cells in use lie outside the box, the outside is flooded first, and the cells outside, partly
   outside or reached are excluded if together under half. An excluded cell seeds no later flood and gets no
   occluder (pvs_shrink_cell sets every object for it); for the others the argument holds unchanged. Leaves the
   sources in fl->queue; returns pvs__vx_flood_run's ext. */
PVS__STATIC int pvs__vx_flood_sources(const pvs__vx_fbox *fb, size_t *qh_io, size_t *qt_io) {
	pvs__vx_flood *fl = fb->fl;
	uint8_t *bits = fl->bits;
	uint32_t *queue = fl->queue;
	uint32_t nnear, q, stamp, active = fl->cell_count - fl->excluded_count, nout, excl = 0;
	size_t qh = 0, qt = 0, vi;
	int ext;
	fl->stamp_next += 2;
	stamp = fl->stamp_next - 1;
	nnear = pvs__vx_flood_near(fb, stamp);
	if (!fl->keep_leaks && nnear &&
		2 * (active - nnear) < active) { /* mostly inside: which cells does the outside reach? */
		pvs__vx_flood_run(bits, queue, &qh, &qt, fb->d, fb->stride, fb->lo, fb->up, 1);
		nout = active - nnear;
		for (q = 0; q < nnear; ++q) {
			if (!fl->near_flag[q] &&
				pvs__vx_seed(fb->gr, fl->cells + fl->near_cells[q], fb->lo, fb->hi, fb->stride, fb->m, fl->near_w[q],
							 bits, queue, &qt, 1))
				fl->near_flag[q] = 2;
			nout += fl->near_flag[q] != 0;
		}
		if (nout && 2 * nout < active) {
			excl = 1;
			for (q = 0; q < nnear; ++q)
				if (fl->near_flag[q]) { fl->excluded[fl->near_cells[q]] = 1; ++fl->excluded_count; }
			for (q = 0; q < fl->cell_count; ++q)
				if (!fl->excluded[q] && fl->stamp[q] != stamp + 1) { fl->excluded[q] = 1; ++fl->excluded_count; }
		}
		for (vi = 0; vi < fb->nvox; ++vi) bits[vi] &= (uint8_t)~(PVS__G_R0 | PVS__G_R1);
	}
	qh = qt = 0;
	ext = 0;
	for (q = 0; q < nnear; ++q) {
		if (excl && fl->near_flag[q]) continue;
		if (fl->near_flag[q] & 1) ext = 1;
		pvs__vx_seed(fb->gr, fl->cells + fl->near_cells[q], fb->lo, fb->hi, fb->stride, fb->m, fl->near_w[q], bits,
					 queue, &qt, 0);
	}
	if (!excl && nnear < active) ext = 1;
	*qh_io = qh;
	*qt_io = qt;
	return ext;
}

/* Floods component K on grid gr, box lo..hi (inclusive, lo[up] >= 1): PVS__G_T/B/W and reached nodes into fl->bits;
   returns 0 when the outside was never entered. mark_touched: PVS__VX_TOUCHED too (gr: the occluders' grid). */
PVS__STATIC int pvs__vx_flood_component(pvs_occluders *o, const pvs__vx_grid *gr, const pvs__vx_topo *tp, uint32_t comp,
										const uint32_t lo[3], const uint32_t hi[3], double m, pvs__vx_flood *fl,
										int mark_touched) {
	pvs__vx_fbox fb;
	size_t qh = 0, qt = 0;
	uint32_t k;
	int ext;
	memset(&fb, 0, sizeof(fb));
	fb.o = o;
	fb.s = o->scene;
	fb.gr = gr;
	fb.tp = tp;
	fb.comp = comp;
	fb.lo = lo;
	fb.hi = hi;
	fb.m = m;
	fb.fl = fl;
	fb.up = fb.s->up_axis;
	pvs__ground_axes(fb.up, &fb.u, &fb.v);
	for (k = 0; k < 3; ++k) fb.d[k] = hi[k] - lo[k] + 1;
	fb.stride[0] = 1;
	fb.stride[1] = fb.d[0];
	fb.stride[2] = (size_t)fb.d[0] * fb.d[1];
	fb.nvox = fb.stride[2] * fb.d[2];
	fb.ncol = (size_t)fb.d[fb.u] * fb.d[fb.v];
	memset(fl->bits, 0, fb.nvox);
	pvs__vx_flood_touched(&fb, mark_touched);
	pvs__vx_flood_sheets(&fb);
	pvs__vx_flood_parity(&fb);
	ext = pvs__vx_flood_sources(&fb, &qh, &qt);
	return pvs__vx_flood_run(fl->bits, fl->queue, &qh, &qt, fb.d, fb.stride, lo, fb.up, ext);
}

/* Certifies K on the occluders' grid: pure voxels whose node the flood missed are solid, and all outside the box (but
   the ground) when it never entered it. */
PVS__STATIC void pvs__vx_certify(pvs_occluders *o, const pvs__vx_topo *tp, uint32_t comp, const uint32_t lo[3],
								 const uint32_t hi[3], double m, pvs__vx_flood *fl) {
	uint32_t d[3], i, j, k;
	size_t stride[3];
	const uint8_t *bits = fl->bits;
	int ext = pvs__vx_flood_component(o, &o->grid, tp, comp, lo, hi, m, fl, 1);
	for (k = 0; k < 3; ++k) d[k] = hi[k] - lo[k] + 1;
	stride[1] = d[0];
	stride[2] = (size_t)d[0] * d[1];
	for (k = 0; k < d[2]; ++k)
		for (j = 0; j < d[1]; ++j)
			for (i = 0; i < d[0]; ++i) {
				uint8_t f = bits[i + stride[1] * j + stride[2] * k];
				if (f & (PVS__G_T | PVS__G_B)) continue;
				if (f & ((f & PVS__G_W) ? PVS__G_R1 : PVS__G_R0)) continue;
				o->state[pvs__vx_index(o, lo[0] + i, lo[1] + j, lo[2] + k)] |= PVS__VX_SOLID;
			}
	if (!ext)
		for (k = 0; k < o->n[2]; ++k)
			for (j = 0; j < o->n[1]; ++j)
				for (i = 0; i < o->n[0]; ++i) {
					size_t x = pvs__vx_index(o, i, j, k);
					if (i >= lo[0] && i <= hi[0] && j >= lo[1] && j <= hi[1] && k >= lo[2] && k <= hi[2]) continue;
					if (!(o->state[x] & PVS__VX_GROUND)) o->state[x] |= PVS__VX_SOLID;
				}
}

/* ---- 2.5D occluders: proved-solid columns at a finer resolution, eroded by distance ----

   Each component is flooded again on its own grid (voxel eps, grown within budgets). A column-map square (side
   eps / 2, larger past PVS__VX_MAP_BUDGET) has as solid height the least top of the proved-solid runs on the ground
   in the voxel columns it overlaps, and as occluder height (Wonka 2000 §2, appendix: shrunk by eps) that, cut to eps
   below the component's triangles within eps of it: the eps-ball of every point below is free of the component and
   joined to proved solid, so a sight line through it meets a triangle first. Squares grow by a margin above the
   coordinates' float precision. */

#define PVS__VX_BOX_BUDGET (1u << 23)
#define PVS__VX_MAP_BUDGET (1u << 22)

PVS__STATIC int pvs__vx_float_cmp(const void *x, const void *y) {
	float a = *(const float *)x, b = *(const float *)y;
	return a < b ? -1 : a > b;
}

/* Least height of triangle p clipped to the prism over the octagon {x0 <= u <= x1, y0 <= v <= y1,
   s0 <= u + v <= s1, d0 <= u - v <= d1}; DBL_MAX if none. */
PVS__STATIC double pvs__vx_clip_min_height(const double p[3][3], int u, int v, int up, const double lim[8]) {
	static const double nu[8] = {-1, 1, 0, 0, -1, 1, -1, 1}, nv[8] = {0, 0, -1, 1, -1, 1, 1, -1};
	double a[16][3], b[16][3], best = DBL_MAX;
	int n = 3, side, i, k;
	for (i = 0; i < 3; ++i)
		for (k = 0; k < 3; ++k) a[i][k] = p[i][k];
	for (side = 0; side < 8 && n > 0; ++side) { /* keep nu u + nv v <= lim */
		int m = 0;
		for (i = 0; i < n; ++i) {
			const double *c = a[i], *d = a[(i + 1) % n];
			double fc = lim[side] - (nu[side] * c[u] + nv[side] * c[v]),
				   fd = lim[side] - (nu[side] * d[u] + nv[side] * d[v]);
			if (fc >= 0.0) { for (k = 0; k < 3; ++k) b[m][k] = c[k]; ++m; }
			if ((fc >= 0.0) != (fd >= 0.0)) {
				double t = fc / (fc - fd);
				for (k = 0; k < 3; ++k) b[m][k] = c[k] + t * (d[k] - c[k]);
				++m;
			}
		}
		n = m;
		for (i = 0; i < n; ++i)
			for (k = 0; k < 3; ++k) a[i][k] = b[i][k];
	}
	for (i = 0; i < n; ++i) best = pvs__dmin(best, a[i][up]);
	return best;
}

/* pvs__vx_scan's visitor: a triangle's least height near each square of the column map. */
typedef struct pvs__vx_tminvisit {
	const pvs__vx_grid *gr;
	double p[3][3], e, margin; /* the triangle; near = within e */
	double zlo;                /* its lowest corner's height */
	double gu, gv, slack;      /* sloped: the plane's height gradient along u, v; rounding slack */
	int sloped;
	int u, v, up;
	float *tmin;               /* per square from (su0, sv0), rows of row */
	uint32_t su0, sv0, row;
} pvs__vx_tminvisit;
/* Lower bounds letting pvs__vx_tmin_visit skip the clip (stacked triangles meet a square many times): the lowest corner
   and, unless steep, the plane, with slack for rounding. */
PVS__STATIC void pvs__vx_tmin_plane(pvs__vx_tminvisit *tv) {
	const double *a = tv->p[0], *b = tv->p[1], *c = tv->p[2];
	int u = tv->u, v = tv->v, up = tv->up;
	double e1[3], e2[3], n[3], mag;
	int k;
	tv->zlo = pvs__dmin(a[up], pvs__dmin(b[up], c[up]));
	for (k = 0; k < 3; ++k) { e1[k] = b[k] - a[k]; e2[k] = c[k] - a[k]; }
	n[0] = e1[1] * e2[2] - e1[2] * e2[1];
	n[1] = e1[2] * e2[0] - e1[0] * e2[2];
	n[2] = e1[0] * e2[1] - e1[1] * e2[0];
	mag = pvs__dabs(n[0]) + pvs__dabs(n[1]) + pvs__dabs(n[2]);
	tv->sloped = pvs__dabs(n[up]) > 1e-3 * mag; /* slope below 1000: the plane's bound is useful */
	if (!tv->sloped) return;
	tv->gu = n[u] / n[up];
	tv->gv = n[v] / n[up];
	tv->slack = 1e-9 *
		(pvs__dabs(a[up]) + pvs__dabs(b[up]) + pvs__dabs(c[up]) +
		 (pvs__dabs(tv->gu) + pvs__dabs(tv->gv)) *
			 (pvs__dabs(a[u]) + pvs__dabs(a[v]) + pvs__dabs(b[u]) + pvs__dabs(b[v]) + pvs__dabs(c[u]) +
			  pvs__dabs(c[v]) + 1.0));
}
PVS__STATIC void pvs__vx_tmin_visit(void *user, const uint32_t at[3]) {
	const pvs__vx_tminvisit *tv = (const pvs__vx_tminvisit *)user;
	uint32_t i = at[tv->u], j = at[tv->v];
	size_t x = (size_t)(j - tv->sv0) * tv->row + (i - tv->su0);
	double h = tv->gr->h, e = tv->e, x0 = tv->gr->origin[tv->u] + i * h, y0 = tv->gr->origin[tv->v] + j * h, z;
	double lim[8], x1 = x0 + h, y1 = y0 + h, ed = e * 1.4142135623730951 * (1.0 + 1e-12);
	/* the square grown by the octagon around the disc of radius e: holds every point within e */
	lim[0] = -(x0 - e); lim[1] = x1 + e; lim[2] = -(y0 - e); lim[3] = y1 + e;
	lim[4] = -(x0 + y0 - ed); lim[5] = x1 + y1 + ed; lim[6] = -(x0 - y1 - ed); lim[7] = x1 - y0 + ed;
	z = tv->zlo; /* lower bound of the clip's height: the lowest corner, or the plane's least over the square */
	if (tv->sloped) {
		double zp = tv->p[0][tv->up] - tv->gu * ((tv->gu > 0.0 ? x0 - e : x1 + e) - tv->p[0][tv->u]) -
					tv->gv * ((tv->gv > 0.0 ? y0 - e : y1 + e) - tv->p[0][tv->v]);
		z = pvs__dmax(z, zp - tv->slack);
	}
	if (pvs__f_down(z - tv->margin) >= tv->tmin[x]) return;
	z = pvs__vx_clip_min_height((const double(*)[3])tv->p, tv->u, tv->v, tv->up, lim);
	if (z < DBL_MAX && pvs__f_down(z - tv->margin) < tv->tmin[x]) tv->tmin[x] = pvs__f_down(z - tv->margin);
}

/* tmin, row-major over map squares sq0..sq1: the least height of K's triangles within e of each (pvs__vx_tmin_visit),
   FLT_MAX if none. */
PVS__STATIC void pvs__vx_columns_tmin(const pvs_occluders *o, const pvs__vx_topo *tp, uint32_t comp,
									  const uint32_t sq0[3], const uint32_t sq1[3], double e, double margin,
									  float *tmin) {
	const pvs__vx_cols *cm = &o->cols;
	pvs__vx_tminvisit tv;
	uint32_t up = o->scene->up_axis, t;
	int u, v, axes[3];
	size_t a, nsub;
	pvs__ground_axes(up, &u, &v);
	nsub = (size_t)(sq1[u] - sq0[u] + 1) * (sq1[v] - sq0[v] + 1);
	for (a = 0; a < nsub; ++a) tmin[a] = FLT_MAX;
	memset(&tv, 0, sizeof(tv));
	tv.gr = &cm->grid;
	tv.u = u;
	tv.v = v;
	tv.up = (int)up;
	tv.e = e;
	tv.margin = margin;
	tv.tmin = tmin;
	tv.su0 = sq0[u];
	tv.sv0 = sq0[v];
	tv.row = sq1[u] - sq0[u] + 1;
	axes[0] = u;
	axes[1] = v;
	axes[2] = (int)up;
	for (t = tp->comp_first[comp]; t < tp->comp_first[comp + 1]; ++t) {
		pvs__vx_tri_points(o->scene, tp->tris[t], tv.p);
		pvs__vx_tmin_plane(&tv);
		pvs__vx_scan(&cm->grid, tv.p[0], 3, axes, 2, e, sq0, sq1, pvs__vx_tmin_visit, &tv);
	}
}

/* One component's pass of the column map: its flood, runs on the ground, the squares' solid and occluder heights.
   Returns OUT_OF_MEMORY or PVS_OK. */
PVS__STATIC pvs_result pvs__vx_columns_component(pvs_occluders *o, const pvs__vx_topo *tp, uint32_t comp,
												 const pvs__vx_grid *gk, const uint32_t lo[3], const uint32_t hi[3],
												 double m, double eps, double margin, pvs__vx_flood *fl) {
	uint32_t sq0[3], sq1[3];
	const pvs_scene *s = o->scene;
	pvs__vx_cols *cm = &o->cols;
	uint32_t up = s->up_axis, d[3], a, b, su0, su1, sv0, sv1, k;
	int u, v, ext;
	size_t stride[3], nsub, ncol;
	double hk = gk->h, g = o->ground, e = eps + margin;
	float *runh = NULL, *tmin = NULL;
	pvs__ground_axes(up, &u, &v);
	ext = pvs__vx_flood_component(o, gk, tp, comp, lo, hi, m, fl, 0);
	for (k = 0; k < 3; ++k) d[k] = hi[k] - lo[k] + 1;
	stride[0] = 1;
	stride[1] = d[0];
	stride[2] = (size_t)d[0] * d[1];
	ncol = (size_t)d[u] * d[v];
	pvs__vx_grange(&cm->grid, u, gk->origin[u] + lo[u] * hk, gk->origin[u] + (hi[u] + 1) * hk, 0.0, &su0, &su1);
	pvs__vx_grange(&cm->grid, v, gk->origin[v] + lo[v] * hk, gk->origin[v] + (hi[v] + 1) * hk, 0.0, &sv0, &sv1);
	if (su0 > su1 || sv0 > sv1) return PVS_OK;
	nsub = (size_t)(su1 - su0 + 1) * (sv1 - sv0 + 1);
	runh = (float *)pvs__alloc_array(&o->allocator, ncol, sizeof(float));
	tmin = (float *)pvs__alloc_array(&o->allocator, nsub, sizeof(float));
	if (!runh || !tmin) {
		pvs__free_array(&o->allocator, runh, ncol, sizeof(float));
		pvs__free_array(&o->allocator, tmin, nsub, sizeof(float));
		return PVS_ERROR_OUT_OF_MEMORY;
	}
	/* runs of proved-solid voxels from the ground (layer 1 of the box) */
	for (b = 0; b < d[v]; ++b)
		for (a = 0; a < d[u]; ++a) {
			uint32_t idx[3], run = 0;
			idx[u] = a; idx[v] = b;
			if (lo[up] == 1)
				for (idx[up] = 0; idx[up] < d[up]; ++idx[up], ++run) {
					uint8_t f = fl->bits[idx[0] + stride[1] * idx[1] + stride[2] * idx[2]];
					if ((f & (PVS__G_T | PVS__G_B)) || (f & ((f & PVS__G_W) ? PVS__G_R1 : PVS__G_R0))) break;
				}
			runh[(size_t)b * d[u] + a] = run ? (float)(gk->origin[up] + (lo[up] + run) * hk) : -FLT_MAX;
		}
	sq0[u] = su0; sq0[v] = sv0; sq0[up] = 0;
	sq1[u] = su1; sq1[v] = sv1; sq1[up] = 0;
	pvs__vx_columns_tmin(o, tp, comp, sq0, sq1, e, margin, tmin);
	for (b = sv0; b <= sv1; ++b)
		for (a = su0; a <= su1; ++a) {
			size_t x = (size_t)b * cm->nu + a, xs = (size_t)(b - sv0) * (su1 - su0 + 1) + (a - su0);
			double x0 = cm->grid.origin[u] + a * cm->grid.h, y0 = cm->grid.origin[v] + b * cm->grid.h, hsub = DBL_MAX,
				   top;
			uint32_t c0, c1, r0, r1, cc, rr;
			/* the voxel columns the square overlaps (genuinely: a hair inside it) */
			pvs__vx_grange(gk, u, x0, x0 + cm->grid.h, -1e-9 * cm->grid.h, &c0, &c1);
			pvs__vx_grange(gk, v, y0, y0 + cm->grid.h, -1e-9 * cm->grid.h, &r0, &r1);
			if (c0 > c1 || r0 > r1) continue;
			for (rr = r0; rr <= r1 && hsub > -FLT_MAX; ++rr)
				for (cc = c0; cc <= c1 && hsub > -FLT_MAX; ++cc) {
					if (cc < lo[u] || cc > hi[u] || rr < lo[v] || rr > hi[v]) { hsub = -FLT_MAX; break; }
					hsub = pvs__dmin(hsub, runh[(size_t)(rr - lo[v]) * d[u] + (cc - lo[u])]);
				}
			if (!(hsub > g)) continue;
			if ((float)hsub > cm->solid[x]) cm->solid[x] = pvs__f_down(hsub);
			top = pvs__dmin(hsub, (double)tmin[xs] - eps);
			if (top > g && pvs__f_down(top) > cm->top[x]) cm->top[x] = pvs__f_down(top);
		}
	if (!ext) { /* every viewer is inside the box: all outside it is solid (to the grid's top); squares
				   more than eps (and the margin) away from the box are occluders up there */
		float sky = pvs__f_down(o->origin[up] + o->n[up] * o->h);
		uint32_t e0, e1, f0, f1;
		pvs__vx_grange(&cm->grid, u, gk->origin[u] + lo[u] * hk, gk->origin[u] + (hi[u] + 1) * hk, e, &e0, &e1);
		pvs__vx_grange(&cm->grid, v, gk->origin[v] + lo[v] * hk, gk->origin[v] + (hi[v] + 1) * hk, e, &f0, &f1);
		for (b = 0; b < cm->nv; ++b)
			for (a = 0; a < cm->nu; ++a) {
				size_t x = (size_t)b * cm->nu + a;
				if (a >= su0 && a <= su1 && b >= sv0 && b <= sv1) continue;
				cm->solid[x] = sky;
				if (!(a >= e0 && a <= e1 && b >= f0 && b <= f1)) cm->top[x] = sky;
			}
	}
	pvs__free_array(&o->allocator, runh, ncol, sizeof(float));
	pvs__free_array(&o->allocator, tmin, nsub, sizeof(float));
	return PVS_OK;
}

typedef struct pvs__vx_chainbuf {
	pvs_facade_chain *chains;
	size_t *first;           /* per chain: its first point (pointers are set at the end) */
	float *points;           /* 2 floats per point */
	size_t count, cap, cap_first, npts, cap_pts;
} pvs__vx_chainbuf;


/* (b - a) x (c - a) on integer points (exact). */
PVS__STATIC int64_t pvs__vx_orient_i(const int32_t *a, const int32_t *b, const int32_t *c) {
	return (int64_t)(b[0] - a[0]) * (c[1] - a[1]) - (int64_t)(b[1] - a[1]) * (c[0] - a[0]);
}
/* 1 if closed segments p-q and r-t meet (exact). */
PVS__STATIC int pvs__vx_seg_meet_i(const int32_t *p, const int32_t *q, const int32_t *r, const int32_t *t) {
	int64_t d1 = pvs__vx_orient_i(p, q, r), d2 = pvs__vx_orient_i(p, q, t), d3 = pvs__vx_orient_i(r, t, p),
			d4 = pvs__vx_orient_i(r, t, q);
	if (((d1 > 0 && d2 > 0) || (d1 < 0 && d2 < 0)) || ((d3 > 0 && d4 > 0) || (d3 < 0 && d4 < 0))) return 0;
	if (d1 == 0 && d2 == 0) /* collinear: do the projections overlap? */
		return (p[0] < q[0] ? p[0] : q[0]) <= (r[0] > t[0] ? r[0] : t[0]) &&
			(r[0] < t[0] ? r[0] : t[0]) <= (p[0] > q[0] ? p[0] : q[0]) &&
			(p[1] < q[1] ? p[1] : q[1]) <= (r[1] > t[1] ? r[1] : t[1]) &&
			(r[1] < t[1] ? r[1] : t[1]) <= (p[1] > q[1] ? p[1] : q[1]);
	return 1;
}

/* Simplifies a loop of n integer points (region on the left) from the inside, in place (pt: room for 2n): from each
   kept point to the farthest later one whose chord keeps the skipped points right of it or on it, at most a square off
   (area lost, never added), meeting no other loop edge. A slanted wall's staircase becomes long edges, whose shadows
   cover whole cull-map cells. Returns the count. */
PVS__STATIC uint32_t pvs__vx_simplify(int32_t *pt, uint32_t n) {
	uint32_t i = 0, kept = 0, j, k, start;
	int32_t *out;
	if (n < 5) return n;
	/* start at a point that stays: the lowest-leftmost is a convex corner */
	start = 0;
	for (k = 1; k < n; ++k)
		if (pt[2 * k + 1] < pt[2 * start + 1] || (pt[2 * k + 1] == pt[2 * start + 1] && pt[2 * k] < pt[2 * start]))
			start = k;
	out = pt + 2 * n;
	while (i < n) {
		uint32_t best = i + 1;
		const int32_t *a = pt + 2 * ((start + i) % n);
		for (j = i + 2; j <= (i ? n : n - 1); ++j) {
			const int32_t *b = pt + 2 * ((start + j) % n);
			int ok = 1;
			double len2 = (double)(b[0] - a[0]) * (b[0] - a[0]) + (double)(b[1] - a[1]) * (b[1] - a[1]);
			for (k = i + 1; k < j && ok; ++k) { /* right of the chord or on it, at most a square off */
				int64_t o = pvs__vx_orient_i(a, b, pt + 2 * ((start + k) % n));
				ok = o <= 0 && (double)o * (double)o <= len2;
			}
			if (!ok) break;
			for (k = 0; k < n && ok; ++k) { /* no other loop edge touches the chord */
				uint32_t e0 = (start + k) % n, e1 = (start + k + 1) % n;
				if (k >= i && k < j) continue;                  /* edges the chord replaces */
				if (k + 1 == i || (k == j % n && j < n) || (j == n && k == 0) || (i == 0 && k + 1 == n)) {
					/* edges sharing an end with the chord may only touch it there */
					const int32_t *c0 = pt + 2 * e0, *c1 = pt + 2 * e1;
					int64_t o0 = pvs__vx_orient_i(a, b, c0), o1 = pvs__vx_orient_i(a, b, c1);
					if (o0 == 0 && o1 == 0) ok = 0; /* collinear overlap */
					continue;
				}
				if (pvs__vx_seg_meet_i(a, b, pt + 2 * e0, pt + 2 * e1)) ok = 0;
			}
			if (ok) best = j;
		}
		out[2 * kept] = a[0];
		out[2 * kept + 1] = a[1];
		++kept;
		i = best;
	}
	memcpy(pt, out, (size_t)kept * 2 * sizeof(int32_t));
	return kept;
}

/* Traces the boundary loops of the squares set in mask (w x h, empty frame around) with the set on the left, turning
   left where diagonal squares meet (4-connected). Each, simplified, becomes a chain of heights [base, top], point
   (i, j) at (ox + i c, oy + j c): outer (counter-clockwise) loops closed, holes open, back to their first point (a
   hole is not solid). used: 4 (w + 1) (h + 1) bytes. Returns 0 when out of memory. */
PVS__STATIC int pvs__vx_trace(const pvs_allocator *al, pvs__vx_chainbuf *cb, const uint8_t *mask, uint32_t w,
							  uint32_t h, double ox, double oy, double c, float base, float top, uint8_t *used,
							  int32_t **ip, size_t *ipcap) {
	/* direction d: 0 +i, 1 +j, 2 -i, 3 -j; the squares left and right of an edge leaving vertex (x, y) */
	static const int di[4] = {1, 0, -1, 0}, dj[4] = {0, 1, 0, -1};
	static const int lqi[4] = {0, -1, -1, 0}, lqj[4] = {0, 0, -1, -1}, rqi[4] = {0, 0, -1, -1}, rqj[4] = {-1, 0, 0, -1};
	/* square (i, j)'s side toward neighbour n (below, right, above, left) leaves vertex (i, j) + v0[n] along n */
	static const int ni[4] = {0, 1, 0, -1}, nj[4] = {-1, 0, 1, 0}, v0i[4] = {0, 1, 1, 0}, v0j[4] = {0, 0, 1, 1};
	uint32_t i, j;
	memset(used, 0, (size_t)(w + 1) * (h + 1) * 4);
#define PVS__IN(x, y) \
	((x) >= 0 && (y) >= 0 && (uint32_t)(x) < w && (uint32_t)(y) < h && mask[(size_t)(y)*w + (uint32_t)(x)])
	for (j = 0; j < h; ++j)
		for (i = 0; i < w; ++i) {
			int side;
			if (!mask[(size_t)j * w + i]) continue;
			for (side = 0; side < 4; ++side) {
				uint32_t vx, vy, start, e, n = 0, kept = 0, q;
				size_t first;
				int d = side;
				float *pt;
				int64_t area2 = 0;
				if (PVS__IN((int)i + ni[side], (int)j + nj[side])) continue;
				vx = i + (uint32_t)v0i[side];
				vy = j + (uint32_t)v0j[side];
				start = 4 * (vy * (w + 1) + vx) + (uint32_t)side;
				if (used[start]) continue;
				e = start;
				for (;;) {
					int turn, nd = -1;
					used[e] = 1;
					if (!pvs__grow(al, (void **)ip, ipcap, 2 * (size_t)n + 2, 2 * sizeof(int32_t))) return 0;
					(*ip)[2 * n] = (int32_t)vx;
					(*ip)[2 * n + 1] = (int32_t)vy;
					++n;
					vx = (uint32_t)((int)vx + di[d]);
					vy = (uint32_t)((int)vy + dj[d]);
					for (turn = 0; turn < 3 && nd < 0; ++turn) { /* left, straight, right */
						int cand = turn == 0 ? (d + 1) & 3 : turn == 1 ? d : (d + 3) & 3;
						if (PVS__IN((int)vx + lqi[cand], (int)vy + lqj[cand]) &&
							!PVS__IN((int)vx + rqi[cand], (int)vy + rqj[cand]))
							nd = cand;
					}
					if (nd < 0) return 0; /* not a boundary: cannot happen */
					d = nd;
					e = 4 * (vy * (w + 1) + vx) + (uint32_t)d;
					if (e == start) break;
				}
				/* corners only, then the simplification (the buffer holds 2n points) */
				for (q = 0; q < n; ++q) {
					const int32_t *pp = *ip + 2 * ((q + n - 1) % n), *pc = *ip + 2 * q, *pn = *ip + 2 * ((q + 1) % n);
					if ((pp[0] == pc[0] && pc[0] == pn[0]) || (pp[1] == pc[1] && pc[1] == pn[1])) continue;
					(*ip)[2 * kept] = pc[0];
					(*ip)[2 * kept + 1] = pc[1];
					++kept;
				}
				if (kept < 4) continue;
				kept = pvs__vx_simplify(*ip, kept);
				for (q = 0; q < kept; ++q) {
					const int32_t *pa = *ip + 2 * q, *pb = *ip + 2 * ((q + 1) % kept);
					area2 += (int64_t)pa[0] * pb[1] - (int64_t)pb[0] * pa[1];
				}
				if (kept < 3 || area2 == 0) continue;
				first = cb->npts;
				if (!pvs__grow(al, (void **)&cb->points, &cb->cap_pts, cb->npts + kept + 1, 2 * sizeof(float)))
					return 0;
				pt = cb->points + 2 * first;
				for (q = 0; q <= kept; ++q) {
					if (q == kept && area2 > 0) break; /* only a hole repeats its first point */
					pt[2 * q] = (float)(ox + (*ip)[2 * (q % kept)] * c);
					pt[2 * q + 1] = (float)(oy + (*ip)[2 * (q % kept) + 1] * c);
				}
				cb->npts += area2 > 0 ? kept : kept + 1;
				if (!pvs__grow(al, (void **)&cb->chains, &cb->cap, cb->count + 1, sizeof(pvs_facade_chain)) ||
					!pvs__grow(al, (void **)&cb->first, &cb->cap_first, cb->count + 1, sizeof(size_t)))
					return 0;
				cb->first[cb->count] = first;
				cb->chains[cb->count].points = NULL;
				cb->chains[cb->count].point_count = (uint32_t)(cb->npts - first);
				cb->chains[cb->count].closed = area2 > 0;
				cb->chains[cb->count].base = base;
				cb->chains[cb->count].top = top;
				++cb->count;
			}
		}
#undef PVS__IN
	return 1;
}

/* pvs__vx_build_chains's scratch: per map square a label, queue and member list; per-region buffers over its frame; the
   chains so far. */
typedef struct pvs__vx_chainwork {
	pvs_occluders *o;
	uint32_t *label, *queue, *members; /* per square of the map */
	float *lev;                        /* the region's levels */
	uint8_t *mask, *inl, *used; /* per frame square: sub-region, at or above the level; trace's */
	uint32_t *sub;                     /* per frame square: its sub-region */
	int32_t *ipts;                     /* pvs__vx_trace's points */
	size_t cap, mcap, ucap, lcap, scap, ipcap;
	uint32_t i0, j0, bw, bh;           /* the region's frame: its rectangle plus a square around */
	pvs__vx_chainbuf cb;
} pvs__vx_chainwork;

/* Labels nlab the region of square x (4-connected squares with an occluder height), lists it in w->members, sets its
   frame. Returns its size. */
PVS__STATIC uint32_t pvs__vx_chain_region(pvs__vx_chainwork *w, size_t x, uint32_t nlab) {
	const pvs__vx_cols *cm = &w->o->cols;
	uint32_t *label = w->label, *queue = w->queue, i0, i1, j0, j1, nm = 0;
	size_t qh = 0, qt = 0;
	queue[qt++] = (uint32_t)x;
	label[x] = nlab;
	i0 = i1 = (uint32_t)(x % cm->nu);
	j0 = j1 = (uint32_t)(x / cm->nu);
	while (qh < qt) {
		uint32_t y = queue[qh++], yi = y % cm->nu, yj = y / cm->nu, dd;
		w->members[nm++] = y;
		if (yi < i0) i0 = yi;
		if (yi > i1) i1 = yi;
		if (yj < j0) j0 = yj;
		if (yj > j1) j1 = yj;
		for (dd = 0; dd < 4; ++dd) {
			int zi = (int)yi + (dd == 0) - (dd == 1), zj = (int)yj + (dd == 2) - (dd == 3);
			size_t z;
			if (zi < 0 || zj < 0 || (uint32_t)zi >= cm->nu || (uint32_t)zj >= cm->nv) continue;
			z = (size_t)zj * cm->nu + (uint32_t)zi;
			if (label[z] != 0xffffffffu || cm->top[z] == -FLT_MAX) continue;
			label[z] = nlab;
			queue[qt++] = (uint32_t)z;
		}
	}
	w->i0 = i0;
	w->j0 = j0;
	w->bw = i1 - i0 + 3;
	w->bh = j1 - j0 + 3;
	return nm;
}

/* Level L's chains: per 4-connected sub-region of the region's squares at or above L with a square at L, its boundary
   at L. Returns 0 when out of memory. */
PVS__STATIC int pvs__vx_chain_level(pvs__vx_chainwork *w, uint32_t nm, float L) {
	const pvs__vx_cols *cm = &w->o->cols;
	uint32_t *queue = w->queue, *sub = w->sub, bw = w->bw, bh = w->bh, i0 = w->i0, j0 = w->j0, nsub = 0, k;
	uint8_t *inl = w->inl, *mask = w->mask;
	double g = w->o->ground;
	size_t qh, qt;
	int u, v;
	pvs__ground_axes(w->o->scene->up_axis, &u, &v);
	memset(inl, 0, (size_t)bw * bh);
	for (k = 0; k < nm; ++k) {
		uint32_t y = w->members[k];
		if (cm->top[y] >= L) inl[(size_t)(y / cm->nu - j0 + 1) * bw + (y % cm->nu - i0 + 1)] = 1;
	}
	for (k = 0; k < (size_t)bw * bh; ++k) sub[k] = 0xffffffffu;
	for (k = 0; k < nm; ++k) {
		uint32_t y = w->members[k], s0 = (y / cm->nu - j0 + 1) * bw + (y % cm->nu - i0 + 1), exact = 0;
		if (!inl[s0] || sub[s0] != 0xffffffffu) continue;
		qh = qt = 0;
		queue[qt++] = s0;
		sub[s0] = nsub;
		memset(mask, 0, (size_t)bw * bh);
		while (qh < qt) {
			uint32_t z = queue[qh++], zi = z % bw, zj = z / bw, dd;
			mask[z] = 1;
			if (cm->top[(size_t)(zj + j0 - 1) * cm->nu + (zi + i0 - 1)] == L) exact = 1;
			for (dd = 0; dd < 4; ++dd) {
				uint32_t w2 = dd == 0 ? z + 1 : dd == 1 ? z - 1 : dd == 2 ? z + bw : z - bw;
				if (!inl[w2] || sub[w2] != 0xffffffffu) continue;
				sub[w2] = nsub;
				queue[qt++] = w2;
			}
		}
		++nsub;
		if (exact &&
			!pvs__vx_trace(&w->o->allocator, &w->cb, mask, bw, bh, cm->grid.origin[u] + ((double)i0 - 1.0) * cm->grid.h,
						   cm->grid.origin[v] + ((double)j0 - 1.0) * cm->grid.h, cm->grid.h, (float)g, L, w->used,
						   &w->ipts, &w->ipcap))
			return 0;
	}
	return 1;
}

/* The region's chains: pvs__vx_chain_level for each of its distinct levels, ascending. Returns 0 when out of memory. */
PVS__STATIC int pvs__vx_chain_levels(pvs__vx_chainwork *w, uint32_t nm) {
	const pvs_allocator *al = &w->o->allocator;
	const pvs__vx_cols *cm = &w->o->cols;
	uint32_t bw = w->bw, bh = w->bh, k, nl = 0, li;
	if (!pvs__grow(al, (void **)&w->lev, &w->lcap, nm, sizeof(float))) return 0;
	for (k = 0; k < nm; ++k) w->lev[k] = cm->top[w->members[k]];
	PVS_QSORT(w->lev, nm, sizeof(float), pvs__vx_float_cmp);
	for (k = 0; k < nm; ++k)
		if (k == 0 || w->lev[k] != w->lev[nl - 1]) w->lev[nl++] = w->lev[k];
	if (!pvs__grow(al, (void **)&w->mask, &w->mcap, (size_t)bw * bh, 1) ||
		!pvs__grow(al, (void **)&w->inl, &w->scap, (size_t)bw * bh, 1) ||
		!pvs__grow(al, (void **)&w->sub, &w->ucap, (size_t)bw * bh, sizeof(uint32_t)) ||
		!pvs__grow(al, (void **)&w->used, &w->cap, (size_t)(bw + 1) * (bh + 1) * 4, 1))
		return 0;
	for (li = 0; li < nl; ++li)
		if (!pvs__vx_chain_level(w, nm, w->lev[li])) return 0;
	return 1;
}

/* Hands the chains over: o->chains (points in o->chain_points), o->chain_boxes (ground rectangle x [base, top]).
   Returns OUT_OF_MEMORY or PVS_OK. */
PVS__STATIC pvs_result pvs__vx_chains_hand_over(pvs_occluders *o, const pvs__vx_chainbuf *cb) {
	const pvs_allocator *al = &o->allocator;
	size_t x;
	int u, v;
	pvs__ground_axes(o->scene->up_axis, &u, &v);
	o->chains = (pvs_facade_chain *)pvs__alloc_array(al, cb->count ? cb->count : 1, sizeof(pvs_facade_chain));
	o->chain_boxes = (pvs_box *)pvs__alloc_array(al, cb->count ? cb->count : 1, sizeof(pvs_box));
	o->chain_points = (float *)pvs__alloc_array(al, cb->npts ? 2 * cb->npts : 1, sizeof(float));
	if (!o->chains || !o->chain_boxes || !o->chain_points) return PVS_ERROR_OUT_OF_MEMORY;
	o->chain_count = (uint32_t)cb->count;
	o->chain_point_count = cb->npts;
	if (cb->npts) memcpy(o->chain_points, cb->points, 2 * cb->npts * sizeof(float));
	for (x = 0; x < cb->count; ++x) {
		pvs_facade_chain *ch = o->chains + x;
		pvs_box *bx = o->chain_boxes + x;
		uint32_t k;
		*ch = cb->chains[x];
		ch->points = o->chain_points + 2 * cb->first[x];
		bx->min[u] = bx->max[u] = ch->points[0];
		bx->min[v] = bx->max[v] = ch->points[1];
		for (k = 1; k < ch->point_count; ++k) {
			if (ch->points[2 * k] < bx->min[u]) bx->min[u] = ch->points[2 * k];
			if (ch->points[2 * k] > bx->max[u]) bx->max[u] = ch->points[2 * k];
			if (ch->points[2 * k + 1] < bx->min[v]) bx->min[v] = ch->points[2 * k + 1];
			if (ch->points[2 * k + 1] > bx->max[v]) bx->max[v] = ch->points[2 * k + 1];
		}
		bx->min[o->scene->up_axis] = ch->base;
		bx->max[o->scene->up_axis] = ch->top;
	}
	return PVS_OK;
}

/* The 2.5D chains: occluder heights quantized down to quarter squares; per 4-connected region of squares at or above
   one of its levels, its boundary at that level. A level-set tree: a block of several heights is one chain at its
   lowest plus one per taller part, so no crack opens between heights. */
PVS__STATIC pvs_result pvs__vx_build_chains(pvs_occluders *o) {
	pvs__vx_cols *cm = &o->cols;
	const pvs_allocator *al = &o->allocator;
	size_t n = (size_t)cm->nu * cm->nv, x;
	uint32_t nlab = 0;
	double g = o->ground, qz = 0.25 * cm->grid.h;
	pvs__vx_chainwork w;
	pvs_result res = PVS_ERROR_OUT_OF_MEMORY;
	memset(&w, 0, sizeof(w));
	w.o = o;
	w.label = (uint32_t *)pvs__alloc_array(al, n ? n : 1, sizeof(uint32_t));
	w.queue = (uint32_t *)pvs__alloc_array(al, n ? n : 1, sizeof(uint32_t));
	w.members = (uint32_t *)pvs__alloc_array(al, n ? n : 1, sizeof(uint32_t));
	if (!w.label || !w.queue || !w.members) goto done;
	for (x = 0; x < n; ++x) {
		float t = cm->top[x];
		if (t > (float)g) cm->top[x] = pvs__f_down(g + floor(((double)t - g) / qz) * qz);
		if (!(cm->top[x] > (float)g)) cm->top[x] = -FLT_MAX;
		w.label[x] = 0xffffffffu;
	}
	for (x = 0; x < n; ++x) {
		uint32_t nm;
		if (w.label[x] != 0xffffffffu || cm->top[x] == -FLT_MAX) continue;
		nm = pvs__vx_chain_region(&w, x, nlab++);
		if (!pvs__vx_chain_levels(&w, nm)) goto done;
	}
	res = pvs__vx_chains_hand_over(o, &w.cb);
done:
	pvs__free_array(al, w.label, n ? n : 1, sizeof(uint32_t));
	pvs__free_array(al, w.queue, n ? n : 1, sizeof(uint32_t));
	pvs__free_array(al, w.members, n ? n : 1, sizeof(uint32_t));
	pvs__free_array(al, w.lev, w.lcap, sizeof(float));
	pvs__free_array(al, w.mask, w.mcap, 1);
	pvs__free_array(al, w.inl, w.scap, 1);
	pvs__free_array(al, w.sub, w.ucap, sizeof(uint32_t));
	pvs__free_array(al, w.used, w.cap, 1);
	pvs__free_array(al, w.ipts, w.ipcap, 2 * sizeof(int32_t));
	pvs__free_array(al, w.cb.chains, w.cb.cap, sizeof(pvs_facade_chain));
	pvs__free_array(al, w.cb.first, w.cb.cap_first, sizeof(size_t));
	pvs__free_array(al, w.cb.points, w.cb.cap_pts, 2 * sizeof(float));
	return res;
}

PVS__STATIC pvs_result pvs__vx_pyramid(pvs_occluders *o) {
	pvs__vx_cols *cm = &o->cols;
	uint32_t l, i, j;
	cm->levels = 1;
	cm->lw[0] = cm->nu;
	cm->lh[0] = cm->nv;
	cm->ptop[0] = cm->top;
	cm->psolid[0] = cm->solid;
	for (l = 1; l < PVS__VX_LEVELS && (cm->lw[l - 1] > 1 || cm->lh[l - 1] > 1); ++l) {
		uint32_t w = (cm->lw[l - 1] + 1) / 2, h = (cm->lh[l - 1] + 1) / 2, pw = cm->lw[l - 1], ph = cm->lh[l - 1];
		cm->ptop[l] = (float *)pvs__alloc_array(&o->allocator, (size_t)w * h, sizeof(float));
		cm->psolid[l] = (float *)pvs__alloc_array(&o->allocator, (size_t)w * h, sizeof(float));
		cm->lw[l] = w;
		cm->lh[l] = h;
		cm->levels = l + 1;
		if (!cm->ptop[l] || !cm->psolid[l]) return PVS_ERROR_OUT_OF_MEMORY;
		for (j = 0; j < h; ++j)
			for (i = 0; i < w; ++i) {
				float t = FLT_MAX, so = FLT_MAX;
				uint32_t a, b;
				for (b = 2 * j; b < 2 * j + 2; ++b)
					for (a = 2 * i; a < 2 * i + 2; ++a) {
						float x = -FLT_MAX, y = o->ground; /* outside the map: no occluder, not solid */
						if (a < pw && b < ph) {
							x = cm->ptop[l - 1][(size_t)b * pw + a];
							y = cm->psolid[l - 1][(size_t)b * pw + a];
						}
						if (x < t) t = x;
						if (y < so) so = y;
					}
				cm->ptop[l][(size_t)j * w + i] = t;
				cm->psolid[l][(size_t)j * w + i] = so;
			}
	}
	return PVS_OK;
}

/* The components' grid voxel: eps, grown by 1.26 while their boxes exceed PVS__VX_TOTAL_BUDGET voxels (or
   PVS__VX_COMPONENT_SHARE each, if more): the floods cost of the order of the scene, whatever eps. */
#define PVS__VX_TOTAL_BUDGET (1u << 26)
#define PVS__VX_COMPONENT_SHARE (1u << 16)
PVS__STATIC pvs_result pvs__vx_component_voxel(const pvs_scene *s, const pvs__vx_topo *tp, const pvs_allocator *al,
											   double eps, double m, double *out) {
	double h = eps, budget = (double)PVS__VX_TOTAL_BUDGET, total, *ext;
	uint32_t comp, t, q, k, n = 0;
	*out = eps;
	for (comp = 0; comp < tp->comp_count; ++comp) n += tp->comp_first[comp + 1] - tp->comp_first[comp] >= 3;
	if (!n) return PVS_OK;
	ext = (double *)pvs__alloc_array(al, 3 * (size_t)n, sizeof(double));
	if (!ext) return PVS_ERROR_OUT_OF_MEMORY;
	for (comp = 0, n = 0; comp < tp->comp_count; ++comp) {
		double lo[3], hi[3];
		if (tp->comp_first[comp + 1] - tp->comp_first[comp] < 3) continue;
		for (k = 0; k < 3; ++k) { lo[k] = DBL_MAX; hi[k] = -DBL_MAX; }
		for (t = tp->comp_first[comp]; t < tp->comp_first[comp + 1]; ++t)
			for (q = 0; q < 3; ++q)
				for (k = 0; k < 3; ++k) {
					double y = s->positions[3 * (size_t)s->indices[3 * (size_t)tp->tris[t] + q] + k];
					lo[k] = pvs__dmin(lo[k], y);
					hi[k] = pvs__dmax(hi[k], y);
				}
		for (k = 0; k < 3; ++k) ext[3 * (size_t)n + k] = hi[k] - lo[k] + 2.0 * m;
		++n;
	}
	budget = pvs__dmax(budget, (double)PVS__VX_COMPONENT_SHARE * n);
	for (;;) {
		for (comp = 0, total = 0.0; comp < n && total <= budget; ++comp) {
			double vol = 1.0;
			for (k = 0; k < 3; ++k) vol *= pvs__dmin(ext[3 * (size_t)comp + k] / h + 3.0, 1e18);
			total += pvs__dmin(vol, (double)PVS__VX_BOX_BUDGET); /* a bigger box grows its own voxels */
		}
		if (total <= budget || !(h < 1e30)) break;
		h *= 1.26;
	}
	pvs__free_array(al, ext, 3 * (size_t)n, sizeof(double));
	*out = h;
	return PVS_OK;
}

PVS__STATIC void pvs__tri_axis_range(const pvs_scene *s, uint32_t tri, uint32_t k, double *lo, double *hi) {
	uint32_t q;
	*lo = DBL_MAX;
	*hi = -DBL_MAX;
	for (q = 0; q < 3; ++q) {
		double x = s->positions[3 * (size_t)s->indices[3 * (size_t)tri + q] + k];
		*lo = pvs__dmin(*lo, x);
		*hi = pvs__dmax(*hi, x);
	}
}

/* The column map, its chains and pyramids: each component of three or more triangles flooded again on its own grid. */
PVS__STATIC pvs_result pvs__vx_columns(pvs_occluders *o, const pvs__vx_topo *tp, const pvs_box *ext, double eps,
									   double m, pvs__vx_flood *fl) {
	const pvs_scene *s = o->scene;
	const pvs_allocator *al = &o->allocator;
	pvs__vx_cols *cm = &o->cols;
	uint32_t up = s->up_axis, comp, k;
	int u, v;
	double c, area, g = o->ground, margin, scale = 0.0, h0;
	size_t x, nmap;
	pvs_result res = PVS_OK;
	pvs__ground_axes(up, &u, &v);
	area = ((double)ext->max[u] - ext->min[u] + 2.0 * eps) * ((double)ext->max[v] - ext->min[v] + 2.0 * eps);
	c = pvs__dmax(0.5 * eps, sqrt(area / (double)PVS__VX_MAP_BUDGET));
	memset(&cm->grid, 0, sizeof(cm->grid));
	cm->grid.h = c;
	for (k = 0; k < 3; ++k) {
		if ((int)k == u || (int)k == v) {
			cm->grid.origin[k] = (double)ext->min[k] - c;
			cm->grid.n[k] = (uint32_t)(floor(((double)ext->max[k] - ext->min[k]) / c) + 3.0);
		} else {
			cm->grid.origin[k] = g;
			cm->grid.n[k] = 1;
		}
		scale = pvs__dmax(scale, pvs__dmax(pvs__dabs(ext->min[k]), pvs__dabs(ext->max[k])));
	}
	cm->nu = cm->grid.n[u];
	cm->nv = cm->grid.n[v];
	nmap = (size_t)cm->nu * cm->nv;
	/* margin: float precision of the chain points and heights, plus the voxel margin */
	margin = 8.0 * FLT_EPSILON * scale + m;
	cm->solid = (float *)pvs__alloc_array(al, nmap, sizeof(float));
	cm->top = (float *)pvs__alloc_array(al, nmap, sizeof(float));
	if (!cm->solid || !cm->top) return PVS_ERROR_OUT_OF_MEMORY;
	for (x = 0; x < nmap; ++x) { cm->solid[x] = (float)g; cm->top[x] = -FLT_MAX; }
	if (pvs__vx_component_voxel(s, tp, al, eps, m, &h0) != PVS_OK) return PVS_ERROR_OUT_OF_MEMORY;
	for (comp = 0; comp < tp->comp_count && res == PVS_OK; ++comp) {
		pvs__vx_grid gk;
		uint32_t lo[3], hi[3], t;
		size_t vol, ncol;
		double hk = h0;
		if (tp->comp_first[comp + 1] - tp->comp_first[comp] < 3) continue;
		for (;;) {
			gk.h = hk;
			for (k = 0; k < 3; ++k) {
				gk.origin[k] = (double)ext->min[k] - hk;
				gk.n[k] = (uint32_t)(floor(((double)ext->max[k] - ext->min[k]) / hk) + 3.0);
				lo[k] = 0xffffffffu;
				hi[k] = 0;
			}
			gk.origin[up] = g - hk;
			for (t = tp->comp_first[comp]; t < tp->comp_first[comp + 1]; ++t) {
				uint32_t tri = tp->tris[t], r0, r1;
				for (k = 0; k < 3; ++k) {
					double tl, th;
					pvs__tri_axis_range(s, tri, k, &tl, &th);
					pvs__vx_grange(&gk, (int)k, tl, th, m, &r0, &r1);
					if (r0 < lo[k]) lo[k] = r0;
					if (r1 > hi[k]) hi[k] = r1;
				}
			}
			if (lo[up] < 1 || tp->open_first[comp + 1] > tp->open_first[comp]) lo[up] = 1;
			if (hi[up] < lo[up]) hi[up] = lo[up];
			vol = 1;
			for (k = 0; k < 3; ++k) vol *= (size_t)(hi[k] - lo[k] + 1);
			if (vol <= PVS__VX_BOX_BUDGET) break;
			hk *= 1.26;
		}
		ncol = (size_t)(hi[u] - lo[u] + 1) * (hi[v] - lo[v] + 1);
		if (vol > fl->cap_vox) {
			pvs__free_array(al, fl->bits, fl->cap_vox ? fl->cap_vox : 1, 1);
			pvs__free_array(al, fl->queue, fl->cap_vox ? 2 * fl->cap_vox : 1, sizeof(uint32_t));
			fl->bits = (uint8_t *)pvs__alloc_array(al, vol, 1);
			fl->queue = (uint32_t *)pvs__alloc_array(al, 2 * vol, sizeof(uint32_t));
			fl->cap_vox = vol;
			if (!fl->bits || !fl->queue) return PVS_ERROR_OUT_OF_MEMORY;
		}
		if (ncol > fl->cap_col) {
			pvs__free_array(al, fl->col, fl->cap_col ? fl->cap_col : 1, 1);
			fl->col = (uint8_t *)pvs__alloc_array(al, ncol, 1);
			fl->cap_col = ncol;
			if (!fl->col) return PVS_ERROR_OUT_OF_MEMORY;
		}
		res = pvs__vx_columns_component(o, tp, comp, &gk, lo, hi, m, eps, margin, fl);
	}
	if (res == PVS_OK) res = pvs__vx_build_chains(o);
	if (res == PVS_OK) res = pvs__vx_pyramid(o);
	return res;
}

/* pvs_occluders_create step by step: what the steps share. A step returns PVS_OK or PVS_ERROR_OUT_OF_MEMORY;
   pvs__vx_build_free frees the scratch left on the error path, and a step freeing a buffer sets it to NULL. */
typedef struct pvs__vx_build {
	const pvs_occluders_desc *d;
	const pvs_scene *s;
	pvs_allocator a;
	pvs_occluders *o;
	pvs_box ext;               /* the scene's and the cells' bounds */
	double g, h, m;            /* ground level, voxel size, the margin voxel tests round toward "touched" by */
	uint32_t up;
	int u, v;
	size_t total, qcap, nbuckets;
	uint32_t bucket_entries;
	uint32_t *queue;           /* qcap: the floods' queue, then the leak flood's */
	uint32_t *cbox;            /* step 1: per component its voxel box, lo[3] hi[3] */
	uint8_t *tmp, *line;       /* total and 1 + n[0] + n[1] + n[2] bytes: erosion and merge scratch */
	pvs__vx_topo tp;
	pvs__vx_flood fl;
} pvs__vx_build;

/* The error path: frees the scratch the steps left (b->o stays: the caller destroys it). */
PVS__STATIC void pvs__vx_build_free(pvs__vx_build *b) {
	const pvs_allocator *a = &b->a;
	pvs__vx_flood *fl = &b->fl;
	uint32_t cells = b->d->cell_count;
	pvs__free_array(a, fl->bucket_first, b->nbuckets + 1, sizeof(uint32_t));
	pvs__free_array(a, fl->bucket_cells, b->bucket_entries ? b->bucket_entries : 1, sizeof(uint32_t));
	pvs__free_array(a, fl->stamp, cells, sizeof(uint32_t));
	pvs__free_array(a, fl->cellbuf, cells, 7);
	if (fl->queue && fl->queue != b->queue)
		pvs__free_array(a, fl->queue, fl->cap_vox ? 2 * fl->cap_vox : 1, sizeof(uint32_t));
	pvs__free_array(a, fl->bits, fl->cap_vox ? fl->cap_vox : 1, 1);
	pvs__free_array(a, fl->col, fl->cap_col ? fl->cap_col : 1, 1);
	pvs__free_array(a, b->cbox, (size_t)(b->tp.comp_count ? b->tp.comp_count : 1) * 6, sizeof(uint32_t));
	pvs__vx_topo_free(a, &b->tp, b->s->triangle_count);
	pvs__free_array(a, b->tmp, b->total, 1);
	pvs__free_array(a, b->queue, b->qcap, sizeof(uint32_t));
	pvs__free_array(a, b->line, 1u + b->o->n[0] + b->o->n[1] + b->o->n[2], 1);
}

/* The voxel grid over the scene and the cells: voxels of voxel_size or eps / 1.5 (2 voxels of erosion = 1.33 eps),
   grown by 1.08 to fit max_voxels; layer 0 below the ground. Allocates b->o, its state and eroded grids, b->tmp,
   b->line. On failure nothing stays allocated; err says why. */
PVS__STATIC pvs_result pvs__vx_build_grid(pvs__vx_build *b, pvs_error *err) {
	const pvs_occluders_desc *d = b->d;
	const pvs_allocator *a = &b->a;
	pvs_occluders *o;
	uint32_t up = b->up, c, i, j, k;
	size_t total = 1;
	double h;
	int kk;
	b->ext = b->s->bounds;
	for (c = 0; c < d->cell_count; ++c)
		for (kk = 0; kk < 3; ++kk) {
			if (d->cells[c].min[kk] < b->ext.min[kk]) b->ext.min[kk] = d->cells[c].min[kk];
			if (d->cells[c].max[kk] > b->ext.max[kk]) b->ext.max[kk] = d->cells[c].max[kk];
		}
	b->g = b->ext.min[up];
	h = d->voxel_size > 0.0f ? d->voxel_size : d->eps / 1.5;
	for (;;) {
		double cnt = 1.0, lim = d->max_voxels ? (double)d->max_voxels : (double)(1u << 24);
		for (kk = 0; kk < 3; ++kk) cnt *= floor(((double)b->ext.max[kk] - b->ext.min[kk]) / h) + 3.0;
		if (cnt <= lim) break;
		h *= 1.08;
	}
	b->h = h;
	o = (pvs_occluders *)pvs__alloc(a, sizeof(*o), 16);
	if (!o) return pvs__fail(err, PVS_ERROR_OUT_OF_MEMORY, -1, 0, "occluders");
	memset(o, 0, sizeof(*o));
	o->allocator = *a;
	o->scene = b->s;
	o->h = h;
	o->ground = (float)b->g;
	for (kk = 0; kk < 3; ++kk) {
		o->n[kk] = (uint32_t)(floor(((double)b->ext.max[kk] - b->ext.min[kk]) / h) + 3.0);
		o->origin[kk] = (double)b->ext.min[kk] - h;
		total *= o->n[kk];
	}
	o->origin[up] = b->g - h;
	o->total = b->total = total;
	for (kk = 0; kk < 3; ++kk) {
		o->grid.origin[kk] = o->origin[kk];
		o->grid.n[kk] = o->n[kk];
	}
	o->grid.h = h;
	o->state = (uint8_t *)pvs__alloc_array(a, total, 1);
	o->eroded = (uint8_t *)pvs__alloc_array(a, total, 1);
	b->tmp = (uint8_t *)pvs__alloc_array(a, total, 1);
	b->line = (uint8_t *)pvs__alloc_array(a, 1u + o->n[0] + o->n[1] + o->n[2], 1);
	if (!o->state || !o->eroded || !b->tmp || !b->line || total > 0x7fffffffu) {
		uint32_t dims[3];
		memcpy(dims, o->n, sizeof(dims)); /* named after o is gone */
		pvs__free_array(a, b->tmp, total, 1);
		pvs__free_array(a, b->line, 1u + o->n[0] + o->n[1] + o->n[2], 1);
		pvs_occluders_destroy(o);
		b->tmp = b->line = NULL;
		return pvs__fail(err, PVS_ERROR_OUT_OF_MEMORY, -1, 0, "voxel grid %u x %u x %u", dims[0], dims[1], dims[2]);
	}
	b->o = o;
	memset(o->state, 0, total);
	for (k = 0; k < o->n[2]; ++k)
		for (j = 0; j < o->n[1]; ++j)
			for (i = 0; i < o->n[0]; ++i) {
				uint32_t idx[3];
				idx[0] = i; idx[1] = j; idx[2] = k;
				if (idx[up] == 0) o->state[pvs__vx_index(o, i, j, k)] = PVS__VX_GROUND;
			}
	b->m = h * 1e-4 + 1e-6 * (pvs__dabs(b->g) + 1.0);
	return PVS_OK;
}

/* The floods' cells, per-cell scratch and ground-plane buckets (PVS__VX_BUCKET voxel columns a side) listing the cells
   whose box grown by m meets them. */
PVS__STATIC pvs_result pvs__vx_build_buckets(pvs__vx_build *b) {
	const pvs_occluders_desc *d = b->d;
	const pvs_allocator *a = &b->a;
	const pvs_occluders *o = b->o;
	pvs__vx_flood *fl = &b->fl;
	int u = b->u, v = b->v;
	uint32_t bpass, c;
	size_t vi, nbuckets;
	fl->cells = d->cells;
	fl->cell_count = d->cell_count;
	fl->keep_leaks = (d->flags & PVS_OCCLUDERS_KEEP_LEAKS) != 0;
	fl->bnu = (o->n[u] + PVS__VX_BUCKET - 1) / PVS__VX_BUCKET;
	fl->bnv = (o->n[v] + PVS__VX_BUCKET - 1) / PVS__VX_BUCKET;
	fl->bucket_grid = o->grid;
	fl->bucket_grid.h = o->h * PVS__VX_BUCKET;
	fl->bucket_grid.n[u] = fl->bnu;
	fl->bucket_grid.n[v] = fl->bnv;
	b->nbuckets = nbuckets = (size_t)fl->bnu * fl->bnv;
	fl->bucket_first = (uint32_t *)pvs__alloc_array(a, nbuckets + 1, sizeof(uint32_t));
	fl->stamp = (uint32_t *)pvs__alloc_array(a, d->cell_count, sizeof(uint32_t));
	fl->cellbuf = (uint8_t *)pvs__alloc_array(a, d->cell_count, 7);
	if (!fl->bucket_first || !fl->stamp || !fl->cellbuf) return PVS_ERROR_OUT_OF_MEMORY;
	memset(fl->bucket_first, 0, (nbuckets + 1) * sizeof(uint32_t));
	memset(fl->stamp, 0, d->cell_count * sizeof(uint32_t));
	memset(fl->cellbuf, 0, (size_t)d->cell_count * 7);
	fl->near_cells = (uint32_t *)(void *)fl->cellbuf; /* the allocator aligns to 16 */
	fl->excluded = fl->cellbuf + 4 * (size_t)d->cell_count;
	fl->near_w = (signed char *)(fl->excluded + d->cell_count);
	fl->near_flag = fl->excluded + 2 * (size_t)d->cell_count;
	for (bpass = 0; bpass < 2; ++bpass) {
		if (bpass) {
			for (vi = 0; vi < nbuckets; ++vi) fl->bucket_first[vi + 1] += fl->bucket_first[vi];
			b->bucket_entries = fl->bucket_first[nbuckets];
			fl->bucket_cells =
				(uint32_t *)pvs__alloc_array(a, b->bucket_entries ? b->bucket_entries : 1, sizeof(uint32_t));
			if (!fl->bucket_cells) return PVS_ERROR_OUT_OF_MEMORY;
		}
		for (c = 0; c < d->cell_count; ++c) {
			uint32_t r0[3], r1[3], bu, bv;
			pvs__vx_grange(&fl->bucket_grid, u, d->cells[c].min[u], d->cells[c].max[u], b->m, r0 + u, r1 + u);
			pvs__vx_grange(&fl->bucket_grid, v, d->cells[c].min[v], d->cells[c].max[v], b->m, r0 + v, r1 + v);
			if (r0[u] > r1[u] || r0[v] > r1[v]) continue;
			for (bv = r0[v]; bv <= r1[v]; ++bv)
				for (bu = r0[u]; bu <= r1[u]; ++bu) {
					size_t bk = (size_t)bv * fl->bnu + bu;
					if (!bpass) ++fl->bucket_first[bk + 1];
					else fl->bucket_cells[--fl->bucket_first[bk + 1]] = c;
				}
		}
	}
	for (vi = 0; vi < nbuckets; ++vi)
		fl->bucket_first[vi] = fl->bucket_first[vi + 1]; /* the fill moved each end to its start */
	fl->bucket_first[nbuckets] = b->bucket_entries;
	return PVS_OK;
}

/* Step 1's component boxes (b->cbox): voxels within m of the triangles' extents, from layer 1 up with open edges; the
   flood scratch sizes of the largest box of 3+ triangles. */
PVS__STATIC pvs_result pvs__vx_build_boxes(pvs__vx_build *b) {
	const pvs_scene *s = b->s;
	const pvs__vx_topo *tp = &b->tp;
	pvs__vx_flood *fl = &b->fl;
	uint32_t up = b->up, c;
	int kk;
	b->cbox = (uint32_t *)pvs__alloc_array(&b->a, (size_t)(tp->comp_count ? tp->comp_count : 1) * 6, sizeof(uint32_t));
	if (!b->cbox) return PVS_ERROR_OUT_OF_MEMORY;
	for (c = 0; c < tp->comp_count; ++c) {
		uint32_t *bx = b->cbox + 6 * (size_t)c, t;
		size_t vol = 1, ncol;
		for (kk = 0; kk < 3; ++kk) { bx[kk] = 0xffffffffu; bx[3 + kk] = 0; }
		for (t = tp->comp_first[c]; t < tp->comp_first[c + 1]; ++t) {
			uint32_t tri = tp->tris[t], r0, r1;
			for (kk = 0; kk < 3; ++kk) {
				double lo, hi;
				pvs__tri_axis_range(s, tri, kk, &lo, &hi);
				pvs__vx_range(b->o, kk, lo, hi, b->m, &r0, &r1);
				if (r0 < bx[kk]) bx[kk] = r0;
				if (r1 > bx[3 + kk]) bx[3 + kk] = r1;
			}
		}
		if (bx[up] < 1 || tp->open_first[c + 1] > tp->open_first[c]) bx[up] = 1;
		if (bx[3 + up] < bx[up]) bx[3 + up] = bx[up];
		for (kk = 0; kk < 3; ++kk) vol *= (size_t)(bx[3 + kk] - bx[kk] + 1);
		ncol = (size_t)(bx[3 + b->u] - bx[b->u] + 1) * (bx[3 + b->v] - bx[b->v] + 1);
		if (tp->comp_first[c + 1] - tp->comp_first[c] < 3) continue; /* encloses nothing: touched only */
		if (vol > fl->cap_vox) fl->cap_vox = vol;
		if (ncol > fl->cap_col) fl->cap_col = ncol;
	}
	return PVS_OK;
}

/* Step 1, solid proved per component (see pvs__vx_orient): components of three or more triangles certified, the others
   marked touched. Allocates b->queue (kept for the leak flood), frees its other scratch. */
PVS__STATIC pvs_result pvs__vx_build_certify(pvs__vx_build *b) {
	static const int xyz[3] = {0, 1, 2};
	pvs_occluders *o = b->o;
	const pvs_allocator *a = &b->a;
	const pvs__vx_topo *tp = &b->tp;
	pvs__vx_flood *fl = &b->fl;
	uint32_t zero[3] = {0, 0, 0}, last[3], c;
	pvs__vx_touch tv;
	size_t vi;
	int kk;
	if (pvs__vx_topology(b->s, (float)b->g, a, &b->tp) != PVS_OK) return PVS_ERROR_OUT_OF_MEMORY;
	if (pvs__vx_build_boxes(b) != PVS_OK) return PVS_ERROR_OUT_OF_MEMORY;
	b->qcap = b->total > 2 * fl->cap_vox ? b->total : 2 * fl->cap_vox;
	fl->bits = (uint8_t *)pvs__alloc_array(a, fl->cap_vox ? fl->cap_vox : 1, 1);
	fl->col = (uint8_t *)pvs__alloc_array(a, fl->cap_col ? fl->cap_col : 1, 1);
	b->queue = (uint32_t *)pvs__alloc_array(a, b->qcap, sizeof(uint32_t));
	fl->queue = b->queue;
	if (!fl->bits || !fl->col || !b->queue) return PVS_ERROR_OUT_OF_MEMORY;
	memset(&tv, 0, sizeof(tv));
	tv.o = o;
	tv.gr = &o->grid;
	tv.hs = 0.5 * b->h + b->m;
	for (kk = 0; kk < 3; ++kk) last[kk] = o->n[kk] - 1;
	for (c = 0; c < tp->comp_count; ++c) {
		uint32_t t;
		if (tp->comp_first[c + 1] - tp->comp_first[c] >= 3) {
			pvs__vx_certify(o, tp, c, b->cbox + 6 * (size_t)c, b->cbox + 6 * (size_t)c + 3, b->m, fl);
			++o->info.components;
			o->info.closed_components += tp->open_first[c + 1] == tp->open_first[c];
			continue;
		}
		for (t = tp->comp_first[c]; t < tp->comp_first[c + 1]; ++t) {
			pvs__vx_tri_points(b->s, tp->tris[t], tv.p);
			pvs__vx_scan(&o->grid, tv.p[0], 3, xyz, 3, b->m, zero, last, pvs__vx_touch_visit, &tv);
		}
	}
	o->info.open_edges = tp->open_count;
	pvs__free_array(a, fl->bits, fl->cap_vox ? fl->cap_vox : 1, 1);
	pvs__free_array(a, fl->col, fl->cap_col ? fl->cap_col : 1, 1);
	pvs__free_array(a, b->cbox, (size_t)(tp->comp_count ? tp->comp_count : 1) * 6, sizeof(uint32_t));
	fl->bits = fl->col = NULL;
	fl->queue = NULL; /* b->queue keeps it */
	fl->cap_vox = fl->cap_col = 0;
	b->cbox = NULL;
	for (vi = 0; vi < b->total; ++vi) o->info.touched += (o->state[vi] & PVS__VX_TOUCHED) != 0;
	return PVS_OK;
}

/* Step 2: voxels above the ground wholly inside an explicit occluder are PVS__VX_EXPLICIT | PVS__VX_SOLID. */
PVS__STATIC void pvs__vx_explicit_solid(pvs_occluders *o) {
	const pvs_scene *s = o->scene;
	double h = o->h;
	uint32_t up = s->up_axis, c, i, j, k;
	int kk;
	for (c = 0; c < s->occluder_count; ++c) {
		const pvs_box *ob = s->occluder_boxes + c;
		uint32_t r0[3], r1[3];
		for (kk = 0; kk < 3; ++kk) pvs__vx_range(o, kk, ob->min[kk], ob->max[kk], 0.0, r0 + kk, r1 + kk);
		for (k = r0[2]; k <= r1[2]; ++k)
			for (j = r0[1]; j <= r1[1]; ++j)
				for (i = r0[0]; i <= r1[0]; ++i) {
					double lo[3], hi[3];
					size_t x = pvs__vx_index(o, i, j, k);
					if (o->state[x] & PVS__VX_GROUND) continue;
					lo[0] = o->origin[0] + i * h; hi[0] = lo[0] + h;
					lo[1] = o->origin[1] + j * h; hi[1] = lo[1] + h;
					lo[2] = o->origin[2] + k * h; hi[2] = lo[2] + h;
					if (pvs__vx_in_occluder(s->occluders + c, up, lo, hi))
						o->state[x] |= PVS__VX_EXPLICIT | PVS__VX_SOLID;
				}
	}
}

/* Step 3, the leak diagnostic: a 6-connected flood from the grid's border through voxels neither touched, ground nor
   explicit, a path meeting no triangle. info.leak_cells counts the cells reached, info.leak_cell and leak_point give
   the lowest and a reached voxel. Floods with b->queue (total entries). */
PVS__STATIC void pvs__vx_leaks(pvs__vx_build *b) {
	pvs_occluders *o = b->o;
	const pvs_occluders_desc *d = b->d;
	uint32_t *queue = b->queue, qh = 0, qt = 0, c, i, j, k;
	double h = b->h;
	int kk;
	o->info.leak_cell = PVS_NO_CELL;
	for (k = 0; k < o->n[2]; ++k)
		for (j = 0; j < o->n[1]; ++j)
			for (i = 0; i < o->n[0]; ++i) {
				size_t x;
				if (i && j && k && i + 1 < o->n[0] && j + 1 < o->n[1] && k + 1 < o->n[2]) continue;
				x = pvs__vx_index(o, i, j, k);
				if (!(o->state[x] & PVS__VX_LEAK_STOP)) { o->state[x] |= PVS__VX_REACHED; queue[qt++] = (uint32_t)x; }
			}
	while (qh < qt) {
		uint32_t x = queue[qh++], cidx[3];
		int dir;
		cidx[0] = x % o->n[0]; cidx[1] = (x / o->n[0]) % o->n[1]; cidx[2] = x / o->n[0] / o->n[1];
		for (dir = 0; dir < 6; ++dir) {
			uint32_t ax = (uint32_t)dir >> 1, nidx[3];
			size_t y;
			if (dir & 1 ? cidx[ax] + 1 >= o->n[ax] : cidx[ax] == 0) continue;
			nidx[0] = cidx[0]; nidx[1] = cidx[1]; nidx[2] = cidx[2];
			nidx[ax] = dir & 1 ? cidx[ax] + 1 : cidx[ax] - 1;
			y = pvs__vx_index(o, nidx[0], nidx[1], nidx[2]);
			if (!(o->state[y] & PVS__VX_LEAK_STOP)) { o->state[y] |= PVS__VX_REACHED; queue[qt++] = (uint32_t)y; }
		}
	}
	for (c = 0; c < d->cell_count; ++c) {
		uint32_t r0[3], r1[3];
		int found = 0;
		const pvs_box *cb = d->cells + c;
		for (kk = 0; kk < 3; ++kk) pvs__vx_range(o, kk, cb->min[kk], cb->max[kk], b->m, r0 + kk, r1 + kk);
		for (k = r0[2]; k <= r1[2] && !found; ++k)
			for (j = r0[1]; j <= r1[1] && !found; ++j)
				for (i = r0[0]; i <= r1[0] && !found; ++i)
					if (o->state[pvs__vx_index(o, i, j, k)] & PVS__VX_REACHED) {
						found = 1;
						if (o->info.leak_cell == PVS_NO_CELL) {
							o->info.leak_cell = c;
							o->info.leak_point[0] = (float)(o->origin[0] + (i + 0.5) * h);
							o->info.leak_point[1] = (float)(o->origin[1] + (j + 0.5) * h);
							o->info.leak_point[2] = (float)(o->origin[2] + (k + 0.5) * h);
						}
					}
		o->info.leak_cells += (uint32_t)found;
	}
}

/* After steps 1 to 3: o->eroded = the solid (eroded in step 5), info.solid, info.thin_objects (drawable objects without
   solid voxels in their box). */
PVS__STATIC void pvs__vx_solid_summary(pvs_occluders *o) {
	const pvs_scene *s = o->scene;
	uint32_t c, i, j, k;
	size_t vi;
	int kk;
	for (vi = 0; vi < o->total; ++vi) {
		o->eroded[vi] = (uint8_t)pvs__vx_solid_state(o->state[vi]);
		o->info.solid += o->eroded[vi];
	}
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
}

/* Step 4, the 2.5D occluders: solid runs on the ground (info.column_voxels; is_2d5 at 90% of the solid), column map,
   chains, hierarchies; frees the floods' scratch but the per-cell bytes. */
PVS__STATIC pvs_result pvs__vx_build_columns(pvs__vx_build *b) {
	pvs_occluders *o = b->o;
	const pvs_allocator *a = &b->a;
	pvs__vx_flood *fl = &b->fl;
	uint32_t up = b->up, cells = b->d->cell_count;
	int u = b->u, v = b->v;
	size_t vi, cols = (size_t)o->n[u] * o->n[v];
	for (vi = 0; vi < cols; ++vi) {
		uint32_t idx[3];
		idx[u] = (uint32_t)(vi % o->n[u]); idx[v] = (uint32_t)(vi / o->n[u]);
		for (idx[up] = 1; idx[up] < o->n[up]; ++idx[up]) {
			if (!o->eroded[pvs__vx_index(o, idx[0], idx[1], idx[2])]) break;
			++o->info.column_voxels;
		}
	}
	o->info.is_2d5 = o->info.solid > 0 && (double)o->info.column_voxels >= 0.9 * (double)o->info.solid;
	if (pvs__vx_columns(o, &b->tp, &b->ext, b->d->eps, b->m, fl) != PVS_OK || pvs__occluders_hierarchies(o) != PVS_OK)
		return PVS_ERROR_OUT_OF_MEMORY;
	o->info.rect_count = o->chain_count;
	pvs__free_array(a, fl->bits, fl->cap_vox ? fl->cap_vox : 1, 1);
	pvs__free_array(a, fl->queue, fl->cap_vox ? 2 * fl->cap_vox : 1, sizeof(uint32_t));
	pvs__free_array(a, fl->col, fl->cap_col ? fl->cap_col : 1, 1);
	pvs__free_array(a, fl->bucket_first, b->nbuckets + 1, sizeof(uint32_t));
	pvs__free_array(a, fl->bucket_cells, b->bucket_entries ? b->bucket_entries : 1, sizeof(uint32_t));
	pvs__free_array(a, fl->stamp, cells, sizeof(uint32_t));
	fl->bits = fl->col = NULL; /* the error path must not free them again */
	fl->queue = fl->bucket_first = fl->bucket_cells = fl->stamp = NULL;
	return PVS_OK;
}

/* The cells the floods left out (o->excluded, o->excluded_boxes); frees the per-cell bytes, clears b->fl. */
PVS__STATIC pvs_result pvs__vx_build_excluded(pvs__vx_build *b) {
	pvs_occluders *o = b->o;
	const pvs_occluders_desc *d = b->d;
	const pvs_allocator *a = &b->a;
	pvs__vx_flood *fl = &b->fl;
	uint32_t c;
	o->info.excluded_cells = fl->excluded_count;
	if (fl->excluded_count) {
		uint32_t n = 0;
		o->excluded = (uint32_t *)pvs__alloc_array(a, fl->excluded_count, sizeof(uint32_t));
		o->excluded_boxes = (pvs_box *)pvs__alloc_array(a, fl->excluded_count, sizeof(pvs_box));
		if (!o->excluded || !o->excluded_boxes) {
			pvs__free_array(a, fl->cellbuf, d->cell_count, 7);
			fl->cellbuf = NULL;
			return PVS_ERROR_OUT_OF_MEMORY;
		}
		for (c = 0; c < d->cell_count; ++c)
			if (fl->excluded[c]) { o->excluded[n] = c; o->excluded_boxes[n++] = d->cells[c]; }
	}
	pvs__free_array(a, fl->cellbuf, d->cell_count, 7);
	memset(fl, 0, sizeof(*fl));
	return PVS_OK;
}

/* Step 5, the occluders shrunk by eps (Wonka 2000 §2, appendix): the solid eroded by r voxels (Chebyshev; outside and
   ground empty), merged greedily into o->boxes (NULL when out of memory). */
PVS__STATIC void pvs__vx_erode_merge(pvs__vx_build *b, uint32_t r) {
	pvs_occluders *o = b->o;
	size_t vi, total = b->total;
	int kk;
	for (kk = 0; kk < 3; ++kk) pvs__vx_erode_axis(o, o->eroded, b->line, kk, r);
	for (vi = 0; vi < total; ++vi) o->info.eroded += o->eroded[vi];
	memcpy(b->tmp, o->eroded, total);
	o->box_count = pvs__vx_merge(o, b->tmp, NULL);
	o->boxes = (pvs_box *)pvs__alloc_array(&b->a, o->box_count ? o->box_count : 1, sizeof(pvs_box));
	if (o->boxes) {
		memcpy(b->tmp, o->eroded, total);
		pvs__vx_merge(o, b->tmp, o->boxes);
	}
	o->info.box_count = o->box_count;
}

PVS_API pvs_result pvs_occluders_create(const pvs_occluders_desc *d, pvs_occluders **out, pvs_error *err) {
	pvs__vx_build b;
	pvs_occluders *o;
	pvs_result res;
	uint32_t c, r;
	int kk;
	if (out) *out = NULL;
	memset(&b, 0, sizeof(b));
	if (!d || !out || !d->scene || !d->cells || !d->cell_count)
		return pvs__fail(err, PVS_ERROR_INVALID_ARGUMENT, -1, 0, "desc, scene, cells and out must be given");
	if (!pvs__finite(d->eps) || !(d->eps > 0.0f) || !pvs__finite(d->voxel_size) || d->voxel_size < 0.0f)
		return pvs__fail(err, PVS_ERROR_INVALID_ARGUMENT, -1, 0,
						 "eps must be finite and > 0, voxel_size finite and >= 0");
	if (d->flags & ~PVS_OCCLUDERS_KEEP_LEAKS)
		return pvs__fail(err, PVS_ERROR_INVALID_ARGUMENT, -1, 0, "unknown occluders flags 0x%x", d->flags);
	for (c = 0; c < d->cell_count; ++c)
		if (!pvs__box_valid(d->cells + c))
			return pvs__fail(err, PVS_ERROR_BAD_CELL, c, 0, "cell %u is not a valid box", c);
	b.d = d;
	b.s = d->scene;
	b.a = d->allocator;
	b.up = b.s->up_axis;
	pvs__ground_axes(b.up, &b.u, &b.v);
	res = pvs__vx_build_grid(&b, err);
	if (res != PVS_OK) return res;
	o = b.o;
	if (pvs__vx_build_buckets(&b) != PVS_OK) goto oom;
	if (pvs__vx_build_certify(&b) != PVS_OK) goto oom;
	pvs__vx_explicit_solid(o);
	pvs__vx_leaks(&b);
	pvs__vx_solid_summary(o);
	r = (uint32_t)floor(d->eps / b.h) + 1u; /* strictly more than eps: rounding toward less solid */
	if (pvs__vx_build_columns(&b) != PVS_OK || pvs__vx_build_excluded(&b) != PVS_OK) goto oom;
	pvs__vx_topo_free(&b.a, &b.tp, b.s->triangle_count);
	pvs__vx_erode_merge(&b, r);
	pvs__free_array(&b.a, b.tmp, b.total, 1);
	pvs__free_array(&b.a, b.queue, b.qcap, sizeof(uint32_t));
	pvs__free_array(&b.a, b.line, 1u + o->n[0] + o->n[1] + o->n[2], 1);
	if (!o->boxes) {
		pvs_occluders_destroy(o);
		return pvs__fail(err, PVS_ERROR_OUT_OF_MEMORY, -1, 0, "occluder boxes");
	}
	for (kk = 0; kk < 3; ++kk) {
		o->info.dims[kk] = o->n[kk];
		o->info.origin[kk] = (float)o->origin[kk];
	}
	o->info.voxel_size = (float)b.h;
	o->info.eps = d->eps;
	*out = o;
	pvs__ok(err);
	return PVS_OK;
oom:
	pvs__vx_build_free(&b);
	pvs_occluders_destroy(o);
	return pvs__fail(err, PVS_ERROR_OUT_OF_MEMORY, -1, 0, "occluder synthesis scratch");
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
PVS_API const uint32_t *pvs_occluders_excluded_cells(const pvs_occluders *o, uint32_t *count) {
	*count = o->info.excluded_cells;
	return o->info.excluded_cells ? o->excluded : NULL;
}

PVS_API float pvs_occluders_column_height(const pvs_occluders *o, float pu, float pv, float *solid) {
	const pvs__vx_cols *cm = &o->cols;
	uint32_t a0, a1, b0, b1, a, b;
	float top = FLT_MAX, sol = FLT_MAX;
	int u, v;
	pvs__ground_axes(o->scene->up_axis, &u, &v);
	pvs__vx_grange(&cm->grid, u, pu, pu, 0.0, &a0, &a1);
	pvs__vx_grange(&cm->grid, v, pv, pv, 0.0, &b0, &b1);
	if (a0 > a1 || b0 > b1 || !cm->top) {
		if (solid) *solid = o->ground;
		return -FLT_MAX;
	}
	for (b = b0; b <= b1; ++b)
		for (a = a0; a <= a1; ++a) {
			size_t x = (size_t)b * cm->nu + a;
			if (cm->top[x] < top) top = cm->top[x];
			if (cm->solid[x] < sol) sol = cm->solid[x];
		}
	if (solid) *solid = sol;
	return top;
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
/* The 2D problem (§3): the view cell C is a rectangle, the occluders opaque segments. Segments whose end points
   coincide exactly and close a ring form a wall loop. A point inside it (odd crossings) is hidden from all outside,
   and a segment crossing its convex hull from outside to outside crosses the loop, so a loop whose hull misses the
   cell is a solid convex blocker (its hull) for points outside the hull. The "objects" of §3 are these hulls
   (buildings) and the other segments.
   Conservativeness: x is hidden when every segment from C to x meets a blocker. A convex blocker disjoint from C and
   not containing x covers an interval of the fan C subtends from x, wholly before or behind C along each ray
   (disjoint convex sets seen from a point never swap order), so one ray decides; x is hidden when the intervals
   before C cover the fan (pvs__vo_hidden). Along a line the answer changes only at an object's boundary or a common
   tangent of two objects (or an object and C) through C, and the hidden set is closed, so one point per interval
   between such events finds a line's hidden parts up to rounding (pvs__vo_line_hidden). Every virtual occluder is
   checked so after its final rounding, against its aggregate's blockers (a subset).
   The construction (§3): seeds by subtended angle; each aggregate grows on both sides along the active supporting
   line P (outer common tangent of C and the aggregate) and separating polyline Q (at first the inner tangent). An
   object B met by an active line: (1) if it meets the umbra U (a probe point of B is hidden without B), it joins U,
   P and Q move to it, and a new virtual occluder goes behind B or (3, found on Q) the furthest one extends; (2) if
   it meets only Q, it bends Q and joins the blockers, so later objects fuse through it. A new occluder dumps the one
   in use into the dense set ("periodically dumped", §3). */

#define PVS__VO_NONE 0xffffffffu
#define PVS__VO_MAXH 64u        /* most hull vertices of a loop blocker */
#define PVS__VO_ATOL 1e-11      /* pseudo-angle overlap joining spans of different vertices */
#define PVS__VO_RTOL 1e-9       /* lengths: times the context's scale */
#define PVS__VO_MAXG 64u        /* most objects in one aggregate */
#define PVS__VO_MAXSTEP 96u     /* most candidates examined per seed */

/* Grows *p to hold need elements (doubling). */
PVS__STATIC int pvs__vo_reserve(const pvs_allocator *a, void **p, uint32_t *cap, size_t need, size_t elem) {
	size_t c = *cap;
	if (need > 0x7fffffffu || !pvs__grow(a, p, &c, need, elem)) return 0;
	*cap = (uint32_t)c;
	return 1;
}
#define PVS__VO_FREE(a, p, cap, T) pvs__free((a), (p), (size_t)(cap) * sizeof(T), 16)

PVS__STATIC double pvs__vo_cross(const double *o, const double *a, const double *b) {
	return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0]);
}

/* Monotone pseudo-angle of direction (cos-like d, sin-like c): (-2, 2], 0 along d. */
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
	uint32_t *loop_start; /* nloop + 1: loop l's ring in ring_seg / ring_pt */
	uint32_t *ring_seg;   /* segments in ring order */
	double *ring_pt;      /* the start of each ring segment */
	uint32_t *hull_start; /* nloop + 1 into hull_pt, hull_vid (counter-clockwise) */
	double *hull_pt;
	uint32_t *hull_vid;
	float *loop_top;      /* lowest top of its walls */
	double *loop_bb;      /* 4 per loop */
	uint32_t nobj;        /* objects: the usable loops, then the other segments */
	uint32_t *obj_ref;    /* < nloop: a loop; else nloop + segment */
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

/* Convex hull (Andrew's monotone chain), counter-clockwise, collinear points dropped, into idx (point indices); keys: n
   scratch. Returns its size. */
PVS__STATIC uint32_t pvs__vo_hull(const double *pts, uint32_t n, pvs__key_index *keys, uint32_t *idx) {
	uint32_t i, k = 0, t;
	for (i = 0; i < n; ++i) { keys[i].key = pts[2 * i]; keys[i].index = i; }
	pvs__key_index_sort(keys, n); /* by x, then y within runs of equal x */
	for (i = 0; i < n;) {
		uint32_t j = i, m;
		while (j < n && keys[j].key == keys[i].key) ++j;
		for (m = i; m < j; ++m) keys[m].key = pts[2 * keys[m].index + 1];
		pvs__key_index_sort(keys + i, j - i);
		for (m = i; m < j; ++m) keys[m].key = pts[2 * keys[m].index];
		i = j;
	}
	if (n < 3) {
		for (i = 0; i < n; ++i) idx[i] = keys[i].index;
		return n;
	}
	for (i = 0; i < n; ++i) {
		while (k >= 2 && pvs__vo_cross(pts + 2 * idx[k - 2], pts + 2 * idx[k - 1], pts + 2 * keys[i].index) <= 0.0) --k;
		idx[k++] = keys[i].index;
	}
	for (i = n - 1, t = k + 1; i-- > 0;) {
		while (k >= t && pvs__vo_cross(pts + 2 * idx[k - 2], pts + 2 * idx[k - 1], pts + 2 * keys[i].index) <= 0.0) --k;
		idx[k++] = keys[i].index;
	}
	return k > 1 ? k - 1 : k;
}

/* pvs__vprep_create's scratch (m segments): keys, deg, uf, idx, hidx 2m + 2 entries, adj 4m + 4. */
typedef struct pvs__vprep_scratch {
	pvs__key_index *keys;
	uint32_t *deg, *adj, *uf, *idx, *hidx;
	uint32_t nv;          /* distinct vertices */
} pvs__vprep_scratch;

/* Vertex ids (p->seg_vid): end points sorted by (x, y), equal points one id; sets w->nv. */
PVS__STATIC void pvs__vprep_vertex_ids(pvs__vprep *p, pvs__vprep_scratch *w) {
	pvs__key_index *keys = w->keys;
	uint32_t m = p->nseg, i, nv = 0;
	for (i = 0; i < 2 * m; ++i) { keys[i].key = p->seg[2 * i]; keys[i].index = i; }
	pvs__key_index_sort(keys, 2 * m);
	for (i = 0; i < 2 * m;) {
		uint32_t j = i, t;
		while (j < 2 * m && keys[j].key == keys[i].key) ++j;
		for (t = i; t < j; ++t) keys[t].key = p->seg[2 * keys[t].index + 1];
		pvs__key_index_sort(keys + i, j - i);
		for (t = i; t < j; ++t) {
			if (t > i && keys[t].key != keys[t - 1].key) ++nv;
			p->seg_vid[keys[t].index] = nv;
		}
		++nv;
		i = j;
	}
	w->nv = nv;
}

/* The segments' graph: per vertex its degree (w->deg), first two segments (w->adj), component root (w->uf); per root
   w->idx = 1 when not a loop (a vertex of degree other than 2). Sets p->seg_loop to -1. */
PVS__STATIC void pvs__vprep_components(pvs__vprep *p, pvs__vprep_scratch *w) {
	uint32_t *deg = w->deg, *adj = w->adj, *uf = w->uf, *idx = w->idx, m = p->nseg, nv = w->nv, i;
	for (i = 0; i < nv; ++i) { deg[i] = 0; uf[i] = i; }
	for (i = 0; i < m; ++i) {
		uint32_t e;
		for (e = 0; e < 2; ++e) {
			uint32_t v = p->seg_vid[2 * i + e];
			if (deg[v] < 2) adj[2 * v + deg[v]] = i;
			++deg[v];
		}
		{
			uint32_t x = pvs__uf_find(uf, p->seg_vid[2 * i]), y = pvs__uf_find(uf, p->seg_vid[2 * i + 1]);
			if (x != y) uf[x < y ? y : x] = x < y ? x : y;
		}
	}
	for (i = 0; i < m; ++i) p->seg_loop[i] = -1;
	for (i = 0; i < nv; ++i) uf[i] = pvs__uf_find(uf, i);
	for (i = 0; i < nv; ++i) idx[i] = 0;
	for (i = 0; i < nv; ++i)
		if (deg[i] != 2) idx[uf[i]] = 1;
}

/* The wall loops: components whose vertices each join two segments, walked from the lowest segment into ring order
   (ring_seg, ring_pt, loop_start), with lowest top, box and convex hull (hull_pt, hull_vid, hull_start). */
PVS__STATIC void pvs__vprep_loops(pvs__vprep *p, pvs__vprep_scratch *w) {
	uint32_t *adj = w->adj, *uf = w->uf, *idx = w->idx, *hidx = w->hidx, m = p->nseg, ring = 0, h = 0, i;
	p->nloop = 0;
	p->loop_start[0] = 0;
	for (i = 0; i < m; ++i) {
		uint32_t root = uf[p->seg_vid[2 * i]], s, v, count = 0, l, hn, k;
		if (idx[root] || p->seg_loop[i] >= 0) continue;
		l = p->nloop;
		s = i;
		v = p->seg_vid[2 * i];
		do {
			uint32_t wv = p->seg_vid[2 * s] == v ? p->seg_vid[2 * s + 1] : p->seg_vid[2 * s];
			const double *pt = p->seg + 4 * (size_t)s + (p->seg_vid[2 * s] == v ? 0 : 2);
			p->seg_loop[s] = (int32_t)l;
			p->ring_seg[ring + count] = s;
			p->ring_pt[2 * (ring + count)] = pt[0];
			p->ring_pt[2 * (ring + count) + 1] = pt[1];
			++count;
			v = wv;
			s = adj[2 * v] == s ? adj[2 * v + 1] : adj[2 * v];
		} while (s != i && count <= m);
		if (count < 3) { /* two segments on the same two points: no inside */
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
		hn = pvs__vo_hull(p->ring_pt + 2 * ring, count, w->keys, hidx);
		p->hull_start[l] = h;
		/* ring point q starts ring segment q: its id is the vertex it shares with segment q - 1 */
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

/* The objects of §3 (Koltun 2000): loops with a usable hull (3 to PVS__VO_MAXH vertices), then the segments of no such
   loop; box, top. */
PVS__STATIC void pvs__vprep_objects(pvs__vprep *p) {
	uint32_t i;
	p->nobj = 0;
	for (i = 0; i < p->nloop; ++i) {
		uint32_t hn = p->hull_start[i + 1] - p->hull_start[i];
		if (hn < 3 || hn > PVS__VO_MAXH) continue;
		p->obj_ref[p->nobj] = i;
		memcpy(p->obj_bb + 4 * (size_t)p->nobj, p->loop_bb + 4 * (size_t)i, 4 * sizeof(double));
		p->obj_top[p->nobj++] = p->loop_top[i];
	}
	for (i = 0; i < p->nseg; ++i) {
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
}

/* The bucket grid: about two objects per bucket, at most 1024 x 1024; an object in the buckets its box covers, a long
   wall in those along it. Returns OUT_OF_MEMORY or PVS_OK. */
PVS__STATIC pvs_result pvs__vprep_grid(pvs__vprep *p, const pvs_allocator *al) {
	double w, hh, cs;
	size_t total = 0, cells;
	uint32_t i, j;
	p->bb[0] = p->bb[1] = DBL_MAX;
	p->bb[2] = p->bb[3] = -DBL_MAX;
	for (i = 0; i < p->nobj; ++i) {
		pvs__vo_bb_add(p->bb, p->obj_bb + 4 * (size_t)i);
		pvs__vo_bb_add(p->bb, p->obj_bb + 4 * (size_t)i + 2);
	}
	if (!p->nobj) { p->bb[0] = p->bb[1] = 0.0; p->bb[2] = p->bb[3] = 1.0; }
	w = p->bb[2] - p->bb[0];
	hh = p->bb[3] - p->bb[1];
	cs = sqrt((w * hh > 0.0 ? w * hh : (w + hh) * (w + hh) + 1.0) / (0.5 * (p->nobj + 1)));
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
	if (!p->gstart) return PVS_ERROR_OUT_OF_MEMORY;
	memset(p->gstart, 0, (cells + 1) * sizeof(uint32_t));
	for (j = 0; j < 2; ++j) {
		for (i = 0; i < p->nobj; ++i) {
			const double *b = p->obj_bb + 4 * (size_t)i;
			uint32_t x0 = (uint32_t)((b[0] - p->g0[0]) / cs), y0 = (uint32_t)((b[1] - p->g0[1]) / cs);
			uint32_t x1 = (uint32_t)((b[2] - p->g0[0]) / cs), y1 = (uint32_t)((b[3] - p->g0[1]) / cs), x, y;
			if (x1 >= p->gw) x1 = p->gw - 1;
			if (y1 >= p->gh) y1 = p->gh - 1;
			if (p->obj_ref[i] >= p->nloop && (uint64_t)(x1 - x0 + 1) * (y1 - y0 + 1) > 16) {
				/* a long wall: the buckets along it, sampled a quarter bucket apart (a missed bucket only hides it from
				   the search, never from a check) */
				const double *sg = p->seg + 4 * (size_t)(p->obj_ref[i] - p->nloop);
				double len = sqrt((sg[2] - sg[0]) * (sg[2] - sg[0]) + (sg[3] - sg[1]) * (sg[3] - sg[1]));
				uint32_t steps = (uint32_t)(4.0 * len / cs) + 1, t, last = 0xffffffffu;
				for (t = 0; t <= steps; ++t) {
					double u = (double)t / steps;
					uint32_t bx = (uint32_t)((sg[0] + u * (sg[2] - sg[0]) - p->g0[0]) / cs),
							 by = (uint32_t)((sg[1] + u * (sg[3] - sg[1]) - p->g0[1]) / cs), at;
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
			if (!p->gitem) return PVS_ERROR_OUT_OF_MEMORY;
			/* prefix sums: gstart[c + 1] ends bucket c; filling moves it to the start */
			for (c2 = 0; c2 < cells; ++c2) p->gstart[c2 + 1] += p->gstart[c2];
		}
	}
	/* gstart[c + 1] now starts bucket c: shift down */
	for (i = 0; i < (uint32_t)cells; ++i) p->gstart[i] = p->gstart[i + 1];
	p->gstart[cells] = (uint32_t)total;
	return PVS_OK;
}

/* Prepares n segments (4 doubles, ground coordinates; zero-length ones dropped) and their tops: vertex ids by exact
   coordinates, wall loops, hulls, objects, buckets. */
PVS__STATIC pvs_result pvs__vprep_create(const pvs_allocator *al, const double *seg, const float *top, uint32_t n,
										 pvs__vprep **out) {
	pvs__vprep *p;
	pvs__vprep_scratch w;
	uint32_t i, m = 0;
	pvs_result r = PVS_ERROR_OUT_OF_MEMORY;
	*out = NULL;
	p = (pvs__vprep *)pvs__alloc(al, sizeof(pvs__vprep), 16);
	if (!p) return PVS_ERROR_OUT_OF_MEMORY;
	memset(p, 0, sizeof(*p));
	memset(&w, 0, sizeof(w));
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
	w.keys = (pvs__key_index *)pvs__alloc_array(al, 2 * (size_t)m + 2, sizeof(pvs__key_index));
	w.deg = (uint32_t *)pvs__alloc_array(al, 2 * (size_t)m + 2, sizeof(uint32_t));
	w.adj = (uint32_t *)pvs__alloc_array(al, 4 * (size_t)m + 4, sizeof(uint32_t));
	w.uf = (uint32_t *)pvs__alloc_array(al, 2 * (size_t)m + 2, sizeof(uint32_t));
	w.idx = (uint32_t *)pvs__alloc_array(al, 2 * (size_t)m + 2, sizeof(uint32_t));
	w.hidx = (uint32_t *)pvs__alloc_array(al, 2 * (size_t)m + 2, sizeof(uint32_t));
	if (!p->seg || !p->seg_top || !p->seg_vid || !p->seg_loop || !p->loop_start || !p->ring_seg || !p->ring_pt ||
		!p->hull_start || !p->hull_pt || !p->hull_vid || !p->loop_top || !p->loop_bb || !p->obj_ref || !p->obj_bb ||
		!p->obj_top || !w.keys || !w.deg || !w.adj || !w.uf || !w.idx || !w.hidx)
		goto done;
	for (i = 0, m = 0; i < n; ++i) {
		if (seg[4 * i] == seg[4 * i + 2] && seg[4 * i + 1] == seg[4 * i + 3]) continue;
		memcpy(p->seg + 4 * (size_t)m, seg + 4 * (size_t)i, 4 * sizeof(double));
		p->seg_top[m++] = top[i];
	}
	pvs__vprep_vertex_ids(p, &w);
	pvs__vprep_components(p, &w);
	pvs__vprep_loops(p, &w);
	pvs__vprep_objects(p);
	r = pvs__vprep_grid(p, al);
done:
	pvs__free_array(al, w.keys, 2 * (size_t)m + 2, sizeof(pvs__key_index));
	pvs__free_array(al, w.deg, 2 * (size_t)m + 2, sizeof(uint32_t));
	pvs__free_array(al, w.adj, 4 * (size_t)m + 4, sizeof(uint32_t));
	pvs__free_array(al, w.uf, 2 * (size_t)m + 2, sizeof(uint32_t));
	pvs__free_array(al, w.idx, 2 * (size_t)m + 2, sizeof(uint32_t));
	pvs__free_array(al, w.hidx, 2 * (size_t)m + 2, sizeof(uint32_t));
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
	uint32_t first, n;      /* vx[first .. first + n): n = 2 a segment, else a counter-clockwise hull */
	int32_t loop;           /* a hull's wall loop (inside test), -1 */
	uint32_t mark, visit;   /* growth and query stamps */
	uint32_t used;          /* in an aggregate of this slice: no seed again */
	double bb[4];
	double angle;           /* subtended from the cell's centre: seed order */
} pvs__vobj;

typedef struct pvs__vo_span {
	double s, e;            /* pseudo-angles */
	uint32_t is, ie;        /* vertex ids of the ends (PVS__VO_NONE) */
} pvs__vo_span;

/* A virtual occluder of the dense set: ends in the cell's frame exactly as checked after rounding, and as stored. */
typedef struct pvs__vo_cand {
	double a[2], b[2];
	float f[4];             /* pvs_vocc_2d: the world end points */
	uint8_t q[5];           /* the file's bytes */
} pvs__vo_cand;

typedef struct pvs__vo_side {
	double po[2], pd[2];    /* supporting line P: the aggregate's vertex, direction away from the cell */
	double qo[2], qd[2];    /* separating polyline Q: its last vertex and direction */
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
	uint32_t *pfirst, *pcount; /* per prepared object: its blockers in this slice */
	uint32_t epoch, visit;
	uint32_t *g, ng, capg;     /* the aggregate's blockers */
	uint32_t *k, nk, capk;     /* the objects fused into its umbra (seed, cases 1 and 3) */
	double *lines;             /* the aggregate's event lines, 4 doubles each */
	uint32_t nlines, caplines;
	pvs__vo_span *span;
	uint32_t capspan;
	pvs__key_index *ev;
	uint32_t capev;
	uint32_t *sub, capsub;
	double *iv;
	uint32_t capiv;
	double *pts;
	uint32_t cappts;
	pvs__key_index *hkeys;
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
	PVS__VO_FREE(a, c->ev, c->capev, pvs__key_index);
	PVS__VO_FREE(a, c->sub, c->capsub, uint32_t);
	PVS__VO_FREE(a, c->iv, c->capiv, double);
	PVS__VO_FREE(a, c->pts, c->cappts, double);
	PVS__VO_FREE(a, c->hkeys, c->caphkeys, pvs__key_index);
	PVS__VO_FREE(a, c->hidx, c->caphidx, uint32_t);
	PVS__VO_FREE(a, c->out, c->capout, pvs__vo_cand);
	memset(c, 0, sizeof(*c));
}

/* A cell's frame (ground rectangle, world coordinates) over the prepared occluders. */
PVS__STATIC int pvs__vctx_init(pvs__vctx *c, const pvs_allocator *al, const pvs__vprep *p, const double cmin[2],
							   const double cmax[2], double range) {
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
	for (k = 0; k < 4; ++k) {
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
/* 1 if counter-clockwise convex polygon v (n >= 3) meets the cell grown by tol (separating axes). */
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
	for (i = 1; i < n; ++i) { /* tangent vertices from the centre: the subtended angle */
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

/* The blockers of slice height h: loops reaching h whose hull misses the cell as hulls, other walls reaching h as
   segments unless they meet the cell. */
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
			for (j = p->loop_start[ref]; j < p->loop_start[ref + 1]; ++j) {
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

/* 1 if x lies inside wall loop l (odd crossings), farther than tol from its walls. Only for loops whose hull misses the
   cell. */
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

/* Entry distance of ray x + s w into object o, -1 when it misses. */
PVS__STATIC double pvs__vo_ray_obj(const pvs__vctx *c, const pvs__vobj *o, const double *x, const double *w) {
	const double *v = c->vx + 2 * (size_t)o->first;
	if (o->n == 2) {
		double ex = v[2] - v[0], ey = v[3] - v[1], den = w[0] * ey - w[1] * ex, qx = v[0] - x[0], qy = v[1] - x[1], s,
			   u;
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
			double nx = b[1] - a[1], ny = a[0] - b[0]; /* outward normal (counter-clockwise edge) */
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

/* 1 if x is inside convex object o or within tol of it (o is then unusable from x). */
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

/* The cell's fan from x: extreme corners cl, ch (in a half-plane), unit bisector f, the edges' pseudo-angles aL, aR
   about f, the box of cell and x grown by tol. */
typedef struct pvs__vo_fan {
	const double *cl, *ch;
	double f[2], aL, aR, bb[4];
} pvs__vo_fan;

/* The fan from x (outside the cell); 0 when it has no direction. */
PVS__STATIC int pvs__vo_fan_init(const pvs__vctx *c, const double *x, pvs__vo_fan *fn) {
	const double *cl, *ch;
	double tol = c->tol;
	uint32_t k;
	cl = ch = c->corner;
	for (k = 1; k < 4; ++k) {
		const double *q = c->corner + 2 * k;
		if (pvs__vo_cross(x, cl, q) < 0.0) cl = q;
		if (pvs__vo_cross(x, ch, q) > 0.0) ch = q;
	}
	fn->cl = cl;
	fn->ch = ch;
	{
		double a0 = cl[0] - x[0], a1 = cl[1] - x[1], b0 = ch[0] - x[0], b1 = ch[1] - x[1];
		double la = sqrt(a0 * a0 + a1 * a1), lb = sqrt(b0 * b0 + b1 * b1), len;
		fn->f[0] = a0 / la + b0 / lb;
		fn->f[1] = a1 / la + b1 / lb;
		len = sqrt(fn->f[0] * fn->f[0] + fn->f[1] * fn->f[1]);
		if (!(len > 0.0)) return 0;
		fn->f[0] /= len;
		fn->f[1] /= len;
		fn->aL = pvs__vo_pangle(fn->f[0] * a0 + fn->f[1] * a1, fn->f[0] * a1 - fn->f[1] * a0);
		fn->aR = pvs__vo_pangle(fn->f[0] * b0 + fn->f[1] * b1, fn->f[0] * b1 - fn->f[1] * b0);
	}
	fn->bb[0] = (x[0] < c->cmin[0] ? x[0] : c->cmin[0]) - tol;
	fn->bb[1] = (x[1] < c->cmin[1] ? x[1] : c->cmin[1]) - tol;
	fn->bb[2] = (x[0] > c->cmax[0] ? x[0] : c->cmax[0]) + tol;
	fn->bb[3] = (x[1] > c->cmax[1] ? x[1] : c->cmax[1]) + tol;
	return 1;
}

/* Blocker o's share of the from-point test: appends to c->span at *ns (room for two) the part of the fan o covers
   before the cell, two intervals across the back direction. Returns 1 when x is inside o's wall loop (hidden). */
PVS__STATIC int pvs__vo_obj_spans(pvs__vctx *c, const pvs__vobj *o, const double *x, const pvs__vo_fan *fn,
								  uint32_t *ns) {
	const double *v = c->vx + 2 * (size_t)o->first, *cl = fn->cl, *ch = fn->ch, *f = fn->f;
	double plo, phi, sp[2][2], tol = c->tol, len;
	uint32_t lo = 0, hi = 0, j, pieces;
	int near_box;
	if (o->loop >= 0 && x[0] >= o->bb[0] && x[0] <= o->bb[2] && x[1] >= o->bb[1] && x[1] <= o->bb[3] &&
		pvs__vo_in_loop(c, (uint32_t)o->loop, x))
		return 1;
	if (o->bb[0] > fn->bb[2] || o->bb[2] < fn->bb[0] || o->bb[1] > fn->bb[3] || o->bb[3] < fn->bb[1]) return 0;
	{ /* a box wholly outside the fan (beyond an edge line) cannot help */
		/* cross(x, q, p) = e0 p1 - e1 p0 - e0 x1 + e1 x0 (e = q - x) is linear in p: the box's corners bound it */
		double e0 = cl[0] - x[0], e1 = cl[1] - x[1], g0 = ch[0] - x[0], g1 = ch[1] - x[1], mx, mn;
		mx = (e0 > 0.0 ? e0 * o->bb[3] : e0 * o->bb[1]) + (e1 > 0.0 ? -e1 * o->bb[0] : -e1 * o->bb[2]) - e0 * x[1] +
			e1 * x[0];
		if (mx < -tol * (fabs(e0) + fabs(e1))) return 0; /* clockwise of the fan's edge x -> cl */
		mn = (g0 > 0.0 ? g0 * o->bb[1] : g0 * o->bb[3]) + (g1 > 0.0 ? -g1 * o->bb[2] : -g1 * o->bb[0]) - g0 * x[1] +
			g1 * x[0];
		if (mn > tol * (fabs(g0) + fabs(g1))) return 0; /* counter-clockwise of x -> ch */
	}
	near_box = x[0] >= o->bb[0] - tol && x[0] <= o->bb[2] + tol && x[1] >= o->bb[1] - tol && x[1] <= o->bb[3] + tol;
	if (near_box && pvs__vo_near_obj(c, o, x)) return 0;
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
		double os = sp[j][0] > fn->aL ? sp[j][0] : fn->aL, oe = sp[j][1] < fn->aR ? sp[j][1] : fn->aR, mid, w[2], wd,
			   wc, so, sc;
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
		c->span[*ns].s = sp[j][0];
		c->span[*ns].e = sp[j][1];
		c->span[*ns].is = c->vid[o->first + lo];
		c->span[*ns].ie = c->vid[o->first + hi];
		++*ns;
	}
	return 0;
}

/* Returns 1 when c->span[0 .. ns) (sorted here) covers the fan [aL, aR]. Spans ending on the same vertex join exactly
   (walls of an open chain), other joins need an overlap beyond PVS__VO_ATOL: rounding only ever says "not hidden". */
PVS__STATIC int pvs__vo_spans_cover(pvs__vctx *c, uint32_t ns, double aL, double aR) {
	double reach;
	uint32_t i, k, rid;
	for (i = 1; i < ns; ++i) {
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

/* The from-point test of the header: 1 if every segment from the cell to x meets one of set[0..n). Rounding only ever
   answers 0. */
PVS__STATIC int pvs__vo_hidden(pvs__vctx *c, const uint32_t *set, uint32_t n, const double *x) {
	pvs__vo_fan fn;
	double tol = c->tol;
	uint32_t i, ns = 0;
	if (x[0] > c->cmin[0] - tol && x[0] < c->cmax[0] + tol && x[1] > c->cmin[1] - tol && x[1] < c->cmax[1] + tol)
		return 0;
	if (!pvs__vo_reserve(c->al, (void **)&c->span, &c->capspan, 2 * (size_t)n + 2, sizeof(pvs__vo_span))) {
		c->oom = 1;
		return 0;
	}
	if (!pvs__vo_fan_init(c, x, &fn)) return 0;
	for (i = 0; i < n; ++i)
		if (pvs__vo_obj_spans(c, c->obj + set[i], x, &fn, &ns)) return 1;
	return pvs__vo_spans_cover(c, ns, fn.aL, fn.aR);
}

/* ---- the aggregate: blockers, and the lines where hidden answers can change ---- */

/* Common tangents of two convex vertex sets through the cell (only those change a hidden answer); need_cell 0 when one
   set is the cell. */
PVS__STATIC void pvs__vo_tangent_lines(pvs__vctx *c, const double *a, uint32_t na, const double *b, uint32_t nb,
									   int need_cell) {
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
			if (!pvs__vo_reserve(c->al, (void **)&c->lines, &c->caplines, 4 * ((size_t)c->nlines + 1),
								 sizeof(double))) {
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

/* Adds object o to the aggregate's blockers and event lines. */
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
	if (!pvs__vo_reserve(c->al, (void **)&c->ev, &c->capev, (size_t)*n + 1, sizeof(pvs__key_index))) {
		c->oom = 1;
		return;
	}
	c->ev[*n].key = t;
	c->ev[*n].index = *n;
	++*n;
}
/* Where segment a-b (a line when `line`) crosses line p + t d. */
PVS__STATIC void pvs__vo_ev_seg(pvs__vctx *c, uint32_t *n, const double *p, const double *d, const double *a,
								const double *b, int line, double t0, double t1) {
	double ex = b[0] - a[0], ey = b[1] - a[1], den = d[0] * ey - d[1] * ex, qx = a[0] - p[0], qy = a[1] - p[1], t, u;
	if (!(fabs(den) > 1e-15 * (fabs(ex) + fabs(ey)) * (fabs(d[0]) + fabs(d[1])))) return;
	t = (qx * ey - qy * ex) / den;
	if (!line) {
		u = (qx * d[1] - qy * d[0]) / den;
		if (u < -1e-9 || u > 1.0 + 1e-9) return;
	}
	pvs__vo_ev_push(c, n, t, t0, t1);
}

/* The hidden parts of p + t d, t in [t0, t1], for the aggregate's blockers: closed intervals into out (at most cap).
   Returns their count. */
PVS__STATIC uint32_t pvs__vo_line_hidden(pvs__vctx *c, const double *p, const double *d, double t0, double t1,
										 double *out, uint32_t cap) {
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
	if (!pvs__vo_reserve(c->al, (void **)&c->sub, &c->capsub, (size_t)c->ng + 1, sizeof(uint32_t))) {
		c->oom = 1;
		return 0;
	}
	for (i = 0; i < c->ng; ++i) { /* blockers that can stand between the cell and the segment */
		const pvs__vobj *o = c->obj + c->g[i];
		if (o->bb[0] > bb[2] + c->tol || o->bb[2] < bb[0] - c->tol || o->bb[1] > bb[3] + c->tol ||
			o->bb[3] < bb[1] - c->tol)
			continue;
		c->sub[nsub++] = c->g[i];
	}
	/* events: the cell's edges, the tangent lines, the blockers' boundaries and loops */
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
	pvs__key_index_sort(c->ev, ne);
	eps = 1e-12 * (span + c->scale / (fabs(d[0]) + fabs(d[1]) + 1e-300));
	for (i = 0, j = 0; i < ne; ++i) /* merge coincident events */
		if (!j || c->ev[i].key - c->ev[j - 1].key > eps) c->ev[j++] = c->ev[i];
	c->ev[j - 1].key = t1;
	c->ev[0].key = t0;
	ne = j;
	for (i = 0; i + 1 < ne; ++i) {
		double m = 0.5 * (c->ev[i].key + c->ev[i + 1].key), x[2];
		int hid;
		x[0] = p[0] + m * d[0];
		x[1] = p[1] + m * d[1];
		hid = pvs__vo_hidden(c, c->sub, nsub, x);
		if (hid && !run) { run = 1; run_start = c->ev[i].key; }
		if (!hid && run) {
			run = 0;
			if (nout < cap) { out[2 * nout] = run_start; out[2 * nout + 1] = c->ev[i].key; ++nout; }
		}
	}
	if (run && nout < cap) { out[2 * nout] = run_start; out[2 * nout + 1] = c->ev[ne - 1].key; ++nout; }
	return c->oom ? 0 : nout;
}

/* 1 if all of segment a-b is hidden (checked a little past both ends). */
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

/* The first object not in or refused by the aggregate on ray o + s w (w unit), 0 < s <= smax, walking the buckets
   (*s_hit: its s); PVS__VO_NONE if none. */
PVS__STATIC uint32_t pvs__vo_ray_first(pvs__vctx *c, const double *o, const double *w, double smax, double *s_hit) {
	const pvs__vprep *p = c->p;
	double ox = o[0] + c->centre[0] - p->g0[0], oy = o[1] + c->centre[1] - p->g0[1], cs = p->gcell, best = DBL_MAX,
		   s = 0.0;
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

/* How far a ray from o along w may go: the analysis radius. */
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

/* The fused objects' vertices into c->pts (after the cell's 4 corners with with_cell). */
PVS__STATIC uint32_t pvs__vo_k_points(pvs__vctx *c, int with_cell) {
	uint32_t i, j, n = with_cell ? 4 : 0, total = n;
	for (i = 0; i < c->nk; ++i) total += c->obj[c->k[i]].n;
	if (!pvs__vo_reserve(c->al, (void **)&c->pts, &c->cappts, 2 * (size_t)total + 2, sizeof(double)) ||
		!pvs__vo_reserve(c->al, (void **)&c->hkeys, &c->caphkeys, (size_t)total + 1, sizeof(pvs__key_index)) ||
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

/* The active lines from the fused objects: supporting lines bridge the hull of cell and aggregate, separating lines are
   inner common tangents; side 0 is the left seen from the cell. Bit s of which resets side s's separating line.
   Returns 0 when the aggregate surrounds the cell. */
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
	/* inner tangents: a cell corner and an aggregate hull vertex, the cell on one side, the aggregate on the other */
	n = pvs__vo_k_points(c, 0);
	hn = pvs__vo_hull(c->pts, n, c->hkeys, c->hidx);
	for (s = 0; s < 2; ++s) {
		double sign = s ? -1.0 : 1.0, best = -1.0;
		uint32_t j, k;
		if (!(which & (1 << s))) continue;
		for (i = 0; i < 4; ++i)
			for (j = 0; j < hn; ++j) {
				const double *cp = c->corner + 2 * i, *kp = c->pts + 2 * c->hidx[j];
				double len = sqrt((kp[0] - cp[0]) * (kp[0] - cp[0]) + (kp[1] - cp[1]) * (kp[1] - cp[1])),
					   t = c->tol * len;
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

/* Case 2: side s's separating polyline bends around b, to b's vertex keeping all of b on the aggregate's side. */
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

/* 1 if a probe point of b (vertices, edge midpoints, extra) is hidden by the aggregate without b: b meets the umbra
   (cases 1, 3). */
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

/* Angle of p + t d, t in [t0, t1], seen from the cell's centre. */
PVS__STATIC double pvs__vo_angle(const double *p, const double *d, double t0, double t1) {
	double a0 = p[0] + t0 * d[0], a1 = p[1] + t0 * d[1], b0 = p[0] + t1 * d[0], b1 = p[1] + t1 * d[1];
	return fabs(atan2(a0 * b1 - a1 * b0, a0 * b0 + a1 * b1));
}

/* The hidden parts of line p + t d (d unit) in the aggregate's wedge (supporting lines widened by a quarter, within the
   analysis radius): *cur gets the one of largest angle (keep: the one around keep_t). Returns that angle, 0 when
   none. */
PVS__STATIC double pvs__vo_try_line(pvs__vctx *c, const pvs__vo_side *sd, const double *p, const double *d,
									double keep_t, int keep, pvs__vo_cur *cur) {
	double lo = DBL_MAX, hi = -DBL_MAX, iv[64], best = 0.0, b, cc, disc, w;
	uint32_t s, n, i;
	for (s = 0; s < 2; ++s) {
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

/* Places a virtual occluder behind b (§3) on the best of three lines just beyond b: across the umbra (normal to the
   supporting lines' bisector), on the silhouette chord through their contacts, across b's view from the cell's centre.
   Keeps the hidden interval subtending the largest angle. keep (case 3): the current line, the interval around its
   middle. */
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
		if (k == 1 && nrm[0] * sd[0].po[0] + nrm[1] * sd[0].po[1] < 0.0) {
			nrm[0] = -nrm[0];
			nrm[1] = -nrm[1];
		} /* away from the cell */
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

/* A cell's coordinate scale S = 2^((code - 128) / 8), code 0..255 (exact: a constant times a power of two). Byte q puts
   a coordinate at centre + S (q - 128) |q - 128| / 16384, from -S to 0.98 S, finer near the cell where a metre matters
   more. */
PVS__STATIC double pvs__vo_scale(uint32_t code) {
	static const double mant[8] = {1.0, 1.0905077326652577, 1.189207115002721, 1.2968395546510096,
								   1.4142135623730951, 1.5422108254079407, 1.681792830507429, 1.8340080864093424};
	return ldexp(mant[code & 7u], (int)(code >> 3) - 16);
}
PVS__STATIC double pvs__vo_offset(double scale, uint32_t q) {
	int32_t d = (int32_t)q - 128;
	return scale * (double)(d * (d < 0 ? -d : d)) / 16384.0;
}
/* Largest byte whose offset is <= x (0 when none). */
PVS__STATIC uint32_t pvs__vo_floor_code(double scale, double x) {
	double r = x / scale * 16384.0, d = r < 0.0 ? -sqrt(-r) : sqrt(r);
	int32_t q = (int32_t)floor(d) + 128;
	if (q < 0) q = 0;
	if (q > 255) q = 255;
	while (q < 255 && pvs__vo_offset(scale, (uint32_t)q + 1) <= x) ++q;
	while (q > 0 && pvs__vo_offset(scale, (uint32_t)q) > x) --q;
	return (uint32_t)q;
}
/* The frame origin as the file reader computes it: float centre of the stored float box. */
PVS__STATIC void pvs__vo_cell_centre(const pvs_box *cell, int u, int v, double centre[2]) {
	centre[0] = (double)(0.5f * cell->min[u] + 0.5f * cell->max[u]);
	centre[1] = (double)(0.5f * cell->min[v] + 0.5f * cell->max[v]);
}
/* Smallest scale code whose range holds every point within reach of the centre. */
PVS__STATIC uint32_t pvs__vo_scale_code(double reach) {
	uint32_t code;
	for (code = 0; code < 255; ++code)
		if (pvs__vo_offset(pvs__vo_scale(code), 255) >= reach && pvs__vo_offset(pvs__vo_scale(code), 0) <= -reach)
			break;
	return code;
}

/* Rounds occluder a-b (cell frame) to stored bytes, shrinking it and moving its ends away from the cell ("toward
   smaller occluders", §4), and checks the rounded one exactly; six tries, each shrinking more. Returns 1 with *out
   filled. */
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
	if (nrm[0] * (a[0] + b[0]) + nrm[1] * (a[1] + b[1]) < 0.0) {
		nrm[0] = -nrm[0];
		nrm[1] = -nrm[1];
	} /* away from the cell */
	/* height: rounded down */
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
		for (end = 0; end < 2; ++end) { /* grid corner around the end: inward, then behind, then nearest */
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
		/* the stored geometry, exactly as the reader decodes it */
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

/* Grows one seed's aggregate umbra (§3, Fig. 3, Fig. 4: both sides at once). */
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
			if (in_u) { /* cases 1 and 3 */
				pvs__vo_g_add(c, b);
				if (c->nk < PVS__VO_MAXG) c->k[c->nk++] = b;
				++c->st.umbra;
				if (!pvs__vo_tangents(c, sd, 1 << s)) break;
				sd[0].done = sd[1].done = 0;
				if (!via_q) { /* case 1: the old one is dumped */
					pvs__vo_cur next;
					memset(&next, 0, sizeof(next));
					if (pvs__vo_place(c, sd, b, &next, 0)) {
						pvs__vo_dump(c, &cur);
						cur = next;
					}
				} else if (!pvs__vo_place(c, sd, b, &cur, 1)) { /* case 3 */
					pvs__vo_place(c, sd, b, &cur, 0);
				}
			} else if (on_q) { /* case 2 */
				pvs__vo_g_add(c, b);
				++c->st.separating;
				pvs__vo_bend(c, sd + s, s, b);
			} else {
				c->obj[b].mark = c->epoch; /* on P only, outside U: no help */
			}
		}
		if (!progressed) break;
	}
	pvs__vo_dump(c, &cur);
	/* the whole aggregate: one more occluder behind the seed */
	if (c->ng > 1 && pvs__vo_place(c, sd, seed, &cur, 0)) pvs__vo_dump(c, &cur);
}

/* Grows up to max_seeds seeds of the slice, largest subtended angle first. */
PVS__STATIC void pvs__vo_run_slice(pvs__vctx *c) {
	pvs__key_index *order;
	uint32_t i, n = c->nobj, grown = 0;
	order = (pvs__key_index *)pvs__alloc_array(c->al, (size_t)n + 1, sizeof(pvs__key_index));
	if (!order) { c->oom = 1; return; }
	for (i = 0; i < n; ++i) {
		order[i].key = -c->obj[i].angle;
		order[i].index = i;
		c->obj[i].used = 0;
		c->obj[i].mark = 0;
	}
	c->epoch = 0;
	pvs__key_index_sort(order, n);
	for (i = 0; i < n && grown < c->max_seeds && !c->oom; ++i) {
		uint32_t o = order[i].index;
		if (c->obj[o].used || !(c->obj[o].angle > 1e-4)) continue;
		pvs__vo_grow(c, o);
		++grown;
	}
	pvs__free_array(c->al, order, (size_t)n + 1, sizeof(pvs__key_index));
}

/* A virtual occluder from the growth: rounded as stored, checked, kept. */
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
	double n[2], off;         /* the occluder's line n.x = off (n unit), the cell where n.x < off */
	double h[8][3];           /* the 2D umbra's other sides: h[0..8) . (x, y, 1) >= 0 (unit normals) */
	double dcmin, dcmax;      /* the cell's ground corners' distances from the line (> 0) */
	double base, top, cbot, ctop;
	double m, mh;             /* margins: lengths, heights */
	int u_axis, v_axis, up, ok;
} pvs__vo_rt;

/* Prepares the test of occluder a-b (world ground coordinates, heights base..top) for a cell. In 2D a box is hidden
   when it lies in the umbra (§3): beyond the line and, for each cell corner c, on b's side of line c-a and a's side of
   c-b. Rectangles are convex: corners decide; support functions test the box's at once. Margins (1e-7 of the frame's
   extent) make rounding answer "not hidden". */
PVS__STATIC void pvs__vo_rt_init(pvs__vo_rt *r, const pvs_box *cell, uint32_t up, const double *a, const double *b,
								 double base, double top) {
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
	if (dmax < 0.0) { /* the cell on the other side: flip */
		double t = dmin;
		r->n[0] = -r->n[0];
		r->n[1] = -r->n[1];
		r->off = -r->off;
		dmin = -dmax;
		dmax = -t;
	}
	if (!(dmin > r->m)) return; /* the line meets the cell: hides nothing */
	for (e = 0; e < 2; ++e) { /* through each end from each cell corner, the occluder's side kept */
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

/* 1 if every sight line from the cell box to box b crosses the occluder. */
PVS__STATIC int pvs__vo_rt_hides(const pvs__vo_rt *r, const pvs_box *b) {
	double x0 = (double)b->min[r->u_axis] - r->o[0], x1 = (double)b->max[r->u_axis] - r->o[0];
	double y0 = (double)b->min[r->v_axis] - r->o[1], y1 = (double)b->max[r->v_axis] - r->o[1];
	double dbmin, dbmax, tmin, tmax, btop, bbot;
	int k;
	if (!r->ok) return 0;
	/* beyond the line: the least n.x - off over the box (support function) */
	dbmin = (r->n[0] > 0.0 ? r->n[0] * x0 : r->n[0] * x1) + (r->n[1] > 0.0 ? r->n[1] * y0 : r->n[1] * y1) - r->off;
	if (!(dbmin > r->m)) return 0;
	for (k = 0; k < 8; ++k) {
		const double *h = r->h[k];
		if (!((h[0] > 0.0 ? h[0] * x0 : h[0] * x1) + (h[1] > 0.0 ? h[1] * y0 : h[1] * y1) + h[2] > r->m)) return 0;
	}
	/* heights: a sight line crosses the occluder's plane at (1 - t) eye + t target, t = dc / (dc + db) (its ends'
	   distances from the line) in [tmin, tmax]; the bounds are linear in t */
	dbmax = (r->n[0] > 0.0 ? r->n[0] * x1 : r->n[0] * x0) + (r->n[1] > 0.0 ? r->n[1] * y1 : r->n[1] * y0) - r->off;
	tmin = r->dcmin / (r->dcmin + dbmax);
	tmax = r->dcmax / (r->dcmax + dbmin);
	btop = b->max[r->up];
	bbot = b->min[r->up];
	if (r->ctop + tmin * (btop - r->ctop) > r->top - r->mh || r->ctop + tmax * (btop - r->ctop) > r->top - r->mh)
		return 0;
	if (r->cbot + tmin * (bbot - r->cbot) < r->base + r->mh || r->cbot + tmax * (bbot - r->cbot) < r->base + r->mh)
		return 0;
	return 1;
}

PVS__STATIC int pvs__vo_box_ok(const pvs_box *b) {
	int k;
	for (k = 0; k < 3; ++k)
		if (!(b->min[k] <= b->max[k]) || !pvs__finite(b->min[k]) || !pvs__finite(b->max[k])) return 0;
	return 1;
}

PVS_API int pvs_vocc_box_hidden(const pvs_box *cell, uint32_t up_axis, const pvs_virtual_occluder *o,
								const pvs_box *box) {
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
PVS__STATIC pvs_visit pvs__vo_walk_visit(void *user, const pvs_box *node_box, float distance, const uint32_t *items,
										 uint32_t count) {
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

/* The walk over prepared occluders rt[0..count) at the scratch's front. */
/* Adds the counts of b to a. */
PVS__STATIC void pvs__vo_stats_add(pvs_vocc_stats *a, const pvs_vocc_stats *b) {
	a->slices += b->slices;
	a->seeds += b->seeds;
	a->umbra += b->umbra;
	a->separating += b->separating;
	a->dense += b->dense;
	a->dropped += b->dropped;
	a->selected += b->selected;
}

PVS__STATIC pvs_result pvs__vo_cull(const pvs_box *cell, pvs__vo_rt *rt, uint32_t count, const pvs_box *boxes,
									uint32_t object_count, const pvs_kdtree *tree, uint8_t *rest, size_t rest_size,
									pvs_word *visible, pvs_error *err) {
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
		if (r != PVS_OK)
			return pvs__fail(err, r, -1, 0, "object tree walk (scratch %llu bytes)", (unsigned long long)rest_size);
	} else {
		for (i = 0; i < object_count; ++i)
			if (pvs__vo_box_ok(boxes + i) && !pvs__vo_walk_hidden(&w, boxes + i)) pvs_bitset_set(visible, i);
	}
	pvs__ok(err);
	return PVS_OK;
}

/* Splits the caller's scratch into the occluder array and the rest (16-aligned). */
PVS__STATIC pvs_result pvs__vo_scratch(void *scratch, size_t size, uint32_t count, const pvs_kdtree *tree,
									   pvs__vo_rt **rt, uint8_t **rest, size_t *rest_size, pvs_error *err) {
	size_t need = pvs_vocc_cull_scratch_size(tree, count),
		   head = ((size_t)count * sizeof(pvs__vo_rt) + 15u) / 16u * 16u;
	uint8_t *p = (uint8_t *)scratch;
	size_t skew;
	if (!scratch) return pvs__fail(err, PVS_ERROR_INVALID_ARGUMENT, -1, 0, "scratch is NULL");
	skew = (size_t)(-(intptr_t)p) & 15u;
	if (size < need || size - skew < need - 16u)
		return pvs__fail(err, PVS_ERROR_BUFFER_TOO_SMALL, -1, 0, "scratch of %llu bytes, need %llu",
						 (unsigned long long)size, (unsigned long long)need);
	p += skew;
	*rt = (pvs__vo_rt *)(void *)p;
	*rest = p + head;
	*rest_size = size - skew - head;
	return PVS_OK;
}

PVS_API pvs_result pvs_vocc_cull_occluders(const pvs_box *cell, uint32_t up_axis, const pvs_virtual_occluder *occ,
										   uint32_t count, const pvs_box *boxes, uint32_t object_count,
										   const pvs_kdtree *tree, void *scratch, size_t scratch_size,
										   pvs_word *visible, pvs_error *err) {
	pvs__vo_rt *rt;
	uint8_t *rest;
	size_t rest_size;
	uint32_t i;
	pvs_result r;
	if (!cell || (count && !occ) || (object_count && !boxes) || !visible)
		return pvs__fail(err, PVS_ERROR_INVALID_ARGUMENT, -1, 0, "cell, occluders, boxes and visible must not be NULL");
	if (!pvs__vo_box_ok(cell))
		return pvs__fail(err, PVS_ERROR_INVALID_ARGUMENT, -1, 0, "the cell box is empty or not finite");
	r = pvs__vo_scratch(scratch, scratch_size, count, tree, &rt, &rest, &rest_size, err);
	if (r != PVS_OK) return r;
	for (i = 0; i < count; ++i) {
		double a[2], b[2];
		a[0] = occ[i].p0[0]; a[1] = occ[i].p0[1];
		b[0] = occ[i].p1[0]; b[1] = occ[i].p1[1];
		pvs__vo_rt_init(rt + i, cell, up_axis, a, b, occ[i].base, occ[i].top);
		if (!pvs__finite(occ[i].p0[0]) || !pvs__finite(occ[i].p0[1]) || !pvs__finite(occ[i].p1[0]) ||
			!pvs__finite(occ[i].p1[1]))
			rt[i].ok = 0;
	}
	return pvs__vo_cull(cell, rt, count, boxes, object_count, tree, rest, rest_size, visible, err);
}

/* ---- the VOCC section of a .pvs file (layout in the manual) ---- */

#define PVS__VO_TAG ((uint32_t)'V' | ((uint32_t)'O' << 8) | ((uint32_t)'C' << 16) | ((uint32_t)'C' << 24))
#define PVS__VO_HEAD 16u
#define PVS__VO_BLOCK 16u

/* Bytes of a VOCC section of cells cells and n occluders (0 past 32 bits). */
PVS__STATIC size_t pvs__vo_section_size(uint32_t cells, uint64_t n) {
	uint64_t blocks = ((uint64_t)cells + PVS__VO_BLOCK - 1) / PVS__VO_BLOCK,
			 size = PVS__VO_HEAD + 4 * (blocks + 1) + 2 * (uint64_t)cells + 5 * n;
	return size > 0xfffffff0ull ? 0 : (size_t)size;
}

/* Writes the section (pvs__vo_section_size bytes) from per-cell counts, scale codes and occluder bytes in cell order
   (stride 0: packed). */
PVS__STATIC void pvs__vo_section_write(uint8_t *o, uint32_t flags, float base, float hstep, uint32_t cells,
									   const uint8_t *counts, const uint8_t *scales, const uint8_t *bytes,
									   uint32_t stride) {
	uint32_t blocks = (cells + PVS__VO_BLOCK - 1) / PVS__VO_BLOCK, b, i, n = 0;
	uint32_t bu, bh;
	for (i = 0; i < cells; ++i) n += counts[i];
	pvs__put32(o, flags);
	pvs__put32(o + 4, n);
	memcpy(&bu, &base, 4);
	memcpy(&bh, &hstep, 4);
	pvs__put32(o + 8, bu);
	pvs__put32(o + 12, bh);
	for (b = 0, n = 0; b <= blocks; ++b) {
		pvs__put32(o + PVS__VO_HEAD + 4 * b, n);
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

/* Validates a VOCC section of f->cell_count cells (pvs_file_open, after META) into *f. Linear in its size; reads
   nothing outside it. */
PVS__STATIC pvs_result pvs__vo_open_section(pvs_file *f, const uint8_t *file, const uint8_t *sec, uint32_t size,
											pvs_error *err) {
	uint64_t so = (uint64_t)(sec - file);
	uint32_t cells = f->cell_count, blocks = (cells + PVS__VO_BLOCK - 1) / PVS__VO_BLOCK, flags, n, b, i;
	size_t need;
	float base, hstep;
	const uint8_t *counts;
	if (size < PVS__VO_HEAD)
		return pvs__fail(err, PVS_ERROR_BAD_SECTION, -1, so, "VOCC has %u bytes, fewer than its 16-byte header", size);
	flags = pvs__get32(sec);
	n = pvs__get32(sec + 4);
	base = pvs__getf32(sec + 8);
	hstep = pvs__getf32(sec + 12);
	if (flags & ~1u) return pvs__fail(err, PVS_ERROR_BAD_SECTION, -1, so, "VOCC: unknown flags 0x%x", flags);
	if ((uint64_t)n > 255ull * cells)
		return pvs__fail(err, PVS_ERROR_BAD_SECTION, -1, so + 4, "VOCC: %u occluders for %u cells", n, cells);
	if (!pvs__finite(base) || !pvs__finite(hstep) || !(hstep > 0.0f) || !pvs__finite(base + 255.0f * hstep))
		return pvs__fail(err, PVS_ERROR_BAD_SECTION, -1, so + 8, "VOCC: base %g or height step %g is not usable",
						 (double)base, (double)hstep);
	need = pvs__vo_section_size(cells, n);
	if (!need || need != size)
		return pvs__fail(err, PVS_ERROR_BAD_SECTION, -1, so, "VOCC has %u bytes, %u cells and %u occluders need %llu",
						 size, cells, n, (unsigned long long)need);
	counts = sec + PVS__VO_HEAD + 4 * ((size_t)blocks + 1);
	if (pvs__get32(sec + PVS__VO_HEAD) != 0 || pvs__get32(sec + PVS__VO_HEAD + 4 * (size_t)blocks) != n)
		return pvs__fail(err, PVS_ERROR_BAD_SECTION, -1, so + PVS__VO_HEAD, "VOCC: block offsets must run from 0 to %u",
						 n);
	for (b = 0; b < blocks; ++b) {
		uint32_t sum = 0, lo = pvs__get32(sec + PVS__VO_HEAD + 4 * (size_t)b),
				 hi = pvs__get32(sec + PVS__VO_HEAD + 4 * (size_t)b + 4);
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
	uint32_t cells = f->cell_count, blocks = (cells + PVS__VO_BLOCK - 1) / PVS__VO_BLOCK, b = cell / PVS__VO_BLOCK,
			 first, i;
	const uint8_t *counts = sec + PVS__VO_HEAD + 4 * ((size_t)blocks + 1);
	first = pvs__get32(sec + PVS__VO_HEAD + 4 * (size_t)b);
	for (i = b * PVS__VO_BLOCK; i < cell; ++i) first += counts[i];
	*scale = counts[cells + cell];
	*bytes = counts + 2 * (size_t)cells + 5 * (size_t)first;
	return counts[cell];
}

/* One occluder's stored geometry: world ground end points, heights. */
PVS__STATIC void pvs__vo_decode(const pvs_box *cell, uint32_t up, uint32_t scale_code, const uint8_t *q, float base,
								float hstep, double *a, double *b, double *vbase, double *vtop) {
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

PVS_API uint32_t pvs_file_virtual_occluders(const pvs_file *f, uint32_t cell, pvs_virtual_occluder *out,
											uint32_t capacity) {
	const uint8_t *bytes;
	uint32_t scale, n, i;
	pvs_box box;
	if (!f || !f->data || !(f->vocc_flags & PVS_VOCC_STORED) || cell >= f->cell_count) return 0;
	n = pvs__vo_file_cell(f, cell, &bytes, &scale);
	box = pvs_file_cell_box(f, cell);
	for (i = 0; i < n && i < capacity && out; ++i) {
		double a[2], b[2], lo, hi;
		pvs__vo_decode(&box, f->up_axis, scale, bytes + 5 * (size_t)i, f->vocc_base, f->vocc_height_step, a, b, &lo,
					   &hi);
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
	if (f && f->data && (f->vocc_flags & PVS_VOCC_STORED) && cell < f->cell_count)
		n = pvs__vo_file_cell(f, cell, &p, &sc);
	if (scale_code) *scale_code = sc;
	if (bytes) *bytes = p;
	return n;
}

PVS_API pvs_result pvs_vocc_cull(const pvs_file *f, uint32_t cell, uint32_t max_occluders, const pvs_box *boxes,
								 uint32_t object_count, const pvs_kdtree *tree, void *scratch, size_t scratch_size,
								 pvs_word *visible, pvs_error *err) {
	const uint8_t *bytes;
	uint32_t scale, n, i;
	pvs_box box;
	pvs__vo_rt *rt;
	uint8_t *rest;
	size_t rest_size;
	pvs_result r;
	if (!f || !f->data || !visible || (object_count && !boxes))
		return pvs__fail(err, PVS_ERROR_INVALID_ARGUMENT, -1, 0, "file, boxes and visible must not be NULL");
	if (!(f->vocc_flags & PVS_VOCC_STORED))
		return pvs__fail(err, PVS_ERROR_INVALID_ARGUMENT, -1, 0, "the file stores no virtual occluders");
	if (cell >= f->cell_count)
		return pvs__fail(err, PVS_ERROR_INVALID_ARGUMENT, cell, 0, "cell %u of %u", cell, f->cell_count);
	if (object_count != f->object_count)
		return pvs__fail(err, PVS_ERROR_INVALID_ARGUMENT, -1, 0, "%u object boxes for a file of %u objects",
						 object_count, f->object_count);
	n = pvs__vo_file_cell(f, cell, &bytes, &scale);
	if (max_occluders && n > max_occluders) n = max_occluders;
	r = pvs__vo_scratch(scratch, scratch_size, n, tree, &rt, &rest, &rest_size, err);
	if (r != PVS_OK) return r;
	box = pvs_file_cell_box(f, cell);
	for (i = 0; i < n; ++i) {
		double a[2], b[2], lo, hi;
		pvs__vo_decode(&box, f->up_axis, scale, bytes + 5 * (size_t)i, f->vocc_base, f->vocc_height_step, a, b, &lo,
					   &hi);
		pvs__vo_rt_init(rt + i, &box, f->up_axis, a, b, lo, hi);
	}
	return pvs__vo_cull(&box, rt, n, boxes, object_count, tree, rest, rest_size, visible, err);
}

/* ---- 2.5D per cell (§3.1), the selection (Fig. 6), the bake's part ---- */

/* What a bake's cells share: prepared facades, quantization, object boxes. */
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

/* The scene's facades (pvs__scene_facades) and the walls of its EXTRUSION and BOX occluders on the ground, prepared;
   the object boxes. */
PVS__STATIC pvs_result pvs__vbake_create(const pvs_scene *s, const pvs_allocator *a, uint32_t slices, uint32_t max_keep,
										 pvs__vbake **out) {
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

/* The slice heights of a cell (§3.1): quantiles (i + 0.2) / (n + 0.2) of the tops of the occluders above the cell,
   weighted by subtended angle (near walls count more), each an occluder's top (n = 1: the 1/6 quantile). Low slices
   fuse best, high ones hide what stands behind low walls. Ascending, distinct; returns their number (<= n). */
PVS__STATIC uint32_t pvs__vo_slice_heights(const pvs__vbake *vb, const double *centre, float ctop, uint32_t n, float *h,
										   const pvs_allocator *al) {
	const pvs__vprep *p = vb->prep;
	pvs__key_index *key;
	double *w, total = 0.0, acc = 0.0;
	uint32_t i, m = 0, j = 0, out = 0;
	key = (pvs__key_index *)pvs__alloc_array(al, (size_t)p->nobj + 1, sizeof(pvs__key_index));
	w = (double *)pvs__alloc_array(al, (size_t)p->nobj + 1, sizeof(double));
	if (!key || !w) {
		pvs__free_array(al, key, (size_t)p->nobj + 1, sizeof(pvs__key_index));
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
		ang = atan2(loc[2 * lo] * loc[2 * hi + 1] - loc[2 * lo + 1] * loc[2 * hi],
					loc[2 * lo] * loc[2 * hi] + loc[2 * lo + 1] * loc[2 * hi + 1]);
		if (!(ang > 0.0)) continue;
		key[m].key = p->obj_top[i];
		key[m].index = m;
		w[m] = ang;
		total += ang;
		++m;
	}
	pvs__key_index_sort(key, m);
	for (i = 0; i < n && m; ++i) {
		double target = total * ((double)i + 0.2) / ((double)n + 0.2);
		float hh;
		while (j + 1 < m && acc + w[key[j].index] < target) acc += w[key[j++].index];
		hh = (float)key[j].key;
		if (!out || hh > h[out - 1]) h[out++] = hh;
	}
	pvs__free_array(al, key, (size_t)p->nobj + 1, sizeof(pvs__key_index));
	pvs__free_array(al, w, (size_t)p->nobj + 1, sizeof(double));
	return out;
}

/* The dense set of one cell (Koltun 2000 §3, §3.1) in c->out: its slices' virtual occluders, in the file's frame.
   Leaves c untouched when the cell can have none (below the base, no area, no occluder). Returns OUT_OF_MEMORY or
   PVS_OK; the caller frees c. */
PVS__STATIC pvs_result pvs__vo_dense_set(const pvs__vbake *vb, const pvs_box *cell, const double centre[2],
										 double reach, uint32_t code, pvs__vctx *c) {
	const pvs_allocator *al = &vb->a;
	double cmin[2], cmax[2];
	float h[16];
	uint32_t ns, i;
	int u, v, k;
	pvs__ground_axes(vb->up, &u, &v);
	cmin[0] = cell->min[u]; cmin[1] = cell->min[v];
	cmax[0] = cell->max[u]; cmax[1] = cell->max[v];
	if (!(cell->min[vb->up] >= vb->base && cmax[0] > cmin[0] && cmax[1] > cmin[1] && vb->prep->nobj)) return PVS_OK;
	if (!pvs__vctx_init(c, al, vb->prep, cmin, cmax, reach)) return PVS_ERROR_OUT_OF_MEMORY;
	c->centre[0] = centre[0]; /* the file's frame (float centre) */
	c->centre[1] = centre[1];
	for (k = 0; k < 2; ++k) {
		c->cmin[k] = cmin[k] - centre[k];
		c->cmax[k] = cmax[k] - centre[k];
	}
	c->corner[0] = c->cmin[0]; c->corner[1] = c->cmin[1];
	c->corner[2] = c->cmax[0]; c->corner[3] = c->cmin[1];
	c->corner[4] = c->cmax[0]; c->corner[5] = c->cmax[1];
	c->corner[6] = c->cmin[0]; c->corner[7] = c->cmax[1];
	c->quantize = 1;
	c->qscale = pvs__vo_scale(code);
	c->qground = vb->base;
	c->qhstep = vb->hstep;
	c->max_seeds = vb->max_seeds;
	ns = pvs__vo_slice_heights(vb, centre, cell->max[vb->up], vb->slices < 16 ? vb->slices : 16, h, al);
	c->st.slices = ns;
	for (i = 0; i < ns && !c->oom; ++i) {
		if (!pvs__vctx_slice(c, h[i])) break;
		pvs__vo_run_slice(c);
	}
	return c->oom ? PVS_ERROR_OUT_OF_MEMORY : PVS_OK;
}

/* pvs__vo_select's scratch; pvs__vo_bake_cell frees it. */
typedef struct pvs__vo_selwork {
	pvs__vo_rt *rt, *sel;      /* c->nout: the dense set's tests; max_keep + 1: the kept ones */
	pvs_word *hid, *covered;   /* c->nout x words: what each hides; words: hidden so far */
} pvs__vo_selwork;

/* The greedy selection (Koltun 2000, Fig. 6) from c->out: the occluder hiding most objects not yet hidden, until
   max_keep are kept or the best adds under min_gain. Writes their 5 bytes to bytes, tests to sw->sel; returns the
   count. *r = OUT_OF_MEMORY without scratch. */
PVS__STATIC uint32_t pvs__vo_select(const pvs__vbake *vb, const pvs_box *cell, uint32_t code, const pvs__vctx *c,
									uint32_t words, uint8_t *bytes, pvs__vo_selwork *sw, pvs_result *r) {
	const pvs_allocator *al = &vb->a;
	uint32_t min_gain = vb->object_count / 1000u + 1u, keep = 0, i, j;
	sw->rt = (pvs__vo_rt *)pvs__alloc_array(al, c->nout, sizeof(pvs__vo_rt));
	sw->hid = (pvs_word *)pvs__alloc_array(al, (size_t)c->nout * words, sizeof(pvs_word));
	sw->covered = (pvs_word *)pvs__alloc_array(al, words, sizeof(pvs_word));
	sw->sel = (pvs__vo_rt *)pvs__alloc_array(al, (size_t)vb->max_keep + 1, sizeof(pvs__vo_rt));
	if (!sw->rt || !sw->hid || !sw->covered || !sw->sel) { *r = PVS_ERROR_OUT_OF_MEMORY; return 0; }
	memset(sw->hid, 0, (size_t)c->nout * words * sizeof(pvs_word));
	memset(sw->covered, 0, words * sizeof(pvs_word));
	for (i = 0; i < c->nout; ++i) {
		double a[2], b[2], lo, hi;
		for (j = 0; j < i; ++j)
			if (!memcmp(c->out[j].q, c->out[i].q, 5)) break;
		if (j < i) { /* the same bytes twice: hides nothing more */
			memset(sw->rt + i, 0, sizeof(pvs__vo_rt));
			continue;
		}
		pvs__vo_decode(cell, vb->up, code, c->out[i].q, vb->base, vb->hstep, a, b, &lo, &hi);
		pvs__vo_rt_init(sw->rt + i, cell, vb->up, a, b, lo, hi);
	}
	for (j = 0; j < vb->object_count; ++j) {
		if (!pvs__vo_box_ok(vb->boxes + j)) continue;
		for (i = 0; i < c->nout; ++i)
			if (pvs__vo_rt_hides(sw->rt + i, vb->boxes + j))
				sw->hid[(size_t)i * words + (j >> 6)] |= (pvs_word)1 << (j & 63);
	}
	while (keep < vb->max_keep) {
		uint32_t best = PVS__VO_NONE, best_gain = 0;
		for (i = 0; i < c->nout; ++i) {
			uint32_t gain = 0;
			const pvs_word *hw = sw->hid + (size_t)i * words;
			for (j = 0; j < words; ++j) gain += pvs__popcount64(hw[j] & ~sw->covered[j]);
			if (gain > best_gain) { best_gain = gain; best = i; }
		}
		if (best == PVS__VO_NONE || best_gain < min_gain) break;
		for (j = 0; j < words; ++j) sw->covered[j] |= sw->hid[(size_t)best * words + j];
		memcpy(bytes + 5 * (size_t)keep, c->out[best].q, 5);
		sw->sel[keep++] = sw->rt[best];
	}
	return keep;
}

/* One cell of a bake: the dense set, the selection (Fig. 6), the PVS rebuilt as pvs_vocc_cull will (never-drawn objects
   empty). Writes *count (<= max_keep) occluders of 5 bytes, the scale code, the PVS (cleared first). */
PVS__STATIC pvs_result pvs__vo_bake_cell(const pvs__vbake *vb, const pvs_box *cell, uint8_t *bytes, uint8_t *count,
										 uint8_t *scale, pvs_word *pvs, pvs_vocc_stats *stats, pvs_error *err) {
	const pvs_allocator *al = &vb->a;
	pvs__vctx c;
	pvs__vo_selwork sw;
	double centre[2], reach = 0.0;
	uint32_t keep = 0, words = (uint32_t)PVS_BITSET_WORDS(vb->object_count), code;
	int u, v, k;
	pvs_result r;
	*count = 0;
	*scale = 128;
	pvs__ground_axes(vb->up, &u, &v);
	pvs__vo_cell_centre(cell, u, v, centre);
	for (k = 0; k < 4; ++k) { /* analysis radius: every occluder */
		double dx = ((k & 1) ? vb->prep->bb[2] : vb->prep->bb[0]) - centre[0],
			   dy = ((k & 2) ? vb->prep->bb[3] : vb->prep->bb[1]) - centre[1];
		double d = sqrt(dx * dx + dy * dy);
		if (d > reach) reach = d;
	}
	reach = reach * 1.01 + 1.0;
	code = pvs__vo_scale_code(reach);
	*scale = (uint8_t)code;
	memset(&c, 0, sizeof(c));
	memset(&sw, 0, sizeof(sw));
	r = pvs__vo_dense_set(vb, cell, centre, reach, code, &c);
	if (r != PVS_OK) goto done;
	if (c.nout) {
		keep = pvs__vo_select(vb, cell, code, &c, words, bytes, &sw, &r);
		if (r != PVS_OK) goto done;
	}
	*count = (uint8_t)keep;
	pvs__vo_cull(cell, sw.sel, keep, vb->boxes, vb->object_count, NULL, NULL, 0, pvs, NULL);
	c.st.selected = keep;
	if (stats) pvs__vo_stats_add(stats, &c.st);
done:
	if (sw.rt) pvs__free_array(al, sw.rt, c.nout, sizeof(pvs__vo_rt));
	if (sw.hid) pvs__free_array(al, sw.hid, (size_t)c.nout * words, sizeof(pvs_word));
	if (sw.covered) pvs__free_array(al, sw.covered, words, sizeof(pvs_word));
	if (sw.sel) pvs__free_array(al, sw.sel, (size_t)vb->max_keep + 1, sizeof(pvs__vo_rt));
	if (c.al) pvs__vctx_free(&c);
	if (r != PVS_OK) return pvs__fail(err, r, -1, 0, "virtual occluders: out of memory");
	return PVS_OK;
}

/* ---- the 2D entry point ---- */

PVS_API pvs_result pvs_vocc_2d(const pvs_vocc_2d_desc *d, float *occ, uint32_t capacity, uint32_t *count,
							   pvs_vocc_stats *stats, pvs_error *err) {
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
		if (!pvs__finite(d->cell_min[k]) || !pvs__finite(d->cell_max[k]))
			return pvs__fail(err, PVS_ERROR_NOT_FINITE, -1, 0, "the cell is not finite");
		if (!(d->cell_min[k] < d->cell_max[k]))
			return pvs__fail(err, PVS_ERROR_BAD_CELL, -1, 0, "the cell has no area (min >= max on axis %u)", k);
	}
	if (!pvs__finite(d->range) || d->range < 0.0f)
		return pvs__fail(err, PVS_ERROR_INVALID_ARGUMENT, -1, 0, "range must be finite and >= 0");
	for (i = 0; i < 4 * d->segment_count; ++i)
		if (!pvs__finite(d->segments[i]))
			return pvs__fail(err, PVS_ERROR_NOT_FINITE, i / 4, 0, "segment %u is not finite", i / 4);
	al = d->allocator;
	seg = (double *)pvs__alloc_array(&al, 4 * (size_t)d->segment_count + 4, sizeof(double));
	top = (float *)pvs__alloc_array(&al, (size_t)d->segment_count + 1, sizeof(float));
	if (!seg || !top) { r = PVS_ERROR_OUT_OF_MEMORY; goto done; }
	for (i = 0; i < 4 * d->segment_count; ++i) seg[i] = d->segments[i];
	for (i = 0; i < d->segment_count; ++i) top[i] = 1.0f;
	r = pvs__vprep_create(&al, seg, top, d->segment_count, &p);
	if (r != PVS_OK) goto done;
	for (k = 0; k < 2; ++k) { cmin[k] = d->cell_min[k]; cmax[k] = d->cell_max[k]; }
	if (!pvs__vctx_init(&c, &al, p, cmin, cmax, d->range)) {
		pvs__vctx_free(&c);
		r = PVS_ERROR_OUT_OF_MEMORY;
		goto done;
	}
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

/* ---- the VOCC bake method (a row of >>bake's table) ---- */

typedef struct pvs__vocc_bake {
	pvs_allocator allocator;
	pvs__vbake *vb;            /* read-only in tasks */
	uint32_t task_count, keep, only;
	uint8_t *bytes;            /* per task: keep x 5 bytes of occluders, */
	uint8_t *count, *scale;    /* their count and scale code */
	pvs_vocc_stats *stats;     /* per task */
} pvs__vocc_bake;

PVS__STATIC pvs_result pvs__vocc_bake_check(const pvs_bake_desc *desc, pvs_error *err) {
	if (desc->vocc.only && (desc->method != PVS_METHOD_VOCC || desc->vocc.only > 1))
		return pvs__fail(err, PVS_ERROR_INVALID_ARGUMENT, -1, 0, "vocc.only is 0 or 1, and 1 needs PVS_METHOD_VOCC");
	return PVS_OK;
}

/* Facades and loops once (pvs__vbake_create), per-task occluder records. */
PVS__STATIC pvs_result pvs__vocc_bake_prepare(pvs__bake_env *env, const pvs_bake_desc *desc, void **state,
											  pvs_error *err) {
	uint32_t slices = desc->vocc.slices ? desc->vocc.slices : 5,
			 keep = desc->vocc.max_occluders ? desc->vocc.max_occluders : 10;
	pvs__vocc_bake *vo;
	pvs_result r;
	*state = NULL;
	if (slices > 16 || keep > 255)
		return pvs__fail(err, PVS_ERROR_INVALID_ARGUMENT, -1, 0,
						 "vocc: slices %u (1..16), occluders per cell %u (1..255)", slices, keep);
	vo = (pvs__vocc_bake *)pvs__alloc(&env->allocator, sizeof(pvs__vocc_bake), 16);
	*state = vo;
	if (!vo) return pvs__fail(err, PVS_ERROR_OUT_OF_MEMORY, -1, 0, "vocc: facades");
	memset(vo, 0, sizeof(*vo));
	vo->allocator = env->allocator;
	vo->task_count = env->task_count;
	vo->keep = keep;
	r = pvs__vbake_create(env->scene, &env->allocator, slices, keep, &vo->vb);
	if (r != PVS_OK) return pvs__fail(err, r, -1, 0, "vocc: facades");
	if (!vo->vb->prep->nobj && !env->is_auto)
		return pvs__fail(err, PVS_ERROR_UNSUPPORTED, -1, 0,
						 "vocc: the scene has no vertical walls standing on the ground (2.5D occluders): virtual "
						 "occluders cannot be built");
	vo->only = desc->vocc.only;
	vo->bytes = (uint8_t *)pvs__alloc_array(&env->allocator, (size_t)vo->task_count * keep * 5, 1);
	vo->count = (uint8_t *)pvs__alloc_array(&env->allocator, vo->task_count, 1);
	vo->scale = (uint8_t *)pvs__alloc_array(&env->allocator, vo->task_count, 1);
	vo->stats = (pvs_vocc_stats *)pvs__alloc_array(&env->allocator, vo->task_count, sizeof(pvs_vocc_stats));
	if (!vo->bytes || !vo->count || !vo->scale || !vo->stats)
		return pvs__fail(err, PVS_ERROR_OUT_OF_MEMORY, -1, 0, "vocc: per-cell occluders");
	memset(vo->count, 0, vo->task_count);
	memset(vo->scale, 0, vo->task_count);
	memset(vo->stats, 0, vo->task_count * sizeof(pvs_vocc_stats));
	return PVS_OK;
}

PVS__STATIC int pvs__vocc_bake_applies(const void *state, const char **why) {
	const pvs__vocc_bake *vo = (const pvs__vocc_bake *)state;
	int any = vo->vb && vo->vb->prep->nobj;
	*why = any ? "2.5D: virtual occluders behind walls standing on the ground"
			   : "not 2.5D: no vertical wall stands on the ground";
	return any;
}

/* The task's whole cell (VOCC bakes no adaptive cells): its occluders into the task's record, the PVS they prove into
   bits; with vocc.only, every drawable object instead (placeholder records). */
PVS__STATIC pvs_result pvs__vocc_bake_cell(const pvs__bake_env *env, void *state, uint32_t task, uint32_t cell,
										   const pvs_box *box, const pvs_word *candidates, pvs_word *bits,
										   unsigned *flags, pvs_error *err) {
	pvs__vocc_bake *vo = (pvs__vocc_bake *)state;
	const pvs__vbake *vb = vo->vb;
	pvs_result r;
	(void)box;
	(void)candidates;
	(void)flags;
	memset(vo->stats + task, 0, sizeof(pvs_vocc_stats));
	r = pvs__vo_bake_cell(vb, env->task_cells + task, vo->bytes + (size_t)task * vb->max_keep * 5, vo->count + task,
						  vo->scale + task, bits, vo->stats + task, err);
	if (r != PVS_OK) {
		if (err) err->index = cell;
		return r;
	}
	if (vo->only) {
		uint32_t i;
		memset(bits, 0, env->words * sizeof(pvs_word));
		for (i = 0; i < env->object_count; ++i)
			if (pvs__vo_box_ok(vb->boxes + i)) pvs_bitset_set(bits, i);
	}
	return PVS_OK;
}

PVS__STATIC void pvs__vocc_bake_file(const void *state, pvs_file_desc *fd) {
	const pvs__vocc_bake *vo = (const pvs__vocc_bake *)state;
	fd->vocc_counts = vo->count;
	fd->vocc_scales = vo->scale;
	fd->virtual_occluders = vo->bytes;
	fd->vocc_stride = vo->vb->max_keep * 5;
	fd->vocc_base = vo->vb->base;
	fd->vocc_height_step = vo->vb->hstep;
	fd->vocc_flags = vo->only ? PVS_VOCC_ONLY : 0u;
}

PVS__STATIC void pvs__vocc_bake_destroy(const pvs__bake_env *env, void *state) {
	pvs__vocc_bake *vo = (pvs__vocc_bake *)state;
	(void)env;
	if (!vo) return;
	pvs__free_array(&vo->allocator, vo->bytes, (size_t)vo->task_count * vo->keep * 5, 1);
	pvs__free_array(&vo->allocator, vo->count, vo->task_count, 1);
	pvs__free_array(&vo->allocator, vo->scale, vo->task_count, 1);
	pvs__free_array(&vo->allocator, vo->stats, vo->task_count, sizeof(pvs_vocc_stats));
	pvs__vbake_destroy(vo->vb);
	pvs__free(&vo->allocator, vo, sizeof(*vo), 16);
}

/* Not in AUTO unless named (pvs_bake_desc.methods): it is for storage and the run-time rebuild, not tightness. */
PVS__STATIC const pvs__bake_method pvs__vocc_method = {PVS_METHOD_VOCC,
													   PVS__METHOD_CONSERVATIVE | PVS__METHOD_WHOLE_CELLS,
													   2,
													   pvs__vocc_bake_check,
													   pvs__vocc_bake_prepare,
													   pvs__vocc_bake_applies,
													   pvs__vocc_bake_cell,
													   pvs__vocc_bake_file,
													   pvs__vocc_bake_destroy};

PVS_API void pvs_bake_get_vocc_stats(const pvs_bake *b, pvs_vocc_stats *out) {
	const pvs__vocc_bake *vo = b ? (const pvs__vocc_bake *)pvs__bake_method_state(b, PVS_METHOD_VOCC) : NULL;
	uint32_t i;
	memset(out, 0, sizeof(*out));
	for (i = 0; vo && vo->stats && i < vo->task_count; ++i) pvs__vo_stats_add(out, vo->stats + i);
}

// >>methods
/* ---------------------------------------------------------------------------------------------- */
/* methods: region visibility: ray sampling, extended projections, shrink (bake methods)          */
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

/* Sample point i of `points`: the cell's 8 corners, 6 face centres, then one jittered point per stratum of a g^k grid
   on its k non-flat axes. */
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

PVS_API uint64_t pvs_sample_visibility(const pvs_scene *scene, const pvs_box *cell, uint32_t points,
									   uint32_t rays_per_point, uint64_t seed, pvs_word *visible) {
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

/* ---- the SAMPLE bake method (a row of >>bake's table): an estimate from below, never intersected ---- */

typedef struct pvs__sample_bake {
	pvs_allocator allocator;
	uint32_t points, rays;
	uint64_t seed;
} pvs__sample_bake;

PVS__STATIC pvs_result pvs__sample_bake_prepare(pvs__bake_env *env, const pvs_bake_desc *desc, void **state,
												pvs_error *err) {
	pvs__sample_bake *sb = (pvs__sample_bake *)pvs__alloc(&env->allocator, sizeof(pvs__sample_bake), 16);
	*state = sb;
	if (!sb) return pvs__fail(err, PVS_ERROR_OUT_OF_MEMORY, -1, 0, "sample");
	sb->allocator = env->allocator;
	sb->points = desc->sample.points ? desc->sample.points : 32;
	sb->rays = desc->sample.rays ? desc->sample.rays : 2048;
	sb->seed = desc->sample.seed;
	return PVS_OK;
}

PVS__STATIC pvs_result pvs__sample_bake_cell(const pvs__bake_env *env, void *state, uint32_t task, uint32_t cell,
											 const pvs_box *box, const pvs_word *candidates, pvs_word *bits,
											 unsigned *flags, pvs_error *err) {
	const pvs__sample_bake *sb = (const pvs__sample_bake *)state;
	uint64_t seed = sb->seed ^ ((uint64_t)cell * 0x9e3779b97f4a7c15ull); /* per cell: independent of the run order */
	(void)task;
	(void)candidates;
	(void)flags;
	(void)err;
	pvs_sample_visibility(env->scene, box, sb->points, sb->rays, pvs__splitmix64(&seed), bits);
	return PVS_OK;
}

PVS__STATIC void pvs__sample_bake_destroy(const pvs__bake_env *env, void *state) {
	(void)env;
	if (state) pvs__free(&((pvs__sample_bake *)state)->allocator, state, sizeof(pvs__sample_bake), 16);
}

PVS__STATIC const pvs__bake_method pvs__sample_method = {
	PVS_METHOD_SAMPLE, PVS__METHOD_APPROXIMATE, 4, NULL, pvs__sample_bake_prepare, NULL, pvs__sample_bake_cell, NULL,
	pvs__sample_bake_destroy};

/* ---- extended projections (Durand et al. 2000) ---- */

/* Rounding: all in double from float inputs. A plane's frame maps a point to (u, v, w), w its Depth beyond the cell's
   face (§2.3; the cell spans w in [-extent, 0]). P's view from cell corner V on the plane w = W is V + (P - V)
   (W - Vw) / (Pw - Vw), for Pw > Vw: occluders are clipped to w >= a small margin, occludees lie wholly at w > 0. A
   convex occluder's Projection is the intersection of its views from the 8 corners (§3.2), a pixel kept when its worst
   corner passes every edge by a margin above all rounding; Depth: its greatest w, rounded up (§2.3). An occludee box's
   Projection is its views' bounding rectangle (§3.1), widened likewise; Depth: its least w, rounded down. It is hidden
   when every pixel there holds an occluder strictly nearer (§2.2; pixels off the plane are visible).

   The bake method (§6.1): occluders prepared once per bake; per cell and direction those of largest solid angle drawn
   on PVS__EP_PLANES depth maps and, with the sweep, extproj.sweep masks out to the scene's far end (§5); then the
   object kD-tree front to back, hidden nodes skipped. Objects meeting the cell are always visible.

   Limits: occluders fuse only through maps and slices; Depths are flat per part; a plane's umbra shrinks by the cell's
   size over the distance, so sparse small occluders (foliage) stay loose; sub-cells (extproj.sweep_subcells) win back
   part (tests/BENCHMARKS.md). */

#define PVS__EP_MAXP 16                               /* vertices of one convex occluder */
#define PVS__EP_CLIPN (PVS__EP_MAXP * PVS__EP_MAXP)
#define PVS__EP_EXTEND 1.5                            /* planes extended beyond the cell (§6.1) */
#define PVS__EP_DEFAULT_RES PVS_EXTPROJ_RESOLUTION
#define PVS__EP_DEFAULT_OCC 128
#define PVS__EP_PLANE_CANDIDATES 16
#define PVS__EP_PLANES 4                              /* planes per direction (§6.1) */
#define PVS__EP_PLANE_RATIO 1.7                       /* their distance bands */
#define PVS__EP_SAT_CACHE ((size_t)64 << 20)          /* bytes of the sweep's summed-area tables */
#define PVS__EP_MAX_SIDE 16384u                       /* longest side of a sweep mask, in pixels */

typedef struct pvs__epframe {
	int a, u, v;
	double s, face, W, u0, v0, su, sv;
	double cu[2], cv[2], cw[2];
	uint32_t width, height;
	unsigned char bits; /* the bits a Projection sets in a sweep mask: 1, or a sub-cell's */
} pvs__epframe;

/* The frame of a plane of sides <= max_side pixels (4096 for the public functions); 0 if the plane is bad. */
PVS__STATIC int pvs__ep_frame_max(const pvs_extproj_plane *pl, uint32_t max_side, pvs__epframe *f) {
	int k;
	if (!pl || pl->axis > 2 || (pl->side != 1 && pl->side != -1) || !pvs__box_valid(&pl->cell)) return 0;
	if (!pvs__finite(pl->distance) || !(pl->distance > 0.0f)) return 0;
	for (k = 0; k < 4; ++k)
		if (!pvs__finite(pl->rect[k])) return 0;
	if (!(pl->rect[2] > pl->rect[0]) || !(pl->rect[3] > pl->rect[1])) return 0;
	if (pl->width < 1 || pl->width > max_side || pl->height < 1 || pl->height > max_side) return 0;
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
	f->bits = 1;
	return 1;
}

PVS__STATIC int pvs__ep_frame(const pvs_extproj_plane *pl, pvs__epframe *f) { return pvs__ep_frame_max(pl, 4096u, f); }

PVS__STATIC double pvs__ep_tri_normal(const float *a, const float *b, const float *c, double n[3]) {
	double e1[3], e2[3];
	int k;
	for (k = 0; k < 3; ++k) { e1[k] = (double)b[k] - a[k]; e2[k] = (double)c[k] - a[k]; }
	n[0] = e1[1] * e2[2] - e1[2] * e2[1];
	n[1] = e1[2] * e2[0] - e1[0] * e2[2];
	n[2] = e1[0] * e2[1] - e1[1] * e2[0];
	return sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
}

PVS__STATIC double pvs__ep_orient(const double *a, const double *b, const double *c) {
	return (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
}

PVS__STATIC int pvs__ep_pt2_cmp(const void *x, const void *y) {
	const double *a = (const double *)x, *b = (const double *)y;
	if (a[0] != b[0]) return a[0] < b[0] ? -1 : 1;
	return a[1] < b[1] ? -1 : a[1] > b[1];
}
/* Convex hull (Andrew's monotone chain), counter-clockwise, collinear points dropped; sorts pts (n x 2), hull holds
   n + 1 points. Returns its size. */
PVS__STATIC int pvs__ep_hull(double (*pts)[2], int n, double (*hull)[2]) {
	int i, k = 0, lower;
	if (n > 1) PVS_QSORT(pts, (size_t)n, sizeof(pts[0]), pvs__ep_pt2_cmp); /* equal points are equal values */
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

/* ceil and floor by conversion, for |x| < 2^31 (callers clamp to the raster first). */
PVS__STATIC double pvs__ceil_small(double x) {
	double t = (double)(int32_t)x;
	return t < x ? t + 1.0 : t;
}
PVS__STATIC double pvs__floor_small(double x) {
	double t = (double)(int32_t)x;
	return t > x ? t - 1.0 : t;
}

PVS__STATIC void pvs__ep_mask_set(unsigned char *mask, unsigned char bits, size_t n) {
	size_t i;
	for (i = 0; i < n; ++i) mask[i] = (unsigned char)(mask[i] | bits);
}

/* A Projection's edges in pixels: a x + b y + c >= 0 inside, |a| + |b| = 1, error bound e, inv = 1 / a (0 if nearly
   horizontal); [xlo, xhi] x [ylo, yhi]: the views' common box. */
typedef struct pvs__epedges {
	double a[8 * PVS__EP_CLIPN], b[8 * PVS__EP_CLIPN], c[8 * PVS__EP_CLIPN], e[8 * PVS__EP_CLIPN],
		inv[8 * PVS__EP_CLIPN];
	int n;
	double xlo, xhi, ylo, yhi;
} pvs__epedges;

/* Into P, the vertices of a convex occluder's part in the slab [wlo, whi]: points inside, and slab crossings of
   segments between any two. Returns their count. */
PVS__STATIC int pvs__ep_clip_slab(const double (*src)[3], int count, double wlo, double whi, double (*P)[3]) {
	int n = 0, i, j;
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
	return n;
}

/* The Projection of convex point set P (shape error `slack`): the intersection of its views from the 8 corners (§3.2),
   edges with error bounds into E. 0 if it surely covers no whole pixel. */
PVS__STATIC int pvs__ep_views(const pvs__epframe *fp, const double (*P)[3], int n, double slack, pvs__epedges *E) {
	pvs__epframe f = *fp;
	double pts[PVS__EP_CLIPN][2], hull[PVS__EP_CLIPN + 1][2], base = pvs__dabs(f.u0) * f.su + pvs__dabs(f.v0) * f.sv;
	int i, c;
	E->n = 0;
	E->xlo = -DBL_MAX; E->xhi = DBL_MAX; E->ylo = -DBL_MAX; E->yhi = DBL_MAX;
	for (c = 0; c < 8; ++c) {
		double Vu = f.cu[c & 1], Vv = f.cv[(c >> 1) & 1], Vw = f.cw[(c >> 2) & 1], h;
		double bx0 = DBL_MAX, bx1 = -DBL_MAX, by0 = DBL_MAX, by1 = -DBL_MAX, area2 = 0.0, mag = 0.0, verr, smax = 0.0;
		int k;
		for (i = 0; i < n; ++i) {
			double t = (f.W - Vw) / (P[i][2] - Vw), du, dv;
			du = (P[i][0] - Vu) * t;
			dv = (P[i][1] - Vv) * t;
			pts[i][0] = (Vu + du - f.u0) * f.su;
			pts[i][1] = (Vv + dv - f.v0) * f.sv;
			bx0 = pvs__dmin(bx0, pts[i][0]); bx1 = pvs__dmax(bx1, pts[i][0]);
			by0 = pvs__dmin(by0, pts[i][1]); by1 = pvs__dmax(by1, pts[i][1]);
			mag = pvs__dmax(mag,
							pvs__dabs(pts[i][0]) + pvs__dabs(pts[i][1]) +
								(pvs__dabs(Vu) + pvs__dabs(P[i][0])) * t * f.su +
								(pvs__dabs(Vv) + pvs__dabs(P[i][1])) * t * f.sv);
			/* a point moved by slack moves its view by at most slack (t + |view - V| / (Pw - Vw)) per axis */
			smax = pvs__dmax(smax, t + (pvs__dabs(du) + pvs__dabs(dv)) / (P[i][2] - Vw));
		}
		/* each projected vertex's error in pixels: a few ulps of the terms, widely, plus the slack */
		verr = 1e-12 * (mag + base + 1.0) + slack * smax * pvs__dmax(f.su, f.sv);
		if (!(bx1 - bx0 < 1e15) || !(by1 - by0 < 1e15)) return 0; /* beyond any useful precision */
		E->xlo = pvs__dmax(E->xlo, bx0); E->xhi = pvs__dmin(E->xhi, bx1);
		E->ylo = pvs__dmax(E->ylo, by0); E->yhi = pvs__dmin(E->yhi, by1);
		if (E->xhi - E->xlo < 1.0 || E->yhi - E->ylo < 1.0) return 0; /* no whole pixel fits */
		k = pvs__ep_hull(pts, n, hull);
		if (k < 3) return 0;
		for (i = 0; i < k; ++i)
			area2 += hull[i][0] * hull[i + 1 < k ? i + 1 : 0][1] - hull[i + 1 < k ? i + 1 : 0][0] * hull[i][1];
		h = (bx1 - bx0) + (by1 - by0);
		if (!(area2 > 1e-9 * h * h)) return 0; /* a sliver: covers no pixel */
		for (i = 0; i < k; ++i) {
			const double *p = hull[i], *q = hull[i + 1 < k ? i + 1 : 0];
			double a = -(q[1] - p[1]), b = q[0] - p[0], len = pvs__dabs(a) + pvs__dabs(b);
			int m = E->n;
			if (!(len > 0.0)) continue;
			E->a[m] = a / len;
			E->b[m] = b / len;
			E->c[m] = -(E->a[m] * p[0] + E->b[m] * p[1]);
			/* ends moved by verr move (a, b) by 2 verr each, the L1 norm by 4 verr: at L1 distance D from p the
			   normalized function moves by at most verr (1 + 6 D / len) */
			E->e[m] = verr *
				(2.0 + 8.0 * (pvs__dabs(p[0]) + pvs__dabs(p[1]) + (double)f.width + (double)f.height + 2.0) / len);
			++E->n;
		}
	}
	return 1;
}

/* Drops edges every candidate pixel passes by more than the row loop's margins (most of the eight views' edges); kept
   ones get that margin, less its row part, and 1 / a. */
PVS__STATIC void pvs__ep_edges_prune(pvs__epedges *E, int32_t i0, int32_t i1, int32_t j0, int32_t j1) {
	int e, m = 0;
	double x0 = i0, x1 = (double)i1 + 1.0, y0 = j0, y1 = (double)j1 + 1.0;
	for (e = 0; e < E->n; ++e) {
		double a = E->a[e], b = E->b[e], cc = E->c[e];
		double least = cc + pvs__dmin(a * x0, a * x1) + pvs__dmin(b * y0, b * y1);
		double errmax = 1e-6 + E->e[e] + 1e-12 * (pvs__dabs(cc) + pvs__dabs(b) * y1);
		double room = 1e-6 + 1e-8 * (pvs__dabs(cc) + pvs__dabs(b) * y1 + pvs__dabs(a) * x1);
		if (least - errmax > room) continue;
		E->a[m] = a;
		E->b[m] = b;
		E->c[m] = cc;
		E->e[m] = 1e-6 + E->e[e] + 1e-12 * pvs__dabs(cc);
		/* a product by 1 / a is within two ulps of the quotient, far inside the 1e-9 |x| margin */
		E->inv[m] = pvs__dabs(a) > 1e-12 ? 1.0 / a : 0.0;
		++m;
	}
	E->n = m;
}

/* Scan-converts Projection E over rows j0..j1, columns i0..i1: pixels whose worst corner passes every edge by its
   margin get `depth` (where nearer) in map and f->bits in mask (either may be NULL). Returns the pixels covered. Not
   pvs__raster_poly: flat-Depth spans are about 3x faster, and these edges carry their own error bounds. */
PVS__STATIC uint32_t pvs__ep_fill_rows(const pvs__epframe *f, const pvs__epedges *E, int32_t i0, int32_t i1, int32_t j0,
									   int32_t j1, float depth, float *map, unsigned char *mask) {
	int32_t row;
	uint32_t written = 0;
	for (row = j0; row <= j1; ++row) {
		double lo = i0, hi = i1, y = row;
		int e;
		for (e = 0; e < E->n && lo <= hi; ++e) {
			double a = E->a[e], b = E->b[e];
			/* the pixel's worst corner: a (i + [a < 0]) + b (y + [b < 0]) + c >= err */
			double r = E->c[e] + b * y + (b < 0.0 ? b : 0.0) + (a < 0.0 ? a : 0.0);
			r -= E->e[e] + 1e-12 * pvs__dabs(b * y);
			if (a > 1e-12) {
				double x = -r * E->inv[e];
				x += 1e-9 * (1.0 + pvs__dabs(x));
				if (x > lo) lo = x > hi ? hi + 1.0 : pvs__ceil_small(x);
			} else if (a < -1e-12) {
				double x = -r * E->inv[e];
				x -= 1e-9 * (1.0 + pvs__dabs(x));
				if (x < hi) hi = x < lo ? lo - 1.0 : pvs__floor_small(x);
			} else {
				/* nearly horizontal: test the worst of the row's two ends */
				double worst = r + pvs__dmin(a * lo, a * hi) - pvs__dabs(a);
				if (worst < 0.0) hi = lo - 1.0;
			}
		}
		if (lo > hi) continue;
		{
			int32_t x0 = (int32_t)lo, x1 = (int32_t)hi, x;
			if (map) {
				float *px = map + (size_t)row * f->width;
				for (x = x0; x <= x1; ++x)
					if (px[x] > depth) px[x] = depth;
			}
			if (mask) pvs__ep_mask_set(mask + (size_t)row * f->width + x0, f->bits, (size_t)(x1 - x0 + 1));
			written += (uint32_t)(x1 - x0 + 1);
		}
	}
	return written;
}

/* The Projection of the occluder's part in the slab [wlo, whi]. */
PVS__STATIC uint32_t pvs__ep_occluder_part(const pvs__epframe *fp, const double (*src)[3], int count, double wlo,
										   double whi, double slack, float *map, unsigned char *mask) {
	double P[PVS__EP_CLIPN][3], dmax = 0.0;
	pvs__epedges E;
	int n, i;
	int32_t i0, i1, j0, j1;
	n = pvs__ep_clip_slab(src, count, wlo, whi, P);
	if (n < 3) return 0;
	for (i = 0; i < n; ++i) dmax = pvs__dmax(dmax, P[i][2]);
	if (!pvs__ep_views(fp, (const double (*)[3])P, n, slack, &E)) return 0;
	i0 = pvs__clampi(ceil(E.xlo), 0, (int32_t)fp->width);
	i1 = pvs__clampi(floor(E.xhi) - 1.0, -1, (int32_t)fp->width - 1);
	j0 = pvs__clampi(ceil(E.ylo), 0, (int32_t)fp->height);
	j1 = pvs__clampi(floor(E.yhi) - 1.0, -1, (int32_t)fp->height - 1);
	if (i0 > i1 || j0 > j1) return 0;
	pvs__ep_edges_prune(&E, i0, i1, j0, j1);
	return pvs__ep_fill_rows(fp, &E, i0, i1, j0, j1, pvs__f_up(dmax + 1e-12 * dmax), map, mask);
}

/* 0 when the occluder's part in the slab [wlo, whi] surely covers no pixel: its bounding box's Projection (which holds
   the part's) holds no whole pixel. 1: maybe. */
PVS__STATIC int pvs__ep_box_may_cover(const pvs__epframe *f, const double (*P)[3], int count, double wlo, double whi) {
	double lo[3] = {DBL_MAX, DBL_MAX, DBL_MAX}, hi[3] = {-DBL_MAX, -DBL_MAX, -DBL_MAX};
	int i, k;
	for (i = 0; i < count; ++i)
		for (k = 0; k < 3; ++k) {
			lo[k] = pvs__dmin(lo[k], P[i][k]);
			hi[k] = pvs__dmax(hi[k], P[i][k]);
		}
	lo[2] = pvs__dmax(lo[2], wlo);
	hi[2] = pvs__dmin(hi[2], whi);
	if (!(hi[2] >= lo[2])) return 0;
	for (k = 0; k < 2; ++k) {
		const double *ck = k ? f->cv : f->cu;
		double k0 = k ? f->v0 : f->u0, sk = k ? f->sv : f->su, a = -DBL_MAX, b = DBL_MAX,
			   size = k ? (double)f->height : (double)f->width;
		int c, e;
		for (c = 0; c < 4; ++c) {
			double Vk = ck[c & 1], Vw = f->cw[c >> 1], mn = DBL_MAX, mx = -DBL_MAX;
			for (e = 0; e < 4; ++e) {
				double x = Vk + ((e & 1 ? hi[k] : lo[k]) - Vk) * (f->W - Vw) / ((e & 2 ? hi[2] : lo[2]) - Vw);
				mn = pvs__dmin(mn, x);
				mx = pvs__dmax(mx, x);
			}
			a = pvs__dmax(a, mn);
			b = pvs__dmin(b, mx);
		}
		a = (a - k0) * sk;
		b = (b - k0) * sk;
		/* a margin far above the rounding of these few operations */
		if (b - a < 1.0 - 1e-6 * (1.0 + pvs__dabs(a) + pvs__dabs(b)) || b < -1e-6 * (1.0 + pvs__dabs(b)) ||
			a > size + 1e-6 * (1.0 + pvs__dabs(a)))
			return 0;
	}
	return 1;
}

/* pvs_extproj_occluder with a prepared frame and finite points; solid, slack as in pvs__epocc. Depths to map (min),
   f->bits to mask, either may be NULL; front_only: only the part before the plane. */
PVS__STATIC uint32_t pvs__ep_occluder(const pvs__epframe *fp, const pvs_box *cell, const float *points, uint32_t count,
									  int solid, double slack, int front_only, float *map, unsigned char *mask) {
	pvs__epframe f = *fp;
	double P[PVS__EP_MAXP][3], margin, wmax = -DBL_MAX;
	uint32_t i, written;
	for (i = 0; i < count; ++i) {
		P[i][0] = points[3 * i + f.u];
		P[i][1] = points[3 * i + f.v];
		P[i][2] = f.s * ((double)points[3 * i + f.a] - f.face);
		wmax = pvs__dmax(wmax, P[i][2]);
	}
	if (solid) {
		/* a solid meeting the cell could hold the viewer, its Depth bounding no first hit: left out */
		pvs_box b = pvs__box_empty();
		for (i = 0; i < count; ++i) pvs__box_add_point(&b, points + 3 * i);
		if (pvs__box_overlap(&b, cell)) return 0;
	}
	/* clipped to w >= a small margin and split at the plane: the cell points seeing a pixel through the part on one
	   side form a convex set, so the corners decide; across the plane not */
	margin = 1e-4 * (f.W - f.cw[0]);
	written = 0;
	if (pvs__ep_box_may_cover(&f, (const double(*)[3])P, (int)count, margin, f.W))
		written = pvs__ep_occluder_part(&f, (const double(*)[3])P, (int)count, margin, f.W, slack, map, mask);
	if (wmax > f.W && !front_only && pvs__ep_box_may_cover(&f, (const double(*)[3])P, (int)count, f.W, DBL_MAX))
		written += pvs__ep_occluder_part(&f, (const double(*)[3])P, (int)count, f.W, DBL_MAX, slack, map, mask);
	return written;
}

PVS_API uint32_t pvs_extproj_occluder(const pvs_extproj_plane *pl, const float *points, uint32_t count, float *map) {
	pvs__epframe f;
	uint32_t i;
	int solid = 0;
	if (!pvs__ep_frame(pl, &f) || !points || !map || count < 1 || count > PVS__EP_MAXP) return 0;
	for (i = 0; i < count * 3; ++i)
		if (!pvs__finite(points[i])) return 0;
	if (count > 3) { /* planar (a polygon) or not (a solid)? */
		double n[3], len = 0.0, scale = 0.0;
		pvs_box b = pvs__box_empty();
		for (i = 0; i < count; ++i) pvs__box_add_point(&b, points + 3 * i);
		for (i = 2; i < count && !(len > 0.0); ++i) len = pvs__ep_tri_normal(points, points + 3, points + 3 * i, n);
		for (i = 0; i < 3; ++i) scale = pvs__dmax(scale, (double)b.max[i] - b.min[i]);
		if (!(len > 0.0)) return 0;
		for (i = 0; i < count && !solid; ++i) {
			double d = n[0] * ((double)points[3 * i] - points[0]) + n[1] * ((double)points[3 * i + 1] - points[1]) +
					   n[2] * ((double)points[3 * i + 2] - points[2]);
			solid = pvs__dabs(d) > 1e-7 * len * scale;
		}
	}
	return pvs__ep_occluder(&f, &pl->cell, points, count, solid, 0.0, 0, map, NULL);
}

/* Pixel bounds of the box's (k, w) views from the cell's (k, w) corners; t[c][b] = (W - cw[c]) / (bw[b] - cw[c]). */
PVS__STATIC void pvs__ep_occludee_axis(const double *cell_k, double bk0, double bk1, const double t[2][2], double k0,
									   double sk, uint32_t size, int32_t *lo, int32_t *hi) {
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
	pvs__ep_occludee_axis(f->cu, box->min[f->u], box->max[f->u], (const double(*)[2])t, f->u0, f->su, f->width,
						  &rect[0], &rect[2]);
	pvs__ep_occludee_axis(f->cv, box->min[f->v], box->max[f->v], (const double(*)[2])t, f->v0, f->sv, f->height,
						  &rect[1], &rect[3]);
	*depth = pvs__f_down(bw[0] - 1e-12 * bw[0]);
	return 1;
}

/* Durand 2000 §4's improved occludee Projection on axis k, for a box between cell and plane (depths w0..w1 <= W).
   Cones go to the cell's near face (w = 0): inside cone(P, cell), so Property 2 holds, and the 3D Projection is exactly
   the product of the 2D ones. With [L(X), R(X)] X's views from the face, I = [a, b] works iff a <= min R and b >= max L
   (over the box's corners): if max L <= min R one point serves (*any = 1: one column must be hidden), else
   [min R, max L] (*any = 0: all). Indices may leave the map. */
PVS__STATIC void pvs__ep_improved_axis(const double *cell_k, double bk0, double bk1, double w0, double w1, double W,
									   double k0, double sk, uint32_t size, int32_t *lo, int32_t *hi, int *any) {
	double maxL = -DBL_MAX, minR = DBL_MAX, mag = 0.0, err, a, b;
	int x, y;
	for (x = 0; x < 2; ++x)
		for (y = 0; y < 2; ++y) {
			double Xk = x ? bk1 : bk0, t = W / (y ? w1 : w0);
			double v0 = (cell_k[0] + (Xk - cell_k[0]) * t - k0) * sk, v1 = (cell_k[1] + (Xk - cell_k[1]) * t - k0) * sk;
			maxL = pvs__dmax(maxL, pvs__dmin(v0, v1));
			minR = pvs__dmin(minR, pvs__dmax(v0, v1));
			mag = pvs__dmax(mag,
							(pvs__dabs(cell_k[0]) + pvs__dabs(cell_k[1]) +
							 (pvs__dabs(Xk) + pvs__dabs(cell_k[0]) + pvs__dabs(cell_k[1])) * t + pvs__dabs(k0)) *
								sk);
		}
	err = 1e-6 + 1e-12 * mag;
	a = maxL + err;
	b = minR - err;
	if (a <= b) { /* any point of [a, b] */
		*any = 1;
		*lo = pvs__clampi(floor(a), -1, (int32_t)size);
		*hi = pvs__clampi(floor(b), -1, (int32_t)size);
	} else { /* the whole of [min R, max L], widened */
		*any = 0;
		*lo = pvs__clampi(floor(minR - err), -1, (int32_t)size);
		*hi = pvs__clampi(floor(maxL + err), -1, (int32_t)size);
	}
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

/* ---- the bake method: occluders per bake, planes per cell ---- */

/* A convex occluder: a planar convex polygon (a triangle or merged triangles) or a closed convex solid. */
typedef struct pvs__epocc {
	pvs_box box;
	uint32_t first, count;   /* points */
	int solid;
	uint32_t xfirst, xcount; /* extended through a sheet (pvs__epsheet), xcount = 0 if none */
	uint32_t sheet;
	int xside;               /* the sheet's side it stands on */
	int cap_side, cap_axis;  /* a capped convex solid (cap_side != 0): used only for cells where */
	float cap_value;         /*   cap_side * (x[cap_axis] - cap_value) > 0 */
	float slack;             /* how far the true shape may lie inside the hull of the points */
	uint32_t object;         /* its object, or PVS_NO_OBJECT */
	float area;              /* area bound: solid angle <= area / distance^2 */
	uint32_t efirst, ecount; /* concave planar (ecount > 0): edges prep->cedge[6 * efirst ...]; points: its vertices'
								hull, for selection */
	float pn[3], pd;         /*   its plane pn . x = pd (pn a unit normal) */
} pvs__epocc;

/* A sheet: coplanar triangles (any objects') in the plane x[axis] = value forming one convex polygon without holes (a
   tiled floor). For a cell strictly on one side and over it, the space beyond, over the polygon, is solid: a segment
   there crosses the polygon. */
#define PVS__EP_MAX_SHEETS 16
#define PVS__EP_AREA_CLASSES 8
typedef struct pvs__epsheet {
	int axis;
	float value;
	uint32_t first, count;   /* convex polygon prep->spoly[2 * first ...] on axes (axis + 1, axis + 2) */
	double area;
} pvs__epsheet;

/* A closed non-convex component sliced by the planes (§3.3): one object's connected triangles, each edge used an even
   number of times, or "capped": the odd edges in one plane, every vertex on one side (a building with no floor). */
typedef struct pvs__epslice {
	pvs_box box;
	uint32_t first, count;   /* scene triangles prep->stri[first .. first + count) */
	uint32_t bfirst, bcount; /* capped: boundary edges prep->bedge[6 * bfirst ...], two points each */
	int capped;              /* capped: the solid lies where cap_side * (x[cap_axis] - cap_value) >= 0 */
	int cap_axis, cap_side;
	float cap_value;
} pvs__epslice;

typedef struct pvs__extproj_prep {
	pvs_allocator allocator;
	pvs__epocc *occ;
	size_t occ_count, occ_capacity;
	float *pts;              /* 3 floats per point */
	size_t pt_count, pt_capacity;
	pvs__epslice *slc;
	size_t slc_count, slc_capacity;
	uint32_t *stri;
	size_t stri_count, stri_capacity;
	float *bedge;            /* 6 floats per boundary edge */
	size_t bedge_count, bedge_capacity;
	uint32_t max_slice_segments; /* the most triangles plus boundary edges of one sliced component */
	pvs__epsheet sheet[PVS__EP_MAX_SHEETS];
	uint32_t sheet_count;
	/* per size class (area bound < 4^c): a kD-tree of the boxes, a node pruned by the largest area */
	pvs_kdtree *occ_tree[PVS__EP_AREA_CLASSES];
	uint32_t *class_occ[PVS__EP_AREA_CLASSES]; /* tree item -> occluder */
	uint32_t class_count[PVS__EP_AREA_CLASSES];
	float class_area[PVS__EP_AREA_CLASSES];
	float *spoly;            /* sheet polygons: 2 floats per vertex */
	size_t spoly_count, spoly_capacity;
	float *cedge;            /* concave occluders' boundary edges: 6 floats each */
	size_t cedge_count, cedge_capacity;
} pvs__extproj_prep;

PVS__STATIC void pvs__extproj_prep_destroy(pvs__extproj_prep *p) {
	pvs_allocator a;
	if (!p) return;
	a = p->allocator;
	pvs__free_array(&a, p->occ, p->occ_capacity, sizeof(pvs__epocc));
	pvs__free_array(&a, p->pts, p->pt_capacity * 3, sizeof(float));
	pvs__free_array(&a, p->slc, p->slc_capacity, sizeof(pvs__epslice));
	pvs__free_array(&a, p->stri, p->stri_capacity, sizeof(uint32_t));
	pvs__free_array(&a, p->bedge, p->bedge_capacity * 6, sizeof(float));
	pvs__free_array(&a, p->spoly, p->spoly_capacity * 2, sizeof(float));
	pvs__free_array(&a, p->cedge, p->cedge_capacity * 6, sizeof(float));
	{
		int c;
		for (c = 0; c < PVS__EP_AREA_CLASSES; ++c) {
			pvs_kdtree_destroy(p->occ_tree[c]);
			pvs__free_array(&a, p->class_occ[c], (size_t)p->class_count[c] + 1, sizeof(uint32_t));
		}
	}
	pvs__free(&a, p, sizeof(*p), 16);
}

/* Adds a convex occluder (room is reserved by the caller). */
PVS__STATIC void pvs__ep_add(pvs__extproj_prep *p, const float *const *pts, uint32_t n, int solid, double slack) {
	pvs__epocc *o = p->occ + p->occ_count++;
	uint32_t i;
	o->box = pvs__box_empty();
	o->first = (uint32_t)p->pt_count;
	o->count = n;
	o->solid = solid;
	o->xfirst = o->xcount = 0;
	o->sheet = 0;
	o->xside = o->cap_side = o->cap_axis = 0;
	o->cap_value = 0.0f;
	o->slack = pvs__f_up(slack);
	o->object = PVS_NO_OBJECT;
	o->efirst = o->ecount = 0;
	o->pn[0] = o->pn[1] = o->pn[2] = o->pd = 0.0f;
	for (i = 0; i < n; ++i) {
		memcpy(p->pts + 3 * p->pt_count, pts[i], 3 * sizeof(float));
		pvs__box_add_point(&o->box, pts[i]);
		++p->pt_count;
	}
	{
		/* area bound: a polygon's area; a solid's, its box's three faces */
		double ex = (double)o->box.max[0] - o->box.min[0], ey = (double)o->box.max[1] - o->box.min[1],
			   ez = (double)o->box.max[2] - o->box.min[2];
		double f = ex * ey + ey * ez + ez * ex;
		if (!solid) {
			double a3[3] = {0.0, 0.0, 0.0};
			int k;
			for (i = 1; i + 1 < n; ++i) {
				double e1[3], e2[3];
				for (k = 0; k < 3; ++k) {
					e1[k] = (double)pts[i][k] - pts[0][k];
					e2[k] = (double)pts[i + 1][k] - pts[0][k];
				}
				a3[0] += e1[1] * e2[2] - e1[2] * e2[1];
				a3[1] += e1[2] * e2[0] - e1[0] * e2[2];
				a3[2] += e1[0] * e2[1] - e1[1] * e2[0];
			}
			f = 0.5 * sqrt(a3[0] * a3[0] + a3[1] * a3[1] + a3[2] * a3[2]) * 1.000001 + 1e-30;
		}
		o->area = pvs__f_up(f);
	}
}

PVS__STATIC int pvs__ep_same(const float *a, const float *b) { return a[0] == b[0] && a[1] == b[1] && a[2] == b[2]; }

/* Two edge-sharing triangles, coplanar to float precision, forming a convex quad: fills q[4] and *slack (from the
   fourth point's distance to the first's plane); returns 1. */
PVS__STATIC int pvs__ep_quad(const float *const *A, const float *const *B, const float **q, double *slack) {
	int i, j, k;
	double n[3], len = pvs__ep_tri_normal(A[0], A[1], A[2], n), scale = 0.0;
	if (!(len > 0.0)) return 0;
	for (i = 0; i < 3; ++i)
		for (j = 0; j < 3; ++j) {
			const float *a0 = A[i], *a1 = A[(i + 1) % 3], *x;
			double dev;
			if (!(pvs__ep_same(a0, B[j]) && pvs__ep_same(a1, B[(j + 2) % 3])) &&
				!(pvs__ep_same(a0, B[(j + 2) % 3]) && pvs__ep_same(a1, B[j])))
				continue;
			x = B[(j + 1) % 3];
			q[0] = a0; q[1] = x; q[2] = a1; q[3] = A[(i + 2) % 3];
			for (k = 0; k < 3; ++k)
				scale = pvs__dmax(scale,
								  pvs__dabs((double)x[k] - a0[k]) + pvs__dabs((double)x[k]) + pvs__dabs((double)a0[k]));
			/* the hull exceeds the two triangles by at most this distance: the slack */
			dev = pvs__dabs(n[0] * ((double)x[0] - a0[0]) + n[1] * ((double)x[1] - a0[1]) +
							n[2] * ((double)x[2] - a0[2])) /
				len;
			if (dev > 1e-6 * scale) return 0;
			for (k = 0; k < 4; ++k) { /* strictly convex at every corner, turning like the triangle */
				const float *p0 = q[k], *p1 = q[(k + 1) % 4], *p2 = q[(k + 2) % 4];
				double m[3];
				pvs__ep_tri_normal(p0, p1, p2, m);
				if (!(m[0] * n[0] + m[1] * n[1] + m[2] * n[2] > 0.0)) return 0;
			}
			*slack = dev == 0.0 ? 0.0 : 2.0 * dev + 1e-12 * scale;
			return 1;
		}
	return 0;
}

/* An edge in a sheet's plane, ends ordered. */
typedef struct pvs__epedge2 {
	float a[2], b[2];
	uint32_t tri;            /* the triangle's index in its group, then its component's root */
} pvs__epedge2;

PVS__STATIC int pvs__ep_p2_cmp(const float *a, const float *b) {
	if (a[0] != b[0]) return a[0] < b[0] ? -1 : 1;
	if (a[1] != b[1]) return a[1] < b[1] ? -1 : 1;
	return 0;
}

PVS__STATIC int pvs__ep_edge2_cmp(const void *x, const void *y) {
	const pvs__epedge2 *a = (const pvs__epedge2 *)x, *b = (const pvs__epedge2 *)y;
	int c = pvs__ep_p2_cmp(a->a, b->a);
	return c ? c : pvs__ep_p2_cmp(a->b, b->b);
}

PVS__STATIC int pvs__ep_edge2_root_cmp(const void *x, const void *y) {
	const pvs__epedge2 *a = (const pvs__epedge2 *)x, *b = (const pvs__epedge2 *)y;
	if (a->tri != b->tri) return a->tri < b->tri ? -1 : 1;
	return pvs__ep_edge2_cmp(x, y);
}

/* 1 if (x, y) lies inside convex counter-clockwise polygon q by a margin. */
PVS__STATIC int pvs__ep_in_convex(const float *q, uint32_t n, double x, double y) {
	uint32_t i;
	for (i = 0; i < n; ++i) {
		const float *a = q + 2 * i, *b = q + 2 * ((i + 1) % n);
		double ex = (double)b[0] - a[0], ey = (double)b[1] - a[1], cr = ex * (y - a[1]) - ey * (x - a[0]);
		double scale = (pvs__dabs(ex) + pvs__dabs(ey)) * (pvs__dabs(x - a[0]) + pvs__dabs(y - a[1]));
		if (!(cr > 1e-9 * scale)) return 0;
	}
	return 1;
}

/* An end of a boundary edge (pvs__ep_sheet_polygon's walk). */
typedef struct pvs__epend {
	float p[2];
	uint32_t edge;
} pvs__epend;
PVS__STATIC int pvs__ep_end_cmp(const void *x, const void *y) {
	const pvs__epend *a = (const pvs__epend *)x, *b = (const pvs__epend *)y;
	int c = pvs__ep_p2_cmp(a->p, b->p);
	return c ? c : a->edge < b->edge ? -1 : a->edge > b->edge;
}

/* Walks boundary edges e[0 .. nb) as one loop from e[0].a into q; 0 if a point is on more than two edges or they form
   several loops. ends: scratch of 2 nb. */
PVS__STATIC int pvs__ep_walk_loop(const pvs__epedge2 *e, uint32_t nb, float *q, pvs__epend *ends) {
	uint32_t i, m, edge = 0;
	float cur[2];
	for (i = 0; i < nb; ++i) {
		memcpy(ends[2 * i].p, e[i].a, sizeof(cur));
		memcpy(ends[2 * i + 1].p, e[i].b, sizeof(cur));
		ends[2 * i].edge = ends[2 * i + 1].edge = i;
	}
	PVS_QSORT(ends, 2 * (size_t)nb, sizeof(pvs__epend), pvs__ep_end_cmp);
	q[0] = e[0].a[0]; q[1] = e[0].a[1];
	cur[0] = e[0].b[0]; cur[1] = e[0].b[1];
	for (m = 1; m < nb; ++m) {
		uint32_t lo = 0, hi = 2 * nb, next;
		q[2 * m] = cur[0];
		q[2 * m + 1] = cur[1];
		while (lo < hi) { /* the first end at cur */
			uint32_t mid = lo + (hi - lo) / 2;
			if (pvs__ep_p2_cmp(ends[mid].p, cur) < 0) lo = mid + 1;
			else hi = mid;
		}
		if (lo + 1 >= 2 * nb || pvs__ep_p2_cmp(ends[lo + 1].p, cur) != 0) return 0; /* a loose end */
		if (lo + 2 < 2 * nb && pvs__ep_p2_cmp(ends[lo + 2].p, cur) == 0) return 0; /* a point on more than two edges */
		next = ends[lo].edge == edge ? ends[lo + 1].edge : ends[lo].edge;
		if (next == 0 || next == edge) return 0;
		edge = next;
		if (pvs__ep_p2_cmp(e[edge].a, cur) == 0) { cur[0] = e[edge].b[0]; cur[1] = e[edge].b[1]; }
		else { cur[0] = e[edge].a[0]; cur[1] = e[edge].a[1]; }
	}
	return pvs__ep_p2_cmp(cur, q) == 0; /* the loop must close at its start */
}

/* The union of a group's triangles as one convex polygon: boundary edges (odd use counts) in one loop turning once,
   with the triangles' area (no overlap, no hole). Fills q (counter-clockwise, collinear points dropped), returns its
   size or 0. tol > 0: wrong turns under tol (relative) count as straight, q is the loop's hull (hp, hh: scratch of
   qcap + 1; 0 past max_hull points), *dent the deepest loop point inside it. ends: 2 qcap. */
PVS__STATIC uint32_t pvs__ep_sheet_polygon(pvs__epedge2 *e, uint32_t ne, double tri_area, float *q, unsigned char *keep,
										   uint32_t qcap, pvs__epend *ends, double tol, double (*hp)[2],
										   double (*hh)[2], int max_hull, double *dent) {
	uint32_t nb = 0, i, j, n = 0, m;
	double area = 0.0, turn = 0.0;
	PVS_QSORT(e, ne, sizeof(pvs__epedge2), pvs__ep_edge2_cmp);
	for (i = 0; i < ne;) { /* a zero-area triangle leaves a zero-length edge: a point, not a side */
		j = i;
		while (j < ne && pvs__ep_edge2_cmp(e + j, e + i) == 0) ++j;
		if (((j - i) & 1u) && pvs__ep_p2_cmp(e[i].a, e[i].b) != 0) e[nb++] = e[i];
		i = j;
	}
	if (nb < 3 || nb > qcap) return 0;
	if (!pvs__ep_walk_loop(e, nb, q, ends)) return 0;
	n = nb;
	for (i = 0; i < n; ++i) {
		const float *a = q + 2 * i, *b = q + 2 * ((i + 1) % n);
		area += (double)a[0] * b[1] - (double)b[0] * a[1];
	}
	area *= 0.5;
	if (area < 0.0) { /* make it counter-clockwise */
		for (i = 0; i < n / 2; ++i) {
			float t0 = q[2 * i], t1 = q[2 * i + 1];
			q[2 * i] = q[2 * (n - 1 - i)];
			q[2 * i + 1] = q[2 * (n - 1 - i) + 1];
			q[2 * (n - 1 - i)] = t0;
			q[2 * (n - 1 - i) + 1] = t1;
		}
		area = -area;
	}
	if (!(pvs__dabs(area - tri_area) <= 1e-6 * tri_area)) return 0;
	if (tol > 0.0) {
		int hn;
		for (i = 0; i < n; ++i) {
			const float *a = q + 2 * ((i + n - 1) % n), *b = q + 2 * i, *c = q + 2 * ((i + 1) % n);
			double ux = (double)b[0] - a[0], uy = (double)b[1] - a[1], vx = (double)c[0] - b[0],
				   vy = (double)c[1] - b[1];
			double cr = ux * vy - uy * vx;
			if (cr < -tol * (pvs__dabs(ux) + pvs__dabs(uy)) * (pvs__dabs(vx) + pvs__dabs(vy))) return 0;
			turn += atan2(cr, ux * vx + uy * vy);
			hp[i][0] = b[0];
			hp[i][1] = b[1];
		}
		if (!(pvs__dabs(turn - 6.283185307179586) < 1e-3)) return 0;
		hn = pvs__ep_hull(hp, (int)n, hh);
		if (hn < 3 || hn > max_hull) return 0;
		*dent = 0.0;
		for (i = 0; i < n; ++i) { /* each loop point's distance inside the hull (hp is sorted now) */
			double best = DBL_MAX;
			int h;
			for (h = 0; h < hn; ++h) {
				const double *a = hh[h], *b = hh[h + 1 < hn ? h + 1 : 0];
				double ex = b[0] - a[0], ey = b[1] - a[1], len = sqrt(ex * ex + ey * ey);
				if (len > 0.0) best = pvs__dmin(best, pvs__dabs(ex * (hp[i][1] - a[1]) - ey * (hp[i][0] - a[0])) / len);
			}
			*dent = pvs__dmax(*dent, best);
		}
		for (i = 0; i < (uint32_t)hn; ++i) {
			q[2 * i] = (float)hh[i][0];
			q[2 * i + 1] = (float)hh[i][1];
		}
		return (uint32_t)hn;
	}
	/* no right turn, one full turn; collinear points dropped */
	for (i = 0, m = 0; i < n; ++i) {
		const float *a = q + 2 * ((i + n - 1) % n), *b = q + 2 * i, *c = q + 2 * ((i + 1) % n);
		double ux = (double)b[0] - a[0], uy = (double)b[1] - a[1], vx = (double)c[0] - b[0], vy = (double)c[1] - b[1];
		double cr = ux * vy - uy * vx;
		if (cr < 0.0) return 0;
		turn += atan2(cr, ux * vx + uy * vy);
		keep[i] = cr > 0.0;
		m += keep[i];
	}
	if (!(pvs__dabs(turn - 6.283185307179586) < 1e-3) || m < 3) return 0;
	for (i = 0, m = 0; i < n; ++i)
		if (keep[i]) {
			q[2 * m] = q[2 * i];
			q[2 * m + 1] = q[2 * i + 1];
			++m;
		}
	return m;
}

/* A corner of the object being prepared: position and slot 3 t + k. */
typedef struct pvs__epvref {
	float p[3];
	uint32_t slot;
} pvs__epvref;

PVS__STATIC int pvs__ep_vref_cmp(const void *a, const void *b) {
	const pvs__epvref *x = (const pvs__epvref *)a, *y = (const pvs__epvref *)b;
	int k;
	for (k = 0; k < 3; ++k)
		if (x->p[k] != y->p[k]) return x->p[k] < y->p[k] ? -1 : 1;
	return x->slot < y->slot ? -1 : x->slot > y->slot;
}

PVS__STATIC int pvs__ep_u64_cmp(const void *a, const void *b) {
	uint64_t x = *(const uint64_t *)a, y = *(const uint64_t *)b;
	return x < y ? -1 : x > y;
}


/* Scratch of the preparation, sized for the largest object. */
typedef struct pvs__epprepwork {
	pvs__epvref *ref;     /* 3 per triangle */
	uint32_t *canon;      /* 3 per triangle: the vertex's id among the object's distinct positions */
	const float **vpos;   /* per distinct position */
	uint32_t *owner;      /* per distinct position: a triangle using it */
	uint32_t *parent;     /* per triangle: union-find */
	uint32_t *order;      /* per triangle: grouped by component */
	uint32_t *start;      /* per triangle + 1: component starts */
	uint64_t *edges;      /* 3 per triangle */
	uint32_t *mark;       /* per distinct position: last component that listed it */
	uint32_t *uv;         /* per distinct position: the component's distinct vertices */
	pvs__epedge2 *e2;     /* 3 per triangle: a planar group's edges in its 2D frame */
	float *q2;            /* 2 (3 per triangle + 1): the group's polygon */
	unsigned char *keep;  /* 3 per triangle + 1 */
	pvs__epend *ends;     /* 6 per triangle: the loop walk's scratch */
	uint32_t *gparent;    /* per triangle of a component: planar groups (union-find) */
	unsigned char *used;  /* per triangle of a component: merged into a planar polygon */
	double *hp, *hh;      /* 2 (3 per triangle + 1): hull scratch */
	uint64_t *bed;        /* 3 per triangle: a group's edges */
	size_t cap;           /* triangles */
} pvs__epprepwork;

PVS__STATIC void pvs__ep_work_free(const pvs_allocator *a, pvs__epprepwork *w) {
	size_t n = w->cap;
	pvs__free_array(a, w->ref, 3 * n, sizeof(pvs__epvref));
	pvs__free_array(a, w->canon, 3 * n, sizeof(uint32_t));
	pvs__free_array(a, (void *)w->vpos, 3 * n, sizeof(const float *));
	pvs__free_array(a, w->owner, 3 * n, sizeof(uint32_t));
	pvs__free_array(a, w->parent, n, sizeof(uint32_t));
	pvs__free_array(a, w->order, n, sizeof(uint32_t));
	pvs__free_array(a, w->start, n + 1, sizeof(uint32_t));
	pvs__free_array(a, w->edges, 3 * n, sizeof(uint64_t));
	pvs__free_array(a, w->mark, 3 * n, sizeof(uint32_t));
	pvs__free_array(a, w->uv, 3 * n, sizeof(uint32_t));
	pvs__free_array(a, w->e2, 3 * n, sizeof(pvs__epedge2));
	pvs__free_array(a, w->ends, 6 * n, sizeof(pvs__epend));
	pvs__free_array(a, w->q2, 2 * (3 * n + 1), sizeof(float));
	pvs__free_array(a, w->keep, 3 * n + 1, 1);
	pvs__free_array(a, w->gparent, n, sizeof(uint32_t));
	pvs__free_array(a, w->used, n, 1);
	pvs__free_array(a, w->hp, 2 * (3 * n + 1), sizeof(double));
	pvs__free_array(a, w->hh, 2 * (3 * n + 1), sizeof(double));
	pvs__free_array(a, w->bed, 3 * n, sizeof(uint64_t));
	memset(w, 0, sizeof(*w));
}

PVS__STATIC int pvs__ep_work_alloc(const pvs_allocator *a, pvs__epprepwork *w, size_t n) {
	memset(w, 0, sizeof(*w));
	w->cap = n;
	w->ref = (pvs__epvref *)pvs__alloc_array(a, 3 * n, sizeof(pvs__epvref));
	w->canon = (uint32_t *)pvs__alloc_array(a, 3 * n, sizeof(uint32_t));
	w->vpos = (const float **)pvs__alloc_array(a, 3 * n, sizeof(const float *));
	w->owner = (uint32_t *)pvs__alloc_array(a, 3 * n, sizeof(uint32_t));
	w->parent = (uint32_t *)pvs__alloc_array(a, n, sizeof(uint32_t));
	w->order = (uint32_t *)pvs__alloc_array(a, n, sizeof(uint32_t));
	w->start = (uint32_t *)pvs__alloc_array(a, n + 1, sizeof(uint32_t));
	w->edges = (uint64_t *)pvs__alloc_array(a, 3 * n, sizeof(uint64_t));
	w->mark = (uint32_t *)pvs__alloc_array(a, 3 * n, sizeof(uint32_t));
	w->uv = (uint32_t *)pvs__alloc_array(a, 3 * n, sizeof(uint32_t));
	w->e2 = (pvs__epedge2 *)pvs__alloc_array(a, 3 * n, sizeof(pvs__epedge2));
	w->q2 = (float *)pvs__alloc_array(a, 2 * (3 * n + 1), sizeof(float));
	w->keep = (unsigned char *)pvs__alloc_array(a, 3 * n + 1, 1);
	w->ends = (pvs__epend *)pvs__alloc_array(a, 6 * n, sizeof(pvs__epend));
	w->gparent = (uint32_t *)pvs__alloc_array(a, n, sizeof(uint32_t));
	w->used = (unsigned char *)pvs__alloc_array(a, n, 1);
	w->hp = (double *)pvs__alloc_array(a, 2 * (3 * n + 1), sizeof(double));
	w->hh = (double *)pvs__alloc_array(a, 2 * (3 * n + 1), sizeof(double));
	w->bed = (uint64_t *)pvs__alloc_array(a, 3 * n, sizeof(uint64_t));
	return w->hp && w->hh && w->bed && w->ref && w->canon && w->vpos && w->owner && w->parent && w->order && w->start &&
		w->edges && w->mark && w->uv && w->e2 && w->q2 && w->keep && w->ends && w->gparent && w->used;
}

/* 1 if the component's distinct vertices (<= PVS__EP_MAXP) lie on one side of each of its triangles' planes, to float
   precision; *slack: twice the largest violation (the hull exceeds the surface by no more). */
PVS__STATIC int pvs__ep_convex_component(const pvs_scene *s, const uint32_t *tris, uint32_t tn, const float *const *pts,
										 uint32_t n, double *slack) {
	uint32_t t, i, k;
	double scale = 0.0, worst = 0.0;
	for (i = 0; i < n; ++i)
		for (k = 0; k < 3; ++k)
			scale = pvs__dmax(scale, pvs__dabs((double)pts[i][k] - pts[0][k]) + pvs__dabs((double)pts[i][k]));
	for (t = 0; t < tn; ++t) {
		const float *c[3];
		double nrm[3], len, lo = 0.0, hi = 0.0;
		for (k = 0; k < 3; ++k) c[k] = s->positions + 3 * (size_t)s->indices[3 * (size_t)tris[t] + k];
		len = pvs__ep_tri_normal(c[0], c[1], c[2], nrm);
		if (!(len > 0.0)) return 0;
		for (i = 0; i < n; ++i) {
			double d = (nrm[0] * ((double)pts[i][0] - c[0][0]) + nrm[1] * ((double)pts[i][1] - c[0][1]) +
						nrm[2] * ((double)pts[i][2] - c[0][2])) /
				len;
			lo = pvs__dmin(lo, d);
			hi = pvs__dmax(hi, d);
		}
		worst = pvs__dmax(worst, pvs__dmin(-lo, hi));
	}
	if (worst > 1e-6 * scale) return 0;
	*slack = worst == 0.0 ? 0.0 : 2.0 * worst + 1e-12 * scale;
	return 1;
}

/* 1 if every vertex lies within float precision of the component's largest triangle's plane. A flat closed mesh (a
   two-sided wall) bounds no volume: neither a solid (its hull would fill windows) nor sliced. */
PVS__STATIC int pvs__ep_flat_component(const pvs_scene *s, const uint32_t *tris, uint32_t tn, const float *const *pts,
									   uint32_t n) {
	uint32_t t, i, k, best = 0;
	double bl = 0.0, nrm[3], scale = 0.0;
	const float *c0 = NULL;
	for (t = 0; t < tn; ++t) {
		const float *c[3];
		double l;
		for (k = 0; k < 3; ++k) c[k] = s->positions + 3 * (size_t)s->indices[3 * (size_t)tris[t] + k];
		l = pvs__ep_tri_normal(c[0], c[1], c[2], nrm);
		if (l > bl) { bl = l; best = t; }
	}
	if (!(bl > 0.0)) return 1;
	{
		const float *c[3];
		for (k = 0; k < 3; ++k) c[k] = s->positions + 3 * (size_t)s->indices[3 * (size_t)tris[best] + k];
		bl = pvs__ep_tri_normal(c[0], c[1], c[2], nrm);
		c0 = c[0];
	}
	for (i = 0; i < n; ++i)
		for (k = 0; k < 3; ++k)
			scale = pvs__dmax(scale, pvs__dabs((double)pts[i][k] - c0[k]) + pvs__dabs((double)pts[i][k]));
	for (i = 0; i < n; ++i) {
		double d = (nrm[0] * ((double)pts[i][0] - c0[0]) + nrm[1] * ((double)pts[i][1] - c0[1]) +
					nrm[2] * ((double)pts[i][2] - c0[2])) /
			bl;
		if (pvs__dabs(d) > 1e-6 * scale) return 0;
	}
	return 1;
}

/* The cap of a component whose boundary edges (pairs in bnd) lie exactly in one axis-aligned plane x_k = c, every
   vertex on one side: *side = +1 if the solid lies where x_k >= c, else -1. Exact, so pvs__ep_slice needs no
   tolerance. */
PVS__STATIC int pvs__ep_cap_axis(const float *const *vpos, const uint32_t *bnd, uint32_t nb, const uint32_t *uv,
								 uint32_t nuv, int *axis, float *c, int *side) {
	int k;
	uint32_t i;
	for (k = 0; k < 3; ++k) {
		float v = vpos[bnd[0]][k];
		int below = 0, above = 0;
		for (i = 0; i < 2 * nb && vpos[bnd[i]][k] == v; ++i) {}
		if (i < 2 * nb) continue;
		for (i = 0; i < nuv; ++i) {
			below |= vpos[uv[i]][k] < v;
			above |= vpos[uv[i]][k] > v;
		}
		if (below == above) continue; /* both sides, or flat */
		*axis = k;
		*c = v;
		*side = above ? 1 : -1;
		return 1;
	}
	return 0;
}

/* 1 if triangle B lies in A's plane (normal na, length la) to float precision, facing the same way. */
PVS__STATIC int pvs__ep_coplanar(const float *const *A, const double *na, double la, const float *const *B,
								 double scale) {
	double nb[3];
	int k;
	if (!(pvs__ep_tri_normal(B[0], B[1], B[2], nb) > 0.0) || !(na[0] * nb[0] + na[1] * nb[1] + na[2] * nb[2] > 0.0))
		return 0;
	for (k = 0; k < 3; ++k) {
		double d = (na[0] * ((double)B[k][0] - A[0][0]) + na[1] * ((double)B[k][1] - A[0][1]) +
					na[2] * ((double)B[k][2] - A[0][2])) /
			la;
		if (pvs__dabs(d) > 1e-6 * scale) return 0;
	}
	return 1;
}

#define PVS__EP_TRI(j, k) (s->positions + 3 * (size_t)s->indices[3 * (size_t)(t0 + tl[j]) + (k)])
#define PVS__EP_CONCAVE_EDGES 256

/* A planar group not forming one convex polygon becomes a concave planar occluder (Durand 2000 §3.4, Fig. 7): boundary
   edges and plane (unit normal nr / lr, vertices within dev); its points, its vertices' hull, serve selection only.
   Past PVS__EP_CONCAVE_EDGES edges it stays in pieces. */
PVS__STATIC pvs_result pvs__ep_add_concave(pvs__extproj_prep *p, const pvs_scene *s, uint32_t t0, const uint32_t *tl,
										   pvs__epprepwork *w, uint32_t m, uint32_t cnt, const double *nr, double lr,
										   double dev, double scale) {
	uint32_t h, c, nb = 0, ne = 0, ax = 0, u, v, i, nh = 0;
	int k, hn;
	pvs_result r = PVS_OK;
	const float *q3[3 * PVS__EP_CONCAVE_EDGES];
	pvs__epocc *o;
	for (k = 1; k < 3; ++k)
		if (pvs__dabs(nr[k]) > pvs__dabs(nr[ax])) ax = (uint32_t)k;
	u = (ax + 1) % 3;
	v = (ax + 2) % 3;
	for (h = m; h < m + cnt; ++h) {
		uint32_t t = (uint32_t)(w->edges[h] & 0xffffffffu);
		for (c = 0; c < 3; ++c) {
			uint64_t x = w->canon[3 * tl[t] + c], y = w->canon[3 * tl[t] + (c + 1) % 3];
			if (x != y) w->bed[ne++] = x < y ? (x << 32) | y : (y << 32) | x;
		}
	}
	PVS_QSORT(w->bed, ne, sizeof(uint64_t), pvs__ep_u64_cmp);
	for (h = 0; h < ne;) {
		uint32_t g = h;
		while (g < ne && w->bed[g] == w->bed[h]) ++g;
		if ((g - h) & 1u) w->bed[nb++] = w->bed[h];
		h = g;
	}
	if (nb < 3 || nb > PVS__EP_CONCAVE_EDGES) return PVS_OK;
	/* the hull of the boundary's vertices (interior ones lie inside) */
	for (h = 0; h < 2 * nb; ++h) {
		const float *x = w->vpos[h & 1u ? (uint32_t)(w->bed[h >> 1] & 0xffffffffu) : (uint32_t)(w->bed[h >> 1] >> 32)];
		w->hp[2 * h] = x[u];
		w->hp[2 * h + 1] = x[v];
	}
	hn = pvs__ep_hull((double(*)[2])w->hp, (int)(2 * nb), (double(*)[2])w->hh);
	if (hn < 3) return PVS_OK;
	for (k = 0; k < hn; ++k) {
		const float *hit = NULL;
		for (h = 0; h < 2 * nb && !hit; ++h) {
			const float *x =
				w->vpos[h & 1u ? (uint32_t)(w->bed[h >> 1] & 0xffffffffu) : (uint32_t)(w->bed[h >> 1] >> 32)];
			if ((double)x[u] == w->hh[2 * k] && (double)x[v] == w->hh[2 * k + 1]) hit = x;
		}
		if (!hit) return PVS_OK;
		q3[nh++] = hit;
	}
	p->cedge = (float *)pvs__grow_array(&p->allocator, p->cedge, &p->cedge_capacity, p->cedge_count,
										p->cedge_count + nb, 6 * sizeof(float), &r);
	if (!p->cedge) return r;
	o = p->occ + p->occ_count;
	pvs__ep_add(p, q3, nh, 0, dev == 0.0 ? 0.0 : dev + 1e-12 * scale);
	o->efirst = (uint32_t)p->cedge_count;
	o->ecount = nb;
	for (i = 0; i < nb; ++i) {
		memcpy(p->cedge + 6 * p->cedge_count, w->vpos[(uint32_t)(w->bed[i] >> 32)], 3 * sizeof(float));
		memcpy(p->cedge + 6 * p->cedge_count + 3, w->vpos[(uint32_t)(w->bed[i] & 0xffffffffu)], 3 * sizeof(float));
		++p->cedge_count;
	}
	{
		const float *a0 = PVS__EP_TRI((uint32_t)(w->edges[m] & 0xffffffffu), 0);
		for (k = 0; k < 3; ++k) o->pn[k] = (float)(nr[k] / lr);
		o->pd = (float)(o->pn[0] * (double)a0[0] + o->pn[1] * (double)a0[1] + o->pn[2] * (double)a0[2]);
	}
	for (h = m; h < m + cnt; ++h) w->used[(uint32_t)(w->edges[h] & 0xffffffffu)] = 1;
	return PVS_OK;
}

/* Union-finds into w->gparent (smaller index roots) triangles sharing an edge, coplanar to float precision (`scale`:
   twice the largest coordinate) and facing alike. Needs 3 n < 2^21 (21-bit packing). */
PVS__STATIC void pvs__ep_planar_groups(const pvs_scene *s, uint32_t t0, const uint32_t *tl, uint32_t n,
									   pvs__epprepwork *w, double scale) {
	uint32_t j, k, ne = 0, g;
	for (j = 0; j < n; ++j)
		for (k = 0; k < 3; ++k) {
			uint64_t x = w->canon[3 * tl[j] + k], y = w->canon[3 * tl[j] + (k + 1) % 3];
			if (x == y) continue;
			w->edges[ne++] = (x < y ? (x << 42) | (y << 21) : (y << 42) | (x << 21)) | j;
		}
	PVS_QSORT(w->edges, ne, sizeof(uint64_t), pvs__ep_u64_cmp);
	for (g = 0; g < ne;) {
		uint32_t h = g + 1;
		while (h < ne && (w->edges[h] >> 21) == (w->edges[g] >> 21)) ++h;
		for (k = g; k + 1 < h; ++k) { /* triangles around the edge, pairwise (two-sided walls: four) */
			uint32_t k2;
			for (k2 = k + 1; k2 < h && k2 < k + 8; ++k2) {
				uint32_t ja = (uint32_t)(w->edges[k] & 0x1fffffu), jb = (uint32_t)(w->edges[k2] & 0x1fffffu), m;
				const float *A[3], *B[3];
				double na[3], la;
				for (m = 0; m < 3; ++m) { A[m] = PVS__EP_TRI(ja, m); B[m] = PVS__EP_TRI(jb, m); }
				la = pvs__ep_tri_normal(A[0], A[1], A[2], na);
				if (!(la > 0.0) || !pvs__ep_coplanar(A, na, la, B, scale) || !pvs__ep_coplanar(B, na, la, A, scale))
					continue;
				{
					uint32_t x = pvs__uf_find(w->gparent, ja), y = pvs__uf_find(w->gparent, jb);
					if (x != y) w->gparent[x > y ? x : y] = x < y ? x : y;
				}
			}
		}
		g = h;
	}
}

/* A planar group's edges in (u, v) into w->e2 (ends ordered, with their triangle); *dev: the farthest vertex from the
   plane (nr, lr) through A[0]; *area: its area in (u, v). Returns the count. */
PVS__STATIC uint32_t pvs__ep_group_edges(const pvs_scene *s, uint32_t t0, const uint32_t *tl, pvs__epprepwork *w,
										 uint32_t m, uint32_t cnt, const float *const *A, const double *nr, double lr,
										 uint32_t u, uint32_t v, double *dev, double *area) {
	uint32_t h, e = 0;
	for (h = m; h < m + cnt; ++h) {
		uint32_t t = (uint32_t)(w->edges[h] & 0xffffffffu), c;
		const float *C[3];
		for (c = 0; c < 3; ++c) {
			const float *x = C[c] = PVS__EP_TRI(t, c);
			*dev = pvs__dmax(*dev,
							 pvs__dabs(nr[0] * ((double)x[0] - A[0][0]) + nr[1] * ((double)x[1] - A[0][1]) +
									   nr[2] * ((double)x[2] - A[0][2])) /
								 lr);
		}
		*area += 0.5 *
			pvs__dabs(((double)C[1][u] - C[0][u]) * ((double)C[2][v] - C[0][v]) -
					  ((double)C[2][u] - C[0][u]) * ((double)C[1][v] - C[0][v]));
		for (c = 0; c < 3; ++c) {
			const float *x = C[c], *y = C[(c + 1) % 3];
			float P0[2], P1[2];
			pvs__epedge2 *ed = w->e2 + e++;
			P0[0] = x[u]; P0[1] = x[v];
			P1[0] = y[u]; P1[1] = y[v];
			if (pvs__ep_p2_cmp(P0, P1) <= 0) { memcpy(ed->a, P0, sizeof(P0)); memcpy(ed->b, P1, sizeof(P1)); }
			else { memcpy(ed->a, P1, sizeof(P1)); memcpy(ed->b, P0, sizeof(P0)); }
			ed->tri = t;
		}
	}
	return e;
}

/* Adds a planar group's convex polygon (k corners in w->q2, in the (u, v) plane of nr's dominant axis ax) as a planar
   occluder, marking its triangles in w->used; nothing if a corner is not a group vertex. */
PVS__STATIC void pvs__ep_add_planar(pvs__extproj_prep *p, const pvs_scene *s, uint32_t t0, const uint32_t *tl,
									pvs__epprepwork *w, uint32_t m, uint32_t cnt, uint32_t k, const double *nr,
									double lr, uint32_t ax, double dev, double dent, double scale) {
	const float *q3[PVS__EP_MAXP];
	uint32_t i, h, found = 0, u = (ax + 1) % 3, v = (ax + 2) % 3;
	for (i = 0; i < k; ++i) { /* the corners back in 3D */
		const float *hit = NULL;
		for (h = m; h < m + cnt && !hit; ++h) {
			uint32_t t = (uint32_t)(w->edges[h] & 0xffffffffu), c;
			for (c = 0; c < 3 && !hit; ++c) {
				const float *x = PVS__EP_TRI(t, c);
				if (x[u] == w->q2[2 * i] && x[v] == w->q2[2 * i + 1]) hit = x;
			}
		}
		if (!hit) break;
		q3[found++] = hit;
	}
	if (found != k) return;
	{
		/* slack: the vertices' distance from a plane through three far-apart corners (the first triangle's plane tilts
		   with its rounding), doubled for hull and surface, again for the footprint, plus dent |n| / |n_ax| (dent in
		   (u, v)) */
		double best = 0.0, nb[3], lb = 0.0, dev2 = 0.0;
		uint32_t i1, i2, b1 = 1, b2 = 2;
		for (i1 = 1; i1 < k; ++i1)
			for (i2 = i1 + 1; i2 < k; ++i2) {
				double l = pvs__ep_tri_normal(q3[0], q3[i1], q3[i2], nb);
				if (l > best) { best = l; b1 = i1; b2 = i2; }
			}
		lb = pvs__ep_tri_normal(q3[0], q3[b1], q3[b2], nb);
		if (lb > 0.0 && nb[0] * nr[0] + nb[1] * nr[1] + nb[2] * nr[2] > 0.0) {
			for (h = m; h < m + cnt; ++h) {
				uint32_t t = (uint32_t)(w->edges[h] & 0xffffffffu), c;
				for (c = 0; c < 3; ++c) {
					const float *x = PVS__EP_TRI(t, c);
					dev2 = pvs__dmax(dev2,
									 pvs__dabs(nb[0] * ((double)x[0] - q3[0][0]) + nb[1] * ((double)x[1] - q3[0][1]) +
											   nb[2] * ((double)x[2] - q3[0][2])) /
										 lb);
				}
			}
			dev = pvs__dmin(dev, dev2);
		}
		dev = 4.0 * dev + 2.0 * dent * lr / pvs__dabs(nr[ax]);
	}
	pvs__ep_add(p, q3, k, 0, dev == 0.0 ? 0.0 : dev + 1e-12 * scale);
	for (h = m; h < m + cnt; ++h) w->used[(uint32_t)(w->edges[h] & 0xffffffffu)] = 1;
}

/* Durand 2000 §3.3-3.4: a wall of several triangles must act as one occluder, or each piece loses a strip along every
   shared edge to its penumbra. Edge-connected, coplanar, like-facing triangles forming one convex polygon of at most
   PVS__EP_MAXP corners become one planar occluder (marked in w->used); other groups, concave ones. */
PVS__STATIC pvs_result pvs__ep_merge_planar(pvs__extproj_prep *p, const pvs_scene *s, uint32_t t0, const uint32_t *tl,
											uint32_t n, pvs__epprepwork *w) {
	uint32_t j, k, g;
	double scale = 0.0;
	pvs_result r = PVS_OK;
	for (j = 0; j < n; ++j) { w->used[j] = 0; w->gparent[j] = j; }
	if (n < 2 || 3 * (uint64_t)n >= (1u << 21)) return PVS_OK;
	for (j = 0; j < n; ++j)
		for (k = 0; k < 3; ++k) {
			const float *x = PVS__EP_TRI(j, k);
			int c;
			for (c = 0; c < 3; ++c) scale = pvs__dmax(scale, 2.0 * pvs__dabs((double)x[c]));
		}
	pvs__ep_planar_groups(s, t0, tl, n, w, scale);
	/* groups: sorted (root, triangle) pairs, the root the group's first triangle */
	for (j = 0; j < n; ++j) w->edges[j] = ((uint64_t)pvs__uf_find(w->gparent, j) << 32) | j;
	PVS_QSORT(w->edges, n, sizeof(uint64_t), pvs__ep_u64_cmp);
	for (g = 0; g < n;) {
		uint32_t h = g + 1, root = (uint32_t)(w->edges[g] >> 32), m, cnt, e, ax = 0, u, v;
		const float *A[3];
		double nr[3], lr, dev = 0.0, area = 0.0, dent = 0.0;
		while (h < n && (uint32_t)(w->edges[h] >> 32) == root) ++h;
		cnt = h - g;
		m = g;
		g = h;
		if (cnt < 2) continue;
		for (k = 0; k < 3; ++k) A[k] = PVS__EP_TRI(root, k);
		lr = pvs__ep_tri_normal(A[0], A[1], A[2], nr);
		if (!(lr > 0.0)) continue;
		for (k = 1; k < 3; ++k)
			if (pvs__dabs(nr[k]) > pvs__dabs(nr[ax])) ax = k;
		u = (ax + 1) % 3;
		v = (ax + 2) % 3;
		e = pvs__ep_group_edges(s, t0, tl, w, m, cnt, A, nr, lr, u, v, &dev, &area);
		if (dev > 1e-6 * scale || !(area > 0.0)) continue;
		k = pvs__ep_sheet_polygon(w->e2, e, area, w->q2, w->keep, e, w->ends, 1e-4, (double(*)[2])w->hp,
								  (double(*)[2])w->hh, PVS__EP_MAXP, &dent);
		if (k < 3 || k > PVS__EP_MAXP || dent > 1e-6 * scale) {
			r = pvs__ep_add_concave(p, s, t0, tl, w, m, cnt, nr, lr, dev, scale);
			if (r != PVS_OK) return r;
			continue;
		}
		pvs__ep_add_planar(p, s, t0, tl, w, m, cnt, k, nr, lr, ax, dev, dent, scale);
	}
	return r;
}
#undef PVS__EP_TRI

/* Connected components (by shared positions) of an object's triangles into w: canon (corner -> distinct vertex), vpos
   (its position), parent (root: the smaller index, deterministic), order (by component, in order); start[root] ends as
   the component's end. */
PVS__STATIC void pvs__ep_components(const pvs_scene *s, uint32_t t0, uint32_t tn, pvs__epprepwork *w) {
	uint32_t i, nv = 0, sum = 0;
	for (i = 0; i < 3 * tn; ++i) {
		const float *q = s->positions + 3 * (size_t)s->indices[3 * (size_t)t0 + i];
		memcpy(w->ref[i].p, q, 3 * sizeof(float));
		w->ref[i].slot = i;
	}
	PVS_QSORT(w->ref, 3 * (size_t)tn, sizeof(pvs__epvref), pvs__ep_vref_cmp);
	for (i = 0; i < 3 * tn; ++i) {
		if (i == 0 || !pvs__ep_same(w->ref[i].p, w->ref[i - 1].p)) {
			w->vpos[nv] = s->positions + 3 * (size_t)s->indices[3 * (size_t)t0 + w->ref[i].slot];
			w->owner[nv] = 0xffffffffu;
			w->mark[nv] = 0xffffffffu;
			++nv;
		}
		w->canon[w->ref[i].slot] = nv - 1;
	}
	for (i = 0; i < tn; ++i) w->parent[i] = i;
	for (i = 0; i < 3 * tn; ++i) {
		uint32_t v = w->canon[i], t = i / 3;
		if (w->owner[v] == 0xffffffffu) w->owner[v] = t;
		else {
			uint32_t x = pvs__uf_find(w->parent, t), y = pvs__uf_find(w->parent, w->owner[v]);
			if (x != y) w->parent[x > y ? x : y] = x < y ? x : y;
		}
	}
	for (i = 0; i < tn; ++i) w->start[i] = 0;
	for (i = 0; i < tn; ++i) ++w->start[pvs__uf_find(w->parent, i)];
	for (i = 0; i < tn; ++i) {
		uint32_t c = w->start[i];
		w->start[i] = sum;
		sum += c;
	}
	w->start[tn] = sum;
	for (i = 0; i < tn; ++i) w->order[w->start[w->parent[i] = pvs__uf_find(w->parent, i)]++] = i;
}

/* Component `comp`'s boundary (edges of odd use count) into w->edges, returning their count; its vertices into
   w->uv[0 .. *nuv). */
PVS__STATIC uint32_t pvs__ep_component_boundary(pvs__epprepwork *w, const uint32_t *tl, uint32_t n, uint32_t comp,
												uint32_t *nuv) {
	uint32_t j, k, ne = 0, nb = 0;
	for (j = 0; j < n; ++j)
		for (k = 0; k < 3; ++k) {
			uint32_t x = w->canon[3 * tl[j] + k], y = w->canon[3 * tl[j] + (k + 1) % 3];
			if (x == y) continue;
			w->edges[ne++] = x < y ? ((uint64_t)x << 32) | y : ((uint64_t)y << 32) | x;
		}
	PVS_QSORT(w->edges, ne, sizeof(uint64_t), pvs__ep_u64_cmp);
	for (j = 0; j < ne;) {
		uint32_t m = j;
		while (m < ne && w->edges[m] == w->edges[j]) ++m;
		if ((m - j) & 1u) w->edges[nb++] = w->edges[j]; /* compacted in place: nb <= j */
		j = m;
	}
	*nuv = 0;
	for (j = 0; j < n; ++j)
		for (k = 0; k < 3; ++k) {
			uint32_t v = w->canon[3 * tl[j] + k];
			if (w->mark[v] != comp) { w->mark[v] = comp; w->uv[(*nuv)++] = v; }
		}
	return nb;
}

/* The component's triangles as planar occluders: merged groups, then consecutive coplanar pairs forming convex quads,
   then lone triangles of non-zero area. */
PVS__STATIC pvs_result pvs__ep_add_polygons(pvs__extproj_prep *p, const pvs_scene *s, uint32_t t0, const uint32_t *tl,
											uint32_t n, pvs__epprepwork *w) {
	uint32_t j, k;
	pvs_result r = pvs__ep_merge_planar(p, s, t0, tl, n, w);
	if (r != PVS_OK) return r;
	for (j = 0; j < n; ++j) {
		const float *tri[3], *nxt[3], *q[4];
		double nrm[3];
		if (w->used[j]) continue;
		for (k = 0; k < 3; ++k) tri[k] = s->positions + 3 * (size_t)s->indices[3 * (size_t)(t0 + tl[j]) + k];
		if (!(pvs__ep_tri_normal(tri[0], tri[1], tri[2], nrm) > 0.0)) continue;
		if (j + 1 < n && !w->used[j + 1]) {
			double slack;
			for (k = 0; k < 3; ++k) nxt[k] = s->positions + 3 * (size_t)s->indices[3 * (size_t)(t0 + tl[j + 1]) + k];
			if (pvs__ep_quad(tri, nxt, q, &slack)) {
				pvs__ep_add(p, q, 4, 0, slack);
				++j;
				continue;
			}
		}
		pvs__ep_add(p, tri, 3, 0, 0.0);
	}
	return PVS_OK;
}

/* Keeps a closed or capped component for slicing (§3.3): triangles, box and, if capped, boundary edges and cap
   plane. */
PVS__STATIC pvs_result pvs__ep_add_slice(pvs__extproj_prep *p, const pvs_scene *s, uint32_t t0, const uint32_t *tl,
										 uint32_t n, const pvs__epprepwork *w, const uint32_t *bnd, uint32_t nb,
										 int capped, int cap_axis, int cap_side, float cap_value) {
	const pvs_allocator *a = &p->allocator;
	pvs__epslice *sl;
	pvs_result r = PVS_OK;
	uint32_t j, k;
	p->slc = (pvs__epslice *)pvs__grow_array(a, p->slc, &p->slc_capacity, p->slc_count, p->slc_count + 1,
											 sizeof(pvs__epslice), &r);
	if (!p->slc) return r;
	p->stri = (uint32_t *)pvs__grow_array(a, p->stri, &p->stri_capacity, p->stri_count, p->stri_count + n,
										  sizeof(uint32_t), &r);
	if (!p->stri) return r;
	if (capped) {
		/* pvs__grow_array counts elements of 6 floats */
		p->bedge = (float *)pvs__grow_array(a, p->bedge, &p->bedge_capacity, p->bedge_count, p->bedge_count + nb,
											6 * sizeof(float), &r);
		if (!p->bedge) return r;
	}
	sl = p->slc + p->slc_count++;
	memset(sl, 0, sizeof(*sl));
	sl->box = pvs__box_empty();
	sl->first = (uint32_t)p->stri_count;
	sl->count = n;
	for (j = 0; j < n; ++j) {
		p->stri[p->stri_count++] = t0 + tl[j];
		for (k = 0; k < 3; ++k)
			pvs__box_add_point(&sl->box, s->positions + 3 * (size_t)s->indices[3 * (size_t)(t0 + tl[j]) + k]);
	}
	sl->capped = capped;
	if (capped) {
		sl->bfirst = (uint32_t)p->bedge_count;
		sl->bcount = nb;
		for (j = 0; j < nb; ++j) {
			memcpy(p->bedge + 6 * p->bedge_count, w->vpos[bnd[2 * j]], 3 * sizeof(float));
			memcpy(p->bedge + 6 * p->bedge_count + 3, w->vpos[bnd[2 * j + 1]], 3 * sizeof(float));
			++p->bedge_count;
		}
		sl->cap_axis = cap_axis;
		sl->cap_side = cap_side;
		sl->cap_value = cap_value;
	}
	if (sl->count + sl->bcount > p->max_slice_segments) p->max_slice_segments = sl->count + sl->bcount;
	return PVS_OK;
}

/* One component (triangles tl[0 .. n), root `comp`): closed and convex, a solid (capped: only for cells on the cap's
   solid side); else its polygons, kept for slicing if closed or capped. */
PVS__STATIC pvs_result pvs__ep_prepare_component(pvs__extproj_prep *p, const pvs_scene *s, uint32_t t0,
												 const uint32_t *tl, uint32_t n, uint32_t comp, uint32_t tn,
												 pvs__epprepwork *w) {
	uint32_t nuv, j, k, closed, *bnd = w->owner; /* owner is done with */
	uint32_t nb = pvs__ep_component_boundary(w, tl, n, comp, &nuv), tris_local[2 * PVS__EP_MAXP];
	int capped = 0, cap_axis = 0, cap_side = 0;
	float cap_value = 0.0f;
	pvs_result r;
	closed = nb == 0;
	if (!closed && 2 * nb <= 3 * tn) {
		for (j = 0; j < nb; ++j) {
			bnd[2 * j] = (uint32_t)(w->edges[j] >> 32);
			bnd[2 * j + 1] = (uint32_t)(w->edges[j] & 0xffffffffu);
		}
		capped = pvs__ep_cap_axis(w->vpos, bnd, nb, w->uv, nuv, &cap_axis, &cap_value, &cap_side);
	}
	if (closed || capped) {
		/* a flat closed or capped mesh bounds no volume */
		const float **vq = (const float **)w->ref; /* ref is done with: room for 3 tn pointers */
		uint32_t *tt = w->gparent;                 /* not in use until the polygons */
		for (j = 0; j < nuv; ++j) vq[j] = w->vpos[w->uv[j]];
		for (j = 0; j < n; ++j) tt[j] = t0 + tl[j];
		if (pvs__ep_flat_component(s, tt, n, vq, nuv)) closed = capped = 0;
	}
	if ((closed || capped) && nuv >= 4 && nuv <= PVS__EP_MAXP && n <= 2 * PVS__EP_MAXP) {
		/* a capped solid serves only cells strictly on its side of the cap: a ray from there crosses the cap's plane
		   once, going away, so it meets the hull (cap included) first on a real face */
		const float *q[PVS__EP_MAXP];
		double slack;
		for (j = 0; j < n; ++j) tris_local[j] = t0 + tl[j];
		for (j = 0; j < nuv; ++j) q[j] = w->vpos[w->uv[j]];
		if (pvs__ep_convex_component(s, tris_local, n, q, nuv, &slack)) {
			pvs__epocc *o = p->occ + p->occ_count;
			pvs__ep_add(p, q, nuv, 1, slack);
			if (capped) {
				o->cap_side = cap_side;
				o->cap_axis = cap_axis;
				o->cap_value = cap_value;
			}
			return PVS_OK;
		}
	}
	r = pvs__ep_add_polygons(p, s, t0, tl, n, w);
	if (r != PVS_OK || n < 4) return r;
	for (j = 0; j < n; ++j) { /* a zero-area triangle blocks no ray: not sliced */
		const float *c3[3];
		double nrm[3];
		for (k = 0; k < 3; ++k) c3[k] = s->positions + 3 * (size_t)s->indices[3 * (size_t)(t0 + tl[j]) + k];
		if (!(pvs__ep_tri_normal(c3[0], c3[1], c3[2], nrm) > 0.0)) break;
	}
	if (j < n || (!closed && !capped)) return PVS_OK;
	return pvs__ep_add_slice(p, s, t0, tl, n, w, bnd, nb, capped, cap_axis, cap_side, cap_value);
}

/* Prepares one object's triangles t0 .. t0 + tn, component by component. */
PVS__STATIC pvs_result pvs__ep_prepare_object(pvs__extproj_prep *p, const pvs_scene *s, uint32_t t0, uint32_t tn,
											  pvs__epprepwork *w) {
	uint32_t comp;
	pvs__ep_components(s, t0, tn, w);
	/* start[root] holds the component's end; components are the roots in order */
	for (comp = 0; comp < tn; ++comp) {
		uint32_t begin, end;
		pvs_result r;
		if (w->parent[comp] != comp) continue;
		end = w->start[comp];
		begin = end;
		while (begin > 0 && w->parent[w->order[begin - 1]] == comp) --begin;
		r = pvs__ep_prepare_component(p, s, t0, w->order + begin, end - begin, comp, tn, w);
		if (r != PVS_OK) return r;
	}
	return PVS_OK;
}

/* ---- sheets (grounds, floors) and occluders extended through them ---- */

typedef struct pvs__epskey {
	float value;
	uint32_t axis, tri;
} pvs__epskey;

PVS__STATIC int pvs__ep_skey_cmp(const void *a, const void *b) {
	const pvs__epskey *x = (const pvs__epskey *)a, *y = (const pvs__epskey *)b;
	if (x->axis != y->axis) return x->axis < y->axis ? -1 : 1;
	if (x->value != y->value) return x->value < y->value ? -1 : 1;
	return x->tri < y->tri ? -1 : x->tri > y->tri;
}

/* The first axis on which triangle t is flat, or -1. */
PVS__STATIC int pvs__ep_flat_axis(const pvs_scene *s, uint32_t t) {
	const uint32_t *ix = s->indices + 3 * (size_t)t;
	const float *v0 = s->positions + 3 * (size_t)ix[0], *v1 = s->positions + 3 * (size_t)ix[1],
				*v2 = s->positions + 3 * (size_t)ix[2];
	int k;
	for (k = 0; k < 3; ++k)
		if (v0[k] == v1[k] && v1[k] == v2[k]) return k;
	return -1;
}

/* Scratch of the sheets' search: `cap` edges (3 per triangle of one plane). */
typedef struct pvs__epsheetwork {
	pvs__epedge2 *e;      /* cap */
	float *q;             /* 2 (cap + 1): a piece's polygon */
	unsigned char *keep;  /* cap + 1 */
	pvs__epend *ends;     /* 2 cap */
	uint32_t *uf;         /* cap: pieces (union-find over the group's triangles) */
	double *tarea;        /* cap: area per triangle, then per piece at its root */
	size_t cap;
} pvs__epsheetwork;

PVS__STATIC void pvs__ep_sheetwork_free(const pvs_allocator *a, pvs__epsheetwork *w) {
	pvs__free_array(a, w->e, w->cap, sizeof(pvs__epedge2));
	pvs__free_array(a, w->q, 2 * (w->cap + 1), sizeof(float));
	pvs__free_array(a, w->keep, w->cap + 1, 1);
	pvs__free_array(a, w->ends, 2 * w->cap, sizeof(pvs__epend));
	pvs__free_array(a, w->uf, w->cap, sizeof(uint32_t));
	pvs__free_array(a, w->tarea, w->cap, sizeof(double));
}

/* Grows the scratch to `cap` edges; 0 when out of memory (what was allocated stays in w). */
PVS__STATIC int pvs__ep_sheetwork_reserve(const pvs_allocator *a, pvs__epsheetwork *w, size_t cap) {
	if (cap <= w->cap) return 1;
	pvs__ep_sheetwork_free(a, w);
	w->cap = cap;
	w->e = (pvs__epedge2 *)pvs__alloc_array(a, cap, sizeof(pvs__epedge2));
	w->q = (float *)pvs__alloc_array(a, 2 * (cap + 1), sizeof(float));
	w->keep = (unsigned char *)pvs__alloc_array(a, cap + 1, 1);
	w->ends = (pvs__epend *)pvs__alloc_array(a, 2 * cap, sizeof(pvs__epend));
	w->uf = (uint32_t *)pvs__alloc_array(a, cap, sizeof(uint32_t));
	w->tarea = (double *)pvs__alloc_array(a, cap, sizeof(double));
	return w->e && w->q && w->keep && w->ends && w->uf && w->tarea;
}

/* Keeps sheet polygon q (m vertices, plane x_axis = value) if among the PVS__EP_MAX_SHEETS largest. */
PVS__STATIC pvs_result pvs__ep_keep_sheet(pvs__extproj_prep *p, int axis, float value, const float *q, uint32_t m,
										  double area) {
	pvs_result r = PVS_OK;
	uint32_t slot;
	if (p->sheet_count < PVS__EP_MAX_SHEETS) slot = p->sheet_count++;
	else {
		uint32_t x;
		slot = 0;
		for (x = 1; x < p->sheet_count; ++x)
			if (p->sheet[x].area < p->sheet[slot].area) slot = x;
		if (!(area > p->sheet[slot].area)) return PVS_OK;
	}
	p->spoly = (float *)pvs__grow_array(&p->allocator, p->spoly, &p->spoly_capacity, p->spoly_count, p->spoly_count + m,
										2 * sizeof(float), &r);
	if (!p->spoly) return r;
	p->sheet[slot].axis = axis;
	p->sheet[slot].value = value;
	p->sheet[slot].first = (uint32_t)p->spoly_count;
	p->sheet[slot].count = m;
	p->sheet[slot].area = area;
	memcpy(p->spoly + 2 * p->spoly_count, q, 2 * (size_t)m * sizeof(float));
	p->spoly_count += m;
	return PVS_OK;
}

/* Sheets among n >= 2 triangles in one axis-aligned plane: edge-joined pieces (a lamp's base on the ground is its own)
   forming one convex polygon. */
PVS__STATIC pvs_result pvs__ep_sheet_group(pvs__extproj_prep *p, const pvs_scene *s, const pvs__epskey *key, size_t n,
										   pvs__epsheetwork *w) {
	int k = (int)key[0].axis, u = (k + 1) % 3, v = (k + 2) % 3;
	uint32_t ne = (uint32_t)(3 * n), m;
	pvs__epedge2 *e;
	size_t g;
	pvs_result r;
	if (!pvs__ep_sheetwork_reserve(&p->allocator, w, 3 * n)) return PVS_ERROR_OUT_OF_MEMORY;
	e = w->e;
	for (g = 0; g < n; ++g) {
		const uint32_t *ix = s->indices + 3 * (size_t)key[g].tri;
		const float *c[3];
		int l;
		for (l = 0; l < 3; ++l) c[l] = s->positions + 3 * (size_t)ix[l];
		w->tarea[g] = 0.5 *
			pvs__dabs(((double)c[1][u] - c[0][u]) * ((double)c[2][v] - c[0][v]) -
					  ((double)c[2][u] - c[0][u]) * ((double)c[1][v] - c[0][v]));
		w->uf[g] = (uint32_t)g;
		for (l = 0; l < 3; ++l) {
			const float *x = c[l], *y = c[(l + 1) % 3];
			float A[2], B[2];
			pvs__epedge2 *ed = e + 3 * g + (size_t)l;
			A[0] = x[u]; A[1] = x[v];
			B[0] = y[u]; B[1] = y[v];
			if (pvs__ep_p2_cmp(A, B) <= 0) { memcpy(ed->a, A, sizeof(A)); memcpy(ed->b, B, sizeof(B)); }
			else { memcpy(ed->a, B, sizeof(B)); memcpy(ed->b, A, sizeof(A)); }
			ed->tri = (uint32_t)g;
		}
	}
	PVS_QSORT(e, ne, sizeof(pvs__epedge2), pvs__ep_edge2_cmp);
	for (g = 1; g < ne; ++g)
		if (pvs__ep_edge2_cmp(e + g, e + g - 1) == 0) {
			uint32_t x = pvs__uf_find(w->uf, e[g].tri), y = pvs__uf_find(w->uf, e[g - 1].tri);
			if (x != y) w->uf[x > y ? x : y] = x < y ? x : y;
		}
	for (g = 0; g < ne; ++g) e[g].tri = pvs__uf_find(w->uf, e[g].tri);
	for (g = 0; g < n; ++g)
		if (w->uf[g] != g) {
			w->tarea[pvs__uf_find(w->uf, (uint32_t)g)] += w->tarea[g];
			w->tarea[g] = 0.0;
		}
	PVS_QSORT(e, ne, sizeof(pvs__epedge2), pvs__ep_edge2_root_cmp);
	for (g = 0; g < ne;) {
		size_t h = g;
		uint32_t root = e[g].tri;
		double area;
		while (h < ne && e[h].tri == root) ++h;
		area = w->tarea[root];
		m = pvs__ep_sheet_polygon(e + g, (uint32_t)(h - g), area, w->q, w->keep, (uint32_t)w->cap, w->ends, 0.0, NULL,
								  NULL, 0, NULL);
		g = h;
		if (!m) continue;
		r = pvs__ep_keep_sheet(p, k, key[0].value, w->q, m, area);
		if (r != PVS_OK) return r;
	}
	return PVS_OK;
}

/* 1 when convex occluder oc stands on sheet S: *on vertices exactly in its plane inside its polygon, the rest on one
   side (*above), each exactly over one of those or inside their hull; not concave, <= PVS__EP_MAXP points once
   extended. */
PVS__STATIC int pvs__ep_stands_on(const pvs__extproj_prep *p, const pvs__epocc *oc, const pvs__epsheet *S, uint32_t *on,
								  int *above) {
	const float *pts = p->pts + 3 * (size_t)oc->first, *poly = p->spoly + 2 * (size_t)S->first;
	int k = S->axis, u = (k + 1) % 3, v = (k + 2) % 3, below = 0, ok = 1, hn;
	double fp[PVS__EP_MAXP][2], fh[PVS__EP_MAXP + 1][2];
	float fpoly[2 * PVS__EP_MAXP];
	uint32_t x, y, nf = 0;
	*on = 0;
	*above = 0;
	for (x = 0; x < oc->count; ++x) {
		float c = pts[3 * x + k];
		*on += c == S->value;
		*above |= c > S->value;
		below |= c < S->value;
	}
	if (!*on || *above == below || oc->count + *on > PVS__EP_MAXP || oc->ecount) return 0;
	for (x = 0; x < oc->count; ++x)
		if (pts[3 * x + k] == S->value) { fp[nf][0] = pts[3 * x + u]; fp[nf][1] = pts[3 * x + v]; ++nf; }
	hn = nf >= 3 ? pvs__ep_hull(fp, (int)nf, fh) : 0;
	for (y = 0; y < (uint32_t)hn; ++y) { fpoly[2 * y] = (float)fh[y][0]; fpoly[2 * y + 1] = (float)fh[y][1]; }
	for (x = 0; x < oc->count && ok; ++x) {
		const float *P = pts + 3 * x;
		if (P[k] == S->value) ok = pvs__ep_in_convex(poly, S->count, P[u], P[v]);
		else {
			for (y = 0; y < oc->count; ++y)
				if (pts[3 * y + k] == S->value && pts[3 * y + u] == P[u] && pts[3 * y + v] == P[v]) break;
			ok = y < oc->count || (hn >= 3 && pvs__ep_in_convex(fpoly, (uint32_t)hn, P[u], P[v]));
		}
	}
	return ok;
}

/* oc's extended point set: its points plus its `on` points in sheet sh's plane pushed through it by D, away from
   `above`. */
PVS__STATIC pvs_result pvs__ep_extend(pvs__extproj_prep *p, pvs__epocc *oc, uint32_t sh, uint32_t on, int above,
									  double D) {
	const pvs__epsheet *S = p->sheet + sh;
	const float *pts;
	pvs_result r = PVS_OK;
	int k = S->axis;
	uint32_t x;
	p->pts = (float *)pvs__grow_array(&p->allocator, p->pts, &p->pt_capacity, p->pt_count, p->pt_count + oc->count + on,
									  3 * sizeof(float), &r);
	if (!p->pts) return r;
	pts = p->pts + 3 * (size_t)oc->first;
	oc->xfirst = (uint32_t)p->pt_count;
	memcpy(p->pts + 3 * p->pt_count, pts, 3 * sizeof(float) * oc->count);
	p->pt_count += oc->count;
	for (x = 0; x < oc->count; ++x) {
		float *P;
		if (pts[3 * x + k] != S->value) continue;
		P = p->pts + 3 * p->pt_count++;
		memcpy(P, pts + 3 * x, 3 * sizeof(float));
		P[k] = (float)(above ? (double)S->value - D : (double)S->value + D);
	}
	oc->xcount = oc->count + on;
	oc->sheet = sh;
	oc->xside = above ? 1 : -1;
	return PVS_OK;
}

/* Finds the largest sheets and extends through them, by the scene's size, the occluders standing on them: the prism
   under the footprint keeps the occluder convex and lies in the sheet's solid half-space, so from a cell over the sheet
   on its side it blocks nothing new, and closes the wall-ground seam the two Projections leave open. */
PVS__STATIC pvs_result pvs__ep_sheets(pvs__extproj_prep *p, const pvs_scene *s) {
	const pvs_allocator *a = &p->allocator;
	pvs__epskey *key = NULL;
	pvs__epsheetwork w;
	size_t nkey = 0, i;
	uint32_t t, o;
	pvs_result r = PVS_OK;
	double D;
	for (t = 0; t < s->triangle_count; ++t) nkey += pvs__ep_flat_axis(s, t) >= 0;
	if (!nkey) return PVS_OK;
	key = (pvs__epskey *)pvs__alloc_array(a, nkey, sizeof(pvs__epskey));
	if (!key) return PVS_ERROR_OUT_OF_MEMORY;
	memset(&w, 0, sizeof(w));
	nkey = 0;
	for (t = 0; t < s->triangle_count; ++t) {
		const uint32_t *ix = s->indices + 3 * (size_t)t;
		const float *v0 = s->positions + 3 * (size_t)ix[0], *v1 = s->positions + 3 * (size_t)ix[1],
					*v2 = s->positions + 3 * (size_t)ix[2];
		int k;
		double n[3];
		if (!(pvs__ep_tri_normal(v0, v1, v2, n) > 0.0)) continue;
		k = pvs__ep_flat_axis(s, t);
		if (k < 0) continue;
		key[nkey].value = v0[k] == 0.0f ? 0.0f : v0[k]; /* -0 and +0 group together */
		key[nkey].axis = (uint32_t)k;
		key[nkey].tri = t;
		++nkey;
	}
	PVS_QSORT(key, nkey, sizeof(pvs__epskey), pvs__ep_skey_cmp);
	for (i = 0; i < nkey;) {
		size_t j = i;
		while (j < nkey && key[j].axis == key[i].axis && key[j].value == key[i].value) ++j;
		if (j - i >= 2) {
			r = pvs__ep_sheet_group(p, s, key + i, j - i, &w);
			if (r != PVS_OK) goto done;
		}
		i = j;
	}
	D = 0.0;
	for (t = 0; t < 3; ++t) D = pvs__dmax(D, 2.0 * ((double)s->bounds.max[t] - s->bounds.min[t]) + 1.0);
	for (o = 0; o < p->occ_count; ++o) {
		pvs__epocc *oc = p->occ + o;
		uint32_t sh;
		for (sh = 0; sh < p->sheet_count && !oc->xcount; ++sh) {
			uint32_t on;
			int above;
			if (!pvs__ep_stands_on(p, oc, p->sheet + sh, &on, &above)) continue;
			r = pvs__ep_extend(p, oc, sh, on, above, D);
			if (r != PVS_OK) goto done;
		}
	}
done:
	pvs__free_array(a, key, nkey, sizeof(pvs__epskey));
	pvs__ep_sheetwork_free(a, &w);
	return r;
}

/* An occluder's size class: area bound < 4^c (the last class open-ended). */
PVS__STATIC int pvs__ep_area_class(float area) {
	int c = 0;
	float lim = 1.0f;
	while (c + 1 < PVS__EP_AREA_CLASSES && !(area < lim)) {
		++c;
		lim *= 4.0f;
	}
	return c;
}

/* The occluders of the scene's triangles, object by object, tagged with it. */
PVS__STATIC pvs_result pvs__ep_prepare_meshes(pvs__extproj_prep *p, const pvs_scene *s, pvs__epprepwork *w) {
	uint32_t t;
	for (t = 0; t < s->triangle_count;) {
		uint32_t end = t + 1;
		size_t first = p->occ_count, q;
		pvs_result r;
		while (end < s->triangle_count && s->triangle_object[end] == s->triangle_object[t]) ++end;
		r = pvs__ep_prepare_object(p, s, t, end - t, w);
		for (q = first; q < p->occ_count; ++q) p->occ[q].object = s->triangle_object[t];
		if (r != PVS_OK) return r;
		t = end;
	}
	return PVS_OK;
}

/* The scene's volumes: a BOX is a convex solid, an EXTRUSION's walls quads; CONVEX ones are left out (conservative). */
PVS__STATIC void pvs__ep_prepare_volumes(pvs__extproj_prep *p, const pvs_scene *s) {
	uint32_t o, i;
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
			pvs__ep_add(p, q, 8, 1, 0.0);
		} else if (d->kind == PVS_OCCLUDER_EXTRUSION) {
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
				pvs__ep_add(p, q, 4, 0, 0.0);
			}
		}
	}
}

/* Per size class: the occluders, the largest area and a kD-tree of the boxes (§6.1's sweeps). */
PVS__STATIC pvs_result pvs__ep_class_trees(pvs__extproj_prep *p, pvs_error *err) {
	const pvs_allocator *a = &p->allocator;
	pvs_kdtree_desc kd;
	pvs_box *boxes = (pvs_box *)pvs__alloc_array(a, p->occ_count + 1, sizeof(pvs_box));
	pvs_result r = PVS_OK;
	size_t q;
	int c;
	if (!boxes) return PVS_ERROR_OUT_OF_MEMORY;
	for (q = 0; q < p->occ_count; ++q) ++p->class_count[pvs__ep_area_class(p->occ[q].area)];
	for (c = 0; c < PVS__EP_AREA_CLASSES; ++c) {
		uint32_t m = 0;
		p->class_occ[c] = (uint32_t *)pvs__alloc_array(a, (size_t)p->class_count[c] + 1, sizeof(uint32_t));
		if (!p->class_occ[c]) r = PVS_ERROR_OUT_OF_MEMORY;
		for (q = 0; q < p->occ_count && r == PVS_OK; ++q)
			if (pvs__ep_area_class(p->occ[q].area) == c) {
				p->class_occ[c][m] = (uint32_t)q;
				boxes[m++] = p->occ[q].box;
				if (p->occ[q].area > p->class_area[c]) p->class_area[c] = p->occ[q].area;
			}
		if (r != PVS_OK) break;
		memset(&kd, 0, sizeof(kd));
		kd.boxes = boxes;
		kd.count = m;
		kd.allocator = *a;
		r = pvs_kdtree_create(&kd, &p->occ_tree[c], err);
		if (r != PVS_OK) break;
	}
	pvs__free_array(a, boxes, p->occ_count + 1, sizeof(pvs_box));
	return r;
}

/* Builds the occluder list of a scene (§6.1 picks among it per cell). */
PVS__STATIC pvs_result pvs__extproj_prepare(const pvs_scene *s, const pvs_allocator *a, pvs__extproj_prep **out,
											pvs_error *err) {
	pvs__extproj_prep *p;
	pvs__epprepwork w;
	size_t occ_cap = (size_t)s->triangle_count + 1, pt_cap = 3 * (size_t)s->triangle_count + 1, most = 1;
	uint32_t t, i;
	pvs_result r;
	*out = NULL;
	memset(&w, 0, sizeof(w)); /* freed below even when its allocation is never tried */
	for (i = 0; i < s->occluder_count; ++i) {
		const pvs_occluder_desc *d = s->occluders + i;
		if (d->kind == PVS_OCCLUDER_BOX) { occ_cap += 1; pt_cap += 8; }
		if (d->kind == PVS_OCCLUDER_EXTRUSION) {
			occ_cap += d->footprint_count;
			pt_cap += 4 * (size_t)d->footprint_count;
		}
	}
	if (occ_cap > 0xffffffffu || pt_cap > 0xffffffffu)
		return pvs__fail(err, PVS_ERROR_COUNT_OVERFLOW, -1, 0, "extproj: too many occluders");
	p = (pvs__extproj_prep *)pvs__alloc(a, sizeof(*p), 16);
	if (!p) return pvs__fail(err, PVS_ERROR_OUT_OF_MEMORY, -1, 0, "extproj occluders");
	memset(p, 0, sizeof(*p));
	p->allocator = *a;
	p->occ_capacity = occ_cap;
	p->pt_capacity = pt_cap;
	p->occ = (pvs__epocc *)pvs__alloc_array(a, occ_cap, sizeof(pvs__epocc));
	p->pts = (float *)pvs__alloc_array(a, pt_cap * 3, sizeof(float));
	for (t = 0; t < s->triangle_count;) { /* the largest object (or run of triangles in no object) */
		uint32_t end = t + 1;
		while (end < s->triangle_count && s->triangle_object[end] == s->triangle_object[t]) ++end;
		if (end - t > most) most = end - t;
		t = end;
	}
	if (!p->occ || !p->pts || !pvs__ep_work_alloc(a, &w, most)) {
		pvs__ep_work_free(a, &w);
		pvs__extproj_prep_destroy(p);
		return pvs__fail(err, PVS_ERROR_OUT_OF_MEMORY, -1, 0, "extproj occluders (%llu)", (unsigned long long)occ_cap);
	}
	r = pvs__ep_prepare_meshes(p, s, &w);
	pvs__ep_work_free(a, &w);
	if (r != PVS_OK) {
		pvs__extproj_prep_destroy(p);
		return pvs__fail(err, r, -1, 0, "extproj: slices of the closed meshes");
	}
	pvs__ep_prepare_volumes(p, s);
	r = pvs__ep_sheets(p, s);
	if (r != PVS_OK) {
		pvs__extproj_prep_destroy(p);
		return pvs__fail(err, r, -1, 0, "extproj: sheets");
	}
	r = pvs__ep_class_trees(p, err);
	if (r != PVS_OK) {
		pvs__extproj_prep_destroy(p);
		return pvs__fail(err, r, -1, 0, "extproj: occluder trees");
	}
	*out = p;
	return PVS_OK;
}

/* ---- slices of closed meshes (§3.3) ---- */

/* The slicer's per-cell scratch: segments (x0, y0, x1, y1 in pixels), crossings, a row. */
typedef struct pvs__epslicer {
	double *seg;
	double *xs;
	unsigned char *row;
	unsigned char *cmark;    /* res * res (no map or mask is larger): the penumbra of a concave occluder's boundary */
	size_t cap;          /* segments */
	uint32_t width;      /* row buffer: the longest side of a map or mask */
} pvs__epslicer;

/* Edge-end order for pvs__ep_cross: fixed by position, so both triangles of an edge get the same crossing and the
   section closes. */
PVS__STATIC int pvs__ep_vref_cmp_pts(const float *a, const float *b) {
	int k;
	for (k = 0; k < 3; ++k)
		if (a[k] != b[k]) return a[k] < b[k] ? -1 : 1;
	return 0;
}

PVS__STATIC void pvs__ep_cross(const pvs__epframe *f, const float *a, const float *b, double *x, double *y,
							   double *mag) {
	const float *p = a, *q = b;
	double wp, wq, t, u, v;
	if (pvs__ep_vref_cmp_pts(a, b) > 0) { p = b; q = a; }
	wp = f->s * ((double)p[f->a] - f->face);
	wq = f->s * ((double)q[f->a] - f->face);
	t = (f->W - wp) / (wq - wp);
	u = p[f->u] + ((double)q[f->u] - p[f->u]) * t;
	v = p[f->v] + ((double)q[f->v] - p[f->v]) * t;
	*x = (u - f->u0) * f->su;
	*y = (v - f->v0) * f->sv;
	*mag = pvs__dmax(*mag,
					 (pvs__dabs(p[f->u]) + pvs__dabs(q[f->u]) + pvs__dabs(f->u0)) * f->su +
						 (pvs__dabs(p[f->v]) + pvs__dabs(q[f->v]) + pvs__dabs(f->v0)) * f->sv);
}

PVS__STATIC int pvs__ep_double_cmp(const void *a, const void *b) {
	double x = *(const double *)a, y = *(const double *)b;
	return x < y ? -1 : x > y;
}

/* Component c's section by w = W: a segment (pixels) per crossing triangle into sc->seg from nseg on; vertices on the
   plane count as beyond it; *mag grows to the points' size. Returns the new count. */
PVS__STATIC uint32_t pvs__ep_section_tris(const pvs_scene *s, const pvs__extproj_prep *p, const pvs__epslice *c,
										  const pvs__epframe *f, pvs__epslicer *sc, uint32_t nseg, double *mag) {
	uint32_t i;
	for (i = 0; i < c->count; ++i) {
		const uint32_t *ix = s->indices + 3 * (size_t)p->stri[c->first + i];
		const float *v[3];
		int k, far[3], nf = 0;
		double pt[2][2];
		int np = 0;
		for (k = 0; k < 3; ++k) {
			v[k] = s->positions + 3 * (size_t)ix[k];
			far[k] = f->s * ((double)v[k][f->a] - f->face) >= f->W;
			nf += far[k];
		}
		if (nf == 0 || nf == 3) continue;
		for (k = 0; k < 3; ++k) {
			int l = (k + 1) % 3;
			if (far[k] == far[l]) continue;
			pvs__ep_cross(f, far[k] ? v[l] : v[k], far[k] ? v[k] : v[l], &pt[np][0], &pt[np][1], mag);
			++np;
		}
		sc->seg[4 * nseg] = pt[0][0];
		sc->seg[4 * nseg + 1] = pt[0][1];
		sc->seg[4 * nseg + 2] = pt[1][0];
		sc->seg[4 * nseg + 3] = pt[1][1];
		++nseg;
	}
	return nseg;
}

/* The cap's section by w = W: boundary edges crossing the plane give points on one line, paired in order into segments
   from nseg on. Returns the new count, or 0xffffffff for an odd count (never when closed). */
PVS__STATIC uint32_t pvs__ep_section_cap(const pvs__extproj_prep *p, const pvs__epslice *c, const pvs__epframe *f,
										 pvs__epslicer *sc, uint32_t nseg, double *mag) {
	double *pts = sc->xs;
	uint32_t i, ncap = 0, x, y;
	int key;
	for (i = 0; i < c->bcount; ++i) {
		const float *a = p->bedge + 6 * (size_t)(c->bfirst + i), *b = a + 3;
		int fa = f->s * ((double)a[f->a] - f->face) >= f->W, fb = f->s * ((double)b[f->a] - f->face) >= f->W;
		if (fa == fb) continue;
		pvs__ep_cross(f, fa ? b : a, fa ? a : b, &pts[2 * ncap], &pts[2 * ncap + 1], mag);
		++ncap;
	}
	if (ncap & 1u) return 0xffffffffu;
	/* the line runs along u or v: the cap is axis-aligned, the plane across another axis */
	key = c->cap_axis == f->u ? 1 : 0; /* the cap fixes u: the line runs along v */
	for (x = 1; x < ncap; ++x) /* insertion sort by the running coordinate */
		for (y = x; y > 0 && pts[2 * y + key] < pts[2 * (y - 1) + key]; --y) {
			double t0 = pts[2 * y], t1 = pts[2 * y + 1];
			pts[2 * y] = pts[2 * (y - 1)];
			pts[2 * y + 1] = pts[2 * (y - 1) + 1];
			pts[2 * (y - 1)] = t0;
			pts[2 * (y - 1) + 1] = t1;
		}
	for (x = 0; x + 1 < ncap; x += 2) {
		sc->seg[4 * nseg] = pts[2 * x];
		sc->seg[4 * nseg + 1] = pts[2 * x + 1];
		sc->seg[4 * nseg + 2] = pts[2 * x + 2];
		sc->seg[4 * nseg + 3] = pts[2 * x + 3];
		++nseg;
	}
	return nseg;
}

/* Fills the section's inside: per row the parity spans of its centre line (half-open in y), less pixels a segment
   crosses in the row's band widened by m, get `depth` (where nearer) in map, f->bits in mask (either may be NULL).
   Returns the count. */
PVS__STATIC uint32_t pvs__ep_fill_section(const pvs__epframe *f, pvs__epslicer *sc, uint32_t nseg, double m,
										  float depth, float *map, unsigned char *mask) {
	double ylo = DBL_MAX, yhi = -DBL_MAX;
	int32_t j0, j1, j;
	uint32_t i, written = 0;
	for (i = 0; i < nseg; ++i) {
		ylo = pvs__dmin(ylo, pvs__dmin(sc->seg[4 * i + 1], sc->seg[4 * i + 3]));
		yhi = pvs__dmax(yhi, pvs__dmax(sc->seg[4 * i + 1], sc->seg[4 * i + 3]));
	}
	j0 = pvs__clampi(floor(ylo), 0, (int32_t)f->height);
	j1 = pvs__clampi(ceil(yhi), -1, (int32_t)f->height - 1);
	for (j = j0; j <= j1; ++j) {
		double yc = (double)j + 0.5, b0 = (double)j - m, b1 = (double)j + 1.0 + m;
		uint32_t nx = 0, x;
		for (i = 0; i < nseg; ++i) {
			const double *g = sc->seg + 4 * i;
			if ((g[1] <= yc) != (g[3] <= yc)) sc->xs[nx++] = g[0] + (yc - g[1]) * (g[2] - g[0]) / (g[3] - g[1]);
		}
		if (nx < 2) continue;
		PVS_QSORT(sc->xs, nx, sizeof(double), pvs__ep_double_cmp);
		memset(sc->row, 0, f->width);
		for (i = 0; i < nseg; ++i) {
			const double *g = sc->seg + 4 * i;
			double ya = g[1], yb = g[3], xa = g[0], xb = g[2], ta, tb, xmin, xmax;
			int32_t q0, q1;
			if (pvs__dmax(ya, yb) < b0 || pvs__dmin(ya, yb) > b1) continue;
			if (ya == yb) { ta = 0.0; tb = 1.0; }
			else {
				ta = (b0 - ya) / (yb - ya);
				tb = (b1 - ya) / (yb - ya);
				if (ta > tb) { double t = ta; ta = tb; tb = t; }
				ta = pvs__dmax(ta, 0.0);
				tb = pvs__dmin(tb, 1.0);
			}
			xmin = pvs__dmin(xa + (xb - xa) * ta, xa + (xb - xa) * tb) - m;
			xmax = pvs__dmax(xa + (xb - xa) * ta, xa + (xb - xa) * tb) + m;
			q0 = pvs__clampi(floor(xmin), 0, (int32_t)f->width);
			q1 = pvs__clampi(floor(xmax), -1, (int32_t)f->width - 1);
			if (q0 <= q1) memset(sc->row + q0, 1, (size_t)(q1 - q0 + 1));
		}
		for (x = 0; x + 1 < nx; x += 2) {
			int32_t i0 = pvs__clampi(ceil(sc->xs[x]), 0, (int32_t)f->width),
					i1 = pvs__clampi(floor(sc->xs[x + 1]) - 1.0, -1, (int32_t)f->width - 1), q;
			for (q = i0; q <= i1; ++q) {
				if (sc->row[q]) continue;
				if (map) {
					float *px = map + (size_t)j * f->width + (size_t)q;
					if (*px > depth) *px = depth;
				}
				if (mask) mask[(size_t)j * f->width + (size_t)q] |= f->bits;
				++written;
			}
		}
	}
	return written;
}

/* Rasterizes the section of a closed (or capped) component by the plane w = W (Durand 2000 §3.3): pixels inside by
   parity, at a margin from every segment, get Depth W. Conservative: a cell point V is outside the solid (the cell is
   outside its box), a section point X inside, so V-X crosses the surface an odd number of times, never the cap (both
   lie strictly on its solid side): it hits a triangle nearer than W. Vertices on the plane count as beyond it (symbolic
   perturbation), so segments agree. Returns the pixels written. */
PVS__STATIC uint32_t pvs__ep_slice(const pvs_scene *s, const pvs__extproj_prep *p, const pvs__epslice *c,
								   const pvs__epframe *f, pvs__epslicer *sc, float *map, unsigned char *mask) {
	double mag = 0.0;
	uint32_t nseg = pvs__ep_section_tris(s, p, c, f, sc, 0, &mag);
	if (c->capped) {
		nseg = pvs__ep_section_cap(p, c, f, sc, nseg, &mag);
		if (nseg == 0xffffffffu) return 0;
	}
	if (nseg < 3) return 0;
	/* margin: the points' rounding in pixels, widely bounded */
	return pvs__ep_fill_section(f, sc, nseg, 1e-6 + 1e-12 * mag, pvs__f_up(f->W), map, mask);
}

/* 1 if the component may be sliced for this cell: outside its box, strictly on the cap's solid side. */
PVS__STATIC int pvs__ep_slice_ok(const pvs__epslice *c, const pvs_box *cell) {
	if (pvs__box_overlap(&c->box, cell)) return 0;
	if (c->capped) {
		if (c->cap_side > 0 && !(cell->min[c->cap_axis] > c->cap_value)) return 0;
		if (c->cap_side < 0 && !(cell->max[c->cap_axis] < c->cap_value)) return 0;
	}
	return 1;
}

/* The slice of a sheet's solid half-space (beyond it from the cell, over its polygon): pixels inside by a margin get
   Depth W. */
PVS__STATIC uint32_t pvs__ep_sheet_slice(const pvs__extproj_prep *p, const pvs__epsheet *S, int side,
										 const pvs__epframe *f, float *map, unsigned char *mask) {
	int k = S->axis, su = (k + 1) % 3;
	const float *poly = p->spoly + 2 * (size_t)S->first;
	double pos = f->face + f->s * f->W, lo = DBL_MAX, hi = -DBL_MAX, x0, x1, y0, y1, m, mag;
	int32_t i0, i1, j0, j1, j, i;
	uint32_t written = 0, e;
	float depth = pvs__f_up(f->W);
	if (k == f->a) {
		if (!(side > 0 ? pos < S->value : pos > S->value)) return 0;
		return 0; /* a parallel plane would need a polygon fill; such planes gain little */
	} else {
		/* the polygon's extent along the line x[a] = pos */
		int along = f->a == su ? 0 : 1; /* polygon coordinate index of the plane's axis */
		for (e = 0; e < S->count; ++e) {
			const float *A = poly + 2 * e, *B = poly + 2 * ((e + 1) % S->count);
			double a0 = A[along], a1 = B[along], t, x;
			if ((a0 < pos && a1 < pos) || (a0 > pos && a1 > pos)) continue;
			if (a0 == a1) {
				lo = pvs__dmin(lo, pvs__dmin(A[1 - along], B[1 - along]));
				hi = pvs__dmax(hi, pvs__dmax(A[1 - along], B[1 - along]));
				continue;
			}
			t = (pos - a0) / (a1 - a0);
			x = A[1 - along] + ((double)B[1 - along] - A[1 - along]) * t;
			lo = pvs__dmin(lo, x);
			hi = pvs__dmax(hi, x);
		}
		if (!(hi > lo)) return 0;
		/* to pixels: the sheet's axis k is the plane's u or v, the interval on the other */
		if (f->u == k) {
			double c = (S->value - f->u0) * f->su;
			x0 = side > 0 ? -DBL_MAX : c;
			x1 = side > 0 ? c : DBL_MAX;
			y0 = (lo - f->v0) * f->sv;
			y1 = (hi - f->v0) * f->sv;
		} else {
			double c = (S->value - f->v0) * f->sv;
			y0 = side > 0 ? -DBL_MAX : c;
			y1 = side > 0 ? c : DBL_MAX;
			x0 = (lo - f->u0) * f->su;
			x1 = (hi - f->u0) * f->su;
		}
	}
	mag = (pvs__dabs(lo) + pvs__dabs(hi) + pvs__dabs(S->value) + pvs__dabs(f->u0) + pvs__dabs(f->v0) + pvs__dabs(pos)) *
		(f->su + f->sv);
	m = 1e-6 + 1e-12 * mag;
	i0 = pvs__clampi(ceil(x0 + m), 0, (int32_t)f->width);
	i1 = pvs__clampi(floor(x1 - m) - 1.0, -1, (int32_t)f->width - 1);
	j0 = pvs__clampi(ceil(y0 + m), 0, (int32_t)f->height);
	j1 = pvs__clampi(floor(y1 - m) - 1.0, -1, (int32_t)f->height - 1);
	for (j = j0; j <= j1; ++j) {
		if (i0 > i1) break;
		if (map)
			for (i = i0; i <= i1; ++i) {
				float *px = map + (size_t)j * f->width + (size_t)i;
				if (*px > depth) *px = depth;
			}
		if (mask) pvs__ep_mask_set(mask + (size_t)j * f->width + (size_t)i0, f->bits, (size_t)(i1 - i0 + 1));
		written += (uint32_t)(i1 - i0 + 1);
	}
	return written;
}

/* Slices every component the plane cuts inside its rectangle. */
PVS__STATIC uint32_t pvs__ep_slices(const pvs_scene *s, const pvs__extproj_prep *p, const pvs_box *cell,
									const pvs_extproj_plane *pl, const pvs__epframe *f, pvs__epslicer *sc,
									const int *sheet_side, float *map, unsigned char *mask) {
	uint32_t i, written = 0;
	double pos = f->face + f->s * f->W;
	for (i = 0; i < p->sheet_count; ++i)
		if (sheet_side[i]) written += pvs__ep_sheet_slice(p, p->sheet + i, sheet_side[i], f, map, mask);
	for (i = 0; i < p->slc_count; ++i) {
		const pvs__epslice *c = p->slc + i;
		if (!(c->box.min[f->a] <= pos && c->box.max[f->a] >= pos)) continue;
		if (c->box.max[f->u] < pl->rect[0] || c->box.min[f->u] > pl->rect[2] || c->box.max[f->v] < pl->rect[1] ||
			c->box.min[f->v] > pl->rect[3])
			continue;
		if (!pvs__ep_slice_ok(c, cell)) continue;
		written += pvs__ep_slice(s, p, c, f, sc, map, mask);
	}
	return written;
}

/* ---- concave planar occluders (§3.4) ---- */

/* Clips a concave occluder's boundary (E, n edges) to w >= c (ge) or w <= c: kept edges cut exactly at c, plus the
   clipping line's parts inside P (crossings sorted, paired by parity). E needs room for 1.5 n + 1 edges. Returns the
   new count. */
PVS__STATIC uint32_t pvs__ep_clip_concave(const pvs__epframe *fp, const pvs__epocc *o, double *E, uint32_t n,
										  double cdepth, int ge) {
	const pvs__epframe f = *fp;
	uint32_t nc = 0, nx = 0, q;
	double xs[PVS__EP_CONCAVE_EDGES][4], dir[3], best = 0.0, ea[3] = {0.0, 0.0, 0.0};
	int c;
	if (n > PVS__EP_CONCAVE_EDGES) return 0;
	ea[f.a] = 1.0; /* the clipping line's direction: pn x the axis */
	dir[0] = (double)o->pn[1] * ea[2] - (double)o->pn[2] * ea[1];
	dir[1] = (double)o->pn[2] * ea[0] - (double)o->pn[0] * ea[2];
	dir[2] = (double)o->pn[0] * ea[1] - (double)o->pn[1] * ea[0];
	for (c = 0; c < 3; ++c) best = pvs__dmax(best, pvs__dabs(dir[c]));
	if (!(best > 1e-6)) return 0; /* the plane nearly parallel to the cut: nothing kept */
	for (q = 0; q < n; ++q) { /* in place: the kept edges move down (nc <= q) */
		double A[3], B[3], wa, wb, *out = E + 6 * (size_t)nc;
		int ia, ib;
		for (c = 0; c < 3; ++c) { A[c] = E[6 * (size_t)q + c]; B[c] = E[6 * (size_t)q + 3 + c]; }
		wa = f.s * (A[f.a] - f.face);
		wb = f.s * (B[f.a] - f.face);
		ia = ge ? wa >= cdepth : wa <= cdepth;
		ib = ge ? wb >= cdepth : wb <= cdepth;
		if (!ia && !ib) continue;
		for (c = 0; c < 3; ++c) { out[c] = A[c]; out[3 + c] = B[c]; }
		if (ia != ib) {
			double t = (cdepth - wa) / (wb - wa), *end = ia ? out + 3 : out;
			for (c = 0; c < 3; ++c) end[c] = A[c] + (B[c] - A[c]) * t;
			end[f.a] = f.face + f.s * cdepth;
			for (c = 0; c < 3; ++c) xs[nx][c] = end[c];
			xs[nx][3] = end[0] * dir[0] + end[1] * dir[1] + end[2] * dir[2];
			++nx;
		}
		++nc;
	}
	if (nx & 1u) return 0;
	for (q = 1; q < nx; ++q) { /* the crossings along the line, then paired */
		double tmp[4];
		uint32_t r2 = q;
		memcpy(tmp, xs[q], sizeof(tmp));
		while (r2 > 0 && xs[r2 - 1][3] > tmp[3]) { memcpy(xs[r2], xs[r2 - 1], sizeof(tmp)); --r2; }
		memcpy(xs[r2], tmp, sizeof(tmp));
	}
	for (q = 0; q + 1 < nx; q += 2) {
		double *out = E + 6 * (size_t)nc++;
		for (c = 0; c < 3; ++c) { out[c] = xs[q][c]; out[3 + c] = xs[q + 1][c]; }
	}
	return nc;
}

/* Marks in cmark (rows j0..j1, columns i0..i1) the pixels edge e's penumbra may touch: the hull of its ends' 16 views
   from the corners, widened by rounding and 1e-3 pixel. 0 (all marked) if too far to bound. */
PVS__STATIC int pvs__ep_mark_penumbra(const pvs__epframe *fp, const double *e, double base, unsigned char *cmark,
									  int32_t i0, int32_t i1, int32_t j0, int32_t j1) {
	const pvs__epframe f = *fp;
	double pts[16][2], hull[17][2], err = 0.0, hy0 = DBL_MAX, hy1 = -DBL_MAX;
	int c, k = 0, hn, m;
	int32_t r0, r1, row;
	for (c = 0; c < 8; ++c) {
		double Vu = f.cu[c & 1], Vv = f.cv[(c >> 1) & 1], Vw = f.cw[(c >> 2) & 1];
		int end;
		for (end = 0; end < 2; ++end) {
			const double *x = e + 3 * end;
			double w = f.s * ((double)x[f.a] - f.face), t = (f.W - Vw) / (w - Vw);
			pts[k][0] = (Vu + ((double)x[f.u] - Vu) * t - f.u0) * f.su;
			pts[k][1] = (Vv + ((double)x[f.v] - Vv) * t - f.v0) * f.sv;
			/* rounding: a few ulps of the terms, widely (the ends are exact) */
			err = pvs__dmax(err,
							1e-12 *
								(pvs__dabs(pts[k][0]) + pvs__dabs(pts[k][1]) + base +
								 ((pvs__dabs(Vu) + pvs__dabs((double)x[f.u])) * f.su +
								  (pvs__dabs(Vv) + pvs__dabs((double)x[f.v])) * f.sv) *
									 t));
			++k;
		}
	}
	err += 1e-3; /* to spare for the crossing test (2) */
	for (k = 0; k < 16; ++k) { hy0 = pvs__dmin(hy0, pts[k][1]); hy1 = pvs__dmax(hy1, pts[k][1]); }
	hn = pvs__ep_hull(pts, 16, hull);
	if (!(hy1 - hy0 < 1e9)) { /* too far to bound */
		for (row = j0; row <= j1; ++row) memset(cmark + (size_t)row * f.width + i0, 1, (size_t)(i1 - i0 + 1));
		return 0;
	}
	if (hn < 3) { /* collinear views: their bounding box */
		hn = 0;
		hull[0][0] = hull[3][0] = DBL_MAX; hull[1][0] = hull[2][0] = -DBL_MAX;
		for (k = 0; k < 16; ++k) {
			hull[0][0] = pvs__dmin(hull[0][0], pts[k][0]);
			hull[1][0] = pvs__dmax(hull[1][0], pts[k][0]);
		}
		hull[3][0] = hull[0][0]; hull[2][0] = hull[1][0];
		hull[0][1] = hull[1][1] = hy0;
		hull[2][1] = hull[3][1] = hy1;
		hn = 4;
	}
	r0 = pvs__clampi(floor(hy0 - err), j0 - 1, j1 + 1);
	r1 = pvs__clampi(floor(hy1 + err), j0 - 1, j1 + 1);
	for (row = r0 < j0 ? j0 : r0; row <= r1 && row <= j1; ++row) {
		double y0 = row - err, y1 = row + 1.0 + err, mn = DBL_MAX, mx = -DBL_MAX;
		int32_t x0, x1;
		for (m = 0; m < hn; ++m) {
			const double *a = hull[m], *b = hull[m + 1 < hn ? m + 1 : 0];
			double ta = 0.0, tb = 1.0, dy = b[1] - a[1];
			if (dy != 0.0) {
				double t0 = (y0 - a[1]) / dy, t1 = (y1 - a[1]) / dy;
				if (t0 > t1) { double tt = t0; t0 = t1; t1 = tt; }
				ta = pvs__dmax(ta, t0);
				tb = pvs__dmin(tb, t1);
			} else if (a[1] < y0 || a[1] > y1) continue;
			if (ta > tb) continue;
			mn = pvs__dmin(mn, pvs__dmin(a[0] + (b[0] - a[0]) * ta, a[0] + (b[0] - a[0]) * tb));
			mx = pvs__dmax(mx, pvs__dmax(a[0] + (b[0] - a[0]) * ta, a[0] + (b[0] - a[0]) * tb));
		}
		if (mn > mx) continue;
		x0 = pvs__clampi(floor(mn - err - 1e-9 * (1.0 + pvs__dabs(mn))), i0 - 1, i1 + 1);
		x1 = pvs__clampi(floor(mx + err + 1e-9 * (1.0 + pvs__dabs(mx))), i0 - 1, i1 + 1);
		if (x0 < i0) x0 = i0;
		if (x1 > i1) x1 = i1;
		if (x0 <= x1) memset(cmark + (size_t)row * f.width + x0, 1, (size_t)(x1 - x0 + 1));
	}
	return 1;
}

/* Test (2) for pixel (xm, row): 1 when the line from the cell's centre through the pixel's centre meets o's plane
   before (front) or behind the plane, inside the boundary by parity, farther from it than the slack. */
PVS__STATIC int pvs__ep_crosses_inside(const pvs__epframe *f, const pvs__epocc *o, const double *E, uint32_t n,
									   const double *world0, const double *pn, int pax, int front, double scale,
									   int32_t xm, int32_t row) {
	double X[3], dir[3], den, t, cp[3], best = DBL_MAX, tol, slack = o->slack;
	int c, inside = 0, pu = (pax + 1) % 3, pv = (pax + 2) % 3;
	uint32_t q;
	X[f->u] = f->u0 + ((double)xm + 0.5) / f->su;
	X[f->v] = f->v0 + ((double)row + 0.5) / f->sv;
	X[f->a] = f->face + f->s * f->W;
	for (c = 0; c < 3; ++c) dir[c] = X[c] - world0[c];
	den = pn[0] * dir[0] + pn[1] * dir[1] + pn[2] * dir[2];
	if (!(pvs__dabs(den) > 1e-9 * sqrt(dir[0] * dir[0] + dir[1] * dir[1] + dir[2] * dir[2]))) return 0;
	t = ((double)o->pd - (pn[0] * world0[0] + pn[1] * world0[1] + pn[2] * world0[2])) / den;
	if (front ? !(t > 0.0 && t <= 1.0) : !(t >= 1.0)) return 0;
	for (c = 0; c < 3; ++c) cp[c] = world0[c] + dir[c] * t;
	for (q = 0; q < n; ++q) { /* parity and distance against the boundary, in (pu, pv) */
		const double *a = E + 6 * (size_t)q, *b = a + 3;
		double ax = a[pu], ay = a[pv], bx = b[pu], by = b[pv], ex = bx - ax, ey = by - ay, l2 = ex * ex + ey * ey, s2;
		if ((ay > cp[pv]) != (by > cp[pv]) && cp[pu] < ax + ex * (cp[pv] - ay) / ey) inside = !inside;
		s2 = l2 > 0.0 ? pvs__dmin(1.0, pvs__dmax(0.0, ((cp[pu] - ax) * ex + (cp[pv] - ay) * ey) / l2)) : 0.0;
		best = pvs__dmin(best,
						 sqrt((cp[pu] - ax - ex * s2) * (cp[pu] - ax - ex * s2) +
							  (cp[pv] - ay - ey * s2) * (cp[pv] - ay - ey * s2)));
	}
	/* the surface lies within slack of the plane: the line crosses that slab over slack |dir| / |den|, 1 / |n_pax|
	   longer in (pu, pv); nearer the boundary, not trusted */
	tol = 4.0 * slack / pvs__dabs(pn[pax]) *
			pvs__dmax(1.0, sqrt(dir[0] * dir[0] + dir[1] * dir[1] + dir[2] * dir[2]) / pvs__dabs(den)) +
		1e-9 * scale;
	return inside && best > tol;
}

/* The Projection of a concave planar occluder P (Durand 2000 §3.4, Fig. 7) wholly in front of the plane or, unless
   front_only, behind it. As the cell point moves, a line's crossing with P's plane leaves P only through its boundary,
   so pixel X is covered when (1) it is outside every boundary edge's penumbra (cmark) and (2) the line from the cell's
   centre through X crosses P; one test per unmarked run of a row. Depth: the farthest vertex plus the slack. */
PVS__STATIC uint32_t pvs__ep_concave(const pvs__epframe *fp, const pvs__extproj_prep *p, const pvs__epocc *o,
									 int front_only, unsigned char *cmark, float *map, unsigned char *mask) {
	const pvs__epframe f = *fp;
	double E[6 * (PVS__EP_CONCAVE_EDGES + PVS__EP_CONCAVE_EDGES / 2 + 1)];
	uint32_t e, written = 0, n = o->ecount;
	double wmin = DBL_MAX, wmax = -DBL_MAX, margin = 1e-4 * (f.W - f.cw[0]), slack = o->slack, base;
	double xlo = -DBL_MAX, xhi = DBL_MAX, ylo = -DBL_MAX, yhi = DBL_MAX, V0[3], world0[3], pn[3], scale = 0.0;
	int c, front, pax = 0;
	int32_t i0, i1, j0, j1, row;
	float depth;
	if (n > PVS__EP_CONCAVE_EDGES) return 0;
	for (e = 0; e < 6 * n; ++e) E[e] = p->cedge[6 * (size_t)o->efirst + e];
	for (e = 0; e < 2 * n; ++e) {
		double w = f.s * (E[3 * e + f.a] - f.face);
		wmin = pvs__dmin(wmin, w);
		wmax = pvs__dmax(wmax, w);
		for (c = 0; c < 3; ++c) scale = pvs__dmax(scale, pvs__dabs(E[3 * e + c]));
	}
	if (!(wmin - slack > margin)) {
		/* reaching past the cell's face (a wall beside the cell): its part at w >= margin, exact input only */
		if (slack > 0.0 || !(wmax > margin)) return 0;
		n = pvs__ep_clip_concave(&f, o, E, n, margin, 1);
		if (n < 3) return 0;
	}
	if (wmax + slack <= f.W) front = 1;
	else if (!front_only && wmin - slack >= f.W) front = 0;
	else if (slack == 0.0) { /* straddling the plane: its part in front */
		n = pvs__ep_clip_concave(&f, o, E, n, f.W, 0);
		if (n < 3) return 0;
		front = 1;
		wmax = f.W;
	} else return 0;
	base = pvs__dabs(f.u0) * f.su + pvs__dabs(f.v0) * f.sv + 1.0;
	for (c = 0; c < 8; ++c) {
		double Vu = f.cu[c & 1], Vv = f.cv[(c >> 1) & 1], Vw = f.cw[(c >> 2) & 1], bx0 = DBL_MAX, bx1 = -DBL_MAX,
			   by0 = DBL_MAX, by1 = -DBL_MAX;
		for (e = 0; e < 2 * n; ++e) {
			const double *x = E + 3 * (size_t)e;
			double w = f.s * ((double)x[f.a] - f.face), t = (f.W - Vw) / (w - Vw);
			double pu_ = (Vu + ((double)x[f.u] - Vu) * t - f.u0) * f.su,
				   pv_ = (Vv + ((double)x[f.v] - Vv) * t - f.v0) * f.sv;
			bx0 = pvs__dmin(bx0, pu_); bx1 = pvs__dmax(bx1, pu_);
			by0 = pvs__dmin(by0, pv_); by1 = pvs__dmax(by1, pv_);
		}
		xlo = pvs__dmax(xlo, bx0); xhi = pvs__dmin(xhi, bx1);
		ylo = pvs__dmax(ylo, by0); yhi = pvs__dmin(yhi, by1);
	}
	if (!(xhi - xlo >= 1.0) || !(yhi - ylo >= 1.0) || !(xhi - xlo < 1e9) || !(yhi - ylo < 1e9)) return 0;
	i0 = pvs__clampi(ceil(xlo + 1e-6 * (1.0 + pvs__dabs(xlo))), 0, (int32_t)f.width);
	i1 = pvs__clampi(floor(xhi - 1e-6 * (1.0 + pvs__dabs(xhi))) - 1.0, -1, (int32_t)f.width - 1);
	j0 = pvs__clampi(ceil(ylo + 1e-6 * (1.0 + pvs__dabs(ylo))), 0, (int32_t)f.height);
	j1 = pvs__clampi(floor(yhi - 1e-6 * (1.0 + pvs__dabs(yhi))) - 1.0, -1, (int32_t)f.height - 1);
	if (i0 > i1 || j0 > j1) return 0;
	for (row = j0; row <= j1; ++row) memset(cmark + (size_t)row * f.width + i0, 0, (size_t)(i1 - i0 + 1));
	/* (1) the boundary's penumbrae */
	for (e = 0; e < n; ++e)
		if (!pvs__ep_mark_penumbra(&f, E + 6 * (size_t)e, base, cmark, i0, i1, j0, j1)) break;
	/* (2) per run of unmarked pixels */
	for (c = 0; c < 3; ++c) pn[c] = o->pn[c];
	for (c = 1; c < 3; ++c)
		if (pvs__dabs(pn[c]) > pvs__dabs(pn[pax])) pax = c;
	V0[0] = 0.5 * (f.cu[0] + f.cu[1]);
	V0[1] = 0.5 * (f.cv[0] + f.cv[1]);
	V0[2] = 0.5 * f.cw[0];
	world0[f.u] = V0[0];
	world0[f.v] = V0[1];
	world0[f.a] = f.face + f.s * V0[2];
	depth = pvs__f_up(wmax + slack + 1e-12 * (pvs__dabs(wmax) + pvs__dabs(f.face)));
	for (row = j0; row <= j1; ++row) {
		const unsigned char *mk = cmark + (size_t)row * f.width;
		int32_t x = i0;
		while (x <= i1) {
			int32_t xs, xe;
			if (mk[x]) { ++x; continue; }
			xs = x;
			while (x <= i1 && !mk[x]) ++x;
			xe = x - 1;
			if (!pvs__ep_crosses_inside(&f, o, E, n, world0, pn, pax, front, scale, (xs + xe) / 2, row)) continue;
			if (map) {
				float *px = map + (size_t)row * f.width;
				int32_t xx;
				for (xx = xs; xx <= xe; ++xx)
					if (px[xx] > depth) px[xx] = depth;
			}
			if (mask) pvs__ep_mask_set(mask + (size_t)row * f.width + xs, f.bits, (size_t)(xe - xs + 1));
			written += (uint32_t)(xe - xs + 1);
		}
	}
	return written;
}

/* ---- depth maps with their pyramids, sweep masks ---- */

/* A depth map and its max pyramid (§2.4): a texel is the greatest Depth of its 2 x 2 children. */
typedef struct pvs__epmap {
	pvs_extproj_plane plane;
	pvs__epframe frame;
	int active;
	uint32_t levels;
	uint32_t lw[14], lh[14];
	float *lv[14];
} pvs__epmap;

/* The max pyramid by pvs__pyramid_level (positive Depths: its SIMD path matches the scalar one). */
PVS__STATIC void pvs__ep_build_pyramid(pvs__epmap *m) {
	uint32_t l;
	for (l = 1; l <= m->levels; ++l)
		pvs__pyramid_level(NULL, m->lv[l - 1], m->lw[l - 1], m->lh[l - 1], NULL, m->lv[l], m->lw[l], m->lh[l], 1, 1, 1);
}

/* The top-down query of extproj's two pyramids: depth maps (max pyramids: a pixel is open where its Depth >= d) and
   sweep masks (AND pyramids: open where `bit` is clear). 1 if some level-0 pixel of rect r (x0 y0 x1 y1) under texel
   (tx, ty) of level l is open. */
typedef struct pvs__ep_pyr {
	float *const *depth;           /* the depth map's levels, or NULL for a mask */
	unsigned char *const *mask;
	const uint32_t *lw, *lh;
	float d;
	unsigned char bit;
} pvs__ep_pyr;

PVS__STATIC int pvs__ep_open_at(const pvs__ep_pyr *p, uint32_t l, uint32_t tx, uint32_t ty, const int32_t *r) {
	uint32_t cx, cy, i = ty * p->lw[l] + tx;
	if (p->depth ? p->depth[l][i] < p->d : (p->mask[l][i] & p->bit) != 0) return 0;
	if (l == 0) return 1;
	for (cy = 2 * ty; cy <= 2 * ty + 1 && cy < p->lh[l - 1]; ++cy)
		for (cx = 2 * tx; cx <= 2 * tx + 1 && cx < p->lw[l - 1]; ++cx) {
			int32_t px0 = (int32_t)(cx << (l - 1)), py0 = (int32_t)(cy << (l - 1));
			int32_t px1 = px0 + (int32_t)(1u << (l - 1)) - 1, py1 = py0 + (int32_t)(1u << (l - 1)) - 1;
			if (px1 < r[0] || px0 > r[2] || py1 < r[1] || py0 > r[3]) continue;
			if (pvs__ep_open_at(p, l - 1, cx, cy, r)) return 1;
		}
	return 0;
}

/* 1 if some pixel of rect r is open or lies outside the plane: from the finest level where r spans 2 x 2 texels. */
PVS__STATIC int pvs__ep_open(const pvs__ep_pyr *p, const pvs_extproj_plane *plane, uint32_t levels, const int32_t *r) {
	uint32_t l = 0, tx, ty;
	if (r[0] < 0 || r[1] < 0 || r[2] >= (int32_t)plane->width || r[3] >= (int32_t)plane->height) return 1;
	while (l < levels &&
		   (((uint32_t)r[2] >> l) - ((uint32_t)r[0] >> l) > 1 || ((uint32_t)r[3] >> l) - ((uint32_t)r[1] >> l) > 1))
		++l;
	for (ty = (uint32_t)r[1] >> l; ty <= (uint32_t)r[3] >> l; ++ty)
		for (tx = (uint32_t)r[0] >> l; tx <= (uint32_t)r[2] >> l; ++tx)
			if (pvs__ep_open_at(p, l, tx, ty, r)) return 1;
	return 0;
}

/* 1 if some pixel of rect r holds a Depth >= d, or lies outside the plane. */
PVS__STATIC int pvs__ep_visible(const pvs__epmap *m, const int32_t *r, float d) {
	pvs__ep_pyr p;
	p.depth = m->lv;
	p.mask = NULL;
	p.lw = m->lw;
	p.lh = m->lh;
	p.d = d;
	p.bit = 0;
	return pvs__ep_open(&p, &m->plane, m->levels, r);
}

/* A sweep plane (§5): a mask (1 = every ray from the cell through the pixel is blocked before the plane) and its AND
   pyramid. With sub-cells (nsub = 4) bit j says so for quarter j of the cell (halved across the direction on u: bit 0,
   v: bit 1; frame sub[j]): their umbrae together are wider than the cell's, and an object is hidden when hidden from
   each; frame.bits is all four (slices block every ray). nsub = 0: bit 1. */
#define PVS__EP_MAX_SUB 4
typedef struct pvs__epmask {
	pvs_extproj_plane plane;
	pvs__epframe frame;
	uint32_t levels, nsub;
	uint32_t lw[14], lh[14];
	unsigned char *lv[14];
	pvs__epframe sub[PVS__EP_MAX_SUB];
} pvs__epmask;

/* The umbrae a mask holds (1 or 4) and the frame of the j-th. */
PVS__STATIC uint32_t pvs__ep_nsub(const pvs__epmask *m) { return m->nsub ? m->nsub : 1u; }
PVS__STATIC const pvs__epframe *pvs__ep_subframe(const pvs__epmask *m, uint32_t j) {
	return m->nsub ? m->sub + j : &m->frame;
}

/* Splits a mask's cell into 4 sub-cells meeting at one midpoint, so they cover the cell. */
PVS__STATIC void pvs__ep_split_mask(pvs__epmask *m) {
	uint32_t j;
	double mu = 0.5 * (m->frame.cu[0] + m->frame.cu[1]), mv = 0.5 * (m->frame.cv[0] + m->frame.cv[1]);
	m->nsub = PVS__EP_MAX_SUB;
	for (j = 0; j < PVS__EP_MAX_SUB; ++j) {
		pvs__epframe *f = m->sub + j;
		*f = m->frame;
		f->cu[j & 1 ? 0 : 1] = mu;
		f->cv[j & 2 ? 0 : 1] = mv;
		f->bits = (unsigned char)(1u << j);
	}
	m->frame.bits = (unsigned char)((1u << PVS__EP_MAX_SUB) - 1u);
}

/* The mask's AND pyramid. Not pvs__pyramid_level: no min or max of values gives each sub-cell bit's AND. */
PVS__STATIC void pvs__ep_build_mask_pyramid(pvs__epmask *m) {
	uint32_t l, x, y;
	for (l = 1; l <= m->levels; ++l) {
		uint32_t pw = m->lw[l - 1], ph = m->lh[l - 1];
		const unsigned char *src = m->lv[l - 1];
		unsigned char *dst = m->lv[l];
		for (y = 0; y < m->lh[l]; ++y)
			for (x = 0; x < m->lw[l]; ++x) {
				uint32_t x0 = 2 * x, y0 = 2 * y, x1 = x0 + 1 < pw ? x0 + 1 : x0, y1 = y0 + 1 < ph ? y0 + 1 : y0;
				dst[y * m->lw[l] + x] =
					(unsigned char)(src[y0 * pw + x0] & src[y0 * pw + x1] & src[y1 * pw + x0] & src[y1 * pw + x1]);
			}
	}
}

/* 1 if some pixel of the rectangle does not have `bit` (or lies outside the plane). */
PVS__STATIC int pvs__ep_mask_open(const pvs__epmask *m, const int32_t *r, unsigned char bit) {
	pvs__ep_pyr p;
	p.depth = NULL;
	p.mask = m->lv;
	p.lw = m->lw;
	p.lh = m->lh;
	p.d = 0.0f;
	p.bit = bit;
	return pvs__ep_open(&p, &m->plane, m->levels, r);
}

/* Reprojection (§5.1): per column of `to`, the range [lo, hi] of `from`'s pixels on u (per row, on v) that rays from
   the cell through it cross, extremes at cell corners and pixel edges; lo = -1 outside `from`. */
PVS__STATIC void pvs__ep_reproject_axis(const double *ck, const double *cw, double W_from, double W_to, double to_k0,
										double to_sk, uint32_t to_n, double from_k0, double from_sk, uint32_t from_n,
										int32_t *lo, int32_t *hi) {
	uint32_t i;
	double a[2];
	int c;
	for (c = 0; c < 2; ++c) a[c] = (W_from - cw[c]) / (W_to - cw[c]);
	for (i = 0; i < to_n; ++i) {
		double q0 = to_k0 + (double)i / to_sk, q1 = to_k0 + (double)(i + 1) / to_sk, mn = DBL_MAX, mx = -DBL_MAX, err;
		int e, k;
		for (k = 0; k < 2; ++k)
			for (c = 0; c < 2; ++c)
				for (e = 0; e < 2; ++e) {
					double q = e ? q1 : q0, x = (ck[k] + (q - ck[k]) * a[c] - from_k0) * from_sk;
					mn = pvs__dmin(mn, x);
					mx = pvs__dmax(mx, x);
				}
		err = 1e-6 +
			1e-12 *
				(pvs__dabs(mn) + pvs__dabs(mx) +
				 (pvs__dabs(from_k0) + pvs__dabs(q0) + pvs__dabs(q1) + pvs__dabs(ck[0]) + pvs__dabs(ck[1])) * from_sk);
		lo[i] = pvs__clampi(floor(mn - err), -1, (int32_t)from_n);
		hi[i] = pvs__clampi(floor(mx + err), -1, (int32_t)from_n);
		if (lo[i] < 0 || hi[i] >= (int32_t)from_n) lo[i] = -1;
	}
}

/* ---- per cell: occluder selection, planes, the object sweep ---- */

typedef struct pvs__epsel {
	float score;
	uint32_t occ;
} pvs__epsel;

typedef struct pvs__epparams {
	uint32_t res;        /* pixels per plane: res x res */
	uint32_t max_occ;    /* occluders per direction on §6.1's planes */
	uint32_t sweep;      /* occlusion sweep planes per direction (§5), 0 = no sweep */
	uint32_t split;      /* 1: sweep masks hold the cell's 4 quarters' umbrae (pvs__epmask) */
	uint32_t coarse;     /* 1 (PVS_BAKE_PREVIEW): object nodes decided whole (pvs__ep_visit) */
} pvs__epparams;

/* The preview's coarse test (PVS_BAKE_PREVIEW): a node subtending less than PVS__EP_COARSE_ANGLE (diagonal over
   distance plus the cell's diagonal; about 4 pixels of a 64-pixel plane) is decided whole, past PVS__EP_COARSE_TESTS
   box tests all are kept. Such nodes number about log(scene / cell) / angle^2 at any scene size. Only hidden boxes are
   dropped. */
#define PVS__EP_COARSE_ANGLE 0.25
#define PVS__EP_COARSE_TESTS 4096u

typedef struct pvs__epcell {
	const pvs_scene *scene;
	pvs_box cell;
	pvs__epmap maps[6 * PVS__EP_PLANES];
	pvs__epmask *masks;  /* 6 x sweep; masks of direction d: d * sweep .. + mask_count[d] */
	uint32_t mask_count[6], sweep;
	const pvs_word *candidates; /* adaptive cells (§6.1): only the parent's PVS is tested, NULL = all */
	pvs_word *bits;
	int coarse;                 /* pvs__epparams.coarse: */
	double cell_diag;           /*   the cell's diagonal, */
	uint32_t tests;             /*   the box tests so far */
} pvs__epcell;

/* 1 if a box between cell and plane (depths w0 > 0 .. w1 <= W) is hidden by §4's improved Projection: some point of
   each "any" axis range and all of each "all" range hold occluders strictly nearer than w0. Property 1 needs them
   convex or planar: Projections and reprojected maps are; slices (Depth W) never pass a front box's depth test. */
PVS__STATIC int pvs__ep_front_hidden(const pvs__epmap *m, const pvs_box *b, double w0, double w1) {
	const pvs__epframe *f = &m->frame;
	int32_t ru[2], rv[2], r[4], i, j;
	int anyu, anyv;
	float depth = pvs__f_down(w0 - 1e-12 * w0);
	double cu[2], cv[2];
	cu[0] = f->cu[0]; cu[1] = f->cu[1];
	cv[0] = f->cv[0]; cv[1] = f->cv[1];
	pvs__ep_improved_axis(cu, b->min[f->u], b->max[f->u], w0, w1, f->W, f->u0, f->su, f->width, &ru[0], &ru[1], &anyu);
	pvs__ep_improved_axis(cv, b->min[f->v], b->max[f->v], w0, w1, f->W, f->v0, f->sv, f->height, &rv[0], &rv[1], &anyv);
	if (ru[0] < 0 || rv[0] < 0 || ru[1] >= (int32_t)f->width || rv[1] >= (int32_t)f->height) return 0;
	if (anyu && ru[1] - ru[0] > 8) ru[1] = ru[0] + 8; /* a few candidates are enough */
	if (anyv && rv[1] - rv[0] > 8) rv[1] = rv[0] + 8;
	for (i = ru[0]; i <= ru[1]; ++i) {
		r[0] = anyu ? i : ru[0];
		r[2] = anyu ? i : ru[1];
		for (j = rv[0]; j <= rv[1]; ++j) {
			r[1] = anyv ? j : rv[0];
			r[3] = anyv ? j : rv[1];
			if (!pvs__ep_visible(m, r, depth)) return 1;
			if (!anyv) break;
		}
		if (!anyu) break;
	}
	return 0;
}

/* A box beyond a sweep plane: §3.1's Projection (every blocked pixel's occluder is nearer); per sub-cell. */
PVS__STATIC int pvs__ep_mask_hidden(const pvs__epmask *m, const pvs_box *b) {
	int32_t r[4];
	float depth;
	uint32_t j, n = pvs__ep_nsub(m);
	for (j = 0; j < n; ++j) {
		const pvs__epframe *f = pvs__ep_subframe(m, j);
		if (!pvs__ep_occludee(f, b, r, &depth) || pvs__ep_mask_open(m, r, f->bits)) return 0;
	}
	return 1;
}

/* 1 if the box is hidden from the whole cell (never if meeting it): on §6.1's planes by §3.1 behind, §4 in front,
   both parts if straddling; on the sweep's by the last two planes before it. */
PVS__STATIC int pvs__ep_box_hidden(pvs__epcell *c, const pvs_box *b) {
	int d;
	if (pvs__box_overlap(b, &c->cell)) return 0;
	for (d = 0; d < 6 * PVS__EP_PLANES; ++d) {
		const pvs__epmap *m = c->maps + d;
		const pvs__epframe *f = &m->frame;
		int32_t r[4];
		float depth;
		double w0, w1;
		if (!m->active) continue;
		w0 = f->s > 0 ? (double)b->min[f->a] - f->face : f->face - (double)b->max[f->a];
		w1 = f->s > 0 ? (double)b->max[f->a] - f->face : f->face - (double)b->min[f->a];
		if (!(w0 > 0.0)) continue;
		if (w1 <= f->W) {
			if (pvs__ep_front_hidden(m, b, w0, w1)) return 1;
			continue;
		}
		if (w0 < f->W) {
			/* straddling: cut at one float */
			pvs_box back = *b;
			float cut = f->s > 0 ? pvs__f_down(f->face + f->W) : pvs__f_up(f->face - f->W);
			double cw = f->s > 0 ? (double)cut - f->face : f->face - (double)cut;
			if (!(cw > 0.0) || !pvs__ep_front_hidden(m, b, w0, cw)) continue;
			if (f->s > 0) back.min[f->a] = cut; else back.max[f->a] = cut;
			if (!pvs__ep_occludee(f, &back, r, &depth)) continue;
			if (!pvs__ep_visible(m, r, depth)) return 1;
			continue;
		}
		if (!pvs__ep_occludee(f, b, r, &depth)) continue;
		if (!pvs__ep_visible(m, r, depth)) return 1;
	}
	for (d = 0; d < 6 && c->sweep; ++d) {
		const pvs__epmask *ms = c->masks + (size_t)d * c->sweep;
		uint32_t n = c->mask_count[d], k;
		int a = d >> 1;
		double w0;
		if (!n) continue;
		w0 = d & 1 ? (double)c->cell.min[a] - b->max[a] : (double)b->min[a] - c->cell.max[a];
		for (k = 0; k < n && ms[k].frame.W < w0; ++k) {}
		if (k >= 1 && pvs__ep_mask_hidden(ms + k - 1, b)) return 1;
		if (k >= 2 && pvs__ep_mask_hidden(ms + k - 2, b)) return 1;
	}
	return 0;
}

/* 1 if some part of object o inside b (its box cut by a leaf) may be seen: ranges of its triangles in file order, their
   boxes (of their points inside b) tested top-down (Durand 2000 §2.4, §6.1), hidden ones skipped, visible ones
   halved. It pays only with the sweep (a tree's box is mostly air). Large objects or runs (PVS__EP_PARTS_TRIS,
   PVS__EP_PARTS_TESTS) are kept. */
#define PVS__EP_PARTS_TRIS 16384u
#define PVS__EP_PARTS_TESTS 256u
PVS__STATIC int pvs__ep_parts_visible(pvs__epcell *c, uint32_t o, const pvs_box *b) {
	const pvs_scene *s = c->scene;
	uint32_t stack[2 * 34], top = 0, tests = 0; /* a pending half per level: at most 33 ranges */
	uint32_t t0 = s->object_triangles[2 * (size_t)o], tn = s->object_triangles[2 * (size_t)o + 1];
	if (tn < 2 || tn > PVS__EP_PARTS_TRIS) return 1; /* as its box test said */
	stack[top++] = t0 + tn / 2; /* the whole box was tested: start with the halves */
	stack[top++] = t0 + tn;
	stack[top++] = t0;
	stack[top++] = t0 + tn / 2;
	while (top) {
		uint32_t hi = stack[--top], lo = stack[--top], mid;
		pvs_box pb = pvs__box_empty();
		size_t t;
		for (t = 3 * (size_t)lo; t < 3 * (size_t)hi; ++t)
			pvs__box_add_point(&pb, s->positions + 3 * (size_t)s->indices[t]);
		if (!pvs__box_clip(&pb, b)) continue;
		if (++tests > PVS__EP_PARTS_TESTS) return 1;
		if (pvs__ep_box_hidden(c, &pb)) continue;
		if (hi - lo == 1) return 1;
		mid = lo + (hi - lo) / 2;
		stack[top++] = mid;
		stack[top++] = hi;
		stack[top++] = lo;
		stack[top++] = mid;
	}
	return 0;
}

/* A leaf's object that may be in the PVS: not occluder-only, and a candidate. */
PVS__STATIC int pvs__ep_wanted(const pvs__epcell *c, uint32_t o) {
	if (c->scene->object_flags[o] & PVS_OBJECT_OCCLUDER_ONLY) return 0;
	return !c->candidates || pvs_bitset_test(c->candidates, o);
}

/* §6.1: occludees top-down through the object kD-tree, hidden nodes skipped; an object is visible if its box cut by a
   leaf is (sweep: pvs__ep_parts_visible). Coarse: PVS__EP_COARSE_ANGLE. */
PVS__STATIC pvs_visit pvs__ep_visit(void *user, const pvs_box *node_box, float distance, const uint32_t *items,
									uint32_t count) {
	pvs__epcell *c = (pvs__epcell *)user;
	uint32_t i;
	if (distance < 0.0f || (c->coarse && items && c->tests >= PVS__EP_COARSE_TESTS)) {
		for (i = 0; i < count; ++i)
			if (pvs__ep_wanted(c, items[i])) pvs_bitset_set(c->bits, items[i]);
		return PVS_VISIT_ALL;
	}
	if (c->coarse && !items) {
		if (c->tests >= PVS__EP_COARSE_TESTS) return PVS_VISIT_ALL;
		++c->tests;
		if (pvs__ep_box_hidden(c, node_box)) return PVS_VISIT_SKIP;
		return pvs__box_diagonal(node_box) < PVS__EP_COARSE_ANGLE * ((double)distance + c->cell_diag)
			? PVS_VISIT_ALL
			: PVS_VISIT_DESCEND;
	}
	c->tests += 1 + count;
	if (pvs__ep_box_hidden(c, node_box)) return PVS_VISIT_SKIP;
	for (i = 0; i < count; ++i) {
		uint32_t o = items[i];
		pvs_box b = c->scene->object_boxes[o];
		if (pvs_bitset_test(c->bits, o) || !pvs__ep_wanted(c, o)) continue;
		if (!pvs__box_clip(&b, node_box)) continue;
		if (!pvs__ep_box_hidden(c, &b) && (!c->sweep || pvs__ep_parts_visible(c, o, &b))) pvs_bitset_set(c->bits, o);
	}
	return PVS_VISIT_DESCEND;
}

/* A box's depths w0, w1 beyond the cell's face in direction d. */
PVS__STATIC void pvs__ep_box_w(const pvs_box *cell, const pvs_box *b, int d, double *w0, double *w1) {
	int a = d >> 1;
	if (d & 1) { *w0 = (double)cell->min[a] - b->max[a]; *w1 = (double)cell->min[a] - b->min[a]; }
	else { *w0 = (double)b->min[a] - cell->max[a]; *w1 = (double)b->max[a] - cell->max[a]; }
}

/* §6.1 plane placement: the pixels an occluder's box fills on the plane at W, axis by axis. */
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
	/* that plane's extent grows with W */
	return len[0] * len[1] /
		   (((double)cell->max[ax[0]] - cell->min[ax[0]] + 2.0 * PVS__EP_EXTEND * (W + ext)) *
			((double)cell->max[ax[1]] - cell->min[ax[1]] + 2.0 * PVS__EP_EXTEND * (W + ext)));
}

/* Plane of direction d at W, reaching PVS__EP_EXTEND times its distance from the cell's far side sideways (§6.1: for
   the corner directions). */
PVS__STATIC void pvs__ep_make_plane(const pvs_box *cell, int d, double W, uint32_t res, pvs_extproj_plane *pl) {
	int a = d >> 1, u = (a + 1) % 3, v = (a + 2) % 3;
	double ext = (double)cell->max[a] - cell->min[a];
	memset(pl, 0, sizeof(*pl));
	pl->cell = *cell;
	pl->axis = (uint32_t)a;
	pl->side = d & 1 ? -1 : 1;
	pl->distance = pvs__f_up(W);
	pl->rect[0] = pvs__f_down(cell->min[u] - PVS__EP_EXTEND * (W + ext));
	pl->rect[1] = pvs__f_down(cell->min[v] - PVS__EP_EXTEND * (W + ext));
	pl->rect[2] = pvs__f_up(cell->max[u] + PVS__EP_EXTEND * (W + ext));
	pl->rect[3] = pvs__f_up(cell->max[v] + PVS__EP_EXTEND * (W + ext));
	pl->width = pl->height = res;
}

/* A sweep mask's longest side (its res^2 pixels spread over what matters, pvs__ep_fit_plane). */
PVS__STATIC uint32_t pvs__ep_max_side(uint32_t res) {
	return 16u * res < PVS__EP_MAX_SIDE ? 16u * res : PVS__EP_MAX_SIDE;
}

/* Pixels of a w x h map with `levels` pyramid levels above it. */
PVS__STATIC size_t pvs__ep_pyramid_size(uint32_t w, uint32_t h, uint32_t levels) {
	size_t n = 0;
	uint32_t k;
	for (k = 0; k <= levels; ++k) {
		n += (size_t)w * h;
		w = (w + 1) / 2;
		h = (h + 1) / 2;
	}
	return n;
}

/* The pyramid levels above a res x res map (down to 1 x 1, at most 13). */
PVS__STATIC uint32_t pvs__ep_level_count(uint32_t res) {
	uint32_t levels = 0;
	while (res > 1 && levels < 13) {
		res = (res + 1) / 2;
		++levels;
	}
	return levels;
}

/* Counts in a mask's summed-area table: (w + 1) (h + 1) <= res^2 + w + h + 1, and w + h <= side + res. */
PVS__STATIC size_t pvs__ep_sat_table(uint32_t res) { return (size_t)res * res + pvs__ep_max_side(res) + res + 1; }

/* The sweep's summed-area tables: one per plane of a direction (each read by up to log2(sweep) + 1 later planes) within
   PVS__EP_SAT_CACHE bytes and sweep >= 2; else two, rebuilt per use. */
PVS__STATIC size_t pvs__ep_sat_count(uint32_t res, uint32_t sweep) {
	return (size_t)sweep * pvs__ep_sat_table(res) * sizeof(uint32_t) <= PVS__EP_SAT_CACHE && sweep >= 2 ? sweep : 2;
}

/* The pixel-sized part of what pvs__extproj_cell allocates (as pvs__ep_scratch_free frees). */
PVS_API size_t pvs_extproj_task_bytes(uint32_t resolution, uint32_t sweep) {
	uint32_t res = resolution ? resolution : PVS__EP_DEFAULT_RES, levels = pvs__ep_level_count(res);
	size_t level_floats, bytes;
	if (res < 16 || res > 4096 || sweep > 256) return 0;
	level_floats = pvs__ep_pyramid_size(res, res, levels);
	bytes = 6 * PVS__EP_PLANES * level_floats * sizeof(float) + (size_t)res * res + res; /* maps, cmark, row */
	if (sweep)
		bytes += 6 * (size_t)sweep * (level_floats + sizeof(pvs__epmask)) +
			pvs__ep_sat_count(res, sweep) * pvs__ep_sat_table(res) * sizeof(uint32_t) +
			2 * ((size_t)pvs__ep_max_side(res) + res) * sizeof(int32_t) + pvs__ep_max_side(res) -
			res; /* masks, tables, ranges, longer row */
	return bytes;
}

/* Fits a sweep plane (§5) to the span of the cell and the scene's bounds per axis (plus a sliver), spreading a
   res x res map's pixels over it as (nearly) square pixels within `room` with `levels`; pixels outside count as open.
   Nothing that could hide is lost: masks are read only by occludees beyond them (§3.1) and by reprojection farther out
   (§5.1), and rays from the cell to points beyond cross the plane inside the span, which holds the cell's (as
   pvs__epslab needs). §6.1's planes are not fitted: §4 often hides by pixels outside the span. */
PVS__STATIC void pvs__ep_fit_plane(const pvs_box *cell, const pvs_box *bounds, uint32_t res, uint32_t levels,
								   size_t room, pvs_extproj_plane *pl) {
	int a = (int)pl->axis, k;
	uint32_t side = pvs__ep_max_side(res);
	double len[2], w, h, px = (double)res * res;
	for (k = 0; k < 2; ++k) {
		int ax = k ? (a + 2) % 3 : (a + 1) % 3;
		double lo = pvs__dmin(cell->min[ax], bounds->min[ax]), hi = pvs__dmax(cell->max[ax], bounds->max[ax]),
			   m = (hi - lo) / 512.0;
		float r0 = (double)pl->rect[k] < lo - m ? pvs__f_down(lo - m) : pl->rect[k];
		float r1 = (double)pl->rect[k + 2] > hi + m ? pvs__f_up(hi + m) : pl->rect[k + 2];
		if (r1 > r0) { /* else (a flat cell in a flat scene) the plane stays */
			pl->rect[k] = r0;
			pl->rect[k + 2] = r1;
		}
		len[k] = (double)pl->rect[k + 2] - pl->rect[k];
	}
	if (!(len[0] > 0.0) || !(len[1] > 0.0)) return;
	w = floor((double)res * sqrt(len[0] / len[1]));
	w = w < 1.0 ? 1.0 : w > side ? side : w;
	h = floor(px / w);
	h = h < 1.0 ? 1.0 : h > side ? side : h;
	w = floor(px / h);
	w = w > side ? side : w;
	pl->width = (uint32_t)w;
	pl->height = (uint32_t)h;
	/* w h <= res^2, but levels round up: a thin map may need a few more pixels than a square one */
	while (pvs__ep_pyramid_size(pl->width, pl->height, levels) > room) {
		if (pl->width >= pl->height) --pl->width;
		else --pl->height;
	}
}

typedef struct pvs__epscratch {
	pvs__epsel *sel;
	float *maps;
	unsigned char *masks;
	uint32_t *sat;
	int32_t *ranges;
	pvs__epmask *mask_hdr;
	pvs__epslicer slicer;
	void *sweep;
	pvs_word *seen;
	size_t nsel, map_floats, mask_bytes, sweep_size, nmask, seen_words;
	size_t sat_count;    /* tables: one per plane of a direction, or 2 (pvs__ep_sat_count) */
	size_t sat_table;    /* counts per table, enough for any mask */
	size_t range_count;  /* int32s in `ranges`: 2 x (width + height) of any mask */
	uint32_t *stamp;     /* the sweep: one per occluder (pvs__epslab) */
	size_t stamp_count;
} pvs__epscratch;

PVS__STATIC void pvs__ep_scratch_free(const pvs_allocator *al, pvs__epscratch *w, uint32_t res) {
	pvs__free_array(al, w->sel, w->nsel, sizeof(pvs__epsel));
	pvs__free_array(al, w->maps, 6 * PVS__EP_PLANES * w->map_floats, sizeof(float));
	pvs__free_array(al, w->masks, w->nmask * w->mask_bytes, 1);
	pvs__free_array(al, w->mask_hdr, w->nmask, sizeof(pvs__epmask));
	pvs__free_array(al, w->sat, w->sat_count * w->sat_table, sizeof(uint32_t));
	pvs__free_array(al, w->ranges, w->range_count, sizeof(int32_t));
	pvs__free_array(al, w->slicer.seg, 4 * w->slicer.cap, sizeof(double));
	pvs__free_array(al, w->slicer.xs, 2 * w->slicer.cap, sizeof(double));
	pvs__free_array(al, w->slicer.row, w->slicer.width, 1);
	pvs__free_array(al, w->slicer.cmark, (size_t)res * res, 1);
	pvs__free(al, w->sweep, w->sweep_size, 16);
	pvs__free_array(al, w->seen, w->seen_words, sizeof(pvs_word));
	pvs__free_array(al, w->stamp, w->stamp_count, sizeof(uint32_t));
}

/* Solid angle of triangle (a, b, c) seen from e (Van Oosterom and Strackee 1983). */
PVS__STATIC double pvs__ep_tri_solid_angle(const double *e, const float *a, const float *b, const float *c) {
	double A[3], B[3], C[3], la, lb, lc, num, den;
	int k;
	for (k = 0; k < 3; ++k) { A[k] = a[k] - e[k]; B[k] = b[k] - e[k]; C[k] = c[k] - e[k]; }
	la = sqrt(A[0] * A[0] + A[1] * A[1] + A[2] * A[2]);
	lb = sqrt(B[0] * B[0] + B[1] * B[1] + B[2] * B[2]);
	lc = sqrt(C[0] * C[0] + C[1] * C[1] + C[2] * C[2]);
	num = A[0] * (B[1] * C[2] - B[2] * C[1]) + A[1] * (B[2] * C[0] - B[0] * C[2]) + A[2] * (B[0] * C[1] - B[1] * C[0]);
	den = la * lb * lc + (A[0] * B[0] + A[1] * B[1] + A[2] * B[2]) * lc +
		(A[0] * C[0] + A[1] * C[1] + A[2] * C[2]) * lb + (B[0] * C[0] + B[1] * C[1] + B[2] * C[2]) * la;
	return 2.0 * pvs__dabs(atan2(num, den));
}

/* Solid angle of an occluder from e: a polygon's by a fan, a solid's by its box (at most three faces face e). */
PVS__STATIC double pvs__ep_solid_angle(const pvs__extproj_prep *p, const pvs__epocc *o, const double *e) {
	double sum = 0.0;
	uint32_t i;
	if (!o->solid) {
		const float *q = p->pts + 3 * (size_t)o->first;
		for (i = 1; i + 1 < o->count; ++i) sum += pvs__ep_tri_solid_angle(e, q, q + 3 * i, q + 3 * i + 3);
	} else {
		int k;
		for (k = 0; k < 3; ++k) {
			int u = (k + 1) % 3, v = (k + 2) % 3;
			float f[4][3];
			if (e[k] >= o->box.min[k] && e[k] <= o->box.max[k]) continue;
			for (i = 0; i < 4; ++i) {
				f[i][k] = e[k] < o->box.min[k] ? o->box.min[k] : o->box.max[k];
				f[i][u] = (i == 1 || i == 2) ? o->box.max[u] : o->box.min[u];
				f[i][v] = i >= 2 ? o->box.max[v] : o->box.min[v];
			}
			sum += pvs__ep_tri_solid_angle(e, f[0], f[1], f[2]) + pvs__ep_tri_solid_angle(e, f[0], f[2], f[3]);
		}
	}
	return sum;
}

/* Selection (§6.1): per direction the n occluders of largest solid angle from the cell's centre beyond the face, by
   (score, lower index): a total order, independent of visiting order. What cannot enter a heap by its bound
   (area / distance^2) is skipped. */
typedef struct pvs__epselect {
	const pvs_scene *scene;
	const pvs__extproj_prep *p;
	const pvs_box *cell;
	const pvs_word *candidates;
	pvs__epsel *sel;
	uint32_t n, *nsel;
	double centre[3];
	pvs_word *seen;          /* occluders met in an earlier leaf */
	int cls;                 /* the size class being swept */
} pvs__epselect;

/* 1 if (score, occ) ranks before the heap entry h. */
PVS__STATIC int pvs__ep_sel_better(float score, uint32_t occ, const pvs__epsel *h) {
	return score > h->score || (score == h->score && occ < h->occ);
}

/* pvs__topk_offer's order: the larger score first, ties to the smaller occluder id. */
PVS__STATIC int pvs__ep_sel_before(const void *a, const void *b) {
	const pvs__epsel *x = (const pvs__epsel *)a;
	return pvs__ep_sel_better(x->score, x->occ, (const pvs__epsel *)b);
}

PVS__STATIC void pvs__ep_sel_push(pvs__epsel *h, uint32_t n, uint32_t *count, float score, uint32_t occ) {
	pvs__epsel e;
	e.score = score;
	e.occ = occ;
	pvs__topk_offer(h, count, n, sizeof(e), &e, pvs__ep_sel_before);
}

/* 1 when an occluder of this box could, by its solid angle bound, enter a heap of a direction it reaches. */
PVS__STATIC int pvs__ep_sel_wanted(const pvs__epselect *w, const pvs_box *box, double bound) {
	uint32_t d;
	for (d = 0; d < 6; ++d) {
		double w0, w1;
		pvs__ep_box_w(w->cell, box, (int)d, &w0, &w1);
		if (w1 > 0.0 && (w->nsel[d] < w->n || bound * 1.000001 >= (double)w->sel[(size_t)d * w->n].score)) return 1;
	}
	return 0;
}

PVS__STATIC pvs_visit pvs__ep_sel_visit(void *user, const pvs_box *node_box, float distance, const uint32_t *items,
										uint32_t count) {
	pvs__epselect *w = (pvs__epselect *)user;
	const pvs__extproj_prep *p = w->p;
	const pvs_box *cell = w->cell;
	uint32_t j, d;
	if (distance > 0.0f &&
		!pvs__ep_sel_wanted(w, node_box, (double)p->class_area[w->cls] / ((double)distance * distance)))
		return PVS_VISIT_SKIP;
	for (j = 0; j < count; ++j) {
		uint32_t i = p->class_occ[w->cls][items[j]];
		const pvs__epocc *o = p->occ + i;
		float score;
		double d2 = 0.0;
		if (pvs_bitset_test(w->seen, i)) continue;
		pvs_bitset_set(w->seen, i);
		if ((o->cap_side > 0 && !(cell->min[o->cap_axis] > o->cap_value)) ||
			(o->cap_side < 0 && !(cell->max[o->cap_axis] < o->cap_value)))
			continue; /* a capped solid this cell cannot use */
		if (w->candidates && o->object != PVS_NO_OBJECT &&
			!(w->scene->object_flags[o->object] & PVS_OBJECT_OCCLUDER_ONLY) &&
			!pvs_bitset_test(w->candidates, o->object))
			continue; /* §6.1: hidden from the parent cell, so redundant (leaving it out is safe) */
		for (d = 0; d < 3; ++d) {
			double g = w->centre[d] < o->box.min[d] ? o->box.min[d] - w->centre[d]
				: w->centre[d] > o->box.max[d]      ? w->centre[d] - o->box.max[d]
													: 0.0;
			d2 += g * g;
		}
		if (!pvs__ep_sel_wanted(w, &o->box, d2 > 0.0 ? (double)o->area / d2 : 1e30)) continue;
		score = (float)pvs__ep_solid_angle(p, o, w->centre);
		if (!(score > 0.0f)) continue;
		for (d = 0; d < 6; ++d) {
			double w0, w1;
			pvs__ep_box_w(cell, &o->box, (int)d, &w0, &w1);
			if (w1 > 0.0) pvs__ep_sel_push(w->sel + (size_t)d * w->n, w->n, w->nsel + d, score, i);
		}
	}
	return PVS_VISIT_DESCEND;
}

PVS__STATIC pvs_result pvs__ep_select(const pvs_scene *s, const pvs__extproj_prep *p, const pvs_box *cell,
									  const pvs_word *candidates, pvs__epsel *sel, uint32_t n, uint32_t *nsel,
									  pvs_word *seen, void *sweep, size_t sweep_size) {
	pvs__epselect w;
	uint32_t i, d;
	pvs_result r;
	memset(&w, 0, sizeof(w));
	w.scene = s;
	w.p = p;
	w.cell = cell;
	w.candidates = candidates;
	w.sel = sel;
	w.n = n;
	w.nsel = nsel;
	w.seen = seen;
	for (i = 0; i < 3; ++i) w.centre[i] = 0.5 * ((double)cell->min[i] + cell->max[i]);
	for (d = 0; d < 6; ++d) nsel[d] = 0;
	memset(seen, 0, PVS_BITSET_WORDS(p->occ_count) * sizeof(pvs_word));
	/* largest first: the heaps fill with high scores and prune the rest early */
	for (w.cls = PVS__EP_AREA_CLASSES - 1; w.cls >= 0; --w.cls) {
		r = pvs_kdtree_sweep(p->occ_tree[w.cls], cell, sweep, sweep_size, pvs__ep_sel_visit, &w);
		if (r != PVS_OK) return r;
	}
	for (d = 0; d < 6; ++d) { /* best first */
		pvs__epsel *h = sel + (size_t)d * n;
		uint32_t k, j;
		for (k = 1; k < nsel[d]; ++k) {
			pvs__epsel t = h[k];
			for (j = k; j > 0 && pvs__ep_sel_better(t.score, t.occ, h + j - 1); --j) h[j] = h[j - 1];
			h[j] = t;
		}
	}
	return PVS_OK;
}

/* Sets up a map's pyramid levels over `base`. */
PVS__STATIC void pvs__ep_levels(uint32_t w, uint32_t h, uint32_t levels, uint32_t *lw, uint32_t *lh, size_t elem,
								void *base, void **lv) {
	uint32_t k;
	unsigned char *b = (unsigned char *)base;
	for (k = 0; k <= levels; ++k) {
		lw[k] = w;
		lh[k] = h;
		lv[k] = b;
		b += (size_t)w * h * elem;
		w = (w + 1) / 2;
		h = (h + 1) / 2;
	}
}

/* An occluder's points for a plane of `axis`: extended through its sheet when the cell stands over it on the occluder's
   side and the extension crosses the axis (along it, it would only push the Depth away); NULL for a capped solid not
   over the cell. */
PVS__STATIC const float *pvs__ep_points(const pvs__extproj_prep *p, const pvs__epocc *o, const pvs_box *cell,
										const int *sheet_side, int axis, uint32_t *count) {
	if (o->cap_side > 0 && !(cell->min[o->cap_axis] > o->cap_value)) return NULL;
	if (o->cap_side < 0 && !(cell->max[o->cap_axis] < o->cap_value)) return NULL;
	if (o->xcount && sheet_side[o->sheet] == o->xside && p->sheet[o->sheet].axis != axis) {
		*count = o->xcount;
		return p->pts + 3 * (size_t)o->xfirst;
	}
	*count = o->count;
	return p->pts + 3 * (size_t)o->first;
}

/* Per sheet: +1 (-1) when the cell lies strictly on its positive (negative) side over its polygon, else 0. */
PVS__STATIC void pvs__ep_sheet_sides(const pvs__extproj_prep *p, const pvs_box *cell, int *side) {
	uint32_t i;
	for (i = 0; i < p->sheet_count; ++i) {
		const pvs__epsheet *S = p->sheet + i;
		int k = S->axis, u = (k + 1) % 3, v = (k + 2) % 3, c;
		const float *poly = p->spoly + 2 * (size_t)S->first;
		side[i] = cell->min[k] > S->value ? 1 : cell->max[k] < S->value ? -1 : 0;
		for (c = 0; c < 4 && side[i]; ++c)
			if (!pvs__ep_in_convex(poly, S->count, c & 1 ? cell->max[u] : cell->min[u],
								   c & 2 ? cell->max[v] : cell->min[v]))
				side[i] = 0;
	}
}

/* §6.1's planes for direction d: one just behind the farthest selected occluder (behind one occluder any plane is
   equivalent, §7.3; in front it loses it to its penumbra), the others per distance band (far / r^q, far / r^(q-1)],
   r = PVS__EP_PLANE_RATIO, behind the band's occluder filling most pixels, for nearer occludees and fusion
   (Fig. 16). */
PVS__STATIC void pvs__ep_direct_planes(const pvs_scene *s, const pvs__extproj_prep *p, const pvs_box *cell, int d,
									   const pvs__epsel *h, uint32_t n, const pvs__epparams *prm, uint32_t levels,
									   float *mem, size_t map_floats, pvs__epslicer *sc, const int *sheet_side,
									   pvs__epmap *maps) {
	int a = d >> 1, q;
	double ext = (double)cell->max[a] - cell->min[a], far = 0.0, w0, w1;
	uint32_t k, j;
	for (k = 0; k < n; ++k) {
		pvs__ep_box_w(cell, &p->occ[h[k].occ].box, d, &w0, &w1);
		far = pvs__dmax(far, w1);
	}
	if (!(far > 0.0)) return;
	for (q = 0; q < PVS__EP_PLANES; ++q) {
		pvs__epmap *m = maps + q;
		double W = far + 1e-3 * (far + ext), hi = far / pow(PVS__EP_PLANE_RATIO, (double)q),
			   lo = hi / PVS__EP_PLANE_RATIO, bestFill = 0.0;
		uint32_t tried = 0;
		if (q > 0) { /* candidates behind the band's occluders, best solid angle first */
			W = 0.0;
			for (k = 0; k < n && tried < PVS__EP_PLANE_CANDIDATES; ++k) {
				double Wc, fill = 0.0;
				pvs__ep_box_w(cell, &p->occ[h[k].occ].box, d, &w0, &w1);
				if (!(w1 > lo && w1 <= hi)) continue;
				++tried;
				Wc = w1 + 1e-3 * (w1 + ext);
				for (j = 0; j < n; ++j) fill += pvs__ep_fill_estimate(cell, &p->occ[h[j].occ].box, d, Wc);
				if (fill > bestFill || (fill == bestFill && Wc < W)) {
					bestFill = fill;
					W = Wc;
				}
			}
			if (!(W > 0.0)) continue;
		}
		pvs__ep_make_plane(cell, d, W, prm->res, &m->plane);
		m->levels = levels;
		pvs__ep_levels(prm->res, prm->res, levels, m->lw, m->lh, sizeof(float), mem + (size_t)q * map_floats,
					   (void **)m->lv);
		for (k = 0; k < prm->res * prm->res; ++k) m->lv[0][k] = PVS_EXTPROJ_EMPTY;
		if (!pvs__ep_frame(&m->plane, &m->frame)) continue;
		for (k = 0; k < n; ++k) {
			uint32_t cnt;
			const float *pts = pvs__ep_points(p, p->occ + h[k].occ, cell, sheet_side, a, &cnt);
			if (p->occ[h[k].occ].ecount) pvs__ep_concave(&m->frame, p, p->occ + h[k].occ, 0, sc->cmark, m->lv[0], NULL);
			else if (pts)
				pvs__ep_occluder(&m->frame, cell, pts, cnt, p->occ[h[k].occ].solid, p->occ[h[k].occ].slack, 0, m->lv[0],
								 NULL);
		}
		pvs__ep_slices(s, p, cell, &m->plane, &m->frame, sc, sheet_side, m->lv[0], NULL);
		pvs__ep_build_pyramid(m);
		m->active = 1;
	}
}

/* §5.1 reprojection: marks in `to` (farther than `from`) the pixels whose every ray from the cell crosses blocked
   pixels of `from`: an umbra inside that of the occluders before `from` (Appendix B), so conservative. The kernel is
   the true cell's per row and column (pvs__ep_reproject_axis); a summed-area table of from's open pixels decides.
   Sub-cell j: own kernel and lane of sat_split, windows of 2^16 pixels or more left open. `ranges`: 2 (width + height)
   of `to`. */
PVS__STATIC void pvs__ep_reproject_sat(const pvs__epmask *from, const uint32_t *sat, const uint64_t *sat_split,
									   pvs__epmask *to, int32_t *ranges, uint32_t j) {
	unsigned char *mask = to->lv[0];
	const pvs__epframe *tf = pvs__ep_subframe(to, j);
	unsigned char bit = tf->bits;
	uint32_t fw = from->plane.width, fh = from->plane.height, tw = to->plane.width, th = to->plane.height, x, y,
			 W1 = fw + 1;
	int32_t *clo = ranges, *chi = ranges + tw, *rlo = ranges + 2 * tw, *rhi = ranges + 2 * tw + th;
	pvs__ep_reproject_axis(tf->cu, tf->cw, from->frame.W, tf->W, tf->u0, tf->su, tw, from->frame.u0, from->frame.su, fw,
						   clo, chi);
	pvs__ep_reproject_axis(tf->cv, tf->cw, from->frame.W, tf->W, tf->v0, tf->sv, th, from->frame.v0, from->frame.sv, fh,
						   rlo, rhi);
	for (y = 0; y < th; ++y) {
		size_t y0, y1;
		if (rlo[y] < 0) continue;
		y0 = (size_t)rlo[y];
		y1 = (size_t)rhi[y] + 1;
		for (x = 0; x < tw; ++x) {
			size_t x0, x1;
			uint64_t open;
			if (clo[x] < 0 || (mask[(size_t)y * tw + x] & bit)) continue;
			x0 = (size_t)clo[x];
			x1 = (size_t)chi[x] + 1;
			if (sat_split) {
				if ((x1 - x0) * (y1 - y0) >= 65536u) continue;
				open = sat_split[y1 * W1 + x1] - sat_split[y0 * W1 + x1] - sat_split[y1 * W1 + x0] +
					sat_split[y0 * W1 + x0];
				open = (open >> (16u * j)) & 0xFFFFu;
			} else
				open = sat[y1 * W1 + x1] - sat[y0 * W1 + x1] - sat[y1 * W1 + x0] + sat[y0 * W1 + x0];
			if (!open) mask[(size_t)y * tw + x] = (unsigned char)(mask[(size_t)y * tw + x] | bit);
		}
	}
}

/* The summed-area table of a mask's pixels without `bit`: (width + 1) x (height + 1) counts. */
PVS__STATIC void pvs__ep_mask_sat(const pvs__epmask *from, uint32_t *sat, unsigned char bit) {
	const unsigned char *prev = from->lv[0];
	uint32_t fw = from->plane.width, fh = from->plane.height, x, y, W1 = fw + 1;
	for (x = 0; x <= fw; ++x) sat[x] = 0;
	for (y = 0; y < fh; ++y) {
		uint32_t run = 0;
		sat[(size_t)(y + 1) * W1] = 0;
		for (x = 0; x < fw; ++x) {
			run += prev[(size_t)y * fw + x] & bit ? 0u : 1u;
			sat[(size_t)(y + 1) * W1 + x + 1] = sat[(size_t)y * W1 + x + 1] + run;
		}
	}
}

/* All sub-cells' summed-area tables at once: 16-bit lane j counts pixels without bit j, modulo 2^64. A window's sum is
   exact modulo 2^64, so each lane is exact below 2^16 (the caller checks): carries between lanes cancel. */
PVS__STATIC void pvs__ep_mask_sat_split(const pvs__epmask *from, uint64_t *sat) {
	const unsigned char *prev = from->lv[0];
	uint32_t fw = from->plane.width, fh = from->plane.height, x, y, W1 = fw + 1, b;
	uint64_t inc[16];
	for (b = 0; b < 16; ++b) /* a 1 in the lanes of the bits clear in b */
		inc[b] = (uint64_t)(~b & 1u) | (uint64_t)((~b >> 1) & 1u) << 16 | (uint64_t)((~b >> 2) & 1u) << 32 |
			(uint64_t)((~b >> 3) & 1u) << 48;
	for (x = 0; x <= fw; ++x) sat[x] = 0;
	for (y = 0; y < fh; ++y) {
		uint64_t run = 0;
		sat[(size_t)(y + 1) * W1] = 0;
		for (x = 0; x < fw; ++x) {
			run += inc[prev[(size_t)y * fw + x] & 15u];
			sat[(size_t)(y + 1) * W1 + x + 1] = sat[(size_t)y * W1 + x + 1] + run;
		}
	}
}

/* pvs__ep_reproject_sat building the table in `sat` ((res + 1)^2 counts; with sub-cells twice that, 8-aligned). */
PVS__STATIC void pvs__ep_reproject(const pvs__epmask *from, pvs__epmask *to, uint32_t *sat, int32_t *ranges) {
	uint32_t j;
	if (!to->nsub) {
		pvs__ep_mask_sat(from, sat, 1);
		pvs__ep_reproject_sat(from, sat, NULL, to, ranges, 0);
		return;
	}
	pvs__ep_mask_sat_split(from, (uint64_t *)(void *)sat);
	for (j = 0; j < to->nsub; ++j) pvs__ep_reproject_sat(from, NULL, (const uint64_t *)(void *)sat, to, ranges, j);
}

/* §5.1 reprojection onto plane `count` from the planes 1, 2, 4, 8, ... back (Appendix B: each one's blocked pixels lie
   in the umbra of the occluders before it). Each reprojection loses up to a pixel per side to rounding (the cell is a
   box, not the paper's planar equivalent cell), which a step per plane would add up; the skips take log2(k - j) + 1
   steps from j to k. `cached` (never with sub-cells): sat holds ms[0 ..]'s tables, `stride` apart; else scratch for
   one. */
PVS__STATIC void pvs__ep_reproject_sweep(const pvs__epmask *ms, uint32_t count, pvs__epmask *to, uint32_t *sat,
										 size_t stride, int cached, int32_t *ranges) {
	uint32_t back;
	for (back = 1; back <= count; back *= 2) {
		if (cached)
			pvs__ep_reproject_sat(ms + count - back, sat + (size_t)(count - back) * stride, NULL, to, ranges, 0);
		else pvs__ep_reproject(ms + count - back, to, sat, ranges);
	}
}

/* The occluders a sweep plane takes (§5.2: "we project the occluders which lie in front of the current projection
   plane P onto P"): those with a part since the previous plane (straddling ones go on each). Skipped: nodes outside
   that slab, beyond the rectangle sideways (farther out from every cell point), or in the previous umbra. */
typedef struct pvs__epslab {
	const pvs_scene *scene;
	const pvs__extproj_prep *p;
	const pvs_box *cell;
	const pvs_word *candidates;
	const int *sheet_side;
	const pvs__epmask *prev;  /* the previous plane, NULL for the first */
	pvs__epmask *m;           /* the plane being filled */
	unsigned char *cmark;
	uint32_t *stamp, serial;  /* occluders met in this traversal (an item comes once per leaf) */
	double W, Wprev, lo[2], hi[2];
	int d, cls, axis[2];
} pvs__epslab;

/* 1 if an occluder or node box can add to the plane: between the planes, in the rectangle, not in the previous
   umbra. */
PVS__STATIC int pvs__ep_slab_wanted(const pvs__epslab *sl, const pvs_box *b) {
	double w0, w1;
	int k;
	pvs__ep_box_w(sl->cell, b, sl->d, &w0, &w1);
	if (!(w0 < sl->W) || !(w1 > 0.0) || (sl->prev && w1 <= sl->Wprev)) return 0;
	for (k = 0; k < 2; ++k)
		if ((double)b->max[sl->axis[k]] < sl->lo[k] || (double)b->min[sl->axis[k]] > sl->hi[k]) return 0;
	if (sl->prev && w0 > sl->Wprev && pvs__ep_mask_hidden(sl->prev, b)) return 0;
	return 1;
}

PVS__STATIC pvs_visit pvs__ep_slab_visit(void *user, const pvs_box *node_box, float distance, const uint32_t *items,
										 uint32_t count) {
	pvs__epslab *sl = (pvs__epslab *)user;
	const pvs__extproj_prep *p = sl->p;
	uint32_t j, k;
	(void)distance;
	if (!pvs__ep_slab_wanted(sl, node_box)) return PVS_VISIT_SKIP;
	for (j = 0; j < count; ++j) {
		uint32_t i = p->class_occ[sl->cls][items[j]], cnt;
		const pvs__epocc *o = p->occ + i;
		const float *pts;
		if (sl->stamp[i] == sl->serial) continue;
		sl->stamp[i] = sl->serial;
		if (sl->candidates && o->object != PVS_NO_OBJECT &&
			!(sl->scene->object_flags[o->object] & PVS_OBJECT_OCCLUDER_ONLY) &&
			!pvs_bitset_test(sl->candidates, o->object))
			continue; /* §6.1: hidden from the parent cell */
		if (!pvs__ep_slab_wanted(sl, &o->box)) continue;
		pts = pvs__ep_points(p, o, sl->cell, sl->sheet_side, sl->d >> 1, &cnt);
		for (k = 0; k < pvs__ep_nsub(sl->m); ++k) {
			const pvs__epframe *f = pvs__ep_subframe(sl->m, k);
			if (o->ecount) pvs__ep_concave(f, p, o, 1, sl->cmark, NULL, sl->m->lv[0]);
			else if (pts) pvs__ep_occluder(f, sl->cell, pts, cnt, o->solid, o->slack, 1, NULL, sl->m->lv[0]);
		}
	}
	return PVS_VISIT_DESCEND;
}

/* The occlusion sweep of §5 for direction d: planes from one cell size C ahead (or behind the nearest selected
   occluder, if farther) to the scene's far end, each holding the reprojected earlier planes (§5.1), the Projections of
   the occluders since the previous plane and the slices it cuts; their count to *planes. Unlike §5.2
   (tests/BENCHMARKS.md, extproj): geometric spacing, as dD = D (K - 1) P / (C N) crowds planes near the cell, where
   small umbrae are short, leaving few far out, where gaps between small occluders close; none nearer than C, as an
   occluder of width s < C / 2 at w casts an umbra ending before w C / (C - s) < 2 w (nearer occluders still reach the
   first plane); the far end is the scene's (§6.1 favours near occluders) and holds no plane. */
PVS__STATIC pvs_result pvs__ep_sweep_planes(const pvs_scene *s, const pvs__extproj_prep *p, const pvs_box *cell, int d,
											const pvs__epsel *h, uint32_t n, const pvs__epparams *prm, uint32_t levels,
											pvs__epscratch *w, const int *sheet_side, const pvs_word *candidates,
											pvs__epmask *ms, uint32_t *planes) {
	int a = d >> 1, u = (a + 1) % 3, v = (a + 2) % 3, cls;
	double ext = (double)cell->max[a] - cell->min[a],
		   C = pvs__dmax((double)cell->max[u] - cell->min[u], (double)cell->max[v] - cell->min[v]);
	double W0 = DBL_MAX, Wend = 0.0, W, Wprev = 0.0, ratio;
	uint32_t k, count = 0, res = prm->res;
	int cached = !prm->split && w->sat_count == prm->sweep;
	pvs__epslab sl;
	pvs_result r = PVS_OK;
	*planes = 0;
	for (k = 0; k < n; ++k) {
		double w0, w1;
		pvs__ep_box_w(cell, &p->occ[h[k].occ].box, d, &w0, &w1);
		W0 = pvs__dmin(W0, pvs__dmax(w1, 0.0));
		Wend = pvs__dmax(Wend, w1);
	}
	{
		double b0, b1;
		pvs__ep_box_w(cell, &s->bounds, d, &b0, &b1);
		Wend = pvs__dmax(Wend, b1);
	}
	if (!(Wend > 0.0)) return PVS_OK;
	if (!(C > 0.0)) C = pvs__dmax(ext, 1e-6);
	/* the first plane at C or just behind the nearest occluder (only there does a flat occluder facing it lie wholly in
	   front), then `sweep` planes up to the far end, exclusive */
	W0 = pvs__dmax(W0 + 1e-3 * (W0 + ext), C);
	Wend += 1e-3 * (Wend + ext);
	if (!(W0 < Wend)) return PVS_OK;
	ratio = pow(Wend / W0, 1.0 / (double)prm->sweep);
	memset(&sl, 0, sizeof(sl));
	sl.scene = s;
	sl.p = p;
	sl.cell = cell;
	sl.candidates = candidates;
	sl.sheet_side = sheet_side;
	sl.cmark = w->slicer.cmark;
	sl.stamp = w->stamp;
	sl.d = d;
	sl.axis[0] = u;
	sl.axis[1] = v;
	for (W = W0; count < prm->sweep; ++count) {
		pvs__epmask *m = ms + count;
		unsigned char *mask;
		pvs__ep_make_plane(cell, d, W, res, &m->plane);
		pvs__ep_fit_plane(cell, &s->bounds, res, levels, w->mask_bytes, &m->plane);
		if (!pvs__ep_frame_max(&m->plane, PVS__EP_MAX_SIDE, &m->frame)) break;
		m->levels = levels;
		m->nsub = 0;
		if (prm->split) pvs__ep_split_mask(m);
		pvs__ep_levels(m->plane.width, m->plane.height, levels, m->lw, m->lh, 1,
					   w->masks + (size_t)((ms - w->mask_hdr) + count) * w->mask_bytes, (void **)m->lv);
		mask = m->lv[0];
		memset(mask, 0, (size_t)m->plane.width * m->plane.height);
		pvs__ep_reproject_sweep(ms, count, m, w->sat, w->sat_table, cached, w->ranges);
		sl.prev = count ? ms + count - 1 : NULL;
		sl.m = m;
		sl.W = m->frame.W;
		sl.Wprev = Wprev;
		for (k = 0; k < 2; ++k) {
			sl.lo[k] = (double)m->plane.rect[k];
			sl.hi[k] = (double)m->plane.rect[k + 2];
		}
		for (cls = PVS__EP_AREA_CLASSES - 1; cls >= 0; --cls) {
			if (!p->class_count[cls]) continue;
			sl.cls = cls;
			++sl.serial;
			r = pvs_kdtree_sweep(p->occ_tree[cls], cell, w->sweep, w->sweep_size, pvs__ep_slab_visit, &sl);
			if (r != PVS_OK) return r;
		}
		pvs__ep_slices(s, p, cell, &m->plane, &m->frame, &w->slicer, sheet_side, NULL, mask);
		if (cached) pvs__ep_mask_sat(m, w->sat + (size_t)count * w->sat_table, 1);
		pvs__ep_build_mask_pyramid(m);
		Wprev = m->frame.W;
		W *= ratio;
		if (!(W < Wend) || !(ratio > 1.0)) { ++count; break; }
	}
	*planes = count;
	return PVS_OK;
}

/* One cell's PVS (Durand 2000 §6.1): per direction the selected occluders on §6.1's planes and §5's sweep, then the
   occludees front to back. `candidates` (adaptive sub-cell): only the parent's visible objects are tested, others'
   occluders left out. */
PVS__STATIC pvs_result pvs__extproj_cell(const pvs_scene *s, const pvs__extproj_prep *p, const pvs_box *cell,
										 const pvs__epparams *prm, const pvs_word *candidates, const pvs_allocator *al,
										 pvs_word *bits, uint32_t cell_id, pvs_error *err) {
	pvs__epcell c;
	pvs__epscratch w;
	uint32_t nsel[6], d, levels = pvs__ep_level_count(prm->res), nper;
	int sheet_side[PVS__EP_MAX_SHEETS];
	size_t level_floats = pvs__ep_pyramid_size(prm->res, prm->res, levels);
	pvs_result r = PVS_OK;
	memset(&c, 0, sizeof(c));
	memset(&w, 0, sizeof(w));
	c.scene = s;
	c.cell = *cell;
	c.bits = bits;
	c.sweep = prm->sweep;
	c.candidates = candidates;
	c.coarse = prm->coarse != 0;
	c.cell_diag = pvs__box_diagonal(cell);
	nper = prm->sweep ? 4 * prm->max_occ : prm->max_occ;
	w.nsel = 6 * (size_t)nper;
	w.map_floats = level_floats;
	w.mask_bytes = level_floats;
	w.nmask = 6 * (size_t)prm->sweep;
	w.sweep_size = pvs_kdtree_sweep_scratch_size(s->object_tree);
	{
		int cls;
		for (cls = 0; cls < PVS__EP_AREA_CLASSES; ++cls) {
			size_t occ_sweep = pvs_kdtree_sweep_scratch_size(p->occ_tree[cls]);
			if (occ_sweep > w.sweep_size) w.sweep_size = occ_sweep;
		}
	}
	w.seen_words = PVS_BITSET_WORDS(p->occ_count);
	w.seen = (pvs_word *)pvs__alloc_array(al, w.seen_words, sizeof(pvs_word));
	w.slicer.cap = (size_t)p->max_slice_segments + 4;
	w.slicer.width = prm->sweep ? pvs__ep_max_side(prm->res) : prm->res;
	w.sel = (pvs__epsel *)pvs__alloc_array(al, w.nsel, sizeof(pvs__epsel));
	w.maps = (float *)pvs__alloc_array(al, 6 * PVS__EP_PLANES * w.map_floats, sizeof(float));
	w.slicer.seg = (double *)pvs__alloc_array(al, 4 * w.slicer.cap, sizeof(double));
	w.slicer.xs = (double *)pvs__alloc_array(al, 2 * w.slicer.cap, sizeof(double));
	w.slicer.row = (unsigned char *)pvs__alloc_array(al, w.slicer.width, 1);
	w.slicer.cmark = (unsigned char *)pvs__alloc_array(al, (size_t)prm->res * prm->res, 1);
	w.sweep = pvs__alloc(al, w.sweep_size, 16);
	if (prm->sweep) {
		w.masks = (unsigned char *)pvs__alloc_array(al, w.nmask * w.mask_bytes, 1);
		w.mask_hdr = (pvs__epmask *)pvs__alloc_array(al, w.nmask, sizeof(pvs__epmask));
		w.sat_count = pvs__ep_sat_count(prm->res, prm->sweep); /* >= 2: room for the split tables */
		w.sat_table = pvs__ep_sat_table(prm->res);
		w.sat = (uint32_t *)pvs__alloc_array(al, w.sat_count * w.sat_table, sizeof(uint32_t));
		w.range_count = 2 * ((size_t)pvs__ep_max_side(prm->res) + prm->res);
		w.ranges = (int32_t *)pvs__alloc_array(al, w.range_count, sizeof(int32_t));
		w.stamp_count = p->occ_count ? p->occ_count : 1;
		w.stamp = (uint32_t *)pvs__alloc_array(al, w.stamp_count, sizeof(uint32_t));
		if (w.stamp) memset(w.stamp, 0, w.stamp_count * sizeof(uint32_t));
	}
	if (!w.sel || !w.maps || !w.slicer.seg || !w.slicer.xs || !w.slicer.row || !w.slicer.cmark || !w.sweep || !w.seen ||
		(prm->sweep && (!w.masks || !w.mask_hdr || !w.sat || !w.ranges || !w.stamp))) {
		r = pvs__fail(err, PVS_ERROR_OUT_OF_MEMORY, cell_id, 0, "extproj scratch for cell %u", cell_id);
		goto done;
	}
	c.masks = w.mask_hdr;
	pvs__ep_sheet_sides(p, cell, sheet_side);
	r = pvs__ep_select(s, p, cell, candidates, w.sel, nper, nsel, w.seen, w.sweep, w.sweep_size);
	if (r != PVS_OK) {
		r = pvs__fail(err, r, cell_id, 0, "extproj: occluder selection of cell %u", cell_id);
		goto done;
	}
	for (d = 0; d < 6; ++d) {
		const pvs__epsel *h = w.sel + (size_t)d * nper;
		if (!nsel[d]) continue;
		pvs__ep_direct_planes(s, p, cell, (int)d, h, nsel[d] < prm->max_occ ? nsel[d] : prm->max_occ, prm, levels,
							  w.maps + (size_t)PVS__EP_PLANES * d * w.map_floats, w.map_floats, &w.slicer, sheet_side,
							  c.maps + PVS__EP_PLANES * d);
		if (prm->sweep) {
			r = pvs__ep_sweep_planes(s, p, cell, (int)d, h, nsel[d], prm, levels, &w, sheet_side, candidates,
									 w.mask_hdr + (size_t)d * prm->sweep, &c.mask_count[d]);
			if (r != PVS_OK) {
				r = pvs__fail(err, r, cell_id, 0, "extproj: occlusion sweep of cell %u", cell_id);
				goto done;
			}
		}
	}
	r = pvs_kdtree_sweep(s->object_tree, cell, w.sweep, w.sweep_size, pvs__ep_visit, &c);
	if (r != PVS_OK) r = pvs__fail(err, r, cell_id, 0, "extproj: object sweep of cell %u", cell_id);
done:
	pvs__ep_scratch_free(al, &w, prm->res);
	return r;
}
/* ---- the EXTPROJ bake method (a row of >>bake's table) ---- */

typedef struct pvs__extproj_bake {
	pvs_allocator allocator;
	pvs__extproj_prep *prep;  /* the scene's occluders, read-only in tasks */
	pvs__epparams prm;
} pvs__extproj_bake;

PVS__STATIC pvs_result pvs__extproj_bake_check(const pvs_bake_desc *desc, pvs_error *err) {
	int preview = (desc->flags & PVS_BAKE_PREVIEW) != 0,
		is_auto = desc->method == PVS_METHOD_AUTO || desc->method == PVS_METHOD_DEFAULT;
	if (desc->extproj.resolution && (desc->extproj.resolution < 16 || desc->extproj.resolution > 4096))
		return pvs__fail(err, PVS_ERROR_INVALID_ARGUMENT, -1, 0, "extproj.resolution %u is not in 16..4096",
						 desc->extproj.resolution);
	if (desc->extproj.occluders > 65536)
		return pvs__fail(err, PVS_ERROR_INVALID_ARGUMENT, -1, 0, "extproj.occluders %u > 65536",
						 desc->extproj.occluders);
	if (desc->extproj.sweep > 256 && desc->extproj.sweep != PVS_EXTPROJ_NO_SWEEP)
		return pvs__fail(err, PVS_ERROR_INVALID_ARGUMENT, -1, 0, "extproj.sweep %u > 256", desc->extproj.sweep);
	if (desc->extproj.sweep_subcells > 1 && desc->extproj.sweep_subcells != 4)
		return pvs__fail(err, PVS_ERROR_INVALID_ARGUMENT, -1, 0, "extproj.sweep_subcells %u is not 0, 1 or 4",
						 desc->extproj.sweep_subcells);
	if (desc->extproj.sweep_subcells == 4 &&
		(desc->extproj.sweep == PVS_EXTPROJ_NO_SWEEP || (!desc->extproj.sweep && (!is_auto || preview))))
		return pvs__fail(err, PVS_ERROR_INVALID_ARGUMENT, -1, 0,
						 "extproj.sweep_subcells 4 needs the occlusion sweep (extproj.sweep)");
	return PVS_OK;
}

/* The parameters: desc's, else the defaults (PREVIEW: coarse; AUTO: with the sweep). */
PVS__STATIC pvs_result pvs__extproj_bake_prepare(pvs__bake_env *env, const pvs_bake_desc *desc, void **state,
												 pvs_error *err) {
	pvs__extproj_bake *x = (pvs__extproj_bake *)pvs__alloc(&env->allocator, sizeof(pvs__extproj_bake), 16);
	int preview = (env->flags & PVS_BAKE_PREVIEW) != 0;
	*state = x;
	if (!x) return pvs__fail(err, PVS_ERROR_OUT_OF_MEMORY, -1, 0, "extproj");
	memset(x, 0, sizeof(*x));
	x->allocator = env->allocator;
	x->prm.res = desc->extproj.resolution ? desc->extproj.resolution
		: preview                         ? PVS_EXTPROJ_PREVIEW_RESOLUTION
										  : PVS__EP_DEFAULT_RES;
	x->prm.max_occ = desc->extproj.occluders ? desc->extproj.occluders : preview ? 32u : PVS__EP_DEFAULT_OCC;
	x->prm.sweep = desc->extproj.sweep == PVS_EXTPROJ_NO_SWEEP ? 0u : desc->extproj.sweep;
	if (!desc->extproj.sweep && env->is_auto && !preview) x->prm.sweep = PVS_EXTPROJ_SWEEP_PLANES; /* AUTO's default */
	x->prm.split = desc->extproj.sweep_subcells == 4;
	x->prm.coarse = preview;
	return pvs__extproj_prepare(env->scene, &env->allocator, &x->prep, err);
}

PVS__STATIC int pvs__extproj_bake_applies(const void *state, const char **why) {
	const pvs__extproj_bake *x = (const pvs__extproj_bake *)state;
	int any = x->prep && x->prep->occ_count;
	*why = !any ? "no planar occluder or convex solid"
		   : x->prm.sweep ? "3D: planar occluders and convex solids, with the occlusion sweep"
						  : "3D: planar occluders and convex solids";
	return any;
}

/* Tests only the candidates (when given) and sets none of the other objects. */
PVS__STATIC pvs_result pvs__extproj_bake_cell(const pvs__bake_env *env, void *state, uint32_t task, uint32_t cell,
											  const pvs_box *box, const pvs_word *candidates, pvs_word *bits,
											  unsigned *flags, pvs_error *err) {
	const pvs__extproj_bake *x = (const pvs__extproj_bake *)state;
	(void)task;
	(void)flags;
	return pvs__extproj_cell(env->scene, x->prep, box, &x->prm, candidates, &env->allocator, bits, cell, err);
}

PVS__STATIC void pvs__extproj_bake_destroy(const pvs__bake_env *env, void *state) {
	pvs__extproj_bake *x = (pvs__extproj_bake *)state;
	(void)env;
	if (!x) return;
	pvs__extproj_prep_destroy(x->prep);
	pvs__free(&x->allocator, x, sizeof(*x), 16);
}

PVS__STATIC const pvs__bake_method pvs__extproj_method = {PVS_METHOD_EXTPROJ,
														  PVS__METHOD_CONSERVATIVE | PVS__METHOD_AUTO_DEFAULT,
														  1,
														  pvs__extproj_bake_check,
														  pvs__extproj_bake_prepare,
														  pvs__extproj_bake_applies,
														  pvs__extproj_bake_cell,
														  NULL,
														  pvs__extproj_bake_destroy};

/* ---- shrink (Wonka, Wimmer, Schmalstieg 2000) ---- */

/* ---- the 2.5D path: per-sample occlusion horizons ----

   Wonka 2000 §2.1: the cell's PVS is the union of its samples'. A sample's visibility is an occlusion horizon over
   PVS__HZ_BINS angular bins around the eye (height H): a facade of height T at ground distance dc hides a point at
   distance r > dc and height z when (z - H) / r < (T - H) / dc. A bin one chain of shrunk facades covers wholly
   (shared corners: no crack) is crossed by all its rays between dmin and dmax, so beyond dmax it hides below slope
   (T - H) / dmax (T >= H) or (T - H) / dmin (T < H); per bin a staircase of (distance, slope) steps keeps the best.
   A box is hidden when every bin its ground rectangle touches has, at its least distance, a slope above its steepest
   sight line. Occluders go front to back, occluded ones skipped (§3.4). Angles are bin-exact, the rest rounded
   safe. */

/* The horizon's angular resolution (0.23 degree at 1536); finer bins, an eps / 2 column grid, more steps and
   per-triangle tests gained nothing (tests/BENCHMARKS.md, shrink). */
#define PVS__HZ_BINS 1536
#define PVS__HZ_STEPS 6

/* Angles are pseudo-angles in [0, 4) (the "diamond angle": monotone in the true angle, a quarter turn per unit, no
   trigonometry); bin b covers [4 b / BINS, 4 (b + 1) / BINS). */
typedef struct pvs__hz {
	double eu, ev, H, w;                         /* the eye; bin width (pseudo-angle) */
	double dir[PVS__HZ_BINS + 1][2];             /* ray direction at each bin boundary (unnormalized) */
	double dlen[PVS__HZ_BINS + 1];               /* its length */
	uint8_t nstep[PVS__HZ_BINS];
	float step_r[PVS__HZ_BINS][PVS__HZ_STEPS];   /* ascending */
	float step_s[PVS__HZ_BINS][PVS__HZ_STEPS];   /* ascending with r (dominated steps dropped) */
	/* per chain */
	uint32_t stamp[PVS__HZ_BINS], cur;
	uint8_t full[PVS__HZ_BINS], npart[PVS__HZ_BINS];
	double plo[PVS__HZ_BINS][4], phi[PVS__HZ_BINS][4], dmax[PVS__HZ_BINS], dmin[PVS__HZ_BINS];
	uint16_t touched[PVS__HZ_BINS];
	uint32_t ntouched;
} pvs__hz;

PVS__STATIC double pvs__hz_angle(double x, double y) {
	double a;
	if (y >= 0.0) a = x >= 0.0 ? y / (x + y) : 1.0 - x / (y - x);
	else a = x < 0.0 ? 2.0 - y / (-x - y) : 3.0 + x / (x - y);
	return a >= 0.0 && a < 4.0 ? a : 0.0;
}
PVS__STATIC void pvs__hz_init(pvs__hz *z) {
	int32_t k;
	z->w = 4.0 / PVS__HZ_BINS;
	for (k = 0; k <= PVS__HZ_BINS; ++k) {
		double a = k == PVS__HZ_BINS ? 0.0 : k * z->w, t = a - floor(a);
		int q = (int)floor(a);
		double *d = z->dir[k];
		if (q == 0) { d[0] = 1.0 - t; d[1] = t; }
		else if (q == 1) { d[0] = -t; d[1] = 1.0 - t; }
		else if (q == 2) { d[0] = -(1.0 - t); d[1] = -t; }
		else { d[0] = t; d[1] = -(1.0 - t); }
		z->dlen[k] = sqrt(d[0] * d[0] + d[1] * d[1]);
	}
}
PVS__STATIC double pvs__hz_lo(const pvs__hz *z, int32_t b) { return b * z->w; }
PVS__STATIC double pvs__hz_hi(const pvs__hz *z, int32_t b) { return b + 1 == PVS__HZ_BINS ? 4.0 : (b + 1) * z->w; }
/* The bin of pseudo-angle a, consistent with pvs__hz_lo / pvs__hz_hi (w is no power of two: floor(a / w) can put an
   angle just below b w in bin b, so a facade ending there would claim bin b - 1). */
PVS__STATIC int32_t pvs__hz_bin(const pvs__hz *z, double a) {
	int32_t b = (int32_t)floor(a / z->w);
	b = b < 0 ? 0 : b >= PVS__HZ_BINS ? PVS__HZ_BINS - 1 : b;
	if (b > 0 && a < pvs__hz_lo(z, b)) --b;
	else if (b + 1 < PVS__HZ_BINS && a >= pvs__hz_hi(z, b)) ++b;
	return b;
}

/* Distance from the eye along bin boundary k's ray to line p-q (relative ground points); -1 if parallel. */
PVS__STATIC double pvs__hz_ray(const pvs__hz *z, int32_t k, const double p[2], const double q[2]) {
	double dx = z->dir[k][0], dy = z->dir[k][1], ex = q[0] - p[0], ey = q[1] - p[1], den = dx * ey - dy * ex;
	if (den == 0.0) return -1.0;
	return (p[0] * ey - p[1] * ex) / den * z->dlen[k];
}

/* Bin b's part [a0, a1] a facade covers, crossed at distances d0, d1, its line nearest at angle afoot, distance dfoot;
   `front`: the eye on its outer side. */
PVS__STATIC void pvs__hz_piece(pvs__hz *z, int32_t b, double a0, double a1, double d0, double d1, double dfoot,
							   double afoot, int front) {
	double lo, hi;
	if (!(d0 > 0.0) || !(d1 > 0.0)) return;
	hi = pvs__dmax(d0, d1) * (1.0 + 1e-9);
	lo = pvs__dmin(d0, d1);
	if (afoot >= a0 && afoot <= a1) lo = pvs__dmin(lo, dfoot);
	lo *= 1.0 - 1e-9;
	if (z->stamp[b] != z->cur) {
		z->stamp[b] = z->cur;
		z->full[b] = 0;
		z->npart[b] = 0;
		z->dmax[b] = front ? hi : 0.0;
		z->dmin[b] = front ? lo : DBL_MAX;
		z->touched[z->ntouched++] = (uint16_t)b;
	} else {
		if (front && hi > z->dmax[b]) z->dmax[b] = hi;
		if (front && lo < z->dmin[b]) z->dmin[b] = lo;
	}
	if (a0 <= pvs__hz_lo(z, b) && a1 >= pvs__hz_hi(z, b)) z->full[b] = 1;
	else if (!z->full[b]) { /* covered parts: up to 4 disjoint intervals, merged where they meet */
		uint32_t i, n = z->npart[b];
		double *L = z->plo[b], *R = z->phi[b];
		for (i = 0; i < n;) {
			if (a0 <= R[i] && a1 >= L[i]) { /* absorb and look again */
				a0 = pvs__dmin(a0, L[i]);
				a1 = pvs__dmax(a1, R[i]);
				L[i] = L[n - 1];
				R[i] = R[n - 1];
				--n;
			} else ++i;
		}
		if (n < 4) { L[n] = a0; R[n] = a1; ++n; }
		else { /* full: keep the longest (less coverage: conservative) */
			uint32_t sh = 0;
			for (i = 1; i < 4; ++i)
				if (R[i] - L[i] < R[sh] - L[sh]) sh = i;
			if (a1 - a0 > R[sh] - L[sh]) { L[sh] = a0; R[sh] = a1; }
		}
		z->npart[b] = (uint8_t)n;
		for (i = 0; i < n; ++i)
			if (L[i] <= pvs__hz_lo(z, b) && R[i] >= pvs__hz_hi(z, b)) z->full[b] = 1;
	}
}

/* Adds facade p-q (world ground points) of the current chain. */
PVS__STATIC void pvs__hz_facade(pvs__hz *z, const float *pf, const float *qf) {
	double p[2], q[2], cr, a, b, fx, fy, t, afoot, dfoot, len2, da, db;
	int32_t b0, b1, k;
	int front;
	p[0] = pf[0] - z->eu; p[1] = pf[1] - z->ev;
	q[0] = qf[0] - z->eu; q[1] = qf[1] - z->ev;
	cr = p[0] * q[1] - p[1] * q[0];
	len2 = (q[0] - p[0]) * (q[0] - p[0]) + (q[1] - p[1]) * (q[1] - p[1]);
	if (!(pvs__dabs(cr) > 1e-12 * (p[0] * p[0] + p[1] * p[1] + q[0] * q[0] + q[1] * q[1]))) return; /* seen edge-on */
	/* the occluder lies left of p -> q; only facades seen from outside matter: a sight line enters through one */
	front = cr < 0.0;
	if (!front) return;
	if (cr < 0.0) { double tt[2]; tt[0] = p[0]; tt[1] = p[1]; p[0] = q[0]; p[1] = q[1]; q[0] = tt[0]; q[1] = tt[1]; }
	/* counter-clockwise from p (angle a) to q (angle b), under a half turn */
	a = pvs__hz_angle(p[0], p[1]);
	b = pvs__hz_angle(q[0], q[1]);
	da = sqrt(p[0] * p[0] + p[1] * p[1]);
	db = sqrt(q[0] * q[0] + q[1] * q[1]);
	/* the line's nearest point to the eye */
	t = -(p[0] * (q[0] - p[0]) + p[1] * (q[1] - p[1])) / len2;
	fx = p[0] + t * (q[0] - p[0]);
	fy = p[1] + t * (q[1] - p[1]);
	dfoot = sqrt(fx * fx + fy * fy);
	afoot = t > 0.0 && t < 1.0 ? pvs__hz_angle(fx, fy) : -1.0;
	b0 = pvs__hz_bin(z, a);
	b1 = pvs__hz_bin(z, b);
	if (b < a) b1 += PVS__HZ_BINS; /* across angle 0 */
	{
		double d1 = da; /* the previous bin's upper crossing is this one's lower */
		for (k = b0; k <= b1; ++k) {
			int32_t bk = k % PVS__HZ_BINS, lo_at_start = k == b0, hi_at_end = k == b1;
			double s0 = lo_at_start ? a : pvs__hz_lo(z, bk), s1 = hi_at_end ? b : pvs__hz_hi(z, bk), d0 = d1;
			d1 = hi_at_end ? db : pvs__hz_ray(z, bk + 1, p, q);
			if (k == b0 && k == b1 && b < a) continue; /* cannot happen: a half turn at most */
			pvs__hz_piece(z, bk, s0, s1, d0, d1, dfoot, afoot, front);
		}
	}
}

/* Inserts step (r, s) into bin b: from distance r on the slope is at least s. */
PVS__STATIC void pvs__hz_insert(pvs__hz *z, int32_t b, float r, float s) {
	uint32_t n = z->nstep[b], i, j;
	float *R = z->step_r[b], *S = z->step_s[b];
	for (i = 0; i < n; ++i)
		if (R[i] <= r && S[i] >= s) return; /* dominated */
	for (i = 0, j = 0; i < n; ++i)
		if (!(R[i] >= r && S[i] <= s)) { R[j] = R[i]; S[j] = S[i]; ++j; }
	n = j;
	if (n == PVS__HZ_STEPS) --n; /* full: forget the farthest (still conservative) */
	for (i = n; i > 0 && R[i - 1] > r; --i) { R[i] = R[i - 1]; S[i] = S[i - 1]; }
	R[i] = r;
	S[i] = s;
	z->nstep[b] = (uint8_t)(n + 1);
}

/* The best slope of bin b for points at distance >= d (-FLT_MAX: none). */
PVS__STATIC float pvs__hz_query(const pvs__hz *z, int32_t b, double d) {
	uint32_t i, n = z->nstep[b];
	float best = -FLT_MAX;
	/* steps ascend in distance and slope: the last one not beyond d is the best (branch-free: faster) */
	for (i = 0; i < n; ++i) best = (double)z->step_r[b][i] <= d ? z->step_s[b][i] : best;
	return best;
}

/* Bins [*b0, *b1] (b1 >= BINS when wrapping) and least and greatest ground distance of rectangle u0..u1, v0..v1 from
   the eye; 0 if the eye is inside or on it. The span runs counter-clockwise between silhouette corners. */
PVS__STATIC int pvs__hz_rect(const pvs__hz *z, double u0, double v0, double u1, double v1, int32_t *b0, int32_t *b1,
							 double *dmin, double *dmax) {
	double x0 = u0 - z->eu, x1 = u1 - z->eu, y0 = v0 - z->ev, y1 = v1 - z->ev, nx, ny, fx, fy, sx, sy, ex, ey, as, ae;
	int rx = x0 > 0.0 ? 0
		: x1 < 0.0    ? 2
					  : 1,
		ry = y0 > 0.0 ? 0
		: y1 < 0.0    ? 2
					  : 1;
	if (rx == 1 && ry == 1) return 0;
	nx = rx == 0 ? x0 : rx == 2 ? -x1 : 0.0;
	ny = ry == 0 ? y0 : ry == 2 ? -y1 : 0.0;
	fx = pvs__dmax(pvs__dabs(x0), pvs__dabs(x1));
	fy = pvs__dmax(pvs__dabs(y0), pvs__dabs(y1));
	*dmin = sqrt(nx * nx + ny * ny) * (1.0 - 1e-9);
	*dmax = sqrt(fx * fx + fy * fy) * (1.0 + 1e-9);
	if (rx == 0) {
		if (ry == 0) { sx = x1; sy = y0; ex = x0; ey = y1; }
		else if (ry == 1) { sx = x0; sy = y0; ex = x0; ey = y1; }
		else { sx = x0; sy = y0; ex = x1; ey = y1; }
	} else if (rx == 1) {
		if (ry == 0) { sx = x1; sy = y0; ex = x0; ey = y0; }
		else { sx = x0; sy = y1; ex = x1; ey = y1; }
	} else {
		if (ry == 0) { sx = x1; sy = y1; ex = x0; ey = y0; }
		else if (ry == 1) { sx = x1; sy = y1; ex = x1; ey = y0; }
		else { sx = x0; sy = y1; ex = x1; ey = y0; }
	}
	as = pvs__hz_angle(sx, sy) - 1e-12;
	ae = pvs__hz_angle(ex, ey) + 1e-12;
	if (as < 0.0) as += 4.0;
	if (ae < as) ae += 4.0;
	*b0 = pvs__hz_bin(z, as);
	*b1 = (int32_t)floor(ae / z->w);
	if (*b1 < *b0) *b1 = *b0;
	return 1;
}

/* Distance along boundary ray k from the eye into the rectangle (relative coordinates); DBL_MAX if none. */
PVS__STATIC double pvs__hz_enter(const pvs__hz *z, int32_t k, double x0, double y0, double x1, double y1) {
	double dx = z->dir[k][0], dy = z->dir[k][1], t0 = 0.0, t1 = DBL_MAX;
	if (dx != 0.0) {
		double a = x0 / dx, b = x1 / dx;
		t0 = pvs__dmax(t0, pvs__dmin(a, b));
		t1 = pvs__dmin(t1, pvs__dmax(a, b));
	} else if (x0 > 0.0 || x1 < 0.0) return DBL_MAX;
	if (dy != 0.0) {
		double a = y0 / dy, b = y1 / dy;
		t0 = pvs__dmax(t0, pvs__dmin(a, b));
		t1 = pvs__dmin(t1, pvs__dmax(a, b));
	} else if (y0 > 0.0 || y1 < 0.0) return DBL_MAX;
	return t1 >= t0 ? t0 * z->dlen[k] : DBL_MAX;
}

/* 1 if the box may be visible: some bin its ground rectangle touches lacks, from its least distance there on, a slope
   above the box's steepest sight line. */
PVS__STATIC int pvs__hz_test_box(const pvs__hz *z, const pvs_box *bx, int u, int v, uint32_t up) {
	int32_t b0, b1, k;
	double dmin, dmax, need, top = bx->max[up], x0, y0, x1, y1, ca[4], near_a;
	if (!pvs__hz_rect(z, bx->min[u], bx->min[v], bx->max[u], bx->max[v], &b0, &b1, &dmin, &dmax)) return 1;
	if (!(dmin > 0.0)) return 1;
	need = top >= z->H ? (top - z->H) / dmin : (top - z->H) / dmax;
	need += 1e-9 * (pvs__dabs(need) + 1e-30);
	if (b1 - b0 < 3) {
		for (k = b0; k <= b1; ++k)
			if (!((double)pvs__hz_query(z, k % PVS__HZ_BINS, dmin) > need)) return 1;
		return 0;
	}
	/* wide boxes: per bin the rectangle's least distance in its wedge (at the rays, inner corners, nearest point) */
	x0 = bx->min[u] - z->eu; x1 = bx->max[u] - z->eu; y0 = bx->min[v] - z->ev; y1 = bx->max[v] - z->ev;
	ca[0] = pvs__hz_angle(x0, y0);
	ca[1] = pvs__hz_angle(x1, y0);
	ca[2] = pvs__hz_angle(x1, y1);
	ca[3] = pvs__hz_angle(x0, y1);
	{
		double nx = x0 > 0.0 ? x0 : x1 < 0.0 ? x1 : 0.0, ny = y0 > 0.0 ? y0 : y1 < 0.0 ? y1 : 0.0;
		near_a = pvs__hz_angle(nx, ny);
	}
	{
		/* bins interleaved (every 8th first): a visible box's open run is found early */
		static const int32_t order[8] = {0, 4, 2, 6, 1, 5, 3, 7};
		int32_t o8;
		for (o8 = 0; o8 < 8; ++o8)
			for (k = b0 + order[o8]; k <= b1; k += 8) {
				int32_t bk = k % PVS__HZ_BINS, c;
				double lo, hi, d, need_b;
				if ((double)pvs__hz_query(z, bk, dmin) > need) continue;
				lo = pvs__hz_lo(z, bk);
				hi = pvs__hz_hi(z, bk);
				d = pvs__dmin(pvs__hz_enter(z, bk, x0, y0, x1, y1), pvs__hz_enter(z, bk + 1, x0, y0, x1, y1));
				for (c = 0; c < 4; ++c)
					if (ca[c] >= lo && ca[c] <= hi) {
						double cx = c == 0 || c == 3 ? x0 : x1, cy = c < 2 ? y0 : y1;
						d = pvs__dmin(d, sqrt(cx * cx + cy * cy));
					}
				if (near_a >= lo && near_a <= hi) d = dmin;
				if (d == DBL_MAX) d = dmin; /* rounding at the span's ends */
				d = pvs__dmax(d * (1.0 - 1e-9), dmin);
				need_b = top >= z->H ? (top - z->H) / d : need;
				need_b += 1e-9 * (pvs__dabs(need_b) + 1e-30);
				if (!((double)pvs__hz_query(z, bk, d) > need_b)) return 1;
			}
	}
	return 0;
}

/* Adds a chain of height top (closed: back to its first point). */
PVS__STATIC void pvs__hz_chain(pvs__hz *z, const pvs_facade_chain *ch) {
	uint32_t i, n = ch->point_count, segs = ch->closed ? n : n - 1;
	double T = ch->top;
	z->cur++;
	z->ntouched = 0;
	for (i = 0; i < segs; ++i) pvs__hz_facade(z, ch->points + 2 * i, ch->points + 2 * ((i + 1) % n));
	for (i = 0; i < z->ntouched; ++i) {
		int32_t b = z->touched[i];
		double sl;
		if (!z->full[b]) continue;
		if (!(z->dmax[b] > 0.0)) continue; /* cannot happen when full */
		if (T >= z->H) sl = (T - z->H) / z->dmax[b];
		else {
			if (!(z->dmin[b] > 0.0)) continue;
			sl = (T - z->H) / z->dmin[b];
		}
		/* to float toward the safe side: a margin far above float's half ulp (6e-8) */
		pvs__hz_insert(z, b, (float)(z->dmax[b] * (1.0 + 1e-6)), (float)(sl - 1e-6 * pvs__dabs(sl) - 1e-30));
	}
}

typedef struct pvs__shrink_walk {
	const pvs_scene *scene;
	const pvs__hz *hz;
	const pvs_box *cell;
	pvs_word *visible;
	int u, v;
} pvs__shrink_walk;

/* 1 if the box's ground rectangle meets the cell's. */
PVS__STATIC int pvs__shrink_near(const pvs__shrink_walk *w, const pvs_box *b) {
	return b->min[w->u] <= w->cell->max[w->u] && b->max[w->u] >= w->cell->min[w->u] &&
		b->min[w->v] <= w->cell->max[w->v] && b->max[w->v] >= w->cell->min[w->v];
}

PVS__STATIC double pvs__hz_dist2(const pvs__hz *z, const pvs_box *b, int u, int v) {
	double du = pvs__dmax(0.0, pvs__dmax(b->min[u] - z->eu, z->eu - b->max[u])),
		   dv = pvs__dmax(0.0, pvs__dmax(b->min[v] - z->ev, z->ev - b->max[v]));
	return du * du + dv * dv;
}

/* The sample's horizon: the chains' hierarchy nearer child first, hidden ones skipped (§3.4). */
PVS__STATIC void pvs__shrink_horizon(const pvs_occluders *o, pvs__hz *hz, uint32_t *stack, int u, int v,
									 pvs_shrink_stats *st) {
	const pvs__obvh *h = &o->chain_bvh;
	uint32_t sp = 0, k, up = o->scene->up_axis;
	if (!h->node_count) return;
	stack[sp++] = 0;
	while (sp) {
		const pvs__obvh_node *nd = h->nodes + stack[--sp];
		if (!pvs__hz_test_box(hz, &nd->box, u, v, up)) continue;
		if (nd->count) {
			for (k = nd->first; k < nd->first + nd->count; ++k) {
				uint32_t c = h->items[k];
				if (!pvs__hz_test_box(hz, o->chain_boxes + c, u, v, up)) continue;
				pvs__hz_chain(hz, o->chains + c);
				++st->occluders_drawn;
			}
		} else {
			int near0 = pvs__hz_dist2(hz, &h->nodes[nd->first].box, u, v) <=
				pvs__hz_dist2(hz, &h->nodes[nd->first + 1].box, u, v);
			stack[sp++] = near0 ? nd->first + 1 : nd->first;
			stack[sp++] = near0 ? nd->first : nd->first + 1;
		}
	}
}

/* Marks ob visible, off the count of every node above it. */
PVS__STATIC void pvs__shrink_found(const pvs_occluders *o, pvs__shrink_walk *w, uint32_t *remaining, uint32_t ob) {
	uint32_t nd;
	pvs_bitset_set(w->visible, ob);
	for (nd = o->bvh.leaf_of[ob]; nd != 0xffffffffu; nd = o->bvh.nodes[nd].parent) --remaining[nd];
}

/* Objects meeting the cell or under its top face: visible unsampled. */
PVS__STATIC void pvs__shrink_walk_near(const pvs_occluders *o, pvs__shrink_walk *w, uint32_t *remaining,
									   uint32_t *stack) {
	uint32_t sp = 0, k;
	if (!o->bvh.node_count) return;
	stack[sp++] = 0;
	while (sp) {
		const pvs__obvh_node *nd = o->bvh.nodes + stack[--sp];
		if (!pvs__shrink_near(w, &nd->box)) continue;
		if (nd->count) {
			for (k = nd->first; k < nd->first + nd->count; ++k) {
				uint32_t ob = o->bvh.items[k];
				if (!pvs_bitset_test(w->visible, ob) && pvs__shrink_near(w, w->scene->object_boxes + ob))
					pvs__shrink_found(o, w, remaining, ob);
			}
		} else {
			stack[sp++] = nd->first;
			stack[sp++] = nd->first + 1;
		}
	}
}

/* A sample's walk over the object hierarchy, skipping nodes hidden from it (§3.4) or all found. */
PVS__STATIC void pvs__shrink_walk_sample(const pvs_occluders *o, pvs__shrink_walk *w, uint32_t *remaining,
										 uint32_t *stack) {
	uint32_t sp = 0, k, up = w->scene->up_axis;
	if (!o->bvh.node_count) return;
	stack[sp++] = 0;
	while (sp) {
		uint32_t id = stack[--sp];
		const pvs__obvh_node *nd = o->bvh.nodes + id;
		if (!remaining[id] || !pvs__hz_test_box(w->hz, &nd->box, w->u, w->v, up)) continue;
		if (nd->count) {
			for (k = nd->first; k < nd->first + nd->count; ++k) {
				uint32_t ob = o->bvh.items[k];
				if (!pvs_bitset_test(w->visible, ob) &&
					pvs__hz_test_box(w->hz, w->scene->object_boxes + ob, w->u, w->v, up))
					pvs__shrink_found(o, w, remaining, ob);
			}
		} else {
			stack[sp++] = nd->first;
			stack[sp++] = nd->first + 1;
		}
	}
}

/* §3: "sample points need only be placed on the edges of the top of the view cells". For a heightfield occluder O and
   a point P outside the cell's footprint R, say V on the top face (height H) sees P. In the vertical plane through P
   and V the ground segment crosses R's boundary at W'. If P is not above H, P-W' lies above P-V, so W' sees P; else
   moving V away from P to the boundary point W keeps P-W above P-V up to V and above H beyond, where no column of O in
   R reaches. O being the shrunk occluder's eps-neighbourhood (which no real sight line enters), the edges decide when
   no column within eps of R rises above H - eps (with the appendix's theorem). */
PVS__STATIC int pvs__shrink_edges_suffice(const pvs_occluders *o, const pvs_box *cell, int u, int v, uint32_t up) {
	const pvs__vx_cols *cm = &o->cols;
	uint32_t i0, i1, j0, j1, i, j;
	double top = (double)cell->max[up] - o->info.eps;
	pvs__vx_grange(&cm->grid, u, cell->min[u], cell->max[u], o->info.eps, &i0, &i1);
	pvs__vx_grange(&cm->grid, v, cell->min[v], cell->max[v], o->info.eps, &j0, &j1);
	for (j = j0; j <= j1; ++j)
		for (i = i0; i <= i1; ++i)
			if ((double)cm->top[(size_t)j * cm->nu + i] > top) return 0;
	return 1;
}

/* The 2.5D path (§3): samples on the cell's top face (a 2.5D occluder hides from a point only what it hides from all
   points above it): on its edges every 2 eps when pvs__shrink_edges_suffice allows, else a grid of spacing eps sqrt(2);
   per sample its horizon (§3.4) and the objects it may see. */
PVS__STATIC pvs_result pvs__shrink_2d5(const pvs_scene *s, const pvs_occluders *o, const pvs_box *cell,
									   pvs_word *visible, pvs_shrink_stats *st, pvs_error *err) {
	pvs__shrink_walk w;
	pvs__hz *hz;
	float eps = o->info.eps;
	double spacing;
	uint32_t *remaining, *stack, *cstack, nnodes = o->bvh.node_count ? o->bvh.node_count : 1;
	uint32_t ncnodes = o->chain_bvh.node_count ? o->chain_bvh.node_count : 1;
	uint32_t nu, nv, a, b, up = s->up_axis;
	int edges, u, v;
	pvs__ground_axes(up, &u, &v);
	edges = pvs__shrink_edges_suffice(o, cell, u, v, up);
	spacing = edges ? 2.0 * eps * (1.0 - 1e-6) : 1.41 * eps;
	nu = (uint32_t)ceil(((double)cell->max[u] - cell->min[u]) / spacing) + 1u;
	nv = (uint32_t)ceil(((double)cell->max[v] - cell->min[v]) / spacing) + 1u;
	if (nu > 4096u || nv > 4096u)
		return pvs__fail(err, PVS_ERROR_UNSUPPORTED, -1, 0, "a cell of %u x %u samples: eps too small for the cell", nu,
						 nv);
	hz = (pvs__hz *)pvs__alloc(&o->allocator, sizeof(pvs__hz), 16);
	remaining = (uint32_t *)pvs__alloc_array(&o->allocator, nnodes, sizeof(uint32_t));
	stack = (uint32_t *)pvs__alloc_array(&o->allocator, nnodes, sizeof(uint32_t));
	cstack = (uint32_t *)pvs__alloc_array(&o->allocator, ncnodes, sizeof(uint32_t));
	if (!hz || !remaining || !stack || !cstack) {
		pvs__free(&o->allocator, hz, sizeof(pvs__hz), 16);
		pvs__free_array(&o->allocator, remaining, nnodes, sizeof(uint32_t));
		pvs__free_array(&o->allocator, stack, nnodes, sizeof(uint32_t));
		pvs__free_array(&o->allocator, cstack, ncnodes, sizeof(uint32_t));
		return pvs__fail(err, PVS_ERROR_OUT_OF_MEMORY, -1, 0, "shrink scratch");
	}
	if (o->bvh.node_count) {
		uint32_t ob, nd;
		memcpy(remaining, o->bvh.count_below, o->bvh.node_count * sizeof(uint32_t));
		/* objects set on entry: off the counts, so nodes holding only them are skipped */
		for (ob = pvs_bitset_next(visible, s->object_count, 0); ob < s->object_count;
			 ob = pvs_bitset_next(visible, s->object_count, ob + 1))
			for (nd = o->bvh.leaf_of[ob]; nd != 0xffffffffu; nd = o->bvh.nodes[nd].parent) --remaining[nd];
	}
	memset(hz, 0, sizeof(*hz));
	pvs__hz_init(hz);
	w.scene = s;
	w.hz = hz;
	w.cell = cell;
	w.visible = visible;
	w.u = u;
	w.v = v;
	hz->H = cell->max[up];
	pvs__shrink_walk_near(o, &w, remaining, stack);
	for (b = 0; b < nv; ++b)
		for (a = 0; a < nu; ++a) {
			if (edges && a > 0 && a + 1 < nu && b > 0 && b + 1 < nv) continue;
			hz->eu = a + 1 == nu
				? cell->max[u]
				: cell->min[u] + (double)a * ((double)cell->max[u] - cell->min[u]) / (nu > 1 ? nu - 1 : 1);
			hz->ev = b + 1 == nv
				? cell->max[v]
				: cell->min[v] + (double)b * ((double)cell->max[v] - cell->min[v]) / (nv > 1 ? nv - 1 : 1);
			memset(hz->nstep, 0, sizeof(hz->nstep));
			pvs__shrink_horizon(o, hz, cstack, u, v, st);
			++st->samples;
			pvs__shrink_walk_sample(o, &w, remaining, stack);
		}
	pvs__free(&o->allocator, hz, sizeof(pvs__hz), 16);
	pvs__free_array(&o->allocator, remaining, nnodes, sizeof(uint32_t));
	pvs__free_array(&o->allocator, stack, nnodes, sizeof(uint32_t));
	pvs__free_array(&o->allocator, cstack, ncnodes, sizeof(uint32_t));
	return PVS_OK;
}

#define PVS__SHRINK_RES 64u

/* 1 when box bx may reach into the view from p along axis dax (positive when pos): lateral offsets within 1.1 x the
   distance ahead, a superset of the 1.6 rad square frustum with room for rounding. *dn, *df: its least and greatest
   distance ahead. */
PVS__STATIC int pvs__shrink_in_view(const pvs_box *bx, const float *p, int dax, int pos, double *dn, double *df) {
	int l;
	double lim;
	if (pos) { *dn = (double)bx->min[dax] - p[dax]; *df = (double)bx->max[dax] - p[dax]; }
	else { *dn = (double)p[dax] - bx->max[dax]; *df = (double)p[dax] - bx->min[dax]; }
	if (!(*df > 0.0)) return 0;
	lim = 1.1 * *df;
	for (l = 0; l < 3; ++l)
		if (l != dax && ((double)bx->min[l] - p[l] > lim || (double)bx->max[l] - p[l] < -lim)) return 0;
	return 1;
}

/* Box bx's image from p along dax, lateral offset / distance ahead on the other axes: r[0..1] least, r[2..3] greatest.
   0 if within 1e-3 of its depth of the eye plane. */
PVS__STATIC int pvs__shrink_view_rect(const pvs_box *bx, const float *p, int dax, double dn, double df, double r[4]) {
	int k;
	if (!(dn > 1e-3 * df)) return 0;
	for (k = 0; k < 2; ++k) {
		int l = (dax + 1 + k) % 3;
		double lo = (double)bx->min[l] - p[l], hi = (double)bx->max[l] - p[l];
		r[k] = pvs__dmin(lo / dn, lo / df);
		r[2 + k] = pvs__dmax(hi / dn, hi / df);
	}
	return 1;
}

/* The 3D path's per-cell state. */
typedef struct pvs__shrink3d {
	const pvs_scene *s;
	const pvs_occluders *o;
	pvs_raster *r;            /* PVS__SHRINK_RES square; the eroded boxes as one occluder mesh */
	float *pos;               /* 24 per eroded box: its corners */
	uint32_t *idx;            /* 36 per eroded box: its faces' triangles */
	uint32_t *sel;            /* 36 per eroded box: the boxes a view draws */
	uint32_t *cand;           /* per object: the objects a view tests */
	pvs_word *seen;           /* objects found visible (or set on entry) */
	float nearp;              /* the views' near plane */
	pvs_shrink_stats *st;
} pvs__shrink3d;

/* Into w->cand, the objects a view from p along dax can change (unseen, pvs__shrink_in_view); *far: their farthest
   distance ahead; crect: their images' union while *bounded stays 1. Returns the count. */
PVS__STATIC uint32_t pvs__shrink_candidates(pvs__shrink3d *w, const float *p, int dax, int pos, double *far,
											double crect[4], int *bounded) {
	const pvs_scene *s = w->s;
	uint32_t ob, ncand = 0;
	double brect[4];
	int k;
	for (ob = 0; ob < s->object_count; ++ob) {
		double dn, df;
		if (pvs_bitset_test(w->seen, ob) || !pvs__box_valid(s->object_boxes + ob)) continue;
		if (!pvs__shrink_in_view(s->object_boxes + ob, p, dax, pos, &dn, &df)) continue;
		w->cand[ncand++] = ob;
		if (df > *far) *far = df;
		if (*bounded && pvs__shrink_view_rect(s->object_boxes + ob, p, dax, dn, df, brect))
			for (k = 0; k < 2; ++k) {
				crect[k] = pvs__dmin(crect[k], brect[k]);
				crect[2 + k] = pvs__dmax(crect[2 + k], brect[2 + k]);
			}
		else *bounded = 0;
	}
	return ncand;
}

/* One view of the cube at sample p (§2.3), direction dir (axis dir / 2, positive if odd): candidates tested in
   occludee mode against the eroded boxes as one occluder mesh, only boxes nearer than the farthest candidate whose
   image meets theirs (no other changes a test); passing ones join w->seen. */
PVS__STATIC void pvs__shrink_view(pvs__shrink3d *w, const float *p, uint32_t dir) {
	const pvs_occluders *o = w->o;
	uint32_t i, nb = o->box_count, nsel = 0, ncand;
	int k, dax = (int)dir / 2, bounded = 1;
	double far = -1.0, crect[4] = {DBL_MAX, DBL_MAX, -DBL_MAX, -DBL_MAX}, brect[4];
	pvs_camera cam;
	float m[16];
	ncand = pvs__shrink_candidates(w, p, dax, dir & 1, &far, crect, &bounded);
	if (!ncand) return;
	for (i = 0; i < nb; ++i) {
		double dn, df;
		if (!pvs__shrink_in_view(o->boxes + i, p, dax, dir & 1, &dn, &df) || dn > far) continue;
		/* a box whose image misses the candidates' (a few pixels' margin) covers no pixel they read */
		if (bounded && pvs__shrink_view_rect(o->boxes + i, p, dax, dn, df, brect) &&
			(brect[0] > crect[2] + 0.1 || brect[2] < crect[0] - 0.1 || brect[1] > crect[3] + 0.1 ||
			 brect[3] < crect[1] - 0.1))
			continue;
		memcpy(w->sel + 36 * (size_t)nsel, w->idx + 36 * (size_t)i, 36 * sizeof(uint32_t));
		++nsel;
	}
	w->st->occluders_drawn += nsel;
	memset(&cam, 0, sizeof(cam));
	for (k = 0; k < 3; ++k) cam.eye[k] = p[k];
	cam.forward[dax] = dir & 1 ? 1.0f : -1.0f;
	cam.up[(dax + 1) % 3] = 1.0f;
	cam.fov_y = 1.6f; /* a little over 90 degrees: the six frusta overlap */
	cam.near_plane = w->nearp;
	if (pvs_camera_matrix(&cam, 1.0f, m) != PVS_OK) return;
	pvs_raster_clear(w->r);
	pvs_raster_set_matrix(w->r, m);
	if (nsel) pvs_raster_mesh(w->r, w->pos, 8 * nb, w->sel, 12 * nsel); /* no cracks along the faces' diagonals */
	pvs_raster_build_pyramid(w->r);
	for (i = 0; i < ncand; ++i)
		if (pvs_raster_test_box(w->r, w->s->object_boxes + w->cand[i])) pvs_bitset_set(w->seen, w->cand[i]);
}

/* Samples of cell face `face` (axis face / 2, max side if odd) at spacing <= `spacing`, corners included, each looking
   six ways; UNSUPPORTED past 1024 a side. */
PVS__STATIC pvs_result pvs__shrink_face(pvs__shrink3d *w, const pvs_box *cell, uint32_t face, float spacing,
										pvs_error *err) {
	int ax = (int)face / 2, a1 = (ax + 1) % 3, a2 = (ax + 2) % 3;
	uint32_t n1 = (uint32_t)ceil(((double)cell->max[a1] - cell->min[a1]) / spacing) + 1u;
	uint32_t n2 = (uint32_t)ceil(((double)cell->max[a2] - cell->min[a2]) / spacing) + 1u;
	uint32_t a, b, dir;
	if (n1 > 1024u || n2 > 1024u)
		return pvs__fail(err, PVS_ERROR_UNSUPPORTED, -1, 0,
						 "a cell face of %u x %u samples: eps too small for the cell", n1, n2);
	for (a = 0; a < n1; ++a)
		for (b = 0; b < n2; ++b) {
			float p[3];
			p[ax] = face & 1 ? cell->max[ax] : cell->min[ax];
			p[a1] = n1 > 1 ? cell->min[a1] + (float)((double)a * ((double)cell->max[a1] - cell->min[a1]) / (n1 - 1))
						   : cell->min[a1];
			p[a2] = n2 > 1 ? cell->min[a2] + (float)((double)b * ((double)cell->max[a2] - cell->min[a2]) / (n2 - 1))
						   : cell->min[a2];
			if (a + 1 == n1) p[a1] = cell->max[a1];
			if (b + 1 == n2) p[a2] = cell->max[a2];
			++w->st->samples;
			for (dir = 0; dir < 6; ++dir) pvs__shrink_view(w, p, dir);
		}
	return PVS_OK;
}

/* The 3D path (§2.1, 2.3): samples on the cell's six faces at spacing <= eps sqrt(2) (sight lines from inside leave
   through the boundary, all within eps of a sample), each a cube of six depth maps of the eroded boxes; the PVS is
   their union. Objects within twice the near distance are set (the cube sees nothing nearer than its near plane). */
PVS__STATIC pvs_result pvs__shrink_3d(const pvs_scene *s, const pvs_occluders *o, const pvs_box *cell,
									  pvs_word *visible, pvs_shrink_stats *st, pvs_error *err) {
	pvs_raster_desc rd;
	pvs__shrink3d w;
	pvs_result res;
	float eps = o->info.eps, spacing = 1.4f * eps;
	uint32_t nb = o->box_count, i, face, ob;
	size_t words = PVS_BITSET_WORDS(s->object_count);
	static const uint32_t quad[36] = {0, 1, 3, 0, 3, 2, 4, 6, 7, 4, 7, 5, 0, 4, 5, 0, 5, 1,
									  2, 3, 7, 2, 7, 6, 0, 2, 6, 0, 6, 4, 1, 5, 7, 1, 7, 3};
	pvs_box grown;
	int k;
	memset(&w, 0, sizeof(w));
	w.s = s;
	w.o = o;
	w.st = st;
	w.nearp = 0.05f * eps;
	memset(&rd, 0, sizeof(rd));
	rd.width = rd.height = PVS__SHRINK_RES;
	rd.max_mesh_triangles = nb ? (nb < 4096u ? 12 * nb : 49152u) : 12u; /* the boxes as one occluder mesh */
	rd.allocator = o->allocator;
	res = pvs_raster_create(&rd, &w.r, err);
	if (res != PVS_OK) return res;
	w.pos = (float *)pvs__alloc_array(&o->allocator, (size_t)(nb ? nb : 1) * 24, sizeof(float));
	w.idx = (uint32_t *)pvs__alloc_array(&o->allocator, (size_t)(nb ? nb : 1) * 36, sizeof(uint32_t));
	w.seen = (pvs_word *)pvs__alloc_array(&o->allocator, words ? words : 1, sizeof(pvs_word));
	w.sel = (uint32_t *)pvs__alloc_array(&o->allocator, (size_t)(nb ? nb : 1) * 36, sizeof(uint32_t));
	w.cand = (uint32_t *)pvs__alloc_array(&o->allocator, s->object_count ? s->object_count : 1, sizeof(uint32_t));
	if (!w.pos || !w.idx || !w.seen || !w.sel || !w.cand) {
		res = pvs__fail(err, PVS_ERROR_OUT_OF_MEMORY, -1, 0, "shrink 3D scratch");
		goto done;
	}
	memset(w.seen, 0, (words ? words : 1) * sizeof(pvs_word));
	memcpy(w.seen, visible, words * sizeof(pvs_word)); /* objects set on entry are not tested */
	for (i = 0; i < nb; ++i) {
		const pvs_box *bx = o->boxes + i;
		uint32_t c;
		for (c = 0; c < 8; ++c) {
			w.pos[24 * i + 3 * c + 0] = c & 1 ? bx->max[0] : bx->min[0];
			w.pos[24 * i + 3 * c + 1] = c & 2 ? bx->max[1] : bx->min[1];
			w.pos[24 * i + 3 * c + 2] = c & 4 ? bx->max[2] : bx->min[2];
		}
		for (c = 0; c < 36; ++c) w.idx[36 * i + c] = 8 * i + quad[c];
	}
	grown = *cell;
	for (k = 0; k < 3; ++k) {
		grown.min[k] -= 2.0f * w.nearp + 1e-4f * eps;
		grown.max[k] += 2.0f * w.nearp + 1e-4f * eps;
	}
	for (ob = 0; ob < s->object_count; ++ob)
		if (pvs__box_valid(s->object_boxes + ob) && pvs__box_overlap(s->object_boxes + ob, &grown))
			pvs_bitset_set(w.seen, ob);
	for (face = 0; face < 6; ++face) {
		res = pvs__shrink_face(&w, cell, face, spacing, err);
		if (res != PVS_OK) goto done;
	}
	for (ob = 0; ob < s->object_count; ++ob)
		if (pvs_bitset_test(w.seen, ob) && !(s->object_flags[ob] & PVS_OBJECT_OCCLUDER_ONLY))
			pvs_bitset_set(visible, ob);
	res = PVS_OK;
done:
	pvs__free_array(&o->allocator, w.pos, (size_t)(nb ? nb : 1) * 24, sizeof(float));
	pvs__free_array(&o->allocator, w.idx, (size_t)(nb ? nb : 1) * 36, sizeof(uint32_t));
	pvs__free_array(&o->allocator, w.seen, words ? words : 1, sizeof(pvs_word));
	pvs__free_array(&o->allocator, w.sel, (size_t)(nb ? nb : 1) * 36, sizeof(uint32_t));
	pvs__free_array(&o->allocator, w.cand, s->object_count ? s->object_count : 1, sizeof(uint32_t));
	pvs_raster_destroy(w.r);
	return res;
}

PVS_API pvs_result pvs_shrink_cell(const pvs_scene *s, const pvs_occluders *o, const pvs_box *cell,
								   pvs_shrink_mode mode, pvs_word *visible, pvs_shrink_stats *stats, pvs_error *err) {
	pvs_result res;
	pvs_shrink_stats st;
	memset(&st, 0, sizeof(st));
	if (stats) memset(stats, 0, sizeof(*stats));
	if (!s || !o || !cell || !visible || o->scene != s)
		return pvs__fail(err, PVS_ERROR_INVALID_ARGUMENT, -1, 0, "NULL argument or occluders of another scene");
	if (!pvs__box_valid(cell)) return pvs__fail(err, PVS_ERROR_BAD_CELL, -1, 0, "cell is not a valid box");
	if ((int)mode < 0 || mode >= PVS_SHRINK_MODE_COUNT)
		return pvs__fail(err, PVS_ERROR_INVALID_ARGUMENT, -1, 0, "unknown mode %d", (int)mode);
	if (mode == PVS_SHRINK_AUTO) mode = o->info.is_2d5 ? PVS_SHRINK_2D5 : PVS_SHRINK_3D;
	st.mode = mode;
	st.occluders = mode == PVS_SHRINK_2D5 ? o->chain_count : o->box_count;
	{
		/* a leaking cell the synthesis left out (or a box in one): the solid is proved for the others only */
		uint32_t i;
		int k;
		for (i = 0; i < o->info.excluded_cells && !st.excluded; ++i) {
			for (k = 0; k < 3; ++k)
				if (cell->min[k] < o->excluded_boxes[i].min[k] || cell->max[k] > o->excluded_boxes[i].max[k]) break;
			st.excluded = k == 3;
		}
	}
	if (st.occluders == 0 || st.excluded) {
		/* nothing survived the erosion, or a left-out cell: every drawable object is set */
		uint32_t i;
		for (i = 0; i < s->object_count; ++i)
			if (!(s->object_flags[i] & PVS_OBJECT_OCCLUDER_ONLY) && pvs__box_valid(s->object_boxes + i))
				pvs_bitset_set(visible, i);
		st.no_occluders = st.occluders == 0;
		if (stats) *stats = st;
		pvs__ok(err);
		return PVS_OK;
	}
	if (mode == PVS_SHRINK_2D5) res = pvs__shrink_2d5(s, o, cell, visible, &st, err);
	else res = pvs__shrink_3d(s, o, cell, visible, &st, err);
	if (res == PVS_OK) {
		uint32_t i;
		for (i = 0; i < s->object_count; ++i)
			st.hidden += !(s->object_flags[i] & PVS_OBJECT_OCCLUDER_ONLY) && pvs__box_valid(s->object_boxes + i) &&
				!pvs_bitset_test(visible, i);
		if (stats) *stats = st;
		pvs__ok(err);
	}
	return res;
}

/* ---- the SHRINK bake method (a row of >>bake's table) ---- */

/* Default eps: an eighth of the cells' median smallest ground extent (Wonka 2000 §4.1: 1 m for cells of several
   metres), in double (a cell 6e38 wide has no float extent), kept between a millionth of the scene's diagonal (no
   underflow to 0) and the diagonal. Any eps > 0 is conservative. */
PVS__STATIC double pvs__cell_ground_extent(const pvs_box *c, int u, int v) {
	double e = (double)c->max[u] - c->min[u], f = (double)c->max[v] - c->min[v];
	return f < e ? f : e;
}
PVS__STATIC float pvs__shrink_default_eps(const pvs_box *cells, uint32_t n, uint32_t up, const pvs_box *scene_bounds) {
	uint32_t i, j, below, equal, m = n < 2048u ? n : 2048u; /* median of the first 2048 cells, by counting */
	int u, v;
	double med = 0.0, diag = pvs__box_diagonal(scene_bounds), eps, lo, hi;
	pvs__ground_axes(up, &u, &v);
	for (i = 0; i < m; ++i) {
		double e = pvs__cell_ground_extent(cells + i, u, v);
		below = equal = 0;
		for (j = 0; j < m; ++j) {
			double f = pvs__cell_ground_extent(cells + j, u, v);
			below += f < e;
			equal += f == e;
		}
		if (2 * below <= m && 2 * (below + equal) > m) { med = e; break; }
	}
	if (!(med > 0.0)) med = 4.0;
	eps = 0.125 * med;
	lo = pvs__dmax(1e-6 * diag, 1e-30);
	hi = pvs__dmin(pvs__dmax(diag, lo), 1e30);
	return (float)(eps < lo ? lo : eps > hi ? hi : eps);
}

typedef struct pvs__shrink_bake {
	pvs_allocator allocator;
	pvs_occluders *occluders;
	pvs_occluders *occluders_leak; /* built with every cell seeding, for the cells the first left out */
	pvs_shrink_mode mode;
} pvs__shrink_bake;

/* Occluder synthesis over every cell of the bake, not only the shard's, so shards agree. */
PVS__STATIC pvs_result pvs__shrink_bake_prepare(pvs__bake_env *env, const pvs_bake_desc *desc, void **state,
												pvs_error *err) {
	pvs__shrink_bake *sh;
	pvs_occluders_desc od;
	pvs_result r;
	*state = NULL;
	if ((int)desc->shrink.mode < 0 || desc->shrink.mode >= PVS_SHRINK_MODE_COUNT)
		return pvs__fail(err, PVS_ERROR_INVALID_ARGUMENT, -1, 0, "unknown shrink mode %d", (int)desc->shrink.mode);
	sh = (pvs__shrink_bake *)pvs__alloc(&env->allocator, sizeof(pvs__shrink_bake), 16);
	*state = sh;
	if (!sh) return pvs__fail(err, PVS_ERROR_OUT_OF_MEMORY, -1, 0, "shrink");
	memset(sh, 0, sizeof(*sh));
	sh->allocator = env->allocator;
	if (!(env->eps > 0.0f)) {
		pvs_box sb = pvs_scene_bounds(desc->scene);
		env->eps = pvs__shrink_default_eps(desc->cells, desc->cell_count, pvs_scene_up_axis(desc->scene), &sb);
		if (env->flags & PVS_BAKE_PREVIEW) env->eps *= 2.0f;
	}
	memset(&od, 0, sizeof(od));
	od.scene = desc->scene;
	od.cells = desc->cells;
	od.cell_count = desc->cell_count;
	od.eps = env->eps;
	od.voxel_size = desc->shrink.voxel_size;
	od.allocator = env->allocator;
	r = pvs_occluders_create(&od, &sh->occluders, err);
	if (r != PVS_OK) return r;
	if (sh->occluders->info.excluded_cells) {
		/* leaking cells, left out of the proof, bake with occluders every cell seeded */
		od.flags = PVS_OCCLUDERS_KEEP_LEAKS;
		r = pvs_occluders_create(&od, &sh->occluders_leak, err);
		if (r != PVS_OK) return r;
	}
	sh->mode = desc->shrink.mode;
	if (sh->mode == PVS_SHRINK_AUTO) sh->mode = sh->occluders->info.is_2d5 ? PVS_SHRINK_2D5 : PVS_SHRINK_3D;
	return PVS_OK;
}

PVS__STATIC int pvs__shrink_bake_applies(const void *state, const char **why) {
	const pvs__shrink_bake *sh = (const pvs__shrink_bake *)state;
	if (!sh->occluders || !sh->occluders->info.eroded) {
		*why = "no occluder volume survives erosion by eps (thin walls or open geometry)";
		return 0;
	}
	*why = sh->mode == PVS_SHRINK_2D5 ? "volumes: 2.5D columns synthesized from closed geometry"
									  : "volumes: 3D boxes synthesized from closed geometry";
	return 1;
}

/* SHRINK tests only the candidates: the other drawable objects are set in `bits` first (the caller's intersection
   removes them); pvs_shrink_cell skips what is set. */
PVS__STATIC void pvs__shrink_bake_preset(const pvs__bake_env *env, const pvs_word *candidates, pvs_word *bits) {
	uint32_t i;
	if (!candidates) return;
	for (i = 0; i < env->object_count; ++i)
		if (!pvs_bitset_test(candidates, i) && !(env->scene->object_flags[i] & PVS_OBJECT_OCCLUDER_ONLY) &&
			pvs__box_valid(env->scene->object_boxes + i))
			pvs_bitset_set(bits, i);
}

PVS__STATIC pvs_result pvs__shrink_bake_cell(const pvs__bake_env *env, void *state, uint32_t task, uint32_t cell,
											 const pvs_box *box, const pvs_word *candidates, pvs_word *bits,
											 unsigned *flags, pvs_error *err) {
	const pvs__shrink_bake *sh = (const pvs__shrink_bake *)state;
	pvs_shrink_stats st;
	pvs_result r;
	(void)task;
	pvs__shrink_bake_preset(env, candidates, bits);
	r = pvs_shrink_cell(env->scene, sh->occluders, box, sh->mode, bits, &st, err);
	if (r == PVS_OK && st.excluded && sh->occluders_leak) {
		memset(bits, 0, env->words * sizeof(pvs_word));
		pvs__shrink_bake_preset(env, candidates, bits);
		r = pvs_shrink_cell(env->scene, sh->occluders_leak, box, sh->mode, bits, &st, err);
		st.excluded = 1;
	}
	if (r != PVS_OK) {
		if (err) err->index = cell;
		return r;
	}
	if (st.no_occluders) *flags |= PVS__BAKE_NO_OCCLUDERS;
	if (st.excluded) *flags |= PVS__BAKE_EXCLUDED;
	return PVS_OK;
}

PVS__STATIC void pvs__shrink_bake_destroy(const pvs__bake_env *env, void *state) {
	pvs__shrink_bake *sh = (pvs__shrink_bake *)state;
	(void)env;
	if (!sh) return;
	pvs_occluders_destroy(sh->occluders);
	pvs_occluders_destroy(sh->occluders_leak);
	pvs__free(&sh->allocator, sh, sizeof(*sh), 16);
}

PVS__STATIC const pvs__bake_method pvs__shrink_method = {PVS_METHOD_SHRINK,
														 PVS__METHOD_CONSERVATIVE | PVS__METHOD_AUTO_DEFAULT |
															 PVS__METHOD_SETS_OTHERS,
														 3,
														 NULL,
														 pvs__shrink_bake_prepare,
														 pvs__shrink_bake_applies,
														 pvs__shrink_bake_cell,
														 NULL,
														 pvs__shrink_bake_destroy};

PVS_API const pvs_occluders *pvs_bake_occluders(const pvs_bake *b) {
	const pvs__shrink_bake *sh = (const pvs__shrink_bake *)pvs__bake_method_state(b, PVS_METHOD_SHRINK);
	return sh ? sh->occluders : NULL;
}
PVS_API pvs_shrink_mode pvs_bake_shrink_mode(const pvs_bake *b) {
	const pvs__shrink_bake *sh = (const pvs__shrink_bake *)pvs__bake_method_state(b, PVS_METHOD_SHRINK);
	return sh && sh->occluders ? sh->mode : PVS_SHRINK_AUTO;
}

// >>bake
/* ==== bake: validated cells, one task per cell, results in cell order whatever the run order ==== */

struct pvs_bake {
	pvs__bake_env env;         /* what the methods see: scene, allocator, cells, eps, flags */
	pvs_box *cells;            /* per task: the shard's cells in id order */
	uint32_t cell_count;       /* the shard's (task_count) */
	uint32_t total_cell_count, shard_index, shard_count;
	uint32_t object_count;
	size_t words;              /* per cell */
	pvs_word *pvs;             /* cell_count * words */
	unsigned char *done;       /* cell_count flags, each written by its task only */
	pvs_method method;
	uint32_t max_chain;
	/* considered (AUTO: all candidates, in run order) and run methods; a task's PVS intersects theirs (conservative) */
	const pvs__bake_method *considered[PVS_METHOD_COUNT];
	const char *reason[PVS_METHOD_COUNT];
	float sample_gain[PVS_METHOD_COUNT]; /* by considered index: AUTO's sample (pvs__bake_auto_sample) */
	uint32_t sample_cells;
	unsigned char ran[PVS_METHOD_COUNT];
	uint32_t considered_count;
	const pvs__bake_method *run[PVS_METHOD_COUNT];
	uint32_t run_count;
	void *state[PVS_METHOD_COUNT]; /* by pvs_method: prepared states */
	uint32_t *stats;           /* per task: run_count own PVS sizes, then run_count sole-cull counts */
	unsigned char *restored;   /* per task: restored (no stats) */
	float max_distance;
	unsigned char *cell_flags; /* per task, written by its task: PVS__BAKE_* */
	uint32_t drawable;         /* objects that can appear in a PVS */
	uint32_t adaptive_budget;  /* adaptive cells (§6.1); 0 = off */
	float adaptive_min_size;
	uint32_t *object_triangles;/* adaptive: triangles per object */
	struct pvs__bakeleaves *leaves; /* adaptive: per task, its leaf cells */
};

/* An adaptive task's leaf cells and their PVSs. */
typedef struct pvs__bakeleaves {
	size_t count, capacity;
	pvs_box *boxes;
	pvs_word *pvs;             /* count * words */
} pvs__bakeleaves;

/* ---- the method table ---- */

/* Every method the driver runs, in pvs_method order (AUTO's order among equal costs). */
PVS__STATIC const pvs__bake_method *const pvs__bake_methods[] = {
	&pvs__sample_method, &pvs__otree_method, &pvs__extproj_method, &pvs__shrink_method, &pvs__vocc_method};
#define PVS__BAKE_METHOD_COUNT (sizeof(pvs__bake_methods) / sizeof(pvs__bake_methods[0]))

/* NULL for AUTO, DEFAULT and unknown values. */
PVS__STATIC const pvs__bake_method *pvs__bake_method_row(pvs_method m) {
	uint32_t k;
	for (k = 0; k < PVS__BAKE_METHOD_COUNT; ++k)
		if (pvs__bake_methods[k]->method == m) return pvs__bake_methods[k];
	return NULL;
}

PVS__STATIC void *pvs__bake_method_state(const pvs_bake *b, pvs_method m) {
	return b && (int)m >= 0 && m < PVS_METHOD_COUNT ? b->state[m] : NULL;
}

/* Prepares the method's per-bake state (read-only in the tasks). */
PVS__STATIC pvs_result pvs__bake_prepare(pvs_bake *b, const pvs__bake_method *row, const pvs_bake_desc *desc,
										 pvs_error *err) {
	return row->prepare(&b->env, desc, &b->state[row->method], err);
}

/* Candidates of the box's k-th method: its own (a sub-cell's parent PVS, or NULL), from the second method on narrowed
   to what earlier ones kept (AUTO runs SHRINK last). In *scratch when computed. */
PVS__STATIC const pvs_word *pvs__bake_prior(const pvs_bake *b, uint32_t k, const pvs_word *candidates,
											const pvs_word *each, pvs_word *scratch) {
	size_t w;
	uint32_t i;
	if (k == 0) return candidates;
	for (w = 0; w < b->words; ++w) {
		pvs_word all = candidates ? candidates[w] : ~(pvs_word)0;
		for (i = 0; i < k; ++i) all &= each[(size_t)i * b->words + w];
		scratch[w] = all;
	}
	return scratch;
}

/* One method's PVS of a task's box into `bits` (cleared by the caller); updates the cell's flags. */
PVS__STATIC pvs_result pvs__bake_method_cell(pvs_bake *b, const pvs__bake_method *row, uint32_t task, uint32_t cell,
											 const pvs_box *box, const pvs_word *candidates, pvs_word *bits,
											 pvs_error *err) {
	unsigned flags = 0;
	pvs_result r = row->cell(&b->env, b->state[row->method], task, cell, box, candidates, bits, &flags, err);
	b->cell_flags[task] |= (unsigned char)flags;
	return r;
}

PVS_API void pvs_bake_destroy(pvs_bake *b) {
	pvs_allocator a;
	uint32_t k;
	if (!b) return;
	a = b->env.allocator;
	pvs__free_array(&a, b->cells, b->cell_count, sizeof(pvs_box));
	pvs__free_array(&a, b->pvs, (size_t)b->cell_count * b->words, sizeof(pvs_word));
	pvs__free_array(&a, b->done, b->cell_count, 1);
	pvs__free_array(&a, b->restored, b->cell_count, 1);
	pvs__free_array(&a, b->stats, (size_t)b->cell_count * 2 * PVS_METHOD_COUNT, sizeof(uint32_t));
	pvs__free_array(&a, b->cell_flags, b->cell_count, 1);
	for (k = 0; k < PVS__BAKE_METHOD_COUNT; ++k)
		if (b->state[pvs__bake_methods[k]->method])
			pvs__bake_methods[k]->destroy(&b->env, b->state[pvs__bake_methods[k]->method]);
	pvs__free_array(&a, b->object_triangles, (size_t)b->object_count + 1, sizeof(uint32_t));
	if (b->leaves) {
		uint32_t i;
		for (i = 0; i < b->cell_count; ++i) {
			pvs__free_array(&a, b->leaves[i].boxes, b->leaves[i].capacity, sizeof(pvs_box));
			pvs__free_array(&a, b->leaves[i].pvs, b->leaves[i].capacity * b->words, sizeof(pvs_word));
		}
		pvs__free_array(&a, b->leaves, b->cell_count, sizeof(pvs__bakeleaves));
	}
	pvs__free(&a, b, sizeof(*b), 16);
}

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

/* 1 only when all of a is surely farther than d from all of b: exact gaps in double, their sum within a few 1e-16
   relative, under the 1e-9 margin; boxes at d or a hair beyond stay. */
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

/* Checks a bake desc: the driver's parameters, each method's, the cells. *mask: the methods AUTO considers. */
PVS__STATIC pvs_result pvs__bake_check(const pvs_bake_desc *desc, uint32_t *mask, pvs_error *err) {
	const pvs__bake_method *row;
	pvs_method method;
	pvs_result r;
	uint32_t k, conservative = 0, byauto = 0;
	size_t i;
	*mask = 0;
	if (!desc->cells || desc->cell_count == 0) return pvs__fail(err, PVS_ERROR_INVALID_ARGUMENT, -1, 0, "no cells");
	if (desc->cell_count == 0xffffffffu) return pvs__fail(err, PVS_ERROR_COUNT_OVERFLOW, -1, 0, "too many cells");
	if (desc->shard_count == 1 || (desc->shard_count && desc->shard_index >= desc->shard_count) ||
		desc->shard_count > desc->cell_count)
		return pvs__fail(err, PVS_ERROR_INVALID_ARGUMENT, -1, 0, "shard %u of %u for %u cells", desc->shard_index,
						 desc->shard_count, desc->cell_count);
	if (desc->max_chain > PVS_MAX_CHAIN)
		return pvs__fail(err, PVS_ERROR_INVALID_ARGUMENT, -1, 0, "max_chain %u > %u", desc->max_chain, PVS_MAX_CHAIN);
	method = desc->method == PVS_METHOD_DEFAULT ? PVS_METHOD_AUTO : desc->method;
	row = pvs__bake_method_row(method);
	if (!row && method != PVS_METHOD_AUTO)
		return pvs__fail(err, PVS_ERROR_INVALID_ARGUMENT, -1, 0, "unknown method %d", (int)desc->method);
	if (!pvs__finite(desc->eps) || desc->eps < 0.0f)
		return pvs__fail(err, PVS_ERROR_INVALID_ARGUMENT, -1, 0, "eps must be finite and >= 0");
	if (!pvs__finite(desc->max_distance) || desc->max_distance < 0.0f)
		return pvs__fail(err, PVS_ERROR_INVALID_ARGUMENT, -1, 0, "max_distance must be finite and >= 0");
	if (desc->flags & ~PVS_BAKE_PREVIEW)
		return pvs__fail(err, PVS_ERROR_INVALID_ARGUMENT, -1, 0, "unknown bake flags 0x%x", desc->flags);
	for (k = 0; k < PVS__BAKE_METHOD_COUNT; ++k) {
		const pvs__bake_method *m = pvs__bake_methods[k];
		if (m->check && (r = m->check(desc, err)) != PVS_OK) return r;
		if (m->traits & PVS__METHOD_CONSERVATIVE) conservative |= 1u << m->method;
		if (m->traits & PVS__METHOD_AUTO_DEFAULT) byauto |= 1u << m->method;
	}
	if (!pvs__finite(desc->adaptive.min_size) || desc->adaptive.min_size < 0.0f)
		return pvs__fail(err, PVS_ERROR_INVALID_ARGUMENT, -1, 0, "adaptive.min_size must be finite and >= 0");
	if (desc->adaptive.budget && desc->shard_count)
		return pvs__fail(err, PVS_ERROR_UNSUPPORTED, -1, 0,
						 "adaptive cells in a sharded bake (part files index whole cells)");
	if (desc->adaptive.budget && row && (row->traits & PVS__METHOD_WHOLE_CELLS))
		return pvs__fail(err, PVS_ERROR_UNSUPPORTED, -1, 0,
						 "adaptive cells with %s (its records belong to whole cells)", pvs_method_name(method));
	if (method == PVS_METHOD_AUTO) {
		if (desc->methods & ~conservative)
			return pvs__fail(err, PVS_ERROR_INVALID_ARGUMENT, -1, 0,
							 "methods mask 0x%x names a method that is not conservative or unknown "
							 "(auto never intersects sample)",
							 desc->methods);
		*mask = desc->methods ? desc->methods : byauto;
	} else if (desc->methods) {
		return pvs__fail(err, PVS_ERROR_INVALID_ARGUMENT, -1, 0, "methods is for PVS_METHOD_AUTO only");
	}
	for (i = 0; i < desc->cell_count; ++i) {
		r = pvs__check_cell(desc->cells + i, (uint32_t)i, err);
		if (r != PVS_OK) return r;
	}
	return PVS_OK;
}

PVS__STATIC pvs_result pvs__bake_arrays(pvs_bake *b, const pvs_bake_desc *desc, pvs_error *err) {
	const pvs_allocator *a = &b->env.allocator;
	size_t total, bytes, i;
	if (!pvs__mul(b->words, b->cell_count, &total) || !pvs__mul(total, sizeof(pvs_word), &bytes))
		return pvs__fail(err, PVS_ERROR_COUNT_OVERFLOW, -1, 0, "%u cells x %u objects do not fit in memory",
						 desc->cell_count, b->object_count);
	b->cells = (pvs_box *)pvs__alloc_array(a, b->cell_count, sizeof(pvs_box));
	b->pvs = (pvs_word *)pvs__alloc_array(a, total, sizeof(pvs_word));
	b->done = (unsigned char *)pvs__alloc_array(a, b->cell_count, 1);
	b->restored = (unsigned char *)pvs__alloc_array(a, b->cell_count, 1);
	b->stats = (uint32_t *)pvs__alloc_array(a, (size_t)b->cell_count * 2 * PVS_METHOD_COUNT, sizeof(uint32_t));
	b->cell_flags = (unsigned char *)pvs__alloc_array(a, b->cell_count, 1);
	if (!b->cells || !b->pvs || !b->done || !b->restored || !b->stats || !b->cell_flags)
		return pvs__fail(err, PVS_ERROR_OUT_OF_MEMORY, -1, 0, "bake arrays for %u cells", desc->cell_count);
	for (i = 0; i < b->cell_count; ++i) b->cells[i] = desc->cells[pvs_bake_task_cell(b, (uint32_t)i)];
	if (b->adaptive_budget) {
		b->object_triangles = (uint32_t *)pvs__alloc_array(a, (size_t)b->object_count + 1, sizeof(uint32_t));
		b->leaves = (pvs__bakeleaves *)pvs__alloc_array(a, b->cell_count, sizeof(pvs__bakeleaves));
		if (!b->object_triangles || !b->leaves) return pvs__fail(err, PVS_ERROR_OUT_OF_MEMORY, -1, 0, "adaptive cells");
		memset(b->object_triangles, 0, ((size_t)b->object_count + 1) * sizeof(uint32_t));
		memset(b->leaves, 0, b->cell_count * sizeof(pvs__bakeleaves));
		for (i = 0; i < desc->scene->triangle_count; ++i)
			if (desc->scene->triangle_object[i] != PVS_NO_OBJECT)
				++b->object_triangles[desc->scene->triangle_object[i]];
	}
	memset(b->pvs, 0, total * sizeof(pvs_word));
	memset(b->done, 0, b->cell_count);
	memset(b->restored, 0, b->cell_count);
	memset(b->cell_flags, 0, b->cell_count);
	memset(b->stats, 0, (size_t)b->cell_count * 2 * PVS_METHOD_COUNT * sizeof(uint32_t));
	for (i = 0; i < b->object_count; ++i)
		b->drawable +=
			!(desc->scene->object_flags[i] & PVS_OBJECT_OCCLUDER_ONLY) && pvs__box_valid(desc->scene->object_boxes + i);
	return PVS_OK;
}

/* AUTO: `mask`'s methods, cheapest first (cost_rank, table order), each prepared and kept if it can cull here; PREVIEW
   stops at the first kept; UNSUPPORTED ones are skipped, with their reason. */
PVS__STATIC pvs_result pvs__bake_choose(pvs_bake *b, const pvs_bake_desc *desc, uint32_t mask, pvs_error *err) {
	int rank;
	uint32_t k;
	pvs_result r;
	for (rank = 1; rank <= 4; ++rank)
		for (k = 0; k < PVS__BAKE_METHOD_COUNT; ++k) {
			const pvs__bake_method *m = pvs__bake_methods[k];
			const char *why = "preview runs only the cheapest method that applies";
			if (!(mask & (1u << m->method)) || m->cost_rank != rank) continue;
			b->considered[b->considered_count] = m;
			if (!((b->env.flags & PVS_BAKE_PREVIEW) && b->run_count)) {
				r = pvs__bake_prepare(b, m, desc, err);
				if (r == PVS_ERROR_UNSUPPORTED) {
					why = "not available in the bake driver";
				} else if (r != PVS_OK) {
					return r;
				} else if (!m->applies) {
					why = "conservative";
					b->ran[b->considered_count] = 1;
					b->run[b->run_count++] = m;
				} else if (m->applies(b->state[m->method], &why)) {
					b->ran[b->considered_count] = 1;
					b->run[b->run_count++] = m;
				}
			}
			b->reason[b->considered_count++] = why;
		}
	if (!b->run_count)
		return pvs__fail(err, PVS_ERROR_UNSUPPORTED, -1, 0,
						 "auto: no conservative method can cull anything in this scene");
	return PVS_OK;
}

/* AUTO pays for what culls (Deliver of issue 28): the methods that apply are prepared for PVS_AUTO_SAMPLE_CELLS cells
   spread evenly over all the bake's cells (a shard's too, so every shard decides alike), and each is baked alone on
   them. Greedily, the method with the smallest PVS is kept, then the others in the order of what they cull beyond
   those kept, while that gain is at least PVS_AUTO_MIN_GAIN of the kept PVS. Only the kept methods are then prepared
   for every cell (the sample's preparations, seeded by its cells only, are cheap) and run. Only for the default set
   (desc->methods 0), at least 4 times as many cells as the sample, without PREVIEW or a method that stores whole
   cells. Deterministic: counts decide, never time. The sample's PVSs only choose; the bake's come from the full
   preparations. */
PVS__STATIC int pvs__bake_wants_sample(const pvs_bake_desc *desc) {
	return !desc->methods && !(desc->flags & PVS_BAKE_PREVIEW) && desc->cell_count >= 4 * PVS_AUTO_SAMPLE_CELLS;
}

/* The greedy choice over the S sample cells of sd (prepared for them): b->run keeps the chosen methods. */
PVS__STATIC pvs_result pvs__bake_auto_sample(pvs_bake *b, const pvs_bake_desc *sd, pvs_error *err) {
	uint32_t n = b->run_count, S = sd->cell_count, s, k, i, keep[PVS_METHOD_COUNT], kept = 0;
	size_t w, words = b->words, total = (size_t)S * (n + 1) * words;
	double base = 0.0;
	pvs_word *bits;
	pvs_result r = PVS_OK;
	if (n < 2) return PVS_OK;
	bits = (pvs_word *)pvs__alloc_array(&b->env.allocator, total, sizeof(pvs_word));
	if (!bits) return pvs__fail(err, PVS_ERROR_OUT_OF_MEMORY, -1, 0, "auto: sample cells");
	memset(bits, 0, total * sizeof(pvs_word));
	for (s = 0; s < S && r == PVS_OK; ++s) /* per sample cell: n methods' PVSs, then the kept intersection */
		for (k = 0; k < n && r == PVS_OK; ++k) {
			unsigned flags = 0;
			r = b->run[k]->cell(&b->env, b->state[b->run[k]->method], 0, s, sd->cells + s, NULL,
								bits + ((size_t)s * (n + 1) + k) * words, &flags, err);
		}
	for (k = 0; k < n; ++k) keep[k] = 0;
	while (r == PVS_OK && kept < n) { /* the next method: the largest gain over the kept intersection */
		uint32_t best = n;
		double best_gain = -1.0, sum;
		for (k = 0; k < n; ++k) {
			if (keep[k]) continue;
			for (sum = 0.0, s = 0; s < S; ++s) {
				const pvs_word *cur = bits + ((size_t)s * (n + 1) + n) * words;
				const pvs_word *own = bits + ((size_t)s * (n + 1) + k) * words;
				for (w = 0; w < words; ++w) sum += (double)pvs__popcount64((kept ? cur[w] : ~(pvs_word)0) & ~own[w]);
			}
			for (i = 0; i < b->considered_count; ++i) /* kept: its gain when chosen; skipped: its last */
				if (b->considered[i] == b->run[k]) b->sample_gain[i] = (float)(sum / S);
			if (sum > best_gain) {
				best_gain = sum;
				best = k;
			}
		}
		if (kept && best_gain < PVS_AUTO_MIN_GAIN * base) break;
		keep[best] = 1;
		for (base = 0.0, s = 0; s < S; ++s) {
			pvs_word *cur = bits + ((size_t)s * (n + 1) + n) * words;
			const pvs_word *own = bits + ((size_t)s * (n + 1) + best) * words;
			for (w = 0; w < words; ++w) cur[w] = kept ? cur[w] & own[w] : own[w];
			base += (double)pvs_bitset_count(cur, b->object_count);
		}
		++kept;
	}
	pvs__free_array(&b->env.allocator, bits, total, sizeof(pvs_word));
	if (r != PVS_OK) return r;
	b->sample_cells = S;
	for (k = 0, kept = 0; k < n; ++k) {
		if (keep[k]) {
			b->run[kept++] = b->run[k];
			continue;
		}
		for (i = 0; i < b->considered_count; ++i)
			if (b->considered[i] == b->run[k]) {
				b->ran[i] = 0;
				b->reason[i] = "negligible: on the sample cells it culled under 2% of what the others kept";
			}
	}
	b->run_count = kept;
	return PVS_OK;
}

/* AUTO with the sample (pvs__bake_wants_sample): choose on the sample's preparations, then prepare the kept methods
   for every cell. */
PVS__STATIC pvs_result pvs__bake_choose_sampled(pvs_bake *b, const pvs_bake_desc *desc, uint32_t mask,
												pvs_error *err) {
	pvs_box sample[PVS_AUTO_SAMPLE_CELLS];
	pvs_bake_desc sd = *desc;
	uint32_t s, k, i, kept = 0, S = PVS_AUTO_SAMPLE_CELLS;
	pvs_result r;
	for (s = 0; s < S; ++s) sample[s] = desc->cells[((2 * (uint64_t)s + 1) * desc->cell_count) / (2 * (uint64_t)S)];
	sd.cells = sample;
	sd.cell_count = S;
	b->env.cells = sample;
	b->env.cell_count = S;
	r = pvs__bake_choose(b, &sd, mask, err);
	for (k = 0; r == PVS_OK && k < b->run_count; ++k)
		if (b->run[k]->traits & PVS__METHOD_WHOLE_CELLS) r = PVS_ERROR_UNSUPPORTED; /* not expected under AUTO */
	if (r == PVS_OK) r = pvs__bake_auto_sample(b, &sd, err);
	for (k = 0; k < PVS__BAKE_METHOD_COUNT; ++k) { /* the sample's preparations */
		const pvs__bake_method *m = pvs__bake_methods[k];
		if (b->state[m->method]) m->destroy(&b->env, b->state[m->method]);
		b->state[m->method] = NULL;
	}
	b->env.cells = desc->cells;
	b->env.cell_count = desc->cell_count;
	b->env.eps = desc->eps;
	if (r != PVS_OK) return r;
	for (k = 0; k < b->run_count; ++k) { /* the kept methods, for every cell */
		const char *why = "conservative";
		const pvs__bake_method *m = b->run[k];
		r = pvs__bake_prepare(b, m, desc, err);
		if (r != PVS_OK && r != PVS_ERROR_UNSUPPORTED) return r;
		if (r == PVS_OK && (!m->applies || m->applies(b->state[m->method], &why))) {
			b->run[kept++] = m;
			continue;
		}
		for (i = 0; i < b->considered_count; ++i)
			if (b->considered[i] == m) {
				b->ran[i] = 0;
				b->reason[i] = r == PVS_OK ? why : "not available in the bake driver";
			}
	}
	b->run_count = kept;
	if (!kept) return pvs__fail(err, PVS_ERROR_UNSUPPORTED, -1, 0, "auto: no conservative method can cull here");
	return PVS_OK;
}

PVS_API pvs_result pvs_bake_begin(const pvs_bake_desc *desc, pvs_bake **out, pvs_error *err) {
	pvs_bake *b;
	pvs_result r;
	uint32_t mask;
	if (out) *out = NULL;
	if (!desc || !out || !desc->scene)
		return pvs__fail(err, PVS_ERROR_INVALID_ARGUMENT, -1, 0, "desc, scene and out_bake must not be NULL");
	r = pvs__bake_check(desc, &mask, err);
	if (r != PVS_OK) return r;
	b = (pvs_bake *)pvs__alloc(&desc->allocator, sizeof(pvs_bake), 16);
	if (!b) return pvs__fail(err, PVS_ERROR_OUT_OF_MEMORY, -1, 0, "bake");
	memset(b, 0, sizeof(*b));
	b->total_cell_count = desc->cell_count;
	b->shard_count = desc->shard_count;
	b->shard_index = desc->shard_count ? desc->shard_index : 0;
	b->cell_count = desc->shard_count
		? (desc->cell_count - desc->shard_index + desc->shard_count - 1) / desc->shard_count
		: desc->cell_count;
	b->max_chain = desc->max_chain;
	b->object_count = pvs_scene_object_count(desc->scene);
	b->words = PVS_BITSET_WORDS(b->object_count);
	b->method = desc->method == PVS_METHOD_DEFAULT ? PVS_METHOD_AUTO : desc->method;
	b->max_distance = desc->max_distance;
	b->adaptive_budget = desc->adaptive.budget;
	b->adaptive_min_size = desc->adaptive.min_size;
	b->env.scene = desc->scene;
	b->env.allocator = desc->allocator;
	b->env.cells = desc->cells;
	b->env.cell_count = desc->cell_count;
	b->env.task_count = b->cell_count;
	b->env.object_count = b->object_count;
	b->env.words = b->words;
	b->env.eps = desc->eps;
	b->env.flags = desc->flags;
	b->env.is_auto = b->method == PVS_METHOD_AUTO;
	r = pvs__bake_arrays(b, desc, err);
	b->env.task_cells = b->cells;
	if (r == PVS_OK && b->method != PVS_METHOD_AUTO) {
		const pvs__bake_method *row = pvs__bake_method_row(b->method);
		b->considered[0] = b->run[0] = row;
		b->ran[0] = 1;
		b->reason[0] = "requested";
		b->considered_count = b->run_count = 1;
		r = pvs__bake_prepare(b, row, desc, err);
	} else if (r == PVS_OK) {
		r = pvs__bake_wants_sample(desc) ? pvs__bake_choose_sampled(b, desc, mask, err)
									   : pvs__bake_choose(b, desc, mask, err);
	}
	b->env.cells = NULL; /* desc's: gone after this call */
	if (r != PVS_OK) {
		pvs_bake_destroy(b);
		return r;
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
PVS_API float pvs_bake_eps(const pvs_bake *b) { return b->env.eps; }

/* The draw distance (pvs_bake_desc.max_distance), rounded toward keeping. */
PVS__STATIC void pvs__bake_distance(const pvs_bake *b, const pvs_box *box, pvs_word *bits) {
	uint32_t i;
	if (!(b->max_distance > 0.0f)) return;
	for (i = pvs_bitset_next(bits, b->object_count, 0); i < b->object_count;
		 i = pvs_bitset_next(bits, b->object_count, i + 1))
		if (pvs__box_beyond(box, b->env.scene->object_boxes + i, b->max_distance)) pvs_bitset_clear(bits, i);
}

/* All methods on a box, intersected, within `candidates` if given, then the draw distance. `each`: run_count + 1. */
PVS__STATIC pvs_result pvs__bake_box(pvs_bake *b, uint32_t task, uint32_t cell, const pvs_box *box,
									 const pvs_word *candidates, pvs_word *bits, pvs_word *each, pvs_error *err) {
	uint32_t k;
	pvs_result r = PVS_OK;
	memset(each, 0, (size_t)b->run_count * b->words * sizeof(pvs_word));
	for (k = 0; k < b->run_count && r == PVS_OK; ++k)
		r = pvs__bake_method_cell(b, b->run[k], task, cell, box,
								  pvs__bake_prior(b, k, candidates, each, each + (size_t)b->run_count * b->words),
								  each + (size_t)k * b->words, err);
	if (r != PVS_OK) return r;
	pvs__bake_prior(b, b->run_count, candidates, each, bits); /* all of them (run_count >= 1) */
	pvs__bake_distance(b, box, bits);
	return PVS_OK;
}

/* Triangles of a PVS's objects (the polygon budget of §6.1). */
PVS__STATIC uint64_t pvs__bake_triangles(const pvs_bake *b, const pvs_word *bits) {
	uint64_t n = 0;
	uint32_t o;
	for (o = pvs_bitset_next(bits, b->object_count, 0); o < b->object_count;
		 o = pvs_bitset_next(bits, b->object_count, o + 1))
		n += b->object_triangles[o];
	return n;
}

/* Adaptive subdivision (Durand 2000 §6.1) of a box with PVS work[depth]: a leaf if the PVS fits the budget or a half
   would be under min_size, else its halves across the longest side, low first, baked from its PVS. work: 48 bitsets;
   each: run_count + 1. */
PVS__STATIC pvs_result pvs__bake_split(pvs_bake *b, uint32_t task, uint32_t cell, const pvs_box *box, float min_size,
									   pvs_word *work, pvs_word *each, uint32_t depth, pvs_error *err) {
	pvs__bakeleaves *L = b->leaves + task;
	const pvs_word *bits = work + (size_t)depth * b->words;
	int k, axis = 0;
	float mid;
	pvs_result r = PVS_OK;
	for (k = 1; k < 3; ++k)
		if (box->max[k] - box->min[k] > box->max[axis] - box->min[axis]) axis = k;
	mid = box->min[axis] + 0.5f * (box->max[axis] - box->min[axis]);
	if (pvs__bake_triangles(b, bits) <= b->adaptive_budget || 0.5f * (box->max[axis] - box->min[axis]) < min_size ||
		depth + 1 >= 48 || !(mid > box->min[axis] && mid < box->max[axis])) {
		if (L->count == L->capacity) {
			size_t cap = L->capacity ? 2 * L->capacity : 8;
			pvs_box *nb = (pvs_box *)pvs__alloc_array(&b->env.allocator, cap, sizeof(pvs_box));
			pvs_word *np = (pvs_word *)pvs__alloc_array(&b->env.allocator, cap * b->words, sizeof(pvs_word));
			if (!nb || !np || cap > 0x3fffffffu) {
				pvs__free_array(&b->env.allocator, nb, cap, sizeof(pvs_box));
				pvs__free_array(&b->env.allocator, np, cap * b->words, sizeof(pvs_word));
				return pvs__fail(err, PVS_ERROR_OUT_OF_MEMORY, cell, 0, "adaptive leaves of cell %u", cell);
			}
			if (L->count) {
				memcpy(nb, L->boxes, L->count * sizeof(pvs_box));
				memcpy(np, L->pvs, L->count * b->words * sizeof(pvs_word));
			}
			pvs__free_array(&b->env.allocator, L->boxes, L->capacity, sizeof(pvs_box));
			pvs__free_array(&b->env.allocator, L->pvs, L->capacity * b->words, sizeof(pvs_word));
			L->boxes = nb;
			L->pvs = np;
			L->capacity = cap;
		}
		L->boxes[L->count] = *box;
		memcpy(L->pvs + L->count * b->words, bits, b->words * sizeof(pvs_word));
		++L->count;
		return PVS_OK;
	}
	for (k = 0; k < 2; ++k) {
		pvs_box child = *box;
		if (k) child.min[axis] = mid; else child.max[axis] = mid;
		r = pvs__bake_box(b, task, cell, &child, bits, work + (size_t)(depth + 1) * b->words, each, err);
		if (r == PVS_OK) r = pvs__bake_split(b, task, cell, &child, min_size, work, each, depth + 1, err);
		if (r != PVS_OK) return r;
	}
	return PVS_OK;
}

/* A done task's adaptive leaves, from scratch. */
PVS__STATIC pvs_result pvs__bake_adapt(pvs_bake *b, uint32_t task, uint32_t cell, pvs_error *err) {
	const pvs_box *c = b->cells + task;
	float min_size = b->adaptive_min_size, longest = 0.0f;
	size_t nw = (49 + (size_t)b->run_count) * b->words;
	pvs_word *work = (pvs_word *)pvs__alloc_array(&b->env.allocator, nw, sizeof(pvs_word));
	pvs_result r;
	int k;
	if (!work) return pvs__fail(err, PVS_ERROR_OUT_OF_MEMORY, cell, 0, "adaptive cells of cell %u", cell);
	for (k = 0; k < 3; ++k) longest = c->max[k] - c->min[k] > longest ? c->max[k] - c->min[k] : longest;
	if (!(min_size > 0.0f)) min_size = 0.125f * longest;
	b->leaves[task].count = 0; /* a task run again starts over */
	memcpy(work, b->pvs + (size_t)task * b->words, b->words * sizeof(pvs_word));
	r = pvs__bake_split(b, task, cell, c, min_size, work, work + 48 * b->words, 0, err);
	pvs__free_array(&b->env.allocator, work, nw, sizeof(pvs_word));
	return r;
}

PVS_API pvs_result pvs_bake_run_task(pvs_bake *b, uint32_t task, pvs_error *err) {
	uint32_t cell, k, i, n, *own, *sole;
	pvs_word *bits, *each = NULL;
	pvs_result r = PVS_OK;
	size_t w;
	if (!b || task >= b->cell_count)
		return pvs__fail(err, PVS_ERROR_INVALID_ARGUMENT, task, 0, "task %u out of range", task);
	cell = pvs_bake_task_cell(b, task);
	bits = b->pvs + (size_t)task * b->words;
	n = b->run_count;
	own = b->stats + (size_t)task * 2 * PVS_METHOD_COUNT;
	sole = own + PVS_METHOD_COUNT;
	memset(bits, 0, b->words * sizeof(pvs_word));
	b->cell_flags[task] = 0;
	if (n == 1) {
		r = pvs__bake_method_cell(b, b->run[0], task, cell, b->cells + task, NULL, bits, err);
		if (r != PVS_OK) return r;
		own[0] = pvs_bitset_count(bits, b->object_count);
		sole[0] = own[0] < b->drawable ? b->drawable - own[0] : 0; /* occluder-only objects are never in a PVS */
		pvs__bake_distance(b, b->cells + task, bits);
	} else {
		/* AUTO: a method's contribution is what it alone leaves out of the intersection */
		each = (pvs_word *)pvs__alloc_array(&b->env.allocator, (size_t)(n + 1) * b->words, sizeof(pvs_word));
		if (!each) return pvs__fail(err, PVS_ERROR_OUT_OF_MEMORY, cell, 0, "cell %u: auto scratch", cell);
		r = pvs__bake_box(b, task, cell, b->cells + task, NULL, bits, each, err);
		if (r == PVS_OK) {
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
		pvs__free_array(&b->env.allocator, each, (size_t)(n + 1) * b->words, sizeof(pvs_word));
		if (r != PVS_OK) return r;
	}
	if (pvs_bitset_count(bits, b->object_count) >= b->drawable) b->cell_flags[task] |= PVS__BAKE_ALL_VISIBLE;
	if (b->adaptive_budget) {
		r = pvs__bake_adapt(b, task, cell, err);
		if (r != PVS_OK) return r;
	}
	b->done[task] = 1;
	pvs__ok(err);
	return PVS_OK;
}

PVS_API void pvs_bake_get_report(const pvs_bake *b, pvs_bake_report *r) {
	uint32_t i;
	memset(r, 0, sizeof(*r));
	for (i = 0; i < b->cell_count; ++i) {
		if (!b->done[i] || b->restored[i]) continue;
		++r->cells;
		r->cells_all_visible += (b->cell_flags[i] & PVS__BAKE_ALL_VISIBLE) != 0;
		/* AUTO: no occluders for a method (otree, shrink) means nothing when another culled */
		r->cells_no_occluders += (b->cell_flags[i] & PVS__BAKE_NO_OCCLUDERS) &&
			(b->run_count == 1 || (b->cell_flags[i] & PVS__BAKE_ALL_VISIBLE));
		r->cells_otree_budget += (b->cell_flags[i] & PVS__BAKE_OTREE_BUDGET) != 0;
		r->cells_excluded += (b->cell_flags[i] & PVS__BAKE_EXCLUDED) != 0;
	}
}

PVS_API uint32_t pvs_bake_leaf_count(const pvs_bake *b) {
	uint64_t n = 0;
	uint32_t i;
	if (!b) return 0;
	if (!b->adaptive_budget) return b->cell_count;
	for (i = 0; i < b->cell_count; ++i)
		if (b->done[i]) n += b->leaves[i].count;
	return n > 0xffffffffu ? 0xffffffffu : (uint32_t)n;
}

PVS_API int pvs_bake_task_done(const pvs_bake *b, uint32_t task) { return b && task < b->cell_count && b->done[task]; }

PVS_API pvs_result pvs_bake_restore_task(pvs_bake *b, uint32_t task, const pvs_word *bits, size_t word_count,
										 pvs_error *err) {
	uint32_t i;
	if (!b || !bits || task >= b->cell_count)
		return pvs__fail(err, PVS_ERROR_INVALID_ARGUMENT, task, 0, "restore: task %u out of range or NULL", task);
	if (word_count < b->words)
		return pvs__fail(err, PVS_ERROR_BUFFER_TOO_SMALL, task, 0, "restore: %zu words < %zu", word_count, b->words);
	if ((b->run[0]->traits & PVS__METHOD_WHOLE_CELLS) &&
		b->method != PVS_METHOD_AUTO) /* its file stores more than PVSs */
		return pvs__fail(err, PVS_ERROR_UNSUPPORTED, task, 0,
						 "restore: a %s bake cannot resume from PVSs: run task %u again", pvs_method_name(b->method),
						 task);
	if (b->adaptive_budget) /* the file stores the leaves, which the cell's PVS does not carry */
		return pvs__fail(err, PVS_ERROR_UNSUPPORTED, task, 0,
						 "restore: an adaptive bake cannot resume from PVSs: run task %u again", task);
	if ((b->object_count & 63u) && (bits[b->words - 1] >> (b->object_count & 63u)))
		return pvs__fail(err, PVS_ERROR_INVALID_ARGUMENT, task, 0, "restore: task %u sets a bit past the %u objects",
						 task, b->object_count);
	for (i = pvs_bitset_next(bits, b->object_count, 0); i < b->object_count;
		 i = pvs_bitset_next(bits, b->object_count, i + 1))
		if (b->env.scene->object_flags[i] & PVS_OBJECT_OCCLUDER_ONLY)
			return pvs__fail(err, PVS_ERROR_INVALID_ARGUMENT, task, 0, "restore: task %u sets occluder-only object %u",
							 task, i);
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
	info->method = b->considered[i]->method;
	info->ran = b->ran[i];
	info->reason = b->reason[i] ? b->reason[i] : "";
	info->sample_cells = b->sample_cells;
	info->sample_gain = b->sample_gain[i];
	if (!info->ran) return PVS_OK;
	for (k = 0; k < b->run_count; ++k)
		if (b->run[k] == b->considered[i]) slot = k;
	info->kept_only = slot > 0 && (b->run[slot]->traits & PVS__METHOD_SETS_OTHERS);
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
	fd->eps = b->env.eps;
	fd->up_axis = pvs_scene_up_axis(b->env.scene);
	fd->flags = b->run[0]->traits & PVS__METHOD_APPROXIMATE ? PVS_FILE_APPROXIMATE : 0u;
	fd->max_chain = b->max_chain;
	fd->shard_index = b->shard_index;
	fd->shard_count = b->shard_count;
	fd->total_cell_count = b->shard_count ? b->total_cell_count : 0;
	fd->allocator = b->env.allocator;
	if (b->method != PVS_METHOD_AUTO && b->run[0]->file) /* AUTO stores PVSs only */
		b->run[0]->file(b->state[b->method], fd);
}

PVS__STATIC int pvs__bake_all_done(const pvs_bake *b) {
	uint32_t i;
	for (i = 0; i < b->cell_count; ++i)
		if (!b->done[i]) return 0;
	return 1;
}

/* All tasks' adaptive leaves in task order, as one table (the caller frees it with the sizes returned). */
PVS__STATIC pvs_result pvs__bake_gather_leaves(const pvs_bake *b, pvs_box **cells, pvs_word **pvs, size_t *count) {
	size_t n = 0, k = 0, bytes;
	uint32_t i;
	for (i = 0; i < b->cell_count; ++i) n += b->leaves[i].count;
	*cells = NULL;
	*pvs = NULL;
	*count = n;
	if (n >= 0x3fffffffu) return PVS_ERROR_COUNT_OVERFLOW;
	if (!pvs__mul(n, b->words * sizeof(pvs_word), &bytes)) return PVS_ERROR_COUNT_OVERFLOW;
	*cells = (pvs_box *)pvs__alloc_array(&b->env.allocator, n, sizeof(pvs_box));
	*pvs = (pvs_word *)pvs__alloc_array(&b->env.allocator, n * b->words, sizeof(pvs_word));
	if (!*cells || !*pvs) return PVS_ERROR_OUT_OF_MEMORY;
	for (i = 0; i < b->cell_count; ++i) {
		const pvs__bakeleaves *L = b->leaves + i;
		memcpy(*cells + k, L->boxes, L->count * sizeof(pvs_box));
		memcpy(*pvs + k * b->words, L->pvs, L->count * b->words * sizeof(pvs_word));
		k += L->count;
	}
	return PVS_OK;
}

/* Encodes the bake (measures only when out is NULL). */
PVS__STATIC pvs_result pvs__bake_encode(const pvs_bake *b, void *out, size_t capacity, size_t *out_size,
										pvs_error *err) {
	pvs_file_desc fd;
	pvs_box *cells = NULL;
	pvs_word *pvs = NULL;
	size_t n = 0;
	pvs_result r;
	pvs__bake_file_desc(b, &fd);
	if (!b->adaptive_budget) return pvs_file_encode(&fd, out, capacity, out_size, err);
	r = pvs__bake_gather_leaves(b, &cells, &pvs, &n);
	if (r == PVS_OK) {
		fd.cells = cells;
		fd.cell_count = (uint32_t)n;
		fd.pvs = pvs;
		r = pvs_file_encode(&fd, out, capacity, out_size, err);
	} else
		r = pvs__fail(err, r, -1, 0, "%llu adaptive cells", (unsigned long long)n);
	pvs__free_array(&b->env.allocator, cells, n, sizeof(pvs_box));
	pvs__free_array(&b->env.allocator, pvs, n * b->words, sizeof(pvs_word));
	return r;
}

PVS_API size_t pvs_bake_file_size(const pvs_bake *b) {
	size_t size = 0;
	if (!b || !pvs__bake_all_done(b)) return 0;
	return pvs__bake_encode(b, NULL, 0, &size, NULL) == PVS_OK ? size : 0;
}

PVS_API pvs_result pvs_bake_write_file(const pvs_bake *b, void *out, size_t capacity, size_t *out_size,
									   pvs_error *err) {
	uint32_t i;
	if (!b) return pvs__fail(err, PVS_ERROR_INVALID_ARGUMENT, -1, 0, "bake is NULL");
	if (out_size) *out_size = 0;
	for (i = 0; i < b->cell_count; ++i)
		if (!b->done[i])
			return pvs__fail(err, PVS_ERROR_NOT_DONE, pvs_bake_task_cell(b, i), 0, "cell %u has not been baked",
							 pvs_bake_task_cell(b, i));
	return pvs__bake_encode(b, out, capacity, out_size, err);
}

// >>format
/* ==== format: the .pvs file (layout: the manual): delta-PVS encoder (Durand et al. 2000, §6.2), set codings,
   validating zero-copy reader ==== */

#define PVS__HEADER_SIZE 32u
#define PVS__SECTION_ENTRY 16u
#define PVS__MAX_SECTIONS 64u
#define PVS__META_SIZE 32u
#define PVS__CELL_HEAD 20u
#define PVS__TREE_HEAD 8u
#define PVS__TREE_MAX_DEPTH 24u        /* deepest look-up tree a reader accepts */
#define PVS__SHRD_SIZE 16u
#define PVS__BLOCK 16u                  /* records per RECS offset block */
#define PVS__CANDIDATES 8u              /* base candidates per cell: the nearest by the sweep */
#define PVS__TREE_LEAF 4u               /* most cells per look-up leaf */
#define PVS__RICE_MAX_K 24u
#define PVS__TAG(a, b, c, d) ((uint32_t)(a) | ((uint32_t)(b) << 8) | ((uint32_t)(c) << 16) | ((uint32_t)(d) << 24))
#define PVS__TAG_META PVS__TAG('M', 'E', 'T', 'A')
#define PVS__TAG_CELL PVS__TAG('C', 'E', 'L', 'L')
#define PVS__TAG_TREE PVS__TAG('T', 'R', 'E', 'E')
#define PVS__TAG_RECS PVS__TAG('R', 'E', 'C', 'S')
#define PVS__TAG_SHRD PVS__TAG('S', 'H', 'R', 'D')
enum { PVS__CODING_GAPS = 0, PVS__CODING_RUNS = 1, PVS__CODING_RICE = 2, PVS__CODING_BITMAP = 3 };

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
PVS__STATIC size_t pvs__varint_size(uint32_t v) {
	return v < (1u << 7) ? 1 : v < (1u << 14) ? 2 : v < (1u << 21) ? 3 : v < (1u << 28) ? 4 : 5;
}
/* Reads a varint from p[0..end): bytes used, 0 if overlong, over 32 bits or cut off. */
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
			if (n > 0 && c == 0) return 0; /* overlong: one encoding per value */
			*v = r;
			return n + 1;
		}
	}
	return 0;
}
/* A varint validated by pvs_file_open. */
PVS__STATIC const uint8_t *pvs__skip_varint(const uint8_t *p, uint32_t *v) {
	uint32_t r = 0;
	int s = 0;
	if (p[0] < 0x80u) {
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

/* Bit fields, LSB first, w <= 32; the reader touches only bytes holding bits [pos, pos + w). */
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

PVS__STATIC uint64_t pvs__load64(const uint8_t *s) { /* little-endian; one load once compiled */
	return (uint64_t)s[0] | (uint64_t)s[1] << 8 | (uint64_t)s[2] << 16 | (uint64_t)s[3] << 24 | (uint64_t)s[4] << 32 |
		   (uint64_t)s[5] << 40 | (uint64_t)s[6] << 48 | (uint64_t)s[7] << 56;
}

/* Bits [bit, bit + 56) of an nbits-bit stream, LSB first, zeros past its end. */
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

/* First clear bit at or after `from`, else bit_count. */
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

/* Four codings (bytes: the manual): Rice codes (Golomb codes, power-of-two divisor) suit sparse random sets, runs the
   ranges of spatially ordered objects; the bitset caps the worst case at n / 8 bytes. */
typedef struct pvs__coded {
	uint32_t coding, rice_k;
	size_t bytes;              /* body size */
} pvs__coded;

PVS__STATIC pvs__coded pvs__set_measure(const pvs_word *bits, uint32_t n) {
	uint64_t rice_bits[PVS__RICE_MAX_K + 1], shifted[PVS__RICE_MAX_K + 1];
	size_t gaps = 0, runs = 0;
	uint32_t count = 0, pairs = 0, k, pos = 0;
	pvs__coded best;
	memset(shifted, 0, sizeof(shifted));
	/* a run of L ids after z absent ones gives gaps z, 0, ..., 0: sizes are sums over runs, not ids */
	while (pos < n) {
		uint32_t one = pvs_bitset_next(bits, n, pos), zero, z, len;
		if (one >= n) break;
		zero = pvs__bitset_next_clear(bits, n, one);
		z = one - pos;
		len = zero - one;
		runs += pvs__varint_size(z) + pvs__varint_size(len - 1);
		gaps += pvs__varint_size(z) + (len - 1); /* a gap of 0 takes a byte */
		for (k = 0; k <= PVS__RICE_MAX_K; ++k) shifted[k] += z >> k;
		count += len;
		++pairs;
		pos = zero;
	}
	for (k = 0; k <= PVS__RICE_MAX_K; ++k) rice_bits[k] = (uint64_t)count * (1u + k) + shifted[k];
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
	pvs_word *bits;            /* the PVS being built (not CHECK) */
	uint32_t words;
	pvs_change_fn fn;          /* optional change reports */
	void *user;
	uint32_t w, before, removed; /* REMOVE_RANKS: scan word, set bits before it, ranks removed */
} pvs__sink;

/* Removes `count` consecutive ranks from `first` (before this set) word by word: cost in words plus bits removed. */
PVS__STATIC void pvs__sink_remove_run(pvs__sink *s, uint32_t first, uint64_t count) {
	uint32_t target = first - s->removed;
	while (s->w < s->words && s->before + pvs__popcount64(s->bits[s->w]) <= target)
		s->before += pvs__popcount64(s->bits[s->w++]);
	while (count && s->w < s->words) {
		pvs_word x = s->bits[s->w], take;
		uint32_t skip = target - s->before, k;
		for (k = 0; k < skip; ++k) x &= x - 1u; /* set bits from the target on */
		take = x;
		if (pvs__popcount64(take) > count) { /* only the lowest `count` */
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
		if (count) { /* the run goes on: nothing before the next words is left to skip */
			s->before += pvs__popcount64(s->bits[s->w]);
			++s->w;
			target = s->before;
		}
	}
}

/* Adds id, or removes the set bit of rank id in the PVS as it was before this set (ranks ascend). */
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
		while (s->w < s->words && s->before + pvs__popcount64(s->bits[s->w]) <= target)
			s->before += pvs__popcount64(s->bits[s->w++]);
		if (s->w == s->words) return; /* damaged file: no such rank */
		x = s->bits[s->w];
		for (k = target - s->before; k; --k) x &= x - 1u;
		k = pvs__ctz64(x);
		s->bits[s->w] &= ~((pvs_word)1 << k);
		++s->removed;
		if (s->fn) s->fn(s->user, s->w * 64 + k, 0);
	}
}

/* pvs__set_apply's decoders, one per coding (bytes: the manual's RECS), with its contract; on a bad byte they set
   *bad_at and return the error. */

/* Coding 0: gap varints. */
PVS__STATIC pvs_result pvs__set_gaps(const uint8_t *p, const uint8_t *end, uint32_t n, pvs__sink *s, size_t *used_out,
									 size_t *bad_at) {
	const uint8_t *q = p;
	uint32_t count, k;
	int act = s->action;
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
		if (act == PVS__SET_ADD && !s->fn) s->bits[id >> 6] |= (pvs_word)1 << (id & 63);
		else if (act) pvs__sink_id(s, (uint32_t)id);
		q += used;
	}
	*used_out = (size_t)(q - p);
	return PVS_OK;
bad:
	*bad_at = (size_t)(q - p);
	return PVS_ERROR_BAD_RECORD;
}

/* Coding 1: run lengths. */
PVS__STATIC pvs_result pvs__set_runs(const uint8_t *p, const uint8_t *end, uint32_t n, pvs__sink *s, size_t *used_out,
									 size_t *bad_at) {
	const uint8_t *q = p;
	uint32_t count, k;
	int act = s->action;
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
		if (act == PVS__SET_ADD && !s->fn) { /* whole words */
			uint64_t e = pos + o + 1u;
			while (pos < e && (pos & 63)) { s->bits[pos >> 6] |= (pvs_word)1 << (pos & 63); ++pos; }
			while (pos + 64 <= e) { s->bits[pos >> 6] = ~(pvs_word)0; pos += 64; }
			while (pos < e) { s->bits[pos >> 6] |= (pvs_word)1 << (pos & 63); ++pos; }
		} else if (act == PVS__SET_REMOVE_RANKS) {
			pvs__sink_remove_run(s, (uint32_t)pos, (uint64_t)o + 1u);
			pos += (uint64_t)o + 1u;
		} else {
			if (act) /* keeps validation linear in the record's bytes */
				for (i = 0; i <= o; ++i) pvs__sink_id(s, (uint32_t)(pos + i));
			pos += (uint64_t)o + 1u;
		}
	}
	*used_out = (size_t)(q - p);
	return PVS_OK;
bad:
	*bad_at = (size_t)(q - p);
	return PVS_ERROR_BAD_RECORD;
}

/* Coding 2: Rice codes (Golomb 1966, Rice 1979). */
PVS__STATIC pvs_result pvs__set_rice(const uint8_t *p, const uint8_t *end, uint32_t n, pvs__sink *s, size_t *used_out,
									 size_t *bad_at) {
	const uint8_t *q = p;
	uint32_t count, k, c;
	int act = s->action;
	uint64_t bit = 0, nbits, id = 0, bytes;
	size_t used;
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
		if (~w & (((uint64_t)1 << 56) - 1u)) { /* the unary run ends in the window */
			ones = pvs__ctz64(~w);
			quot = ones;
			if (bit + ones + 1u + k > nbits) goto bad;
			if (quot > n) { *bad_at = (size_t)(q - p) + (size_t)(bit >> 3); return PVS_ERROR_OBJECT_OUT_OF_RANGE; }
			g = ones + 1u + k <= 56u ? (w >> (ones + 1u)) & (((uint64_t)1 << k) - 1u)
									 : pvs__get_bits(q, bit + ones + 1u, k);
			bit += ones + 1u + k;
		} else {
			for (;;) { /* long unary run: bit by bit */
				uint32_t b1;
				if (bit >= nbits) goto bad;
				b1 = (q[bit >> 3] >> (bit & 7u)) & 1u;
				++bit;
				if (!b1) break;
				if (++quot > n) {
					*bad_at = (size_t)(q - p) + (size_t)(bit >> 3);
					return PVS_ERROR_OBJECT_OUT_OF_RANGE;
				}
			}
			if (bit + k > nbits) goto bad;
			g = pvs__get_bits(q, bit, k);
			bit += k;
		}
		g |= quot << k;
		id = c ? id + 1u + g : g;
		if (id >= n) { *bad_at = (size_t)(q - p) + (size_t)(bit >> 3); return PVS_ERROR_OBJECT_OUT_OF_RANGE; }
		if (act == PVS__SET_ADD && !s->fn) s->bits[id >> 6] |= (pvs_word)1 << (id & 63);
		else if (act) pvs__sink_id(s, (uint32_t)id);
	}
	/* unused high bits of the last byte are zero */
	bytes = (bit + 7) / 8;
	if ((bit & 7u) && (q[bit >> 3] >> (bit & 7u))) { q += (size_t)(bit >> 3); goto bad; }
	q += (size_t)bytes;
	*used_out = (size_t)(q - p);
	return PVS_OK;
bad:
	*bad_at = (size_t)(q - p);
	return PVS_ERROR_BAD_RECORD;
}

/* Coding 3: raw bitset. */
PVS__STATIC pvs_result pvs__set_bitmap(const uint8_t *p, const uint8_t *end, uint32_t n, pvs__sink *s, size_t *used_out,
									   size_t *bad_at) {
	size_t nb = ((size_t)n + 7) / 8, i;
	int act = s->action;
	if ((size_t)(end - p) < nb) { *bad_at = 0; return PVS_ERROR_BAD_RECORD; }
	if ((n & 7u) && (p[nb - 1] >> (n & 7u))) { *bad_at = nb - 1; return PVS_ERROR_OBJECT_OUT_OF_RANGE; }
	if (act == PVS__SET_ADD && !s->fn) {
		for (i = 0; i < nb; ++i) s->bits[i >> 3] |= (pvs_word)p[i] << (8 * (i & 7));
	} else if (act) {
		for (i = 0; i < nb; ++i) {
			uint32_t b = p[i];
			while (b) {
				uint32_t id = (uint32_t)(8 * i) + pvs__ctz64(b);
				b &= b - 1u;
				pvs__sink_id(s, id);
			}
		}
	}
	*used_out = nb;
	return PVS_OK;
}

/* Decodes the set of ids in [0, n) coded at p (readable to end) into the sink, ascending; *used: its size. PVS_OK, or
   BAD_RECORD / OBJECT_OUT_OF_RANGE with *bad_at the offending offset. */
PVS__STATIC pvs_result pvs__set_apply(const uint8_t *p, const uint8_t *end, uint32_t coding, uint32_t n, pvs__sink *s,
									  size_t *used_out, size_t *bad_at) {
	switch (coding) {
	case PVS__CODING_GAPS: return pvs__set_gaps(p, end, n, s, used_out, bad_at);
	case PVS__CODING_RUNS: return pvs__set_runs(p, end, n, s, used_out, bad_at);
	case PVS__CODING_RICE: return pvs__set_rice(p, end, n, s, used_out, bad_at);
	case PVS__CODING_BITMAP: return pvs__set_bitmap(p, end, n, s, used_out, bad_at);
	default: *bad_at = 0; return PVS_ERROR_BAD_RECORD;
	}
}

/* ---- encoder ---- */

typedef struct pvs__heapent {
	uint32_t weight, node, from; /* from: base cell + 1; 0: the virtual root (a key) */
} pvs__heapent;

PVS__STATIC int pvs__heap_less(const void *pa, const void *pb) {
	const pvs__heapent *a = (const pvs__heapent *)pa, *b = (const pvs__heapent *)pb;
	if (a->weight != b->weight) return a->weight < b->weight;
	if (a->node != b->node) return a->node < b->node;
	return a->from < b->from;
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

/* The file's look-up tree (the manual's TREE), implicit so a look-up reads one split per level, then one leaf; its
   split rule never copies touching neighbours. */
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
	if (level == b->depth) {
		b->items = (uint8_t *)pvs__grow_array(b->a, b->items, &b->item_capacity, b->item_bytes,
											  b->item_bytes + 5 * (size_t)n, 1, &r);
		if (!b->items) return r;
		b->leaf_start[b->leaves_done++] = (uint32_t)b->item_bytes;
		for (i = 0; i < n; ++i)
			b->item_bytes += pvs__put_varint(b->items + b->item_bytes, i ? ids[i] - ids[i - 1] - 1 : ids[0]);
		return PVS_OK;
	}
	if (n > 1) {
		/* each cell edge is a candidate: binary search on sorted mins and maxes counts cells going left (min < v, flat
		   cells at v aside) and right (max > v); the smaller larger side wins, first on ties. Unlike a median, this
		   splits crossing cells. */
		float *mins = b->keys, *maxs = b->keys + n;
		for (axis = 0; axis < 3; ++axis) {
			int side;
			for (i = 0; i < n; ++i) {
				mins[i] = b->boxes[ids[i]].min[axis];
				maxs[i] = b->boxes[ids[i]].max[axis];
			}
			PVS_QSORT(mins, n, sizeof(float), pvs__float_cmp);
			PVS_QSORT(maxs, n, sizeof(float), pvs__float_cmp);
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

PVS__STATIC pvs_visit pvs__collect_candidates(void *user, const pvs_box *node_box, float distance,
											  const uint32_t *items, uint32_t item_count) {
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
	pvs_box *boxes;            /* the cells as stored (-0 as +0) */
	float *values[3];
	uint32_t value_count[3], index_bits[6]; /* widths: min indices, then extents */
	pvs_kdtree *tree;          /* over the cells: base candidates */
	uint8_t *tree_stream;      /* TREE nodes */
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
	uint32_t *base, *depth;    /* PVS_NO_CELL for keys */
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

/* Cell i's record sets against base j (PVS_NO_CELL: a key): e->tmp = ids added (a key: the whole PVS); a delta's
   e->ranks = ids removed, as ranks in the base's PVS (Durand et al. 2000, §6.2; ranks among the base's few visible
   objects are cheaper). Returns the base's PVS size. */
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
/* Record size of cell i against base j. */
PVS__STATIC uint32_t pvs__encoder_cost(pvs__encoder *e, uint32_t i, uint32_t j) {
	size_t b;
	uint32_t m = pvs__encoder_sets(e, i, j);
	b = pvs__set_measure(e->tmp, e->n).bytes + 2u;
	if (j != PVS_NO_CELL) b += 2u + pvs__varint_size(m) + pvs__set_measure(e->ranks, m).bytes;
	return b > 0xffffffffu ? 0xffffffffu : (uint32_t)b;
}

/* Bases: edges from each cell to its nearest cells (kD-tree sweep), a virtual root joined to all at their key size;
   Prim's tree from the root, an edge weighed on reach by the delta's coded size that way and taken only while its chain
   stays within K (a greedy depth-bounded minimum arborescence); cells linked to the root are keys. Ties break by
   (weight, cell, base): deterministic. */
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
	/* unique undirected edges */
	PVS_QSORT(e->edges, e->edge_count, sizeof(pvs__link), pvs__edge_cmp);
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
		/* second cursor per cell in depth[] (scratch until Prim) */
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
		pvs__pq_push(e->heap, &heap_n, sizeof(h), &h, pvs__heap_less);
	}
	while (heap_n) {
		pvs__heapent h;
		uint32_t v, j;
		pvs__pq_pop(e->heap, &heap_n, sizeof(h), &h, pvs__heap_less);
		v = h.node;
		if (e->placed[v]) continue;
		if (h.from && e->depth[h.from - 1] >= max_chain) continue; /* the chain would exceed K */
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
				pvs__pq_push(e->heap, &heap_n, sizeof(g), &g, pvs__heap_less);
			}
		}
	}
	return PVS_OK;
}

/* Writes the RECS body to `out`, or measures it when out is NULL. */
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

/* pvs_file_encode's checks, each with its error; *max_chain: K; *vocc_size: the VOCC section's size (0: none). */
PVS__STATIC pvs_result pvs__encode_check(const pvs_file_desc *d, uint32_t *max_chain, size_t *vocc_size,
										 pvs_error *err) {
	pvs_result r;
	uint32_t i;
	if (!d || !d->cells || !d->pvs || !d->cell_count || !d->object_count)
		return pvs__fail(err, PVS_ERROR_INVALID_ARGUMENT, -1, 0, "desc, cells and pvs must not be NULL or empty");
	if (d->up_axis != 1 && d->up_axis != 2)
		return pvs__fail(err, PVS_ERROR_INVALID_ARGUMENT, -1, 0, "up_axis must be 1 or 2");
	if ((int)d->method < 0 || d->method >= PVS_METHOD_COUNT || !pvs__finite(d->eps) || d->eps < 0.0f)
		return pvs__fail(err, PVS_ERROR_INVALID_ARGUMENT, -1, 0, "bad method or eps");
	if (d->cell_count == PVS_NO_CELL || d->object_count == 0xffffffffu || d->cell_count > 0x3fffffffu)
		return pvs__fail(err, PVS_ERROR_COUNT_OVERFLOW, -1, 0, "too many cells or objects");
	*max_chain = d->max_chain ? d->max_chain : PVS_DEFAULT_CHAIN;
	if (*max_chain > PVS_MAX_CHAIN)
		return pvs__fail(err, PVS_ERROR_INVALID_ARGUMENT, -1, 0, "max_chain %u > %u", *max_chain, PVS_MAX_CHAIN);
	if (d->shard_count == 1 ||
		(d->shard_count &&
		 (d->shard_index >= d->shard_count || d->total_cell_count > 0x3fffffffu ||
		  d->cell_count != (d->total_cell_count - d->shard_index + d->shard_count - 1) / d->shard_count)))
		return pvs__fail(err, PVS_ERROR_INVALID_ARGUMENT, -1, 0, "shard %u of %u does not hold %u of %u cells",
						 d->shard_index, d->shard_count, d->cell_count, d->total_cell_count);
	for (i = 0; i < d->cell_count; ++i) {
		r = pvs__check_cell(d->cells + i, i, err);
		if (r != PVS_OK) return r;
	}
	if (d->vocc_counts) { /* the optional VOCC section (>>vocc) */
		uint64_t n = 0;
		for (i = 0; i < d->cell_count; ++i) n += d->vocc_counts[i];
		*vocc_size = pvs__vo_section_size(d->cell_count, n);
		if (!d->vocc_scales || (n && !d->virtual_occluders) || !pvs__finite(d->vocc_base) ||
			!pvs__finite(d->vocc_height_step) || !(d->vocc_height_step > 0.0f) || (d->vocc_flags & ~PVS_VOCC_ONLY) ||
			!*vocc_size)
			return pvs__fail(err, PVS_ERROR_INVALID_ARGUMENT, -1, 0,
							 "virtual occluders: missing arrays, bad heights or flags");
	}
	return PVS_OK;
}

/* CELL: stored cells (-0 as +0), per axis the sorted distinct coordinates (e->values), packed field widths;
   *cell_bytes: its size. */
PVS__STATIC pvs_result pvs__encoder_cell_tables(pvs__encoder *e, size_t *cell_bytes, pvs_error *err) {
	const pvs_file_desc *d = e->d;
	size_t index_bits_total;
	uint32_t i, k;
	e->boxes = (pvs_box *)pvs__alloc_array(&e->a, e->cells, sizeof(pvs_box));
	if (!e->boxes) return pvs__fail(err, PVS_ERROR_OUT_OF_MEMORY, -1, 0, "cell boxes");
	for (i = 0; i < e->cells; ++i)
		for (k = 0; k < 3; ++k) {
			e->boxes[i].min[k] = d->cells[i].min[k] + 0.0f;
			e->boxes[i].max[k] = d->cells[i].max[k] + 0.0f;
		}
	for (k = 0; k < 3; ++k) {
		float *v = (float *)pvs__alloc_array(&e->a, 2 * (size_t)e->cells, sizeof(float));
		uint32_t n = 0, widest = 0;
		if (!v) return pvs__fail(err, PVS_ERROR_OUT_OF_MEMORY, -1, 0, "cell coordinate tables");
		e->values[k] = v;
		for (i = 0; i < e->cells; ++i) {
			v[2 * i] = e->boxes[i].min[k];
			v[2 * i + 1] = e->boxes[i].max[k];
		}
		PVS_QSORT(v, 2 * (size_t)e->cells, sizeof(float), pvs__float_cmp);
		for (i = 0; i < 2 * e->cells; ++i)
			if (!n || v[i] != v[n - 1]) v[n++] = v[i];
		e->value_count[k] = n;
		e->index_bits[k] = pvs__bits_for(n - 1);
		for (i = 0; i < e->cells; ++i) {
			uint32_t ext = pvs__value_index(v, n, e->boxes[i].max[k]) - pvs__value_index(v, n, e->boxes[i].min[k]);
			if (ext > widest) widest = ext;
		}
		e->index_bits[3 + k] = pvs__bits_for(widest);
	}
	index_bits_total = (size_t)(e->index_bits[0] + e->index_bits[1] + e->index_bits[2] + e->index_bits[3] +
								e->index_bits[4] + e->index_bits[5]) *
		e->cells;
	*cell_bytes = PVS__CELL_HEAD + 4 * ((size_t)e->value_count[0] + e->value_count[1] + e->value_count[2]) +
		(index_bits_total + 7) / 8;
	return PVS_OK;
}

/* kD-tree over the cells for base candidates; over centres if big overlapping cells would fill too many leaves. */
PVS__STATIC pvs_result pvs__encoder_kdtree(pvs__encoder *e, pvs_error *err) {
	pvs_kdtree_desc td;
	pvs_result r = PVS_OK;
	uint32_t long_cells = 0, i, k;
	memset(&td, 0, sizeof(td));
	td.boxes = e->boxes;
	td.count = e->cells;
	td.allocator = e->a;
	{ /* cells over 16 times the lower-quartile extent on an axis cross many split planes */
		float *ext = (float *)pvs__alloc_array(&e->a, e->cells, sizeof(float)), med[3];
		if (!ext) return pvs__fail(err, PVS_ERROR_OUT_OF_MEMORY, -1, 0, "cell extents");
		for (k = 0; k < 3; ++k) {
			for (i = 0; i < e->cells; ++i) ext[i] = e->boxes[i].max[k] - e->boxes[i].min[k];
			PVS_QSORT(ext, e->cells, sizeof(float), pvs__float_cmp);
			med[k] = ext[e->cells / 4]; /* lower quartile: half the cells may be long */
		}
		for (i = 0; i < e->cells; ++i)
			for (k = 0; k < 3; ++k)
				if (e->boxes[i].max[k] - e->boxes[i].min[k] > 16.0f * med[k]) {
					++long_cells;
					break;
				}
		pvs__free_array(&e->a, ext, e->cells, sizeof(float));
	}
	if (long_cells <= e->cells / 16) r = pvs_kdtree_create(&td, &e->tree, err);
	if (r == PVS_OK && (!e->tree || e->tree->item_count > 16u * e->cells)) {
		pvs_box *centres = (pvs_box *)pvs__alloc_array(&e->a, e->cells, sizeof(pvs_box));
		pvs_kdtree_destroy(e->tree);
		e->tree = NULL;
		if (!centres) return pvs__fail(err, PVS_ERROR_OUT_OF_MEMORY, -1, 0, "cell centres");
		for (i = 0; i < e->cells; ++i)
			for (k = 0; k < 3; ++k)
				centres[i].min[k] = centres[i].max[k] =
					0.5f * e->boxes[i].min[k] + 0.5f * e->boxes[i].max[k]; /* no overflow */
		td.boxes = centres;
		r = pvs_kdtree_create(&td, &e->tree, err);
		pvs__free_array(&e->a, centres, e->cells, sizeof(pvs_box));
	}
	return r;
}

/* TREE: D is the smallest depth giving leaves of about PVS__TREE_LEAF cells. */
PVS__STATIC pvs_result pvs__encoder_lookup_tree(pvs__encoder *e, pvs_error *err) {
	pvs__tbuild tb;
	pvs_result r;
	uint32_t *ids = (uint32_t *)pvs__alloc_array(&e->a, e->cells, sizeof(uint32_t)), leaves, i, k;
	memset(&tb, 0, sizeof(tb));
	tb.a = &e->a;
	tb.boxes = e->boxes;
	while (tb.depth < 20 && (e->cells >> tb.depth) > PVS__TREE_LEAF) ++tb.depth;
	leaves = 1u << tb.depth;
	tb.keys = (float *)pvs__alloc_array(&e->a, 2 * (size_t)e->cells, sizeof(float));
	tb.nodes = (uint32_t *)pvs__alloc_array(&e->a, leaves, sizeof(uint32_t));
	tb.leaf_start = (uint32_t *)pvs__alloc_array(&e->a, (size_t)leaves + 1, sizeof(uint32_t));
	for (k = 0; k < 3; ++k) tb.values[k] = e->values[k];
	tb.value_count = e->value_count;
	if (ids && tb.keys && tb.nodes && tb.leaf_start) {
		for (i = 0; i < e->cells; ++i) ids[i] = i;
		r = pvs__tree_node(&tb, ids, e->cells, 0, 0);
	} else {
		r = PVS_ERROR_OUT_OF_MEMORY;
	}
	if (r == PVS_OK) {
		uint8_t *t;
		tb.leaf_start[leaves] = (uint32_t)tb.item_bytes;
		e->tree_bytes = 5 * (size_t)(leaves - 1) + 4 * ((size_t)leaves + 1) + tb.item_bytes;
		e->tree_depth = tb.depth;
		e->tree_stream = t = (uint8_t *)pvs__alloc_array(&e->a, e->tree_bytes, 1);
		if (!t) {
			r = PVS_ERROR_OUT_OF_MEMORY;
		} else {
			/* splits, leaf offsets, axes; a node passing all left is axis 0 at FLT_MAX */
			for (i = 0; i + 1 < leaves; ++i, t += 4)
				pvs__putf32(t, (tb.nodes[i] & 3u) == 3u ? FLT_MAX : tb.values[tb.nodes[i] & 3u][tb.nodes[i] >> 2]);
			for (i = 0; i <= leaves; ++i, t += 4) pvs__put32(t, tb.leaf_start[i]);
			for (i = 0; i + 1 < leaves; ++i) *t++ = (uint8_t)((tb.nodes[i] & 3u) == 3u ? 0u : tb.nodes[i] & 3u);
			if (tb.item_bytes) memcpy(t, tb.items, tb.item_bytes);
		}
	}
	pvs__free_array(&e->a, ids, e->cells, sizeof(uint32_t));
	pvs__free_array(&e->a, tb.keys, 2 * (size_t)e->cells, sizeof(float));
	pvs__free_array(&e->a, tb.nodes, leaves, sizeof(uint32_t));
	pvs__free_array(&e->a, tb.leaf_start, (size_t)leaves + 1, sizeof(uint32_t));
	pvs__free_array(&e->a, tb.items, tb.item_capacity, 1);
	if (r != PVS_OK) return pvs__fail(err, r, -1, 0, "cell look-up tree");
	return PVS_OK;
}

/* Writes CELL at c (layout: the manual). */
PVS__STATIC void pvs__encoder_write_cells(const pvs__encoder *e, uint8_t *c) {
	uint8_t *v, *bits;
	uint64_t pos = 0;
	uint32_t i, k;
	for (k = 0; k < 3; ++k) pvs__put32(c + 4 * k, e->value_count[k]);
	for (k = 0; k < 6; ++k) c[12 + k] = (uint8_t)e->index_bits[k];
	v = c + PVS__CELL_HEAD;
	for (k = 0; k < 3; ++k)
		for (i = 0; i < e->value_count[k]; ++i, v += 4) pvs__putf32(v, e->values[k][i]);
	bits = v;
	for (i = 0; i < e->cells; ++i) {
		uint32_t lo[3];
		for (k = 0; k < 3; ++k) {
			lo[k] = pvs__value_index(e->values[k], e->value_count[k], e->boxes[i].min[k]);
			pvs__put_bits(bits, pos, lo[k], e->index_bits[k]);
			pos += e->index_bits[k];
		}
		for (k = 0; k < 3; ++k) {
			pvs__put_bits(bits, pos, pvs__value_index(e->values[k], e->value_count[k], e->boxes[i].max[k]) - lo[k],
						  e->index_bits[3 + k]);
			pos += e->index_bits[3 + k];
		}
	}
}

/* Header and section table for `total` bytes of written sections: section CRC-32s, then the header's. */
PVS__STATIC void pvs__encoder_write_header(uint8_t *o, size_t total, uint32_t flags, uint32_t sections,
										   const uint32_t *tags, const size_t *at, const size_t *sz) {
	uint32_t k, crc;
	memcpy(o, "PVS\x1a", 4);
	pvs__put32(o + 4, PVS_FORMAT_VERSION);
	pvs__put32(o + 8, (uint32_t)total);
	pvs__put32(o + 12, sections);
	pvs__put32(o + 16, flags);
	for (k = 0; k < sections; ++k) {
		uint8_t *en = o + PVS__HEADER_SIZE + PVS__SECTION_ENTRY * k;
		pvs__put32(en + 0, tags[k]);
		pvs__put32(en + 4, (uint32_t)at[k]);
		pvs__put32(en + 8, (uint32_t)sz[k]);
		pvs__put32(en + 12, pvs__crc32(0, o + at[k], sz[k]));
	}
	crc = pvs__crc32(0, o, 20);
	crc = pvs__crc32(crc, o + PVS__HEADER_SIZE, (size_t)sections * PVS__SECTION_ENTRY);
	pvs__put32(o + 20, crc);
}

PVS_API pvs_result pvs_file_encode(const pvs_file_desc *d, void *out, size_t capacity, size_t *out_size,
								   pvs_error *err) {
	pvs__encoder e;
	pvs_result r;
	uint32_t i, k, max_chain = 0, sections, keys = 0;
	size_t at[6], sz[6], total, cell_bytes = 0, recs_size, vocc_size = 0;
	uint32_t tags[6];
	uint8_t *o = (uint8_t *)out;
	if (out_size) *out_size = 0;
	r = pvs__encode_check(d, &max_chain, &vocc_size, err);
	if (r != PVS_OK) return r;
	memset(&e, 0, sizeof(e));
	e.a = d->allocator;
	e.d = d;
	e.n = d->object_count;
	e.cells = d->cell_count;
	e.words = PVS_BITSET_WORDS(d->object_count);

	r = pvs__encoder_cell_tables(&e, &cell_bytes, err);
	if (r != PVS_OK) goto done;
	r = pvs__encoder_kdtree(&e, err);
	if (r != PVS_OK) goto done;
	r = pvs__encoder_lookup_tree(&e, err);
	if (r != PVS_OK) goto done;

	e.tmp = (pvs_word *)pvs__alloc_array(&e.a, e.words, sizeof(pvs_word));
	e.ranks = (pvs_word *)pvs__alloc_array(&e.a, e.words, sizeof(pvs_word));
	if (!e.tmp || !e.ranks) { r = pvs__fail(err, PVS_ERROR_OUT_OF_MEMORY, -1, 0, "encoder bitset"); goto done; }
	r = pvs__encoder_bases(&e, max_chain, err);
	if (r != PVS_OK) goto done;
	for (i = 0; i < e.cells; ++i) keys += e.base[i] == PVS_NO_CELL;
	recs_size = pvs__encoder_records(&e, NULL);

	/* sections in the manual's order, each 8-aligned */
	sections = d->shard_count ? 5u : 4u;
	tags[0] = PVS__TAG_META; sz[0] = PVS__META_SIZE;
	tags[1] = PVS__TAG_CELL; sz[1] = cell_bytes;
	tags[2] = PVS__TAG_TREE; sz[2] = PVS__TREE_HEAD + e.tree_bytes;
	tags[3] = PVS__TAG_RECS; sz[3] = recs_size;
	tags[4] = PVS__TAG_SHRD; sz[4] = PVS__SHRD_SIZE;
	if (d->vocc_counts) {
		tags[sections] = PVS__VO_TAG;
		sz[sections++] = vocc_size;
	}
	total = pvs__align8(PVS__HEADER_SIZE + PVS__SECTION_ENTRY * (size_t)sections);
	for (k = 0; k < sections; ++k) {
		at[k] = total;
		total = pvs__align8(total + sz[k]);
	}
	if (total > 0xffffffffu) {
		r = pvs__fail(err, PVS_ERROR_COUNT_OVERFLOW, -1, 0, "the file would exceed 4 GiB");
		goto done;
	}
	if (out_size) *out_size = total;
	if (!o) { /* size query */
		pvs__ok(err);
		goto done;
	}
	if (capacity < total) {
		r = pvs__fail(err, PVS_ERROR_BUFFER_TOO_SMALL, -1, 0, "need %llu bytes, have %llu", (unsigned long long)total,
					  (unsigned long long)capacity);
		goto done;
	}
	memset(o, 0, total);
	{
		uint8_t *m = o + at[0];
		pvs__put32(m + 0, e.cells);
		pvs__put32(m + 4, e.n);
		pvs__put32(m + 8, (uint32_t)d->method);
		pvs__putf32(m + 12, d->eps);
		pvs__put32(m + 16, d->up_axis);
		pvs__put32(m + 20, max_chain);
		pvs__put32(m + 24, keys);
	}
	pvs__encoder_write_cells(&e, o + at[1]);
	pvs__put32(o + at[2], e.tree_depth);
	memcpy(o + at[2] + PVS__TREE_HEAD, e.tree_stream, e.tree_bytes);
	(void)pvs__encoder_records(&e, o + at[3]);
	if (d->shard_count) {
		uint8_t *s = o + at[4];
		pvs__put32(s + 0, d->shard_index);
		pvs__put32(s + 4, d->shard_count);
		pvs__put32(s + 8, d->total_cell_count);
	}
	if (d->vocc_counts)
		pvs__vo_section_write(o + at[sections - 1], (d->vocc_flags & PVS_VOCC_ONLY) ? 1u : 0u, d->vocc_base,
							  d->vocc_height_step, d->cell_count, d->vocc_counts, d->vocc_scales, d->virtual_occluders,
							  d->vocc_stride);
	pvs__encoder_write_header(o, total, d->flags, sections, tags, at, sz);
	pvs__ok(err);
done:
	pvs__encoder_free(&e);
	return r;
}

/* ---- reader ---- */

/* A record located by the reader (files that passed pvs_file_open only). */
typedef struct pvs__rec {
	const uint8_t *start, *body, *end; /* body: a delta's removed ranks, else the added ids */
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

/* Applies a record: a key adds its ids (bits start empty); a delta removes its ranks (in the base's PVS, in bits), then
   adds. Changes go to fn. Opened files only. */
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

PVS__STATIC pvs_result pvs__open_cells(pvs_file *f, const uint8_t *base, const uint8_t *c, uint32_t size,
									   pvs_error *err) {
	uint64_t off = (uint64_t)(c - base), need, nbits, pos = 0;
	uint32_t k, i, total = 0;
	const uint8_t *v;
	if (size < PVS__CELL_HEAD)
		return pvs__fail(err, PVS_ERROR_BAD_SECTION, -1, off, "CELL has %u bytes, fewer than its 20-byte head", size);
	for (k = 0; k < 3; ++k) {
		uint32_t n = pvs__get32(c + 4 * k);
		if (n == 0 || n > 2 * (uint64_t)f->cell_count)
			return pvs__fail(err, PVS_ERROR_BAD_SECTION, -1, off + 4 * k,
							 "CELL: %u coordinates on axis %u for %u cells", n, k, f->cell_count);
		if (c[12 + k] != pvs__bits_for(n - 1))
			return pvs__fail(err, PVS_ERROR_BAD_SECTION, -1, off + 12 + k,
							 "CELL: index width %u on axis %u, %u values need %u", c[12 + k], k, n,
							 pvs__bits_for(n - 1));
		if (c[15 + k] > pvs__bits_for(n - 1))
			return pvs__fail(err, PVS_ERROR_BAD_SECTION, -1, off + 15 + k,
							 "CELL: extent width %u on axis %u exceeds %u", c[15 + k], k, pvs__bits_for(n - 1));
		f->private_.value_count[k] = n;
		f->private_.index_bits[k] = c[12 + k];
		f->private_.index_bits[3 + k] = c[15 + k];
		total += n;
	}
	if (c[18] || c[19]) return pvs__fail(err, PVS_ERROR_BAD_SECTION, -1, off + 18, "CELL: reserved bytes are not zero");
	f->private_.cell_bits = f->private_.index_bits[0] + f->private_.index_bits[1] + f->private_.index_bits[2] +
		f->private_.index_bits[3] + f->private_.index_bits[4] + f->private_.index_bits[5];
	nbits = (uint64_t)f->private_.cell_bits * f->cell_count;
	need = PVS__CELL_HEAD + 4 * (uint64_t)total + (nbits + 7) / 8;
	if (need != size)
		return pvs__fail(err, PVS_ERROR_BAD_SECTION, -1, off, "CELL has %u bytes, its tables and indices need %llu",
						 size, (unsigned long long)need);
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
				return pvs__fail(err, PVS_ERROR_BAD_CELL, i, (uint64_t)(v - base) + pos / 8,
								 "cell %u: coordinate index %u + %u out of range on axis %u", i, idx[k], idx[k + 3], k);
	}
	if ((nbits & 7u) && (v[nbits / 8] >> (nbits & 7u)))
		return pvs__fail(err, PVS_ERROR_BAD_SECTION, -1, (uint64_t)(v - base) + nbits / 8,
						 "CELL: unused index bits are not zero");
	return PVS_OK;
}

/* TREE, as the manual lays it out. Splits and axes lie apart so a level costs one dependent load. */
PVS__STATIC pvs_result pvs__open_tree(pvs_file *f, const uint8_t *base, const uint8_t *t, uint32_t size,
									  pvs_error *err) {
	uint64_t off = (uint64_t)(t - base), need;
	uint32_t depth, inner, leaves, i;
	const uint8_t *nodes, *starts, *items;
	if (size < PVS__TREE_HEAD)
		return pvs__fail(err, PVS_ERROR_BAD_TREE, -1, off, "TREE has %u bytes, fewer than its 8-byte head", size);
	depth = pvs__get32(t);
	if (depth > PVS__TREE_MAX_DEPTH)
		return pvs__fail(err, PVS_ERROR_BAD_TREE, -1, off, "TREE depth %u > %u", depth, PVS__TREE_MAX_DEPTH);
	if (pvs__get32(t + 4)) return pvs__fail(err, PVS_ERROR_BAD_TREE, -1, off + 4, "TREE reserved field is not zero");
	leaves = 1u << depth;
	inner = leaves - 1u;
	need = PVS__TREE_HEAD + 5 * (uint64_t)inner + 4 * ((uint64_t)leaves + 1);
	if (need > size)
		return pvs__fail(err, PVS_ERROR_BAD_TREE, -1, off, "TREE has %u bytes, depth %u needs %llu before its items",
						 size, depth, (unsigned long long)need);
	nodes = t + PVS__TREE_HEAD;
	starts = nodes + 4 * (size_t)inner;
	items = starts + 4 * ((size_t)leaves + 1) + inner;
	for (i = 0; i < inner; ++i) {
		uint8_t axis = starts[4 * ((size_t)leaves + 1) + i];
		if (axis > 2u || !pvs__finite(pvs__getf32(nodes + 4 * (size_t)i)))
			return pvs__fail(err, PVS_ERROR_BAD_TREE, i, off + PVS__TREE_HEAD + 4 * (uint64_t)i,
							 "TREE node %u: axis %u or split not finite", i, axis);
	}
	if (pvs__get32(starts) != 0 || pvs__get32(starts + 4 * (size_t)leaves) != size - need)
		return pvs__fail(err, PVS_ERROR_BAD_TREE, -1, (uint64_t)(starts - base),
						 "TREE leaf offsets do not span its items");
	for (i = 0; i < leaves; ++i) {
		uint32_t lo = pvs__get32(starts + 4 * (size_t)i), hi = pvs__get32(starts + 4 * (size_t)i + 4);
		const uint8_t *p = items + lo, *end = items + hi;
		uint64_t id = 0;
		int first = 1;
		if (hi < lo || hi > size - need)
			return pvs__fail(err, PVS_ERROR_BAD_TREE, i, (uint64_t)(starts - base) + 4 * (uint64_t)i,
							 "TREE leaf %u offsets do not ascend", i);
		while (p < end) {
			uint32_t g;
			size_t used = pvs__get_varint(p, end, &g);
			if (!used)
				return pvs__fail(err, PVS_ERROR_BAD_TREE, i, (uint64_t)(p - base), "TREE leaf %u: bad cell id", i);
			id = first ? g : id + 1u + g;
			first = 0;
			if (id >= f->cell_count)
				return pvs__fail(err, PVS_ERROR_BAD_TREE, i, (uint64_t)(p - base), "TREE leaf %u names cell %llu of %u",
								 i, (unsigned long long)id, f->cell_count);
			p += used;
		}
	}
	f->private_.tree = nodes;
	f->private_.tree_depth = depth;
	return PVS_OK;
}

/* RECS: each record's structure, then the chains: depth falls by one per base, so a chain reaches a key within
   max_chain steps and cannot cycle. Linear in the section. */
PVS__STATIC pvs_result pvs__open_records(pvs_file *f, const uint8_t *base, const uint8_t *rs, uint32_t size,
										 pvs_error *err) {
	uint64_t off = (uint64_t)(rs - base);
	uint32_t blocks = (f->cell_count + PVS__BLOCK - 1) / PVS__BLOCK, b, keys = 0, i;
	if ((uint64_t)4 * (blocks + 1) > size)
		return pvs__fail(err, PVS_ERROR_BAD_SECTION, -1, off, "RECS is too small for %u block offsets", blocks + 1);
	if (pvs__get32(rs) != 4 * (blocks + 1))
		return pvs__fail(err, PVS_ERROR_BAD_RECORD, 0, off, "block 0 does not start after the offset table");
	if (pvs__get32(rs + 4 * (size_t)blocks) != size)
		return pvs__fail(err, PVS_ERROR_BAD_RECORD, -1, off + 4 * (uint64_t)blocks,
						 "the last block offset is not the section size");
	for (b = 0; b < blocks; ++b) {
		uint32_t lo = pvs__get32(rs + 4 * (size_t)b), hi = pvs__get32(rs + 4 * (size_t)b + 4), cell;
		const uint8_t *p = rs + lo, *end = rs + hi;
		if (hi < lo || hi > size)
			return pvs__fail(err, PVS_ERROR_BAD_RECORD, -1, off + 4 * (uint64_t)b, "block %u offsets do not ascend", b);
		for (cell = b * PVS__BLOCK; cell < f->cell_count && cell < (b + 1) * PVS__BLOCK; ++cell) {
			uint32_t len, head, zz, depth;
			const uint8_t *rend;
			size_t used = pvs__get_varint(p, end, &len), bad = 0;
			pvs_result r;
			if (!used || len > (size_t)(end - p) - used)
				return pvs__fail(err, PVS_ERROR_BAD_RECORD, cell, (uint64_t)(p - base), "record of cell %u: bad length",
								 cell);
			p += used;
			rend = p + len;
			used = pvs__get_varint(p, rend, &head);
			if (!used)
				return pvs__fail(err, PVS_ERROR_BAD_RECORD, cell, (uint64_t)(p - base), "record of cell %u: bad head",
								 cell);
			p += used;
			depth = head >> 2;
			if (depth > f->max_chain)
				return pvs__fail(err, PVS_ERROR_BAD_CHAIN, cell, (uint64_t)(p - base), "cell %u: chain depth %u > %u",
								 cell, depth, f->max_chain);
			if (depth) {
				int64_t bc;
				used = pvs__get_varint(p, rend, &zz);
				if (!used)
					return pvs__fail(err, PVS_ERROR_BAD_RECORD, cell, (uint64_t)(p - base),
									 "record of cell %u: bad base", cell);
				bc = (int64_t)cell - pvs__unzigzag(zz);
				if (bc < 0 || bc >= (int64_t)f->cell_count || bc == (int64_t)cell)
					return pvs__fail(err, PVS_ERROR_BAD_CHAIN, cell, (uint64_t)(p - base),
									 "cell %u: base %lld is itself or no cell", cell, (long long)bc);
				p += used;
			} else {
				++keys;
			}
			{
				pvs__sink check;
				size_t body = 0;
				memset(&check, 0, sizeof(check));
				if (depth) { /* removed ranks: coding byte, base PVS size, ranks below it */
					uint32_t m;
					if (p >= rend || *p > 3u)
						return pvs__fail(err, PVS_ERROR_BAD_RECORD, cell, (uint64_t)(p - base),
										 "record of cell %u: bad coding", cell);
					used = pvs__get_varint(p + 1, rend, &m);
					if (!used || m > f->object_count)
						return pvs__fail(err, PVS_ERROR_BAD_RECORD, cell, (uint64_t)(p - base),
										 "record of cell %u: bad base size", cell);
					r = pvs__set_apply(p + 1 + used, rend, *p, m, &check, &body, &bad);
					if (r != PVS_OK)
						return pvs__fail(err, r, cell, (uint64_t)(p + 1 + used - base) + bad,
										 "record of cell %u (removed)", cell);
					p += 1 + used + body;
				}
				r = pvs__set_apply(p, rend, head & 3u, f->object_count, &check, &body, &bad);
				if (r != PVS_OK) return pvs__fail(err, r, cell, (uint64_t)(p - base) + bad, "record of cell %u", cell);
				if (p + body != rend)
					return pvs__fail(err, PVS_ERROR_BAD_RECORD, cell, (uint64_t)(p + body - base),
									 "record of cell %u: bytes after its sets", cell);
			}
			p = rend;
		}
		if (p != end)
			return pvs__fail(err, PVS_ERROR_BAD_RECORD, -1, (uint64_t)(p - base),
							 "block %u has bytes after its last record", b);
	}
	if (keys != f->key_count)
		return pvs__fail(err, PVS_ERROR_BAD_HEADER, -1, 0, "META says %u key cells, the records have %u", f->key_count,
						 keys);
	for (i = 0; i < f->cell_count; ++i) {
		pvs__rec r, rb;
		pvs__record_at(f, i, &r);
		if (!r.depth) continue;
		pvs__record_at(f, r.base, &rb);
		if (rb.depth + 1 != r.depth)
			return pvs__fail(err, PVS_ERROR_BAD_CHAIN, i, (uint64_t)(r.start - base),
							 "cell %u: depth %u, its base %u has depth %u", i, r.depth, r.base, rb.depth);
	}
	return PVS_OK;
}

/* The sections pvs_file_open knows, as the table places them (NULL: absent). */
typedef struct pvs__open_sections {
	const uint8_t *meta, *cells, *tree, *recs, *shrd, *vocc;
	uint32_t meta_size, cells_size, tree_size, recs_size, shrd_size, vocc_size;
} pvs__open_sections;

/* The header, in the format table's order. *count_out: the section count. */
PVS__STATIC pvs_result pvs__open_header(const uint8_t *p, size_t size, uint32_t *count_out, pvs_error *err) {
	uint32_t count, crc;
	if (size < 4 || memcmp(p, "PVS\x1a", 4) != 0)
		return pvs__fail(err, size < 4 ? PVS_ERROR_TRUNCATED : PVS_ERROR_BAD_MAGIC, -1, 0, "not a .pvs file (magic)");
	if (size < PVS__HEADER_SIZE)
		return pvs__fail(err, PVS_ERROR_TRUNCATED, -1, size, "the header needs 32 bytes, have %llu",
						 (unsigned long long)size);
	if (pvs__get32(p + 4) != PVS_FORMAT_VERSION)
		return pvs__fail(err, PVS_ERROR_BAD_VERSION, -1, 4, "format version %u, this reader knows %d",
						 pvs__get32(p + 4), PVS_FORMAT_VERSION);
	if (pvs__get32(p + 8) != size) {
		pvs_result code = pvs__get32(p + 8) > size ? PVS_ERROR_TRUNCATED : PVS_ERROR_BAD_HEADER;
		return pvs__fail(err, code, -1, 8, "the header says %u bytes, the buffer has %llu", pvs__get32(p + 8),
						 (unsigned long long)size);
	}
	count = pvs__get32(p + 12);
	if (count == 0 || count > PVS__MAX_SECTIONS)
		return pvs__fail(err, PVS_ERROR_BAD_HEADER, -1, 12, "section count %u is not in 1..%u", count,
						 PVS__MAX_SECTIONS);
	if (PVS__HEADER_SIZE + (size_t)count * PVS__SECTION_ENTRY > size)
		return pvs__fail(err, PVS_ERROR_TRUNCATED, -1, PVS__HEADER_SIZE, "the section table runs past the end");
	crc = pvs__crc32(0, p, 20);
	crc = pvs__crc32(crc, p + PVS__HEADER_SIZE, (size_t)count * PVS__SECTION_ENTRY);
	if (crc != pvs__get32(p + 20)) return pvs__fail(err, PVS_ERROR_CHECKSUM, -1, 20, "header checksum");
	if (pvs__get32(p + 24) || pvs__get32(p + 28))
		return pvs__fail(err, PVS_ERROR_BAD_HEADER, -1, 24, "reserved header bytes are not zero");
	*count_out = count;
	return PVS_OK;
}

/* The section table, rules as in the manual; known tags into *sec. */
PVS__STATIC pvs_result pvs__open_table(const uint8_t *p, size_t size, uint32_t count, pvs__open_sections *sec,
									   pvs_error *err) {
	uint32_t i, j;
	for (i = 0; i < count; ++i) {
		const uint8_t *e = p + PVS__HEADER_SIZE + PVS__SECTION_ENTRY * (size_t)i;
		uint32_t tag = pvs__get32(e), off = pvs__get32(e + 4), sz = pvs__get32(e + 8);
		uint64_t at = PVS__HEADER_SIZE + PVS__SECTION_ENTRY * (uint64_t)i;
		if ((off & 7u) || off < PVS__HEADER_SIZE + count * PVS__SECTION_ENTRY)
			return pvs__fail(err, PVS_ERROR_BAD_SECTION, i, at,
							 "section %u: offset %u is misaligned or inside the header", i, off);
		if ((uint64_t)off + sz > size)
			return pvs__fail(err, PVS_ERROR_TRUNCATED, i, at, "section %u: bytes %u..%llu run past the end", i, off,
							 (unsigned long long)off + sz);
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
		if (tag == PVS__TAG_META) { sec->meta = p + off; sec->meta_size = sz; }
		else if (tag == PVS__TAG_CELL) { sec->cells = p + off; sec->cells_size = sz; }
		else if (tag == PVS__TAG_TREE) { sec->tree = p + off; sec->tree_size = sz; }
		else if (tag == PVS__TAG_RECS) { sec->recs = p + off; sec->recs_size = sz; }
		else if (tag == PVS__TAG_SHRD) { sec->shrd = p + off; sec->shrd_size = sz; }
		else if (tag == PVS__VO_TAG) { sec->vocc = p + off; sec->vocc_size = sz; }
	}
	return PVS_OK;
}

/* Bytes outside header, table and sections must be zero: each byte of a valid file is checksummed or fixed. */
PVS__STATIC pvs_result pvs__open_padding(const uint8_t *p, size_t size, uint32_t count, pvs_error *err) {
	uint32_t order[PVS__MAX_SECTIONS], i, j, k;
	size_t pos = PVS__HEADER_SIZE + (size_t)count * PVS__SECTION_ENTRY;
	for (i = 0; i < count; ++i) { /* insertion sort by offset; count <= 64 */
		uint32_t off = pvs__get32(p + PVS__HEADER_SIZE + PVS__SECTION_ENTRY * (size_t)i + 4);
		for (j = i; j > 0 && pvs__get32(p + PVS__HEADER_SIZE + PVS__SECTION_ENTRY * (size_t)order[j - 1] + 4) > off;
			 --j)
			order[j] = order[j - 1];
		order[j] = i;
	}
	for (k = 0; k <= count; ++k) {
		const uint8_t *e = k < count ? p + PVS__HEADER_SIZE + PVS__SECTION_ENTRY * (size_t)order[k] : NULL;
		size_t next = e ? pvs__get32(e + 4) : size;
		for (; pos < next; ++pos)
			if (p[pos])
				return pvs__fail(err, PVS_ERROR_BAD_SECTION, -1, pos, "padding byte %llu is not zero",
								 (unsigned long long)pos);
		if (e && (size_t)pvs__get32(e + 4) + pvs__get32(e + 8) > pos)
			pos = (size_t)pvs__get32(e + 4) + pvs__get32(e + 8);
	}
	return PVS_OK;
}

/* META (32 bytes) into f, checked in the format table's order. */
PVS__STATIC pvs_result pvs__open_meta(pvs_file *f, const uint8_t *p, const uint8_t *meta, uint32_t meta_size,
									  pvs_error *err) {
	uint64_t mo = (uint64_t)(meta - p);
	if (meta_size != PVS__META_SIZE)
		return pvs__fail(err, PVS_ERROR_BAD_SECTION, -1, mo, "META has %u bytes, not 32", meta_size);
	f->cell_count = pvs__get32(meta);
	f->object_count = pvs__get32(meta + 4);
	f->method = (pvs_method)pvs__get32(meta + 8);
	f->eps = pvs__getf32(meta + 12);
	f->up_axis = pvs__get32(meta + 16);
	f->max_chain = pvs__get32(meta + 20);
	f->key_count = pvs__get32(meta + 24);
	if (f->cell_count == 0) return pvs__fail(err, PVS_ERROR_BAD_HEADER, -1, mo, "cell count 0");
	if (f->cell_count > 0x3fffffffu)
		return pvs__fail(err, PVS_ERROR_COUNT_OVERFLOW, -1, mo, "cell count %u > 2^30 - 1", f->cell_count);
	if (f->object_count == 0) return pvs__fail(err, PVS_ERROR_BAD_HEADER, -1, mo + 4, "object count 0");
	if (f->object_count == 0xffffffffu)
		return pvs__fail(err, PVS_ERROR_COUNT_OVERFLOW, -1, mo + 4, "object count 2^32 - 1");
	if (pvs__get32(meta + 8) >= (uint32_t)PVS_METHOD_COUNT)
		return pvs__fail(err, PVS_ERROR_BAD_HEADER, -1, mo + 8, "unknown method %u", pvs__get32(meta + 8));
	if (!pvs__finite(f->eps) || f->eps < 0.0f)
		return pvs__fail(err, PVS_ERROR_BAD_HEADER, -1, mo + 12, "eps is not a finite number >= 0");
	if (f->up_axis != 1 && f->up_axis != 2)
		return pvs__fail(err, PVS_ERROR_BAD_HEADER, -1, mo + 16, "up axis %u", f->up_axis);
	if (f->max_chain == 0 || f->max_chain > PVS_MAX_CHAIN)
		return pvs__fail(err, PVS_ERROR_BAD_HEADER, -1, mo + 20, "chain bound %u is not in 1..%u", f->max_chain,
						 PVS_MAX_CHAIN);
	if (f->key_count == 0 || f->key_count > f->cell_count)
		return pvs__fail(err, PVS_ERROR_BAD_HEADER, -1, mo + 24, "%u key cells of %u", f->key_count, f->cell_count);
	if (pvs__get32(meta + 28))
		return pvs__fail(err, PVS_ERROR_BAD_HEADER, -1, mo + 28, "reserved META bytes are not zero");
	return PVS_OK;
}

/* SHRD (16 bytes) into f: a part of cell_count cells of a sharded bake. */
PVS__STATIC pvs_result pvs__open_shard(pvs_file *f, const uint8_t *p, const uint8_t *shrd, uint32_t shrd_size,
									   pvs_error *err) {
	uint64_t so = (uint64_t)(shrd - p);
	if (shrd_size != PVS__SHRD_SIZE)
		return pvs__fail(err, PVS_ERROR_BAD_SECTION, -1, so, "SHRD has %u bytes, not 16", shrd_size);
	f->shard_index = pvs__get32(shrd);
	f->shard_count = pvs__get32(shrd + 4);
	f->total_cell_count = pvs__get32(shrd + 8);
	if (f->shard_count < 2 || f->shard_index >= f->shard_count || f->total_cell_count > 0x3fffffffu ||
		pvs__get32(shrd + 12) ||
		f->cell_count != (f->total_cell_count - f->shard_index + f->shard_count - 1) / f->shard_count)
		return pvs__fail(err, PVS_ERROR_BAD_HEADER, -1, so, "SHRD: shard %u of %u cannot hold %u of %u cells",
						 f->shard_index, f->shard_count, f->cell_count, f->total_cell_count);
	return PVS_OK;
}

PVS_API pvs_result pvs_file_open(const void *data, size_t size, pvs_file *f, pvs_error *err) {
	const uint8_t *p = (const uint8_t *)data;
	uint32_t count = 0;
	pvs__open_sections sec;
	pvs_result r;
	if (!f) return pvs__fail(err, PVS_ERROR_INVALID_ARGUMENT, -1, 0, "file must not be NULL");
	memset(f, 0, sizeof(*f));
	if (!p && size) return pvs__fail(err, PVS_ERROR_INVALID_ARGUMENT, -1, 0, "data is NULL");
	r = pvs__open_header(p, size, &count, err);
	if (r != PVS_OK) return r;
	memset(&sec, 0, sizeof(sec));
	r = pvs__open_table(p, size, count, &sec, err);
	if (r != PVS_OK) return r;
	r = pvs__open_padding(p, size, count, err);
	if (r != PVS_OK) return r;
	if (!sec.meta || !sec.cells || !sec.tree || !sec.recs)
		return pvs__fail(err, PVS_ERROR_BAD_SECTION, -1, 0, "missing required section %s",
						 !sec.meta ? "META" : !sec.cells ? "CELL" : !sec.tree ? "TREE" : "RECS");
	r = pvs__open_meta(f, p, sec.meta, sec.meta_size, err);
	if (r != PVS_OK) return r;
	if (sec.shrd) {
		r = pvs__open_shard(f, p, sec.shrd, sec.shrd_size, err);
		if (r != PVS_OK) return r;
	}
	/* records first: 3 bytes or more each, a valid RECS bounds the cell count by the file size and the cell checks stay
	   linear (indices can be 0 bits wide) */
	f->private_.records = sec.recs;
	f->private_.records_size = sec.recs_size;
	f->private_.block_count = (f->cell_count + PVS__BLOCK - 1) / PVS__BLOCK;
	r = pvs__open_records(f, p, sec.recs, sec.recs_size, err);
	if (r == PVS_OK) r = pvs__open_cells(f, p, sec.cells, sec.cells_size, err);
	if (r == PVS_OK) r = pvs__open_tree(f, p, sec.tree, sec.tree_size, err);
	if (r == PVS_OK && sec.vocc) r = pvs__vo_open_section(f, p, sec.vocc, sec.vocc_size, err);
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

PVS_API void pvs_file_get_record_info(const pvs_file *f, uint32_t cell, pvs_record_info *info) {
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
/* ==== runtime: cell look-up through the stored kD-tree, decoding, the cursor; no allocation ==== */

/* Cell c's coordinate indices, min then max per axis (one 64-bit read when the six fit). */
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

/* Does cell c contain p? The look-up's inner loop, with pvs__cell_indices' fast path inlined. */
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
		if (p[0] < pvs__getf32(f->private_.values[0] + 4 * (size_t)lo0) ||
			p[0] > pvs__getf32(f->private_.values[0] + 4 * (size_t)(lo0 + e0)))
			return 0;
		e1 = (uint32_t)(w & (((uint64_t)1 << wb[4]) - 1u)); w >>= wb[4];
		if (p[1] < pvs__getf32(f->private_.values[1] + 4 * (size_t)lo1) ||
			p[1] > pvs__getf32(f->private_.values[1] + 4 * (size_t)(lo1 + e1)))
			return 0;
		e0 = (uint32_t)(w & (((uint64_t)1 << wb[5]) - 1u));
		return !(p[2] < pvs__getf32(f->private_.values[2] + 4 * (size_t)lo2) ||
				 p[2] > pvs__getf32(f->private_.values[2] + 4 * (size_t)(lo2 + e0)));
	}
	pvs__cell_indices(f, c, idx);
	for (k = 0; k < 3; ++k)
		if (p[k] < pvs__getf32(f->private_.values[k] + 4 * (size_t)idx[k]) ||
			p[k] > pvs__getf32(f->private_.values[k] + 4 * (size_t)idx[k + 3]))
			return 0;
	return 1;
}

/* Point location, the manual's TREE rule (p == split: a stack no deeper than the tree); lowest containing cell wins. */
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
			/* k's children sit side by side, loaded while k compares: one load latency per level (branch-free) */
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
			const uint8_t *q = items + pvs__get32(starts + 4 * (size_t)(k - inner)),
						  *end = items + pvs__get32(starts + 4 * (size_t)(k - inner) + 4);
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
	for (;;) { /* from the cell to its key: at most max_chain + 1 records (checked by open) */
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

PVS_API pvs_result pvs_file_decode(const pvs_file *f, uint32_t cell, pvs_word *bits, size_t word_count,
								   pvs_error *err) {
	if (!f || !bits || !f->data)
		return pvs__fail(err, PVS_ERROR_INVALID_ARGUMENT, -1, 0, "file and bits must not be NULL");
	if (cell >= f->cell_count)
		return pvs__fail(err, PVS_ERROR_INVALID_ARGUMENT, cell, 0, "cell %u of %u", cell, f->cell_count);
	if (word_count < PVS_BITSET_WORDS(f->object_count))
		return pvs__fail(err, PVS_ERROR_BUFFER_TOO_SMALL, -1, 0, "%llu words, %u objects need %llu",
						 (unsigned long long)word_count, f->object_count,
						 (unsigned long long)PVS_BITSET_WORDS(f->object_count));
	pvs__file_decode(f, cell, bits, word_count);
	pvs__ok(err);
	return PVS_OK;
}

PVS_API pvs_result pvs_cursor_init(pvs_cursor *c, const pvs_file *f, pvs_word *bits, pvs_word *scratch,
								   size_t word_count, pvs_error *err) {
	if (!c || !f || !f->data || !bits || !scratch || bits == scratch)
		return pvs__fail(err, PVS_ERROR_INVALID_ARGUMENT, -1, 0,
						 "cursor, file, bits and scratch must be given, bits != scratch");
	if (word_count < PVS_BITSET_WORDS(f->object_count))
		return pvs__fail(err, PVS_ERROR_BUFFER_TOO_SMALL, -1, 0, "%llu words, %u objects need %llu",
						 (unsigned long long)word_count, f->object_count,
						 (unsigned long long)PVS_BITSET_WORDS(f->object_count));
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
   0.5.0 (2026-11-28) AUTO pays for what culls (a sample of cells chooses the methods it runs); shared
					  kernels (priority queue, union-find); the header indented with tabs.
   0.4.0 (2026-11-28) AUTO (the default), max_distance, PREVIEW, resumable bakes, virtual occluders (vocc),
					  extproj's slices, sheets and occlusion sweep, adaptive cells; bounded memory; the
					  method table; per-method parameter structs in pvs_bake_desc, pvs_*_get_* getters.
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
