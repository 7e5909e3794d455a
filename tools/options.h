// The command line's shared parts, each said once: the checks on numbers and paths, the options
// every command that flies takes alike (the scenario, the backend, the device, the step, the
// flock's size), lists, named choices and the cameras. A command adds its own options beside them
// (add_run_command and the others).
#pragma once

#include <CLI/CLI.hpp>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "model/scenario.h"
#include "render/camera_control.h"

namespace aeroflock {

// A command: its CLI11 subcommand, and what runs it once the line is parsed (its exit status).
struct Command {
  CLI::App* app = nullptr;
  std::function<int()> run;
};

// Whole numbers from `min` to `max`: "expected an integer from 1 to 1024, got 0" (CLI11's own
// range checks name the whole double range, some 300 digits, and accept 2.5).
CLI::Validator integer_in(uint64_t min, uint64_t max);
extern const CLI::Validator kCount;     // 1 or more
extern const CLI::Validator kIndex;     // 0 or more
extern const CLI::Validator kPath;      // not empty (an unset "$OUT" would lose the output)
extern const CLI::Validator kPositive;  // > 0, finite
extern const CLI::Validator kStep;      // a time step in s (kMinDt to kMaxDt)
extern const CLI::Validator kStepMs;    // the same in ms
extern const CLI::Validator kSeconds;   // a flight's duration, at most kMaxDuration
extern const CLI::Validator kTime;      // a simulated time: 0 (the start) to kMaxDuration

// A named choice (a mode) straight into its enum: any other word is refused, "--camera: expected
// auto, orbit, follow or fixed, got bogus" (CLI11's CheckedTransformer would also take the enum's
// numbers, and names them in its message).
template <class Enum>
using Names = std::vector<std::pair<std::string, Enum>>;
// "a, b or c" (between ", ", before_last " or "); "a,b,c".
std::string word_list(const std::vector<std::string>& words, const char* between,
                      const char* before_last);
template <class Enum>
CLI::Option* add_choice(CLI::App* app, const std::string& name, Enum& value,
                        const Names<Enum>& names, const std::string& help) {
  std::vector<std::string> words;
  for (const auto& [word, e] : names) words.push_back(word);
  const std::string expected = "expected " + word_list(words, ", ", " or ");
  CLI::Validator checked(
      [names, expected](std::string& text) -> std::string {
        for (const auto& [word, e] : names)
          if (text == word) {
            text = std::to_string(static_cast<long long>(e));
            return "";
          }
        return expected + ", got " + text;
      },
      "");
  return app->add_option(name, value, help)
      ->transform(checked)
      ->option_text("{" + word_list(words, ",", ",") + "}");
}
// The word for `value` ("?" for none).
template <class Enum>
std::string name_of(Enum value, const Names<Enum>& names) {
  for (const auto& [word, e] : names)
    if (e == value) return word;
  return "?";
}

// One of `words`, as given: "expected vulkan or cpu, got gpu".
CLI::Validator one_of(const std::vector<std::string>& words);

// A list: comma-separated, or the option repeated ("--dts 0.3,2" is "--dts 0.3 --dts 2"); each
// item checked by the option's checks.
template <class T>
CLI::Option* add_list(CLI::App* app, const std::string& name, std::vector<T>& values,
                      const std::string& help) {
  return app->add_option(name, values, help)->delimiter(',')->allow_extra_args(false);
}

// The scenario, the same way everywhere: the first argument, a built-in name or a FILE.toml.
void add_scenario_argument(CLI::App* app, std::string& scenario);
// --backend vulkan|cpu.
void add_backend_option(CLI::App* app, std::string& backend);
// --device N: the Vulkan device (`aeroflock devices`).
void add_device_option(CLI::App* app, int& device);

// --fidelity paper|fast or --dt SECONDS: the step a run takes instead of its scenario's.
struct StepOption {
  Fidelity fidelity = Fidelity::paper;
  std::optional<double> dt;
  const CLI::Option* fidelity_given = nullptr;
  // The step chosen, if one was.
  std::optional<double> value() const;
  void apply(Scenario& s) const;
};
void add_step_options(CLI::App* app, StepOption& step, const char* default_is);

// --birds N or --flock NAME=COUNT (repeatable): how many birds the scenario's flocks get.
struct FlockSizeOption {
  uint32_t birds = 0;               // > 0: in all, shared over the flocks in proportion
  std::vector<std::string> flocks;  // NAME=COUNT
  // Resizes the scenario's flocks as asked (each as dense as before); throws std::runtime_error
  // naming the option for a flock the scenario lacks, a bad count, or no birds left.
  void apply(Scenario& s) const;
};
void add_flock_size_options(CLI::App* app, FlockSizeOption& size);

// --size WxH into `width` and `height`.
void add_size_option(CLI::App* app, uint32_t& width, uint32_t& height, const char* what);

// The cameras of `run` (pictures) and `view` (the window): --camera, --camera-bird, --camera-eye,
// --camera-target, --fov, --targets. check_camera_options, after parsing: options that belong to
// another camera (or, without pictures, to none, as --msaa and --size) are errors, not silently
// ignored.
void add_camera_options(CLI::App* app, render::CameraOptions& camera, bool& targets);
void check_camera_options(const render::CameraOptions& camera, const CLI::App& app, bool draws);

// "aeroflock runn": the commands there are, and the likely one (CLI11 says only that a
// subcommand is required). Empty when `word` is a command.
std::string unknown_command(const CLI::App& app, const std::string& word);

// CLI11's errors said as the program's own are, "aeroflock: error: ...", with the nearest option
// to one the command does not take (app.failure_message).
std::string failure_message(const CLI::App* app, const CLI::Error& e);

}  // namespace aeroflock
