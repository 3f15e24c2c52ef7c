// Reading YAML input files (shapes, scenes) with errors that name the file and the line.
// Internal to the libraries that read files; users include shape_file.hpp or scene.hpp.
#pragma once

#include "billiards/geometry/expression.hpp"
#include "billiards/geometry/input_error.hpp"
#include "billiards/geometry/pieces.hpp"

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <set>
#include <string>
#include <string_view>

namespace billiards {

/// A count as people write it: 1000, 1e+12.
inline std::string format_count(double v) {
  char text[32];
  std::snprintf(text, sizeof text, v < 1e6 ? "%.0f" : "%g", v);
  return text;
}

/// File/line-aware accessors over one YAML document whose numbers are expressions.
class YamlReader {
 public:
  YamlReader(std::string file, Expressions& expr) : file_(std::move(file)), expr_(expr) {}

  const std::string& file() const { return file_; }
  int line(const YAML::Node& n) const { return n.Mark().line + 1; }
  geometry::SourceRef ref(const YAML::Node& n) const { return {file_, line(n)}; }
  [[noreturn]] void fail(const YAML::Node& n, const std::string& msg) const {
    throw InputError(file_, line(n), msg);
  }

  /// Fails on a key not in `allowed`, listing the allowed ones.
  void expect_keys(const YAML::Node& map, std::initializer_list<const char*> allowed,
                   const std::string& what) const {
    if (!map.IsMap()) fail(map, what + " must be a mapping");
    const std::set<std::string> ok(allowed.begin(), allowed.end());
    for (const auto& kv : map) {
      const auto key = kv.first.as<std::string>();
      if (ok.count(key)) continue;
      std::string list;
      for (const auto* k : allowed) list += std::string(list.empty() ? "" : ", ") + k;
      fail(kv.first, "unknown key '" + key + "' in " + what + " (expected one of: " + list + ")");
    }
  }
  YAML::Node required(const YAML::Node& map, const char* key, const std::string& what) const {
    const YAML::Node n = map[key];
    if (!n) fail(map, what + " needs '" + key + "'");
    return n;
  }
  double number(const YAML::Node& n) const {
    if (!n.IsScalar()) fail(n, "expected a number or an expression");
    return expr_.evaluate(n.Scalar(), file_, line(n));
  }
  double positive(const YAML::Node& n, const std::string& what) const {
    const double v = number(n);
    if (!(v > 0)) fail(n, what + " must be positive, got " + std::to_string(v));
    return v;
  }
  /// A whole number in [lo, hi] (hi at most 2^53, where doubles stop counting one by one).
  std::uint64_t whole(const YAML::Node& n, const std::string& what, double lo, double hi) const {
    const double v = number(n);
    if (!(v >= lo && v <= hi) || v != std::floor(v))
      fail(n, what + " must be a whole number from " + format_count(lo) + " to " + format_count(hi));
    return std::uint64_t(v);
  }
  std::size_t count(const YAML::Node& n, const std::string& what) const { return whole(n, what, 1, 1e12); }
  /// Defines each parameter of a `parameters:` mapping, in order (later ones may use earlier
  /// ones); an override of the same name replaces its value.
  void define_parameters(const YAML::Node& params, const Overrides& overrides) const {
    if (!params.IsMap()) fail(params, "'parameters' must be a mapping NAME: value");
    for (const auto& kv : params) {
      if (!kv.second.IsScalar()) fail(kv.second, "a parameter value must be a number or expression");
      expr_.define(kv.first.as<std::string>(), kv.second.Scalar(), file_, line(kv.first), overrides);
    }
  }
  /// What a shape file holds besides its walls, read alike in 2-D and 3-D: a mapping of the
  /// shape keys only, whose `dimension` is `dimension` (2 when absent), its parameters (each
  /// --set naming one of them) and its `name`.  Returns the name (the file's stem when absent).
  std::string shape_header(const YAML::Node& doc, int dimension, const Overrides& overrides) const;
  geometry::Vec2 point(const YAML::Node& n) const { return vector(n, 2); }
  /// A vector of `size` (2 or 3) numbers.
  Eigen::VectorXd vector(const YAML::Node& n, int size) const {
    if (!n.IsSequence() || int(n.size()) != size) fail(n, size == 2 ? "expected a vector [x, y]" : "expected a vector [x, y, z]");
    Eigen::VectorXd v(size);
    for (int k = 0; k < size; ++k) v[k] = number(n[k]);
    return v;
  }

 private:
  std::string file_;
  Expressions& expr_;
};

/// The whole text of an input file; `what` names it in the error ("shape file").
std::string read_input_file(const std::string& path, const std::string& what);
/// Fails, naming the line, unless `text` is well-formed UTF-8.
void check_utf8(std::string_view text, const std::string& name);
/// Parses YAML text (UTF-8), reporting a syntax error, a duplicate key or a key that is not a
/// name at its line in `name`.
YAML::Node load_yaml(const std::string& text, const std::string& name);
/// The comment lines at the top of a file, without their '#': what the file describes.
std::string leading_comment(const std::string& text);

}  // namespace billiards
