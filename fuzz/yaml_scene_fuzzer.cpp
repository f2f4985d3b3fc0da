// libFuzzer target: vantage's YAML scene loader (docs/scene-format.md). An InputError is the
// loader rejecting bad input, as it should; anything else (another exception, a sanitizer report,
// a hang, an out-of-memory) is a bug.
#include <cstddef>
#include <cstdint>

#include "fuzz_util.hpp"
#include "vantage/error.hpp"
#include "vantage/problem.hpp"

extern "C" int LLVMFuzzerInitialize(int* /*argc*/, char*** /*argv*/) {
  return vantage::fuzz::Initialize();
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  // In scenes/, so that the examples' ../meshes/small_motor.obj resolves.
  const std::string path = vantage::fuzz::WriteInput("scenes/input.yaml", data, size);
  try {
    const vantage::Problem problem = vantage::LoadYamlScene(path);
    // A scene that loads must be usable: every population and sensor names a known type.
    for (const vantage::Population& p : problem.populations)
      VANTAGE_CHECK(problem.FindType(p.sensor_type));
    for (const vantage::ExplicitSensor& s : problem.sensors)
      VANTAGE_CHECK(problem.FindType(s.sensor_type));
    VANTAGE_CHECK(problem.cell_size > 0);
    VANTAGE_CHECK(problem.scene.TargetCount() > 0);
  } catch (const vantage::InputError&) {
    // rejected with a message: the expected outcome for bad input
  }
  return 0;
}
