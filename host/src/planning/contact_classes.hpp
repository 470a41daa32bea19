#pragma once
// The appearance classes of each training contact, as the planner predicts what a touch would feel. The map file
// does not store them, but every pair entry carries them: an entry of reading a under key (c_a, c_b, d) has weight
// w_a(c_a) w_b(c_b) w(d), so summing an entry's weight into its ends' classes and normalising gives each reading's
// soft classes back exactly (the partners' class and distance weights each sum to 1).
#include <vector>

#include "appearance/appearance_model.hpp"
#include "map/pair_map.hpp"

namespace sva::planning {

// Per row of map.readings: its soft classes (weight > 0, increasing class, summing to 1). A reading that takes
// part in no pair gets the classes of its object's nearest reading that does (a surface contact only, of a map
// trained with pair_readings: what was felt there is most like what was felt nearby), or, when the object has no
// paired reading, its object's class histogram (the appearance baseline's), or uniform classes when the map has
// none.
std::vector<std::vector<ClassWeight>> contact_classes(const PairMap& map);

// How alike two soft class lists are (both in increasing class order): their Bhattacharyya coefficient, in [0, 1].
double class_overlap(const std::vector<ClassWeight>& a, const std::vector<ClassWeight>& b);

}  // namespace sva::planning
