// Magnetic-flight throughput: collisions per second on one core in a uniform field (cyclotron
// arcs in 2-D, B perpendicular to the plane; helices in the 3-D Sinai billiard, B along z and
// oblique), beside the straight flight in the same run, per table and cyclotron radius r_c
// (speed 1).  The Sinai billiard (the unit square less a disk of radius 1/4) at r_c = 2 is
// DynamicalBilliards.jl's benchmark: billiard_sinai() with MagneticParticle(…, ω = 0.5).
// Usage: bench_magnetic [collisions per case, default 1e7] [shape: clover, stadium, sinai, sinai3]
#include "billiards/dynamics/ensemble.hpp"
#include "billiards/dynamics/magnetic_flight.hpp"
#include "billiards/geometry.hpp"
#include "billiards/geometry3/shape3_file.hpp"
#include "throughput.hpp"

#include <fmt/core.h>

#include <cstdlib>
#include <string>
#include <vector>

using namespace billiards;

int main(int argc, char** argv) {
  const double n = argc > 1 ? std::atof(argv[1]) : 1e7;
  const std::string only = argc > 2 ? argv[2] : "";
  auto wanted = [&](const std::string& name) { return only.empty() || only == name; };
  fmt::print("{:<14} {:>6} {:>14} {:>14} {:>10} {:>8}\n", "shape", "r_c", "magnetic M/s", "straight M/s",
             "ns/bounce", "escapes");
  for (const char* name : {"clover", "stadium", "sinai"}) {
    if (!wanted(name)) continue;
    const auto region = geometry::load_shape(fmt::format("{}/shapes/{}.yaml", BILLIARDS_SOURCE_DIR, name)).region;
    const auto [straight, straight_escapes] = bench::throughput(region, dynamics::FreeFlight{}, n);
    const auto radii = std::string(name) == "sinai" ? std::vector{10.0, 2.0, 1.0, 0.3} : std::vector{10.0, 1.0, 0.3};
    for (const double rc : radii) {
      const auto [magnetic, escapes] = bench::throughput(region, dynamics::MagneticFlight{1 / rc}, n);
      fmt::print("{:<14} {:>6} {:>14.2f} {:>14.2f} {:>10.1f} {:>8}\n", name, rc, magnetic / 1e6, straight / 1e6,
                 1e9 / magnetic, escapes + straight_escapes);
    }
  }
  if (!wanted("sinai3")) return 0;
  const auto sinai3 = geometry3::load_shape3(BILLIARDS_SOURCE_DIR "/shapes/3d/sinai3.yaml").region;
  const auto [straight, straight_escapes] = bench::throughput(sinai3, dynamics::FreeFlight3{}, n);
  for (const auto& [axis, direction] : {std::pair{"z", dynamics::Vec3(0, 0, 1)},
                                        std::pair{"oblique", dynamics::Vec3(dynamics::Vec3(1, 2, 2) / 3)}})
    for (const double rc : {10.0, 1.0, 0.3}) {
      const auto [magnetic, escapes] = bench::throughput(sinai3, dynamics::MagneticFlight3{direction / rc}, n);
      fmt::print("{:<14} {:>6} {:>14.2f} {:>14.2f} {:>10.1f} {:>8}\n", fmt::format("sinai3 {}", axis), rc,
                 magnetic / 1e6, straight / 1e6, 1e9 / magnetic, escapes + straight_escapes);
    }
  return 0;
}
