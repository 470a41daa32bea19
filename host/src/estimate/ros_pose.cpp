// to_ros (sva/recognizer.hpp), beside the report stage that makes the public Estimate: a hypothesis in
// geometry_msgs/PoseWithCovariance's units, the mapping docs/api.md documents ("Mapping an Estimate onto
// vision_msgs/Detection3D").
#include <sva/recognizer.hpp>

#include <glm/gtc/quaternion.hpp>

namespace sva {

RosPose to_ros(const PoseHypothesis& h) {
  constexpr double kMetresPerMm = 1e-3;
  RosPose out;
  for (int k = 0; k < 3; ++k) out.position[static_cast<std::size_t>(k)] = h.pose.T[k] * kMetresPerMm;
  glm::dquat q = glm::normalize(glm::quat_cast(h.pose.R));
  if (q.w < 0.0) q = -q;  // q and -q are the same rotation: one sign, so that equal poses give equal messages
  out.orientation = {q.x, q.y, q.z, q.w};
  // Rows and columns 0-2 are millimetres: a variance scales by the square, a translation-rotation term once.
  for (std::size_t r = 0; r < 6; ++r)
    for (std::size_t c = 0; c < 6; ++c)
      out.covariance[r * 6 + c] = h.covariance[r * 6 + c] * (r < 3 ? kMetresPerMm : 1.0) * (c < 3 ? kMetresPerMm : 1.0);
  return out;
}

}  // namespace sva
