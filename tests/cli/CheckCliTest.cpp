// `clipray check` as a user meets it: exit statuses 0/1/2, text and JSON, files, bad flags.

#include <gtest/gtest.h>

#include <fstream>
#include <nlohmann/json.hpp>

#include "support/RunCommand.hpp"

namespace clipray {
namespace {

using testing::runClipray;
using testing::TempFolder;

// glm::perspectiveRH_NO(60 deg, 16/9, 0.1, 100) * lookAtRH((0,2,5), (0,0,0), (0,1,0)),
// column-major, printed with 9 significant digits as an app would log it.
const std::string kPerspectiveNo =
    "0.974278579 0 0 0 0 1.6081688 -0.372134201 -0.371390676 "
    "0 -0.643267521 -0.930335503 -0.928476691 0 -3.84592537e-16 5.19574572 5.38516481";

TEST(CheckCli, CleanMatrixExitsZero) {
  TempFolder folder;
  const auto result = runClipray(
      "check --clip-from-world '" + kPerspectiveNo + "' --declared-depth no", folder.path());
  EXPECT_EQ(result.status, 0) << result.err;
  EXPECT_NE(result.out.find("matrix: perspective, right-handed"), std::string::npos) << result.out;
  EXPECT_NE(result.out.find("built for: no (near 0.1 if NO, 0.1998 if ZO)"), std::string::npos)
      << result.out;
  EXPECT_NE(result.out.find("0 errors, 0 warnings, 0 notes"), std::string::npos) << result.out;
}

TEST(CheckCli, MismatchExitsOneWithJson) {
  TempFolder folder;
  const auto result = runClipray(
      "check --clip-from-world '" + kPerspectiveNo + "' --declared-depth zo --json", folder.path());
  EXPECT_EQ(result.status, 1) << result.err;
  const auto report = nlohmann::json::parse(result.out);
  EXPECT_EQ(report["verdict"], "errors");
  EXPECT_EQ(report["properties"]["built_for"], "no");
  EXPECT_EQ(report["properties"]["projection"], "perspective");
  ASSERT_EQ(report["findings"].size(), 1u);
  EXPECT_EQ(report["findings"][0]["code"], "depth-convention-mismatch");
  EXPECT_EQ(report["findings"][0]["severity"], "error");
  EXPECT_FALSE(report["findings"][0]["fix"].get<std::string>().empty());
}

TEST(CheckCli, StatedNearSettlesAnAmbiguousReading) {
  TempFolder folder;
  // glm::infinitePerspective(radians(60.0f), 1.5f, 0.1f) in float, printed with %.9g: near 0.1
  // if NO, 0.2 if ZO, both round.
  const std::string infinite = "1.1547004 0 0 0 0 1.73205066 0 0 0 0 -1 -1 0 0 -0.200000003 0";
  const auto ambiguous = runClipray(
      "check --clip-from-world '" + infinite + "' --declared-depth zo --json", folder.path());
  EXPECT_EQ(ambiguous.status, 0) << ambiguous.err;
  EXPECT_EQ(nlohmann::json::parse(ambiguous.out)["properties"]["built_for"], "ambiguous");
  const auto settled =
      runClipray("check --clip-from-world '" + infinite + "' --declared-depth zo --near 0.1 --json",
                 folder.path());
  EXPECT_EQ(settled.status, 1) << settled.err;
  const auto report = nlohmann::json::parse(settled.out);
  EXPECT_EQ(report["properties"]["built_for"], "no");
  EXPECT_EQ(report["properties"]["built_for_reason"], "the stated near plane, 0.1");
  EXPECT_EQ(report["properties"]["infinite_far"], true);
  EXPECT_EQ(report["properties"]["far"], nullptr);
  EXPECT_EQ(report["findings"][0]["code"], "depth-convention-mismatch");
  const auto wrong = runClipray(
      "check --clip-from-world '" + infinite + "' --declared-depth no --near 0.3", folder.path());
  EXPECT_EQ(wrong.status, 1);
  EXPECT_NE(wrong.out.find("error [near-plane-mismatch] the stated near plane 0.3 is neither "
                           "reading of the matrix (0.1 if built for NO, 0.2 if built for ZO)"),
            std::string::npos)
      << wrong.out;
}

// Names in any case, zo-reversed as the other commands take it, and a layout given wrongly.
TEST(CheckCli, DepthNamesInAnyCaseAndTheLayoutGivenWrongly) {
  TempFolder folder;
  const auto upper = runClipray(
      "check --clip-from-world '" + kPerspectiveNo + "' --declared-depth ZO --json", folder.path());
  EXPECT_EQ(upper.status, 1) << upper.err;
  EXPECT_EQ(nlohmann::json::parse(upper.out)["findings"][0]["code"], "depth-convention-mismatch");
  const auto reversed = runClipray(
      "check --clip-from-world '" + kPerspectiveNo + "' --declared-depth zo-reversed --json",
      folder.path());
  EXPECT_EQ(reversed.status, 1) << reversed.err;
  const auto report = nlohmann::json::parse(reversed.out);
  EXPECT_EQ(report["declared"]["depth"], "zo");
  EXPECT_EQ(report["declared"]["reversed"], true);
  const auto rowMajor = runClipray(
      "check --clip-from-world '" + kPerspectiveNo + "' --layout row-major --declared-depth no",
      folder.path());
  EXPECT_EQ(rowMajor.status, 1) << rowMajor.err;
  EXPECT_EQ(
      rowMajor.out.rfind(
          "matrix: no projection as given (its transpose is one); the camera is not read\n", 0),
      0u)
      << rowMajor.out;
  EXPECT_EQ(rowMajor.out.find("--layout row-major reads"), std::string::npos) << rowMajor.out;
}

TEST(CheckCli, ReadsTheSameFieldsFromAFile) {
  TempFolder folder;
  std::ofstream(folder.path() / "app.json")
      << R"({"clipFromWorld": ")" << kPerspectiveNo
      << R"(", "declaredDepth": "zo", "origin": "upper-left"})";
  const auto result = runClipray("check app.json --json", folder.path());
  EXPECT_EQ(result.status, 1) << result.err;
  const auto report = nlohmann::json::parse(result.out);
  EXPECT_EQ(report["findings"].size(), 2u);
  EXPECT_EQ(report["findings"][1]["code"], "window-origin-upper-left");
}

TEST(CheckCli, FileFieldsTakeTheSceneFormsToo) {
  TempFolder folder;
  std::ofstream(folder.path() / "app.json") << R"({"clipFromWorld": ")" << kPerspectiveNo
                                            << R"(", "viewport": [640, 480], "depthBits": 16})";
  const auto result = runClipray("check app.json --json", folder.path());
  EXPECT_EQ(result.status, 0) << result.err;
  const auto report = nlohmann::json::parse(result.out);
  EXPECT_EQ(report["declared"]["viewport"], nlohmann::json::array({640, 480}));
  EXPECT_EQ(report["declared"]["depth_bits"], "16");
}

TEST(CheckCli, AFileAndFieldOptionsTogetherAreRefused) {
  TempFolder folder;
  std::ofstream(folder.path() / "app.json")
      << R"({"clipFromWorld": ")" << kPerspectiveNo << R"("})";
  const auto result = runClipray("check app.json --declared-depth no", folder.path());
  EXPECT_EQ(result.status, 2);
  EXPECT_EQ(result.err, "clipray: app.json: give the fields in the file or as options, not both\n");
}

// --depth-clamp and the file's depthClamp: the declared state and the note; a file's value must
// be a boolean, and a trace brings its own depth clamp.
TEST(CheckCli, DepthClampFromTheCommandLineOrAFile) {
  TempFolder folder;
  const auto flagged = runClipray(
      "check --clip-from-world '" + kPerspectiveNo + "' --depth-clamp --json", folder.path());
  EXPECT_EQ(flagged.status, 0) << flagged.err;
  const auto report = nlohmann::json::parse(flagged.out);
  EXPECT_EQ(report["declared"]["depth_clamp"], true);
  ASSERT_EQ(report["findings"].size(), 2u);
  EXPECT_EQ(report["findings"][1]["code"], "depth-clamp-near-plane");
  EXPECT_EQ(report["findings"][1]["severity"], "info");
  std::ofstream(folder.path() / "app.json")
      << R"({"clipFromWorld": ")" << kPerspectiveNo << R"(", "depthClamp": true})";
  const auto filed = runClipray("check app.json --json", folder.path());
  EXPECT_EQ(filed.status, 0) << filed.err;
  EXPECT_EQ(nlohmann::json::parse(filed.out)["findings"][1]["message"],
            report["findings"][1]["message"]);
  std::ofstream(folder.path() / "bad.json")
      << R"({"clipFromWorld": ")" << kPerspectiveNo << R"(", "depthClamp": 1})";
  const auto bad = runClipray("check bad.json", folder.path());
  EXPECT_EQ(bad.status, 2);
  EXPECT_EQ(bad.err,
            "clipray: bad.json: /depthClamp: unknown key or wrong type (1); valid keys: "
            "clipFromWorld, projection, view, layout, declaredDepth, reversed, depthRange, origin, "
            "viewport, depthBits, sceneExtent, precision, near, far, cull, frontFace, depthClamp, "
            "comment\n");
  const auto traced = runClipray("check --trace app.trace --depth-clamp", folder.path());
  EXPECT_EQ(traced.status, 2);
  EXPECT_EQ(traced.err,
            "clipray: --trace: the depth state and matrices come from the trace; give no check "
            "file or field options with it\n");
}

struct BadCheck {
  const char* name;
  std::string arguments;
  std::string expected;
};
void PrintTo(const BadCheck& bad, std::ostream* os) {
  *os << bad.name;
}

class CheckBadInput : public ::testing::TestWithParam<BadCheck> {};

TEST_P(CheckBadInput, ExitsTwoWithAMessage) {
  TempFolder folder;
  const auto result = runClipray(GetParam().arguments, folder.path());
  EXPECT_EQ(result.status, 2);
  EXPECT_EQ(result.err, "clipray: " + GetParam().expected + "\n");
  EXPECT_TRUE(result.out.empty());
}

INSTANTIATE_TEST_SUITE_P(
    Messages, CheckBadInput,
    ::testing::Values(
        BadCheck{
            "NoMatrix", "check --declared-depth zo",
            "give the matrix: --clip-from-world \"16 numbers\", or --projection (with --view)"},
        BadCheck{"WrongCount", "check --clip-from-world '1 2 3'",
                 "--clip-from-world: expected 16 numbers, got 3"},
        BadCheck{"NotANumber", "check --clip-from-world '1 2 x'",
                 "--clip-from-world: \"x\" is not a number"},
        BadCheck{"NaN", "check --clip-from-world 'nan 0 0 0 0 1 0 0 0 0 1 0 0 0 0 1'",
                 "--clip-from-world: number 1 is nan; expected finite numbers"},
        BadCheck{"AllZero", "check --clip-from-world '0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0'",
                 "--clip-from-world: the matrix is all zero"},
        BadCheck{"NonProjective", "check --clip-from-world '1 0 0 0 0 1 0 0 0 0 1 0 0 0 0 0'",
                 "--clip-from-world: row 3 (w) is all zero: not a projection (every point would "
                 "have w = 0)"},
        BadCheck{"BothForms",
                 "check --clip-from-world '" + kPerspectiveNo + "' --projection '" +
                     kPerspectiveNo + "'",
                 "--clip-from-world and --projection are exclusive: give one"},
        BadCheck{"ViewWithoutProjection",
                 "check --clip-from-world '" + kPerspectiveNo + "' --view '" + kPerspectiveNo + "'",
                 "--view needs --projection (for a combined matrix use --clip-from-world alone)"},
        BadCheck{"UnknownLayout",
                 "check --clip-from-world '" + kPerspectiveNo + "' --layout diagonal",
                 "--layout: unknown value \"diagonal\"; expected one of: column-major, row-major, "
                 "xmmatrix"},
        BadCheck{"UnknownPrecision",
                 "check --clip-from-world '" + kPerspectiveNo + "' --precision half",
                 "--precision: unknown value \"half\"; expected one of: float, double"},
        BadCheck{"NearNotANumber",
                 "check --clip-from-world '" + kPerspectiveNo + "' --near 0.1,0.2",
                 "--near: expected one finite number, got \"0.1,0.2\""},
        BadCheck{"FarNotBeyondNear",
                 "check --clip-from-world '" + kPerspectiveNo + "' --near 1 --far 0.5",
                 "--far: expected a number greater than --near (1), got 0.5"},
        BadCheck{"UnknownDepth",
                 "check --clip-from-world '" + kPerspectiveNo + "' --declared-depth zero",
                 "--declared-depth: unknown value \"zero\"; expected one of: no, zo, zo-reversed"},
        BadCheck{"BadDepthRange",
                 "check --clip-from-world '" + kPerspectiveNo + "' --depth-range 0,2",
                 "--depth-range: expected NEAR,FAR in [0, 1], got \"0,2\""},
        BadCheck{"EqualDepthRange",
                 "check --clip-from-world '" + kPerspectiveNo + "' --depth-range 0.5,0.5",
                 "--depth-range: near and far are both 0.5; every depth would be equal"},
        BadCheck{"BadExtent",
                 "check --clip-from-world '" + kPerspectiveNo + "' --scene-extent '1 1 1 0 0 0'",
                 "--scene-extent: expected \"minx miny minz maxx maxy maxz\", finite, min <= max, "
                 "got \"1 1 1 0 0 0\""},
        BadCheck{"NanExtent",
                 "check --clip-from-world '" + kPerspectiveNo + "' --scene-extent 'nan 0 0 1 1 1'",
                 "--scene-extent: expected \"minx miny minz maxx maxy maxz\", finite, min <= max, "
                 "got \"nan 0 0 1 1 1\""},
        BadCheck{"NanDepthRange",
                 "check --clip-from-world '" + kPerspectiveNo + "' --depth-range nan,1",
                 "--depth-range: expected NEAR,FAR in [0, 1], got \"nan,1\""},
        BadCheck{"Overflow",
                 "check --clip-from-world '1e300 0 0 0 0 1e300 0 0 0 0 -1 -1 0 0 -0.2 0'",
                 "--clip-from-world: element (row 0, column 0) is 1e+300, beyond float range: a GL "
                 "uniform cannot hold it"},
        BadCheck{"MissingFile", "check nope.json", "nope.json: cannot open file"}),
    [](const ::testing::TestParamInfo<BadCheck>& param) { return std::string(param.param.name); });

}  // namespace
}  // namespace clipray
