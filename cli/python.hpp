// Figures are drawn by matplotlib scripts in scripts/, started without a shell.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace billiards::cli {

/// scripts/NAME: from $BILLIARDS_SCRIPTS, else the source tree this program was built from.
std::filesystem::path script_path(const std::string& name);

/// Runs PYTHON SCRIPT ARGS... directly (no shell, so any path is passed as it is) and waits;
/// PYTHON is Debian's /usr/bin/python3 (it has python3-matplotlib) unless $BILLIARDS_PYTHON
/// says otherwise.  Throws with the interpreter, script and exit status if it fails.
void run_python(const std::filesystem::path& script, const std::vector<std::string>& args);

}  // namespace billiards::cli
