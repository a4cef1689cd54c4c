# pvs.h - build, test, demo, bench, verify. Everything lands in build/.
# Configurations in one place: CONFIG=release (default) | debug | sanitize | scalar
CC      ?= cc
CXX     ?= c++
CONFIG  ?= release
B       := build
WARN    := -Wall -Wextra -Wshadow -Wstrict-prototypes -Wmissing-prototypes
CFLAGS_release  := -O2 -g
CFLAGS_debug    := -O0 -g
CFLAGS_sanitize := -O1 -g -fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=all
CFLAGS_scalar   := -O2 -g -DPVS_NO_SIMD
CFLAGS  := -std=c99 $(WARN) $(CFLAGS_$(CONFIG))
LDLIBS  := -lm -lpthread
TEST_CFLAGS := -std=c99 -Wall -Wextra -Wshadow -Werror -Og -g -fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=all

TOOL_LIB := tools/mesh.c tools/obj.c tools/toolutil.c tools/gen.c tools/cli.c tools/render.c tools/pvs_impl.c
TOOL_HDR := pvs.h tools/mesh.h tools/obj.h tools/toolutil.h tools/gen.h tools/cli.h tools/render.h
TOOL_OBJ := $(patsubst tools/%.c,$(B)/obj/%.o,$(TOOL_LIB))
TOOLS    := $(B)/pvsbake $(B)/pvsinfo $(B)/pvscheck $(B)/pvsgen $(B)/pvsview
TEST_SRC := tests/impl.c tests/test_extproj.c tests/test_noalloc.c tests/main.c tests/test_core.c tests/test_format.c tests/test_kdtree.c \
            tests/test_gen.c tests/test_tools.c tests/test_cli.c tests/test_raster.c tests/test_otree.c \
            tests/test_shrink.c tests/test_auto.c tests/test_examples.c tests/test_vocc.c tools/mesh.c tools/obj.c tools/toolutil.c tools/gen.c tools/cli.c tools/render.c tests/fuzz_target.c

.PHONY: all tools test test-neon demo bench verify fuzz clean compile-checks readme-check examples cullmap-images
all: tools
tools: $(TOOLS)

# the implementation and the tool helpers are compiled once and linked into every tool and example
$(B)/obj/%.o: tools/%.c $(TOOL_HDR)
	@mkdir -p $(B)/obj
	$(CC) $(CFLAGS) -c -o $@ $<

$(B)/%: tools/%.c $(TOOL_OBJ) $(TOOL_HDR)
	@mkdir -p $(B)
	$(CC) $(CFLAGS) -o $@ $< $(TOOL_OBJ) $(LDLIBS)

# The header compiles as C99, C11 and C++ (include, define, include again), as a PVS_STATIC unit, and
# with the user's allocator and sort (no stdlib.h needed), the last also without stdio.
compile-checks: tests/compile_check.c pvs.h
	@mkdir -p $(B)
	$(CC) -std=c99 -pedantic -Wall -Wextra -Werror -c tests/compile_check.c -o $(B)/cc_c99.o
	$(CC) -std=c11 -pedantic -Wall -Wextra -Werror -c tests/compile_check.c -o $(B)/cc_c11.o
	$(CXX) -x c++ -std=c++11 -Wall -Wextra -Werror -c tests/compile_check.c -o $(B)/cc_cpp.o
	$(CC) -std=c99 -Wall -Wextra -Werror -DCHECK_STATIC -c tests/compile_check.c -o $(B)/cc_static.o
	$(CC) -std=c99 -pedantic -Wall -Wextra -Werror -DPVS_NO_SIMD -DCHECK_HOOKS -c tests/compile_check.c -o $(B)/cc_hooks.o
	$(CC) -std=c99 -pedantic -Wall -Wextra -Werror -DPVS_NO_SIMD -DPVS_NO_STDIO -DCHECK_SORT -c tests/compile_check.c -o $(B)/cc_sort.o

# one object per source, so that make -j compiles them side by side (the three that hold a copy of the
# implementation first: they take longest)
TEST_OBJ := $(patsubst %.c,$(B)/tobj/%.o,$(TEST_SRC))
$(B)/tobj/%.o: %.c tests/test.h $(TOOL_HDR)
	@mkdir -p $(dir $@)
	$(CC) $(TEST_CFLAGS) -c -o $@ $<
$(B)/pvstest: $(TEST_OBJ)
	$(CC) $(TEST_CFLAGS) -o $@ $(TEST_OBJ) $(LDLIBS)

# The README's quick start (its first ```c block) must compile and print what it claims.
readme-check: README.md pvs.h
	@mkdir -p $(B)
	awk '/^```c$$/ { f = 1; next } /^```$$/ { if (f) exit } f' README.md > $(B)/readme_example.c
	$(CC) -std=c99 -Wall -Wextra -Werror -I. -o $(B)/readme_example $(B)/readme_example.c -lm
	./$(B)/readme_example | grep -x 'object 0 visible, object 1 hidden'

# the groups run side by side, one per CPU (the output does not depend on it)
test: $(B)/pvstest compile-checks readme-check tools $(B)/pvsruntime
	cd $(B) && ./pvstest -j 0

# NEON (not part of `make test`): the test binary built for aarch64, static, its raster group run under
# qemu-user; the SIMD and scalar paths must agree there as on x86. Skipped when the tools are missing.
AARCH64_CC ?= aarch64-linux-gnu-gcc
QEMU_AARCH64 ?= qemu-aarch64
test-neon:
	@if command -v $(AARCH64_CC) >/dev/null 2>&1 && command -v $(QEMU_AARCH64) >/dev/null 2>&1; then \
	  mkdir -p $(B)/neon && \
	  $(AARCH64_CC) -std=c99 -Wall -Wextra -Wshadow -Werror -O1 -g -static -o $(B)/neon/pvstest $(TEST_SRC) $(LDLIBS) && \
	  cd $(B) && $(QEMU_AARCH64) ./neon/pvstest raster; \
	else echo "test-neon: $(AARCH64_CC) or $(QEMU_AARCH64) not found, skipped"; fi

$(B)/pvsdemo: examples/demo.c $(TOOL_OBJ) $(TOOL_HDR)
	@mkdir -p $(B)
	$(CC) $(CFLAGS) -Itools -o $@ examples/demo.c $(TOOL_OBJ) $(LDLIBS)

# examples/cullmap.c: per-frame culling of the city, images in build/cullmap/
$(B)/pvscullmap: examples/cullmap.c $(TOOL_OBJ) $(TOOL_HDR)
	@mkdir -p $(B)
	$(CC) $(CFLAGS) -Itools -o $@ examples/cullmap.c $(TOOL_OBJ) $(LDLIBS)

# examples/walkthrough.c, forest.c, indoor.c (the demo's images) and runtime_minimal.c (the
# runtime alone: pvs.h and libc, no tool code, no allocation)
$(B)/pvswalkthrough: examples/walkthrough.c $(TOOL_OBJ) $(TOOL_HDR)
	@mkdir -p $(B)
	$(CC) $(CFLAGS) -Itools -o $@ examples/walkthrough.c $(TOOL_OBJ) $(LDLIBS)
$(B)/pvsforest: examples/forest.c examples/methods_view.h $(TOOL_OBJ) $(TOOL_HDR)
	@mkdir -p $(B)
	$(CC) $(CFLAGS) -Itools -o $@ examples/forest.c $(TOOL_OBJ) $(LDLIBS)
$(B)/pvsindoor: examples/indoor.c examples/methods_view.h $(TOOL_OBJ) $(TOOL_HDR)
	@mkdir -p $(B)
	$(CC) $(CFLAGS) -Itools -o $@ examples/indoor.c $(TOOL_OBJ) $(LDLIBS)
$(B)/pvsruntime: examples/runtime_minimal.c pvs.h
	@mkdir -p $(B)
	$(CC) $(CFLAGS) -o $@ examples/runtime_minimal.c -lm

examples: $(B)/pvsdemo $(B)/pvscullmap $(B)/pvswalkthrough $(B)/pvsforest $(B)/pvsindoor $(B)/pvsruntime

cullmap-images: $(B)/pvscullmap
	@mkdir -p $(B)/cullmap
	./$(B)/pvscullmap -o $(B)/cullmap

# make demo: the city baked on 2 cores (otree: see examples/demo.c), the walkthrough with its plot and
# frames, pvsview's map of the bake, the methods side by side on the forest and the indoor plan, and
# the runtime on a memory buffer. Everything lands in build/demo/.
demo: $(B)/pvsdemo $(B)/pvswalkthrough $(B)/pvsview $(B)/pvsforest $(B)/pvsindoor $(B)/pvsruntime $(B)/pvsgen
	@mkdir -p $(B)/demo
	./$(B)/pvsdemo -j 2 -o $(B)/demo/city.pvs
	./$(B)/pvswalkthrough --pvs $(B)/demo/city.pvs -o $(B)/demo
	./$(B)/pvsgen city -o $(B)/demo/city.obj --cells $(B)/demo/city.cells
	./$(B)/pvsview $(B)/demo/city.obj $(B)/demo/city.pvs -o $(B)/demo/view.png --cell-at 346 1.7 388 --frame 346 1.7 388 1 -0.03 0
	./$(B)/pvsforest -o $(B)/demo
	./$(B)/pvsindoor -o $(B)/demo
	./$(B)/pvsruntime $(B)/demo/city.pvs

$(B)/bench_kdtree: tests/bench_kdtree.c pvs.h
	@mkdir -p $(B)
	$(CC) $(CFLAGS) -O2 -o $@ tests/bench_kdtree.c $(LDLIBS)
$(B)/bench_bake: tests/bench_bake.c $(TOOL_LIB) $(TOOL_HDR)
	@mkdir -p $(B)
	$(CC) $(CFLAGS) -O2 -o $@ tests/bench_bake.c $(TOOL_LIB) $(LDLIBS)

$(B)/bench_file: tests/bench_file.c $(TOOL_LIB) $(TOOL_HDR)
	@mkdir -p $(B)
	$(CC) $(CFLAGS) -O2 -o $@ tests/bench_file.c $(TOOL_LIB) $(LDLIBS)

$(B)/bench_raster: tests/bench_raster.c $(TOOL_LIB) $(TOOL_HDR)
	@mkdir -p $(B)
	$(CC) $(CFLAGS) -O2 -o $@ tests/bench_raster.c $(TOOL_LIB) $(LDLIBS)

$(B)/bench_otree: tests/bench_otree.c $(TOOL_LIB) $(TOOL_HDR)
	@mkdir -p $(B)
	$(CC) $(CFLAGS) -O2 -o $@ tests/bench_otree.c $(TOOL_LIB) $(LDLIBS)

$(B)/bench_extproj: tests/bench_extproj.c $(TOOL_LIB) $(TOOL_HDR)
	@mkdir -p $(B)
	$(CC) $(CFLAGS) -O2 -o $@ tests/bench_extproj.c $(TOOL_LIB) $(LDLIBS)

$(B)/bench_shrink: tests/bench_shrink.c $(TOOL_LIB) $(TOOL_HDR)
	@mkdir -p $(B)
	$(CC) $(CFLAGS) -O2 -o $@ tests/bench_shrink.c $(TOOL_LIB) $(LDLIBS)

$(B)/bench_auto: tests/bench_auto.c $(TOOL_OBJ) $(TOOL_HDR)
	@mkdir -p $(B)
	$(CC) $(CFLAGS) -O2 -o $@ tests/bench_auto.c $(TOOL_OBJ) $(LDLIBS)

$(B)/bench_bounded: tests/bench_bounded.c $(TOOL_OBJ) $(TOOL_HDR)
	@mkdir -p $(B)
	$(CC) $(CFLAGS) -O2 -o $@ tests/bench_bounded.c $(TOOL_OBJ) $(LDLIBS)

$(B)/bench_vocc: tests/bench_vocc.c $(TOOL_OBJ) $(TOOL_HDR)
	@mkdir -p $(B)
	$(CC) $(CFLAGS) -O2 -o $@ tests/bench_vocc.c $(TOOL_OBJ) $(LDLIBS)

bench: $(B)/bench_kdtree $(B)/bench_bake $(B)/bench_file $(B)/bench_raster $(B)/bench_otree $(B)/bench_extproj $(B)/bench_shrink \
       $(B)/bench_auto $(B)/bench_vocc $(B)/bench_bounded $(B)/pvswalkthrough tools
	./$(B)/bench_bounded
	./$(B)/bench_kdtree
	./$(B)/bench_bake
	./$(B)/bench_file
	./$(B)/bench_raster
	./$(B)/bench_otree
	./$(B)/bench_extproj
	./$(B)/bench_shrink
	./$(B)/bench_auto
	./$(B)/pvswalkthrough --bench
	./$(B)/bench_vocc

# Fuzzing the file reader: a libFuzzer build (clang) seeded with tests/corpus, FUZZ_SECONDS long, and
# a plain replay binary (any compiler) that runs files through the same target.
FUZZ_SECONDS ?= 60
FUZZ_SRC := tests/fuzz_main.c tests/fuzz_target.c tests/impl.c
$(B)/fuzz_replay: $(FUZZ_SRC) pvs.h
	@mkdir -p $(B)
	$(CC) -std=c99 -O1 -g -fsanitize=address,undefined -o $@ $(FUZZ_SRC) -lm
fuzz: $(B)/fuzz_replay
	@mkdir -p $(B)/fuzz-corpus
	clang -std=c99 -O1 -g -DPVS_LIBFUZZER -fsanitize=fuzzer,address,undefined -o $(B)/fuzz_file $(FUZZ_SRC) -lm
	./$(B)/fuzz_file -max_total_time=$(FUZZ_SECONDS) -max_len=65536 -artifact_prefix=$(B)/ $(B)/fuzz-corpus tests/corpus
	./$(B)/fuzz_replay tests/corpus/*

# The raster module's long run: >= 10,000 cameras against ray casting, optimised build.
$(B)/verify_raster: tests/verify_raster.c tests/test_raster.c tests/test.h tools/mesh.c tools/gen.c $(TOOL_HDR)
	@mkdir -p $(B)
	$(CC) -std=c99 $(WARN) -Werror -O2 -g -o $@ tests/verify_raster.c tests/test_raster.c tests/impl.c tools/mesh.c tools/gen.c $(LDLIBS)

# From-point culling with the occlusion tree: >= 10,000 cameras against ray casting, optimised build.
$(B)/verify_otree: tests/verify_otree.c tests/test_otree.c tests/test.h tools/mesh.c tools/gen.c $(TOOL_HDR)
	@mkdir -p $(B)
	$(CC) -std=c99 $(WARN) -Werror -O2 -g -o $@ tests/verify_otree.c tests/test_otree.c tests/impl.c tools/mesh.c tools/gen.c $(LDLIBS)

verify: tools $(B)/verify_raster $(B)/verify_otree
	sh tests/bake_hashes.sh --check
	./$(B)/verify_raster
	./$(B)/verify_otree
	sh tests/verify.sh

clean:
	rm -rf $(B)
