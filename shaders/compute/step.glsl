// One frame of the flock: each invocation steps one bird `steps` times with the fixed dt, its
// state in registers throughout, and writes it back once. step.comp is this; step_forces.comp
// (RECORD_FORCES) also writes the forces of the step each bird takes next (the exporters' and the
// cross-check's forces): a pipeline of its own, so that the plain step carries none of it.

#include "buffers.glsl"

layout(local_size_x = kWorkgroupSize) in;
layout(push_constant) uniform StepPush { StepConstants pc; };  // model.glsl reads pc
layout(std430, set = 0, binding = kBindingPerception) readonly buffer Perceptions { GpuPerception perception[]; };
#ifdef RECORD_FORCES
layout(std430, set = 0, binding = kBindingForces) writeonly buffer Forces { GpuForces forces_out[]; };
#endif

#include "model.glsl"

// Moves the bird into the tile its position is now over, by whole tiles (exact: host_device.h),
// with the points it carries, once a frame: its offset stays within about half a tile. Not while
// it lands: its curve's via point is compared with the perch point bit for bit (model.glsl).
void retile(inout GpuBird b) {
  vec2 tiles = round(b.position.xz / kTile);
  if (tiles == vec2(0.0) || b.landing_stage != stage_none) return;
  vec3 shift = vec3(tiles.x, 0.0, tiles.y) * kTile;
  b.position -= shift;
  b.landing_start -= shift;
  b.via_point -= shift;
  b.tile_x += int(tiles.x);
  b.tile_z += int(tiles.y);
}

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= pc.bird_count) return;
  GpuBird b = birds[i];
  GpuSpecies s = species[b.species];
  Leg leg = load_leg(b, pc.targets_base);
  GpuPerception seen = GpuPerception(vec3(0.0), 0.0, 0u, 0.0, 0u, 0u);
  if (pc.flocking != 0u) seen = perception[i];
  // NaN quarantine (step.cpp: step_bird): a step whose result is not finite is undone, the bird
  // frozen at its last finite state. Rather than keep a copy of the state through every step, the
  // frame's finite steps are taken again from its start (still in `birds`): the same code on the
  // same numbers, the same result.
  uint finite_steps = pc.steps;
  bool again = false;
  for (;;) {
    for (uint k = 0u; k < finite_steps; ++k) {
      step_bird(b, s, leg, pc.time + float(k) * pc.dt, pc.dt, seen);
      if (!all_finite(b)) {
        finite_steps = k;
        break;
      }
    }
    if (again || finite_steps == pc.steps) break;
    b = birds[i];
    leg = load_leg(b, pc.targets_base);
    again = true;
  }
  if (again) {
    b.mode = mode_quarantined;
    b.quarantined_at = pc.time + float(finite_steps) * pc.dt;
  }
  retile(b);
  birds[i] = b;
#ifdef RECORD_FORCES
  {
    // The step is taken again by the next frame, with the targets where it sees them: only its
    // forces are kept.
    GpuBird next = b;
    Leg next_leg = load_leg(next, pc.targets_base + pc.next_targets);
    GpuForces f = step_bird(next, s, next_leg, pc.time + float(pc.steps) * pc.dt, pc.dt, seen);
    forces_out[i] = all_finite(next) ? f : no_forces();  // a step that quarantines has none
  }
#endif
}
