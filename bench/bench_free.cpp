// Free-flight throughput: collisions per second on one core, per shape, for the toolkit's
// kernels and for two baselines run in the same process:
//   textbook — the ray–circle code most people write: t = −B − √(B² − C), an atan2 span test
//              and a 1e-10 threshold against re-hitting the wall just left;
//   cgal     — each hit time computed exactly with CGAL's Exact_circular_kernel_2 (clover).
// Usage: bench_free [collisions per shape, default 2e7]
#include "billiards/dynamics/ensemble.hpp"
#include "billiards/geometry.hpp"
#include "throughput.hpp"

#include <CGAL/Exact_circular_kernel_2.h>
#include <fmt/core.h>

#include <cmath>
#include <cstdlib>

using namespace billiards;
using dynamics::ArcWall;
using dynamics::SegmentWall;
using dynamics::State;
using dynamics::Vec2;

namespace {

/// The textbook kernel (see the file comment).
struct TextbookFlight : dynamics::FreeFlight {
  static constexpr double threshold = 1e-10;
  double exit_time(const State& s, const SegmentWall& w, double) const {
    const Vec2 d = w.b - w.a;
    const double den = geometry::cross(s.v, d);
    if (den == 0) return dynamics::never;
    const double t = geometry::cross(Vec2(w.a - s.x), d) / den;
    const double u = geometry::cross(Vec2(w.a - s.x), s.v) / den;
    return t > threshold && u >= 0 && u <= 1 ? s.t + t : dynamics::never;
  }
  double exit_time(const State& s, const ArcWall& w, double) const {
    const Vec2 f = s.x - w.center;
    const double a = s.v.squaredNorm(), B = f.dot(s.v) / a, C = (f.squaredNorm() - w.radius2) / a;
    const double disc = B * B - C;
    if (disc < 0) return dynamics::never;
    for (const double t : {-B - std::sqrt(disc), -B + std::sqrt(disc)}) {
      if (t <= threshold) continue;
      const Vec2 u = f + s.v * t;
      double angle = std::atan2(u.y(), u.x()) - std::atan2(w.from.y(), w.from.x());
      if (angle < 0) angle += 2 * geometry::pi;
      if (angle <= w.ccw_extent) return s.t + t;
    }
    return dynamics::never;
  }
};

/// Hit times from CGAL's exact circular kernel, rounded to double at the end.
struct CgalExactFlight : dynamics::FreeFlight {
  using K = CGAL::Exact_circular_kernel_2;
  double exit_time(const State& s, const SegmentWall& w, double t_end) const {
    return TextbookFlight{}.exit_time(s, w, t_end);  // the clover has no segments
  }
  double exit_time(const State& s, const ArcWall& w, double) const {
    const K::Point_2 p(s.x.x(), s.x.y()), q(s.x.x() + s.v.x(), s.x.y() + s.v.y());
    const K::Circle_2 circle(K::Point_2(w.center.x(), w.center.y()), K::FT(w.radius) * K::FT(w.radius));
    using Point = std::pair<K::Circular_arc_point_2, unsigned>;
    std::vector<boost::variant<Point>> hits;
    CGAL::intersection(K::Line_2(p, q), circle, std::back_inserter(hits));
    double best = dynamics::never;
    for (const auto& h : hits) {
      const auto& point = boost::get<Point>(h).first;
      const double x = CGAL::to_double(point.x()), y = CGAL::to_double(point.y());
      const double t = (Vec2(x, y) - s.x).dot(s.v) / s.v.squaredNorm();
      const Vec2 n = w.normal_at(Vec2(x, y));
      if (t > 1e-12 && n.dot(s.v) > 0 && w.within_span(Vec2(x, y))) best = std::min(best, s.t + t);
    }
    return best;
  }
};

}  // namespace

int main(int argc, char** argv) {
  const double n = argc > 1 ? std::atof(argv[1]) : 2e7;
  fmt::print("{:<10} {:>14} {:>14} {:>8} {:>14}\n", "shape", "toolkit M/s", "textbook M/s", "ratio",
             "textbook esc.");
  for (const char* name : {"clover", "stadium", "sinai", "mushroom", "wavy-1200", "square", "circle"}) {
    const auto shape = geometry::load_shape(fmt::format("{}/shapes/{}.yaml", BILLIARDS_SOURCE_DIR, name));
    const auto [fast, fast_escapes] = bench::throughput(shape.region, dynamics::FreeFlight{}, n);
    const auto [slow, slow_escapes] = bench::throughput(shape.region, TextbookFlight{}, n);
    if (fast_escapes) fmt::print("ERROR: {} escapes with the toolkit's kernels on {}\n", fast_escapes, name);
    fmt::print("{:<10} {:>14.2f} {:>14.2f} {:>8.2f} {:>14}\n", name, fast / 1e6, slow / 1e6, fast / slow,
               slow_escapes);
  }
  const auto clover = geometry::load_shape(BILLIARDS_SOURCE_DIR "/shapes/clover.yaml");
  const auto [exact, exact_escapes] = bench::throughput(clover.region, CgalExactFlight{}, n / 200);
  const auto [fast, fast_escapes] = bench::throughput(clover.region, dynamics::FreeFlight{}, n);
  fmt::print("clover, CGAL exact circular kernel: {:.3f} M/s; toolkit {:.2f} M/s; ratio {:.0f}\n", exact / 1e6,
             fast / 1e6, fast / exact);
  return 0;
}
