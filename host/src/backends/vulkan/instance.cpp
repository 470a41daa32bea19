#include "backends/vulkan/instance.hpp"

#include <sva/error.hpp>

#include <algorithm>
#include <cstdlib>
#include <string>
#ifdef __SANITIZE_ADDRESS__
#include <dlfcn.h>
#include <link.h>
#endif
#include <cstring>

#include "backends/vulkan/vk_check.hpp"

namespace sva::vk {

namespace {

constexpr const char* kValidationLayer = "VK_LAYER_KHRONOS_validation";

VKAPI_ATTR VkBool32 VKAPI_CALL on_validation(VkDebugUtilsMessageSeverityFlagBitsEXT severity,
                                             VkDebugUtilsMessageTypeFlagsEXT,
                                             const VkDebugUtilsMessengerCallbackDataEXT* data, void* user) {
  if (severity >= VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT) {
    auto* log = static_cast<Instance::Log*>(user);
    std::lock_guard lock(log->mutex);
    log->messages.emplace_back(data && data->pMessage ? data->pMessage : "(no message)");
  }
  return VK_FALSE;
}

void require_validation_layer() {
  std::uint32_t n = 0;
  check(vkEnumerateInstanceLayerProperties(&n, nullptr), "vkEnumerateInstanceLayerProperties");
  std::vector<VkLayerProperties> props(n);
  const VkResult listed = vkEnumerateInstanceLayerProperties(&n, props.data());
  if (listed != VK_INCOMPLETE) check(listed, "vkEnumerateInstanceLayerProperties");
  props.resize(n);
  const auto is_validation = [](const VkLayerProperties& p) { return std::strcmp(p.layerName, kValidationLayer) == 0; };
  if (std::none_of(props.begin(), props.end(), is_validation))
    throw Error(
        "Vulkan validation requested (SVA_VK_VALIDATION=1) but VK_LAYER_KHRONOS_validation is not installed "
        "(apt-get install vulkan-validationlayers)");
}

VkDebugUtilsMessengerEXT create_messenger(VkInstance instance, Instance::Log* log) {
  auto create = reinterpret_cast<PFN_vkCreateDebugUtilsMessengerEXT>(
      vkGetInstanceProcAddr(instance, "vkCreateDebugUtilsMessengerEXT"));
  if (!create) return VK_NULL_HANDLE;
  VkDebugUtilsMessengerCreateInfoEXT mci{VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT};
  mci.messageSeverity = VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT;
  mci.messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT |
                    VK_DEBUG_UTILS_MESSAGE_TYPE_PERFORMANCE_BIT_EXT;
  mci.pfnUserCallback = on_validation;
  mci.pUserData = log;
  VkDebugUtilsMessengerEXT messenger = VK_NULL_HANDLE;
  check(create(instance, &mci, nullptr, &messenger), "vkCreateDebugUtilsMessengerEXT");
  return messenger;
}

#ifdef __SANITIZE_ADDRESS__
// Sanitizer builds only: the Vulkan driver (lavapipe and its LLVM) keeps process-lifetime state that it never frees,
// and the loader unloads it at vkDestroyInstance, so LeakSanitizer could not name its frames and its suppression
// (tests/lsan-suppressions.txt) could not match. Marking the loaded driver libraries never-unloaded keeps them named.
int keep_loaded(dl_phdr_info* info, std::size_t, void*) {
  const std::string name = info->dlpi_name ? info->dlpi_name : "";
  if (name.find("libvulkan_") != std::string::npos || name.find("libLLVM") != std::string::npos)
    dlopen(name.c_str(), RTLD_NOW | RTLD_NOLOAD | RTLD_NODELETE);  // a reference that is never dropped
  return 0;
}
void keep_drivers_loaded() { dl_iterate_phdr(keep_loaded, nullptr); }
#else
void keep_drivers_loaded() {}
#endif

// Why vkCreateInstance found no driver. Where the caller named the drivers (an NVIDIA container's ICD file), the
// likely fault is not a missing package but a library the driver opens that the machine lacks: on a bare container
// libglvnd's libEGL.so.1 for NVIDIA's libGLX_nvidia.so.0 (docs/vulkan-backend.md, "Running on a GPU machine").
std::string no_driver_message() {
  for (const char* var : {"VK_DRIVER_FILES", "VK_ICD_FILENAMES"}) {
    const char* files = std::getenv(var);
    if (!files || !*files) continue;
    return std::string("no Vulkan device: the Vulkan driver named by ") + var + "=" + files +
           " did not load (a missing file, or a library it opens is missing, e.g. libglvnd's libEGL.so.1 for NVIDIA's; "
           "VK_LOADER_DEBUG=error,driver prints the loader's reason)";
  }
  return "no Vulkan device: no Vulkan driver is installed (apt-get install mesa-vulkan-drivers for the lavapipe "
         "CPU driver; VK_LOADER_DEBUG=error,driver prints what the loader tried)";
}

}  // namespace

Instance::Instance(bool validation) {
  VkApplicationInfo app{VK_STRUCTURE_TYPE_APPLICATION_INFO};
  app.pApplicationName = "sva";
  app.apiVersion = VK_API_VERSION_1_2;
  std::vector<const char*> layers, extensions;
  if (validation) {
    require_validation_layer();
    layers.push_back(kValidationLayer);
    extensions.push_back(VK_EXT_DEBUG_UTILS_EXTENSION_NAME);
  }
  VkInstanceCreateInfo ici{VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};
  ici.pApplicationInfo = &app;
  ici.enabledLayerCount = static_cast<std::uint32_t>(layers.size());
  ici.ppEnabledLayerNames = layers.data();
  ici.enabledExtensionCount = static_cast<std::uint32_t>(extensions.size());
  ici.ppEnabledExtensionNames = extensions.data();
  const VkResult r = vkCreateInstance(&ici, nullptr, &instance_);
  if (r == VK_ERROR_INCOMPATIBLE_DRIVER || r == VK_ERROR_INITIALIZATION_FAILED) throw Error(no_driver_message());
  check(r, "vkCreateInstance");
  keep_drivers_loaded();
  if (!validation) return;
  try {
    messenger_ = create_messenger(instance_, log_.get());
  } catch (...) {
    vkDestroyInstance(instance_, nullptr);  // the destructor does not run for a failed constructor
    throw;
  }
}

Instance::~Instance() {
  if (messenger_) {
    auto destroy = reinterpret_cast<PFN_vkDestroyDebugUtilsMessengerEXT>(
        vkGetInstanceProcAddr(instance_, "vkDestroyDebugUtilsMessengerEXT"));
    if (destroy) destroy(instance_, messenger_, nullptr);
  }
  if (instance_) vkDestroyInstance(instance_, nullptr);
}

std::uint32_t Instance::validation_messages() const {
  std::lock_guard lock(log_->mutex);
  return static_cast<std::uint32_t>(log_->messages.size());
}

}  // namespace sva::vk
