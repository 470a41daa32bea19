#pragma once
// From a raw reading to what the filter sees: refuses readings the controller
// did not converge on, images of the wrong size or with non-finite values, then
// describes the image with the map's appearance model (descriptor, soft
// classes, normConf). Shared by the Recognizer and batch recognition.
#include <sva/reading.hpp>

#include <string>

#include "map/pair_map.hpp"
#include "recognition/observed_reading.hpp"

namespace sva {

// Throws sva::Error starting with `what` (e.g. "reading 3") on bad input.
ObservedReading describe_reading(const PairMap& map, const Reading& reading, const std::string& what);

}  // namespace sva
