// Mounting rules in a world (docs/constraints.md): <vantage:keep_out> boxes and
// <vantage:min_separation>, siblings of <population>. The vantage: prefix makes them custom
// elements, which libsdformat keeps in the world's element tree instead of refusing them.
#include <fmt/format.h>

#include <string>

#include "scene/sdf/loader.hpp"
#include "scene/sdf/text.hpp"

namespace vantage::detail::gazebo {

void Loader::ReadKeepOut(const Doc& doc, const XmlElement& e) {
  KeepOutBox box;
  box.file = doc.xml.path;
  box.line = e.line;
  const std::string* name = e.Attribute("name");
  box.name = name && !Trim(*name).empty()
                 ? Trim(*name)
                 : fmt::format("keep_out[{}]", problem_.mounting.keep_out.size());
  const std::string what = fmt::format("<vantage:keep_out name='{}'>", box.name);
  box.world_from_box = WorldPose(doc, e.Child("pose"));
  const XmlElement* size = e.Child("size");
  const XmlElement* min = e.Child("min");
  const XmlElement* max = e.Child("max");
  if (size != nullptr && (min != nullptr || max != nullptr)) {
    Error(doc, size->line, what + " has <size> and <min>/<max> — keep one of them");
    return;
  }
  if (size != nullptr) {
    const auto extent = Vector(doc, *size, true, "1 1 1");
    if (!extent) return;
    box.min = -0.5 * *extent;
    box.max = 0.5 * *extent;
  } else if (min != nullptr && max != nullptr) {
    const auto low = Vector(doc, *min, false, "0 0 0");
    const auto high = Vector(doc, *max, false, "1 1 1");
    if (!low || !high) return;
    if ((low->array() >= high->array()).any()) {
      Error(doc, max->line, what + ": <max> must exceed <min> on every axis — swap or fix them");
      return;
    }
    box.min = *low;
    box.max = *high;
  } else {
    Error(doc, e.line,
          what + " needs <size>sx sy sz</size> (centred at its <pose>) or <min> and <max>");
    return;
  }
  problem_.mounting.keep_out.push_back(std::move(box));
}

void Loader::ReadMinSeparation(const Doc& doc, const XmlElement& e) {
  if (problem_.mounting.min_separation) {
    Error(doc, e.line, "a second <vantage:min_separation> — keep one");
    return;
  }
  if (const auto value = PositiveNumber(doc, e, "0.2")) {
    if (const std::string problem = MinSeparationProblem(*value); !problem.empty()) {
      Error(doc, e.line, problem);
      return;
    }
    problem_.mounting.min_separation = *value;
    problem_.mounting.min_separation_file = doc.xml.path;
    problem_.mounting.min_separation_line = e.line;
  }
}

}  // namespace vantage::detail::gazebo
