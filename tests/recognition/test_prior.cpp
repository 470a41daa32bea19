// Priors at estimate time: a Gaussian pose prior beside the object prior (what it moves, what it leaves, the same on
// the CPU reference and on Vulkan), and a reset that keeps the belief table's allocation for the next session.
#include <catch2/catch.hpp>

#include <sva/engine.hpp>
#include <sva/error.hpp>
#include <sva/recognizer.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <memory>

#include "backends/cpu/belief.hpp"
#include "backends/vote_backend_factory.hpp"
#include "estimate/candidates.hpp"
#include "fixture.hpp"
#include "map/map_access.hpp"
#include "reading/observed_reading.hpp"
#include "test_support.hpp"
#include "trained_map.hpp"

using namespace sva;
using namespace sva::test;

namespace {

// The CPU reference, and Vulkan (lavapipe in the suite) where a device can be made.
std::vector<BackendKind> backends() {
  std::vector<BackendKind> out{BackendKind::cpu};
  try {
    EngineOptions eo;
    eo.backend = BackendKind::vulkan;
    Engine probe(trained().map, eo);
    out.push_back(BackendKind::vulkan);
  } catch (const Error& e) {
    WARN("no Vulkan device, the CPU reference only: " << e.what());
  }
  return out;
}

std::vector<Reading> readings_of(std::uint32_t object, const RigidPose& truth, std::uint64_t seed, int count) {
  return readings_at(object, truth, util::Rng(seed, 3), count);
}

Recognizer recognizer_on(BackendKind kind) {
  RecognizerOptions o;
  o.backend = kind;
  o.refine_pose = false;  // the histogram's pose: what the prior moves (the fine pose then starts from it)
  return Recognizer(trained().map, paper_space(), o);
}

// A bin of the best object among the best bins the estimate reads (kPosePriorCandidates), more than a bin away
// from the best one in translation: the prior's target.
const Hypothesis* other_bin(const Estimate& e) {
  for (std::size_t i = 1; i < e.top.size(); ++i)
    if (e.top[i].object == e.object && glm::length(e.top[i].pose.T - e.bin_pose.T) > 1.5 * bin_width(paper_space()))
      return &e.top[i];
  return nullptr;
}
// The result points into the estimate: a temporary one would be freed before the pointer is read.
const Hypothesis* other_bin(const Estimate&&) = delete;

PosePrior gaussian_at(const RigidPose& pose, double sigma_mm, double sigma_rad) {
  PosePrior p;
  p.position = pose.T;
  p.position_sigma_mm = sigma_mm;
  p.has_rotation = true;
  p.rotation = pose.R;
  p.rotation_sigma_rad = sigma_rad;
  return p;
}

}  // namespace

TEST_CASE("Pose prior: it moves the best pose and the hypotheses to the mode it favours, not the object posterior") {
  const RigidPose truth = random_pose(700, 100.0);
  const std::vector<Reading> readings = readings_of(1, truth, 701, 3);
  std::vector<Estimate> with_prior;
  for (BackendKind kind : backends()) {
    INFO("backend " << backend_kind_name(kind));
    Recognizer plain = recognizer_on(kind), camera = recognizer_on(kind), vague = recognizer_on(kind);
    for (const Reading& r : readings) plain.add_reading(r), camera.add_reading(r), vague.add_reading(r);
    const Estimate p = plain.estimate(3);
    REQUIRE(p.pose_valid);
    const Estimate candidates = plain.estimate(kPosePriorCandidates);
    const Hypothesis* target = other_bin(candidates);
    REQUIRE(target != nullptr);               // three readings leave the belief wide
    const RigidPose favoured = target->pose;  // a bin centre

    Prior prior;
    prior.object_pose.resize(3);
    prior.object_pose[p.object] = gaussian_at(favoured, 0.02 * bin_width(paper_space()), 0.05);
    camera.set_prior(prior);
    const Estimate c = camera.estimate(3);
    // The object posterior is the evidence's: the pose prior does not touch it.
    CHECK(c.object_probability == p.object_probability);
    CHECK(c.object == p.object);
    // The best bin is now the favoured one, and the strongest hypothesis is its mode, its peak within the bin.
    CHECK(c.bin_pose.T == favoured.T);
    CHECK(c.bin_pose.R == favoured.R);
    // The object's strongest mode is the favoured bin's (a prior weighs 1 at its mean, so another object's modes,
    // which have no pose prior, keep their evidence and may still rank above it).
    const PoseHypothesis* first = nullptr;
    for (const PoseHypothesis& h : c.hypotheses)
      if (!first && h.object == p.object) first = &h;
    REQUIRE(first != nullptr);
    CHECK(glm::length(first->pose.T - favoured.T) <= 0.87 * bin_width(paper_space()));
    CHECK(glm::length(c.object_hypotheses[p.object].pose.T - favoured.T) <= 0.87 * bin_width(paper_space()));
    CHECK(glm::length(c.pose.T - favoured.T) <= 0.87 * bin_width(paper_space()));
    // A prior on another object leaves this estimate's pose alone; a vague one (sigma far beyond the box) too.
    Prior elsewhere;
    elsewhere.object_pose.resize(3);
    elsewhere.object_pose[(p.object + 1) % 3] = gaussian_at(favoured, 1.0, 0.05);
    vague.set_prior(elsewhere);
    CHECK(vague.estimate(3).bin_pose.T == p.bin_pose.T);
    Prior wide;
    wide.object_pose.assign(3, PosePrior{p.bin_pose.T, 1e7});
    vague.set_prior(wide);
    const Estimate v = vague.estimate(3);
    CHECK(v.bin_pose.T == p.bin_pose.T);
    CHECK(v.object_probability == p.object_probability);
    REQUIRE(v.hypotheses.size() == p.hypotheses.size());
    std::vector<double> pv, pp;  // bins of equal evidence may swap places under the prior's slight slope
    for (std::size_t i = 0; i < v.hypotheses.size(); ++i)
      pv.push_back(v.hypotheses[i].probability), pp.push_back(p.hypotheses[i].probability);
    std::sort(pv.begin(), pv.end());
    std::sort(pp.begin(), pp.end());
    for (std::size_t i = 0; i < pv.size(); ++i) CHECK(pv[i] == Approx(pp[i]).epsilon(1e-6));
    // Reset forgets the pose prior with the rest.
    camera.reset();
    for (const Reading& r : readings) camera.add_reading(r);
    CHECK(camera.estimate(3).bin_pose.T == p.bin_pose.T);
    camera.set_prior(prior);
    with_prior.push_back(camera.estimate(3));
  }
  // The same answer on every backend, bit for bit.
  for (std::size_t b = 1; b < with_prior.size(); ++b) {
    CHECK(with_prior[b].pose.T == with_prior[0].pose.T);
    CHECK(with_prior[b].bin_pose.T == with_prior[0].bin_pose.T);
    REQUIRE(with_prior[b].hypotheses.size() == with_prior[0].hypotheses.size());
    for (std::size_t i = 0; i < with_prior[0].hypotheses.size(); ++i) {
      CHECK(with_prior[b].hypotheses[i].probability == with_prior[0].hypotheses[i].probability);
      CHECK(with_prior[b].hypotheses[i].covariance == with_prior[0].hypotheses[i].covariance);
    }
  }
}

TEST_CASE("Pose prior: a saved session keeps it, and a restored one answers as the original") {
  const RigidPose truth = random_pose(720, 100.0);
  const std::vector<Reading> readings = readings_of(1, truth, 721, 3);
  const std::filesystem::path dir = temp_dir("pose-prior-session");
  Recognizer original = recognizer_on(BackendKind::cpu);
  for (const Reading& r : readings) original.add_reading(r);
  const Estimate plain = original.estimate(kPosePriorCandidates);
  const Hypothesis* target = other_bin(plain);
  REQUIRE(target != nullptr);
  Prior prior;
  prior.object_probability.assign(3, 0.3);
  prior.object_probability[target->object] = 0.4;  // the best object stays the best
  prior.object_pose.resize(3);
  prior.object_pose[target->object] = gaussian_at(target->pose, 0.02 * bin_width(paper_space()), 0.05);
  original.set_prior(prior);
  original.save_session(dir / "s.svas");
  Recognizer resumed = recognizer_on(BackendKind::cpu);
  resumed.restore_session(dir / "s.svas");
  const Estimate a = original.estimate(3), b = resumed.estimate(3);
  CHECK(b.bin_pose.T == a.bin_pose.T);
  CHECK(b.bin_pose.T == target->pose.T);  // the pose prior came back, not only the object prior
  CHECK(b.object_probability == a.object_probability);
  REQUIRE(b.hypotheses.size() == a.hypotheses.size());
  for (std::size_t i = 0; i < a.hypotheses.size(); ++i) CHECK(b.hypotheses[i].pose.T == a.hypotheses[i].pose.T);
  std::filesystem::remove_all(dir);
}

TEST_CASE("Pose prior: priors that do not fit are refused, and the box can be placed around one") {
  Recognizer rec = recognizer_on(BackendKind::cpu);
  Prior p;
  p.object_pose.resize(2);
  CHECK_THROWS_WITH(rec.set_prior(p), Catch::Contains("2 object pose priors") && Catch::Contains("3 objects"));
  p.object_pose.assign(3, std::nullopt);
  p.object_pose[1] = PosePrior{{0, 0, 0}, 0.0};
  CHECK_THROWS_WITH(rec.set_prior(p), Catch::Contains("object 1") && Catch::Contains("position_sigma_mm"));
  p.object_pose[1] = PosePrior{{0, std::nan(""), 0}, 5.0};
  CHECK_THROWS_WITH(rec.set_prior(p), Catch::Contains("not finite"));
  PosePrior skew{{0, 0, 0}, 5.0};
  skew.has_rotation = true;
  skew.rotation = glm::dmat3(2.0);
  skew.rotation_sigma_rad = 0.1;
  p.object_pose[1] = skew;
  CHECK_THROWS_WITH(rec.set_prior(p), Catch::Contains("not a rotation"));
  skew.rotation = glm::dmat3(1.0);
  skew.rotation_sigma_rad = -1;
  p.object_pose[1] = skew;
  CHECK_THROWS_WITH(rec.set_prior(p), Catch::Contains("rotation_sigma_rad"));

  const PosePrior seen{{600, -20, 100}, 10.0};
  const PoseSpaceSpec box = pose_space_around(paper_space(), seen);
  CHECK(box.workspace.T == seen.position);
  CHECK(box.translation_max_mm == 30.0);
  CHECK(box.translation_min_mm == -30.0);
  CHECK(box.translation_bins == paper_space().translation_bins);
}

TEST_CASE("Reset keeps the belief table: the next session allocates none until it outgrows the last one") {
  const Trained& t = trained();
  const RigidPose truth = random_pose(710, 100.0);
  const std::vector<Reading> long_session = readings_of(2, truth, 711, 14),
                             short_session = readings_of(0, truth, 712, 4);
  for (BackendKind kind : backends()) {
    INFO("backend " << backend_kind_name(kind));
    const PairMap& map = MapAccess::pair_map(t.map);
    PoseSpace space(paper_space(), static_cast<std::uint32_t>(map.objects.size()));
    auto backend = make_vote_backend(kind, map, space, {}).backend;
    BayesFilter filter(map, space, {}, *backend);
    auto observe_all = [&](const std::vector<Reading>& rs) {
      for (std::size_t i = 0; i < rs.size(); ++i) filter.add(describe_reading(map, rs[i], "reading"));
    };
    const std::size_t at_start = filter.belief().table_allocations();
    CHECK(at_start == (kind == BackendKind::cpu ? kBeliefShards : 1));  // the first table (the CPU's: one per shard)
    observe_all(long_session);
    const std::size_t grown = filter.belief().table_allocations();
    REQUIRE(grown > at_start);  // the long session outgrew the first table
    const Candidates first = candidates(filter, 3);
    filter.reset();
    CHECK(filter.belief().table_allocations() == grown);
    observe_all(short_session);  // smaller than the last: no allocation at all
    CHECK(filter.belief().table_allocations() == grown);
    filter.reset();
    observe_all(long_session);  // the same session again: it fits the kept table, and answers as before
    CHECK(filter.belief().table_allocations() == grown);
    const Candidates again = candidates(filter, 3);
    CHECK(again.object_probability == first.object_probability);
    CHECK(again.pose.T == first.pose.T);
    REQUIRE(again.top.size() == first.top.size());
    for (std::size_t i = 0; i < first.top.size(); ++i) CHECK(again.top[i].key == first.top[i].key);
  }
}
