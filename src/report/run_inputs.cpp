// report.json's `inputs` block: every option that shaped the run, as it was given.
#include "report/run_inputs.hpp"

#include <fmt/format.h>

#include <type_traits>
#include <variant>

#include "util/cell_size.hpp"
#include "vantage/error.hpp"

namespace vantage::detail {
namespace {

using nlohmann::json;
using nlohmann::ordered_json;

template <typename T>
void Put(ordered_json* j, const char* key, const std::optional<T>& value) {
  if (value) (*j)[key] = *value;
}

// Reads `key` when present: InputError naming it when its JSON type is not `T`'s.
class Reader {
 public:
  Reader(const json& j, std::string where) : j_(j), where_(std::move(where)) {}

  bool Has(const char* key) const { return j_.contains(key) && !j_[key].is_null(); }

  void String(const char* key, std::string* out) const {
    if (!Has(key)) return;
    if (!j_[key].is_string()) Fail(key, "a string");
    *out = j_[key].get<std::string>();
  }
  void String(const char* key, std::optional<std::string>* out) const {
    if (!Has(key)) return;
    std::string text;
    String(key, &text);
    *out = text;
  }
  void Strings(const char* key, std::vector<std::string>* out) const {
    if (!Has(key)) return;
    if (!j_[key].is_array()) Fail(key, "an array of strings");
    for (const json& item : j_[key]) {
      if (!item.is_string()) Fail(key, "an array of strings");
      out->push_back(item.get<std::string>());
    }
  }
  void Number(const char* key, std::optional<double>* out) const {
    if (!Has(key)) return;
    if (!j_[key].is_number()) Fail(key, "a number");
    *out = j_[key].get<double>();
  }
  void Integer(const char* key, std::optional<int>* out) const {
    if (!Has(key)) return;
    if (!j_[key].is_number_integer() || j_[key].get<int64_t>() < INT32_MIN ||
        j_[key].get<int64_t>() > INT32_MAX)
      Fail(key, "a whole number");
    *out = static_cast<int>(j_[key].get<int64_t>());
  }
  void Unsigned(const char* key, std::optional<uint64_t>* out) const {
    if (!Has(key)) return;
    if (!j_[key].is_number_unsigned()) Fail(key, "a whole number >= 0");
    *out = j_[key].get<uint64_t>();
  }
  void Boolean(const char* key, bool* out) const {
    if (!Has(key)) return;
    if (!j_[key].is_boolean()) Fail(key, "true or false");
    *out = j_[key].get<bool>();
  }
  void Boolean(const char* key, std::optional<bool>* out) const {
    if (!Has(key)) return;
    bool value = false;
    Boolean(key, &value);
    *out = value;
  }
  void Point(const char* key, std::optional<Vec3>* out) const {
    if (!Has(key)) return;
    const json& v = j_[key];
    if (!v.is_array() || v.size() != 3 || !v[0].is_number() || !v[1].is_number() ||
        !v[2].is_number())
      Fail(key, "an array of 3 numbers");
    *out = Vec3(v[0].get<double>(), v[1].get<double>(), v[2].get<double>());
  }

  // `text` of `key` parsed by `parse`; its InputError (which lists the valid names) naming the key.
  template <typename Parse>
  auto Parsed(const char* key, const std::string& text, Parse parse) const {
    try {
      return parse(text);
    } catch (const InputError& e) {
      throw InputError(fmt::format("{}: inputs.{}: {}", where_, key, e.what()));
    }
  }

 private:
  [[noreturn]] void Fail(const char* key, const char* what) const {
    throw InputError(fmt::format("{}: inputs.{} must be {} — give a report.json written by vantage",
                                 where_, key, what));
  }
  const json& j_;
  std::string where_;
};

// The selection options as SelectionOptionTable() names them, in its order, then the
// installation constraints; a flag only when set.
void PutSelection(ordered_json* j, const SelectionRequest& request) {
  for (const SelectionOption& option : SelectionOptionTable()) {
    const std::string key(option.input);
    std::visit(
        [&](auto pointer) {
          const auto& value = request.*pointer;
          using Value = std::decay_t<decltype(value)>;
          if constexpr (std::is_same_v<Value, bool>) {
            if (value) (*j)[key] = true;
          } else if constexpr (std::is_same_v<Value, std::optional<Method>>) {
            if (value) (*j)[key] = MethodName(*value);
          } else if constexpr (std::is_same_v<Value, std::optional<OverStates>>) {
            if (value) (*j)[key] = OverStatesName(*value);
          } else {
            Put(j, key.c_str(), value);
          }
        },
        option.member);
  }
  const ConstraintOptions& c = request.constraints;
  Put(j, "interference", c.interference);
  Put(j, "interference_overlap", c.interference_overlap);
  Put(j, "calibration_overlap", c.calibration_overlap);
  Put(j, "calibration_overlap_frac", c.calibration_overlap_frac);
}

void ReadSelection(const Reader& r, SelectionRequest* request) {
  for (const SelectionOption& option : SelectionOptionTable()) {
    const std::string key(option.input);
    std::visit(
        [&](auto pointer) {
          auto& value = request->*pointer;
          using Value = std::decay_t<decltype(value)>;
          if constexpr (std::is_same_v<Value, bool>) {
            r.Boolean(key.c_str(), &value);
          } else if constexpr (std::is_same_v<Value, std::optional<int>>) {
            r.Integer(key.c_str(), &value);
          } else if constexpr (std::is_same_v<Value, std::optional<int64_t>>) {
            std::optional<int> whole;  // the range a run writes (ResolveMinPoints checks it)
            r.Integer(key.c_str(), &whole);
            if (whole) value = *whole;
          } else if constexpr (std::is_same_v<Value, std::optional<double>>) {
            r.Number(key.c_str(), &value);
          } else {
            std::optional<std::string> name;
            r.String(key.c_str(), &name);
            if (name) value = r.Parsed(key.c_str(), *name, [](const std::string& text) {
              if constexpr (std::is_same_v<Value, std::optional<Method>>)
                return ParseMethod(text);
              else
                return ParseOverStates(text);
            });
          }
        },
        option.member);
  }
  ConstraintOptions& c = request->constraints;
  r.Boolean("interference", &c.interference);
  r.Number("interference_overlap", &c.interference_overlap);
  r.Unsigned("calibration_overlap", &c.calibration_overlap);
  r.Number("calibration_overlap_frac", &c.calibration_overlap_frac);
}

}  // namespace

ordered_json RunInputsJson(const RunInputs& in) {
  ordered_json j;
  j["command"] = in.command;
  j["scene"] = in.scene;
  j["model_paths"] = in.model_paths;
  j["resource_paths"] = in.resource_paths;
  if (!in.package_paths.empty()) j["package_paths"] = in.package_paths;
  j["targets"] = in.targets;
  Put(&j, "cell_size", in.cell_size);
  Put(&j, "seed", in.seed);
  if (in.observation_point) {
    const Vec3& p = *in.observation_point;
    j["observation_point"] = ordered_json::array({p.x(), p.y(), p.z()});
  }
  Put(&j, "random_roll", in.random_roll);
  j["cull"] = in.cull;
  if (in.exposed_only) j["exposed_only"] = true;
  if (in.physical) j["sensor_model"] = "physical";
  Put(&j, "max_incidence_deg", in.quality.max_incidence_deg);
  if (in.quality.max_depth_noise) j["max_depth_noise_mm"] = *in.quality.max_depth_noise * 1000.0;
  PutSelection(&j, in.selection);
  if (in.refine) j["refine"] = true;
  Put(&j, "refine_rounds", in.refine_rounds);
  Put(&j, "fov_tolerance_deg", in.fov_tolerance_deg);
  Put(&j, "pose_tolerance_m", in.pose_tolerance_m);
  Put(&j, "pose_tolerance_deg", in.pose_tolerance_deg);
  Put(&j, "pose_samples", in.pose_samples);
  Put(&j, "alternatives_within", in.alternatives_within);
  if (!in.visibility_file.empty()) j["visibility_file"] = in.visibility_file;
  if (!in.constellation.empty()) j["constellation"] = in.constellation;
  return j;
}

RunInputs ParseRunInputs(const json& j, const std::string& where) {
  if (!j.is_object())
    throw InputError(fmt::format("{}: 'inputs' must be an object — give a report.json written by "
                                 "vantage", where));
  const Reader r(j, where);
  RunInputs in;
  r.String("command", &in.command);
  r.String("scene", &in.scene);
  r.Strings("model_paths", &in.model_paths);
  r.Strings("resource_paths", &in.resource_paths);
  r.Strings("package_paths", &in.package_paths);
  r.Strings("targets", &in.targets);
  r.Number("cell_size", &in.cell_size);
  // evaluate and render use it as if given as --cell-size: checked here, where it enters, so
  // that the error names the file and the field (issue 15), not the option.
  if (in.cell_size) {
    if (const std::string problem = CellSizeProblem(*in.cell_size); !problem.empty())
      throw InputError(fmt::format("{}: inputs.{}", where, problem));
  }
  r.Unsigned("seed", &in.seed);
  r.Point("observation_point", &in.observation_point);
  r.Boolean("random_roll", &in.random_roll);
  r.Boolean("cull", &in.cull);
  r.Boolean("exposed_only", &in.exposed_only);
  std::optional<std::string> model;
  r.String("sensor_model", &model);
  if (model && *model != "physical" && *model != "ideal")
    throw InputError(fmt::format("{}: inputs.sensor_model '{}' is not physical or ideal", where,
                                 *model));
  in.physical = model == "physical";
  r.Number("max_incidence_deg", &in.quality.max_incidence_deg);
  std::optional<double> noise_mm;
  r.Number("max_depth_noise_mm", &noise_mm);
  if (noise_mm) in.quality.max_depth_noise = *noise_mm / 1000.0;
  ReadSelection(r, &in.selection);
  r.Boolean("refine", &in.refine);
  r.Integer("refine_rounds", &in.refine_rounds);
  r.Number("fov_tolerance_deg", &in.fov_tolerance_deg);
  r.Number("pose_tolerance_m", &in.pose_tolerance_m);
  r.Number("pose_tolerance_deg", &in.pose_tolerance_deg);
  r.Integer("pose_samples", &in.pose_samples);
  r.Number("alternatives_within", &in.alternatives_within);
  r.String("visibility_file", &in.visibility_file);
  r.String("constellation", &in.constellation);
  return in;
}

}  // namespace vantage::detail
