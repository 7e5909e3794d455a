#include "gpu/compute.h"

#include <algorithm>
#include <string>

namespace aeroflock::gpu {

namespace {

uint32_t format_bytes(VkFormat format) {
  switch (format) {
    case VK_FORMAT_R32_UINT:
      return 4;
    case VK_FORMAT_R32G32_UINT:
      return 8;
    case VK_FORMAT_R32G32B32A32_SFLOAT:
    case VK_FORMAT_R32G32B32A32_SINT:
    case VK_FORMAT_R32G32B32A32_UINT:
      return 16;
    default:
      throw Error("compute pipeline: texel format " + std::to_string(format) + " not supported");
  }
}

}  // namespace

// --- ComputePipeline ------------------------------------------------------------------------

ComputePipeline::ComputePipeline(const Device& device, std::span<const uint32_t> spirv,
                                 std::vector<Binding> bindings, uint32_t push_size,
                                 uint32_t max_sets, std::vector<uint32_t> constants)
    : device_(device), bindings_(std::move(bindings)), push_size_(push_size) {
  const uint32_t count = static_cast<uint32_t>(bindings_.size());
  if (spirv.empty()) throw Error("compute pipeline: empty SPIR-V");
  if (push_size % 4 != 0 || push_size > device.limits().maxPushConstantsSize)
    throw Error("compute pipeline: push constants of " + std::to_string(push_size) +
                " bytes (a multiple of 4, at most maxPushConstantsSize = " +
                std::to_string(device.limits().maxPushConstantsSize) + ")");
  // A device's limits on a stage's descriptors of each kind (the least the spec allows is 4).
  auto within = [&](VkDescriptorType type, uint32_t most, const char* limit) {
    const auto n = std::count_if(bindings_.begin(), bindings_.end(),
                                 [&](const Binding& b) { return b.type == type; });
    if (uint32_t(n) > most)
      throw Error("compute pipeline: " + std::to_string(n) + " bindings of descriptor type " +
                  std::to_string(int(type)) + ", more than " + device.name() + "'s " + limit +
                  " = " + std::to_string(most));
  };
  within(VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, device.limits().maxPerStageDescriptorStorageBuffers,
         "maxPerStageDescriptorStorageBuffers");
  within(VK_DESCRIPTOR_TYPE_STORAGE_TEXEL_BUFFER,
         device.limits().maxPerStageDescriptorStorageImages, "maxPerStageDescriptorStorageImages");
  VkDevice dev = device.handle();
  try {
    VkShaderModuleCreateInfo module{VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO};
    module.codeSize = spirv.size_bytes();
    module.pCode = spirv.data();
    check(vkCreateShaderModule(dev, &module, nullptr, &module_), "vkCreateShaderModule");

    std::vector<VkDescriptorSetLayoutBinding> slots(count);
    for (uint32_t i = 0; i < count; ++i)
      slots[i] = {bindings_[i].number, bindings_[i].type, 1, VK_SHADER_STAGE_COMPUTE_BIT, nullptr};
    VkDescriptorSetLayoutCreateInfo set_layout{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
    set_layout.bindingCount = count;
    set_layout.pBindings = slots.data();
    check(vkCreateDescriptorSetLayout(dev, &set_layout, nullptr, &set_layout_),
          "vkCreateDescriptorSetLayout");

    VkPushConstantRange push{VK_SHADER_STAGE_COMPUTE_BIT, 0, push_size};
    VkPipelineLayoutCreateInfo layout{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
    layout.setLayoutCount = 1;
    layout.pSetLayouts = &set_layout_;
    layout.pushConstantRangeCount = push_size > 0 ? 1 : 0;
    layout.pPushConstantRanges = &push;
    check(vkCreatePipelineLayout(dev, &layout, nullptr, &layout_), "vkCreatePipelineLayout");

    VkComputePipelineCreateInfo pipeline{VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO};
    pipeline.stage = {VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO};
    pipeline.stage.stage = VK_SHADER_STAGE_COMPUTE_BIT;
    pipeline.stage.module = module_;
    pipeline.stage.pName = "main";
    std::vector<VkSpecializationMapEntry> entries(constants.size());
    for (uint32_t i = 0; i < entries.size(); ++i)
      entries[i] = {i, i * uint32_t(sizeof(uint32_t)), sizeof(uint32_t)};
    const VkSpecializationInfo specialization{uint32_t(entries.size()), entries.data(),
                                              constants.size() * sizeof(uint32_t),
                                              constants.data()};
    if (!constants.empty()) pipeline.stage.pSpecializationInfo = &specialization;
    pipeline.layout = layout_;
    check(vkCreateComputePipelines(dev, VK_NULL_HANDLE, 1, &pipeline, nullptr, &pipeline_),
          "vkCreateComputePipelines");

    std::vector<VkDescriptorPoolSize> sizes;
    for (const Binding& b : bindings_) {
      auto same =
          std::find_if(sizes.begin(), sizes.end(), [&](const auto& s) { return s.type == b.type; });
      if (same == sizes.end()) same = sizes.insert(sizes.end(), {b.type, 0});
      same->descriptorCount += max_sets;
    }
    if (sizes.empty()) sizes.push_back({VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1});
    VkDescriptorPoolCreateInfo pool{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
    pool.maxSets = max_sets;
    pool.poolSizeCount = uint32_t(sizes.size());
    pool.pPoolSizes = sizes.data();
    check(vkCreateDescriptorPool(dev, &pool, nullptr, &pool_), "vkCreateDescriptorPool");
  } catch (...) {
    destroy();
    throw;
  }
}

ComputePipeline::~ComputePipeline() { destroy(); }

void ComputePipeline::destroy() {
  VkDevice dev = device_.handle();
  for (VkBufferView view : views_) vkDestroyBufferView(dev, view, nullptr);
  views_.clear();
  if (pool_) vkDestroyDescriptorPool(dev, pool_, nullptr);  // frees its sets
  if (pipeline_) vkDestroyPipeline(dev, pipeline_, nullptr);
  if (layout_) vkDestroyPipelineLayout(dev, layout_, nullptr);
  if (set_layout_) vkDestroyDescriptorSetLayout(dev, set_layout_, nullptr);
  if (module_) vkDestroyShaderModule(dev, module_, nullptr);
  pool_ = VK_NULL_HANDLE;
  pipeline_ = VK_NULL_HANDLE;
  layout_ = VK_NULL_HANDLE;
  set_layout_ = VK_NULL_HANDLE;
  module_ = VK_NULL_HANDLE;
}

// Throws Error unless a buffer of `bytes` fits the device's limit for the binding's type.
void ComputePipeline::check_range(const Binding& binding, VkDeviceSize bytes) const {
  const VkPhysicalDeviceLimits& limits = device_.limits();
  const auto fail = [&](const char* what, VkDeviceSize size, VkDeviceSize most, const char* unit,
                        const char* limit) {
    throw Error(std::string("a ") + what + " of " + std::to_string(size) + " " + unit + "; " +
                device_.name() + " allows " + std::to_string(most) + " (" + limit + ")");
  };
  switch (binding.type) {
    case VK_DESCRIPTOR_TYPE_STORAGE_TEXEL_BUFFER:
      if (bytes < format_bytes(binding.texels))
        throw Error("a texel buffer of " + std::to_string(bytes) + " bytes holds no texel of " +
                    std::to_string(format_bytes(binding.texels)));
      if (bytes / format_bytes(binding.texels) > limits.maxTexelBufferElements)
        fail("texel buffer", bytes / format_bytes(binding.texels), limits.maxTexelBufferElements,
             "texels", "maxTexelBufferElements");
      break;
    default:
      if (bytes > limits.maxStorageBufferRange)
        fail("storage buffer", bytes, limits.maxStorageBufferRange, "bytes",
             "maxStorageBufferRange");
  }
}

VkDescriptorSet ComputePipeline::make_set(std::span<const Bound> bound) {
  // Each of the pipeline's bindings' buffer, found by its number.
  const size_t count = bindings_.size();
  std::vector<const Buffer*> buffers(count, nullptr);
  for (const Bound& b : bound) {
    const auto it = std::find_if(bindings_.begin(), bindings_.end(), [&](const Binding& binding) {
      return binding.number == b.binding;
    });
    if (it == bindings_.end())
      throw Error("compute pipeline: a buffer for binding " + std::to_string(b.binding) +
                  ", which it does not have");
    const Buffer*& slot = buffers[size_t(it - bindings_.begin())];
    if (slot)
      throw Error("compute pipeline: binding " + std::to_string(b.binding) + " given twice");
    slot = b.buffer;
  }
  for (size_t i = 0; i < count; ++i) {
    if (!buffers[i])
      throw Error("compute pipeline: no buffer for binding " + std::to_string(bindings_[i].number));
    check_range(bindings_[i], buffers[i]->size());
  }

  VkDescriptorSetAllocateInfo alloc{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO};
  alloc.descriptorPool = pool_;
  alloc.descriptorSetCount = 1;
  alloc.pSetLayouts = &set_layout_;
  VkDescriptorSet set = VK_NULL_HANDLE;
  check(vkAllocateDescriptorSets(device_.handle(), &alloc, &set),
        "vkAllocateDescriptorSets (more sets than the pipeline's max_sets?)");

  std::vector<VkDescriptorBufferInfo> infos(count);
  std::vector<VkBufferView> views(count, VK_NULL_HANDLE);
  std::vector<VkWriteDescriptorSet> writes(count);
  for (size_t i = 0; i < count; ++i) {
    writes[i] = {VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
    writes[i].dstSet = set;
    writes[i].dstBinding = bindings_[i].number;
    writes[i].descriptorCount = 1;
    writes[i].descriptorType = bindings_[i].type;
    if (bindings_[i].type == VK_DESCRIPTOR_TYPE_STORAGE_TEXEL_BUFFER) {
      VkBufferViewCreateInfo view{VK_STRUCTURE_TYPE_BUFFER_VIEW_CREATE_INFO};
      view.buffer = buffers[i]->handle();
      view.format = bindings_[i].texels;
      view.range = buffers[i]->size() / format_bytes(bindings_[i].texels) *
                   format_bytes(bindings_[i].texels);
      check(vkCreateBufferView(device_.handle(), &view, nullptr, &views[i]), "vkCreateBufferView");
      views_.push_back(views[i]);
      writes[i].pTexelBufferView = &views[i];
    } else {
      infos[i] = {buffers[i]->handle(), 0, VK_WHOLE_SIZE};
      writes[i].pBufferInfo = &infos[i];
    }
  }
  vkUpdateDescriptorSets(device_.handle(), uint32_t(count), writes.data(), 0, nullptr);
  return set;
}

void ComputePipeline::dispatch(VkCommandBuffer cmd, uint32_t groups_x, const void* push,
                               uint32_t push_size) const {
  if (!default_set_) throw Error("compute pipeline: dispatch before set_buffers");
  dispatch(cmd, default_set_, groups_x, push, push_size);
}

void ComputePipeline::dispatch(VkCommandBuffer cmd, VkDescriptorSet set, uint32_t groups_x,
                               const void* push, uint32_t push_size) const {
  if (push_size != push_size_ || (push_size > 0 && !push))
    throw Error("compute pipeline: push constants of " + std::to_string(push_size) +
                " bytes for a block of " + std::to_string(push_size_));
  check_groups(groups_x);
  if (groups_x == 0) return;
  vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline_);
  vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, layout_, 0, 1, &set, 0, nullptr);
  if (push_size > 0)
    vkCmdPushConstants(cmd, layout_, VK_SHADER_STAGE_COMPUTE_BIT, 0, push_size, push);
  vkCmdDispatch(cmd, groups_x, 1, 1);
}

void ComputePipeline::check_groups(uint32_t groups_x) const {
  const uint32_t max_groups = device_.limits().maxComputeWorkGroupCount[0];
  if (groups_x > max_groups)
    throw Error("compute dispatch of " + std::to_string(groups_x) + " work groups; " +
                device_.name() + " allows " + std::to_string(max_groups) +
                " (maxComputeWorkGroupCount[0])");
}

uint32_t group_count(uint64_t items, uint32_t local_size) {
  const uint64_t groups = (items + local_size - 1) / local_size;
  if (groups > UINT32_MAX) throw Error("group_count: " + std::to_string(items) + " items");
  return static_cast<uint32_t>(groups);
}

void check_group_count(const Device& device, uint64_t items, uint32_t local_size,
                       std::string_view what) {
  const uint64_t most_groups = device.limits().maxComputeWorkGroupCount[0];
  const uint64_t groups = (items + local_size - 1) / local_size;
  if (groups <= most_groups) return;
  throw Error(std::to_string(items) + " " + std::string(what) + " need " + std::to_string(groups) +
              " work groups of " + std::to_string(local_size) + " in one dispatch; " +
              device.name() + " allows " + std::to_string(most_groups) +
              " (maxComputeWorkGroupCount[0]): at most " +
              std::to_string(most_groups * local_size) + " " + std::string(what));
}

// --- Barriers and copies --------------------------------------------------------------------

namespace {

void memory_barrier(VkCommandBuffer cmd, VkPipelineStageFlags dst_stage, VkAccessFlags dst_access) {
  VkMemoryBarrier barrier{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
  barrier.srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_WRITE_BIT;
  barrier.dstAccessMask = dst_access;
  vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT,
                       dst_stage, 0, 1, &barrier, 0, nullptr, 0, nullptr);
}

}  // namespace

void barrier_to_compute(VkCommandBuffer cmd) {
  memory_barrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                 VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT);
}

void barrier_to_transfer(VkCommandBuffer cmd) {
  memory_barrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT,
                 VK_ACCESS_TRANSFER_READ_BIT | VK_ACCESS_TRANSFER_WRITE_BIT);
}

void barrier_to_host(VkCommandBuffer cmd) {
  memory_barrier(cmd, VK_PIPELINE_STAGE_HOST_BIT, VK_ACCESS_HOST_READ_BIT);
}

void copy_buffer(VkCommandBuffer cmd, const Buffer& src, const Buffer& dst, VkDeviceSize size,
                 VkDeviceSize src_offset, VkDeviceSize dst_offset) {
  if (src_offset + size > src.size() || dst_offset + size > dst.size())
    throw Error("copy_buffer: " + std::to_string(size) + " bytes out of range");
  VkBufferCopy region{src_offset, dst_offset, size};
  vkCmdCopyBuffer(cmd, src.handle(), dst.handle(), 1, &region);
}

void record_readback(VkCommandBuffer cmd, const Buffer& src, const Buffer& dst, VkDeviceSize size) {
  barrier_to_transfer(cmd);
  copy_buffer(cmd, src, dst, std::min({size, src.size(), dst.size()}));
  barrier_to_host(cmd);
}

// --- Submitter ------------------------------------------------------------------------------

Submitter::Submitter(const Device& device, uint32_t frames) : device_(device) {
  if (frames == 0) throw Error("Submitter with 0 frames");
  try {
    pool_ = device.create_command_pool();
    slots_.resize(frames);
    for (Slot& s : slots_) {
      s.cmd = device.allocate_command_buffer(pool_);
      s.fence = device.create_fence();
    }
    slot_ = frames - 1;  // begin() moves to slot 0
  } catch (...) {
    destroy();
    throw;
  }
}

Submitter::~Submitter() {
  try {
    wait_all();
  } catch (const Error&) {  // device lost: nothing left to wait for
  }
  destroy();
}

void Submitter::destroy() {
  VkDevice dev = device_.handle();
  for (Slot& s : slots_)
    if (s.fence) vkDestroyFence(dev, s.fence, nullptr);
  slots_.clear();
  if (pool_) vkDestroyCommandPool(dev, pool_, nullptr);  // frees its command buffers
  pool_ = VK_NULL_HANDLE;
}

void Submitter::submit(VkCommandBuffer cmd, VkFence fence) const {
  VkSubmitInfo submit{VK_STRUCTURE_TYPE_SUBMIT_INFO};
  submit.commandBufferCount = 1;
  submit.pCommandBuffers = &cmd;
  check(vkQueueSubmit(device_.queue(), 1, &submit, fence), "vkQueueSubmit");
}

void Submitter::run(const std::function<void(VkCommandBuffer)>& record) {
  VkDevice dev = device_.handle();
  VkCommandBuffer cmd = device_.allocate_command_buffer(pool_);
  VkFence fence = VK_NULL_HANDLE;
  bool submitted = false;
  try {
    fence = device_.create_fence();
    VkCommandBufferBeginInfo begin{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
    begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
    check(vkBeginCommandBuffer(cmd, &begin), "vkBeginCommandBuffer");
    record(cmd);
    check(vkEndCommandBuffer(cmd), "vkEndCommandBuffer");
    submit(cmd, fence);
    submitted = true;
    wait(fence);
  } catch (...) {
    if (submitted) vkQueueWaitIdle(device_.queue());  // only on failure
    if (fence) vkDestroyFence(dev, fence, nullptr);
    vkFreeCommandBuffers(dev, pool_, 1, &cmd);
    throw;
  }
  vkDestroyFence(dev, fence, nullptr);
  vkFreeCommandBuffers(dev, pool_, 1, &cmd);
}

VkCommandBuffer Submitter::begin() {
  if (recording_) throw Error("Submitter::begin() twice without submit()");
  slot_ = (slot_ + 1) % slots_.size();
  Slot& s = slots_[slot_];
  if (s.submitted) {
    wait(s.fence);
    check(vkResetFences(device_.handle(), 1, &s.fence), "vkResetFences");
    s.submitted = false;
  }
  check(vkResetCommandBuffer(s.cmd, 0), "vkResetCommandBuffer");
  VkCommandBufferBeginInfo begin{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
  begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
  check(vkBeginCommandBuffer(s.cmd, &begin), "vkBeginCommandBuffer");
  recording_ = true;
  return s.cmd;
}

VkFence Submitter::submit() {
  if (!recording_) throw Error("Submitter::submit() without begin()");
  Slot& s = slots_[slot_];
  recording_ = false;
  check(vkEndCommandBuffer(s.cmd), "vkEndCommandBuffer");
  submit(s.cmd, s.fence);
  s.submitted = true;
  return s.fence;
}

void Submitter::wait(VkFence fence) const {
  check(vkWaitForFences(device_.handle(), 1, &fence, VK_TRUE, UINT64_MAX), "vkWaitForFences");
}

void Submitter::wait_all() const {
  for (const Slot& s : slots_)
    if (s.submitted) wait(s.fence);
}

namespace {
// The bits of a timestamp the device's queue writes (0: it writes none).
uint32_t timestamp_bits(const Device& device) {
  uint32_t n = 0;
  vkGetPhysicalDeviceQueueFamilyProperties(device.physical(), &n, nullptr);
  std::vector<VkQueueFamilyProperties> families(n);
  vkGetPhysicalDeviceQueueFamilyProperties(device.physical(), &n, families.data());
  return device.queue_family() < n ? families[device.queue_family()].timestampValidBits : 0;
}
}  // namespace

bool Timestamps::supported(const Device& device) {
  return timestamp_bits(device) > 0 && device.limits().timestampPeriod > 0.0f;
}

Timestamps::Timestamps(const Device& device, uint32_t count) : device_(device) {
  const uint32_t bits = timestamp_bits(device);
  if (bits == 0 || device.limits().timestampPeriod <= 0.0f)
    throw Error(device.name() + " writes no timestamps on its queue");
  mask_ = bits >= 64 ? ~uint64_t(0) : (uint64_t(1) << bits) - 1;
  ns_per_tick_ = double(device.limits().timestampPeriod);
  VkQueryPoolCreateInfo info{VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO};
  info.queryType = VK_QUERY_TYPE_TIMESTAMP;
  info.queryCount = count;
  check(vkCreateQueryPool(device.handle(), &info, nullptr, &pool_), "vkCreateQueryPool");
}

Timestamps::~Timestamps() { vkDestroyQueryPool(device_.handle(), pool_, nullptr); }

void Timestamps::reset(VkCommandBuffer cmd, uint32_t n) { vkCmdResetQueryPool(cmd, pool_, 0, n); }

void Timestamps::write(VkCommandBuffer cmd, uint32_t query) {
  vkCmdWriteTimestamp(cmd, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, pool_, query);
}

std::vector<double> Timestamps::read_ns(uint32_t n) const {
  if (n == 0) return {};
  std::vector<uint64_t> ticks(n);
  check(vkGetQueryPoolResults(device_.handle(), pool_, 0, n, n * sizeof(uint64_t), ticks.data(),
                              sizeof(uint64_t), VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WAIT_BIT),
        "vkGetQueryPoolResults");
  std::vector<double> ns(n);
  for (uint32_t i = 0; i < n; ++i) ns[i] = double((ticks[i] - ticks[0]) & mask_) * ns_per_tick_;
  return ns;
}

}  // namespace aeroflock::gpu
