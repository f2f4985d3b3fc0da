#pragma once
/// Finding a run-time module (the CAD reader, libvantage_cad.so; Assimp's mesh reader,
/// libvantage_assimp.so; the arm module, libvantage_arm.so; CBC and CLP, libvantage_cbc.so):
/// shared objects loaded with dlopen the first time they are needed, so that a process that never
/// reads CAD or a mesh through Assimp, plans for an arm or solves a model does not map their
/// libraries.
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace vantage::detail {

/// Where the module `name` may be, in order: beside the code running (the binary, or the Python
/// module's shared object: the object holding `code`, then /proc/self/exe), in the install's
/// library folder relative to it (`from_bin`: `cmake --install` puts bin/vantage and
/// lib/vantage/NAME), and the build tree's own copy `built` (the tests, the Python module run
/// from build/).
std::vector<std::filesystem::path> ModulePlaces(const void* code, const std::string& name,
                                                const std::string& from_bin,
                                                const std::string& built);

/// The first of `places` that is a regular file, or nullopt; `tried` gets the places passed
/// over, comma-separated, for the message that says the module is not installed.
std::optional<std::filesystem::path> FirstModulePlace(
    const std::vector<std::filesystem::path>& places, std::string* tried);

/// What a module's API entry (a C function taking nothing) returned: the process keeps the module
/// mapped until it ends (its objects may live that long). `place`: where it was found.
struct ModuleEntry {
  const void* api = nullptr;  ///< null when the module has no `symbol` or its entry gave none
  std::filesystem::path place;
};

/// Finds the module (ModulePlaces, FirstModulePlace), loads it and calls its entry `symbol`.
/// InternalError when it is not installed ("cannot `purpose`: the `what` NAME is not installed
/// (looked at ...)") or cannot be loaded ("cannot load the `what` PLACE: dlerror"). The caller
/// checks the API it gets (its type and version).
ModuleEntry LoadModuleEntry(const void* code, const std::string& name,
                            const std::string& from_bin, const std::string& built,
                            const std::string& purpose, const std::string& what,
                            const char* symbol);

}  // namespace vantage::detail
