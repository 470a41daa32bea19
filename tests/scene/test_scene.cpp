#include <catch2/catch.hpp>

#include <sva/dataset.hpp>
#include <sva/error.hpp>
#include <sva/scene.hpp>

#include <cmath>
#include <nlohmann/json.hpp>

#include "test_support.hpp"

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

TEST_CASE("scene JSON: an object's family survives the round trip, and no family writes no key") {
  auto s = parse(R"({"objects": [{"mesh": "clamp_s.glb", "family": "clamps"}, {"mesh": "cup.glb"}]})");
  CHECK(s.objects[0].family == "clamps");
  CHECK(s.objects[1].family.empty());
  const std::string text = sva::scene_to_json(s);
  CHECK(text.find("\"family\"") != std::string::npos);
  CHECK(text.find("\"family\"") == text.rfind("\"family\""));  // once: the object without one writes none
  auto again = sva::parse_scene(text, "/tmp/x/again.json");
  CHECK(again.objects[0].family == "clamps");
  CHECK(again.objects[1].family.empty());
  CHECK_THROWS_WITH(parse(R"({"objects": [{"mesh": "a.glb", "family": ""}]})"),
                    Contains("objects[0].family") && Contains("empty family"));
  CHECK_THROWS_WITH(parse(R"({"objects": [{"mesh": "a.glb", "family": 3}]})"),
                    Contains("objects[0].family") && Contains("expected a string"));
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
  CHECK_THROWS_WITH(parse(R"({"objects": [{"mesh": "a.glb"}], "appearance": {"pair_readings": 1}})"),
                    Contains("appearance.pair_readings") && Contains("two readings"));
  CHECK_THROWS_WITH(parse(R"({"objects": [{"mesh": "a.glb"}], "appearance": {"pair_readings": -3}})"),
                    Contains("appearance.pair_readings"));
  CHECK(parse(R"({"objects": [{"mesh": "a.glb"}], "appearance": {"pair_readings": 300}})").appearance.pair_readings ==
        300);
  CHECK_THROWS_WITH(parse(R"({"objects": [{"mesh": "a.glb"}], "pose_space": {"kind": "4d"}})"),
                    Contains("pose_space.kind"));
  CHECK_THROWS_WITH(parse(R"({"objects": [{"mesh": "a.glb", "symmetry": {"type": "axis", "axis": [0, 0, 0]}}]})"),
                    Contains("zero length"));
  CHECK_THROWS_WITH(sva::load_scene("/nonexistent/scene.json"), Contains("/nonexistent/scene.json"));
  CHECK_THROWS_WITH(sva::load_scene("no-such-builtin"), Contains("no-such-builtin"));
}

TEST_CASE("scene JSON: names refuse control characters and take any other Unicode") {
  // Names reach terminals, CSV and pages (docs/scene-format.md, "Names"): U+0000-U+001F and U+007F are refused,
  // with the file, the field and the character's place.
  CHECK_THROWS_WITH(parse(R"({"objects": [{"mesh": "a.glb"}, {"mesh": "b.glb", "name": "b\u00e9l\u0007l"}]})"),
                    Contains("scene.json: objects[1].name: control character U+0007 at character 4"));
  CHECK_THROWS_WITH(parse(R"({"name": "s\u001b[31m", "objects": [{"mesh": "a.glb"}]})"),
                    Contains("scene.json: name: control character U+001B at character 2"));
  CHECK_THROWS_WITH(parse(R"({"objects": [{"mesh": "a.glb", "family": "f\u007f"}]})"),
                    Contains("objects[0].family: control character U+007F at character 2"));
  CHECK_THROWS_WITH(parse(R"({"objects": [{"mesh": "a.glb", "name": "\u0000"}]})"),
                    Contains("objects[0].name: control character U+0000 at character 1"));
  CHECK_THROWS_WITH(parse("{\"objects\": [{\"mesh\": \"tab\\u0009.glb\"}]}"),  // the mesh's stem, as the name
                    Contains("objects[0].name: control character U+0009"));
  // Markup, quotes, an RTL override, emoji and U+0080 (a C1 control, not refused): as written.
  const std::string hostile = "<img src=x onerror=\"alert('x')\"></script>\u202e\u00e9\U0001F600\u0080";
  const nlohmann::json scene = {{"name", hostile},
                                {"objects", {{{"mesh", "a.glb"}, {"name", hostile}, {"family", hostile}}}}};
  const sva::Scene s = parse(scene.dump());
  CHECK(s.name == hostile);
  CHECK(s.objects[0].name == hostile);
  CHECK(s.objects[0].family == hostile);
  CHECK(sva::parse_scene(sva::scene_to_json(s), "/tmp/x/again.json").objects[0].name == hostile);
}

TEST_CASE("scene JSON: a dataset whose scene names hold a control character is refused (sva train)") {
  // A scene made in memory (not parsed) carries one into a dataset file; reading it back names the file and field.
  sva::Dataset d;
  d.scene = parse(R"({"objects": [{"mesh": "a.glb"}]})");
  d.scene.objects[0].name = "a\nb";
  d.split = "train";
  const auto file = sva::test::temp_dir("scene-control") / "train.svad";
  sva::save_dataset(d, file);
  CHECK_THROWS_WITH(sva::load_dataset(file),
                    Contains("train.svad") && Contains("objects[0].name: control character U+000A at character 2"));
}

TEST_CASE("scene JSON: the errors block, its defaults and its round trip") {
  // No block is the ideal world: old scenes keep their meaning.
  auto ideal = parse(R"({"objects": [{"mesh": "a.glb"}]})");
  CHECK(ideal.errors.arm_ideal());
  CHECK(ideal.errors.gain_spread == 0.0);
  CHECK(ideal.errors.noise_kpa == 0.0);
  CHECK(ideal.errors.full_scale_kpa == 0.0);
  CHECK(ideal.errors.crosstalk == 0.0);
  auto s = parse(R"({"objects": [{"mesh": "a.glb"}], "errors": {"position_sigma_mm": 0.5, "normal_sigma_deg": 0.3,
      "gain_spread": 0.05, "offset_kpa": 0.2, "noise_kpa": 0.3, "full_scale_kpa": 200, "crosstalk": 0.02,
      "crosstalk_diagonal": 0.01, "train_sensor": 1, "test_sensor": 2, "comment": "a real sensor"}})");
  CHECK(s.errors.position_sigma_mm == 0.5);
  CHECK(s.errors.normal_sigma_deg == 0.3);
  CHECK(s.errors.gain_spread == 0.05);
  CHECK(s.errors.offset_kpa == 0.2);
  CHECK(s.errors.noise_kpa == 0.3);
  CHECK(s.errors.full_scale_kpa == 200);
  CHECK(s.errors.crosstalk == 0.02);
  CHECK(s.errors.crosstalk_diagonal == 0.01);
  CHECK(s.errors.train_sensor == 1u);
  CHECK(s.errors.test_sensor == 2u);
  auto again = sva::parse_scene(sva::scene_to_json(s), "/tmp/x/again.json");
  CHECK(again.errors.position_sigma_mm == s.errors.position_sigma_mm);
  CHECK(again.errors.crosstalk_diagonal == s.errors.crosstalk_diagonal);
  CHECK(again.errors.test_sensor == s.errors.test_sensor);
  // Only some fields: the others stay ideal.
  auto some = parse(R"({"objects": [{"mesh": "a.glb"}], "errors": {"noise_kpa": 1}})");
  CHECK(some.errors.noise_kpa == 1.0);
  CHECK(some.errors.arm_ideal());
}

TEST_CASE("scene JSON: every fault in the errors block names the field") {
  auto with = [](const std::string& errors) {
    return parse(R"({"objects": [{"mesh": "a.glb"}], "errors": )" + errors + "}");
  };
  CHECK_THROWS_WITH(with(R"({"position_sigma": 1})"), Contains("errors") && Contains("unknown key \"position_sigma\""));
  CHECK_THROWS_WITH(with(R"({"position_sigma_mm": -0.1})"),
                    Contains("errors.position_sigma_mm") && Contains("out of range"));
  CHECK_THROWS_WITH(with(R"({"normal_sigma_deg": "1"})"),
                    Contains("errors.normal_sigma_deg") && Contains("expected a number"));
  CHECK_THROWS_WITH(with(R"({"normal_sigma_deg": -2})"), Contains("errors.normal_sigma_deg"));
  CHECK_THROWS_WITH(with(R"({"gain_spread": 0.5})"), Contains("errors.gain_spread"));
  CHECK_THROWS_WITH(with(R"({"offset_kpa": -1})"), Contains("errors.offset_kpa"));
  CHECK_THROWS_WITH(with(R"({"noise_kpa": -1})"), Contains("errors.noise_kpa"));
  CHECK_THROWS_WITH(with(R"({"crosstalk": -0.01})"), Contains("errors.crosstalk"));
  CHECK_THROWS_WITH(with(R"({"crosstalk": 0.15, "crosstalk_diagonal": 0.12})"),
                    Contains("errors.crosstalk") && Contains(">= 1"));
  CHECK_THROWS_WITH(with(R"({"full_scale_kpa": 15})"),
                    Contains("errors.full_scale_kpa") && Contains("target_pressure_kpa"));
  CHECK_THROWS_WITH(with(R"({"train_sensor": -1})"), Contains("errors.train_sensor"));
  CHECK_THROWS_WITH(with(R"({"test_sensor": 1.5})"), Contains("errors.test_sensor") && Contains("integer"));
  CHECK_THROWS_WITH(with(R"([0.5])"), Contains("errors") && Contains("expected a JSON object"));
  // JSON has no NaN; a number too large for a double is refused too.
  CHECK_THROWS_WITH(with(R"({"noise_kpa": NaN})"), Contains("invalid JSON"));
  CHECK_THROWS_WITH(with(R"({"noise_kpa": 1e999})"), Contains("invalid JSON") && Contains("1e999"));
  // The skin's target may come after the errors block: the check sees both.
  CHECK_THROWS_WITH(parse(R"({"objects": [{"mesh": "a.glb"}], "errors": {"full_scale_kpa": 40},
      "skin": {"target_pressure_kpa": 50}})"),
                    Contains("errors.full_scale_kpa"));
}

TEST_CASE("scene JSON: the built-in scenes spell out their errors, the -ideal ones are the ideal world") {
  for (const auto& name : sva::builtin_scene_names()) {
    INFO(name);
    const auto s = sva::load_scene(name);
    const bool ideal = name.find("-ideal") != std::string::npos;
    CHECK(s.errors.arm_ideal() == ideal);
    CHECK((s.errors.gain_spread == 0.0) == ideal);
    CHECK((s.errors.noise_kpa == 0.0) == ideal);
    CHECK((s.errors.full_scale_kpa == 0.0) == ideal);
    CHECK((s.errors.train_sensor == s.errors.test_sensor) == ideal);
  }
  // The ideal twins differ from their scenes only in the errors (and, for the
  // letters, where the skin noise lives).
  for (const char* base : {"paper3d", "letters2d"}) {
    auto real = sva::load_scene(base), ideal = sva::load_scene(std::string(base) + "-ideal");
    CHECK(ideal.name == std::string(base) + "-ideal");
    REQUIRE(real.objects.size() == ideal.objects.size());
    for (std::size_t i = 0; i < real.objects.size(); ++i) CHECK(real.objects[i].mesh == ideal.objects[i].mesh);
    CHECK(std::hypot(real.skin.noise_kpa, real.errors.noise_kpa) >= ideal.skin.noise_kpa);
    CHECK(real.protocol.train_per_object == ideal.protocol.train_per_object);
    CHECK(real.pose_space.translation_bins == ideal.pose_space.translation_bins);
  }
  CHECK_THROWS_WITH(sva::load_scene("paper3d-real"), Contains("paper3d-ideal") && Contains("letters2d-ideal"));
}
