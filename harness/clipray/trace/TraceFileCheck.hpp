#pragma once
// `clipray check --trace FILE [--frames A-B]`: a trace file checked by running `apitrace dump` on
// it and streaming its output into the trace checker (TraceCheck.hpp).

#include <string>

#include "clipray/trace/TraceCheck.hpp"

namespace clipray::trace {

// Throws InputError (exit 2) for a missing or unreadable file, a truncated trace, a file that is
// no trace, a trace without draws or projections, or apitrace missing.
TraceCheckResult checkTrace(const std::string& tracePath, const std::string& frames);

// --verify: replays the trace headlessly (eglretrace -D CALL, WAFFLE_PLATFORM=surfaceless_egl)
// up to each group's first draw and adds what its depth buffer shows to the group. A replay that
// fails is noted in the group, not an error.
void verifyTrace(const std::string& tracePath, TraceCheckResult& result);

}  // namespace clipray::trace
