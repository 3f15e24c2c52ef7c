// libFuzzer target: the initial-condition CSV of a scene (x, y, vx, vy per line), read for
// the unit square.
#include "fuzz_file.hpp"

#include "billiards/dynamics/scene.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto path = write_fuzz_file(data, size, ".csv");
  const std::string scene = "shape: " BILLIARDS_SOURCE_DIR "/shapes/square.yaml\ninitial: {csv: " + path.string() +
                            "}\nrun: {time: 1}\n";
  try {
    billiards::dynamics::parse_scene(scene, "fuzz.yaml", ".");
  } catch (const billiards::InputError&) {
  }
  std::filesystem::remove(path);
  return 0;
}
