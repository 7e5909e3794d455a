#include "render/camera_control.h"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

namespace aeroflock::render {
namespace {

constexpr float kRadiansPerPixel = 0.005f;
constexpr float kMaxPitch = 1.5f;   // rad, short of straight up or down
constexpr float kGlideRate = 3.0f;  // 1/s: how fast the cameras catch up with what they follow
constexpr float kZoomPerClick = 0.9f;
constexpr float kPi = 3.14159265f;

// Unit vector at `yaw` from +x towards +z and `pitch` above the horizontal.
glm::vec3 direction(float yaw, float pitch) {
  return {std::cos(pitch) * std::cos(yaw), std::sin(pitch), std::cos(pitch) * std::sin(yaw)};
}

// The fraction of the way to go in `seconds` of an exponential glide.
float glide(float seconds) { return 1.0f - std::exp(-kGlideRate * seconds); }

}  // namespace

void CameraControl::reset(const glm::dvec3& centre, float radius) {
  mode_ = Mode::orbit;
  distance_ = std::max(1500.0f, 3.0f * radius);
  free_speed_ = std::max(500.0f, 0.5f * distance_);
  camera_.origin = centre;
  camera_.target = glm::vec3(0.0f);
  camera_.eye = distance_ * direction(yaw_, pitch_);
}

void CameraControl::move_origin(const glm::dvec3& to) { camera_ = camera_.from(to); }

void CameraControl::set_mode(Mode mode) {
  if (mode == Mode::free) {
    const glm::vec3 look = glm::normalize(camera_.target - camera_.eye);
    free_yaw_ = std::atan2(look.z, look.x);
    free_pitch_ = std::asin(std::clamp(look.y, -1.0f, 1.0f));
  }
  if (mode == Mode::follow && mode_ != Mode::follow) follow_offset_ = camera_.eye - camera_.target;
  mode_ = mode;
}

void CameraControl::drag(float dx, float dy) {
  float& yaw = mode_ == Mode::orbit ? yaw_ : mode_ == Mode::follow ? follow_yaw_ : free_yaw_;
  float& pitch = mode_ == Mode::orbit    ? pitch_
                 : mode_ == Mode::follow ? follow_pitch_
                                         : free_pitch_;
  // Orbit and follow turn the scene with the mouse; the free camera looks where the mouse goes.
  const float sign = mode_ == Mode::free ? 1.0f : -1.0f;
  yaw += sign * kRadiansPerPixel * dx;
  pitch = std::clamp(pitch - sign * kRadiansPerPixel * dy, -kMaxPitch, kMaxPitch);
}

void CameraControl::zoom(float clicks) {
  const float factor = std::pow(kZoomPerClick, clicks);
  if (mode_ == Mode::orbit) distance_ = std::clamp(distance_ * factor, 100.0f, 1.0e6f);
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

const Camera& CameraControl::update(float seconds, const glm::dvec3& centre, const glm::dvec3& bird,
                                    glm::vec3 velocity) {
  switch (mode_) {
    case Mode::orbit:
      move_origin(centre);
      camera_.target = glm::vec3(0.0f);
      camera_.eye = distance_ * direction(yaw_, pitch_);
      break;
    case Mode::follow: {
      // From behind the bird's horizontal heading (the last one while it hovers or stands); the
      // offset from the bird glides, so the camera turns smoothly but never trails behind.
      const glm::vec3 ahead(velocity.x, 0.0f, velocity.z);
      if (glm::length(ahead) > 10.0f) follow_heading_ = std::atan2(ahead.z, ahead.x);
      const glm::vec3 offset =
          follow_distance_ * direction(follow_heading_ + kPi + follow_yaw_, follow_pitch_);
      follow_offset_ += (offset - follow_offset_) * glide(seconds);
      move_origin(bird);
      camera_.eye = follow_offset_;
      camera_.target = glm::vec3(0.0f);
      break;
    }
    case Mode::free:
      move_origin(camera_.eye_world());
      camera_.target = camera_.eye + direction(free_yaw_, free_pitch_);
      break;
  }
  return camera_;
}

}  // namespace aeroflock::render
