// The JUnit XML of clipray reconcile --junit: one test case per run, failures with their text.

#include <gtest/gtest.h>

#include "clipray/io/XmlText.hpp"
#include "clipray/report/JUnit.hpp"

namespace clipray {
namespace {

RunRecord run(const std::string& camera, bool consistent) {
  RunRecord r;
  r.scene = "a<b";
  r.camera = camera;
  r.convention = kZeroToOne;
  r.depthFormat = DepthFormat::Float32;
  r.vertexMode = VertexMode::World;
  r.size = {4, 2};
  r.metrics.pixels = 8;
  r.metrics.coverageMismatch = {3, 1, consistent ? 0 : 2};
  r.metrics.depthCompared = 5;
  r.metrics.depthBeyondTolerance = consistent ? 0 : 1;
  r.metrics.toleranceRatio = {consistent ? 0.5 : 4.0, 0.25, 0.5};
  r.timings = {1.0, 0.5, 0.25, 0.125, 0.125};  // 2 ms
  return r;
}

TEST(JUnit, OneTestCasePerRunAndTheFailuresText) {
  RunRecord bad = run("m\"1", false);
  bad.images = {{"a_b/m_1-zo-32f-world/mismatch.png", ""}};
  bad.clusters.count = 3;
  bad.clusters.largest = {{2, 2, 0, 0, 1, 0, 2, 0, 1, 0}, {1, 0, 0, 1, 3, 1, 3, 1, 3, 1}};
  PixelHits cover;  // what each side hit: at the first cluster's pixel and the worst pixel
  cover.x = 1;
  cover.pixelClass = PixelClass::CoverageUnexplained;
  cover.raster = {3, "wall", "triangle", 2, 0.5};
  PixelHits deep;
  deep.x = 3;
  deep.y = 1;
  deep.pixelClass = PixelClass::DepthBeyondTolerance;
  deep.raster = {9, "ball", "sphere", -1, 0.25};
  deep.ray = {9, "ball", "sphere", -1, 0.125};
  deep.toleranceRatio = 4.0;
  bad.clusterHits = {cover, deep};
  bad.worstPixel = cover;
  const std::string xml = junitXml({run("main", true), bad}, "out");
  EXPECT_EQ(xml,
            "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
            "<testsuites name=\"clipray reconcile\" tests=\"2\" failures=\"1\" errors=\"0\" "
            "time=\"0.004\">\n"
            "  <testsuite name=\"clipray reconcile\" tests=\"2\" failures=\"1\" errors=\"0\" "
            "time=\"0.004\">\n"
            "    <testcase classname=\"a&lt;b\" name=\"main zo 32f world\" time=\"0.002\"/>\n"
            "    <testcase classname=\"a&lt;b\" name=\"m&quot;1 zo 32f world\" time=\"0.002\">\n"
            "      <failure message=\"inconsistent\" type=\"inconsistent\">2 unexplained coverage "
            "mismatches, 0 unexplained id mismatches, 1 depths beyond tolerance (worst error / "
            "tolerance 4) of 8 pixels\n" +
                xmlEscaped(runSummaryLine(bad)) +
                "\nlargest unexplained clusters (2 of 3, 8-connected):"
                "\n  2 px at GL window (1, 0) = image (1, 1), GL bounds (1, 0) - (2, 0): "
                "coverage 2, id 0, depth 0"
                "\n  1 px at GL window (3, 1) = image (3, 0), GL bounds (3, 1) - (3, 1): "
                "coverage 0, id 0, depth 1"
                "\nwhich side hit what (GL window pixels):"
                "\n  worst pixel (1, 0): coverage_unexplained: raster &quot;wall&quot; triangle "
                "2 at depth 0.5, ray nothing"
                "\n  cluster 1 (2 px) at (1, 0): coverage_unexplained: raster &quot;wall&quot; "
                "triangle 2 at depth 0.5, ray nothing"
                "\n  cluster 2 (1 px) at (3, 1): depth_beyond_tolerance: raster &quot;ball&quot; "
                "(sphere) at depth 0.25, ray &quot;ball&quot; (sphere) at depth 0.125, "
                "error/tolerance 4"
                "\nimages: out/a_b/m_1-zo-32f-world/mismatch.png</failure>\n"
                "    </testcase>\n"
                "  </testsuite>\n"
                "</testsuites>\n");
  EXPECT_NE(xml.find("&gt;tol 1"), std::string::npos);  // the summary line's ">tol", escaped
}

TEST(JUnit, NoDepthsComparedIsSaid) {
  RunRecord bad = run("m", false);
  bad.metrics.depthCompared = 0;
  bad.metrics.depthBeyondTolerance = 0;
  bad.metrics.toleranceRatio = {};
  const std::string xml = junitXml({bad}, "out");
  EXPECT_NE(xml.find("0 depths beyond tolerance (no depths compared) of 8 pixels"),
            std::string::npos)
      << xml;
  EXPECT_NE(xml.find("depth n/a (0 compared)"), std::string::npos) << xml;
}

TEST(JUnit, NoRunsIsAnEmptySuite) {
  EXPECT_EQ(junitXml({}, "out"),
            "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
            "<testsuites name=\"clipray reconcile\" tests=\"0\" failures=\"0\" errors=\"0\" "
            "time=\"0.000\">\n"
            "  <testsuite name=\"clipray reconcile\" tests=\"0\" failures=\"0\" errors=\"0\" "
            "time=\"0.000\">\n"
            "  </testsuite>\n"
            "</testsuites>\n");
}

}  // namespace
}  // namespace clipray
