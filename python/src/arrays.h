// numpy arrays in, octarc images out: what every binding file shares. An array is looked at
// once, with the GIL held (ArrayView); its pixels are then read with the GIL released.
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <cstdint>
#include <string>
#include <vector>

#include "octarc/core/ConvKernel.h"
#include "octarc/core/Image.h"
#include "octarc/io/FitsHeader.h"
#include "octarc/io/FitsImage.h"

namespace octarc::python {

namespace py = pybind11;

// A 2-D C-contiguous array of float32, float64 or bool (masks), borrowed: the caller keeps the
// array alive while the view is used.
struct ArrayView {
  enum class Type { Float32, Float64, Bool };
  const void* data = nullptr;
  Type type = Type::Float32;
  std::int64_t width = 0;   // columns (NAXIS1)
  std::int64_t height = 0;  // rows (NAXIS2)
};

// The view of `array`, named `what` in messages; ValueError unless it is 2-D, C-contiguous and
// of one of the types above (the Python package converts other arrays once before calling).
ArrayView viewOf(const py::array& array, const std::string& what);

// viewOf for pixel values: ValueError for a bool array too.
ArrayView floatViewOf(const py::array& array, const std::string& what);

// ValueError naming both arrays (`image` as `imageName`) when `view` is not width x height.
void requireSameShape(const ArrayView& view, const std::string& what, const ArrayView& image,
                      const std::string& imageName = "data");

// The pixels of `view` as octarc's float image (the one copy octarc works on: float32 values
// copied as they are, float64 values rounded to float32 as cfitsio rounds a BITPIX -64 image),
// with the pixels where `mask` is true set to NaN (blank). No GIL needed.
ImageF imageOf(const ArrayView& view, const ArrayView* mask = nullptr);

// A header of FITS cards, each of 80 characters (ValueError otherwise).
FitsHeader headerOf(const std::vector<std::string>& cards);

// The pixels of `view` (imageOf, with `mask`) as the image HDU of a file named `what`, with
// `header`: what octarc reads an image file into.
ImageHdu imageHduOf(const ArrayView& view, const std::string& what, const FitsHeader& header,
                    const ArrayView* mask = nullptr);

// A convolution kernel from a 2-D array, normalised as a .conv file with NORM is (the
// coefficients over the sum of their absolute values); ValueError for an even side, or
// coefficients all zero or not finite.
ConvKernel kernelOf(const py::array& array);

// An exception thrown from a checkpoint when Python has a pending signal (Ctrl-C): the Python
// error is set; the binding raises it once the GIL is back.
struct PythonSignal {};

// A checkpoint for the library (run/ImageRun.h): at most every 0.1 s it takes the GIL and lets
// Python run its signal handlers; throws PythonSignal when one raised (KeyboardInterrupt).
class SignalCheck {
 public:
  void operator()();

 private:
  double lastSec_ = 0.0;
};

}  // namespace octarc::python
