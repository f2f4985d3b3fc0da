#pragma once
/// Results people can look at (issue #7): the self-contained report.html, the chosen sensors as
/// ROS-style static transforms, and the colours and default viewpoint they share with the
/// rendered PNG (render.hpp).
#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "vantage/report.hpp"
#include "vantage/scene.hpp"
#include "vantage/types.hpp"

namespace vantage {

/// Colours shared by the page and the picture (8-bit sRGB).
using Rgb = std::array<uint8_t, 3>;
/// Target surface that no chosen sensor observes.
inline constexpr Rgb kUnobservedColor = {214, 64, 52};
/// Target surface observed by 1, 2, and 3 or more chosen sensors.
inline constexpr std::array<Rgb, 3> kObservedColors = {Rgb{70, 180, 75}, Rgb{30, 160, 135},
                                                       Rgb{45, 110, 200}};
/// Occluders.
inline constexpr Rgb kOccluderColor = {168, 168, 168};
/// Frusta and markers of the chosen sensors.
inline constexpr Rgb kFrustumColor = {255, 200, 0};

/// One colour per selection method, the same in every page and picture (report.html's chart and
/// tables, render's legend), whatever methods a run has.
struct MethodColorEntry {
  std::string_view method;
  Rgb color;
};
inline constexpr std::array<MethodColorEntry, 7> kMethodColors = {{
    {"best", {31, 119, 180}},     // blue
    {"ransac", {255, 127, 14}},   // orange
    {"greedy", {44, 160, 44}},    // green
    {"local", {214, 39, 40}},     // red
    {"exact", {148, 103, 189}},   // purple
    {"refined", {140, 86, 75}},   // brown
    {"given", {23, 190, 207}},    // cyan
}};
/// Methods that kMethodColors does not list.
inline constexpr Rgb kOtherMethodColor = {110, 110, 110};
/// The colour of `method`: its kMethodColors entry, else kOtherMethodColor.
Rgb MethodColor(std::string_view method);

/// Options of the HTML report.
struct HtmlReportOptions {
  /// Folder of three.js r111 (Debian's libjs-three): three.min.js and
  /// examples/js/controls/OrbitControls.js are read from it and inlined. When they are missing the
  /// page is written without the 3D view, with a visible note saying why.
  std::string three_js_dir = "/usr/share/javascript/three";
  /// Most triangles embedded for the 3D view; larger scenes are simplified by vertex clustering
  /// (the page says so). Must be >= 1.
  size_t max_mesh_triangles = 300000;
  /// Most bytes of the what-if data: the candidates' observation sets embedded in the page, and
  /// the bitsets the browser decodes them into (candidates x |R| / 8). Above it the page says
  /// that it offers no what-if layout.
  size_t max_whatif_bytes = size_t{64} << 20;
};

/// The report.html text: one self-contained page (no network access, opens from disk) with a 3D
/// view (scene meshes, candidates coloured by their coverage, the chosen sensors with frusta cut
/// at `far`, the reference voxels coloured by how many chosen sensors see them), a
/// coverage-versus-N chart per method (with the exact bound where present) and sortable tables of
/// the candidates and of the chosen sensors (with marginal gains). The chosen sensors are those of
/// report.primary (or PrimaryResult()); none when there is no result. `scene` may be empty (the
/// page then shows no meshes). When the page's script runs to the end it sets the text of the
/// element `#vantage-status` to "ok"; on a script error, to "error: <message>".
/// Requires report.data; InternalError otherwise.
std::string HtmlReport(const Report& report,
                       const Scene& scene,
                       const HtmlReportOptions& options = {});

/// The chosen sensors of report.primary (or PrimaryResult()) as ROS-style static transforms YAML
/// (schema vantage.static_transforms/1, docs/outputs.md): per sensor its name, parent frame,
/// translation xyz [m] and rotation quaternion in ROS order x, y, z, w of the sensor body frame
/// (x forward, y left, z up) in `parent_frame`; each followed by its optical frame
/// (`<name>_optical_frame`: z forward, x right, y down) as a child of the body frame.
/// An empty `transforms` list when there is no result. Requires report.data.
std::string StaticTransformsYaml(const Report& report, const std::string& parent_frame = "world");
/// cameras.urdf.xacro (docs/outputs.md): the primary result's cameras as fixed joints from
/// `parent_frame` (a xacro argument; a macro `vantage_cameras parent=...` for use in a robot) to
/// each camera's body frame, and from it to its optical frame, rpy(-pi/2, 0, -pi/2). Frame names
/// are ExportedFrameName's.
std::string CamerasXacro(const Report& report, const std::string& parent_frame = "world");

/// The frame name of a sensor in cameras.urdf.xacro, static_transforms.launch.py and
/// static_transforms.yaml (docs/outputs.md, "Frame names"): the name's bytes A-Z a-z 0-9 _ -
/// as they are, "::" as "..", every other byte as '.' and two lowercase hex digits ("cam 1" ->
/// "cam.201", "ü" -> ".c3.bc"); also escaped: the '_' of a trailing "_optical" or
/// "_optical_frame" (so that no body frame or joint is another sensor's optical one) and the
/// first byte of a name equal to `parent_frame`. Distinct names give distinct frames, and
/// SensorNameOfFrame gives the name back.
std::string ExportedFrameName(const std::string& sensor_name,
                              const std::string& parent_frame = "world");
/// The inverse of ExportedFrameName: ".." -> "::", ".hh" -> that byte. Throws InputError on a
/// text that no name gives.
std::string SensorNameOfFrame(const std::string& frame);
/// static_transforms.launch.py: a ROS 2 launch file with one tf2_ros static_transform_publisher
/// node per frame of CamerasXacro (the same names and poses; argument parent_frame).
std::string StaticTransformsLaunch(const Report& report, const std::string& parent_frame = "world");

/// A viewpoint: where the eye is and what it looks at (up is +z).
struct View {
  Vec3 eye = Vec3::Zero();
  Vec3 look_at = Vec3::Zero();
};

/// What the default views frame (issue 16): the targets' bounds (R's voxels without meshes), the
/// primary result's sensors (every one of them), and the direction from the point looked at
/// towards the eye: 35° above the horizon, from the sensors' side turned by 30° to the side that
/// frames them from closer (a fixed oblique azimuth when they surround the targets); steeper or
/// from another side when that look sees under half the target surface the best such look sees
/// (targets deep in a bin). Requires a derived report when report.data is set.
struct Framing {
  Aabb targets;
  std::vector<Vec3> sensors;
  Vec3 direction = Vec3::UnitZ();  ///< unit
};
Framing DefaultFraming(const Scene& scene, const Report& report);

/// The view along -direction that frames every point of `points` (5 % margin) for a vertical
/// field of view [rad] and an aspect ratio (width / height), centred on their extent in the image.
View FitView(const std::vector<Vec3>& points, const Vec3& direction, double vertical_fov,
             double aspect);

/// The default viewpoint of RenderView (and, computed again for the canvas' aspect by the page's
/// script, of the page's 3D view): FitView of DefaultFraming's targets' corners and sensors.
View DefaultView(const Scene& scene, const Report& report, double vertical_fov,
                 double aspect = 1.0, const std::vector<Vec3>& frame_also = {});
/// DefaultView for a framing already made (its surface probe is the costly part of a page).
View FramedView(const Framing& framing, double vertical_fov, double aspect = 1.0,
                const std::vector<Vec3>& frame_also = {});

/// The depth along a sensor's optical axis where its drawn frustum ends, so that frusta stop at
/// the scene instead of running to `far`: the far side of the targets' bounds, within
/// [near, far]; `far` when there are no targets.
double FrustumDepth(const Candidate& sensor, const Aabb& targets);

}  // namespace vantage
