/* toolutil.h - small helpers shared by the command-line tools (pvsbake, pvsinfo, pvscheck) and the
   examples: error reporting, whole-file reading, atomic file writing, a progress bar, a pthread
   parallel-for, strict option parsing, a PNG writer and a 5x7 bitmap font. Not part of the library.

   Conventions:
   - C99 + POSIX (pthreads). No global mutable state; every function is thread-safe on distinct data.
   - Functions returning int return 0 on success and -1 on failure; on failure a tool_error, when
     given (it may be NULL), holds a ready-to-print message "PATH:LINE: problem" (or "PATH: problem"
     with line 0 for file-level problems).
   - The tools run in the "C" locale (they never call setlocale), so strtod/strtof read '.' as the
     decimal point. Number parsers here also verify that the whole token was consumed, so a foreign
     locale shows up as a "bad number" error rather than silently wrong values. */
#ifndef TOOL_TOOLUTIL_H
#define TOOL_TOOLUTIL_H
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <pthread.h>

/* ---- errors ---------------------------------------------------------------------------------- */

typedef struct tool_error {
    int line;            /* 1-based source line of the problem, 0 for file-level problems */
    char message[512];   /* "PATH:LINE: problem" or "PATH: problem" (truncated if very long) */
} tool_error;

/* Formats err->message as "PATH:LINE: <fmt...>" (line > 0) or "PATH: <fmt...>" (line <= 0) and sets
   err->line. err may be NULL (nothing happens). path may be NULL (then the prefix is omitted). */
void tool_error_set(tool_error *err, const char *path, int line, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 4, 5)))
#endif
    ;

/* ---- files ----------------------------------------------------------------------------------- */

/* Reads a whole file into a malloc'd buffer (free it with free()). The buffer holds size bytes plus
   one extra NUL byte at data[size] (not counted in size), so text parsers may rely on it. Works on
   pipes too. Errors: "PATH: cannot open: <reason>", "PATH: cannot read: <reason>", out of memory. */
int read_file(const char *path, void **data, size_t *size, tool_error *err);
/* The little-endian 32-bit word at p (the .pvs, BSP and bake-state files). */
uint32_t tool_get32(const void *p);

/* Writes data to PATH.tmp.PID, fsyncs it, then renames it over path, so readers see either the old
   file or the complete new one. On any failure the temporary file is removed and path is untouched.
   (Two threads of one process must not write the same path at the same time: they would share the
   temporary name.) */
int write_file_atomic(const char *path, const void *data, size_t size, tool_error *err);

/* The same for a file written through a stream: fn(f, ctx) writes it (returns 0, or non-zero on
   failure). An existing non-regular path (/dev/null, a pipe) is written in place; a directory is an
   error. */
int write_stream_atomic(const char *path, int (*fn)(FILE *f, const void *ctx), const void *ctx, tool_error *err);

/* ---- progress -------------------------------------------------------------------------------- */

#define PROGRESS_QUIET 1u /* draw nothing at all */
#define PROGRESS_TTY   2u /* force the in-place bar even when the output is not a terminal */
#define PROGRESS_PLAIN 4u /* force plain periodic lines even on a terminal */

typedef struct progress {
    pthread_mutex_t mutex;
    FILE *out;
    char label[64];
    uint64_t total, done;
    double start, last_draw;  /* seconds, monotonic clock */
    int last_percent;         /* last percentage drawn (bar) */
    int last_decile;          /* last 10% step printed (plain lines) */
    int tty, quiet, drawn, ended;
} progress;

/* Starts a progress report of `total` units (0 = unknown: a counter without bar or ETA) on stderr:
   `label [#####.....] 45% 123/456 ETA 12s`, redrawn in place with '\r' when stderr is a terminal,
   otherwise a plain line at most every ~2 seconds or at each new 10% step. */
void progress_begin(progress *p, const char *label, uint64_t total);
/* Same with PROGRESS_* flags and an output stream (NULL = stderr). */
void progress_begin_ex(progress *p, const char *label, uint64_t total, unsigned flags, FILE *out);
/* Thread-safe: sets the number of finished units (values lower than an earlier one are ignored). */
void progress_update(progress *p, uint64_t done);
/* Thread-safe: adds n finished units. */
void progress_add(progress *p, uint64_t n);
/* Draws the final state ("... 100% 456/456 in 3.2s") and releases the mutex. Call exactly once. */
void progress_end(progress *p);

/* ---- threads --------------------------------------------------------------------------------- */

/* Number of online CPUs (at least 1). */
uint32_t cpu_count(void);

/* Physical memory in bytes (sysconf _SC_PHYS_PAGES: Linux, macOS), 0 when the system does not say. */
double memory_bytes(void);

/* Calls fn(user, index, thread) for every index in [0, count) exactly once, spread over `threads`
   threads (0 = cpu_count(); never more threads than indices) with dynamic scheduling (each thread
   takes the next unclaimed index). `thread` is in [0, threads used); the caller's own thread takes
   part as thread 0, and threads == 1 runs everything inline in index order. Returns when all calls
   have returned. If some threads cannot be created the work runs on fewer threads. Returns 0. */
int parallel_for(uint32_t threads, uint32_t count, void (*fn)(void *user, uint32_t index, uint32_t thread),
                 void *user);

/* ---- option parsing -------------------------------------------------------------------------- */

/* Strict decimal integer in [0, 1024] (0 = all CPUs); no sign, spaces or trailing characters. */
int parse_threads(const char *s, uint32_t *out);
/* Strict finite float: the whole string must be a number ("1", "-2.5", "1e-3"); rejects empty
   strings, spaces, trailing garbage, NaN, Inf, hex and values overflowing a float. */
int parse_float(const char *s, float *out);
/* The n arguments argv[at .. at + n) as strict floats into out (the values of an option such as
   --at X Y Z). -1 when fewer than n remain or one is not a number. */
int parse_floats(char **argv, int at, int argc, int n, float *out);
/* A usage error: "TOOL: <fmt...>" and "(see TOOL --help)" on stderr. Returns 2, the tools' exit
   status for usage errors. */
int tool_usage_error(const char *tool, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 2, 3)))
#endif
    ;

/* ---- images ---------------------------------------------------------------------------------- */

/* Writes w x h RGBA8 pixels (row-major, top row first, 4 bytes per pixel) as a PNG (colour type 6,
   per-row adaptive filter, zlib stream of one fixed-Huffman deflate block with LZ77 matching),
   atomically. */
int png_write(const char *path, const uint8_t *rgba, uint32_t w, uint32_t h, tool_error *err);
/* Encodes into a malloc'd buffer instead (free with free()). stored != 0 uses uncompressed (stored)
   deflate blocks and filter 0 (so the pixels appear verbatim). Returns 0 or -1 (zero or too large
   size, out of memory). */
int png_encode(const uint8_t *rgba, uint32_t w, uint32_t h, int stored, uint8_t **png, size_t *size);
/* CRC-32 (PNG / zlib polynomial) and Adler-32, exposed for tests. Start with crc = 0 / adler = 1. */
uint32_t tool_crc32(uint32_t crc, const void *data, size_t size);
uint32_t tool_adler32(uint32_t adler, const void *data, size_t size);

/* Color as 0xRRGGBBAA. */
#define TOOL_RGBA(r, g, b, a) (((uint32_t)(r) << 24) | ((uint32_t)(g) << 16) | ((uint32_t)(b) << 8) | (uint32_t)(a))

/* Draws text with a 5x7 bitmap font (cell 6x9 pixels per character at scale 1) into an RGBA8 image,
   top-left corner at (x, y), clipped to the image. Lowercase letters are drawn as uppercase;
   printable ASCII is covered (unknown characters draw as '?'); '\n' starts a new line.
   Pixels are overwritten with color (no blending). Returns the width in pixels of the widest line. */
int draw_text(uint8_t *rgba, uint32_t w, uint32_t h, int x, int y, const char *text, uint32_t color);
int draw_text_scaled(uint8_t *rgba, uint32_t w, uint32_t h, int x, int y, const char *text, uint32_t color,
                     int scale);

#endif
