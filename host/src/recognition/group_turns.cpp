#include "recognition/group_turns.hpp"

#include <thread>
#include <vector>

namespace sva::batch {

void GroupTurns::wait(Stage stage, std::size_t group) {
  std::unique_lock lock(mutex_);
  turned_.wait(lock, [&] { return next_[stage] == group || failed_ < group; });
  if (failed_ < group) throw Stopped{};
}

void GroupTurns::pass(Stage stage) {
  {
    std::lock_guard lock(mutex_);
    ++next_[stage];
  }
  turned_.notify_all();
}

void GroupTurns::check(std::size_t group) const {
  std::lock_guard lock(mutex_);
  if (failed_ < group) throw Stopped{};
}

void GroupTurns::fail(std::size_t group, std::exception_ptr error) {
  {
    std::lock_guard lock(mutex_);
    if (group < failed_) failed_ = group, error_ = std::move(error);
  }
  turned_.notify_all();
}

void GroupTurns::rethrow() const {
  std::lock_guard lock(mutex_);
  if (error_) std::rethrow_exception(error_);
}

namespace {

void run_worker(std::size_t w, std::size_t groups, std::size_t workers, GroupTurns& turns,
                const std::function<void(std::size_t, std::size_t)>& run_group) {
  for (std::size_t g = w; g < groups; g += workers) {
    try {
      turns.check(g);
      run_group(g, w);
    } catch (const GroupTurns::Stopped&) {
      return;  // an earlier group failed: this one and the worker's later ones never run
    } catch (...) {
      turns.fail(g, std::current_exception());
      return;
    }
  }
}

}  // namespace

void run_groups(std::size_t groups, std::size_t workers, GroupTurns& turns,
                const std::function<void(std::size_t group, std::size_t worker)>& run_group) {
  if (workers <= 1) {
    run_worker(0, groups, 1, turns, run_group);
  } else {
    std::vector<std::jthread> threads;  // joined when they go, also when a later one cannot start
    for (std::size_t w = 1; w < workers; ++w)
      threads.emplace_back(run_worker, w, groups, workers, std::ref(turns), std::cref(run_group));
    run_worker(0, groups, workers, turns, run_group);
  }
  turns.rethrow();
}

}  // namespace sva::batch
