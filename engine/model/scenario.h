// A scenario: everything a run needs, as plain data. engine/io reads it from TOML.
#pragma once

#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "species.h"
#include "world.h"

namespace aeroflock {

// A group of birds of one species on one route, spawned in a box.
struct Flock {
  std::string name;
  uint32_t species = 0;  // index into Scenario::species
  uint32_t route = 0;    // index into World::routes
  uint32_t count = 1;
  glm::dvec3 spawn_centre{0.0};  // cm
  glm::dvec3 spawn_extent{0.0};  // half-size of the spawn box, cm
  double heading = 0.0;          // rad, from +x towards +z (the right of a bird facing +x)
  double speed = 1000.0;         // initial speed along the heading, cm/s
  // Initial wingbeat frequency (Hz) and amplitude, clamped to the species' ranges; NaN: the
  // middle of the range.
  double frequency = std::numeric_limits<double>::quiet_NaN();
  double amplitude = std::numeric_limits<double>::quiet_NaN();
  bool standing = false;      // start standing on the ground, take off at takeoff_time
  double takeoff_time = 0.0;  // s
  bool random_phase = true;   // spread the wingbeat phase over the flock
  bool flocking = false;  // its birds see one another and steer by it (docs/MODEL.md "Flocking")
  bool wake = false;      // and meet the wakes of those they see (docs/MODEL.md "The wake")
};

// How far out (x, z) a scenario may place anything: 20,000 km, in cm; no length of a scenario is
// longer.
inline constexpr double kWorldRadius = 2.0e9;

// How finely a scenario is stepped: the paper's dt, or the largest dt at which every behaviour and
// envelope case still holds and positions stay within 1 % of the flight (docs/convergence.md).
enum class Fidelity { paper, fast };
inline constexpr double kPaperDt = 0.0003;     // s (paper, section 6)
inline constexpr double kFastDt = 0.002;       // s (docs/convergence.md)
inline constexpr double kFrameSeconds = 0.03;  // s: a frame, whatever the dt

// The steps a scenario may take, checked before any work (validate(), set_dt, the scenario files
// and the command line's --dt): the convergence study measured 0.1 to 10 ms and found 2 ms the
// largest at which everything holds (docs/convergence.md); below 10 us a second takes 10^5 steps
// and the rounding of t + dt grows, above 10 ms the flight is not resolved (at 1 s a step the
// birds go NaN).
inline constexpr double kMinDt = 1.0e-5;  // s
inline constexpr double kMaxDt = 0.01;    // s
// Steps a frame: a frame of the slowest step (kMaxDt) is then at most 1,000 s.
inline constexpr uint32_t kMaxStepsPerFrame = 100000;
// The longest flight a run may ask for: 11.6 days, 10^11 steps at kMinDt, frame counts far from
// any overflow.
inline constexpr double kMaxDuration = 1.0e6;  // s
// Speeds (flocks, wind, targets): below the speed of sound, as the model's incompressible air
// (eq. 1's constant density) assumes.
inline constexpr double kMaxSpeed = 34300.0;  // cm/s
// A target's oscillation period: 0 (none) or from a tenth of a second, the frame's order (a target
// moves between frames), to kMaxDuration.
inline constexpr double kMinTargetPeriod = 0.1;  // s
double dt_of(Fidelity f);
// "paper", "fast", or "custom" for any other dt.
const char* fidelity_name(double dt);
// Throws std::invalid_argument for anything but "paper" or "fast".
Fidelity parse_fidelity(const std::string& name);

struct Scenario {
  std::string name;
  std::string description;
  std::string hash;      // of the text it was read from (engine/io): which run this was
  double dt = kPaperDt;  // s
  uint32_t steps_per_frame = 100;
  double duration = 10.0;  // s
  uint64_t seed = 1;
  std::vector<Species> species;
  World world;
  std::vector<Flock> flocks;
  double frame_seconds() const { return dt * steps_per_frame; }
  // The fewest whole frames after which the simulated time, as Simulation::time() counts it
  // (steps x dt), is at least `seconds` (0 for seconds <= 0).
  uint64_t frames_reaching(double seconds) const;
};

// The whole steps of `dt` nearest to `seconds`, at least one.
uint32_t steps_in(double seconds, double dt);

// Steps `s` by `dt`, its frames kept as long as they were (steps_per_frame rounded, at least 1).
// Throws std::invalid_argument, `s` unchanged, for a dt outside [kMinDt, kMaxDt] or frames that
// would take more than kMaxStepsPerFrame steps of it.
void set_dt(Scenario& s, double dt);

// Throws std::invalid_argument naming the bound for a dt outside [kMinDt, kMaxDt]: "dt must be
// within [1e-05, 0.01] s (docs/convergence.md), got 2 s".
void check_dt(double dt);

// Throws std::invalid_argument when a standing flock's takeoff_time is more than 2^32 - 1 steps of
// `dt`: a bird's rest is counted in whole steps on both backends (BirdState::rest_steps).
// validate(), set_dt() and spawn_birds() ask it.
void check_takeoff_steps(const Scenario& s, double dt);
// Whether a standing bird's wait of `seconds` counts in whole steps of `dt` (rest_steps, 32 bits).
inline bool takeoff_counts(double seconds, double dt) { return seconds / dt < double(UINT32_MAX); }

// Whether height `y` (cm) lies above the world's ground, or on it where `on_allowed` (a target may
// lie on it; nothing may start under it): validate() and the loader ask the same.
inline bool above_ground(double y, const World& w, bool on_allowed = false) {
  return y > w.ground_height || (on_allowed && y == w.ground_height);
}

// Throws std::invalid_argument naming what is wrong (indices out of range, a dt, steps_per_frame
// or duration out of its range, a target, branch or spawn centre not above the ground, ...).
void validate(const Scenario& s);

// The same scenario moved by `offset` (cm): targets, branches, spawn boxes and the ground.
Scenario moved_by(Scenario s, const glm::dvec3& offset);

// Gives flock `index` `count` birds, its spawn box scaled (cube root) to keep its density, as
// spawn_extent() grows it; a count of 0 removes the flock. Throws std::out_of_range for a bad
// index.
void resize_flock(Scenario& s, size_t index, uint32_t count);

// The half-size of flock `f`'s spawn box for `count` birds of species `sp`: its own extent, grown
// or shrunk (cube root) when `count` differs from its count; a box of many birds that has none
// gets one, about a wing length between birds. A box grown so far that it would reach the ground
// keeps its height (90 % of its centre's height above `ground_height`) and widens instead.
glm::dvec3 spawn_extent(const Flock& f, const Species& sp, uint32_t count, double ground_height);

// Test hook (NaN quarantine, issue 16): gives flock `name` a species of its own, its own but for a
// NaN ground-effect coefficient k (eq. 15), which no scenario file may have: its birds' states
// become non-finite once they fly within a wing length of the ground. Throws
// std::invalid_argument for a flock the scenario does not have.
void make_flock_non_finite(Scenario& s, const std::string& name);

// Whether any flock of the scenario flocks.
bool any_flocking(const Scenario& s);
// Whether any flock flocks with wakes (Flock::wake).
bool any_wake(const Scenario& s);

// A leg of a flock's route (from its spawn centre to the first target, then from target to
// target, and round again on a loop) that the flock's birds cannot fly at their airspeed V
// (cruise_speed; max_speed for a flock that does not flock) for the wind at one of its ends'
// heights: across it at least as fast as they fly, or against it as fast as what holding the track
// leaves them along it (sqrt(V^2 - across^2)). They head into the wind (control.h: track_aim) and
// are blown off or back along the leg, which the run reports rather than flying the leg as if it
// could be held.
struct WindBeyondAirspeed {
  static constexpr uint32_t kSpawn = ~0u;
  uint32_t flock = 0;      // index into Scenario::flocks
  uint32_t from = kSpawn;  // index into World::targets: where the leg starts (kSpawn: the spawn)
  uint32_t target = 0;     // index into World::targets: where the leg ends
  double across = 0.0;     // cm/s: the wind across the leg, where it is least to be held
  double against = 0.0;    // cm/s: the wind against the flight along the leg, there (< 0: with)
  double height = 0.0;     // cm: the world height of that end
  double airspeed = 0.0;   // cm/s: V
};
std::vector<WindBeyondAirspeed> wind_beyond_airspeed(const Scenario& s);

}  // namespace aeroflock
