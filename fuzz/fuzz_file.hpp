// Readers that take a path (meshes, initial conditions) get the fuzzer's bytes through a
// file of this process's own.
#pragma once

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>

#include <unistd.h>

inline std::filesystem::path write_fuzz_file(const std::uint8_t* data, std::size_t size, const std::string& ext) {
  const auto path = std::filesystem::temp_directory_path() / ("billiards-fuzz-" + std::to_string(getpid()) + ext);
  std::ofstream(path, std::ios::binary).write(reinterpret_cast<const char*>(data), std::streamsize(size));
  return path;
}
