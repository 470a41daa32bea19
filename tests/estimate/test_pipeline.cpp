// The estimate's stages called in order (host/src/estimate/pipeline.cpp): the calibration learns from what
// recognition computes, and the report takes the object the calibrated posterior names.
#include <catch2/catch.hpp>

#include <sva/base/rng.hpp>

#include <cmath>

#include "backends/vote_backend_factory.hpp"
#include "estimate/pipeline.hpp"
#include "map/map_access.hpp"
#include "map/surface_index.hpp"
#include "reading/observed_reading.hpp"
#include "recognition/bayes_filter.hpp"
#include "recognition/trained_map.hpp"

using namespace sva;
using namespace sva::test;

namespace {

// A calibration whose "none of these" reads the fit (a steep logit in its cost share), so that any difference in
// the fit the two paths compute shows in p_unknown.
Calibration fit_reading_calibration() {
  Calibration c;
  c.unknown.per_readings.push_back({-1.0, 0.5, 0.25, 4.0, 3.0});
  return c;
}

struct Session {
  const PairMap& map = MapAccess::pair_map(trained().map);
  PoseSpace space{paper_space(), static_cast<std::uint32_t>(map.objects.size())};
  std::unique_ptr<VoteBackend> backend = make_vote_backend(BackendKind::cpu, map, space, {}).backend;
  BayesFilter filter{map, space, {}, *backend};
  SurfaceIndex surface{map.readings, map.objects.size()};
  EstimateInput input() const { return {filter.belief(), filter.space(), filter.observed()}; }
};

}  // namespace

TEST_CASE("pipeline: the calibration's sessions read what recognition's calibrate stage reads") {
  Session s;
  const Calibration cal = fit_reading_calibration();
  const RefineSettings refine = refine_settings(s.space, 0);
  const PoseWeighting no_pose_prior;
  const RigidPose truth = random_pose(4101, 80.0);
  util::Rng rng(4102, 3);
  std::size_t fitted = 0;
  for (const Reading& r : readings_at(1, truth, rng, 12)) {
    s.filter.add(to_grid(s.space, describe_reading(s.map, r, "reading")));
    const EvidenceLevel level = estimate_evidence(s.input(), s.surface, refine);
    const EstimateRequest request{.top_k = 3,
                                  .pose_weighting = no_pose_prior,
                                  .surface = &s.surface,
                                  .refine = refine,
                                  .calibration = &cal,
                                  .unknown_prior = 0.2};
    const Estimate e = estimate_session(s.input(), s.map.objects, request);
    INFO("after " << s.filter.readings() << " readings");
    CHECK(level.readings == s.filter.readings());
    CHECK(e.p_unknown == cal.p_unknown(level, 0.2));
    if (level.fit_cost_share >= 0.0) ++fitted;
  }
  CHECK(fitted == 12 - (refine.min_readings - 1));  // the fit's share exists from the fine pose's start on
}

TEST_CASE("pipeline: without a surface the estimate is the candidates' parabolic pose, with no fit for the unknown") {
  Session s;
  const PoseWeighting no_pose_prior;
  const RigidPose truth = random_pose(4103, 80.0);
  util::Rng rng(4104, 3);
  for (const Reading& r : readings_at(2, truth, rng, 8))
    s.filter.add(to_grid(s.space, describe_reading(s.map, r, "reading")));
  const EstimateRequest bare{.top_k = 3, .pose_weighting = no_pose_prior};
  const Estimate e = estimate_session(s.input(), s.map.objects, bare);
  REQUIRE(e.pose_valid);
  CHECK_FALSE(e.pose_refined);
  CHECK(e.pose.T == e.parabolic_pose.T);
  CHECK(e.p_unknown == 0.0);  // no calibration: no "none of these"
  double sum = 0.0;
  for (double p : e.object_probability) sum += p;
  CHECK(sum == Approx(1.0));
  const EstimateRequest fitted{
      .top_k = 3, .pose_weighting = no_pose_prior, .surface = &s.surface, .refine = refine_settings(s.space, 0)};
  const Estimate f = estimate_session(s.input(), s.map.objects, fitted);
  CHECK(f.object == e.object);
  CHECK(f.pose_refined);
  CHECK(glm::length(f.pose.T - truth.T) <= glm::length(e.pose.T - truth.T) + 1e-9);
}
