#include "reading/observed_reading.hpp"

#include <sva/base/finite.hpp>
#include <sva/error.hpp>

#include <algorithm>
#include <cmath>
#include <string>

namespace sva {

namespace {

// The normal at unit length and the class weights summing to 1 (`len` and `sum` checked above 0 by the caller).
void normalise(ObservedReading& r, double len, double sum) {
  r.normal = r.normal / len;
  for (ClassWeight& c : r.classes) c.weight = static_cast<float>(c.weight / sum);
}

}  // namespace

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
  normalise(out, len, sum);
  return out;
}

ObservedReading describe_reading(const PairMap& map, const Reading& r, const std::string& what) {
  if (r.status != ControllerStatus::converged)
    throw Error(what + ": the contact controller did not converge (status " +
                std::to_string(static_cast<int>(r.status)) + "); it is not used");
  const auto& cal = map.appearance.calibration;
  if (r.pressure.size() != static_cast<std::size_t>(cal.sensor.elements()))
    throw Error(what + ": " + std::to_string(r.pressure.size()) + " pressure values, but the map's sensor has " +
                std::to_string(cal.sensor.elements()));
  if ((r.rows != 0 || r.cols != 0) && (r.rows != cal.sensor.rows || r.cols != cal.sensor.cols))
    throw Error(what + ": the pressure image is " + std::to_string(r.rows) + " x " + std::to_string(r.cols) +
                ", but the map's sensor is " + std::to_string(cal.sensor.rows) + " x " +
                std::to_string(cal.sensor.cols));
  for (float v : r.pressure)
    if (!std::isfinite(v)) throw Error(what + ": the pressure image has a non-finite value");
  ObservedReading o;
  o.position = r.position;
  o.normal = r.normal;
  if (finite(r.x_axis)) {
    o.x_axis = r.x_axis;
    o.depth_mm.reserve(r.pressure.size());
    for (float v : r.pressure)
      o.depth_mm.push_back(static_cast<float>(std::max(0.0, static_cast<double>(v)) / cal.stiffness_kpa_per_mm));
  }
  try {
    o.norm_conf = map.appearance.norm_conf(r);
    o.classes = map.appearance.classify(map.appearance.describe(r));
  } catch (const Error& e) {
    throw Error(what + ": " + e.what());
  }
  return validated(o, map, what.c_str());
}

ObservedReading to_grid(const PoseSpace& space, ObservedReading r) {
  const RigidPose to = space.workspace().inverse();
  r.position = to.apply(r.position);
  r.normal = to.rotate(r.normal);
  r.x_axis = to.rotate(r.x_axis);
  double sum = 0.0;
  for (const ClassWeight& c : r.classes) sum += c.weight;
  normalise(r, glm::length(r.normal), sum);
  return r;
}

}  // namespace sva
