// The pictures index.html shows beside the four full-size PNGs: thumbnails and cluster crops, and
// the colour functions its legend reads.

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

#include "clipray/report/RunImages.hpp"

namespace clipray {

std::ostream& operator<<(std::ostream& os, const Rgb& c) {
  return os << "(" << int{c.r} << "," << int{c.g} << "," << int{c.b} << ")";
}

namespace {

constexpr float kNaNf = std::numeric_limits<float>::quiet_NaN();

using Decoded = testing::DecodedPng<Rgb>;
Decoded decode(const std::string& png) {
  return testing::decodePng<Rgb>(png);
}

RunRecord sampleRun() {
  RunRecord run;
  run.scene = "standard";
  run.camera = "main";
  run.convention = kZeroToOne;
  run.depthFormat = DepthFormat::Float32;
  run.vertexMode = VertexMode::World;
  return run;
}

// A frame of background pixels, not compared.
PixelComparison blankFrame(Viewport viewport) {
  const std::size_t n = static_cast<std::size_t>(viewport.width) * viewport.height;
  PixelComparison p;
  p.viewport = viewport;
  p.rasterDepth.assign(n, kNaNf);
  p.analyticDepth.assign(n, std::numeric_limits<double>::quiet_NaN());
  p.toleranceRatio.assign(n, kNaNf);
  p.classes.assign(n, PixelClass::Background);
  return p;
}

constexpr Rgb kMagenta{255, 0, 255}, kYellow{255, 230, 0}, kRed{255, 0, 0}, kGrey{128, 128, 128},
    kBlack{0, 0, 0}, kWhite{255, 255, 255};

TEST(HeatMapColour, LogarithmicWithinToleranceRedToWhiteBeyond) {
  // The ramp's stops, one a decade.
  EXPECT_EQ(heatMapColour(1e-4), (Rgb{68, 1, 84}));
  EXPECT_EQ(heatMapColour(1e-3), (Rgb{59, 82, 139}));
  EXPECT_EQ(heatMapColour(1e-2), (Rgb{33, 145, 140}));
  EXPECT_EQ(heatMapColour(0.1), (Rgb{94, 201, 98}));
  EXPECT_EQ(heatMapColour(1.0), (Rgb{253, 231, 37}));
  // A typical consistent run's worst pixel (0.05 .. 0.18 of its tolerance) is told apart:
  // s = log10(r) + 4, between the 0.01 and 0.1 stops, then between 0.1 and 1.
  EXPECT_EQ(heatMapColour(0.05), (Rgb{76, 184, 111}));  // f = 0.699 of (33,145,140)->(94,201,98)
  EXPECT_EQ(heatMapColour(0.18), (Rgb{135, 209, 82}));  // f = 0.255 of (94,201,98)->(253,231,37)
  EXPECT_EQ(heatMapColour(1e-9), heatMapColour(1e-4));  // below the floor
  EXPECT_EQ(heatMapColour(0.0), heatMapColour(1e-4));
  EXPECT_EQ(heatMapColour(std::pow(10.0, 0.4)), (Rgb{240, 102, 102}));  // f = 0.4: red -> white
  EXPECT_EQ(heatMapColour(10.0), kWhite);
  EXPECT_EQ(heatMapColour(1e6), kWhite);
  EXPECT_EQ(heatMapColour(std::nan("")), kBlack);
}

TEST(Thumbnails, SizeIsTheFrameInWholeBlocksWithin160Pixels) {
  EXPECT_EQ(thumbnailSize({1920, 1080}), (Viewport{160, 90}));  // blocks of 12
  EXPECT_EQ(thumbnailSize({320, 240}), (Viewport{160, 120}));   // 2
  EXPECT_EQ(thumbnailSize({161, 10}), (Viewport{81, 5}));       // 2, the last block partial
  EXPECT_EQ(thumbnailSize({100, 400}), (Viewport{34, 134}));    // 3, by the height
  EXPECT_EQ(thumbnailSize({64, 48}), (Viewport{64, 48}));       // 1
  EXPECT_EQ(thumbnailSize({1, 1}), (Viewport{1, 1}));
}

TEST(Thumbnails, EachPixelIsTheMostSevereClassAndLargestRatioOfItsBlock) {
  // 330 x 4 frame: blocks of 3, a 110 x 2 thumbnail; frame rows 0..2 make thumbnail row 0 (the
  // bottom one, PNG row 1), frame row 3 thumbnail row 1 (PNG row 0).
  PixelComparison p = blankFrame({330, 4});
  for (int x = 0; x < 330; ++x) {
    p.classes[x] = PixelClass::Agree;
    p.toleranceRatio[x] = 0.01f;
  }
  p.classes[91] = PixelClass::IdUnexplained;  // one pixel among 9 (block 30): it shows
  p.toleranceRatio[7] = 0.5f;                 // the block's largest ratio
  p.classes[3 * 330 + 100] = PixelClass::CoverageEdgeAmbiguous;
  RunRecord run = sampleRun();
  encodeThumbnails(run, p);
  ASSERT_EQ(run.images.size(), 2u);
  EXPECT_EQ(run.images[0].relativePath, "standard/main-zo-32f-world/thumb_mismatch.png");
  EXPECT_EQ(run.images[1].relativePath, "standard/main-zo-32f-world/thumb_heatmap.png");
  const Decoded m = decode(run.images[0].pngBytes);
  const Decoded h = decode(run.images[1].pngBytes);
  ASSERT_EQ(m.width, 110);
  ASSERT_EQ(m.height, 2);
  ASSERT_EQ(h.width, 110);
  ASSERT_EQ(h.height, 2);
  EXPECT_EQ(m.at(30, 1), kMagenta);  // IdUnexplained beats Agree and Background
  // and paints the eight thumbnail pixels around it, Agree and Background alike: a dot.
  for (const int x : {29, 30, 31}) {
    EXPECT_EQ(m.at(x, 0), kMagenta) << x;
    EXPECT_EQ(m.at(x, 1), kMagenta) << x;
  }
  EXPECT_EQ(m.at(28, 1), kGrey);    // beyond the dot
  EXPECT_EQ(m.at(32, 0), kBlack);   // an ambiguous class beside it (33, 0) does not spread
  EXPECT_EQ(m.at(0, 1), kGrey);     // Agree beats Background
  EXPECT_EQ(m.at(33, 0), kYellow);  // frame (100, 3)
  EXPECT_EQ(m.at(0, 0), kBlack);    // all background
  EXPECT_EQ(m.at(109, 0), kBlack);
  EXPECT_EQ(h.at(2, 1), (Rgb{205, 222, 55}));  // 0.5, the largest of its block
  EXPECT_EQ(h.at(1, 1), (Rgb{33, 145, 140}));  // 0.01
  EXPECT_EQ(h.at(0, 0), kBlack);               // nothing compared
  // Appended: the full-size images a run may already have stay.
  encodeThumbnails(run, p);
  EXPECT_EQ(run.images.size(), 4u);
}

TEST(ClusterCrops, WindowCentredOnThePixelAndMovedInsideTheFrame) {
  MismatchCluster c;
  c.x = 20;
  c.y = 18;  // image row 35 - 18 = 17 of a 36-row frame
  const CropWindow centred = clusterCropWindow(c, {40, 36});
  EXPECT_EQ(centred.x, 4);  // 20 - 16, within [0, 40 - 32]
  EXPECT_EQ(centred.y, 1);  // 17 - 16
  EXPECT_EQ(centred.width, 32);
  EXPECT_EQ(centred.height, 32);
  c.x = 39;
  c.y = 0;  // the bottom-right corner
  const CropWindow corner = clusterCropWindow(c, {40, 36});
  EXPECT_EQ(corner.x, 8);
  EXPECT_EQ(corner.y, 4);
  const CropWindow small = clusterCropWindow(c, {10, 6});
  EXPECT_EQ(small.x, 0);
  EXPECT_EQ(small.y, 0);
  EXPECT_EQ(small.width, 10);
  EXPECT_EQ(small.height, 6);
}

TEST(ClusterCrops, EnlargedEightTimesWithThePixelOutlined) {
  PixelComparison p = blankFrame({40, 36});
  const auto glIndex = [](int x, int y) { return static_cast<std::size_t>(y) * 40 + x; };
  p.classes[glIndex(2, 30)] = PixelClass::CoverageUnexplained;  // image (2, 5)
  p.classes[glIndex(10, 20)] = PixelClass::IdUnexplained;       // image (10, 15)
  RunRecord run = sampleRun();
  run.clusters.count = 2;
  run.clusters.largest = {{1, 1, 0, 0, 2, 30, 2, 30, 2, 30}, {1, 0, 1, 0, 10, 20, 10, 20, 10, 20}};
  encodeClusterCrops(run, p);
  ASSERT_EQ(run.images.size(), 2u);
  EXPECT_EQ(run.images[0].relativePath, "standard/main-zo-32f-world/cluster1.png");
  EXPECT_EQ(run.images[1].relativePath, "standard/main-zo-32f-world/cluster2.png");
  // Cluster 1: the window is image (0, 0) .. (31, 31); its pixel's cell is (16, 40) .. (23, 47).
  const Decoded first = decode(run.images[0].pngBytes);
  ASSERT_EQ(first.width, 256);
  ASSERT_EQ(first.height, 256);
  for (const auto& [x, y] : {std::pair{16, 40}, {23, 40}, {16, 47}, {23, 47}, {19, 40}, {16, 44}})
    EXPECT_EQ(first.at(x, y), kWhite) << x << "," << y;
  for (int y = 41; y < 47; ++y)
    for (int x = 17; x < 23; ++x) EXPECT_EQ(first.at(x, y), kRed) << x << "," << y;
  EXPECT_EQ(first.at(15, 44), kBlack);                    // the background beside it
  EXPECT_EQ(first.at(10 * 8 + 3, 15 * 8 + 3), kMagenta);  // the other cluster's pixel
  // Cluster 2: window image (0, 0) .. (31, 31) again (10 - 16 and 15 - 16 move inside).
  const Decoded second = decode(run.images[1].pngBytes);
  EXPECT_EQ(second.at(80, 120), kWhite);
  EXPECT_EQ(second.at(83, 123), kMagenta);
  EXPECT_EQ(second.at(19, 43), kRed);
}

TEST(ClusterCrops, ASmallFrameIsCroppedWhole) {
  PixelComparison p = blankFrame({10, 6});
  p.classes[0] = PixelClass::DepthBeyondTolerance;  // GL (0, 0): image (0, 5)
  RunRecord run = sampleRun();
  run.clusters.count = 1;
  run.clusters.largest = {{1, 0, 0, 1, 0, 0, 0, 0, 0, 0}};
  encodeClusterCrops(run, p);
  ASSERT_EQ(run.images.size(), 1u);
  const Decoded crop = decode(run.images[0].pngBytes);
  EXPECT_EQ(crop.width, 80);
  EXPECT_EQ(crop.height, 48);
  EXPECT_EQ(crop.at(0, 40), kWhite);
  EXPECT_EQ(crop.at(3, 43), (Rgb{255, 140, 0}));
  // No clusters, no crops.
  RunRecord none = sampleRun();
  encodeClusterCrops(none, p);
  EXPECT_TRUE(none.images.empty());
}

}  // namespace
}  // namespace clipray
