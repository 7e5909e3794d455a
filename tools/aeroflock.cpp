// aeroflock: list the built-in scenarios, run one and summarise it, or watch it in a window.
#include <omp.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <atomic>
#include <cerrno>
#include <charconv>
#include <chrono>
#include <climits>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <limits>
#include <optional>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

#include <glm/geometric.hpp>

#include "backend.h"
#include "bench.h"
#include "bench_ranks.h"
#include "converge.h"
#include "dist/collectives.h"
#include "dist/distributed.h"
#include "dist/distributed_gpu.h"
#include "dist/mpi_session.h"
#include "dist/on_rank_zero.h"
#include "envelope.h"
#include "gpu/gpu_simulation.h"
#include "io/paths.h"
#include "io/scenario_file.h"
#include "io/summary.h"
#include "options.h"
#include "output/pictures.h"
#include "output/vtk_export.h"
#include "progress.h"
#include "render/viewer.h"
#include "run/structure.h"

namespace aeroflock {
namespace {

namespace fs = std::filesystem;

constexpr uint64_t kMaxThreads = 1024;

struct RunOptions {
  std::string scenario = "default";
  StepOption step;
  std::string backend = "vulkan";
  int device = -1;
  FlockSizeOption size;
  std::optional<double> seconds;
  std::string summary;
  int threads = 0;
  PictureOptions images;
  VtkOptions vtk;                  // vtk.dir empty: no export
  std::optional<double> vtk_from;  // s: --vtk-from
  bool strict = false;             // the first bird quarantined (NaN) is an error
  // --structure-from: measure each flock's structure (run/structure.h) from then on.
  std::optional<double> structure_from;
  std::optional<double> structure_to;
  double structure_every = 1.0;
};

// Ctrl-C (SIGINT) or SIGTERM: the run stops after the frame in progress, finishes its outputs and
// exits 128 + the signal's number, as a shell reports a death by it (130, 143). A second one ends
// the program at once, unless it comes within kSignalGrace of the first: the same stop delivered
// twice (`timeout -s INT` signals the program, then its process group).
volatile std::sig_atomic_t g_signal = 0;
constexpr int64_t kSignalGrace = 1'000'000'000;  // ns
// When the first signal came (CLOCK_MONOTONIC, ns; 0: none yet). The two signals may be handled
// in two threads at once: the first to set it is the stop, and a lock-free atomic is
// async-signal-safe.
std::atomic<int64_t> g_first_signal{0};
static_assert(std::atomic<int64_t>::is_always_lock_free);
extern "C" void on_stop_signal(int signal) {
  timespec now{};
  clock_gettime(CLOCK_MONOTONIC, &now);  // async-signal-safe, as are signal() and raise()
  const int64_t ns = int64_t(now.tv_sec) * 1'000'000'000 + now.tv_nsec;
  int64_t first = 0;
  if (g_first_signal.compare_exchange_strong(first, ns)) {
    g_signal = signal;
    return;
  }
  if (ns - first < kSignalGrace) return;  // the same stop
  std::signal(signal, SIG_DFL);
  std::raise(signal);  // delivered as the handler returns (the signal is blocked in it)
}
constexpr uint64_t kBirdFramesPerSubmission =
    20000;  // a run's frames go to the device in batches of about this

struct ViewOptions {
  std::string scenario = "default";
  StepOption step;
  FlockSizeOption size;
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

// --structure-from: a flock's figures beside what the field measures (docs/FIELD.md).
void print_structure(const FlockStructureSummary& f) {
  const StructureMean& s = f.structure;
  const StructureFigures& m = s.mean;
  std::printf("structure %-10s ", f.flock.c_str());
  if (s.samples == 0) {
    std::printf("no snapshot (fewer than two of its birds flocked at the window's times)\n");
    return;
  }
  // A figure no snapshot could measure (NaN; FlockStructure) is printed as "-".
  auto fig = [](double x) {
    char text[32];
    if (std::isnan(x)) return std::string("-");
    std::snprintf(text, sizeof text, "%.2f", x);
    return std::string(text);
  };
  std::printf("%zu snapshot%s from %.1f to %.1f s, %.0f birds each\n", s.samples,
              s.samples == 1 ? "" : "s", s.first, s.last, m.birds);
  std::printf("  nearest neighbour  %.2f m, %.2f wingspans of its %s (%.2f m)\n",
              m.median_nearest / 100, m.median_nearest_wingspans, f.species.c_str(),
              f.wingspan / 100);
  std::printf(
      "  shape              %.1f x %.1f x %.1f m; thickness / length %.2f, width / length %.2f; "
      "thinnest axis %.0f deg from vertical; motion |cos| on thickness, width, length %s %s %s\n",
      m.thickness / 100, m.width / 100, m.length / 100, m.thickness_over_length,
      m.width_over_length, degrees(m.thinnest_from_vertical), fig(m.motion_on_axes[0]).c_str(),
      fig(m.motion_on_axes[1]).c_str(), fig(m.motion_on_axes[2]).c_str());
  std::printf(
      "  border             %.0f %% of the birds; their nearest neighbour / the interior's %s\n",
      100 * m.border_fraction, fig(m.border_over_interior).c_str());
  std::printf("  anisotropy gamma(n), n = 1..%zu:", kStructureRanks);
  for (double g : m.anisotropy) std::printf(" %s", fig(g).c_str());
  std::printf(" (1/3 isotropic); nearest along the motion %s\n",
              fig(m.nearest_along_motion).c_str());
  if (const auto& v = f.formation) {
    std::printf(
        "  formation          %.1f followers a snapshot; %s %% in a V place (30-60 deg behind the "
        "wing, %.2f m across +-10 %%), %s %% of those in the leader's wingtip path\n",
        v->followers(), fig(100 * v->in_v()).c_str(), v->optimum / 100,
        fig(100 * v->in_phase()).c_str());
    std::printf(
        "                     %s %% directly behind (within a quarter span across), %s %% of "
        "those in spatial anti-phase\n",
        fig(100 * v->behind()).c_str(), fig(100 * v->anti_phase()).c_str());
    std::printf(
        "  wings' power       a head of the formation %s W, a follower %s W, one in a V place %s "
        "W\n",
        fig(v->head_power_w()).c_str(), fig(v->follower_power_w()).c_str(),
        fig(v->in_v_power_w()).c_str());
  }
}

// `asked_seconds`: --seconds, or the scenario's duration (`scenario_duration`).
void print_summary(const RunSummary& r, const std::string& flocks, double asked_seconds,
                   bool scenario_duration, const std::string& summary_path, const VtkExporter* vtk,
                   const std::vector<std::string>& images, bool interrupted) {
  const FlockStatistics& s = r.stats;
  const double rate = r.wall_seconds > 0 ? s.birds * double(r.steps) / r.wall_seconds : 0.0;
  std::printf("scenario         %s\n", r.scenario.c_str());
  std::printf("backend          %s\n", r.device.c_str());
  std::printf("birds            %llu (%llu flying, %llu perched, %llu landed, %llu with NaN)\n",
              (unsigned long long)s.birds, (unsigned long long)s.flying,
              (unsigned long long)s.perched, (unsigned long long)s.landed,
              (unsigned long long)s.nan_birds);
  std::printf("flocks           %s\n", flocks.c_str());
  const double frame_seconds = r.dt * r.steps_per_frame;
  std::printf("simulated        %.3f s (%llu steps of %g s", r.sim_seconds,
              (unsigned long long)r.steps, r.dt);
  if (!interrupted && std::abs(r.sim_seconds - asked_seconds) > 1e-9 * asked_seconds)
    std::printf("; %s%g s%s, rounded up to whole frames of %g s",
                scenario_duration ? "the scenario's " : "", asked_seconds,
                scenario_duration ? "" : " asked", frame_seconds);
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
  for (const FlockStructureSummary& f : r.structure) print_structure(f);
  for (const WindWarning& w : r.wind) std::printf("warning          %s\n", w.sentence().c_str());
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

// The VTK export's collectives over MPI_COMM_WORLD (output/vtk_export.h: VtkRanks).
VtkRanks vtk_ranks(const dist::MpiSession& mpi) {
  VtkRanks r;
  r.rank = mpi.rank();
  r.ranks = mpi.ranks();
  r.fewest = [](uint64_t mine) {
    uint64_t fewest = 0;
    MPI_Allreduce(&mine, &fewest, 1, MPI_UINT64_T, MPI_MIN, MPI_COMM_WORLD);
    return fewest;
  };
  r.gather = [](const std::vector<TrajectoryPoint>& mine) {
    try {
      return dist::gather_to(0, MPI_COMM_WORLD, mine);
    } catch (const std::runtime_error& e) {  // every rank's alike
      throw std::runtime_error(std::string("--vtk: the trajectories' saved positions: ") +
                               e.what() +
                               ": export fewer birds (--vtk-birds) or frames (--vtk-every)");
    }
  };
  return r;
}

// Rank 0's error `why` ("" for none) on every rank.
std::string from_rank_zero(std::string why) {
  int length = static_cast<int>(why.size());
  MPI_Bcast(&length, 1, MPI_INT, 0, MPI_COMM_WORLD);
  why.resize(static_cast<size_t>(length));
  MPI_Bcast(why.data(), length, MPI_CHAR, 0, MPI_COMM_WORLD);
  return why;
}

// AEROFLOCK_TEST_FAIL_RANK's observer: its run fails after frame `at`.
class FailingRank final : public RunObserver {
 public:
  explicit FailingRank(uint64_t at) : at_(at) {}
  void frame(Simulation&, uint64_t frames) override {
    if (frames >= at_) throw std::runtime_error("AEROFLOCK_TEST_FAIL_RANK: this rank fails here");
  }

 private:
  uint64_t at_;
};

// An error in the options that every rank meets alike (over many ranks rank 0 alone says it).
struct OptionError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// Directories a run's checks made (`dirs`, outer first): removed when empty unless the run began
// (`keep`), so that an error before it leaves no empty --frames-dir or --vtk behind.
struct MadeDirectories {
  std::vector<std::filesystem::path> dirs;
  bool keep = false;
  ~MadeDirectories() {
    if (keep) return;
    std::error_code ec;
    for (auto dir = dirs.rbegin(); dir != dirs.rend(); ++dir)
      std::filesystem::remove(*dir, ec);  // an empty directory only
  }
};

// The MPI session main() opened (dist/mpi_session.h): one process unless a launcher started many.
const dist::MpiSession* g_mpi = nullptr;

int run(const RunOptions& opt) {
  g_signal = 0;
  g_first_signal = 0;
  struct sigaction action {};
  action.sa_handler = on_stop_signal;
  // SA_RESTART: a write under way (a video frame into ffmpeg's pipe) goes on, not half done.
  action.sa_flags = SA_RESTART;
  sigemptyset(&action.sa_mask);  // each blocks the other in the thread that handles it
  sigaddset(&action.sa_mask, SIGINT);
  sigaddset(&action.sa_mask, SIGTERM);
  sigaction(SIGINT, &action, nullptr);
  sigaction(SIGTERM, &action, nullptr);
  // A video's ffmpeg that has died: a write error to report, not a silent death by SIGPIPE.
  std::signal(SIGPIPE, SIG_IGN);
  const bool many = g_mpi && g_mpi->ranks() > 1;
  const bool root = !g_mpi || g_mpi->root();
  if (!opt.summary.empty() && !many) check_output_path(opt.summary, "--summary", {".json"});
  if (!opt.summary.empty() && many) {
    // Rank 0 writes it: rank 0 checks it, and every rank stops alike when it cannot.
    std::string why;
    if (root) try {
        check_output_path(opt.summary, "--summary", {".json"});
      } catch (const std::runtime_error& e) {
        why = e.what();
      }
    if (why = from_rank_zero(why); !why.empty()) {
      if (root) std::cerr << "aeroflock: error: " << why << "\n";
      return 2;
    }
  }
  if (opt.threads > 0) omp_set_num_threads(opt.threads);

  Scenario scenario = load_scenario(opt.scenario);
  opt.step.apply(scenario);
  opt.size.apply(scenario);
  // Tests of the NaN quarantine: that flock's birds turn non-finite near the ground.
  if (const char* doomed = std::getenv("AEROFLOCK_TEST_NAN_FLOCK"))
    make_flock_non_finite(scenario, doomed);
  // Tests of an error on one rank: "RANK:FRAME", that rank's run fails after that frame.
  std::optional<FailingRank> failing;
  if (const char* f = std::getenv("AEROFLOCK_TEST_FAIL_RANK"); f && g_mpi)
    if (const int rank = std::atoi(f); rank == g_mpi->rank())
      failing.emplace(
          std::strtoull(std::strchr(f, ':') ? std::strchr(f, ':') + 1 : "1", nullptr, 10));
  const double seconds = opt.seconds.value_or(scenario.duration);
  const double frame_seconds = scenario.dt * scenario.steps_per_frame;
  // Whole frames, at least one: any positive duration flies. The small allowance keeps an exact
  // multiple from gaining a frame to rounding. (seconds <= kMaxDuration and frame_seconds >=
  // kMinDt: at most 10^11 frames, far inside uint64_t.)
  const auto frames =
      static_cast<uint64_t>(std::max(1.0, std::ceil(seconds / frame_seconds - 1e-9)));
  const double total_seconds = double(frames) * frame_seconds;  // whole frames
  // The structure's window, checked before any output is made.
  std::optional<StructureWindow> structure_window;
  if (opt.structure_from) {
    structure_window = StructureWindow{
        *opt.structure_from, opt.structure_to.value_or(total_seconds), opt.structure_every};
    if (opt.structure_to && structure_window->to < structure_window->from)
      throw OptionError("--structure-to must not be before --structure-from");
    if (structure_window->to < frame_seconds - 1e-9) {
      char why[160];
      std::snprintf(why, sizeof why, "--structure-to %g s is before the first frame's end at %g s",
                    structure_window->to, frame_seconds);
      throw OptionError(why);
    }
    if (structure_window->from > total_seconds + 1e-9) {
      char why[160];
      std::snprintf(why, sizeof why, "--structure-from %g s is past the run's end at %g s",
                    structure_window->from, total_seconds);
      throw OptionError(why);
    }
    if (!any_flocking(scenario) && root)
      std::fprintf(stderr,
                   "aeroflock: warning: --structure-from: no flock of %s flocks, so none is "
                   "measured (docs/FIELD.md)\n",
                   scenario.name.c_str());
  }

  RunSummary summary;
  // A leg the wind blows across faster than its birds fly is flown as it can be (into the wind):
  // said now, and in the summary.
  summary.wind = wind_warnings(scenario);
  for (const WindWarning& w : summary.wind)
    if (root) std::fprintf(stderr, "aeroflock: warning: %s\n", w.sentence().c_str());
  summary.scenario = scenario.name;
  summary.scenario_hash = scenario.hash;
  summary.dt = scenario.dt;
  summary.steps_per_frame = scenario.steps_per_frame;
  std::unique_ptr<Simulation> sim;
  dist::DistributedSimulation* ranks = nullptr;
  if (many) {
    std::unique_ptr<dist::DistributedSimulation> d;
    if (opt.backend == "cpu")
      d = std::make_unique<dist::DistributedCpuSimulation>(std::move(scenario), MPI_COMM_WORLD,
                                                           opt.size.birds);
    else  // a device each, chosen on every rank (collective)
      d = std::make_unique<dist::DistributedGpuSimulation>(
          dist::rank_device(MPI_COMM_WORLD, opt.device), std::move(scenario), MPI_COMM_WORLD,
          opt.size.birds);
    ranks = d.get();
    sim = std::move(d);
  } else {
    sim = make_simulation({opt.backend, opt.size.birds, opt.device, opt.images.any()},
                          std::move(scenario));
  }
  std::unique_ptr<Pictures> images;
  // Over many ranks the pictures and the structure see every bird, gathered on rank 0.
  std::unique_ptr<dist::GatheredFlock> gathered_flock;
  std::vector<std::unique_ptr<dist::OnRankZero>> on_rank_zero;
  if (many && (opt.images.any() || opt.structure_from))
    gathered_flock = std::make_unique<dist::GatheredFlock>(*ranks);
  // The directories the outputs' checks make: an error before the run leaves none of them empty.
  MadeDirectories made;
  const std::filesystem::path vtk_frames =
      opt.vtk.dir.empty() ? std::filesystem::path() : opt.vtk.dir / "frames";
  for (const std::filesystem::path& dir :
       {std::filesystem::path(opt.images.frames_dir), opt.vtk.dir, vtk_frames})
    if (std::error_code ec; !dir.empty() && !std::filesystem::exists(dir, ec))
      made.dirs.push_back(dir);
  if (opt.images.any() && !many) images = std::make_unique<Pictures>(opt.images, *sim);
  if (opt.images.any() && many) {
    std::string why;
    if (root) try {
        images = std::make_unique<Pictures>(opt.images, *gathered_flock);
      } catch (const gpu::Error& e) {
        why = "rank 0 cannot draw the " + std::to_string(ranks->total_birds()) +
              " birds of the run (" + e.what() +
              "): export them with --vtk and draw them with ParaView (docs/ANALYSIS.md)";
      } catch (const std::runtime_error& e) {
        why = e.what();
      }
    if (why = from_rank_zero(why); !why.empty()) {
      if (root) std::cerr << "aeroflock: error: " << why << "\n";
      return 2;
    }
    // Only the frames directory and the video look at every frame; a PNG at the last alone.
    std::function<bool(double)> reads;
    if (!opt.images.frames_dir.empty() || !opt.images.video.empty())
      reads = [](double) { return true; };
    on_rank_zero.push_back(
        std::make_unique<dist::OnRankZero>(*gathered_flock, images.get(), reads));
  }
  summary.backend = sim->backend();
  summary.device = describe_device(*sim);

  const size_t birds = ranks ? ranks->total_birds() : sim->bird_count();
  // Before the run: a directory that cannot be written fails now.
  std::unique_ptr<VtkExporter> vtk;
  if (!opt.vtk.dir.empty()) {
    sim->prepare_forces();  // the exported forces: a flock whose forces do not fit fails now
    VtkOptions vo = opt.vtk;
    // --vtk-from: the first whole frame at or after that time (a long run's export starts late).
    if (opt.vtk_from) vo.from = uint64_t(std::ceil(*opt.vtk_from / frame_seconds - 1e-9));
    if (many) vo.ranks = vtk_ranks(*g_mpi);
    auto make = [&] {
      try {
        vtk = std::make_unique<VtkExporter>(vo, sim->scenario(), birds);
      } catch (const std::invalid_argument& e) {
        throw std::runtime_error(std::string("--vtk-birds: ") + e.what());
      }
    };
    if (!many) {
      make();
    } else {
      // Rank 0 checks and clears the directory; the others' exporters only once it has.
      std::string why;
      if (root) try {
          make();
        } catch (const std::runtime_error& e) {
          why = e.what();
        }
      if (why = from_rank_zero(why); !why.empty()) {
        if (root) std::cerr << "aeroflock: error: " << why << "\n";
        return 2;
      }
      if (!root) make();
    }
  }
  // The run's observers, finished in this order: the progress line's last, --strict's error, the
  // pictures, the VTK files (the first error is the summary's).
  RunProgress progress(total_seconds);
  StrictCheck strict;
  std::vector<RunObserver*> observers;
  if (root) observers.push_back(&progress);
  if (opt.strict) observers.push_back(&strict);
  if (failing) observers.push_back(&*failing);
  if (images && !many) observers.push_back(images.get());
  if (many && opt.images.any()) observers.push_back(on_rank_zero.back().get());
  if (vtk) observers.push_back(vtk.get());
  std::unique_ptr<StructureObserver> structure;
  if (structure_window) {
    structure = std::make_unique<StructureObserver>(*structure_window);
    if (!many) {
      observers.push_back(structure.get());
    } else {
      // Every rank has the observer, to decide alike which frames it measures (the others see
      // no birds: their figures are not used).
      StructureObserver* s = structure.get();
      on_rank_zero.push_back(std::make_unique<dist::OnRankZero>(
          *gathered_flock, s, [s](double t) { return s->due(t); }));
      observers.push_back(on_rank_zero.back().get());
    }
  }
  RunLimits limits;
  limits.frames = frames;
  limits.signal = &g_signal;
  // Without pictures or exports nothing reads a frame: a small flock's frames go to the device
  // several at a time (Simulation::step_frames), about kBirdFramesPerSubmission bird-frames each.
  limits.batch = std::clamp<uint64_t>(kBirdFramesPerSubmission / std::max<size_t>(birds, 1), 1,
                                      gpu::kFramesPerSubmission);
  // Over many ranks every rank steps one frame a turn, whatever its own observers read: the
  // ranks' frames and their exchanges must pair up (and the CPU gains nothing from batches).
  if (many) limits.batch = 1;
  made.keep = true;
  const RunResult run = run_frames(*sim, observers, limits);
  const bool interrupted = run.end == RunResult::End::signal;
  std::vector<std::string> errors = run.errors;

  summary.wall_seconds = run.wall_seconds;
  summary.steps = sim->steps();
  summary.sim_seconds = sim->time();
  summary.interrupted = interrupted;
  // Over many ranks the summary is rank 0's, of every rank's birds; the others say only their
  // errors, and every rank exits alike.
  std::vector<BirdState> gathered;
  if (ranks) {
    gathered = ranks->gather();
    for (const dist::RankShare& r : ranks->gather_shares())
      summary.ranks.push_back({r.rank, r.birds, r.ghosts, r.traffic.migrants_sent,
                               r.traffic.ghosts_sent, r.traffic.bytes_sent, r.traffic.rebalances,
                               r.traffic.seconds});
    int mine = run.errors.empty() ? 0 : 1, any = 0;
    MPI_Allreduce(&mine, &any, 1, MPI_INT, MPI_MAX, MPI_COMM_WORLD);
    if (!root) {
      for (const std::string& e : run.errors)
        std::cerr << "aeroflock: error (" << g_mpi->describe() << "): " << e << "\n";
      return any ? 2 : interrupted ? 128 + run.signal : 0;
    }
    if (any && errors.empty()) errors.push_back("another rank stopped with an error (above)");
  }
  const std::vector<BirdState>& birds_now = ranks ? gathered : sim->birds();
  summary.stats = flock_statistics(birds_now, sim->scenario().species);
  summary.flocking = flocking_summary(sim->scenario(), birds_now);
  if (structure) summary.structure = structure->flocks();
  summary.quarantined = quarantined_birds(birds_now, sim->scenario().dt, kQuarantinedListed);
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
  print_summary(summary, flock_counts(sim->scenario(), birds_now), seconds, !opt.seconds,
                summary_written, vtk.get(), images ? images->written() : std::vector<std::string>{},
                interrupted);
  report_quarantined(birds_now, summary.quarantined);
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
  opt.size.apply(scenario);
  std::cout << render::viewer_keys() << std::endl;
  render::ViewerOptions viewer = opt.viewer;
  viewer.birds = opt.size.birds;
  return render::run_viewer(std::move(scenario), viewer);
}

const Names<VtkOptions::Compression> kCompressions{{"none", VtkOptions::Compression::none},
                                                   {"lz4", VtkOptions::Compression::lz4},
                                                   {"zlib", VtkOptions::Compression::zlib}};
const Names<VtkOptions::Precision> kPrecisions{{"float", VtkOptions::Precision::float32},
                                               {"double", VtkOptions::Precision::float64}};

Command add_run_command(CLI::App& app, RunOptions& opt) {
  CLI::App* cmd = app.add_subcommand("run", "Run a scenario and summarise it");
  add_scenario_argument(cmd, opt.scenario);
  add_backend_option(cmd, opt.backend);
  add_device_option(cmd, opt.device);
  add_flock_size_options(cmd, opt.size);
  cmd->add_option("--seconds", opt.seconds,
                  "Simulated seconds (default: the scenario's; at most 1e6)")
      ->check(kSeconds);
  add_step_options(cmd, opt.step, "the scenario's");
  cmd->add_option("--summary", opt.summary, "Write the run summary to this JSON file")
      ->check(kPath);
  cmd->add_option("--threads", opt.threads, "CPU threads (default: all, as OpenMP chooses)")
      ->check(integer_in(1, kMaxThreads));

  PictureOptions& images = opt.images;
  cmd->add_option("--png", images.png, "Render the last frame to this PNG (headless)")
      ->check(kPath);
  CLI::Option* frames_dir =
      cmd->add_option("--frames-dir", images.frames_dir, "Render frames to DIR/frame_NNNNNN.png")
          ->check(kPath);
  cmd->add_option("--every", images.every, "With --frames-dir: every K-th frame")
      ->check(kCount)
      ->needs(frames_dir);
  CLI::Option* video =
      cmd->add_option("--video", images.video, "Render the run to FILE.mp4 (needs ffmpeg)")
          ->check(kPath);
  cmd->add_option("--fps", images.fps,
                  "With --video: frames per simulated second (default: one a frame, real time)")
      ->check(kPositive)
      ->needs(video);
  add_camera_options(cmd, images.camera, images.targets);
  cmd->add_option("--msaa", images.msaa, "Samples a pixel: 1 (none), 2, 4 or 8 (default 4)")
      ->check(one_of({"1", "2", "4", "8"}));
  add_size_option(cmd, images.width, images.height, "Image size WxH (default 1280x720)");

  CLI::Option* vtk =
      cmd->add_option(
             "--vtk", opt.vtk.dir,
             "Write VTK files for ParaView/Python to DIR: frames, flock.pvd, trajectories.vtp")
          ->check(kPath);
  cmd->add_option("--vtk-every", opt.vtk.every,
                  "With --vtk: every K-th frame besides the first and the last (default 1)")
      ->check(kCount)
      ->needs(vtk);
  cmd->add_option("--vtk-from", opt.vtk_from,
                  "With --vtk: start the export at this simulated time in seconds (default 0: the "
                  "start); then every --vtk-every-th frame, and the last")
      ->check(kTime)
      ->needs(vtk);
  cmd->add_option("--vtk-birds", opt.vtk.birds,
                  "With --vtk: all, every:N or a list of bird ids like 3,7,12 (default all)")
      ->capture_default_str()
      ->needs(vtk);
  add_choice(cmd, "--vtk-compression", opt.vtk.compression, kCompressions,
             "With --vtk: none, lz4 or zlib (default lz4)")
      ->needs(vtk);
  add_choice(cmd, "--vtk-precision", opt.vtk.precision, kPrecisions,
             "With --vtk: float or double, the point data's precision (positions and times are "
             "double always; default float, the Vulkan backend's own)")
      ->needs(vtk);
  cmd->add_flag("--overwrite", opt.vtk.overwrite,
                "With --vtk: replace an earlier run's export in DIR (its flock.pvd, "
                "trajectories.vtp and frames/flock_*.vtp, no other file); without it such a DIR "
                "is an error")
      ->needs(vtk);
  CLI::Option* structure =
      cmd->add_option("--structure-from", opt.structure_from,
                      "Measure each flock that flocks as the field measures starlings (nearest "
                      "neighbours, principal axes, border, anisotropy; docs/FIELD.md) from this "
                      "simulated time in seconds on (0: from the first frame), and print and "
                      "summarise the means")
          ->check(kTime);
  cmd->add_option("--structure-to", opt.structure_to,
                  "With --structure-from: until this simulated time (default: the end)")
      ->check(kTime)
      ->needs(structure);
  cmd->add_option("--structure-every", opt.structure_every,
                  "With --structure-from: seconds of simulated time between snapshots (default 1)")
      ->check(kPositive)
      ->needs(structure);
  cmd->add_flag(
      "--strict", opt.strict,
      "A bird whose state becomes non-finite (NaN) stops the run with an error (exit 2), its "
      "outputs closed; without it the bird is quarantined (frozen, reported) and the rest fly on");
  return {cmd, [&opt, cmd] {
            check_camera_options(opt.images.camera, *cmd, opt.images.any());
            return run(opt);
          }};
}

Command add_view_command(CLI::App& app, ViewOptions& opt) {
  CLI::App* cmd = app.add_subcommand("view", "Watch a scenario in a window");
  add_scenario_argument(cmd, opt.scenario);
  add_device_option(cmd, opt.viewer.device);
  add_flock_size_options(cmd, opt.size);
  add_step_options(cmd, opt.step, "the scenario's");
  add_size_option(cmd, opt.viewer.width, opt.viewer.height, "Window size WxH (default 1280x720)");
  cmd->add_flag("--paused", opt.viewer.paused, "Start with the simulation paused");
  add_camera_options(cmd, opt.viewer.camera, opt.viewer.targets);
  cmd->add_option(
         "--msaa", opt.viewer.msaa,
         "Samples a pixel: 1 (none), 2, 4 or 8 (default 4; 1 on a CPU device such as lavapipe)")
      ->check(one_of({"1", "2", "4", "8"}));
  cmd->add_option("--frames", opt.viewer.frames, "Close the window after N frames (for tests)")
      ->check(kCount);
  return {cmd, [&opt, cmd] {
            check_camera_options(opt.viewer.camera, *cmd, true);
            return view(opt);
          }};
}

Command add_scenarios_command(CLI::App& app, std::string& show) {
  CLI::App* cmd = app.add_subcommand("scenarios", "List the built-in scenarios");
  cmd->add_option("--show", show,
                  "Print a built-in scenario's TOML (to start one's own from: "
                  "aeroflock scenarios --show default > mine.toml)");
  return {cmd, [&show] { return list_scenarios(show); }};
}

Command add_devices_command(CLI::App& app) {
  CLI::App* cmd = app.add_subcommand("devices", "List the Vulkan devices");
  return {cmd, [] {
            for (const std::string& line : vulkan_devices()) std::cout << line << "\n";
            return 0;
          }};
}

}  // namespace
}  // namespace aeroflock

int main(int argc, char** argv) {
  using namespace aeroflock;
  // Under mpirun every rank runs this; without, MPI is never initialised.
  const dist::MpiSession mpi(&argc, &argv);
  g_mpi = &mpi;
  CLI::App app{"aeroflock: real-time bird flight simulation based on aerodynamics"};
  app.require_subcommand(1);
  app.failure_message(failure_message);
  std::string show;
  RunOptions run;
  ViewOptions view;
  BenchOptions bench;
  EnvelopeOptions envelope;
  ConvergeOptions converge;
  const std::vector<Command> commands{
      add_scenarios_command(app, show),   add_devices_command(app),
      add_run_command(app, run),          add_view_command(app, view),
      add_bench_command(app, bench),      add_envelope_command(app, envelope),
      add_converge_command(app, converge)};

  if (argc > 1 && argv[1][0] != '-')
    if (const std::string message = unknown_command(app, argv[1]); !message.empty()) {
      std::cerr << message << "\n";
      return 2;
    }
  // Over many ranks a mistake in the command line or the scenario is every rank's alike: rank 0
  // says it, once. Any other error may be one rank's alone: it says it, and ends every rank.
  auto said_once = [&](int code, auto&& say) {
    if (mpi.root()) say();
    return code;
  };
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return mpi.root() ? (app.exit(e) == 0 ? 0 : 2) : (e.get_exit_code() == 0 ? 0 : 2);
  }
  try {
    // Under mpirun: `run`, and `bench --weak-scaling`; the rest runs on one process.
    if (bench.weak_scaling > 0) {
      if (!mpi.active())
        throw std::runtime_error("--weak-scaling runs under mpirun (mpirun -n P ...)");
      return run_weak_scaling(bench, mpi);
    }
    if (mpi.ranks() > 1)
      for (const Command& c : commands)
        if (c.app->parsed() && c.app->get_name() != "run")
          return said_once(2, [&] {
            std::cerr << "aeroflock: error: " << c.app->get_name()
                      << " runs on one process: under mpirun, run and bench --weak-scaling do\n";
          });
    for (const Command& c : commands)
      if (c.app->parsed()) return c.run();
    return 2;
  } catch (const CLI::ParseError& e) {  // a check made once the whole line is read
    return mpi.root() ? (app.exit(e) == 0 ? 0 : 2) : (e.get_exit_code() == 0 ? 0 : 2);
  } catch (const ScenarioError& e) {
    // Already "FILE:LINE:COLUMN: error: ...", but for a name that is no scenario.
    const std::string_view what = e.what();
    return said_once(2, [&] {
      std::cerr << (what.find(": error: ") == what.npos ? "aeroflock: error: " : "") << what
                << "\n";
    });
  } catch (const OptionError& e) {
    return said_once(2, [&] { std::cerr << "aeroflock: error: " << e.what() << "\n"; });
  } catch (const std::exception& e) {
    if (mpi.ranks() > 1) {
      std::cerr << "aeroflock: error (" << mpi.describe() << "): " << e.what() << "\n";
      mpi.abort(2);
    }
    std::cerr << "aeroflock: error: " << e.what() << "\n";
    return 2;
  }
}
