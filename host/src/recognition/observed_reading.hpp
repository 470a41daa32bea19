#pragma once
// A reading as the filter sees it: where it was taken (robot frame), its
// normal, normConf and soft appearance classes. Describing a raw Reading is the
// appearance model's job (Recognizer does it); the filter starts here.
#include <glm/glm.hpp>

#include <vector>

#include "appearance/appearance_model.hpp"
#include "map/pair_map.hpp"

namespace sva {

struct ObservedReading {
  glm::dvec3 position{0.0};
  glm::dvec3 normal{0.0, 0.0, 1.0};
  float norm_conf = 0.0f;
  std::vector<ClassWeight> classes;  // Eq 12: non-empty, weights sum to 1
};

// Checks an observed reading against a map (finite geometry, unit-able normal,
// classes the map knows); throws sva::Error naming `what` and the fault.
// Returns the reading with its normal normalised and its weights renormalised.
ObservedReading validated(const ObservedReading& r, const PairMap& map, const char* what);

}  // namespace sva
