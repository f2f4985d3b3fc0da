// The outputs of a camera on an arm (issue 45): its tour in report.json, views.yaml for a robot
// program, and trajectory.json, which mirrors ROS 2's trajectory_msgs/msg/JointTrajectory so
// that a ROS node (or MoveIt's execution) can load it field for field.
#include "report/arm_export.hpp"

#include <fmt/format.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>

#include "vantage/error.hpp"
#include "vantage/types.hpp"

namespace vantage::detail {
namespace {

using nlohmann::ordered_json;

/// Seconds as builtin_interfaces/Duration.
ordered_json Duration(double seconds) {
  const double whole = std::floor(seconds);
  auto nanosec = static_cast<int64_t>(std::llround((seconds - whole) * 1e9));
  auto sec = static_cast<int64_t>(whole);
  if (nanosec >= 1'000'000'000) {
    ++sec;
    nanosec -= 1'000'000'000;
  }
  ordered_json d;
  d["sec"] = sec;
  d["nanosec"] = nanosec;
  return d;
}

/// When the arm arrives at each view, starts its acquisition and leaves (after it) [s from
/// home]. With a state interval (--track) view k's acquisition starts at the first's + k · T
/// (the moves fit: the arm waits); otherwise at once.
void Timeline(const ArmTour& tour, std::vector<double>* arrive, std::vector<double>* leave,
              std::vector<double>* acquire = nullptr) {
  double at = 0;
  for (size_t k = 0; k < tour.views.size(); ++k) {
    at += tour.move_seconds[k];
    arrive->push_back(at);
    if (tour.state_interval && k > 0)
      at = std::max(at, (acquire ? (*acquire)[0] : arrive->front()) +
                            static_cast<double>(k) * *tour.state_interval);
    if (acquire) acquire->push_back(at);
    at += tour.acquisition_seconds[k];
    leave->push_back(at);
  }
}

/// A planned move's waypoints (the straight move collides): `key: [{positions, seconds}, ...]`,
/// seconds after the move starts.
void Via(const ArmVia& via, const char* key, YAML::Emitter* out) {
  *out << YAML::Key << key << YAML::Value << YAML::BeginSeq;
  for (size_t s = 0; s < via.waypoints.size(); ++s) {
    *out << YAML::BeginMap;
    *out << YAML::Key << "positions" << YAML::Value << YAML::Flow << via.waypoints[s];
    *out << YAML::Key << "seconds" << YAML::Value << via.seconds[s];
    *out << YAML::EndMap;
  }
  *out << YAML::EndSeq;
}

}  // namespace

ordered_json ArmTourJson(const ArmTour& tour, const VisibilityFile& data) {
  ordered_json j;
  j["robot"] = tour.robot;
  j["method"] = tour.tour.method;
  j["exact"] = tour.tour.exact;
  j["connected"] = tour.tour.connected();
  j["seconds"] = tour.tour.connected() ? ordered_json(tour.tour.total_seconds) : ordered_json();
  j["motion_seconds"] = tour.tour.connected() ? ordered_json(tour.tour.motion_seconds) : ordered_json();
  j["acquisition_seconds"] = tour.tour.acquisition_seconds;
  ordered_json order = ordered_json::array();
  for (uint32_t view : tour.views) order.push_back(data.candidates.at(view).name);
  j["order"] = std::move(order);
  if (!tour.states.empty()) j["states"] = tour.states;  // --track: the state of each view
  j["resolution"] = tour.resolution;
  j["unconnected_moves"] = tour.unconnected_pairs;
  j["planned_moves"] = tour.planned_pairs;
  return j;
}

std::string ViewsYaml(const ArmTour& tour, const VisibilityFile& data) {
  std::vector<double> arrive, leave, acquire;
  Timeline(tour, &arrive, &leave, &acquire);
  YAML::Emitter out;
  out.SetDoublePrecision(9);
  out << YAML::BeginMap;
  out << YAML::Key << "robot" << YAML::Value << tour.robot;
  out << YAML::Key << "joint_names" << YAML::Value << YAML::Flow << tour.joint_names;
  out << YAML::Key << "home" << YAML::Value << YAML::Flow << tour.home;
  out << YAML::Key << "order" << YAML::Value << tour.tour.method;
  out << YAML::Key << "exact" << YAML::Value << tour.tour.exact;
  if (tour.tour.connected()) {
    out << YAML::Key << "tour_seconds" << YAML::Value << tour.tour.total_seconds;
  } else {
    out << YAML::Key << "tour_seconds" << YAML::Value << YAML::Null;
  }
  out << YAML::Key << "views" << YAML::Value << YAML::BeginSeq;
  for (size_t k = 0; k < tour.views.size(); ++k) {
    const Candidate& c = data.candidates.at(tour.views[k]);
    const Pose& pose = c.world_from_body;
    out << YAML::BeginMap;
    out << YAML::Key << "name" << YAML::Value << c.name;
    if (k < tour.states.size()) out << YAML::Key << "state" << YAML::Value << tour.states[k];
    out << YAML::Key << "positions" << YAML::Value << YAML::Flow << tour.configurations[k];
    out << YAML::Key << "move_seconds" << YAML::Value << tour.move_seconds[k];
    if (k < tour.move_via.size() && !tour.move_via[k].empty())
      Via(tour.move_via[k], "via", &out);
    out << YAML::Key << "arrive_seconds" << YAML::Value << arrive[k];
    if (tour.state_interval)
      out << YAML::Key << "acquire_seconds" << YAML::Value << acquire[k];
    out << YAML::Key << "acquisition_seconds" << YAML::Value << tour.acquisition_seconds[k];
    out << YAML::Key << "camera_pose" << YAML::Value << YAML::BeginMap;
    out << YAML::Key << "frame_id" << YAML::Value << "world";
    out << YAML::Key << "xyz" << YAML::Value << YAML::Flow
        << std::vector<double>{pose.position.x(), pose.position.y(), pose.position.z()};
    out << YAML::Key << "quaternion_wxyz" << YAML::Value << YAML::Flow
        << std::vector<double>{pose.rotation.w(), pose.rotation.x(), pose.rotation.y(),
                               pose.rotation.z()};
    out << YAML::EndMap;
    out << YAML::EndMap;
  }
  out << YAML::EndSeq;
  out << YAML::Key << "return_seconds" << YAML::Value << tour.return_seconds;
  if (!tour.return_via.empty()) Via(tour.return_via, "return_via", &out);
  out << YAML::EndMap;
  return std::string("# vantage: one camera on the arm, its views in tour order (docs/arm.md)\n") +
         out.c_str() + "\n";
}

ordered_json ArmTrackJson(const TrackInfo& track, const VisibilityFile& data) {
  ordered_json j;
  j["method"] = "dynamic-programme";
  j["exact"] = true;
  j["move_penalty"] = track.move_penalty;
  j["state_interval"] = track.state_interval ? ordered_json(*track.state_interval) : ordered_json();
  j["value"] = track.value;
  j["coverage_sum"] = track.coverage_sum;
  j["move_seconds"] = track.move_seconds;
  j["views"] = track.views;
  j["checked_moves"] = track.checked_moves;
  j["solves"] = track.solves;
  ordered_json states = ordered_json::array();
  for (const TrackInfo::State& state : track.states) {
    ordered_json s;
    s["state"] = state.name;
    s["view"] = data.candidates.at(state.view).name;
    s["coverage"] = state.coverage;
    s["move_seconds"] = state.move_seconds;
    s["planned"] = state.planned;
    s["views_free"] = state.views_free;
    states.push_back(std::move(s));
  }
  j["states"] = std::move(states);
  return j;
}

std::string TrajectoryJson(const ArmTour& tour) {
  std::vector<double> arrive, leave, acquire;
  Timeline(tour, &arrive, &leave, &acquire);
  ordered_json j;
  j["_type"] = "trajectory_msgs/msg/JointTrajectory";
  j["header"] = {{"stamp", {{"sec", 0}, {"nanosec", 0}}}, {"frame_id", "world"}};
  j["joint_names"] = tour.joint_names;
  ordered_json points = ordered_json::array();
  const std::vector<double> still(tour.joint_names.size(), 0.0);
  const auto point = [&](const std::vector<double>& q, double t) {
    ordered_json p;
    p["positions"] = q;
    p["velocities"] = still;  // the arm stops at every view (straight moves, stop to stop)
    p["accelerations"] = ordered_json::array();
    p["effort"] = ordered_json::array();
    p["time_from_start"] = Duration(t);
    points.push_back(std::move(p));
  };
  // A planned move's waypoints, at the times the tour gives them (the arm stops at each).
  const auto via_points = [&](const ArmVia& via, double depart) {
    for (size_t s = 0; s < via.waypoints.size(); ++s) point(via.waypoints[s], depart + via.seconds[s]);
  };
  point(tour.home, 0.0);
  double departed = 0;
  for (size_t k = 0; k < tour.views.size(); ++k) {
    if (k < tour.move_via.size()) via_points(tour.move_via[k], departed);
    point(tour.configurations[k], arrive[k]);
    if (acquire[k] > arrive[k]) point(tour.configurations[k], acquire[k]);  // waits for its state
    if (tour.acquisition_seconds[k] > 0) point(tour.configurations[k], leave[k]);
    departed = leave[k];
  }
  via_points(tour.return_via, departed);
  point(tour.home, departed + tour.return_seconds);
  j["points"] = std::move(points);
  return j.dump(2) + "\n";
}

}  // namespace vantage::detail

namespace vantage {

ArmViewsFile ReadArmViews(const std::string& path) {
  YAML::Node root;
  try {
    root = YAML::LoadFile(path);
  } catch (const YAML::Exception& e) {
    throw InputError(AtPlace(path, e.mark.line + 1, fmt::format("not YAML: {}", e.msg)));
  }
  const auto bad = [&](const YAML::Node& at, const std::string& what) {
    return InputError(AtPlace(path, at.Mark().line + 1,
                              what + " — give the views.yaml a vantage run wrote"));
  };
  ArmViewsFile file;
  try {
    if (!root.IsMap() || !root["robot"] || !root["joint_names"] || !root["views"])
      throw bad(root, "needs `robot`, `joint_names` and `views`");
    file.robot = root["robot"].as<std::string>();
    file.joint_names = root["joint_names"].as<std::vector<std::string>>();
    // A mapping here gave yaml-cpp's "invalid node; this may result from using a map iterator".
    if (!root["views"].IsSequence()) throw bad(root["views"], "`views` must be a list of views");
    for (const YAML::Node& view : root["views"]) {
      if (!view.IsMap()) throw bad(view, "a view needs `name` and `positions`");
      if (!view["name"] || !view["positions"]) throw bad(view, "a view needs `name` and `positions`");
      file.views.push_back(view["name"].as<std::string>());
      file.lines.push_back(view.Mark().line + 1);
      file.positions.push_back(view["positions"].as<std::vector<double>>());
      if (file.positions.back().size() != file.joint_names.size())
        throw bad(view, fmt::format("view '{}' has {} positions for {} joint names",
                                    file.views.back(), file.positions.back().size(),
                                    file.joint_names.size()));
      for (double q : file.positions.back())
        if (!std::isfinite(q)) throw bad(view, fmt::format("view '{}': a position is not finite", file.views.back()));
    }
  } catch (const YAML::Exception& e) {
    throw InputError(AtPlace(path, e.mark.line + 1, fmt::format("unexpected value: {}", e.msg)));
  }
  return file;
}

}  // namespace vantage
