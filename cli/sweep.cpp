// billiard run SCENE --sweep NAME=VALUES: one ensemble per value of a parameter (omega, or any
// scene or shape parameter), each run by all ranks and threads in turn, and a table of their
// moments against the prediction — the paper's Fig. 4 is `--sweep omega=10*pi..2560*pi:x2`.
#include "ranks.hpp"
#include "run.hpp"

#include <fmt/core.h>

#include <cmath>

namespace billiards::cli {

namespace {

/// "a,b,c" (expressions), "a..b:xF" (a, aF, aF², ... up to b) or "a..b:+d" (a, a+d, ... up to b).
std::vector<double> sweep_values(const std::string& text) {
  const auto value = [&](const std::string& e) { return Expressions().evaluate(e, "--sweep", 0); };
  const auto range = text.find("..");
  if (range == std::string::npos) {
    std::vector<double> values;
    for (std::size_t at = 0; at <= text.size();) {
      const auto comma = std::min(text.find(',', at), text.size());
      values.push_back(value(text.substr(at, comma - at)));
      at = comma + 1;
    }
    return values;
  }
  const auto colon = text.find(':', range);
  if (colon == std::string::npos || colon + 1 >= text.size() || (text[colon + 1] != 'x' && text[colon + 1] != '+'))
    throw InputError("--sweep", 0, "a range is FROM..TO:xFACTOR or FROM..TO:+STEP, not '" + text + "'");
  const double from = value(text.substr(0, range)), to = value(text.substr(range + 2, colon - range - 2));
  const double step = value(text.substr(colon + 2));
  const bool geometric = text[colon + 1] == 'x';
  if (geometric ? !(step > 1 && from > 0) : !(step > 0))
    throw InputError("--sweep", 0, "the range '" + text + "' does not advance from its start");
  if (from > to) throw InputError("--sweep", 0, "the range '" + text + "' is empty: it starts above its end");
  std::vector<double> values;
  const double last = to * (1 + 1e-12) + 1e-300;  // the end, despite rounding of the steps
  for (int k = 0;; ++k) {
    const double v = geometric ? from * std::pow(step, k) : from + k * step;
    if (v > last) break;
    values.push_back(v);
    if (values.size() > 100000) throw InputError("--sweep", 0, "more than 100000 values in '" + text + "'");
  }
  return values;
}

struct Sweep {
  std::string name;
  std::vector<double> values;
};

std::string point_dir(const std::string& name, double value) { return fmt::format("{}={:.6g}", name, value); }

Sweep parse_sweep(const std::string& text) {
  const auto eq = text.find('=');
  if (eq == std::string::npos || eq == 0) throw InputError("--sweep", 0, "expected NAME=VALUES, not '" + text + "'");
  return {text.substr(0, eq), sweep_values(text.substr(eq + 1))};
}

}  // namespace

void run_sweep(const RunArgs& args) {
  const auto sweep = parse_sweep(args.sweep);
  const std::string base = load_scene(args).output_dir;
  std::string csv = fmt::format("{},particles,mean_dE,se_mean_dE,var_dE,se_var_dE,g1_dt,g2_dt,fp_mean_dE,fp_var_dE,"
                                "collisions,escapes,wall_seconds,dir\n", sweep.name);
  nlohmann::json points = nlohmann::json::array();
  // Every point's scene is read before the first runs: a value that makes a bad scene fails
  // the sweep before it writes anything.
  std::vector<RunArgs> points_args;
  for (const double value : sweep.values) {
    RunArgs& point = points_args.emplace_back(args);
    if (sweep.name == "omega")
      point.overrides.omega = value;
    else
      point.set.push_back(fmt::format("{}={:.17g}", sweep.name, value));
    point.overrides.output_dir = base + "/" + point_dir(sweep.name, value);
    load_scene(point);
  }
  if (ranks().root()) OutputDir::require_creatable(base);
  for (std::size_t k = 0; k < sweep.values.size(); ++k) {
    const double value = sweep.values[k];
    const RunArgs& point = points_args[k];
    const std::string dir = point_dir(sweep.name, value);
    const auto run = run_ensemble(load_scene(point), point);
    if (!run) return;  // interrupted: the same command resumes this point
    if (!ranks().root()) continue;
    OutputDir out(run->scene.output_dir);
    write_run_files(out, *run, point);
    out.commit();
    report(*run);
    const auto& j = run->summary;
    const auto get = [&](const char* key) { return j.contains(key) ? j[key].get<double>() : NAN; };
    const auto c = run->prediction;
    csv += fmt::format("{:.17g},{},{:.17g},{:.17g},{:.17g},{:.17g},{:.17g},{:.17g},{:.17g},{:.17g},{},{},{:.4g},{}\n",
                       value, run->scene.particles, get("mean_dE"), get("se_mean_dE"), get("var_dE"),
                       get("se_var_dE"), c ? c->g1 * run->scene.time : NAN, c ? c->g2 * run->scene.time : NAN,
                       get("fp_mean_dE"), get("fp_var_dE"), run->result.collisions(), run->result.escapes(),
                       get("wall_seconds"), dir);
    points.push_back({{"value", value}, {"dir", dir}, {"summary", j}});
  }
  if (!ranks().root()) return;
  // The table is rewritten whole, and only once every point is done.
  write_file_atomically(std::filesystem::path(base) / "sweep.csv", csv);
  write_file_atomically(std::filesystem::path(base) / "sweep.json",
                        nlohmann::json{{"parameter", sweep.name}, {"points", points}}.dump(1));
  fmt::print("sweep of {} over {} values: {}/sweep.csv\n", sweep.name, sweep.values.size(), base);
}

}  // namespace billiards::cli
