#pragma once
// `clipray check --trace`: the convention check on what a real GL app did, read from an apitrace
// trace's text dump one line at a time (memory bounded by the distinct (matrix, depth state)
// pairs, not by the trace). Each distinct pair gets the matrix check (ConventionCheck) with the
// traced depth state as the declared state, plus findings only a trace can give; pairs whose
// analysis reads alike (an animated MVP over many frames) are reported as one group.

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

#include <nlohmann/json.hpp>

#include "clipray/check/ConventionCheck.hpp"
#include "clipray/trace/GlTraceState.hpp"

namespace clipray::trace {

// At most this many distinct (matrix, depth state) pairs are kept; draws with further new pairs
// are counted, not analysed. Each pair costs a few hundred bytes and one matrix analysis.
inline constexpr std::size_t kMaxDistinctPairs = 20000;
// And at most this many per source (one animated uniform must not crowd out the others).
inline constexpr std::size_t kMaxPairsPerSource = 1000;

struct FrameRange {
  std::uint64_t first = 0;
  std::uint64_t last = UINT64_MAX;
};

// The matrix check on one matrix with this depth state as the declared state (declaredDepth from
// the clip control, reversed from a GREATER/GEQUAL depth test, depth range, origin, viewport,
// depth format), the texture-space reading of a biased projection, and the findings only a depth
// state gives (clear depth, reversed depth range, the depth func's call). Throws InputError where
// the matrix check refuses the matrix. Used by the trace checker and engine::checkCurrentState.
CheckReport checkUnderDepthState(const TracedMatrix& matrix, const TraceDepthState& depth,
                                 CheckInput* inputUsed = nullptr);

// "A-B" or "A" (frames count from 0, as apitrace's). Throws InputError naming --frames.
FrameRange parseFrameRange(const std::string& text);

struct Occurrence {
  std::uint64_t frame = 0;
  std::uint64_t call = 0;
  // Where a replay dumps the draw's depth: the draw, or the glEnd closing a glBegin.
  std::uint64_t completedAtCall = 0;
};

// One distinct (matrix, depth state) pair as drawn.
struct TracedPair {
  TracedMatrix matrix;
  TraceDepthState depth;
  Occurrence first, last;
  std::uint64_t draws = 0;
};

// Pairs whose analysis reads alike, reported once: the first pair's matrix and report stand for
// the group.
struct TracePairGroup {
  std::string source;
  TraceDepthState depth;
  glm::dmat4 matrix{1.0};
  CheckInput input;
  CheckReport report;
  std::string unusable;  // why the matrix check refused the matrix (then no report)
  std::size_t distinctMatrices = 0;
  std::uint64_t draws = 0;
  Occurrence first, last;
  // --verify: the replayed depth buffer at the group's first draw (ReplayDepth.hpp).
  nlohmann::json verify;  // null when not verified
  std::vector<std::string> verifyObservations;
};

struct TraceCheckResult {
  std::string traceName;
  FrameRange frames;
  std::uint64_t framesSeen = 0;  // frames of the trace read (up to the range's end)
  std::uint64_t draws = 0;       // draws in the frame range
  std::uint64_t drawsWithProjection = 0;
  std::uint64_t drawsNotKept = 0;  // their pair came after kMaxDistinctPairs/kMaxPairsPerSource
  std::size_t distinctPairs = 0;
  std::vector<TracePairGroup> groups;
  std::vector<Finding> findings;  // about the trace as a whole
  bool hasErrors() const;
};

class TraceCheckCollector {
 public:
  TraceCheckCollector(std::string traceName, FrameRange frames);

  // One line of `apitrace dump --color=never --multiline=false` (apitrace's stderr merged in).
  // Returns false once the frame range is past: the rest of the trace need not be read. Throws
  // InputError "<trace>: call N: ..." where a call the checker needs cannot be read.
  bool addLine(std::string_view line);

  // Where `apitrace dump --blobs` writes its blob files, for the uniform buffers' contents.
  void setBlobDirectory(std::filesystem::path directory) {
    state_.setBlobDirectory(std::move(directory));
  }

  // The analysis. Throws InputError "<trace>: ..." for a truncated trace, an apitrace error, a
  // trace without draws, or draws without a projective matrix.
  TraceCheckResult finish();

 private:
  void onDraw(const TraceDraw& draw);

  std::string traceName_;
  FrameRange frames_;
  GlTraceState state_;
  std::uint64_t callLines_ = 0;
  std::vector<std::string> apitraceErrors_;
  bool truncated_ = false;
  std::uint64_t draws_ = 0, drawsWithProjection_ = 0, drawsNotKept_ = 0;
  std::unordered_map<std::string, std::size_t> pairIndex_;
  std::vector<TracedPair> pairs_;
  std::unordered_map<std::string, std::size_t> pairsPerSource_;
  // Projection changes inside a frame: the matrix each source last drew with in this frame.
  std::unordered_map<std::string, std::string> lastInFrame_;
  std::uint64_t framesWithChanges_ = 0;
  std::optional<std::uint64_t> lastChangedFrame_;
  std::string firstChange_;
};

nlohmann::json traceCheckJson(const TraceCheckResult& result);
std::string traceCheckText(const TraceCheckResult& result);

}  // namespace clipray::trace
