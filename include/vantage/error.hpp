#pragma once
/// Errors of vantage: what the user can fix (InputError, exit 2) and broken invariants
/// (InternalError, exit 1). Only `main` maps them to exit codes.
#include <stdexcept>
#include <string>
#include <vector>

namespace vantage {

/// A problem with the user's input. what() is "file:line: message" (line omitted when unknown).
class InputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// An InputError about option fields (`fields()`: the struct fields at fault, e.g. {"n", "k"}),
/// so that a caller can say where the value came from: a flag, or the scene file.
class FieldError : public InputError {
 public:
  FieldError(std::vector<std::string> fields, const std::string& message)
      : InputError(message), fields_(std::move(fields)) {}
  const std::vector<std::string>& fields() const { return fields_; }

 private:
  std::vector<std::string> fields_;
};

/// A broken invariant inside vantage: a bug, never the user's fault.
class InternalError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Formats "file:line: message", or "file: message" when line <= 0, or "message" when file is empty.
std::string AtPlace(const std::string& file, int line, const std::string& message);

/// Collects every problem of one input file, then throws once (as sdformat's Errors do).
class Diagnostics {
 public:
  explicit Diagnostics(std::string file) : file_(std::move(file)) {}
  /// Records an error at a 1-based line (<= 0: no line).
  void Error(int line, const std::string& message);
  bool HasErrors() const { return !messages_.empty(); }
  const std::string& file() const { return file_; }
  /// Throws one InputError listing every recorded problem, one per line; no-op when none.
  void ThrowIfAny() const;

 private:
  std::string file_;
  std::vector<std::string> messages_;
};

[[noreturn]] void ThrowInternal(const char* condition, const char* file, int line);

}  // namespace vantage

/// Throws InternalError when `cond` is false.
#define VANTAGE_CHECK(cond) \
  do { \
    if (!(cond)) ::vantage::ThrowInternal(#cond, __FILE__, __LINE__); \
  } while (false)
