/* verify_otree.c - the long acceptance run of from-point culling with the occlusion tree (make
   verify): the from-point part of tests/test_otree.c at a larger scale, optimised: >= 10,000 camera
   positions on random and generator scenes checked against ray casting (0 misses), walkthroughs
   where hierarchy updating must equal testing every node. Exit 0 when all pass.
   Usage: verify_otree [SCALE]   (default 60: 20 x SCALE cameras per scene) */
#include "test.h"
#include <stdlib.h>

int test_failures, test_checks;
extern unsigned long otree_cameras, otree_misses;
void otree_verify(int scale);

int main(int argc, char **argv) {
    int scale = argc > 1 ? atoi(argv[1]) : 60;
    if (scale < 1) scale = 1;
    otree_verify(scale);
    printf("otree verify: scale %d, %lu camera positions, %lu misses, %d checks, %d failed\n", scale, otree_cameras, otree_misses,
           test_checks, test_failures);
    return test_failures ? 1 : 0;
}
