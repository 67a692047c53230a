#include "ThreeWayPick.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iterator>
#include <memory>
#include <vector>

#include "clipray/compare/DepthMapping.hpp"
#include "clipray/engine/DrawStateGroups.hpp"

namespace clipray::demo {

std::string rayChoiceName(RayChoice choice) {
  return rayMethodName(choice.method) + " " + precisionName(choice.precision);
}

RayChoice nextRayChoice(RayChoice choice) {
  constexpr std::size_t count = std::size(kDemoRayChoices);
  for (std::size_t k = 0; k < count; ++k) {
    if (kDemoRayChoices[k] == choice) return kDemoRayChoices[(k + 1) % count];
  }
  for (std::size_t k = 0; k < count; ++k) {
    if (kDemoRayChoices[k].method == choice.method) return kDemoRayChoices[(k + 1) % count];
  }
  return kDemoRayChoices[0];
}

namespace {

template <typename T>
PickRay libraryRay(RayMethod method, const CameraInputs& camera, Viewport viewport,
                   glm::ivec2 pixel) {
  PickRay result;
  const std::unique_ptr<RayGenerator<T>> generator = makeRayGenerator<T>(method, camera, viewport);
  if (!generator) {
    result.unavailable = missingInputs(method, camera);
    if (result.unavailable.empty()) result.unavailable = "cannot run on this camera";
    return result;
  }
  const CameraRay<T> r = generator->pixelRay(pixel.x, pixel.y);
  Ray ray;
  ray.origin = glm::dvec3(r.origin);
  ray.direction = glm::dvec3(r.direction);
  ray.tMax = static_cast<double>(r.tMax);
  const bool finite = std::isfinite(ray.origin.x) && std::isfinite(ray.origin.y) &&
                      std::isfinite(ray.origin.z) && std::isfinite(ray.direction.x) &&
                      std::isfinite(ray.direction.y) && std::isfinite(ray.direction.z);
  // robust says "no ray" with a negative t_max: the pixel's line of sight meets the near plane
  // behind the eye (beyond an oblique near plane's horizon), and the raster shows nothing there.
  if (ray.tMax < 0.0) {
    result.unavailable =
        "no ray: the line of sight never crosses the near plane in front of the eye";
    return result;
  }
  // t_max may be +inf (infinite far plane, direction-only methods) but not NaN or negative.
  if (!finite || !(glm::length(ray.direction) > 0.0) || !(ray.tMax > 0.0)) {
    result.unavailable = "non-finite ray";
    return result;
  }
  result.ray = ray;
  return result;
}

glm::dvec3 unproject(const glm::dmat4& worldFromClip, const glm::dvec3& ndc) {
  const glm::dvec4 p = worldFromClip * glm::dvec4(ndc, 1.0);
  return glm::dvec3(p) / p.w;
}

nlohmann::json pointJson(const std::optional<glm::dvec3>& point) {
  if (!point) return nullptr;
  return nlohmann::json::array({point->x, point->y, point->z});
}

}  // namespace

int surfaceIndex(const Scene& scene, const PrimitiveIdTable& ids, std::uint32_t primitiveId) {
  const PrimitiveIdTable::Decoded decoded = ids.decode(primitiveId);
  if (decoded.analytic >= 0) return static_cast<int>(scene.objects.size()) + decoded.analytic;
  return decoded.object;
}

std::string surfaceName(const Scene& scene, int surface) {
  if (surface < 0) return "background";
  const auto index = static_cast<std::size_t>(surface);
  return index < scene.objects.size() ? scene.objects[index].name
                                      : scene.primitives[index - scene.objects.size()].name;
}

namespace {

nlohmann::json objectJson(const Scene& scene, int object) {
  if (object < 0) return nullptr;
  return surfaceName(scene, object);
}

nlohmann::json optionalJson(const std::optional<double>& value) {
  if (!value) return nullptr;
  return *value;
}

}  // namespace

PickRay pickRay(RayChoice choice, const CameraInputs& camera, Viewport viewport, glm::ivec2 pixel) {
  return choice.precision == Precision::Float
             ? libraryRay<float>(choice.method, camera, viewport, pixel)
             : libraryRay<double>(choice.method, camera, viewport, pixel);
}

CameraInputs lowerLeftCameraInputs(const CameraInputs& drawn) {
  CameraInputs view = drawn;
  const ClipOrigin origin = drawn.mode.origin;
  view.mode = drawn.mode.lowerLeft();
  view.clipFromWorld = lowerLeftClipFromWorld(drawn.clipFromWorld, origin);
  // clipFromView * viewFromWorld keeps composing to clipFromWorld: the y row is the projection's.
  if (drawn.clipFromView) view.clipFromView = lowerLeftClipFromWorld(*drawn.clipFromView, origin);
  return view;
}

const char* pixelCoordinatesLabel(ClipOrigin origin) {
  return origin == ClipOrigin::UpperLeft
             ? "framebuffer, GL: origin lower left, y up; clip y down (GL_UPPER_LEFT)"
             : "framebuffer, GL: origin lower left, y up";
}

std::optional<glm::dvec2> framebufferFromWorld(const glm::dmat4& clipFromWorld, Viewport viewport,
                                               const glm::dvec3& world) {
  const glm::dvec4 clip = clipFromWorld * glm::dvec4(world, 1.0);
  if (!(clip.w > 0.0)) return std::nullopt;
  const glm::dvec2 ndc = glm::dvec2(clip) / clip.w;
  return glm::dvec2((ndc.x + 1.0) * 0.5 * viewport.width, (ndc.y + 1.0) * 0.5 * viewport.height);
}

namespace {

// The reconcile's classification of one mismatching pixel, for the pick's own ray: the polygons
// of just the two primitives are clipped (ToleranceModel's lazy path), not the whole scene's.
PixelClass classifyPickMismatch(const PickView& view, const Ray& ray, double t,
                                std::uint32_t rayPrimitive, std::uint32_t rasterPrimitive,
                                glm::ivec2 pixel) {
  const RasterSetup& setup = *view.setup;
  std::vector<std::uint32_t> shown;
  for (const std::uint32_t id : {rayPrimitive, rasterPrimitive}) {
    if (id != 0) shown.push_back(id);
  }
  const ToleranceModel model(*view.intersector, setup, view.raster->viewport, shown, 1);
  double rayDepth = std::nan(""), rayTolerance = 0.0;
  if (rayPrimitive != 0) {
    const glm::dvec4 hitClip =
        setup.clipFromWorld * glm::dvec4(ray.origin + t * ray.direction, 1.0);
    rayDepth = windowDepthFromNdc(hitClip.z / hitClip.w, setup.mode.convention);
    rayTolerance = view.intersector->isAnalytic(rayPrimitive)
                       ? model.analyticDepthTolerance(rayPrimitive, ray, t)
                       : model.depthToleranceAtClip(rayPrimitive, hitClip);
  }
  return classifyMismatch(model, rayPrimitive, rayDepth, rayTolerance, rasterPrimitive,
                          glm::dvec2(pixel) + 0.5);
}

}  // namespace

PickResult pick(const PickView& view, RayChoice ray, glm::ivec2 pixel) {
  const Scene& scene = *view.scene;
  const RasterFrame& raster = *view.raster;
  const Viewport viewport = raster.viewport;
  const PrimitiveIdTable ids(scene);
  PickResult result;
  result.pixel = pixel;
  result.framebuffer = viewport;
  result.ray = ray;
  result.mode = view.camera.mode;
  result.mode.origin = view.drawnOrigin;
  result.depthFormat = view.depthFormat;
  result.clipPlaneCount = view.clipPlanes.size();
  const glm::dvec2 clipXY = clipXYOfPixelCentre(pixel.x, pixel.y, viewport);

  // 1. The analytic ray through the pixel centre, cut where the picture is.
  PickRay analytic = pickRay(ray, view.camera, viewport, pixel);
  // The picture shows nothing a plane clips, so no method's pick may find it either.
  if (analytic.ray) cutToClipPlanes(*analytic.ray, view.clipPlanes);
  std::uint32_t rayPrimitive = 0;
  double rayHitT = 0.0;
  if (analytic.ray) {
    // The hit the picture keeps: where objects are drawn with state of their own (a depth range,
    // clip planes, a polygon offset), the one the depth test keeps, as the reconcile decides it.
    PickingCamera camera;
    camera.clipFromWorld = view.camera.clipFromWorld;
    camera.mode = view.camera.mode;
    camera.viewport = viewport;
    camera.clipPlanes = view.clipPlanes;
    // The lower-left view's y row negated back for an upper-left origin: the matrix as drawn,
    // which decides facing.
    const Hit hit = engine::closestHitByDrawState(
        *analytic.ray, *view.intersector, scene,
        lowerLeftClipFromWorld(view.camera.clipFromWorld, view.drawnOrigin), camera);
    rayPrimitive = hit.primitiveId;
    rayHitT = hit.t;
    if (hit.hit()) {
      result.rayObject = surfaceIndex(scene, ids, hit.primitiveId);
      result.rayPoint = analytic.ray->origin + hit.t * analytic.ray->direction;
    }
  } else {
    result.rayUnavailable = analytic.unavailable;
  }

  // 2. and 3. What the raster stored at that pixel.
  const std::size_t index = static_cast<std::size_t>(pixel.y) * viewport.width + pixel.x;
  result.windowDepth = raster.depth[index];
  result.primitiveId = raster.ids[index];
  result.idObject = surfaceIndex(scene, ids, result.primitiveId);
  const glm::dmat4 worldFromClip = glm::inverse(view.camera.clipFromWorld);
  // The depth readback undoes the mapping the pixel was drawn with: glDepthRange, the scene's or
  // the object's own (a weapon in [0, 0.1]), whose object the id buffer names. The clear value is
  // the far end the depth test starts from.
  const DepthMapping drawnMapping{
      view.camera.mode, PrimitiveDepthRanges(scene).rangeOf(result.primitiveId, scene.depthRange),
      false};
  const float clearDepth = nearerIsGreater(view.camera.mode, scene.depthRange) ? 0.0f : 1.0f;
  if (result.windowDepth != clearDepth) {
    const double zNdc = drawnMapping.ndcOfWindowDepth(result.windowDepth);
    result.depthPoint = unproject(worldFromClip, glm::dvec3(clipXY, zNdc));
  }

  if (result.rayPoint) {
    if (const auto onScreen =
            framebufferFromWorld(view.camera.clipFromWorld, viewport, *result.rayPoint)) {
      result.rayOffsetPixels = glm::distance(*onScreen, glm::dvec2(pixel) + 0.5);
    }
  }
  if (view.setup != nullptr && analytic.ray && rayPrimitive != result.primitiveId) {
    result.reconcileClass =
        classifyPickMismatch(view, *analytic.ray, rayHitT, rayPrimitive, result.primitiveId, pixel);
  }

  if (result.rayPoint && result.depthPoint) {
    result.gapWorld = glm::distance(*result.rayPoint, *result.depthPoint);
    // One pixel's footprint at the depth point: the next pixel centre at the same NDC depth.
    const double zNdc = drawnMapping.ndcOfWindowDepth(result.windowDepth);
    const glm::dvec3 neighbour =
        unproject(worldFromClip, glm::dvec3(clipXY.x + 2.0 / viewport.width, clipXY.y, zNdc));
    const double footprint = glm::distance(neighbour, *result.depthPoint);
    if (footprint > 0.0 && std::isfinite(footprint))
      result.gapPixels = *result.gapWorld / footprint;
  }
  return result;
}

const char* pickVerdictName(PickVerdict verdict) {
  switch (verdict) {
    case PickVerdict::Agree:
      return "agree";
    case PickVerdict::Apart:
      return "apart";
    case PickVerdict::Ambiguous:
      return "ambiguous";
    case PickVerdict::Disagree:
      return "disagree";
    case PickVerdict::NoRay:
      return "n/a";
  }
  return "?";
}

PickJudgement judgePick(const PickResult& result, const Scene& scene) {
  char text[256];
  if (!result.rayUnavailable.empty()) {
    return {PickVerdict::NoRay, "1 and 3: n/a (" + result.rayUnavailable + ")"};
  }
  const std::string rayName = surfaceName(scene, result.rayObject);
  const std::string idName = surfaceName(scene, result.idObject);
  if (result.agree()) {
    if (!result.rayOffsetPixels) return {PickVerdict::Agree, "1 and 3 agree: " + rayName};
    const double offset = *result.rayOffsetPixels;
    if (offset <= kPickAgreementPixels) {
      std::snprintf(text, sizeof text, "1 and 3 agree: %s, hit %.2g px from the pixel centre",
                    rayName.c_str(), offset);
      return {PickVerdict::Agree, text};
    }
    std::snprintf(text, sizeof text,
                  "1 and 3 APART: both %s, but the ray's hit lands %.3g px from the clicked pixel",
                  rayName.c_str(), offset);
    return {PickVerdict::Apart, text};
  }
  const PixelClass cls = result.reconcileClass.value_or(PixelClass::IdUnexplained);
  if (cls == PixelClass::IdDepthAmbiguous) {
    return {PickVerdict::Ambiguous, "1 and 3 ambiguous: " + rayName + " and " + idName +
                                        " z-fight here (depths within the tolerance)"};
  }
  if (cls == PixelClass::IdEdgeAmbiguous || cls == PixelClass::CoverageEdgeAmbiguous) {
    return {PickVerdict::Ambiguous,
            "1 and 3 ambiguous: " + rayName + " or " + idName + ", the pixel centre is on an edge"};
  }
  return {PickVerdict::Disagree,
          "1 and 3 DISAGREE: the ray hits " + rayName + ", the id buffer shows " + idName};
}

nlohmann::json pickJson(const PickResult& result, const Scene& scene, bool teleported) {
  nlohmann::json line;
  line["pixel"] = {result.pixel.x, result.pixel.y};
  line["framebuffer"] = {result.framebuffer.width, result.framebuffer.height};
  line["method"] = rayMethodName(result.ray.method);
  line["precision"] = precisionName(result.ray.precision);
  line["convention"] = result.mode.name();
  line["clip_origin"] = result.mode.origin == ClipOrigin::UpperLeft ? "upper-left" : "lower-left";
  line["clip_planes"] = result.clipPlaneCount;
  line["depth_format"] = depthFormatName(result.depthFormat);
  line["teleported"] = teleported;
  if (result.rayUnavailable.empty()) {
    line["ray"] = {{"object", objectJson(scene, result.rayObject)},
                   {"point", pointJson(result.rayPoint)}};
  } else {
    line["ray"] = nullptr;
  }
  line["depth"] = {{"point", pointJson(result.depthPoint)},
                   {"window_depth", static_cast<double>(result.windowDepth)}};
  line["id"] = {{"object", objectJson(scene, result.idObject)}};
  line["gap_world"] = optionalJson(result.gapWorld);
  line["gap_px"] = optionalJson(result.gapPixels);
  line["ray_offset_px"] = optionalJson(result.rayOffsetPixels);
  const PickVerdict verdict = judgePick(result, scene).verdict;
  if (result.rayUnavailable.empty()) {
    // "agree" is the verdict's word: the same object is not enough where the hit lands apart.
    line["same_object"] = result.agree();
    line["agree"] = verdict == PickVerdict::Agree;
  } else {
    line["same_object"] = nullptr;
    line["agree"] = nullptr;
  }
  if (result.reconcileClass) {
    line["reconcile_class"] = pixelClassName(*result.reconcileClass);
  } else {
    line["reconcile_class"] = nullptr;
  }
  line["verdict"] = pickVerdictName(verdict);
  return line;
}

}  // namespace clipray::demo
