// Options shared by several subcommands.
#pragma once

#include "billiards/analysis/coefficients.hpp"
#include "billiards/dynamics/scene.hpp"
#include "billiards/geometry/expression.hpp"
#include "billiards/geometry/shape_file.hpp"

#include <CLI/CLI.hpp>
#include <fmt/core.h>
#include <nlohmann/json.hpp>

#include <optional>
#include <string>
#include <vector>

namespace billiards::cli {

/// `--set NAME=VALUE` (repeatable): overrides a shape or scene parameter.
inline void add_set_option(CLI::App* cmd, std::vector<std::string>& target) {
  cmd->add_option("--set", target, "override a parameter: NAME=VALUE (an expression); repeatable");
}

/// Lets a numeric option take an expression ("320*pi", "2^10"), as numbers in shape files do.
inline const CLI::Validator expression_value(
    [](std::string& text) {
      try {
        text = fmt::format("{:.17g}", Expressions().evaluate(text, "", 0));
        return std::string();
      } catch (const InputError& e) {
        return std::string(e.what());
      }
    },
    "EXPR");

inline Overrides parse_overrides(const std::vector<std::string>& assignments) {
  Overrides out;
  for (const auto& a : assignments) add_override(out, a);
  return out;
}

void print_prediction(const analysis::Coefficients& c, double dt);

/// A warning on stderr when the numerical Fokker–Planck grid resolves the first time's spread
/// by fewer than 5 cells (fp.cpp).
void warn_if_coarse(const analysis::FokkerPlanckSolution& solution);

}  // namespace billiards::cli
