// glClipControl's origin (GL 4.6 13.8.1): a run drawn under GL_UPPER_LEFT. A camera whose
// projection clipray builds gets the y-down projection a Direct3D-style app builds, so the picture
// is the lower-left run's pixel for pixel; a raw matrix is drawn as it is, upside down, and the
// rays follow it. Either way raster and rays agree.

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "clipray/engine/ReconcileRun.hpp"
#include "clipray/scene/Scene.hpp"
#include "support/GlFixture.hpp"
#include "support/RunStates.hpp"

namespace clipray {
namespace {

using testing::GlTest;

std::string runName(const RunRecord& run) {
  return run.scene + "/" + run.camera + " " + run.convention.name() + " " +
         depthFormatName(run.depthFormat);
}

class ClipOriginRuns : public GlTest {};

TEST(ClipOriginNames, ParseAndPrintWithTheUpperLeftSuffix) {
  for (const DepthMode mode : testing::kLowerLeftModes) {
    const DepthMode upper = testing::upperLeft(mode);
    EXPECT_EQ(upper.name(), mode.name() + "-upper-left");
    EXPECT_EQ(DepthMode::parse(upper.name()), upper);
    EXPECT_EQ(upper.lowerLeft(), mode);
  }
  EXPECT_EQ(DepthMode::parse("upper-left"), std::nullopt);
  EXPECT_EQ(DepthMode::parse("no-reversed-upper-left"), std::nullopt);
  EXPECT_EQ(DepthMode::parse("zo-upper-left-upper-left"), std::nullopt);
}

TEST(ClipOriginMatrices, TheUpperLeftProjectionIsTheLowerLeftOneWithYNegated) {
  const Scene scene = loadScene(testing::sourcePath("scenes/standard.json"));
  const Camera& camera = scene.cameras.at(0);
  for (const DepthMode mode : testing::kLowerLeftModes) {
    const glm::dmat4 lower = camera.clipFromWorld(mode, camera.viewport);
    const glm::dmat4 upper = camera.clipFromWorld(testing::upperLeft(mode), camera.viewport);
    EXPECT_NE(upper, lower);
    // Bit for bit: the negation is exact.
    EXPECT_EQ(lowerLeftClipFromWorld(upper, ClipOrigin::UpperLeft), lower) << mode.name();
  }
}

// Built projections: the upper-left frame is the lower-left frame, every depth and id exactly;
// and the runs agree with their rays with the same figures.
TEST_F(ClipOriginRuns, ABuiltProjectionDrawsTheSamePixelsUnderEitherOrigin) {
  for (const char* file : {"scenes/standard.json", "scenes/primitives.json"}) {
    const Scene scene = loadScene(testing::sourcePath(file));
    const Camera& camera = scene.cameras.at(0);
    for (const DepthMode mode : testing::kLowerLeftModes) {
      const engine::AnalyticPass lower =
          engine::runAnalyticPass(scene, camera, mode, camera.viewport);
      const engine::AnalyticPass upper =
          engine::runAnalyticPass(scene, camera, testing::upperLeft(mode), camera.viewport);
      EXPECT_EQ(upper.camera.clipFromWorld, lower.camera.clipFromWorld);
      for (const DepthFormat format : testing::kDepthFormats) {
        const RasterFrame a =
            renderer().render(engine::renderRequest(lower, format, VertexMode::World));
        const RasterFrame b =
            renderer().render(engine::renderRequest(upper, format, VertexMode::World));
        EXPECT_TRUE(a.ids == b.ids) << file << " " << mode.name();
        EXPECT_TRUE(a.depth == b.depth) << file << " " << mode.name();
        const RunRecord runA =
            engine::rasterAndCompare(renderer(), lower, format, VertexMode::World, false);
        const RunRecord runB =
            engine::rasterAndCompare(renderer(), upper, format, VertexMode::World, false);
        EXPECT_EQ(runB.convention, testing::upperLeft(mode));
        EXPECT_EQ(runB.metrics.consistent(), runA.metrics.consistent()) << runName(runB);
        EXPECT_EQ(runB.metrics.rasterHits, runA.metrics.rasterHits) << runName(runB);
        EXPECT_EQ(runB.metrics.rayHits, runA.metrics.rayHits) << runName(runB);
        EXPECT_EQ(runB.metrics.depthCompared, runA.metrics.depthCompared) << runName(runB);
        EXPECT_EQ(runB.metrics.toleranceRatio.max, runA.metrics.toleranceRatio.max)
            << runName(runB);
      }
    }
  }
}

// A raw clipFromWorld is drawn unchanged: under the upper-left origin its picture is upside down
// in the framebuffer, and clipray's rays (and the primitives' shader rays) follow it.
TEST_F(ClipOriginRuns, ARawMatrixIsDrawnUpsideDownAndTheRaysFollowIt) {
  Scene scene = loadScene(testing::sourcePath("scenes/primitives.json"));
  Camera& camera = scene.cameras.at(0);
  camera.rawClipFromWorld = camera.clipFromWorld(kZeroToOne, camera.viewport);
  const Viewport v = camera.viewport;
  for (const DepthMode mode : testing::kLowerLeftModes) {
    const engine::AnalyticPass lower = engine::runAnalyticPass(scene, camera, mode, v);
    const engine::AnalyticPass upper =
        engine::runAnalyticPass(scene, camera, testing::upperLeft(mode), v);
    for (const DepthFormat format : testing::kDepthFormats) {
      const RunRecord run =
          engine::rasterAndCompare(renderer(), upper, format, VertexMode::World, false);
      EXPECT_TRUE(run.metrics.consistent()) << runName(run);
      EXPECT_GT(run.metrics.rasterHits, v.width * v.height / 4) << runName(run);
      // The analytic frames are each other's mirror image, row for row, but where a pixel centre
      // lies within rounding of an edge (its clip y is computed from the other end of the
      // column): there the upper-left frame shows what a neighbouring pixel of the lower-left
      // frame shows. Not under reversed-Z: this ZO matrix's far plane is then where the rays
      // start, and the floor and the box that stands on it meet there in a band where rounding
      // picks either at random.
      if (mode.reversed) continue;
      const auto lowerId = [&](int x, int y) {
        if (x < 0 || y < 0 || x >= v.width || y >= v.height) return ~0u;
        return lower.frame.hits[static_cast<std::size_t>(y) * v.width + x].primitiveId;
      };
      int differing = 0;
      for (int y = 0; y < v.height; ++y) {
        for (int x = 0; x < v.width; ++x) {
          const std::uint32_t id =
              upper.frame.hits[static_cast<std::size_t>(v.height - 1 - y) * v.width + x]
                  .primitiveId;
          if (id == lowerId(x, y)) continue;
          ++differing;
          EXPECT_TRUE(id == lowerId(x - 1, y) || id == lowerId(x + 1, y) ||
                      id == lowerId(x, y - 1) || id == lowerId(x, y + 1))
              << runName(run) << " pixel (" << x << ", " << y << ")";
        }
      }
      EXPECT_LT(differing, v.width * v.height / 1000) << runName(run);
    }
  }
}

}  // namespace
}  // namespace clipray
