// The fuzzing campaign's regression inputs and hand-made broken cases (tests/fuzz/corpus/<harness>/regression-*
// and broken-*), loaded by the normal build: each must give sva::Error naming the file, never a crash. The fuzz
// harnesses (tests/fuzz) run the same loaders under ASan + UBSan; these tests keep the fixes in the gcc build.
#include <catch2/catch.hpp>

#include <sva/batch_file.hpp>
#include <sva/dataset.hpp>
#include <sva/error.hpp>
#include <sva/scene.hpp>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <map>

#include "map/map_file.hpp"
#include "recognition/batch_sessions.hpp"
#include "recognition/session_file.hpp"
#include "test_support.hpp"
#if __has_include(<sva/sim/mesh.hpp>)
#include <sva/sim/mesh.hpp>
#define SVA_TEST_HAVE_SIM 1
#endif
#if __has_include(<sva/drivers/session.hpp>)
#include <sva/drivers/calibration.hpp>
#include <sva/drivers/frame.hpp>
#include <sva/drivers/session.hpp>
#define SVA_TEST_HAVE_DRIVERS 1
#endif

namespace fs = std::filesystem;

namespace {

// The fuzz corpus of the source tree; a bundle for a GPU machine (scripts/bundle.sh) carries only the assets.
fs::path corpus() {
  const auto dir = fs::path(std::getenv("SVA_ASSETS")) / ".." / "tests" / "fuzz" / "corpus";
  if (!fs::is_directory(dir)) sva::test::skip("no fuzz corpus beside the assets (" + dir.string() + ")");
  return dir;
}

std::vector<std::uint8_t> bytes_of(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), {}};
}

// Each harness's loader, as the normal build runs it on a file.
std::map<std::string, std::function<void(const fs::path&)>> loaders() {
  std::map<std::string, std::function<void(const fs::path&)>> l;
  l["scene"] = [](const fs::path& f) { (void)sva::load_scene(f.string()); };
  l["dataset"] = [](const fs::path& f) { (void)sva::load_dataset(f); };
  l["map"] = [](const fs::path& f) { (void)sva::load_pair_map(f); };
  l["session_file"] = [](const fs::path& f) { (void)sva::io::load_session_file(f); };
  l["batch_sessions"] = [](const fs::path& f) { (void)sva::read_batch_sessions(f, 36); };
#ifdef SVA_TEST_HAVE_SIM
  l["mesh"] = [](const fs::path& f) { (void)sva::sim::load_mesh(f); };
#endif
#ifdef SVA_TEST_HAVE_DRIVERS
  l["calibration"] = [](const fs::path& f) { (void)sva::drivers::Calibration::load(f); };
  l["recording"] = [](const fs::path& f) { (void)sva::drivers::load_session(f); };
  l["frame"] = [](const fs::path& f) {
    try {
      (void)sva::drivers::parse_frame(bytes_of(f));
    } catch (const sva::Error& e) {
      throw sva::Error(f.string() + ": " + e.what());  // frames carry no file name of their own
    }
  };
#endif
  return l;
}

}  // namespace

TEST_CASE("fuzz regressions and broken seeds give sva::Error naming the file") {
  const auto l = loaders();
  int checked = 0;
  for (const auto& dir : fs::directory_iterator(corpus())) {
    const auto loader = l.find(dir.path().filename().string());
    if (loader == l.end()) continue;  // sensor_stream: a byte stream, not a file format
    for (const auto& entry : fs::directory_iterator(dir.path())) {
      const std::string name = entry.path().filename().string();
      if (name.rfind("regression-", 0) != 0 && name.rfind("broken-", 0) != 0) continue;
      INFO(entry.path().string());
      CHECK_THROWS_WITH(loader->second(entry.path()), Catch::Contains(name));
      ++checked;
    }
  }
  CHECK(checked >= 10);
}

TEST_CASE("fuzz regression: a version-1 map whose offsets run past its entries") {
  // Found by fuzz_map: keep_one_order walked the key ranges before validation (heap overflow).
  CHECK_THROWS_WITH(sva::load_pair_map(corpus() / "map" / "regression-v1-offsets-past-entries.svam"),
                    Catch::Contains("offsets"));
}

TEST_CASE("fuzz regression: deeply nested JSON is refused before parsing") {
  // json::dump in error messages recursed once per level: 60,000 nested brackets overflowed the stack.
  const std::string deep = std::string(100000, '[') + std::string(100000, ']');
  CHECK_THROWS_WITH(sva::parse_scene("{\"objects\": [{\"mesh\": \"a.glb\", \"center\": " + deep + "}]}", "deep.json"),
                    Catch::Contains("deep.json") && Catch::Contains("nested deeper than 64"));
  CHECK_THROWS_WITH(sva::batch::parse_sessions("{\"id\": " + deep + ", \"readings\": []}\n", "deep.jsonl", 1, 0, 36),
                    Catch::Contains("deep.jsonl:1") && Catch::Contains("nested deeper"));
  CHECK_THROWS_WITH(sva::load_scene((corpus() / "scene" / "regression-nested-200.json").string()),
                    Catch::Contains("nested deeper"));
#ifdef SVA_TEST_HAVE_DRIVERS
  CHECK_THROWS_WITH(sva::drivers::Calibration::from_json("{\"rows\": " + deep + "}", "deep-cal.json"),
                    Catch::Contains("deep-cal.json") && Catch::Contains("nested deeper"));
#endif
  // Nesting inside strings is text, not structure.
  CHECK_NOTHROW(sva::parse_scene("{\"name\": \"" + deep + "\", \"objects\": [{\"mesh\": \"a.glb\"}]}", "s.json"));
}

#ifdef SVA_TEST_HAVE_SIM
TEST_CASE("fuzz regression: glTF node graphs that instance a mesh without end") {
  // 61 nodes, each listing the next 4 times: 4^60 visits. Refused after a bounded number.
  CHECK_THROWS_WITH(sva::sim::load_mesh(corpus() / "mesh" / "regression-shared-children.gltf"),
                    Catch::Contains("regression-shared-children.gltf") && Catch::Contains("node graph"));
  CHECK_THROWS_WITH(sva::sim::load_mesh(corpus() / "mesh" / "regression-nested-extras.gltf"),
                    Catch::Contains("nested deeper"));
}
#endif

TEST_CASE("fuzz regression: numbers past the range of the field's C++ type") {
  // Found by fuzz_calibration: get<int>() of 7e85 is undefined behaviour (UBSan); get<float>() of 1e300 too.
  std::string pressure = "[1e300";
  for (int i = 1; i < 36; ++i) pressure += ", 0";
  pressure += "]";
  CHECK_THROWS_WITH(sva::batch::parse_sessions("{\"readings\": [{\"position\": [0, 0, 0], \"normal\": [0, 0, 1], "
                                               "\"pressure\": " +
                                                   pressure + "}]}",
                                               "big.jsonl", 1, 0, 36),
                    Catch::Contains("big.jsonl:1") && Catch::Contains("out-of-range"));
#ifdef SVA_TEST_HAVE_DRIVERS
  using sva::drivers::Calibration;
  CHECK_THROWS_WITH(Calibration::load(corpus() / "calibration" / "regression-rows-1e85.json"),
                    Catch::Contains("regression-rows-1e85.json") && Catch::Contains("rows/cols"));
  const std::string base = R"("rows": 1, "cols": 1, "pitch_mm": 1, )";
  CHECK_THROWS_WITH(Calibration::from_json("{" + base + R"("gain_kpa_per_count": [1e300], "zero_counts": [0]})", "g"),
                    Catch::Contains("gain_kpa_per_count") && Catch::Contains("out-of-range"));
  CHECK_THROWS_WITH(
      Calibration::from_json(
          "{" + base + R"("gain_kpa_per_count": [1], "zero_counts": [0], "saturation_counts": 1e300})", "s"),
      Catch::Contains("saturation_counts must be in [1, 65535]"));
  CHECK(Calibration::from_json("{" + base + R"("gain_kpa_per_count": [1.5], "zero_counts": [2]})", "ok").gain[0] ==
        1.5f);
  CHECK_THROWS_WITH(sva::drivers::SettleRule::from_json(R"({"frames": 1e300})", "settle.json"),
                    Catch::Contains("settle.json") && Catch::Contains("frames"));
  CHECK(sva::drivers::SettleRule::from_json(R"({"frames": 7})", "settle.json").frames == 7);
#endif
}
