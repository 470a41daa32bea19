#pragma once
// The bounded queue between the sensor's reader thread and the consumer. The
// reader must never block on a slow consumer (USB transfers would back up and
// the device would drop frames unseen), so a full queue refuses the newest
// item and counts it; the consumer waits with a timeout.
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <optional>
#include <vector>

namespace sva::drivers {

template <class T>
class RingBuffer {
 public:
  explicit RingBuffer(std::size_t capacity) : slots_(capacity ? capacity : 1) {}

  // Producer: false (and counted as an overflow) when full.
  bool try_push(T item) {
    {
      std::lock_guard lock(mutex_);
      if (size_ == slots_.size()) {
        ++overflows_;
        return false;
      }
      slots_[(head_ + size_) % slots_.size()] = std::move(item);
      ++size_;
    }
    ready_.notify_one();
    return true;
  }
  // Producer, for rare items that must not be lost (link status): waits for
  // room unless closed.
  bool push_wait(T item) {
    std::unique_lock lock(mutex_);
    room_.wait(lock, [&] { return size_ < slots_.size() || closed_; });
    if (closed_) return false;
    slots_[(head_ + size_) % slots_.size()] = std::move(item);
    ++size_;
    lock.unlock();
    ready_.notify_one();
    return true;
  }
  // Consumer: the oldest item, or nothing after `timeout` (or once closed and empty).
  std::optional<T> pop(std::chrono::nanoseconds timeout) {
    std::unique_lock lock(mutex_);
    if (!ready_.wait_for(lock, timeout, [&] { return size_ > 0 || closed_; }) || size_ == 0) return std::nullopt;
    T item = std::move(slots_[head_]);
    head_ = (head_ + 1) % slots_.size();
    --size_;
    lock.unlock();
    room_.notify_one();
    return item;
  }
  // No more items will come: wakes every waiter.
  void close() {
    {
      std::lock_guard lock(mutex_);
      closed_ = true;
    }
    ready_.notify_all();
    room_.notify_all();
  }
  bool closed_and_empty() const {
    std::lock_guard lock(mutex_);
    return closed_ && size_ == 0;
  }
  std::uint64_t overflows() const {
    std::lock_guard lock(mutex_);
    return overflows_;
  }
  std::size_t capacity() const { return slots_.size(); }

 private:
  mutable std::mutex mutex_;
  std::condition_variable ready_, room_;
  std::vector<T> slots_;
  std::size_t head_ = 0, size_ = 0;
  std::uint64_t overflows_ = 0;
  bool closed_ = false;
};

}  // namespace sva::drivers
