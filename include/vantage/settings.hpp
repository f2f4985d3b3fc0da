#pragma once
/// Settings that a scene declares for the stages after it, in the util layer (std only): the
/// scene readers fill them without seeing selection, and select.hpp includes this header for
/// Method.
#include <map>
#include <optional>
#include <string>

namespace vantage {

enum class Method { kBest, kRansac, kGreedy, kLocal, kExact, kAll };

/// "best", "ransac", ... ; ParseMethod throws InputError listing the valid names.
std::string MethodName(Method method);
Method ParseMethod(const std::string& name);

/// The selection settings a scene declares (YAML `settings:`, the Gazebo plugin's parameters);
/// the pipeline turns them into SelectOptions, command-line options first.
struct SelectionSettings {
  int n = 1;                     ///< sensors wanted (numberOfIntendedSensors)
  std::optional<Method> method;  ///< unset: the command's default
  int ransac_iterations = 1000;
  double ransac_stop_coverage = 1.0;  ///< fraction in [0, 1]
  std::optional<double> goal;         ///< fewest sensors reaching this coverage
  int k = 1;                          ///< k-coverage when >= 2
  std::optional<double> budget;       ///< total sensor cost cap
  /// The scene file's line of each setting it gives, by SelectOptions' field name ("n",
  /// "ransac_iterations", ...), so that a setting found invalid later (n above the candidates)
  /// names its line. Empty for defaults and visibility files (not stored there).
  std::map<std::string, int> lines;
};

}  // namespace vantage
