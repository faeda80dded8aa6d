#include "octarc/plot/Stamp.h"

#include <cairo.h>
#include <png.h>

#include <algorithm>
#include <cmath>
#include <csetjmp>
#include <cstdint>
#include <cstdio>
#include <memory>
#include <numbers>
#include <vector>

#include "octarc/core/Error.h"

namespace octarc {

namespace {

// Softness of the asinh stretch: the faint end is stretched about this much more than the top.
constexpr double kStretch = 12.0;
// Of the PNG side, around the image: room for a title and subtitle, or a thin frame without.
constexpr double kTextMarginFraction = 0.07;
constexpr double kFrameMarginFraction = 0.015;

double stretched(double v, double lo, double hi) {
  if (!std::isfinite(v)) return 0.0;
  const double t = std::clamp((v - lo) / (hi - lo), 0.0, 1.0);
  return std::asinh(kStretch * t) / std::asinh(kStretch);
}

struct SurfaceDeleter {
  void operator()(cairo_surface_t* s) const { cairo_surface_destroy(s); }
};
struct ContextDeleter {
  void operator()(cairo_t* c) const { cairo_destroy(c); }
};
using Surface = std::unique_ptr<cairo_surface_t, SurfaceDeleter>;
using Context = std::unique_ptr<cairo_t, ContextDeleter>;

// Image pixel coordinates (1-based, +y up) to PNG coordinates (+y down).
struct Frame {
  double x0, y0;      // image coordinates of the image area's lower-left corner
  double pixPerUnit;  // PNG pixels per image pixel
  double left, top, size;
  double x(double xFits) const { return left + (xFits - x0) * pixPerUnit; }
  double y(double yFits) const { return top + size - (yFits - y0) * pixPerUnit; }
};

void centredText(cairo_t* cr, double x, double y, const std::string& text) {
  cairo_text_extents_t e;
  cairo_text_extents(cr, text.c_str(), &e);
  cairo_move_to(cr, x - 0.5 * e.width - e.x_bearing, y - 0.5 * e.height - e.y_bearing);
  cairo_show_text(cr, text.c_str());
}

// An arrow from (x, y) along the unit vector (ux, uy) of the image (+y up), `length` PNG pixels.
void drawArrow(cairo_t* cr, double x, double y, double ux, double uy, double length,
               const char* label) {
  const double dx = ux * length, dy = -uy * length;  // PNG +y is down
  cairo_move_to(cr, x, y);
  cairo_line_to(cr, x + dx, y + dy);
  const double head = 0.25 * length, c = 0.87, s = 0.5;
  const double hx = -dx / length * head, hy = -dy / length * head;
  cairo_move_to(cr, x + dx + c * hx - s * hy, y + dy + s * hx + c * hy);
  cairo_line_to(cr, x + dx, y + dy);
  cairo_line_to(cr, x + dx + c * hx + s * hy, y + dy - s * hx + c * hy);
  cairo_stroke(cr);
  centredText(cr, x + 1.35 * dx, y + 1.35 * dy, label);
}

// Writes an RGB24 cairo surface as an 8-bit RGB PNG with libpng at zlib's fastest level:
// cairo's own writer uses the default level, which made PNG compression most of a search's
// time. On failure the partly written file is removed.
void writePng(cairo_surface_t* surface, const std::string& path) {
  const int width = cairo_image_surface_get_width(surface);
  const int height = cairo_image_surface_get_height(surface);
  const int stride = cairo_image_surface_get_stride(surface);
  const unsigned char* data = cairo_image_surface_get_data(surface);
  std::FILE* file = std::fopen(path.c_str(), "wb");
  if (file == nullptr) throw IoError(path + ": cannot create the stamp");
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  png_infop info = png != nullptr ? png_create_info_struct(png) : nullptr;
  std::vector<png_byte> row(std::size_t(width) * 3);
  bool ok = png != nullptr && info != nullptr;
  if (ok) {
    if (setjmp(png_jmpbuf(png))) {  // libpng's error path lands here
      ok = false;
    } else {
      png_init_io(png, file);
      png_set_compression_level(png, 1);
      // One filter (left neighbour) instead of libpng's per-row trial of all five: the stamp's
      // pixels repeat along rows, which it turns into runs of zeros.
      png_set_filter(png, PNG_FILTER_TYPE_BASE, PNG_FILTER_SUB);
      png_set_IHDR(png, info, png_uint_32(width), png_uint_32(height), 8, PNG_COLOR_TYPE_RGB,
                   PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
      png_write_info(png, info);
      for (int y = 0; y < height; ++y) {
        const auto* pixel = reinterpret_cast<const std::uint32_t*>(data + std::size_t(y) * stride);
        for (int x = 0; x < width; ++x) {
          row[std::size_t(x) * 3 + 0] = png_byte((pixel[x] >> 16) & 0xff);
          row[std::size_t(x) * 3 + 1] = png_byte((pixel[x] >> 8) & 0xff);
          row[std::size_t(x) * 3 + 2] = png_byte(pixel[x] & 0xff);
        }
        png_write_row(png, row.data());
      }
      png_write_end(png, nullptr);
    }
  }
  png_destroy_write_struct(png != nullptr ? &png : nullptr, info != nullptr ? &info : nullptr);
  ok = std::fclose(file) == 0 && ok;
  if (!ok) {
    std::remove(path.c_str());
    throw IoError(path + ": cannot write the stamp");
  }
}

}  // namespace

void writeStampPng(const std::string& path, const Stamp& stamp) {
  const std::int64_t nx = stamp.pixels.width(), ny = stamp.pixels.height();
  if (nx <= 0 || ny <= 0) throw ConfigError("stamp " + stamp.title + ": empty cut-out");
  const bool colour = !stamp.rgbPixels.empty();
  if (colour && (stamp.rgbPixels.width() != nx || stamp.rgbPixels.height() != ny)) {
    throw ConfigError("stamp " + stamp.title + ": the colours are not the cut-out's size");
  }
  if (!colour && !(stamp.displayHighAdu > stamp.displayLowAdu)) {
    throw ConfigError("stamp " + stamp.title + ": the display range is not increasing");
  }
  // The grey levels (or the colours), top row first as a PNG holds them.
  Surface image(cairo_image_surface_create(CAIRO_FORMAT_RGB24, int(nx), int(ny)));
  if (cairo_surface_status(image.get()) != CAIRO_STATUS_SUCCESS) {
    throw IoError(path + ": cannot draw the stamp (" +
                  cairo_status_to_string(cairo_surface_status(image.get())) + ")");
  }
  const int stride = cairo_image_surface_get_stride(image.get());
  unsigned char* data = cairo_image_surface_get_data(image.get());
  for (std::int64_t j = 0; j < ny; ++j) {
    auto* row = reinterpret_cast<std::uint32_t*>(data + std::size_t(ny - 1 - j) * stride);
    for (std::int64_t i = 0; i < nx; ++i) {
      if (colour) {
        row[i] = stamp.rgbPixels(i, j) & 0xffffffu;
        continue;
      }
      const auto g = std::uint32_t(std::lround(
          255.0 * stretched(stamp.pixels(i, j), stamp.displayLowAdu, stamp.displayHighAdu)));
      row[i] = (g << 16) | (g << 8) | g;
    }
  }
  cairo_surface_mark_dirty(image.get());

  const double side = double(stamp.sizePix);
  Surface png(cairo_image_surface_create(CAIRO_FORMAT_RGB24, stamp.sizePix, stamp.sizePix));
  if (cairo_surface_status(png.get()) != CAIRO_STATUS_SUCCESS) {
    throw IoError(path + ": cannot draw the stamp (" +
                  cairo_status_to_string(cairo_surface_status(png.get())) + ")");
  }
  Context owner(cairo_create(png.get()));
  cairo_t* cr = owner.get();
  cairo_set_source_rgb(cr, 0.094, 0.094, 0.094);
  cairo_paint(cr);
  const bool text = !stamp.title.empty() || !stamp.subtitle.empty();
  const double margin = (text ? kTextMarginFraction : kFrameMarginFraction) * side;
  const double area = side - 2.0 * margin;
  const double extent = double(std::max(nx, ny));
  const Frame f{
      stamp.xFirstFits - 0.5, stamp.yFirstFits - 0.5, area / extent, margin, margin, area};
  // The cut-out, each pixel a square (no interpolation: the inspector sees the real pixels).
  cairo_save(cr);
  cairo_translate(cr, f.left, f.top + area - double(ny) * f.pixPerUnit);
  cairo_scale(cr, f.pixPerUnit, f.pixPerUnit);
  cairo_set_source_surface(cr, image.get(), 0, 0);
  cairo_pattern_set_filter(cairo_get_source(cr), CAIRO_FILTER_NEAREST);
  cairo_rectangle(cr, 0, 0, double(nx), double(ny));
  cairo_fill(cr);
  cairo_restore(cr);

  cairo_select_font_face(cr, "sans-serif", CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);
  cairo_set_font_size(cr, std::max(9.0, 0.032 * side));
  cairo_set_line_width(cr, std::max(1.0, 0.004 * side));
  for (const StampMark& m : stamp.marks) {
    cairo_set_source_rgb(cr, m.red / 255.0, m.green / 255.0, m.blue / 255.0);
    const double a = m.semiAxis1Pix * f.pixPerUnit;
    const double b = (m.ellipse ? m.semiAxis2Pix : m.semiAxis1Pix) * f.pixPerUnit;
    if (a > 0 && b > 0) {
      cairo_save(cr);
      cairo_translate(cr, f.x(m.xFits), f.y(m.yFits));
      cairo_rotate(cr, -m.angleRad);  // counter-clockwise on the sky image is clockwise in PNG y
      cairo_scale(cr, a, b);
      cairo_new_sub_path(cr);
      cairo_arc(cr, 0, 0, 1, 0, 2 * std::numbers::pi);
      cairo_restore(cr);
      cairo_stroke(cr);
    }
    if (!m.label.empty()) {
      cairo_move_to(cr, f.x(m.xFits) + a + 3, f.y(m.yFits) + 4);
      cairo_show_text(cr, m.label.c_str());
    }
  }
  cairo_set_source_rgb(cr, 1.0, 0.86, 0.24);
  if (stamp.hasSkyDirections) {
    const double length = 0.13 * area;
    const double ax = f.left + 0.82 * area, ay = f.top + 0.22 * area;
    drawArrow(cr, ax, ay, stamp.northX, stamp.northY, length, "N");
    drawArrow(cr, ax, ay, stamp.eastX, stamp.eastY, length, "E");
  }
  if (stamp.pixelScaleArcsec > 0 && stamp.scaleBarArcsec > 0) {
    const double bar = stamp.scaleBarArcsec / stamp.pixelScaleArcsec * f.pixPerUnit;
    const double bx = f.left + 0.06 * area, by = f.top + 0.94 * area;
    cairo_save(cr);
    cairo_set_line_width(cr, std::max(2.0, 0.008 * side));
    cairo_move_to(cr, bx, by);
    cairo_line_to(cr, bx + bar, by);
    cairo_stroke(cr);
    cairo_restore(cr);
    char label[32];
    std::snprintf(label, sizeof label, "%g\"", stamp.scaleBarArcsec);
    centredText(cr, bx + 0.5 * bar, by - 0.04 * area, label);
  }
  cairo_set_source_rgb(cr, 0.92, 0.92, 0.92);
  if (!stamp.title.empty()) centredText(cr, 0.5 * side, 0.5 * margin, stamp.title);
  if (!stamp.subtitle.empty()) centredText(cr, 0.5 * side, side - 0.5 * margin, stamp.subtitle);
  cairo_surface_flush(png.get());
  writePng(png.get(), path);
}

}  // namespace octarc
