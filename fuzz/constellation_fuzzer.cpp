// libFuzzer target: the constellation reader (`vantage evaluate --constellation report.json`).
// InputError is the expected outcome for bad input; anything else crashes.
#include <cstddef>
#include <cstdint>

#include "fuzz_util.hpp"
#include "vantage/error.hpp"
#include "vantage/report.hpp"

extern "C" int LLVMFuzzerInitialize(int* /*argc*/, char*** /*argv*/) {
  return vantage::fuzz::Initialize();
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = vantage::fuzz::WriteInput("report.json", data, size);
  try {
    const vantage::Constellation constellation = vantage::LoadConstellation(path);
    // What `vantage evaluate` relies on: at least one sensor, each with a valid camera.
    VANTAGE_CHECK(!constellation.sensors.empty());
    for (const vantage::Candidate& c : constellation.sensors) {
      VANTAGE_CHECK(c.sensor.width >= 1 && c.sensor.height >= 1);
      VANTAGE_CHECK(c.world_from_body.position.allFinite());
    }
  } catch (const vantage::InputError&) {
    // rejected with a message: the expected outcome for bad input
  }
  return 0;
}
