// libFuzzer target: the scene reader (and, through its `shape:` paths, the 2-D and 3-D shape
// readers), relative to scenes/ as the bundled scenes are.
#include "billiards/dynamics/scene.hpp"

#include <cstdint>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  try {
    billiards::dynamics::parse_scene(std::string(reinterpret_cast<const char*>(data), size), "fuzz.yaml",
                                     BILLIARDS_SOURCE_DIR "/scenes");
  } catch (const billiards::InputError&) {
  }
  return 0;
}
