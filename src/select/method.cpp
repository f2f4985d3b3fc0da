// Method names and SelectOptions::Validate (SYSTEM.md, Select).
#include <fmt/format.h>

#include <array>
#include <cmath>

#include "vantage/error.hpp"
#include "vantage/select.hpp"

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

void SelectOptions::Validate(size_t candidate_count) const {
  if (candidate_count == 0) {
    throw InputError(fmt::format("n = {} but there are no candidates to select from", n));
  }
  if (n < 1 || static_cast<size_t>(n) > candidate_count) {
    throw InputError(
        fmt::format("n = {} is out of range: there are {} candidates, so n must be "
                    "between 1 and {}",
                    n, candidate_count, candidate_count));
  }
  if (ransac_iterations < 1) {
    throw InputError(fmt::format("ransac_iterations = {} must be at least 1", ransac_iterations));
  }
  if (!(ransac_stop_coverage >= 0.0 && ransac_stop_coverage <= 1.0)) {
    throw InputError(fmt::format("ransac_stop_coverage = {} must be a fraction in [0, 1]",
                                 ransac_stop_coverage));
  }
  if (!(time_limit > 0.0) || !std::isfinite(time_limit)) {
    throw InputError(
        fmt::format("time_limit = {} s must be a positive number of seconds", time_limit));
  }
}

}  // namespace vantage
