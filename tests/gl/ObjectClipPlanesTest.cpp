// User clip planes per object (MeshObject::clipPlanes): a section view cuts one object (a house,
// closed, cut by [-1, 0, 0, 0.3]) and leaves the rest whole. GL clips that draw by the camera's
// planes and its own; the rays of its objects are cut by both (engine/DrawStateGroups.hpp), the
// tolerance model's screen polygons too, and a pixel the screen path decided from its planes goes
// along the house's ray where the compare must test it. A compare that does not know the object's
// planes is caught.

#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <cstdio>

#include <optional>
#include <string>
#include <tuple>
#include <vector>

#include "clipray/compare/PrimitiveClipPlanes.hpp"
#include "clipray/engine/ReconcileRun.hpp"
#include "clipray/scene/Scene.hpp"
#include "support/AnalyticPathFor.hpp"
#include "support/GlFixture.hpp"
#include "support/PlanePixelChecks.hpp"
#include "support/RunStates.hpp"
#include "support/SceneObjects.hpp"

namespace clipray {
namespace {

using testing::GlTest;
using testing::objectIndex;

class ObjectClipPlanes : public GlTest {};

Scene sectionScene() {
  return loadScene(testing::sourcePath("scenes/object_clip_planes.json"));
}

// What the rays of a pass show: the house's inside (a face seen from behind), the ground beyond
// the house's plane (x > 0.3, which the house's plane would cut), and any hit on a point the
// house's plane removes (none may be on the house).
struct Shown {
  int houseInside = 0, groundBeyondPlane = 0, houseBeyondPlane = 0;
  bool operator==(const Shown&) const = default;
};

Shown shownBy(const engine::AnalyticPass& pass, const Scene& scene) {
  const PrimitiveIdTable ids(scene);
  const std::size_t house = objectIndex(scene, "house"), ground = objectIndex(scene, "ground");
  const auto ofObject = [&](std::size_t object, std::uint32_t id) {
    return id >= ids.firstIdOfObject[object] &&
           id < ids.firstIdOfObject[object] + scene.objects[object].triangles.size();
  };
  const Viewport viewport = pass.camera.viewport;
  std::vector<Ray> row(static_cast<std::size_t>(viewport.width));
  Shown shown;
  for (int y = 0; y < viewport.height; ++y) {
    pass.frame.pixelCentreRays->row(y, 0, viewport.width, row.data());
    for (int x = 0; x < viewport.width; ++x) {
      Hit hit = pass.frame.hits[static_cast<std::size_t>(y) * viewport.width + x];
      if (!hit.hit()) continue;
      const Ray& ray = row[static_cast<std::size_t>(x)];
      // A hit the screen path decided from its triangle's planes has no t: the triangle's test
      // along the ray gives it (the ground is drawn along the frame's rays).
      if (std::isnan(hit.t)) hit = pass.intersector->intersectOne(hit.primitiveId, ray);
      const glm::dvec3 point = ray.origin + hit.t * ray.direction;
      if (ofObject(house, hit.primitiveId)) {
        const std::array<glm::dvec3, 3> v = pass.intersector->worldTriangle(hit.primitiveId);
        const glm::dvec3 normal = glm::cross(v[1] - v[0], v[2] - v[0]);
        shown.houseInside += glm::dot(normal, ray.direction) > 0.0 ? 1 : 0;
        shown.houseBeyondPlane += point.x > 0.3 + 1e-9 ? 1 : 0;
      }
      if (ofObject(ground, hit.primitiveId) && point.x > 0.3) ++shown.groundBeyondPlane;
    }
  }
  return shown;
}

TEST_F(ObjectClipPlanes, TheHouseShowsItsInsideThroughItsOwnCutUnderEveryState) {
  const Scene scene = sectionScene();
  ASSERT_EQ(scene.objects.at(objectIndex(scene, "house")).clipPlanes,
            (std::vector<glm::dvec4>{{-1.0, 0.0, 0.0, 0.3}}));
  const Camera& camera = scene.cameras.at(0);
  std::optional<Shown> first;
  int runs = 0;
  for (const DepthMode lowerLeft : testing::kLowerLeftModes) {
    for (const DepthMode mode : {lowerLeft, testing::upperLeft(lowerLeft)}) {
      const engine::AnalyticPass pass =
          engine::runAnalyticPass(scene, camera, mode, camera.viewport);
      const Shown shown = shownBy(pass, scene);
      EXPECT_GT(shown.houseInside, 2000) << mode.name();
      EXPECT_GT(shown.groundBeyondPlane, 5000) << mode.name();
      EXPECT_EQ(shown.houseBeyondPlane, 0) << mode.name();
      // The rays are those of the lower-left view under every state.
      if (!first) first = shown;
      EXPECT_EQ(shown, *first) << mode.name();
      for (const DepthFormat format : testing::kDepthFormats) {
        for (const VertexMode vertexMode : {VertexMode::World, VertexMode::Pretransformed}) {
          const RunRecord run =
              engine::rasterAndCompare(renderer(), pass, format, vertexMode, false);
          EXPECT_TRUE(run.metrics.consistent())
              << mode.name() << " " << depthFormatName(format) << ": coverage unexplained "
              << run.metrics.coverageMismatch.unexplained << ", ids unexplained "
              << run.metrics.idMismatch.unexplained << ", depth beyond "
              << run.metrics.depthBeyondTolerance;
          EXPECT_GT(run.metrics.depthCompared, run.metrics.rayHits * 9 / 10) << mode.name();
          ++runs;
        }
      }
    }
  }
  EXPECT_EQ(runs, 6 * 3 * 2);
}

// The camera's planes and the object's together: a camera plane keeping y >= 0.2 cuts the ground
// away and the house's floor with it; the house is cut by both.
// The house's pixels the screen path decided from its planes, seen through its cut: where the
// compare goes along the ray for one (its class open), it gets the ray path's hit bit for bit,
// along the house's ray (the frame's cut by its plane, which moves its start into the house) with
// t given along the frame's. Tracing the frame's uncut ray instead moves t.
TEST_F(ObjectClipPlanes, APixelDecidedFromPlanesGetsTheRayPathsHitAlongItsObjectsRay) {
  const Scene scene = sectionScene();
  const Camera& camera = scene.cameras.at(0);
  const std::size_t house = objectIndex(scene, "house");
  const PrimitiveIdTable ids(scene);
  const PrimitiveClipPlanes objectPlanes(scene);
  int alongOwnRays = 0, tMovedByTheFramesRay = 0;
  for (const DepthMode lowerLeft : testing::kLowerLeftModes) {
    const engine::AnalyticPass rays = [&] {
      const testing::AnalyticPathFor path(AnalyticPath::Rays);
      return engine::runAnalyticPass(scene, camera, lowerLeft, camera.viewport);
    }();
    const engine::AnalyticPass screen = [&] {
      const testing::AnalyticPathFor path(AnalyticPath::Screen);
      return engine::runAnalyticPass(scene, camera, lowerLeft, camera.viewport);
    }();
    ASSERT_TRUE(screen.frame.planesById) << lowerLeft.name();
    for (const testing::PlanePixel& pixel :
         testing::planePixelsAsTheRayPathHitsThem(screen, rays, objectPlanes, lowerLeft.name())) {
      const std::uint32_t id = pixel.hit.primitiveId;
      if (id < ids.firstIdOfObject[house] ||
          id >= ids.firstIdOfObject[house] + scene.objects[house].triangles.size()) {
        continue;
      }
      ++alongOwnRays;
      const Hit uncut = screen.intersector->intersectOne(id, pixel.ray);
      tMovedByTheFramesRay += uncut.t != pixel.hit.t ? 1 : 0;
    }
  }
  std::printf(
      "%d of the house's plane pixels along its own rays, the ray path's hit each; the "
      "frame's uncut ray moves t at %d\n",
      alongOwnRays, tMovedByTheFramesRay);
  EXPECT_GT(alongOwnRays, 3000);
  EXPECT_GT(tMovedByTheFramesRay, alongOwnRays / 10);
}

TEST_F(ObjectClipPlanes, TheCamerasPlanesAndTheObjectsCutTogether) {
  Scene scene = sectionScene();
  scene.cameras.at(0).clipPlanes = {{0.0, 1.0, 0.0, -0.2}};
  const Camera& camera = scene.cameras.at(0);
  for (const DepthMode mode : {kZeroToOne, testing::upperLeft(kNegativeOneToOne)}) {
    const engine::AnalyticPass pass = engine::runAnalyticPass(scene, camera, mode, camera.viewport);
    const Shown shown = shownBy(pass, scene);
    EXPECT_EQ(shown.groundBeyondPlane, 0) << mode.name();
    EXPECT_EQ(shown.houseBeyondPlane, 0) << mode.name();
    EXPECT_GT(shown.houseInside, 2000) << mode.name();
    const RunRecord run =
        engine::rasterAndCompare(renderer(), pass, DepthFormat::Unorm24, VertexMode::World, false);
    EXPECT_TRUE(run.metrics.consistent()) << mode.name();
  }
}

// A compare that does not know the house's plane: the rays see its outside where the picture
// shows its inside and the ground behind it.
TEST_F(ObjectClipPlanes, ACompareThatDoesNotKnowTheObjectsPlanesIsCaught) {
  const Scene cut = sectionScene();
  Scene whole = cut;
  for (MeshObject& object : whole.objects) object.clipPlanes.clear();
  const Camera& camera = cut.cameras.at(0);
  const engine::AnalyticPass pass =
      engine::runAnalyticPass(whole, camera, kZeroToOne, camera.viewport);
  gl::RenderRequest request = engine::renderRequest(pass, DepthFormat::Float32, VertexMode::World);
  request.scene = &cut;
  const RasterFrame raster = renderer().render(request);
  const engine::ComparedRun run = engine::compareRasterFrame(
      pass, raster, DepthFormat::Float32, VertexMode::World, renderer().info().subpixelBits, {});
  EXPECT_FALSE(run.run.metrics.consistent());
  EXPECT_GT(run.run.metrics.idMismatch.unexplained, 2000);
}

}  // namespace
}  // namespace clipray
