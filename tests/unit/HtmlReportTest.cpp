// index.html as text: what it shows, in which order, escaped. (tests/cli/ReportPageCliTest.cpp
// loads a real one in a browser.)

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "clipray/report/HtmlReport.hpp"

namespace clipray {
namespace {

using ::testing::HasSubstr;
using ::testing::Not;

RunRecord run(const std::string& camera, bool consistent) {
  RunRecord r;
  r.scene = "standard";
  r.camera = camera;
  r.convention = kZeroToOne;
  r.depthFormat = DepthFormat::Float32;
  r.vertexMode = VertexMode::World;
  r.size = {64, 48};
  r.metrics.pixels = 64 * 48;
  r.metrics.coverageMismatch = {3, 1, consistent ? 0 : 2};
  r.metrics.toleranceRatio = {consistent ? 0.125 : 4.0, 0.0625, 0.0625};
  return r;
}

GlInfo gl() {
  return {"osmesa", "Mesa", "llvmpipe (LLVM 15.0.6, 256 bits)", "4.5 (Core)", 8};
}

std::size_t occurrences(const std::string& text, const std::string& part) {
  std::size_t n = 0;
  for (std::size_t at = text.find(part); at != std::string::npos; at = text.find(part, at + 1)) ++n;
  return n;
}

TEST(HtmlReport, RowsWorstFirstWithClustersThumbnailsAndCrops) {
  RunRecord good = run("a<b", true);
  good.images = {{"standard/a_b-zo-32f-world/thumb_mismatch.png", ""},
                 {"standard/a_b-zo-32f-world/thumb_heatmap.png", ""}};
  RunRecord bad = run("main", false);
  bad.images = {{"standard/main-zo-32f-world/mismatch.png", ""},
                {"standard/main-zo-32f-world/thumb_mismatch.png", ""},
                {"standard/main-zo-32f-world/cluster1.png", ""}};
  bad.clusters.count = 7;
  bad.clusters.largest = {{2, 2, 0, 0, 10, 20, 11, 20, 10, 20}, {1, 0, 0, 1, 5, 0, 5, 0, 5, 0}};
  PixelHits wall;  // what each side hit at the clusters' pixels and at the worst pixel
  wall.x = 10;
  wall.y = 20;
  wall.pixelClass = PixelClass::CoverageUnexplained;
  wall.ray = {4, "far<wall", "triangle", 1, 0.75};
  PixelHits ball = wall;
  ball.x = 5;
  ball.y = 0;
  ball.pixelClass = PixelClass::IdUnexplained;
  ball.raster = {9, "ball", "sphere", -1, 0.5};
  bad.clusterHits = {wall, ball};
  bad.worstPixel = ball;
  const std::string html =
      reportHtml({good, bad}, gl(), {"clipray reconcile a.json --out r", "2026-11-25T05:00:00Z"});

  EXPECT_THAT(html, HasSubstr("<p id=\"verdict\" class=\"verdict inconsistent\">inconsistent: 2 "
                              "runs, 1 consistent, 1 inconsistent</p>"));
  EXPECT_THAT(html, HasSubstr("clipray reconcile a.json --out r"));
  EXPECT_THAT(html, HasSubstr("2026-11-25T05:00:00Z"));
  EXPECT_THAT(html, HasSubstr("llvmpipe (LLVM 15.0.6, 256 bits)"));
  // The inconsistent run first; names escaped.
  const std::size_t first = html.find(
      "<tr class=\"run inconsistent\" id=\"run-1\" "
      "data-run=\"standard/main-zo-32f-world\">");
  const std::size_t second = html.find(
      "<tr class=\"run consistent\" id=\"run-2\" "
      "data-run=\"standard/a_b-zo-32f-world\">");
  ASSERT_NE(first, std::string::npos) << html;
  ASSERT_NE(second, std::string::npos) << html;
  EXPECT_LT(first, second);
  EXPECT_THAT(html, HasSubstr("<td class=\"name\">standard/a&lt;b<br><span>zo 32f world "
                              "64x48</span></td>"));
  EXPECT_THAT(html, Not(HasSubstr("standard/a<b")));
  EXPECT_EQ(occurrences(html, "<tr class=\"run "), 2u);
  // Thumbnails at twice their size (a 64x48 frame's is 64x48), the mismatch one linking to the
  // full-size image where there is one.
  EXPECT_THAT(html, HasSubstr("<a href=\"standard/main-zo-32f-world/mismatch.png\"><img "
                              "class=\"thumb\" src=\"standard/main-zo-32f-world/"
                              "thumb_mismatch.png\" alt=\"standard/main zo 32f world: mismatch\" "
                              "width=\"128\" height=\"96\"></a>"));
  EXPECT_THAT(html, HasSubstr("<span title=\"no full-size image: clipray reconcile --images all "
                              "writes every run's\"><img class=\"thumb\" "
                              "src=\"standard/a_b-zo-32f-world/thumb_heatmap.png\""));
  // The legend comes before the runs whose thumbnails it explains.
  ASSERT_NE(html.find("id=\"legend-classes\""), std::string::npos);
  EXPECT_LT(html.find("id=\"legend-classes\""), html.find("<table id=\"runs\">"));
  // The clusters: both of the inconsistent run, in GL and image coordinates, the first with its
  // crop (a 32x32 window drawn 8x: 256 px).
  EXPECT_THAT(html, HasSubstr("<section class=\"clusters\" id=\"clusters-1\" "
                              "data-run=\"standard/main-zo-32f-world\">"));
  EXPECT_THAT(html, HasSubstr("standard/main zo 32f world: 7 clusters</h3>"));
  EXPECT_THAT(html, HasSubstr("<tr class=\"cluster\" data-pixels=\"2\" data-gl-x=\"10\" "
                              "data-gl-y=\"20\" data-image-x=\"10\" data-image-y=\"27\">"));
  EXPECT_THAT(html, HasSubstr("<tr class=\"cluster\" data-pixels=\"1\" data-gl-x=\"5\" "
                              "data-gl-y=\"0\" data-image-x=\"5\" data-image-y=\"47\">"));
  // The pixel and the bounds in GL window coordinates over image coordinates, one cell each.
  EXPECT_THAT(html, HasSubstr("<td class=\"figures\">(10, 20)<br>(10, 27)</td>"));
  EXPECT_THAT(html, HasSubstr("<td class=\"figures\">(10, 20) - (11, 20)<br>(10, 27) - (11, "
                              "27)</td>"));
  EXPECT_THAT(html, HasSubstr("<img class=\"crop\" src=\"standard/main-zo-32f-world/cluster1.png\" "
                              "alt=\"standard/main zo 32f world: cluster 1\" width=\"256\" "
                              "height=\"256\">"));
  EXPECT_EQ(occurrences(html, "<tr class=\"cluster\""), 2u);
  // Which side hit what: the worst pixel, and each cluster's pixel (names escaped).
  EXPECT_THAT(html, HasSubstr("<p class=\"worst-pixel\" data-gl-x=\"5\" data-gl-y=\"0\">Worst "
                              "pixel: GL window (5, 0) = image (5, 47): id_unexplained: raster "
                              "&quot;ball&quot; (sphere) at depth 0.5, ray &quot;far&lt;wall&quot; "
                              "triangle 1 at depth 0.75</p>"));
  EXPECT_THAT(html, HasSubstr("<th>class at the pixel</th><th>raster hit</th><th>ray hit</th>"));
  EXPECT_THAT(html, HasSubstr("<td class=\"figures\">coverage_unexplained</td><td "
                              "class=\"hit\">nothing</td><td class=\"hit\">&quot;far&lt;wall&quot; "
                              "triangle 1<br>depth 0.75</td>"));
  EXPECT_THAT(html, HasSubstr("<td class=\"figures\">id_unexplained</td><td "
                              "class=\"hit\">&quot;ball&quot; (sphere)<br>depth 0.5</td>"));
  EXPECT_EQ(occurrences(html, "<section class=\"clusters\""), 1u);
  EXPECT_THAT(html, Not(HasSubstr("no-images")));
  EXPECT_THAT(html, HasSubstr("<th>thumbnails: mismatch, error / tolerance</th>"));
  // Nothing from the network.
  EXPECT_THAT(html, Not(HasSubstr("http:")));
  EXPECT_THAT(html, Not(HasSubstr("https:")));
  EXPECT_THAT(html, Not(HasSubstr("<script")));
}

TEST(HtmlReport, DepthFiguresInUnitsOfTheToleranceOrNotAvailable) {
  RunRecord compared = run("compared", true);
  compared.metrics.depthCompared = 100;
  compared.metrics.distanceRelError = {3e-6, 1e-7, 2.5e-6};
  RunRecord none = run("none", true);  // depthCompared 0: the figures measured nothing
  const std::string html = reportHtml({compared, none}, gl());
  EXPECT_THAT(html, HasSubstr("<td class=\"figures\">tol 0.12/0.062<br>rel 2.5e-6</td>"));
  EXPECT_THAT(html, HasSubstr("<td class=\"figures\">n/a (0 compared)</td>"));
  EXPECT_THAT(html, Not(HasSubstr(">q ")));
}

TEST(HtmlReport, TheLegendHasEveryColour) {
  const std::string html = reportHtml({run("main", true)}, gl());
  for (const auto& [name, colour] : std::vector<std::pair<std::string, std::string>>{
           {"agree", "rgb(128,128,128)"},
           {"depth_beyond_tolerance", "rgb(255,140,0)"},
           {"coverage_edge_ambiguous", "rgb(255,230,0)"},
           {"coverage_unexplained", "rgb(255,0,0)"},
           {"id_depth_ambiguous", "rgb(0,255,255)"},
           {"id_edge_ambiguous", "rgb(60,110,255)"},
           {"id_unexplained", "rgb(255,0,255)"},
           {"background", "rgb(0,0,0)"}}) {
    EXPECT_THAT(html, HasSubstr("<tr data-class=\"" + name +
                                "\"><td><span class=\"swatch\" style=\"background:" + colour))
        << name;
  }
  // The heat-map bar: the ramp's stops at their decades (1e-4 at 0%, 1 at 80%), then red to white
  // up to 10.
  EXPECT_THAT(html, HasSubstr("linear-gradient(to right, rgb(68,1,84) 0%, rgb(59,82,139) 20%, "
                              "rgb(33,145,140) 40%, rgb(94,201,98) 60%, rgb(253,231,37) 80%, "
                              "rgb(230,0,0) 80%, rgb(255,255,255) 100%)"));
  EXPECT_THAT(html, HasSubstr("id=\"legend-depth\""));
  EXPECT_THAT(html, HasSubstr("rgb(20,30,70)"));
  EXPECT_THAT(html, HasSubstr("None: every run is consistent."));
}

TEST(HtmlReport, WithoutImagesThePageSaysSo) {
  RunRecord bad = run("main", false);
  bad.clusters.count = 1;
  bad.clusters.largest = {{2, 2, 0, 0, 10, 20, 11, 20, 10, 20}};
  const std::string html = reportHtml({bad}, gl());
  EXPECT_THAT(html, HasSubstr("<p class=\"note\" id=\"no-images\">No images"));
  EXPECT_THAT(html, Not(HasSubstr("<img")));
  EXPECT_THAT(html, Not(HasSubstr("<th>thumbnails")));
  EXPECT_THAT(html, Not(HasSubstr("<th>images</th>")));
  EXPECT_THAT(html, HasSubstr("data-gl-x=\"10\""));  // the clusters still are
  EXPECT_THAT(html, HasSubstr("<td>no image</td>"));
}

}  // namespace
}  // namespace clipray
