#version 450
// A triangle covering the screen, with the world-space view ray at each corner (the inverse
// projection is done here, three times, rather than per pixel).
#extension GL_GOOGLE_include_directive : require

#include "frame.glsl"

layout(location = 0) out vec3 out_ray;

void main() {
  vec2 p = vec2((gl_VertexIndex << 1) & 2, gl_VertexIndex & 2) * 2.0 - 1.0;
  vec4 far_point = inverse(frame.view_projection) * vec4(p, 1.0, 1.0);
  out_ray = far_point.xyz / far_point.w;  // from the eye, where the picture is drawn from
  gl_Position = vec4(p, 1.0, 1.0);
}
