#include <catch2/catch.hpp>

#include <sva/error.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <vector>

#include "backends/vulkan/context.hpp"
#include "backends/vulkan/faults.hpp"
#include "backends/vulkan/gpu_layout.hpp"
#include "spv/belief_math_device.h"
#include "vk_test_support.hpp"
#include "votes/fixed_point.hpp"

TEST_CASE("to_fixed quantises, clamps and rejects NaN") {
  CHECK(sva::to_fixed(1.0f) == SVA_FIXED_ONE);
  CHECK(sva::to_fixed(2.0f) == SVA_FIXED_ONE);
  CHECK(sva::to_fixed(0.5f) == SVA_FIXED_ONE / 2);
  CHECK(sva::to_fixed(-0.1f) == 0);
  CHECK(sva::to_fixed(NAN) == 0);
  CHECK(sva::to_fixed(INFINITY) == SVA_FIXED_ONE);
  CHECK(sva::to_fixed(1e-9f) == 0);
}

TEST_CASE("an impossible device request is a clear error") {
  sva::vk::ContextOptions o;
  o.device = "no-such-gpu-name";
  try {
    sva::vk::Context ctx(o);
    FAIL("expected an error");
  } catch (const sva::Error& e) {
    std::string m = e.what();
    CHECK((m.find("no-such-gpu-name") != std::string::npos || m.find("no Vulkan device") != std::string::npos));
  }
}

TEST_CASE("buffers have device addresses and fills clear exactly their range") {
  auto ctx = sva::test::vulkan_context_or_skip();
  auto a = ctx->create_buffer(4096), b = ctx->create_buffer(64);
  CHECK(a.device_address() != 0);
  CHECK(b.device_address() != 0);
  CHECK(a.device_address() != b.device_address());
  std::memset(a.data(), 0x11, 4096);
  ctx->run({}, nullptr, {{&a, 0xffffffffu, 1024, 2048}, {&b, 7u}});
  const auto* w = a.as<std::uint32_t>();
  CHECK(w[255] == 0x11111111u);
  CHECK(w[256] == 0xffffffffu);
  CHECK(w[767] == 0xffffffffu);
  CHECK(w[768] == 0x11111111u);
  for (int i = 0; i < 16; ++i) CHECK(b.as<std::uint32_t>()[i] == 7u);
  CHECK_THROWS_AS(ctx->run({}, nullptr, {{&b, 0u, 2, 8}}), std::logic_error);  // misaligned
  CHECK(ctx->validation_messages() == 0);
}

TEST_CASE("a submission's time is counted: recording it and waiting for it, the device's span only where timed") {
  auto ctx = sva::test::vulkan_context_or_skip();
  auto a = ctx->create_buffer(1 << 20);
  const sva::vk::SubmitTimes t0 = ctx->submit_times();
  const std::uint64_t s0 = ctx->submissions();
  ctx->run({}, nullptr, {{&a, 1u}});
  const sva::vk::SubmitTimes t1 = ctx->submit_times();
  CHECK(ctx->submissions() == s0 + 1);
  CHECK(t1.record_ms > t0.record_ms);
  CHECK(t1.wait_ms > t0.wait_ms);
  CHECK(t1.span_ms == t0.span_ms);  // no timed dispatch: no span
  CHECK(a.as<std::uint32_t>()[(1 << 18) - 1] == 1u);
}

namespace {
// n cases of belief_math_device.comp's input, 7 words each (mass, total, eps units, d, a, b, mass bits: in the
// kernel's domain), the masses shifted by `shift` so that sessions' inputs differ.
std::vector<std::uint64_t> math_cases(std::uint32_t n, std::uint64_t shift) {
  std::vector<std::uint64_t> in(std::size_t{n} * 7);
  for (std::size_t c = 0; c < n; ++c)
    std::copy_n(std::array<std::uint64_t, 7>{1 + c + shift, 2 + 2 * c, 3, c, 5 + c, 7, 20}.begin(), 7, &in[c * 7]);
  return in;
}
}  // namespace

TEST_CASE("the timed dispatches' time is summed by pipeline name, untimed runs add nothing, a reset empties it") {
  auto ctx = sva::test::vulkan_context_or_skip();
  const std::uint32_t n = 16384;  // cases: enough work for a dispatch to span ticks of any timestamp clock
  const std::vector<std::uint64_t> in = math_cases(n, 0);
  auto bin = ctx->create_buffer(in.size() * sizeof(std::uint64_t)), bout = ctx->create_buffer(bin.size());
  std::memcpy(bin.data(), in.data(), bin.size());
  // One shader under two names: the name, not the code, is what the time is summed under.
  const sva::vk::Pipeline a = ctx->create_pipeline("first", sva_spv_belief_math_device, 2, sizeof(std::uint32_t));
  const sva::vk::Pipeline b = ctx->create_pipeline("second", sva_spv_belief_math_device, 2, sizeof(std::uint32_t));
  const auto dispatch = [&](const sva::vk::Pipeline& p) {
    return sva::vk::Dispatch{&p, {&bin, &bout}, sva::gpu::push_bytes(n), (n + 63) / 64};
  };
  const sva::vk::KernelTimes before = ctx->submit_times().kernels;
  std::vector<double> ms1, ms2;
  // A pass of a pipeline (Dispatch::pass) is counted as "pipeline:pass", apart from the pipeline's other dispatches.
  sva::vk::Dispatch pass = dispatch(b);
  pass.pass = "third";
  ctx->run({dispatch(a), dispatch(b), dispatch(a)}, &ms1);
  ctx->run({dispatch(b), pass}, &ms2);
  ctx->run({dispatch(a)});  // not timed: not counted
  const sva::vk::SubmitTimes t = ctx->submit_times();
  const sva::vk::KernelTimes k = sva::vk::kernel_times_since(before, t.kernels);
  if (!ctx->info().timestamps) {
    WARN("no timestamps on " << ctx->info().name << ": nothing timed");
    CHECK(k.empty());
    return;
  }
  REQUIRE(k.size() == 3);
  REQUIRE(ms1.size() == 3);
  REQUIRE(ms2.size() == 2);
  CHECK(k.at("first").dispatches == 2);
  CHECK(k.at("second").dispatches == 2);
  CHECK(k.at("second:third").dispatches == 1);
  CHECK(k.at("first").ms == Approx(ms1[0] + ms1[2]).epsilon(1e-12));
  CHECK(k.at("second").ms == Approx(ms1[1] + ms2[0]).epsilon(1e-12));
  CHECK(k.at("second:third").ms == Approx(ms2[1]).epsilon(1e-12));
  for (const auto& [name, time] : k) CHECK(time.ms > 0.0);
  CHECK(k.at("first").ms + k.at("second").ms + k.at("second:third").ms ==
        Approx(ms1[0] + ms1[1] + ms1[2] + ms2[0] + ms2[1]).epsilon(1e-12));
  ctx->reset_submit_times();
  const sva::vk::SubmitTimes r = ctx->submit_times();
  CHECK(r.kernels.empty());
  CHECK(r.span_ms == 0.0);
  CHECK(ctx->validation_messages() == 0);
}

TEST_CASE("side_by_side records the lists round by round: one barrier before each round and each list in its order") {
  // Lists of 3, 1 and 2 dispatches, told apart by their group counts (list * 10 + place).
  std::vector<std::vector<sva::vk::Dispatch>> lists(3);
  for (std::uint32_t l = 0; l < 3; ++l)
    for (std::uint32_t i = 0; i < std::array<std::uint32_t, 3>{3, 1, 2}[l]; ++i)
      lists[l].push_back(sva::vk::Dispatch{nullptr, {}, {}, 10 * l + i});
  const std::vector<sva::vk::Dispatch> out = sva::vk::side_by_side(std::move(lists));
  std::vector<std::uint32_t> order;
  std::vector<bool> barriers;
  for (const sva::vk::Dispatch& d : out) order.push_back(d.groups_x), barriers.push_back(d.barrier);
  CHECK(order == std::vector<std::uint32_t>{0, 10, 20, 1, 21, 2});
  CHECK(barriers == std::vector<bool>{true, false, false, true, false, true});
  CHECK(sva::vk::side_by_side({}).empty());
  CHECK(sva::vk::side_by_side({{}, {}}).empty());
}

TEST_CASE("dispatches side by side share a barrier per round and give what one at a time gives: serial records all") {
  const std::uint32_t n = 4096;
  const auto run = [&](bool serial, std::uint64_t* barriers) {
    sva::vk::ContextOptions o = sva::vk::Context::from_environment();
    o.serial_dispatches = serial;
    std::unique_ptr<sva::vk::Context> ctx;
    try {
      ctx = std::make_unique<sva::vk::Context>(o);
    } catch (const sva::Error& e) {
      sva::test::skip(e.what());
    }
    const sva::vk::Pipeline p = ctx->create_pipeline("math", sva_spv_belief_math_device, 2, sizeof(std::uint32_t));
    // Three sessions, each two passes over buffers of its own: its input, then the same input again into its output
    // (the second pass overwrites the first's results with the same values: a later pass of one list).
    std::vector<sva::vk::Buffer> in, out;
    for (std::uint64_t s = 0; s < 3; ++s) {
      const std::vector<std::uint64_t> words = math_cases(n, s);
      in.push_back(ctx->create_buffer(words.size() * sizeof(std::uint64_t)));
      out.push_back(ctx->create_buffer(in.back().size()));
      std::memcpy(in.back().data(), words.data(), in.back().size());
    }
    std::vector<std::vector<sva::vk::Dispatch>> lists(3);
    for (std::size_t s = 0; s < 3; ++s)
      for (int pass = 0; pass < 2; ++pass)
        lists[s].push_back(sva::vk::Dispatch{&p, {&in[s], &out[s]}, sva::gpu::push_bytes(n), (n + 63) / 64});
    const std::uint64_t before = ctx->barriers();
    ctx->run(sva::vk::side_by_side(std::move(lists)));
    *barriers = ctx->barriers() - before;
    std::vector<std::uint64_t> results;
    for (const sva::vk::Buffer& b : out)
      results.insert(results.end(), b.as<std::uint64_t>(), b.as<std::uint64_t>() + b.size() / sizeof(std::uint64_t));
    CHECK(ctx->validation_messages() == 0);
    return results;
  };
  std::uint64_t side = 0, serial = 0;
  const std::vector<std::uint64_t> a = run(false, &side), b = run(true, &serial);
  CHECK(side == 1);    // between the two rounds only
  CHECK(serial == 5);  // before every dispatch but the first
  CHECK(a == b);
}

TEST_CASE("a device buffer of undefined contents is poisoned on demand, a zeroed one never") {
  auto ctx = sva::test::vulkan_context_or_skip();
  struct PoisonOff {
    ~PoisonOff() { sva::vk::faults::set_poison_uncleared(false); }
  } off;
  sva::vk::faults::set_poison_uncleared(true);
  auto uncleared = ctx->create_uncleared_device_buffer(4096), zeroed = ctx->create_device_buffer(4096);
  std::vector<std::uint32_t> u(1024), z(1024);
  ctx->download(uncleared, u.data(), 4096);
  ctx->download(zeroed, z.data(), 4096);
  for (std::size_t i = 0; i < u.size(); i += 255) CHECK(z[i] == 0u);
  // Only a mapped buffer can be poisoned from the host (lavapipe's are; a discrete GPU's device buffers are not).
  if (uncleared.mapped())
    for (std::size_t i = 0; i < u.size(); i += 255) CHECK(u[i] == 0xa5a5a5a5u);
  CHECK(ctx->validation_messages() == 0);
}

TEST_CASE("memory types: a discrete GPU keeps device buffers out of the host's mapped window, downloads cached") {
  // An NVIDIA board's memory types (a resizable BAR: its device memory is host-visible too).
  VkPhysicalDeviceMemoryProperties m{};
  const VkMemoryPropertyFlags dl = VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT, hv = VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT,
                              hc = VK_MEMORY_PROPERTY_HOST_COHERENT_BIT, cached = VK_MEMORY_PROPERTY_HOST_CACHED_BIT;
  const VkMemoryPropertyFlags types[] = {0, dl, hv | hc, hv | hc | cached, dl | hv | hc};
  m.memoryTypeCount = 5;
  for (std::uint32_t i = 0; i < 5; ++i) m.memoryTypes[i].propertyFlags = types[i];
  using sva::vk::Memory;
  // Discrete: device buffers in memory the host cannot map, then the BAR; never host memory.
  CHECK(sva::vk::memory_types(m, 0x1f, Memory::device, true) == std::vector<std::uint32_t>{1, 4});
  // Not discrete (integrated, lavapipe): the device's host-visible memory first, mapped, no staging.
  CHECK(sva::vk::memory_types(m, 0x1f, Memory::device, false) == std::vector<std::uint32_t>{4, 1, 2, 3});
  // Mapped buffers, kernels' inputs: the device's own host-visible memory first, on either.
  CHECK(sva::vk::memory_types(m, 0x1f, Memory::mapped, true) == std::vector<std::uint32_t>{4, 2, 3});
  CHECK(sva::vk::memory_types(m, 0x1f, Memory::mapped, false) == std::vector<std::uint32_t>{4, 2, 3});
  // Downloads: host-cached memory first, on either.
  CHECK(sva::vk::memory_types(m, 0x1f, Memory::readback, true) == std::vector<std::uint32_t>{3, 2, 4});
  // Only what the buffer allows, and a clear error when nothing fits.
  CHECK(sva::vk::memory_types(m, 0x0c, Memory::readback, true) == std::vector<std::uint32_t>{3, 2});
  CHECK_THROWS_WITH(sva::vk::memory_types(m, 0x0c, Memory::device, true), Catch::Contains("no usable memory type"));
  CHECK_THROWS_WITH(sva::vk::memory_types(m, 0x03, Memory::mapped, true), Catch::Contains("no usable memory type"));
}

TEST_CASE("gpu::ensure grows a work buffer to a power of two, remaking it only when it must, each buffer counted") {
  auto ctx = sva::test::vulkan_context_or_skip();
  sva::vk::Buffer b;
  const std::uint64_t a0 = ctx->buffers_made();
  sva::gpu::ensure(*ctx, b, 100);
  CHECK(b.size() == 128);
  CHECK(ctx->buffers_made() == a0 + 1);
  // A batch's inputs grow by a few pairs an update: within the power of two, no new buffer.
  std::memset(b.data(), 0x5a, b.size());
  for (std::size_t bytes : {101u, 120u, 128u, 16u}) sva::gpu::ensure(*ctx, b, bytes);
  CHECK(b.size() == 128);
  CHECK(ctx->buffers_made() == a0 + 1);
  CHECK(b.as<std::uint8_t>()[127] == 0x5a);  // kept, not remade
  sva::gpu::ensure(*ctx, b, 129);
  CHECK(b.size() == 256);
  CHECK(ctx->buffers_made() == a0 + 2);
  // The power of two never passes one binding's range (a dispatch would refuse the buffer): the range itself.
  const std::size_t cap = std::min<std::size_t>(ctx->info().max_storage_buffer_range, ctx->info().max_allocation);
  if (cap <= (std::size_t{1} << 28)) {  // lavapipe: 2^27 bytes
    sva::vk::Buffer big;
    sva::gpu::ensure(*ctx, big, cap - 4);
    CHECK(big.size() == cap);
  }
}
