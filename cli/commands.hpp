// Registration of the subcommands of `billiard`.
#pragma once

#include <CLI/CLI.hpp>

#include <string>

namespace billiards::cli {

void add_info(CLI::App& app);
void add_run(CLI::App& app);
void add_coeffs(CLI::App& app);
void add_plot(CLI::App& app);
void add_fp(CLI::App& app);
void add_compare(CLI::App& app);
void add_bench(CLI::App& app);
void add_animate(CLI::App& app);
void add_bmap(CLI::App& app);
void add_lyapunov(CLI::App& app);
void add_chaos(CLI::App& app);
void add_escape(CLI::App& app);
void add_trajectory(CLI::App& app);

/// The command line as typed, recorded in summary.json.
void set_command_line(int argc, char** argv);
const std::string& command_line();

}  // namespace billiards::cli
