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

struct Reading {
  std::uint32_t object = 0;  // object id in the scene (ground truth; ignored by recognition)
  // Sensor pose in the robot frame: the sensor centre, the outward surface
  // normal it was aligned to (the sensor presses along -normal), and its x axis
  // (perpendicular to normal; rotation about the normal is uncontrolled).
  glm::dvec3 position{0.0};
  glm::dvec3 normal{0.0, 0.0, 1.0};
  glm::dvec3 x_axis{1.0, 0.0, 0.0};
  std::vector<float> pressure;  // SensorSpec::elements() values, kPa, row-major
  ControllerStatus status = ControllerStatus::converged;
  std::uint16_t iterations = 0;  // controller iterations used
};

}  // namespace sva
