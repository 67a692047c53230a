#include "clipray/engine/VerifyCheck.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "clipray/engine/ReconcileRun.hpp"
#include "clipray/rays/RobustRays.hpp"
#include "clipray/util/OptionValues.hpp"

namespace clipray::engine {

namespace {

std::string number(double value) {
  return sixDigits(value);
}

}  // namespace

VerifyResult verifyCheck(const CheckInput& input, const CheckReport& report,
                         gl::Renderer& renderer) {
  const MatrixProperties& p = report.properties;
  const DepthMode mode{input.declaredDepth.value_or(DepthConvention::NegativeOneToOne),
                       input.declaredReversed};
  // The probe's frame: a modest viewport with the app's aspect is enough to count pixels.
  const double aspect = static_cast<double>(input.viewport.width) / input.viewport.height;
  const Viewport viewport =
      aspect >= 1.0 ? Viewport{320, std::max(1, static_cast<int>(std::lround(320 / aspect)))}
                    : Viewport{std::max(1, static_cast<int>(std::lround(320 * aspect))), 320};

  Scene scene;
  scene.path = "probe";
  scene.name = "probe";
  Camera camera;
  camera.name = "app";
  camera.viewport = viewport;
  camera.projection = std::monostate{};
  camera.rawClipFromWorld = input.clipFromWorld;
  scene.cameras.push_back(camera);

  // World point at view depth s (perspective: from the eye; orthographic: from the near plane)
  // through clip-space xy, using the matrix's own geometry.
  const RobustRayGenerator rays(input.clipFromWorld, p.perspective && p.reversed
                                                         ? kZeroToOneReversed
                                                         : DepthMode{mode.convention, false});
  const glm::dvec3 forward = p.viewDirection;
  auto pointAt = [&](double x, double y, double s) {
    const Ray ray = rays.generate({x, y});
    if (p.perspective) return *p.eye + ray.direction * (s / glm::dot(ray.direction, forward));
    return ray.origin + ray.direction * s;
  };
  auto addQuad = [&](const std::string& name, double x0, double x1, double y0, double y1,
                     double s) {
    MeshObject quad;
    quad.name = name;
    quad.worldPositions = {pointAt(x0, y0, s), pointAt(x1, y0, s), pointAt(x1, y1, s),
                           pointAt(x0, y1, s)};
    quad.triangles = {{0, 1, 2}, {0, 2, 3}};
    scene.objects.push_back(quad);
  };

  VerifyResult result;
  // Depths to probe: from the nearest plausible near plane to the far plane (or 1000x near).
  const Uncertain drawnNear = p.near.value_or(Uncertain{});
  const double nearest = p.perspective ? std::min(p.nearIfBuiltForNo.value_or(drawnNear).value,
                                                  p.nearIfBuiltForZo.value_or(drawnNear).value)
                                       : 0.0;
  const double farthest =
      p.far ? p.far->value
            : (p.perspective ? 1000.0 * std::max(nearest, 1e-6) : p.depthExtent.value_or(1.0));
  // Band 1: the near probe, at 1.5x the near plane the matrix was built for.
  std::optional<double> builtNear;
  if (p.builtFor == "no" && p.nearIfBuiltForNo) builtNear = p.nearIfBuiltForNo->value;
  if (p.builtFor == "zo" && p.nearIfBuiltForZo) builtNear = p.nearIfBuiltForZo->value;
  if (p.builtFor == "zo-reversed" && p.near) builtNear = p.near->value;
  if (p.perspective && builtNear) {
    result.nearProbeDistance = 1.5 * *builtNear;
    addQuad("near_probe", -0.8, 0.8, 0.4, 0.8, result.nearProbeDistance);
  }
  // Band 2: two overlapping probes; the nearer one must win the depth test.
  const double sNear =
      p.perspective ? std::sqrt(std::max(nearest, 1e-6) * farthest) * 0.5 : farthest * 0.3;
  const double sFar = sNear * 1.5;
  addQuad("overlap_near", -0.8, 0.2, -0.2, 0.2, sNear);
  addQuad("overlap_far", -0.2, 0.8, -0.2, 0.2, sFar);
  // Band 3: a floor-like probe receding through the depth range.
  {
    MeshObject slope;
    slope.name = "slope";
    const double s0 = p.perspective ? std::max(nearest, 1e-6) * 2.0 : farthest * 0.05;
    const double s1 = farthest * 0.9;
    slope.worldPositions = {pointAt(-0.8, -0.9, s0), pointAt(0.8, -0.9, s0), pointAt(0.8, -0.4, s1),
                            pointAt(-0.8, -0.4, s1)};
    slope.triangles = {{0, 1, 2}, {0, 2, 3}};
    scene.objects.push_back(slope);
  }

  const AnalyticPass pass = runAnalyticPass(scene, scene.cameras[0], mode, viewport);
  const RunRecord run =
      rasterAndCompare(renderer, pass, input.depthFormat, VertexMode::World, false);
  result.reconcile = run.metrics;

  // Count what the raster actually shows, from its id buffer.
  gl::RenderRequest request;
  request.scene = &scene;
  request.clipFromWorld = input.clipFromWorld;
  request.mode = mode;
  request.depthFormat = input.depthFormat;
  request.viewport = viewport;
  const RasterFrame frame = renderer.render(request);
  const PrimitiveIdTable ids(scene);
  std::vector<std::int64_t> pixelsOf(scene.objects.size(), 0);
  for (const std::uint32_t id : frame.ids) {
    if (id != 0) ++pixelsOf[ids.decode(id).object];
  }
  auto objectIndex = [&](const std::string& name) {
    for (std::size_t k = 0; k < scene.objects.size(); ++k) {
      if (scene.objects[k].name == name) return static_cast<int>(k);
    }
    return -1;
  };
  if (const int k = objectIndex("near_probe"); k >= 0) {
    result.nearProbeDrawn = pixelsOf[k] > 0;
    result.observations.push_back(
        std::string("a probe at 1.5x the near plane the matrix was built for (") +
        number(result.nearProbeDistance) + ") is " +
        (*result.nearProbeDrawn ? "drawn" : "clipped away") + " under the declared conventions" +
        (p.near && !*result.nearProbeDrawn ? " (effective near plane " + number(p.near->value) + ")"
                                           : ""));
  }
  // In the overlap (clip x in [-0.2, 0.2]) the nearer probe should own the pixels.
  std::int64_t nearerOwned = 0, fartherOwned = 0;
  const int nearIndex = objectIndex("overlap_near"), farIndex = objectIndex("overlap_far");
  for (int y = 0; y < viewport.height; ++y) {
    for (int x = 0; x < viewport.width; ++x) {
      const glm::dvec2 c = clipXYOfPixelCentre(x, y, viewport);
      if (std::abs(c.x) > 0.15 || std::abs(c.y) > 0.15) continue;
      const std::uint32_t id = frame.ids[static_cast<std::size_t>(y) * viewport.width + x];
      if (id == 0) continue;
      const int object = ids.decode(id).object;
      nearerOwned += object == nearIndex;
      fartherOwned += object == farIndex;
    }
  }
  result.nearerProbeWins = nearerOwned >= fartherOwned;
  result.observations.push_back(
      "where probes at " + number(sNear) + " and " + number(sFar) +
      " overlap, the raster shows the " + (result.nearerProbeWins ? "nearer" : "farther") +
      " one (" + std::to_string(nearerOwned) + " vs " + std::to_string(fartherOwned) + " pixels)");
  result.observations.push_back(std::string("probe reconcile under the declared conventions: ") +
                                (run.metrics.consistent() ? "consistent" : "inconsistent") +
                                ", depth error max " + number(run.metrics.depthErrorQuanta.max) +
                                " quanta, tolerance ratio max " +
                                number(run.metrics.toleranceRatio.max));
  return result;
}

nlohmann::json verifyResultJson(const VerifyResult& result) {
  nlohmann::json json = {
      {"reconcile_verdict", result.reconcile.consistent() ? "consistent" : "inconsistent"},
      {"depth_error_quanta_max", result.reconcile.depthErrorQuanta.max},
      {"tolerance_ratio_max", result.reconcile.toleranceRatio.max},
      {"nearer_probe_wins", result.nearerProbeWins},
      {"observations", result.observations},
  };
  json["near_probe_drawn"] =
      result.nearProbeDrawn ? nlohmann::json(*result.nearProbeDrawn) : nlohmann::json(nullptr);
  return json;
}

}  // namespace clipray::engine
