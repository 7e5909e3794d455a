// Pictures of a run without a window: the last frame as a PNG, every K-th frame into a directory,
// or a video through ffmpeg. Rendered offscreen from the birds' state on the run's thread;
// encoded and written by an AsyncWriter (output/async_writer.h), so that the next frame is
// stepped while the last is written.
#pragma once

#include <cstdint>
#include <cstdio>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "model/simulation.h"
#include "render/camera_control.h"
#include "run/run_loop.h"

namespace aeroflock {

struct PictureOptions {
  std::string png;         // the last frame
  std::string frames_dir;  // every `every`-th frame as frame_000000.png, ...
  uint32_t every = 1;
  std::string video;          // FILE.mp4, through ffmpeg
  std::optional<double> fps;  // video frames per simulated second (default: one a frame, real time)
  uint32_t width = 1280, height = 720;
  render::CameraOptions camera;
  bool targets = true;  // the target spheres and routes
  uint32_t msaa = 4;    // samples a pixel
  bool any() const { return !png.empty() || !frames_dir.empty() || !video.empty(); }
};

// A run's observer (run/run_loop.h): it looks at every frame.
class Pictures final : public RunObserver {
 public:
  // Checks that every output can be written (and that ffmpeg exists for a video) before the run.
  Pictures(const PictureOptions& options, Simulation& sim);
  ~Pictures() override;
  // After the run's frame number `frames` (from 1): the frames directory's and the video's due.
  void frame(Simulation& sim, uint64_t frames) override;
  // After the last frame: writes --png and closes the video.
  void finish(Simulation& sim) override;
  // What finish() has left on disk, a line each for the run's summary: "png   FILE", ...
  std::vector<std::string> written() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace aeroflock
