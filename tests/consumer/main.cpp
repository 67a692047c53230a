// A program outside clipray, built against the installed package twice (find_package and
// pkg-config) by run-consumer-test.cmake: a ray from a camera matrix, then an app-style picking
// function reconciled with the headless raster. Exits 0 only when every check holds.
// Usage: clipray_consumer <scene.json>   (scenes/near_plane_straddle.json)

#include <cmath>
#include <cstdio>
#include <exception>
#include <optional>
#include <string>

#include <glm/glm.hpp>

#include "clipray/gl/GlContext.hpp"
#include "clipray/gl/ReconcileRun.hpp"
#include "clipray/gl/Renderer.hpp"
#include "clipray/math/Projections.hpp"
#include "clipray/rays/RobustRays.hpp"
#include "clipray/report/Report.hpp"
#include "clipray/scene/Scene.hpp"

// No compile definition of clipray's reaches a consumer (clipray once passed GLM_FORCE_XYZW_ONLY
// on, which took glm's colour and texture-coordinate names away).
#ifdef GLM_FORCE_XYZW_ONLY
#error "GLM_FORCE_XYZW_ONLY reached a consumer of clipray::core"
#endif
template <typename V>
concept HasColourNames = requires(V v) {
  v.r;
  v.s;
};
static_assert(HasColourNames<glm::vec4>, "glm's .r/.s names must stay available to consumers");

namespace {

int failures = 0;

void check(bool ok, const std::string& what) {
  std::printf("%s %s\n", ok ? "ok  " : "FAIL", what.c_str());
  if (!ok) {
    ++failures;
  }
}

// The app's picking: a ray through the pixel centre (lower-left origin), or, with the classic
// bug, through the pixel's corner.
clipray::PickRayFunction appPicking(bool pixelCorner) {
  return [pixelCorner](int x, int y,
                       const clipray::PickingCamera& camera) -> std::optional<clipray::Ray> {
    const double offset = pixelCorner ? 0.0 : 0.5;
    const glm::dvec2 clip{2.0 * (x + offset) / camera.viewport.width - 1.0,
                          2.0 * (y + offset) / camera.viewport.height - 1.0};
    return clipray::RobustRayGenerator(camera.clipFromWorld, camera.mode).generate(clip);
  };
}

void checkCameraRay() {
  // Eye at z = 5 looking at the origin, near plane 0.1 under ZERO_TO_ONE: the ray through the
  // centre of the frame starts on the near plane (z = 4.9) and points down -z.
  const glm::dmat4 clipFromWorld =
      clipray::perspectiveClipFromView(glm::radians(60.0), 4.0 / 3.0, 0.1, 100.0,
                                       clipray::kZeroToOne) *
      clipray::viewFromWorldLookAt({0.0, 0.0, 5.0}, {0.0, 0.0, 0.0}, {0.0, 1.0, 0.0});
  const clipray::Ray ray =
      clipray::RobustRayGenerator(clipFromWorld, clipray::kZeroToOne).generate({0.0, 0.0});
  check(glm::length(ray.origin - glm::dvec3(0.0, 0.0, 4.9)) < 1e-9,
        "centre ray starts on the near plane");
  check(glm::length(ray.direction - glm::dvec3(0.0, 0.0, -1.0)) < 1e-12,
        "centre ray points at the target");
  check(std::abs(ray.tMax - 99.9) < 1e-6, "centre ray ends on the far plane");
}

void checkReconcile(const std::string& scenePath) {
  const clipray::Scene scene = clipray::loadScene(scenePath);
  const clipray::Camera& camera = scene.cameras.at(0);
  auto context = clipray::gl::createOsMesaContext();
  clipray::gl::Renderer renderer(*context);
  for (const bool bug : {false, true}) {
    const clipray::gl::AnalyticPass pass = clipray::gl::runAnalyticPass(
        scene, camera, clipray::kZeroToOne, camera.viewport, appPicking(bug));
    const clipray::RunRecord run = clipray::gl::rasterAndCompare(
        renderer, pass, clipray::DepthFormat::Float32, clipray::VertexMode::World, false);
    std::printf("%s", clipray::textSummary({run}).c_str());
    check(run.metrics.pixels == std::int64_t{camera.viewport.width} * camera.viewport.height,
          "every pixel compared");
    check(run.metrics.consistent() == !bug,
          bug ? "pixel-corner picking is caught" : "pixel-centre picking is consistent");
  }
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: %s <scene.json>\n", argv[0]);
    return 2;
  }
  try {
    checkCameraRay();
    checkReconcile(argv[1]);
  } catch (const std::exception& error) {
    std::fprintf(stderr, "error: %s\n", error.what());
    return 1;
  }
  std::printf("%s\n", failures == 0 ? "consumer: all checks passed" : "consumer: FAILED");
  return failures == 0 ? 0 : 1;
}
