#include "map/surface_index.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>

namespace sva {

namespace {

constexpr std::uint32_t kLeafSize = 8;

// A strict total order along one axis (position, then the original index), so
// that the split, and with it every answer, does not depend on the sort.
struct AxisOrder {
  const std::vector<SurfacePoint>* points;
  int axis;
  bool operator()(std::uint32_t a, std::uint32_t b) const {
    const double pa = (*points)[a].position[axis], pb = (*points)[b].position[axis];
    return pa < pb || (pa == pb && a < b);
  }
};

// The one order of neighbours: nearer first, ties to the smaller index.
bool before(const SurfaceNeighbour& a, const SurfaceNeighbour& b) {
  return a.distance_sq < b.distance_sq || (a.distance_sq == b.distance_sq && a.index < b.index);
}

double distance_sq(const glm::dvec3& p, const glm::dvec3& q) {
  const glm::dvec3 d = p - q;
  return glm::dot(d, d);
}

void insert_neighbour(std::vector<SurfaceNeighbour>* best, std::size_t k, SurfaceNeighbour n) {
  if (best->size() == k && !before(n, best->back())) return;
  best->insert(std::upper_bound(best->begin(), best->end(), n, before), n);
  if (best->size() > k) best->pop_back();
}

}  // namespace

SurfaceIndex::SurfaceIndex(const MapReadings& readings, std::size_t objects) : trees_(objects) {
  for (std::size_t i = 0; i < readings.size(); ++i) {
    if (readings.object[i] >= objects) continue;
    SurfacePoint p;
    p.position = {readings.px[i], readings.py[i], readings.pz[i]};
    p.normal = {readings.nx[i], readings.ny[i], readings.nz[i]};
    p.reading = static_cast<std::uint32_t>(i);
    trees_[readings.object[i]].points.push_back(p);
  }
  for (Tree& t : trees_) {
    if (t.points.empty()) continue;
    // Sort a permutation, then apply it: the nodes refer to the reordered points.
    std::vector<std::uint32_t> order(t.points.size());
    std::iota(order.begin(), order.end(), 0u);
    Tree work;
    work.points = t.points;
    t.nodes.clear();
    // Build over the permutation, reordering `order` in place.
    struct Builder {
      Tree& tree;
      std::vector<std::uint32_t>& order;
      const std::vector<SurfacePoint>& original;
      std::int32_t run(std::uint32_t begin, std::uint32_t end) {
        const auto id = static_cast<std::int32_t>(tree.nodes.size());
        tree.nodes.push_back({begin, end, end, -1, -1, 0, 0.0});
        if (end - begin <= kLeafSize) return id;
        glm::dvec3 lo(1e300), hi(-1e300);
        for (std::uint32_t i = begin; i < end; ++i) {
          lo = glm::min(lo, original[order[i]].position);
          hi = glm::max(hi, original[order[i]].position);
        }
        const glm::dvec3 extent = hi - lo;
        const int axis = extent.x >= extent.y && extent.x >= extent.z ? 0 : (extent.y >= extent.z ? 1 : 2);
        const std::uint32_t mid = begin + (end - begin) / 2;
        std::nth_element(order.begin() + begin, order.begin() + mid, order.begin() + end, AxisOrder{&original, axis});
        const double split = original[order[mid]].position[axis];
        const std::int32_t left = run(begin, mid);
        const std::int32_t right = run(mid, end);
        Node& n = tree.nodes[static_cast<std::size_t>(id)];
        n.mid = mid;
        n.axis = axis;
        n.split = split;
        n.left = left;
        n.right = right;
        return id;
      }
    } builder{t, order, work.points};
    builder.run(0, static_cast<std::uint32_t>(order.size()));
    for (std::size_t i = 0; i < order.size(); ++i) t.points[i] = work.points[order[i]];
  }
}

void SurfaceIndex::search(const Tree& tree, std::int32_t id, const glm::dvec3& q, std::size_t k,
                          std::vector<SurfaceNeighbour>* best) {
  const Node& n = tree.nodes[static_cast<std::size_t>(id)];
  if (n.left < 0) {
    for (std::uint32_t i = n.begin; i < n.end; ++i) {
      insert_neighbour(best, k, {i, distance_sq(tree.points[i].position, q)});
    }
    return;
  }
  // Points on the split plane may sit on either side: the far side is searched
  // whenever the plane is no farther than the k-th best (ties included).
  const double diff = q[n.axis] - n.split;
  const std::int32_t near = diff < 0.0 ? n.left : n.right;
  const std::int32_t far = diff < 0.0 ? n.right : n.left;
  search(tree, near, q, k, best);
  if (best->size() < k || diff * diff <= best->back().distance_sq) search(tree, far, q, k, best);
}

void SurfaceIndex::nearest(std::uint32_t object, const glm::dvec3& q, std::size_t k,
                           std::vector<SurfaceNeighbour>* out) const {
  out->clear();
  if (object >= trees_.size() || k == 0) return;
  const Tree& t = trees_[object];
  if (t.nodes.empty()) return;
  search(t, 0, q, k, out);
}

// Every contact lies within delta = |q - memo.q| of its distance to the memo's point, so any contact the memo does not
// hold lies at least r_K - delta from q (r_K: the memo's farthest). When the k-th nearest of the memo's contacts,
// weighed at q, lies nearer than that (by a margin far above the rounding of these distances, so that no near tie
// crosses), they are the k nearest of all. A memo of every contact of the object always holds.
bool SurfaceIndex::from_memo(const NeighbourMemo& memo, std::uint32_t object, const glm::dvec3& q, std::size_t k,
                             std::vector<SurfaceNeighbour>* out) const {
  if (!memo.valid || memo.object != object || memo.k != k) return false;
  const std::vector<SurfacePoint>& pts = trees_[object].points;
  out->clear();
  for (const SurfaceNeighbour& n : memo.near) out->push_back({n.index, distance_sq(pts[n.index].position, q)});
  std::sort(out->begin(), out->end(), before);
  if (out->size() > k) out->resize(k);
  if (memo.near.size() < memo_size(k)) return true;
  const double delta = glm::length(q - memo.q), reach = std::sqrt(memo.near.back().distance_sq);
  const glm::dvec3 a = glm::abs(q);
  const double margin = 1e-9 * (1.0 + std::max({a.x, a.y, a.z}) + reach);
  return std::sqrt(out->back().distance_sq) + delta + margin < reach;
}

void SurfaceIndex::nearest(std::uint32_t object, const glm::dvec3& q, std::size_t k, std::vector<SurfaceNeighbour>* out,
                           NeighbourMemo* memo) const {
  if (object >= trees_.size() || k == 0 || trees_[object].nodes.empty()) return nearest(object, q, k, out);
  if (from_memo(*memo, object, q, k, out)) return;
  nearest(object, q, memo_size(k), &memo->near);
  memo->valid = true, memo->object = object, memo->k = k, memo->q = q;
  out->assign(memo->near.begin(), memo->near.begin() + static_cast<std::ptrdiff_t>(std::min(k, memo->near.size())));
}

}  // namespace sva
