#pragma once
// `clipray check --capture FILE.rdc [--draws A-B]`: a RenderDoc capture checked with the trace
// checker's state model, grouping and findings (TraceCheck.hpp); a second reader beside
// `apitrace dump`. RenderDoc's replay API is a Python module on Debian (python3-renderdoc), so
// harness/renderdoc/clipray-capture-reader.py replays the capture and writes one JSON object a
// line; this side runs it and parses the lines (CaptureDraw.hpp). No Python in the core.

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "clipray/trace/ReplayDepth.hpp"
#include "clipray/trace/TraceCheck.hpp"

namespace clipray::trace {

// At most this many draws are listed one by one in the report (all are checked).
inline constexpr std::size_t kMaxListedCaptureDraws = 1000;

struct CaptureCheckResult {
  TraceCheckResult check;  // occurrences' calls are RenderDoc event IDs (EIDs)
  // The capture's API as RenderDoc names its driver: "OpenGL" or "OpenGLES".
  std::string api = "OpenGL";
  std::uint64_t events = 0;
  std::uint64_t drawsInCapture = 0;
  std::optional<FrameRange> drawRange;  // --draws, in EIDs
  // Per draw in the range: what the state model does not follow (depth writes, polygon offset,
  // the program and its shaders' text), as the reader wrote it.
  std::vector<nlohmann::json> draws;
  // Every draw in the range as the state model read it, in event order (reconcile --capture),
  // with its viewport's lower-left corner (the state keeps the viewport's size only) and its
  // depth attachment (RenderDoc's resource id; the depth clear the state names is that one's).
  struct DrawState {
    TraceDraw draw;
    int viewportX = 0, viewportY = 0;
    std::string depthTarget;
  };
  std::vector<DrawState> drawStates;
};

// "A-B" or "A": RenderDoc event IDs. Throws InputError naming --draws.
FrameRange parseDrawRange(const std::string& text);

// Throws InputError (exit 2) for a missing or unreadable file, a file that is no capture, a
// truncated one, a capture of another API than OpenGL, the reader or RenderDoc's Python module
// missing, a draw range without draws, a capture without draws or projections.
// The reader: CLIPRAY_CAPTURE_READER, else clipray-capture-reader.py beside the running binary or
// in ../share/clipray; run by CLIPRAY_CAPTURE_PYTHON, else /usr/bin/python3 (Debian's, the one
// python3-renderdoc is built for).
CaptureCheckResult checkCapture(const std::string& capturePath, const std::string& draws);

// `--verify`: the depth attachment as each group's first draw leaves it, replayed by RenderDoc
// (the reader's --depth-after), set against the group's convention as `--trace --verify` sets a
// replayed one (ReplayDepth.hpp): at most 8 groups; a depth that cannot be read is noted in the
// group ("not verified: ..."), never an error.
void verifyCapture(const std::string& capturePath, CaptureCheckResult& result);

// The reader run on the capture with these arguments (--geometry, --depth-after EIDs): its JSON
// lines other than "capture" ones, in order. Throws InputError for an "error" line, or a reader
// that exits with another status than 0 (naming the status and its last other output).
std::vector<nlohmann::json> readCaptureLines(const std::string& capturePath,
                                             const std::vector<std::string>& arguments);

// The reader's --depth-after line: the image (window depths, rows from the bottom), or nullopt
// and why there is none in failure (the reader's own failure, or a line whose bytes do not match
// its size). Throws std::invalid_argument for base64 that is not.
std::optional<DepthImage> captureDepthImage(const nlohmann::json& line, std::string& failure);

nlohmann::json captureCheckJson(const CaptureCheckResult& result);
std::string captureCheckText(const CaptureCheckResult& result);

}  // namespace clipray::trace
