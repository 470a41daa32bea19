#include "roofline/vote_math.hpp"

#include <sva/base/rng.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>

#include "backends/vulkan/gpu_layout.hpp"
#include "spv/vote_math.h"
#include "spv/vote_math_device_division.h"
#include "sva_shared.h"  // SVA_WORKGROUP_SIZE
#include "votes/vote_math.hpp"

namespace sva::bench {

namespace {

namespace vm = sva::vote_math;
constexpr std::size_t kMatchFloats = 28;

// The paper's spatial pose grid (60 translation bins of 5 mm from -150 mm, 36 rotation bins), as the stage tests.
struct GridPush {
  std::uint32_t n = 0;
  std::int32_t kind = SVA_POSE_SPATIAL;
  std::int32_t translation_bins = 60;
  float translation_min = -150.0f;
  float translation_width = 5.0f;
  std::int32_t rotation_bins = 36;
  float rotation_width = 6.28318530717959f / 36;
};

void random_patch(util::Rng& rng, float* f, float reach) {
  for (int k = 0; k < 3; ++k) f[k] = static_cast<float>(reach * (rng.uniform() - 0.5));
  float n[3];
  double len = 0.0;
  for (float& v : n) {
    v = static_cast<float>(rng.uniform() - 0.5);
    len += static_cast<double>(v) * v;
  }
  len = std::sqrt(std::max(len, 1e-12));
  for (int k = 0; k < 3; ++k) f[3 + k] = static_cast<float>(n[k] / len);
  f[6] = static_cast<float>(0.3 + 0.7 * rng.uniform());
}

vm::SvaPatch patch_at(const float* f) {
  vm::SvaPatch p;
  p.p = glm::vec3(f[0], f[1], f[2]);
  p.n = glm::vec3(f[3], f[4], f[5]);
  p.conf = f[6];
  return p;
}

// One kernel over the matches: best of three GPU times (0 without timestamps), its checksums in `out`.
double run_kernel(vk::Context& ctx, const char* name, std::span<const std::uint32_t> spirv, vk::Buffer& in,
                  vk::Buffer& out, std::size_t matches) {
  const vk::Pipeline pipe = ctx.create_pipeline(name, spirv, 2, sizeof(GridPush));
  GridPush push;
  push.n = static_cast<std::uint32_t>(matches);
  const vk::Dispatch d{&pipe,
                       {&in, &out},
                       gpu::push_bytes(push),
                       static_cast<std::uint32_t>((matches + SVA_WORKGROUP_SIZE - 1) / SVA_WORKGROUP_SIZE)};
  double best = 0.0;
  for (int rep = 0; rep < 3; ++rep) {
    std::vector<double> ms;
    ctx.run({d}, &ms);
    double t = 0.0;
    for (double m : ms) t += m;
    if (t > 0 && (best == 0.0 || t < best)) best = t;
  }
  return best;
}

}  // namespace

std::vector<float> vote_math_matches(std::size_t matches, std::uint64_t seed) {
  util::Rng rng(seed, 11);
  std::vector<float> in(matches * kMatchFloats);
  for (std::size_t c = 0; c < matches; ++c) {
    float* f = &in[c * kMatchFloats];
    for (int k = 0; k < 4; ++k) random_patch(rng, f + 7 * k, 160.0f);
  }
  return in;
}

std::uint32_t vote_math_checksum(const float* f, std::uint32_t out[3]) {
  const GridPush g;
  const vm::SvaAlignment al = vm::sva_align(patch_at(f), patch_at(f + 7), patch_at(f + 14), patch_at(f + 21));
  const vm::SvaPoseGrid grid = vm::sva_pose_grid(g.kind, g.translation_bins, g.translation_min, g.translation_width,
                                                 g.rotation_bins, g.rotation_width);
  const vm::SvaBetaPlan plan = vm::sva_beta_plan(al, grid);
  const float scale = vm::sva_vote_scale(1.0f, vm::sva_beta_weight_sum(plan));
  std::uint32_t keys = 0, masses = 0, inside = 0;
  for (int i = 0; i < plan.n; ++i) {
    const float weight = vm::sva_beta_weight(plan, i) * scale;
    const vm::SvaVote v = vm::sva_vote(al, plan, grid, 1u, weight, i);
    keys = keys * 31u + (static_cast<std::uint32_t>(v.key) ^ static_cast<std::uint32_t>(v.key >> 32));
    masses += static_cast<std::uint32_t>(static_cast<std::uint64_t>(v.mass) & 0xffffffffu);
    inside += static_cast<std::uint32_t>(v.inside);
  }
  out[0] = keys;
  out[1] = masses;
  out[2] = inside;
  return static_cast<std::uint32_t>(plan.n);
}

VoteMathRoofline measure_vote_math(vk::Context& ctx, std::size_t matches) {
  const std::vector<float> in = vote_math_matches(matches, 9);
  VoteMathRoofline r;
  r.matches = matches;
  auto bin = ctx.create_buffer(in.size() * sizeof(float));
  auto bout = ctx.create_buffer(matches * 3 * sizeof(std::uint32_t));
  std::memcpy(bin.data(), in.data(), in.size() * sizeof(float));
  r.exact_ms = run_kernel(ctx, "vote_math", sva_spv_vote_math, bin, bout, matches);
  r.exact_agrees = true;
  for (std::size_t c = 0; c < matches; ++c) {  // every match: its samples are counted here too
    std::uint32_t want[3];
    r.samples += vote_math_checksum(&in[c * kMatchFloats], want);
    r.exact_agrees = r.exact_agrees && std::memcmp(want, bout.as<std::uint32_t>() + 3 * c, sizeof want) == 0;
  }
  r.device_division_ms =
      run_kernel(ctx, "vote_math_device_division", sva_spv_vote_math_device_division, bin, bout, matches);
  return r;
}

}  // namespace sva::bench
