// The cameras of the window and the pictures (render/camera_control.h): auto, orbit, follow,
// fixed and free.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/mat4x4.hpp>
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

// How a flock's birds lie in a picture of `aspect` from `camera`: the share of them in it, and how
// far out from its middle they reach (1: to its edge, across or up).
struct InPicture {
  double seen = 0.0, reach = 0.0;
};
InPicture in_picture(const Camera& camera, float aspect, const std::vector<BirdState>& birds,
                     uint32_t flock) {
  const glm::mat4 vp = camera.view_projection(aspect);
  float reach = 0.0f;
  size_t inside = 0, all = 0;
  for (const BirdState& b : birds) {
    if (b.flock != flock) continue;
    ++all;
    const glm::vec4 clip = vp * glm::vec4(glm::vec3(b.position - camera.origin), 1.0f);
    const glm::vec2 ndc = glm::vec2(clip) / clip.w;
    if (clip.w <= 0.0f || std::abs(ndc.x) > 1.0f || std::abs(ndc.y) > 1.0f) continue;
    ++inside;
    reach = std::max({reach, std::abs(ndc.x), std::abs(ndc.y)});
  }
  return {double(inside) / double(all), double(reach)};
}

// The automatic camera frames the followed bird's flock alone, and a flat or wide one as it is
// seen, not as the sphere round it: a V of 15 birds 60 m wide (an ibis or goose skein) with
// another 300 m to its side, and a flat disc of birds 80 m across.
TEST(CameraControl, AutoFramesTheFollowedBirdsFlockAsItIsSeen) {
  std::vector<BirdState> birds;
  auto bird = [&](uint32_t flock, glm::dvec3 at) {
    BirdState b;
    b.flock = flock;
    b.position = at;
    b.velocity = {1000.0, 0.0, 0.0};  // along +x, 10 m/s
    birds.push_back(b);
  };
  for (const uint32_t flock : {0u, 1u})
    for (int k = -7; k <= 7; ++k)  // arms 30 m out, each bird 4 m behind the one ahead
      bird(flock, {-400.0 * std::abs(k), 3000.0, 430.0 * k + 30000.0 * flock});
  for (const float aspect : {16.0f / 9.0f, 4.0f / 3.0f, 9.0f / 16.0f}) {
    CameraOptions options;
    options.aspect = aspect;
    const CameraControl c(options, subject_of(birds, 0, 0.0));
    const InPicture v = in_picture(c.camera(), aspect, birds, 0);
    EXPECT_EQ(v.seen, 1.0) << aspect;
    EXPECT_GT(v.reach, 0.5) << aspect;  // the outline within kFill, 0.6, of each side
    EXPECT_LE(v.reach, 0.61) << aspect;
    EXPECT_LT(c.camera().target_world().z, 500.0) << aspect;  // on this skein, not between
  }
  // A followed bird quarantined (not finite): still its own skein.
  std::vector<BirdState> quarantined = birds;
  quarantined[0].position.x = std::numeric_limits<double>::quiet_NaN();
  EXPECT_LT(
      CameraControl(CameraOptions{}, subject_of(quarantined, 0, 0.0)).camera().target_world().z,
      500.0);
  // Following a bird of the other skein frames that one.
  const CameraControl other(CameraOptions{}, subject_of(birds, 20, 0.0));
  EXPECT_EQ(in_picture(other.camera(), 16.0f / 9.0f, birds, 1).seen, 1.0);
  EXPECT_GT(other.camera().target_world().z, 29500.0);

  // A flat disc 80 m across, 2 m thick: framed by its width, nearer than the sphere of its radius
  // would be.
  birds.clear();
  for (int i = 0; i < 400; ++i) {
    const double r = 4000.0 * std::sqrt((i + 0.5) / 400.0), a = 2.39996 * i;  // sunflower
    bird(0, {r * std::cos(a), 3000.0 + 100.0 * std::sin(7.0 * a), r * std::sin(a)});
  }
  const Subject disc = subject_of(birds, 0, 0.0);
  const CameraControl c(CameraOptions{}, disc);
  const InPicture v = in_picture(c.camera(), 16.0f / 9.0f, birds, 0);
  EXPECT_GE(v.seen, 0.95);
  EXPECT_GT(v.reach, 0.5);
  const float sphere = disc.radius / std::tan(0.3f * glm::radians(50.0f));
  EXPECT_LT(glm::length(c.camera().eye - c.camera().target), sphere / 1.3f);
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
