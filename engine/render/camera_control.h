// The viewer's three cameras: orbit around the flock, follow one bird from behind and above,
// and fly freely. Drags, wheel clicks and movement keys go in; a Camera comes out.
#pragma once

#include <glm/vec3.hpp>

#include "render/camera.h"

namespace aeroflock::render {

class CameraControl {
 public:
  enum class Mode { orbit, follow, free };

  // Orbit around `centre` (world) from far enough to see a flock of that `radius` (cm).
  void reset(const glm::dvec3& centre, float radius);

  Mode mode() const { return mode_; }
  // The free camera starts where the camera is now.
  void set_mode(Mode mode);

  // Left-button drag by (dx, dy) pixels: turns the orbit or the view around the bird, or looks
  // around with the free camera.
  void drag(float dx, float dy);
  // Wheel clicks (away from the user > 0): closer.
  void zoom(float clicks);
  // Free camera: moves along (right, up, forward) for `seconds`; `fast` five times quicker.
  void move(glm::vec3 direction, float seconds, bool fast);

  // Advances the camera by `seconds` of wall time: the orbit around `centre`, the follow camera
  // gliding to behind `bird` flying with `velocity` (centre and bird: world). Returns the camera
  // to draw with, its origin on what it looks at (on itself, free), so its floats stay small.
  const Camera& update(float seconds, const glm::dvec3& centre, const glm::dvec3& bird, glm::vec3 velocity);
  const Camera& camera() const { return camera_; }

 private:
  void move_origin(const glm::dvec3& to);  // the same camera, from `to`

  Mode mode_ = Mode::orbit;
  Camera camera_;
  float yaw_ = -1.5708f;  // rad: where the camera is seen from the centre (orbit, follow)
  float pitch_ = 0.35f;
  float distance_ = 3000.0f;  // cm
  float follow_yaw_ = 0.0f;   // rad: around the bird, 0 straight behind it
  float follow_pitch_ = 0.3f;
  float follow_distance_ = 800.0f;
  float follow_heading_ = 0.0f;    // rad: the bird's last horizontal heading
  glm::vec3 follow_offset_{0.0f};  // eye - bird, gliding towards behind and above the bird
  float free_yaw_ = 0.0f;          // rad: the free camera's view direction
  float free_pitch_ = 0.0f;
  float free_speed_ = 1000.0f;  // cm/s
};

}  // namespace aeroflock::render
