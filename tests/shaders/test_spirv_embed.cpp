// The embedded kernels (shaders/tools/spirv_embed.cpp): every floating-point
// operation of every kernel carries NoContraction, so that no driver fuses a
// multiply and an add anywhere in the shared vote math (docs/vulkan-backend.md,
// "The agreement contract"), and the modules are still well formed.
#include <catch2/catch.hpp>

#include <cstdint>
#include <set>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "spv/belief_fold.h"
#include "spv/belief_lookup.h"
#include "spv/belief_reduce.h"
#include "spv/belief_rehash.h"
#include "spv/expand_pair_keys.h"
#include "spv/match_votes.h"
#include "spv/match_votes_portable.h"
#include "spv/scan_matches.h"
#include "spv/vote_math_stages.h"

namespace {

struct Census {
  std::size_t float_ops = 0, undecorated = 0;
  bool well_formed = true;
};

// Counts the float arithmetic results (OpFNegate .. OpDot) and those without an OpDecorate NoContraction.
Census census(std::span<const std::uint32_t> words) {
  Census c;
  std::set<std::uint32_t> decorated;
  std::vector<std::uint32_t> results;
  if (words.size() < 5 || words[0] != 0x07230203u) return {0, 0, false};
  for (std::size_t i = 5; i < words.size();) {
    const std::uint32_t op = words[i] & 0xffffu, count = words[i] >> 16;
    if (count == 0 || i + count > words.size()) return {0, 0, false};
    if (op == 71 && count >= 3 && words[i + 2] == 42) decorated.insert(words[i + 1]);
    const bool arithmetic = op == 127 || op == 129 || op == 131 || op == 133 || op == 136 || (op >= 140 && op <= 148);
    if (arithmetic && count >= 3) results.push_back(words[i + 2]);
    i += count;
  }
  c.float_ops = results.size();
  for (std::uint32_t id : results) c.undecorated += decorated.count(id) == 0;
  return c;
}

}  // namespace

TEST_CASE("every float operation of every embedded kernel is NoContraction") {
  const std::vector<std::pair<std::string, std::span<const std::uint32_t>>> kernels = {
      {"belief_fold", sva_spv_belief_fold},
      {"belief_lookup", sva_spv_belief_lookup},
      {"belief_reduce", sva_spv_belief_reduce},
      {"belief_rehash", sva_spv_belief_rehash},
      {"expand_pair_keys", sva_spv_expand_pair_keys},
      {"match_votes", sva_spv_match_votes},
      {"match_votes_portable", sva_spv_match_votes_portable},
      {"scan_matches", sva_spv_scan_matches},
      {"vote_math_stages (a test kernel)", sva_spv_vote_math_stages},
  };
  std::size_t total = 0;
  for (const auto& [name, words] : kernels) {
    INFO(name);
    const Census c = census(words);
    CHECK(c.well_formed);
    CHECK(c.undecorated == 0);
    total += c.float_ops;
  }
  CHECK(census(sva_spv_match_votes).float_ops > 100);  // the vote math is there to decorate
  CHECK(total > 300);
}
