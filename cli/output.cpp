#include "output.hpp"

#include <fmt/core.h>

#include <fstream>
#include <stdexcept>

#include <unistd.h>

namespace billiards::cli {

namespace fs = std::filesystem;

OutputDir::OutputDir(fs::path final_dir) : final_(std::move(final_dir)) {
  tmp_ = final_;
  tmp_ += fmt::format(".tmp-{}", getpid());
  fs::remove_all(tmp_);
  fs::create_directories(tmp_);
}

OutputDir::~OutputDir() {
  if (!committed_) {
    std::error_code ignored;
    fs::remove_all(tmp_, ignored);
  }
}

void OutputDir::write_text(const std::string& name, const std::string& text) const {
  write_stream(name, [&](std::ostream& out) { out << text; });
}

void OutputDir::write_stream(const std::string& name, const std::function<void(std::ostream&)>& writer) const {
  std::ofstream out(path(name));
  writer(out);
  out.flush();
  if (!out) throw std::runtime_error("cannot write " + path(name).string());
}

void OutputDir::write_json(const std::string& name, const nlohmann::json& j) const {
  write_text(name, j.dump(2) + "\n");
}

void OutputDir::write_npy(const std::string& name, const std::vector<double>& data, std::size_t rows,
                          std::size_t cols) const {
  // Format 1.0: magic, version, little-endian header length, a Python dict padded to 64 bytes.
  std::string header =
      fmt::format("{{'descr': '<f8', 'fortran_order': False, 'shape': ({}, {}), }}", rows, cols);
  const std::size_t total = 10 + header.size() + 1;
  header += std::string((64 - total % 64) % 64, ' ') + "\n";
  std::ofstream out(path(name), std::ios::binary);
  const unsigned short len = static_cast<unsigned short>(header.size());
  out.write("\x93NUMPY\x01\x00", 8);
  out.put(char(len & 0xff)).put(char(len >> 8));
  out << header;
  out.write(reinterpret_cast<const char*>(data.data()), std::streamsize(data.size() * sizeof(double)));
  if (!out) throw std::runtime_error("cannot write " + path(name).string());
}

void OutputDir::commit() {
  if (!final_.parent_path().empty()) fs::create_directories(final_.parent_path());
  fs::remove_all(final_);
  fs::rename(tmp_, final_);
  committed_ = true;
}

}  // namespace billiards::cli
