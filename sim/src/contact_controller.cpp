// The contact controller of the paper's Sec 1.1: alternate a PD pressing step
// towards the target mean pressure with a re-orientation of the sensor normal
// to the surface normal under the contact, until both settle. Rotation about
// the normal is never changed here (the caller randomises it).
#include <sva/sim/tactile_sensor.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

#include "util/rng.hpp"

namespace sva::sim {

namespace {

// Rodrigues' rotation of v by angle a about the unit axis k.
glm::dvec3 rotate(const glm::dvec3& v, double a, const glm::dvec3& k) {
  return v * std::cos(a) + glm::cross(k, v) * std::sin(a) + k * glm::dot(k, v) * (1.0 - std::cos(a));
}

double angle_between(const glm::dvec3& a, const glm::dvec3& b) {
  return std::atan2(glm::length(glm::cross(a, b)), glm::dot(a, b));
}

// Re-orthonormalise so that rounding cannot accumulate over iterations.
void orthonormalise(SensorPose& p) {
  p.normal = glm::normalize(p.normal);
  p.x_axis = glm::normalize(p.x_axis - glm::dot(p.x_axis, p.normal) * p.normal);
}

}  // namespace

Reading press(const TactileSensor& sensor, SensorPose pose, const ControllerSettings& cs, std::uint64_t noise_seed) {
  const SkinModel& skin = sensor.skin();
  const double pitch = sensor.sensor().pitch_mm;
  const double target = skin.target_pressure_kpa;
  const double stiffness = skin.stiffness_kpa_per_mm;
  orthonormalise(pose);

  Reading out;
  out.status = ControllerStatus::no_contact;
  bool touched = false;
  double prev_error = std::numeric_limits<double>::quiet_NaN();
  TactileImage img;
  int it = 0;
  for (it = 1; it <= cs.max_iterations; ++it) {
    img = sensor.touch(pose, util::splitmix64(noise_seed + static_cast<std::uint64_t>(it)));
    if (img.contacts == 0) {
      if (!img.surface_below) {
        if (!touched) break;                            // nothing under the array: no contact
        pose.position += cs.max_step_mm * pose.normal;  // lost the surface after touching: back off and look again
        prev_error = std::numeric_limits<double>::quiet_NaN();
        continue;
      }
      // Approach: move straight to the surface (the rays give the gap), then a
      // little into it; pressing is PD-controlled from the first contact on.
      double step = std::max(img.gap_mm, 0.0) + 0.5 * skin.contact_threshold_kpa / stiffness + 0.01;
      pose.position -= step * pose.normal;
      prev_error = std::numeric_limits<double>::quiet_NaN();
      continue;
    }
    touched = true;
    const double error = target - img.mean_contact_kpa;
    const double turn = img.surface_normal != glm::dvec3(0.0) ? angle_between(pose.normal, img.surface_normal) : 0.0;
    const double offset = glm::length(img.contact_centroid);
    const bool pressure_ok = std::abs(error) <= cs.pressure_tolerance * target;
    const bool normal_ok = !cs.reorient || turn <= cs.normal_tolerance_deg * M_PI / 180.0;
    const bool centre_ok = !cs.recenter || offset <= 0.5 * pitch;
    if (pressure_ok && normal_ok && centre_ok) {
      out.status = ControllerStatus::converged;
      break;
    }
    // One iteration does both steps of Sec 1.1 from the same image: turn
    // (and re-centre), then the PD pressing step along the new normal.
    // (Measured: alternating them in separate iterations, or damping the turn,
    // converges less often on concave and textured surfaces.)
    double d_error = std::isnan(prev_error) ? 0.0 : error - prev_error;
    double step = std::clamp((cs.kp * error + cs.kd * d_error) / stiffness, -cs.max_step_mm, cs.max_step_mm);
    prev_error = error;
    const glm::dvec3 y = glm::cross(pose.normal, pose.x_axis);
    const glm::dvec3 contact = pose.position + img.contact_centroid.x * pose.x_axis + img.contact_centroid.y * y;
    if (cs.reorient && turn > 0.25 * cs.normal_tolerance_deg * M_PI / 180.0) {
      // Turn about the contact point: the contact stays where it is while the
      // sensor rolls onto the surface's tangent plane.
      double a = std::min(cs.turn_gain * turn, cs.max_turn_deg * M_PI / 180.0);
      glm::dvec3 axis = glm::cross(pose.normal, img.surface_normal);
      double len = glm::length(axis);
      if (len > 1e-12) {
        axis /= len;
        pose.position = contact + rotate(pose.position - contact, a, axis);
        pose.normal = rotate(pose.normal, a, axis);
        pose.x_axis = rotate(pose.x_axis, a, axis);
        orthonormalise(pose);
      }
    }
    if (cs.recenter && offset > 0.25 * pitch) pose.position = contact;
    pose.position -= step * pose.normal;
  }
  if (out.status != ControllerStatus::converged && touched) out.status = ControllerStatus::not_converged;
  out.position = pose.position;
  out.normal = pose.normal;
  out.x_axis = pose.x_axis;
  out.pressure = std::move(img.pressure);
  if (out.pressure.empty()) out.pressure.assign(static_cast<std::size_t>(sensor.sensor().elements()), 0.0f);
  out.iterations = static_cast<std::uint16_t>(std::min(it, cs.max_iterations));
  return out;
}

}  // namespace sva::sim
