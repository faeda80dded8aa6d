// Population parameter files of the lens simulations (params/simulation/population.txt).
#include <cstddef>
#include <cstdint>
#include <string>

#include "FuzzInput.h"
#include "octarc/core/Error.h"
#include "octarc/simulation/Population.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = octarc::fuzz::writeInput(data, size, "population.txt");
  try {
    const octarc::simulation::PopulationModel model = octarc::simulation::readPopulationModel(path);
    model.lensKCorrectionMag(0.3);  // the interpolation table the file defines
  } catch (const octarc::Error&) {
  }
  return 0;
}
