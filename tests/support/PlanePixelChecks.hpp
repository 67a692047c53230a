#pragma once
// The pixels a screen-path pass decided from their triangles' planes (t NaN), each with the hit
// PlanePixelHits gives it (what the compare classifies where it goes along the ray), checked
// against the ray path's pass bit for bit (id and t).

#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "clipray/compare/PlanePixelHits.hpp"
#include "clipray/compare/PrimitiveClipPlanes.hpp"
#include "clipray/engine/ReconcileRun.hpp"

namespace clipray::testing {

struct PlanePixel {
  int x = 0, y = 0;
  Ray ray;  // the frame's
  Hit hit;  // PlanePixelHits', the ray path's
};

// Every plane pixel of `screen` (none where it kept no planes), in pixel order, after an
// expectation that its PlanePixelHits hit is rays' (the same scene, camera and state on the ray
// path): stops at the first that is not, naming `what` and the pixel.
inline std::vector<PlanePixel> planePixelsAsTheRayPathHitsThem(const engine::AnalyticPass& screen,
                                                               const engine::AnalyticPass& rays,
                                                               const PrimitiveClipPlanes& planes,
                                                               const std::string& what) {
  std::vector<PlanePixel> pixels;
  if (!screen.frame.planesById) return pixels;
  const PlanePixelHits planePixelHits(*screen.frame.pixelCentreRays, planes);
  const Viewport viewport = screen.frame.viewport;
  for (int y = 0; y < viewport.height; ++y) {
    for (int x = 0; x < viewport.width; ++x) {
      const std::size_t i = static_cast<std::size_t>(y) * viewport.width + x;
      const Hit& decided = screen.frame.hits[i];
      if (!decided.hit() || !std::isnan(decided.t)) continue;
      PlanePixel pixel{x, y, {}, {}};
      screen.frame.pixelCentreRays->row(y, x, 1, &pixel.ray);
      pixel.hit =
          planePixelHits.rayPathHit(*screen.intersector, decided.primitiveId, x, y, pixel.ray);
      const Hit& expected = rays.frame.hits[i];
      const bool same =
          pixel.hit.primitiveId == expected.primitiveId &&
          std::bit_cast<std::uint64_t>(pixel.hit.t) == std::bit_cast<std::uint64_t>(expected.t);
      EXPECT_TRUE(same) << what << ", pixel " << x << "," << y << ": id " << pixel.hit.primitiveId
                        << " t " << pixel.hit.t << " against id " << expected.primitiveId << " t "
                        << expected.t;
      if (!same) return pixels;
      pixels.push_back(pixel);
    }
  }
  return pixels;
}

}  // namespace clipray::testing
