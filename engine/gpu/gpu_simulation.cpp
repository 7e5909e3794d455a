#include "gpu/gpu_simulation.h"

#include <cstring>
#include <span>

#include "gpu/shaders.h"
#include "model/simulation.h"

namespace aeroflock::gpu {
namespace {

constexpr uint32_t kLocalSize = 64;  // local_size_x of step.comp and probe.comp
constexpr uint32_t kBindings = 6;    // birds, species, targets, routes, route targets, branches

template <class T>
std::span<const std::byte> bytes_of(const std::vector<T>& v) {
  return std::as_bytes(std::span<const T>(v));
}

// A buffer holding `items` (at least one element, so that every binding is a valid buffer).
template <class T>
Buffer buffer_with(const Device& device, const std::vector<T>& items, Memory memory) {
  Buffer b(device, std::max<size_t>(items.size(), 1) * sizeof(T), memory);
  if (!items.empty()) b.upload(bytes_of(items));
  return b;
}

std::vector<GpuSpecies> pack_species(const Scenario& s) {
  std::vector<GpuSpecies> out;
  for (const Species& sp : s.species) out.push_back(pack(sp));
  return out;
}

std::vector<GpuBird> pack_birds(const std::vector<BirdState>& birds) {
  std::vector<GpuBird> out;
  out.reserve(birds.size());
  for (const BirdState& b : birds) out.push_back(pack(b));
  return out;
}

Buffer make_bird_buffer(const Device& device, const std::vector<BirdState>& birds, Memory memory) {
  check_storage_size(device, birds.size() * sizeof(GpuBird), sizeof(GpuBird));
  return buffer_with(device, pack_birds(birds), memory);
}

}  // namespace

// The scenario's birds, once the device is known to hold that many (before spawning them).
std::vector<BirdState> spawn_fitting(const Device& device, const Scenario& scenario, uint32_t birds_override) {
  uint64_t count = birds_override;
  if (count == 0)
    for (const Flock& f : scenario.flocks) count += f.count;
  check_storage_size(device, count * sizeof(GpuBird), sizeof(GpuBird));
  return spawn_birds(scenario, birds_override);
}

GpuSimulation::GpuSimulation(const Device& device, Scenario scenario, uint32_t birds_override)
    : GpuSimulation(device, scenario, spawn_fitting(device, scenario, birds_override)) {}

GpuSimulation::GpuSimulation(const Device& device, Scenario scenario, std::vector<BirdState> birds)
    : device_(device),
      scenario_(std::move(scenario)),
      count_(static_cast<uint32_t>(birds.size())),
      birds_(make_bird_buffer(device, birds, Memory::device_local)),
      species_(buffer_with(device, pack_species(scenario_), Memory::device_local)),
      routes_(buffer_with(device, pack(scenario_.world).routes, Memory::device_local)),
      route_targets_(buffer_with(device, pack(scenario_.world).route_targets, Memory::device_local)),
      branches_(buffer_with(device, pack(scenario_.world).branches, Memory::device_local)),
      probes_(device, std::max<size_t>(count_, 1) * sizeof(ProbeForces), Memory::host),
      targets_{buffer_with(device, pack_targets(scenario_.world, 0.0), Memory::host),
               buffer_with(device, pack_targets(scenario_.world, 0.0), Memory::host)},
      readback_{Buffer(device, birds_.size(), Memory::host), Buffer(device, birds_.size(), Memory::host)},
      step_(device, shader_spirv("step"), kBindings, sizeof(StepConstants), 2),
      probe_(device, shader_spirv("probe"), kBindings + 1, sizeof(StepConstants), 1),
      host_birds_(std::move(birds)),
      submitter_(device, 2) {
  for (uint32_t slot = 0; slot < 2; ++slot)
    step_sets_[slot] = step_.make_set({&birds_, &species_, &targets_[slot], &routes_, &route_targets_, &branches_});
  probe_set_ = probe_.make_set({&birds_, &species_, &targets_[0], &routes_, &route_targets_, &branches_, &probes_});
}

StepConstants GpuSimulation::constants(uint32_t steps) const {
  const World& w = scenario_.world;
  StepConstants c{};
  c.wind_ground = glm::vec4(glm::vec3(w.wind), float(w.ground_height));
  c.dt = float(scenario_.dt);
  c.time = float(time_);
  c.steps = steps;
  c.bird_count = count_;
  c.turning = uint32_t(w.turning);
  c.ground_effect = w.ground_effect ? 1u : 0u;
  return c;
}

void GpuSimulation::write_targets(uint32_t slot, double time) {
  scenario_.world.move_targets(time);
  const std::vector<GpuTarget> targets = pack_targets(scenario_.world, time);
  if (!targets.empty()) std::memcpy(targets_[slot].mapped(), targets.data(), targets.size() * sizeof(GpuTarget));
}

double GpuSimulation::frame_start() const {
  const uint64_t per_frame = scenario_.steps_per_frame;
  return double(steps_ / per_frame * per_frame) * scenario_.dt;
}

void GpuSimulation::step_frame() { step(scenario_.steps_per_frame); }

void GpuSimulation::step(uint32_t steps) {
  VkCommandBuffer cmd = submitter_.begin();  // waits for this slot's previous frame only
  const uint32_t slot = submitter_.frame();
  write_targets(slot, frame_start());  // targets move between frames
  const StepConstants c = constants(steps);
  barrier_to_compute(cmd);
  step_.dispatch(cmd, step_sets_[slot], group_count(count_, kLocalSize), &c, sizeof c);
  record_readback(cmd, birds_, readback_[slot]);
  last_frame_ = submitter_.submit();
  last_slot_ = slot;
  host_current_ = false;
  steps_ += steps;
  time_ = steps_ * scenario_.dt;
  slot_fence_[slot] = last_frame_;
  slot_time_[slot] = time_;
  ++frames_in_row_;
}

std::vector<ProbeForces> GpuSimulation::step_probe() {
  submitter_.wait_all();
  write_targets(0, frame_start());
  const StepConstants c = constants(1);
  submitter_.run([&](VkCommandBuffer cmd) {
    barrier_to_compute(cmd);
    probe_.dispatch(cmd, probe_set_, group_count(count_, kLocalSize), &c, sizeof c);
    record_readback(cmd, birds_, readback_[0]);
  });
  last_frame_ = VK_NULL_HANDLE;
  last_slot_ = 0;
  frames_in_row_ = 0;
  host_current_ = false;
  ++steps_;
  time_ = steps_ * scenario_.dt;
  std::vector<ProbeForces> out(count_);
  std::memcpy(out.data(), probes_.mapped(), count_ * sizeof(ProbeForces));
  return out;
}

const std::vector<BirdState>& GpuSimulation::previous_birds() {
  if (frames_in_row_ < 2) return birds();
  const uint32_t slot = 1 - last_slot_;
  submitter_.wait(slot_fence_[slot]);
  const auto* gpu = reinterpret_cast<const GpuBird*>(readback_[slot].mapped());
  previous_birds_.resize(count_);
  for (uint32_t i = 0; i < count_; ++i) previous_birds_[i] = unpack(gpu[i]);
  return previous_birds_;
}

double GpuSimulation::previous_time() const {
  return frames_in_row_ < 2 ? time_ : slot_time_[1 - last_slot_];
}

const std::vector<BirdState>& GpuSimulation::birds() {
  if (host_current_) return host_birds_;
  if (last_frame_ != VK_NULL_HANDLE) submitter_.wait(last_frame_);
  const auto* gpu = reinterpret_cast<const GpuBird*>(readback_[last_slot_].mapped());
  for (uint32_t i = 0; i < count_; ++i) host_birds_[i] = unpack(gpu[i]);
  host_current_ = true;
  return host_birds_;
}

}  // namespace aeroflock::gpu
