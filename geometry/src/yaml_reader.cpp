#include "billiards/geometry/yaml_reader.hpp"

#include <fmt/core.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <utility>

namespace billiards {

namespace {

/// Length of the UTF-8 sequence that starts at `s[i]`, or 0 if it is not well formed
/// (overlong forms, surrogates and code points above U+10FFFF included).
std::size_t utf8_sequence(std::string_view s, std::size_t i) {
  const auto byte = [&](std::size_t k) { return static_cast<unsigned char>(s[k]); };
  const unsigned char b = byte(i);
  if (b < 0x80) return 1;
  const std::size_t n = b >= 0xc2 && b <= 0xdf ? 2 : b >= 0xe0 && b <= 0xef ? 3 : b >= 0xf0 && b <= 0xf4 ? 4 : 0;
  if (n == 0 || i + n > s.size()) return 0;
  for (std::size_t k = 1; k < n; ++k)
    if ((byte(i + k) & 0xc0) != 0x80) return 0;
  const unsigned char c = byte(i + 1);
  if ((b == 0xe0 && c < 0xa0) || (b == 0xed && c > 0x9f) || (b == 0xf0 && c < 0x90) || (b == 0xf4 && c > 0x8f))
    return 0;
  return n;
}

/// Fails on a mapping that has the same key twice (yaml-cpp keeps both and finds the first),
/// or a key that is not a plain scalar, anywhere in the document.  Maps reached again through
/// an alias are checked once.
void check_keys(const YAML::Node& n, const std::string& name, std::set<std::pair<int, int>>& seen) {
  if (n.IsSequence()) {
    for (const auto& item : n) check_keys(item, name, seen);
    return;
  }
  if (!n.IsMap() || !seen.insert({n.Mark().line, n.Mark().column}).second) return;
  std::map<std::string, int> lines;
  for (const auto& kv : n) {
    const int line = kv.first.Mark().line + 1;
    if (!kv.first.IsScalar()) throw InputError(name, line, "a key must be a name, not a list or a mapping");
    const auto [first, fresh] = lines.emplace(kv.first.Scalar(), line);
    if (!fresh)
      throw InputError(name, line, fmt::format("key '{}' appears twice in one mapping (first at line {})",
                                               kv.first.Scalar(), first->second));
    check_keys(kv.second, name, seen);
  }
}

}  // namespace

void check_utf8(std::string_view text, const std::string& name) {
  int line = 1;
  for (std::size_t i = 0; i < text.size();) {
    const std::size_t n = utf8_sequence(text, i);
    if (n == 0)
      throw InputError(name, line, fmt::format("byte 0x{:02X} is not UTF-8: save the file as UTF-8",
                                               static_cast<unsigned char>(text[i])));
    if (text[i] == '\n') ++line;
    i += n;
  }
}

std::string read_input_file(const std::string& path, const std::string& what) {
  std::ifstream in(path, std::ios::binary);
  if (!in || std::filesystem::is_directory(path)) throw InputError(path, 0, "cannot open " + what);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

std::string YamlReader::shape_header(const YAML::Node& doc, int dimension, const Overrides& overrides) const {
  if (!doc.IsMap()) throw InputError(file_, 1, "a shape file is a YAML mapping");
  const std::string what = dimension == 3 ? "a 3-D shape file" : "a shape file";
  expect_keys(doc, {"name", "dimension", "parameters", "boundary", "holes", "exits"}, what);
  const YAML::Node dim = dimension == 3 ? required(doc, "dimension", what) : doc["dimension"];
  if (dim && !(dim.IsScalar() && dim.Scalar() == std::to_string(dimension)))
    fail(dim, dimension == 3 ? "a 3-D shape file has 'dimension: 3'" : "'dimension' is 2 (the default) or 3");
  if (const YAML::Node params = doc["parameters"]) define_parameters(params, overrides);
  if (const auto unknown = expr_.unused(overrides); !unknown.empty())
    throw InputError(file_, 0, "--set names '" + unknown.front() + "', which is not a parameter of this shape");
  const YAML::Node name = doc["name"];
  if (name && !name.IsScalar()) fail(name, "'name' is a single word or phrase");
  return name ? name.Scalar() : std::filesystem::path(file_).stem().string();
}

YAML::Node load_yaml(const std::string& text, const std::string& name) {
  check_utf8(text, name);
  YAML::Node doc;
  try {
    doc = YAML::Load(text);
  } catch (const YAML::Exception& e) {
    throw InputError(name, e.mark.line + 1, "not valid YAML: " + e.msg);
  }
  std::set<std::pair<int, int>> seen;
  check_keys(doc, name, seen);
  return doc;
}

std::string leading_comment(const std::string& text) {
  std::istringstream in(text);
  std::string line, out;
  while (std::getline(in, line) && !line.empty() && line[0] == '#') {
    const auto body = line.find_first_not_of("# ");
    out += (out.empty() ? "" : "\n") + (body == std::string::npos ? "" : line.substr(body));
  }
  return out;
}

}  // namespace billiards
