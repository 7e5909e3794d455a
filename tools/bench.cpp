#include "bench.h"

#include <omp.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>
#include <limits>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include <glm/geometric.hpp>

#include "backend.h"
#include "git_revision.h"
#include "gpu/compute.h"
#include "gpu/error.h"
#include "gpu/gpu_simulation.h"
#include "io/atomic_file.h"
#include "io/host.h"
#include "io/paths.h"
#include "io/scenario_file.h"
#include "model/statistics.h"
#include "output/pictures.h"
#include "output/vtk_export.h"
#include "plot.h"
#include "progress.h"
#include "render/offscreen.h"
#include "render/renderer.h"
#include "run/run_loop.h"

#ifndef AEROFLOCK_BUILD_TYPE
#define AEROFLOCK_BUILD_TYPE "unknown"
#endif

namespace aeroflock {
namespace {

// 12345 as "12,345".
std::string thousands(uint64_t n) {
  const std::string digits = std::to_string(n);
  std::string out;
  for (size_t i = 0; i < digits.size(); ++i) {
    if (i > 0 && (digits.size() - i) % 3 == 0) out += ',';
    out += digits[i];
  }
  return out;
}

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

constexpr uint32_t kRenderWidth = 1280, kRenderHeight = 720;
constexpr uint32_t kVtkEvery = 10;
// The frame budget: 40 frames per second of wall time, as the paper's real-time figure (a frame of
// the default scenario is 100 steps of 0.3 ms).
constexpr double kBudgetMs = 25.0;
// A sweep stops before a size whose measurement would take longer than this (estimated from the
// size before it, cost taken as linear in N).
constexpr double kMaxMeasurementSeconds = 150.0;

struct Settings {
  Scenario scenario;  // the scenario measured (--scenario), loaded once
  std::vector<std::string> backends;
  std::vector<std::string> variants;  // headless; solo, render and vtk too unless --quick
  std::vector<uint32_t> sizes;        // the sweep
  uint32_t cpu_cap = 0;               // the CPU reference is swept up to this many birds
  uint32_t max_birds = 0;
  double budget_ms = 0;  // wall ms per frame
  int warmup = 0;
  int repetitions = 0;
  bool quick = false;
  int device = -1;
  double after = 0.0;  // s of flight before the first frame timed (--after)
};

// A Vulkan frame's passes on the device's own clock (timestamps, gpu_simulation.h): the median
// over the timed frames of each pass, ms.
struct DevicePasses {
  double grid = 0, perception = 0, steps = 0;
  double cell = 0;  // cm: the neighbour grid's cell at the end (it follows the searches), 0: none
  double total() const { return grid + perception + steps; }
};

struct Measurement {
  std::string backend, variant, device;
  uint32_t birds = 0;
  int iterations = 0;
  double median = 0, p10 = 0, p90 = 0;  // ms per frame
  double bird_steps_per_second = 0;
  std::optional<DevicePasses> passes;  // Vulkan without drawing (headless, solo, realtime-*)
};

struct Series {
  std::string backend, variant;
  std::vector<Measurement> points;  // the sweep
  std::string stopped;              // why the sweep stopped early, if it did
  uint32_t birds_per_frame = 0;
  bool lower_bound = false;  // every size measured fitted: the real figure may be larger
  int search_steps = 0;
  bool skipped = false;              // n/a (the CPU reference with rendering)
  double budget_ms = 0.0, dt = 0.0;  // the realtime series': the frame's flight, and its step
  std::string key() const { return backend + "/" + variant; }
  bool real_time() const { return variant.starts_with("realtime-"); }
};

std::string host_name() {
  char name[256] = {};
  if (gethostname(name, sizeof name - 1) != 0) return "unknown";
  return name;
}

std::string now_iso8601() {
  const std::time_t t = std::time(nullptr);
  std::tm tm{};
  localtime_r(&t, &tm);
  char text[64];
  std::strftime(text, sizeof text, "%Y-%m-%dT%H:%M:%S%z", &tm);
  return text;
}

// Renders every frame offscreen at 1280x720 from the birds on the device, as `aeroflock run --png`
// does (the image is not read back). The camera looks at the whole flock as it is at the start.
class OffscreenLoad final : public RunObserver {
 public:
  explicit OffscreenLoad(Simulation& sim) : sim_(dynamic_cast<gpu::GpuSimulation*>(&sim)) {
    if (!sim_) throw std::runtime_error("rendering is measured only with the Vulkan backend");
    const gpu::Device& device = sim_->gpu_device();
    const VkExtent2D size{kRenderWidth, kRenderHeight};
    renderer_ = std::make_unique<render::Renderer>(device, sim.scenario(),
                                                   render::Offscreen::kFormat, size);
    target_ = std::make_unique<render::Offscreen>(device, size);
    submitter_ = std::make_unique<gpu::Submitter>(device, 1);
    const render::CameraControl control({}, render::subject_of(sim.birds(), 0, sim.time()));
    camera_ = control.camera();
    scene_distance_ = control.subject_distance();
  }

  void frame(Simulation&, uint64_t) override {
    render::View view;
    view.camera = camera_;
    view.scene_distance = scene_distance_;
    view.time = float(sim_->time());
    World world = sim_->scenario().world;
    world.move_targets(sim_->time());
    submitter_->run([&](VkCommandBuffer cmd) {
      renderer_->record(cmd, target_->image(), target_->view(), sim_->bird_buffer(),
                        uint32_t(sim_->bird_count()), world, view,
                        VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL);
    });
  }

 private:
  gpu::GpuSimulation* sim_;
  std::unique_ptr<render::Renderer> renderer_;
  std::unique_ptr<render::Offscreen> target_;
  std::unique_ptr<gpu::Submitter> submitter_;
  render::Camera camera_;
  float scene_distance_ = 0.0f;
};

int frames_per_sample(const std::string& variant) { return variant == "vtk" ? int(kVtkEvery) : 1; }
// VTK samples are whole export cycles: a third as many of them.
int samples(const std::string& variant, const Settings& s) {
  return variant == "vtk" ? std::max(3, (s.repetitions + 2) / 3) : s.repetitions;
}

// One flock of one backend and variant, flown through the run loop with the load measured
// (render: an offscreen picture of every frame; vtk: the export) and FrameTimes last: a frame's
// time is its steps, the birds read back and the load, in wall ms. With VTK export a sample is
// the mean frame of a whole export cycle (kVtkEvery frames, one of them handing its state to the
// writer thread); otherwise one frame. Throws gpu::Error when the device cannot hold the flock.
class Subject {
 public:
  Subject(const std::string& backend_name, const std::string& variant, uint32_t birds,
          const Settings& s)
      : cycle_(frames_per_sample(variant)) {
    // "vulkan:N" is Vulkan on device N; plain "vulkan" is the --device choice.
    const bool on_device = backend_name.starts_with("vulkan:");
    const int device = on_device ? std::stoi(backend_name.substr(7)) : s.device;
    // "solo": the same birds with flocking off, to show what flocking costs.
    Scenario scenario = s.scenario;
    if (variant == "solo")
      for (Flock& f : scenario.flocks) f.flocking = false;
    const bool rendering = variant == "render";
    sim_ = make_simulation(
        {on_device ? std::string("vulkan") : backend_name, birds, device, rendering}, scenario);
    // A flock that has flown a while (--after): spawned, it is more compact than in flight.
    if (s.after > 0.0) {
      flown_ = uint64_t(std::ceil(s.after / sim_->scenario().frame_seconds()));
      sim_->step_frames(uint32_t(flown_));
    }
    if (rendering) render_ = std::make_unique<OffscreenLoad>(*sim_);
    // The passes are timed where nothing but the flock runs (a timestamp costs next to nothing).
    // Not where a frame is drawn between the flock's: lavapipe then writes the timestamps late
    // (at the paper step the steps' 27 ms showed up in the perception's, the steps took 0.1 ms).
    if (auto* gpu = dynamic_cast<gpu::GpuSimulation*>(sim_.get());
        gpu && (variant == "headless" || variant == "solo" || variant.starts_with("realtime-")))
      timed_ = gpu->time_passes();
    if (variant == "vtk") {
      static int counter = 0;
      vtk_dir_.path = fs::temp_directory_path() / ("aeroflock-bench-" + std::to_string(::getpid()) +
                                                   "-" + std::to_string(counter++));
      VtkOptions vo;
      vo.dir = vtk_dir_.path;
      vo.every = kVtkEvery;
      sim_->prepare_forces();
      vtk_ = std::make_unique<VtkExporter>(vo, sim_->scenario(), sim_->bird_count());
    }
  }

  // `count` samples, flown as one run (the VTK export's start and end are not timed).
  std::vector<double> samples(int count) {
    FrameTimes times;
    std::vector<RunObserver*> observers;
    if (render_) observers.push_back(render_.get());
    if (vtk_) observers.push_back(vtk_.get());
    observers.push_back(&times);
    const RunResult r = run_frames(*sim_, observers, {.frames = uint64_t(count) * cycle_});
    if (!r.errors.empty()) throw std::runtime_error(r.errors.front());
    std::vector<double> out;
    const std::vector<double>& ms = times.milliseconds();
    for (size_t f = 0; f + cycle_ <= ms.size(); f += cycle_) {
      double sum = 0.0;
      for (int k = 0; k < cycle_; ++k) sum += ms[f + k];
      out.push_back(sum / cycle_);
    }
    return out;
  }
  double sample() { return samples(1).front(); }
  const Simulation& simulation() const { return *sim_; }

  // The passes' median device times over the frames after the first `skipped` (the warm-up).
  std::optional<DevicePasses> passes(uint64_t skipped) {
    if (!timed_) return std::nullopt;
    auto& gpu = dynamic_cast<gpu::GpuSimulation&>(*sim_);
    std::vector<double> grid, perception, steps;
    for (const gpu::GpuSimulation::PassTimes& t : gpu.pass_times())
      if (t.frame > flown_ + skipped) {
        grid.push_back(t.grid_ms);
        perception.push_back(t.perception_ms);
        steps.push_back(t.steps_ms);
      }
    if (steps.empty()) return std::nullopt;
    return DevicePasses{quantile(grid, 0.5), quantile(perception, 0.5), quantile(steps, 0.5),
                        gpu.grid_cell()};
  }

 private:
  int cycle_;
  uint64_t flown_ = 0;  // frames flown before any was timed (--after)
  bool timed_ = false;
  std::unique_ptr<Simulation> sim_;
  std::unique_ptr<OffscreenLoad> render_;
  TempDir vtk_dir_;  // before vtk_: the exporter finishes before its directory goes
  std::unique_ptr<VtkExporter> vtk_;
};

// One flock size, one backend, one variant: warm-up samples, then `repetitions` timed ones.
Measurement measure(const std::string& backend_name, const std::string& variant, uint32_t birds,
                    const Settings& s) {
  Subject subject(backend_name, variant, birds, s);
  std::vector<double> times = subject.samples(s.warmup + samples(variant, s));
  times.erase(times.begin(), times.begin() + s.warmup);

  Measurement m;
  m.backend = backend_name;
  m.variant = variant;
  m.device = describe_device(subject.simulation());
  m.birds = uint32_t(subject.simulation().bird_count());
  m.iterations = int(times.size());
  m.median = quantile(times, 0.5);
  m.p10 = quantile(times, 0.1);
  m.p90 = quantile(times, 0.9);
  m.bird_steps_per_second =
      m.median > 0 ? m.birds * double(s.scenario.steps_per_frame) / (m.median / 1000.0) : 0.0;
  m.passes = subject.passes(uint64_t(s.warmup) * frames_per_sample(variant));
  return m;
}

// What flocking costs at one size, its frames alternated with those of the same flock without it
// (headless and solo, in turn, each first every other time), so that both see the machine as it
// was in the same seconds: on a shared machine whose speed drifts over a sweep, the ratio of two
// sweeps measured minutes apart says more of the machine than of flocking.
struct Paired {
  std::string backend;
  uint32_t birds = 0;
  int iterations = 0;
  double with_ms = 0, without_ms = 0;  // median wall ms per frame
  double keeps() const { return with_ms > 0 ? without_ms / with_ms : 0.0; }
};

Paired measure_paired(const std::string& backend, uint32_t birds, const Settings& s) {
  Subject with(backend, "headless", birds, s), without(backend, "solo", birds, s);
  for (int i = 0; i < s.warmup; ++i) with.sample(), without.sample();
  std::vector<double> a, b;
  for (int i = 0; i < s.repetitions; ++i) {
    if (i % 2 == 0) {
      a.push_back(with.sample());
      b.push_back(without.sample());
    } else {
      b.push_back(without.sample());
      a.push_back(with.sample());
    }
  }
  return {backend, uint32_t(with.simulation().bird_count()), s.repetitions, quantile(a, 0.5),
          quantile(b, 0.5)};
}

void print_header(const Settings& s) {
  char after[64] = "";
  if (s.after > 0.0) std::snprintf(after, sizeof after, " after %g s of flight", s.after);
  std::printf(
      "aeroflock bench%s: %s scenario, %u steps of %g ms per frame, budget %g ms (%g fps), "
      "%d warm-up + %d timed frames%s\n\n",
      s.quick ? " --quick" : "", s.scenario.name.c_str(), s.scenario.steps_per_frame,
      s.scenario.dt * 1000, s.budget_ms, 1000.0 / s.budget_ms, s.warmup, s.repetitions, after);
  std::printf("%-8s %-9s %9s %11s %10s %10s %14s\n", "backend", "variant", "birds", "median ms",
              "p10 ms", "p90 ms", "bird-steps/s");
  std::fflush(stdout);
}

void print_row(const Measurement& m, double budget_ms) {
  std::printf("%-8s %-9s %9u %11.3f %10.3f %10.3f %14.4g%s", m.backend.c_str(), m.variant.c_str(),
              m.birds, m.median, m.p10, m.p90, m.bird_steps_per_second,
              m.median <= budget_ms ? "  fits" : "");
  if (m.passes) {
    const DevicePasses& p = *m.passes;
    const double total = p.total() > 0 ? p.total() : 1.0;
    std::printf("  device: grid %.3f, perception %.3f (%.0f %%), steps %.3f ms", p.grid,
                p.perception, 100.0 * p.perception / total, p.steps);
    if (p.cell > 0.0) std::printf(" (cells of %.2f m)", p.cell / 100.0);
  }
  std::printf("\n");
  std::fflush(stdout);
}

// b of ms = a N^b, least squares on log-log, and the sizes it was fitted over.
struct Fit {
  double b = 0.0;
  std::vector<uint32_t> sizes;
};

// Over sizes >= 3000 (all when fewer than 2 of them).
std::optional<Fit> scaling_exponent(const std::vector<Measurement>& points) {
  std::vector<const Measurement*> use;
  for (const Measurement& m : points)
    if (m.birds >= 3000 && m.median > 0) use.push_back(&m);
  if (use.size() < 2) {
    use.clear();
    for (const Measurement& m : points)
      if (m.median > 0) use.push_back(&m);
  }
  if (use.size() < 2) return std::nullopt;
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  const double n = double(use.size());
  for (const Measurement* m : use) {
    const double x = std::log(double(m->birds)), y = std::log(m->median);
    sx += x, sy += y, sxx += x * x, sxy += x * y;
  }
  const double d = n * sxx - sx * sx;
  if (std::abs(d) < 1e-12) return std::nullopt;
  Fit fit{(n * sxy - sx * sy) / d, {}};
  for (const Measurement* m : use) fit.sizes.push_back(m->birds);
  return fit;
}

// Quoted for gnuplot ('' is a quote inside '...') and for the shell ('\'' likewise).
void write_plot(const fs::path& png, const std::vector<Series>& series, double budget_ms) {
  std::vector<const Series*> drawn;
  for (const Series& s : series)
    if (!s.points.empty()) drawn.push_back(&s);
  if (drawn.empty()) throw std::runtime_error("--plot: nothing was measured");
  write_plot_png(png, "--plot", 1400, 560, [&](std::ostream& gp, const fs::path& dir) {
    const std::string data = (dir / "bench.dat").string();
    {
      std::ofstream out(data);
      for (const Series* s : drawn) {
        out << "# " << s->key() << "\n";
        for (const Measurement& m : s->points)
          out << m.birds << " " << m.median << " " << m.bird_steps_per_second << "\n";
        out << "\n\n";
      }
    }
    gp << "set multiplot layout 1,2 title 'aeroflock bench (default scenario)'\n";
    gp << "set logscale xy\nset grid\nset key top left\nset xlabel 'birds'\n";
    auto plot = [&](int column) {
      gp << "plot ";
      for (size_t i = 0; i < drawn.size(); ++i)
        gp << (i ? ", " : "") << gnuplot_string(data) << " index " << i << " using 1:" << column
           << " with linespoints title " << gnuplot_string(drawn[i]->key());
      if (column == 2)
        gp << ", " << budget_ms << " with lines dashtype 2 lc rgb 'gray' title 'budget "
           << budget_ms << " ms'";
      gp << "\n";
    };
    gp << "set ylabel 'ms per frame (median)'\n";
    plot(2);
    gp << "set ylabel 'bird-steps per second'\n";
    plot(3);
    gp << "unset multiplot\n";
  });
}

// Everything about the options that can fail fails now, before the run.
void check_options(const BenchOptions& options) {
  if (options.backends.empty()) throw std::runtime_error("--backends: none given");
  for (const std::string& b : options.backends)
    if (b != "vulkan" && b != "cpu" &&
        !(b.size() > 7 && b.starts_with("vulkan:") &&
          b.find_first_not_of("0123456789", 7) == std::string::npos && b.size() < 12))
      throw std::runtime_error("--backend: unknown backend " + b +
                               " (vulkan, vulkan:N for device N, cpu)");
  for (size_t i = 0; i < options.backends.size(); ++i)
    if (std::find(options.backends.begin() + i + 1, options.backends.end(), options.backends[i]) !=
        options.backends.end())
      throw std::runtime_error("--backend: " + options.backends[i] + " given twice");
  for (const std::string& b : options.backends)
    if (b.starts_with("vulkan:")) {
      const size_t count = vulkan_devices().size();
      if (std::stoul(b.substr(7)) >= count)
        throw std::runtime_error("--backend " + b + ": no such device (" + std::to_string(count) +
                                 " Vulkan device(s); see `aeroflock devices`)");
    }
  const std::vector<std::string> known{"headless", "solo", "render", "vtk", "realtime"};
  for (size_t i = 0; i < options.variants.size(); ++i) {
    const std::string& v = options.variants[i];
    if (std::find(known.begin(), known.end(), v) == known.end())
      throw std::runtime_error("--variants: unknown variant " + v +
                               " (headless, solo, render, vtk, realtime)");
    if (std::find(options.variants.begin() + i + 1, options.variants.end(), v) !=
        options.variants.end())
      throw std::runtime_error("--variants: " + v + " given twice");
  }
  if (!options.plot.empty()) {
    if (!has_program("gnuplot"))
      throw std::runtime_error("--plot needs gnuplot (Debian: apt-get install gnuplot-nox)");
    check_output_path(options.plot, "--plot", {".png"});
  }
  if (!options.json.empty()) check_output_path(options.json, "--json", {".json"});
}

Settings settings(const BenchOptions& options) {
  Settings s;
  s.scenario = load_scenario(options.scenario);
  options.step.apply(s.scenario);
  s.backends = options.backends;
  s.variants = !options.variants.empty() ? options.variants
               : options.quick
                   ? std::vector<std::string>{"headless"}
                   : std::vector<std::string>{"headless", "solo", "render", "vtk", "realtime"};
  s.sizes = options.quick
                ? std::vector<uint32_t>{1000, 3000}
                : std::vector<uint32_t>{1000, 3000, 10000, 30000, 100000, 300000, 1000000};
  std::erase_if(s.sizes, [&](uint32_t n) { return n > options.max_birds; });
  if (s.sizes.empty() || (!options.quick && s.sizes.back() < options.max_birds))
    s.sizes.push_back(options.max_birds);  // the largest asked for is measured too
  s.cpu_cap = options.quick ? 3000 : 30000;
  s.max_birds = options.max_birds;
  s.budget_ms = kBudgetMs;
  s.quick = options.quick;
  s.warmup = options.quick ? 2 : 5;
  s.repetitions = options.repetitions > 0 ? options.repetitions : (options.quick ? 5 : 15);
  s.device = options.device;
  s.after = options.after;
  return s;
}

// What the run has measured so far, and the progress line while it measures.
struct Run {
  explicit Run(const Settings& settings) : s(settings) {}

  // measure(), with the progress line saying what is measured.
  Measurement attempt(const Series& series, uint32_t n, const char* phase) {
    progress.show(series.key() + ": " + std::to_string(n) + " birds (" + phase + ")");
    Measurement m = measure(series.backend, series.variant, n, s);
    progress.clear();
    devices[series.backend] = m.device;
    return m;
  }

  // A series that fails once others have been measured: the run keeps what it has and goes on.
  void fail(Series& series, const std::exception& e) {
    series.stopped = std::string("failed: ") + e.what();
    failed.push_back(series.key() + ": " + e.what());
    std::printf("%-8s %-9s   failed: %s\n", series.backend.c_str(), series.variant.c_str(),
                e.what());
  }

  const Settings& s;
  Progress progress;
  std::vector<Series> all;                     // the series done, in the order measured
  std::map<std::string, std::string> devices;  // backend: its device
  std::vector<std::string> failed;             // "series: why"
  std::vector<Paired> paired;                  // flocking's cost, frames alternated
};

// The sizes both the headless and the solo sweep of a backend measured, their frames alternated
// (measure_paired), as long as a pair takes at most kMaxMeasurementSeconds.
void measure_flocking_cost(Run& run) {
  const Settings& s = run.s;
  for (const std::string& backend : s.backends) {
    const Series *with = nullptr, *without = nullptr;
    for (const Series& series : run.all)
      if (series.backend == backend) {
        if (series.variant == "headless") with = &series;
        if (series.variant == "solo") without = &series;
      }
    if (!with || !without) continue;
    for (const Measurement& a : with->points)
      for (const Measurement& b : without->points) {
        if (a.birds != b.birds) continue;
        const double seconds = (a.median + b.median) / 1000.0 * (s.warmup + s.repetitions);
        if (seconds > kMaxMeasurementSeconds) continue;
        try {
          run.progress.show(backend + ": " + std::to_string(a.birds) +
                            " birds (flocking's cost, frames alternated)");
          run.paired.push_back(measure_paired(backend, a.birds, s));
          run.progress.clear();
        } catch (const std::exception& e) {
          run.progress.clear();
          std::printf("%-8s %9u birds: flocking's cost not measured: %s\n", backend.c_str(),
                      a.birds, e.what());
        }
      }
  }
}

// Seconds a measurement of `n` birds would take, from the one of `last`, cost linear in N.
double estimated_seconds(const Measurement& last, uint32_t n, const Settings& s) {
  const double frames =
      double(frames_per_sample(last.variant)) * (s.warmup + samples(last.variant, s));
  return last.median * (double(n) / last.birds) * frames / 1000.0;
}

// The sweep over the sizes, a row printed for each. Returns the size the device could not hold,
// or 0.
uint32_t sweep(Run& run, Series& series) {
  const Settings& s = run.s;
  for (uint32_t n : s.sizes) {
    if (series.backend == "cpu" && n > s.cpu_cap) {
      series.stopped = "the CPU reference is swept up to " + std::to_string(s.cpu_cap) + " birds";
      return 0;
    }
    if (!series.points.empty()) {
      const double estimate = estimated_seconds(series.points.back(), n, s);
      if (estimate > kMaxMeasurementSeconds) {
        series.stopped = "stopped before " + std::to_string(n) + " birds: would take about " +
                         std::to_string(int(estimate)) + " s";
        return 0;
      }
    }
    try {
      series.points.push_back(run.attempt(series, n, "sweep"));
      print_row(series.points.back(), s.budget_ms);
    } catch (const gpu::Error& e) {
      run.progress.clear();
      if (series.points.empty()) {
        // Nothing measured yet: fail at once (no device, a bad vulkan:N).
        if (run.all.empty()) throw;
        run.fail(series, e);
        return 0;
      }
      series.stopped = std::string("device limit: ") + e.what();
      std::printf("%-8s %-9s %9u   does not fit: %s\n", series.backend.c_str(),
                  series.variant.c_str(), n, e.what());
      return n;
    } catch (const std::exception& e) {
      run.progress.clear();
      if (run.all.empty() && series.points.empty()) throw;
      run.fail(series, e);  // keep what the run has measured so far
      return 0;
    }
  }
  return 0;
}

// Birds per frame: bracketed from the sweep (the largest size that fitted, the smallest larger one
// that did not or that the device cannot hold), then bisected; --quick takes the bracket's foot.
void search_birds_per_frame(Run& run, Series& series, uint32_t device_cap) {
  const Settings& s = run.s;
  uint32_t lo = 0, hi = device_cap;
  for (const Measurement& m : series.points)
    if (m.median <= s.budget_ms) lo = std::max(lo, m.birds);
  for (const Measurement& m : series.points)
    if (m.median > s.budget_ms && m.birds > lo && (hi == 0 || m.birds < hi)) hi = m.birds;
  series.lower_bound = hi == 0 || s.quick;
  if (!s.quick && hi != 0) {
    while (hi - lo > std::max<uint32_t>(16, lo / 50)) {
      const uint32_t mid = lo + (hi - lo) / 2;
      ++series.search_steps;
      try {
        const Measurement m = run.attempt(series, mid, "search");
        (m.median <= s.budget_ms ? lo : hi) = mid;
      } catch (const gpu::Error&) {
        hi = mid;
      } catch (const std::exception& e) {
        run.progress.clear();
        run.fail(series, e);
        break;
      }
    }
  }
  series.birds_per_frame = lo;
}

// One backend and variant: the sweep, then the search for birds per frame.
Series measure_series(Run& run, const std::string& backend, const std::string& variant) {
  Series series;
  series.backend = backend;
  series.variant = variant;
  series.skipped = backend == "cpu" && variant == "render";
  if (series.skipped) return series;
  const uint32_t device_cap = sweep(run, series);
  search_birds_per_frame(run, series, device_cap);
  return series;
}

// Birds in real time: at the paper's and at the fast step, the largest flock (flocking as the
// scenario says) whose frame takes no longer on the wall clock than it flies: the budget is the
// frame's simulated time. Series "realtime-paper" and "realtime-fast", measured as headless.
void measure_real_time(Run& run, const std::string& backend) {
  for (const Fidelity fidelity : {Fidelity::paper, Fidelity::fast}) {
    Settings rt = run.s;
    set_dt(rt.scenario, dt_of(fidelity));
    rt.budget_ms = rt.scenario.frame_seconds() * 1000.0;
    const std::string name = fidelity_name(rt.scenario.dt);
    std::printf("%-8s realtime-%s: %u steps of %g ms a frame, budget %g ms (the frame's flight)\n",
                backend.c_str(), name.c_str(), rt.scenario.steps_per_frame, rt.scenario.dt * 1000,
                rt.budget_ms);
    Run sub(rt);
    Series series = measure_series(sub, backend, "realtime-" + name);
    series.budget_ms = rt.budget_ms;
    series.dt = rt.scenario.dt;
    run.devices.insert(sub.devices.begin(), sub.devices.end());
    run.failed.insert(run.failed.end(), sub.failed.begin(), sub.failed.end());
    run.all.push_back(std::move(series));
  }
}

// A Vulkan backend over the CPU reference in bird-steps/s, at the sizes both measured headless.
struct Ratios {
  std::string backend;
  std::vector<std::pair<uint32_t, double>> by_birds;
};

// The scaling exponent of each series measured (backend/variant), in the order measured (none:
// fewer than 2 sizes).
using Exponents = std::vector<std::pair<std::string, std::optional<Fit>>>;

const Series* headless(const std::vector<Series>& all, const std::string& backend) {
  for (const Series& series : all)
    if (series.backend == backend && series.variant == "headless") return &series;
  return nullptr;
}

std::vector<Ratios> vulkan_over_cpu(const std::vector<Series>& all,
                                    const std::vector<std::string>& backends) {
  std::vector<Ratios> ratios;
  const Series* cpu = headless(all, "cpu");
  for (const std::string& backend : backends) {
    const Series* vk = backend.starts_with("vulkan") ? headless(all, backend) : nullptr;
    if (!vk || !cpu || vk->points.empty() || cpu->points.empty()) continue;
    Ratios r{backend, {}};
    for (const Measurement& a : vk->points)
      for (const Measurement& b : cpu->points)
        if (a.birds == b.birds && b.bird_steps_per_second > 0)
          r.by_birds.emplace_back(a.birds, a.bird_steps_per_second / b.bird_steps_per_second);
    ratios.push_back(r);
  }
  return ratios;
}

Exponents scaling_exponents(const std::vector<Series>& all) {
  Exponents exponents;
  for (const Series& series : all)
    if (!series.skipped) exponents.emplace_back(series.key(), scaling_exponent(series.points));
  return exponents;
}

uint32_t largest_measured(const Series& series) {
  uint32_t n = 0;
  for (const Measurement& m : series.points) n = std::max(n, m.birds);
  return n;
}

// Birds per frame, or (real_time) birds in real time, each series' search found.
void print_birds_per_frame(const std::vector<Series>& all, const Settings& s, bool real_time) {
  bool any = false;
  for (const Series& series : all) any = any || series.real_time() == real_time;
  if (!any) return;
  if (real_time)
    std::printf(
        "\nbirds in real time (median frame <= the frame's flight, flocking as the scenario "
        "says):\n");
  else
    std::printf("\nbirds per frame (median frame <= %g ms):\n", s.budget_ms);
  for (const Series& series : all) {
    if (series.real_time() != real_time) continue;
    if (series.skipped) {
      std::printf("  %-16s n/a\n", series.key().c_str());
      continue;
    }
    if (series.points.empty()) {
      std::printf("  %-16s failed\n", series.key().c_str());
      continue;
    }
    if (series.birds_per_frame == 0)  // not even the smallest flock measured fitted
      std::printf("  %-16s < %s: the smallest size measured did not fit", series.key().c_str(),
                  thousands(std::min_element(series.points.begin(), series.points.end(),
                                             [](const Measurement& a, const Measurement& b) {
                                               return a.birds < b.birds;
                                             })
                                ->birds)
                      .c_str());
    else if (s.quick && series.birds_per_frame < largest_measured(series))
      std::printf(
          "  %-16s %s: the largest size measured that fitted (--quick does not search between "
          "sizes)",
          series.key().c_str(), thousands(series.birds_per_frame).c_str());
    else
      std::printf(
          "  %-16s %s%s", series.key().c_str(), thousands(series.birds_per_frame).c_str(),
          !series.lower_bound ? ""
          : s.quick ? " or more: the largest size measured fitted (--quick does not search beyond)"
                    : " or more: every size measured fitted");
    if (series.search_steps) std::printf("  [%d search steps]", series.search_steps);
    if (real_time) std::printf("  (dt %g ms, frame %g ms)", series.dt * 1000, series.budget_ms);
    std::printf("\n");
    if (!series.stopped.empty()) std::printf("  %-16s   sweep: %s\n", "", series.stopped.c_str());
  }
  // What flocking costs is measured with the frames alternated (print_flocking_cost): the two
  // searches above ran minutes apart.
}

void print_ratios(const std::vector<Ratios>& ratios) {
  for (const Ratios& r : ratios) {
    std::printf("\n%s / CPU reference, bird-steps/s (headless):\n", r.backend.c_str());
    for (const auto& [birds, ratio] : r.by_birds)
      std::printf("  %9u birds  %8.2fx\n", birds, ratio);
  }
}

void print_exponents(const Exponents& exponents) {
  std::printf(
      "\nscaling exponent b of ms per frame = a N^b (least squares over the sizes named: those\n"
      ">= 3,000 birds where two were measured, else all):\n");
  for (const auto& [series, fit] : exponents) {
    if (!fit) {
      std::printf("  %-16s n/a (fewer than 2 sizes)\n", series.c_str());
      continue;
    }
    std::string sizes;
    for (uint32_t n : fit->sizes) sizes += (sizes.empty() ? "" : ", ") + thousands(n);
    std::printf("  %-16s %.3f  (from %s birds)\n", series.c_str(), fit->b, sizes.c_str());
  }
}

void print_flocking_cost(const std::vector<Paired>& paired) {
  if (paired.empty()) return;
  std::printf(
      "\nflocking's cost, its frames alternated with those of the same flock without it (median ms "
      "a frame):\n");
  for (const Paired& p : paired)
    std::printf(
        "  %-8s %9s birds  %9.3f with, %9.3f without: flocking keeps %.0f %% of the birds per "
        "frame\n",
        p.backend.c_str(), thousands(p.birds).c_str(), p.with_ms, p.without_ms, 100.0 * p.keeps());
}

void print_summary(const Run& run, const std::vector<Ratios>& ratios, const Exponents& exponents) {
  print_birds_per_frame(run.all, run.s, false);
  print_birds_per_frame(run.all, run.s, true);
  print_flocking_cost(run.paired);
  print_ratios(ratios);
  print_exponents(exponents);
  std::printf("\n");
  for (const auto& [backend, device] : run.devices)
    std::printf("%-8s %s\n", backend.c_str(), device.c_str());
}

// Where and how the figures were taken.
nlohmann::json context_json(const Settings& s, const std::map<std::string, std::string>& devices) {
  return {
      {"date", now_iso8601()},
      {"host_name", host_name()},
      {"executable", "aeroflock bench"},
      {"cpu_model", cpu_model()},
      {"num_cpus", std::thread::hardware_concurrency()},
      {"omp_threads", omp_get_max_threads()},
      {"git_revision", AEROFLOCK_GIT_REVISION},
      {"library_build_type", AEROFLOCK_BUILD_TYPE},
      {"build_type", AEROFLOCK_BUILD_TYPE},
      {"scenario", s.scenario.name},
      {"dt", s.scenario.dt},
      {"steps_per_frame", s.scenario.steps_per_frame},
      {"budget_ms", s.budget_ms},
      {"warmup_frames", s.warmup},
      {"after_seconds", s.after},
      {"repetitions", s.repetitions},
      {"quick", s.quick},
      {"max_birds", s.max_birds},
      {"render_size", std::to_string(kRenderWidth) + "x" + std::to_string(kRenderHeight)},
      {"vtk_every", kVtkEvery},
      {"devices", devices},
  };
}

// Google Benchmark's layout (context, benchmarks) with the bench's own findings beside it.
nlohmann::json bench_json(const Run& run, const std::vector<Ratios>& ratios,
                          const Exponents& exponents) {
  nlohmann::json benchmarks = nlohmann::json::array();
  nlohmann::json birds_per_frame = nlohmann::json::object();
  nlohmann::json lower_bounds = nlohmann::json::object();
  nlohmann::json sweep_notes = nlohmann::json::object();
  for (const Series& series : run.all) {
    if (series.skipped) {
      birds_per_frame[series.key()] = "n/a";
      continue;
    }
    birds_per_frame[series.key()] =
        series.points.empty() ? nlohmann::json(nullptr) : nlohmann::json(series.birds_per_frame);
    lower_bounds[series.key()] = series.lower_bound;
    if (!series.stopped.empty()) sweep_notes[series.key()] = series.stopped;
    for (const Measurement& m : series.points)
      benchmarks.push_back({
          {"name", m.backend + "/" + m.variant + "/birds:" + std::to_string(m.birds)},
          {"run_type", "iteration"},
          {"backend", m.backend},
          {"variant", m.variant},
          {"birds", m.birds},
          {"iterations", m.iterations},
          {"real_time", m.median},
          {"p10", m.p10},
          {"p90", m.p90},
          {"time_unit", "ms"},
          {"bird_steps_per_second", m.bird_steps_per_second},
          {"device_passes_ms", m.passes ? nlohmann::json{{"grid", m.passes->grid},
                                                         {"perception", m.passes->perception},
                                                         {"steps", m.passes->steps}}
                                        : nlohmann::json(nullptr)},
          // The neighbour grid's cell the device's search ended with (it follows how far the
          // searches reach: docs/MODEL.md "The neighbour grid"); null without device passes or
          // flocking.
          {"grid_cell_cm", m.passes && m.passes->cell > 0.0 ? nlohmann::json(m.passes->cell)
                                                            : nlohmann::json(nullptr)},
      });
  }
  nlohmann::json ratios_json = nlohmann::json::array();
  for (const Ratios& r : ratios)
    for (const auto& [birds, ratio] : r.by_birds)
      ratios_json.push_back({{"backend", r.backend}, {"birds", birds}, {"vulkan_over_cpu", ratio}});
  nlohmann::json exponents_json = nlohmann::json::object();
  nlohmann::json fitted_json = nlohmann::json::object();
  for (const auto& [series, fit] : exponents) {
    exponents_json[series] = fit ? nlohmann::json(fit->b) : nlohmann::json(nullptr);
    fitted_json[series] = fit ? nlohmann::json(fit->sizes) : nlohmann::json::array();
  }
  nlohmann::json real_time = nlohmann::json::object();
  for (const Series& series : run.all)
    if (series.real_time() && !series.points.empty())
      real_time[series.key()] = {{"dt", series.dt},
                                 {"budget_ms", series.budget_ms},
                                 {"birds", series.birds_per_frame},
                                 {"lower_bound", series.lower_bound}};
  nlohmann::json flocking_cost = nlohmann::json::array();
  for (const Paired& p : run.paired)
    flocking_cost.push_back({{"backend", p.backend},
                             {"birds", p.birds},
                             {"iterations", p.iterations},
                             {"with_flocking_ms", p.with_ms},
                             {"without_flocking_ms", p.without_ms},
                             {"flocking_keeps", p.keeps()}});
  return {
      {"context", context_json(run.s, run.devices)},
      {"flocking_cost", flocking_cost},
      {"benchmarks", benchmarks},
      {"birds_per_frame", birds_per_frame},
      {"birds_per_frame_is_lower_bound", lower_bounds},
      {"birds_in_real_time", real_time},
      {"sweep_notes", sweep_notes},
      {"scaling_exponent", exponents_json},
      {"scaling_exponent_sizes", fitted_json},
      {"ratios", ratios_json},
  };
}

void write_json(const fs::path& path, const nlohmann::json& j) {
  try {
    write_text_atomically(path, j.dump(2) + "\n");
  } catch (const std::runtime_error& e) {
    throw std::runtime_error(std::string("--json: ") + e.what());
  }
}

}  // namespace

int run_bench(const BenchOptions& options) {
  check_options(options);
  const Settings s = settings(options);
  print_header(s);
  Run run(s);
  for (const std::string& backend : s.backends)
    for (const std::string& variant : s.variants)
      if (variant == "realtime")
        measure_real_time(run, backend);
      else
        run.all.push_back(measure_series(run, backend, variant));
  run.progress.clear();
  measure_flocking_cost(run);

  const std::vector<Ratios> ratios = vulkan_over_cpu(run.all, s.backends);
  const Exponents exponents = scaling_exponents(run.all);
  print_summary(run, ratios, exponents);
  if (!options.json.empty()) {
    write_json(options.json, bench_json(run, ratios, exponents));
    std::printf("json     %s\n", options.json.c_str());
  }
  if (!options.plot.empty()) {
    write_plot(options.plot, run.all, s.budget_ms);
    std::printf("plot     %s\n", options.plot.c_str());
  }
  // The outputs hold what was measured; the failed series are in sweep_notes.
  for (const std::string& f : run.failed)
    std::fprintf(stderr, "aeroflock: error: bench %s\n", f.c_str());
  return run.failed.empty() ? 0 : 1;
}

Command add_bench_command(CLI::App& app, BenchOptions& o) {
  CLI::App* cmd = app.add_subcommand(
      "bench",
      "Measure birds per frame, scaling with the flock and Vulkan against the CPU reference");
  add_scenario_argument(cmd, o.scenario);
  cmd->add_flag("--quick", o.quick, "A short smoke run: 1000 and 3000 birds, headless only");
  cmd->add_option("--json", o.json, "Write the results as JSON (Google Benchmark-like) to FILE")
      ->check(kPath);
  cmd->add_option("--plot", o.plot,
                  "Plot ms per frame and bird-steps/s against N to FILE.png (gnuplot)")
      ->check(kPath);
  add_list(cmd, "--backend,--backends", o.backends,
           "Backends: vulkan, vulkan:N (Vulkan on device N), cpu; a list (default vulkan,cpu)");
  add_list(cmd, "--variants", o.variants,
           "Variants: headless, solo, render, vtk, realtime (birds in real time at the paper's and "
           "the fast step); a list (default: all; --quick: headless)")
      ->check(one_of({"headless", "solo", "render", "vtk", "realtime"}));
  cmd->add_option("--max-birds", o.max_birds,
                  "Largest flock of the sweep (1k, 3k, 10k, ... up to it, and it)")
      ->check(kCount)
      ->capture_default_str();
  cmd->add_option("--repetitions", o.repetitions,
                  "Timed frames per measurement (default 5 quick, 15 full)")
      ->check(kCount);
  CLI::Option* after =
      cmd->add_option(
             "--after", o.after,
             "Time each flock after it has flown this long, in s (default 0: from its spawn, "
             "more compact than a flown flock)")
          ->check(kTime);
  add_device_option(cmd, o.device);
  add_step_options(cmd, o.step, "the scenario's");
  cmd->add_option("--weak-scaling", o.weak_scaling,
                  "Under mpirun: P ranks fly P x N0 birds, the flock P times as long, on the "
                  "first of --backends (docs/DISTRIBUTED.md); N0 here")
      ->check(kCount)
      ->excludes(after);
  return {cmd, [&o] { return run_bench(o); }};
}

}  // namespace aeroflock
