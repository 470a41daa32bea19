// Fitting per-element gains against known loads: an emulated array with known
// gains, zeros and noise (frames built directly, and through a recording and
// `sva calibrate`), the fit recovering them, and every ill-conditioned fit
// refused with a message naming the load or element.
#include <catch2/catch.hpp>

#include <sva/drivers/calibration.hpp>
#include <sva/drivers/session.hpp>
#include <sva/error.hpp>

#include <cmath>
#include <random>

#include "test_support.hpp"

using namespace sva::drivers;
using Catch::Contains;

namespace {

// A 4 x 5 array whose element i has zero 900 + 7 i counts and gain 0.01 + 0.0005 i kPa per count, read with
// Gaussian noise of `noise` counts.
struct EmulatedArray {
  sva::SensorSpec spec{4, 5, 2.0};
  std::vector<double> gain, zero;
  double noise = 1.0;
  std::mt19937 rng{7};
  std::uint16_t sequence = 0;

  EmulatedArray() {
    for (int i = 0; i < spec.elements(); ++i) {
      gain.push_back(0.01 + 0.0005 * i);
      zero.push_back(900.0 + 7.0 * i);
    }
  }
  TactileFrame frame(double kpa) {
    std::normal_distribution<double> n(0.0, noise);
    TactileFrame f{sequence++, spec.rows, spec.cols, {}};
    for (std::size_t i = 0; i < gain.size(); ++i)
      f.counts.push_back(static_cast<std::uint16_t>(std::lround(zero[i] + kpa / gain[i] + n(rng))));
    return f;
  }
  std::vector<TactileFrame> frames(int count, double kpa) {
    std::vector<TactileFrame> out;
    for (int k = 0; k < count; ++k) out.push_back(frame(kpa));
    return out;
  }
};

}  // namespace

TEST_CASE("the gain fit recovers each element's known gain and zero from loaded frames") {
  EmulatedArray array;
  auto c = Calibration::uniform(array.spec, 1.0f, 0.0f);
  const auto unloaded = array.frames(200, 0.0);
  const std::vector<LoadFrames> loads{{10.0, array.frames(100, 10.0)}, {25.0, array.frames(100, 25.0)}};
  const GainFit fit = fit_gains(c, unloaded, loads);
  CHECK(fit.loads == 2);
  CHECK(fit.frames == 200);
  for (std::size_t i = 0; i < array.gain.size(); ++i) {
    // The counts carry 1 count of noise and rounding on ~1000 counts of signal: the gains to about 0.2%.
    CHECK(std::abs(c.gain[i] - array.gain[i]) < 3e-3 * array.gain[i]);
    CHECK(std::abs(c.zero[i] - array.zero[i]) < 0.3);
  }
  // The residual is the noise, in kPa: about gain * 1 count.
  CHECK(fit.rms_residual_kpa > 0.005);
  CHECK(fit.rms_residual_kpa < 0.05);
  CHECK(fit.relative_residual < 0.01);
  CHECK(fit.min_gain == Approx(array.gain.front()).epsilon(3e-3));
  CHECK(fit.max_gain == Approx(array.gain.back()).epsilon(3e-3));
  // The fitted calibration reads the loads back.
  const auto p = c.to_pressure(array.frame(25.0));
  for (float v : p) CHECK(std::abs(v - 25.0) < 0.2);
}

TEST_CASE("ill-conditioned or inconsistent gain fits are refused and leave the calibration unchanged") {
  EmulatedArray array;
  const auto base = Calibration::uniform(array.spec, 1.0f, 0.0f);
  auto c = base;
  const auto unloaded = array.frames(50, 0.0);
  auto loaded = [&](double kpa) { return std::vector<LoadFrames>{{kpa, array.frames(50, kpa)}}; };

  CHECK_THROWS_WITH(fit_gains(c, unloaded, {}), Contains("no loads"));
  CHECK_THROWS_WITH(fit_gains(c, {}, loaded(10)), Contains("no unloaded frames"));
  CHECK_THROWS_WITH(fit_gains(c, unloaded, std::vector<LoadFrames>{{0.0, array.frames(5, 0)}}),
                    Contains("above 0 kPa"));
  CHECK_THROWS_WITH(fit_gains(c, unloaded, std::vector<LoadFrames>{{10.0, {}}}), Contains("10 kPa has no frames"));

  // A load too light to lift the elements above their noise: the slopes are mostly noise.
  array.noise = 3.0;
  const auto noisy_zero = array.frames(50, 0.0);
  CHECK_THROWS_WITH(fit_gains(c, noisy_zero, loaded(0.05)), Contains("ill-conditioned") && Contains("element 0"));
  array.noise = 1.0;

  // A dead element (stuck at its zero) and one wired backwards.
  auto dead = loaded(10);
  for (auto& f : dead[0].frames) f.counts[7] = static_cast<std::uint16_t>(array.zero[7]);
  CHECK_THROWS_WITH(fit_gains(c, unloaded, dead), Contains("element 7 (row 1, col 2)") && Contains("ill-conditioned"));
  auto backwards = loaded(10);
  for (auto& f : backwards[0].frames) f.counts[3] = 100;
  CHECK_THROWS_WITH(fit_gains(c, unloaded, backwards), Contains("element 3") && Contains("falls"));

  // Saturated under load.
  c.saturation_counts = 1500;
  CHECK_THROWS_WITH(fit_gains(c, unloaded, loaded(10)), Contains("saturated under 10 kPa"));
  c.saturation_counts = 65535;

  // Presses that do not match the load list (10 and 20 kPa given, both pressed at 15): not linear.
  const std::vector<LoadFrames> swapped{{10.0, array.frames(50, 15.0)}, {20.0, array.frames(50, 15.0)}};
  CHECK_THROWS_WITH(fit_gains(c, unloaded, swapped), Contains("residual") && Contains("linearly"));

  // Frames of another array.
  std::vector<LoadFrames> wrong{{10.0, {TactileFrame{0, 6, 6, std::vector<std::uint16_t>(36, 1000)}}}};
  CHECK_THROWS_WITH(fit_gains(c, unloaded, wrong), Contains("6 x 6"));

  CHECK(c.gain == base.gain);
  CHECK(c.zero == base.zero);
}

TEST_CASE("sva calibrate --load fits the gains from a recording of the presses and reports the residual") {
  EmulatedArray array;
  const auto dir = sva::test::temp_dir("calibrate-fit");
  const auto file = dir / "presses.svar";
  {
    SessionWriter writer(file, {Calibration::uniform(array.spec, 1.0f, 0.0f), {}, "emulated array"});
    std::int64_t ns = 1'000'000'000;
    auto emit = [&](int count, double kpa) {
      for (int k = 0; k < count; ++k, ns += 1'000'000)
        writer.chunk(Chunk{LinkStatus::data, ns, encode_frame(array.frame(kpa)), {}});
    };
    emit(100, 0.0);
    emit(10, 5.0), emit(100, 12.0);  // 10 frames of the press settling, skipped
    emit(10, 30.0), emit(100, 24.0);
    writer.chunk(Chunk{LinkStatus::ended, ns, {}, "end"});
  }
  const auto out = dir / "cal.json";
  std::string text;
  REQUIRE(sva::test::run_sva("calibrate --session " + file.string() + " --rows 4 --cols 5 --frames 100 --skip 10 " +
                                 "--load 12 --load 24 --out " + out.string(),
                             &text) == 0);
  CHECK_THAT(text, Contains("gain fit: 2 loads, 200 frames") && Contains("residual"));
  const auto c = Calibration::load(out);
  for (std::size_t i = 0; i < array.gain.size(); ++i) CHECK(std::abs(c.gain[i] - array.gain[i]) < 3e-3 * array.gain[i]);

  // The same presses against a wrong load list: refused, naming the fault, and no file written.
  const auto bad = dir / "bad.json";
  REQUIRE(sva::test::run_sva("calibrate --session " + file.string() + " --rows 4 --cols 5 --frames 100 --skip 10 " +
                                 "--load 24 --load 12 --out " + bad.string(),
                             &text) != 0);
  CHECK_THAT(text, Contains("linearly"));
  CHECK_FALSE(std::filesystem::exists(bad));
  REQUIRE(sva::test::run_sva("calibrate --session " + file.string() + " --load x3 --out " + bad.string(), &text) != 0);
  CHECK_THAT(text, Contains("--load x3"));
}
