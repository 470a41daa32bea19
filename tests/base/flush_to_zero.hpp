#pragma once
// The calling thread's flush-to-zero switched on or off (x86: FTZ and DAZ; aarch64: FZ), as Embree's builds and
// -ffast-math libraries leave a thread: the caller a test of sva's floating-point environment plays
// (sva/base/float_environment.hpp). false where this CPU's has no such switch that a test can reach.
#include <cstdint>

#if defined(__x86_64__) || defined(__i386__)
#include <xmmintrin.h>
#endif

namespace sva::test {

inline bool set_flush_to_zero(bool on) {
#if defined(__x86_64__) || defined(__i386__)
  const unsigned bits = 0x8040;
  _mm_setcsr(on ? _mm_getcsr() | bits : _mm_getcsr() & ~bits);
  return true;
#elif defined(__aarch64__)
  std::uint64_t v;
  asm volatile("mrs %0, fpcr" : "=r"(v));
  const std::uint64_t fz = std::uint64_t{1} << 24;
  v = on ? v | fz : v & ~fz;
  asm volatile("msr fpcr, %0" : : "r"(v));
  return true;
#else
  (void)on;
  return false;
#endif
}

}  // namespace sva::test
