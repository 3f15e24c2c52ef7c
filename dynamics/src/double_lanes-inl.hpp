// The traits of a vector of doubles, one flight per lane, for the algorithms written over
// `Lanes` (straight_exit-inl.hpp, magnetic_exit-inl.hpp), and the walls as those read them:
// included into each SIMD target's namespace by the kernel files that search in lanes
// (free_lanes_kernel.cpp, magnetic_lanes_kernel.cpp), after Highway's header and free_lanes.hpp.
// (No include guard: included once into each namespace.)

namespace hn = hwy::HWY_NAMESPACE;

using D = hn::ScalableTag<double>;  // the target's vector of doubles
using DI = hn::RebindToSigned<D>;   // and of 64-bit integers
constexpr int L = int(hn::MaxLanes(D()));
static_assert(lanes % L == 0, "the flights fill whole vectors");

/// Traits of a vector of doubles, one flight per lane.  `undecided`
/// gathers the lanes whose circle discriminant the filter could not sign: the flight is then
/// handed back to the scalar search, which decides it exactly.
struct Lanes {
  using Num = hn::Vec<D>;
  using Truth = hn::Mask<D>;
  Truth undecided;

  Lanes() : undecided(hn::FirstN(D(), 0)) {}  // (not a default initializer: made for this target)

  static constexpr bool reference = false;  // (doubles)
  static Num splat(double x) { return hn::Set(D(), x); }
  static Num never() { return splat(std::numeric_limits<double>::infinity()); }
  static Num select(Truth m, Num a, Num b) { return hn::IfThenElse(m, a, b); }
  template <class Contact>  // (ContactLanes, field by field)
  static Contact select(Truth m, const Contact& a, const Contact& b) {
    return {select(m, a.x, b.x), select(m, a.y, b.y), select(m, a.nx, b.nx), select(m, a.ny, b.ny)};
  }
  static Truth select_truth(Truth m, Truth a, Truth b) { return hn::Or(hn::And(m, a), hn::AndNot(m, b)); }
  static Truth splat_truth(bool a) { return hn::FirstN(D(), a ? L : 0); }
  static bool none(Truth m) { return hn::AllFalse(D(), m); }
  /// f() where m, else g(): both computed, no branch (a branch on the flights' truths would be
  /// as unpredictable as their data)...
  template <class F, class G>
  static auto choose(Truth m, F f, G g) {
    return pick(m, f(), g());
  }
  /// ...but a branch on a wall's truth, the same in every lane.
  template <class F, class G>
  static auto choose(bool m, F f, G g) {
    return m ? f() : g();
  }
  static Truth select_truth(bool m, Truth a, Truth b) { return m ? a : b; }
  static Truth both(bool a, Truth b) { return a ? b : hn::FirstN(D(), 0); }
  static Truth both(Truth a, Truth b) { return hn::And(a, b); }
  static Truth either(Truth a, Truth b) { return hn::Or(a, b); }
  static Truth negate(Truth a) { return hn::Not(a); }
  static Num sqrt(Num x) { return hn::Sqrt(x); }
  static Num abs(Num x) { return hn::Abs(x); }
  static Num max(Num a, Num b) { return hn::IfThenElse(a < b, b, a); }  // (std::max's order)
  static Num neg(Num a) { return hn::Neg(a); }
  /// Lanes whose D lies within its error bound are `undecided`.
  template <class Bound, class Ray, class Arc>
  Truth discriminant_positive_filtered(Truth needed, Num D_, Bound bound, const Ray&, const Arc&) {
    const Num e = bound();
    const Truth positive = D_ > e;
    undecided = either(undecided, hn::AndNot(either(positive, D_ < neg(e)), needed));
    return both(needed, positive);
  }

 private:
  static Num pick(Truth m, Num a, Num b) { return select(m, a, b); }
  static Truth pick(Truth m, Truth a, Truth b) { return select_truth(m, a, b); }
  template <class Contact>
  static Contact pick(Truth m, const Contact& a, const Contact& b) {
    return select(m, a, b);
  }
};

#include "billiards/dynamics/straight_exit-inl.hpp"

using Num = Lanes::Num;
using Truth = Lanes::Truth;
using Index = hn::Vec<DI>;

/// A segment or an arc, the same in every lane.
inline SegmentLanes<Num> lanes_of(const free_lanes::Segment& g) {
  return {Lanes::splat(g.ax), Lanes::splat(g.ay),    Lanes::splat(g.nx),    Lanes::splat(g.ny),
          Lanes::splat(g.dir_x), Lanes::splat(g.dir_y), Lanes::splat(g.slack), Lanes::splat(g.span_tol)};
}
inline ArcLanes<Num, bool> lanes_of(const free_lanes::Arc& a) {
  return {Lanes::splat(a.cx),     Lanes::splat(a.cy),   Lanes::splat(a.r),    Lanes::splat(a.r2),
          Lanes::splat(a.near),   Lanes::splat(a.span_tol), Lanes::splat(a.from_x), Lanes::splat(a.from_y),
          Lanes::splat(a.to_x),   Lanes::splat(a.to_y), a.focusing, a.full, a.half};
}
inline EllipseMapLanes<Num> lanes_of(const free_lanes::Ellipse& e) {
  return {Lanes::splat(e.cx),  Lanes::splat(e.cy),  Lanes::splat(e.l00),
          Lanes::splat(e.l01), Lanes::splat(e.l10), Lanes::splat(e.l11)};
}

/// Sets the lanes of `v` to `value` where `where`.
inline void assign_where(Truth where, std::int64_t value, Index& v) {
  v = hn::IfThenElse(hn::RebindMask(DI(), where), hn::Set(DI(), value), v);
}
