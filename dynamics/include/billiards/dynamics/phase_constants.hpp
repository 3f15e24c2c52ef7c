// The constants of the drive's phase reduction (phase.hpp), apart: the lock-step kernel
// (lockstep_kernel.cpp) reduces phases with them too, and may include no inline function.
#pragma once

namespace billiards::dynamics::phase_constants {

/// 2π = C1 + C2 + C3 (C3 leaves 6e-33 out): C1 and C2 of 25 and 24 bits, so that k·C1 and k·C2
/// are exact for |k| ≤ 2²⁶.
inline constexpr double C1 = 0x1.921fb5p+2, C2 = 0x1.110b46p-24, C3 = 0x1.1a62633145c07p-52;
/// 2π and 1/2π rounded to double.
inline constexpr double two_pi = 0x1.921fb54442d18p+2, inv_two_pi = 0x1.45f306dc9c883p-3;
/// Phases reduced by the three parts: below 2²⁶·2π (MPFR beyond).
inline constexpr double fast_limit = 0x1p26 * two_pi;
/// Veltkamp's splitting factor 2²⁷ + 1 (Dekker's product).
inline constexpr double split = 134217729.0;

}  // namespace billiards::dynamics::phase_constants
