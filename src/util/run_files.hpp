#pragma once
/// The files a run will write, kept apart from the files it reads (issue 15: `render --png`
/// naming the run's report.json, or `observe --out` naming a mesh of the scene, replaced that
/// input with the output).
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace vantage::detail {

/// While one lives, NoteInputFile refuses to read any of `outputs` (option, path) as an input:
/// the run stops when the reader meets the file, before its expensive work, and the file stays.
class PlannedOutputs {
 public:
  explicit PlannedOutputs(std::vector<std::pair<std::string, std::string>> outputs);
  ~PlannedOutputs();
  PlannedOutputs(const PlannedOutputs&) = delete;
  PlannedOutputs& operator=(const PlannedOutputs&) = delete;

 private:
  std::vector<std::pair<std::string, std::string>> outputs_;
};

/// Every reader calls this with each file it is about to open (`kind`: "mesh file", "URDF
/// file", ...). InputError naming the option when the file is one this run will write.
void NoteInputFile(const std::string& path, std::string_view kind);

}  // namespace vantage::detail
