#version 450
#extension GL_GOOGLE_include_directive : require

#include "frame.glsl"

layout(location = 0) in vec3 in_normal;
layout(location = 1) in vec3 in_world;
layout(location = 2) flat in uint in_kind;
layout(location = 0) out vec4 out_color;

void main() {
  if (in_kind == 0u)
    out_color = vec4(shade(vec3(0.95, 0.75, 0.20), in_normal, in_world), 0.25);  // targets
  else if (in_kind == 2u)
    out_color = vec4(0.95, 0.80, 0.30, 0.8);  // routes
  else
    out_color = vec4(shade(vec3(0.35, 0.24, 0.14), in_normal, in_world), 1.0);   // branches
}
