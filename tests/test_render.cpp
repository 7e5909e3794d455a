// Headless rendering: the image has the asked size, the birds are drawn where their state says
// (projected with the same camera), a known pose draws as its reference image and differently
// where the wings, the tail or the bank change, shadows lie on the ground under the birds, and
// the automatic camera frames the flock. Validation on.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <tuple>

#include <glm/vec4.hpp>

#include <algorithm>
#include <cstdlib>
#include <filesystem>

#include <glm/gtc/quaternion.hpp>

#include "gpu/compute.h"
#include "gpu/gpu_simulation.h"
#include "gpu_test_device.h"
#include "io/scenario_file.h"
#include "model/constants.h"
#include "model/flock_geometry.h"
#include "model/simulation.h"
#include "output/image.h"
#include "render/camera_control.h"
#include "render/offscreen.h"
#include "render/renderer.h"
#include "render_image.h"

namespace aeroflock {
namespace {

using testing::Image;
using testing::render;

// Pixel coordinates of a world point.
glm::vec2 project(const render::Camera& camera, VkExtent2D size, const glm::dvec3& p) {
  const glm::vec4 clip =
      camera.view_projection(float(size.width) / size.height) * glm::vec4(glm::vec3(p), 1.0f);
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
  EXPECT_GT(changed_near(image, background, at, 6), 10)
      << "bird pixels at " << at.x << ", " << at.y;
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

// A site on the ground (where a species that does not perch lands: a goose on a field) is drawn
// as a patch flat on the ground, 4 m square round its point; a branch above the ground as a stick
// 4 cm thick. Seen from 8 m above, with the bird out of the picture.
TEST(Render, ASiteOnTheGroundIsDrawnAsAPatchOnIt) {
  AEROFLOCK_DEVICE_OR_SKIP(device, true);
  const VkExtent2D size{320, 240};
  const Scenario scenario = load_scenario("fig16-circling-eagle");
  BirdState bird = spawn_birds(scenario)[0];
  bird.position.y = 1e5;
  render::Camera camera;
  camera.target = glm::vec3(0.0f);
  camera.eye = glm::vec3(-300.0f, 800.0f, 0.0f);
  auto draw = [&](std::vector<Branch> branches) {
    Scenario s = scenario;
    s.world.branches = std::move(branches);
    gpu::GpuSimulation sim(device, s, std::vector<BirdState>{bird});
    return render(device, sim, camera, size);
  };
  const Image bare = draw({});
  const Image site = draw({{"field", {0.0, scenario.world.ground_height, 0.0}, {1.0, 0.0, 0.0}}});
  const Image stick = draw({{"oak", {0.0, 300.0, 0.0}, {1.0, 0.0, 0.0}}});
  auto changed_at = [&](const Image& image, glm::dvec3 p) {
    return changed_near(image, bare, project(camera, size, p), 2);
  };
  const double g = scenario.world.ground_height;
  EXPECT_EQ(changed_at(site, {0.0, g, 0.0}), 25) << "the site's point";
  EXPECT_EQ(changed_at(site, {0.0, g, 150.0}), 25) << "1.5 m across";
  EXPECT_EQ(changed_at(site, {150.0, g, -150.0}), 25) << "a corner's way";
  EXPECT_EQ(changed_at(site, {0.0, g, 300.0}), 0) << "3 m across: past the patch";
  EXPECT_GT(changed_at(stick, {0.0, 300.0, 0.0}), 0) << "the stick's point";
  EXPECT_EQ(changed_at(stick, {0.0, 300.0, 150.0}), 0) << "a stick, not a patch";
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

// The automatic camera of `aeroflock run --png` frames the flock, not the route: at the end of the
// default run (1,000 birds, 20 s) and with 100,000 birds (packed into the spawn box, 0.3 s), the
// birds' projected bounding box spans at least a quarter of the image's width, and nine in ten
// birds are in the picture.
TEST(Render, AutoCameraFramesTheDefaultFlock) {
  AEROFLOCK_DEVICE_OR_SKIP(device, true);
  const VkExtent2D size{1280, 720};
  for (const auto& [birds, frames] : {std::pair<uint32_t, int>{1000, 667}, {100000, 10}}) {
    gpu::GpuSimulation sim(device, load_scenario("default"), birds);
    sim.step(uint32_t(frames) * sim.scenario().steps_per_frame);
    const std::vector<BirdState>& state = sim.birds();
    const render::CameraControl control({}, render::subject_of(state, 0, sim.time()));
    const render::Camera camera = control.camera().from(control.camera().eye_world());
    const glm::mat4 vp = camera.view_projection(float(size.width) / size.height);
    size_t inside = 0, finite = 0;
    float left = float(size.width), right = 0.0f;
    for (const BirdState& b : state) {
      if (!is_finite(b)) continue;
      ++finite;
      const glm::vec4 clip = vp * glm::vec4(glm::vec3(b.position - camera.origin), 1.0f);
      if (clip.w <= 0.0f) continue;
      const glm::vec2 ndc = glm::vec2(clip) / clip.w;
      if (std::abs(ndc.x) > 1.0f || std::abs(ndc.y) > 1.0f) continue;
      ++inside;
      const float x = (ndc.x * 0.5f + 0.5f) * float(size.width);
      left = std::min(left, x);
      right = std::max(right, x);
    }
    const double width = (right - left) / size.width, seen = double(inside) / double(finite);
    RecordProperty("flock_width_" + std::to_string(birds), std::to_string(width));
    EXPECT_GE(width, 0.25) << birds << " birds: the flock spans " << width << " of the width";
    EXPECT_GE(seen, 0.9) << birds << " birds: " << seen << " of them in the picture";
  }
  EXPECT_EQ(device.validation_errors(), 0);
}

// An eagle in a known pose, seen from behind, above and to its left.
struct PoseScene {
  Scenario scenario = load_scenario("fig16-circling-eagle");
  BirdState bird = [this] {
    BirdState b = spawn_birds(scenario)[0];
    b.position = {0.0, 400.0, 0.0};
    b.velocity = {1000.0, 0.0, 0.0};
    b.attitude = glm::dquat(1.0, 0.0, 0.0, 0.0);
    b.phase = 1.0;
    b.amplitude = 1.0;
    b.tail_bend = 0.1;
    b.tail_twist = 0.0;
    return b;
  }();
  render::Camera camera = [this] {
    render::Camera c;
    c.target = glm::vec3(bird.position) + glm::vec3(-20.0f, -20.0f, 0.0f);
    c.eye = glm::vec3(bird.position) + glm::vec3(-250.0f, 210.0f, -170.0f);
    return c;
  }();
  Image draw(const gpu::Device& device, const BirdState& b, VkExtent2D size) {
    gpu::GpuSimulation sim(device, scenario, std::vector<BirdState>{b});
    return render(device, sim, camera, size);
  }
};

// Pixels whose colour differs by more than `threshold` (sum over r, g, b).
int differing(const Image& a, const Image& b, int threshold) {
  int n = 0;
  for (uint32_t y = 0; y < a.height; ++y)
    for (uint32_t x = 0; x < a.width; ++x) {
      const glm::ivec3 d = a.at(int(x), int(y)) - b.at(int(x), int(y));
      if (std::abs(d.x) + std::abs(d.y) + std::abs(d.z) > threshold) ++n;
    }
  return n;
}

// Issue 44: the window's level of detail on a CPU device (birds narrower than 6 pixels drawn with
// a triangle a wing, viewer.cpp) differs from the full drawing of the same state, as the window
// draws it (one sample a pixel, the automatic camera), in at most 1 % of the pixels: the
// murmuration's 10,000 starlings after 2 s, and the default flock's 1,000 after 20 s.
TEST(Render, TheWindowsLevelOfDetailDiffersInAtMostOnePercentOfThePixels) {
  AEROFLOCK_DEVICE_OR_SKIP(device, true);
  const VkExtent2D size{1280, 720};
  // The default as the window frames it leaves no bird that narrow: seen zoomed out, as a user may.
  for (const auto& [name, frames, zoom_out] :
       {std::tuple<const char*, int, float>{"murmuration", 67, 0.0f}, {"default", 667, 6.0f}}) {
    gpu::GpuSimulation sim(device, load_scenario(name));
    sim.step_frames(uint32_t(frames));
    const render::Subject subject = render::subject_of(sim.birds(), 0, sim.time());
    render::CameraControl control({}, subject);
    control.zoom(-zoom_out);
    const render::Camera camera = control.update(0.0f, subject, sim.time());
    const Image full = render(device, sim, camera, size, false, 1, 0.0f);
    const Image lod = render(device, sim, camera, size, false, 1, 6.0f);
    const int changed = differing(full, lod, 0);
    const double share = double(changed) / (size.width * size.height);
    RecordProperty(std::string(name) + "_pixels_differing", std::to_string(share));
    EXPECT_LE(share, 0.01) << name;
    EXPECT_GT(changed, 0) << name << ": no bird was drawn tiny";
  }
  EXPECT_EQ(device.validation_errors(), 0);
}

// The rendered image of a known pose matches tests/data/render/eagle_pose.png (written by running
// this test with AEROFLOCK_UPDATE_REFERENCE=1, and looked at): at most 0.5 % of the pixels differ
// by more than 24 (of 765), which allows another driver's rasterisation of the edges. The same bird
// with its wings later in the beat, its tail fully open (landing) or banked 30 degrees differs
// from it where those parts are.
TEST(Render, AKnownPoseMatchesItsReference) {
  AEROFLOCK_DEVICE_OR_SKIP(device, true);
  const VkExtent2D size{320, 200};
  PoseScene scene;
  const Image image = scene.draw(device, scene.bird, size);
  const std::filesystem::path reference =
      std::filesystem::path(AEROFLOCK_TEST_DATA) / "render" / "eagle_pose.png";
  if (std::getenv("AEROFLOCK_UPDATE_REFERENCE"))
    write_png(reference, size.width, size.height, image.rgba);
  const Rgba expected = read_png(reference);
  ASSERT_EQ(expected.width, size.width);
  ASSERT_EQ(expected.height, size.height);
  const Image want{expected.width, expected.height, expected.pixels};
  const int off = differing(image, want, 24);
  RecordProperty("pixels_off_reference", off);
  EXPECT_LE(off, int(0.005 * size.width * size.height))
      << off << " pixels differ from " << reference;

  BirdState wings = scene.bird, tail = scene.bird, banked = scene.bird;
  wings.phase += 2.0;
  tail.mode = FlightMode::landing;
  banked.attitude = glm::angleAxis(glm::radians(30.0), glm::dvec3(1.0, 0.0, 0.0));
  const int by_wings = differing(scene.draw(device, wings, size), image, 24);
  const int by_tail = differing(scene.draw(device, tail, size), image, 24);
  const int by_bank = differing(scene.draw(device, banked, size), image, 24);
  RecordProperty(
      "pixels_changed_wings_tail_bank",
      std::to_string(by_wings) + " " + std::to_string(by_tail) + " " + std::to_string(by_bank));
  EXPECT_GT(by_wings, 300);
  EXPECT_GT(by_tail, 100);
  EXPECT_GT(by_bank, 300);
  EXPECT_EQ(device.validation_errors(), 0);
}

// A bird 3 m over the ground casts its shadow where the sun's ray through it meets the ground: the
// ground is darker there than with the bird gone, and not on the side away from the sun.
TEST(Render, AShadowLiesUnderTheBirdOnTheGround) {
  AEROFLOCK_DEVICE_OR_SKIP(device, true);
  const VkExtent2D size{320, 200};
  PoseScene scene;
  scene.bird.position = {0.0, 300.0, 0.0};
  const glm::dvec3 sun(render::sun_direction());
  const glm::dvec3 shadow = scene.bird.position - sun * (scene.bird.position.y / sun.y);
  const glm::dvec3 away_from_sun = scene.bird.position +
                                   sun * (scene.bird.position.y / sun.y) * glm::dvec3(1, 0, 1) -
                                   glm::dvec3(0.0, scene.bird.position.y, 0.0);
  scene.camera.target = glm::vec3(0.5 * (shadow + scene.bird.position));
  scene.camera.eye = scene.camera.target + glm::vec3(-150.0f, 900.0f, -500.0f);
  BirdState gone = scene.bird;
  gone.position.y = 1e6;
  const Image with = scene.draw(device, scene.bird, size), without = scene.draw(device, gone, size);
  auto darker_near = [&](const glm::dvec3& p) {
    const glm::vec2 at = project(scene.camera, size, p);
    int n = 0;
    for (int y = int(at.y) - 6; y <= int(at.y) + 6; ++y)
      for (int x = int(at.x) - 6; x <= int(at.x) + 6; ++x) {
        if (x < 0 || y < 0 || x >= int(size.width) || y >= int(size.height)) continue;
        const glm::ivec3 a = with.at(x, y), b = without.at(x, y);
        if (a.x + a.y + a.z + 15 < b.x + b.y + b.z) ++n;
      }
    return n;
  };
  const int under = darker_near(shadow), other_side = darker_near(away_from_sun);
  RecordProperty("shadow_pixels", under);
  EXPECT_GT(under, 60) << "pixels darkened round the shadow's centre";
  EXPECT_EQ(other_side, 0) << "pixels darkened on the side away from the sun";
  EXPECT_EQ(device.validation_errors(), 0);
}

// A bird on its legs is drawn standing on them: seen from its side at their height, its legs
// fill the pixels half way from its body down to the ground under its centre, standing or crouched
// to take off, where the same bird in flight at the same place shows the background (its legs
// folded into its body).
TEST(Render, ABirdOnTheGroundStandsOnItsLegs) {
  AEROFLOCK_DEVICE_OR_SKIP(device, true);
  const VkExtent2D size{320, 240};
  PoseScene scene;
  const Species& s = scene.scenario.species[scene.bird.species];
  BirdState standing = scene.bird;
  standing.mode = FlightMode::standing;
  standing.position = {0.0, scene.scenario.world.ground_height + s.stand_height, 0.0};
  standing.velocity = glm::dvec3(0.0);
  standing.amplitude = 0.0;
  BirdState flying = standing;
  flying.mode = FlightMode::flying;
  // Crouched to leap (taking off), still on its legs: they reach the ground from its lower body.
  BirdState crouching = standing;
  crouching.mode = FlightMode::taking_off;
  crouching.position.y -= s.crouch_depth;
  BirdState gone = standing;
  gone.position.y = 1e6;
  const glm::dvec3 legs =
      standing.position - glm::dvec3(0.0, 0.5 * (0.3 * s.box_b + s.stand_height), 0.0);
  scene.camera.target = glm::vec3(legs);
  scene.camera.eye = glm::vec3(legs) + glm::vec3(0.0f, 0.0f, -150.0f);
  const Image background = scene.draw(device, gone, size);
  const glm::vec2 at = project(scene.camera, size, legs);
  const int on_legs = changed_near(scene.draw(device, standing, size), background, at, 3);
  const int in_flight = changed_near(scene.draw(device, flying, size), background, at, 3);
  // Between its crouched body and the ground.
  const glm::dvec3 shins{
      0.0, 0.5 * (crouching.position.y - 0.5 * s.box_b + scene.scenario.world.ground_height), 0.0};
  scene.camera.target = glm::vec3(shins);
  scene.camera.eye = glm::vec3(shins) + glm::vec3(0.0f, 0.0f, -150.0f);
  const Image low_background = scene.draw(device, gone, size);
  const int crouched = changed_near(scene.draw(device, crouching, size), low_background,
                                    project(scene.camera, size, shins), 2);
  RecordProperty("leg_pixels", on_legs);
  EXPECT_GE(on_legs, 7) << "a leg's column through the 7 x 7 pixels";
  EXPECT_GE(crouched, 5) << "on its legs while it crouches to take off";
  EXPECT_EQ(in_flight, 0) << "legs folded in flight";
  EXPECT_EQ(device.validation_errors(), 0);
}

}  // namespace
}  // namespace aeroflock
