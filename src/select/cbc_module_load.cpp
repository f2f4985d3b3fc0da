// Loads the CBC module (cbc_module.hpp) the first time CBC or CLP is called, as arm_forward.cpp
// loads the arm module.
#include <dlfcn.h>
#include <fmt/format.h>

#include <filesystem>
#include <optional>
#include <string>

#include "select/cbc_module.hpp"
#include "util/module_places.hpp"
#include "vantage/error.hpp"

namespace vantage::detail {
namespace {

const CbcModuleApi& LoadCbcModule() {
  std::string tried;
  const std::optional<std::filesystem::path> place = FirstModulePlace(
      ModulePlaces(reinterpret_cast<const void*>(&Cbc), VANTAGE_CBC_MODULE_NAME,
                   VANTAGE_CBC_MODULE_FROM_BIN, VANTAGE_CBC_MODULE_BUILT),
      &tried);
  if (!place)
    throw InternalError(fmt::format("cannot solve with CBC or CLP: the CBC module {} is not "
                                    "installed (looked at {})",
                                    VANTAGE_CBC_MODULE_NAME, tried));
  void* module = dlopen(place->c_str(), RTLD_NOW | RTLD_LOCAL);
  if (module == nullptr)
    throw InternalError(
        fmt::format("cannot load the CBC module {}: {}", place->string(), dlerror()));
  using Entry = const CbcModuleApi* (*)();
  const auto entry = reinterpret_cast<Entry>(dlsym(module, "vantage_cbc_module"));
  const CbcModuleApi* api = entry ? entry() : nullptr;
  if (api == nullptr || api->version != kCbcModuleVersion)
    throw InternalError(fmt::format("{} is not this vantage's CBC module", place->string()));
  return *api;  // never unloaded: its models may live until the process ends
}

}  // namespace

const CbcModuleApi& Cbc() {
  static const CbcModuleApi& api = LoadCbcModule();  // once, thread-safe
  return api;
}

}  // namespace vantage::detail
