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
# the tests: AddressSanitizer and UndefinedBehaviorSanitizer, less its pointer-overflow check (pointer
# arithmetic wrapping the address space; ASan checks every access itself), which makes the implementation's
# build and the tests' run about a third longer. make CONFIG=sanitize builds the tools with all of it.
TEST_CFLAGS := -std=c99 -Wall -Wextra -Wshadow -Werror -O1 -g1 -fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize=pointer-overflow -fno-sanitize-recover=all

TOOL_LIB := tools/mesh.c tools/bsp.c tools/wad.c tools/obj.c tools/toolutil.c tools/gen.c tools/cli.c tools/render.c tools/pvs_impl.c
TOOL_HDR := pvs.h tools/bsp.h tools/wad.h tools/mesh.h tools/obj.h tools/toolutil.h tools/gen.h tools/cli.h tools/render.h
TOOL_OBJ := $(patsubst tools/%.c,$(B)/obj/%.o,$(TOOL_LIB))
TOOLS    := $(B)/pvsbake $(B)/pvsinfo $(B)/pvscheck $(B)/pvsgen $(B)/pvsview $(B)/pvsimport
TEST_SRC := tests/test_extproj.c tests/test_noalloc.c tests/main.c tests/test_core.c tests/test_format.c tests/test_kdtree.c \
            tests/test_gen.c tests/test_tools.c tests/test_cli.c tests/test_raster.c tests/test_otree.c \
            tests/test_shrink.c tests/test_auto.c tests/test_examples.c tests/test_vocc.c tests/test_bsp.c tests/test_wad.c tests/test_portal.c tests/test_seethrough.c tests/test_walkable.c tools/mesh.c tools/bsp.c tools/wad.c tools/obj.c tools/toolutil.c tools/gen.c tools/cli.c tools/render.c tests/fuzz_target.c

.PHONY: all tools test test-neon test-x87 test-tsan demo bench verify fuzz clean compile-checks readme-check examples cullmap-images lint bench-moc
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
# with the user's allocator and sort (no stdlib.h needed), the last also without stdio. Syntax and
# semantics only (-fsyntax-only): the tests build the code itself.
compile-checks: tests/compile_check.c pvs.h
	$(CC) -std=c99 -pedantic -Wall -Wextra -Werror -fsyntax-only tests/compile_check.c
	$(CC) -std=c11 -pedantic -Wall -Wextra -Werror -fsyntax-only tests/compile_check.c
	$(CXX) -x c++ -std=c++11 -Wall -Wextra -Werror -fsyntax-only tests/compile_check.c
	$(CC) -std=c99 -Wall -Wextra -Werror -DCHECK_STATIC -fsyntax-only tests/compile_check.c
	$(CC) -std=c99 -pedantic -Wall -Wextra -Werror -DPVS_NO_SIMD -DCHECK_HOOKS -fsyntax-only tests/compile_check.c
	$(CC) -std=c99 -pedantic -Wall -Wextra -Werror -DPVS_NO_SIMD -DPVS_NO_STDIO -DCHECK_SORT -fsyntax-only tests/compile_check.c
	$(CC) -std=c99 -pedantic -Wall -Wextra -Werror -DPVS_RUNTIME_ONLY -fsyntax-only tests/compile_check.c
	$(CXX) -x c++ -std=c++11 -pedantic -Wall -Wextra -Werror -DPVS_RUNTIME_ONLY -fsyntax-only tests/compile_check.c

# one object per source, so that make -j compiles them side by side (the two that hold a copy of the
# implementation first: they take longest). test_extproj.c's copy is the one the tests link against.
TEST_OBJ := $(patsubst %.c,$(B)/tobj/%.o,$(TEST_SRC))
$(B)/tobj/tests/test_extproj.o: TEST_CFLAGS += -DTEST_SHARED_IMPL
$(B)/tobj/%.o: %.c tests/test.h $(TOOL_HDR)
	@mkdir -p $(dir $@)
	$(CC) $(TEST_CFLAGS) -c -o $@ $<
$(B)/pvstest: $(TEST_OBJ)
	$(CC) $(TEST_CFLAGS) -o $@ $(TEST_OBJ) $(LDLIBS)

# The README's quick start (its first ```c block) must compile and print what it claims; its run-time
# snippet (the second) must compile against the API, pedantic C99.
readme-check: README.md pvs.h
	@mkdir -p $(B)
	awk '/^```c$$/ { f = 1; next } /^```$$/ { if (f) exit } f' README.md > $(B)/readme_example.c
	$(CC) -std=c99 -Wall -Wextra -Werror -I. -o $(B)/readme_example $(B)/readme_example.c -lm
	./$(B)/readme_example | grep -x 'object 0 visible, object 1 hidden'
	awk '/^```c$$/ { n++; if (n == 2) { f = 1; next } } /^```$$/ { if (f) exit } f' README.md > $(B)/readme_runtime.c
	test -s $(B)/readme_runtime.c
	$(CC) -std=c99 -pedantic -Wall -Wextra -Werror -I. -c -o $(B)/readme_runtime.o $(B)/readme_runtime.c

# the groups run side by side, one per CPU (the output does not depend on it)
# The house rules a compiler does not check: pvs.h lines within 120 columns, functions in pvs.h and tools/
# within 150 lines (tests/lint.sh).
lint:
	sh tests/lint.sh

# pvs_impl.o (the tools' copy of the implementation, ~30 s) right after the test objects, so that it compiles beside
# the tests' copy instead of after the syntax checks (make -j2 takes prerequisites in order): 65 -> 53 s of compiles
test: lint $(B)/pvstest $(B)/obj/pvs_impl.o compile-checks readme-check tools $(B)/pvsruntime $(B)/pvsdoor
	cd $(B) && ./pvstest -j 0

# NEON (not part of `make test`): the test binary built for aarch64, static, its raster group run under
# qemu-user; the SIMD and scalar paths must agree there as on x86. Skipped when the tools are missing.
AARCH64_CC ?= aarch64-linux-gnu-gcc
QEMU_AARCH64 ?= qemu-aarch64
test-neon:
	@if command -v $(AARCH64_CC) >/dev/null 2>&1 && command -v $(QEMU_AARCH64) >/dev/null 2>&1; then \
	  mkdir -p $(B)/neon && \
	  $(AARCH64_CC) -std=c99 -Wall -Wextra -Wshadow -Werror -O1 -g -static -DTEST_SHARED_IMPL -o $(B)/neon/pvstest $(TEST_SRC) $(LDLIBS) && \
	  cd $(B) && $(QEMU_AARCH64) ./neon/pvstest raster; \
	else echo "test-neon: $(AARCH64_CC) or $(QEMU_AARCH64) not found, skipped"; fi

# Excess precision (not part of `make test`): the whole suite built for 32-bit x86 with x87 arithmetic, where float and
# double expressions are evaluated in 80 bits (FLT_EVAL_METHOD 2, as 32-bit GCC builds without -mfpmath=sse), twice:
# without SSE2 (scalar raster) and with it (SSE2 raster beside x87 scalar code), against the tools of this build
# (about 7 minutes). Skipped when the compiler cannot build -m32 programs (Debian: gcc-multilib) or the kernel cannot
# run them; X87_RUN=qemu-i386 (qemu-user) runs them emulated, X87_GROUPS=format only some groups.
X87_FLAGS := -m32 -mfpmath=387 -D_FILE_OFFSET_BITS=64 -std=c99 -Wall -Wextra -Wshadow -Werror -O1 -g -DTEST_SHARED_IMPL
X87_RUN ?=
X87_GROUPS ?=
test-x87: tools $(B)/pvsruntime $(B)/pvsdoor
	@mkdir -p $(B)/x87
	@if printf 'int main(void) { return 0; }\n' > $(B)/x87/probe.c && \
	  $(CC) -m32 -o $(B)/x87/probe $(B)/x87/probe.c 2>/dev/null && $(X87_RUN) $(B)/x87/probe 2>/dev/null; then \
	  $(CC) $(X87_FLAGS) -o $(B)/x87/pvstest $(TEST_SRC) $(LDLIBS) && \
	  $(CC) $(X87_FLAGS) -msse2 -o $(B)/x87/pvstest-sse2 $(TEST_SRC) $(LDLIBS) && \
	  cd $(B) && $(X87_RUN) ./x87/pvstest -j 0 $(X87_GROUPS) && $(X87_RUN) ./x87/pvstest-sse2 -j 0 $(X87_GROUPS); \
	else echo "test-x87: $(CC) -m32 cannot build or run 32-bit programs here (gcc-multilib; X87_RUN=qemu-i386), skipped"; fi

# ThreadSanitizer (not part of `make test`): the raster group, whose frames run on two threads, and bakes on two
# threads (`auto` on a city, each other conservative method and adaptive cells on an indoor scene, pvscheck -j 2) with
# tools built under TSan in $(B)/tsan; any report fails it.
TSAN_RUN := TSAN_OPTIONS=halt_on_error=1 $(B)/tsan
test-tsan:
	@mkdir -p $(B)/tsan
	$(CC) -std=c99 -Wall -Wextra -Wshadow -Werror -O1 -g -fsanitize=thread -DTEST_SHARED_IMPL -o $(B)/tsan/pvstest \
	  $(TEST_SRC) $(LDLIBS)
	cd $(B) && TSAN_OPTIONS=halt_on_error=1 ./tsan/pvstest raster
	$(MAKE) B=$(B)/tsan CFLAGS_release="-O1 -g -fsanitize=thread" LDLIBS="$(LDLIBS) -fsanitize=thread" tools
	$(TSAN_RUN)/pvsgen city --size 0.2 --max-cells 12 -o $(B)/tsan/c.obj --cells $(B)/tsan/c.txt
	$(TSAN_RUN)/pvsgen indoor --size 0.3 --max-cells 12 -o $(B)/tsan/i.obj --cells $(B)/tsan/i.txt
	$(TSAN_RUN)/pvsbake -q $(B)/tsan/c.obj --cells $(B)/tsan/c.txt -o $(B)/tsan/c.pvs -j 2
	for m in portal otree shrink extproj vocc; do \
	  $(TSAN_RUN)/pvsbake -q $(B)/tsan/i.obj --cells $(B)/tsan/i.txt -o $(B)/tsan/i.pvs -j 2 --method $$m || exit 1; done
	$(TSAN_RUN)/pvsbake -q $(B)/tsan/i.obj --cells $(B)/tsan/i.txt -o $(B)/tsan/a.pvs -j 2 --adaptive 500
	$(TSAN_RUN)/pvscheck -q -j 2 $(B)/tsan/c.obj $(B)/tsan/c.pvs

# The examples: examples/NAME.c -> build/pvsNAME on the tool objects (demo; cullmap: per-frame culling
# of the city, images in build/cullmap/; walkthrough, forest, indoor: the demo's images). pvsruntime is
# examples/runtime_minimal.c, the runtime alone: pvs.h and libc, no tool code, no allocation (its own
# copy of the implementation, with a counting PVS_MALLOC).
$(B)/pvs%: examples/%.c examples/methods_view.h $(TOOL_OBJ) $(TOOL_HDR)
	@mkdir -p $(B)
	$(CC) $(CFLAGS) -Itools -o $@ $< $(TOOL_OBJ) $(LDLIBS)
$(B)/pvsruntime: examples/runtime_minimal.c pvs.h
	@mkdir -p $(B)
	$(CC) $(CFLAGS) -o $@ examples/runtime_minimal.c -lm

examples: $(B)/pvsdemo $(B)/pvscullmap $(B)/pvswalkthrough $(B)/pvsforest $(B)/pvsindoor $(B)/pvsdoor $(B)/pvsruntime

cullmap-images: $(B)/pvscullmap
	@mkdir -p $(B)/cullmap
	./$(B)/pvscullmap -o $(B)/cullmap

# make demo: the city baked on 2 cores (otree: see examples/demo.c), the walkthrough with its plot and
# frames, pvsview's map of the bake, the methods side by side on the forest and the indoor plan, and
# the runtime on a memory buffer. Everything lands in build/demo/.
demo: $(B)/pvsdemo $(B)/pvswalkthrough $(B)/pvsview $(B)/pvsforest $(B)/pvsindoor $(B)/pvsdoor $(B)/pvsruntime $(B)/pvsgen
	@mkdir -p $(B)/demo
	./$(B)/pvsdemo -j 2 -o $(B)/demo/city.pvs
	./$(B)/pvswalkthrough --pvs $(B)/demo/city.pvs -o $(B)/demo
	./$(B)/pvsgen city -o $(B)/demo/city.obj --cells $(B)/demo/city.cells
	./$(B)/pvsview $(B)/demo/city.obj $(B)/demo/city.pvs -o $(B)/demo/view.png --cell-at 346 1.7 388 --frame 346 1.7 388 1 -0.03 0
	./$(B)/pvsforest -o $(B)/demo
	./$(B)/pvsindoor -o $(B)/demo
	./$(B)/pvsdoor -o $(B)/demo
	./$(B)/pvsruntime $(B)/demo/city.pvs

# The benches: tests/bench_NAME.c -> build/bench_NAME on the tool objects, except bench_kdtree, which
# times the library's internals and so holds its own copy of the implementation.
BENCHES := bounded kdtree bake file raster otree extproj shrink auto vocc
$(B)/bench_%: tests/bench_%.c tests/test.h $(TOOL_OBJ) $(TOOL_HDR)
	@mkdir -p $(B)
	$(CC) $(CFLAGS) -O2 -o $@ $< $(TOOL_OBJ) $(LDLIBS)
$(B)/bench_kdtree: tests/bench_kdtree.c tests/test.h pvs.h
	@mkdir -p $(B)
	$(CC) $(CFLAGS) -O2 -o $@ tests/bench_kdtree.c $(LDLIBS)

# every bench, in the order they always ran (the walkthrough's figures between bench_auto's and bench_vocc's)
bench: $(patsubst %,$(B)/bench_%,$(BENCHES)) $(B)/pvswalkthrough tools
	@set -e; for b in $(filter-out vocc,$(BENCHES)); do echo "./$(B)/bench_$$b"; ./$(B)/bench_$$b; done
	./$(B)/pvswalkthrough --bench
	./$(B)/bench_vocc
	@printf '#define PVS_RUNTIME_ONLY\n#define PVS_IMPLEMENTATION\n#include "pvs.h"\n' > $(B)/runtime_only.c
	@$(CC) -std=c99 -O2 -I. -c -o $(B)/runtime_only.o $(B)/runtime_only.c
	@size $(B)/runtime_only.o | awk 'NR == 2 { print "BENCH runtime_text_bytes " $$1 " bytes" }'
	sh tests/bench_maps.sh
	sh tests/bench_file_ratio.sh

# Side by side with Intel's Masked Occlusion Culling (issue 31): tests/bench_moc.cpp built against a checkout of
# github.com/GameTechDev/MaskedOcclusionCulling named by MOC_DIR (outside the repository; its code is never committed
# here), every MOC path the CPU has, one process, one core. Not part of `make bench`; without MOC_DIR it says so.
MOC_FLAGS := -O2 -std=c++11 -DUSE_AVX512=1 -include tests/bench_moc_shim.h
bench-moc: tools $(TOOL_OBJ)
	@if [ -z "$(MOC_DIR)" ] || [ ! -f "$(MOC_DIR)/MaskedOcclusionCulling.h" ]; then \
	  echo "bench-moc: set MOC_DIR to a checkout of github.com/GameTechDev/MaskedOcclusionCulling"; exit 0; fi; \
	mkdir -p $(B)/moc && \
	$(CXX) $(MOC_FLAGS) -msse4.1 -c -o $(B)/moc/sse.o $(MOC_DIR)/MaskedOcclusionCulling.cpp && \
	$(CXX) $(MOC_FLAGS) -mavx2 -mfma -msse4.1 -c -o $(B)/moc/avx2.o $(MOC_DIR)/MaskedOcclusionCullingAVX2.cpp && \
	$(CXX) $(MOC_FLAGS) -mavx512f -mavx512bw -mavx512dq -mavx2 -mfma -msse4.1 -c -o $(B)/moc/avx512.o \
	  $(MOC_DIR)/MaskedOcclusionCullingAVX512.cpp && \
	$(CXX) $(MOC_FLAGS) -I$(MOC_DIR) -o $(B)/bench_moc tests/bench_moc.cpp $(B)/moc/sse.o $(B)/moc/avx2.o \
	  $(B)/moc/avx512.o $(TOOL_OBJ) $(LDLIBS) && \
	(cd $(MOC_DIR) && git log -1 --format='# MOC commit %H' 2>/dev/null || true) && \
	grep -m1 'model name' /proc/cpuinfo | sed 's/^/# /' ; ./$(B)/bench_moc

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

# The long runs of the raster module (cull maps and coverage) and of from-point culling with the
# occlusion tree: >= 10,000 cameras each against ray casting, tests/test_NAME.c's checks optimised.
$(B)/verify_%: tests/verify_%.c tests/test_%.c tests/test.h $(TOOL_OBJ) $(TOOL_HDR)
	@mkdir -p $(B)
	$(CC) -std=c99 $(WARN) -Werror -O2 -g -o $@ tests/verify_$*.c tests/test_$*.c $(TOOL_OBJ) $(LDLIBS)

# make verify: the test suite at full size first (PVSTEST_FULL=1: the checks make test runs smaller, tests/test.h)
verify: tools $(B)/pvstest $(B)/verify_raster $(B)/verify_otree $(B)/verify_extproj
	cd $(B) && PVSTEST_FULL=1 ./pvstest -j 0
	sh tests/bake_hashes.sh --check
	./$(B)/verify_raster
	./$(B)/verify_otree
	./$(B)/verify_extproj
	sh tests/verify.sh

clean:
	rm -rf $(B)
