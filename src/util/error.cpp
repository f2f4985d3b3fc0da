#include "vantage/error.hpp"

#include <fmt/format.h>

namespace vantage {

std::string AtPlace(const std::string& file, int line, const std::string& message) {
  if (file.empty()) return message;
  if (line <= 0) return fmt::format("{}: {}", file, message);
  return fmt::format("{}:{}: {}", file, line, message);
}

void Diagnostics::Error(int line, const std::string& message) {
  messages_.push_back(AtPlace(file_, line, message));
}

void Diagnostics::ThrowIfAny() const {
  if (messages_.empty()) return;
  std::string all;
  for (size_t i = 0; i < messages_.size(); ++i) {
    if (i) all += '\n';
    all += messages_[i];
  }
  throw InputError(all);
}

void ThrowInternal(const char* condition, const char* file, int line) {
  throw InternalError(fmt::format("check failed: {} ({}:{})", condition, file, line));
}

}  // namespace vantage
