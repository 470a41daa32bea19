// Distinct hypotheses read from a device-resident belief equal the CPU reference's, bit for bit: keys, masses,
// covariances and poses, spatial and planar, at every suppression radius.
#include <catch2/catch.hpp>

#include "estimate/hypotheses.hpp"
#include "recognition/fixture.hpp"
#include "vk_test_support.hpp"

using namespace sva;

namespace {

void require_same(const ModeHypothesis& a, const ModeHypothesis& b) {
  CHECK(a.key == b.key);
  CHECK(a.probability == b.probability);
  CHECK(a.covariance == b.covariance);
  for (int k = 0; k < 3; ++k) {
    CHECK(a.pose.T[k] == b.pose.T[k]);
    for (int j = 0; j < 3; ++j) CHECK(a.pose.R[k][j] == b.pose.R[k][j]);
  }
}

void twin(const test::WorldSpec& spec, const PoseSpaceSpec& space_spec, double t_range) {
  auto w = test::make_world(spec);
  PoseSpace space(space_spec, static_cast<std::uint32_t>(spec.objects));
  auto gpu = test::vulkan_backend_or_skip(*w.map, space, {});
  auto cpu = make_cpu_vote_backend(*w.map, space, {});
  BayesFilter fc(*w.map, space, {}, *cpu), fg(*w.map, space, {}, *gpu);
  const RigidPose truth = test::random_pose(811, t_range, spec.planar);
  for (int r = 0; r < 7; ++r) {
    const ObservedReading o =
        test::observe(w.objects[1][static_cast<std::size_t>(r * 11 + 3) % w.objects[1].size()], truth);
    fc.add(o);
    fg.add(o);
  }
  for (int radius = 0; radius <= 2; ++radius) {
    INFO("radius " << radius);
    const HypothesisSet a = hypotheses(fc.belief(), space, fc.belief().summarise(), 4, radius);
    const HypothesisSet b = hypotheses(fg.belief(), space, fg.belief().summarise(), 4, radius);
    REQUIRE(a.modes.size() == b.modes.size());
    CHECK(!a.modes.empty());
    for (std::size_t i = 0; i < a.modes.size(); ++i) require_same(a.modes[i], b.modes[i]);
    CHECK(a.per_object_valid == b.per_object_valid);
    for (std::size_t o = 0; o < a.per_object.size(); ++o)
      if (a.per_object_valid[o]) require_same(a.per_object[o], b.per_object[o]);
  }
}

}  // namespace

TEST_CASE("GPU hypotheses: distinct modes, masses and covariances equal the CPU reference's (spatial)") {
  twin(test::WorldSpec{}, test::paper_space(), 120.0);
}

TEST_CASE("GPU hypotheses: distinct modes, masses and covariances equal the CPU reference's (planar)") {
  twin(test::planar_spec(), test::letters_space(), 6.0);
}
