// engine/model/aerodynamics.cpp in float (eqs. 1, 2; model.glsl).

vec3 aerodynamic_force(GpuSpecies s, vec3 air, vec3 chord, vec3 normal, float area) {
  precise float u_chord = dot(air, chord);
  precise float u_normal = dot(air, normal);
  precise float speed2 = u_chord * u_chord + u_normal * u_normal;
  if (!(speed2 > 0.0)) return vec3(0.0);
  precise float speed = sqrt(speed2);
  precise float sin_a = u_normal / speed;
  precise float cos_a = -u_chord / speed;
  precise float cl = s.Cl_max * 2.0 * sin_a * cos_a;
  precise float cd = s.Cd_0 + (s.Cd_90 - s.Cd_0) * sin_a * sin_a;
  precise float q_area = 0.5 * kAirDensity * speed2 * area;
  precise vec3 lift_dir = chord * sin_a + normal * cos_a;
  precise vec3 drag_dir = chord * -cos_a + normal * sin_a;
  precise vec3 f = q_area * (cl * lift_dir + cd * drag_dir);
  return f;
}
