// Distinct hypotheses: non-maximum suppression in pose space, each mode's mass and covariance, on hand-made
// beliefs whose answers are computed here independently, and on a recognizer.
#include <catch2/catch.hpp>

#include <sva/error.hpp>

#include <cmath>
#include <map>

#include "backends/cpu/belief.hpp"
#include "belief/belief_math.hpp"
#include "belief/object_mass.hpp"
#include "estimate/candidates.hpp"
#include "estimate/hypotheses.hpp"
#include "recognition/fixture.hpp"
#include "votes/neighbourhood_steps.hpp"

using namespace sva;
using namespace sva::test;

namespace {

constexpr double kUnits = belief_math::kUnitsPerBit;

BinIndex bin(std::uint32_t object, int tx, int ty, int tz, int rx, int ry, int rz) {
  BinIndex b;
  b.object = object;
  b.t[0] = tx;
  b.t[1] = ty;
  b.t[2] = tz;
  b.r[0] = rx;
  b.r[1] = ry;
  b.r[2] = rz;
  return b;
}

// A belief holding exactly `bits` of evidence per bin.
Belief belief_of(const PoseSpace& space, const std::map<std::uint64_t, double>& bits) {
  Belief b(space, 1e-6);
  std::vector<BinOffset> terms;
  for (const auto& [key, v] : bits) terms.push_back({key, static_cast<std::uint64_t>(v * kUnits)});
  b.add(BeliefTerms::grouped(terms), 1);
  return b;
}

}  // namespace

TEST_CASE("hypotheses: a weaker distant mode survives suppression, a stronger neighbour does not") {
  const PoseSpace space(paper_space(), 2);
  const BinIndex a = bin(0, 20, 20, 20, 4, 4, 4), b = bin(0, 23, 20, 20, 4, 4, 4), c = bin(1, 20, 20, 20, 4, 4, 4);
  std::map<std::uint64_t, double> bits;
  bits[space.pack(a)] = 40.0;
  BinIndex an = a;
  an.t[0] += 1;  // stronger than b, but a's neighbour: the same hypothesis
  bits[space.pack(an)] = 38.0;
  an.t[0] -= 2;
  bits[space.pack(an)] = 38.0;
  bits[space.pack(b)] = 36.0;
  bits[space.pack(c)] = 35.0;
  const Belief belief = belief_of(space, bits);
  const BeliefSummary s = belief.summarise();
  const HypothesisSet h = hypotheses(belief, space, s, 3, 1);
  REQUIRE(h.modes.size() == 3);
  CHECK(h.modes[0].key == space.pack(a));
  CHECK(h.modes[1].key == space.pack(b));
  CHECK(h.modes[2].key == space.pack(c));
  CHECK(h.modes[2].object == 1);
  // Mass: every bin's posterior, summed independently over a's 3^6 neighbourhood (two touched neighbours, the
  // rest at the baseline, whose weight the integer mass rounds to 0 as the object posterior does).
  const double z = total_mass(s, space);
  const double unit = std::ldexp(1.0, static_cast<int>(belief_math::mass_bits(space.bins_per_object()))) / z;
  const double expected_a = (1.0 + 2.0 * std::exp2(-2.0) + (729.0 - 3.0) * std::exp2(-40.0)) * unit;
  CHECK(h.modes[0].probability == Approx(expected_a).epsilon(1e-8));
  // The masses of all bins sum to 1: a's mode holds most of it.
  CHECK(h.modes[0].probability > 0.5);
  CHECK(h.modes[0].probability < 1.0);
  // Its spread is along x (the two neighbours), and symmetric about the bin: the parabola keeps the centre.
  const auto& cov = h.modes[0].covariance;
  const double tw = bin_width(paper_space());
  CHECK(cov[0] > cov[7]);
  CHECK(cov[7] == Approx(tw * tw / 12.0).epsilon(1e-6));
  CHECK(cov[0] == Approx(tw * tw / 12.0 + tw * tw * 2.0 * 0.25 / 1.5).epsilon(1e-6));
  for (int i = 0; i < 6; ++i)
    for (int j = 0; j < 6; ++j) CHECK(cov[i * 6 + j] == Approx(cov[j * 6 + i]));
  CHECK(glm::length(h.modes[0].pose.T - space.translation_centre(a)) < 1e-9);
  // Per object: each object's best bin.
  REQUIRE(h.per_object.size() == 2);
  CHECK(h.per_object_valid[0]);
  CHECK(h.per_object_valid[1]);
  CHECK(h.per_object[0].key == space.pack(a));
  CHECK(h.per_object[1].key == space.pack(c));
  // A radius that reaches b (3 bins away) folds it into a's hypothesis; 0 keeps a's neighbour apart.
  const HypothesisSet wide = hypotheses(belief, space, s, 3, 4);
  REQUIRE(wide.modes.size() == 2);
  CHECK(wide.modes[1].key == space.pack(c));
  const HypothesisSet narrow = hypotheses(belief, space, s, 2, 0);
  REQUIRE(narrow.modes.size() == 2);
  CHECK(space.unpack(narrow.modes[1].key).t[0] == a.t[0] - 1);  // the tie goes to the smaller key
}

TEST_CASE("hypotheses: planar modes wrap the angle and fix z and the out-of-plane rotations") {
  const PoseSpace space(letters_space(), 1);
  const int rb = letters_space().rotation_bins;
  const BinIndex a = bin(0, 10, 10, 0, 0, 0, 0);
  std::map<std::uint64_t, double> bits;
  bits[space.pack(a)] = 30.0;
  BinIndex wrapped = a;
  wrapped.r[2] = rb - 1;  // the angle's other side of -pi: a's neighbour
  bits[space.pack(wrapped)] = 29.0;
  const Belief belief = belief_of(space, bits);
  const HypothesisSet h = hypotheses(belief, space, belief.summarise(), 2, 1);
  REQUIRE(h.modes.size() == 1);  // the wrapped bin is suppressed, and no other bin is touched
  const auto& cov = h.modes[0].covariance;
  for (int k : {2, 3, 4})
    for (int j = 0; j < 6; ++j) {
      CHECK(cov[k * 6 + j] == 0.0);
      CHECK(cov[j * 6 + k] == 0.0);
    }
  const double rw = 2.0 * std::numbers::pi / rb;
  CHECK(cov[35] > rw * rw / 12.0);  // the wrapped neighbour spreads the angle
  // The parabola pulls the peak towards the wrapped neighbour (below a's centre angle).
  CHECK(so3::log(h.modes[0].pose.R).z < space.rotation_centre(a).z);
}

TEST_CASE("hypotheses: an untouched belief has none, and the covariance turns with the workspace") {
  const PoseSpace space(paper_space(), 2);
  const Belief empty(space, 1e-6);
  const HypothesisSet h = hypotheses(empty, space, empty.summarise(), 5, 1);
  CHECK(h.modes.empty());
  CHECK_FALSE(h.per_object_valid[0]);
  std::array<double, 36> c{};
  c[0] = 4.0;   // x
  c[21] = 0.5;  // rotation about X
  const std::array<double, 36> r = covariance_to_robot(c, so3::about_z(std::numbers::pi / 2));
  CHECK(r[7] == Approx(4.0));  // x of the grid is y of the robot
  CHECK(r[0] == Approx(0.0).margin(1e-12));
  CHECK(r[28] == Approx(0.5));  // so is the rotation about it
}

TEST_CASE("hypotheses: a bin two modes share counts for the stronger one only") {
  const PoseSpace space(paper_space(), 2);
  const BinIndex a = bin(0, 20, 20, 20, 4, 4, 4), d = bin(0, 20, 22, 20, 4, 4, 4);
  BinIndex between = a;
  between.t[1] = 21;  // within one step of both
  const Belief belief = belief_of(space, {{space.pack(a), 40.0}, {space.pack(d), 39.0}, {space.pack(between), 38.0}});
  const BeliefSummary s = belief.summarise();
  const HypothesisSet h = hypotheses(belief, space, s, 2, 1);
  REQUIRE(h.modes.size() == 2);
  CHECK(h.modes[1].key == space.pack(d));
  const double object = object_probability(s, space)[0];
  CHECK(h.modes[0].probability + h.modes[1].probability <= object * (1.0 + 1e-12));
  // a's mode holds the shared bin: d's mass is d's bin and the baseline (its 729 bins less the 243 a claimed).
  const double z = total_mass(s, space);
  const double unit = std::ldexp(1.0, static_cast<int>(belief_math::mass_bits(space.bins_per_object()))) / z;
  CHECK(h.modes[1].probability == Approx((0.5 + (729.0 - 243.0 - 1.0) * std::exp2(-40.0)) * unit).epsilon(1e-8));
}

namespace {

// Every bin of c's object within `radius` steps of it, by within_steps over a box of the grid about it (the
// planar angle's whole circle).
template <class Fn>
void for_each_within(const PoseSpace& space, const BinIndex& c, int radius, Fn&& fn) {
  const PoseSpaceSpec& spec = space.spec();
  int lo[6], hi[6];
  for (int a = 0; a < 6; ++a) {
    const int at = a < 3 ? c.t[a] : c.r[a - 3], bins = a < 3 ? spec.translation_bins : spec.rotation_bins;
    const bool fixed = space.planar() && (a == 2 || a == 3 || a == 4), circle = space.planar() && a == 5;
    lo[a] = fixed ? at : circle ? 0 : std::max(0, at - radius);
    hi[a] = fixed ? at : circle ? bins - 1 : std::min(bins - 1, at + radius);
  }
  for (int tx = lo[0]; tx <= hi[0]; ++tx)
    for (int ty = lo[1]; ty <= hi[1]; ++ty)
      for (int tz = lo[2]; tz <= hi[2]; ++tz)
        for (int rx = lo[3]; rx <= hi[3]; ++rx)
          for (int ry = lo[4]; ry <= hi[4]; ++ry)
            for (int rz = lo[5]; rz <= hi[5]; ++rz) {
              const BinIndex b = bin(c.object, tx, ty, tz, rx, ry, rz);
              if (within_steps(b, c, space, radius)) fn(b);
            }
}

// A mode's mass-weighted spread computed here bin by bin: every bin within `radius` steps of the centre, weighed
// by 2^(its bits - the centre's), its rotation log(R_bin R_c^T).
std::array<double, 36> spread_of(const PoseSpace& space, const Belief& belief, const BinIndex& c, int radius) {
  const PoseSpaceSpec& spec = space.spec();
  const glm::dmat3 r0t = glm::transpose(so3::exp(space.rotation_centre(c)));
  const auto bits_at = [&](const BinIndex& b) {
    return belief_math::units_to_bits(belief.offsets(std::vector{space.pack(b)})[0]);
  };
  const double centre_bits = bits_at(c);
  std::vector<std::array<double, 6>> x;
  std::vector<double> w;
  for_each_within(space, c, radius, [&](const BinIndex& b) {
    const glm::dvec3 dt = space.translation_centre(b) - space.translation_centre(c);
    const glm::dvec3 dr = so3::log(so3::exp(space.rotation_centre(b)) * r0t);
    x.push_back({dt.x, dt.y, dt.z, dr.x, dr.y, dr.z});
    w.push_back(std::exp2(bits_at(b) - centre_bits));
  });
  double sum = 0.0;
  std::array<double, 6> mean{};
  for (std::size_t i = 0; i < w.size(); ++i) {
    sum += w[i];
    for (int a = 0; a < 6; ++a) mean[a] += w[i] * x[i][a];
  }
  for (double& m : mean) m /= sum;
  std::array<double, 36> cov{};
  for (std::size_t i = 0; i < w.size(); ++i)
    for (int a = 0; a < 6; ++a)
      for (int b = 0; b < 6; ++b) cov[a * 6 + b] += w[i] * (x[i][a] - mean[a]) * (x[i][b] - mean[b]) / sum;
  const double tw = (spec.translation_max_mm - spec.translation_min_mm) / spec.translation_bins;
  const double rw = 2.0 * std::numbers::pi / spec.rotation_bins;
  for (int a = 0; a < 6; ++a) {
    if (space.planar() && (a == 2 || a == 3 || a == 4))
      for (int b = 0; b < 6; ++b) cov[a * 6 + b] = cov[b * 6 + a] = 0.0;
    else
      cov[a * 6 + a] += (a < 3 ? tw * tw : rw * rw) / 12.0;
  }
  return cov;
}

// A belief with random evidence (0-6 bits under the centre's 20) on every bin within 2 steps of `c`.
Belief rough_belief(const PoseSpace& space, const BinIndex& c, std::uint64_t seed) {
  util::Rng rng(seed);
  std::map<std::uint64_t, double> bits;
  for_each_within(space, c, 2, [&](const BinIndex& b) { bits[space.pack(b)] = 14.0 + 6.0 * rng.uniform(0.0, 1.0); });
  bits[space.pack(c)] = 20.0;
  return belief_of(space, bits);
}

// The one mode of a rough belief about c, at radius 2: centred on c, its covariance the spread computed bin by bin.
void check_spread(const PoseSpace& space, const BinIndex& c, std::uint64_t seed) {
  const Belief belief = rough_belief(space, c, seed);
  const HypothesisSet h = hypotheses(belief, space, belief.summarise(), 1, 2);
  REQUIRE(h.modes.size() == 1);
  REQUIRE(h.modes[0].key == space.pack(c));
  const std::array<double, 36> want = spread_of(space, belief, c, 2);
  for (int i = 0; i < 36; ++i) CHECK(h.modes[0].covariance[i] == Approx(want[i]).epsilon(1e-9).margin(1e-15));
  CHECK(h.modes[0].covariance[35] > 0.0);
  // Symmetric bit for bit, in the grid's frame and turned into a tilted workspace's.
  const std::array<double, 36> robot = covariance_to_robot(h.modes[0].covariance, so3::exp({0.3, -0.7, 1.1}));
  for (int a = 0; a < 6; ++a)
    for (int b = 0; b < a; ++b) {
      INFO("entry " << a << ", " << b);
      CHECK(h.modes[0].covariance[a * 6 + b] == h.modes[0].covariance[b * 6 + a]);
      CHECK(robot[a * 6 + b] == robot[b * 6 + a]);
    }
}

}  // namespace

TEST_CASE("hypotheses: a mode's covariance is its bins' weighted spread, round the planar circle too") {
  // Radius 2 on a planar circle of 4 and 5 bins (steps -1..2 and -2..2: every angle once) and on the paper's 3-D
  // grid at an edge: each rotation bin's small rotation must be its own, wherever the neighbourhood wraps.
  for (int rotation_bins : {4, 5, 9}) {
    PoseSpaceSpec spec = letters_space();
    spec.rotation_bins = rotation_bins;
    const PoseSpace space(spec, 1);
    for (int r : {0, rotation_bins - 1}) {
      INFO("rotation bins " << rotation_bins << ", centre angle bin " << r);
      check_spread(space, bin(0, 10, 0, 0, 0, 0, r), 11 + static_cast<std::uint64_t>(rotation_bins * 7 + r));
    }
  }
  // At the grid's edges: the neighbourhood is cut.
  check_spread(PoseSpace(paper_space(), 1), bin(0, 0, 20, 49, 0, 4, 8), 5);
}
