#pragma once
// The objects' surfaces as the map knows them: every training reading's
// contact position and normal (object frame, mm), in one small k-d tree per
// object, so that the fine pose (estimate/fine_pose.hpp) finds the
// training contacts nearest to an observed one in microseconds. Built once per
// map (by the recognizer that uses it), never per estimate; immutable, so any
// number of sessions may query it at once.
#include <glm/glm.hpp>

#include <cstdint>
#include <vector>

#include "map/pair_map.hpp"

namespace sva {

struct SurfacePoint {
  glm::dvec3 position{0.0};
  glm::dvec3 normal{0.0, 0.0, 1.0};
  std::uint32_t reading = 0;  // its row in the map's reading table (MapReadings)
};

struct SurfaceNeighbour {
  std::uint32_t index = 0;  // into points(object)
  double distance_sq = 0.0;
};

// What a query keeps for the next one nearby (SurfaceIndex::nearest with a memo): its point and its 2k nearest. The
// fine pose asks again for each reading at every step of its fit, a micron to a few mm from the last query; while
// the k nearest of those 2k, weighed at the new point, lie nearer than any contact outside the memo can now be, they
// are the answer without a search. One per reading, per fit: never shared between threads.
struct NeighbourMemo {
  bool valid = false;
  std::uint32_t object = 0;
  std::size_t k = 0;
  glm::dvec3 q{0.0};                   // the last searched point
  std::vector<SurfaceNeighbour> near;  // its 2k nearest (fewer: every contact of the object), nearest first
};

class SurfaceIndex {
 public:
  explicit SurfaceIndex(const MapReadings& readings, std::size_t objects);

  std::size_t objects() const { return trees_.size(); }
  const std::vector<SurfacePoint>& points(std::uint32_t object) const { return trees_[object].points; }
  // The (up to) k training contacts of `object` nearest to `q` (object frame),
  // nearest first; ties go to the smaller index, so the answer is one and the
  // same on every machine. `out` is overwritten.
  void nearest(std::uint32_t object, const glm::dvec3& q, std::size_t k, std::vector<SurfaceNeighbour>* out) const;
  // The same answer, bit for bit, from `memo`'s last search when q lies close enough to it, else by a search that
  // refills the memo.
  void nearest(std::uint32_t object, const glm::dvec3& q, std::size_t k, std::vector<SurfaceNeighbour>* out,
               NeighbourMemo* memo) const;

 private:
  // A node covers points [begin, end); an inner node splits them at `split`
  // along `axis` into [begin, mid) and [mid, end).
  struct Node {
    std::uint32_t begin = 0, end = 0, mid = 0;
    std::int32_t left = -1, right = -1;  // -1: a leaf
    int axis = 0;
    double split = 0.0;
  };
  struct Tree {
    std::vector<SurfacePoint> points;  // reordered so that every node's points are contiguous
    std::vector<Node> nodes;           // nodes[0] is the root (when there are points)
  };
  static void search(const Tree& tree, std::int32_t node, const glm::dvec3& q, std::size_t k,
                     std::vector<SurfaceNeighbour>* best);
  static std::size_t memo_size(std::size_t k) { return 2 * k; }
  // Whether the memo proves the k nearest to q (NeighbourMemo); `out` is overwritten either way, and holds them if so.
  bool from_memo(const NeighbourMemo& memo, std::uint32_t object, const glm::dvec3& q, std::size_t k,
                 std::vector<SurfaceNeighbour>* out) const;

  std::vector<Tree> trees_;
};

}  // namespace sva
