// The connected components of a run's unexplained pixels, on hand-made masks.

#include <gtest/gtest.h>

#include <string>

#include "clipray/compare/MismatchClusters.hpp"
#include "clipray/util/Check.hpp"

namespace clipray {
namespace {

// A mask from text rows, the top row first (as printed); row 0 of the frame is the last string.
// '.' agree, ' ' background, 'C' coverage unexplained, 'I' id unexplained, 'D' depth beyond
// tolerance, 'e' coverage edge-ambiguous, 'z' id depth-ambiguous.
FrameVector<PixelClass> mask(const std::vector<std::string>& topFirst, Viewport& viewport) {
  viewport = {static_cast<int>(topFirst.front().size()), static_cast<int>(topFirst.size())};
  FrameVector<PixelClass> classes;
  for (auto row = topFirst.rbegin(); row != topFirst.rend(); ++row) {
    for (const char c : *row) {
      switch (c) {
        case 'C':
          classes.push_back(PixelClass::CoverageUnexplained);
          break;
        case 'I':
          classes.push_back(PixelClass::IdUnexplained);
          break;
        case 'D':
          classes.push_back(PixelClass::DepthBeyondTolerance);
          break;
        case 'e':
          classes.push_back(PixelClass::CoverageEdgeAmbiguous);
          break;
        case 'z':
          classes.push_back(PixelClass::IdDepthAmbiguous);
          break;
        case ' ':
          classes.push_back(PixelClass::Background);
          break;
        default:
          classes.push_back(PixelClass::Agree);
      }
    }
  }
  return classes;
}

TEST(MismatchClusters, EightConnectedComponentsLargestFirst) {
  Viewport viewport;
  const auto classes = mask(
      {
          ".C....",  // GL row 3
          "CC..I.",  // GL row 2
          ".....D",  // GL row 1
          "..e..D",  // GL row 0
      },
      viewport);
  const MismatchClusters found = findMismatchClusters(classes, viewport, 5);
  EXPECT_EQ(found.count, 2);
  ASSERT_EQ(found.largest.size(), 2u);
  // Both have three pixels: the one whose first pixel comes first in frame order (GL row 0) leads.
  // (4, 2) touches (5, 1) only at a corner: one component when 8-connected.
  // Centroid (14/3, 1): (5, 1) is the nearest member.
  const MismatchCluster right{3, 0, 1, 2, 4, 0, 5, 2, 5, 1};
  // Centroid (2/3, 7/3): (1, 2) is the nearest member.
  const MismatchCluster left{3, 3, 0, 0, 0, 2, 1, 3, 1, 2};
  EXPECT_EQ(found.largest[0], right);
  EXPECT_EQ(found.largest[1], left);
  EXPECT_EQ(imageY(found.largest[1].y, viewport.height), 1);  // top-down: the second row

  const MismatchClusters one = findMismatchClusters(classes, viewport, 1);
  EXPECT_EQ(one.count, 2);
  ASSERT_EQ(one.largest.size(), 1u);
  EXPECT_EQ(one.largest[0], right);
}

TEST(MismatchClusters, SizeDecidesTheOrderAndAmbiguousPixelsNeitherJoinNorSplit) {
  Viewport viewport;
  const auto classes = mask(
      {
          "C.e.II",
          "..z.II",
          "I...I.",
      },
      viewport);
  const MismatchClusters found = findMismatchClusters(classes, viewport, 5);
  EXPECT_EQ(found.count, 3);
  ASSERT_EQ(found.largest.size(), 3u);
  // The five I pixels at the right: centroid (4.4, 1.2); distances^2 (4,0) 1.6, (4,1) 0.2,
  // (5,1) 0.4, (4,2) 0.8, (5,2) 1.0: (4, 1).
  EXPECT_EQ(found.largest[0], (MismatchCluster{5, 0, 5, 0, 4, 0, 5, 2, 4, 1}));
  // Then the single pixels in frame order: (0, 0) before (0, 2).
  EXPECT_EQ(found.largest[1], (MismatchCluster{1, 0, 1, 0, 0, 0, 0, 0, 0, 0}));
  EXPECT_EQ(found.largest[2], (MismatchCluster{1, 1, 0, 0, 0, 2, 0, 2, 0, 2}));
}

TEST(MismatchClusters, ARingIsNamedByAPixelOnIt) {
  Viewport viewport;
  const auto classes = mask(
      {
          "CCC",
          "C.C",
          "CCC",
      },
      viewport);
  const MismatchClusters found = findMismatchClusters(classes, viewport, 5);
  ASSERT_EQ(found.largest.size(), 1u);
  // The centroid (1, 1) is not on the ring; four members lie 1 from it: the first in frame order,
  // (1, 0), names it.
  EXPECT_EQ(found.largest[0], (MismatchCluster{8, 8, 0, 0, 0, 0, 2, 2, 1, 0}));
}

TEST(MismatchClusters, AConsistentFrameHasNone) {
  Viewport viewport;
  const auto classes = mask({"..e ", "z..."}, viewport);
  const MismatchClusters found = findMismatchClusters(classes, viewport, 5);
  EXPECT_EQ(found.count, 0);
  EXPECT_TRUE(found.largest.empty());
  EXPECT_EQ(findMismatchClusters({}, {0, 0}, 5), MismatchClusters{});
}

TEST(MismatchClusters, AWrongSizedMaskIsRefused) {
  Viewport viewport;
  auto classes = mask({"C.", ".C"}, viewport);
  classes.pop_back();
  EXPECT_THROW(findMismatchClusters(classes, viewport, 5), InternalError);
}

TEST(MismatchClusters, TheUnexplainedClasses) {
  EXPECT_TRUE(isUnexplained(PixelClass::CoverageUnexplained));
  EXPECT_TRUE(isUnexplained(PixelClass::IdUnexplained));
  EXPECT_TRUE(isUnexplained(PixelClass::DepthBeyondTolerance));
  for (const PixelClass value :
       {PixelClass::Background, PixelClass::Agree, PixelClass::CoverageEdgeAmbiguous,
        PixelClass::IdDepthAmbiguous, PixelClass::IdEdgeAmbiguous}) {
    EXPECT_FALSE(isUnexplained(value)) << pixelClassName(value);
  }
}

}  // namespace
}  // namespace clipray
