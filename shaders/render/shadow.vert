#version 450
// Each bird's shadow on the ground: a soft disc where the sun's ray through the bird meets the
// ground, as wide as the bird plus the sun's penumbra (0.53 deg), fainter as it spreads.
#extension GL_GOOGLE_include_directive : require

#include "frame.glsl"

layout(std430, set = 0, binding = kBindingPoses) readonly buffer Poses { Pose poses[]; };

layout(location = 0) out vec2 out_disc;  // -1..1 across the disc
layout(location = 1) out float out_alpha;

const float kPenumbra = 0.0093;  // 2 tan(0.265 deg): the penumbra's width per cm of height
const float kDarkness = 0.45;    // of a shadow as wide as the bird

void main() {
  Pose pose = poses[gl_InstanceIndex];
  vec3 bird = vec3(pose.rows[0].w, pose.rows[1].w, pose.rows[2].w);  // from the eye
  float ground = frame.fog_color.w - frame.eye.y;
  float height = bird.y - ground;
  float span = pose.tail.z;
  float radius = 0.35 * span + kPenumbra * height;
  vec3 centre = bird - frame.sun.xyz * (height / frame.sun.y);
  centre.y = ground;
  // A square of two triangles round the centre.
  const vec2 kCorners[6] = vec2[](vec2(-1, -1), vec2(1, -1), vec2(-1, 1), vec2(-1, 1), vec2(1, -1), vec2(1, 1));
  vec2 corner = kCorners[gl_VertexIndex];
  vec3 world = centre + radius * vec3(corner.x, 0.0, corner.y);
  float spread = 0.35 * span / radius;
  out_alpha = height > 0.0 ? kDarkness * spread * spread * (1.0 - fog_at(length(centre))) : 0.0;
  out_disc = corner;
  gl_Position = frame.view_projection * vec4(world, 1.0);
}
