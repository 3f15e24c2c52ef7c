// billiard: the command-line program.  Each subcommand lives in its own file.
#include "commands.hpp"
#include "ranks.hpp"

#include "billiards/geometry/input_error.hpp"
#include "billiards/version.hpp"

#include <CLI/CLI.hpp>
#include <fmt/core.h>

#include <cstdio>

namespace billiards::cli {
namespace {
std::string the_command_line;
}
void set_command_line(int argc, char** argv) {
  for (int i = 0; i < argc; ++i) the_command_line += (i ? " " : "") + std::string(argv[i]);
}
const std::string& command_line() { return the_command_line; }
}  // namespace billiards::cli

int main(int argc, char** argv) {
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
  bool speaks = true;  // in an MPI job only the first rank prints; all compute
  try {
    const billiards::cli::Ranks ranks(argc, argv);
    speaks = ranks.root();
    if (!speaks && !std::freopen("/dev/null", "w", stdout)) return 1;
    app.parse(argc, argv);
  } catch (const CLI::Error& e) {
    return speaks ? app.exit(e) : e.get_exit_code();
  } catch (const billiards::InputError& e) {
    if (speaks) fmt::print(stderr, "billiard: error: {}\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    if (speaks) fmt::print(stderr, "billiard: error: {}\n", e.what());
    return 1;
  }
  return 0;
}
