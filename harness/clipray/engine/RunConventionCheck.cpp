#include "clipray/engine/RunConventionCheck.hpp"

#include <algorithm>
#include <cstdint>
#include <utility>

#include "clipray/InputError.hpp"
#include "clipray/check/FacingCheck.hpp"
#include "clipray/compare/ToleranceModel.hpp"
#include "clipray/trace/GlEnums.hpp"
#include "clipray/trace/TraceCheck.hpp"

namespace clipray::engine {

namespace {

// The state clipray's renderer draws the run with (gl/Renderer.cpp, beginFrame), as the check
// reads a draw's state. Culling is per object, so it is checked per object below.
trace::TraceDepthState drawnState(const Scene& scene, const Camera& camera, DepthMode mode,
                                  Viewport viewport, DepthFormat depthFormat) {
  trace::TraceDepthState state;
  state.clipZeroToOne = mode.convention == DepthConvention::ZeroToOne;
  state.clipUpperLeft = mode.origin == ClipOrigin::UpperLeft;
  state.depthTest = true;
  const bool greater = nearerIsGreater(mode, scene.depthRange);
  state.depthFunc = greater ? trace::kGlGreater : trace::kGlLess;
  state.clearedDepth = greater ? 0.0 : 1.0;
  state.depthRange = scene.depthRange;
  state.viewport = viewport;
  state.depthFormat = depthFormat;
  state.depthFormatName = depthFormatName(depthFormat);
  state.depthClamp = scene.depthClamp;
  state.clipDistances = static_cast<std::uint8_t>((1u << camera.clipPlanes.size()) - 1u);
  state.writesClipDistance = !camera.clipPlanes.empty();
  return state;
}

// Where the report's messages say the culling was set: the objects that draw with it.
std::string cullingObjects(const Scene& scene, CullFace cull, FrontFace frontFace) {
  std::string names;
  for (const MeshObject& object : scene.objects) {
    if (object.cull != cull || object.frontFace != frontFace) continue;
    names += (names.empty() ? "scene object \"" : ", \"") + object.name + "\"";
  }
  return names;
}

// The facing check for each culling state the scene's objects draw with, each once.
std::vector<Finding> cullingFindings(const Scene& scene, const glm::dmat4& clipFromWorld,
                                     DepthMode mode) {
  std::vector<Finding> findings;
  std::vector<std::pair<CullFace, FrontFace>> seen;
  for (const MeshObject& object : scene.objects) {
    const std::pair<CullFace, FrontFace> key{object.cull, object.frontFace};
    if (object.cull == CullFace::None || std::find(seen.begin(), seen.end(), key) != seen.end()) {
      continue;
    }
    seen.push_back(key);
    CullingState state;
    state.cull = object.cull;
    state.frontFace = object.frontFace;
    state.origin = mode.origin;
    state.reversedDepth = nearerIsGreater(mode, scene.depthRange);
    state.cullSetAt = cullingObjects(scene, object.cull, object.frontFace);
    state.frontFaceSetAt = state.cullSetAt;
    if (auto finding = faceCullingFinding(clipFromWorld, state)) {
      findings.push_back(std::move(*finding));
    }
  }
  return findings;
}

}  // namespace

std::vector<RunFinding> runConventionFindings(const Scene& scene, const Camera& camera,
                                              const glm::dmat4& drawnClipFromWorld, DepthMode mode,
                                              Viewport viewport, DepthFormat depthFormat) {
  CheckReport report;
  try {
    report =
        trace::checkUnderDepthState({"camera \"" + camera.name + "\"", false, drawnClipFromWorld},
                                    drawnState(scene, camera, mode, viewport, depthFormat));
  } catch (const InputError& error) {
    // The scene loader accepted the matrix; the check reads matrices an app can build and may not
    // take every one a scene can (then the run still reconciles, unchecked).
    return {{"warning", "matrix-not-checked", error.what(),
             "nothing in the scene: the run's pixels are reconciled all the same", false}};
  }
  // A transposed upload's winding means nothing (as in a trace).
  if (!report.properties.likelyTransposed) {
    for (Finding& finding : cullingFindings(scene, drawnClipFromWorld, mode)) {
      report.findings.push_back(std::move(finding));
    }
  }
  std::vector<RunFinding> findings;
  for (const Finding& finding : report.findings) {
    if (finding.severity != "error" && finding.severity != "warning") continue;
    const bool expected = std::find(camera.expectedFindings.begin(), camera.expectedFindings.end(),
                                    finding.code) != camera.expectedFindings.end();
    findings.push_back({finding.severity, finding.code, finding.message, finding.fix, expected});
  }
  return findings;
}

}  // namespace clipray::engine
