#include "backends/vulkan/faults.hpp"

#include <sva/error.hpp>

#include <atomic>
#include <cstdlib>
#include <mutex>

namespace sva::vk::faults {

namespace {

std::uint64_t env_count(const char* name) {
  const char* v = std::getenv(name);
  if (!v || !*v) return 0;
  char* end = nullptr;
  const unsigned long long n = std::strtoull(v, &end, 10);
  if (!end || *end != '\0') throw Error(std::string(name) + " expects a count, got \"" + v + "\"");
  return n;
}

// The state, first read from the environment; the hooks replace it.
struct State {
  std::atomic<std::uint64_t> budget{0};
  std::atomic<std::uint64_t> max_allocations{0};
  std::atomic<bool> poison{false};
  std::atomic<std::int64_t> submissions_before_loss{-1};  // -1: no loss pending
  std::mutex mutex;
  std::string missing;
  State() {
    budget = env_count("SVA_VK_MEMORY_BUDGET_BYTES");
    max_allocations = env_count("SVA_VK_MAX_ALLOCATIONS");
    if (const char* v = std::getenv("SVA_VK_FAULT_DEVICE_LOST_AFTER"); v && *v)
      submissions_before_loss = static_cast<std::int64_t>(env_count("SVA_VK_FAULT_DEVICE_LOST_AFTER"));
    if (const char* v = std::getenv("SVA_VK_FAULT_MISSING_FEATURE")) missing = v;
    poison = env_count("SVA_VK_POISON_UNCLEARED") != 0;
  }
};

State& state() {
  static State s;
  return s;
}

}  // namespace

std::uint64_t memory_budget() { return state().budget.load(); }
void set_memory_budget(std::uint64_t bytes) { state().budget = bytes; }

std::uint64_t max_allocations() { return state().max_allocations.load(); }
void set_max_allocations(std::uint64_t count) { state().max_allocations = count; }

bool take_device_loss() {
  std::atomic<std::int64_t>& n = state().submissions_before_loss;
  std::int64_t now = n.load();
  while (now >= 0)
    if (n.compare_exchange_weak(now, now - 1)) return now == 0;
  return false;
}
void lose_device_after(std::uint64_t submissions) {
  state().submissions_before_loss = static_cast<std::int64_t>(submissions);
}
void clear_device_loss() { state().submissions_before_loss = -1; }

std::string missing_feature() {
  State& s = state();
  std::lock_guard lock(s.mutex);
  return s.missing;
}
void set_missing_feature(const std::string& feature) {
  State& s = state();
  std::lock_guard lock(s.mutex);
  s.missing = feature;
}

bool poison_uncleared() { return state().poison.load(); }
void set_poison_uncleared(bool on) { state().poison = on; }

}  // namespace sva::vk::faults
