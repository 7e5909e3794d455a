#include "output/pictures.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <stdexcept>

#include "gpu/compute.h"
#include "gpu/gpu_simulation.h"
#include "gpu/layout.h"
#include "io/host.h"
#include "io/paths.h"
#include "output/async_writer.h"
#include "output/image.h"
#include "output/video.h"
#include "render/offscreen.h"
#include "render/renderer.h"

namespace aeroflock {

namespace fs = std::filesystem;

struct Pictures::Impl {
  PictureOptions options;
  // A device of our own where the sim has none (the CPU reference), with a bird buffer.
  std::unique_ptr<gpu::Device> own_device;
  std::unique_ptr<gpu::Buffer> own_birds;
  const gpu::Device* device = nullptr;
  std::unique_ptr<render::Renderer> renderer;
  std::unique_ptr<render::Offscreen> target;
  std::unique_ptr<gpu::Submitter> submitter;
  std::optional<render::CameraControl> camera;  // from the first picture
  double camera_time = 0.0;                     // simulated time of its last update
  std::unique_ptr<VideoWriter> video;
  double video_fps = 0.0;
  uint64_t dir_frames = 0;  // PNGs written to frames_dir
  bool png_written = false, video_written = false;
  uint64_t video_frames =
      0;  // written so far: frame k (from 0) shows simulated time (k + 1) / video_fps
  // The PNGs' encoding and the video's frames, off the run's thread; last: it stops first.
  std::unique_ptr<AsyncWriter> writer = std::make_unique<AsyncWriter>(AsyncWriter::Limits{});

  Impl(const PictureOptions& o, Simulation& sim) : options(o) {
    if (!options.png.empty()) check_output_path(options.png, "--png", {".png"});
    if (!options.video.empty()) {
      if (!has_program("ffmpeg"))
        throw std::runtime_error(
            "--video needs ffmpeg, which is not installed (Debian: apt-get install ffmpeg)");
      if (options.width % 2 != 0 || options.height % 2 != 0)
        throw std::runtime_error("--video needs an even width and height (H.264), got --size " +
                                 std::to_string(options.width) + "x" +
                                 std::to_string(options.height));
      check_output_path(options.video, "--video", {".mp4", ".mkv", ".mov", ".webm"});
    }
    if (options.camera.bird >= sim.bird_count())
      throw std::runtime_error("--camera-bird " + std::to_string(options.camera.bird) +
                               ": the run has " + std::to_string(sim.bird_count()) +
                               " birds (0 to " + std::to_string(sim.bird_count() - 1) + ")");
    if (const auto* gpu_sim = dynamic_cast<const gpu::GpuSimulation*>(&sim))
      device = &gpu_sim->gpu_device();
    if (!device) {
      gpu::DeviceOptions d = gpu::headless(-1, false);
      d.graphics = true;
      own_device = std::make_unique<gpu::Device>(d);
      device = own_device.get();
      own_birds = std::make_unique<gpu::Buffer>(
          *device, std::max<size_t>(sim.bird_count(), 1) * sizeof(gpu::GpuBird), gpu::Memory::host);
    }
    const VkExtent2D size{options.width, options.height};
    renderer = std::make_unique<render::Renderer>(*device, sim.scenario(),
                                                  render::Offscreen::kFormat, size, options.msaa);
    target = std::make_unique<render::Offscreen>(*device, size);
    submitter = std::make_unique<gpu::Submitter>(*device, 1);
    // Created once every other check has passed: an error leaves no empty directory behind.
    if (!options.frames_dir.empty()) check_writable_dir(options.frames_dir, "--frames-dir");
    if (!options.video.empty()) {
      // Real time unless asked otherwise: one video frame per simulated frame.
      const double frame_seconds = sim.scenario().dt * sim.scenario().steps_per_frame;
      video_fps = options.fps.value_or(1.0 / frame_seconds);
      char rate[64];
      if (options.fps)
        std::snprintf(rate, sizeof rate, "%.9g", *options.fps);
      else
        std::snprintf(rate, sizeof rate, "1000000/%.0f", frame_seconds * 1e6);
      video = std::make_unique<VideoWriter>(options.video, options.width, options.height, rate);
    }
  }

  std::vector<uint8_t> render(Simulation& sim) {
    const std::vector<BirdState>& birds = sim.birds();  // waits for the frame
    const gpu::Buffer* bird_buffer = nullptr;
    uint32_t count = 0;
    if (const auto* gpu_sim = dynamic_cast<const gpu::GpuSimulation*>(&sim)) {
      bird_buffer = &gpu_sim->bird_buffer();
      count = uint32_t(gpu_sim->bird_count());
    } else {
      std::vector<gpu::GpuBird> packed;
      for (const BirdState& b : birds) packed.push_back(gpu::pack(b));
      own_birds->upload(std::as_bytes(std::span<const gpu::GpuBird>(packed)));
      bird_buffer = own_birds.get();
      count = uint32_t(packed.size());
    }
    const render::Subject subject = render::subject_of(birds, options.camera.bird, sim.time());
    if (!camera) {
      render::CameraOptions framing = options.camera;
      framing.aspect = float(options.width) / float(options.height);
      camera.emplace(framing, subject), camera_time = sim.time();
    }
    render::View view;
    view.camera = camera->update(float(sim.time() - camera_time), subject, sim.time());
    view.scene_distance = camera->subject_distance();
    view.show_targets = options.targets;
    view.time = float(sim.time());
    camera_time = sim.time();
    World world = sim.scenario().world;
    world.move_targets(sim.time());
    submitter->run([&](VkCommandBuffer cmd) {
      renderer->record(cmd, target->image(), target->view(), *bird_buffer, count, world, view,
                       VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL);
      target->record_copy(cmd);
    });
    return target->pixels();
  }
};

Pictures::Pictures(const PictureOptions& options, Simulation& sim)
    : impl_(std::make_unique<Impl>(options, sim)) {}

Pictures::~Pictures() = default;

void Pictures::frame(Simulation& sim, uint64_t frames) {
  Impl& o = *impl_;
  if (o.writer->failed()) o.writer->finish();  // throws the writer's error: the run stops
  const uint64_t index = frames - 1;           // the frame's, from 0
  const bool to_dir = !o.options.frames_dir.empty() && index % o.options.every == 0;
  // The video frames whose time has come (none, or several when --fps is above the frame rate).
  uint64_t due = 0;
  if (o.video)
    while (double(o.video_frames + due + 1) / o.video_fps <= sim.time() + 1e-9) ++due;
  if (!to_dir && due == 0) return;
  auto pixels = std::make_shared<const std::vector<uint8_t>>(o.render(sim));
  const uint32_t width = o.options.width, height = o.options.height;
  if (to_dir) {
    char name[32];
    std::snprintf(name, sizeof name, "frame_%06llu.png",
                  (unsigned long long)(index / o.options.every));
    const fs::path path = fs::path(o.options.frames_dir) / name;
    o.writer->push(pixels->size(),
                   [path, width, height, pixels] { write_png(path, width, height, *pixels); });
    ++o.dir_frames;
  }
  if (due > 0) {
    o.writer->push(pixels->size(), [video = o.video.get(), due, pixels] {
      for (uint64_t k = 0; k < due; ++k) video->frame(*pixels);
    });
    o.video_frames += due;
  }
}

void Pictures::finish(Simulation& sim) {
  Impl& o = *impl_;
  bool png = false;
  if (!o.options.png.empty() && !o.writer->failed()) {
    auto pixels = std::make_shared<const std::vector<uint8_t>>(o.render(sim));
    o.writer->push(pixels->size(), [&o, pixels] {
      write_png(o.options.png, o.options.width, o.options.height, *pixels);
    });
    png = true;
  }
  // Every picture written, then the video closed (a run stopped before its first frame: none).
  o.writer->finish([&o] {
    if (o.video && o.video_frames > 0) o.video->finish(), o.video_written = true;
    o.video.reset();
  });
  o.png_written = png;
}

std::vector<std::string> Pictures::written() const {
  const Impl& o = *impl_;
  std::vector<std::string> lines;
  char line[512];
  if (o.png_written) lines.push_back("png              " + o.options.png);
  if (!o.options.frames_dir.empty()) {
    std::snprintf(line, sizeof line, "frames           %s (%llu PNG%s)",
                  o.options.frames_dir.c_str(), (unsigned long long)o.dir_frames,
                  o.dir_frames == 1 ? "" : "s");
    lines.push_back(line);
  }
  if (o.video_written) {
    std::snprintf(line, sizeof line, "video            %s (%llu frames at %.4g fps, %.2f s)",
                  o.options.video.c_str(), (unsigned long long)o.video_frames, o.video_fps,
                  double(o.video_frames) / o.video_fps);
    lines.push_back(line);
  }
  return lines;
}

}  // namespace aeroflock
