#define PVS_IMPLEMENTATION
#include "../pvs.h"
