// The public Recognizer on a map trained by the map builder from a small
// synthetic dataset with pressure images: SVA and the appearance-only baseline,
// refused readings and options.
#include <catch2/catch.hpp>

#include <sva/error.hpp>
#include <sva/recognizer.hpp>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "calibration/calibration.hpp"
#include "fixture.hpp"
#include "map/map_access.hpp"
#include "trained_map.hpp"

using namespace sva;
using namespace sva::test;

TEST_CASE("Recognizer: SVA on a trained map finds the object and its pose") {
  const Trained& t = trained();
  for (std::uint32_t object = 0; object < 3; ++object) {
    Recognizer rec(t.map, paper_space());
    const RigidPose truth = random_pose(600 + object, 100.0);
    util::Rng rng(41, object);
    for (int i = 0; i < 14; ++i)
      rec.add_reading(reading_of(t.data.scene.sensor,
                                 world_point(t.spec, static_cast<int>(object), static_cast<int>(rng.below(70))), truth,
                                 rng));
    const Estimate e = rec.estimate(5);
    INFO("object " << object << " probability " << e.object_probability[object]);
    CHECK(e.readings == 14);
    CHECK(e.ready);
    CHECK(e.object == object);
    CHECK(e.object_name == "obj" + std::to_string(object));
    double sum = 0;
    for (double p : e.object_probability) sum += p;
    CHECK(sum == Approx(1.0));
    REQUIRE(e.pose_valid);
    CHECK(e.top.size() == 5);
    CHECK(e.votes > 0);
    if (e.object == object) CHECK(glm::length(e.pose.T - truth.T) < 1.5 * bin_width(paper_space()));
    rec.reset();
    CHECK(rec.reading_count() == 0);
    CHECK_FALSE(rec.estimate().pose_valid);
  }
}

TEST_CASE("Recognizer: before any reading the estimate is not ready and names no object") {
  const Trained& t = trained();
  Recognizer rec(t.map, paper_space());
  Estimate e = rec.estimate(5);
  CHECK_FALSE(e.ready);
  CHECK_FALSE(e.pose_valid);
  CHECK(e.object_name.empty());
  CHECK(e.top.empty());
  CHECK(e.hypotheses.empty());
  CHECK(e.object_hypotheses.empty());
  CHECK(e.object_probability == std::vector<double>(3, 1.0 / 3.0));
  rec.set_prior(Prior{.object_probability = {1.0, 2.0, 1.0}});
  CHECK(rec.estimate().object_probability == std::vector<double>{0.25, 0.5, 0.25});  // the prior, not evidence
  CHECK_FALSE(rec.estimate().ready);
}

TEST_CASE("Map: the sensor's shape, and a reading of another shape is refused naming both") {
  const Trained& t = trained();
  CHECK(t.map.sensor().rows == t.data.scene.sensor.rows);
  CHECK(t.map.sensor().cols == t.data.scene.sensor.cols);
  util::Rng rng(3);
  Reading r = reading_of(t.data.scene.sensor, world_point(t.spec, 1, 0), RigidPose{}, rng);
  Recognizer rec(t.map, paper_space());
  r.rows = 4;
  r.cols = 9;
  CHECK_THROWS_WITH(rec.add_reading(r),
                    Catch::Contains("the pressure image is 4 x 9, but the map's sensor is " +
                                    std::to_string(t.map.sensor().rows) + " x " + std::to_string(t.map.sensor().cols)));
  r.rows = t.map.sensor().rows;
  r.cols = t.map.sensor().cols;
  rec.add_reading(r);
  CHECK(rec.reading_count() == 1);
  CHECK(rec.estimate().ready);
}

TEST_CASE("Recognizer: the appearance-only baseline gives object probabilities without a pose") {
  const Trained& t = trained();
  RecognizerOptions o;
  o.method = Method::appearance;
  Recognizer rec(t.map, paper_space(), o);
  util::Rng rng(42);
  for (int i = 0; i < 10; ++i)
    rec.add_reading(
        reading_of(t.data.scene.sensor, world_point(t.spec, 1, static_cast<int>(rng.below(70))), RigidPose{}, rng));
  const Estimate e = rec.estimate();
  CHECK_FALSE(e.pose_valid);
  REQUIRE(e.object_probability.size() == 3);
  double sum = 0;
  for (double p : e.object_probability) {
    CHECK(std::isfinite(p));
    sum += p;
  }
  CHECK(sum == Approx(1.0));
}

TEST_CASE("Recognizer: refused readings, options and maps") {
  const Trained& t = trained();
  util::Rng rng(43);
  Recognizer rec(t.map, paper_space());
  Reading r = reading_of(t.data.scene.sensor, world_point(t.spec, 0, 0), RigidPose{}, rng);
  Reading bad = r;
  bad.status = ControllerStatus::not_converged;
  CHECK_THROWS_WITH(rec.add_reading(bad), Catch::Contains("converge"));
  bad = r;
  bad.pressure.assign(bad.pressure.size(), 0.0f);  // empty image
  CHECK_THROWS_AS(rec.add_reading(bad), Error);
  bad = r;
  bad.pressure[3] = std::nanf("");
  CHECK_THROWS_WITH(rec.add_reading(bad), Catch::Contains("non-finite"));
  bad = r;
  bad.pressure.resize(10);
  CHECK_THROWS_WITH(rec.add_reading(bad), Catch::Contains("pressure values"));
  bad = r;
  bad.position.y = std::nan("");
  CHECK_THROWS_AS(rec.add_reading(bad), Error);
  bad = r;
  bad.pressure.assign(bad.pressure.size(), 1e6f);  // saturated: uniform image, described or refused, never NaN
  try {
    rec.add_reading(bad);
  } catch (const Error&) {
  }
  CHECK(rec.reading_count() <= 1);
  const Estimate e = rec.estimate();
  for (double p : e.object_probability) CHECK(std::isfinite(p));

  CHECK_THROWS_WITH(Recognizer(t.map, letters_space()), Catch::Contains("planar"));
  PoseSpaceSpec empty = paper_space();
  empty.translation_bins = 0;
  CHECK_THROWS_AS(Recognizer(t.map, empty), Error);
  RecognizerOptions eps;
  eps.eps = -1.0;
  CHECK_THROWS_WITH(Recognizer(t.map, paper_space(), eps), Catch::Contains("eps"));
  CHECK_THROWS_AS(Recognizer(Map{}, paper_space()), Error);
}

// Votes are rounded to nearest 2^-24 units: a vote below half a unit adds no
// mass, and the estimate counts it in votes_zero instead of losing it silently.
TEST_CASE("Recognizer: votes whose mass rounds to zero are counted in the estimate") {
  const Trained& t = trained();
  // The same map with every entry weight scaled by 1e-9: likelihoods (Eq 15) mostly stay above their 2^-40
  // resolution, but no beta sample of a match reaches half a vote unit.
  auto faint = std::make_shared<PairMap>(MapAccess::pair_map(t.map));
  for (float& w : faint->entry_weight) w *= 1e-9f;
  const Map faint_map = MapAccess::wrap(faint);
  const RigidPose truth = random_pose(700, 100.0);
  Recognizer normal(t.map, paper_space()), quiet(faint_map, paper_space());
  util::Rng rng(43);
  for (int i = 0; i < 6; ++i) {
    const Reading r =
        reading_of(t.data.scene.sensor, world_point(t.spec, 0, static_cast<int>(rng.below(70))), truth, rng);
    normal.add_reading(r);
    quiet.add_reading(r);
  }
  const Estimate n = normal.estimate(1), q = quiet.estimate(1);
  REQUIRE(n.votes > 0);
  CHECK(n.votes_zero < n.votes);
  // Matches whose likelihood falls below 2^-40 cast no vote at all; every other sample lands where it did
  // and rounds to 0.
  CHECK(q.votes > 0);
  CHECK(q.votes <= n.votes);
  CHECK(q.votes_zero == q.votes);
  CHECK_FALSE(q.pose_valid);  // nothing was folded
  quiet.reset();
  CHECK(quiet.estimate(1).votes_zero == 0);
}

// The workspace frame (PoseSpaceSpec::workspace): the map was trained around the object's origin, and the same
// map recognises the object far from the robot frame's origin once the box is placed there.
TEST_CASE("Recognizer: a workspace frame recognises the object where the box is placed") {
  const Trained& t = trained();
  const RigidPose truth = random_pose(610, 60.0);
  RigidPose workspace;
  workspace.R = so3::exp(glm::dvec3(0.3, -0.2, 0.5));
  workspace.T = {700.0, -350.0, 420.0};
  Recognizer at_origin(t.map, paper_space());
  Recognizer placed(t.map, placed_pose_space(paper_space(), workspace.T, 200.0, workspace.R));
  Recognizer unplaced(t.map, paper_space());
  util::Rng pick(44);
  for (int i = 0; i < 10; ++i) {
    const WorldPoint w = world_point(t.spec, 2, static_cast<int>(pick.below(70)));
    util::Rng image_a(45, static_cast<std::uint64_t>(i)), image_b(45, static_cast<std::uint64_t>(i)),
        image_c(45, static_cast<std::uint64_t>(i));
    at_origin.add_reading(reading_of(t.data.scene.sensor, w, truth, image_a));
    placed.add_reading(reading_of(t.data.scene.sensor, w, workspace * truth, image_b));
    unplaced.add_reading(reading_of(t.data.scene.sensor, w, workspace * truth, image_c));
  }
  const Estimate a = at_origin.estimate(3), b = placed.estimate(3), c = unplaced.estimate(3);
  REQUIRE(a.pose_valid);
  REQUIRE(b.pose_valid);
  CHECK(b.object == a.object);
  for (std::size_t o = 0; o < a.object_probability.size(); ++o)
    CHECK(b.object_probability[o] == Approx(a.object_probability[o]).margin(1e-9));
  // Poses come back in the robot frame: the placed recognizer's pose is the workspace times the other's.
  const RigidPose expected = workspace * a.pose;
  CHECK(glm::length(b.pose.T - expected.T) < 0.5);
  CHECK(angle_between(b.pose.R, expected.R) < 0.01);
  CHECK(glm::length(b.bin_pose.T - (workspace * a.bin_pose).T) < 1e-6);
  // The box at the robot frame's origin does not contain the object: every vote falls outside.
  CHECK(c.votes == 0);
  CHECK(c.votes_outside > 0);
  CHECK_FALSE(c.pose_valid);
}

TEST_CASE("Recognizer: distinct hypotheses carry a mass and a covariance, the best one the estimate's pose") {
  const Trained& t = trained();
  Recognizer rec(t.map, paper_space());
  const RigidPose truth = random_pose(620, 100.0);
  util::Rng rng(46);
  for (int i = 0; i < 10; ++i)
    rec.add_reading(
        reading_of(t.data.scene.sensor, world_point(t.spec, 1, static_cast<int>(rng.below(70))), truth, rng));
  const Estimate e = rec.estimate(4);
  REQUIRE(e.pose_valid);
  REQUIRE(!e.hypotheses.empty());
  CHECK(e.hypotheses.size() <= 4);
  double mass = 0.0;
  for (const PoseHypothesis& h : e.hypotheses) {
    CHECK(h.valid);
    CHECK(h.probability >= 0.0);  // a mode far below the best rounds to 0, as the object posterior does
    mass += h.probability;
    for (int a = 0; a < 6; ++a) CHECK(h.covariance[a * 6 + a] > 0.0);
  }
  CHECK(e.hypotheses[0].probability > 0.0);
  CHECK(mass <= 1.0 + 1e-12);
  // No two hypotheses of one object share a bin neighbourhood: their centres are more than a bin apart.
  for (std::size_t i = 0; i < e.hypotheses.size(); ++i)
    for (std::size_t j = 0; j < i; ++j)
      if (e.hypotheses[i].object == e.hypotheses[j].object)
        CHECK((glm::length(e.hypotheses[i].pose.T - e.hypotheses[j].pose.T) > 0.5 * bin_width(paper_space()) ||
               angle_between(e.hypotheses[i].pose.R, e.hypotheses[j].pose.R) > 0.3));
  REQUIRE(e.object_hypotheses.size() == 3);
  CHECK(e.object_hypotheses[e.object].valid);
  CHECK(glm::length(e.object_hypotheses[e.object].pose.T - e.pose.T) == 0.0);
  CHECK(e.object_hypotheses[e.object].probability <= e.object_probability[e.object] + 1e-9);
  CHECK(rec.estimate(0).hypotheses.empty());
  RecognizerOptions wide;
  wide.hypothesis_radius_bins = 5;
  CHECK_THROWS_WITH(Recognizer(t.map, paper_space(), wide), Catch::Contains("hypothesis_radius_bins"));
}

TEST_CASE("Recognizer: a prior over objects decides what touch cannot, and a flat one changes nothing") {
  const Trained& t = trained();
  const RigidPose truth = random_pose(630, 100.0);
  Recognizer plain(t.map, paper_space()), flat(t.map, paper_space()), camera(t.map, paper_space());
  flat.set_prior({{0.2, 0.2, 0.2}});
  // One reading makes no pair: touch alone cannot tell the objects apart, the prior decides.
  camera.set_prior({{0.1, 0.2, 0.7}});
  util::Rng rng(47);
  const Reading first =
      reading_of(t.data.scene.sensor, world_point(t.spec, 0, static_cast<int>(rng.below(70))), truth, rng);
  plain.add_reading(first);
  flat.add_reading(first);
  camera.add_reading(first);
  CHECK(plain.estimate().object_probability[2] == Approx(1.0 / 3.0));
  CHECK(camera.estimate().object == 2);
  CHECK(camera.estimate().object_probability[2] == Approx(0.7));
  for (int i = 0; i < 2; ++i) {
    const Reading r =
        reading_of(t.data.scene.sensor, world_point(t.spec, 0, static_cast<int>(rng.below(70))), truth, rng);
    plain.add_reading(r);
    flat.add_reading(r);
    camera.add_reading(r);
  }
  const Estimate p = plain.estimate(3), f = flat.estimate(3), c = camera.estimate(3);
  CHECK(f.object_probability == p.object_probability);
  CHECK(f.object == p.object);
  REQUIRE(f.hypotheses.size() == p.hypotheses.size());
  for (std::size_t i = 0; i < p.hypotheses.size(); ++i)
    CHECK(f.hypotheses[i].probability == p.hypotheses[i].probability);
  // With evidence, the posterior is the evidence times the prior, renormalised.
  const double w[3] = {0.1 / 0.7, 0.2 / 0.7, 1.0};
  double z = 0.0;
  for (int o = 0; o < 3; ++o) z += p.object_probability[o] * w[o];
  for (int o = 0; o < 3; ++o) CHECK(c.object_probability[o] == Approx(p.object_probability[o] * w[o] / z));
  // A prior strong enough against the evidence's winner overturns it.
  std::vector<double> strong(3, 1.0);
  strong[p.object] = 1e-12;
  camera.set_prior({strong});
  CHECK(camera.estimate().object != p.object);
  // Reset forgets the prior with the readings.
  camera.reset();
  camera.add_reading(first);
  CHECK(camera.estimate().object_probability[2] == Approx(1.0 / 3.0));
  // Priors that do not fit the map are refused.
  CHECK_THROWS_WITH(camera.set_prior({{0.5, 0.5}}), Catch::Contains("2 object probabilities"));
  CHECK_THROWS_WITH(camera.set_prior({{0.5, -0.1, 0.5}}), Catch::Contains("object 1"));
  CHECK_THROWS_WITH(camera.set_prior({{0.5, std::nan(""), 0.5}}), Catch::Contains("finite"));
  CHECK_THROWS_WITH(camera.set_prior({{0.0, 0.0, 0.0}}), Catch::Contains("every object probability is 0"));
}

TEST_CASE("Recognizer: the estimate's fits and hypotheses are the same on one thread and on several") {
  const Trained& t = trained();
  RecognizerOptions one, several;
  one.backend = several.backend = BackendKind::cpu;
  one.threads = 1;
  several.threads = 2;  // the check's three objects and their starts interleave on the workers
  Recognizer a(t.map, paper_space(), one), b(t.map, paper_space(), several);
  const RigidPose truth = random_pose(611, 100.0);
  util::Rng rng(43);
  for (int i = 0; i < 10; ++i) {
    const Reading r =
        reading_of(t.data.scene.sensor, world_point(t.spec, 2, static_cast<int>(rng.below(70))), truth, rng);
    a.add_reading(r);
    b.add_reading(r);
    const Estimate ea = a.estimate(5), eb = b.estimate(5);
    INFO("reading " << i + 1);
    CHECK(ea.object == eb.object);
    CHECK(ea.object_probability == eb.object_probability);
    CHECK(ea.p_unknown == eb.p_unknown);
    CHECK(ea.pose_refined == eb.pose_refined);
    CHECK(ea.pose.T == eb.pose.T);
    CHECK(ea.pose.R == eb.pose.R);
    // Each object's best mode and the distinct modes, their neighbourhoods' moments computed on the workers.
    REQUIRE(ea.object_hypotheses.size() == eb.object_hypotheses.size());
    REQUIRE(ea.hypotheses.size() == eb.hypotheses.size());
    for (std::size_t o = 0; o < ea.object_hypotheses.size(); ++o) {
      CHECK(ea.object_hypotheses[o].probability == eb.object_hypotheses[o].probability);
      CHECK(ea.object_hypotheses[o].covariance == eb.object_hypotheses[o].covariance);
      CHECK(ea.object_hypotheses[o].pose.T == eb.object_hypotheses[o].pose.T);
    }
    for (std::size_t m = 0; m < ea.hypotheses.size(); ++m) {
      CHECK(ea.hypotheses[m].object == eb.hypotheses[m].object);
      CHECK(ea.hypotheses[m].probability == eb.hypotheses[m].probability);
      CHECK(ea.hypotheses[m].covariance == eb.hypotheses[m].covariance);
    }
  }
  CHECK(a.estimate().pose_refined);  // the fits ran (6 readings and more)
}

TEST_CASE("Recognizer: the fine pose and the surface check start at the reading count the map keeps") {
  const Trained& t = trained();
  TrainOptions o;
  o.calibrate = false;  // the default calibration in both maps: the start is all that differs
  o.fine_pose_from = 4;
  const Map early = Map::train(t.data, o);
  CHECK(early.fine_pose_from() == 4);
  CHECK(t.map.fine_pose_from() == Calibration::kFinePoseFromSpatial);
  RecognizerOptions ro;
  ro.backend = BackendKind::cpu;
  int refined_early = 0;
  for (std::uint64_t session = 0; session < 4; ++session) {
    Recognizer a(t.map, paper_space(), ro), b(early, paper_space(), ro);
    for (const Reading& r : readings_at(1, random_pose(700 + session, 100.0), util::Rng(44, session), 7)) {
      a.add_reading(r);
      b.add_reading(r);
      const Estimate ea = a.estimate(), eb = b.estimate();
      const std::size_t n = a.reading_count();
      INFO("session " << session << ", reading " << n);
      if (n < 4) {  // before either start: the same estimate (from it on, a fit also needs as many inliers)
        CHECK(ea.object_probability == eb.object_probability);
        CHECK_FALSE(eb.pose_refined);
        CHECK(ea.pose.T == eb.pose.T);
      } else if (n < 6) {
        CHECK_FALSE(ea.pose_refined);
        refined_early += eb.pose_refined ? 1 : 0;
      }
    }
  }
  CHECK(refined_early > 0);  // the early map fitted at 4 and 5 readings
  o.fine_pose_from = 2;      // too few contacts to fit a pose: refused by name
  CHECK_THROWS_WITH(Map::train(t.data, o), Catch::Contains("fine pose from 2 readings"));
}

TEST_CASE("Recognizer: the estimate's evidence is what its object probabilities are made of") {
  const Trained& t = trained();
  RecognizerOptions plain;
  plain.backend = BackendKind::cpu;
  plain.calibrate = false;  // Eq 5's posterior with the surfaces' bits as they are: 2^(pairs + surface), normalised
  RecognizerOptions calibrated;
  calibrated.backend = BackendKind::cpu;
  Recognizer raw(t.map, paper_space(), plain), cal(t.map, paper_space(), calibrated);
  CHECK(raw.estimate().evidence.pairs_log2_mass.empty());  // not ready: no evidence yet
  std::size_t with_surfaces = 0;
  for (const Reading& r : readings_at(2, random_pose(710, 100.0), util::Rng(45, 1), 12)) {
    raw.add_reading(r);
    cal.add_reading(r);
    const Estimate e = raw.estimate(), c = cal.estimate();
    INFO("reading " << raw.reading_count());
    const ObjectEvidence& ev = e.evidence;
    REQUIRE(ev.pairs_log2_mass.size() == e.object_probability.size());
    CHECK(ev.temperature == 1.0);
    std::vector<double> q(ev.pairs_log2_mass);
    if (!ev.surface_log2_fit.empty()) {
      REQUIRE(ev.surface_log2_fit.size() == q.size());
      CHECK(ev.surface_weight == 1.0);
      for (std::size_t o = 0; o < q.size(); ++o) q[o] += ev.surface_log2_fit[o];
      ++with_surfaces;
    }
    const double top = *std::max_element(q.begin(), q.end());
    double z = 0.0;
    for (double v : q) z += std::exp2(v - top);
    // The masses are the belief summary's (an object's far tail bounded rather than summed): a part in a thousand.
    for (std::size_t o = 0; o < q.size(); ++o)
      CHECK(e.object_probability[o] == Approx(std::exp2(q[o] - top) / z).epsilon(1e-3).margin(1e-9));
    // Calibrated: the map's temperature and surface weight, which weigh the same parts into its ranking.
    const ObjectEvidence& cv = c.evidence;
    CHECK(cv.pairs_log2_mass == ev.pairs_log2_mass);
    CHECK(cv.surface_log2_fit == ev.surface_log2_fit);
    if (raw.reading_count() >= 2) CHECK(cv.temperature != 1.0);
    std::vector<double> w(q.size());
    for (std::size_t o = 0; o < w.size(); ++o)
      w[o] = cv.temperature * cv.pairs_log2_mass[o] +
             (cv.surface_log2_fit.empty() ? 0.0 : cv.surface_weight * cv.surface_log2_fit[o]);
    CHECK(static_cast<std::uint32_t>(std::max_element(w.begin(), w.end()) - w.begin()) == c.object);
  }
  CHECK(with_surfaces > 0);  // the surface check ran from the fine pose on
}
