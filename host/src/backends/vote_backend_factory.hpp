#pragma once
// The one place that picks a vote backend: cpu (the reference), vulkan, or
// auto (Vulkan when a usable device exists, else the CPU reference, with the
// reason). Every command and the public Recognizer / BatchRecognizer come here.
#include <sva/recognizer.hpp>

#include <memory>
#include <string>

#include "backends/vote_backend.hpp"
#include "backends/vulkan/vulkan_vote_backend.hpp"

namespace sva {

struct VoteBackendChoice {
  std::unique_ptr<VoteBackend> backend;
  BackendKind kind = BackendKind::cpu;  // the one made: cpu or vulkan, never automatic
  std::string fallback_reason;          // automatic only: why the CPU reference runs ("" when Vulkan does)
};

// Throws sva::Error when the asked-for backend cannot be made (vulkan without a
// usable device, say); automatic then falls back to the CPU reference instead.
VoteBackendChoice make_vote_backend(BackendKind kind, const PairMap& map, const PoseSpace& space,
                                    const VoteSettings& settings, const VulkanBackendOptions& vulkan = {});

}  // namespace sva
