// The touch planner (sva/touch_planner.hpp) on a synthetic world of two objects of one shape whose textures differ
// only on a cap: it plans there first, and choosing touches by plan decides the object in fewer readings than
// touching at random. Scores are finite and deterministic; no candidate set makes it fail.
#include <catch2/catch.hpp>

#include <sva/error.hpp>
#include <sva/recognizer.hpp>
#include <sva/touch_planner.hpp>

#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>

#include "estimate/heightfield.hpp"
#include "recognition/fixture.hpp"
#include "recognition/trained_map.hpp"
#include "test_support.hpp"

using namespace sva;
using namespace sva::test;

namespace {

// A point of the twins' common ellipsoid. Textures follow the octant (three of them) everywhere but on the cap
// u.z > 0.75 (an eighth of the surface), where object 0 alone has a fourth texture: the one place they differ.
struct TwinPoint {
  WorldPoint w;
  bool cap = false;
};

TwinPoint twin_point(int object, int i, std::uint64_t seed) {
  util::Rng rng(seed, static_cast<std::uint64_t>(i));
  const glm::dvec3 axes(30.0, 22.0, 15.0);
  const double z = rng.uniform(-1.0, 1.0), phi = rng.uniform(0.0, 2.0 * std::numbers::pi);
  const double rho = std::sqrt(1.0 - z * z);
  const glm::dvec3 u(rho * std::cos(phi), rho * std::sin(phi), z);
  TwinPoint t;
  t.w.p = axes * u;
  t.w.n = glm::normalize(u / axes);
  t.cap = u.z > 0.75;
  const int oct = (u.x > 0) + 2 * (u.y > 0) + 4 * (u.z > 0);
  t.w.cls = t.cap && object == 0 ? 3u : static_cast<std::uint32_t>(oct % 3);
  return t;
}

struct Twins {
  Dataset data;
  Map map;
};

const Twins& twins() {
  static const Twins t = [] {
    Twins x;
    x.data = synthetic_training_set("twins", "twin", 2);
    for (int o = 0; o < 2; ++o)
      for (int i = 0; i < 90; ++i) {
        util::Rng rng(2, static_cast<std::uint64_t>(o), static_cast<std::uint64_t>(i));
        Sample s;
        s.object = static_cast<std::uint32_t>(o);
        s.reading = reading_of(x.data.scene.sensor, twin_point(o, i, 3).w, RigidPose{}, rng);
        x.data.samples.push_back(s);
      }
    TrainOptions no_calibration;  // the recognizers below read Eq 5's raw posterior (run_trial)
    no_calibration.calibrate = false;
    x.map = Map::train(x.data, no_calibration);
    return x;
  }();
  return t;
}

const TouchPlanner& planner() {
  static const TouchPlanner p(twins().map);
  return p;
}

// An estimate holding the two objects at one pose, equally likely.
Estimate both_at(const RigidPose& pose) {
  Estimate e;
  for (std::uint32_t o = 0; o < 2; ++o) {
    PoseHypothesis h;
    h.object = o;
    h.pose = pose;
    h.probability = 0.5;
    h.valid = true;
    e.hypotheses.push_back(h);
  }
  e.object_probability = {0.5, 0.5};
  e.pose_valid = true;
  e.pose = pose;
  return e;
}

// A trial: the true object in a random pose, test readings drawn from its surface (other points than the
// training ones). Returns the readings until the true object holds >= 95% and until the first touch of the cap
// (max + 1 if never).
struct Outcome {
  std::size_t readings = 0;
  std::size_t first_cap = 0;
};

Outcome run_trial(std::uint32_t object, std::uint64_t seed, bool active, std::size_t max_readings = 30) {
  const Twins& t = twins();
  // Eq 5's raw posterior: the planner is measured against the overconfident belief it was designed for. Calibrated
  // (docs/recognition.md), the twins' belief stays below 95% for 30 readings either way: a temperature learned on
  // random sessions, where the raw belief sits confidently on the wrong twin until the cap is touched, is low.
  RecognizerOptions ro;
  ro.calibrate = false;
  Recognizer rec(t.map, paper_space(), ro);
  const RigidPose truth = random_pose(seed, 100.0);
  std::vector<TwinPoint> pool;
  for (int i = 0; i < 150; ++i) pool.push_back(twin_point(static_cast<int>(object), 1000 + i, 17 + seed));
  util::Rng rng(seed, 5);
  std::vector<std::size_t> order(pool.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  for (std::size_t i = 0; i < order.size(); ++i) std::swap(order[i], order[i + rng.below(order.size() - i)]);
  std::vector<bool> used(pool.size(), false);
  std::vector<glm::dvec3> visited, normals;
  Estimate est;
  Outcome out{max_readings + 1, max_readings + 1};
  for (std::size_t n = 1; n <= max_readings; ++n) {
    std::size_t pick = *std::find_if(order.begin(), order.end(), [&](std::size_t i) { return !used[i]; });
    if (active && est.pose_valid) {
      TouchPlanOptions o;
      o.visited = visited;
      o.visited_normals = normals;
      const auto cands = planner().sample_candidates(est, 100, seed * 100 + n, o);
      const TouchPlan plan = plan_next_touch(planner(), est, cands, o);
      if (!plan.best.empty() && plan.best[0].score > 0.0) {
        double best = std::numeric_limits<double>::infinity();
        for (std::size_t i = 0; i < pool.size(); ++i) {
          const double d = glm::length(truth.apply(pool[i].w.p) - plan.best[0].touch.position);
          if (!used[i] && d < best) best = d, pick = i;
        }
      }
    }
    used[pick] = true;
    if (pool[pick].cap) out.first_cap = std::min(out.first_cap, n);
    const Reading r = reading_of(t.data.scene.sensor, pool[pick].w, truth, rng);
    visited.push_back(r.position);
    normals.push_back(r.normal);
    rec.add_reading(r);
    est = rec.estimate(8);
    if (est.object_probability[object] >= 0.95) {
      out.readings = n;
      return out;
    }
  }
  return out;
}

}  // namespace

TEST_CASE("Touch planner: between two objects alike but for a cap, the best touch is on the cap") {
  const RigidPose pose = random_pose(3, 50.0);
  const Estimate e = both_at(pose);
  const auto cands = planner().sample_candidates(e, 200, 9);
  REQUIRE(cands.size() == 200);
  TouchPlanOptions o;
  o.best = 5;
  const TouchPlan plan = plan_next_touch(planner(), e, cands, o);
  REQUIRE(plan.best.size() == 5);
  CHECK(plan.hypotheses == 2);
  CHECK(plan.note.empty());
  for (const TouchScore& s : plan.best) {
    const glm::dvec3 q = pose.inverse().apply(s.touch.position);
    INFO("candidate " << s.candidate << " score " << s.score << " at object-frame z " << q.z);
    CHECK(q.z / 15.0 > 0.6);  // on (or at the rim of) the cap, u.z > 0.75
    CHECK(s.score > 0.1);
    CHECK(s.score <= 1.0 + 1e-12);  // at most the entropy of two equal masses
  }
  // Off the cap the twins feel the same: the worst candidates score (nearly) nothing.
  TouchPlanOptions all;
  all.best = cands.size();
  const TouchPlan every = planner().plan(e, cands, all);
  REQUIRE(every.best.size() == cands.size());
  CHECK(every.best.back().score < 0.05);
}

// Object 0 is told from object 1 by its cap alone; the recognizer, overconfident, gives object 1 nearly all the
// mass until a cap reading arrives. The plan keeps object 0's best mode in play (TouchPlanOptions::object_floor)
// and sends the sensor to the cap once the pose is known. Object 1 has nothing of its own to touch: there the
// policy may only not lose much (its first plans check the cap for object 0 while random touches confirm object 1).
// Totals over 8 placements, not trial by trial: a random order touches the cap first now and then, and then ties
// or beats the plan. Over 10 seeds (bench/reliability/test_margins.py, docs/reliability.md "Margins") the total ratio
// was 0.44 to 0.82 and object 1's 0.50 to 0.91; object 0's alone was 0.34 to 0.75 but 1.11 at one seed, where one
// placement kept the overconfident belief on object 1 for 13 readings: it is printed, not asserted.
TEST_CASE("Touch planner: touching where the plan says decides the object in fewer readings than at random") {
  std::size_t active[2] = {0, 0}, random[2] = {0, 0}, active_cap = 0, random_cap = 0;
  for (std::uint64_t k = 1; k <= 8; ++k)
    for (std::uint32_t object = 0; object < 2; ++object) {
      const std::uint64_t seed = test::scenario_seed(k);
      const Outcome a = run_trial(object, seed, true), r = run_trial(object, seed, false);
      std::printf(
          "seed %llu object %u: readings to 95%% active %zu, random %zu; first cap touch active %zu, random %zu\n",
          static_cast<unsigned long long>(seed), object, a.readings, r.readings, a.first_cap, r.first_cap);
      active[object] += a.readings;
      random[object] += r.readings;
      if (object == 0) active_cap += a.first_cap, random_cap += r.first_cap;
    }
  const auto ratio = [](std::size_t x, std::size_t y) { return static_cast<double>(x) / static_cast<double>(y); };
  std::printf("object 0: readings to 95%% active / random %.3f, first cap touch active / random %.3f\n",
              ratio(active[0], random[0]), ratio(active_cap, random_cap));
  test::margin("twins: object 1's readings to 95%, active / random", ratio(active[1], random[1]), "<", 1.25);
  test::margin("twins: readings to 95%, active / random", ratio(active[0] + active[1], random[0] + random[1]), "<",
               0.95);
  CHECK(ratio(active[1], random[1]) < 1.25);
  CHECK(ratio(active[0] + active[1], random[0] + random[1]) < 0.95);
}

TEST_CASE("Touch planner: scores are finite and the same run to run") {
  const Estimate e = both_at(random_pose(8, 80.0));
  const auto a = planner().sample_candidates(e, 300, 4), b = planner().sample_candidates(e, 300, 4);
  REQUIRE(a.size() == b.size());
  for (std::size_t i = 0; i < a.size(); ++i) CHECK(a[i].position == b[i].position);
  CHECK(planner().sample_candidates(e, 300, 5)[0].position != a[0].position);
  TouchPlanOptions o;
  o.best = a.size();
  const TouchPlan p = planner().plan(e, a, o), q = planner().plan(e, a, o);
  REQUIRE(p.best.size() == a.size());
  for (std::size_t i = 0; i < p.best.size(); ++i) {
    CHECK(std::isfinite(p.best[i].score));
    CHECK(p.best[i].score >= 0.0);
    CHECK(p.best[i].candidate == q.best[i].candidate);
    CHECK(p.best[i].score == q.best[i].score);
    if (i) CHECK(p.best[i - 1].score >= p.best[i].score);
  }
}

TEST_CASE("Touch planner: empty, single, unreachable and bad candidate sets give clear plans") {
  const Estimate e = both_at(RigidPose{});
  const TouchPlan none = planner().plan(e, {});
  CHECK(none.best.empty());
  CHECK(none.note.find("no candidate") != std::string::npos);

  const std::vector<CandidateTouch> one{{{0.0, 0.0, 15.0}, {0.0, 0.0, -1.0}, true}};
  const TouchPlan single = planner().plan(e, one);
  REQUIRE(single.best.size() == 1);
  CHECK(single.best[0].candidate == 0);
  CHECK(std::isfinite(single.best[0].score));

  const double nan = std::numeric_limits<double>::quiet_NaN();
  const std::vector<CandidateTouch> unreachable{{{0.0, 0.0, 15.0}, {0.0, 0.0, -1.0}, false},
                                                {{nan, 0.0, 0.0}, {0.0, 0.0, -1.0}, true},
                                                {{0.0, 0.0, 15.0}, {0.0, 0.0, 0.0}, true}};
  const TouchPlan blocked = planner().plan(e, unreachable);
  CHECK(blocked.best.empty());
  CHECK(blocked.reachable == 0);
  CHECK(blocked.note.find("reachable") != std::string::npos);

  // No pose yet (an estimate of one reading): every candidate scores 0, the plan says why.
  const TouchPlan blind = planner().plan(Estimate{}, one);
  REQUIRE(blind.best.size() == 1);
  CHECK(blind.best[0].score == 0.0);
  CHECK(blind.hypotheses == 0);
  CHECK_FALSE(blind.note.empty());
  CHECK(planner().sample_candidates(Estimate{}, 10, 1).empty());

  TouchPlanOptions bad;
  bad.best = 0;
  CHECK_THROWS_AS(planner().plan(e, one, bad), Error);
  bad = {};
  bad.contact_tolerance_mm = nan;
  CHECK_THROWS_AS(planner().plan(e, one, bad), Error);
}

TEST_CASE(
    "Touch planner: once the object is known, a touch that constrains the pose where the visited ones do not wins") {
  Estimate e = both_at(RigidPose{});
  e.hypotheses.resize(1);  // object 0 alone, at the identity
  e.hypotheses[0].probability = 1.0;
  e.object_probability = {1.0, 0.0};
  const auto cands = planner().sample_candidates(e, 400, 21);
  // The candidate facing most nearly up (+z) and the one facing most nearly sideways (+x).
  std::size_t up = 0, side = 0;
  for (std::size_t i = 0; i < cands.size(); ++i) {
    if (-cands[i].approach.z > -cands[up].approach.z) up = i;
    if (-cands[i].approach.x > -cands[side].approach.x) side = i;
  }
  TouchPlanOptions o;
  o.best = cands.size();
  // Three touches on the top, all felt with normal +z: they fix z and the tilts, not x, y or the turn about z.
  o.visited = {{0.0, 0.0, 15.0}, {12.0, 0.0, 12.0}, {0.0, 10.0, 12.0}};
  o.visited_normals = {{0.0, 0.0, 1.0}, {0.0, 0.0, 1.0}, {0.0, 0.0, 1.0}};
  o.pair_min_mm = 0.0;  // every candidate pairs: the comparison is the pose term's alone
  auto score_of = [&](const TouchPlan& p, std::size_t c) {
    for (const TouchScore& s : p.best)
      if (s.candidate == c) return s.score;
    return -1.0;
  };
  const TouchPlan plan = planner().plan(e, cands, o);
  INFO("up " << -cands[up].approach.z << " side " << -cands[side].approach.x);
  CHECK(score_of(plan, side) > score_of(plan, up) + 0.5);
  CHECK(std::isfinite(plan.best.front().score));
  o.pose_gain = false;  // one hypothesis, nothing to tell apart: every score is 0
  CHECK(planner().plan(e, cands, o).best.front().score == 0.0);
  o.pose_gain = true;
  e.object_probability = {0.9, 0.1};  // the object not yet known: no pose term
  CHECK(planner().plan(e, cands, o).best.front().score == 0.0);
  o.visited_normals.pop_back();
  CHECK_THROWS_WITH(planner().plan(e, cands, o), Catch::Contains("2 visited normals for 3 visited touches"));
}

TEST_CASE("Touch planner: the first touch's contact estimate guesses poses that put a like contact at the touch") {
  const Twins& t = twins();
  const RigidPose truth = random_pose(12, 80.0);
  // A touch on object 0's cap: its texture is object 0's alone.
  TwinPoint cap;
  for (int i = 2000; !cap.cap; ++i) cap = twin_point(0, i, 41);
  util::Rng rng(12, 1);
  const Reading touch = reading_of(t.data.scene.sensor, cap.w, truth, rng);
  const Estimate e = planner().contact_estimate(touch, 5, 7);
  CHECK(e.readings == 1);
  CHECK_FALSE(e.pose_valid);
  REQUIRE(e.object_probability.size() == 2);
  CHECK(e.object_probability[0] + e.object_probability[1] == Approx(1.0));
  CHECK(e.object_probability[0] > 0.8);  // only object 0 has contacts that feel like its cap
  CHECK(e.object == 0);
  REQUIRE(e.object_hypotheses.size() == 2);
  CHECK(e.object_hypotheses[0].valid);
  std::size_t of_object0 = 0;
  double mass = 0.0;
  for (const PoseHypothesis& h : e.hypotheses) {
    mass += h.probability;
    of_object0 += h.object == 0;
    // The pose carries one of the object's training contacts onto the touch, normal onto normal.
    const glm::dvec3 q = h.pose.inverse().apply(touch.position), n = h.pose.inverse().rotate(touch.normal);
    double nearest = std::numeric_limits<double>::infinity(), normal_gap = 0.0;
    for (const Sample& s : t.data.samples) {
      if (s.object != h.object) continue;
      const double d = glm::length(s.reading.position - q);
      if (d < nearest) nearest = d, normal_gap = glm::length(glm::normalize(s.reading.normal) - n);
    }
    CHECK(nearest < 1e-6);
    CHECK(normal_gap < 1e-6);
  }
  CHECK(of_object0 == 5);
  CHECK(mass == Approx(1.0));
  // Deterministic for a seed; another seed draws other guesses.
  const Estimate again = planner().contact_estimate(touch, 5, 7), other = planner().contact_estimate(touch, 5, 8);
  REQUIRE(again.hypotheses.size() == e.hypotheses.size());
  for (std::size_t i = 0; i < e.hypotheses.size(); ++i) CHECK(again.hypotheses[i].pose.T == e.hypotheses[i].pose.T);
  CHECK(other.hypotheses.front().pose.T != e.hypotheses.front().pose.T);
  // The second touch can be planned over it: candidates on the guessed surfaces, scored over the guesses.
  TouchPlanOptions o;
  o.max_hypotheses = e.hypotheses.size();
  o.visited = {touch.position};
  const auto cands = planner().sample_candidates(e, 50, 3, o);
  CHECK(cands.size() == 50);
  const TouchPlan plan = planner().plan(e, cands, o);
  CHECK(plan.hypotheses == e.hypotheses.size());
  REQUIRE_FALSE(plan.best.empty());
  CHECK(std::isfinite(plan.best.front().score));

  CHECK_THROWS_WITH(planner().contact_estimate(touch, 0, 7), Catch::Contains("at least 1 hypothesis per object"));
  Reading unsettled = touch;
  unsettled.status = ControllerStatus::not_converged;
  CHECK_THROWS_WITH(planner().contact_estimate(unsettled, 5, 7), Catch::Contains("the first touch"));
  Reading broken = touch;
  broken.pressure.pop_back();
  CHECK_THROWS_WITH(planner().contact_estimate(broken, 5, 7), Catch::Contains("pressure values"));
}

namespace {

// Twins as meshes (the map's surfaces, format 9): a flat field and its twin with a raised plateau. Their training
// contacts lie on the flat field alike (one class): the meshes alone tell them apart.
const Map& field_twins() {
  static const Map m = [] {
    Dataset d = synthetic_training_set("field-twins", "field", 2);
    for (int o = 0; o < 2; ++o)
      for (int i = 0; i < 80; ++i) {
        util::Rng rng(4, static_cast<std::uint64_t>(o), static_cast<std::uint64_t>(i));
        WorldPoint w;
        w.p = glm::dvec3(rng.uniform(0.0, 40.0), rng.uniform(0.0, 40.0), 0.0);
        w.n = glm::dvec3(0.0, 0.0, 1.0);
        w.cls = 0;
        Sample s;
        s.object = static_cast<std::uint32_t>(o);
        s.reading = reading_of(d.scene.sensor, w, RigidPose{}, rng);
        d.samples.push_back(s);
      }
    TrainOptions o;
    o.calibrate = false;
    o.surfaces = {heightfield(false), heightfield(true)};
    return Map::train(d, o);
  }();
  return m;
}

}  // namespace

TEST_CASE("Touch planner: with the map's meshes, two posed twins that differ in one region are touched there") {
  const TouchPlanner mesh_planner(field_twins());
  const RigidPose pose = random_pose(12, 40.0);
  const Estimate e = both_at(pose);
  std::vector<CandidateTouch> cands;  // presses down onto the flat field, every 2.5 mm
  for (int j = 0; j <= 16; ++j)
    for (int i = 0; i <= 16; ++i)
      cands.push_back({pose.apply(glm::dvec3(2.5 * i, 2.5 * j, 0.0)), pose.rotate(glm::dvec3(0.0, 0.0, -1.0)), true});
  TouchPlanOptions all;
  all.best = cands.size();
  const TouchPlan plan = mesh_planner.plan(e, cands, all);
  REQUIRE(plan.best.size() == cands.size());
  for (std::size_t k = 0; k < 5; ++k) {
    const glm::dvec3 q = pose.inverse().apply(plan.best[k].touch.position);
    INFO("best " << k << " at " << q.x << ", " << q.y << ", score " << plan.best[k].score);
    CHECK(q.x > 10.0);  // on the plateau or its slopes
    CHECK(q.x < 30.0);
    CHECK(q.y > 10.0);
    CHECK(q.y < 30.0);
    CHECK(plan.best[k].score > 0.5);
  }
  // Away from the region the twins' meshes predict the same contact: nothing to learn there.
  for (const TouchScore& s : plan.best) {
    const glm::dvec3 q = pose.inverse().apply(s.touch.position);
    if (q.x < 7.5 || q.x > 32.5 || q.y < 7.5 || q.y > 32.5) CHECK(s.score == 0.0);
  }
}
