// Logarithmic depth written by the mesh fragment shader (Camera::logarithmicDepth): the shipped
// scene (scenes/logarithmic_depth.json: three.js's form and Outerra's) agrees with the rays under
// every convention, clip origin and depth format once the compare maps each hit's clip w the same
// way; a compare not told about the mapping is caught, and so is a depth-buffer picking function
// that unprojects the stored depth as if it were projective, while one that inverts the mapping
// agrees.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <optional>
#include <string>

#include "clipray/engine/ReconcileRun.hpp"
#include "clipray/scene/Scene.hpp"
#include "support/GlFixture.hpp"
#include "support/RunStates.hpp"

namespace clipray {
namespace {

using testing::GlTest;

class LogarithmicDepthDraw : public GlTest {};

Scene logDepthScene() {
  return loadScene(testing::sourcePath("scenes/logarithmic_depth.json"));
}

TEST_F(LogarithmicDepthDraw, ConsistentUnderEveryConventionOriginAndFormat) {
  const Scene scene = logDepthScene();
  int runs = 0;
  for (const Camera& camera : scene.cameras) {
    ASSERT_TRUE(camera.logarithmicDepth.has_value()) << camera.name;
    for (const DepthMode lowerLeft : testing::kLowerLeftModes) {
      for (const DepthMode mode : {lowerLeft, testing::upperLeft(lowerLeft)}) {
        const engine::AnalyticPass pass =
            engine::runAnalyticPass(scene, camera, mode, camera.viewport);
        ASSERT_TRUE(pass.logDepth.has_value());
        EXPECT_EQ(pass.logDepth->reversed(), mode.reversed);
        for (const DepthFormat format : testing::kDepthFormats) {
          const std::string name = camera.name + " " + mode.name() + " " + depthFormatName(format);
          const RunRecord run =
              engine::rasterAndCompare(renderer(), pass, format, VertexMode::World, false);
          const RunMetrics& m = run.metrics;
          EXPECT_TRUE(m.consistent())
              << name << ": depth beyond " << m.depthBeyondTolerance << ", ids unexplained "
              << m.idMismatch.unexplained << ", coverage unexplained "
              << m.coverageMismatch.unexplained;
          // Nearly every pixel shows something (ground to the horizon), and nearly all of them
          // are depth-compared.
          EXPECT_GT(m.depthCompared, m.rayHits * 9 / 10) << name;
          EXPECT_GT(m.rayHits, camera.viewport.width * camera.viewport.height / 3) << name;
          std::printf(
              "%s: %lld compared, |d_r - d_a| max %.3g quanta, tolerance ratio p99 %.3g "
              "max %.3g\n",
              name.c_str(), static_cast<long long>(m.depthCompared), m.depthErrorQuanta.max,
              m.toleranceRatio.p99, m.toleranceRatio.max);
          ++runs;
        }
      }
    }
  }
  EXPECT_EQ(runs, 36);  // 2 cameras, 3 conventions, 2 origins, 3 formats
}

// The raster stores L(w) (1 - L reversed), not the projective depth: a compare that maps hits to
// the projective depth finds every compared pixel beyond tolerance.
TEST_F(LogarithmicDepthDraw, ACompareNotToldAboutTheMappingIsCaught) {
  const Scene scene = logDepthScene();
  for (const DepthMode mode : testing::kLowerLeftModes) {
    for (const DepthFormat format : testing::kDepthFormats) {
      const Camera& camera = scene.cameras.at(0);
      engine::AnalyticPass pass = engine::runAnalyticPass(scene, camera, mode, camera.viewport);
      const RasterFrame frame =
          renderer().render(engine::renderRequest(pass, format, VertexMode::World));
      pass.logDepth.reset();  // the compare now expects the projective depth
      const engine::ComparedRun run = engine::compareRasterFrame(
          pass, frame, format, VertexMode::World, renderer().info().subpixelBits, {});
      const RunMetrics& m = run.run.metrics;
      const std::string name = mode.name() + " " + depthFormatName(format);
      EXPECT_FALSE(m.consistent()) << name;
      // Every compared pixel (the 16-bit frame has two pixels fewer where both sides show the same
      // primitive).
      EXPECT_EQ(m.depthCompared, format == DepthFormat::Unorm16 ? 41821 : 41823) << name;
      EXPECT_EQ(m.depthBeyondTolerance, m.depthCompared) << name;
      std::printf("%s: %lld of %lld compared pixels beyond tolerance\n", name.c_str(),
                  static_cast<long long>(m.depthBeyondTolerance),
                  static_cast<long long>(m.depthCompared));
    }
  }
}

// An app's depth-buffer picking over the frame the renderer drew: the id and depth under the
// pixel, turned into a hit along clipray's robust ray. invertMapping: the clip w whose log depth
// is stored, then the point at that w; otherwise the depth unprojected through the inverse matrix
// as if it were projective (what picking code written for a projective buffer does).
PickHitFunction depthBufferPicking(const Scene& scene, const RasterFrame& frame,
                                   const LogDepthMapping& mapping, bool invertMapping) {
  const PickRayFunction rays = robustPickRays();
  const PrimitiveIdTable ids(scene);
  return [=](int x, int y, const PickingCamera& camera) -> std::optional<PickHit> {
    const std::optional<Ray> ray = rays(x, y, camera);
    if (!ray) return std::nullopt;
    PickHit pick;
    pick.ray = *ray;
    const std::size_t i = static_cast<std::size_t>(y) * camera.viewport.width + x;
    if (frame.ids[i] == 0) return pick;
    const PrimitiveIdTable::Decoded decoded = ids.decode(frame.ids[i]);
    pick.mesh = static_cast<std::size_t>(decoded.object);
    pick.triangle = decoded.triangle;
    const double depth = frame.depth[i];
    const glm::dvec4 rowW(camera.clipFromWorld[0][3], camera.clipFromWorld[1][3],
                          camera.clipFromWorld[2][3], camera.clipFromWorld[3][3]);
    if (invertMapping) {
      const double w = mapping.clipWOfWindowDepth(depth);
      pick.t = (w - glm::dot(rowW, glm::dvec4(ray->origin, 1.0))) /
               glm::dot(glm::dvec3(rowW), ray->direction);
    } else {
      const glm::dvec4 ndc((x + 0.5) / camera.viewport.width * 2.0 - 1.0,
                           (y + 0.5) / camera.viewport.height * 2.0 - 1.0,
                           ndcFromWindowDepth(depth, camera.mode.convention), 1.0);
      const glm::dvec4 world = glm::inverse(camera.clipFromWorld) * ndc;
      pick.t = glm::dot(glm::dvec3(world) / world.w - ray->origin, ray->direction);
    }
    return pick;
  };
}

TEST_F(LogarithmicDepthDraw, DepthBufferPickingMustInvertTheMapping) {
  const Scene scene = logDepthScene();
  const Camera& camera = scene.cameras.at(0);
  for (const DepthMode mode : testing::kLowerLeftModes) {
    for (const DepthFormat format : testing::kDepthFormats) {
      const std::string name = mode.name() + " " + depthFormatName(format);
      const engine::AnalyticPass drawn =
          engine::runAnalyticPass(scene, camera, mode, camera.viewport);
      const RasterFrame frame =
          renderer().render(engine::renderRequest(drawn, format, VertexMode::World));
      for (const bool invert : {true, false}) {
        const engine::AnalyticPass pass =
            engine::runAnalyticPass(scene, camera, mode, camera.viewport,
                                    depthBufferPicking(scene, frame, *drawn.logDepth, invert));
        const engine::ComparedRun run = engine::compareRasterFrame(
            pass, frame, format, VertexMode::World, renderer().info().subpixelBits, {});
        const RunMetrics& m = run.run.metrics;
        // The picking reads the frame's own ids: every pixel agrees on what was hit, and every
        // pixel with a hit is compared.
        EXPECT_EQ(m.depthCompared, 41827) << name;
        EXPECT_EQ(m.idMismatch.total, 0) << name;
        EXPECT_EQ(m.coverageMismatch.total, 0) << name;
        if (invert) {
          EXPECT_TRUE(m.consistent()) << name << ": depth beyond " << m.depthBeyondTolerance;
          EXPECT_EQ(m.depthBeyondTolerance, 0) << name;
        } else {
          EXPECT_FALSE(m.consistent()) << name;
          EXPECT_EQ(m.depthBeyondTolerance, m.depthCompared) << name;
        }
        std::printf("%s, picking %s the mapping: %lld of %lld beyond tolerance\n", name.c_str(),
                    invert ? "inverting" : "ignoring",
                    static_cast<long long>(m.depthBeyondTolerance),
                    static_cast<long long>(m.depthCompared));
      }
    }
  }
}

}  // namespace
}  // namespace clipray
