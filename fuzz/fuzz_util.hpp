#pragma once
/// Shared by the libFuzzer targets: a scratch folder per process in which the fuzzed bytes are
/// written as a file (the loaders read paths), laid out so that the relative paths of the seed
/// corpus resolve (`../meshes/…` of the example scenes, `materials/…` and `model://…` of the test
/// worlds).
#include <spdlog/spdlog.h>
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

namespace vantage::fuzz {

/// Absolute path of a folder of the source tree (VANTAGE_SOURCE_DIR is set by fuzz/CMakeLists.txt).
inline std::string SourcePath(const std::string& relative) {
  return std::string(VANTAGE_SOURCE_DIR) + "/" + relative;
}

/// /tmp/vantage_fuzz_<pid>, created with its links the first time and removed at exit. Held by a
/// pointer that is never freed: the exit handler runs after function-local statics are destroyed.
inline const std::string& ScratchDir() {
  static const std::string* const dir = [] {
    namespace fs = std::filesystem;
    const fs::path path =
        fs::temp_directory_path() / ("vantage_fuzz_" + std::to_string(::getpid()));
    fs::remove_all(path);
    fs::create_directories(path / "scenes");
    // YAML scenes of examples/scenes name meshes as ../meshes/NAME.
    fs::create_directory_symlink(SourcePath("examples/meshes"), path / "meshes");
    // Test worlds name file://materials/… and model folders beside them.
    fs::create_directory_symlink(SourcePath("tests/data/worlds/materials"), path / "materials");
    fs::create_directory_symlink(SourcePath("tests/data/worlds/models"), path / "models");
    auto* created = new std::string(path.string());  // NOLINT(cppcoreguidelines-owning-memory)
    std::atexit([] {
      std::error_code ec;
      fs::remove_all(ScratchDir(), ec);
    });
    return created;
  }();
  return *dir;
}

/// What every target's LLVMFuzzerInitialize does (each is one line that returns this): logging
/// off (the readers' warnings would flood the fuzzer's output), no Gazebo search paths from the
/// machine (only the model paths a target passes may change an outcome), the scratch folder
/// created before the first input. Runs before any thread starts, so unsetenv is safe.
inline int Initialize() {
  spdlog::set_level(spdlog::level::off);
  ::unsetenv("GAZEBO_MODEL_PATH");     // NOLINT(concurrency-mt-unsafe): before any thread starts
  ::unsetenv("GAZEBO_RESOURCE_PATH");  // NOLINT(concurrency-mt-unsafe)
  ScratchDir();
  return 0;
}

/// Writes the fuzzed bytes to ScratchDir()/relative and returns the file's path.
inline std::string WriteInput(const std::string& relative, const uint8_t* data, size_t size) {
  const std::string path = ScratchDir() + "/" + relative;
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  return path;
}

}  // namespace vantage::fuzz
