/* verify_raster.c - the long acceptance run of the raster module (make verify): tests/test_raster.c
   at a larger scale, optimised: >= 10,000 camera positions checked against ray casting (0 misses),
   thousands of random triangles against 16 x 16 sub-sample brute force. Exit 0 when all pass.
   Usage: verify_raster [SCALE [coverage]]   (default 100: 40 x SCALE cameras per scene, half of them with tiles) */
#include "test.h"
#include <stdlib.h>

int test_failures, test_checks;
extern unsigned long raster_cameras, raster_misses;
void raster_verify(int scale);
void raster_verify_coverage(int scale);

int main(int argc, char **argv) {
    int scale = argc > 1 ? atoi(argv[1]) : 100;
    if (scale < 1) scale = 1;
    if (argc > 2) raster_verify_coverage(scale); /* any second argument: the coverage part only */
    else raster_verify(scale);
    printf("raster verify: scale %d, %lu camera positions, %lu misses, %d checks, %d failed\n", scale, raster_cameras, raster_misses,
           test_checks, test_failures);
    return test_failures ? 1 : 0;
}
