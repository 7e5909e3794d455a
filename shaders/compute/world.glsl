// engine/model/world.cpp in float (model.glsl): the wind. The world's targets, routes and branches
// are the buffers (buffers.glsl), the rest of World the push constants `pc`; target_position is
// the host's (World::move_targets, between frames).

// At world height y: pc.wind_ground.xyz at pc.wind_height above the ground, by the profile.
vec3 wind_at(float y) {
  uint profile = kWindProfile == kWindProfileAny ? pc.wind_profile : kWindProfile;
  if (profile == 0u) return pc.wind_ground.xyz;
  float h = y - pc.wind_ground.w;
  if (profile == 1u)
    return h > 0.0 ? pc.wind_ground.xyz * pow(h / pc.wind_height, pc.wind_exponent) : vec3(0.0);
  return h > pc.wind_roughness ? pc.wind_ground.xyz * (log(h / pc.wind_roughness) /
                                                       log(pc.wind_height / pc.wind_roughness))
                               : vec3(0.0);
}

// The wind where the bird is this step (step_bird sets it once: the step moves the bird only at
// its end); a private global rather than a parameter, which made glslang's precise propagation
// blow up (docs/ARCHITECTURE.md).
vec3 step_wind;
