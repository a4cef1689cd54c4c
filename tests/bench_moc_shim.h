/* bench_moc_shim.h - force-included before Masked Occlusion Culling's sources by `make bench-moc`: newer GCC and
   Clang declare __cpuidex and _xgetbv in <cpuid.h> and <immintrin.h>, which MOC's CompilerSpecific.inl defines
   again. The system headers first, then MOC's definitions and uses renamed, so that MOC builds unchanged. */
#include <cpuid.h>
#include <immintrin.h>
#define __cpuidex moc_cpuidex
#define _xgetbv moc_xgetbv
