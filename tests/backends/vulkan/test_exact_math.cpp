// The agreement contract of docs/vulkan-backend.md: Vulkan only promises
// division to 2.5 ULP and a square root derived from inversesqrt, so the shared
// vote math divides and takes roots through sva_div and sva_sqrt, which in GLSL
// compute the correctly rounded IEEE result with integer arithmetic. Here the
// GLSL versions run on the device and must equal the CPU's IEEE division and
// square root bit for bit over the normal range, and the vote math may use no
// other division or root.
#include <sva/base/rng.hpp>

#include <catch2/catch.hpp>

#include <bit>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <regex>
#include <span>
#include <vector>

#include "backends/vulkan/gpu_layout.hpp"
#include "spv/exact_math.h"
#include "spv/exact_math_skewed.h"
#include "vk_test_support.hpp"

namespace {

const std::filesystem::path kShaderInclude = SVA_TEST_SHADER_INCLUDE;

bool normal_or_zero(float x) { return x == 0.0f || std::fpclassify(x) == FP_NORMAL || std::isinf(x) || std::isnan(x); }

// Same bits, or both NaN (the payload carries no meaning).
bool same(float x, float y) {
  return (std::isnan(x) && std::isnan(y)) || std::bit_cast<std::uint32_t>(x) == std::bit_cast<std::uint32_t>(y);
}

// Operands: the hard cases (ties and near-ties of the rounding, exact quotients, powers of two, the extremes of the
// normal range, zeros, infinities and NaN) pairwise, then random significands over a wide but overflow-free
// exponent range, both signs.
void operands(std::vector<float>* a, std::vector<float>* b, int random) {
  const float specials[] = {1.0f,
                            -1.0f,
                            3.0f,
                            7.0f,
                            0.1f,
                            1.0f + 0x1p-23f,
                            2.0f - 0x1p-23f,
                            0x1p-126f,
                            0x1.fffffep127f,
                            0x1p100f,
                            0x1p-100f,
                            0.0f,
                            -0.0f,
                            INFINITY,
                            -INFINITY,
                            NAN,
                            6.28318530717959f,
                            1e-30f};
  for (float x : specials)
    for (float y : specials) {
      a->push_back(x);
      b->push_back(y);
    }
  sva::util::Rng rng(21, 4);
  const auto bits = [&](int lo, int hi) {
    const std::uint32_t e =
        static_cast<std::uint32_t>(lo + static_cast<int>(rng.below(static_cast<std::uint64_t>(hi - lo))));
    return std::bit_cast<float>((static_cast<std::uint32_t>(rng.below(2)) << 31) | (e << 23) |
                                static_cast<std::uint32_t>(rng.below(1u << 23)));
  };
  for (int i = 0; i < random; ++i) {
    a->push_back(bits(64, 190));
    b->push_back(bits(64, 190));
  }
}

// Runs a kernel of the exact_math layout (a, b in; a / b and sqrt(a) out) and compares with the CPU's IEEE
// results; returns the quotients compared.
std::size_t compare_with_ieee(sva::vk::Context& ctx, std::span<const std::uint32_t> spirv,
                              const std::vector<std::uint8_t>& push, const std::vector<float>& a,
                              const std::vector<float>& b) {
  const auto n = static_cast<std::uint32_t>(a.size());
  auto ba = ctx.create_buffer(n * sizeof(float)), bb = ctx.create_buffer(n * sizeof(float));
  auto bq = ctx.create_buffer(n * sizeof(float)), br = ctx.create_buffer(n * sizeof(float));
  std::memcpy(ba.data(), a.data(), n * sizeof(float));
  std::memcpy(bb.data(), b.data(), n * sizeof(float));
  const sva::vk::Pipeline pipe = ctx.create_pipeline("exact_math", spirv, 4, static_cast<std::uint32_t>(push.size()));
  ctx.run({sva::vk::Dispatch{&pipe, {&ba, &bb, &bq, &br}, push, (n + 63) / 64}});
  const float* q = bq.as<float>();
  const float* r = br.as<float>();
  std::size_t checked = 0;
  for (std::uint32_t i = 0; i < n; ++i) {
    const float want_q = a[i] / b[i], want_r = std::sqrt(a[i]);
    // The contract covers operands and results in the normal range (and zeros, infinities, NaN).
    if (normal_or_zero(a[i]) && normal_or_zero(b[i]) && normal_or_zero(want_q)) {
      INFO(a[i] << " / " << b[i]);
      CHECK(same(q[i], want_q));
      ++checked;
    }
    if (normal_or_zero(a[i]) && normal_or_zero(want_r)) {
      INFO("sqrt " << a[i]);
      CHECK(same(r[i], want_r));
    }
  }
  return checked;
}

}  // namespace

TEST_CASE("sva_div and sva_sqrt on the device equal IEEE division and square root bit for bit") {
  auto ctx = sva::test::vulkan_context_or_skip();
  std::vector<float> a, b;
  operands(&a, &b, 200000);
  const auto n = static_cast<std::uint32_t>(a.size());
  CHECK(compare_with_ieee(*ctx, sva_spv_exact_math, sva::gpu::push_bytes(n), a, b) > 190000);
}

TEST_CASE("sva_div and sva_sqrt stay exact when the device's own estimate is off (corrected, or the fallback)") {
  // The fast paths start from the device's division and square root; a device within Vulkan's 2.5 ULP is a few
  // units off, one outside it may be far off. Skewed estimates take each path on any device.
  auto ctx = sva::test::vulkan_context_or_skip();
  std::vector<float> a, b;
  operands(&a, &b, 20000);
  const auto n = static_cast<std::uint32_t>(a.size());
  for (std::int32_t skew : {1, -1, 6, -7, 9, -9, 1000000, -1000000}) {
    INFO("estimate off by " << skew << " units");
    struct {
      std::uint32_t n;
      std::int32_t skew;
    } push{n, skew};
    CHECK(compare_with_ieee(*ctx, sva_spv_exact_math_skewed, sva::gpu::push_bytes(push), a, b) > 19000);
  }
}

TEST_CASE("the shared vote math divides and takes roots only through sva_div and sva_sqrt") {
  // A plain `/` between runtime values or a builtin sqrt would break the
  // contract on devices that do not round them correctly. Constant folding
  // (literal / literal, done once by glslang and by the C++ compiler) is fine.
  const std::regex runtime_div(R"([A-Za-z_\)\]][\w\.\]\)]*\s*/\s*[A-Za-z_\(])");
  const std::regex builtin_root(R"((^|[^_\w])(sqrt|inversesqrt)\s*\()");
  if (!std::filesystem::is_directory(kShaderInclude))
    sva::test::skip("no source tree here (" + kShaderInclude.string() + ")");
  int estimates = 0;
  for (const char* name : {"sva_fast_math.h", "sva_quaternion.h", "sva_alignment.h", "sva_pose_bins.h",
                           "sva_beta_sampling.h", "sva_match_likelihood.h", "sva_match_owner.h", "sva_vote_math.h"}) {
    std::ifstream in(kShaderInclude / name);
    REQUIRE(in);
    std::string line;
    bool in_cpp_branch = false;
    int number = 0;
    while (std::getline(in, line)) {
      ++number;
      if (line.rfind("#ifdef __cplusplus", 0) == 0) in_cpp_branch = true;
      if (line.rfind("#else", 0) == 0 || line.rfind("#endif", 0) == 0) in_cpp_branch = false;
      const std::string code = line.substr(0, line.find("//"));
      if (in_cpp_branch || code.find('#') == 0) continue;
      // sva_div's and sva_sqrt's own first estimates, which their exact integer corrections make harmless.
      if (line.find("// sva-exact: an estimate, corrected exactly below") != std::string::npos) {
        CHECK(std::string(name) == "sva_fast_math.h");
        ++estimates;
        continue;
      }
      INFO(name << ":" << number << ": " << line);
      CHECK_FALSE(std::regex_search(code, runtime_div));
      CHECK_FALSE(std::regex_search(code, builtin_root));
    }
  }
  CHECK(estimates == 2);  // one in sva_div, one in sva_sqrt
}
