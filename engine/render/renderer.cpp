#include "render/renderer.h"

#include <array>
#include <cmath>
#include <cstring>
#include <map>
#include <optional>
#include <vector>

#include <glm/mat4x4.hpp>
#include <glm/vec2.hpp>
#include <glm/vec4.hpp>

#include "gpu/compute.h"
#include "gpu/error.h"
#include "gpu/image.h"
#include "gpu/layout.h"
#include "gpu/shaders.h"
#include "render/meshes.h"

namespace aeroflock::render {
namespace {

using gpu::Buffer;
using gpu::check;
using gpu::Memory;

using gpu::FrameConstants;
using gpu::PoseConstants;

// What the draws read (host_device.h): the targets and branches, each bird's pose and the draw
// lists, the mesh drawn, the route lines.
constexpr std::array<uint32_t, 6> kDrawBindings = {gpu::kBindingTargets, gpu::kBindingBranches,
                                                   gpu::kBindingPoses,   gpu::kBindingDrawLists,
                                                   gpu::kBindingMesh,    gpu::kBindingSegments};
constexpr uint32_t kMaxTargets = 2048;  // vkCmdUpdateBuffer writes at most 65536 bytes
constexpr VkFormat kDepthFormat = VK_FORMAT_D32_SFLOAT;
constexpr float kDetailPixels = 32.0f;  // narrower birds are drawn with a few triangles
constexpr float kMinPixels = 2.5f;      // no bird is drawn narrower: a far one is a soft dot
constexpr uint32_t kDrawLists = 3;      // the birds' draws: detailed, distant, tiny (pose.comp)
constexpr int kRingVertices = 128;      // a target's ring: 64 line segments
// The haze: what the camera looks at (View::scene_distance) is 5 % hazed, ten times as far 40 %.
constexpr float kHazeAtSubject = 0.05f;
constexpr float kMinHazeDistance = 2000.0f;  // cm: close-ups are hazed as a scene this large
const glm::vec3 kSun = glm::normalize(glm::vec3(0.55f, 0.5f, 0.4f));  // 36 deg high

// The most samples a pixel up to `wanted` that the device draws colour and depth with.
VkSampleCountFlagBits sample_count(const gpu::Device& device, uint32_t wanted) {
  const VkSampleCountFlags both =
      device.limits().framebufferColorSampleCounts & device.limits().framebufferDepthSampleCounts;
  uint32_t n = 8;
  while (n > 1 && (n > wanted || !(both & n))) n /= 2;
  return VkSampleCountFlagBits(n);
}

template <class T>
Buffer buffer_of(const gpu::Device& device, const std::vector<T>& items) {
  Buffer b(device, std::max<size_t>(items.size(), 1) * sizeof(T), Memory::device_local);
  if (!items.empty()) b.upload(std::as_bytes(std::span<const T>(items)));
  return b;
}

VkShaderModule shader_module(VkDevice device, std::string_view name) {
  const std::span<const uint32_t> words = gpu::shader_spirv(name);
  VkShaderModuleCreateInfo info{VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO};
  info.codeSize = words.size_bytes();
  info.pCode = words.data();
  VkShaderModule module = VK_NULL_HANDLE;
  check(vkCreateShaderModule(device, &info, nullptr, &module), "vkCreateShaderModule");
  return module;
}

// How one of the pipelines draws.
struct PipelineSpec {
  std::string_view vertex, fragment;
  uint32_t kind = 0;  // solid.vert's specialisation: 0 target rings, 1 branches, 2 routes, 3 posts
  bool depth_write = true;
  VkCompareOp depth_compare = VK_COMPARE_OP_LESS;
  bool blend = false;
  VkPrimitiveTopology topology = VK_PRIMITIVE_TOPOLOGY_TRIANGLE_LIST;
};

// The routes as pairs of target indices: one line from each target to the next.
std::vector<glm::uvec2> route_segments(const World& world) {
  std::vector<glm::uvec2> out;
  for (const Route& r : world.routes) {
    for (size_t i = 1; i < r.targets.size(); ++i) out.push_back({r.targets[i - 1], r.targets[i]});
    if (r.loop && r.targets.size() > 2) out.push_back({r.targets.back(), r.targets.front()});
  }
  return out;
}

}  // namespace

struct Renderer::Impl {
  const gpu::Device& device;
  VkFormat format;
  VkExtent2D extent;
  // Buffers the renderer owns: species, targets now, branches, meshes, route lines.
  Buffer species, targets, branches, bird_mesh, box, segments;
  uint32_t bird_vertices, distant_vertices, tiny_vertices, box_vertices, target_count, branch_count,
      segment_count;
  float ground_height;
  // Each bird's pose for drawing, computed once a frame by pose.comp.
  std::unique_ptr<Buffer> poses, lists, draws;
  uint32_t pose_capacity = 0;
  gpu::ComputePipeline pose_pipeline;
  std::map<VkBuffer, VkDescriptorSet> pose_sets;  // by bird buffer
  gpu::Image depth;
  VkDescriptorSetLayout set_layout = VK_NULL_HANDLE;
  VkPipelineLayout layout = VK_NULL_HANDLE;
  VkDescriptorPool pool = VK_NULL_HANDLE;
  std::map<VkImageLayout, VkRenderPass> passes;  // by final layout
  // The draws' pipelines, one set of them per final layout of the image drawn.
  struct Pipelines {
    VkPipeline sky, birds, branches, rings, routes, posts, shadows;
    std::array<VkPipeline, 7> all() const {
      return {sky, birds, branches, rings, routes, posts, shadows};
    }
  };
  std::map<VkImageLayout, Pipelines> pipelines;
  VkSampleCountFlagBits samples;
  std::unique_ptr<gpu::Image> color;  // multisampled, resolved into the caller's image
  std::map<std::pair<VkImageView, VkImageLayout>, VkFramebuffer> framebuffers;
  // The draws' descriptor sets, by the mesh they read (draw_sets): the bird's (sky, shadows and
  // birds), the box's (branches and posts), and the box's again for the lines of routes and
  // rings, which read no mesh.
  struct DrawSets {
    VkDescriptorSet birds, boxes, lines;
  };
  std::optional<DrawSets> sets;

  Impl(const gpu::Device& d, const Scenario& scenario, VkFormat f, VkExtent2D e, uint32_t msaa)
      : device(d),
        format(f),
        extent(e),
        species(buffer_of(d,
                          [&] {
                            std::vector<gpu::GpuSpecies> out;
                            for (const Species& s : scenario.species) out.push_back(gpu::pack(s));
                            return out;
                          }())),
        targets(d, kMaxTargets * sizeof(gpu::GpuTarget), Memory::device_local),
        branches(buffer_of(d, gpu::pack(scenario.world).branches)),
        bird_mesh(buffer_of(d,
                            [] {
                              std::vector<MeshVertex> all = render::bird_mesh(),
                                                      distant = distant_bird_mesh(),
                                                      tiny = tiny_bird_mesh();
                              all.insert(all.end(), distant.begin(), distant.end());
                              all.insert(all.end(), tiny.begin(), tiny.end());
                              return all;
                            }())),
        box(buffer_of(d, box_mesh())),
        segments(buffer_of(d, route_segments(scenario.world))),
        bird_vertices(uint32_t(render::bird_mesh().size())),
        distant_vertices(uint32_t(distant_bird_mesh().size())),
        tiny_vertices(uint32_t(tiny_bird_mesh().size())),
        box_vertices(uint32_t(box_mesh().size())),
        target_count(uint32_t(std::min<size_t>(scenario.world.targets.size(), kMaxTargets))),
        branch_count(uint32_t(scenario.world.branches.size())),
        segment_count(uint32_t(route_segments(scenario.world).size())),
        ground_height(float(scenario.world.ground_height)),
        pose_pipeline(d, gpu::shader_spirv("pose"),
                      {gpu::kBindingBirds, gpu::kBindingSpecies, gpu::kBindingPoses,
                       gpu::kBindingDrawLists, gpu::kBindingDraws},
                      sizeof(PoseConstants), 16),
        depth(d, e, kDepthFormat, VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT,
              VK_IMAGE_ASPECT_DEPTH_BIT, sample_count(d, msaa)),
        samples(sample_count(d, msaa)) {
    if (samples != VK_SAMPLE_COUNT_1_BIT)
      color = std::make_unique<gpu::Image>(
          d, e, f, VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSIENT_ATTACHMENT_BIT,
          VK_IMAGE_ASPECT_COLOR_BIT, samples);
    create_layouts();
  }

  ~Impl() {
    VkDevice dev = device.handle();
    vkDeviceWaitIdle(dev);
    for (auto& [key, fb] : framebuffers) vkDestroyFramebuffer(dev, fb, nullptr);
    for (auto& [key, list] : pipelines)
      for (VkPipeline p : list.all()) vkDestroyPipeline(dev, p, nullptr);
    for (auto& [key, pass] : passes) vkDestroyRenderPass(dev, pass, nullptr);
    vkDestroyDescriptorPool(dev, pool, nullptr);
    vkDestroyPipelineLayout(dev, layout, nullptr);
    vkDestroyDescriptorSetLayout(dev, set_layout, nullptr);
  }

  void create_layouts() {
    VkDevice dev = device.handle();
    std::array<VkDescriptorSetLayoutBinding, kDrawBindings.size()> bindings{};
    for (uint32_t i = 0; i < kDrawBindings.size(); ++i) {
      bindings[i].binding = kDrawBindings[i];
      bindings[i].descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
      bindings[i].descriptorCount = 1;
      bindings[i].stageFlags = VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT;
    }
    VkDescriptorSetLayoutCreateInfo set{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
    set.bindingCount = uint32_t(kDrawBindings.size());
    set.pBindings = bindings.data();
    check(vkCreateDescriptorSetLayout(dev, &set, nullptr, &set_layout),
          "vkCreateDescriptorSetLayout");
    VkPushConstantRange push{VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT, 0,
                             sizeof(FrameConstants)};
    VkPipelineLayoutCreateInfo info{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
    info.setLayoutCount = 1;
    info.pSetLayouts = &set_layout;
    info.pushConstantRangeCount = 1;
    info.pPushConstantRanges = &push;
    check(vkCreatePipelineLayout(dev, &info, nullptr, &layout), "vkCreatePipelineLayout");
    VkDescriptorPoolSize size{VK_DESCRIPTOR_TYPE_STORAGE_BUFFER,
                              uint32_t(4 * kDrawBindings.size())};
    VkDescriptorPoolCreateInfo pool_info{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
    pool_info.maxSets = 4;
    pool_info.poolSizeCount = 1;
    pool_info.pPoolSizes = &size;
    check(vkCreateDescriptorPool(dev, &pool_info, nullptr, &pool), "vkCreateDescriptorPool");
  }

  VkRenderPass pass(VkImageLayout final_layout) {
    if (auto it = passes.find(final_layout); it != passes.end()) return it->second;
    // 0 the colour drawn (multisampled, or the caller's image), 1 depth, 2 the caller's image
    // the samples are resolved into.
    const bool resolve = samples != VK_SAMPLE_COUNT_1_BIT;
    std::array<VkAttachmentDescription, 3> attachments{};
    attachments[0].format = format;
    attachments[0].samples = samples;
    attachments[0].loadOp = VK_ATTACHMENT_LOAD_OP_DONT_CARE;  // the sky covers every pixel
    attachments[0].storeOp = VK_ATTACHMENT_STORE_OP_STORE;
    attachments[0].stencilLoadOp = VK_ATTACHMENT_LOAD_OP_DONT_CARE;
    attachments[0].stencilStoreOp = VK_ATTACHMENT_STORE_OP_DONT_CARE;
    attachments[0].initialLayout = VK_IMAGE_LAYOUT_UNDEFINED;
    attachments[0].finalLayout = final_layout;
    attachments[2] = attachments[0];
    attachments[2].samples = VK_SAMPLE_COUNT_1_BIT;
    if (resolve) {
      attachments[0].storeOp = VK_ATTACHMENT_STORE_OP_DONT_CARE;
      attachments[0].finalLayout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL;
    }
    attachments[1] = attachments[0];
    attachments[1].format = kDepthFormat;
    attachments[1].loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR;
    attachments[1].storeOp = VK_ATTACHMENT_STORE_OP_DONT_CARE;
    attachments[1].finalLayout = VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL;
    VkAttachmentReference color{0, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL};
    VkAttachmentReference depth{1, VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL};
    VkAttachmentReference resolved{2, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL};
    VkSubpassDescription subpass{};
    subpass.pipelineBindPoint = VK_PIPELINE_BIND_POINT_GRAPHICS;
    subpass.colorAttachmentCount = 1;
    subpass.pColorAttachments = &color;
    if (resolve) subpass.pResolveAttachments = &resolved;
    subpass.pDepthStencilAttachment = &depth;
    // Earlier work on the attachments (the previous frame, a present) before this frame's writes;
    // this frame's writes before whatever reads the image next (copies, presentation).
    std::array<VkSubpassDependency, 2> deps{};
    deps[0].srcSubpass = VK_SUBPASS_EXTERNAL;
    deps[0].dstSubpass = 0;
    deps[0].srcStageMask = VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT |
                           VK_PIPELINE_STAGE_LATE_FRAGMENT_TESTS_BIT |
                           VK_PIPELINE_STAGE_TRANSFER_BIT;
    deps[0].dstStageMask =
        VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT | VK_PIPELINE_STAGE_EARLY_FRAGMENT_TESTS_BIT;
    deps[0].srcAccessMask = VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT |
                            VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT |
                            VK_ACCESS_TRANSFER_READ_BIT;
    deps[0].dstAccessMask =
        VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT | VK_ACCESS_COLOR_ATTACHMENT_READ_BIT |
        VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT | VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_READ_BIT;
    deps[1].srcSubpass = 0;
    deps[1].dstSubpass = VK_SUBPASS_EXTERNAL;
    deps[1].srcStageMask = VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT;
    deps[1].dstStageMask = VK_PIPELINE_STAGE_TRANSFER_BIT | VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT;
    deps[1].srcAccessMask = VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT;
    deps[1].dstAccessMask = VK_ACCESS_TRANSFER_READ_BIT;
    VkRenderPassCreateInfo info{VK_STRUCTURE_TYPE_RENDER_PASS_CREATE_INFO};
    info.attachmentCount = resolve ? 3 : 2;
    info.pAttachments = attachments.data();
    info.subpassCount = 1;
    info.pSubpasses = &subpass;
    info.dependencyCount = 2;
    info.pDependencies = deps.data();
    VkRenderPass result = VK_NULL_HANDLE;
    check(vkCreateRenderPass(device.handle(), &info, nullptr, &result), "vkCreateRenderPass");
    passes[final_layout] = result;
    return result;
  }

  VkPipeline make_pipeline(VkRenderPass render_pass, const PipelineSpec& spec) {
    VkDevice dev = device.handle();
    VkShaderModule vert = shader_module(dev, spec.vertex), frag = shader_module(dev, spec.fragment);
    VkSpecializationMapEntry entry{0, 0, sizeof(uint32_t)};
    VkSpecializationInfo specialization{1, &entry, sizeof(uint32_t), &spec.kind};
    std::array<VkPipelineShaderStageCreateInfo, 2> stages{};
    stages[0].sType = stages[1].sType = VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO;
    stages[0].stage = VK_SHADER_STAGE_VERTEX_BIT;
    stages[0].module = vert;
    stages[0].pName = "main";
    stages[0].pSpecializationInfo = &specialization;
    stages[1].stage = VK_SHADER_STAGE_FRAGMENT_BIT;
    stages[1].module = frag;
    stages[1].pName = "main";
    VkPipelineVertexInputStateCreateInfo input{
        VK_STRUCTURE_TYPE_PIPELINE_VERTEX_INPUT_STATE_CREATE_INFO};
    VkPipelineInputAssemblyStateCreateInfo assembly{
        VK_STRUCTURE_TYPE_PIPELINE_INPUT_ASSEMBLY_STATE_CREATE_INFO};
    assembly.topology = spec.topology;
    VkPipelineViewportStateCreateInfo viewport{
        VK_STRUCTURE_TYPE_PIPELINE_VIEWPORT_STATE_CREATE_INFO};
    viewport.viewportCount = 1;
    viewport.scissorCount = 1;
    VkPipelineRasterizationStateCreateInfo raster{
        VK_STRUCTURE_TYPE_PIPELINE_RASTERIZATION_STATE_CREATE_INFO};
    raster.polygonMode = VK_POLYGON_MODE_FILL;
    raster.cullMode = VK_CULL_MODE_NONE;
    raster.frontFace = VK_FRONT_FACE_COUNTER_CLOCKWISE;
    raster.lineWidth = 1.0f;
    VkPipelineMultisampleStateCreateInfo multisample{
        VK_STRUCTURE_TYPE_PIPELINE_MULTISAMPLE_STATE_CREATE_INFO};
    multisample.rasterizationSamples = samples;
    VkPipelineDepthStencilStateCreateInfo depth{
        VK_STRUCTURE_TYPE_PIPELINE_DEPTH_STENCIL_STATE_CREATE_INFO};
    depth.depthTestEnable = VK_TRUE;
    depth.depthWriteEnable = spec.depth_write;
    depth.depthCompareOp = spec.depth_compare;
    VkPipelineColorBlendAttachmentState attachment{};
    attachment.colorWriteMask = VK_COLOR_COMPONENT_R_BIT | VK_COLOR_COMPONENT_G_BIT |
                                VK_COLOR_COMPONENT_B_BIT | VK_COLOR_COMPONENT_A_BIT;
    if (spec.blend) {
      attachment.blendEnable = VK_TRUE;
      attachment.srcColorBlendFactor = VK_BLEND_FACTOR_SRC_ALPHA;
      attachment.dstColorBlendFactor = VK_BLEND_FACTOR_ONE_MINUS_SRC_ALPHA;
      attachment.colorBlendOp = VK_BLEND_OP_ADD;
      attachment.srcAlphaBlendFactor = VK_BLEND_FACTOR_ONE;
      attachment.dstAlphaBlendFactor = VK_BLEND_FACTOR_ONE_MINUS_SRC_ALPHA;
      attachment.alphaBlendOp = VK_BLEND_OP_ADD;
    }
    VkPipelineColorBlendStateCreateInfo blend{
        VK_STRUCTURE_TYPE_PIPELINE_COLOR_BLEND_STATE_CREATE_INFO};
    blend.attachmentCount = 1;
    blend.pAttachments = &attachment;
    const std::array<VkDynamicState, 2> dynamic_states = {VK_DYNAMIC_STATE_VIEWPORT,
                                                          VK_DYNAMIC_STATE_SCISSOR};
    VkPipelineDynamicStateCreateInfo dynamic{VK_STRUCTURE_TYPE_PIPELINE_DYNAMIC_STATE_CREATE_INFO};
    dynamic.dynamicStateCount = uint32_t(dynamic_states.size());
    dynamic.pDynamicStates = dynamic_states.data();
    VkGraphicsPipelineCreateInfo info{VK_STRUCTURE_TYPE_GRAPHICS_PIPELINE_CREATE_INFO};
    info.stageCount = 2;
    info.pStages = stages.data();
    info.pVertexInputState = &input;
    info.pInputAssemblyState = &assembly;
    info.pViewportState = &viewport;
    info.pRasterizationState = &raster;
    info.pMultisampleState = &multisample;
    info.pDepthStencilState = &depth;
    info.pColorBlendState = &blend;
    info.pDynamicState = &dynamic;
    info.layout = layout;
    info.renderPass = render_pass;
    VkPipeline pipeline = VK_NULL_HANDLE;
    const VkResult r = vkCreateGraphicsPipelines(dev, VK_NULL_HANDLE, 1, &info, nullptr, &pipeline);
    vkDestroyShaderModule(dev, vert, nullptr);
    vkDestroyShaderModule(dev, frag, nullptr);
    check(r, "vkCreateGraphicsPipelines");
    return pipeline;
  }

  const Pipelines& pipelines_for(VkImageLayout final_layout) {
    if (auto it = pipelines.find(final_layout); it != pipelines.end()) return it->second;
    VkRenderPass rp = pass(final_layout);
    constexpr VkPrimitiveTopology kLines = VK_PRIMITIVE_TOPOLOGY_LINE_LIST;
    Pipelines list;
    list.sky = make_pipeline(rp, {"sky_vert", "sky_frag", 0, true, VK_COMPARE_OP_ALWAYS, false});
    list.birds = make_pipeline(rp, {"bird_vert", "bird_frag", 0, true, VK_COMPARE_OP_LESS, false});
    list.branches =
        make_pipeline(rp, {"solid_vert", "solid_frag", 1, true, VK_COMPARE_OP_LESS, false});
    list.rings =
        make_pipeline(rp, {"solid_vert", "solid_frag", 0, false, VK_COMPARE_OP_LESS, true, kLines});
    list.routes =
        make_pipeline(rp, {"solid_vert", "solid_frag", 2, false, VK_COMPARE_OP_LESS, true, kLines});
    list.posts =
        make_pipeline(rp, {"solid_vert", "solid_frag", 3, true, VK_COMPARE_OP_LESS, false});
    // Shadows lie on the ground, under everything but the ground itself.
    list.shadows =
        make_pipeline(rp, {"shadow_vert", "shadow_frag", 0, false, VK_COMPARE_OP_ALWAYS, true});
    return pipelines[final_layout] = list;
  }

  VkFramebuffer framebuffer(VkImageView view, VkImageLayout final_layout) {
    const auto key = std::make_pair(view, final_layout);
    if (auto it = framebuffers.find(key); it != framebuffers.end()) return it->second;
    const std::array<VkImageView, 3> views = {color ? color->view() : view, depth.view(), view};
    VkFramebufferCreateInfo info{VK_STRUCTURE_TYPE_FRAMEBUFFER_CREATE_INFO};
    info.renderPass = pass(final_layout);
    info.attachmentCount = color ? 3 : 2;
    info.pAttachments = views.data();
    info.width = extent.width;
    info.height = extent.height;
    info.layers = 1;
    VkFramebuffer fb = VK_NULL_HANDLE;
    check(vkCreateFramebuffer(device.handle(), &info, nullptr, &fb), "vkCreateFramebuffer");
    return framebuffers[key] = fb;
  }

  // Makes room for `count` poses; the descriptor sets that name the old buffer go.
  void reserve_poses(uint32_t count) {
    if (count <= pose_capacity && poses) return;
    vkDeviceWaitIdle(device.handle());
    pose_capacity = std::max({count, 2 * pose_capacity, 1024u});
    poses = std::make_unique<Buffer>(device, VkDeviceSize(pose_capacity) * sizeof(gpu::Pose),
                                     Memory::device_local);
    lists = std::make_unique<Buffer>(
        device, VkDeviceSize(pose_capacity) * kDrawLists * sizeof(uint32_t), Memory::device_local);
    draws = std::make_unique<Buffer>(device, kDrawLists * sizeof(VkDrawIndirectCommand),
                                     Memory::device_local);
    check(vkResetDescriptorPool(device.handle(), pool, 0), "vkResetDescriptorPool");
    sets.reset();
    pose_sets.clear();
  }

  VkDescriptorSet pose_set_for(const Buffer& birds) {
    if (auto it = pose_sets.find(birds.handle()); it != pose_sets.end()) return it->second;
    return pose_sets[birds.handle()] =
               pose_pipeline.make_set({{gpu::kBindingBirds, &birds},
                                       {gpu::kBindingSpecies, &species},
                                       {gpu::kBindingPoses, poses.get()},
                                       {gpu::kBindingDrawLists, lists.get()},
                                       {gpu::kBindingDraws, draws.get()}});
  }

  // A set of the draws' layout (kDrawBindings) reading `mesh`.
  VkDescriptorSet draw_set(const Buffer& mesh) {
    VkDescriptorSetAllocateInfo alloc{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO};
    alloc.descriptorPool = pool;
    alloc.descriptorSetCount = 1;
    alloc.pSetLayouts = &set_layout;
    VkDescriptorSet set = VK_NULL_HANDLE;
    check(vkAllocateDescriptorSets(device.handle(), &alloc, &set), "vkAllocateDescriptorSets");
    const std::array<gpu::Bound, kDrawBindings.size()> bound = {
        {{gpu::kBindingTargets, &targets},
         {gpu::kBindingBranches, &branches},
         {gpu::kBindingPoses, poses.get()},
         {gpu::kBindingDrawLists, lists.get()},
         {gpu::kBindingMesh, &mesh},
         {gpu::kBindingSegments, &segments}}};
    std::array<VkDescriptorBufferInfo, kDrawBindings.size()> infos{};
    std::array<VkWriteDescriptorSet, kDrawBindings.size()> writes{};
    for (size_t i = 0; i < bound.size(); ++i) {
      infos[i] = {bound[i].buffer->handle(), 0, VK_WHOLE_SIZE};
      writes[i] = {VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
      writes[i].dstSet = set;
      writes[i].dstBinding = bound[i].binding;
      writes[i].descriptorCount = 1;
      writes[i].descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
      writes[i].pBufferInfo = &infos[i];
    }
    vkUpdateDescriptorSets(device.handle(), uint32_t(writes.size()), writes.data(), 0, nullptr);
    return set;
  }

  const DrawSets& draw_sets() {
    if (!sets) sets = DrawSets{draw_set(bird_mesh), draw_set(box), draw_set(box)};
    return *sets;
  }
};

glm::vec3 sun_direction() { return kSun; }

Renderer::Renderer(const gpu::Device& device, const Scenario& scenario, VkFormat color_format,
                   VkExtent2D extent, uint32_t msaa)
    : impl_(std::make_unique<Impl>(device, scenario, color_format, extent, msaa)) {}

uint32_t Renderer::samples() const { return uint32_t(impl_->samples); }

bool is_cpu_device(const gpu::Device& device) {
  VkPhysicalDeviceProperties properties;
  vkGetPhysicalDeviceProperties(device.physical(), &properties);
  return properties.deviceType == VK_PHYSICAL_DEVICE_TYPE_CPU;
}

uint32_t default_msaa(const gpu::Device& device, bool interactive) {
  return interactive && is_cpu_device(device) ? 1 : 4;
}

Renderer::~Renderer() = default;

VkExtent2D Renderer::extent() const { return impl_->extent; }
VkFormat Renderer::format() const { return impl_->format; }

void Renderer::record(VkCommandBuffer cmd, VkImage /*color*/, VkImageView color_view,
                      const gpu::Buffer& birds, uint32_t bird_count, const World& world,
                      const View& view, VkImageLayout final_layout) {
  Impl& r = *impl_;
  r.reserve_poses(bird_count);
  const auto& pipelines = r.pipelines_for(final_layout);
  const auto& sets = r.draw_sets();

  // The previous frame's reads of the buffers written below are done before they are written.
  vkCmdPipelineBarrier(cmd,
                       VK_PIPELINE_STAGE_DRAW_INDIRECT_BIT | VK_PIPELINE_STAGE_VERTEX_SHADER_BIT |
                           VK_PIPELINE_STAGE_FRAGMENT_SHADER_BIT |
                           VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                       VK_PIPELINE_STAGE_TRANSFER_BIT | VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, 0, 0,
                       nullptr, 0, nullptr, 0, nullptr);
  // Each bird's pose, once, and into the detailed or the distant draw by its size on screen
  // (after the simulation's writes to the birds).
  const std::array<VkDrawIndirectCommand, kDrawLists> empty_draws = {
      VkDrawIndirectCommand{r.bird_vertices, 0, 0, 0},
      VkDrawIndirectCommand{r.distant_vertices, 0, r.bird_vertices, 0},
      VkDrawIndirectCommand{r.tiny_vertices, 0, r.bird_vertices + r.distant_vertices, 0}};
  vkCmdUpdateBuffer(cmd, r.draws->handle(), 0, sizeof empty_draws, empty_draws.data());
  gpu::barrier_to_compute(cmd);
  // Everything is drawn from the eye (host_device.h: FrameConstants).
  const glm::dvec3 eye_world = view.camera.eye_world();
  const gpu::Tiled tile = gpu::tiled(eye_world);
  const glm::vec4 eye_in_tile(glm::vec3(eye_world - tile.centre), view.time);
  const Camera camera = view.camera.from(eye_world);
  const float focal_pixels = 0.5f * float(r.extent.height) / std::tan(0.5f * camera.fov_y);
  const PoseConstants pose{eye_in_tile,
                           bird_count,
                           r.pose_capacity,
                           focal_pixels / kDetailPixels,
                           tile.tile.x,
                           tile.tile.y,
                           kMinPixels / focal_pixels,
                           view.tiny_pixels > 0.0f ? focal_pixels / view.tiny_pixels : 0.0f,
                           r.ground_height};
  if (bird_count > 0)
    r.pose_pipeline.dispatch(cmd, r.pose_set_for(birds),
                             gpu::group_count(bird_count, gpu::kWorkgroupSize), &pose, sizeof pose);

  // The targets where they are now, written in the command stream (no host race with frames in
  // flight); then every earlier write (compute, transfer) before the vertex shaders read.
  if (r.target_count > 0) {
    std::vector<gpu::GpuTarget> placed(r.target_count);
    for (uint32_t i = 0; i < r.target_count; ++i)
      placed[i] =
          gpu::pack_target(world.targets[i], world.target_now.size() > i ? world.target_now[i]
                                                                         : world.targets[i].centre);
    vkCmdUpdateBuffer(cmd, r.targets.handle(), 0, placed.size() * sizeof(gpu::GpuTarget),
                      placed.data());
  }
  VkMemoryBarrier barrier{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
  barrier.srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_WRITE_BIT;
  barrier.dstAccessMask = VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_INDIRECT_COMMAND_READ_BIT;
  vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT,
                       VK_PIPELINE_STAGE_DRAW_INDIRECT_BIT | VK_PIPELINE_STAGE_VERTEX_SHADER_BIT |
                           VK_PIPELINE_STAGE_FRAGMENT_SHADER_BIT,
                       0, 1, &barrier, 0, nullptr, 0, nullptr);

  VkClearValue clears[2] = {};
  clears[1].depthStencil = {1.0f, 0};
  VkRenderPassBeginInfo begin{VK_STRUCTURE_TYPE_RENDER_PASS_BEGIN_INFO};
  begin.renderPass = r.pass(final_layout);
  begin.framebuffer = r.framebuffer(color_view, final_layout);
  begin.renderArea = {{0, 0}, r.extent};
  begin.clearValueCount = 2;
  begin.pClearValues = clears;
  vkCmdBeginRenderPass(cmd, &begin, VK_SUBPASS_CONTENTS_INLINE);
  const VkViewport viewport{0, 0, float(r.extent.width), float(r.extent.height), 0, 1};
  const VkRect2D scissor{{0, 0}, r.extent};
  vkCmdSetViewport(cmd, 0, 1, &viewport);
  vkCmdSetScissor(cmd, 0, 1, &scissor);

  FrameConstants frame{};
  frame.view_projection = camera.view_projection(float(r.extent.width) / float(r.extent.height));
  frame.eye = eye_in_tile;
  frame.tile_x = tile.tile.x;
  frame.tile_z = tile.tile.y;
  const float haze =
      -std::log(1.0f - kHazeAtSubject) / std::max(view.scene_distance, kMinHazeDistance);
  frame.sun = glm::vec4(kSun, haze);
  frame.fog_color = glm::vec4(0.72f, 0.80f, 0.88f, r.ground_height);
  vkCmdPushConstants(cmd, r.layout, VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT, 0,
                     sizeof frame, &frame);
  auto draw = [&](VkPipeline pipeline, VkDescriptorSet set, uint32_t vertices, uint32_t instances) {
    if (instances == 0) return;
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pipeline);
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, r.layout, 0, 1, &set, 0, nullptr);
    vkCmdDraw(cmd, vertices, instances, 0, 0);
  };
  draw(pipelines.sky, sets.birds, 3, 1);  // sky and ground
  // The birds' shadows: of every bird, or of every shadow_stride-th.
  const uint32_t casters = view.shadow_casters > 0 ? view.shadow_casters : std::max(bird_count, 1u);
  frame.shadow_stride = std::max(1u, (bird_count + casters - 1) / casters);
  vkCmdPushConstants(cmd, r.layout, VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT, 0,
                     sizeof frame, &frame);
  draw(pipelines.shadows, sets.birds,
       6 * ((bird_count + frame.shadow_stride - 1) / frame.shadow_stride), bird_count > 0 ? 1 : 0);
  // The flock: the detailed birds, then the distant ones, then the tiny ones, as the pose pass
  // sorted them.
  if (bird_count > 0) {
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pipelines.birds);
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, r.layout, 0, 1, &sets.birds, 0,
                            nullptr);
    for (uint32_t list = 0; list < kDrawLists; ++list) {
      frame.list_offset = list * r.pose_capacity;
      vkCmdPushConstants(cmd, r.layout, VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT,
                         0, sizeof frame, &frame);
      vkCmdDrawIndirect(cmd, r.draws->handle(), list * sizeof(VkDrawIndirectCommand), 1, 0);
    }
  }
  draw(pipelines.branches, sets.boxes, r.box_vertices, r.branch_count);
  draw(pipelines.posts, sets.boxes, r.box_vertices, r.branch_count);  // the posts they are on
  if (view.show_targets) {
    draw(pipelines.routes, sets.lines, 2, r.segment_count);
    draw(pipelines.rings, sets.lines, kRingVertices, r.target_count);  // a ring round each target
  }
  vkCmdEndRenderPass(cmd);
}

}  // namespace aeroflock::render
