/* compile_check.c - include, define the implementation, include again; C99, C11, C++ and PVS_STATIC. */
#ifdef CHECK_STATIC
#define PVS_STATIC
#endif
#include "../pvs.h"
#define PVS_IMPLEMENTATION
#include "../pvs.h"
#include "../pvs.h"
int compile_check(void);
int compile_check(void) { return (int)pvs_version(); }
