// billiards/geometry: 2-D billiard tables made of segments and arcs, their shape files,
// CGAL validation and exact measures.
#pragma once

#include "billiards/geometry/expression.hpp"
#include "billiards/geometry/input_error.hpp"
#include "billiards/geometry/measures.hpp"
#include "billiards/geometry/pieces.hpp"
#include "billiards/geometry/shape_file.hpp"
#include "billiards/geometry/validate.hpp"
