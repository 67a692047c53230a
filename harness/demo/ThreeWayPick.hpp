#pragma once
// One click picked three ways (no GL, no window: testable on its own):
//   1. the analytic ray through the pixel centre -> object and hit point;
//   2. the raster depth at the pixel, unprojected through worldFromClip -> world point (the classic
//      depth-readback idiom);
//   3. the raster id at the pixel -> object.
// and the gap between 1 and 2, in world units and in pixel footprints at that depth.

#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <glm/glm.hpp>
#include <nlohmann/json.hpp>

#include "clipray/Conventions.hpp"
#include "clipray/Ray.hpp"
#include "clipray/compare/Frames.hpp"
#include "clipray/compare/Reconcile.hpp"
#include "clipray/intersect/SceneIntersector.hpp"
#include "clipray/rays/RayMethods.hpp"
#include "clipray/scene/Scene.hpp"

namespace clipray::demo {

// The rays the demo offers: every method of clipray's ray library (RayMethods.hpp) in float, as
// most apps run them, plus robust in double. The M key cycles through kDemoRayChoices.
struct RayChoice {
  RayMethod method = RayMethod::Robust;
  Precision precision = Precision::Float;
  bool operator==(const RayChoice&) const = default;
};
inline constexpr RayChoice kDemoRayChoices[] = {
    {RayMethod::UnprojectGlm, Precision::Float}, {RayMethod::TwoPoint, Precision::Float},
    {RayMethod::InversePv, Precision::Float},    {RayMethod::FovTangent, Precision::Float},
    {RayMethod::PlaneCross, Precision::Float},   {RayMethod::PlaneCrossPre, Precision::Float},
    {RayMethod::Full, Precision::Float},         {RayMethod::Robust, Precision::Float},
    {RayMethod::Robust, Precision::Double}};
// "two_point float", "robust double", ...
std::string rayChoiceName(RayChoice choice);
// The choice after `choice` in kDemoRayChoices (a choice not in the list, e.g. two_point double,
// continues after its float entry).
RayChoice nextRayChoice(RayChoice choice);

// A ray for a pick, or why there is none.
struct PickRay {
  std::optional<Ray> ray;   // the method's ray, widened exactly to double
  std::string unavailable;  // empty when `ray` is set; otherwise why not (missing inputs,
                            // a non-finite ray: e.g. two_point's far point at infinity)
};

// The ray through the centre of pixel (lower-left origin) by `choice` on `camera`. Never throws.
PickRay pickRay(RayChoice choice, const CameraInputs& camera, Viewport viewport, glm::ivec2 pixel);

// The camera a frame drawn with `drawn` (its matrices as the app hands them to GL, built for
// drawn.mode, whose origin is glClipControl's) shows, as a lower-left origin numbers the
// framebuffer rows: for GL_UPPER_LEFT every matrix's y row negated (exact, in float too) and the
// origin lower-left, as the reconcile traces it (lowerLeftClipFromWorld). glReadPixels and the
// cursor count rows from the bottom whatever the origin, so the ray methods, the depth
// unprojection and the tolerance model all take this view. The fov scalars describe the camera as
// built, upright, and stay as they are.
CameraInputs lowerLeftCameraInputs(const CameraInputs& drawn);

// How the panel names the coordinates of `pixel (i, j)`: the framebuffer's, rows counted from the
// bottom as glReadPixels and gl_FragCoord count them under either clip origin; for GL_UPPER_LEFT
// it adds that clip space's y runs down those rows.
const char* pixelCoordinatesLabel(ClipOrigin origin);

// What the screen showed when the user clicked.
struct PickView {
  const Scene* scene = nullptr;
  // The camera as a lower-left origin sees the frame (lowerLeftCameraInputs): clipFromWorld and
  // mode always; projection, view, fov where known.
  CameraInputs camera;
  // glClipControl's origin the frame was drawn under (camera.mode is lower-left either way).
  ClipOrigin drawnOrigin = ClipOrigin::LowerLeft;
  // The camera's user clip planes, in the same world as the scene (moved with a teleport): the
  // picture was drawn with them, and every pick's ray is cut by them (cutToClipPlanes).
  std::vector<glm::dvec4> clipPlanes;
  DepthFormat depthFormat = DepthFormat::Float32;
  const RasterFrame* raster = nullptr;            // depth and ids read back from the same frame
  const SceneIntersector* intersector = nullptr;  // over the same (possibly teleported) scene
  // How the raster was drawn, when the caller knows: a pick whose ray and id buffer name
  // different primitives is then classified as the reconcile classifies such a pixel
  // (classifyMismatch), so that z-fighting and edges read "ambiguous", not "disagree".
  const RasterSetup* setup = nullptr;
};

struct PickResult {
  glm::ivec2 pixel{0};  // lower-left origin, framebuffer pixels
  Viewport framebuffer;
  RayChoice ray;
  DepthMode mode;  // as drawn: its origin is glClipControl's
  DepthFormat depthFormat = DepthFormat::Float32;
  std::size_t clipPlaneCount = 0;  // the user clip planes the picture and the ray were cut by
  // 1. analytic ray
  std::string rayUnavailable;  // not empty: the method could not run here ("n/a"); why
  int rayObject = -1;          // surface index (see surfaceIndex), -1: background (or no ray)
  std::optional<glm::dvec3> rayPoint;
  // 2. depth readback
  float windowDepth = 0.0f;
  std::optional<glm::dvec3> depthPoint;  // nullopt where the depth is the clear value
  // 3. id buffer
  int idObject = -1;
  std::uint32_t primitiveId = 0;
  // gaps between 1 and 2 (where both exist)
  std::optional<double> gapWorld;
  std::optional<double> gapPixels;  // gapWorld / one pixel's footprint at the depth point
  // How far from the clicked pixel's centre the ray's hit point projects, in framebuffer pixels: a
  // ray through the centre hits a point that projects back onto it, whatever it hits.
  std::optional<double> rayOffsetPixels;
  // Where the ray's primitive and the id buffer's differ (and PickView::setup is given): what the
  // reconcile calls such a pixel, one of the coverage and id mismatch classes.
  std::optional<PixelClass> reconcileClass;
  bool agree() const { return rayObject == idObject; }  // same object; meaningful with a ray
};

// A pick's verdict on 1 (the ray) against 3 (the id buffer), as the panel and the JSON line say it.
enum class PickVerdict {
  Agree,      // the same object, and the ray's hit projects into the clicked pixel
  Apart,      // the same object, but the ray's hit lands elsewhere on screen
  Ambiguous,  // different objects where the reconcile calls the pixel ambiguous (z-fighting, edge)
  Disagree,   // different objects, unexplained
  NoRay,      // the method gave no ray here
};
// "agree", "apart", "ambiguous", "disagree", "n/a"
const char* pickVerdictName(PickVerdict verdict);
// A hit projecting more than this far from the pixel centre lands outside the clicked pixel.
inline constexpr double kPickAgreementPixels = 0.5;

struct PickJudgement {
  PickVerdict verdict = PickVerdict::NoRay;
  std::string text;  // one line: "1 and 3 agree: box, hit 0.003 px from the pixel centre"
};
PickJudgement judgePick(const PickResult& result, const Scene& scene);

// pixel must lie inside the raster frame.
PickResult pick(const PickView& view, RayChoice ray, glm::ivec2 pixel);

// Surfaces are numbered mesh objects first, then analytic primitives: the index of the surface a
// primitive id belongs to (-1 for background), and its name ("background" for -1).
int surfaceIndex(const Scene& scene, const PrimitiveIdTable& ids, std::uint32_t primitiveId);
std::string surfaceName(const Scene& scene, int surface);

// Projects a world point to continuous framebuffer coordinates (lower-left origin; pixel (i, j)
// covers [i, i+1) x [j, j+1)). nullopt behind the camera.
std::optional<glm::dvec2> framebufferFromWorld(const glm::dmat4& clipFromWorld, Viewport viewport,
                                               const glm::dvec3& world);

// {pixel, framebuffer, method, precision, convention, clip_origin, clip_planes, depth_format,
// teleported, ray:{object, point}, depth:{point, window_depth}, id:{object}, gap_world, gap_px,
// ray_offset_px, same_object, agree, reconcile_class, verdict}; absent values are null;
// "convention" is the mode's name ("zo-upper-left"), "clip_origin" its origin ("lower-left" or
// "upper-left"), "clip_planes" how many user clip planes cut the picture and the ray; "ray",
// "same_object" and "agree" are null where the method could not run. "verdict" is
// pickVerdictName(judgePick(...)); "agree" is true exactly where the verdict is "agree" (the same
// object and the hit inside the clicked pixel); "same_object" compares objects only (true for an
// "apart" pick).
nlohmann::json pickJson(const PickResult& result, const Scene& scene, bool teleported);

}  // namespace clipray::demo
