// libFuzzer target: the visibility-matrix reader (`vantage observe` writes, `vantage select`
// reads). InputError is the expected outcome; anything else crashes. Random bytes almost never
// carry a valid FNV-1a checksum, so each input is also tried with its last 8 bytes replaced by
// the checksum of the rest: that reaches the payload parser.
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string>
#include <string_view>

#include "fuzz_util.hpp"
#include "util/binary_io.hpp"
#include "vantage/error.hpp"
#include "vantage/observe.hpp"
#include "vantage/visibility_file.hpp"

namespace {

void Load(const std::string& path) {
  try {
    const vantage::VisibilityFile file = vantage::LoadVisibilityFile(path);
    // What `vantage select` relies on once the file is accepted.
    VANTAGE_CHECK(file.observations.size() == file.candidates.size());
    VANTAGE_CHECK(file.reference.cell_size > 0);
    for (const vantage::Observation& o : file.observations) {
      for (uint32_t index : o.reference_indices) VANTAGE_CHECK(index < file.reference.keys.size());
    }
  } catch (const vantage::InputError&) {
    // rejected with a message: the expected outcome for bad input
  }
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int* /*argc*/, char*** /*argv*/) {
  return vantage::fuzz::Initialize();
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  Load(vantage::fuzz::WriteInput("input.vis", data, size));
  if (size >= 8) {
    std::string fixed(reinterpret_cast<const char*>(data), size);
    const uint64_t checksum =
        vantage::detail::Fnv1a64(std::string_view(fixed.data(), fixed.size() - 8));
    std::memcpy(fixed.data() + fixed.size() - 8, &checksum, 8);
    Load(vantage::fuzz::WriteInput("fixed.vis", reinterpret_cast<const uint8_t*>(fixed.data()),
                                   fixed.size()));
  }
  return 0;
}
