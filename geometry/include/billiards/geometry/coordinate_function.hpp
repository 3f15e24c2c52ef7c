// Functions of the coordinates, f(x, y), given as expressions in scene files: a potential U(x)
// and the amplitude F(x) of a drive.  The text is the expression language of shape files over
// the parameters defined so far and the coordinates x, y, restricted to what can be
// differentiated: + − * / ^, parentheses, sin cos tan asin acos atan sinh cosh tanh exp log
// sqrt abs (muparser's ?:, min, max, sum, rint, ... are refused with a clear message).
//
// Derivatives are exact: the text is parsed and differentiated symbolically by GiNaC, and every
// function (the expression and its derivatives) is compiled into a small stack program whose
// evaluation is thread-safe and allocation-free.  Each parsed text is also evaluated by
// muparser, the parser of shape files, at a few points: a text the two read differently (an
// operator precedence, a function name) is an error, so a scene means what a shape file would.
#pragma once

#include "billiards/geometry/expression.hpp"
#include "billiards/geometry/pieces.hpp"

#include <memory>
#include <string>
#include <vector>

namespace billiards {

class CoordinateFunction {
 public:
  /// One instruction of the stack program (internal).
  struct Op {
    int code;
    double value;  // a constant, or an integer exponent
  };

  CoordinateFunction();  // f = 0
  /// Parses `text` with the parameters of `params`; throws InputError at file:line on a bad
  /// expression, an unknown name, or a construct that cannot be differentiated.
  CoordinateFunction(const std::string& text, const Expressions& params, const std::string& file, int line);
  ~CoordinateFunction();
  CoordinateFunction(const CoordinateFunction&);
  CoordinateFunction& operator=(const CoordinateFunction&);

  double operator()(const geometry::Vec2& p) const;
  /// ∂f/∂x (axis 0) or ∂f/∂y (axis 1), exact (symbolic).
  CoordinateFunction derivative(int axis) const;
  /// The expression as GiNaC writes it (after substitution of the parameters).
  std::string text() const;
  /// True when f does not depend on x or y.
  bool constant() const;

 private:
  struct Symbolic;
  explicit CoordinateFunction(std::shared_ptr<const Symbolic> s);
  std::shared_ptr<const Symbolic> symbolic_;
  std::vector<Op> program_;
};

}  // namespace billiards
