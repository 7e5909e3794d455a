#version 450
// The sky with the sun above the horizon, the ground (a checkerboard of 10.24 m squares, hazed)
// below it. The ground writes its depth so that birds below it are hidden.
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
    vec2 at = (hit.xz + frame.eye.xz) / 1024.0;  // in squares, from the eye's tile: 16 a tile
    vec2 cell = floor(at);
    // Where a pixel spans most of a square, the squares fade to their mean (no moire far off).
    float footprint = max(fwidth(at.x), fwidth(at.y));
    float checker = mix(mod(cell.x + cell.y, 2.0), 0.5, smoothstep(0.25, 0.75, footprint));
    vec3 grass = mix(vec3(0.30, 0.40, 0.21), vec3(0.33, 0.44, 0.23), checker);
    out_color = vec4(shade(grass, vec3(0, 1, 0), hit), 1.0);
    vec4 clip = frame.view_projection * vec4(hit, 1.0);
    gl_FragDepth = clamp(clip.z / clip.w, 0.0, 1.0);
  } else {
    // Haze at the horizon, deep blue overhead; the sun a bright disc (0.53 deg) in its glow.
    float up = clamp(ray.y, 0.0, 1.0);
    vec3 sky = mix(frame.fog_color.rgb, kSkyZenith, pow(up, 0.5));
    float towards_sun = max(dot(ray, frame.sun.xyz), 0.0);
    sky += kSunlight * (0.25 * pow(towards_sun, 12.0) + 0.5 * pow(towards_sun, 300.0));
    sky = mix(sky, vec3(1.0, 0.98, 0.92),
              smoothstep(0.9999863, 0.9999905, towards_sun));  // cos 0.30, 0.25 deg
    out_color = vec4(min(sky, vec3(1.0)), 1.0);
    gl_FragDepth = 1.0;
  }
}
