// Ctrl-C (SIGINT) and SIGTERM: the program stops within a moment, removes every file it was
// still writing and keeps only a run's checkpoint (DIR.partial/), then exits 128 + signal
// (130 for Ctrl-C).  The signals are blocked in every thread and a watcher thread waits for
// them, so the cleanup runs as ordinary code, never inside a signal handler.
#pragma once

#include <filesystem>
#include <mutex>
#include <string>

#include <spawn.h>

namespace billiards::cli {

/// Blocks SIGINT and SIGTERM in this thread (and the threads it starts later) and starts the
/// watcher.  Called first thing in main.
void watch_interrupts();

/// A file or directory that is removed if the program is interrupted while it exists:
/// temporaries that are renamed into place when complete.  `commit` stops watching it; the
/// rename that makes the output final happens under the same lock, so an interruption sees
/// either the temporary (and removes it) or the final output (and leaves it).
class Unfinished {
 public:
  explicit Unfinished(std::filesystem::path path);
  ~Unfinished();
  Unfinished(const Unfinished&) = delete;
  Unfinished& operator=(const Unfinished&) = delete;
  /// Renames the temporary to `final` and stops watching it.
  void commit(const std::filesystem::path& final);

 private:
  std::filesystem::path path_;
  bool watched_ = true;
};

/// A line printed if the program is interrupted while it lives ("the same command resumes from
/// out/x.partial/").
class InterruptNote {
 public:
  explicit InterruptNote(std::string text);
  ~InterruptNote();
  InterruptNote(const InterruptNote&) = delete;
  InterruptNote& operator=(const InterruptNote&) = delete;
};

/// Makes a child process start with no signal blocked (it inherits the mask otherwise).
void unblock_interrupts_in_child(posix_spawnattr_t& attr);

}  // namespace billiards::cli
