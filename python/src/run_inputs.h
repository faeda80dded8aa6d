// What octarc.detect and octarc.measure share: the arrays and options of a call turned into
// octarc's run settings and prepared image, the run's values, and arrays handed back to Python.
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "arrays.h"
#include "octarc/core/ConvKernel.h"
#include "octarc/core/Error.h"
#include "octarc/io/FitsHeader.h"
#include "octarc/measure/Registry.h"
#include "octarc/run/PreparedImage.h"
#include "octarc/run/RunSettings.h"
#include "octarc/sexcompat/Config.h"

namespace octarc::python {

namespace py = pybind11;

// Configuration keys as a command line gives them: (KEY, value).
using Keys = std::vector<std::pair<std::string, std::string>>;

// A number as a configuration value that reads back as the same double ("%.17g").
std::string numberText(double value);

// The plan measuring every built-in column (`octarc detect -dp`), in registration order.
MeasurementPlan allColumnsPlan();

// The image and maps of one call, looked at with the GIL held, prepared without it.
//   data        the image (2-D float32/float64, C-contiguous)
//   background  None (BACK_TYPE AUTO, or as `keys` say), a number (BACK_TYPE MANUAL), or a map
//   error       None, a number (the noise sigma, ADU), or a map of per-pixel RMS (MAP_RMS)
//   weight      None or a map of relative weights (MAP_WEIGHT)
//   mask        None or a bool map: true pixels are blank (NaN) for octarc
//   kernel      None (FILTER N), a .conv file name (FILTER_NAME) or a 2-D array
//   headerCards the image's FITS header cards (GAIN, SATURATE, the WCS), 80 characters each
//   keys        octarc's configuration keys on top of their defaults
// ValueError for an array of the wrong shape or type, or both `error` as a map and `weight`;
// OSError for a kernel file that cannot be read; ValueError naming the key for a bad key.
// `configuration` is the command whose keys the call takes (detect's by default, or the
// search's) and the .sex file read before `keys` (none by default); with kernelFromConfig a
// kernel of None leaves FILTER and FILTER_NAME to the configuration, as the command does.
struct CallConfiguration {
  std::vector<sexcompat::KeySpec> schema;  // empty: octarc detect's keys
  std::string sexFile;
  bool kernelFromConfig = false;
};
class RunInputs {
 public:
  RunInputs(const py::array& data, const py::object& background, const py::object& error,
            const py::object& weight, const py::object& mask, const py::object& kernel,
            const std::vector<std::string>& headerCards, Keys keys,
            const CallConfiguration& configuration = {});

  const RunSettings& settings() const { return settings_; }
  // The loaded configuration (its keys at their defaults, the .sex file's, then the call's).
  const sexcompat::Config& config() const { return *config_; }
  // Its warnings (an unknown key of the .sex file, a key octarc ignores), as the command prints
  // them.
  const std::vector<std::string>& warnings() const { return warnings_; }
  const ArrayView& data() const { return data_; }
  // The prepared image (run/PreparedImage.h's prepareImage, the arrays standing in for the
  // files); call without the GIL. ValueError for an image without a finite pixel.
  PreparedImage prepare(bool filterVariance, SignalCheck& signals) const;

 private:
  ArrayView data_;
  std::vector<py::array> keep_;  // the maps' arrays, alive as long as their views
  std::optional<ArrayView> mask_, weights_, background_;
  std::optional<double> sigmaAdu_;
  std::optional<ConvKernel> kernel_;
  FitsHeader header_;
  std::optional<sexcompat::Config> config_;
  std::vector<std::string> warnings_;
  RunSettings settings_;
};

// The run's background and noise, as octarc's catalog header gives them.
struct RunValues {
  double backgroundAdu = 0.0, sigmaAdu = 0.0, weightScale = 1.0, gain = 0.0;
  std::string backgroundOrigin, sigmaOrigin;
  std::vector<std::string> warnings;
  py::dict asDict() const;
};
// The values of `image`, the warnings of the call's configuration first.
RunValues runValues(const PreparedImage& image, const RunInputs& inputs);

// Calls `work` (without the GIL): octarc's errors about the arrays (IoError) become
// ValueError, as no file is involved; PythonSignal passes through.
template <typename Work>
auto runGuarded(Work work) -> decltype(work()) {
  try {
    return work();
  } catch (const IoError& e) {
    throw py::value_error(e.what());
  }
}

// A numpy int32 array that takes over `labels` (no copy).
py::array ownedArray(std::unique_ptr<ImageI32> labels);
// A numpy float32 array that takes over `pixels` (no copy).
py::array ownedArray(std::unique_ptr<ImageF> pixels);

}  // namespace octarc::python
