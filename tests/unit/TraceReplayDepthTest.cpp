// Reading the depth buffer from apitrace's state dump (eglretrace -D CALL) and what it says
// (harness/clipray/trace/ReplayDepth.*).

#include <gtest/gtest.h>

#include <cstring>
#include <stdexcept>
#include <string>

#include "clipray/trace/ReplayDepth.hpp"

namespace clipray::trace {
namespace {

std::string base64(const std::string& bytes) {
  static const char* alphabet = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string text;
  unsigned value = 0;
  int bits = 0;
  for (const char c : bytes) {
    value = (value << 8) | static_cast<unsigned char>(c);
    bits += 8;
    while (bits >= 6) {
      bits -= 6;
      text.push_back(alphabet[(value >> bits) & 63u]);
    }
  }
  if (bits > 0) text.push_back(alphabet[(value << (6 - bits)) & 63u]);
  while (text.size() % 4 != 0) text.push_back('=');
  return text;
}

// A state dump as eglretrace writes it: a 2x2 float depth image, with a raw newline in a shader
// string (apitrace does not escape them) and the base64 split over lines.
std::string stateWith(const float (&depth)[4]) {
  std::string pfm = "Pf\n2 2\n1\n";
  pfm.append(reinterpret_cast<const char*>(depth), sizeof depth);
  const std::string encoded = base64(pfm);
  const std::string data = encoded.substr(0, 8) + "\n" + encoded.substr(8);
  return "{\"shaders\": {\"GL_VERTEX_SHADER\": \"#version 450\nvoid main() {}\"},\n"
         " \"framebuffer\": {\"GL_COLOR_ATTACHMENT0\": {\"__format__\": \"GL_RGBA8\"},\n"
         "  \"GL_DEPTH_ATTACHMENT\": {\"__class__\": \"image\", \"__width__\": 2, \"__height__\": "
         "2, \"__format__\": \"GL_DEPTH_COMPONENT32F\", \"__data__\": \"" +
         data + "\"}}}";
}

TEST(TraceReplayDepth, ReadsTheDepthImage) {
  const float depth[4] = {1.0f, 0.25f, 0.5f, 1.0f};
  const auto image = depthImageFromState(stateWith(depth));
  ASSERT_TRUE(image);
  EXPECT_EQ(image->width, 2);
  EXPECT_EQ(image->height, 2);
  EXPECT_EQ(image->format, "GL_DEPTH_COMPONENT32F");
  ASSERT_EQ(image->depth.size(), 4u);
  EXPECT_EQ(image->depth[1], 0.25f);
  EXPECT_EQ(image->depth[2], 0.5f);
  EXPECT_FALSE(depthImageFromState("{\"framebuffer\": {}}"));
  EXPECT_THROW(depthImageFromState("{\"framebuffer\": "), std::invalid_argument);
}

TEST(TraceReplayDepth, ViewDepthsAndTheBuiltForPick) {
  // A NO perspective (near 1, far 3, looking down -z from the origin) drawn under ZERO_TO_ONE:
  // z_ndc = 2 + 3/z_view... with A = -(f+n)/(f-n) = -2, B = -2fn/(f-n) = -3.
  TracePairGroup group;
  group.matrix = glm::dmat4(0.0);
  group.matrix[0][0] = 1.0;
  group.matrix[1][1] = 1.0;
  group.matrix[2][2] = -2.0;
  group.matrix[2][3] = -1.0;
  group.matrix[3][2] = -3.0;
  group.depth.clipZeroToOne = true;
  group.depth.depthTest = true;
  group.depth.clearedDepth = 1.0;
  group.first = {0, 42, 42};
  group.report.properties.perspective = true;
  group.report.properties.eye = glm::dvec3(0.0);
  group.report.properties.viewDirection = glm::dvec3(0.0, 0.0, -1.0);
  group.report.properties.builtFor = "no";
  // Window depth 0.5 under ZO: z_ndc 0.5 = 2 - 3/s, s = 2; read as NO: z_ndc 0, s = 1.5.
  const float depth[4] = {1.0f, 0.5f, 0.5f, 1.0f};
  const DepthUse use = analyseDepthUse(*depthImageFromState(stateWith(depth)), group);
  EXPECT_EQ(use.written, 2u);
  EXPECT_EQ(use.minDepth, 0.5);
  EXPECT_DOUBLE_EQ(*use.nearestViewDepth, 2.0);
  EXPECT_DOUBLE_EQ(*use.pickedNearest, 1.5);
  EXPECT_DOUBLE_EQ(*use.pickWorstRelativeError, 0.25);
  EXPECT_EQ(use.observations.back(),
            "read back with the convention the matrix was built for (no), as a pick that "
            "unprojects the depth does, they land at 1.5 to 1.5: up to 25% off");

  const float untouched[4] = {1.0f, 1.0f, 1.0f, 1.0f};
  const DepthUse none = analyseDepthUse(*depthImageFromState(stateWith(untouched)), group);
  EXPECT_EQ(none.written, 0u);
  EXPECT_EQ(none.observations.back(),
            "no fragment passed the depth test (or none was drawn) by this call");
  // Drawn with depth writes off (MeshLab's trackball, inside glPushAttrib(GL_DEPTH_BUFFER_BIT)):
  // the reason is the mask, not the test.
  group.depth.depthWrite = false;
  group.depth.depthMaskCall = 5844;
  const DepthUse masked = analyseDepthUse(*depthImageFromState(stateWith(untouched)), group);
  EXPECT_EQ(masked.written, 0u);
  EXPECT_EQ(masked.observations.back(),
            "depth writes were off (glDepthMask(GL_FALSE) at call 5844): this call wrote no depth");
}

}  // namespace
}  // namespace clipray::trace
