// reconcile --page's toggled run without a browser: the rule that decides where the page allows
// the toggle (PageToggle.hpp), the check that the toggle took, and the report of a toggled run:
// the JSON's "toggled" and "overall", the text's lines, index.html and picks.png (PageHtml.hpp).

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "clipray/page/PageHtml.hpp"
#include "clipray/page/PageReconcile.hpp"
#include "clipray/page/PageToggle.hpp"

namespace clipray::page {
namespace {

nlohmann::json facts(bool setReversed, bool clipControl, bool logarithmic) {
  return {{"setReversed", setReversed},
          {"clipControl", clipControl},
          {"logarithmicDepthBuffer", logarithmic}};
}

TEST(PageToggle, TheRuleRefusesWhatThreeJsWouldNotMake) {
  EXPECT_EQ(toggleRefusal(facts(true, true, false), false), "");
  EXPECT_EQ(toggleRefusal(facts(true, true, false), true), "");
  // Turning a reversed depth buffer off needs no extension.
  EXPECT_EQ(toggleRefusal(facts(true, false, false), true), "");
  EXPECT_EQ(toggleRefusal(facts(true, false, false), false),
            "the page's WebGL context has no EXT_clip_control (three.js ignores "
            "reversedDepthBuffer without it)");
  EXPECT_EQ(toggleRefusal(facts(false, true, false), false),
            "the page's three.js has no reversed depth buffer (WebGLRenderer's depth state has no "
            "setReversed; three.js r169 added it)");
  EXPECT_EQ(toggleRefusal(nlohmann::json(), false),
            toggleRefusal(facts(false, true, false), false));
  EXPECT_EQ(
      toggleRefusal(facts(true, true, true), false),
      "the page uses a logarithmic depth buffer (three.js turns it off under a reversed depth "
      "buffer: the toggled page would not be one three.js makes)");
}

TEST(PageToggle, TheToggledLoadMustHaveFlippedTheRenderer) {
  const nlohmann::json flipped = {{"toggled", {{{"from", false}, {"to", true}}}}};
  EXPECT_EQ(toggleFailure(flipped, true, true), "");
  EXPECT_EQ(toggleFailure(flipped, false, true),
            "the page's renderer drew with reversedDepthBuffer off after the toggle (the page "
            "sets it itself)");
  EXPECT_EQ(toggleFailure({{"toggled", nlohmann::json::array()}}, true, true),
            "no renderer was toggled (none announced itself to __THREE_DEVTOOLS__)");
  const nlohmann::json refused = {
      {"toggled", {{{"from", false}, {"to", false}, {"failure", "no EXT_clip_control"}}}}};
  EXPECT_EQ(toggleFailure(refused, false, true),
            "the renderer could not be toggled (no EXT_clip_control)");
}

// A 2x1 grid: one agreeing pick on a surface, one raster-only.
PageReconcileResult twoPicks(bool reversed) {
  PageReconcileResult r;
  r.check.page = "page.html";
  r.revision = "187";
  r.canvas = "canvas#view";
  r.width = 2;
  r.height = 1;
  r.columns = 2;
  r.rows = 1;
  r.camera = {{"type", "PerspectiveCamera"}, {"near", 0.1}, {"far", 100.0}};
  r.reversedDepthBuffer = reversed;
  r.clipDepth = reversed ? "zero-to-one" : "negative-one-to-one";
  r.clearDepth = reversed ? 0.0 : 1.0;
  r.depthFormat = "GL_DEPTH24_STENCIL8";
  PagePick agree;
  agree.hit = agree.surface = true;
  agree.rayDepth = agree.bufferDepth = 0.5;
  agree.tolerance = 1e-6;
  agree.object = "Box <1>";
  PagePick rasterOnly;
  rasterOnly.x = 1;
  rasterOnly.kind = PagePick::Kind::RasterOnly;
  rasterOnly.surface = true;
  rasterOnly.bufferDepth = 0.25;
  r.picks = {agree, rasterOnly};
  return r;
}

TEST(PageToggle, TheReportCarriesTheToggledRunBesideThePage) {
  PageReconcileResult r = twoPicks(false);
  r.picks.pop_back();
  r.columns = 1;
  r.toggle.run = std::make_shared<PageReconcileResult>(twoPicks(true));
  EXPECT_TRUE(r.consistent());
  EXPECT_FALSE(r.allConsistent());
  const nlohmann::json report = pageReconcileJson(r);
  EXPECT_EQ(report["verdict"], "consistent");
  EXPECT_EQ(report["overall"], "inconsistent");
  EXPECT_EQ(report["toggled"]["made"], true);
  EXPECT_EQ(report["toggled"]["reversed_depth_buffer"], true);
  EXPECT_EQ(report["toggled"]["depth"]["clip_depth"], "zero-to-one");
  EXPECT_EQ(report["toggled"]["picks"]["raster_only"]["unexplained"], 1);
  EXPECT_EQ(report["toggled"]["verdict"], "inconsistent");
  const std::string text = pageReconcileText(r);
  EXPECT_NE(text.find("\ntoggled: reversedDepthBuffer on (the page: off), the page loaded again "
                      "with its renderer's depth buffer flipped before its first frame\n"
                      "  depth: clip zero-to-one, reversedDepthBuffer on, cleared to 0"),
            std::string::npos)
      << text;
  EXPECT_TRUE(text.ends_with("\noverall: inconsistent (the page as it is and toggled)\n")) << text;

  const std::string html = pageReconcileHtml(r, true);
  EXPECT_NE(html.find("<p id=\"verdict\" class=\"verdict inconsistent\">inconsistent: the page as "
                      "it is consistent, reversedDepthBuffer toggled on inconsistent</p>"),
            std::string::npos);
  EXPECT_NE(html.find("<tr class=\"run consistent\" data-run=\"page\">"), std::string::npos);
  EXPECT_NE(html.find("<tr class=\"run inconsistent\" data-run=\"toggled\">"), std::string::npos);
  EXPECT_NE(html.find("src=\"picks-toggled.png\""), std::string::npos);
  EXPECT_NE(html.find("<tr data-x=\"1\" data-y=\"0\"><td class=\"figures\">1, 0</td><td>"
                      "raster-only</td><td>nothing</td>"),
            std::string::npos);
  EXPECT_EQ(pageReconcileHtml(r, false).find("picks.png"), std::string::npos);

  // picks.png: 2 x 1 picks of 8 x 8 pixels.
  const std::string png = pagePicksPng(*r.toggle.run);
  ASSERT_GT(png.size(), 24u);
  EXPECT_EQ(png.substr(1, 3), "PNG");
  EXPECT_EQ(static_cast<unsigned char>(png[19]), 16u);  // width
  EXPECT_EQ(static_cast<unsigned char>(png[23]), 8u);   // height
}

TEST(PageToggle, ARunNotMadeSaysWhy) {
  PageReconcileResult r = twoPicks(true);
  r.picks.pop_back();
  r.columns = 1;
  r.toggle.skipped = "--no-toggle";
  nlohmann::json report = pageReconcileJson(r);
  EXPECT_EQ(report["toggled"], nlohmann::json({{"made", false},
                                               {"reversed_depth_buffer", false},
                                               {"skipped", "--no-toggle"},
                                               {"verdict", nullptr}}));
  EXPECT_EQ(report["overall"], "consistent");
  EXPECT_TRUE(pageReconcileText(r).ends_with(
      "\ntoggled: reversedDepthBuffer off: not made (--no-toggle)\n"));

  r.toggle.skipped.clear();
  r.toggle.notApplicable = toggleRefusal(facts(true, true, true), true);
  report = pageReconcileJson(r);
  EXPECT_EQ(report["toggled"]["not_applicable"], r.toggle.notApplicable);
  EXPECT_EQ(report["toggled"]["verdict"], nullptr);
  EXPECT_EQ(report["overall"], "consistent");
  EXPECT_TRUE(pageReconcileText(r).ends_with(
      "\ntoggled: reversedDepthBuffer off: not applicable: the page uses a logarithmic depth "
      "buffer (three.js turns it off under a reversed depth buffer: the toggled page would not be "
      "one three.js makes)\n"));
  EXPECT_NE(pageReconcileHtml(r, true).find("<tr><th>reversedDepthBuffer toggled off</th><td>not "
                                            "applicable: the page uses a logarithmic depth buffer"),
            std::string::npos);

  r.toggle.notApplicable.clear();
  r.toggle.failed = "page.html: never drew in 30 s (1 WebGL context)";
  EXPECT_FALSE(r.allConsistent());
  report = pageReconcileJson(r);
  EXPECT_EQ(report["toggled"]["failed"], r.toggle.failed);
  EXPECT_EQ(report["toggled"]["verdict"], "failed");
  EXPECT_EQ(report["overall"], "inconsistent");
  EXPECT_TRUE(pageReconcileText(r).ends_with(
      "\ntoggled: reversedDepthBuffer off: failed: page.html: never drew in 30 s (1 WebGL "
      "context)\noverall: inconsistent (the page as it is and toggled)\n"));
}

}  // namespace
}  // namespace clipray::page
