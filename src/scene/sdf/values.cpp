// Typed values of SDF elements: numbers, whole numbers, booleans, vectors and poses, each checked
// and, when wrong, recorded as an error at the element's line (the caller gets nullopt or a
// fallback and reading goes on, so that one run lists every problem).
#include <fmt/format.h>

#include <array>
#include <cmath>
#include <numbers>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "scene/sdf/loader.hpp"
#include "scene/sdf/text.hpp"
#include "vantage/words.hpp"

namespace vantage::detail::gazebo {

std::optional<std::vector<double>> Loader::Numbers(const Doc& doc,
                                                   const XmlElement& e,
                                                   size_t count,
                                                   std::string_view example) {
  const std::vector<std::string> words = SplitWords(e.text);
  std::vector<double> values;
  bool ok = words.size() == count;
  for (size_t i = 0; ok && i < words.size(); ++i) {
    const std::optional<double> v = ParseDouble(words[i]);
    ok = v && std::isfinite(*v);
    if (ok) values.push_back(*v);
  }
  if (!ok) {
    Error(doc, e.line,
          fmt::format("<{}> '{}' must be {} finite number{} — write e.g. <{}>{}</{}>", e.name,
                      e.Trimmed(), count, count == 1 ? "" : "s", e.name, example, e.name));
    return std::nullopt;
  }
  return values;
}

std::optional<double> Loader::Number(const Doc& doc,
                                     const XmlElement& e,
                                     std::string_view example) {
  const auto values = Numbers(doc, e, 1, example);
  if (!values) return std::nullopt;
  return (*values)[0];
}

std::optional<double> Loader::PositiveNumber(const Doc& doc,
                                             const XmlElement& e,
                                             std::string_view unit_example) {
  const auto value = Number(doc, e, unit_example);
  if (!value) return std::nullopt;
  if (*value <= 0) {
    Error(doc, e.line,
          fmt::format("<{}> {} must be positive — write e.g. <{}>{}</{}>", e.name, e.Trimmed(),
                      e.name, unit_example, e.name));
    return std::nullopt;
  }
  return value;
}

std::optional<int64_t> Loader::Integer(const Doc& doc,
                                       const XmlElement& e,
                                       int64_t min,
                                       int64_t max) {
  const std::optional<int64_t> value = ParseInteger(e.Trimmed());
  if (!value || *value < min || *value > max) {
    Error(doc, e.line,
          fmt::format("<{}> '{}' must be a whole number from {} to {}", e.name, e.Trimmed(), min,
                      max));
    return std::nullopt;
  }
  return value;
}

std::optional<bool> BoolWord(std::string text) {
  // As sdformat reads a bool: true/false/1/0 in any case, around spaces.
  text = LowerCase(Trim(text));
  if (text == "true" || text == "1") return true;
  if (text == "false" || text == "0") return false;
  return std::nullopt;
}

std::optional<bool> Loader::Boolean(const Doc& doc, const XmlElement& e) {
  if (const std::optional<bool> value = BoolWord(e.Trimmed())) return value;
  Error(doc, e.line, fmt::format("<{}> '{}' must be true or false", e.name, e.Trimmed()));
  return std::nullopt;
}

std::optional<Vec3> Loader::Vector(const Doc& doc,
                                   const XmlElement& e,
                                   bool positive,
                                   std::string_view example) {
  const auto values = Numbers(doc, e, 3, example);
  if (!values) return std::nullopt;
  const Vec3 v((*values)[0], (*values)[1], (*values)[2]);
  if (positive && (v.array() <= 0).any()) {
    Error(doc, e.line,
          fmt::format("<{}> '{}' must be three positive numbers — write e.g. "
                      "<{}>{}</{}>",
                      e.name, e.Trimmed(), e.name, example, e.name));
    return std::nullopt;
  }
  return v;
}

Pose Loader::PoseValue(const Doc& doc, const XmlElement* pose) {
  if (!pose || pose->Trimmed().empty()) return Pose{};
  const std::string* format = pose->Attribute("rotation_format");
  const bool is_quaternion = format && *format == "quat_xyzw";
  if (format && !is_quaternion && *format != "euler_rpy") {
    Error(doc, pose->line,
          fmt::format("<pose rotation_format='{}'> is unknown — use euler_rpy "
                      "or quat_xyzw",
                      *format));
    return Pose{};
  }
  const auto values = Numbers(doc, *pose, is_quaternion ? 7 : 6,
                              is_quaternion ? "x y z qx qy qz qw" : "x y z roll pitch yaw");
  if (!values) return Pose{};
  const auto& v = *values;
  if (is_quaternion) {
    // QuatFromWxyz, as the YAML and report.json readers: [1e200, 0, 0, 1e200] normalised by its
    // overflowing norm gave a zero quaternion that passed.
    const std::array<double, 4> wxyz = {v[6], v[3], v[4], v[5]};
    const std::optional<Quat> q = QuatFromWxyz(wxyz);
    if (!q) {
      Error(doc, pose->line, "<pose> quaternion is zero, or shorter than 1e-09 (no direction to "
                              "normalise) — give a unit quaternion qx qy qz qw");
      return Pose{};
    }
    return Pose{Vec3(v[0], v[1], v[2]), *q};
  }
  // degrees="TRUE" was read as radians, a rotation 57 times too large (issue 15).
  const std::string* degrees = pose->Attribute("degrees");
  const std::optional<bool> in_degrees = degrees ? BoolWord(*degrees) : false;
  if (!in_degrees) {
    Error(doc, pose->line, fmt::format("<pose degrees='{}'> must be true or false", *degrees));
    return Pose{};
  }
  // <pose>0 0 1 0 90 -10</pose> is likely degrees where radians belong, but Gazebo reads it as
  // radians and vantage reads worlds as Gazebo does: a warning, not a refusal (YAML scenes,
  // vantage's own format, refuse it).
  if (!*in_degrees && (std::abs(v[3]) > 2.0 * std::numbers::pi + 1e-9 ||
                       std::abs(v[4]) > 2.0 * std::numbers::pi + 1e-9 ||
                       std::abs(v[5]) > 2.0 * std::numbers::pi + 1e-9)) {
    Warn(AtPlace(doc.xml.path, pose->line,
                 fmt::format("<pose> angles {:g} {:g} {:g} include one above 2π (6.283) radians, "
                             "read as radians as Gazebo does — if they are degrees, write "
                             "<pose degrees=\"true\">",
                             v[3], v[4], v[5])));
  }
  const double scale = *in_degrees ? std::numbers::pi / 180.0 : 1.0;
  return Pose::FromXyzRpy(v[0], v[1], v[2], v[3] * scale, v[4] * scale, v[5] * scale);
}

std::string Loader::RelativeTo(const Doc& doc, const XmlElement* pose) {
  if (!pose) return "";
  const std::string* frame = pose->Attribute("frame");
  if (frame && !Trim(*frame).empty()) {
    Note(AtPlace(doc.xml.path, pose->line,
                 fmt::format("<pose frame='{}'>: the frame attribute is ignored, as Gazebo "
                             "classic ignores it",
                             *frame)));
  }
  const std::string* relative_to = pose->Attribute("relative_to");
  return relative_to ? Trim(*relative_to) : "";
}

Pose Loader::WorldPose(const Doc& doc, const XmlElement* pose) {
  const std::string relative_to = RelativeTo(doc, pose);
  if (relative_to.empty() || relative_to == "world") return PoseValue(doc, pose);
  if (&doc != world_doc_) {
    // The top-level pose of an included model file: libsdformat refuses relative_to there too.
    Error(doc, pose->line,
          fmt::format("<pose relative_to='{}'> on a model file's own model is not supported — "
                      "give the pose relative to its parent (no relative_to)",
                      relative_to));
    return PoseValue(doc, pose);
  }
  return WorldFrame(relative_to, pose->line) * PoseValue(doc, pose);
}

Pose Loader::WorldFrame(const std::string& name, int line) {
  if (name == "world") return Pose{};
  if (const auto it = world_frames_.find(name); it != world_frames_.end()) return it->second;
  const Doc& doc = *world_doc_;
  // The world-level element of that name: <frame name>, <model name>, <include><name>.
  const XmlElement* found = nullptr;
  for (const XmlElement& child : world_->children) {
    std::string child_name;
    if (child.name == "frame" || child.name == "model") {
      const std::string* attribute = child.Attribute("name");
      child_name = attribute ? Trim(*attribute) : "";
    } else if (child.name == "include" && child.Child("name")) {
      child_name = child.Child("name")->Trimmed();
    }
    if (!child_name.empty() && child_name == name) {
      found = &child;
      break;
    }
  }
  if (!found) {
    Error(doc, line,
          fmt::format("relative_to '{}' names no frame, model or named include of the world — "
                      "name one (an <include> by its <name>; scoped names a::b are not "
                      "supported)",
                      name));
    return Pose{};
  }
  const bool placed = found->name == "include"
                          ? found->Child("placement_frame") != nullptr
                          : found->Attribute("placement_frame") != nullptr;
  if (placed) {
    Error(doc, line,
          fmt::format("relative_to '{}' names a model placed by its placement_frame — place "
                      "this pose relative to the world or to another frame",
                      name));
    return Pose{};
  }
  if (!world_frames_visiting_.insert(name).second) {
    Error(doc, found->line,
          fmt::format("'{}' is placed relative to itself (a relative_to cycle) — break the cycle",
                      name));
    return Pose{};
  }
  const XmlElement* pose = found->Child("pose");
  Pose result;
  if (found->name == "include" && !pose) {
    Error(doc, line,
          fmt::format("relative_to '{}' names an <include> without its own <pose> — give it one",
                      name));
  } else {
    std::string parent = RelativeTo(doc, pose);
    if (parent.empty() && found->name == "frame") {
      const std::string* attached_to = found->Attribute("attached_to");
      if (attached_to) parent = Trim(*attached_to);
    }
    result = (parent.empty() ? Pose{} : WorldFrame(parent, pose ? pose->line : found->line)) *
             PoseValue(doc, pose);
  }
  world_frames_visiting_.erase(name);
  world_frames_[name] = result;
  return result;
}

void Loader::SetPlacementFrame(const Doc& include_doc, const XmlElement* include,
                               const Doc& model_doc, const XmlElement& model,
                               ModelContext* context) {
  context->placement_frame.clear();
  context->placement_doc = nullptr;
  if (include) {
    if (const XmlElement* frame = include->Child("placement_frame")) {
      context->placement_frame = frame->Trimmed();
      context->placement_doc = &include_doc;
      context->placement_line = frame->line;
      return;
    }
  }
  if (const std::string* attribute = model.Attribute("placement_frame")) {
    context->placement_frame = Trim(*attribute);
    context->placement_doc = &model_doc;
    context->placement_line = model.line;
  }
}

double Loader::NumberOr(const Doc& doc,
                        const XmlElement* parent,
                        std::string_view child,
                        double fallback,
                        bool positive) {
  const XmlElement* e = parent ? parent->Child(child) : nullptr;
  if (!e) return fallback;
  const auto value = positive ? PositiveNumber(doc, *e, fmt::format("{}", fallback))
                              : Number(doc, *e, fmt::format("{}", fallback));
  return value.value_or(fallback);
}

}  // namespace vantage::detail::gazebo
