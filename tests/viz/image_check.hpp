#pragma once
// Reading figures back in the viz tests: file bytes, the PNG header's size, decoded pixels,
// and what a PDF or SVG file must start with.

#include <cairo/cairo.h>  // only to read pixels back; barn_viz links Cairo

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <memory>
#include <string>
#include <vector>

#include <gtest/gtest.h>

namespace barn::viz::test {

namespace fs = std::filesystem;

inline std::vector<unsigned char> readBytes(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

inline std::string readText(const fs::path& path) {
  const std::vector<unsigned char> bytes = readBytes(path);
  return {bytes.begin(), bytes.end()};
}

inline std::uint32_t bigEndian32(const std::vector<unsigned char>& bytes, std::size_t offset) {
  return (std::uint32_t{bytes[offset]} << 24) | (std::uint32_t{bytes[offset + 1]} << 16) |
         (std::uint32_t{bytes[offset + 2]} << 8) | std::uint32_t{bytes[offset + 3]};
}

struct Size {
  long width;   // [px]
  long height;  // [px]
};

/// Checks the PNG signature and returns the IHDR size (bytes 16 and 20, big-endian).
inline Size pngSize(const fs::path& png) {
  const std::vector<unsigned char> bytes = readBytes(png);
  const std::array<unsigned char, 8> signature = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n'};
  EXPECT_GE(bytes.size(), 24u) << png;
  if (bytes.size() < 24) return {0, 0};
  EXPECT_TRUE(std::equal(signature.begin(), signature.end(), bytes.begin())) << png;
  EXPECT_EQ(std::string(bytes.begin() + 12, bytes.begin() + 16), "IHDR");
  return {static_cast<long>(bigEndian32(bytes, 16)), static_cast<long>(bigEndian32(bytes, 20))};
}

/// Checks that `file` is a complete figure in the format its extension names: the PNG
/// signature, "%PDF-" ... "%%EOF", or an SVG document ("<?xml" then "<svg", closed by
/// "</svg>"); at least `min_bytes` long; no ".partial" temporary left beside it.
inline void expectFigureFile(const fs::path& file, std::size_t min_bytes) {
  ASSERT_TRUE(fs::exists(file)) << file;
  const std::string text = readText(file);
  EXPECT_GE(text.size(), min_bytes) << file << " is too small to hold a figure";
  const std::string extension = file.extension().string();
  if (extension == ".png") {
    EXPECT_EQ(text.substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8)) << file;
  } else if (extension == ".pdf") {
    EXPECT_EQ(text.substr(0, 5), "%PDF-") << file;
    EXPECT_NE(text.find("%%EOF", text.size() > 32 ? text.size() - 32 : 0), std::string::npos) << file;
  } else {
    EXPECT_TRUE(text.rfind("<?xml", 0) == 0 || text.rfind("<svg", 0) == 0) << file;
    EXPECT_NE(text.find("<svg"), std::string::npos) << file;
    EXPECT_NE(text.find("</svg>"), std::string::npos) << file;
  }
  EXPECT_FALSE(fs::exists(fs::path(file.string() + ".partial"))) << file;
}

/// The width and height an SVG states in its root element ("123pt"), 0 if absent.
inline Size svgSize(const fs::path& svg) {
  const std::string text = readText(svg);
  const auto attribute = [&](const std::string& name) -> long {
    const std::size_t at = text.find(" " + name + "=\"");
    if (at == std::string::npos) return 0;
    return std::lround(std::stod(text.substr(at + name.size() + 3)));
  };
  return {attribute("width"), attribute("height")};
}

struct Pixel {
  int r, g, b;  // [0, 255]
};

/// The decoded image, for pixel checks.
class Image {
 public:
  explicit Image(const fs::path& png)
      : surface_(cairo_image_surface_create_from_png(png.string().c_str()), &cairo_surface_destroy) {}
  bool ok() const { return cairo_surface_status(surface_.get()) == CAIRO_STATUS_SUCCESS; }
  int width() const { return cairo_image_surface_get_width(surface_.get()); }
  int height() const { return cairo_image_surface_get_height(surface_.get()); }
  Pixel at(int x, int y) const {
    const unsigned char* row =
        cairo_image_surface_get_data(surface_.get()) + y * cairo_image_surface_get_stride(surface_.get());
    std::uint32_t argb = 0;
    std::memcpy(&argb, row + 4 * x, 4);  // native-endian 0xAARRGGBB, opaque here
    return {static_cast<int>((argb >> 16) & 0xff), static_cast<int>((argb >> 8) & 0xff),
            static_cast<int>(argb & 0xff)};
  }
  /// True if some pixel of the rectangle [x0, x1) x [y0, y1) satisfies `test`.
  bool any(int x0, int y0, int x1, int y1, const std::function<bool(Pixel)>& test) const {
    for (int y = std::max(0, y0); y < std::min(y1, height()); ++y) {
      for (int x = std::max(0, x0); x < std::min(x1, width()); ++x) {
        if (test(at(x, y))) return true;
      }
    }
    return false;
  }

 private:
  std::unique_ptr<cairo_surface_t, decltype(&cairo_surface_destroy)> surface_;
};

/// Matches an 8-bit colour against one given in [0, 1], within rounding.
inline ::testing::AssertionResult near(Pixel p, double r, double g, double b) {
  const auto close = [](int v, double want) { return std::abs(v - want * 255.0) <= 2.0; };
  if (close(p.r, r) && close(p.g, g) && close(p.b, b)) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "pixel (" << p.r << ", " << p.g << ", " << p.b << ") is not ("
                                       << r * 255 << ", " << g * 255 << ", " << b * 255 << ")";
}

/// A test predicate: the pixel is within rounding of the colour (r, g, b) in [0, 1].
inline std::function<bool(Pixel)> isColour(double r, double g, double b) {
  return [=](Pixel p) { return static_cast<bool>(near(p, r, g, b)); };
}

}  // namespace barn::viz::test
