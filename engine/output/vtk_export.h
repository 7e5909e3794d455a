// VTK export of a run for ParaView and Python's vtk: a time series of XML PolyData files (one
// vertex per bird, its state and forces as point data), a ParaView collection (.pvd) listing them
// with their simulated times, and one polyline per bird through its saved positions.
//
// DIR/frames/flock_000000.vtp, ...  one file per saved frame, the first at t = 0. Points: the
//   birds' positions, cm, double. Point data, one tuple per bird: the arrays of kPointArrays in
//   vtk_export.cpp (docs/VTK.md "Arrays" lists them), float or double. Forces are the
//   backend's own: the step it takes next from the saved state (at t = 0 the CPU reference's).
//   Field data: TimeValue, array_units ("name: unit"), species_names and flight_state_names
//   (the codes' names), scenario, scenario_hash, dt, steps_per_frame.
// DIR/flock.pvd        the collection of the frame files with timestep = simulated time.
// DIR/trajectories.vtp one polyline per exported bird through its saved positions; point data
//                      time and speed, cell data bird_id and species; the same field data.
//
// Files are written by the exporter's AsyncWriter (output/async_writer.h), so the simulation
// waits for the disk only when the queue of frames for it is full (VtkOptions::queue_frames,
// queue_bytes). Every file is written
// to a temporary name and renamed (io/atomic_file.h): at every moment each is complete and
// readable, the .pvd lists exactly the frame files written (a frame whose .pvd cannot be written is
// removed again), and the trajectories are at most about 2.5 s of wall time behind. A write error
// stops the writer (finish() throws "cannot write PATH: why") and leaves the files so far as they
// are.
//
// A directory that holds an earlier export (earlier_export_files) is refused, or with
// VtkOptions::overwrite cleared of those files (and no others) before the run.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <glm/vec3.hpp>

#include "model/bird.h"
#include "model/scenario.h"
#include "model/simulation.h"
#include "output/async_writer.h"
#include "run/run_loop.h"

namespace aeroflock {

// A bird's saved position in a run over many ranks, sent to rank 0 for the trajectories.
struct TrajectoryPoint {
  uint32_t id = 0;
  uint32_t species = 0;
  uint64_t frame = 0;  // the saved frame's index (0: the first saved)
  glm::dvec3 position{0.0};
  double speed = 0.0;
};

// One rank's part of an export over many (dist/). The calls are collective: every rank makes them,
// from the run's thread.
struct VtkRanks {
  int rank = 0, ranks = 1;
  // The fewest frames any rank has written whole, given this rank's.
  std::function<uint64_t(uint64_t)> fewest;
  // Every rank's points on rank 0 (empty elsewhere).
  std::function<std::vector<TrajectoryPoint>(const std::vector<TrajectoryPoint>&)> gather;
};

struct VtkOptions {
  std::filesystem::path dir;
  uint32_t every = 1;         // export after every `every`-th frame (see VtkExporter::due)
  uint64_t from = 0;          // the first frame exported (0: the start); none before it
  std::string birds = "all";  // see select_birds
  enum class Compression { none, lz4, zlib } compression = Compression::lz4;
  // The point data's reals (positions and times are double always).
  enum class Precision { float32, float64 } precision = Precision::float32;
  // An earlier export in `dir` (earlier_export_files): removed before the run when true, an error
  // when false.
  bool overwrite = false;
  // Frames (at least one) and bytes of bird data queued for the writer at most, besides the frame
  // it is writing: offer() waits for room, so a slow disk slows the run instead of filling memory.
  size_t queue_frames = 4;
  size_t queue_bytes = size_t(256) << 20;
  // Test hook: called on the writer thread before each frame file is written (a slow disk).
  std::function<void()> before_frame_write;
  // Over many ranks (ranks->ranks > 1): each rank writes its birds of a frame as a piece,
  // frames/flock_NNNNNN_pRRRR.vtp, with a point array `rank` and field data `ranks`; rank 0
  // writes frames/flock_NNNNNN.pvtp of the pieces and lists it in flock.pvd once every rank has
  // written its piece, and the trajectories at the end, whole across the birds' changes of rank.
  // Only rank 0 checks and clears the directory (the others' exporters come after it did).
  std::optional<VtkRanks> ranks;
};

// The files of an earlier export in `dir`, as this exporter names them: flock.pvd,
// trajectories.vtp and frames/flock_NNNNNN.vtp (over many ranks also flock_NNNNNN.pvtp and
// flock_NNNNNN_pRRRR.vtp). Nothing else in `dir` is counted.
std::vector<std::filesystem::path> earlier_export_files(const std::filesystem::path& dir);

// The names of the point arrays of a frame file, in the order they are written.
std::vector<std::string> vtk_point_arrays();

// The birds to export, in the order given: "all"; "every:N" (birds 0, N, 2N, ...); or a list of
// ids "3,7,12" (or "ids:3,7,12"). Throws std::invalid_argument for bad syntax, an id out of
// range or listed twice.
std::vector<uint32_t> select_birds(std::string_view selection, size_t bird_count);

// A run's observer (run/run_loop.h): the start, every frame due (stepped with its forces), the
// last; it stops the run when the writer has failed, and finish() throws the writer's error.
class VtkExporter final : public RunObserver {
 public:
  // Parses the selection and creates and checks the directory (std::runtime_error naming it when
  // it cannot be created or written, or when it holds an earlier export and options.overwrite is
  // false), before the run starts; removes an earlier export with options.overwrite and a killed
  // run's temporaries. Starts the writer thread.
  VtkExporter(const VtkOptions& options, const Scenario& scenario, size_t bird_count);
  // Finishes (drains the queue) if finish() was not called; errors are then dropped.
  ~VtkExporter() override;
  VtkExporter(const VtkExporter&) = delete;
  VtkExporter& operator=(const VtkExporter&) = delete;

  // Whether frame number `frame` (Snapshot::frame: 0 the start, 1 after the first step) is one
  // to export: the start and every `options.every`-th; with `options.from`, that frame and every
  // `every`-th after it. Step those frames with record_forces.
  bool due(uint64_t frame) const { return frame >= from_ && (frame - from_) % every_ == 0; }

  // Queues the snapshot's selected birds for the writer when its frame is due and newer than the
  // last one queued (so that the newest ready snapshot can be offered after every frame, and the
  // last one at the end); returns at once unless the queue is full, then waits for room. A due
  // snapshot without forces is a logic_error. Does nothing after the writer has failed (see
  // failed()).
  void offer(const Snapshot& snapshot) { offer(snapshot, false); }
  // After each frame of `sim`: offers the newest frame ready without waiting for the device,
  // reading it only when it is wanted. After the run, offer_last: the last frame (waited for).
  // Before the run: the start (t = 0, forces from the CPU reference: Simulation::start_snapshot).
  void offer_start(Simulation& sim) {
    if (wants(0)) offer(sim.start_snapshot());
  }
  void offer_ready(Simulation& sim) {
    if (wants(sim.ready_frame())) offer(sim.ready_snapshot());
  }
  // After the run: the last frame, due or not when it was stepped with record_forces (the files
  // end where the run ends), else only when due.
  void offer_last(Simulation& sim) {
    const Snapshot last = sim.snapshot();
    if (last.forces && (!any_offered_ || last.frame > last_frame_))
      offer(last, true);
    else if (wants(last.frame))
      offer(last);
  }
  bool wants(uint64_t frame) const { return due(frame) && (!any_offered_ || frame > last_frame_); }

  // Waits for every queued frame, writes the final .pvd and trajectories and stops the writer.
  // Rethrows the writer's error, if any (std::runtime_error). Calling it again does nothing.
  void finish();

  // RunObserver: offer_start, wants_forces = due or last, offer_ready, failed, offer_last + finish.
  void start(Simulation& sim) override { offer_start(sim); }
  bool wants_forces(uint64_t frame, bool last) const override { return due(frame) || last; }
  void frame(Simulation& sim, uint64_t) override {
    offer_ready(sim);
    if (pieces()) announce_pieces();
  }
  std::string stop_reason() const override { return failed() ? "the VTK export failed" : ""; }
  void finish(Simulation& sim) override {
    offer_last(sim);
    finish();
  }
  // Over many ranks: whether this exporter writes pieces.
  bool pieces() const { return ranks_.has_value(); }

  // The writer has hit an error (finish() will throw it): the run may as well stop.
  bool failed() const;

  size_t frames_added() const { return frames_added_; }
  // The most frames (and their bytes of bird data) that waited in the queue at once.
  struct QueueUse {
    size_t frames = 0;
    size_t bytes = 0;
  };
  QueueUse queue_high_water() const;
  // The queue's bound (VtkOptions::queue_frames, at least 1).
  size_t queue_bound() const;
  const std::vector<uint32_t>& selected() const { return selected_; }
  const std::filesystem::path& dir() const { return dir_; }

 private:
  struct Writer;
  void offer(const Snapshot& snapshot, bool due_or_not);
  // Over many ranks, after each frame: rank 0 lists the frames every rank has written.
  void announce_pieces();
  void prepare_dir(const VtkOptions& options);
  void start_writer(const VtkOptions& options, const Scenario& scenario);
  std::optional<VtkRanks> ranks_;
  std::vector<bool> chosen_;  // by global id: selected (pieces)
  uint64_t announced_ = 0;    // frames rank 0 has listed (pieces)
  std::filesystem::path dir_;
  uint32_t every_ = 1;
  uint64_t from_ = 0;
  std::vector<uint32_t> selected_;
  size_t bird_count_ = 0;
  size_t frames_added_ = 0;
  uint64_t last_frame_ = 0;  // the last frame queued
  bool any_offered_ = false;
  bool finished_ = false;
  std::unique_ptr<Writer> writer_;
  std::unique_ptr<AsyncWriter> async_;  // after writer_: its jobs use it until it stops
};

}  // namespace aeroflock
