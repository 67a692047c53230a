// An app's picking with its own hits (PickHitFunction): its intersection code is compared with the
// picture. Picking that tests every triangle hits the back of a card the picture culls, and the
// run says so; picking that culls the faces the draw culls agrees with the picture.

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "clipray/Reconcile.hpp"
#include "clipray/math/Projections.hpp"
#include "support/GlFixture.hpp"

namespace clipray {
namespace {

// The app's meshes, as it keeps them: a ground (its front face up) and a card standing on it
// whose front faces away from the camera (wound clockwise as the camera sees it).
const std::vector<float> kGround = {-4, 0, -4, -4, 0, 4, 4, 0, 4, 4, 0, -4};
const std::vector<float> kCard = {-0.8f, 0.2f, 1, 0.8f, 0.2f, 1, 0.8f, 1.4f, 1, -0.8f, 1.4f, 1};
const std::vector<std::uint32_t> kGroundIndices = {0, 1, 2, 0, 2, 3};
const std::vector<std::uint32_t> kCardIndices = {0, 2, 1, 0, 3, 2};

TestScene culledCardScene() {
  const glm::dmat4 clipFromWorld =
      perspectiveClipFromView(glm::radians(60.0), 4.0 / 3.0, 0.1, 100.0, kZeroToOne) *
      viewFromWorldLookAt({0.0, 1.5, 4.0}, {0.0, 0.5, 0.0}, {0.0, 1.0, 0.0});
  return SceneBuilder("culled_card")
      .mesh("ground", kGround, kGroundIndices)
      .faceCulling(CullFace::Back, FrontFace::Ccw)
      .mesh("card", kCard, kCardIndices)
      .faceCulling(CullFace::Back, FrontFace::Ccw)
      .camera("main", clipFromWorld, {64, 48})
      .build();
}

// The app's intersection code: Moller-Trumbore over its meshes, nearest hit; cullBackFaces leaves
// out the triangles whose counter-clockwise front faces away from the ray (what glCullFace(GL_BACK)
// with GL_CCW leaves out of a picture seen through an unmirrored camera).
PickHitFunction appPicking(bool cullBackFaces) {
  const PickRayFunction rays = robustPickRays();
  return
      [rays, cullBackFaces](int x, int y, const PickingCamera& camera) -> std::optional<PickHit> {
        const std::optional<Ray> ray = rays(x, y, camera);
        if (!ray) return std::nullopt;
        PickHit pick;
        pick.ray = *ray;
        pick.t = ray->tMax;
        const std::array<const std::vector<float>*, 2> positions = {&kGround, &kCard};
        const std::array<const std::vector<std::uint32_t>*, 2> indices = {&kGroundIndices,
                                                                          &kCardIndices};
        for (std::size_t mesh = 0; mesh < 2; ++mesh) {
          for (std::uint32_t t = 0; t < indices[mesh]->size() / 3; ++t) {
            std::array<glm::dvec3, 3> v;
            for (int k = 0; k < 3; ++k) {
              const std::uint32_t i = (*indices[mesh])[3 * t + k];
              v[k] = {(*positions[mesh])[3 * i], (*positions[mesh])[3 * i + 1],
                      (*positions[mesh])[3 * i + 2]};
            }
            const glm::dvec3 e1 = v[1] - v[0], e2 = v[2] - v[0];
            if (cullBackFaces && glm::dot(glm::cross(e1, e2), ray->direction) > 0.0) continue;
            const glm::dvec3 p = glm::cross(ray->direction, e2);
            const double det = glm::dot(e1, p);
            if (det == 0.0) continue;
            const glm::dvec3 s = ray->origin - v[0];
            const double u = glm::dot(s, p) / det;
            const glm::dvec3 q = glm::cross(s, e1);
            const double w = glm::dot(ray->direction, q) / det;
            const double hitT = glm::dot(e2, q) / det;
            if (u < 0.0 || w < 0.0 || u + w > 1.0 || hitT <= 0.0 || hitT >= pick.t) continue;
            pick.t = hitT;
            pick.mesh = mesh;
            pick.triangle = t;
          }
        }
        return pick;
      };
}

ReconcileOptions options() {
  ReconcileOptions options;
  options.backend = testing::glBackendForTests();
  return options;
}

TEST(AppPickHits, PickingThatCullsAsTheDrawCullsAgrees) {
  const ReconcileResult result = reconcile(culledCardScene(), appPicking(true), options());
  ASSERT_EQ(result.runs.size(), 1u);
  EXPECT_TRUE(result.consistent()) << result.text();
  EXPECT_TRUE(result.runs[0].notes.empty());
  EXPECT_GT(result.runs[0].depthCompared, 1000);
}

TEST(AppPickHits, PickingThroughCulledBackFacesIsCaughtAndNamed) {
  // Where the app's own picking lands on the card: its pixels, and the first in row order.
  const TestScene scene = culledCardScene();
  const PickHitFunction pick = appPicking(false);
  PickingCamera camera;
  camera.clipFromWorld = scene.model().cameras.at(0).clipFromWorld(kZeroToOne, {64, 48});
  camera.mode = kZeroToOne;
  camera.viewport = {64, 48};
  int cardPixels = 0;
  std::string first;
  for (int y = 0; y < 48; ++y) {
    for (int x = 0; x < 64; ++x) {
      const std::optional<PickHit> hit = pick(x, y, camera);
      if (!hit || hit->mesh != std::size_t{1}) continue;
      if (cardPixels++ == 0) {
        first = "(" + std::to_string(x) + ", " + std::to_string(y) + "): \"card\" triangle " +
                std::to_string(*hit->triangle);
      }
    }
  }
  ASSERT_GT(cardPixels, 100);

  const ReconcileResult result = reconcile(scene, pick, options());
  ASSERT_EQ(result.runs.size(), 1u);
  const RunResult& run = result.runs[0];
  EXPECT_FALSE(run.consistent);
  // Every card pixel shows the ground (an id mismatch) or the sky (a coverage mismatch) in the
  // picture, unexplained away from the card's outline; every other pixel agrees.
  EXPECT_EQ(run.idMismatches + run.coverageMismatches, cardPixels);
  EXPECT_GT(run.idUnexplained, 100);
  EXPECT_GT(run.coverageUnexplained, 100);
  EXPECT_EQ(run.notes,
            (std::vector<std::string>{
                "the app's picking hit faces the picture culls at " + std::to_string(cardPixels) +
                " px (first at pixel " + first +
                "): face culling leaves them out of the picture, so a click there picks what is "
                "not shown; the picking must cull the faces the draw culls"}));
}

TEST(AppPickHits, AHitOnAMeshTheSceneLacksIsRefused) {
  const PickRayFunction rays = robustPickRays();
  const PickHitFunction pick = [&](int x, int y,
                                   const PickingCamera& camera) -> std::optional<PickHit> {
    PickHit hit;
    hit.ray = *rays(x, y, camera);
    hit.mesh = 2;
    hit.t = 1.0;
    return hit;
  };
  try {
    reconcile(culledCardScene(), pick, options());
    FAIL() << "no error";
  } catch (const InputError& error) {
    EXPECT_EQ(std::string(error.what()),
              "PickHit at pixel (0, 0): mesh 2, but the scene has 2 meshes");
  }
}

}  // namespace
}  // namespace clipray
