#include "recognition/engine.hpp"

#include <sva/error.hpp>

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
  // The CPU backend holds nothing worth sharing; a Vulkan one keeps the device and the map's upload alive.
  if (choice.kind == BackendKind::vulkan) impl_->keep_backend = std::move(choice.backend);
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
