#include "backends/vulkan/pipeline.hpp"

#include <utility>
#include <vector>

#include "backends/vulkan/device.hpp"
#include "backends/vulkan/vk_check.hpp"

namespace sva::vk {

Pipeline::Pipeline(const Device& device, std::string name, std::span<const std::uint32_t> spirv, std::uint32_t bindings,
                   std::uint32_t push_bytes)
    : name_(std::move(name)), device_(device.handle()), bindings_(bindings), push_bytes_(push_bytes) {
  try {
    create(spirv);
  } catch (...) {
    release();  // the destructor does not run for a failed constructor
    throw;
  }
}

void Pipeline::create(std::span<const std::uint32_t> spirv) {
  VkShaderModuleCreateInfo smi{VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO};
  smi.codeSize = spirv.size_bytes();
  smi.pCode = spirv.data();
  check(vkCreateShaderModule(device_, &smi, nullptr, &module_), "vkCreateShaderModule");
  std::vector<VkDescriptorSetLayoutBinding> b(bindings_);
  for (std::uint32_t i = 0; i < bindings_; ++i)
    b[i] = {i, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1, VK_SHADER_STAGE_COMPUTE_BIT, nullptr};
  VkDescriptorSetLayoutCreateInfo dli{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
  dli.bindingCount = bindings_;
  dli.pBindings = b.data();
  check(vkCreateDescriptorSetLayout(device_, &dli, nullptr, &set_layout_), "vkCreateDescriptorSetLayout");
  VkPushConstantRange range{VK_SHADER_STAGE_COMPUTE_BIT, 0, push_bytes_};
  VkPipelineLayoutCreateInfo pli{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
  pli.setLayoutCount = 1;
  pli.pSetLayouts = &set_layout_;
  pli.pushConstantRangeCount = push_bytes_ ? 1 : 0;
  pli.pPushConstantRanges = push_bytes_ ? &range : nullptr;
  check(vkCreatePipelineLayout(device_, &pli, nullptr, &layout_), "vkCreatePipelineLayout");
  VkComputePipelineCreateInfo cpi{VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO};
  cpi.stage = {VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO,
               nullptr,
               0,
               VK_SHADER_STAGE_COMPUTE_BIT,
               module_,
               "main",
               nullptr};
  cpi.layout = layout_;
  check(vkCreateComputePipelines(device_, VK_NULL_HANDLE, 1, &cpi, nullptr, &pipeline_), "vkCreateComputePipelines");
}

void Pipeline::release() {
  if (device_) {
    if (pipeline_) vkDestroyPipeline(device_, pipeline_, nullptr);
    if (layout_) vkDestroyPipelineLayout(device_, layout_, nullptr);
    if (set_layout_) vkDestroyDescriptorSetLayout(device_, set_layout_, nullptr);
    if (module_) vkDestroyShaderModule(device_, module_, nullptr);
  }
  device_ = VK_NULL_HANDLE;
  pipeline_ = VK_NULL_HANDLE;
  layout_ = VK_NULL_HANDLE;
  set_layout_ = VK_NULL_HANDLE;
  module_ = VK_NULL_HANDLE;
}

Pipeline::~Pipeline() { release(); }
Pipeline::Pipeline(Pipeline&& o) noexcept { *this = std::move(o); }
Pipeline& Pipeline::operator=(Pipeline&& o) noexcept {
  if (this != &o) {
    release();
    std::swap(name_, o.name_);
    std::swap(device_, o.device_);
    std::swap(module_, o.module_);
    std::swap(set_layout_, o.set_layout_);
    std::swap(layout_, o.layout_);
    std::swap(pipeline_, o.pipeline_);
    std::swap(bindings_, o.bindings_);
    std::swap(push_bytes_, o.push_bytes_);
  }
  return *this;
}

}  // namespace sva::vk
