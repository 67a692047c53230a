// windingSign: whether a matrix keeps the winding on screen of triangles seen from the eye, for
// the projections apps build (glm's RH/LH, NO/ZO, perspective/orthographic), y-flipped and
// mirrored; and the facing rule of math/Facing.hpp it rests on.

#include <gtest/gtest.h>

#include <glm/gtc/matrix_transform.hpp>

#include "clipray/check/FacingCheck.hpp"
#include "clipray/math/Facing.hpp"

namespace clipray {
namespace {

glm::dmat4 yFlipped(glm::dmat4 m) {
  for (int column = 0; column < 4; ++column) m[column][1] = -m[column][1];
  return m;
}

TEST(FacingCheck, WindingSignOfTheProjectionsAppsBuild) {
  const glm::dmat4 view =
      glm::lookAtRH(glm::dvec3(3.0, 2.0, 5.0), glm::dvec3(0.0), glm::dvec3(0.0, 1.0, 0.0));
  const glm::dmat4 perspectives[] = {
      glm::perspectiveRH_NO(1.0, 1.5, 0.1, 100.0),
      glm::perspectiveRH_ZO(1.0, 1.5, 0.1, 100.0),
      glm::perspectiveRH_ZO(1.0, 1.5, 100.0, 0.1),  // reversed-Z
      glm::orthoRH_NO(-2.0, 2.0, -1.5, 1.5, 0.1, 100.0),
      glm::orthoRH_ZO(-2.0, 2.0, -1.5, 1.5, 0.1, 100.0),
  };
  for (const glm::dmat4& projection : perspectives) {
    EXPECT_EQ(windingSign(projection * view), 1);
    EXPECT_EQ(windingSign(yFlipped(projection) * view), -1);
    // A reflection pass: the view mirrored in the plane y = 0.
    const glm::dmat4 mirror = glm::scale(glm::dmat4(1.0), glm::dvec3(1.0, -1.0, 1.0));
    EXPECT_EQ(windingSign(projection * view * mirror), -1);
  }
  // A left-handed view and projection from the same eye, target and up: lookAtLH's right is
  // up x forward, the opposite of lookAtRH's, so the picture is the mirror image and a triangle
  // counter-clockwise seen from the eye (right-handed arithmetic) winds clockwise on screen. A
  // Direct3D mesh (front faces clockwise on screen) drawn so needs glFrontFace(GL_CW).
  const glm::dmat4 viewLh =
      glm::lookAtLH(glm::dvec3(3.0, 2.0, 5.0), glm::dvec3(0.0), glm::dvec3(0.0, 1.0, 0.0));
  EXPECT_EQ(windingSign(glm::perspectiveLH_ZO(1.0, 1.5, 0.1, 100.0) * viewLh), -1);
  EXPECT_EQ(windingSign(glm::dmat4(0.0)), 0);
}

TEST(FacingCheck, DrawnUnderCullingFollowsGlCullFaceAndGlFrontFace) {
  EXPECT_TRUE(drawnUnderCulling(-1.0, CullFace::None, FrontFace::Ccw));
  EXPECT_TRUE(drawnUnderCulling(1.0, CullFace::Back, FrontFace::Ccw));
  EXPECT_FALSE(drawnUnderCulling(-1.0, CullFace::Back, FrontFace::Ccw));
  EXPECT_TRUE(drawnUnderCulling(-1.0, CullFace::Back, FrontFace::Cw));
  EXPECT_TRUE(drawnUnderCulling(-1.0, CullFace::Front, FrontFace::Ccw));
  EXPECT_FALSE(drawnUnderCulling(-1.0, CullFace::Front, FrontFace::Cw));
  // Zero: the eye in the triangle's plane; back-facing, so culled by GL_BACK.
  EXPECT_FALSE(drawnUnderCulling(0.0, CullFace::Back, FrontFace::Ccw));
  EXPECT_FALSE(drawnUnderCulling(0.0, CullFace::Back, FrontFace::Cw));
  // det[x; y; w] of a counter-clockwise NDC triangle (w = 1) is twice its area.
  EXPECT_EQ(clipOrientation({0, 0, 0, 1}, {1, 0, 0, 1}, {0, 1, 0, 1}), 1.0);
  EXPECT_EQ(clipOrientation({0, 0, 0, 1}, {0, 1, 0, 1}, {1, 0, 0, 1}), -1.0);
  // Scaling a vertex's homogeneous coordinates by w > 0 keeps the sign.
  EXPECT_EQ(clipOrientation({0, 0, 0, 2}, {3, 0, 0, 3}, {0, 1, 0, 1}), 6.0);
}

}  // namespace
}  // namespace clipray
