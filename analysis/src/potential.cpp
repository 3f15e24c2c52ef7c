#include "billiards/analysis/potential.hpp"

#include "billiards/geometry/measures.hpp"

#include <boost/math/tools/minima.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <vector>

namespace billiards::analysis {

using geometry::Vec2;

namespace {

/// Is the point of the arc's curve at parameter θ (polar angle, eccentric anomaly) within the arc?
template <class A>
bool within_arc(const A& arc, double theta) {
  double rel = arc.sweep > 0 ? theta - arc.start : arc.start - theta;
  rel = std::fmod(rel, 2 * geometry::pi);
  if (rel < 0) rel += 2 * geometry::pi;
  return rel <= std::abs(arc.sweep);
}

/// An elliptic arc's abscissa as x(φ) = cₓ + r cos(φ − φₓ).
struct AbscissaWave {
  double r, phase;
  explicit AbscissaWave(const geometry::EllipticArc& e)
      : r(std::hypot(e.semi_axes.x() * std::cos(e.angle), e.semi_axes.y() * std::sin(e.angle))),
        phase(std::atan2(-e.semi_axes.y() * std::sin(e.angle), e.semi_axes.x() * std::cos(e.angle))) {}
};

/// The abscissae at which a chord of Ω can change its number of intervals or stop being
/// smooth: joints, and the leftmost and rightmost points of arcs.  Sorted, unique.
std::vector<double> strip_breaks(const geometry::Region2& region) {
  std::vector<double> xs;
  for (const geometry::Loop* loop : region.loops())
    for (const geometry::Piece& piece : loop->pieces) {
      xs.push_back(geometry::source_of(piece).x());
      if (const auto* arc = std::get_if<geometry::Arc>(&piece)) {
        if (within_arc(*arc, 0)) xs.push_back(arc->center.x() + arc->radius);
        if (within_arc(*arc, geometry::pi)) xs.push_back(arc->center.x() - arc->radius);
      } else if (const auto* e = std::get_if<geometry::EllipticArc>(&piece)) {
        const AbscissaWave w(*e);
        for (double phi : {w.phase, w.phase + geometry::pi})
          if (within_arc(*e, phi)) xs.push_back(e->point_at(phi).x());
      }
    }
  std::sort(xs.begin(), xs.end());
  xs.erase(std::unique(xs.begin(), xs.end()), xs.end());
  return xs;
}

/// The ordinates at which the vertical line through x meets the boundary, sorted: Ω(x) is the
/// union of [y0, y1], [y2, y3], ...  x must lie strictly inside a strip (not at a break).
std::vector<double> crossings(const geometry::Region2& region, double x) {
  std::vector<double> ys;
  for (const geometry::Loop* loop : region.loops())
    for (const geometry::Piece& piece : loop->pieces) {
      if (const auto* s = std::get_if<geometry::Segment>(&piece)) {
        if (s->a.x() == s->b.x() || x < std::min(s->a.x(), s->b.x()) || x > std::max(s->a.x(), s->b.x())) continue;
        ys.push_back(s->a.y() + (x - s->a.x()) * (s->b.y() - s->a.y()) / (s->b.x() - s->a.x()));
      } else if (const auto* arc = std::get_if<geometry::Arc>(&piece)) {
        const double dx = x - arc->center.x();
        if (std::abs(dx) >= arc->radius) continue;
        const double h = std::sqrt((arc->radius - dx) * (arc->radius + dx));
        for (double dy : {h, -h})
          if (within_arc(*arc, std::atan2(dy, dx))) ys.push_back(arc->center.y() + dy);
      } else {
        const auto& e = std::get<geometry::EllipticArc>(piece);
        const AbscissaWave w(e);
        const double c = (x - e.center.x()) / w.r;
        if (std::abs(c) >= 1) continue;
        for (double phi : {w.phase + std::acos(c), w.phase - std::acos(c)})
          if (within_arc(e, phi)) ys.push_back(e.point_at(phi).y());
      }
    }
  if (ys.size() % 2) throw std::logic_error("allowed_area: a vertical line met the boundary an odd number of times");
  std::sort(ys.begin(), ys.end());
  return ys;
}

/// Bisects the predicate `p` (p(lo) ≠ p(hi)) to rounding; returns the end where p differs
/// from p(lo).
template <class Pred>
double bisect(Pred p, double lo, double hi) {
  const bool at_lo = p(lo);
  for (double mid = (lo + hi) / 2; lo < mid && mid < hi; mid = (lo + hi) / 2) (p(mid) == at_lo ? lo : hi) = mid;
  return hi;
}

/// The part of one chord where U < E: its length and the number of roots of U − E on it.
struct AllowedChord {
  double length = 0;
  int roots = 0;
};

/// Sample points along one interval of a chord, with whether U < E at each.  Where three
/// consecutive samples are forbidden but the middle one is lowest, U may dip below E between
/// them (a chord near a vertical tangent of the turning curve): the minimum there is found by
/// Brent's method and added as a sample, so that such an allowed stretch is not missed.
std::vector<std::pair<double, bool>> chord_samples(const Potential& U, double E, double x, double a, double b) {
  constexpr int samples = 32;
  auto u = [&](double y) { return U(Vec2(x, y)); };
  std::vector<double> ys(samples + 1), us(samples + 1);
  for (int k = 0; k <= samples; ++k) {
    ys[k] = k == samples ? b : a + (b - a) * k / samples;
    us[k] = u(ys[k]);
  }
  std::vector<std::pair<double, bool>> out{{ys[0], us[0] < E}};
  for (int k = 1; k <= samples; ++k) {
    if (k < samples && us[k] >= E && us[k] <= us[k - 1] && us[k] <= us[k + 1]) {
      const auto [y_min, u_min] = boost::math::tools::brent_find_minima(u, ys[k - 1], ys[k + 1], std::numeric_limits<double>::digits / 2);
      if (u_min < E && y_min > out.back().first && y_min < ys[k + 1]) {
        if (y_min < ys[k]) out.emplace_back(y_min, true);
        out.emplace_back(ys[k], false);
        if (y_min > ys[k]) out.emplace_back(y_min, true);
        continue;
      }
    }
    out.emplace_back(ys[k], us[k] < E);
  }
  return out;
}

AllowedChord allowed_chord(const geometry::Region2& region, const Potential& U, double E, double x) {
  const auto ys = crossings(region, x);
  auto allowed = [&](double y) { return U(Vec2(x, y)) < E; };
  AllowedChord c;
  for (std::size_t i = 0; i < ys.size(); i += 2) {
    const auto samples = chord_samples(U, E, x, ys[i], ys[i + 1]);
    for (std::size_t k = 0; k + 1 < samples.size(); ++k) {
      const auto [y0, in0] = samples[k];
      const auto [y1, in1] = samples[k + 1];
      if (in0 == in1) {
        if (in0) c.length += y1 - y0;
      } else {
        const double root = bisect(allowed, y0, y1);
        c.length += in0 ? root - y0 : y1 - root;
        ++c.roots;
      }
    }
  }
  return c;
}

/// Cuts of the strip (lo, hi) where the number of roots of U − E on the chord changes (the
/// chord length's square-root kinks), with lo and hi themselves.
std::vector<double> kinks(const geometry::Region2& region, const Potential& U, double E, double lo, double hi) {
  constexpr int samples = 64;
  auto roots = [&](double x) { return allowed_chord(region, U, E, x).roots; };
  std::vector<double> cuts{lo};
  double x0 = lo + (hi - lo) * 0.5 / samples;
  int r0 = roots(x0);
  for (int k = 1; k < samples; ++k) {
    const double x1 = lo + (hi - lo) * (k + 0.5) / samples;
    const int r1 = roots(x1);
    if (r1 != r0) cuts.push_back(bisect([&](double x) { return roots(x) == r0; }, x0, x1));
    x0 = x1;
    r0 = r1;
  }
  cuts.push_back(hi);
  return cuts;
}

void accumulate(Quadrature& total, const Quadrature& q) {
  total.value += q.value;
  total.error += q.error;
}

}  // namespace

Quadrature allowed_area(const geometry::Region2& region, const Potential& U, double E, double tolerance) {
  const auto breaks = strip_breaks(region);
  auto length = [&](double x) { return allowed_chord(region, U, E, x).length; };
  Quadrature area;
  for (std::size_t i = 0; i + 1 < breaks.size(); ++i) {
    const auto cuts = kinks(region, U, E, breaks[i], breaks[i + 1]);
    for (std::size_t j = 0; j + 1 < cuts.size(); ++j)
      accumulate(area, integrate_adaptive(length, cuts[j], cuts[j + 1], tolerance));
  }
  return area;
}

Quadrature density_of_states(const geometry::Region2& region, const Potential& U, double E, double mass,
                             double tolerance) {
  const Quadrature a = allowed_area(region, U, E, tolerance);
  const double factor = 2 * geometry::pi / mass;  // d B_d/m with d = 2
  return {factor * a.value, factor * a.error};
}

ScalarField speed_field(Potential U, double E, double mass) {
  return [U = std::move(U), E, mass](const Vec2& x) { return local_speed(E, U(x), mass); };
}

ScalarField collision_rate_field(Potential U, double E, double mass, double Sigma) {
  return [U = std::move(U), E, mass, Sigma](const Vec2& x) {
    return collision_rate_density(2, mass, local_speed(E, U(x), mass), Sigma);
  };
}

PotentialCoefficients potential_coefficients(const geometry::Region2& region, const Potential& U,
                                             const ForceField& F, double E, double omega, double mass,
                                             double tolerance) {
  PotentialCoefficients c;
  c.energy = E;
  c.Sigma = density_of_states(region, U, E, mass, tolerance);
  if (c.Sigma.value == 0) return c;  // no allowed region: no collisions, g1 = g2 = 0
  const ScalarField gamma = collision_rate_field(U, E, mass, c.Sigma.value);
  c.g1 = drift_g1(region, F, gamma, omega, mass, tolerance);
  c.g2 = diffusion_g2(region, F, gamma, speed_field(U, E, mass), omega, tolerance);
  // γ_E ∝ 1/Σ: Σ's relative error carries over to both.
  const double relative = c.Sigma.error / c.Sigma.value;
  c.g1.error += std::abs(c.g1.value) * relative;
  c.g2.error += std::abs(c.g2.value) * relative;
  return c;
}

Quadrature fluctuation_dissipation_g1(const geometry::Region2& region, const Potential& U, const ForceField& F,
                                      double E, double omega, double mass, double tolerance) {
  const double h = E / 100;
  constexpr int offsets[] = {-2, -1, 1, 2};
  constexpr double weights[] = {1, -8, 8, -1};  // (f(−2) − 8f(−1) + 8f(1) − f(2))/(12h)
  double derivative = 0, error = 0;
  for (int i = 0; i < 4; ++i) {
    const auto c = potential_coefficients(region, U, F, E + offsets[i] * h, omega, mass, tolerance);
    derivative += weights[i] * c.g2.value * c.Sigma.value / (12 * h);
    error += std::abs(weights[i]) * (c.g2.error * c.Sigma.value + c.g2.value * c.Sigma.error) / (12 * h);
  }
  const Quadrature Sigma = density_of_states(region, U, E, mass, tolerance);
  return {derivative / (2 * Sigma.value),
          error / (2 * Sigma.value) + std::abs(derivative) * Sigma.error / (2 * Sigma.value * Sigma.value)};
}

EnergyCoefficients energy_coefficients(const geometry::Region2& region, const Potential& U, const ForceField& F,
                                       double omega, double mass, double tolerance) {
  return [&region, U, F, omega, mass, tolerance](double E) {
    const PotentialCoefficients c = potential_coefficients(region, U, F, E, omega, mass, tolerance);
    return DriftDiffusion{c.g1.value, c.g2.value};
  };
}

}  // namespace billiards::analysis
