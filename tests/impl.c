/* impl.c - the one translation unit of the tests that holds the implementation. */
#define PVS_IMPLEMENTATION
#include "../pvs.h"
