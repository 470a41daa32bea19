#pragma once
// Groups of a batch in flight on several recognizers at once (issue 52: submissions double-buffered). While one
// recognizer's update waits on the device, another prepares its group's next update on the host (pair keys, map
// ranges, the estimate's fits); the device's queue takes their submissions in turn (vk::Context). What must stay in
// the order of a single recognizer does: groups are read from the file and their results written in group order,
// and a batch that fails reports the error of its first failing group, whatever the timing.
#include <condition_variable>
#include <cstddef>
#include <exception>
#include <functional>
#include <limits>
#include <mutex>

namespace sva::batch {

class GroupTurns {
 public:
  enum Stage { kFetch = 0, kDone = 1 };
  // Thrown in a group once an earlier group has failed: its work is dropped, as one recognizer never began it.
  struct Stopped {};

  // Waits until every earlier group has passed `stage`; Stopped when an earlier group failed.
  void wait(Stage stage, std::size_t group);
  // Group `next` of `stage` passes it (call after wait()).
  void pass(Stage stage);
  // Stopped when a group before `group` has failed.
  void check(std::size_t group) const;
  // Group `group` failed with `error`; the earliest failing group's error is kept.
  void fail(std::size_t group, std::exception_ptr error);
  // The kept error, if any.
  void rethrow() const;

 private:
  mutable std::mutex mutex_;
  std::condition_variable turned_;
  std::size_t next_[2] = {0, 0};
  std::size_t failed_ = std::numeric_limits<std::size_t>::max();
  std::exception_ptr error_;
};

// Runs run_group(g, w) for groups 0..groups-1 on `workers` threads, group g on worker g % workers (so a worker keeps
// its recognizer), and rethrows the first failing group's error once all have stopped. One worker runs on the
// calling thread.
void run_groups(std::size_t groups, std::size_t workers, GroupTurns& turns,
                const std::function<void(std::size_t group, std::size_t worker)>& run_group);

}  // namespace sva::batch
