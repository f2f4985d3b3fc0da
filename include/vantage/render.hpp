#pragma once
/// A ray-traced PNG view of a finished run (issue #7): the scene shaded, targets coloured by how
/// many chosen sensors observe each voxel, the chosen sensors' frusta drawn over it. The one
/// output that casts rays, so it is a stage of its own above the report writers.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "vantage/ray_scene.hpp"
#include "vantage/report.hpp"
#include "vantage/scene.hpp"
#include "vantage/visualize.hpp"

namespace vantage {

/// An 8-bit RGB picture, rows top to bottom.
struct Image {
  int width = 0;
  int height = 0;
  std::vector<uint8_t> rgb;  ///< 3 * width * height bytes

  Rgb At(int x, int y) const {
    const size_t i =
        3 * (static_cast<size_t>(y) * static_cast<size_t>(width) + static_cast<size_t>(x));
    return {rgb[i], rgb[i + 1], rgb[i + 2]};
  }
};

/// Options of RenderView.
struct RenderOptions {
  int width = 1280;                          ///< pixels, 16..8192
  int height = 960;                          ///< pixels, 16..8192
  double vertical_fov = 0.7853981633974483;  ///< [rad], in (0, pi); default 45°
  /// Viewpoint [m, world]. Default: DefaultView, a three-quarter view framing the targets and
  /// the chosen sensors.
  std::optional<Vec3> eye;
  /// Point looked at [m, world]. Default: DefaultView's (the centre of what it frames).
  std::optional<Vec3> look_at;
  /// Chosen sensors' frusta; each frustum ends at the targets' far side (FrustumDepth), never
  /// beyond `far`. Faint where they cross a target, so that they do not hide its colours.
  bool draw_frusta = true;
  /// Chosen sensors' markers (numbered in the order chosen when there are at most 12), each with a
  /// dashed drop line straight down to the first surface below it (or the scene's lowest point):
  /// the height cue. Drawn with or without frusta.
  bool draw_markers = true;
  /// The default view from below (35° under the horizon, framing the targets) with the occluders
  /// left out, so that
  /// target surface resting on or hidden by other geometry shows (issue 46: the unseen third of a
  /// part lay underneath, never in the picture). eye/look_at still override the viewpoint.
  bool from_below = false;
  /// A legend in the top left corner: the colours, the result shown (in its method's colour).
  bool draw_legend = false;
  /// Points the default view also frames [m, world] (e.g. the links of an arm drawn at a view).
  std::vector<Vec3> frame_also;
  /// Throws InputError naming the field.
  void Validate() const;
};

/// Ray traces (Embree) a shaded view of `scene`: occluders grey; targets coloured by how many of
/// the chosen sensors observe the voxel hit (kObservedColors; kUnobservedColor when none), the
/// same voxels as report.json counts; the chosen sensors' markers, drop lines and frusta drawn
/// over it (dimmed where hidden). The default view (DefaultView) has every chosen sensor in it. Requires report.data (its reference and observations); InputError on bad options
/// or when eye == look_at.
Image RenderView(const RayScene& rays, const Scene& scene, const Report& report,
                 const RenderOptions& options = {});
/// The same, building the scene's RayScene for this call only.
Image RenderView(const Scene& scene, const Report& report, const RenderOptions& options = {});

/// Writes `image` as a PNG file. InputError naming the path when it cannot be written.
void WritePng(const std::string& path, const Image& image);

}  // namespace vantage
