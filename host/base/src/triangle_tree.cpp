#include <sva/base/triangle_tree.hpp>

#include <sva/base/closest_point.hpp>

#include "embree_search.hpp"

namespace sva {

namespace {

struct Search {
  const float* corners;
  const std::uint32_t* index;
  glm::dvec3 p;
  double size;
  TriangleTree::Hit best;
};

// One triangle Embree's walk reached: weighed in double, and the radius shrunk to the best so far.
bool visit(RTCPointQueryFunctionArguments* args) {
  Search& s = *static_cast<Search*>(args->userPtr);
  const float* c = s.corners + 9 * static_cast<std::size_t>(args->primID);
  const glm::dvec3 q = closest_on_triangle(s.p, glm::dvec3(c[0], c[1], c[2]), glm::dvec3(c[3], c[4], c[5]),
                                           glm::dvec3(c[6], c[7], c[8]));
  const double d2 = glm::dot(q - s.p, q - s.p);
  const std::uint32_t index = s.index[args->primID];
  if (!(d2 < s.best.d2 || (d2 == s.best.d2 && s.best.found && index < s.best.index))) return false;
  s.best.found = true, s.best.index = index, s.best.point = q, s.best.d2 = d2;
  const float r = embree::culling_radius(s.size, std::sqrt(d2));
  if (!(r < args->query->radius)) return false;
  args->query->radius = r;
  return true;
}

}  // namespace

TriangleTree::TriangleTree() = default;
TriangleTree::~TriangleTree() = default;
TriangleTree::TriangleTree(TriangleTree&&) noexcept = default;
TriangleTree& TriangleTree::operator=(TriangleTree&&) noexcept = default;

TriangleTree::TriangleTree(const std::vector<Triangle>& triangles) {
  if (triangles.empty()) return;
  corners_.reserve(9 * triangles.size() + 3);  // Embree reads a vertex's last float as part of 16 bytes
  index_.reserve(triangles.size());
  for (const Triangle& t : triangles) {
    for (const glm::vec3& v : {t.a, t.b, t.c}) corners_.insert(corners_.end(), {v.x, v.y, v.z});
    index_.push_back(t.index);
  }
  corners_.insert(corners_.end(), {0.0f, 0.0f, 0.0f});
  embree::clear_error();
  RTCGeometry g = rtcNewGeometry(embree::device(), RTC_GEOMETRY_TYPE_TRIANGLE);
  embree::check("triangle tree: a mesh");
  rtcSetSharedGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, corners_.data(), 0, 3 * sizeof(float),
                             3 * triangles.size());
  auto* ib = static_cast<std::uint32_t*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                                 3 * sizeof(std::uint32_t), triangles.size()));
  if (!ib) {
    rtcReleaseGeometry(g);
    embree::check("triangle tree: the triangles' buffer");
    throw Error("triangle tree: Embree could not allocate the triangles' buffer");
  }
  for (std::uint32_t k = 0; k < 3 * triangles.size(); ++k) ib[k] = k;  // each triangle its own three corners
  scene_ = embree::scene_of(g, "triangle tree of " + std::to_string(triangles.size()) + " triangles");
}

TriangleTree::Hit TriangleTree::nearest(const glm::dvec3& p, double radius) const {
  Search s{corners_.data(), index_.data(), p, embree::query_size(p), {}};
  if (!scene_ || !(radius > 0.0) || !(s.size < embree::kFarthest)) return s.best;
  s.best.d2 = radius * radius;
  RTCPointQuery q;
  q.x = static_cast<float>(p.x), q.y = static_cast<float>(p.y), q.z = static_cast<float>(p.z);
  q.time = 0.0f;
  q.radius = embree::culling_radius(s.size, radius);
  RTCPointQueryContext context;
  rtcInitPointQueryContext(&context);
  rtcPointQuery(scene_.get(), &q, &context, visit, &s);
  return s.best;
}

}  // namespace sva
