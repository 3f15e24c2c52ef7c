// Large arrays on transparent huge pages (dynamics/huge_pages.hpp): aligned to the huge page,
// advised to the kernel, their contents kept through growth, small ones left to operator new.
#include "billiards/dynamics/huge_pages.hpp"

#include <catch2/catch.hpp>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

using namespace billiards::dynamics;

namespace {

constexpr std::uintptr_t huge_page = std::uintptr_t(2) << 20;

/// The VmFlags of the mapping of /proc/self/smaps that holds p ("" where none is found).
std::string vm_flags_of(const void* p) {
  std::ifstream smaps("/proc/self/smaps");
  const auto at = reinterpret_cast<std::uintptr_t>(p);
  bool inside = false;
  for (std::string line; std::getline(smaps, line);) {
    std::uintptr_t lo, hi;
    char dash;
    std::istringstream range(line);
    if (line.find(' ') != std::string::npos && range >> std::hex >> lo >> dash >> hi && dash == '-')
      inside = lo <= at && at < hi;
    else if (inside && line.rfind("VmFlags:", 0) == 0)
      return line;
  }
  return "";
}

}  // namespace

TEST_CASE("a large array lies on huge pages, aligned and advised, and keeps its contents as it grows") {
  HugePageVector<std::uint64_t> v;
  const std::uint64_t n = 3 << 20;  // 24 MiB, through reallocations below and above 2 MiB
  for (std::uint64_t i = 0; i < n; ++i) v.push_back(i * 0x9e3779b97f4a7c15);
  REQUIRE(reinterpret_cast<std::uintptr_t>(v.data()) % huge_page == 0);
  bool kept = true;
  for (std::uint64_t i = 0; i < n; ++i) kept = kept && v[i] == i * 0x9e3779b97f4a7c15;
  REQUIRE(kept);
  // Advised where the kernel has transparent huge pages ("hg" in the mapping's flags).
  if (std::filesystem::exists("/sys/kernel/mm/transparent_hugepage/enabled")) {
    const std::string flags = vm_flags_of(v.data());
    INFO(flags);
    REQUIRE(flags.find(" hg") != std::string::npos);
  }
  HugePageVector<std::uint64_t> copy = v;  // (a second mapping, freed apart)
  REQUIRE(copy == v);
  v.clear();
  v.shrink_to_fit();
  REQUIRE(copy[n - 1] == (n - 1) * 0x9e3779b97f4a7c15);
}

TEST_CASE("a small array through the huge-page allocator is an ordinary aligned allocation") {
  struct alignas(64) Line {
    double x[8];
  };
  HugePageVector<Line> v(100);
  REQUIRE(reinterpret_cast<std::uintptr_t>(v.data()) % alignof(Line) == 0);
  REQUIRE(vm_flags_of(v.data()).find(" hg") == std::string::npos);
}
