// billiard bmap SHAPE|SCENE: the boundary map in Birkhoff coordinates (s, p) of every collision
// of an ensemble, or a Poincaré section of its flights on a line (--section "y = 0"), or the
// stroboscopic section of a driven scene (--strobe PHASE); as .npy, CSV and a picture drawn by
// scripts/plot_bmap.py.  In 3-D: plane sections (--section "z = 0") and the stroboscopic
// section.
#include "commands.hpp"
#include "output.hpp"
#include "phase_space.hpp"
#include "progress.hpp"
#include "python.hpp"

#include "billiards/analysis/boundary_map.hpp"
#include "billiards/dynamics/scene_run.hpp"

#include <fmt/core.h>
#include <fmt/format.h>

#include <filesystem>
#include <fstream>
#include <sstream>

namespace billiards::cli {

namespace {

namespace fs = std::filesystem;
using analysis::SectionLine;
using analysis::SectionRows;

struct BmapArgs : PhaseSpaceArgs {
  std::string picture, out, section;
  std::optional<double> strobe;
  bool csv = true;
};

/// The CSV of rows with the given columns (particle and counters as whole numbers).
template <std::size_t N>
void write_rows_csv(std::ostream& out, const SectionRows& r, const std::array<const char*, N>& columns) {
  for (std::size_t j = 0; j < N; ++j) out << (j ? "," : "") << columns[j];
  out << "\n";
  fmt::memory_buffer line;
  for (std::size_t i = 0; i < r.row_count(); ++i) {
    line.clear();
    const double* row = &r.rows[i * N];
    fmt::format_to(std::back_inserter(line), "{:.0f},{:.0f}", row[0], row[1]);
    for (std::size_t j = 2; j < N; ++j) fmt::format_to(std::back_inserter(line), ",{:.17g}", row[j]);
    line.push_back('\n');
    out.write(line.data(), std::streamsize(line.size()));
  }
}

/// The rows of the section asked for, with the flight the scene needs.
struct Section {
  std::string kind;  // "bmap", "section", "section3", "strobe" or "strobe3"
  SectionRows rows;
};

template <class Flight>
Section compute(const dynamics::Scene& scene, const Flight& flight, const BmapArgs& args, Progress& progress) {
  constexpr int D = Flight::State::dimension;
  const auto table = dynamics::table_of<Flight>(scene);
  const auto initial = dynamics::initial_states(scene, table, flight);
  const auto tick = [&](std::size_t done) { progress.update(done); };
  const std::size_t n = scene.particles, k = args.collisions;
  if (!args.section.empty()) {
    if constexpr (analysis::section_flight<Flight>)
      return {D == 2 ? "section" : "section3", analysis::line_section(table, flight, analysis::parse_section<D>(args.section, "--section"),
                                                                      initial, n, k, args.threads, scene.mass, tick)};
    throw InputError("--section", 0,
                     fmt::format("a section is drawn for free flights and a uniform force, static or periodic (lab "
                                 "picture); not for this scene (force {}{})",
                                 scene.force.name(), scene.magnetic() ? ", magnetic" : ""));
  }
  if (args.strobe) {
    if constexpr (analysis::driven_flight<Flight>)
      return {D == 2 ? "strobe" : "strobe3",
              analysis::stroboscopic_section(table, flight, *args.strobe, initial, n, k, args.threads, scene.mass, tick)};
    throw InputError("--strobe", 0,
                     fmt::format("a stroboscopic section needs a periodic drive (scene force: {})", scene.force.name()));
  }
  if constexpr (D == 3) {
    throw InputError(scene.file, 0,
                     "the boundary map's coordinates (s, p) are 2-D only: for a 3-D table give a plane section, such "
                     "as --section \"z = 0\", or --strobe PHASE for a driven scene");
  } else {
    const analysis::BoundaryCoordinates coordinates(scene.shape<2>().region);
    return {"bmap", analysis::boundary_map(table, coordinates, flight, initial, n, k, args.threads, scene.mass, tick)};
  }
}

template <std::size_t N>
std::vector<std::string> names(const std::array<const char*, N>& columns) {
  return {columns.begin(), columns.end()};
}

std::vector<std::string> columns_of(const std::string& kind) {
  if (kind == "section") return names(analysis::section_columns);
  if (kind == "section3") return names(analysis::section3_columns);
  if (kind == "strobe") return names(analysis::strobe_columns);
  if (kind == "strobe3") return names(analysis::strobe3_columns);
  return names(analysis::bmap_columns);
}

void write_csv(const OutputDir& out, const Section& s) {
  out.write_stream(s.kind + ".csv", [&](std::ostream& os) {
    if (s.kind == "section") write_rows_csv(os, s.rows, analysis::section_columns);
    else if (s.kind == "section3") write_rows_csv(os, s.rows, analysis::section3_columns);
    else if (s.kind == "strobe") write_rows_csv(os, s.rows, analysis::strobe_columns);
    else if (s.kind == "strobe3") write_rows_csv(os, s.rows, analysis::strobe3_columns);
    else write_rows_csv(os, s.rows, analysis::bmap_columns);
  });
}

void run_bmap(const BmapArgs& args) {
  if (!args.section.empty() && args.strobe) throw InputError("--section", 0, "give --section or --strobe, not both");
  auto scene = load_phase_space_scene(args);
  refuse_forced_magnetic(scene, "billiard bmap");
  if (!args.section.empty()) {  // (before any work)
    if (scene.dimension() == 3) analysis::parse_section<3>(args.section, "--section");
    else analysis::parse_section<2>(args.section, "--section");
  }
  const std::string out_dir = !args.out.empty() ? args.out : scene.output_dir + "-bmap";
  OutputDir::require_creatable(out_dir);
  if (!args.picture.empty()) {
    const std::string ext = fs::path(args.picture).extension().string();
    if (ext != ".png" && ext != ".pdf" && ext != ".svg")
      throw InputError("-o " + args.picture, 0, "the picture's format follows its extension: .png, .pdf or .svg");
  }
  Progress progress("bmap", scene.particles, !args.quiet);
  const Section s = dynamics::with_flight(scene, [&](const auto& flight) { return compute(scene, flight, args, progress); });
  progress.finish();

  OutputDir out(out_dir);
  const auto columns = columns_of(s.kind);
  out.write_npy(s.kind + ".npy", s.rows.rows, s.rows.row_count(), columns.size());
  if (args.csv) write_csv(out, s);
  nlohmann::json meta = {
      {"kind", s.kind}, {"table", scene.file}, {"shape", scene.shape_name()}, {"force", scene.force.name()},
      {"particles", scene.particles}, {"collisions", args.collisions}, {"seed", scene.seed}, {"columns", columns},
      {"rows", s.rows.row_count()}, {"escapes", s.rows.escapes()}, {"section", args.section}, {"strobe", args.strobe ? nlohmann::json(*args.strobe) : nlohmann::json()},
      {"npy", s.kind + ".npy"}};
  if (s.kind == "bmap") {
    const analysis::BoundaryCoordinates coordinates(scene.shape<2>().region);
    meta["perimeter"] = coordinates.perimeter();
    meta["piece_starts"] = coordinates.piece_starts();
    meta["loop_firsts"] = coordinates.loop_firsts();
  }
  out.write_json(s.kind + ".json", meta);
  const std::string picture = s.kind + ".png";
  run_python(script_path("plot_bmap.py"), {out.path(s.kind + ".json").string(), out.path(picture).string()});
  out.commit();
  if (!args.picture.empty()) {
    std::ifstream in(fs::path(out_dir) / picture, std::ios::binary);
    std::ostringstream bytes;
    bytes << in.rdbuf();
    if (fs::path(args.picture).extension() == ".png") {
      if (fs::path(args.picture).has_parent_path()) fs::create_directories(fs::path(args.picture).parent_path());
      write_file_atomically(args.picture, bytes.str());
    } else {  // another format: drawn again
      run_python(script_path("plot_bmap.py"), {(fs::path(out_dir) / (s.kind + ".json")).string(), args.picture});
    }
  }
  fmt::print("{}: {} points of {} particles x {} collisions on '{}' (force {}); results in {}/\n", s.kind,
             s.rows.row_count(), scene.particles, args.collisions, scene.shape_name(), scene.force.name(), out_dir);
  if (s.rows.escapes() > 0) {
    fmt::print(stderr, "billiard: error: {} particle(s) escaped the region\n", s.rows.escapes());
    throw CLI::RuntimeError(3);
  }
}

}  // namespace

void add_bmap(CLI::App& app) {
  auto* cmd = app.add_subcommand(
      "bmap", "The boundary map (s, p) of every collision, a line (3-D: plane) section or a stroboscopic section");
  auto args = std::make_shared<BmapArgs>();
  add_phase_space_options(cmd, *args, 10, 10000);
  cmd->add_option("-o,--output", args->picture, "also draw the picture here (.png, .pdf or .svg)");
  cmd->add_option("--out", args->out, "output directory (default: out/NAME-bmap)");
  cmd->add_option("--section", args->section, "Poincaré section on a line (3-D: a plane) instead, e.g. \"y = 0\" (free flights, a uniform force)");
  cmd->add_option("--strobe", args->strobe, "stroboscopic section at this drive phase instead (driven scenes)")
      ->transform(expression_value);
  cmd->add_flag("!--no-csv", args->csv, "write the .npy only");
  cmd->callback([args] { run_bmap(*args); });
}

}  // namespace billiards::cli
