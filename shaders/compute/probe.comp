#version 450
// One step of each bird, with the step's forces written out: the cross-check against the CPU
// reference's StepForces.
#extension GL_GOOGLE_include_directive : require

layout(local_size_x = 64) in;

#include "layout.glsl"
#include "constants.glsl"
#include "model.glsl"

struct ProbeForces {
  vec4 total;        // world, dyn
  vec4 torque;       // body, dyn cm
  vec4 tail;         // world, dyn
  vec4 tail_torque;  // body, dyn cm
};
layout(std430, set = 0, binding = 6) writeonly buffer Probes { ProbeForces probes[]; };

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= pc.bird_count) return;
  Bird b = unpack(birds[i]);
  Leg leg = load_leg(b);
  Forces f = step_bird(b, species[b.species], leg, pc.time, pc.dt);
  birds[i] = pack(b);
  probes[i] = ProbeForces(vec4(f.total, 0.0), vec4(f.torque, 0.0), vec4(f.tail, 0.0), vec4(f.tail_torque, 0.0));
}
