#pragma once
// The toggled run of `clipray reconcile --page` (issue #40, item 2: "for the page as it is and
// with reversedDepthBuffer toggled where the page allows"): the same page loaded again in the
// same browser with its renderer's reversed depth buffer flipped (on where the page has it off,
// off where it has it on), picked and checked as the first load is.
//
// How, without changing the page (three.js 0.187, src/renderers): WebGLRenderer's constructor
// reads `reversedDepthBuffer` once; WebGLCapabilities keeps it only where the context has
// EXT_clip_control, and initGLContext then calls state.buffers.depth.setReversed(true). Every
// later use asks the depth buffer's getReversed(): setReversed calls clipControlEXT(LOWER_LEFT,
// ZERO_TO_ONE or NEGATIVE_ONE_TO_ONE) and re-sends the clear depth (1 - d when reversed), setFunc
// maps each material's depthFunc through ReversedDepthFuncs, polygon offsets change sign,
// WebGLPrograms compiles USE_REVERSED_DEPTH_BUFFER into its programs, and a render through a camera
// whose reversedDepth is false sets it and calls camera.updateProjectionMatrix() (never back:
// a camera once drawn reversed stays so). The renderer announces itself to
// window.__THREE_DEVTOOLS__ ('observe') at the end of its constructor, after initGLContext and
// before it can draw: the recorder calls setReversed(!getReversed()) there
// (PageRecorder.cpp), which is what the constructor's parameter would have done, with no camera
// drawn yet. Flipping later, on a page that has drawn, would leave its cameras reversed.
//
// The rule ("where the page allows"): a toggled run is made unless
//   - the page's three.js has no reversed depth buffer (its depth buffer has no setReversed:
//     before r169);
//   - the page's depth is not reversed and its context has no EXT_clip_control (three.js would
//     ignore reversedDepthBuffer: true there, with a warning);
//   - the page uses a logarithmic depth buffer (three.js turns it off under reversed depth, so the
//     toggled page would not be one three.js makes).
// What the page does by hand is toggled all the same and shows as it is: three.js reverses what
// it owns (clip control, clear value, materials' depth functions, the projections of the cameras
// it updates); a projection the page built itself and keeps (an updateProjectionMatrix of its
// own), a depth state set on the context directly, stay as the page made them, and the toggled
// run's picks and state check say what that does.

#include <string>

#include <nlohmann/json.hpp>

namespace clipray::page {

// Why the page as it is cannot be toggled (the rule above), or "" where it can; `facts` is the
// "toggle" object of the first load's picks ({setReversed, clipControl, logarithmicDepthBuffer})
// and `reversed` its reversed depth buffer.
std::string toggleRefusal(const nlohmann::json& facts, bool reversed);

// Whether the toggled load flipped the page's renderer as asked: "" where its depth buffer ended
// up `want` (each observed renderer toggled without failure), else why not. `facts` is the
// toggled load's "toggle" object ({toggled: [{from, to, failure}]}), `reversed` what its drawing
// renderer reported.
std::string toggleFailure(const nlohmann::json& facts, bool reversed, bool want);

}  // namespace clipray::page
