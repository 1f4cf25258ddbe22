#pragma once
// Whether this build carries the AVX-512 kernels (products in batch.cpp, gate functions in
// gates.cpp), and the attribute that compiles one function for that target whatever the build's
// -march. Internal to gesture/nn's .cpp files.
//
// The AVX-512 kernels are compiled for that target and chosen at run time (GCC and Clang on
// x86-64), in builds whose own kernels are fused multiply-adds (-march with FMA, as release builds
// are): they compute the same operations, so the same bits. A build without FMA (the sanitizer
// builds, which take no -march) multiplies and adds separately, with other bits, and keeps its own
// kernels only.

#if defined(__x86_64__) && defined(__FMA__) && (defined(__GNUC__) || defined(__clang__))
#define DEIXIS_AVX512_KERNEL 1
#define DEIXIS_AVX512_TARGET __attribute__((target("avx512f")))
#else
#define DEIXIS_AVX512_KERNEL 0
#endif
