#include "dist/distributed_gpu.h"

#include <algorithm>
#include <cstdlib>
#include <stdexcept>
#include <string>
#include <thread>
#include <type_traits>

#include "dist/exchange.h"
#include "gpu/buffer.h"
#include "gpu/layout.h"

namespace aeroflock::dist {
namespace {

using gpu::GpuBird;
using gpu::GpuPerception;

// A bird another rank's device perceives: what the grid and the search read of it (grid_count.comp,
// flock.glsl: its flock and whether it flocks now, its tile, place and velocity), 56 bytes instead
// of the device state's whole.
struct DeviceGhost {
  uint32_t id;
  uint32_t species, flock, flocking, mode, landing_stage;
  int32_t tile_x, tile_z;
  float position[3], velocity[3];

  static DeviceGhost of(uint32_t id, const GpuBird& b) {
    return {id,
            b.species,
            b.flock,
            b.flocking,
            b.mode,
            b.landing_stage,
            b.tile_x,
            b.tile_z,
            {b.position.x, b.position.y, b.position.z},
            {b.velocity.x, b.velocity.y, b.velocity.z}};
  }
  // As the device's state of a bird: these fields, the rest a new bird's.
  GpuBird bird() const {
    static const GpuBird blank = gpu::pack(BirdState{});
    GpuBird b = blank;
    b.species = species, b.flock = flock, b.flocking = flocking;
    b.mode = mode, b.landing_stage = landing_stage;
    b.tile_x = tile_x, b.tile_z = tile_z;
    b.position = {position[0], position[1], position[2]};
    b.velocity = {velocity[0], velocity[1], velocity[2]};
    return b;
  }
};
// A ghost in a run whose flocks meet wakes: also what a neighbour's wake follows from (flock.glsl
// see_wakes: its attitude, lift and wingbeat), 88 bytes.
struct DeviceWakeGhost : DeviceGhost {
  float attitude[4];  // x, y, z, w
  float lift, phase, frequency, amplitude;

  static DeviceWakeGhost of(uint32_t id, const GpuBird& b) {
    return {DeviceGhost::of(id, b),
            {b.attitude.x, b.attitude.y, b.attitude.z, b.attitude.w},
            b.lift,
            b.phase,
            b.frequency,
            b.amplitude};
  }
  GpuBird bird() const {
    GpuBird b = DeviceGhost::bird();
    b.attitude = {attitude[0], attitude[1], attitude[2], attitude[3]};
    b.lift = lift, b.phase = phase, b.frequency = frequency, b.amplitude = amplitude;
    return b;
  }
};
static_assert(sizeof(DeviceGhost) == 56 && sizeof(DeviceWakeGhost) == 88, "no padding sent unset");
static_assert(std::is_trivially_copyable_v<DeviceWakeGhost> &&
              std::is_trivially_copyable_v<DistributedGpuSimulation::OnDevice>);

// The device sees in float what the reference sees in double: a bird at the edge of the blind
// sector may be seen by one and not the other. The depth a rank asks for past its cuts is taken
// with a blind sector this much wider (radians), by far more than float's rounding of its angle.
constexpr double kFloatBlindMargin = 1e-3;

}  // namespace

DistributedGpuSimulation::DistributedGpuSimulation(std::unique_ptr<gpu::Device> device,
                                                   Scenario scenario, MPI_Comm comm,
                                                   uint32_t birds_override, uint32_t least_capacity)
    : DistributedSimulation(std::move(scenario), comm),
      device_(std::move(device)),
      least_capacity_(least_capacity) {
  place(spawned(this->scenario(), birds_override));
  start();
}

DistributedGpuSimulation::DistributedGpuSimulation(std::unique_ptr<gpu::Device> device,
                                                   Scenario scenario, MPI_Comm comm,
                                                   const std::vector<BirdState>& all,
                                                   uint32_t least_capacity)
    : DistributedSimulation(std::move(scenario), comm),
      device_(std::move(device)),
      least_capacity_(least_capacity) {
  place(given(all));
  start();
}

DistributedGpuSimulation::~DistributedGpuSimulation() = default;

void DistributedGpuSimulation::start() {
  // A global id carries kGhostBird on the device for a ghost: every rank knows the count, and
  // every one refuses alike.
  if (total_birds() >= gpu::kGhostBird)
    throw std::runtime_error(std::to_string(total_birds()) +
                             " birds over ranks on Vulkan: at most " +
                             std::to_string(gpu::kGhostBird - 1) + " (the ids' ghost flag)");
  blind_margin_ = kFloatBlindMargin;
  // As GpuSimulation packs a flock, each bird's perception none yet.
  const GpuPerception none = gpu::pack(Perception{});
  on_device_.reserve(birds_.size());
  for (const BirdState& b : birds_) on_device_.push_back({gpu::pack(b), none});
  perception_.assign(birds_.size(), Perception{});
  // A share of the flock that the device cannot hold fails now, naming the limit.
  make_engine(room_for(birds_.size()));
}

uint32_t DistributedGpuSimulation::room_for(size_t birds) const {
  const uint64_t most = std::min<uint64_t>(
      {gpu::storage_capacity(*device_, sizeof(GpuBird)),
       uint64_t(device_->limits().maxComputeWorkGroupCount[0]) * gpu::kWorkgroupSize,
       gpu::kGhostBird});
  const uint64_t room = std::max<uint64_t>(least_capacity_, birds + birds / 2);
  return static_cast<uint32_t>(std::max<uint64_t>(std::min(room, most), birds));
}

void DistributedGpuSimulation::make_engine(uint32_t capacity) {
  auto engine = std::make_unique<gpu::GpuSimulation>(*device_, scenario(), kinds_, capacity);
  engine->continue_clock(steps(), frames());
  if (forces_prepared_) engine->prepare_forces();
  if (engine_) ++growths_;
  engine_ = std::move(engine);
}

std::string DistributedGpuSimulation::device() const {
  return engine_->device() + " (rank " + std::to_string(rank_) + "'s) on " +
         std::to_string(ranks_) + " MPI ranks, a device each";
}

void DistributedGpuSimulation::prepare_forces() {
  forces_prepared_ = true;
  engine_->prepare_forces();
}

void DistributedGpuSimulation::step(uint32_t steps, bool record_forces) {
  const uint64_t frame = frames();  // this frame's number, as perceive.comp counts it
  forces_current_ = false;          // until this frame's are read back
  rebalance_if_due();
  migrate(on_device_);
  perception_.resize(birds_.size());  // set again from the device below
  const std::vector<uint32_t> mine =
      !flocking_ ? load_among(std::vector<DeviceGhost>{})
      : wakes_   ? load_among(exchange_ghosts<DeviceWakeGhost>(
                     frame,
                     [this](size_t k) { return DeviceWakeGhost::of(ids_[k], on_device_[k].bird); }))
                 : load_among(exchange_ghosts<DeviceGhost>(frame, [this](size_t k) {
                   return DeviceGhost::of(ids_[k], on_device_[k].bird);
                 }));

  begin_frame();
  engine_->step(steps, record_forces);
  const gpu::GpuSimulation::Raw after = engine_->raw();
  forces_.resize(record_forces ? birds_.size() : 0);
  for (size_t k = 0; k < birds_.size(); ++k) {
    const uint32_t at = mine[k];
    on_device_[k].bird = after.birds[at];
    birds_[k] = gpu::unpack(after.birds[at]);
    if (flocking_) {
      on_device_[k].perception = after.perception[at];
      perception_[k] = gpu::unpack(after.perception[at]);
    }
    if (record_forces) forces_[k] = gpu::unpack(after.forces[at]);
  }
  forces_current_ = record_forces;
  end_frame(steps);
}

template <class Ghosts>
std::vector<uint32_t> DistributedGpuSimulation::load_among(const Ghosts& ghosts) {
  // This rank's birds and its ghosts, by id: ties among neighbours go by buffer index on the
  // device, so that is by global id, as on one device.
  std::vector<GpuBird> birds;
  std::vector<GpuPerception> perception;
  std::vector<uint32_t> ids, mine;
  const size_t n = birds_.size() + ghosts.size();
  birds.reserve(n), perception.reserve(flocking_ ? n : 0), ids.reserve(n), mine.reserve(n);
  const GpuPerception none = gpu::pack(Perception{});
  merge_by_id(
      ids_, ghosts,
      [&](size_t k) {
        mine.push_back(static_cast<uint32_t>(birds.size()));
        birds.push_back(on_device_[k].bird), ids.push_back(ids_[k]);
        if (flocking_) perception.push_back(on_device_[k].perception);
      },
      [&](size_t g) {
        birds.push_back(ghosts[g].bird()), ids.push_back(ghosts[g].id | gpu::kGhostBird);
        if (flocking_) perception.push_back(none);
      });
  if (n > engine_->capacity()) make_engine(room_for(n));
  engine_->load(birds, perception, ids);
  return mine;
}

std::unique_ptr<gpu::Device> rank_device(MPI_Comm comm, int index) {
  MPI_Comm node;
  MPI_Comm_split_type(comm, MPI_COMM_TYPE_SHARED, 0, MPI_INFO_NULL, &node);
  int local = 0, locals = 1;
  MPI_Comm_rank(node, &local);
  MPI_Comm_size(node, &locals);
  MPI_Comm_free(&node);
  // Before any Vulkan instance: lavapipe reads it when it enumerates.
  const unsigned cores = std::max(1u, std::thread::hardware_concurrency());
  setenv("LP_NUM_THREADS", std::to_string(std::max(1u, cores / unsigned(locals))).c_str(), 0);
  if (index < 0) {
    const std::vector<gpu::DeviceInfo> all = gpu::Device::list_devices();
    int best = 5;  // past every kind
    for (const gpu::DeviceInfo& d : all) best = std::min(best, gpu::preference(d.type));
    std::vector<uint32_t> kind;
    for (const gpu::DeviceInfo& d : all)
      if (gpu::preference(d.type) == best) kind.push_back(d.index);
    if (!kind.empty()) index = static_cast<int>(kind[size_t(local) % kind.size()]);
  }
  return std::make_unique<gpu::Device>(gpu::headless(index, false));
}

}  // namespace aeroflock::dist
