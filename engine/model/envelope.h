// The flight envelope of a species: a grid of single-bird flights (start speed, pitch and bank,
// where the target is, crosswind, take-offs, branch landings), each flown and judged. A user who
// defines a species learns from it whether the species flies (aeroflock envelope).
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "constants.h"
#include "simulation.h"
#include "species.h"
#include "touchdown.h"

namespace aeroflock {

struct EnvelopeCase {
  enum class Kind { flight, takeoff, landing } kind = Kind::flight;
  double speed = 1000.0;   // at the start, along the head, cm/s (take-off: 0)
  double pitch = 0.0;      // at the start, rad
  double bank = 0.0;       // at the start, rad (right wing down > 0)
  double rise = 0.0;       // the target (branch) above the start, cm
  double bearing = 0.0;    // the target (branch) off the start heading, rad (right > 0)
  double distance = 0.0;   // to the target (branch), horizontal, cm
  double crosswind = 0.0;  // from the bird's left at the start, cm/s
  std::string describe() const;
};

// The limits a flight keeps once settled (the envelope's judge; the convergence study's too).
inline constexpr double kSettleTime = 3.0;           // s: the limits hold from then on
inline constexpr double kBankMargin = radians(5.0);  // beyond the species' bank_max
inline constexpr double kPitchLimit = radians(60.0);
// Braking towards its branch a bird pitches up to stop (landing pigeons' body nearly vertical:
// Berg and Biewener 2010), and still so as it goes round from the flare, for kGoRoundGrace.
inline constexpr double kFlarePitchLimit = radians(85.0);
inline constexpr double kGoRoundGrace = 1.0;  // s

enum class Outcome {
  reached,       // the target passed (landing: perched) in time, within the limits throughout
  late,          // within the limits, but not there in time
  over_bank,     // banked past bank_max + 5 degrees once settled
  over_pitch,    // pitched past 60 degrees once settled
  below_ground,  // the body centre below the ground
  not_finite,    // NaN or infinity in its state
};
const char* name(Outcome o);

// One state of a flight against what a flight never does (the envelope's judge and the
// convergence study's, written once): finite; its body centre above the ground; once settled
// (t >= kSettleTime, and not perched) banked at most bank_max + kBankMargin and pitched at most
// kPitchLimit. A non-finite state is that alone; the others may come together.
struct FlightFaults {
  bool not_finite = false, below_ground = false, over_bank = false, over_pitch = false;
  bool any() const { return not_finite || below_ground || over_bank || over_pitch; }
};
FlightFaults flight_faults(const BirdState& b, const Species& species, double t,
                           double ground_height, bool flaring = false);

struct EnvelopeResult {
  EnvelopeCase c;
  Outcome outcome = Outcome::late;
  double time = 0.0;         // s: when it reached the target, or failed, or the time limit
  double worst_bank = 0.0;   // rad, largest |bank| once settled
  double worst_pitch = 0.0;  // rad, largest |pitch| once settled
  double lowest = 0.0;       // cm, lowest body centre above the ground
  // Its first touch-down (a landing's grip on the branch, or any flight's on the ground), followed
  // for kSettleWatch after it, by 30 ms frames (touchdown.h); and its go-rounds before it.
  std::optional<Touchdown> touchdown;
  size_t go_rounds = 0;
  double flaring_until = -1.0;  // s: braking, or going round from it (kGoRoundGrace), until then
};

// The grid: every combination of start speed 5-20 m/s, pitch -30..30 and bank -60..60 degrees,
// target 50 m above to 150 m below, 0 to 180 degrees off the heading, 50 m to 2 km away (crosswind
// 0, 5, 8 m/s in turn), then take-offs and branch landings from several directions and winds (a
// species that does not perch lands on the ground under the branch, from the same start).
// `quick`: a subset of short flights (tests).
std::vector<EnvelopeCase> envelope_cases(bool quick = false);

// A sample of the grid that still has every start, wind and target kind: every take-off and
// landing, and every `every`-th of the flights at most `farthest` (cm) away, in grid order.
std::vector<EnvelopeCase> envelope_sample(size_t every, double farthest);

// Cases of one crosswind as one scenario of single birds, bird k flying cases[k] (the birds never
// meet), stepped by `dt` and judged every frame (about 6 ms); flown by run/fly_envelope.h.
struct EnvelopeFlight {
  Scenario scenario;
  std::vector<BirdState> birds;
  double longest = 0.0;  // s: the longest time limit of its cases
  uint64_t frames = 0;   // the frames that reach it
};
EnvelopeFlight envelope_flight(const Species& species, const std::vector<EnvelopeCase>& cases,
                               double dt);

// Judges `r`'s bird (r.c its case) at time t: its worst bank and pitch and lowest height so far,
// and true with r.outcome and r.time once it has arrived, failed or run out of time.
bool judge_envelope(EnvelopeResult& r, const BirdState& b, const Species& species, double t,
                    double ground_height);

}  // namespace aeroflock
