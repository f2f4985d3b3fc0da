#include "util/atomic_file.hpp"

#include <fmt/format.h>
#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <array>
#include <atomic>
#include <cerrno>
#include <chrono>
#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <system_error>
#include <thread>
#include <vector>

#include "vantage/error.hpp"
#include "vantage/interrupt.hpp"

namespace vantage::detail {
namespace fs = std::filesystem;

namespace {

// SIGINT/SIGTERM while outputs are written (issue #8): the handler only records the signal; the
// writer checks it between files and before its renames, removes its temporary sibling, restores
// the previous action and raises the signal again, so the process still ends as killed by it
// (exit status 130 in a shell), leaves no `.tmp-PID` behind and the earlier output as it was. A
// signal during the final renames takes effect once they are done. Outside a write vantage keeps
// the default action: nothing half-written exists then.
std::atomic<int> g_pending_signal{0};
static_assert(std::atomic<int>::is_always_lock_free, "used in a signal handler");

extern "C" void RecordSignal(int signal) { g_pending_signal.store(signal); }

/// Installs RecordSignal for SIGINT and SIGTERM while alive, where their action is the default
/// (a program embedding vantage keeps its own handlers, and an ignored signal stays ignored).
class InterruptGuard {
 public:
  InterruptGuard() {
    std::lock_guard<std::mutex> lock(Mutex());
    if (Depth()++ > 0) return;
    g_pending_signal.store(0);
    const std::vector<int>& signals = Signals();
    previous_.resize(signals.size());
    installed_.assign(signals.size(), false);
    for (size_t i = 0; i < signals.size(); ++i) {
      struct sigaction action {};
      action.sa_handler = RecordSignal;
      sigemptyset(&action.sa_mask);
      installed_[i] = ::sigaction(signals[i], nullptr, &previous_[i]) == 0 &&
                      previous_[i].sa_handler == SIG_DFL && !(previous_[i].sa_flags & SA_SIGINFO) &&
                      ::sigaction(signals[i], &action, nullptr) == 0;
    }
  }
  ~InterruptGuard() {
    std::lock_guard<std::mutex> lock(Mutex());
    if (--Depth() > 0) return;
    for (size_t i = 0; i < installed_.size(); ++i)
      if (installed_[i]) ::sigaction(Signals()[i], &previous_[i], nullptr);
    // Restored the default action: a signal that came during the write ends the process now.
    if (const int signal = g_pending_signal.exchange(0)) ::raise(signal);
  }
  InterruptGuard(const InterruptGuard&) = delete;
  InterruptGuard& operator=(const InterruptGuard&) = delete;

  /// True once SIGINT or SIGTERM arrived during the write, or once the run was asked to stop
  /// (vantage/interrupt.hpp: the CLI's handler, which then stands in for this one).
  static bool Interrupted() { return g_pending_signal.load() != 0 || InterruptRequested(); }

 private:
  // Every asynchronous signal whose default action ends the process: what a user, a shell, a
  // scheduler or a resource limit sends (issue 15: SIGHUP, SIGALRM and SIGUSR1 left
  // `OUT.tmp-PID` behind, then SIGQUIT, SIGXCPU, SIGXFSZ, SIGVTALRM and SIGPROF). Not the faults
  // (SIGSEGV, SIGBUS, SIGFPE, SIGILL, SIGABRT, SIGTRAP, SIGSYS): those are crashes.
  // The real-time signals (SIGRTMIN..SIGRTMAX) and SIGSTKFLT end the process too (issue 15:
  // they left it behind as well); SIGRTMIN is a function call in glibc, so the list is built once.
  static const std::vector<int>& Signals() {
    static const std::vector<int> signals = [] {
      std::vector<int> list = {SIGINT,  SIGTERM, SIGHUP,  SIGQUIT,   SIGALRM, SIGUSR1, SIGUSR2,
                               SIGPIPE, SIGXCPU, SIGXFSZ, SIGVTALRM, SIGPROF, SIGIO,   SIGPWR};
#ifdef SIGSTKFLT
      list.push_back(SIGSTKFLT);
#endif
      for (int signal = SIGRTMIN; signal <= SIGRTMAX; ++signal) list.push_back(signal);
      return list;
    }();
    return signals;
  }
  static std::mutex& Mutex() {
    static std::mutex mutex;
    return mutex;
  }
  static int& Depth() {
    static int depth = 0;
    return depth;
  }
  std::vector<struct sigaction> previous_;
  std::vector<bool> installed_;
};

// Test hook: VANTAGE_TEST_WRITE_DELAY_S seconds of sleep after each file of a folder is written,
// so that a test can interrupt a run while its temporary folder exists.
void TestWriteDelay() {
  static const double seconds = [] {
    const char* text = std::getenv("VANTAGE_TEST_WRITE_DELAY_S");
    return text ? std::atof(text) : 0.0;
  }();
  if (seconds > 0) std::this_thread::sleep_for(std::chrono::duration<double>(seconds));
}

/// An exclusive flock(2) on a folder while alive; none when the folder cannot be opened (the
/// renames then report their own errors).
class FolderLock {
 public:
  explicit FolderLock(const fs::path& folder)
      : fd_(::open(folder.empty() ? "." : folder.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC)) {
    if (fd_ >= 0)
      while (::flock(fd_, LOCK_EX) != 0 && errno == EINTR) {
      }
  }
  ~FolderLock() {
    if (fd_ >= 0) ::close(fd_);  // closing releases the lock
  }
  FolderLock(const FolderLock&) = delete;
  FolderLock& operator=(const FolderLock&) = delete;

 private:
  int fd_;
};

// The folder an output goes into, checked before any work (session 10's sweep: a parent that is
// a file, or missing, was found only at the write, after the ray casting, and the message named
// the temporary). `may_create`: the missing folders are made at the write (--out folders).
void CheckParentFolder(const std::string& path, bool may_create) {
  fs::path folder = AbsolutePath(path).lexically_normal().parent_path();
  std::error_code ec;
  fs::path existing = folder;
  while (!fs::exists(existing, ec) && existing.has_relative_path()) existing = existing.parent_path();
  if (!fs::is_directory(existing, ec))
    throw InputError(fmt::format("{}: '{}' is a file, not a folder — choose another path", path,
                                 existing.string()));
  if (existing != folder && !may_create)
    throw InputError(fmt::format("{}: its folder '{}' does not exist — create it first", path,
                                 folder.string()));
  if (::access(existing.c_str(), W_OK | X_OK) != 0)
    throw InputError(fmt::format("{}: the folder '{}' is not writable ({}) — choose another path",
                                 path, existing.string(), std::generic_category().message(errno)));
}

/// A suffix no other write of this process or another one uses at the same time: ".tmp-PID-N"
/// (N counts the calls of this process). Two threads writing one path each have their own
/// temporary (issue 44: both used ".tmp-PID", and one failed or the folder mixed both runs).
std::string UniqueSuffix(std::string_view kind) {
  static std::atomic<unsigned long long> calls{0};
  return fmt::format(".{}-{}-{}", kind, ::getpid(), calls.fetch_add(1) + 1);
}

void WriteFile(const fs::path& path, const std::string& content) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(content.data(), static_cast<std::streamsize>(content.size()));
  out.close();
  if (!out) throw InputError(fmt::format("{}: cannot write — check the folder exists and is writable",
                                         path.string()));
}

}  // namespace

std::filesystem::path AbsolutePath(const std::string& path) {
  std::error_code ec;
  fs::path absolute = fs::absolute(path, ec);
  if (ec)
    throw InputError(fmt::format("{}: a relative path, and the working folder no longer exists "
                                 "({}) — give an absolute path, or run from an existing folder",
                                 path, ec.message()));
  return absolute;
}

void CheckOutputFile(const std::string& path) {
  // The CLI refuses an empty --out first; the library's other callers (Python) meet it here (was
  // std::filesystem's "cannot make absolute path").
  if (path.empty()) throw InputError("the output path is empty — give the file to write");
  const fs::path target(path);
  // The rename would replace a device or a pipe with a plain file (issue 15: `observe --out
  // /dev/null` as root replaced the machine's /dev/null). A symbolic link to a file is replaced
  // by the new file, as any editor saving through a temporary does.
  std::error_code status_error;
  const fs::file_status status = fs::symlink_status(target, status_error);
  if (fs::exists(status) && !fs::is_regular_file(status) && !fs::is_symlink(status) &&
      !fs::is_directory(status))
    throw InputError(fmt::format(
        "{}: exists and is not a regular file (a device, a pipe or a socket) — choose another path",
        path));
  if (fs::is_symlink(status) && fs::exists(target, status_error) &&
      !fs::is_regular_file(target, status_error) && !fs::is_directory(target, status_error))
    throw InputError(fmt::format(
        "{}: links to something that is not a regular file (a device, a pipe or a socket) — "
        "choose another path",
        path));
  if (fs::is_directory(target, status_error))
    throw InputError(fmt::format("{}: is a folder — give the path of a file", path));
  CheckParentFolder(path, false);
}

void WriteFileAtomically(const std::string& path, const std::string& content) {
  const fs::path target(path);
  CheckOutputFile(path);
  const fs::path temp = target.string() + UniqueSuffix("tmp");
  const InterruptGuard guard;
  std::error_code ec;
  try {
    WriteFile(temp, content);
  } catch (const InputError&) {
    const int reason = errno;  // read before the cleanup's calls change it
    fs::remove(temp, ec);
    // The path the user gave, not the temporary's.
    throw InputError(fmt::format("{}: cannot write ({}) — check that its folder exists and is "
                                 "writable, and that the disk is not full",
                                 path, std::generic_category().message(reason)));
  } catch (...) {
    fs::remove(temp, ec);
    throw;
  }
  if (InterruptGuard::Interrupted()) {
    fs::remove(temp, ec);
    ThrowIfInterrupted();  // a run that handles its own interrupts is told so
    return;                // ~InterruptGuard raises the signal
  }
  fs::rename(temp, target, ec);
  if (ec) {
    // The reason first: the cleanup's own error code would say "Success" (issue 15).
    const std::string why = fs::is_directory(target) ? "it is a folder" : ec.message();
    fs::remove(temp, ec);
    throw InputError(fmt::format("{}: cannot write ({}) — check the path", path, why));
  }
}

std::filesystem::path CheckOutputFolder(const std::string& dir) {
  fs::path target = AbsolutePath(dir).lexically_normal();
  if (target.filename().empty()) target = target.parent_path();
  CheckParentFolder(target.string(), true);
  std::error_code ec;
  // A link to a folder stays a link: the folder it names is the one replaced (session 9: the
  // link was replaced by a real folder, and the folder it named kept the old outputs).
  if (fs::is_symlink(fs::symlink_status(target, ec))) {
    if (!fs::exists(target, ec))
      throw InputError(fmt::format("{}: is a link to '{}', which does not exist — create that "
                                   "folder, or choose another --out",
                                   dir, fs::read_symlink(target, ec).string()));
    target = fs::canonical(target, ec);
    if (ec) throw InputError(fmt::format("{}: cannot follow the link ({})", dir, ec.message()));
  }
  if (fs::exists(target, ec)) {
    if (!fs::is_directory(target, ec))
      throw InputError(fmt::format("{}: exists and is not a folder — choose another --out", dir));
    // Never replace a folder that vantage did not write: it may hold the user's files.
    if (!fs::is_empty(target, ec) && !fs::exists(target / "report.json", ec))
      throw InputError(fmt::format(
          "{}: is a non-empty folder without a report.json — choose an empty or new --out folder", dir));
  }
  return target;
}

void WriteFolderAtomically(const std::string& dir, const std::map<std::string, std::string>& files,
                           const std::set<std::string>& owned) {
  const fs::path target = CheckOutputFolder(dir);
  std::error_code ec;
  if (target.has_parent_path()) fs::create_directories(target.parent_path(), ec);
  const fs::path temp = target.string() + UniqueSuffix("tmp");
  const fs::path old = target.string() + UniqueSuffix("old");
  const InterruptGuard guard;
  fs::remove_all(temp, ec);
  fs::create_directories(temp, ec);
  if (ec) throw InputError(fmt::format("{}: cannot create ({}) — check the path", dir, ec.message()));
  try {
    for (const auto& [name, content] : files) {
      if (InterruptGuard::Interrupted()) break;
      WriteFile(temp / name, content);
      TestWriteDelay();
    }
  } catch (...) {
    fs::remove_all(temp, ec);
    throw;
  }
  if (InterruptGuard::Interrupted()) {
    fs::remove_all(temp, ec);
    ThrowIfInterrupted();  // a run that handles its own interrupts is told so
    return;  // ~InterruptGuard raises the signal; the earlier outputs stay as they were
  }
  // From here on the renames complete (a few system calls) before the signal is acted on.
  // Two runs writing the same folder take turns (issue 15: one of them failed when the other
  // had just moved the old folder away); the lock is the parent folder's, so no file is left.
  const FolderLock lock(target.parent_path());
  const bool had_old = fs::exists(target, ec);
  std::vector<fs::path> kept;  // the user's entries, moved from the old folder into the new one
  const auto restore_kept = [&] {
    for (const fs::path& name : kept) fs::rename(temp / name, target / name, ec);
  };
  if (had_old) {
    std::vector<fs::path> users;  // listed first: the loop below changes the folder
    for (const fs::directory_entry& entry : fs::directory_iterator(target, ec)) {
      const std::string name = entry.path().filename().string();
      if (!files.count(name) && !owned.count(name)) users.push_back(name);
    }
    for (const fs::path& name : users) {
      fs::rename(target / name, temp / name, ec);
      if (ec) {
        const std::string why = ec.message();
        restore_kept();
        fs::remove_all(temp, ec);
        throw InputError(fmt::format("{}: cannot keep {} ({})", dir, name.string(), why));
      }
      kept.push_back(name);
    }
    fs::rename(target, old, ec);
    if (ec) {
      const std::string why = ec.message();
      restore_kept();
      fs::remove_all(temp, ec);
      throw InputError(fmt::format("{}: cannot replace ({})", dir, why));
    }
  }
  fs::rename(temp, target, ec);
  if (ec) {
    const std::string why = ec.message();
    if (had_old) {
      fs::rename(old, target, ec);
      restore_kept();
    }
    fs::remove_all(temp, ec);
    throw InputError(fmt::format("{}: cannot write ({})", dir, why));
  }
  if (had_old) fs::remove_all(old, ec);
}

}  // namespace vantage::detail
