#pragma once
// `clipray reconcile --capture FILE.rdc [--draws A-B]`: the frame an unmodified app drew, as a
// RenderDoc capture holds it, against the picking rays of the app's own camera matrix.
//
// The raster side is the capture's own depth buffer after the frame's last draw, replayed by
// RenderDoc (the capture reader's --depth-after), and each pixel's draw is the last one that
// changed it (the depth after every draw of the frame, one after the other). The ray side is the
// same draws' triangles as their vertex shaders put them out (RenderDoc's post-VS gl_Position,
// --geometry), taken back to world space through the inverse of the camera matrix found in the
// uniforms (p_world = clipFromWorld^-1 p_clip: the clip positions GL rasterized, to double
// rounding), and traced as a scene with that camera, compared pixel by pixel with the scene
// reconcile's classes, tolerance and report.
//
// What the rays are traced under is what the matrix says the app meant (the check's reading of
// it, ConventionCheck.hpp), not what the capture's state did: the depth convention the matrix was
// built for, its depth direction (reversed-Z keeps the greater depth), and face culling with the
// front face that keeps what the app's meshes show outside (FacingCheck.hpp). A correct app draws
// what it meant and is consistent; NO drawn under glClipControl's ZERO_TO_ONE, a reversed matrix
// under GL_LESS over overlapping surfaces, or GL_CCW left under a y-flipped projection show as the
// pixels where the two differ, and the check's own findings on the captured state are the run's
// convention findings (a frame whose pixels agree is still a convention-error where they are
// errors).
//
// Draws the frame: those into the last draw's depth attachment since the depth clear before it,
// with the depth test on and depth writes on (the others leave no depth to compare, and are
// listed). Refused, exit 2: draws the post-VS data cannot stand for (gl_ClipDistance in use,
// gl_FragDepth written, a depth test other than LESS, LEQUAL, GREATER, GEQUAL), a frame with no
// depth clear captured before it (what the buffer held is unknown), draws with different
// viewports, depth clamps or depth targets than the last, a multisampled depth target, more than
// 254 draws, and a frame with no camera matrix among its uniforms.

#include <cstdint>
#include <string>
#include <vector>

#include "clipray/compare/Reconcile.hpp"
#include "clipray/report/Report.hpp"
#include "clipray/trace/CaptureFileCheck.hpp"

namespace clipray::engine {

struct CaptureReconcileOptions {
  std::string capture;  // the .rdc file
  std::string draws;    // --draws A-B in RenderDoc event IDs; empty: every draw
  unsigned threads = 0;
};

struct CaptureReconcileResult {
  trace::CaptureCheckResult check;  // check --capture's reading of the draws
  RunRecord run;                    // the frame's comparison, a scene run's record
  PixelComparison pixels;
  std::vector<std::uint64_t> events;  // the draws compared (EIDs), in order
  std::uint64_t cameraEvent = 0;      // the draw whose matrix is the camera
  std::string cameraSource;           // where that matrix was found
  std::uint64_t clearEvent = 0;       // the depth clear the draws draw over
};

// Throws InputError (exit 2, nothing written) for what checkCapture refuses and what the header
// lists.
CaptureReconcileResult reconcileCapture(const CaptureReconcileOptions& options);

// The GL the frame was drawn with, as report.json records it: RenderDoc's replay of the capture.
GlInfo captureGlInfo(const CaptureReconcileResult& result);

}  // namespace clipray::engine
