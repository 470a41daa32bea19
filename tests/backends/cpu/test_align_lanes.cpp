// The CPU reference's block alignment (backends/cpu/align_lanes.cpp) against the shared text's one-match alignment
// and beta plan (sva_align, sva_beta_plan: the GPU's text): every field of every match's alignment and plan, bit for
// bit, on a synthetic world's pairs
// under random poses, and on the hard cases: coincident ends (no axis: the invalid alignment), anti-parallel axes
// (the half-turn branch of R1), NaN and zero normals, confidences outside [0, 1], and blocks of every fill.
#include <catch2/catch.hpp>

#include <sva/base/rng.hpp>

#include <bit>
#include <cmath>
#include <limits>
#include <vector>

#include "backends/cpu/align_lanes.hpp"
#include "recognition/fixture.hpp"
#include "votes/vote_math.hpp"
#include "votes/vote_patches.hpp"

using namespace sva;
using namespace sva::test;
namespace vm = sva::vote_math;

namespace {

// What the comparisons covered, so that a test cannot pass by comparing nothing.
struct Tally {
  long matches = 0, valid = 0, invalid = 0, half_turns = 0, circles = 0, mismatches = 0;
};

bool same(float a, float b) { return std::bit_cast<std::uint32_t>(a) == std::bit_cast<std::uint32_t>(b); }

bool same(const vm::SvaAlignment& a, const vm::SvaAlignment& b) {
  const float fa[] = {a.q1.x,    a.q1.y,    a.q1.z,      a.q1.w,      a.axis.x,    a.axis.y,   a.axis.z,     a.c_obs.x,
                      a.c_obs.y, a.c_obs.z, a.c_map_r.x, a.c_map_r.y, a.c_map_r.z, a.beta_hat, a.align_conf, a.sigma};
  const float fb[] = {b.q1.x,    b.q1.y,    b.q1.z,      b.q1.w,      b.axis.x,    b.axis.y,   b.axis.z,     b.c_obs.x,
                      b.c_obs.y, b.c_obs.z, b.c_map_r.x, b.c_map_r.y, b.c_map_r.z, b.beta_hat, b.align_conf, b.sigma};
  for (std::size_t i = 0; i < std::size(fa); ++i)
    if (!same(fa[i], fb[i])) return false;
  return a.valid == b.valid;
}

bool same(const vm::SvaBetaPlan& a, const vm::SvaBetaPlan& b) {
  return a.n == b.n && a.circle == b.circle && same(a.unit, b.unit) && same(a.inv_sigma, b.inv_sigma);
}

// The observed pair (a1, b1) against map pairs (ra[i], rb[i]) of `patches`, in blocks of `fill` matches.
void compare(const vm::SvaPatch& a1, const vm::SvaPatch& b1, const std::vector<vm::SvaPatch>& patches,
             const std::vector<std::pair<std::uint32_t, std::uint32_t>>& pairs, const vm::SvaPoseGrid& grid, int fill,
             Tally* tally) {
  for (std::size_t first = 0; first < pairs.size(); first += static_cast<std::size_t>(fill)) {
    cpu::MatchLanes block;
    for (std::size_t i = first; i < pairs.size() && block.n < fill; ++i, ++block.n) {
      block.ra[block.n] = pairs[i].first;
      block.rb[block.n] = pairs[i].second;
    }
    vm::SvaAlignment lanes[cpu::MatchLanes::kLanes];
    vm::SvaBetaPlan plans[cpu::MatchLanes::kLanes];
    cpu::align_lanes(cpu::ObservedLanes(a1, b1), patches, grid, block, lanes, plans);
    for (int l = 0; l < block.n; ++l) {
      const vm::SvaAlignment one = vm::sva_align(a1, b1, patches[block.ra[l]], patches[block.rb[l]]);
      const vm::SvaBetaPlan plan = vm::sva_beta_plan(one, grid);
      ++tally->matches;
      (one.valid ? tally->valid : tally->invalid) += 1;
      if (one.valid && one.q1.w == 0.0f) ++tally->half_turns;
      if (plan.circle) ++tally->circles;
      if (!same(lanes[l], one) || !same(plans[l], plan)) {
        ++tally->mismatches;
        if (tally->mismatches <= 5)
          UNSCOPED_INFO("match " << first + static_cast<std::size_t>(l) << ": beta-hat " << lanes[l].beta_hat << " vs "
                                 << one.beta_hat << ", sigma " << lanes[l].sigma << " vs " << one.sigma << ", valid "
                                 << lanes[l].valid << " vs " << one.valid << ", samples " << plans[l].n << " vs "
                                 << plan.n);
      }
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

}  // namespace

TEST_CASE("block alignments and plans equal sva_align's and sva_beta_plan's bits on a world's pairs") {
  const WorldSpec spec;
  const World world = make_world(spec);
  const vm::SvaPoseGrid spatial = grid_of(paper_space()), planar = grid_of(letters_space());
  util::Rng rng(spec.seed, 17);
  Tally tally;
  for (std::size_t o = 0; o < world.objects.size(); ++o) {
    const auto& pts = world.objects[o];
    std::vector<vm::SvaPatch> map;
    for (const WorldPoint& w : pts) map.push_back(patch(w.p, w.n, static_cast<float>(rng.uniform(0.0, 1.0))));
    const RigidPose pose = random_pose(spec.seed + o, 120.0, false);
    for (int trial = 0; trial < 12; ++trial) {
      const auto seen = [&](const WorldPoint& w) {
        const glm::dvec3 noise(rng.uniform(-0.5, 0.5), rng.uniform(-0.5, 0.5), rng.uniform(-0.5, 0.5));
        return patch(pose.apply(w.p) + noise, pose.R * w.n, static_cast<float>(rng.uniform(0.0, 1.0)));
      };
      const vm::SvaPatch a1 = seen(pts[rng.below(pts.size())]), b1 = seen(pts[rng.below(pts.size())]);
      const auto same_reading = static_cast<std::uint32_t>(rng.below(map.size()));
      std::vector<std::pair<std::uint32_t, std::uint32_t>> pairs = {{same_reading, same_reading}};
      for (int m = 0; m < 40; ++m)
        pairs.emplace_back(static_cast<std::uint32_t>(rng.below(map.size())),
                           static_cast<std::uint32_t>(rng.below(map.size())));
      compare(a1, b1, map, pairs, trial % 2 ? spatial : planar, 1 + trial % cpu::MatchLanes::kLanes, &tally);
    }
  }
  CHECK(tally.mismatches == 0);
  CHECK(tally.valid > 1000);
  CHECK(tally.invalid > 0);  // a map pair of one reading twice: coincident ends
  CHECK(tally.circles > 0);  // confidences near 0: the whole circle
}

TEST_CASE(
    "block alignments and plans equal sva_align's and sva_beta_plan's bits on coincident, anti-parallel and "
    "broken patches") {
  util::Rng rng(11, 3);
  const vm::SvaPoseGrid spatial = grid_of(paper_space()), planar = grid_of(letters_space());
  const float nan = std::numeric_limits<float>::quiet_NaN();
  Tally tally;
  for (int t = 0; t < 300; ++t) {
    const glm::dvec3 a1(rng.uniform(-100, 100), rng.uniform(-100, 100), rng.uniform(-100, 100));
    const glm::dvec3 b1 = a1 + 60.0 * unit(rng);
    // Map patches: a pair along the observed axis reversed (anti-parallel: the half turn), one with both ends at one
    // point (no axis), one closer than the separation floor, and ordinary ones; normals at random, zero or NaN, and
    // confidences outside [0, 1] (clamped by sva_align).
    std::vector<vm::SvaPatch> map;
    const glm::dvec3 a2(rng.uniform(-50, 50), rng.uniform(-50, 50), rng.uniform(-50, 50));
    const auto conf = [&] { return static_cast<float>(rng.uniform(-0.5, 1.5)); };
    map.push_back(patch(a2, unit(rng), conf()));
    map.push_back(patch(a2 - (b1 - a1), unit(rng), conf()));  // (map[0], map[1]): anti-parallel to the observed axis
    map.push_back(patch(a2 + glm::dvec3(1e-4, 0, 0), unit(rng)));  // with map[0]: closer than 1e-3 mm
    vm::SvaPatch broken = patch(a2 + 30.0 * unit(rng), unit(rng), conf());
    broken.n = t % 2 ? vm::vec3(nan, 0.0f, 0.0f) : vm::vec3(0.0f, 0.0f, 0.0f);
    map.push_back(broken);
    for (int k = 0; k < 6; ++k) map.push_back(patch(a2 + 80.0 * unit(rng), unit(rng), conf()));
    std::vector<std::pair<std::uint32_t, std::uint32_t>> pairs = {{0, 1}, {0, 0}, {0, 2}, {0, 3}, {3, 4}};
    for (int m = 0; m < 11; ++m)
      pairs.emplace_back(static_cast<std::uint32_t>(rng.below(map.size())),
                         static_cast<std::uint32_t>(rng.below(map.size())));
    const float c1 = t % 3 == 0 ? nan : static_cast<float>(rng.uniform(-0.5, 1.5));
    compare(patch(a1, unit(rng), c1), patch(b1, unit(rng), c1), map, pairs, t % 2 ? spatial : planar,
            1 + t % cpu::MatchLanes::kLanes, &tally);
  }
  CHECK(tally.mismatches == 0);
  CHECK(tally.invalid >= 600);
  CHECK(tally.half_turns >= 100);
  CHECK(tally.circles >= 100);
  CHECK(tally.valid > 2000);
}
