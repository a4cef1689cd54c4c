/* impl.c - the implementation for the fuzzing builds (make fuzz); pvstest links test_extproj.c's. */
#define PVS_IMPLEMENTATION
#include "../pvs.h"
