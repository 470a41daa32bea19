#pragma once
// Pose bins as the GPU tables key them: the object in the high bits (from
// object_shift), below it one mixed-radix index over (tx, ty, tz, rx, ry, rz),
// planar spaces without tz, rx and ry (sva_linear_bin in sva_vote_math.h). The
// vote table puts the pair above that (from pair_shift). Shifts rather than
// products, so the kernels split a key without 64-bit division. The order is
// the packed keys' order, so the smallest linear index is the smallest key and
// sorted read-outs agree with the CPU's.
#include <bit>
#include <cstdint>

#include <sva/error.hpp>

#include "votes/pose_space.hpp"

namespace sva {

class LinearBins {
 public:
  explicit LinearBins(const PoseSpace& space)
      : space_(&space),
        t_(static_cast<std::uint64_t>(space.spec().translation_bins)),
        r_(static_cast<std::uint64_t>(space.spec().rotation_bins)),
        tz_(space.planar() ? 1 : t_),
        rxy_(space.planar() ? 1 : r_),
        per_object_(t_ * t_ * tz_ * rxy_ * rxy_ * r_),
        object_shift_(static_cast<std::uint32_t>(std::bit_width(per_object_ - 1))),
        pair_shift_(object_shift_ + static_cast<std::uint32_t>(std::bit_width(std::uint64_t{space.objects()} - 1))) {
    if (pair_shift_ > 62) throw Error("pose space has too many bins for the GPU backend's 64-bit keys");
  }

  std::uint32_t object_shift() const { return object_shift_; }
  std::uint32_t pair_shift() const { return pair_shift_; }
  // The most pairs one vote table can key (pair << pair_shift stays below 2^62).
  std::uint64_t max_pairs() const { return std::uint64_t{1} << (62 - pair_shift_); }
  std::uint64_t pair_of(std::uint64_t vote_key) const { return vote_key >> pair_shift_; }
  std::uint64_t bin_of(std::uint64_t vote_key) const { return vote_key & ((std::uint64_t{1} << pair_shift_) - 1); }
  std::uint32_t dim_tz() const { return static_cast<std::uint32_t>(tz_); }
  std::uint32_t dim_rxy() const { return static_cast<std::uint32_t>(rxy_); }

  std::uint64_t linear(std::uint64_t key) const {
    return vote_math::sva_linear_bin(key, static_cast<std::uint32_t>(t_), static_cast<std::uint32_t>(r_),
                                     static_cast<std::uint32_t>(tz_), static_cast<std::uint32_t>(rxy_), object_shift_);
  }

  // The inverse of linear(), on the host only.
  std::uint64_t key(std::uint64_t linear) const {
    BinIndex b;
    b.object = static_cast<std::uint32_t>(linear >> object_shift_);
    linear &= (std::uint64_t{1} << object_shift_) - 1;
    b.r[2] = static_cast<int>(linear % r_);
    linear /= r_;
    b.r[1] = static_cast<int>(linear % rxy_);
    linear /= rxy_;
    b.r[0] = static_cast<int>(linear % rxy_);
    linear /= rxy_;
    b.t[2] = static_cast<int>(linear % tz_);
    linear /= tz_;
    b.t[1] = static_cast<int>(linear % t_);
    linear /= t_;
    b.t[0] = static_cast<int>(linear);
    return space_->pack(b);
  }

 private:
  const PoseSpace* space_;
  std::uint64_t t_, r_, tz_, rxy_, per_object_;
  std::uint32_t object_shift_, pair_shift_;
};

}  // namespace sva
