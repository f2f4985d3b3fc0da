#include "util/run_files.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <filesystem>
#include <mutex>

#include "vantage/error.hpp"
#include "vantage/output_guard.hpp"

namespace vantage {
namespace {

std::mutex planned_mutex;
// Every live OutputGuard's entries (a Python session may run two commands at once).
std::vector<std::pair<std::string, std::string>> planned;

}  // namespace

OutputGuard::OutputGuard(std::vector<std::pair<std::string, std::string>> outputs)
    : outputs_(std::move(outputs)) {
  const std::lock_guard<std::mutex> lock(planned_mutex);
  planned.insert(planned.end(), outputs_.begin(), outputs_.end());
}

OutputGuard::~OutputGuard() {
  const std::lock_guard<std::mutex> lock(planned_mutex);
  for (const auto& output : outputs_) {
    const auto it = std::find(planned.begin(), planned.end(), output);
    if (it != planned.end()) planned.erase(it);
  }
}

namespace detail {

void NoteInputFile(const std::string& path, std::string_view kind) {
  const std::lock_guard<std::mutex> lock(planned_mutex);
  for (const auto& [option, output] : planned) {
    std::error_code error;
    // equivalent() sees through links and other spellings; false while the output is new.
    if (std::filesystem::equivalent(output, path, error))
      throw InputError(fmt::format("{}: '{}' is the {} '{}' that this run reads — writing it would "
                                   "replace that input; choose another file",
                                   option, output, kind, path));
  }
}

}  // namespace detail
}  // namespace vantage
