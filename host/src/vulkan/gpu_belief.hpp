#pragma once
// A session's belief in device memory: the Vulkan backend's BeliefState. The
// offsets live in an open-addressing table reached by device address (it may
// outgrow one binding's range); the fold writes it (belief_fold.comp, run by
// the backend), and the estimate's reductions, top-k selection and lookups
// run on the device (belief_reduce.comp, belief_lookup.comp). Only the
// reductions' few integers come back to the host, which finishes the estimate
// with the same code as the CPU reference.
#include <cstdint>
#include <optional>
#include <vector>

#include "recognition/belief.hpp"
#include "vulkan/context.hpp"
#include "vulkan/linear_bins.hpp"

namespace sva {

// Invocations of a kernel that visits `slots` table slots, SVA_SLOTS_PER_INVOCATION each.
std::uint64_t slot_invocations(std::uint64_t slots);

// The pipelines and constants every GpuBelief of one backend shares.
struct GpuBeliefKernels {
  vk::Context* ctx = nullptr;
  const PoseSpace* space = nullptr;
  LinearBins bins;
  const vk::Pipeline* rehash = nullptr;  // the engine's (vulkan/vulkan_engine.hpp)
  const vk::Pipeline* reduce = nullptr;
  const vk::Pipeline* lookup = nullptr;
  std::size_t initial_slots = 1 << 12;
  double kernel_ms = 0.0;  // GPU time of belief work since the backend last reset it
};

class GpuBelief final : public BeliefState {
 public:
  GpuBelief(GpuBeliefKernels& kernels, double eps);

  void reset() override;
  std::size_t pairs_folded() const override { return pairs_; }
  std::size_t touched() const override { return count_; }
  BeliefSummary summarise() const override;
  std::vector<BinOffset> best_bins(std::size_t k) const override;
  std::vector<std::uint64_t> offsets(std::span<const std::uint64_t> keys) const override;
  std::vector<BinOffset> table() const override;

  // For the backend's fold.
  std::uint64_t eps_units() const { return eps_units_; }
  std::uint32_t capacity() const { return capacity_; }
  VkDeviceAddress address() const { return table_.device_address(); }
  // Records a fold pass: `inserted` new keys; `folded` more pairs.
  void record(std::uint64_t inserted, std::size_t folded);
  // Moves the table into one of at least `slots` slots (a power of two).
  void grow(std::uint64_t slots);
  // Keeps the load at most one half for the next update.
  void keep_half_empty() {
    if (2 * count_ > capacity_) grow(2 * count_);
  }

 private:
  void allocate(vk::Buffer& b, std::uint32_t capacity) const;
  // MAX and MASS passes; the histogram of distances below the maximum comes with them.
  void reduce() const;

  GpuBeliefKernels* k_;
  std::uint64_t eps_units_;
  vk::Buffer table_;
  std::uint32_t capacity_ = 0;
  std::size_t count_ = 0, pairs_ = 0;
  mutable vk::Buffer summary_, candidates_, queries_;
  mutable std::optional<BeliefSummary> summary_cache_;
  mutable std::vector<std::uint64_t> histogram_;
};

}  // namespace sva
