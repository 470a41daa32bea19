#include "recognition/describe_reading.hpp"

#include <sva/error.hpp>

#include <cmath>

namespace sva {

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
  try {
    o.norm_conf = map.appearance.norm_conf(r);
    o.classes = map.appearance.classify(map.appearance.describe(r));
  } catch (const Error& e) {
    throw Error(what + ": " + e.what());
  }
  return validated(o, map, what.c_str());
}

}  // namespace sva
