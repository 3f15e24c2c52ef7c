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

/// A shape file NAME.yaml in this test's scratch folder: `head` (the file's first lines), then
/// "exits:" and `exits`.
std::filesystem::path open_shape(const std::string& name, const std::string& head, const std::string& exits) {
  const auto dir = scratch_root() / "escape";
  std::filesystem::create_directories(dir);
  const auto path = dir / (name + ".yaml");
  std::ofstream(path) << "name: " << name << "\n" << head << "exits:\n" << exits;
  return path;
}

/// The Sinai table (square of side 1, disk of radius 1/4) with an exit `exit` (YAML).
std::filesystem::path sinai_with_exit(const std::string& name, const std::string& exit) {
  return open_shape(name,
                    "parameters: {L: 1, R: 0.25, w: 0.1}\n"
                    "boundary:\n  polygon: [[-L/2, -L/2], [L/2, -L/2], [L/2, L/2], [-L/2, L/2]]\n"
                    "holes:\n  - circle: {center: [0, 0], radius: R}\n",
                    exit);
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

TEST_CASE("a scene's through_exit ensemble: Kac's lemma at its energy, --set, the same numbers on 1 and 2 threads") {
  const auto dir = scratch_root() / "escape-scene";
  std::filesystem::create_directories(dir);
  std::ofstream(dir / "clover-open.yaml") << read_file(BILLIARDS_SOURCE_DIR "/shapes/clover.yaml")
                                         << "exits:\n  - {from: [R1*sin(0.1), a + R1*cos(0.1)], to: [-R1*sin(0.1), a + R1*cos(0.1)]}\n";
  std::ofstream(dir / "open.yaml") << "shape: clover-open.yaml\nparameters: {E0: 1}\n"
                                   << "initial:\n  through_exit: {energy: 2*E0}\nrun: {particles: 6000, time: 1, seed: 4}\n";
  const auto V = geometry::measures_of(geometry::load_shape((dir / "clover-open.yaml").string()).region).volume;
  for (const double E0 : {1.0, 0.25}) {
    const auto r = billiard("escape " + (dir / "open.yaml").string() + " --set E0=" + std::to_string(E0) +
                            " --json --quiet --threads 2 --out " + (dir / "out2").string());
    INFO(r.output);
    REQUIRE(r.status == 0);
    const auto j = nlohmann::json::parse(r.output);
    CHECK(j["ensemble"] == "through_exit");
    const double v = std::sqrt(2 * 2 * E0), kac = geometry::pi * V / (0.2 * v);
    const double mean = j["mean_escape_time"], se = j["mean_escape_time_se"];
    INFO("E0 " << E0 << ": mean " << mean << " ± " << se << ", Kac " << kac);
    CHECK(std::abs(mean - kac) < 3 * se);
  }
  const auto one = billiard("escape " + (dir / "open.yaml").string() + " --particles 300 --quiet --threads 1 --out " +
                            (dir / "t1").string());
  const auto two = billiard("escape " + (dir / "open.yaml").string() + " --particles 300 --quiet --threads 2 --out " +
                            (dir / "t2").string());
  REQUIRE(one.status == 0);
  REQUIRE(two.status == 0);
  CHECK(read_file(dir / "t1" / "escape.csv") == read_file(dir / "t2" / "escape.csv"));
}

TEST_CASE("through_exit refused with its line: a shape without exits, a command that needs particles inside") {
  const auto dir = scratch_root() / "escape-bad-scene";
  std::filesystem::create_directories(dir);
  std::ofstream(dir / "closed.yaml") << "shape: " BILLIARDS_SOURCE_DIR "/shapes/clover.yaml\n"
                                     << "initial:\n  through_exit: {energy: 1}\nrun: {particles: 10, time: 1}\n";
  auto r = billiard("escape " + (dir / "closed.yaml").string() + " --quiet --out " + (dir / "out").string());
  CHECK(r.status == 2);
  CHECK(r.output.find("closed.yaml:3: 'through_exit' needs exits, and the shape file") != std::string::npos);
  CHECK(!std::filesystem::exists(dir / "out"));

  const auto open = sinai_with_exit("sinai-run", "  - {from: [-w/2, -L/2], to: [w/2, -L/2]}\n");
  std::ofstream(dir / "run.yaml") << "shape: " << open.string() << "\ninitial:\n  through_exit: {energy: 1}\n"
                                  << "run: {particles: 10, time: 1}\n";
  r = billiard("run " + (dir / "run.yaml").string() + " --quiet --out " + (dir / "run-out").string());
  INFO(r.output);
  CHECK(r.status == 2);
  CHECK(r.output.find("run.yaml:3: particles entering through exits ('through_exit') are for open tables") !=
        std::string::npos);
  CHECK(!std::filesystem::exists(dir / "run-out"));
  std::ofstream(dir / "both.yaml") << "shape: " << open.string() << "\ninitial:\n  through_exit: {energy: 1}\n"
                                   << "  microcanonical: {energy: 1}\nrun: {particles: 10, time: 1}\n";
  r = billiard("escape " + (dir / "both.yaml").string() + " --quiet --out " + (dir / "out").string());
  CHECK(r.status == 2);
  CHECK(r.output.find("both.yaml:3: 'initial' takes one of") != std::string::npos);
}

namespace {

/// The 3-D Sinai table (cube of side 1, ball of radius 1/4) with the exits `exits` (YAML).
std::filesystem::path sinai3_with_exit(const std::string& name, const std::string& exits) {
  return open_shape(name,
                    "dimension: 3\nparameters: {L: 1, R: 0.25, r: 0.2}\n"
                    "boundary:\n  box: {min: [-L/2, -L/2, -L/2], max: [L/2, L/2, L/2]}\n"
                    "holes:\n  - ball: {center: [0, 0, 0], radius: R}\n",
                    exits);
}

}  // namespace

TEST_CASE("3-D: particles entering through a disc of area A stay 4 V / (A v) on average, and leave through it only") {
  const auto shape = geometry3::load_shape3(
      sinai3_with_exit("sinai3-open", "  - disc: {center: [L/2, 0.1, -0.1], radius: r}\n").string());
  const dynamics::Table3 table(shape.region);
  const analysis::Exits3 exits(analysis::read_exits3(shape));
  const double A = geometry::pi * 0.2 * 0.2;
  REQUIRE(exits.area() == Approx(A).epsilon(1e-12));
  const double V = 1 - 4 * geometry::pi / 3 * std::pow(0.25, 3);
  const double speed = 1.5;
  const auto initial = [&](std::size_t i) {
    dynamics::ParticleRng rng(7, i);
    return exits.entering_state(speed, rng);
  };
  const auto leaves = [&](const auto& hit) { return exits.contains(hit.wall, hit.point); };
  const auto r = analysis::escape_times(table, dynamics::FreeFlight3{}, initial, leaves, 20000, 1000000, 2);
  std::vector<double> times;
  for (const auto& e : r) {
    REQUIRE(e.escaped);
    times.push_back(e.time);
  }
  const auto m = analysis::sample_moments(times);
  const double kac = 4 * V / (A * speed);
  INFO("mean " << m.mean << " ± " << m.se_mean << ", Kac " << kac);
  CHECK(std::abs(m.mean - kac) < 3 * m.se_mean);
  // Every hit before the escape is off the disc, the escape's on it (checked from the points).
  for (std::size_t i = 0; i < 300; ++i) {
    std::vector<geometry3::Vec3> points;
    dynamics::evolve(table, dynamics::FreeFlight3{}, initial(i), r[i].collisions + 1,
                     [&](const auto& hit, const auto&) { points.push_back(hit.point); });
    for (std::size_t k = 0; k < points.size(); ++k) {
      const auto& p = points[k];
      const bool on_disc = std::abs(p.x() - 0.5) < 1e-9 && std::hypot(p.y() - 0.1, p.z() + 0.1) <= 0.2;
      CHECK(on_disc == (k == r[i].collisions));
    }
  }
}

TEST_CASE("billiard escape in 3-D: JSON, a through_exit scene, 1 and 2 threads alike; discs off a face refused") {
  const auto good = sinai3_with_exit("sinai3-cli", "  - disc: {center: [0, -L/2, 0.2], radius: r}\n");
  const auto dir = scratch_root() / "escape3-out";
  std::filesystem::create_directories(dir);
  std::ofstream(dir / "scene.yaml") << "shape: " << good.string() << "\ninitial:\n  through_exit: {energy: 2}\n"
                                    << "run: {particles: 400, time: 1, seed: 5}\n";
  const auto one = billiard("escape " + (dir / "scene.yaml").string() + " --json --quiet --threads 1 --out " +
                            (dir / "t1").string());
  const auto two = billiard("escape " + (dir / "scene.yaml").string() + " --json --quiet --threads 2 --out " +
                            (dir / "t2").string());
  INFO(one.output);
  REQUIRE(one.status == 0);
  REQUIRE(two.status == 0);
  CHECK(read_file(dir / "t1" / "escape.csv") == read_file(dir / "t2" / "escape.csv"));
  const auto j = nlohmann::json::parse(one.output);
  CHECK(j["exit_length"].get<double>() == Approx(geometry::pi * 0.04));
  CHECK(j["speed"].get<double>() == Approx(2.0));
  CHECK(j["ensemble"] == "through_exit");

  const auto off = sinai3_with_exit("sinai3-off", "  - disc: {center: [0, 0.3, 0.2], radius: r}\n");
  auto r = billiard("escape " + off.string() + " --entering --out " + (dir / "bad").string());
  CHECK(r.status == 2);
  CHECK(r.output.find("sinai3-off.yaml:9: the exit's centre (0, 0.3, 0.2) is not on a face of the polyhedron") !=
        std::string::npos);
  const auto wide = sinai3_with_exit("sinai3-wide", "  - disc: {center: [L/2, 0.4, 0], radius: r}\n");
  r = billiard("escape " + wide.string() + " --entering --out " + (dir / "bad").string());
  CHECK(r.status == 2);
  CHECK(r.output.find("sinai3-wide.yaml:9: the exit's disc (radius 0.2) reaches beyond the face") != std::string::npos);
  CHECK(!std::filesystem::exists(dir / "bad"));
}
