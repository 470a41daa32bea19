// The first touch's estimate (TouchPlanner::contact_estimate): pose guesses from one touch's appearance, so that
// the second touch can be planned before any pair has voted.
#include <sva/error.hpp>
#include <sva/touch_planner.hpp>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include <sva/base/portable_math.hpp>
#include <sva/base/rng.hpp>
#include <sva/base/so3.hpp>
#include "planning/contact_classes.hpp"
#include "planning/planner_state.hpp"
#include "reading/observed_reading.hpp"

namespace sva {

namespace {

// The rotation taking unit vector `from` onto unit vector `to` (the shortest one; about any perpendicular axis
// when they are opposite).
glm::dmat3 rotation_onto(const glm::dvec3& from, const glm::dvec3& to) {
  const glm::dvec3 axis = glm::cross(from, to);
  const double s = glm::length(axis), c = glm::dot(from, to);
  if (s > 1e-12) return so3::exp(axis / s * pmath::atan2(s, c));
  if (c > 0.0) return glm::dmat3(1.0);
  const glm::dvec3 any = std::abs(from.x) < 0.9 ? glm::dvec3(1.0, 0.0, 0.0) : glm::dvec3(0.0, 1.0, 0.0);
  return so3::exp(glm::normalize(glm::cross(from, any)) * std::numbers::pi);
}

// The pose that puts training contact `p` (object frame) at the touch, its normal along the touch's, turned by
// `beta` about that normal.
RigidPose aligned_pose(const SurfacePoint& p, const ObservedReading& touch, double beta) {
  const glm::dmat3 R = so3::exp(touch.normal * beta) * rotation_onto(glm::normalize(p.normal), touch.normal);
  return {R, touch.position - R * p.position};
}

// One object's contacts' likenesses to the touch, and `count` of them drawn by likeness (none when all are 0).
struct ObjectGuess {
  double likeness = 0.0;           // mean over the object's contacts
  std::vector<std::size_t> drawn;  // indices into surface.points(object)
};

ObjectGuess guess_object(const TouchPlanner::Impl& m, std::uint32_t object, const ObservedReading& touch,
                         std::size_t count, util::Rng& rng) {
  const auto& points = m.surface.points(object);
  std::vector<double> cumulative(points.size());
  double total = 0.0;
  for (std::size_t i = 0; i < points.size(); ++i)
    cumulative[i] = total += planning::class_overlap(touch.classes, m.classes[points[i].reading]);
  ObjectGuess g;
  if (points.empty() || !(total > 0.0)) return g;
  g.likeness = total / static_cast<double>(points.size());
  for (std::size_t k = 0; k < count; ++k) {
    const double u = rng.uniform() * total;
    const auto it = std::upper_bound(cumulative.begin(), cumulative.end(), u);
    g.drawn.push_back(std::min<std::size_t>(static_cast<std::size_t>(it - cumulative.begin()), points.size() - 1));
  }
  return g;
}

}  // namespace

Estimate TouchPlanner::contact_estimate(const Reading& touch, std::size_t per_object, std::uint64_t seed) const {
  if (per_object == 0) throw Error("touch planner: contact_estimate needs at least 1 hypothesis per object, got 0");
  const Impl& m = *impl_;
  const ObservedReading observed = describe_reading(*m.map, touch, "touch planner: the first touch");
  const std::uint32_t objects = static_cast<std::uint32_t>(m.surface.objects());
  util::Rng rng(seed, 0xc047ac7);
  std::vector<ObjectGuess> guesses;
  double total = 0.0;
  for (std::uint32_t o = 0; o < objects; ++o) {
    guesses.push_back(guess_object(m, o, observed, per_object, rng));
    total += guesses.back().likeness;
  }
  Estimate est;
  est.ready = true;
  est.readings = 1;
  est.object_probability.assign(objects, total > 0.0 ? 0.0 : 1.0 / std::max<std::uint32_t>(objects, 1));
  est.object_hypotheses.resize(objects);
  for (std::uint32_t o = 0; o < objects; ++o) {
    PoseHypothesis& best = est.object_hypotheses[o];
    best.object = o;
    best.object_name = m.map->objects[o].name;
    if (!(total > 0.0) || guesses[o].drawn.empty()) continue;
    const double p = guesses[o].likeness / total;
    est.object_probability[o] = p;
    for (std::size_t i : guesses[o].drawn) {
      PoseHypothesis h = best;
      h.pose = aligned_pose(m.surface.points(o)[i], observed, rng.uniform(0.0, 2.0 * std::numbers::pi));
      h.probability = p / static_cast<double>(guesses[o].drawn.size());
      h.valid = true;
      est.hypotheses.push_back(h);
    }
    best = est.hypotheses[est.hypotheses.size() - guesses[o].drawn.size()];
  }
  std::stable_sort(est.hypotheses.begin(), est.hypotheses.end(),
                   [](const PoseHypothesis& a, const PoseHypothesis& b) { return a.probability > b.probability; });
  est.object = static_cast<std::uint32_t>(
      std::max_element(est.object_probability.begin(), est.object_probability.end()) - est.object_probability.begin());
  est.object_name = objects > 0 ? m.map->objects[est.object].name : "";
  if (!est.hypotheses.empty()) est.pose = est.parabolic_pose = est.bin_pose = est.hypotheses.front().pose;
  return est;
}

}  // namespace sva
