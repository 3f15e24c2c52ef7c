// Options shared by several subcommands.
#pragma once

#include "billiards/analysis/coefficients.hpp"
#include "billiards/dynamics/scene.hpp"
#include "billiards/geometry/expression.hpp"
#include "billiards/geometry/shape_file.hpp"
#include "billiards/geometry/yaml_reader.hpp"

#include <CLI/CLI.hpp>
#include <fmt/core.h>
#include <nlohmann/json.hpp>

#include <cmath>
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

/// A whole number in [lo, hi], written as an expression ("1e6", "2^20"); a value outside is
/// refused, never wrapped or rounded.
inline CLI::Validator whole_number(double lo, double hi) {
  return CLI::Validator(
      [lo, hi](std::string& text) {
        const std::string range = fmt::format("a whole number from {} to {}", format_count(lo), format_count(hi));
        try {
          const double v = Expressions().evaluate(text, "", 0);
          if (!(v >= lo && v <= hi) || v != std::floor(v)) return fmt::format("must be {}, not {}", range, text);
          text = fmt::format("{:.0f}", v);
          return std::string();
        } catch (const InputError& e) {
          return fmt::format("must be {}: {}", range, e.what());
        }
      },
      "INT");
}

/// A 64-bit seed: digits only (a negative number would wrap).
inline const CLI::Validator seed_value(
    [](std::string& text) {
      const bool digits = !text.empty() && text.size() <= 20 && text.find_first_not_of("0123456789") == std::string::npos;
      if (digits && (text.size() < 20 || text <= "18446744073709551615")) return std::string();
      return "must be a whole number from 0 to 18446744073709551615, not " + text;
    },
    "UINT64");

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
