// What every render shader sees: the camera and the light, as push constants (FrameConstants).
#include "gpu/host_device.h"

layout(push_constant) uniform FramePush { FrameConstants frame; };

const vec3 kSunlight = vec3(1.0, 0.95, 0.86);
const vec3 kSkyZenith = vec3(0.30, 0.50, 0.84);

// How much of what lies `distance` (cm) away the haze hides.
float fog_at(float distance) { return clamp(1.0 - exp(-frame.sun.w * distance), 0.0, 1.0); }

// Lit by the sun and by the sky above and the ground below (hemisphere light), then hazed.
vec3 shade(vec3 albedo, vec3 normal, vec3 world_position) {
  vec3 n = normalize(normal);
  vec3 to_eye = normalize(-world_position);  // drawn from the eye (FrameConstants)
  if (dot(n, to_eye) < 0.0) n = -n;          // wings and tail are seen from both sides
  float diffuse = max(dot(n, frame.sun.xyz), 0.0);
  vec3 ambient = mix(vec3(0.32, 0.32, 0.24), vec3(0.62, 0.70, 0.82), 0.5 + 0.5 * n.y);
  vec3 lit = albedo * (0.75 * ambient + 0.7 * diffuse * kSunlight);
  return mix(lit, frame.fog_color.rgb, fog_at(length(world_position)));
}
