#include <catch2/catch.hpp>

#include <sva/base/rng.hpp>
#include <sva/error.hpp>

#include <cmath>

#include "appearance/appearance_model.hpp"
#include "appearance/descriptor.hpp"
#include "synthetic.hpp"

using namespace sva;

namespace {

AppearanceModel model(DescriptorKind kind) {
  AppearanceModel m;
  m.descriptor = kind;
  m.mn_size = 8;
  m.mnti_pad = 16;
  m.mnti_freqs = 4;
  m.descriptor_size = kind == DescriptorKind::mn ? 64 : appearance::fourier_magnitude_count(4);
  return m;
}

Reading reading(std::vector<float> image) {
  Reading r;
  r.pressure = std::move(image);
  return r;
}

// Rotates a square row-major image by 90 degrees `turns` times (exact, on the grid).
std::vector<float> rotate90(const std::vector<float>& img, int n, int turns) {
  std::vector<float> out = img;
  for (int t = 0; t < turns; ++t) {
    std::vector<float> next(out.size());
    for (int r = 0; r < n; ++r)
      for (int c = 0; c < n; ++c)
        next[static_cast<std::size_t>(c * n + (n - 1 - r))] = out[static_cast<std::size_t>(r * n + c)];
    out = next;
  }
  return out;
}

float dot(const std::vector<float>& a, const std::vector<float>& b) {
  REQUIRE(a.size() == b.size());
  return appearance::affinity(a.data(), b.data(), static_cast<std::uint32_t>(a.size()));
}

// An asymmetric image: an elongated blob plus a weaker one to one side.
std::vector<float> asymmetric(const SensorSpec& s, util::Rng& rng) {
  auto a = test::blob_image(s, rng.uniform(0.8, 1.5), rng.uniform(2.0, 3.0), rng.uniform(0, 3.14),
                            rng.uniform(-0.5, 0.5), 0.0);
  auto b = test::blob_image(s, 0.7, 0.7, 0.0, rng.uniform(1.0, 2.0), rng.uniform(-2.0, -1.0), 15.0);
  for (std::size_t i = 0; i < a.size(); ++i) a[i] += b[i];
  return a;
}

}  // namespace

TEST_CASE("descriptor: MN is invariant to 90/180/270 degree rotations of the image") {
  const AppearanceModel m = model(DescriptorKind::mn);
  util::Rng rng(3);
  for (int trial = 0; trial < 20; ++trial) {
    const auto img = asymmetric(m.calibration.sensor, rng);
    const auto base = m.describe(reading(img));
    CHECK(dot(base, base) == Approx(1.0f).margin(1e-5));
    for (int turns = 1; turns <= 3; ++turns) {
      const auto rotated = m.describe(reading(rotate90(img, 6, turns)));
      CHECK(dot(base, rotated) >= 0.99f);
    }
  }
}

TEST_CASE("descriptor: MN tells different shapes apart") {
  const AppearanceModel m = model(DescriptorKind::mn);
  const SensorSpec s;
  const auto line = m.describe(reading(test::blob_image(s, 0.6, 4.0, 0.3, 0, 0)));
  const auto disc = m.describe(reading(test::blob_image(s, 3.0, 3.0, 0.0, 0, 0)));
  CHECK(dot(line, disc) < 0.9f);
}

TEST_CASE("descriptor: MNTI is robust to a one-element shift") {
  const AppearanceModel m = model(DescriptorKind::mnti);
  util::Rng rng(11);
  for (int trial = 0; trial < 20; ++trial) {
    // Content away from the border, so a shift keeps all of it on the sensor.
    std::vector<float> img(36, 0.0f), shifted(36, 0.0f);
    for (int r = 1; r < 4; ++r)
      for (int c = 1; c < 4; ++c) img[static_cast<std::size_t>(r * 6 + c)] = static_cast<float>(rng.uniform(3.0, 30.0));
    const int dr = trial % 2, dc = 1 - trial % 2;
    for (int r = 0; r + dr < 6; ++r)
      for (int c = 0; c + dc < 6; ++c)
        shifted[static_cast<std::size_t>((r + dr) * 6 + c + dc)] = img[static_cast<std::size_t>(r * 6 + c)];
    const auto a = m.describe(reading(img)), b = m.describe(reading(shifted));
    CHECK(a.size() == 25);
    CHECK(dot(a, a) == Approx(1.0f).margin(1e-5));
    CHECK(dot(a, b) >= 0.95f);
  }
}

TEST_CASE("descriptor: images that cannot be described are refused with a reason") {
  const AppearanceModel m = model(DescriptorKind::mnti);
  CHECK_THROWS_WITH(m.describe(reading(std::vector<float>(36, 0.0f))), Catch::Contains("contact threshold"));
  std::vector<float> faint(36, 1.0f);  // below the 2 kPa threshold everywhere
  CHECK_FALSE(m.why_not_describable(reading(faint)).empty());
  std::vector<float> nan(36, 10.0f);
  nan[5] = std::nanf("");
  CHECK_THROWS_WITH(m.describe(reading(nan)), Catch::Contains("non-finite"));
  CHECK_THROWS_WITH(m.describe(reading(std::vector<float>(35, 10.0f))), Catch::Contains("35 elements"));
  // A single element in contact is describable and unit length.
  std::vector<float> point(36, 0.0f);
  point[14] = 20.0f;
  CHECK(dot(m.describe(reading(point)), m.describe(reading(point))) == Approx(1.0f).margin(1e-5));
}
