// The chosen sensors as ROS-style static transforms (issue #7; docs/outputs.md,
// static_transforms.yaml): what `static_transform_publisher` or a launch file needs.
#include <fmt/format.h>

#include <cmath>
#include <string>

#include "vantage/error.hpp"
#include "vantage/visualize.hpp"

namespace vantage {
namespace {

// A YAML double-quoted scalar.
std::string Quoted(const std::string& text) {
  std::string out = "\"";
  for (const char ch : text) {
    const auto byte = static_cast<unsigned char>(ch);
    if (ch == '"' || ch == '\\') {
      out += '\\';
      out += ch;
    } else if (byte < 0x20) {
      out += fmt::format("\\x{:02x}", byte);
    } else {
      out += ch;
    }
  }
  return out + "\"";
}

// Shortest round-trippable enough text for a coordinate, never "-0".
std::string Number(double value) {
  if (value == 0.0) value = 0.0;  // folds -0 into 0
  return fmt::format("{:.9g}", value);
}

// Optical frame (z forward, x right, y down) in the body frame (x forward, y left, z up):
// columns are the optical axes expressed in the body frame.
Quat BodyFromOptical() {
  Mat3 rotation;
  rotation.col(0) = Vec3(0, -1, 0);  // optical x = right = body -y
  rotation.col(1) = Vec3(0, 0, -1);  // optical y = down = body -z
  rotation.col(2) = Vec3(1, 0, 0);   // optical z = forward = body x
  return Quat(rotation);
}

// ROS order x, y, z, w (Eigen's coeffs() order); w >= 0 so that the text is canonical.
std::string QuaternionXyzw(Quat q) {
  q.normalize();
  if (q.w() < 0) q.coeffs() *= -1.0;
  return fmt::format("[{}, {}, {}, {}]", Number(q.x()), Number(q.y()), Number(q.z()),
                     Number(q.w()));
}

void AppendTransform(const std::string& name,
                     const std::string& parent,
                     const Pose& parent_from_child,
                     const std::string& extra,
                     std::string* yaml) {
  const Vec3& p = parent_from_child.position;
  *yaml += fmt::format("  - name: {}\n", Quoted(name));
  *yaml += extra;
  *yaml += fmt::format("    parent_frame: {}\n    child_frame: {}\n", Quoted(parent), Quoted(name));
  *yaml += fmt::format("    xyz: [{}, {}, {}]\n", Number(p.x()), Number(p.y()), Number(p.z()));
  *yaml += fmt::format("    quaternion_xyzw: {}\n", QuaternionXyzw(parent_from_child.rotation));
}

}  // namespace

std::string StaticTransformsYaml(const Report& report, const std::string& parent_frame) {
  VANTAGE_CHECK(report.data != nullptr && report.is_derived);
  const VisibilityFile& data = *report.data;
  const Selection* result =
      report.primary >= 0 ? &report.results[static_cast<size_t>(report.primary)] : nullptr;

  std::string yaml =
      "# vantage: the chosen sensors as static transforms (docs/outputs.md, "
      "static_transforms.yaml).\n"
      "# Each entry places child_frame in parent_frame: xyz [m], quaternion_xyzw in ROS order.\n"
      "# Body frames: x forward, y left, z up (ROS, Gazebo). Optical frames "
      "(<name>_optical_frame,\n"
      "# where depth images live): z forward, x right, y down. ROS 2, one entry:\n"
      "#   ros2 run tf2_ros static_transform_publisher --x X --y Y --z Z --qx QX --qy QY --qz QZ\n"
      "#     --qw QW --frame-id PARENT_FRAME --child-frame-id CHILD_FRAME\n"
      "schema: vantage.static_transforms/1\n";
  yaml += fmt::format("scene: {}\n", Quoted(report.scene));
  if (result == nullptr) {
    yaml += "result: null\ntransforms: []\n";
    return yaml;
  }
  yaml += fmt::format("result: {{method: {}, n: {}, coverage: {}}}\n", Quoted(result->method),
                      result->n, Number(result->coverage));
  if (result->chosen.empty()) {
    yaml += "transforms: []\n";
    return yaml;
  }
  yaml += "transforms:\n";
  const Pose body_from_optical{Vec3::Zero(), BodyFromOptical()};
  const size_t reference_size = data.reference.keys.size();
  for (uint32_t index : result->chosen) {
    const Candidate& c = data.candidates.at(index);
    const Observation& o = data.observations.at(index);
    const double coverage = reference_size ? static_cast<double>(o.reference_indices.size()) /
                                                 static_cast<double>(reference_size)
                                           : 0.0;
    const std::string extra =
        fmt::format("    type: {}\n    coverage: {}\n",
                    Quoted(c.type_id.empty() ? c.sensor.id : c.type_id), Number(coverage));
    AppendTransform(c.name, parent_frame, c.world_from_body, extra, &yaml);
    AppendTransform(c.name + "_optical_frame", c.name, body_from_optical, "", &yaml);
  }
  return yaml;
}

}  // namespace vantage
