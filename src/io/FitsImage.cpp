#include "octarc/io/FitsImage.h"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <new>
#include <string>
#include <thread>
#include <vector>

#include "octarc/core/AtomicFile.h"
#include "octarc/core/Error.h"
#include "octarc/core/Format.h"
#include "octarc/core/Parallel.h"
#include "octarc/io/detail/Cfitsio.h"

namespace octarc {

namespace {

using detail::FitsPtr;
using detail::hduIndex;
using detail::throwIfFitsError;

// Axes beyond the second are accepted only when degenerate (length 1), as in data cubes with a
// single plane.
constexpr int kMaxAxes = 9;

struct ImageShape {
  int bitpix = 0;  // stored BITPIX
  int naxis = 0;
  std::array<long, kMaxAxes> naxes{};
};

// True when the user's path selects an HDU explicitly ("f.fits[2]", "f.fits[SCI]").
bool namesHdu(const std::string& path) {
  char fileType[FLEN_FILENAME] = {0};
  char inFile[FLEN_FILENAME] = {0};
  char outFile[FLEN_FILENAME] = {0};
  char extSpec[FLEN_FILENAME] = {0};
  char filter[FLEN_FILENAME] = {0};
  char binSpec[FLEN_FILENAME] = {0};
  char colSpec[FLEN_FILENAME] = {0};
  int status = 0;
  if (path.size() >= FLEN_FILENAME) return path.find('[') != std::string::npos;
  std::string url = path;  // cfitsio takes a non-const buffer
  fits_parse_input_url(url.data(), fileType, inFile, outFile, extSpec, filter, binSpec, colSpec,
                       &status);
  if (status != 0) {
    fits_clear_errmsg();
    return path.find('[') != std::string::npos;
  }
  return extSpec[0] != '\0';
}

// The file part of a path, for messages and for building "file[N]" paths.
std::string fileOf(const std::string& path) {
  const std::size_t bracket = path.find('[');
  return bracket == std::string::npos ? path : path.substr(0, bracket);
}

// "file: HDU n", the start of every message about one HDU.
std::string hduText(fitsfile* f, const std::string& path) {
  return fileOf(path) + ": HDU " + std::to_string(hduIndex(f));
}

int hduType(fitsfile* f, const std::string& path) {
  int type = 0;
  int status = 0;
  fits_get_hdu_type(f, &type, &status);
  throwIfFitsError(status, path, "cannot read HDU type");
  return type;
}

ImageShape readShape(fitsfile* f, const std::string& path) {
  ImageShape shape;
  int status = 0;
  fits_get_img_param(f, kMaxAxes, &shape.bitpix, &shape.naxis, shape.naxes.data(), &status);
  throwIfFitsError(status, path, "cannot read image size");
  return shape;
}

// An HDU without pixels to look for: NAXIS = 0 (the usual empty primary of a MEF), or a 1-D
// axis of length 0. A 2-D image with a zero axis is not empty but wrong (requireTwoDimensional).
bool isEmpty(const ImageShape& shape) {
  return shape.naxis == 0 || (shape.naxis == 1 && shape.naxes[0] == 0);
}

void requireImageHdu(fitsfile* f, const std::string& path) {
  detail::requireSoundHdu(f, fileOf(path));
  const int type = hduType(f, path);
  if (type == IMAGE_HDU) return;
  throw IoError(path + ": HDU " + std::to_string(hduIndex(f)) + " is " +
                (type == BINARY_TBL ? "a binary table" : "an ASCII table") + ", not an image");
}

// A 2-D image (further axes of length 1 allowed) of at least 1 x 1 pixels whose pixel count,
// as float and as double, can be addressed. Checked before any pixel buffer is allocated; that
// the data fit in the file has been checked by requireSoundHdu. `where` is "file: HDU n".
void requireTwoDimensional(const ImageShape& shape, const std::string& where) {
  if (shape.naxis < 2 || shape.naxis > kMaxAxes) {
    throw IoError(where + ": image has NAXIS = " + std::to_string(shape.naxis) +
                  ", expected a 2-D image");
  }
  for (int i = 2; i < shape.naxis; ++i) {
    if (shape.naxes[i] != 1) {
      throw IoError(where + ": image has NAXIS = " + std::to_string(shape.naxis) + " with NAXIS" +
                    std::to_string(i + 1) + " = " + std::to_string(shape.naxes[i]) +
                    ", expected a 2-D image");
    }
  }
  const std::string size = std::to_string(shape.naxes[0]) + " x " + std::to_string(shape.naxes[1]);
  if (shape.naxes[0] < 1 || shape.naxes[1] < 1) {
    throw IoError(where + ": image is " + size + " pixels, expected at least 1 x 1");
  }
  long long count = 0;
  if (__builtin_mul_overflow(static_cast<long long>(shape.naxes[0]),
                             static_cast<long long>(shape.naxes[1]), &count) ||
      count > PTRDIFF_MAX / static_cast<long long>(sizeof(double))) {
    throw IoError(where + ": image of " + size + " pixels is too large to be held in memory");
  }
}

// BSCALE and BZERO must be finite numbers, BSCALE not 0, and (for integer data) BLANK an
// integer: otherwise the pixel values cannot be interpreted. cfitsio would read such a header
// (ignoring or replacing what it cannot parse), so it is refused here, before either the raw
// float reader or cfitsio sees the pixels. BLANK of a floating-point image has no meaning in
// FITS (NaN marks undefined pixels) and is ignored, as by cfitsio.
void requireUsableScaling(const FitsHeader& header, int bitpix, const std::string& where) {
  const auto refuse = [&](const char* key, const std::string& value, const char* expected) {
    throw IoError(where + ": " + key + " = " + quoteForMessage(value) + " is not " + expected +
                  ": the pixel values cannot be interpreted");
  };
  if (const std::optional<std::string> text = header.value("BSCALE")) {
    const std::optional<double> v = header.number("BSCALE");
    if (!v || *v == 0.0) refuse("BSCALE", *text, "a finite non-zero number");
  }
  if (const std::optional<std::string> text = header.value("BZERO")) {
    if (!header.number("BZERO")) refuse("BZERO", *text, "a finite number");
  }
  if (bitpix > 0) {
    if (const std::optional<std::string> text = header.value("BLANK")) {
      const std::optional<double> v = header.number("BLANK");
      if (!v || *v != std::floor(*v) || std::fabs(*v) > 9.2e18) {
        refuse("BLANK", *text, "an integer");
      }
    }
  }
}

// Positions an open file on the image HDU a path refers to: the HDU it names, or else the first
// non-empty image HDU.
void moveToImage(fitsfile* f, const std::string& path) {
  if (namesHdu(path)) {
    requireImageHdu(f, path);
    return;
  }
  int count = 0;
  int status = 0;
  fits_get_num_hdus(f, &count, &status);
  throwIfFitsError(status, path, "cannot count HDUs");
  for (int hdu = 1; hdu <= count; ++hdu) {
    fits_movabs_hdu(f, hdu, nullptr, &status);
    throwIfFitsError(status, path, "cannot read HDU " + std::to_string(hdu - 1));
    detail::requireSoundHdu(f, path);
    if (hduType(f, path) == IMAGE_HDU && !isEmpty(readShape(f, path))) return;
  }
  throw IoError(path + ": no image HDU in file");
}

// The header of the current HDU as 80-character cards. For a tile-compressed image cfitsio
// returns the header of the uncompressed image.
FitsHeader readHeaderCards(fitsfile* f, const std::string& path) {
  char* text = nullptr;
  int count = 0;
  int status = 0;
  fits_convert_hdr2str(f, 0, nullptr, 0, &text, &count, &status);
  if (status != 0) {
    // cfitsio calls do nothing while their status is set: free with a clean one.
    int freeStatus = 0;
    if (text != nullptr) fits_free_memory(text, &freeStatus);
    throwIfFitsError(status, path, "cannot read header");
  }
  FitsHeader header;
  const std::string all(text);
  int ignored = 0;
  fits_free_memory(text, &ignored);
  for (std::size_t pos = 0; pos + 80 <= all.size(); pos += 80) {
    std::string card = all.substr(pos, 80);
    if (card.compare(0, 8, "END     ") == 0) break;
    header.cards.push_back(std::move(card));
  }
  return header;
}

// cfitsio only notices a short file when the pixels are read; checking the size up front lets
// header-only reads report it too. Like cfitsio, the data unit must be complete including its
// padding to a multiple of 2880 bytes.
void requireCompleteData(fitsfile* f, const std::string& path) {
  int status = 0;
  if (fits_is_compressed_image(f, &status)) return;  // sizes refer to the compressed table
  LONGLONG headStart = 0;
  LONGLONG dataStart = 0;
  LONGLONG dataEnd = 0;
  fits_get_hduaddrll(f, &headStart, &dataStart, &dataEnd, &status);
  throwIfFitsError(status, path, "cannot locate image data");
  const LONGLONG fileBytes = f->Fptr->filesize;
  if (dataEnd > fileBytes) {
    throw IoError(path + ": file is truncated (the header needs " + std::to_string(dataEnd) +
                  " bytes, the file has " + std::to_string(fileBytes) + ")");
  }
}

ImageHdu readHduInfo(fitsfile* f, const std::string& path) {
  ImageHdu hdu;
  hdu.path = path;
  hdu.hduIndex = hduIndex(f);
  const ImageShape shape = readShape(f, path);
  requireTwoDimensional(shape, hduText(f, path));
  requireCompleteData(f, path);
  hdu.bitpix = shape.bitpix;
  hdu.widthPix = shape.naxes[0];
  hdu.heightPix = shape.naxes[1];
  hdu.header = readHeaderCards(f, path);
  requireUsableScaling(hdu.header, shape.bitpix, hduText(f, path));
  hdu.extname = hdu.header.value("EXTNAME").value_or("");
  return hdu;
}

// Image sizes have been checked against the file, except for tile-compressed images whose
// pixels may legitimately need far more memory than the file: that failure names the file too.
template <typename T>
Image<T> allocatePixels(fitsfile* f, const std::string& path, long width, long height) {
  try {
    return Image<T>(width, height, UninitializedPixels{});  // every pixel is read by the caller
  } catch (const std::bad_alloc&) {
    throw IoError(hduText(f, path) + ": image of " + std::to_string(width) + " x " +
                  std::to_string(height) + " pixels does not fit in memory");
  }
}

// cfitsio's HCOMPRESS decoder takes the tile size from the compressed stream, not from the
// header, and writes that many pixels into a buffer sized for the tile: a stream that states
// a larger tile overwrites memory (a segmentation fault found by fuzzing). Before the pixels of
// an HCOMPRESS_1 image are read, every tile's stream must start with the HCOMPRESS code and
// state the size of its own tile.
void requireConsistentHcompressTiles(fitsfile* f, const std::string& where) {
  int status = 0;
  char type[FLEN_VALUE] = {0};
  fits_read_key_str(f, "ZCMPTYPE", type, nullptr, &status);
  if (status != 0 || std::strncmp(type, "HCOMPRESS_1", 11) != 0) {
    fits_clear_errmsg();
    return;
  }
  const auto key = [&](const char* name, long long fallback) {
    LONGLONG value = 0;
    int s = 0;
    if (fits_read_key_lnglng(f, name, &value, nullptr, &s) != 0) {
      fits_clear_errmsg();
      return fallback;
    }
    return static_cast<long long>(value);
  };
  const long long width = key("ZNAXIS1", 0);
  const long long height = key("ZNAXIS2", 0);
  const long long tileWidth = key("ZTILE1", width);
  const long long tileHeight = key("ZTILE2", 1);
  int column = 0;
  fits_get_colnum(f, CASEINSEN, const_cast<char*>("COMPRESSED_DATA"), &column, &status);
  if (status != 0 || width < 1 || height < 1 || tileWidth < 1 || tileHeight < 1) {
    fits_clear_errmsg();
    return;  // cfitsio refuses these itself
  }
  const long long tilesPerRow = (width + tileWidth - 1) / tileWidth;
  const long long tiles = tilesPerRow * ((height + tileHeight - 1) / tileHeight);
  for (long long row = 1; row <= tiles; ++row) {
    LONGLONG bytes = 0;
    LONGLONG offset = 0;
    fits_read_descriptll(f, column, row, &bytes, &offset, &status);
    if (status != 0) {
      fits_clear_errmsg();
      return;  // cfitsio reports the table itself
    }
    if (bytes == 0) continue;  // the tile is stored in another column
    const long long i = (row - 1) % tilesPerRow;
    const long long j = (row - 1) / tilesPerRow;
    const long long nx = std::min(tileWidth, width - i * tileWidth);
    const long long ny = std::min(tileHeight, height - j * tileHeight);
    unsigned char head[10] = {0};
    int anyNull = 0;
    if (bytes < 10 ||
        fits_read_col(f, TBYTE, column, row, 1, 10, nullptr, head, &anyNull, &status) != 0) {
      fits_clear_errmsg();
      throw IoError(where + ": HCOMPRESS tile " + std::to_string(row) + " is truncated");
    }
    const auto int32 = [&](int at) {
      return static_cast<long long>(static_cast<std::int32_t>(
          (std::uint32_t(head[at]) << 24) | (std::uint32_t(head[at + 1]) << 16) |
          (std::uint32_t(head[at + 2]) << 8) | std::uint32_t(head[at + 3])));
    };
    const long long a = int32(2);
    const long long b = int32(6);
    if (head[0] != 0xDD || head[1] != 0x99 || a < 1 || b < 1 || a * b != nx * ny) {
      throw IoError(where + ": HCOMPRESS tile " + std::to_string(row) + " is not a stream of a " +
                    std::to_string(nx) + " x " + std::to_string(ny) + " tile");
    }
  }
}

// cfitsio reads an image serially through its own buffers. A plain BITPIX -32 image in a disk
// file (not tile-compressed, not scaled) is one block of big-endian floats: read it straight into
// the pixels, in slices on several threads, and swap the bytes in place. Returns false, having
// read nothing usable, whenever that does not apply or fails; cfitsio then reads the image (and
// reports any error itself).
bool readPlainFloatData(fitsfile* f, ImageF& pixels) {
  if constexpr (std::endian::native != std::endian::little) return false;
  int status = 0;
  if (fits_is_compressed_image(f, &status) || status != 0) return false;
  char urlType[FLEN_FILENAME] = {0};
  if (fits_url_type(f, urlType, &status) != 0 || std::strcmp(urlType, "file://") != 0) {
    return false;
  }
  for (const char* key : {"BSCALE", "BZERO"}) {
    double value = 0.0;
    int keyStatus = 0;
    if (fits_read_key(f, TDOUBLE, key, &value, nullptr, &keyStatus) == 0 &&
        value != (std::strcmp(key, "BSCALE") == 0 ? 1.0 : 0.0)) {
      return false;
    }
  }
  LONGLONG headStart = 0, dataStart = 0, dataEnd = 0;
  char openedName[FLEN_FILENAME] = {0};
  char fileName[FLEN_FILENAME] = {0};
  // The name as opened may carry an HDU selection ("f.fits[1]"): keep the file's own name.
  if (fits_get_hduaddrll(f, &headStart, &dataStart, &dataEnd, &status) != 0 ||
      fits_file_name(f, openedName, &status) != 0 ||
      fits_parse_rootname(openedName, fileName, &status) != 0) {
    return false;
  }
  const char* diskName = fileName;
  if (std::strncmp(diskName, "file://", 7) == 0) diskName += 7;
  const std::int64_t count = pixels.size();
  if (dataEnd - dataStart < LONGLONG(count) * LONGLONG(sizeof(float))) return false;
  const int fd = ::open(diskName, O_RDONLY | O_CLOEXEC);
  if (fd < 0) return false;
  constexpr std::int64_t kSlicePixels = std::int64_t(1) << 20;  // 4 MB per read
  const int threads = count < 4 * kSlicePixels ? 1 : std::min(resolveThreads(0), 4);
  std::atomic<bool> ok{true};
  parallelBlocks(count, threads, [&](std::int64_t begin, std::int64_t end) {
    for (std::int64_t i = begin; i < end && ok; i += kSlicePixels) {
      const std::int64_t n = std::min(kSlicePixels, end - i);
      char* out = reinterpret_cast<char*>(pixels.data() + i);
      std::int64_t done = 0;
      while (done < n * 4) {
        const ssize_t got =
            ::pread(fd, out + done, std::size_t(n * 4 - done), off_t(dataStart + i * 4 + done));
        if (got <= 0) {
          ok = false;
          return;
        }
        done += got;
      }
      // Through memcpy: the bytes belong to float objects.
      for (std::int64_t k = 0; k < n; ++k) {
        std::uint32_t word;
        std::memcpy(&word, out + 4 * k, 4);
        word = __builtin_bswap32(word);
        std::memcpy(out + 4 * k, &word, 4);
      }
    }
  });
  ::close(fd);
  return ok;
}

// Reads the pixels of the current HDU as float; undefined pixels (BLANK or NaN) become NaN.
// Integer data are scaled the way SExtractor scales them, in single precision:
// float(BSCALE) * float(raw) + float(BZERO). The result is within one float ulp of the exact
// value, and identical to the pixels SExtractor measures, so that catalogs can agree with
// SExtractor's to the last digit.
ImageF readPixels(fitsfile* f, const std::string& path, int bitpix, long width, long height) {
  requireConsistentHcompressTiles(f, hduText(f, path));
  ImageF pixels = allocatePixels<float>(f, path, width, height);
  long first[kMaxAxes];
  std::fill(std::begin(first), std::end(first), 1L);
  int anyNull = 0;
  int status = 0;
  const LONGLONG count = static_cast<LONGLONG>(width) * height;
  if (bitpix == FLOAT_IMG && readPlainFloatData(f, pixels)) return pixels;
  if (bitpix < 0) {
    // No null value: IEEE NaNs come through as NaN unchanged, and cfitsio skips its
    // per-pixel null test.
    fits_read_pix(f, TFLOAT, first, count, nullptr, pixels.data(), &anyNull, &status);
    throwIfFitsError(status, path, "cannot read pixels, file truncated or corrupt");
    return pixels;
  }
  double bscale = 1.0, bzero = 0.0;
  char comment[FLEN_COMMENT];
  int keyStatus = 0;
  if (fits_read_key(f, TDOUBLE, "BSCALE", &bscale, comment, &keyStatus) != 0) bscale = 1.0;
  keyStatus = 0;
  if (fits_read_key(f, TDOUBLE, "BZERO", &bzero, comment, &keyStatus) != 0) bzero = 0.0;
  // Raw integers (cfitsio still recognises BLANK before scaling), one row at a time.
  fits_set_bscale(f, 1.0, 0.0, &status);
  throwIfFitsError(status, path, "cannot read pixels");
  const float scale = static_cast<float>(bscale);
  const float zero = static_cast<float>(bzero);
  std::vector<double> row(static_cast<std::size_t>(width));
  const double nullValue = std::numeric_limits<double>::quiet_NaN();
  for (long y = 0; y < height; ++y) {
    first[1] = y + 1;
    fits_read_pix(f, TDOUBLE, first, width, const_cast<double*>(&nullValue), row.data(), &anyNull,
                  &status);
    throwIfFitsError(status, path, "cannot read pixels, file truncated or corrupt");
    float* out = pixels.data() + static_cast<std::int64_t>(y) * width;
    for (long x = 0; x < width; ++x) {
      const double raw = row[static_cast<std::size_t>(x)];
      out[x] = std::isnan(raw) ? std::numeric_limits<float>::quiet_NaN()
                               : scale * static_cast<float>(raw) + zero;
    }
  }
  fits_set_bscale(f, bscale, bzero, &status);
  return pixels;
}

}  // namespace

std::vector<std::string> listImageHdus(const std::string& path) {
  FitsPtr f = detail::openFits(path);
  if (namesHdu(path)) {
    requireImageHdu(f.get(), path);
    requireTwoDimensional(readShape(f.get(), path), hduText(f.get(), path));
    return {path};
  }
  int count = 0;
  int status = 0;
  fits_get_num_hdus(f.get(), &count, &status);
  throwIfFitsError(status, path, "cannot count HDUs");
  // SExtractor processes every image HDU that holds data; an empty primary (the usual MEF
  // layout) and table HDUs are skipped.
  std::vector<int> images;
  for (int hdu = 1; hdu <= count; ++hdu) {
    fits_movabs_hdu(f.get(), hdu, nullptr, &status);
    throwIfFitsError(status, path, "cannot read HDU " + std::to_string(hdu - 1));
    detail::requireSoundHdu(f.get(), path);
    if (hduType(f.get(), path) != IMAGE_HDU) continue;
    const ImageShape shape = readShape(f.get(), path);
    if (isEmpty(shape)) continue;
    requireTwoDimensional(shape, hduText(f.get(), path));
    images.push_back(hdu - 1);
  }
  if (images.empty()) throw IoError(path + ": no image HDU in file");
  if (images.size() == 1 && images.front() == 0) return {path};
  std::vector<std::string> paths;
  for (int index : images) paths.push_back(fileOf(path) + "[" + std::to_string(index) + "]");
  return paths;
}

ImageHdu readImageHeader(const std::string& path) {
  FitsPtr f = detail::openFits(path);
  moveToImage(f.get(), path);
  return readHduInfo(f.get(), path);
}

ImageHdu readImage(const std::string& path) {
  FitsPtr f = detail::openFits(path);
  moveToImage(f.get(), path);
  ImageHdu hdu = readHduInfo(f.get(), path);
  const ImageShape shape = readShape(f.get(), path);
  hdu.pixels = readPixels(f.get(), path, shape.bitpix, shape.naxes[0], shape.naxes[1]);
  return hdu;
}

ImageI32 readIntImage(const std::string& path, FitsHeader* header) {
  FitsPtr f = detail::openFits(path);
  moveToImage(f.get(), path);
  const ImageShape shape = readShape(f.get(), path);
  requireTwoDimensional(shape, hduText(f.get(), path));
  requireCompleteData(f.get(), path);
  FitsHeader cards = readHeaderCards(f.get(), path);
  requireUsableScaling(cards, shape.bitpix, hduText(f.get(), path));
  const double bscale = cards.number("BSCALE").value_or(1.0);
  const double bzero = cards.number("BZERO").value_or(0.0);
  if (shape.bitpix < 0 || bscale != 1.0 || bzero != std::floor(bzero)) {
    throw IoError(path + ": not an integer image (BITPIX " + std::to_string(shape.bitpix) +
                  (bscale != 1.0 ? ", BSCALE != 1" : "") +
                  (bzero != std::floor(bzero) ? ", non-integer BZERO" : "") +
                  "), expected integer labels");
  }
  requireConsistentHcompressTiles(f.get(), hduText(f.get(), path));
  ImageI32 pixels = allocatePixels<std::int32_t>(f.get(), path, shape.naxes[0], shape.naxes[1]);
  long first[kMaxAxes];
  std::fill(std::begin(first), std::end(first), 1L);
  int anyNull = 0;
  int status = 0;
  // A null value of 0 disables BLANK substitution: labels are read as stored.
  fits_read_pix(f.get(), TINT, first, static_cast<LONGLONG>(shape.naxes[0]) * shape.naxes[1],
                nullptr, pixels.data(), &anyNull, &status);
  if (status == NUM_OVERFLOW) {
    fits_clear_errmsg();
    throw IoError(path + ": integer image has values outside the 32-bit range");
  }
  throwIfFitsError(status, path, "cannot read pixels, file truncated or corrupt");
  if (header != nullptr) *header = std::move(cards);
  return pixels;
}

namespace {

// Keywords that describe the data layout: writeImageFile writes its own.
bool isStructural(const std::string& card) {
  const std::string key = card.substr(0, 8);
  static const char* const kExact[] = {"SIMPLE  ", "XTENSION", "BITPIX  ", "NAXIS   ", "PCOUNT  ",
                                       "GCOUNT  ", "EXTEND  ", "BSCALE  ", "BZERO   ", "BLANK   ",
                                       "END     ", "CHECKSUM", "DATASUM ", "THEAP   "};
  for (const char* exact : kExact) {
    if (key == exact) return true;
  }
  if (key.compare(0, 5, "NAXIS") == 0) return true;  // NAXIS1, NAXIS2, ...
  // The two reference comments cfitsio writes into every primary header would repeat.
  if (key == "COMMENT " &&
      (card.find("FITS (Flexible Image Transport System) format is") != std::string::npos ||
       card.find("and Astrophysics', volume 376, page 359") != std::string::npos)) {
    return true;
  }
  return false;
}

// Keywords the FITS standard allows in the primary header only (fitsverify flags them in an
// extension: a multi-level check-image copies the image's primary header into every HDU).
bool isPrimaryOnly(const std::string& card) {
  const std::string key = card.substr(0, 8);
  return key == "BLOCKED " || key == "GROUPS  " || key == "SIMPLE  " || key == "EXTEND  ";
}

void writeHdu(fitsfile* f, const std::string& path, const OutputImageHdu& hdu) {
  const bool isInt = hdu.intPixels != nullptr;
  if (isInt == (hdu.floatPixels != nullptr)) {
    throw IoError(path + ": each output HDU needs exactly one of float or int pixels");
  }
  const std::int64_t width = isInt ? hdu.intPixels->width() : hdu.floatPixels->width();
  const std::int64_t height = isInt ? hdu.intPixels->height() : hdu.floatPixels->height();
  if (width <= 0 || height <= 0) throw IoError(path + ": cannot write an empty image");
  long naxes[2] = {static_cast<long>(width), static_cast<long>(height)};
  int status = 0;
  fits_create_img(f, isInt ? LONG_IMG : FLOAT_IMG, 2, naxes, &status);
  throwIfFitsError(status, path, "cannot create image HDU");
  int hduNumber = 0;
  fits_get_hdu_num(f, &hduNumber);
  for (const std::string& card : hdu.header.cards) {
    if (isStructural(card) || (hduNumber > 1 && isPrimaryOnly(card))) continue;
    fits_write_record(f, card.c_str(), &status);
    throwIfFitsError(status, path, "cannot write header card '" + card.substr(0, 8) + "'");
  }
  long first[2] = {1, 1};
  const LONGLONG count = static_cast<LONGLONG>(width) * height;
  if (isInt) {
    fits_write_pix(f, TINT, first, count, const_cast<std::int32_t*>(hdu.intPixels->data()),
                   &status);
  } else {
    fits_write_pix(f, TFLOAT, first, count, const_cast<float*>(hdu.floatPixels->data()), &status);
  }
  throwIfFitsError(status, path, "cannot write pixels");
}

}  // namespace

void writeImageFileSequential(const std::string& path, int hduCount,
                              const std::function<void(int k, OutputImageHdu& hdu)>& fill) {
  if (hduCount <= 0) throw IoError(path + ": nothing to write");
  AtomicFile out(path);
  // cfitsio will not overwrite an existing file; the temporary name is fresh, and the rename
  // in commit() replaces the target.
  FitsPtr f = detail::createFits(out.tempPath());
  int status = 0;
  if (hduCount > 1) {
    fits_create_img(f.get(), BYTE_IMG, 0, nullptr, &status);
    throwIfFitsError(status, path, "cannot create primary HDU");
  }
  for (int k = 0; k < hduCount; ++k) {
    OutputImageHdu hdu;
    fill(k, hdu);
    writeHdu(f.get(), path, hdu);
  }
  // Close explicitly: buffered data is flushed here, and a failure must not be ignored.
  fits_close_file(f.release(), &status);
  throwIfFitsError(status, path, "cannot write file");
  out.commit();
}

void writeImageFile(const std::string& path, const std::vector<OutputImageHdu>& hdus) {
  writeImageFileSequential(path, static_cast<int>(hdus.size()),
                           [&](int k, OutputImageHdu& hdu) { hdu = hdus[std::size_t(k)]; });
}

void writeImageCube(const std::string& path, const std::vector<const ImageF*>& planes,
                    const FitsHeader& header) {
  if (planes.empty()) throw IoError(path + ": nothing to write");
  const ImageF& first = *planes.front();
  for (const ImageF* p : planes) {
    if (p->width() != first.width() || p->height() != first.height() || p->empty()) {
      throw IoError(path + ": the planes of a cube must be non-empty and of one size");
    }
  }
  FitsPtr f = detail::createFits(path);
  long naxes[3] = {static_cast<long>(first.width()), static_cast<long>(first.height()),
                   static_cast<long>(planes.size())};
  int status = 0;
  fits_create_img(f.get(), FLOAT_IMG, 3, naxes, &status);
  throwIfFitsError(status, path, "cannot create image cube");
  for (const std::string& card : header.cards) {
    if (isStructural(card)) continue;
    fits_write_record(f.get(), card.c_str(), &status);
    throwIfFitsError(status, path, "cannot write header card '" + card.substr(0, 8) + "'");
  }
  for (std::size_t k = 0; k < planes.size(); ++k) {
    long firstPixel[3] = {1, 1, static_cast<long>(k) + 1};
    fits_write_pix(f.get(), TFLOAT, firstPixel, static_cast<LONGLONG>(first.size()),
                   const_cast<float*>(planes[k]->data()), &status);
    throwIfFitsError(status, path, "cannot write pixels");
  }
  fits_close_file(f.release(), &status);
  throwIfFitsError(status, path, "cannot write file");
}

}  // namespace octarc
