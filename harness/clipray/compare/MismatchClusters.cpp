// findMismatchClusters: a flood fill over the unexplained pixels (see MismatchClusters.hpp).

#include "clipray/compare/MismatchClusters.hpp"

#include <algorithm>
#include <limits>
#include <string>

#include "clipray/util/Check.hpp"

namespace clipray {

bool isUnexplained(PixelClass value) {
  return value == PixelClass::CoverageUnexplained || value == PixelClass::IdUnexplained ||
         value == PixelClass::DepthBeyondTolerance;
}

MismatchClusters findMismatchClusters(const FrameVector<PixelClass>& classes, Viewport viewport,
                                      std::size_t keep) {
  const int width = viewport.width, height = viewport.height;
  CLIPRAY_CHECK(
      width >= 0 && height >= 0 &&
          classes.size() == static_cast<std::size_t>(width) * static_cast<std::size_t>(height),
      "findMismatchClusters: " + std::to_string(classes.size()) + " pixel classes for a " +
          std::to_string(width) + "x" + std::to_string(height) + " frame");
  MismatchClusters result;
  std::vector<MismatchCluster> all;
  std::vector<bool> seen(classes.size(), false);
  std::vector<std::size_t> stack, members;
  for (std::size_t start = 0; start < classes.size(); ++start) {
    if (seen[start] || !isUnexplained(classes[start])) continue;
    // Flood fill from the first pixel of a new component in frame order.
    MismatchCluster cluster;
    cluster.minX = cluster.minY = std::numeric_limits<int>::max();
    cluster.maxX = cluster.maxY = -1;
    std::int64_t sumX = 0, sumY = 0;
    members.clear();
    stack.assign(1, start);
    seen[start] = true;
    while (!stack.empty()) {
      const std::size_t i = stack.back();
      stack.pop_back();
      members.push_back(i);
      const int x = static_cast<int>(i % static_cast<std::size_t>(width));
      const int y = static_cast<int>(i / static_cast<std::size_t>(width));
      ++cluster.pixels;
      switch (classes[i]) {
        case PixelClass::CoverageUnexplained:
          ++cluster.coverageUnexplained;
          break;
        case PixelClass::IdUnexplained:
          ++cluster.idUnexplained;
          break;
        default:
          ++cluster.depthBeyondTolerance;
      }
      cluster.minX = std::min(cluster.minX, x);
      cluster.maxX = std::max(cluster.maxX, x);
      cluster.minY = std::min(cluster.minY, y);
      cluster.maxY = std::max(cluster.maxY, y);
      sumX += x;
      sumY += y;
      for (int dy = -1; dy <= 1; ++dy) {
        for (int dx = -1; dx <= 1; ++dx) {
          const int nx = x + dx, ny = y + dy;
          if (nx < 0 || ny < 0 || nx >= width || ny >= height) continue;
          const std::size_t n = static_cast<std::size_t>(ny) * width + nx;
          if (seen[n] || !isUnexplained(classes[n])) continue;
          seen[n] = true;
          stack.push_back(n);
        }
      }
    }
    // The member nearest the centroid; ties: the first in frame order.
    const double centreX = static_cast<double>(sumX) / static_cast<double>(cluster.pixels);
    const double centreY = static_cast<double>(sumY) / static_cast<double>(cluster.pixels);
    double best = std::numeric_limits<double>::infinity();
    std::size_t bestIndex = 0;
    for (const std::size_t i : members) {
      const double ex = static_cast<double>(i % static_cast<std::size_t>(width)) - centreX;
      const double ey = static_cast<double>(i / static_cast<std::size_t>(width)) - centreY;
      const double distance = ex * ex + ey * ey;
      if (distance < best || (distance == best && i < bestIndex)) {
        best = distance;
        bestIndex = i;
      }
    }
    cluster.x = static_cast<int>(bestIndex % static_cast<std::size_t>(width));
    cluster.y = static_cast<int>(bestIndex / static_cast<std::size_t>(width));
    all.push_back(cluster);
  }
  result.count = static_cast<std::int64_t>(all.size());
  std::stable_sort(all.begin(), all.end(), [](const MismatchCluster& a, const MismatchCluster& b) {
    return a.pixels > b.pixels;
  });
  if (all.size() > keep) all.resize(keep);
  result.largest = std::move(all);
  return result;
}

}  // namespace clipray
