// Method names (settings.hpp): in the util layer so that the scene readers parse `method` without
// depending on selection.
#include "vantage/settings.hpp"

#include <fmt/format.h>

#include <array>

#include "vantage/error.hpp"

namespace vantage {
namespace {

constexpr std::array<Method, 6> kMethods = {Method::kBest,  Method::kRansac, Method::kGreedy,
                                            Method::kLocal, Method::kExact,  Method::kAll};

}  // namespace

std::string MethodName(Method method) {
  switch (method) {
    case Method::kBest:
      return "best";
    case Method::kRansac:
      return "ransac";
    case Method::kGreedy:
      return "greedy";
    case Method::kLocal:
      return "local";
    case Method::kExact:
      return "exact";
    case Method::kAll:
      return "all";
  }
  VANTAGE_CHECK(false);
  return "";
}

Method ParseMethod(const std::string& name) {
  std::string names;
  for (const Method method : kMethods) {
    if (MethodName(method) == name) return method;
    names += (names.empty() ? "" : ", ") + MethodName(method);
  }
  throw InputError(fmt::format("unknown method '{}' — use one of {}", name, names));
}

}  // namespace vantage
