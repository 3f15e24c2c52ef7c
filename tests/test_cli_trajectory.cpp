// `billiard trajectory`: one particle's rows streamed to chunked .npy files.  The rows are checked
// against a dynamics::follow written here from the same scene and start, bit for bit and for any
// chunk size; a run of 10⁷ collisions against the memory its rows would need; bad input and
// Ctrl-C against "nothing written".
#include "cli_helpers.hpp"

#include "billiards/dynamics/follow.hpp"
#include "billiards/dynamics/scene_run.hpp"

#include <catch2/catch.hpp>

#include <chrono>
#include <csignal>
#include <cstring>
#include <thread>

#include <fcntl.h>
#include <sys/resource.h>
#include <sys/wait.h>

namespace fs = std::filesystem;
using namespace billiards;

namespace {

/// One .npy file's float64 matrix as (rows, columns, values); the header is parsed, not assumed.
struct Npy {
  std::size_t rows = 0, cols = 0;
  std::vector<double> values;
};

Npy read_matrix(const fs::path& p) {
  const std::string bytes = read_file(p);
  REQUIRE(bytes.substr(0, 8) == std::string("\x93NUMPY\x01\x00", 8));
  const std::size_t header_len = std::size_t(std::uint8_t(bytes[8])) | std::size_t(std::uint8_t(bytes[9])) << 8;
  const std::string header = bytes.substr(10, header_len);
  REQUIRE_THAT(header, Catch::Contains("'descr': '<f8'") && Catch::Contains("'fortran_order': False"));
  Npy m;
  REQUIRE(std::sscanf(header.c_str() + header.find("'shape': (") + 10, "%zu, %zu", &m.rows, &m.cols) == 2);
  const std::size_t data = 10 + header_len;
  REQUIRE(bytes.size() == data + m.rows * m.cols * sizeof(double));
  m.values.resize(m.rows * m.cols);
  std::memcpy(m.values.data(), bytes.data() + data, bytes.size() - data);
  return m;
}

/// Every chunk the index lists, concatenated; checks that the chunks are the directory's files
/// and that none is larger than `chunk` rows.
std::vector<double> all_rows(const fs::path& dir, std::size_t chunk) {
  const auto index = read_json(dir / "trajectory.json");
  std::vector<double> rows;
  std::size_t files = 0, total = 0;
  for (const auto& c : index["chunks"]) {
    const Npy m = read_matrix(dir / c["file"].get<std::string>());
    CHECK(m.cols == index["columns"].size());
    CHECK(m.rows == c["rows"].get<std::size_t>());
    CHECK(m.rows <= chunk);
    rows.insert(rows.end(), m.values.begin(), m.values.end());
    total += m.rows;
    ++files;
  }
  CHECK(total == index["rows"].get<std::size_t>());
  CHECK(std::size_t(std::distance(fs::directory_iterator(dir), fs::directory_iterator())) == files + 1);
  return rows;
}

/// The rows `billiard trajectory` should write for particle `particle` of `scene`, made here by
/// following it: the start (wall −1), then each sample (wall −2) and bounce (its piece) in order.
std::vector<double> followed_rows(const dynamics::Scene& scene, std::size_t particle, std::size_t collisions, double dt) {
  std::vector<double> rows;
  dynamics::with_flight(scene, [&](const auto& flight) {
    const auto table = dynamics::table_of<std::decay_t<decltype(flight)>>(scene);
    const auto add = [&](const auto& s, double wall) {
      rows.push_back(s.t);
      for (int i = 0; i < s.x.size(); ++i) rows.push_back(s.x[i]);
      for (int i = 0; i < s.v.size(); ++i) rows.push_back(s.v[i]);
      rows.push_back(wall);
      rows.push_back(dynamics::energy_of(flight, s, scene.mass));
    };
    const auto s = dynamics::initial_states(scene, table, flight)(particle);
    add(s, -1);
    dynamics::follow(
        table, flight, s, {.collisions = collisions}, dynamics::SampleClock{s.t, dt},
        [&](const auto& hit, const auto& after) { add(after, table.piece_of(hit.wall)); },
        [&](const auto& state) { add(state, -2); });
  });
  return rows;
}

bool same_bits(const std::vector<double>& a, const std::vector<double>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(double)) == 0;
}

/// Nothing at `out`, and no temporary beside it.
bool leaves_nothing(const fs::path& out) {
  if (fs::exists(out)) return false;
  for (const auto& e : fs::directory_iterator(out.parent_path()))
    if (e.path().filename().string().rfind(out.filename().string(), 0) == 0) return false;
  return true;
}

/// Runs `billiard ARGS` (split at spaces) from the source root, without a shell, and returns its
/// exit status and peak resident memory in MB (the child's own, from wait4).
std::pair<int, double> run_measured(const std::vector<std::string>& args) {
  const pid_t pid = fork();
  if (pid == 0) {
    const int null = ::open("/dev/null", O_WRONLY);
    dup2(null, STDOUT_FILENO);
    dup2(null, STDERR_FILENO);
    if (chdir(BILLIARDS_SOURCE_DIR) != 0) _exit(127);
    std::vector<char*> argv{const_cast<char*>(BILLIARDS_BINARY)};
    for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    execv(BILLIARDS_BINARY, argv.data());
    _exit(127);
  }
  int status = 0;
  rusage usage{};
  wait4(pid, &status, 0, &usage);
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, double(usage.ru_maxrss) / 1024};
}

}  // namespace

TEST_CASE("trajectory writes the followed rows of a scene's particle, whatever the chunk size") {
  const auto dir = scratch("trajectory-scene");
  const std::string scene_file = BILLIARDS_SOURCE_DIR "/scenes/clover-driven.yaml";
  dynamics::SceneOverrides ov;
  ov.seed = 7;
  const auto scene = dynamics::load_scene(scene_file, ov);
  const auto expected = followed_rows(scene, 3, 500, 0.01);
  REQUIRE(expected.size() > 7 * 1000);  // the samples outnumber the bounces
  for (const std::size_t chunk : {97, 65536}) {
    const auto out = dir / ("chunk-" + std::to_string(chunk));
    const auto r = billiard("trajectory scenes/clover-driven.yaml --collisions 500 --dt 0.01 --particle 3 --seed 7 "
                            "--quiet --chunk " + std::to_string(chunk) + " --out " + out.string());
    INFO(r.output);
    REQUIRE(r.status == 0);
    CHECK(same_bits(all_rows(out, chunk), expected));
    const auto index = read_json(out / "trajectory.json");
    CHECK(index["collisions"] == 500);
    CHECK(index["columns"] == nlohmann::json({"t", "x", "y", "vx", "vy", "wall", "energy"}));
    CHECK(index["chunks"].size() == (expected.size() / 7 + chunk - 1) / chunk);
    CHECK(index["escaped"] == false);
  }
}

TEST_CASE("trajectory of a shape: a free particle at speed 1 in 2-D and 3-D, as the scene of that shape") {
  const auto dir = scratch("trajectory-shape");
  for (const std::string shape : {"shapes/stadium.yaml", "shapes/3d/sinai3.yaml"}) {
    const auto out = dir / fs::path(shape).stem();
    const auto r = billiard("trajectory " + shape + " --collisions 300 --particle 2 --seed 11 --quiet --chunk 64 --out " +
                            out.string());
    INFO(r.output);
    REQUIRE(r.status == 0);
    // The scene the documentation says a shape stands for: free, E = 1/2, m = 1, seed 11.
    const auto scene = dynamics::parse_scene("shape: " + std::string(BILLIARDS_SOURCE_DIR "/") + shape +
                                                 "\ninitial:\n  microcanonical: {energy: 1/2}\nrun:\n  particles: 3\n  time: 1\n  seed: 11\n",
                                             "test", ".", {});
    const auto rows = all_rows(out, 64);
    CHECK(same_bits(rows, followed_rows(scene, 2, 300, 0)));
    const std::size_t cols = read_json(out / "trajectory.json")["columns"].size();
    CHECK(cols == (scene.dimension() == 3 ? 9 : 7));
    for (std::size_t i = 0; i < rows.size(); i += cols) CHECK(rows[i + cols - 1] == Approx(0.5).epsilon(1e-14));
  }
}

TEST_CASE("10^7 collisions stream through bounded memory") {
  // Holding the rows would take 10^7 x 7 doubles = 560 MB; the run's peak stays below 80 MB.
  const auto out = scratch("trajectory-long") / "out";
  const auto [status, peak_mb] =
      run_measured({"trajectory", "shapes/circle.yaml", "--collisions", "1e7", "--quiet", "--out", out.string()});
  REQUIRE(status == 0);
  INFO("peak resident memory " << peak_mb << " MB");
  CHECK(peak_mb < 80);
  const auto index = read_json(out / "trajectory.json");
  CHECK(index["rows"] == 10000001);
  // The last chunk: a circle's free orbit keeps its speed.
  const Npy last = read_matrix(out / index["chunks"].back()["file"].get<std::string>());
  CHECK(std::hypot(last.values[last.values.size() - 4], last.values[last.values.size() - 3]) == Approx(1).epsilon(1e-12));
  fs::remove_all(out);
}

TEST_CASE("trajectory refuses bad input with exit 2 and writes nothing") {
  const auto dir = scratch("trajectory-bad");
  const auto out = dir / "out";
  const auto refused = [&](const std::string& args, const std::string& what) {
    const auto r = billiard("trajectory " + args + " --quiet --out " + out.string());
    INFO(r.output);
    CHECK(r.status == 2);
    CHECK_THAT(r.output, Catch::StartsWith("billiard: error: ") && Catch::Contains(what));
    CHECK(leaves_nothing(out));
  };
  refused("shapes/circle.yaml --collisions -5", "--collisions: must be a whole number from 1");
  refused("scenes/clover-driven.yaml --particle 1000000", "--particle: particle 1000000 is not in the scene");
  refused("shapes/no-such-shape.yaml", "no-such-shape.yaml");
  refused("shapes/circle.yaml --dt 0", "--dt: must be a positive finite number");
  refused("shapes/circle.yaml --time inf", "--time");
  refused("scenes/clover-magnetic-driven.yaml --collisions 50", "clover-magnetic-driven.yaml: a magnetic field with a force is followed to a time: give --time");
  const auto r = billiard("trajectory scenes/clover-magnetic-driven.yaml --time 2 --quiet --out " + out.string());
  INFO(r.output);
  CHECK(r.status == 0);
  CHECK(fs::exists(out / "trajectory.json"));
  fs::remove_all(out);
}

TEST_CASE("Ctrl-C stops a trajectory within a second and leaves nothing") {
  const auto out = scratch("trajectory-interrupt") / "out";
  const pid_t pid = fork();
  if (pid == 0) {
    const int null = ::open("/dev/null", O_WRONLY);
    dup2(null, STDOUT_FILENO);
    dup2(null, STDERR_FILENO);
    execl(BILLIARDS_BINARY, BILLIARDS_BINARY, "trajectory", BILLIARDS_SOURCE_DIR "/scenes/clover-driven.yaml",
          "--collisions", "1e9", "--quiet", "--out", out.c_str(), nullptr);
    _exit(127);
  }
  std::this_thread::sleep_for(std::chrono::milliseconds(1500));
  kill(pid, SIGINT);
  const auto sent = std::chrono::steady_clock::now();
  int status = 0;
  waitpid(pid, &status, 0);
  CHECK(std::chrono::duration<double>(std::chrono::steady_clock::now() - sent).count() < 1);
  CHECK(WIFEXITED(status));
  CHECK(WEXITSTATUS(status) == 130);
  CHECK(leaves_nothing(out));
}
