// The library entry point catches real picking bugs: an app's own ray function is reconciled
// against the raster, and each classic mistake is reported inconsistent while the right one passes.

#include <gtest/gtest.h>

#include "clipray/math/Projections.hpp"
#include "clipray/rays/RobustRays.hpp"
#include "clipray/scene/Scene.hpp"
#include "support/GlFixture.hpp"

namespace clipray {
namespace {

using testing::GlTest;
using testing::sourcePath;

// A textbook picking function: ray through clip xy from the near point, with knobs for each bug.
struct PickingBugs {
  bool pixelCorner = false;         // forgets the +0.5 of the pixel centre
  bool classicNearUnderZo = false;  // unprojects z_ndc = -1 even though the frame is drawn under ZO
  bool yFlipped = false;            // treats the pixel row as top-left origin
  bool transposed = false;          // uses the transposed matrix (row-major upload confusion)
  bool originAtEye = false;         // starts the ray at the eye instead of the near plane
};

PickRayFunction pickingFunction(PickingBugs bugs) {
  return [bugs](int x, int y, const PickingCamera& camera) -> std::optional<Ray> {
    const glm::dmat4 m =
        bugs.transposed ? glm::transpose(camera.clipFromWorld) : camera.clipFromWorld;
    const int row = bugs.yFlipped ? camera.viewport.height - 1 - y : y;
    glm::dvec2 clip = clipXYOfPixelCentre(x, row, camera.viewport);
    if (bugs.pixelCorner) {
      clip = {2.0 * x / camera.viewport.width - 1.0, 2.0 * row / camera.viewport.height - 1.0};
    }
    Ray ray = RobustRayGenerator(m, camera.mode).generate(clip);
    if (bugs.classicNearUnderZo) {
      const glm::dvec4 p = glm::inverse(m) * glm::dvec4(clip, -1.0, 1.0);
      const glm::dvec3 origin = glm::dvec3(p) / p.w;
      ray.tMax += glm::length(ray.origin - origin);
      ray.origin = origin;
    }
    if (bugs.originAtEye) {
      const glm::dvec4 e = glm::inverse(m) * glm::dvec4(0.0, 0.0, 1.0, 0.0);
      const glm::dvec3 eye = glm::dvec3(e) / e.w;
      ray.tMax += glm::length(ray.origin - eye);
      ray.origin = eye;
    }
    return ray;
  };
}

class CallerRayFunction : public GlTest {
 protected:
  RunRecord reconcile(PickingBugs bugs, DepthMode mode = kZeroToOne) {
    const Scene& scene = this->scene();
    const engine::AnalyticPass pass = engine::runAnalyticPass(
        scene, scene.cameras[0], mode, scene.cameras[0].viewport, pickingFunction(bugs));
    return engine::rasterAndCompare(renderer(), pass, DepthFormat::Float32, VertexMode::World,
                                    false);
  }
  static const Scene& scene() {
    // Geometry crosses the near plane and sits between the eye and the near plane.
    static const Scene loaded = loadScene(sourcePath("scenes/near_plane_straddle.json"));
    return loaded;
  }
};

TEST_F(CallerRayFunction, CorrectPickingIsConsistent) {
  for (const DepthMode mode : {kNegativeOneToOne, kZeroToOne}) {
    const RunRecord run = reconcile({}, mode);
    EXPECT_TRUE(run.metrics.consistent()) << mode.name();
  }
}

TEST_F(CallerRayFunction, PixelCornerInsteadOfCentreIsCaught) {
  const RunRecord run = reconcile({.pixelCorner = true});
  EXPECT_FALSE(run.metrics.consistent());
  EXPECT_GT(run.metrics.coverageMismatch.unexplained + run.metrics.idMismatch.unexplained, 0);
}

TEST_F(CallerRayFunction, ClassicNearPlaneUnderZeroToOneIsCaught) {
  const RunRecord run = reconcile({.classicNearUnderZo = true});
  EXPECT_FALSE(run.metrics.consistent());
}

TEST_F(CallerRayFunction, FlippedYIsCaught) {
  const RunRecord run = reconcile({.yFlipped = true});
  EXPECT_FALSE(run.metrics.consistent());
  EXPECT_GT(run.metrics.idMismatch.unexplained + run.metrics.coverageMismatch.unexplained,
            run.metrics.pixels / 10);
}

TEST_F(CallerRayFunction, TransposedMatrixIsCaught) {
  const RunRecord run = reconcile({.transposed = true});
  EXPECT_FALSE(run.metrics.consistent());
}

TEST_F(CallerRayFunction, OriginAtTheEyeIsCaught) {
  const RunRecord run = reconcile({.originAtEye = true});
  EXPECT_FALSE(run.metrics.consistent());
  // The pillar between the eye and the near plane is hit by the rays but clipped by the raster.
  EXPECT_GT(run.metrics.idMismatch.unexplained + run.metrics.coverageMismatch.unexplained, 100);
}

}  // namespace
}  // namespace clipray
