// The Fokker–Planck solution for a standard billiard: the analytic eta (eq. B4) without overflow,
// its exact moments and CDF, and the finite-volume solver against it.
#include "billiards/analysis.hpp"

#include <boost/math/distributions/non_central_chi_squared.hpp>
#include <boost/math/special_functions/bessel.hpp>
#include <catch2/catch.hpp>

#include <cmath>

using namespace billiards;

namespace {

constexpr double E0 = 0.5;

/// ∫_0^{e_max} f(E) η(E, s) dE by the trapezoidal rule in u = E^{1/4} (smooth at E = 0).
template <class F>
double integrate_eta(double s, int d, double e_max, F f, int points = 20000) {
  const double top = std::pow(e_max, 0.25), h = top / points;
  double sum = 0;
  for (int i = 1; i <= points; ++i) {
    const double u = i * h, E = u * u * u * u, weight = i == points ? h / 2 : h;  // 0 at u = 0
    sum += f(E) * analysis::fokker_planck_eta(E, s, E0, d) * 4 * u * u * u * weight;
  }
  return sum;
}

double e_max_for(double s) { return 40 * E0 + 50 * s * s; }

}  // namespace

TEST_CASE("eta at tiny s: finite, and the Gaussian of the short-time limit") {
  // Unscaled, I_{d−1}(4(d+1)/s (E0 E)^{1/4}) overflows once its argument passes ~710, i.e. s < 0.02.
  // The skewness of η grows like √s; at s = 1e-8 it moves η by < 0.1% within three sd.
  for (int d : {2, 3}) {
    const double s = 1e-8;
    const double mean = E0 + s * std::sqrt(E0), sd = std::sqrt(4 * std::pow(E0, 1.5) * s / (d + 1));
    for (double z : {-3.0, 0.0, 2.0}) {
      INFO("d = " << d << ", z = " << z);
      const double E = mean + z * sd;
      const double gauss = std::exp(-z * z / 2) / (sd * std::sqrt(2 * M_PI));
      CHECK(std::isfinite(analysis::fokker_planck_eta(E, s, E0, d)));
      CHECK(analysis::fokker_planck_eta(E, s, E0, d) == Approx(gauss).epsilon(2e-3));
    }
    // Far from E0 it underflows to zero rather than producing inf·0.
    CHECK(analysis::fokker_planck_eta(2 * E0, s, E0, d) == 0);
  }
}

TEST_CASE("exact moments (noncentral chi-squared) agree with quadrature of eta, d = 2 and 3") {
  for (int d : {2, 3}) {
    for (double s : {0.01, 0.1, 1.0, 10.0}) {
      INFO("d = " << d << ", s = " << s);
      const double top = e_max_for(s);
      const auto exact = analysis::fokker_planck_exact_moments(s, E0, d);
      CHECK(integrate_eta(s, d, top, [](double) { return 1.0; }) == Approx(1).epsilon(1e-8));
      CHECK(integrate_eta(s, d, top, [](double E) { return E; }) == Approx(exact.mean).epsilon(1e-8));
      CHECK(integrate_eta(s, d, top, [](double E) { return std::sqrt(E); }) == Approx(exact.mean_root).epsilon(1e-8));
      const double var = integrate_eta(s, d, top, [&](double E) { return (E - exact.mean) * (E - exact.mean); });
      CHECK(var == Approx(exact.variance).epsilon(1e-7));
    }
  }
}

TEST_CASE("exact moments obey the Fokker-Planck equation: d<E>/ds = <sqrt E>, and the short-time slopes") {
  for (int d : {2, 3}) {
    for (double s : {0.3, 3.0}) {
      const double ds = 1e-4 * s;
      const double slope = (analysis::fokker_planck_exact_moments(s + ds, E0, d).mean -
                            analysis::fokker_planck_exact_moments(s - ds, E0, d).mean) /
                           (2 * ds);
      CHECK(slope == Approx(analysis::fokker_planck_exact_moments(s, E0, d).mean_root).epsilon(1e-8));
    }
    // s → 0: ⟨E⟩ − E0 → g1(E0) s = √E0 s and Var → g2(E0) s = 4 E0^{3/2} s/(d+1), with s = C t.
    const double s = 1e-9;
    const auto m = analysis::fokker_planck_exact_moments(s, E0, d);
    CHECK((m.mean - E0) / s == Approx(std::sqrt(E0)).epsilon(1e-6));
    CHECK(m.variance / s == Approx(4 * std::pow(E0, 1.5) / (d + 1)).epsilon(1e-6));
  }
}

TEST_CASE("exact CDF agrees with quadrature of eta") {
  for (int d : {2, 3}) {
    for (double s : {0.1, 1.0, 10.0}) {
      const auto m = analysis::fokker_planck_exact_moments(s, E0, d);
      for (double E : {0.5 * m.mean, m.mean, m.mean + 2 * std::sqrt(m.variance)}) {
        INFO("d = " << d << ", s = " << s << ", E = " << E);
        const double by_quadrature = integrate_eta(s, d, E, [](double) { return 1.0; });
        CHECK(analysis::fokker_planck_cdf(E, s, E0, d) == Approx(by_quadrature).epsilon(1e-7));
      }
    }
  }
}

TEST_CASE("exact CDF in double: Boost's CDF carried through long double to 1e-14, narrow and wide laws") {
  // s from compare's first record times (a narrow law, λ ~ 10³) to wide ones.
  for (int d : {2, 3}) {
    for (double s : {0.0034, 0.07, 1.0, 10.0}) {
      const double c = 2.0 * (d + 1) / s;
      const boost::math::non_central_chi_squared promoted(2.0 * d, 2 * c * std::sqrt(E0));
      const auto m = analysis::fokker_planck_exact_moments(s, E0, d);
      for (double z = -4; z <= 4; z += 0.25) {
        const double E = m.mean + z * std::sqrt(m.variance);
        if (E <= 0) continue;
        INFO("d = " << d << ", s = " << s << ", E = " << E);
        CHECK(std::abs(analysis::fokker_planck_cdf(E, s, E0, d) - boost::math::cdf(promoted, 2 * c * std::sqrt(E))) < 1e-14);
      }
    }
  }
}

TEST_CASE("finite volumes (Chang-Cooper) follow the analytic eta from s = 0.01 through 0.1, 1, 10") {
  // One grid and one run per d, continued from each checkpoint.  Implicit Euler is first order in
  // time and its error dominates: with 1500 steps per leg L1 reaches 6.3e-4 (d = 3, s = 10),
  // with 3000 it is ~3e-4 at most; doubling the 3000 cells changes it by < 5%.
  for (int d : {2, 3}) {
    auto g1 = [](double E) { return std::sqrt(E); };  // in units of s = C t
    auto g2 = [d](double E) { return 4 * std::pow(E, 1.5) / (d + 1); };
    const auto grid = analysis::quartic_root_grid(e_max_for(10), 3000);
    std::vector<double> eta(grid.cells());
    double s = 0.01, initial_mass = 0;
    for (std::size_t i = 0; i < eta.size(); ++i) {
      eta[i] = analysis::fokker_planck_eta(grid.center(i), s, E0, d);
      initial_mass += eta[i] * grid.width(i);
    }
    for (double target : {0.1, 1.0, 10.0}) {
      eta = analysis::evolve_fokker_planck(grid, eta, g1, g2, target - s, 3000);
      s = target;
      double l1 = 0, mass = 0, lowest = 0;
      for (std::size_t i = 0; i < eta.size(); ++i) {
        l1 += std::abs(eta[i] - analysis::fokker_planck_eta(grid.center(i), s, E0, d)) * grid.width(i);
        mass += eta[i] * grid.width(i);
        lowest = std::min(lowest, eta[i]);
      }
      INFO("d = " << d << ", s = " << s);
      CHECK(l1 <= 1e-3);
      CHECK(lowest >= 0);
      CHECK(std::abs(mass - initial_mass) < 1e-12);  // conservative to rounding
    }
  }
}

TEST_CASE("scaled Bessel function: continuous across its two methods, exact below") {
  for (double nu : {1.0, 2.0}) {
    CHECK(analysis::scaled_bessel_i(nu, 3.0) == Approx(boost::math::cyl_bessel_i(nu, 3.0) * std::exp(-3.0)).epsilon(1e-14));
    // Boost is still finite at 650: the asymptotic series must agree there.
    const double direct = boost::math::cyl_bessel_i(nu, 650.0) * std::exp(-650.0);
    CHECK(direct == Approx(analysis::scaled_bessel_i(nu, 650.0)).epsilon(1e-13));
  }
}

TEST_CASE("Fokker-Planck solution: normalized, and its moments grow as the equation says") {
  for (int d : {2, 3}) {
    for (double s : {0.1, 1.0, 10.0}) {
      INFO("d = " << d << ", s = " << s);
      CHECK(analysis::fokker_planck_moments(s, E0, d).norm == Approx(1).epsilon(2e-6));
    }
    // Small s: d<E>/ds = <√E> ≈ √E0, dVar/ds = 4 E0^{3/2}/(d+1) (g1 = C√E, g2 = 4C E^{3/2}/(d+1)).
    const double s = 1e-3;
    const auto m = analysis::fokker_planck_moments(s, E0, d);
    CHECK((m.mean - E0) / s == Approx(std::sqrt(E0)).epsilon(2e-2));
    CHECK(m.variance / s == Approx(4 * std::pow(E0, 1.5) / (d + 1)).epsilon(2e-2));
    // At any s, d<E>/ds = <√E> (the drift g1 = C√E averaged over η): by central differences.
    const double s1 = 2.0, ds = 1e-3;
    const double slope = (analysis::fokker_planck_moments(s1 + ds, E0, d).mean -
                          analysis::fokker_planck_moments(s1 - ds, E0, d).mean) / (2 * ds);
    const int n = 200000;
    const double hi = std::pow(40 * E0 + 50 * s1 * s1, 0.25), h = hi / n;
    double root_mean = 0;
    for (int i = 1; i < n; ++i) {
      const double u = i * h;
      root_mean += u * u * analysis::fokker_planck_eta(u * u * u * u, s1, E0, d) * 4 * u * u * u * h;
    }
    CHECK(slope == Approx(root_mean).epsilon(1e-5));
  }
}
