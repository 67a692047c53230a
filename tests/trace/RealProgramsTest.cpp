// `clipray check --trace` on recordings of unmodified Debian 12 programs (OpenSCAD 2021.01,
// OpenSceneGraph 3.6.5's osgviewer and 11 examples, glmark2 2023.01, f3d 1.3.1 on VTK 9.1,
// MeshLab 2020.09, Stellarium 0.22.2) drawn with Mesa's llvmpipe under Xvfb:
// tests/data/trace/real/*.dump.txt, their `apitrace dump` listings trimmed to the first frames and
// to the calls that can change a reading (record.sh re-records them and checks that the trimmed
// listing reads as the whole trace does). The clipray binary reads each listing through
// tests/data/trace/real/apitrace-cat.sh standing in for apitrace (CLIPRAY_APITRACE), so neither the
// programs nor apitrace are needed here. Pinned per program: the counts, each group's source,
// draws, matrices, reading (projection, convention, near, far, fov and their ranges) and findings,
// and the trace-wide findings. Every one of these programs draws correctly: none may read with an
// error.

#include <gtest/gtest.h>

#include <cstdio>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "support/RunCommand.hpp"

namespace clipray {
namespace {

using testing::runClipray;
using testing::TempFolder;

const std::string kRecorded = std::string(CLIPRAY_SOURCE_DIR) + "/tests/data/trace/real/";

// A number as the text report prints it (6 digits); "none" for null.
std::string number(const nlohmann::json& value) {
  if (value.is_null()) return "none";
  char text[32];
  std::snprintf(text, sizeof text, "%.6g", value.get<double>());
  return text;
}

std::string joined(const std::vector<std::string>& parts, const std::string& separator) {
  std::string text;
  for (const std::string& part : parts) text += (text.empty() ? "" : separator) + part;
  return text;
}

std::vector<std::string> codes(const nlohmann::json& findings) {
  std::vector<std::string> result;
  for (const auto& f : findings) {
    result.push_back(f["severity"].get<std::string>() + ":" + f["code"].get<std::string>());
  }
  return result;
}

// "min..max" of a group's range, or the one value.
std::string range(const nlohmann::json& ranges, const std::string& key) {
  if (!ranges.contains(key) || ranges[key].is_null()) return "none";
  const nlohmann::json& r = ranges[key];
  const std::string low = number(r["min"]), high = number(r["max"]);
  return low == high ? low : low + ".." + high;
}

// One line per group: source, draws, matrices, depth test, then the reading and the findings
// (or why the group is not analysed).
std::string reading(const nlohmann::json& group) {
  std::string line = group["source"].get<std::string>() + ": " +
                     std::to_string(group["draws"].get<int>()) + " draws, " +
                     std::to_string(group["distinct_matrices"].get<int>()) + " matrices, " +
                     group["depth_state"]["depth_func"].get<std::string>() + "; ";
  if (group.contains("unusable"))
    return line + "not analysed: " + group["unusable"].get<std::string>();
  const nlohmann::json& p = group["properties"];
  line += p["projection"].get<std::string>() + ", built for " + p["built_for"].get<std::string>();
  if (group["distinct_matrices"].get<int>() > 1) {
    line += ", near " + range(group["ranges"], "near") + ", far " + range(group["ranges"], "far");
    if (p["projection"] == "perspective")
      line += ", fov " + range(group["ranges"], "fov_y_degrees");
  } else {
    line += ", near " + number(p.value("near", nlohmann::json())) + ", far " +
            number(p.value("far", nlohmann::json()));
    if (p["projection"] == "perspective") line += ", fov " + number(p["fov_y_degrees"]);
  }
  return line + "; [" + joined(codes(group["findings"]), ", ") + "]";
}

struct Recorded {
  int status = -1;
  std::string err;
  nlohmann::json report;
};

Recorded check(const std::string& name) {
  TempFolder folder;
  const auto result =
      runClipray("check --trace '" + kRecorded + name + ".dump.txt' --json", folder.path(),
                 "CLIPRAY_APITRACE='" + kRecorded + "apitrace-cat.sh'");
  Recorded recorded;
  recorded.status = result.status;
  recorded.err = result.err;
  if (result.status == 0 || result.status == 1) {
    recorded.report = nlohmann::json::parse(result.out);
  }
  return recorded;
}

struct Program {
  std::string name;
  // "F frames, D draws (P with a projection), N pairs in G groups, verdict V"
  std::string summary;
  std::vector<std::string> groups;
  std::vector<std::string> traceFindings;
};

std::string summary(const nlohmann::json& report) {
  return std::to_string(report["frames"]["read"].get<int>()) + " frames, " +
         std::to_string(report["draws"].get<int>()) + " draws (" +
         std::to_string(report["draws_with_projection"].get<int>()) + " with a projection), " +
         std::to_string(report["distinct_pairs"].get<int>()) + " pairs in " +
         std::to_string(report["groups"].size()) + " groups, verdict " +
         report["verdict"].get<std::string>();
}

void PrintTo(const Program& program, std::ostream* out) {
  *out << program.name;
}

// What each recording reads as: tests/data/trace/real/record.sh's programs, in its order.
const std::vector<Program> kPrograms = {
    {"openscad-render-ortho",
     "1 frames, 1 draws (1 with a projection), 1 pairs in 1 groups, verdict ok",
     {"fixed-function GL_PROJECTION: 1 draws, 1 matrices, GL_LESS; orthographic, built for "
      "ambiguous, near -4439.1, far 4439.1; [info:depth-convention-ambiguous]"},
     {}},
    {"openscad-render-persp",
     "1 frames, 1 draws (1 with a projection), 1 pairs in 1 groups, verdict ok",
     {"fixed-function GL_PROJECTION: 1 draws, 1 matrices, GL_LESS; perspective, built for "
      "ambiguous, near 4.4391, far 4439.1, fov 22.5; [info:depth-convention-ambiguous]"},
     {}},
    {"openscad-preview-ortho",
     "1 frames, 224 draws (224 with a projection), 8 pairs in 8 groups, verdict ok",
     {"fixed-function GL_PROJECTION: 6 draws, 1 matrices, GL_GREATER; orthographic, built for "
      "ambiguous, near -4439.1, far 4439.1; [info:depth-convention-ambiguous, "
      "info:multi-pass-far-surfaces]",
      "fixed-function GL_PROJECTION: 50 draws, 1 matrices, GL_LESS; orthographic, built for "
      "ambiguous, near -4439.1, far 4439.1; [info:depth-convention-ambiguous, "
      "info:multi-pass-over-far-surfaces]",
      "fixed-function GL_PROJECTION: 50 draws, 1 matrices, GL_GREATER; orthographic, built for "
      "ambiguous, near -4439.1, far 4439.1; [info:depth-convention-ambiguous, "
      "info:multi-pass-far-surfaces]",
      "fixed-function GL_PROJECTION: 6 draws, 1 matrices, GL_LESS; orthographic, built for "
      "ambiguous, near -4439.1, far 4439.1; [info:depth-convention-ambiguous, "
      "info:multi-pass-over-far-surfaces]",
      "fixed-function GL_PROJECTION: 6 draws, 1 matrices, GL_LESS; orthographic, built for "
      "ambiguous, near -4439.1, far 4439.1; [info:depth-convention-ambiguous, "
      "info:multi-pass-over-far-surfaces]",
      "fixed-function GL_PROJECTION: 50 draws, 1 matrices, GL_LESS; orthographic, built for "
      "ambiguous, near -4439.1, far 4439.1; [info:depth-convention-ambiguous, "
      "info:multi-pass-over-far-surfaces]",
      "fixed-function GL_PROJECTION: 6 draws, 1 matrices, GL_EQUAL; orthographic, built for "
      "ambiguous, near -4439.1, far 4439.1; [info:depth-convention-ambiguous, "
      "info:multi-pass-over-far-surfaces]",
      "fixed-function GL_PROJECTION: 50 draws, 1 matrices, GL_EQUAL; orthographic, built for "
      "ambiguous, near -4439.1, far 4439.1; [info:depth-convention-ambiguous, "
      "info:multi-pass-over-far-surfaces]"},
     {}},
    {"openscad-preview-persp",
     "1 frames, 224 draws (224 with a projection), 8 pairs in 8 groups, verdict ok",
     {"fixed-function GL_PROJECTION: 6 draws, 1 matrices, GL_GREATER; perspective, built for "
      "ambiguous, near 4.4391, far 4439.1, fov 22.5; [info:depth-convention-ambiguous, "
      "info:multi-pass-far-surfaces]",
      "fixed-function GL_PROJECTION: 50 draws, 1 matrices, GL_LESS; perspective, built for "
      "ambiguous, near 4.4391, far 4439.1, fov 22.5; [info:depth-convention-ambiguous, "
      "info:multi-pass-over-far-surfaces]",
      "fixed-function GL_PROJECTION: 50 draws, 1 matrices, GL_GREATER; perspective, built for "
      "ambiguous, near 4.4391, far 4439.1, fov 22.5; [info:depth-convention-ambiguous, "
      "info:multi-pass-far-surfaces]",
      "fixed-function GL_PROJECTION: 6 draws, 1 matrices, GL_LESS; perspective, built for "
      "ambiguous, near 4.4391, far 4439.1, fov 22.5; [info:depth-convention-ambiguous, "
      "info:multi-pass-over-far-surfaces]",
      "fixed-function GL_PROJECTION: 6 draws, 1 matrices, GL_LESS; perspective, built for "
      "ambiguous, near 4.4391, far 4439.1, fov 22.5; [info:depth-convention-ambiguous, "
      "info:multi-pass-over-far-surfaces]",
      "fixed-function GL_PROJECTION: 50 draws, 1 matrices, GL_LESS; perspective, built for "
      "ambiguous, near 4.4391, far 4439.1, fov 22.5; [info:depth-convention-ambiguous, "
      "info:multi-pass-over-far-surfaces]",
      "fixed-function GL_PROJECTION: 6 draws, 1 matrices, GL_EQUAL; perspective, built for "
      "ambiguous, near 4.4391, far 4439.1, fov 22.5; [info:depth-convention-ambiguous, "
      "info:multi-pass-over-far-surfaces]",
      "fixed-function GL_PROJECTION: 50 draws, 1 matrices, GL_EQUAL; perspective, built for "
      "ambiguous, near 4.4391, far 4439.1, fov 22.5; [info:depth-convention-ambiguous, "
      "info:multi-pass-over-far-surfaces]"},
     {}},
    {"osgviewer",
     "3 frames, 3 draws (3 with a projection), 1 pairs in 1 groups, verdict ok",
     {"fixed-function GL_PROJECTION: 3 draws, 1 matrices, GL_LESS; perspective, built for "
      "ambiguous, near 28.8278, far 40.2044, fov 29.1484; [info:depth-convention-ambiguous]"},
     {}},
    {"osghud",
     "3 frames, 54 draws (42 with a projection), 3 pairs in 3 groups, verdict ok",
     {"fixed-function GL_PROJECTION: 3 draws, 1 matrices, GL_LESS; perspective, built for "
      "ambiguous, near 28.8278, far 40.2044, fov 29.1484; [info:depth-convention-ambiguous]",
      "fixed-function GL_PROJECTION: 3 draws, 1 matrices, GL_LESS; orthographic, built for "
      "ambiguous, near -1, far 1.1; [info:depth-convention-ambiguous]",
      "fixed-function GL_PROJECTION (program 4: its vertex shader reads "
      "gl_ModelViewProjectionMatrix): 36 draws, 1 matrices, GL_LESS; orthographic, built for "
      "ambiguous, near -1, far 1.1; [info:depth-convention-ambiguous]"},
     {"info:projection-changes-within-frame"}},
    {"osgshadow-sm",
     "3 frames, 42 draws (42 with a projection), 2 pairs in 2 groups, verdict ok",
     {"fixed-function GL_PROJECTION: 21 draws, 1 matrices, GL_LESS; orthographic, built for "
      "ambiguous, near 7.51681, far 22.5504; [info:depth-convention-ambiguous]",
      "fixed-function GL_PROJECTION (program 1: it has no vertex shader): 21 draws, 1 matrices, "
      "GL_LESS; perspective, built for ambiguous, near 23.541, far 34.7019, fov 29.1484; "
      "[info:depth-convention-ambiguous]"},
     {}},
    {"osgshadow-lispsm",
     "3 frames, 63 draws (63 with a projection), 5 pairs in 3 groups, verdict ok",
     {"fixed-function GL_PROJECTION (program 1: its vertex shader calls ftransform()): 21 draws, "
      "1 matrices, GL_LESS; perspective, built for ambiguous, near 23.541, far 34.7019, fov "
      "30.8856; [info:depth-convention-ambiguous]",
      // LiSPSM's light-space warp: its centre of projection is at infinity, so there is no near,
      // far or fov to range (RealProgramsDetail.OsgShadowLispsmEyeAtInfinity).
      "fixed-function GL_PROJECTION: 21 draws, 3 matrices, GL_LESS; perspective, built for "
      "ambiguous, near none, far none, fov none; [info:oblique-near-plane]",
      "fixed-function GL_PROJECTION (program 4: it has no vertex shader): 21 draws, 1 matrices, "
      "GL_LESS; perspective, built for ambiguous, near 23.541, far 34.7019, fov 29.1484; "
      "[info:depth-convention-ambiguous]"},
     {}},
    {"osgtext",
     "3 frames, 292 draws (156 with a projection), 8 pairs in 8 groups, verdict ok",
     {"fixed-function GL_PROJECTION (program 22: its vertex shader reads "
      "gl_ModelViewProjectionMatrix): 12 draws, 1 matrices, GL_LESS; perspective, built for "
      "ambiguous, near 1938.65, far 2126.16, fov 29.1484; [info:depth-convention-ambiguous]",
      "fixed-function GL_PROJECTION (program 24: its vertex shader reads "
      "gl_ModelViewProjectionMatrix): 42 draws, 1 matrices, GL_LESS; perspective, built for "
      "ambiguous, near 1938.65, far 2126.16, fov 29.1484; [info:depth-convention-ambiguous]",
      "fixed-function GL_PROJECTION (program 24: its vertex shader reads "
      "gl_ModelViewProjectionMatrix): 60 draws, 1 matrices, GL_LESS; orthographic, built for "
      "ambiguous, near -1, far 1; [info:depth-convention-ambiguous]",
      "fixed-function GL_PROJECTION (program 26: its vertex shader reads "
      "gl_ModelViewProjectionMatrix): 6 draws, 1 matrices, GL_LESS; orthographic, built for "
      "ambiguous, near -1, far 1; [info:depth-convention-ambiguous]",
      "fixed-function GL_PROJECTION (program 28: its vertex shader reads "
      "gl_ModelViewProjectionMatrix): 12 draws, 1 matrices, GL_LESS; orthographic, built for "
      "ambiguous, near -1, far 1; [info:depth-convention-ambiguous]",
      "fixed-function GL_PROJECTION (program 30: its vertex shader reads "
      "gl_ModelViewProjectionMatrix): 12 draws, 1 matrices, GL_LESS; orthographic, built for "
      "ambiguous, near -1, far 1; [info:depth-convention-ambiguous]",
      "fixed-function GL_PROJECTION (program 32: its vertex shader reads "
      "gl_ModelViewProjectionMatrix): 6 draws, 1 matrices, GL_LESS; orthographic, built for "
      "ambiguous, near -1, far 1; [info:depth-convention-ambiguous]",
      "fixed-function GL_PROJECTION (program 34: its vertex shader reads "
      "gl_ModelViewProjectionMatrix): 6 draws, 1 matrices, GL_LESS; orthographic, built for "
      "ambiguous, near -1, far 1; [info:depth-convention-ambiguous]"},
     {"info:projection-changes-within-frame"}},
    {"osguniformbuffer",
     "3 frames, 9 draws (9 with a projection), 1 pairs in 1 groups, verdict ok",
     {"fixed-function GL_PROJECTION (program 3: its vertex shader calls ftransform()): 9 draws, 1 "
      "matrices, GL_LESS; perspective, built for ambiguous, near 104.715, far 119.189, fov "
      "29.1484; [info:depth-convention-ambiguous]"},
     {}},
    {"osgteapot",
     "3 frames, 96 draws (96 with a projection), 1 pairs in 1 groups, verdict ok",
     {"fixed-function GL_PROJECTION: 96 draws, 1 matrices, GL_LESS; perspective, built for "
      "ambiguous, near 14.1563, far 18.8141, fov 29.1484; [info:depth-convention-ambiguous]"},
     {}},
    {"osgdepthpartition",
     "3 frames, 15 draws (15 with a projection), 2 pairs in 1 groups, verdict ok",
     {"fixed-function GL_PROJECTION: 15 draws, 2 matrices, GL_LESS; perspective, built for "
      "ambiguous, near 3647.17..1.15334e+06, far 1.15333e+06..3.64714e+08, fov 29.1484; "
      "[info:depth-convention-ambiguous]"},
     {"info:projection-changes-within-frame"}},
    {"osgreflect",
     "3 frames, 15 draws (15 with a projection), 12 pairs in 6 groups, verdict ok",
     {"fixed-function GL_PROJECTION: 6 draws, 3 matrices, GL_LESS; perspective, built for "
      "ambiguous, near 62.0838..62.5455, far 83.837..84.3176, fov 29.1484; "
      "[info:depth-convention-ambiguous]",
      "fixed-function GL_PROJECTION: 1 draws, 1 matrices, GL_ALWAYS; not analysed: glDepthRange(1, "
      "1) at call 523: near and far are equal, so every fragment gets the same depth",
      "fixed-function GL_PROJECTION: 3 draws, 3 matrices, GL_LESS; perspective, built for "
      "ambiguous, near 62.0838..62.5455, far 83.837..84.3176, fov 29.1484; "
      "[info:depth-convention-ambiguous]",
      "fixed-function GL_PROJECTION: 3 draws, 3 matrices, GL_ALWAYS; perspective, built for "
      "ambiguous, near 62.0838..62.5455, far 83.837..84.3176, fov 29.1484; "
      "[info:depth-convention-ambiguous]",
      "fixed-function GL_PROJECTION: 1 draws, 1 matrices, GL_ALWAYS; not analysed: glDepthRange(1, "
      "1) at call 646: near and far are equal, so every fragment gets the same depth",
      "fixed-function GL_PROJECTION: 1 draws, 1 matrices, GL_ALWAYS; not analysed: glDepthRange(1, "
      "1) at call 769: near and far are equal, so every fragment gets the same depth"},
     {}},
    {"glmark2-build",
     "3 frames, 3 draws (3 with a projection), 3 pairs in 1 groups, verdict ok",
     {"uniform ModelViewProjectionMatrix (program 1): 3 draws, 3 matrices, GL_LEQUAL; perspective, "
      "built for no, near 2, far 4.25224, fov 39.6211; []"},
     {}},
    {"f3d",
     "1 frames, 2 draws (1 with a projection), 1 pairs in 1 groups, verdict ok",
     {"uniform MCDCMatrix (program 3): 1 draws, 1 matrices, GL_LEQUAL; perspective, built for "
      "ambiguous, near 28.176, far 38.8453, fov 30; [info:depth-convention-ambiguous]"},
     {}},
    {"osgmultiplerendertargets",
     "3 frames, 6 draws (6 with a projection), 2 pairs in 2 groups, verdict ok",
     {"fixed-function GL_PROJECTION (program 4: it has no vertex shader): 3 draws, 1 matrices, "
      "GL_LESS; orthographic, built for ambiguous, near -1.01328e-06, far 2; "
      "[info:depth-convention-ambiguous]",
      "fixed-function GL_PROJECTION (program 2: it has no vertex shader): 3 draws, 1 matrices, "
      "GL_LESS; perspective, built for ambiguous, near 2.75386, far 2.86626, fov 29.1484; "
      "[info:depth-convention-ambiguous]"},
     {}},
    {"osgscalarbar",
     "1 frames, 150 draws (78 with a projection), 4 pairs in 4 groups, verdict ok",
     {"fixed-function GL_PROJECTION: 4 draws, 1 matrices, GL_LESS; perspective, built for "
      "ambiguous, near 4.00897, far 4.17261, fov 29.1484; [info:depth-convention-ambiguous]",
      "fixed-function GL_PROJECTION (program 4: its vertex shader reads "
      "gl_ModelViewProjectionMatrix): 48 draws, 1 matrices, GL_LESS; perspective, built for "
      "ambiguous, near 4.00897, far 4.17261, fov 29.1484; [info:depth-convention-ambiguous]",
      "fixed-function GL_PROJECTION: 2 draws, 1 matrices, GL_LESS; orthographic, built for "
      "ambiguous, near -1, far 1; [info:depth-convention-ambiguous]",
      "fixed-function GL_PROJECTION (program 4: its vertex shader reads "
      "gl_ModelViewProjectionMatrix): 24 draws, 1 matrices, GL_LESS; orthographic, built for "
      "ambiguous, near -1, far 1; [info:depth-convention-ambiguous]"},
     {"info:projection-changes-within-frame"}},
    {"osgdistortion",
     "3 frames, 150 draws (150 with a projection), 2 pairs in 2 groups, verdict ok",
     {"fixed-function GL_PROJECTION: 3 draws, 1 matrices, GL_LESS; perspective, built for "
      "ambiguous, near 28.8278, far 40.2044, fov 29.1484; [info:depth-convention-ambiguous]",
      "fixed-function GL_PROJECTION: 147 draws, 1 matrices, GL_LESS; orthographic, built for "
      "ambiguous, near -1, far 1; [info:depth-convention-ambiguous]"},
     {"info:projection-changes-within-frame"}},
    {"osgfpdepth",
     "3 frames, 30 draws (24 with a projection), 3 pairs in 3 groups, verdict ok",
     {"fixed-function GL_PROJECTION: 3 draws, 1 matrices, GL_GEQUAL; perspective, built for "
      "ambiguous, near 0.03125, far 499.829, fov 40; [info:depth-convention-ambiguous, "
      "warning:depth-range-reversed]",
      "fixed-function GL_PROJECTION: 3 draws, 1 matrices, GL_LESS; orthographic, built for "
      "ambiguous, near -1, far 1; [info:depth-convention-ambiguous]",
      "fixed-function GL_PROJECTION (program 4: its vertex shader reads "
      "gl_ModelViewProjectionMatrix): 18 draws, 1 matrices, GL_LESS; orthographic, built for "
      "ambiguous, near -1, far 1; [info:depth-convention-ambiguous]"},
     {"info:projection-changes-within-frame"}},
    // Per frame: the gradient background (an ortho drawn with the depth test disabled inside
    // glPushAttrib(GL_ENABLE_BIT)), then the trackball and, from frame 2 on, the mesh with the
    // depth test on again after glPopAttrib; the window's layout changes its size at frame 2.
    // Qt's own overlay draws (their matrix in vertex attributes) have no projection.
    {"meshlab",
     "5 frames, 65 draws (38 with a projection), 4 pairs in 4 groups, verdict ok",
     {"fixed-function GL_PROJECTION: 8 draws, 1 matrices, GL_LESS; orthographic, built for "
      "ambiguous, near -1, far 1; [info:depth-convention-ambiguous]",
      "fixed-function GL_PROJECTION: 6 draws, 1 matrices, GL_LESS; perspective, built for "
      "ambiguous, near 0.303109, far 4.78109, fov 60; [info:depth-convention-ambiguous]",
      "fixed-function GL_PROJECTION: 12 draws, 1 matrices, GL_LESS; orthographic, built for "
      "ambiguous, near -1, far 1; [info:depth-convention-ambiguous]",
      "fixed-function GL_PROJECTION: 12 draws, 1 matrices, GL_LESS; perspective, built for "
      "ambiguous, near 0.303109, far 6.49519, fov 60; [info:depth-convention-ambiguous]"},
     {"info:projection-changes-within-frame"}},
    // Its first frame (of 2023-01-01 22:00): the sky, projected on the CPU, drawn in pixels
    // through one ortho, with the depth test off; Qt's paint engine draws the rest (no projection).
    {"stellarium",
     "1 frames, 218 draws (116 with a projection), 5 pairs in 5 groups, verdict ok",
     {"uniform projectionMatrix (program 18): 4 draws, 1 matrices, GL_LESS; orthographic, built "
      "for ambiguous, near -1, far 1; [info:depth-convention-ambiguous]",
      "uniform projectionMatrix (program 3): 2 draws, 1 matrices, GL_LESS; orthographic, built "
      "for ambiguous, near -1, far 1; [info:depth-convention-ambiguous]",
      "uniform projectionMatrix (program 6): 88 draws, 1 matrices, GL_LESS; orthographic, built "
      "for ambiguous, near -1, far 1; [info:depth-convention-ambiguous]",
      "uniform projectionMatrix (program 15): 20 draws, 1 matrices, GL_LESS; orthographic, built "
      "for ambiguous, near -1, far 1; [info:depth-convention-ambiguous]",
      "uniform projectionMatrix (program 15): 2 draws, 1 matrices, GL_LESS; orthographic, built "
      "for ambiguous, near -1, far 1; [info:depth-convention-ambiguous]"},
     {}}};

class RealPrograms : public ::testing::TestWithParam<Program> {};

TEST_P(RealPrograms, ReadAsPinnedWithoutErrors) {
  const Program& program = GetParam();
  const Recorded recorded = check(program.name);
  // Status 0: no error (1 would be an error finding, 2 a refusal).
  ASSERT_EQ(recorded.status, 0) << recorded.err << recorded.report.dump(2);
  EXPECT_EQ(summary(recorded.report), program.summary);
  std::vector<std::string> groups;
  for (const auto& group : recorded.report["groups"]) groups.push_back(reading(group));
  EXPECT_EQ(groups, program.groups);
  EXPECT_EQ(codes(recorded.report["findings"]), program.traceFindings);
}

// Test names from the program names ("openscad-render-ortho": openscad_render_ortho).
std::string testName(const ::testing::TestParamInfo<Program>& param) {
  std::string name = param.param.name;
  for (char& c : name) {
    if (c == '-') c = '_';
  }
  return name;
}

INSTANTIATE_TEST_SUITE_P(Debian12, RealPrograms, ::testing::ValuesIn(kPrograms), testName);

// OpenSCAD's preview (OpenCSG's SCS passes): the GL_LESS and GL_EQUAL passes drawn over what the
// GL_GREATER pass wrote into depth cleared to 0 are a technique's steps, not clear-depth errors.
TEST(RealProgramsDetail, OpenScadPreviewPassesOverTheFarPass) {
  const Recorded recorded = check("openscad-preview-persp");
  ASSERT_EQ(recorded.status, 0) << recorded.err;
  const nlohmann::json& less = recorded.report["groups"][1];
  ASSERT_EQ(less["depth_state"]["depth_func"], "GL_LESS");
  ASSERT_EQ(less["findings"].size(), 2u);
  EXPECT_EQ(less["findings"][1]["message"],
            "this pass draws with glDepthFunc(GL_LESS) (call 2194) into depth cleared to 0 (call "
            "2117) after frame 0 drew the same matrix into that clear with "
            "glDepthFunc(GL_GREATER) (first at call 2127): it tests against the depth that pass "
            "wrote, not against the clear, a step of a multi-pass technique (OpenCSG's CSG "
            "passes, depth peeling), not a clear-depth mismatch");
}

// MeshLab disables the depth test for its background inside glPushAttrib(GL_ENABLE_BIT) (call
// 5800-5814) after enabling it for the frame (call 5780): the groups drawn after glPopAttrib
// (the trackball from call 5857, the mesh from call 7239) have it on again, as GL has.
TEST(RealProgramsDetail, MeshLabDepthTestRestoredByPopAttrib) {
  const Recorded recorded = check("meshlab");
  ASSERT_EQ(recorded.status, 0) << recorded.err;
  std::vector<std::string> groups;
  for (const auto& group : recorded.report["groups"]) {
    const nlohmann::json& state = group["depth_state"];
    groups.push_back(group["properties"]["projection"].get<std::string>() + " from call " +
                     std::to_string(group["first"]["call"].get<int>()) + ", viewport " +
                     std::to_string(state["viewport"][0].get<int>()) + "x" +
                     std::to_string(state["viewport"][1].get<int>()) + ": depth test " +
                     (state["depth_test"].get<bool>() ? "on" : "off"));
  }
  EXPECT_EQ(groups, (std::vector<std::string>{
                        "orthographic from call 5804, viewport 682x408: depth test off",
                        "perspective from call 5857, viewport 682x408: depth test on",
                        "orthographic from call 7164, viewport 264x603: depth test off",
                        "perspective from call 7239, viewport 264x603: depth test on"}));
}

// osgshadow --lispsm: the light-space perspective warp's centre of projection is at infinity
// along +z. It reads as no eye point, in words, with no NaN in the text or the JSON and no number
// standing for the fov it has not got.
TEST(RealProgramsDetail, OsgShadowLispsmEyeAtInfinity) {
  const Recorded recorded = check("osgshadow-lispsm");
  ASSERT_EQ(recorded.status, 0) << recorded.err;
  const std::string json = recorded.report.dump();
  EXPECT_EQ(json.find("nan"), std::string::npos) << json;
  EXPECT_EQ(json.find("NaN"), std::string::npos) << json;
  const nlohmann::json& warp = recorded.report["groups"][1];
  ASSERT_EQ(warp["distinct_matrices"], 3);
  const nlohmann::json& p = warp["properties"];
  EXPECT_TRUE(p["eye"].is_null());
  EXPECT_EQ(p["eye_at_infinity_along"], nlohmann::json({0.0, 0.0, 1.0}));
  EXPECT_EQ(p["view_direction"], nlohmann::json({0.0, 1.0, 0.0}));
  EXPECT_TRUE(p["fov_y_degrees"].is_null());
  EXPECT_TRUE(p["fov_x_degrees"].is_null());
  EXPECT_TRUE(p["near"].is_null());
  EXPECT_TRUE(p["far"].is_null());
  EXPECT_TRUE(p["oblique"].get<bool>());

  TempFolder folder;
  const auto text =
      runClipray("check --trace '" + kRecorded + "osgshadow-lispsm.dump.txt'", folder.path(),
                 "CLIPRAY_APITRACE='" + kRecorded + "apitrace-cat.sh'");
  ASSERT_EQ(text.status, 0) << text.err;
  for (const char* nan : {"nan", "NaN", "NAN"}) {
    EXPECT_EQ(text.out.find(nan), std::string::npos) << text.out;
  }
  EXPECT_NE(text.out.find("[2] fixed-function GL_PROJECTION: 3 matrices, 21 draws, first frame 0 "
                          "call 1168, last frame 2 call 1978\n"),
            std::string::npos)
      << text.out;
  EXPECT_NE(text.out.find(
                "  matrix: perspective, off-axis, oblique near plane, right-handed\n"
                "  over its 3 matrices: no near, far, fov or eye to range (the lines below read "
                "the first)\n"
                "    no eye point: the centre of projection is at infinity along (0, 0, 1) (rows "
                "x, y and w share no point; a light-space perspective warp such as LiSPSM's), "
                "looking along (0, 1, 0)\n"
                "    near -, far -, fov - (no eye to measure it from)\n"),
            std::string::npos)
      << text.out;
}

}  // namespace
}  // namespace clipray
