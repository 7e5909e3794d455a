#version 450
// Sky above the horizon, the ground (a checkerboard of 10.24 m squares, fogged) below it. The
// ground writes its depth so that birds below it are hidden.
#extension GL_GOOGLE_include_directive : require

#include "frame.glsl"

layout(location = 0) in vec3 in_ray;
layout(location = 0) out vec4 out_color;


void main() {
  vec3 ray = normalize(in_ray);
  float height = frame.eye.y - frame.fog_color.w;  // fog_color.w: ground height
  if (ray.y < 0.0 && height > 0.0) {
    float t = height / -ray.y;
    vec3 hit = t * ray;
    vec2 cell = floor((hit.xz + frame.eye.xz) / 1024.0);  // from the eye's tile: 16 squares a tile
    float checker = mod(cell.x + cell.y, 2.0);
    vec3 grass = mix(vec3(0.30, 0.42, 0.22), vec3(0.34, 0.47, 0.25), checker);
    out_color = vec4(shade(grass, vec3(0, 1, 0), hit), 1.0);
    vec4 clip = frame.view_projection * vec4(hit, 1.0);
    gl_FragDepth = clamp(clip.z / clip.w, 0.0, 1.0);
  } else {
    float up = clamp(ray.y, 0.0, 1.0);
    out_color = vec4(mix(frame.fog_color.rgb, vec3(0.32, 0.52, 0.85), pow(up, 0.6)), 1.0);
    gl_FragDepth = 1.0;
  }
}
