#include <fmt/format.h>

#include <memory>
#include <nlohmann/json.hpp>

#include "commands.hpp"

namespace vantage::cli {
namespace {

constexpr double kRadToDeg = 180.0 / 3.14159265358979323846;

void RunSensors(bool as_json) {
  if (as_json) {
    nlohmann::ordered_json list = nlohmann::ordered_json::array();
    for (const SensorType& s : Catalog()) {
      list.push_back({{"id", s.id}, {"name", s.name}, {"technology", s.technology}, {"width", s.width},
                      {"height", s.height}, {"hfov", s.HorizontalFov()}, {"vfov", s.VerticalFov()},
                      {"fx", s.fx}, {"fy", s.fy}, {"cx", s.cx}, {"cy", s.cy}, {"near", s.near},
                      {"far", s.far}, {"fps", s.fps}});
      // A vendor that publishes no price: null, not a made-up number (docs/sensor-models.md).
      list.back()["cost"] = s.cost_given ? nlohmann::ordered_json(s.cost) : nlohmann::ordered_json();
    }
    fmt::print("{}\n", list.dump(2));
    return;
  }
  fmt::print("{:<29} {:<34} {:>10} {:>13} {:>12} {:>5} {:>7}\n", "id", "sensor", "W x H",
             "fov (deg)", "range (m)", "fps", "cost");
  for (const SensorType& s : Catalog()) {
    fmt::print("{:<29} {:<34} {:>10} {:>13} {:>12} {:>5} {:>7}\n", s.id, s.name,
               fmt::format("{}x{}", s.width, s.height),
               fmt::format("{:.1f}x{:.1f}", s.HorizontalFov() * kRadToDeg, s.VerticalFov() * kRadToDeg),
               fmt::format("{:g}-{:g}", s.near, s.far), s.fps,
               s.cost_given ? fmt::format("{:g}", s.cost) : std::string("-"));
  }
}

}  // namespace

void SetupSensors(CLI::App* parent) {
  auto as_json = std::make_shared<bool>(false);
  CLI::App* app = parent->add_subcommand("sensors", "list the sensor catalog");
  app->add_flag("--json", *as_json, "print the catalog as JSON");
  app->callback([as_json] { RunSensors(*as_json); });
}

}  // namespace vantage::cli
