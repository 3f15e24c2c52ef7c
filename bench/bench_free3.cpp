// 3-D flights: collisions per second on one core for the 3-D Sinai billiard and the
// 1e5-triangle mesh, free and under the paper's drive, with baselines in the same process:
//   sinai (2-D)  — the 2-D kernels on shapes/sinai.yaml (bench_free's code path), free and
//                  driven alike;
//   CGAL AABB    — the mesh's collisions found by CGAL's AABB_tree::first_intersection (the
//                  face just left skipped), instead of the toolkit's BVH and watertight test.
// "toolkit" runs 64 free particles one after the other (Table3::collision); "toolkit ensemble"
// and the driven runs use the ensemble code of `billiard run` (64 particles, one thread,
// flights not re-verified: free ones sixteen at a time, in lanes or a mesh's walks together,
// driven ones one at a time), F = 10 along (1, 1[, 1])/√d, ω = 320π, E = 1/2.
// Usage: bench_free3 [free collisions per shape, default 5e6] [driven, default a tenth]
#include "billiards/dynamics/ensemble.hpp"
#include "billiards/dynamics/forced_flight.hpp"
#include "billiards/dynamics/table3.hpp"
#include "billiards/geometry.hpp"
#include "billiards/geometry3/shape3_file.hpp"

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <fmt/core.h>

#include <chrono>
#include <cstdlib>

using namespace billiards;
using dynamics::State3;
using geometry3::Vec3;

namespace {

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

/// Collisions per second of one thread running 64 particles one after the other; escapes.
std::pair<double, long> toolkit3(const geometry3::Region3& region, double collisions) {
  const dynamics::Table3 table(region);
  const dynamics::FreeFlight3 flight;
  const int particles = 64;
  const double T = collisions / particles * geometry::mean_free_path(geometry3::measures_of(region));
  std::vector<State3> initial;
  for (int i = 0; i < particles; ++i) {
    dynamics::ParticleRng rng(1, i);
    initial.push_back(dynamics::sample_microcanonical(table, 1.0, rng));
  }
  long n = 0, escapes = 0;
  const auto start = std::chrono::steady_clock::now();
  for (State3 s : initial) {
    for (;;) {
      const auto hit = table.collision(flight, s, T);
      if (!hit.found()) {
        escapes += s.t < T && table.collision(flight, s).t <= T;  // no wall at all before T
        break;
      }
      dynamics::bounce(flight, s, hit);
      dynamics::restore_speed(s.v, 1.0);
      ++n;
    }
  }
  return {n / seconds_since(start), escapes};
}

/// The same flights with CGAL's AABB tree over the mesh triangles (EPICK, ray queries).
std::pair<double, long> cgal_aabb(const geometry3::TriangleMesh& mesh, const geometry3::Region3& region,
                                  double collisions) {
  using K = CGAL::Exact_predicates_inexact_constructions_kernel;
  using Triangles = std::vector<K::Triangle_3>;
  using Tree = CGAL::AABB_tree<CGAL::AABB_traits<K, CGAL::AABB_triangle_primitive<K, Triangles::const_iterator>>>;
  const auto point = [](const Vec3& p) { return K::Point_3(p.x(), p.y(), p.z()); };
  Triangles tris;
  for (const auto& t : mesh.triangles)
    tris.emplace_back(point(mesh.vertices[t[0]]), point(mesh.vertices[t[1]]), point(mesh.vertices[t[2]]));
  Tree tree(tris.cbegin(), tris.cend());
  const dynamics::Table3 table(region);  // for sampling only
  const int particles = 64;
  const long per_particle = long(collisions / particles);
  long n = 0, escapes = 0;
  const auto start = std::chrono::steady_clock::now();
  for (int i = 0; i < particles; ++i) {
    dynamics::ParticleRng rng(1, i);
    State3 s = dynamics::sample_microcanonical(table, 1.0, rng);
    Triangles::const_iterator last = tris.cend();
    for (long k = 0; k < per_particle; ++k) {
      const K::Ray_3 ray(point(s.x), K::Vector_3(s.v.x(), s.v.y(), s.v.z()));
      const auto hit = tree.first_intersection(ray, [&](Triangles::const_iterator f) { return f == last; });
      const K::Point_3* p = hit ? boost::get<K::Point_3>(&hit->first) : nullptr;
      if (!p) {
        ++escapes;
        break;
      }
      last = hit->second;
      const auto nrm = CGAL::unit_normal(last->vertex(0), last->vertex(1), last->vertex(2));
      const Vec3 normal(nrm.x(), nrm.y(), nrm.z());
      s.x = Vec3(p->x(), p->y(), p->z());
      s.v -= 2 * s.v.dot(normal) * normal;
      ++n;
    }
  }
  return {n / seconds_since(start), escapes};
}

/// Collisions per second of the ensemble code on one thread: 64 particles for about
/// `collisions` collisions in all.
template <class Table, class Flight>
double ensemble_rate(const Table& table, const Flight& flight, double mean_free_path, double collisions) {
  dynamics::RunOptions opt;
  opt.record_times = {collisions / 64 * mean_free_path};
  const auto initial = dynamics::microcanonical(table, flight, 1.0, 1);
  const auto start = std::chrono::steady_clock::now();
  const auto res = dynamics::run_ensemble(table, flight, initial, opt, 64, 1);
  if (res.escapes() > 0) fmt::print("  {} ESCAPES\n", res.escapes());
  return res.collisions() / seconds_since(start);
}

constexpr double F = 10, omega = 320 * geometry::pi;

double sinai2_driven(double collisions) {
  const auto shape = geometry::load_shape(BILLIARDS_SOURCE_DIR "/shapes/sinai.yaml");
  const dynamics::Table table(shape.region);
  const dynamics::PeriodicDriveFlight flight{dynamics::Vec2(F, F) / std::sqrt(2.0), omega, 0};
  return ensemble_rate(table, flight, geometry::mean_free_path(geometry::measures_of(shape.region)), collisions);
}

double driven3(const geometry3::Region3& region, double collisions) {
  const dynamics::Table3 table(region);
  const dynamics::PeriodicDriveFlight3 flight{Vec3(F, F, F) / std::sqrt(3.0), omega, 0};
  return ensemble_rate(table, flight, geometry::mean_free_path(geometry3::measures_of(region)), collisions);
}

double sinai2(double collisions) {
  const auto shape = geometry::load_shape(BILLIARDS_SOURCE_DIR "/shapes/sinai.yaml");
  const dynamics::Table table(shape.region);
  return ensemble_rate(table, dynamics::FreeFlight{}, geometry::mean_free_path(geometry::measures_of(shape.region)),
                       collisions);
}

/// The free ensemble (sixteen particles in lanes, or a mesh's sixteen walks together).
double free3(const geometry3::Region3& region, double collisions) {
  const dynamics::Table3 table(region);
  return ensemble_rate(table, dynamics::FreeFlight3{}, geometry::mean_free_path(geometry3::measures_of(region)),
                       collisions);
}

}  // namespace

int main(int argc, char** argv) {
  const double n = argc > 1 ? std::atof(argv[1]) : 5e6;
  const double n_driven = argc > 2 ? std::atof(argv[2]) : n / 10;
  fmt::print("sinai (2-D), toolkit: {:.2f} M collisions/s\n", sinai2(n) / 1e6);
  const double driven2 = sinai2_driven(n_driven);
  fmt::print("sinai (2-D), driven at 320 pi: {:.3f} M collisions/s\n", driven2 / 1e6);
  for (const char* name : {"sinai3", "bumpy-100k"}) {
    const auto shape = geometry3::load_shape3(fmt::format("{}/shapes/3d/{}.yaml", BILLIARDS_SOURCE_DIR, name));
    const auto [rate, escapes] = toolkit3(shape.region, n);
    fmt::print("{}, toolkit: {:.2f} M collisions/s, {} escapes\n", name, rate / 1e6, escapes);
    fmt::print("{}, toolkit ensemble: {:.2f} M collisions/s\n", name, free3(shape.region, n) / 1e6);
    if (const auto* mesh = std::get_if<geometry3::TriangleMesh>(&shape.region.outer)) {
      const auto [cgal, cgal_escapes] = cgal_aabb(*mesh, shape.region, n / 10);
      fmt::print("{}, CGAL AABB_tree first_intersection: {:.3f} M collisions/s, {} escapes; toolkit / CGAL = {:.1f}\n",
                 name, cgal / 1e6, cgal_escapes, rate / cgal);
    }
    const double driven = driven3(shape.region, n_driven);
    fmt::print("{}, driven at 320 pi: {:.3f} M collisions/s; / free = {:.2f}; / 2-D sinai driven = {:.2f}\n", name,
               driven / 1e6, driven / rate, driven / driven2);
  }
  return 0;
}
