#include "test_util.hpp"

#include <sys/wait.h>

#include <array>
#include <atomic>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <stdexcept>
#include <unistd.h>

namespace vantage::test {
namespace fs = std::filesystem;

TempDir::TempDir() {
  static std::atomic<int> counter{0};
  const fs::path base = fs::temp_directory_path() /
                        ("vantage_test_" + std::to_string(::getpid()) + "_" +
                         std::to_string(counter++));
  fs::remove_all(base);
  fs::create_directories(base);
  path_ = base.string();
}

TempDir::~TempDir() {
  std::error_code ec;
  fs::remove_all(path_, ec);
}

std::string TempDir::File(const std::string& name) const { return path_ + "/" + name; }

void WriteText(const std::string& path, const std::string& text) {
  const fs::path p(path);
  if (p.has_parent_path()) fs::create_directories(p.parent_path());
  std::ofstream out(path, std::ios::binary);
  out << text;
}

std::string ReadText(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

CommandResult RunVantage(const std::string& args) {
  TempDir dir;
  const std::string out_file = dir.File("stdout");
  const std::string err_file = dir.File("stderr");
  const std::string command =
      std::string(VANTAGE_BINARY) + " " + args + " >" + out_file + " 2>" + err_file + " </dev/null";
  const int status = std::system(command.c_str());
  CommandResult result;
  result.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  result.out = ReadText(out_file);
  result.err = ReadText(err_file);
  return result;
}

std::string DataPath(const std::string& name) { return std::string(VANTAGE_TEST_DATA) + "/" + name; }

std::string Costa2017Dir() {
  return fs::weakly_canonical(fs::path(VANTAGE_SHARED_DIR) / "worlds" / "costa2017").string();
}

}  // namespace vantage::test
