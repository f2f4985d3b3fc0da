// The Python module `vantage` (docs/python.md): the pipeline's functions for scripts, notebooks
// and robot stacks. Like the CLI it is a face over include/vantage/pipeline.hpp: keyword
// arguments go onto the pipeline's option structs, results come back as NumPy/SciPy values, and
// every C++ exception is turned into a Python one at the boundary (InputError ->
// vantage.InputError, a ValueError; anything else -> RuntimeError), so that the interpreter never
// aborts. The GIL is released while the library works, so that other Python threads run meanwhile.
#include <fmt/format.h>
#include <fmt/ranges.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <condition_variable>
#include <csignal>
#include <cstdint>
#include <functional>
#include <initializer_list>
#include <limits>
#include <map>
#include <memory>
#include <mutex>
#include <numbers>
#include <optional>
#include <string>
#include <string_view>
#include <thread>
#include <type_traits>
#include <utility>
#include <variant>
#include <vector>

#include "vantage/error.hpp"
#include "vantage/external_matrix.hpp"
#include "vantage/interrupt.hpp"
#include "vantage/pipeline.hpp"
#include "vantage/select_states.hpp"
#include "vantage/selection_options.hpp"
#include "vantage/sensors.hpp"
#include "vantage/types.hpp"
#include "vantage/words.hpp"

namespace py = pybind11;

namespace vantage::python {
namespace {

using Strings = std::vector<std::string>;

// ---- arguments --------------------------------------------------------------------------------

// A path given as str, bytes or os.PathLike, in the bytes the OS takes: os.fsencode keeps a file
// name that is not UTF-8 (a str holding surrogate escapes: was "Unable to cast Python instance";
// bytes were read as the text "b'...'"). A NUL, where the OS would cut the path, is refused.
// `key` names the keyword in the errors: a TypeError for what is no path, an InputError for a
// NUL.
std::string PathOf(const py::handle& value, const std::string& key) {
  const py::module_ os = py::module_::import("os");
  if (!py::isinstance<py::str>(value) && !py::isinstance<py::bytes>(value) &&
      !py::hasattr(value, "__fspath__"))
    throw py::type_error(fmt::format("{}: give a path (str, bytes or os.PathLike), not {}", key,
                                     std::string(py::str(py::type::of(value).attr("__name__")))));
  const std::string path = os.attr("fsencode")(os.attr("fspath")(value)).cast<py::bytes>();
  if (path.find('\0') != std::string::npos)
    throw InputError(fmt::format("{}: '{}' holds a NUL character, which no path can — check the "
                                 "path",
                                 key, ShownOnOneLine(path)));
  return path;
}

// A path back to Python as os.fsdecode gives it (a name that is not UTF-8 as surrogate escapes;
// pybind11's UTF-8 decoding raised UnicodeDecodeError).
py::str PathText(const std::string& path) {
  return py::reinterpret_steal<py::str>(PyUnicode_DecodeFSDefault(path.c_str()));
}

std::optional<std::string> OptionalPathOf(const py::object& value, const std::string& key) {
  if (value.is_none()) return std::nullopt;
  return PathOf(value, key);
}

// One path or a list of them (the CLI's repeatable --model-path).
Strings PathsOf(const py::object& value, const std::string& key) {
  if (value.is_none()) return {};
  if (py::isinstance<py::str>(value) || py::isinstance<py::bytes>(value) ||
      py::hasattr(value, "__fspath__"))
    return {PathOf(value, key)};
  if (!py::isinstance<py::iterable>(value))
    throw py::type_error(fmt::format("{}: give a path or a list of paths, not {}", key,
                                     std::string(py::str(py::type::of(value).attr("__name__")))));
  Strings paths;
  for (const py::handle item : value) paths.push_back(PathOf(item, key));
  return paths;
}

// One name or a list of them (--target).
Strings NamesOf(const py::object& value) {
  if (value.is_none()) return {};
  if (py::isinstance<py::str>(value)) return {value.cast<std::string>()};
  if (!py::isinstance<py::iterable>(value))  // was: RuntimeError "Unable to cast"
    throw py::type_error("targets: give a name or a list of names, not " +
                         std::string(py::str(py::type::of(value).attr("__name__"))));
  Strings names;
  for (const py::handle item : value) {
    if (!py::isinstance<py::str>(item))
      throw py::type_error("targets: every name is a str, not " +
                           std::string(py::str(py::type::of(item).attr("__name__"))));
    names.push_back(item.cast<std::string>());
  }
  return names;
}

Method MethodOf(const std::string& name) {
  try {
    return ParseMethod(name);
  } catch (const InputError& e) {
    throw InputError(AtPlace("method", 0, e.what()));
  }
}

std::optional<Method> OptionalMethodOf(const std::optional<std::string>& name) {
  if (!name) return std::nullopt;
  return MethodOf(*name);
}

// The over_states keyword's values for its help: 'mean'/'min'/..., kAggregations' names.
const std::string& OverStatesKeywordValues() {
  static const std::string values = [] {
    std::vector<std::string> quoted;
    for (const Aggregation& row : kAggregations) quoted.push_back(fmt::format("'{}'", row.name));
    return fmt::format("{}", fmt::join(quoted, "/"));
  }();
  return values;
}

std::optional<OverStates> OverStatesOf(const std::optional<std::string>& name) {
  if (!name) return std::nullopt;
  try {
    return ParseOverStates(*name);
  } catch (const InputError& e) {
    throw InputError(AtPlace("over_states", 0, e.what()));
  }
}

// ---- numbers, flags and words: every keyword and dict entry of the module ----------------------
// One rule for all of them (docs/python.md, Errors; issue 44): a value of the wrong type is a
// TypeError naming the keyword, a value of the right type that no option takes (too large for
// any double or integer, negative where a count is meant) an InputError naming it. pybind11's
// own casters said "Unable to cast Python instance" (a RuntimeError) inside dicts and
// "incompatible function arguments" for 10**400.

std::string TypeName(const py::handle& value) {
  return py::str(py::type::of(value).attr("__name__"));
}

[[noreturn]] void WrongType(const std::string& key, const py::handle& value, const char* wanted) {
  throw py::type_error(fmt::format("{}: give {}, not {}", key, wanted, TypeName(value)));
}

// The text of a number for a message, shortened (10**400 has 401 digits).
std::string ShownNumber(const py::handle& value) {
  std::string text = py::repr(value);
  if (text.size() > 24) text = text.substr(0, 10) + "..." + text.substr(text.size() - 6);
  return text;
}

bool IsInteger(const py::handle& value) {
  // bool is an int in Python, but True as a count or a length is a mistake.
  return !PyBool_Check(value.ptr()) && PyIndex_Check(value.ptr()) && !PyFloat_Check(value.ptr());
}

// A real number: int or float (NumPy's too), not bool, not str.
std::optional<double> RealOf(const py::handle& value, const std::string& key) {
  if (value.is_none()) return std::nullopt;
  const bool number = IsInteger(value) || PyFloat_Check(value.ptr()) ||
                      (!PyBool_Check(value.ptr()) && !PyComplex_Check(value.ptr()) &&
                       !py::isinstance<py::str>(value) && !py::isinstance<py::bytes>(value) &&
                       py::hasattr(value, "__float__"));
  if (!number) WrongType(key, value, "a number");
  const double result = PyFloat_AsDouble(value.ptr());
  if (result == -1.0 && PyErr_Occurred()) {
    if (!PyErr_ExceptionMatches(PyExc_OverflowError)) throw py::error_already_set();
    PyErr_Clear();
    throw InputError(fmt::format("{}: {} is out of range — no double holds it", key,
                                 ShownNumber(value)));
  }
  return result;
}

// A whole number in [low, high]: int (NumPy's integers too), not bool, not float.
std::optional<int64_t> WholeOf(const py::handle& value, const std::string& key, int64_t low,
                               int64_t high) {
  if (value.is_none()) return std::nullopt;
  if (!IsInteger(value)) WrongType(key, value, "a whole number (int)");
  const py::int_ integer = py::reinterpret_steal<py::int_>(PyNumber_Index(value.ptr()));
  if (!integer) throw py::error_already_set();
  int overflow = 0;
  const long long result = PyLong_AsLongLongAndOverflow(integer.ptr(), &overflow);
  if (overflow != 0 || result < low || result > high)
    throw InputError(fmt::format("{}: {} is out of range — give {} to {}", key,
                                 ShownNumber(value), low, high));
  return result;
}

std::optional<int> IntOf(const py::handle& value, const std::string& key) {
  const std::optional<int64_t> whole = WholeOf(value, key, std::numeric_limits<int>::min(),
                                               std::numeric_limits<int>::max());
  if (!whole) return std::nullopt;
  return static_cast<int>(*whole);
}

// A whole number >= 0 up to 2^64 - 1 (seeds, counts of cells).
std::optional<uint64_t> UnsignedOf(const py::handle& value, const std::string& key) {
  if (value.is_none()) return std::nullopt;
  if (!IsInteger(value)) WrongType(key, value, "a whole number (int)");
  const py::int_ integer = py::reinterpret_steal<py::int_>(PyNumber_Index(value.ptr()));
  if (!integer) throw py::error_already_set();
  const unsigned long long result = PyLong_AsUnsignedLongLong(integer.ptr());
  if (result == static_cast<unsigned long long>(-1) && PyErr_Occurred()) {
    PyErr_Clear();
    throw InputError(fmt::format("{}: {} is out of range — give 0 to 18446744073709551615", key,
                                 ShownNumber(value)));
  }
  return result;
}

std::optional<bool> FlagOf(const py::handle& value, const std::string& key) {
  if (value.is_none()) return std::nullopt;
  // Python's bool and NumPy's bool_; not 1 or "yes", which are more likely mistakes.
  if (PyBool_Check(value.ptr())) return value.ptr() == Py_True;
  if (TypeName(value) == "bool_") return PyObject_IsTrue(value.ptr()) == 1;
  WrongType(key, value, "True or False");
}

bool FlagOf(const py::handle& value, const std::string& key, bool when_none) {
  return FlagOf(value, key).value_or(when_none);
}

std::optional<std::string> TextOf(const py::handle& value, const std::string& key) {
  if (value.is_none()) return std::nullopt;
  if (!py::isinstance<py::str>(value)) WrongType(key, value, "a str");
  return value.cast<std::string>();
}

// (x, y, z): a sequence of three numbers.
std::optional<std::array<double, 3>> PointOf(const py::handle& value, const std::string& key) {
  if (value.is_none()) return std::nullopt;
  if (py::isinstance<py::str>(value) || py::isinstance<py::bytes>(value) ||
      !PySequence_Check(value.ptr()))
    WrongType(key, value, "a sequence (x, y, z) of three numbers");
  const py::sequence items = py::reinterpret_borrow<py::sequence>(value);
  if (items.size() != 3)
    throw InputError(fmt::format("{}: has {} values — give (x, y, z) [m]", key, items.size()));
  std::array<double, 3> point{};
  for (size_t a = 0; a < 3; ++a) {
    const std::string item_key = fmt::format("{}[{}]", key, a);
    const py::object item = items[a];
    if (item.is_none()) WrongType(item_key, item, "a number");  // RealOf reads None as unset
    point[a] = *RealOf(item, item_key);
  }
  return point;
}

// `quality`: None or a dict with max_incidence [deg] and max_depth_noise [mm], as the CLI's flags.
QualityFilter QualityOf(const py::object& value) {
  QualityFilter quality;
  if (value.is_none()) return quality;
  if (!py::isinstance<py::dict>(value))
    throw py::type_error("quality: give a dict such as {'max_incidence': 60, "
                         "'max_depth_noise': 2} (degrees, millimetres) or None, not " +
                         TypeName(value));
  for (const auto& [key, item] : value.cast<py::dict>()) {
    if (!py::isinstance<py::str>(key))
      throw py::type_error("quality: every key is a str, not " + TypeName(key));
    const std::string name = py::str(key);
    if (item.is_none()) continue;
    if (name == "max_incidence") {
      quality.max_incidence_deg = RealOf(item, "quality['max_incidence']");
    } else if (name == "max_depth_noise") {
      quality.max_depth_noise = *RealOf(item, "quality['max_depth_noise']") / 1000.0;
    } else {
      throw InputError(
          AtPlace("quality", 0,
                  "unknown key '" + name + "' — use max_incidence [deg] and max_depth_noise [mm]"));
    }
  }
  return quality;
}

// The progress callable, called as progress(done, total) from the library's worker threads with
// the GIL taken; its exception stops the run and is raised to the caller. The callable is held
// by a shared pointer whose deleter takes the GIL, since the option structs are copied and
// destroyed inside the library, without it.
std::function<void(size_t, size_t)> ProgressOf(const py::object& progress) {
  if (progress.is_none()) return {};
  if (!PyCallable_Check(progress.ptr()))
    throw py::type_error("progress: give a callable progress(done, total) or None, not " +
                         std::string(py::str(py::type::of(progress).attr("__name__"))));
  std::shared_ptr<py::object> callable(new py::object(progress), [](py::object* held) {
    py::gil_scoped_acquire gil;
    delete held;
  });
  return [callable](size_t done, size_t total) {
    py::gil_scoped_acquire gil;
    (*callable)(done, total);
  };
}

// The scene keywords of load, optimize and evaluate (the CLI's scene flags).
struct SceneArgs {
  py::object model_path, resource_path, package_path, targets, cell_size, seed,
      observation_point, random_roll, exposed_only;
};

SceneInput SceneInputOf(const std::string& path_key, const py::object& path,
                        const SceneArgs& args) {
  SceneInput input;
  input.path = OptionalPathOf(path, path_key).value_or("");
  input.load.model_paths = PathsOf(args.model_path, "model_path");
  input.load.resource_paths = PathsOf(args.resource_path, "resource_path");
  input.load.package_paths = PathsOf(args.package_path, "package_path");
  // --exposed-only is a flag: False is the default, the paper's metric (evaluate: the run's).
  if (FlagOf(args.exposed_only, "exposed_only", false)) input.exposed_only = true;
  const py::object& targets = args.targets;
  const py::object& cell_size = args.cell_size;
  const py::object& seed = args.seed;
  const py::object& observation_point = args.observation_point;
  const py::object& random_roll = args.random_roll;
  input.load.targets = NamesOf(targets);
  input.load.cell_size = RealOf(cell_size, "cell_size");
  input.seed = UnsignedOf(seed, "seed");
  if (const auto point = PointOf(observation_point, "observation_point")) {
    const auto& p = *point;
    input.observation_point = Vec3(p[0], p[1], p[2]);
  }
  input.random_roll = FlagOf(random_roll, "random_roll");
  return input;
}

// `physical`: None (the pipeline's default: physical, ideal for a Gazebo world of the paper's
// system), True (--physical) or False (--ideal).
ObserveOptions ObserveOptionsOf(const py::object& quality, const py::object& cull,
                                const py::object& progress, const py::object& physical) {
  ObserveOptions options;
  options.physical = FlagOf(physical, "physical");
  options.cull = FlagOf(cull, "cull", true);
  options.quality = QualityOf(quality);
  options.progress = ProgressOf(progress);
  return options;
}

// `out`: None (nothing written) or the folder to write (the CLI's --out).
std::optional<std::string> OutDirOf(const py::object& out) {
  std::optional<std::string> folder = OptionalPathOf(out, "out");
  if (folder && folder->empty())
    throw InputError(AtPlace("out", 0, "the path is empty — give the folder to write, or None"));
  if (folder) CheckRunFolder(*folder);  // before any work, as the CLI's --out
  return folder;
}

RunLimits LimitsOf(const py::object& max_memory_value, const py::object& max_seconds_value) {
  const std::optional<double> max_memory = RealOf(max_memory_value, "max_memory");
  RunLimits limits;
  // 0 is the CLI's "no limit" for --max-seconds; Validate refuses < 0 and infinity.
  limits.max_seconds = RealOf(max_seconds_value, "max_seconds").value_or(0.0);
  if (max_memory) {
    // The library reads 0 as "75 % of the RAM"; a caller's 0 (or less) is a mistake, as the
    // CLI's --max-memory 0 is (was: taken as no limit of its own).
    if (!(*max_memory > 0))
      throw InputError(fmt::format("max_memory: {} is not a positive number of MiB — give e.g. "
                                   "4096, or None for 75 % of the RAM",
                                   *max_memory));
    limits.max_memory_mib = *max_memory;
  }
  return limits;
}

RobustnessOptions RobustnessOf(const py::object& fov_tolerance_value,
                               const py::object& alternatives_within_value) {
  const std::optional<double> fov_tolerance = RealOf(fov_tolerance_value, "fov_tolerance");
  const std::optional<double> alternatives_within =
      RealOf(alternatives_within_value, "alternatives_within");
  RobustnessOptions robustness;
  if (fov_tolerance) robustness.fov_tolerance_deg = *fov_tolerance;
  if (alternatives_within) robustness.within = *alternatives_within / 100.0;  // points
  return robustness;
}

// `pose_tolerance`: None or (metres, degrees), the CLI's --pose-tolerance P,A; `pose_samples` its
// --pose-samples (only with a tolerance, as the CLI's needs --pose-tolerance). Ranges: Validate.
std::optional<PoseToleranceOptions> PoseToleranceOf(const py::object& tolerance,
                                                    const py::object& samples_value) {
  const std::optional<int> samples = IntOf(samples_value, "pose_samples");
  if (tolerance.is_none()) {
    if (samples)
      throw InputError("pose_samples: only pose_tolerance perturbs layouts — give "
                       "pose_tolerance=(metres, degrees), or leave pose_samples out");
    return std::nullopt;
  }
  if (py::isinstance<py::str>(tolerance) || py::isinstance<py::bytes>(tolerance) ||
      !PySequence_Check(tolerance.ptr()))
    WrongType("pose_tolerance", tolerance, "a pair (metres, degrees) such as (0.02, 2)");
  const py::sequence items = py::reinterpret_borrow<py::sequence>(tolerance);
  if (items.size() != 2)
    throw InputError(fmt::format("pose_tolerance: has {} values — give (metres, degrees), e.g. "
                                 "(0.02, 2) for 2 cm and 2 degrees",
                                 items.size()));
  std::array<double, 2> values{};
  for (size_t i = 0; i < 2; ++i) {
    const std::string key = fmt::format("pose_tolerance[{}]", i);
    const py::object item = items[i];
    if (item.is_none()) WrongType(key, item, "a number");  // RealOf reads None as unset
    values[i] = *RealOf(item, key);
  }
  PoseToleranceOptions options;
  options.position = values[0];
  options.angle_deg = values[1];
  if (samples) options.samples = *samples;
  return options;
}

// The arm keywords of optimize (docs/arm.md), the CLI's flags of the same names.
ArmTourOptions ArmTourOf(const py::object& cycle_time, const py::object& joint_speed,
                         const py::object& frames, const py::object& motion_resolution,
                         const py::object& plan_time, const py::object& track,
                         const py::object& move_penalty, const py::object& state_interval) {
  ArmTourOptions arm;
  arm.cycle_time = RealOf(cycle_time, "cycle_time");
  arm.joint_speed = RealOf(joint_speed, "joint_speed");
  if (const auto count = IntOf(frames, "frames")) arm.frames = *count;
  if (const auto step = RealOf(motion_resolution, "motion_resolution")) arm.resolution = *step;
  if (const auto seconds = RealOf(plan_time, "plan_time")) arm.plan_seconds = *seconds;
  arm.track = FlagOf(track, "track", false);
  arm.move_penalty = RealOf(move_penalty, "move_penalty");
  arm.state_interval = RealOf(state_interval, "state_interval");
  return arm;
}

// ---- running without the GIL ------------------------------------------------------------------

void CheckThreads(std::optional<int> threads) {
  if (threads && (*threads < 0 || *threads > 4096))
    throw InputError(AtPlace("threads", 0,
                             std::to_string(*threads) +
                                 " is out of range — give 1 to 4096 worker threads, or None "
                                 "(0) for all cores"));
}

// The interpreter's main thread, where Python handles signals (set when the module is imported).
std::thread::id g_main_thread;

// The signal that asked the run to stop (0: none, or a call asked).
int SignalRequested() {
  if (!InterruptRequested()) return 0;
  try {
    ThrowIfInterrupted();
  } catch (const Interrupted& interrupted) {
    return interrupted.signal();
  }
  return 0;
}

// While alive (a call on the main thread, which has taken SIGINT, SIGTERM and SIGHUP from Python):
// once a signal asked the run to stop, the call has kStopGrace to return; one that is blocked
// (a progress callable that never returns, a lock held elsewhere) then ends the process by that
// signal, as it would have ended without vantage (issue 44: a deadlocked call ignored SIGTERM,
// whose request only the library's stages read).
class SignalWatchdog {
 public:
  static constexpr std::chrono::seconds kStopGrace{3};

  SignalWatchdog() : thread_([this] { Watch(); }) {}
  ~SignalWatchdog() {
    {
      const std::lock_guard<std::mutex> lock(mutex_);
      done_ = true;
    }
    wake_.notify_all();
    thread_.join();
  }
  SignalWatchdog(const SignalWatchdog&) = delete;
  SignalWatchdog& operator=(const SignalWatchdog&) = delete;

 private:
  void Watch() {
    std::unique_lock<std::mutex> lock(mutex_);
    std::optional<std::chrono::steady_clock::time_point> asked;
    while (!wake_.wait_for(lock, std::chrono::milliseconds(100), [this] { return done_; })) {
      const int signal = SignalRequested();
      if (signal == 0) continue;
      const auto now = std::chrono::steady_clock::now();
      if (!asked) asked = now;
      if (now - *asked < kStopGrace) continue;
      std::signal(signal, SIG_DFL);
      std::raise(signal);
    }
  }

  std::mutex mutex_;
  std::condition_variable wake_;
  bool done_ = false;
  std::thread thread_;
};

// Runs `work` with the GIL released, on at most `threads` worker threads (None or 0: all cores;
// results are the same for any number). `work` must not touch Python objects. Called from the
// main thread, Ctrl-C stops the work within a second (vantage/interrupt.hpp) and raises
// KeyboardInterrupt; Python's own handler is back once the call returns.
template <typename Work>
auto WithoutGil(const py::object& threads_value, Work&& work) {
  const std::optional<int> threads = IntOf(threads_value, "threads");
  CheckThreads(threads);
  std::optional<InterruptOnSignals> interrupts;
  std::optional<SignalWatchdog> watchdog;
  if (std::this_thread::get_id() == g_main_thread) {
    ClearInterrupt();
    interrupts.emplace();
    watchdog.emplace();
  }
  try {
    py::gil_scoped_release release;
    if (!threads || *threads == 0) return work();
    tbb::task_arena arena(*threads);
    return arena.execute(std::forward<Work>(work));
  } catch (const Interrupted&) {
    watchdog.reset();
    interrupts.reset();
    ClearInterrupt();
    PyErr_SetNone(PyExc_KeyboardInterrupt);
    throw py::error_already_set();
  }
}

// ---- results ----------------------------------------------------------------------------------

/// One candidate sensor as Python sees it (vantage.Candidate).
struct CandidateInfo {
  std::string name;
  std::string type;    // catalog id, or the type's own name
  std::string sensor;  // display name of the type
  std::string technology;
  std::string population;              // "" for an explicit sensor
  std::array<double, 3> position{};    // [m], world
  std::array<double, 4> quaternion{};  // world_from_body, [w, x, y, z]
  int width = 0, height = 0;
  double fx = 0, fy = 0, cx = 0, cy = 0, near = 0, far = 0, cost = 0;
  std::optional<double> coverage;         // |O_i ∩ R| / |R|, once observed
  std::optional<size_t> observed_voxels;  // |O_i ∩ R|, once observed
  // report.json's other candidate keys, once observed: the paper's score, the pixels traced,
  // under the physical model the ideal pinhole's coverage, under a quality filter the plain one
  // and the pixel counts (None where report.json has no such key).
  std::optional<double> paper_coverage;
  std::optional<uint64_t> rays_traced;
  std::optional<double> ideal_coverage;
  std::optional<double> plain_coverage;
  std::optional<uint64_t> target_pixels;
  std::optional<uint64_t> quality_pixels;
};

CandidateInfo InfoOf(const Candidate& c) {
  CandidateInfo info;
  info.name = c.name;
  info.type = c.type_id;
  info.sensor = c.sensor.name;
  info.technology = c.sensor.technology;
  info.population = c.population;
  for (int a = 0; a < 3; ++a) info.position[static_cast<size_t>(a)] = c.world_from_body.position[a];
  info.quaternion = WxyzOf(c.world_from_body.rotation);
  info.width = c.sensor.width;
  info.height = c.sensor.height;
  info.fx = c.sensor.fx;
  info.fy = c.sensor.fy;
  info.cx = c.sensor.cx;
  info.cy = c.sensor.cy;
  info.near = c.sensor.near;
  info.far = c.sensor.far;
  info.cost = c.sensor.cost;
  return info;
}

std::vector<CandidateInfo> CandidatesOf(const VisibilityFile& data) {
  std::vector<CandidateInfo> list;
  list.reserve(data.candidates.size());
  const double cells = static_cast<double>(data.reference.size());
  const auto share = [cells](size_t count) {
    return cells > 0 ? static_cast<double>(count) / cells : 0.0;
  };
  for (size_t i = 0; i < data.candidates.size(); ++i) {
    CandidateInfo info = InfoOf(data.candidates[i]);
    const Observation& o = data.observations[i];
    const size_t seen = o.reference_indices.size();
    info.observed_voxels = seen;
    info.coverage = share(seen);
    info.paper_coverage = share(seen + o.outside_keys.size());
    info.rays_traced = o.rays_traced;
    if (data.physical)
      info.ideal_coverage =
          share(o.ideal_differs ? o.ideal_reference_indices.size() : o.reference_indices.size());
    if (data.quality.active()) {
      info.plain_coverage = share(o.plain_reference_indices.size());
      info.target_pixels = o.target_pixels;
      info.quality_pixels = o.quality_pixels;
    }
    list.push_back(std::move(info));
  }
  return list;
}

/// A chosen constellation (vantage.Selection).
struct SelectionInfo {
  Selection selection;
  Strings sensors;  // names of the chosen candidates, in the order chosen
  // What report.json derives for the result (DeriveReport): None where it has no such key.
  std::optional<double> ideal_coverage;  // the physical model: the ideal pinhole's coverage
  std::optional<double> plain_coverage;  // a quality filter: coverage counting every pixel
  std::optional<double> ceiling;         // all candidates together, counted as this result
  std::vector<std::pair<std::string, double>> part_coverage;  // per target part, R's order
  py::object constraints = py::none();   // results[i].constraints as a dict
};

SelectionInfo SelectionInfoOf(Selection selection, const VisibilityFile& data) {
  SelectionInfo info;
  for (uint32_t i : selection.chosen) info.sensors.push_back(data.candidates[i].name);
  info.selection = std::move(selection);
  return info;
}

py::object JsonOf(const std::string& text) {
  return py::module_::import("json").attr("loads")(text);
}

// The CSR matrix of the sets: the index lists are copied once, straight into the NumPy array
// SciPy keeps (no intermediate vector, no conversion afterwards: SciPy takes arrays of one index
// dtype as they are).
template <typename Index>
py::object CsrOf(const VisibilityFile& data, size_t nonzeros) {
  const size_t rows = data.observations.size();
  py::array_t<Index> indptr(static_cast<py::ssize_t>(rows + 1));
  py::array_t<Index> indices(static_cast<py::ssize_t>(nonzeros));
  Index* row_start = indptr.mutable_data();
  Index* column = indices.mutable_data();
  size_t at = 0;
  row_start[0] = 0;
  for (size_t i = 0; i < rows; ++i) {
    for (uint32_t r : data.observations[i].reference_indices) column[at++] = static_cast<Index>(r);
    row_start[i + 1] = static_cast<Index>(at);
  }
  py::object ones = py::module_::import("numpy").attr("ones")(nonzeros, "float64");
  py::object csr = py::module_::import("scipy.sparse")
                       .attr("csr_matrix")(py::make_tuple(ones, indices, indptr),
                                           py::make_tuple(rows, data.reference.size()));
  csr.attr("has_sorted_indices") = true;  // each O_i is sorted and unique
  return csr;
}

py::object MatrixOf(const VisibilityFile& data) {
  size_t nonzeros = 0;
  for (const Observation& o : data.observations) nonzeros += o.reference_indices.size();
  constexpr size_t kInt32 = static_cast<size_t>(std::numeric_limits<int32_t>::max());
  if (nonzeros <= kInt32 && data.reference.size() <= kInt32) return CsrOf<int32_t>(data, nonzeros);
  return CsrOf<int64_t>(data, nonzeros);
}

/// A loaded, deployed scene (vantage.Problem); immutable, so observe may run from many threads.
struct ProblemHandle {
  std::shared_ptr<const PreparedScene> prepared;
};

/// An observed scene's matrix (vantage.Visibility); immutable but for the matrix built lazily.
struct VisibilityHandle {
  std::shared_ptr<const VisibilityFile> data;
  py::object matrix;  // scipy.sparse.csr_matrix, built on first use
};

// ---- a matrix from elsewhere (Visibility.from_matrix, issue 42) ------------------------------

// A 1-D array of integers of any width (the CSR's indptr, indices) as int64, C-contiguous.
// `key` names it in the errors ("csr: indices").
py::array_t<int64_t> IndexArrayOf(const py::handle& value, const std::string& key) {
  const py::module_ np = py::module_::import("numpy");
  py::array array;
  try {
    array = np.attr("asarray")(value);
  } catch (const py::error_already_set& e) {  // a ragged list
    throw py::type_error(fmt::format("{}: give a 1-D array of integers ({})", key, e.what()));
  }
  if (array.ndim() != 1)
    throw InputError(fmt::format("{}: has {} dimensions — give a 1-D array", key, array.ndim()));
  const char kind = array.dtype().kind();
  if (kind != 'i' && kind != 'u' && array.size() > 0)
    throw py::type_error(fmt::format("{}: give integers, not {}", key,
                                     std::string(py::str(array.dtype()))));
  if (kind == 'u' && array.size() > 0 &&
      np.attr("max")(array).cast<uint64_t>() >
          static_cast<uint64_t>(std::numeric_limits<int64_t>::max()))
    throw InputError(fmt::format("{}: holds {} — out of range", key,
                                 np.attr("max")(array).cast<uint64_t>()));
  return np.attr("ascontiguousarray")(array, py::arg("dtype") = "int64").cast<py::array_t<int64_t>>();
}

// The CSR's data (point counts): numbers (bool, integers, floats) as float64, C-contiguous; the
// library checks that they are whole and >= 1.
py::array_t<double> CountArrayOf(const py::handle& value, const std::string& key) {
  const py::module_ np = py::module_::import("numpy");
  py::array array;
  try {
    array = np.attr("asarray")(value);
  } catch (const py::error_already_set& e) {
    throw py::type_error(fmt::format("{}: give a 1-D array of point counts ({})", key, e.what()));
  }
  if (array.ndim() != 1)
    throw InputError(fmt::format("{}: has {} dimensions — give a 1-D array", key, array.ndim()));
  const char kind = array.dtype().kind();
  if (kind != 'b' && kind != 'i' && kind != 'u' && kind != 'f' && array.size() > 0)
    throw py::type_error(fmt::format("{}: give point counts (numbers), not {}", key,
                                     std::string(py::str(array.dtype()))));
  return np.attr("ascontiguousarray")(array, py::arg("dtype") = "float64").cast<py::array_t<double>>();
}

// `names`: None (c0, c1, ...) or a sequence of str, one per row.
Strings RowNamesOf(const py::object& value) {
  if (value.is_none()) return {};
  if (py::isinstance<py::str>(value) || py::isinstance<py::bytes>(value) ||
      !py::isinstance<py::iterable>(value))
    WrongType("names", value, "a list of names (str), one per row");
  Strings names;
  size_t i = 0;
  for (const py::handle item : value) {
    const std::string key = fmt::format("names[{}]", i++);
    if (!py::isinstance<py::str>(item)) WrongType(key, item, "a str");
    Py_ssize_t size = 0;
    const char* text = PyUnicode_AsUTF8AndSize(item.ptr(), &size);
    if (text == nullptr) {  // a lone surrogate: no UTF-8 holds it
      PyErr_Clear();
      throw InputError(fmt::format("{}: is not valid Unicode (a lone surrogate) — give the name "
                                   "as text",
                                   key));
    }
    names.emplace_back(text, static_cast<size_t>(size));
  }
  return names;
}

// `costs`: None (1 each) or a sequence of numbers (a NumPy array too), one per row.
std::vector<double> RowCostsOf(const py::object& value) {
  if (value.is_none()) return {};
  if (py::isinstance<py::str>(value) || py::isinstance<py::bytes>(value) ||
      !py::isinstance<py::iterable>(value))
    WrongType("costs", value, "a list of numbers, one per row");
  std::vector<double> costs;
  for (const py::handle item : value) {
    const std::string key = fmt::format("costs[{}]", costs.size());
    if (item.is_none()) WrongType(key, item, "a number");  // RealOf reads None as unset
    costs.push_back(*RealOf(item, key));
  }
  return costs;
}

// Visibility.from_matrix: the arrays held while the library reads them without the GIL.
VisibilityHandle FromMatrix(const py::object& csr, const py::object& cells_value,
                            const py::object& names_value, const py::object& costs_value,
                            const py::object& states) {
  if (!states.is_none())
    throw InputError(
        "states: a .vis file holds one state's matrix (selection over states runs in optimize, "
        "on a scene with states), so a Visibility cannot group its cells by state — call "
        "from_matrix once per state's matrix, or leave states out");
  std::optional<uint64_t> cells;
  if (const auto whole = WholeOf(cells_value, "cells", 1, static_cast<int64_t>(kMaxExternalCells)))
    cells = static_cast<uint64_t>(*whole);
  py::array_t<int64_t> indptr, indices;
  std::optional<py::array_t<double>> counts;
  if (py::hasattr(csr, "format") && py::hasattr(csr, "tocsr")) {  // scipy.sparse
    const std::string format = py::str(csr.attr("format"));
    if (format != "csr")
      throw py::type_error(fmt::format("csr: give a CSR matrix, not SciPy's {} (convert it with "
                                       ".tocsr())",
                                       format));
    const auto shape = csr.attr("shape").cast<std::pair<uint64_t, uint64_t>>();
    if (cells && *cells != shape.second)
      throw InputError(fmt::format("cells: {}, but the matrix has {} columns — leave cells out "
                                   "with a SciPy matrix",
                                   *cells, shape.second));
    cells = shape.second;
    indptr = IndexArrayOf(csr.attr("indptr"), "csr: indptr");
    indices = IndexArrayOf(csr.attr("indices"), "csr: indices");
    counts = CountArrayOf(csr.attr("data"), "csr: data");
    if (static_cast<uint64_t>(indptr.size()) != shape.first + 1)
      throw InputError(fmt::format("csr: indptr has {} entries for {} rows — a CSR matrix has "
                                   "rows + 1",
                                   indptr.size(), shape.first));
  } else if (py::isinstance<py::tuple>(csr) || py::isinstance<py::list>(csr)) {
    const py::sequence parts = py::reinterpret_borrow<py::sequence>(csr);
    if (parts.size() != 2 && parts.size() != 3)
      throw InputError(fmt::format("csr: holds {} arrays — give (indptr, indices) or (indptr, "
                                   "indices, data)",
                                   parts.size()));
    if (!cells)
      throw py::type_error("cells: give the number of cells (the matrix's columns) with "
                           "(indptr, indices) arrays");
    indptr = IndexArrayOf(parts[0], "csr: indptr");
    indices = IndexArrayOf(parts[1], "csr: indices");
    if (parts.size() == 3) counts = CountArrayOf(parts[2], "csr: data");
  } else {
    WrongType("csr", csr,
              "a scipy.sparse CSR matrix or (indptr, indices[, data]) arrays (a dense array: "
              "scipy.sparse.csr_matrix(dense))");
  }
  ExternalMatrix matrix;
  matrix.cells = *cells;
  matrix.indptr = {indptr.data(), static_cast<size_t>(indptr.size())};
  matrix.indices = {indices.data(), static_cast<size_t>(indices.size())};
  if (counts) matrix.counts = {counts->data(), static_cast<size_t>(counts->size())};
  matrix.names = RowNamesOf(names_value);
  matrix.costs = RowCostsOf(costs_value);
  VisibilityHandle result;
  result.data = WithoutGil(py::none(), [&] {
    return std::make_shared<const VisibilityFile>(VisibilityOfMatrix(matrix));
  });
  return result;
}

// The installation constraints' keywords (docs/constraints.md), None where not given, set on
// `constraints` (a SelectionRequest's or EvaluateOptions').
void SetConstraintKeywords(ConstraintOptions* constraints, const py::object& interference,
                           const py::object& interference_overlap,
                           const py::object& calibration_overlap,
                           const py::object& calibration_overlap_frac) {
  constraints->interference = FlagOf(interference, "interference");
  constraints->interference_overlap = RealOf(interference_overlap, "interference_overlap");
  constraints->calibration_overlap = UnsignedOf(calibration_overlap, "calibration_overlap");
  constraints->calibration_overlap_frac =
      RealOf(calibration_overlap_frac, "calibration_overlap_frac");
}

// The selection keywords every selecting function shares, by keyword: each read as its row of
// the selection options' table (selection_options.hpp) types it, None (False for a flag) where
// not given, with the rule above.
SelectionRequest RequestOf(
    std::initializer_list<std::pair<std::string_view, const py::object*>> keywords) {
  SelectionRequest request;
  for (const auto& [keyword, value] : keywords) {
    const std::string key(keyword);
    std::visit(
        [&](auto pointer) {
          auto& field = request.*pointer;
          using Value = std::decay_t<decltype(field)>;
          if constexpr (std::is_same_v<Value, bool>)
            field = FlagOf(*value, key, false);
          else if constexpr (std::is_same_v<Value, std::optional<int>>)
            field = IntOf(*value, key);
          else if constexpr (std::is_same_v<Value, std::optional<int64_t>>)
            field = WholeOf(*value, key, std::numeric_limits<int64_t>::min(),
                            std::numeric_limits<int64_t>::max());
          else if constexpr (std::is_same_v<Value, std::optional<double>>)
            field = RealOf(*value, key);
          else if constexpr (std::is_same_v<Value, std::optional<Method>>)
            field = OptionalMethodOf(TextOf(*value, key));
          else
            field = OverStatesOf(TextOf(*value, key));
        },
        SelectionOptionOfKeyword(keyword).member);
  }
  return request;
}

// Selection as `vantage select FILE`: the same resolution, constraints included; each result
// with what report.json derives for it (the same DeriveReport and, for the constraints,
// ReportJson as `vantage select` writes).
std::vector<SelectionInfo> SelectOn(const VisibilityFile& data,
                                    const SelectionRequest& request,
                                    std::optional<uint64_t> seed,
                                    Method default_method,
                                    const py::object& threads) {
  const MatrixSelection resolved =
      ResolveMatrixSelection(data, request, seed.value_or(data.seed), default_method);
  struct Derived {
    Report report;
    std::string json;  // report.json, only when constraints are on
  };
  const std::shared_ptr<const Derived> derived = WithoutGil(threads, [&] {
    auto d = std::make_shared<Derived>();
    d->report.results = Select(data.observations, data.reference.size(), resolved.options);
    d->report.scene = data.scene;
    d->report.seed = resolved.options.seed;
    d->report.data = &data;
    d->report.constraints = resolved.constraints;
    DeriveReport(&d->report);
    if (d->report.constraints) d->json = ReportJson(d->report);
    return d;
  });
  const Report& report = derived->report;
  const py::object results_json =
      derived->json.empty() ? py::object(py::none()) : JsonOf(derived->json)["results"];
  std::vector<SelectionInfo> list;
  for (size_t i = 0; i < report.results.size(); ++i) {
    SelectionInfo info = SelectionInfoOf(report.results[i], data);
    if (i < report.result_ideal_coverage.size()) info.ideal_coverage = report.result_ideal_coverage[i];
    if (i < report.result_plain_coverage.size()) info.plain_coverage = report.result_plain_coverage[i];
    info.ceiling = report.ceiling;
    if (i < report.result_part_coverage.size())
      for (size_t p = 0; p < report.parts.size(); ++p)
        info.part_coverage.emplace_back(report.parts[p].name, report.result_part_coverage[i][p]);
    if (!results_json.is_none()) {
      const py::dict result = results_json[py::int_(i)];
      if (result.contains("constraints")) info.constraints = result["constraints"];
    }
    list.push_back(std::move(info));
  }
  return list;
}

py::list SensorCatalog() {
  py::list list;
  for (const SensorType& s : Catalog()) {
    py::dict entry;
    entry["id"] = s.id;
    entry["name"] = s.name;
    entry["technology"] = s.technology;
    entry["width"] = s.width;
    entry["height"] = s.height;
    entry["hfov"] = s.HorizontalFov();
    entry["vfov"] = s.VerticalFov();
    entry["fx"] = s.fx;
    entry["fy"] = s.fy;
    entry["cx"] = s.cx;
    entry["cy"] = s.cy;
    entry["near"] = s.near;
    entry["far"] = s.far;
    entry["fps"] = s.fps;
    entry["cost"] = s.cost_given ? py::object(py::float_(s.cost)) : py::object(py::none());
    if (s.depth_noise) {
      py::dict noise;
      noise["a"] = s.depth_noise->a;
      noise["b"] = s.depth_noise->b;
      noise["c"] = s.depth_noise->c;
      noise["source"] = s.depth_noise->source;
      entry["depth_noise"] = noise;
    } else {
      entry["depth_noise"] = py::none();
    }
    list.append(entry);
  }
  return list;
}

void SetLogLevel(const std::string& level) {
  const spdlog::level::level_enum parsed = spdlog::level::from_str(level);
  if (parsed == spdlog::level::off && level != "off")
    throw InputError(AtPlace(
        "level", 0, "unknown log level '" + level + "' — use debug, info, warning, error or off"));
  spdlog::default_logger()->set_level(parsed);
}

py::array_t<double> ArrayOf(const double* values, size_t count) {
  return py::array_t<double>(static_cast<py::ssize_t>(count), values);
}

py::object OptionalDouble(const std::optional<double>& value) {
  return value ? py::object(py::float_(*value)) : py::object(py::none());
}

}  // namespace

void Bind(py::module_& m) {
  m.doc() =
      "vantage: where to put 3D depth cameras so that together they see as much as possible of "
      "the targets.\n\nThe library's pipeline (load, observe, select, optimize, evaluate) for "
      "Python; docs/python.md describes the API, units and frames. Lengths are metres, angles "
      "degrees in options, quaternions [w, x, y, z]. Bad input raises vantage.InputError (a "
      "ValueError) with the CLI's `file:line: message`; internal failures raise RuntimeError.";
  m.attr("__version__") = Version();

  static py::exception<InputError> input_error(m, "InputError", PyExc_ValueError);
  py::register_exception_translator([](std::exception_ptr thrown) {
    try {
      if (thrown) std::rethrow_exception(thrown);
    } catch (const InputError& e) {
      // A message may quote a file name that is not UTF-8 (legal on Linux): its bytes become
      // surrogate escapes, as os.fsdecode shows such names (was: a UnicodeDecodeError instead).
      PyObject* message = PyUnicode_DecodeFSDefault(e.what());
      PyErr_SetObject(input_error.ptr(), message);
      Py_XDECREF(message);
    }
  });
  m.attr("InputError").attr("__doc__") =
      "Bad input that the user can fix: a scene, visibility or report file (the message starts "
      "with `file:line:` as the CLI's) or an option (the message names it). A ValueError.";

  py::class_<CandidateInfo>(m, "Candidate",
                            "One candidate sensor: a sensor type at a world pose of its camera "
                            "body frame (x forward, y left, z up).")
      .def_readonly("name", &CandidateInfo::name, "unique name, e.g. 'kinect_ring_3'")
      .def_readonly("type", &CandidateInfo::type,
                    "catalog id of the sensor type (vantage.sensors()), or the type's own name")
      .def_readonly("sensor", &CandidateInfo::sensor, "display name of the sensor type")
      .def_readonly("technology", &CandidateInfo::technology, "e.g. 'structured light'")
      .def_readonly("population", &CandidateInfo::population,
                    "the population it was deployed from; '' for an explicit sensor")
      .def_property_readonly(
          "position", [](const CandidateInfo& c) { return ArrayOf(c.position.data(), 3); },
          "position of the camera body frame in the world [m], shape (3,)")
      .def_property_readonly(
          "quaternion", [](const CandidateInfo& c) { return ArrayOf(c.quaternion.data(), 4); },
          "rotation world_from_body as a unit quaternion [w, x, y, z], shape (4,)")
      .def_readonly("width", &CandidateInfo::width, "image width [px]")
      .def_readonly("height", &CandidateInfo::height, "image height [px]")
      .def_readonly("fx", &CandidateInfo::fx, "focal length [px]")
      .def_readonly("fy", &CandidateInfo::fy, "focal length [px]")
      .def_readonly("cx", &CandidateInfo::cx, "principal point [px] (continuous coordinates)")
      .def_readonly("cy", &CandidateInfo::cy, "principal point [px] (continuous coordinates)")
      .def_readonly("near", &CandidateInfo::near, "nearest valid depth [m]")
      .def_readonly("far", &CandidateInfo::far, "farthest valid depth [m]")
      .def_readonly("cost", &CandidateInfo::cost, "unit cost of the type (budget objective)")
      .def_readonly("coverage", &CandidateInfo::coverage,
                    "share of the reference cells it sees alone, 0..1 (None before observe)")
      .def_readonly("observed_voxels", &CandidateInfo::observed_voxels,
                    "reference cells it sees alone (its row sum of Visibility.matrix; None "
                    "before observe)")
      .def_readonly("paper_coverage", &CandidateInfo::paper_coverage,
                    "|O_i| / |R|: cells seen outside R counted too (the paper's score; None "
                    "before observe)")
      .def_readonly("rays_traced", &CandidateInfo::rays_traced,
                    "pixels actually ray cast, after culling (None before observe)")
      .def_readonly("ideal_coverage", &CandidateInfo::ideal_coverage,
                    "observed with the physical sensor model: its coverage under the paper's "
                    "ideal pinhole; else None")
      .def_readonly("plain_coverage", &CandidateInfo::plain_coverage,
                    "observed with a quality filter: its coverage counting every pixel; else None")
      .def_readonly("target_pixels", &CandidateInfo::target_pixels,
                    "with a quality filter: pixels whose first hit is a target in range; else None")
      .def_readonly("quality_pixels", &CandidateInfo::quality_pixels,
                    "with a quality filter: the target pixels that pass it; else None")
      .def("__repr__", [](const CandidateInfo& c) {
        return "<vantage.Candidate " + c.name + " (" + c.type + ")>";
      });

  py::class_<SelectionInfo>(m, "Selection", "A chosen constellation and how good it is.")
      .def_property_readonly(
          "method", [](const SelectionInfo& s) { return s.selection.method; },
          "the method that chose it: best, ransac, greedy, local or exact")
      .def_property_readonly(
          "n", [](const SelectionInfo& s) { return s.selection.n; }, "number of sensors chosen")
      .def_readonly("sensors", &SelectionInfo::sensors,
                    "names of the chosen candidates, in the order chosen")
      .def_property_readonly(
          "indices", [](const SelectionInfo& s) { return s.selection.chosen; },
          "rows of Visibility.matrix (candidate indices) of the chosen, in the order chosen")
      .def_property_readonly(
          "coverage", [](const SelectionInfo& s) { return s.selection.coverage; },
          "|(union of O_i) ∩ R| / |R| of the chosen, 0..1 (k-coverage: the share seen by k)")
      .def_property_readonly(
          "paper_coverage", [](const SelectionInfo& s) { return s.selection.paper_coverage; },
          "|union of O_i| / |R|, cells outside R included (the paper's metric)")
      .def_property_readonly(
          "upper_bound",
          [](const SelectionInfo& s) { return OptionalDouble(s.selection.upper_bound); },
          "proven bound on the best coverage for the same objective and n (exact), else None")
      .def_property_readonly(
          "optimal", [](const SelectionInfo& s) { return s.selection.proven_optimal; },
          "True when proven optimal (coverage == upper_bound, or set cover's least n)")
      .def_property_readonly(
          "objective", [](const SelectionInfo& s) { return s.selection.objective; },
          "coverage, set-cover, k-coverage or budget")
      .def_property_readonly(
          "k", [](const SelectionInfo& s) { return s.selection.k; }, "k of k-coverage (else 1)")
      .def_property_readonly(
          "goal", [](const SelectionInfo& s) { return OptionalDouble(s.selection.goal); },
          "set cover's coverage goal, 0..1, else None")
      .def_property_readonly(
          "budget", [](const SelectionInfo& s) { return OptionalDouble(s.selection.budget); },
          "the budget of the budget objective, else None")
      .def_property_readonly(
          "cost", [](const SelectionInfo& s) { return OptionalDouble(s.selection.cost); },
          "total cost of the chosen (budget objective), else None")
      .def_property_readonly(
          "n_lower_bound", [](const SelectionInfo& s) { return s.selection.n_lower_bound; },
          "set cover: proven least number of sensors, else None")
      .def_property_readonly(
          "seconds", [](const SelectionInfo& s) { return s.selection.seconds; },
          "time the method took [s]")
      .def_property_readonly(
          "gap",
          [](const SelectionInfo& s) {
            return s.selection.upper_bound
                       ? OptionalDouble(std::max(0.0, *s.selection.upper_bound - s.selection.coverage))
                       : OptionalDouble(std::nullopt);
          },
          "upper_bound - coverage (>= 0) where a bound is proven, else None")
      .def_property_readonly(
          "min_points", [](const SelectionInfo& s) { return s.selection.min_points; },
          "point density: the points a cell needed (min_points, min_density), else None")
      .def_property_readonly(
          "cost_lower_bound",
          [](const SelectionInfo& s) { return OptionalDouble(s.selection.cost_lower_bound); },
          "cheapest with exact: proven least cost of any layout reaching the goal, else None")
      .def_readonly("ideal_coverage", &SelectionInfo::ideal_coverage,
                    "observed with the physical sensor model: the same sensors' coverage under "
                    "the paper's ideal pinhole (its k); else None")
      .def_readonly("plain_coverage", &SelectionInfo::plain_coverage,
                    "observed with a quality filter: the same sensors' coverage counting every "
                    "pixel; else None")
      .def_readonly("ceiling", &SelectionInfo::ceiling,
                    "the coverage of all candidates together, counted as this result counts (k, "
                    "min_points): what no selection exceeds (report.json's ceiling.coverage)")
      .def_property_readonly(
          "part_coverage",
          [](const SelectionInfo& s) -> py::object {
            if (s.part_coverage.empty()) return py::none();
            py::dict parts;
            for (const auto& [name, share] : s.part_coverage) parts[py::str(name)] = share;
            return parts;
          },
          "per target part (by name, in R's order) the share of its cells covered; None when "
          "R does not know its parts (a matrix from elsewhere, an old .vis)")
      .def_readonly("constraints", &SelectionInfo::constraints,
                    "with installation constraints: report.json's result constraints (satisfied, "
                    "conflicts, overlap_graph, ...) as a dict; else None")
      .def("__repr__", [](const SelectionInfo& s) {
        return "<vantage.Selection " + s.selection.method + " n=" + std::to_string(s.selection.n) +
               " coverage=" + std::to_string(s.selection.coverage) + ">";
      });

  py::class_<VisibilityHandle>(m, "Visibility",
                               "The visibility matrix of an observed scene: which reference "
                               "cells each candidate sees, with R and the candidates.")
      .def_property_readonly(
          "matrix",
          [](VisibilityHandle& v) {
            if (!v.matrix) v.matrix = MatrixOf(*v.data);
            return v.matrix;
          },
          "scipy.sparse.csr_matrix of shape (candidates, reference cells), float64, 1.0 where "
          "the candidate sees the cell (its observation set O_i, quality filter applied). Built "
          "once, on first use, then shared.")
      .def_property_readonly(
          "reference",
          [](const VisibilityHandle& v) {
            const Reference& r = v.data->reference;
            py::array_t<double> centres({static_cast<py::ssize_t>(r.size()), py::ssize_t{3}});
            double* out = centres.mutable_data();
            for (size_t i = 0; i < r.size(); ++i) {
              const Vec3 c = VoxelCenter(r.keys[i], r.cell_size);
              for (int a = 0; a < 3; ++a) out[3 * i + static_cast<size_t>(a)] = c[a];
            }
            return centres;
          },
          "numpy array (R, 3): centres of the reference cells in the world [m], in the order of "
          "the matrix's columns")
      .def_property_readonly(
          "reference_keys",
          [](const VisibilityHandle& v) {
            const std::vector<uint64_t>& keys = v.data->reference.keys;
            return py::array_t<uint64_t>(static_cast<py::ssize_t>(keys.size()), keys.data());
          },
          "numpy uint64 array (R,): the packed cell keys (21 bits per axis, offset 2^20, x "
          "highest), ascending")
      .def_property_readonly(
          "cell_size", [](const VisibilityHandle& v) { return v.data->reference.cell_size; },
          "edge of the cubic cells F [m]")
      .def_property_readonly(
          "candidates", [](const VisibilityHandle& v) { return CandidatesOf(*v.data); },
          "list of vantage.Candidate in row order, with coverage and observed_voxels")
      .def_property_readonly(
          "scene", [](const VisibilityHandle& v) { return v.data->scene; },
          "path of the scene it was observed in")
      .def_property_readonly(
          "seed", [](const VisibilityHandle& v) { return v.data->seed; },
          "the run's seed (selection's default)")
      .def_property_readonly(
          "physical", [](const VisibilityHandle& v) { return v.data->physical; },
          "True when observed with the physical sensor model, False for the ideal pinhole")
      .def_property_readonly(
          "exposed_only", [](const VisibilityHandle& v) { return v.data->reference.exposed_only; },
          "True when R holds only exposed surface (exposed_only=True)")
      .def_property_readonly(
          "parts", [](const VisibilityHandle& v) { return v.data->reference.part_names; },
          "R's target parts by name, in scene order (report.json ceiling.parts); empty when R "
          "does not know them (a matrix from elsewhere, an old .vis)")
      .def_property_readonly(
          "reference_parts",
          [](const VisibilityHandle& v) -> py::object {
            const Reference& r = v.data->reference;
            if (r.part_names.empty() || r.part_of.size() != r.size()) return py::none();
            return py::array_t<uint32_t>(static_cast<py::ssize_t>(r.part_of.size()),
                                         r.part_of.data());
          },
          "numpy uint32 array (R,): each cell's part, an index into parts (column order); None "
          "when R does not know its parts")
      .def_property_readonly(
          "reference_exposed",
          [](const VisibilityHandle& v) -> py::object {
            const Reference& r = v.data->reference;
            if (r.exposed.size() != r.size()) return py::none();
            py::array_t<bool> exposed(static_cast<py::ssize_t>(r.size()));
            bool* out = exposed.mutable_data();
            for (size_t i = 0; i < r.size(); ++i) out[i] = r.exposed[i] != 0;
            return exposed;
          },
          "numpy bool array (R,): True where some viewpoint could see the cell, False for "
          "surface resting on or enclosed by other geometry (report.json's unexposed cells); "
          "None when exposure was not computed")
      .def_property_readonly(
          "quality",
          [](const VisibilityHandle& v) {
            py::dict quality;
            const QualityFilter& q = v.data->quality;
            quality["max_incidence"] = OptionalDouble(q.max_incidence_deg);
            quality["max_depth_noise"] = q.max_depth_noise
                                             ? py::object(py::float_(*q.max_depth_noise * 1000.0))
                                             : py::object(py::none());
            return quality;
          },
          "the quality filter the sets were made with: max_incidence [deg], max_depth_noise [mm]")
      .def(
          "select",
          [](const VisibilityHandle& v, const py::object& n, const py::object& method,
             const py::object& time_limit, const py::object& k, const py::object& goal,
             const py::object& budget, const py::object& iterations, const py::object& stop,
             const py::object& seed, const py::object& threads, const py::object& interference,
             const py::object& interference_overlap, const py::object& calibration_overlap,
             const py::object& calibration_overlap_frac, const py::object& min_points,
             const py::object& min_density, const py::object& cheapest,
             const py::object& keep_existing) {
            const std::optional<std::string> method_name = TextOf(method, "method");
            if (!method_name)
              throw py::type_error("method: give a str (best, ransac, greedy, local or exact), "
                                   "not NoneType");
            const Method chosen = MethodOf(*method_name);
            if (chosen == Method::kAll)
              throw InputError(AtPlace("method", 0,
                                       "'all' gives one result per method and n — use "
                                       "select_all(), or name one method"));
            SelectionRequest request = RequestOf(
                {{"n", &n}, {"time_limit", &time_limit}, {"k", &k}, {"goal", &goal},
                 {"budget", &budget}, {"iterations", &iterations}, {"stop", &stop},
                 {"min_points", &min_points}, {"min_density", &min_density},
                 {"cheapest", &cheapest}, {"keep_existing", &keep_existing}});
            request.method = chosen;
            SetConstraintKeywords(&request.constraints, interference, interference_overlap,
                                  calibration_overlap, calibration_overlap_frac);
            std::vector<SelectionInfo> results =
                SelectOn(*v.data, request, UnsignedOf(seed, "seed"), Method::kExact, threads);
            return std::move(results.back());
          },
          py::arg("n") = py::none(), py::arg("method") = "exact",
          py::arg("time_limit") = py::none(), py::arg("k") = py::none(),
          py::arg("goal") = py::none(), py::arg("budget") = py::none(), py::kw_only(),
          py::arg("iterations") = py::none(), py::arg("stop") = py::none(),
          py::arg("seed") = py::none(), py::arg("threads") = py::none(),
          py::arg("interference") = py::none(), py::arg("interference_overlap") = py::none(),
          py::arg("calibration_overlap") = py::none(),
          py::arg("calibration_overlap_frac") = py::none(), py::arg("min_points") = py::none(),
          py::arg("min_density") = py::none(), py::arg("cheapest") = false,
          py::arg("keep_existing") = false,
          "Chooses n sensors with one method, as `vantage select FILE -n N --method M`.\n\n"
          "n: sensors (None: the scene's n); method: best, ransac, greedy, local or exact;\n"
          "time_limit: seconds for exact (None: 60); k: k-coverage when >= 2; goal: set cover,\n"
          "the fewest sensors reaching this coverage fraction; budget: the most coverage for a\n"
          "total cost within it; iterations, stop: RANSAC's cap and stop coverage (fraction).\n"
          "None takes the scene's own setting (goal, k and budget given replace its objective).\n"
          "seed: None for the run's; threads: None for all cores (same result for any).\n"
          "interference, interference_overlap, calibration_overlap, calibration_overlap_frac:\n"
          "the installation constraints (docs/constraints.md), as the CLI's flags; min_points,\n"
          "min_density: point density (docs/constraints.md, \"Point density\"); cheapest: with\n"
          "goal, the cheapest sensors reaching it (--cheapest); keep_existing: every answer keeps\n"
          "the sensors the scene declares (--keep-existing; n counts them).\n"
          "Returns a vantage.Selection; raises InputError for invalid options.")
      .def(
          "select_all",
          [](const VisibilityHandle& v, const py::object& n, const py::object& method,
             const py::object& time_limit, const py::object& k, const py::object& goal,
             const py::object& budget, const py::object& iterations, const py::object& stop,
             const py::object& seed, const py::object& threads, const py::object& interference,
             const py::object& interference_overlap, const py::object& calibration_overlap,
             const py::object& calibration_overlap_frac, const py::object& min_points,
             const py::object& min_density, const py::object& cheapest,
             const py::object& keep_existing) {
            SelectionRequest request = RequestOf(
                {{"n", &n}, {"method", &method}, {"time_limit", &time_limit}, {"k", &k},
                 {"goal", &goal}, {"budget", &budget}, {"iterations", &iterations},
                 {"stop", &stop}, {"min_points", &min_points}, {"min_density", &min_density},
                 {"cheapest", &cheapest}, {"keep_existing", &keep_existing}});
            SetConstraintKeywords(&request.constraints, interference, interference_overlap,
                                  calibration_overlap, calibration_overlap_frac);
            return SelectOn(*v.data, request, UnsignedOf(seed, "seed"), Method::kAll, threads);
          },
          py::arg("n") = py::none(), py::arg("method") = py::none(),
          py::arg("time_limit") = py::none(), py::arg("k") = py::none(),
          py::arg("goal") = py::none(), py::arg("budget") = py::none(), py::kw_only(),
          py::arg("iterations") = py::none(), py::arg("stop") = py::none(),
          py::arg("seed") = py::none(), py::arg("threads") = py::none(),
          py::arg("interference") = py::none(), py::arg("interference_overlap") = py::none(),
          py::arg("calibration_overlap") = py::none(),
          py::arg("calibration_overlap_frac") = py::none(), py::arg("min_points") = py::none(),
          py::arg("min_density") = py::none(), py::arg("cheapest") = false,
          py::arg("keep_existing") = false,
          "Every result of `vantage select FILE` (report.json's `results`, in order): with\n"
          "method None or 'all', best for n = 1, then ransac, greedy, local and exact for each\n"
          "n from 1 to n. Arguments as select(). Returns a list of vantage.Selection.")
      .def_static("from_matrix", &FromMatrix, py::arg("csr"), py::kw_only(),
                  py::arg("cells") = py::none(), py::arg("names") = py::none(),
                  py::arg("costs") = py::none(), py::arg("states") = py::none(),
                  "A Visibility of a matrix computed elsewhere (another simulator, a real\n"
                  "capture, a set-cover benchmark), which select(), select_all() and save() take\n"
                  "as one loaded from a .vis file; save() writes the .vis that `vantage select\n"
                  "FILE` reads (scripts/vis_writer.py writes the same file in plain Python).\n\n"
                  "csr: candidates x cells, a scipy.sparse CSR matrix or (indptr, indices) or\n"
                  "(indptr, indices, data) arrays; each row's indices sorted and unique; data, when\n"
                  "given (a SciPy matrix's always is), are point counts per cell for min_points:\n"
                  "whole numbers >= 1 (a 0/1 matrix: one point each; stored at most 65535).\n"
                  "cells: the number of cells (columns), needed with arrays; names: one str per\n"
                  "row, distinct (None: c0, c1, ...); costs: one number >= 0 per row, the budget\n"
                  "objective's (None: 1 each); states: not supported (a .vis holds one state):\n"
                  "InputError when given.\n"
                  "Candidates get placeholder sensors and poses, cells placeholder 1 cm keys.\n"
                  "Raises TypeError or InputError naming the argument for bad input.")
      .def(
          "save",
          [](const VisibilityHandle& v, const py::object& path) {
            const std::string file = PathOf(path, "path");
            WithoutGil(py::none(), [&] { SaveVisibilityFile(file, *v.data); });
          },
          py::arg("path"),
          "Writes the matrix as a .vis file (the format of `vantage observe --out`, "
          "docs/outputs.md), atomically; `vantage select` and load_visibility() read it.")
      .def("__repr__", [](const VisibilityHandle& v) {
        return "<vantage.Visibility " + std::to_string(v.data->candidates.size()) +
               " candidates x " + std::to_string(v.data->reference.size()) + " cells>";
      });

  py::class_<ProblemHandle>(m, "Problem",
                            "A loaded scene with its candidates deployed, before any ray is "
                            "cast (vantage.load). Immutable: observe() may run from several "
                            "threads at once.")
      .def_property_readonly(
          "source", [](const ProblemHandle& p) { return PathText(p.prepared->problem.source); },
          "path of the scene file")
      .def_property_readonly(
          "cell_size", [](const ProblemHandle& p) { return p.prepared->problem.cell_size; },
          "edge of the cubic cells F [m] (the scene's, or load's cell_size)")
      .def_property_readonly(
          "seed", [](const ProblemHandle& p) { return p.prepared->problem.seed; }, "the run's seed")
      .def_property_readonly(
          "n", [](const ProblemHandle& p) { return p.prepared->problem.selection.n; },
          "the scene's number of sensors wanted")
      .def_property_readonly(
          "candidates",
          [](const ProblemHandle& p) {
            std::vector<CandidateInfo> list;
            for (const Candidate& c : p.prepared->candidates) list.push_back(InfoOf(c));
            return list;
          },
          "list of vantage.Candidate as deployed (coverage None until observed)")
      .def_property_readonly(
          "states",
          [](const ProblemHandle& p) {
            Strings names;
            for (const SceneState& s : p.prepared->problem.states) names.push_back(s.name);
            return names;
          },
          "names of the scene's states (empty when it does not change)")
      .def(
          "observe",
          [](const ProblemHandle& p, const py::object& quality, const py::object& threads,
             const py::object& progress, const py::object& cull, const py::object& max_memory,
             const py::object& physical, const py::object& max_seconds, const py::object& n) {
            const ObserveOptions options = ObserveOptionsOf(quality, cull, progress, physical);
            const RunLimits limits = LimitsOf(max_memory, max_seconds);
            const std::optional<int> sensors = IntOf(n, "n");
            const std::shared_ptr<const PreparedScene> prepared = p.prepared;
            VisibilityHandle result;
            result.data = WithoutGil(threads, [&] {
              PreparedScene scene = *prepared;
              if (sensors) {
                // As ObserveRun's -n: checked before any ray, then stored with the matrix.
                SelectionRequest request;
                request.n = sensors;
                ResolveSelection(scene.problem.selection, request, scene.problem.seed,
                                 scene.candidates, scene.problem.source, Method::kAll);
                scene.problem.selection.n = *sensors;
              }
              ObservedScene observed = ObservePrepared(std::move(scene), options, limits);
              return std::make_shared<const VisibilityFile>(std::move(observed.data));
            });
            return result;
          },
          py::arg("quality") = py::none(), py::arg("threads") = py::none(),
          py::arg("progress") = py::none(), py::kw_only(), py::arg("cull") = true,
          py::arg("max_memory") = py::none(), py::arg("physical") = py::none(),
          py::arg("max_seconds") = py::none(), py::arg("n") = py::none(),
          "Builds R and ray casts every candidate's depth image, as `vantage observe`; the GIL\n"
          "is released meanwhile.\n\n"
          "quality: None or {'max_incidence': deg, 'max_depth_noise': mm} (a pixel counts only\n"
          "when it meets that quality); threads: worker threads (None: all cores; the result is\n"
          "the same for any); progress: None or a callable progress(done, total), called from\n"
          "worker threads; cull: False traces every pixel (slower, same result); max_memory:\n"
          "refuse runs estimated above this many MiB (None: 75 % of the RAM); physical: True\n"
          "the physical sensor model (--physical), False the paper's ideal pinhole (--ideal),\n"
          "None the default (physical, ideal for a Gazebo world of the paper's system);\n"
          "max_seconds: refuse runs whose ray casting is estimated above this (None: no limit);\n"
          "n: the default number of sensors stored with the matrix (observe's -n).\n"
          "A scene with states: the first state's matrix (optimize() selects over all).\n"
          "Returns a vantage.Visibility.")
      .def("__repr__", [](const ProblemHandle& p) {
        return PathText("<vantage.Problem " + p.prepared->problem.source + ": " +
                        std::to_string(p.prepared->candidates.size()) + " candidates>");
      });

  m.def(
      "load",
      [](const py::object& path, const py::object& model_path, const py::object& resource_path,
         const py::object& targets, const py::object& cell_size, const py::object& seed,
         const py::object& observation_point, const py::object& random_roll,
         const py::object& package_path, const py::object& exposed_only) {
        const SceneInput input =
            SceneInputOf("path", path,
                         {model_path, resource_path, package_path, targets, cell_size, seed,
                          observation_point, random_roll, exposed_only});
        ProblemHandle problem;
        problem.prepared = WithoutGil(
            py::none(), [&] { return std::make_shared<const PreparedScene>(Prepare(input)); });
        return problem;
      },
      py::arg("path"), py::kw_only(), py::arg("model_path") = py::none(),
      py::arg("resource_path") = py::none(), py::arg("targets") = py::none(),
      py::arg("cell_size") = py::none(), py::arg("seed") = py::none(),
      py::arg("observation_point") = py::none(), py::arg("random_roll") = py::none(),
      py::arg("package_path") = py::none(), py::arg("exposed_only") = false,
      "Loads a scene (.yaml/.yml, docs/scene-format.md) or a Gazebo world (.world/.sdf) and\n"
      "deploys its candidate sensors, as the CLI's commands do before any ray is cast.\n\n"
      "model_path, resource_path: a folder or a list of folders (--model-path,\n"
      "--resource-path); targets: a name or a list overriding the scene's targets; cell_size:\n"
      "F [m] overriding the scene's; seed: None for the scene's (else 1); observation_point:\n"
      "(x, y, z) [m] every candidate looks at; random_roll: True/False. None keeps the scene's.\n"
      "package_path: a folder or a list where a URDF's package:// paths are found\n"
      "(--package-path); exposed_only: R holds only surface some viewpoint can see\n"
      "(--exposed-only; default False, the paper's metric).\n"
      "Returns a vantage.Problem; raises InputError ('file:line: ...') for a broken scene.");

  m.def(
      "load_visibility",
      [](const py::object& path) {
        const std::string file = PathOf(path, "path");
        VisibilityHandle result;
        result.data = WithoutGil(py::none(), [&] {
          return std::make_shared<const VisibilityFile>(LoadVisibilityFile(file));
        });
        return result;
      },
      py::arg("path"),
      "Reads a .vis file written by Visibility.save() or `vantage observe --out`. Returns a\n"
      "vantage.Visibility; raises InputError naming the file when it is not one, is corrupt or\n"
      "of another format version.");

  m.def(
      "optimize",
      [](const py::object& scene, const py::object& n, const py::object& method,
         const py::object& out, const py::object& model_path, const py::object& resource_path,
         const py::object& targets, const py::object& cell_size, const py::object& seed,
         const py::object& observation_point, const py::object& random_roll,
         const py::object& quality, const py::object& cull, const py::object& max_memory,
         const py::object& iterations, const py::object& stop, const py::object& time_limit,
         const py::object& goal, const py::object& k, const py::object& budget,
         const py::object& over_states, const py::object& fov_tolerance,
         const py::object& alternatives_within, const py::object& refine_value,
         const py::object& refine_rounds_value, const py::object& threads,
         const py::object& progress, const py::object& interference,
         const py::object& interference_overlap, const py::object& calibration_overlap,
         const py::object& calibration_overlap_frac, const py::object& min_points,
         const py::object& min_density, const py::object& package_path,
         const py::object& exposed_only, const py::object& physical,
         const py::object& max_seconds, const py::object& cheapest,
         const py::object& keep_existing, const py::object& pose_tolerance,
         const py::object& pose_samples, const py::object& by_type,
         const py::object& cycle_time, const py::object& joint_speed, const py::object& frames,
         const py::object& motion_resolution, const py::object& plan_time,
         const py::object& track, const py::object& move_penalty,
         const py::object& state_interval, const py::object& over_parts) {
        const bool refine = FlagOf(refine_value, "refine", false);
        const std::optional<int> refine_rounds = IntOf(refine_rounds_value, "refine_rounds");
        OptimizeOptions options;
        options.scene = SceneInputOf("scene", scene,
                                     {model_path, resource_path, package_path, targets, cell_size,
                                      seed, observation_point, random_roll, exposed_only});
        options.observe = ObserveOptionsOf(quality, cull, progress, physical);
        options.limits = LimitsOf(max_memory, max_seconds);
        options.selection = RequestOf(
            {{"n", &n}, {"method", &method}, {"iterations", &iterations}, {"stop", &stop},
             {"time_limit", &time_limit}, {"goal", &goal}, {"cheapest", &cheapest}, {"k", &k},
             {"budget", &budget}, {"min_points", &min_points}, {"min_density", &min_density},
             {"over_states", &over_states}, {"over_parts", &over_parts},
             {"keep_existing", &keep_existing}});
        SetConstraintKeywords(&options.selection.constraints, interference, interference_overlap,
                              calibration_overlap, calibration_overlap_frac);
        options.robustness = RobustnessOf(fov_tolerance, alternatives_within);
        options.pose_tolerance = PoseToleranceOf(pose_tolerance, pose_samples);
        options.by_type = FlagOf(by_type, "by_type", false);
        options.arm = ArmTourOf(cycle_time, joint_speed, frames, motion_resolution, plan_time,
                                track, move_penalty, state_interval);
        if (refine_rounds && !refine)  // as the CLI's --refine-rounds without --refine
          throw InputError("refine_rounds: only refine=True runs rounds — pass refine=True, or "
                           "leave refine_rounds out");
        if (refine) {
          RefineOptions refine_options;
          if (refine_rounds) refine_options.max_rounds = *refine_rounds;
          options.refine = refine_options;
        }
        const std::optional<std::string> out_dir = OutDirOf(out);
        const std::string report = WithoutGil(threads, [&] {
          const RunResult run = Optimize(options);
          if (out_dir) WriteRun(*out_dir, run);
          return run.files.at("report.json");
        });
        return JsonOf(report);
      },
      py::arg("scene"), py::arg("n") = py::none(), py::arg("method") = py::none(),
      py::arg("out") = py::none(), py::kw_only(), py::arg("model_path") = py::none(),
      py::arg("resource_path") = py::none(), py::arg("targets") = py::none(),
      py::arg("cell_size") = py::none(), py::arg("seed") = py::none(),
      py::arg("observation_point") = py::none(), py::arg("random_roll") = py::none(),
      py::arg("quality") = py::none(), py::arg("cull") = true, py::arg("max_memory") = py::none(),
      py::arg("iterations") = py::none(), py::arg("stop") = py::none(),
      py::arg("time_limit") = py::none(), py::arg("goal") = py::none(), py::arg("k") = py::none(),
      py::arg("budget") = py::none(), py::arg("over_states") = py::none(),
      py::arg("fov_tolerance") = py::none(), py::arg("alternatives_within") = py::none(),
      py::arg("refine") = false, py::arg("refine_rounds") = py::none(),
      py::arg("threads") = py::none(), py::arg("progress") = py::none(),
      py::arg("interference") = py::none(), py::arg("interference_overlap") = py::none(),
      py::arg("calibration_overlap") = py::none(), py::arg("calibration_overlap_frac") = py::none(),
      py::arg("min_points") = py::none(), py::arg("min_density") = py::none(),
      py::arg("package_path") = py::none(), py::arg("exposed_only") = false,
      py::arg("physical") = py::none(), py::arg("max_seconds") = py::none(),
      py::arg("cheapest") = false, py::arg("keep_existing") = false,
      py::arg("pose_tolerance") = py::none(), py::arg("pose_samples") = py::none(),
      py::arg("by_type") = false, py::arg("cycle_time") = py::none(),
      py::arg("joint_speed") = py::none(), py::arg("frames") = py::none(),
      py::arg("motion_resolution") = py::none(), py::arg("plan_time") = py::none(),
      py::arg("track") = false, py::arg("move_penalty") = py::none(),
      py::arg("state_interval") = py::none(), py::arg("over_parts") = py::none(),
      std::string(
          "The whole pipeline, as `vantage optimize SCENE`: the same outputs (report.json,\n"
          "report.html, candidates.csv, ...) written atomically into the folder `out` (None: none\n"
          "written). Returns report.json as a dict (docs/outputs.md).\n\n"
          "Each keyword is the CLI flag of the same name (docs/python.md lists them): n, method\n"
          "('all' by default: every method), model_path, resource_path, targets, cell_size, seed,\n"
          "observation_point, random_roll, quality ({'max_incidence': deg, 'max_depth_noise':\n"
          "mm}), cull, max_memory [MiB], iterations, stop, time_limit [s], goal, k, budget,\n"
          "over_states (" +
          OverStatesKeywordValues() +
          "), fov_tolerance [deg], alternatives_within [points],\n"
          "refine, refine_rounds, threads, progress, interference, interference_overlap,\n"
          "calibration_overlap, calibration_overlap_frac, min_points, min_density, package_path,\n"
          "exposed_only, physical (True: --physical, False: --ideal, None: the default),\n"
          "max_seconds, cheapest, keep_existing, pose_tolerance ((metres, degrees): "
          "--pose-tolerance\n"
          "P,A), pose_samples, by_type, and a camera on an arm's cycle_time [s], joint_speed,\n"
          "frames, motion_resolution, plan_time [s], track, move_penalty, state_interval [s],\n"
          "over_parts ('mean'/'min': the parts' coverages' mean or worst).\n"
          "None keeps the scene's setting (or the CLI's default).")
          .c_str());

  m.def(
      "select",
      [](const py::object& file, const py::object& n, const py::object& method,
         const py::object& out, const py::object& iterations, const py::object& stop,
         const py::object& time_limit, const py::object& goal, const py::object& k,
         const py::object& budget, const py::object& cheapest, const py::object& keep_existing,
         const py::object& over_states, const py::object& seed, const py::object& fov_tolerance,
         const py::object& alternatives_within, const py::object& pose_tolerance,
         const py::object& pose_samples, const py::object& threads,
         const py::object& interference, const py::object& interference_overlap,
         const py::object& calibration_overlap, const py::object& calibration_overlap_frac,
         const py::object& min_points, const py::object& min_density,
         const py::object& over_parts, const py::object& cycle_time,
         const py::object& joint_speed, const py::object& frames,
         const py::object& motion_resolution, const py::object& plan_time) {
        SelectFileOptions options;
        options.visibility_file = PathOf(file, "file");
        options.selection = RequestOf(
            {{"n", &n}, {"method", &method}, {"iterations", &iterations}, {"stop", &stop},
             {"time_limit", &time_limit}, {"goal", &goal}, {"cheapest", &cheapest}, {"k", &k},
             {"budget", &budget}, {"min_points", &min_points}, {"min_density", &min_density},
             {"over_states", &over_states}, {"over_parts", &over_parts},
             {"keep_existing", &keep_existing}});
        SetConstraintKeywords(&options.selection.constraints, interference, interference_overlap,
                              calibration_overlap, calibration_overlap_frac);
        options.seed = UnsignedOf(seed, "seed");
        options.robustness = RobustnessOf(fov_tolerance, alternatives_within);
        options.pose_tolerance = PoseToleranceOf(pose_tolerance, pose_samples);
        // A file of a camera on an arm (format 11): its tours, as select FILE's flags.
        options.arm = ArmTourOf(cycle_time, joint_speed, frames, motion_resolution, plan_time,
                                py::none(), py::none(), py::none());
        const std::optional<std::string> out_dir = OutDirOf(out);
        const std::string report = WithoutGil(threads, [&] {
          const RunResult run = SelectFromFile(options);
          if (out_dir) WriteRun(*out_dir, run);
          return run.files.at("report.json");
        });
        return JsonOf(report);
      },
      py::arg("file"), py::arg("n") = py::none(), py::arg("method") = py::none(),
      py::arg("out") = py::none(), py::kw_only(), py::arg("iterations") = py::none(),
      py::arg("stop") = py::none(), py::arg("time_limit") = py::none(),
      py::arg("goal") = py::none(), py::arg("k") = py::none(), py::arg("budget") = py::none(),
      py::arg("cheapest") = false, py::arg("keep_existing") = false,
      py::arg("over_states") = py::none(), py::arg("seed") = py::none(),
      py::arg("fov_tolerance") = py::none(), py::arg("alternatives_within") = py::none(),
      py::arg("pose_tolerance") = py::none(), py::arg("pose_samples") = py::none(),
      py::arg("threads") = py::none(), py::arg("interference") = py::none(),
      py::arg("interference_overlap") = py::none(), py::arg("calibration_overlap") = py::none(),
      py::arg("calibration_overlap_frac") = py::none(), py::arg("min_points") = py::none(),
      py::arg("min_density") = py::none(), py::arg("over_parts") = py::none(),
      py::arg("cycle_time") = py::none(), py::arg("joint_speed") = py::none(),
      py::arg("frames") = py::none(), py::arg("motion_resolution") = py::none(),
      py::arg("plan_time") = py::none(),
      "`vantage select FILE`: selection from a .vis file (Visibility.save(), `vantage\n"
      "observe --out`) with the assessment of the CLI's run, robustness and pose tolerance\n"
      "included, its files written atomically into `out` (None: none). Returns report.json\n"
      "as a dict. Keywords as optimize()'s selection keywords (method None: 'all'), plus\n"
      "seed (None: the file's), fov_tolerance, alternatives_within, pose_tolerance,\n"
      "pose_samples, and for a camera on an arm (docs/arm.md) cycle_time [s], joint_speed,\n"
      "frames, motion_resolution, plan_time [s]. For one result as an object, use\n"
      "Visibility.select().");

  m.def(
      "evaluate",
      [](const py::object& scene, const py::object& constellation, const py::object& out,
         const py::object& model_path, const py::object& resource_path, const py::object& targets,
         const py::object& cell_size, const py::object& seed, const py::object& quality,
         const py::object& cull, const py::object& max_memory, const py::object& threads,
         const py::object& progress, const py::object& interference,
         const py::object& interference_overlap, const py::object& calibration_overlap,
         const py::object& calibration_overlap_frac, const py::object& min_points,
         const py::object& min_density, const py::object& observation_point,
         const py::object& random_roll, const py::object& package_path,
         const py::object& exposed_only, const py::object& physical,
         const py::object& max_seconds, const py::object& pose_tolerance,
         const py::object& pose_samples) {
        EvaluateOptions options;
        options.scene = SceneInputOf("scene", scene,
                                     {model_path, resource_path, package_path, targets, cell_size,
                                      seed, observation_point, random_roll, exposed_only});
        // None: the layout the scene declares itself (the CLI's evaluate without --constellation).
        options.constellation = OptionalPathOf(constellation, "constellation").value_or("");
        options.observe = ObserveOptionsOf(quality, cull, progress, physical);
        options.limits = LimitsOf(max_memory, max_seconds);
        SetConstraintKeywords(&options.constraints, interference, interference_overlap,
                              calibration_overlap, calibration_overlap_frac);
        options.min_points = WholeOf(min_points, "min_points", std::numeric_limits<int64_t>::min(),
                                     std::numeric_limits<int64_t>::max());
        options.min_density = RealOf(min_density, "min_density");
        options.pose_tolerance = PoseToleranceOf(pose_tolerance, pose_samples);
        const std::optional<std::string> out_dir = OutDirOf(out);
        struct Outcome {
          Strings sensors;
          std::vector<double> sensor_coverage;
          double coverage = 0, paper_coverage = 0;
          std::string report;
        };
        const Outcome outcome = WithoutGil(threads, [&] {
          const EvaluateResult result = Evaluate(options);
          if (out_dir) WriteRun(*out_dir, result.run);
          Outcome o;
          for (const Candidate& c : result.run.data->candidates) o.sensors.push_back(c.name);
          o.sensor_coverage = result.sensor_coverage;
          const Selection& given = result.run.report.results.front();
          o.coverage = given.coverage;
          o.paper_coverage = given.paper_coverage;
          o.report = result.run.files.at("report.json");
          return o;
        });
        py::dict result;
        result["sensors"] = outcome.sensors;
        result["sensor_coverage"] = outcome.sensor_coverage;
        result["coverage"] = outcome.coverage;
        result["paper_coverage"] = outcome.paper_coverage;
        result["report"] = JsonOf(outcome.report);
        return result;
      },
      py::arg("scene") = py::none(), py::kw_only(), py::arg("constellation") = py::none(),
      py::arg("out") = py::none(), py::arg("model_path") = py::none(),
      py::arg("resource_path") = py::none(), py::arg("targets") = py::none(),
      py::arg("cell_size") = py::none(), py::arg("seed") = py::none(),
      py::arg("quality") = py::none(), py::arg("cull") = true, py::arg("max_memory") = py::none(),
      py::arg("threads") = py::none(), py::arg("progress") = py::none(),
      py::arg("interference") = py::none(), py::arg("interference_overlap") = py::none(),
      py::arg("calibration_overlap") = py::none(), py::arg("calibration_overlap_frac") = py::none(),
      py::arg("min_points") = py::none(), py::arg("min_density") = py::none(),
      py::arg("observation_point") = py::none(), py::arg("random_roll") = py::none(),
      py::arg("package_path") = py::none(), py::arg("exposed_only") = false,
      py::arg("physical") = py::none(), py::arg("max_seconds") = py::none(),
      py::arg("pose_tolerance") = py::none(), py::arg("pose_samples") = py::none(),
      "The coverage of given sensor poses, as `vantage evaluate [SCENE] --constellation\n"
      "FILE`: the primary result's sensors of a report.json (or all candidates of a\n"
      "constellation file). scene None, and options left None, take the constellation run's\n"
      "own (its report.json `inputs`). constellation None: the sensors the scene declares (a\n"
      "gz-sim world's cameras, a YAML scene's `sensors:`). out: also write a report folder.\n"
      "interference, interference_overlap, calibration_overlap(_frac): the constraints the\n"
      "layout is checked against (the CLI's flags); min_points, min_density, observation_point,\n"
      "random_roll, package_path, exposed_only, physical (None: the run's model), max_seconds,\n"
      "pose_tolerance ((metres, degrees)) and pose_samples as optimize() and the CLI's flags.\n"
      "Returns a dict: sensors (names), sensor_coverage (each alone, 0..1), coverage and\n"
      "paper_coverage of them together, report (report.json as a dict).");

  m.def(
      "render",
      [](const py::object& run, const py::object& png, const py::object& eye,
         const py::object& look_at, const py::object& width, const py::object& height,
         const py::object& fov, const py::object& frusta, const py::object& from_below,
         const py::object& legend, const py::object& scene, const py::object& model_path,
         const py::object& resource_path, const py::object& package_path,
         const py::object& targets, const py::object& arm_view, const py::object& threads) {
        RenderRunOptions options;
        options.run = PathOf(run, "run");
        options.png = OptionalPathOf(png, "png").value_or("");
        if (!png.is_none() && options.png.empty())
          throw InputError("png: the path is empty — give the PNG file to write, or None for "
                           "view.png in the run's folder");
        options.scene = SceneInputOf("scene", scene,
                                     {model_path, resource_path, package_path, targets,
                                      py::none(), py::none(), py::none(), py::none(),
                                      py::none()});
        RenderOptions& render = options.render;
        if (const auto point = PointOf(eye, "eye")) render.eye = Vec3((*point)[0], (*point)[1], (*point)[2]);
        if (const auto point = PointOf(look_at, "look_at"))
          render.look_at = Vec3((*point)[0], (*point)[1], (*point)[2]);
        // The CLI's ranges (--width, --height 16..8192; --fov 1..170 degrees), named here.
        if (const auto pixels = WholeOf(width, "width", 16, 8192)) render.width = static_cast<int>(*pixels);
        if (const auto pixels = WholeOf(height, "height", 16, 8192)) render.height = static_cast<int>(*pixels);
        if (const auto degrees = RealOf(fov, "fov")) {
          if (!(*degrees >= 1 && *degrees <= 170))
            throw InputError(fmt::format("fov: {} is out of range — give 1 to 170 degrees",
                                         *degrees));
          render.vertical_fov = *degrees * std::numbers::pi / 180.0;
        }
        render.draw_frusta = FlagOf(frusta, "frusta", true);
        render.from_below = FlagOf(from_below, "from_below", false);
        render.draw_legend = FlagOf(legend, "legend", true);
        options.arm_view = IntOf(arm_view, "arm_view");
        const RenderRunResult result = WithoutGil(threads, [&] { return RenderRun(options); });
        py::dict outcome;
        outcome["png"] = PathText(result.png);
        outcome["sensors"] = result.sensors;
        outcome["coverage"] = result.coverage;
        return outcome;
      },
      py::arg("run"), py::arg("png") = py::none(), py::kw_only(), py::arg("eye") = py::none(),
      py::arg("look_at") = py::none(), py::arg("width") = py::none(),
      py::arg("height") = py::none(), py::arg("fov") = py::none(), py::arg("frusta") = true,
      py::arg("from_below") = false, py::arg("legend") = true, py::arg("scene") = py::none(),
      py::arg("model_path") = py::none(), py::arg("resource_path") = py::none(),
      py::arg("package_path") = py::none(), py::arg("targets") = py::none(),
      py::arg("arm_view") = py::none(), py::arg("threads") = py::none(),
      "`vantage render RUN`: a ray-traced PNG of a finished run (an output folder of\n"
      "optimize/select/evaluate, or its report.json), targets coloured by how many chosen\n"
      "sensors see them. png: the file (None: view.png in the run's folder); eye, look_at:\n"
      "(x, y, z) [m] (None: framing targets and sensors); width, height [px] (16..8192,\n"
      "default 1280 x 960); fov: vertical field of view [deg] (1..170, default 45); frusta,\n"
      "legend: False leaves them out (--no-frusta, --no-legend); from_below: --from-below;\n"
      "scene, model_path, resource_path, package_path, targets: None takes the run's;\n"
      "arm_view: a camera on an arm, the view (1-based) at which the arm is drawn.\n"
      "Returns {'png': path, 'sensors': count, 'coverage': of the re-observed layout}.");

  m.def("sensors", &SensorCatalog,
        "The sensor catalog (SENSORS.md) as a list of dicts: id, name, technology, width,\n"
        "height, hfov, vfov [rad], fx, fy, cx, cy [px], near, far [m], fps, cost, and\n"
        "depth_noise ({a, b, c, source}: sigma(z) = a + b z + c z^2 [m]) or None. The keys of\n"
        "`vantage sensors --json`, plus depth_noise.");

  m.def("set_log_level", &SetLogLevel, py::arg("level"),
        "The library's log on stderr: 'debug', 'info', 'warning' (the default), 'error' or\n"
        "'off'.");
}

}  // namespace vantage::python

PYBIND11_MODULE(vantage, m) {
  vantage::python::g_main_thread = std::this_thread::get_id();
  // NumPy's C API, looked up now, with the GIL held and one thread (issue 44): pybind11 looks it
  // up in a function-local static on first use, and the import inside releases the GIL, so two
  // threads touching NumPy first together (two reading Visibility.matrix, a progress callable
  // reading a matrix) deadlocked, one holding the GIL and waiting for the static, the other
  // holding the static and waiting for the GIL. The dtypes the module makes are cached as well.
  py::module_::import("numpy");
  py::detail::npy_api::get();
  for (const py::dtype& type : {py::dtype::of<double>(), py::dtype::of<int32_t>(),
                                py::dtype::of<int64_t>(), py::dtype::of<uint64_t>()})
    static_cast<void>(type);
  // The library logs through spdlog's default logger (and one named "vantage"): on stderr, as
  // the CLI's, warnings and errors only unless set_log_level says otherwise.
  std::shared_ptr<spdlog::logger> logger = spdlog::get("vantage");
  if (!logger) logger = spdlog::stderr_color_mt("vantage");
  logger->set_pattern("[vantage %l] %v");
  logger->set_level(spdlog::level::warn);
  spdlog::set_default_logger(logger);
  vantage::python::Bind(m);
}
