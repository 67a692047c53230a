// Face culling in the intersector: the triangles the drawn matrix culls are left out of the
// screen bins, the BVH and the linear scan alike, with the same hits bit for bit.

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "clipray/compare/Frames.hpp"
#include "clipray/intersect/SceneIntersector.hpp"
#include "clipray/rays/RobustRays.hpp"
#include "support/FastPathScenes.hpp"

namespace clipray {
namespace {

using namespace testing::fast_path;

// Face culling: with the drawn matrix, the triangles it culls are left out of the bins, the BVH
// and the linear scan alike (still bit for bit the same hits), and the culled ones are exactly
// those whose index-order normal faces away from the eye (the clip-space rule, checked in world
// space: det[x; y; w] of a triangle is the same positive multiple of n . (eye - a) for every
// triangle of a non-mirrored camera, whether or not it crosses the eye plane).
TEST(FastPathBinned, CulledTrianglesAreLeftOutOfEveryQuery) {
  Scene scene = testSceneWithPrimitives();
  scene.objects[0].cull = CullFace::Back;   // the terrain
  scene.objects[1].cull = CullFace::Front;  // the ball: its inside
  const Scene unculled = testSceneWithPrimitives();
  for (const BinnedCase& c : binnedCases()) {
    SCOPED_TRACE(c.name);
    const SceneIntersector reference = intersectorSeenFrom(unculled, c.camera);
    const SceneIntersector intersector(scene, reference.reference(),
                                       SceneIntersector::BvhBuild::WhenFirstNeeded,
                                       c.camera.clipFromWorld);
    EXPECT_EQ(intersector.triangleCount(), reference.triangleCount());
    EXPECT_GT(intersector.culledCount(), intersector.triangleCount() / 4);
    AnalyticFrame frame = generateRobustRays(c.camera, 2);
    EXPECT_EQ(intersectFrame(frame, intersector, c.camera, 2), tileCount(c.camera.viewport));
    expectFrameMatchesTheLinearScan(intersector, frame, c.name);
    std::vector<Hit> walked(frame.rays.size());
    intersector.closestHits(frame.rays, walked);  // packets walking the BVH
    int culledIdHits = 0;
    int fartherOnTheBall = 0;
    int ballPixels = 0;
    const PrimitiveIdTable ids(scene);
    AnalyticFrame whole = generateRobustRays(c.camera, 2);
    intersectFrame(whole, reference, c.camera, 2);
    for (std::size_t i = 0; i < frame.rays.size(); ++i) {
      ASSERT_EQ(walked[i].primitiveId, frame.hits[i].primitiveId) << "pixel " << i;
      ASSERT_EQ(walked[i].t, frame.hits[i].t) << "pixel " << i;
      culledIdHits += intersector.culled(frame.hits[i].primitiveId);
      const bool ballBefore = ids.decode(whole.hits[i].primitiveId).object == 1;
      const bool ballAfter = ids.decode(frame.hits[i].primitiveId).object == 1;
      ballPixels += ballBefore;
      if (ballBefore && ballAfter) fartherOnTheBall += frame.hits[i].t > whole.hits[i].t;
      // Culled: no hit on a culled triangle, and never an earlier hit than without culling.
      ASSERT_GE(frame.hits[i].t, whole.hits[i].t) << "pixel " << i;
      EXPECT_EQ(intersector.intersectOne(whole.hits[i].primitiveId, frame.rays[i]).hit(),
                !intersector.culled(whole.hits[i].primitiveId))
          << "pixel " << i;
    }
    EXPECT_EQ(culledIdHits, 0);
    // The eye: the point clipFromWorld maps to x = y = w = 0 (at infinity for orthographic).
    const glm::dvec4 eye = glm::inverse(c.camera.clipFromWorld) * glm::dvec4(0.0, 0.0, 1.0, 0.0);
    const bool eyeInBall = std::abs(eye.w) > 1e-9 &&
                           glm::distance(glm::dvec3(eye) / eye.w, glm::dvec3(0.5, 1.0, -0.5)) < 0.8;
    // Seen from outside, the ball shows its inside: further away (the terrain crosses the ball,
    // so some rays meet that first). Seen from inside, it shows its inside either way.
    if (eyeInBall) {
      EXPECT_EQ(fartherOnTheBall, 0);
    } else {
      EXPECT_GE(fartherOnTheBall, ballPixels / 2);
    }
    if (std::abs(eye.w) < 1e-9) continue;
    std::uint32_t id = 1;
    for (std::size_t k = 0; k < 2; ++k) {
      const MeshObject& object = scene.objects[k];
      for (const glm::u32vec3& t : object.triangles) {
        const glm::dvec3 a = object.worldPositions[t.x];
        const glm::dvec3 n =
            glm::cross(object.worldPositions[t.y] - a, object.worldPositions[t.z] - a);
        const bool facesEye = glm::dot(n, glm::dvec3(eye) / eye.w - a) > 0.0;
        ASSERT_EQ(intersector.culled(id), facesEye == (object.cull == CullFace::Front))
            << object.name << " triangle " << id;
        ++id;
      }
    }
  }
}

}  // namespace
}  // namespace clipray
