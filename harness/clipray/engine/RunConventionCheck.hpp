#pragma once
// Each reconcile run carries its camera's convention check: `clipray check` (ConventionCheck) on
// the matrix the run draws with, under the state it draws with (glClipControl's origin and depth
// mode, the depth test and clear value reversed-Z takes, glDepthRange, each culling object's
// glCullFace / glFrontFace, GL_DEPTH_CLAMP, the clip distances), as `clipray check --trace` and
// engine::checkCurrentState check an app's draw. Raster and rays can agree with each other while
// the app's depth state is wrong (a NO-built matrix drawn under ZERO_TO_ONE): the check says so.

#include <vector>

#include "clipray/report/Report.hpp"
#include "clipray/scene/Scene.hpp"

namespace clipray::engine {

// The check's errors and warnings (infos are left out: they neither fail a run nor need a look),
// each marked expected where the camera declares its code (Camera::expectedFindings). A matrix the
// check refuses gives one warning, "matrix-not-checked", with the check's reason.
// drawnClipFromWorld: the matrix as uploaded for the run (Camera::clipFromWorld(mode, viewport)).
std::vector<RunFinding> runConventionFindings(const Scene& scene, const Camera& camera,
                                              const glm::dmat4& drawnClipFromWorld, DepthMode mode,
                                              Viewport viewport, DepthFormat depthFormat);

}  // namespace clipray::engine
