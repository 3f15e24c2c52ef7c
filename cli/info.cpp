// billiard info SHAPE: exact geometry of a shape file.
#include "commands.hpp"
#include "options.hpp"

#include "billiards/geometry.hpp"
#include "billiards/geometry/shape_info.hpp"
#include "billiards/geometry3/shape3_info.hpp"

#include <fmt/core.h>
#include <nlohmann/json.hpp>

#include <iostream>

namespace billiards::cli {

namespace {

/// `billiard info` for a 3-D shape file (`dimension: 3`).
void print_info3(const std::string& path, const Overrides& set, bool json) {
  const auto shape = geometry3::load_shape3(path, set);
  const auto info = geometry3::shape_info(shape);
  if (json) {
    std::cout << info.dump(2) << "\n";
    return;
  }
  const auto T = info["boundary_tensor"].get<std::vector<std::vector<double>>>();
  const auto lo = info["bbox"][0].get<std::vector<double>>(), hi = info["bbox"][1].get<std::vector<double>>();
  if (!shape.description.empty()) fmt::print("{}\n\n", shape.description);
  fmt::print("shape            {} ({}), dimension 3\n", shape.region.name, path);
  fmt::print("volume V         {:.15g}\n", info["V"].get<double>());
  fmt::print("surface S        {:.15g}\n", info["S"].get<double>());
  fmt::print("mean free path   {:.15g}   (lambda = 4 V / S)\n", info["mean_free_path"].get<double>());
  fmt::print("boundary tensor  [[{:.12g}, {:.12g}, {:.12g}], [{:.12g}, {:.12g}, {:.12g}], [{:.12g}, {:.12g}, {:.12g}]]"
             "   (int n n^T dS)\n", T[0][0], T[0][1], T[0][2], T[1][0], T[1][1], T[1][2], T[2][0], T[2][1], T[2][2]);
  fmt::print("bounding box     [{:.6g}, {:.6g}] x [{:.6g}, {:.6g}] x [{:.6g}, {:.6g}]\n", lo[0], hi[0], lo[1], hi[1],
             lo[2], hi[2]);
  fmt::print("boundary         {}\n", info["boundary"].dump());
  fmt::print("holes            {} (balls)\n", shape.region.holes.size());
}

}  // namespace

void add_info(CLI::App& app) {
  auto* cmd = app.add_subcommand("info", "Exact geometry of a shape: V, S, mean free path, ...");
  struct Args {
    std::string shape;
    bool json = false;
    std::vector<std::string> set;
  };
  auto args = std::make_shared<Args>();
  cmd->add_option("shape", args->shape, "shape file (YAML)")->required();
  cmd->add_flag("--json", args->json, "print JSON instead of text");
  add_set_option(cmd, args->set);
  cmd->callback([args] {
    if (geometry3::shape_dimension(args->shape) == 3)
      return print_info3(args->shape, parse_overrides(args->set), args->json);
    const auto shape = geometry::load_shape(args->shape, parse_overrides(args->set));
    const auto info = geometry::shape_info(shape);
    if (args->json) {
      std::cout << info.dump(2) << "\n";
      return;
    }
    if (!shape.description.empty()) fmt::print("{}\n\n", shape.description);
    fmt::print("shape            {} ({})\n", info["name"].get<std::string>(), args->shape);
    fmt::print("area V           {:.15g}\n", info["V"].get<double>());
    fmt::print("perimeter S      {:.15g}\n", info["S"].get<double>());
    fmt::print("mean free path   {:.15g}   (lambda = pi V / S)\n", info["mean_free_path"].get<double>());
    const auto& T = info["boundary_tensor"];
    fmt::print("boundary tensor  [[{:.12g}, {:.12g}], [{:.12g}, {:.12g}]]   (int n n^T dS)\n",
               T[0][0].get<double>(), T[0][1].get<double>(), T[1][0].get<double>(), T[1][1].get<double>());
    const auto& b = info["bbox"];
    fmt::print("bounding box     [{:.6g}, {:.6g}] x [{:.6g}, {:.6g}]\n", b[0][0].get<double>(),
               b[1][0].get<double>(), b[0][1].get<double>(), b[1][1].get<double>());
    fmt::print("pieces           {} ({} holes)\n", info["pieces"].size(), shape.region.holes.size());
    for (const auto& p : info["pieces"]) {
      const auto& k = p["curvature"];  // an elliptic arc's is its range [least, greatest]
      const std::string curvature = k.is_array() ? fmt::format("{:+.6g} to {:+.6g}", k[0].get<double>(), k[1].get<double>())
                                                 : fmt::format("{:+.6g}", k.get<double>());
      fmt::print("  line {:>4}  {:<12}  length {:<12.8g}  curvature {}\n", p["line"].get<int>(),
                 p["kind"].get<std::string>(), p["length"].get<double>(), curvature);
    }
  });
}

}  // namespace billiards::cli
