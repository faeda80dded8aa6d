#include "run_inputs.h"

#include <pybind11/stl.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "octarc/core/DataFiles.h"
#include "octarc/run/RunKeys.h"
#include "octarc/sexcompat/Config.h"
#include "octarc/sexcompat/ConvFile.h"

namespace octarc::python {

std::string numberText(double value) {
  char text[40];
  std::snprintf(text, sizeof text, "%.17g", value);
  return text;
}

MeasurementPlan allColumnsPlan() {
  std::vector<ColumnRequest> requests;
  for (const ColumnSpec& spec : allBuiltinColumns()) requests.push_back({spec.name, spec.repeat});
  return MeasurementPlan::build(requests, {}, nullptr);
}

RunInputs::RunInputs(const py::array& data, const py::object& background, const py::object& error,
                     const py::object& weight, const py::object& mask, const py::object& kernel,
                     const std::vector<std::string>& headerCards, Keys keys,
                     const CallConfiguration& configuration) {
  data_ = floatViewOf(data, "data");
  // A map of the image's shape: pixel values, or (a mask) bools.
  auto map = [&](const py::object& object, const char* what, bool values = true) {
    keep_.push_back(py::array(object));
    const ArrayView view = values ? floatViewOf(keep_.back(), what) : viewOf(keep_.back(), what);
    requireSameShape(view, what, data_);
    return view;
  };
  if (!mask.is_none()) {
    mask_ = map(mask, "mask", false);
    if (mask_->type != ArrayView::Type::Bool) throw py::value_error("mask: dtype must be bool");
  }
  if (!background.is_none()) {
    if (py::isinstance<py::array>(background)) {
      background_ = map(background, "background");
    } else {
      keys.emplace_back("BACK_TYPE", "MANUAL");
      keys.emplace_back("BACK_VALUE", numberText(background.cast<double>()));
    }
  }
  if (!error.is_none()) {
    if (py::isinstance<py::array>(error)) {
      weights_ = map(error, "error");
      keys.emplace_back("WEIGHT_TYPE", "MAP_RMS");
    } else {
      sigmaAdu_ = error.cast<double>();
      if (!(std::isfinite(*sigmaAdu_) && *sigmaAdu_ > 0)) {
        throw py::value_error("error: the noise sigma must be a finite number > 0, not " +
                              numberText(*sigmaAdu_));
      }
    }
  }
  if (!weight.is_none()) {
    if (weights_) throw py::value_error("weight: give either an error map or weights, not both");
    weights_ = map(weight, "weight");
    keys.emplace_back("WEIGHT_TYPE", "MAP_WEIGHT");
  }
  if (kernel.is_none()) {
    if (!configuration.kernelFromConfig) keys.emplace_back("FILTER", "N");
  } else if (py::isinstance<py::str>(kernel)) {
    keys.emplace_back("FILTER", "Y");
    kernel_ = sexcompat::readConvFile(resolveFilterFile(kernel.cast<std::string>()));
  } else {
    keys.emplace_back("FILTER", "Y");
    kernel_ = kernelOf(py::array(kernel));
  }
  for (const std::string& card : headerCards) {
    if (card.size() != 80) {
      throw py::value_error("header: a card of " + std::to_string(card.size()) +
                            " characters; FITS cards have 80");
    }
  }
  header_.cards = headerCards;
  keys.emplace_back("VERBOSE_TYPE", "QUIET");
  config_ = sexcompat::Config::load(
      configuration.schema.empty() ? octarcKeys() : configuration.schema,
      configuration.sexFile.empty() ? std::string()
                                    : existingUserOrDataFile(configuration.sexFile, "config_file"),
      keys, &warnings_, {"config", ""});
  settings_ = settingsFromConfig(*config_, true);
  // The weight map is an array here (WEIGHT_IMAGE is not read): a configuration that asks for
  // one (a .sex file of the command's, say) is told where it goes rather than failing on an
  // empty file name.
  if (settings_.weightType != WeightType::None && !weights_) {
    throw py::value_error(
        "WEIGHT_TYPE: the configuration asks for a weight map; give it as "
        "weight= (or error= for MAP_RMS), or set WEIGHT_TYPE NONE");
  }
}

PreparedImage RunInputs::prepare(bool filterVariance, SignalCheck& signals) const {
  signals();
  ImageHdu hdu = imageHduOf(data_, "data", header_, mask_ ? &*mask_ : nullptr);
  const auto& pixels = hdu.pixels.pixels();
  if (!std::any_of(pixels.begin(), pixels.end(), [](float v) { return std::isfinite(v); })) {
    throw py::value_error(mask_ ? "data: no finite pixel outside the mask (all NaN, Inf or masked)"
                                : "data: no finite pixel (all NaN or Inf)");
  }
  ImageMaps maps;
  if (weights_) {
    const ArrayView weights = *weights_;
    maps.weights = [weights] { return imageOf(weights); };
  }
  if (background_) {
    const ArrayView background = *background_;
    maps.background = [background] { return imageOf(background); };
  }
  maps.filter = kernel_ ? &*kernel_ : nullptr;
  CatalogRunValues given;
  given.sigmaAdu = sigmaAdu_;
  PreparedImage image = runGuarded(
      [&] { return prepareImage(std::move(hdu), "data", settings_, maps, given, filterVariance); });
  signals();
  return image;
}

py::dict RunValues::asDict() const {
  py::dict out;
  out["background"] = backgroundAdu;
  out["background_origin"] = backgroundOrigin;
  out["sigma"] = sigmaAdu;
  out["sigma_origin"] = sigmaOrigin;
  out["weight_scale"] = weightScale;
  out["gain"] = gain;
  out["warnings"] = warnings;
  return out;
}

RunValues runValues(const PreparedImage& image, const RunInputs& inputs) {
  RunValues v;
  v.backgroundAdu = image.backgroundAdu;
  v.sigmaAdu = image.sigmaAdu;
  v.weightScale = image.weightScale;
  v.gain = image.gain;
  v.backgroundOrigin = image.origin.background;
  v.sigmaOrigin = image.origin.sigma;
  v.warnings = inputs.warnings();
  v.warnings.insert(v.warnings.end(), image.warnings.begin(), image.warnings.end());
  return v;
}

py::array ownedArray(std::unique_ptr<ImageI32> labels) {
  ImageI32* raw = labels.release();
  py::capsule owner(raw, [](void* p) { delete static_cast<ImageI32*>(p); });
  return py::array_t<std::int32_t>({raw->height(), raw->width()}, raw->data(), owner);
}

py::array ownedArray(std::unique_ptr<ImageF> pixels) {
  ImageF* raw = pixels.release();
  py::capsule owner(raw, [](void* p) { delete static_cast<ImageF*>(p); });
  return py::array_t<float>({raw->height(), raw->width()}, raw->data(), owner);
}

}  // namespace octarc::python
