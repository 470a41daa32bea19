// The contact controller of the paper's Sec 1.1, steered only by what a real
// robot measures: the array's reported image. A guarded move advances the
// sensor until the array reports contact; then every iteration fits a plane to
// the contact points (the depths the pressures say), turns the sensor onto it,
// re-centres on the contact and takes a PD pressing step towards the target
// mean pressure, until all three settle. Rotation about the normal is never
// changed here (the caller randomises it). The rays only compute the skin's
// physics (tactile_sensor.cpp); the truth they know is reported beside the
// reading, never used to steer.
#include <sva/sim/tactile_sensor.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

#include <sva/base/portable_math.hpp>
#include <sva/base/rng.hpp>
#include <sva/base/so3.hpp>

namespace sva::sim {

namespace {

// Rodrigues' rotation of v by angle a about the unit axis k.
double angle_between(const glm::dvec3& a, const glm::dvec3& b) {
  return pmath::atan2(glm::length(glm::cross(a, b)), glm::dot(a, b));
}

// Re-orthonormalise so that rounding cannot accumulate over iterations.
void orthonormalise(SensorPose& p) {
  p.normal = glm::normalize(p.normal);
  p.x_axis = glm::normalize(p.x_axis - glm::dot(p.x_axis, p.normal) * p.normal);
}

// Every frame the array reads gets its own noise.
class Frames {
 public:
  explicit Frames(std::uint64_t seed) : seed_(seed) {}
  std::uint64_t next() { return util::splitmix64(seed_ + ++count_); }

 private:
  std::uint64_t seed_;
  std::uint64_t count_ = 0;
};

// The guarded move: advance along -normal one step per frame until the array
// reports an element above the contact threshold; false (no contact) after
// cs.max_approach_mm of travel. While the rays say the skin still touches
// nothing, the frame is the array's reading of nothing (offsets and noise), so
// no rays are cast for it: the same frames, computed faster.
bool guarded_move(const TactileSensor& sensor, SensorPose& pose, const ControllerSettings& cs, Frames& frames,
                  TactileImage& img) {
  img = sensor.touch(pose, frames.next());
  double untouched_for = img.clearance_mm;
  double travelled = 0;
  while (img.contacts == 0) {
    if (travelled + cs.approach_step_mm > cs.max_approach_mm + 1e-9) return false;
    pose.position -= cs.approach_step_mm * pose.normal;
    travelled += cs.approach_step_mm;
    untouched_for -= cs.approach_step_mm;
    if (untouched_for > 0) {
      img = sensor.untouched(frames.next());
    } else {
      img = sensor.touch(pose, frames.next());
      untouched_for = img.clearance_mm;
    }
  }
  return true;
}

// One controller iteration on an image with contact: true when the pressure,
// the fitted tilt and the centring are all within tolerance (the pose is then
// left as it is); otherwise turn (and re-centre), then the PD pressing step
// along the new normal, both from the same image. (Measured: alternating them
// in separate iterations converges less often on concave and textured surfaces.)
bool control_step(const TactileSensor& sensor, const TactileImage& img, const ControllerSettings& cs, SensorPose& pose,
                  double& prev_error) {
  const SkinModel& skin = sensor.skin();
  const double pitch = sensor.sensor().pitch_mm, target = skin.target_pressure_kpa;
  const glm::dvec3 y = glm::cross(pose.normal, pose.x_axis);
  const glm::dvec3 f = fit_contact_plane(img.pressure, sensor.sensor(), skin);
  const glm::dvec3 surface = glm::normalize(f.x * pose.x_axis + f.y * y + f.z * pose.normal);
  const double error = target - img.mean_contact_kpa;
  const double turn = angle_between(pose.normal, surface);
  const double offset = glm::length(img.contact_centroid);
  const bool pressure_ok = std::abs(error) <= cs.pressure_tolerance * target;
  const bool normal_ok = !cs.reorient || turn <= cs.normal_tolerance_deg * M_PI / 180.0;
  const bool centre_ok = !cs.recenter || offset <= 0.5 * pitch;
  if (pressure_ok && normal_ok && centre_ok) return true;

  const double d_error = std::isnan(prev_error) ? 0.0 : error - prev_error;
  const double step =
      std::clamp((cs.kp * error + cs.kd * d_error) / skin.stiffness_kpa_per_mm, -cs.max_step_mm, cs.max_step_mm);
  prev_error = error;
  const glm::dvec3 contact = pose.position + img.contact_centroid.x * pose.x_axis + img.contact_centroid.y * y;
  const bool turned = cs.reorient && turn > 0.25 * cs.normal_tolerance_deg * M_PI / 180.0;
  if (turned) {
    // Turn about the contact point: the contact stays where it is while the
    // sensor rolls onto the fitted plane.
    glm::dvec3 axis = glm::cross(pose.normal, surface);
    const double len = glm::length(axis);
    if (len > 1e-12) {
      axis /= len;
      const double a = std::min(cs.turn_gain * turn, cs.max_turn_deg * M_PI / 180.0);
      pose.position = contact + so3::rotate(pose.position - contact, a, axis);
      pose.normal = so3::rotate(pose.normal, a, axis);
      pose.x_axis = so3::rotate(pose.x_axis, a, axis);
      orthonormalise(pose);
    }
  }
  // Re-centre on the contact only once the turn is done, or when the contact
  // has drifted by more than a pitch: re-centring in every turning iteration
  // lets a biased fit (a fluted or knurled surface bears more on one rim) roll
  // the sensor around a body of revolution for ever. (Measured on paper3d's
  // glass: 62% converge re-centring every iteration, 96% like this.)
  if (cs.recenter && offset > 0.25 * pitch && (!turned || offset > pitch)) pose.position = contact;
  pose.position -= step * pose.normal;
  return false;
}

}  // namespace

// The surface under the array as the robot sees it: the least-squares plane
// through the contact points of Algorithm 1, each element in contact at its
// centre and at the depth its pressure gives through the nominal calibration
// (p / stiffness; the robot does not know its elements' gains). Returns the
// plane's outward normal in the sensor frame (x, y, normal). The slopes are
// ridge-regularised by one element's lever (pitch^2): a line or point contact
// does not constrain the tilt across it, and there the sensor is not turned.
glm::dvec3 fit_contact_plane(const std::vector<float>& pressure, const SensorSpec& s, const SkinModel& skin) {
  struct Point {
    double x, y, d;
  };
  std::vector<Point> pts;
  glm::dvec3 mean(0.0);
  for (int i = 0; i < s.rows; ++i)
    for (int j = 0; j < s.cols; ++j) {
      const double p = pressure[static_cast<std::size_t>(i * s.cols + j)];
      if (p <= skin.contact_threshold_kpa) continue;
      Point q{(j - 0.5 * (s.cols - 1)) * s.pitch_mm, (i - 0.5 * (s.rows - 1)) * s.pitch_mm,
              p / skin.stiffness_kpa_per_mm};
      pts.push_back(q);
      mean += glm::dvec3(q.x, q.y, q.d);
    }
  if (pts.size() < 2) return {0.0, 0.0, 1.0};
  mean /= static_cast<double>(pts.size());
  const double ridge = s.pitch_mm * s.pitch_mm;
  double sxx = ridge, syy = ridge, sxy = 0, sxd = 0, syd = 0;
  for (const Point& q : pts) {
    const double x = q.x - mean.x, y = q.y - mean.y, d = q.d - mean.z;
    sxx += x * x, syy += y * y, sxy += x * y, sxd += x * d, syd += y * d;
  }
  const double det = sxx * syy - sxy * sxy;  // > 0: the ridge keeps it positive definite
  const double a = (syy * sxd - sxy * syd) / det, b = (sxx * syd - sxy * sxd) / det;
  // Depth grows where the surface stands higher, so the surface faces away from that side.
  return glm::normalize(glm::dvec3(-a, -b, 1.0));
}

Contact press(const TactileSensor& sensor, SensorPose pose, const ControllerSettings& cs, std::uint64_t noise_seed) {
  orthonormalise(pose);
  Frames frames(noise_seed);
  Contact out;
  Reading& r = out.reading;
  r.status = ControllerStatus::no_contact;
  TactileImage img;
  int it = 0;
  if (guarded_move(sensor, pose, cs, frames, img)) {
    r.status = ControllerStatus::not_converged;
    double prev_error = std::numeric_limits<double>::quiet_NaN();
    for (it = 1; it <= cs.max_iterations; ++it) {
      if (it > 1) img = sensor.touch(pose, frames.next());
      if (img.contacts == 0) {
        // Contact lost (a turn or re-centre left an edge): another guarded move.
        prev_error = std::numeric_limits<double>::quiet_NaN();
        if (!guarded_move(sensor, pose, cs, frames, img)) break;
      }
      if (control_step(sensor, img, cs, pose, prev_error)) {
        r.status = ControllerStatus::converged;
        break;
      }
    }
  }
  r.position = pose.position;
  r.normal = pose.normal;
  r.x_axis = pose.x_axis;
  r.pressure = std::move(img.pressure);
  r.iterations = static_cast<std::uint16_t>(std::min(it, cs.max_iterations));
  out.surface_normal = img.surface_normal;
  return out;
}

}  // namespace sva::sim
