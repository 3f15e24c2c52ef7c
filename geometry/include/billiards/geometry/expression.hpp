// Numbers in shape and scene files are expressions ("2/sqrt(3)", "pi/6", "R1 + R2") over named
// parameters.  Parsing is done by muparser (Debian's libmuparser); this class adds ordered
// parameter definitions, command-line overrides and errors that name file and line.
#pragma once

#include "billiards/geometry/input_error.hpp"

#include <map>
#include <memory>
#include <string>
#include <vector>

namespace billiards {

/// NAME=VALUE pairs from the command line (`--set R2=3`); VALUE is itself an expression.
using Overrides = std::map<std::string, std::string>;
/// Parses "NAME=VALUE" into `out`; throws InputError naming the offending argument.
void add_override(Overrides& out, const std::string& assignment);

class Expressions {
 public:
  /// The largest magnitude of any number in an input: products of a few lengths, speeds and
  /// energies stay far from overflow, and any physical system fits in some unit.
  static constexpr double max_magnitude = 1e30;

  Expressions();
  ~Expressions();
  Expressions(Expressions&&) noexcept;
  Expressions& operator=(Expressions&&) noexcept;

  /// Declares parameter `name`; an override of the same name replaces `text`.  Later
  /// definitions may use earlier ones.  Throws on a bad name, a redefinition or a bad value.
  void define(const std::string& name, const std::string& text, const std::string& file, int line,
              const Overrides& overrides = {});
  /// Evaluates `text` with the parameters defined so far (plus pi and e); fails unless the
  /// value is finite and within ±max_magnitude.
  double evaluate(const std::string& text, const std::string& file, int line) const;
  /// Overrides that named no declared parameter (to be reported as errors by the caller).
  std::vector<std::string> unused(const Overrides& overrides) const;
  const std::map<std::string, double>& values() const { return values_; }

 private:
  struct Parser;
  std::unique_ptr<Parser> parser_;
  std::map<std::string, double> values_;
};

}  // namespace billiards
