// aeroflock: list the built-in scenarios, run one and summarise it, or watch it in a window.
#include <omp.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cerrno>
#include <charconv>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <limits>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include <glm/geometric.hpp>

#include "backend.h"
#include "bench.h"
#include "converge.h"
#include "envelope.h"
#include "frame_output.h"
#include "gpu/gpu_simulation.h"
#include "io/paths.h"
#include "io/scenario_file.h"
#include "io/summary.h"
#include "io/vtk_export.h"
#include "progress.h"
#include "render/viewer.h"

namespace aeroflock {
namespace {

namespace fs = std::filesystem;

// --fidelity or --dt: the step a run takes instead of its scenario's (docs/convergence.md).
struct StepOption {
  std::string fidelity;
  std::optional<double> dt;
  // The step chosen, if one was.
  std::optional<double> value() const {
    if (!fidelity.empty()) return dt_of(parse_fidelity(fidelity));
    return dt;
  }
  void apply(Scenario& s) const {
    if (const auto v = value()) set_dt(s, *v);
  }
};

struct RunOptions {
  std::string scenario = "default";
  StepOption step;
  std::string backend = "vulkan";
  int device = -1;
  uint32_t birds = 0;
  std::vector<std::string> flocks;  // --flock NAME=COUNT
  std::optional<double> seconds;
  std::string summary;
  int threads = 0;
  ImageOptions images;
  std::string vtk_dir;
  uint32_t vtk_every = 1;
  std::string vtk_birds = "all";
  std::string vtk_compression = "lz4";
  std::string vtk_precision = "float";
  bool overwrite = false;  // --overwrite: an earlier export in vtk_dir is replaced
  bool strict = false;     // the first bird quarantined (NaN) is an error
};

// Ctrl-C (SIGINT) or SIGTERM: the run stops after the frame in progress, finishes its outputs and
// exits 128 + the signal's number, as a shell reports a death by it (130, 143). A second one
// (SA_RESETHAND) ends the program at once.
volatile std::sig_atomic_t g_signal = 0;
extern "C" void on_stop_signal(int signal) { g_signal = signal; }
constexpr uint64_t kBirdFramesPerSubmission =
    20000;  // a run's frames go to the device in batches of about this

struct ViewOptions {
  std::string scenario = "default";
  StepOption step;
  std::vector<std::string> flocks;  // --flock NAME=COUNT
  render::ViewerOptions viewer;
};

int list_scenarios(const std::string& show) {
  std::string names;
  for (const BuiltinScenario& s : builtin_scenarios()) {
    if (show.empty()) std::cout << s.name << "\n    " << s.description << "\n";
    if (s.name == show) {
      std::cout << s.text;
      return 0;
    }
    names += (names.empty() ? "" : ", ") + s.name;
  }
  if (!show.empty())
    throw std::runtime_error("--show: no built-in scenario " + show + " (the built-ins: " + names +
                             ")");
  return 0;
}

// --flock NAME=COUNT, each in turn: that flock gets COUNT birds (0 removes it), its spawn box
// grown or shrunk to keep its density.
void resize_flocks(Scenario& scenario, const std::vector<std::string>& sizes) {
  for (const std::string& item : sizes) {
    const size_t eq = item.find('=');
    uint64_t count = 0;
    const char* first = item.data() + (eq == std::string::npos ? 0 : eq + 1);
    const char* last = item.data() + item.size();
    const auto [end, ec] = std::from_chars(first, last, count);
    if (eq == std::string::npos || eq == 0 || first == last || ec != std::errc() || end != last ||
        count > std::numeric_limits<uint32_t>::max())
      throw std::runtime_error(
          "--flock: expected NAME=COUNT (a flock of the scenario and a whole "
          "number of birds, 0 to leave it out), got " +
          item);
    const std::string name = item.substr(0, eq);
    std::string names;
    size_t index = scenario.flocks.size();
    for (size_t i = 0; i < scenario.flocks.size(); ++i) {
      if (scenario.flocks[i].name == name) index = i;
      names += (i ? ", " : "") + scenario.flocks[i].name;
    }
    if (index == scenario.flocks.size())
      throw std::runtime_error("--flock " + item + ": scenario " + scenario.name +
                               " has no flock " + name +
                               " (its flocks: " + (names.empty() ? "none" : names) + ")");
    resize_flock(scenario, index, uint32_t(count));
  }
}

// Whole numbers from `min` to `max`: "expected an integer from 1 to 1024, got 0" (CLI11's own
// range checks name the whole double range, some 300 digits, and accept 2.5).
CLI::Validator integer_in(uint64_t min, uint64_t max) {
  return CLI::Validator(
      [min, max](std::string& text) -> std::string {
        uint64_t v = 0;
        const char* end = text.data() + text.size();
        const auto [ptr, ec] = std::from_chars(text.data(), end, v);
        if (ec == std::errc() && ptr == end && v >= min && v <= max) return "";
        const bool too_large =
            (ec == std::errc::result_out_of_range || (ec == std::errc() && v > max)) && ptr == end;
        return max == std::numeric_limits<uint32_t>::max() && !too_large
                   ? "expected an integer >= " + std::to_string(min) + ", got " + text
                   : "expected an integer from " + std::to_string(min) + " to " +
                         std::to_string(max) + ", got " + text;
      },
      max == std::numeric_limits<uint32_t>::max()
          ? ">= " + std::to_string(min)
          : std::to_string(min) + ".." + std::to_string(max));
}
const CLI::Validator kCount = integer_in(1, std::numeric_limits<uint32_t>::max());
const CLI::Validator kIndex = integer_in(0, std::numeric_limits<uint32_t>::max());
constexpr uint64_t kMaxThreads = 1024;
// A path: an empty one (an unset "$OUT") would lose the output without a word.
const CLI::Validator kPath(
    [](std::string& text) -> std::string {
      return text.empty() ? "expected a path, got an empty one" : "";
    },
    "PATH");

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

// Numbers from `min` to `max` (`unit` after them in the message), e.g. --dt's "expected a number
// from 1e-05 to 0.01 s (docs/convergence.md), got 2".
CLI::Validator number_in(double min, double max, const std::string& unit, const std::string& why) {
  return CLI::Validator(
      [=](std::string& text) -> std::string {
        char* end = nullptr;
        const double v = std::strtod(text.c_str(), &end);
        if (end != text.c_str() && *end == '\0' && v >= min && v <= max) return "";
        std::ostringstream message;
        message << "expected a number from " << min << " to " << max << " " << unit << " (" << why
                << "), got " << text;
        return message.str();
      },
      "");
}
// The time step and the flight a run may ask for (engine/model/scenario.h, docs/convergence.md).
const CLI::Validator kStep = number_in(kMinDt, kMaxDt, "s", "docs/convergence.md");
const CLI::Validator kStepMs = number_in(kMinDt * 1e3, kMaxDt * 1e3, "ms", "docs/convergence.md");
// A positive duration, at most kMaxDuration (strtod: "1e-30" is positive, it flies one frame).
const CLI::Validator kSeconds(
    [](std::string& text) -> std::string {
      char* end = nullptr;
      const double v = std::strtod(text.c_str(), &end);
      if (end != text.c_str() && *end == '\0' && v > 0 && v <= kMaxDuration) return "";
      std::ostringstream message;
      message << "expected a positive number of seconds, at most " << kMaxDuration
              << " (11.6 days), got " << text;
      return message.str();
    },
    "");

// "starlings 1000, eagles 20": each flock's birds, as --birds or --flock shared them.
std::string flock_counts(const Scenario& scenario, const std::vector<BirdState>& birds) {
  std::vector<uint64_t> count(scenario.flocks.size(), 0);
  for (const BirdState& b : birds)
    if (b.flock < count.size()) ++count[b.flock];
  std::string text;
  for (size_t i = 0; i < count.size(); ++i)
    text += (i ? ", " : "") + scenario.flocks[i].name + " " + std::to_string(count[i]);
  return text;
}

void print_summary(const RunSummary& r, const std::string& flocks, double asked_seconds,
                   const std::string& summary_path, const VtkExporter* vtk,
                   const std::vector<std::string>& images, bool interrupted) {
  const FlockStatistics& s = r.stats;
  const double rate = r.wall_seconds > 0 ? s.birds * double(r.steps) / r.wall_seconds : 0.0;
  std::printf("scenario         %s\n", r.scenario.c_str());
  std::printf("backend          %s\n", r.device.c_str());
  std::printf("birds            %llu (%llu flying, %llu perched, %llu with NaN)\n",
              (unsigned long long)s.birds, (unsigned long long)s.flying,
              (unsigned long long)s.perched, (unsigned long long)s.nan_birds);
  std::printf("flocks           %s\n", flocks.c_str());
  const double frame_seconds = r.dt * r.steps_per_frame;
  std::printf("simulated        %.3f s (%llu steps of %g s", r.sim_seconds,
              (unsigned long long)r.steps, r.dt);
  if (!interrupted && std::abs(r.sim_seconds - asked_seconds) > 1e-9 * asked_seconds)
    std::printf("; %g s asked, rounded up to whole frames of %g s", asked_seconds, frame_seconds);
  std::printf(")\n");
  std::printf("wall time        %.3f s (%.3g bird-steps/s)\n", r.wall_seconds, rate);
  std::printf("centroid         (%.2f, %.2f, %.2f) m\n", s.centroid.x / 100, s.centroid.y / 100,
              s.centroid.z / 100);
  std::printf("mean speed       %.2f m/s\n", s.mean_speed / 100);
  std::printf("targets reached  %llu\n", (unsigned long long)s.targets_reached);
  for (const FlockingSummary& f : r.flocking)
    std::printf(
        "flock %-10s median nearest neighbour %.2f m, %.2f %% nearer than half a wingspan, "
        "polarisation %.3f, largest cluster %.1f %%\n",
        f.name.c_str(), f.metrics.median_nearest / 100, 100 * f.metrics.too_close,
        f.metrics.polarisation, 100 * f.metrics.largest_cluster);
  // Only the files written are named (summary_path is empty when its write failed).
  if (!summary_path.empty()) std::printf("summary          %s\n", summary_path.c_str());
  for (const std::string& line : images) std::printf("%s\n", line.c_str());
  if (vtk && !vtk->failed())
    std::printf("vtk              %s (%zu frame%s of %zu bird%s: flock.pvd, trajectories.vtp)\n",
                vtk->dir().c_str(), vtk->frames_added(), vtk->frames_added() == 1 ? "" : "s",
                vtk->selected().size(), vtk->selected().size() == 1 ? "" : "s");
  if (vtk)
    std::printf("vtk queue        at most %llu of %llu frames waited for the disk (%.3g MB)\n",
                (unsigned long long)r.vtk_queue_frames, (unsigned long long)r.vtk_queue_bound,
                double(r.vtk_queue_bytes) / 1e6);
  if (interrupted)
    std::printf("interrupted      at t = %.3f s (%s)\n", r.sim_seconds,
                r.signal == "SIGINT" ? "SIGINT, Ctrl-C" : r.signal.c_str());
  if (!r.error.empty())
    std::printf("stopped          at t = %.3f s: %s\n", r.sim_seconds, r.error.c_str());
}

// NaN quarantine (step.cpp): each quarantined bird once on stderr, the first kShown by time.
void report_quarantined(const std::vector<BirdState>& birds,
                        const std::vector<QuarantinedBird>& listed) {
  constexpr size_t kShown = 10;
  for (size_t k = 0; k < listed.size() && k < kShown; ++k) {
    const BirdState& b = listed[k].last;
    std::fprintf(
        stderr,
        "aeroflock: bird %llu quarantined: its state became non-finite in the step at t = %.4f s; "
        "frozen at its last finite state, position (%.2f, %.2f, %.2f) m, velocity (%.2f, %.2f, "
        "%.2f) m/s\n",
        (unsigned long long)listed[k].bird, listed[k].time, b.position.x / 100, b.position.y / 100,
        b.position.z / 100, b.velocity.x / 100, b.velocity.y / 100, b.velocity.z / 100);
  }
  const auto all =
      static_cast<size_t>(std::count_if(birds.begin(), birds.end(), [](const BirdState& b) {
        return b.mode == FlightMode::quarantined;
      }));
  if (all > kShown)
    std::fprintf(stderr,
                 "aeroflock: %zu more birds quarantined (the summary lists the first %zu)\n",
                 all - kShown, kQuarantinedListed);
}

// A scenario without birds is a mistake (an empty file), not a run. (A flock's count is >= 1.)
void require_birds(const Scenario& scenario, const std::vector<std::string>& flock_sizes) {
  if (scenario.flocks.empty() && !flock_sizes.empty())
    throw std::runtime_error("--flock: no birds are left in scenario " + scenario.name +
                             " (every flock was given 0)");
  if (scenario.flocks.empty())
    throw std::runtime_error(
        "scenario " + scenario.name +
        " has no birds: it needs a [[flocks]] table (see `aeroflock scenarios --show default`)");
}

int run(const RunOptions& opt) {
  g_signal = 0;
  struct sigaction action {};
  action.sa_handler = on_stop_signal;
  // SA_RESTART: a write under way (a video frame into ffmpeg's pipe) goes on, not half done.
  action.sa_flags = SA_RESETHAND | SA_RESTART;
  sigemptyset(&action.sa_mask);
  sigaction(SIGINT, &action, nullptr);
  sigaction(SIGTERM, &action, nullptr);
  // A video's ffmpeg that has died: a write error to report, not a silent death by SIGPIPE.
  std::signal(SIGPIPE, SIG_IGN);
  if (!opt.summary.empty()) check_output_path(opt.summary, "--summary", {".json"});
  if (opt.threads > 0) omp_set_num_threads(opt.threads);

  Scenario scenario = load_scenario(opt.scenario);
  opt.step.apply(scenario);
  resize_flocks(scenario, opt.flocks);
  require_birds(scenario, opt.flocks);
  // Tests of the NaN quarantine: that flock's birds turn non-finite near the ground.
  if (const char* doomed = std::getenv("AEROFLOCK_TEST_NAN_FLOCK"))
    make_flock_non_finite(scenario, doomed);
  const double seconds = opt.seconds.value_or(scenario.duration);
  const double frame_seconds = scenario.dt * scenario.steps_per_frame;
  // Whole frames, at least one: any positive duration flies. The small allowance keeps an exact
  // multiple from gaining a frame to rounding. (seconds <= kMaxDuration and frame_seconds >=
  // kMinDt: at most 10^11 frames, far inside uint64_t.)
  const auto frames =
      static_cast<uint64_t>(std::max(1.0, std::ceil(seconds / frame_seconds - 1e-9)));
  const double total_seconds = double(frames) * frame_seconds;  // whole frames

  RunSummary summary;
  summary.scenario = scenario.name;
  summary.scenario_hash = scenario.hash;
  summary.dt = scenario.dt;
  summary.steps_per_frame = scenario.steps_per_frame;
  std::unique_ptr<Simulation> sim =
      make_simulation({opt.backend, opt.birds, opt.device, opt.images.any()}, std::move(scenario));
  std::unique_ptr<FrameOutput> images;
  if (opt.images.any()) images = std::make_unique<FrameOutput>(opt.images, *sim);
  summary.backend = sim->backend();
  summary.device = describe_device(*sim);

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
    vo.precision = opt.vtk_precision == "double" ? VtkOptions::Precision::float64
                                                 : VtkOptions::Precision::float32;
    vo.overwrite = opt.overwrite;
    try {
      vtk = std::make_unique<VtkExporter>(vo, sim->scenario(), birds);
    } catch (const std::invalid_argument& e) {
      throw std::runtime_error(std::string("--vtk-birds: ") + e.what());
    }
  }
  // The run's observers, finished in this order: the progress line's last, --strict's error, the
  // pictures, the VTK files (the first error is the summary's).
  RunProgress progress(total_seconds);
  StrictCheck strict;
  std::vector<RunObserver*> observers = {&progress};
  if (opt.strict) observers.push_back(&strict);
  if (images) observers.push_back(images.get());
  if (vtk) observers.push_back(vtk.get());
  RunLimits limits;
  limits.frames = frames;
  limits.signal = &g_signal;
  // Without pictures or exports nothing reads a frame: a small flock's frames go to the device
  // several at a time (Simulation::step_frames), about kBirdFramesPerSubmission bird-frames each.
  limits.batch = std::clamp<uint64_t>(kBirdFramesPerSubmission / std::max<size_t>(birds, 1), 1,
                                      gpu::kFramesPerSubmission);
  const RunResult run = run_frames(*sim, observers, limits);
  const bool interrupted = run.end == RunResult::End::signal;
  std::vector<std::string> errors = run.errors;

  summary.wall_seconds = run.wall_seconds;
  summary.steps = sim->steps();
  summary.sim_seconds = sim->time();
  summary.interrupted = interrupted;
  summary.stats = flock_statistics(sim->birds());
  summary.flocking = flocking_summary(sim->scenario(), sim->birds());
  summary.quarantined = quarantined_birds(sim->birds(), kQuarantinedListed);
  if (vtk) {
    const VtkExporter::QueueUse queue = vtk->queue_high_water();
    summary.vtk_queue_frames = queue.frames;
    summary.vtk_queue_bytes = queue.bytes;
    summary.vtk_queue_bound = vtk->queue_bound();
  }
  if (interrupted) summary.signal = run.signal == SIGTERM ? "SIGTERM" : "SIGINT";
  if (!errors.empty()) summary.error = errors.front();
  std::string summary_written = opt.summary;
  if (!opt.summary.empty()) {
    try {
      write_summary(opt.summary, summary);
    } catch (const std::runtime_error& e) {
      errors.push_back(e.what());
      if (summary.error.empty()) summary.error = e.what();
      summary_written.clear();
    }
  }
  print_summary(summary, flock_counts(sim->scenario(), sim->birds()), seconds, summary_written,
                vtk.get(), images ? images->written() : std::vector<std::string>{}, interrupted);
  report_quarantined(sim->birds(), summary.quarantined);
  if (!errors.empty()) {
    std::fflush(stdout);
    for (const std::string& e : errors) std::cerr << "aeroflock: error: " << e << "\n";
    return 2;
  }
  return interrupted ? 128 + run.signal : 0;
}

int view(const ViewOptions& opt) {
  Scenario scenario = load_scenario(opt.scenario);
  opt.step.apply(scenario);
  resize_flocks(scenario, opt.flocks);
  require_birds(scenario, opt.flocks);
  std::cout << render::viewer_keys() << std::endl;
  return render::run_viewer(std::move(scenario), opt.viewer);
}

// --fidelity paper|fast or --dt SECONDS: the time step, the frame kept 30 ms of flight.
// The options every command that flies a simulation takes alike: the backend, the Vulkan device
// and the scenario, said once here.
void add_backend_option(CLI::App* app, std::string& backend) {
  app->add_option("--backend", backend,
                  "Backend: vulkan (compute shaders) or cpu (reference, double)")
      ->check(CLI::IsMember({"vulkan", "cpu"}))
      ->capture_default_str();
}

void add_device_option(CLI::App* app, int& device) {
  app->add_option("--device", device, "Vulkan device index (see `aeroflock devices`)")
      ->check(kIndex);
}

void add_scenario_argument(CLI::App* app, std::string& scenario) {
  app->add_option("scenario", scenario, "A built-in scenario name or a FILE.toml")
      ->capture_default_str();
}

void add_step_options(CLI::App* app, StepOption& step, const char* default_is) {
  char help[160];
  std::snprintf(help, sizeof help,
                "The time step: paper (%g ms) or fast (%g ms, docs/convergence.md); default %s",
                kPaperDt * 1e3, kFastDt * 1e3, default_is);
  CLI::Option* fidelity =
      app->add_option("--fidelity", step.fidelity, help)->check(CLI::IsMember({"paper", "fast"}));
  app->add_option("--dt", step.dt,
                  "The time step in seconds, instead of --fidelity's (10 us to 10 ms)")
      ->check(kStep)
      ->excludes(fidelity);
}

// --size WxH into `width` and `height`.
void add_size_option(CLI::App* app, uint32_t& width, uint32_t& height, const char* what) {
  app->add_option_function<std::string>(
      "--size",
      [&width, &height](const std::string& text) {
        // Strictly WxH: digits, an x, digits, nothing else (sscanf would wrap 4294967312 to 16
        // and ignore "junk" after the height).
        uint64_t w = 0, h = 0;
        const char* end = text.data() + text.size();
        const auto [x, ec1] = std::from_chars(text.data(), end, w);
        const bool has_x = ec1 == std::errc() && x != end && *x == 'x';
        const auto [rest, ec2] = has_x ? std::from_chars(x + 1, end, h)
                                       : std::from_chars_result{x, std::errc::invalid_argument};
        if (!has_x || ec2 != std::errc() || rest != end || w < 16 || h < 16 || w > 8192 || h > 8192)
          throw CLI::ValidationError("--size",
                                     "expected WxH between 16x16 and 8192x8192, got " + text);
        width = uint32_t(w);
        height = uint32_t(h);
      },
      what);
}

// X,Y,Z in metres into `point` (cm).
void add_point_option(CLI::App* app, const char* name, std::optional<glm::dvec3>& point,
                      const char* what) {
  app->add_option_function<std::string>(
      name,
      [&point, name](const std::string& text) {
        double x = 0, y = 0, z = 0;
        char extra = 0;
        if (std::sscanf(text.c_str(), "%lf,%lf,%lf%c", &x, &y, &z, &extra) != 3 ||
            !std::isfinite(x) || !std::isfinite(y) || !std::isfinite(z))
          throw CLI::ValidationError(name, "expected X,Y,Z in metres, got " + text);
        point = glm::dvec3(x, y, z) * 100.0;
      },
      what);
}

// The cameras of `run` (pictures) and `view` (the window).
void add_camera_options(CLI::App* app, render::CameraOptions& camera, bool& targets) {
  app->add_option(
         "--camera", camera.mode,
         "auto (frames the flock, following it), orbit (circles the flock), follow (behind "
         "one bird, --camera-bird) or fixed (--camera-eye, --camera-target)")
      ->check(CLI::IsMember({"auto", "orbit", "follow", "fixed"}))
      ->capture_default_str();
  app->add_option("--camera-bird", camera.bird,
                  "With --camera follow: the bird followed (default 0)");
  add_point_option(
      app, "--camera-eye", camera.eye,
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
    for (const char* name : {"--camera", "--camera-bird", "--camera-eye", "--camera-target",
                             "--fov", "--targets", "--msaa"})
      if (app.count(name) > 0)
        throw CLI::ValidationError(name, "needs --png, --frames-dir or --video");
  if (camera.mode != "fixed" && (camera.eye || camera.target))
    throw CLI::ValidationError(camera.eye ? "--camera-eye" : "--camera-target",
                               "needs --camera fixed (the camera is " + camera.mode + ")");
  if (camera.eye && camera.target && glm::distance(*camera.eye, *camera.target) < 1.0)
    throw CLI::ValidationError("--camera-target",
                               "must differ from --camera-eye (the camera looks at its own eye)");
  if (camera.mode != "follow" && app.count("--camera-bird") > 0)
    throw CLI::ValidationError("--camera-bird",
                               "needs --camera follow (the camera is " + camera.mode + ")");
}

// Letters to change, add or remove to turn `a` into `b` (Levenshtein).
size_t edit_distance(const std::string& a, const std::string& b) {
  std::vector<size_t> row(b.size() + 1);
  for (size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (size_t i = 1; i <= a.size(); ++i) {
    size_t diagonal = row[0];
    row[0] = i;
    for (size_t j = 1; j <= b.size(); ++j) {
      const size_t up = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] != b[j - 1])});
      diagonal = up;
    }
  }
  return row[b.size()];
}

// "aeroflock runn": the commands there are, and the likely one (CLI11 says only that a
// subcommand is required). Empty when `word` is a command.
std::string unknown_command(const CLI::App& app, const std::string& word) {
  std::string list, closest;
  size_t best = 3;  // suggest only within two edits
  for (const CLI::App* sub : app.get_subcommands({})) {
    if (sub->get_name() == word) return "";
    list += (list.empty() ? "" : ", ") + sub->get_name();
    if (const size_t d = edit_distance(word, sub->get_name()); d < best)
      best = d, closest = sub->get_name();
  }
  return "aeroflock: unknown command '" + word + "'" +
         (closest.empty() ? "" : " (did you mean '" + closest + "'?)") + "; the commands are " +
         list + " (aeroflock --help)";
}

}  // namespace
}  // namespace aeroflock

int main(int argc, char** argv) {
  using namespace aeroflock;
  CLI::App app{"aeroflock: real-time bird flight simulation based on aerodynamics"};
  app.require_subcommand(1);
  std::string show_scenario;
  CLI::App* scenarios = app.add_subcommand("scenarios", "List the built-in scenarios");
  scenarios->add_option("--show", show_scenario,
                        "Print a built-in scenario's TOML (to start one's own from: "
                        "aeroflock scenarios --show default > mine.toml)");
  CLI::App* devices = app.add_subcommand("devices", "List the Vulkan devices");

  RunOptions opt;
  CLI::App* run_cmd = app.add_subcommand("run", "Run a scenario and summarise it");
  add_scenario_argument(run_cmd, opt.scenario);
  add_backend_option(run_cmd, opt.backend);
  add_device_option(run_cmd, opt.device);
  CLI::Option* run_birds = run_cmd
                               ->add_option("--birds", opt.birds,
                                            "Birds in all, shared over the flocks in proportion, "
                                            "each flock as dense as the scenario's")
                               ->check(kCount);
  run_cmd
      ->add_option("--flock", opt.flocks,
                   "NAME=COUNT: that flock's birds (0 leaves it out), as dense as the scenario's; "
                   "repeatable")
      ->excludes(run_birds);
  run_cmd
      ->add_option("--seconds", opt.seconds,
                   "Simulated seconds (default: the scenario's; at most 1e6)")
      ->check(kSeconds);
  add_step_options(run_cmd, opt.step, "the scenario's");
  run_cmd->add_option("--summary", opt.summary, "Write the run summary to this JSON file")
      ->check(kPath);
  run_cmd->add_option("--threads", opt.threads, "CPU threads (default: OpenMP's choice)")
      ->check(integer_in(1, kMaxThreads));
  run_cmd->add_option("--png", opt.images.png, "Render the last frame to this PNG (headless)")
      ->check(kPath);
  CLI::Option* frames_dir_opt = run_cmd
                                    ->add_option("--frames-dir", opt.images.frames_dir,
                                                 "Render frames to DIR/frame_NNNNNN.png")
                                    ->check(kPath);
  run_cmd->add_option("--every", opt.images.every, "With --frames-dir: every K-th frame")
      ->check(kCount)
      ->needs(frames_dir_opt);
  CLI::Option* video_opt =
      run_cmd->add_option("--video", opt.images.video, "Render the run to FILE.mp4 (needs ffmpeg)")
          ->check(kPath);
  run_cmd
      ->add_option("--fps", opt.images.fps,
                   "With --video: frames per simulated second (default: one a frame, real time)")
      ->check(kPositive)
      ->needs(video_opt);
  add_camera_options(run_cmd, opt.images.camera, opt.images.targets);
  run_cmd->add_option("--msaa", opt.images.msaa, "Samples a pixel: 1 (none), 2, 4 or 8 (default 4)")
      ->check(CLI::IsMember({1, 2, 4, 8}));
  add_size_option(run_cmd, opt.images.width, opt.images.height,
                  "Image size WxH (default 1280x720)");
  CLI::Option* vtk_opt =
      run_cmd
          ->add_option(
              "--vtk", opt.vtk_dir,
              "Write VTK files for ParaView/Python to DIR: frames, flock.pvd, trajectories.vtp")
          ->check(kPath);
  run_cmd
      ->add_option("--vtk-every", opt.vtk_every,
                   "With --vtk: every K-th frame besides the first and the last (default 1)")
      ->check(kCount)
      ->needs(vtk_opt);
  run_cmd
      ->add_option("--vtk-birds", opt.vtk_birds,
                   "With --vtk: all, every:N or a list of bird ids like 3,7,12 (default all)")
      ->capture_default_str()
      ->needs(vtk_opt);
  run_cmd
      ->add_option("--vtk-compression", opt.vtk_compression,
                   "With --vtk: none, lz4 or zlib (default lz4)")
      ->check(CLI::IsMember({"none", "lz4", "zlib"}))
      ->capture_default_str()
      ->needs(vtk_opt);
  run_cmd
      ->add_option("--vtk-precision", opt.vtk_precision,
                   "With --vtk: float or double, the point data's precision (positions and times "
                   "are double always; default float, the Vulkan backend's own)")
      ->check(CLI::IsMember({"float", "double"}))
      ->capture_default_str()
      ->needs(vtk_opt);
  run_cmd
      ->add_flag(
          "--overwrite", opt.overwrite,
          "With --vtk: replace an earlier run's export in DIR (its flock.pvd, trajectories.vtp "
          "and frames/flock_*.vtp, no other file); without it such a DIR is an error")
      ->needs(vtk_opt);
  run_cmd->add_flag(
      "--strict", opt.strict,
      "A bird whose state becomes non-finite (NaN) stops the run with an error (exit 2), its "
      "outputs closed; without it the bird is quarantined (frozen, reported) and the rest fly on");

  ViewOptions view_opt;
  CLI::App* view_cmd = app.add_subcommand("view", "Watch a scenario in a window");
  add_scenario_argument(view_cmd, view_opt.scenario);
  add_device_option(view_cmd, view_opt.viewer.device);
  CLI::Option* view_birds = view_cmd
                                ->add_option("--birds", view_opt.viewer.birds,
                                             "Birds in all, shared over the flocks in proportion, "
                                             "each flock as dense as the scenario's")
                                ->check(kCount);
  view_cmd
      ->add_option("--flock", view_opt.flocks,
                   "NAME=COUNT: that flock's birds (0 leaves it out), as dense as the scenario's; "
                   "repeatable")
      ->excludes(view_birds);
  add_step_options(view_cmd, view_opt.step, "the scenario's");
  add_size_option(view_cmd, view_opt.viewer.width, view_opt.viewer.height,
                  "Window size WxH (default 1280x720)");
  view_cmd->add_flag("--paused", view_opt.viewer.paused, "Start with the simulation paused");
  add_camera_options(view_cmd, view_opt.viewer.camera, view_opt.viewer.targets);
  view_cmd
      ->add_option(
          "--msaa", view_opt.viewer.msaa,
          "Samples a pixel: 1 (none), 2, 4 or 8 (default 4; 1 on a CPU device such as lavapipe)")
      ->check(CLI::IsMember({1, 2, 4, 8}));
  view_cmd
      ->add_option("--frames", view_opt.viewer.frames,
                   "Close the window after N frames (for tests)")
      ->check(kCount);

  BenchOptions bench_opt;
  std::string bench_backends = "vulkan,cpu";
  std::string bench_variants;
  CLI::App* bench_cmd = app.add_subcommand(
      "bench",
      "Measure birds per frame, scaling with the flock and Vulkan against the CPU reference");
  bench_cmd->add_flag("--quick", bench_opt.quick,
                      "A short smoke run: 1000 and 3000 birds, headless only");
  bench_cmd
      ->add_option("--json", bench_opt.json,
                   "Write the results as JSON (Google Benchmark-like) to FILE")
      ->check(kPath);
  bench_cmd
      ->add_option("--plot", bench_opt.plot,
                   "Plot ms per frame and bird-steps/s against N to FILE.png (gnuplot)")
      ->check(kPath);
  bench_cmd
      ->add_option("--backends", bench_backends,
                   "Comma-separated backends: vulkan, vulkan:N (Vulkan on device N), cpu")
      ->capture_default_str();
  bench_cmd->add_option(
      "--variants", bench_variants,
      "Comma-separated variants: headless, solo, render, vtk, realtime (birds in real "
      "time at the paper's and the fast step) (default: all; --quick: headless)");
  bench_cmd->add_option("--scenario", bench_opt.scenario,
                        "Scenario measured, a built-in name or FILE.toml (default: default)");
  bench_cmd
      ->add_option("--max-birds", bench_opt.max_birds,
                   "Largest flock of the sweep (1k, 3k, 10k, ... up to it, and it)")
      ->check(kCount)
      ->capture_default_str();
  bench_cmd
      ->add_option("--repetitions", bench_opt.repetitions,
                   "Timed frames per measurement (default 5 quick, 15 full)")
      ->check(kCount);
  add_device_option(bench_cmd, bench_opt.device);
  StepOption bench_step;
  add_step_options(bench_cmd, bench_step, "the scenario's");

  EnvelopeOptions envelope_opt;
  CLI::App* envelope_cmd = app.add_subcommand(
      "envelope", "Fly a species through a grid of starts, targets, winds, take-offs and landings");
  envelope_cmd
      ->add_option("--species", envelope_opt.species,
                   "A preset (eagle, starling) or FILE.toml (its last [[species]])")
      ->capture_default_str();
  add_backend_option(envelope_cmd, envelope_opt.backend);
  add_device_option(envelope_cmd, envelope_opt.device);
  envelope_cmd->add_option("--json", envelope_opt.json, "Write every case and its outcome to FILE")
      ->check(kPath);
  envelope_cmd->add_flag("--quick", envelope_opt.quick, "A small subset of short flights");
  StepOption envelope_step;
  add_step_options(envelope_cmd, envelope_step, "paper");

  ConvergeOptions converge_opt;
  std::vector<double> converge_dts_ms;
  CLI::App* converge_cmd = app.add_subcommand("converge",
                                              "The time step's convergence study: every scenario "
                                              "and the envelope at steps of 0.1 to 10 ms");
  converge_cmd
      ->add_option("--scenarios", converge_opt.scenarios,
                   "Built-in names or FILE.toml, comma-separated (default: every built-in)")
      ->delimiter(',');
  converge_cmd
      ->add_option("--dts", converge_dts_ms,
                   "Steps in ms, comma-separated, the smallest the reference (default "
                   "0.1,0.3,0.5,1,2,3,5,10)")
      ->delimiter(',')
      ->check(kStepMs);
  converge_cmd
      ->add_option("--seconds", converge_opt.seconds, "Seconds flown by each run (default 10)")
      ->check(kSeconds);
  add_backend_option(converge_cmd, converge_opt.backend);
  add_device_option(converge_cmd, converge_opt.device);
  converge_cmd
      ->add_option(
          "--envelope", converge_opt.envelope,
          "Envelope cases flown at each step: none, quick, sample (every 5th flight) or whole")
      ->check(CLI::IsMember({"none", "quick", "sample", "whole"}))
      ->capture_default_str();
  converge_cmd->add_option("--json", converge_opt.json, "Write every figure to FILE.json")
      ->check(kPath);

  if (argc > 1 && argv[1][0] != '-')
    if (const std::string message = unknown_command(app, argv[1]); !message.empty()) {
      std::cerr << message << "\n";
      return 2;
    }
  try {
    app.parse(argc, argv);
    if (run_cmd->parsed()) check_camera_options(opt.images.camera, *run_cmd, opt.images.any());
    if (view_cmd->parsed()) check_camera_options(view_opt.viewer.camera, *view_cmd, true);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : 2;
  }
  try {
    if (scenarios->parsed()) return list_scenarios(show_scenario);
    if (devices->parsed()) {
      for (const std::string& line : vulkan_devices()) std::cout << line << "\n";
      return 0;
    }
    if (view_cmd->parsed()) return view(view_opt);
    if (envelope_cmd->parsed()) {
      envelope_opt.dt = envelope_step.value().value_or(kPaperDt);
      return run_envelope(envelope_opt);
    }
    if (converge_cmd->parsed()) {
      if (!converge_dts_ms.empty()) {
        converge_opt.dts.clear();
        for (double ms : converge_dts_ms) converge_opt.dts.push_back(ms * 1e-3);
      }
      return run_converge(converge_opt);
    }
    if (bench_cmd->parsed()) {
      bench_opt.backends.clear();
      std::string item;
      for (std::istringstream in(bench_backends); std::getline(in, item, ',');)
        if (!item.empty()) bench_opt.backends.push_back(item);
      for (std::istringstream in(bench_variants); std::getline(in, item, ',');)
        if (!item.empty()) bench_opt.variants.push_back(item);
      bench_opt.dt = bench_step.value().value_or(0.0);
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
