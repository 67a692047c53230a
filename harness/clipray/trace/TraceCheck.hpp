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
#include <unordered_set>
#include <vector>

#include <nlohmann/json.hpp>

#include "clipray/check/ConventionCheck.hpp"
#include "clipray/trace/GlTraceState.hpp"

namespace clipray::trace {

// At most this many distinct (matrix, depth state) pairs are kept; draws with further new pairs
// are counted, not analysed. Each pair costs a few hundred bytes and one matrix analysis.
inline constexpr std::size_t kMaxDistinctPairs = 20000;
// And at most this many per source and depth state, the matrices of one group (one animated
// uniform must not crowd out the others); the draws past it are counted per group.
inline constexpr std::size_t kMaxPairsPerGroup = 1000;
// Of the matrices left out of one group, at most this many are told apart to count them.
inline constexpr std::size_t kMaxLeftOutMatricesCounted = 100000;

struct FrameRange {
  std::uint64_t first = 0;
  std::uint64_t last = UINT64_MAX;
};

// The same matrix (of one source) drawn in one frame under depth tests of both directions, a
// LESS/LEQUAL pass and a GREATER/GEQUAL pass: the signature of a multi-pass technique that finds
// far surfaces on purpose (OpenCSG's CSG passes in `openscad --preview`, depth peeling, shadow
// volumes), not a statement of the depth convention. The first such frame, with the first draw
// of each direction in it and the depth each found cleared.
struct OppositeDepthPasses {
  std::uint64_t frame = 0;
  std::uint32_t lessFunc = kGlLess, greaterFunc = kGlGreater;
  std::uint64_t lessCall = 0, greaterCall = 0;  // 0: no draw of that direction (yet)
  std::optional<double> lessCleared, greaterCleared;
  // The depth clear the last GREATER/GEQUAL draw of the frame drew into (0: none yet): a later
  // draw into that clear is drawn over the far pass (TracedPair::overFarPass).
  std::uint64_t lastGreaterClearCall = 0;
};

// The matrix check on one matrix with this depth state as the declared state (declaredDepth from
// the clip control, reversed from a GREATER/GEQUAL depth test, depth range, origin, viewport,
// depth format), the texture-space reading of a biased projection, and the findings only a depth
// state gives (clear depth, reversed depth range, the depth func's call). Throws InputError where
// the matrix check refuses the matrix. Used by the trace checker and engine::checkCurrentState.
// With passes (the same matrix also drawn with the opposite depth test in one frame), a
// GREATER/GEQUAL pass of a matrix that is not itself reversed is that technique's far-surface
// pass: an info, not a reversed-Z or clear-depth error. A reversed matrix drawn with LESS stays an
// error whatever other passes do: reversed-Z is read from the matrix, never from a depth test.
// overFarPass: the draw tests against what a GREATER pass of that technique wrote into the same
// depth clear before it (TracedPair::overFarPass): its clear is not checked, an info says why.
CheckReport checkUnderDepthState(const TracedMatrix& matrix, const TraceDepthState& depth,
                                 CheckInput* inputUsed = nullptr,
                                 const OppositeDepthPasses* passes = nullptr,
                                 bool overFarPass = false);

// "A-B" or "A" (frames count from 0, as apitrace's). Throws InputError naming --frames.
FrameRange parseFrameRange(const std::string& text);
// "A-B" or "A" of unsigned numbers: InputError "<option>: expected A-B or A (<numbers>, A <= B),
// got "<text>"" otherwise.
FrameRange parseNumberRange(const std::string& text, const std::string& option,
                            const std::string& numbers);

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
  // Drawn with another depth test (LESS, LEQUAL, EQUAL, ...) into a depth clear a GREATER/GEQUAL
  // draw of the same matrix drew into before it in the frame. OpenCSG's SCS algorithm clears
  // depth to 0, keeps the farthest front faces with GL_GREATER, then tests faces against those
  // with GL_LESS (floriankirsch/OpenCSG, src/renderSCS.cpp: renderSCS, renderIntersectedFront,
  // subtractPrimitives, renderIntersectedBack), and OpenSCAD shades the result with GL_EQUAL:
  // such a pass tests against the depth the far pass wrote, not against the clear. (The depth
  // write mask is not followed: a far pass drawn with glDepthMask(GL_FALSE) counts too.) Part of
  // the pair's key: the same state before and after the far pass are two pairs.
  bool overFarPass = false;
};

// The smallest and largest value of one property over a group's matrices.
struct ValueRange {
  double min = 0.0, max = 0.0;
};

// Each property over the matrices of a group, as the matrix check reads each: a camera whose
// near and far change every frame (OpenSceneGraph computes them per frame) reads as one group,
// and these say how far they moved. Unset where no matrix of the group has the property.
struct GroupRanges {
  std::optional<ValueRange> near, far, fovYDegrees;
  std::optional<ValueRange> eyeX, eyeY, eyeZ;
  void include(const MatrixProperties& properties);
};

// The draws of a group's source and depth state whose matrices came after kMaxPairsPerGroup.
struct LeftOutDraws {
  std::uint64_t draws = 0;
  std::size_t distinctMatrices = 0;  // told apart up to kMaxLeftOutMatricesCounted
  bool distinctCapped = false;       // more than that: distinctMatrices is a lower bound
  Occurrence first, last;
};

// Pairs whose analysis reads alike, reported once: the first pair's matrix and report stand for
// the group, the ranges for all of its matrices.
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
  GroupRanges ranges;
  // Draws of the group's source and depth state not analysed (the first group of that source and
  // depth state carries them).
  std::optional<LeftOutDraws> leftOut;
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
  std::uint64_t drawsNotKept = 0;  // their pair came after kMaxDistinctPairs/kMaxPairsPerGroup
  std::size_t distinctPairs = 0;
  std::vector<TracePairGroup> groups;
  std::vector<Finding> findings;  // about the trace as a whole
  // What --verify read the groups' depth from, for the report's heading.
  std::string verifiedBy = "replayed by eglretrace";
  bool hasErrors() const;
};

class TraceCheckCollector {
 public:
  TraceCheckCollector(std::string traceName, FrameRange frames);

  // One line of `apitrace dump --color=never --multiline=false` (apitrace's stderr merged in).
  // Returns false once the frame range is past: the rest of the trace need not be read. Throws
  // InputError "<trace>: call N: ..." where a call the checker needs cannot be read.
  bool addLine(std::string_view line);

  // One draw read by another reader than the dump's (a RenderDoc capture: CaptureFileCheck.hpp),
  // its state and matrices already read: the same grouping and findings as a dump's draws.
  void addDraw(const TraceDraw& draw) {
    ++callLines_;
    onDraw(draw);
  }

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
  // Per source and depth state (a group's matrices): pairs kept, and the draws left out with
  // the hashes of their matrices' bits (to count them).
  std::unordered_map<std::string, std::size_t> pairsPerGroup_;
  std::unordered_map<std::string, LeftOutDraws> leftOut_;
  std::unordered_map<std::string, std::unordered_set<std::size_t>> leftOutMatrices_;
  // Projection changes inside a frame: the matrix each source last drew with in this frame.
  std::unordered_map<std::string, std::string> lastInFrame_;
  // Multi-pass techniques: per (source, matrix), the depth test directions drawn in the frame
  // passesFrame_, and the first frame where both were (OppositeDepthPasses).
  // Returns whether the draw is drawn over a far pass of the matrix (TracedPair::overFarPass).
  bool notePassDirection(const std::string& matrixKey, const TraceDraw& draw);
  void noteLeftOut(const std::string& sourceAndDepth, const std::string& matrixBits,
                   const TraceDraw& draw);
  std::uint64_t passesFrame_ = UINT64_MAX;
  std::unordered_map<std::string, OppositeDepthPasses> passesInFrame_;
  std::unordered_map<std::string, OppositeDepthPasses> oppositePasses_;
  std::uint64_t framesWithChanges_ = 0;
  std::optional<std::uint64_t> lastChangedFrame_;
  std::string firstChange_;
};

nlohmann::json traceCheckJson(const TraceCheckResult& result);
std::string traceCheckText(const TraceCheckResult& result);

}  // namespace clipray::trace
