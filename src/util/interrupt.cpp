#include "vantage/interrupt.hpp"

#include <array>
#include <atomic>
#include <csignal>

namespace vantage {
namespace {

// 0: no request; -1: requested by a call; otherwise the signal.
std::atomic<int> g_request{0};
static_assert(std::atomic<int>::is_always_lock_free, "read and written in a signal handler");

// The signals that ask a run to stop: Ctrl-C, kill, and the terminal closing.
constexpr std::array<int, 3> kStopSignals = {SIGINT, SIGTERM, SIGHUP};
std::array<struct sigaction, kStopSignals.size()> g_previous{};

extern "C" void RequestOnSignal(int signal) {
  int expected = 0;
  if (g_request.compare_exchange_strong(expected, signal)) return;
  // The second Ctrl-C: the user wants out now, whatever is running.
  std::signal(signal, SIG_DFL);
  std::raise(signal);
}

}  // namespace

Interrupted::Interrupted(int signal)
    : std::runtime_error(signal == SIGTERM  ? "terminated (SIGTERM)"
                         : signal == SIGINT ? "interrupted (Ctrl-C)"
                         : signal == SIGHUP ? "hung up (SIGHUP)"
                                            : "interrupted"),
      signal_(signal) {}

void RequestInterrupt(int signal) noexcept {
  int expected = 0;
  g_request.compare_exchange_strong(expected, signal == 0 ? -1 : signal);
}

bool InterruptRequested() noexcept { return g_request.load(std::memory_order_relaxed) != 0; }

void ThrowIfInterrupted() {
  const int request = g_request.load(std::memory_order_relaxed);
  if (request != 0) throw Interrupted(request < 0 ? 0 : request);
}

void ClearInterrupt() noexcept { g_request.store(0); }

InterruptOnSignals::InterruptOnSignals() {
  struct sigaction action {};
  action.sa_handler = RequestOnSignal;
  sigemptyset(&action.sa_mask);
  for (size_t i = 0; i < kStopSignals.size(); ++i)
    ::sigaction(kStopSignals[i], &action, &g_previous[i]);
}

InterruptOnSignals::~InterruptOnSignals() {
  for (size_t i = 0; i < kStopSignals.size(); ++i)
    ::sigaction(kStopSignals[i], &g_previous[i], nullptr);
}

}  // namespace vantage
