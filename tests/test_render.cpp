// Headless rendering: the image has the asked size, the birds are drawn where their state says
// (projected with the same camera), and a bird with its wings up draws differently from one with
// its wings down. Validation on.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>

#include <glm/vec4.hpp>

#include "gpu/compute.h"
#include "gpu/gpu_simulation.h"
#include "gpu_test_device.h"
#include "io/scenario_file.h"
#include "model/constants.h"
#include "model/simulation.h"
#include "render/offscreen.h"
#include "render/renderer.h"
#include "render_image.h"

namespace aeroflock {
namespace {

using testing::Image;
using testing::render;

// Pixel coordinates of a world point.
glm::vec2 project(const render::Camera& camera, VkExtent2D size, const glm::dvec3& p) {
  const glm::vec4 clip = camera.view_projection(float(size.width) / size.height) * glm::vec4(glm::vec3(p), 1.0f);
  const glm::vec2 ndc = glm::vec2(clip) / clip.w;
  return {(ndc.x * 0.5f + 0.5f) * size.width, (ndc.y * 0.5f + 0.5f) * size.height};
}

// Pixels within `radius` of `centre` that differ from the same pixels of `background`.
int changed_near(const Image& image, const Image& background, glm::vec2 centre, int radius) {
  int changed = 0;
  for (int y = int(centre.y) - radius; y <= int(centre.y) + radius; ++y)
    for (int x = int(centre.x) - radius; x <= int(centre.x) + radius; ++x) {
      if (x < 0 || y < 0 || x >= int(image.width) || y >= int(image.height)) continue;
      const glm::ivec3 d = image.at(x, y) - background.at(x, y);
      if (std::abs(d.x) + std::abs(d.y) + std::abs(d.z) > 30) ++changed;
    }
  return changed;
}

TEST(Render, BirdsAreWhereTheirStateSays) {
  AEROFLOCK_DEVICE_OR_SKIP(device, true);
  const VkExtent2D size{320, 180};
  Scenario scenario = load_scenario("fig16-circling-eagle");
  gpu::GpuSimulation sim(device, scenario, 1);
  for (int i = 0; i < 20; ++i) sim.step_frame();
  const glm::dvec3 bird = sim.birds()[0].position;
  render::Camera camera;
  camera.target = glm::vec3(bird);
  camera.eye = glm::vec3(bird) + glm::vec3(-800.0f, 300.0f, -600.0f);
  const Image image = render(device, sim, camera, size);
  ASSERT_EQ(image.rgba.size(), size.width * size.height * 4u);

  // The same view with the bird moved far away: what is left is the background.
  Scenario empty = scenario;
  gpu::GpuSimulation away(device, empty, std::vector<BirdState>{[&] {
                            BirdState b = sim.birds()[0];
                            b.position += glm::dvec3(0.0, 1e5, 0.0);
                            return b;
                          }()});
  const Image background = render(device, away, camera, size);
  const glm::vec2 at = project(camera, size, bird);
  EXPECT_GT(changed_near(image, background, at, 6), 10) << "bird pixels at " << at.x << ", " << at.y;
  EXPECT_EQ(changed_near(image, background, {40, 40}, 6), 0) << "nothing drawn far from the bird";
  EXPECT_EQ(device.validation_errors(), 0);
}

TEST(Render, WingsUpAndDownDrawDifferently) {
  AEROFLOCK_DEVICE_OR_SKIP(device, true);
  const VkExtent2D size{320, 180};
  Scenario scenario = load_scenario("fig16-circling-eagle");
  BirdState bird = spawn_birds(scenario)[0];
  bird.amplitude = 1.0;
  auto render_at_phase = [&](double phase) {
    BirdState b = bird;
    b.phase = phase;
    gpu::GpuSimulation sim(device, scenario, std::vector<BirdState>{b});
    render::Camera camera;
    camera.target = glm::vec3(b.position);
    camera.eye = glm::vec3(b.position) + glm::vec3(600.0f, 0.0f, 0.0f);  // head on
    return render(device, sim, camera, size);
  };
  const Image up = render_at_phase(0.0), down = render_at_phase(kPi);
  EXPECT_GT(changed_near(up, down, {160, 90}, 80), 50);
  EXPECT_EQ(device.validation_errors(), 0);
}

// A bird braking to land holds its tail fully open (the model's opening, paper 4.4): seen from
// below, its tail fan is drawn wider than the same bird's in level flight, and nothing else
// differs.
TEST(Render, LandingBirdDrawsItsTailFullyOpen) {
  AEROFLOCK_DEVICE_OR_SKIP(device, true);
  const VkExtent2D size{320, 240};
  Scenario scenario = load_scenario("fig16-circling-eagle");
  const Species& eagle = scenario.species[spawn_birds(scenario)[0].species];
  BirdState bird = spawn_birds(scenario)[0];
  bird.tail_bend = bird.tail_twist = 0.0;
  render::Camera camera;
  camera.target = glm::vec3(bird.position);
  camera.eye = glm::vec3(bird.position) + glm::vec3(-60.0f, -320.0f, 20.0f);  // below, behind
  auto render_in = [&](FlightMode mode) {
    BirdState b = bird;
    b.mode = mode;
    gpu::GpuSimulation sim(device, scenario, std::vector<BirdState>{b});
    return render(device, sim, camera, size);
  };
  const Image flying = render_in(FlightMode::flying), landing = render_in(FlightMode::landing);
  const glm::dvec3 ahead = bird.attitude * glm::dvec3{1.0, 0.0, 0.0};
  const glm::dvec3 tail = bird.position - ahead * (0.5 * eagle.box_a + 0.5 * eagle.tail_length);
  const glm::dvec3 head = bird.position + ahead * (0.5 * eagle.box_a);
  const int tail_pixels = changed_near(landing, flying, project(camera, size, tail), 25);
  RecordProperty("tail_pixels_changed", tail_pixels);
  EXPECT_GT(tail_pixels, 100) << "the open tail fan (about 117 degrees against 10 closed)";
  EXPECT_EQ(changed_near(landing, flying, project(camera, size, head), 8), 0) << "the head";
  EXPECT_EQ(device.validation_errors(), 0);
}

}  // namespace
}  // namespace aeroflock
