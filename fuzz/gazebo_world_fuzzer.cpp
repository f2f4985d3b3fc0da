// libFuzzer target: the Gazebo SDF world loader (GAZEBO.md). InputError is the expected outcome
// for bad input; anything else crashes. The world is written beside links to the test worlds'
// materials/ and models/, and those model folders are on the model path, so that the seed worlds
// of tests/data/worlds load as they do in the tests.
#include <cstddef>
#include <cstdint>

#include "fuzz_util.hpp"
#include "vantage/error.hpp"
#include "vantage/problem.hpp"

extern "C" int LLVMFuzzerInitialize(int* /*argc*/, char*** /*argv*/) {
  return vantage::fuzz::Initialize();
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = vantage::fuzz::WriteInput("input.world", data, size);
  vantage::LoadOptions options;
  options.model_paths = {vantage::fuzz::SourcePath("tests/data/worlds/models"),
                         vantage::fuzz::SourcePath("tests/data/worlds/bad/models")};
  options.resource_paths = {vantage::fuzz::SourcePath("tests/data/worlds")};
  try {
    const vantage::Problem problem = vantage::LoadGazeboWorld(path, options);
    for (const vantage::Population& p : problem.populations)
      VANTAGE_CHECK(problem.FindType(p.sensor_type));
    for (const vantage::ExplicitSensor& s : problem.sensors)
      VANTAGE_CHECK(problem.FindType(s.sensor_type));
    VANTAGE_CHECK(problem.cell_size > 0);
  } catch (const vantage::InputError&) {
    // rejected with a message: the expected outcome for bad input
  }
  return 0;
}
