// engine/model/wake.cpp in float, function for function; the reasons are in wake.h. Needs
// wingbeat.glsl (right_wingtip) and host_device.h (GpuWakeSource).

float vortex_span(GpuSpecies s) { return kWakeVortexSpan * s.box_c; }

float wake_circulation(GpuSpecies s, float lift, float airspeed) {
  precise float circulation =
      airspeed > 0.0 ? lift / (kAirDensity * airspeed * vortex_span(s)) : 0.0;
  return circulation;
}

float wake_core(GpuSpecies s) { return kWakeCore * s.box_c; }

vec3 vortex_place(GpuSpecies s, GpuWakeSource src, float distance) {
  float airspeed = length(src.air_velocity_frequency.xyz);
  precise float age = airspeed > 0.0 ? distance / airspeed : 0.0;
  precise float phase = src.position_phase.w - 2.0 * kPi * src.air_velocity_frequency.w * age;
  vec3 tip = right_wingtip(s, phase, src.lift_amplitude.y, 0.0);
  return vec3(0.0, kWakeVortexSpan * tip.y, kWakeVortexSpan * tip.z);
}

vec3 half_line(vec3 r, vec3 along, float circulation, float core) {
  float len = length(r);
  if (!(len > 0.0)) return vec3(0.0);
  precise float on = dot(r, along);
  precise vec3 across = r - along * on;
  precise float h2 = dot(across, across);
  precise vec3 v =
      cross(along, across) * (circulation / (4.0 * kPi) * (1.0 + on / len) / (h2 + core * core));
  return v;
}

// wake.cpp: VortexPair (back 0: no wake).
struct VortexPair {
  vec3 right_start, left_start, back;
  float circulation, core;
};

VortexPair vortex_pair(GpuSpecies s, GpuWakeSource src, vec3 station) {
  VortexPair pair = VortexPair(vec3(0.0), vec3(0.0), vec3(0.0), 0.0, 0.0);
  vec3 air = src.air_velocity_frequency.xyz;
  float airspeed = length(air);
  float lift = src.lift_amplitude.x;
  if (!(airspeed > 0.0) || lift == 0.0) return pair;
  pair.back = -air / airspeed;
  vec3 position = src.position_phase.xyz;
  precise vec3 offset = station - position;
  float behind = max(dot(offset, pair.back), 0.0);
  vec3 place = vortex_place(s, src, behind);
  vec3 up = rotate(src.attitude, vec3(0.0, 1.0, 0.0));
  vec3 right = rotate(src.attitude, vec3(0.0, 0.0, 1.0));
  precise vec3 right_start = position + up * place.y + right * place.z;
  precise vec3 left_start = position + up * place.y - right * place.z;
  pair.right_start = right_start;
  pair.left_start = left_start;
  pair.circulation = wake_circulation(s, lift, airspeed);
  pair.core = wake_core(s);
  return pair;
}

vec3 pair_velocity(VortexPair pair, vec3 point) {
  if (pair.circulation == 0.0) return vec3(0.0);
  precise vec3 v = half_line(point - pair.right_start, pair.back, pair.circulation, pair.core) +
                   half_line(point - pair.left_start, pair.back, -pair.circulation, pair.core);
  return v;
}

vec3 wake_velocity(GpuSpecies s, GpuWakeSource src, vec3 point) {
  return pair_velocity(vortex_pair(s, src, point), point);
}
