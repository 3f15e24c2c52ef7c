// The SIMD targets every kernel file compiles for (lockstep_kernel.cpp, free_lanes_kernel.cpp,
// magnetic_lanes_kernel.cpp, bvh_lanes_kernel.cpp), and that simd.cpp lists: included before
// Highway's headers, so that all agree; and how a kernel file names its kernel for each.
//
// Targets left out: sizeless vectors (SVE, RVV) cannot be members of the lock-step kernel's
// Pack; NEON's vectors have constructors that GCC 12 will not inline into a Pack's implicit one
// (a build error), and leave `Pack{}` unset where the lanes need zeros; SSSE3 (no 64-bit
// comparison) and AVX3_DL (nothing more for doubles than AVX-512) would only lengthen the build.
#pragma once

#ifndef HWY_DISABLED_TARGETS
#define HWY_DISABLED_TARGETS \
  (HWY_SSSE3 | HWY_AVX3_DL | HWY_NEON | HWY_SVE | HWY_SVE2 | HWY_SVE_256 | HWY_SVE2_128 | HWY_RVV)
#endif

/// The body of a kernel file's `kernel_of(target)` (in its HWY_ONCE part): FN as compiled for
/// that target (simd.hpp's bits), nullptr for simd::scalar.
#define BILLIARDS_KERNEL_OF(target, FN)                            \
  switch (target) {                                               \
    case HWY_AVX3: return HWY_CHOOSE_AVX3(FN);                    \
    case HWY_AVX2: return HWY_CHOOSE_AVX2(FN);                    \
    case HWY_SSE4: return HWY_CHOOSE_SSE4(FN);                    \
    case HWY_EMU128 | HWY_SCALAR: return HWY_CHOOSE_FALLBACK(FN); \
    default: return nullptr;                                      \
  }
