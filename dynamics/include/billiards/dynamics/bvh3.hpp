// The bounding-volume hierarchy over the triangles of a mesh that a 3-D table walks
// (table3.cpp): built by the surface-area heuristic, eight children a node, their boxes
// stored as floats rounded outward, walked nearest box first.
#pragma once

#include "billiards/dynamics/bvh_lanes.hpp"
#include "billiards/geometry3/region3.hpp"

#include <bit>
#include <limits>
#include <vector>

#ifdef __SSE2__
#include <emmintrin.h>
#endif

namespace billiards::dynamics {

using geometry3::Vec3;

/// The boxes are grown by a pad (the walls' slack, so that a ray within rounding of a triangle
/// is never culled by its box) and then rounded outward to floats: a stored box always holds
/// the padded box in doubles.  A walk grows them again by its own pad (a tube's radius).
class Bvh {
 public:
  static constexpr int width = bvh_lanes::width;  // children of a node
  static constexpr int max_leaf = 8;  // triangles of a leaf
  struct Box {
    Vec3 lo, hi;
  };
  /// A node's children, structure of arrays.  A child is an inner node (its index, ≥ 0) or a
  /// leaf, ~(first · max_leaf + count − 1) for the triangles [first, first + count) of the
  /// leaf order; an unused child has an empty box (lo = +∞, hi = −∞), which no ray enters.
  struct alignas(64) Node {
    float bound[2][3][width];  // [lo, hi][axis][child]
    int child[width];
  };

  Bvh() = default;
  /// Over one box per triangle, each grown by `pad`; walked with the slab test of `slab_test`
  /// (bvh_lanes.hpp), or the scalar one where it is null.
  Bvh(const std::vector<Box>& boxes, double pad, bvh_lanes::Kernel slab_test);
  /// The triangles in leaf order: position i holds triangle order()[i].
  const std::vector<int>& order() const { return order_; }

  /// Walks the leaves whose boxes, grown by `pad`, the ray origin + τ dir enters for τ in
  /// [0, tau_max], nearest box first: `tau_max = leaf(first, count)` for each, so that a leaf
  /// may shrink the bound of the rest.  `fetch(first, count)` is told of a leaf as soon as its
  /// box is entered, so that its triangles may be fetched from memory meanwhile.
  template <class Leaf, class Fetch>
  void walk(const Vec3& origin, const Vec3& dir, double pad, double tau_max, Leaf leaf, Fetch fetch) const;
  /// A child entered and not yet searched, on a walk's stack.
  struct Pending {
    int child;
    double t_in;  // where the ray enters its box
  };
  /// The most children a walk's stack holds: the binary build's depth bound (from depth 32 on
  /// it splits at the median: at most 31 more levels), each node popped pushing at most `width`.
  static constexpr int max_depth = 64, stack_size = (width - 1) * max_depth + 1;
  /// The same walk a step at a time (a node's children tested, or a leaf asked), on a stack
  /// of stack_size entries: `walk` runs one to its end; `walk_together` runs several in turns.
  template <class Leaf, class Fetch>
  class Walk;
  /// Runs the walks a step each in turn until every one has ended, so that the nodes and
  /// triangles one walk fetches arrive while the others step (a walk alone waits for each
  /// fetch); each walk takes the steps it takes alone.
  template <class W>
  static void walk_together(W* walks, int n);

 private:
  /// Binary nodes of the build, before they are gathered into nodes of `width`.
  struct Split;
  int build(std::vector<Split>& tree, const std::vector<Box>& boxes, int first, int count, int depth);
  int gather(const std::vector<Split>& tree, int split, double pad);
  static void prefetch(const Node& n) {
    for (std::size_t line = 0; line < sizeof(Node); line += 64) __builtin_prefetch(reinterpret_cast<const char*>(&n) + line);
  }

  std::vector<Node> nodes_;
  std::vector<int> order_;
  bvh_lanes::Kernel slab_test_ = nullptr;
};

namespace detail {

/// Two doubles in one SSE2 register (GCC's and Clang's vector extension): the slab test's
/// lanes without a SIMD target (the project's flags leave the vectorizing to the code: no SLP
/// vectorizer, no wider registers by default).
struct PairLanes {
  using Num = double __attribute__((vector_size(2 * sizeof(double))));
  static constexpr int lanes = 2;
  static Num splat(double x) { return Num{x, x}; }
  /// (One instruction where SSE2 has it: compilers convert a vector of two floats one at a time.)
  static Num widened(const float* p) {
#ifdef __SSE2__
    double both;
    __builtin_memcpy(&both, p, sizeof both);
    return Num(_mm_cvtps_pd(_mm_castpd_ps(_mm_set_sd(both))));
#else
    return Num{p[0], p[1]};
#endif
  }
  static Num later(Num a, Num b) { return a < b ? b : a; }
  static Num earlier(Num a, Num b) { return b < a ? b : a; }
  static void store(Num v, double* p) { __builtin_memcpy(p, &v, sizeof v); }
  static unsigned entered(Num in, Num out) {
#ifdef __SSE2__
    return unsigned(__builtin_ia32_movmskpd(Num(in <= out)));  // (the sign bits)
#else
    const auto m = in <= out;
    return unsigned(m[0] & 1) | unsigned(m[1] & 1) << 1;
#endif
  }
};

#include "billiards/dynamics/slab_test-inl.hpp"

/// A ray as the slab test reads it; a zero component of its direction is replaced by a tiny
/// one of the same role: the slab then spans everything (origin between the planes) or
/// nothing, with no 0·∞.
struct BvhRay : bvh_lanes::Ray {
  BvhRay(const Vec3& origin, const Vec3& dir, double pad) {
    for (int k = 0; k < 3; ++k) {
      x[k] = origin[k];
      inv[k] = 1 / (dir[k] != 0 ? dir[k] : 1e-300);
      near[k] = inv[k] < 0;
      grow[k] = near[k] ? -pad : pad;
    }
  }
};

}  // namespace detail

template <class Leaf, class Fetch>
class Bvh::Walk {
 public:
  Walk(const Bvh& bvh, const Vec3& origin, const Vec3& dir, double pad, double tau_max, Leaf leaf, Fetch fetch,
       Pending* stack)
      : bvh_(&bvh), ray_(origin, dir, pad), tau_max_(tau_max), child_(bvh.nodes_.empty() ? ended : 0), leaf_(leaf),
        fetch_(fetch), stack_(stack) {}
  /// Searches the node or leaf next (false: the walk has ended, nothing is left).
  bool step() {
    if (child_ == ended) return false;
    if (child_ < 0) {
      const int code = ~child_;
      tau_max_ = leaf_(code / max_leaf, code % max_leaf + 1);
    } else if (enter_children()) {
      return true;
    }
    // Next, the nearest entry left that is not beyond a hit found since it was pushed.
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
  /// Pushes the children of node child_ that the ray enters, farthest first (insertion by
  /// t_in), and makes the nearest the next, so that the bound shrinks early; the others are
  /// fetched meanwhile.  False where it enters none.
  bool enter_children() {
    const Node& node = bvh_->nodes_[child_];
    double t_in[width];
    const int bottom = top_;
    const float* bound = &node.bound[0][0][0];
    const unsigned entered = bvh_->slab_test_ ? bvh_->slab_test_(bound, ray_, tau_max_, t_in)
                                              : detail::slab_test<detail::PairLanes>(bound, ray_, tau_max_, t_in);
    for (unsigned mask = entered; mask; mask &= mask - 1) {
      const int i = std::countr_zero(mask);
      if (const int c = node.child[i]; c >= 0) prefetch(bvh_->nodes_[c]);
      else fetch_(~c / max_leaf, ~c % max_leaf + 1);
      int j = top_++;
      for (; j > bottom && stack_[j - 1].t_in < t_in[i]; --j) stack_[j] = stack_[j - 1];
      stack_[j] = {node.child[i], t_in[i]};
    }
    if (top_ == bottom) return false;
    child_ = stack_[--top_].child;  // (entered, so t_in ≤ tau_max)
    return true;
  }

  const Bvh* bvh_;
  detail::BvhRay ray_;
  double tau_max_;
  int top_ = 0, child_;  // the node or leaf searched next
  Leaf leaf_;
  Fetch fetch_;
  Pending* stack_;
};

template <class Leaf, class Fetch>
void Bvh::walk(const Vec3& origin, const Vec3& dir, double pad, double tau_max, Leaf leaf, Fetch fetch) const {
  Pending stack[stack_size];
  Walk<Leaf, Fetch>(*this, origin, dir, pad, tau_max, leaf, fetch, stack).run();
}

template <class W>
void Bvh::walk_together(W* walks, int n) {
  for (bool any = true; any;) {
    any = false;
    for (int i = 0; i < n; ++i) any |= walks[i].step();
  }
}

}  // namespace billiards::dynamics
