#pragma once
// The lock-step batch loop: many independent recognition sessions stepped
// together, so that step k adds the k-th reading of every session of a group
// in one backend update (one GPU submission with the Vulkan backend). It is the
// one loop behind `sva recognize` (sessions from a file), `sva eval` on the
// Vulkan backend (trials) and `sva bench` (timed trials).
//
// It lives with recognition, not with eval, because by the data flow it is
// batch recognition's driver: readings in, backend updates out. What a caller
// does with each update (record an eval step, time a checkpoint, read the
// final estimates) comes in through hooks, so the loop knows nothing of
// trials, files or reports.
#include <sva/batch_recognizer.hpp>
#include <sva/error.hpp>
#include <sva/reading.hpp>

#include <cstddef>
#include <functional>
#include <span>
#include <vector>

#include <sva/base/progress.hpp>

namespace sva {

// Sessions that step together: one call adds the next reading of each listed
// session. reset() makes every session fresh, so one batch serves every group.
class LockstepSessions {
 public:
  virtual ~LockstepSessions() = default;
  virtual std::size_t size() const = 0;
  virtual void add_readings(std::span<const std::size_t> sessions, std::span<const Reading> readings) = 0;
  virtual void reset() = 0;
};

// What one update was: group [first, first + count) of all sessions, reading
// `step` (from 0) of the batch slots in `sessions` (the group's sessions that
// still have a reading), and the update's wall time.
struct LockstepStep {
  std::size_t first = 0, count = 0;
  std::size_t step = 0;
  std::span<const std::size_t> sessions;  // batch slots; slot i is session first + i
  double update_ms = 0.0;
};

struct LockstepHooks {
  // Required: the readings of sessions [first, first + count), in order; the
  // caller keeps them alive until the next call.
  std::function<std::vector<std::span<const Reading>>(std::size_t first, std::size_t count)> group;
  // After the batch is reset for group [first, first + count), before its first update (a session's prior).
  std::function<void(std::size_t first, std::size_t count)> on_group_start;
  // After every update (estimates, timings, checkpoints).
  std::function<void(const LockstepStep&)> on_step;
  // After a group's last update, before the batch is reset for the next group.
  std::function<void(std::size_t first, std::size_t count)> on_group_end;
  // Turns a failed update into the error the user sees (naming the file,
  // trial or session); by default the error propagates as it is.
  std::function<Error(const Error&, const LockstepStep&)> on_error;
  // Advanced by the readings of every update.
  util::Progress* progress = nullptr;
};

// Steps `sessions` sessions through `batch`, batch.size() at a time. Polls
// Ctrl-C before every update (sva::Interrupted propagates untouched).
void run_lockstep(LockstepSessions& batch, std::size_t sessions, const LockstepHooks& hooks);

// The same over a BatchRecognizer (its sessions reset between groups).
void run_lockstep(BatchRecognizer& batch, std::size_t sessions, const LockstepHooks& hooks);

}  // namespace sva
