// The collision sequences of every bundled table, free and forced, against those recorded
// before the wall-and-flight core was rebuilt (tests/golden/collisions.csv, record_golden).
// Two builds of the same algorithm differ in the last bits (a reassociation, another compiler),
// and chaos amplifies that; so the tolerance at each collision is set by the table itself: the
// same trajectory is run again from a start moved and turned by the flight's own accuracy
// (golden::run: 1e-15 for the closed forms, the integrator's tolerance for integrated flights),
// and the runs may differ by 1e-14 of the table's size plus 100 times what that made of them,
// until the perturbed run has separated (by 1e-6 of the size): past that, chaos has the word.
#include "golden_collisions.hpp"

#include <catch2/catch.hpp>

#include <fstream>
#include <map>
#include <sstream>

namespace {

std::map<std::string, std::vector<golden::Row>> recorded() {
  std::ifstream in(std::string(BILLIARDS_SOURCE_DIR) + "/tests/golden/collisions.csv");
  std::map<std::string, std::vector<golden::Row>> rows;
  std::string line;
  std::getline(in, line);  // header
  while (std::getline(in, line)) {
    std::istringstream is(line);
    golden::Row r;
    std::string field;
    std::getline(is, r.label, ',');
    std::getline(is, field, ',');
    r.particle = std::stoi(field);
    std::getline(is, field, ',');
    r.k = std::stoi(field);
    std::getline(is, field, ',');
    r.wall = std::stol(field);
    for (double* v : {&r.t, &r.x, &r.y, &r.z}) {
      std::getline(is, field, ',');
      *v = std::stod(field);
    }
    rows[r.label].push_back(r);
  }
  return rows;
}

double distance(const golden::Row& a, const golden::Row& b) {
  return std::max({std::abs(a.t - b.t), std::abs(a.x - b.x), std::abs(a.y - b.y), std::abs(a.z - b.z)});
}

}  // namespace

TEST_CASE("collision sequences equal the recorded ones up to chaotic separation") {
  const auto golden = recorded();
  REQUIRE(golden.size() == golden::cases().size());
  std::size_t compared = 0;
  for (const auto& c : golden::cases()) {
    INFO(c.label);
    const auto run = golden::run(c), perturbed_run = golden::run(c, true);
    const auto& now = run.rows;
    const auto& perturbed = perturbed_run.rows;
    const auto& then = golden.at(c.label);
    const double size = run.size;
    std::map<std::pair<int, int>, const golden::Row*> moved;
    for (const auto& r : perturbed) moved[{r.particle, r.k}] = &r;
    std::map<int, bool> separated;
    std::size_t i = 0;
    for (const auto& r : then) {
      if (separated[r.particle]) continue;
      const auto m = moved.find({r.particle, r.k});
      const double chaos = m == moved.end() ? INFINITY : distance(r, *m->second);
      if (chaos > 1e-6 * size) {
        separated[r.particle] = true;
        continue;
      }
      while (i < now.size() && (now[i].particle < r.particle || (now[i].particle == r.particle && now[i].k < r.k))) ++i;
      INFO("particle " << r.particle << ", collision " << r.k);
      REQUIRE(i < now.size());
      REQUIRE(now[i].particle == r.particle);
      REQUIRE(now[i].k == r.k);
      CHECK(now[i].wall == r.wall);
      CHECK(distance(now[i], r) <= 1e-14 * size + 100 * chaos);
      ++compared;
    }
  }
  // Most collisions come before chaos separates the runs.
  CHECK(compared > 3000);
}
