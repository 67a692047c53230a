// The app's picking and rendering tested with clipray from the installed package, as a consumer's
// CI would, and the tests of the tests: each classic bug in the app must fail them.

#include <gtest/gtest-spi.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <span>
#include <string>
#include <vector>

#include <clipray/SceneBuilder.hpp>
#include <clipray/StateCheck.hpp>
#include <clipray/gtest.hpp>

#include "App.hpp"

// No compile definition of clipray's reaches a consumer (clipray once passed GLM_FORCE_XYZW_ONLY
// on, which took glm's colour and texture-coordinate names away).
#ifdef GLM_FORCE_XYZW_ONLY
#error "GLM_FORCE_XYZW_ONLY reached a consumer of clipray"
#endif
static_assert(
    requires(glm::vec4 v) {
      v.r;
      v.s;
    },
    "glm's .r/.s names must stay available to consumers");

namespace {

const app::App theApp;
const app::App theDirect3dApp(app::Style::Direct3D);
const app::App theReversedRangeApp(app::Style::ReversedDepthRange);
const app::App theCulledDirect3dApp(app::Style::Direct3D, true);
const app::App theSignApp(app::Style::OpenGl, true, true);
const app::App theDecalApp(app::Style::OpenGl, false, false, true);
const app::App theReversedRangeDecalApp(app::Style::ReversedDepthRange, false, false, true);

// What the Direct3D-style app draws under: glClipControl(GL_UPPER_LEFT, GL_ZERO_TO_ONE).
constexpr clipray::DepthMode kZeroToOneUpperLeft{clipray::DepthConvention::ZeroToOne, false,
                                                 clipray::ClipOrigin::UpperLeft};

clipray::TestScene appScene(const app::App& app = theApp) {
  const clipray::Viewport viewport{app.camera.viewport.z, app.camera.viewport.w};
  const bool direct3d = app.style == app::Style::Direct3D;
  const bool reversedRange = app.style == app::Style::ReversedDepthRange;
  clipray::SceneBuilder builder(direct3d        ? "direct3d-app"
                                : reversedRange ? "reversed-range-app"
                                                : "app");
  // The face culling the app means to draw with: what it sets when it gets it right.
  const auto culling = [&] {
    if (app.cullBackFaces) {
      builder.faceCulling(clipray::CullFace::Back,
                          direct3d ? clipray::FrontFace::Cw : clipray::FrontFace::Ccw);
    }
  };
  builder.mesh("floor", std::span<const float>(app.floor.positions),
               std::span<const std::uint32_t>(app.floor.indices));
  culling();
  builder.mesh("box", std::span<const float>(app.box.positions),
               std::span<const std::uint32_t>(app.box.indices));
  culling();
  if (app.sign) {
    builder.mesh("sign", std::span<const float>(app.sign->positions),
                 std::span<const std::uint32_t>(app.sign->indices));
    culling();
  }
  if (app.decal) {
    // The offset the app means to draw the decal with: toward the camera under its depth test.
    builder.mesh("decal", std::span<const float>(app.decal->positions),
                 std::span<const std::uint32_t>(app.decal->indices));
    culling();
    builder.objectPolygonOffset(app.decalOffset(), app.decalOffset());
  }
  builder.camera("main", app.camera.viewFromWorld, app.camera.clipFromView, viewport);
  if (direct3d) {
    builder.conventions({kZeroToOneUpperLeft});
  } else if (reversedRange) {
    // A NO projection drawn with glDepthRange(1, 0): no clip control at all.
    builder.conventions({clipray::kNegativeOneToOne}).depthRange(1.0, 0.0);
  } else {
    builder.conventions({clipray::kZeroToOne});
  }
  return builder.build();
}

clipray::AppWindow appWindow() {
  clipray::AppWindow window;
  window.origin = clipray::WindowOrigin::UpperLeft;
  window.pixelRatio = theApp.window.pixelRatio;
  window.viewportX = theApp.camera.viewport.x;
  window.viewportY = theApp.camera.viewport.y;
  window.framebufferWidth = theApp.window.framebufferWidth();
  window.framebufferHeight = theApp.window.framebufferHeight();
  return window;
}

clipray::PickRayFunction appPicking(app::PickingBug bug = app::PickingBug::None,
                                    const app::App& app = theApp) {
  return clipray::pickingInWindow(
      appWindow(),
      [bug, &app](glm::dvec2 mouse, const clipray::PickingCamera&) -> std::optional<clipray::Ray> {
        const std::optional<app::PickRay> ray = app.pick(mouse, bug);
        if (!ray) return std::nullopt;
        clipray::Ray result;
        result.origin = ray->origin;
        result.direction = ray->direction;  // tMax 0: to the far plane
        return result;
      });
}

// The app's picking with its own hits (App::pickHit), through the same window as its rays.
clipray::PickHitFunction appPickHits(app::PickingBug bug, const app::App& app) {
  return clipray::pickHitsInWindow(
      appWindow(),
      [bug, &app](glm::dvec2 mouse,
                  const clipray::PickingCamera&) -> std::optional<clipray::PickHit> {
        const std::optional<app::PickRay> ray = app.pick(mouse, bug);
        if (!ray) return std::nullopt;
        clipray::PickHit hit;
        hit.ray.origin = ray->origin;
        hit.ray.direction = ray->direction;  // tMax 0: to the far plane
        if (const std::optional<app::PickedTriangle> picked = app.pickHit(mouse, bug)) {
          hit.mesh = picked->mesh;
          hit.triangle = picked->triangle;
          hit.t = picked->t;
        }
        return hit;
      });
}

clipray::ReconcileOptions options(app::RenderBug renderBug = app::RenderBug::None,
                                  bool appRender = false,
                                  clipray::AppIds ids = clipray::AppIds::Written,
                                  const app::App& app = theApp) {
  clipray::ReconcileOptions options;
  options.window = appWindow();
  options.reportDirectory = ::testing::TempDir() + "clipray-consumer";
  options.appIds = ids;
  if (appRender) {
    options.render = [renderBug, ids, &app](const clipray::AppFrame& frame) {
      app::render(app, frame.getProcAddress, frame.firstIds, renderBug,
                  ids == clipray::AppIds::Written);
    };
  }
  return options;
}

clipray::ReconcileOptions direct3dOptions(app::RenderBug renderBug = app::RenderBug::None,
                                          const app::App& app = theDirect3dApp) {
  return options(renderBug, true, clipray::AppIds::Written, app);
}

TEST(AppPicking, AgreesWithTheRaster) {
  EXPECT_PICKING_CONSISTENT(appScene(), appPicking(), options());
}

TEST(AppRendering, AgreesWithTheRays) {
  EXPECT_PICKING_CONSISTENT(appScene(), clipray::robustPickRays(),
                            options(app::RenderBug::None, true));
}

TEST(AppRenderingAndPicking, AgreeWithEachOther) {
  EXPECT_PICKING_CONSISTENT(appScene(), appPicking(), options(app::RenderBug::None, true));
}

TEST(AppRendering, WithoutIdsInItsShadersAgreesDrawCallByDrawCall) {
  const clipray::ReconcileOptions perDrawCall =
      options(app::RenderBug::None, true, clipray::AppIds::PerDrawCall);
  EXPECT_PICKING_CONSISTENT(appScene(), appPicking(), perDrawCall);
}

// An engine ported from Direct3D: y-down projection, glClipControl(GL_UPPER_LEFT, GL_ZERO_TO_ONE),
// the mouse's y taken as it comes. Correct, so consistent.
TEST(Direct3dStyleApp, RenderingAndPickingAgree) {
  const clipray::PickRayFunction picking = appPicking(app::PickingBug::None, theDirect3dApp);
  const clipray::ReconcileResult result =
      clipray::reconcile(appScene(theDirect3dApp), picking, direct3dOptions());
  ASSERT_EQ(result.runs.size(), 1u);
  EXPECT_EQ(result.runs[0].convention, "zo-upper-left");
  EXPECT_TRUE(result.runs[0].consistent) << result.text();
  // The whole box and floor are in view: most of the viewport is hit on both sides.
  EXPECT_GT(result.runs[0].rasterHits, result.runs[0].pixels / 2) << result.text();
  EXPECT_PICKING_CONSISTENT(appScene(theDirect3dApp), clipray::robustPickRays(), direct3dOptions());
  EXPECT_PICKING_CONSISTENT(
      appScene(theDirect3dApp), picking,
      options(app::RenderBug::None, false, clipray::AppIds::Written, theDirect3dApp));
}

// Its buggy twin: the origin left at GL_LOWER_LEFT, so the y-down projection draws the picture
// upside down while the mouse's y goes in as it comes.
TEST(TestOfTheTest, Direct3dStyleWithoutTheUpperLeftOriginFails) {
  const clipray::ReconcileResult result = clipray::reconcile(
      appScene(theDirect3dApp), appPicking(app::PickingBug::None, theDirect3dApp),
      direct3dOptions(app::RenderBug::LowerLeftOrigin));
  ASSERT_EQ(result.runs.size(), 1u);
  EXPECT_FALSE(result.runs[0].consistent) << result.text();
  EXPECT_GT(result.runs[0].coverageUnexplained + result.runs[0].idUnexplained, 10000)
      << result.text();
  // What clipray read from the app's draws says why.
  EXPECT_EQ(
      result.runs[0].notes,
      std::vector<std::string>{"draws 1, 2: glClipControl(GL_LOWER_LEFT, GL_ZERO_TO_ONE), "
                               "but the run is zo-upper-left (GL_UPPER_LEFT, GL_ZERO_TO_ONE)"});
  EXPECT_NE(result.text().find("the app's GL state\n  draws 1, 2: glClipControl"),
            std::string::npos)
      << result.text();
}

// The Direct3D-style app culling back faces with glFrontFace(GL_CW): its y-down projection
// reverses the winding on screen, and GL_CW accounts for it. The scene says the same
// (SceneBuilder::faceCulling), so clipray's rays cull what the picture culls: consistent.
TEST(Direct3dStyleApp, CullingBackFacesRenderingAndPickingAgree) {
  const clipray::ReconcileResult result = clipray::reconcile(
      appScene(theCulledDirect3dApp), appPicking(app::PickingBug::None, theCulledDirect3dApp),
      direct3dOptions(app::RenderBug::None, theCulledDirect3dApp));
  ASSERT_EQ(result.runs.size(), 1u);
  EXPECT_TRUE(result.runs[0].consistent) << result.text();
  EXPECT_GT(result.runs[0].rasterHits, result.runs[0].pixels / 2) << result.text();
  EXPECT_TRUE(result.runs[0].notes.empty()) << result.text();
}

// The culled Direct3D-style app's frame reconciled with its own picking, its frames captured into
// `captures` while RenderDoc is loaded (ReconcileOptions::renderDocCaptures).
clipray::ReconcileResult culledDirect3dRun(app::RenderBug bug, const std::string& backend,
                                           const std::string& captures) {
  clipray::ReconcileOptions options = direct3dOptions(bug, theCulledDirect3dApp);
  if (!backend.empty()) options.backend = backend;
  options.renderDocCaptures = captures;
  return clipray::reconcile(appScene(theCulledDirect3dApp),
                            appPicking(app::PickingBug::None, theCulledDirect3dApp), options);
}

// A failing frame handed to the developer as a RenderDoc capture. run-consumer-test.cmake runs
// these tests a second time with librenderdoc.so preloaded and CLIPRAY_CONSUMER_CAPTURES naming
// the folder, on the EGL backend (RenderDoc hooks EGL, not OSMesa); without them they are skipped.
TEST(RenderDocCapture, AFailingFrameIsKeptAndAPassingOneIsNot) {
  const char* folder = std::getenv("CLIPRAY_CONSUMER_CAPTURES");
  if (!folder || !*folder) GTEST_SKIP() << "run by run-consumer-test.cmake under RenderDoc";
  const clipray::ReconcileResult result =
      culledDirect3dRun(app::RenderBug::FrontFaceNotFlipped, "egl", folder);
  ASSERT_EQ(result.runs.size(), 1u);
  EXPECT_FALSE(result.runs[0].consistent) << result.text();
  const std::string kept = std::string(folder) + "/direct3d-app-main-zo-upper-left-32f.rdc";
  EXPECT_EQ(result.runs[0].capture, kept) << result.text();
  EXPECT_NE(result.text().find(": the app's frame, captured by RenderDoc: " + kept),
            std::string::npos)
      << result.text();
  // The correct app's frame passes: its capture is removed, and none is named.
  const clipray::ReconcileResult passed = culledDirect3dRun(app::RenderBug::None, "egl", folder);
  ASSERT_EQ(passed.runs.size(), 1u);
  EXPECT_TRUE(passed.runs[0].consistent) << passed.text();
  EXPECT_EQ(passed.runs[0].capture, "");
  std::size_t files = 0;
  for (const auto& entry : std::filesystem::directory_iterator(folder)) {
    ++files;
    EXPECT_EQ(entry.path().string(), kept);
  }
  EXPECT_EQ(files, 1u);
}

// Without RenderDoc in the process, a failing run says why it has no capture.
TEST(RenderDocCapture, WithoutRenderDocAFailingRunSaysWhy) {
  if (std::getenv("CLIPRAY_CONSUMER_CAPTURES")) GTEST_SKIP() << "RenderDoc is loaded";
  const clipray::ReconcileResult result = culledDirect3dRun(
      app::RenderBug::FrontFaceNotFlipped, "", ::testing::TempDir() + "clipray-consumer-captures");
  ASSERT_EQ(result.runs.size(), 1u);
  EXPECT_EQ(result.runs[0].capture, "");
  EXPECT_EQ(result.runs[0].notes.back(),
            "ReconcileOptions::renderDocCaptures: no capture of this frame: RenderDoc is not "
            "loaded into the process (run the test with LD_PRELOAD=librenderdoc.so, Debian's "
            "librenderdoc)");
}

// Its buggy twin leaves glFrontFace at GL_CCW: the floor (seen from above) is culled and the box
// shows its inside, where the app meant its outside: the rays, culling as the scene says the app
// means to, disagree with the picture.
TEST(TestOfTheTest, Direct3dStyleCullingWithTheFrontFaceLeftAtCcwFails) {
  const clipray::ReconcileResult result = clipray::reconcile(
      appScene(theCulledDirect3dApp), appPicking(app::PickingBug::None, theCulledDirect3dApp),
      direct3dOptions(app::RenderBug::FrontFaceNotFlipped, theCulledDirect3dApp));
  ASSERT_EQ(result.runs.size(), 1u);
  EXPECT_FALSE(result.runs[0].consistent) << result.text();
  EXPECT_GT(result.runs[0].coverageUnexplained, 10000) << result.text();
  const std::string declared =
      ", but the scene declares glCullFace(GL_BACK) with glFrontFace(GL_CW) for mesh ";
  EXPECT_EQ(
      result.runs[0].notes,
      (std::vector<std::string>{"draw 1: glCullFace(GL_BACK) with glFrontFace(GL_CCW)" + declared +
                                    "\"floor\" (cull and frontFace, SceneBuilder::faceCulling)",
                                "draw 2: glCullFace(GL_BACK) with glFrontFace(GL_CCW)" + declared +
                                    "\"box\" (cull and frontFace, SceneBuilder::faceCulling)"}));
}

// The app's own picking, its intersection code and culling policy included: a sign hangs between
// the camera and the box with its back to the camera. The draw culls it and so does the app's
// ray-triangle test: the picks agree with the picture.
TEST(AppPickingWithItsOwnHits, CullsWhatThePictureCulls) {
  const clipray::ReconcileResult result =
      clipray::reconcile(appScene(theSignApp), appPickHits(app::PickingBug::None, theSignApp),
                         options(app::RenderBug::None, true, clipray::AppIds::Written, theSignApp));
  ASSERT_EQ(result.runs.size(), 1u);
  EXPECT_TRUE(result.runs[0].consistent) << result.text();
  EXPECT_GT(result.runs[0].depthCompared, result.runs[0].pixels / 2) << result.text();
  EXPECT_TRUE(result.runs[0].notes.empty()) << result.text();
}

// Its buggy twin tests every triangle: it picks the sign the picture does not show.
TEST(TestOfTheTest, PickingThroughCulledBackFacesFails) {
  const clipray::ReconcileResult result = clipray::reconcile(
      appScene(theSignApp), appPickHits(app::PickingBug::HitsCulledFaces, theSignApp),
      options(app::RenderBug::None, true, clipray::AppIds::Written, theSignApp));
  ASSERT_EQ(result.runs.size(), 1u);
  EXPECT_FALSE(result.runs[0].consistent) << result.text();
  EXPECT_GT(result.runs[0].idUnexplained, 10000) << result.text();
  ASSERT_EQ(result.runs[0].notes.size(), 1u) << result.text();
  EXPECT_EQ(result.runs[0].notes[0].rfind("the app's picking hit faces the picture culls at ", 0),
            0u)
      << result.runs[0].notes[0];
  EXPECT_NE(result.runs[0].notes[0].find(": \"sign\" triangle "), std::string::npos)
      << result.runs[0].notes[0];
}

// Reversed-Z as it was done before clip control: a NO projection, glDepthRange(1, 0), GL_GREATER,
// depth cleared to 0. Correct, so consistent.
TEST(ReversedDepthRangeApp, RenderingAndPickingAgree) {
  const clipray::ReconcileOptions drawn =
      options(app::RenderBug::None, true, clipray::AppIds::Written, theReversedRangeApp);
  const clipray::ReconcileResult result = clipray::reconcile(
      appScene(theReversedRangeApp), appPicking(app::PickingBug::None, theReversedRangeApp), drawn);
  ASSERT_EQ(result.runs.size(), 1u);
  EXPECT_EQ(result.runs[0].convention, "no");
  EXPECT_TRUE(result.runs[0].consistent) << result.text();
  EXPECT_GT(result.runs[0].depthCompared, result.runs[0].pixels / 2) << result.text();
  EXPECT_PICKING_CONSISTENT(appScene(theReversedRangeApp), clipray::robustPickRays(), drawn);
  EXPECT_TRUE(result.runs[0].notes.empty()) << result.text();
}

// Its buggy twin: the range reversed but the depth test left at GL_LESS, so the farthest surface
// wins everywhere.
TEST(TestOfTheTest, ReversedDepthRangeWithTheDepthTestLeftAtLessFails) {
  const clipray::ReconcileResult result = clipray::reconcile(
      appScene(theReversedRangeApp), clipray::robustPickRays(),
      options(app::RenderBug::DepthFuncLess, true, clipray::AppIds::Written, theReversedRangeApp));
  ASSERT_EQ(result.runs.size(), 1u);
  EXPECT_FALSE(result.runs[0].consistent) << result.text();
  EXPECT_EQ(result.runs[0].notes,
            std::vector<std::string>{"draws 1, 2: glDepthFunc(GL_LESS), but under no with a "
                                     "reversed depth range the nearer surface has the greater "
                                     "depth: GL_GREATER"});
}

// The tests of the tests: a classic bug in the app fails them, with the worst pixels named.
TEST(TestOfTheTest, MouseYNotFlippedFails) {
  EXPECT_NONFATAL_FAILURE(EXPECT_PICKING_CONSISTENT(
                              appScene(), appPicking(app::PickingBug::MouseYNotFlipped), options()),
                          "worst pixels");
  const clipray::ReconcileResult result =
      clipray::reconcile(appScene(), appPicking(app::PickingBug::MouseYNotFlipped), options());
  ASSERT_EQ(result.runs.size(), 1u);
  EXPECT_FALSE(result.runs[0].consistent);
  EXPECT_GT(result.runs[0].coverageUnexplained + result.runs[0].idUnexplained, 1000);
  ASSERT_EQ(result.runs[0].worstPixels.size(), 5u);
  EXPECT_TRUE(result.runs[0].worstPixels[0].window.has_value());
}

TEST(TestOfTheTest, PickingUnprojectedForTheOtherConventionFailsWhereItMatters) {
  // unProjectNO's window z 0 is NDC z -1: under this ZERO_TO_ONE projection (near 0.1) that point
  // lies 0.05 from the eye, in front of the near plane. Nothing of the app's scene is there, so
  // both rays hit the same surfaces and the run is rightly consistent...
  const clipray::PickRayFunction buggy = appPicking(app::PickingBug::UnprojectsNegativeOneToOne);
  EXPECT_TRUE(clipray::reconcile(appScene(), buggy, options()).consistent());
  // ...until something sits between the two: a card 0.07 in front of the eye, which the raster
  // clips away and only the buggy rays hit.
  const glm::dvec3 eye(3.0, 2.5, 4.0);
  const glm::dvec3 forward = glm::normalize(glm::dvec3(0.0, 0.5, 0.0) - eye);
  const glm::dvec3 right = glm::normalize(glm::cross(forward, glm::dvec3(0.0, 1.0, 0.0)));
  const glm::dvec3 up = glm::cross(right, forward);
  const clipray::Viewport viewport{theApp.camera.viewport.z, theApp.camera.viewport.w};
  const clipray::TestScene withCard =
      clipray::SceneBuilder("app-with-card")
          .mesh("floor", std::span<const float>(theApp.floor.positions),
                std::span<const std::uint32_t>(theApp.floor.indices))
          .quad("card", eye + 0.07 * forward, 0.02 * right, 0.02 * up)
          .camera("main", theApp.camera.viewFromWorld, theApp.camera.clipFromView, viewport)
          .conventions({clipray::kZeroToOne})
          .build();
  EXPECT_TRUE(clipray::reconcile(withCard, appPicking(), options()).consistent());
  const clipray::ReconcileResult result = clipray::reconcile(withCard, buggy, options());
  ASSERT_EQ(result.runs.size(), 1u);
  EXPECT_FALSE(result.runs[0].consistent);
  // The first of them (lowest row, then column): the floor on screen, the card behind the near
  // plane (a negative window depth) for the ray.
  const clipray::PixelReport& first = result.runs[0].worstPixels.at(0);
  EXPECT_EQ(first.pixelClass, "id_unexplained") << result.text();
  EXPECT_EQ(first.rasterHit, "\"floor\" triangle 1") << result.text();
  EXPECT_EQ(first.rayHit, "\"card\" (quad)") << result.text();
  EXPECT_LT(first.rayDepth, 0.0) << result.text();
}

TEST(TestOfTheTest, RenderingWithoutClipControlFails) {
  EXPECT_NONFATAL_FAILURE(EXPECT_PICKING_CONSISTENT(appScene(), clipray::robustPickRays(),
                                                    options(app::RenderBug::NoClipControl, true)),
                          "depth_beyond_tolerance");
}

TEST(TestOfTheTest, RenderingWithoutClipControlFailsDrawCallByDrawCall) {
  const clipray::ReconcileResult result = clipray::reconcile(
      appScene(), clipray::robustPickRays(),
      options(app::RenderBug::NoClipControl, true, clipray::AppIds::PerDrawCall));
  ASSERT_EQ(result.runs.size(), 1u);
  EXPECT_FALSE(result.runs[0].consistent) << result.text();
  EXPECT_GT(result.runs[0].depthBeyondTolerance, 10000) << result.text();
  EXPECT_EQ(result.runs[0].notes,
            std::vector<std::string>{"draws 1, 2: glClipControl(GL_LOWER_LEFT, "
                                     "GL_NEGATIVE_ONE_TO_ONE), but the run is zo (GL_LOWER_LEFT, "
                                     "GL_ZERO_TO_ONE)"});
}

// A decal on the box's front face, coplanar with it, drawn with glPolygonOffset(-1, -1) under
// GL_LESS: the offset brings it forward, and the scene declares the same offset, so clipray's rays
// see the decal where the picture shows it. Consistent, and nothing to note.
TEST(DecalApp, RenderingAndPickingAgree) {
  const clipray::ReconcileResult result = clipray::reconcile(
      appScene(theDecalApp), appPicking(app::PickingBug::None, theDecalApp),
      options(app::RenderBug::None, true, clipray::AppIds::Written, theDecalApp));
  ASSERT_EQ(result.runs.size(), 1u);
  EXPECT_TRUE(result.runs[0].consistent) << result.text();
  EXPECT_TRUE(result.runs[0].notes.empty()) << result.text();
}

// Reversed depth range (GL_GREATER): the decal comes forward with glPolygonOffset(1, 1).
TEST(ReversedDepthRangeApp, DecalWithTheOffsetFlippedAgrees) {
  const clipray::ReconcileResult result = clipray::reconcile(
      appScene(theReversedRangeDecalApp),
      appPicking(app::PickingBug::None, theReversedRangeDecalApp),
      options(app::RenderBug::None, true, clipray::AppIds::Written, theReversedRangeDecalApp));
  ASSERT_EQ(result.runs.size(), 1u);
  EXPECT_TRUE(result.runs[0].consistent) << result.text();
  EXPECT_TRUE(result.runs[0].notes.empty()) << result.text();
}

// Its buggy twin keeps GL_LESS's glPolygonOffset(-1, -1): under GL_GREATER that pushes the decal
// into the box, which hides it; the rays, offset as the scene declares, see the decal.
TEST(TestOfTheTest, DecalOffsetNotFlippedUnderReversedDepthFails) {
  const clipray::ReconcileResult result =
      clipray::reconcile(appScene(theReversedRangeDecalApp),
                         appPicking(app::PickingBug::None, theReversedRangeDecalApp),
                         options(app::RenderBug::DecalOffsetNotFlipped, true,
                                 clipray::AppIds::Written, theReversedRangeDecalApp));
  ASSERT_EQ(result.runs.size(), 1u);
  EXPECT_FALSE(result.runs[0].consistent) << result.text();
  EXPECT_GT(result.runs[0].idUnexplained, 1000) << result.text();
  EXPECT_EQ(
      result.runs[0].notes,
      std::vector<std::string>{"draw 3: glPolygonOffsetClamp(-1, -1, 0), but the scene declares "
                               "glPolygonOffsetClamp(1, 1, 0) for mesh \"decal\" (polygonOffset, "
                               "SceneBuilder::objectPolygonOffset)"});
}

// The app draws into a multisampled framebuffer (4 samples, fixed locations): each sample is a run,
// compared with the app's picking at that sample's window position.
clipray::ReconcileOptions multisampled(app::RenderBug renderBug, const app::App& app) {
  clipray::ReconcileOptions drawn = options(renderBug, true, clipray::AppIds::Written, app);
  drawn.samples = 4;
  return drawn;
}

TEST(MultisampledApp, RenderingAndPickingAgreeAtEverySample) {
  for (const app::App* app : {&theApp, &theDecalApp}) {
    const clipray::ReconcileResult result =
        clipray::reconcile(appScene(*app), appPicking(app::PickingBug::None, *app),
                           multisampled(app::RenderBug::None, *app));
    ASSERT_EQ(result.runs.size(), 4u) << result.text();
    for (int s = 0; s < 4; ++s) {
      const clipray::RunResult& run = result.runs[static_cast<std::size_t>(s)];
      EXPECT_TRUE(run.consistent) << result.text();
      EXPECT_EQ(run.sample, s);
      EXPECT_EQ(run.sampleCount, 4);
      EXPECT_EQ(run.frameUnexplainedPixels, 0) << result.text();
      // The box's and the floor's edges cross pixels: some are covered by part of their samples.
      EXPECT_GT(run.framePartlyCoveredPixels, 0) << result.text();
      EXPECT_GT(run.depthCompared, run.pixels / 2) << result.text();
    }
  }
}

// Its buggy twin passes depth through gl_FragDepth: one value per fragment, from the pixel centre,
// on every sample it covers. Single-sampled that is the fixed-function depth and agrees...
TEST(TestOfTheTest, DepthWrittenByTheShaderFailsOnlyMultisampled) {
  const clipray::ReconcileResult single =
      clipray::reconcile(appScene(), appPicking(), options(app::RenderBug::FragDepthWritten, true));
  ASSERT_EQ(single.runs.size(), 1u);
  EXPECT_TRUE(single.runs[0].consistent) << single.text();
  // ...multisampled, each sample's depth is the centre's: off by the depth's slope times the
  // sample's distance from the centre, where the sloped floor and box faces are.
  const clipray::ReconcileResult result = clipray::reconcile(
      appScene(), appPicking(), multisampled(app::RenderBug::FragDepthWritten, theApp));
  ASSERT_EQ(result.runs.size(), 4u) << result.text();
  for (const clipray::RunResult& run : result.runs) {
    EXPECT_FALSE(run.consistent) << result.text();
    EXPECT_GT(run.depthBeyondTolerance, run.depthCompared / 2) << result.text();
  }
}

// The app's render function asks clipray about its own GL state as it draws (a debug build's
// check): nothing declared by hand, the context says what the app set.
std::vector<std::string> stateCheckCodes(app::RenderBug bug, const app::App& app = theApp) {
  std::vector<std::string> codes;
  clipray::ReconcileOptions checked = options(bug, true, clipray::AppIds::Written, app);
  checked.render = [bug, &codes, &app](const clipray::AppFrame& frame) {
    app::render(app, frame.getProcAddress, frame.firstIds, bug);
    const clipray::StateCheckResult check = clipray::checkCurrentState(
        app.camera.clipFromView * app.camera.viewFromWorld, frame.getProcAddress);
    for (const clipray::StateFinding& finding : check.findings) {
      codes.push_back(finding.severity + ":" + finding.code);
    }
  };
  (void)clipray::reconcile(appScene(app), clipray::robustPickRays(), checked);
  return codes;
}

TEST(AppRendering, StateCheckFindsNothingWrong) {
  EXPECT_EQ(stateCheckCodes(app::RenderBug::None), std::vector<std::string>{});
}

TEST(TestOfTheTest, StateCheckNamesTheMissingClipControl) {
  EXPECT_EQ(stateCheckCodes(app::RenderBug::NoClipControl),
            std::vector<std::string>{"error:depth-convention-mismatch"});
}

// The culling Direct3D-style app: the y flip is noted; its twin with GL_CCW is named.
TEST(Direct3dStyleApp, StateCheckNotesTheYFlipOnly) {
  EXPECT_EQ(stateCheckCodes(app::RenderBug::None, theCulledDirect3dApp),
            std::vector<std::string>{"info:y-flipped"});
}

TEST(TestOfTheTest, StateCheckNamesTheFrontFaceTheYFlipReversed) {
  EXPECT_EQ(stateCheckCodes(app::RenderBug::FrontFaceNotFlipped, theCulledDirect3dApp),
            (std::vector<std::string>{"info:y-flipped", "warning:face-culling-keeps-insides"}));
}

TEST(TestOfTheTest, RenderingWithTheWrongDepthFunctionFails) {
  const clipray::ReconcileResult result = clipray::reconcile(
      appScene(), clipray::robustPickRays(), options(app::RenderBug::DepthFuncGreater, true));
  ASSERT_EQ(result.runs.size(), 1u);
  EXPECT_FALSE(result.runs[0].consistent) << result.text();
}

TEST(SceneBuilderInput, AnIndexOutOfRangeIsRefusedAsAFileWouldBe) {
  const float positions[] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0};
  const std::uint32_t indices[] = {0, 1, 99};
  try {
    clipray::SceneBuilder("bad").mesh("quad", positions, indices).build();
    FAIL() << "expected clipray::InputError";
  } catch (const clipray::InputError& error) {
    EXPECT_STREQ(
        error.what(),
        "SceneBuilder \"bad\": /objects/0/indices/2: index 99 out of range for 4 vertices");
  }
}

}  // namespace
