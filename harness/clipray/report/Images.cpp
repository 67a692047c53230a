// The pictures of a run: the four full-size PNGs (raster depth, ray depth, error heat map with its
// colour scale, mismatch mask), the two thumbnails index.html shows, and the enlarged crops around
// the largest unexplained clusters. Frames are stored bottom row first (GL's lower-left origin);
// PNG rows are top-down, so every image is flipped while it is drawn.
//
// Colours (docs/reconcile.md and index.html's legend show these):
//   raster_depth.png / ray_depth.png: window depth as grey, with ONE range [min, max] shared by
//     both images (every finite depth of either side), nearer = brighter: the nearest depth is
//     grey 255, the farthest grey 48 (under reversed-Z the larger depth is the nearer one). A
//     frame whose finite depths are all equal is mid-grey 128. Background (no hit, NaN) is dark
//     blue (20,30,70).
//   error_heatmap.png: r = |d_r - d_a| / predicted tolerance on a logarithmic scale, so that a
//     consistent run shows where it sits within its tolerance:
//     r <= 1 (within tolerance): s = log10(max(r, 1e-4)) + 4 in [0, 4], one decade per segment
//       of a viridis-like ramp, linear in s: (68,1,84) at 1e-4 and below (0 too), (59,82,139) at
//       1e-3, (33,145,140) at 0.01, (94,201,98) at 0.1, (253,231,37) at 1;
//     r > 1 (beyond tolerance): red (230,0,0) just above 1 rising linearly in log10(r) to white
//       (255,255,255) at 10 and beyond, so such pixels stand out against the ramp;
//     not compared (NaN): black (0,0,0). A 100 px strip on the right holds the scale: the title
//       "err/tol", the bar (1e-4 at its bottom, 10 at its top), tick marks and the labels 1e-4,
//       1e-3, 0.01, 0.1, 1, >=10, drawn with stb_easy_font at twice its size (glyphs 14 px high),
//       in white on grey (32,32,32). Images lower than 160 px are padded below with that grey so
//       the scale always fits.
//   mismatch.png, one colour per PixelClass:
//     Background            black        (0,0,0)
//     Agree                 mid grey     (128,128,128): apart from the black background
//     DepthBeyondTolerance  orange       (255,140,0)
//     CoverageEdgeAmbiguous yellow       (255,230,0)
//     CoverageUnexplained   red          (255,0,0)
//     IdDepthAmbiguous      cyan         (0,255,255)
//     IdEdgeAmbiguous       blue         (60,110,255)
//     IdUnexplained         magenta      (255,0,255)
//     InFrontOfNear         green        (40,200,90): agrees, drawn by depth clamp
//   thumb_mismatch.png / thumb_heatmap.png: the frame in blocks of f x f pixels, f the smallest
//     integer that brings both sides to 160 px or less; each thumbnail pixel is the most severe
//     class of its block (IdUnexplained, CoverageUnexplained, DepthBeyondTolerance,
//     IdEdgeAmbiguous, CoverageEdgeAmbiguous, IdDepthAmbiguous, InFrontOfNear, Agree, Background,
//     in that order), or the heat-map colour of its block's largest compared ratio, so a single
//     unexplained pixel of a 1080p frame still shows. In thumb_mismatch.png a block holding an
//     unexplained class (IdUnexplained, CoverageUnexplained, DepthBeyondTolerance) also paints the
//     eight thumbnail pixels around it where they show a less severe class: one unexplained pixel
//     is a 3 x 3 dot at thumbnail size. No scale strip.
//   cluster<k>.png: the mismatch colours of a 32 x 32 window around cluster k's representative
//     pixel (moved inside the frame; smaller frames whole), each pixel drawn 8 x 8, the
//     representative pixel outlined in white (255,255,255).

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "clipray/io/FastDeflate.hpp"
#include "clipray/report/Report.hpp"
#include "clipray/report/RunImages.hpp"
#include "clipray/util/Check.hpp"

// stb_image_write writes the PNGs, libdeflate compresses them (FastDeflate.hpp).
#define STB_IMAGE_WRITE_IMPLEMENTATION
#define STBIW_ZLIB_COMPRESS clipray::detail::zlibCompressForPng
#include <stb_easy_font.h>
#include <stb_image_write.h>

namespace clipray {
namespace {

constexpr int kFlatGrey = 128;

constexpr Rgb kPanel{32, 32, 32};
constexpr Rgb kText{255, 255, 255};
constexpr Rgb kBarBorder{160, 160, 160};
constexpr Rgb kNotCompared{0, 0, 0};
constexpr Rgb kOutline{255, 255, 255};
constexpr int kScaleWidth = 100;        // the strip added on the right of the heat map
constexpr int kMinHeatMapHeight = 160;  // the heat map is padded below to at least this height
constexpr int kLabelScale = 2;          // stb_easy_font glyphs drawn this many times their size

// The within-tolerance ramp, at ratio 1e-4, 1e-3, 0.01, 0.1 and 1: one decade per segment.
constexpr std::array<Rgb, 5> kRamp{{
    {68, 1, 84},
    {59, 82, 139},
    {33, 145, 140},
    {94, 201, 98},
    {253, 231, 37},
}};
constexpr Rgb kBeyondLow{230, 0, 0};       // just above 1
constexpr Rgb kBeyondHigh{255, 255, 255};  // at kHeatMapCeiling and above

// log10(kHeatMapFloor) and log10(kHeatMapCeiling): the scale's bar runs from the first at its
// bottom row to the second at its top row.
constexpr double kBarLow = -4.0, kBarHigh = 1.0;

std::uint8_t channel(double value) {
  return static_cast<std::uint8_t>(std::clamp(std::lround(value), 0L, 255L));
}

Rgb mix(Rgb a, Rgb b, double f) {
  return {channel(a.r + (b.r - a.r) * f), channel(a.g + (b.g - a.g) * f),
          channel(a.b + (b.b - a.b) * f)};
}

// How much a class tells a person, for the thumbnails: the most severe class of a block shows.
int severity(PixelClass value) {
  switch (value) {
    case PixelClass::Background:
      return 0;
    case PixelClass::Agree:
      return 1;
    case PixelClass::InFrontOfNear:
      return 2;
    case PixelClass::IdDepthAmbiguous:
      return 3;
    case PixelClass::CoverageEdgeAmbiguous:
      return 4;
    case PixelClass::IdEdgeAmbiguous:
      return 5;
    case PixelClass::DepthBeyondTolerance:
      return 6;
    case PixelClass::CoverageUnexplained:
      return 7;
    case PixelClass::IdUnexplained:
      return 8;
  }
  return 9;  // an out-of-range value: shown (in white), never hidden
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

// Draws text with its top-left corner at (x, y) (y from the top), each font unit a scale x scale
// block of pixels.
void drawText(Image& image, int x, int y, const std::string& text, Rgb colour, int scale) {
  std::string mutableText = text;  // stb_easy_font takes a char*
  std::vector<char> vertices(text.size() * 1024 + 64);
  const int quads = stb_easy_font_print(0.0f, 0.0f, mutableText.data(), nullptr, vertices.data(),
                                        static_cast<int>(vertices.size()));
  constexpr std::size_t kVertexBytes = 16;  // x, y, z as float, then RGBA8
  const auto at = [scale](float unit, int origin, bool up) {
    return origin + scale * static_cast<int>(up ? std::ceil(unit) : std::floor(unit));
  };
  for (int q = 0; q < quads; ++q) {
    float first[2], third[2];  // vertices 0 and 2 are opposite corners of the axis-aligned quad
    const std::size_t base = static_cast<std::size_t>(q) * 4 * kVertexBytes;
    std::memcpy(first, vertices.data() + base, sizeof first);
    std::memcpy(third, vertices.data() + base + 2 * kVertexBytes, sizeof third);
    image.fill(at(std::min(first[0], third[0]), x, false),
               at(std::min(first[1], third[1]), y, false),
               at(std::max(first[0], third[0]), x, true), at(std::max(first[1], third[1]), y, true),
               colour);
  }
}

// The colour scale strip right of the heat map, starting at column x0.
void drawScale(Image& image, int x0) {
  image.fill(x0, 0, image.width(), image.height(), kPanel);
  drawText(image, x0 + 6, 6, "err/tol", kText, kLabelScale);
  const int barLeft = x0 + 8, barRight = x0 + 24;          // [barLeft, barRight)
  const int barTop = 34, barBottom = image.height() - 12;  // inclusive rows; 10 at the top
  const int span = barBottom - barTop;
  image.fill(barLeft - 1, barTop - 1, barRight + 1, barBottom + 2, kBarBorder);
  for (int y = barTop; y <= barBottom; ++y) {
    const double decades =
        kBarLow + (kBarHigh - kBarLow) * static_cast<double>(barBottom - y) / span;
    image.fill(barLeft, y, barRight, y + 1, heatMapColour(std::pow(10.0, decades)));
  }
  struct Tick {
    double decades;
    const char* label;
  };
  constexpr std::array<Tick, 6> kTicks{
      {{-4.0, "1e-4"}, {-3.0, "1e-3"}, {-2.0, "0.01"}, {-1.0, "0.1"}, {0.0, "1"}, {1.0, ">=10"}}};
  for (const Tick& tick : kTicks) {
    const int y =
        barBottom -
        static_cast<int>(std::lround((tick.decades - kBarLow) / (kBarHigh - kBarLow) * span));
    image.fill(barRight + 1, y, barRight + 6, y + 1, kText);
    drawText(image, barRight + 10, y - 3 * kLabelScale, tick.label, kText, kLabelScale);
  }
}

template <typename Values>
void checkSize(const Values& values, std::size_t expected, const char* name) {
  CLIPRAY_CHECK(values.size() == expected, std::string("encodeRunImages: ") + name + " has " +
                                               std::to_string(values.size()) +
                                               " values, the viewport " + std::to_string(expected));
}

// The number of pixels, after checking that every per-pixel image of the comparison has them.
std::size_t checkedPixelCount(const PixelComparison& pixels) {
  const int width = pixels.viewport.width, height = pixels.viewport.height;
  constexpr int kMaxSide = 1 << 15;
  CLIPRAY_CHECK(
      width > 0 && height > 0 && width <= kMaxSide && height <= kMaxSide,
      "encodeRunImages: unusable viewport " + std::to_string(width) + "x" + std::to_string(height));
  const std::size_t count = static_cast<std::size_t>(width) * height;
  checkSize(pixels.rasterDepth, count, "rasterDepth");
  checkSize(pixels.analyticDepth, count, "analyticDepth");
  checkSize(pixels.toleranceRatio, count, "toleranceRatio");
  checkSize(pixels.classes, count, "classes");
  return count;
}

int thumbnailBlock(Viewport frame) {
  return std::max({1, (frame.width + kThumbnailSide - 1) / kThumbnailSide,
                   (frame.height + kThumbnailSide - 1) / kThumbnailSide});
}

}  // namespace

std::string encodeRgbPng(int width, int height, const std::vector<std::uint8_t>& rgb) {
  if (width < 1 || height < 1 ||
      rgb.size() != static_cast<std::size_t>(width) * static_cast<std::size_t>(height) * 3) {
    throw std::runtime_error("could not encode a " + std::to_string(width) + "x" +
                             std::to_string(height) + " PNG from " + std::to_string(rgb.size()) +
                             " bytes");
  }
  Image image(width, height, Rgb{});
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      const std::size_t i = (static_cast<std::size_t>(y) * width + x) * 3;
      image.set(x, y, {rgb[i], rgb[i + 1], rgb[i + 2]});
    }
  }
  return encodePng(image);
}

Rgb pixelClassColour(PixelClass value) {
  switch (value) {
    case PixelClass::Background:
      return {0, 0, 0};
    case PixelClass::Agree:
      return {128, 128, 128};
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
    case PixelClass::InFrontOfNear:
      return {40, 200, 90};
  }
  return {255, 255, 255};  // an out-of-range value: impossible to miss
}

Rgb heatMapColour(double ratio) {
  if (std::isnan(ratio)) return kNotCompared;
  if (ratio <= 1.0) {
    // 0 and negative ratios (log10 -inf or NaN) sit at the floor with the tiny ones.
    const double decades = ratio > kHeatMapFloor ? std::log10(ratio) : kBarLow;
    const double s = std::clamp(decades - kBarLow, 0.0, static_cast<double>(kRamp.size() - 1));
    const auto i = std::min(static_cast<std::size_t>(s), kRamp.size() - 2);
    return mix(kRamp[i], kRamp[i + 1], s - static_cast<double>(i));
  }
  return mix(kBeyondLow, kBeyondHigh, std::clamp(std::log10(ratio) / kBarHigh, 0.0, 1.0));
}

void encodeRunImages(RunRecord& run, const PixelComparison& pixels) {
  const std::size_t count = checkedPixelCount(pixels);
  const int width = pixels.viewport.width, height = pixels.viewport.height;
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
      heat.set(x, y, heatMapColour(pixels.toleranceRatio[i]));
      mismatch.set(x, y, pixelClassColour(pixels.classes[i]));
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

Viewport thumbnailSize(Viewport frame) {
  const int block = thumbnailBlock(frame);
  return {(frame.width + block - 1) / block, (frame.height + block - 1) / block};
}

void encodeThumbnails(RunRecord& run, const PixelComparison& pixels) {
  checkedPixelCount(pixels);
  const int width = pixels.viewport.width, height = pixels.viewport.height;
  const int block = thumbnailBlock(pixels.viewport);
  const Viewport thumb = thumbnailSize(pixels.viewport);
  const int thumbWidth = thumb.width, thumbHeight = thumb.height;
  // Per thumbnail pixel: the most severe class, and the largest compared ratio (NaN: none
  // compared). One pass over the frame a block's width at a time: every run of the default
  // reconcile pays for it.
  std::vector<int> worst(static_cast<std::size_t>(thumbWidth) * thumbHeight, 0);
  std::vector<float> largest(worst.size(), std::numeric_limits<float>::quiet_NaN());
  std::array<int, 256> rank{};
  for (int c = 0; c < 256; ++c)
    rank[static_cast<std::size_t>(c)] = severity(static_cast<PixelClass>(c));
  for (int row = 0; row < height; ++row) {
    const std::size_t thumbRow = static_cast<std::size_t>(row / block) * thumbWidth;
    const std::size_t frameRow = static_cast<std::size_t>(row) * width;
    for (int x0 = 0, t = 0; x0 < width; x0 += block, ++t) {
      int& worstRank = worst[thumbRow + static_cast<std::size_t>(t)];
      float& largestRatio = largest[thumbRow + static_cast<std::size_t>(t)];
      for (int x = x0; x < std::min(x0 + block, width); ++x) {
        worstRank =
            std::max(worstRank, rank[static_cast<std::uint8_t>(pixels.classes[frameRow + x])]);
        const float ratio = pixels.toleranceRatio[frameRow + x];
        if (!std::isnan(ratio) && !(largestRatio >= ratio)) largestRatio = ratio;
      }
    }
  }
  // The class of each severity rank.
  constexpr int kOutsideRank = 9;  // severity() of a value outside PixelClass
  std::array<PixelClass, kOutsideRank> ofRank{};
  ofRank.fill(PixelClass::Background);
  for (int c = 0; c < 256; ++c) {
    const int r = rank[static_cast<std::size_t>(c)];
    if (r < kOutsideRank) ofRank[static_cast<std::size_t>(r)] = static_cast<PixelClass>(c);
  }
  // An unexplained block (rank 6 and above: depth beyond tolerance, coverage and id
  // unexplained) spreads to its eight neighbours where they rank lower: a dot a person sees.
  constexpr int kUnexplainedRank = 6;
  std::vector<int> shown = worst;
  for (int row = 0; row < thumbHeight; ++row) {
    for (int x = 0; x < thumbWidth; ++x) {
      const int r = worst[static_cast<std::size_t>(row) * thumbWidth + x];
      if (r < kUnexplainedRank) continue;
      for (int ny = std::max(0, row - 1); ny <= std::min(thumbHeight - 1, row + 1); ++ny) {
        for (int nx = std::max(0, x - 1); nx <= std::min(thumbWidth - 1, x + 1); ++nx) {
          int& neighbour = shown[static_cast<std::size_t>(ny) * thumbWidth + nx];
          neighbour = std::max(neighbour, r);
        }
      }
    }
  }
  Image mismatch(thumbWidth, thumbHeight, {}), heat(thumbWidth, thumbHeight, {});
  for (int row = 0; row < thumbHeight; ++row) {
    for (int x = 0; x < thumbWidth; ++x) {
      const std::size_t t = static_cast<std::size_t>(row) * thumbWidth + x;
      const int r = shown[t];
      // A value outside PixelClass: white, as in mismatch.png.
      mismatch.set(
          x, thumbHeight - 1 - row,
          r < kOutsideRank ? pixelClassColour(ofRank[static_cast<std::size_t>(r)]) : kOutline);
      heat.set(x, thumbHeight - 1 - row, heatMapColour(largest[t]));
    }
  }
  const std::string folder = runFolderName(run) + "/";
  run.images.push_back({folder + "thumb_mismatch.png", encodePng(mismatch)});
  run.images.push_back({folder + "thumb_heatmap.png", encodePng(heat)});
}

CropWindow clusterCropWindow(const MismatchCluster& cluster, Viewport viewport) {
  CropWindow window;
  window.width = std::min(kCropSide, viewport.width);
  window.height = std::min(kCropSide, viewport.height);
  window.x = std::clamp(cluster.x - kCropSide / 2, 0, viewport.width - window.width);
  window.y = std::clamp(imageY(cluster.y, viewport.height) - kCropSide / 2, 0,
                        viewport.height - window.height);
  return window;
}

void encodeClusterCrops(RunRecord& run, const PixelComparison& pixels) {
  checkedPixelCount(pixels);
  const Viewport viewport = pixels.viewport;
  const std::string folder = runFolderName(run) + "/";
  for (std::size_t k = 0; k < run.clusters.largest.size(); ++k) {
    const MismatchCluster& cluster = run.clusters.largest[k];
    const CropWindow window = clusterCropWindow(cluster, viewport);
    Image crop(window.width * kCropScale, window.height * kCropScale, {});
    for (int y = 0; y < window.height; ++y) {
      const int row = viewport.height - 1 - (window.y + y);  // the frame row of image row y
      for (int x = 0; x < window.width; ++x) {
        const std::size_t i = static_cast<std::size_t>(row) * viewport.width + (window.x + x);
        crop.fill(x * kCropScale, y * kCropScale, (x + 1) * kCropScale, (y + 1) * kCropScale,
                  pixelClassColour(pixels.classes[i]));
      }
    }
    // A one-pixel frame just inside the representative pixel's cell.
    const int left = (cluster.x - window.x) * kCropScale;
    const int top = (imageY(cluster.y, viewport.height) - window.y) * kCropScale;
    crop.fill(left, top, left + kCropScale, top + 1, kOutline);
    crop.fill(left, top + kCropScale - 1, left + kCropScale, top + kCropScale, kOutline);
    crop.fill(left, top, left + 1, top + kCropScale, kOutline);
    crop.fill(left + kCropScale - 1, top, left + kCropScale, top + kCropScale, kOutline);
    run.images.push_back({folder + "cluster" + std::to_string(k + 1) + ".png", encodePng(crop)});
  }
}

}  // namespace clipray
