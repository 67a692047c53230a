// clipray-pick's pieces that need no window: cursor -> pixel, the verdict and JSON of a pick, the
// panel's labels, script parsing and the ray methods (PickDemoTest.cpp runs the demo itself).

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <sstream>

#include "GlfwBackend.hpp"
#include "PickDemo.hpp"
#include "PickScript.hpp"
#include "ThreeWayPick.hpp"
#include "clipray/InputError.hpp"
#include "clipray/rays/RayMethods.hpp"
#include "clipray/rays/RobustRays.hpp"
#include "support/RunCommand.hpp"

namespace clipray {
namespace {

using testing::TempFolder;

const std::string kSource = CLIPRAY_SOURCE_DIR;
const std::string kStandard = kSource + "/scenes/standard.json";
TEST(WindowGeometry, ScalesThenFlipsOnHighDpi) {
  const demo::WindowGeometry g{glm::dvec2(100, 50), glm::ivec2(200, 100)};  // scale 2
  EXPECT_EQ(g.scale(), glm::dvec2(2.0));
  EXPECT_EQ(g.pixelFromCursor({0.0, 0.0}), glm::ivec2(0, 99));  // top-left -> top row
  EXPECT_EQ(g.pixelFromCursor({0.49, 0.49}), glm::ivec2(0, 99));
  EXPECT_EQ(g.pixelFromCursor({0.5, 0.5}), glm::ivec2(1, 98));
  EXPECT_EQ(g.pixelFromCursor({99.9, 49.9}), glm::ivec2(199, 0));   // bottom-right
  EXPECT_EQ(g.pixelFromCursor({100.0, 50.0}), glm::ivec2(199, 0));  // clamped
  EXPECT_EQ(g.cursorFromFramebuffer({0.0, 100.0}), glm::dvec2(0.0, 0.0));
  EXPECT_EQ(g.cursorFromFramebuffer({200.0, 0.0}), glm::dvec2(100.0, 50.0));
  // A pixel's centre maps back inside the same pixel.
  const glm::dvec2 centre = g.cursorFromFramebuffer(glm::dvec2(37, 61) + 0.5);
  EXPECT_EQ(g.pixelFromCursor(centre), glm::ivec2(37, 61));
}

TEST(WindowGeometry, NoScaleIsTheIdentityUpToTheFlip) {
  const demo::WindowGeometry g{glm::dvec2(320, 240), glm::ivec2(320, 240)};
  EXPECT_EQ(g.pixelFromCursor({160.2, 120.7}), glm::ivec2(160, 119));
}

TEST(PickVerdict, SaysAgreeApartAmbiguousDisagreeOrNoRay) {
  Scene scene;
  scene.objects.resize(2);
  scene.objects[0].name = "floor";
  scene.objects[1].name = "box";
  demo::PickResult result;
  result.rayObject = 1;
  result.idObject = 1;
  result.rayOffsetPixels = 0.004;
  demo::PickJudgement judgement = demo::judgePick(result, scene);
  EXPECT_EQ(judgement.verdict, demo::PickVerdict::Agree);
  EXPECT_EQ(judgement.text, "1 and 3 agree: box, hit 0.004 px from the pixel centre");
  result.rayOffsetPixels = 26.25;
  judgement = demo::judgePick(result, scene);
  EXPECT_EQ(judgement.verdict, demo::PickVerdict::Apart);
  EXPECT_EQ(judgement.text,
            "1 and 3 APART: both box, but the ray's hit lands 26.2 px from the clicked pixel");
  result.rayOffsetPixels = demo::kPickAgreementPixels;  // still inside the pixel
  EXPECT_EQ(demo::judgePick(result, scene).verdict, demo::PickVerdict::Agree);
  result.idObject = 0;
  result.reconcileClass = PixelClass::IdDepthAmbiguous;
  judgement = demo::judgePick(result, scene);
  EXPECT_EQ(judgement.verdict, demo::PickVerdict::Ambiguous);
  EXPECT_EQ(judgement.text,
            "1 and 3 ambiguous: box and floor z-fight here (depths within the tolerance)");
  result.reconcileClass = PixelClass::IdEdgeAmbiguous;
  EXPECT_EQ(demo::judgePick(result, scene).text,
            "1 and 3 ambiguous: box or floor, the pixel centre is on an edge");
  result.idObject = -1;
  result.reconcileClass = PixelClass::CoverageEdgeAmbiguous;
  EXPECT_EQ(demo::judgePick(result, scene).verdict, demo::PickVerdict::Ambiguous);
  result.reconcileClass = PixelClass::CoverageUnexplained;
  judgement = demo::judgePick(result, scene);
  EXPECT_EQ(judgement.verdict, demo::PickVerdict::Disagree);
  EXPECT_EQ(judgement.text, "1 and 3 DISAGREE: the ray hits box, the id buffer shows background");
  // Without the reconcile's classes a mismatch is a disagreement.
  result.reconcileClass.reset();
  EXPECT_EQ(demo::judgePick(result, scene).verdict, demo::PickVerdict::Disagree);
  result.rayUnavailable = "non-finite ray";
  judgement = demo::judgePick(result, scene);
  EXPECT_EQ(judgement.verdict, demo::PickVerdict::NoRay);
  EXPECT_EQ(judgement.text, "1 and 3: n/a (non-finite ray)");
  EXPECT_STREQ(demo::pickVerdictName(demo::PickVerdict::NoRay), "n/a");
}

// The JSON line says what the verdict says: an "apart" pick (same object, hit pixels away) does
// not "agree", though its objects are the same.
TEST(PickJson, AgreeIsTheVerdictAndSameObjectComparesObjects) {
  Scene scene;
  scene.objects.resize(2);
  scene.objects[0].name = "floor";
  scene.objects[1].name = "box";
  demo::PickResult result;
  result.rayObject = 1;
  result.idObject = 1;
  result.rayOffsetPixels = 24.1;
  nlohmann::json line = demo::pickJson(result, scene, true);
  EXPECT_EQ(line["verdict"], "apart");
  EXPECT_EQ(line["agree"], false);
  EXPECT_EQ(line["same_object"], true);
  result.rayOffsetPixels = 0.004;
  line = demo::pickJson(result, scene, false);
  EXPECT_EQ(line["verdict"], "agree");
  EXPECT_EQ(line["agree"], true);
  EXPECT_EQ(line["same_object"], true);
  result.idObject = 0;
  result.reconcileClass = PixelClass::IdDepthAmbiguous;
  line = demo::pickJson(result, scene, false);
  EXPECT_EQ(line["verdict"], "ambiguous");
  EXPECT_EQ(line["agree"], false);
  EXPECT_EQ(line["same_object"], false);
  result.reconcileClass.reset();
  line = demo::pickJson(result, scene, false);
  EXPECT_EQ(line["verdict"], "disagree");
  EXPECT_EQ(line["agree"], false);
  EXPECT_EQ(line["same_object"], false);
  result.rayUnavailable = "non-finite ray";
  line = demo::pickJson(result, scene, false);
  EXPECT_EQ(line["verdict"], "n/a");
  EXPECT_TRUE(line["agree"].is_null());
  EXPECT_TRUE(line["same_object"].is_null());
  EXPECT_TRUE(line["ray"].is_null());
}

// The JSON line names the clip origin twice: in the convention's name and on its own.
TEST(PickJson, NamesTheClipOriginAndTheClipPlanes) {
  Scene scene;
  scene.objects.resize(1);
  scene.objects[0].name = "box";
  demo::PickResult result;
  result.mode = kZeroToOne;
  nlohmann::json line = demo::pickJson(result, scene, false);
  EXPECT_EQ(line["convention"], "zo");
  EXPECT_EQ(line["clip_origin"], "lower-left");
  EXPECT_EQ(line["clip_planes"], 0);
  result.mode.origin = ClipOrigin::UpperLeft;
  result.clipPlaneCount = 2;
  line = demo::pickJson(result, scene, false);
  EXPECT_EQ(line["convention"], "zo-upper-left");
  EXPECT_EQ(line["clip_origin"], "upper-left");
  EXPECT_EQ(line["clip_planes"], 2);
}

TEST(PickPanel, LabelsFramebufferRowsAndTheClipOrigin) {
  EXPECT_STREQ(demo::pixelCoordinatesLabel(ClipOrigin::LowerLeft),
               "framebuffer, GL: origin lower left, y up");
  EXPECT_STREQ(demo::pixelCoordinatesLabel(ClipOrigin::UpperLeft),
               "framebuffer, GL: origin lower left, y up; clip y down (GL_UPPER_LEFT)");
}

// The camera an upper-left app draws (a y-down projection) seen as a lower-left origin numbers the
// rows is the camera a lower-left app draws, bit for bit: every ray method gets the same inputs.
TEST(PickRays, TheLowerLeftViewOfAnUpperLeftCameraIsTheLowerLeftCamera) {
  const Scene scene = loadScene(kStandard);
  const Camera& camera = scene.cameras[0];
  const Viewport viewport{320, 240};
  auto inputs = [&](DepthMode mode) {
    Camera projection = camera;
    projection.viewFromWorld = glm::dmat4(1.0);
    CameraInputs drawn;
    drawn.mode = mode;
    drawn.clipFromWorld = camera.clipFromWorld(mode, viewport);
    drawn.clipFromView = projection.clipFromWorld(mode, viewport);
    drawn.viewFromWorld = camera.viewFromWorld;
    return drawn;
  };
  DepthMode upperLeft = kZeroToOne;
  upperLeft.origin = ClipOrigin::UpperLeft;
  const CameraInputs drawnUpperLeft = inputs(upperLeft);
  const CameraInputs lowerLeft = inputs(kZeroToOne);
  // The app's own matrix does flip y ...
  EXPECT_EQ(drawnUpperLeft.clipFromWorld[1][1], -lowerLeft.clipFromWorld[1][1]);
  EXPECT_NE(drawnUpperLeft.clipFromWorld[1][1], 0.0);
  // ... and its lower-left view undoes exactly that.
  const CameraInputs view = demo::lowerLeftCameraInputs(drawnUpperLeft);
  EXPECT_EQ(view.mode, kZeroToOne);
  EXPECT_EQ(view.clipFromWorld, lowerLeft.clipFromWorld);
  EXPECT_EQ(view.clipFromView, lowerLeft.clipFromView);
  EXPECT_EQ(view.viewFromWorld, lowerLeft.viewFromWorld);
  // A lower-left camera is its own view.
  const CameraInputs same = demo::lowerLeftCameraInputs(lowerLeft);
  EXPECT_EQ(same.clipFromWorld, lowerLeft.clipFromWorld);
  EXPECT_EQ(same.clipFromView, lowerLeft.clipFromView);
}

// The demo cuts every method's ray by the camera's clip planes as clipray cuts its own robust
// rays: the same bits, on the water reflection whose plane clips the sea floor and the submerged
// box away.
TEST(PickRays, ClipPlaneCutIsTheRobustGeneratorsBitForBit) {
  const Scene scene = loadScene(kSource + "/scenes/water_reflection_clipped.json");
  const Camera& camera = scene.cameras[0];
  ASSERT_EQ(camera.clipPlanes.size(), 1u);
  const Viewport viewport{320, 240};
  const glm::dmat4 clipFromWorld = camera.clipFromWorld(kNegativeOneToOne, viewport);
  const RobustRayGenerator uncut(clipFromWorld, kNegativeOneToOne);
  const RobustRayGenerator cut(clipFromWorld, kNegativeOneToOne, camera.clipPlanes);
  int moved = 0;
  for (int j = 0; j < viewport.height; j += 7) {
    for (int i = 0; i < viewport.width; i += 7) {
      Ray ray = uncut.generateForPixel(i, j, viewport);
      const Ray before = ray;
      cutToClipPlanes(ray, camera.clipPlanes);
      const Ray expected = cut.generateForPixel(i, j, viewport);
      ASSERT_EQ(ray.origin, expected.origin) << i << " " << j;
      ASSERT_EQ(ray.direction, expected.direction) << i << " " << j;
      ASSERT_EQ(ray.tMax, expected.tMax) << i << " " << j;
      if (ray.origin != before.origin) ++moved;
    }
  }
  EXPECT_GT(moved, 0);
  // No clip planes: the ray as it was.
  Ray ray = uncut.generateForPixel(3, 4, viewport);
  const Ray before = ray;
  cutToClipPlanes(ray, {});
  EXPECT_EQ(ray.origin, before.origin);
  EXPECT_EQ(ray.tMax, before.tMax);
  // A plane that keeps nothing of any line of sight (0 x + 0 y + 0 z - 1 >= 0 never holds).
  const glm::dvec4 nothing{0.0, 0.0, 0.0, -1.0};
  ray = before;
  cutToClipPlanes(ray, std::span<const glm::dvec4>(&nothing, 1));
  EXPECT_EQ(ray.tMax, 0.0);
}

TEST(PickScript, ParsesEveryCommand) {
  const auto commands = demo::parseScript(
      "# a comment\n\nresize 640 480\nclick 1.5 2\ndrag right 1 2 3 4  # pan\nscroll -2\nkey T\n",
      "s.txt");
  ASSERT_EQ(commands.size(), 5u);
  EXPECT_EQ(commands[0].kind, demo::ScriptCommand::Kind::Resize);
  EXPECT_EQ(commands[0].a, glm::dvec2(640, 480));
  EXPECT_EQ(commands[0].line, 3);
  EXPECT_EQ(commands[1].a, glm::dvec2(1.5, 2));
  EXPECT_TRUE(commands[2].rightButton);
  EXPECT_EQ(commands[2].b, glm::dvec2(3, 4));
  EXPECT_EQ(commands[3].steps, -2.0);
  EXPECT_EQ(commands[4].key, 't');
}

TEST(PickScript, BadLinesNameFileAndLine) {
  auto message = [](const std::string& text) {
    try {
      demo::parseScript(text, "s.txt");
    } catch (const InputError& error) {
      return std::string(error.what());
    }
    return std::string("no error");
  };
  EXPECT_EQ(message("resize 0 10"), "s.txt:1: resize: expected whole numbers from 1 to 16384");
  EXPECT_EQ(message("\nclick 1"), "s.txt:2: missing y");
  EXPECT_EQ(message("click 1 2 3"), "s.txt:1: unexpected \"3\" at the end of the line");
  EXPECT_EQ(message("drag middle 1 2 3 4"),
            "s.txt:1: drag: expected left or right, got \"middle\"");
  EXPECT_EQ(message("scroll nan"), "s.txt:1: steps: expected a number, got \"nan\"");
}

TEST(PickScript, DevicesAndNulBytesAreRefusedBeforeParsing) {
  auto message = [](const std::string& path) {
    try {
      demo::loadScript(path);
    } catch (const InputError& error) {
      return std::string(error.what());
    }
    return std::string("no error");
  };
  EXPECT_EQ(message("/dev/zero"), "/dev/zero: is not a regular file (a FIFO, device or socket)");
  TempFolder folder;
  const std::string nul = (folder.path() / "nul.txt").string();
  std::ofstream(nul, std::ios::binary) << std::string("key c\n\0key t\n", 13);
  EXPECT_EQ(message(nul), nul + ": byte 6: a NUL byte in a text file");
}

CameraInputs standardInputs(const Camera& camera, Viewport viewport, const glm::dmat4& move) {
  CameraInputs inputs;
  inputs.mode = kZeroToOne;
  inputs.clipFromWorld = camera.clipFromWorld(kZeroToOne, viewport) * move;
  return inputs;
}

TEST(PickRays, RobustAndTwoPointAgreeNearTheOriginAndPartFarFromIt) {
  const Scene scene = loadScene(kStandard);
  const Viewport viewport{320, 240};
  const glm::ivec2 pixel{160, 119};
  const demo::RayChoice robustFloat{RayMethod::Robust, Precision::Float};
  const demo::RayChoice twoPointFloat{RayMethod::TwoPoint, Precision::Float};
  const CameraInputs near = standardInputs(scene.cameras[0], viewport, glm::dmat4(1.0));
  const auto robust = demo::pickRay(robustFloat, near, viewport, pixel).ray;
  const auto twoPoint = demo::pickRay(twoPointFloat, near, viewport, pixel).ray;
  ASSERT_TRUE(robust && twoPoint);
  EXPECT_GT(glm::dot(robust->direction, twoPoint->direction), 1.0 - 1e-9);
  // 1e5 away, the float inverse loses the near plane: the directions part by far more than a
  // pixel's angle (about 60 deg / 240).
  glm::dmat4 offset(1.0);
  offset[3] = glm::dvec4(-1e5, 0.0, 0.0, 1.0);
  const CameraInputs far = standardInputs(scene.cameras[0], viewport, offset);
  const auto robustFar = demo::pickRay(robustFloat, far, viewport, pixel).ray;
  const auto twoPointFar = demo::pickRay(twoPointFloat, far, viewport, pixel).ray;
  ASSERT_TRUE(robustFar);
  EXPECT_GT(glm::dot(robustFar->direction, robust->direction), 1.0 - 1e-12);
  if (twoPointFar) {
    const double angle =
        std::acos(std::min(1.0, glm::dot(twoPointFar->direction, robust->direction)));
    EXPECT_GT(angle, glm::radians(60.0) / 240.0);
  }
  // plane_cross has no sign fix: on this right-handed camera it points straight backwards.
  const auto planeCross =
      demo::pickRay({RayMethod::PlaneCross, Precision::Float}, near, viewport, pixel).ray;
  ASSERT_TRUE(planeCross);
  EXPECT_LT(glm::dot(planeCross->direction, robust->direction), -1.0 + 1e-6);
  // An infinite far plane puts two_point's far point at infinity: no ray at all.
  const Scene infinite = loadScene(kSource + "/scenes/infinite_far.json");
  const CameraInputs infiniteInputs = standardInputs(infinite.cameras[0], viewport, glm::dmat4(1));
  EXPECT_TRUE(demo::pickRay(robustFloat, infiniteInputs, viewport, pixel).ray);
  const demo::PickRay none = demo::pickRay(twoPointFloat, infiniteInputs, viewport, pixel);
  EXPECT_FALSE(none.ray);
  EXPECT_EQ(none.unavailable, "non-finite ray");
  // Without projection, view or scalars, inverse_pv and fov_tangent cannot run: n/a, and why.
  const demo::PickRay noScalars =
      demo::pickRay({RayMethod::FovTangent, Precision::Float}, near, viewport, pixel);
  EXPECT_FALSE(noScalars.ray);
  EXPECT_EQ(noScalars.unavailable, missingInputs(RayMethod::FovTangent, near));
  EXPECT_FALSE(noScalars.unavailable.empty());
}

TEST(PickRays, MCyclesThroughEveryLibraryMethodInFloatThenRobustDouble) {
  demo::RayChoice choice{RayMethod::UnprojectGlm, Precision::Float};
  std::vector<std::string> names;
  for (std::size_t k = 0; k < std::size(demo::kDemoRayChoices); ++k) {
    names.push_back(demo::rayChoiceName(choice));
    choice = demo::nextRayChoice(choice);
  }
  EXPECT_EQ(choice, (demo::RayChoice{RayMethod::UnprojectGlm, Precision::Float}));  // wrapped
  const std::vector<std::string> expected = {
      "unproject_glm float", "two_point float",   "inverse_pv float",
      "fov_tangent float",   "plane_cross float", "plane_cross_pre float",
      "full float",          "robust float",      "robust double"};
  EXPECT_EQ(names, expected);
  for (const RayMethod method : kRayMethods) {
    EXPECT_NE(std::find(names.begin(), names.end(), rayMethodName(method) + " float"), names.end());
  }
  // A choice off the cycle (--method two_point --precision double) continues after its float one.
  EXPECT_EQ(demo::nextRayChoice({RayMethod::TwoPoint, Precision::Double}),
            (demo::RayChoice{RayMethod::InversePv, Precision::Float}));
}

}  // namespace
}  // namespace clipray
