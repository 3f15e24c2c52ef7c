// A root finder that trusts nothing of the code under test: the first time after 0 at which
// f(t) goes from < 0 to > 0, sampled every h in long double, then bisected in 100-bit MPFR.
// f is a generic callable, f.template operator()<T>(t) for T = long double and the MPFR type.
#pragma once

#include <boost/multiprecision/mpfr.hpp>

namespace brute_force {

using Real = boost::multiprecision::mpfr_float_100;

/// The first upward crossing of f after 0; −1 when none before t_max.
template <class F>
double first_upward_root(F f, double h, double t_max) {
  long double before = f.template operator()<long double>(0.0L);
  for (long n = 1; n * h <= t_max; ++n) {
    const long double t = (long double)n * h, now = f.template operator()<long double>(t);
    if (before < 0 && now > 0) {
      Real a = Real(double(n - 1)) * h, b = Real(double(n)) * h;
      for (int k = 0; k < 120; ++k) {
        const Real m = (a + b) / 2;
        (f.template operator()<Real>(m) > 0 ? b : a) = m;
      }
      return static_cast<double>(b);
    }
    before = now;
  }
  return -1;
}

}  // namespace brute_force
