#include "votes/pose_space.hpp"

#include <sva/base/so3.hpp>
#include <sva/error.hpp>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

namespace sva {

namespace {
constexpr std::uint64_t mask(int bits) { return (std::uint64_t{1} << bits) - 1; }

// The workspace frame must be rigid (a rotation, finite): anything else would shear the readings' geometry. A
// planar space keeps its plane: the frame may only turn about z.
void check_workspace(const PoseSpaceSpec& spec, const std::string& where) {
  const RigidPose& w = spec.workspace;
  for (int k = 0; k < 3; ++k) {
    if (!std::isfinite(w.T[k])) throw Error(where + "workspace centre is not finite");
    for (int j = 0; j < 3; ++j)
      if (!std::isfinite(w.R[k][j])) throw Error(where + "workspace rotation is not finite");
  }
  const glm::dmat3 g = glm::transpose(w.R) * w.R;
  double off = 0.0;
  for (int k = 0; k < 3; ++k)
    for (int j = 0; j < 3; ++j) off = std::max(off, std::fabs(g[k][j] - (k == j ? 1.0 : 0.0)));
  if (off > 1e-6 || glm::determinant(w.R) < 0.0)
    throw Error(where + "workspace rotation is not a rotation matrix (orthonormal, determinant +1)");
  if (spec.kind == PoseSpaceSpec::Kind::planar && std::fabs(w.R[2][2] - 1.0) > 1e-9)
    throw Error(where + "a planar space's workspace may only rotate about z (the plane's normal)");
}
}  // namespace

PoseSpace::PoseSpace(const PoseSpaceSpec& spec, std::uint32_t objects) : spec_(spec), objects_(objects) {
  const std::string where = "pose space: ";
  if (objects == 0) throw Error(where + "the map has no objects");
  if (objects > SVA_MAX_OBJECTS)
    throw Error(where + std::to_string(objects) + " objects do not fit the bin key (at most " +
                std::to_string(SVA_MAX_OBJECTS) + ")");
  if (spec.translation_bins < 1 || spec.translation_bins > SVA_MAX_TRANSLATION_BINS)
    throw Error(where + "translation_bins = " + std::to_string(spec.translation_bins) + " must be in [1, " +
                std::to_string(SVA_MAX_TRANSLATION_BINS) + "]");
  if (spec.rotation_bins < 1 || spec.rotation_bins > SVA_MAX_ROTATION_BINS)
    throw Error(where + "rotation_bins = " + std::to_string(spec.rotation_bins) + " must be in [1, " +
                std::to_string(SVA_MAX_ROTATION_BINS) + "]");
  if (!std::isfinite(spec.translation_min_mm) || !std::isfinite(spec.translation_max_mm) ||
      !(spec.translation_max_mm > spec.translation_min_mm))
    throw Error(where + "translation range [" + std::to_string(spec.translation_min_mm) + ", " +
                std::to_string(spec.translation_max_mm) + "] mm is empty or not finite");
  check_workspace(spec, where);
  grid_ = vote_math::sva_pose_grid(
      planar() ? SVA_POSE_PLANAR : SVA_POSE_SPATIAL, spec.translation_bins, static_cast<float>(spec.translation_min_mm),
      static_cast<float>((spec.translation_max_mm - spec.translation_min_mm) / spec.translation_bins),
      spec.rotation_bins, static_cast<float>(2.0 * std::numbers::pi / spec.rotation_bins));
  if (!(grid_.translation_width > 0.0f) || !std::isfinite(grid_.translation_scale))
    throw Error(where + "translation bins narrower than float precision");
  const std::uint64_t tb = static_cast<std::uint64_t>(spec.translation_bins),
                      rb = static_cast<std::uint64_t>(spec.rotation_bins);
  bins_per_object_ = planar() ? tb * tb * rb : tb * tb * tb * rb * rb * rb;
}

BinIndex PoseSpace::unpack(std::uint64_t key) const {
  BinIndex b;
  b.object = static_cast<std::uint32_t>((key >> SVA_KEY_OBJECT_SHIFT) & mask(SVA_KEY_OBJECT_BITS));
  b.t[0] = static_cast<int>((key >> SVA_KEY_TX_SHIFT) & mask(SVA_KEY_TRANS_BITS));
  b.t[1] = static_cast<int>((key >> SVA_KEY_TY_SHIFT) & mask(SVA_KEY_TRANS_BITS));
  b.t[2] = static_cast<int>((key >> SVA_KEY_TZ_SHIFT) & mask(SVA_KEY_TRANS_BITS));
  b.r[0] = static_cast<int>((key >> SVA_KEY_RX_SHIFT) & mask(SVA_KEY_ROT_BITS));
  b.r[1] = static_cast<int>((key >> SVA_KEY_RY_SHIFT) & mask(SVA_KEY_ROT_BITS));
  b.r[2] = static_cast<int>((key >> SVA_KEY_RZ_SHIFT) & mask(SVA_KEY_ROT_BITS));
  return b;
}

std::uint64_t PoseSpace::pack(const BinIndex& b) const {
  return vote_math::sva_pack_bin_key(b.object, b.t[0], b.t[1], b.t[2], b.r[0], b.r[1], b.r[2]);
}

glm::dvec3 PoseSpace::translation_centre(const BinIndex& b) const {
  const double w = (spec_.translation_max_mm - spec_.translation_min_mm) / spec_.translation_bins;
  glm::dvec3 t;
  for (int k = 0; k < 3; ++k) t[k] = spec_.translation_min_mm + (b.t[k] + 0.5) * w;
  if (planar()) t.z = 0.0;
  return t;
}

glm::dvec3 PoseSpace::rotation_centre(const BinIndex& b) const {
  const double w = 2.0 * std::numbers::pi / spec_.rotation_bins;
  glm::dvec3 r;
  for (int k = 0; k < 3; ++k) r[k] = -std::numbers::pi + (b.r[k] + 0.5) * w;
  if (planar()) r.x = r.y = 0.0;
  return r;
}

RigidPose PoseSpace::centre(std::uint64_t key) const {
  const BinIndex b = unpack(key);
  RigidPose p;
  p.T = translation_centre(b);
  p.R = so3::exp(rotation_centre(b));
  return p;
}

bool PoseSpace::bin_of(std::uint32_t object, const RigidPose& pose, std::uint64_t* key) const {
  if (object >= objects_) return false;
  const double w = (spec_.translation_max_mm - spec_.translation_min_mm) / spec_.translation_bins;
  const double rw = 2.0 * std::numbers::pi / spec_.rotation_bins;
  BinIndex b;
  b.object = object;
  const int tdim = planar() ? 2 : 3;
  for (int k = 0; k < tdim; ++k) {
    const double f = (pose.T[k] - spec_.translation_min_mm) / w;
    if (!(f >= 0.0 && f < spec_.translation_bins)) return false;
    b.t[k] = static_cast<int>(f);
  }
  glm::dvec3 r = so3::log(pose.R);
  if (planar()) r = glm::dvec3(0.0, 0.0, r.z);
  for (int k = planar() ? 2 : 0; k < 3; ++k)
    b.r[k] = std::min(static_cast<int>(std::floor((r[k] + std::numbers::pi) / rw)), spec_.rotation_bins - 1);
  *key = pack(b);
  return true;
}

}  // namespace sva
