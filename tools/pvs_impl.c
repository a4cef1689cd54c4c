/* pvs_impl.c - the implementation of pvs.h for the tools and examples. */
#define PVS_IMPLEMENTATION
#include "../pvs.h"
