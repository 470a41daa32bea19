#include <sva/eval/trials.hpp>

#include <sva/base/finite.hpp>
#include <sva/base/so3.hpp>

#include <sva/base/portable_math.hpp>
#include <sva/error.hpp>

#include <cmath>

#include "training/session_sampling.hpp"

namespace sva::eval {

TrialGenerator::TrialGenerator(const Dataset& test, const PoseSpaceSpec& space, std::uint64_t seed,
                               std::size_t max_readings, std::string source)
    : test_(test), space_(space), seed_(seed), max_readings_(max_readings) {
  if (max_readings == 0) throw Error("max readings per trial must be at least 1, got 0");
  if (!(space.translation_min_mm <= space.translation_max_mm) || !std::isfinite(space.translation_min_mm) ||
      !std::isfinite(space.translation_max_mm))
    throw Error("pose space translation range is invalid");
  const auto n_objects = test.scene.objects.size();
  if (n_objects == 0) throw Error(source + ": the scene has no objects");
  const auto elements = static_cast<std::size_t>(test.scene.sensor.elements());
  by_object_.assign(n_objects, {});
  object_frame_.resize(test.samples.size());
  for (std::size_t i = 0; i < test.samples.size(); ++i) {
    const Sample& s = test.samples[i];
    const Reading& r = s.reading;
    if (r.status != ControllerStatus::converged) continue;
    auto bad = [&](const std::string& what) { throw Error(source + ": sample " + std::to_string(i) + ": " + what); };
    if (s.object >= n_objects) bad("object id " + std::to_string(s.object) + " out of range");
    if (!finite(r.position) || !finite(r.normal) || !finite(r.x_axis) || !finite(s.object_pose.T))
      bad("sensor or object pose holds a NaN or infinite value");
    if (!so3::is_rotation(s.object_pose.R)) bad("object pose rotation is not a rotation matrix");
    if (r.pressure.size() != elements)
      bad("pressure image has " + std::to_string(r.pressure.size()) + " values, the sensor has " +
          std::to_string(elements));
    for (float v : r.pressure)
      if (!std::isfinite(v)) bad("pressure image holds a NaN or infinite value");
    // Readings are stored in the robot frame of their session; bring them to
    // the object frame so that the trial pose is the only motion.
    object_frame_[i] = transform_reading(r, s.object_pose.inverse());
    by_object_[s.object].push_back(i);
  }
  std::size_t total = 0;
  for (const auto& v : by_object_) total += v.size();
  if (total == 0)
    throw Error(source + ": the test set is empty (" + std::to_string(test.samples.size()) +
                " samples, none with a converged controller)");
  for (std::size_t o = 0; o < n_objects; ++o)
    if (by_object_[o].empty())
      throw Error(source + ": object \"" + test.scene.objects[o].name + "\" has no converged test readings");
}

Trial TrialGenerator::make(std::size_t t) const {
  Trial trial;
  trial.index = t;
  trial.object = static_cast<std::uint32_t>(t % by_object_.size());
  util::Rng rng(seed_, t);
  trial.pose = random_pose(rng, space_);
  const auto& pool = by_object_[trial.object];
  std::vector<std::size_t> order = pool;
  // Partial Fisher-Yates: only the positions that will be shown are drawn.
  const std::size_t distinct = std::min(max_readings_, order.size());
  for (std::size_t k = 0; k < distinct; ++k) std::swap(order[k], order[k + rng.below(order.size() - k)]);
  trial.samples.assign(order.begin(), order.begin() + static_cast<std::ptrdiff_t>(distinct));
  while (trial.samples.size() < max_readings_) trial.samples.push_back(pool[rng.below(pool.size())]);
  trial.readings.reserve(trial.samples.size());
  for (std::size_t i : trial.samples) trial.readings.push_back(transform_reading(object_frame_[i], trial.pose));
  return trial;
}

}  // namespace sva::eval
