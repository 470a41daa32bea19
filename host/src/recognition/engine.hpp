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
  // The device's memory as the backend found it (sessions_per_submission): kind, largest device-local heap, map.
  std::string device_type;
  std::uint64_t device_memory_bytes = 0, map_device_bytes = 0;

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

// A device's memory, for sizing a batch's submissions.
struct DeviceMemoryInfo {
  std::string type;                // "discrete", "integrated", "cpu" (lavapipe); "" on the CPU reference
  std::uint64_t bytes = 0;         // its largest device-local heap
  std::uint64_t map_bytes = 0;     // of it, the uploaded map's
  std::uint64_t belief_bytes = 0;  // one session's belief at its bound (0: no bound)
};
// Engine::sessions_per_submission's rule: the sessions whose beliefs at their bound fill half the memory the map
// leaves, from kMinSubmission to kMaxSubmission; kMinSubmission on a CPU (the reference or lavapipe) or unbounded.
constexpr std::size_t kMinSubmission = 64, kMaxSubmission = 4096;
std::size_t submission_sessions(const DeviceMemoryInfo& device);
// The groups a batch keeps in flight on `device`: 2 on a GPU, 1 on a CPU (Engine::submissions_in_flight).
std::size_t in_flight(const DeviceMemoryInfo& device);

}  // namespace sva
