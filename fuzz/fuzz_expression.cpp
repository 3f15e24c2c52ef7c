// libFuzzer target: the expression parser.  The input is "NAME: TEXT" lines defining
// parameters in order, the last line an expression evaluated with them.
#include "billiards/geometry/expression.hpp"

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <sstream>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  std::istringstream in(std::string(reinterpret_cast<const char*>(data), size));
  billiards::Expressions expr;
  std::string line;
  int number = 0;
  try {
    while (std::getline(in, line)) {
      ++number;
      const auto colon = line.find(':');
      if (colon == std::string::npos || in.peek() == EOF) {
        const double v = expr.evaluate(line, "fuzz", number);
        if (!(std::abs(v) <= billiards::Expressions::max_magnitude)) std::abort();  // the promised range
      } else {
        expr.define(line.substr(0, colon), line.substr(colon + 1), "fuzz", number);
      }
    }
  } catch (const billiards::InputError&) {
  }
  return 0;
}
