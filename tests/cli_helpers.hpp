// Running the `billiard` program from tests.
#pragma once

#include <nlohmann/json.hpp>

#include <array>
#include <cstring>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <system_error>
#include <vector>

#include <sys/wait.h>
#include <unistd.h>

struct CommandResult {
  int status;
  std::string output;  // stdout and stderr
};

/// Runs a shell command and captures its output (stdout and stderr) and exit status.
inline CommandResult run_command(const std::string& command) {
  const std::string cmd = command + " 2>&1";
  FILE* pipe = popen(cmd.c_str(), "r");
  std::string out;
  std::array<char, 4096> buf;
  while (std::size_t n = fread(buf.data(), 1, buf.size(), pipe)) out.append(buf.data(), n);
  const int status = pclose(pipe);
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, out};
}

/// Runs `billiard ARGS` from the source root.
inline CommandResult billiard(const std::string& args) {
  return run_command("cd " BILLIARDS_SOURCE_DIR " && " BILLIARDS_BINARY " " + args);
}

inline std::string read_file(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

/// This test process's own temporary directory, removed when the process exits: two test runs
/// on one machine (two checkouts, or CI beside a developer's run) never share a file.
inline const std::filesystem::path& scratch_root() {
  struct Root {
    std::filesystem::path dir =
        std::filesystem::temp_directory_path() / ("billiards-test-" + std::to_string(::getpid()));
    ~Root() {
      std::error_code ignored;
      std::filesystem::remove_all(dir, ignored);
    }
  };
  static const Root root;
  return root.dir;
}

/// A fresh temporary directory for one test.
inline std::filesystem::path scratch(const std::string& name) {
  const auto dir = scratch_root() / name;
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

inline void write_file(const std::filesystem::path& p, const std::string& text) {
  std::ofstream(p) << text;
}

inline nlohmann::json read_json(const std::filesystem::path& p) { return nlohmann::json::parse(read_file(p)); }

/// energies.npy as doubles, row after row (its header is padded to 128 bytes).
inline std::vector<double> read_npy(const std::filesystem::path& p) {
  const std::string bytes = read_file(p);
  std::vector<double> x((bytes.size() - 128) / sizeof(double));
  std::memcpy(x.data(), bytes.data() + 128, x.size() * sizeof(double));
  return x;
}
