#include "gpu/gpu_simulation.h"

#include <algorithm>
#include <bit>
#include <cstring>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>

#include "gpu/shaders.h"
#include "model/constants.h"

namespace aeroflock::gpu {
namespace {

// A buffer holding `items` (at least one element, so that every binding is a valid buffer), once
// the device is known to hold that many (`what` they are, for the error).
template <class T>
Buffer buffer_with(const Device& device, const std::vector<T>& items, Memory memory,
                   std::string_view what) {
  check_storage_size(device, std::max<size_t>(items.size(), 1) * sizeof(T), sizeof(T), what);
  Buffer b(device, std::max<size_t>(items.size(), 1) * sizeof(T), memory);
  if (!items.empty()) b.upload(std::as_bytes(std::span<const T>(items)));
  return b;
}

std::vector<GpuSpecies> pack_species(const Scenario& s) {
  std::vector<GpuSpecies> out;
  for (const Species& sp : s.species) out.push_back(pack(sp));
  return out;
}

// The frames a submission records: kFramesPerSubmission, fewer where that many frames' targets
// would not fit one storage buffer (a world of 10^5 targets on lavapipe); an error naming the
// targets where one frame's do not.
uint32_t frames_fitting(const Device& device, const World& world) {
  const size_t frame_bytes = 2 * sizeof(GpuTarget);  // a target at a frame's start and the next's
  check_storage_size(device, world.targets.size() * frame_bytes, frame_bytes, "targets");
  if (world.targets.empty()) return kFramesPerSubmission;
  return uint32_t(std::clamp<VkDeviceSize>(
      storage_capacity(device, frame_bytes) / world.targets.size(), 1, kFramesPerSubmission));
}

// A frame's targets: where they are at its start, then at the next frame's start; for each frame
// of a submission.
Buffer targets_buffer(const Device& device, const World& world, uint32_t frames) {
  return Buffer(device, std::max<size_t>(2 * world.targets.size() * frames, 1) * sizeof(GpuTarget),
                Memory::host);
}

// Throws Error unless `birds` fit the device: their states in one storage buffer, one invocation
// each in one dispatch (maxComputeWorkGroupCount). The tighter limit is checked first, so that
// the error's "at most" is the largest flock that fits.
void check_flock_fits(const Device& device, uint64_t birds) {
  const uint64_t by_groups = uint64_t(device.limits().maxComputeWorkGroupCount[0]) * kWorkgroupSize;
  if (storage_capacity(device, sizeof(GpuBird)) > by_groups)
    check_group_count(device, birds, kWorkgroupSize);
  check_storage_size(device, birds * sizeof(GpuBird), sizeof(GpuBird));
  check_group_count(device, birds, kWorkgroupSize);
}

// Room for `capacity` birds, the first of them `birds`.
Buffer make_bird_buffer(const Device& device, const std::vector<BirdState>& birds,
                        uint32_t capacity) {
  check_flock_fits(device, capacity);
  std::vector<GpuBird> packed(capacity, pack(BirdState{}));
  for (size_t i = 0; i < birds.size(); ++i) packed[i] = pack(birds[i]);
  return buffer_with(device, packed, Memory::device_local, "birds");
}

// Room for `capacity` birds' ids, bird k's k (one device: its index is its id).
Buffer make_ids_buffer(const Device& device, uint32_t capacity) {
  std::vector<uint32_t> ids(capacity);
  for (uint32_t k = 0; k < capacity; ++k) ids[k] = k;
  return buffer_with(device, ids, Memory::device_local, "birds' ids");
}

// The scenario's birds, once the device is known to hold that many (before spawning them).
std::vector<BirdState> spawn_fitting(const Device& device, const Scenario& scenario,
                                     uint32_t birds_override) {
  check_flock_fits(device, spawn_count(scenario, birds_override));
  return spawn_birds(scenario, birds_override);
}

// Every bird's perception, none seen yet (one element when no flock flocks).
Buffer perception_buffer(const Device& device, size_t birds, bool flocking) {
  const size_t n = flocking ? birds : 0;
  return buffer_with(device, std::vector<GpuPerception>(n, pack(Perception{})),
                     Memory::device_local, "birds' perception");
}

Buffer grid_buffer(const Device& device, size_t words, const char* what) {
  check_storage_size(device, std::max<size_t>(words, 1) * sizeof(uint32_t), sizeof(uint32_t), what);
  return Buffer(device, std::max<size_t>(words, 1) * sizeof(uint32_t), Memory::device_local);
}

// The bindings of every pass that flies or sees birds: the birds, their species and their world
// (GpuSimulation::world_buffers), and then the pass's own.
std::vector<Binding> world_and(std::initializer_list<Binding> more) {
  std::vector<Binding> all = {kBindingBirds,   kBindingIds,    kBindingSpecies,
                              kBindingTargets, kBindingRoutes, kBindingRouteTargets,
                              kBindingBranches};
  all.insert(all.end(), more);
  return all;
}

// The search reads the grid as texels (compute.h: Binding).
const std::vector<Binding> kPerceiveBindings =
    world_and({kBindingPerception,
               {kBindingGridPoints, VK_FORMAT_R32G32B32A32_SFLOAT},
               {kBindingGridKeys, VK_FORMAT_R32G32B32A32_SINT},
               {kBindingGridCells, VK_FORMAT_R32G32B32A32_UINT},
               {kBindingGridSearch, VK_FORMAT_R32G32B32A32_SINT},
               {kBindingGridSeen, VK_FORMAT_R32G32B32A32_SFLOAT},
               kBindingCutShort});

// perceive.comp's specialisation: the model's (layout.h: model_constants), then the most
// neighbours a species that flocks sees (kSeen, at least 1) and whether each of them sees that
// many (kAllSeeKSeen).
std::vector<uint32_t> perceive_constants(const Scenario& scenario,
                                         const std::vector<BirdState>& birds) {
  const std::vector<bool> flocks = flocking_species(scenario.species.size(), birds);
  uint32_t most = 0, least = aeroflock::kMaxNeighbours;
  for (size_t k = 0; k < flocks.size(); ++k)
    if (flocks[k]) {
      most = std::max(most, static_cast<uint32_t>(scenario.species[k].neighbours));
      least = std::min(least, static_cast<uint32_t>(scenario.species[k].neighbours));
    }
  std::vector<uint32_t> constants = model_constants(scenario, birds);
  constants.push_back(std::max(most, 1u));
  constants.push_back(most == least && most >= 1 ? 1u : 0u);
  return constants;
}

// The farthest a species that flocks sees: the search's order reaches it.
double farthest_seen(const Scenario& scenario, const std::vector<BirdState>& birds) {
  const std::vector<bool> flocks = flocking_species(scenario.species.size(), birds);
  double radius = 0.0;
  for (size_t k = 0; k < flocks.size(); ++k)
    if (flocks[k]) radius = std::max(radius, scenario.species[k].perception_radius);
  return radius;
}

// The search's orders for each of `cells`, one after the other; where each begins and how many
// cells a part's list holds.
Buffer search_buffer(const Device& device, const std::vector<double>& cells, uint32_t buckets,
                     double radius, std::vector<uint32_t>& first, std::vector<uint32_t>& length) {
  std::vector<glm::ivec4> orders;
  constexpr size_t kParts = size_t{kSearchParts} * kSearchParts * kSearchParts;
  for (const double cell : cells) {
    const std::vector<glm::ivec4> order =
        grid_search_order(GridShape{cell, buckets}, radius, kSearchParts);
    first.push_back(static_cast<uint32_t>(orders.size()));
    length.push_back(static_cast<uint32_t>(order.size() / kParts));
    orders.insert(orders.end(), order.begin(), order.end());
  }
  return buffer_with(device, orders, Memory::device_local, "grid search offsets");
}

// The grid's table's room: 16 slots a bird, where the device's buffers hold them, and never fewer
// than grid_buckets' 4 (the least the table takes). Fitted to a compact flock the sides need
// about 16 (1,000 paper starlings flying the default scenario span 26 x 9 x 20 cells).
uint32_t table_room(const Device& device, uint32_t capacity) {
  const uint64_t fits = std::min<uint64_t>(storage_capacity(device, sizeof(glm::ivec4)),
                                           device.limits().maxTexelBufferElements) -
                        1;  // grid_cells.comp's slot after the last
  const uint64_t wanted = std::bit_ceil(16 * uint64_t(std::max(capacity, 1u)));
  return uint32_t(std::max<uint64_t>(grid_buckets(capacity),
                                     std::min({wanted, std::bit_floor(fits), uint64_t(1) << 31})));
}

}  // namespace

GpuSimulation::Flocking::Flocking(const Device& device, const Scenario& scenario,
                                  const std::vector<BirdState>& kinds, uint32_t capacity)
    : shape{grid_shape(scenario.species, kinds).cell, table_room(device, capacity)},
      table(grid_table(uint32_t(std::countr_zero(grid_buckets(capacity))))),
      least_bits(table.bits()),
      most_bits(uint32_t(std::countr_zero(shape.buckets))),
      cells(grid_cells_allowed(scenario.species, kinds)),
      place(grid_buffer(device, 2 * size_t{capacity}, "birds' grid places")),
      counts(grid_buffer(device, shape.buckets, "grid slots")),
      starts(grid_buffer(device, shape.buckets, "grid slots")),
      blocks(grid_buffer(device, shape.buckets / kScanBlock, "grid blocks")),
      points(grid_buffer(device, 4 * std::max<size_t>(capacity, 1),
                         "birds in the grid")),  // a texel at least
      keys(grid_buffer(device, 4 * size_t{shape.buckets}, "grid slots")),
      owners(grid_buffer(device, shape.buckets, "grid slots")),
      cell_boxes(grid_buffer(device, 4 * (size_t{shape.buckets} + 1), "grid slots")),
      seen(grid_buffer(device, 8 * std::max<size_t>(capacity, 1), "birds in the grid")),
      search(search_buffer(device, cells, shape.buckets, farthest_seen(scenario, kinds),
                           search_first, search_cells)),
      count(device, shader_spirv("grid_count"),
            world_and({kBindingGridPlace, kBindingGridCounts, kBindingGridKeys, kBindingGridOwners,
                       kBindingPerception}),
            sizeof(StepConstants), 2),
      scan_blocks(device, shader_spirv("grid_scan_blocks"),
                  {kBindingGridCounts, kBindingGridStarts, kBindingGridBlocks},
                  sizeof(StepConstants), 1),
      scan_totals(device, shader_spirv("grid_scan_totals"),
                  {kBindingGridCounts, kBindingGridStarts, kBindingGridBlocks},
                  sizeof(StepConstants), 1),
      scatter(device, shader_spirv("grid_scatter"),
              {kBindingBirds, kBindingGridPlace, kBindingGridStarts, kBindingGridBlocks,
               kBindingGridPoints, kBindingGridSeen},
              sizeof(StepConstants), 1),
      cells_pass(device, shader_spirv("grid_cells"),
                 {kBindingGridPlace, kBindingGridCounts, kBindingGridStarts, kBindingGridBlocks,
                  kBindingGridPoints, kBindingGridCells},
                 sizeof(StepConstants), 1),
      perceive(device, shader_spirv("perceive"), kPerceiveBindings, sizeof(StepConstants), 2,
               perceive_constants(scenario, kinds)) {
  scan_blocks.set_buffers({{kBindingGridCounts, &counts},
                           {kBindingGridStarts, &starts},
                           {kBindingGridBlocks, &blocks}});
  scan_totals.set_buffers({{kBindingGridCounts, &counts},
                           {kBindingGridStarts, &starts},
                           {kBindingGridBlocks, &blocks}});
  cells_pass.set_buffers({{kBindingGridPlace, &place},
                          {kBindingGridCounts, &counts},
                          {kBindingGridStarts, &starts},
                          {kBindingGridBlocks, &blocks},
                          {kBindingGridPoints, &points},
                          {kBindingGridCells, &cell_boxes}});

  if (cell_index() == cells.size())
    throw std::logic_error("the grid's cell is not one it may take");
  perceive.check_groups(group_count(capacity, kWorkgroupSize));
  scan_blocks.check_groups(shape.buckets / kScanBlock);
}

GpuSimulation::GpuSimulation(const Device& device, Scenario scenario, uint32_t birds_override)
    : GpuSimulation(device, scenario, spawn_fitting(device, scenario, birds_override)) {}

GpuSimulation::GpuSimulation(std::unique_ptr<Device> device, Scenario scenario,
                             uint32_t birds_override)
    : GpuSimulation(*device, std::move(scenario), birds_override) {
  owned_device_ = std::move(device);  // the members made on it are destroyed before it
}

GpuSimulation::GpuSimulation(std::unique_ptr<Device> device, Scenario scenario,
                             std::vector<BirdState> birds)
    : GpuSimulation(*device, std::move(scenario), std::move(birds)) {
  owned_device_ = std::move(device);
}

GpuSimulation::GpuSimulation(const Device& device, Scenario scenario, std::vector<BirdState> birds)
    : GpuSimulation(device, std::move(scenario), std::move(birds), nullptr, 0) {}

GpuSimulation::GpuSimulation(const Device& device, Scenario scenario,
                             const std::vector<BirdState>& kinds, uint32_t capacity)
    : GpuSimulation(device, std::move(scenario), {}, &kinds, capacity) {}

GpuSimulation::GpuSimulation(const Device& device, Scenario scenario, std::vector<BirdState> birds,
                             const std::vector<BirdState>* kinds, uint32_t capacity)
    : Simulation(std::move(scenario)),
      device_(device),
      count_(static_cast<uint32_t>(birds.size())),
      capacity_(kinds ? capacity : count_),
      birds_(make_bird_buffer(device, birds, capacity_)),
      ids_(make_ids_buffer(device, capacity_)),
      species_(
          buffer_with(device, pack_species(this->scenario()), Memory::device_local, "species")),
      routes_(buffer_with(device, pack(world()).routes, Memory::device_local, "routes")),
      route_targets_(buffer_with(device, pack(world()).route_targets, Memory::device_local,
                                 "routes' targets")),
      branches_(buffer_with(device, pack(world()).branches, Memory::device_local, "branches")),
      perception_(perception_buffer(device, capacity_, any_flocking(this->scenario()))),
      model_constants_(model_constants(this->scenario(), kinds ? *kinds : birds)),
      step_(device, shader_spirv("step"), world_and({kBindingPerception, kBindingCutShort}),
            sizeof(StepConstants), 2, model_constants_),
      frames_per_submission_(frames_fitting(device, world())),
      slots_{{targets_buffer(device, world(), frames_per_submission_),
              Buffer(device, birds_.size(), Memory::host),
              Buffer(device, (3 + kReachBins) * sizeof(uint32_t), Memory::host)},
             {targets_buffer(device, world(), frames_per_submission_),
              Buffer(device, birds_.size(), Memory::host),
              Buffer(device, (3 + kReachBins) * sizeof(uint32_t), Memory::host)}},
      initial_(std::move(birds)),
      submitter_(device, 2) {
  step_.check_groups(group_count(capacity_, kWorkgroupSize));  // so that step() cannot fail on it
  if (any_flocking(this->scenario()))
    flocking_ =
        std::make_unique<Flocking>(device, this->scenario(), kinds ? *kinds : initial_, capacity_);
  if (flocking_) {
    std::vector<GpuBird> packed(initial_.size());
    std::transform(initial_.begin(), initial_.end(), packed.begin(),
                   [](const BirdState& b) { return pack(b); });
    fit_grid_table(packed);
  }
  for (Slot& slot : slots_) {
    std::memset(slot.cut_short.mapped(), 0, slot.cut_short.size());
    slot.set = step_.make_set(world_buffers(
        slot.targets, {{kBindingPerception, &perception_}, {kBindingCutShort, &slot.cut_short}}));
    if (!flocking_) continue;
    Flocking& f = *flocking_;
    slot.perception = std::make_unique<Buffer>(device, perception_.size(), Memory::host);
    slot.perceive_set =
        f.perceive.make_set(world_buffers(slot.targets, {{kBindingPerception, &perception_},
                                                         {kBindingGridPoints, &f.points},
                                                         {kBindingGridKeys, &f.keys},
                                                         {kBindingGridCells, &f.cell_boxes},
                                                         {kBindingGridSearch, &f.search},
                                                         {kBindingGridSeen, &f.seen},
                                                         {kBindingCutShort, &slot.cut_short}}));
  }
  if (flocking_) {  // the count pass reads no target: either slot's buffer will do
    Flocking& f = *flocking_;
    f.count.set_buffers(world_buffers(slots_[0].targets, {{kBindingGridPlace, &f.place},
                                                          {kBindingGridCounts, &f.counts},
                                                          {kBindingGridKeys, &f.keys},
                                                          {kBindingGridOwners, &f.owners},
                                                          {kBindingPerception, &perception_}}));
    f.scatter.set_buffers({{kBindingBirds, &birds_},
                           {kBindingGridPlace, &f.place},
                           {kBindingGridStarts, &f.starts},
                           {kBindingGridBlocks, &f.blocks},
                           {kBindingGridPoints, &f.points},
                           {kBindingGridSeen, &f.seen}});
  }
}

// The birds see their flock (the frame's start): the grid is built (each bird's cell's slot and a
// counting sort: count, prefix sum in two levels, scatter; each slot's range and bounds), then each
// due bird searches it; a barrier between each.
void GpuSimulation::record_perception(VkCommandBuffer cmd, Slot& slot, const StepConstants& c,
                                      Timestamps* timestamps, uint32_t first) {
  Flocking& f = *flocking_;
  // The last frame's passes (several frames a submission) are done with the grid before it is
  // cleared.
  barrier_to_transfer(cmd);
  // The slots the table takes now (its sides), every one empty.
  const VkDeviceSize slots = f.table.slots();
  vkCmdFillBuffer(cmd, f.counts.handle(), 0, slots * sizeof(uint32_t), 0u);
  vkCmdFillBuffer(cmd, f.owners.handle(), 0, slots * sizeof(uint32_t), kNoBird);
  vkCmdFillBuffer(cmd, f.keys.handle(), 0, slots * sizeof(glm::ivec4), uint32_t(kNoFlock));
  barrier_to_compute(cmd);
  const uint32_t groups = group_count(count_, kWorkgroupSize);
  f.count.dispatch(cmd, groups, &c, sizeof c);
  barrier_to_compute(cmd);
  f.scan_blocks.dispatch(cmd, f.table.slots() / kScanBlock, &c, sizeof c);
  barrier_to_compute(cmd);
  f.scan_totals.dispatch(cmd, 1, &c, sizeof c);
  barrier_to_compute(cmd);
  f.scatter.dispatch(cmd, groups, &c, sizeof c);
  barrier_to_compute(cmd);
  f.cells_pass.dispatch(cmd, groups, &c, sizeof c);
  barrier_to_compute(cmd);
  if (timestamps) timestamps->write(cmd, first + 1);
  f.perceive.dispatch(cmd, slot.perceive_set, groups, &c, sizeof c);
  barrier_to_compute(cmd);
  if (timestamps) timestamps->write(cmd, first + 2);
}

// A frame's timestamps: its start, the grid built, the perception done, the steps done.
constexpr uint32_t kTimestampsPerFrame = 4;

bool GpuSimulation::time_passes() {
  if (!Timestamps::supported(device_)) return false;
  for (Slot& slot : slots_)
    if (!slot.timestamps)
      slot.timestamps =
          std::make_unique<Timestamps>(device_, frames_per_submission_ * kTimestampsPerFrame);
  return true;
}

void GpuSimulation::collect_all() {
  if (last_ < 0) return;
  submitter_.wait_all();
  collect(slots_[1 - last_]);  // the older first
  collect(slots_[last_]);
}

const std::vector<GpuSimulation::PassTimes>& GpuSimulation::pass_times() {
  collect_all();
  // A snapshot may have read the last submission's before the one before.
  std::sort(pass_times_.begin(), pass_times_.end(),
            [](const PassTimes& a, const PassTimes& b) { return a.frame < b.frame; });
  return pass_times_;
}

GpuSimulation::Searches GpuSimulation::searches() {
  collect_all();
  return searches_;
}

void GpuSimulation::collect(Slot& slot) {
  if (!slot.counted && slot.fence != VK_NULL_HANDLE) {
    const auto* counts = reinterpret_cast<const uint32_t*>(slot.cut_short.mapped());
    for (uint32_t b = 0; b < kReachBins; ++b) searches_.sampled += counts[2 + b];
    searches_.again += counts[2 + kReachBins];
    slot.counted = true;
  }
  if (slot.timed_frames == 0) return;
  const std::vector<double> ns = slot.timestamps->read_ns(slot.timed_frames * kTimestampsPerFrame);
  for (uint32_t f = 0; f < slot.timed_frames; ++f) {
    const double* t = &ns[f * kTimestampsPerFrame];
    if (flocking_)
      pass_times_.push_back(
          {slot.first_frame + f, (t[1] - t[0]) * 1e-6, (t[2] - t[1]) * 1e-6, (t[3] - t[2]) * 1e-6});
    else  // its middle two mark no pass (a device's clock may still move between them)
      pass_times_.push_back({slot.first_frame + f, 0.0, 0.0, (t[3] - t[0]) * 1e-6});
  }
  slot.timed_frames = 0;
}

std::vector<Bound> GpuSimulation::world_buffers(const Buffer& targets,
                                                std::initializer_list<Bound> more) const {
  std::vector<Bound> all = {{kBindingBirds, &birds_},      {kBindingIds, &ids_},
                            {kBindingSpecies, &species_},  {kBindingTargets, &targets},
                            {kBindingRoutes, &routes_},    {kBindingRouteTargets, &route_targets_},
                            {kBindingBranches, &branches_}};
  all.insert(all.end(), more);
  return all;
}

std::string GpuSimulation::device() const { return device_.name() + " (" + device_.driver() + ")"; }

// The forces pipeline and buffers, made the first time a frame records forces (the buffers are
// as large as the flock's state again, three times over).
void GpuSimulation::prepare_forces() {
  if (step_forces_) return;
  const VkDeviceSize bytes = std::max<VkDeviceSize>(capacity_, 1) * sizeof(GpuForces);
  check_storage_size(device_, bytes, sizeof(GpuForces), "birds' forces");
  forces_ = std::make_unique<Buffer>(device_, bytes, Memory::device_local);
  step_forces_ = std::make_unique<ComputePipeline>(
      device_, shader_spirv("step_forces"),
      world_and({kBindingPerception, kBindingForces, kBindingCutShort}), sizeof(StepConstants), 2,
      model_constants_);
  for (Slot& slot : slots_) {
    slot.forces = std::make_unique<Buffer>(device_, bytes, Memory::host);
    slot.forces_set =
        step_forces_->make_set(world_buffers(slot.targets, {{kBindingPerception, &perception_},
                                                            {kBindingForces, forces_.get()},
                                                            {kBindingCutShort, &slot.cut_short}}));
  }
}

void GpuSimulation::set_steps_per_dispatch(uint32_t steps) {
  if (steps < 1) throw std::invalid_argument("steps per dispatch: 0");
  steps_per_dispatch_ = steps;
}

size_t GpuSimulation::Flocking::cell_index() const {
  return static_cast<size_t>(std::find(cells.begin(), cells.end(), shape.cell) - cells.begin());
}

void GpuSimulation::fit_grid_cell(const Slot& slot) {
  if (!flocking_) return;
  Flocking& f = *flocking_;
  SearchReach reach;
  std::memcpy(reach.count.data(), reinterpret_cast<const uint32_t*>(slot.cut_short.mapped()) + 2,
              sizeof(reach.count));
  const double cell = grid_cell_for(reach, f.cells);
  if (cell > 0.0) f.shape.cell = cell;  // else no search reached: keep the cell
}

void GpuSimulation::fit_grid_table(std::span<const GpuBird> birds) {
  if (!flocking_) return;
  Flocking& f = *flocking_;
  // Its outermost birds search a cell or two past them: a grid's cell is about the reach of a
  // bird's search (grid_cell_for).
  constexpr int kMargin = 2;
  f.table = grid_table_for(flock_extents(birds, f.shape.cell, uint32_t(scenario().flocks.size())),
                           kMargin, f.least_bits, f.most_bits);
}

void GpuSimulation::check_cut_short(const Slot& slot) const {
  const auto* cut = reinterpret_cast<const uint32_t*>(slot.cut_short.mapped());
  if (cut[0] > 0)
    throw Error(device() + " ended the steps of " + std::to_string(cut[0]) + " of " +
                std::to_string(count_) +
                " birds early (a limit of the driver's on a shader's loops; dispatches of " +
                std::to_string(steps_per_dispatch_) + " steps at most): frame " +
                std::to_string(slot.snapshot.frame) + "'s state is wrong");
  if (cut[1] > 0)
    throw Error(device() + " ended the neighbour search of " + std::to_string(cut[1]) + " of " +
                std::to_string(count_) +
                " birds early (a limit of the driver's on a shader's loops: a cell of the grid "
                "holds more birds than a search can look through): frame " +
                std::to_string(slot.snapshot.frame) + "'s perception is wrong");
}

void GpuSimulation::step(uint32_t steps, bool record_forces) {
  submit_frames(1, steps, record_forces);
}

void GpuSimulation::step_frames(uint32_t frames) {
  while (frames > 0) {
    const uint32_t n = std::min(frames, frames_per_submission_);
    submit_frames(n, scenario().steps_per_frame, false);
    frames -= n;
  }
}

void GpuSimulation::submit_frames(uint32_t frames, uint32_t steps, bool record_forces) {
  if (record_forces) prepare_forces();
  if (last_ >= 0 && slots_[1 - last_].fence != VK_NULL_HANDLE) {  // the slot about to be reused
    Slot& reused = slots_[1 - last_];
    submitter_.wait(reused.fence);  // as begin() would
    check_cut_short(reused);        // before its count is cleared
    fit_grid_cell(reused);
    if (reused.loads == loads_)  // else load() fitted the table to newer birds
      fit_grid_table({reinterpret_cast<const GpuBird*>(reused.readback.mapped()), reused.copied});
    collect(reused);
    std::memset(reused.cut_short.mapped(), 0, reused.cut_short.size());
  }
  VkCommandBuffer cmd = submitter_.begin();  // waits for this slot's previous submission only
  Slot& slot = slots_[submitter_.frame()];
  Timestamps* timestamps = slot.timestamps.get();
  if (timestamps) timestamps->reset(cmd, frames * kTimestampsPerFrame);
  slot.first_frame = this->frames() + 1;
  auto* targets_of = reinterpret_cast<GpuTarget*>(slot.targets.mapped());
  const uint32_t targets_count = uint32_t(world().targets.size());
  const uint32_t per_frame =
      2 * targets_count;  // a frame's targets at its start, then at the next's
  StepConstants c{};      // what every frame of the submission shares; the loop sets the rest
  c.wind_ground = vec4(vec3(world().wind), float(world().ground_height));
  c.dt = float(scenario().dt);
  c.frame_steps = steps;
  c.bird_count = count_;
  c.turning = uint32_t(world().turning);
  c.ground_effect = world().ground_effect ? 1u : 0u;
  c.next_targets = targets_count;
  c.flocking = flocking_ ? 1u : 0u;
  c.frame_seconds = float(scenario().frame_seconds());
  c.rest_steps = whole_steps(kRestAfterTouchdown, scenario().dt);
  c.wind_profile = uint32_t(world().wind_profile);
  c.wind_height = float(world().wind_height);
  c.wind_exponent = float(world().wind_exponent);
  c.wind_roughness = float(world().wind_roughness);
  if (flocking_) {
    const Flocking& f = *flocking_;
    c.grid_cell = float(f.shape.cell);
    c.buckets = f.table.slots();
    c.grid_bits = f.table.packed();
    const size_t k = f.cell_index();
    c.search_first = f.search_first[k];
    c.search_cells = f.search_cells[k];
  }
  for (uint32_t f = 0; f < frames; ++f) {
    const double start = begin_frame();
    // The targets where they are at the frame's start, then where the next frame sees them (for
    // the recorded forces), in this slot's buffer (the other slot's frames may still read theirs).
    std::vector<GpuTarget> targets = pack_targets(world(), start);
    const std::vector<GpuTarget> next = pack_targets(world(), frame_start(this->steps() + steps));
    targets.insert(targets.end(), next.begin(), next.end());
    if (!targets.empty())
      std::memcpy(targets_of + f * per_frame, targets.data(), targets.size() * sizeof(GpuTarget));

    c.step = uvec2(uint32_t(this->steps()), uint32_t(this->steps() >> 32));
    c.frame = uint32_t(this->frames() - 1);
    c.targets_base = f * per_frame;
    barrier_to_compute(cmd);  // after the frame before: its stepping, or the host's writes
    const uint32_t first_timestamp = f * kTimestampsPerFrame;
    if (timestamps) timestamps->write(cmd, first_timestamp);
    if (flocking_) {
      record_perception(cmd, slot, c, timestamps, first_timestamp);
    } else if (timestamps) {  // no grid, no perception: written, as every query read must be
      timestamps->write(cmd, first_timestamp + 1);
      timestamps->write(cmd, first_timestamp + 2);
    }
    // The frame's steps, at most steps_per_dispatch_ a dispatch (kMaxStepsPerDispatch); a frame
    // of 0 steps is one dispatch still (it retiles, it may record forces).
    for (uint32_t first = 0;;) {
      c.first_step = first;
      c.steps = std::min(steps - first, steps_per_dispatch_);
      if (first > 0) barrier_to_compute(cmd);  // after the part before
      if (record_forces)
        step_forces_->dispatch(cmd, slot.forces_set, group_count(count_, kWorkgroupSize), &c,
                               sizeof c);
      else
        step_.dispatch(cmd, slot.set, group_count(count_, kWorkgroupSize), &c, sizeof c);
      first += c.steps;
      if (first == steps) break;
    }
    if (timestamps) timestamps->write(cmd, first_timestamp + 3);
    end_frame(steps);
  }
  // The birds there are (a share has room for more), at least one element: a copy is never empty.
  const VkDeviceSize birds = std::max<VkDeviceSize>(count_, 1);
  record_readback(cmd, birds_, slot.readback, birds * sizeof(GpuBird));
  if (record_forces) record_readback(cmd, *forces_, *slot.forces, birds * sizeof(GpuForces));
  if (flocking_) record_readback(cmd, perception_, *slot.perception, birds * sizeof(GpuPerception));
  slot.fence = submitter_.submit();
  slot.timed_frames = timestamps ? frames : 0;

  slot.snapshot = {this->frames(), this->steps(), time(), nullptr, nullptr};
  slot.unpacked = false;
  slot.counted = false;
  slot.copied = count_;
  slot.loads = loads_;
  slot.has_forces = record_forces;
  last_ = static_cast<int>(submitter_.frame());
}

uint64_t GpuSimulation::ready_frame() const {
  if (last_ < 0) return frames();
  const Slot& other = slots_[1 - last_];
  // Before a second submission the last is the only one: waited for.
  return other.fence == VK_NULL_HANDLE ? frames() : other.snapshot.frame;
}

Snapshot GpuSimulation::read(Slot& slot) {
  if (!slot.unpacked) {
    submitter_.wait(slot.fence);
    check_cut_short(slot);
    collect(slot);
    const auto* gpu = reinterpret_cast<const GpuBird*>(slot.readback.mapped());
    slot.birds.resize(count_);
    for (uint32_t i = 0; i < count_; ++i) slot.birds[i] = unpack(gpu[i]);
    if (slot.has_forces) {
      const auto* f = reinterpret_cast<const GpuForces*>(slot.forces->mapped());
      slot.step_forces.resize(count_);
      for (uint32_t i = 0; i < count_; ++i) slot.step_forces[i] = unpack(f[i]);
    }
    if (flocking_) {
      const auto* p = reinterpret_cast<const GpuPerception*>(slot.perception->mapped());
      slot.perception_state.resize(count_);
      for (uint32_t i = 0; i < count_; ++i) slot.perception_state[i] = unpack(p[i]);
    }
    slot.unpacked = true;
  }
  Snapshot s = slot.snapshot;
  s.birds = &slot.birds;
  s.forces = slot.has_forces ? &slot.step_forces : nullptr;
  s.perception = flocking_ ? &slot.perception_state : nullptr;
  return s;
}

void GpuSimulation::load(std::span<const GpuBird> birds, std::span<const GpuPerception> perception,
                         std::span<const uint32_t> ids) {
  if (birds.size() > capacity_ || ids.size() != birds.size() ||
      (flocking_ && perception.size() != birds.size()))
    throw std::logic_error("GpuSimulation::load: " + std::to_string(birds.size()) + " birds, " +
                           std::to_string(ids.size()) + " ids, " +
                           std::to_string(perception.size()) + " perceptions for room for " +
                           std::to_string(capacity_));
  submitter_.wait_all();
  count_ = static_cast<uint32_t>(birds.size());
  if (birds.empty()) return;
  birds_.upload(std::as_bytes(birds));
  ids_.upload(std::as_bytes(ids));
  if (flocking_) perception_.upload(std::as_bytes(perception));
  ++loads_;
  fit_grid_table(birds);
}

GpuSimulation::Raw GpuSimulation::raw() {
  if (last_ < 0) throw std::logic_error("GpuSimulation::raw before the first step");
  Slot& slot = slots_[last_];
  submitter_.wait(slot.fence);
  check_cut_short(slot);
  collect(slot);
  Raw r;
  r.birds = {reinterpret_cast<const GpuBird*>(slot.readback.mapped()), count_};
  if (flocking_)
    r.perception = {reinterpret_cast<const GpuPerception*>(slot.perception->mapped()), count_};
  if (slot.has_forces)
    r.forces = {reinterpret_cast<const GpuForces*>(slot.forces->mapped()), count_};
  return r;
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
