// billiards/analysis: the theory of Hodson & Jarzynski computed from a shape and a drive.
#pragma once

#include "billiards/analysis/coefficients.hpp"
#include "billiards/analysis/fokker_planck.hpp"
