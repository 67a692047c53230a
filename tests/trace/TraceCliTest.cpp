// `clipray check --trace` on real traces: tests/traceapps/ConventionApp.cpp, one case per depth
// convention and per classic mistake, recorded with `apitrace trace --api egl` on Mesa's
// surfaceless EGL platform (no display, no GPU: llvmpipe), then checked by the clipray binary.
// Needs Debian's apitrace (harness/install-deps.sh).

#include <gtest/gtest.h>

#include <sys/wait.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "support/RunCommand.hpp"

namespace clipray {
namespace {

using testing::runClipray;
using testing::TempFolder;

// Records `clipray_trace_app CASE FRAMES` into FOLDER/CASE.trace; "" on success, else apitrace's
// output.
std::string recordTrace(const std::string& name, const TempFolder& folder, int frames = 3) {
  const std::filesystem::path log = folder.path() / (name + ".log");
  const std::string command = "cd '" + folder.path().string() +
                              "' && apitrace trace --api egl -o '" + name + ".trace' '" +
                              CLIPRAY_TRACE_APP + "' " + name + " " + std::to_string(frames) +
                              " >'" + log.string() + "' 2>&1";
  const int raw = std::system(command.c_str());
  const int status = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
  const std::string output = testing::readText(log);
  std::filesystem::remove(log);
  if (status != 0 || !std::filesystem::exists(folder.path() / (name + ".trace"))) {
    return "apitrace trace of " + name + " failed (status " + std::to_string(status) +
           "; is Debian's apitrace installed? harness/install-deps.sh): " + output;
  }
  return "";
}

struct Checked {
  int status = -1;
  nlohmann::json report;
  std::string err;
};

Checked checkTraced(const std::string& name, const TempFolder& folder) {
  Checked checked;
  const std::string failure = recordTrace(name, folder);
  if (!failure.empty()) {
    checked.err = failure;
    return checked;
  }
  const auto result = runClipray("check --trace " + name + ".trace --json", folder.path());
  checked.status = result.status;
  checked.err = result.err;
  if (result.status == 0 || result.status == 1) checked.report = nlohmann::json::parse(result.out);
  return checked;
}

std::vector<std::string> codes(const nlohmann::json& group) {
  std::vector<std::string> result;
  for (const auto& f : group["findings"]) {
    result.push_back(f["severity"].get<std::string>() + ":" + f["code"].get<std::string>());
  }
  return result;
}

// The one group every test app draws: one matrix, three frames, one draw each.
const nlohmann::json& onlyGroup(const Checked& checked) {
  static const nlohmann::json empty = nlohmann::json::object();
  if (!checked.report.contains("groups") || checked.report["groups"].size() != 1) {
    ADD_FAILURE() << "expected one group: " << checked.report.dump(2) << checked.err;
    return empty;
  }
  const nlohmann::json& group = checked.report["groups"][0];
  EXPECT_EQ(group["draws"], 3);
  EXPECT_EQ(group["distinct_matrices"], 1);
  EXPECT_EQ(group["first"]["frame"], 0);
  EXPECT_EQ(group["last"]["frame"], 2);
  EXPECT_EQ(checked.report["frames"]["read"], 3);
  return group;
}

TEST(TraceCli, NegativeOneToOneApp) {
  TempFolder folder;
  const Checked checked = checkTraced("no", folder);
  ASSERT_EQ(checked.status, 0) << checked.err;
  const nlohmann::json& group = onlyGroup(checked);
  EXPECT_EQ(group["source"], "uniform clipFromWorld (program 1)");
  EXPECT_EQ(group["depth_state"]["clip_depth"], "negative-one-to-one");
  EXPECT_EQ(group["depth_state"]["depth_func"], "GL_LESS");
  EXPECT_EQ(group["depth_state"]["depth_format"], "32f");
  EXPECT_EQ(group["depth_state"]["viewport"], nlohmann::json::array({64, 48}));
  EXPECT_EQ(group["properties"]["built_for"], "no");
  EXPECT_NEAR(group["properties"]["near"].get<double>(), 0.1, 2e-5);
  EXPECT_NEAR(group["properties"]["far"].get<double>(), 100.0, 0.2);
  EXPECT_NEAR(group["properties"]["fov_y_degrees"].get<double>(), 60.0, 2e-4);
  EXPECT_EQ(codes(group), std::vector<std::string>{});
  EXPECT_EQ(checked.report["verdict"], "ok");
}

TEST(TraceCli, ZeroToOneApp) {
  TempFolder folder;
  const Checked checked = checkTraced("zo", folder);
  ASSERT_EQ(checked.status, 0) << checked.err;
  const nlohmann::json& group = onlyGroup(checked);
  EXPECT_EQ(group["depth_state"]["clip_depth"], "zero-to-one");
  EXPECT_EQ(group["properties"]["built_for"], "zo");
  EXPECT_NEAR(group["properties"]["near"].get<double>(), 0.1, 3e-5);
  EXPECT_EQ(codes(group), std::vector<std::string>{});
}

// The depth buffer is a GL_DEPTH_COMPONENT24 texture (glTexStorage2D, glFramebufferTexture2D),
// set up after a GL_DEPTH_COMPONENT16 texture on another unit.
TEST(TraceCli, ZeroToOneAppIntoADepthTexture) {
  TempFolder folder;
  const Checked checked = checkTraced("zo-depth-texture", folder);
  ASSERT_EQ(checked.status, 0) << checked.err;
  const nlohmann::json& group = onlyGroup(checked);
  EXPECT_EQ(group["depth_state"]["depth_format"], "24");
  EXPECT_EQ(group["properties"]["built_for"], "zo");
  EXPECT_EQ(codes(group), std::vector<std::string>{});
}

TEST(TraceCli, ReversedInfiniteApp) {
  TempFolder folder;
  const Checked checked = checkTraced("reversed-infinite", folder);
  ASSERT_EQ(checked.status, 0) << checked.err;
  const nlohmann::json& group = onlyGroup(checked);
  EXPECT_EQ(group["depth_state"]["depth_func"], "GL_GREATER");
  EXPECT_EQ(group["depth_state"]["cleared_depth"], 0.0);
  EXPECT_EQ(group["properties"]["built_for"], "zo-reversed");
  EXPECT_EQ(group["properties"]["reversed"], true);
  EXPECT_EQ(group["properties"]["infinite_far"], true);
  EXPECT_NEAR(group["properties"]["near"].get<double>(), 0.1, 1e-5);
  // About picking rays at an infinite far plane, not about the app's depth state.
  EXPECT_EQ(codes(group), std::vector<std::string>{"warning:infinite-far-plane"});
}

TEST(TraceCli, NegativeOneToOneMatrixUnderZeroToOne) {
  TempFolder folder;
  const Checked checked = checkTraced("no-under-zo", folder);
  ASSERT_EQ(checked.status, 1) << checked.err;
  const nlohmann::json& group = onlyGroup(checked);
  EXPECT_EQ(group["first"]["call"], 49);
  EXPECT_EQ(group["last"]["call"], 57);
  EXPECT_EQ(group["depth_state"]["calls"]["clip_control"], 23);
  EXPECT_EQ(group["properties"]["built_for"], "no");
  ASSERT_EQ(codes(group), std::vector<std::string>{"error:depth-convention-mismatch"});
  const std::string message = group["findings"][0]["message"];
  EXPECT_NE(message.find("the effective near plane moves to 0.1998 (1.998x)"), std::string::npos)
      << message;
  EXPECT_EQ(checked.report["verdict"], "errors");
}

TEST(TraceCli, ReversedMatrixWithLess) {
  TempFolder folder;
  const Checked checked = checkTraced("reversed-with-less", folder);
  ASSERT_EQ(checked.status, 1) << checked.err;
  const nlohmann::json& group = onlyGroup(checked);
  EXPECT_EQ(codes(group),
            (std::vector<std::string>{"error:reversed-z-mismatch", "warning:infinite-far-plane",
                                      "error:clear-depth-mismatch"}));
  const std::string mismatch = group["findings"][0]["message"];
  EXPECT_NE(mismatch.find("(traced: glDepthFunc(GL_LESS) at call 24)"), std::string::npos)
      << mismatch;
  EXPECT_EQ(group["findings"][2]["message"],
            "the depth buffer is cleared to 1 (call 47), the far value of the classic "
            "convention; this matrix puts far at 0, so the cleared depth is nearer than any "
            "surface and nothing passes the test");
}

TEST(TraceCli, RowMajorMatrixUploadedUntransposed) {
  TempFolder folder;
  const Checked checked = checkTraced("row-major-untransposed", folder);
  ASSERT_EQ(checked.status, 1) << checked.err;
  const nlohmann::json& group = onlyGroup(checked);
  EXPECT_EQ(group["properties"]["likely_transposed"], true);
  EXPECT_EQ(codes(group), std::vector<std::string>{"error:likely-transposed"});
}

TEST(TraceCli, VulkanFlipUnderLowerLeftOrigin) {
  TempFolder folder;
  const Checked checked = checkTraced("vulkan-flip", folder);
  ASSERT_EQ(checked.status, 0) << checked.err;
  const nlohmann::json& group = onlyGroup(checked);
  EXPECT_EQ(group["depth_state"]["clip_origin"], "lower-left");
  EXPECT_EQ(group["properties"]["y_flipped"], true);
  EXPECT_EQ(group["properties"]["built_for"], "zo");
  EXPECT_EQ(codes(group), std::vector<std::string>{"warning:y-flipped"});
}

// A Direct3D-style app culling back faces: with glFrontFace(GL_CW) its y-down projection keeps
// the outsides (only the y flip is noted); its twin with GL_CCW is warned.
TEST(TraceCli, FaceCullingUnderAnUpperLeftOrigin) {
  TempFolder folder;
  const Checked right = checkTraced("d3d-style-culled", folder);
  ASSERT_EQ(right.status, 0) << right.err;
  const nlohmann::json& group = onlyGroup(right);
  EXPECT_EQ(group["depth_state"]["clip_origin"], "upper-left");
  EXPECT_EQ(group["depth_state"]["cull_face"], "GL_BACK");
  EXPECT_EQ(group["depth_state"]["front_face"], "GL_CW");
  EXPECT_EQ(codes(group), std::vector<std::string>{"info:y-flipped"});
  const Checked wrong = checkTraced("d3d-style-culled-ccw", folder);
  ASSERT_EQ(wrong.status, 0) << wrong.err;  // a warning: meshes wound clockwise are drawn right
  const nlohmann::json& twin = onlyGroup(wrong);
  EXPECT_EQ(twin["depth_state"]["front_face"], "GL_CCW");
  EXPECT_EQ(twin["depth_state"]["calls"]["front_face"], 0);
  EXPECT_EQ(codes(twin),
            (std::vector<std::string>{"info:y-flipped", "warning:face-culling-keeps-insides"}));
}

TEST(TraceCli, FixedFunctionFrustumUnderZeroToOne) {
  TempFolder folder;
  const Checked checked = checkTraced("fixed-function-frustum-under-zo", folder);
  ASSERT_EQ(checked.status, 1) << checked.err;
  const nlohmann::json& group = onlyGroup(checked);
  EXPECT_EQ(group["source"], "fixed-function GL_PROJECTION");
  EXPECT_EQ(group["depth_state"]["depth_func"], "GL_LEQUAL");
  EXPECT_EQ(group["properties"]["built_for"], "no");
  EXPECT_NEAR(group["properties"]["near_if_built_for_no"].get<double>(), 0.1, 1e-6);
  EXPECT_EQ(codes(group), std::vector<std::string>{"error:depth-convention-mismatch"});
}

// OpenCSG's passes: the same glFrustum drawn with GL_LESS into depth cleared to 1 and with
// GL_GREATER into depth cleared to 0 in every frame. The far-surface pass is an info, never a
// reversed-Z error.
TEST(TraceCli, OpenCsgPassesAreNoError) {
  TempFolder folder;
  const Checked checked = checkTraced("opencsg-passes", folder);
  ASSERT_EQ(checked.status, 0) << checked.err << checked.report.dump(2);
  ASSERT_EQ(checked.report["groups"].size(), 2u) << checked.report.dump(2);
  const nlohmann::json& nearest = checked.report["groups"][0];
  EXPECT_EQ(nearest["depth_state"]["depth_func"], "GL_LESS");
  EXPECT_EQ(nearest["depth_state"]["cleared_depth"], 1.0);
  EXPECT_TRUE(codes(nearest).empty());
  const nlohmann::json& farthest = checked.report["groups"][1];
  EXPECT_EQ(farthest["depth_state"]["depth_func"], "GL_GREATER");
  EXPECT_EQ(farthest["depth_state"]["cleared_depth"], 0.0);
  EXPECT_EQ(farthest["properties"]["built_for"], "no");
  EXPECT_EQ(codes(farthest), std::vector<std::string>{"info:multi-pass-far-surfaces"});
  EXPECT_EQ(checked.report["verdict"], "ok");
}

// A GLSL 1.20 program calling ftransform() draws through glFrustum's GL_PROJECTION: read as the
// camera, under the program's name.
TEST(TraceCli, FtransformProgramReadsTheProjectionStack) {
  TempFolder folder;
  const Checked checked = checkTraced("ftransform-program", folder);
  ASSERT_EQ(checked.status, 0) << checked.err << checked.report.dump(2);
  const nlohmann::json& group = onlyGroup(checked);
  EXPECT_EQ(group["source"],
            "fixed-function GL_PROJECTION (program 1: its vertex shader calls ftransform())");
  EXPECT_EQ(group["properties"]["built_for"], "no");
  EXPECT_NEAR(group["properties"]["near"].get<double>(), 0.1, 2e-5);
  EXPECT_TRUE(codes(group).empty());
}

// The camera set through the ARB_shader_objects entry points (glUniformMatrix4fvARB into a
// program from glCreateProgramObjectARB, glLinkProgramARB, glUseProgramObjectARB): read as the
// core calls are.
TEST(TraceCli, ArbShaderObjectsProgram) {
  TempFolder folder;
  const Checked checked = checkTraced("arb-shader-objects", folder);
  ASSERT_EQ(checked.status, 0) << checked.err << checked.report.dump(2);
  const nlohmann::json& group = onlyGroup(checked);
  EXPECT_EQ(group["source"], "uniform clipFromWorld (program 1)");
  EXPECT_EQ(group["properties"]["built_for"], "no");
  EXPECT_NEAR(group["properties"]["near"].get<double>(), 0.1, 2e-5);
  EXPECT_NEAR(group["properties"]["fov_y_degrees"].get<double>(), 60.0, 2e-4);
  EXPECT_TRUE(codes(group).empty());
}

// GL_DEPTH_CLAMP on a correct ZO app: recorded in the draw's state, and a note (not an error)
// on what it does to picking rays.
TEST(TraceCli, DepthClampIsRecordedAndNoted) {
  TempFolder folder;
  const Checked checked = checkTraced("zo-depth-clamp", folder);
  ASSERT_EQ(checked.status, 0) << checked.err;
  const nlohmann::json& group = onlyGroup(checked);
  EXPECT_EQ(group["depth_state"]["depth_clamp"], true);
  EXPECT_EQ(group["depth_state"]["clip_distances"], nlohmann::json::array());
  EXPECT_EQ(group["properties"]["built_for"], "zo");
  EXPECT_EQ(codes(group), std::vector<std::string>{"info:depth-clamp-near-plane"});
  EXPECT_EQ(group["depth_state"]["calls"]["depth_clamp"], 25);
  EXPECT_EQ(group["findings"][0]["message"],
            "GL_DEPTH_CLAMP is on (glEnable(GL_DEPTH_CLAMP) at call 25): nothing is clipped at "
            "the near plane; a surface between the eye and the near plane (0.1) is drawn at "
            "window depth 0, the near plane's, so a picking ray that starts on the near plane "
            "cannot hit it and unprojecting the depth buffer there gives a point on the near "
            "plane, not on the surface; likewise a surface beyond the far plane (100) is drawn at "
            "window depth 1, past the end of a ray bounded by it");
}

// The camera in a std140 uniform block: written with glBufferSubData, bound with
// glBindBufferBase to the shader's `binding = 0`. The block's view matrix (no projection) and its
// vec4[4] of the projection's columns (no matrix) give no group.
TEST(TraceCli, ZeroToOneCameraInUniformBlock) {
  TempFolder folder;
  const Checked checked = checkTraced("zo-ubo", folder);
  ASSERT_EQ(checked.status, 0) << checked.err;
  const nlohmann::json& group = onlyGroup(checked);
  EXPECT_EQ(group["source"], "ubo Camera.clipFromWorld (program 1)");
  EXPECT_EQ(group["depth_state"]["clip_depth"], "zero-to-one");
  EXPECT_EQ(group["properties"]["built_for"], "zo");
  EXPECT_NEAR(group["properties"]["near"].get<double>(), 0.1, 3e-5);
  EXPECT_NEAR(group["properties"]["fov_y_degrees"].get<double>(), 60.0, 2e-4);
  EXPECT_EQ(codes(group), std::vector<std::string>{});
  EXPECT_EQ(checked.report["findings"], nlohmann::json::array());
  // apitrace's blob files went to a folder of clipray's own, not next to the trace.
  std::vector<std::string> left;
  for (const auto& entry : std::filesystem::directory_iterator(folder.path())) {
    left.push_back(entry.path().filename().string());
  }
  EXPECT_EQ(left, std::vector<std::string>{"zo-ubo.trace"});
}

// A NEGATIVE_ONE_TO_ONE camera in a std140 block at binding 3 (glUniformBlockBinding), in a
// glBindBufferRange at offset 256, written through glMapBufferRange (apitrace's memcpy record).
TEST(TraceCli, NegativeOneToOneCameraInMappedUniformBlockUnderZeroToOne) {
  TempFolder folder;
  const Checked checked = checkTraced("no-under-zo-ubo", folder);
  ASSERT_EQ(checked.status, 1) << checked.err;
  const nlohmann::json& group = onlyGroup(checked);
  EXPECT_EQ(group["source"], "ubo Camera.clipFromWorld (program 1)");
  EXPECT_EQ(group["first"]["call"], 57);
  EXPECT_EQ(group["last"]["call"], 71);
  EXPECT_EQ(group["depth_state"]["calls"]["clip_control"], 23);
  EXPECT_EQ(group["properties"]["built_for"], "no");
  ASSERT_EQ(codes(group), std::vector<std::string>{"error:depth-convention-mismatch"});
  const std::string message = group["findings"][0]["message"];
  EXPECT_NE(message.find("the effective near plane moves to 0.1998 (1.998x)"), std::string::npos)
      << message;
  EXPECT_EQ(checked.report["findings"], nlohmann::json::array());
  EXPECT_EQ(checked.report["verdict"], "errors");
  // Replayed, the block's matrix puts the triangle where the uniform app's does (the same camera
  // in VerifyReplaysTheDepthBuffer): the bytes were read as the shader reads them.
  const auto verified =
      runClipray("check --trace no-under-zo-ubo.trace --verify --json", folder.path());
  ASSERT_EQ(verified.status, 1) << verified.err;
  const nlohmann::json verify = nlohmann::json::parse(verified.out)["groups"][0]["verify"];
  EXPECT_EQ(verify["call"], 57);
  EXPECT_EQ(verify["written"], 56);
  EXPECT_NEAR(verify["nearest_view_depth"].get<double>(), 5.06817, 1e-4);
  EXPECT_NEAR(verify["picked_nearest"].get<double>(), 2.59997, 1e-4);
}

// Separable programs in a program pipeline and no glUseProgram: the camera is the vertex stage's
// program's uniform, set with glProgramUniformMatrix4fv (a checker that follows glUseProgram alone
// sees draws without a projection and refuses the trace).
TEST(TraceCli, NegativeOneToOneMatrixInAProgramPipelineUnderZeroToOne) {
  TempFolder folder;
  const Checked checked = checkTraced("no-under-zo-pipeline", folder);
  ASSERT_EQ(checked.status, 1) << checked.err;
  const nlohmann::json& group = onlyGroup(checked);
  EXPECT_EQ(group["source"], "uniform clipFromWorld (program 2)");
  EXPECT_EQ(group["first"]["call"], 43);
  EXPECT_EQ(group["last"]["call"], 51);
  EXPECT_EQ(group["depth_state"]["calls"]["clip_control"], 23);
  EXPECT_EQ(group["properties"]["built_for"], "no");
  ASSERT_EQ(codes(group), std::vector<std::string>{"error:depth-convention-mismatch"});
  EXPECT_EQ(checked.report["verdict"], "errors");
}

TEST(TraceCli, TextReport) {
  TempFolder folder;
  ASSERT_EQ(recordTrace("no-under-zo", folder), "");
  const auto result = runClipray("check --trace no-under-zo.trace --frames 1-2", folder.path());
  EXPECT_EQ(result.status, 1) << result.err;
  EXPECT_NE(result.out.find("trace no-under-zo.trace: frames 1-2, 2 draws (2 with a projection), "
                            "1 distinct (matrix, depth state) pairs in 1 groups\n"),
            std::string::npos)
      << result.out;
  EXPECT_NE(result.out.find("[1] uniform clipFromWorld (program 1): 1 matrix, 2 draws, first "
                            "frame 1 call 53, last frame 2 call 57\n"),
            std::string::npos)
      << result.out;
  EXPECT_NE(result.out.find("  depth state: clip control lower-left, zero-to-one; depth test "
                            "GL_LESS; depth range 0, 1; cleared to 1; viewport 64x48; depth "
                            "buffer 32f\n"),
            std::string::npos)
      << result.out;
  EXPECT_NE(result.out.find("\n1 errors, 0 warnings, 0 notes\n"), std::string::npos) << result.out;
}

TEST(TraceCli, VerifyReplaysTheDepthBuffer) {
  TempFolder folder;
  ASSERT_EQ(recordTrace("no-under-zo", folder), "");
  ASSERT_EQ(recordTrace("no", folder), "");
  const auto mistaken =
      runClipray("check --trace no-under-zo.trace --verify --json", folder.path());
  ASSERT_EQ(mistaken.status, 1) << mistaken.err;
  const nlohmann::json verify = nlohmann::json::parse(mistaken.out)["groups"][0]["verify"];
  EXPECT_EQ(verify["call"], 49);
  EXPECT_EQ(verify["pixels"], 64 * 48);
  EXPECT_EQ(verify["written"], 56);  // the triangle's pixel centres on llvmpipe
  // The triangle spans view depths 5.07..5.36 from the eye (0, 2, 5); read back as the NO
  // matrix it was built for, a pick puts it at 2.60..2.75.
  EXPECT_NEAR(verify["nearest_view_depth"].get<double>(), 5.06817, 1e-4);
  EXPECT_NEAR(verify["farthest_view_depth"].get<double>(), 5.35939, 1e-4);
  EXPECT_NEAR(verify["picked_nearest"].get<double>(), 2.59997, 1e-4);
  EXPECT_NEAR(verify["pick_worst_relative_error"].get<double>(), 0.487, 1e-3);

  const auto right = runClipray("check --trace no.trace --verify", folder.path());
  ASSERT_EQ(right.status, 0) << right.err;
  EXPECT_NE(right.out.find("  verify (replayed by eglretrace):\n    depth buffer after call 48 "
                           "(frame 0): 64x48 GL_DEPTH_COMPONENT32F, 56 of 3072 pixels differ "
                           "from the cleared depth 1\n    window depth used: 0.98125 to "
                           "0.982323\n    view depth of those pixels under the traced "
                           "NEGATIVE_ONE_TO_ONE: 5.06817 to 5.35938\n"),
            std::string::npos)
      << right.out;
  EXPECT_EQ(right.out.find("read back with"), std::string::npos) << right.out;
}

// eglretrace cannot dump the state between glBegin and glEnd: a fixed-function group is
// replayed up to the glEnd that completes its first draw.
TEST(TraceCli, VerifyReplaysAGlBeginUpToItsGlEnd) {
  TempFolder folder;
  ASSERT_EQ(recordTrace("fixed-function-frustum-under-zo", folder), "");
  const auto checked = runClipray(
      "check --trace fixed-function-frustum-under-zo.trace --verify --json", folder.path());
  ASSERT_EQ(checked.status, 1) << checked.err;
  const nlohmann::json group = nlohmann::json::parse(checked.out)["groups"][0];
  const nlohmann::json& verify = group["verify"];
  EXPECT_FALSE(verify.contains("failure")) << verify.dump();
  EXPECT_EQ(group["first"]["call"], 33);  // glBegin
  EXPECT_EQ(verify["call"], 37);          // three glVertex3f later, its glEnd
  EXPECT_EQ(verify["written"], 56);       // the triangle's pixel centres on llvmpipe
  EXPECT_NEAR(verify["pick_worst_relative_error"].get<double>(), 0.4846, 1e-4);
}

// Unusable input: one line naming the file, exit 2, nothing on stdout, nothing written.
void expectRefused(const std::string& arguments, const TempFolder& folder,
                   const std::string& message, const std::string& environment = "") {
  std::vector<std::filesystem::path> before;
  for (const auto& entry : std::filesystem::directory_iterator(folder.path())) {
    before.push_back(entry.path());
  }
  const auto result = runClipray("check " + arguments, folder.path(), environment);
  EXPECT_EQ(result.status, 2) << arguments;
  EXPECT_EQ(result.out, "") << arguments;
  EXPECT_EQ(result.err, "clipray: " + message + "\n") << arguments;
  std::vector<std::filesystem::path> after;
  for (const auto& entry : std::filesystem::directory_iterator(folder.path())) {
    after.push_back(entry.path());
  }
  std::sort(before.begin(), before.end());
  std::sort(after.begin(), after.end());
  EXPECT_EQ(before, after) << arguments;
}

TEST(TraceCli, BadTraces) {
  TempFolder folder;
  ASSERT_EQ(recordTrace("no", folder), "");
  ASSERT_EQ(recordTrace("identity", folder), "");
  ASSERT_EQ(recordTrace("clear-only", folder), "");
  {
    // The first 30000 bytes of a trace: apitrace reads what is there and warns.
    std::ifstream whole(folder.path() / "no.trace", std::ios::binary);
    std::string bytes(30000, '\0');
    whole.read(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    std::ofstream(folder.path() / "truncated.trace", std::ios::binary) << bytes;
    std::ofstream(folder.path() / "scene.json") << R"({"objects": []})";
  }
  expectRefused("--trace missing.trace", folder, "missing.trace: cannot open file");
  expectRefused("--trace truncated.trace", folder,
                "truncated.trace: truncated trace (apitrace: unexpected end of file while "
                "reading trace)");
  expectRefused("--trace scene.json", folder,
                "scene.json: no calls: not an apitrace trace, or an empty one");
  expectRefused("--trace clear-only.trace", folder,
                "clear-only.trace: no GL draw calls (29 calls in 3 frames read): nothing to check");
  expectRefused("--trace identity.trace", folder,
                "identity.trace: none of the 3 draws has a matrix with a projection's structure "
                "(uniform mat4, std140 uniform block mat4 or fixed-function GL_PROJECTION)");
  expectRefused("--trace no.trace --frames 5-9", folder,
                "no.trace: no GL draw calls in frames 5-9 (58 calls in 3 frames read): nothing "
                "to check");
  expectRefused("--trace no.trace --frames 2-1", folder,
                "--frames: expected A-B or A (frame numbers from 0, A <= B), got \"2-1\"");
  expectRefused("--trace no.trace --declared-depth zo", folder,
                "--trace: the depth state and matrices come from the trace; give no check file "
                "or field options with it");
  expectRefused("--trace no.trace", folder,
                "/nonexistent/apitrace: cannot run apitrace (not installed?): install Debian's "
                "apitrace (harness/install-deps.sh), or set CLIPRAY_APITRACE",
                "CLIPRAY_APITRACE=/nonexistent/apitrace");
}

}  // namespace
}  // namespace clipray
