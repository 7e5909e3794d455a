#version 450
// One bird per instance: its mesh placed by the pose the pose pass computed for it this frame
// (pose.comp: wingbeat angles at the bird's phase, tail bend, twist and opening, attitude).
#extension GL_GOOGLE_include_directive : require

#include "frame.glsl"

layout(std430, set = 0, binding = kBindingMesh) readonly buffer Mesh { MeshVertex mesh[]; };
layout(std430, set = 0, binding = kBindingPoses) readonly buffer Poses { Pose poses[]; };
layout(std430, set = 0, binding = kBindingDrawLists) readonly buffer Lists { uint lists[]; };

// Shaded per vertex, smoothly across the faces: the fragment shader only writes the colour.
layout(location = 0) out vec3 out_color;

const vec3 kPlumage[4] = vec3[](vec3(0.36, 0.25, 0.16),  // eagle: brown
                                vec3(0.10, 0.10, 0.13),  // starling: glossy black
                                vec3(0.55, 0.55, 0.60), vec3(0.60, 0.35, 0.20));

const float kClosedTail = 0.25;
const float kHip = 0.3;  // body heights under its centre

void main() {
  uint bird = lists[frame.list_offset + gl_InstanceIndex];
  MeshVertex v = mesh[gl_VertexIndex];
  uint part = uint(v.position.w);
  uint transform = part < 4u ? part : part == 7u ? 0u : part - 1u;  // left arm 5 -> 4, hand 6 -> 5
  vec3 p = v.position.xyz, n = v.normal.xyz;
  // The legs, with the body: from the hip to the feet, poses.tail.w body heights under its centre
  // on its legs (pose.comp), folded into the body in flight.
  if (part == 7u) p.y = mix(-kHip, -max(poses[bird].tail.w, kHip), p.y);
  if (part == 3u) {  // the tail's fan: x radius fraction, z angle fraction of the opening
    float a = p.z * poses[bird].tail.x;
    // Closed, the rectrices still lie side by side: the tip kClosedTail of the length wide.
    p = p.x * vec3(-cos(a), 0.0, sin(a)) + vec3(0.0, 0.0, kClosedTail * p.z * p.x);
  }
  vec4 r0 = poses[bird].rows[3u * transform];
  vec4 r1 = poses[bird].rows[3u * transform + 1u];
  vec4 r2 = poses[bird].rows[3u * transform + 2u];
  vec4 h = vec4(p, 1.0);
  vec3 world = vec3(dot(r0, h), dot(r1, h), dot(r2, h));
  // Normals by the inverse transpose of the part's scaled rotation M: M (n / |columns of M|^2).
  vec3 column_sq = r0.xyz * r0.xyz + r1.xyz * r1.xyz + r2.xyz * r2.xyz;
  vec3 m = n / max(column_sq, vec3(1e-12));
  vec3 normal = vec3(dot(r0.xyz, m), dot(r1.xyz, m), dot(r2.xyz, m));
  vec3 plumage = kPlumage[floatBitsToUint(poses[bird].tail.y) % 4u];
  uint tint = uint(v.normal.w);
  vec3 albedo = tint == 1u ? vec3(0.85, 0.62, 0.12) : tint == 2u ? 0.6 * plumage : plumage;
  out_color = shade(albedo, normal, world);
  gl_Position = frame.view_projection * vec4(world, 1.0);
}
