// Writes the golden collision sequences (golden_collisions.hpp) to standard output as CSV:
//   record_golden > tests/golden/collisions.csv
#include "golden_collisions.hpp"

#include <cstdio>

int main() {
  std::printf("case,particle,collision,wall,t,x,y,z\n");
  for (const auto& c : golden::cases())
    for (const auto& r : golden::run(c).rows)
      std::printf("%s,%d,%d,%ld,%.17g,%.17g,%.17g,%.17g\n", r.label.c_str(), r.particle, r.k, r.wall, r.t, r.x, r.y, r.z);
}
