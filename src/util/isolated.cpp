#include "util/isolated.hpp"

#include <fmt/format.h>
#include <spdlog/spdlog.h>
#include <sys/mman.h>
#include <sys/prctl.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <stdexcept>

#include "vantage/error.hpp"
#include "vantage/interrupt.hpp"

namespace vantage::detail {
namespace {

// The child's answer: one kind byte, then the bytes of the result or of the message.
constexpr char kResult = 'R', kInputError = 'I', kOtherError = 'O';

void WriteAll(int fd, const std::string& bytes) {
  size_t done = 0;
  while (done < bytes.size()) {
    const ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return;  // the parent is gone: nothing to tell
    done += static_cast<size_t>(n);
  }
}

/// Everything `fd` holds until its end. With `child`: a stop request (Ctrl-C, SIGTERM) while
/// waiting kills the child, which may be stuck, and is thrown as Interrupted.
std::string ReadAll(int fd, pid_t child = 0) {
  std::string bytes;
  char buffer[1 << 16];
  for (;;) {
    const ssize_t n = ::read(fd, buffer, sizeof(buffer));
    if (n < 0 && errno == EINTR) {
      if (child > 0 && InterruptRequested()) {
        ::kill(child, SIGKILL);
        while (::waitpid(child, nullptr, 0) < 0 && errno == EINTR) {
        }
        ::close(fd);
        ThrowIfInterrupted();
      }
      continue;
    }
    if (n <= 0) return bytes;
    bytes.append(buffer, static_cast<size_t>(n));
  }
}

/// The last non-empty line the child printed on stderr (an assertion's words), at most 300 bytes.
std::string LastLine(int fd) {
  ::lseek(fd, 0, SEEK_SET);
  std::string text = ReadAll(fd);
  while (!text.empty() && (text.back() == '\n' || text.back() == '\r')) text.pop_back();
  const size_t start = text.find_last_of('\n');
  std::string line = start == std::string::npos ? text : text.substr(start + 1);
  if (line.size() > 300) line = line.substr(0, 300) + "…";
  return line;
}

}  // namespace

std::string RunIsolated(const std::function<std::string()>& work,
                        const std::string& who,
                        double cpu_seconds) {
  int pipe_fds[2];
  if (::pipe(pipe_fds) != 0) return work();
  // The child's stderr, kept for the message: a file in memory, read after it ended.
  const int stderr_fd = ::memfd_create("vantage_isolated_stderr", MFD_CLOEXEC);
  std::fflush(nullptr);  // nothing buffered is printed twice
  const pid_t pid = ::fork();
  if (pid < 0) {
    ::close(pipe_fds[0]);
    ::close(pipe_fds[1]);
    if (stderr_fd >= 0) ::close(stderr_fd);
    spdlog::debug("fork failed ({}): reading in this process", std::strerror(errno));
    return work();
  }
  if (pid == 0) {
    ::close(pipe_fds[0]);
    if (stderr_fd >= 0) ::dup2(stderr_fd, STDERR_FILENO);
    ::prctl(PR_SET_PDEATHSIG, SIGKILL);  // never outlive vantage
    // A fault ends the child by its signal, whoever handles it in vantage's process (the
    // sanitizers, libFuzzer, Python): their handlers would report it as vantage's own.
    for (const int fault : {SIGSEGV, SIGBUS, SIGFPE, SIGILL, SIGABRT}) std::signal(fault, SIG_DFL);
    // A reader that loops on a broken file (Assimp's PLY reader on a header without its end)
    // is stopped by SIGXCPU, then SIGKILL a second later.
    const auto limit = static_cast<rlim_t>(std::max(1.0, cpu_seconds));
    const struct rlimit cpu = {limit, limit + 1};
    ::setrlimit(RLIMIT_CPU, &cpu);
    std::string answer;
    try {
      answer = kResult + work();
    } catch (const InputError& e) {
      answer = std::string(1, kInputError) + e.what();
    } catch (const std::exception& e) {
      answer = std::string(1, kOtherError) + e.what();
    }
    WriteAll(pipe_fds[1], answer);
    ::_exit(0);  // no exit handlers: they belong to the parent (its temporary files, its logs)
  }
  ::close(pipe_fds[1]);
  std::string answer;
  try {
    answer = ReadAll(pipe_fds[0], pid);  // before waiting: a full pipe would block the child
  } catch (...) {
    if (stderr_fd >= 0) ::close(stderr_fd);
    throw;
  }
  ::close(pipe_fds[0]);
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  const std::string said = stderr_fd >= 0 ? LastLine(stderr_fd) : "";
  if (stderr_fd >= 0) ::close(stderr_fd);
  if (WIFEXITED(status) && WEXITSTATUS(status) == 0 && !answer.empty()) {
    const std::string rest = answer.substr(1);
    if (answer[0] == kResult) return rest;
    if (answer[0] == kInputError) throw InputError(rest);
    throw std::runtime_error(rest);
  }
  const bool out_of_time =
      WIFSIGNALED(status) && (WTERMSIG(status) == SIGXCPU || WTERMSIG(status) == SIGKILL);
  if (out_of_time)
    throw InputError(
        fmt::format("{} did not finish reading it within {:g} s of CPU time (a "
                    "reader looping on a broken file?)",
                    who, std::max(1.0, cpu_seconds)));
  const std::string how =
      WIFSIGNALED(status)
          ? fmt::format("signal {}: {}", WTERMSIG(status), ::strsignal(WTERMSIG(status)))
          : fmt::format("exit status {}", WIFEXITED(status) ? WEXITSTATUS(status) : -1);
  throw InputError(fmt::format("{} crashed on it, so the file is broken ({}{})", who, how,
                               said.empty() ? "" : fmt::format("; it said: {}", said)));
}

}  // namespace vantage::detail
