#version 450
// One frame of the flock: each invocation steps one bird `steps` times with the fixed dt, its
// state in registers throughout, and writes it back once.
#extension GL_GOOGLE_include_directive : require

layout(local_size_x = 64) in;

#include "layout.glsl"
#include "constants.glsl"
#include "model.glsl"

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= pc.bird_count) return;
  Bird b = unpack(birds[i]);
  Species s = species[b.species];
  Leg leg = load_leg(b);
  for (uint k = 0u; k < pc.steps; ++k) step_bird(b, s, leg, pc.time + float(k) * pc.dt, pc.dt);
  birds[i] = pack(b);
}
