#pragma once
/// The visibility matrix with what it was made from, as the versioned `.vis` file that lets
/// `vantage select` rerun selection without re-rendering (SYSTEM.md, pipeline stage 4).
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "vantage/candidates.hpp"
#include "vantage/reference.hpp"
#include "vantage/settings.hpp"
#include "vantage/visibility.hpp"

namespace vantage {

/// Everything `vantage select` needs to rerun selection without re-rendering.
struct VisibilityFile {
  std::string scene;  ///< path of the scene it came from
  uint64_t seed = 1;
  /// The scene's selection settings (n and RANSAC's since format version 1, method, goal, k and
  /// budget since version 2; older files read as the defaults).
  SelectionSettings selection;
  Reference reference;
  std::vector<Candidate> candidates;
  std::vector<Observation> observations;  ///< one per candidate
  QualityFilter quality;  ///< the filter the observations were made with (format version 3)
};

/// Writes the versioned binary file (magic, version, payload, FNV-1a 64 checksum) atomically.
void SaveVisibilityFile(const std::string& path, const VisibilityFile& file);
/// Reads it back; InputError naming the file when it is not one, corrupt, or another version.
VisibilityFile LoadVisibilityFile(const std::string& path);

}  // namespace vantage
