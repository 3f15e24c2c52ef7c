// Open tables (analysis/escape.hpp, `billiard escape`): Kac's lemma for particles entering
// through an exit, the exponential survival of a small exit, escapes only through exits, and
// exits that are not on the boundary refused with their line.
#include "cli_helpers.hpp"

#include "billiards/analysis/escape.hpp"
#include "billiards/analysis/statistics.hpp"
#include "billiards/geometry/measures.hpp"

#include <catch2/catch.hpp>

#include <fstream>
#include <string>

using namespace billiards;

namespace {

/// The Sinai table (square of side 1, disk of radius 1/4) with an exit `exit` (YAML).
std::filesystem::path sinai_with_exit(const std::string& name, const std::string& exit) {
  const auto dir = scratch_root() / "escape";
  std::filesystem::create_directories(dir);
  const auto path = dir / (name + ".yaml");
  std::ofstream(path) << "name: " << name << "\nparameters: {L: 1, R: 0.25, w: 0.1}\n"
                      << "boundary:\n  polygon: [[-L/2, -L/2], [L/2, -L/2], [L/2, L/2], [-L/2, L/2]]\n"
                      << "holes:\n  - circle: {center: [0, 0], radius: R}\n"
                      << "exits:\n" << exit;
  return path;
}

struct Open {
  geometry::Shape shape;
  dynamics::Table table;
  analysis::BoundaryCoordinates coordinates;
  analysis::Exits exits;
  explicit Open(const std::filesystem::path& path)
      : shape(geometry::load_shape(path.string())), table(shape.region), coordinates(shape.region),
        exits(coordinates, analysis::read_exits(shape, coordinates)) {}
};

}  // namespace

TEST_CASE("Kac's lemma: particles entering through an exit of length w stay pi V / (w v) on average") {
  // The clover (dispersing and focusing arcs, no flat walls: a finite horizon, so escape times
  // have a finite variance and the SE is a fair yardstick), open on the top of its upper lobe.
  const auto path = scratch_root() / "escape" / "clover-open.yaml";
  std::filesystem::create_directories(path.parent_path());
  std::ofstream(path) << read_file(BILLIARDS_SOURCE_DIR "/shapes/clover.yaml")
                      << "exits:\n  - {from: [R1*sin(0.1), a + R1*cos(0.1)], to: [-R1*sin(0.1), a + R1*cos(0.1)]}\n";
  const Open open(path);
  REQUIRE(open.exits.length() == Approx(0.2).epsilon(1e-12));
  const double V = geometry::measures_of(open.shape.region).volume;
  for (const double speed : {1.0, 2.5}) {
    const auto initial = [&](std::size_t i) {
      dynamics::ParticleRng rng(5, i);
      return analysis::entering_state(open.coordinates, open.exits, speed, rng);
    };
    const auto r = analysis::escape_times(open.table, open.coordinates, open.exits, dynamics::FreeFlight{}, initial,
                                          20000, 1000000, 2);
    std::vector<double> times;
    for (const auto& e : r) {
      REQUIRE(e.escaped);
      times.push_back(e.time);
    }
    const auto m = analysis::sample_moments(times);
    const double kac = geometry::pi * V / (open.exits.length() * speed);
    INFO("speed " << speed << ": mean " << m.mean << " ± " << m.se_mean << ", Kac " << kac);
    CHECK(std::abs(m.mean - kac) < 3 * m.se_mean);
  }
}

TEST_CASE("a small exit: the survival of particles started inside decays like exp(-w v t / (pi V))") {
  const Open open(sinai_with_exit("sinai-small", "  - {from: [L/2, -w/4], to: [L/2, w/4]}\n"));  // w = 0.05
  const double tau = geometry::pi * geometry::measures_of(open.shape.region).volume / open.exits.length();
  const std::size_t n = 20000;
  const auto r = analysis::escape_times(open.table, open.coordinates, open.exits, dynamics::FreeFlight{},
                                        dynamics::microcanonical(open.table, dynamics::FreeFlight{}, 1.0, 3), n,
                                        1000000, 2);
  for (const double t : {0.5 * tau, tau, 2 * tau}) {
    std::size_t inside = 0;
    for (const auto& e : r) inside += e.time > t;
    const double P = double(inside) / double(n), expected = std::exp(-t / tau);
    INFO("t = " << t << ": P = " << P << ", exp(-t/tau) = " << expected);
    // Binomial noise, and the law's own correction for an exit of 1/80 of the perimeter.
    CHECK(std::abs(P - expected) < 4 * std::sqrt(expected * (1 - expected) / double(n)) + 0.02 * expected);
  }
}

TEST_CASE("particles leave through the exits only: a wrapping exit on a hole, checked along each trajectory") {
  // The hole runs clockwise from (R, 0): from (0, R) to (0, −R) in its direction is its right
  // half, across the hole's first point, where s wraps.
  const Open open(sinai_with_exit("sinai-hole-exit", "  - {from: [0, R], to: [0, -R]}\n"));
  CHECK(open.exits.length() == Approx(geometry::pi * 0.25).epsilon(1e-9));
  const auto initial = dynamics::microcanonical(open.table, dynamics::FreeFlight{}, 1.0, 9);
  const auto r = analysis::escape_times(open.table, open.coordinates, open.exits, dynamics::FreeFlight{}, initial, 500,
                                        100000, 2);
  for (std::size_t i = 0; i < r.size(); ++i) {
    REQUIRE(r[i].escaped);
    const auto hits = dynamics::evolve(open.table, dynamics::FreeFlight{}, initial(i), r[i].collisions + 1);
    for (std::size_t k = 0; k < hits.size(); ++k) {
      const auto& p = hits[k].point;
      const bool on_exit = std::abs(p.norm() - 0.25) < 1e-9 && p.x() >= -1e-12;
      CHECK(on_exit == (k == r[i].collisions));
    }
    CHECK(hits.back().t == Approx(r[i].time));
  }
}

TEST_CASE("billiard escape: the survival files and JSON; exits off the boundary refused with their line") {
  const auto good = sinai_with_exit("sinai-cli", "  - {from: [-w/2, -L/2], to: [w/2, -L/2]}\n");
  const auto dir = scratch_root() / "escape-out";
  auto r = billiard("escape " + good.string() + " --entering --particles 2000 --json --quiet --out " + dir.string());
  INFO(r.output);
  REQUIRE(r.status == 0);
  const auto j = nlohmann::json::parse(r.output);
  CHECK(j["exit_length"].get<double>() == Approx(0.1));
  CHECK(j["mean_escape_time"].get<double>() > 0);
  CHECK(j["mean_escape_time_se"].get<double>() > 0);
  for (const char* file : {"escape.csv", "survival.csv", "escape.json", "survival.png"})
    CHECK(std::filesystem::exists(dir / file));

  const auto off = sinai_with_exit("sinai-off", "  - {from: [0, 0.1], to: [w/2, -L/2]}\n");
  r = billiard("escape " + off.string() + " --out " + (dir / "bad").string());
  CHECK(r.status == 2);
  CHECK(r.output.find("sinai-off.yaml:8: the exit's 'from' point (0, 0.1) is not on the boundary") != std::string::npos);
  const auto empty = sinai_with_exit("sinai-empty", "  - {from: [w/2, -L/2], to: [w/2, -L/2]}\n");
  r = billiard("escape " + empty.string() + " --out " + (dir / "bad").string());
  CHECK(r.status == 2);
  CHECK(r.output.find("sinai-empty.yaml:8: the exit is empty") != std::string::npos);
  CHECK(!std::filesystem::exists(dir / "bad"));
}
