#include "octarc/catalog/AppendedCatalog.h"

#include <algorithm>
#include <cstring>
#include <set>

#include "FitsColumns.h"
#include "octarc/core/AtomicFile.h"
#include "octarc/core/Error.h"
#include "octarc/io/detail/Cfitsio.h"

namespace octarc {

namespace {

constexpr std::size_t kCardBytes = 80;
// Rows are copied in blocks of about this many bytes: large enough that cfitsio reads and writes
// them straight between the file and the buffer, in a few system calls per block.
constexpr std::int64_t kBlockBytes = std::int64_t(8) << 20;

std::string keyOf(const std::string& card) {
  std::string key = card.substr(0, std::min<std::size_t>(8, card.size()));
  while (!key.empty() && key.back() == ' ') key.pop_back();
  return key;
}

std::set<std::string> keysOf(const std::vector<std::string>& cards) {
  std::set<std::string> keys;
  for (const std::string& c : cards) keys.insert(keyOf(c));
  return keys;
}

std::string hduName(int hdu) {
  return "HDU " + std::to_string(hdu);
}

// The header cards of the current HDU, each padded to 80 characters, END not included.
std::vector<std::string> readCards(fitsfile* f, const std::string& path, int hdu) {
  int status = 0;
  int count = 0;
  int more = 0;
  fits_get_hdrspace(f, &count, &more, &status);
  std::vector<std::string> cards;
  cards.reserve(std::size_t(count));
  char card[FLEN_CARD];
  for (int k = 1; k <= count && status == 0; ++k) {
    fits_read_record(f, k, card, &status);
    std::string c(card);
    c.resize(kCardBytes, ' ');
    cards.push_back(std::move(c));
  }
  detail::throwIfFitsError(status, path, "cannot read the header of " + hduName(hdu));
  return cards;
}

long long integerKey(fitsfile* f, const char* key, const std::string& path, int hdu) {
  int status = 0;
  LONGLONG value = 0;
  fits_read_key_lnglng(f, key, &value, nullptr, &status);
  detail::throwIfFitsError(status, path, std::string("cannot read ") + key + " of " + hduName(hdu));
  return value;
}

bool hasKey(fitsfile* f, const char* key) {
  char value[FLEN_VALUE];
  int status = 0;
  fits_read_keyword(f, key, value, nullptr, &status);
  fits_clear_errmsg();
  return status == 0;
}

// Starts a new HDU in `out` holding exactly `cards` (the structure keywords among them), without
// defining its data yet.
void writeCards(fitsfile* out, const std::vector<std::string>& cards, const std::string& path) {
  int status = 0;
  fits_create_hdu(out, &status);
  for (const std::string& card : cards) fits_write_record(out, card.c_str(), &status);
  detail::throwIfFitsError(status, path, "cannot write header");
}

// Sets an integer or string structure keyword, keeping its comment.
void setKey(fitsfile* out, const char* key, long long value, const std::string& path) {
  int status = 0;
  fits_modify_key_lng(out, key, LONGLONG(value), "&", &status);
  detail::throwIfFitsError(status, path, std::string("cannot write ") + key);
}
void setKey(fitsfile* out, const char* key, const std::string& value, const std::string& path) {
  int status = 0;
  fits_modify_key_str(out, key, value.c_str(), "&", &status);
  detail::throwIfFitsError(status, path, std::string("cannot write ") + key);
}

// Lets cfitsio read the layout of the HDU whose header was just written.
void defineLayout(fitsfile* out, const std::string& path) {
  int status = 0;
  fits_set_hdustruc(out, &status);
  detail::throwIfFitsError(status, path, "cannot write header");
}

// The header of an objects table with the new columns: the original cards (NAXIS1/TFIELDS are
// updated later), each new column's block right after the cards of the column before it, as
// detail::writeColumnCards places them, then the provenance cards.
std::vector<std::string> objectsCards(std::vector<std::string> cards, int originalColumns,
                                      const std::vector<ColumnSpec>& added,
                                      const std::vector<std::string>& provenance) {
  for (std::size_t i = 0; i < added.size(); ++i) {
    const int colnum = originalColumns + int(i) + 1;
    const std::string n = std::to_string(colnum);
    // A stray card of this not yet existing column (a TUNITn...) gives way to the new ones.
    for (const char* root : {"TTYPE", "TFORM", "TUNIT", "TDISP"}) {
      const auto stale = std::find_if(cards.begin(), cards.end(),
                                      [&](const std::string& c) { return keyOf(c) == root + n; });
      if (stale != cards.end()) cards.erase(stale);
    }
    std::size_t insertAt = cards.size();
    for (std::size_t k = 0; k < cards.size(); ++k) {
      const std::string key = keyOf(cards[k]);
      if (colnum == 1 ? (key == "TFIELDS" || key == "EXTNAME")
                      : detail::columnOfKeyword(key) == colnum - 1) {
        insertAt = k + 1;
      }
    }
    const std::vector<std::string> block = detail::columnCards(colnum, added[i]);
    cards.insert(cards.begin() + std::ptrdiff_t(insertAt), block.begin(), block.end());
  }
  cards.insert(cards.end(), provenance.begin(), provenance.end());
  return cards;
}

// The provenance cards whose keyword is not among `present`.
std::vector<std::string> newCards(const std::vector<std::string>& cards,
                                  const std::set<std::string>& present) {
  std::vector<std::string> out;
  for (const std::string& c : cards) {
    std::string card = c;
    card.resize(kCardBytes, ' ');
    if (!present.count(keyOf(card))) out.push_back(std::move(card));
  }
  return out;
}

struct HduPlan {
  int type = 0;
  std::string extname;
  int part = -1;      // objects table: index in `parts`
  int imheadOf = -1;  // LDAC_IMHEAD: index of the part whose objects table follows it
};

class Appender {
 public:
  Appender(const std::string& inputPath, const std::vector<InputCatalogPart>& parts,
           const std::string& outputPath, const std::vector<AppendedColumns>& appended)
      : inputPath_(inputPath), outputPath_(outputPath), parts_(parts), appended_(appended) {}

  void run() {
    if (appended_.size() != parts_.size()) {
      throw IoError(inputPath_ + ": holds " + std::to_string(parts_.size()) +
                    " objects table(s) but columns for " + std::to_string(appended_.size()) +
                    " were given");
    }
    checkColumns();
    detail::FitsPtr input = openInput();
    in_ = input.get();
    plan();

    AtomicFile out(outputPath_);
    fitsfile* created = nullptr;
    int status = 0;
    // The disk-file variant: no cfitsio syntax in the name.
    fits_create_diskfile(&created, out.tempPath().c_str(), &status);
    detail::throwIfFitsError(status, outputPath_, "cannot create");
    detail::FitsPtr output(created);
    out_ = output.get();
    for (int hdu = 1; hdu <= int(hdus_.size()); ++hdu) {
      moveInput(hdu);
      const HduPlan& h = hdus_[std::size_t(hdu - 1)];
      if (h.part >= 0) {
        copyObjects(hdu, std::size_t(h.part));
      } else if (h.imheadOf >= 0 && !imheadCards(std::size_t(h.imheadOf)).empty()) {
        copyImhead(hdu, imheadCards(std::size_t(h.imheadOf)));
      } else {
        fits_copy_hdu(in_, out_, 0, &status);
        detail::throwIfFitsError(status, outputPath_, "cannot copy " + hduName(hdu));
      }
    }
    // The old checksums of the HDUs written anew no longer match them.
    for (int hdu : checksummed_) {
      int type = 0;
      fits_movabs_hdu(out_, hdu, &type, &status);
      fits_write_chksum(out_, &status);
      detail::throwIfFitsError(status, outputPath_, "cannot update CHECKSUM of " + hduName(hdu));
    }
    detail::closeWritten(output.release(), outputPath_);
    out.commit();
  }

 private:
  std::string where(std::size_t p) const {
    return inputPath_ + ": objects table " + std::to_string(p + 1) + " (" +
           hduName(parts_[p].objectsHdu) + ")";
  }

  std::vector<ColumnSpec> addedColumns(std::size_t p) const {
    const AppendedColumns& a = appended_[p];
    std::vector<ColumnSpec> specs;
    if (a.table == nullptr) return specs;
    if (a.columns.empty()) return a.table->columns();
    for (int c : a.columns) specs.push_back(a.table->columns().at(std::size_t(c)));
    return specs;
  }

  std::vector<int> addedColumnIndices(std::size_t p) const {
    const AppendedColumns& a = appended_[p];
    if (a.table == nullptr || !a.columns.empty()) return a.columns;
    std::vector<int> all(std::size_t(a.table->columnCount()));
    for (int c = 0; c < a.table->columnCount(); ++c) all[std::size_t(c)] = c;
    return all;
  }

  // Checked for every table before anything is written.
  void checkColumns() const {
    for (std::size_t p = 0; p < parts_.size(); ++p) {
      const AppendedColumns& a = appended_[p];
      const std::vector<ColumnSpec> specs = addedColumns(p);
      if (specs.empty()) continue;
      const std::int64_t rows = std::int64_t(parts_[p].numbers.size());
      const std::int64_t given = a.rows ? std::int64_t(a.rows->size()) : a.table->rows();
      if (given != rows) {
        throw IoError(where(p) + " has " + std::to_string(rows) + " rows but " +
                      std::to_string(given) + " rows of new columns were given");
      }
      if (a.rows) {
        for (std::int64_t r : *a.rows) {
          if (r < 0 || r >= a.table->rows()) {
            throw std::out_of_range("writeAppendedCatalog: row index out of the table");
          }
        }
      }
      std::set<std::string> names(parts_[p].columnNames.begin(), parts_[p].columnNames.end());
      for (const ColumnSpec& c : specs) {
        if (!names.insert(c.name).second) {
          throw ConfigError(where(p) + " already has a column " + c.name);
        }
      }
    }
  }

  detail::FitsPtr openInput() const {
    fitsfile* opened = nullptr;
    int status = 0;
    fits_open_diskfile(&opened, inputPath_.c_str(), READONLY, &status);  // no cfitsio syntax
    if (status != 0 && opened != nullptr) {
      int ignored = 0;
      fits_close_file(opened, &ignored);
    }
    detail::throwIfFitsError(status, inputPath_, "cannot open as FITS");
    return detail::FitsPtr(opened);
  }

  void moveInput(int hdu) {
    int type = 0;
    int status = 0;
    fits_movabs_hdu(in_, hdu, &type, &status);
    detail::throwIfFitsError(status, inputPath_, "cannot read " + hduName(hdu));
  }

  // What each HDU is: an objects table of `parts` (checked against the file), the LDAC_IMHEAD of
  // one, or something to copy. The primary header's keywords are noted (FITS_1.0 keeps
  // SExtractor's run keywords there).
  void plan() {
    int status = 0;
    int count = 0;
    fits_get_num_hdus(in_, &count, &status);
    detail::throwIfFitsError(status, inputPath_, "cannot read FITS structure");
    int pendingImhead = -1;
    std::size_t next = 0;
    for (int hdu = 1; hdu <= count; ++hdu) {
      moveInput(hdu);
      HduPlan h;
      fits_get_hdu_type(in_, &h.type, &status);
      detail::throwIfFitsError(status, inputPath_, "cannot read " + hduName(hdu));
      if (hdu == 1) primaryKeys_ = keysOf(readCards(in_, inputPath_, hdu));
      if (h.type == BINARY_TBL) {
        char value[FLEN_VALUE] = {0};
        int s = 0;
        fits_read_key_str(in_, "EXTNAME", value, nullptr, &s);
        fits_clear_errmsg();
        if (s == 0) h.extname = value;
      }
      hdus_.push_back(h);
      if (h.extname == "LDAC_IMHEAD") {
        pendingImhead = hdu;
      } else if (h.extname == "LDAC_OBJECTS" || h.extname == "OBJECTS") {
        if (next >= parts_.size() || parts_[next].objectsHdu != hdu) {
          throw IoError(inputPath_ + ": " + h.extname + " table (" + hduName(hdu) +
                        ") was not in the catalog as it was read (the file changed?)");
        }
        hdus_.back().part = int(next);
        if (pendingImhead > 0) hdus_[std::size_t(pendingImhead - 1)].imheadOf = int(next);
        imheadHdu_.push_back(pendingImhead);
        pendingImhead = -1;
        ++next;
      }
    }
    if (next != parts_.size()) {
      throw IoError(inputPath_ + ": holds " + std::to_string(next) + " objects table(s), not the " +
                    std::to_string(parts_.size()) +
                    " it held when it was read (the file changed?)");
    }
  }

  // The provenance cards the LDAC_IMHEAD of part p gets (none when they all exist there).
  std::vector<std::string> imheadCards(std::size_t p) const {
    return newCards(appended_[p].cards, keysOf(parts_[p].imageHeader.cards));
  }

  void noteChecksum(int hdu) {
    if (hasKey(in_, "CHECKSUM")) checksummed_.push_back(hdu);
  }

  // LDAC_IMHEAD with `cards` added before END in its cell; the cell's TFORM and TDIM grow.
  void copyImhead(int hdu, const std::vector<std::string>& cards) {
    const std::string what = "LDAC_IMHEAD (" + hduName(hdu) + ")";
    const long long width = integerKey(in_, "NAXIS1", inputPath_, hdu);
    if (integerKey(in_, "TFIELDS", inputPath_, hdu) != 1 ||
        integerKey(in_, "NAXIS2", inputPath_, hdu) != 1 ||
        integerKey(in_, "PCOUNT", inputPath_, hdu) != 0 || width <= 0 ||
        width % std::int64_t(kCardBytes) != 0) {
      throw IoError(inputPath_ + ": " + what + " is not one cell of 80-character header cards");
    }
    std::string cell(std::size_t(width), ' ');
    int status = 0;
    fits_read_tblbytes(in_, 1, 1, width, reinterpret_cast<unsigned char*>(cell.data()), &status);
    detail::throwIfFitsError(status, inputPath_, "cannot read " + what);
    std::size_t end = std::string::npos;
    for (std::size_t at = 0; at + kCardBytes <= cell.size(); at += kCardBytes) {
      // "END" then blanks (some writers pad the cell's cards with NULs).
      if (cell.compare(at, 3, "END") == 0 &&
          cell.find_first_not_of(std::string(" \0", 2), at + 3) >= at + 8) {
        end = at;
        break;
      }
    }
    if (end == std::string::npos) {
      throw IoError(inputPath_ + ": " + what + " has no END card in its header cell");
    }
    std::string added;
    for (const std::string& c : cards) added += c;
    cell.insert(end, added);
    noteChecksum(hdu);

    writeCards(out_, readCards(in_, inputPath_, hdu), outputPath_);
    const long long newWidth = (long long)cell.size();
    setKey(out_, "NAXIS1", newWidth, outputPath_);
    setKey(out_, "TFORM1", std::to_string(newWidth) + "A", outputPath_);
    if (hasKey(in_, "TDIM1")) {
      setKey(out_, "TDIM1", "(80, " + std::to_string(newWidth / 80) + ")", outputPath_);
    }
    defineLayout(out_, outputPath_);
    fits_write_tblbytes(out_, 1, 1, newWidth, reinterpret_cast<unsigned char*>(cell.data()),
                        &status);
    detail::throwIfFitsError(status, outputPath_, "cannot write " + what);
  }

  // The objects table of part p: header with the new columns, then every row, original bytes
  // first and the new columns' bytes after them.
  void copyObjects(int hdu, std::size_t p) {
    const AppendedColumns& a = appended_[p];
    const InputCatalogPart& part = parts_[p];
    const long long rows = integerKey(in_, "NAXIS2", inputPath_, hdu);
    const long long width = integerKey(in_, "NAXIS1", inputPath_, hdu);
    const long long fields = integerKey(in_, "TFIELDS", inputPath_, hdu);
    if (rows != (long long)part.numbers.size() || fields != (long long)part.columnNames.size()) {
      throw IoError(where(p) + " no longer has the rows and columns it had when it was read " +
                    "(the file changed?)");
    }
    const std::vector<ColumnSpec> added = addedColumns(p);
    const std::vector<std::string> original = readCards(in_, inputPath_, hdu);
    std::vector<std::string> provenance;
    if (imheadHdu_[p] < 0) {
      std::set<std::string> present = keysOf(original);
      present.insert(primaryKeys_.begin(), primaryKeys_.end());
      provenance = newCards(a.cards, present);
    }
    int status = 0;
    if (added.empty() && provenance.empty()) {
      fits_copy_hdu(in_, out_, 0, &status);
      detail::throwIfFitsError(status, outputPath_, "cannot copy " + hduName(hdu));
      return;
    }
    if (integerKey(in_, "PCOUNT", inputPath_, hdu) != 0) {
      throw IoError(where(p) + " has a heap (variable-length arrays): not a SExtractor catalog, " +
                    "columns cannot be appended to it");
    }
    noteChecksum(hdu);

    writeCards(out_, objectsCards(original, int(fields), added, provenance), outputPath_);
    static const Table kNoTable;
    const detail::RowPacker packer(added.empty() ? kNoTable : *a.table, addedColumnIndices(p));
    const long long newWidth = width + (long long)packer.rowBytes();
    if (!added.empty()) {
      setKey(out_, "NAXIS1", newWidth, outputPath_);
      setKey(out_, "TFIELDS", fields + (long long)added.size(), outputPath_);
    }
    defineLayout(out_, outputPath_);
    if (rows == 0 || newWidth == 0) return;

    const long long rowsPerBlock = std::max<long long>(1, kBlockBytes / newWidth);
    std::vector<unsigned char> originalRows(std::size_t(std::min(rows, rowsPerBlock) * width));
    std::vector<unsigned char> block(std::size_t(std::min(rows, rowsPerBlock) * newWidth));
    for (long long r0 = 0; r0 < rows; r0 += rowsPerBlock) {
      const long long n = std::min(rowsPerBlock, rows - r0);
      if (width > 0) {
        fits_read_tblbytes(in_, r0 + 1, 1, n * width, originalRows.data(), &status);
        detail::throwIfFitsError(status, inputPath_, "cannot read the rows of " + hduName(hdu));
      }
      for (long long i = 0; i < n; ++i) {
        unsigned char* row = block.data() + i * newWidth;
        std::memcpy(row, originalRows.data() + i * width, std::size_t(width));
        if (!added.empty()) {
          const std::int64_t r = r0 + i;
          packer.pack(a.rows ? (*a.rows)[std::size_t(r)] : r, row + width);
        }
      }
      fits_write_tblbytes(out_, r0 + 1, 1, n * newWidth, block.data(), &status);
      detail::throwIfFitsError(status, outputPath_, "cannot write the rows of " + hduName(hdu));
    }
  }

  const std::string& inputPath_;
  const std::string& outputPath_;
  const std::vector<InputCatalogPart>& parts_;
  const std::vector<AppendedColumns>& appended_;
  fitsfile* in_ = nullptr;
  fitsfile* out_ = nullptr;
  std::vector<HduPlan> hdus_;
  std::vector<int> imheadHdu_;  // per part: its LDAC_IMHEAD HDU, or -1
  std::set<std::string> primaryKeys_;
  std::vector<int> checksummed_;
};

}  // namespace

void writeAppendedCatalog(const std::string& inputPath, const std::vector<InputCatalogPart>& parts,
                          const std::string& outputPath,
                          const std::vector<AppendedColumns>& appended) {
  Appender(inputPath, parts, outputPath, appended).run();
}

void writeAppendedCatalog(const std::string& inputPath, const std::string& outputPath,
                          const std::vector<const Table*>& appended) {
  const std::vector<InputCatalogPart> parts = readInputCatalog(inputPath);
  std::vector<AppendedColumns> columns;
  for (const Table* t : appended) {
    AppendedColumns a;
    a.table = t;
    columns.push_back(std::move(a));
  }
  writeAppendedCatalog(inputPath, parts, outputPath, columns);
}

}  // namespace octarc
