/* main.c - the test runner: runs every group (or those named on the command line) and ends with
   the line "N passed, N failed" (checks), exit status 1 on any failure. */
#include "test.h"
#include <string.h>

int test_failures, test_checks;

void test_core(void);
void test_format(void);
void test_noalloc(void);
void test_kdtree(void);
void test_gen(void);
void test_tools(void);
void test_cli(void);
void test_raster(void);
void test_otree(void);
void test_extproj(void);
void test_shrink(void);
void test_auto(void);
void test_examples(void);
void test_vocc(void);
void test_bounded(void);

static const struct {
    const char *name;
    void (*run)(void);
} groups[] = {
    {"core", test_core}, {"format", test_format}, {"noalloc", test_noalloc}, {"kdtree", test_kdtree},
    {"gen", test_gen},   {"tools", test_tools},   {"cli", test_cli},     {"raster", test_raster},
    {"otree", test_otree},
    {"extproj", test_extproj},
    {"shrink", test_shrink},
    {"auto", test_auto},
    {"examples", test_examples},
    {"vocc", test_vocc},
    {"bounded", test_bounded},
};

int main(int argc, char **argv) {
    size_t g;
    int i;
    for (g = 0; g < sizeof(groups) / sizeof(groups[0]); ++g) {
        int before_f = test_failures, before_c = test_checks, wanted = argc < 2;
        for (i = 1; i < argc; ++i) wanted |= strcmp(argv[i], groups[g].name) == 0;
        if (!wanted) continue;
        groups[g].run();
        fprintf(stderr, "%-8s %6d checks, %d failed\n", groups[g].name, test_checks - before_c, test_failures - before_f);
    }
    printf("%d passed, %d failed\n", test_checks - test_failures, test_failures);
    return test_failures ? 1 : 0;
}
