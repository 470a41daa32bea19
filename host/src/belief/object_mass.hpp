#pragma once
// Each object's share of a belief, from the belief's reductions alone (BeliefSummary): the filter prunes objects
// by it, the estimate's candidates read it. Untouched bins count at the baseline offset 0, so no object is ever
// given zero mass by the pairs that missed it (DESIGN 4).
#include <span>
#include <vector>

#include "belief/belief_state.hpp"
#include "votes/pose_space.hpp"

namespace sva {

// Mass of each object relative to a bin at the maximum (weight 2^mass_bits): touched bins by their weights,
// untouched bins at the baseline. `weight` (per object, largest 1; empty: flat) scales each object's bins, as a
// per-object offset of log2(weight) added to every bin of the object would.
std::vector<double> object_mass(const BeliefSummary& summary, const PoseSpace& space,
                                std::span<const double> weight = {});
// The belief's total mass in object_mass's units.
double total_mass(const BeliefSummary& summary, const PoseSpace& space, std::span<const double> object_weight = {});
// Posterior per object (untouched bins at the baseline), without a prior.
std::vector<double> object_probability(const BeliefSummary& summary, const PoseSpace& space);
// Each object's log-evidence (EvidenceLevel::object_log2_mass): log2 of its mass over poses relative to one bin at
// the maximum, untouched bins at the baseline; never -inf.
std::vector<double> object_log2_mass(const BeliefSummary& summary, const PoseSpace& space);

}  // namespace sva
