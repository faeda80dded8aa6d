// Reading and writing FITS images (cfitsio stays inside src/io).
//
// A path may carry cfitsio's extended syntax: "file.fits[2]", "file.fits[SCI]", "file.fits.fz".
// Pixel values are returned after BSCALE/BZERO, as float, whatever the BITPIX.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "octarc/core/Image.h"
#include "octarc/io/FitsHeader.h"

namespace octarc {

struct ImageHdu {
  std::string path;     // as given, e.g. "file.fits[1]"
  int hduIndex = 0;     // 0-based HDU number in the file (0 = primary)
  std::string extname;  // EXTNAME, or "" if none
  FitsHeader header;    // the image's own header (for .fz: the uncompressed image header)
  ImageF pixels;        // NaN where the file has blank/NaN pixels
  int bitpix = 0;       // BITPIX of the stored data (8, 16, 32, 64, -32, -64)
  // NAXIS1 and NAXIS2 as checked (of the uncompressed image for .fz), also when only the
  // header was read.
  std::int64_t widthPix = 0;
  std::int64_t heightPix = 0;
};

// The image HDUs of a file, in order, for SExtractor-like multi-extension processing: a plain
// file gives one entry (primary); a MEF gives one entry per non-empty image extension; a path
// that names an HDU ("f.fits[2]") gives that HDU only. Returns the path of each (e.g. "f.fits[2]").
// Throws IoError (naming the file) if the file is missing, not FITS, has no image, etc.
std::vector<std::string> listImageHdus(const std::string& path);

// Reads one image HDU (a path as returned by listImageHdus, or a plain file: its first
// non-empty image HDU). Throws IoError for a missing/unreadable/truncated file, a table HDU, a
// non-2-D image.
//
// Every reader here checks a file before it allocates anything from its header, and says
// which file, HDU and size is wrong (IoError): every HDU passed must have an XTENSION of
// IMAGE, BINTABLE or TABLE and data that fit in the file (|BITPIX|/8 * NAXIS1 * NAXIS2 ... may
// not overflow and must not exceed the bytes after the header; tile-compressed images are
// checked on their compressed table); a 2-D image needs NAXIS1, NAXIS2 >= 1 and a pixel count
// that memory can address. BSCALE and BZERO must be finite numbers, BSCALE not 0, and the
// BLANK of integer data an integer: otherwise the pixel values cannot be interpreted (IoError
// naming the keyword). BLANK of floating-point data has no meaning in FITS and is ignored.
ImageHdu readImage(const std::string& path);

// Reads only the header and size of an image HDU (no pixels), with the checks of readImage.
ImageHdu readImageHeader(const std::string& path);

// Reads an integer image exactly (for SExtractor segmentation maps), with the checks of
// readImage. Throws IoError if the HDU is not an integer image (BITPIX 8/16/32/64 with BSCALE 1
// and integer BZERO).
ImageI32 readIntImage(const std::string& path, FitsHeader* header = nullptr);

// One HDU of an output image file: the header cards to copy (WCS etc.; structural keywords
// SIMPLE/XTENSION/BITPIX/NAXISn/PCOUNT/GCOUNT/EXTEND/BSCALE/BZERO/END are replaced).
struct OutputImageHdu {
  FitsHeader header;
  const ImageF* floatPixels = nullptr;  // written as BITPIX -32
  const ImageI32* intPixels = nullptr;  // written as BITPIX 32
};

// Writes a 3-D float cube (NAXIS3 = number of planes, all of the same size) with the given
// header cards, at `path` itself, not atomically: pass the temporary path of an AtomicFile that
// the caller commits (so that several files can be committed together).
void writeImageCube(const std::string& path, const std::vector<const ImageF*>& planes,
                    const FitsHeader& header);

// Writes a FITS file atomically (temporary file + rename). One HDU: a primary image. Several:
// SExtractor's MEF check-image layout (empty primary + one IMAGE extension each).
void writeImageFile(const std::string& path, const std::vector<OutputImageHdu>& hdus);

// The same file layout for hduCount HDUs, filled one at a time: fill(k, hdu) is called for
// k = 0 .. hduCount-1 on a fresh OutputImageHdu just before HDU k is written, so only one HDU's
// pixels need to exist at a time (the pointers must stay valid until fill is called again).
void writeImageFileSequential(const std::string& path, int hduCount,
                              const std::function<void(int k, OutputImageHdu& hdu)>& fill);

}  // namespace octarc
