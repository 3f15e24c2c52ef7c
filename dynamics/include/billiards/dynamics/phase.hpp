// The phase of the periodic drive, θ = ω t + phase: its type, its reduction to [0, 2π), and
// its advance over long flights (internal to dynamics: the flights and the certified scan).
#pragma once

#include <boost/math/constants/constants.hpp>

#include <cmath>
#include <type_traits>

namespace billiards::dynamics {

/// The drive's phase θ = ω t + phase is kept reduced to [0, 2π) in a type wider than double:
/// long double for the hardware types, the reference type itself for MPFR.  A plain double
/// ω t at ω = 2560π, t = 1e4 would keep only 8 digits.
template <class Real>
using PhaseOf = std::conditional_t<std::is_floating_point_v<Real>, long double, Real>;

/// θ reduced to [0, 2π).
template <class P>
P reduce_phase(P theta) {
  using std::fmod;
  const P two_pi = boost::math::constants::two_pi<P>();
  theta = fmod(theta, two_pi);
  return theta < 0 ? P(theta + two_pi) : theta;
}

/// θ + ω τ (for set_phase to reduce), to the rounding of the phase type even when ωτ is 10¹⁰
/// (a flight of 10⁸ periods, as a particle nearly at rest can make): ωτ in the phase type
/// would keep only ~1e-10 rad there.  Beyond 2²⁰ rad, in hardware types, ωτ is split into its
/// rounding p and the exact remainder (fma), and only p is reduced (exactly, by fmod); the
/// representation error of 2π then shifts the phase by the same small multiple for every τ in
/// a period, a slightly different ω rather than noise.
template <class P, class Real>
P advance_phase(const P& theta, const Real& omega, const Real& tau) {
  if constexpr (std::is_floating_point_v<Real>) {
    using std::fma;
    const Real p = omega * tau;
    if (p < 0x1p20) return theta + P(omega) * P(tau);  // (to 1e-13 rad, as always)
    return theta + reduce_phase(P(p)) + P(fma(omega, tau, -p));
  } else {
    return theta + P(omega) * P(tau);
  }
}

}  // namespace billiards::dynamics
