// The reading stage (host/src/reading): a raw Reading checked once and described (describe_reading), an observed
// reading checked against the map (validated), and put in the pose grid's frame (to_grid). Each refusal names the
// reading (`what`) and the fault; what passes is normalised, so that later stages check nothing again.
#include <catch2/catch.hpp>

#include <sva/base/so3.hpp>
#include <sva/error.hpp>

#include <cmath>
#include <limits>
#include <numbers>

#include "map/map_access.hpp"
#include "reading/observed_reading.hpp"
#include "recognition/fixture.hpp"
#include "recognition/trained_map.hpp"

using namespace sva;
using namespace sva::test;

TEST_CASE("reading: a raw reading the recogniser cannot use is refused, naming the reading and the fault") {
  const Trained& t = trained();
  const PairMap& map = MapAccess::pair_map(t.map);
  util::Rng rng(43);
  const Reading good = reading_of(t.data.scene.sensor, world_point(t.spec, 0, 0), RigidPose{}, rng);
  const ObservedReading seen = describe_reading(map, good, "reading 3");
  CHECK(seen.position == good.position);
  for (int k = 0; k < 3; ++k) CHECK(seen.normal[k] == Approx(good.normal[k]).margin(1e-12));
  CHECK_FALSE(seen.classes.empty());
  CHECK(seen.depth_mm.size() == good.pressure.size());  // the image as the pad pressed, for the surface model

  Reading bad = good;
  bad.status = ControllerStatus::no_contact;
  CHECK_THROWS_WITH(describe_reading(map, bad, "reading 3"),
                    Catch::StartsWith("reading 3: the contact controller did not converge"));
  bad = good;
  bad.pressure.resize(10);
  CHECK_THROWS_WITH(describe_reading(map, bad, "reading 3"),
                    Catch::StartsWith("reading 3: 10 pressure values, but the map's sensor has"));
  bad = good;
  bad.rows = 4;
  bad.cols = 9;
  CHECK_THROWS_WITH(describe_reading(map, bad, "reading 3"),
                    Catch::StartsWith("reading 3: the pressure image is 4 x 9"));
  bad = good;
  bad.pressure[5] = std::numeric_limits<float>::infinity();
  CHECK_THROWS_WITH(describe_reading(map, bad, "reading 3"), Catch::Contains("non-finite value"));
  bad = good;
  bad.position.x = std::nan("");
  CHECK_THROWS_WITH(describe_reading(map, bad, "reading 3"),
                    Catch::StartsWith("reading 3") && Catch::Contains("position is not finite"));
}

TEST_CASE("reading: an observed reading is checked against the map and normalised") {
  const PairMap& map = MapAccess::pair_map(trained().map);
  ObservedReading r;
  r.position = {1, 2, 3};
  r.normal = {0, 0, 2};
  r.norm_conf = 0.5f;
  r.classes = {{0, 1.0f}, {1, 3.0f}};
  const ObservedReading v = validated(r, map, "by hand");
  CHECK(v.normal == glm::dvec3(0, 0, 1));
  REQUIRE(v.classes.size() == 2);
  CHECK(v.classes[0].weight == Approx(0.25));
  CHECK(v.classes[1].weight == Approx(0.75));

  const auto refused = [&](ObservedReading bad, const char* fault) {
    CHECK_THROWS_WITH(validated(bad, map, "by hand"), Catch::StartsWith("by hand") && Catch::Contains(fault));
  };
  ObservedReading bad = r;
  bad.position.z = 2e7;
  refused(bad, "more than 10 km");
  bad = r;
  bad.normal = {0, 0, 0};
  refused(bad, "zero length");
  bad = r;
  bad.norm_conf = 1.5f;
  refused(bad, "normConf");
  bad = r;
  bad.classes.clear();
  refused(bad, "no appearance class");
  bad = r;
  bad.classes = {{map.key_space.n_classes + 3, 1.0f}};
  refused(bad, "is not one of the map's");
  bad = r;
  bad.classes = {{0, 0.0f}};
  refused(bad, "all appearance class weights are zero");
}

TEST_CASE("reading: to_grid puts a reading in the pose grid's frame, the box placed anywhere in the workspace") {
  const Trained& t = trained();
  const PairMap& map = MapAccess::pair_map(t.map);
  util::Rng rng(7);
  const ObservedReading robot =
      describe_reading(map, reading_of(t.data.scene.sensor, world_point(t.spec, 1, 4), RigidPose{}, rng), "reading 0");
  // Identity workspace: the robot frame is the grid's.
  const PoseSpace at_origin(paper_space(), 3);
  const ObservedReading same = to_grid(at_origin, robot);
  CHECK(same.position == robot.position);
  CHECK(same.normal.z == Approx(robot.normal.z));
  // A box turned a quarter about z and moved: the reading is where the box's frame sees it.
  const glm::dmat3 quarter = so3::exp(glm::dvec3(0, 0, std::numbers::pi / 2));
  const PoseSpace placed(placed_pose_space(paper_space(), {100, -50, 20}, 150.0, quarter), 3);
  const ObservedReading grid = to_grid(placed, robot);
  const RigidPose box = placed.workspace();
  const glm::dvec3 back = box.apply(grid.position);
  for (int k = 0; k < 3; ++k) {
    CHECK(back[k] == Approx(robot.position[k]).margin(1e-9));
    CHECK(box.rotate(grid.normal)[k] == Approx(robot.normal[k]).margin(1e-12));
    CHECK(box.rotate(grid.x_axis)[k] == Approx(robot.x_axis[k]).margin(1e-12));
  }
  CHECK(glm::length(grid.normal) == Approx(1.0).margin(1e-15));
  double sum = 0.0;
  for (const ClassWeight& c : grid.classes) sum += c.weight;
  CHECK(sum == Approx(1.0).margin(1e-12));
  CHECK(grid.depth_mm == robot.depth_mm);
}
