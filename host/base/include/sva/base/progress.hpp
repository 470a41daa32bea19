#pragma once
// Progress for long work, on stderr: a single line redrawn at most a few times
// a second when stderr is a terminal, otherwise a line every 10%.
#include <atomic>
#include <chrono>
#include <cstddef>
#include <mutex>
#include <string>

namespace sva::util {

class Progress {
 public:
  Progress(std::string label, std::size_t total);
  ~Progress();
  void advance(std::size_t n = 1);  // thread-safe
  void finish();
  static void set_quiet(bool quiet);  // --quiet and tests

 private:
  void draw(std::size_t done, bool final);
  std::string label_;
  std::size_t total_;
  std::atomic<std::size_t> done_{0};
  std::chrono::steady_clock::time_point start_, last_draw_;
  int last_decile_ = -1;
  bool finished_ = false;
  bool tty_;
  std::mutex mutex_;
};

}  // namespace sva::util
