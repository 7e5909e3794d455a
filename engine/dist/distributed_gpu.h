// One flock over many MPI ranks on the Vulkan backend: each rank steps its own birds on a device of
// its own with the compute shaders, bird for bird the same as GpuSimulation on one device
// (docs/DISTRIBUTED.md "The Vulkan backend").
#pragma once

#include <memory>
#include <string>
#include <vector>

#include <mpi.h>

#include "dist/distributed.h"
#include "gpu/device.h"
#include "gpu/gpu_simulation.h"
#include "gpu/host_device.h"

namespace aeroflock::dist {

class DistributedGpuSimulation final : public DistributedSimulation {
 public:
  // Room for this many birds and ghosts at least: a share that starts small grows less often.
  static constexpr uint32_t kLeastCapacity = 1024;

  // Every bird spawned as one rank would, or bird k of `all` with global id k (every rank the
  // same); this rank's on `device`, which it keeps. Its share starts with room for half again its
  // birds, at least `least_capacity` (tests make it small, so that shares grow). Throws
  // std::runtime_error for a flock of kGhostBird or more birds (the ids' flag).
  DistributedGpuSimulation(std::unique_ptr<gpu::Device> device, Scenario scenario, MPI_Comm comm,
                           uint32_t birds_override = 0, uint32_t least_capacity = kLeastCapacity);
  DistributedGpuSimulation(std::unique_ptr<gpu::Device> device, Scenario scenario, MPI_Comm comm,
                           const std::vector<BirdState>& all,
                           uint32_t least_capacity = kLeastCapacity);
  ~DistributedGpuSimulation() override;

  std::string backend() const override { return "vulkan"; }
  std::string device() const override;
  // Each frame: migrants and ghosts exchanged from the state the last frame read back, this
  // rank's birds and its ghosts loaded on the device in id order, the frame stepped there (the
  // ghosts perceived, never stepped) and read back. It waits for the device: a frame's exchange
  // needs the last frame's state.
  void step(uint32_t steps, bool record_forces = false) override;
  void prepare_forces() override;
  // The birds and ghosts the device has room for (it grows by half again when a frame needs more,
  // up to what the device holds).
  uint32_t capacity() const { return engine_->capacity(); }
  // How many times the share was made again larger.
  uint32_t growths() const { return growths_; }

  // What a rank keeps of each of its birds beside its state: the device's own state of it (its
  // world tile and float offset, not re-tiled by a round trip through BirdState) and its last
  // perception.
  struct OnDevice {
    gpu::GpuBird bird;
    gpu::GpuPerception perception;
  };

 private:
  void start();
  // Room for `birds` birds and ghosts and half again, at least least_capacity_, at most what the
  // device holds (never less than `birds`: a share that does not fit fails as it is made).
  uint32_t room_for(size_t birds) const;
  // A device share with room for `capacity` birds and ghosts, continuing this run's clock; the
  // last one stays when it cannot be made.
  void make_engine(uint32_t capacity);
  // Loads this rank's birds and `ghosts` (a vector of a ghost type, ordered by id) on the device,
  // merged by id; returns where each of this rank's birds went in its buffer.
  template <class Ghosts>
  std::vector<uint32_t> load_among(const Ghosts& ghosts);

  std::unique_ptr<gpu::Device> device_;
  std::unique_ptr<gpu::GpuSimulation> engine_;
  bool forces_prepared_ = false;
  uint32_t least_capacity_;
  uint32_t growths_ = 0;
  std::vector<OnDevice> on_device_;  // one per bird of this rank, in order
};

// The Vulkan device of this rank of `comm` (collective): device `index` where it is >= 0, else the
// node's devices of the preferred kind (a discrete GPU, else integrated, virtual, a CPU) dealt to
// its ranks in turn (the node-local rank modulo their count). The ranks of a node share its cores
// on a CPU device: LP_NUM_THREADS (lavapipe's threads), unless set, is the cores over the node's
// ranks.
std::unique_ptr<gpu::Device> rank_device(MPI_Comm comm, int index);

}  // namespace aeroflock::dist
