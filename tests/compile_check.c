/* compile_check.c - include, define the implementation, include again; C99, C11, C++ and PVS_STATIC;
   PVS_RUNTIME_ONLY: the run-time calls a game makes, with none of the bake's declarations.
   CHECK_HOOKS: the allocator given by the user (stdlib.h then comes only with PVS_QSORT's default);
   CHECK_SORT: the sort too, so the implementation must need nothing of stdlib.h (build these with
   PVS_NO_SIMD: the SIMD headers of some compilers include it; the Makefile adds PVS_NO_STDIO). */
#ifdef CHECK_STATIC
#define PVS_STATIC
#endif
#if defined(CHECK_HOOKS) || defined(CHECK_SORT)
#include <stddef.h>
void *check_malloc(size_t size);
void check_free(void *p);
#define PVS_MALLOC(sz) check_malloc(sz)
#define PVS_FREE(p) check_free(p)
#endif
#ifdef CHECK_SORT
void check_sort(void *base, size_t n, size_t size, int (*cmp)(const void *, const void *));
#define PVS_QSORT(base, n, size, cmp) check_sort(base, n, size, cmp)
#endif
#include "../pvs.h"
#define PVS_IMPLEMENTATION
#include "../pvs.h"
#include "../pvs.h"
int compile_check(void);
#ifdef PVS_RUNTIME_ONLY /* the run-time part alone: the bake's declarations are gone */
#if defined(PVS_BAKE_PREVIEW) || defined(PVS_SCENE_ALLOW_EMPTY_OBJECTS) || defined(PVS_CULL_OCCLUDER_MESH)
#error "PVS_RUNTIME_ONLY declares the bake"
#endif
int compile_check(void) {
    static const unsigned char none[1] = {0};
    pvs_file f;
    pvs_cursor c;
    pvs_word bits[1], scratch[1];
    float p[3] = {0, 0, 0};
    if (pvs_file_open(none, sizeof(none), &f, NULL) != PVS_OK) return (int)pvs_version();
    if (pvs_cursor_init(&c, &f, bits, scratch, 1, NULL) != PVS_OK) return -1;
    pvs_cursor_move(&c, pvs_file_find_cell(&f, p), NULL, NULL);
    return (int)pvs_file_find_object(&f, "door") + (pvs_file_object_name(&f, 0) != NULL) +
           (int)pvs_vocc_cull_scratch_size(NULL, 8);
}
#else
int compile_check(void) { return (int)pvs_version(); }
#endif
