// The Bayes filter's numerical robustness (DESIGN 4) and its bad-input errors.
#include <catch2/catch.hpp>

#include <sva/base/interrupt.hpp>
#include <sva/error.hpp>

#include <cmath>

#include "fixture.hpp"

using namespace sva;
using namespace sva::test;

namespace {

struct Session {
  World world;
  PoseSpace space;
  std::unique_ptr<VoteBackend> backend;
  BayesFilter filter;
  Session(const WorldSpec& ws, const PoseSpaceSpec& spec, const FilterOptions& fo = {}, const VoteSettings& vs = {})
      : world(make_world(ws)),
        space(spec, static_cast<std::uint32_t>(ws.objects)),
        backend(make_cpu_vote_backend(*world.map, space, vs)),
        filter(*world.map, space, fo, *backend) {}
  // As the recognizer does: the reading checked once (reading/observed_reading.hpp), then the filter.
  UpdateStats add(const ObservedReading& r) { return filter.add(validated(r, *world.map, "reading")); }
};

// The true bin's rank among all touched bins (0 = best) and whether it is finite.
std::size_t rank_of_truth(const BayesFilter& f, std::uint32_t object, const RigidPose& truth) {
  std::uint64_t key = 0;
  REQUIRE(f.space().bin_of(object, truth, &key));
  // Best of the true bin and its neighbours: the truth can sit at a bin edge.
  std::vector<std::uint64_t> near;
  f.space().for_each_neighbour(key, [&](std::uint64_t k) { near.push_back(k); });
  std::uint64_t best = 0;
  for (std::uint64_t o : f.belief().offsets(near)) best = std::max(best, o);
  std::size_t rank = 0;
  for (const BinOffset& b : f.belief().best_bins(50))
    if (b.offset > best) ++rank;
  return rank;
}

void require_finite(const Candidates& e) {
  for (double p : e.object_probability) REQUIRE(std::isfinite(p));
  for (const BinHypothesis& h : e.top) REQUIRE(std::isfinite(h.probability));
  if (e.pose_valid) {
    for (int k = 0; k < 3; ++k) REQUIRE(std::isfinite(e.pose.T[k]));
    for (int c = 0; c < 3; ++c)
      for (int r = 0; r < 3; ++r) REQUIRE(std::isfinite(e.pose.R[c][r]));
  }
}

}  // namespace

TEST_CASE("200 readings: no NaN or Inf, the true pose stays on top") {
  WorldSpec ws;
  ws.objects = 2;
  ws.points = 40;
  Session s(ws, paper_space());
  const RigidPose truth = random_pose(77, 100.0);
  util::Rng rng(8);
  for (int i = 0; i < 200; ++i) {
    s.add(observe(s.world.objects[1][rng.below(40)], truth));
    if (i % 50 == 49) {
      const Candidates e = candidates(s.filter, 5);
      require_finite(e);
      CHECK(e.object == 1);
      CHECK(rank_of_truth(s.filter, 1, truth) == 0);
    }
  }
  const Candidates e = candidates(s.filter, 5);
  CHECK(glm::length(e.pose.T - truth.T) < 1.5 * bin_width(paper_space()));
}

TEST_CASE("a reading from a part never seen in training does not destroy the true hypothesis") {
  WorldSpec ws;
  Session s(ws, paper_space());
  const RigidPose truth = random_pose(12, 80.0);
  util::Rng rng(2);
  for (int i = 0; i < 8; ++i) s.add(observe(s.world.objects[0][rng.below(80)], truth));
  REQUIRE(candidates(s.filter, 1).object == 0);
  // Off the surface, with a normal that matches nothing, in a class seen elsewhere.
  WorldPoint alien{{60.0, -5.0, 40.0}, glm::normalize(glm::dvec3(1, 1, 0)), 2};
  s.add(observe(alien, truth));
  for (int i = 0; i < 3; ++i) s.add(observe(s.world.objects[0][rng.below(80)], truth));
  const Candidates e = candidates(s.filter, 5);
  require_finite(e);
  CHECK(e.object == 0);
  CHECK(rank_of_truth(s.filter, 0, truth) == 0);
}

TEST_CASE("the same reading repeated adds no information and no NaN") {
  WorldSpec ws;
  Session s(ws, paper_space());
  const RigidPose truth = random_pose(13, 80.0);
  const ObservedReading r = observe(s.world.objects[2][5], truth);
  s.add(r);
  const UpdateStats st = s.add(r);  // coincident with the first: no axis, pair skipped
  CHECK(st.pairs == 2);
  CHECK(st.pairs_folded == 0);
  CHECK(s.filter.belief().touched() == 0);
  const Candidates e = candidates(s.filter, 3);
  require_finite(e);
  CHECK_FALSE(e.pose_valid);
}

TEST_CASE("every pair out of distance range leaves the belief uniform") {
  WorldSpec ws;
  Session s(ws, paper_space());
  ObservedReading a = observe(s.world.objects[0][0], RigidPose{});
  ObservedReading b = a;
  b.position += glm::dvec3(500.0, 0.0, 0.0);  // beyond dist_max
  s.add(a);
  const UpdateStats st = s.add(b);
  CHECK(st.votes == 0);
  CHECK(s.filter.belief().touched() == 0);
  const Candidates e = candidates(s.filter, 3);
  require_finite(e);
  CHECK_FALSE(e.pose_valid);
  for (double p : e.object_probability) CHECK(p == Approx(1.0 / 3.0));
}

TEST_CASE("a single-object map localises with probability 1") {
  WorldSpec ws;
  ws.objects = 1;
  Session s(ws, paper_space());
  const RigidPose truth = random_pose(14, 100.0);
  util::Rng rng(3);
  for (int i = 0; i < 8; ++i) s.add(observe(s.world.objects[0][rng.below(80)], truth));
  const Candidates e = candidates(s.filter, 3);
  require_finite(e);
  CHECK(e.object_probability.size() == 1);
  CHECK(e.object_probability[0] == 1.0);
  CHECK(e.pose_valid);
  CHECK(glm::length(e.pose.T - truth.T) < 1.5 * bin_width(paper_space()));
}

TEST_CASE("a translation range that excludes the true pose is reported, not crashed") {
  WorldSpec ws;
  PoseSpaceSpec spec = paper_space();
  spec.translation_min_mm = 300.0;
  spec.translation_max_mm = 500.0;
  Session s(ws, spec);
  const RigidPose truth = random_pose(15, 50.0);
  util::Rng rng(4);
  UpdateStats st;
  for (int i = 0; i < 5; ++i) st = s.add(observe(s.world.objects[0][rng.below(80)], truth));
  CHECK(st.votes_outside > 0);
  CHECK(st.votes == 0);
  require_finite(candidates(s.filter, 3));
}

TEST_CASE("edge contacts and normals along the pair axis spread votes without NaN") {
  WorldSpec ws;
  Session s(ws, paper_space());
  const RigidPose truth = random_pose(16, 80.0);
  util::Rng rng(5);
  for (int i = 0; i < 6; ++i) {
    const UpdateStats st = s.add(observe(s.world.objects[1][rng.below(80)], truth, 0.0f));  // normConf = 0
    if (i > 0) CHECK(st.votes > 0);
  }
  const Candidates e = candidates(s.filter, 5);
  require_finite(e);
  CHECK(e.pose_valid);
}

TEST_CASE("bad input is refused with sva::Error") {
  WorldSpec ws;
  Session s(ws, paper_space());
  ObservedReading r = observe(s.world.objects[0][0], RigidPose{});
  ObservedReading bad = r;
  bad.position.x = std::nan("");
  CHECK_THROWS_WITH(s.add(bad), Catch::Contains("position"));
  bad = r;
  bad.position.z = 1e12;  // finite in double, infinite in the float vote math
  CHECK_THROWS_WITH(s.add(bad), Catch::Contains("10 km"));
  bad = r;
  bad.normal = glm::dvec3(0.0);
  CHECK_THROWS_WITH(s.add(bad), Catch::Contains("normal"));
  bad = r;
  bad.classes = {{99, 1.0f}};
  CHECK_THROWS_WITH(s.add(bad), Catch::Contains("class 99"));
  bad = r;
  bad.classes.clear();
  CHECK_THROWS_AS(s.add(bad), Error);
  bad = r;
  bad.norm_conf = std::nanf("");
  CHECK_THROWS_AS(s.add(bad), Error);
  CHECK(s.filter.readings() == 0);  // refused readings leave no trace
  // Options and a pose space that does not match the map.
  FilterOptions fo;
  fo.eps = 0.0;
  CHECK_THROWS_WITH(BayesFilter(*s.world.map, s.space, fo, *s.backend), Catch::Contains("eps"));
  fo.eps = 1e-13;  // below the fixed-point fold's resolution
  CHECK_THROWS_WITH(BayesFilter(*s.world.map, s.space, fo, *s.backend), Catch::Contains("eps"));
  PoseSpace wrong(paper_space(), 5);
  CHECK_THROWS_WITH(BayesFilter(*s.world.map, wrong, {}, *s.backend), Catch::Contains("objects"));
}

TEST_CASE("results do not depend on the thread count") {
  // On 16 workers the CPU update cuts most pairs into pieces that vote apart and joins them again
  // (cpu_vote_backend.cpp, split_pairs): the same votes, the same belief, bit for bit.
  WorldSpec ws;
  VoteSettings one, two, many;
  one.threads = 1;
  two.threads = 2;
  many.threads = 16;
  Session a(ws, paper_space(), {}, one), b(ws, paper_space(), {}, two), c(ws, paper_space(), {}, many);
  const RigidPose truth = random_pose(17, 100.0);
  util::Rng rng(6);
  for (int i = 0; i < 8; ++i) {
    const ObservedReading r = observe(a.world.objects[1][rng.below(80)], truth);
    const UpdateStats sa = a.add(r), sb = b.add(r), sc = c.add(r);
    for (const UpdateStats* s : {&sb, &sc}) {
      CHECK(s->matches == sa.matches);
      CHECK(s->votes == sa.votes);
      CHECK(s->votes_outside == sa.votes_outside);
      CHECK(s->votes_zero == sa.votes_zero);
      CHECK(s->pairs_folded == sa.pairs_folded);
    }
  }
  CHECK(a.filter.last_update().votes > 1000);  // not vacuous
  CHECK(b.filter.belief().table() == a.filter.belief().table());
  CHECK(c.filter.belief().table() == a.filter.belief().table());
  // Same pair votes, bit for bit, and the same belief.
  VoteBatch batch;
  a.filter.queue_pairs(observe(a.world.objects[1][3], truth), 0, &batch);
  const auto va = a.backend->vote(batch), vb = b.backend->vote(batch);
  REQUIRE(va.size() == vb.size());
  for (std::size_t i = 0; i < va.size(); ++i) {
    CHECK(va[i].keys == vb[i].keys);
    CHECK(va[i].mass == vb[i].mass);
  }
  for (const Session* other : {&b, &c}) {
    const Candidates ea = candidates(a.filter, 10), eb = candidates(other->filter, 10);
    CHECK(ea.object_probability == eb.object_probability);
    REQUIRE(ea.top.size() == eb.top.size());
    for (std::size_t i = 0; i < ea.top.size(); ++i) {
      CHECK(ea.top[i].key == eb.top[i].key);
      CHECK(ea.top[i].probability == eb.top[i].probability);
    }
  }
}

TEST_CASE("a batch of sessions gives the same beliefs as updating each alone") {
  // On 16 workers a batch too cuts its largest pairs into pieces (cpu_vote_backend.cpp, split_pairs), each pair's
  // pieces joined and added under its session's lock: the same votes and beliefs as alone on the default workers.
  WorldSpec ws;
  const World w = make_world(ws);
  PoseSpace space(paper_space(), 3);
  VoteSettings many;
  many.threads = 16;
  auto backend = make_cpu_vote_backend(*w.map, space, {}), wide = make_cpu_vote_backend(*w.map, space, many);
  BayesFilter s0(*w.map, space, {}, *backend), s1(*w.map, space, {}, *backend), r0(*w.map, space, {}, *backend),
      r1(*w.map, space, {}, *backend), c0(*w.map, space, {}, *wide), c1(*w.map, space, {}, *wide);
  const RigidPose t0 = random_pose(18, 100.0), t1 = random_pose(19, 100.0);
  util::Rng rng(7);
  for (int i = 0; i < 6; ++i) {
    const ObservedReading a = observe(w.objects[0][rng.below(80)], t0), b = observe(w.objects[2][rng.below(80)], t1);
    update_sessions({&s0, &s1}, {a, b});
    const std::vector<UpdateStats> cut = update_sessions({&c0, &c1}, {a, b});
    const UpdateStats alone[2] = {r0.add(a), r1.add(b)};
    for (int k = 0; k < 2; ++k) {
      CHECK(cut[k].matches == alone[k].matches);
      CHECK(cut[k].votes == alone[k].votes);
      CHECK(cut[k].votes_zero == alone[k].votes_zero);
      CHECK(cut[k].pairs_folded == alone[k].pairs_folded);
    }
  }
  CHECK(r1.last_update().votes > 1000);  // not vacuous
  CHECK(s0.belief().table() == r0.belief().table());
  CHECK(s1.belief().table() == r1.belief().table());
  CHECK(c0.belief().table() == r0.belief().table());
  CHECK(c1.belief().table() == r1.belief().table());
  CHECK(candidates(s0, 5).object_probability == candidates(r0, 5).object_probability);
  CHECK(candidates(s1, 5).object_probability == candidates(r1, 5).object_probability);
  CHECK(candidates(s1, 5).best_key == candidates(r1, 5).best_key);
}

TEST_CASE("speed knobs: pair cap, likelihood cut-off and object pruning keep the answer") {
  WorldSpec ws;
  FilterOptions fo;
  fo.max_pairs_per_update = 6;
  fo.object_prune_probability = 1e-3;
  VoteSettings vs;
  vs.likelihood_cutoff = 0.5f;
  Session s(ws, paper_space(), fo, vs);
  const RigidPose truth = random_pose(20, 100.0);
  util::Rng rng(9);
  UpdateStats st;
  for (int i = 0; i < 12; ++i) st = s.add(observe(s.world.objects[2][rng.below(80)], truth));
  CHECK(st.pairs == 6);
  const Candidates e = candidates(s.filter, 3);
  CHECK(e.object == 2);
  CHECK(glm::length(e.pose.T - truth.T) < 1.5 * bin_width(paper_space()));
}

TEST_CASE("a session interrupted during an update refuses further use until reset") {
  Session s(WorldSpec{}, paper_space());
  const RigidPose pose = random_pose(31, 100.0);
  for (int i = 0; i < 4; ++i) s.add(observe(s.world.objects[0][static_cast<std::size_t>(i * 9)], pose));
  util::request_interrupt();  // as Ctrl-C would, while the backend votes and folds
  CHECK_THROWS_AS(s.add(observe(s.world.objects[0][50], pose)), Interrupted);
  util::clear_interrupt();
  // Its belief may hold part of that update: no estimate, no update, a clear reason.
  CHECK_THROWS_WITH(s.filter.require_complete(), Catch::Contains("interrupted") && Catch::Contains("reset"));
  CHECK_THROWS_WITH(s.add(observe(s.world.objects[0][51], pose)), Catch::Contains("interrupted"));
  s.filter.reset();
  for (int i = 0; i < 6; ++i) s.add(observe(s.world.objects[0][static_cast<std::size_t>(i * 7)], pose));
  CHECK(candidates(s.filter, 1).object == 0);
}
