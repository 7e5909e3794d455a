// engine/model/wingbeat.cpp in float (model.glsl), function for function in its order; the
// reasons are in the C++. wingbeat_angles is in bird.glsl (drawing needs it too).

struct WingPoint {
  vec3 position, velocity, chord, normal;
  float area;
};

// A frame as its three axes in body coordinates.
struct Frame {
  vec3 x, y, z;
};

Frame flap(Frame f, float angle) {
  vec2 sc = sin_cos(angle);
  float c = sc.y, s = sc.x;
  return Frame(f.x, c * f.y - s * f.z, s * f.y + c * f.z);
}

void feather(Frame f, float angle, out vec3 chord, out vec3 normal) {
  vec2 sc = sin_cos(angle);
  float c = sc.y, s = sc.x;
  chord = c * f.x - s * f.y;
  normal = s * f.x + c * f.y;
}

// wingbeat.cpp: WingFrames and wing_frames (the lengths are the species').
struct WingFrames {
  Frame shoulder, arm, hand;
  vec3 shoulder_pos, wrist;
};

WingFrames wing_frames(GpuSpecies s, WingbeatAngles a) {
  vec2 l = sin_cos(a.leadlag);
  // wingbeat.cpp's rotate_y of the body's x and z axes, written out.
  WingFrames w;
  w.shoulder = Frame(vec3(l.y, 0.0, -l.x), vec3(0.0, 1.0, 0.0), vec3(l.x, 0.0, l.y));
  w.arm = flap(w.shoulder, a.flap_arm);
  w.hand = flap(w.arm, a.flap_hand);
  w.shoulder_pos = vec3(s.shoulder_x, 0.0, s.shoulder_z);
  precise vec3 wrist = w.shoulder_pos + w.arm.z * s.arm_length;
  w.wrist = wrist;
  return w;
}

// wingbeat.cpp: segment_middles.
void segment_middles(GpuSpecies s, WingFrames w, out vec3 arm, out vec3 hand) {
  arm = w.shoulder_pos + w.arm.z * (0.5 * s.arm_length);
  hand = w.wrist + w.hand.z * (0.5 * s.hand_length);
}

void right_wing_points(GpuSpecies s, float phase, float amp, float frequency, float sweep,
                       float incidence, out WingPoint points[2]) {
  WingbeatAngles a = wingbeat_angles(s, phase, amp, sweep, incidence);
  float phase_rate = 2.0 * kPi * frequency;
  float leadlag_rate = s.C_leadlag * a.cos_phase * phase_rate;
  float flap_arm_rate = -amp * s.A_arm * a.sin_phase * phase_rate;
  float flap_hand_rate = -amp * s.A_hand * a.sin_hand_phase * phase_rate;

  WingFrames w = wing_frames(s, a);
  segment_middles(s, w, points[0].position, points[1].position);
  vec3 omega_shoulder = vec3(0.0, leadlag_rate, 0.0) - w.shoulder.x * flap_arm_rate;
  vec3 omega_wrist = -w.arm.x * flap_hand_rate;
  points[0].velocity = cross(omega_shoulder, points[0].position - w.shoulder_pos);
  points[1].velocity = cross(omega_shoulder, points[1].position - w.shoulder_pos) +
                       cross(omega_wrist, points[1].position - w.wrist);
  feather(w.arm, a.feather_arm, points[0].chord, points[0].normal);
  feather(w.hand, a.feather_arm + a.feather_hand, points[1].chord, points[1].normal);
  points[0].area = s.arm_area;
  points[1].area = s.hand_area;
}

// wingbeat.cpp: right_wing_places.
void right_wing_places(GpuSpecies s, float phase, float amp, float sweep, out vec3 places[2]) {
  segment_middles(s, wing_frames(s, wingbeat_angles(s, phase, amp, sweep, 0.0)), places[0],
                  places[1]);
}

// wingbeat.cpp: right_wingtip.
vec3 right_wingtip(GpuSpecies s, float phase, float amp, float sweep) {
  WingFrames w = wing_frames(s, wingbeat_angles(s, phase, amp, sweep, 0.0));
  precise vec3 tip = w.wrist + w.hand.z * s.hand_length;
  return tip;
}

WingPoint mirror_to_left(WingPoint p) {
  vec3 m = vec3(1.0, 1.0, -1.0);
  p.position *= m;
  p.velocity *= m;
  p.chord *= m;
  p.normal *= m;
  return p;
}
