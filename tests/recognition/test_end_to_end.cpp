// Small synthetic end-to-end recognition through the Bayes filter and the CPU
// reference backend, in the paper's 3-D pose space and in the letters' planar one.
#include <catch2/catch.hpp>

#include <cstdio>

#include "fixture.hpp"

using namespace sva;
using namespace sva::test;

namespace {

struct RunResult {
  Candidates estimate;
  RigidPose truth;
};

RunResult run(const World& w, const PoseSpaceSpec& spec, std::uint32_t object, const RigidPose& truth, int readings,
              std::uint64_t seed) {
  PoseSpace space(spec, static_cast<std::uint32_t>(w.map->objects.size()));
  auto backend = make_cpu_vote_backend(*w.map, space, {});
  BayesFilter filter(*w.map, space, {}, *backend);
  util::Rng rng(seed, 5);
  for (int i = 0; i < readings; ++i) {
    const auto& pts = w.objects[object];
    filter.add(observe(pts[rng.below(pts.size())], truth));
  }
  return {candidates(filter, 5), truth};
}

// A planar world like the raised letters: points on z = 0, normals +z.
World letters_world(int objects) {
  WorldSpec ws;
  ws.planar = true;
  ws.objects = objects;
  ws.points = 60;
  ws.dist_min = 3.0;
  ws.dist_max = 20.0;
  ws.dist_bins = 17;
  return make_world(ws);
}

}  // namespace

TEST_CASE("synthetic 3-D objects are recognised and localised") {
  WorldSpec ws;
  const World w = make_world(ws);
  const PoseSpaceSpec spec = paper_space();
  int correct = 0;
  for (std::uint32_t object = 0; object < 3; ++object) {
    const RigidPose truth = random_pose(100 + object, 120.0);
    const RunResult r = run(w, spec, object, truth, 12, 7 + object);
    INFO("object " << object << " p=" << r.estimate.object_probability[object]);
    if (r.estimate.object == object) {
      ++correct;
      REQUIRE(r.estimate.pose_valid);
      const double terr = glm::length(r.estimate.pose.T - truth.T);
      const double rerr = angle_between(r.estimate.pose.R, truth.R);
      std::printf("object %u: translation error %.2f mm, angle error %.3f rad (p = %.3f)\n", object, terr, rerr,
                  r.estimate.object_probability[object]);
      CHECK(terr < 1.5 * bin_width(spec));
      CHECK(rerr < 0.6);
    }
  }
  CHECK(correct == 3);
}

TEST_CASE("synthetic planar letters are recognised and localised") {
  const World w = letters_world(3);
  const PoseSpaceSpec spec = letters_space();
  for (std::uint32_t object = 0; object < 3; ++object) {
    const RigidPose truth = random_pose(300 + object, 8.0, true);
    const RunResult r = run(w, spec, object, truth, 15, 17 + object);
    INFO("object " << object);
    REQUIRE(r.estimate.object == object);
    REQUIRE(r.estimate.pose_valid);
    const double terr = glm::length(r.estimate.pose.T - truth.T);
    const double rerr = angle_between(r.estimate.pose.R, truth.R);
    std::printf("letter %u: translation error %.2f mm, angle error %.3f rad\n", object, terr, rerr);
    CHECK(terr < 1.5 * bin_width(spec));
    CHECK(rerr < 2.0 * std::numbers::pi / spec.rotation_bins);
    CHECK(std::fabs(r.estimate.pose.T.z) < 1e-9);
  }
}

TEST_CASE("the refined pose beats the centre of the best bin") {
  const World w = letters_world(2);
  const PoseSpaceSpec spec = letters_space();
  double refined = 0.0, centre = 0.0;
  for (std::uint32_t trial = 0; trial < 8; ++trial) {
    const std::uint32_t object = trial % 2;
    const RigidPose truth = random_pose(700 + trial, 8.0, true);
    const RunResult r = run(w, spec, object, truth, 15, 40 + trial);
    REQUIRE(r.estimate.pose_valid);
    refined += glm::length(r.estimate.pose.T - truth.T);
    centre += glm::length(r.estimate.bin_pose.T - truth.T);
  }
  std::printf("mean translation error: refined %.3f mm, bin centre %.3f mm\n", refined / 8, centre / 8);
  CHECK(refined < 0.95 * centre);
}
