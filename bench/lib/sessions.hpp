#pragma once
// The bench programs' fixed sessions (bench/speed/estimate_speed.cpp, batch_speed.cpp; filter_speed.cpp groups its
// readings by object here too, and draws its own trials): session t touches object t % objects at a random pose of the
// map's space, as `sva bench`'s trials do (seed 1), and a digest of every number an estimate reports that its stages
// decide, which must not change when a stage is made faster or the threads change.
#include <sva/base/rng.hpp>
#include <sva/base/so3.hpp>
#include <sva/dataset.hpp>
#include <sva/error.hpp>
#include <sva/map.hpp>
#include <sva/recognizer.hpp>

#include <cstdint>
#include <cstring>
#include <numbers>
#include <string>
#include <vector>

namespace sva::bench {

// Each object's converged test readings.
inline std::vector<std::vector<const Reading*>> readings_by_object(const Map& map, const Dataset& test) {
  std::vector<std::vector<const Reading*>> by_object(map.objects());
  for (const Sample& s : test.samples)
    if (s.reading.status == ControllerStatus::converged && s.object < map.objects())
      by_object[s.object].push_back(&s.reading);
  return by_object;
}

// A bench session: its readings of one object, moved by one pose (the truth its estimates are judged by).
struct BenchSession {
  std::vector<Reading> readings;
  std::uint32_t object = 0;
  RigidPose truth;
};

// Session t of `readings` readings: object t % objects, moved by a random pose of the map's space. Throws naming
// `test` when that object has no test readings.
inline BenchSession make_session(const std::vector<std::vector<const Reading*>>& by_object, const PoseSpaceSpec& space,
                                 std::size_t t, std::size_t readings, const std::string& test) {
  BenchSession out;
  out.object = static_cast<std::uint32_t>(t % by_object.size());
  const auto& pool = by_object[out.object];
  if (pool.empty()) throw Error(test + ": object " + std::to_string(out.object) + " has no test readings");
  util::Rng rng(1, t);
  RigidPose& truth = out.truth;
  const double lo = space.translation_min_mm, hi = space.translation_max_mm;
  if (space.kind == PoseSpaceSpec::Kind::planar) {
    truth.R = so3::about_z(rng.uniform(-3.1, 3.1));
    truth.T = {rng.uniform(lo, hi), rng.uniform(lo, hi), 0.0};
  } else {
    const glm::dvec3 axis = glm::normalize(glm::dvec3(rng.normal(), rng.normal(), rng.normal()));
    truth.R = so3::exp(axis * rng.uniform(0.0, std::numbers::pi));
    truth.T = {rng.uniform(lo, hi), rng.uniform(lo, hi), rng.uniform(lo, hi)};
  }
  for (std::size_t i = 0; i < readings; ++i) {
    Reading r = *pool[rng.below(pool.size())];
    r.position = truth.apply(r.position);
    r.normal = truth.rotate(r.normal);
    r.x_axis = truth.rotate(r.x_axis);
    out.readings.push_back(r);
  }
  return out;
}

inline std::uint64_t mix(std::uint64_t h, std::uint64_t v) { return (h ^ v) * 0x100000001b3ULL; }
inline std::uint64_t mix(std::uint64_t h, double v) {
  std::uint64_t bits;
  std::memcpy(&bits, &v, sizeof bits);
  return mix(h, bits);
}
inline std::uint64_t mix(std::uint64_t h, const RigidPose& p) {
  for (int c = 0; c < 3; ++c) {
    h = mix(h, p.T[c]);
    for (int r = 0; r < 3; ++r) h = mix(h, p.R[c][r]);
  }
  return h;
}

inline constexpr std::uint64_t kDigestStart = 0xcbf29ce484222325ULL;

// Every number an estimate reports that the stages decide (the hypotheses' covariances and each object's too).
inline std::uint64_t digest(std::uint64_t h, const Estimate& e) {
  h = mix(mix(h, static_cast<std::uint64_t>(e.object)), e.p_unknown);
  for (double p : e.object_probability) h = mix(h, p);
  h = mix(mix(mix(h, e.pose), e.parabolic_pose), static_cast<std::uint64_t>(e.pose_refined));
  const auto add = [&](const PoseHypothesis& m) {
    h = mix(mix(mix(h, static_cast<std::uint64_t>(m.object)), m.pose), m.probability);
    for (double c : m.covariance) h = mix(h, c);
  };
  for (const PoseHypothesis& m : e.hypotheses) add(m);
  for (const PoseHypothesis& m : e.object_hypotheses) add(m);
  return h;
}

}  // namespace sva::bench
