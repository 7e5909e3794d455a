#version 450
// The wake's field at given points (wake.glsl), for its test against the CPU reference
// (tests/test_wake_vulkan.cpp): velocity[i] = the wake of sources[i] at points[i].
#extension GL_GOOGLE_include_directive : require
#include "gpu/host_device.h"
layout(local_size_x = 64) in;
layout(std430, set = 0, binding = 0) readonly buffer SpeciesTable { GpuSpecies species[]; };
layout(std430, set = 0, binding = 1) readonly buffer Sources { GpuWakeSource sources[]; };
layout(std430, set = 0, binding = 2) readonly buffer Points { vec4 points[]; };
layout(std430, set = 0, binding = 3) writeonly buffer Velocities { vec4 velocities[]; };
layout(push_constant) uniform Push { uint n; };
#include "bird.glsl"
#include "wingbeat.glsl"
#include "wake.glsl"

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i < n) velocities[i] = vec4(wake_velocity(species[0], sources[i], points[i].xyz), 0.0);
}
