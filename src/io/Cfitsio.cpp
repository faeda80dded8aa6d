#include "octarc/io/detail/Cfitsio.h"

#include <cctype>
#include <cstdio>
#include <string>
#include <string_view>
#include <vector>

#include "octarc/core/Error.h"
#include "octarc/core/Format.h"

// cfitsio reads raw bytes at the position set by ffmbyt (public, fitsio.h) with ffgbyt, which
// its installed fitsio2.h declares without C linkage for C++.
extern "C" int ffgbyt(fitsfile* fptr, LONGLONG nbytes, void* buffer, int* status);

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

// Highest expansion ratio of a deflate stream (RFC 1951: a 258-byte match coded in at least
// 2 bits): 1032 to 1, plus room for headers.
constexpr long long kMaxDeflateRatio = 1032;
constexpr long long kDeflateSlackBytes = 65536;

// cfitsio decompresses a gzip or zip file into a memory buffer sized from the size the file
// states (gzip: the ISIZE trailer; zip: the local header), whatever the data can expand to: a
// 1 KB file could make it allocate 4 GB. A stated size no deflate stream of this length can
// reach is refused. Other compressed formats get a buffer of three times the file size.
void requireHonestCompressedSize(const std::string& path) {
  char root[FLEN_FILENAME] = {0};
  int status = 0;
  if (path.size() >= FLEN_FILENAME ||
      fits_parse_rootname(const_cast<char*>(path.c_str()), root, &status) != 0) {
    fits_clear_errmsg();
    return;  // cfitsio will report the name
  }
  std::string disk = root;
  if (disk.compare(0, 7, "file://") == 0) disk.erase(0, 7);
  // cfitsio also opens name.gz, name.Z, ... when name does not exist.
  std::FILE* in = nullptr;
  for (const char* suffix : {"", ".gz", ".Z", ".z", ".zip"}) {
    in = std::fopen((disk + suffix).c_str(), "rb");
    if (in != nullptr) break;
  }
  if (in == nullptr) return;
  unsigned char magic[2] = {0, 0};
  unsigned char stated[4] = {0, 0, 0, 0};
  long long fileBytes = -1;
  bool compressed = false;
  if (std::fread(magic, 1, 2, in) == 2) {
    const bool gzip = magic[0] == 0x1F && magic[1] == 0x8B;
    const bool zip = magic[0] == 'P' && magic[1] == 'K';
    if ((gzip || zip) && std::fseek(in, 0, SEEK_END) == 0) {
      fileBytes = std::ftell(in);
      compressed = fileBytes >= 4 &&
                   std::fseek(in, gzip ? -4L : 22L, gzip ? SEEK_END : SEEK_SET) == 0 &&
                   std::fread(stated, 1, 4, in) == 4;
    }
  }
  std::fclose(in);
  if (!compressed) return;
  long long size =
      stated[0] | (stated[1] << 8) | (stated[2] << 16) | (static_cast<long long>(stated[3]) << 24);
  // cfitsio adds 2^32 until the size exceeds the file's, for files above 10000 bytes.
  if (magic[0] == 0x1F && fileBytes > 10000) {
    while (size < fileBytes) size += 4294967296LL;
  }
  if (size > kMaxDeflateRatio * fileBytes + kDeflateSlackBytes) {
    throw IoError(path + ": compressed file of " + std::to_string(fileBytes) +
                  " bytes states an uncompressed size of " + std::to_string(size) +
                  " bytes, more than its data can hold");
  }
}

// Checks the raw header of extension `hdu` (from 0), starting at byte `headStart`, before
// cfitsio parses it. cfitsio 4.2 copies the value of a TTYPEn card of a table into a 70-byte
// buffer with strcpy: an unquoted value of 70 characters or more (or one after an '=' out of
// place) overflows it. FITS wants TTYPEn to be a quoted string, so anything else is refused,
// in every extension (cfitsio's idea of a table is looser than "XTENSION= 'BINTABLE'").
void requireSafeHeader(fitsfile* f, LONGLONG headStart, int hdu, const std::string& path) {
  const LONGLONG fileBytes = f->Fptr->filesize;
  char block[2880];
  for (LONGLONG at = headStart; at >= 0 && at + 2880 <= fileBytes; at += 2880) {
    int status = 0;
    constexpr int kReportEof = 0;  // fitsio2.h REPORT_EOF
    if (ffmbyt(f, at, kReportEof, &status) != 0 || ffgbyt(f, 2880, block, &status) != 0) {
      fits_clear_errmsg();
      return;  // cfitsio will report what it cannot read
    }
    for (int c = 0; c < 36; ++c) {
      const std::string_view card(block + 80 * c, 80);
      if (card.compare(0, 8, "END     ") == 0) return;
      bool ttype = true;
      for (int k = 0; k < 5; ++k) {
        ttype = ttype && std::toupper(static_cast<unsigned char>(card[k])) == "TTYPE"[k];
      }
      if (!ttype) continue;
      const std::size_t value = card.find_first_not_of(' ', 10);
      if (card.compare(8, 2, "= ") != 0 || value == std::string_view::npos || card[value] != '\'') {
        std::string_view keyword = card.substr(0, card.find_first_of(" =", 0));
        if (keyword.size() > 8) keyword = keyword.substr(0, 8);
        throw IoError(path + ": HDU " + std::to_string(hdu) + ": " + quoteForMessage(keyword) +
                      " is not a quoted string (FITS table column names are)");
      }
    }
  }
}

}  // namespace

FitsPtr openFits(const std::string& path, bool readWrite) {
  requireHonestCompressedSize(path);
  const auto open = [&](const std::string& name) {
    fitsfile* f = nullptr;
    int status = 0;
    fits_open_file(&f, name.c_str(), readWrite ? READWRITE : READONLY, &status);
    if (status != 0) {
      if (f != nullptr) {
        int ignored = 0;
        fits_close_file(f, &ignored);
      }
      throwIfFitsError(status, path, "cannot open as FITS");
    }
    return FitsPtr(f);
  };
  // The file alone first: cfitsio then parses the primary header only. Every further header is
  // checked before cfitsio moves to it; a path that selects an HDU ("f.fits[2]") is opened
  // again once all of them passed.
  char root[FLEN_FILENAME] = {0};
  int status = 0;
  const bool hasRoot = path.size() < FLEN_FILENAME &&
                       fits_parse_rootname(const_cast<char*>(path.c_str()), root, &status) == 0 &&
                       root[0] != '\0';
  if (!hasRoot) fits_clear_errmsg();
  FitsPtr file = open(hasRoot ? std::string(root) : path);
  fitsfile* f = file.get();
  for (int hdu = 0;; ++hdu) {
    LONGLONG headStart = 0, dataStart = 0, dataEnd = 0;
    status = 0;
    fits_get_hduaddrll(f, &headStart, &dataStart, &dataEnd, &status);
    if (status != 0 || dataEnd + 2880 > f->Fptr->filesize) break;
    requireSafeHeader(f, dataEnd, hdu + 1, hasRoot ? std::string(root) : path);
    fits_movabs_hdu(f, hdu + 2, nullptr, &status);
    if (status != 0) break;  // reported by the reader when it gets there
  }
  fits_clear_errmsg();
  if (!hasRoot || std::string(root) != path) {
    file.reset();
    return open(path);
  }
  status = 0;
  fits_movabs_hdu(f, 1, nullptr, &status);
  throwIfFitsError(status, path, "cannot read HDU 0");
  return file;
}

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
