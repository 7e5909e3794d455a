// The flock's buffers (engine/gpu/host_device.h declares their contents and bindings).
#include "gpu/host_device.h"

// The render shaders only read the birds: they define BIRDS_ACCESS as readonly.
#ifndef BIRDS_ACCESS
#define BIRDS_ACCESS
#endif
layout(std430, set = 0, binding = kBindingBirds) BIRDS_ACCESS buffer Birds { GpuBird birds[]; };
layout(std430, set = 0, binding = kBindingSpecies) readonly buffer SpeciesTable {
  GpuSpecies species[];
};
layout(std430, set = 0, binding = kBindingTargets) readonly buffer Targets { GpuTarget targets[]; };
layout(std430, set = 0, binding = kBindingRoutes) readonly buffer Routes { GpuRoute routes[]; };
layout(std430, set = 0, binding = kBindingRouteTargets) readonly buffer RouteTargets {
  uint route_targets[];
};
layout(std430, set = 0, binding = kBindingBranches) readonly buffer Branches {
  GpuBranch branches[];
};

// A perception of no one (flock.h: Perception{}).
GpuPerception no_perception() {
  GpuPerception p;
  p.direction = vec3(0.0);
  p.airspeed = 0.0;
  p.neighbours = 0u;
  p.nearest = 0.0;
  p.seen_key = 0u;
  p.wakes = 0u;
  p.wake_step = 0u;
  p.wake_tile_x = 0;
  p.wake_tile_z = 0;
  p.phase_rate = 0.0;
  for (uint k = 0u; k < kGpuWakeSources; ++k)
    p.wake[k] = GpuWakeSource(vec4(0.0), vec4(0.0), vec4(0.0), vec4(0.0));
  return p;
}
