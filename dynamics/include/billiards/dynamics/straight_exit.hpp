// The exit time of a straight flight through a segment or a circular arc in a scalar type:
// straight_exit-inl.hpp's algorithms, with the traits of one number.
#pragma once

#include "billiards/dynamics/predicates.hpp"
#include "billiards/dynamics/state.hpp"

#include <algorithm>
#include <cmath>
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
  static Num never() { return Num(dynamics::never); }
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
  /// A reference type (long double, MPFR) computes with its own functions, at its precision.
  static constexpr bool reference = !std::is_same_v<Real, double>;
  static Num atan2(const Num& y, const Num& x) {
    using std::atan2;
    return Num(atan2(y, x));
  }
  static Num neg(const Num& a) { return -a; }
  /// Is the discriminant D of the ray against the arc's circle positive (a crossing)?  Asked
  /// only where `needed`.  In double the value decides unless it lies within its forward error
  /// bound; then the exact sign (GMP).  A reference type's own precision decides.
  template <class Bound, class Ray, class Arc>
  bool discriminant_positive_filtered(bool needed, const Num& D, Bound bound, const Ray& s, const Arc& w) const {
    if (!needed) return false;
    if constexpr (std::is_same_v<Real, double>) {
      const double e = bound();
      if (D > e) return true;
      if (D < -e) return false;
      return circle_discriminant_sign_exact(Vec2(s.x, s.y), Vec2(w.cx, w.cy), Vec2(s.vx, s.vy), w.r) > 0;
    } else {
      return D > 0;
    }
  }
};

#include "billiards/dynamics/straight_exit-inl.hpp"

}  // namespace billiards::dynamics
