#pragma once
// A pool of objects that are expensive to make (a recognition session: its backend's scratch, a belief; on Vulkan an
// open device), lent to the workers of a parallel loop one at a time: a loop over many sessions makes no more of them
// than it has workers, and each is reset by whoever borrows it.
#include <functional>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <utility>
#include <vector>

namespace sva::util {

template <class T>
class Pool {
 public:
  using Factory = std::function<std::unique_ptr<T>()>;
  explicit Pool(Factory make) : make_(std::move(make)) {}

  // A free object, or a new one when none is free.
  std::unique_ptr<T> take() {
    {
      std::lock_guard lock(mutex_);
      if (!free_.empty()) {
        std::unique_ptr<T> t = std::move(free_.back());
        free_.pop_back();
        return t;
      }
    }
    std::unique_ptr<T> t = make_();
    if (!t) throw std::logic_error("pool: the factory made nothing");
    return t;
  }
  // Returns an object taken; one whose use threw may be dropped instead (the pool makes another when asked).
  void give_back(std::unique_ptr<T> t) {
    std::lock_guard lock(mutex_);
    free_.push_back(std::move(t));
  }
  // How many objects it holds now (free ones only).
  std::size_t free() const {
    std::lock_guard lock(mutex_);
    return free_.size();
  }

 private:
  Factory make_;
  mutable std::mutex mutex_;
  std::vector<std::unique_ptr<T>> free_;
};

}  // namespace sva::util
