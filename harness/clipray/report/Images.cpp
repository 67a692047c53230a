// The four PNGs of a run: raster depth, ray depth, error heat map (with its colour scale) and the
// mismatch mask. Frames are stored bottom row first (GL's lower-left origin); PNG rows are
// top-down, so every image is flipped while it is drawn.
//
// Colours (the README quotes these):
//   raster_depth.png / ray_depth.png: window depth as grey, with ONE range [min, max] shared by
//   both
//     images (every finite depth of either side), nearer = brighter: the nearest depth is grey 255,
//     the farthest grey 48 (under reversed-Z the larger depth is the nearer one). A frame whose
//     finite depths are all equal is mid-grey 128. Background (no hit, NaN) is dark blue
//     (20,30,70).
//   error_heatmap.png: |d_r - d_a| / predicted tolerance on the fixed range [0, 2]:
//     0 .. 1 (within tolerance): a viridis-like ramp, (68,1,84) at 0, (59,82,139) at 0.25,
//       (33,145,140) at 0.5, (94,201,98) at 0.75, (253,231,37) at 1;
//     above 1 (beyond tolerance): red (230,0,0) just above 1 rising to white (255,255,255) at 2 and
//       beyond, so such pixels stand out against the ramp;
//     not compared (NaN): black (0,0,0). A 70 px strip on the right holds the scale: the title
//     "err/tol", the bar, tick marks and the labels 0, 0.5, 1, 1.5, >=2 in white on grey
//     (32,32,32). Images lower than 120 px are padded below with that grey so the scale always
//     fits.
//   mismatch.png, one colour per PixelClass:
//     Background            black        (0,0,0)
//     Agree                 dark grey    (60,60,60)
//     DepthBeyondTolerance  orange       (255,140,0)
//     CoverageEdgeAmbiguous yellow       (255,230,0)
//     CoverageUnexplained   red          (255,0,0)
//     IdDepthAmbiguous      cyan         (0,255,255)
//     IdEdgeAmbiguous       blue         (60,110,255)
//     IdUnexplained         magenta      (255,0,255)

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "clipray/report/FastDeflate.hpp"
#include "clipray/report/Report.hpp"

// stb_image_write writes the PNGs, libdeflate compresses them (FastDeflate.hpp).
#define STB_IMAGE_WRITE_IMPLEMENTATION
#define STBIW_ZLIB_COMPRESS clipray::detail::zlibCompressForPng
#include <stb_easy_font.h>
#include <stb_image_write.h>

namespace clipray {
namespace {

struct Rgb {
  std::uint8_t r = 0, g = 0, b = 0;
};

constexpr Rgb kDepthBackground{20, 30, 70};
constexpr int kFarGrey = 48;
constexpr int kNearGrey = 255;
constexpr int kFlatGrey = 128;

constexpr Rgb kPanel{32, 32, 32};
constexpr Rgb kText{255, 255, 255};
constexpr Rgb kBarBorder{160, 160, 160};
constexpr Rgb kNotCompared{0, 0, 0};
constexpr int kScaleWidth = 70;         // the strip added on the right of the heat map
constexpr int kMinHeatMapHeight = 120;  // the heat map is padded below to at least this height
constexpr double kHeatMapMaxRatio = 2.0;

// The within-tolerance ramp, at ratio 0, 0.25, 0.5, 0.75 and 1.
constexpr std::array<Rgb, 5> kRamp{{
    {68, 1, 84},
    {59, 82, 139},
    {33, 145, 140},
    {94, 201, 98},
    {253, 231, 37},
}};
constexpr Rgb kBeyondLow{230, 0, 0};       // just above 1
constexpr Rgb kBeyondHigh{255, 255, 255};  // at 2 and above

Rgb classColour(PixelClass value) {
  switch (value) {
    case PixelClass::Background:
      return {0, 0, 0};
    case PixelClass::Agree:
      return {60, 60, 60};
    case PixelClass::DepthBeyondTolerance:
      return {255, 140, 0};
    case PixelClass::CoverageEdgeAmbiguous:
      return {255, 230, 0};
    case PixelClass::CoverageUnexplained:
      return {255, 0, 0};
    case PixelClass::IdDepthAmbiguous:
      return {0, 255, 255};
    case PixelClass::IdEdgeAmbiguous:
      return {60, 110, 255};
    case PixelClass::IdUnexplained:
      return {255, 0, 255};
  }
  return {255, 255, 255};  // an out-of-range value: impossible to miss
}

std::uint8_t channel(double value) {
  return static_cast<std::uint8_t>(std::clamp(std::lround(value), 0L, 255L));
}

Rgb mix(Rgb a, Rgb b, double f) {
  return {channel(a.r + (b.r - a.r) * f), channel(a.g + (b.g - a.g) * f),
          channel(a.b + (b.b - a.b) * f)};
}

Rgb heatColour(double ratio) {
  if (std::isnan(ratio)) return kNotCompared;
  const double r = std::clamp(ratio, 0.0, kHeatMapMaxRatio);
  if (r <= 1.0) {
    const double s = r * static_cast<double>(kRamp.size() - 1);
    const auto i = std::min(static_cast<std::size_t>(s), kRamp.size() - 2);
    return mix(kRamp[i], kRamp[i + 1], s - static_cast<double>(i));
  }
  return mix(kBeyondLow, kBeyondHigh, (r - 1.0) / (kHeatMapMaxRatio - 1.0));
}

// An RGB image with top-down rows, as PNG wants them.
class Image {
 public:
  Image(int width, int height, Rgb fill)
      : width_(width), height_(height), data_(static_cast<std::size_t>(width) * height * 3) {
    for (std::size_t i = 0; i < data_.size(); i += 3) {
      data_[i] = fill.r;
      data_[i + 1] = fill.g;
      data_[i + 2] = fill.b;
    }
  }
  int width() const { return width_; }
  int height() const { return height_; }
  // (x, y) with y counted from the top; outside the image: ignored.
  void set(int x, int y, Rgb c) {
    if (x < 0 || y < 0 || x >= width_ || y >= height_) return;
    const std::size_t i = (static_cast<std::size_t>(y) * width_ + x) * 3;
    data_[i] = c.r;
    data_[i + 1] = c.g;
    data_[i + 2] = c.b;
  }
  // [x0, x1) x [y0, y1), clipped to the image.
  void fill(int x0, int y0, int x1, int y1, Rgb c) {
    for (int y = std::max(y0, 0); y < std::min(y1, height_); ++y)
      for (int x = std::max(x0, 0); x < std::min(x1, width_); ++x) set(x, y, c);
  }
  const std::uint8_t* data() const { return data_.data(); }

 private:
  int width_, height_;
  std::vector<std::uint8_t> data_;
};

void appendBytes(void* context, void* data, int size) {
  if (size > 0) static_cast<std::string*>(context)->append(static_cast<const char*>(data), size);
}

std::string encodePng(const Image& image) {
  std::string png;
  if (stbi_write_png_to_func(&appendBytes, &png, image.width(), image.height(), 3, image.data(),
                             image.width() * 3) == 0)
    throw std::runtime_error("could not encode a " + std::to_string(image.width()) + "x" +
                             std::to_string(image.height()) + " PNG");
  return png;
}

// Draws text with its top-left corner at (x, y) (y from the top), one font unit per pixel.
void drawText(Image& image, int x, int y, const std::string& text, Rgb colour) {
  std::string mutableText = text;  // stb_easy_font takes a char*
  std::vector<char> vertices(text.size() * 1024 + 64);
  const int quads =
      stb_easy_font_print(static_cast<float>(x), static_cast<float>(y), mutableText.data(), nullptr,
                          vertices.data(), static_cast<int>(vertices.size()));
  constexpr std::size_t kVertexBytes = 16;  // x, y, z as float, then RGBA8
  for (int q = 0; q < quads; ++q) {
    float first[2], third[2];  // vertices 0 and 2 are opposite corners of the axis-aligned quad
    const std::size_t base = static_cast<std::size_t>(q) * 4 * kVertexBytes;
    std::memcpy(first, vertices.data() + base, sizeof first);
    std::memcpy(third, vertices.data() + base + 2 * kVertexBytes, sizeof third);
    image.fill(static_cast<int>(std::floor(std::min(first[0], third[0]))),
               static_cast<int>(std::floor(std::min(first[1], third[1]))),
               static_cast<int>(std::ceil(std::max(first[0], third[0]))),
               static_cast<int>(std::ceil(std::max(first[1], third[1]))), colour);
  }
}

// The colour scale strip right of the heat map, starting at column x0.
void drawScale(Image& image, int x0) {
  image.fill(x0, 0, image.width(), image.height(), kPanel);
  drawText(image, x0 + 4, 4, "err/tol", kText);
  const int barLeft = x0 + 8, barRight = x0 + 20;          // [barLeft, barRight)
  const int barTop = 20, barBottom = image.height() - 10;  // inclusive rows; v = 2 at the top
  const int span = barBottom - barTop;
  image.fill(barLeft - 1, barTop - 1, barRight + 1, barBottom + 2, kBarBorder);
  for (int y = barTop; y <= barBottom; ++y) {
    const double v = kHeatMapMaxRatio * static_cast<double>(barBottom - y) / span;
    image.fill(barLeft, y, barRight, y + 1, heatColour(v));
  }
  struct Tick {
    double value;
    const char* label;
  };
  constexpr std::array<Tick, 5> kTicks{
      {{0.0, "0"}, {0.5, "0.5"}, {1.0, "1"}, {1.5, "1.5"}, {2.0, ">=2"}}};
  for (const Tick& tick : kTicks) {
    const int y = barBottom - static_cast<int>(std::lround(tick.value / kHeatMapMaxRatio * span));
    image.fill(barRight + 1, y, barRight + 5, y + 1, kText);
    drawText(image, barRight + 8, y - 3, tick.label, kText);
  }
}

template <typename Values>
void checkSize(const Values& values, std::size_t expected, const char* name) {
  if (values.size() != expected)
    throw std::invalid_argument(std::string("encodeRunImages: ") + name + " has " +
                                std::to_string(values.size()) + " values, the viewport " +
                                std::to_string(expected));
}

}  // namespace

void encodeRunImages(RunRecord& run, const PixelComparison& pixels) {
  const int width = pixels.viewport.width, height = pixels.viewport.height;
  constexpr int kMaxSide = 1 << 15;
  if (width <= 0 || height <= 0 || width > kMaxSide || height > kMaxSide)
    throw std::invalid_argument("encodeRunImages: unusable viewport " + std::to_string(width) +
                                "x" + std::to_string(height));
  const std::size_t count = static_cast<std::size_t>(width) * height;
  checkSize(pixels.rasterDepth, count, "rasterDepth");
  checkSize(pixels.analyticDepth, count, "analyticDepth");
  checkSize(pixels.toleranceRatio, count, "toleranceRatio");
  checkSize(pixels.classes, count, "classes");
  // Frame pixel (x, row) with row 0 at the bottom lies on PNG row height - 1 - row.
  const auto index = [width](int x, int row) { return static_cast<std::size_t>(row) * width + x; };

  // Depth: one range over both sides.
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (std::size_t i = 0; i < count; ++i) {
    for (const double d : {static_cast<double>(pixels.rasterDepth[i]), pixels.analyticDepth[i]}) {
      if (!std::isfinite(d)) continue;
      lo = std::min(lo, d);
      hi = std::max(hi, d);
    }
  }
  const double range = hi - lo;
  const bool flat = !(range > 0.0) || !std::isfinite(range);
  const bool reversed = run.convention.reversed;
  const auto depthColour = [&](double d) -> Rgb {
    if (!std::isfinite(d)) return kDepthBackground;
    if (flat) return {kFlatGrey, kFlatGrey, kFlatGrey};
    const double t = std::clamp((d - lo) / range, 0.0, 1.0);
    const double nearness = reversed ? t : 1.0 - t;
    const std::uint8_t g = channel(kFarGrey + (kNearGrey - kFarGrey) * nearness);
    return {g, g, g};
  };

  Image rasterDepth(width, height, kDepthBackground), rayDepth(width, height, kDepthBackground);
  Image mismatch(width, height, {});
  const int heatHeight = std::max(height, kMinHeatMapHeight);
  Image heat(width + kScaleWidth, heatHeight, kPanel);
  for (int row = 0; row < height; ++row) {
    const int y = height - 1 - row;
    for (int x = 0; x < width; ++x) {
      const std::size_t i = index(x, row);
      rasterDepth.set(x, y, depthColour(pixels.rasterDepth[i]));
      rayDepth.set(x, y, depthColour(pixels.analyticDepth[i]));
      heat.set(x, y, heatColour(pixels.toleranceRatio[i]));
      mismatch.set(x, y, classColour(pixels.classes[i]));
    }
  }
  drawScale(heat, width);

  const std::string folder = runFolderName(run) + "/";
  run.images.clear();
  run.images.push_back({folder + "raster_depth.png", encodePng(rasterDepth)});
  run.images.push_back({folder + "ray_depth.png", encodePng(rayDepth)});
  run.images.push_back({folder + "error_heatmap.png", encodePng(heat)});
  run.images.push_back({folder + "mismatch.png", encodePng(mismatch)});
}

}  // namespace clipray
