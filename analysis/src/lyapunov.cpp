#include "billiards/analysis/lyapunov.hpp"

#include "billiards/analysis/statistics.hpp"

namespace billiards::analysis {

Estimate estimate_of(const std::vector<double>& values) {
  const auto m = sample_moments(values);
  return {m.mean, m.se_mean};
}

}  // namespace billiards::analysis
