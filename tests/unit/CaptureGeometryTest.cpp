// The captured draws' clip-space triangles (trace/CaptureGeometry.hpp): the reader's lines read
// back.

#include <gtest/gtest.h>

#include <stdexcept>
#include <string>
#include <vector>

#include "clipray/math/Projections.hpp"
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

// The camera's projection times any affine view and model matrix fits the positions it produces;
// a light's projection with other near and far planes does not; an orthographic projection
// (w constant) cannot tell.
TEST(CaptureGeometry, TheMatrixGlPositionIsComputedWithFitsItsPositions) {
  const glm::dmat4 view = viewFromWorldLookAt({-1.7, 0.0, 3.2}, {0.0, 0.0, 0.0}, {0.0, 1.0, 0.0});
  const glm::dmat4 model = glm::dmat4(glm::dmat3(0.8, 0.6, 0.0, -0.6, 0.8, 0.0, 0.0, 0.0, 1.0));
  const glm::dmat4 camera =
      perspectiveClipFromView(glm::radians(48.0), 4.0 / 3.0, 2.0, 5.2, kNegativeOneToOne) * view;
  const glm::dmat4 light =
      perspectiveClipFromView(glm::radians(70.0), 4.0 / 3.0, 1.237, 5.2, kNegativeOneToOne) *
      viewFromWorldLookAt({1.0, 1.0, 2.0}, {0.0, 0.0, 0.0}, {0.0, 1.0, 0.0});
  std::vector<glm::dvec4> clip;
  for (const glm::dvec3 p :
       {glm::dvec3(0.3, 0.1, -0.2), glm::dvec3(-0.5, 0.4, 0.6), glm::dvec3(0.1, -0.7, 0.2)}) {
    // The vertex shader's output, in float32.
    clip.push_back(glm::dvec4(glm::vec4(camera * model * glm::dvec4(p, 1.0))));
  }
  EXPECT_EQ(fitsClipPositions(camera * model, clip), ClipFit::Fits);
  EXPECT_EQ(fitsClipPositions(camera, clip), ClipFit::Fits);  // the model matrix is affine
  EXPECT_EQ(fitsClipPositions(light, clip), ClipFit::DoesNotFit);
  const glm::dmat4 parallel =
      orthographicClipFromView(-2.0, 2.0, -1.5, 1.5, 0.1, 10.0, kNegativeOneToOne) * view;
  EXPECT_EQ(fitsClipPositions(parallel, clip), ClipFit::CannotTell);
  EXPECT_EQ(fitsClipPositions(camera, {}), ClipFit::CannotTell);
}

}  // namespace
}  // namespace clipray::trace
