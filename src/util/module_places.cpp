#include "util/module_places.hpp"

#include <dlfcn.h>
#include <fmt/format.h>

#include <cstring>
#include <system_error>

#include "vantage/error.hpp"

namespace vantage::detail {

std::vector<std::filesystem::path> ModulePlaces(const void* code, const std::string& name,
                                                const std::string& from_bin,
                                                const std::string& built) {
  std::vector<std::filesystem::path> folders;
  Dl_info info{};
  if (dladdr(code, &info) != 0 && info.dli_fname != nullptr &&
      std::strchr(info.dli_fname, '/') != nullptr) {
    folders.push_back(std::filesystem::path(info.dli_fname).parent_path());
  }
  std::error_code error;
  const std::filesystem::path self = std::filesystem::read_symlink("/proc/self/exe", error);
  // The binary's folder once, when the code running is the binary itself.
  if (!error && (folders.empty() || folders.front() != self.parent_path()))
    folders.push_back(self.parent_path());
  std::vector<std::filesystem::path> places;
  for (const std::filesystem::path& folder : folders) {
    places.push_back(folder / name);
    places.push_back(folder / from_bin / name);
  }
  places.emplace_back(built);
  return places;
}

std::optional<std::filesystem::path> FirstModulePlace(
    const std::vector<std::filesystem::path>& places, std::string* tried) {
  for (const std::filesystem::path& place : places) {
    std::error_code error;
    if (std::filesystem::is_regular_file(place, error)) return place;
    *tried += (tried->empty() ? "" : ", ") + place.string();
  }
  return std::nullopt;
}

ModuleEntry LoadModuleEntry(const void* code, const std::string& name,
                            const std::string& from_bin, const std::string& built,
                            const std::string& purpose, const std::string& what,
                            const char* symbol) {
  std::string tried;
  const std::optional<std::filesystem::path> place =
      FirstModulePlace(ModulePlaces(code, name, from_bin, built), &tried);
  if (!place)
    throw InternalError(fmt::format("cannot {}: the {} {} is not installed (looked at {})",
                                    purpose, what, name, tried));
  void* module = dlopen(place->c_str(), RTLD_NOW | RTLD_LOCAL);
  if (module == nullptr)
    throw InternalError(fmt::format("cannot load the {} {}: {}", what, place->string(), dlerror()));
  using Entry = const void* (*)();
  const auto entry = reinterpret_cast<Entry>(dlsym(module, symbol));
  return {entry ? entry() : nullptr, *place};
}

}  // namespace vantage::detail
