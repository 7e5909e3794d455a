#version 450
#extension GL_GOOGLE_include_directive : require

#include "frame.glsl"

layout(location = 0) in vec3 in_normal;
layout(location = 1) in vec3 in_world;
layout(location = 2) flat in uint in_species;
layout(location = 0) out vec4 out_color;

const vec3 kPlumage[4] = vec3[](vec3(0.36, 0.25, 0.16),   // eagle: brown
                                vec3(0.10, 0.10, 0.13),   // starling: glossy black
                                vec3(0.55, 0.55, 0.60),
                                vec3(0.60, 0.35, 0.20));

void main() { out_color = vec4(shade(kPlumage[in_species % 4u], in_normal, in_world), 1.0); }
