// LoadProblem: the scene readers in one table by file extension (as Open3D's PointCloudIO.cpp
// chooses its readers), so that a new reader is one row and the unknown-extension message names
// every reader there is. LoadOptions::Validate, which every reader calls first, is here too.
#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "util/cell_size.hpp"
#include "util/words.hpp"
#include "vantage/error.hpp"
#include "vantage/problem.hpp"

namespace vantage {
namespace {

/// One scene reader: the extensions it reads (lower case, with the dot), its function, and how
/// the unknown-extension message names it ("{}" stands for the extensions, joined by '/').
struct SceneReader {
  std::vector<std::string> extensions;
  Problem (*load)(const std::string& path, const LoadOptions& options);
  std::string description;
};

const std::vector<SceneReader>& SceneReaders() {
  static const std::vector<SceneReader> readers = {
      {{".yaml", ".yml"}, LoadYamlScene, "a {} scene (docs/scene-format.md)"},
      {{".world", ".sdf"}, LoadGazeboWorld, "a Gazebo {}"},
  };
  return readers;
}

}  // namespace

void LoadOptions::Validate() const {
  // Worded as ReferenceOptions::Validate words it (the scene layer cannot call the reference
  // stage above it), placed at the option.
  if (cell_size) {
    if (const std::string problem = detail::CellSizeProblem(*cell_size); !problem.empty())
      throw InputError(AtPlace("--cell-size", 0, problem));
  }
  // A target name is matched against the scene's names, which take no control character; it
  // is refused here, so that no message echoes it raw (issue 15).
  for (const std::string& target : targets) {
    if (const std::string problem = detail::NameProblem(target); !problem.empty())
      throw InputError(AtPlace(targets_origin, 0,
                               fmt::format("'{}' {}", detail::Escaped(target), problem)));
  }
  struct Folders {
    const std::vector<std::string>& paths;
    const std::string& origin;
    const char* holding;
  };
  for (const Folders& list :
       {Folders{model_paths, model_paths_origin, "a folder of Gazebo models (each a folder with a "
                                                 "model.config)"},
        Folders{resource_paths, resource_paths_origin,
                "a folder of Gazebo resources (holding materials/scripts/)"},
        Folders{package_paths, package_paths_origin,
                "a folder holding ROS packages, or an install prefix with share/PKG"}}) {
    for (const std::string& folder : list.paths) {
      std::error_code error;
      if (!std::filesystem::is_directory(folder, error))
        throw InputError(AtPlace(list.origin, 0,
                                 fmt::format("'{}' is not a folder — give {}",
                                             ShownOnOneLine(folder), list.holding)));
    }
  }
}

std::string MinSeparationProblem(double metres) {
  if (std::isfinite(metres) && metres >= kMinSeparationFloor && metres <= kMaxWorldCoordinate)
    return "";
  return fmt::format("min_separation {} m is outside [{:g}, {:g}] m — give the distance between "
                     "two mounts in metres, e.g. 0.15",
                     metres, kMinSeparationFloor, kMaxWorldCoordinate);
}

bool KeepOutBox::Contains(const Vec3& world) const {
  const Vec3 local = world_from_box.Inverse() * world;
  return (local.array() >= min.array()).all() && (local.array() <= max.array()).all();
}

bool InKeepOut(std::span<const KeepOutBox> boxes, const Vec3& world) {
  return std::any_of(boxes.begin(), boxes.end(),
                     [&](const KeepOutBox& box) { return box.Contains(world); });
}

Problem LoadProblem(const std::string& path, const LoadOptions& options) {
  const std::string extension = LowerExtension(path);
  std::string readers;
  for (const SceneReader& reader : SceneReaders()) {
    const auto& names = reader.extensions;
    if (std::find(names.begin(), names.end(), extension) != names.end()) {
      Problem problem = reader.load(path, options);
      CheckSceneExtent(problem.scene, problem.source);
      for (std::string& warning : CollapsedOccluderWarnings(problem.scene, problem.source)) {
        problem.warnings.push_back(warning);
        problem.notes.push_back(std::move(warning));
      }
      return problem;
    }
    readers += fmt::format("{}{}", readers.empty() ? "" : " or ",
                           fmt::format(fmt::runtime(reader.description), fmt::join(names, "/")));
  }
  throw InputError(
      AtPlace(path, 0, fmt::format("unknown scene extension '{}' — give {}", extension, readers)));
}

}  // namespace vantage
