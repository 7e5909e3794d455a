#version 450
#extension GL_GOOGLE_include_directive : require

#include "frame.glsl"

layout(location = 0) in vec3 in_normal;
layout(location = 1) in vec3 in_world;
layout(location = 2) flat in uint in_kind;
layout(location = 0) out vec4 out_color;

void main() {
  float haze = fog_at(length(in_world));
  if (in_kind == 0u)
    out_color = vec4(1.0, 0.85, 0.35, 0.6 * (1.0 - haze));  // target rings
  else if (in_kind == 2u)
    out_color = vec4(1.0, 0.85, 0.35, 0.3 * (1.0 - haze));  // routes
  else if (in_kind == 3u)
    out_color = vec4(shade(vec3(0.30, 0.22, 0.15), in_normal, in_world), 1.0);  // posts
  else if (in_kind == 4u)
    out_color = vec4(shade(vec3(0.78, 0.70, 0.42), in_normal, in_world), 1.0);  // ground sites
  else
    out_color = vec4(shade(vec3(0.35, 0.24, 0.14), in_normal, in_world), 1.0);  // branches
}
