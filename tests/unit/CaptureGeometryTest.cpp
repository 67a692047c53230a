// The captured draws' clip-space triangles (trace/CaptureGeometry.hpp): the reader's lines read
// back.

#include <gtest/gtest.h>

#include <stdexcept>
#include <string>

#include "clipray/trace/CaptureGeometry.hpp"

namespace clipray::trace {
namespace {

TEST(CaptureGeometry, ReadsTheReadersLines) {
  // One triangle: (1, 2, 3, 4), (5, 6, 7, 8), (9, 10, 11, 12) as little-endian float32, base64.
  const std::string clip = "AACAPwAAAEAAAEBAAACAQAAAoEAAAMBAAADgQAAAAEEAABBBAAAgQQAAMEEAAEBB";
  const CapturedDrawGeometry draw =
      capturedDrawGeometry(nlohmann::json{{"kind", "geometry"},
                                          {"event", 17},
                                          {"depth_target", "ResourceId::28"},
                                          {"instances", 1},
                                          {"triangles", 1},
                                          {"clip", clip}});
  EXPECT_EQ(draw.event, 17u);
  EXPECT_EQ(draw.depthTarget, "ResourceId::28");
  ASSERT_EQ(draw.clip.size(), 3u);
  EXPECT_EQ(draw.clip[2], glm::dvec4(9, 10, 11, 12));
  const CapturedDrawGeometry lines = capturedDrawGeometry(nlohmann::json{
      {"kind", "geometry"}, {"event", 9}, {"skipped", "draws LineList, not triangles"}});
  EXPECT_EQ(lines.skipped, "draws LineList, not triangles");
  EXPECT_TRUE(lines.clip.empty());
  try {
    capturedDrawGeometry(
        nlohmann::json{{"kind", "geometry"}, {"event", 17}, {"triangles", 2}, {"clip", clip}});
    FAIL() << "expected std::invalid_argument";
  } catch (const std::invalid_argument& error) {
    EXPECT_STREQ(error.what(),
                 "event 17: 48 bytes of clip coordinates for 2 triangles (48 bytes each)");
  }
}

}  // namespace
}  // namespace clipray::trace
