#pragma once
/// The files a run will write, kept apart from the files it reads (issue 15: `render --png
/// run/report.json` and `observe --out mesh.ply` replaced that input with the output).
#include <string>
#include <utility>
#include <vector>

namespace vantage {

/// While one lives, a reader about to open one of `outputs` ((option, path), e.g. ("--out",
/// "scene.vis")) as an input — the scene, a mesh, a URDF, a material script, a report — refuses it
/// with an InputError naming the option: the run stops when the reader meets the file, before
/// any ray is cast, and the file stays as it was.
class OutputGuard {
 public:
  explicit OutputGuard(std::vector<std::pair<std::string, std::string>> outputs);
  ~OutputGuard();
  OutputGuard(const OutputGuard&) = delete;
  OutputGuard& operator=(const OutputGuard&) = delete;

 private:
  std::vector<std::pair<std::string, std::string>> outputs_;
};

}  // namespace vantage
