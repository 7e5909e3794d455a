#version 450
// One bird per instance: its mesh placed by the pose the pose pass computed for it this frame
// (pose.comp: wingbeat angles at the bird's phase, tail bend, twist and opening, attitude).
#extension GL_GOOGLE_include_directive : require

#include "frame.glsl"

struct MeshVertex {
  vec4 position;  // xyz, w: part (0 body, 1 arm, 2 hand, 3 tail; +4 left)
  vec4 normal;
};
layout(std430, set = 0, binding = 6) readonly buffer Mesh { MeshVertex mesh[]; };
struct Pose {
  vec4 rows[18];
  vec4 tail;
};
layout(std430, set = 0, binding = 3) readonly buffer Poses { Pose poses[]; };

layout(location = 0) out vec3 out_normal;
layout(location = 1) out vec3 out_world;
layout(location = 2) flat out uint out_species;


void main() {
  MeshVertex v = mesh[gl_VertexIndex];
  uint part = uint(v.position.w);
  uint transform = part < 4u ? part : part - 1u;  // left arm 5 -> 4, left hand 6 -> 5
  vec3 p = v.position.xyz, n = v.normal.xyz;
  if (part == 3u) {  // the tail's fan: x radius fraction, z angle fraction of the opening
    float a = p.z * poses[gl_InstanceIndex].tail.x;
    p = p.x * vec3(-cos(a), 0.0, sin(a));
  }
  vec4 r0 = poses[gl_InstanceIndex].rows[3u * transform];
  vec4 r1 = poses[gl_InstanceIndex].rows[3u * transform + 1u];
  vec4 r2 = poses[gl_InstanceIndex].rows[3u * transform + 2u];
  vec4 h = vec4(p, 1.0);
  vec3 world = vec3(dot(r0, h), dot(r1, h), dot(r2, h));
  out_normal = vec3(dot(r0.xyz, n), dot(r1.xyz, n), dot(r2.xyz, n));
  out_world = world;
  out_species = floatBitsToUint(poses[gl_InstanceIndex].tail.y);
  // Level of detail: a bird smaller on screen than frame.lod_pixels wide is drawn with its four
  // wing triangles only; its other triangles collapse to a point and are not rasterised.
  vec3 body_x = vec3(poses[gl_InstanceIndex].rows[0].x, poses[gl_InstanceIndex].rows[1].x,
                     poses[gl_InstanceIndex].rows[2].x);
  float span = 3.0 * length(body_x);
  vec3 centre = vec3(poses[gl_InstanceIndex].rows[0].w, poses[gl_InstanceIndex].rows[1].w,
                     poses[gl_InstanceIndex].rows[2].w);
  bool distant = span * frame.lod_scale < distance(centre, frame.eye.xyz);
  gl_Position = distant && v.normal.w > 0.5 ? vec4(0.0, 0.0, 2.0, 1.0)
                                            : frame.view_projection * vec4(world, 1.0);
}
