// The automatic cameras of assets that ship without one: framed on the bounds, each seeing what
// its name says.

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "clipray/InputError.hpp"
#include "clipray/scene/AutoCameras.hpp"
#include "clipray/scene/Scene.hpp"

namespace clipray {
namespace {

constexpr DepthMode kModes[] = {kNegativeOneToOne, kZeroToOne, kZeroToOneReversed};

MeshObject box(const std::string& name, glm::dvec3 lo, glm::dvec3 hi) {
  MeshObject mesh;
  mesh.name = name;
  for (int k = 0; k < 8; ++k) {
    mesh.worldPositions.push_back(
        {(k & 1) ? hi.x : lo.x, (k & 2) ? hi.y : lo.y, (k & 4) ? hi.z : lo.z});
  }
  // Counter-clockwise seen from outside (glTF's front faces): -x, +x, -y, +y, -z, +z.
  mesh.triangles = {{0, 4, 6}, {0, 6, 2}, {1, 3, 7}, {1, 7, 5}, {0, 1, 5}, {0, 5, 4},
                    {2, 6, 7}, {2, 7, 3}, {0, 2, 3}, {0, 3, 1}, {4, 5, 7}, {4, 7, 6}};
  return mesh;
}

// A floor 8 x 8 at y = -1 (its top at y = -1), a 2 x 2 x 2 crate on it, far from the origin: the
// bounds are x, z in [1e4 - 4, 1e4 + 4], y in [-1.5, 1].
Scene floorAndCrate() {
  Scene scene;
  scene.path = "floor.obj";
  const glm::dvec3 at(1e4, 0.0, -1e4);
  scene.objects.push_back(box("floor", at + glm::dvec3(-4, -1.5, -4), at + glm::dvec3(4, -1, 4)));
  scene.objects.push_back(box("crate", at + glm::dvec3(-1, -1, -1), at + glm::dvec3(1, 1, 1)));
  return scene;
}

glm::dvec3 eyeOf(const Camera& camera) {
  return glm::dvec3(glm::inverse(camera.viewFromWorld)[3]);
}

TEST(AutoCameras, FourCamerasNamedForWhatTheyShow) {
  const std::vector<Camera> cameras = autoCameras(floorAndCrate());
  ASSERT_EQ(cameras.size(), 4u);
  EXPECT_EQ(cameras[0].name, "auto_three_quarter");
  EXPECT_EQ(cameras[1].name, "auto_grazing");
  EXPECT_EQ(cameras[2].name, "auto_orthographic_y");  // the bounds are thinnest in y
  EXPECT_EQ(cameras[3].name, "auto_near_cut");
  for (const Camera& camera : cameras) {
    EXPECT_EQ(camera.viewport.width, 640);
    EXPECT_EQ(camera.viewport.height, 480);
  }
}

TEST(AutoCameras, FramingViewsSeeTheWholeBoundingBoxUnderEveryConvention) {
  const Scene scene = floorAndCrate();
  const std::vector<Camera> cameras = autoCameras(scene);
  for (const Camera* camera : {&cameras[0], &cameras[2]}) {
    for (const DepthMode mode : kModes) {
      const glm::dmat4 m = camera->clipFromWorld(mode, camera->viewport);
      for (const MeshObject& mesh : scene.objects) {
        for (const glm::dvec3& p : mesh.worldPositions) {
          const glm::dvec4 c = m * glm::dvec4(p, 1.0);
          ASSERT_GT(c.w, 0.0);
          EXPECT_LE(std::abs(c.x / c.w), 1.0) << camera->name;
          EXPECT_LE(std::abs(c.y / c.w), 1.0) << camera->name;
          const double z = c.z / c.w;
          EXPECT_GE(z, mode.clipVolumeMinZ()) << camera->name << " " << mode.name();
          EXPECT_LE(z, 1.0) << camera->name << " " << mode.name();
        }
      }
    }
  }
}

TEST(AutoCameras, GrazingLooksAcrossTheLowestLargeUpwardSurface) {
  // The floor's top (y = -1) holds 64 of the 68 square units facing up: the eye is 1% of the
  // bounding radius above it, looking horizontally.
  const Scene scene = floorAndCrate();
  const Camera grazing = autoCameras(scene)[1];
  const double radius = glm::length(glm::dvec3(4.0, 1.25, 4.0));
  EXPECT_NEAR(eyeOf(grazing).y, -1.0 + 0.01 * radius, 1e-9);
  const glm::dmat4& v = grazing.viewFromWorld;  // row 2 is the view's z axis: -forward
  const glm::dvec3 forward = -glm::dvec3(v[0][2], v[1][2], v[2][2]);
  EXPECT_NEAR(forward.y, 0.0, 1e-12);
  const auto& projection = std::get<PerspectiveProjection>(grazing.projection);
  EXPECT_NEAR(projection.nearDistance, 0.01 * radius, 1e-12);
}

TEST(AutoCameras, GrazingTakesHorizontalSurfacesEitherWayWhenNoneFacesUp) {
  // The same boxes wound inside out (clockwise from outside): no triangle faces up by its
  // winding, so horizontal ones count whichever way they face; the lowest is the floor's bottom.
  Scene scene = floorAndCrate();
  for (MeshObject& mesh : scene.objects) {
    for (glm::u32vec3& t : mesh.triangles) std::swap(t[1], t[2]);
  }
  const double radius = glm::length(glm::dvec3(4.0, 1.25, 4.0));
  EXPECT_NEAR(eyeOf(autoCameras(scene)[1]).y, -1.5 + 0.01 * radius, 1e-9);
}

TEST(AutoCameras, NearCutPutsTheNearPlaneThroughTheCentre) {
  const Scene scene = floorAndCrate();
  const Camera cut = autoCameras(scene)[3];
  const glm::dvec3 centre(1e4, -0.25, -1e4);
  for (const DepthMode mode : kModes) {
    const glm::dvec4 c = cut.clipFromWorld(mode, cut.viewport) * glm::dvec4(centre, 1.0);
    EXPECT_NEAR(c.z / c.w, mode.nearNdcZ(), 1e-9) << mode.name();
    EXPECT_NEAR(c.x / c.w, 0.0, 1e-9);
    EXPECT_NEAR(c.y / c.w, 0.0, 1e-9);
  }
}

TEST(AutoCameras, NothingFiniteToFrameIsAnInputError) {
  Scene scene;
  scene.path = "plane.gltf";
  AnalyticPrimitive plane;
  plane.kind = PrimitiveKind::Plane;
  scene.primitives.push_back(plane);
  try {
    autoCameras(scene);
    FAIL() << "no error";
  } catch (const InputError& error) {
    EXPECT_EQ(std::string(error.what()),
              "plane.gltf: no cameras, and no finite geometry to frame automatic cameras on");
  }
}

}  // namespace
}  // namespace clipray
