/* obj.h - Wavefront OBJ scene loader and view-cells file loader for the tools (see DESIGN.md,
   "The command-line contract"). Not part of the library.

   OBJ:
   - Each `o NAME` starts an object. When the file has no `o` line at all, each `g NAME` does instead
     (otherwise `g` lines are ignored). Objects are numbered in file order from 0. Faces before the
     first object line form object 0, named "default". An `o`/`g` without a name is named "unnamed" /
     "default". Names are the rest of the line with surrounding whitespace removed.
   - Objects whose name begins with "occluder" get MESH_OBJECT_OCCLUDER; those whose name begins with
     "glass", "door" or "see_through" get MESH_OBJECT_SEE_THROUGH (drawn, never blocking sight).
   - `v x y z [w | r g b ...]`: the first 3 numbers are the position; the rest must be numbers too.
   - `f a b c ...`: polygons are fan-triangulated (a b c, a c d, ...). Each vertex is `v`, `v/vt`,
     `v//vn` or `v/vt/vn`; only the position index is used (vt/vn must be integers or empty but are
     not range-checked). Negative indices count back from the last vertex defined so far (-1 = the
     latest). Degenerate faces (a repeated index) are kept.
   - Ignored: vt, vn, vp, usemtl, mtllib, s, l, p, any unknown statement, comments, blank lines. A
     `#` ends the data of a v / f line. LF, CRLF and CR (old Mac) line ends and a UTF-8 byte order
     mark are accepted.
     Backslash line continuation is not supported.
   - Empty objects (no faces) are kept, so ids follow the file; see obj_check_empty_objects.
   - Numbers are read in the "C" locale.

   On success *m holds the scene (the caller mesh_free()s it). On error *m is left empty
   (mesh_init'ed, nothing to free) and err (may be NULL) holds "NAME:LINE: problem" or, for
   file-level problems, "NAME: problem" with err->line == 0. */
#ifndef TOOL_OBJ_H
#define TOOL_OBJ_H
#include "mesh.h"
#include "toolutil.h"

int obj_load(const char *path, mesh *m, tool_error *err);
/* text need not be NUL-terminated; name is used in messages. */
int obj_parse(const char *name, const char *text, size_t len, mesh *m, tool_error *err);

/* Returns how many objects of m have no triangles; if there is at least one and first is not NULL,
   first gets "NAME:LINE: object N 'OBJNAME' has no faces" about the first of them (NAME = path),
   so the caller can print it as a warning or fail with it. */
uint32_t obj_check_empty_objects(const char *path, const mesh *m, tool_error *first);

/* Cells file: one box per line, `minx miny minz maxx maxy maxz`; `#` starts a comment anywhere on a
   line; blank lines are fine. Cell ids follow line order. min == max on an axis is allowed (flat
   cell). Errors: wrong number of values, bad number, non-finite value, min greater than max, no cells,
   binary data. Same error / ownership conventions as obj_load (*c is left empty on error). */
int cells_load(const char *path, mesh_cells *c, tool_error *err);
int cells_parse(const char *name, const char *text, size_t len, mesh_cells *c, tool_error *err);

#endif
