// pickingInWindow: clipray's lower-left integer pixels as an app's mouse positions (upper-left
// origin, HiDPI, a viewport beside a panel), and the app's ray normalized and ended at the far
// plane.

#include <cmath>
#include <limits>
#include <optional>
#include <string>

#include <gtest/gtest.h>

#include "clipray/Picking.hpp"
#include "clipray/math/Projections.hpp"

namespace clipray {
namespace {

AppWindow hiDpiWindowWithPanel() {
  AppWindow window;
  window.origin = WindowOrigin::UpperLeft;
  window.pixelRatio = 2.0;
  window.viewportX = 80;
  window.viewportY = 10;
  window.framebufferHeight = 610;
  return window;
}

TEST(WindowPicking, PixelCentresInTheAppsWindowCoordinates) {
  const Viewport viewport{640, 600};
  const AppWindow window = hiDpiWindowWithPanel();
  // Framebuffer pixel centre (80.5, 10.5) from the bottom: 299.75 window units from the top.
  EXPECT_EQ(windowPositionOfPixel(window, 0, 0, viewport), glm::dvec2(40.25, 299.75));
  EXPECT_EQ(windowPositionOfPixel(window, 639, 599, viewport), glm::dvec2(359.75, 0.25));
  AppWindow lowerLeft = window;
  lowerLeft.origin = WindowOrigin::LowerLeft;
  EXPECT_EQ(windowPositionOfPixel(lowerLeft, 0, 0, viewport), glm::dvec2(40.25, 5.25));
  // Without a framebuffer height the viewport reaches the top: 10 + 600 pixels.
  AppWindow toTop = window;
  toTop.framebufferHeight = 0;
  EXPECT_EQ(windowPositionOfPixel(toTop, 0, 0, viewport), glm::dvec2(40.25, 299.75));
}

TEST(WindowPicking, TheAppsRayIsNormalizedAndEndsAtTheFarPlane) {
  PickingCamera camera;
  camera.mode = kZeroToOne;
  camera.viewport = {640, 600};
  camera.clipFromWorld = perspectiveClipFromView(glm::radians(60.0), 1.0, 1.0, 10.0, kZeroToOne);
  glm::dvec2 asked{-1.0};
  const PickRayFunction pick =
      pickingInWindow(hiDpiWindowWithPanel(), [&asked](glm::dvec2 window, const PickingCamera&) {
        asked = window;
        Ray ray;
        ray.origin = {0.0, 0.0, -1.0};
        ray.direction = {0.0, 0.0, -2.0};  // not unit length; tMax 0: to the far plane
        return std::optional<Ray>(ray);
      });
  const std::optional<Ray> ray = pick(0, 0, camera);
  ASSERT_TRUE(ray);
  EXPECT_EQ(asked, glm::dvec2(40.25, 299.75));
  EXPECT_EQ(ray->direction, glm::dvec3(0.0, 0.0, -1.0));
  EXPECT_NEAR(ray->tMax, 9.0, 1e-12);  // from z = -1 to the far plane at z = -10

  // A tMax given in the app's direction's units is scaled with it.
  const PickRayFunction scaled = pickingInWindow(AppWindow{}, [](glm::dvec2, const PickingCamera&) {
    return std::optional<Ray>(Ray{{0.0, 0.0, -1.0}, {0.0, 0.0, -2.0}, 3.0});
  });
  EXPECT_EQ(scaled(5, 5, camera)->tMax, 6.0);

  // An infinite far plane: the ray never leaves through it.
  camera.clipFromWorld =
      perspectiveClipFromView(glm::radians(60.0), 1.0, 1.0, std::nullopt, kZeroToOne);
  EXPECT_EQ(pick(0, 0, camera)->tMax, std::numeric_limits<double>::infinity());
}

TEST(WindowPicking, TheAppsHitIsAskedTheSameWayAndItsTScaledToTheUnitRay) {
  PickingCamera camera;
  camera.mode = kZeroToOne;
  camera.viewport = {640, 600};
  camera.clipFromWorld = perspectiveClipFromView(glm::radians(60.0), 1.0, 1.0, 10.0, kZeroToOne);
  glm::dvec2 asked{-1.0};
  const PickHitFunction pick =
      pickHitsInWindow(hiDpiWindowWithPanel(), [&asked](glm::dvec2 window, const PickingCamera&) {
        asked = window;
        PickHit answer;
        answer.ray.origin = {0.0, 0.0, -1.0};
        answer.ray.direction = {0.0, 0.0, -4.0};  // not unit length; tMax 0: to the far plane
        answer.mesh = 1;
        answer.triangle = 7;
        answer.t = 0.5;  // z = -3, 2 units along the unit ray
        return std::optional<PickHit>(answer);
      });
  const std::optional<PickHit> hit = pick(0, 0, camera);
  ASSERT_TRUE(hit);
  EXPECT_EQ(asked, glm::dvec2(40.25, 299.75));
  EXPECT_EQ(hit->ray.direction, glm::dvec3(0.0, 0.0, -1.0));
  EXPECT_NEAR(hit->ray.tMax, 9.0, 1e-12);
  EXPECT_EQ(hit->t, 2.0);
  EXPECT_EQ(hit->mesh, std::optional<std::size_t>(1));
  EXPECT_EQ(hit->triangle, std::optional<std::uint32_t>(7));

  // No hit, or a ray without a direction: nothing.
  const PickHitFunction none = pickHitsInWindow(
      AppWindow{}, [](glm::dvec2, const PickingCamera&) { return std::optional<PickHit>(); });
  EXPECT_FALSE(none(0, 0, camera));
  const PickHitFunction zero = pickHitsInWindow(AppWindow{}, [](glm::dvec2, const PickingCamera&) {
    PickHit directionless;
    directionless.ray.direction = glm::dvec3(0.0);
    return std::optional<PickHit>(directionless);
  });
  EXPECT_FALSE(zero(0, 0, camera));
  // The same refusal of a window that cannot hold the viewport.
  AppWindow small = hiDpiWindowWithPanel();
  small.framebufferHeight = 100;
  const PickHitFunction tooSmall = pickHitsInWindow(
      small, [](glm::dvec2, const PickingCamera&) { return std::optional<PickHit>(); });
  EXPECT_THROW(tooSmall(0, 0, camera), InputError);
}

TEST(WindowPicking, NoRayOrNoDirectionIsNoRay) {
  PickingCamera camera;
  camera.viewport = {4, 4};
  const PickRayFunction none = pickingInWindow(
      AppWindow{}, [](glm::dvec2, const PickingCamera&) { return std::optional<Ray>(); });
  EXPECT_FALSE(none(0, 0, camera));
  const PickRayFunction zero = pickingInWindow(AppWindow{}, [](glm::dvec2, const PickingCamera&) {
    return std::optional<Ray>(Ray{{0.0, 0.0, 0.0}, {0.0, 0.0, 0.0}, 0.0});
  });
  EXPECT_FALSE(zero(0, 0, camera));
}

TEST(WindowPicking, RefusesAWindowThatCannotHoldTheViewport) {
  const AppPickFunction pickNothing = [](glm::dvec2, const PickingCamera&) {
    return std::optional<Ray>();
  };
  AppWindow window;
  window.pixelRatio = 0.0;
  try {
    pickingInWindow(window, pickNothing);
    FAIL() << "no error";
  } catch (const InputError& error) {
    EXPECT_STREQ(error.what(), "AppWindow: pixelRatio: expected a positive number, got 0");
  }
  window = hiDpiWindowWithPanel();
  window.framebufferHeight = 100;
  const PickRayFunction pick = pickingInWindow(window, pickNothing);
  PickingCamera camera;
  camera.viewport = {640, 600};
  try {
    pick(0, 0, camera);
    FAIL() << "no error";
  } catch (const InputError& error) {
    EXPECT_STREQ(error.what(),
                 "AppWindow: framebufferHeight: 100 pixels cannot hold a viewport of height 600 "
                 "at y 10");
  }
}

}  // namespace
}  // namespace clipray
