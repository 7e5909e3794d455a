// aeroflock: list the built-in scenarios, run one and summarise it, or watch it in a window.
#include <omp.h>

#include <CLI/CLI.hpp>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <optional>
#include <sstream>
#include <string>

#include <glm/geometric.hpp>

#include "backend.h"
#include "bench.h"
#include "envelope.h"
#include "frame_output.h"
#include "io/paths.h"
#include "io/scenario_file.h"
#include "io/summary.h"
#include "io/vtk_export.h"
#include "progress.h"
#include "render/viewer.h"

namespace aeroflock {
namespace {

namespace fs = std::filesystem;

struct RunOptions {
  std::string scenario = "default";
  std::string backend = "vulkan";
  int device = -1;
  uint32_t birds = 0;
  std::optional<double> seconds;
  std::string summary;
  int threads = 0;
  ImageOptions images;
  std::string vtk_dir;
  uint32_t vtk_every = 1;
  std::string vtk_birds = "all";
  std::string vtk_compression = "lz4";
};

// Ctrl-C: the run stops after the frame in progress, finishes its outputs and exits 130. A second
// Ctrl-C (SA_RESETHAND) ends the program at once.
volatile std::sig_atomic_t g_interrupted = 0;
extern "C" void on_sigint(int) { g_interrupted = 1; }
constexpr int kInterruptedStatus = 130;  // 128 + SIGINT, as a shell reports it

struct ViewOptions {
  std::string scenario = "default";
  render::ViewerOptions viewer;
};

int list_scenarios() {
  for (const BuiltinScenario& s : builtin_scenarios())
    std::cout << s.name << "\n    " << s.description << "\n";
  return 0;
}

// CLI11's own PositiveNumber names the whole double range in its message.
const CLI::Validator kPositive(
    [](std::string& text) -> std::string {
      char* end = nullptr;
      const double v = std::strtod(text.c_str(), &end);
      if (end == text.c_str() || *end != '\0' || !(v > 0) || !std::isfinite(v))
        return "expected a positive number, got " + text;
      return "";
    },
    "> 0");

void print_summary(const RunSummary& r, const std::string& summary_path, const VtkExporter* vtk,
                   bool interrupted) {
  const FlockStatistics& s = r.stats;
  const double rate = r.wall_seconds > 0 ? s.birds * double(r.steps) / r.wall_seconds : 0.0;
  std::printf("scenario         %s\n", r.scenario.c_str());
  std::printf("backend          %s\n", r.device.c_str());
  std::printf("birds            %llu (%llu flying, %llu perched, %llu with NaN)\n",
              (unsigned long long)s.birds, (unsigned long long)s.flying,
              (unsigned long long)s.perched, (unsigned long long)s.nan_birds);
  std::printf("simulated        %.3f s (%llu steps of %g s)\n", r.sim_seconds,
              (unsigned long long)r.steps, r.dt);
  std::printf("wall time        %.3f s (%.3g bird-steps/s)\n", r.wall_seconds, rate);
  std::printf("centroid         (%.2f, %.2f, %.2f) m\n", s.centroid.x / 100, s.centroid.y / 100,
              s.centroid.z / 100);
  std::printf("mean speed       %.2f m/s\n", s.mean_speed / 100);
  std::printf("targets reached  %llu\n", (unsigned long long)s.targets_reached);
  for (const FlockingSummary& f : r.flocking)
    std::printf("flock %-10s median nearest neighbour %.2f m, %.2f %% nearer than half a wingspan, "
                "polarisation %.3f, largest cluster %.1f %%\n",
                f.name.c_str(), f.metrics.median_nearest / 100, 100 * f.metrics.too_close, f.metrics.polarisation,
                100 * f.metrics.largest_cluster);
  if (!summary_path.empty()) std::printf("summary          %s\n", summary_path.c_str());
  if (vtk)
    std::printf("vtk              %s (%zu frame%s of %zu bird%s: flock.pvd, trajectories.vtp)\n",
                vtk->dir().c_str(), vtk->frames_added(), vtk->frames_added() == 1 ? "" : "s",
                vtk->selected().size(), vtk->selected().size() == 1 ? "" : "s");
  if (interrupted) std::printf("interrupted      at t = %.3f s (Ctrl-C)\n", r.sim_seconds);
}

int run(const RunOptions& opt) {
  g_interrupted = 0;
  struct sigaction action {};
  action.sa_handler = on_sigint;
  action.sa_flags = SA_RESETHAND;
  sigemptyset(&action.sa_mask);
  sigaction(SIGINT, &action, nullptr);
  if (!opt.summary.empty()) check_output_path(opt.summary, "--summary");
  if (opt.threads > 0) omp_set_num_threads(opt.threads);

  Scenario scenario = load_scenario(opt.scenario);
  const double seconds = opt.seconds.value_or(scenario.duration);
  const double frame_seconds = scenario.dt * scenario.steps_per_frame;
  // The small allowance keeps an exact multiple from gaining a frame to rounding.
  const auto frames = static_cast<uint64_t>(std::ceil(seconds / frame_seconds - 1e-9));

  RunSummary summary;
  summary.scenario = scenario.name;
  summary.dt = scenario.dt;
  summary.steps_per_frame = scenario.steps_per_frame;
  std::unique_ptr<Simulation> sim =
      make_simulation({opt.backend, opt.birds, opt.device, opt.images.any()}, std::move(scenario));
  std::unique_ptr<FrameOutput> images;
  if (opt.images.any()) images = std::make_unique<FrameOutput>(opt.images, *sim);
  summary.backend = sim->backend();
  summary.device = describe_device(*sim);

  Progress progress;
  const size_t birds = sim->bird_count();
  // Before the run: a directory that cannot be written fails now.
  std::unique_ptr<VtkExporter> vtk;
  if (!opt.vtk_dir.empty()) {
    sim->prepare_forces();  // the exported forces: a flock whose forces do not fit fails now
    VtkOptions vo;
    vo.dir = opt.vtk_dir;
    vo.every = opt.vtk_every;
    vo.birds = opt.vtk_birds;
    vo.compression = parse_vtk_compression(opt.vtk_compression);
    try {
      vtk = std::make_unique<VtkExporter>(vo, sim->scenario(), birds);
    } catch (const std::invalid_argument& e) {
      throw std::runtime_error(std::string("--vtk-birds: ") + e.what());
    }
  }
  const auto start = std::chrono::steady_clock::now();
  auto wall = [&] {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  };
  bool interrupted = false;
  for (uint64_t frame = 0; frame < frames; ++frame) {
    if (g_interrupted || (vtk && vtk->failed())) {
      interrupted = g_interrupted;
      break;
    }
    // Frames due for export record their forces; the exporter takes the newest state that is
    // ready without waiting (on Vulkan the frame before the last) and writes on its own thread.
    sim->step_frame(vtk && vtk->due(sim->frames() + 1));
    if (images) images->frame(*sim, frame);
    if (vtk) vtk->offer_ready(*sim);
    if (progress.due() || frame + 1 == frames)
      progress.show(run_progress(sim->time(), seconds, birds, double(sim->steps()), wall()));
  }
  progress.finish();
  interrupted = interrupted || g_interrupted;
  if (vtk) vtk->offer_last(*sim);  // the last frame, if due and still owed

  summary.wall_seconds = wall();
  summary.steps = sim->steps();
  summary.sim_seconds = sim->time();
  summary.stats = flock_statistics(sim->birds());
  summary.flocking = flocking_summary(sim->scenario(), sim->birds());
  if (images) images->finish(*sim);
  if (vtk) vtk->finish();  // the writer's error, if any, is thrown here
  if (!opt.summary.empty()) write_summary(opt.summary, summary);
  print_summary(summary, opt.summary, vtk.get(), interrupted);
  return interrupted ? kInterruptedStatus : 0;
}

int view(const ViewOptions& opt) {
  Scenario scenario = load_scenario(opt.scenario);
  std::cout << render::viewer_keys() << std::endl;
  return render::run_viewer(std::move(scenario), opt.viewer);
}

// --size WxH into `width` and `height`.
void add_size_option(CLI::App* app, uint32_t& width, uint32_t& height, const char* what) {
  app->add_option_function<std::string>(
      "--size",
      [&width, &height](const std::string& text) {
        unsigned w = 0, h = 0;
        char x = 0;
        if (std::sscanf(text.c_str(), "%u%c%u", &w, &x, &h) != 3 || x != 'x' || w < 16 || h < 16 ||
            w > 8192 || h > 8192)
          throw CLI::ValidationError("--size",
                                     "expected WxH between 16x16 and 8192x8192, got " + text);
        width = w;
        height = h;
      },
      what);
}

// X,Y,Z in metres into `point` (cm).
void add_point_option(CLI::App* app, const char* name, std::optional<glm::dvec3>& point, const char* what) {
  app->add_option_function<std::string>(
      name,
      [&point, name](const std::string& text) {
        double x = 0, y = 0, z = 0;
        char extra = 0;
        if (std::sscanf(text.c_str(), "%lf,%lf,%lf%c", &x, &y, &z, &extra) != 3 || !std::isfinite(x) ||
            !std::isfinite(y) || !std::isfinite(z))
          throw CLI::ValidationError(name, "expected X,Y,Z in metres, got " + text);
        point = glm::dvec3(x, y, z) * 100.0;
      },
      what);
}

// The cameras of `run` (pictures) and `view` (the window).
void add_camera_options(CLI::App* app, render::CameraOptions& camera, bool& targets) {
  app->add_option("--camera", camera.mode,
                  "auto (frames the flock, following it), orbit (circles the flock), follow (behind "
                  "one bird, --camera-bird) or fixed (--camera-eye, --camera-target)")
      ->check(CLI::IsMember({"auto", "orbit", "follow", "fixed"}))
      ->capture_default_str();
  app->add_option("--camera-bird", camera.bird, "With --camera follow: the bird followed (default 0)");
  add_point_option(app, "--camera-eye", camera.eye,
                   "With --camera fixed: where the camera is, X,Y,Z in metres (default: where auto starts)");
  add_point_option(app, "--camera-target", camera.target,
                   "With --camera fixed: what it looks at, X,Y,Z in metres (default: the flock)");
  app->add_option("--fov", camera.fov_degrees, "Vertical field of view in degrees")
      ->check(CLI::Range(5.0f, 150.0f))
      ->capture_default_str();
  app->add_option_function<std::string>(
         "--targets", [&targets](const std::string& v) { targets = v == "on"; },
         "on or off: the target rings and the routes between them (default on)")
      ->check(CLI::IsMember({"on", "off"}));
}

// Options that belong to another camera are errors, not silently ignored.
void check_camera_options(const render::CameraOptions& camera, const CLI::App& app, bool draws) {
  if (!draws)
    for (const char* name : {"--camera", "--camera-bird", "--camera-eye", "--camera-target", "--fov", "--targets", "--msaa"})
      if (app.count(name) > 0) throw CLI::ValidationError(name, "needs --png, --frames-dir or --video");
  if (camera.mode != "fixed" && (camera.eye || camera.target))
    throw CLI::ValidationError(camera.eye ? "--camera-eye" : "--camera-target",
                               "needs --camera fixed (the camera is " + camera.mode + ")");
  if (camera.eye && camera.target && glm::distance(*camera.eye, *camera.target) < 1.0)
    throw CLI::ValidationError("--camera-target", "must differ from --camera-eye (the camera looks at its own eye)");
  if (camera.mode != "follow" && app.count("--camera-bird") > 0)
    throw CLI::ValidationError("--camera-bird", "needs --camera follow (the camera is " + camera.mode + ")");
}

}  // namespace
}  // namespace aeroflock

int main(int argc, char** argv) {
  using namespace aeroflock;
  CLI::App app{"aeroflock: real-time bird flight simulation based on aerodynamics"};
  app.require_subcommand(1);
  CLI::App* scenarios = app.add_subcommand("scenarios", "List the built-in scenarios");
  CLI::App* devices = app.add_subcommand("devices", "List the Vulkan devices");

  RunOptions opt;
  CLI::App* run_cmd = app.add_subcommand("run", "Run a scenario and summarise it");
  run_cmd->add_option("scenario", opt.scenario, "A built-in scenario name or a FILE.toml")
      ->capture_default_str();
  run_cmd
      ->add_option("--backend", opt.backend, "Backend: vulkan (compute shaders) or cpu (reference)")
      ->check(CLI::IsMember({"vulkan", "cpu"}))
      ->capture_default_str();
  run_cmd->add_option("--device", opt.device, "Vulkan device index (see `aeroflock devices`)")
      ->check(CLI::NonNegativeNumber);
  run_cmd->add_option("--birds", opt.birds, "Birds in all, shared over the flocks in proportion")
      ->check(kPositive);
  run_cmd->add_option("--seconds", opt.seconds, "Simulated seconds (default: the scenario's)")
      ->check(kPositive);
  run_cmd->add_option("--summary", opt.summary, "Write the run summary to this JSON file");
  run_cmd->add_option("--threads", opt.threads, "CPU threads (default: OpenMP's choice)")
      ->check(kPositive);
  run_cmd->add_option("--png", opt.images.png, "Render the last frame to this PNG (headless)");
  run_cmd->add_option("--frames-dir", opt.images.frames_dir,
                      "Render frames to DIR/frame_NNNNNN.png");
  run_cmd->add_option("--every", opt.images.every, "With --frames-dir: every K-th frame")
      ->check(CLI::PositiveNumber);
  CLI::Option* video_opt =
      run_cmd->add_option("--video", opt.images.video, "Render the run to FILE.mp4 (needs ffmpeg)");
  run_cmd->add_option("--fps", opt.images.fps,
                      "With --video: frames per simulated second (default: one a frame, real time)")
      ->check(kPositive)
      ->needs(video_opt);
  add_camera_options(run_cmd, opt.images.camera, opt.images.targets);
  run_cmd->add_option("--msaa", opt.images.msaa, "Samples a pixel: 1 (none), 2, 4 or 8 (default 4)")
      ->check(CLI::IsMember({1, 2, 4, 8}));
  add_size_option(run_cmd, opt.images.width, opt.images.height,
                  "Image size WxH (default 1280x720)");
  run_cmd->add_option(
      "--vtk", opt.vtk_dir,
      "Write VTK files for ParaView/Python to DIR: frames, flock.pvd, trajectories.vtp");
  run_cmd->add_option("--vtk-every", opt.vtk_every, "With --vtk: every K-th frame (default 1)")
      ->check(CLI::PositiveNumber);
  run_cmd
      ->add_option("--vtk-birds", opt.vtk_birds,
                   "With --vtk: all, every:N or a list of bird ids like 3,7,12 (default all)")
      ->capture_default_str();
  run_cmd
      ->add_option("--vtk-compression", opt.vtk_compression,
                   "With --vtk: none, lz4 or zlib (default lz4)")
      ->check(CLI::IsMember({"none", "lz4", "zlib"}))
      ->capture_default_str();

  ViewOptions view_opt;
  CLI::App* view_cmd = app.add_subcommand("view", "Watch a scenario in a window");
  view_cmd->add_option("scenario", view_opt.scenario, "A built-in scenario name or a FILE.toml")
      ->capture_default_str();
  view_cmd
      ->add_option("--device", view_opt.viewer.device,
                   "Vulkan device index (see `aeroflock devices`)")
      ->check(CLI::NonNegativeNumber);
  view_cmd
      ->add_option("--birds", view_opt.viewer.birds,
                   "Birds in all, shared over the flocks in proportion")
      ->check(kPositive);
  add_size_option(view_cmd, view_opt.viewer.width, view_opt.viewer.height,
                  "Window size WxH (default 1280x720)");
  view_cmd->add_flag("--paused", view_opt.viewer.paused, "Start with the simulation paused");
  add_camera_options(view_cmd, view_opt.viewer.camera, view_opt.viewer.targets);
  view_cmd
      ->add_option("--msaa", view_opt.viewer.msaa,
                   "Samples a pixel: 1 (none), 2, 4 or 8 (default 4; 1 on a CPU device such as lavapipe)")
      ->check(CLI::IsMember({1, 2, 4, 8}));
  view_cmd
      ->add_option("--frames", view_opt.viewer.frames,
                   "Close the window after N frames (for tests)")
      ->check(kPositive);

  BenchOptions bench_opt;
  std::string bench_backends = "vulkan,cpu";
  std::string bench_variants;
  CLI::App* bench_cmd = app.add_subcommand(
      "bench",
      "Measure birds per frame, scaling with the flock and Vulkan against the CPU reference");
  bench_cmd->add_flag("--quick", bench_opt.quick,
                      "A short smoke run: 1000 and 3000 birds, headless only");
  bench_cmd->add_option("--json", bench_opt.json,
                        "Write the results as JSON (Google Benchmark-like) to FILE");
  bench_cmd->add_option("--plot", bench_opt.plot,
                        "Plot ms per frame and bird-steps/s against N to FILE.png (gnuplot)");
  bench_cmd
      ->add_option("--backends", bench_backends,
                   "Comma-separated backends: vulkan, vulkan:N (Vulkan on device N), cpu")
      ->capture_default_str();
  bench_cmd->add_option("--variants", bench_variants,
                        "Comma-separated variants: headless, solo, render, vtk (default: all; "
                        "--quick: headless)");
  bench_cmd->add_option("--scenario", bench_opt.scenario,
                        "Scenario measured, a built-in name or FILE.toml (default: default)");
  bench_cmd->add_option("--max-birds", bench_opt.max_birds,
                        "Largest flock of the sweep (1k, 3k, 10k, ... up to it, and it)")
      ->check(kPositive)
      ->capture_default_str();
  bench_cmd
      ->add_option("--repetitions", bench_opt.repetitions,
                   "Timed frames per measurement (default 5 quick, 15 full)")
      ->check(kPositive);
  bench_cmd
      ->add_option("--device", bench_opt.device, "Vulkan device index (see `aeroflock devices`)")
      ->check(CLI::NonNegativeNumber);

  EnvelopeOptions envelope_opt;
  CLI::App* envelope_cmd = app.add_subcommand(
      "envelope", "Fly a species through a grid of starts, targets, winds, take-offs and landings");
  envelope_cmd->add_option("--species", envelope_opt.species, "A preset (eagle, starling) or FILE.toml (its last [[species]])")
      ->capture_default_str();
  envelope_cmd->add_option("--backend", envelope_opt.backend, "cpu (reference) or vulkan")
      ->check(CLI::IsMember({"vulkan", "cpu"}))
      ->capture_default_str();
  envelope_cmd->add_option("--device", envelope_opt.device, "Vulkan device index (see `aeroflock devices`)")
      ->check(CLI::NonNegativeNumber);
  envelope_cmd->add_option("--json", envelope_opt.json, "Write every case and its outcome to FILE");
  envelope_cmd->add_flag("--quick", envelope_opt.quick, "A small subset of short flights");

  try {
    app.parse(argc, argv);
    if (run_cmd->parsed()) check_camera_options(opt.images.camera, *run_cmd, opt.images.any());
    if (view_cmd->parsed()) check_camera_options(view_opt.viewer.camera, *view_cmd, true);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : 2;
  }
  try {
    if (scenarios->parsed()) return list_scenarios();
    if (devices->parsed()) {
      for (const std::string& line : vulkan_devices()) std::cout << line << "\n";
      return 0;
    }
    if (view_cmd->parsed()) return view(view_opt);
    if (envelope_cmd->parsed()) return run_envelope(envelope_opt);
    if (bench_cmd->parsed()) {
      bench_opt.backends.clear();
      std::string item;
      for (std::istringstream in(bench_backends); std::getline(in, item, ',');)
        if (!item.empty()) bench_opt.backends.push_back(item);
      for (std::istringstream in(bench_variants); std::getline(in, item, ',');)
        if (!item.empty()) bench_opt.variants.push_back(item);
      return run_bench(bench_opt);
    }
    return run(opt);
  } catch (const ScenarioError& e) {
    std::cerr << e.what() << "\n";  // already "FILE:LINE:COLUMN: error: ..."
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "aeroflock: error: " << e.what() << "\n";
    return 2;
  }
}
