#include "billiards/analysis/speed_error.hpp"

#include "billiards/analysis/statistics.hpp"
#include "billiards/dynamics/collision.hpp"
#include "billiards/dynamics/ensemble.hpp"
#include "billiards/dynamics/random.hpp"

#include <boost/multiprecision/mpfr.hpp>
#include <boost/numeric/odeint.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <ctime>
#include <limits>

namespace billiards::analysis {

namespace {

using dynamics::ArcWall;
using dynamics::SegmentWall;

// ---- The exact flight -------------------------------------------------------------------

/// CPU seconds per particle of the toolkit's ensemble code (one thread, the every-flight check
/// on, as `billiard run` does), repeated until the clock has something to measure.
double exact_cpu_per_particle(const Table& table, const PeriodicDriveFlight& flight, const SpeedErrorOptions& o) {
  dynamics::RunOptions opt;
  opt.record_times = {o.t_end};
  opt.mass = o.mass;
  opt.verify_every_flight = true;
  const auto initial = dynamics::microcanonical(table, flight, std::sqrt(2 * o.energy / o.mass), o.seed);
  const std::clock_t start = std::clock();
  std::size_t runs = 0;
  do {
    dynamics::run_ensemble(table, flight, initial, opt, o.particles, 1);
    ++runs;
  } while (std::clock() - start < CLOCKS_PER_SEC / 4);
  return double(std::clock() - start) / CLOCKS_PER_SEC / double(runs * o.particles);
}

// ---- The Odeint baseline ----------------------------------------------------------------

using OdeState = std::array<double, 4>;  // x, y, vx, vy

/// How far beyond wall w the point p is (the wall's signed gap).
double beyond(const Table& table, const dynamics::WallId& w, const Vec2& p) {
  return table.visit(w, [&](const auto& wall) { return wall.gap(p); });
}

bool within_span(const Table& table, const dynamics::WallId& w, const Vec2& p) {
  return table.visit(w, [&](const auto& wall) { return wall.within_span(p); });
}

Vec2 position(const OdeState& y) { return {y[0], y[1]}; }

/// The first wall crossed outward within the step [t0, t1] of the dense output, as the last
/// time found inside by bisection (so the particle is reflected on the table's side).
template <class Dense>
Bounce first_crossing(const Table& table, const Dense& dense, const OdeState& y0, const OdeState& y1) {
  Bounce best{std::numeric_limits<double>::infinity(), {}, Vec2::Zero()};
  const double t0 = dense.previous_time(), t1 = dense.current_time();
  OdeState y;
  table.for_each_kind([&](const auto& walls, int kind) {
    for (int i = 0, n = int(walls.size()); i < n; ++i) {
      const dynamics::WallId w{kind, i};
      if (!(beyond(table, w, position(y0)) <= 0 && beyond(table, w, position(y1)) > 0)) continue;
      double a = t0, b = t1;
      while (b - a > 4 * std::numeric_limits<double>::epsilon() * std::max(1.0, b)) {
        const double m = 0.5 * (a + b);
        dense.calc_state(m, y);
        (beyond(table, w, position(y)) > 0 ? b : a) = m;
      }
      dense.calc_state(a, y);
      if (a < best.t && within_span(table, w, position(y))) best = {a, w, position(y)};
    }
  });
  return best;
}

// ---- The MPFR check ---------------------------------------------------------------------

using Real = boost::multiprecision::mpfr_float_100;

struct RealState {
  std::array<Real, 2> x, v;
  Real t;
};

/// Appendix B from s to time t: v = v_s + (F/mω)[sin θ − sin θ_s],
/// x = x_s + [v_s − (F/mω) sin θ_s](t − t_s) − (F/mω²)[cos θ − cos θ_s], θ = ω t + phase.
RealState advance(const PeriodicDriveFlight& f, const RealState& s, const Real& t) {
  const Real w = f.omega, th_s = w * s.t + f.phase0, th = w * t + f.phase0;
  const Real sin_s = sin(th_s), sin_t = sin(th), dcos = cos(th) - cos(th_s);
  RealState r{s.x, s.v, t};
  for (int i = 0; i < 2; ++i) {
    const Real a = f.accel[i];
    r.v[i] = s.v[i] + a / w * (sin_t - sin_s);
    r.x[i] = s.x[i] + (s.v[i] - a / w * sin_s) * (t - s.t) - a / (w * w) * dcos;
  }
  return r;
}

/// The wall's outward normal at x and how far beyond the wall x is, in MPFR.
std::pair<std::array<Real, 2>, Real> wall_at(const Table& table, const dynamics::WallId& w, const std::array<Real, 2>& x) {
  return table.visit(w, [&](const auto& wall) -> std::pair<std::array<Real, 2>, Real> {
    using Wall = std::decay_t<decltype(wall)>;
    if constexpr (std::is_same_v<Wall, SegmentWall>) {
      const std::array<Real, 2> n{Real(wall.normal.x()), Real(wall.normal.y())};
      return {n, n[0] * (x[0] - wall.a.x()) + n[1] * (x[1] - wall.a.y())};
    } else {
      // A circle, or an ellipse as the unit circle of its map u = L (x − c) (walls.hpp).
      const auto L = [&](int i, int j) {
        if constexpr (std::is_same_v<Wall, ArcWall>) return Real(i == j ? 1 / wall.radius : 0.0);
        else return Real(wall.map(i, j));
      };
      const Real px = x[0] - wall.center.x(), py = x[1] - wall.center.y();
      const Real ux = L(0, 0) * px + L(0, 1) * py, uy = L(1, 0) * px + L(1, 1) * py, rho = sqrt(ux * ux + uy * uy);
      const Real nx = L(0, 0) * ux + L(1, 0) * uy, ny = L(0, 1) * ux + L(1, 1) * uy, nn = sqrt(nx * nx + ny * ny);
      const Real sign = wall.focusing ? 1 : -1;
      return {{sign * nx / nn, sign * ny / nn}, sign * (rho - 1)};
    }
  });
}

Vec2 to_vec(const std::array<Real, 2>& x) { return {static_cast<double>(x[0]), static_cast<double>(x[1])}; }

// ---- Sweeps -----------------------------------------------------------------------------

double median(std::vector<double> x) {
  if (x.empty()) return std::nan("");
  std::nth_element(x.begin(), x.begin() + x.size() / 2, x.end());
  return x[x.size() / 2];
}

double variance(const std::vector<double>& x) {
  return x.size() < 2 ? std::nan("") : analysis::sample_moments(x).variance;
}

}  // namespace

Run exact_run(const Table& table, const PeriodicDriveFlight& flight, const dynamics::State& s0, double t_end) {
  Run run;
  auto s = flight.start(s0);
  dynamics::Clock clock;  // (each flight on its own clock, as in every run)
  dynamics::restart_clock(flight, s, clock);
  for (dynamics::Hit hit; (hit = dynamics::collision(table, flight, s, clock.until(t_end))).found();) {
    run.bounces.push_back({clock.after(hit.t), hit.wall, hit.point});
    dynamics::bounce(flight, s, hit);
    dynamics::restart_clock(flight, s, clock);
  }
  run.end = dynamics::on_clock(flight.advance(s, clock.until(t_end)), clock);
  run.escaped = !table.contains(run.end.x);
  return run;
}

Run odeint_run(const Table& table, const PeriodicDriveFlight& flight, const dynamics::State& s0, double t_end,
               double tolerance) {
  namespace odeint = boost::numeric::odeint;
  const auto rhs = [&flight](const OdeState& y, OdeState& dy, double t) {
    const double c = std::cos(flight.omega * t + flight.phase0);
    dy = {y[2], y[3], flight.accel.x() * c, flight.accel.y() * c};
  };
  auto dense = odeint::make_dense_output(tolerance, tolerance, odeint::runge_kutta_dopri5<OdeState>());
  // First step: a tenth of the drive's period; the controller adapts it.
  dense.initialize(OdeState{s0.x.x(), s0.x.y(), s0.v.x(), s0.v.y()}, s0.t, 0.2 * geometry::pi / flight.omega);
  Run run;
  OdeState y;
  while (dense.current_time() < t_end) {
    const OdeState y0 = dense.current_state();
    dense.do_step(rhs);
    const Bounce hit = first_crossing(table, dense, y0, dense.current_state());
    if (!hit.wall.valid() || hit.t > t_end) continue;
    run.bounces.push_back(hit);
    dense.calc_state(hit.t, y);
    const Vec2 v = dynamics::reflect(Vec2(y[2], y[3]), table.normal_at(hit.wall, hit.x));
    dense.initialize(OdeState{y[0], y[1], v.x(), v.y()}, hit.t, dense.current_time_step());
  }
  dense.calc_state(t_end, y);
  run.end.x = position(y);
  run.end.v = Vec2(y[2], y[3]);
  run.end.t = t_end;
  run.escaped = !table.contains(run.end.x);
  return run;
}

MpfrCheck mpfr_check(const Table& table, const PeriodicDriveFlight& flight, const dynamics::State& s0,
                     const Run& exact, double t_end, double mass) {
  MpfrCheck check;
  RealState s{{Real(s0.x.x()), Real(s0.x.y())}, {Real(s0.v.x()), Real(s0.v.y())}, Real(s0.t)};
  for (const Bounce& b : exact.bounces) {
    // The bracket starts far wider than the toolkit's own error and far narrower than a
    // flight; it widens while chaos separates the two trajectories.
    const auto f = [&](const Real& t) { return wall_at(table, b.wall, advance(flight, s, t).x).second; };
    Real lo, hi;
    for (double half = 1e-8;; half *= 4) {
      if (half > 1e-3) return check;
      lo = max(s.t, Real(b.t) - half), hi = Real(b.t) + half;
      if (f(lo) < 0 && f(hi) > 0) break;
    }
    for (int k = 0; k < 110; ++k) {
      const Real m = (lo + hi) / 2;
      (f(m) > 0 ? hi : lo) = m;
    }
    s = advance(flight, s, lo);
    if (&b == &exact.bounces.front()) check.first_collision = to_vec(s.x);
    const auto [n, ignored] = wall_at(table, b.wall, s.x);
    const Real vn = s.v[0] * n[0] + s.v[1] * n[1];
    for (int i = 0; i < 2; ++i) s.v[i] -= 2 * vn * n[i];
  }
  s = advance(flight, s, Real(t_end));
  check.confirmed = true;
  check.x = to_vec(s.x);
  check.energy = static_cast<double>(Real(0.5) * mass * (s.v[0] * s.v[0] + s.v[1] * s.v[1]));
  return check;
}

std::vector<SpeedErrorRow> speed_error(const Table& table, const PeriodicDriveFlight& flight,
                                       const SpeedErrorOptions& o) {
  const std::size_t n = o.particles;
  const double speed = std::sqrt(2 * o.energy / o.mass);
  std::vector<dynamics::State> initial(n);
  for (std::size_t i = 0; i < n; ++i) {
    dynamics::ParticleRng rng(o.seed, i);  // exactly the initial conditions of `billiard run`
    initial[i] = dynamics::sample_microcanonical(table, speed, rng);
  }
  std::vector<Run> reference(n);
  std::size_t collisions = 0, escapes = 0;
  for (std::size_t i = 0; i < n; ++i) {
    reference[i] = exact_run(table, flight, initial[i], o.t_end);
    collisions += reference[i].bounces.size();
    escapes += reference[i].escaped;
  }
  std::vector<double> all_dE;
  for (const Run& r : reference) all_dE.push_back(dynamics::kinetic_energy(r.end, o.mass) - o.energy);
  const auto moments = analysis::sample_moments(all_dE);

  // The exact flight against MPFR on the first particles.
  std::vector<double> dE_exact, dE_mpfr, dx, dx_first;
  std::size_t unconfirmed = 0;
  for (std::size_t i = 0; i < std::min(n, o.mpfr_particles); ++i) {
    const MpfrCheck c = mpfr_check(table, flight, initial[i], reference[i], o.t_end, o.mass);
    if (!c.confirmed) {
      ++unconfirmed;
      continue;
    }
    dE_exact.push_back(all_dE[i]);
    dE_mpfr.push_back(c.energy - o.energy);
    dx.push_back((c.x - reference[i].end.x).norm());
    if (!reference[i].bounces.empty()) dx_first.push_back((c.first_collision - reference[i].bounces[0].x).norm());
  }
  SpeedErrorRow exact{"exact", flight.omega, 0, n, escapes, unconfirmed};
  exact.cpu_seconds_per_time = exact_cpu_per_particle(table, flight, o) / o.t_end;
  exact.var_dE = moments.variance;
  exact.var_dE_error = std::abs(variance(dE_exact) - variance(dE_mpfr));
  exact.var_dE_se = moments.se_variance;
  exact.median_position_error = median(dx);
  exact.median_first_collision_error = median(dx_first);
  exact.collisions_per_particle = double(collisions) / double(n);
  std::vector<SpeedErrorRow> rows{exact};

  for (const double tol : o.tolerances) {
    std::vector<Run> runs(n);
    const std::clock_t start = std::clock();
    for (std::size_t i = 0; i < n; ++i) runs[i] = odeint_run(table, flight, initial[i], o.t_end, tol);
    const double cpu = double(std::clock() - start) / CLOCKS_PER_SEC;
    SpeedErrorRow row{"odeint", flight.omega, tol, n};
    std::vector<double> dE, dE_ref, errors, errors_first;
    std::size_t bounces = 0;
    for (std::size_t i = 0; i < n; ++i) {
      bounces += runs[i].bounces.size();
      if (runs[i].escaped) {
        ++row.escapes;
        continue;
      }
      dE.push_back(dynamics::kinetic_energy(runs[i].end, o.mass) - o.energy);
      dE_ref.push_back(all_dE[i]);
      errors.push_back((runs[i].end.x - reference[i].end.x).norm());
    }
    for (std::size_t i = 0; i < n; ++i)
      if (!runs[i].bounces.empty() && !reference[i].bounces.empty())
        errors_first.push_back((runs[i].bounces[0].x - reference[i].bounces[0].x).norm());
    row.cpu_seconds_per_time = cpu / double(n) / o.t_end;
    row.var_dE = variance(dE);
    row.var_dE_error = std::abs(row.var_dE - variance(dE_ref));
    row.var_dE_se = moments.se_variance;
    row.median_position_error = median(errors);
    row.median_first_collision_error = median(errors_first);
    row.collisions_per_particle = double(bounces) / double(n);
    rows.push_back(row);
  }
  return rows;
}

SpeedRatios speed_ratios(const std::vector<SpeedErrorRow>& rows) {
  SpeedRatios out;
  for (const auto& r : rows)
    if (r.method == "exact") out.exact = &r;
  if (!out.exact) return out;
  const auto keep_cheaper = [](const SpeedErrorRow*& best, const SpeedErrorRow& r) {
    if (!best || r.cpu_seconds_per_time < best->cpu_seconds_per_time) best = &r;
  };
  for (const auto& r : rows) {
    if (r.method != "odeint") continue;
    keep_cheaper(out.cheapest, r);
    if (r.escapes > 0) continue;
    if (r.var_dE_error <= out.exact->var_dE_error) keep_cheaper(out.equal, r);
    if (r.var_dE_error <= r.var_dE_se) keep_cheaper(out.within_se, r);
  }
  return out;
}

}  // namespace billiards::analysis
