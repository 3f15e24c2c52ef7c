// Bad input never crashes, hangs or lies: every class of malformed input (extreme numbers,
// wrapped integers, duplicate keys, bytes that are not UTF-8, impossible outputs, Ctrl-C) ends
// with one `billiard: error: ...` line, a documented exit status and no output directory but
// (for an interrupted run) its checkpoint.
#include "cli_helpers.hpp"

#include <catch2/catch.hpp>

#include <chrono>
#include <cmath>
#include <csignal>
#include <thread>

#include <fcntl.h>

namespace fs = std::filesystem;

namespace {

const std::string shapes = BILLIARDS_SOURCE_DIR "/shapes/";

/// A driven clover scene with `extra` lines under `run:` replaced by the caller's text.
std::string driven_scene(const std::string& run = "  particles: 200\n  time: 2\n", const std::string& top = "") {
  return top + "shape: " + shapes + "clover.yaml\nmass: 1\ninitial:\n  microcanonical: {energy: 1/2}\n"
         "force:\n  periodic: {amplitude: [5, 5], omega: 40*pi}\nrun:\n" + run;
}

/// Output paths a failed command must not leave: OUT, OUT.partial, OUT.tmp-*.
bool leaves_nothing(const fs::path& out) {
  if (fs::exists(out) || fs::exists(out.string() + ".partial")) return false;
  for (const auto& e : fs::directory_iterator(out.parent_path()))
    if (e.path().filename().string().rfind(out.filename().string() + ".tmp", 0) == 0) return false;
  return true;
}

/// Runs `billiard run SCENE ARGS --out DIR/out`, SCENE written from `yaml`.
CommandResult run_scene(const fs::path& dir, const std::string& yaml, const std::string& args = "") {
  write_file(dir / "scene.yaml", yaml);
  return billiard("run " + (dir / "scene.yaml").string() + " --quiet --threads 2 --out " + (dir / "out").string() +
                  " " + args);
}

/// The command failed as promised: one error line naming `what`, exit status 2, no output.
void check_refused(const CommandResult& r, const std::string& what, const fs::path& out) {
  INFO(r.output);
  CHECK(r.status == 2);
  CHECK_THAT(r.output, Catch::Contains("billiard: error: ") && Catch::Contains(what));
  for (const char* internal : {"std::", "json.exception", "filesystem error", "Traceback", "terminate"})
    CHECK_THAT(r.output, !Catch::Contains(internal));
  CHECK(leaves_nothing(out));
}

}  // namespace

TEST_CASE("numbers out of range are refused where they enter, naming the key or option") {
  const auto dir = scratch("range");
  const auto out = dir / "out";
  check_refused(run_scene(dir, driven_scene("  particles: 200\n  time: 1e308\n")), "scene.yaml:9: '1e308' = 1e+308 is out of range: numbers lie within ±1e+30", out);
  check_refused(run_scene(dir, driven_scene(), "--time inf"), "--time", out);
  check_refused(run_scene(dir, driven_scene(), "--time 1e31"), "--time", out);
  check_refused(run_scene(dir, driven_scene(), "--threads 100000"), "--threads: must be a whole number from 1 to 1024", out);
  check_refused(run_scene(dir, driven_scene(), "--threads -3"), "--threads", out);
  check_refused(run_scene(dir, driven_scene(), "--particles -1"), "--particles: must be a whole number from 2 to 1e+12, not -1", out);
  check_refused(run_scene(dir, driven_scene(), "--particles 2.5"), "--particles", out);
  check_refused(run_scene(dir, driven_scene(), "--seed -1"), "--seed: must be a whole number from 0 to 18446744073709551615", out);
  check_refused(run_scene(dir, driven_scene("  particles: 200\n  time: 2\n  seed: -1\n")), "scene.yaml:10: run.seed must be a whole number from 0 to 9.0072e+15", out);
  check_refused(run_scene(dir, driven_scene("  particles: 1e12\n  time: 2\n")), "GB of memory", out);
  check_refused(run_scene(dir, driven_scene("  particles: 200\n  time: 2\n  record: {every: 1e-9}\n")),
                "at most 10000", out);
  // A shape of side 1e308 would have an infinite area.
  write_file(dir / "huge.yaml", "boundary:\n  polygon: [[0, 0], [1e308, 0], [1e308, 1e308], [0, 1e308]]\n");
  check_refused(billiard("info " + (dir / "huge.yaml").string()), "huge.yaml:2: '1e308' = 1e+308 is out of range", out);
}

TEST_CASE("a tiny drive frequency is refused, not run into a statistics error") {
  const auto dir = scratch("omega");
  check_refused(run_scene(dir, driven_scene(), "--omega 1e-300"), "omega", dir / "out");
}

TEST_CASE("scene and shape files: duplicate keys, non-UTF-8 bytes, unknown parameters, clockwise pieces") {
  const auto dir = scratch("files");
  const auto out = dir / "out";
  check_refused(run_scene(dir, driven_scene("  particles: 200\n  time: 2\n  time: 3\n")),
                "scene.yaml:10: key 'time' appears twice in one mapping (first at line 9)", out);
  check_refused(run_scene(dir, "# caf\xe9\n" + driven_scene()), "scene.yaml:1: byte 0xE9 is not UTF-8", out);
  write_file(dir / "r.yaml", "boundary:\n  circle: {center: [0, 0], radius: 2*R}\n");
  check_refused(billiard("info " + (dir / "r.yaml").string()), "r.yaml:2: bad expression '2*R': unknown parameter 'R'", out);
  // A rectangle capped by a half-disc, its pieces listed clockwise: the arc (always running
  // counter-clockwise) bulges downwards and meets the bottom side.
  write_file(dir / "cw.yaml", "boundary:\n  pieces:\n    - point: [0, 1]\n"
                              "    - arc: {center: [1, 1], radius: 1, side: inside}\n"
                              "    - point: [2, 1]\n    - point: [2, 0]\n    - point: [0, 0]\n");
  check_refused(billiard("info " + (dir / "cw.yaml").string()), "runs clockwise: list its pieces counter-clockwise", out);
}

TEST_CASE("a field or potential that is not finite in the table's bounding box is bad input, for every command") {
  // sqrt(x − 0.5) is NaN on the left half of the unit square, the corner (0, 0) the first point
  // checked; the error names the line of the key `field` (`potential`) and comes before any
  // command prints a prediction (which would be NaN) or writes a file.
  const auto dir = scratch("field-box");
  const auto out = dir / "out";
  const auto scene = dir / "scene.yaml";
  const std::string head = "shape: " + shapes + "square.yaml\nmass: 1\ninitial:\n  microcanonical: {energy: 1/2}\n";
  const std::string tail = "run:\n  particles: 50\n  time: 1\n";
  const struct {
    std::string yaml, error;
  } cases[] = {
      {head + "force:\n  field:\n    amplitude: [\"sqrt(x - 0.5)\", \"0\"]\n    omega: 40*pi\n" + tail,
       ":6: the force is not finite at (x, y) = (0, 0), in the table's bounding box\n"},
      {head + "force:\n  periodic: {amplitude: [1, 0], omega: 40*pi}\npotential:\n  expression: sqrt(x - 0.5)\n" + tail,
       ":7: the force −∇U is not finite at (x, y) = (0, 0), in the table's bounding box\n"},
  };
  const std::string out_args = " --quiet --out " + out.string();
  const std::pair<const char*, std::string> commands[] = {
      {"run", out_args},         {"compare", out_args}, {"coeffs", ""},
      {"fp", " --times 1 -o " + out.string()},          {"trajectory", out_args},
      {"bmap", out_args},        {"lyapunov", ""},      {"animate", " --quiet -o " + out.string() + ".gif"}};
  for (const auto& c : cases) {
    write_file(scene, c.yaml);
    for (const auto& [command, args] : commands) {
      const auto r = billiard(std::string(command) + " " + scene.string() + args);
      INFO(command);
      check_refused(r, "", out);
      CHECK(r.output == "billiard: error: " + scene.string() + c.error);
      CHECK_FALSE(fs::exists(out.string() + ".gif"));
    }
  }
}

TEST_CASE("a field that is not finite where only some particles go: an error naming the scene and the particle") {
  // sqrt(|x − 0.31| − 0.001) is NaN in a strip 0.002 wide, between the points of the grid on
  // which the scene's field is checked before the run (1/32 apart): only the particles that
  // cross the strip meet it.  The integrator then stopped with "cannot meet its tolerance (step
  // size underflow)", naming neither the scene nor the particle, and left OUT.partial/.
  const auto dir = scratch("field-nan");
  const auto out = dir / "out";
  const std::string scene = "shape: " + shapes + "clover.yaml\nmass: 1\ninitial:\n  microcanonical: {energy: 1/2}\n"
                            "force:\n  field: {amplitude: [\"10*sqrt(abs(x - 0.31) - 0.001)\", \"0\"], omega: 320*pi}\n"
                            "run:\n  particles: 50\n  time: 1\n";
  const auto r = run_scene(dir, scene);
  INFO(r.output);
  CHECK(r.status == 1);
  const std::string prefix = "billiard: error: " + (dir / "scene.yaml").string() + ": particle ";
  REQUIRE_THAT(r.output, Catch::Contains(prefix) && Catch::Contains(", in its flight from t = ") &&
                             Catch::Contains(": the force is not finite at (x, y) = ("));
  for (const char* internal : {"std::", "underflow", "terminate"}) CHECK_THAT(r.output, !Catch::Contains(internal));
  CHECK(leaves_nothing(out));
  // The point named lies in the strip, and the time within the run.
  const auto at = r.output.find("(x, y) = (") + 10;
  CHECK(std::abs(std::stod(r.output.substr(at)) - 0.31) <= 0.001);
  const double t = std::stod(r.output.substr(r.output.find("from t = ") + 9));
  CHECK((t >= 0 && t < 1));
  // The first failing particle, whatever the number of threads.
  const auto one = billiard("run " + (dir / "scene.yaml").string() + " --quiet --threads 1 --out " + out.string());
  const auto line = [](const std::string& text) { return text.substr(text.find("billiard: error: ")); };
  CHECK(line(one.output) == line(r.output));
  CHECK(leaves_nothing(out));
}

TEST_CASE("record times always start at 0, so the measured changes are from the start") {
  const auto dir = scratch("record");
  const auto r = run_scene(dir, driven_scene("  particles: 300\n  time: 2\n  record: [1]\n"), "--no-csv");
  REQUIRE(r.status == 0);
  const auto j = read_json(dir / "out" / "summary.json");
  CHECK(j["record_times"] == nlohmann::json({0.0, 1.0, 2.0}));
  // Driven particles gain energy: the variance of ΔE over (0, 2) is positive and finite.
  CHECK(j["var_dE"].get<double>() > 0);
  CHECK(std::isfinite(j["mean_dE_deviation_se"].get<double>()));
}

TEST_CASE("--record replaces the file's record times before they are counted for an overridden --time") {
  // The file's 2000 record times would be 20000 at --time 20, more than a run allows.
  const auto dir = scratch("record-override");
  const auto r = run_scene(dir, driven_scene("  particles: 300\n  time: 2\n  record: {every: 0.001}\n"),
                           "--time 20 --record 1 --no-csv");
  REQUIRE(r.status == 0);
  CHECK(read_json(dir / "out" / "summary.json")["record_times"] == nlohmann::json({0.0, 1.0, 20.0}));
}

TEST_CASE("command lines: unknown commands and options, empty sweeps, impossible outputs") {
  const auto dir = scratch("cli");
  const auto out = dir / "out";
  check_refused(billiard("frobnicate"), "unknown command 'frobnicate'; the commands are info, run", out);
  check_refused(billiard(""), "no command given", out);
  check_refused(billiard("run scenes/clover-free.yaml --frob"), "--frob", out);
  check_refused(run_scene(dir, driven_scene(), "--sweep omega=10..1:x2"), "--sweep: the range '10..1:x2' is empty", out);
  check_refused(run_scene(dir, driven_scene(), "--sweep F=1,x"), "--sweep", out);
  // A SIMD target that does not exist is refused before the run prints or writes anything.
  const auto simd = run_command("cd " BILLIARDS_SOURCE_DIR " && BILLIARDS_SIMD=avx1024 " BILLIARDS_BINARY
                                " run scenes/clover-driven.yaml --particles 20 --time 1 --out " + out.string());
  check_refused(simd, "billiard: error: BILLIARDS_SIMD: 'avx1024': expected scalar, ", out);
  CHECK_THAT(simd.output, !Catch::Contains("prediction"));
  write_file(dir / "file", "a regular file");
  const auto under_file = dir / "file" / "out";
  const auto r = billiard("run scenes/clover-free.yaml --particles 100 --time 1 --quiet --out " + under_file.string());
  check_refused(r, "cannot create the output directory: Not a directory", out);
  CHECK(read_file(dir / "file") == "a regular file");
}

TEST_CASE("plot: the format follows the extension; long trajectories draw; no tracebacks") {
  const auto dir = scratch("plot");
  check_refused(billiard("plot shapes/clover.yaml -o " + (dir / "x.jpg").string()), ".png, .pdf or .svg", dir / "x.jpg");
  const auto r = billiard("plot shapes/clover.yaml --trajectory 200000 -o " + (dir / "long.png").string());
  INFO(r.output);
  CHECK(r.status == 0);
  CHECK(read_file(dir / "long.png").substr(1, 3) == "PNG");
  const auto pdf = billiard("plot shapes/clover.yaml -o " + (dir / "x.pdf").string());
  CHECK(read_file(dir / "x.pdf").substr(0, 4) == "%PDF");
  // A drawing script that fails: its traceback stays out of the user's terminal.
  fs::create_directories(dir / "scripts");
  write_file(dir / "scripts" / "plot_shape.py", "raise ValueError('no room for the legend')\n");
  const auto bad = run_command("cd " BILLIARDS_SOURCE_DIR " && BILLIARDS_SCRIPTS=" + (dir / "scripts").string() +
                               " " BILLIARDS_BINARY " plot shapes/clover.yaml -o " + (dir / "y.png").string());
  INFO(bad.output);
  CHECK(bad.status == 1);
  CHECK_THAT(bad.output, Catch::Contains("billiard: error: drawing failed: plot_shape.py ended with exit status 1: "
                                         "ValueError: no room for the legend"));
  CHECK_THAT(bad.output, !Catch::Contains("Traceback"));
  CHECK_FALSE(fs::exists(dir / "y.png"));
  // The figure scripts users run themselves: a missing run is one line too.
  for (const char* script : {"plot_run.py", "plot_compare.py"}) {
    const auto missing = run_command("/usr/bin/python3 " BILLIARDS_SOURCE_DIR "/scripts/" + std::string(script) + " " +
                                     (dir / "no-such-run").string());
    INFO(missing.output);
    CHECK(missing.status == 1);
    CHECK_THAT(missing.output, Catch::Contains(std::string(script) + ": error: ") && !Catch::Contains("Traceback"));
  }
}

namespace {

/// Starts `billiard ARGS` in the background, sends `signal` `delay` after the file `started`
/// exists (the run is under way then, on a fast machine or a slow one), and returns the exit
/// status and the seconds from the signal to the exit.
std::pair<int, double> interrupt(const std::string& args, const fs::path& started, int signal,
                                 std::chrono::milliseconds delay) {
  const pid_t pid = fork();
  if (pid == 0) {
    const int null = ::open("/dev/null", O_WRONLY);
    dup2(null, STDOUT_FILENO);
    dup2(null, STDERR_FILENO);
    execl("/bin/sh", "sh", "-c", ("cd " BILLIARDS_SOURCE_DIR " && exec " BILLIARDS_BINARY " " + args).c_str(), nullptr);
    _exit(127);
  }
  for (int waited = 0; !fs::exists(started) && waited < 60000; waited += 10)
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  std::this_thread::sleep_for(delay);
  kill(pid, signal);
  const auto sent = std::chrono::steady_clock::now();
  int status = 0;
  waitpid(pid, &status, 0);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - sent).count();
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, seconds};
}

}  // namespace

TEST_CASE("Ctrl-C and SIGTERM stop a run within a second, leaving only its checkpoint, which resumes") {
  const auto dir = scratch("interrupt");
  const auto out = dir / "out";
  // 3e7 collisions (~3 s on two AVX-512 cores); each signal comes 0.7 s into a run.
  const std::string cmd = "run scenes/clover-driven.yaml --particles 400000 --time 200 --record 50 --threads 2 --quiet "
                          "--no-csv --out " + out.string();
  const auto checkpoint = out.string() + ".partial/fingerprint.json";
  const auto [status, seconds] = interrupt(cmd, checkpoint, SIGINT, std::chrono::milliseconds(700));
  CHECK(status == 130);
  CHECK(seconds < 1);
  CHECK_FALSE(fs::exists(out));
  CHECK(fs::exists(checkpoint));
  const auto [term_status, term_seconds] = interrupt(cmd, checkpoint, SIGTERM, std::chrono::milliseconds(700));
  CHECK(term_status == 143);
  CHECK(term_seconds < 1);
  CHECK_FALSE(fs::exists(out));
  for (const auto& e : fs::directory_iterator(dir)) CHECK(e.path().filename().string().find(".tmp") == std::string::npos);
  const auto resumed = billiard(cmd);
  CHECK(resumed.status == 0);
  CHECK(fs::exists(out / "summary.json"));
  CHECK_FALSE(fs::exists(out.string() + ".partial"));
}

TEST_CASE("fuzzing findings: each crash found is a regression test") {
  const auto dir = scratch("fuzz-findings");
  write_file(dir / "mesh.yaml", "dimension: 3\nboundary:\n  mesh: tetrahedron.obj\n");
  // fuzz_mesh: an OBJ whose faces name a vertex it does not have made CGAL read past its list.
  write_file(dir / "tetrahedron.obj", "v 0 0 0\nv 1 0 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n");
  check_refused(billiard("info " + (dir / "mesh.yaml").string()),
                "mesh.yaml:3: mesh " + (dir / "tetrahedron.obj").string() + ": face 1 refers to vertex 3 (counting from 0), but there are 3 vertices",
                dir / "out");
  // fuzz_expression: a parameter name muparser refuses (too long) escaped as its own exception.
  const std::string name = "log" + std::string(99, 'i') + "RR";
  write_file(dir / "name.yaml", "parameters:\n  " + name + ": 1\nboundary:\n  circle: {center: [0, 0], radius: 1}\n");
  check_refused(billiard("info " + (dir / "name.yaml").string()), "name.yaml:2: '" + name + "' cannot be a parameter name", dir / "out");
  // fuzz_mesh: the L-prism of shapes/3d with one vertex moved, (0, 2, 0) to (6, 2, 0): its
  // hexagonal face crosses itself and could not be triangulated, which failed a CGAL precondition.
  std::string prism = read_file(BILLIARDS_SOURCE_DIR "/shapes/3d/l-prism.off");
  const auto at = prism.find("\n0 2 0\n");
  REQUIRE(at != std::string::npos);
  prism.replace(at, 7, "\n6 2 0\n");
  write_file(dir / "bent.off", prism);
  write_file(dir / "bent.yaml", "dimension: 3\nboundary:\n  mesh: bent.off\n");
  check_refused(billiard("info " + (dir / "bent.yaml").string()), "bent.yaml:3: mesh ", dir / "out");
}
