// The CPU reference's merge over an observed pair's key ranges (backends/cpu/key_ranges.hpp, for_each_match)
// against the shared owner rule (sva_match_owner.h, the GPU's text): the same matches, the same owner entry for
// each, the same summed likelihood units, on a synthetic world's map with ranges that overlap (a key met twice,
// parts of one key), both orientations, and empty ranges.
#include <catch2/catch.hpp>

#include <sva/base/rng.hpp>

#include <algorithm>
#include <tuple>
#include <vector>

#include "backends/cpu/key_ranges.hpp"
#include "recognition/fixture.hpp"

using namespace sva;
using namespace sva::test;
using cpu::KeyRange;

namespace {

using Match = std::tuple<std::uint32_t, std::uint32_t, std::uint32_t, std::uint64_t>;  // entry, ra, rb, units

// The rule's matches: every entry that no earlier range holds, with sva_owned_likelihood's units.
std::vector<Match> by_rule(const PairMap& map, const std::vector<KeyRange>& ranges) {
  cpu::OwnerRule rule(map, ranges);
  std::vector<Match> out;
  const auto n = static_cast<std::uint32_t>(ranges.size());
  for (std::uint32_t j = 0; j < n; ++j)
    for (std::uint32_t e = ranges[j].begin; e < ranges[j].end; ++e) {
      const std::uint32_t ra = ranges[j].reversed ? map.entry_b[e] : map.entry_a[e];
      const std::uint32_t rb = ranges[j].reversed ? map.entry_a[e] : map.entry_b[e];
      bool earlier = false;
      for (std::uint32_t i = 0; i < j; ++i) earlier = earlier || rule.sva_find_in_item(i, ra, rb) != SVA_NO_ENTRY;
      if (!earlier) out.emplace_back(e, ra, rb, rule.sva_owned_likelihood(0, j, n, ra, rb, map.entry_weight[e]));
    }
  std::sort(out.begin(), out.end());
  return out;
}

std::vector<Match> by_merge(const PairMap& map, const std::vector<KeyRange>& ranges) {
  std::vector<Match> out;
  cpu::for_each_match(map, ranges, [&](std::uint32_t e, std::uint32_t ra, std::uint32_t rb, std::uint64_t units) {
    out.emplace_back(e, ra, rb, units);
  });
  std::sort(out.begin(), out.end());
  return out;
}

// An observed pair's ranges as a test meets them: 1 to 9 keys of the map, either orientation, a third of them only a
// part of their key's entries (still sorted, possibly empty), some met twice.
std::vector<KeyRange> random_ranges(const PairMap& map, util::Rng& rng) {
  std::vector<KeyRange> ranges;
  const int count = 1 + static_cast<int>(rng.below(9));
  for (int k = 0; k < count; ++k) {
    const std::size_t slot = rng.below(map.keys.size());
    std::uint32_t begin = map.offsets[slot], end = map.offsets[slot + 1];
    if (rng.below(3) == 0) {  // a part of the key's entries
      const std::uint32_t span = end - begin;
      const std::uint32_t from = begin + static_cast<std::uint32_t>(rng.below(span + 1));
      begin = from;
      end = from + static_cast<std::uint32_t>(rng.below(end - from + 1));
    }
    const bool reversed = rng.below(2) == 1;
    ranges.push_back({begin, end, static_cast<float>(rng.uniform(0.0, 1.0)), reversed});
    if (rng.below(4) == 0) ranges.push_back(ranges[rng.below(ranges.size())]);  // a key met twice
  }
  return ranges;
}

}  // namespace

TEST_CASE("merging a pair's key ranges finds the owner rule's matches, owners and likelihoods") {
  const World world = make_world(WorldSpec{});
  const PairMap& map = *world.map;
  REQUIRE(map.keys.size() > 10);
  util::Rng rng(3, 4);
  std::size_t matches = 0, shared = 0;
  for (int t = 0; t < 300; ++t) {
    const std::vector<KeyRange> ranges = random_ranges(map, rng);
    const std::vector<Match> rule = by_rule(map, ranges), merged = by_merge(map, ranges);
    REQUIRE(merged == rule);
    matches += rule.size();
    for (const KeyRange& r : ranges) shared += r.end - r.begin;
  }
  CHECK(matches > 1000);
  CHECK(shared > matches);  // ranges overlapped: some pairs had several holders
}

TEST_CASE("a pair's ranges cut by first reading hold its matches, each once, with the whole pair's owners and units") {
  // The CPU update cuts a pair far larger than the rest into pieces that vote on several workers
  // (cpu_vote_backend.cpp): together the pieces' merges must meet every map pair once, with the owner and the summed
  // likelihood units the whole pair's merge gives it, also where ranges are parts of keys, empty or met twice.
  const World world = make_world(WorldSpec{});
  const PairMap& map = *world.map;
  util::Rng rng(5, 9);
  std::size_t cut = 0, pieces_made = 0;
  for (int t = 0; t < 200; ++t) {
    const std::vector<KeyRange> ranges = random_ranges(map, rng);
    const std::size_t asked = 1 + rng.below(8);
    const std::vector<std::vector<KeyRange>> pieces = cpu::split_by_first_reading(map, ranges, asked);
    INFO("trial " << t << ", " << asked << " pieces asked");
    CHECK(pieces.size() <= asked);
    std::vector<Match> joined;
    std::uint64_t entries = 0;
    for (const std::vector<KeyRange>& piece : pieces) {
      REQUIRE(piece.size() == ranges.size());  // the same ranges in the same key order, each cut
      CHECK(cpu::map_entries(piece) > 0);      // no piece without entries
      for (std::size_t k = 0; k < ranges.size(); ++k) {
        CHECK(piece[k].begin >= ranges[k].begin);
        CHECK(piece[k].end <= ranges[k].end);
        CHECK(piece[k].weight == ranges[k].weight);
        CHECK(piece[k].reversed == ranges[k].reversed);
      }
      entries += cpu::map_entries(piece);
      const std::vector<Match> mine = by_merge(map, piece);
      joined.insert(joined.end(), mine.begin(), mine.end());
    }
    std::sort(joined.begin(), joined.end());
    CHECK(entries == cpu::map_entries(ranges));
    CHECK(joined == by_merge(map, ranges));
    if (pieces.size() > 1) ++cut, pieces_made += pieces.size();
  }
  CHECK(cut > 100);  // not vacuous: most pairs were cut, into several pieces each
  CHECK(pieces_made > 3 * cut);
}

TEST_CASE("cutting a pair with no entries, or into one piece, leaves it whole") {
  const World world = make_world(WorldSpec{});
  const PairMap& map = *world.map;
  CHECK(cpu::split_by_first_reading(map, {}, 4).empty());
  const std::vector<KeyRange> empty{{map.offsets[0], map.offsets[0], 1.0f, false}};
  CHECK(cpu::split_by_first_reading(map, empty, 4).empty());
  const std::vector<KeyRange> one{{map.offsets[0], map.offsets[1], 1.0f, false}};
  REQUIRE(map.offsets[1] > map.offsets[0]);
  const auto whole = cpu::split_by_first_reading(map, one, 1);
  REQUIRE(whole.size() == 1);
  CHECK(whole[0][0].begin == one[0].begin);
  CHECK(whole[0][0].end == one[0].end);
}
