// Figures are drawn by matplotlib scripts in scripts/, started without a shell; those scripts,
// shapes and scenes are found in the source tree or an install prefix.
#pragma once

#include "interrupt.hpp"

#include <filesystem>
#include <string>
#include <vector>

namespace billiards::cli {

/// The bundled data (shapes/, scenes/, scripts/): $BILLIARDS_DATA if set; else, for an
/// installed program, PREFIX/share/billiards next to its bin/; else the source tree it was
/// built from.
std::filesystem::path data_dir();

/// scripts/NAME: from $BILLIARDS_SCRIPTS, else data_dir()/scripts.
std::filesystem::path script_path(const std::string& name);

/// Runs PYTHON SCRIPT ARGS... directly (no shell, so any path is passed as it is) and waits;
/// PYTHON is Debian's /usr/bin/python3 (it has python3-matplotlib) unless $BILLIARDS_PYTHON
/// says otherwise.  Throws with the interpreter, script and exit status if it fails.
void run_python(const std::filesystem::path& script, const std::vector<std::string>& args);

/// Removes its file when it goes out of scope (or the program is interrupted), so no exit path
/// leaves temporaries behind.
struct TempFile {
  std::filesystem::path path;
  Unfinished unfinished{path};
  ~TempFile();
};

/// Runs SCRIPT INPUT TMP EXTRA..., where TMP is a temporary beside `output` (same extension) that
/// is renamed to `output` only on success, so `output` is either complete or untouched.
/// Creates `output`'s directory.
void draw_into(const std::filesystem::path& script, const std::filesystem::path& input,
               const std::filesystem::path& output, const std::vector<std::string>& extra = {});

}  // namespace billiards::cli
