#include "recognition/observed_reading.hpp"

#include <sva/base/finite.hpp>
#include <sva/error.hpp>

#include <cmath>
#include <string>

namespace sva {

ObservedReading validated(const ObservedReading& r, const PairMap& map, const char* what) {
  const std::string w = what;
  if (!finite(r.position)) throw Error(w + ": the sensor position is not finite");
  // The vote math runs in float (24-bit mantissa): beyond 1e7 mm its steps exceed a millimetre.
  if (std::fabs(r.position.x) > 1e7 || std::fabs(r.position.y) > 1e7 || std::fabs(r.position.z) > 1e7)
    throw Error(w + ": the sensor position is more than 10 km from the origin (units are mm)");
  if (!finite(r.normal)) throw Error(w + ": the sensor normal is not finite");
  const double len = glm::length(r.normal);
  if (!(len > 1e-9)) throw Error(w + ": the sensor normal has zero length");
  if (!std::isfinite(r.norm_conf) || r.norm_conf < 0.0f || r.norm_conf > 1.0f + 1e-4f)
    throw Error(w + ": normConf " + std::to_string(r.norm_conf) + " is not in [0, 1]");
  if (r.classes.empty()) throw Error(w + ": no appearance class (empty or unreadable pressure image?)");
  ObservedReading out = r;
  out.normal = r.normal / len;
  out.norm_conf = std::fmin(r.norm_conf, 1.0f);
  double sum = 0.0;
  for (const ClassWeight& c : r.classes) {
    if (c.cls >= map.key_space.n_classes)
      throw Error(w + ": appearance class " + std::to_string(c.cls) + " is not one of the map's " +
                  std::to_string(map.key_space.n_classes));
    if (!std::isfinite(c.weight) || c.weight < 0.0f)
      throw Error(w + ": appearance class weight " + std::to_string(c.weight) + " is not a finite non-negative number");
    sum += c.weight;
  }
  if (!(sum > 0.0)) throw Error(w + ": all appearance class weights are zero");
  for (ClassWeight& c : out.classes) c.weight = static_cast<float>(c.weight / sum);
  return out;
}

}  // namespace sva
