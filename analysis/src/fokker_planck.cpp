#include "billiards/analysis/fokker_planck.hpp"

#include <boost/math/special_functions/bessel.hpp>

#include <cmath>

namespace billiards::analysis {

double scaled_bessel_i(double nu, double x) {
  if (x < 500) return boost::math::cyl_bessel_i(nu, x) * std::exp(-x);
  // Hankel's asymptotic series e⁻ˣ I_ν(x) ~ (2πx)^{−1/2} Σ (−1)^k a_k(ν)/x^k,
  // a_k = Π_{j=1..k} (4ν² − (2j−1)²)/(8 j); at x ≥ 500 twelve terms reach rounding.
  const double mu = 4 * nu * nu;
  double term = 1, sum = 1;
  for (int k = 1; k <= 12; ++k) {
    term *= -(mu - (2 * k - 1) * (2 * k - 1)) / (8.0 * k * x);
    sum += term;
  }
  return sum / std::sqrt(2 * M_PI * x);
}

double fokker_planck_eta(double E, double s, double E0, int d) {
  if (E <= 0) return 0;
  const double k = 2.0 * (d + 1) / s;
  const double x = 2 * k * std::pow(E0 * E, 0.25);
  const double gap = std::pow(E0, 0.25) - std::pow(E, 0.25);
  // I_{d−1}(x) e^{−k(√E0 + √E)} = [e⁻ˣ I_{d−1}(x)] e^{−k (E0^{1/4} − E^{1/4})²}
  return (d + 1) / (s * std::sqrt(E0)) * std::pow(E / E0, (d - 3) / 4.0) * scaled_bessel_i(d - 1, x) *
         std::exp(-k * gap * gap);
}

Moments fokker_planck_moments(double s, double E0, int d, int points) {
  const double hi = std::pow(40 * E0 + 50 * s * s, 0.25), h = hi / points;
  double m0 = 0, m1 = 0, m2 = 0;
  for (int i = 1; i < points; ++i) {
    const double u = i * h, E = u * u * u * u, w = fokker_planck_eta(E, s, E0, d) * 4 * u * u * u * h;
    m0 += w;
    m1 += w * E;
    m2 += w * E * E;
  }
  const double mean = m1 / m0;
  return {m0, mean, m2 / m0 - mean * mean};
}

}  // namespace billiards::analysis
