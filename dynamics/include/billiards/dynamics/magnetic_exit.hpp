// The outward crossings of a magnetic flight through segments and circular arcs in a scalar
// type: magnetic_exit-inl.hpp's algorithms, with the traits of one number (straight_exit.hpp).
#pragma once

#include "billiards/dynamics/straight_exit.hpp"

namespace billiards::dynamics {

#include "billiards/dynamics/magnetic_exit-inl.hpp"

}  // namespace billiards::dynamics
