// The chosen sensors as ROS-style static transforms (issue #7; docs/outputs.md,
// static_transforms.yaml): what `static_transform_publisher` or a launch file needs.
#include <fmt/format.h>

#include <cctype>
#include <cmath>
#include <string>
#include <vector>

#include "util/markup.hpp"
#include "util/words.hpp"
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

/// A frame name that URDF, xacro and tf2 all accept: vantage's "outer::inner" and "model/sensor"
/// become "outer__inner" and "model_sensor", other characters outside [A-Za-z0-9_.-] '_'.
std::string FrameName(const std::string& name) {
  std::string out;
  for (size_t i = 0; i < name.size(); ++i) {
    const auto c = static_cast<unsigned char>(name[i]);
    if (name.compare(i, 2, "::") == 0) {
      out += "__";
      ++i;
    } else {
      out.push_back(std::isalnum(c) || c == '_' || c == '-' || c == '.' ? name[i] : '_');
    }
  }
  return out.empty() ? "_" : out;
}

/// A Python single-quoted string literal.
std::string PyString(const std::string& text) {
  std::string out = "'";
  for (const char ch : text) {
    const auto byte = static_cast<unsigned char>(ch);
    if (ch == '\'' || ch == '\\') {
      out += '\\';
      out += ch;
    } else if (byte < 0x20 || byte >= 0x7f) {
      out += fmt::format("\\x{:02x}", byte);
    } else {
      out += ch;
    }
  }
  return out + "'";
}

/// The primary result's candidates, in the order chosen (empty without a result).
std::vector<const Candidate*> PrimaryCameras(const Report& report) {
  VANTAGE_CHECK(report.data != nullptr && report.is_derived);
  std::vector<const Candidate*> cameras;
  if (report.primary < 0) return cameras;
  for (const uint32_t i : report.results[static_cast<size_t>(report.primary)].chosen)
    cameras.push_back(&report.data->candidates.at(i));
  return cameras;
}

// Full precision: the exports must place the cameras exactly (1e-9).
std::string Exact(double value) {
  if (value == 0.0) value = 0.0;
  return fmt::format("{}", value);
}

}  // namespace

std::string CamerasXacro(const Report& report, const std::string& parent_frame) {
  std::string xml =
      "<?xml version=\"1.0\"?>\n"
      "<!-- vantage: the chosen cameras as fixed joints (docs/outputs.md, cameras.urdf.xacro).\n"
      "     Each camera NAME has a mount (body) frame NAME: x forward, y left, z up, placed in\n"
      "     the parent frame by <origin xyz rpy> (rpy: R = Rz(yaw) Ry(pitch) Rx(roll) [rad]),\n"
      "     and the ROS optical frame NAME_optical_frame (z forward, x right, y down, where\n"
      "     depth images live) = the body rotated by rpy(-pi/2, 0, -pi/2) (REP 103).\n"
      "     Standalone: xacro cameras.urdf.xacro parent_frame:=world; in a robot:\n"
      "     <xacro:include filename=\"cameras.urdf.xacro\"/> and\n"
      "     <xacro:vantage_cameras parent=\"base_link\"/> with vantage_standalone:=false. -->\n"
      "<robot name=\"vantage_cameras\" xmlns:xacro=\"http://www.ros.org/wiki/xacro\">\n";
  xml += fmt::format("  <xacro:arg name=\"parent_frame\" default=\"{}\"/>\n",
                     detail::MarkupEscape(parent_frame));
  xml += "  <xacro:arg name=\"vantage_standalone\" default=\"true\"/>\n";
  xml += "  <xacro:macro name=\"vantage_cameras\" params=\"parent\">\n";
  for (const Candidate* c : PrimaryCameras(report)) {
    const std::string name = detail::MarkupEscape(FrameName(c->name));
    const Pose& pose = c->world_from_body;
    const Vec3 rpy = RpyFromRotation(pose.rotation.normalized().toRotationMatrix());
    xml += fmt::format("    <!-- {} ({}) -->\n", detail::MarkupEscape(c->name),
                       detail::MarkupEscape(c->type_id.empty() ? c->sensor.id : c->type_id));
    xml += fmt::format("    <joint name=\"{}_joint\" type=\"fixed\">\n", name);
    xml += "      <parent link=\"${parent}\"/>\n";
    xml += fmt::format("      <child link=\"{}\"/>\n", name);
    xml += fmt::format("      <origin xyz=\"{} {} {}\" rpy=\"{} {} {}\"/>\n",
                       Exact(pose.position.x()), Exact(pose.position.y()),
                       Exact(pose.position.z()), Exact(rpy.x()), Exact(rpy.y()), Exact(rpy.z()));
    xml += "    </joint>\n";
    xml += fmt::format("    <link name=\"{}\"/>\n", name);
    xml += fmt::format("    <joint name=\"{}_optical_joint\" type=\"fixed\">\n", name);
    xml += fmt::format("      <parent link=\"{}\"/>\n", name);
    xml += fmt::format("      <child link=\"{}_optical_frame\"/>\n", name);
    xml += "      <origin xyz=\"0 0 0\" rpy=\"${-pi/2} 0 ${-pi/2}\"/>\n";
    xml += "    </joint>\n";
    xml += fmt::format("    <link name=\"{}_optical_frame\"/>\n", name);
  }
  xml += "  </xacro:macro>\n";
  xml += "  <xacro:if value=\"$(arg vantage_standalone)\">\n";
  xml += "    <link name=\"$(arg parent_frame)\"/>\n";
  xml += "    <xacro:vantage_cameras parent=\"$(arg parent_frame)\"/>\n";
  xml += "  </xacro:if>\n";
  xml += "</robot>\n";
  return xml;
}

std::string StaticTransformsLaunch(const Report& report, const std::string& parent_frame) {
  std::string py =
      "# vantage: the chosen cameras as ROS 2 static transforms (docs/outputs.md,\n"
      "# static_transforms.launch.py): ros2 launch static_transforms.launch.py [parent_frame:=F]\n"
      "# Per camera NAME: NAME (body: x forward, y left, z up) in the parent frame, and\n"
      "# NAME_optical_frame (z forward, x right, y down) = the body rotated by\n"
      "# rpy(-pi/2, 0, -pi/2). Quaternions in ROS order x, y, z, w.\n"
      "from launch import LaunchDescription\n"
      "from launch.actions import DeclareLaunchArgument\n"
      "from launch.substitutions import LaunchConfiguration\n"
      "from launch_ros.actions import Node\n"
      "\n"
      "\n"
      "def _static_transform(name, parent, xyz, xyzw):\n"
      "    return Node(\n"
      "        package='tf2_ros', executable='static_transform_publisher',\n"
      "        name='vantage_' + name.replace('.', '_').replace('-', '_'),\n"
      "        arguments=['--x', xyz[0], '--y', xyz[1], '--z', xyz[2],\n"
      "                   '--qx', xyzw[0], '--qy', xyzw[1], '--qz', xyzw[2], '--qw', xyzw[3],\n"
      "                   '--frame-id', parent, '--child-frame-id', name])\n"
      "\n"
      "\n"
      "def generate_launch_description():\n";
  py += fmt::format("    parent = LaunchConfiguration('parent_frame', default={})\n",
                    PyString(parent_frame));
  py += "    return LaunchDescription([\n";
  py += fmt::format("        DeclareLaunchArgument('parent_frame', default_value={}),\n",
                    PyString(parent_frame));
  Quat optical = BodyFromOptical().normalized();
  if (optical.w() < 0) optical.coeffs() *= -1.0;  // as static_transforms.yaml writes it
  for (const Candidate* c : PrimaryCameras(report)) {
    const std::string name = FrameName(c->name);
    Quat q = c->world_from_body.rotation.normalized();
    if (q.w() < 0) q.coeffs() *= -1.0;
    const Vec3& p = c->world_from_body.position;
    py += fmt::format(
        "        _static_transform({}, parent, ['{}', '{}', '{}'], ['{}', '{}', '{}', '{}']),\n",
        PyString(name), Exact(p.x()), Exact(p.y()), Exact(p.z()), Exact(q.x()), Exact(q.y()),
        Exact(q.z()), Exact(q.w()));
    py += fmt::format(
        "        _static_transform({}, {}, ['0', '0', '0'], ['{}', '{}', '{}', '{}']),\n",
        PyString(name + "_optical_frame"), PyString(name), Exact(optical.x()), Exact(optical.y()),
        Exact(optical.z()), Exact(optical.w()));
  }
  py += "    ])\n";
  return py;
}

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
  yaml += fmt::format("scene: {}\n", Quoted(detail::AsUtf8(report.scene)));
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
