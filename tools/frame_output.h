// Images of a run without a window: the last frame as a PNG, every K-th frame into a directory,
// or a video through ffmpeg. Rendered offscreen from the birds' state.
#pragma once

#include <cstdint>
#include <cstdio>
#include <memory>
#include <string>

#include "model/simulation.h"
#include "render/camera.h"

namespace aeroflock {

struct ImageOptions {
  std::string png;         // the last frame
  std::string frames_dir;  // every `every`-th frame as frame_000000.png, ...
  uint32_t every = 1;
  std::string video;  // FILE.mp4, through ffmpeg
  uint32_t width = 1280, height = 720;
  bool any() const { return !png.empty() || !frames_dir.empty() || !video.empty(); }
};

// Looks at the flock from behind and above, far enough to see all of it; eases between updates
// (the first update frames the flock at once).
class AutoCamera {
 public:
  render::Camera update(const std::vector<BirdState>& birds);

 private:
  bool first_ = true;
  glm::dvec3 centre_{0.0};
  float radius_ = 0.0f;
};

class FrameOutput {
 public:
  // Checks that every output can be written (and that ffmpeg exists for a video) before the run.
  FrameOutput(const ImageOptions& options, Simulation& sim);
  ~FrameOutput();
  // After frame `index` (0-based) of the run.
  void frame(Simulation& sim, uint64_t index);
  // After the last frame: writes --png and closes the video.
  void finish(Simulation& sim);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace aeroflock
