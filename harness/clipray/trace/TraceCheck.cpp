#include "clipray/trace/TraceCheck.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <map>
#include <stdexcept>

#include "clipray/InputError.hpp"
#include "clipray/check/CheckText.hpp"
#include "clipray/check/FacingCheck.hpp"

namespace clipray::trace {

namespace {

std::string number(double value) {
  return detail::checkNumber(value);
}

// The matrix's bits as a key: equal keys, equal matrices.
std::string matrixKey(const glm::dmat4& matrix) {
  std::string key(sizeof(double) * 16, '\0');
  for (int column = 0; column < 4; ++column) {
    std::memcpy(key.data() + sizeof(double) * 4 * column, &matrix[column][0], sizeof(double) * 4);
  }
  return key;
}

bool isGreaterTest(std::uint32_t func) {
  return func == kGlGreater || func == kGlGequal;
}

bool isLessTest(std::uint32_t func) {
  return func == kGlLess || func == kGlLequal;
}

std::string callNote(std::uint64_t call) {
  return call == 0 ? "GL's default" : "call " + std::to_string(call);
}

CheckInput checkInputOf(const TracedMatrix& matrix, const TraceDepthState& depth) {
  CheckInput input;
  input.clipFromWorld = matrix.matrix;
  if (matrix.fixedFunction) {
    input.projection = matrix.matrix;
    input.view = glm::dmat4(1.0);
  }
  input.declaredDepth =
      depth.clipZeroToOne ? DepthConvention::ZeroToOne : DepthConvention::NegativeOneToOne;
  // The depth test is what declares reversed-Z: GREATER or GEQUAL keeps the larger depth.
  input.declaredReversed = depth.depthTest && isGreaterTest(depth.depthFunc);
  input.depthRange = depth.depthRange;
  input.origin = depth.clipUpperLeft ? WindowOrigin::UpperLeft : WindowOrigin::LowerLeft;
  if (depth.viewport.width > 0 && depth.viewport.height > 0) input.viewport = depth.viewport;
  if (depth.depthFormat) input.depthFormat = *depth.depthFormat;
  if (depth.depthClamp) {
    // Call 0: read from a live context (engine::checkCurrentState), GL's default being off.
    input.depthClampEnabledAt =
        depth.depthClampCall != 0
            ? "glEnable(GL_DEPTH_CLAMP) at call " + std::to_string(depth.depthClampCall)
            : std::string("glIsEnabled(GL_DEPTH_CLAMP)");
  }
  input.predictMethods = false;
  return input;
}

// The info a LESS (EQUAL, ...) pass gets in place of clear-depth-mismatch where it tests against
// the depth a GREATER pass of the same matrix wrote into that clear (OppositeDepthPasses).
Finding nearOverFarPassFinding(const TraceDepthState& depth, const OppositeDepthPasses& passes) {
  return {"info", "multi-pass-over-far-surfaces",
          "this pass draws with glDepthFunc(" + glEnumName(depth.depthFunc) + ") (" +
              callNote(depth.depthFuncCall) + ") into depth cleared to " +
              number(depth.clearedDepth.value_or(0.0)) + " (" + callNote(depth.clearCall) +
              ") after frame " + std::to_string(passes.frame) +
              " drew the same matrix into that clear with glDepthFunc(" +
              glEnumName(passes.greaterFunc) + ") (first at call " +
              std::to_string(passes.greaterCall) +
              "): it tests against the depth that pass wrote, not against the clear, a step of "
              "a multi-pass technique (OpenCSG's CSG passes, depth peeling), not a clear-depth "
              "mismatch",
          "nothing, if the technique is intended"};
}

// A polygon offset whose every non-zero term moves depths toward the camera under GL_GREATER/
// GEQUAL, where the nearer surface has the greater depth (GL 4.6 14.6.5: o = m factor + r units
// is added to the window depth): the sign a GL_LESS renderer gave its shadow casters and
// hidden-line passes to push them away, kept through a move to reversed-Z. Under GL_LESS a
// negative offset comes forward on purpose as often as not (a decal; OSG's ShadowMap pulls the back
// faces it renders forward): not named.
void addPolygonOffsetFinding(const TraceDepthState& depth, CheckReport& report) {
  if (!offsetTowardCameraUnderGreater(depth)) return;
  std::string offset = "glPolygonOffset(" + number(depth.offsetFactor) + ", ";
  offset += number(depth.offsetUnits);
  offset += ")";
  std::string flipped = "glPolygonOffset(" + number(-depth.offsetFactor) + ", ";
  flipped += number(-depth.offsetUnits);
  flipped += ")";
  report.findings.push_back(
      {"warning", "polygon-offset-toward-camera",
       offset + " (" + callNote(depth.polygonOffsetCall) +
           ") with GL_POLYGON_OFFSET_FILL enabled (" + callNote(depth.polygonOffsetFillCall) +
           ") under glDepthFunc(" + glEnumName(depth.depthFunc) + ") (" +
           callNote(depth.depthFuncCall) +
           "): the nearer surface has the greater depth here, so a positive offset moves the "
           "surface toward the camera; kept from a GL_LESS renderer (a shadow caster's or a "
           "hidden-line pass's offset, meant to push away), it pulls the surface in front of "
           "what lies on it: shadow acne and z-fighting return",
       "flip the signs under GL_GREATER: " + flipped +
           " pushes away (a decal meant to come forward keeps positive values)"});
}

// A program whose fragment shader writes gl_FragDepth (FragDepthWrite.hpp): the depth buffer holds
// what the shader computes (three.js's logarithmicDepthBuffer writes log2(1 + w) / log2(1 + far);
// Outerra's and Cesium's log depth likewise), not the projective depth of the matrix. The matrix
// checks still hold for what the near and far planes clip; a depth-buffer picking function that
// unprojects the stored depth through the inverse matrix finds the wrong point.
void addFragDepthFinding(const TraceDepthState& depth, CheckReport& report) {
  if (depth.fragDepthProgram == 0) return;
  report.findings.push_back(
      {"info", "fragment-depth-not-projective",
       "program " + std::to_string(depth.fragDepthProgram) +
           " writes gl_FragDepth from its fragment shader: the depth buffer holds the depth the "
           "shader computes (a logarithmic depth of clip w, as three.js's logarithmicDepthBuffer "
           "and Outerra's write), not the projective depth of the matrix, so the depth buffer is "
           "not projective for these draws",
       "depth-buffer picking must invert the same mapping (three.js: w = 2^(d * log2(far + 1)) - "
       "1, then the point at that w along the pixel's ray), not unproject the depth through the "
       "inverse matrix"});
}

// What only the traced state shows, beyond the matrix check's findings. A far-surface pass
// (OppositeDepthPasses) clears to the near end on purpose: its clear is not checked; nor is the
// clear of a near pass drawn over what a far pass of the same matrix wrote into it (overFarPass).
void addTraceFindings(const TraceDepthState& depth, bool farSurfacePass,
                      const OppositeDepthPasses* overFarPass, CheckReport& report) {
  if (depth.writesClipDistance && depth.clipDistances == 0) {
    // Where the same program clips with them enabled in other draws, the collector makes this
    // an info (a pass that does not clip on purpose, such as the main view of a water reflection).
    report.findings.push_back(
        {"warning", "clip-distance-not-enabled",
         "the program writes gl_ClipDistance but no GL_CLIP_DISTANCEi is enabled (" +
             (depth.clipDistancesCall != 0 ? "last glEnable/glDisable of one at call " +
                                                 std::to_string(depth.clipDistancesCall)
                                           : std::string("none enabled in the trace")) +
             "): GL ignores the values written (OpenGL 4.6, 13.7), so they clip nothing",
         "glEnable(GL_CLIP_DISTANCE0 + i) before the draw for each gl_ClipDistance[i] the shader "
         "writes"});
  }
  addPolygonOffsetFinding(depth, report);
  addFragDepthFinding(depth, report);
  const MatrixProperties& p = report.properties;
  // A transposed upload reads as any convention: its depth readings mean nothing.
  if (!depth.depthTest || !p.reversedDecided || p.likelyTransposed) return;
  const bool rangeReversed = depth.depthRange.x > depth.depthRange.y;
  // Near ends at the larger window depth: a reversed matrix, or a classic one through
  // glDepthRange(1, 0). Then only GREATER/GEQUAL keeps the nearer surface.
  const bool nearIsDeeper = p.reversed != rangeReversed;
  // A reversed-Z matrix drawn with LESS/LEQUAL, or a classic one with GREATER/GEQUAL: the
  // matrix check's reversed-z-mismatch (the traced test is its declared state); the trace adds
  // the call that set the test.
  for (Finding& finding : report.findings) {
    if (finding.code == "reversed-z-mismatch") {
      finding.message += " (traced: glDepthFunc(" + glEnumName(depth.depthFunc) + ") at " +
                         callNote(depth.depthFuncCall) + ")";
    }
  }
  // The far plane's window depth under this matrix, and under the other convention.
  const double ownFar = nearIsDeeper ? std::min(depth.depthRange.x, depth.depthRange.y)
                                     : std::max(depth.depthRange.x, depth.depthRange.y);
  const double otherFar = nearIsDeeper ? std::max(depth.depthRange.x, depth.depthRange.y)
                                       : std::min(depth.depthRange.x, depth.depthRange.y);
  if (!farSurfacePass && depth.clearedDepth && *depth.clearedDepth == otherFar &&
      otherFar != ownFar && overFarPass && !nearIsDeeper) {
    report.findings.push_back(nearOverFarPassFinding(depth, *overFarPass));
  } else if (!farSurfacePass && depth.clearedDepth && *depth.clearedDepth == otherFar &&
             otherFar != ownFar) {
    report.findings.push_back(
        {"error", "clear-depth-mismatch",
         "the depth buffer is cleared to " + number(*depth.clearedDepth) + " (" +
             callNote(depth.clearCall) + "), the far value of the " +
             (nearIsDeeper ? "classic" : "reversed-Z") + " convention; this matrix puts far at " +
             number(ownFar) + ", so " +
             (isLessTest(depth.depthFunc) || isGreaterTest(depth.depthFunc)
                  ? "the cleared depth is nearer than any surface and nothing passes the test"
                  : "the cleared depth reads as nearest"),
         "glClearDepth(" + number(ownFar) + ") before glClear(GL_DEPTH_BUFFER_BIT)"});
  }
  if (rangeReversed && !p.reversed) {
    // One cause, one finding (osgfpdepth's osg::Depth(GEQUAL, 1, 0) under NEGATIVE_ONE_TO_ONE):
    // the matrix check's reversed-z-without-zero-to-one says the same of this depth range without
    // the call that set it.
    std::erase_if(report.findings, [](const Finding& finding) {
      return finding.code == "reversed-z-without-zero-to-one";
    });
    report.findings.push_back(
        {"warning", "depth-range-reversed",
         "glDepthRange(" + number(depth.depthRange.x) + ", " + number(depth.depthRange.y) + ") (" +
             callNote(depth.depthRangeCall) +
             ") reverses window depth under a classic matrix: reversed-Z by depth range keeps "
             "float depth precise only under ZERO_TO_ONE, where the matrix itself can be "
             "reversed",
         "build the projection reversed-Z, keep glDepthRange(0, 1), and draw under "
         "glClipControl(GL_LOWER_LEFT, GL_ZERO_TO_ONE)"});
  }
}

std::string clearedText(const std::optional<double>& cleared) {
  return cleared ? "depth cleared to " + number(*cleared) : std::string("depth never cleared");
}

// The info a far-surface pass gets in place of the reversed-Z findings: what this pass does and
// the opposite pass of the same matrix that shows it is a technique.
Finding farSurfacePassFinding(const TraceDepthState& depth, const OppositeDepthPasses& passes) {
  return {"info", "multi-pass-far-surfaces",
          "this pass draws with glDepthFunc(" + glEnumName(depth.depthFunc) + ") (" +
              callNote(depth.depthFuncCall) + ") into " + clearedText(depth.clearedDepth) +
              (depth.clearedDepth ? " (" + callNote(depth.clearCall) + ")" : std::string()) +
              ", and frame " + std::to_string(passes.frame) +
              " draws the same matrix with glDepthFunc(" + glEnumName(passes.lessFunc) +
              ") (first at call " + std::to_string(passes.lessCall) + ") into " +
              clearedText(passes.lessCleared) +
              ": a pass that keeps the farthest surface, the signature of a multi-pass technique "
              "(OpenCSG's CSG passes, depth peeling, shadow volumes), not reversed-Z; the matrix "
              "maps near to the smaller depth, as the " +
              glEnumName(passes.lessFunc) + " pass expects",
          "nothing, if the technique is intended; picking reads the nearest surface, as the " +
              glEnumName(passes.lessFunc) + " pass draws it"};
}

// The culling state at the draw, as the facing check reads it; GL_FRONT_AND_BACK (nothing drawn)
// and values clipray does not know leave culling out of it.
CullingState cullingStateOf(const TraceDepthState& depth) {
  CullingState state;
  state.origin = depth.clipUpperLeft ? ClipOrigin::UpperLeft : ClipOrigin::LowerLeft;
  if (depth.cullFace && depth.cullFaceMode == kGlBack) state.cull = CullFace::Back;
  if (depth.cullFace && depth.cullFaceMode == kGlFront) state.cull = CullFace::Front;
  if (depth.frontFace == kGlCw) state.frontFace = FrontFace::Cw;
  if (depth.frontFace != kGlCw && depth.frontFace != kGlCcw) state.cull = CullFace::None;
  state.reversedDepth = reversedDepthFrame(depth);
  state.cullSetAt = callNote(std::max(depth.cullFaceCall, depth.cullFaceModeCall));
  state.frontFaceSetAt = callNote(depth.frontFaceCall);
  return state;
}

// A shadow-map or projective-texture matrix: bias * projection * view, the bias (scale 0.5,
// translate 0.5, as glmark2's scene-shadow.cpp builds its LightMatrix) taking NDC [-1, 1] to
// texture coordinates [0, 1]. It feeds a texture look-up, not gl_Position, and reads as an
// off-axis ZO matrix. Undone (row_i := 2 row_i - row_3 for x, y, z), it is an on-axis projection:
// then the report is that projection's, with a note instead of the depth-state findings.
bool readAsTextureSpace(const CheckInput& input, CheckReport& report) {
  if (!report.properties.offAxis || !report.properties.perspective) return false;
  CheckInput unbiased = input;
  for (int column = 0; column < 4; ++column) {
    for (int row = 0; row < 3; ++row) {
      // Rounded to the dump's 7 digits again, so that the entries read at the listing's
      // precision and the listing's rounding is not taken for an off-axis offset.
      char digits[32];
      std::snprintf(digits, sizeof digits, "%.7g",
                    2.0 * input.clipFromWorld[column][row] - input.clipFromWorld[column][3]);
      unbiased.clipFromWorld[column][row] = std::strtod(digits, nullptr);
    }
  }
  if (unbiased.projection) unbiased.projection = unbiased.clipFromWorld;
  CheckReport projection;
  try {
    projection = checkConventions(unbiased);
  } catch (const InputError&) {
    return false;
  }
  if (projection.properties.offAxis) return false;
  const MatrixProperties& p = projection.properties;
  std::string reading = p.builtFor;
  if (p.nearIfBuiltForNo && p.nearIfBuiltForZo) {
    reading += " (near " + number(p.nearIfBuiltForNo->value) + " if NO, " +
               number(p.nearIfBuiltForZo->value) + " if ZO)";
  }
  report = CheckReport{};
  report.properties = p;
  report.findings.push_back(
      {"info", "texture-space-matrix",
       "the matrix is a [0, 1] bias (scale 0.5, translate 0.5) times an on-axis projection, built "
       "for " +
           reading +
           ": a shadow-map or projective-texture look-up matrix, not the one the app draws with, "
           "so it is not checked against the depth state; the properties above are the "
           "projection's",
       "nothing, if it only feeds texture look-ups; if it reaches gl_Position, drop the bias"});
  return true;
}

// Groups pairs whose analysis reads alike: same source and depth state, same reading of the
// convention, same findings (codes).
std::string groupKey(const TracedPair& pair, const CheckReport* report,
                     const std::string& unusable) {
  std::string key = pair.matrix.source + "|" + pair.depth.key() + "|" + unusable;
  if (report) {
    key += "|" + report->properties.builtFor + (report->properties.perspective ? "|p" : "|o") +
           (report->properties.reversed ? "r" : "c");
    for (const Finding& f : report->findings) key += "|" + f.severity + ":" + f.code;
  }
  return key;
}

}  // namespace

CheckReport checkUnderDepthState(const TracedMatrix& matrix, const TraceDepthState& depth,
                                 CheckInput* inputUsed, const OppositeDepthPasses* passes,
                                 bool overFarPass) {
  if (depth.depthRange.x == depth.depthRange.y) {
    // Named as the app set it: the matrix check's own message names its --depth-range option.
    throw InputError("glDepthRange(" + number(depth.depthRange.x) + ", " +
                     number(depth.depthRange.y) + ")" +
                     (depth.depthRangeCall != 0 ? " at call " + std::to_string(depth.depthRangeCall)
                                                : std::string()) +
                     ": near and far are equal, so every fragment gets the same depth");
  }
  CheckInput input = checkInputOf(matrix, depth);
  CheckReport report;
  try {
    report = checkConventions(input);
  } catch (const InputError& error) {
    // The matrix check names its own options (--clip-from-world, --projection); a traced matrix
    // came through none: it is named by its source.
    std::string message = error.what();
    for (const std::string option :
         {"--projection * --view", "--clip-from-world", "--projection"}) {
      if (message.starts_with(option)) {
        message = matrix.source + message.substr(option.size());
        break;
      }
    }
    throw InputError(message);
  }
  // A GREATER pass beside a LESS pass of the same matrix declares no convention: unless the matrix
  // itself is reversed (near maps to 1), it is read as the classic matrix the LESS pass draws it
  // as. A reversed depth range is a convention of its own and left to the checks above.
  const MatrixProperties& read = report.properties;
  const bool matrixReversed = read.perspective && read.reversedDecided && read.reversed;
  const bool farSurfacePass = passes != nullptr && passes->lessCall != 0 &&
                              input.declaredReversed && !matrixReversed && !read.likelyTransposed &&
                              depth.depthRange.x <= depth.depthRange.y;
  if (farSurfacePass) {
    input.declaredReversed = false;
    report = checkConventions(input);  // the same matrix, accepted above
  }
  if (inputUsed) *inputUsed = input;
  // A LESS (EQUAL, ...) pass into the clear a GREATER pass of the same matrix drew into before,
  // in a technique's frame (both a LESS and a GREATER pass of the matrix).
  const bool overFar = overFarPass && passes != nullptr && passes->lessCall != 0 &&
                       passes->greaterCall != 0 && depth.depthTest &&
                       !isGreaterTest(depth.depthFunc);
  if (!readAsTextureSpace(input, report)) {
    addTraceFindings(depth, farSurfacePass, overFar ? passes : nullptr, report);
    if (farSurfacePass) report.findings.push_back(farSurfacePassFinding(depth, *passes));
    // A transposed upload's winding means nothing either.
    if (!report.properties.likelyTransposed) {
      // A far-surface pass keeps the greater depth of a classic matrix: its viewer is the LESS
      // pass's.
      CullingState culling = cullingStateOf(depth);
      if (farSurfacePass) culling.reversedDepth = false;
      if (auto finding = faceCullingFinding(input.clipFromWorld, culling)) {
        report.findings.push_back(std::move(*finding));
      }
    }
  }
  return report;
}

FrameRange parseNumberRange(const std::string& text, const std::string& option,
                            const std::string& numbers) {
  const auto parse = [&](std::string_view part, std::uint64_t& value) {
    const auto [end, error] = std::from_chars(part.data(), part.data() + part.size(), value);
    return error == std::errc() && end == part.data() + part.size() && !part.empty();
  };
  FrameRange range;
  const std::size_t dash = text.find('-');
  const std::string_view whole = text;
  const bool ok =
      dash == std::string::npos
          ? parse(whole, range.first) && ((range.last = range.first), true)
          : parse(whole.substr(0, dash), range.first) && parse(whole.substr(dash + 1), range.last);
  if (!ok || range.last < range.first) {
    throw InputError(option + ": expected A-B or A (" + numbers + ", A <= B), got \"" + text +
                     "\"");
  }
  return range;
}

FrameRange parseFrameRange(const std::string& text) {
  return parseNumberRange(text, "--frames", "frame numbers from 0");
}

void GroupRanges::include(const MatrixProperties& properties) {
  const auto widen = [](std::optional<ValueRange>& range, double value) {
    if (!std::isfinite(value)) return;
    if (!range) {
      range = ValueRange{value, value};
    } else {
      range->min = std::min(range->min, value);
      range->max = std::max(range->max, value);
    }
  };
  if (properties.near) widen(near, properties.near->value);
  if (properties.far) widen(far, properties.far->value);
  if (properties.perspective && !properties.eyeAtInfinityAlong) {
    widen(fovYDegrees, properties.fovYDegrees.value);
  }
  if (properties.eye && !properties.eyeAtInfinityAlong) {
    widen(eyeX, properties.eye->x);
    widen(eyeY, properties.eye->y);
    widen(eyeZ, properties.eye->z);
  }
}

bool TraceCheckResult::hasErrors() const {
  return std::any_of(groups.begin(), groups.end(),
                     [](const TracePairGroup& g) { return g.report.hasErrors(); }) ||
         std::any_of(findings.begin(), findings.end(),
                     [](const Finding& f) { return f.severity == "error"; });
}

TraceCheckCollector::TraceCheckCollector(std::string traceName, FrameRange frames)
    : traceName_(std::move(traceName)), frames_(frames) {}

bool TraceCheckCollector::addLine(std::string_view line) {
  const auto head = dumpCallHead(line);
  if (!head) {
    // apitrace's own messages on the merged stderr (lib/trace/trace_parser.cpp, cli/cli_dump.cpp).
    if (line.starts_with("warning: unexpected end of file")) truncated_ = true;
    if (line.starts_with("error: ")) apitraceErrors_.emplace_back(line.substr(7));
    return true;
  }
  ++callLines_;
  if (!GlTraceState::needs(head->second)) return true;
  try {
    const DumpCall call = parseDumpCall(line);
    state_.apply(call, [this](const TraceDraw& draw) { onDraw(draw); });
  } catch (const std::invalid_argument& error) {
    throw InputError(traceName_ + ": call " + std::to_string(head->first) + " (" +
                     std::string(head->second) + "): " + error.what());
  }
  return state_.frame() <= frames_.last;
}

void TraceCheckCollector::onDraw(const TraceDraw& draw) {
  if (draw.frame < frames_.first || draw.frame > frames_.last) return;
  ++draws_;
  if (draw.matrices.empty()) return;
  ++drawsWithProjection_;
  const std::string depthKey = draw.depth.key();
  for (const TracedMatrix& matrix : draw.matrices) {
    const std::string bits = matrixKey(matrix.matrix);
    // Projection changes within a frame, per source.
    const std::string frameSource = std::to_string(draw.frame) + "|" + matrix.source;
    auto [previous, inserted] = lastInFrame_.try_emplace(frameSource, bits);
    if (!inserted && previous->second != bits) {
      if (lastChangedFrame_ != draw.frame) {
        ++framesWithChanges_;
        lastChangedFrame_ = draw.frame;
      }
      if (firstChange_.empty()) {
        firstChange_ = "frame " + std::to_string(draw.frame) + ", " + matrix.source + ", at call " +
                       std::to_string(draw.call);
      }
      previous->second = bits;
    }
    const bool overFar = notePassDirection(matrix.source + "|" + bits, draw);
    const std::string key =
        matrix.source + "|" + bits + "|" + depthKey + (overFar ? "|over-far" : "");
    const auto found = pairIndex_.find(key);
    if (found == pairIndex_.end()) {
      const std::string sourceAndDepth = matrix.source + "|" + depthKey;
      std::size_t& ofGroup = pairsPerGroup_[sourceAndDepth];
      if (pairs_.size() >= kMaxDistinctPairs || ofGroup >= kMaxPairsPerGroup) {
        ++drawsNotKept_;
        noteLeftOut(sourceAndDepth, bits, draw);
        continue;
      }
      ++ofGroup;
      pairIndex_.emplace(key, pairs_.size());
      const Occurrence occurrence{draw.frame, draw.call, draw.completedAtCall};
      pairs_.push_back({matrix, draw.depth, occurrence, occurrence, 1, overFar});
      continue;
    }
    TracedPair& pair = pairs_[found->second];
    pair.last = {draw.frame, draw.call, draw.completedAtCall};
    ++pair.draws;
  }
  // Only this frame's entries matter from here on.
  if (lastInFrame_.size() > 4 * draw.matrices.size() + 64) {
    std::erase_if(lastInFrame_, [&](const auto& entry) {
      return !entry.first.starts_with(std::to_string(draw.frame) + "|");
    });
  }
}

void TraceCheckCollector::noteLeftOut(const std::string& sourceAndDepth,
                                      const std::string& matrixBits, const TraceDraw& draw) {
  const Occurrence occurrence{draw.frame, draw.call, draw.completedAtCall};
  auto found = leftOut_.find(sourceAndDepth);
  if (found == leftOut_.end()) {
    // As many groups as pairs at most: past that, the draws are counted in drawsNotKept only.
    if (leftOut_.size() >= kMaxDistinctPairs) return;
    found =
        leftOut_.emplace(sourceAndDepth, LeftOutDraws{0, 0, false, occurrence, occurrence}).first;
  }
  LeftOutDraws& left = found->second;
  ++left.draws;
  left.last = occurrence;
  std::unordered_set<std::size_t>& seen = leftOutMatrices_[sourceAndDepth];
  if (seen.size() < kMaxLeftOutMatricesCounted) {
    seen.insert(std::hash<std::string>{}(matrixBits));
    left.distinctMatrices = seen.size();
  } else if (!seen.contains(std::hash<std::string>{}(matrixBits))) {
    left.distinctCapped = true;
  }
}

bool TraceCheckCollector::notePassDirection(const std::string& matrixKey, const TraceDraw& draw) {
  const TraceDepthState& depth = draw.depth;
  const bool less = isLessTest(depth.depthFunc), greater = isGreaterTest(depth.depthFunc);
  if (!depth.depthTest) return false;
  if (draw.frame != passesFrame_) {
    passesInFrame_.clear();
    passesFrame_ = draw.frame;
  }
  auto found = passesInFrame_.find(matrixKey);
  if (!less && !greater && found == passesInFrame_.end()) return false;
  if (found == passesInFrame_.end()) {
    // Bounded as the pairs are: a frame of more distinct matrices is not searched further.
    if (passesInFrame_.size() >= kMaxDistinctPairs) return false;
    OppositeDepthPasses inThisFrame;
    inThisFrame.frame = draw.frame;
    found = passesInFrame_.emplace(matrixKey, inThisFrame).first;
  }
  OppositeDepthPasses& passes = found->second;
  if (less && passes.lessCall == 0) {
    passes.lessFunc = depth.depthFunc;
    passes.lessCall = draw.call;
    passes.lessCleared = depth.clearedDepth;
  }
  if (greater && passes.greaterCall == 0) {
    passes.greaterFunc = depth.depthFunc;
    passes.greaterCall = draw.call;
    passes.greaterCleared = depth.clearedDepth;
  }
  if (greater) passes.lastGreaterClearCall = depth.clearCall;
  const bool overFar =
      !greater && passes.greaterCall != 0 && passes.lastGreaterClearCall == depth.clearCall;
  if (passes.lessCall != 0 && passes.greaterCall != 0) {
    // The first frame with both passes, kept up to date while that frame lasts.
    const auto kept = oppositePasses_.find(matrixKey);
    if (kept == oppositePasses_.end()) {
      if (oppositePasses_.size() < kMaxDistinctPairs) oppositePasses_.emplace(matrixKey, passes);
    } else if (kept->second.frame == passes.frame) {
      kept->second = passes;
    }
  }
  return overFar;
}

TraceCheckResult TraceCheckCollector::finish() {
  state_.finish([this](const TraceDraw& draw) { onDraw(draw); });
  if (!apitraceErrors_.empty()) throw InputError(traceName_ + ": apitrace: " + apitraceErrors_[0]);
  if (truncated_) {
    throw InputError(traceName_ +
                     ": truncated trace (apitrace: unexpected end of file while reading trace)");
  }
  if (callLines_ == 0) {
    throw InputError(traceName_ + ": no calls: not an apitrace trace, or an empty one");
  }
  TraceCheckResult result;
  result.traceName = traceName_;
  result.frames = frames_;
  result.framesSeen = state_.frame();
  result.draws = draws_;
  result.drawsWithProjection = drawsWithProjection_;
  result.drawsNotKept = drawsNotKept_;
  result.distinctPairs = pairs_.size();
  const std::string where =
      frames_.first == 0 && frames_.last == UINT64_MAX
          ? std::string()
          : " in frames " + std::to_string(frames_.first) + "-" +
                (frames_.last == UINT64_MAX ? std::string("end") : std::to_string(frames_.last));
  if (draws_ == 0) {
    throw InputError(traceName_ + ": no GL draw calls" + where + " (" + std::to_string(callLines_) +
                     " calls in " + std::to_string(state_.frame()) +
                     " frames read): nothing to check");
  }
  const std::vector<std::string>& unreadBlocks = state_.unreadUniformBlocks();
  if (pairs_.empty()) {
    throw InputError(
        traceName_ + ": none of the " + std::to_string(draws_) + " draws" + where +
        " has a matrix with a projection's structure (uniform mat4, std140 uniform "
        "block mat4 or fixed-function GL_PROJECTION)" +
        (unreadBlocks.empty() ? std::string() : "; not read: " + unreadBlocks.front()));
  }
  // The first draw of each source whose program writes gl_ClipDistance with a plane enabled.
  std::map<std::string, std::uint64_t> clipsElsewhere;
  for (const TracedPair& pair : pairs_) {
    if (pair.depth.writesClipDistance && pair.depth.clipDistances != 0) {
      clipsElsewhere.try_emplace(pair.matrix.source, pair.first.call);
    }
  }
  std::map<std::string, std::size_t> groupIndex;
  for (const TracedPair& pair : pairs_) {
    CheckInput input;
    std::optional<CheckReport> report;
    std::string unusable;
    try {
      const auto passes =
          oppositePasses_.find(pair.matrix.source + "|" + matrixKey(pair.matrix.matrix));
      report = checkUnderDepthState(pair.matrix, pair.depth, &input,
                                    passes != oppositePasses_.end() ? &passes->second : nullptr,
                                    pair.overFarPass);
    } catch (const InputError& error) {
      unusable = error.what();
    }
    const auto clips = clipsElsewhere.find(pair.matrix.source);
    if (report && clips != clipsElsewhere.end()) {
      for (Finding& finding : report->findings) {
        if (finding.code != "clip-distance-not-enabled") continue;
        finding.severity = "info";
        finding.message +=
            "; the same program draws with a clip distance enabled elsewhere (first "
            "at call " +
            std::to_string(clips->second) + "): a pass that does not clip on purpose";
        finding.fix = "nothing, if this pass should not clip";
      }
    }
    const std::string key = groupKey(pair, report ? &*report : nullptr, unusable);
    const auto [found, inserted] = groupIndex.try_emplace(key, result.groups.size());
    if (inserted) {
      TracePairGroup group;
      group.source = pair.matrix.source;
      group.depth = pair.depth;
      group.matrix = pair.matrix.matrix;
      group.input = input;
      if (report) group.report = std::move(*report);
      group.unusable = unusable;
      group.first = pair.first;
      group.last = pair.last;
      // The first group of its source and depth state carries the draws left out of them.
      const auto left = leftOut_.find(pair.matrix.source + "|" + pair.depth.key());
      if (left != leftOut_.end()) {
        group.leftOut = left->second;
        leftOut_.erase(left);
      }
      result.groups.push_back(std::move(group));
    }
    TracePairGroup& group = result.groups[found->second];
    if (report) group.ranges.include(report->properties);
    ++group.distinctMatrices;
    group.draws += pair.draws;
    if (pair.first.call < group.first.call) group.first = pair.first;
    if (pair.last.call > group.last.call) group.last = pair.last;
  }
  for (const std::string& unread : unreadBlocks) {
    result.findings.push_back(
        {"info", "uniform-block-not-read", unread,
         "a projection kept in this block is not checked: std140 blocks whose bytes the trace "
         "shows are (docs/check-trace.md)"});
  }
  if (framesWithChanges_ > 0) {
    result.findings.push_back(
        {"info", "projection-changes-within-frame",
         "a projective matrix changes between draws of one frame in " +
             std::to_string(framesWithChanges_) + " frame(s) (first: " + firstChange_ +
             "): per-object MVPs, or a second camera (shadow map, UI)",
         "nothing to fix if intended; picking must use the matrix of the pass it picks in"});
  }
  return result;
}

}  // namespace clipray::trace
