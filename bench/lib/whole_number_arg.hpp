#pragma once
// The bench programs' positional arguments (bench/speed/*.cpp): a whole number in a range, or the program ends naming
// the argument's position, its text and the range (the smoke tests read that line).
#include <cstddef>
#include <cstdio>
#include <cstdlib>

namespace sva::bench {

// Argument i as a whole number in lo..hi, `fallback` when not given; `program` names the program in the refusal.
inline std::size_t whole_number_arg(const char* program, int argc, char** argv, int i, std::size_t fallback,
                                    std::size_t lo, std::size_t hi) {
  if (argc <= i) return fallback;
  char* end = nullptr;
  const unsigned long long v = std::strtoull(argv[i], &end, 10);
  if (argv[i][0] == '-' || !end || *end != '\0' || v < lo || v > hi) {
    std::fprintf(stderr, "%s: argument %d (\"%s\") is not a whole number in %zu..%zu\n", program, i, argv[i], lo, hi);
    std::exit(2);
  }
  return static_cast<std::size_t>(v);
}

}  // namespace sva::bench
