/* mesh.h - the in-memory scene the tools, examples and tests share: triangles grouped into named
   objects, plus view cells. Produced by the OBJ loader (obj.h) and the scene generators (gen.h),
   handed to pvs.h as caller arrays. Not part of the library. */
#ifndef TOOL_MESH_H
#define TOOL_MESH_H
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#define MESH_OBJECT_OCCLUDER 1u    /* blocks sight, never drawn (OBJ name begins with "occluder") */
#define MESH_OBJECT_SEE_THROUGH 2u /* drawn, never blocks sight (OBJ name begins with "glass", "door" or
                                      "see_through") */
#define MESH_OBJECT_ONE_SIDED 4u   /* drawn with back faces culled, counter-clockwise front (OBJ name begins with
                                      "one_sided") */

typedef struct mesh_object {
    char *name;              /* owned, NUL-terminated, never NULL */
    uint32_t first_triangle; /* range into mesh.indices / 3 */
    uint32_t triangle_count;
    uint32_t flags;          /* MESH_OBJECT_* */
    uint32_t line;           /* source line that started it (0 when generated) */
} mesh_object;

typedef struct mesh {
    float *positions;        /* 3 floats per vertex */
    uint32_t vertex_count, vertex_cap;
    uint32_t *indices;       /* 3 per triangle */
    uint32_t triangle_count, triangle_cap;
    mesh_object *objects;
    uint32_t object_count, object_cap;
} mesh;

typedef struct mesh_cells {
    float *boxes;            /* 6 floats per cell: minx miny minz maxx maxy maxz */
    uint32_t count, cap;
    uint32_t *lines;         /* per cell, its source line (NULL when generated) */
    uint32_t line_cap;
} mesh_cells;

/* All return 0 on success, -1 when out of memory (the mesh stays valid). */
void mesh_init(mesh *m);
void mesh_free(mesh *m);
int mesh_add_vertex(mesh *m, float x, float y, float z);        /* index = vertex_count - 1 */
int mesh_add_triangle(mesh *m, uint32_t a, uint32_t b, uint32_t c); /* appended to the last object */
int mesh_begin_object(mesh *m, const char *name, uint32_t flags, uint32_t line);
/* Convenience for generators: a quad a-b-c-d as two triangles. */
int mesh_add_quad(mesh *m, uint32_t a, uint32_t b, uint32_t c, uint32_t d);
/* Write as OBJ ("o NAME", "v", "f" lines, 1-based). Returns 0 or -1 on an I/O error. */
int mesh_write_obj(const mesh *m, FILE *f);

void mesh_cells_init(mesh_cells *c);
void mesh_cells_free(mesh_cells *c);
int mesh_cells_add(mesh_cells *c, const float box[6]);
/* The same for a cell read from a file's line `line` (mesh_cells_line gives it back; 0 = unknown). */
int mesh_cells_add_line(mesh_cells *c, const float box[6], uint32_t line);
uint32_t mesh_cells_line(const mesh_cells *c, uint32_t cell);
/* Write one "minx miny minz maxx maxy maxz" line per cell (%.9g). */
int mesh_cells_write(const mesh_cells *c, FILE *f);

#endif
