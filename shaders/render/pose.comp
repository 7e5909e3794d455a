#version 450
// Each bird's pose for drawing, once per frame rather than once per vertex: the world transform
// of its body, right arm, right hand and tail (the left wing is the right one mirrored in the
// body frame), from its wingbeat phase, amplitude, tail and attitude.
#extension GL_GOOGLE_include_directive : require

#define BIRDS_ACCESS readonly
#include "buffers.glsl"
#include "bird.glsl"

layout(local_size_x = kWorkgroupSize) in;
layout(std430, set = 0, binding = kBindingPoses) writeonly buffer Poses { Pose poses[]; };
// Three draws (detailed, distant, tiny), each drawing the birds of its list.
layout(std430, set = 0, binding = kBindingDrawLists) writeonly buffer Lists { uint lists[]; };
layout(std430, set = 0, binding = kBindingDraws) buffer Draws { DrawCommand draws[3]; };
layout(push_constant) uniform PosePush { PoseConstants pc; };

mat3 rot_x(float a) {
  float c = cos(a), s = sin(a);
  return mat3(1, 0, 0, 0, c, s, 0, -s, c);
}
mat3 rot_y(float a) {
  float c = cos(a), s = sin(a);
  return mat3(c, 0, -s, 0, 1, 0, s, 0, c);
}
mat3 rot_z(float a) {
  float c = cos(a), s = sin(a);
  return mat3(c, s, 0, -s, c, 0, 0, 0, 1);
}

// The pose's transforms, grown about the bird by `grow` (a distant bird kept visible).
vec3 g_position;
float g_grow;

// Part `part` at `offset` from the bird (world axes): rows of the 3x4 matrix [m | t].
void store(uint i, uint part, mat3 m, vec3 offset) {
  m *= g_grow;
  vec3 t = g_position + g_grow * offset;
  poses[i].rows[3 * part + 0] = vec4(m[0][0], m[1][0], m[2][0], t.x);
  poses[i].rows[3 * part + 1] = vec4(m[0][1], m[1][1], m[2][1], t.y);
  poses[i].rows[3 * part + 2] = vec4(m[0][2], m[1][2], m[2][2], t.z);
}

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= pc.bird_count) return;
  GpuBird b = birds[i];
  if (b.mode == mode_quarantined) return;  // frozen where its state stopped being finite: not drawn
  GpuSpecies s = species[b.species];
  bool folded = b.mode == mode_perched || b.mode == mode_standing;

  vec4 q = b.attitude;
  mat3 attitude =
      mat3(rotate(q, vec3(1, 0, 0)), rotate(q, vec3(0, 1, 0)), rotate(q, vec3(0, 0, 1)));
  vec3 position = b.position + tile_shift(b.tile_x, b.tile_z, pc.tile_x, pc.tile_z) -
                  pc.eye.xyz;  // from the eye
  float span = 2.0 * (s.shoulder_z + s.arm_length + s.hand_length);
  float distance = length(position);
  g_position = position;
  g_grow = max(1.0, distance * pc.min_angle / span);

  // Body: the box a x b x b.
  store(i, 0u, attitude * mat3(s.box_a, 0, 0, 0, s.box_b, 0, 0, 0, s.box_b), vec3(0.0));

  // Wings: the model's joints (bird.glsl), folded along the body when perched or standing.
  WingbeatAngles w =
      wingbeat_angles(s, b.phase, b.amplitude, b.sweep, 0.0);  // drawn without the brake incidence
  if (folded) {
    w.flap_arm = 0.0;
    w.flap_hand = 0.0;
    w.feather_arm = 0.0;
    w.feather_hand = 0.0;
    w.leadlag = -1.3;
  }
  mat3 shoulder = rot_y(w.leadlag) * rot_x(-w.flap_arm);
  vec3 shoulder_at = vec3(s.shoulder_x, 0.0, s.shoulder_z);
  // Segment meshes span z in 0..1 and chord x in -0.5..0.5: scale by length and mean chord.
  mat3 arm_scale = mat3(s.arm_area / s.arm_length, 0, 0, 0, 1, 0, 0, 0, s.arm_length);
  mat3 hand_scale = mat3(s.hand_area / s.hand_length, 0, 0, 0, 1, 0, 0, 0, s.hand_length);
  mat3 arm = shoulder * rot_z(-w.feather_arm);
  mat3 hand = shoulder * rot_x(-w.flap_hand) * rot_z(-(w.feather_arm + w.feather_hand));
  vec3 wrist = shoulder_at + shoulder * vec3(0.0, 0.0, s.arm_length);
  store(i, 1u, attitude * arm * arm_scale, attitude * shoulder_at);
  store(i, 2u, attitude * hand * hand_scale, attitude * wrist);
  // The left wing: the right one mirrored through the body's x-y plane.
  mat3 mirror = mat3(1, 0, 0, 0, 1, 0, 0, 0, -1);
  store(i, 4u, attitude * mirror * arm * arm_scale, attitude * (mirror * shoulder_at));
  store(i, 5u, attitude * mirror * hand * hand_scale, attitude * (mirror * wrist));

  // Tail: hinged at x = -a/2, bent up by incidence + bend, twisted about x; scaled by lr.
  mat3 tail = rot_x(b.tail_twist) * rot_z(-(s.tail_incidence + b.tail_bend));
  store(i, 3u, attitude * tail * s.tail_length, attitude * vec3(s.tail_hinge_x, 0.0, 0.0));
  // Detailed, distant or tiny: how wide the bird is on screen.
  uint list = distance > span * pc.lod_scale ? 1u : 0u;
  if (pc.tiny_scale > 0.0 && distance > span * pc.tiny_scale) list = 2u;
  lists[list * pc.capacity + atomicAdd(draws[list].instance_count, 1u)] = i;

  // The tail's opening as the model has it now: fully open while braking to land.
  // The span: the shadow's size (shadow.vert; a distant bird grown on screen casts its own).
  // The legs (body heights under its centre): on its legs (standing, taking off, perched) they
  // reach stand_height down, or to the ground where that is nearer: folded as its body crouches to
  // leap or sinks onto the ground in a hard touch-down. In flight, none.
  float legs = folded || b.mode == mode_taking_off
                   ? clamp(b.position.y - pc.ground_height, 0.0, s.stand_height) / s.box_b
                   : 0.0;
  poses[i].tail = vec4(tail_opening(s, b), uintBitsToFloat(b.species), span, legs);
}
