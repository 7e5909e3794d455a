// engine/model/wingbeat.cpp in float (model.glsl); wing_angles is in bird.glsl.

struct WingPoint {
  vec3 position, velocity, chord, normal;
  float area;
};

void flap(inout vec3 fy, inout vec3 fz, float angle) {
  vec2 sc = sin_cos(angle);
  float c = sc.y, s = sc.x;
  vec3 y = c * fy - s * fz;
  vec3 z = s * fy + c * fz;
  fy = y;
  fz = z;
}

void feather(vec3 fx, vec3 fy, float angle, out vec3 chord, out vec3 normal) {
  vec2 sc = sin_cos(angle);
  float c = sc.y, s = sc.x;
  chord = c * fx - s * fy;
  normal = s * fx + c * fy;
}

void right_wing_points(GpuSpecies s, float phase, float amp, float frequency, float sweep,
                       float incidence, out WingPoint points[2]) {
  WingAngles w = wing_angles(s, phase, amp, sweep, incidence);
  float phase_rate = 2.0 * kPi * frequency;
  float leadlag_rate = s.C_leadlag * w.cos_phase * phase_rate;
  float flap_arm_rate = -amp * s.A_arm * w.sin_phase * phase_rate;
  float flap_hand_rate = -amp * s.A_hand * w.sin_hand_phase * phase_rate;

  vec2 l = sin_cos(w.leadlag);
  float cl = l.y, sl = l.x;
  vec3 sx = vec3(cl, 0.0, -sl), sy = vec3(0.0, 1.0, 0.0), sz = vec3(sl, 0.0, cl);
  vec3 ax = sx, ay = sy, az = sz;
  flap(ay, az, w.flap_arm);
  vec3 hx = ax, hy = ay, hz = az;
  flap(hy, hz, w.flap_hand);

  vec3 shoulder = vec3(s.shoulder_x, 0.0, s.shoulder_z);
  vec3 wrist = shoulder + az * s.arm_length;
  points[0].position = shoulder + az * (0.5 * s.arm_length);
  points[1].position = wrist + hz * (0.5 * s.hand_length);
  vec3 omega_shoulder = vec3(0.0, leadlag_rate, 0.0) - sx * flap_arm_rate;
  vec3 omega_wrist = -ax * flap_hand_rate;
  points[0].velocity = cross(omega_shoulder, points[0].position - shoulder);
  points[1].velocity = cross(omega_shoulder, points[1].position - shoulder) +
                       cross(omega_wrist, points[1].position - wrist);
  feather(ax, ay, w.feather_arm, points[0].chord, points[0].normal);
  feather(hx, hy, w.feather_arm + w.feather_hand, points[1].chord, points[1].normal);
  points[0].area = s.arm_area;
  points[1].area = s.hand_area;
}

WingPoint mirror_to_left(WingPoint p) {
  vec3 m = vec3(1.0, 1.0, -1.0);
  p.position *= m;
  p.velocity *= m;
  p.chord *= m;
  p.normal *= m;
  return p;
}
