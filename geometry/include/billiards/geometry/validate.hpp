// Validation of a 2-D region with CGAL (exact arithmetic): loops closed, boundary simple
// (pieces meet only at their declared joints), holes strictly inside the outer loop and
// pairwise disjoint, orientation consistent (outer counter-clockwise, holes clockwise).
#pragma once

#include "billiards/geometry/pieces.hpp"

namespace billiards::geometry {

/// Throws InputError naming the file, the line(s) and the pieces involved.
void validate(const Region2& region);

}  // namespace billiards::geometry
