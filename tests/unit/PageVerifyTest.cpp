// `clipray check --page --verify` without a browser: the depth images as the recorder returns
// them, set against a canvas's groups; what is not an image is said per group, never an error.

#include <gtest/gtest.h>

#include <cstring>
#include <nlohmann/json.hpp>

#include "clipray/page/PageVerify.hpp"
#include "support/TraceLines.hpp"

namespace clipray::page {
namespace {

using nlohmann::json;

// One canvas: the NO matrix of tests/webgl/no.html, LESS, cleared to 1 (the trace's lines).
PageCheckResult oneCanvas() {
  PageCheckResult result;
  CanvasCheck canvas;
  canvas.name = "canvas#view";
  canvas.result = trace::testing::checkLines(
      "1 glViewport(x = 0, y = 0, width = 2, height = 1)\n"
      "2 glEnable(cap = GL_DEPTH_TEST)\n"
      "3 glClear(mask = GL_DEPTH_BUFFER_BIT)\n"
      "4 glUseProgram(program = 1)\n"
      "5 glGetUniformLocation(program = 1, name = \"clipFromWorld\") = 0\n"
      "6 glUniformMatrix4fv(location = 0, count = 1, transpose = GL_FALSE, value = {1.299038, 0, "
      "0, 0, 0, 1.608169, -0.3721342, -0.3713907, 0, -0.6432675, -0.9303355, -0.9284767, 0, 0, "
      "5.195746, 5.385165})\n"
      "7 glDrawArrays(mode = GL_TRIANGLES, first = 0, count = 3)\n");
  result.canvases.push_back(std::move(canvas));
  return result;
}

std::string base64(const std::vector<float>& values) {
  static const char* alphabet = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string bytes(values.size() * sizeof(float), '\0');
  std::memcpy(bytes.data(), values.data(), bytes.size());
  std::string out;
  std::size_t k = 0;
  for (; k + 3 <= bytes.size(); k += 3) {
    const unsigned v = (static_cast<unsigned char>(bytes[k]) << 16) |
                       (static_cast<unsigned char>(bytes[k + 1]) << 8) |
                       static_cast<unsigned char>(bytes[k + 2]);
    for (int shift = 18; shift >= 0; shift -= 6) out += alphabet[(v >> shift) & 63];
  }
  const std::size_t left = bytes.size() - k;  // 8 bytes: 2 left
  unsigned v = static_cast<unsigned char>(bytes[k]) << 16;
  if (left == 2) v |= static_cast<unsigned char>(bytes[k + 1]) << 8;
  out += alphabet[(v >> 18) & 63];
  out += alphabet[(v >> 12) & 63];
  out += left == 2 ? std::string(1, alphabet[(v >> 6) & 63]) + "=" : std::string("==");
  return out;
}

TEST(PageVerify, ADepthImageIsReadAsTheTracesReplayedOne) {
  PageCheckResult result = oneCanvas();
  // Two pixels: one cleared (1), one written at window depth 0.98.
  addDepthImages(result, json::array({{{"width", 2},
                                       {"height", 1},
                                       {"format", "GL_DEPTH24_STENCIL8"},
                                       {"depth", base64({1.0f, 0.98f})}}}));
  const trace::TracePairGroup& group = result.canvases[0].result->groups.at(0);
  ASSERT_GE(group.verifyObservations.size(), 2u);
  EXPECT_EQ(group.verifyObservations[0],
            "depth buffer after call 7 (frame 0): 2x1 GL_DEPTH24_STENCIL8, 1 of 2 pixels differ "
            "from the cleared depth 1");
  EXPECT_EQ(group.verifyObservations[1], "window depth used: 0.98 to 0.98");
  EXPECT_EQ(group.verify["written"], 1);
}

TEST(PageVerify, WhatIsNoImageIsSaidPerGroup) {
  PageCheckResult failed = oneCanvas();
  addDepthImages(failed,
                 json::array({{{"failure", "a WebGL 1 context (reading depth needs WebGL 2)"}}}));
  EXPECT_EQ(
      failed.canvases[0].result->groups.at(0).verifyObservations,
      std::vector<std::string>{"not verified: a WebGL 1 context (reading depth needs WebGL 2)"});

  PageCheckResult short_ = oneCanvas();
  addDepthImages(short_, json::array({{{"width", 2},
                                       {"height", 2},
                                       {"format", "GL_DEPTH24_STENCIL8"},
                                       {"depth", base64({1.0f, 0.98f})}}}));
  EXPECT_EQ(short_.canvases[0].result->groups.at(0).verifyObservations,
            std::vector<std::string>{
                "not verified: the depth image read back is not width x height floats"});

  PageCheckResult none = oneCanvas();
  addDepthImages(none, json());  // the page did not answer
  EXPECT_EQ(none.canvases[0].result->groups.at(0).verify, json({{"failure", "no depth image"}}));
}

}  // namespace
}  // namespace clipray::page
