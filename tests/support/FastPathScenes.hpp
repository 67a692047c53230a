#pragma once
// The scenes and cameras the intersector's fast-path tests share: a terrain with a ball and two
// coplanar decals (with analytic primitives added), and the binned-frame cameras (perspective NO,
// reversed-Z infinite ZO, inside the terrain, orthographic) at 61x47, partial tiles included.

#include <gtest/gtest.h>

#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "clipray/compare/Frames.hpp"
#include "clipray/intersect/SceneIntersector.hpp"
#include "clipray/math/Projections.hpp"
#include "support/TestScenes.hpp"

namespace clipray::testing::fast_path {

// A heightfield grid (shared vertices stored once), cells x cells quads over [-s, s]^2.
inline MeshObject terrain(int cells, double size, std::uint64_t seed) {
  MeshObject mesh;
  mesh.name = "terrain";
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> height(-0.5, 0.5);
  const int n = cells + 1;
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      mesh.worldPositions.emplace_back(-size + 2 * size * i / cells, height(rng),
                                       -size + 2 * size * j / cells);
    }
  }
  mesh.triangles = testing::gridTriangles(cells);
  return mesh;
}

inline Scene testScene() {
  Scene scene;
  scene.objects.push_back(terrain(40, 5.0, 11));
  scene.objects.push_back(testing::icosphere("ball", {0.5, 1.0, -0.5}, 0.8, 3));
  // A coplanar duplicate of part of the floor: ties at equal t must go to the smaller id.
  scene.objects.push_back(testing::quad("decal", {-1, 2, -1}, {-1, 2, 1}, {1, 2, 1}, {1, 2, -1}));
  scene.objects.push_back(testing::quad("decal2", {-1, 2, -1}, {-1, 2, 1}, {1, 2, 1}, {1, 2, -1}));
  return scene;
}

inline Scene testSceneWithPrimitives() {
  Scene scene = testScene();
  auto add = [&](PrimitiveKind kind, const glm::dmat4& worldFromLocal) {
    AnalyticPrimitive p;
    p.name = primitiveKindName(kind);
    p.kind = kind;
    p.worldFromLocal = worldFromLocal;
    p.localFromWorld = glm::inverse(worldFromLocal);
    scene.primitives.push_back(p);
  };
  auto placed = [](glm::dvec3 position, glm::dvec3 scale) {
    glm::dmat4 m(1.0);
    m[0][0] = scale.x;
    m[1][1] = scale.y;
    m[2][2] = scale.z;
    m[3] = glm::dvec4(position, 1.0);
    return m;
  };
  glm::dmat4 upright(0.0);  // local z -> world y, local y -> world -z
  upright[0] = {1, 0, 0, 0};
  upright[1] = {0, 0, -1, 0};
  upright[2] = {0, 1, 0, 0};
  upright[3] = {0, 0, 0, 1};
  add(PrimitiveKind::Sphere, placed({-2.0, 0.5, 1.0}, {1.0, 1.0, 1.0}));  // half sunk in terrain
  add(PrimitiveKind::Box, placed({2.5, 0.0, -2.0}, {0.7, 1.2, 0.5}));
  // A disk on the decals' plane (y = 2): ties with both decals, which must keep winning.
  glm::dmat4 disk = upright * placed({0, 0, 0}, {0.8, 0.8, 1.0});
  disk[3] = {0.0, 2.0, 0.0, 1.0};
  add(PrimitiveKind::Disk, disk);
  glm::dmat4 quad = upright * placed({0, 0, 0}, {0.5, 0.5, 1.0});
  quad[3] = {-3.0, 1.5, -3.0, 1.0};
  add(PrimitiveKind::Quad, quad);
  add(PrimitiveKind::Plane, placed({0, 0, -4.5}, {1, 1, 1}));  // a wall behind the terrain
  return scene;
}

struct BinnedCase {
  const char* name;
  PickingCamera camera;
};

inline PickingCamera lookingAt(const glm::dmat4& clipFromView, DepthMode mode,
                               const glm::dvec3& eye, const glm::dvec3& target, Viewport viewport) {
  return {clipFromView * viewFromWorldLookAt(eye, target, {0, 1, 0}), mode, viewport};
}

// 61x47 by default: partial tiles at the right and top.
inline std::vector<BinnedCase> binnedCases(Viewport v = {61, 47}) {
  const double aspect = static_cast<double>(v.width) / v.height;
  return {
      {"perspective NO",
       lookingAt(perspectiveClipFromView(0.9, aspect, 0.1, 100.0, kNegativeOneToOne),
                 kNegativeOneToOne, {0.3, 6.0, 9.0}, {0, 0, -1}, v)},
      {"reversed-Z infinite ZO",
       lookingAt(perspectiveClipFromView(0.9, aspect, 0.05, std::nullopt, kZeroToOneReversed),
                 kZeroToOneReversed, {-3.0, 2.5, 7.0}, {0.5, 0.5, -1}, v)},
      // Inside the scene, eye level with the terrain: many triangles cross the eye plane and are
      // clipped at w = wClip before they are binned.
      {"inside the terrain", lookingAt(perspectiveClipFromView(1.4, aspect, 0.01, 50.0, kZeroToOne),
                                       kZeroToOne, {0.2, 0.7, 0.1}, {-3.0, 0.2, -2.0}, v)},
      {"orthographic", lookingAt(orthographicClipFromView(-6, 6, -4.6, 4.6, 0.5, 40.0, kZeroToOne),
                                 kZeroToOne, {1.0, 9.0, 8.0}, {0, 0, 0}, v)},
  };
}

inline void expectFrameMatchesTheLinearScan(const SceneIntersector& intersector,
                                            const AnalyticFrame& frame, const std::string& what) {
  for (std::size_t i = 0; i < frame.rays.size(); ++i) {
    const Hit expected = intersector.closestHitLinear(frame.rays[i]);
    ASSERT_EQ(frame.hits[i].primitiveId, expected.primitiveId) << what << " pixel " << i;
    ASSERT_EQ(frame.hits[i].t, expected.t) << what << " pixel " << i;
  }
}

inline std::size_t tileCount(Viewport v) {
  return static_cast<std::size_t>((v.width + 7) / 8) * ((v.height + 7) / 8);
}

// The intersector as a reconcile makes it for a camera: the reference point at the near plane's
// centre, the BVH only if a tile needs it.
inline SceneIntersector intersectorSeenFrom(const Scene& scene, const PickingCamera& camera) {
  const glm::dvec4 centre =
      glm::inverse(camera.clipFromWorld) * glm::dvec4(0.0, 0.0, camera.mode.nearNdcZ(), 1.0);
  return SceneIntersector(scene, glm::dvec3(centre) / centre.w,
                          SceneIntersector::BvhBuild::WhenFirstNeeded);
}

}  // namespace clipray::testing::fast_path
