#pragma once
// `clipray check --trace FILE [--frames A-B]`: the trace checker on `apitrace dump`'s output.

#include <string>

#include "clipray/trace/TraceCheck.hpp"

namespace clipray::cli {

// Throws InputError (exit 2) for a missing or unreadable file, a truncated trace, a file that is
// no trace, a trace without draws or projections, or apitrace missing.
trace::TraceCheckResult checkTrace(const std::string& tracePath, const std::string& frames);

// --verify: replays the trace headlessly (eglretrace -D CALL, WAFFLE_PLATFORM=surfaceless_egl)
// up to each group's first draw and adds what its depth buffer shows to the group. A replay that
// fails is noted in the group, not an error.
void verifyTrace(const std::string& tracePath, trace::TraceCheckResult& result);

}  // namespace clipray::cli
