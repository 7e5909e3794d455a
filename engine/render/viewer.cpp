#include "render/viewer.h"

#include <GLFW/glfw3.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>

#include "gpu/gpu_simulation.h"
#include "model/flock_geometry.h"
#include "render/camera_control.h"
#include "render/frame_ring.h"
#include "render/renderer.h"
#include "render/swapchain.h"
#include "render/window.h"
#include "run/run_loop.h"

namespace aeroflock::render {
namespace {

using Clock = std::chrono::steady_clock;
// Shadows in a window on the CPU: of at most this many birds, each darkening for the ones after it
// (the fill of 10,000 soft discs costs lavapipe a quarter of its frame rate); GPUs and pictures
// have all.
constexpr uint32_t kWindowShadows = 4096;
// In a window on the CPU birds narrower than this many pixels are drawn with a triangle a wing
// (View::tiny_pixels): drawing a vertex is what costs lavapipe's one vertex thread.
constexpr float kWindowTinyPixels = 6.0f;

double seconds_between(Clock::time_point a, Clock::time_point b) {
  return std::chrono::duration<double>(b - a).count();
}

// This frame's reads of the bird buffer before the next frame's step writes it. Only the
// renderer's pose pass (compute) reads the birds; its draws read the poses, which the renderer
// guards itself (Renderer::record). So the next frame's step may run while this one is drawn.
void barrier_reads_to_next_writes(VkCommandBuffer cmd) {
  vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                       VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT, 0, 0,
                       nullptr, 0, nullptr, 0, nullptr);
}

gpu::DeviceOptions window_device(const Window& window, int index) {
  gpu::DeviceOptions o;
  o.index = index;
  o.graphics = true;
  o.instance_extensions = window.instance_extensions();
  o.surface = [&window](VkInstance instance) { return window.create_surface(instance); };
  return o;
}

// The window as an observer of the run loop: before each turn it reads the input and sets the
// pace (the speed's steps, none while paused); after it, draws the flock.
class Viewer final : public RunObserver {
 public:
  Viewer(Window& window, const gpu::Device& device, Scenario scenario,
         const ViewerOptions& options);
  void run();

  std::optional<uint32_t> pace(Simulation&) override;
  void frame(Simulation&, uint64_t) override;
  std::string stop_reason() const override {
    return window_.should_close() ? "the window was closed" : "";
  }

 private:
  void handle(const Input& input, float seconds);
  void read_flock();
  uint32_t steps_now();
  void draw();
  void recreate_swapchain();
  void update_title(Clock::time_point now);
  uint32_t msaa() const { return options_.msaa > 0 ? options_.msaa : default_msaa(device_, true); }

  Window& window_;
  const gpu::Device& device_;
  ViewerOptions options_;
  gpu::GpuSimulation sim_;
  Swapchain swapchain_;
  std::unique_ptr<Renderer> renderer_;
  FrameRing frames_;  // after the renderer: waits for the device before anything is destroyed
  CameraControl camera_;
  View view_;

  Subject flock_;
  uint32_t followed_ = 0;       // the bird the follow camera follows
  uint64_t last_readback_ = 0;  // frame of the last readback
  bool paused_;
  double speed_ = 1.0;          // scenario frames of steps per drawn frame
  double pending_steps_ = 0.0;  // fractional steps carried to the next frame (slow motion)
  bool swapchain_stale_ = false;

  uint64_t frames_drawn_ = 0;
  Clock::time_point last_;        // the last turn's start
  float seconds_ = 0.0f;          // since the turn before
  Clock::time_point title_time_;  // the title's last update, and what it counted since
  uint64_t title_frames_ = 0;
  double step_ms_sum_ = 0.0;
  int step_ms_count_ = 0;
  double step_ms_ = -1.0;
};

Viewer::Viewer(Window& window, const gpu::Device& device, Scenario scenario,
               const ViewerOptions& options)
    : window_(window),
      device_(device),
      options_(options),
      sim_(device, std::move(scenario), options.birds),
      swapchain_(device, window.framebuffer_size()),
      renderer_(std::make_unique<Renderer>(device, sim_.scenario(), swapchain_.format(),
                                           swapchain_.extent(), msaa())),
      frames_(device),
      followed_(options.camera.bird),
      paused_(options.paused) {
  if (followed_ >= sim_.bird_count())
    throw std::runtime_error("--camera-bird " + std::to_string(followed_) + ": the flock has " +
                             std::to_string(sim_.bird_count()) + " birds");
  read_flock();
  CameraOptions framing = options.camera;
  if (const VkExtent2D e = swapchain_.extent(); e.height > 0)
    framing.aspect = float(e.width) / float(e.height);
  camera_ = CameraControl(framing, flock_);
  view_.show_targets = options.targets;
  view_.shadow_casters = is_cpu_device(device) ? kWindowShadows : 0;
  view_.tiny_pixels = is_cpu_device(device) ? kWindowTinyPixels : 0.0f;
}

void Viewer::run() {
  const Clock::time_point start = Clock::now();
  last_ = title_time_ = start;
  const RunResult r = run_frames(sim_, {this}, {.frames = std::numeric_limits<uint64_t>::max()});
  if (!r.errors.empty()) throw std::runtime_error(r.errors.front());
  const double wall = seconds_between(start, Clock::now());
  std::printf(
      "%llu frames in %.2f s (%.1f frames/s), %.2f s simulated, %ux%u, %u sample%s a pixel\n",
      (unsigned long long)frames_drawn_, wall, wall > 0 ? frames_drawn_ / wall : 0.0, sim_.time(),
      renderer_->extent().width, renderer_->extent().height, renderer_->samples(),
      renderer_->samples() == 1 ? "" : "s");
}

std::optional<uint32_t> Viewer::pace(Simulation&) {
  const Input input = window_.poll();
  const Clock::time_point now = Clock::now();
  seconds_ = float(seconds_between(last_, now));
  last_ = now;
  handle(input, seconds_);
  if (input.resized) swapchain_stale_ = true;
  window_.wait_while_minimised();
  if (window_.should_close()) return 0;
  if (swapchain_stale_) recreate_swapchain();

  frames_.begin();
  if (frames_.step_ms()) step_ms_sum_ += *frames_.step_ms(), ++step_ms_count_;
  // Every few frames (large flocks: fewer), before this frame's step: waits for the last one.
  const uint64_t every = sim_.bird_count() > 100000 ? 32 : 4;
  if (frames_drawn_ - last_readback_ >= every) read_flock();
  return steps_now();
}

void Viewer::frame(Simulation&, uint64_t) {
  if (window_.should_close()) return;
  const VkExtent2D extent = swapchain_.extent();
  if (extent.height > 0) camera_.set_aspect(float(extent.width) / float(extent.height));
  view_.camera = camera_.update(seconds_, flock_, sim_.time());
  view_.scene_distance = camera_.subject_distance();
  view_.time = float(sim_.time());
  draw();
  update_title(Clock::now());
  if (options_.frames > 0 && frames_drawn_ >= options_.frames) window_.close();
}

void Viewer::handle(const Input& input, float seconds) {
  using Mode = CameraControl::Mode;
  for (size_t i = 0; i < input.pressed.size(); ++i) {
    const bool shift = input.mods[i] & GLFW_MOD_SHIFT;
    switch (input.pressed[i]) {
      case GLFW_KEY_ESCAPE:
        window_.close();
        break;
      case GLFW_KEY_SPACE:
        paused_ = !paused_;
        break;
      case GLFW_KEY_EQUAL:
      case GLFW_KEY_KP_ADD:
      case GLFW_KEY_RIGHT_BRACKET:
        speed_ = std::min(speed_ * 2.0, 64.0);
        break;
      case GLFW_KEY_MINUS:
      case GLFW_KEY_KP_SUBTRACT:
      case GLFW_KEY_LEFT_BRACKET:
        speed_ = std::max(speed_ / 2.0, 1.0 / 64.0);
        break;
      case GLFW_KEY_T:
        view_.show_targets = !view_.show_targets;
        break;
      case GLFW_KEY_F: {  // follow bird 0, then the next (Shift: the previous) one
        const uint32_t n = sim_.bird_count();
        if (camera_.mode() == Mode::follow) followed_ = (followed_ + (shift ? n - 1 : 1)) % n;
        camera_.set_mode(Mode::follow);
        read_flock();
        break;
      }
      case GLFW_KEY_C:
        camera_.set_mode(camera_.mode() == Mode::free ? Mode::automatic : Mode::free);
        break;
      case GLFW_KEY_O:
        camera_.set_mode(Mode::orbit);
        break;
      case GLFW_KEY_R:
        read_flock();
        camera_.reset(flock_);
        break;
      default:
        break;
    }
  }
  if (input.drag_x != 0.0 || input.drag_y != 0.0)
    camera_.drag(float(input.drag_x), float(input.drag_y));
  if (input.scroll != 0.0) camera_.zoom(float(input.scroll));
  auto axis = [&](int plus, int minus) {
    return float(window_.key_down(plus)) - float(window_.key_down(minus));
  };
  const glm::vec3 move(axis(GLFW_KEY_D, GLFW_KEY_A), axis(GLFW_KEY_E, GLFW_KEY_Q),
                       axis(GLFW_KEY_W, GLFW_KEY_S));
  if (move != glm::vec3(0.0f))
    camera_.move(move, seconds,
                 window_.key_down(GLFW_KEY_LEFT_SHIFT) || window_.key_down(GLFW_KEY_RIGHT_SHIFT));
}

void Viewer::read_flock() {
  flock_ = subject_of(sim_.birds(), followed_, sim_.time());
  last_readback_ = frames_drawn_;
}

// The steps of this turn: a scenario frame's times the speed, the fraction carried to the next
// (slow motion); none while paused.
uint32_t Viewer::steps_now() {
  if (paused_) return 0;
  pending_steps_ += sim_.scenario().steps_per_frame * speed_;
  const auto steps = static_cast<uint32_t>(pending_steps_);
  if (steps == 0) return 0;
  pending_steps_ -= steps;
  frames_.stamp_step_start();
  return steps;
}

void Viewer::draw() {
  uint32_t image = 0;
  if (!swapchain_.acquire(frames_.acquired(), image)) {
    swapchain_stale_ = true;
    return;
  }
  VkCommandBuffer cmd = frames_.begin_draw();
  renderer_->record(cmd, swapchain_.image(image), swapchain_.view(image), sim_.bird_buffer(),
                    sim_.bird_count(), sim_.world(), view_, VK_IMAGE_LAYOUT_PRESENT_SRC_KHR);
  barrier_reads_to_next_writes(cmd);
  frames_.submit_draw(swapchain_.render_finished(image));
  if (!swapchain_.present(image)) swapchain_stale_ = true;
  ++frames_drawn_;
}

void Viewer::recreate_swapchain() {
  swapchain_.recreate(window_.framebuffer_size());  // waits for the device to be idle
  renderer_.reset();
  renderer_ = std::make_unique<Renderer>(device_, sim_.scenario(), swapchain_.format(),
                                         swapchain_.extent(), msaa());
  swapchain_stale_ = false;
}

void Viewer::update_title(Clock::time_point now) {
  ++title_frames_;
  const double elapsed = seconds_between(title_time_, now);
  if (elapsed < 0.5) return;
  if (step_ms_count_ > 0) step_ms_ = step_ms_sum_ / step_ms_count_;
  char text[256];
  const char* camera = CameraControl::name(camera_.mode());
  const std::string follow =
      camera_.mode() == CameraControl::Mode::follow ? " bird " + std::to_string(followed_) : "";
  char step[32] = "-";
  if (step_ms_ >= 0) std::snprintf(step, sizeof step, "%.2f ms", step_ms_);
  std::snprintf(text, sizeof text,
                "aeroflock  %s  |  %u bird%s  |  t = %.1f s  |  %.1f fps  |  step %s  |  x%g%s  |  "
                "%s camera%s",
                sim_.scenario().name.c_str(), uint32_t(sim_.bird_count()),
                sim_.bird_count() == 1 ? "" : "s", sim_.time(), title_frames_ / elapsed, step,
                speed_, paused_ ? " paused" : "", camera, follow.c_str());
  window_.set_title(text);
  title_time_ = now;
  title_frames_ = 0;
  step_ms_sum_ = 0.0;
  step_ms_count_ = 0;
}

}  // namespace

const char* viewer_keys() {
  return "left drag: turn the camera, wheel: zoom, F: follow a bird (again: the next one), "
         "C: free camera (WASD, Q/E down/up, Shift faster), O: orbit, R: the automatic camera,\n"
         "Space: pause, + / -: faster / slower, T: targets on/off, Esc: quit";
}

int run_viewer(Scenario scenario, const ViewerOptions& options) {
  Window window("aeroflock  " + scenario.name, int(options.width), int(options.height));
  gpu::Device device(window_device(window, options.device));
  {
    Viewer viewer(window, device, std::move(scenario), options);
    viewer.run();
  }  // everything on the device is destroyed here, after the device has gone idle
  if (device.validation() && device.validation_errors() > 0) {
    std::fprintf(stderr, "aeroflock view: %d Vulkan validation errors\n",
                 device.validation_errors());
    return 1;
  }
  return 0;
}

}  // namespace aeroflock::render
