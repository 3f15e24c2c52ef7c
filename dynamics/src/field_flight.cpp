#include "billiards/dynamics/field_flight.hpp"

#include "billiards/geometry/input_error.hpp"

#include "billiards/dynamics/certified_scan.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace billiards::dynamics {

using Vec4 = FieldPath::Vec4;

// ---- The field --------------------------------------------------------------------------

struct FieldFlight::Model {
  double mass;
  std::optional<std::array<CoordinateFunction, 2>> field;  // F(x), or
  Vec2 uniform = Vec2::Zero();                             // a uniform F
  geometry::SourceRef field_source;                        // the scene's key of F(x), for errors
  bool driven = false;
  double omega = 0, phase = 0;
  std::optional<Potential> potential;
  double tolerance, scale;  // relative tolerance; the table's size
  double accel_bound = 0;   // A ≥ |∇U|/m + |F|/m over the bounding box

  Vec2 amplitude(const Vec2& x) const { return field ? Vec2((*field)[0](x), (*field)[1](x)) : uniform; }
  Vec2 gradient(const Vec2& x) const { return Vec2(potential->gradient[0](x), potential->gradient[1](x)); }
  /// ẍ at x when the drive's phase is θ.
  Vec2 acceleration(const Vec2& x, double theta) const {
    Vec2 a = Vec2::Zero();
    if (driven) a += amplitude(x) * std::cos(theta);
    if (potential) a -= gradient(x);
    return a / mass;
  }
  /// |∇U|/m + |F|/m at x.
  double acceleration_size(const Vec2& x) const {
    double a = 0;
    if (driven) a += amplitude(x).norm();
    if (potential) a += gradient(x).norm();
    return a / mass;
  }
};

namespace {

/// A force that is not finite at x, in the box: bad input, at the scene's key of the potential
/// when its gradient is not finite there, else at the field's.
[[noreturn]] void refuse_force_at(const FieldFlight::Model& m, const Vec2& x) {
  const bool potential = m.potential && (!m.field || !m.gradient(x).allFinite());
  const geometry::SourceRef& where = potential ? m.potential->source : m.field_source;
  throw InputError(where.file, where.line,
                   fmt::format("the force {}is not finite at (x, y) = ({:.9g}, {:.9g}), in the table's bounding box",
                               potential ? "−∇U " : "", x.x(), x.y()));
}

/// Bound on |∇U|/m + |F|/m over the box: the largest value on a 129 × 129 grid plus the
/// largest difference between neighbouring grid values (a Lipschitz margin: any point is within
/// h/√2 of a grid point, and a neighbour difference estimates the change over h).  Doubled for
/// the event search, which must also cover the dense output's own deviation from it.
double acceleration_bound(const FieldFlight::Model& m, const Vec2& lo, const Vec2& hi) {
  constexpr int n = 128;
  std::vector<double> a((n + 1) * (n + 1));
  double top = 0, jump = 0;
  for (int i = 0; i <= n; ++i)
    for (int j = 0; j <= n; ++j) {
      const Vec2 x = lo + Vec2((hi - lo).x() * i / n, (hi - lo).y() * j / n);
      const double v = m.acceleration_size(x);
      if (!std::isfinite(v)) refuse_force_at(m, x);
      a[i * (n + 1) + j] = v;
      top = std::max(top, v);
      if (i > 0) jump = std::max(jump, std::abs(v - a[(i - 1) * (n + 1) + j]));
      if (j > 0) jump = std::max(jump, std::abs(v - a[i * (n + 1) + j - 1]));
    }
  return 2 * (top + jump);
}

// Dormand–Prince 5(4) (DOPRI5): the tableau, the error weights and the dense-output weights.
constexpr double a21 = 1.0 / 5;
constexpr double a31 = 3.0 / 40, a32 = 9.0 / 40;
constexpr double a41 = 44.0 / 45, a42 = -56.0 / 15, a43 = 32.0 / 9;
constexpr double a51 = 19372.0 / 6561, a52 = -25360.0 / 2187, a53 = 64448.0 / 6561, a54 = -212.0 / 729;
constexpr double a61 = 9017.0 / 3168, a62 = -355.0 / 33, a63 = 46732.0 / 5247, a64 = 49.0 / 176,
                 a65 = -5103.0 / 18656;
constexpr double a71 = 35.0 / 384, a73 = 500.0 / 1113, a74 = 125.0 / 192, a75 = -2187.0 / 6784, a76 = 11.0 / 84;
constexpr double c2 = 1.0 / 5, c3 = 3.0 / 10, c4 = 4.0 / 5, c5 = 8.0 / 9;
constexpr double e1 = 71.0 / 57600, e3 = -71.0 / 16695, e4 = 71.0 / 1920, e5 = -17253.0 / 339200, e6 = 22.0 / 525,
                 e7 = -1.0 / 40;
constexpr double d1 = -12715105075.0 / 11282082432, d3 = 87487479700.0 / 32700410799,
                 d4 = -10690763975.0 / 1880347072, d5 = 701980252875.0 / 199316789632,
                 d6 = -1453857185.0 / 822651844, d7 = 69997945.0 / 29380423;

/// Integrates one flight step by step, appending every accepted step to a path.
class Integrator {
 public:
  Integrator(const FieldFlight::Model& m, const FieldState& s, FieldPath& path)
      : m_(m), path_(path), theta0_(double(s.phase)) {
    y_ << s.x, s.v;
    k1_ = rhs(0, y_);
    h_ = s.step > 0 ? s.step : first_step(s);
  }

  /// Takes the next accepted step; returns it (it is also appended to the path).
  const FieldPath::Step& next() {
    for (int tries = 0;; ++tries) {
      if (tries > 1000 || !(h_ > 4 * scan::eps<double> * std::max(tau_, 1.0)))
        throw std::runtime_error("the field integrator cannot meet its tolerance (step size underflow)");
      const double h = h_;
      const Vec4 k2 = rhs(tau_ + c2 * h, y_ + h * a21 * k1_);
      const Vec4 k3 = rhs(tau_ + c3 * h, y_ + h * (a31 * k1_ + a32 * k2));
      const Vec4 k4 = rhs(tau_ + c4 * h, y_ + h * (a41 * k1_ + a42 * k2 + a43 * k3));
      const Vec4 k5 = rhs(tau_ + c5 * h, y_ + h * (a51 * k1_ + a52 * k2 + a53 * k3 + a54 * k4));
      const Vec4 k6 = rhs(tau_ + h, y_ + h * (a61 * k1_ + a62 * k2 + a63 * k3 + a64 * k4 + a65 * k5));
      const Vec4 y1 = y_ + h * (a71 * k1_ + a73 * k3 + a74 * k4 + a75 * k5 + a76 * k6);
      const Vec4 k7 = rhs(tau_ + h, y1);
      const Vec4 err = h * (e1 * k1_ + e3 * k3 + e4 * k4 + e5 * k5 + e6 * k6 + e7 * k7);
      // Error per component against tolerance × (its size + a floor: the table's size for
      // positions, the speed for velocities), so that a component passing through zero does
      // not force tiny steps.
      const double speed = y_.tail<2>().norm();
      double norm = 0;
      for (int i = 0; i < 4; ++i) {
        const double floor = i < 2 ? m_.scale : speed;
        const double sc = m_.tolerance * (floor + std::max(std::abs(y_[i]), std::abs(y1[i])));
        norm += (err[i] / sc) * (err[i] / sc);
      }
      norm = std::sqrt(norm / 4);
      // Standard controller: safety 0.9, growth within [0.2, 5] (no growth after a rejection).
      const double factor = norm > 0 ? 0.9 * std::pow(norm, -0.2) : 5.0;
      if (!(norm <= 1)) {
        h_ = h * std::clamp(factor, 0.2, 1.0);
        continue;
      }
      FieldPath::Step step{tau_, h, {}};
      step.r[0] = y_;
      step.r[1] = y1 - y_;
      step.r[2] = h * k1_ - step.r[1];
      step.r[3] = step.r[1] - h * k7 - step.r[2];
      step.r[4] = h * (d1 * k1_ + d3 * k3 + d4 * k4 + d5 * k5 + d6 * k6 + d7 * k7);
      path_.steps.push_back(step);
      tau_ += h;
      y_ = y1;
      k1_ = k7;
      h_ = h * std::clamp(factor, 0.2, 5.0);
      return path_.steps.back();
    }
  }
  double next_step_size() const { return h_; }

 private:
  Vec4 rhs(double tau, const Vec4& y) const {
    Vec4 d;
    d.head<2>() = y.tail<2>();
    d.tail<2>() = m_.acceleration(y.head<2>(), theta0_ + m_.omega * tau);
    // (Else the steps would shrink until they underflow, a message that hides the cause: a
    // field or potential that is not finite where the particle goes, between the grid points
    // acceleration_bound checked.)
    if (!d.tail<2>().allFinite())
      throw std::runtime_error(fmt::format("the force is not finite at (x, y) = ({:.9g}, {:.9g})", y[0], y[1]));
    return d;
  }
  /// A first trial step: a small fraction of the drive's period and of the time to cross the
  /// table; the controller takes over from there.
  double first_step(const FieldState& s) const {
    double h = 0.01 * m_.scale / std::max(s.v.norm(), 1e-300);
    if (m_.driven) h = std::min(h, 0.1 / m_.omega);
    return std::min(h, 0.1 * std::sqrt(m_.scale / std::max(m_.accel_bound, 1e-300)));
  }

  const FieldFlight::Model& m_;
  FieldPath& path_;
  double theta0_;  // the drive's phase at the start of the flight (within one flight, ωτ is moderate)
  Vec4 y_, k1_;
  double tau_ = 0, h_;
};

/// One wall's scan along a path, step by step: `advance_to(τ1)` scans [resume, τ1] of the last
/// step and returns the crossing time, or +∞ (then it resumes from where it stopped).  The
/// wall's `gap_sample` bounds f'' from the acceleration bound A.
template <class Wall>
class WallScan {
 public:
  WallScan(const Wall& w, const FieldFlight::Model& m, const FieldState& s) : w_(w), m_(m) {
    scale_ = m.scale + (s.x - w.bound_center).norm();
  }

  double advance_to(const FieldPath::Step& step, double tau1) { return resume_ > tau1 ? never : scan_step(step, tau1); }

 private:
  /// (Out of line: most steps end before the scan's resume point, and that test should not pay
  /// for the scan's frame.)
  [[gnu::noinline]] double scan_step(const FieldPath::Step& step, double tau1) {
    const double start = resume_;
    auto tolerance = [&](double tau) {
      return w_.slack + 8 * scan::eps<double> * (scale_ + start + tau) + 4 * m_.tolerance * m_.scale;
    };
    auto sample = [&](double tau) {
      const Vec4 y = FieldPath::at(step, start + tau);
      return w_.gap_sample(Vec2(y.head<2>()), Vec2(y.tail<2>()), m_.accel_bound);
    };
    auto earliest = [](double tau) { return tau; };
    auto in_span = [&](const Vec2& x) { return w_.within_span(x); };
    double resume = never;
    const double tau = scan::first_outward_crossing(sample, earliest, in_span, tolerance, tau1 - start, &resume);
    if (tau != never) return start + tau;
    resume_ = start + resume;
    return never;
  }

  const Wall& w_;
  const FieldFlight::Model& m_;
  double scale_;
  double resume_ = 0;
};

}  // namespace

namespace {

/// A new empty path.  Paths of long flights hold ~10⁴ steps (~2 MB); their step buffers are
/// recycled through a small per-thread pool instead of being returned to the system after
/// every collision (fresh pages cost a page fault each: 20% of the run time, measured).
std::shared_ptr<FieldPath> new_path() {
  thread_local std::vector<std::vector<FieldPath::Step>> pool;
  auto* path = new FieldPath;
  if (!pool.empty()) {
    path->steps = std::move(pool.back());
    pool.pop_back();
  }
  return std::shared_ptr<FieldPath>(path, [](FieldPath* p) {
    if (pool.size() < 16) {
      p->steps.clear();
      pool.push_back(std::move(p->steps));
    }
    delete p;
  });
}

/// Integrates the flight from s into `path`, handing each step to `scan(step, τ1)`, which
/// returns the earliest crossing in [.., τ1] or +∞, until one is found or τ_end is passed.
template <class Scan>
double integrate_and_scan(const FieldFlight::Model& m, const FieldState& s, double tau_end, FieldPath& path,
                          Scan scan) {
  path.x0 = s.x;
  path.v0 = s.v;
  path.t0 = s.t;
  Integrator integrator(m, s, path);
  while (path.end() < tau_end) {
    // (2·10⁶ steps is ~800 drive periods at the tightest tolerance, ~350 MB: far beyond any flight
    // between two walls.)
    if (path.steps.size() > 2000000)
      throw std::runtime_error("a flight in the field met no wall within 2e6 integrator steps (no horizon given?)");
    const auto& step = integrator.next();
    const double tau = scan(step, std::min(step.tau0 + step.h, tau_end));
    if (tau != never) return tau;
  }
  return never;
}

/// The scans of every wall of a table, kind by kind.
template <class Kinds>
struct TableScans;
template <class... W>
struct TableScans<std::tuple<W...>> {
  std::tuple<std::vector<WallScan<W>>...> scans;
  TableScans(const Table& table, const FieldFlight::Model& m, const FieldState& s) {
    table.for_each_kind([&]<class K>(const Walls<K>& walls, int) {
      for (const auto& w : walls) std::get<std::vector<WallScan<K>>>(scans).emplace_back(w, m, s);
    });
  }
  /// The earliest crossing within a step (ties: the first kind, then the lower index).
  void earliest_in_step(const FieldPath::Step& step, double& tau, WallId& wall) {
    [&]<std::size_t... k>(std::index_sequence<k...>) {
      (earliest_of_kind(std::get<k>(scans), int(k), step, tau, wall), ...);
    }(std::index_sequence_for<W...>{});
  }

 private:
  template <class Scans>
  static void earliest_of_kind(Scans& scans, int kind, const FieldPath::Step& step, double& tau, WallId& wall) {
    for (std::size_t i = 0; i < scans.size(); ++i) {
      const double t = scans[i].advance_to(step, tau);
      if (t != never && (!wall.valid() || t < tau)) {
        tau = t;
        wall = {kind, int(i)};
      }
    }
  }
};

template <class Wall>
double single_wall_exit(const FieldFlight::Model& m, const FieldState& s, const Wall& w, double t_end) {
  auto path = new_path();
  WallScan<Wall> scan(w, m, s);
  const double tau = integrate_and_scan(m, s, t_end - s.t, *path,
                                        [&](const FieldPath::Step& step, double tau1) { return scan.advance_to(step, tau1); });
  s.path = path;
  return tau == never ? never : s.t + tau;
}

}  // namespace

// ---- The dense output ---------------------------------------------------------------------

Vec4 FieldPath::at(const Step& step, double tau) {
  const double th = std::clamp((tau - step.tau0) / step.h, 0.0, 1.0), th1 = 1 - th;
  return step.r[0] + th * (step.r[1] + th1 * (step.r[2] + th * (step.r[3] + th1 * step.r[4])));
}

Vec4 FieldPath::at(double tau) const {
  if (steps.empty()) return (Vec4() << x0, v0).finished();
  // The last step starting at or before τ.
  auto it = std::upper_bound(steps.begin(), steps.end(), tau, [](double t, const Step& s) { return t < s.tau0; });
  return at(it == steps.begin() ? steps.front() : *std::prev(it), tau);
}

// ---- The flight ---------------------------------------------------------------------------

FieldFlight::FieldFlight(const Force& force, const std::optional<Potential>& potential, double mass,
                         const Table& table, double tolerance) {
  auto m = std::make_shared<Model>();
  m->mass = mass;
  m->potential = potential;
  m->tolerance = tolerance;
  m->scale = (table.hi() - table.lo()).norm();
  if (force.kind == Force::Kind::field)
    m->field = force.field;
  else
    m->uniform = force.amplitude;
  m->field_source = force.field_source;
  m->driven = force.kind != Force::Kind::none;
  m->omega = force.kind == Force::Kind::constant ? 0.0 : force.omega;
  m->phase = force.kind == Force::Kind::constant ? 0.0 : force.phase;
  m->accel_bound = dynamics::acceleration_bound(*m, table.lo(), table.hi());
  model_ = m;
}

FieldState FieldFlight::start(const BasicState<double>& s) const {
  FieldState f;
  static_cast<BasicState<double>&>(f) = s;
  f.phase = reduce_phase(advance_phase(Phase(model_->phase), model_->omega, s.t));
  return f;
}

FieldState FieldFlight::advance(const FieldState& s, double t) const {
  const double tau = t - s.t;
  std::shared_ptr<const FieldPath> path = s.path;
  double next_step = s.step;
  if (!path || !path->starts_at(s) || path->end() < tau) {
    // Not searched from here (or not this far): integrate afresh, with the same steps.
    auto fresh = new_path();
    integrate_and_scan(*model_, s, tau, *fresh, [](const FieldPath::Step&, double) { return never; });
    path = fresh;
  }
  // The next flight starts with the step size the controller was using at t.
  auto it = std::upper_bound(path->steps.begin(), path->steps.end(), tau,
                             [](double x, const FieldPath::Step& st) { return x < st.tau0; });
  if (it != path->steps.begin()) next_step = std::prev(it)->h;
  const Vec4 y = path->at(tau);
  FieldState r;
  r.x = y.head<2>();
  r.v = y.tail<2>();
  r.t = t;
  r.phase = reduce_phase(advance_phase(s.phase, model_->omega, tau));
  r.step = next_step;
  return r;
}

Hit FieldFlight::first_exit(const Table& table, const FieldState& s, double t_end) const {
  TableScans<Table::Kinds> scans(table, *model_, s);
  auto path = new_path();
  Hit best;
  const double tau = integrate_and_scan(*model_, s, t_end - s.t, *path, [&](const FieldPath::Step& step, double tau1) {
    double t = tau1;
    scans.earliest_in_step(step, t, best.wall);
    return best.found() ? t : never;
  });
  s.path = path;
  if (!best.found()) return best;
  best.t = s.t + tau;
  best.point = path->at(tau).head<2>();
  best.normal = table.normal_at(best.wall, best.point);
  return best;
}

template <class Wall>
double FieldFlight::exit_time(const FieldState& s, const Wall& w, double t_end) const {
  return single_wall_exit(*model_, s, w, t_end);
}

namespace {
/// Instantiates exit_time for every wall kind (a kind added to WallKinds needs no line here).
template <class... W>
auto exit_times(std::tuple<W...>*) {
  return std::tuple{&FieldFlight::exit_time<W>...};
}
[[gnu::used]] const auto exit_times_of_every_kind = exit_times(static_cast<Table::Kinds*>(nullptr));
}  // namespace

double FieldFlight::potential(const Vec2& x) const { return model_->potential ? model_->potential->U(x) : 0.0; }
double FieldFlight::mass() const { return model_->mass; }
double FieldFlight::acceleration_bound() const { return model_->accel_bound; }

Hit collision(const Table& table, const FieldFlight& flight, const FieldState& s, double t_end) {
  return flight.first_exit(table, s, t_end);
}

}  // namespace billiards::dynamics
