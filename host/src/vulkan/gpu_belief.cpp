#include "vulkan/gpu_belief.hpp"

#include <sva/error.hpp>

#include <algorithm>
#include <bit>
#include <cassert>
#include <cstring>
#include <string>

#include "recognition/belief_math.hpp"
#include "vulkan/gpu_layout.hpp"

namespace sva {

namespace {

using gpu::ensure;
using gpu::hi;
using gpu::lo;
using gpu::push_bytes;

// The most slots a table may have (its index is a 32-bit uint in the shaders).
constexpr std::uint64_t kMaxSlots = std::uint64_t{1} << 31;

}  // namespace

std::uint64_t slot_invocations(std::uint64_t slots) {
  return (slots + SVA_SLOTS_PER_INVOCATION - 1) / SVA_SLOTS_PER_INVOCATION;
}

GpuBelief::GpuBelief(GpuBeliefKernels& kernels, double eps) : k_(&kernels), eps_units_(belief_math::eps_units(eps)) {
  reset();
}

void GpuBelief::allocate(vk::Buffer& b, std::uint32_t capacity) const {
  // The device's own memory: only kernels touch a belief (zeroed: keys, then offsets).
  b = k_->ctx->create_device_buffer(std::size_t{capacity} * 2 * sizeof(std::uint64_t));
  k_->ctx->run({}, nullptr, {{&b, 0xffffffffu, 0, std::size_t{capacity} * sizeof(std::uint64_t)}});
}

void GpuBelief::reset() {
  capacity_ = static_cast<std::uint32_t>(std::bit_ceil(std::max<std::size_t>(k_->initial_slots, 64)));
  allocate(table_, capacity_);
  count_ = 0;
  pairs_ = 0;
  summary_cache_.reset();
}

void GpuBelief::record(std::uint64_t inserted, std::size_t folded) {
  count_ += inserted;
  pairs_ += folded;
  summary_cache_.reset();
}

void GpuBelief::grow(std::uint64_t slots) {
  std::uint64_t cap = std::bit_ceil(std::max<std::uint64_t>(slots, 2 * std::uint64_t{capacity_}));
  vk::Buffer status = k_->ctx->create_buffer(sizeof(std::uint32_t));
  for (;;) {
    if (cap > kMaxSlots)
      throw Error("GPU belief table would need more than 2^31 slots (" + std::to_string(count_) + " touched bins)");
    vk::Buffer next;
    allocate(next, static_cast<std::uint32_t>(cap));
    *status.as<std::uint32_t>() = 0;
    gpu::SvaRehashParams p{lo(table_.device_address()), hi(table_.device_address()), capacity_,
                           lo(next.device_address()),   hi(next.device_address()),   static_cast<std::uint32_t>(cap)};
    const vk::Grid g = k_->ctx->grid(slot_invocations(capacity_));
    vk::Dispatch d{k_->rehash, {&status}, push_bytes(p), g.x};
    d.groups_y = g.y;
    std::vector<double> ms;
    k_->ctx->run({d}, &ms);
    for (double m : ms) k_->kernel_ms += m;
    if (*status.as<std::uint32_t>() == 0) {
      table_ = std::move(next);
      capacity_ = static_cast<std::uint32_t>(cap);
      return;
    }
    cap *= 2;  // a probe run too long even at this load: spread further
  }
}

void GpuBelief::reduce() const {
  const std::uint32_t objects = k_->space->objects();
  const std::size_t words = SVA_SUMMARY_OBJECTS + 4 * std::size_t{objects} + SVA_BELIEF_BUCKETS;
  ensure(*k_->ctx, summary_, words * sizeof(std::uint64_t));
  auto* w = summary_.as<std::uint64_t>();
  std::fill(w, w + words, std::uint64_t{0});
  std::uint64_t* best_key = w + SVA_SUMMARY_OBJECTS + 3 * objects;
  std::fill(best_key, best_key + objects, ~std::uint64_t{0});
  ensure(*k_->ctx, candidates_, 2 * sizeof(std::uint64_t));
  gpu::SvaReduceParams p{};
  p.table_lo = lo(table_.device_address());
  p.table_hi = hi(table_.device_address());
  p.capacity = capacity_;
  p.objects = objects;
  p.mass_bits = belief_math::mass_bits(k_->space->bins_per_object());
  p.object_shift = k_->bins.object_shift();
  const vk::Grid g = k_->ctx->grid(slot_invocations(capacity_));
  std::vector<vk::Dispatch> ds;
  for (std::uint32_t pass : {SVA_REDUCE_MAX, SVA_REDUCE_MASS}) {
    p.pass = pass;
    vk::Dispatch d{k_->reduce, {&summary_, &candidates_}, push_bytes(p), g.x};
    d.groups_y = g.y;
    ds.push_back(std::move(d));
  }
  std::vector<double> ms;
  k_->ctx->run(ds, &ms);
  for (double m : ms) k_->kernel_ms += m;

  BeliefSummary s;
  s.max_offset = w[SVA_SUMMARY_MAX];
  const std::uint64_t* o = w + SVA_SUMMARY_OBJECTS;
  s.touched.assign(o, o + objects);
  s.touched_mass.assign(o + objects, o + 2 * objects);
  s.best_offset.assign(o + 2 * objects, o + 3 * objects);
  s.best_key.assign(objects, 0);
  for (std::uint32_t i = 0; i < objects; ++i)
    if (s.touched[i] > 0) s.best_key[i] = k_->bins.key(best_key[i]);
  histogram_.assign(o + 4 * objects, o + 4 * objects + SVA_BELIEF_BUCKETS);
  summary_cache_ = std::move(s);
}

BeliefSummary GpuBelief::summarise() const {
  if (!summary_cache_) reduce();
  return *summary_cache_;
}

std::vector<BinOffset> GpuBelief::best_bins(std::size_t k) const {
  k = std::min(k, count_);
  if (k == 0) return {};
  if (!summary_cache_) reduce();
  if (k == 1) {
    // The best bin overall is the best of the objects' best bins (largest
    // offset, then smaller key): the reductions already hold it.
    const BeliefSummary& s = *summary_cache_;
    BinOffset best;
    bool found = false;
    for (std::size_t o = 0; o < s.touched.size(); ++o) {
      if (s.touched[o] == 0) continue;
      const BinOffset c{s.best_key[o], s.best_offset[o]};
      if (!found || c.offset > best.offset || (c.offset == best.offset && c.key < best.key)) best = c;
      found = true;
    }
    return {best};
  }
  // The smallest bucket bound that holds at least k bins: those bins contain the top k.
  std::uint32_t bucket = 0;
  std::uint64_t n = 0;
  for (; bucket < SVA_BELIEF_BUCKETS; ++bucket)
    if ((n += histogram_[bucket]) >= k) break;
  assert(bucket < SVA_BELIEF_BUCKETS);
  const auto best_first = [](const BinOffset& a, const BinOffset& b) {
    return a.offset != b.offset ? a.offset > b.offset : a.key < b.key;
  };
  if (n * 2 * sizeof(std::uint64_t) > k_->ctx->info().max_storage_buffer_range) {
    // So many bins tie near the maximum that their list would not fit one
    // binding: sort the whole table on the host instead (same answer).
    std::vector<BinOffset> all = table();
    std::partial_sort(all.begin(), all.begin() + static_cast<std::ptrdiff_t>(k), all.end(), best_first);
    all.resize(k);
    return all;
  }
  ensure(*k_->ctx, candidates_, n * 2 * sizeof(std::uint64_t));
  summary_.as<std::uint64_t>()[SVA_SUMMARY_CANDIDATES] = 0;
  gpu::SvaReduceParams p{};
  p.table_lo = lo(table_.device_address());
  p.table_hi = hi(table_.device_address());
  p.capacity = capacity_;
  p.pass = SVA_REDUCE_SELECT;
  p.objects = k_->space->objects();
  p.mass_bits = belief_math::mass_bits(k_->space->bins_per_object());
  p.object_shift = k_->bins.object_shift();
  p.select_bucket = bucket;
  p.select_capacity = static_cast<std::uint32_t>(n);
  const vk::Grid g = k_->ctx->grid(slot_invocations(capacity_));
  vk::Dispatch d{k_->reduce, {&summary_, &candidates_}, push_bytes(p), g.x};
  d.groups_y = g.y;
  std::vector<double> ms;
  k_->ctx->run({d}, &ms);
  for (double m : ms) k_->kernel_ms += m;
  if (summary_.as<std::uint64_t>()[SVA_SUMMARY_CANDIDATES] != n)
    throw std::logic_error("GPU belief: top-k selection found a different number of bins than its histogram");
  const auto* c = candidates_.as<std::uint64_t>();
  std::vector<BinOffset> out(n);
  for (std::size_t i = 0; i < n; ++i) out[i] = {k_->bins.key(c[2 * i]), c[2 * i + 1]};
  std::partial_sort(out.begin(), out.begin() + static_cast<std::ptrdiff_t>(k), out.end(), best_first);
  out.resize(k);
  return out;
}

std::vector<std::uint64_t> GpuBelief::offsets(std::span<const std::uint64_t> keys) const {
  if (keys.empty()) return {};
  ensure(*k_->ctx, queries_, keys.size() * sizeof(std::uint64_t));
  auto* q = queries_.as<std::uint64_t>();
  for (std::size_t i = 0; i < keys.size(); ++i) q[i] = k_->bins.linear(keys[i]);
  gpu::SvaLookupParams p{lo(table_.device_address()), hi(table_.device_address()), capacity_,
                         static_cast<std::uint32_t>(keys.size())};
  const vk::Grid g = k_->ctx->grid(keys.size());
  vk::Dispatch d{k_->lookup, {&queries_}, push_bytes(p), g.x};
  d.groups_y = g.y;
  std::vector<double> ms;
  k_->ctx->run({d}, &ms);
  for (double m : ms) k_->kernel_ms += m;
  return std::vector<std::uint64_t>(q, q + keys.size());
}

std::vector<BinOffset> GpuBelief::table() const {
  std::vector<std::uint64_t> words(std::size_t{capacity_} * 2);
  k_->ctx->download(table_, words.data(), words.size() * sizeof(std::uint64_t));
  const std::uint64_t* keys = words.data();
  const std::uint64_t* offsets = keys + capacity_;
  std::vector<BinOffset> out;
  out.reserve(count_);
  for (std::uint32_t i = 0; i < capacity_; ++i)
    if (keys[i] != ~std::uint64_t{0}) out.push_back({k_->bins.key(keys[i]), offsets[i]});
  std::sort(out.begin(), out.end(), [](const BinOffset& a, const BinOffset& b) { return a.key < b.key; });
  return out;
}

}  // namespace sva
