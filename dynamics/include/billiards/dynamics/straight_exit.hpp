// The exit time of a straight flight through a segment or a circular arc in a scalar type:
// straight_exit-inl.hpp's algorithms, with the traits of one number.
#pragma once

#include "billiards/dynamics/scalar_lanes.hpp"

namespace billiards::dynamics {

#include "billiards/dynamics/straight_exit-inl.hpp"

}  // namespace billiards::dynamics
