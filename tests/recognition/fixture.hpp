#pragma once
// Synthetic worlds for the recognition tests, built in code so they run in
// milliseconds: objects are ellipsoids sampled at surface points whose hard
// appearance class depends on where they lie (spatially-varying appearance);
// the pair map is built by the map builder's own pair index.
#include <sva/base/rng.hpp>
#include <sva/base/so3.hpp>

#include <glm/glm.hpp>

#include <cmath>
#include <memory>
#include <numbers>
#include <string>
#include <vector>

#include "backends/vote_backend.hpp"
#include "estimate/candidates.hpp"
#include "map/map_builder.hpp"
#include "map/pair_map.hpp"
#include "reading/observed_reading.hpp"
#include "recognition/bayes_filter.hpp"
#include "votes/pose_space.hpp"

namespace sva::test {

struct WorldPoint {
  glm::dvec3 p, n;
  std::uint32_t cls;
};

struct World {
  std::vector<std::vector<WorldPoint>> objects;
  std::shared_ptr<PairMap> map;
};

struct WorldSpec {
  int objects = 3;
  int points = 80;
  std::uint32_t classes = 6;
  std::uint32_t dist_bins = 12;
  double dist_min = 5.0, dist_max = 80.0;
  bool planar = false;  // points on the plane z = 0, normals +z (the letters)
  std::uint64_t seed = 11;
};

// Surface point i of object o: deterministic, dense enough that test readings
// can be drawn from the training points themselves.
inline WorldPoint world_point(const WorldSpec& s, int o, int i) {
  util::Rng rng(s.seed, static_cast<std::uint64_t>(o), static_cast<std::uint64_t>(i));
  WorldPoint w;
  if (s.planar) {
    const double x = rng.uniform(-12.0, 12.0), y = rng.uniform(-12.0, 12.0);
    w.p = {x, y, 0.0};
    w.n = {0.0, 0.0, 1.0};
    const int cell =
        static_cast<int>(std::floor((x + 12.0) / 8.0)) * 3 + static_cast<int>(std::floor((y + 12.0) / 8.0));
    w.cls = static_cast<std::uint32_t>((cell * 7 + o * 3) % static_cast<int>(s.classes));
    return w;
  }
  const glm::dvec3 axes(30.0 - 4.0 * o, 22.0 + 3.0 * o, 15.0 + 2.0 * o);
  const double z = rng.uniform(-1.0, 1.0), phi = rng.uniform(0.0, 2.0 * std::numbers::pi);
  const double rho = std::sqrt(1.0 - z * z);
  const glm::dvec3 u(rho * std::cos(phi), rho * std::sin(phi), z);
  w.p = axes * u;
  w.n = glm::normalize(u / axes);
  const int oct = (u.x > 0) + 2 * (u.y > 0) + 4 * (u.z > 0);
  w.cls = static_cast<std::uint32_t>((oct * 5 + o * 2 + (std::fabs(u.z) > 0.7 ? 1 : 0)) % static_cast<int>(s.classes));
  return w;
}

inline World make_world(const WorldSpec& s) {
  World w;
  auto map = std::make_shared<PairMap>();
  map->scene_name = "synthetic-recognition";
  map->pose_space.kind = s.planar ? PoseSpaceSpec::Kind::planar : PoseSpaceSpec::Kind::spatial;
  map->key_space.n_classes = s.classes;
  map->key_space.n_dist_bins = s.dist_bins;
  map->distance.count = s.dist_bins;
  map->distance.min_mm = s.dist_min;
  map->distance.max_mm = s.dist_max;
  std::vector<std::vector<ClassWeight>> classes;
  for (int o = 0; o < s.objects; ++o) {
    MapObject mo;
    mo.name = "obj" + std::to_string(o);
    map->objects.push_back(mo);
    w.objects.emplace_back();
    for (int i = 0; i < s.points; ++i) {
      const WorldPoint pt = world_point(s, o, i);
      w.objects.back().push_back(pt);
      map->readings.push_back(static_cast<std::uint32_t>(o), pt.p, pt.n, 1.0f);
      classes.push_back({{pt.cls, 1.0f}});
    }
  }
  build_pair_index(*map, classes, 1, false);
  w.map = map;
  return w;
}

// The estimate's first stage on a filter's belief: what the filter's tests read of it.
inline Candidates candidates(const BayesFilter& f, std::size_t top_k, std::size_t modes = 1) {
  f.require_complete();
  CandidateRequest r;
  r.top_k = top_k;
  r.modes = modes;
  return find_candidates(f.belief(), f.space(), r);
}

// A point of the object seen in the robot frame under `pose`.
inline ObservedReading observe(const WorldPoint& w, const RigidPose& pose, float norm_conf = 1.0f) {
  ObservedReading r;
  r.position = pose.apply(w.p);
  r.normal = pose.rotate(w.n);
  r.normal = r.normal / glm::length(r.normal);  // as describe_reading and to_grid hand the filter its readings
  r.norm_conf = norm_conf;
  r.classes = {{w.cls, 1.0f}};
  return r;
}

inline PoseSpaceSpec paper_space() {
  PoseSpaceSpec s;  // 50 bins over [-200, 200] mm, 9 Rodrigues bins: the paper's 3-D space
  return s;
}

// A planar world (points on z = 0) whose pairs span 1 to 30 mm.
inline WorldSpec planar_spec() {
  WorldSpec s;
  s.planar = true;
  s.dist_min = 1.0;
  s.dist_max = 30.0;
  return s;
}

inline PoseSpaceSpec letters_space() {
  PoseSpaceSpec s;
  s.kind = PoseSpaceSpec::Kind::planar;
  s.translation_bins = 21;
  s.translation_min_mm = -10.0;
  s.translation_max_mm = 10.0;
  s.rotation_bins = 9;
  return s;
}

inline RigidPose random_pose(std::uint64_t seed, double t_range, bool planar = false) {
  util::Rng rng(seed, 99);
  RigidPose p;
  if (planar) {
    p.R = so3::about_z(rng.uniform(-3.0, 3.0));
    p.T = {rng.uniform(-t_range, t_range), rng.uniform(-t_range, t_range), 0.0};
  } else {
    glm::dvec3 axis(rng.normal(), rng.normal(), rng.normal());
    axis = glm::normalize(axis);
    p.R = so3::exp(axis * rng.uniform(0.2, 3.0));
    p.T = {rng.uniform(-t_range, t_range), rng.uniform(-t_range, t_range), rng.uniform(-t_range, t_range)};
  }
  return p;
}

inline double angle_between(const glm::dmat3& a, const glm::dmat3& b) { return so3::angle(glm::transpose(a) * b); }

// Translation width of one bin of a space.
inline double bin_width(const PoseSpaceSpec& s) {
  return (s.translation_max_mm - s.translation_min_mm) / s.translation_bins;
}

}  // namespace sva::test
