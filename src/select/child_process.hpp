#pragma once
/// Running a solver that cannot be stopped from outside (CBC: its root LP ignores its time limit,
/// and its own SIGINT handler swallows Ctrl-C) in a child process, which can.
#include <functional>
#include <optional>
#include <string>

namespace vantage::detail {

/// Runs `solve` in a forked child process and returns the bytes it produced. The child is killed,
/// and nullopt returned with `why` set, when it does not finish within `seconds` or dies; on an
/// interrupt request (vantage/interrupt.hpp) it is killed and Interrupted thrown. The child runs
/// only `solve` and ends with _exit: it must not log, lock or use threads of the parent. When the
/// process cannot fork, `solve` runs in this process (without the limit).
std::optional<std::string> RunInChildProcess(const std::function<std::string()>& solve,
                                             double seconds, std::string* why);

}  // namespace vantage::detail
