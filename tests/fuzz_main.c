/* fuzz_main.c - `make fuzz`: with -DPVS_LIBFUZZER the libFuzzer entry point (clang
   -fsanitize=fuzzer); without it a plain replay main: `fuzz_replay FILE...` runs each file through
   the same target and prints its result code. */
#include "../pvs.h"
#include <stdio.h>
#include <stdlib.h>

int pvs_fuzz_one(const uint8_t *data, size_t size);

#ifdef PVS_LIBFUZZER
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
    pvs_fuzz_one(data, size);
    return 0;
}
#else
int main(int argc, char **argv) {
    int i;
    for (i = 1; i < argc; ++i) {
        FILE *fp = fopen(argv[i], "rb");
        long n;
        uint8_t *buf;
        if (!fp) { fprintf(stderr, "fuzz_replay: cannot open %s\n", argv[i]); return 1; }
        fseek(fp, 0, SEEK_END);
        n = ftell(fp);
        fseek(fp, 0, SEEK_SET);
        buf = (uint8_t *)malloc(n > 0 ? (size_t)n : 1);
        if (!buf || fread(buf, 1, (size_t)n, fp) != (size_t)n) { fprintf(stderr, "fuzz_replay: cannot read %s\n", argv[i]); return 1; }
        fclose(fp);
        printf("%s: %s\n", argv[i], pvs_result_string((pvs_result)pvs_fuzz_one(buf, (size_t)n)));
        free(buf);
    }
    return 0;
}
#endif
