// The triangle BVH's build: a binary tree split by the binned surface-area heuristic, whose
// nodes are then gathered eight at a time (Wald, "On fast construction of SAH-based bounding
// volume hierarchies", 2007; Embree's and pbrt's BVHs), each child with the cone of its
// triangles' normals (the normal cones of Shirman & Abi-Ezzi, "The cone of normals technique
// for fast processing of curved patches", 1993, used here to pass over back faces).
#include "billiards/dynamics/bvh3.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <numeric>

namespace billiards::dynamics {

namespace {

constexpr int bins = 16;
/// The cost of a node's test relative to a triangle's exit test, in the surface-area
/// heuristic: about one (the slab test of a node's eight boxes in one vector is some 85
/// instructions, a triangle's watertight test some 100).
constexpr double traversal_cost = 1;
/// The binary depth from which the build splits at the median instead (any input then keeps
/// the depth under max_depth).
constexpr int sah_depth = 32;

Bvh::Box empty_box() { return {Vec3::Constant(INFINITY), Vec3::Constant(-INFINITY)}; }

void grow(Bvh::Box& b, const Bvh::Box& c) {
  b.lo = b.lo.cwiseMin(c.lo);
  b.hi = b.hi.cwiseMax(c.hi);
}

double half_area(const Bvh::Box& b) {
  const Vec3 d = b.hi - b.lo;
  return d.x() * d.y() + d.y() * d.z() + d.z() * d.x();
}

Vec3 centroid(const Bvh::Box& b) { return (b.lo + b.hi) / 2; }

/// The largest float ≤ x, and the smallest ≥ x.
float float_below(double x) {
  const float f = float(x);
  return double(f) > x ? std::nextafter(f, -INFINITY) : f;
}
float float_above(double x) {
  const float f = float(x);
  return double(f) < x ? std::nextafter(f, INFINITY) : f;
}

}  // namespace

namespace detail {

BvhRay::BvhRay(const Vec3& origin, const Vec3& dir, double pad, double extent, Bvh::Heading heading_) {
  // The power of two of the largest component: its exponent's bits (by ldexp below the normals).
  const double largest = dir.cwiseAbs().maxCoeff();
  time_scale = largest >= std::numeric_limits<double>::min()
                   ? std::bit_cast<double>(std::bit_cast<std::uint64_t>(largest) & 0x7ff0000000000000)
                   : largest > 0 ? std::ldexp(1.0, std::ilogb(largest)) : 1;
  for (int k = 0; k < 3; ++k) {
    // 1/d' for d' = dir[k] / time_scale (exact), rounded once.
    const double inverse = dir[k] != 0 ? time_scale / dir[k] : std::numeric_limits<double>::infinity();
    inv[k] = float(inverse);  // (±∞ beyond the floats)
    // (The near side of the slab: the hi bound where the ray moves down the axis.)
    const bool near = inverse < 0;
    enter_at[k] = (near * 3 + k) * bvh_lanes::width;
    leave_at[k] = ((1 - near) * 3 + k) * bvh_lanes::width;
    const double x = origin[k], moved = pad + 0x1p-20 * (extent + std::abs(x) + pad);
    const float up = float(x + moved), down = float(x - moved);
    enter[k] = near ? down : up;
    leave[k] = near ? up : down;
  }
  // (Scaled first: |dir|² may be beyond the doubles.)
  const Vec3 unit = heading_ == Bvh::Heading::straight && largest > 0 ? Vec3((dir / largest).normalized()) : Vec3::Zero();
  for (int k = 0; k < 3; ++k) heading[k] = float(unit[k]);
}

}  // namespace detail

struct Bvh::Split {
  Box box;
  int first, count;         // its triangles, [first, first + count) of order_
  int left = -1, right = -1;  // children in the tree; −1 for a leaf
};

Bvh::Bvh(const std::vector<Box>& boxes, const std::vector<Facing>& facings, double pad, bvh_lanes::Kernel slab_test)
    : slab_test_(slab_test) {
  order_.resize(boxes.size());
  std::iota(order_.begin(), order_.end(), 0);
  if (boxes.empty()) return;
  std::vector<Split> tree;
  tree.reserve(2 * boxes.size());
  build(tree, boxes, 0, int(boxes.size()), 0);
  nodes_.reserve(tree.size() / 2);
  center_ = centroid(tree[0].box);
  gather(tree, facings, 0, pad);
}

/// Splits order_[first, first + count) where the binned surface-area heuristic puts it (or
/// makes a leaf when that is cheaper); returns the index of its node in `tree`.
int Bvh::build(std::vector<Split>& tree, const std::vector<Box>& boxes, int first, int count, int depth) {
  const int index = int(tree.size());
  tree.push_back({empty_box(), first, count});
  Box centroids = empty_box();
  for (int i = first; i < first + count; ++i) {
    grow(tree[index].box, boxes[order_[i]]);
    const Vec3 c = centroid(boxes[order_[i]]);
    grow(centroids, {c, c});
  }
  if (count == 1) return index;
  int axis;
  const double extent = (centroids.hi - centroids.lo).maxCoeff(&axis);
  const auto bin_of = [&](int t) {
    return std::min(bins - 1, int(bins * (centroid(boxes[t])[axis] - centroids.lo[axis]) / extent));
  };
  int mid = first + count / 2;  // the median, where the heuristic cannot split
  if (extent > 0 && depth < sah_depth) {
    Box bin_box[bins];
    int bin_count[bins] = {};
    std::fill_n(bin_box, bins, empty_box());
    for (int i = first; i < first + count; ++i) {
      const int b = bin_of(order_[i]);
      grow(bin_box[b], boxes[order_[i]]);
      ++bin_count[b];
    }
    // cost[s]: the heuristic's cost of splitting before bin s, its right side summed first.
    double cost[bins] = {};
    Box right = empty_box();
    for (int s = bins - 1, n = 0; s > 0; --s) {
      grow(right, bin_box[s]);
      n += bin_count[s];
      cost[s] = n * half_area(right);
    }
    Box left = empty_box();
    int best = 1;
    for (int s = 1, n = 0; s < bins; ++s) {
      grow(left, bin_box[s - 1]);
      n += bin_count[s - 1];
      cost[s] += n * half_area(left);
      if (cost[s] < cost[best]) best = s;
    }
    const double area = half_area(tree[index].box);
    if (count <= max_leaf && count * area <= traversal_cost * area + cost[best]) return index;
    mid = int(std::partition(order_.begin() + first, order_.begin() + first + count,
                             [&](int t) { return bin_of(t) < best; }) -
              order_.begin());
  } else if (count <= max_leaf) {
    return index;
  } else {
    const auto key = [&](int t) { return centroid(boxes[t])[axis]; };
    std::nth_element(order_.begin() + first, order_.begin() + mid, order_.begin() + first + count,
                     [&](int a, int b) { return key(a) < key(b); });
  }
  const int left = build(tree, boxes, first, mid - first, depth + 1);
  const int right = build(tree, boxes, mid, first + count - mid, depth + 1);
  tree[index].left = left, tree[index].right = right;
  return index;
}

/// The node of `width` children under `split`: its two children (a leaf: itself, the root of
/// a tree of one leaf), then repeatedly the inner child of largest surface area replaced by
/// its own two.
int Bvh::gather(const std::vector<Split>& tree, const std::vector<Facing>& facings, int split, double pad) {
  int children[width] = {split};
  int n = 1;
  if (tree[split].left >= 0) children[0] = tree[split].left, children[n++] = tree[split].right;
  while (n < width) {
    int widest = -1;
    for (int i = 0; i < n; ++i)
      if (tree[children[i]].left >= 0 &&
          (widest < 0 || half_area(tree[children[i]].box) > half_area(tree[children[widest]].box)))
        widest = i;
    if (widest < 0) break;
    const Split& s = tree[children[widest]];
    children[widest] = s.left;
    children[n++] = s.right;
  }
  const int index = int(nodes_.size());
  nodes_.emplace_back();
  for (int i = 0; i < width; ++i) {
    const Box box = i < n ? tree[children[i]].box : empty_box();
    for (int k = 0; k < 3; ++k) {
      nodes_[index].bound[0][k][i] = float_below(box.lo[k] - pad - center_[k]);
      nodes_[index].bound[1][k][i] = float_above(box.hi[k] + pad - center_[k]);
      if (i < n)
        extent_ = std::max({extent_, std::abs(double(nodes_[index].bound[0][k][i])),
                            std::abs(double(nodes_[index].bound[1][k][i]))});
    }
  }
  for (int i = 0; i < n; ++i) {
    const Split& s = tree[children[i]];
    cone_of(facings, s, nodes_[index], i);
    // (Not `nodes_[index].child[i] = gather(...)`: gather may move nodes_.)
    const int child = s.left >= 0 ? gather(tree, facings, children[i], pad) : ~(s.first * max_leaf + s.count - 1);
    nodes_[index].child[i] = child;
  }
  return index;
}

/// Child i's cone: the axis q, the mean of its triangles' normals as integers of 127 at most,
/// and t with −t ≤ h·q in floats wherever h is within the angle α of the plane normal to q:
/// α = β + arcsin δ, β the widest angle between q and a normal and δ the largest margin, so
/// that a heading h beyond it (h·q < −|q| sin α) makes more than 90° + arcsin δ with each
/// normal n, that is n·h < −δ.  The float product moves h·q by less than 6·10⁻⁷ |q| (h's
/// rounding to floats, 6·10⁻⁸ |q|; the three products and two sums, 2⁻²⁴ each of at most
/// √3 |q|), and the angles here in doubles by far less than 10⁻⁶: t holds 10⁻⁶ of each.
/// Zero (no heading is passed over) where α is not below 90° or t would need more than 8 bits.
void Bvh::cone_of(const std::vector<Facing>& facings, const Split& split, Node& node, int i) const {
  Vec3 sum = Vec3::Zero();
  double margin = 0;
  for (int j = split.first; j < split.first + split.count; ++j) {
    sum += facings[order_[j]].normal;
    margin = std::max(margin, facings[order_[j]].margin);
  }
  if (!(margin < 1) || !(sum.norm() > 0)) return;
  const Vec3 q = (127 * sum.normalized()).array().round();
  const Vec3 axis = q.normalized();
  double widest = 0;
  for (int j = split.first; j < split.first + split.count; ++j) {
    const Vec3& n = facings[order_[j]].normal;
    widest = std::max(widest, std::atan2(axis.cross(n).norm(), axis.dot(n)));
  }
  const double alpha = widest + std::asin(margin) + 1e-6;
  if (!(alpha < std::numbers::pi / 2)) return;
  const double t = std::ceil(q.norm() * (std::sin(alpha) + 1e-6));
  if (t > 127) return;
  for (int k = 0; k < 3; ++k) node.cone[k][i] = std::int8_t(q[k]);
  node.cone[3][i] = std::int8_t(-t);
}

}  // namespace billiards::dynamics
