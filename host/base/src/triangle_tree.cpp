#include <sva/base/triangle_tree.hpp>

#include <sva/base/closest_point.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace sva {

namespace {

// Triangles a leaf holds at most: four closest points cost about what the two boxes above them do.
constexpr std::size_t kLeafTriangles = 4;
// A box is passed over when it lies farther than the best triangle by more than this (mm): far above the rounding
// of a box's distance and of a closest point (1e-13 of coordinates of hundreds of mm), so a box that could hold an
// equal or nearer triangle is always searched.
constexpr double kMargin = 1e-6;

glm::vec3 centre_of(const TriangleTree::Triangle& t) { return (t.a + t.b + t.c) / 3.0f; }

}  // namespace

TriangleTree::TriangleTree(std::vector<Triangle> triangles) : triangles_(std::move(triangles)) {
  if (triangles_.empty()) return;
  pairs_.reserve(triangles_.size() / kLeafTriangles + 1);
  root_ = build(triangles_, 0);
}

// The node of `triangles` (triangles_[begin, begin + size)), reordered in place: its box, and either a leaf or a
// pair of children, split at the median centre along the longest side of the centres' box.
TriangleTree::Node TriangleTree::build(std::span<Triangle> triangles, std::uint32_t begin) {
  glm::vec3 lo(std::numeric_limits<float>::infinity()), hi(-std::numeric_limits<float>::infinity());
  glm::vec3 clo = lo, chi = hi;
  for (const Triangle& t : triangles) {
    lo = glm::min(lo, glm::min(t.a, glm::min(t.b, t.c)));
    hi = glm::max(hi, glm::max(t.a, glm::max(t.b, t.c)));
    clo = glm::min(clo, centre_of(t)), chi = glm::max(chi, centre_of(t));
  }
  Node node{{lo.x, lo.y, lo.z}, begin, {hi.x, hi.y, hi.z}, static_cast<std::uint32_t>(triangles.size())};
  if (triangles.size() <= kLeafTriangles) return node;
  const glm::vec3 extent = chi - clo;
  const int axis = extent.x >= extent.y && extent.x >= extent.z ? 0 : (extent.y >= extent.z ? 1 : 2);
  const std::size_t mid = triangles.size() / 2;
  // Ties by index: the same tree from every standard library (the answers would not differ, the times might).
  std::nth_element(triangles.begin(), triangles.begin() + static_cast<std::ptrdiff_t>(mid), triangles.end(),
                   [axis](const Triangle& u, const Triangle& v) {
                     const float cu = centre_of(u)[axis], cv = centre_of(v)[axis];
                     return cu != cv ? cu < cv : u.index < v.index;
                   });
  node.first = static_cast<std::uint32_t>(pairs_.size()), node.count = 0;
  pairs_.emplace_back();
  const Node left = build(triangles.first(mid), begin);
  const Node right = build(triangles.subspan(mid), begin + static_cast<std::uint32_t>(mid));
  pairs_[node.first] = Pair{{left, right}};
  return node;
}

namespace {

// One axis's gap between p and the box [lo, hi] (0 inside).
[[gnu::always_inline]] inline double gap(float lo, float hi, double p) {
  return std::max(std::max(static_cast<double>(lo) - p, p - static_cast<double>(hi)), 0.0);
}

// Inlined and written out by axis: two calls a visited node, the search's most frequent step.
[[gnu::always_inline]] inline double box_distance2(const float* lo, const float* hi, const glm::dvec3& p) {
  const double x = gap(lo[0], hi[0], p.x), y = gap(lo[1], hi[1], p.y), z = gap(lo[2], hi[2], p.z);
  return x * x + y * y + z * z;
}

}  // namespace

TriangleTree::Hit TriangleTree::nearest(const glm::dvec3& p, double radius) const {
  Hit best;
  if (triangles_.empty() || !(radius > 0.0)) return best;
  best.d2 = radius * radius;
  double reach = radius + kMargin;  // boxes farther than this hold no triangle that could win or tie
  // Depth first, the nearer child first. A median split makes the tree at most 32 deep, and the stack holds at most
  // one pending sibling a level.
  struct Pending {
    const Node* node;
    double d2;
  };
  std::array<Pending, 64> stack;
  std::size_t top = 0;
  stack[top++] = {&root_, box_distance2(root_.lo, root_.hi, p)};
  while (top > 0) {
    const Pending at = stack[--top];
    if (at.d2 > reach * reach) continue;
    const Node& n = *at.node;
    if (n.count == 0) {
      const Pair& pair = pairs_[n.first];
      const double dl = box_distance2(pair.child[0].lo, pair.child[0].hi, p);
      const double dr = box_distance2(pair.child[1].lo, pair.child[1].hi, p);
      const Pending near = dl <= dr ? Pending{&pair.child[0], dl} : Pending{&pair.child[1], dr};
      const Pending far = dl <= dr ? Pending{&pair.child[1], dr} : Pending{&pair.child[0], dl};
      if (far.d2 <= reach * reach) stack[top++] = far;
      if (near.d2 <= reach * reach) stack[top++] = near;
      continue;
    }
    for (std::uint32_t s = n.first; s < n.first + n.count; ++s) {
      const Triangle& t = triangles_[s];
      const glm::dvec3 q = closest_on_triangle(p, glm::dvec3(t.a), glm::dvec3(t.b), glm::dvec3(t.c));
      const double d2 = glm::dot(q - p, q - p);
      if (d2 < best.d2 || (d2 == best.d2 && best.found && t.index < best.index)) {
        best.found = true, best.index = t.index, best.point = q, best.d2 = d2;
        reach = std::sqrt(d2) + kMargin;
      }
    }
  }
  return best;
}

}  // namespace sva
