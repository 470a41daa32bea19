// The CPU reference's lane-parallel vote (backends/cpu/sample_votes.cpp) against the shared text's one-sample vote
// (sva_vote_math.h, the GPU's text): every sample's pose bin key, fixed-point mass and inside flag, bit for bit, on
// a synthetic world's pairs under random poses, in spatial and planar spaces, and on the hard cases: beta-hat at
// +-pi, translations on bin edges, rotations of pi (the Rodrigues sign rule), anti-parallel and degenerate axes,
// whole-circle plans, poses outside the space and planar samples at the tilt limit.
#include <catch2/catch.hpp>

#include <sva/base/rng.hpp>

#include <cmath>
#include <numbers>

#include "backends/cpu/sample_votes.hpp"
#include "recognition/fixture.hpp"
#include "votes/vote_math.hpp"
#include "votes/vote_patches.hpp"

using namespace sva;
using namespace sva::test;
namespace vm = sva::vote_math;

namespace {

// What the comparisons covered, so that a test cannot pass by comparing nothing.
struct Tally {
  long samples = 0, inside = 0, outside = 0, circles = 0, matches = 0, mismatches = 0;
};

// One match through both paths; every sample compared.
void compare(const vm::SvaAlignment& al, const vm::SvaPoseGrid& grid, std::uint32_t object, float likelihood,
             Tally* tally) {
  const vm::SvaBetaPlan plan = vm::sva_beta_plan(al, grid);
  cpu::SampleVotes lanes;
  cpu::sample_votes(al, plan, grid, object, likelihood, &lanes);
  REQUIRE(lanes.n == plan.n);
  if (plan.n == 0) return;
  ++tally->matches;
  if (plan.circle) ++tally->circles;
  float weight[SVA_MAX_BETA_SAMPLES];
  const float scale = vm::sva_vote_scale(likelihood, vm::sva_beta_weights(plan, weight));
  for (int s = 0; s < plan.n; ++s) {
    const vm::SvaVote one = vm::sva_vote(al, plan, grid, object, weight[s] * scale, s);
    ++tally->samples;
    (one.inside ? tally->inside : tally->outside) += 1;
    const bool same =
        lanes.inside[s] == one.inside && (!one.inside || (lanes.key[s] == one.key && lanes.mass[s] == one.mass));
    if (!same) {
      ++tally->mismatches;
      if (tally->mismatches <= 5)
        UNSCOPED_INFO("sample " << s << " of " << plan.n << ": key " << lanes.key[s] << " vs " << one.key << ", mass "
                                << lanes.mass[s] << " vs " << one.mass << ", inside " << lanes.inside[s] << " vs "
                                << one.inside << ", beta-hat " << al.beta_hat);
    }
  }
}

glm::dvec3 unit(util::Rng& rng) {
  for (;;) {
    const glm::dvec3 v(rng.uniform(-1.0, 1.0), rng.uniform(-1.0, 1.0), rng.uniform(-1.0, 1.0));
    const double l = glm::length(v);
    if (l > 0.1 && l <= 1.0) return v / l;
  }
}

// Every pair of a synthetic world's object, seen under a random pose with a little noise, aligned to map pairs
// of the same object (the pairs a session meets).
void world_pairs(const WorldSpec& spec, const PoseSpaceSpec& space, Tally* tally) {
  const World world = make_world(spec);
  const vm::SvaPoseGrid grid = grid_of(space);
  util::Rng rng(spec.seed, 99);
  for (std::size_t o = 0; o < world.objects.size(); ++o) {
    const RigidPose pose = random_pose(spec.seed + o, 120.0, spec.planar);
    const auto& pts = world.objects[o];
    for (int trial = 0; trial < 60; ++trial) {
      const std::size_t i = rng.below(pts.size()), j = rng.below(pts.size());
      const std::size_t k = rng.below(pts.size()), l = rng.below(pts.size());
      const auto seen = [&](const WorldPoint& w) {
        const glm::dvec3 noise(rng.uniform(-0.5, 0.5), rng.uniform(-0.5, 0.5),
                               spec.planar ? 0.0 : rng.uniform(-0.5, 0.5));
        return patch(pose.apply(w.p) + noise, pose.R * w.n, static_cast<float>(rng.uniform(0.0, 1.0)));
      };
      const vm::SvaAlignment al =
          vm::sva_align(seen(pts[i]), seen(pts[j]), patch(pts[k].p, pts[k].n), patch(pts[l].p, pts[l].n));
      compare(al, grid, static_cast<std::uint32_t>(o), static_cast<float>(rng.uniform(1e-6, 1.0)), tally);
    }
  }
}

}  // namespace

TEST_CASE("lane-parallel votes equal sva_vote bit for bit on a world's pairs, spatial and planar") {
  Tally spatial, planar;
  world_pairs(WorldSpec{}, paper_space(), &spatial);
  world_pairs(planar_spec(), letters_space(), &planar);
  for (const Tally* t : {&spatial, &planar}) {
    CHECK(t->mismatches == 0);
    CHECK(t->matches > 100);
    CHECK(t->samples > 1000);
    CHECK(t->inside > 0);
  }
}

TEST_CASE("lane-parallel votes equal sva_vote bit for bit on random and degenerate alignments") {
  util::Rng rng(7, 1);
  const vm::SvaPoseGrid spatial = grid_of(paper_space());
  const vm::SvaPoseGrid planar = grid_of(letters_space());
  Tally tally;
  for (int t = 0; t < 4000; ++t) {
    // Positions across and beyond the space (outside votes), normals at random, confidences including 0 (edge
    // contacts: whole-circle plans), and every 7th pair with coincident or mirrored ends.
    const double range = t % 3 == 0 ? 400.0 : 150.0;
    const auto point = [&] {
      return glm::dvec3(rng.uniform(-range, range), rng.uniform(-range, range), rng.uniform(-range, range));
    };
    const glm::dvec3 a1 = point(), b1 = point(), a2 = point();
    glm::dvec3 b2 = point();
    if (t % 7 == 0) b2 = a2 + (b1 - a1) * -1.0;  // anti-parallel axes: the half-turn branch of R1
    const float c1 = t % 5 == 0 ? 0.0f : static_cast<float>(rng.uniform(0.0, 1.0));
    const float c2 = t % 11 == 0 ? 0.0f : static_cast<float>(rng.uniform(0.0, 1.0));
    const vm::SvaAlignment al = vm::sva_align(patch(a1, unit(rng), c1), patch(b1, unit(rng), c1),
                                              patch(a2, unit(rng), c2), patch(b2, unit(rng), c2));
    compare(al, t % 2 ? spatial : planar, static_cast<std::uint32_t>(t % 200),
            static_cast<float>(rng.uniform(0.0, 1.0)), &tally);
  }
  CHECK(tally.mismatches == 0);
  CHECK(tally.circles > 100);
  CHECK(tally.outside > 1000);
  CHECK(tally.inside > 1000);
}

TEST_CASE("lane-parallel votes equal sva_vote bit for bit at beta = +-pi, on bin edges and at half turns") {
  const vm::SvaPoseGrid grid = grid_of(paper_space());  // 8 mm bins from -200 mm
  Tally tally;
  // Map pair along x; the observed pair along x too (R1 = identity), its midpoint placed so that the mean sample's
  // translation falls exactly on a bin edge, and its normals turned by angles up to and across pi about the axis
  // (beta-hat at +-pi and the Rodrigues vector's sign rule at a half turn).
  const glm::dvec3 n(0.0, 1.0, 0.0);
  for (int edge = -3; edge <= 3; ++edge)
    for (int a = 0; a <= 32; ++a) {
      const double angle = std::numbers::pi * (a / 16.0 - 1.0) + (a % 2 ? 1e-7 : 0.0);
      const glm::dvec3 m(0.0, std::cos(angle), std::sin(angle));
      const glm::dvec3 c(8.0 * edge, 8.0 * edge, 0.0);
      for (float conf : {1.0f, 0.3f, 0.02f}) {
        const vm::SvaAlignment al =
            vm::sva_align(patch(c + glm::dvec3(-10, 0, 0), n, conf), patch(c + glm::dvec3(10, 0, 0), n, conf),
                          patch({-10, 0, 0}, m, conf), patch({10, 0, 0}, m, conf));
        compare(al, grid, 3, 0.75f, &tally);
      }
    }
  // A planar space's tilt limit: map pairs tilted about x by angles around the limit (about 0.5 rad).
  const vm::SvaPoseGrid planar = grid_of(letters_space());
  for (int a = -40; a <= 40; ++a) {
    const double tilt = 0.5 + a * 1e-3;
    const glm::dvec3 axis2(std::cos(tilt), 0.0, std::sin(tilt));
    const vm::SvaAlignment al =
        vm::sva_align(patch({-10, 0, 0}, {0, 0, 1}, 0.5f), patch({10, 0, 0}, {0, 0, 1}, 0.5f),
                      patch(-10.0 * axis2, {0, 0, 1}, 0.5f), patch(10.0 * axis2, {0, 0, 1}, 0.5f));
    compare(al, planar, 1, 0.5f, &tally);
  }
  CHECK(tally.mismatches == 0);
  CHECK(tally.matches > 600);
  CHECK(tally.outside > 0);
}
