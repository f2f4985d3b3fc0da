#pragma once
/// Writing outputs so that a failed or interrupted run never leaves a half-written file or folder.
/// SIGINT or SIGTERM during a write removes the temporary sibling, keeps the earlier output, and
/// then ends the process by that signal (see InterruptGuard in atomic_file.cpp).
#include <filesystem>
#include <map>
#include <set>
#include <string>

namespace vantage::detail {

/// `path` made absolute against the working folder. Throws InputError naming `path` when it is
/// relative and the working folder no longer exists (was std::filesystem's "cannot make absolute
/// path", an exit 1): that is the user's to fix, by an absolute path or another folder.
std::filesystem::path AbsolutePath(const std::string& path);

/// Throws InputError when WriteFileAtomically(path, ...) would refuse `path`: a device, a pipe
/// or a socket, or a link to one. Commands call it before any work, so the refusal costs nothing.
void CheckOutputFile(const std::string& path);

/// Throws InputError when WriteFolderAtomically(dir, ...) would refuse `dir`: a file, a folder
/// of the user's without a report.json, a link to nothing. Returns the folder to replace (a link
/// to a folder resolved to that folder). Commands call it before any work.
std::filesystem::path CheckOutputFolder(const std::string& dir);

/// Writes `content` to `path` through a temporary sibling and a rename.
void WriteFileAtomically(const std::string& path, const std::string& content);

/// Writes every (name -> content) into a temporary sibling folder of `dir`, then replaces `dir`
/// with it (the old folder is removed only after the new one is complete). Of the old folder's
/// entries, those named in `files` or in `owned` (every name the caller ever writes there) are
/// replaced or dropped; every other entry is the user's and moves into the new folder unchanged.
void WriteFolderAtomically(const std::string& dir, const std::map<std::string, std::string>& files,
                           const std::set<std::string>& owned = {});

}  // namespace vantage::detail
