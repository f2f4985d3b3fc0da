// The chosen sensors as ROS-style static transforms (issue #7; docs/outputs.md,
// static_transforms.yaml): what `static_transform_publisher` or a launch file needs.
#include <fmt/format.h>

#include <cctype>
#include <cmath>
#include <set>
#include <string>
#include <string_view>
#include <vector>

#include "util/markup.hpp"
#include "util/words.hpp"
#include "vantage/error.hpp"
#include "vantage/visualize.hpp"

namespace vantage {
namespace {

// A YAML double-quoted scalar of `text` as UTF-8: '"', '\\' and every character outside YAML's
// printable set (controls, DEL, C1, U+2028/9 line separators, U+FEFF) escaped.
std::string Quoted(const std::string& raw) {
  const std::string text = detail::AsUtf8(raw);
  std::string out = "\"";
  for (size_t i = 0; i < text.size(); ++i) {
    const auto byte = static_cast<unsigned char>(text[i]);
    if (text[i] == '"' || text[i] == '\\') {
      out += '\\';
      out += text[i];
    } else if (byte < 0x20 || byte == 0x7f) {
      out += fmt::format("\\x{:02x}", byte);
    } else if (byte == 0xc2 && i + 1 < text.size() &&
               static_cast<unsigned char>(text[i + 1]) < 0xa0) {  // U+0080..U+009F
      out += fmt::format("\\x{:02x}", static_cast<unsigned char>(text[i + 1]));
      ++i;
    } else if (text.compare(i, 3, "\xe2\x80\xa8") == 0 || text.compare(i, 3, "\xe2\x80\xa9") == 0 ||
               text.compare(i, 3, "\xef\xbb\xbf") == 0) {
      out += text[i + 2] == '\xa8' ? "\\L" : text[i + 2] == '\xa9' ? "\\P" : "\\ufeff";
      i += 2;
    } else {
      out += text[i];
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
                     const std::string& child,
                     const std::string& parent,
                     const Pose& parent_from_child,
                     const std::string& extra,
                     std::string* yaml) {
  const Vec3& p = parent_from_child.position;
  *yaml += fmt::format("  - name: {}\n", Quoted(name));
  *yaml += extra;
  *yaml += fmt::format("    parent_frame: {}\n    child_frame: {}\n", Quoted(parent),
                       Quoted(child));
  *yaml += fmt::format("    xyz: [{}, {}, {}]\n", Number(p.x()), Number(p.y()), Number(p.z()));
  *yaml += fmt::format("    quaternion_xyzw: {}\n", QuaternionXyzw(parent_from_child.rotation));
}

/// A Python single-quoted string literal (UTF-8 text as it is: the file is UTF-8, Python's
/// default; a byte that is not UTF-8 shown as U+FFFD).
std::string PyString(const std::string& text) {
  std::string out = "'";
  for (const char ch : detail::AsUtf8(text)) {
    const auto byte = static_cast<unsigned char>(ch);
    if (ch == '\'' || ch == '\\') {
      out += '\\';
      out += ch;
    } else if (byte < 0x20 || byte == 0x7f) {
      out += fmt::format("\\x{:02x}", byte);
    } else {
      out += ch;
    }
  }
  return out + "'";
}

bool IsPlainFrameByte(unsigned char c) { return std::isalnum(c) || c == '_' || c == '-'; }

/// The frames of the primary result's cameras, by ExportedFrameName; unique (checked: a clash
/// would be a bug of the encoding, not the user's input).
std::vector<std::string> FrameNames(const std::vector<const Candidate*>& cameras,
                                    const std::string& parent_frame) {
  std::vector<std::string> frames;
  std::set<std::string> taken;
  for (const Candidate* c : cameras) {
    frames.push_back(ExportedFrameName(c->name, parent_frame));
    VANTAGE_CHECK(taken.insert(frames.back()).second &&
                  taken.insert(frames.back() + "_optical_frame").second);
  }
  return frames;
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

std::string ExportedFrameName(const std::string& sensor_name, const std::string& parent_frame) {
  // Which bytes are escaped although plain: the '_' starting a trailing "_optical" or
  // "_optical_frame", and the first byte when the name is the parent frame's.
  size_t escaped_underscore = std::string::npos;
  for (const std::string_view suffix :
       {std::string_view("_optical"), std::string_view("_optical_frame")}) {
    if (sensor_name.size() >= suffix.size() &&
        sensor_name.compare(sensor_name.size() - suffix.size(), suffix.size(), suffix) == 0)
      escaped_underscore = sensor_name.size() - suffix.size();
  }
  const bool escape_first = sensor_name == parent_frame;
  std::string out;
  for (size_t i = 0; i < sensor_name.size(); ++i) {
    const auto c = static_cast<unsigned char>(sensor_name[i]);
    if (sensor_name.compare(i, 2, "::") == 0) {
      out += "..";
      ++i;
    } else if (IsPlainFrameByte(c) && i != escaped_underscore && !(i == 0 && escape_first)) {
      out.push_back(sensor_name[i]);
    } else {
      out += fmt::format(".{:02x}", c);
    }
  }
  return out;
}

std::string SensorNameOfFrame(const std::string& frame) {
  const auto hex = [](char c) -> int {
    if (c >= '0' && c <= '9') return c - '0';
    if (c >= 'a' && c <= 'f') return c - 'a' + 10;
    return -1;
  };
  std::string name;
  for (size_t i = 0; i < frame.size(); ++i) {
    const auto c = static_cast<unsigned char>(frame[i]);
    if (c != '.') {
      if (!IsPlainFrameByte(c))
        throw InputError(fmt::format("frame '{}': byte {} is neither plain nor escaped",
                                     detail::Escaped(frame), i));
      name.push_back(frame[i]);
    } else if (i + 1 < frame.size() && frame[i + 1] == '.') {
      name += "::";
      ++i;
    } else if (i + 2 < frame.size() && hex(frame[i + 1]) >= 0 && hex(frame[i + 2]) >= 0) {
      name.push_back(static_cast<char>(16 * hex(frame[i + 1]) + hex(frame[i + 2])));
      i += 2;
    } else {
      throw InputError(fmt::format("frame '{}': '.' at byte {} starts no escape",
                                   detail::Escaped(frame), i));
    }
  }
  return name;
}

std::string CamerasXacro(const Report& report, const std::string& parent_frame) {
  std::string xml =
      "<?xml version=\"1.0\"?>\n"
      "<!-- vantage: the chosen cameras as fixed joints (docs/outputs.md, cameras.urdf.xacro).\n"
      "     Each camera has a mount (body) frame NAME (its name as docs/outputs.md, Frame\n"
      "     names, encodes it): x forward, y left, z up, placed in\n"
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
  const std::vector<const Candidate*> cameras = PrimaryCameras(report);
  const std::vector<std::string> frames = FrameNames(cameras, parent_frame);
  for (size_t k = 0; k < cameras.size(); ++k) {
    const Candidate* c = cameras[k];
    // Frames are plain ASCII with '.' escapes: nothing to escape, and no "$" for xacro to expand.
    const std::string& name = frames[k];
    const Pose& pose = c->world_from_body;
    const Vec3 rpy = RpyFromRotation(pose.rotation.normalized().toRotationMatrix());
    xml += fmt::format("    <!-- sensor {} ({}) -->\n",
                       detail::CommentText(detail::AsUtf8(c->name)),
                       detail::CommentText(detail::AsUtf8(c->type_id.empty() ? c->sensor.id
                                                                             : c->type_id)));
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
      "def _static_transform(node, name, parent, xyz, xyzw):\n"
      "    return Node(\n"
      "        package='tf2_ros', executable='static_transform_publisher', name=node,\n"
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
  const std::vector<const Candidate*> cameras = PrimaryCameras(report);
  const std::vector<std::string> frames = FrameNames(cameras, parent_frame);
  for (size_t k = 0; k < cameras.size(); ++k) {
    const Candidate* c = cameras[k];
    const std::string& name = frames[k];
    // ROS node names: letters, digits and '_', unique by the camera's index.
    std::string node = fmt::format("vantage_{}_", k + 1);
    for (const char ch : name) node.push_back(std::isalnum(static_cast<unsigned char>(ch)) ? ch : '_');
    Quat q = c->world_from_body.rotation.normalized();
    if (q.w() < 0) q.coeffs() *= -1.0;
    const Vec3& p = c->world_from_body.position;
    py += fmt::format(
        "        _static_transform({}, {}, parent, ['{}', '{}', '{}'], ['{}', '{}', '{}', '{}']),\n",
        PyString(node), PyString(name), Exact(p.x()), Exact(p.y()), Exact(p.z()), Exact(q.x()),
        Exact(q.y()), Exact(q.z()), Exact(q.w()));
    py += fmt::format(
        "        _static_transform({}, {}, {}, ['0', '0', '0'], ['{}', '{}', '{}', '{}']),\n",
        PyString(node + "_optical"), PyString(name + "_optical_frame"), PyString(name),
        Exact(optical.x()), Exact(optical.y()), Exact(optical.z()), Exact(optical.w()));
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
  const std::vector<const Candidate*> cameras = PrimaryCameras(report);
  const std::vector<std::string> frames = FrameNames(cameras, parent_frame);
  for (size_t k = 0; k < cameras.size(); ++k) {
    const uint32_t index = result->chosen[k];
    const Candidate& c = data.candidates.at(index);
    const Observation& o = data.observations.at(index);
    const double coverage = reference_size ? static_cast<double>(o.reference_indices.size()) /
                                                 static_cast<double>(reference_size)
                                           : 0.0;
    const std::string extra =
        fmt::format("    type: {}\n    coverage: {}\n",
                    Quoted(detail::AsUtf8(c.type_id.empty() ? c.sensor.id : c.type_id)),
                    Number(coverage));
    // The body entry's name is the sensor's (report.json's); its frame ExportedFrameName's.
    AppendTransform(detail::AsUtf8(c.name), frames[k], parent_frame, c.world_from_body, extra,
                    &yaml);
    AppendTransform(frames[k] + "_optical_frame", frames[k] + "_optical_frame", frames[k],
                    body_from_optical, "", &yaml);
  }
  return yaml;
}

}  // namespace vantage
