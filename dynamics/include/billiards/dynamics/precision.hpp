// Scalar types beyond double for reference trajectories.  The geometry and flight code is
// written once over its scalar type; ensembles run it in double, reference runs in these.
#pragma once

#include <boost/multiprecision/eigen.hpp>
#include <boost/multiprecision/mpfr.hpp>

namespace billiards::dynamics {

/// MPFR with 40 decimal digits (136 bits), without expression templates, which Eigen's
/// arithmetic does not expect.
using Reference =
    boost::multiprecision::number<boost::multiprecision::mpfr_float_backend<40>, boost::multiprecision::et_off>;

}  // namespace billiards::dynamics
