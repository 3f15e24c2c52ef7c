// billiards/analysis: the theory of Hodson & Jarzynski computed from a shape and a drive, and
// the statistics that compare it with an ensemble.
#pragma once

#include "billiards/analysis/coefficients.hpp"
#include "billiards/analysis/fokker_planck.hpp"
#include "billiards/analysis/potential.hpp"
#include "billiards/analysis/quadrature.hpp"
#include "billiards/analysis/statistics.hpp"
#include "billiards/analysis/wall.hpp"
