#pragma once
// `clipray reconcile --page URL|file.html [--grid CxR] [--frames N] [--timeout S] [--no-toggle]`: a
// three.js page's own picking against its own picture. The page is loaded as `check --page
// --verify` loads it (PageCheck.hpp), with window.__THREE_DEVTOOLS__ defined before its scripts so
// that three.js announces its renderers; each renderer's render is wrapped to keep the scene and
// camera it drew last. After the N frames, the page's own Raycaster (from window.THREE or the
// module the page imported) is set from the camera at the centres of a C x R grid of the drawing
// buffer's pixels (NDC as a pointer handler computes it from CSS pixels), its first hit is mapped
// through the camera's projection * view to window depth under the page's depth state
// (EXT_clip_control's depth mode, depthRange) and compared with the depth buffer the last frame
// left at that pixel, read in the same task (PageRecorder.cpp's readDepth).
//
// Each pick is one class, as a reconcile's pixel: agree (a hit whose depth is within the
// tolerance of the buffer's, or no hit over a pixel that kept the clear depth), depth beyond the
// tolerance, or a coverage mismatch (the ray hits and the pixel kept the clear depth, or the
// reverse); the last two are edge-ambiguous where the rays 2^-SUBPIXEL_BITS pixel around the
// centre reach different objects, else unexplained. The page is consistent without unexplained
// picks.
//
// Then, where the page allows, the same browser loads the page again with its renderer's
// reversed depth buffer toggled and picks it the same way (PageToggle.hpp): the toggled run,
// reported beside the first; index.html and the picks images are PageHtml.hpp's.

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "clipray/page/PageCheck.hpp"

namespace clipray::page {

struct PageReconcileOptions {
  PageOptions page;
  int columns = 32, rows = 24;
  // A second load of the page with its reversed depth buffer toggled (PageToggle.hpp), in the
  // same browser; false: the page as it is only (--no-toggle).
  bool toggle = true;
};

// One pick, as classified.
struct PagePick {
  enum class Kind { Agree, DepthBeyondTolerance, RayOnly, RasterOnly };
  int x = 0, y = 0;  // the drawing buffer's pixel, y from the top
  Kind kind = Kind::Agree;
  bool ambiguous = false;
  bool hit = false, surface = false;  // the ray hit something; the pixel is not the clear depth
  double rayDepth = 0.0, bufferDepth = 0.0, tolerance = 0.0;
  std::string object;  // what the ray hit first
};

struct PageReconcileResult {
  PageCheckResult check;
  std::string revision;  // three.js's REVISION
  std::string canvas;
  int width = 0, height = 0;
  double cssWidth = 0.0, cssHeight = 0.0, devicePixelRatio = 1.0;
  int columns = 0, rows = 0;
  nlohmann::json camera;
  bool reversedDepthBuffer = false;
  std::string clipDepth;  // negative-one-to-one, zero-to-one
  double clearDepth = 1.0, depthRangeNear = 0.0, depthRangeFar = 1.0;
  std::string depthFormat;
  int subpixelBits = 0;
  std::vector<PagePick> picks;

  // The toggled run (PageToggle.hpp), on the result of the page as it is: made (run), or why not
  // (notApplicable: the page does not allow it; skipped: --no-toggle), or failed (the toggled
  // load did not give picks: why).
  struct Toggle {
    std::string notApplicable, skipped, failed;
    std::shared_ptr<const PageReconcileResult> run;
  };
  Toggle toggle;
  bool toggled = false;  // this result is the toggled run

  struct Counts {
    std::uint64_t agreeSurface = 0, agreeBackground = 0;
    std::uint64_t depthEdge = 0, depthUnexplained = 0;
    std::uint64_t rayOnlyEdge = 0, rayOnlyUnexplained = 0;
    std::uint64_t rasterOnlyEdge = 0, rasterOnlyUnexplained = 0;
  };
  Counts counts() const;
  double maxDepthError() const;  // over the picks that hit a drawn pixel
  double maxErrorOverTolerance() const;
  bool consistent() const;
  // consistent(), and the toggled run's where one was made; a failed toggled run is not.
  bool allConsistent() const;
};

// Throws InputError (exit 2, nothing written) for what checkPage refuses, and for a page without
// three.js (no renderer observed, none drew through a camera, its Raycaster out of reach: the
// line says so and gives the state check's counts) or whose depth cannot be read. The toggled
// run's failures are reported in result.toggle.failed instead.
PageReconcileResult reconcilePage(const PageReconcileOptions& options);

// The report of the page as it is, with the toggled run under "toggled" (the same fields for
// that run, or why there is none) and "overall" (allConsistent()).
nlohmann::json pageReconcileJson(const PageReconcileResult& result);
std::string pageReconcileText(const PageReconcileResult& result);

// The class of a pick as the report names it: agree, depth-beyond-tolerance, ray-only,
// raster-only.
const char* pagePickClassName(PagePick::Kind kind);
// "E errors, W warnings, N notes" of the state check (and each canvas not checked, why).
std::string pageStateCheckCounts(const PageCheckResult& check);

}  // namespace clipray::page
