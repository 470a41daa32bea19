// sva simulate / export / demo through the CLI: determinism, outputs, and
// every kind of bad input giving a message that names the file and the fault.
#include <catch2/catch.hpp>

#include <sys/wait.h>
#include <unistd.h>
#include <csignal>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <sstream>
#include <thread>

#include "gltf_writer.hpp"
#include "test_support.hpp"

using Catch::Contains;
namespace fs = std::filesystem;

namespace {

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

std::string q(const fs::path& p) { return "'" + p.string() + "'"; }

// Runs `sva simulate --mesh FILE` and checks that it fails with a message
// naming the file and containing `fault`, leaving no dataset behind.
void expect_mesh_failure(const fs::path& mesh, const std::string& fault) {
  auto out = mesh.parent_path() / ("out-" + mesh.filename().string());
  std::string output;
  int rc = sva::test::run_sva("simulate --mesh " + q(mesh) + " --out " + q(out) + " --train 2 --test 1", &output);
  INFO(output);
  CHECK(rc != 0);
  CHECK(rc < 128);  // an error exit, not a crash
  CHECK_THAT(output, Contains(mesh.filename().string()) && Contains(fault));
  CHECK_FALSE(fs::exists(out / "train.svad"));
  CHECK_FALSE(fs::exists(out / "test.svad"));
}

}  // namespace

TEST_CASE("simulate: same seed gives the same bytes on 1 and 2 threads and another seed differs") {
  auto dir = sva::test::temp_dir("sim-determinism");
  std::string args = "simulate --scene tiny --train 12 --test 3 --seed 5 --out ";
  ::setenv("SVA_THREADS", "1", 1);
  REQUIRE(sva::test::run_sva(args + q(dir / "a")) == 0);
  ::setenv("SVA_THREADS", "2", 1);
  REQUIRE(sva::test::run_sva(args + q(dir / "b")) == 0);
  ::unsetenv("SVA_THREADS");
  REQUIRE(sva::test::run_sva(args + q(dir / "c") + " --threads 2") == 0);
  REQUIRE(sva::test::run_sva("simulate --scene tiny --train 12 --test 3 --seed 6 --out " + q(dir / "d")) == 0);
  for (const char* f : {"train.svad", "test.svad"}) {
    std::string a = slurp(dir / "a" / f);
    REQUIRE(a.size() > 1000);
    CHECK(a == slurp(dir / "b" / f));
    CHECK(a == slurp(dir / "c" / f));
    CHECK(a != slurp(dir / "d" / f));
  }
}

TEST_CASE("simulate --mesh, --preview, inspect and export") {
  auto dir = sva::test::temp_dir("sim-outputs");
  auto mesh = sva::test::write_gltf(sva::test::box_mesh({0, 0, 0}, {3, 2, 1}), dir / "block.gltf");
  std::string output;
  int rc = sva::test::run_sva("simulate --mesh " + q(mesh) + " --mesh " +
                                  q(sva::test::write_gltf(sva::test::sphere_mesh(1, 3), dir / "ball.gltf")) +
                                  " --out " + q(dir / "data") + " --train 6 --test 2 --preview " + q(dir / "sheet.png"),
                              &output);
  INFO(output);
  REQUIRE(rc == 0);
  CHECK(slurp(dir / "sheet.png").substr(1, 3) == "PNG");
  REQUIRE(sva::test::run_sva("inspect " + q(dir / "data" / "train.svad"), &output) == 0);
  CHECK_THAT(output, Contains("block") && Contains("ball") && Contains("12"));
  REQUIRE(sva::test::run_sva("export --data " + q(dir / "data" / "train.svad") + " --out " + q(dir / "export"),
                             &output) == 0);
  std::string csv = slurp(dir / "export" / "train.csv");
  CHECK(std::count(csv.begin(), csv.end(), '\n') == 13);  // header + 12 readings
  CHECK_THAT(csv,
             Contains("object,object_name,status,iterations,px,py,pz") && Contains("p_r5c5") && Contains(",ball,"));
  std::string ply = slurp(dir / "export" / "train.ply");
  CHECK_THAT(ply, Contains("element vertex 12") && Contains("property float nx") && Contains("property uchar red"));
  CHECK(rc == 0);
  // Export of a file that is not a dataset fails and names it.
  CHECK(sva::test::run_sva("export --data " + q(dir / "block.gltf") + " --out " + q(dir / "bad"), &output) != 0);
  CHECK_THAT(output, Contains("block.gltf"));
}

TEST_CASE("simulate --mesh: a control character in a mesh file's name is refused, as in a scene file's names") {
  // The object is named by the file's stem (docs/scene-format.md, "Names"): refused before anything is simulated.
  auto dir = sva::test::temp_dir("sim-control-name");
  auto mesh = sva::test::write_gltf(sva::test::box_mesh({0, 0, 0}, {3, 2, 1}), dir / "tab\tblock.gltf");
  std::string output;
  const int rc =
      sva::test::run_sva("simulate --mesh " + q(mesh) + " --out " + q(dir / "data") + " --train 2 --test 1", &output);
  INFO(output);
  CHECK(rc != 0);
  CHECK(rc < 128);
  CHECK_THAT(output, Contains("sva simulate --mesh: objects[0].name: control character U+0009 at character 4"));
  CHECK_FALSE(fs::exists(dir / "data" / "train.svad"));
}

TEST_CASE("simulate: bad meshes are refused with the file and the fault") {
  auto dir = sva::test::temp_dir("sim-bad-mesh");
  using sva::test::TestMesh;
  expect_mesh_failure(dir / "missing.glb", "no such file");
  std::ofstream(dir / "empty.glb").close();
  expect_mesh_failure(dir / "empty.glb", "empty");
  std::ofstream(dir / "text.gltf") << "this is not glTF";
  expect_mesh_failure(dir / "text.gltf", "not a glTF");
  std::ofstream(dir / "junk.glb", std::ios::binary) << "glTF\x02\x00\x00\x00garbage-garbage";
  expect_mesh_failure(dir / "junk.glb", "invalid glTF");

  TestMesh box = sva::test::box_mesh({0, 0, 0}, {1, 1, 1});
  TestMesh bad_index = box;
  bad_index.indices[4] = 99;
  sva::test::write_gltf(bad_index, dir / "index.gltf");
  expect_mesh_failure(dir / "index.gltf", "out of range");

  TestMesh inf = box;
  inf.positions[3].y = std::numeric_limits<float>::infinity();
  sva::test::write_gltf(inf, dir / "inf.gltf");
  expect_mesh_failure(dir / "inf.gltf", "non-finite");

  sva::test::write_gltf(box, dir / "nobuffer.gltf");
  fs::remove(dir / "nobuffer.bin");
  expect_mesh_failure(dir / "nobuffer.gltf", "nobuffer.bin");

  auto j = sva::test::gltf_json(box, dir / "types.bin");
  j["accessors"][0]["count"] = "eight";
  sva::test::write_json(j, dir / "types.gltf");
  expect_mesh_failure(dir / "types.gltf", "invalid glTF");

  auto k = sva::test::gltf_json(box, dir / "overrun.bin");
  k["accessors"][0]["count"] = 5000;
  sva::test::write_json(k, dir / "overrun.gltf");
  expect_mesh_failure(dir / "overrun.gltf", "overrun");

  TestMesh flat;
  flat.positions = {{0, 0, 0}, {1, 1, 1}, {2, 2, 2}, {3, 3, 3}};
  flat.indices = {0, 1, 2, 1, 2, 3};
  sva::test::write_gltf(flat, dir / "flat.gltf");
  expect_mesh_failure(dir / "flat.gltf", "zero");

  TestMesh none;
  none.positions = {{0, 0, 0}};
  none.indices = {};
  auto n = sva::test::gltf_json(none, dir / "none.bin");
  n["meshes"][0]["primitives"][0].erase("indices");
  sva::test::write_json(n, dir / "none.gltf");
  expect_mesh_failure(dir / "none.gltf", "not a multiple of 3");
  n["meshes"][0]["primitives"][0]["mode"] = 0;  // points only: no surface to touch
  sva::test::write_json(n, dir / "points.gltf");
  expect_mesh_failure(dir / "points.gltf", "no triangles");
}

TEST_CASE("simulate: bad scenes and options are refused") {
  auto dir = sva::test::temp_dir("sim-bad-scene");
  std::string output;
  auto run = [&](const std::string& json, const std::string& fault) {
    auto file = dir / "scene.json";
    std::ofstream(file) << json;
    int rc = sva::test::run_sva("simulate --scene " + q(file) + " --out " + q(dir / "out"), &output);
    INFO(output);
    CHECK(rc != 0);
    CHECK(rc < 128);
    CHECK_THAT(output, Contains("scene.json") && Contains(fault));
    CHECK_FALSE(fs::exists(dir / "out" / "train.svad"));
  };
  run("", "empty");
  run("{\"objects\": [", "invalid JSON");
  run("{}", "missing \"objects\"");
  run(R"({"objects": [{"mesh": 3}]})", "objects[0].mesh");
  run(R"({"objects": [{"mesh": "a.glb"}], "skin": {"rays_per_axis": "many"}})", "skin.rays_per_axis");
  run(R"({"objects": [{"mesh": "a.glb"}], "protocol": {"kind": "poke"}})", "protocol.kind");
  // A valid scene naming a mesh that does not exist names the mesh.
  std::ofstream(dir / "ok.json") << R"({"objects": [{"mesh": "nowhere/cup.glb"}]})";
  int rc = sva::test::run_sva("simulate --scene " + q(dir / "ok.json") + " --out " + q(dir / "out"), &output);
  CHECK(rc != 0);
  CHECK_THAT(output, Contains("nowhere/cup.glb") && Contains("no such file"));
  CHECK(sva::test::run_sva("simulate --scene tiny", &output) != 0);
  CHECK_THAT(output, Contains("--out"));
  CHECK(sva::test::run_sva("simulate --scene tiny --mesh x.glb --out " + q(dir / "o2"), &output) != 0);
  CHECK(sva::test::run_sva("simulate --scene tiny --train -3 --out " + q(dir / "o3"), &output) != 0);
  CHECK_THAT(output, Contains("--train"));
  CHECK_FALSE(fs::exists(dir / "o3"));
}

TEST_CASE("demo: simulates into its cache once, then reuses it") {
  auto dir = sva::test::temp_dir("sim-demo");
  std::string output;
  std::string args = "demo --scene tiny --train 4 --test 2 --work " + q(dir);
  REQUIRE(sva::test::run_sva(args, &output) == 0);
  CHECK_THAT(output, Contains("[simulate]") && Contains("readings in") && Contains("[summary]"));
  CHECK(fs::exists(dir / "preview_tiny_train.png"));
  std::string first = slurp(dir / "data" / "tiny" / "train.svad");
  REQUIRE(sva::test::run_sva(args, &output) == 0);
  CHECK_THAT(output, Contains("reusing cached"));
  CHECK(slurp(dir / "data" / "tiny" / "train.svad") == first);
  REQUIRE(sva::test::run_sva(args + " --seed 9", &output) == 0);
  CHECK_THAT(output, Contains("simulating again"));
}

TEST_CASE("simulate: Ctrl-C stops cleanly and leaves no output") {
  auto dir = sva::test::temp_dir("sim-interrupt");
  const char* bin = std::getenv("SVA_BIN");
  REQUIRE(bin);
  const std::string out = (dir / "out").string();
  pid_t pid = ::fork();
  REQUIRE(pid >= 0);
  if (pid == 0) {
    ::execl(bin, bin, "--quiet", "simulate", "--scene", "paper3d", "--out", out.c_str(), "--threads", "2",
            static_cast<char*>(nullptr));
    std::_Exit(127);
  }
  std::this_thread::sleep_for(std::chrono::milliseconds(800));  // meshes loaded, simulation under way
  ::kill(pid, SIGINT);
  int status = 0;
  ::waitpid(pid, &status, 0);
  REQUIRE(WIFEXITED(status));
  CHECK(WEXITSTATUS(status) == 130);
  CHECK_FALSE(fs::exists(dir / "out" / "train.svad"));
  CHECK_FALSE(fs::exists(dir / "out" / "test.svad"));
}

TEST_CASE("train: the objects' meshes go into the map, and a missing or broken one is refused, naming it") {
  auto dir = sva::test::temp_dir("train-surfaces");
  sva::test::write_gltf(sva::test::box_mesh({0, 0, 0}, {1, 2, 3}), dir / "box.gltf");
  std::string output;
  REQUIRE(sva::test::run_sva("simulate --mesh " + q(dir / "box.gltf") + " --out " + q(dir) + " --train 60 --test 2",
                             &output) == 0);
  REQUIRE(sva::test::run_sva("train --data " + q(dir / "train.svad") + " --out " + q(dir / "map.svam"), &output) == 0);
  CHECK_THAT(output, Contains("surfaces       1 mesh, 12 triangles"));
  REQUIRE(sva::test::run_sva("inspect " + q(dir / "map.svam"), &output) == 0);
  CHECK_THAT(output, Contains("1 mesh, 12 triangles, 8 vertices"));
  // The mesh broken after simulating: training names it and the way around it, and writes no map.
  std::ofstream(dir / "box.gltf") << "this is not glTF";
  const int rc =
      sva::test::run_sva("train --data " + q(dir / "train.svad") + " --out " + q(dir / "broken.svam"), &output);
  INFO(output);
  CHECK(rc != 0);
  CHECK(rc < 128);
  CHECK_THAT(output, Contains("box.gltf") && Contains("not a glTF") && Contains("--no-surfaces"));
  CHECK_FALSE(fs::exists(dir / "broken.svam"));
  fs::remove(dir / "box.gltf");
  CHECK(sva::test::run_sva("train --data " + q(dir / "train.svad") + " --out " + q(dir / "gone.svam"), &output) != 0);
  CHECK_THAT(output, Contains("box.gltf") && Contains("no such file"));
  // A dataset whose meshes are not to be had (a real sensor's recordings): --no-surfaces, and the map says so.
  REQUIRE(sva::test::run_sva("train --no-surfaces --data " + q(dir / "train.svad") + " --out " + q(dir / "bare.svam"),
                             &output) == 0);
  CHECK_THAT(output, Contains("surfaces       none: the verify stage weighs the readings against the training"));
}
