#pragma once
// What a search over Embree's tree needs beside its visit (triangle_tree.cpp): a scene of one geometry, and the float
// radius that keeps every box that could hold an equal or nearer answer. Embree proposes, sva decides: each candidate
// is weighed in double by the caller, the smallest (squared distance, index) wins, and the query's float radius only
// shrinks to the best distance plus a margin above the rounding of Embree's floats (its query point, the float corners
// or points its boxes hold, its box distances).
#include <embree3/rtcore.h>
#include <sva/base/embree.hpp>
#include <sva/error.hpp>

#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

namespace sva::embree {

// Query points past this (mm) are not searched: Embree's query is in floats (3.4e38 at most).
inline constexpr double kFarthest = 1e30;

// The size the margin scales with: the query point's largest coordinate, at least 1 mm.
inline double query_size(const glm::dvec3& p) {
  return std::max({std::fabs(p.x), std::fabs(p.y), std::fabs(p.z), 1.0});
}

// The float radius that searches every box within `r` of p (size: query_size(p)): 1e-6 mm plus 8 float epsilons of
// the coordinates' and the radius's size, rounded up.
inline float culling_radius(double size, double r) {
  const double margin = 1e-6 + 8.0 * static_cast<double>(std::numeric_limits<float>::epsilon()) * (size + r);
  return std::nextafter(static_cast<float>(r + margin), std::numeric_limits<float>::infinity());
}

// A scene of the one committed geometry `g` (released here), compact nodes at medium quality: a fifth less memory
// than Embree's default nodes at the same speed of these queries. Throws sva::Error naming `what`.
inline Scene scene_of(RTCGeometry g, const std::string& what) {
  rtcCommitGeometry(g);
  Scene scene(rtcNewScene(device()));
  if (!scene) {
    rtcReleaseGeometry(g);
    check(what + ": a scene");
    throw Error(what + ": Embree could not make a scene");
  }
  rtcSetSceneFlags(scene.get(), RTC_SCENE_FLAG_COMPACT);
  rtcSetSceneBuildQuality(scene.get(), RTC_BUILD_QUALITY_MEDIUM);
  rtcAttachGeometry(scene.get(), g);
  rtcReleaseGeometry(g);
  rtcCommitScene(scene.get());
  check(what + ": building the tree");
  return scene;
}

}  // namespace sva::embree
