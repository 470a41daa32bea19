#pragma once
// A planned touch (sva::plan_next_touch) pressed on the scene's meshes, as `sva simulate` takes a test reading:
// what `sva eval --policy active-sim` feeds the recognizer instead of the nearest recorded test reading.
#include <sva/pose.hpp>
#include <sva/reading.hpp>
#include <sva/scene.hpp>
#include <sva/touch_planner.hpp>

#include <cstdint>
#include <memory>
#include <optional>

namespace sva::sim {

class TouchSimulator {
 public:
  // Loads every object's mesh once, with one test sensor each (the scene's errors, its test sensor instance).
  // sva::Error naming the object when a mesh cannot be loaded.
  explicit TouchSimulator(const Scene& scene);
  ~TouchSimulator();
  TouchSimulator(TouchSimulator&&) noexcept;
  TouchSimulator& operator=(TouchSimulator&&) noexcept;

  // Presses `touch` (robot frame) on `object` lying at `object_pose`: the sensor starts the protocol's approach
  // distance off the planned point, pressing along the planned approach with an uncontrolled turn about it (drawn
  // from `seed`), the contact controller settles it, and the arm's pose error is put on the reading, which comes
  // back in the robot frame. Nothing when the controller does not converge there.
  std::optional<Reading> press(std::uint32_t object, const RigidPose& object_pose, const CandidateTouch& touch,
                               std::uint64_t seed) const;

 private:
  struct World;
  std::unique_ptr<World> world_;
};

}  // namespace sva::sim
