// The CPU reference's fold terms, 8 bins at a time (backends/cpu/fold_lanes.cpp), against the shared text's
// sva_fold_units_given (sva_belief_math.h, the GPU's fold): every term bit for bit, on the masses votes give and on
// the extremes (one unit, the whole total, totals near 2^63, eps at both ends, bin counts that are not whole groups).
#include <catch2/catch.hpp>

#include <sva/base/rng.hpp>

#include <vector>

#include "backends/cpu/fold_lanes.hpp"
#include "belief/belief_math.hpp"

using namespace sva;
namespace bm = sva::belief_math;

namespace {

// Folds masses through both paths; returns how many terms differ.
std::size_t mismatches(const std::vector<std::uint64_t>& mass, std::uint64_t eps_units) {
  std::uint64_t total = 0;
  for (std::uint64_t m : mass) total += m;
  const std::uint64_t floor_log = bm::sva_floor_log(total, eps_units);
  std::vector<std::uint64_t> lanes(mass.size(), ~std::uint64_t{0});
  cpu::fold_units(mass.data(), mass.size(), total, eps_units, floor_log, lanes.data());
  std::size_t wrong = 0;
  for (std::size_t i = 0; i < mass.size(); ++i)
    if (lanes[i] != bm::sva_fold_units_given(mass[i], total, eps_units, floor_log)) ++wrong;
  return wrong;
}

}  // namespace

TEST_CASE("fold terms in lanes equal sva_fold_units_given bit for bit") {
  util::Rng rng(5, 2);
  const std::vector<std::uint64_t> eps = {bm::eps_units(1e-12), bm::eps_units(1e-6), bm::eps_units(0.01),
                                          bm::eps_units(0.999)};
  std::size_t terms = 0;
  for (int t = 0; t < 300; ++t) {
    // 1 to 100 bins (none, one and three whole groups of 32, and a rest), masses from one unit to a full vote
    // (2^24) and beyond.
    std::vector<std::uint64_t> mass(1 + rng.below(100));
    const int bits = 1 + static_cast<int>(rng.below(40));
    for (std::uint64_t& m : mass) m = 1 + rng.below(std::uint64_t{1} << bits);
    for (std::uint64_t e : eps) {
      CHECK(mismatches(mass, e) == 0);
      terms += mass.size();
    }
  }
  CHECK(terms > 10000);
  // One bin holding the whole total; a total near 2^63; single units beside a huge bin.
  for (std::uint64_t e : eps) {
    CHECK(mismatches({std::uint64_t{1} << 24}, e) == 0);
    CHECK(mismatches({1}, e) == 0);
    CHECK(mismatches({(std::uint64_t{1} << 62) + 12345, (std::uint64_t{1} << 62) - 1, 1, 7}, e) == 0);
    CHECK(mismatches({1, 1, 1, 1, 1, 1, 1, 1, 1, std::uint64_t{1} << 40}, e) == 0);
    // The same extremes in whole groups of lanes, not only in the rest.
    std::vector<std::uint64_t> group;
    for (int k = 0; k < 24; ++k)
      for (std::uint64_t m :
           {(std::uint64_t{1} << 61) + 12345u, std::uint64_t{1}, std::uint64_t{7}, std::uint64_t{1} << 40})
        group.push_back(m);
    CHECK(mismatches(group, e) == 0);
  }
}
