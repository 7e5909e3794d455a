// The flock on the GPU: the CPU reference's state, species and world packed into the layouts of
// host_device.h (floats on the device, doubles in the reference), and back.
#pragma once

#include <span>
#include <vector>

#include <glm/vec2.hpp>

#include "gpu/host_device.h"
#include "model/bird.h"
#include "model/flock.h"
#include "model/scenario.h"
#include "model/species.h"
#include "model/step.h"
#include "model/wake.h"
#include "model/world.h"

namespace aeroflock::gpu {

// World tiles (host_device.h): the tile a world point is over, and that tile's centre.
inline constexpr double kTile = double(1u << kTileLog2);  // cm
struct Tiled {
  glm::ivec2 tile;    // x, z
  glm::dvec3 centre;  // world, cm (y 0)
};
Tiled tiled(const glm::dvec3& world);
glm::dvec3 tile_centre(int tile_x, int tile_z);

GpuBird pack(const BirdState& b);
BirdState unpack(const GpuBird& g);
GpuSpecies pack(const Species& s);
StepForces unpack(const GpuForces& g);
GpuPerception pack(const Perception& p);
// Its position as it is (the wake's test probes it near the origin).
GpuWakeSource pack(const WakeSource& w);
WakeSource unpack(const GpuWakeSource& g);
Perception unpack(const GpuPerception& g);

// The world's static tables (targets move between frames: pack_targets).
struct GpuWorld {
  std::vector<GpuRoute> routes;
  std::vector<uint32_t> route_targets;
  std::vector<GpuBranch> branches;
};
GpuWorld pack(const World& w);
GpuTarget pack_target(const Target& t, const glm::dvec3& centre);  // the target at `centre`
std::vector<GpuTarget> pack_targets(const World& w, double time);

// The model's specialisation constants for a flock of `birds` in `scenario`, by constant_id
// (host_device.h: kConstantWakes...): what its birds can reach. A bird brakes for a branch only on
// a route to one, so kConstantBranches is off where no route has one and none of `birds` brakes
// already (an MPI rank's `birds` are a bird of each kind; the rest come from the same routes).
std::vector<uint32_t> model_constants(const Scenario& scenario, std::span<const BirdState> birds);

}  // namespace aeroflock::gpu
