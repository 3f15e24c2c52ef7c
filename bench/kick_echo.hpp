// Kicks of the driven 3-D Sinai billiard (the cube minus a ball) and the echo between parallel
// faces that makes Var ΔE differ from g2 Δt there (docs/3d.md, "The Sinai tables' excess of
// Var ΔE"): shared by bench_sinai3_kicks and tests/test_driven3.cpp.  Mass 1.
#pragma once

#include "billiards/dynamics/table3.hpp"

#include <array>
#include <cmath>
#include <vector>

namespace billiards::bench {

using dynamics::Vec3;

/// One collision in the oscillating frame w = v − (F/mω) sin θ, where w is constant in flight:
/// the kick κ = ½|w'|² − ½|w|² = 2(a + b)b, with a = w·n and b = (F·n/ω) sin θ.
struct Kick {
  double t, a, Fn, kappa;
  dynamics::WallId wall;
  Vec3 n, x, w;  // normal, hit point, oscillating-frame velocity before the hit
};

inline bool is_ball(const dynamics::WallId& wall) { return wall.kind == dynamics::wall_kind3::sphere; }

/// Echo triples: hits p, m, q on the faces normal to one axis α (so p and q on the same face,
/// m on the opposite one) with no ball hit between p and q.  The flights p → m and m → q then
/// take the same time L/|w_α| (the motion along α is a free bounce between the two faces), so
/// the kick at m, which changes |w_α| by −2(F·n_m/mω) sin θ_m, shifts θ_q by K sin θ_m with
/// K = 2|F_α| L/(m w_α²) and θ_p + θ_q = 2θ_m ± K sin θ_m + O(F/ω) whatever the ω: the
/// standard map's echo (Rechester & White 1980).  Averaged over θ_m,
/// E[κ_p κ_q] = −2 w_α² F_α² J₂(K)/(m ω²), with J₂ the Bessel function, which the theory's
/// independent kicks leave out.  Calls f(p, m, q, prediction of 2E[κ_p κ_q]) for each triple.
template <class Visit>
void echoes(const dynamics::Table3& table, const std::vector<Kick>& kicks, const Vec3& accel, double omega,
            Visit f) {
  std::array<int, 3> last{-1, -1, -1}, before{-1, -1, -1};
  for (int k = 0; k < int(kicks.size()); ++k) {
    if (is_ball(kicks[k].wall)) {
      last = before = {-1, -1, -1};
      continue;
    }
    int axis = 0;
    kicks[k].n.cwiseAbs().maxCoeff(&axis);
    if (before[axis] >= 0) {
      const auto& m = kicks[last[axis]];
      const double L = table.hi()[axis] - table.lo()[axis], F = accel[axis], s2 = m.a * m.a;
      f(before[axis], last[axis], k, -4 * s2 * F * F * std::cyl_bessel_j(2.0, 2 * std::abs(F) * L / s2) / (omega * omega));
    }
    before[axis] = last[axis];
    last[axis] = k;
  }
}

/// The driven path of one particle: its kicks and its lab-frame ΔE.
inline std::vector<Kick> driven_kicks(const dynamics::Table3& table, const dynamics::PeriodicDriveFlight3& flight,
                               const dynamics::State3& s0, double dt, double& dE) {
  std::vector<Kick> kicks;
  auto s = flight.start(s0);
  const Vec3 amp_v = flight.accel / flight.omega;
  while (true) {
    const auto hit = table.collision(flight, s, dt);
    if (!hit.found()) break;
    const auto before = flight.advance(s, hit.t);
    const Vec3 u = amp_v * before.sin_phase, w = before.v - u;
    dynamics::bounce(flight, s, hit);
    const Vec3 w_after = s.v - u;
    kicks.push_back({hit.t, w.dot(hit.normal), flight.accel.dot(hit.normal),
                     0.5 * (w_after.squaredNorm() - w.squaredNorm()), hit.wall, hit.normal, hit.point, w});
  }
  dE = 0.5 * (flight.advance(s, dt).v.squaredNorm() - s0.v.squaredNorm());
  return kicks;
}

/// The undriven path from the same start: hit times, normal speeds and normals.
inline std::vector<Kick> free_kicks(const dynamics::Table3& table, const Vec3& accel, dynamics::State3 s, double dt) {
  std::vector<Kick> kicks;
  const double v2 = s.v.squaredNorm();
  while (true) {
    const auto hit = table.collision(dynamics::FreeFlight3{}, s, dt);
    if (!hit.found()) break;
    kicks.push_back({hit.t, s.v.dot(hit.normal), accel.dot(hit.normal), 0, hit.wall, hit.normal, hit.point, s.v});
    dynamics::bounce(dynamics::FreeFlight3{}, s, hit);
    dynamics::restore_speed(s.v, v2);
  }
  return kicks;
}

}  // namespace billiards::bench
