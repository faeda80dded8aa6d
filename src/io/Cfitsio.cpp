#include "octarc/io/detail/Cfitsio.h"

#include <string>
#include <vector>

#include "octarc/core/Error.h"
#include "octarc/core/Format.h"

namespace octarc::detail {

namespace {

// An integer keyword of the current HDU, or `fallback` when it is absent.
long long integerKey(fitsfile* f, const char* key, long long fallback, const std::string& where) {
  LONGLONG value = 0;
  int status = 0;
  fits_read_key_lnglng(f, key, &value, nullptr, &status);
  if (status == KEY_NO_EXIST) {
    fits_clear_errmsg();
    return fallback;
  }
  throwIfFitsError(status, where, std::string("cannot read ") + key);
  return value;
}

std::string axesText(const std::vector<long long>& axes) {
  std::string text;
  for (long long n : axes) text += (text.empty() ? "" : " x ") + std::to_string(n);
  return text;
}

}  // namespace

std::int64_t requireSoundHdu(fitsfile* f, const std::string& path) {
  const int hdu = hduIndex(f);
  const std::string where = path + ": HDU " + std::to_string(hdu);
  if (hdu > 0) {
    char xtension[FLEN_VALUE] = {0};
    int status = 0;
    fits_read_key_str(f, "XTENSION", xtension, nullptr, &status);
    if (status != 0) fits_clear_errmsg();
    std::string type(xtension);
    while (!type.empty() && type.back() == ' ') type.pop_back();
    if (type != "IMAGE" && type != "BINTABLE" && type != "TABLE") {
      throw IoError(where + ": XTENSION " + quoteForMessage(type) +
                    " is not a FITS extension type (IMAGE, BINTABLE or TABLE)");
    }
  }
  // cfitsio has checked that BITPIX is legal and that NAXIS and every NAXISn are >= 0.
  const long long bitpix = integerKey(f, "BITPIX", 8, where);
  const long long naxis = integerKey(f, "NAXIS", 0, where);
  const bool groups = [&] {
    int value = 0;
    int status = 0;
    fits_read_key_log(f, "GROUPS", &value, nullptr, &status);
    if (status != 0) fits_clear_errmsg();
    return status == 0 && value != 0;
  }();
  std::vector<long long> axes;
  for (long long k = 1; k <= naxis; ++k) {
    axes.push_back(integerKey(f, ("NAXIS" + std::to_string(k)).c_str(), 0, where));
  }
  const long long pcount = integerKey(f, "PCOUNT", 0, where);
  const long long gcount = integerKey(f, "GCOUNT", 1, where);

  long long bytes = 0;
  bool overflow = false;
  if (naxis > 0) {
    long long elements = 1;
    for (std::size_t k = 0; k < axes.size(); ++k) {
      if (k == 0 && groups && axes[0] == 0) continue;  // random groups: NAXIS1 = 0 is no axis
      overflow = overflow || __builtin_mul_overflow(elements, axes[k], &elements);
    }
    overflow = overflow || __builtin_add_overflow(elements, pcount, &elements) ||
               __builtin_mul_overflow(elements, gcount, &elements) ||
               __builtin_mul_overflow(elements, (bitpix < 0 ? -bitpix : bitpix) / 8, &bytes);
  }
  if (overflow || bytes < 0) {
    throw IoError(where + ": NAXISn = " + axesText(axes) + " (BITPIX " + std::to_string(bitpix) +
                  ", PCOUNT " + std::to_string(pcount) + ", GCOUNT " + std::to_string(gcount) +
                  "): the data size overflows 64 bits");
  }
  LONGLONG headStart = 0;
  LONGLONG dataStart = 0;
  LONGLONG dataEnd = 0;
  int status = 0;
  fits_get_hduaddrll(f, &headStart, &dataStart, &dataEnd, &status);
  throwIfFitsError(status, where, "cannot locate the data");
  const long long available = static_cast<long long>(f->Fptr->filesize) - dataStart;
  if (bytes > available) {
    throw IoError(where + ": file is truncated: NAXISn = " + axesText(axes) + " (BITPIX " +
                  std::to_string(bitpix) + ") needs " + std::to_string(bytes) +
                  " bytes of data but the file has " + std::to_string(available) +
                  " after the header");
  }
  return bytes;
}

}  // namespace octarc::detail
