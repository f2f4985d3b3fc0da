#include "select/child_process.hpp"

#include <fmt/format.h>
#include <poll.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <csignal>
#include <cstring>
#include <mutex>

#include "vantage/interrupt.hpp"

namespace vantage::detail {
namespace {

// How often the parent looks at the interrupt flag while the child works.
constexpr int kPollMilliseconds = 50;

bool WriteAll(int fd, const std::string& bytes) {
  size_t done = 0;
  while (done < bytes.size()) {
    const ssize_t written = ::write(fd, bytes.data() + done, bytes.size() - done);
    if (written < 0 && errno == EINTR) continue;
    if (written <= 0) return false;
    done += static_cast<size_t>(written);
  }
  return true;
}

[[noreturn]] void ChildMain(int fd, const std::function<std::string()>& solve) {
  // The terminal's Ctrl-C reaches the whole process group: the parent decides, the child waits to
  // be killed.
  std::signal(SIGINT, SIG_IGN);
  int code = 0;
  try {
    code = WriteAll(fd, solve()) ? 0 : 3;
  } catch (...) {
    code = 4;
  }
  ::close(fd);
  ::_exit(code);  // no atexit handlers, no destructors of the parent's objects
}

void KillAndReap(pid_t child) {
  ::kill(child, SIGKILL);
  int status = 0;
  while (::waitpid(child, &status, 0) < 0 && errno == EINTR) {
  }
}

}  // namespace

std::optional<std::string> RunInChildProcess(const std::function<std::string()>& solve,
                                             double seconds, std::string* why) {
  int fds[2];
  pid_t child = -1;
  {
    // `--method all` runs exact on two threads: a child forked by one must not inherit the
    // other's write end, or that pipe's end of file waits for the wrong child.
    static std::mutex forking;
    const std::lock_guard<std::mutex> lock(forking);
    if (::pipe(fds) == 0) {
      child = ::fork();
      if (child == 0) {
        ::close(fds[0]);
        ChildMain(fds[1], solve);
      }
      if (child < 0) ::close(fds[0]);
      ::close(fds[1]);
    }
  }
  if (child < 0) return solve();
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
  std::string bytes;
  char buffer[1 << 16];
  bool open = true;
  while (open) {
    if (InterruptRequested()) {
      ::close(fds[0]);
      KillAndReap(child);
      ThrowIfInterrupted();
    }
    if (std::chrono::steady_clock::now() > deadline) {
      ::close(fds[0]);
      KillAndReap(child);
      *why = fmt::format("did not finish within {:.3g} s and was stopped", seconds);
      return std::nullopt;
    }
    pollfd ready{fds[0], POLLIN, 0};
    const int events = ::poll(&ready, 1, kPollMilliseconds);
    if (events <= 0) continue;  // timeout or EINTR: look at the flag and the clock again
    const ssize_t got = ::read(fds[0], buffer, sizeof(buffer));
    if (got < 0 && errno == EINTR) continue;
    if (got <= 0) {
      open = false;
    } else {
      bytes.append(buffer, static_cast<size_t>(got));
    }
  }
  ::close(fds[0]);
  int status = 0;
  while (::waitpid(child, &status, 0) < 0 && errno == EINTR) {
  }
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) {
    *why = WIFSIGNALED(status) ? fmt::format("died of signal {}", WTERMSIG(status))
                               : fmt::format("failed (exit status {})", WEXITSTATUS(status));
    return std::nullopt;
  }
  return bytes;
}

}  // namespace vantage::detail
