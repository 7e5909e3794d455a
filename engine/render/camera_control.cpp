#include "render/camera_control.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <glm/geometric.hpp>

#include "model/flock_geometry.h"

namespace aeroflock::render {
namespace {

constexpr float kRadiansPerPixel = 0.005f;
constexpr float kMaxPitch = 1.5f;     // rad, short of straight up or down
constexpr float kGlideRate = 3.0f;    // 1/s: how fast follow catches up with its bird
constexpr float kFrameRate = 1.0f;    // 1/s: how fast auto and orbit follow the flock's changes
constexpr float kOrbitRate = 0.1f;    // rad/s: a turn round the flock a minute
constexpr float kAutoSide = 1.0f;     // rad: auto looks from behind and to the side
constexpr float kAutoPitch = 0.25f;   // rad: auto and orbit look down on the flock this much
constexpr float kMinRadius = 150.0f;  // cm: one bird is framed as a flock this wide
constexpr float kFill = 0.6f;         // of the picture (height and width), the flock's core
constexpr float kZoomPerClick = 0.9f;
constexpr float kPi = 3.14159265f;

// The outline's directions (Subject::outline): the 6 axes, the 12 diagonals of the squares and
// the 8 of the cube.
const std::array<glm::vec3, 26> kOutline = [] {
  std::array<glm::vec3, 26> d{};
  size_t n = 0;
  for (int x = -1; x <= 1; ++x)
    for (int y = -1; y <= 1; ++y)
      for (int z = -1; z <= 1; ++z)
        if (x != 0 || y != 0 || z != 0) d[n++] = glm::normalize(glm::vec3(x, y, z));
  return d;
}();

// Unit vector at `yaw` from +x towards +z and `pitch` above the horizontal.
glm::vec3 direction(float yaw, float pitch) {
  return {std::cos(pitch) * std::cos(yaw), std::sin(pitch), std::cos(pitch) * std::sin(yaw)};
}

// The fraction of the way to go in `seconds` of an exponential glide at `rate`.
float glide(float seconds, float rate = kGlideRate) { return 1.0f - std::exp(-rate * seconds); }

// `a` moved the fraction `f` of the way to `b` round the circle.
float glide_angle(float a, float b, float f) { return a + f * std::remainder(b - a, 2.0f * kPi); }

}  // namespace

Subject subject_of(const std::vector<BirdState>& birds, uint32_t followed, double time) {
  Subject s;
  s.time = time;
  const bool bird_ok = followed < birds.size() && is_finite(birds[followed]);
  const uint32_t flock = followed < birds.size() ? birds[followed].flock : kAnyFlock;
  const FlockCore core = flock_core(birds, 0.9, flock);
  if (core.finite == 0) return s;
  s.centre = core.centre;
  s.radius = float(core.radius);
  std::array<float, 26> farthest;
  farthest.fill(-1.0f);
  for (const BirdState& b : birds) {
    if (!is_finite(b) || (flock != kAnyFlock && b.flock != flock)) continue;
    const glm::vec3 offset(b.position - core.centre);
    if (glm::length(offset) > s.radius) continue;
    for (size_t k = 0; k < kOutline.size(); ++k)
      if (const float out = glm::dot(offset, kOutline[k]); out > farthest[k])
        farthest[k] = out, s.outline[k] = offset;
  }
  s.has_outline = true;
  s.velocity = core.velocity;
  s.bird = bird_ok ? birds[followed].position : s.centre;
  s.bird_velocity = bird_ok ? birds[followed].velocity : s.velocity;
  return s;
}

const char* CameraControl::name(Mode mode) {
  switch (mode) {
    case Mode::automatic:
      return "auto";
    case Mode::orbit:
      return "orbit";
    case Mode::follow:
      return "follow";
    case Mode::free:
      return "free";
  }
  return "?";
}

CameraControl::CameraControl(const CameraOptions& options, const Subject& subject) {
  camera_.fov_y = glm::radians(options.fov_degrees);
  aspect_ = options.aspect;
  reset(subject);
  const Mode mode = options.mode;
  if (mode == Mode::free) {
    // Placed where asked; what is not given comes from the automatic camera's first framing.
    const glm::dvec3 eye = options.eye.value_or(camera_.eye_world());
    const glm::dvec3 target =
        options.target.value_or(options.eye ? subject.centre : camera_.target_world());
    if (glm::distance(eye, target) < 1.0)
      throw std::invalid_argument("the fixed camera's eye and target are the same point");
    camera_.origin = eye;
    camera_.eye = glm::vec3(0.0f);
    camera_.target = glm::vec3(target - eye);
  }
  set_mode(mode);
  if (mode == Mode::follow) {  // behind the bird from the first picture
    const glm::dvec3 v = subject.bird_velocity;
    if (v.x * v.x + v.z * v.z > 10.0 * 10.0) heading_ = float(std::atan2(v.z, v.x));
    follow_offset_ = follow_distance_ * direction(heading_ + kPi + follow_yaw_, follow_pitch_);
  }
  update(0.0f, subject, subject.time);
}

void CameraControl::reset(const Subject& subject) {
  mode_ = Mode::automatic;
  framed_ = false;
  zoom_ = 1.0f;
  drag_yaw_ = 0.0f;
  pitch_ = kAutoPitch;
  update(0.0f, subject, subject.time);
}

void CameraControl::move_origin(const glm::dvec3& to) { camera_ = camera_.from(to); }

void CameraControl::set_mode(Mode mode) {
  if (mode == Mode::free) {
    const glm::vec3 look = glm::normalize(camera_.target - camera_.eye);
    free_yaw_ = std::atan2(look.z, look.x);
    free_pitch_ = std::clamp(std::asin(std::clamp(look.y, -1.0f, 1.0f)), -kMaxPitch, kMaxPitch);
  }
  if (mode == Mode::follow && mode_ != Mode::follow) follow_offset_ = camera_.eye - camera_.target;
  const bool around_flock = mode == Mode::automatic || mode == Mode::orbit;
  if (around_flock && framed_ && (mode_ == Mode::follow || mode_ == Mode::free)) {
    // Glide to the flock from where the camera is: it looks at what it looked at, from there.
    centre_ = camera_.target_world();
    const glm::vec3 offset = camera_.eye - camera_.target;
    distance_ = std::max(glm::length(offset), 1.0f) / zoom_;
    pitch_ = std::clamp(
        std::asin(std::clamp(offset.y / std::max(glm::length(offset), 1e-6f), -1.0f, 1.0f)),
        -kMaxPitch, kMaxPitch);
    view_yaw_ = orbit_yaw_ = std::atan2(offset.z, offset.x);
    drag_yaw_ = 0.0f;
  } else if (mode == Mode::orbit && mode_ == Mode::automatic) {
    orbit_yaw_ = view_yaw_ + drag_yaw_, drag_yaw_ = 0.0f;
  }
  mode_ = mode;
}

void CameraControl::drag(float dx, float dy) {
  const bool around_flock = mode_ == Mode::automatic || mode_ == Mode::orbit;
  float& yaw = around_flock ? drag_yaw_ : mode_ == Mode::follow ? follow_yaw_ : free_yaw_;
  float& pitch = around_flock ? pitch_ : mode_ == Mode::follow ? follow_pitch_ : free_pitch_;
  // Auto, orbit and follow turn the scene with the mouse; the free camera looks where it goes.
  const float sign = mode_ == Mode::free ? 1.0f : -1.0f;
  yaw += sign * kRadiansPerPixel * dx;
  pitch = std::clamp(pitch - sign * kRadiansPerPixel * dy, -kMaxPitch, kMaxPitch);
}

void CameraControl::zoom(float clicks) {
  const float factor = std::pow(kZoomPerClick, clicks);
  if (mode_ == Mode::automatic || mode_ == Mode::orbit)
    zoom_ = std::clamp(zoom_ * factor, 0.01f, 100.0f);
  if (mode_ == Mode::follow)
    follow_distance_ = std::clamp(follow_distance_ * factor, 50.0f, 1.0e5f);
  if (mode_ == Mode::free) free_speed_ = std::clamp(free_speed_ / factor, 10.0f, 1.0e6f);
}

void CameraControl::move(glm::vec3 d, float seconds, bool fast) {
  if (mode_ != Mode::free) return;
  const glm::vec3 forward = direction(free_yaw_, free_pitch_);
  const glm::vec3 right = glm::normalize(glm::cross(forward, glm::vec3(0.0f, 1.0f, 0.0f)));
  const float step = free_speed_ * seconds * (fast ? 5.0f : 1.0f);
  camera_.eye += step * (d.x * right + d.y * glm::vec3(0.0f, 1.0f, 0.0f) + d.z * forward);
}

// Auto and orbit: the point looked at glides with the flock (carried at its velocity, so a flock
// flying straight is not trailed), and the distance to fit its core in kFill of the view.
void CameraControl::frame(float seconds, const Subject& subject, double time, bool snap) {
  const float f = snap ? 1.0f : glide(seconds, kFrameRate);
  // Carried by the simulated time gone by (none while paused, more when sped up).
  const glm::dvec3 carried = centre_ + subject.velocity * (snap ? 0.0 : time - framed_time_);
  framed_time_ = time;
  centre_ = glm::mix(carried, subject.centre_at(time), double(f));
  const glm::dvec3 v = subject.velocity;
  if (v.x * v.x + v.z * v.z > 100.0 * 100.0) heading_ = float(std::atan2(v.z, v.x));
  view_yaw_ =
      snap ? heading_ + kPi + kAutoSide : glide_angle(view_yaw_, heading_ + kPi + kAutoSide, f);
  orbit_yaw_ += kOrbitRate * seconds;
  const float yaw = (mode_ == Mode::orbit ? orbit_yaw_ : view_yaw_) + drag_yaw_;
  // Its outline, seen from here, in kFill of the height and the width (a flat flock seen from a
  // little above, a wide one from behind, a picture taller than wide); without one, the core's
  // sphere in kFill of the height.
  const float fit = subject.has_outline ? outline_fit(subject, yaw)
                                        : std::max(subject.radius, kMinRadius) /
                                              std::tan(0.5f * kFill * camera_.fov_y);
  distance_ += f * (fit - distance_);
  move_origin(centre_);
  camera_.target = glm::vec3(0.0f);
  camera_.eye = zoom_ * distance_ * direction(yaw, pitch_);
  subject_distance_ = zoom_ * distance_;
}

float CameraControl::outline_fit(const Subject& subject, float yaw) const {
  const glm::vec3 back = direction(yaw, pitch_);  // from the centre towards the eye
  const glm::vec3 right = glm::normalize(glm::cross(glm::vec3(0.0f, 1.0f, 0.0f), back));
  const glm::vec3 up = glm::cross(back, right);
  const float tan_y = kFill * std::tan(0.5f * camera_.fov_y), tan_x = aspect_ * tan_y;
  float fit = kMinRadius / std::tan(0.5f * kFill * camera_.fov_y);
  for (const glm::vec3& c : subject.outline) {
    const float depth = glm::dot(c, back);  // nearer the eye than the centre by this
    fit = std::max({fit, depth + kMinRadius, depth + std::abs(glm::dot(c, right)) / tan_x,
                    depth + std::abs(glm::dot(c, up)) / tan_y});
  }
  return fit;
}

const Camera& CameraControl::update(float seconds, const Subject& subject, double time) {
  switch (mode_) {
    case Mode::automatic:
    case Mode::orbit:
      frame(seconds, subject, time, !framed_);
      framed_ = true;
      break;
    case Mode::follow: {
      // From behind the bird's horizontal heading (the last one while it hovers or stands); the
      // offset from the bird glides, so the camera turns smoothly but never trails behind.
      const glm::vec3 velocity(subject.bird_velocity);
      const glm::vec3 ahead(velocity.x, 0.0f, velocity.z);
      if (glm::length(ahead) > 10.0f) heading_ = std::atan2(ahead.z, ahead.x);
      const glm::vec3 offset =
          follow_distance_ * direction(heading_ + kPi + follow_yaw_, follow_pitch_);
      follow_offset_ += (offset - follow_offset_) * glide(seconds);
      move_origin(subject.bird_at(time));
      camera_.eye = follow_offset_;
      camera_.target = glm::vec3(0.0f);
      subject_distance_ = glm::length(follow_offset_);
      break;
    }
    case Mode::free:
      move_origin(camera_.eye_world());
      camera_.target = camera_.eye + direction(free_yaw_, free_pitch_);
      subject_distance_ = float(glm::distance(camera_.eye_world(), subject.centre_at(time)));
      break;
  }
  return camera_;
}

}  // namespace aeroflock::render
