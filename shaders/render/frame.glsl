// What every render shader sees: the camera and the light, as push constants (FrameConstants).
#include "gpu/host_device.h"

layout(push_constant) uniform FramePush { FrameConstants frame; };

vec3 shade(vec3 albedo, vec3 normal, vec3 world_position) {
  vec3 n = normalize(normal);
  vec3 to_eye = normalize(-world_position);  // drawn from the eye (FrameConstants)
  if (dot(n, to_eye) < 0.0) n = -n;  // wings and tail are seen from both sides
  float diffuse = max(dot(n, frame.sun.xyz), 0.0);
  vec3 lit = albedo * (0.35 + 0.65 * diffuse);
  float distance = length(world_position);
  float fog = 1.0 - exp(-frame.sun.w * distance);
  return mix(lit, frame.fog_color.rgb, clamp(fog, 0.0, 1.0));
}
