// The cameras of the window and the pictures (render/camera_control.h): auto, orbit, follow,
// fixed and free.
#include <gtest/gtest.h>

#include <cmath>

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>
#include <glm/vec2.hpp>

#include "render/camera_control.h"

namespace aeroflock::render {
namespace {

using Mode = CameraControl::Mode;

Subject flock_at(glm::dvec3 centre, float radius, glm::dvec3 velocity = glm::dvec3(0.0)) {
  Subject s;
  s.centre = s.bird = centre;
  s.radius = radius;
  s.velocity = s.bird_velocity = velocity;
  return s;
}

TEST(CameraControl, AutoFramesTheFlockFromBehindItsHeading) {
  const Subject flock = flock_at({100.0, 3000.0, 0.0}, 2000.0f, {0.0, 0.0, 1000.0});  // along +z
  CameraControl c(CameraOptions{}, flock);
  EXPECT_EQ(c.mode(), Mode::automatic);
  const Camera cam = c.camera();
  EXPECT_NEAR(glm::distance(cam.target_world(), flock.centre), 0.0, 1e-3);
  // The core's radius fills 60 % of the field of view: 2000 / tan(0.3 fov).
  const float fit = 2000.0f / std::tan(0.3f * glm::radians(50.0f));
  EXPECT_NEAR(glm::length(cam.eye - cam.target), fit, 1.0f);
  const glm::vec3 offset = cam.eye - cam.target;
  EXPECT_LT(offset.z, -0.5f * fit);  // behind the flock
  EXPECT_GT(offset.y, 0.2f * fit);   // above it

  c.zoom(1.0f);  // one click closer
  const Camera closer = c.update(0.0f, flock, 0.0);
  EXPECT_NEAR(glm::length(closer.eye - closer.target), 0.9f * fit, 1.0f);
  c.drag(100.0f, 0.0f);  // turns around the flock, same distance
  const Camera turned = c.update(0.0f, flock, 0.0);
  EXPECT_GT(glm::length(turned.eye - closer.eye), 100.0f);
  EXPECT_NEAR(glm::length(turned.eye - turned.target), 0.9f * fit, 1.0f);
}

TEST(CameraControl, AutoGlidesWithTheFlockWithoutTrailingIt) {
  // A flock flying straight at 10 m/s is kept centred (carried at its velocity, not chased), and a
  // flock that grows is framed again smoothly, without a jump.
  const glm::dvec3 v(1000.0, 0.0, 0.0);
  CameraControl c(CameraOptions{}, flock_at({0.0, 3000.0, 0.0}, 1000.0f, v));
  double t = 0.0;
  float last_distance = glm::length(c.camera().eye - c.camera().target);
  float largest_step = 0.0f;
  for (int i = 0; i < 300; ++i) {  // 9 s at 30 ms a frame
    t += 0.03;
    Subject flock = flock_at(v * t + glm::dvec3(0.0, 3000.0, 0.0), t < 3.0 ? 1000.0f : 3000.0f, v);
    flock.time = t;
    const Camera& cam = c.update(0.03f, flock, t);
    EXPECT_LT(glm::distance(cam.target_world(), flock.centre), 1.0) << "t = " << t;
    const float distance = glm::length(cam.eye - cam.target);
    largest_step = std::max(largest_step, std::abs(distance - last_distance));
    last_distance = distance;
  }
  const float fit = 3000.0f / std::tan(0.3f * glm::radians(50.0f));
  EXPECT_NEAR(last_distance, fit, 0.02f * fit);  // settled on the larger flock
  EXPECT_LT(largest_step, 0.05f * fit);          // a glide, not a jump
}

TEST(CameraControl, AutoStaysOnAPausedFlock) {
  // In a window the glide runs on wall time while the simulation may be paused: the camera is
  // carried with the flock by simulated time only, so it does not drift ahead of a paused flock.
  const glm::dvec3 v(1500.0, 0.0, 0.0);
  Subject flock = flock_at({0.0, 3000.0, 0.0}, 1000.0f, v);
  flock.time = 5.0;
  CameraControl c(CameraOptions{}, flock);
  for (int i = 0; i < 200; ++i) c.update(0.02f, flock, 5.0);  // 4 s of wall time, paused
  EXPECT_LT(glm::distance(c.camera().target_world(), flock.centre), 1.0);
}

TEST(CameraControl, OrbitCirclesTheFlock) {
  const Subject flock = flock_at({0.0, 3000.0, 0.0}, 1000.0f);
  CameraOptions options;
  options.mode = CameraMode::orbit;
  CameraControl c(options, flock);
  const glm::vec3 start = c.camera().eye - c.camera().target;
  const Camera& cam = c.update(10.0f, flock, 10.0);  // a tenth of a turn a second
  const glm::vec3 now = cam.eye - cam.target;
  EXPECT_NEAR(glm::length(now), glm::length(start), 1.0f);
  const float turned = std::acos(glm::dot(glm::normalize(glm::vec2(start.x, start.z)),
                                          glm::normalize(glm::vec2(now.x, now.z))));
  EXPECT_NEAR(turned, 1.0f, 1e-3f);
}

TEST(CameraControl, FixedLooksFromWhereItIsPut) {
  CameraOptions options;
  options.mode = CameraMode::free;
  options.eye = glm::dvec3(5.0e7, 2000.0, 100.0);  // 500 km out
  options.target = glm::dvec3(5.0e7 + 1000.0, 2000.0, 100.0);
  CameraControl c(options, flock_at({0.0, 3000.0, 0.0}, 1000.0f));
  EXPECT_EQ(c.mode(), Mode::free);
  const Camera& cam = c.update(1.0f, flock_at({0.0, 3000.0, 0.0}, 1000.0f), 1.0);
  EXPECT_NEAR(glm::distance(cam.eye_world(), *options.eye), 0.0, 1e-3);
  EXPECT_NEAR(glm::dot(glm::normalize(cam.target - cam.eye), glm::vec3(1.0f, 0.0f, 0.0f)), 1.0f,
              1e-6f);
}

TEST(CameraControl, FollowSettlesBehindAndAboveTheBird) {
  CameraOptions options;
  options.mode = CameraMode::follow;
  const glm::dvec3 velocity(0.0, 0.0, 1500.0);  // flying along +z
  glm::dvec3 bird(0.0, 3000.0, 0.0);
  CameraControl c(options, flock_at(bird, 0.0f, velocity));
  for (int i = 0; i < 300; ++i) {  // 6 s at 50 frames/s
    bird += velocity * 0.02;
    c.update(0.02f, flock_at(bird, 0.0f, velocity), 0.0);
  }
  const Camera& cam = c.camera();
  EXPECT_NEAR(glm::distance(cam.target_world(), bird), 0.0, 1e-3);
  const glm::vec3 offset(cam.eye_world() - bird);
  EXPECT_LT(offset.z, -500.0f);       // behind
  EXPECT_GT(offset.y, 100.0f);        // above
  EXPECT_NEAR(offset.x, 0.0f, 1.0f);  // straight behind
  EXPECT_NEAR(glm::length(offset), 800.0f, 1.0f);
}

TEST(CameraControl, FreeCameraFliesWhereItLooks) {
  const Subject flock = flock_at({0.0, 3000.0, 0.0}, 0.0f);
  CameraControl c(CameraOptions{}, flock);
  const Camera start = c.update(0.02f, flock, 0.0);
  c.set_mode(Mode::free);
  const glm::vec3 look = glm::normalize(start.target - start.eye);
  c.move({0.0f, 0.0f, 1.0f}, 1.0f, false);  // forward for a second
  const Camera& moved = c.update(0.02f, flock, 0.0);
  const glm::vec3 travel(moved.eye_world() - start.eye_world());
  EXPECT_GT(glm::length(travel), 100.0f);
  EXPECT_NEAR(glm::dot(glm::normalize(travel), look), 1.0f, 1e-4f);
  EXPECT_NEAR(glm::dot(glm::normalize(moved.target - moved.eye), look), 1.0f, 1e-4f);
}

}  // namespace
}  // namespace aeroflock::render
