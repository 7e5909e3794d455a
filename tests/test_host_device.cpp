// host_device.h is one declaration compiled twice, as C++ and as GLSL: the layouts glslang gives
// the shaders (the Offset and ArrayStride decorations of the embedded SPIR-V) must be the C++
// layouts, member by member for the lists in engine/model/*.def and in size for every buffer's
// element. Needs no device.
#include <gtest/gtest.h>

#include <cstddef>
#include <cstdint>
#include <map>
#include <span>
#include <string>
#include <vector>

#include "gpu/host_device.h"
#include "gpu/layout.h"
#include "gpu/shaders.h"

namespace aeroflock::gpu {
namespace {

// What the tests need of a SPIR-V module: struct member offsets and array strides, by name.
class SpirvLayouts {
 public:
  explicit SpirvLayouts(std::span<const uint32_t> words) {
    for (size_t i = 5; i < words.size();) {
      const uint32_t count = words[i] >> 16, op = words[i] & 0xffffu;
      if (count == 0 || i + count > words.size()) break;
      const std::span<const uint32_t> w = words.subspan(i, count);
      switch (op) {
        case 5:  // OpName id "name"
          names_[w[1]] = text(w.subspan(2));
          break;
        case 6:  // OpMemberName type member "name"
          member_names_[w[1]][w[2]] = text(w.subspan(3));
          break;
        case 71:  // OpDecorate id ArrayStride(6) stride, or SpecId(1) constant_id
          if (w[2] == 6) strides_[w[1]] = w[3];
          if (w[2] == 1) spec_ids_[w[1]] = w[3];
          break;
        case 72:  // OpMemberDecorate type member Offset(35) offset
          if (w[3] == 35) offsets_[w[1]][member_names_[w[1]][w[2]]] = w[4];
          break;
        case 28:  // OpTypeArray result element length
        case 29:  // OpTypeRuntimeArray result element
          element_[w[1]] = w[2];
          break;
        default:
          break;
      }
      i += count;
    }
  }

  // The member offsets of the struct `name` as laid out in a buffer (the type that has offsets).
  std::map<std::string, uint32_t> offsets(const std::string& name) const {
    for (const auto& [id, members] : offsets_)
      if (names_.count(id) && names_.at(id) == name) return members;
    return {};
  }

  // The stride of an array of struct `name` (0 when there is none).
  uint32_t stride(const std::string& name) const {
    for (const auto& [array, element] : element_)
      if (names_.count(element) && names_.at(element) == name && strides_.count(array))
        return strides_.at(array);
    return 0;
  }

  // The constant_id of each specialisation constant, by name.
  std::map<std::string, uint32_t> spec_ids() const {
    std::map<std::string, uint32_t> ids;
    for (const auto& [id, spec] : spec_ids_)
      if (names_.count(id)) ids[names_.at(id)] = spec;
    return ids;
  }

 private:
  static std::string text(std::span<const uint32_t> w) {
    std::string s;
    for (uint32_t word : w)
      for (int b = 0; b < 4; ++b) {
        const char c = char((word >> (8 * b)) & 0xffu);
        if (c == '\0') return s;
        s += c;
      }
    return s;
  }

  std::map<uint32_t, std::string> names_;
  std::map<uint32_t, std::map<uint32_t, std::string>> member_names_;
  std::map<uint32_t, std::map<std::string, uint32_t>> offsets_;
  std::map<uint32_t, uint32_t> strides_, element_, spec_ids_;
};

TEST(HostDevice, GpuBirdHasTheSameLayoutInTheShaders) {
  const SpirvLayouts step(shader_spirv("step"));
  const std::map<std::string, uint32_t> spirv = step.offsets("GpuBird");
  const std::map<std::string, uint32_t> cpp = {
#define AF_BIRD_FIELD(gpu_type, cpp_type, name, initial) {#name, uint32_t(offsetof(GpuBird, name))},
#include "model/bird_state.def"
#undef AF_BIRD_FIELD
      {"tile_x", uint32_t(offsetof(GpuBird, tile_x))},  // the device's own (world tiles)
      {"tile_z", uint32_t(offsetof(GpuBird, tile_z))},
  };
  EXPECT_EQ(spirv, cpp);
  EXPECT_EQ(step.stride("GpuBird"), sizeof(GpuBird));
}

TEST(HostDevice, GpuSpeciesHasTheSameLayoutInTheShaders) {
  const SpirvLayouts step(shader_spirv("step"));
  const std::map<std::string, uint32_t> spirv = step.offsets("GpuSpecies");
#define AF_SPECIES_PARAM(name, default_value, unit, rule, max) \
  EXPECT_EQ(spirv.count(#name) ? spirv.at(#name) : ~0u, offsetof(GpuSpecies, name)) << #name;
#include "model/species.def"
#undef AF_SPECIES_PARAM
  EXPECT_EQ(step.stride("GpuSpecies"), sizeof(GpuSpecies));  // the derived values too
}

TEST(HostDevice, EveryBufferElementHasTheSameSizeInTheShaders) {
  const SpirvLayouts step(shader_spirv("step")), forces(shader_spirv("step_forces"));
  const SpirvLayouts pose(shader_spirv("pose")), bird(shader_spirv("bird_vert"));
  EXPECT_EQ(step.stride("GpuTarget"), sizeof(GpuTarget));
  EXPECT_EQ(step.stride("GpuRoute"), sizeof(GpuRoute));
  EXPECT_EQ(step.stride("GpuBranch"), sizeof(GpuBranch));
  EXPECT_EQ(forces.stride("GpuForces"), sizeof(GpuForces));
  EXPECT_EQ(pose.stride("Pose"), sizeof(Pose));
  EXPECT_EQ(pose.stride("DrawCommand"), sizeof(DrawCommand));
  EXPECT_EQ(bird.stride("MeshVertex"), sizeof(MeshVertex));
  const SpirvLayouts perceive(shader_spirv("perceive"));
  EXPECT_EQ(step.stride("GpuPerception"), sizeof(GpuPerception));
  EXPECT_EQ(perceive.stride("GpuPerception"), sizeof(GpuPerception));
  EXPECT_EQ(perceive.offsets("GpuPerception").at("seen_key"), offsetof(GpuPerception, seen_key));
  // The push-constant blocks, member by member where C++ can name them.
  EXPECT_EQ(step.offsets("StepConstants").at("next_targets"),
            offsetof(StepConstants, next_targets));
  EXPECT_EQ(step.offsets("StepConstants").at("first_step"), offsetof(StepConstants, first_step));
  EXPECT_EQ(forces.offsets("StepConstants").at("frame_steps"),
            offsetof(StepConstants, frame_steps));
  EXPECT_EQ(perceive.offsets("StepConstants").at("frame_seconds"),
            offsetof(StepConstants, frame_seconds));
  EXPECT_EQ(perceive.offsets("StepConstants").at("grid_cell"), offsetof(StepConstants, grid_cell));
  EXPECT_EQ(perceive.offsets("StepConstants").at("grid_bits"), offsetof(StepConstants, grid_bits));
  EXPECT_EQ(pose.offsets("PoseConstants").at("lod_scale"), offsetof(PoseConstants, lod_scale));
  EXPECT_EQ(pose.offsets("PoseConstants").at("tile_z"), offsetof(PoseConstants, tile_z));
  EXPECT_EQ(bird.offsets("FrameConstants").at("list_offset"),
            offsetof(FrameConstants, list_offset));
  const SpirvLayouts solid(shader_spirv("solid_vert"));
  EXPECT_EQ(solid.offsets("FrameConstants").at("tile_z"), offsetof(FrameConstants, tile_z));
  EXPECT_EQ(solid.offsets("GpuTarget").at("tile_z"), offsetof(GpuTarget, tile_z));
  EXPECT_EQ(solid.offsets("GpuBranch").at("tile_z"), offsetof(GpuBranch, tile_z));
}

}  // namespace
// The model's specialisation constants (host_device.h) are the ids the host sets in every shader
// that steps or perceives, and perceive.comp's own follow them.
TEST(HostDevice, TheModelsConstantsHaveTheirIdsInTheShaders) {
  const std::map<std::string, uint32_t> model = {{"kWakes", kConstantWakes},
                                                 {"kBranches", kConstantBranches},
                                                 {"kWindProfile", kConstantWindProfile}};
  EXPECT_EQ(SpirvLayouts(shader_spirv("step")).spec_ids(), model);
  EXPECT_EQ(SpirvLayouts(shader_spirv("step_forces")).spec_ids(), model);
  std::map<std::string, uint32_t> perceive = model;
  perceive["kSeen"] = kModelConstants;
  perceive["kAllSeeKSeen"] = kModelConstants + 1;
  EXPECT_EQ(SpirvLayouts(shader_spirv("perceive")).spec_ids(), perceive);
}

// What a scenario can reach: wakes where a flock meets them, the landing where a route ends on a
// branch or a bird already brakes for one, the world's wind profile.
TEST(ModelConstants, FollowWhatTheScenarioCanReach) {
  Scenario s;
  s.flocks.push_back(Flock{});
  s.world.routes.push_back(Route{});
  std::vector<BirdState> birds(2);
  auto constants = [&] { return model_constants(s, birds); };
  EXPECT_EQ(constants(), (std::vector<uint32_t>{0, 0, 0}));

  s.flocks[0].flocking = true;
  s.flocks[0].wake = true;
  EXPECT_EQ(constants()[kConstantWakes], 1u);
  s.flocks[0].flocking = false;  // a flock that does not flock meets no wakes
  EXPECT_EQ(constants()[kConstantWakes], 0u);

  birds[1].mode = FlightMode::landing;
  EXPECT_EQ(constants()[kConstantBranches], 1u);
  birds[1].mode = FlightMode::flying;
  Route to_branch;
  to_branch.branch = 0;
  s.world.routes.push_back(to_branch);
  EXPECT_EQ(constants()[kConstantBranches], 1u);

  for (const WindProfile p :
       {WindProfile::uniform, WindProfile::power_law, WindProfile::logarithmic}) {
    s.world.wind_profile = p;
    EXPECT_EQ(constants()[kConstantWindProfile], static_cast<uint32_t>(p));
  }
  EXPECT_EQ(constants().size(), kModelConstants);
}

}  // namespace aeroflock::gpu
