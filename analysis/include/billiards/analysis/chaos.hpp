// The check behind the theory: is the undriven table chaotic and ergodic?  The paper's g1, g2
// assume that a free particle's collisions sample the boundary with the invariant measure
// ds dp (boundary_map.hpp) whatever its initial state.  The evidence, from free orbits at
// speed 1 from a microcanonical start:
//  - every orbit's maximal Lyapunov exponent per collision is positive (an integrable table's
//    estimates fall like log K / K; a regular island of a mixed table has orbits with none);
//  - every orbit's collisions cover the boundary map uniformly: the total-variation distance
//    between its histogram on a grid of cells in (s, p) and the uniform law is small (an
//    integrable orbit stays on its invariant curve; a chaotic orbit of a mixed table never
//    enters the islands).
// In 3-D the invariant measure of the collisions is dA cos θ dΩ: the position uniform in area
// over the walls and, independently, u = cos² θ uniform in [0, 1] (θ between the velocity and
// the normal).  The cells are then (wall, u): a plane face or a sphere each, a mesh's triangles
// together, with the law (wall's area / total area) × (1 / cells_p).  An integrable orbit (cube:
// |v_x|, |v_y|, |v_z| fixed; ball: θ fixed) sees a few values of u only.
#pragma once

#include "billiards/analysis/lyapunov.hpp"
#include "billiards/geometry/pieces.hpp"
#include "billiards/geometry3/region3.hpp"

#include <cstdint>
#include <functional>
#include <vector>

namespace billiards::analysis {

struct ChaosOptions {
  std::size_t orbits = 12;
  std::size_t collisions = 50000;
  std::uint64_t seed = 1;
  int threads = 0;
  int cells_s = 16, cells_p = 16;  // the grid on [0, S) × [−1, 1]; in 3-D cells_p bins of cos² θ
  /// An orbit is chaotic if its exponent per collision exceeds this.
  double min_exponent_per_collision = 0.02;
  /// An orbit covers the map if its histogram is this close to uniform (total variation).
  double max_distance = 0.1;
};

struct OrbitEvidence {
  double lyapunov = 0;                // per unit time (speed 1)
  double lyapunov_per_collision = 0;
  double distance = 0;                // total variation from uniform on the grid, in [0, 1]
  double coverage = 0;                // fraction of the grid's cells visited
  bool escaped = false;
};

struct ChaosVerdict {
  Estimate lyapunov, lyapunov_per_collision;  // over the orbits
  std::vector<OrbitEvidence> orbits;
  double pooled_distance = 0, pooled_coverage = 0;
  /// The total variation an orbit of independent uniform points would show on the grid
  /// (Σ of binomial mean absolute deviations / 2n): the distance's noise floor.
  double noise_distance = 0;
  int position_cells = 0;  // cells along s (2-D) or walls (3-D)
  bool chaotic = false;  // every orbit's exponent above the threshold
  bool uniform = false;  // every orbit's distance below the threshold
  bool ergodic() const { return chaotic && uniform; }
};

ChaosVerdict chaos_of(const geometry::Region2& region, const ChaosOptions& options,
                      const std::function<void(std::size_t)>& progress = {});
ChaosVerdict chaos_of(const geometry3::Region3& region, const ChaosOptions& options,
                      const std::function<void(std::size_t)>& progress = {});

}  // namespace billiards::analysis
