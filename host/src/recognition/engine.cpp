#include "recognition/engine.hpp"

#include <sva/error.hpp>

#include <algorithm>

#include "backends/vulkan/gpu_belief.hpp"
#include "estimate/verify.hpp"
#include "map/map_access.hpp"
#include "map/pair_map.hpp"

namespace sva {

Engine::Engine(const Map& map, const EngineOptions& options) : impl_(std::make_shared<Impl>()) {
  if (map.empty()) throw Error("engine: the map is empty (not trained or not loaded)");
  impl_->map = map;
  impl_->options = options;
  const PairMap& m = MapAccess::pair_map(map);
  impl_->keep_space = std::make_unique<PoseSpace>(m.pose_space, static_cast<std::uint32_t>(m.objects.size()));
  VoteBackendChoice choice = make_vote_backend(options.backend, m, *impl_->keep_space, {}, vulkan_options(*impl_));
  impl_->kind = choice.kind;
  impl_->fallback_reason = std::move(choice.fallback_reason);
  impl_->description = choice.kind == BackendKind::vulkan ? "vulkan: " + choice.backend->statistics().device
                                                          : std::string(choice.backend->name());
  const BackendStats stats = choice.backend->statistics();
  impl_->device_type = stats.device_type;
  impl_->device_memory_bytes = stats.device_memory_bytes;
  impl_->map_device_bytes = stats.map_device_bytes;
  // The CPU backend holds nothing worth sharing; a Vulkan one keeps the device and the map's upload alive.
  if (choice.kind == BackendKind::vulkan) impl_->keep_backend = std::move(choice.backend);
}

std::size_t Engine::sessions_per_submission(const RecognizerOptions& options) const {
  DeviceMemoryInfo d{impl_->device_type, impl_->device_memory_bytes, impl_->map_device_bytes, 0};
  if (impl_->kind == BackendKind::vulkan && options.belief_budget_bins > 0)
    d.belief_bytes = GpuBelief::bytes_at(options.belief_budget_bins, impl_->keep_space->objects());
  return submission_sessions(d);
}

std::size_t Engine::submissions_in_flight() const {
  return in_flight({impl_->device_type, impl_->device_memory_bytes, impl_->map_device_bytes, 0});
}

namespace {
// A GPU, not the CPU reference ("") nor a CPU device (lavapipe: "cpu").
bool on_gpu(const DeviceMemoryInfo& d) { return !d.type.empty() && d.type != "cpu"; }
}  // namespace

std::size_t in_flight(const DeviceMemoryInfo& d) { return on_gpu(d) ? 2 : 1; }

std::size_t submission_sessions(const DeviceMemoryInfo& d) {
  if (!on_gpu(d) || d.belief_bytes == 0 || d.bytes <= d.map_bytes) return kMinSubmission;
  const std::uint64_t fits = (d.bytes - d.map_bytes) / 2 / in_flight(d) / d.belief_bytes;
  return static_cast<std::size_t>(std::clamp<std::uint64_t>(fits, kMinSubmission, kMaxSubmission));
}

const Map& Engine::map() const { return impl_->map; }
BackendKind Engine::backend() const { return impl_->kind; }
const std::string& Engine::fallback_reason() const { return impl_->fallback_reason; }
std::string Engine::backend_description() const { return impl_->description; }

const SurfaceIndex& Engine::Impl::surface() const {
  std::call_once(surface_once_, [&] {
    const PairMap& m = MapAccess::pair_map(map);
    surface_ = std::make_unique<SurfaceIndex>(m.readings, m.objects.size());
  });
  return *surface_;
}

const SurfaceModel* Engine::Impl::surface_model() const {
  std::call_once(model_once_, [&] { model_ = surface_model_of(MapAccess::pair_map(map)); });
  return model_.get();
}

VulkanBackendOptions vulkan_options(const Engine::Impl& engine) {
  VulkanBackendOptions vo;
  vo.device = engine.options.vulkan_device;
  return vo;
}

}  // namespace sva
