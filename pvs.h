/* pvs.h - v0.1.0 - conservative potentially visible sets: bake, store, look up, cull - public domain or MIT (see end of file)

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
       size_t size = pvs_bake_file_bound(bake);
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
   >>raster     conservative rasterizer, depth pyramid, cull map            (planned)
   >>otree      occlusion trees: line-space BSP; exact 2D and conservative 2.5D (c-LSS) region visibility
   >>occluders  occluder synthesis                                        (planned)
   >>methods    region methods; today the ray-sampling estimator `sample`
   >>bake       bake driver: tasks, determinism
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

   FILE FORMAT (version 1; all integers little-endian; offsets from the start of the file)
   ===========
   header, 32 bytes:
     0  u8[4]  magic "PVS\x1a"
     4  u32    format version (PVS_FORMAT_VERSION); a reader rejects any other version
     8  u32    file size in bytes (must equal the buffer size)
     12 u32    section count S (1..64)
     16 u32    flags (PVS_FILE_APPROXIMATE = 1); unknown bits are ignored
     20 u32    CRC-32 (IEEE) of bytes 0..19 and of the section table
     24 u32[2] reserved, zero
   section table at 32: S entries of 16 bytes: u32 tag, u32 offset, u32 size, u32 CRC-32 of the bytes.
     Sections are 8-byte aligned, lie inside the file and do not overlap; every byte outside the
     header, the table and the sections is zero padding. Tags are four ASCII
     characters. A reader skips tags it does not know; every required tag appears exactly once.
   "META" (required, 32 bytes): u32 cell_count, u32 object_count, u32 method (pvs_method),
     f32 eps, u32 up_axis (1 or 2), u32 record_coding (1 = gap varints), u32[2] reserved zero.
   "CELL" (required): cell_count boxes of 6 f32 (min xyz, max xyz), finite, min <= max.
   "RECS" (required): u32 offsets[cell_count + 1], ascending, then the records. A record (coding 1)
     is varint n followed by n varints: the first object id, then gaps minus one between ascending ids.
     Varints are LEB128, at most 5 bytes, the value must fit 32 bits. Every id < object_count.

   RECENT HISTORY
   ==============
   0.1.0 (2026-11-22) scene, kD-tree, ray-sampling estimator, bake tasks, .pvs container v1.
*/
// >>api
#ifndef PVS_H
#define PVS_H

#include <stddef.h>
#include <stdint.h>

#define PVS_VERSION_MAJOR 0
#define PVS_VERSION_MINOR 1
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
    PVS_RESULT_MIN = -22               /* sentinel: every result is > PVS_RESULT_MIN */
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

/* ---- methods --------------------------------------------------------------------------------- */

/* Region methods. 0 is the default (today: SAMPLE, until a conservative method lands). */
typedef enum pvs_method {
    PVS_METHOD_DEFAULT = 0,
    PVS_METHOD_SAMPLE,       /* ray sampling: an estimate from below, NOT conservative */
    PVS_METHOD_OTREE,        /* 2.5D occlusion trees, c-LSS (Bittner 2002, ch. 7): conservative; occluders are the
                                scene's vertical rectangles standing on the ground (see pvs_visibility_25d) */
    PVS_METHOD_COUNT
} pvs_method;

/* Name of a method ("sample"), or "unknown". */
PVS_API const char *pvs_method_name(pvs_method method);

/* The ray-sampling estimator: `points` stratified points in `cell` (its 8 corners and 6 face centres
   first, then a jittered grid), `rays_per_point` uniformly distributed directions from each, and the
   first object each ray hits is set in `visible` (PVS_BITSET_WORDS(object_count) words, not cleared
   first; occluder-only objects are never set). A lower bound of the exact visible set: the yardstick
   of the tests and pvscheck, never a conservative PVS. Deterministic in `seed`. Thread-safe, no
   allocation. Returns the number of rays cast. */
PVS_API uint64_t pvs_sample_visibility(const pvs_scene *scene, const pvs_box *cell, uint32_t points,
                                       uint32_t rays_per_point, uint64_t seed, pvs_word *visible);

/* ---- bake ------------------------------------------------------------------------------------ */

/* What to bake. Left at zero, optional fields get defaults. */
typedef struct pvs_bake_desc {
    const pvs_scene *scene;   /* must outlive the bake */
    const pvs_box *cells;     /* cell_count view cells, copied */
    uint32_t cell_count;
    pvs_method method;        /* PVS_METHOD_DEFAULT picks */
    float eps;                /* sampling / shrinking distance; 0 = derived from the cells */
    uint32_t sample_points;   /* SAMPLE: points per cell, 0 = 64 */
    uint32_t sample_rays;     /* SAMPLE: rays per point, 0 = 4096 */
    uint64_t seed;            /* SAMPLE: random seed */
    pvs_allocator allocator;
} pvs_bake_desc;

typedef struct pvs_bake pvs_bake;

/* Validates the desc and prepares the tasks. Errors: INVALID_ARGUMENT, BAD_CELL (err->index = cell),
   NOT_FINITE, OUT_OF_MEMORY. */
PVS_API pvs_result pvs_bake_begin(const pvs_bake_desc *desc, pvs_bake **out_bake, pvs_error *err);
/* Number of tasks (today one per cell). */
PVS_API uint32_t pvs_bake_task_count(const pvs_bake *bake);
/* The cell a task bakes. */
PVS_API uint32_t pvs_bake_task_cell(const pvs_bake *bake, uint32_t task);
/* Runs one task. Thread-safe for distinct task indices; each task uses its own scratch. */
PVS_API pvs_result pvs_bake_run_task(pvs_bake *bake, uint32_t task, pvs_error *err);
/* The resolved parameters (method, eps). */
PVS_API pvs_method pvs_bake_method(const pvs_bake *bake);
PVS_API float pvs_bake_eps(const pvs_bake *bake);
/* The PVS of a cell whose task has run, or NULL. PVS_BITSET_WORDS(object_count) words. */
PVS_API const pvs_word *pvs_bake_cell_pvs(const pvs_bake *bake, uint32_t cell);
/* A byte count the file will not exceed (0 if not every task has run). */
PVS_API size_t pvs_bake_file_bound(const pvs_bake *bake);
/* Writes the .pvs file into out[0..capacity). Errors: NOT_DONE, BUFFER_TOO_SMALL, COUNT_OVERFLOW. */
PVS_API pvs_result pvs_bake_write_file(const pvs_bake *bake, void *out, size_t capacity, size_t *out_size, pvs_error *err);
PVS_API void pvs_bake_destroy(pvs_bake *bake);

/* ---- format ---------------------------------------------------------------------------------- */

/* File flags. */
#define PVS_FILE_APPROXIMATE 1u /* baked by an estimator (SAMPLE): not conservative */

/* A PVS table to encode: cell_count bitsets of PVS_BITSET_WORDS(object_count) words each. */
typedef struct pvs_file_desc {
    const pvs_box *cells;
    uint32_t cell_count;
    uint32_t object_count;
    const pvs_word *pvs;     /* cell-major */
    pvs_method method;
    float eps;
    uint32_t up_axis;        /* 1 or 2 */
    uint32_t flags;          /* PVS_FILE_* */
} pvs_file_desc;

/* Upper bound of the encoded size, 0 on overflow. */
PVS_API size_t pvs_file_bound(const pvs_file_desc *desc);
/* Encodes the table. Deterministic. Errors: INVALID_ARGUMENT, BAD_CELL, BUFFER_TOO_SMALL, COUNT_OVERFLOW. */
PVS_API pvs_result pvs_file_encode(const pvs_file_desc *desc, void *out, size_t capacity, size_t *out_size, pvs_error *err);

/* An opened file: a view of the caller's bytes, which must stay alive and unchanged. Plain data,
   no allocation; copy freely. Fields are read-only to the caller. */
typedef struct pvs_file {
    const uint8_t *data;
    size_t size;
    uint32_t version, flags;
    uint32_t cell_count, object_count;
    pvs_method method;
    float eps;
    uint32_t up_axis;
    const uint8_t *cells;    /* CELL section */
    const uint8_t *records;  /* RECS section */
    uint32_t records_size;
} pvs_file;

/* Validates everything (time linear in size) and fills *file. Safe on untrusted input. */
PVS_API pvs_result pvs_file_open(const void *data, size_t size, pvs_file *file, pvs_error *err);

/* ---- runtime --------------------------------------------------------------------------------- */

#define PVS_NO_CELL 0xffffffffu
/* The cell containing point p (boundaries included); of overlapping cells the lowest id; PVS_NO_CELL
   when none. No allocation. */
PVS_API uint32_t pvs_file_find_cell(const pvs_file *file, const float p[3]);
/* The box of a cell (< cell_count). */
PVS_API pvs_box pvs_file_cell_box(const pvs_file *file, uint32_t cell);
/* Decodes a cell's PVS into bits[0..word_count), clearing it first. word_count must be at least
   PVS_BITSET_WORDS(object_count). Errors: INVALID_ARGUMENT, BUFFER_TOO_SMALL. No allocation. */
PVS_API pvs_result pvs_file_decode(const pvs_file *file, uint32_t cell, pvs_word *bits, size_t word_count, pvs_error *err);

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
        a->free(p, size, a->user);
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
#if defined(__GNUC__) || defined(__clang__)
    return (uint32_t)__builtin_popcountll(x);
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
    s->occluders = (pvs_occluder_desc *)pvs__alloc_array(&a, desc->occluder_count, sizeof(pvs_occluder_desc));
    s->occluder_boxes = (pvs_box *)pvs__alloc_array(&a, desc->occluder_count, sizeof(pvs_box));
    s->occluder_data = (float *)pvs__alloc_array(&a, floats, sizeof(float));
    tri_boxes = (pvs_box *)pvs__alloc_array(&a, desc->triangle_count, sizeof(pvs_box));
    if (!s->positions || !s->indices || !s->triangle_object || !s->object_boxes || !s->object_flags || !s->occluders ||
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
/* (planned: conservative rasterizer, depth pyramid, cull map) */

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
   c-LSS, ch. 7) and the OTREE bake method. Not yet here: the from-point shadow-volume tree (ch. 4). */

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
    int32_t sign;
    uint32_t kind;      /* 0 interior, PVS__OT_OUT, PVS__OT_IN */
    uint32_t child[2];  /* [0] negative side, [1] positive side */
    uint32_t first, count; /* in-leaf payload: occluders seq[first .. first + count) */
    double mvd;         /* 2D: maximum visibility distance of the subtree (§6.5.5); DBL_MAX above out-leaves */
} pvs__otnode;

typedef struct pvs__otree {
    const pvs_allocator *a;
    pvs__otnode *nodes;
    size_t node_count, node_cap;
    uint32_t *seq;
    size_t seq_count, seq_cap;
    pvs__otpoly *stack;             /* work stack of polygons */
    uint32_t *stack_node;
    size_t stack_count, stack_cap;
    int oom;
    const double *seg;              /* occluder segments, 4 doubles each (local coordinates) */
    const double *top;              /* 2.5D: occluder top heights; NULL in 2D */
    const double *reach;            /* 2D: per occluder, the largest distance between it and a cell point */
    double sa[2], sb[2];            /* the source edge (cell edge or top edge) */
    double eye;                     /* 2.5D: height of the source edge */
    const double *corners;          /* 2.5D: the cell's 4 ground corners (every possible eye position) */
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
    t->nodes = NULL; t->seq = NULL; t->stack = NULL; t->stack_node = NULL;
    t->node_cap = t->seq_cap = t->stack_cap = 0;
}

/* Resets to the whole line set: a single out-leaf (§3.3.2). */
PVS__STATIC int pvs__ot_reset(pvs__otree *t) {
    t->node_count = t->seq_count = t->stack_count = 0;
    if (!pvs__ot_grow(t->a, (void **)&t->nodes, &t->node_cap, 1, sizeof(pvs__otnode))) { t->oom = 1; return 0; }
    memset(t->nodes, 0, sizeof(pvs__otnode));
    t->nodes[0].kind = PVS__OT_OUT;
    t->nodes[0].mvd = DBL_MAX;
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

PVS__STATIC int pvs__ot_push(pvs__otree *t, uint32_t node, const pvs__otpoly *poly) {
    size_t c1 = t->stack_cap, c2 = t->stack_cap;
    if (t->stack_count + 1 > t->stack_cap) {
        if (!pvs__ot_grow(t->a, (void **)&t->stack, &c1, t->stack_count + 1, sizeof(pvs__otpoly)) ||
            !pvs__ot_grow(t->a, (void **)&t->stack_node, &c2, t->stack_count + 1, sizeof(uint32_t))) {
            /* keep the arrays consistent with the smaller capacity */
            t->oom = 1;
            return 0;
        }
        t->stack_cap = c1 < c2 ? c1 : c2;
    }
    t->stack[t->stack_count] = *poly;
    t->stack_node[t->stack_count++] = node;
    return 1;
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
    if (len > 0.0) { v[0] /= len; v[1] /= len; v[2] /= len; }
}

#define PVS__OT_EPS 1e-12

/* Keeps the part of `in` where sign * side(p) >= -slack (slack 0: the exact half). New edges lie in
   the plane of p and get mark `mark`. Returns the vertex count of the result (0 = empty). */
PVS__STATIC int pvs__ot_clip(const pvs__otpoly *in, const double p[2], double sign, double slack, int mark, pvs__otpoly *out) {
    double d[PVS__OT_MAXV];
    int i, n = in->n, m = 0, any_in = 0;
    for (i = 0; i < n; ++i) {
        d[i] = sign * pvs__ot_side(in->v[i], p) + slack;
        if (d[i] > PVS__OT_EPS) any_in = 1;
    }
    out->xsplit = in->xsplit;
    if (!any_in) { out->n = 0; return 0; }
    for (i = 0; i < n; ++i) {
        int j = (i + 1) % n;
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
    for (i = 0; i < n; ++i) {
        const double *v0 = q->v[i], *v1 = q->v[(i + 1) % n];
        const double *cand[4];
        int best = -1;
        double best_err = DBL_MAX;
        cand[0] = a; cand[1] = b; cand[2] = c; cand[3] = d;
        for (k = 0; k < 4; ++k) {
            double e0 = fabs(pvs__ot_side(v0, cand[k])), e1 = fabs(pvs__ot_side(v1, cand[k]));
            double err = e0 > e1 ? e0 : e1;
            if (err < best_err) { best_err = err; best = k; }
        }
        if (best < 0 || best_err > 1e-9) return 0;
        q->e[i][0] = cand[best][0]; q->e[i][1] = cand[best][1];
    }
    /* convexity: every vertex on the inner side of every edge plane */
    {
        double cen[3] = {0, 0, 0};
        for (i = 0; i < n; ++i) for (k = 0; k < 3; ++k) cen[k] += q->v[i][k];
        for (i = 0; i < n; ++i) {
            double s = pvs__ot_side(cen, q->e[i]);
            if (fabs(s) <= 1e-12) return 0;
            for (k = 0; k < n; ++k)
                if ((s > 0 ? 1.0 : -1.0) * pvs__ot_side(q->v[k], q->e[i]) < -1e-9) return 0;
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
        t->nodes[node].kind = 0;
        t->nodes[node].p[0] = q->e[i][0];
        t->nodes[node].p[1] = q->e[i][1];
        t->nodes[node].sign = s > 0 ? 1 : -1;
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
    t->nodes[node].kind = 0;
    t->nodes[node].p[0] = p[0];
    t->nodes[node].p[1] = p[1];
    t->nodes[node].sign = sign > 0 ? 1 : -1;
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
        uint32_t node = t->stack_node[--t->stack_count];
        pvs__otnode *nd;
        q = t->stack[t->stack_count];
        nd = t->nodes + node;
        /* the maximum visibility distance shortcut (§6.5.5): every line of this subtree meets a
           stored occluder closer to any cell point than k is to the cell: k is hidden here */
        if (near > nd->mvd) continue;
        if (nd->kind == 0) {
            double lo, hi, p[2];
            int i;
            p[0] = nd->p[0]; p[1] = nd->p[1];
            pvs__ot_range(&q, p, &lo, &hi);
            lo *= nd->sign; hi *= nd->sign;
            if (nd->sign < 0) { double tmp = lo; lo = hi; hi = tmp; }
            for (i = 0; i < q.n; ++i)
                if (q.e[i][0] == p[0] && q.e[i][1] == p[1]) q.mark[i] = 1;
            if (lo >= -1e-12) { pvs__ot_push(t, nd->child[1], &q); continue; }
            if (hi <= 1e-12) { pvs__ot_push(t, nd->child[0], &q); continue; }
            if (pvs__ot_clip(&q, p, (double)nd->sign, 0.0, 1, &part) >= 3) pvs__ot_push(t, t->nodes[node].child[1], &part);
            if (pvs__ot_clip(&q, p, -(double)t->nodes[node].sign, 0.0, 1, &part) >= 3) pvs__ot_push(t, t->nodes[node].child[0], &part);
        } else if (nd->kind == PVS__OT_OUT) {
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
        uint32_t node = t->stack_node[--t->stack_count];
        const pvs__otnode *nd = t->nodes + node;
        q = t->stack[t->stack_count];
        if (near > nd->mvd) continue; /* §6.5.5 */
        if (nd->kind == 0) {
            double lo, hi, p[2];
            p[0] = nd->p[0]; p[1] = nd->p[1];
            pvs__ot_range(&q, p, &lo, &hi);
            lo *= nd->sign; hi *= nd->sign;
            if (nd->sign < 0) { double tmp = lo; lo = hi; hi = tmp; }
            /* a polygon whose vertices sit on the plane within 1e-12 (an edge on the plane) goes to one
               side; otherwise both sides get their part widened by the same 1e-12 */
            if (lo >= -1e-12) vis |= !pvs__ot_push(t, nd->child[1], &q);
            else if (hi <= 1e-12) vis |= !pvs__ot_push(t, nd->child[0], &q);
            else {
                int c0 = pvs__ot_clip(&q, p, (double)nd->sign, 1e-12, 0, &part);
                if (c0 != 0) vis |= !pvs__ot_push(t, t->nodes[node].child[1], c0 > 0 ? &part : &q);
                c0 = pvs__ot_clip(&q, p, -(double)t->nodes[node].sign, 1e-12, 0, &part);
                if (c0 != 0) vis |= !pvs__ot_push(t, t->nodes[node].child[0], c0 > 0 ? &part : &q);
            }
        } else if (pvs__ot_thickness(&q) < PVS__OT_SLIVER) {
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

#define PVS__OT25_MAX_UMBRAE 96

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
PVS__STATIC int pvs__ot25_umbra(const pvs__otree *t, uint32_t j, const double *e, double h, double *u0, double *u1) {
    const double *s = t->seg + 4 * (size_t)j;
    double dx = s[2] - s[0], dy = s[3] - s[1], len = sqrt(dx * dx + dy * dy), hj = t->top[j] - t->eye, hn = h - t->eye;
    double de[2], q0, q1, lo = -DBL_MAX, hi = DBL_MAX, sa;
    int i;
    if (!(len > 0.0)) return 0;
    /* the side the lines come from: the source edge's midpoint side */
    sa = dx * (0.5 * (t->sa[1] + t->sb[1]) - s[1]) - dy * (0.5 * (t->sa[0] + t->sb[0]) - s[0]);
    if (sa == 0.0) return 0;
    sa = sa > 0.0 ? 1.0 : -1.0;
    de[0] = DBL_MAX; de[1] = -DBL_MAX;
    for (i = 0; i < 4; ++i) {
        double d = sa * (dx * (t->corners[2 * i + 1] - s[1]) - dy * (t->corners[2 * i] - s[0])) / len;
        if (d < 0.0) d = 0.0;
        if (d < de[0]) de[0] = d;
        if (d > de[1]) de[1] = d;
    }
    q0 = sa * (dx * (e[1] - s[1]) - dy * (e[0] - s[0])) / len;
    q1 = sa * (dx * (e[3] - s[1]) - dy * (e[2] - s[0])) / len;
    /* constraints alpha + beta u > margin */
    for (i = 0; i < 3; ++i) {
        double alpha, beta, margin, lim;
        if (i < 2) {
            double d = de[i];
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
    for (i = 0; i < q->n; ++i) {
        double u;
        if (pvs__ot_param(q->v[i], e, &u)) { if (u < flo) flo = u; if (u > fhi) fhi = u; }
        else { flo = -DBL_MAX; fhi = DBL_MAX; }
    }
    if (flo < 0.0) flo = 0.0;
    if (fhi > 1.0) fhi = 1.0;
    *f0 = flo; *f1 = fhi;
    *v0 = flo; *v1 = fhi;
    for (m = 0; m < count && nu < PVS__OT25_MAX_UMBRAE; ++m) {
        uint32_t j = t->seq[first + m];
        const double *sj = t->seg + 4 * (size_t)j;
        int front, behind;
        if (j == self) continue;
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
        {   /* quick order: e wholly beyond j's line (seen from the source) puts j in front on every
               line that crosses both; e wholly on the source side puts j behind */
            double dx = sj[2] - sj[0], dy = sj[3] - sj[1];
            double sa = dx * (t->sa[1] - sj[1]) - dy * (t->sa[0] - sj[0]), sb = dx * (t->sb[1] - sj[1]) - dy * (t->sb[0] - sj[0]);
            double ss = sa + sb;
            double s0 = dx * (e[1] - sj[1]) - dy * (e[0] - sj[0]), s1 = dx * (e[3] - sj[1]) - dy * (e[2] - sj[0]);
            double tol = t->len_eps * sqrt(dx * dx + dy * dy);
            if ((sa > tol && sb > tol) || (sa < -tol && sb < -tol)) { /* the whole source edge on one side */
                if (ss < 0.0) { s0 = -s0; s1 = -s1; }
                if (s0 >= -tol && s1 >= -tol) continue;       /* e on the source side: j is behind */
                if (!(s0 < -tol && s1 < -tol)) {               /* e crosses j's line: vertex test */
                    pvs__ot_depth(t, q, e, sj, &front, &behind);
                    if (!front || behind) continue;
                }
            } else {
                pvs__ot_depth(t, q, e, sj, &front, &behind);
                if (!front || behind) continue;
            }
        }
        if (pvs__ot25_umbra(t, j, e, h, &um[nu][0], &um[nu][1])) ++nu;
    }
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
    if (!pvs__ot_push(t, 0, blocker)) return;
    while (t->stack_count > base && !t->oom) {
        pvs__otpoly q, part;
        uint32_t node = t->stack_node[--t->stack_count];
        pvs__otnode *nd;
        q = t->stack[t->stack_count];
        nd = t->nodes + node;
        if (nd->kind == 0) {
            double lo, hi, p[2];
            int i;
            p[0] = nd->p[0]; p[1] = nd->p[1];
            pvs__ot_range(&q, p, &lo, &hi);
            lo *= nd->sign; hi *= nd->sign;
            if (nd->sign < 0) { double tmp = lo; lo = hi; hi = tmp; }
            for (i = 0; i < q.n; ++i)
                if (q.e[i][0] == p[0] && q.e[i][1] == p[1]) q.mark[i] = 1;
            if (lo >= -1e-12) { pvs__ot_push(t, nd->child[1], &q); continue; }
            if (hi <= 1e-12) { pvs__ot_push(t, nd->child[0], &q); continue; }
            if (pvs__ot_clip(&q, p, (double)nd->sign, 0.0, 1, &part) >= 3) pvs__ot_push(t, t->nodes[node].child[1], &part);
            if (pvs__ot_clip(&q, p, -(double)t->nodes[node].sign, 0.0, 1, &part) >= 3) pvs__ot_push(t, t->nodes[node].child[0], &part);
        } else if (nd->kind == PVS__OT_OUT) {
            uint32_t leaf = pvs__ot_refine(t, node, &q);
            if (leaf != PVS__OT_NONE) pvs__ot_set_payload(t, leaf, 0, 0, k);
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
        }
    }
    t->stack_count = base;
}

/* Read-only c-LSS test of a far edge e (height h) of an object box `box` (umin, vmin, umax, vmax):
   1 when some part of it may be seen through the lines of the blocker. */
PVS__STATIC int pvs__ot25_visible(pvs__otree *t, const pvs__otpoly *blocker, const double *e, double h, const double *box) {
    size_t base = t->stack_count;
    int vis = 0;
    if (!pvs__ot_push(t, 0, blocker)) return 1;
    while (t->stack_count > base && !vis) {
        pvs__otpoly q, part;
        uint32_t node = t->stack_node[--t->stack_count];
        const pvs__otnode *nd = t->nodes + node;
        q = t->stack[t->stack_count];
        if (nd->kind == 0) {
            double lo, hi, p[2];
            p[0] = nd->p[0]; p[1] = nd->p[1];
            pvs__ot_range(&q, p, &lo, &hi);
            lo *= nd->sign; hi *= nd->sign;
            if (nd->sign < 0) { double tmp = lo; lo = hi; hi = tmp; }
            if (lo >= -1e-12) vis |= !pvs__ot_push(t, nd->child[1], &q);
            else if (hi <= 1e-12) vis |= !pvs__ot_push(t, nd->child[0], &q);
            else {
                int c0 = pvs__ot_clip(&q, p, (double)nd->sign, 1e-12, 0, &part);
                if (c0 != 0) vis |= !pvs__ot_push(t, t->nodes[node].child[1], c0 > 0 ? &part : &q);
                c0 = pvs__ot_clip(&q, p, -(double)t->nodes[node].sign, 1e-12, 0, &part);
                if (c0 != 0) vis |= !pvs__ot_push(t, t->nodes[node].child[0], c0 > 0 ? &part : &q);
            }
        } else if (nd->kind == PVS__OT_OUT) {
            vis = 1;
        } else {
            double f0, f1, v0, v1;
            if (pvs__ot25_open(t, &q, nd->first, nd->count, PVS__OT_NONE, e, h, box, &f0, &f1, &v0, &v1)) vis = 1;
        }
    }
    t->stack_count = base;
    return vis || t->oom;
}

/* 1 when some part of box bx (umin, vmin, umax, vmax in local coordinates, top) beyond the source
   edge a -> b may be seen through the tree: its top edges as far segments (§7.7). */
PVS__STATIC int pvs__ot25_box_visible(pvs__otree *t, const double *bx, double top, const double a[2], const double b[2], int *any_far) {
    double c4[8];
    int edge, vis = 0, skip = -1;
    c4[0] = bx[0]; c4[1] = bx[1]; c4[2] = bx[2]; c4[3] = bx[1]; c4[4] = bx[2]; c4[5] = bx[3]; c4[6] = bx[0]; c4[7] = bx[3];
    if (any_far) *any_far = 0;
    /* A box taller than the eyes is seen (if at all) along a rising ray, at least as well at the
       point where the ray's 2D line enters the box; no line of this tree enters through the box
       edge that faces the same way as the source edge (edges 0..3: -v, +u, +v, -u). */
    if (top > t->eye) {
        double nx = 0.5 * (a[0] + b[0]), ny = 0.5 * (a[1] + b[1]); /* the source edge's outward direction */
        if (fabs(nx) > fabs(ny)) skip = nx > 0 ? 1 : 3;
        else skip = ny > 0 ? 2 : 0;
    }
    for (edge = 0; edge < 4 && !vis; ++edge) {
        if (edge == skip) continue;
        double sg[4], o[4];
        pvs__otpoly bl[2];
        int on, nb, deg, m;
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
} pvs__ot25_sweep;

/* The sweep visitor (§7.7): nodes front to back; a node whose box meets the cell is visible; else
   its box is tested as a virtual occluder (its footprint's edges at its top height) and culled when
   hidden; leaves insert their facades and mark their objects for the test after the sweep. */
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
    if (!items && !(bx[0] <= w->cell[2] && bx[2] >= w->cell[0] && bx[1] <= w->cell[5] && bx[3] >= w->cell[1])) {
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

PVS_API void pvs_visibility_25d_boxes(const float *facades, uint32_t facade_count, const float *objects, uint32_t object_count,
                                      pvs_box *boxes);
PVS_API pvs_result pvs_visibility_25d(const pvs_visibility_25d_desc *desc, pvs_word *visible_objects, pvs_otree_stats *stats,
                                      pvs_error *err) {
    pvs__otree t;
    pvs_allocator al;
    double cell[8], cx, cy, ext = 1.0, margin;
    double *all = NULL, *top = NULL, *seg = NULL, *box = NULL;
    unsigned char *done = NULL, *state = NULL;
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
    box = (double *)pvs__alloc_array(&al, 5 * (size_t)no + 5, sizeof(double));
    done = (unsigned char *)pvs__alloc_array(&al, (size_t)no + 1, 1);
    state = (unsigned char *)pvs__alloc_array(&al, (size_t)nf + 1, 1);
    scratch_size = pvs_kdtree_sweep_scratch_size(tree);
    scratch = pvs__alloc(&al, scratch_size, 16);
    if (!all || !seg || !top || !box || !done || !state || !scratch) { r = pvs__fail(err, PVS_ERROR_OUT_OF_MEMORY, -1, 0, "2.5D visibility arrays"); goto done; }
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
        w.a = a;
        w.b = b;
        w.side = side;
        src.min[0] = (float)(cx + cell[0]); src.min[1] = (float)(cy + cell[1]); src.min[2] = desc->cell_top;
        src.max[0] = (float)(cx + cell[4]); src.max[1] = (float)(cy + cell[5]); src.max[2] = desc->cell_top;
        r = pvs_kdtree_sweep(tree, &src, scratch, scratch_size, pvs__ot25_visit, &w);
        if (r != PVS_OK) { pvs__fail(err, r, -1, 0, "2.5D sweep"); goto done; }
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
    pvs__free_array(&al, all, 4 * (size_t)nf + 4, sizeof(double));
    pvs__free_array(&al, seg, 4 * (size_t)nf + 4, sizeof(double));
    pvs__free_array(&al, top, (size_t)nf + 1, sizeof(double));
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

// >>occluders
/* (planned: occluder synthesis) */

// >>methods
/* ---------------------------------------------------------------------------------------------- */
/* methods: region visibility. Today: the ray-sampling estimator.                                 */
/* ---------------------------------------------------------------------------------------------- */

PVS_API const char *pvs_method_name(pvs_method m) {
    switch (m) {
    case PVS_METHOD_DEFAULT: return "default";
    case PVS_METHOD_SAMPLE: return "sample";
    case PVS_METHOD_OTREE: return "otree";
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

// >>bake
/* ---------------------------------------------------------------------------------------------- */
/* bake: validated cells, one task per cell, results in cell order whatever the run order         */
/* ---------------------------------------------------------------------------------------------- */

struct pvs_bake {
    pvs_allocator allocator;
    const pvs_scene *scene;
    pvs_box *cells;
    uint32_t cell_count, object_count;
    size_t words;              /* per cell */
    pvs_word *pvs;             /* cell_count * words */
    unsigned char *done;       /* cell_count flags, each written by its own task only */
    pvs_method method;
    float eps;
    uint32_t sample_points, sample_rays;
    uint64_t seed;
    float *ot_facades;         /* OTREE: facade_count x (u0 v0 u1 v1 top), then facade_count bases */
    uint32_t ot_facade_count;
    float *ot_objects;         /* OTREE: object_count x (umin vmin umax vmax top) */
    pvs_kdtree *ot_tree;       /* OTREE: over pvs_visibility_25d_boxes */
};

PVS_API void pvs_bake_destroy(pvs_bake *b) {
    pvs_allocator a;
    if (!b) return;
    a = b->allocator;
    pvs__free_array(&a, b->cells, b->cell_count, sizeof(pvs_box));
    pvs__free_array(&a, b->pvs, (size_t)b->cell_count * b->words, sizeof(pvs_word));
    pvs__free_array(&a, b->done, b->cell_count, 1);
    pvs__free_array(&a, b->ot_facades, (size_t)b->ot_facade_count * 6 + 6, sizeof(float));
    pvs__free_array(&a, b->ot_objects, (size_t)b->object_count * 5 + 5, sizeof(float));
    pvs_kdtree_destroy(b->ot_tree);
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
PVS__STATIC pvs_result pvs__otree_cell(pvs_bake *b, uint32_t cell, pvs_word *bits, pvs_error *err) {
    const pvs_scene *s = b->scene;
    const pvs_box *c = b->cells + cell;
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

PVS_API pvs_result pvs_bake_begin(const pvs_bake_desc *desc, pvs_bake **out, pvs_error *err) {
    pvs_bake *b;
    pvs_allocator a;
    size_t total, i;
    pvs_result r;
    if (out) *out = NULL;
    if (!desc || !out || !desc->scene) return pvs__fail(err, PVS_ERROR_INVALID_ARGUMENT, -1, 0, "desc, scene and out_bake must not be NULL");
    if (!desc->cells || desc->cell_count == 0) return pvs__fail(err, PVS_ERROR_INVALID_ARGUMENT, -1, 0, "no cells");
    if (desc->cell_count == 0xffffffffu) return pvs__fail(err, PVS_ERROR_COUNT_OVERFLOW, -1, 0, "too many cells");
    if ((int)desc->method < 0 || desc->method >= PVS_METHOD_COUNT)
        return pvs__fail(err, PVS_ERROR_INVALID_ARGUMENT, -1, 0, "unknown method %d", (int)desc->method);
    if (!pvs__finite(desc->eps) || desc->eps < 0.0f)
        return pvs__fail(err, PVS_ERROR_INVALID_ARGUMENT, -1, 0, "eps must be finite and >= 0");
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
    b->cell_count = desc->cell_count;
    b->object_count = pvs_scene_object_count(desc->scene);
    b->words = PVS_BITSET_WORDS(b->object_count);
    b->method = desc->method == PVS_METHOD_DEFAULT ? PVS_METHOD_SAMPLE : desc->method;
    b->eps = desc->eps;
    b->sample_points = desc->sample_points ? desc->sample_points : 32;
    b->sample_rays = desc->sample_rays ? desc->sample_rays : 2048;
    b->seed = desc->seed;
    if (!pvs__mul(b->words, desc->cell_count, &total) || !pvs__mul(total, sizeof(pvs_word), &i)) {
        pvs_bake_destroy(b);
        return pvs__fail(err, PVS_ERROR_COUNT_OVERFLOW, -1, 0, "%u cells x %u objects do not fit in memory", desc->cell_count,
                         b->object_count);
    }
    b->cells = (pvs_box *)pvs__alloc_array(&a, desc->cell_count, sizeof(pvs_box));
    b->pvs = (pvs_word *)pvs__alloc_array(&a, total, sizeof(pvs_word));
    b->done = (unsigned char *)pvs__alloc_array(&a, desc->cell_count, 1);
    if (!b->cells || !b->pvs || !b->done) {
        pvs_bake_destroy(b);
        return pvs__fail(err, PVS_ERROR_OUT_OF_MEMORY, -1, 0, "bake arrays for %u cells", desc->cell_count);
    }
    memcpy(b->cells, desc->cells, desc->cell_count * sizeof(pvs_box));
    memset(b->pvs, 0, total * sizeof(pvs_word));
    memset(b->done, 0, desc->cell_count);
    if (b->method == PVS_METHOD_OTREE && pvs__otree_prepare(b) != PVS_OK) {
        pvs_bake_destroy(b);
        return pvs__fail(err, PVS_ERROR_OUT_OF_MEMORY, -1, 0, "otree facades");
    }
    *out = b;
    pvs__ok(err);
    return PVS_OK;
}

PVS_API uint32_t pvs_bake_task_count(const pvs_bake *b) { return b->cell_count; }
PVS_API uint32_t pvs_bake_task_cell(const pvs_bake *b, uint32_t task) {
    PVS_ASSERT(task < b->cell_count);
    return task;
}
PVS_API pvs_method pvs_bake_method(const pvs_bake *b) { return b->method; }
PVS_API float pvs_bake_eps(const pvs_bake *b) { return b->eps; }


PVS_API pvs_result pvs_bake_run_task(pvs_bake *b, uint32_t task, pvs_error *err) {
    uint32_t cell;
    pvs_word *bits;
    if (!b || task >= b->cell_count) return pvs__fail(err, PVS_ERROR_INVALID_ARGUMENT, task, 0, "task %u out of range", task);
    cell = pvs_bake_task_cell(b, task);
    bits = b->pvs + (size_t)cell * b->words;
    memset(bits, 0, b->words * sizeof(pvs_word));
    switch (b->method) {
    case PVS_METHOD_SAMPLE: {
        /* per-cell seed: independent of the order and thread the tasks run in */
        uint64_t state = b->seed ^ ((uint64_t)cell * 0x9e3779b97f4a7c15ull);
        pvs_sample_visibility(b->scene, b->cells + cell, b->sample_points, b->sample_rays, pvs__splitmix64(&state), bits);
        break;
    }
    case PVS_METHOD_OTREE: {
        pvs_result r = pvs__otree_cell(b, cell, bits, err);
        if (r != PVS_OK) return r;
        break;
    }
    default: return pvs__fail(err, PVS_ERROR_UNSUPPORTED, cell, 0, "method %d", (int)b->method);
    }
    b->done[cell] = 1;
    pvs__ok(err);
    return PVS_OK;
}

PVS_API const pvs_word *pvs_bake_cell_pvs(const pvs_bake *b, uint32_t cell) {
    if (cell >= b->cell_count || !b->done[cell]) return NULL;
    return b->pvs + (size_t)cell * b->words;
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
}

PVS__STATIC int pvs__bake_all_done(const pvs_bake *b) {
    uint32_t i;
    for (i = 0; i < b->cell_count; ++i)
        if (!b->done[i]) return 0;
    return 1;
}

PVS_API size_t pvs_bake_file_bound(const pvs_bake *b) {
    pvs_file_desc fd;
    if (!pvs__bake_all_done(b)) return 0;
    pvs__bake_file_desc(b, &fd);
    return pvs_file_bound(&fd);
}

PVS_API pvs_result pvs_bake_write_file(const pvs_bake *b, void *out, size_t capacity, size_t *out_size, pvs_error *err) {
    pvs_file_desc fd;
    uint32_t i;
    if (!b) return pvs__fail(err, PVS_ERROR_INVALID_ARGUMENT, -1, 0, "bake is NULL");
    for (i = 0; i < b->cell_count; ++i)
        if (!b->done[i]) return pvs__fail(err, PVS_ERROR_NOT_DONE, i, 0, "cell %u has not been baked", i);
    pvs__bake_file_desc(b, &fd);
    return pvs_file_encode(&fd, out, capacity, out_size, err);
}

// >>format
/* ---------------------------------------------------------------------------------------------- */
/* format: the .pvs file (layout in the manual at the top)                                        */
/* ---------------------------------------------------------------------------------------------- */

#define PVS__HEADER_SIZE 32u
#define PVS__SECTION_ENTRY 16u
#define PVS__MAX_SECTIONS 64u
#define PVS__META_SIZE 32u
#define PVS__CELL_BYTES 24u
#define PVS__TAG(a, b, c, d) ((uint32_t)(a) | ((uint32_t)(b) << 8) | ((uint32_t)(c) << 16) | ((uint32_t)(d) << 24))
#define PVS__TAG_META PVS__TAG('M', 'E', 'T', 'A')
#define PVS__TAG_CELL PVS__TAG('C', 'E', 'L', 'L')
#define PVS__TAG_RECS PVS__TAG('R', 'E', 'C', 'S')
#define PVS__CODING_GAP_VARINT 1u

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

/* The record coding, behind one pair of functions: gap varints (coding 1). A worst-case record is
   5 + 5 * object_count bytes. */
PVS__STATIC size_t pvs__record_bound(uint32_t object_count) { return 5u + 5u * (size_t)object_count; }
PVS__STATIC size_t pvs__encode_record(const pvs_word *bits, uint32_t object_count, uint8_t *out) {
    uint32_t n = pvs_bitset_count(bits, object_count), i, prev = 0;
    size_t len = pvs__put_varint(out, n);
    int first = 1;
    for (i = pvs_bitset_next(bits, object_count, 0); i < object_count; i = pvs_bitset_next(bits, object_count, i + 1)) {
        len += pvs__put_varint(out + len, first ? i : i - prev - 1);
        prev = i;
        first = 0;
    }
    return len;
}
/* Decodes (bits != NULL) or only validates (bits == NULL) one record of exactly `size` bytes.
   Returns PVS_OK or BAD_RECORD / OBJECT_OUT_OF_RANGE with *bad_at = the offending byte. */
PVS__STATIC pvs_result pvs__decode_record(const uint8_t *p, size_t size, uint32_t object_count, pvs_word *bits, size_t *bad_at) {
    const uint8_t *q = p, *end = p + size;
    uint32_t n, k, id = 0;
    size_t used = pvs__get_varint(q, end, &n);
    if (!used) { *bad_at = 0; return PVS_ERROR_BAD_RECORD; }
    q += used;
    if (n > object_count) { *bad_at = 0; return PVS_ERROR_OBJECT_OUT_OF_RANGE; }
    for (k = 0; k < n; ++k) {
        uint32_t g;
        uint64_t next;
        used = pvs__get_varint(q, end, &g);
        if (!used) { *bad_at = (size_t)(q - p); return PVS_ERROR_BAD_RECORD; }
        next = k == 0 ? (uint64_t)g : (uint64_t)id + 1u + g;
        if (next >= object_count) { *bad_at = (size_t)(q - p); return PVS_ERROR_OBJECT_OUT_OF_RANGE; }
        id = (uint32_t)next;
        if (bits) bits[id >> 6] |= (pvs_word)1 << (id & 63);
        q += used;
    }
    if (q != end) { *bad_at = (size_t)(q - p); return PVS_ERROR_BAD_RECORD; }
    return PVS_OK;
}

PVS_API size_t pvs_file_bound(const pvs_file_desc *d) {
    size_t total = PVS__HEADER_SIZE + 3 * PVS__SECTION_ENTRY, t;
    if (!d || !d->cell_count) return 0;
    total = pvs__align8(total) + PVS__META_SIZE;
    if (!pvs__mul(d->cell_count, PVS__CELL_BYTES, &t) || !pvs__add(total, t, &total)) return 0;
    total = pvs__align8(total);
    if (!pvs__mul((size_t)d->cell_count + 1, 4, &t) || !pvs__add(total, t, &total)) return 0;
    if (!pvs__mul(d->cell_count, pvs__record_bound(d->object_count), &t) || !pvs__add(total, t, &total)) return 0;
    return pvs__align8(total);
}

PVS_API pvs_result pvs_file_encode(const pvs_file_desc *d, void *out, size_t capacity, size_t *out_size, pvs_error *err) {
    uint8_t *o = (uint8_t *)out, *rec;
    size_t bound, meta_at, cell_at, recs_at, pos, words;
    uint32_t i;
    if (out_size) *out_size = 0;
    if (!d || !out || !d->cells || !d->pvs || !d->cell_count || !d->object_count)
        return pvs__fail(err, PVS_ERROR_INVALID_ARGUMENT, -1, 0, "desc, out, cells and pvs must not be NULL or empty");
    if (d->up_axis != 1 && d->up_axis != 2) return pvs__fail(err, PVS_ERROR_INVALID_ARGUMENT, -1, 0, "up_axis must be 1 or 2");
    if ((int)d->method < 0 || d->method >= PVS_METHOD_COUNT || !pvs__finite(d->eps))
        return pvs__fail(err, PVS_ERROR_INVALID_ARGUMENT, -1, 0, "bad method or eps");
    for (i = 0; i < d->cell_count; ++i) {
        pvs_result r = pvs__check_cell(d->cells + i, i, err);
        if (r != PVS_OK) return r;
    }
    bound = pvs_file_bound(d);
    if (!bound || bound > 0xffffffffu) return pvs__fail(err, PVS_ERROR_COUNT_OVERFLOW, -1, 0, "the file would exceed 4 GiB");
    words = PVS_BITSET_WORDS(d->object_count);
    meta_at = pvs__align8(PVS__HEADER_SIZE + 3 * PVS__SECTION_ENTRY);
    cell_at = meta_at + PVS__META_SIZE;
    recs_at = pvs__align8(cell_at + (size_t)d->cell_count * PVS__CELL_BYTES);
    /* records are written straight into the output when it is large enough for the bound, else
       the exact size is measured first */
    {
        size_t need = recs_at + 4 * ((size_t)d->cell_count + 1), recs = 0;
        uint8_t tmp[5];
        for (i = 0; i < d->cell_count; ++i) {
            const pvs_word *bits = d->pvs + (size_t)i * words;
            uint32_t k, prev = 0;
            int first = 1;
            recs += pvs__put_varint(tmp, pvs_bitset_count(bits, d->object_count));
            for (k = pvs_bitset_next(bits, d->object_count, 0); k < d->object_count; k = pvs_bitset_next(bits, d->object_count, k + 1)) {
                recs += pvs__put_varint(tmp, first ? k : k - prev - 1);
                prev = k;
                first = 0;
            }
        }
        need = pvs__align8(need + recs);
        if (capacity < need)
            return pvs__fail(err, PVS_ERROR_BUFFER_TOO_SMALL, -1, 0, "need %llu bytes, have %llu", (unsigned long long)need,
                             (unsigned long long)capacity);
        memset(o, 0, need);
        bound = need;
    }
    /* META */
    pvs__put32(o + meta_at + 0, d->cell_count);
    pvs__put32(o + meta_at + 4, d->object_count);
    pvs__put32(o + meta_at + 8, (uint32_t)d->method);
    pvs__putf32(o + meta_at + 12, d->eps);
    pvs__put32(o + meta_at + 16, d->up_axis);
    pvs__put32(o + meta_at + 20, PVS__CODING_GAP_VARINT);
    /* CELL */
    for (i = 0; i < d->cell_count; ++i) {
        uint8_t *c = o + cell_at + (size_t)i * PVS__CELL_BYTES;
        int k;
        for (k = 0; k < 3; ++k) {
            pvs__putf32(c + 4 * k, d->cells[i].min[k]);
            pvs__putf32(c + 12 + 4 * k, d->cells[i].max[k]);
        }
    }
    /* RECS */
    rec = o + recs_at;
    pos = 4 * ((size_t)d->cell_count + 1);
    for (i = 0; i < d->cell_count; ++i) {
        pvs__put32(rec + 4 * (size_t)i, (uint32_t)pos);
        pos += pvs__encode_record(d->pvs + (size_t)i * words, d->object_count, rec + pos);
    }
    pvs__put32(rec + 4 * (size_t)d->cell_count, (uint32_t)pos);
    /* header and section table */
    memcpy(o, "PVS\x1a", 4);
    pvs__put32(o + 4, PVS_FORMAT_VERSION);
    pvs__put32(o + 8, (uint32_t)bound);
    pvs__put32(o + 12, 3);
    pvs__put32(o + 16, d->flags);
    {
        const uint32_t tags[3] = {PVS__TAG_META, PVS__TAG_CELL, PVS__TAG_RECS};
        const size_t at[3] = {meta_at, cell_at, recs_at};
        const size_t sz[3] = {PVS__META_SIZE, (size_t)d->cell_count * PVS__CELL_BYTES, pos};
        uint32_t crc;
        for (i = 0; i < 3; ++i) {
            uint8_t *e = o + PVS__HEADER_SIZE + PVS__SECTION_ENTRY * i;
            pvs__put32(e + 0, tags[i]);
            pvs__put32(e + 4, (uint32_t)at[i]);
            pvs__put32(e + 8, (uint32_t)sz[i]);
            pvs__put32(e + 12, pvs__crc32(0, o + at[i], sz[i]));
        }
        crc = pvs__crc32(0, o, 20);
        crc = pvs__crc32(crc, o + PVS__HEADER_SIZE, 3 * PVS__SECTION_ENTRY);
        pvs__put32(o + 20, crc);
    }
    if (out_size) *out_size = bound;
    pvs__ok(err);
    return PVS_OK;
}

PVS_API pvs_result pvs_file_open(const void *data, size_t size, pvs_file *f, pvs_error *err) {
    const uint8_t *p = (const uint8_t *)data;
    uint32_t count, i, j, crc;
    const uint8_t *meta = NULL, *cells = NULL, *recs = NULL;
    uint32_t meta_size = 0, cells_size = 0, recs_size = 0, coding;
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
        else if (tag == PVS__TAG_RECS) { recs = p + off; recs_size = sz; }
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
            if (e) pos = (size_t)pvs__get32(e + 4) + pvs__get32(e + 8);
        }
    }
    if (!meta || !cells || !recs)
        return pvs__fail(err, PVS_ERROR_BAD_SECTION, -1, 0, "missing required section %s", !meta ? "META" : !cells ? "CELL" : "RECS");
    if (meta_size != PVS__META_SIZE) return pvs__fail(err, PVS_ERROR_BAD_SECTION, -1, (uint64_t)(meta - p), "META has %u bytes, not 32", meta_size);
    f->cell_count = pvs__get32(meta);
    f->object_count = pvs__get32(meta + 4);
    f->method = (pvs_method)pvs__get32(meta + 8);
    f->eps = pvs__getf32(meta + 12);
    f->up_axis = pvs__get32(meta + 16);
    coding = pvs__get32(meta + 20);
    {
        uint64_t mo = (uint64_t)(meta - p);
        if (f->cell_count == 0 || f->cell_count == 0xffffffffu) return pvs__fail(err, PVS_ERROR_BAD_HEADER, -1, mo, "cell count %u", f->cell_count);
        if (f->object_count == 0) return pvs__fail(err, PVS_ERROR_BAD_HEADER, -1, mo + 4, "object count 0");
        if (pvs__get32(meta + 8) >= (uint32_t)PVS_METHOD_COUNT) return pvs__fail(err, PVS_ERROR_BAD_HEADER, -1, mo + 8, "unknown method %u", pvs__get32(meta + 8));
        if (!pvs__finite(f->eps) || f->eps < 0.0f) return pvs__fail(err, PVS_ERROR_BAD_HEADER, -1, mo + 12, "eps is not a finite number >= 0");
        if (f->up_axis != 1 && f->up_axis != 2) return pvs__fail(err, PVS_ERROR_BAD_HEADER, -1, mo + 16, "up axis %u", f->up_axis);
        if (coding != PVS__CODING_GAP_VARINT) return pvs__fail(err, PVS_ERROR_BAD_HEADER, -1, mo + 20, "unknown record coding %u", coding);
        if (pvs__get32(meta + 24) || pvs__get32(meta + 28)) return pvs__fail(err, PVS_ERROR_BAD_HEADER, -1, mo + 24, "reserved META bytes are not zero");
    }
    if ((uint64_t)f->cell_count * PVS__CELL_BYTES != cells_size)
        return pvs__fail(err, PVS_ERROR_BAD_SECTION, -1, (uint64_t)(cells - p), "CELL has %u bytes, %u cells need %llu", cells_size,
                         f->cell_count, (unsigned long long)f->cell_count * PVS__CELL_BYTES);
    for (i = 0; i < f->cell_count; ++i) {
        const uint8_t *c = cells + (size_t)i * PVS__CELL_BYTES;
        int k;
        for (k = 0; k < 3; ++k) {
            float lo = pvs__getf32(c + 4 * k), hi = pvs__getf32(c + 12 + 4 * k);
            if (!pvs__finite(lo) || !pvs__finite(hi) || lo > hi)
                return pvs__fail(err, PVS_ERROR_BAD_CELL, i, (uint64_t)(c - p), "cell %u box is not finite or has min > max", i);
        }
    }
    if ((uint64_t)4 * ((uint64_t)f->cell_count + 1) > recs_size)
        return pvs__fail(err, PVS_ERROR_BAD_SECTION, -1, (uint64_t)(recs - p), "RECS is too small for %u record offsets", f->cell_count);
    {
        uint32_t prev = 4 * (f->cell_count + 1);
        if (pvs__get32(recs) != prev)
            return pvs__fail(err, PVS_ERROR_BAD_RECORD, 0, (uint64_t)(recs - p), "record 0 does not start after the offset table");
        if (pvs__get32(recs + 4 * (size_t)f->cell_count) != recs_size)
            return pvs__fail(err, PVS_ERROR_BAD_RECORD, -1, (uint64_t)(recs - p) + 4 * (uint64_t)f->cell_count,
                             "the last record offset is not the section size");
        for (i = 0; i < f->cell_count; ++i) {
            uint32_t a = pvs__get32(recs + 4 * (size_t)i), b = pvs__get32(recs + 4 * (size_t)i + 4);
            size_t bad = 0;
            pvs_result r;
            if (b < a || b > recs_size)
                return pvs__fail(err, PVS_ERROR_BAD_RECORD, i, (uint64_t)(recs - p) + 4 * (uint64_t)i, "record %u offsets are not ascending", i);
            r = pvs__decode_record(recs + a, b - a, f->object_count, NULL, &bad);
            if (r != PVS_OK)
                return pvs__fail(err, r, i, (uint64_t)(recs - p) + a + bad, "record %u (cell %u)", i, i);
        }
    }
    f->data = p;
    f->size = size;
    f->version = PVS_FORMAT_VERSION;
    f->flags = pvs__get32(p + 16);
    f->cells = cells;
    f->records = recs;
    f->records_size = recs_size;
    pvs__ok(err);
    return PVS_OK;
}

// >>runtime
/* ---------------------------------------------------------------------------------------------- */
/* runtime: cell look-up and decoding; no allocation                                              */
/* ---------------------------------------------------------------------------------------------- */

PVS_API pvs_box pvs_file_cell_box(const pvs_file *f, uint32_t cell) {
    pvs_box b;
    const uint8_t *c;
    int k;
    PVS_ASSERT(cell < f->cell_count);
    c = f->cells + (size_t)cell * PVS__CELL_BYTES;
    for (k = 0; k < 3; ++k) {
        b.min[k] = pvs__getf32(c + 4 * k);
        b.max[k] = pvs__getf32(c + 12 + 4 * k);
    }
    return b;
}

PVS_API uint32_t pvs_file_find_cell(const pvs_file *f, const float p[3]) {
    uint32_t i;
    for (i = 0; i < f->cell_count; ++i) {
        pvs_box b = pvs_file_cell_box(f, i);
        if (pvs__box_contains_point(&b, p)) return i;
    }
    return PVS_NO_CELL;
}

PVS_API pvs_result pvs_file_decode(const pvs_file *f, uint32_t cell, pvs_word *bits, size_t word_count, pvs_error *err) {
    uint32_t a, b;
    size_t bad;
    if (!f || !bits || !f->data) return pvs__fail(err, PVS_ERROR_INVALID_ARGUMENT, -1, 0, "file and bits must not be NULL");
    if (cell >= f->cell_count) return pvs__fail(err, PVS_ERROR_INVALID_ARGUMENT, cell, 0, "cell %u of %u", cell, f->cell_count);
    if (word_count < PVS_BITSET_WORDS(f->object_count))
        return pvs__fail(err, PVS_ERROR_BUFFER_TOO_SMALL, -1, 0, "%llu words, %u objects need %llu", (unsigned long long)word_count,
                         f->object_count, (unsigned long long)PVS_BITSET_WORDS(f->object_count));
    memset(bits, 0, word_count * sizeof(pvs_word));
    a = pvs__get32(f->records + 4 * (size_t)cell);
    b = pvs__get32(f->records + 4 * (size_t)cell + 4);
    (void)pvs__decode_record(f->records + a, b - a, f->object_count, bits, &bad); /* validated by open */
    pvs__ok(err);
    return PVS_OK;
}

#endif /* PVS_IMPLEMENTATION_ONCE */
#endif /* PVS_IMPLEMENTATION */

/*
   FULL HISTORY
   ============
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
