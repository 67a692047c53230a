// `clipray check --page` without a browser: recorded WebGL calls (as PageRecorder's script keeps
// them) translated into the trace checker's dump lines, and WebGL's own rules on top (the
// drawing buffer's implicit clear, the initial viewport, several canvases).

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "clipray/InputError.hpp"
#include "clipray/page/PageCalls.hpp"
#include "support/TraceLines.hpp"

namespace clipray::page {
namespace {

using nlohmann::json;
using trace::testing::codes;

// The reversed ZO matrix tests/webgl/zo-reversed.html uploads (near 0.1, far 100, fov 60,
// aspect 4/3, eye (0, 2, 5)), as Float32Array values read back in JavaScript.
const json kReversedMatrix =
    json::array({1.299038052558899, 0, 0, 0, 0, 1.6081688404083252, 0.00037176243495196104,
                 -0.3713906705379486, 0, -0.6432675123214722, 0.0009294060873799026,
                 -0.9284766912460327, 0, 0, 0.09470954537391663, 5.385164737701416});

json context(const std::string& name, bool preserve = false) {
  return {{"name", name},
          {"type", "webgl2"},
          {"depth", true},
          {"depthBits", 24},
          {"preserveDrawingBuffer", preserve}};
}

// One canvas drawing the reversed matrix with clipControlEXT(LOWER_LEFT, ZERO_TO_ONE) and
// GREATER, `clear` called with the depth bit or not.
json reversedRecording(bool pageClears, bool preserve = false) {
  json calls = json::array(
      {json::array({0, "context", 320, 240}), json::array({0, "clipControl", 0x8CA1, 0x935F}),
       json::array({0, "linkProgram", 1}),
       json::array({0, "getUniformLocation", 1, "clipFromWorld", 2}),
       json::array({0, "enable", 0x0B71}), json::array({0, "depthFunc", 0x0204}),
       json::array({0, "clearDepth", 0}), json::array({-1, "frame"})});
  if (pageClears) calls.push_back(json::array({0, "clear", 0x4100}));
  calls.push_back(json::array({0, "useProgram", 1}));
  calls.push_back(json::array({0, "uniformMatrix4fv", 2, 0, kReversedMatrix}));
  calls.push_back(json::array({0, "drawArrays"}));
  return {{"url", "file:///page.html"},
          {"devicePixelRatio", 2},
          {"frames", 1},
          {"draws", 1},
          {"dropped", 0},
          {"contexts", json::array({context("canvas#view", preserve)})},
          {"calls", calls}};
}

TEST(PageCalls, CallsBecomeTheDumpLinesOfTheirGlCalls) {
  EXPECT_EQ(dumpLineFor(json::array({0, "depthFunc", 516}), 7), "7 glDepthFunc(func = 516)");
  EXPECT_EQ(dumpLineFor(json::array({0, "clipControl", 36001, 37727}), 3),
            "3 glClipControl(origin = 36001, depth = 37727)");
  EXPECT_EQ(dumpLineFor(json::array({0, "clearDepth", 0.25}), 4), "4 glClearDepth(depth = 0.25)");
  EXPECT_EQ(dumpLineFor(json::array({0, "depthRange", 0.25, 1}), 5),
            "5 glDepthRangef(n = 0.25, f = 1)");
  EXPECT_EQ(dumpLineFor(json::array({0, "viewport", 0, 0, 640, 480}), 6),
            "6 glViewport(x = 0, y = 0, width = 640, height = 480)");
  EXPECT_EQ(dumpLineFor(json::array({0, "getUniformLocation", 3, "a\"b", 9}), 8),
            "8 glGetUniformLocation(program = 3, name = \"a\\\"b\") = 9");
  EXPECT_EQ(dumpLineFor(json::array({0, "clearBufferfi", 0x84F9, 0, 0.0, 0}), 2),
            "2 glClearBufferfi(buffer = 34041, drawbuffer = 0, depth = 0, stencil = 0)");
  EXPECT_EQ(dumpLineFor(json::array({0, "drawElementsInstanced"}), 11),
            "11 glDrawElementsInstanced()");
  EXPECT_EQ(dumpLineFor(json::array({-1, "frame"}), 12), "12 glFrameTerminatorGREMEDY()");
  // Floats with 7 significant digits, as apitrace writes them.
  EXPECT_EQ(dumpLineFor(json::array({0, "uniformMatrix4fv", 2, 0, kReversedMatrix}), 1),
            "1 glUniformMatrix4fv(location = 2, count = 1, transpose = GL_FALSE, value = "
            "{1.299038, 0, 0, 0, 0, 1.608169, 0.0003717624, -0.3713907, 0, -0.6432675, "
            "0.0009294061, -0.9284767, 0, 0, 0.09470955, 5.385165})");
  // What WebGL refuses (nothing changes) and what the recorder could not read: no line.
  EXPECT_EQ(dumpLineFor(json::array({0, "viewport", 0, 0, -1, 480}), 1), "");
  EXPECT_EQ(dumpLineFor(json::array({0, "clearDepth", nullptr}), 1), "");
  EXPECT_EQ(dumpLineFor(json::array({0, "depthRange", 1, 0}), 1), "");  // WebGL 1.0, 6.12
  EXPECT_EQ(dumpLineFor(json::array({0, "uniformMatrix4fv", 2, 0, json::array({1, 2, 3})}), 1), "");
  EXPECT_EQ(dumpLineFor(json::array({0, "bufferData", 1}), 1), "");
}

TEST(PageCalls, ReversedZClearedByThePageChecksClean) {
  const PageCheckResult result = checkRecording("page.html", reversedRecording(true));
  ASSERT_EQ(result.canvases.size(), 1u);
  const CanvasCheck& canvas = result.canvases[0];
  ASSERT_TRUE(canvas.result.has_value()) << canvas.notChecked;
  ASSERT_EQ(canvas.result->groups.size(), 1u);
  const trace::TracePairGroup& group = canvas.result->groups[0];
  EXPECT_EQ(group.source, "uniform clipFromWorld (program 1)");
  EXPECT_TRUE(group.depth.clipZeroToOne);
  EXPECT_EQ(group.depth.clearedDepth, 0.0);
  // The viewport WebGL starts with: the drawing buffer's size.
  EXPECT_EQ(group.depth.viewport.width, 320);
  EXPECT_EQ(group.depth.viewport.height, 240);
  EXPECT_EQ(codes(group), std::vector<std::string>{});
  EXPECT_FALSE(result.hasErrors());
  EXPECT_EQ(result.devicePixelRatio, 2.0);
}

// WebGL clears the drawing buffer's depth to 1 before each frame (preserveDrawingBuffer false):
// a reversed-Z page that never clears depth itself draws against 1, where GREATER passes nothing.
TEST(PageCalls, TheDrawingBuffersImplicitClearCountsAsAClearToOne) {
  const PageCheckResult result = checkRecording("page.html", reversedRecording(false));
  const trace::TracePairGroup& group = result.canvases.at(0).result->groups.at(0);
  EXPECT_EQ(group.depth.clearedDepth, 1.0);
  EXPECT_EQ(codes(group), std::vector<std::string>{"error:clear-depth-mismatch"});
  EXPECT_TRUE(result.hasErrors());

  // preserveDrawingBuffer: nothing is cleared between frames; the depth is whatever was left.
  const PageCheckResult kept = checkRecording("page.html", reversedRecording(false, true));
  EXPECT_EQ(kept.canvases.at(0).result->groups.at(0).depth.clearedDepth, std::nullopt);
}

// depthMask and polygon offset are outside the trace's state model: counted at the draws.
TEST(PageCalls, DepthWritesOffAndPolygonOffsetAreCountedAtTheDraws) {
  json recording = reversedRecording(true);
  json& calls = recording["calls"];
  const json more =
      json::array({json::array({0, "depthMask", 0}), json::array({0, "drawArrays"}),
                   json::array({0, "depthMask", 1}), json::array({0, "polygonOffset", -1.5, -2}),
                   json::array({0, "enable", 0x8037}), json::array({0, "drawArrays"}),
                   json::array({0, "drawArrays"}), json::array({0, "disable", 0x8037}),
                   json::array({0, "polygonOffset", 3, 4}), json::array({0, "drawArrays"})});
  calls.insert(calls.end(), more.begin(), more.end());
  const PageCheckResult result = checkRecording("page.html", recording);
  const CanvasCheck& canvas = result.canvases.at(0);
  EXPECT_EQ(canvas.draws, 5u);
  EXPECT_EQ(canvas.drawsWithoutDepthWrites, 1u);
  EXPECT_EQ(canvas.drawsWithPolygonOffset, 2u);
  EXPECT_EQ(canvas.polygonOffsetFactor, -1.5);
  EXPECT_EQ(canvas.polygonOffsetUnits, -2.0);
}

TEST(PageCalls, EachCanvasIsCheckedOnItsOwn) {
  json recording = reversedRecording(true);
  recording["contexts"].push_back(context("canvas 2"));
  recording["calls"].push_back(json::array({1, "context", 64, 64}));
  recording["calls"].push_back(json::array({1, "depthFunc", 0x0201}));
  const PageCheckResult result = checkRecording("page.html", recording);
  ASSERT_EQ(result.canvases.size(), 2u);
  EXPECT_EQ(result.canvases[0].name, "canvas#view");
  EXPECT_TRUE(result.canvases[0].result.has_value());
  EXPECT_EQ(result.canvases[1].name, "canvas 2");
  EXPECT_EQ(result.canvases[1].calls, 2u);
  EXPECT_FALSE(result.canvases[1].result.has_value());
  EXPECT_EQ(result.canvases[1].notChecked, "no draws");
}

// A std140 block's matrix comes from the bytes bufferData wrote (base64 in the recording), read
// by the trace's uniform-buffer model through a blob file.
TEST(PageCalls, UniformBlockMatricesAreReadFromTheRecordedBytes) {
  std::string bytes;
  for (const json& value : kReversedMatrix) {
    const float f = value.get<float>();
    bytes.append(reinterpret_cast<const char*>(&f), sizeof f);
  }
  static const char* alphabet = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string encoded;  // 64 bytes: no padding needed past the last full group
  for (std::size_t k = 0; k + 3 <= bytes.size(); k += 3) {
    const unsigned v = (static_cast<unsigned char>(bytes[k]) << 16) |
                       (static_cast<unsigned char>(bytes[k + 1]) << 8) |
                       static_cast<unsigned char>(bytes[k + 2]);
    for (int shift = 18; shift >= 0; shift -= 6) encoded += alphabet[(v >> shift) & 63];
  }
  const unsigned last = static_cast<unsigned char>(bytes[63]) << 16;
  encoded += alphabet[(last >> 18) & 63];
  encoded += alphabet[(last >> 12) & 63];
  encoded += "==";

  json recording = reversedRecording(true);
  json& calls = recording["calls"];
  calls.erase(calls.size() - 2);  // the uniformMatrix4fv
  const json setup = json::array(
      {json::array({0, "createShader", 0x8B31, 5}),
       json::array({0, "shaderSource", 5,
                    "#version 300 es\nlayout(std140) uniform Camera { mat4 clipFromWorld; };\n"
                    "in vec3 p;\nvoid main() { gl_Position = clipFromWorld * vec4(p, 1.0); }\n"}),
       json::array({0, "attachShader", 1, 5}), json::array({0, "linkProgram", 1}),
       json::array({0, "getUniformBlockIndex", 1, "Camera", 0}),
       json::array({0, "uniformBlockBinding", 1, 0, 0}), json::array({0, "bindBuffer", 0x8A11, 6}),
       json::array({0, "bufferData", 0x8A11, 64, nullptr}),
       json::array({0, "bindBufferBase", 0x8A11, 0, 6}),
       json::array({0, "bufferSubData", 0x8A11, 0, 64, encoded})});
  calls.insert(calls.end() - 1, setup.begin(), setup.end());
  const PageCheckResult result = checkRecording("page.html", recording);
  const trace::TracePairGroup& group = result.canvases.at(0).result->groups.at(0);
  EXPECT_EQ(group.source, "ubo Camera.clipFromWorld (program 1)");
  for (int column = 0; column < 4; ++column) {
    for (int row = 0; row < 4; ++row) {
      EXPECT_EQ(group.matrix[column][row],
                static_cast<double>(kReversedMatrix[column * 4 + row].get<float>()));
    }
  }
  EXPECT_EQ(codes(group), std::vector<std::string>{});
}

TEST(PageCalls, PagesWithoutContextsOrDrawsAreInputErrors) {
  json noContext = {
      {"frames", 5}, {"draws", 0}, {"contexts", json::array()}, {"calls", json::array()}};
  try {
    checkRecording("page.html", noContext);
    FAIL() << "no error";
  } catch (const InputError& error) {
    EXPECT_STREQ(error.what(), "page.html: no WebGL context");
  }
  json noDraws = reversedRecording(true);
  noDraws["draws"] = 0;
  noDraws["frames"] = 2;
  noDraws["calls"].erase(noDraws["calls"].size() - 1);
  try {
    checkRecording("page.html", noDraws);
    FAIL() << "no error";
  } catch (const InputError& error) {
    EXPECT_STREQ(error.what(), "page.html: never drew (1 WebGL context)");
  }
  // Draws, but none with a projection: the trace checker's message, for the canvas.
  json noMatrix = reversedRecording(true);
  noMatrix["calls"].erase(noMatrix["calls"].size() - 2);
  try {
    checkRecording("page.html", noMatrix);
    FAIL() << "no error";
  } catch (const InputError& error) {
    EXPECT_EQ(std::string(error.what())
                  .rfind("page.html: canvas#view: none of the 1 "
                         "draws has a matrix with a projection's structure",
                         0),
              0u)
        << error.what();
  }
}

}  // namespace
}  // namespace clipray::page
