// What must be the same in every process of one result (docs/distributed.md): the build and the
// settings; the scene's content is compared as traced (RayScene::GeometryFingerprint).
#include <dlfcn.h>
#include <elf.h>
#include <fmt/format.h>
#include <link.h>

#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <map>

#include "vantage/distribute.hpp"
#include "vantage/report.hpp"

namespace vantage {
namespace {

struct BuildIdSearch {
  uintptr_t address = 0;  // an address inside vantage's code
  std::string id;         // hex, once found
};

// The GNU build id note of the loaded object that holds `address` (the executable, or the
// Python module's shared object): the linker's hash of its whole content.
int FindBuildId(dl_phdr_info* info, size_t, void* data) {
  auto* search = static_cast<BuildIdSearch*>(data);
  bool holds = false;
  for (int i = 0; i < info->dlpi_phnum; ++i) {
    const ElfW(Phdr)& segment = info->dlpi_phdr[i];
    const uintptr_t start = info->dlpi_addr + segment.p_vaddr;
    if (segment.p_type == PT_LOAD && search->address >= start &&
        search->address < start + segment.p_memsz)
      holds = true;
  }
  if (!holds) return 0;
  for (int i = 0; i < info->dlpi_phnum; ++i) {
    const ElfW(Phdr)& segment = info->dlpi_phdr[i];
    if (segment.p_type != PT_NOTE) continue;
    const char* at = reinterpret_cast<const char*>(info->dlpi_addr + segment.p_vaddr);
    const char* end = at + segment.p_memsz;
    while (at + sizeof(ElfW(Nhdr)) <= end) {
      ElfW(Nhdr) note;
      std::memcpy(&note, at, sizeof(note));
      const char* name = at + sizeof(note);
      const char* desc = name + ((note.n_namesz + 3) & ~3u);
      if (desc + note.n_descsz > end) break;
      if (note.n_type == NT_GNU_BUILD_ID && note.n_namesz == 4 && std::memcmp(name, "GNU", 4) == 0) {
        for (uint32_t k = 0; k < note.n_descsz; ++k)
          search->id += fmt::format("{:02x}", static_cast<unsigned char>(desc[k]));
        return 1;
      }
      at = desc + ((note.n_descsz + 3) & ~3u);
    }
  }
  return 1;  // the object holding vantage has no build id
}

}  // namespace

std::string BuildIdentity() {
  if (const char* test = std::getenv("VANTAGE_TEST_BUILD_ID")) return test;
  BuildIdSearch search;
  search.address = reinterpret_cast<uintptr_t>(&FindBuildId);
  dl_iterate_phdr(FindBuildId, &search);
  return search.id.empty() ? fmt::format("vantage {}", Version())
                           : fmt::format("vantage {} build {}", Version(), search.id);
}

std::string SettingsDifference(const RunSettings& a, const std::string& a_name,
                               const RunSettings& b, const std::string& b_name) {
  // A setting's name is its text up to the first space ("--seed 7": "--seed").
  const auto name_of = [](const std::string& setting) { return setting.substr(0, setting.find(' ')); };
  std::multimap<std::string, std::string> in_b;
  for (const std::string& setting : b) in_b.emplace(name_of(setting), setting);
  for (const std::string& setting : a) {
    const std::string name = name_of(setting);
    const auto [first, last] = in_b.equal_range(name);
    if (first == last) return fmt::format("{} has '{}', {} has not", a_name, setting, b_name);
    bool same = false;
    for (auto it = first; it != last && !same; ++it) same = it->second == setting;
    if (!same)
      return fmt::format("{} has '{}', {} has '{}'", a_name, setting, b_name, first->second);
  }
  std::multimap<std::string, std::string> in_a;
  for (const std::string& setting : a) in_a.emplace(name_of(setting), setting);
  for (const std::string& setting : b) {
    if (!in_a.count(name_of(setting)))
      return fmt::format("{} has '{}', {} has not", b_name, setting, a_name);
  }
  if (a != b)  // the same settings in another order: a repeated option's values
    return fmt::format("{} and {} list the values of an option in another order", a_name, b_name);
  return {};
}

}  // namespace vantage
