/* cli.h - what pvsbake, pvsinfo, pvscheck and the examples share on top of pvs.h: loading a scene
   (OBJ or generator) into a pvs_scene, cells from a file or a grid, baking on a thread pool with a
   progress bar, and per-cell ray-sampling checks. Not part of the library. */
#ifndef TOOL_CLI_H
#define TOOL_CLI_H
#include "../pvs.h"
#include <pthread.h>
#include "gen.h"
#include "mesh.h"
#include "obj.h"
#include "toolutil.h"

/* ---- a bake-wide memory limit ---- */

/* A pvs_allocator that counts the bytes it holds and refuses (returns NULL) past `limit`; thread-safe.
   Give it to the scene and the bake, and every method's allocations stay within the limit: a
   refusal is the library's OUT_OF_MEMORY, never more memory. */
typedef struct cli_memory {
    pthread_mutex_t mutex;
    size_t limit, used, peak;
    int refused;              /* an allocation was refused */
    const char *source;       /* where the limit came from, for messages ("--memory", ...) */
} cli_memory;
void cli_memory_init(cli_memory *m, size_t limit, const char *source);
void cli_memory_destroy(cli_memory *m);
pvs_allocator cli_memory_allocator(cli_memory *m);
void cli_memory_add(cli_memory *m, size_t bytes); /* counts memory the tools hold outside the library (the mesh) */
size_t cli_memory_used(cli_memory *m);
/* "1.5 GiB", "300 MiB" or "512 bytes" into buf (32 bytes). */
const char *cli_size_text(double bytes, char *buf);
/* A size: bytes, or with a K, M, G or T suffix (powers of 1024), e.g. "512M", "1.5G". 0 or -1. */
int cli_parse_size(const char *s, size_t *out);

/* Builds a pvs_scene from a mesh. up_axis 1 = Y, 2 = Z. Objects without faces are kept (ids follow
   the file) and never visible; `name` is used in messages. Returns 0 or -1 with err set. */
int cli_make_scene(const char *name, const mesh *m, uint32_t up_axis, pvs_scene **scene, tool_error *err);

/* The demo city (generator city, seed 1, size 1, Y up): its mesh, view cells and scene. m and cells
   are initialised here; free them (and the scene) as usual, also after a failure. */
int cli_demo_city(mesh *m, mesh_cells *cells, pvs_scene **scene, tool_error *err);

/* Loads an OBJ file and builds its scene; warns on stderr about objects without faces. */
int cli_load_scene(const char *path, uint32_t up_axis, mesh *m, pvs_scene **scene, tool_error *err);
/* The same with the scene's allocations through `memory` (a limit), which also counts the mesh. */
int cli_load_scene_limited(const char *path, uint32_t up_axis, mesh *m, cli_memory *memory, pvs_scene **scene, tool_error *err);

/* pvscheck's and pvsview's inputs: reads and opens the .pvs file (*data gets its bytes, which the
   file uses in place: free() them after it), then loads the OBJ scene with up_axis, or the file's
   when it is 0. Returns 0, or -1 with err set ("PVS_PATH: reason" for the file; a file without cell
   boxes, PVS_FILE_NO_LOOKUP, is refused). */
int cli_load_pvs_scene(const char *pvs_path, const char *scene_path, uint32_t up_axis, void **data, pvs_file *file, mesh *m, pvs_scene **scene,
                       tool_error *err);

/* A 3D grid of cubes of edge `size` covering the scene bounds (at most max_cells cells). */
int cli_grid_cells(const pvs_scene *scene, float size, uint32_t max_cells, mesh_cells *cells, tool_error *err);

/* Bakes every task on `threads` threads (0 = all CPUs) with a progress bar labelled `label` unless
   quiet. Returns 0 or -1 with err set (the first failing task's message). */
int cli_run_bake(pvs_bake *bake, uint32_t threads, int quiet, const char *label, tool_error *err);

/* The one tightness yardstick of the benches: a lower bound of the cell's exact visible set from 32
   points x 2048 uniform rays (pvs_sample_visibility) and then 32 rays aimed at every object not yet
   seen (pvs_sample_visibility_toward). Sets bits in `visible` (not cleared first). Returns the rays. */
uint64_t cli_reference_visibility(const pvs_scene *scene, const pvs_box *cell, uint64_t seed, pvs_word *visible);

/* The ray-sampling check of a PVS table: per cell, objects the sampler sees that the PVS lacks. */
typedef struct cli_check {
    uint32_t cells;
    uint64_t misses;            /* (cell, object) pairs seen by rays but missing from the PVS */
    uint32_t cells_with_misses;
    uint32_t first_miss_cell, first_miss_object;
    double pvs_sum, seen_sum;   /* sums of PVS sizes and ray-sampled visible set sizes */
    uint64_t rays;
    uint32_t rebuilt;           /* 1: the file has virtual occluders and the PVS checked is the one pvs_vocc_cull
                                   rebuilds from them (what a runtime using them draws) */
    uint32_t stored_differs;    /* rebuilt: cells whose stored records hold an object the occluders' PVS
                                   (every box tested, no tree) leaves out: must be 0 (the records are that
                                   PVS, less objects beyond a draw distance; placeholders are not compared) */
} cli_check;
/* Checks cells [0, cell_count) of `file` against ray sampling in `scene` (points x rays per cell,
   seeded per cell from `seed`), on `threads` threads. Deterministic for any thread count. A file with
   virtual occluders (VOCC) is checked through the PVS pvs_vocc_cull rebuilds from them. */
int cli_check_file(const pvs_scene *scene, const pvs_file *file, uint32_t points, uint32_t rays, uint32_t aim, uint64_t seed,
                   uint32_t threads, int quiet, cli_check *out, tool_error *err);
/* The same for a bake with a draw distance (pvsbake --max-distance): objects whose box is farther
   than max_distance (> 0) from the cell's box do not count as seen. */
int cli_check_file_ex(const pvs_scene *scene, const pvs_file *file, uint32_t points, uint32_t rays, uint32_t aim, uint64_t seed,
                      uint32_t threads, int quiet, float max_distance, cli_check *out, tool_error *err);

/* Encodes a finished bake and writes it to `path` (temp file + rename). *size gets the file size. */
int cli_write_bake(const pvs_bake *bake, const char *path, size_t *size, tool_error *err);

/* `pvsbake merge`: reads the part files of one sharded bake (any order), checks that they make up
   the whole (same shard count, every shard once, same table shape and parameters) and encodes the
   whole table into *out (malloc'd, *out_size bytes): the bytes an unsharded bake writes. One whole
   file re-encodes itself. no_lookup: the result without cell boxes and look-up (PVS_FILE_NO_LOOKUP). */
int cli_merge_parts(const char *const *paths, int count, int no_lookup, void **out, size_t *out_size, tool_error *err);

/* Seconds on a monotonic clock. */
double cli_seconds(void);

/* Parses "y"/"z" into 1/2. */
int cli_parse_up(const char *s, uint32_t *up);
/* Strict unsigned decimal in [lo, hi]. */
int cli_parse_u32(const char *s, uint32_t lo, uint32_t hi, uint32_t *out);
/* The arguments with every "-jN" (N starting with a digit) split into "-j" and "N", as make spells
   it, except where it is the value of one of `value_options` (a NULL-terminated list of the options
   that take a value: a file may be named -j2.txt): a new NULL-terminated array (the strings are
   argv's; free() it when it is not argv), or argv itself when there is none or no memory. *argc is
   updated. */
char **cli_split_jobs(int *argc, char **argv, const char *const *value_options);
/* 1 if `option` is in the NULL-terminated list. */
int cli_is_option(const char *option, const char *const *list);

/* ---- resumable bakes with statistics (pvsbake, the examples) ---- */

/* Options and results of cli_run_bake_ex. Zero-initialise, then set what you need. */
typedef struct cli_bake_run {
    const char *state_path;   /* NULL: no state file. Else, when it exists and belongs to this bake (same
                                 fingerprint, task and object counts), its cells are restored and only
                                 the others run. It is a journal (cli.c): each finished cell appends a
                                 record, flushed after every `state_every` records or a second; it is
                                 compacted when read and when the bake fails; the caller removes it
                                 once the output is written */
    uint32_t state_every;     /* 0 = 32 */
    uint64_t fingerprint;     /* identifies the bake's inputs (cli_fingerprint) */
    uint32_t object_count;    /* the scene's (needed with a state file) */
    double *task_seconds;     /* NULL, or task_count entries: each run task's time (restored: -1) */
    cli_memory *memory;       /* NULL, or the bake's allocator: the threads are planned from what its limit
                                 leaves, a task at a time being measured first; tasks refused memory
                                 while others ran are run again one at a time */
    size_t task_bytes;        /* a known least size of one task (0: none; the first task measures it), */
    const char *task_what;    /*   what needs it ("extproj at 256 pixels"), and what lowers it, for messages */
    const char *task_hint;
    int threads_given;        /* -j was given: more threads than task_bytes fits is an error (-2); what the
                                 first task measures only lowers them, with a note */
    int quiet_plan;           /* no note when the threads are lowered */
    uint32_t threads_used;    /* out: the threads that ran (0 = none needed) */
    uint32_t resumed;         /* out: tasks restored from the state file */
    int state_ignored;        /* out: 1 when a state file was there but belongs to another bake */
    int state_torn;           /* out: 1 when its end was cut short or damaged (those cells run again) */
} cli_bake_run;

/* cli_run_bake with a state file for resuming and per-task times. Returns 0, -1 with err set, or -2
   (err set) when the memory limit does not fit one task or the threads given. */
int cli_run_bake_ex(pvs_bake *bake, uint32_t threads, int quiet, const char *label, cli_bake_run *run, tool_error *err);

/* FNV-1a 64 over bytes, chained: start with h = CLI_FNV_START. */
#define CLI_FNV_START 0xcbf29ce484222325ull
uint64_t cli_fingerprint(uint64_t h, const void *data, size_t size);

#endif
