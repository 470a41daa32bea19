// Dataset files (host/src/dataset, docs/dataset-format.md): every field of a sample written and read back bit for
// bit, version-1 files, a bad record refused naming the file and the sample, and the dataset without some objects
// (`sva train --exclude-objects`). Datasets made in code: no simulator needed.
#include <catch2/catch.hpp>

#include <sva/base/rng.hpp>
#include <sva/base/so3.hpp>
#include <sva/dataset.hpp>
#include <sva/error.hpp>
#include <sva/scene.hpp>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include <sva/io/binary_file.hpp>
#include "test_support.hpp"

using namespace sva;

namespace {

glm::dvec3 unit(util::Rng& rng) {
  return glm::normalize(glm::dvec3(rng.normal(), rng.normal(), rng.normal()) + glm::dvec3(0, 0, 1e-3));
}

// Six samples of the tiny scene's objects with every field set (one unconverged, one truth without a surface
// normal), and a scene whose error model differs from the default.
Dataset small_dataset() {
  Dataset d;
  d.scene = load_scene("tiny");
  d.scene.errors.test_sensor = 5;
  d.split = "test";
  d.seed = 77;
  util::Rng rng(5);
  const auto objects = static_cast<std::uint32_t>(d.scene.objects.size());
  for (std::uint32_t i = 0; i < 6; ++i) {
    Sample s;
    s.object = i % objects;
    s.reading.status = i == 3 ? ControllerStatus::not_converged : ControllerStatus::converged;
    s.reading.iterations = static_cast<std::uint16_t>(10 + i);
    s.reading.position = {rng.uniform(-50, 50), rng.uniform(-50, 50), rng.uniform(0, 80)};
    s.reading.normal = unit(rng);
    s.reading.x_axis = glm::normalize(glm::cross(s.reading.normal, glm::dvec3(1, 0, 0)));
    for (int e = 0; e < d.scene.sensor.elements(); ++e)
      s.reading.pressure.push_back(static_cast<float>(rng.uniform(0, 40)));
    s.object_pose = {so3::exp(glm::dvec3(rng.normal(), rng.normal(), rng.normal())), {rng.normal(), 2.0, -3.0}};
    s.truth = {s.reading.position + glm::dvec3(0.1, 0, 0), unit(rng), s.reading.x_axis,
               i == 4 ? glm::dvec3(0.0) : unit(rng)};
    d.samples.push_back(s);
  }
  return d;
}

}  // namespace

TEST_CASE("dataset: every field of every sample round-trips bit for bit, the scene and the truth included") {
  const auto dir = test::temp_dir("dataset-roundtrip");
  const Dataset data = small_dataset();
  save_dataset(data, dir / "test.svad");
  const Dataset back = load_dataset(dir / "test.svad");
  CHECK(back.split == "test");
  CHECK(back.seed == 77u);
  CHECK(scene_to_json(back.scene) == scene_to_json(data.scene));
  CHECK(back.scene.errors.test_sensor == 5u);
  REQUIRE(back.samples.size() == data.samples.size());
  for (std::size_t i = 0; i < back.samples.size(); ++i) {
    INFO("sample " << i);
    const Sample &a = data.samples[i], &b = back.samples[i];
    CHECK(b.object == a.object);
    CHECK(b.reading.status == a.reading.status);
    CHECK(b.reading.iterations == a.reading.iterations);
    CHECK(b.reading.position == a.reading.position);
    CHECK(b.reading.normal == a.reading.normal);
    CHECK(b.reading.x_axis == a.reading.x_axis);
    CHECK(b.reading.pressure == a.reading.pressure);
    // A loaded image has the scene's sensor's shape.
    CHECK(b.reading.rows == data.scene.sensor.rows);
    CHECK(b.reading.cols == data.scene.sensor.cols);
    CHECK(b.object_pose.R == a.object_pose.R);
    CHECK(b.object_pose.T == a.object_pose.T);
    CHECK(b.truth.position == a.truth.position);
    CHECK(b.truth.normal == a.truth.normal);
    CHECK(b.truth.x_axis == a.truth.x_axis);
    CHECK(b.truth.surface_normal == a.truth.surface_normal);
  }
  CHECK(back.count_converged() == 5u);
  std::filesystem::remove_all(dir);
}

TEST_CASE("dataset: a version-1 file loads with the reading's pose as its truth") {
  const auto dir = test::temp_dir("dataset-v1");
  // A version-1 file (no truth, a scene without errors) as the old writer made it.
  io::BinaryWriter w;
  w.put_string(R"({"objects": [{"mesh": "a.glb"}]})");
  w.put_string("test");
  w.put<std::uint64_t>(7);
  w.put<std::uint64_t>(1);
  w.put<std::uint32_t>(0);
  w.put<std::uint8_t>(0);
  w.put<std::uint16_t>(4);
  const double pose[] = {1, 2, 3, 0, 0, 1, 1, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0};
  w.put_array(pose, 21);
  std::vector<float> pressure(36, 5.0f);
  w.put_array(pressure.data(), 36);
  w.write_file(dir / "v1.svad", "SVADATA1", 1);
  const Dataset v1 = load_dataset(dir / "v1.svad");
  REQUIRE(v1.samples.size() == 1u);
  CHECK(v1.seed == 7u);
  CHECK(v1.samples[0].reading.iterations == 4u);
  CHECK(v1.samples[0].truth.position == glm::dvec3(1, 2, 3));
  CHECK(v1.samples[0].truth.normal == glm::dvec3(0, 0, 1));
  CHECK(v1.samples[0].truth.surface_normal == glm::dvec3(0.0));
  CHECK(v1.scene.errors.position_sigma_mm == 0.0);
  std::filesystem::remove_all(dir);
}

TEST_CASE("dataset: a bad record is refused naming the file, the sample and the fault") {
  const auto dir = test::temp_dir("dataset-bad");
  const Dataset data = small_dataset();
  const auto refused = [&](Dataset bad, const std::string& name) {
    save_dataset(bad, dir / name);
    return load_dataset(dir / name);
  };
  Dataset bad = data;
  bad.samples[1].truth.normal = {0, 0, 2};
  CHECK_THROWS_WITH(refused(bad, "truth.svad"), Catch::Contains("truth.svad") && Catch::Contains("sample 1") &&
                                                    Catch::Contains("true sensor normal"));
  bad = data;
  bad.samples[2].object = 99;
  CHECK_THROWS_WITH(refused(bad, "object.svad"), Catch::Contains("object.svad") && Catch::Contains("sample 2") &&
                                                     Catch::Contains("object id 99 out of range"));
  bad = data;
  bad.samples[5].reading.pressure[7] = -1.0f;
  CHECK_THROWS_WITH(refused(bad, "pressure.svad"),
                    Catch::Contains("pressure.svad") && Catch::Contains("sample 5") && Catch::Contains("negative"));
  // A file cut short: refused, not read past its end.
  save_dataset(data, dir / "whole.svad");
  std::ifstream in(dir / "whole.svad", std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), {});
  std::ofstream(dir / "cut.svad", std::ios::binary) << bytes.substr(0, bytes.size() - 100);
  CHECK_THROWS_WITH(load_dataset(dir / "cut.svad"), Catch::Contains("cut.svad"));
  std::filesystem::remove_all(dir);
}

// The loader weighs a large file's checksum beside its parse where it may use a second thread: a flipped byte that
// breaks the parse (the scene's length, its JSON, a sample's object id) is still named a checksum mismatch, on one
// thread and on two.
TEST_CASE("dataset: a flipped byte is named corrupt wherever it lies, the checksum weighed first or beside the parse") {
  const auto dir = test::temp_dir("dataset-flips");
  Dataset data = small_dataset();
  while (data.samples.size() < 300) data.samples.push_back(data.samples[data.samples.size() % 6]);  // past 64 KiB
  save_dataset(data, dir / "whole.svad");
  std::ifstream in(dir / "whole.svad", std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), {});
  for (const char* threads : {"1", "2"}) {
    const test::ScopedEnv env("SVA_THREADS", threads);
    CHECK(load_dataset(dir / "whole.svad").samples.size() == 300);
    for (const std::size_t at : {std::size_t{32}, std::size_t{45}, bytes.size() / 2, bytes.size() - 1}) {
      std::string flipped = bytes;
      flipped[at] = static_cast<char>(flipped[at] ^ 0x40);
      std::ofstream(dir / "flipped.svad", std::ios::binary | std::ios::trunc) << flipped;
      INFO(threads << " thread(s), byte " << at << " of " << bytes.size());
      CHECK_THROWS_WITH(load_dataset(dir / "flipped.svad"),
                        Catch::Contains("flipped.svad") && Catch::Contains("checksum"));
    }
  }
  std::filesystem::remove_all(dir);
}

TEST_CASE("dataset: without some objects, their samples are dropped and the others renumbered in order") {
  Dataset data = small_dataset();
  data.scene.objects.push_back(data.scene.objects[0]);  // a third object (the tiny scene has two)
  data.scene.objects.back().name = "third";
  for (std::size_t i = 0; i < data.samples.size(); ++i) data.samples[i].object = static_cast<std::uint32_t>(i % 3);
  const std::string first = data.scene.objects[0].name, second = data.scene.objects[1].name;
  const Dataset rest = without_objects(data, {second});
  REQUIRE(rest.scene.objects.size() == data.scene.objects.size() - 1);
  CHECK(rest.scene.objects[0].name == first);
  CHECK(rest.scene.objects[1].name == data.scene.objects[2].name);
  std::size_t kept = 0;
  for (const Sample& s : data.samples) {
    if (s.object == 1) continue;
    const Sample& r = rest.samples[kept++];
    CHECK(r.object == (s.object == 0 ? 0u : s.object - 1));
    CHECK(r.reading.position == s.reading.position);
  }
  CHECK(kept == rest.samples.size());
  CHECK_THROWS_WITH(without_objects(data, {"no-such-object"}),
                    Catch::Contains("\"tiny\"") && Catch::Contains("no object \"no-such-object\""));
  std::vector<std::string> all;
  for (const SceneObject& o : data.scene.objects) all.push_back(o.name);
  CHECK_THROWS_WITH(without_objects(data, all), Catch::Contains("no object of scene \"tiny\" is left"));
}
