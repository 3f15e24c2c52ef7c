// The SIMD targets of the kernels that search in lanes (lockstep.hpp, free_lanes.hpp,
// magnetic_lanes.hpp), compiled by Google Highway for each and chosen at run time, or forced by
// the environment variable BILLIARDS_SIMD=scalar|avx512|avx2|sse4|generic|auto.
#pragma once

#include <cstdint>
#include <string_view>
#include <vector>

namespace billiards::dynamics::simd {

/// Highway's targets without SIMD (EMU128, or SCALAR where the compiler cannot build it): the
/// lanes in plain C++, for the tests on any processor; `generic` in BILLIARDS_SIMD.
inline constexpr std::int64_t generic = std::int64_t(1) << 61 | std::int64_t(1) << 62;
/// No target: the scalar search.
inline constexpr std::int64_t scalar = 0;

/// A target the kernels are compiled for: its name (as BILLIARDS_SIMD spells it), Highway's bit
/// for it, and whether `auto` may choose it: only targets faster than the scalar search
/// (AVX-512 and AVX2; SSE4's two lanes a register run at half its rate: BENCHMARKS.md).
struct Target {
  const char* name;
  std::int64_t bit;
  bool automatic;
};
/// The targets compiled in, best first.
const std::vector<Target>& compiled_targets();
/// Those this processor can run, best first.
std::vector<Target> runnable_targets();
/// The target for a value of BILLIARDS_SIMD: `scalar`, none; a target's name, its bit; `auto`,
/// the best `automatic` target this processor runs, else none.  Throws InputError for any
/// other name or a target this processor cannot run.
std::int64_t target_for(std::string_view choice);
/// The target the kernels use: target_for(BILLIARDS_SIMD), `auto` where it is unset.
std::int64_t chosen_target();

}  // namespace billiards::dynamics::simd
