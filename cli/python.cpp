#include "python.hpp"

#include <fmt/core.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <stdexcept>

#include <spawn.h>
#include <sys/wait.h>

extern char** environ;

namespace billiards::cli {

namespace fs = std::filesystem;

fs::path data_dir() {
  if (const char* env = std::getenv("BILLIARDS_DATA")) return env;
  std::error_code error;
  const fs::path program = fs::read_symlink("/proc/self/exe", error);
  const fs::path installed = program.parent_path() / BILLIARDS_DATA_FROM_BINDIR;
  if (!error && fs::is_directory(installed / "scripts", error)) return installed.lexically_normal();
  return BILLIARDS_SOURCE_DIR;
}

fs::path script_path(const std::string& name) {
  const char* env = std::getenv("BILLIARDS_SCRIPTS");
  const fs::path script = (env ? fs::path(env) : data_dir() / "scripts") / name;
  if (!fs::is_regular_file(script))
    throw std::runtime_error(fmt::format("{} not found (set BILLIARDS_SCRIPTS to the directory that holds it)",
                                         script.string()));
  return script;
}

void run_python(const fs::path& script, const std::vector<std::string>& args) {
  const char* env = std::getenv("BILLIARDS_PYTHON");
  std::vector<std::string> argv_s = {env ? env : "/usr/bin/python3", script.string()};
  argv_s.insert(argv_s.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (auto& a : argv_s) argv.push_back(a.data());
  argv.push_back(nullptr);
  pid_t pid = 0;
  if (const int err = posix_spawnp(&pid, argv[0], nullptr, nullptr, argv.data(), environ))
    throw std::runtime_error(fmt::format("cannot run {}: {} (set BILLIARDS_PYTHON to a python3 with matplotlib)",
                                         argv_s[0], std::strerror(err)));
  int status = 0;
  while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  if (WIFEXITED(status) && WEXITSTATUS(status) == 0) return;
  const std::string how = WIFEXITED(status) ? fmt::format("exit status {}", WEXITSTATUS(status))
                                            : fmt::format("signal {}", WTERMSIG(status));
  throw std::runtime_error(fmt::format("drawing failed: {} {} ended with {}", argv_s[0], script.string(), how));
}

}  // namespace billiards::cli
