// The flock on the GPU: the CPU reference's state, species and world packed into the layouts of
// host_device.h (floats on the device, doubles in the reference), and back.
#pragma once

#include <vector>

#include "gpu/host_device.h"
#include "model/bird.h"
#include "model/flock.h"
#include "model/species.h"
#include "model/step.h"
#include "model/world.h"

namespace aeroflock::gpu {

GpuBird pack(const BirdState& b);
BirdState unpack(const GpuBird& g);
GpuSpecies pack(const Species& s);
StepForces unpack(const GpuForces& g);
GpuPerception pack(const Perception& p);
Perception unpack(const GpuPerception& g);

// The world's static tables (targets move between frames: pack_targets).
struct GpuWorld {
  std::vector<GpuRoute> routes;
  std::vector<uint32_t> route_targets;
  std::vector<GpuBranch> branches;
};
GpuWorld pack(const World& w);
std::vector<GpuTarget> pack_targets(const World& w, double time);

}  // namespace aeroflock::gpu
