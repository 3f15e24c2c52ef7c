// Writing results: every file of a run goes into a temporary directory that is renamed into
// place only when complete, so a failed or interrupted run leaves no half-written output
// (interrupt.hpp removes the temporary on Ctrl-C).
#pragma once

#include "interrupt.hpp"

#include <nlohmann/json.hpp>

#include <filesystem>
#include <functional>
#include <ostream>
#include <string>
#include <vector>

namespace billiards::cli {

/// Writes `text` to `path` through a temporary beside it, renamed into place when complete (and
/// removed if the program fails or is interrupted first).
void write_file_atomically(const std::filesystem::path& path, const std::string& text);

class OutputDir {
 public:
  /// Creates the temporary directory; an InputError names `final_dir` if that is impossible.
  explicit OutputDir(std::filesystem::path final_dir);
  ~OutputDir();  // removes the temporary directory unless committed
  /// Fails as the constructor would, leaving nothing: for checking before a long run.
  static void require_creatable(const std::filesystem::path& final_dir) { OutputDir probe(final_dir); }
  OutputDir(const OutputDir&) = delete;
  OutputDir& operator=(const OutputDir&) = delete;

  std::filesystem::path path(const std::string& name) const { return tmp_ / name; }
  void write_text(const std::string& name, const std::string& text) const;
  /// A file written piece by piece by `writer` (for outputs too large to hold as one string).
  void write_stream(const std::string& name, const std::function<void(std::ostream&)>& writer) const;
  void write_json(const std::string& name, const nlohmann::json& j) const;
  /// A float64 matrix (rows × cols, row-major) in numpy's .npy format.
  void write_npy(const std::string& name, const std::vector<double>& data, std::size_t rows,
                 std::size_t cols) const;
  /// The same in float32.
  void write_npy(const std::string& name, const std::vector<float>& data, std::size_t rows, std::size_t cols) const;
  /// Replaces the final directory with the temporary one.
  void commit();

 private:
  /// The .npy file of `bytes`, rows × cols values of numpy's type `descr` ('<f8', '<f4').
  void write_npy_bytes(const std::string& name, const char* descr, const char* bytes, std::size_t size,
                       std::size_t rows, std::size_t cols) const;

  std::filesystem::path final_, tmp_;
  Unfinished unfinished_;
  bool committed_ = false;
};

}  // namespace billiards::cli
