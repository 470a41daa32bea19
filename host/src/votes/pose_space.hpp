#pragma once
// The discretised pose space of the belief (paper Sec 5): object x translation
// bins x Rodrigues rotation bins (planar: x, y and the angle about z). Only
// touched bins are stored; a bin is named by a 64-bit key whose layout is
// defined once in sva_vote_math.h.
#include <sva/pose.hpp>
#include <sva/pose_space.hpp>

#include <cstdint>

#include "votes/vote_math.hpp"

namespace sva {

struct BinIndex {
  std::uint32_t object = 0;
  int t[3] = {0, 0, 0};
  int r[3] = {0, 0, 0};
};

class PoseSpace {
 public:
  // Throws sva::Error when the spec is empty, inverted, does not fit the key, or its workspace frame is not a
  // rigid transform (a planar one: not a rotation about z).
  PoseSpace(const PoseSpaceSpec& spec, std::uint32_t objects);

  const PoseSpaceSpec& spec() const { return spec_; }
  std::uint32_t objects() const { return objects_; }
  bool planar() const { return spec_.kind == PoseSpaceSpec::Kind::planar; }
  // Where the grid lies in the robot frame (x_robot = workspace().apply(x_grid)). The belief and the fine pose
  // work in the grid's frame: readings enter through to_grid(), poses leave through to_robot().
  const RigidPose& workspace() const { return spec_.workspace; }
  RigidPose to_robot(const RigidPose& grid_pose) const { return spec_.workspace * grid_pose; }
  // The grid as the vote math sees it.
  vote_math::SvaPoseGrid grid() const { return grid_; }
  // Bins per object (all of them, touched or not).
  std::uint64_t bins_per_object() const { return bins_per_object_; }

  static std::uint32_t object_of(std::uint64_t key) { return static_cast<std::uint32_t>(key >> SVA_KEY_OBJECT_SHIFT); }
  BinIndex unpack(std::uint64_t key) const;
  std::uint64_t pack(const BinIndex& b) const;
  // Centre of a bin (planar: z = 0, rotation about z).
  RigidPose centre(std::uint64_t key) const;
  // Bin-centre coordinates: translation (mm) and Rodrigues vector (planar: (0, 0, angle)).
  glm::dvec3 translation_centre(const BinIndex& b) const;
  glm::dvec3 rotation_centre(const BinIndex& b) const;
  // The bin of a continuous pose, or false when it lies outside the space.
  bool bin_of(std::uint32_t object, const RigidPose& pose, std::uint64_t* key) const;
  // Keys of the 3^d neighbourhood (d = 6 spatial, 3 planar) inside the grid, `key` included.
  template <class Fn>
  void for_each_neighbour(std::uint64_t key, Fn&& fn) const;

 private:
  PoseSpaceSpec spec_;
  std::uint32_t objects_;
  vote_math::SvaPoseGrid grid_{};
  std::uint64_t bins_per_object_ = 0;
};

template <class Fn>
void PoseSpace::for_each_neighbour(std::uint64_t key, Fn&& fn) const {
  const BinIndex c = unpack(key);
  const int tdim = planar() ? 2 : 3;
  const int rlo = planar() ? 2 : 0;
  const int tb = spec_.translation_bins, rb = spec_.rotation_bins;
  for (int dx = -1; dx <= 1; ++dx)
    for (int dy = -1; dy <= 1; ++dy)
      for (int dz = (tdim == 3 ? -1 : 0); dz <= (tdim == 3 ? 1 : 0); ++dz)
        for (int ex = (rlo == 0 ? -1 : 0); ex <= (rlo == 0 ? 1 : 0); ++ex)
          for (int ey = (rlo == 0 ? -1 : 0); ey <= (rlo == 0 ? 1 : 0); ++ey)
            for (int ez = -1; ez <= 1; ++ez) {
              BinIndex n = c;
              n.t[0] += dx;
              n.t[1] += dy;
              n.t[2] += dz;
              n.r[0] += ex;
              n.r[1] += ey;
              n.r[2] += ez;
              if (rlo == 2) n.r[2] = (n.r[2] + rb) % rb;  // the planar angle is periodic
              bool ok = true;
              for (int k = 0; k < 3; ++k) ok = ok && n.t[k] >= 0 && n.t[k] < tb && n.r[k] >= 0 && n.r[k] < rb;
              if (ok) fn(pack(n));
            }
}

}  // namespace sva
