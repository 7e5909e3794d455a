// engine/model/aerodynamics.cpp in float (eqs. 1, 2; model.glsl), function for function in its
// order; the reasons are in the C++.

struct Coefficients {
  float lift, drag;
};
Coefficients coefficients(GpuSpecies s, float sin_a, float cos_a) {
  precise float lift = s.Cl_max * 2.0 * sin_a * cos_a;
  precise float drag = s.Cd_0 + (s.Cd_90 - s.Cd_0) * sin_a * sin_a;
  return Coefficients(lift, drag);
}

// lift_coefficient, drag_coefficient and attack_angle are the host's alone (tests, export).

vec3 aerodynamic_force(GpuSpecies s, vec3 air, vec3 chord, vec3 normal, float area) {
  precise float u_chord = dot(air, chord);
  precise float u_normal = dot(air, normal);
  precise float speed2 = u_chord * u_chord + u_normal * u_normal;
  if (!(speed2 > 0.0)) return vec3(0.0);
  precise float speed = sqrt(speed2);
  precise float sin_a = u_normal / speed;
  precise float cos_a = -u_chord / speed;
  Coefficients c = coefficients(s, sin_a, cos_a);
  precise float q_area = 0.5 * kAirDensity * speed2 * area;
  precise vec3 lift_dir = chord * sin_a + normal * cos_a;
  precise vec3 drag_dir = chord * -cos_a + normal * sin_a;
  precise vec3 f = q_area * (c.lift * lift_dir + c.drag * drag_dir);
  return f;
}

struct WingForces {
  vec3 force[4];  // right arm, right hand, left arm, left hand
  vec3 torque;
};
// `right`: the right wing's points (right_wing_points); `induced`: aerodynamics.cpp's.
WingForces wing_forces_at(GpuSpecies s, WingPoint right[2], vec3 body_air, vec3 omega,
                          vec3 induced[4]) {
  WingForces w;
  precise vec3 torque = vec3(0.0);
  for (int i = 0; i < 2; ++i) {
    for (int side = 0; side < 2; ++side) {
      WingPoint p = side == 0 ? right[i] : mirror_to_left(right[i]);
      precise vec3 air = body_air - cross(omega, p.position) - p.velocity;
      air += induced[2 * side + i];
      vec3 force = aerodynamic_force(s, air, p.chord, p.normal, p.area);
      w.force[2 * side + i] = force;
      torque += cross(p.position, force);
    }
  }
  w.torque = torque;
  return w;
}

WingForces wing_forces(GpuSpecies s, float phase, float amp, float frequency, float sweep,
                       float incidence, vec3 body_air, vec3 omega) {
  WingPoint right[2];
  right_wing_points(s, phase, amp, frequency, sweep, incidence, right);
  vec3 none[4] = vec3[4](vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0));
  return wing_forces_at(s, right, body_air, omega, none);
}
