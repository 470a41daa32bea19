#include "recognition/lockstep.hpp"

#include <sva/base/interrupt.hpp>

#include <algorithm>
#include <chrono>
#include <numeric>
#include <stdexcept>

namespace sva {

namespace {

class RecognizerSessions final : public LockstepSessions {
 public:
  explicit RecognizerSessions(BatchRecognizer& batch) : batch_(batch) {}
  std::size_t size() const override { return batch_.sessions(); }
  void add_readings(std::span<const std::size_t> sessions, std::span<const Reading> readings) override {
    batch_.add_readings(sessions, readings);
  }
  void reset() override {
    std::vector<std::size_t> all(batch_.sessions());
    std::iota(all.begin(), all.end(), std::size_t{0});
    batch_.reset(all);  // one submission for every session's belief on a GPU
  }

 private:
  BatchRecognizer& batch_;
};

// One update: the step-th reading of every session of the group that has one.
void update(LockstepSessions& batch, const std::vector<std::span<const Reading>>& readings, LockstepStep& step,
            const LockstepHooks& hooks) {
  std::vector<std::size_t> ids;
  std::vector<Reading> rd;
  for (std::size_t i = 0; i < readings.size(); ++i) {
    if (step.step >= readings[i].size()) continue;
    ids.push_back(i);
    rd.push_back(readings[i][step.step]);
  }
  step.sessions = ids;
  const auto start = std::chrono::steady_clock::now();
  try {
    batch.add_readings(ids, rd);
  } catch (const Interrupted&) {
    throw;
  } catch (const Error& e) {
    if (hooks.on_error) throw hooks.on_error(e, step);
    throw;
  }
  step.update_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  if (hooks.on_step) hooks.on_step(step);
  if (hooks.progress) hooks.progress->advance(ids.size());
}

}  // namespace

void run_lockstep(LockstepSessions& batch, std::size_t sessions, const LockstepHooks& hooks) {
  if (!hooks.group) throw std::logic_error("run_lockstep: no group hook");
  if (batch.size() == 0) throw std::logic_error("run_lockstep: an empty batch");
  for (std::size_t first = 0; first < sessions; first += batch.size()) {
    LockstepStep step;
    step.first = first;
    step.count = std::min(batch.size(), sessions - first);
    const std::vector<std::span<const Reading>> readings = hooks.group(first, step.count);
    if (readings.size() != step.count) throw std::logic_error("run_lockstep: the group hook gave the wrong count");
    std::size_t longest = 0;
    for (const auto& r : readings) longest = std::max(longest, r.size());
    batch.reset();
    if (hooks.on_group_start) hooks.on_group_start(first, step.count);
    for (step.step = 0; step.step < longest; ++step.step) {
      util::throw_if_interrupted();
      update(batch, readings, step, hooks);
    }
    if (hooks.on_group_end) hooks.on_group_end(first, step.count);
  }
}

void run_lockstep(BatchRecognizer& batch, std::size_t sessions, const LockstepHooks& hooks) {
  RecognizerSessions s(batch);
  run_lockstep(s, sessions, hooks);
}

}  // namespace sva
