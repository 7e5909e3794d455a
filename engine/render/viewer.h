// `aeroflock view`: the flock stepped by the compute shaders and drawn in a window as it flies.
#pragma once

#include <cstdint>

#include "model/scenario.h"
#include "render/camera_control.h"

namespace aeroflock::render {

struct ViewerOptions {
  int device = -1;      // Vulkan device index (< 0: the preferred one)
  uint32_t birds = 0;   // > 0: override the scenario's flock sizes
  uint64_t frames = 0;  // > 0: close the window after that many frames
  bool paused = false;  // start with the simulation paused (Space resumes)
  uint32_t width = 1280;
  uint32_t height = 720;
  CameraOptions camera;
  bool targets = true;  // the target rings and routes (T toggles)
  uint32_t msaa = 0;    // samples a pixel (0: default_msaa)
};

// The keys, one line each, for the terminal.
const char* viewer_keys();

// Opens the window and runs until it is closed (Esc, the window's close button, or `frames`).
// Returns the exit status: 0, or 1 when the validation layer (AEROFLOCK_VALIDATION=1) reported
// errors. Throws NoDisplay (render/window.h) without a display, gpu::Error for Vulkan failures.
int run_viewer(Scenario scenario, const ViewerOptions& options);

}  // namespace aeroflock::render
