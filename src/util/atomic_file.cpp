#include "util/atomic_file.hpp"

#include <fmt/format.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "vantage/error.hpp"

namespace vantage::detail {
namespace fs = std::filesystem;

namespace {

void WriteFile(const fs::path& path, const std::string& content) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(content.data(), static_cast<std::streamsize>(content.size()));
  out.close();
  if (!out) throw InputError(fmt::format("{}: cannot write — check the folder exists and is writable",
                                         path.string()));
}

}  // namespace

void WriteFileAtomically(const std::string& path, const std::string& content) {
  const fs::path target(path);
  const fs::path temp = target.string() + fmt::format(".tmp-{}", ::getpid());
  WriteFile(temp, content);
  std::error_code ec;
  fs::rename(temp, target, ec);
  if (ec) {
    fs::remove(temp, ec);
    throw InputError(fmt::format("{}: cannot write ({}) — check the path", path, ec.message()));
  }
}

void WriteFolderAtomically(const std::string& dir, const std::map<std::string, std::string>& files) {
  fs::path target = fs::absolute(fs::path(dir)).lexically_normal();
  if (target.filename().empty()) target = target.parent_path();
  std::error_code ec;
  if (fs::exists(target, ec)) {
    if (!fs::is_directory(target, ec))
      throw InputError(fmt::format("{}: exists and is not a folder — choose another --out", dir));
    // Never replace a folder that vantage did not write: it may hold the user's files.
    if (!fs::is_empty(target, ec) && !fs::exists(target / "report.json", ec))
      throw InputError(fmt::format(
          "{}: is a non-empty folder without a report.json — choose an empty or new --out folder", dir));
  }
  if (target.has_parent_path()) fs::create_directories(target.parent_path(), ec);
  const fs::path temp = target.string() + fmt::format(".tmp-{}", ::getpid());
  const fs::path old = target.string() + fmt::format(".old-{}", ::getpid());
  fs::remove_all(temp, ec);
  fs::create_directories(temp, ec);
  if (ec) throw InputError(fmt::format("{}: cannot create ({}) — check the path", temp.string(), ec.message()));
  try {
    for (const auto& [name, content] : files) WriteFile(temp / name, content);
  } catch (...) {
    fs::remove_all(temp, ec);
    throw;
  }
  const bool had_old = fs::exists(target, ec);
  if (had_old) {
    fs::rename(target, old, ec);
    if (ec) {
      fs::remove_all(temp, ec);
      throw InputError(fmt::format("{}: cannot replace ({})", dir, ec.message()));
    }
  }
  fs::rename(temp, target, ec);
  if (ec) {
    const std::string why = ec.message();
    if (had_old) fs::rename(old, target, ec);
    fs::remove_all(temp, ec);
    throw InputError(fmt::format("{}: cannot write ({})", dir, why));
  }
  if (had_old) fs::remove_all(old, ec);
}

}  // namespace vantage::detail
