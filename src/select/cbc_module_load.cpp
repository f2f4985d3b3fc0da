// Loads the CBC module (cbc_module.hpp) the first time CBC or CLP is called, as arm_forward.cpp
// loads the arm module.
#include <fmt/format.h>

#include "select/cbc_module.hpp"
#include "util/module_places.hpp"
#include "vantage/error.hpp"

namespace vantage::detail {
namespace {

const CbcModuleApi& LoadCbcModule() {
  const ModuleEntry loaded = LoadModuleEntry(
      reinterpret_cast<const void*>(&Cbc), VANTAGE_CBC_MODULE_NAME, VANTAGE_CBC_MODULE_FROM_BIN,
      VANTAGE_CBC_MODULE_BUILT, "solve with CBC or CLP", "CBC module", "vantage_cbc_module");
  const auto* api = static_cast<const CbcModuleApi*>(loaded.api);
  if (api == nullptr || api->version != kCbcModuleVersion)
    throw InternalError(fmt::format("{} is not this vantage's CBC module", loaded.place.string()));
  return *api;  // never unloaded: its models may live until the process ends
}

}  // namespace

const CbcModuleApi& Cbc() {
  static const CbcModuleApi& api = LoadCbcModule();  // once, thread-safe
  return api;
}

}  // namespace vantage::detail
