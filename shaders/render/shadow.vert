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
const float kFaintest = 0.05;    // fainter shadows are left out (the starling's above 150 m)

void main() {
  // Six vertices a bird in one draw; in a large flock every shadow_stride-th bird casts the shadow
  // of that many (as dark where they overlap, a fraction of the fill).
  uint corner_index = uint(gl_VertexIndex) % 6u;
  Pose pose = poses[uint(gl_VertexIndex) / 6u * frame.shadow_stride];
  vec3 bird = vec3(pose.rows[0].w, pose.rows[1].w, pose.rows[2].w);  // from the eye
  float ground = frame.fog_color.w - frame.eye.y;
  float height = bird.y - ground;
  float span = pose.tail.z;
  float radius = 0.35 * span + 0.5 * kPenumbra * height;  // the penumbra's half on each side
  vec3 centre = bird - frame.sun.xyz * (height / frame.sun.y);
  centre.y = ground;
  // A square of two triangles round the centre.
  const vec2 kCorners[6] =
      vec2[](vec2(-1, -1), vec2(1, -1), vec2(-1, 1), vec2(-1, 1), vec2(1, -1), vec2(1, 1));
  vec2 corner = kCorners[corner_index];
  vec3 world = centre + radius * vec3(corner.x, 0.0, corner.y);
  float spread = 0.35 * span / radius;
  float alpha = kDarkness * spread * spread;
  alpha = 1.0 - pow(1.0 - alpha, float(frame.shadow_stride));
  out_alpha = height > 0.0 ? alpha * (1.0 - fog_at(length(centre))) : 0.0;
  out_disc = corner;
  // A shadow too faint to see (a bird high up, or far in the haze) is not drawn at all.
  gl_Position =
      out_alpha < kFaintest ? vec4(0.0, 0.0, -1.0, 1.0) : frame.view_projection * vec4(world, 1.0);
}
