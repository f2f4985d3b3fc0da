#pragma once
/// Writing outputs so that a failed or interrupted run never leaves a half-written file or folder.
/// SIGINT or SIGTERM during a write removes the temporary sibling, keeps the earlier output, and
/// then ends the process by that signal (see InterruptGuard in atomic_file.cpp).
#include <map>
#include <set>
#include <string>

namespace vantage::detail {

/// Writes `content` to `path` through a temporary sibling and a rename.
void WriteFileAtomically(const std::string& path, const std::string& content);

/// Writes every (name -> content) into a temporary sibling folder of `dir`, then replaces `dir`
/// with it (the old folder is removed only after the new one is complete). Of the old folder's
/// entries, those named in `files` or in `owned` (every name the caller ever writes there) are
/// replaced or dropped; every other entry is the user's and moves into the new folder unchanged.
void WriteFolderAtomically(const std::string& dir, const std::map<std::string, std::string>& files,
                           const std::set<std::string>& owned = {});

}  // namespace vantage::detail
