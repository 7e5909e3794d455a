#include "gpu/gpu_simulation.h"

#include <cstring>
#include <span>

#include "gpu/shaders.h"

namespace aeroflock::gpu {
namespace {

// A buffer holding `items` (at least one element, so that every binding is a valid buffer).
template <class T>
Buffer buffer_with(const Device& device, const std::vector<T>& items, Memory memory) {
  Buffer b(device, std::max<size_t>(items.size(), 1) * sizeof(T), memory);
  if (!items.empty()) b.upload(std::as_bytes(std::span<const T>(items)));
  return b;
}

std::vector<GpuSpecies> pack_species(const Scenario& s) {
  std::vector<GpuSpecies> out;
  for (const Species& sp : s.species) out.push_back(pack(sp));
  return out;
}

// A frame's targets: where they are at its start, then at the next frame's start.
Buffer targets_buffer(const Device& device, const World& world) {
  return Buffer(device, std::max<size_t>(2 * world.targets.size(), 1) * sizeof(GpuTarget),
                Memory::host);
}

Buffer make_bird_buffer(const Device& device, const std::vector<BirdState>& birds) {
  check_storage_size(device, birds.size() * sizeof(GpuBird), sizeof(GpuBird));
  std::vector<GpuBird> packed;
  packed.reserve(birds.size());
  for (const BirdState& b : birds) packed.push_back(pack(b));
  return buffer_with(device, packed, Memory::device_local);
}

// The scenario's birds, once the device is known to hold that many (before spawning them).
std::vector<BirdState> spawn_fitting(const Device& device, const Scenario& scenario,
                                     uint32_t birds_override) {
  check_storage_size(device, spawn_count(scenario, birds_override) * sizeof(GpuBird),
                     sizeof(GpuBird));
  return spawn_birds(scenario, birds_override);
}

}  // namespace

GpuSimulation::GpuSimulation(const Device& device, Scenario scenario, uint32_t birds_override)
    : GpuSimulation(device, scenario, spawn_fitting(device, scenario, birds_override)) {}

GpuSimulation::GpuSimulation(std::unique_ptr<Device> device, Scenario scenario,
                             uint32_t birds_override)
    : GpuSimulation(*device, std::move(scenario), birds_override) {
  owned_device_ = std::move(device);  // the members made on it are destroyed before it
}

GpuSimulation::GpuSimulation(const Device& device, Scenario scenario, std::vector<BirdState> birds)
    : Simulation(std::move(scenario)),
      device_(device),
      count_(static_cast<uint32_t>(birds.size())),
      birds_(make_bird_buffer(device, birds)),
      species_(buffer_with(device, pack_species(this->scenario()), Memory::device_local)),
      routes_(buffer_with(device, pack(world()).routes, Memory::device_local)),
      route_targets_(buffer_with(device, pack(world()).route_targets, Memory::device_local)),
      branches_(buffer_with(device, pack(world()).branches, Memory::device_local)),
      step_(device, shader_spirv("step"),
            {kBindingBirds, kBindingSpecies, kBindingTargets, kBindingRoutes, kBindingRouteTargets,
             kBindingBranches},
            sizeof(StepConstants), 2),
      slots_{{targets_buffer(device, world()), Buffer(device, birds_.size(), Memory::host)},
             {targets_buffer(device, world()), Buffer(device, birds_.size(), Memory::host)}},
      initial_(std::move(birds)),
      submitter_(device, 2) {
  step_.check_groups(group_count(count_, kWorkgroupSize));  // so that step() cannot fail on it
  for (Slot& slot : slots_)
    slot.set =
        step_.make_set({&birds_, &species_, &slot.targets, &routes_, &route_targets_, &branches_});
}

std::string GpuSimulation::device() const { return device_.name() + " (" + device_.driver() + ")"; }

// The forces pipeline and buffers, made the first time a frame records forces (the buffers are
// as large as the flock's state again, three times over).
void GpuSimulation::prepare_forces() {
  if (step_forces_) return;
  const VkDeviceSize bytes = std::max<VkDeviceSize>(count_, 1) * sizeof(GpuForces);
  check_storage_size(device_, bytes, sizeof(GpuForces), "birds' forces");
  forces_ = std::make_unique<Buffer>(device_, bytes, Memory::device_local);
  step_forces_ = std::make_unique<ComputePipeline>(
      device_, shader_spirv("step_forces"),
      std::vector<uint32_t>{kBindingBirds, kBindingSpecies, kBindingTargets, kBindingRoutes,
                            kBindingRouteTargets, kBindingBranches, kBindingForces},
      sizeof(StepConstants), 2);
  for (Slot& slot : slots_) {
    slot.forces = std::make_unique<Buffer>(device_, bytes, Memory::host);
    slot.forces_set = step_forces_->make_set(
        {&birds_, &species_, &slot.targets, &routes_, &route_targets_, &branches_, forces_.get()});
  }
}

void GpuSimulation::step(uint32_t steps, bool record_forces) {
  if (record_forces) prepare_forces();
  VkCommandBuffer cmd = submitter_.begin();  // waits for this slot's previous frame only
  Slot& slot = slots_[submitter_.frame()];
  const double start = begin_frame();
  // The targets where they are at the frame's start, then where the next frame sees them (for
  // the recorded forces), in this slot's buffer (the other slot's frame may still read its own).
  std::vector<GpuTarget> targets = pack_targets(world(), start);
  const std::vector<GpuTarget> next = pack_targets(world(), frame_start(this->steps() + steps));
  targets.insert(targets.end(), next.begin(), next.end());
  if (!targets.empty())
    std::memcpy(slot.targets.mapped(), targets.data(), targets.size() * sizeof(GpuTarget));

  StepConstants c{};
  c.wind_ground = vec4(vec3(world().wind), float(world().ground_height));
  c.dt = float(scenario().dt);
  c.time = float(time());
  c.steps = steps;
  c.bird_count = count_;
  c.turning = uint32_t(world().turning);
  c.ground_effect = world().ground_effect ? 1u : 0u;
  c.next_targets = uint32_t(next.size());
  barrier_to_compute(cmd);
  if (record_forces)
    step_forces_->dispatch(cmd, slot.forces_set, group_count(count_, kWorkgroupSize), &c, sizeof c);
  else
    step_.dispatch(cmd, slot.set, group_count(count_, kWorkgroupSize), &c, sizeof c);
  record_readback(cmd, birds_, slot.readback);
  if (record_forces) record_readback(cmd, *forces_, *slot.forces);
  slot.fence = submitter_.submit();
  end_frame(steps);

  slot.snapshot = {frames(), this->steps(), time(), nullptr, nullptr};
  slot.unpacked = false;
  slot.has_forces = record_forces;
  last_ = static_cast<int>(submitter_.frame());
}

Snapshot GpuSimulation::read(Slot& slot) {
  if (!slot.unpacked) {
    submitter_.wait(slot.fence);
    const auto* gpu = reinterpret_cast<const GpuBird*>(slot.readback.mapped());
    slot.birds.resize(count_);
    for (uint32_t i = 0; i < count_; ++i) slot.birds[i] = unpack(gpu[i]);
    if (slot.has_forces) {
      const auto* f = reinterpret_cast<const GpuForces*>(slot.forces->mapped());
      slot.step_forces.resize(count_);
      for (uint32_t i = 0; i < count_; ++i) slot.step_forces[i] = unpack(f[i]);
    }
    slot.unpacked = true;
  }
  Snapshot s = slot.snapshot;
  s.birds = &slot.birds;
  s.forces = slot.has_forces ? &slot.step_forces : nullptr;
  return s;
}

Snapshot GpuSimulation::snapshot() {
  if (last_ < 0) return {0, 0, 0.0, &initial_, nullptr};
  return read(slots_[last_]);
}

Snapshot GpuSimulation::ready_snapshot() {
  if (ready_frame() == frames()) return snapshot();
  return read(slots_[1 - last_]);
}

}  // namespace aeroflock::gpu
