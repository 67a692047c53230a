// `clipray reconcile` with each run's convention check: the shipped scenes that demonstrate a
// NO-built matrix drawn under ZO declare it and stay green, with the note on their runs; the same
// scene without the declaration fails with the verdict convention-error and exit status 1.

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <fstream>
#include <string>

#include "support/RunCommand.hpp"

namespace clipray {
namespace {

using testing::runClipray;
using testing::TempFolder;

const std::string kSource = CLIPRAY_SOURCE_DIR;

// The summary line of the run named "<scene>/<camera> <convention> ..." in `out`.
std::string lineOf(const std::string& out, const std::string& sceneCamera,
                   const std::string& rest) {
  std::size_t at = 0;
  while ((at = out.find(sceneCamera + " ", at)) != std::string::npos) {
    const std::size_t start = out.rfind('\n', at) + 1;
    const std::string line = out.substr(start, out.find('\n', at) - start);
    std::string tail = line.substr(at - start + sceneCamera.size());
    tail.erase(0, tail.find_first_not_of(' '));
    if (tail.starts_with(rest)) return line;
    at += sceneCamera.size();
  }
  return "no line";
}

TEST(RunConventionCheckCli, TheShippedNoUnderZoRunsDeclareTheirMistakeAndStayGreen) {
  TempFolder folder;
  const auto result = runClipray(
      "reconcile '" + kSource + "/scenes/no_matrix_under_zo.json' '" + kSource +
          "/scenes/water_reflection.json' '" + kSource +
          "/scenes/water_reflection_clipped.json' --depth-formats 24 --size 64x48 --out out "
          "--junit junit.xml",
      folder.path());
  ASSERT_EQ(result.status, 0) << result.out << result.err;
  const std::string mismatch = " check error:depth-convention-mismatch (expected)";
  EXPECT_TRUE(lineOf(result.out, "no_matrix_under_zo/main", "zo ").starts_with("consistent "));
  EXPECT_TRUE(lineOf(result.out, "no_matrix_under_zo/main", "zo ").ends_with(mismatch))
      << result.out;
  // The plain NO projection of the clipped reflection, mirrored.
  EXPECT_TRUE(lineOf(result.out, "water_reflection_clipped/clipped_no", "zo ")
                  .ends_with(mismatch + ", warning:y-flipped (expected)"))
      << result.out;
  // Lengyel's oblique near plane reads as NO or ZO alike (clipray check: ambiguous), so drawn
  // under ZO it shows only its mirror.
  EXPECT_TRUE(lineOf(result.out, "water_reflection/reflection_no", "zo ")
                  .ends_with(" check warning:y-flipped (expected)"))
      << result.out;
  // Drawn under the convention it is built for, the matrix has nothing to say.
  EXPECT_EQ(lineOf(result.out, "no_matrix_under_zo/main", "no ").find(" check "), std::string::npos)
      << result.out;
  const auto report = nlohmann::json::parse(testing::readText(folder.path() / "out/report.json"));
  EXPECT_EQ(report["summary"]["verdict"], "consistent");
  EXPECT_EQ(report["summary"]["convention_error"], 0);
  int mismatches = 0;
  for (const auto& run : report["runs"]) {
    EXPECT_EQ(run["verdict"], "consistent") << run["scene"] << "/" << run["camera"];
    for (const auto& finding : run["convention_check"]) {
      EXPECT_EQ(finding["expected"], true);
      if (finding["code"] != "depth-convention-mismatch") continue;
      ++mismatches;
      // Each matrix drawn under the convention it is not built for.
      EXPECT_EQ(run["camera"] == "clipped_zo" ? "no" : "zo", run["convention"])
          << run["scene"] << "/" << run["camera"];
    }
  }
  EXPECT_EQ(mismatches, 3);  // no_matrix_under_zo/main, clipped_no and clipped_zo
  const std::string junit = testing::readText(folder.path() / "junit.xml");
  EXPECT_NE(junit.find("failures=\"0\""), std::string::npos);
  EXPECT_NE(junit.find("(expected by the scene)\n"), std::string::npos) << junit;
}

TEST(RunConventionCheckCli, AnUndeclaredMistakeIsAConventionErrorAndExitsOne) {
  TempFolder folder;
  // The shipped scene without its declaration.
  nlohmann::json scene =
      nlohmann::json::parse(testing::readText(kSource + "/scenes/no_matrix_under_zo.json"));
  ASSERT_TRUE(scene["cameras"][0].contains("expectedFindings"));
  scene["cameras"][0].erase("expectedFindings");
  std::ofstream(folder.path() / "undeclared.json") << scene.dump();
  const auto result = runClipray(
      "reconcile undeclared.json --depth-formats 24 --size 64x48 --out out --junit junit.xml",
      folder.path());
  ASSERT_EQ(result.status, 1) << result.out << result.err;
  const std::string zo = lineOf(result.out, "undeclared/main", "zo ");
  EXPECT_TRUE(zo.starts_with("CONVENTION-ERROR undeclared/main ")) << zo;
  EXPECT_TRUE(zo.ends_with(" check error:depth-convention-mismatch")) << zo;
  EXPECT_TRUE(lineOf(result.out, "undeclared/main", "no ").starts_with("consistent "))
      << result.out;
  EXPECT_NE(result.out.find("\n2 runs: 1 consistent, 0 inconsistent, 1 convention error\n"
                            "convention errors the scenes do not expect (clipray check on the "
                            "run's camera under the state it is drawn with):\n"
                            "  undeclared/main zo 24 world\n"
                            "    error [depth-convention-mismatch] built for NEGATIVE_ONE_TO_ONE "
                            "(near 1) but drawn under ZERO_TO_ONE: the rasterizer clips at z_ndc "
                            "= 0, so the effective near plane moves to 1.9802 (1.9802x) and NDC "
                            "[-1, 0), half the depth range, is never used (read as built for no: "
                            "the NO reading 1 +-7.5e-15 lies within its uncertainty of the round "
                            "number 1, the ZO reading 1.9802 +-1.5e-14 lies 0.019802 from the "
                            "nearest one, 2)\n"
                            "      fix: build the projection for ZO (glm::perspectiveRH_ZO; in any "
                            "engine, the depth row z replaced by (z + w) / 2) or draw with "
                            "glClipControl(GL_LOWER_LEFT, GL_NEGATIVE_ONE_TO_ONE)\n"),
            std::string::npos)
      << result.out;
  const auto report = nlohmann::json::parse(testing::readText(folder.path() / "out/report.json"));
  EXPECT_EQ(report["summary"]["verdict"], "convention-error");
  EXPECT_EQ(report["runs"][1]["verdict"], "convention-error");
  EXPECT_EQ(report["runs"][1]["convention_check"][0]["expected"], false);
  const std::string junit = testing::readText(folder.path() / "junit.xml");
  EXPECT_NE(junit.find("<failure message=\"convention error\" type=\"convention-error\">1 "
                       "convention error(s) the scene does not expect (raster and rays agree)\n"
                       "CONVENTION-ERROR undeclared/main zo"),
            std::string::npos)
      << junit;
  // index.html: the verdict and the finding's row under the run.
  const std::string html = testing::readText(folder.path() / "out/index.html");
  EXPECT_NE(html.find("<td class=\"verdict\">CONVENTION ERROR</td>"), std::string::npos);
  EXPECT_NE(
      html.find("<tr class=\"check\" data-for-run=\"undeclared/main-zo-24-world\"><td></td><td "
                "colspan=\"6\">convention check (clipray check on the camera under the "
                "run's state):<details data-code=\"depth-convention-mismatch\" "
                "open><summary><span class=\"error\">error "
                "[depth-convention-mismatch]</span></summary>built for NEGATIVE_ONE_TO_ONE "
                "(near 1"),
      std::string::npos)
      << html;
}

}  // namespace
}  // namespace clipray
