#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "test_support.hpp"

using Catch::Contains;
using sva::test::run_sva;

namespace {
std::string slurp(const std::filesystem::path& p) {
  std::ifstream in(p);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// Simulates and trains the tiny built-in scene once per test process.
std::filesystem::path tiny_world() {
  static const std::filesystem::path dir = [] {
    auto d = sva::test::temp_dir("recognize-cli");
    std::string out;
    REQUIRE(run_sva("simulate --scene tiny --out " + d.string() + " --seed 3", &out) == 0);
    REQUIRE(run_sva("train --data " + (d / "train.svad").string() + " --out " + (d / "map.svam").string(), &out) == 0);
    return d;
  }();
  return dir;
}
}  // namespace

TEST_CASE("sva recognize: batched Vulkan estimates equal the CPU reference's, byte for byte") {
  const auto d = tiny_world();
  const std::string map = (d / "map.svam").string();
  std::string out;
  REQUIRE(run_sva("recognize --write-sessions " + (d / "s.jsonl").string() + " --map " + map + " --data " +
                      (d / "test.svad").string() + " --trials 6 --max-readings 6",
                  &out) == 0);
  REQUIRE(run_sva("recognize --map " + map + " --batch " + (d / "s.jsonl").string() + " --out " +
                      (d / "cpu.jsonl").string() + " --backend cpu",
                  &out) == 0);
  int rc = run_sva("recognize --map " + map + " --batch " + (d / "s.jsonl").string() + " --out " +
                       (d / "gpu.jsonl").string() + " --backend vulkan --sessions-per-submission 4",
                   &out);
  if (rc != 0 && out.find("no Vulkan device") != std::string::npos) sva::test::skip(out);
  REQUIRE(rc == 0);
  const std::string cpu = slurp(d / "cpu.jsonl"), gpu = slurp(d / "gpu.jsonl");
  CHECK(std::count(cpu.begin(), cpu.end(), '\n') == 6);
  CHECK(cpu.find("\"truth\"") != std::string::npos);
  CHECK(cpu == gpu);
}

TEST_CASE("sva recognize: a malformed sessions file names the line and the fault") {
  const auto d = tiny_world();
  const std::string map = (d / "map.svam").string();
  std::ofstream(d / "bad1.jsonl") << "{\"id\": 1, \"readings\": []}\n";
  std::ofstream(d / "bad2.jsonl")
      << "\n{\"readings\": [{\"position\": [0,0,0], \"normal\": [0,0,1], \"pressure\": [1, 2]}]}\n";
  std::ofstream(d / "bad3.jsonl") << "{not json\n";
  std::ofstream(d / "empty.jsonl") << "";
  std::string out;
  CHECK(run_sva(
            "recognize --map " + map + " --batch " + (d / "bad1.jsonl").string() + " --out " + (d / "x.jsonl").string(),
            &out) != 0);
  CHECK_THAT(out, Contains("bad1.jsonl:1") && Contains("non-empty"));
  CHECK(run_sva(
            "recognize --map " + map + " --batch " + (d / "bad2.jsonl").string() + " --out " + (d / "x.jsonl").string(),
            &out) != 0);
  CHECK_THAT(out, Contains("bad2.jsonl:2") && Contains("pressure"));
  CHECK(run_sva(
            "recognize --map " + map + " --batch " + (d / "bad3.jsonl").string() + " --out " + (d / "x.jsonl").string(),
            &out) != 0);
  CHECK_THAT(out, Contains("bad3.jsonl:1") && Contains("invalid JSON"));
  CHECK(run_sva("recognize --map " + map + " --batch " + (d / "empty.jsonl").string() + " --out " +
                    (d / "x.jsonl").string(),
                &out) != 0);
  CHECK_THAT(out, Contains("no sessions"));
  CHECK_FALSE(std::filesystem::exists(d / "x.jsonl"));
}

TEST_CASE("sva recognize: --max-pairs, --likelihood-cutoff and --belief-budget reach the sessions, bad values are "
          "refused") {
  const auto d = tiny_world();
  const std::string map = (d / "map.svam").string();
  std::string out;
  REQUIRE(run_sva("recognize --write-sessions " + (d / "b.jsonl").string() + " --map " + map + " --data " +
                      (d / "test.svad").string() + " --trials 3 --max-readings 6",
                  &out) == 0);
  const std::string base = "recognize --map " + map + " --batch " + (d / "b.jsonl").string() + " --backend cpu ";
  REQUIRE(run_sva(base + "--out " + (d / "exact.jsonl").string(), &out) == 0);
  REQUIRE(run_sva(base + "--belief-budget 0 --out " + (d / "unbounded.jsonl").string(), &out) == 0);
  REQUIRE(run_sva(base + "--max-pairs 2 --out " + (d / "bounded.jsonl").string(), &out) == 0);
  REQUIRE(run_sva(base + "--likelihood-cutoff 0.9 --out " + (d / "cut.jsonl").string(), &out) == 0);
  // A tiny scene's six readings stay far below the default budget: no bound changes nothing; two pairs per update
  // (the new reading with the last one) cast other votes.
  CHECK(slurp(d / "exact.jsonl") == slurp(d / "unbounded.jsonl"));
  CHECK(slurp(d / "exact.jsonl") != slurp(d / "bounded.jsonl"));
  CHECK(slurp(d / "exact.jsonl") != slurp(d / "cut.jsonl"));  // fewer votes: other evidence
  for (const std::string bad :
       {"--belief-budget -1", "--belief-budget x", "--max-pairs -2", "--likelihood-cutoff -1", "--likelihood-cutoff y"}) {
    INFO(bad);
    CHECK(run_sva(base + bad + " --out " + (d / "bad.jsonl").string(), &out) != 0);
    CHECK_THAT(out, Contains(bad.substr(0, bad.find(' '))));
    CHECK_FALSE(std::filesystem::exists(d / "bad.jsonl"));
  }
}
