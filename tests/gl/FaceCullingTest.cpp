// Face culling (GL 4.6 14.6.1): glCullFace and glFrontFace per object, the facing decided by the
// winding on screen. The rays cull the faces the picture culls under every convention, clip
// origin and depth format; the y-flipped projection of an upper-left run flips the winding as a
// y flip does in GL (the classic mistake: its back faces are drawn unless glFrontFace(GL_CW)),
// and a mirrored object shows its inside.

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

// scenes/standard.json (a ground quad, a box and a tetrahedron, wound counter-clockwise seen from
// outside) with a mirror image of the box: reflected through the plane x = -1.5 and lifted off
// the ground, its triangles keep their index order, so seen from outside they wind clockwise.
Scene standardWithMirroredBox(CullFace cull, FrontFace frontFace) {
  Scene scene = loadScene(testing::sourcePath("scenes/standard.json"));
  MeshObject mirrored = scene.objects.at(1);
  mirrored.name = "mirrored_box";
  for (glm::dvec3& p : mirrored.worldPositions) {
    p.x = -3.0 - p.x;
    p.y += 0.25;  // off the ground: its bottom face would tie with the ground
  }
  scene.objects.push_back(mirrored);
  for (MeshObject& object : scene.objects) {
    object.cull = cull;
    object.frontFace = frontFace;
  }
  return scene;
}

std::string runName(const RunRecord& run, CullFace cull, FrontFace frontFace) {
  return run.convention.name() + " " + depthFormatName(run.depthFormat) + " cull " +
         cullFaceName(cull) + " front " + frontFaceName(frontFace);
}

// Whether a triangle winds counter-clockwise seen from the eye: its index-order normal points
// towards the eye. Computed in world space, independently of the clip-space rule clipray uses.
bool windsCounterClockwiseFromEye(const std::array<glm::dvec3, 3>& t, const glm::dvec3& eye) {
  return glm::dot(glm::cross(t[1] - t[0], t[2] - t[0]), eye - t[0]) > 0.0;
}

class FaceCulling : public GlTest {};

// Every cull mode and front face under every convention and origin: raster and rays agree, no
// pixel shows a triangle the rays cull, and every triangle shown has the facing GL keeps: front
// for GL_BACK, back for GL_FRONT, where front is the winding glFrontFace names as the built
// projection draws it (a lower-left one as the eye sees it, an upper-left one y-flipped).
TEST_F(FaceCulling, TheRaysCullWhatThePictureCulls) {
  for (const CullFace cull : {CullFace::Back, CullFace::Front}) {
    for (const FrontFace frontFace : {FrontFace::Ccw, FrontFace::Cw}) {
      const Scene scene = standardWithMirroredBox(cull, frontFace);
      const Camera& camera = scene.cameras.at(0);
      const glm::dvec3 eye(glm::inverse(camera.viewFromWorld)[3]);
      for (const DepthMode lowerMode : testing::kLowerLeftModes) {
        for (const DepthMode mode : {lowerMode, testing::upperLeft(lowerMode)}) {
          const engine::AnalyticPass pass =
              engine::runAnalyticPass(scene, camera, mode, camera.viewport);
          const SceneIntersector& intersector = *pass.intersector;
          // Closed meshes seen from outside: about half their triangles face each way.
          EXPECT_GT(intersector.culledCount(), 10u) << mode.name();
          EXPECT_LT(intersector.culledCount(), intersector.triangleCount() - 10) << mode.name();
          const bool flipped = mode.origin == ClipOrigin::UpperLeft;
          const bool ccwIsFront = (frontFace == FrontFace::Ccw) != flipped;
          const bool keepsFront = cull == CullFace::Back;
          for (const DepthFormat format : testing::kDepthFormats) {
            const RasterFrame raster =
                renderer().render(engine::renderRequest(pass, format, VertexMode::World));
            const RunRecord run =
                engine::rasterAndCompare(renderer(), pass, format, VertexMode::World, false);
            const std::string name = runName(run, cull, frontFace);
            EXPECT_TRUE(run.metrics.consistent()) << name;
            // The ground is a single quad: culled where the boxes show their insides.
            EXPECT_GT(run.metrics.depthCompared, 2000) << name;
            int culledShown = 0;
            int wrongFacing = 0;
            for (const std::uint32_t id : raster.ids) {
              if (id == 0 || intersector.isAnalytic(id)) continue;
              culledShown += intersector.culled(id);
              const bool front =
                  windsCounterClockwiseFromEye(intersector.worldTriangle(id), eye) == ccwIsFront;
              wrongFacing += front != keepsFront;
            }
            EXPECT_EQ(culledShown, 0) << name;
            EXPECT_EQ(wrongFacing, 0) << name;
          }
        }
      }
    }
  }
}

// A D3D-style app's y-flipped projection under GL_UPPER_LEFT: the picture is upright, but the
// winding on screen is reversed, so glCullFace(GL_BACK) with glFrontFace(GL_CCW) draws exactly what
// the lower-left run draws with GL_FRONT (the insides), and glFrontFace(GL_CW) restores the
// lower-left picture: every id and depth the same.
TEST_F(FaceCulling, AnUpperLeftProjectionFlipsTheWindingAsAYFlipDoes) {
  const Scene backCcw = standardWithMirroredBox(CullFace::Back, FrontFace::Ccw);
  const Scene frontCcw = standardWithMirroredBox(CullFace::Front, FrontFace::Ccw);
  const Scene backCw = standardWithMirroredBox(CullFace::Back, FrontFace::Cw);
  const Camera& camera = backCcw.cameras.at(0);
  const Viewport viewport = camera.viewport;
  for (const DepthMode mode : testing::kLowerLeftModes) {
    const engine::AnalyticPass upperBackCcw =
        engine::runAnalyticPass(backCcw, camera, testing::upperLeft(mode), viewport);
    const engine::AnalyticPass lowerFrontCcw =
        engine::runAnalyticPass(frontCcw, camera, mode, viewport);
    const engine::AnalyticPass upperBackCw =
        engine::runAnalyticPass(backCw, camera, testing::upperLeft(mode), viewport);
    const engine::AnalyticPass lowerBackCcw =
        engine::runAnalyticPass(backCcw, camera, mode, viewport);
    EXPECT_EQ(upperBackCcw.intersector->culledCount(), lowerFrontCcw.intersector->culledCount());
    EXPECT_EQ(upperBackCw.intersector->culledCount(), lowerBackCcw.intersector->culledCount());
    for (const DepthFormat format : testing::kDepthFormats) {
      const auto draw = [&](const engine::AnalyticPass& pass) {
        return renderer().render(engine::renderRequest(pass, format, VertexMode::World));
      };
      const RasterFrame a = draw(upperBackCcw);
      const RasterFrame b = draw(lowerFrontCcw);
      EXPECT_TRUE(a.ids == b.ids) << mode.name() << " " << depthFormatName(format);
      EXPECT_TRUE(a.depth == b.depth) << mode.name() << " " << depthFormatName(format);
      const RasterFrame c = draw(upperBackCw);
      const RasterFrame d = draw(lowerBackCcw);
      EXPECT_TRUE(c.ids == d.ids) << mode.name() << " " << depthFormatName(format);
      EXPECT_TRUE(c.depth == d.depth) << mode.name() << " " << depthFormatName(format);
      // And the culled pictures differ from each other: culling is in effect.
      EXPECT_FALSE(a.ids == c.ids) << mode.name() << " " << depthFormatName(format);
    }
  }
}

// The mirrored box with GL_BACK and GL_CCW: its near faces wind clockwise and are culled, so every
// ray that meets it without culling at its near side meets its far side instead, further away;
// the unmirrored box keeps its near faces and every such ray's hit.
TEST_F(FaceCulling, AMirroredObjectShowsItsInside) {
  const testing::AnalyticPathFor rays(AnalyticPath::Rays);  // every hit's t
  const Scene culled = standardWithMirroredBox(CullFace::Back, FrontFace::Ccw);
  const Scene whole = standardWithMirroredBox(CullFace::None, FrontFace::Ccw);
  const Camera& camera = culled.cameras.at(0);
  const PrimitiveIdTable ids(culled);
  const int box = 1;
  const int mirrored = 3;
  for (const DepthMode mode : testing::kLowerLeftModes) {
    const engine::AnalyticPass a = engine::runAnalyticPass(culled, camera, mode, camera.viewport);
    const engine::AnalyticPass b = engine::runAnalyticPass(whole, camera, mode, camera.viewport);
    int mirroredPixels = 0;
    int boxPixels = 0;
    for (std::size_t i = 0; i < b.frame.hits.size(); ++i) {
      const Hit& unculled = b.frame.hits[i];
      const int object = ids.decode(unculled.primitiveId).object;
      const Hit& hit = a.frame.hits[i];
      if (object == mirrored) {
        ++mirroredPixels;
        EXPECT_EQ(ids.decode(hit.primitiveId).object, mirrored) << mode.name() << " pixel " << i;
        EXPECT_GT(hit.t, unculled.t) << mode.name() << " pixel " << i;
      }
      if (object == box) {
        ++boxPixels;
        EXPECT_EQ(hit.primitiveId, unculled.primitiveId) << mode.name() << " pixel " << i;
        EXPECT_EQ(hit.t, unculled.t) << mode.name() << " pixel " << i;
      }
    }
    EXPECT_GT(mirroredPixels, 1000) << mode.name();
    EXPECT_GT(boxPixels, 1000) << mode.name();
  }
}

}  // namespace
}  // namespace clipray
