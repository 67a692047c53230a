#pragma once
// The script `clipray check --page` adds to the page before the page's own scripts
// (Page.addScriptToEvaluateOnNewDocument): it wraps the WebGL and WebGL2 context methods that
// decide the depth state and the matrices, and keeps each call in `window.__clipray`.

#include <cstdint>
#include <string>

namespace clipray::page {

// The recorder's source, recording `frames` animation frames (and the calls before the first).
// With `verify`, contexts are made with preserveDrawingBuffer and without antialiasing, and
// `window.__clipray.readDepth()` returns each canvas's depth buffer (PageCheck.hpp).
// What it keeps, per call, is an array [context, name, arguments...] (PageCalls.hpp reads
// them); `window.__clipray.progress()` returns "frames draws contexts done", and
// `window.__clipray.snapshot()` the whole recording as one JSON string.
// With `three`, window.__THREE_DEVTOOLS__ is defined before the page's scripts and
// `window.__clipray.findThree(importer)` / `pick(columns, rows)` serve reconcile --page
// (PageReconcile.hpp). With `toggleReversedDepth` too, each observed WebGLRenderer's reversed
// depth buffer is flipped as it announces itself, before its first frame (PageToggle.hpp).
std::string pageRecorderScript(std::uint64_t frames, bool verify, bool three = false,
                               bool toggleReversedDepth = false);

}  // namespace clipray::page
