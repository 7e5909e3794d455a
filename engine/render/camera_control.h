// The cameras of the window and of headless pictures alike: auto (frames the flock from behind
// its heading), orbit (circles the flock), follow (behind one bird) and free (placed, or flown with
// the keys). What the flock does goes in as a Subject; drags, wheel clicks and keys go in; a
// Camera comes out.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "model/bird.h"
#include "render/camera.h"

namespace aeroflock::render {

// What the cameras look at, from a reading of the birds now and then.
struct Subject {
  glm::dvec3 centre{0.0};  // the flock's main body (model/flock_geometry.h: flock_core), world cm
  float radius = 0.0f;     // 90 % of its birds lie this near the centre, cm
  // Of those birds, the farthest out in each of 26 directions (the axes, and the diagonals of the
  // squares and of the cube), about the centre, cm: the outline auto fits in the picture. Without
  // it only the radius is fitted.
  std::array<glm::vec3, 26> outline{};
  bool has_outline = false;
  glm::dvec3 velocity{0.0};  // the flock's mean velocity, cm/s
  glm::dvec3 bird{0.0};      // the followed bird, world cm
  glm::dvec3 bird_velocity{0.0};
  double time = 0.0;  // simulated time of the reading, s

  // The centre and the followed bird at simulated time `t`, carried on at their velocities.
  glm::dvec3 centre_at(double t) const { return centre + velocity * (t - time); }
  glm::dvec3 bird_at(double t) const { return bird + bird_velocity * (t - time); }
};
// The flock of bird `followed`, of its finite birds (a bird with NaN is left out): a scenario's
// flocks may fly far apart (geese-migration's three skeins, 300 m), and a picture of them all
// would draw each bird a pixel. A bird `followed` that is not there: every flock. One not finite
// (quarantined) falls back on the centre of its flock.
Subject subject_of(const std::vector<BirdState>& birds, uint32_t followed, double time);

// automatic frames the flock and follows it, orbit circles it, follow rides behind one bird, free
// is moved by hand (--camera fixed: held still where it is put).
enum class CameraMode { automatic, orbit, follow, free };

// How a camera starts: `--camera`, `--camera-bird`, `--camera-eye`, `--camera-target`, `--fov`.
struct CameraOptions {
  CameraMode mode = CameraMode::automatic;
  uint32_t bird = 0;                      // follow: which bird
  std::optional<glm::dvec3> eye, target;  // fixed: world, cm (default: where auto starts)
  float fov_degrees = 50.0f;
  float aspect = 16.0f / 9.0f;  // the picture's width / height: auto frames the flock in both
};

class CameraControl {
 public:
  using Mode = CameraMode;
  static const char* name(Mode mode);

  CameraControl() = default;
  // Starts as `options` say, framing `subject` at once. Throws std::invalid_argument for a fixed
  // camera that looks at its own eye.
  CameraControl(const CameraOptions& options, const Subject& subject);

  Mode mode() const { return mode_; }
  // The free camera starts where the camera is now; follow, auto and orbit glide from it.
  void set_mode(Mode mode);
  // Back to the automatic camera at its own distance, framing `subject` at once.
  void reset(const Subject& subject);

  // Left-button drag by (dx, dy) pixels: turns the view around the flock or the bird, or looks
  // around with the free camera.
  void drag(float dx, float dy);
  // Wheel clicks (away from the user > 0): closer.
  void zoom(float clicks);
  // Free camera: moves along (right, up, forward) for `seconds`; `fast` five times quicker.
  void move(glm::vec3 direction, float seconds, bool fast);

  // Advances the camera by `seconds` (of simulated time for pictures, of wall time in a window)
  // to look at `subject` as it is at simulated time `time`. Returns the camera to draw with, its
  // origin on what it looks at (on itself, free), so its floats stay small.
  const Camera& update(float seconds, const Subject& subject, double time);
  const Camera& camera() const { return camera_; }
  // The picture's width / height (a window resized).
  void set_aspect(float aspect) { aspect_ = aspect; }
  // How far what the camera looks at is (cm): the fog and the shadows scale with it.
  float subject_distance() const { return subject_distance_; }

 private:
  void frame(float seconds, const Subject& subject, double time, bool snap);
  // The distance at which the subject's outline, seen from `yaw`, fills at most kFill of the
  // picture's height and width.
  float outline_fit(const Subject& subject, float yaw) const;
  void move_origin(const glm::dvec3& to);  // the same camera, from `to`

  Mode mode_ = Mode::automatic;
  Camera camera_;
  bool framed_ = false;         // auto and orbit have framed the flock once
  double framed_time_ = 0.0;    // s: the simulated time they last framed it at
  glm::dvec3 centre_{0.0};      // auto and orbit: the gliding point looked at, world
  float distance_ = 3000.0f;    // cm, gliding towards the framing distance
  float zoom_ = 1.0f;           // the wheel's factor on it
  float heading_ = 0.0f;        // rad: the flock's (auto) or the bird's (follow) last heading
  float view_yaw_ = 0.0f;       // rad: auto, gliding towards behind the heading
  float orbit_yaw_ = -1.5708f;  // rad: where orbit sees the flock from, turning slowly
  float drag_yaw_ = 0.0f;       // rad: the user's turn on auto and orbit
  float pitch_ = 0.25f;         // rad above the horizontal: auto and orbit
  float follow_yaw_ = 0.0f;     // rad: around the bird, 0 straight behind it
  float follow_pitch_ = 0.3f;
  float follow_distance_ = 800.0f;
  glm::vec3 follow_offset_{0.0f};  // eye - bird, gliding towards behind and above the bird
  float free_yaw_ = 0.0f;          // rad: the free camera's view direction
  float free_pitch_ = 0.0f;
  float free_speed_ = 1000.0f;  // cm/s
  float subject_distance_ = 3000.0f;
  float aspect_ = 16.0f / 9.0f;
};

}  // namespace aeroflock::render
