#include "test_util.hpp"

#include <sys/wait.h>

#include <array>
#include <atomic>
#include <cmath>
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

std::string SceneDifference(const Scene& a, const Scene& b) {
  if (a.objects.size() != b.objects.size())
    return std::to_string(a.objects.size()) + " objects vs " + std::to_string(b.objects.size());
  for (size_t i = 0; i < a.objects.size(); ++i) {
    const SceneObject& x = a.objects[i];
    const SceneObject& y = b.objects[i];
    const std::string which = "object " + std::to_string(i) + " (" + x.name + "): ";
    if (x.name != y.name) return which + "named " + y.name + " in the other";
    if (x.role != y.role) return which + "another role";
    if (x.mesh.vertices.size() != y.mesh.vertices.size() ||
        x.mesh.triangles.size() != y.mesh.triangles.size()) {
      return which + std::to_string(x.mesh.vertices.size()) + " vertices, " +
             std::to_string(x.mesh.triangles.size()) + " triangles vs " +
             std::to_string(y.mesh.vertices.size()) + ", " +
             std::to_string(y.mesh.triangles.size());
    }
    for (size_t v = 0; v < x.mesh.vertices.size(); ++v)
      if (x.mesh.vertices[v] != y.mesh.vertices[v]) return which + "vertex " + std::to_string(v);
    for (size_t t = 0; t < x.mesh.triangles.size(); ++t)
      if (x.mesh.triangles[t] != y.mesh.triangles[t])
        return which + "triangle " + std::to_string(t);
  }
  return "";
}

int RimVertices(const TriangleMesh& mesh, double z, double radius) {
  int rim = 0;
  for (const Vec3& v : mesh.vertices) {
    if (std::abs(v.z() - z) < 1e-12 && std::abs(v.head<2>().norm() - radius) < 1e-12) ++rim;
  }
  return rim;
}

}  // namespace vantage::test
