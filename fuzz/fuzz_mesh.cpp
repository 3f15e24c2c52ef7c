// libFuzzer target: the mesh readers (OFF, OBJ, STL through CGAL, then the manifold, closed,
// self-intersection and orientation checks).  The first byte picks the format.
#include "fuzz_file.hpp"

#include "billiards/geometry/input_error.hpp"
#include "billiards/geometry3/region3.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  static const char* const formats[] = {".off", ".obj", ".stl"};
  const auto path = write_fuzz_file(data + 1, size - 1, formats[data[0] % 3]);
  try {
    billiards::geometry3::read_mesh(path.string(), {"fuzz.yaml", 1});
  } catch (const billiards::InputError&) {
  }
  std::filesystem::remove(path);
  return 0;
}
