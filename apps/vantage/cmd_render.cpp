// `vantage render OUT_DIR --png view.png`: a picture of a finished run without a browser. The
// run's scene is reloaded with the run's own inputs (report.json) and the chosen sensors
// re-observed, so the colours are those of the numbers in report.json (issue #7).
#include <fmt/format.h>

#include <memory>
#include <numbers>

#include "commands.hpp"

namespace vantage::cli {
namespace {

struct RenderFlags {
  RenderRunOptions options;
  double fov_deg = 45;
  bool no_frusta = false;
  bool no_legend = false;
};

void RunRender(RenderFlags flags) {
  const auto start = std::chrono::steady_clock::now();
  flags.options.render.vertical_fov = flags.fov_deg * std::numbers::pi / 180.0;
  flags.options.render.draw_frusta = !flags.no_frusta;
  flags.options.render.draw_legend = !flags.no_legend;
  const RenderRunResult result = RenderRun(flags.options);
  fmt::print("render  {}  {}x{}  {} sensors, coverage {:.2f} %  {:.3f} s\n", ShownOnOneLine(result.png),
             flags.options.render.width, flags.options.render.height, result.sensors,
             100.0 * result.coverage,
             std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
}

// --eye / --look-at: three numbers into an optional point.
void AddPointFlag(CLI::App* app, const std::string& flag, std::optional<Vec3>* point,
                  const std::string& help) {
  app->add_option_function<std::vector<double>>(
         flag, [point](const std::vector<double>& p) { *point = Vec3(p[0], p[1], p[2]); }, help)
      ->expected(3);
}

}  // namespace

void SetupRender(CLI::App* parent) {
  auto flags = std::make_shared<RenderFlags>();
  RenderRunOptions& options = flags->options;
  CLI::App* app = parent->add_subcommand(
      "render",
      "ray-trace a PNG of a finished run: targets coloured observed / unobserved, sensors' "
      "frusta");
  app->add_option("dir", options.run, "output folder of optimize/select/evaluate (or its report.json)")
      ->required();
  app->add_option("--arm-view", options.arm_view,
                  "a run of a camera on an arm: draw the arm at this view of its views.yaml "
                  "(1 = the first, the default)");
  app->add_option("--png", options.png, "PNG file to write (default: DIR/view.png)")
      ->check(OutPathValidator());
  AddPointFlag(app, "--eye", &options.render.eye,
               "viewpoint x y z [m] (default: framing targets and sensors)");
  AddPointFlag(app, "--look-at", &options.render.look_at,
               "point looked at x y z [m] (default: the centre of the targets and sensors)");
  app->add_option("--width", options.render.width, "picture width [px]")
      ->check(NumberFrom(16, 8192, ValueKind::kWholeNumber))
      ->capture_default_str();
  app->add_option("--height", options.render.height, "picture height [px]")
      ->check(NumberFrom(16, 8192, ValueKind::kWholeNumber))
      ->capture_default_str();
  app->add_option("--fov", flags->fov_deg, "vertical field of view [deg]")
      ->check(NumberFrom(1, 170, ValueKind::kNumber))
      ->capture_default_str();
  app->add_flag("--no-frusta", flags->no_frusta,
                "do not draw the sensors' frusta (their markers and height lines stay)");
  app->add_flag("--from-below", options.render.from_below,
                "look from below with the occluders left out: the target surface that rests on "
                "or hides behind other geometry shows, red where no chosen sensor sees it");
  app->add_flag("--no-legend", flags->no_legend, "do not draw the legend");
  app->add_option("--scene", options.scene.path,
                  "scene file (default: the one the run used, report.json `inputs`)");
  AddSourceFlags(app, &options.scene);
  app->callback([flags] { RunRender(*flags); });
}

}  // namespace vantage::cli
