// One frame of the flock, or a part of a long one: each invocation steps one bird `steps` times
// with the fixed dt, its state in registers throughout, and writes it back once. A frame longer
// than kMaxStepsPerDispatch (gpu_simulation.h) is several dispatches: each takes the frame's
// steps from first_step on, the last retiles and records the forces, so that the parts step
// exactly as one would. step.comp is this; step_forces.comp
// (RECORD_FORCES) also writes the forces of the step each bird takes next (the exporters' and the
// cross-check's forces): a pipeline of its own, so that the plain step carries none of it.

#include "buffers.glsl"

layout(local_size_x = kWorkgroupSize) in;
layout(push_constant) uniform StepPush { StepConstants pc; };  // model.glsl reads pc
layout(std430, set = 0, binding = kBindingPerception) readonly buffer Perceptions {
  GpuPerception perception[];
};
// Counts the birds whose loop ended before its steps were taken: a driver may end a shader's
// loops (lavapipe after 65,535 turns); the host refuses the frame rather than show it.
layout(std430, set = 0, binding = kBindingCutShort) buffer CutShort {
  uint steps_short;
  uint searches_short;  // perceive.comp's
};
layout(std430, set = 0, binding = kBindingIds) readonly buffer Ids { uint ids[]; };
#ifdef RECORD_FORCES
layout(std430, set = 0, binding = kBindingForces) writeonly buffer Forces {
  GpuForces forces_out[];
};
#endif

#include "model.glsl"

// Moves the bird into the tile its position is now over, by whole tiles (exact: host_device.h),
// with the points it carries, once a frame: its offset stays within about half a tile. Not while
// it lands: its curve's via point is compared with the perch point bit for bit (route.glsl).
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
  if (i >= pc.bird_count || (ids[i] & kGhostBird) != 0u) return;  // a ghost is its rank's to step
  GpuBird b = birds[i];
  GpuSpecies s = species[b.species];
  Leg leg = load_leg(b, pc.targets_base);
  GpuPerception seen = no_perception();
  if (pc.flocking != 0u && kWakes) {
    seen = perception[i];
  } else if (pc.flocking != 0u) {
    seen.direction = perception[i].direction;
    seen.airspeed = perception[i].airspeed;
    seen.neighbours = perception[i].neighbours;
  }
  uint end = pc.first_step + pc.steps;
  // NaN quarantine (step.cpp: step_bird): a step whose result is not finite is undone, the bird
  // frozen at its last finite state. Rather than keep a copy of the state through every step, the
  // dispatch's finite steps are taken again from its start (still in `birds`): the same code on the
  // same numbers, the same result.
  uint finite_end = end;
  bool again = false;
  uint taken = 0u;  // counted apart from k, so that no compiler reads it off the loop's condition
  for (;;) {
    for (uint k = pc.first_step; k < finite_end; ++k) {
      step_bird(b, s, leg, pc.dt, seen, pc.step.x + k);
      ++taken;
      if (!all_finite(b)) {
        finite_end = k;
        break;
      }
    }
    if (again || finite_end == end) break;
    b = birds[i];
    leg = load_leg(b, pc.targets_base);
    again = true;
  }
  if (!again && taken != pc.steps) atomicAdd(steps_short, 1u);
  if (again) {
    b.mode = mode_quarantined;
    uint carry;
    b.quarantined_step.x = uaddCarry(pc.step.x, finite_end, carry);
    b.quarantined_step.y = pc.step.y + carry;
  }
  bool frame_ends = end == pc.frame_steps;
  if (frame_ends) retile(b);
  birds[i] = b;
#ifdef RECORD_FORCES
  if (frame_ends) {
    // The step is taken again by the next frame, with the targets where it sees them: only its
    // forces are kept.
    GpuBird next = b;
    Leg next_leg = load_leg(next, pc.targets_base + pc.next_targets);
    GpuForces f = step_bird(next, s, next_leg, pc.dt, seen, pc.step.x + end);
    forces_out[i] = all_finite(next) ? f : no_forces();  // a step that quarantines has none
  }
#endif
}
