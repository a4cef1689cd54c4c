/* impl.c - the one translation unit of the tests that holds the implementation. */
#define PVS_TEST_HOOKS /* the test-only flags (pvs.h, CONFIGURATION) */
#define PVS_IMPLEMENTATION
#include "../pvs.h"
