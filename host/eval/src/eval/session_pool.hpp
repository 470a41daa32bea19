#pragma once
// The pool of recognition sessions the trial runners borrow from (one per worker, reset between trials).
#include <memory>
#include <mutex>
#include <stdexcept>
#include <vector>

#include "eval/trial_runner.hpp"

namespace sva::eval {

// Sessions are expensive to build (a Vulkan backend opens a device), so each
// worker borrows one from a pool and resets it between trials.
class SessionPool {
 public:
  explicit SessionPool(const SessionFactory& make) : make_(make) {}
  std::unique_ptr<Session> take() {
    {
      std::lock_guard lock(mutex_);
      if (!free_.empty()) {
        auto s = std::move(free_.back());
        free_.pop_back();
        return s;
      }
    }
    auto s = make_();
    if (!s) throw std::logic_error("eval: the session factory returned no session");
    return s;
  }
  void give_back(std::unique_ptr<Session> s) {
    std::lock_guard lock(mutex_);
    free_.push_back(std::move(s));
  }

 private:
  const SessionFactory& make_;
  std::mutex mutex_;
  std::vector<std::unique_ptr<Session>> free_;
};

}  // namespace sva::eval
