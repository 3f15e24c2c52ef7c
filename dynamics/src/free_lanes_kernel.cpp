// The lock-step search of straight flights (free_lockstep.hpp), compiled once for each SIMD
// target of Google Highway (hwy/foreach_target.h includes this file again for each, in its own
// namespace, as lockstep_kernel.cpp is).  Its exit times are straight_exit-inl.hpp's, the
// scalar search's own source, included into each target's namespace with the traits of a
// vector of doubles, one flight per lane: the same operations in the same order, each rounded
// once (no fused multiply-add: -ffp-contract=off), so each lane's time is the scalar search's,
// bit for bit; and the walls are tried in the scalar search's order, each kept only when it is
// hit strictly earlier.  An elliptic arc is its unit arc, hit by the flight seen through the
// ellipse's map (mapped_ray), as the scalar search sees it.  The 3-D kernel does the same
// through planes and spheres with straight_exit3-inl.hpp's exit times, walls3.cpp's source.

#include "simd_targets.hpp"  // (first: the targets compiled)
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "free_lanes_kernel.cpp"
#include <hwy/foreach_target.h>  // (this file, once per target)
#include <hwy/highway.h>

#include "billiards/dynamics/free_lanes.hpp"
#include "billiards/dynamics/phase_constants.hpp"
#include "billiards/dynamics/simd.hpp"

#include <cstdint>
#include <cstring>
#include <limits>
#include <type_traits>  // (straight_exit-inl.hpp: no code)

#pragma GCC diagnostic ignored "-Wpsabi"  // (vectors passed by value: inlined throughout)

HWY_BEFORE_NAMESPACE();
namespace billiards::dynamics::free_lanes::HWY_NAMESPACE {

namespace {

#include "double_lanes-inl.hpp"
#include "billiards/dynamics/straight_exit3-inl.hpp"
#include "billiards/dynamics/drive_phase-inl.hpp"  // (the run's clock)
#include "billiards/dynamics/bounce-inl.hpp"

/// A plane or a sphere, the same in every lane.
PlaneLanes<Num> lanes_of(const Plane& p) {
  return {Lanes::splat(p.nx), Lanes::splat(p.ny), Lanes::splat(p.nz), Lanes::splat(p.offset), Lanes::splat(p.slack)};
}
SphereLanes<Num, bool> lanes_of(const Sphere& b) {
  return {Lanes::splat(b.cx), Lanes::splat(b.cy), Lanes::splat(b.cz),
          Lanes::splat(b.r),  Lanes::splat(b.r2), Lanes::splat(b.near), b.focusing};
}

/// The search's best hit so far, lane by lane: time, kind and index of the wall.
struct Best {
  Num t;
  Index kind, index;
  explicit Best(Num t_end) : t(t_end), kind(hn::Set(DI(), -1)), index(hn::Set(DI(), -1)) {}
  /// Keeps the wall (kind, i) in the lanes where it is hit before the best so far (the scalar
  /// search's strict <: the first of equal times).
  void keep(Num hit, int k, int i) {
    const Truth earlier = hit < t;
    t = hn::IfThenElse(earlier, hit, t);
    assign_where(earlier, k, kind);
    assign_where(earlier, i, index);
  }
  /// The lanes' hits into those from lane `first` (handed back: those `undecided`).
  void store(const Lanes& lanes, int first, Hits& hits) const {
    const DI di;
    hn::Store(t, D(), hits.t + first);
    hn::Store(kind, di, hits.kind + first);
    hn::Store(index, di, hits.index + first);
    hn::Store(hn::VecFromMask(di, hn::RebindMask(di, lanes.undecided)), di, hits.handed_back + first);
  }
  /// Where the wall of each lane's hit is of kind k.
  Truth of_kind(int k) const { return hn::RebindMask(D(), kind == hn::Set(DI(), k)); }
};

/// column[i] in each lane (i < count; a lane's i beyond: any entry): the table lookup of the
/// L entries from the one that holds i.
Num lookup(const double* column, int count, Index i) {
  const D d;
  const auto at = hn::IndicesFromVec(d, hn::And(i, hn::Set(DI(), L - 1)));
  Num r = hn::TableLookupLanes(hn::Load(d, column), at);
  for (int first = L; first < count; first += L)
    r = hn::IfThenElse(hn::RebindMask(d, hn::Set(DI(), first - 1) < i), hn::TableLookupLanes(hn::Load(d, column + first), at), r);
  return r;
}

/// Does the kernel make the hits' contacts (contacts_of)?  With eight lanes (AVX-512) the
/// clover, the stadium and the Sinai table run at 1.06–1.12× the rate of leaving them to the
/// scalar code, the mushroom at 0.97×; with four (AVX2) at 0.93–1.05× (BENCHMARKS.md, free
/// flights): an arc's contact computes both its branches in every lane.
constexpr bool contacts_in_lanes = L >= 8;

/// The flight's position at each lane's hit and the contact there, as the scalar code makes
/// them (FreeFlight::advance, then the wall's `contact`: straight_exit-inl.hpp's
/// segment_contact and arc_contact), `made` where a segment or an arc was hit and the lane was
/// not handed back (an elliptic arc's hit is left to the scalar code).
struct Contacts {
  Truth made;
  Num x, y;
  ContactLanes<Num> at;
  /// Into the hits from lane `first`.
  void store(int first, Hits& hits) const {
    const D d;
    const DI di;
    hn::Store(hn::VecFromMask(di, hn::RebindMask(di, made)), di, hits.made + first);
    hn::Store(x, d, hits.x + first), hn::Store(y, d, hits.y + first);
    hn::Store(at.x, d, hits.point_x + first), hn::Store(at.y, d, hits.point_y + first);
    hn::Store(at.nx, d, hits.normal_x + first), hn::Store(at.ny, d, hits.normal_y + first);
  }
};
Contacts contacts_of(const Walls& walls, const RayLanes<Num>& s, const Best& best, const Lanes& lanes) {
  const D d;
  const Num tau = best.t - s.t, x = s.x + s.vx * tau, y = s.y + s.vy * tau;
  const Truth on_segment = hn::AndNot(lanes.undecided, best.of_kind(0));
  const Truth on_arc = hn::AndNot(lanes.undecided, best.of_kind(1));
  const Num zero = hn::Zero(d);
  const ContactColumns& w = walls.contacts;
  ContactLanes<Num> c{zero, zero, zero, zero};
  if (!hn::AllFalse(d, on_segment)) {
    auto field = [&](const double* column) { return lookup(column, walls.segment_count, best.index); };
    const SegmentLanes<Num> g{field(w.ax), field(w.ay), field(w.nx), field(w.ny), field(w.dir_x), field(w.dir_y), zero, zero};
    c = Lanes::select(on_segment, segment_contact<Lanes>(g, field(w.bx), field(w.by), x, y), c);
  }
  if (!hn::AllFalse(d, on_arc)) {
    auto field = [&](const double* column) { return lookup(column, walls.arc_count, best.index); };
    const DI di;
    const Index i = hn::IfThenElseZero(hn::RebindMask(di, on_arc), best.index);  // (no shift by −1)
    const Truth focusing = hn::RebindMask(d, hn::TestBit(hn::Set(di, std::int64_t(w.focusing)), hn::Set(di, 1) << i));
    const ArcLanes<Num, Truth> a{field(w.cx), field(w.cy), field(w.r), field(w.r2), zero, zero, zero, zero, zero, zero,
                                 focusing,    focusing,    focusing};
    c = Lanes::select(on_arc, arc_contact(Lanes{}, a, field(w.slack), x, y, s.vx, s.vy), c);
  }
  return {hn::Or(on_segment, on_arc), x, y, c};
}

/// The L flights from lane `first`.
RayLanes<Num> rays_at(const Rays& rays, int first) {
  const D d;
  return {hn::Load(d, rays.x + first),  hn::Load(d, rays.y + first), hn::Load(d, rays.vx + first),
          hn::Load(d, rays.vy + first), hn::Load(d, rays.t + first), hn::Load(d, rays.vv + first)};
}

/// The first walls the flights s meet before t_end, in the scalar search's order of walls.
Best search(const Walls& walls, Lanes& lanes, const RayLanes<Num>& s, Num t_end) {
  Best best(t_end);
  for (int i = 0; i < walls.segment_count; ++i)
    best.keep(straight_exit_time(lanes, s, lanes_of(walls.segments[i]), t_end), 0, i);
  for (int i = 0; i < walls.arc_count; ++i) best.keep(straight_exit_time(lanes, s, lanes_of(walls.arcs[i]), t_end), 1, i);
  for (int i = 0; i < walls.ellipse_count; ++i) {
    const Ellipse& e = walls.ellipses[i];
    best.keep(straight_exit_time(lanes, mapped_ray<Lanes>(s, lanes_of(e)), lanes_of(e.unit), t_end), 2, i);
  }
  return best;
}

/// The first hits of the L flights from lane `first`.
void first_hits_of(const Walls& walls, const Rays& rays, int first, Hits& hits) {
  Lanes lanes;
  const RayLanes<Num> s = rays_at(rays, first);
  const Best best = search(walls, lanes, s, hn::Load(D(), rays.t_end + first));
  best.store(lanes, first, hits);
  if constexpr (contacts_in_lanes) contacts_of(walls, s, best, lanes).store(first, hits);
  else hn::Store(hn::Zero(DI()), DI(), hits.made + first);
}

/// The lanes where m holds, as bits (bit i: lane i).
std::uint32_t lanes_of_mask(Truth m) {
  std::uint8_t bytes[(L + 7) / 8];
  hn::StoreMaskBits(D(), m, bytes);
  std::uint32_t bits = 0;
  for (int b = 0; b < (L + 7) / 8; ++b) bits |= std::uint32_t(bytes[b]) << (8 * b);
  return bits & ((1u << L) - 1);
}

/// The traits of a double for drive_phase-inl.hpp, the clock of one lane at a time (Clock::until's
/// arithmetic).
struct OneDouble {
  using Num = double;
  static double neg(double a) { return -a; }
};

/// Is the point (x, y) in a cell that lies wholly inside?  Classes::cell_of's arithmetic, then
/// a bit of Cells::inside: where this holds, Table::contains answers true at its lookup.
bool certainly_inside(const Cells& cells, double x, double y) {
  const double ux = (x - cells.origin_x) * cells.inverse_x, uy = (y - cells.origin_y) * cells.inverse_y;
  if (!(ux >= 0 && uy >= 0 && ux < cells.nx && uy < cells.ny)) return false;  // (NaN too)
  const std::int64_t cell = std::int64_t(uy) * std::int64_t(cells.nx) + std::int64_t(ux);
  return cells.inside[cell >> 6] >> (cell & 63) & 1;
}
/// The same in each lane (the same arithmetic; the words gathered).
Truth certainly_inside(const Cells& cells, Num x, Num y) {
  const D d;
  const DI di;
  const Num ux = (x - Lanes::splat(cells.origin_x)) * Lanes::splat(cells.inverse_x);
  const Num uy = (y - Lanes::splat(cells.origin_y)) * Lanes::splat(cells.inverse_y);
  const Num zero = hn::Zero(d);
  const Truth on_grid = hn::And(hn::And(ux >= zero, uy >= zero),
                                hn::And(ux < Lanes::splat(cells.nx), uy < Lanes::splat(cells.ny)));  // (NaN: off)
  const Index cell = hn::ConvertTo(di, hn::IfThenElseZero(on_grid, hn::Trunc(uy) * Lanes::splat(cells.nx) + hn::Trunc(ux)));
  const Index word = hn::GatherIndex(di, cells.inside, hn::ShiftRight<6>(cell));
  return hn::And(on_grid, hn::RebindMask(d, hn::TestBit(word, hn::Set(di, 1) << hn::And(cell, hn::Set(di, 63)))));
}

/// `record`'s records of the lanes `due`, each lane's in a loop of its own: the lanes that
/// leave.
Truth record_lane_by_lane(const Walls& walls, const Records& records, Particles& p, int first, const RayLanes<Num>& s,
                          Num t_hit, Truth due) {
  const D d;
  alignas(64) double x[L], y[L], vx[L], vy[L], t0[L], energy[L], end[L];
  hn::Store(s.x, d, x), hn::Store(s.y, d, y), hn::Store(s.vx, d, vx), hn::Store(s.vy, d, vy), hn::Store(s.t, d, t0);
  hn::Store(Lanes::splat(records.half_mass) * s.vv, d, energy), hn::Store(t_hit, d, end);
  std::uint64_t left = 0;
  for (std::uint32_t bits = lanes_of_mask(due); bits != 0; bits &= bits - 1) {
    const int i = __builtin_ctz(bits), j = first + i;
    const Unevaluated<double> clock{p.clock_hi[j], p.clock_lo[j]};
    std::int64_t k = p.record[j];
    for (double t; (t = clock_until<OneDouble>(clock, records.times[k])) <= end[i];) {
      const double tau = t - t0[i];
      if (!certainly_inside(walls.cells, x[i] + vx[i] * tau, y[i] + vy[i] * tau)) {
        left |= std::uint64_t(1) << i;
        break;
      }
      p.energies[j][k] = energy[i];
      if (++k == records.count) {
        left |= std::uint64_t(1) << i;
        break;
      }
    }
    p.record[j] = k, p.record_at[j] = records.times[k];
  }
  std::uint8_t mask[8];
  std::memcpy(mask, &left, sizeof mask);
  return hn::LoadMaskBits(d, mask);
}

/// The records of the flights s from lane `first` that reach their next record times by their
/// hits at t_hit, in the lanes `flying` (`due` of them now, at t on their clocks): at each,
/// the energy ½m|v|² (Trajectory::record's, as energy_of sums it) where the position there
/// (FreeFlight::advance's) is `certainly_inside`, and the next record time taken up.  Returns
/// the lanes still flying, all of whose next record times lie beyond their hits: not those
/// that reached a record time outside the cells inside (for the scalar code's point-in-region
/// test), nor those past their last.
///
/// The records are taken in rounds of all lanes due while more than L/2 + 1 are (6 of 8, 4 of
/// 4), then lane by lane: rounds alone end with the flight that spans the most (about 8 of 8
/// flights of 2.6 each, the free clover recorded at every time unit), a lane at a time alone
/// pays a mispredicted branch at the end of each flight's records (BENCHMARKS.md, records).  A
/// round is kept short: the next round's times are gathered a round ahead, a round's record
/// times follow from the lanes due alone (the lanes that fail the lookup leave, so in those
/// still flying every due record is taken), and its energies are stored lane by lane, a lane
/// not taken writing to a sink.
[[gnu::noinline]] Truth record(const Walls& walls, const Records& records, Particles& p, int first, const RayLanes<Num>& s,
                               Num t_hit, const Unevaluated<Num>& clock, Truth flying, Num t, Truth due) {
  const D d;
  const DI di;
  constexpr std::size_t few = L / 2 + 1;
  if (hn::CountTrue(d, due) > few) {
    const Index one = hn::Set(di, 1), count = hn::Set(di, records.count);
    Index k = hn::Load(di, p.record + first);
    Num at = hn::Load(d, p.record_at + first), next = hn::GatherIndex(d, records.times, hn::Min(k + one, count));
    alignas(64) double energy[L];
    alignas(64) std::int64_t index[L];
    hn::Store(Lanes::splat(records.half_mass) * s.vv, d, energy);
    double sink;
    do {
      // The next round's times, as if every lane due took its record (those that do not leave).
      const Index after = k + hn::IfThenElseZero(hn::RebindMask(di, due), one);
      at = hn::IfThenElse(due, next, at);
      next = hn::GatherIndex(d, records.times, hn::Min(after + one, count));
      const Num tau = t - s.t;
      const Truth taken = hn::And(due, certainly_inside(walls.cells, s.x + s.vx * tau, s.y + s.vy * tau));
      hn::Store(k, di, index);
      const std::uint32_t bits = lanes_of_mask(taken);
      for (int i = 0; i < L; ++i) *(bits >> i & 1 ? p.energies[first + i] + index[i] : &sink) = energy[i];
      k = hn::IfThenElse(hn::RebindMask(di, taken), after, k);
      flying = hn::AndNot(hn::Or(hn::AndNot(taken, due), hn::RebindMask(d, after == count)), flying);
      t = clock_until<Lanes>(clock, at);
      due = hn::And(flying, t <= t_hit);
    } while (hn::CountTrue(d, due) > few);
    hn::Store(k, di, p.record + first);
    hn::Store(hn::GatherIndex(d, records.times, k), d, p.record_at + first);
  }
  if (hn::AllFalse(d, due)) return flying;
  return hn::AndNot(record_lane_by_lane(walls, records, p, first, s, t_hit, due), flying);
}

/// `propagate` for the L particles from lane `first`: the lanes left to the scalar code.  The
/// bounce is collision.hpp's (bounce-inl.hpp's, with k = 2(v·n) and |v|² summed as Eigen sums
/// a 2-vector's), the clock's add is state.hpp's (drive_phase-inl.hpp's), each of the same
/// operations in the same order: so a particle's bounces in the lanes are the scalar code's,
/// bit for bit.  The contacts are made on every target here: a lane that leaves costs more
/// than an arc's two branches.
std::uint32_t propagate_of(const Walls& walls, const Records& records, Particles& p, int first, Hits& hits) {
  const D d;
  const DI di;
  Lanes lanes;
  Rays& r = p.rays;
  const RayLanes<Num> s = rays_at(r, first);
  const Best best = search(walls, lanes, s, hn::Load(d, r.t_end + first));
  best.store(lanes, first, hits);
  const Contacts c = contacts_of(walls, s, best, lanes);
  c.store(first, hits);
  const Unevaluated<Num> clock{hn::Load(d, p.clock_hi + first), hn::Load(d, p.clock_lo + first)};
  const Truth recording = hn::RebindMask(d, hn::Load(di, p.record + first) < hn::Set(di, records.count));
  const Truth flying = hn::And(hn::And(c.made, best.t != hn::Zero(d)), recording);
  const Num t_record = clock_until<Lanes>(clock, hn::Load(d, p.record_at + first));
  const Truth due = hn::And(flying, t_record <= best.t);
  const Truth stays =
      hn::AllFalse(d, due) ? flying : record(walls, records, p, first, s, best.t, clock, flying, t_record, due);
  const std::uint32_t left = lanes_of_mask(hn::Not(stays)) << first;
  if (hn::AllFalse(d, stays)) return left;
  Num v[2] = {s.vx, s.vy};
  const Num n[2] = {c.at.nx, c.at.ny};
  reflect_in_place<Lanes, 2>(v, n, Lanes::splat(2) * (s.vx * c.at.nx + s.vy * c.at.ny));
  const Num v2 = hn::Load(d, p.v2 + first);
  restore_speed_in_place<Lanes, 2>(v, v2, v[0] * v[0] + v[1] * v[1], Lanes::splat(speed_band<double>));
  const Unevaluated<Num> after = clock_after_flight(clock, best.t);
  auto keep = [&](double* column, Num value) {
    hn::Store(hn::IfThenElse(stays, value, hn::Load(d, column + first)), d, column + first);
  };
  keep(r.x, c.at.x), keep(r.y, c.at.y), keep(r.vx, v[0]), keep(r.vy, v[1]), keep(r.vv, v[0] * v[0] + v[1] * v[1]);
  keep(p.clock_hi, after.hi), keep(p.clock_lo, after.lo);
  const auto bounces = hn::Load(di, p.bounces + first);
  hn::Store(hn::IfThenElse(hn::RebindMask(di, stays), bounces + hn::Set(di, 1), bounces), di, p.bounces + first);
  return left;
}

/// The same in 3-D: the planes, then the spheres (Table3::collision's order of kinds).
void first_hits3_of(const Walls3& walls, const Rays3& rays, int first, Hits& hits) {
  const D d;
  Lanes lanes;
  const Ray3Lanes<Num> s{hn::Load(d, rays.x + first),  hn::Load(d, rays.y + first),  hn::Load(d, rays.z + first),
                         hn::Load(d, rays.vx + first), hn::Load(d, rays.vy + first), hn::Load(d, rays.vz + first),
                         hn::Load(d, rays.t + first),  hn::Load(d, rays.vv + first)};
  const Num t_end = hn::Load(d, rays.t_end + first);
  Best best(t_end);
  for (int i = 0; i < walls.plane_count; ++i) best.keep(straight_exit_time(lanes, s, lanes_of(walls.planes[i]), t_end), 0, i);
  for (int i = 0; i < walls.sphere_count; ++i)
    best.keep(straight_exit_time(lanes, s, lanes_of(walls.spheres[i]), t_end), 2, i);
  best.store(lanes, first, hits);
}

}  // namespace

void first_hits(const Walls& walls, const Rays& rays, Hits& hits) {
  for (int first = 0; first < lanes; first += L) first_hits_of(walls, rays, first, hits);
}
void first_hits3(const Walls3& walls, const Rays3& rays, Hits& hits) {
  for (int first = 0; first < lanes; first += L) first_hits3_of(walls, rays, first, hits);
}
std::uint32_t propagate(const Walls& walls, const Records& records, Particles& particles, Hits& hits) {
  std::uint32_t left = 0;
  for (int first = 0; first < lanes; first += L) left |= propagate_of(walls, records, particles, first, hits);
  return left;
}

}  // namespace billiards::dynamics::free_lanes::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace billiards::dynamics::free_lanes {

Kernel kernel_of(std::int64_t target) { BILLIARDS_KERNEL_OF(target, first_hits) }
Kernel3 kernel3_of(std::int64_t target) { BILLIARDS_KERNEL_OF(target, first_hits3) }
Propagator propagator_of(std::int64_t target) { BILLIARDS_KERNEL_OF(target, propagate) }

}  // namespace billiards::dynamics::free_lanes
#endif
