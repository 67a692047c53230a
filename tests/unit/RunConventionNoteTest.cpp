// Each reconcile run carries its camera's convention check (engine/RunConventionCheck): the
// verdict it gives, and how the summary, report.json, its reading back and JUnit show it; the
// scene key that declares a finding expected, and its errors. (The check on real runs: the GL
// suite's RunConventionCheckTest and the CLI's ReconcileCliTest.)

#include <algorithm>
#include <fstream>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "clipray/SceneBuilder.hpp"
#include "clipray/io/XmlText.hpp"
#include "clipray/report/JUnit.hpp"
#include "clipray/report/ReportReading.hpp"
#include "clipray/scene/ExpectedFindings.hpp"
#include "clipray/scene/Scene.hpp"
#include "support/ReportSamples.hpp"
#include "support/SceneText.hpp"

namespace clipray {
namespace {

const RunFinding kNoUnderZo{"error", "depth-convention-mismatch",
                            "built for NEGATIVE_ONE_TO_ONE but drawn under ZERO_TO_ONE",
                            "build the projection for ZO", false};
const RunFinding kFlipped{"warning", "y-flipped", "the projection flips y", "", false};

// sampleRun with its pixels explained: raster and rays agree.
RunRecord agreeingRun(std::vector<RunFinding> findings) {
  RunRecord run = testing::sampleRun();
  run.metrics.coverageMismatch.unexplained = 0;
  run.conventionFindings = std::move(findings);
  return run;
}

RunFinding expected(RunFinding finding) {
  finding.expected = true;
  return finding;
}

TEST(RunConventionNote, AnUnexpectedErrorIsItsOwnVerdictAndAMismatchComesFirst) {
  EXPECT_EQ(runVerdict(agreeingRun({})), RunVerdict::Consistent);
  EXPECT_EQ(runVerdict(agreeingRun({kFlipped})), RunVerdict::Consistent);
  EXPECT_EQ(runVerdict(agreeingRun({expected(kNoUnderZo)})), RunVerdict::Consistent);
  EXPECT_EQ(runVerdict(agreeingRun({kNoUnderZo})), RunVerdict::ConventionError);
  EXPECT_FALSE(runPasses(agreeingRun({kNoUnderZo})));
  RunRecord both = testing::sampleRun();  // 2 unexplained coverage mismatches
  both.conventionFindings = {kNoUnderZo};
  EXPECT_EQ(runVerdict(both), RunVerdict::Inconsistent);
  EXPECT_STREQ(runVerdictName(RunVerdict::ConventionError), "convention-error");
}

TEST(RunConventionNote, TheSummaryLineEndsWithTheNoteAndTheTotalsCountConventionErrors) {
  RunRecord declared = agreeingRun({expected(kNoUnderZo), kFlipped});
  declared.camera = "declared";
  RunRecord undeclared = agreeingRun({kNoUnderZo});
  undeclared.camera = "undeclared";
  RunRecord clean = agreeingRun({});
  EXPECT_EQ(conventionNoteText(declared),
            "check error:depth-convention-mismatch (expected), warning:y-flipped");
  EXPECT_EQ(conventionNoteText(clean), "");
  const std::string summary = textSummary({clean, declared, undeclared});
  EXPECT_EQ(summary,
            "verdict          scene/camera        convention fmt vertex mode size    mismatches "
            "and depth error\n"
            "CONVENTION-ERROR standard/undeclared zo         24  world       640x480 cov 12 (e10 "
            "u0) id 3 (z2 e1 u0) >tol 0 tol 0.75/0.5 rel 2.1e-7 check "
            "error:depth-convention-mismatch\n"
            "consistent       standard/main       zo         24  world       640x480 cov 12 (e10 "
            "u0) id 3 (z2 e1 u0) >tol 0 tol 0.75/0.5 rel 2.1e-7\n"
            "consistent       standard/declared   zo         24  world       640x480 cov 12 (e10 "
            "u0) id 3 (z2 e1 u0) >tol 0 tol 0.75/0.5 rel 2.1e-7 check "
            "error:depth-convention-mismatch (expected), warning:y-flipped\n"
            "3 runs: 2 consistent, 0 inconsistent, 1 convention error\n"
            "convention errors the scenes do not expect (clipray check on the run's camera under "
            "the state it is drawn with):\n"
            "  standard/undeclared zo 24 world\n"
            "    error [depth-convention-mismatch] built for NEGATIVE_ONE_TO_ONE but drawn under "
            "ZERO_TO_ONE\n"
            "      fix: build the projection for ZO\n"
            "  cov: coverage mismatches (e edge-ambiguous, u unexplained); >tol: depths beyond "
            "tolerance\n"
            "  id: id mismatches (z depth-ambiguous, e edge-ambiguous, u unexplained)\n"
            "  tol: depth error / predicted tolerance, max/p99 (above 1: beyond it); rel: p99 "
            "distance error / eye distance\n"
            "  n/a (0 compared): no pixel where both sides hit the same primitive\n"
            "  check: clipray check on the run's camera under the state it is drawn with, its "
            "errors and warnings (expected: the scene declares it, expectedFindings); an error "
            "the scene does not expect is the verdict CONVENTION-ERROR\n");
}

TEST(RunConventionNote, ReportJsonHasTheFindingsAndTheVerdictAndReadsBack) {
  const RunRecord undeclared = agreeingRun({kNoUnderZo, expected(kFlipped)});
  const nlohmann::json json = reportJson({undeclared, agreeingRun({})}, testing::sampleGl());
  const nlohmann::json& run = json["runs"][0];
  EXPECT_EQ(run["verdict"], "convention-error");
  EXPECT_EQ(run["convention_check"].dump(),
            R"([{"code":"depth-convention-mismatch","expected":false,"fix":"build the projection )"
            R"(for ZO","message":"built for NEGATIVE_ONE_TO_ONE but drawn under ZERO_TO_ONE",)"
            R"("severity":"error"},{"code":"y-flipped","expected":true,"fix":"","message":"the )"
            R"(projection flips y","severity":"warning"}])");
  EXPECT_EQ(json["runs"][1]["convention_check"].dump(), "[]");
  EXPECT_EQ(json["summary"].dump(),
            R"({"consistent":1,"convention_error":1,"inconsistent":0,"runs":2,)"
            R"("verdict":"convention-error"})");

  const std::string text = json.dump(2);
  const ReadReport read = parseReport(text, ".", "report.json");
  ASSERT_EQ(read.runs.size(), 2u);
  EXPECT_EQ(read.runs[0].conventionFindings, undeclared.conventionFindings);
  EXPECT_EQ(runVerdict(read.runs[0]), RunVerdict::ConventionError);
  EXPECT_EQ(reportJson(read.runs, read.gl).dump(2), text);
}

TEST(RunConventionNote, ReadingRefusesAVerdictTheFindingsDoNotGiveAndABadFinding) {
  nlohmann::json json = reportJson({agreeingRun({kNoUnderZo})}, testing::sampleGl());
  json["runs"][0]["verdict"] = "consistent";
  const auto errorOf = [](const nlohmann::json& report) {
    try {
      parseReport(report.dump(), ".", "report.json");
    } catch (const InputError& error) {
      return std::string(error.what());
    }
    return std::string("no error");
  };
  EXPECT_EQ(errorOf(json),
            "report.json: /runs/0/verdict: \"consistent\" does not follow from the run's counts "
            "and convention check");
  json["runs"][0]["verdict"] = "convention-error";
  json["runs"][0]["convention_check"][0]["severity"] = "info";
  EXPECT_EQ(errorOf(json),
            "report.json: /runs/0/convention_check/0/severity: expected \"error\" or "
            "\"warning\", got \"info\"");
  // A report written before runs carried their check reads as having no findings.
  json["runs"][0].erase("convention_check");
  json["runs"][0]["verdict"] = "consistent";
  EXPECT_EQ(errorOf(json), "no error");
}

TEST(RunConventionNote, JUnitFailsAnUndeclaredErrorAndShowsExpectedFindings) {
  RunRecord undeclared = agreeingRun({kNoUnderZo});
  undeclared.camera = "undeclared";
  RunRecord declared = agreeingRun({expected(kNoUnderZo)});
  declared.camera = "declared";
  const std::string xml = junitXml({undeclared, declared}, "out");
  const std::string failure =
      "<failure message=\"convention error\" type=\"convention-error\">1 convention error(s) "
      "the scene does not expect (raster and rays agree)\n" +
      xmlEscaped(runSummaryLine(undeclared)) +
      "\nconvention check (clipray check on the camera under the run&apos;s state):\n"
      "  error [depth-convention-mismatch] built for NEGATIVE_ONE_TO_ONE but drawn under "
      "ZERO_TO_ONE\n"
      "    fix: build the projection for ZO\n"
      "</failure>";
  EXPECT_NE(xml.find(failure), std::string::npos) << xml;
  EXPECT_NE(xml.find("tests=\"2\" failures=\"1\""), std::string::npos) << xml;
  EXPECT_NE(xml.find("<testcase classname=\"standard\" name=\"declared zo 24 world\" "
                     "time=\"0.052\">\n      <system-out>convention check (clipray check on the "
                     "camera under the run&apos;s state):\n"
                     "  error [depth-convention-mismatch] built for NEGATIVE_ONE_TO_ONE but "
                     "drawn under ZERO_TO_ONE (expected by the scene)\n"
                     "    fix: build the projection for ZO\n"
                     "</system-out>"),
            std::string::npos)
      << xml;
}

// ------------------------------------------------------------------------------------------------
// The scene key

std::string withExpected(const std::string& value) {
  return testing::withCamera(R"({"name": "main", "viewport": [640, 480],
    "view": {"eye": [0, 0, 5], "target": [0, 0, 0], "up": [0, 1, 0]},
    "projection": {"type": "perspective", "fovYDegrees": 60, "near": 0.1, "far": 100},
    "expectedFindings": )" + value +
                             "}");
}

TEST(RunConventionNote, TheSceneKeyReadsCodesOfTheChecksErrorsAndWarnings) {
  const Scene scene =
      parseScene(withExpected(R"(["depth-convention-mismatch", "y-flipped"])"), testing::kFile);
  EXPECT_EQ(scene.cameras[0].expectedFindings,
            (std::vector<std::string>{"depth-convention-mismatch", "y-flipped"}));
  // On a raw clipFromWorld too.
  const Scene raw =
      parseScene(testing::withCamera(R"({"name": "main", "viewport": [4, 4], "clipFromWorld":
        [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, -1, -1, 0, 0, -0.2, 0], "expectedFindings": ["y-flipped"]})"),
                 testing::kFile);
  EXPECT_EQ(raw.cameras[0].expectedFindings, std::vector<std::string>{"y-flipped"});
  EXPECT_TRUE(parseScene(testing::withCamera(testing::kCamera), testing::kFile)
                  .cameras[0]
                  .expectedFindings.empty());
}

TEST(RunConventionNote, TheSceneKeysErrorsNameThePointerAndTheValue) {
  EXPECT_EQ(testing::errorOf(withExpected(R"("depth-convention-mismatch")")),
            "scenes/a.json: /cameras/0/expectedFindings: expected an array of clipray check "
            "finding codes (e.g. [\"depth-convention-mismatch\"]), got "
            "\"depth-convention-mismatch\"");
  EXPECT_EQ(testing::errorOf(withExpected("[3]")),
            "scenes/a.json: /cameras/0/expectedFindings/0: expected a string, got 3");
  EXPECT_EQ(testing::errorOf(withExpected(R"(["y-flipped", "depth-convention-ambiguous"])")),
            "scenes/a.json: /cameras/0/expectedFindings/1: expected the code of a clipray check "
            "error or warning (\"clear-depth-mismatch\", \"depth-convention-mismatch\", "
            "\"depth-range-reversed\", \"face-culling-keeps-insides\", \"far-plane-mismatch\", "
            "\"float-precision-risk\", \"infinite-far-plane\", \"likely-transposed\", "
            "\"near-plane-mismatch\", \"near-plane-precision\", \"reversed-z-mismatch\", "
            "\"reversed-z-without-zero-to-one\", \"y-flipped\"), got "
            "\"depth-convention-ambiguous\"");
  EXPECT_EQ(testing::errorOf(withExpected(R"(["y-flipped", "y-flipped"])")),
            "scenes/a.json: /cameras/0/expectedFindings/1: expected each code once, got "
            "\"y-flipped\" again");
}

TEST(RunConventionNote, SceneBuilderDeclaresFindingsOfTheCameraAddedLast) {
  const float positions[] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  const std::uint32_t indices[] = {0, 1, 2};
  SceneBuilder builder("level");
  builder.mesh("tri", positions, indices);
  try {
    builder.expectedFindings({"depth-convention-mismatch"});
    FAIL() << "no error";
  } catch (const InputError& error) {
    EXPECT_EQ(std::string(error.what()),
              "SceneBuilder \"level\": expectedFindings() applies to the camera added last, and "
              "no camera was added yet");
  }
  builder.camera("main", glm::dmat4(1.0), {4, 4}).expectedFindings({"depth-convention-mismatch"});
  EXPECT_EQ(builder.build().model().cameras[0].expectedFindings,
            std::vector<std::string>{"depth-convention-mismatch"});
  builder.expectedFindings({"no-such-code"});
  try {
    builder.build();
    FAIL() << "no error";
  } catch (const InputError& error) {
    EXPECT_TRUE(std::string(error.what())
                    .starts_with("SceneBuilder \"level\": /cameras/0/expectedFindings/0: expected "
                                 "the code of a clipray check error or warning ("))
        << error.what();
    EXPECT_TRUE(std::string(error.what()).ends_with("), got \"no-such-code\"")) << error.what();
  }
}

// Every error and warning docs/check.md lists (its Findings tables) can be declared, and nothing
// else: a finding added to the check and its docs is added to the scene key.
TEST(RunConventionNote, TheDeclarableCodesAreTheErrorsAndWarningsOfDocsCheck) {
  std::ifstream docs(std::string(CLIPRAY_SOURCE_DIR) + "/docs/check.md");
  ASSERT_TRUE(docs) << "docs/check.md";
  std::set<std::string> documented;
  std::string line;
  const auto trimmed = [](const std::string& cell) {
    const std::size_t first = cell.find_first_not_of(' ');
    return first == std::string::npos ? std::string()
                                      : cell.substr(first, cell.find_last_not_of(' ') - first + 1);
  };
  while (std::getline(docs, line)) {
    // | `code` | error | ..., | `code` | warning / info | ...
    std::vector<std::string> cells;
    std::stringstream row(line);
    for (std::string cell; std::getline(row, cell, '|');) cells.push_back(trimmed(cell));
    if (cells.size() < 3 || !cells[0].empty()) continue;
    const std::string& code = cells[1];
    const bool oneCode = code.size() > 2 && code.front() == '`' && code.back() == '`' &&
                         std::count(code.begin(), code.end(), '`') == 2;
    if (oneCode && (cells[2] == "error" || cells[2].starts_with("warning"))) {
      documented.insert(code.substr(1, code.size() - 2));
    }
  }
  // Findings only a trace can raise (what a program's shader text writes): a run's check never
  // sees them, so a scene cannot declare them.
  for (const char* traceOnly : {"clip-distance-not-enabled", "polygon-offset-toward-camera"}) {
    EXPECT_EQ(documented.erase(traceOnly), 1u) << traceOnly;
  }
  const std::set<std::string> declarable(kDeclarableFindingCodes.begin(),
                                         kDeclarableFindingCodes.end());
  EXPECT_EQ(declarable, documented);
}

}  // namespace
}  // namespace clipray
