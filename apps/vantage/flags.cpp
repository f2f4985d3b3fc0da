// Flags onto the pipeline's option structs: each flag writes its field, CLI11's validators and
// transformers check what they can, the pipeline's Validate() the rest.
#include <fmt/format.h>
#include <spdlog/spdlog.h>
#include <unistd.h>

#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <limits>
#include <map>
#include <memory>
#include <mutex>
#include <set>
#include <string_view>
#include <type_traits>
#include <variant>

#include "commands.hpp"
#include "vantage/selection_options.hpp"

namespace vantage::cli {
namespace {

// A whole number in decimal from `low` to `high`, parsed here exactly: CLI11 reads "-1" into an
// unsigned as 2^64 - 1 and clamps 18446744073709551616 to 2^64 - 1 (issue 15), and a double
// would round large ones. "" when it is one, else what is wrong. The value comes trimmed
// (PlainValueValidator's transform runs first), a leading + allowed.
std::string WholeNumberProblem(std::string_view text, uint64_t low, uint64_t high) {
  const std::string wanted = fmt::format("give a whole number from {} to {}", low, high);
  std::string_view digits = text;
  if (!digits.empty() && digits.front() == '+') digits.remove_prefix(1);
  const bool negative = !digits.empty() && digits.front() == '-';
  if (negative) digits.remove_prefix(1);
  uint64_t value = 0;
  const char* end = digits.data() + digits.size();
  const auto [stop, error] = std::from_chars(digits.data(), end, value);
  if (stop != end || digits.empty() || (error != std::errc() && error != std::errc::result_out_of_range))
    return fmt::format("'{}' is not a whole number — {}", text, wanted);
  if (negative && (value != 0 || error != std::errc()))
    return fmt::format("{} is negative — {}", text, wanted);
  if (error == std::errc::result_out_of_range || value > high)
    return fmt::format("{} is too large — {}", text, wanted);
  if (value < low) return fmt::format("{} is out of range — {}", text, wanted);
  return {};
}

// --seed, --calibration-overlap: any unsigned 64-bit number.
std::string NonNegativeWholeNumber(std::string& text) {
  return WholeNumberProblem(text, 0, std::numeric_limits<uint64_t>::max());
}

// --random-roll, --interference: CLI11's words for a bool (true/false, yes/no, on/off, 1/0);
// anything else is named with the two to give, not CLI11's "Could not convert".
std::string TrueOrFalse(std::string& text) {
  bool value = false;
  if (!CLI::detail::lexical_cast(text, value))
    return fmt::format("'{}' is not true or false — give true or false", text);
  return {};
}

// --max-memory: a positive, finite number of MiB.
std::string PositiveMiB(std::string& text) {
  double value = 0;
  if (!CLI::detail::lexical_cast(text, value) || !std::isfinite(value) || value <= 0)
    return fmt::format("{} is not a positive number of MiB — give e.g. --max-memory 4096", text);
  return {};
}

// --max-seconds: a finite number of seconds >= 0 (0: no limit).
std::string NonNegativeSeconds(std::string& text) {
  double value = 0;
  if (!CLI::detail::lexical_cast(text, value) || !std::isfinite(value) || value < 0)
    return fmt::format("{} is not a number of seconds >= 0 — give e.g. --max-seconds 3600 "
                       "(0: no limit)",
                       text);
  return {};
}

// An enum flag: the library's own parser names the valid values (its message, unchanged), then
// CLI11's CheckedTransformer maps the name onto the enum.
template <typename Enum>
void AddEnumOption(CLI::App* app, const std::string& flag, std::optional<Enum>* value,
                   const std::vector<Enum>& values, std::string (*name)(Enum),
                   Enum (*parse)(const std::string&), const std::string& help) {
  std::map<std::string, Enum> by_name;
  for (const Enum v : values) by_name[name(v)] = v;
  const auto check = [parse](std::string& text) -> std::string {
    try {
      parse(text);
    } catch (const InputError& e) {
      return e.what();
    }
    return {};
  };
  // CLI11 runs the transformer added last first: the name check, then the mapping.
  app->add_option(flag, *value, help)
      ->transform(CLI::CheckedTransformer(by_name).description(""))
      ->transform(CLI::Validator(check, ""))
      ->type_name("NAME");
}

}  // namespace

CLI::Validator WholeNumberValidator() {
  return CLI::Validator(NonNegativeWholeNumber, "0 or more");
}

CLI::Validator OutPathValidator() {
  return CLI::Validator(
      [](const std::string& text) -> std::string {
        if (!text.empty()) return {};
        return "the path is empty — give the file or folder to write, e.g. results";
      },
      "");
}

CLI::Validator PlainValueValidator(ValueKind kind) {
  return CLI::Validator(
      [kind](std::string& text) -> std::string {
        if (kind != ValueKind::kText) {
          const size_t first = text.find_first_not_of(" \t");
          text = first == std::string::npos
                     ? std::string()
                     : text.substr(first, text.find_last_not_of(" \t") - first + 1);
        }
        if (text.empty()) return "the value is empty — give one, or leave the option out";
        if (kind != ValueKind::kWholeNumber) return {};
        std::string_view digits(text);
        if (!digits.empty() && (digits.front() == '-' || digits.front() == '+'))
          digits.remove_prefix(1);
        if (digits.size() > 1 && digits.front() == '0')
          return fmt::format("'{}' is not a whole number in decimal (a leading 0 reads as octal, "
                             "0x as hex) — write it in decimal without leading zeros",
                             text);
        return {};
      },
      "");
}

CLI::Validator NumberFrom(double low, double high, ValueKind kind) {
  const std::string help = fmt::format("in [{} - {}]", low, high);  // as CLI::Range's help
  if (kind == ValueKind::kWholeNumber) {
    // Whole numbers are parsed as unsigned: their ranges start at 0 or above.
    VANTAGE_CHECK(low >= 0 && low <= high);
    return CLI::Validator(
        [=](std::string& text) {
          return WholeNumberProblem(text, static_cast<uint64_t>(low), static_cast<uint64_t>(high));
        },
        help);
  }
  return CLI::Validator(
      [=](std::string& text) -> std::string {
        const std::string wanted = fmt::format("give a number from {} to {}", low, high);
        double value = 0;
        if (!CLI::detail::lexical_cast(text, value) || std::isnan(value))
          return fmt::format("'{}' is not a number — {}", text, wanted);
        if (value < low || value > high) return fmt::format("{} is out of range — {}", text, wanted);
        return {};
      },
      help);
}

OutputGuard RefuseOutputOverInput(const std::string& out, const std::vector<std::string>& inputs) {
  CheckOutputFile(out);  // a device, a pipe or a folder: refused before any work
  std::error_code error;
  for (const std::string& input : inputs) {
    // equivalent() sees through links and other spellings of one path; false when out is new.
    if (std::filesystem::equivalent(out, input, error))
      throw InputError(fmt::format("--out: '{}' names the input '{}' of this run — writing it would "
                                   "replace that input; choose another file",
                                   out, input));
  }
  return OutputGuard({{"--out", out}});
}

std::function<void(size_t, size_t)> ProgressBar(const std::string& label) {
  if (!::isatty(STDERR_FILENO) || spdlog::get_level() > spdlog::level::info) return {};
  const auto start = std::chrono::steady_clock::now();
  auto mutex = std::make_shared<std::mutex>();
  return [label, start, mutex](size_t done, size_t total) {
    std::lock_guard<std::mutex> lock(*mutex);
    const double elapsed =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const double rate = elapsed > 0 ? static_cast<double>(done) / elapsed : 0.0;
    const double eta = rate > 0 ? static_cast<double>(total - done) / rate : 0.0;
    const int width = 30;
    const int filled = total ? static_cast<int>(width * done / total) : width;
    std::fprintf(stderr, "\r%s [%s%s] %zu/%zu  %.1f/s  ETA %.1fs ", label.c_str(),
                 std::string(static_cast<size_t>(filled), '#').c_str(),
                 std::string(static_cast<size_t>(width - filled), '.').c_str(), done, total, rate,
                 eta);
    if (done == total) std::fprintf(stderr, "\n");
    std::fflush(stderr);
  };
}

RunSettings GivenSettings(const CLI::App& command) {
  // What only says where: two nodes may hold the same files at other paths.
  static const std::set<std::string> kWhere = {"--out", "--shard", "--model-path",
                                               "--resource-path", "--package-path"};
  RunSettings settings = {"command " + command.get_name()};
  for (const CLI::Option* option : command.get_options()) {
    if (option->count() == 0 || option->get_positional()) continue;
    const std::string name = !option->get_lnames().empty() ? "--" + option->get_lnames().front()
                                                           : "-" + option->get_snames().front();
    if (kWhere.count(name)) continue;
    std::string setting = name;
    if (option->get_expected_min() > 0)  // a flag has no value to show
      for (const std::string& value : option->results()) setting += " " + value;
    settings.push_back(setting);
  }
  return settings;
}

void AddSourceFlags(CLI::App* app, SceneInput* scene) {
  // Each folder is checked by LoadOptions::Validate, as the Python module's are.
  app->add_option("--model-path", scene->load.model_paths, "folder of Gazebo models (repeatable)");
  app->add_option("--resource-path", scene->load.resource_paths,
                  "folder of Gazebo resources, e.g. materials (repeatable)");
  app->add_option("--package-path", scene->load.package_paths,
                  "folder where a URDF's package://PKG paths are found: holding PKG/, or an "
                  "install prefix holding share/PKG/ (repeatable; then ROS_PACKAGE_PATH, "
                  "AMENT_PREFIX_PATH)");
  app->add_option("--target", scene->load.targets,
                  "target object/model name, overrides the scene (repeatable)");
}

void AddSceneFlags(CLI::App* app, SceneInput* scene, bool scene_positional) {
  if (scene_positional)
    app->add_option("scene", scene->path,
                    "scene: .yaml (docs/scene-format.md) or Gazebo .world/.sdf")
        ->required();
  AddSourceFlags(app, scene);
  app->add_option("--cell-size", scene->load.cell_size,
                  "voxel cell size F in metres (default: the scene's)");
  app->add_option("--seed", scene->seed, "random seed (default: the scene's, else 1)");
  app->add_option_function<std::vector<double>>(
         "--observation-point",
         [scene](const std::vector<double>& p) { scene->observation_point = Vec3(p[0], p[1], p[2]); },
         "x y z [m] every candidate looks at (default: the scene's)")
      ->expected(3);
  app->add_option("--random-roll", scene->random_roll,
                  "true|false: random roll after the look-at (default: the scene's)")
      ->check(CLI::Validator(TrueOrFalse, "true|false"));
  app->add_flag_callback("--exposed-only", [scene] { scene->exposed_only = true; },
                         "coverage counts only exposed surface: cells resting on or enclosed by "
                         "other geometry, which no viewpoint sees, leave R (default: every cell, "
                         "the paper's metric)");
}

void AddObserveFlags(CLI::App* app, ObserveOptions* observe, RunLimits* limits) {
  app->add_flag_callback("--no-cull", [observe] { observe->cull = false; },
                         "trace every pixel (slower; same result)");
  // The sensor model (issue 43; docs/sensor-models.md, Sensor model).
  CLI::Option* ideal = app->add_flag_callback(
      "--ideal", [observe] { observe->physical = false; },
      "the paper's ideal pinhole: every pixel whose ray first meets a target counts (default for "
      "a Gazebo world of the original system)");
  CLI::Option* physical = app->add_flag_callback(
      "--physical", [observe] { observe->physical = true; },
      "the physical sensor model: a pixel counts only where the type's projector or second "
      "imager sees the point and stereo can match it (default for other scenes)");
  ideal->excludes(physical);
  physical->excludes(ideal);
  app->add_option("--max-incidence", observe->quality.max_incidence_deg,
                  "quality: a pixel counts only when its ray meets the surface within this many "
                  "degrees of the normal (0-90]");
  app->add_option_function<double>(
      "--max-depth-noise",
      [observe](double mm) {
        // A positive value so small that it is 0 in metres was refused as "0" (issue 15).
        if (mm > 0 && !(mm / 1000.0 > 0))
          throw InputError(fmt::format("--max-depth-noise {:g} mm is too small to hold in metres "
                                       "— give a positive number of millimetres, e.g. 2",
                                       mm));
        observe->quality.max_depth_noise = mm / 1000.0;
      },
      "quality: a pixel counts only when its sensor's depth noise sigma(z) is at most this many "
      "mm (docs/sensor-models.md)");
  app->add_option("--max-memory", limits->max_memory_mib,
                  "refuse runs estimated above this many MiB (default: 75 % of RAM)")
      ->check(CLI::Validator(PositiveMiB, "MiB > 0"));
  app->add_option("--max-seconds", limits->max_seconds,
                  "refuse runs whose ray casting is estimated above this many seconds, before "
                  "any ray (default 0: no limit; the estimate is logged)")
      ->check(CLI::Validator(NonNegativeSeconds, "s >= 0"));
}

void AddSelectionFlags(CLI::App* app, SelectionRequest* request) {
  for (const SelectionOption& option : SelectionOptionTable()) {
    const std::string names(option.cli_names);
    const std::string help(option.help);
    std::visit(
        [&](auto pointer) {
          auto& value = request->*pointer;
          using Value = std::decay_t<decltype(value)>;
          if constexpr (std::is_same_v<Value, bool>) {
            app->add_flag(names, value, help);
          } else if constexpr (std::is_same_v<Value, std::optional<Method>>) {
            AddEnumOption<Method>(app, names, &value,
                                  {Method::kBest, Method::kRansac, Method::kGreedy,
                                   Method::kLocal, Method::kExact, Method::kAll},
                                  MethodName, ParseMethod, help);
          } else if constexpr (std::is_same_v<Value, std::optional<OverStates>>) {
            AddEnumOption<OverStates>(app, names, &value, OverStatesValues(), OverStatesName,
                                      ParseOverStates, help);
          } else {
            app->add_option(names, value, help);
          }
        },
        option.member);
  }
  AddConstraintFlags(app, &request->constraints);
}

void AddPointDensityFlags(CLI::App* app, std::optional<int64_t>* min_points,
                          std::optional<double>* min_density) {
  // The rows of the selection options' table, onto evaluate's own fields too.
  app->add_option("--min-points", *min_points,
                  std::string(SelectionOptionOfKeyword("min_points").help));
  app->add_option("--min-density", *min_density,
                  std::string(SelectionOptionOfKeyword("min_density").help));
}

void AddConstraintFlags(CLI::App* app, ConstraintOptions* c) {
  app->add_option("--interference", c->interference,
                  "true|false: two chosen structured-light or time-of-flight sensors may not "
                  "light up more than --interference-overlap of each other's observed cells "
                  "(default: false; an --interference-overlap turns it on; docs/constraints.md)")
      ->check(CLI::Validator(TrueOrFalse, "true|false"));
  app->add_option("--interference-overlap", c->interference_overlap,
                  "interference: the largest share of the smaller of two projecting sensors' "
                  "observed cells they may both light up, fraction 0..1 (default 0.1)");
  app->add_option("--calibration-overlap", c->calibration_overlap,
                  "calibration: the chosen sensors must form a connected graph, an edge joining "
                  "two that see at least this many common cells of the targets");
  app->add_option("--calibration-overlap-frac", c->calibration_overlap_frac,
                  "calibration: as --calibration-overlap, an edge needing this share (0..1] of "
                  "the smaller of the two sensors' observed cells");
}

void AddArmTourFlags(CLI::App* app, ArmTourOptions* arm) {
  app->add_option("--cycle-time", arm->cycle_time,
                  "a camera on an arm: the most coverage (greedy) whose tour, home to home with "
                  "each view's acquisition, fits this many seconds");
  app->add_option("--joint-speed", arm->joint_speed,
                  "a camera on an arm: every joint's speed [rad/s or m/s] for the tour (default: "
                  "each joint's URDF <limit velocity>)");
  app->add_option("--frames", arm->frames,
                  "a camera on an arm: frames taken at each view (acquisition = frames / fps)")
      ->check(NumberFrom(1, 100000, ValueKind::kWholeNumber))
      ->capture_default_str();
  app->add_option("--motion-resolution", arm->resolution,
                  "a camera on an arm: the step [rad or m] at which a straight joint-space move "
                  "is checked for collisions")
      ->capture_default_str();
  app->add_option("--plan-time", arm->plan_seconds,
                  "a camera on an arm: the most seconds spent planning around one colliding move "
                  "(OMPL RRT-Connect; its sample budget usually ends it first)")
      ->capture_default_str();
}

void AddPoseToleranceFlags(CLI::App* app, std::optional<PoseToleranceOptions>* tolerance) {
  CLI::Option* given = app->add_option_function<std::string>(
      "--pose-tolerance",
      [tolerance](const std::string& text) {
        const size_t comma = text.find(',');
        double values[2] = {0, 0};
        bool ok = comma != std::string::npos;
        for (int i = 0; ok && i < 2; ++i) {
          const std::string part = i == 0 ? text.substr(0, comma) : text.substr(comma + 1);
          char* end = nullptr;
          values[i] = std::strtod(part.c_str(), &end);
          ok = !part.empty() && end == part.c_str() + part.size() && std::isfinite(values[i]);
        }
        if (!ok)
          throw InputError(fmt::format(
              "--pose-tolerance '{}': give the mounting error as metres,degrees — e.g. 0.02,2 for "
              "2 cm and 2 degrees",
              ShownOnOneLine(text)));
        if (!*tolerance) *tolerance = PoseToleranceOptions{};
        (*tolerance)->position = values[0];
        (*tolerance)->angle_deg = values[1];
      },
      "P,A: mounting tolerance, metres and degrees (e.g. 0.02,2): each result's coverage over "
      "layouts whose sensors are off by up to P and A (mean, 5th percentile, worst, costliest "
      "sensor)");
  app->add_option_function<int>(
         "--pose-samples",
         [tolerance](int samples) {
           if (!*tolerance) *tolerance = PoseToleranceOptions{};
           (*tolerance)->samples = samples;
         },
         "perturbed layouts per result for --pose-tolerance")
      ->check(NumberFrom(1, 10000, ValueKind::kWholeNumber))
      ->default_str("64")
      ->needs(given);
}

void AddRobustnessFlags(CLI::App* app, RobustnessOptions* robustness) {
  app->add_option("--fov-tolerance", robustness->fov_tolerance_deg,
                  "robustness: degrees the chosen sensors' fields of view are shrunk by "
                  "(datasheet tolerance)")
      ->check(NumberFrom(0, 45, ValueKind::kNumber))
      ->capture_default_str();
  app->add_option_function<double>(
         "--alternatives-within", [robustness](double points) { robustness->within = points / 100.0; },
         "robustness: list one-sensor alternatives losing at most this many coverage points")
      ->check(NumberFrom(0, 100, ValueKind::kNumber))
      ->default_str("1");
}

}  // namespace vantage::cli
