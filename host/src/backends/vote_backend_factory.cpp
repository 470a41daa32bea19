#include "backends/vote_backend_factory.hpp"

#include <sva/error.hpp>

#include "backends/vulkan/vulkan_vote_backend.hpp"

namespace sva {

VoteBackendChoice make_vote_backend(BackendKind kind, const PairMap& map, const PoseSpace& space,
                                    const VoteSettings& settings, const VulkanBackendOptions& vulkan) {
  VoteBackendChoice choice;
  if (kind == BackendKind::cpu) {
    choice.backend = make_cpu_vote_backend(map, space, settings);
    return choice;
  }
  try {
    // auto: a GPU. A software Vulkan device (lavapipe) runs on the same cores
    // as the CPU reference, several times slower; it serves only when named.
    if (kind == BackendKind::automatic) {
      const VulkanDeviceChoice d = probe_vulkan_device(vulkan);
      if (d.type == "cpu" && !d.named) {
        choice.backend = make_cpu_vote_backend(map, space, settings);
        choice.kind = BackendKind::cpu;
        choice.fallback_reason = "the only Vulkan device is a software one (" + d.name +
                                 "), slower than the CPU reference; name it (--device, SVA_VK_DEVICE) to use it";
        return choice;
      }
    }
    choice.backend = make_vulkan_vote_backend(map, space, settings, vulkan);
    choice.kind = BackendKind::vulkan;
  } catch (const Interrupted&) {
    throw;
  } catch (const Error& e) {
    if (kind != BackendKind::automatic) throw;
    // Both backends give the same answers (the CPU one is the specification),
    // so falling back changes the speed, never the results.
    choice.backend = make_cpu_vote_backend(map, space, settings);
    choice.kind = BackendKind::cpu;
    choice.fallback_reason = e.what();
  }
  return choice;
}

BackendKind parse_backend_kind(const std::string& text, const std::string& option) {
  if (text == "cpu") return BackendKind::cpu;
  if (text == "vulkan") return BackendKind::vulkan;
  if (text == "auto") return BackendKind::automatic;
  throw Error(option + " expects auto, cpu or vulkan, got \"" + text + "\"");
}

const char* backend_kind_name(BackendKind kind) {
  switch (kind) {
    case BackendKind::cpu:
      return "cpu";
    case BackendKind::vulkan:
      return "vulkan";
    case BackendKind::automatic:
      return "auto";
  }
  return "?";
}

}  // namespace sva
