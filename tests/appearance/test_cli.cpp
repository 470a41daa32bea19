#include <catch2/catch.hpp>

#include <sva/dataset.hpp>

#include <cstdlib>
#include <fstream>
#include <iterator>

#include "synthetic.hpp"
#include "test_support.hpp"

using namespace sva;
using Catch::Contains;

namespace {
// tests/main.cpp normally sets SVA_BIN; if a runner does not, fall back to
// the sva binary of the build tree this test executable belongs to.
int run(const std::string& args, std::string* out) {
  if (!std::getenv("SVA_BIN")) {
    const auto build = std::filesystem::read_symlink("/proc/self/exe").parent_path().parent_path();
    for (const auto& sva : {build / "sva", build / "host" / "cli" / "sva"})
      if (std::filesystem::exists(sva)) {
        ::setenv("SVA_BIN", sva.c_str(), 1);
        break;
      }
  }
  return test::run_sva(args, out);
}

std::vector<char> bytes_of(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}
}  // namespace

TEST_CASE("cli: sva train and sva inspect on a map") {
  const auto dir = test::temp_dir("cli-train");
  save_dataset(test::synthetic_dataset(3, 40), dir / "train.svad");
  // A synthetic dataset names no real mesh: trained as a real sensor's recordings are, without surfaces.
  const std::string base = "train --no-surfaces --data " + (dir / "train.svad").string() + " --out ";
  const std::string small_calibration = " --calibration-sessions 10 --calibration-readings 4";
  std::string out;
  REQUIRE(run(base + (dir / "a.svamap").string() + " --threads 1" + small_calibration, &out) == 0);
  CHECK_THAT(out, Contains("entries") && Contains("classes") && Contains("calibration    learned"));
  REQUIRE(run(base + (dir / "b.svamap").string() + " --threads 2" + small_calibration, &out) == 0);
  CHECK(bytes_of(dir / "a.svamap") == bytes_of(dir / "b.svamap"));
  REQUIRE(run("inspect " + (dir / "a.svamap").string(), &out) == 0);
  CHECK_THAT(out, Contains("sva map") && Contains("ambiguity A") && Contains("entries/key") && Contains("obj2") &&
                      Contains("learned: temperature") && Contains("from 10 + 5 held-out sessions of 4 readings") &&
                      Contains("fine pose from 6 readings") &&
                      Contains("says \"none of these\" (from the evidence alone)"));  // too short for a fine pose
  // The fine pose from 3 readings: the map keeps it, and sessions of 4 readings now reach it in the calibration.
  REQUIRE(run(base + (dir / "f.svamap").string() + small_calibration + " --fine-pose-from 3", &out) == 0);
  CHECK_THAT(out, Contains("fine pose from 3 readings") &&
                      Contains("says \"none of these\" (from the evidence, then the fine pose's fit)"));
  CHECK(run(base + (dir / "g.svamap").string() + " --fine-pose-from 1001", &out) != 0);
  CHECK_THAT(out, Contains("--fine-pose-from 1001 is out of range [3, 1000]"));
  REQUIRE(run(base + (dir / "e.svamap").string() + " --calibration-sessions 10 --calibration-readings 8", &out) == 0);
  REQUIRE(run("inspect " + (dir / "e.svamap").string(), &out) == 0);
  CHECK_THAT(out, Contains("says \"none of these\" (from the evidence, then the fine pose's fit)"));
  REQUIRE(run(base + (dir / "c.svamap").string() +
                  " --descriptor mn --clusters 4 --dist-bins 7 --dist-range 10:60 --no-calibration",
              &out) == 0);
  CHECK_THAT(out, Contains("calibration off"));
  REQUIRE(run("inspect " + (dir / "c.svamap").string(), &out) == 0);
  CHECK_THAT(out, Contains("MN (64 values)") && Contains("7 over 10-60 mm") && Contains("calibration    the default"));
  CHECK(run(base + (dir / "d.svamap").string() + " --calibration-readings 1", &out) != 0);
  CHECK_THAT(out, Contains("calibration readings 1"));
  std::filesystem::remove_all(dir);
}

TEST_CASE("cli: bad maps and bad options exit non-zero with a message") {
  const auto dir = test::temp_dir("cli-bad");
  save_dataset(test::synthetic_dataset(2, 20), dir / "train.svad");
  const std::string base = "train --no-surfaces --data " + (dir / "train.svad").string() + " --out " +
                           (dir / "m.svamap").string() + " --no-calibration";
  std::string out;
  REQUIRE(run(base, &out) == 0);
  auto bytes = bytes_of(dir / "m.svamap");
  bytes[bytes.size() - 7] ^= 1;
  {
    std::ofstream f(dir / "bad.svamap", std::ios::binary);
    f.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  }
  CHECK(run("inspect " + (dir / "bad.svamap").string(), &out) != 0);
  CHECK_THAT(out, Contains("bad.svamap") && Contains("checksum"));
  // Checked by the library (TrainOptions::validate), named by the command.
  CHECK(run(base + " --dist-range 80:20", &out) != 0);
  CHECK_THAT(out, Contains("sva train") && Contains("distance range 80"));
  CHECK(run(base + " --dist-range abc", &out) != 0);
  CHECK(run(base + " --descriptor sift", &out) != 0);
  CHECK_THAT(out, Contains("sift"));
  CHECK(run(base + " --clusters 0", &out) != 0);
  CHECK_THAT(out, Contains("clusters 0: expected 1 to 4096"));
  CHECK(run("train --data " + (dir / "nope.svad").string() + " --out " + (dir / "x.svamap").string(), &out) != 0);
  CHECK_THAT(out, Contains("nope.svad"));
  CHECK(run("train --data " + (dir / "m.svamap").string() + " --out " + (dir / "x.svamap").string(), &out) != 0);
  CHECK_FALSE(std::filesystem::exists(dir / "x.svamap"));
  std::filesystem::remove_all(dir);
}
