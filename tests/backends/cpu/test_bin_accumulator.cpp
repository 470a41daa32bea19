// The CPU's pose-bin table (backends/cpu/bin_accumulator.hpp): copy_positive gives the bins that for_each visits with
// a positive value, in the same order, into buffers of exactly size() + 1 entries (AddressSanitizer, in the CI's
// sanitizer stage, sees a write past them).
#include <sva/base/rng.hpp>

#include <catch2/catch.hpp>

#include <vector>

#include "backends/cpu/bin_accumulator.hpp"

TEST_CASE("copy_positive keeps the positive bins in slot order, within size() + 1 entries") {
  sva::util::Rng rng(3, 9);
  std::size_t kept_total = 0, dropped_total = 0;
  for (const int adds : {0, 1, 2, 40, 700, 5000}) {
    sva::BinAccumulator acc(8);
    for (int a = 0; a < adds; ++a) {
      const std::uint64_t pick = rng.below(4);
      acc.add(1 + rng.below(3000), pick == 0 ? 0 : pick == 1 ? -3 : static_cast<std::int64_t>(1 + rng.below(1000)));
    }
    std::vector<std::uint64_t> want_keys;
    std::vector<std::int64_t> want_values;
    acc.for_each([&](std::uint64_t k, std::int64_t v) {
      if (v <= 0) return;
      want_keys.push_back(k);
      want_values.push_back(v);
    });
    std::vector<std::uint64_t> keys(acc.size() + 1);
    std::vector<std::int64_t> values(acc.size() + 1);
    const std::size_t n = acc.copy_positive(keys.data(), values.data());
    INFO(adds << " additions");
    REQUIRE(n == want_keys.size());
    keys.resize(n);
    values.resize(n);
    CHECK(keys == want_keys);
    CHECK(values == want_values);
    kept_total += n;
    dropped_total += acc.size() - n;
  }
  CHECK(kept_total > 1000);    // not vacuous: positive bins
  CHECK(dropped_total > 500);  // and bins of zero or negative sums left out
}
