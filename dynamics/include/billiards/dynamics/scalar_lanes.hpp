// The traits of one number (double, long double or MPFR) for the algorithms written over a
// `Lanes` traits class (straight_exit-inl.hpp, magnetic_exit-inl.hpp, drive_phase-inl.hpp,
// driven_exit-inl.hpp): the scalar searches run them in one number, the SIMD kernels in a
// vector of doubles, one flight per lane.
#pragma once

#include "billiards/dynamics/predicates.hpp"

#include <boost/math/constants/constants.hpp>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <type_traits>

namespace billiards::dynamics {

/// Traits of one number: the scalar search in Real.  The discriminant's sign is filtered in
/// double (exact rationals where its error bound cannot decide) and taken as computed in a
/// reference type, whose own precision decides it.
template <class Real>
struct ScalarLanes {
  using Num = Real;
  using Truth = bool;
  static Num splat(double x) { return Num(x); }
  /// a/b rounded once in Num (a series' coefficient: in MPFR at its precision, not double's).
  static Num fraction(int a, int b) { return Num(Num(a) / b); }
  static Num never() { return Num(std::numeric_limits<double>::infinity()); }
  static Num eps() { return std::numeric_limits<Real>::epsilon(); }
  static Num two_pi() { return boost::math::constants::two_pi<Real>(); }
  static Num select(bool m, const Num& a, const Num& b) { return m ? a : b; }
  static bool select_truth(bool m, bool a, bool b) { return m ? a : b; }
  static bool splat_truth(bool a) { return a; }
  static bool none(bool m) { return !m; }
  /// f() where m, else g(): a branch.
  template <class F, class G>
  static auto choose(bool m, F f, G g) {
    return m ? f() : g();
  }
  static bool both(bool a, bool b) { return a && b; }
  static bool either(bool a, bool b) { return a || b; }
  static bool negate(bool a) { return !a; }
  static Num sqrt(const Num& x) {
    using std::sqrt;
    return sqrt(x);
  }
  static Num abs(const Num& x) {
    using std::abs;
    return abs(x);
  }
  static Num max(const Num& a, const Num& b) { return std::max(a, b); }
  static Num min(const Num& a, const Num& b) { return std::min(a, b); }
  /// A reference type (long double, MPFR) computes with its own functions, at its precision.
  static constexpr bool reference = !std::is_same_v<Real, double>;
  static Num atan2(const Num& y, const Num& x) {
    using std::atan2;
    return Num(atan2(y, x));
  }
  static Num neg(const Num& a) { return -a; }
  /// x truncated toward zero, |x| < 2⁶³ (double).
  static double trunc(double x) { return double(static_cast<long long>(x)); }
  /// sin and cos of qπ/2 + x from s = sin x and c = cos x, q = k an integer (double): swapped
  /// when q is odd, negated by the quadrant.  Selected with bit masks, not branches: q is as
  /// good as random from one sample to the next, and gcc compiled the conditional expressions
  /// into three jumps that the processor mispredicted half the time.
  static void to_quadrant(double k, double& s, double& c) {
    const auto q = std::uint64_t(static_cast<long>(k));
    const auto sb = std::bit_cast<std::uint64_t>(s), cb = std::bit_cast<std::uint64_t>(c);
    const std::uint64_t odd = -(q & 1);  // all ones when q is odd
    const std::uint64_t sq = (sb & ~odd) | (cb & odd), cq = (cb & ~odd) | (sb & odd);
    // (Bit 1 of q, and of q + 1, moved to the sign bit.)
    s = std::bit_cast<double>(sq ^ ((q & 2) << 62));
    c = std::bit_cast<double>(cq ^ (((q + 1) & 2) << 62));
  }
  /// Is the discriminant D of the ray against the arc's circle (or a 3-D ray against the
  /// sphere) positive (a crossing)?  Asked only where `needed`.  In double the value decides
  /// unless it lies within its forward error bound; then the exact sign (GMP).  A reference
  /// type's own precision decides.
  template <class Bound, class Ray, class Arc>
  bool discriminant_positive_filtered(bool needed, const Num& D, Bound bound, const Ray& s, const Arc& w) const {
    if (!needed) return false;
    if constexpr (std::is_same_v<Real, double>) {
      const double e = bound();
      if (D > e) return true;
      if (D < -e) return false;
      if constexpr (requires { s.z; })  // a 3-D ray and a sphere
        return sphere_discriminant_sign_exact(Eigen::Vector3d(s.x, s.y, s.z), Eigen::Vector3d(w.cx, w.cy, w.cz),
                                              Eigen::Vector3d(s.vx, s.vy, s.vz), w.r) > 0;
      else
        return circle_discriminant_sign_exact(Vec2(s.x, s.y), Vec2(w.cx, w.cy), Vec2(s.vx, s.vy), w.r) > 0;
    } else {
      return D > 0;
    }
  }
};

}  // namespace billiards::dynamics
