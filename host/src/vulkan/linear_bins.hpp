#pragma once
// Pose bins as the GPU tables key them: one linear index over (object, tx, ty,
// tz, rx, ry, rz), planar spaces without tz, rx and ry (match_votes.comp's
// linear_bin). Its order is the packed keys' order, so the smallest linear
// index is the smallest key and sorted read-outs agree with the CPU's.
#include <cstdint>

#include "recognition/pose_space.hpp"

namespace sva {

class LinearBins {
 public:
  explicit LinearBins(const PoseSpace& space)
      : space_(&space),
        t_(static_cast<std::uint64_t>(space.spec().translation_bins)),
        r_(static_cast<std::uint64_t>(space.spec().rotation_bins)),
        tz_(space.planar() ? 1 : t_),
        rxy_(space.planar() ? 1 : r_),
        per_object_(t_ * t_ * tz_ * rxy_ * rxy_ * r_) {}

  std::uint64_t per_object() const { return per_object_; }
  std::uint64_t total() const { return per_object_ * space_->objects(); }
  std::uint32_t dim_tz() const { return static_cast<std::uint32_t>(tz_); }
  std::uint32_t dim_rxy() const { return static_cast<std::uint32_t>(rxy_); }

  std::uint64_t linear(std::uint64_t key) const {
    const BinIndex b = space_->unpack(key);
    std::uint64_t i = b.object;
    i = i * t_ + static_cast<std::uint64_t>(b.t[0]);
    i = i * t_ + static_cast<std::uint64_t>(b.t[1]);
    i = i * tz_ + static_cast<std::uint64_t>(b.t[2]);
    i = i * rxy_ + static_cast<std::uint64_t>(b.r[0]);
    i = i * rxy_ + static_cast<std::uint64_t>(b.r[1]);
    return i * r_ + static_cast<std::uint64_t>(b.r[2]);
  }

  std::uint64_t key(std::uint64_t linear) const {
    BinIndex b;
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
    b.t[0] = static_cast<int>(linear % t_);
    b.object = static_cast<std::uint32_t>(linear / t_);
    return space_->pack(b);
  }

 private:
  const PoseSpace* space_;
  std::uint64_t t_, r_, tz_, rxy_, per_object_;
};

}  // namespace sva
