#include "progress.hpp"

#include <fmt/core.h>

#include <unistd.h>

namespace billiards::cli {

Progress::Progress(std::string label, std::size_t total, bool enabled)
    : label_(std::move(label)), total_(total), enabled_(enabled && isatty(STDERR_FILENO)),
      start_(std::chrono::steady_clock::now()), last_(start_) {}

void Progress::update(std::size_t done) {
  if (!enabled_) return;
  const auto now = std::chrono::steady_clock::now();
  if (now - last_ < std::chrono::milliseconds(200) && done < total_) return;
  last_ = now;
  const double elapsed = std::chrono::duration<double>(now - start_).count();
  const double rate = elapsed > 0 ? double(done) / elapsed : 0;
  const double eta = rate > 0 ? double(total_ - done) / rate : 0;
  constexpr int width = 30;
  const int filled = total_ ? int(width * double(done) / double(total_)) : width;
  fmt::print(stderr, "\r{} [{:<{}}] {}/{}  {:.0f}/s  ETA {:.0f}s   ", label_, std::string(filled, '#'),
             width, done, total_, rate, eta);
}

void Progress::finish() {
  if (enabled_) fmt::print(stderr, "\n");
}

}  // namespace billiards::cli
