#ifndef TEST_H
#define TEST_H
#undef NDEBUG
#include <stdio.h>
extern int test_failures, test_checks;
#define CHECK(c) do { ++test_checks; if (!(c)) { ++test_failures; fprintf(stderr, "%s:%d: CHECK failed: %s\n", __FILE__, __LINE__, #c); } } while (0)
#endif
