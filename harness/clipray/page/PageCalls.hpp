#pragma once
// A page's recording (PageRecorder.hpp) read as the trace checker reads an app: each recorded
// WebGL call becomes the line `apitrace dump` writes for the GL call it stands for, and those
// lines go through the same TraceCheckCollector as `clipray check --trace`'s. So the state model
// (GlTraceState), the grouping, the findings and the reports are the trace's, one per canvas.
//
// WebGL's rules that differ from a GL app's, applied while translating:
// - the viewport starts as the drawing buffer's size (WebGL 1.0, 5.13.4), GL's is the window's;
// - the drawing buffer of a context without preserveDrawingBuffer is cleared after each frame is
//   presented, depth to 1.0 whatever clearDepth holds (WebGL 1.0, 2.2 "The Drawing Buffer"): the
//   default framebuffer starts each frame cleared to 1 unless the page clears it;
// - the clip volume is z in [-w, w] unless EXT_clip_control's clipControlEXT says ZERO_TO_ONE_EXT
//   (EXT_clip_control, Khronos WebGL extension registry; the values are GL's).

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "clipray/trace/TraceCheck.hpp"

namespace clipray::page {

// One canvas's WebGL context and what its calls read as.
struct CanvasCheck {
  std::string name;       // "canvas#view" (its id) or "canvas 2" (the order contexts were made in)
  std::string type;       // "webgl2", "webgl", "experimental-webgl"
  nlohmann::json canvas;  // sizes, depth attributes, as recorded
  std::uint64_t calls = 0;
  std::uint64_t draws = 0;
  // State the trace's model does not follow, counted at the draws: depthMask(false) (the draw
  // leaves no depth to pick against) and POLYGON_OFFSET_FILL (the depth written is shifted by
  // polygonOffset's factor and units, the last ones such a draw used).
  std::uint64_t drawsWithoutDepthWrites = 0;
  std::uint64_t drawsWithPolygonOffset = 0;
  double polygonOffsetFactor = 0.0, polygonOffsetUnits = 0.0;
  std::optional<trace::TraceCheckResult> result;
  std::string notChecked;  // why not (no draws, no projection): then no result
};

struct PageCheckResult {
  std::string page;  // as given
  std::string url;   // as loaded
  double devicePixelRatio = 1.0;
  std::uint64_t frames = 0;        // requestAnimationFrame ticks recorded
  std::uint64_t draws = 0;         // of all canvases
  std::uint64_t callsNotKept = 0;  // past the recorder's cap
  std::vector<std::string> recorderErrors;
  std::vector<std::string> pageErrors;  // the page's uncaught errors (at most 10)
  std::vector<CanvasCheck> canvases;
  bool hasErrors() const;
};

// The analysis of a recording (the JSON `window.__clipray.snapshot()` returns). Throws
// InputError "<page>: ..." where the page made no WebGL context, never drew, or no canvas's draws
// have a projection to check.
// With `requireProjection` false (reconcile --page, which picks regardless), a page none of
// whose canvases has a projection is not refused: each canvas keeps its notChecked.
PageCheckResult checkRecording(const std::string& page, const nlohmann::json& recording,
                               bool requireProjection = true);

// Base64 (RFC 4648) as the recorder writes bytes (btoa); nullopt for other characters.
std::optional<std::string> base64Decoded(const std::string& text);

// The dump line (apitrace's text) a recorded call stands for; empty for calls the state model
// does not need. `call` numbers the line. Exposed for the tests.
std::string dumpLineFor(const nlohmann::json& record, std::uint64_t call);

}  // namespace clipray::page
