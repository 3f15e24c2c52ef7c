// `mpirun -np K billiard run`: ranks split the particles and give exactly the single-process
// results, also when a run is interrupted on some ranks and resumed on another number of them.
#include "cli_helpers.hpp"

#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

namespace fs = std::filesystem;

namespace {

/// Runs `mpirun -np K billiard ARGS` (oversubscribed: this machine may have fewer cores).
CommandResult mpi_billiard(int ranks, const std::string& args) {
  // Open MPI refuses to start as root unless told; CI containers run as root.
  return run_command("cd " BILLIARDS_SOURCE_DIR " && OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 "
                     BILLIARDS_MPIEXEC " -np " + std::to_string(ranks) + " --oversubscribe " BILLIARDS_BINARY " " +
                     args);
}

bool have_mpi() { return std::string(BILLIARDS_MPIEXEC).size() > 0; }

// 7000 particles are 7 chunks of 1024: uneven over 2 and 3 ranks.
const std::string scene = "run scenes/clover-driven.yaml --particles 7000 --time 5 --threads 1 --quiet --out ";

}  // namespace

TEST_CASE("1, 2 and 3 ranks give the single-process outputs, byte for byte") {
  if (!have_mpi()) {
    WARN("built without MPI: nothing to test");
    return;
  }
  const auto dir = scratch("mpi");
  REQUIRE(billiard(scene + (dir / "single").string()).status == 0);
  const auto single = nlohmann::json::parse(read_file(dir / "single" / "summary.json"));
  for (int k = 1; k <= 3; ++k) {
    const auto out = dir / ("ranks-" + std::to_string(k));
    const auto r = mpi_billiard(k, scene + out.string());
    INFO(r.output);
    REQUIRE(r.status == 0);
    CHECK(read_file(out / "energies.npy") == read_file(dir / "single" / "energies.npy"));
    CHECK(read_file(out / "energies.csv") == read_file(dir / "single" / "energies.csv"));
    const auto summary = nlohmann::json::parse(read_file(out / "summary.json"));
    CHECK(summary["ranks"] == k);
    for (const char* key : {"mean_dE", "var_dE", "se_mean_dE", "se_var_dE", "collisions", "escapes", "per_time"})
      CHECK(summary[key] == single[key]);
  }
}

TEST_CASE("an MPI run interrupted on 2 ranks and resumed on 3 equals an uninterrupted run") {
  if (!have_mpi()) {
    WARN("built without MPI: nothing to test");
    return;
  }
  const auto dir = scratch("mpi-resume");
  REQUIRE(billiard(scene + (dir / "whole").string()).status == 0);
  const auto part = dir / "part";
  // Each of the 2 ranks runs one new chunk and stops: 2 of 7 chunks are saved.
  REQUIRE(mpi_billiard(2, scene + part.string() + " --max-chunks 1").status == 0);
  CHECK_FALSE(fs::exists(part));
  std::size_t saved = 0;
  for (const auto& e : fs::directory_iterator(part.string() + ".partial"))
    saved += e.path().extension() == ".bin";
  CHECK(saved == 2);
  const auto r = mpi_billiard(3, scene + part.string());
  INFO(r.output);
  REQUIRE(r.status == 0);
  CHECK(read_file(part / "energies.npy") == read_file(dir / "whole" / "energies.npy"));
  CHECK_FALSE(fs::exists(part.string() + ".partial"));
}

TEST_CASE("an error in an MPI run is printed once and fails the job") {
  if (!have_mpi()) {
    WARN("built without MPI: nothing to test");
    return;
  }
  // (Three times: the launcher stops the job at the first rank to exit with an error, and the
  // first rank must have printed by then.)
  for (int attempt = 0; attempt < 3; ++attempt) {
    const auto r = mpi_billiard(2, "run scenes/clover-free.yaml --particles 10 --quiet --set nonexistent=1 --out " +
                                       (scratch("mpi-error") / "out").string());
    INFO(r.output);
    CHECK(r.status != 0);
    const std::string message = "--set names 'nonexistent'";
    const auto first = r.output.find(message);
    REQUIRE(first != std::string::npos);
    CHECK(r.output.find(message, first + 1) == std::string::npos);
  }
}

TEST_CASE("a sweep on 2 ranks equals the single-process sweep") {
  if (!have_mpi()) {
    WARN("built without MPI: nothing to test");
    return;
  }
  const auto dir = scratch("mpi-sweep");
  const std::string sweep = "run scenes/clover-driven.yaml --particles 3000 --time 5 --threads 1 --quiet --no-csv "
                            "--sweep omega=40*pi,320*pi --out ";
  REQUIRE(billiard(sweep + (dir / "single").string()).status == 0);
  const auto r = mpi_billiard(2, sweep + (dir / "mpi").string());
  INFO(r.output);
  REQUIRE(r.status == 0);
  for (const char* point : {"omega=125.664", "omega=1005.31"})
    CHECK(read_file(dir / "mpi" / point / "energies.npy") == read_file(dir / "single" / point / "energies.npy"));
}
