// billiard: the command-line program.  Each subcommand lives in its own file.
//
// Every failure ends here with one line `billiard: error: ...` on stderr and a documented exit
// status (docs/commands.md): 2 bad input (a file, an option, the command line), 1 a failure to
// complete (cannot write, out of memory), 3 particles escaped, 128 + signal when interrupted
// (interrupt.hpp).
#include "commands.hpp"
#include "interrupt.hpp"
#include "ranks.hpp"

#include "billiards/dynamics/simd.hpp"
#include "billiards/geometry/input_error.hpp"
#include "billiards/version.hpp"

#include <CLI/CLI.hpp>
#include <fmt/core.h>

#include <cstdio>
#include <filesystem>
#include <new>
#include <optional>
#include <string>

namespace billiards::cli {
namespace {
std::string the_command_line;

/// The commands as a list for messages: "info, run, ...".
std::string command_names(const CLI::App& app) {
  std::string names;
  for (const auto* sub : app.get_subcommands([](const CLI::App*) { return true; }))
    names += (names.empty() ? "" : ", ") + sub->get_name();
  return names;
}

/// The first word, when it is not an option, must name a command (CLI11 would call it "an
/// extra argument" or say that a subcommand is required).
void require_known_command(const CLI::App& app, int argc, char** argv) {
  const std::string hint = "; the commands are " + command_names(app) + " ('billiard --help' describes them)";
  if (argc < 2) throw InputError("", 0, "no command given" + hint);
  const std::string first = argv[1];
  if (first.empty() || first[0] == '-') return;
  for (const auto* sub : app.get_subcommands([](const CLI::App*) { return true; }))
    if (sub->check_name(first)) return;
  throw InputError("", 0, "unknown command '" + first + "'" + hint);
}
}  // namespace

void set_command_line(int argc, char** argv) {
  for (int i = 0; i < argc; ++i) the_command_line += (i ? " " : "") + std::string(argv[i]);
}
const std::string& command_line() { return the_command_line; }
}  // namespace billiards::cli

int main(int argc, char** argv) {
  billiards::cli::watch_interrupts();
  CLI::App app{"billiard: exact geometry, dynamics and energy diffusion of billiards"};
  app.require_subcommand(1);
  app.set_version_flag("--version", std::string("billiard ") + billiards::version);
  billiards::cli::set_command_line(argc, argv);
  billiards::cli::add_info(app);
  billiards::cli::add_run(app);
  billiards::cli::add_coeffs(app);
  billiards::cli::add_plot(app);
  billiards::cli::add_fp(app);
  billiards::cli::add_compare(app);
  billiards::cli::add_bench(app);
  billiards::cli::add_animate(app);
  billiards::cli::add_bmap(app);
  billiards::cli::add_lyapunov(app);
  billiards::cli::add_chaos(app);
  billiards::cli::add_escape(app);
  billiards::cli::add_trajectory(app);
  bool speaks = true;  // in an MPI job only the first rank prints; all compute
  std::optional<billiards::cli::Ranks> ranks;  // (MPI ends after the error is out)
  // A failed job's ranks leave together: an MPI launcher stops the job at the first rank that
  // exits with an error, and would stop the first rank before it has printed the message.  A
  // rank that fails alone, the others still at work, prints its own message and ends the job.
  const auto failed = [&](const std::string& message, int status) {
    if (ranks && !ranks->fail_together(10)) {
      if (!speaks) fmt::print(stderr, "billiard: error: rank {}: {}\n", ranks->rank(), message);
      ranks->abort(status);
    }
    return status;
  };
  const auto error = [&](const std::string& message, int status) {
    if (speaks) fmt::print(stderr, "billiard: error: {}\n", message);
    return failed(message, status);
  };
  try {
    ranks.emplace(argc, argv);
    speaks = ranks->root();
    if (!speaks && !std::freopen("/dev/null", "w", stdout)) return 1;
    billiards::cli::require_known_command(app, argc, argv);
    billiards::dynamics::simd::chosen_target();  // (BILLIARDS_SIMD checked before any output)
    app.parse(argc, argv);
  } catch (const CLI::Success& e) {  // --help
    return speaks ? app.exit(e) : 0;
  } catch (const CLI::RuntimeError& e) {  // a command's own status, its message printed
    return e.get_exit_code() == 0 ? 0 : failed("exit status " + std::to_string(e.get_exit_code()), e.get_exit_code());
  } catch (const CLI::Error& e) {
    std::string help = "billiard --help";
    for (const auto* sub : app.get_subcommands()) help = "billiard " + sub->get_name() + " --help";
    return error(fmt::format("{} (see '{}')", e.what(), help), 2);
  } catch (const billiards::InputError& e) {
    return error(e.what(), 2);
  } catch (const std::bad_alloc&) {
    return error("out of memory", 1);
  } catch (const std::filesystem::filesystem_error& e) {
    return error(fmt::format("{}: {}", e.path1().string(), e.code().message()), 1);
  } catch (const std::exception& e) {
    return error(e.what(), 1);
  }
  return 0;
}
