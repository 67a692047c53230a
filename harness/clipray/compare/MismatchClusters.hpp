#pragma once
// Where a reconcile's unexplained pixels are: the connected components of the pixels whose class
// makes a run inconsistent (CoverageUnexplained, IdUnexplained, DepthBeyondTolerance), so a report
// can name the few places to look at instead of a count. Components are 8-connected (a pixel
// touches the eight around it): the pixels along a slanted edge meet only at corners, and they are
// one place to look at. The three classes join into one component where they touch.

#include <cstddef>
#include <cstdint>
#include <vector>

#include "clipray/compare/Reconcile.hpp"

namespace clipray {

// One component. Coordinates are pixel indices in GL window coordinates: x from the left column
// (0), y from the bottom row (0), as the frames store them; imageY converts to the top-down rows
// of the PNGs.
struct MismatchCluster {
  std::int64_t pixels = 0;
  // Its pixels by class (they sum to pixels).
  std::int64_t coverageUnexplained = 0, idUnexplained = 0, depthBeyondTolerance = 0;
  // The bounding box, inclusive.
  int minX = 0, minY = 0, maxX = 0, maxY = 0;
  // A pixel of the component to look at: the one nearest its centroid (so it lies on the
  // component even where the component is a ring or an L); ties: the first in frame order (rows
  // bottom first, then x).
  int x = 0, y = 0;
  friend bool operator==(const MismatchCluster&, const MismatchCluster&) = default;
};

// A GL window row as a top-down image row, in a frame `height` rows high.
inline int imageY(int glY, int height) {
  return height - 1 - glY;
}

struct MismatchClusters {
  std::int64_t count = 0;                // components in the frame
  std::vector<MismatchCluster> largest;  // the largest, most pixels first; ties in frame order
  friend bool operator==(const MismatchClusters&, const MismatchClusters&) = default;
};

// The pixel classes that form components.
bool isUnexplained(PixelClass value);

// The components of classes (width x height, row 0 at the bottom), the largest `keep` of them.
// classes must hold width x height values (InternalError otherwise).
MismatchClusters findMismatchClusters(const FrameVector<PixelClass>& classes, Viewport viewport,
                                      std::size_t keep);

}  // namespace clipray
