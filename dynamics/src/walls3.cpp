// Exit times of straight 3-D flights (see walls3.hpp for the rules): through planes and spheres
// straight_exit3-inl.hpp's, the lanes' own source (through triangles: walls3.hpp).
#include "billiards/dynamics/walls3.hpp"

#include "billiards/dynamics/predicates.hpp"
#include "billiards/dynamics/straight_exit3.hpp"

#include <algorithm>

namespace billiards::dynamics {

int sphere_discriminant_sign_filtered(const Vec3& x, const Vec3& c, const Vec3& v, double r) {
  const Vec3 f = x - c;
  const auto d = sphere_discriminant<ScalarLanes<double>>(f.x(), f.y(), f.z(), v.x(), v.y(), v.z(), r * r * v.squaredNorm());
  if (d.D > d.bound) return 1;
  if (d.D < -d.bound) return -1;
  return sphere_discriminant_sign_exact(x, c, v, r);
}

Ray::Ray(const Vec3& x, const Vec3& v) : origin(x), dir(v) {
  v.cwiseAbs().maxCoeff(&kz);
  kx = (kz + 1) % 3;
  ky = (kx + 1) % 3;
  if (v[kz] < 0) std::swap(kx, ky);  // keeps the winding of the sheared triangle
  sx = v[kx] / v[kz];
  sy = v[ky] / v[kz];
  sz = 1 / v[kz];
}

TriangleWall::TriangleWall(const Vec3& a, const Vec3& b, const Vec3& c, double slack_)
    : p{a, b, c}, normal((b - a).cross(c - a).normalized()), slack(slack_) {
  double longest = 0;
  for (int k = 0; k < 3; ++k) {
    edge_normal[k] = (p[(k + 1) % 3] - p[k]).cross(normal).normalized();
    longest = std::max(longest, (p[(k + 1) % 3] - p[k]).norm());
  }
  span_slack = slack * longest / (b - a).cross(c - a).norm();  // slack / smallest altitude
}

/// Where the particle starts on the wall's side, the test needs normal·v > 0 in doubles (off by
/// at most 3 ε |v|); strictly inside, det < 0.  With N = (b − a) × (c − a) of the vertices as
/// stored, the exact det of the sheared vertices is −N·w (the swap of kx, ky keeps the sign)
/// for the shear's direction w = (sx, sy, 1) in the ray's axes, which is within √2 ε of
/// v / v_kz (sx, sy rounded once, |sx|, |sy| ≤ 1), with |v_kz| ≤ |v|: a flight moving away,
/// N̂·h < −δ', has det ≥ |N| (δ' − 2 ε).  In doubles each sheared coordinate is within 6 ε R
/// of its exact value (R = reach; |x|, |y| ≤ 2 R), each of u, v, e within 64 ε R² and det
/// within 240 ε R²; 512 for margin.  The stored normal, rounded from the computed cross
/// product, is within 16 ε |b − a| |c − a| / |N| of N̂.  So normal·h < −δ with
/// δ = (512 ε R² + 16 ε |b − a| |c − a|) / |N| + 8 ε keeps det > 0 as computed, and normal·v < 0.
double TriangleWall::facing_away_margin(double reach) const {
  constexpr double eps = std::numeric_limits<double>::epsilon();
  const Vec3 ab = p[1] - p[0], ac = p[2] - p[0];
  const double sides = ab.norm() * ac.norm();
  const double area2 = ab.cross(ac).norm() - 8 * eps * sides;  // |N|, not above
  if (!(area2 > 0)) return 1;
  return std::min(1.0, (512 * eps * reach * reach + 16 * eps * sides) / area2 + 8 * eps);
}

double straight_exit_time(const State3& s, const PlaneWall& w, double t_end) {
  ScalarLanes<double> scalar;
  return straight_exit_time(scalar, ray3_lanes(s), plane_lanes(w), t_end);
}

double straight_exit_time(const State3& s, const SphereWall& w, double t_end) {
  ScalarLanes<double> scalar;
  return straight_exit_time(scalar, ray3_lanes(s), sphere_lanes(w), t_end);
}

}  // namespace billiards::dynamics
