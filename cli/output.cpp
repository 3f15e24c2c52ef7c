#include "output.hpp"

#include "billiards/geometry/input_error.hpp"

#include <fmt/core.h>

#include <fstream>
#include <stdexcept>

#include <unistd.h>

namespace billiards::cli {

namespace fs = std::filesystem;

namespace {
fs::path temporary_beside(const fs::path& final) {
  fs::path tmp = final;
  tmp += fmt::format(".tmp-{}", getpid());
  return tmp;
}
}  // namespace

void write_file_atomically(const fs::path& path, const std::string& text) {
  fs::path tmp = path;
  tmp += fmt::format(".tmp-{}", getpid());
  Unfinished unfinished(tmp);
  std::ofstream out(tmp);
  out << text;
  out.close();
  if (!out) {
    std::error_code ignored;
    fs::remove(tmp, ignored);
    throw InputError(path.string(), 0, "cannot write the file");
  }
  unfinished.commit(path);
}

OutputDir::OutputDir(fs::path final_dir)
    : final_(std::move(final_dir)), tmp_(temporary_beside(final_)), unfinished_(tmp_) {
  try {
    fs::remove_all(tmp_);
    fs::create_directories(tmp_);
  } catch (const fs::filesystem_error& e) {
    throw InputError(final_.string(), 0, "cannot create the output directory: " + e.code().message());
  }
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
  write_npy_bytes(name, "<f8", reinterpret_cast<const char*>(data.data()), data.size() * sizeof(double), rows, cols);
}

void OutputDir::write_npy(const std::string& name, const std::vector<float>& data, std::size_t rows,
                          std::size_t cols) const {
  write_npy_bytes(name, "<f4", reinterpret_cast<const char*>(data.data()), data.size() * sizeof(float), rows, cols);
}

void OutputDir::write_npy_bytes(const std::string& name, const char* descr, const char* bytes, std::size_t size,
                                std::size_t rows, std::size_t cols) const {
  // Format 1.0: magic, version, little-endian header length, a Python dict padded to 64 bytes.
  std::string header =
      fmt::format("{{'descr': '{}', 'fortran_order': False, 'shape': ({}, {}), }}", descr, rows, cols);
  const std::size_t total = 10 + header.size() + 1;
  header += std::string((64 - total % 64) % 64, ' ') + "\n";
  std::ofstream out(path(name), std::ios::binary);
  const unsigned short len = static_cast<unsigned short>(header.size());
  out.write("\x93NUMPY\x01\x00", 8);
  out.put(char(len & 0xff)).put(char(len >> 8));
  out << header;
  out.write(bytes, std::streamsize(size));
  if (!out) throw std::runtime_error("cannot write " + path(name).string());
}

void OutputDir::commit() {
  try {
    fs::remove_all(final_);
    unfinished_.commit(final_);
  } catch (const fs::filesystem_error& e) {
    throw std::runtime_error(fmt::format("cannot move the results into {}: {}", final_.string(), e.code().message()));
  }
  committed_ = true;
}

}  // namespace billiards::cli
