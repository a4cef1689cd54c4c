/* compile_check.c - include, define the implementation, include again; C99, C11, C++ and PVS_STATIC.
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
int compile_check(void) { return (int)pvs_version(); }
