#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "test_support.hpp"

using sva::test::run_sva;

namespace {
// Drops the timing fields, the only ones allowed to differ between backends.
nlohmann::json without_timing(nlohmann::json j) {
  if (j.is_object()) {
    for (auto it = j.begin(); it != j.end();) {
      const std::string k = it.key();
      if (k.find("_ms") != std::string::npos || k == "backend")
        it = j.erase(it);
      else {
        *it = without_timing(*it);
        ++it;
      }
    }
  } else if (j.is_array()) {
    for (auto& v : j) v = without_timing(v);
  }
  return j;
}
}  // namespace

TEST_CASE("sva eval: the Vulkan backend (trials batched per submission) gives the CPU reference's JSON") {
  auto d = sva::test::temp_dir("eval-agreement");
  std::string out;
  REQUIRE(run_sva("simulate --scene tiny --out " + d.string() + " --seed 5", &out) == 0);
  REQUIRE(run_sva("train --data " + (d / "train.svad").string() + " --out " + (d / "map.svam").string(), &out) == 0);
  const std::string common = "eval --map " + (d / "map.svam").string() + " --data " + (d / "test.svad").string() +
                             " --trials 6 --max-readings 5 --seed 9";
  REQUIRE(run_sva(common + " --backend cpu --json " + (d / "cpu.json").string(), &out) == 0);
  const int rc = run_sva(common + " --backend vulkan --json " + (d / "gpu.json").string(), &out);
  if (rc != 0 && out.find("no Vulkan device") != std::string::npos) sva::test::skip(out);
  REQUIRE(rc == 0);
  nlohmann::json cpu, gpu;
  std::ifstream(d / "cpu.json") >> cpu;
  std::ifstream(d / "gpu.json") >> gpu;
  CHECK(cpu["backend"] == "cpu");
  CHECK(gpu["backend"] == "vulkan");
  REQUIRE(cpu["curve"].size() == 5);
  CHECK(without_timing(cpu) == without_timing(gpu));
  std::filesystem::remove_all(d);
}
