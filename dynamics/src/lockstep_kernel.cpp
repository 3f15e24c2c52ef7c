// The lock-step search of driven flights (lockstep.hpp), compiled once for each SIMD target of
// Google Highway: hwy/foreach_target.h includes this file again for each (SSE4, AVX2 and
// AVX-512 on x86-64, and EMU128 or SCALAR, plain C++, everywhere), each in its own namespace;
// lockstep.cpp chooses one at run time.  A call searches sixteen flights (lockstep::lanes): in
// W = 16 lanes on AVX-512 (two vectors of eight), and eight at a time elsewhere (AVX2: two
// vectors of four), where sixteen lanes would overflow the target's registers (BENCHMARKS.md,
// driven clover on Zen 3).
//
// The search's arithmetic is the scalar search's own source, with the traits of W lanes
// (PackLanes): drive_phase-inl.hpp (the phase's advance and reduction, its sine and cosine and
// their shift), driven_exit-inl.hpp (the guide's numbers, creeping, SphereGap's numbers,
// windows, sign of f' and Taylor samples, the span test of a window, monotone_crossing's
// Halley step and certain landing, and the drive's motion: the guide, Quiver's position and
// velocity, the hit's state as PeriodicDriveFlight::advance makes it) and
// straight_exit-inl.hpp (the span test of a point, the hit's contact point and normal).  This
// file holds what differs: the rounds in which each lane chooses its next window or steps its
// root search (first_hit_in_windows and monotone_crossing's loops, branches become
// selections) and the walls and flights in lanes.  A lane leaves the search
// (`handed_back`) wherever the scalar search would take a path not run here.  The lanes use
// only Highway's operations that round as IEEE (no fused multiply-add: -ffp-contract=off keeps
// the compiler from fusing them either), builtins and the functions of the files above and this
// one (no std:: function and no Eigen, whose inline functions would be compiled for one target
// and linked for all).

#include "simd_targets.hpp"  // (first: the targets compiled)
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "lockstep_kernel.cpp"
#include <hwy/foreach_target.h>  // (this file, once per target)
#include <hwy/highway.h>

#include "billiards/dynamics/lockstep.hpp"
#include "billiards/dynamics/lockstep_lanes.hpp"
#include "billiards/dynamics/phase_constants.hpp"

#include <cstdint>
#include <type_traits>  // (std::is_arithmetic_v: no code)

#pragma GCC diagnostic ignored "-Wpsabi"  // (vectors passed by value: inlined throughout)

HWY_BEFORE_NAMESPACE();
namespace billiards::dynamics::lockstep::HWY_NAMESPACE {

namespace {

namespace hn = hwy::HWY_NAMESPACE;

using D = hn::ScalableTag<double>;       // the target's vector of doubles
using DI = hn::RebindToSigned<D>;        // and of 64-bit integers
constexpr int L = int(hn::MaxLanes(D()));
constexpr int W = L >= 8 ? lanes : lanes / 2;  // lanes searched together
static_assert(lanes % W == 0 && W % L == 0 && L <= max_walls && max_walls % L == 0,
              "a Pack is whole vectors, a call's flights whole Packs; a table's walls fill one or more vectors");
constexpr int K = W / L;           // vectors in a Pack
constexpr int KW = max_walls / L;  // vectors of a table's field

// Every function here is inlined: a Pack passed to a call costs more than most of them (and
// GCC inlines a function of Highway's vectors less readily than one of its own vector types).
#define LANES [[gnu::always_inline]] inline
#define LANES_LAMBDA __attribute__((always_inline))
// ...except the two halves of a round (Lanes::choose and Lanes::step), each a few hundred
// operations on lanes: inlined into one loop, GCC allocates registers for both at once and
// spills more; called, each half has the registers to itself.
#define ROUND_PART [[gnu::noinline]]
#define EACH_VECTOR _Pragma("GCC unroll 16") for (int k = 0; k < K; ++k)

/// W lanes in K vectors (or N: a table's fields), every operation issued for each vector one
/// after the other: the chains of dependent operations (a round of the search is one) overlap
/// in the processor.
template <class V, int N = K>
struct Parts {
  V v[N];
};
using VD = hn::Vec<D>;
using VI = hn::Vec<DI>;
using Pack = Parts<VD>;
/// W 64-bit integers: lane indices, counters, and truth values (−1 true, 0 false, as
/// the comparisons of C's vector extensions make them).
using Mask = Parts<VI>;
/// f of each vector of x.
template <class R, class V, class F>
LANES Parts<R> each(Parts<V> x, F f) {
  Parts<R> r;
  EACH_VECTOR r.v[k] = f(x.v[k]);
  return r;
}

template <class S>
concept Scalar = std::is_arithmetic_v<S>;
template <class V>
LANES Parts<V> splat_as(hn::TFromV<V> x) {
  Parts<V> r;
  EACH_VECTOR r.v[k] = hn::Set(hn::DFromV<V>(), x);
  return r;
}
LANES Pack splat(double x) { return splat_as<VD>(x); }
/// A comparison's result in lanes: −1 or 0.
template <class M, class V>
LANES VI truth(M m, V) {
  return hn::BitCast(DI(), hn::VecFromMask(hn::DFromV<V>(), m));
}

#define LANES_ARITHMETIC(op)                                                          \
  template <class V>                                                                 \
  LANES Parts<V> operator op(Parts<V> x, Parts<V> y) {                               \
    Parts<V> r;                                                                      \
    EACH_VECTOR r.v[k] = x.v[k] op y.v[k];                                           \
    return r;                                                                        \
  }                                                                                  \
  template <class V, Scalar S>                                                       \
  LANES Parts<V> operator op(Parts<V> x, S y) { return x op splat_as<V>(hn::TFromV<V>(y)); } \
  template <class V, Scalar S>                                                       \
  LANES Parts<V> operator op(S x, Parts<V> y) { return splat_as<V>(hn::TFromV<V>(x)) op y; }
LANES_ARITHMETIC(+)
LANES_ARITHMETIC(-)
LANES_ARITHMETIC(*)
LANES_ARITHMETIC(/)
LANES_ARITHMETIC(&)
LANES_ARITHMETIC(|)
LANES_ARITHMETIC(^)
#undef LANES_ARITHMETIC
// Comparisons as C's: false where an operand is NaN, except != (true there).  On x86, GCC's
// vector comparisons and selections on Highway's registers: from them GCC keeps a comparison's
// result in a mask register up to the selection (AVX-512), where Highway's VecFromMask and
// MaskFromVec, opaque to it, convert to a vector and back on the search's critical path (the
// kernel was 15-40% slower).  Elsewhere Highway's (whose != is false on NaN: ~(x == y) here).
#if HWY_ARCH_X86 && HWY_TARGET != HWY_EMU128 && HWY_TARGET != HWY_SCALAR
#define LANES_COMPARISON(op, lane)                                            \
  template <class V>                                                         \
  LANES Mask operator op(Parts<V> x, Parts<V> y) {                           \
    Mask r;                                                                  \
    EACH_VECTOR r.v[k].raw = decltype(r.v[k].raw)(x.v[k].raw op y.v[k].raw); \
    return r;                                                                \
  }                                                                          \
  template <class V, Scalar S>                                               \
  LANES Mask operator op(Parts<V> x, S y) { return x op splat_as<V>(hn::TFromV<V>(y)); }
#define LANES_SELECT(m, a, b) r.v[k].raw = m.v[k].raw ? a.v[k].raw : b.v[k].raw
#else
template <class V>
LANES auto at_least(V a, V b) {
  if constexpr (hwy::IsFloat<hn::TFromV<V>>())
    return a >= b;
  else
    return hn::Not(a < b);  // (on doubles, not the same: NaN)
}
#define LANES_COMPARISON(op, lane)                                                    \
  template <class V>                                                                 \
  LANES Mask operator op(Parts<V> x, Parts<V> y) {                                   \
    Mask r;                                                                          \
    EACH_VECTOR {                                                                    \
      const V a = x.v[k], b = y.v[k];                                                \
      r.v[k] = lane;                                                                 \
    }                                                                                \
    return r;                                                                        \
  }                                                                                  \
  template <class V, Scalar S>                                                       \
  LANES Mask operator op(Parts<V> x, S y) { return x op splat_as<V>(hn::TFromV<V>(y)); }
#define LANES_SELECT(m, a, b) \
  r.v[k] = hn::IfThenElse(hn::MaskFromVec(hn::BitCast(hn::DFromV<V>(), m.v[k])), a.v[k], b.v[k])
#endif
LANES_COMPARISON(<, truth(a < b, a))
LANES_COMPARISON(>, truth(b < a, a))
LANES_COMPARISON(==, truth(a == b, a))
LANES_COMPARISON(!=, hn::Xor(truth(a == b, a), hn::Set(DI(), -1)))
LANES_COMPARISON(<=, truth(at_least(b, a), a))
LANES_COMPARISON(>=, truth(at_least(a, b), a))
#undef LANES_COMPARISON
template <class V>
LANES Parts<V> operator-(Parts<V> x) {
  return each<V>(x, [](V v) LANES_LAMBDA { return hn::Neg(v); });
}
// (x ^ −1, not hn::Not: GCC sees through the xor, and makes x & ~y one and-not.)
LANES Mask operator~(Mask x) { return x ^ -1; }
LANES Mask operator<<(Mask x, int bits) {
  return each<VI>(x, [bits](VI v) LANES_LAMBDA { return hn::ShiftLeftSame(v, bits); });
}
LANES Mask operator>>(Mask x, int bits) {
  return each<VI>(x, [bits](VI v) LANES_LAMBDA { return hn::ShiftRightSame(v, bits); });
}
LANES Mask& operator&=(Mask& x, Mask y) { return x = x & y; }
LANES Mask& operator|=(Mask& x, Mask y) { return x = x | y; }

constexpr double inf = __builtin_inf();

// ---- Lanes ---------------------------------------------------------------------------------

template <class T>
LANES Parts<hn::Vec<hn::Rebind<T, D>>> load_as(const T* x) {
  Parts<hn::Vec<hn::Rebind<T, D>>> r;
  EACH_VECTOR r.v[k] = hn::LoadU(hn::Rebind<T, D>(), x + k * L);
  return r;
}
LANES Pack load(const double* x) { return load_as(x); }
LANES Mask load_mask(const std::int64_t* x) { return load_as(x); }
LANES void store(double* x, Pack p) { EACH_VECTOR hn::StoreU(p.v[k], D(), x + k * L); }
/// A table's field (max_walls entries, in KW vectors), for `pick`.
template <class T>
LANES Parts<hn::Vec<hn::Rebind<T, D>>, KW> load_walls(const T* x) {
  Parts<hn::Vec<hn::Rebind<T, D>>, KW> r;
  for (int k = 0; k < KW; ++k) r.v[k] = hn::LoadU(hn::Rebind<T, D>(), x + k * L);
  return r;
}
/// The vectors of load_walls that `pick` looks in: those that hold the first half of
/// max_walls (a table of so few walls), or all.
template <int n>
using WallVectors = std::integral_constant<int, n>;
using HalfWallVectors = WallVectors<max_walls / 2 / L>;
using AllWallVectors = WallVectors<max_walls / L>;
/// Each lane's values, to be read one by one.
template <class T>
struct Values {
  T x[W];
  T operator[](int i) const { return x[i]; }
};
template <class V>
LANES Values<hn::TFromV<V>> values(Parts<V> p) {
  Values<hn::TFromV<V>> r;
  EACH_VECTOR hn::StoreU(p.v[k], hn::DFromV<V>(), r.x + k * L);
  return r;
}
template <class V>
LANES Parts<V> sel(Mask m, Parts<V> a, Parts<V> b) {
  Parts<V> r;
  EACH_VECTOR LANES_SELECT(m, a, b);
  return r;
}
LANES bool any(Mask m) {
  VI r = m.v[0];
  for (int k = 1; k < K; ++k) r = r | m.v[k];
  return !hn::AllFalse(DI(), hn::MaskFromVec(r));
}
LANES Pack abs(Pack x) { return each<VD>(x, [](VD v) LANES_LAMBDA { return hn::Abs(v); }); }
LANES Pack sqrt(Pack x) { return each<VD>(x, [](VD v) LANES_LAMBDA { return hn::Sqrt(v); }); }
/// Truncated to integers (as C converts; exact for integers below 2⁵²).
LANES Mask to_long(Pack x) { return each<VI>(x, [](VD v) LANES_LAMBDA { return hn::ConvertTo(DI(), v); }); }
LANES Pack to_double(Mask x) { return each<VD>(x, [](VI v) LANES_LAMBDA { return hn::ConvertTo(D(), v); }); }
/// A double's bits, and back.
LANES Mask bits(Pack x) { return each<VI>(x, [](VD v) LANES_LAMBDA { return hn::BitCast(DI(), v); }); }
LANES Pack from_bits(Mask x) { return each<VD>(x, [](VI v) LANES_LAMBDA { return hn::BitCast(D(), v); }); }
/// std::max(a, b) and std::min(a, b), as the scalar code has them: (a < b) ? b : a, (b < a) ? b : a.
LANES Pack max(Pack a, Pack b) { return sel(a < b, b, a); }
LANES Pack min(Pack a, Pack b) { return sel(b < a, b, a); }
/// A table's field (load_walls, its walls in the first `vectors`) for each lane's wall index
/// (taken modulo max_walls; an index beyond the table's walls reads a padding wall or any wall).
template <class V, int vectors>
LANES Parts<V> pick(const Parts<V, KW>& table, Mask index, WallVectors<vectors>) {
  const hn::DFromV<V> d;
  Parts<V> r;
  EACH_VECTOR {
    const VI i = hn::And(index.v[k], hn::Set(DI(), max_walls - 1));
    const auto lane = hn::IndicesFromVec(d, hn::And(i, hn::Set(DI(), L - 1)));
    r.v[k] = hn::TableLookupLanes(table.v[0], lane);
    for (int j = 1; j < vectors; ++j)  // (the vector that holds entry i)
      r.v[k] = hn::IfThenElse(hn::RebindMask(d, hn::Set(DI(), j * L - 1) < i), hn::TableLookupLanes(table.v[j], lane), r.v[k]);
  }
  return r;
}
LANES Pack cross(Pack ax, Pack ay, Pack bx, Pack by) { return ax * by - ay * bx; }

// ---- The traits of W lanes, and the scalar search's own source -----------------------------

/// The traits of a Pack for the algorithms written over `Lanes` (straight_exit-inl.hpp,
/// drive_phase-inl.hpp, driven_exit-inl.hpp): one flight per lane, branches as selections.
struct PackLanes {
  using Num = Pack;
  using Truth = Mask;
  LANES static Pack splat(double x) { return ::billiards::dynamics::lockstep::HWY_NAMESPACE::splat(x); }
  LANES static Pack fraction(int a, int b) { return splat(double(a) / b); }
  LANES static Pack never() { return splat(inf); }
  LANES static Pack eps() { return splat(0x1p-52); }
  LANES static Pack two_pi() { return splat(6.28318530717958647692); }
  LANES static Pack select(Mask m, Pack a, Pack b) { return sel(m, a, b); }
  LANES static Mask select_truth(Mask m, Mask a, Mask b) { return sel(m, a, b); }
  LANES static Mask splat_truth(bool a) { return a ? ~Mask{} : Mask{}; }
  LANES static bool none(Mask m) { return !any(m); }
  template <class F, class G>
  LANES static auto choose(Mask m, F f, G g) {
    return sel(m, f(), g());
  }
  template <class F, class G>
  LANES static auto choose(bool m, F f, G g) {
    return m ? f() : g();
  }
  LANES static Mask both(Mask a, Mask b) { return a & b; }
  LANES static Mask either(Mask a, Mask b) { return a | b; }
  LANES static Mask negate(Mask a) { return ~a; }
  LANES static Pack sqrt(Pack x) { return ::billiards::dynamics::lockstep::HWY_NAMESPACE::sqrt(x); }
  LANES static Pack abs(Pack x) { return ::billiards::dynamics::lockstep::HWY_NAMESPACE::abs(x); }
  LANES static Pack max(Pack a, Pack b) { return ::billiards::dynamics::lockstep::HWY_NAMESPACE::max(a, b); }
  LANES static Pack min(Pack a, Pack b) { return ::billiards::dynamics::lockstep::HWY_NAMESPACE::min(a, b); }
  LANES static Pack neg(Pack a) { return -a; }
  LANES static Pack trunc(Pack x) { return to_double(to_long(x)); }
  /// ScalarLanes::to_quadrant, on the doubles' bits.
  LANES static void to_quadrant(Pack k, Pack& s, Pack& c) {
    const Mask q = to_long(k), sb = bits(s), cb = bits(c);
    const Mask odd = -(q & 1);
    const Mask sq = (sb & ~odd) | (cb & odd), cq = (cb & ~odd) | (sb & odd);
    s = from_bits(sq ^ ((q & 2) << 62));
    c = from_bits(cq ^ (((q + 1) & 2) << 62));
  }
};

#include "billiards/dynamics/straight_exit-inl.hpp"
#include "billiards/dynamics/drive_phase-inl.hpp"
#include "billiards/dynamics/driven_exit-inl.hpp"

/// sin θ and cos θ where |θ| < 2¹⁹π (`fast`; the other lanes are handed back).
LANES SinCos<Pack> sin_cos(Pack theta, Mask& fast) {
  fast = abs(theta) < 0x1p19 * 3.14159265358979311600;
  return sin_cos_below_limit<PackLanes>(sel(fast, theta, splat(0.0)));
}
/// reduce_phase(hi + lo) below phase_constants::fast_limit (`fast`; the other lanes' results are
/// meaningless: MPFR reduces them).
LANES Unevaluated<Pack> reduce_phase(Pack hi, Pack lo, Mask& fast) {
  fast = abs(hi) < phase_constants::fast_limit;
  return reduce_phase_below_limit<PackLanes>(Unevaluated<Pack>{sel(fast, hi, splat(0.0)), lo});
}

// ---- One wall, lane by lane ------------------------------------------------------------------

// The fields of a wall (lockstep::Walls'): its kind and slack, an arc's, a segment's.
#define ARC_FIELDS(F) F(cx) F(cy) F(r) F(sign) F(fx) F(fy) F(tx) F(ty) F(full) F(half)
#define SEGMENT_FIELDS(F) F(ax) F(ay) F(bx) F(by) F(nx) F(ny) F(dir_x) F(dir_y) F(dir_norm) F(span_tol)
// F for the fields of the kinds `arcs` and `segments` (a wall's others are never read: its
// fields of a kind the table lacks are neither loaded nor moved).
#define WALL_FIELDS(F, arcs, segments) \
  F(arc) F(slack);                     \
  if (arcs) { ARC_FIELDS(F) }          \
  if (segments) { SEGMENT_FIELDS(F) }

/// The kinds of wall that the lanes that count have: arcs only, segments only, or both.
enum class Mix { arcs, segments, both };
constexpr bool has_arcs(Mix m) { return m != Mix::segments; }
constexpr bool has_segments(Mix m) { return m != Mix::arcs; }

/// The fields of walls in the lanes of N vectors: a segment's or an arc's (`arc`), the other
/// kind's unused.
template <int N>
struct WallFields {
  Parts<VI, N> arc;
  Parts<VD, N> slack;
  Parts<VD, N> cx, cy, r, sign, fx, fy, tx, ty;  // an arc
  Parts<VI, N> full, half;
  Parts<VD, N> ax, ay, bx, by, nx, ny, dir_x, dir_y, dir_norm, span_tol;  // a segment
};

/// The walls of a table, one per lane of KW vectors.
struct WallTable : WallFields<KW> {
  LANES WallTable(const Walls& w, Mix mix) {
#define LOAD(f) f = load_walls(w.f);
    WALL_FIELDS(LOAD, has_arcs(mix), has_segments(mix))
#undef LOAD
  }
};

/// A wall's fields for each lane: a segment's or an arc's (`arc`), the other kind's unused.
struct Wall : WallFields<K> {
  Wall() = default;
  /// Wall number wall[i] in lane i, from the table's walls `all`, whose walls fill `vectors`
  /// of its vectors.
  template <int n>
  LANES Wall(const WallTable& all, Mask wall, Mix mix, WallVectors<n> vectors) {
#define PICK(f) f = pick(all.f, wall, vectors);
    WALL_FIELDS(PICK, has_arcs(mix), has_segments(mix))
#undef PICK
  }
  /// Wall number i in every lane.
  LANES Wall(const Walls& w, int i) {
#define SPLAT(f) f = splat_as<std::decay_t<decltype(f.v[0])>>(w.f[i]);
    WALL_FIELDS(SPLAT, w.arc[i], !w.arc[i])
#undef SPLAT
  }
  /// An arc's fields as straight_exit-inl.hpp and driven_exit-inl.hpp read them (arc_lanes; the
  /// fields they do not read for a span test are the circle's own).
  LANES ArcLanes<Pack, Mask> arc_lanes() const {
    const Pack r2 = r * r;
    return {cx, cy, r, r2, r2, slack * r, fx, fy, tx, ty, sign > 0, full, half};
  }
  /// A segment's (segment_lanes).
  LANES SegmentLanes<Pack> segment_lanes() const { return {ax, ay, nx, ny, dir_x, dir_y, slack, span_tol}; }
};

/// The fields of a where m, else those of b (the kinds of `mix`).
LANES Wall select(Mask m, const Wall& a, const Wall& b, Mix mix) {
  Wall r;
#define SELECT(f) r.f = sel(m, a.f, b.f);
  WALL_FIELDS(SELECT, has_arcs(mix), has_segments(mix))
#undef SELECT
  return r;
}

/// The Taylor sample of a where m, else b's.
LANES TaylorLanes<Pack> sel(Mask m, const TaylorLanes<Pack>& a, const TaylorLanes<Pack>& b) {
  return {sel(m, a.f, b.f), sel(m, a.df, b.df), sel(m, a.d2f, b.d2f)};
}

/// The walls' kinds in lanes: by_kind(on_arc, on_segment) is on_arc() where a lane's wall is
/// an arc, on_segment() where it is a segment; only one of them is computed where every lane
/// that counts has a wall of one kind (`mix`, a constant: each mix has its own code, with no
/// branch and no value of the other kind kept in registers).
template <Mix mix>
struct Kinds {
  Mask arc;
  template <class A, class S>
  LANES auto by_kind(A on_arc, S on_segment) const {
    if constexpr (mix == Mix::arcs) return on_arc();
    else if constexpr (mix == Mix::segments) return on_segment();
    else return sel(arc, on_arc(), on_segment());
  }
};

/// f(Kinds) for the kinds of the walls w of the lanes that `count`, in a table that has both.
template <class F>
LANES void with_kinds(const Wall& w, Mask count, F f) {
  const bool arcs = any(count & w.arc), segments = any(count & ~w.arc);
  if (!segments) return f(Kinds<Mix::arcs>{w.arc});
  if (!arcs) return f(Kinds<Mix::segments>{w.arc});
  f(Kinds<Mix::both>{w.arc});
}

/// The flights' lanes: Quiver's fields (forced_flight.hpp), computed as its constructor does.
struct Quiver {
  Pack sx, sy, v0x, v0y, phase, sin_phase, cos_phase;
  Pack omega, accel_x, accel_y, amp_x_x, amp_x_y, amp_v_x, amp_v_y, accel_norm, inv_omega, delta;
  Pack ux, uy, g0x, g0y;
  GuideLanes<Pack> numbers;
  Mask creeping;  // (handed back: the scalar search, wall by wall)
  Pack rounding_rate;
  /// Of the flights from number `first` on.
  explicit Quiver(const Drive& d, const Flights& f, int first)
      : sx(load(f.sx + first)), sy(load(f.sy + first)), v0x(load(f.vx + first)), v0y(load(f.vy + first)),
        phase(load(f.phase_hi + first) + load(f.phase_lo + first)), sin_phase(load(f.sin_phase + first)),
        cos_phase(load(f.cos_phase + first)), omega(splat(d.omega)), accel_x(splat(d.accel_x)),
        accel_y(splat(d.accel_y)), amp_x_x(splat(d.amp_x_x)), amp_x_y(splat(d.amp_x_y)), amp_v_x(splat(d.amp_v_x)),
        amp_v_y(splat(d.amp_v_y)), accel_norm(splat(d.accel_norm)), inv_omega(splat(d.inv_omega)),
        delta(splat(d.delta)) {
    ux = guide_velocity(v0x, amp_v_x, sin_phase), uy = guide_velocity(v0y, amp_v_y, sin_phase);
    g0x = guide_start(sx, amp_x_x, cos_phase), g0y = guide_start(sy, amp_x_y, cos_phase);
    numbers = guide_lanes<PackLanes>(ux * ux + uy * uy, accel_norm, omega, inv_omega, delta);
    creeping = creeps<PackLanes>(numbers);
    rounding_rate = ::billiards::dynamics::lockstep::HWY_NAMESPACE::rounding_rate<PackLanes>(numbers, creeping);
  }
  LANES const GuideLanes<Pack>& lanes() const { return numbers; }
  /// The guide at τ.
  LANES Pack guide_x(Pack tau) const { return g0x + ux * tau; }
  LANES Pack guide_y(Pack tau) const { return g0y + uy * tau; }
};

/// SphereGap's numbers for the arc of each lane's wall along its flight, and PlaneGap's for the
/// segment's (those a caller does not read cost nothing: inlined, they are never computed).
LANES SphereGapLanes<Pack> sphere_gap_of(const Quiver& q, const Wall& a) {
  const Pack q0x = q.g0x - a.cx, q0y = q.g0y - a.cy;
  return sphere_gap<PackLanes>(q.lanes(), a.r, a.sign, a.slack, q0x * q.ux + q0y * q.uy, q0x * q0x + q0y * q0y,
                               (abs(q0x) + abs(q0y)) * (abs(q.ux) + abs(q.uy)), abs(q.sx - a.cx) + abs(q.sy - a.cy),
                               q.rounding_rate);
}
LANES PlaneGapLanes<Pack> plane_gap_of(const Quiver& q, const Wall& g) {
  return plane_gap<PackLanes>(q.lanes(), g.nx * q.accel_x + g.ny * q.accel_y, g.nx * q.ux + g.ny * q.uy,
                              g.nx * (q.g0x - g.ax) + g.ny * (q.g0y - g.ay), g.slack);
}

/// A lane's windows, in slots: one per segment (PlaneGap's window), then two per arc
/// (SphereGap::windows' first and second), the walls in their order (Walls: the segments
/// first), as the scalar search inserts them (a tie goes to the first slot, as it goes to the
/// first inserted there).
struct Windows {
  Pack start[2 * max_walls], end[2 * max_walls], margin[2 * max_walls];
  Mask below[2 * max_walls], open[2 * max_walls];  // open: found and not yet visited
};

/// The first of wall w's slots among the walls' (Windows).
LANES int first_slot(const Walls& walls, int w) { return w < walls.segments ? w : 2 * w - walls.segments; }

/// The sign of f' in each lane's window [start, end] of margin m (slope_sign).
template <Mix mix>
LANES Pack slope_sign(const Quiver& q, const Wall& w, const Kinds<mix>& kinds, Pack start, Pack end, Pack margin) {
  return kinds.by_kind([&]() LANES_LAMBDA { return slope_sign<PackLanes>(sphere_gap_of(q, w), q.lanes(), start, end, margin); },
                       [&]() LANES_LAMBDA { return slope_sign<PackLanes>(plane_gap_of(q, w), q.lanes()); });
}

/// may_meet_span(wall, guide(start), guide(end), δ): can the particle reach the wall's span?
template <Mix mix>
LANES Mask may_meet_span(const Quiver& q, const Wall& w, const Kinds<mix>& kinds, Pack start, Pack end) {
  const Pack px = q.guide_x(start), py = q.guide_y(start), qx = q.guide_x(end), qy = q.guide_y(end);
  return kinds.by_kind(
      [&]() LANES_LAMBDA { return may_meet_span<PackLanes>(w.arc_lanes(), w.slack, q.delta, px - w.cx, py - w.cy, qx - w.cx, qy - w.cy); },
      [&]() LANES_LAMBDA { return may_meet_span<PackLanes>(w.segment_lanes(), w.dir_norm, q.delta, px, py, qx, qy); });
}

/// The windows of wall w until `horizon`, into its slots.  Lanes whose guide stands
/// still (u = 0) get no window here: they are handed back.  Two kinds of window are not
/// opened, since one visit fewer for a lane is one round fewer for all W when it is the last to
/// finish:
/// - one in which f' < 0 is certain: the scalar search visits it and passes it (slope_sign = −1
///   with the window's end cut at the best hit so far, which can only be earlier: −1 at the end
///   here is −1 there, since for an arc qe and the threshold, rounded, only decrease with the
///   end, and an inward guide cannot be outward too; for a segment the sign does not depend on
///   the window);
/// - one in which the particle cannot reach the wall's span (may_meet_span over the whole
///   window; about one window a collision in the clover, a circle passed beside its arc): the
///   scalar search visits it, and either passes it by the same test over a part of it (its end
///   cut at the best hit), or searches it and finds no collision there, since the test is
///   certain (a collision is a point within δ of the guide in the span).  Either way the
///   search goes on with the same best hit, bit for bit.
LANES void wall_windows(const Quiver& q, const Walls& walls, Pack horizon, Mask live, Windows& out, int w) {
  const Wall wall(walls, w);
  WindowLanes<Pack, Mask> found[2];
  Pack slope[2];
  Mask passes[2];
  int slots = 1;
  if (walls.arc[w]) {
    const SphereGapLanes<Pack> g = sphere_gap_of(q, wall);
    windows<PackLanes>(g, q.lanes(), horizon, live, found[0], found[1]);
    // (The arc's fields as numbers, its kind as truths: one wall in every lane, so the span
    // test branches on whether the arc is full or at most half a circle.)
    const double r = walls.r[w], r2 = r * r;
    const ArcLanes<double, bool> arc{walls.cx[w], walls.cy[w], r,  r2, r2, walls.slack[w] * r, walls.fx[w], walls.fy[w],
                                     walls.tx[w], walls.ty[w], walls.sign[w] > 0, walls.full[w] != 0, walls.half[w] != 0};
    for (int j = 0; j < 2; ++j) {
      const Pack start = found[j].start, end = found[j].end;
      slope[j] = slope_sign<PackLanes>(g, q.lanes(), start, end, found[j].margin);
      passes[j] = ~may_meet_span<PackLanes>(arc, wall.slack, q.delta, q.guide_x(start) - arc.cx, q.guide_y(start) - arc.cy,
                                            q.guide_x(end) - arc.cx, q.guide_y(end) - arc.cy);
    }
    slots = 2;
  } else {
    const PlaneGapLanes<Pack> g = plane_gap_of(q, wall);
    found[0] = window<PackLanes>(g, q.lanes(), horizon, live);
    slope[0] = slope_sign<PackLanes>(g, q.lanes());
    passes[0] = ~may_meet_span(q, wall, Kinds<Mix::segments>{}, found[0].start, found[0].end);
  }
  for (int j = 0; j < slots; ++j) {
    const int slot = first_slot(walls, w) + j;
    const auto& f = found[j];
    out.open[slot] = f.open & ~(slope[j] < 0) & ~passes[j];
    out.start[slot] = f.start, out.end[slot] = f.end, out.margin[slot] = f.margin, out.below[slot] = f.below;
  }
}

/// BasicArcWall's or BasicSegmentWall's within_span of (x, y).
template <Mix mix>
LANES Mask within_span(const Wall& w, const Kinds<mix>& kinds, Pack x, Pack y) {
  const PackLanes l;
  return kinds.by_kind([&]() LANES_LAMBDA { return within_span(l, w.arc_lanes(), x, y); },
                       [&]() LANES_LAMBDA { return within_span(l, w.segment_lanes(), x, y); });
}

/// A hit's point and normal (straight_exit-inl.hpp's ContactLanes) of a where m, else b's.
LANES ContactLanes<Pack> sel(Mask m, const ContactLanes<Pack>& a, const ContactLanes<Pack>& b) {
  return {sel(m, a.x, b.x), sel(m, a.y, b.y), sel(m, a.nx, b.nx), sel(m, a.ny, b.ny)};
}

/// The searches' lanes: the best hit so far (first_hit_in_windows' tau_best, best_wall, phase)
/// and, for the lanes in a root search, monotone_crossing's variables.
template <Mix table>
class Lanes {
 public:
  Lanes(const Walls& walls, const WallTable& all, const Quiver& q, Mask live, Pack horizon)
      : walls_(walls), all_(all), q_(q), tau_best_(horizon), cur_(walls, 0) {
    handed_back_ = ~live | ~(q.numbers.uu > 0) | q.creeping;  // (a guide standing still: the scalar search)
    choosing_ = ~handed_back_;
    for (int w = 0; w < walls.count; ++w) wall_windows(q, walls, horizon, choosing_, win_, w);
  }

  /// The windows are visited in the order in which they open, each lane on its own: in a
  /// round, a lane either chooses its next window (and decides its sign of f' and span test
  /// there) or takes one step of its root search.
  bool busy() const { return any(choosing_ | searching_); }
  void round() {
    if (any(choosing_)) choose();
    if (any(searching_)) step();
  }
  /// The hits of the flights from number `first` on.
  void write(Hits& hits, int first) const {
    store(hits.tau + first, tau_best_), store(hits.theta + first, theta_), store(hits.sin + first, sin_);
    store(hits.cos + first, cos_);
    const auto wall = values(best_wall_), handed_back = values(handed_back_);
    for (int i = 0; i < W; ++i) hits.wall[first + i] = int(wall[i]), hits.handed_back[first + i] = handed_back[i] != 0;
  }

  /// The flight's state at each lane's hit, as LockstepTable::collisions has the scalar code
  /// make it (t = s.t + τ; PeriodicDriveFlight::advance from the root's sample; the arc's
  /// contact), into `hits` where `made`.  A lane whose phase is too far from the sample's to
  /// shift, or beyond the three-part reduction, is left to the scalar code.
  ROUND_PART void make_states(const Cells& cells, const Flights& f, Hits& hits, int first) const {
    const Quiver& q = q_;
    const Mask found = ~handed_back_ & (best_wall_ >= 0);
    Mask made{};
    if (any(found)) {
      const Pack st = load(f.t + first), t = st + tau_best_, tau = t - st;
      check_midpoints(cells, found, st, t, hits, first);
      // set_phase_at: θ = advance_phase(s.phase, ω, τ), its sine and cosine shifted from the
      // sample's by h = θ − sample (Phase's operator−, then to double).
      const auto theta = advance_phase<PackLanes>(Unevaluated<Pack>{load(f.phase_hi + first), load(f.phase_lo + first)}, q.omega, tau);
      const auto shift = phase_difference(theta, Unevaluated<Pack>{theta_, splat(0.0)});
      const Pack h = shift.hi + shift.lo;
      const auto [sn, cs] = shifted<PackLanes>(SinCos<Pack>{sin_, cos_}, h);
      Mask fast;
      const auto [phase_hi, phase_lo] = reduce_phase(theta.hi, theta.lo, fast);
      made = found & (abs(h) <= 0.05) & fast;
      // advance: v = s.v + (F/mω)(sin θ − sin θ_s), x = s.x + u τ − (F/mω²)(cos θ − cos θ_s).
      const Pack vx = advanced_velocity(q.v0x, q.amp_v_x, sn, q.sin_phase);
      const Pack vy = advanced_velocity(q.v0y, q.amp_v_y, sn, q.sin_phase);
      const Pack x = advanced_position(q.sx, q.ux, tau, q.amp_x_x, cs, q.cos_phase);
      const Pack y = advanced_position(q.sy, q.uy, tau, q.amp_x_y, cs, q.cos_phase);
      const Wall a = wall_of(best_wall_);
      const PackLanes l;
      ContactLanes<Pack> c;
      for_kinds(a, found, [&](const auto& kinds) LANES_LAMBDA {
        c = kinds.by_kind([&]() LANES_LAMBDA { return arc_contact(l, a.arc_lanes(), a.slack, x, y, vx, vy); },
                          [&]() LANES_LAMBDA { return segment_contact<PackLanes>(a.segment_lanes(), a.bx, a.by, x, y); });
      });
      auto put = [first](double* field, Pack p) LANES_LAMBDA { store(field + first, p); };
      put(hits.t, t), put(hits.x, x), put(hits.y, y), put(hits.vx, vx), put(hits.vy, vy);
      put(hits.phase_hi, phase_hi), put(hits.phase_lo, phase_lo), put(hits.sin_phase, sn), put(hits.cos_phase, cs);
      put(hits.point_x, c.x), put(hits.point_y, c.y), put(hits.normal_x, c.nx), put(hits.normal_y, c.ny);
    }
    const auto made_in = values(made);
    for (int i = 0; i < W; ++i) hits.made[first + i] = made_in[i] != 0;
  }

 private:
  /// Table::certainly_contains of each found lane's oscillation segment at mid-flight, as
  /// Trajectory::inside_at asks it at 0.5 (s.t + t): the segment g ± F/(mω²) (sweep), g the
  /// guide there; the cells of its ends (Classes::cell_of) in lanes, their classes lane by lane.
  void check_midpoints(const Cells& cells, Mask found, Pack st, Pack t, Hits& hits, int first) const {
    const Quiver& q = q_;
    const Pack tau = 0.5 * (st + t) - st;
    const Pack gx = q.g0x + q.ux * tau, gy = q.g0y + q.uy * tau;
    auto cell_of = [&](Pack x, Pack y, Mask& ix, Mask& iy) LANES_LAMBDA {
      const Pack u = (x - cells.origin_x) * cells.inverse_x, v = (y - cells.origin_y) * cells.inverse_y;
      const Mask in = (u >= 0) & (v >= 0) & (u < double(cells.nx)) & (v < double(cells.ny));  // (NaN: out)
      ix = sel(in, to_long(sel(in, u, splat(0.0))), Mask{} - 1), iy = to_long(sel(in, v, splat(0.0)));
    };
    Mask pix, piy, qix, qiy;
    cell_of(gx - q.amp_x_x, gy - q.amp_x_y, pix, piy);
    cell_of(gx + q.amp_x_x, gy + q.amp_x_y, qix, qiy);
    // One cell, or neighbouring ones (by a side or a corner) whose block of two or four cells
    // is convex: all four corners of the block inside.  Without branches (whether the ends
    // share a cell is as good as random); lanes that cannot be certain look up cell 0.
    const auto px = values(pix), py = values(piy), qx = values(qix), qy = values(qiy), found_in = values(found);
    for (int i = 0; i < W; ++i) {
      const long ix = px[i], iy = py[i], jx = qx[i], jy = qy[i];
      const bool near = (found_in[i] != 0) & (ix >= 0) & (jx >= 0) & (ix - jx <= 1) & (jx - ix <= 1) & (iy - jy <= 1) &
                        (jy - iy <= 1);
      auto inside = [&](long x, long y) { return cells.cell[near ? y * cells.nx + x : 0] == 1; };  // (Classes::inside)
      hits.midpoint_inside[first + i] = near & inside(ix, iy) & inside(jx, jy) & inside(ix, jy) & inside(jx, iy);
    }
  }

  /// Each choosing lane's earliest open window, if it opens by the best hit so far; its sign of
  /// f' and span test; and the start of a root search where both allow a collision.
  ROUND_PART void choose() {
    // The earliest open window, the first of equals (as the scalar search's stable order):
    // a tournament, whose rounds do not wait on one another as a pass over the slots would.
    constexpr int max_slots = 2 * max_walls;
    const int slots = first_slot(walls_, walls_.count);
    Pack key[max_slots];
    Mask index[max_slots];
    Mask found{};
    for (int j = 0; j < slots; ++j) {
      const Mask open = choosing_ & win_.open[j];
      key[j] = sel(open, win_.start[j], splat(inf));
      index[j] = Mask{} + j;
      found |= open;
    }
    for (int width = 1; width < slots; width *= 2)
      for (int j = 0; j + width < slots; j += 2 * width) {
        const Mask later = key[j + width] < key[j];
        key[j] = sel(later, key[j + width], key[j]);
        index[j] = sel(later, index[j + width], index[j]);
      }
    const Mask slot = index[0];
    Pack start = key[0], end{}, margin{};
    Mask below{};
    for (int j = 0; j < slots; ++j) {
      const Mask here = slot == j;
      end = sel(here, win_.end[j], end), margin = sel(here, win_.margin[j], margin), below = sel(here, win_.below[j], below);
    }
    const Mask go = found & (start <= tau_best_);
    choosing_ &= go;
    for (int j = 0; j < slots; ++j) win_.open[j] &= ~(go & (slot == j));
    if (!any(go)) return;
    const Mask wall = wall_of_slot(slot);
    const Wall a = wall_of(wall);
    end = min(end, tau_best_);
    for_kinds(a, go, [&](const auto& kinds) LANES_LAMBDA { begin_searches(kinds, go, wall, a, start, end, margin, below); });
  }

  /// The sign of f' and the span test of the windows [start, end] of margin m that the lanes
  /// `go` chose (their walls a); the start of a root search where both allow a collision.
  template <Mix mix>
  LANES void begin_searches(const Kinds<mix>& kinds, Mask go, Mask wall, const Wall& a, Pack start, Pack end,
                                 Pack margin, Mask below) {
    const Pack slope = slope_sign(q_, a, kinds, start, end, margin);
    const Mask passes = ~may_meet_span(q_, a, kinds, start, end);
    const Mask kept = go & ~((slope < 0) | passes);
    const Mask uncertain = kept & (slope == 0);  // (the certified scan: the scalar search)
    handed_back_ |= uncertain;
    const Mask begin = kept & (slope > 0);
    choosing_ &= ~(uncertain | begin);
    if (!any(begin)) return;
    searching_ |= begin;
    cur_ = select(begin, a, cur_, table);
    wall_ = sel(begin, wall, wall_);
    start_ = sel(begin, start, start_), end_ = sel(begin, end, end_);
    lo_ = sel(begin, start, lo_), hi_ = sel(begin, end, hi_);
    bracketed_ &= ~begin;
    steps_ = sel(begin, Mask{}, steps_);
    const Pack jerk = kinds.by_kind([&]() LANES_LAMBDA { return jerk_bound<PackLanes>(sphere_gap_of(q_, a), q_.lanes(), margin); },
                                    [&]() LANES_LAMBDA { return jerk_bound<PackLanes>(plane_gap_of(q_, a), q_.lanes(), margin); });
    jerk_ = sel(begin, jerk, jerk_);
    tau_ = sel(begin, sel(below, start + (end - start) / 2, start), tau_);
  }

  /// Wall number wall[i] in lane i, looked up in the first half of the table's vectors where its
  /// walls fit there (the clover's eight: half the look-ups, one vector on AVX-512).
  LANES Wall wall_of(Mask wall) const {
    if (walls_.count <= max_walls / 2) return Wall(all_, wall, table, HalfWallVectors{});
    return Wall(all_, wall, table, AllWallVectors{});
  }

  /// The wall of each lane's slot (first_slot's inverse).
  LANES Mask wall_of_slot(Mask slot) const {
    if constexpr (table == Mix::segments) return slot;
    if constexpr (table == Mix::arcs) return slot >> 1;
    const int segments = walls_.segments;
    return sel(slot < segments, slot, (slot + segments) >> 1);
  }

  /// f(Kinds) for the kinds of the walls w of the lanes that `count`: the table's one kind, or
  /// where it has both, theirs.
  template <class F>
  LANES void for_kinds(const Wall& w, Mask count, F f) const {
    if constexpr (table == Mix::both) with_kinds(w, count, f);
    else f(Kinds<table>{w.arc});
  }

  /// One iteration of monotone_crossing in every searching lane.
  void step() {
    for_kinds(cur_, searching_, [&](const auto& kinds) LANES_LAMBDA { step(kinds); });
  }
  template <Mix mix>
  ROUND_PART void step(const Kinds<mix>& kinds) {
    const Quiver& q = q_;
    const Wall& a = cur_;
    const SphereGapLanes<Pack> sphere = sphere_gap_of(q, a);
    const PlaneGapLanes<Pack> plane = plane_gap_of(q, a);
    const Pack tau = tau_;
    // The Taylor sample at τ (SphereGap::taylor, Quiver::motion).
    const Mask at_start = tau == 0;
    Pack th = q.phase + q.omega * tau;
    Mask fast;
    auto [sn, cs] = sin_cos(th, fast);
    handed_back_ |= searching_ & ~at_start & ~fast;
    searching_ &= at_start | fast;
    th = sel(at_start, q.phase, th), sn = sel(at_start, q.sin_phase, sn), cs = sel(at_start, q.cos_phase, cs);
    const Pack x = sel(at_start, q.sx, quiver_position(q.g0x, q.ux, tau, q.amp_x_x, cs));
    const Pack y = sel(at_start, q.sy, quiver_position(q.g0y, q.uy, tau, q.amp_x_y, cs));
    const Pack vx = sel(at_start, q.v0x, quiver_velocity(q.ux, q.amp_v_x, sn));
    const Pack vy = sel(at_start, q.v0y, quiver_velocity(q.uy, q.amp_v_y, sn));
    const Pack ax = q.accel_x * cs, ay = q.accel_y * cs;
    // SphereGap::taylor from the dot products of p = x − c; PlaneGap::taylor, n·(x − a), n·v, n·ẍ.
    const TaylorLanes<Pack> p = kinds.by_kind([&]() LANES_LAMBDA {
      const Pack px = x - a.cx, py = y - a.cy;
      return taylor<PackLanes>(sphere, px * px + py * py, px * vx + py * vy, vx * vx + vy * vy, px * ax + py * ay);
    }, [&]() LANES_LAMBDA {
      return TaylorLanes<Pack>{a.nx * (x - a.ax) + a.ny * (y - a.ay), a.nx * vx + a.ny * vy, a.nx * ax + a.ny * ay};
    });
    const Pack &f = p.f, &df = p.df;
    const Pack tol = kinds.by_kind([&]() LANES_LAMBDA { return band<PackLanes>(sphere, tau); },
                                   [&]() LANES_LAMBDA { return band<PackLanes>(plane, tau); });

    // At the wall to rounding: the polished root, if it is in the span.
    const Mask band = searching_ & (abs(f) <= tol);
    const Mask rising = df > 0;
    Mask undecided = band & ~rising, never{}, root{};
    Pack found = tau, found_th = th, found_sn = sn, found_cs = cs;
    if (any(band & rising)) {  // (rare: most roots are found by a certain step, below)
      never = band & rising & ~within_span(a, kinds, x, y);
      root = band & rising & ~never;
      found = polished_root<PackLanes>(tau, f, df, tol);
    }

    // Otherwise the bracket shrinks, and a Halley step (or bisection) gives the next τ.
    const Mask on = searching_ & ~band, neg = f < 0;
    never |= on & ((neg & (tau >= end_)) | (~neg & (tau == start_)));
    const Mask moving = on & ~never;
    lo_ = sel(moving & neg, tau, lo_);
    hi_ = sel(moving & ~neg, tau, hi_);
    bracketed_ |= moving & ~neg;
    const Pack next = halley_next<PackLanes>(p, tau, lo_, hi_, bracketed_);
    undecided |= moving & (next == tau);
    Mask stepping = moving & (next != tau);
    // certainly_below: the next τ is the root without a sample there.
    const Pack th_next = q.phase + q.omega * next, shift = th_next - th;
    const Mask landed =
        stepping &
        certainly_below<PackLanes>(p, next - tau, jerk_,
                                   kinds.by_kind([&]() LANES_LAMBDA { return rounding<PackLanes>(sphere, next); },
                                                 [&]() LANES_LAMBDA { return rounding<PackLanes>(plane, next); })) &
        (abs(shift) <= 0.05);
    if (any(landed)) {
      const auto [sn_next, cs_next] = shifted<PackLanes>(SinCos<Pack>{sn, cs}, shift);
      const Mask in =
          within_span(a, kinds, quiver_position(q.g0x, q.ux, next, q.amp_x_x, cs_next),
                      quiver_position(q.g0y, q.uy, next, q.amp_x_y, cs_next));
      never |= landed & ~in;
      root |= landed & in;
      found = sel(landed, next, found);
      found_th = sel(landed, th_next, found_th), found_sn = sel(landed, sn_next, found_sn);
      found_cs = sel(landed, cs_next, found_cs);
      stepping &= ~landed;
    }
    tau_ = sel(stepping, next, tau_);
    steps_ = sel(stepping, steps_ + 1, steps_);
    undecided |= stepping & (steps_ == 100);

    // The searches that ended: the hit, if earlier than the best so far.
    const Mask better = root & (found < tau_best_);
    tau_best_ = sel(better, found, tau_best_);
    best_wall_ = sel(better, wall_, best_wall_);
    theta_ = sel(better, found_th, theta_), sin_ = sel(better, found_sn, sin_), cos_ = sel(better, found_cs, cos_);
    handed_back_ |= undecided;
    const Mask ended = root | never;
    searching_ &= ~(ended | undecided);
    // A lane with no window left that opens by its best hit is done now, not after one more
    // round in which `choose` would find none: its last round is often the batch's last.
    if (any(ended)) choosing_ |= ended & window_opens_by(tau_best_);
  }

  /// Has the lane a window not yet visited that opens by τ?
  Mask window_opens_by(Pack tau) const {
    Mask opens{};
    for (int j = 0; j < first_slot(walls_, walls_.count); ++j) opens |= win_.open[j] & (win_.start[j] <= tau);
    return opens;
  }

  const Walls& walls_;
  const WallTable& all_;
  const Quiver& q_;
  Windows win_;
  Pack tau_best_;
  Mask best_wall_ = Mask{} - 1;
  Pack theta_ = splat(inf), sin_ = splat(0.0), cos_ = splat(1.0);
  Mask handed_back_, choosing_, searching_{};
  // The root search of each searching lane: its window's arc, wall, ends, bracket and iterate.
  Wall cur_;
  Mask wall_{}, bracketed_{}, steps_{};
  Pack start_{}, end_{}, lo_{}, hi_{}, tau_{}, jerk_{};
};

}  // namespace

void first_hits(const Walls& walls, const Drive& drive, const Cells& cells, const Flights& flights, Hits& hits) {
  // The table's walls loaded once, then the flights W lanes at a time.
  auto search = [&]<Mix mix>() {
    const WallTable all(walls, mix);
    for (int first = 0; first < lanes; first += W) {
      const Mask live = load_mask(flights.active + first);
      if (!any(live)) {
        for (int i = first; i < first + W; ++i) hits.handed_back[i] = true;
        continue;
      }
      const Quiver q(drive, flights, first);
      Lanes<mix> part(walls, all, q, live, load(flights.tau_end + first));
      while (part.busy()) part.round();
      part.write(hits, first);
      if (walls.make_states)
        part.make_states(cells, flights, hits, first);
      else
        for (int i = first; i < first + W; ++i) hits.made[i] = false;
    }
  };
  if (walls.segments == 0) search.template operator()<Mix::arcs>();
  else if (walls.segments == walls.count) search.template operator()<Mix::segments>();
  else search.template operator()<Mix::both>();
}

#undef LANES
#undef LANES_LAMBDA
#undef LANES_SELECT
#undef EACH_VECTOR
#undef ROUND_PART

}  // namespace billiards::dynamics::lockstep::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace billiards::dynamics::lockstep {

Kernel kernel_of(std::int64_t target) { BILLIARDS_KERNEL_OF(target, first_hits) }

}  // namespace billiards::dynamics::lockstep
#endif
