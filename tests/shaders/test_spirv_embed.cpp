// The embedded kernels (shaders/tools/spirv_embed.cpp): every floating-point
// operation of every kernel carries NoContraction, so that no driver fuses a
// multiply and an add anywhere in the shared vote math (docs/vulkan-backend.md,
// "The agreement contract"), and the modules are still well formed.
#include <catch2/catch.hpp>

#include <cstdint>
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
#include "tools/spirv_contraction.hpp"

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
    const sva::spirv::Census c = sva::spirv::census(words);
    CHECK(c.well_formed);
    CHECK(c.undecorated() == 0);
    total += c.float_results.size();
  }
  CHECK(sva::spirv::census(sva_spv_match_votes).float_results.size() > 100);  // the vote math is there to decorate
  CHECK(total > 300);
}
