#include "options.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string_view>
#include <vector>

#include <glm/geometric.hpp>

#include "io/words.h"

namespace aeroflock {
namespace {

const Names<Fidelity> kFidelities{{"paper", Fidelity::paper}, {"fast", Fidelity::fast}};
// "fixed" is the free camera, held still where --camera-eye puts it.
const Names<render::CameraMode> kCameras{{"auto", render::CameraMode::automatic},
                                         {"orbit", render::CameraMode::orbit},
                                         {"follow", render::CameraMode::follow},
                                         {"fixed", render::CameraMode::free}};

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

}  // namespace

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

const CLI::Validator kTime(
    [](std::string& text) -> std::string {
      char* end = nullptr;
      const double v = std::strtod(text.c_str(), &end);
      if (end != text.c_str() && *end == '\0' && v >= 0 && v <= kMaxDuration) return "";
      std::ostringstream message;
      message << "expected a simulated time in seconds from 0 (the start) to " << kMaxDuration
              << " (11.6 days), got " << text;
      return message.str();
    },
    "");

void add_backend_option(CLI::App* app, std::string& backend) {
  app->add_option("--backend", backend,
                  "Backend: vulkan (compute shaders) or cpu (reference, double)")
      ->check(one_of({"vulkan", "cpu"}))
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
  CLI::Option* fidelity = add_choice(app, "--fidelity", step.fidelity, kFidelities, help);
  step.fidelity_given = fidelity;
  app->add_option("--dt", step.dt,
                  "The time step in seconds, instead of --fidelity's (10 us to 10 ms)")
      ->check(kStep)
      ->excludes(fidelity);
}

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

void add_camera_options(CLI::App* app, render::CameraOptions& camera, bool& targets) {
  add_choice(app, "--camera", camera.mode, kCameras,
             "auto (frames the flock, following it), orbit (circles the flock), follow (behind "
             "one bird, --camera-bird) or fixed (--camera-eye, --camera-target); default auto");
  app->add_option("--camera-bird", camera.bird,
                  "The bird follow flies behind, and whose flock auto and orbit frame (default 0)");
  add_point_option(
      app, "--camera-eye", camera.eye,
      "With --camera fixed: where the camera is, X,Y,Z in metres (default: where auto starts)");
  add_point_option(app, "--camera-target", camera.target,
                   "With --camera fixed: what it looks at, X,Y,Z in metres (default: the flock)");
  app->add_option("--fov", camera.fov_degrees, "Vertical field of view in degrees")
      ->check(CLI::Range(5.0f, 150.0f))
      ->capture_default_str();
  add_choice(app, "--targets", targets, Names<bool>{{"on", true}, {"off", false}},
             "on or off: the target rings and the routes between them (default on)");
}

void check_camera_options(const render::CameraOptions& camera, const CLI::App& app, bool draws) {
  if (!draws)
    for (const char* name : {"--camera", "--camera-bird", "--camera-eye", "--camera-target",
                             "--fov", "--targets", "--msaa", "--size"})
      if (app.count(name) > 0)
        throw CLI::ValidationError(name, "needs --png, --frames-dir or --video");
  const std::string mode = name_of(camera.mode, kCameras);
  if (camera.mode != render::CameraMode::free && (camera.eye || camera.target))
    throw CLI::ValidationError(camera.eye ? "--camera-eye" : "--camera-target",
                               "needs --camera fixed (the camera is " + mode + ")");
  if (camera.eye && camera.target && glm::distance(*camera.eye, *camera.target) < 1.0)
    throw CLI::ValidationError("--camera-target",
                               "must differ from --camera-eye (the camera looks at its own eye)");
  if (camera.mode == render::CameraMode::free && app.count("--camera-bird") > 0)
    throw CLI::ValidationError("--camera-bird",
                               "needs --camera auto, orbit or follow (the camera is fixed)");
}

void add_flock_size_options(CLI::App* app, FlockSizeOption& size) {
  CLI::Option* birds = app->add_option("--birds", size.birds,
                                       "Birds in all, shared over the flocks in proportion, each "
                                       "flock as dense as the scenario's")
                           ->check(kCount);
  app->add_option("--flock", size.flocks,
                  "NAME=COUNT: that flock's birds (0 leaves it out), as dense as the scenario's; "
                  "repeatable")
      ->excludes(birds);
}

void FlockSizeOption::apply(Scenario& s) const {
  resize_flocks(s, flocks);
  require_birds(s, flocks);
}

std::optional<double> StepOption::value() const {
  if (fidelity_given && fidelity_given->count() > 0) return dt_of(fidelity);
  return dt;
}

void StepOption::apply(Scenario& s) const {
  if (const auto v = value()) set_dt(s, *v);
}

std::string word_list(const std::vector<std::string>& words, const char* between,
                      const char* before_last) {
  std::string out;
  for (size_t i = 0; i < words.size(); ++i)
    out += (i == 0 ? "" : i + 1 == words.size() ? before_last : between) + words[i];
  return out;
}

CLI::Validator one_of(const std::vector<std::string>& words) {
  const std::string expected = "expected " + word_list(words, ", ", " or ");
  return CLI::Validator(
      [words, expected](std::string& text) -> std::string {
        return std::find(words.begin(), words.end(), text) != words.end()
                   ? ""
                   : expected + ", got " + text;
      },
      "{" + word_list(words, ",", ",") + "}");
}

std::string unknown_command(const CLI::App& app, const std::string& word) {
  std::string list;
  std::vector<std::string_view> names;
  for (const CLI::App* sub : app.get_subcommands({})) {
    if (sub->get_name() == word) return "";
    list += (list.empty() ? "" : ", ") + sub->get_name();
    names.push_back(sub->get_name());
  }
  return "aeroflock: error: unknown command '" + word + "'" + did_you_mean(word, names) +
         "; the commands are " + list + " (aeroflock --help)";
}

std::string failure_message(const CLI::App* app, const CLI::Error& e) {
  std::string message = std::string("aeroflock: error: ") + e.what();
  const CLI::App* command = app;
  for (const CLI::App* sub : app->get_subcommands())
    if (sub->parsed()) command = sub;
  // An option the command does not take: the nearest it does. CLI11 leaves the words it could
  // not place in the command that was parsing, or in the program's own list.
  if (dynamic_cast<const CLI::ExtrasError*>(&e)) {
    std::vector<std::string> names;
    for (const CLI::Option* o : command->get_options())
      for (const std::string& name : o->get_lnames()) names.push_back("--" + name);
    const std::vector<std::string_view> words(names.begin(), names.end());
    std::string near;
    for (const CLI::App* a : {app, command})
      for (const std::string& extra : a->remaining())
        if (near.empty() && extra.starts_with("--"))
          near = closest_word(extra.substr(0, extra.find('=')), words);
    if (!near.empty()) message += " (did you mean '" + near + "'?)";
  }
  const std::string help =
      command == app ? "aeroflock --help" : "aeroflock " + command->get_name() + " --help";
  return message + "\n" + help + " lists what it takes.\n";
}

}  // namespace aeroflock
