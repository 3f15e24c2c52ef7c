#include "billiards/geometry/yaml_reader.hpp"

#include <fstream>
#include <sstream>

namespace billiards {

std::string read_input_file(const std::string& path, const std::string& what) {
  std::ifstream in(path);
  if (!in) throw InputError(path, 0, "cannot open " + what);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

YAML::Node load_yaml(const std::string& text, const std::string& name) {
  try {
    return YAML::Load(text);
  } catch (const YAML::Exception& e) {
    throw InputError(name, e.mark.line + 1, "not valid YAML: " + e.msg);
  }
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
