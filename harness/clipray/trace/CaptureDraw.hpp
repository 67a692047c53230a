#pragma once
// One draw of a RenderDoc capture as harness/renderdoc/clipray-capture-reader.py writes it (a
// JSON object a line), read into the trace checker's state model (GlTraceState.hpp): the same
// TraceDraw a dump's draw becomes, so grouping, findings and reports are the trace check's.

#include <nlohmann/json.hpp>

#include "clipray/trace/GlTraceState.hpp"

namespace clipray::trace {

// A "draw" line's state, calls (RenderDoc event IDs) and the vertex stage's 4x4 matrices with a
// projection's structure. Throws std::invalid_argument naming a field missing or of a wrong type.
TraceDraw captureDrawOf(const nlohmann::json& line);

}  // namespace clipray::trace
