#version 450
// One bird per instance, posed from its own state in the flock's storage buffer: wingbeat angles
// of arm and hand at the bird's phase, tail bend, twist and opening, the body's attitude.
#extension GL_GOOGLE_include_directive : require

#include "frame.glsl"
#define BIRDS_ACCESS readonly
#include "../compute/layout.glsl"

// The mesh, read by vertex index (engine/render/meshes.h).
struct MeshVertex {
  vec4 position;  // xyz, w: part
  vec4 normal;
};
layout(std430, set = 0, binding = 6) readonly buffer Mesh { MeshVertex mesh[]; };

layout(location = 0) out vec3 out_normal;
layout(location = 1) out vec3 out_world;
layout(location = 2) flat out uint out_species;

vec3 rotate(vec4 q, vec3 v) {
  vec3 t = 2.0 * cross(q.xyz, v);
  return v + q.w * t + cross(q.xyz, t);
}
mat3 rot_x(float a) { float c = cos(a), s = sin(a); return mat3(1, 0, 0, 0, c, s, 0, -s, c); }
mat3 rot_y(float a) { float c = cos(a), s = sin(a); return mat3(c, 0, -s, 0, 1, 0, s, 0, c); }
mat3 rot_z(float a) { float c = cos(a), s = sin(a); return mat3(c, s, 0, -s, c, 0, 0, 0, 1); }

void main() {
  MeshVertex mv = mesh[gl_VertexIndex];
  vec3 in_position = mv.position.xyz, in_normal = mv.normal.xyz;
  uint in_part = uint(mv.position.w);  // 0 body, 1 arm, 2 hand, 3 tail; +4: left side
  GpuBird b = birds[gl_InstanceIndex];
  uint species_index = b.ids.x >> 16;
  Species s = species[species_index];
  bool perched = (b.ids.x & 0xffu) == kPerched || (b.ids.x & 0xffu) == kStanding;
  float phase = b.position_phase.w, amp = perched ? 0.0 : b.omega_amplitude.w;
  uint part = in_part & 3u;
  bool left = in_part >= 4u;

  vec3 p = in_position, n = in_normal;
  if (part == 0u) {  // body: the box a x b x b
    p *= vec3(-2.0 * s.tail_hinge_x, s.box_b, s.box_b);
  } else if (part == 3u) {  // tail: a fan of radius lr opened to phi, bent and twisted
    float opening = s.Ct * max(abs(b.tail_times.x), abs(b.tail_times.y)) + s.tail_min;
    float lr = sqrt(2.0 * s.tail_area_per_radian);
    // in_position: x = radius fraction, z = angle fraction in [-0.5, 0.5]
    float a = in_position.z * opening;
    p = lr * in_position.x * vec3(-cos(a), 0.0, sin(a));
    n = vec3(0, 1, 0);
    mat3 m = rot_x(b.tail_times.y) * rot_z(-(s.tail_incidence + b.tail_times.x));
    p = m * p + vec3(s.tail_hinge_x, 0.0, 0.0);
    n = m * n;
  } else {  // wing segments: span along z, chord along x, posed like the model's joints
    float hand_phase = phase - s.lag_hand;
    float flap_arm = amp * s.A_arm * cos(phase) + s.flap_bias;
    float flap_hand = amp * s.A_hand * cos(hand_phase);
    float feather_arm = s.B_arm * sin(phase) - s.twist_bias;
    float feather_hand = s.B_hand * sin(hand_phase);
    float leadlag = s.C_leadlag * sin(phase);
    if (perched) {  // folded along the body
      flap_arm = 0.0; flap_hand = 0.0; feather_arm = 0.0; feather_hand = 0.0; leadlag = -1.3;
    }
    float length = part == 1u ? s.arm_length : s.hand_length;
    float chord = (part == 1u ? s.arm_area : s.hand_area) / length;
    vec3 local = vec3(in_position.x * chord, 0.0, in_position.z * length);
    mat3 shoulder = rot_y(leadlag) * rot_x(-flap_arm);
    vec3 origin = vec3(s.shoulder_x, 0.0, s.shoulder_z);
    mat3 m;
    if (part == 1u) {
      m = shoulder * rot_z(-feather_arm);
    } else {
      origin += shoulder * vec3(0.0, 0.0, s.arm_length);
      m = shoulder * rot_x(-flap_hand) * rot_z(-(feather_arm + feather_hand));
    }
    p = origin + m * local;
    n = m * vec3(0, 1, 0);
  }
  if (left) {
    p.z = -p.z;
    n.z = -n.z;
  }
  vec4 q = b.attitude;
  vec3 world = b.position_phase.xyz + rotate(q, p);
  out_normal = rotate(q, n);
  out_world = world;
  out_species = species_index;
  gl_Position = frame.view_projection * vec4(world, 1.0);
}
