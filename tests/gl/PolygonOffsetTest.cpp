// Polygon offset (MeshObject::polygonOffset, GL 4.6 14.6.5): a decal coplanar with a slanted wall
// (scenes/polygon_offset.json) drawn with an offset that pushes it toward the camera under the
// depth test in use (negative under GL_LESS, positive under reversed-Z's GL_GREATER) shows at every
// pixel it covers, agrees with the rays under every convention, origin and depth format, and its
// measured offsets lie in the interval the model predicts; a compare not told about the offset is
// caught.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>

#include "clipray/engine/ReconcileRun.hpp"
#include "clipray/scene/Scene.hpp"
#include "support/GlFixture.hpp"
#include "support/RunStates.hpp"
#include "support/SceneObjects.hpp"

namespace clipray {
namespace {

using testing::GlTest;
using testing::objectIndex;
using testing::ofObject;

class PolygonOffsetDraw : public GlTest {};

// The shipped scene, its decal's offset pushed toward the camera under the mode's depth test: the
// scene's (-1, -2) under GL_LESS, (1, 2) under reversed-Z.
Scene decalScene(DepthMode mode) {
  Scene scene = loadScene(testing::sourcePath("scenes/polygon_offset.json"));
  for (MeshObject& object : scene.objects) {
    if (object.name == "decal" && mode.reversed) {
      object.polygonOffset->factor = -object.polygonOffset->factor;
      object.polygonOffset->units = -object.polygonOffset->units;
    }
  }
  return scene;
}

TEST_F(PolygonOffsetDraw, TheDecalShowsWholeAndItsOffsetLiesInThePredictedInterval) {
  int runs = 0;
  for (const DepthMode lowerLeft : testing::kLowerLeftModes) {
    for (const DepthMode mode : {lowerLeft, testing::upperLeft(lowerLeft)}) {
      const Scene scene = decalScene(mode);
      const std::size_t decal = objectIndex(scene, "decal");
      const Camera& camera = scene.cameras.at(0);
      const engine::AnalyticPass pass =
          engine::runAnalyticPass(scene, camera, mode, camera.viewport);
      Scene alone = scene;
      alone.objects = {scene.objects[decal]};
      for (const DepthFormat format : testing::kDepthFormats) {
        const std::string name = mode.name() + " " + depthFormatName(format);
        gl::RenderRequest request = engine::renderRequest(pass, format, VertexMode::World);
        const RasterFrame frame = renderer().render(request);
        request.scene = &alone;
        const RasterFrame decalOnly = renderer().render(request);
        // The decal wins every pixel it covers: the wall under it never shows through.
        int inFrame = 0, drawnAlone = 0;
        for (std::size_t i = 0; i < frame.ids.size(); ++i) {
          inFrame += ofObject(scene, decal, frame.ids[i]) ? 1 : 0;
          drawnAlone += decalOnly.ids[i] != 0 ? 1 : 0;
        }
        EXPECT_EQ(inFrame, drawnAlone) << name;
        EXPECT_GT(drawnAlone, 3000) << name;

        const engine::ComparedRun run = engine::compareRasterFrame(
            pass, frame, format, VertexMode::World, renderer().info().subpixelBits, {});
        const RunMetrics& m = run.run.metrics;
        EXPECT_TRUE(m.consistent()) << name << ": depth beyond " << m.depthBeyondTolerance
                                    << ", ids unexplained " << m.idMismatch.unexplained
                                    << ", coverage unexplained " << m.coverageMismatch.unexplained;
        ASSERT_EQ(run.run.polygonOffsets.size(), 1u) << name;
        const OffsetRecord& offset = run.run.polygonOffsets[0];
        EXPECT_EQ(offset.object, "decal");
        // Every decal pixel the rays hit too (the others are at its edges).
        EXPECT_GT(offset.pixels, drawnAlone * 9 / 10) << name;
        // Toward the camera: below the wall's depth under GL_LESS, above it under GL_GREATER.
        if (mode.reversed) {
          EXPECT_GT(offset.predictedLow, 0.0) << name;
          EXPECT_GT(offset.measuredMin, 0.0) << name;
        } else {
          EXPECT_LT(offset.predictedHigh, 0.0) << name;
          EXPECT_LT(offset.measuredMax, 0.0) << name;
        }
        // Measured within the predicted interval, widened by the depth's own rounding: one
        // quantum of the format at the largest depth (a fixed-point buffer rounds to 2^-n, the
        // float buffer's ulp below 1 is at most 2^-24), and the plane's evaluation in float.
        const double quantum = depthQuantum(format, 1.0);
        EXPECT_GE(offset.measuredMin, offset.predictedLow - quantum - 1e-6) << name;
        EXPECT_LE(offset.measuredMax, offset.predictedHigh + quantum + 1e-6) << name;
        std::printf("%s: predicted [%.4g, %.4g] measured [%.4g, %.4g] over %lld pixels\n",
                    name.c_str(), offset.predictedLow, offset.predictedHigh, offset.measuredMin,
                    offset.measuredMax, static_cast<long long>(offset.pixels));
        ++runs;
      }
    }
  }
  EXPECT_EQ(runs, 18);  // 3 conventions, 2 origins, 3 formats
}

// glPolygonOffsetClamp (GL 4.6, ARB_polygon_offset_clamp; llvmpipe has it): the decal's offset,
// about -3.4e-5 unclamped, held at -2e-5; the predicted interval is the clamp itself and the
// compare agrees.
TEST_F(PolygonOffsetDraw, TheClampHoldsTheOffset) {
  for (const DepthFormat format : {DepthFormat::Unorm24, DepthFormat::Float32}) {
    Scene scene = decalScene(kZeroToOne);
    scene.objects[objectIndex(scene, "decal")].polygonOffset->clamp = -2e-5;
    const Camera& camera = scene.cameras.at(0);
    const engine::AnalyticPass pass =
        engine::runAnalyticPass(scene, camera, kZeroToOne, camera.viewport);
    const RasterFrame frame =
        renderer().render(engine::renderRequest(pass, format, VertexMode::World));
    const engine::ComparedRun run = engine::compareRasterFrame(
        pass, frame, format, VertexMode::World, renderer().info().subpixelBits, {});
    EXPECT_TRUE(run.run.metrics.consistent()) << depthFormatName(format);
    ASSERT_EQ(run.run.polygonOffsets.size(), 1u);
    const OffsetRecord& offset = run.run.polygonOffsets[0];
    EXPECT_EQ(offset.predictedLow, -2e-5);
    EXPECT_EQ(offset.predictedHigh, -2e-5);
    // Within two quanta of 2^-24 (the 24-bit quantum, and the 32f ulp below 1): the stored
    // depth's rounding and that of the interpolated depth the offset is added to.
    const double quantum = std::ldexp(1.0, -23);
    EXPECT_GE(offset.measuredMin, -2e-5 - quantum) << depthFormatName(format);
    EXPECT_LE(offset.measuredMax, -2e-5 + quantum) << depthFormatName(format);
  }
}

// The bug the offset hides when the compare is not told: the rays find the decal at its plane's
// depth, the picture stores it moved by the offset, many times the depth tolerance (32f: the
// slope term alone is about a thousand ulps). The decal alone, so that no coplanar wall makes the
// rays' choice between the two a tie.
TEST_F(PolygonOffsetDraw, ACompareThatDoesNotKnowTheOffsetIsCaught) {
  for (const DepthMode mode : {kZeroToOne, kZeroToOneReversed}) {
    Scene offset = decalScene(mode);
    offset.objects = {offset.objects[objectIndex(offset, "decal")]};
    Scene undeclared = offset;
    undeclared.objects[0].polygonOffset.reset();
    const Camera& camera = offset.cameras.at(0);
    const engine::AnalyticPass pass =
        engine::runAnalyticPass(undeclared, camera, mode, camera.viewport);
    gl::RenderRequest request =
        engine::renderRequest(pass, DepthFormat::Float32, VertexMode::World);
    request.scene = &offset;
    const RasterFrame raster = renderer().render(request);
    const engine::ComparedRun run = engine::compareRasterFrame(
        pass, raster, DepthFormat::Float32, VertexMode::World, renderer().info().subpixelBits, {});
    const RunMetrics& m = run.run.metrics;
    EXPECT_FALSE(m.consistent()) << mode.name();
    EXPECT_GT(m.depthCompared, 3000) << mode.name();
    EXPECT_EQ(m.depthBeyondTolerance, m.depthCompared) << mode.name();
    EXPECT_TRUE(run.run.polygonOffsets.empty());
  }
}

}  // namespace
}  // namespace clipray
