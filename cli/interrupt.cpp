#include "interrupt.hpp"

#include <fmt/core.h>

#include <csignal>
#include <cstdio>
#include <set>
#include <thread>

#include <pthread.h>
#include <unistd.h>

namespace billiards::cli {

namespace {

namespace fs = std::filesystem;

/// What the watcher needs, behind one lock: the temporaries to remove and the note to print.
struct Pending {
  std::mutex lock;
  std::multiset<fs::path> unfinished;
  std::string note;
};

Pending& pending() {
  static Pending p;  // never destroyed before the watcher uses it: the watcher ends the process
  return p;
}

sigset_t interrupt_signals() {
  sigset_t set;
  sigemptyset(&set);
  sigaddset(&set, SIGINT);
  sigaddset(&set, SIGTERM);
  return set;
}

[[noreturn]] void stop(int signal) {
  Pending& p = pending();
  p.lock.lock();  // held until _exit: no output is committed from now on
  for (const auto& path : p.unfinished) {
    // Another thread may still be adding a file to a temporary directory (a trajectory's next
    // chunk), which makes one remove_all fail as "not empty": try again until it is gone.
    std::error_code ignored;
    for (int attempt = 0; attempt < 1000 && fs::exists(path, ignored); ++attempt) fs::remove_all(path, ignored);
  }
  fmt::print(stderr, "\nbilliard: interrupted ({}){}{}\n", signal == SIGINT ? "Ctrl-C" : "SIGTERM",
             p.note.empty() ? "" : "; ", p.note);
  std::fflush(stdout);
  _exit(128 + signal);
}

}  // namespace

void watch_interrupts() {
  const sigset_t set = interrupt_signals();
  pthread_sigmask(SIG_BLOCK, &set, nullptr);
  std::thread([set] {
    int signal = 0;
    while (sigwait(&set, &signal) != 0) {
    }
    stop(signal);
  }).detach();
}

Unfinished::Unfinished(fs::path path) : path_(std::move(path)) {
  const std::lock_guard guard(pending().lock);
  pending().unfinished.insert(path_);
}

Unfinished::~Unfinished() {
  if (!watched_) return;
  const std::lock_guard guard(pending().lock);
  pending().unfinished.erase(pending().unfinished.find(path_));
}

void Unfinished::commit(const fs::path& final) {
  const std::lock_guard guard(pending().lock);
  fs::rename(path_, final);
  pending().unfinished.erase(pending().unfinished.find(path_));
  watched_ = false;
}

InterruptNote::InterruptNote(std::string text) {
  const std::lock_guard guard(pending().lock);
  pending().note = std::move(text);
}

InterruptNote::~InterruptNote() {
  const std::lock_guard guard(pending().lock);
  pending().note.clear();
}

void unblock_interrupts_in_child(posix_spawnattr_t& attr) {
  sigset_t none;
  sigemptyset(&none);
  posix_spawnattr_setsigmask(&attr, &none);
  posix_spawnattr_setflags(&attr, POSIX_SPAWN_SETSIGMASK);
}

}  // namespace billiards::cli
