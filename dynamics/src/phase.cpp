#include "billiards/dynamics/phase.hpp"

#include "billiards/dynamics/precision.hpp"

namespace billiards::dynamics::detail {

/// Beyond 2²⁶·2π the three parts of 2π no longer multiply k exactly: the remainder in 136-bit
/// MPFR instead (1e-41 of θ: 1e-23 rad at 10¹⁸ rad), rounded to two doubles.
Phase reduce_phase_mpfr(const Phase& theta) {
  using std::isfinite;
  if (!isfinite(theta.hi) || !isfinite(theta.lo)) return theta;
  const Reference two_pi = boost::math::constants::two_pi<Reference>();
  Reference r = fmod(Reference(theta.hi) + Reference(theta.lo), two_pi);
  if (r < 0) r += two_pi;
  const double hi = static_cast<double>(r);
  return {hi, static_cast<double>(Reference(r - hi))};
}

}  // namespace billiards::dynamics::detail
