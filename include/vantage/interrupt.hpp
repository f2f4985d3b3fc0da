#pragma once
/// Stopping a run on request (Ctrl-C): long stages poll InterruptRequested() and throw Interrupted;
/// the caller (the CLI, the Python module) decides what an interrupt means. Nothing is written
/// once a stage has thrown, so the previous outputs stay as they were.
#include <stdexcept>

namespace vantage {

/// Thrown by a stage that saw an interrupt request. `signal()` is the signal that asked for it
/// (SIGINT, SIGTERM, SIGHUP), or 0 when it was requested by a call.
class Interrupted : public std::runtime_error {
 public:
  explicit Interrupted(int signal);
  int signal() const { return signal_; }

 private:
  int signal_;
};

/// Asks every running stage to stop. Async-signal-safe: a signal handler may call it.
void RequestInterrupt(int signal = 0) noexcept;
/// True once an interrupt was requested and not yet cleared.
bool InterruptRequested() noexcept;
/// Throws Interrupted when an interrupt was requested.
void ThrowIfInterrupted();
/// Forgets a request (before a new run in the same process).
void ClearInterrupt() noexcept;

/// While alive, SIGINT, SIGTERM and SIGHUP request an interrupt instead of ending the process, so that the
/// stage running stops within a fraction of a second and nothing half-written is left; a second
/// signal ends the process at once (the default action). Restores the previous actions on exit.
class InterruptOnSignals {
 public:
  InterruptOnSignals();
  ~InterruptOnSignals();
  InterruptOnSignals(const InterruptOnSignals&) = delete;
  InterruptOnSignals& operator=(const InterruptOnSignals&) = delete;
};

}  // namespace vantage
