#pragma once
// A tactile reading: the pressure image and the sensor pose when it was taken.
// Simulated and real sensor readings are the same type.
#include <glm/glm.hpp>

#include <cstdint>
#include <vector>

namespace sva {

// Geometry of the tactile array. Elements are square; the image is row-major
// with rows along the sensor y axis and columns along the sensor x axis,
// centred on the sensor origin.
struct SensorSpec {
  int rows = 6;
  int cols = 6;
  double pitch_mm = 2.0;
  int elements() const { return rows * cols; }
};

enum class ControllerStatus : std::uint8_t {
  converged = 0,      // the contact controller met its pressure and normal tolerances
  not_converged = 1,  // it ran out of iterations; flagged, never silently used
  no_contact = 2,     // the sensor never touched the surface
};

// "converged", "not_converged", "no_contact": the names used in CSV and JSON files.
inline const char* to_string(ControllerStatus s) {
  switch (s) {
    case ControllerStatus::converged:
      return "converged";
    case ControllerStatus::not_converged:
      return "not_converged";
    case ControllerStatus::no_contact:
      return "no_contact";
  }
  return "unknown";
}

// What a sensor gives: no ground truth (a dataset's Sample holds the touched object and the true poses).
struct Reading {
  // Sensor pose in the robot frame: the sensor centre, the outward surface
  // normal it was aligned to (the sensor presses along -normal), and its x axis
  // (perpendicular to normal; rotation about the normal is uncontrolled).
  glm::dvec3 position{0.0};
  glm::dvec3 normal{0.0, 0.0, 1.0};
  glm::dvec3 x_axis{1.0, 0.0, 0.0};
  std::vector<float> pressure;  // SensorSpec::elements() values, kPa, row-major
  // The image's shape when its source gave one (a 2-D array, a dataset's sensor); 0 x 0: not given. A given shape
  // must be the map's sensor's: a 4 x 9 image has a 6 x 6 sensor's 36 values but is another sensor's image.
  int rows = 0;
  int cols = 0;
  ControllerStatus status = ControllerStatus::converged;
  std::uint16_t iterations = 0;  // controller iterations used
  // When the contact settled, in seconds on the clock of the frames it came from (a real sensor: the host's
  // monotonic clock; a recording: its timeline). 0: unknown (simulated datasets). Recognition does not read it;
  // it travels with the reading into saved sessions and outputs so that a robot can match estimates to motion.
  double time_s = 0.0;
};

}  // namespace sva
