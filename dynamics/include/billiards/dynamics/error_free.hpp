// Error-free transformations of doubles (Knuth, Dekker) and the drive's phase arithmetic in
// double, drive_phase-inl.hpp with the traits of one double: the run's clock (state.hpp) and the
// drive's phase (phase.hpp).  The lock-step kernel runs the same source in lanes.
#pragma once

#include "billiards/dynamics/phase_constants.hpp"
#include "billiards/dynamics/scalar_lanes.hpp"

namespace billiards::dynamics::detail {

#include "billiards/dynamics/drive_phase-inl.hpp"

/// The traits of the flights' doubles.
using Doubles = ScalarLanes<double>;

}  // namespace billiards::dynamics::detail
