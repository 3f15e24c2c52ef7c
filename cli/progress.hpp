// A progress bar with rate and ETA on a terminal; silent when stderr is not a terminal.
#pragma once

#include <chrono>
#include <cstddef>
#include <string>

namespace billiards::cli {

class Progress {
 public:
  Progress(std::string label, std::size_t total, bool enabled);
  /// Reports `done` items so far (thread-compatible: call from one thread).
  void update(std::size_t done);
  void finish();

 private:
  std::string label_;
  std::size_t total_;
  bool enabled_;
  std::chrono::steady_clock::time_point start_, last_;
};

}  // namespace billiards::cli
