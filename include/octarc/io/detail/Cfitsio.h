// The one place cfitsio is wrapped. Include only from .cpp files of the io and catalog stages:
// public headers never expose fitsio.h.
#pragma once

#include <fitsio.h>

#include <cstdint>
#include <memory>
#include <string>

#include "octarc/core/Error.h"

namespace octarc::detail {

struct FitsCloser {
  void operator()(fitsfile* f) const {
    int status = 0;
    fits_close_file(f, &status);  // errors on close of a read-only file are not actionable
  }
};

// Owning handle: closes the file when it goes out of scope.
using FitsPtr = std::unique_ptr<fitsfile, FitsCloser>;

// cfitsio's message for a status code, e.g. "FITS file not found".
inline std::string cfitsioMessage(int status) {
  char text[FLEN_STATUS] = {0};
  fits_get_errstatus(status, text);
  fits_clear_errmsg();
  return text;
}

// Throws IoError("<file>: <what> (<cfitsio message>)") when status != 0.
inline void throwIfFitsError(int status, const std::string& file, const std::string& what) {
  if (status != 0) throw IoError(file + ": " + what + " (" + cfitsioMessage(status) + ")");
}

// Opens an existing file (cfitsio extended syntax allowed) read-only or read-write. Before
// cfitsio parses any header beyond the primary, the file is checked for what would make
// cfitsio itself misbehave (see Cfitsio.cpp): a gzip or zip file whose stated size would make
// cfitsio allocate far more memory than its data can expand to, and an extension header whose
// TTYPEn value is not a quoted string (cfitsio 4.2 copies such a value into a 70-byte buffer
// without a bound). IoError naming the file in either case.
FitsPtr openFits(const std::string& path, bool readWrite = false);

// Creates a new file (fails if it exists; pass a temporary path from AtomicFile).
inline FitsPtr createFits(const std::string& path) {
  fitsfile* f = nullptr;
  int status = 0;
  fits_create_file(&f, path.c_str(), &status);
  throwIfFitsError(status, path, "cannot create");
  return FitsPtr(f);
}

// 0-based index of the current HDU (0 = primary).
inline int hduIndex(fitsfile* f) {
  int hdu = 0;
  fits_get_hdu_num(f, &hdu);  // 1-based
  return hdu - 1;
}

// Checks the current HDU before anything is read or allocated from its sizes, and returns the
// size of its data in bytes. cfitsio takes any XTENSION for an image and computes the data size
// |BITPIX|/8 * GCOUNT * (PCOUNT + NAXIS1 * ... * NAXISn) without overflow checks, so a header
// can claim more data than any file holds. Refused with an IoError naming the file and the HDU:
// an extension whose XTENSION is not 'IMAGE', 'BINTABLE' or 'TABLE'; a data size that overflows
// 64 bits; data that does not fit in the bytes of the file after the header (the padding of the
// last block is not required here).
std::int64_t requireSoundHdu(fitsfile* f, const std::string& path);

}  // namespace octarc::detail
