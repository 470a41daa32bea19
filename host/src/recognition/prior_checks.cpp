#include "recognition/prior_checks.hpp"

#include <sva/base/finite.hpp>
#include <sva/base/so3.hpp>
#include <sva/error.hpp>

#include <algorithm>
#include <cmath>
#include <string>

namespace sva {

std::vector<double> prior_weights(const Prior& prior, std::size_t objects) {
  const std::vector<double>& p = prior.object_probability;
  if (p.empty()) return {};
  if (p.size() != objects)
    throw Error("prior: " + std::to_string(p.size()) + " object probabilities, but the map has " +
                std::to_string(objects) + " objects");
  double top = 0.0;
  for (std::size_t o = 0; o < p.size(); ++o) {
    if (!std::isfinite(p[o]) || p[o] < 0.0)
      throw Error("prior: object " + std::to_string(o) + " has probability " + std::to_string(p[o]) +
                  " (must be finite and >= 0)");
    top = std::max(top, p[o]);
  }
  if (!(top > 0.0)) throw Error("prior: every object probability is 0");
  std::vector<double> w(p.size());
  for (std::size_t o = 0; o < p.size(); ++o) w[o] = p[o] / top;
  return w;
}

void check_pose_priors(const Prior& prior, std::size_t objects) {
  const auto& p = prior.object_pose;
  if (p.empty()) return;
  if (p.size() != objects)
    throw Error("prior: " + std::to_string(p.size()) + " object pose priors, but the map has " +
                std::to_string(objects) + " objects (give one per object, empty where there is none)");
  for (std::size_t o = 0; o < p.size(); ++o) {
    if (!p[o]) continue;
    const std::string what = "prior: object " + std::to_string(o) + "'s pose prior: ";
    if (!finite(p[o]->position)) throw Error(what + "the position is not finite");
    if (!(p[o]->position_sigma_mm > 0.0) || !std::isfinite(p[o]->position_sigma_mm))
      throw Error(what + "position_sigma_mm = " + std::to_string(p[o]->position_sigma_mm) + " must be > 0");
    if (!p[o]->has_rotation) continue;
    // Finite, orthonormal to 1e-6 and proper.
    if (!so3::is_rotation(p[o]->rotation)) throw Error(what + "the rotation is not a rotation matrix");
    if (!(p[o]->rotation_sigma_rad > 0.0) || !std::isfinite(p[o]->rotation_sigma_rad))
      throw Error(what + "rotation_sigma_rad = " + std::to_string(p[o]->rotation_sigma_rad) + " must be > 0");
  }
}

}  // namespace sva
