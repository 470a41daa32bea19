#pragma once
// The engine's private side: what the recognizers made from one sva::Engine share.
#include <sva/engine.hpp>

#include <memory>
#include <mutex>

#include "backends/vote_backend.hpp"
#include "backends/vote_backend_factory.hpp"
#include "estimate/surface_model.hpp"
#include "map/surface_index.hpp"
#include "votes/pose_space.hpp"

namespace sva {

struct Engine::Impl {
  Map map;
  EngineOptions options;
  BackendKind kind = BackendKind::cpu;
  std::string fallback_reason;
  std::string description;
  // Holds the device and the uploaded map (a VulkanEngine, shared by every Vulkan backend on this map and
  // device) for as long as the Engine lives; CPU: nothing.
  std::unique_ptr<PoseSpace> keep_space;
  std::unique_ptr<VoteBackend> keep_backend;

  // The fine pose's index of the objects' training contacts, built on first use and shared.
  const SurfaceIndex& surface() const;
  // The verify stage's measurement model of the map's meshes, built on first use and shared; null when the map
  // carries none.
  const SurfaceModel* surface_model() const;

 private:
  mutable std::once_flag surface_once_, model_once_;
  mutable std::unique_ptr<SurfaceIndex> surface_;
  mutable std::unique_ptr<SurfaceModel> model_;
};

// The backend options of a recognizer made from `engine`: its kind (resolved) and device.
VulkanBackendOptions vulkan_options(const Engine::Impl& engine);

}  // namespace sva
