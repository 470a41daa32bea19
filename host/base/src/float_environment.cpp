#include <sva/base/float_environment.hpp>

#if defined(__x86_64__) || defined(__i386__)
#include <xmmintrin.h>
#elif !defined(__aarch64__)
#include <cfenv>
#endif

namespace sva::util {

namespace {

#if defined(__x86_64__) || defined(__i386__)
// MXCSR: every exception masked, round to nearest, neither flush-to-zero (bit 15) nor denormals-are-zero (bit 6). The
// six status flags (bits 0-5) are the thread's own record and are left out of the comparison.
constexpr std::uint64_t kStandard = 0x1f80;
constexpr std::uint64_t kControl = 0xffc0;
std::uint64_t read_environment() { return _mm_getcsr(); }
void write_environment(std::uint64_t v) { _mm_setcsr(static_cast<unsigned>(v)); }
#elif defined(__aarch64__)
// FPCR: round to nearest, no flush-to-zero (FZ, FZ16), no default NaN, no traps: all zero.
constexpr std::uint64_t kStandard = 0;
constexpr std::uint64_t kControl = ~std::uint64_t{0};
std::uint64_t read_environment() {
  std::uint64_t v;
  asm volatile("mrs %0, fpcr" : "=r"(v));
  return v;
}
void write_environment(std::uint64_t v) { asm volatile("msr fpcr, %0" : : "r"(v)); }
#else
// Elsewhere: the C library's rounding mode only (such CPUs' flush-to-zero is not reachable portably).
constexpr std::uint64_t kStandard = FE_TONEAREST;
constexpr std::uint64_t kControl = ~std::uint64_t{0};
std::uint64_t read_environment() { return static_cast<std::uint64_t>(std::fegetround()); }
void write_environment(std::uint64_t v) { std::fesetround(static_cast<int>(v)); }
#endif

}  // namespace

StandardFloats::StandardFloats() : saved_(read_environment()) {
  if ((saved_ & kControl) == (kStandard & kControl)) return;
  write_environment((saved_ & ~kControl) | kStandard);
  changed_ = true;
}

StandardFloats::~StandardFloats() {
  if (changed_) write_environment(saved_);
}

bool standard_floats() { return (read_environment() & kControl) == (kStandard & kControl); }

}  // namespace sva::util
