// The bounding-volume hierarchy over the triangles of a mesh that a 3-D table walks
// (table3.cpp): built by the surface-area heuristic, eight children a node, their boxes
// stored as floats rounded outward with the cones of their triangles' normals, walked into the
// nearest child entered first.
#pragma once

#include "billiards/dynamics/bvh_lanes.hpp"
#include "billiards/dynamics/huge_pages.hpp"
#include "billiards/geometry3/region3.hpp"

#include <bit>
#include <cassert>
#include <cstdint>
#include <limits>
#include <utility>
#include <vector>

namespace billiards::dynamics {

using geometry3::Vec3;

/// The boxes are grown by a pad (the walls' slack, so that a ray within rounding of a triangle
/// is never culled by its box), moved to the frame of the root box's center and then rounded
/// outward to floats: a stored box always holds the padded box in doubles (the shift's
/// roundings, within an ulp of the coordinates, are far inside a pad of some ulps of them).
/// The frame keeps the floats' coordinates as small as the mesh, wherever it lies.  A walk
/// grows the boxes again by its own pad (a tube's radius).
class Bvh {
 public:
  static constexpr int width = bvh_lanes::width;  // children of a node
  static constexpr int max_leaf = 8;  // triangles of a leaf
  struct Box {
    Vec3 lo, hi;
  };
  /// A triangle's outward unit normal n and the margin δ of its exit test: a straight flight
  /// whose unit heading h has n·h < −δ never leaves the region through it
  /// (TriangleWall::facing_away_margin).
  struct Facing {
    Vec3 normal;
    double margin;
  };
  /// A node's children, structure of arrays.  A child is an inner node (its index, ≥ 0) or a
  /// leaf, ~(first · max_leaf + count − 1) for the triangles [first, first + count) of the
  /// leaf order; an unused child has an empty box (lo = +∞, hi = −∞), which no ray enters.
  /// Each child's cone [x, y, z, −t] holds its triangles' normals: a heading h with
  /// h·(x, y, z) < −t in floats moves away from each of them by more than its margin, and no
  /// straight flight so headed is walked into the child (Bvh::cone_of; all zero: every heading
  /// is walked in).
  struct alignas(64) Node {
    float bound[2][3][width];  // [lo, hi][axis][child]
    std::int8_t cone[4][width];
    int child[width];
  };

  Bvh() = default;
  /// Over one box per triangle, each grown by `pad`, and its Facing; walked with the slab test
  /// of `slab_test` (bvh_lanes.hpp), or the scalar one where it is null.
  Bvh(const std::vector<Box>& boxes, const std::vector<Facing>& facings, double pad, bvh_lanes::Kernel slab_test);
  /// The triangles in leaf order: position i holds triangle order()[i].
  const std::vector<int>& order() const { return order_; }

  /// Walks the leaves whose boxes, grown by `pad`, the ray origin + τ dir enters for τ in
  /// [0, tau_max], into the nearest child of a node first: `tau_max = leaf(first, count)` for
  /// each, so that a leaf may shrink the bound of the rest.  `fetch(first, count)` is told of a
  /// leaf as soon as its box is entered, so that its triangles may be fetched from memory
  /// meanwhile.  A path that only stays within the pad of the ray (a helix, a driven flight)
  /// enters every such box; the ray of a straight flight (`Heading::straight`) passes over
  /// those whose triangles it all moves away from.
  enum class Heading { any, straight };
  template <class Leaf, class Fetch>
  void walk(const Vec3& origin, const Vec3& dir, double pad, double tau_max, Leaf leaf, Fetch fetch,
            Heading heading = Heading::any) const;
  /// A child entered and not yet searched, on a walk's stack.
  struct Pending {
    int child;
    float t_in;  // where the ray enters its box (BvhRay's τ')
  };
  /// The most children a walk's stack holds: the binary build's depth bound (from depth 32 on
  /// it splits at the median: at most 31 more levels), each node popped pushing at most `width`.
  static constexpr int max_depth = 64, stack_size = (width - 1) * max_depth + 1;
  /// The same walk a step at a time (a node's children tested, or a leaf asked), on a stack
  /// of stack_size entries: `walk` runs one to its end; `walk_stream` runs several in turns.
  template <class Leaf, class Fetch>
  class Walk;
  /// Runs the walks of n ≤ 32 lanes a step each in turn, so that the nodes and triangles one
  /// walk fetches arrive while the others step (a walk alone waits for each fetch).  When lane
  /// i's walk has ended (as each has before its first), `next(i)` sets out its next walk
  /// (Walk::set_out; true) or closes the lane (false), so that as many walks stay in flight as
  /// there are flights to search; each walk takes the steps it takes alone.  Until every lane
  /// is closed.
  template <class W, class Next>
  static void walk_stream(W* walks, int n, Next next);

 private:
  /// Binary nodes of the build, before they are gathered into nodes of `width`.
  struct Split;
  int build(std::vector<Split>& tree, const std::vector<Box>& boxes, int first, int count, int depth);
  int gather(const std::vector<Split>& tree, const std::vector<Facing>& facings, int split, double pad);
  void cone_of(const std::vector<Facing>& facings, const Split& split, Node& node, int i) const;
  static void prefetch(const Node& n) {
    for (std::size_t line = 0; line < sizeof(Node); line += 64) __builtin_prefetch(reinterpret_cast<const char*>(&n) + line);
  }

  HugePageVector<Node> nodes_;  // (read at random: huge_pages.hpp)
  Vec3 center_ = Vec3::Zero();  // the frame of the stored boxes
  double extent_ = 0;  // the largest |coordinate| of a stored non-empty box
  std::vector<int> order_;
  bvh_lanes::Kernel slab_test_ = nullptr;
};

namespace detail {

/// Four floats in one SSE2 register (GCC's and Clang's vector extension): the slab test's
/// lanes without a SIMD target (the project's flags leave the vectorizing to the code: no SLP
/// vectorizer, no wider registers by default).
struct QuadLanes {
  using Num = float __attribute__((vector_size(4 * sizeof(float))));
  static constexpr int lanes = 4;
  static Num splat(float x) { return Num{x, x, x, x}; }
  static Num load(const float* p) {
    Num v;
    __builtin_memcpy(&v, p, sizeof v);
    return v;
  }
  static Num convert(const std::int8_t* p) { return Num{float(p[0]), float(p[1]), float(p[2]), float(p[3])}; }
  static Num later(Num a, Num b) { return a < b ? b : a; }
  static Num earlier(Num a, Num b) { return b < a ? b : a; }
  static void store(Num v, float* p) { __builtin_memcpy(p, &v, sizeof v); }
  static unsigned entered(Num in, Num out) {
#ifdef __SSE2__
    return unsigned(__builtin_ia32_movmskps(Num(in <= out)));  // (the sign bits)
#else
    const auto m = in <= out;
    return unsigned(m[0] & 1) | unsigned(m[1] & 1) << 1 | unsigned(m[2] & 1) << 2 | unsigned(m[3] & 1) << 3;
#endif
  }
};

#include "billiards/dynamics/slab_test-inl.hpp"

/// A ray origin + τ dir as the slab test reads it, in floats, with boxes grown by `pad`, in the
/// time τ' = τ · time_scale of its direction scaled by a power of two to a largest component
/// in [1, 2): a box of the table is then entered and left at times the floats hold, whatever
/// the speed.  Each coordinate of the origin is moved by the pad and a margin of
/// 2⁻²⁰ (extent + |x| + pad), where `extent` bounds the boxes' coordinates, towards the side of
/// the slab it stands for (Ray::enter, Ray::leave): each rounding of the test in floats (the
/// origin's, the inverse's, the subtraction's, the product's) is within 2⁻²⁴ of that sum in
/// space, and the origin's move to the boxes' frame (Bvh) within 2⁻⁵³ of |x|, so together they
/// keep within the margin, on the side of entering, and no box the ray meets in doubles is
/// culled.  A zero component of the direction has the inverse +∞: the slab spans everything
/// (origin between the planes) or nothing.  The heading of a straight ray is dir / |dir|
/// rounded to floats (Bvh::cone_of allows for that), else zero.
struct BvhRay : bvh_lanes::Ray {
  double time_scale = 1;
  BvhRay() = default;
  BvhRay(const Vec3& origin, const Vec3& dir, double pad, double extent, Bvh::Heading heading = Bvh::Heading::any);
  /// τ' of a bound τ, as a float not below it (2⁻²³ above before rounding to nearest).
  float time_bound(double tau) const { return float(tau * time_scale * (1 + 0x1p-23)); }
};

}  // namespace detail

template <class Leaf, class Fetch>
class Bvh::Walk {
 public:
  /// A walk that has ended (none set out yet), on `stack`.
  Walk(const Bvh& bvh, Leaf leaf, Fetch fetch, Pending* stack) : bvh_(&bvh), leaf_(leaf), fetch_(fetch), stack_(stack) {}
  /// Sets out on the walk along origin + τ dir for τ in [0, tau_max] (Bvh::walk), in place of
  /// the one under way, if any.
  void set_out(const Vec3& origin, const Vec3& dir, double pad, double tau_max, Heading heading = Heading::any) {
    ray_ = detail::BvhRay(origin - bvh_->center_, dir, pad, bvh_->extent_, heading);
    tau_max_ = ray_.time_bound(tau_max);
    top_ = 0;
    child_ = bvh_->nodes_.empty() ? ended : 0;
  }
  /// Searches the node or leaf next (false: the walk has ended, nothing is left).
  bool step() {
    if (child_ == ended) return false;
    if (child_ < 0) {
      const int code = ~child_;
      tau_max_ = ray_.time_bound(leaf_(code / max_leaf, code % max_leaf + 1));
    } else if (enter_children()) {
      return true;
    }
    // Next, the last entry pushed that is not beyond a hit found since.
    do {
      if (top_ == 0) return (child_ = ended), false;
    } while (stack_[--top_].t_in > tau_max_);
    child_ = stack_[top_].child;
    return true;
  }
  /// Steps to the end.
  void run() {
    while (step()) {
    }
  }

 private:
  static constexpr int ended = std::numeric_limits<int>::min();  // (no leaf's code)
  /// Pushes the children of node child_ that the ray enters (and does not move away from) and
  /// makes the nearest the next, so that the bound shrinks early; the others are fetched
  /// meanwhile, and stay in the node's order (sorting them costs more than it saves: the hit
  /// does not depend on the order, and the ray most often enters one or two).  False where it
  /// enters none.
  bool enter_children() {
    const Node& node = bvh_->nodes_[child_];
    float t_in[width];
    const float* bound = &node.bound[0][0][0];
    const std::int8_t* cone = &node.cone[0][0];
    const unsigned entered = bvh_->slab_test_ ? bvh_->slab_test_(bound, cone, ray_, tau_max_, t_in)
                                              : detail::slab_test<detail::QuadLanes>(bound, cone, ray_, tau_max_, t_in);
    if (entered == 0) return false;
    // One child entered: the next, with nothing pushed.
    if ((entered & (entered - 1)) == 0) return (child_ = fetch(node.child[std::countr_zero(entered)])), true;
    // (In locals: the compiler cannot tell the stack's stores from top_ and nodes_.)
    int top = top_;
    const int bottom = top;
    for (unsigned mask = entered; mask; mask &= mask - 1) {
      const int i = std::countr_zero(mask);
      // The nearest so far stays on top.
      stack_[top] = {fetch(node.child[i]), t_in[i]};
      const bool farther = top > bottom && stack_[top - 1].t_in < t_in[i];
      std::swap(stack_[top], stack_[top - farther]);
      ++top;
    }
    child_ = stack_[--top].child;  // (entered, so t_in ≤ tau_max)
    top_ = top;
    return true;
  }
  /// Starts fetching a child from memory (a node's boxes or a leaf's triangles); returns it.
  int fetch(int c) const {
    if (c >= 0) prefetch(bvh_->nodes_[c]);
    else fetch_(~c / max_leaf, ~c % max_leaf + 1);
    return c;
  }

  const Bvh* bvh_;
  detail::BvhRay ray_;
  float tau_max_ = 0;  // τ'
  int top_ = 0, child_ = ended;  // the node or leaf searched next
  Leaf leaf_;
  Fetch fetch_;
  Pending* stack_;
};

template <class Leaf, class Fetch>
void Bvh::walk(const Vec3& origin, const Vec3& dir, double pad, double tau_max, Leaf leaf, Fetch fetch,
               Heading heading) const {
  Pending stack[stack_size];
  Walk<Leaf, Fetch> w(*this, leaf, fetch, stack);
  w.set_out(origin, dir, pad, tau_max, heading);
  w.run();
}

template <class W, class Next>
void Bvh::walk_stream(W* walks, int n, Next next) {
  assert(n <= 32);
  for (std::uint32_t open = n < 32 ? (1u << n) - 1 : ~0u; open;)
    for (int i = 0; i < n; ++i)
      if (!walks[i].step() && (open >> i & 1) && !next(i)) open &= ~(1u << i);
}

}  // namespace billiards::dynamics
