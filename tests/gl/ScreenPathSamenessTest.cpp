// The screen path (--analytic screen: ScreenEvaluator.hpp, its decided pixels compared from their
// triangles' planes, PlaneClassification.cpp) classifies what the ray path classifies: random mesh
// scenes seen by the hard-case cameras, drawn once per depth format and compared with both passes,
// give every pixel the same class and every count the same; the depths of the pixels the planes
// decided lie within their planes' bound of the exact crossing (tests/unit/ScreenEvaluatorTest.cpp)
// and, printed here with the worst difference of every figure, close to the ray path's.
// A third of the cameras draw with a user clip plane through the scene, a quarter with depth clamp
// (some with both), and a fifth of the perspective ones without depth clamp write a logarithmic
// depth (three.js's or Outerra's), whose pixels' depths lie within the reach the plane of 1 / w
// gives them (LogDepthMapping::reachOver); a quarter draw an object with a depth range, a polygon
// offset or a clip plane of its own (DrawStateGroups.hpp: its group's depths from planes compete
// in the depth test).

#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <iostream>
#include <limits>
#include <string>
#include <vector>

#include "clipray/compare/PrimitiveClipPlanes.hpp"
#include "clipray/engine/ReconcileRun.hpp"
#include "clipray/rays/HardCases.hpp"
#include "clipray/report/Report.hpp"
#include "support/AnalyticPathFor.hpp"
#include "support/EveryDepthFormat.hpp"
#include "support/GlFixture.hpp"
#include "support/PlanePixelChecks.hpp"
#include "support/RandomScenes.hpp"
#include "support/Sanitizers.hpp"

namespace clipray {
namespace {

using testing::AnalyticPathFor;
using testing::GlTest;

// Every number of the run's report entry that is not a count: the figures the planes compute.
void collectFigures(const nlohmann::json& entry, const std::string& at,
                    std::vector<std::pair<std::string, double>>& figures) {
  if (entry.is_object()) {
    for (const auto& [key, value] : entry.items()) collectFigures(value, at + "/" + key, figures);
  } else if (entry.is_array()) {
    for (std::size_t k = 0; k < entry.size(); ++k) {
      collectFigures(entry[k], at + "/" + std::to_string(k), figures);
    }
  } else if (entry.is_number_float()) {
    figures.emplace_back(at, entry.get<double>());
  }
}

// The run's report entry without what is measured (timings) or says which path ran.
nlohmann::json entryOf(const RunRecord& run) {
  nlohmann::json entry = reportJson({run}, GlInfo{})["runs"].at(0);
  for (const char* measured : {"timings_ms", "cpu_ms", "analytic_over_raster", "screen_path"}) {
    entry.erase(measured);
  }
  return entry;
}

// The entry with every float figure set to 0: what must be equal exactly (counts, verdicts,
// classes' clusters, the worst pixel's place).
nlohmann::json withoutFigures(nlohmann::json entry) {
  if (entry.is_object() || entry.is_array()) {
    for (auto& value : entry) value = withoutFigures(value);
  } else if (entry.is_number_float()) {
    entry = 0.0;
  }
  return entry;
}

class ScreenPathSameness : public GlTest {};

TEST_F(ScreenPathSameness, RandomMeshScenesThroughTheHardCaseCamerasClassifyAsTheRayPath) {
  const std::vector<Viewport> sizes = testing::kUnderAddressSanitizer
                                          ? std::vector<Viewport>{{101, 61}}
                                          : std::vector<Viewport>{{96, 64}, {101, 61}};
  std::uint64_t seed = 1;
  int runs = 0, evaluated = 0;
  std::int64_t fromPlanes = 0, compared = 0;
  double worstDepth = 0.0, worstDepthOverBound = 0.0, worstFigure = 0.0;
  std::string worstFigureAt;
  int clipped = 0, clamped = 0, logDepth = 0, grouped = 0;
  std::int64_t logFromPlanes = 0, groupsFromPlanes = 0, rayPathHits = 0, ownPlaneHits = 0;
  for (const Viewport size : sizes) {
    for (const HardCase& hardCase : hardCases(size)) {
      Scene scene = testing::randomScene(hardCase, hardCase.viewport, seed++, true);
      if (scene.objects.empty()) continue;
      if (seed % 4 == 1) {
        // Drawn with GL_DEPTH_CLAMP: the rays start at the eye, decided pixels are tested.
        scene.depthClamp = true;
        ++clamped;
      }
      // A quarter of the scenes draw a copy of their first object with state of its own, a group
      // apart that meets the original at every pixel it covers: a depth range of its own (a
      // first-person weapon's), a polygon offset toward the camera (a decal on its wall) or a
      // clip plane of its own through its first vertex (a section view's).
      // The reversed-Z cameras too, whose depth test keeps the greater depth.
      const bool ownState = (seed % 4 == 3 || hardCase.inputs.mode.reversed) && !scene.depthClamp;
      if (ownState) {
        MeshObject copy = scene.objects.front();
        copy.name += "_own_state";
        const glm::dvec3 through = copy.worldPositions.front();
        switch (seed % 3) {
          case 0:
            copy.depthRange = glm::dvec2(0.0, 0.25);
            break;
          case 1:
            copy.polygonOffset = PolygonOffset{-1.0, -2.0, 0.0};
            break;
          default: {
            copy.clipPlanes = {
                glm::dvec4(glm::dvec3(0.6, 0.0, 0.8), -0.6 * through.x - 0.8 * through.z)};
            // The last object too, with a plane of its own through its first vertex (its pixels
            // are its group's, not the copy's, which ties with the original it lies on).
            MeshObject& last = scene.objects.back();
            const glm::dvec3 at = last.worldPositions.front();
            last.clipPlanes = {glm::dvec4(glm::dvec3(-0.8, 0.0, 0.6), 0.8 * at.x - 0.6 * at.z)};
            break;
          }
        }
        scene.objects.push_back(std::move(copy));
        ++grouped;
      }
      Camera camera = testing::hardCaseCamera(hardCase);
      if (seed % 5 == 2 && hardCase.fovYDegrees && !scene.depthClamp && !ownState) {
        // L reaches 1 beyond every vertex in front of the eye.
        double farthest = 0.0;
        for (const MeshObject& object : scene.objects) {
          for (const glm::dvec3& v : object.worldPositions) {
            farthest = std::max(farthest, (hardCase.inputs.clipFromWorld * glm::dvec4(v, 1.0)).w);
          }
        }
        if (farthest > 0.0) {
          camera.logarithmicDepth =
              seed % 2 == 0 ? LogarithmicDepth{LogDepthForm::ThreeJs, 2.0 * farthest, 1.0}
                            : LogarithmicDepth{LogDepthForm::Outerra, 2.0 * farthest, 0.05};
          ++logDepth;
        }
      }
      if (seed % 3 == 0) {
        // A user clip plane through a vertex of the scene, its normal from the seed: the triangles
        // it cuts go to the rays, those it keeps or clips whole stay on the screen path.
        const glm::dvec3 through = scene.objects.front().worldPositions.front();
        const double angle = static_cast<double>(seed) * 2.399963;
        const glm::dvec3 normal = glm::normalize(glm::dvec3(std::cos(angle), 0.6, std::sin(angle)));
        camera.clipPlanes = {glm::dvec4(normal, -glm::dot(normal, through))};
        ++clipped;
      }
      const DepthMode mode = hardCase.inputs.mode;
      const engine::AnalyticPass rays = [&] {
        const AnalyticPathFor path(AnalyticPath::Rays);
        return engine::runAnalyticPass(scene, camera, mode, camera.viewport, 2);
      }();
      const engine::AnalyticPass screen = [&] {
        const AnalyticPathFor path(AnalyticPath::Screen);
        return engine::runAnalyticPass(scene, camera, mode, camera.viewport, 2);
      }();
      const std::string what =
          scene.name + " " + hardCase.convention() + " " + std::to_string(size.width) + "x" +
          std::to_string(size.height) + (camera.clipPlanes.empty() ? "" : " clipped") +
          (scene.depthClamp ? " depth clamp" : "") + (camera.logarithmicDepth ? " log depth" : "");
      ASSERT_FALSE(rays.frame.planesById) << what;
      evaluated += screen.screen.used ? 1 : 0;
      // Where the compare goes along the ray for a pixel decided from planes, it gets the ray
      // path's hit bit for bit: along its group's ray, t given along the frame's.
      const PrimitiveClipPlanes objectPlanes(scene);
      for (const testing::PlanePixel& pixel :
           testing::planePixelsAsTheRayPathHitsThem(screen, rays, objectPlanes, what)) {
        ++rayPathHits;
        ownPlaneHits += objectPlanes.of(pixel.hit.primitiveId).empty() ? 0 : 1;
      }
      const double toWindow = 1.0 / (1.0 - mode.clipVolumeMinZ());
      testing::drawInEveryDepthFormat(
          renderer(), rays, runs, [&](DepthFormat format, const auto& compare) {
            double runDepthQuanta = 0.0;  // the plane pixels' depths apart, in quanta
            const engine::ComparedRun byRays = compare(rays);
            const engine::ComparedRun byScreen = compare(screen);
            const std::string run = what + " " + depthFormatName(format);
            const nlohmann::json a = entryOf(byRays.run);
            const nlohmann::json b = entryOf(byScreen.run);
            const nlohmann::json patch = nlohmann::json::diff(withoutFigures(a), withoutFigures(b));
            EXPECT_TRUE(patch.empty()) << run << ": the screen path's entry differs by " << patch;
            ASSERT_EQ(byRays.pixels.classes.size(), byScreen.pixels.classes.size()) << run;
            for (std::size_t i = 0; i < byRays.pixels.classes.size(); ++i) {
              ASSERT_EQ(byRays.pixels.classes[i], byScreen.pixels.classes[i])
                  << run << ", pixel " << i % camera.viewport.width << ","
                  << i / camera.viewport.width;
              const Hit& hit = screen.frame.hits[i];
              if (!screen.frame.planesById || !hit.hit() || !std::isnan(hit.t)) continue;
              ++fromPlanes;
              const double depthA = byRays.pixels.analyticDepth[i];
              const double depthB = byScreen.pixels.analyticDepth[i];
              if (std::isnan(depthA) || std::isnan(depthB)) continue;
              ++compared;
              const TrianglePlanes& planes = (*screen.frame.planesById)[hit.primitiveId];
              double bound = planes.depthError * toWindow;
              if (screen.logDepth) {
                // The ray path's w within twice the plane's bound of 1 / w (reachOver's claim).
                const Viewport viewport = camera.viewport;
                const glm::dvec2 ndc =
                    clipXYOfPixelCentre(static_cast<int>(i % viewport.width),
                                        static_cast<int>(i / viewport.width), viewport);
                const double reciprocalW = planes.ra * ndc.x + (planes.rb * ndc.y + planes.rc);
                const auto reach =
                    screen.logDepth->reachOver(reciprocalW, 2.0 * planes.reciprocalWError, depthB);
                if (!reach) {
                  // No reach: the compare went along the ray, the ray path's depth.
                  EXPECT_EQ(depthA, depthB) << run << ", pixel " << i;
                  continue;
                }
                bound = reach->depth;
                ++logFromPlanes;
              }
              groupsFromPlanes += ownState ? 1 : 0;
              // The compare's quantum: at least the smallest normal float.
              const double quantum =
                  std::max(depthQuantum(format, depthA), double{std::numeric_limits<float>::min()});
              runDepthQuanta = std::max(runDepthQuanta, std::abs(depthA - depthB) / quantum);
              worstDepth = std::max(worstDepth, std::abs(depthA - depthB));
              worstDepthOverBound =
                  std::max(worstDepthOverBound, std::abs(depthA - depthB) / bound);
            }
            std::vector<std::pair<std::string, double>> figuresA, figuresB;
            collectFigures(a, "", figuresA);
            collectFigures(b, "", figuresB);
            // The entries' shapes are equal (above): the figures pair up in order.
            ASSERT_EQ(figuresA.size(), figuresB.size()) << run;
            for (std::size_t k = 0; k < figuresA.size(); ++k) {
              const std::string& at = figuresA[k].first;
              const double x = figuresA[k].second, y = figuresB[k].second;
              // A quantile or mean of the errors in quanta moves by at most the largest move of a
              // pixel's: its depths' difference in quanta. Every figure is a ratio of quantities
              // of one scale, rounded far finer than 2^-40 (a parallel camera's distance figure is
              // 10^-17 where the raster holds the exact depth: rounding, on either path). What
              // lies beyond that counts.
              const double explained = std::max(
                  at.find("depth_error_quanta") != std::string::npos ? runDepthQuanta : 0.0,
                  0x1p-40);
              const double apart = std::max(0.0, std::abs(x - y) - explained) /
                                   std::max({std::abs(x), std::abs(y), 1e-300});
              if (apart > worstFigure) {
                worstFigure = apart;
                worstFigureAt = run + " " + at;
              }
            }
          });
    }
  }
  std::cout << runs << " runs (" << clipped << " scene cameras with a clip plane, " << clamped
            << " with depth clamp, " << logDepth << " with a logarithmic depth, " << logFromPlanes
            << " of its pixels compared from planes, " << grouped
            << " with an object drawn with state of its own, " << groupsFromPlanes
            << " of their pixels decided from planes), " << evaluated
            << " scene cameras on the screen path; " << fromPlanes
            << " pixels decided from planes, " << compared
            << " with depths on both sides: the depths apart by at most " << worstDepth << " ("
            << worstDepthOverBound << " of the planes' bound); the report's figures apart by "
            << worstFigure << " of themselves at most (" << worstFigureAt << ")\n";
  EXPECT_GT(evaluated * 4, runs);  // three runs per scene camera: most cameras on planes
  EXPECT_GT(compared, 10000);
  EXPECT_GT(logFromPlanes, 1000);
  EXPECT_GT(groupsFromPlanes, 1000);
  std::cout << rayPathHits << " plane pixels' ray path hits through PlanePixelHits, "
            << ownPlaneHits
            << " of them along an object's own rays: each the ray path's bit for bit\n";
  // One size under AddressSanitizer: a handful there.
  EXPECT_GT(ownPlaneHits, testing::kUnderAddressSanitizer ? 0 : 500);
  // The ray path's depth lies far closer to the exact crossing than the planes' bound (the
  // bound's worst case stacks every rounding): both depths within it of each other.
  EXPECT_LE(worstDepthOverBound, 1.0);
  // Figures are differences of nearly equal depths (error over tolerance or quantum, distances
  // apart): their relative change is the depths' difference over the error, well below 1% here.
  EXPECT_LT(worstFigure, 0.01) << worstFigureAt;
}

}  // namespace
}  // namespace clipray
