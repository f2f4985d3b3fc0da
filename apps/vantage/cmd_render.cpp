// `vantage render OUT_DIR --png view.png`: a picture of a finished run without a browser. The
// scene named in OUT_DIR/report.json is reloaded and the report's chosen sensors re-observed, so
// the colours are those of the numbers in report.json (issue #7).
#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <memory>
#include <nlohmann/json.hpp>
#include <numeric>

#include "commands.hpp"
#include "vantage/visualize.hpp"

namespace vantage::cli {
namespace {

namespace fs = std::filesystem;

struct RenderCommandOptions {
  std::string dir;
  std::string png;
  std::string scene;
  std::vector<std::string> model_paths;
  std::vector<std::string> resource_paths;
  std::vector<std::string> targets;
  std::vector<double> eye;
  std::vector<double> look_at;
  int width = 1280;
  int height = 960;
  double fov_deg = 45;
  bool no_frusta = false;
};

// The scene path and cell size that report.json records.
struct ReportHeader {
  std::string scene;
  double cell_size = 0;
  std::optional<double> coverage;  ///< of the primary result, to compare with
};

ReportHeader ReadReportHeader(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in)
    throw InputError(
        AtPlace(path, 0,
                "cannot open report.json — give an output folder of `vantage optimize`, "
                "`select` or `evaluate`"));
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const nlohmann::json j = nlohmann::json::parse(text, nullptr, /*allow_exceptions=*/false);
  if (j.is_discarded() || !j.is_object())
    throw InputError(AtPlace(path, 0, "not valid JSON — give a report.json written by vantage"));
  ReportHeader header;
  if (!j.contains("scene") || !j["scene"].is_string() || j["scene"].get<std::string>().empty())
    throw InputError(AtPlace(path, 0, "no 'scene' path — give the scene with --scene PATH"));
  header.scene = j["scene"].get<std::string>();
  if (!j.contains("cell_size") || !j["cell_size"].is_number() ||
      !(j["cell_size"].get<double>() > 0))
    throw InputError(AtPlace(
        path, 0, "'cell_size' must be a positive number — give a report.json written by vantage"));
  header.cell_size = j["cell_size"].get<double>();
  if (j.contains("results") && j["results"].is_array() && !j["results"].empty()) {
    size_t which = 0;
    if (j.contains("primary_result") && j["primary_result"].is_number_unsigned() &&
        j["primary_result"].get<size_t>() < j["results"].size())
      which = j["primary_result"].get<size_t>();
    const auto& result = j["results"][which];
    if (result.is_object() && result.contains("coverage") && result["coverage"].is_number())
      header.coverage = result["coverage"].get<double>();
  }
  return header;
}

std::optional<Vec3> PointOption(const std::vector<double>& values) {
  if (values.empty()) return std::nullopt;
  return Vec3(values[0], values[1], values[2]);
}

void RunRender(const RenderCommandOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  const std::string report_path = fs::is_directory(options.dir)
                                      ? (fs::path(options.dir) / "report.json").string()
                                      : options.dir;
  const ReportHeader header = ReadReportHeader(report_path);
  const Constellation constellation = LoadConstellation(report_path);

  const std::string scene_path = options.scene.empty() ? header.scene : options.scene;
  if (!fs::exists(scene_path))
    throw InputError(AtPlace(report_path, 0,
                             fmt::format("its scene '{}' is not found from here — run from the "
                                         "folder the run started in, or give --scene PATH",
                                         scene_path)));
  LoadOptions load;
  load.model_paths = options.model_paths;
  load.resource_paths = options.resource_paths;
  load.targets = options.targets;
  load.cell_size = header.cell_size;  // the run's tessellation, also after --cell-size
  const Problem problem = LoadProblem(scene_path, load);

  // Re-observe the chosen sensors: the same voxels as the report counts.
  VisibilityFile data;
  data.scene = scene_path;
  data.reference = BuildReference(problem.scene, ReferenceOptions{header.cell_size});
  data.candidates = constellation.sensors;
  data.observations = Observe(problem.scene, data.reference, data.candidates);
  const CoverageEvaluator evaluator(data.observations, data.reference.size());
  Selection given = WholeConstellation(evaluator);
  if (header.coverage && std::abs(*header.coverage - given.coverage) > 1e-9)
    spdlog::warn("{}: coverage {:.4f} % now, {:.4f} % in the report — has the scene changed since?",
                 report_path, 100.0 * given.coverage, 100.0 * *header.coverage);

  Report report;
  report.scene = scene_path;
  report.data = &data;
  report.results = {given};

  RenderOptions render;
  render.width = options.width;
  render.height = options.height;
  render.vertical_fov = options.fov_deg * 3.14159265358979323846 / 180.0;
  render.eye = PointOption(options.eye);
  render.look_at = PointOption(options.look_at);
  render.draw_frusta = !options.no_frusta;
  const std::string png =
      options.png.empty() ? (fs::path(options.dir) / "view.png").string() : options.png;
  WritePng(png, RenderView(problem.scene, report, render));
  fmt::print("render  {}  {}x{}  {} sensors, coverage {:.2f} %  {:.3f} s\n", png, render.width,
             render.height, data.candidates.size(), 100.0 * given.coverage, SecondsSince(start));
}

}  // namespace

void SetupRender(CLI::App* parent) {
  auto options = std::make_shared<RenderCommandOptions>();
  CLI::App* app = parent->add_subcommand(
      "render",
      "ray-trace a PNG of a finished run: targets coloured observed / unobserved, sensors' frusta");
  app->add_option("dir", options->dir,
                  "output folder of optimize/select/evaluate (or its report.json)")
      ->required();
  app->add_option("--png", options->png, "PNG file to write (default: DIR/view.png)");
  app->add_option("--eye", options->eye,
                  "viewpoint x y z [m] (default: framing targets and sensors)")
      ->expected(3);
  app->add_option("--look-at", options->look_at,
                  "point looked at x y z [m] (default: the targets' centre)")
      ->expected(3);
  app->add_option("--width", options->width, "picture width [px]")
      ->check(CLI::Range(16, 8192))
      ->capture_default_str();
  app->add_option("--height", options->height, "picture height [px]")
      ->check(CLI::Range(16, 8192))
      ->capture_default_str();
  app->add_option("--fov", options->fov_deg, "vertical field of view [deg]")
      ->check(CLI::Range(1.0, 170.0))
      ->capture_default_str();
  app->add_flag("--no-frusta", options->no_frusta, "do not draw the sensors' frusta");
  app->add_option("--scene", options->scene, "scene file (default: the one named in report.json)");
  app->add_option("--model-path", options->model_paths, "folder of Gazebo models (repeatable)");
  app->add_option("--resource-path", options->resource_paths,
                  "folder of Gazebo resources (repeatable)");
  app->add_option("--target", options->targets,
                  "target object/model name, as given to the run (repeatable)");
  app->callback([options] { RunRender(*options); });
}

}  // namespace vantage::cli
