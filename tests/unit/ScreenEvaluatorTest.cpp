// The screen-space evaluator (ScreenEvaluator.hpp) gives the ray path's hits bit for bit: the
// fast-path scene through the binned cameras, and random mesh scenes through every hard-case
// camera (telephoto, far from the origin, reversed-Z, infinite far, oblique, orthographic, tiny
// and odd viewports). No decided pixel's test may miss (a bound that did not hold), and most
// pixels must be decided without the ray path's search. Each frame is evaluated under both
// kernel choices.

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <iostream>
#include <string>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>

#include "clipray/compare/ScreenEvaluator.hpp"
#include "clipray/math/Projections.hpp"
#include "clipray/rays/QuadReference.hpp"
#include "clipray/util/KernelChoice.hpp"
#include "support/FastPathScenes.hpp"
#include "support/RandomScenes.hpp"

namespace clipray {
namespace {

using testing::fast_path::intersectorSeenFrom;

// The kernel choice for one scope (the screen walk runs on AVX2 lanes or on the baseline's).
struct KernelsFor {
  explicit KernelsFor(KernelChoice choice) { chooseKernels(choice); }
  ~KernelsFor() { chooseKernels(KernelChoice::Simd); }
  KernelsFor(const KernelsFor&) = delete;
  KernelsFor& operator=(const KernelsFor&) = delete;
};

// The frame's hits through the screen and through the rays, under one kernel choice.
ScreenEvaluation expectTheRayPathsHits(const SceneIntersector& intersector,
                                       const PickingCamera& camera, const AnalyticFrame& byRays,
                                       KernelChoice kernels, const std::string& what) {
  const KernelsFor scope(kernels);
  AnalyticFrame byScreen = robustRayFrame(camera);
  const ScreenEvaluation evaluation = intersectFrameInScreenSpace(byScreen, intersector, camera, 2);
  EXPECT_EQ(byScreen.hits.size(), byRays.hits.size()) << what;
  for (std::size_t i = 0; i < byRays.hits.size() && i < byScreen.hits.size(); ++i) {
    const Hit& a = byScreen.hits[i];
    const Hit& b = byRays.hits[i];
    if (a.primitiveId != b.primitiveId ||
        std::bit_cast<std::uint64_t>(a.t) != std::bit_cast<std::uint64_t>(b.t)) {
      ADD_FAILURE() << what << ", pixel " << i % camera.viewport.width << ","
                    << i / camera.viewport.width << ": screen " << a.primitiveId << " at " << a.t
                    << ", rays " << b.primitiveId << " at " << b.t;
      break;
    }
  }
  EXPECT_EQ(evaluation.boundMisses, 0u) << what;
  if (evaluation.used) {
    EXPECT_EQ(evaluation.background + evaluation.decided + evaluation.contested + evaluation.traced,
              byRays.hits.size())
        << what;
  }
  // Decided pixels from their planes: the same triangles, no t (NaN) where no ray was traced,
  // the ray path's t everywhere else, and the same counts.
  AnalyticFrame byPlanes = robustRayFrame(camera);
  const ScreenEvaluation planes = intersectFrameInScreenSpace(byPlanes, intersector, camera, 2,
                                                              nullptr, DecidedHits::FromPlanes);
  EXPECT_EQ(planes.used, evaluation.used) << what;
  EXPECT_EQ(planes.decided, evaluation.decided) << what;
  EXPECT_EQ(planes.background, evaluation.background) << what;
  EXPECT_EQ(planes.contested, evaluation.contested) << what;
  EXPECT_EQ(planes.traced, evaluation.traced) << what;
  // Under depth clamp a parallel camera's rays reach behind the near plane, and the compare
  // measures along them: its decided pixels are tested.
  const bool clampedParallel =
      camera.depthClamp && glm::dvec3(matrixRow(camera.clipFromWorld, 3)) == glm::dvec3(0.0);
  EXPECT_EQ(byPlanes.planesById != nullptr, planes.used && !clampedParallel) << what;
  std::size_t untraced = 0;
  for (std::size_t i = 0; i < byRays.hits.size() && i < byPlanes.hits.size(); ++i) {
    const Hit& a = byPlanes.hits[i];
    const Hit& b = byRays.hits[i];
    const bool fromPlanes = std::isnan(a.t);
    untraced += fromPlanes ? 1 : 0;
    if (a.primitiveId != b.primitiveId ||
        (!fromPlanes && std::bit_cast<std::uint64_t>(a.t) != std::bit_cast<std::uint64_t>(b.t))) {
      ADD_FAILURE() << what << " from planes, pixel " << i % camera.viewport.width << ","
                    << i / camera.viewport.width << ": " << a.primitiveId << " at " << a.t
                    << ", rays " << b.primitiveId << " at " << b.t;
      break;
    }
  }
  EXPECT_LE(untraced, planes.decided) << what;
  // Decided pixels take their planes: every camera here has a ray at every pixel of most tiles.
  if (planes.used && planes.decided > 0 && !clampedParallel) {
    EXPECT_GT(untraced, 0u) << what;
  }
  if (clampedParallel) {
    EXPECT_EQ(untraced, 0u) << what;
  }
  return evaluation;
}

// The same under both kernel choices, which make the same decisions: the walk's operations are
// the same on AVX2 lanes as on the baseline's (no multiply-add is fused in ISO C++), so the
// counts agree too. Returns the SIMD walk's evaluation.
ScreenEvaluation expectTheRayPathsHits(const Scene& scene, const PickingCamera& camera,
                                       const std::string& what) {
  const SceneIntersector intersector = intersectorSeenFrom(scene, camera);
  AnalyticFrame byRays = robustRayFrame(camera);
  intersectFrame(byRays, intersector, camera, 2);
  const ScreenEvaluation simd =
      expectTheRayPathsHits(intersector, camera, byRays, KernelChoice::Simd, what + " (simd)");
  const ScreenEvaluation portable = expectTheRayPathsHits(
      intersector, camera, byRays, KernelChoice::Portable, what + " (portable)");
  EXPECT_EQ(simd.used, portable.used) << what;
  EXPECT_EQ(simd.background, portable.background) << what;
  EXPECT_EQ(simd.decided, portable.decided) << what;
  EXPECT_EQ(simd.contested, portable.contested) << what;
  EXPECT_EQ(simd.traced, portable.traced) << what;
  return simd;
}

// What the random scenes' evaluations add up to; a frame left to the rays is printed with why.
struct Tally {
  int evaluated = 0;
  std::size_t traced = 0, decided = 0, pixels = 0;
  void add(const ScreenEvaluation& e, const std::string& what) {
    if (!e.used) {
      std::cout << what << ": rays (" << e.reason << ")\n";
      return;
    }
    ++evaluated;
    traced += e.traced;
    decided += e.decided;
    pixels += e.background + e.decided + e.contested + e.traced;
  }
};

TEST(ScreenEvaluator, TheBinnedCamerasGetTheRayPathsHits) {
  Scene scene = testing::fast_path::testScene();
  for (const Viewport size : {Viewport{61, 47}, Viewport{320, 240}}) {
    for (const testing::fast_path::BinnedCase& c : testing::fast_path::binnedCases(size)) {
      const std::string what = std::string(c.name) + " at " + std::to_string(size.width);
      const ScreenEvaluation e = expectTheRayPathsHits(scene, c.camera, what);
      ASSERT_TRUE(e.used) << what << ": " << e.reason;
      const std::size_t pixels = static_cast<std::size_t>(size.width) * size.height;
      // The decisions' margins are 10^-8 of a pixel and less here: the ray path's search is
      // left for the pixels where two triangles meet within them (coplanar decals, shared
      // edges through a centre) and for triangles crossing the near plane.
      EXPECT_LT(e.traced * 20, pixels)
          << what << ": " << e.traced << " traced, " << e.decided << " decided, " << e.contested
          << " contested, " << e.background << " background";
      EXPECT_GT(e.decided, pixels / 4) << what;
      EXPECT_GT(e.rayDeviationNdc, 0.0) << what;
      EXPECT_LT(e.rayDeviationNdc, 1e-9) << what;
    }
  }
}

TEST(ScreenEvaluator, RandomMeshScenesThroughTheHardCaseCamerasGetTheRayPathsHits) {
  std::uint64_t seed = 1;
  Tally tally;
  int scenes = 0;
  for (const Viewport size : {Viewport{96, 64}, Viewport{101, 61}}) {
    for (const HardCase& hardCase : hardCases(size)) {
      const Scene scene = testing::randomScene(hardCase, hardCase.viewport, seed++, true);
      if (scene.objects.empty()) continue;
      ++scenes;
      const PickingCamera camera{hardCase.inputs.clipFromWorld, hardCase.inputs.mode,
                                 hardCase.viewport};
      const std::string what = scene.name + " " + hardCase.convention() + " " +
                               std::to_string(size.width) + "x" + std::to_string(size.height);
      tally.add(expectTheRayPathsHits(scene, camera, what), what);
    }
  }
  std::cout << tally.evaluated << " of " << scenes << " scenes evaluated in screen space, "
            << tally.traced << " of " << tally.pixels << " pixels traced\n";
  EXPECT_GT(tally.evaluated * 4, scenes * 3);
}

// The NDC depth at which the exact line of sight through NDC (x, y) crosses the triangle's plane,
// in binary128 from the matrix and the vertices as stored: z = sum_k E_k(s) z_k / det[h0, h1, h2]
// with E_k(s) = det[h_j, h_l, s] over clip (x, y, w) and s = (x, y, 1).
double exactNdcZ(const glm::dmat4& clipFromWorld, const std::array<glm::dvec3, 3>& triangle,
                 glm::dvec2 s) {
  const QuadMat4 m = toQuad(clipFromWorld);
  QuadVec4 h[3];
  for (int k = 0; k < 3; ++k) {
    const QuadVec4 v = {triangle[k].x, triangle[k].y, triangle[k].z, 1.0};
    Float128 c[4];
    for (int r = 0; r < 4; ++r) c[r] = dot(quadRow(m, r), v);
    h[k] = {c[0], c[1], c[2], c[3]};
  }
  const QuadVec3 point = {s.x, s.y, 1.0};
  const auto xyw = [](const QuadVec4& v) { return QuadVec3{v.x, v.y, v.w}; };
  Float128 numerator = 0, determinant = 0;
  for (int k = 0; k < 3; ++k) {
    const QuadVec4 &a = h[(k + 1) % 3], &b = h[(k + 2) % 3];
    numerator += dot(cross(xyw(a), xyw(b)), point) * h[k].z;
  }
  determinant = dot(cross(xyw(h[1]), xyw(h[2])), xyw(h[0]));
  return toDouble(numerator / determinant);
}

// A decided pixel's depth from its triangle's depth plane lies within the setup's bound of the
// exact crossing of the pixel centre's line of sight: the depth a compare in screen space would
// take instead of the ray's. Printed beside it: how far the ray path's own depth (its ray at its
// t, through the matrix, as the compare computes it) lies from the same crossing.
TEST(ScreenEvaluator, DecidedDepthsLieWithinTheirBoundOfTheExactCrossing) {
  std::uint64_t seed = 1;
  std::size_t pixels = 0, decided = 0;
  double worstRatio = 0.0, worstScreen = 0.0, worstRays = 0.0;
  for (const Viewport size : {Viewport{96, 64}, Viewport{101, 61}}) {
    for (const HardCase& hardCase : hardCases(size)) {
      const Scene scene = testing::randomScene(hardCase, hardCase.viewport, seed++, true);
      if (scene.objects.empty()) continue;
      const PickingCamera camera{hardCase.inputs.clipFromWorld, hardCase.inputs.mode,
                                 hardCase.viewport};
      const SceneIntersector intersector = intersectorSeenFrom(scene, camera);
      AnalyticFrame frame = robustRayFrame(camera);
      ScreenDepths depths;
      const ScreenEvaluation e =
          intersectFrameInScreenSpace(frame, intersector, camera, 2, &depths);
      ASSERT_EQ(depths.ndcZ.size(), frame.pixelCount());
      if (!e.used) continue;
      decided += e.decided;
      const Viewport viewport = camera.viewport;
      std::vector<Ray> row(static_cast<std::size_t>(viewport.width));
      for (int y = 0; y < viewport.height; ++y) {
        frame.pixelCentreRays->row(y, 0, viewport.width, row.data());
        for (int x = 0; x < viewport.width; ++x) {
          const std::size_t i = static_cast<std::size_t>(y) * viewport.width + x;
          if (std::isnan(depths.ndcZ[i])) continue;
          ++pixels;
          const Hit& hit = frame.hits[i];
          const double exact =
              exactNdcZ(camera.clipFromWorld, intersector.worldTriangle(hit.primitiveId),
                        clipXYOfPixelCentre(x, y, viewport));
          const double screen = std::abs(depths.ndcZ[i] - exact);
          ASSERT_LE(screen, depths.bound[i])
              << scene.name << " " << hardCase.convention() << ", pixel " << x << "," << y
              << ": plane " << depths.ndcZ[i] << ", exact " << exact;
          const Ray& ray = row[static_cast<std::size_t>(x)];
          const glm::dvec4 clip =
              camera.clipFromWorld * glm::dvec4(ray.origin + hit.t * ray.direction, 1.0);
          worstRatio = std::max(worstRatio, screen / depths.bound[i]);
          worstScreen = std::max(worstScreen, screen);
          worstRays = std::max(worstRays, std::abs(clip.z / clip.w - exact));
        }
      }
    }
  }
  std::cout << pixels << " decided pixels: NDC depth from the plane within " << worstScreen
            << " of the exact crossing (at most " << worstRatio
            << " of its bound); the ray path's depth within " << worstRays << "\n";
  // Every decided pixel with a ray has its depth (none lacks one in these scenes).
  EXPECT_EQ(pixels, decided);
}

// A bumpy grid whose vertices lie on pixel centres' lines of sight, every third pixel: its
// edges and vertices pass through pixel centres (up to the vertices' rounding), where the edge
// functions are zero and only the ray path can decide.
TEST(ScreenEvaluator, EdgesAndVerticesThroughPixelCentresAreTracedAndMatch) {
  for (const testing::fast_path::BinnedCase& c : testing::fast_path::binnedCases({64, 48})) {
    const RobustRayGenerator generator(c.camera.clipFromWorld, c.camera.mode);
    MeshObject grid;
    grid.name = "grid";
    const int cells = 12;
    for (int j = 0; j <= cells; ++j) {
      for (int i = 0; i <= cells; ++i) {
        const Ray ray = generator.generateForPixel(8 + 3 * i, 5 + 3 * j, c.camera.viewport);
        const double t = (std::isfinite(ray.tMax) ? 0.05 * ray.tMax : 5.0) *
                         (1.0 + 0.2 * std::sin(0.7 * i) * std::cos(0.5 * j));
        grid.worldPositions.push_back(ray.origin + t * ray.direction);
      }
    }
    grid.triangles = testing::gridTriangles(cells);
    Scene scene;
    scene.objects.push_back(grid);
    const ScreenEvaluation e = expectTheRayPathsHits(scene, c.camera, c.name);
    ASSERT_TRUE(e.used) << c.name << ": " << e.reason;
    // Every shared edge crosses pixel centres: those pixels are the ray path's.
    EXPECT_GT(e.traced, 100u) << c.name;
    EXPECT_GT(e.decided, 100u) << c.name;
  }
}

// Analytic primitives stay on rays: the pixels of their padded bounds are traced where the nearest
// triangle may lie beyond their box's least depth, the rest decided. A plane may cover any pixel at
// any depth: with one, every pixel is traced.
TEST(ScreenEvaluator, AnalyticPrimitivesTraceThePixelsTheyMayCover) {
  const Scene withPlane = testing::fast_path::testSceneWithPrimitives();
  Scene bounded = withPlane;
  std::erase_if(bounded.primitives,
                [](const AnalyticPrimitive& p) { return p.kind == PrimitiveKind::Plane; });
  ASSERT_EQ(bounded.primitives.size() + 1, withPlane.primitives.size());
  for (const Viewport size : {Viewport{61, 47}, Viewport{96, 64}}) {
    for (const testing::fast_path::BinnedCase& c : testing::fast_path::binnedCases(size)) {
      const std::string what = std::string(c.name) + " at " + std::to_string(size.width);
      const std::size_t pixels = static_cast<std::size_t>(size.width) * size.height;
      const ScreenEvaluation everywhere = expectTheRayPathsHits(withPlane, c.camera, what);
      ASSERT_TRUE(everywhere.used) << what << ": " << everywhere.reason;
      EXPECT_EQ(everywhere.traced, pixels) << what;
      const ScreenEvaluation e = expectTheRayPathsHits(bounded, c.camera, what);
      const ScreenEvaluation meshes =
          expectTheRayPathsHits(testing::fast_path::testScene(), c.camera, what);
      EXPECT_GT(e.traced, meshes.traced) << what;
      EXPECT_GT(e.decided, pixels / 8) << what;
    }
  }
}

// A sphere wholly behind a wall: its box's least depth lies beyond the wall's, so no pixel of its
// bounds is traced; without the wall, every pixel it shows is.
TEST(ScreenEvaluator, APrimitiveBehindTheNearestTriangleIsNotTraced) {
  const PickingCamera camera = testing::fast_path::binnedCases(Viewport{96, 64})[0].camera;
  const glm::dmat4 worldFromClip = glm::inverse(camera.clipFromWorld);
  const auto unproject = [&](double x, double y, double along) {
    const double z =
        camera.mode.nearNdcZ() + along * (camera.mode.farNdcZ() - camera.mode.nearNdcZ());
    const glm::dvec4 p = worldFromClip * glm::dvec4(x, y, z, 1.0);
    return glm::dvec3(p) / p.w;
  };
  Scene wall;
  wall.name = "wall";
  MeshObject quad;
  quad.name = "wall";
  quad.worldPositions = {unproject(-0.8, -0.8, 0.3), unproject(0.8, -0.8, 0.3),
                         unproject(0.8, 0.8, 0.3), unproject(-0.8, 0.8, 0.3)};
  quad.triangles = {glm::u32vec3(0, 1, 2), glm::u32vec3(0, 2, 3)};
  wall.objects.push_back(quad);
  const glm::dvec3 centre = unproject(0.0, 0.0, 0.9);
  const double radius = 0.05 * glm::length(centre - unproject(0.0, 0.0, 0.3));
  AnalyticPrimitive sphere;
  sphere.name = "sphere";
  sphere.worldFromLocal =
      glm::translate(glm::dmat4(1.0), centre) * glm::scale(glm::dmat4(1.0), glm::dvec3(radius));
  sphere.localFromWorld = glm::inverse(sphere.worldFromLocal);
  wall.primitives.push_back(sphere);
  const ScreenEvaluation behind = expectTheRayPathsHits(wall, camera, "a sphere behind a wall");
  ASSERT_TRUE(behind.used) << behind.reason;
  EXPECT_EQ(behind.traced, 0u);
  Scene open = wall;
  open.objects.front().worldPositions = {unproject(-0.8, -0.8, 0.3), unproject(-0.7, -0.8, 0.3),
                                         unproject(-0.7, -0.7, 0.3), unproject(-0.8, -0.7, 0.3)};
  const ScreenEvaluation shown = expectTheRayPathsHits(open, camera, "a sphere in the open");
  ASSERT_TRUE(shown.used) << shown.reason;
  EXPECT_GT(shown.traced, 0u);
}

TEST(ScreenEvaluator, FramesOutsideItsDecisionsAreTheRayPathsWithTheReason) {
  const PickingCamera camera = testing::fast_path::binnedCases()[0].camera;
  Scene primitivesAlone = testing::fast_path::testSceneWithPrimitives();
  primitivesAlone.objects.clear();
  const ScreenEvaluation e = expectTheRayPathsHits(primitivesAlone, camera, "primitives alone");
  EXPECT_FALSE(e.used);
  EXPECT_EQ(e.reason, "analytic primitives stay on rays");
}

// The triangle from world points a, b, c, as an object of its own.
MeshObject triangleObject(const std::string& name, glm::dvec3 a, glm::dvec3 b, glm::dvec3 c) {
  MeshObject object;
  object.name = name;
  object.worldPositions = {a, b, c};
  object.triangles = {glm::u32vec3(0, 1, 2)};
  return object;
}

// GL_DEPTH_CLAMP draws what lies in front of the near plane, and the rays start at the eye (a
// parallel camera's behind the near plane): the screen path bins and decides down to 2^-16 of the
// near plane's w, with Delta grown as 1 / w towards the eye. Random scenes through every hard-case
// camera, with triangles between the eye and the near plane and a floor reaching behind the eye,
// beyond the far plane or not, a third of them with a user clip plane through the weapon; a
// triangle through the eye leaves the frame to the rays.
TEST(ScreenEvaluator, DepthClampedRaysFromTheEyeGetTheRayPathsHits) {
  std::uint64_t seed = 301;
  Tally tally;
  int scenes = 0, nearTriangles = 0, clipped = 0, clippedEvaluated = 0;
  for (const HardCase& hardCase : hardCases(Viewport{96, 64})) {
    Scene scene = testing::randomScene(hardCase, hardCase.viewport, seed++, true);
    if (scene.objects.empty()) continue;
    PickingCamera c{hardCase.inputs.clipFromWorld, hardCase.inputs.mode, hardCase.viewport};
    c.depthClamp = true;
    c.depthClampBeyondFar = scenes % 2 == 1;
    const glm::dmat4 worldFromClip = glm::inverse(c.clipFromWorld);
    const auto unproject = [&](double x, double y, double z) {
      const glm::dvec4 p = worldFromClip * glm::dvec4(x, y, z, 1.0);
      return glm::dvec3(p) / p.w;
    };
    const double zn = c.mode.nearNdcZ();
    const bool parallel = glm::dvec3(matrixRow(c.clipFromWorld, 3)) == glm::dvec3(0.0);
    if (parallel) {
      c.depthClampReach = 4.0 * glm::length(unproject(1.0, 1.0, zn) - unproject(-1.0, -1.0, 1.0));
    } else {
      const glm::dvec4 e = worldFromClip * glm::dvec4(0.0, 0.0, 1.0, 0.0);
      const glm::dvec3 eye = glm::dvec3(e) / e.w;
      // Between the eye and the near plane (a first-person weapon), and a floor from below the
      // view to behind the eye: its plane passes well below the eye.
      const auto towards = [&](double x, double y, double lambda) {
        return eye + lambda * (unproject(x, y, zn) - eye);
      };
      scene.objects.push_back(triangleObject("weapon", towards(-0.5, -0.6, 0.3),
                                             towards(0.4, -0.7, 0.8), towards(0.1, 0.2, 0.5)));
      scene.objects.push_back(triangleObject(
          "floor", towards(-1.5, -0.9, 40.0), towards(1.5, -0.9, 40.0),
          eye - 8.0 * (unproject(0.0, 0.9, zn) - eye) - 4.0 * (unproject(0.0, 1.0, zn) - eye)));
      nearTriangles += 2;
      if (scenes % 3 == 0) {
        // A plane through the weapon, moving the rays' start off the eye where it cuts them.
        const glm::dvec3 through = towards(0.0, -0.4, 0.5);
        const glm::dvec3 normal = glm::normalize(unproject(0.0, 0.0, zn) - eye);
        c.clipPlanes = {glm::dvec4(normal, -glm::dot(normal, through))};
        ++clipped;
      }
    }
    ++scenes;
    const std::string what = scene.name + " " + hardCase.convention() + " depth clamp" +
                             (c.depthClampBeyondFar ? " beyond far" : "") +
                             (c.clipPlanes.empty() ? "" : " clipped");
    const ScreenEvaluation e = expectTheRayPathsHits(scene, c, what);
    clippedEvaluated += e.used && !c.clipPlanes.empty() ? 1 : 0;
    tally.add(e, what);
  }
  std::cout << tally.evaluated << " of " << scenes << " depth-clamped scenes evaluated in screen "
            << "space (" << nearTriangles << " triangles in front of the near plane or behind the "
            << "eye), " << clippedEvaluated << " of " << clipped << " with a clip plane; "
            << tally.decided << " pixels decided, " << tally.traced << " traced\n";
  EXPECT_GT(tally.evaluated * 4, scenes * 3);
  EXPECT_GT(clippedEvaluated * 2, clipped);
  EXPECT_GT(tally.decided, 10 * tally.traced);

  // A triangle with a vertex at the eye: rays near the eye may hit it where no bound holds.
  const PickingCamera binned = testing::fast_path::binnedCases()[0].camera;
  PickingCamera clamped = binned;
  clamped.depthClamp = true;
  const glm::dmat4 worldFromClip = glm::inverse(binned.clipFromWorld);
  const glm::dvec4 e = worldFromClip * glm::dvec4(0.0, 0.0, 1.0, 0.0);
  const glm::dvec3 eye = glm::dvec3(e) / e.w;
  Scene throughTheEye = testing::fast_path::testScene();
  const ScreenEvaluation whole = expectTheRayPathsHits(throughTheEye, clamped, "depth clamp");
  EXPECT_TRUE(whole.used) << whole.reason;
  throughTheEye.objects.push_back(triangleObject("through the eye", eye, eye + glm::dvec3(5, 0, 0),
                                                 eye + glm::dvec3(0, 0, -5)));
  const ScreenEvaluation touched =
      expectTheRayPathsHits(throughTheEye, clamped, "depth clamp, a triangle through the eye");
  EXPECT_FALSE(touched.used);
  EXPECT_EQ(touched.reason, "a triangle passes within the depth-clamped rays' reach of the eye");
}

// The camera's user clip planes cut the rays as GL cuts the drawing: the triangles a plane may cut
// are left to the ray path where they may be the nearest, those it keeps or clips whole are
// decided. Planes through the scene at random, some cutting every ray's start (its origin moved
// to where its line of sight enters the kept side, as a mirrored water camera's rays are).
TEST(ScreenEvaluator, UserClipPlanesCutTheHitsAsTheRayPathCutsThem) {
  const Scene binned = testing::fast_path::testScene();
  const PickingCamera camera = testing::fast_path::binnedCases()[0].camera;
  PickingCamera clipped = camera;
  clipped.clipPlanes = {glm::dvec4(0.0, 1.0, 0.0, -0.5)};
  const ScreenEvaluation water = expectTheRayPathsHits(binned, clipped, "y >= 0.5");
  ASSERT_TRUE(water.used) << water.reason;
  EXPECT_GT(water.decided, water.traced);

  std::uint64_t seed = 101;
  Tally tally;
  int scenes = 0, originsMoved = 0;
  for (const HardCase& hardCase : hardCases(Viewport{96, 64})) {
    const Scene scene = testing::randomScene(hardCase, hardCase.viewport, seed, true);
    if (scene.objects.empty()) continue;
    PickingCamera c{hardCase.inputs.clipFromWorld, hardCase.inputs.mode, hardCase.viewport};
    // A plane through a vertex of the scene, its normal at random, and now and then a second.
    std::uint64_t state = seed++ * 0x9e3779b97f4a7c15ull;
    const auto next = [&state] {
      state = state * 6364136223846793005ull + 1442695040888963407ull;
      return static_cast<double>(state >> 11) * 0x1p-53 * 2.0 - 1.0;
    };
    for (int k = 0; k < (scenes % 3 == 2 ? 2 : 1); ++k) {
      const MeshObject& object =
          scene.objects[static_cast<std::size_t>(scenes) % scene.objects.size()];
      const glm::dvec3 through =
          object.worldPositions[static_cast<std::size_t>(k) % object.worldPositions.size()];
      const glm::dvec3 normal = glm::normalize(glm::dvec3(next(), next(), next()) + 1e-3);
      c.clipPlanes.emplace_back(normal, -glm::dot(normal, through));
    }
    ++scenes;
    const Ray centre = robustRayFrame(c).pixelCentreRays->generator().generate({0.0, 0.0});
    const Ray uncut = robustRayFrame(PickingCamera{c.clipFromWorld, c.mode, c.viewport})
                          .pixelCentreRays->generator()
                          .generate({0.0, 0.0});
    originsMoved += centre.origin != uncut.origin ? 1 : 0;
    const std::string what = scene.name + " " + hardCase.convention() + " with " +
                             std::to_string(c.clipPlanes.size()) + " clip planes";
    tally.add(expectTheRayPathsHits(scene, c, what), what);
  }
  std::cout << tally.evaluated << " of " << scenes << " clipped scenes evaluated in screen space, "
            << originsMoved << " with the centre ray's origin moved; " << tally.decided
            << " pixels decided, " << tally.traced << " traced\n";
  EXPECT_GT(tally.evaluated * 4, scenes * 3);
  EXPECT_GT(originsMoved, 0);
  EXPECT_GT(tally.decided, tally.traced);
}

}  // namespace
}  // namespace clipray
