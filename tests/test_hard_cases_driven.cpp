// Hard cases of driven flights (issue 6): ω from 2π (strong bending, chattering) to 1e5π,
// particles nearly at rest, tables scaled by 1e-6 and 1e6.  Each asserts no escape (no flight
// starts beyond a wall by more than rounding) and agreement with the same code in MPFR.
#include "hard_cases.hpp"

#include "billiards/dynamics/ensemble.hpp"
#include "billiards/dynamics/forced_flight.hpp"

#include <catch2/catch.hpp>

using namespace billiards;
using hard::Reference;
using hard::Vec2;

namespace {

/// The paper's drive, F = 10 along (1, 1)/√2 (m = 1), scaled with the table, in precision Real; its
/// phase at t = 0 is 1, so that a particle at rest drifts (at phase 0 its guiding line stands still).
template <class Real>
dynamics::BasicPeriodicDriveFlight<Real> drive(double omega_over_pi, double scale) {
  const Real a = Real(10 * scale) / sqrt(Real(2));
  return {dynamics::Vec2T<Real>(a, a), Real(omega_over_pi) * boost::math::constants::pi<Real>(), Real(1)};
}

}  // namespace

TEST_CASE("the driven clover at omega 2pi...1e5pi, scaled, from rest: as MPFR") {
  for (const double scale : {1e-6, 1.0, 1e6}) {
    const auto region = hard::shape("clover", {{"R1", std::to_string(scale)}, {"R2", std::to_string(2 * scale)}});
    const dynamics::Table table(region);
    for (const double w : {2.0, 40.0, 1e3, 1e5}) {
      for (const double speed : {1.0, 1e-9, 0.0}) {
        std::size_t worst_agree = 1000;
        double worst_beyond = 0;
        for (std::uint64_t i = 0; i < 4; ++i) {
          dynamics::ParticleRng rng(5, i);
          const dynamics::State s = dynamics::sample_microcanonical(table, speed * scale, rng);
          INFO("scale " << scale << " omega " << w << " pi, speed " << speed << ", particle " << i);
          const auto flight = drive<double>(w, scale);
          const auto walk = hard::walk(table, flight, flight.start(s), 30);
          CHECK_FALSE(walk.escaped);
          worst_beyond = std::max(worst_beyond, walk.worst_beyond / scale);
          const auto ref = hard::reference_hits(region, drive<Reference>(w, scale), s, 30);
          REQUIRE(ref.size() == 30);
          worst_agree = std::min(worst_agree, hard::agreeing(walk.hits, ref, 1e-6 * scale));
          // The first collision: time and point to the roots' polish.
          CHECK(std::abs(walk.hits[0].t - ref[0].t) <= 1e-10 * (1 + ref[0].t));
          CHECK((walk.hits[0].point - ref[0].point).norm() <= 1e-11 * scale);
        }
        // Chaos allows ~10 collisions to 1e-6 (measured 8-16); a particle starting slowly drifts
        // at F/(mω), so its flights last 1e2-1e5 periods and only the first 1-4 collisions agree
        // to 1e-6 (the first one, asserted above, to 1e-10).
        CHECK(worst_agree >= (speed == 1 ? 8u : 1u));
        CHECK(worst_beyond <= 1e-15);
      }
    }
  }
}
