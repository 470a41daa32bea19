#pragma once
// A compute pipeline from embedded SPIR-V, with its descriptor-set layout (one
// storage buffer per binding) and push-constant range: all a kernel launch needs.
// Its name (the shader's file stem, e.g. "belief_fold") is what the device's time
// by kernel is summed under (CommandRunner's SubmitTimes).
#include <vulkan/vulkan.h>

#include <cstdint>
#include <span>
#include <string>

namespace sva::vk {

class Device;

class Pipeline {
 public:
  Pipeline() = default;
  Pipeline(const Device& device, std::string name, std::span<const std::uint32_t> spirv, std::uint32_t bindings,
           std::uint32_t push_bytes);
  Pipeline(Pipeline&&) noexcept;
  Pipeline& operator=(Pipeline&&) noexcept;
  Pipeline(const Pipeline&) = delete;
  Pipeline& operator=(const Pipeline&) = delete;
  ~Pipeline();

  const std::string& name() const { return name_; }
  std::uint32_t bindings() const { return bindings_; }
  std::uint32_t push_bytes() const { return push_bytes_; }
  VkPipeline handle() const { return pipeline_; }
  VkPipelineLayout layout() const { return layout_; }
  VkDescriptorSetLayout set_layout() const { return set_layout_; }

 private:
  void create(std::span<const std::uint32_t> spirv);
  void release();

  std::string name_;
  VkDevice device_ = VK_NULL_HANDLE;
  VkShaderModule module_ = VK_NULL_HANDLE;
  VkDescriptorSetLayout set_layout_ = VK_NULL_HANDLE;
  VkPipelineLayout layout_ = VK_NULL_HANDLE;
  VkPipeline pipeline_ = VK_NULL_HANDLE;
  std::uint32_t bindings_ = 0;
  std::uint32_t push_bytes_ = 0;
};

}  // namespace sva::vk
