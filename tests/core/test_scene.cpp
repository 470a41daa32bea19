#include <catch2/catch.hpp>

#include <sva/error.hpp>
#include <sva/scene.hpp>

using Catch::Contains;

namespace {
sva::Scene parse(const std::string& s) { return sva::parse_scene(s, "/tmp/x/scene.json"); }
}  // namespace

TEST_CASE("scene JSON: defaults, paths and round trip") {
  auto s =
      parse(R"({"name": "t", "objects": [{"mesh": "m/cup.glb", "symmetry": {"type": "axis", "axis": [0, 0, 2]}}]})");
  REQUIRE(s.objects.size() == 1);
  CHECK(s.objects[0].name == "cup");
  CHECK(s.objects[0].mesh == "/tmp/x/m/cup.glb");
  CHECK(s.objects[0].symmetry.kind == sva::Symmetry::Kind::axis);
  CHECK(s.objects[0].symmetry.axis.z == Approx(1.0));
  CHECK(s.appearance.descriptor == "mnti");
  auto again = sva::parse_scene(sva::scene_to_json(s), "/tmp/x/again.json");
  CHECK(again.objects[0].mesh == s.objects[0].mesh);
  CHECK(again.sensor.rows == s.sensor.rows);
  auto planar = parse(
      R"({"objects": [{"mesh": "a.glb", "symmetry": {"type": "cyclic", "order": 2}}], "pose_space": {"kind": "planar"}})");
  CHECK(planar.appearance.descriptor == "mn");
  CHECK(planar.objects[0].symmetry.rotations.size() == 2);
}

TEST_CASE("scene JSON: every fault names the field") {
  CHECK_THROWS_WITH(parse("{"), Contains("scene.json") && Contains("invalid JSON"));
  CHECK_THROWS_WITH(parse("[]"), Contains("expected a JSON object"));
  CHECK_THROWS_WITH(parse("{}"), Contains("missing \"objects\""));
  CHECK_THROWS_WITH(parse(R"({"objects": []})"), Contains("non-empty"));
  CHECK_THROWS_WITH(parse(R"({"objects": [{"mesh": 3}]})"),
                    Contains("objects[0].mesh") && Contains("expected a string"));
  CHECK_THROWS_WITH(parse(R"({"objects": [{"mesh": "a.glb", "size": 3}]})"), Contains("unknown key \"size\""));
  CHECK_THROWS_WITH(parse(R"({"objects": [{"mesh": "a.glb"}, {"mesh": "a.glb"}]})"), Contains("duplicate"));
  CHECK_THROWS_WITH(parse(R"({"objects": [{"mesh": "a.glb"}], "sensor": {"rows": 0}})"), Contains("sensor.rows"));
  CHECK_THROWS_WITH(parse(R"({"objects": [{"mesh": "a.glb"}], "sensor": {"rows": "6"}})"), Contains("sensor.rows"));
  CHECK_THROWS_WITH(parse(R"({"objects": [{"mesh": "a.glb"}], "appearance": {"dist_range_mm": [50, 10]}})"),
                    Contains("min must be below max"));
  CHECK_THROWS_WITH(parse(R"({"objects": [{"mesh": "a.glb"}], "pose_space": {"kind": "4d"}})"),
                    Contains("pose_space.kind"));
  CHECK_THROWS_WITH(parse(R"({"objects": [{"mesh": "a.glb", "symmetry": {"type": "axis", "axis": [0, 0, 0]}}]})"),
                    Contains("zero length"));
  CHECK_THROWS_WITH(sva::load_scene("/nonexistent/scene.json"), Contains("/nonexistent/scene.json"));
  CHECK_THROWS_WITH(sva::load_scene("no-such-builtin"), Contains("no-such-builtin"));
}
