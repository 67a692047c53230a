#include "clipray/engine/CaptureReconcile.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <limits>
#include <map>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "clipray/InputError.hpp"
#include "clipray/SceneBuilder.hpp"
#include "clipray/check/CheckText.hpp"
#include "clipray/check/FacingCheck.hpp"
#include "clipray/compare/DepthMapping.hpp"
#include "clipray/compare/DrawCallIds.hpp"
#include "clipray/engine/ReconcileRun.hpp"
#include "clipray/engine/WorstPixels.hpp"
#include "clipray/report/RunImages.hpp"
#include "clipray/trace/CaptureGeometry.hpp"
#include "clipray/trace/GlEnums.hpp"
#include "clipray/trace/TraceCheck.hpp"

namespace clipray::engine {

namespace {

using trace::CaptureCheckResult;
using trace::TraceDepthState;

// idsFromDrawCalls numbers a pixel's draw in a byte, 0 being the background.
constexpr std::size_t kMaxFrameDraws = 254;
// A capture does not record GL_SUBPIXEL_BITS: the least GL allows (GL 4.6 table 23.54), whose
// edge epsilon is the widest.
constexpr int kAssumedSubpixelBits = 4;

std::string eventText(std::uint64_t event) {
  return "draw " + std::to_string(event);
}

bool keepsLess(std::uint32_t func) {
  return func == trace::kGlLess || func == trace::kGlLequal;
}
bool keepsGreater(std::uint32_t func) {
  return func == trace::kGlGreater || func == trace::kGlGequal;
}

CullFace cullFaceOf(const TraceDepthState& depth) {
  if (!depth.cullFace) return CullFace::None;
  return depth.cullFaceMode == trace::kGlFront ? CullFace::Front : CullFace::Back;
}

// What the draw's matrix says the app meant, read by the check under the captured state.
struct Reading {
  trace::TracedMatrix matrix;
  CheckReport report;
};

std::optional<Reading> readingOf(const trace::TraceDraw& draw) {
  for (const trace::TracedMatrix& matrix : draw.matrices) {
    try {
      return Reading{matrix, trace::checkUnderDepthState(matrix, draw.depth)};
    } catch (const InputError&) {
      // Not a camera the check can read (singular, not projective): the next one, if any.
    }
  }
  return std::nullopt;
}

// The convention the rays are traced under: the one the matrix was built for (the captured one
// where the entries cannot tell), its depth direction, the captured clip origin.
DepthMode intendedMode(const MatrixProperties& properties, const TraceDepthState& captured) {
  DepthMode mode;
  mode.origin = captured.clipUpperLeft ? ClipOrigin::UpperLeft : ClipOrigin::LowerLeft;
  const bool capturedZo = captured.clipZeroToOne;
  if (properties.builtFor == "no") {
    mode.convention = DepthConvention::NegativeOneToOne;
  } else if (properties.builtFor == "zo" || properties.builtFor == "zo-reversed") {
    mode.convention = DepthConvention::ZeroToOne;
  } else {
    mode.convention = capturedZo ? DepthConvention::ZeroToOne : DepthConvention::NegativeOneToOne;
  }
  const bool rangeReversed = captured.depthRange.x > captured.depthRange.y;
  // Reversed-Z is read from the matrix; where its entries cannot tell, from the depth test.
  const bool reversed = properties.reversedDecided
                            ? properties.reversed
                            : keepsGreater(captured.depthFunc) != rangeReversed;
  mode.reversed = reversed && mode.convention == DepthConvention::ZeroToOne;
  return mode;
}

DepthMode capturedMode(const TraceDepthState& depth) {
  DepthMode mode;
  mode.convention =
      depth.clipZeroToOne ? DepthConvention::ZeroToOne : DepthConvention::NegativeOneToOne;
  const bool rangeReversed = depth.depthRange.x > depth.depthRange.y;
  mode.reversed = mode.convention == DepthConvention::ZeroToOne &&
                  keepsGreater(depth.depthFunc) != rangeReversed;
  mode.origin = depth.clipUpperLeft ? ClipOrigin::UpperLeft : ClipOrigin::LowerLeft;
  return mode;
}

struct FrameDraw {
  const CaptureCheckResult::DrawState* state = nullptr;
  trace::CapturedDrawGeometry geometry;
  std::vector<float> depthAfter;    // the viewport's pixels, rows from the bottom
  std::vector<std::size_t> traced;  // the mesh's triangle k is geometry's triangle traced[k]
};

// The raster side knows each pixel's draw, not its triangle: idsFromDrawCalls names the triangle
// of that draw the pixel's ray hit. Where that triangle's depth is beyond the tolerance of the
// stored one, the stored depth may be another triangle's of the same draw whose edge passes
// within the rasterizer's snapping of the pixel centre (a sliver in front, covered by GL's fixed
// point, missed by the ray in double). Such a pixel is given the triangle of its draw, within
// `reach` pixels of its centre, whose depth at the centre (as GL interpolates it: NDC z is affine
// in window x and y, mapped by the captured convention and depth range) is nearest the stored
// one, when nearer than the first triangle's; the comparison then classifies the id mismatch
// (edge-ambiguous where the centre lies within either triangle's edge epsilon). Returns how many
// pixels changed.
std::size_t refineIdsByDepth(const std::vector<FrameDraw>& draws, const Scene& scene,
                             const DepthMapping& captured, bool upperLeft, Viewport viewport,
                             const std::vector<std::uint8_t>& drawOfPixel,
                             const PixelComparison& pixels, const std::vector<float>& depth,
                             double reach, std::vector<std::uint32_t>& ids) {
  const std::size_t count = drawOfPixel.size();
  std::vector<std::uint8_t> flagged(count, 0);
  bool any = false;
  for (std::size_t p = 0; p < count; ++p) {
    if (pixels.classes[p] == PixelClass::DepthBeyondTolerance) flagged[p] = 1, any = true;
  }
  if (!any) return 0;
  const PrimitiveIdTable table(scene);
  std::vector<double> bestError(count, std::numeric_limits<double>::infinity());
  std::vector<std::uint32_t> bestId(count, 0);
  for (std::size_t k = 0; k < draws.size(); ++k) {
    const std::vector<glm::dvec4>& clip = draws[k].geometry.clip;
    for (std::size_t t = 0; t < draws[k].traced.size(); ++t) {
      const std::size_t first = 3 * draws[k].traced[t];
      glm::dvec3 window[3];
      bool inFront = true;
      for (std::size_t c = 0; c < 3; ++c) {
        const glm::dvec4& v = clip[first + c];
        if (!(v.w > 0.0)) inFront = false;
        const double y = upperLeft ? -v.y / v.w : v.y / v.w;
        window[c] = {(v.x / v.w * 0.5 + 0.5) * viewport.width, (y * 0.5 + 0.5) * viewport.height,
                     v.z / v.w};
      }
      if (!inFront) continue;
      const glm::dvec2 a(window[0]), b(window[1]), c(window[2]);
      const double area = (b.x - a.x) * (c.y - a.y) - (c.x - a.x) * (b.y - a.y);
      if (area == 0.0) continue;
      const int x0 = std::max(0, static_cast<int>(std::floor(std::min({a.x, b.x, c.x}) - reach)));
      const int x1 = std::min(viewport.width - 1,
                              static_cast<int>(std::ceil(std::max({a.x, b.x, c.x}) + reach)));
      const int y0 = std::max(0, static_cast<int>(std::floor(std::min({a.y, b.y, c.y}) - reach)));
      const int y1 = std::min(viewport.height - 1,
                              static_cast<int>(std::ceil(std::max({a.y, b.y, c.y}) + reach)));
      const std::uint32_t id = table.firstIdOfObject[k] + static_cast<std::uint32_t>(t);
      for (int y = y0; y <= y1; ++y) {
        for (int x = x0; x <= x1; ++x) {
          const std::size_t p = static_cast<std::size_t>(y) * viewport.width + x;
          if (!flagged[p] || drawOfPixel[p] != k + 1) continue;
          const glm::dvec2 centre(x + 0.5, y + 0.5);
          // Barycentric coordinates of the centre, and its distance outside each edge in pixels.
          const double l1 =
              ((centre.x - a.x) * (c.y - a.y) - (c.x - a.x) * (centre.y - a.y)) / area;
          const double l2 =
              ((b.x - a.x) * (centre.y - a.y) - (centre.x - a.x) * (b.y - a.y)) / area;
          const double l0 = 1.0 - l1 - l2;
          const double lengths[3] = {glm::length(c - b), glm::length(a - c), glm::length(b - a)};
          const double weights[3] = {l0, l1, l2};
          double outside = 0.0;
          for (int e = 0; e < 3; ++e) {
            // Weight e is 0 on the opposite edge and 1 at vertex e: its distance from that edge
            // is the weight times the triangle's height over it, |area| / length.
            outside = std::max(outside, -weights[e] * std::abs(area) / lengths[e]);
          }
          if (outside > reach) continue;
          const double z = l0 * window[0].z + l1 * window[1].z + l2 * window[2].z;
          const double error = std::abs(captured.mappedWindowDepth(z) - depth[p]);
          if (error < bestError[p]) {
            bestError[p] = error;
            bestId[p] = id;
          }
        }
      }
    }
  }
  std::size_t changed = 0;
  for (std::size_t p = 0; p < count; ++p) {
    if (!flagged[p] || bestId[p] == 0 || bestId[p] == ids[p]) continue;
    ids[p] = bestId[p];
    ++changed;
  }
  return changed;
}

}  // namespace

CaptureReconcileResult reconcileCapture(const CaptureReconcileOptions& options) {
  CaptureReconcileResult result;
  result.check = trace::checkCapture(options.capture, options.draws);
  const std::string& path = options.capture;
  const auto& states = result.check.drawStates;
  if (states.empty()) throw InputError(path + ": no draws to reconcile");
  const CaptureCheckResult::DrawState& last = states.back();
  const TraceDepthState& lastDepth = last.draw.depth;
  if (!lastDepth.clearedDepth || lastDepth.clearCall == 0) {
    throw InputError(path + ": " + eventText(last.draw.call) +
                     ": no depth clear is captured before it, so what the depth buffer held "
                     "before the frame's draws is unknown (capture a whole frame, from its "
                     "glClear)");
  }
  result.clearEvent = lastDepth.clearCall;
  std::vector<std::string> notes;
  std::vector<const CaptureCheckResult::DrawState*> frame;
  for (const auto& state : states) {
    const TraceDepthState& depth = state.draw.depth;
    // The frame: the draws into the last draw's depth attachment since its clear.
    if (state.depthTarget != last.depthTarget || depth.clearCall != lastDepth.clearCall) continue;
    const std::string name = eventText(state.draw.call);
    if (!depth.depthTest || !depth.depthWrite) {
      notes.push_back(name + ": not compared (" +
                      (depth.depthTest ? "depth writes off" : "depth test off") +
                      ": it leaves no depth)");
      continue;
    }
    if (!keepsLess(depth.depthFunc) && !keepsGreater(depth.depthFunc)) {
      throw InputError(path + ": " + name + ": depth test " + trace::glEnumName(depth.depthFunc) +
                       ": reconcile --capture compares draws whose depth test keeps the nearer "
                       "or the farther surface (LESS, LEQUAL, GREATER, GEQUAL)");
    }
    if (depth.clipDistances != 0 && depth.writesClipDistance) {
      throw InputError(path + ": " + name +
                       ": clips with gl_ClipDistance, which the post-vertex-shader positions do "
                       "not hold: reconcile --capture cannot trace it");
    }
    if (depth.fragDepthProgram != 0) {
      throw InputError(path + ": " + name +
                       ": its fragment shader writes gl_FragDepth, so the depth it stores is not "
                       "the triangles' (check --capture reports it)");
    }
    if (depth.depthClamp != lastDepth.depthClamp) {
      throw InputError(path + ": " + name + ": depth clamp " + (depth.depthClamp ? "on" : "off") +
                       " where the frame's last draw has it " +
                       (lastDepth.depthClamp ? "on" : "off"));
    }
    if (depth.viewport != lastDepth.viewport || state.viewportX != last.viewportX ||
        state.viewportY != last.viewportY) {
      throw InputError(path + ": " + name +
                       ": drawn with another viewport than the frame's last draw; reconcile "
                       "--capture compares one viewport (use --draws)");
    }
    if (depth.cullFace && depth.cullFaceMode == trace::kGlFrontAndBack) {
      notes.push_back(name + ": culls GL_FRONT_AND_BACK: draws nothing");
      continue;
    }
    frame.push_back(&state);
  }
  if (frame.empty()) {
    throw InputError(path + ": no draw since the depth clear at event " +
                     std::to_string(lastDepth.clearCall) + " writes depth");
  }
  if (frame.size() > kMaxFrameDraws) {
    throw InputError(path + ": " + std::to_string(frame.size()) +
                     " draws write depth since the clear at event " +
                     std::to_string(lastDepth.clearCall) +
                     "; reconcile --capture compares at most " + std::to_string(kMaxFrameDraws) +
                     " (use --draws)");
  }
  if (!lastDepth.depthFormat) {
    throw InputError(path + ": the depth attachment's format (" + lastDepth.depthFormatName +
                     ") is not one clipray models (16, 24, 32f)");
  }

  // One replay: each draw's post-VS triangles, then the depth after each.
  std::string events;
  for (const auto* state : frame) {
    events += (events.empty() ? "" : ",") + std::to_string(state->draw.call);
  }
  const std::vector<nlohmann::json> lines =
      trace::readCaptureLines(path, {"--geometry", "--depth-after", events});
  std::map<std::uint64_t, trace::CapturedDrawGeometry> geometries;
  std::map<std::uint64_t, const nlohmann::json*> depthLines;
  for (const nlohmann::json& line : lines) {
    const std::string kind = line.value("kind", "");
    try {
      if (kind == "geometry") {
        trace::CapturedDrawGeometry geometry = trace::capturedDrawGeometry(line);
        geometries[geometry.event] = std::move(geometry);
      } else if (kind == "depth") {
        depthLines[line.value("event", std::uint64_t{0})] = &line;
      }
    } catch (const std::exception& error) {
      throw InputError(path + ": the capture reader's " + kind + " line: " + error.what());
    }
  }
  const int viewportX = last.viewportX, viewportY = last.viewportY;
  const Viewport viewport = lastDepth.viewport;
  const std::size_t pixelCount =
      static_cast<std::size_t>(viewport.width) * static_cast<std::size_t>(viewport.height);
  if (viewport.width <= 0 || viewport.height <= 0) {
    throw InputError(path + ": an empty viewport at " + eventText(last.draw.call));
  }
  std::vector<FrameDraw> draws;
  std::string target;
  for (const auto* state : frame) {
    const std::uint64_t event = state->draw.call;
    const std::string name = eventText(event);
    const auto geometry = geometries.find(event);
    const auto depthLine = depthLines.find(event);
    if (geometry == geometries.end() || depthLine == depthLines.end()) {
      throw InputError(path + ": the capture reader gave no geometry or depth for " + name);
    }
    if (!geometry->second.skipped.empty()) {
      notes.push_back(name + ": not compared (" + geometry->second.skipped + ")");
      continue;
    }
    if (target.empty()) target = geometry->second.depthTarget;
    if (geometry->second.depthTarget != target) {
      throw InputError(path + ": " + name + " draws into depth target " +
                       geometry->second.depthTarget + ", the frame's first draw into " + target +
                       " (use --draws)");
    }
    if (geometry->second.instances > 1) {
      notes.push_back(name + ": " + std::to_string(geometry->second.instances) +
                      " instances drawn, only instance 0 traced");
    }
    const nlohmann::json& line = *depthLine->second;
    if (line.value("samples", 1) > 1) {
      throw InputError(path + ": the depth target is multisampled (" +
                       std::to_string(line.value("samples", 1)) +
                       " samples): reconcile --capture reads single-sampled depth only");
    }
    std::string failure;
    std::optional<trace::DepthImage> image;
    try {
      image = trace::captureDepthImage(line, failure);
    } catch (const std::invalid_argument& error) {
      failure = error.what();
    }
    if (!image) throw InputError(path + ": the depth after " + name + ": " + failure);
    if (image->width < viewportX + viewport.width || image->height < viewportY + viewport.height ||
        viewportX < 0 || viewportY < 0) {
      throw InputError(path + ": the " + std::to_string(image->width) + "x" +
                       std::to_string(image->height) + " depth target does not hold the " +
                       std::to_string(viewport.width) + "x" + std::to_string(viewport.height) +
                       " viewport at (" + std::to_string(viewportX) + ", " +
                       std::to_string(viewportY) + ")");
    }
    FrameDraw draw;
    draw.state = state;
    draw.geometry = std::move(geometry->second);
    draw.depthAfter.resize(pixelCount);
    for (int y = 0; y < viewport.height; ++y) {
      const auto* row =
          image->depth.data() + static_cast<std::size_t>(y + viewportY) * image->width + viewportX;
      std::copy(row, row + viewport.width,
                draw.depthAfter.begin() + static_cast<std::ptrdiff_t>(y) * viewport.width);
    }
    draws.push_back(std::move(draw));
  }
  if (draws.empty()) throw InputError(path + ": no draw of the frame draws triangles");

  // Each pixel's draw: the last whose depth differs there from the one before it (the clear
  // before the first).
  std::vector<std::uint8_t> drawOfPixel(pixelCount, 0);
  std::vector<std::size_t> pixelsOfDraw(draws.size(), 0);
  const float cleared = static_cast<float>(*lastDepth.clearedDepth);
  for (std::size_t p = 0; p < pixelCount; ++p) {
    float before = cleared;
    for (std::size_t k = 0; k < draws.size(); ++k) {
      const float after = draws[k].depthAfter[p];
      if (after != before) drawOfPixel[p] = static_cast<std::uint8_t>(k + 1);
      before = after;
    }
    if (drawOfPixel[p] != 0) ++pixelsOfDraw[drawOfPixel[p] - 1];
  }

  // The camera: the matrix of the draw that shows most, among those with one the check reads.
  std::optional<Reading> camera;
  std::size_t cameraDraw = 0;
  for (std::size_t k = 0; k < draws.size(); ++k) {
    if (camera && pixelsOfDraw[k] <= pixelsOfDraw[cameraDraw]) continue;
    if (std::optional<Reading> reading = readingOf(draws[k].state->draw)) {
      camera = std::move(reading);
      cameraDraw = k;
    }
  }
  if (!camera) {
    throw InputError(path +
                     ": no draw of the frame has a camera matrix among its vertex "
                     "shader's uniforms (check --capture lists what was found): reconcile "
                     "--capture traces the picking rays of the app's camera");
  }
  const TraceDepthState& cameraDepth = draws[cameraDraw].state->draw.depth;
  const glm::dmat4 clipFromWorld = camera->matrix.matrix;
  const glm::dmat4 worldFromClip = glm::inverse(clipFromWorld);
  const DepthMode mode = intendedMode(camera->report.properties, cameraDepth);
  result.cameraEvent = draws[cameraDraw].state->draw.call;
  result.cameraSource = camera->matrix.source;

  // The scene: one mesh per draw, its clip positions taken back through the camera.
  const std::string stem = std::filesystem::path(path).stem().string();
  SceneBuilder builder(stem.empty() ? "capture" : stem);
  builder.depthRange(lastDepth.depthRange.x, lastDepth.depthRange.y);
  builder.depthClamp(lastDepth.depthClamp);
  std::size_t unplaced = 0;
  for (FrameDraw& draw : draws) {
    const TraceDepthState& depth = draw.state->draw.depth;
    std::vector<double> positions;
    std::vector<std::uint32_t> indices;
    const std::vector<glm::dvec4>& clip = draw.geometry.clip;
    for (std::size_t t = 0; t + 2 < clip.size(); t += 3) {
      std::array<glm::dvec3, 3> corners;
      bool placed = true;
      for (int c = 0; c < 3; ++c) {
        const glm::dvec4 world = worldFromClip * clip[t + static_cast<std::size_t>(c)];
        // A vertex the camera's inverse sends to infinity: drawn with another projection.
        if (!(std::abs(world.w) > 1e-12) || !std::isfinite(world.w)) placed = false;
        corners[static_cast<std::size_t>(c)] = glm::dvec3(world) / world.w;
      }
      if (!placed) {
        ++unplaced;
        continue;
      }
      draw.traced.push_back(t / 3);
      for (const glm::dvec3& corner : corners) {
        indices.push_back(static_cast<std::uint32_t>(positions.size() / 3));
        positions.insert(positions.end(), {corner.x, corner.y, corner.z});
      }
    }
    builder.mesh(eventText(draw.state->draw.call), positions, indices);
    const CullFace cull = cullFaceOf(depth);
    if (cull != CullFace::None) {
      // The front face the app meant: the captured one, turned where the matrix reverses the
      // winding on screen and glFrontFace does not account for it (FacingCheck.hpp).
      CullingState culling;
      culling.cull = cull;
      culling.frontFace = depth.frontFace == trace::kGlCw ? FrontFace::Cw : FrontFace::Ccw;
      culling.origin = mode.origin;
      culling.reversedDepth = mode.reversed;
      FrontFace front = culling.frontFace;
      if (faceCullingFinding(clipFromWorld, culling)) {
        front = front == FrontFace::Ccw ? FrontFace::Cw : FrontFace::Ccw;
        notes.push_back(eventText(draw.state->draw.call) + ": traced with glFrontFace(" +
                        (front == FrontFace::Cw ? "GL_CW" : "GL_CCW") +
                        "), the winding its matrix makes of the outsides; captured " +
                        (culling.frontFace == FrontFace::Cw ? "GL_CW" : "GL_CCW"));
      }
      builder.faceCulling(cull, front);
    }
    if (depth.depthRange != lastDepth.depthRange) {
      builder.objectDepthRange(depth.depthRange.x, depth.depthRange.y);
    }
    if (depth.polygonOffsetFill && (depth.offsetFactor != 0.0 || depth.offsetUnits != 0.0)) {
      builder.objectPolygonOffset(depth.offsetFactor, depth.offsetUnits, depth.offsetClamp);
    }
  }
  if (unplaced > 0) {
    notes.push_back(std::to_string(unplaced) +
                    " triangles not traced: the camera's inverse sends a corner to infinity "
                    "(drawn with another projection)");
  }
  builder.camera("capture", clipFromWorld, viewport);
  const TestScene scene = builder.build();
  const Scene& model = scene.model();

  AnalyticPass pass =
      runAnalyticPass(model, model.cameras.front(), mode, viewport, options.threads);
  RasterFrame raster;
  raster.viewport = viewport;
  raster.depth = draws.back().depthAfter;
  raster.ids = idsFromDrawCalls(model, pass.camera, drawOfPixel, pass.frame);
  const gl::RenderTimings timings;
  ComparedRun compared =
      compareRasterFrame(pass, raster, *lastDepth.depthFormat, VertexMode::Pretransformed,
                         kAssumedSubpixelBits, timings, options.threads);
  const DepthMapping capturedMapping{capturedMode(lastDepth), lastDepth.depthRange,
                                     lastDepth.depthClamp};
  const std::size_t refined = refineIdsByDepth(
      draws, model, capturedMapping, lastDepth.clipUpperLeft, viewport, drawOfPixel,
      compared.pixels, raster.depth, 1.0 / (1 << kAssumedSubpixelBits), raster.ids);
  if (refined > 0) {
    // The tolerance model holds the screen polygons of the triangles the raster showed.
    pass.toleranceModel.reset();
    compared = compareRasterFrame(pass, raster, *lastDepth.depthFormat, VertexMode::Pretransformed,
                                  kAssumedSubpixelBits, timings, options.threads);
    notes.push_back(std::to_string(refined) +
                    " pixels' triangle taken from the depth they store: another triangle of "
                    "their draw within the rasterizer's snapping of their centre (the ray hit "
                    "one whose depth is beyond tolerance)");
  }
  RunRecord& run = compared.run;
  run.camera = "events " + std::to_string(draws.front().state->draw.call) + "-" +
               std::to_string(draws.back().state->draw.call);

  run.notes.push_back("rays traced under " + mode.name() + ", the convention " +
                      camera->matrix.source + " at " + eventText(result.cameraEvent) +
                      " was built for; captured: " + capturedMode(cameraDepth).name() + ", " +
                      trace::glEnumName(cameraDepth.depthFunc));
  run.notes.push_back("GL_SUBPIXEL_BITS is not in a capture: " +
                      std::to_string(kAssumedSubpixelBits) + " assumed, the least GL allows");
  run.notes.insert(run.notes.end(), notes.begin(), notes.end());
  for (const Finding& finding : camera->report.findings) {
    if (finding.severity != "error" && finding.severity != "warning") continue;
    run.conventionFindings.push_back(
        {finding.severity, finding.code, finding.message, finding.fix, false});
  }
  describeHits(pass, raster, compared.pixels, run);
  encodeRunImages(run, compared.pixels);
  encodeThumbnails(run, compared.pixels);
  encodeClusterCrops(run, compared.pixels);
  for (const FrameDraw& draw : draws) result.events.push_back(draw.state->draw.call);
  result.run = std::move(run);
  result.pixels = std::move(compared.pixels);
  return result;
}

GlInfo captureGlInfo(const CaptureReconcileResult& result) {
  GlInfo gl;
  gl.backend = "renderdoc";
  gl.vendor = "RenderDoc";
  gl.renderer = "the replay of " + result.check.check.traceName;
  gl.version = result.check.api;
  gl.subpixelBits = kAssumedSubpixelBits;
  return gl;
}

}  // namespace clipray::engine
