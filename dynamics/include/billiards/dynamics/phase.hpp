// The phase of the periodic drive, θ = ω t + phase: its type, its reduction to [0, 2π), its
// advance over long flights, its sine and cosine, and its samples in a root search (internal to
// dynamics: the driven flights).
#pragma once

#include "billiards/dynamics/phase_constants.hpp"
#include "billiards/dynamics/state.hpp"

#include <boost/math/constants/constants.hpp>

#include <cmath>
#include <type_traits>
#include <utility>

namespace billiards::dynamics {

/// The drive's phase θ = ω t + phase of a flight in double: the unevaluated sum hi + lo of two
/// doubles (106 bits), kept reduced to [0, 2π) between flights.  A plain double ω t at
/// ω = 2560π, t = 1e4 would keep only 8 digits.  Its arithmetic is a dozen double operations:
/// the long double it replaces put x87 arithmetic, and values moved between x87 and SSE
/// registers through memory, on the chain from one collision to the next (~10% of a driven
/// clover collision, BENCHMARKS.md).
struct Phase {
  double hi = 0, lo = 0;
  constexpr Phase() = default;
  constexpr Phase(double x) : hi(x) {}
  constexpr Phase(double h, double l) : hi(h), lo(l) {}
  /// θ rounded to double.
  explicit constexpr operator double() const { return hi + lo; }
};
/// a − b, unnormalized (PhaseSample's shift from a sampled phase to the precise one).
inline Phase operator-(const Phase& a, const Phase& b) {
  const auto d = detail::phase_difference<double>({a.hi, a.lo}, {b.hi, b.lo});
  return {d.hi, d.lo};
}

/// The phase's type for a flight in Real: Phase for double, long double for long double, the
/// type itself for MPFR.
template <class Real>
using PhaseOf = std::conditional_t<std::is_same_v<Real, double>, Phase,
                                   std::conditional_t<std::is_floating_point_v<Real>, long double, Real>>;

namespace detail {
/// reduce_phase beyond 2²⁶·2π, in MPFR (phase.cpp): reached by flights of more than 6·10⁷
/// periods and starts at ω t > 4·10⁸.
Phase reduce_phase_mpfr(const Phase& theta);
}  // namespace detail

/// θ reduced to [0, 2π) (to rounding), within 1e-23 rad of the exact remainder of hi + lo
/// below phase_constants::fast_limit (drive_phase-inl.hpp's three-part reduction); beyond, and for
/// non-finite θ, MPFR.
inline Phase reduce_phase(const Phase& theta) {
  if (!(std::abs(theta.hi) < phase_constants::fast_limit)) return detail::reduce_phase_mpfr(theta);
  const auto r = detail::reduce_phase_below_limit<detail::Doubles>({theta.hi, theta.lo});
  return {r.hi, r.lo};
}

/// θ reduced to [0, 2π) in long double (the flights in long double) and in MPFR.  In long
/// double below 2²⁴·2π, θ − k·2π with 2π in two parts, the first of 40 bits so that k·2π₁ and
/// the difference are exact: as accurate as fmod (more: fmod reduces by 2π rounded to 64
/// bits), without the x87 remainder loop.  k is truncated in double (an x87 truncation
/// switches the rounding mode twice); it may be off by one when θ is within 1e-8 of a multiple
/// of 2π, which the last step puts right.
template <class P>
P reduce_phase(P theta) {
  using std::abs;
  using std::fmod;
  const P two_pi = boost::math::constants::two_pi<P>();
  if constexpr (std::is_same_v<P, long double>) {
    if (abs(theta) < 0x1p24L * two_pi) {
      constexpr long double two_pi_1 = 0x1.921fb54442p+2L, two_pi_2 = 0xd18469898cc51702p-102L;
      const long double k = static_cast<long double>(static_cast<long long>(double(theta) * 0.15915494309189535));
      theta = (theta - k * two_pi_1) - k * two_pi_2;
      return theta < 0 ? P(theta + two_pi) : theta >= two_pi ? P(theta - two_pi) : theta;
    }
  }
  theta = fmod(theta, two_pi);
  return theta < 0 ? P(theta + two_pi) : theta;
}

/// θ + ω τ, not reduced (set_phase reduces it), exact in Phase: ω τ as its rounding and its
/// exact error.  A flight of 10⁸ periods (as a particle nearly at rest can make) has ω τ ~ 10⁹.
inline Phase advance_phase(const Phase& theta, double omega, double tau) {
  const auto r = detail::advance_phase<detail::Doubles>({theta.hi, theta.lo}, omega, tau);
  return {r.hi, r.lo};
}

/// The same in long double, to its rounding even when ωτ is 10¹⁰: ωτ in long double would keep
/// only ~1e-10 rad there.  Beyond 2²⁰ rad ωτ is split into its rounding p and the exact
/// remainder (fma), and only p is reduced (exactly, by fmod); the representation error of 2π
/// then shifts the phase by the same small multiple for every τ in a period, a slightly
/// different ω rather than noise.  In MPFR, at its precision.
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

/// The amplitudes of the drive's oscillation in position and velocity, F/(mω²) and F/(mω),
/// from `accel` = F/m, with one division: every driven flight, its scan and its advance use
/// these same numbers, so that a root found by the scan is where the advance puts the particle.
template <class V, class Real>
std::pair<V, V> drive_amplitudes(const V& accel, const Real& omega) {
  const Real inv = 1 / omega;
  const V amp_v = accel * inv;
  return {V(amp_v * inv), amp_v};
}

/// sin θ and cos θ of a drive's phase, the one transcendental function of a driven flight's
/// hot path (each sample of a root search).  For double and |θ| < 2¹⁹π, fdlibm's reduction and
/// kernels (drive_phase-inl.hpp): a third of the cost of glibc's sincos, which reduces through a
/// table (measured with callgrind: 142 instructions a call on a driven clover).  Other types
/// and larger θ: std.
template <class Real>
std::pair<Real, Real> sin_cos(const Real& theta) {
  using std::abs;
  using std::cos;
  using std::sin;
  if constexpr (std::is_same_v<Real, double>) {
    if (abs(theta) < 0x1p19 * 3.14159265358979311600) {
      const auto r = detail::sin_cos_below_limit<detail::Doubles>(theta);
      return {r.sin, r.cos};
    }
  }
  return {sin(theta), cos(theta)};
}

/// The drive's phase θ (as computed in Real, not reduced) and its sine and cosine at one
/// sample of a root search: the state at the root, a polishing step away, is had from them
/// without another sine and cosine.  (Not for creeping flights, whose samples reduce θ.)
template <class Real>
struct PhaseSample {
  Real theta = never, sin = 0, cos = 1;
  /// The farthest shift `shifted` serves.
  static constexpr double h_max = 0.05;
  bool known() const { return theta != never; }
  /// Is the phase `precise` (in the phase type) within h_max of θ, not reduced?  (A flight of
  /// 2²⁰ rad and more has its phase partly reduced by advance_phase.)
  bool near(const PhaseOf<Real>& precise) const {
    using std::abs;
    return abs(Real(precise - PhaseOf<Real>(theta))) <= Real(h_max);
  }
  /// sin and cos of `precise` (θ + h, near θ): which corrects the last step of a root search
  /// and the rounding of θ in Real.
  std::pair<Real, Real> at(const PhaseOf<Real>& precise) const { return shifted(Real(precise - PhaseOf<Real>(theta))); }
  /// sin and cos of θ + h, |h| ≤ h_max, by the angle-sum formulas (drive_phase-inl.hpp).
  std::pair<Real, Real> shifted(const Real& h) const {
    const auto r = detail::shifted<ScalarLanes<Real>>(detail::SinCos<Real>{sin, cos}, h);
    return {r.sin, r.cos};
  }
};


}  // namespace billiards::dynamics
