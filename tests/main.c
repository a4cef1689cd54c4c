/* main.c - the test runner: runs every group (or those named on the command line) and ends with
   the line "N passed, N failed" (checks), exit status 1 on any failure.
   -j N: up to N groups at once, each in a child process (N = 0: one per CPU); each group's output is
   kept in pvstest-GROUP.log and printed in group order, so the output is the same for any N. */
#define _POSIX_C_SOURCE 200809L
#include "test.h"
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

int test_failures, test_checks;

void test_core(void);
void test_format(void);
void test_noalloc(void);
void test_kdtree(void);
void test_gen(void);
void test_tools(void);
void test_bsp(void);
void test_portal(void);
void test_cli(void);
void test_raster(void);
void test_otree(void);
void test_extproj(void);
void test_shrink(void);
void test_auto(void);
void test_examples(void);
void test_vocc(void);
void test_bounded(void);
void test_seethrough(void);
void test_walkable(void);

/* seconds: about how long each group runs (the sanitizer build on one core, measured 2026-12-02), to start the
   longest first */
static const struct {
    const char *name;
    void (*run)(void);
    int seconds;
} groups[] = {
    {"core", test_core, 1},         {"format", test_format, 23},     {"noalloc", test_noalloc, 1},
    {"kdtree", test_kdtree, 13},    {"gen", test_gen, 1},           {"tools", test_tools, 1},      {"bsp", test_bsp, 1},      {"portal", test_portal, 6},
    {"cli", test_cli, 14},           {"raster", test_raster, 13},     {"otree", test_otree, 20},
    {"extproj", test_extproj, 42},  {"shrink", test_shrink, 26},    {"auto", test_auto, 60},
    {"examples", test_examples, 17}, {"vocc", test_vocc, 7},        {"bounded", test_bounded, 1},
    {"seethrough", test_seethrough, 12},     {"walkable", test_walkable, 1},
};
#define GROUP_COUNT (sizeof(groups) / sizeof(groups[0]))

static void log_path(char *buf, size_t size, size_t g, const char *ext) { snprintf(buf, size, "pvstest-%s.%s", groups[g].name, ext); }

/* Runs the wanted groups in up to `jobs` children, longest first; prints their logs in group order. */
static int run_parallel(const int *wanted, int jobs) {
    size_t order[GROUP_COUNT], n = 0, i, j, next = 0;
    pid_t pid_of[GROUP_COUNT];
    int running = 0, failures = 0, checks = 0, lost = 0;
    for (i = 0; i < GROUP_COUNT; ++i) {
        pid_of[i] = -1;
        if (wanted[i]) order[n++] = i;
    }
    for (i = 1; i < n; ++i) /* longest first */
        for (j = i; j > 0 && groups[order[j]].seconds > groups[order[j - 1]].seconds; --j) {
            size_t t = order[j];
            order[j] = order[j - 1];
            order[j - 1] = t;
        }
    while (next < n || running) {
        while (next < n && running < jobs) {
            size_t g = order[next++];
            char path[256];
            pid_t pid;
            fflush(NULL);
            pid = fork();
            if (pid == 0) {
                FILE *f;
                log_path(path, sizeof(path), g, "log");
                if (!freopen(path, "w", stderr)) _exit(2);
                groups[g].run();
                fprintf(stderr, "%-8s %6d checks, %d failed\n", groups[g].name, test_checks, test_failures);
                fflush(stderr);
                log_path(path, sizeof(path), g, "count");
                f = fopen(path, "w");
                if (!f || fprintf(f, "%d %d\n", test_checks, test_failures) < 0 || fclose(f)) _exit(2);
                _exit(0);
            }
            if (pid < 0) {
                fprintf(stderr, "pvstest: cannot start a child for %s\n", groups[g].name);
                return 1;
            }
            pid_of[g] = pid;
            ++running;
        }
        {
            int status;
            pid_t done = wait(&status);
            if (done < 0) break;
            --running;
            for (i = 0; i < GROUP_COUNT; ++i)
                if (wanted[i] && pid_of[i] == done && (!WIFEXITED(status) || WEXITSTATUS(status)))
                    fprintf(stderr, "pvstest: group %s ended abnormally (status %d)\n", groups[i].name, status), ++lost;
        }
    }
    for (i = 0; i < GROUP_COUNT; ++i) {
        char path[256], line[4096];
        FILE *f;
        int c = 0, fl = 0;
        if (!wanted[i]) continue;
        log_path(path, sizeof(path), i, "log");
        if ((f = fopen(path, "r"))) {
            while (fgets(line, sizeof(line), f)) fputs(line, stderr);
            fclose(f);
            remove(path);
        }
        log_path(path, sizeof(path), i, "count");
        if ((f = fopen(path, "r"))) {
            if (fscanf(f, "%d %d", &c, &fl) != 2) ++lost;
            fclose(f);
            remove(path);
        } else {
            ++lost;
        }
        checks += c;
        failures += fl;
    }
    failures += lost;
    printf("%d passed, %d failed\n", checks - failures, failures);
    return failures ? 1 : 0;
}

int main(int argc, char **argv) {
    size_t g;
    int i, jobs = 1, wanted[GROUP_COUNT], any = 0;
    for (g = 0; g < GROUP_COUNT; ++g) wanted[g] = 0;
    for (i = 1; i < argc; ++i) {
        if (!strcmp(argv[i], "-j") && i + 1 < argc) {
            jobs = atoi(argv[++i]);
            if (jobs <= 0) {
                long cpus = sysconf(_SC_NPROCESSORS_ONLN);
                jobs = cpus > 0 ? (int)cpus : 1;
            }
            continue;
        }
        for (g = 0; g < GROUP_COUNT; ++g)
            if (!strcmp(argv[i], groups[g].name)) wanted[g] = any = 1;
    }
    for (g = 0; g < GROUP_COUNT; ++g) wanted[g] |= !any;
    if (jobs > 1) return run_parallel(wanted, jobs);
    for (g = 0; g < GROUP_COUNT; ++g) {
        int before_f = test_failures, before_c = test_checks;
        if (!wanted[g]) continue;
        groups[g].run();
        fprintf(stderr, "%-8s %6d checks, %d failed\n", groups[g].name, test_checks - before_c, test_failures - before_f);
    }
    printf("%d passed, %d failed\n", test_checks - test_failures, test_failures);
    return test_failures ? 1 : 0;
}
