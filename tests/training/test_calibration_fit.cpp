// Learning a map's calibration (host/src/training): the held-out split of the training readings, and the fits of
// the temperature and surface weight, the top label and "none of these" on sessions whose truth is drawn from a
// known model, which each fit must recover. The model they fit is tests/calibration's.
#include <catch2/catch.hpp>

#include <sva/base/rng.hpp>
#include <sva/dataset.hpp>
#include <sva/scene.hpp>
#include <sva/sim/simulate.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <optional>

#include "calibration/calibration.hpp"
#include "map/map_builder.hpp"
#include "test_support.hpp"
#include "training/calibration_fit.hpp"
#include "training/held_out_sessions.hpp"

using namespace sva;

namespace {

// Sessions whose objects' log-evidence is exactly `true_tau`^-1 times a calibrated log-likelihood: the true object
// is drawn from the tempered posterior, so the fit should find tau(n) = true_tau. With a surface weight, each level
// also carries surface-check bits that count `surface_weight` times in the true posterior.
std::vector<CalibrationSession> synthetic_sessions(double true_tau, std::size_t count,
                                                   std::optional<double> surface_weight = std::nullopt) {
  std::vector<CalibrationSession> out;
  for (std::size_t t = 0; t < count; ++t) {
    util::Rng rng(42, t);
    std::vector<double> logit(4);
    for (std::size_t n = 2; n <= 8; ++n) {
      for (double& l : logit) l = 3.0 * rng.normal();
      EvidenceLevel level;
      level.readings = n;
      for (double l : logit) level.object_log2_mass.push_back(l / true_tau);
      if (surface_weight)
        for (std::size_t o = 0; o < logit.size(); ++o) level.surface_log2_fit.push_back(6.0 * rng.normal());
      const std::vector<double> p = tempered_posterior(level.object_log2_mass, true_tau, {}, level.surface_log2_fit,
                                                       surface_weight.value_or(0.0));
      double u = rng.uniform(), acc = 0.0;
      std::uint32_t truth = 3;
      for (std::uint32_t o = 0; o < 4; ++o)
        if (u < (acc += p[o])) {
          truth = o;
          break;
        }
      // One session per step keeps each step's truth its own draw.
      CalibrationSession one;
      one.object = truth;
      one.steps.push_back(level);
      out.push_back(std::move(one));
    }
  }
  return out;
}

}  // namespace

TEST_CASE("fit_temperature recovers the temperature of sessions drawn from a tempered posterior") {
  for (double tau : {0.2, 0.6}) {
    Calibration c;
    fit_temperature(synthetic_sessions(tau, 400), &c);
    // tau(n) = scale (n-1)^-power with the same temperature at every n: power near 0, scale near tau.
    for (std::size_t n : {2, 4, 8}) CHECK(c.temperature(n) == Approx(tau).epsilon(0.2));
    CHECK(c.surface_weight == Calibration::kDefaultSurfaceWeight);  // no surface check in these sessions
  }
}

TEST_CASE("fit_temperature recovers the surface check's weight beside the temperature") {
  for (double weight : {0.0, 0.25}) {
    INFO("true surface weight " << weight);
    Calibration c;
    fit_temperature(synthetic_sessions(0.4, 400, weight), &c);
    CHECK(c.surface_weight == weight);
    for (std::size_t n : {2, 4, 8}) CHECK(c.temperature(n) == Approx(0.4).epsilon(0.2));
  }
}

TEST_CASE("fit_top_label recovers the top label of sessions whose top is right as often as it says") {
  // Steps whose top object is right with probability sigmoid(a + b logit p_top) under the default temperature:
  // before the fine pose {a, b} = {0.5, 0.4} (a flat top too unsure, a sure one too sure), from it on {-0.3, 0.8}.
  const std::array<Calibration::TopLabel, 2> truth{Calibration::TopLabel{0.5, 0.4}, Calibration::TopLabel{-0.3, 0.8}};
  std::vector<CalibrationSession> sessions;
  const Calibration tempering;
  for (std::size_t t = 0; t < 4000; ++t) {
    util::Rng rng(7, t);
    EvidenceLevel level;
    level.readings = 2 + t % 8;
    level.fit_cost_share = t % 2 ? 0.1 : -1.0;
    for (int o = 0; o < 5; ++o) level.object_log2_mass.push_back(12.0 * rng.normal());
    const std::vector<double> p = tempering.object_probability(level, {});
    const std::size_t top = static_cast<std::size_t>(std::max_element(p.begin(), p.end()) - p.begin());
    const Calibration::TopLabel& k = truth[t % 2];
    const double right = 1.0 / (1.0 + std::exp(-(k[0] + k[1] * Calibration::top_logit(p[top]))));
    CalibrationSession s;
    s.object = rng.uniform() < right ? static_cast<std::uint32_t>(top)
                                     : static_cast<std::uint32_t>((top + 1 + rng.below(4)) % 5);
    s.steps.push_back(level);
    sessions.push_back(std::move(s));
  }
  Calibration c;
  fit_top_label(sessions, &c);
  for (int regime = 0; regime < 2; ++regime) {
    INFO("regime " << regime);
    CHECK(c.top_label[regime][0] == Approx(truth[regime][0]).margin(0.15));
    CHECK(c.top_label[regime][1] == Approx(truth[regime][1]).margin(0.1));
  }
  // Every step right: nothing to learn, the identity stays.
  for (CalibrationSession& s : sessions) {
    const std::vector<double> p = tempering.object_probability(s.steps[0], {});
    s.object = static_cast<std::uint32_t>(std::max_element(p.begin(), p.end()) - p.begin());
  }
  Calibration all_right;
  fit_top_label(sessions, &all_right);
  CHECK(all_right.top_label == Calibration{}.top_label);
}

TEST_CASE("fit_light learns a light estimate's calibration from the sessions' light view, from their first fine pose") {
  // Sessions whose light view is the calibrated posterior of temperature 0.3 (no surface bits), to which steps from 6
  // readings on add a fine pose and surface bits that point at the true object: the full calibration learns with
  // them, and the light one must find the temperature without them and leave its top label near the identity.
  std::vector<CalibrationSession> sessions = synthetic_sessions(0.3, 400);
  for (CalibrationSession& s : sessions)
    for (EvidenceLevel& level : s.steps) {
      if (level.readings < 6) continue;
      level.fit_cost_share = 0.1;
      level.fine_pose_from = 6;
      for (std::size_t o = 0; o < level.object_log2_mass.size(); ++o)
        level.surface_log2_fit.push_back(o == s.object ? 8.0 : 0.0);
    }
  Calibration c;
  fit_temperature(sessions, &c);
  fit_light(sessions, sessions, &c);
  REQUIRE_FALSE(c.light.empty());
  CHECK(c.light.from == 6);
  // (Within 10%: on these draws the full fit, leaning on the surface bits, found 0.26 at 8 readings, the light 0.30.)
  for (std::size_t n : {2, 4, 6, 8}) {
    INFO(n << " readings");
    if (n < 6) CHECK(c.temperature(n, true) == c.temperature(n));
    if (n >= 6) CHECK(c.temperature(n, true) == Approx(0.3).epsilon(0.1));
  }
  CHECK_FALSE(c.temperature(8) == Approx(0.3).epsilon(0.1));
  CHECK(c.light.top_label[0] == Approx(0.0).margin(0.3));
  CHECK(c.light.top_label[1] == Approx(1.0).margin(0.2));
  CHECK(c.light.unknown.empty());  // no unknown sessions
  // Sessions that never reach a fine pose: light and full estimates are the same steps, nothing of its own.
  Calibration none;
  fit_light(synthetic_sessions(0.3, 20), synthetic_sessions(0.3, 20), &none);
  CHECK(none.light.empty());
}

TEST_CASE("the temperature's map holds every object: the same readings held out, no object held out whole") {
  sim::SimulateOptions so;
  so.train_per_object = 20;
  so.test_per_object = 1;
  Dataset data = sim::simulate(load_scene("tiny"), so).train;
  // Five objects (the split reads ids and names alone): a fifth of them, one, is held out whole.
  const SceneObject first = data.scene.objects[0];
  data.scene.objects.assign(5, first);
  for (std::size_t o = 0; o < 5; ++o) data.scene.objects[o].name = "object" + std::to_string(o);
  for (std::size_t i = 0; i < data.samples.size(); ++i) data.samples[i].object = static_cast<std::uint32_t>(i % 5);
  const CalibrationSplit with = split_for_calibration(data, 0.2, 5);
  const CalibrationSplit every = split_for_calibration(data, 0.2, 5, false);
  CHECK(std::count(with.map_object.begin(), with.map_object.end(), -1) >= 1);
  CHECK(std::count(every.map_object.begin(), every.map_object.end(), -1) == 0);
  CHECK(every.map_part.scene.objects.size() == data.scene.objects.size());
  CHECK(every.map_part.samples.size() + every.held_out.samples.size() == data.samples.size());
  // A known object's held-out readings are the same in both splits.
  std::size_t known_held_out = 0;
  for (const Sample& s : with.held_out.samples) known_held_out += with.map_object[s.object] >= 0 ? 1 : 0;
  std::size_t every_held_out_of_those = 0;
  for (const Sample& s : every.held_out.samples) every_held_out_of_those += with.map_object[s.object] >= 0 ? 1 : 0;
  CHECK(known_held_out == every_held_out_of_those);
  CHECK(known_held_out > 0);
}

TEST_CASE("fit_unknown: the evidence before the fine pose, the fit after it, coefficients linear in log(n - 1)") {
  // Before the fine pose (5 readings or fewer here) the evidence per pair separates the kinds: known ~ 3 bits, unknown
  // ~ 1. From it on, the fit cost share does: known ~ N(0.1, 0.05), unknown drifting away as 0.1 + 0.15 log(n - 1);
  // and half the known sessions are "flat" objects whose evidence per pair is as low as an unknown one's, which must
  // not count against them. 12 steps per session, the first (1 reading) unused.
  std::vector<CalibrationSession> sessions;
  for (std::size_t t = 0; t < 200; ++t) {
    util::Rng rng(7, t);
    CalibrationSession s;
    s.known = t % 3 != 0;
    const bool flat = s.known && t % 2 == 0;
    for (std::size_t n = 1; n <= 12; ++n) {
      EvidenceLevel level;
      level.readings = n;
      level.object_log2_mass = {0.0, -5.0};
      const bool fine_pose = n >= 6;
      level.best_bits_per_pair = std::max(0.0, (s.known && !(flat && fine_pose) ? 3.0 : 1.0) + 0.5 * rng.normal());
      const double drift = s.known || n < 2 ? 0.0 : 0.15 * std::log(static_cast<double>(n - 1));
      level.fit_cost_share = fine_pose ? std::max(0.0, 0.1 + drift + 0.05 * rng.normal()) : -1.0;
      s.steps.push_back(level);
    }
    sessions.push_back(std::move(s));
  }
  Calibration c;
  fit_unknown(sessions, &c);
  REQUIRE(c.unknown.per_readings.size() == 23);  // n = 2 .. 24: twice the sessions' length
  CHECK(c.unknown.features == UnknownFeatureSet::evidence_then_fit);
  const auto& k = c.unknown.per_readings;
  for (std::size_t i = 0; i < kUnknownFeatures + 1; ++i) {
    // log(4 - 1) lies log(3) / log(7) of the way from n = 2 (log 1 = 0) to n = 8.
    CHECK(k[2][i] == Approx(k[0][i] + (k[6][i] - k[0][i]) * std::log(3.0) / std::log(7.0)).margin(1e-9));
  }
  for (const auto& row : k) {
    CHECK(row[1] < 0.0);  // more evidence per pair: less likely unknown (before the fine pose)
    CHECK(row[4] > 0.0);  // a costlier fit: more likely unknown (from it on)
  }
  EvidenceLevel level;
  level.object_log2_mass = {0.0, -5.0};
  for (std::size_t n : {3, 5}) {
    level.readings = n;
    level.best_bits_per_pair = 3.0;
    const double high = c.p_unknown(level, 0.5);
    level.best_bits_per_pair = 1.0;
    const double low = c.p_unknown(level, 0.5);
    CHECK(high < 0.3);
    CHECK(low > high + 0.2);
  }
  level.best_bits_per_pair = 1.0;  // a flat known object's evidence, or an unknown one's: the fit decides
  for (std::size_t n : {6, 12, 20}) {
    level.readings = n;
    level.fit_cost_share = 0.1;
    CHECK(c.p_unknown(level, 0.5) < 0.3);
    level.fit_cost_share = 0.1 + 0.15 * std::log(static_cast<double>(n - 1));
    CHECK(c.p_unknown(level, 0.5) > 0.7);
  }
  level.readings = 100;  // past the written-out counts: the last model
  level.fit_cost_share = 0.3;
  Calibration last = c;
  last.unknown.per_readings = {k.back()};
  CHECK(c.p_unknown(level, 0.1) == last.p_unknown(level, 0.1));
  // Sessions too short for a fine pose: the evidence model alone, read as earlier builds read theirs.
  std::vector<CalibrationSession> short_sessions = sessions;
  for (CalibrationSession& s : short_sessions) s.steps.resize(5);
  fit_unknown(short_sessions, &c);
  CHECK(c.unknown.features == UnknownFeatureSet::evidence_gap_share);
  level.readings = 4;
  level.fit_cost_share = -1.0;
  level.best_bits_per_pair = 3.0;
  const double high = c.p_unknown(level, 0.5);
  level.best_bits_per_pair = 1.0;
  CHECK(c.p_unknown(level, 0.5) > high + 0.2);
  // Without unknown sessions there is nothing to fit.
  for (CalibrationSession& s : sessions) s.known = true;
  fit_unknown(sessions, &c);
  CHECK(c.unknown.empty());
}

TEST_CASE("held-out sessions run side by side give every session's evidence whatever the thread count") {
  const Scene scene = load_scene("tiny");
  sim::SimulateOptions so;
  so.train_per_object = 60;
  so.test_per_object = 1;
  so.seed = 4;
  const Dataset data = sim::simulate(scene, so).train;
  TrainOptions to;
  to.clusters = 6;
  const TrainParameters params = resolve_train_parameters(scene, to);
  const CalibrationSplit split = split_for_calibration(data, 0.3, 7, false);
  const std::shared_ptr<PairMap> map = train_pair_map(split.map_part, params, nullptr);
  HeldOutSessionOptions options;
  options.known_sessions = 7;
  options.readings = 5;
  options.seed = 9;
  auto run = [&](unsigned threads) {
    HeldOutSessionOptions o = options;
    o.threads = threads;
    return run_held_out_sessions(*map, split, o);
  };
  const std::vector<CalibrationSession> one = run(1);
  REQUIRE(one.size() == 7);
  std::size_t objects_seen = 0;
  for (std::uint32_t o = 0; o < map->objects.size(); ++o)
    objects_seen += std::any_of(one.begin(), one.end(), [&](const CalibrationSession& s) { return s.object == o; });
  CHECK(objects_seen == map->objects.size());  // sessions cycle through the objects
  for (unsigned threads : {2u, 3u}) {
    const std::vector<CalibrationSession> many = run(threads);
    REQUIRE(many.size() == one.size());
    for (std::size_t t = 0; t < one.size(); ++t) {
      INFO("threads " << threads << ", session " << t);
      CHECK(many[t].known == one[t].known);
      CHECK(many[t].object == one[t].object);
      REQUIRE(many[t].steps.size() == options.readings);
      for (std::size_t n = 0; n < options.readings; ++n) {
        const EvidenceLevel &a = one[t].steps[n], &b = many[t].steps[n];
        CHECK(b.readings == a.readings);
        CHECK(b.object_log2_mass == a.object_log2_mass);  // exact: the same bits
        CHECK(b.best_bits_per_pair == a.best_bits_per_pair);
        CHECK(b.fit_cost_share == a.fit_cost_share);
        CHECK(b.surface_log2_fit == a.surface_log2_fit);
      }
    }
  }
}
