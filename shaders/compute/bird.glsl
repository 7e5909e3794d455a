// What the step and the drawing of a bird share: precise trigonometry, quaternion rotation, the
// wingbeat's joint angles and the tail's opening (engine/model: wingbeat.cpp, body.cpp, tail.cpp).
// Needs host_device.h (GpuBird, GpuSpecies).
#include "model/constants.h"

// --- Precise trigonometry --------------------------------------------------------------------
// Vulkan lets sin and cos be off by 2^-11 (lavapipe's are); these are good to a few float ulps
// for the angles the model uses, so that the shader follows the double-precision reference.

vec2 sin_cos(float x) {
  precise float k = round(x * 0.636619772);                    // x / (pi / 2)
  precise float r = (x - k * 1.57079637) + k * 4.37113883e-8;  // x - k pi / 2, two-part pi / 2
  precise float r2 = r * r;
  // clang-format off
  precise float s = r + r * r2 * (-1.66666667e-1 + r2 * (8.33333333e-3 + r2 * (-1.98412698e-4 + r2 * 2.75573192e-6)));
  precise float c = 1.0 + r2 * (-0.5 + r2 * (4.16666667e-2 + r2 * (-1.38888889e-3 + r2 * 2.48015873e-5)));
  // clang-format on
  int q = int(k) & 3;
  if (q == 0) return vec2(s, c);
  if (q == 1) return vec2(c, -s);
  if (q == 2) return vec2(-s, -c);
  return vec2(-c, s);
}
float sin_p(float x) { return sin_cos(x).x; }
float cos_p(float x) { return sin_cos(x).y; }
float tan_p(float x) {
  vec2 sc = sin_cos(x);
  return sc.x / sc.y;
}

// atan2 (Vulkan allows atan 4096 ulps): reduced to |u| <= tan(pi / 8), then a series.
float atan_p(float y, float x) {
  float ax = abs(x), ay = abs(y);
  if (ax == 0.0 && ay == 0.0) return 0.0;
  bool swap = ay > ax;
  precise float t = swap ? ax / ay : ay / ax;
  bool shift = t > 0.414213562;
  precise float u = shift ? (t - 1.0) / (t + 1.0) : t;
  precise float u2 = u * u;
  // clang-format off
  precise float a = u + u * u2 * (-0.333333333 + u2 * (0.2 + u2 * (-0.142857143 + u2 * (0.111111111 +
                    u2 * (-0.0909090909 + u2 * (0.0769230769 + u2 * (-0.0666666667)))))));
  // clang-format on
  if (shift) a += 0.785398163;
  if (swap) a = 1.57079633 - a;
  if (x < 0.0) a = 3.14159265 - a;
  return y < 0.0 ? -a : a;
}
float atan_p(float x) { return atan_p(x, 1.0); }
float asin_p(float x) { return atan_p(x, sqrt(max(0.0, 1.0 - x * x))); }

// --- Quaternions (body.cpp) -----------------------------------------------------------------

vec3 rotate(vec4 q, vec3 v) {
  precise vec3 t = 2.0 * cross(q.xyz, v);
  precise vec3 r = v + q.w * t + cross(q.xyz, t);
  return r;
}

// --- Wingbeat joint angles (wingbeat.cpp) ----------------------------------------------------

// wingbeat.h's, with the sines and cosines of the phases, which right_wing_points uses again.
struct WingbeatAngles {
  float sin_phase, cos_phase, sin_hand_phase, cos_hand_phase;
  float flap_arm, flap_hand, feather_arm, feather_hand, leadlag;  // rad
};

// The right wing's joint angles at wingbeat phase `phase`, amplitude `amp`, mean lead-lag `sweep`
// and the arm's added incidence (docs/MODEL.md; wingbeat.cpp).
WingbeatAngles wingbeat_angles(GpuSpecies s, float phase, float amp, float sweep, float incidence) {
  WingbeatAngles w;
  vec2 p = sin_cos(phase), h = sin_cos(phase - s.lag_hand);
  w.sin_phase = p.x;
  w.cos_phase = p.y;
  w.sin_hand_phase = h.x;
  w.cos_hand_phase = h.y;
  w.flap_arm = amp * s.A_arm * w.cos_phase + s.flap_bias;
  w.flap_hand = amp * s.A_hand * w.cos_hand_phase;
  w.feather_arm = s.B_arm * w.sin_phase - s.twist_bias - incidence;
  w.feather_hand = s.B_hand * w.sin_hand_phase;
  w.leadlag = sweep + s.C_leadlag * w.sin_phase;
  return w;
}

// --- Tail opening (eq. 10; tail.cpp) ---------------------------------------------------------

float tail_opening(GpuSpecies s, float bend, float twist) {
  float larger = abs(bend) > abs(twist) ? bend : twist;
  return s.Ct * abs(larger) + s.tail_min;
}

// The opening now: eq. 10, or fully open while the bird brakes to land.
float tail_opening(GpuSpecies s, GpuBird b) {
  return b.mode == mode_landing ? s.open_tail : tail_opening(s, b.tail_bend, b.tail_twist);
}
