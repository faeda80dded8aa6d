#include "arrays.h"

#include <chrono>
#include <cmath>
#include <limits>

namespace octarc::python {

namespace {

std::string shapeText(std::int64_t width, std::int64_t height) {
  return "(" + std::to_string(height) + ", " + std::to_string(width) + ")";
}

}  // namespace

ArrayView viewOf(const py::array& array, const std::string& what) {
  if (array.ndim() != 2) {
    throw py::value_error(what + ": a 2-D array is needed, not one of " +
                          std::to_string(array.ndim()) + " dimension(s)");
  }
  if (!(array.flags() & py::array::c_style)) {
    throw py::value_error(what + ": the array is not C-contiguous");
  }
  ArrayView view;
  // numpy's type equivalence: a byte-swapped float32 is not float32.
  if (py::isinstance<py::array_t<float>>(array)) {
    view.type = ArrayView::Type::Float32;
  } else if (py::isinstance<py::array_t<double>>(array)) {
    view.type = ArrayView::Type::Float64;
  } else if (py::isinstance<py::array_t<bool>>(array)) {
    view.type = ArrayView::Type::Bool;
  } else {
    const py::dtype dtype = array.dtype();
    throw py::value_error(what + ": dtype " + py::cast<std::string>(py::str(py::object(dtype))) +
                          " is not float32, float64 or bool");
  }
  view.data = array.data();
  view.height = array.shape(0);
  view.width = array.shape(1);
  if (view.width < 1 || view.height < 1) {
    throw py::value_error(what + ": the array is empty (shape " +
                          shapeText(view.width, view.height) + ")");
  }
  if (view.width > kMaxImageSidePix || view.height > kMaxImageSidePix) {
    throw py::value_error(what + ": a side of more than " + std::to_string(kMaxImageSidePix) +
                          " pixels");
  }
  return view;
}

ArrayView floatViewOf(const py::array& array, const std::string& what) {
  const ArrayView view = viewOf(array, what);
  if (view.type == ArrayView::Type::Bool) {
    throw py::value_error(what + ": dtype bool is not float32 or float64");
  }
  return view;
}

FitsHeader headerOf(const std::vector<std::string>& cards) {
  for (const std::string& card : cards) {
    if (card.size() != 80) {
      throw py::value_error("header: a card of " + std::to_string(card.size()) +
                            " characters; FITS cards have 80");
    }
  }
  FitsHeader header;
  header.cards = cards;
  return header;
}

ImageHdu imageHduOf(const ArrayView& view, const std::string& what, const FitsHeader& header,
                    const ArrayView* mask) {
  ImageHdu hdu;
  hdu.path = what;
  hdu.header = header;
  hdu.bitpix = -32;
  hdu.pixels = imageOf(view, mask);
  hdu.widthPix = view.width;
  hdu.heightPix = view.height;
  return hdu;
}

void requireSameShape(const ArrayView& view, const std::string& what, const ArrayView& image,
                      const std::string& imageName) {
  if (view.width != image.width || view.height != image.height) {
    throw py::value_error(what + ": shape " + shapeText(view.width, view.height) + " but " +
                          imageName + " has shape " + shapeText(image.width, image.height));
  }
}

ImageF imageOf(const ArrayView& view, const ArrayView* mask) {
  ImageF image(view.width, view.height, UninitializedPixels{});
  float* out = image.data();
  const std::int64_t n = image.size();
  switch (view.type) {
    case ArrayView::Type::Float32: {
      const float* in = static_cast<const float*>(view.data);
      std::copy(in, in + n, out);
      break;
    }
    case ArrayView::Type::Float64: {
      const double* in = static_cast<const double*>(view.data);
      for (std::int64_t i = 0; i < n; ++i) out[i] = float(in[i]);
      break;
    }
    case ArrayView::Type::Bool: {
      const bool* in = static_cast<const bool*>(view.data);
      for (std::int64_t i = 0; i < n; ++i) out[i] = in[i] ? 1.0f : 0.0f;
      break;
    }
  }
  if (mask) {
    const bool* masked = static_cast<const bool*>(mask->data);
    constexpr float blank = std::numeric_limits<float>::quiet_NaN();
    for (std::int64_t i = 0; i < n; ++i) {
      if (masked[i]) out[i] = blank;
    }
  }
  return image;
}

ConvKernel kernelOf(const py::array& array) {
  const py::array_t<double, py::array::c_style | py::array::forcecast> values(array);
  if (values.ndim() != 2) {
    throw py::value_error("kernel: a 2-D array is needed, not one of " +
                          std::to_string(values.ndim()) + " dimension(s)");
  }
  ConvKernel kernel;
  kernel.height = int(values.shape(0));
  kernel.width = int(values.shape(1));
  if (kernel.width % 2 == 0 || kernel.height % 2 == 0) {
    throw py::value_error("kernel: shape (" + std::to_string(kernel.height) + ", " +
                          std::to_string(kernel.width) + ") has an even side; odd sides only");
  }
  // As a .conv file with NORM: the coefficients as float, divided by the sum of their
  // absolute values.
  const double* in = values.data();
  double sumAbs = 0.0;
  for (py::ssize_t i = 0; i < values.size(); ++i) sumAbs += std::fabs(double(float(in[i])));
  if (!(std::isfinite(sumAbs) && sumAbs > 0.0)) {
    throw py::value_error("kernel: every coefficient is zero, or one is not finite");
  }
  for (py::ssize_t i = 0; i < values.size(); ++i) {
    kernel.coefficients.push_back(float(double(float(in[i])) / sumAbs));
  }
  return kernel;
}

void SignalCheck::operator()() {
  const double nowSec =
      std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
  if (nowSec - lastSec_ < 0.1) return;
  lastSec_ = nowSec;
  py::gil_scoped_acquire gil;
  if (PyErr_CheckSignals() != 0) throw PythonSignal();
}

}  // namespace octarc::python
