// Registration of the subcommands of `billiard`.
#pragma once

#include <CLI/CLI.hpp>

namespace billiards::cli {

void add_info(CLI::App& app);

}  // namespace billiards::cli
