#include "wingbeat.h"

#include <cmath>

#include <glm/geometric.hpp>

#include "constants.h"

namespace aeroflock {
namespace {

using glm::dvec3;

// Rotation about body y (right-handed).
dvec3 rotate_y(const dvec3& v, double c, double s) {
  return {c * v.x + s * v.z, v.y, -s * v.x + c * v.z};
}

// A frame as its three axes in body coordinates.
struct Frame {
  dvec3 x, y, z;
};

// Frame rotated by -angle about its own x axis (flapping up for the right wing).
Frame flap(const Frame& f, double angle) {
  const double c = std::cos(angle), s = std::sin(angle);
  return {f.x, c * f.y - s * f.z, s * f.y + c * f.z};
}

// Chord and normal of a segment feathered by `angle` (leading edge down > 0) about its span.
void feather(const Frame& f, double angle, dvec3& chord, dvec3& normal) {
  const double c = std::cos(angle), s = std::sin(angle);
  chord = c * f.x - s * f.y;
  normal = s * f.x + c * f.y;
}

// The shoulder, arm and hand frames at angles `a`, and the shoulder's and wrist's places.
struct WingFrames {
  Frame shoulder, arm, hand;
  dvec3 shoulder_pos, wrist;
  double arm_length, hand_length;
};
WingFrames wing_frames(const Species& s, const WingbeatAngles& a) {
  // Shoulder frame: lead-lag about body y. Arm: flapped about the shoulder frame's x axis.
  // Hand: flapped again about the arm's x axis at the wrist.
  const double cl = std::cos(a.leadlag), sl = std::sin(a.leadlag);
  WingFrames w;
  w.shoulder = {rotate_y({1, 0, 0}, cl, sl), {0, 1, 0}, rotate_y({0, 0, 1}, cl, sl)};
  w.arm = flap(w.shoulder, a.flap_arm);
  w.hand = flap(w.arm, a.flap_hand);
  w.arm_length = s.arm_fraction * s.wing_length;
  w.hand_length = s.wing_length - w.arm_length;
  w.shoulder_pos = dvec3{s.shoulder_x, 0.0, 0.5 * s.box_c - s.wing_length};
  w.wrist = w.shoulder_pos + w.arm.z * w.arm_length;
  return w;
}

// The middles of the arm and the hand: the wing's force points.
void segment_middles(const WingFrames& w, dvec3& arm, dvec3& hand) {
  arm = w.shoulder_pos + w.arm.z * (0.5 * w.arm_length);
  hand = w.wrist + w.hand.z * (0.5 * w.hand_length);
}

}  // namespace

WingbeatAngles wingbeat_angles(const Species& s, double phase, double amp, double sweep,
                               double incidence) {
  const double hand_phase = phase - s.lag_hand;
  return {
      amp * s.A_arm * std::cos(phase) + s.flap_bias,
      amp * s.A_hand * std::cos(hand_phase),
      s.B_arm * std::sin(phase) - s.twist_bias - incidence,
      s.B_hand * std::sin(hand_phase),
      sweep + s.C_leadlag * std::sin(phase),
  };
}

void right_wing_points(const Species& s, double phase, double amp, double frequency, double sweep,
                       double incidence, WingPoint out[2]) {
  const WingbeatAngles a = wingbeat_angles(s, phase, amp, sweep, incidence);
  const double phase_rate = 2.0 * kPi * frequency;
  const double hand_phase = phase - s.lag_hand;
  // Angle rates: d(angle)/dpsi * dpsi/dt.
  const double leadlag_rate = s.C_leadlag * std::cos(phase) * phase_rate;
  const double flap_arm_rate = -amp * s.A_arm * std::sin(phase) * phase_rate;
  const double flap_hand_rate = -amp * s.A_hand * std::sin(hand_phase) * phase_rate;

  const WingFrames w = wing_frames(s, a);
  const Frame &shoulder = w.shoulder, &arm = w.arm, &hand = w.hand;
  const double wing_area = 0.5 * s.wing_area;
  const dvec3 &shoulder_pos = w.shoulder_pos, &wrist = w.wrist;

  WingPoint& pa = out[0];
  WingPoint& ph = out[1];
  segment_middles(w, pa.position, ph.position);
  // Joint angular velocities: lead-lag about body y, flapping about -x of the parent frame.
  const dvec3 omega_shoulder = dvec3{0, leadlag_rate, 0} - shoulder.x * flap_arm_rate;
  const dvec3 omega_wrist = -arm.x * flap_hand_rate;
  pa.velocity = glm::cross(omega_shoulder, pa.position - shoulder_pos);
  ph.velocity = glm::cross(omega_shoulder, ph.position - shoulder_pos) +
                glm::cross(omega_wrist, ph.position - wrist);
  feather(arm, a.feather_arm, pa.chord, pa.normal);
  feather(hand, a.feather_arm + a.feather_hand, ph.chord, ph.normal);
  pa.area = s.arm_area_fraction * wing_area;
  ph.area = wing_area - pa.area;
}

void right_wing_places(const Species& s, double phase, double amp, double sweep, dvec3 out[2]) {
  segment_middles(wing_frames(s, wingbeat_angles(s, phase, amp, sweep, 0.0)), out[0], out[1]);
}

dvec3 right_wingtip(const Species& s, double phase, double amp, double sweep) {
  const WingFrames w = wing_frames(s, wingbeat_angles(s, phase, amp, sweep, 0.0));
  return w.wrist + w.hand.z * w.hand_length;
}

WingPoint mirror_to_left(const WingPoint& p) {
  auto m = [](const dvec3& v) { return dvec3{v.x, v.y, -v.z}; };
  return {m(p.position), m(p.velocity), m(p.chord), m(p.normal), p.area};
}

}  // namespace aeroflock
