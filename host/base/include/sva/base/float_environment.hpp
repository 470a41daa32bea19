#pragma once
// The floating-point environment sva's answers are defined in: IEEE 754 round to nearest, with subnormal numbers
// kept (not flushed to zero on output, not read as zero on input). A thread that calls sva may hold another:
//  - Embree sets flush-to-zero while it builds a tree, and oneTBB's implicit arena keeps the environment of the
//    thread that first used it, so its tasks ran flushed when Embree's build was the process's first use of oneTBB
//    (found 2026-11-30: a hypothesis's covariance entries near 1e-299 changed in their last bits);
//  - a library built with -ffast-math sets flush-to-zero for the whole process when it loads;
//  - a robot's stack may set it on purpose, for speed.
// So each of sva's public calls and each task of its worker pool runs under a StandardFloats, which sets this
// environment for its scope and gives the thread its own back after. Nothing is set where the thread already has it.
#include <cstdint>

namespace sva::util {

class StandardFloats {
 public:
  StandardFloats();
  ~StandardFloats();
  StandardFloats(const StandardFloats&) = delete;
  StandardFloats& operator=(const StandardFloats&) = delete;

 private:
  std::uint64_t saved_ = 0;
  bool changed_ = false;
};

// Whether the calling thread now computes in that environment (for tests and checks).
bool standard_floats();

}  // namespace sva::util
