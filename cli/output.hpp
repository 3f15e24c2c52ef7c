// Writing results: every file of a run goes into a temporary directory that is renamed into
// place only when complete, so a failed or interrupted run leaves no half-written output.
#pragma once

#include <nlohmann/json.hpp>

#include <filesystem>
#include <string>
#include <vector>

namespace billiards::cli {

class OutputDir {
 public:
  explicit OutputDir(std::filesystem::path final_dir);
  ~OutputDir();  // removes the temporary directory unless committed
  OutputDir(const OutputDir&) = delete;
  OutputDir& operator=(const OutputDir&) = delete;

  std::filesystem::path path(const std::string& name) const { return tmp_ / name; }
  void write_text(const std::string& name, const std::string& text) const;
  void write_json(const std::string& name, const nlohmann::json& j) const;
  /// A float64 matrix (rows × cols, row-major) in numpy's .npy format.
  void write_npy(const std::string& name, const std::vector<double>& data, std::size_t rows,
                 std::size_t cols) const;
  /// Replaces the final directory with the temporary one.
  void commit();

 private:
  std::filesystem::path final_, tmp_;
  bool committed_ = false;
};

/// A script of scripts/ ($BILLIARDS_SCRIPTS overrides the folder); throws if it is missing.
std::filesystem::path script_path(const std::string& name);
/// Runs PYTHON SCRIPT ARGS... directly (no shell, so any path is passed as it is) and waits;
/// PYTHON is Debian's /usr/bin/python3 (it has matplotlib) unless $BILLIARDS_PYTHON is set.
/// Throws if it cannot start or does not exit with status 0.
void run_python(const std::filesystem::path& script, const std::vector<std::string>& args);

}  // namespace billiards::cli
