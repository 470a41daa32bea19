#include "roofline/roofline.hpp"

#include <sva/base/rng.hpp>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <span>
#include <vector>

#include "backends/vulkan/context.hpp"
#include "backends/vulkan/gpu_layout.hpp"
#include "roofline/hash_scatter.hpp"
#include "spv/fixed_point_scatter.h"
#include "sva_shared.h"  // SVA_WORKGROUP_SIZE

namespace sva::bench {

namespace {

using Clock = std::chrono::steady_clock;

struct ScatterPush {
  std::uint32_t count, bin_count, base;  // base: first vote of this dispatch
};

// The bare fixed-point scatter of `w` into `s` by bin `b`: best of three runs,
// GPU time when the device has timestamps, else wall time.
double fixed_point_scatter_ms(vk::Context& ctx, vk::Buffer& w, vk::Buffer& b, vk::Buffer& s, std::size_t votes,
                              std::size_t bins) {
  auto pipeline = ctx.create_pipeline("fixed_point_scatter", sva_spv_fixed_point_scatter, 3, sizeof(ScatterPush));
  // One dispatch covers at most maxComputeWorkGroupCount[0] workgroups.
  std::vector<vk::Dispatch> dispatches;
  const std::size_t per = std::size_t{ctx.info().max_workgroup_count_x} * SVA_WORKGROUP_SIZE;
  for (std::size_t base = 0; base < votes; base += per) {
    const ScatterPush push{static_cast<std::uint32_t>(votes), static_cast<std::uint32_t>(bins),
                           static_cast<std::uint32_t>(base)};
    const std::size_t n = std::min(per, votes - base);
    dispatches.push_back({&pipeline,
                          {&w, &b, &s},
                          gpu::push_bytes(push),
                          static_cast<std::uint32_t>((n + SVA_WORKGROUP_SIZE - 1) / SVA_WORKGROUP_SIZE)});
  }
  std::vector<double> kernel;
  double best_kernel = 1e30, best_wall = 1e30;
  for (int rep = 0; rep < 3; ++rep) {
    const auto t0 = Clock::now();
    ctx.run(dispatches, &kernel);
    best_wall = std::min(best_wall, std::chrono::duration<double, std::milli>(Clock::now() - t0).count());
    double k = 0.0;
    for (double m : kernel) k += m;
    if (!kernel.empty()) best_kernel = std::min(best_kernel, k);
  }
  return best_kernel < 1e30 ? best_kernel : best_wall;
}

// The same votes through the vote kernel's hash table; 0 without timestamps.
double hash_scatter_ms(vk::Context& ctx, const vk::Buffer& w, const vk::Buffer& b, std::size_t votes,
                       std::size_t bins) {
  std::vector<std::uint64_t> keys(votes);
  for (std::size_t i = 0; i < votes; ++i) keys[i] = b.as<std::uint32_t>()[i] * 0x9e3779b97f4a7c15ull >> 2;
  const std::span<const float> weights(w.as<float>(), votes);
  HashScatter hs(ctx, 4 * bins);
  hs.run(keys, weights);  // sizes the table
  double ms = 1e30;
  for (int rep = 0; rep < 3; ++rep) {
    hs.run(keys, weights);
    ms = std::min(ms, hs.last_kernel_ms());
  }
  return ms > 0 && ms < 1e30 ? ms : 0.0;
}

}  // namespace

Roofline measure_roofline(std::size_t votes, std::size_t bins, const std::string& device) {
  vk::ContextOptions co = vk::Context::from_environment();
  if (!device.empty()) co.device = device;
  vk::Context ctx(co);
  util::Rng rng(5);
  auto w = ctx.create_buffer(votes * sizeof(float));
  auto b = ctx.create_buffer(votes * sizeof(std::uint32_t));
  auto s = ctx.create_buffer(bins * sizeof(std::int64_t));
  for (std::size_t i = 0; i < votes; ++i) {
    w.as<float>()[i] = static_cast<float>(rng.uniform());
    b.as<std::uint32_t>()[i] = static_cast<std::uint32_t>(rng.below(bins));
  }
  Roofline r;
  r.device = ctx.info().name + " (" + ctx.info().type + ")";
  r.votes = votes;
  r.bins = bins;
  r.kernel_ms = fixed_point_scatter_ms(ctx, w, b, s, votes, bins);
  r.votes_per_second = 1e3 * static_cast<double>(votes) / r.kernel_ms;
  r.hash_kernel_ms = hash_scatter_ms(ctx, w, b, votes, bins);
  if (r.hash_kernel_ms > 0) r.hash_votes_per_second = 1e3 * static_cast<double>(votes) / r.hash_kernel_ms;
  // About a vote per sample on a GPU (a match casts 10-20); a CPU device (lavapipe) runs the math on the host's
  // cores, where a sixteenth of that already times it.
  const std::size_t matches = votes / (ctx.info().type == "cpu" ? 256 : 16);
  r.vote_math = measure_vote_math(ctx, std::max<std::size_t>(matches, 64));
  r.host_reads = measure_host_reads(ctx);
  return r;
}

}  // namespace sva::bench
