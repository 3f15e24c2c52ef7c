// Kick statistics of the driven 3-D Sinai billiard, m = 1 (docs/3d.md, "The Sinai tables' excess of Var ΔE": the excess of
// Var ΔE, an echo between parallel walls).  In the oscillating frame w = v − (F/mω) sin θ(t)
// the velocity is constant in flight, so ε = ½m|w|² changes only at collisions, by the kick
// κ = 2m(a + b)b with a = w·n, b = (F·n/mω) sin θ; with Δt a whole number of drive periods
// ΔE = Σκ exactly.  The theory's g2 is E[Σκ²] = Σ 2a²(F·n)²/(mω²) with independent phases; this
// program measures, per particle, Σκ², its theory along the same path, the cross terms
// Σ_{k≠l} κ_k κ_l by lag, by the kind of wall pair, in echo triples (against their J₂
// prediction, kick_echo.hpp) and in longer chains on one axis, and the same sums for the frozen
// (undriven) path with the drive's phase averaged in closed form: (2/mω²)|Σ a_k (F·n_k) e^{iωt_k}|².
// Every value is an ensemble mean with its standard error, relative to g2Δt.
//
//   bench_sinai3_kicks [--R 0.25] [--omega-pi 320] [--dt 10] [--n 20000] [--seed 1] [--F 10]
//                      [--threads 2] [--lags 6] [--isotropy N] [--dump kicks.csv]
//   bench_sinai3_kicks --spectrum W1,W2,... (ω/π) [--n N]: the frozen paths' cross terms only
#include "kick_echo.hpp"

#include "billiards/analysis.hpp"
#include "billiards/dynamics/table3.hpp"
#include "billiards/geometry3/shape3_file.hpp"

#include <fmt/core.h>

#include <array>
#include <cmath>
#include <complex>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <thread>
#include <vector>

using namespace billiards;
using dynamics::Vec3;
using namespace billiards::bench;

namespace {

// Per-particle sums; ensemble means and standard errors are taken over particles.
enum Column {
  dE,            // E(Δt) − E0 from the lab-frame velocity
  dE2,           // (ΔE − g1Δt)²: its mean is Var ΔE
  sum_k2,        // Σκ²
  theory_k2,     // Σ 2a²(F·n)²/(mω²): the same with the phase averaged
  cross,         // (Σκ)² − Σκ² − (g1Δt)²: Σ_{k≠l} κ_k κ_l less the square of the mean
  face_k2,       // Σκ² on the cube's faces
  ball_k2,       // Σκ² on the ball
  face_theory,   // Σ 2a²(F·n)²/(mω²) on the faces
  ball_theory,   // ... on the ball
  cross_opp,     // 2κ_kκ_{k+1} for consecutive hits on opposite faces
  cross_adj,     // ... adjacent faces (sharing an edge)
  cross_ball,    // ... a face and the ball
  cross_short,   // 2κ_kκ_{k+1} with ω(t_{k+1} − t_k) < 2π (within one drive period)
  frozen_white,  // undriven path: Σ 2a²(F·n)²/(mω²)
  frozen_total,  // undriven path: (2/mω²)|Σ a (F·n) e^{iωt}|²
  collisions,
  lab_mismatch,  // |ΔE − Σκ|: zero up to rounding when Δt is whole periods
  echo_measured, // 2κ_pκ_q over echo triples (see echoes)
  echo_driven,   // their prediction −4a²F_α²J₂(K)/(mω²) along the driven path
  echo_frozen,   // ... along the undriven path
  cross_other,   // the cross terms that are not echo triples
  chain1,        // 2κ_jκ_k for hits on one axis's faces with no ball hit between, next on the axis
  chain3,        // ... third on the axis (the second is the echo triple)
  chain4,        // ... fourth or later
  cross_rest,    // the cross terms outside such chains
  columns_before_lags
};

struct Options {
  double R = 0.25, omega_pi = 320, dt = 10, F = 10;
  std::size_t n = 20000, seed = 1, isotropy = 0;
  int threads = 2, lags = 6;
  std::vector<double> spectrum;  // ω/π values: the frozen-path spectrum only, no driven runs
  std::string dump;              // a CSV of every driven kick, for further analysis
};

Options parse(int argc, char** argv) {
  Options o;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string k = argv[i];
    const double v = std::atof(argv[i + 1]);
    if (k == "--R") o.R = v;
    else if (k == "--omega-pi") o.omega_pi = v;
    else if (k == "--dt") o.dt = v;
    else if (k == "--F") o.F = v;
    else if (k == "--n") o.n = std::size_t(v);
    else if (k == "--seed") o.seed = std::size_t(v);
    else if (k == "--threads") o.threads = int(v);
    else if (k == "--lags") o.lags = int(v);
    else if (k == "--isotropy") o.isotropy = std::size_t(v);
    else if (k == "--dump") o.dump = argv[i + 1];
    else if (k == "--spectrum")
      for (const char* p = argv[i + 1]; *p;) {
        char* end = nullptr;
        o.spectrum.push_back(std::strtod(p, &end));
        p = *end == ',' ? end + 1 : end;
      }
    else {
      fmt::print(stderr, "bench_sinai3_kicks: unknown option {}\n", k);
      std::exit(2);
    }
  }
  return o;
}

void particle_row(const dynamics::Table3& table, const dynamics::PeriodicDriveFlight3& flight, const Options& o,
                  double g1dt, std::size_t i, double* row, std::string* dump) {
  dynamics::ParticleRng rng(o.seed, i);
  const auto s0 = dynamics::sample_microcanonical(table, 1.0, rng);  // E0 = 1/2, m = 1
  double dE_lab = 0;
  const auto kicks = driven_kicks(table, flight, s0, o.dt, dE_lab);
  if (dump)
    for (std::size_t k = 0; k < kicks.size(); ++k) {
      const auto& q = kicks[k];
      *dump += fmt::format("{},{},{:.17g},{},{},{:.17g},{:.17g},{:.17g},{:.17g},{:.17g},{:.17g},{:.17g},{:.17g},{:.17g},{:.17g},{:.17g}\n",
                           i, k, q.t, q.wall.kind, q.wall.index, q.n[0], q.n[1], q.n[2], q.x[0], q.x[1], q.x[2], q.w[0], q.w[1], q.w[2],
                           q.a, q.kappa);
    }
  const double w2 = flight.omega * flight.omega;
  double sum = 0;
  for (std::size_t k = 0; k < kicks.size(); ++k) {
    const auto& q = kicks[k];
    const bool ball = is_ball(q.wall);
    const double th = 2 * q.a * q.a * q.Fn * q.Fn / w2;
    sum += q.kappa;
    row[sum_k2] += q.kappa * q.kappa;
    row[theory_k2] += th;
    row[ball ? ball_k2 : face_k2] += q.kappa * q.kappa;
    row[ball ? ball_theory : face_theory] += th;
    for (int lag = 1; lag <= o.lags && k + lag < kicks.size(); ++lag)
      row[columns_before_lags + lag - 1] += 2 * q.kappa * kicks[k + lag].kappa;
    if (k + 1 < kicks.size()) {
      const auto& r = kicks[k + 1];
      const double c = 2 * q.kappa * r.kappa;
      if (ball || is_ball(r.wall)) row[cross_ball] += c;
      else if (q.n.dot(r.n) < -0.5) row[cross_opp] += c;
      else row[cross_adj] += c;
      if (flight.omega * (r.t - q.t) < 2 * geometry::pi) row[cross_short] += c;
    }
  }
  echoes(table, kicks, flight.accel, flight.omega, [&](int p, int, int q, double predicted) {
    row[echo_measured] += 2 * kicks[p].kappa * kicks[q].kappa;
    row[echo_driven] += predicted;
  });
  std::array<std::vector<int>, 3> chain;  // per axis, its face hits since the last ball hit
  for (int k = 0; k < int(kicks.size()); ++k) {
    if (is_ball(kicks[k].wall)) {
      for (auto& c : chain) c.clear();
      continue;
    }
    int axis = 0;
    kicks[k].n.cwiseAbs().maxCoeff(&axis);
    auto& c = chain[std::size_t(axis)];
    for (int j = 0; j < int(c.size()); ++j) {
      const int sublag = int(c.size()) - j;
      if (sublag != 2) row[sublag == 1 ? chain1 : sublag == 3 ? chain3 : chain4] += 2 * kicks[c[j]].kappa * kicks[k].kappa;
    }
    c.push_back(k);
  }
  row[dE] = dE_lab;
  row[dE2] = (dE_lab - g1dt) * (dE_lab - g1dt);
  row[cross] = sum * sum - row[sum_k2] - g1dt * g1dt;
  row[cross_other] = row[cross] - row[echo_measured];
  row[cross_rest] = row[cross_other] - row[chain1] - row[chain3] - row[chain4];
  row[collisions] = double(kicks.size());
  row[lab_mismatch] = std::abs(dE_lab - sum);
  std::complex<double> z = 0;
  const auto frozen = free_kicks(table, flight.accel, s0, o.dt);
  echoes(table, frozen, flight.accel, flight.omega, [&](int, int, int, double predicted) { row[echo_frozen] += predicted; });
  for (const auto& q : frozen) {
    row[frozen_white] += 2 * q.a * q.a * q.Fn * q.Fn / w2;
    z += q.a * q.Fn * std::polar(1.0, flight.omega * q.t + flight.phase0);
  }
  row[frozen_total] = 2 * std::norm(z) / w2;
}

/// (d): positions uniform in the region and velocities isotropic, from the sampler itself.
void isotropy_check(const dynamics::Table3& table, std::size_t n, double R) {
  std::array<double, 6> m{};  // ⟨v_i²⟩ (i = x, y, z), ⟨v_x v_y⟩, ⟨|x|⟩, fraction with |x| < R
  for (std::size_t i = 0; i < n; ++i) {
    dynamics::ParticleRng rng(7, i);
    const auto s = dynamics::sample_microcanonical(table, 1.0, rng);
    for (int k = 0; k < 3; ++k) m[k] += s.v[k] * s.v[k];
    m[3] += s.v[0] * s.v[1];
    m[4] += std::abs(s.x[0]);
    m[5] += std::abs(s.x[0]) < R;
  }
  for (auto& x : m) x /= double(n);
  // Exact for the unit cube minus a centred ball: ∫|x| dV = 1/4 over the cube, πR⁴/2 over the ball.
  const double pi = geometry::pi, V = 1 - 4 * pi * R * R * R / 3;
  const double mean_abs_x = (0.25 - pi * R * R * R * R / 2) / V;
  const double frac_inner = (2 * R - 4 * pi * R * R * R / 3) / V;
  fmt::print("isotropy ({} samples): <vx^2> {:.5f} <vy^2> {:.5f} <vz^2> {:.5f} (1/3, SE {:.5f}), <vx vy> {:+.5f} (0)\n",
             n, m[0], m[1], m[2], std::sqrt(4.0 / 45 / double(n)), m[3]);
  fmt::print("  <|x|> {:.5f} (exact {:.5f}), P(|x| < R) {:.5f} (exact {:.5f})\n", m[4], mean_abs_x, m[5], frac_inner);
}

/// The frozen (undriven) paths' excess (E|Z(ω)|² − E Σa²(F·n)²)/E Σa²(F·n)² at each ω: the
/// relative size of the cross terms that the theory's independent kicks leave out, to first
/// order in F, for every ω from the same paths.
void frozen_spectrum(const dynamics::Table3& table, const Vec3& F, const Options& o) {
  const std::size_t m = o.spectrum.size();
  std::vector<double> rows(o.n * (m + 1), 0.0);  // per particle: W, then |Z_j|² − W
  std::vector<std::thread> pool;
  for (int t = 0; t < o.threads; ++t)
    pool.emplace_back([&, t] {
      for (std::size_t i = std::size_t(t); i < o.n; i += std::size_t(o.threads)) {
        dynamics::ParticleRng rng(o.seed, i);
        const auto kicks = free_kicks(table, F, dynamics::sample_microcanonical(table, 1.0, rng), o.dt);
        double* row = &rows[i * (m + 1)];
        for (const auto& q : kicks) row[0] += q.a * q.a * q.Fn * q.Fn;
        for (std::size_t j = 0; j < m; ++j) {
          std::complex<double> z = 0;
          for (const auto& q : kicks) z += q.a * q.Fn * std::polar(1.0, o.spectrum[j] * geometry::pi * q.t);
          row[j + 1] = std::norm(z) - row[0];
        }
      }
    });
  for (auto& th : pool) th.join();
  auto column = [&](std::size_t k) {
    std::vector<double> x(o.n);
    for (std::size_t i = 0; i < o.n; ++i) x[i] = rows[i * (m + 1) + k];
    return analysis::sample_moments(x);
  };
  const double white = column(0).mean;
  fmt::print("frozen spectrum, R = {} dt = {} n = {} seed = {}: cross terms / white part\n", o.R, o.dt, o.n, o.seed);
  for (std::size_t j = 0; j < m; ++j) {
    const auto c = column(j + 1);
    fmt::print("  omega = {:7g} pi: {:+.4f} ± {:.4f}\n", o.spectrum[j], c.mean / white, c.se_mean / white);
  }
}

}  // namespace

int main(int argc, char** argv) {
  const Options o = parse(argc, argv);
  const auto shape = geometry3::load_shape3(BILLIARDS_SOURCE_DIR "/shapes/3d/sinai3.yaml", {{"R", fmt::format("{}", o.R)}});
  const dynamics::Table3 table(shape.region);
  if (o.isotropy) isotropy_check(table, o.isotropy, o.R);
  const double omega = o.omega_pi * geometry::pi;
  const Vec3 F = o.F * Vec3(1, 1, 1) / std::sqrt(3.0);
  if (!o.spectrum.empty()) return frozen_spectrum(table, F, o), 0;
  const dynamics::PeriodicDriveFlight3 flight{F, omega, 0};
  analysis::Drive drive;
  drive.F = F;
  drive.omega = omega;
  drive.mass = 1;
  const auto c = analysis::coefficients(geometry3::measures_of(shape.region), drive, 0.5);
  const double g2dt = c.g2 * o.dt, g1dt = c.g1 * o.dt;
  const auto fp = analysis::fokker_planck_exact_moments(c.C * o.dt, 0.5, 3);

  const int width = columns_before_lags + o.lags;
  std::vector<double> rows(o.n * std::size_t(width), 0.0);
  std::vector<std::thread> pool;
  std::vector<std::string> dumps(std::size_t(o.threads));
  for (int t = 0; t < o.threads; ++t)
    pool.emplace_back([&, t] {
      for (std::size_t i = std::size_t(t); i < o.n; i += std::size_t(o.threads))
        particle_row(table, flight, o, g1dt, i, &rows[i * std::size_t(width)], o.dump.empty() ? nullptr : &dumps[t]);
    });
  for (auto& th : pool) th.join();
  if (!o.dump.empty()) {
    std::FILE* f = std::fopen(o.dump.c_str(), "w");
    std::fputs("particle,k,t,wall_kind,wall,nx,ny,nz,x,y,z,wx,wy,wz,a,kappa\n", f);
    for (const auto& d : dumps) std::fputs(d.c_str(), f);
    std::fclose(f);
  }

  auto column = [&](int k) {
    std::vector<double> x(o.n);
    for (std::size_t i = 0; i < o.n; ++i) x[i] = rows[i * std::size_t(width) + std::size_t(k)];
    return analysis::sample_moments(x);
  };
  auto rel = [&](const char* what, int k, double reference) {
    const auto m = column(k);
    fmt::print("  {:<44} {:+8.4f} ± {:.4f}\n", what, m.mean / reference, m.se_mean / reference);
  };
  const auto e = column(dE);
  fmt::print("R = {} omega = {} pi dt = {} F = {} n = {} seed = {}: {:.2f} collisions/particle (v/lambda dt = {:.2f})\n",
             o.R, o.omega_pi, o.dt, o.F, o.n, o.seed, column(collisions).mean, o.dt / c.mean_free_path);
  const auto& var = e;
  fmt::print("  <dE> / g1dt {:+.3f} ± {:.3f};  Var dE / g2dt {:.4f} ± {:.4f}  (FP variance / g2dt {:.4f}); "
             "(Var − FP)/g2dt {:+.4f} ± {:.4f}\n",
             e.mean / g1dt, e.se_mean / g1dt, var.variance / g2dt, var.se_variance / g2dt, fp.variance / g2dt,
             (var.variance - fp.variance) / g2dt, var.se_variance / g2dt);
  fmt::print("  per-particle means, relative to g2dt = {:.6g}:\n", g2dt);
  rel("E[(dE - g1dt)^2]", dE2, g2dt);
  rel("sum kappa^2 (measured)", sum_k2, g2dt);
  rel("sum 2a^2(F.n)^2/w^2 (phase-averaged)", theory_k2, g2dt);
  rel("  faces: measured", face_k2, g2dt);
  rel("  faces: phase-averaged", face_theory, g2dt);
  rel("  ball: measured", ball_k2, g2dt);
  rel("  ball: phase-averaged", ball_theory, g2dt);
  rel("cross terms sum_{k!=l} kappa_k kappa_l - (g1dt)^2", cross, g2dt);
  for (int lag = 1; lag <= o.lags; ++lag)
    rel(fmt::format("  lag {}", lag).c_str(), columns_before_lags + lag - 1, g2dt);
  rel("  lag 1, opposite faces", cross_opp, g2dt);
  rel("  lag 1, adjacent faces", cross_adj, g2dt);
  rel("  lag 1, face and ball", cross_ball, g2dt);
  rel("  lag 1, within one drive period", cross_short, g2dt);
  rel("echo triples: measured 2 kappa_p kappa_q", echo_measured, g2dt);
  rel("echo triples: -4a^2F^2 J2(K)/w^2, driven path", echo_driven, g2dt);
  rel("echo triples: -4a^2F^2 J2(K)/w^2, frozen path", echo_frozen, g2dt);
  rel("cross terms other than echo triples", cross_other, g2dt);
  rel("  same axis, no ball between: next hit", chain1, g2dt);
  rel("  same axis, no ball between: third hit", chain3, g2dt);
  rel("  same axis, no ball between: fourth or later", chain4, g2dt);
  rel("  all other pairs, less (g1dt)^2", cross_rest, g2dt);
  rel("frozen path: white part", frozen_white, g2dt);
  rel("frozen path: total (phase-averaged)", frozen_total, g2dt);
  fmt::print("  max |dE - sum kappa| = {:.2e}\n", [&] {
    double m = 0;
    for (std::size_t i = 0; i < o.n; ++i) m = std::max(m, rows[i * std::size_t(width) + lab_mismatch]);
    return m;
  }());
}
