// The public Recognizer on a map trained by the map builder from a small
// synthetic dataset with pressure images: SVA and the appearance-only baseline,
// refused readings and options.
#include <catch2/catch.hpp>

#include <sva/error.hpp>
#include <sva/recognizer.hpp>

#include <cmath>
#include <numbers>

#include "fixture.hpp"

using namespace sva;
using namespace sva::test;

namespace {

// A blob image whose shape is the point's texture, rotated at random about the
// normal (the controllers leave that rotation free).
std::vector<float> texture_image(const SensorSpec& sensor, std::uint32_t texture, double angle) {
  const double shapes[4][2] = {{3.0, 3.0}, {0.8, 3.5}, {1.5, 2.5}, {0.9, 1.0}};
  const double sx = shapes[texture % 4][0], sy = shapes[texture % 4][1];
  std::vector<float> img(static_cast<std::size_t>(sensor.elements()));
  const double c = std::cos(angle), s = std::sin(angle);
  for (int r = 0; r < sensor.rows; ++r)
    for (int col = 0; col < sensor.cols; ++col) {
      const double x = col - 0.5 * (sensor.cols - 1), y = r - 0.5 * (sensor.rows - 1);
      const double u = c * x + s * y, v = -s * x + c * y;
      img[static_cast<std::size_t>(r * sensor.cols + col)] =
          static_cast<float>(30.0 * std::exp(-0.5 * (u * u / (sx * sx) + v * v / (sy * sy))));
    }
  return img;
}

Reading reading_of(const SensorSpec& sensor, const WorldPoint& w, std::uint32_t object, const RigidPose& pose,
                   util::Rng& rng) {
  Reading r;
  r.object = object;
  r.position = pose.apply(w.p);
  r.normal = pose.rotate(w.n);
  r.x_axis =
      glm::normalize(glm::cross(r.normal, std::fabs(r.normal.z) < 0.9 ? glm::dvec3(0, 0, 1) : glm::dvec3(1, 0, 0)));
  r.pressure = texture_image(sensor, w.cls, rng.uniform(0.0, 2.0 * std::numbers::pi));
  return r;
}

struct Trained {
  WorldSpec spec;
  Dataset data;
  Map map;
};

const Trained& trained() {
  static const Trained t = [] {
    Trained x;
    x.spec.classes = 4;
    x.spec.points = 70;
    x.data.scene.name = "synthetic-recognizer";
    for (int o = 0; o < x.spec.objects; ++o) {
      SceneObject so;
      so.name = "obj" + std::to_string(o);
      so.mesh = "/nonexistent.glb";
      x.data.scene.objects.push_back(so);
    }
    x.data.scene.appearance.descriptor = "mnti";
    x.data.scene.appearance.clusters = 4;
    x.data.scene.appearance.dist_bins = 12;
    x.data.scene.appearance.dist_min_mm = 5.0;
    x.data.scene.appearance.dist_max_mm = 80.0;
    x.data.split = "train";
    for (int o = 0; o < x.spec.objects; ++o)
      for (int i = 0; i < x.spec.points; ++i) {
        util::Rng rng(1, static_cast<std::uint64_t>(o), static_cast<std::uint64_t>(i));
        Sample s;
        s.reading =
            reading_of(x.data.scene.sensor, world_point(x.spec, o, i), static_cast<std::uint32_t>(o), RigidPose{}, rng);
        x.data.samples.push_back(s);
      }
    x.map = Map::train(x.data, {});
    return x;
  }();
  return t;
}

}  // namespace

TEST_CASE("Recognizer: SVA on a trained map finds the object and its pose") {
  const Trained& t = trained();
  for (std::uint32_t object = 0; object < 3; ++object) {
    Recognizer rec(t.map, paper_space());
    const RigidPose truth = random_pose(600 + object, 100.0);
    util::Rng rng(41, object);
    for (int i = 0; i < 14; ++i)
      rec.add_reading(reading_of(t.data.scene.sensor,
                                 world_point(t.spec, static_cast<int>(object), static_cast<int>(rng.below(70))), object,
                                 truth, rng));
    const Estimate e = rec.estimate(5);
    INFO("object " << object << " probability " << e.object_probability[object]);
    CHECK(e.readings == 14);
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
    CHECK(rec.readings() == 0);
    CHECK_FALSE(rec.estimate().pose_valid);
  }
}

TEST_CASE("Recognizer: the appearance-only baseline gives object probabilities without a pose") {
  const Trained& t = trained();
  RecognizerOptions o;
  o.method = Method::appearance;
  Recognizer rec(t.map, paper_space(), o);
  util::Rng rng(42);
  for (int i = 0; i < 10; ++i)
    rec.add_reading(
        reading_of(t.data.scene.sensor, world_point(t.spec, 1, static_cast<int>(rng.below(70))), 1, RigidPose{}, rng));
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
  Reading r = reading_of(t.data.scene.sensor, world_point(t.spec, 0, 0), 0, RigidPose{}, rng);
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
  CHECK(rec.readings() <= 1);
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
  auto faint = std::make_shared<PairMap>(t.map.internal());
  for (float& w : faint->entry_weight) w *= 1e-9f;
  const Map faint_map(faint);
  const RigidPose truth = random_pose(700, 100.0);
  Recognizer normal(t.map, paper_space()), quiet(faint_map, paper_space());
  util::Rng rng(43);
  for (int i = 0; i < 6; ++i) {
    const Reading r =
        reading_of(t.data.scene.sensor, world_point(t.spec, 0, static_cast<int>(rng.below(70))), 0, truth, rng);
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
