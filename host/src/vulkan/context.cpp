#include "vulkan/context.hpp"

#include <cstdlib>

namespace sva::vk {

ContextOptions Context::from_environment() {
  ContextOptions o;
  if (const char* d = std::getenv("SVA_VK_DEVICE")) o.device = d;
  if (const char* v = std::getenv("SVA_VK_VALIDATION")) o.validation = std::string(v) == "1";
  return o;
}

Context::Context(const ContextOptions& options)
    : instance_(options.validation), device_(instance_, options.device), commands_(device_) {}

}  // namespace sva::vk
