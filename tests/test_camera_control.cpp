// The viewer's cameras (render/camera_control.h): orbit, follow and free.
#include <gtest/gtest.h>

#include <glm/geometric.hpp>

#include "render/camera_control.h"

namespace aeroflock::render {
namespace {

using Mode = CameraControl::Mode;

TEST(CameraControl, OrbitLooksAtTheCentreFromFarEnoughForTheFlock) {
  CameraControl c;
  c.reset({100.0f, 3000.0f, 0.0f}, 2000.0f);
  const Camera& cam = c.update(0.02f, {100.0f, 3000.0f, 0.0f}, {}, {});
  EXPECT_EQ(cam.target_world(), glm::dvec3(100.0, 3000.0, 0.0));
  EXPECT_NEAR(glm::length(cam.eye - cam.target), 6000.0f, 1e-2f);
  EXPECT_GT(cam.eye.y, cam.target.y);  // from above

  c.zoom(1.0f);  // one click closer
  const Camera& closer = c.update(0.02f, {100.0f, 3000.0f, 0.0f}, {}, {});
  EXPECT_NEAR(glm::length(closer.eye - closer.target), 5400.0f, 1e-2f);

  const glm::vec3 before = closer.eye;
  c.drag(100.0f, 0.0f);  // turns around the centre, same distance
  const Camera& turned = c.update(0.02f, {100.0f, 3000.0f, 0.0f}, {}, {});
  EXPECT_GT(glm::length(turned.eye - before), 100.0f);
  EXPECT_NEAR(glm::length(turned.eye - turned.target), 5400.0f, 1e-2f);
}

TEST(CameraControl, FollowSettlesBehindAndAboveTheBird) {
  CameraControl c;
  c.reset({0.0f, 3000.0f, 0.0f}, 0.0f);
  c.set_mode(Mode::follow);
  const glm::vec3 velocity(0.0f, 0.0f, 1500.0f);  // flying along +z
  glm::vec3 bird(0.0f, 3000.0f, 0.0f);
  for (int i = 0; i < 300; ++i) {  // 6 s at 50 frames/s
    bird += velocity * 0.02f;
    c.update(0.02f, bird, bird, velocity);
  }
  const Camera& cam = c.camera();
  EXPECT_EQ(cam.target_world(), glm::dvec3(bird));
  const glm::vec3 offset(cam.eye_world() - glm::dvec3(bird));
  EXPECT_LT(offset.z, -500.0f);       // behind
  EXPECT_GT(offset.y, 100.0f);        // above
  EXPECT_NEAR(offset.x, 0.0f, 1.0f);  // straight behind
  EXPECT_NEAR(glm::length(offset), 800.0f, 1.0f);
}

TEST(CameraControl, FreeCameraFliesWhereItLooks) {
  CameraControl c;
  c.reset({0.0f, 3000.0f, 0.0f}, 0.0f);
  const Camera start = c.update(0.02f, {0.0f, 3000.0f, 0.0f}, {}, {});
  c.set_mode(Mode::free);
  const glm::vec3 look = glm::normalize(start.target - start.eye);
  c.move({0.0f, 0.0f, 1.0f}, 1.0f, false);  // forward for a second
  const Camera& moved = c.update(0.02f, {}, {}, {});
  const glm::vec3 travel(moved.eye_world() - start.eye_world());
  EXPECT_GT(glm::length(travel), 100.0f);
  EXPECT_NEAR(glm::dot(glm::normalize(travel), look), 1.0f, 1e-4f);
  EXPECT_NEAR(glm::dot(glm::normalize(moved.target - moved.eye), look), 1.0f, 1e-4f);
}

}  // namespace
}  // namespace aeroflock::render
