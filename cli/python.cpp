#include "python.hpp"

#include "billiards/geometry/input_error.hpp"

#include "interrupt.hpp"

#include <fmt/core.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <stdexcept>

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

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

namespace {
/// The last non-empty line of a Python error output: the exception and its message.
std::string last_line(const fs::path& file) {
  std::ifstream in(file);
  std::string line, last;
  while (std::getline(in, line))
    if (line.find_first_not_of(" \t\r") != std::string::npos) last = line;
  return last;
}
}  // namespace

void run_python(const fs::path& script, const std::vector<std::string>& args) {
  const char* env = std::getenv("BILLIARDS_PYTHON");
  std::vector<std::string> argv_s = {env ? env : "/usr/bin/python3", script.string()};
  argv_s.insert(argv_s.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (auto& a : argv_s) argv.push_back(a.data());
  argv.push_back(nullptr);
  // The script's stderr goes to a file: a failure is reported as one line, not a traceback.
  const fs::path errors = fs::temp_directory_path() / fmt::format("billiard-python-{}.err", getpid());
  const Unfinished unfinished(errors);
  posix_spawn_file_actions_t files;
  posix_spawn_file_actions_init(&files);
  posix_spawn_file_actions_addopen(&files, STDERR_FILENO, errors.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0600);
  posix_spawnattr_t attr;
  posix_spawnattr_init(&attr);
  unblock_interrupts_in_child(attr);
  pid_t pid = 0;
  const int err = posix_spawnp(&pid, argv[0], &files, &attr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&files);
  posix_spawnattr_destroy(&attr);
  if (err)
    throw std::runtime_error(fmt::format("cannot run {}: {} (set BILLIARDS_PYTHON to a python3 with matplotlib)",
                                         argv_s[0], std::strerror(err)));
  int status = 0;
  while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  const std::string message = last_line(errors);
  std::error_code ignored;
  fs::remove(errors, ignored);
  if (WIFEXITED(status) && WEXITSTATUS(status) == 0) return;
  const std::string how = WIFEXITED(status) ? fmt::format("exit status {}", WEXITSTATUS(status))
                                            : fmt::format("signal {}", WTERMSIG(status));
  throw std::runtime_error(fmt::format("drawing failed: {} ended with {}{}{}", script.filename().string(), how,
                                       message.empty() ? "" : ": ", message));
}

TempFile::~TempFile() {
  std::error_code ignored;
  fs::remove(path, ignored);
}

void draw_into(const fs::path& script, const fs::path& input, const fs::path& output,
               const std::vector<std::string>& extra) {
  try {
    if (output.has_parent_path()) fs::create_directories(output.parent_path());
  } catch (const fs::filesystem_error& e) {
    throw InputError("-o " + output.string(), 0, "cannot create its directory: " + e.code().message());
  }
  TempFile picture{fs::path(output.string() + fmt::format(".tmp-{}", getpid()) + output.extension().string())};
  std::vector<std::string> args = {input.string(), picture.path.string()};
  args.insert(args.end(), extra.begin(), extra.end());
  run_python(script, args);
  picture.unfinished.commit(output);
}

}  // namespace billiards::cli
