/* verify_extproj.c - the long extended-projection checks of tests/test_extproj.c (make verify): the
   occlusion sweep with sub-cells and adaptive cells, and on more cells of three scenes, against ray sampling. Exit 0 when all pass. */
#include "test.h"

int test_failures, test_checks;
void extproj_verify(void);

int main(void) {
    extproj_verify();
    printf("extproj verify: %d checks, %d failed\n", test_checks, test_failures);
    return test_failures ? 1 : 0;
}
