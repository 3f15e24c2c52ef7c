#include "billiards/analysis/lyapunov.hpp"

#include "billiards/analysis/statistics.hpp"

namespace billiards::analysis {

Eigen::Matrix4d collision_jacobian(const Vec2& v, const Vec2& n, double kappa, const Vec2& a) {
  const double vn = v.dot(n);
  const Eigen::Matrix2d I = Eigen::Matrix2d::Identity();
  const Eigen::Matrix2d R = I - 2 * n * n.transpose();
  // δt = −nᵀδx/(n·v); δx_c = P δx with P = I − v nᵀ/(n·v); δn = κ P δx.
  const Eigen::Matrix2d P = I - v * n.transpose() / vn;
  const Eigen::Matrix2d C =
      2 * a.dot(n) / vn * n * n.transpose() - 2 * kappa * (n * v.transpose() + vn * I) * P;
  Eigen::Matrix4d J = Eigen::Matrix4d::Zero();
  J.topLeftCorner<2, 2>() = R;
  J.bottomRightCorner<2, 2>() = R;
  J.bottomLeftCorner<2, 2>() = C;
  return J;
}

void orthonormalize(TangentBasis& q, std::array<double, 4>& logs) {
  for (int j = 0; j < 4; ++j) {
    for (int i = 0; i < j; ++i) q.col(j) -= q.col(i).dot(q.col(j)) * q.col(i);
    const double r = q.col(j).norm();
    logs[j] += std::log(r);
    q.col(j) /= r;
  }
}

TangentBasis initial_tangent_basis() {
  TangentBasis q;
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) q(i, j) = std::sin(1.0 + 4 * i + j) + (i == j ? 2 : 0);
  std::array<double, 4> ignored{};
  orthonormalize(q, ignored);
  return q;
}

std::size_t LyapunovSpectrum::escapes() const {
  std::size_t n = 0;
  for (const auto& t : trajectories) n += t.escaped;
  return n;
}

LyapunovSpectrum summarize(std::vector<LyapunovTrajectory> trajectories) {
  LyapunovSpectrum out;
  out.trajectories = std::move(trajectories);
  for (int k = 0; k < 4; ++k) {
    std::vector<double> per_time, per_collision;
    for (const auto& t : out.trajectories) {
      if (t.escaped || t.collisions == 0) continue;
      per_time.push_back(t.log_stretch[k] / t.time);
      per_collision.push_back(t.log_stretch[k] / double(t.collisions));
    }
    if (per_time.size() < 2) continue;
    const auto mt = sample_moments(per_time), mc = sample_moments(per_collision);
    out.per_time[k] = {mt.mean, mt.se_mean};
    out.per_collision[k] = {mc.mean, mc.se_mean};
  }
  return out;
}

}  // namespace billiards::analysis
