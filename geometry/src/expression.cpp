#include "billiards/geometry/expression.hpp"

#include <muParser.h>

#include <fmt/core.h>

#include <cmath>
#include <regex>

namespace billiards {

struct Expressions::Parser {
  mu::Parser parser;
};

Expressions::Expressions() : parser_(std::make_unique<Parser>()) {
  parser_->parser.DefineConst("pi", M_PI);
  parser_->parser.DefineConst("e", M_E);
}
Expressions::~Expressions() = default;
Expressions::Expressions(Expressions&&) noexcept = default;
Expressions& Expressions::operator=(Expressions&&) noexcept = default;

namespace {
bool valid_name(const std::string& name) {
  static const std::regex identifier("[A-Za-z_][A-Za-z0-9_]*");
  return std::regex_match(name, identifier);
}
}  // namespace

void add_override(Overrides& out, const std::string& assignment) {
  const auto eq = assignment.find('=');
  const std::string name = assignment.substr(0, eq);
  if (eq == std::string::npos || !valid_name(name) || eq + 1 == assignment.size())
    throw InputError("--set", 0, "expected NAME=VALUE, got '" + assignment + "'");
  out[name] = assignment.substr(eq + 1);
}

void Expressions::define(const std::string& name, const std::string& text, const std::string& file,
                         int line, const Overrides& overrides) {
  if (!valid_name(name)) throw InputError(file, line, "'" + name + "' is not a valid parameter name");
  if (values_.count(name) || name == "pi" || name == "e")
    throw InputError(file, line, "parameter '" + name + "' is defined twice");
  const auto o = overrides.find(name);
  const double value = o != overrides.end() ? evaluate(o->second, "--set " + name, 0)
                                            : evaluate(text, file, line);
  try {
    parser_->parser.DefineConst(name, value);
  } catch (const mu::ParserError& e) {
    throw InputError(file, line, "'" + name + "' cannot be a parameter name: " + e.GetMsg());
  }
  values_[name] = value;
}

namespace {
/// muparser's message in the user's terms: a name it does not know is an unknown parameter.
std::string explain(const mu::ParserError& e, const std::map<std::string, double>& defined) {
  static const std::regex name_at_start("^[A-Za-z_][A-Za-z0-9_]*");
  std::smatch name;
  const std::string& token = e.GetToken();
  if (e.GetCode() != mu::ecUNASSIGNABLE_TOKEN || !std::regex_search(token, name, name_at_start)) return e.GetMsg();
  std::string known = "pi, e";
  for (const auto& [parameter, value] : defined) known += ", " + parameter;
  return "unknown parameter '" + name.str() + "' (defined so far: " + known + ")";
}
}  // namespace

double Expressions::evaluate(const std::string& text, const std::string& file, int line) const {
  double value = 0;
  try {
    parser_->parser.SetExpr(text);
    value = parser_->parser.Eval();
  } catch (const mu::ParserError& e) {
    throw InputError(file, line, "bad expression '" + text + "': " + explain(e, values_));
  }
  if (!std::isfinite(value))
    throw InputError(file, line, "expression '" + text + "' is not a finite number");
  if (std::abs(value) > max_magnitude)
    throw InputError(file, line, fmt::format("'{}' = {:g} is out of range: numbers lie within ±{:g}", text, value,
                                             max_magnitude));
  return value;
}

std::vector<std::string> Expressions::unused(const Overrides& overrides) const {
  std::vector<std::string> names;
  for (const auto& [name, text] : overrides)
    if (!values_.count(name)) names.push_back(name);
  return names;
}

}  // namespace billiards
