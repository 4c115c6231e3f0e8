#pragma once
// VTS_SIMD_CLONES before a function definition: with GCC on x86-64, the
// function is also built for AVX2 (x86-64-v3) and AVX-512 (x86-64-v4), and
// the dynamic loader picks the best the CPU has (target_clones). Only for
// loops written to vectorize; the files holding them are built without FMA
// contraction (see their CMakeLists.txt), so every clone gives the same bits.
// Off under AddressSanitizer and with other compilers: plain functions.
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__) && !defined(__SANITIZE_ADDRESS__)
#define VTS_SIMD_CLONES __attribute__((target_clones("default", "arch=x86-64-v3", "arch=x86-64-v4")))
#else
#define VTS_SIMD_CLONES
#endif
