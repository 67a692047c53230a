// glDepthRange(n, f) (GL 4.6 13.8.1): window depth n + (f - n) d. A scene drawn with any range,
// reversed (1, 0) included (the reversed-Z of apps without clip control), agrees with its rays
// under every convention and depth format, and shows the same surfaces as under (0, 1); a range
// the compare does not know about is caught.

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

class DepthRange : public GlTest {};

RasterFrame drawn(gl::Renderer& renderer, const engine::AnalyticPass& pass, DepthFormat format,
                  glm::dvec2 range) {
  gl::RenderRequest request = engine::renderRequest(pass, format, VertexMode::World);
  request.depthRange = range;
  return renderer.render(request);
}

const std::vector<glm::dvec2> kRanges = {{1.0, 0.0}, {0.2, 0.7}, {0.0, 0.1}, {0.9, 0.3}};

std::string runName(const RunRecord& run, glm::dvec2 range) {
  return run.scene + " " + run.convention.name() + " " + depthFormatName(run.depthFormat) +
         " range (" + std::to_string(range.x) + ", " + std::to_string(range.y) + ")";
}

TEST_F(DepthRange, EveryRangeAgreesWithTheRaysAndShowsTheSameSurfaces) {
  for (const char* file : {"scenes/standard.json", "scenes/primitives.json"}) {
    const Scene base = loadScene(testing::sourcePath(file));
    for (const glm::dvec2 range : kRanges) {
      Scene scene = base;
      scene.depthRange = range;
      const Camera& camera = scene.cameras.at(0);
      for (const DepthMode mode : testing::kLowerLeftModes) {
        const engine::AnalyticPass pass =
            engine::runAnalyticPass(scene, camera, mode, camera.viewport);
        for (const DepthFormat format : testing::kDepthFormats) {
          const RunRecord run =
              engine::rasterAndCompare(renderer(), pass, format, VertexMode::World, false);
          EXPECT_TRUE(run.metrics.consistent()) << runName(run, range);
          EXPECT_GT(run.metrics.depthCompared, 1000) << runName(run, range);
          // The depth test keeps the nearer surface whichever way the range runs: the same ids
          // as under (0, 1) but where two triangles meet at equal depth (a shared edge) and the
          // mapped depths' rounding turns the tie (at 32f, where no quantum hides it).
          if (format == DepthFormat::Float32) {
            const RasterFrame ranged = drawn(renderer(), pass, format, range);
            const RasterFrame unit = drawn(renderer(), pass, format, {0.0, 1.0});
            int differing = 0;
            for (std::size_t i = 0; i < ranged.ids.size(); ++i) {
              differing += ranged.ids[i] != unit.ids[i] && ranged.ids[i] != 0 && unit.ids[i] != 0;
              EXPECT_EQ(ranged.ids[i] == 0, unit.ids[i] == 0) << runName(run, range);
            }
            // Only pixels on an edge between two surfaces: ambiguous in this run, or the one
            // tie of standard's floor diagonal that the (0, 1) run draws the other way.
            EXPECT_LE(differing, run.metrics.idMismatch.edgeAmbiguous +
                                     run.metrics.idMismatch.depthAmbiguous + 1)
                << runName(run, range);
            // Every stored depth lies within the range.
            const float low = static_cast<float>(std::min(range.x, range.y));
            const float high = static_cast<float>(std::max(range.x, range.y));
            int outside = 0;
            for (std::size_t i = 0; i < ranged.depth.size(); ++i) {
              if (ranged.ids[i] != 0 && !(ranged.depth[i] >= low && ranged.depth[i] <= high)) {
                ++outside;
              }
            }
            EXPECT_EQ(outside, 0) << runName(run, range);
          }
        }
      }
    }
  }
}

// The old reversed-Z recipe compared as if drawn with (0, 1): every compared depth is wrong.
TEST_F(DepthRange, ARangeTheCompareDoesNotKnowIsCaught) {
  const Scene scene = loadScene(testing::sourcePath("scenes/standard.json"));
  const Camera& camera = scene.cameras.at(0);
  const engine::AnalyticPass pass =
      engine::runAnalyticPass(scene, camera, kNegativeOneToOne, camera.viewport);
  const RasterFrame raster = drawn(renderer(), pass, DepthFormat::Float32, {1.0, 0.0});
  const engine::ComparedRun run = engine::compareRasterFrame(
      pass, raster, DepthFormat::Float32, VertexMode::World, renderer().info().subpixelBits, {});
  EXPECT_FALSE(run.run.metrics.consistent());
  EXPECT_GT(run.run.metrics.depthCompared, 1000);
  EXPECT_EQ(run.run.metrics.depthBeyondTolerance, run.run.metrics.depthCompared);
}

}  // namespace
}  // namespace clipray
