/* mesh.c - see mesh.h */
#include "mesh.h"
#include <stdlib.h>
#include <string.h>

static int mesh__grow(void **p, uint32_t *cap, uint32_t need, size_t elem) {
    if (need <= *cap) return 0;
    uint64_t n = *cap ? (uint64_t)*cap * 2 : 64;
    while (n < need) n *= 2;
    if (n > 0xffffffffu) n = 0xffffffffu;
    if (n < need || n * elem > (uint64_t)SIZE_MAX) return -1;
    void *q = realloc(*p, (size_t)(n * elem));
    if (!q) return -1;
    *p = q;
    *cap = (uint32_t)n;
    return 0;
}

void mesh_init(mesh *m) { memset(m, 0, sizeof(*m)); }

void mesh_free(mesh *m) {
    for (uint32_t i = 0; i < m->object_count; ++i) free(m->objects[i].name);
    free(m->positions);
    free(m->indices);
    free(m->objects);
    memset(m, 0, sizeof(*m));
}

int mesh_add_vertex(mesh *m, float x, float y, float z) {
    if (m->vertex_count == 0xffffffffu) return -1;
    if (mesh__grow((void **)&m->positions, &m->vertex_cap, m->vertex_count + 1, 3 * sizeof(float))) return -1;
    float *p = m->positions + 3 * (size_t)m->vertex_count++;
    p[0] = x; p[1] = y; p[2] = z;
    return 0;
}

int mesh_begin_object(mesh *m, const char *name, uint32_t flags, uint32_t line) {
    if (m->object_count == 0xffffffffu) return -1;
    if (mesh__grow((void **)&m->objects, &m->object_cap, m->object_count + 1, sizeof(mesh_object))) return -1;
    size_t len = strlen(name);
    char *copy = (char *)malloc(len + 1);
    if (!copy) return -1;
    memcpy(copy, name, len + 1);
    mesh_object *o = &m->objects[m->object_count++];
    o->name = copy;
    o->first_triangle = m->triangle_count;
    o->triangle_count = 0;
    o->flags = flags;
    o->line = line;
    return 0;
}

int mesh_add_triangle(mesh *m, uint32_t a, uint32_t b, uint32_t c) {
    if (m->object_count == 0 && mesh_begin_object(m, "default", 0, 0)) return -1;
    if (m->triangle_count == 0xffffffffu / 3) return -1;
    if (mesh__grow((void **)&m->indices, &m->triangle_cap, m->triangle_count + 1, 3 * sizeof(uint32_t))) return -1;
    uint32_t *t = m->indices + 3 * (size_t)m->triangle_count++;
    t[0] = a; t[1] = b; t[2] = c;
    m->objects[m->object_count - 1].triangle_count++;
    return 0;
}

int mesh_add_quad(mesh *m, uint32_t a, uint32_t b, uint32_t c, uint32_t d) {
    return mesh_add_triangle(m, a, b, c) || mesh_add_triangle(m, a, c, d) ? -1 : 0;
}

int mesh_write_obj(const mesh *m, FILE *f) {
    for (uint32_t i = 0; i < m->vertex_count; ++i) {
        const float *p = m->positions + 3 * (size_t)i;
        fprintf(f, "v %.9g %.9g %.9g\n", p[0], p[1], p[2]);
    }
    for (uint32_t o = 0; o < m->object_count; ++o) {
        const mesh_object *ob = &m->objects[o];
        fprintf(f, "o %s\n", ob->name);
        for (uint32_t t = ob->first_triangle; t < ob->first_triangle + ob->triangle_count; ++t) {
            const uint32_t *v = m->indices + 3 * (size_t)t;
            fprintf(f, "f %u %u %u\n", v[0] + 1, v[1] + 1, v[2] + 1);
        }
    }
    return ferror(f) ? -1 : 0;
}

void mesh_cells_init(mesh_cells *c) { memset(c, 0, sizeof(*c)); }
void mesh_cells_free(mesh_cells *c) {
    free(c->boxes);
    free(c->lines);
    memset(c, 0, sizeof(*c));
}

int mesh_cells_add(mesh_cells *c, const float box[6]) {
    if (mesh__grow((void **)&c->boxes, &c->cap, c->count + 1, 6 * sizeof(float))) return -1;
    memcpy(c->boxes + 6 * (size_t)c->count++, box, 6 * sizeof(float));
    return 0;
}

int mesh_cells_add_line(mesh_cells *c, const float box[6], uint32_t line) {
    if (mesh__grow((void **)&c->lines, &c->line_cap, c->count + 1, sizeof(uint32_t))) return -1;
    if (mesh_cells_add(c, box)) return -1;
    c->lines[c->count - 1] = line;
    return 0;
}

uint32_t mesh_cells_line(const mesh_cells *c, uint32_t cell) { return c->lines && cell < c->count ? c->lines[cell] : 0; }

int mesh_cells_write(const mesh_cells *c, FILE *f) {
    for (uint32_t i = 0; i < c->count; ++i) {
        const float *b = c->boxes + 6 * (size_t)i;
        fprintf(f, "%.9g %.9g %.9g %.9g %.9g %.9g\n", b[0], b[1], b[2], b[3], b[4], b[5]);
    }
    return ferror(f) ? -1 : 0;
}
