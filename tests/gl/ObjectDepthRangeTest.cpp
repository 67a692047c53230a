// A depth range per object (MeshObject::depthRange): a first-person weapon drawn with
// glDepthRange(0, 0.1) in front of a world drawn with (0.1, 1) shows whole, even where it reaches
// through a nearer wall, because the depth test compares window depths. The rays trace each range
// apart and keep the hit the depth test keeps (engine/DrawStateGroups.hpp); a compare that does
// not know the weapon's range is caught.

#include <gtest/gtest.h>

#include <optional>
#include <string>
#include <utility>
#include <vector>

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

class ObjectDepthRange : public GlTest {};

struct Ranges {
  const char* name;
  glm::dvec2 world, weapon;
};

// The ranges that put the weapon in front for each depth test: the near end of the window depths
// is 0 under GL_LESS, 1 under GL_GREATER (reversed-Z, and the old recipe's reversed range).
Ranges rangesFor(DepthMode mode, bool reversedRange) {
  if (mode.reversed) return {"reversed-z", {0.0, 0.9}, {0.9, 1.0}};
  if (reversedRange) return {"reversed range", {0.9, 0.0}, {1.0, 0.9}};
  return {"forward", {0.1, 1.0}, {0.0, 0.1}};
}

Scene weaponScene(const Ranges& ranges) {
  Scene scene = loadScene(testing::sourcePath("scenes/object_depth_range.json"));
  scene.depthRange = ranges.world;
  for (MeshObject& object : scene.objects) {
    if (object.name == "weapon") object.depthRange = ranges.weapon;
  }
  return scene;
}

TEST_F(ObjectDepthRange, TheWeaponShowsWholeThroughTheNearerWallUnderEveryState) {
  int runs = 0;
  // The rays are those of the lower-left view under every state: the same pixels show the weapon.
  std::optional<std::pair<int, int>> firstCounts;
  for (const DepthMode lowerLeft : testing::kLowerLeftModes) {
    for (const DepthMode mode : {lowerLeft, testing::upperLeft(lowerLeft)}) {
      for (const bool reversedRange : {false, true}) {
        if (reversedRange && mode.reversed) continue;
        const Ranges ranges = rangesFor(mode, reversedRange);
        const Scene scene = weaponScene(ranges);
        const std::size_t weapon = objectIndex(scene, "weapon");
        const std::size_t wall = objectIndex(scene, "wall");
        const Camera& camera = scene.cameras.at(0);
        const std::string name = mode.name() + " " + ranges.name;
        const engine::AnalyticPass pass =
            engine::runAnalyticPass(scene, camera, mode, camera.viewport);

        // The rays: the weapon where it lies behind the wall, which the nearest hit would miss.
        const Viewport viewport = camera.viewport;
        std::vector<Ray> row(static_cast<std::size_t>(viewport.width));
        int behindWall = 0, weaponHits = 0;
        for (int y = 0; y < viewport.height; ++y) {
          pass.frame.pixelCentreRays->row(y, 0, viewport.width, row.data());
          for (int x = 0; x < viewport.width; ++x) {
            const std::uint32_t shown =
                pass.frame.hits[static_cast<std::size_t>(y) * viewport.width + x].primitiveId;
            if (!ofObject(scene, weapon, shown)) continue;
            ++weaponHits;
            const Hit nearest = pass.intersector->closestHit(row[static_cast<std::size_t>(x)]);
            behindWall += ofObject(scene, wall, nearest.primitiveId) ? 1 : 0;
          }
        }
        EXPECT_GT(behindWall, 300) << name;
        if (!firstCounts) firstCounts = {weaponHits, behindWall};
        EXPECT_EQ(std::make_pair(weaponHits, behindWall), *firstCounts) << name;
        EXPECT_LT(behindWall, weaponHits) << name;

        // The weapon drawn alone covers the same pixels as in the frame: nothing hides it.
        Scene alone = scene;
        alone.objects = {scene.objects[weapon]};
        for (const DepthFormat format : testing::kDepthFormats) {
          gl::RenderRequest request = engine::renderRequest(pass, format, VertexMode::World);
          const RasterFrame frame = renderer().render(request);
          request.scene = &alone;
          const RasterFrame weaponOnly = renderer().render(request);
          int inFrame = 0, drawnAlone = 0;
          for (std::size_t i = 0; i < frame.ids.size(); ++i) {
            inFrame += ofObject(scene, weapon, frame.ids[i]) ? 1 : 0;
            drawnAlone += weaponOnly.ids[i] != 0 ? 1 : 0;
          }
          EXPECT_EQ(inFrame, drawnAlone) << name << " " << depthFormatName(format);

          const engine::ComparedRun run = engine::compareRasterFrame(
              pass, frame, format, VertexMode::World, renderer().info().subpixelBits, {});
          EXPECT_TRUE(run.run.metrics.consistent())
              << name << " " << depthFormatName(format) << ": depth beyond "
              << run.run.metrics.depthBeyondTolerance << ", ids unexplained "
              << run.run.metrics.idMismatch.unexplained << ", coverage unexplained "
              << run.run.metrics.coverageMismatch.unexplained;
          EXPECT_GT(run.run.metrics.depthCompared, run.run.metrics.rayHits * 9 / 10) << name;
          ++runs;
        }
      }
    }
  }
  // Three formats each: the 4 modes without reversed-Z (2 conventions, 2 origins) with a forward
  // and a reversed range, and the 2 reversed-Z modes with a forward one.
  EXPECT_EQ(runs, 30);
}

// The bug the per-object range hides when the compare is not told: the rays keep the nearest
// surface and map every depth with the scene's range, while the picture shows the weapon through
// the wall at the weapon's depths.
TEST_F(ObjectDepthRange, ACompareThatDoesNotKnowTheWeaponsRangeIsCaught) {
  const Scene ranged = weaponScene(rangesFor(kZeroToOne, false));
  Scene undeclared = ranged;
  for (MeshObject& object : undeclared.objects) object.depthRange.reset();
  const Camera& camera = ranged.cameras.at(0);
  const engine::AnalyticPass pass =
      engine::runAnalyticPass(undeclared, camera, kZeroToOne, camera.viewport);
  gl::RenderRequest request = engine::renderRequest(pass, DepthFormat::Float32, VertexMode::World);
  request.scene = &ranged;
  const RasterFrame raster = renderer().render(request);
  const engine::ComparedRun run = engine::compareRasterFrame(
      pass, raster, DepthFormat::Float32, VertexMode::World, renderer().info().subpixelBits, {});
  EXPECT_FALSE(run.run.metrics.consistent());
  EXPECT_GT(run.run.metrics.idMismatch.unexplained, 300);
  EXPECT_GT(run.run.metrics.depthBeyondTolerance, 100);
}

}  // namespace
}  // namespace clipray
