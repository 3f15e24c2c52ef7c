#include "simd_targets.hpp"  // (first: the targets compiled)

#include "billiards/dynamics/simd.hpp"
#include "billiards/geometry/input_error.hpp"

#include <hwy/targets.h>

#include <cstdlib>
#include <string>

static_assert(billiards::dynamics::simd::generic == (HWY_EMU128 | HWY_SCALAR));

namespace billiards::dynamics::simd {

const std::vector<Target>& compiled_targets() {
  static const std::vector<Target> targets = [] {
    const Target all[] = {{"avx512", HWY_AVX3, true}, {"avx2", HWY_AVX2, true}, {"sse4", HWY_SSE4, false}};
    std::vector<Target> compiled;
    for (const Target& t : all)
      if (HWY_TARGETS & t.bit) compiled.push_back(t);
    if (HWY_TARGETS & generic) compiled.push_back({"generic", generic, false});
    return compiled;
  }();
  return targets;
}

std::vector<Target> runnable_targets() {
  std::vector<Target> runnable;
  const std::int64_t supported = hwy::SupportedTargets();
  for (const Target& t : compiled_targets())
    if (supported & t.bit) runnable.push_back(t);
  return runnable;
}

std::int64_t target_for(std::string_view choice) {
  if (choice == "scalar") return scalar;
  const std::vector<Target> runnable = runnable_targets();
  if (choice == "auto") {
    for (const Target& t : runnable)
      if (t.automatic) return t.bit;
    return scalar;
  }
  std::string names, runs;
  for (const Target& t : compiled_targets()) {
    names += std::string(t.name) + ", ";
    if (t.name != choice) continue;
    for (const Target& r : runnable) {
      if (r.name == choice) return r.bit;
      runs += std::string(runs.empty() ? "" : ", ") + r.name;
    }
    throw InputError("BILLIARDS_SIMD", 0, "'" + std::string(choice) + "': this processor cannot run it (it runs " + runs +
                                              ", scalar or auto)");
  }
  throw InputError("BILLIARDS_SIMD", 0, "'" + std::string(choice) + "': expected scalar, " + names + "or auto");
}

std::int64_t chosen_target() {
  static const std::int64_t target = [] {
    const char* env = std::getenv("BILLIARDS_SIMD");
    return target_for(env ? env : "auto");
  }();
  return target;
}

}  // namespace billiards::dynamics::simd
