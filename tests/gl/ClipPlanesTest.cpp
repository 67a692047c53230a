// User clip planes (gl_ClipDistance, GL 4.6 13.7.1): a camera's world-space planes clip what the
// picture shows, and the rays start and end where the planes let them. Raster and rays agree
// under every convention, clip origin, depth format and vertex mode; a raster clipped while the
// rays are not is caught.

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "clipray/engine/ReconcileRun.hpp"
#include "clipray/scene/Scene.hpp"
#include "support/AnalyticPathFor.hpp"
#include "support/GlFixture.hpp"
#include "support/RunStates.hpp"

namespace clipray {
namespace {

using testing::GlTest;

const std::vector<VertexMode> kVertexModes = {VertexMode::World, VertexMode::CameraRelative,
                                              VertexMode::Pretransformed};

// scenes/standard.json cut by two planes: y <= 0.8 (the box's top and the tetrahedron's tip go,
// so the box shows its inside) and x + 0.3 z >= -0.5 (the ground's left part goes).
const std::vector<glm::dvec4> kPlanes = {{0.0, -1.0, 0.0, 0.8}, {1.0, 0.0, 0.3, 0.5}};

Scene clippedStandard() {
  Scene scene = loadScene(testing::sourcePath("scenes/standard.json"));
  scene.cameras.at(0).clipPlanes = kPlanes;
  return scene;
}

class ClipPlanes : public GlTest {};

TEST_F(ClipPlanes, RasterAndRaysAgreeAndEveryHitIsKept) {
  const Scene scene = clippedStandard();
  const Camera& camera = scene.cameras.at(0);
  for (const DepthMode lowerMode : testing::kLowerLeftModes) {
    for (const DepthMode mode : {lowerMode, testing::upperLeft(lowerMode)}) {
      const engine::AnalyticPass pass =
          engine::runAnalyticPass(scene, camera, mode, camera.viewport);
      for (const DepthFormat format : testing::kDepthFormats) {
        for (const VertexMode vertexMode : kVertexModes) {
          const RunRecord run =
              engine::rasterAndCompare(renderer(), pass, format, vertexMode, false);
          const std::string name =
              mode.name() + " " + depthFormatName(format) + " " + vertexModeName(vertexMode);
          EXPECT_TRUE(run.metrics.consistent()) << name;
          EXPECT_EQ(run.metrics.coverageMismatch.unexplained, 0) << name;
          EXPECT_GT(run.metrics.depthCompared, 20000) << name;
        }
      }
    }
  }
}

// What the planes remove: the unclipped camera's hits above y = 0.8 or left of the second plane
// are gone from the clipped rays (and from its picture, which agrees with them); every clipped
// hit is kept by both planes.
TEST_F(ClipPlanes, TheRaysStartWhereThePlanesLetThem) {
  const testing::AnalyticPathFor rays(AnalyticPath::Rays);  // every hit's t
  const Scene clipped = clippedStandard();
  const Scene open = loadScene(testing::sourcePath("scenes/standard.json"));
  const Camera& camera = clipped.cameras.at(0);
  const engine::AnalyticPass a =
      engine::runAnalyticPass(clipped, camera, kZeroToOne, camera.viewport);
  const engine::AnalyticPass b =
      engine::runAnalyticPass(open, open.cameras.at(0), kZeroToOne, camera.viewport);
  const PixelCentreRays clippedRays(a.camera.clipFromWorld, a.camera.mode, camera.viewport,
                                    kPlanes);
  const PixelCentreRays openRays(b.camera.clipFromWorld, b.camera.mode, camera.viewport);
  int removed = 0, outside = 0;
  Ray clippedRay, openRay;
  for (int y = 0; y < camera.viewport.height; ++y) {
    for (int x = 0; x < camera.viewport.width; ++x) {
      const std::size_t i = static_cast<std::size_t>(y) * camera.viewport.width + x;
      clippedRays.row(y, x, 1, &clippedRay);
      openRays.row(y, x, 1, &openRay);
      const Hit& hit = a.frame.hits[i];
      if (hit.hit()) {
        const glm::dvec4 p(clippedRay.origin + hit.t * clippedRay.direction, 1.0);
        for (const glm::dvec4& plane : kPlanes) outside += glm::dot(plane, p) < -1e-9;
      }
      const Hit& openHit = b.frame.hits[i];
      if (!openHit.hit()) continue;
      const glm::dvec4 q(openRay.origin + openHit.t * openRay.direction, 1.0);
      removed += glm::dot(kPlanes[0], q) < 0.0 || glm::dot(kPlanes[1], q) < 0.0;
    }
  }
  EXPECT_EQ(outside, 0);
  EXPECT_GT(removed, 5000);
}

// The test of the test: the picture clipped, the rays not (the scene forgot the planes the app
// draws with). Whatever the planes removed is a coverage mismatch nothing explains.
TEST_F(ClipPlanes, ARasterClippedWhileTheRaysAreNotIsCaught) {
  const Scene open = loadScene(testing::sourcePath("scenes/standard.json"));
  const Camera& camera = open.cameras.at(0);
  const engine::AnalyticPass pass =
      engine::runAnalyticPass(open, camera, kZeroToOne, camera.viewport);
  gl::RenderRequest request = engine::renderRequest(pass, DepthFormat::Float32, VertexMode::World);
  request.clipPlanes = kPlanes;
  const RasterFrame raster = renderer().render(request);
  const engine::ComparedRun compared = engine::compareRasterFrame(
      pass, raster, DepthFormat::Float32, VertexMode::World, renderer().info().subpixelBits, {}, 1);
  EXPECT_FALSE(compared.run.metrics.consistent());
  EXPECT_GT(compared.run.metrics.coverageMismatch.unexplained, 5000);
}

}  // namespace
}  // namespace clipray
