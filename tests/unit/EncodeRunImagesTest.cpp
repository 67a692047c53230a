// The four PNGs of a run (encodeRunImages): their folder and names, the mismatch mask's colours,
// the depth images' shared range, the tolerance heat map, and frame sizes at the extremes.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <ostream>
#include <string>
#include <vector>

#define STB_IMAGE_STATIC
#define STB_IMAGE_IMPLEMENTATION
#include "support/DecodedPng.hpp"

#include "clipray/report/Report.hpp"
#include "clipray/util/Check.hpp"
#include "support/ReportSamples.hpp"

namespace clipray {
namespace {

using testing::imageNamed;
using testing::sampleGl;
using testing::sampleRun;
using testing::tinyComparison;

constexpr float kNaNf = std::numeric_limits<float>::quiet_NaN();
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

struct Rgb {
  int r, g, b;
  friend bool operator==(const Rgb&, const Rgb&) = default;
  friend std::ostream& operator<<(std::ostream& os, const Rgb& c) {
    return os << "(" << c.r << "," << c.g << "," << c.b << ")";
  }
};

using Decoded = testing::DecodedPng<Rgb>;
Decoded decode(const std::string& png) {
  return testing::decodePng<Rgb>(png);
}

constexpr Rgb kDepthBackground{20, 30, 70};
constexpr Rgb kPanel{32, 32, 32};
constexpr Rgb kWhite{255, 255, 255};

// PNG row of frame row `row` in a 3-row frame.
int pngRow(int row) {
  return 2 - row;
}

TEST(EncodeRunImages, ProducesTheFourImagesInTheRunFolder) {
  RunRecord run = sampleRun();
  encodeRunImages(run, tinyComparison());
  ASSERT_EQ(run.images.size(), 4u);
  EXPECT_EQ(run.images[0].relativePath, "standard/main-zo-24-world/raster_depth.png");
  EXPECT_EQ(run.images[1].relativePath, "standard/main-zo-24-world/ray_depth.png");
  EXPECT_EQ(run.images[2].relativePath, "standard/main-zo-24-world/error_heatmap.png");
  EXPECT_EQ(run.images[3].relativePath, "standard/main-zo-24-world/mismatch.png");
  // Encoding again replaces them.
  encodeRunImages(run, tinyComparison());
  EXPECT_EQ(run.images.size(), 4u);
  const nlohmann::json j = reportJson({run}, sampleGl());
  EXPECT_EQ(j["runs"][0]["images"]["error_heatmap"], "standard/main-zo-24-world/error_heatmap.png");
}

TEST(EncodeRunImages, MismatchMaskHasOneColourPerClassAndIsFlipped) {
  RunRecord run = sampleRun();
  encodeRunImages(run, tinyComparison());
  const Decoded m = decode(imageNamed(run, "mismatch.png").pngBytes);
  ASSERT_EQ(m.width, 4);
  ASSERT_EQ(m.height, 3);
  // Frame row 0 (bottom) is the last PNG row.
  EXPECT_EQ(m.at(0, 2), (Rgb{0, 0, 0}));        // Background
  EXPECT_EQ(m.at(1, 2), (Rgb{128, 128, 128}));  // Agree
  EXPECT_EQ(m.at(2, 2), (Rgb{255, 140, 0}));    // DepthBeyondTolerance
  EXPECT_EQ(m.at(3, 2), (Rgb{255, 230, 0}));    // CoverageEdgeAmbiguous
  EXPECT_EQ(m.at(0, 1), (Rgb{255, 0, 0}));      // CoverageUnexplained
  EXPECT_EQ(m.at(1, 1), (Rgb{0, 255, 255}));    // IdDepthAmbiguous
  EXPECT_EQ(m.at(2, 1), (Rgb{60, 110, 255}));   // IdEdgeAmbiguous
  EXPECT_EQ(m.at(3, 1), (Rgb{255, 0, 255}));    // IdUnexplained
  EXPECT_EQ(m.at(0, 0), (Rgb{128, 128, 128}));  // frame row 2 is the first PNG row
  EXPECT_EQ(m.at(3, 0), (Rgb{0, 0, 0}));
}

TEST(EncodeRunImages, DepthImagesShareOneRangeNearerIsBrighter) {
  RunRecord run = sampleRun();
  encodeRunImages(run, tinyComparison());
  const Decoded raster = decode(imageNamed(run, "raster_depth.png").pngBytes);
  const Decoded ray = decode(imageNamed(run, "ray_depth.png").pngBytes);
  ASSERT_EQ(raster.width, 4);
  ASSERT_EQ(raster.height, 3);
  ASSERT_EQ(ray.width, 4);
  ASSERT_EQ(ray.height, 3);
  // grey = 48 + 207 * (1 - d) on the shared range [0, 1].
  const auto grey = [](int g) { return Rgb{g, g, g}; };
  EXPECT_EQ(ray.at(1, pngRow(0)), grey(255));     // d = 0: the nearest of both sides
  EXPECT_EQ(raster.at(1, pngRow(0)), grey(203));  // d = 0.25: the nearest raster pixel
  EXPECT_EQ(raster.at(3, pngRow(0)), grey(48));   // d = 1: the farthest
  EXPECT_EQ(ray.at(3, pngRow(0)), grey(100));     // d = 0.75
  EXPECT_EQ(raster.at(2, pngRow(0)), grey(152));  // d = 0.5 in both
  EXPECT_EQ(ray.at(2, pngRow(0)), grey(152));
  EXPECT_EQ(raster.at(0, pngRow(2)), grey(100));  // top-left of the PNG is frame row 2
  // Background (NaN) and a non-finite depth: dark blue.
  EXPECT_EQ(raster.at(0, pngRow(0)), kDepthBackground);
  EXPECT_EQ(ray.at(0, pngRow(0)), kDepthBackground);
  EXPECT_EQ(raster.at(3, pngRow(2)), kDepthBackground);
  EXPECT_EQ(ray.at(2, pngRow(2)), kDepthBackground);
  // The brightest pixel of each image is its nearest depth.
  for (const Decoded* image : {&raster, &ray}) {
    int brightest = 0;
    for (int y = 0; y < 3; ++y)
      for (int x = 0; x < 4; ++x)
        if (image->at(x, y) != kDepthBackground) brightest = std::max(brightest, image->at(x, y).r);
    EXPECT_EQ(brightest, image == &ray ? 255 : 203);
  }
}

TEST(EncodeRunImages, ReversedZLargerDepthIsNearer) {
  RunRecord run = sampleRun();
  run.convention = kZeroToOneReversed;
  encodeRunImages(run, tinyComparison());
  const Decoded raster = decode(imageNamed(run, "raster_depth.png").pngBytes);
  const Decoded ray = decode(imageNamed(run, "ray_depth.png").pngBytes);
  // grey = 48 + 207 * d.
  EXPECT_EQ(raster.at(3, pngRow(0)), (Rgb{255, 255, 255}));  // d = 1: the nearest
  EXPECT_EQ(ray.at(1, pngRow(0)), (Rgb{48, 48, 48}));        // d = 0: the farthest
  EXPECT_EQ(raster.at(1, pngRow(0)), (Rgb{100, 100, 100}));  // d = 0.25
}

TEST(EncodeRunImages, FlatDepthIsMidGrey) {
  PixelComparison p = tinyComparison();
  for (float& d : p.rasterDepth)
    if (!std::isnan(d)) d = 0.5f;
  for (double& d : p.analyticDepth)
    if (std::isfinite(d)) d = 0.5;
  RunRecord run = sampleRun();
  encodeRunImages(run, p);
  const Decoded raster = decode(imageNamed(run, "raster_depth.png").pngBytes);
  EXPECT_EQ(raster.at(1, pngRow(0)), (Rgb{128, 128, 128}));
  EXPECT_EQ(raster.at(0, pngRow(0)), kDepthBackground);
}

TEST(EncodeRunImages, HeatMapColoursAndScale) {
  RunRecord run = sampleRun();
  encodeRunImages(run, tinyComparison());
  const Decoded h = decode(imageNamed(run, "error_heatmap.png").pngBytes);
  // 100 px scale strip on the right; padded to 160 px high.
  ASSERT_EQ(h.width, 4 + 100);
  ASSERT_EQ(h.height, 160);
  // r <= 1: s = log10(max(r, 1e-4)) + 4 on the ramp (68,1,84) (59,82,139) (33,145,140)
  // (94,201,98) (253,231,37), one decade per segment; r > 1: (230,0,0) -> white, f = log10(r).
  // Each channel rounded to nearest.
  EXPECT_EQ(h.at(0, pngRow(0)), (Rgb{0, 0, 0}));        // NaN: not compared
  EXPECT_EQ(h.at(1, pngRow(0)), (Rgb{68, 1, 84}));      // 0: at the floor
  EXPECT_EQ(h.at(2, pngRow(0)), (Rgb{205, 222, 55}));   // 0.5: s = 3.699
  EXPECT_EQ(h.at(3, pngRow(0)), (Rgb{253, 231, 37}));   // 1: the predicted tolerance
  EXPECT_EQ(h.at(0, pngRow(1)), (Rgb{234, 45, 45}));    // 1.5: f = 0.176
  EXPECT_EQ(h.at(1, pngRow(1)), (Rgb{238, 77, 77}));    // 2: f = 0.301
  EXPECT_EQ(h.at(2, pngRow(1)), (Rgb{247, 178, 178}));  // 5: f = 0.699
  EXPECT_EQ(h.at(3, pngRow(1)), (Rgb{68, 1, 84}));      // -1: at the floor
  EXPECT_EQ(h.at(0, pngRow(2)), kWhite);                // +inf
  EXPECT_EQ(h.at(1, pngRow(2)), (Rgb{157, 213, 74}));   // 0.25: s = 3.398
  EXPECT_EQ(h.at(2, pngRow(2)), (Rgb{233, 227, 45}));   // 0.75: s = 3.875
  EXPECT_EQ(h.at(3, pngRow(2)), (Rgb{0, 0, 0}));        // NaN
  // Padding below the image and the strip background.
  EXPECT_EQ(h.at(0, 3), kPanel);
  EXPECT_EQ(h.at(3, 159), kPanel);
  EXPECT_EQ(h.at(4 + 99, 159), kPanel);
  // The bar: log10(r) from -4 at its bottom row 148 to 1 (white) at its top row 34, linearly in
  // rows: row y shows r = 10^(-4 + 5 (148 - y) / 114).
  const int barX = 4 + 12;
  EXPECT_EQ(h.at(barX, 34), kWhite);
  EXPECT_EQ(h.at(barX, 148), (Rgb{68, 1, 84}));
  EXPECT_EQ(h.at(barX, 125), (Rgb{59, 83, 139}));   // r = 10^-2.991: next to the 1e-3 stop
  EXPECT_EQ(h.at(barX, 102), (Rgb{34, 146, 139}));  // 10^-1.982: next to 0.01
  EXPECT_EQ(h.at(barX, 80), (Rgb{93, 200, 99}));    // 10^-1.018: next to 0.1
  EXPECT_EQ(h.at(barX, 57), (Rgb{252, 231, 38}));   // 10^-0.0088: just within tolerance
  EXPECT_EQ(h.at(barX, 56), (Rgb{231, 9, 9}));      // 10^0.035: just beyond it, red
  // Tick marks right of the bar at 1e-4, 1e-3, 0.01, 0.1, 1 and 10: rows 148 - round((d + 4) /
  // 5 * 114).
  for (const int y : {148, 125, 102, 80, 57, 34}) EXPECT_EQ(h.at(4 + 27, y), kWhite) << y;
  EXPECT_EQ(h.at(4 + 27, 90), kPanel);
  // Labels and title are drawn at twice the font's size: white pixels right of the ticks and above
  // the bar, glyph strokes 2 px wide.
  const auto whiteIn = [&](int x0, int y0, int x1, int y1) {
    int n = 0;
    for (int y = y0; y < y1; ++y)
      for (int x = x0; x < x1; ++x) n += h.at(x, y) == kWhite;
    return n;
  };
  EXPECT_GT(whiteIn(4 + 34, 142, 4 + 100, 158), 40);  // "1e-4"
  EXPECT_GT(whiteIn(4 + 34, 51, 4 + 100, 66), 12);    // "1"
  EXPECT_GT(whiteIn(4 + 34, 28, 4 + 100, 44), 40);    // ">=10"
  EXPECT_GT(whiteIn(4, 0, 4 + 100, 26), 60);          // "err/tol"
  EXPECT_EQ(whiteIn(4 + 34, 66, 4 + 100, 73), 0);     // nothing between "1" and "0.1"
  // The glyphs are 2x: the label "1"'s vertical stroke is 2 px wide and 14 px high.
  int tallest = 0;
  for (int x = 4 + 34; x < 4 + 60; ++x) tallest = std::max(tallest, whiteIn(x, 51, x + 1, 66));
  EXPECT_EQ(tallest, 14);
}

TEST(EncodeRunImages, TinyViewportsDoNotCrash) {
  for (const Viewport viewport : {Viewport{1, 1}, Viewport{7, 3}, Viewport{3, 7}}) {
    const std::size_t n = static_cast<std::size_t>(viewport.width) * viewport.height;
    PixelComparison p;
    p.viewport = viewport;
    p.rasterDepth.assign(n, 0.5f);
    p.analyticDepth.assign(n, 0.5);
    p.toleranceRatio.assign(n, 0.5f);
    p.classes.assign(n, PixelClass::Agree);
    RunRecord run = sampleRun();
    run.size = viewport;
    ASSERT_NO_THROW(encodeRunImages(run, p));
    ASSERT_EQ(run.images.size(), 4u);
    const Decoded m = decode(imageNamed(run, "mismatch.png").pngBytes);
    EXPECT_EQ(m.width, viewport.width);
    EXPECT_EQ(m.height, viewport.height);
    const Decoded h = decode(imageNamed(run, "error_heatmap.png").pngBytes);
    EXPECT_EQ(h.width, viewport.width + 100);
    EXPECT_EQ(h.height, 160);
    EXPECT_EQ(h.at(0, 0), (Rgb{205, 222, 55}));  // 0.5
  }
}

TEST(EncodeRunImages, TallImagesKeepTheirHeight) {
  const Viewport viewport{2, 300};
  const std::size_t n = 600;
  PixelComparison p;
  p.viewport = viewport;
  p.rasterDepth.assign(n, kNaNf);
  p.analyticDepth.assign(n, kNaN);
  p.toleranceRatio.assign(n, kNaNf);
  p.classes.assign(n, PixelClass::Background);
  RunRecord run = sampleRun();
  encodeRunImages(run, p);
  const Decoded h = decode(imageNamed(run, "error_heatmap.png").pngBytes);
  EXPECT_EQ(h.width, 102);
  EXPECT_EQ(h.height, 300);
  EXPECT_EQ(h.at(1, 299), (Rgb{0, 0, 0}));
  EXPECT_EQ(h.at(2 + 12, 288), (Rgb{68, 1, 84}));      // the bar reaches row height - 12
  EXPECT_EQ(h.at(2 + 12, 289), (Rgb{160, 160, 160}));  // its border
}

TEST(EncodeRunImages, RejectsInconsistentSizes) {
  PixelComparison p = tinyComparison();
  p.classes.pop_back();
  RunRecord run = sampleRun();
  EXPECT_THROW(encodeRunImages(run, p), InternalError);
  PixelComparison empty;
  EXPECT_THROW(encodeRunImages(run, empty), InternalError);
}

}  // namespace
}  // namespace clipray
