// The CLI as a user meets it: exit statuses, messages, report fields, nothing half-written.

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <fstream>
#include <set>
#include <thread>

#include "support/RunCommand.hpp"
#include "support/VersionLine.hpp"

namespace clipray {
namespace {

using testing::runClipray;
using testing::TempFolder;

const std::string kSource = CLIPRAY_SOURCE_DIR;

bool folderIsEmpty(const std::filesystem::path& folder) {
  return std::filesystem::is_empty(folder);
}

// An inconsistent run says which side hit what: under an infinite far plane, 16-bit depth rounds
// the far wall to the cleared 1.0 and the raster drops it, where the rays hit it.
TEST(ReconcileCli, SaysWhichSideHitWhat) {
  TempFolder folder;
  const auto result = runClipray("reconcile '" + kSource +
                                     "/scenes/infinite_far.json' --conventions zo --depth-formats "
                                     "16 --size 64x36 --out out --junit junit.xml",
                                 folder.path());
  ASSERT_EQ(result.status, 1) << result.err;
  const std::string hits =
      "which side hit what in the inconsistent runs (pixels in GL window coordinates, y up from "
      "the bottom row):\n"
      "  infinite_far/main zo 16 world\n"
      "    worst pixel (13, 21): coverage_unexplained: raster nothing, ray \"far_wall\" triangle "
      "1 at depth 0.999999\n"
      "    cluster 1 (472 px) at (31, 27): coverage_unexplained: raster nothing, ray "
      "\"far_wall\" triangle 1 at depth 0.999999\n";
  EXPECT_NE(result.out.find(hits), std::string::npos) << result.out;
  // The last line names the page a person opens.
  EXPECT_TRUE(result.out.ends_with("\nreport: out/index.html (report.json beside it)\n"))
      << result.out;
  EXPECT_NE(testing::readText(folder.path() / "out/summary.txt").find(hits), std::string::npos);
  const auto report = nlohmann::json::parse(testing::readText(folder.path() / "out/report.json"));
  const auto& run = report["runs"][0];
  const auto wall = nlohmann::json::parse(
      R"({"id": 4, "object": "far_wall", "kind": "triangle", "triangle": 1})");
  for (const auto& pixel : {run["worst_pixel"], run["clusters"][0]}) {
    EXPECT_EQ(pixel["class"], "coverage_unexplained");
    EXPECT_TRUE(pixel["raster"].is_null());
    auto ray = pixel["ray"];
    EXPECT_GT(ray["depth"].get<double>(), 0.99999);
    ray.erase("depth");
    EXPECT_EQ(ray, wall);
    EXPECT_TRUE(pixel["tolerance_ratio"].is_null());
  }
  EXPECT_EQ(run["worst_pixel"]["pixel_gl"], nlohmann::json::parse(R"({"x": 13, "y": 21})"));
  EXPECT_EQ(run["worst_pixel"]["pixel_image"], nlohmann::json::parse(R"({"x": 13, "y": 14})"));
  const std::string junit = testing::readText(folder.path() / "junit.xml");
  EXPECT_NE(junit.find("\n  worst pixel (13, 21): coverage_unexplained: raster nothing, ray "
                       "&quot;far_wall&quot; triangle 1 at depth 0.999999\n"),
            std::string::npos)
      << junit;
  const std::string html = testing::readText(folder.path() / "out/index.html");
  EXPECT_NE(html.find("<td class=\"hit\">nothing</td><td class=\"hit\">&quot;far_wall&quot; "
                      "triangle 1<br>depth 0.999999</td>"),
            std::string::npos);
}

TEST(ReconcileCli, WritesTheReportAndExitsZeroWhenConsistent) {
  TempFolder folder;
  const auto result =
      runClipray("reconcile '" + kSource + "/scenes/standard.json' --out out --json --images all",
                 folder.path());
  ASSERT_EQ(result.status, 0) << result.err;
  const auto report = nlohmann::json::parse(testing::readText(folder.path() / "out/report.json"));
  EXPECT_EQ(report["tool"], "clipray");
  EXPECT_EQ(report["gl"]["backend"], "osmesa");
  EXPECT_FALSE(report["gl"]["renderer"].get<std::string>().empty());
  ASSERT_EQ(report["runs"].size(), 4u);  // no,zo x 24,32f x world
  for (const auto& run : report["runs"]) {
    EXPECT_EQ(run["scene"], "standard");
    EXPECT_EQ(run["camera"], "main");
    EXPECT_EQ(run["verdict"], "consistent");
    EXPECT_EQ(run["vertex_mode"], "world");
    EXPECT_EQ(run["size"]["width"], 320);
    EXPECT_EQ(run["pixels"], 320 * 240);
    for (const char* field :
         {"raster_hits", "ray_hits", "coverage_mismatch", "id_mismatch", "depth_error_quanta",
          "distance_rel_error", "tolerance_ratio", "timings_ms", "cpu_ms", "images"}) {
      EXPECT_TRUE(run.contains(field)) << field;
    }
    ASSERT_EQ(run["images"].size(), 4u);
    for (const auto& [name, path] : run["images"].items()) {
      ASSERT_TRUE(path.is_string()) << name;
      EXPECT_TRUE(std::filesystem::is_regular_file(folder.path() / "out" / path.get<std::string>()))
          << name;
    }
  }
  std::set<std::string> conventions, formats;
  for (const auto& run : report["runs"]) {
    conventions.insert(run["convention"].get<std::string>());
    formats.insert(run["depth_format"].get<std::string>());
  }
  EXPECT_EQ(conventions, (std::set<std::string>{"no", "zo"}));
  EXPECT_EQ(formats, (std::set<std::string>{"24", "32f"}));
  // --json prints only the report on stdout (parseable); the summary goes to stderr.
  EXPECT_EQ(nlohmann::json::parse(result.out)["tool"], "clipray");
  EXPECT_NE(result.err.find("4 runs: 4 consistent, 0 inconsistent"), std::string::npos)
      << result.err;
}

TEST(ReconcileCli, RoundsRepeatEveryRunAndMeasureNothingElseDifferently) {
  TempFolder folder;
  const std::string scene =
      "reconcile '" + kSource + "/scenes/standard.json' --conventions no,zo --depth-formats 32f ";
  const auto once = runClipray(scene + "--out once", folder.path());
  const auto thrice = runClipray(scene + "--rounds 3 --out thrice --images all", folder.path());
  ASSERT_EQ(once.status, 0) << once.err;
  ASSERT_EQ(thrice.status, 0) << thrice.err;
  const auto a = nlohmann::json::parse(testing::readText(folder.path() / "once/report.json"));
  const auto b = nlohmann::json::parse(testing::readText(folder.path() / "thrice/report.json"));
  ASSERT_EQ(a["runs"].size(), 2u);
  ASSERT_EQ(b["runs"].size(), 2u);
  for (std::size_t i = 0; i < 2; ++i) {
    nlohmann::json runA = a["runs"][i], runB = b["runs"][i];
    EXPECT_FALSE(runA.contains("rounds"));
    EXPECT_EQ(runB["rounds"], 3);
    const nlohmann::json& first = runB["first_round_timings_ms"];
    for (const char* timing : {"raster", "readback", "rays", "intersect", "compare"}) {
      EXPECT_GT(first[timing].get<double>(), 0.0) << timing;
      EXPECT_GT(runB["timings_ms"][timing].get<double>(), 0.0) << timing;
    }
    // CPU time: measured where there is work to time, and never more than every core busy for
    // the phase's wall time in the same round (1 ms for the clocks' granularity and for reading
    // them apart; the medians of rounds 2.. may come from different rounds).
    const double cores = std::max(1u, std::thread::hardware_concurrency());
    for (const char* timing : {"raster", "intersect", "compare"}) {
      EXPECT_GT(runB["cpu_ms"][timing].get<double>(), 0.0) << timing;
      const double firstCpu = runB["first_round_cpu_ms"][timing].get<double>();
      EXPECT_GT(firstCpu, 0.0) << timing;
      EXPECT_LE(firstCpu, cores * first[timing].get<double>() + 1.0) << timing;
    }
    for (const nlohmann::json& run : {runA, runB}) {
      const nlohmann::json& t = run["timings_ms"];
      const double ratio = run["analytic_over_raster"].get<double>();
      EXPECT_GT(ratio, 0.0);
      if (!run.contains("rounds")) {  // one round: the run's own timings' ratio
        EXPECT_DOUBLE_EQ(ratio, (t["rays"].get<double>() + t["intersect"].get<double>() +
                                 t["compare"].get<double>()) /
                                    t["raster"].get<double>());
      }
    }
    // The last round's images are written.
    ASSERT_EQ(runB["images"].size(), 4u);
    for (const auto& [name, path] : runB["images"].items()) {
      ASSERT_TRUE(path.is_string()) << name;
      EXPECT_TRUE(
          std::filesystem::is_regular_file(folder.path() / "thrice" / path.get<std::string>()))
          << name;
    }
    // Everything measured but time is the same, round after round.
    for (const char* timed : {"timings_ms", "cpu_ms", "analytic_over_raster", "rounds",
                              "first_round_timings_ms", "first_round_cpu_ms", "images"}) {
      runA.erase(timed);
      runB.erase(timed);
    }
    EXPECT_EQ(runA, runB);
  }
}

TEST(ReconcileCli, ImagesAreWrittenForTheInconsistentRunsUnlessAskedOtherwise) {
  // The water reflection's NO-built camera drawn under zo-reversed is inconsistent (its z = w
  // near plane lies behind the eye: no rays where GL draws the farthest surfaces); under zo it
  // is consistent. Its two inconsistent runs have 4 and 1 unexplained clusters at 64x48.
  TempFolder folder;
  const std::string command = "reconcile '" + kSource +
                              "/scenes/water_reflection.json' --conventions zo,zo-reversed "
                              "--depth-formats 32f --size 64x48 ";
  const std::set<std::string> kNames{"raster_depth", "ray_depth", "error_heatmap", "mismatch"};
  const auto pngsUnder = [&](const std::string& out) {
    std::set<std::string> files;
    for (const auto& entry : std::filesystem::recursive_directory_iterator(folder.path() / out)) {
      if (entry.path().extension() == ".png") {
        files.insert(std::filesystem::relative(entry.path(), folder.path() / out).string());
      }
    }
    return files;
  };
  for (const std::string policy : {"", "failing", "all", "none"}) {
    SCOPED_TRACE("--images " + policy);
    const std::string out = "out-" + (policy.empty() ? std::string("default") : policy);
    const auto result = runClipray(
        command + "--out " + out + (policy.empty() ? "" : " --images " + policy), folder.path());
    ASSERT_EQ(result.status, 1) << result.err;
    const auto report =
        nlohmann::json::parse(testing::readText(folder.path() / out / "report.json"));
    ASSERT_EQ(report["runs"].size(), 4u);
    std::set<std::string> expected;
    std::size_t images = 0, thumbnails = 0, crops = 0;
    for (const auto& run : report["runs"]) {
      const bool consistent = run["verdict"] == "consistent";
      EXPECT_EQ(consistent, run["convention"] == "zo");
      const bool wanted = policy == "all" || (policy != "none" && !consistent);
      ASSERT_EQ(run["images"].size(), 4u);
      for (const auto& [name, path] : run["images"].items()) {
        EXPECT_TRUE(kNames.count(name)) << name;
        if (!wanted) {
          EXPECT_TRUE(path.is_null()) << name;
          continue;
        }
        ASSERT_TRUE(path.is_string()) << name;
        expected.insert(path.get<std::string>());
        ++images;
      }
      // Every run's thumbnails, for index.html, unless --images none.
      for (const auto& [name, path] : run["thumbnails"].items()) {
        if (policy == "none") {
          EXPECT_TRUE(path.is_null()) << name;
          continue;
        }
        ASSERT_TRUE(path.is_string()) << name;
        expected.insert(path.get<std::string>());
        ++thumbnails;
      }
      // The crops go with the full-size images.
      EXPECT_EQ(run["clusters"].size(), consistent                         ? 0u
                                        : run["camera"] == "reflection_zo" ? 4u
                                                                           : 1u);
      for (const auto& cluster : run["clusters"]) {
        if (!wanted) {
          EXPECT_TRUE(cluster["crop"].is_null());
          continue;
        }
        ASSERT_TRUE(cluster["crop"].is_string());
        expected.insert(cluster["crop"].get<std::string>());
        ++crops;
      }
    }
    EXPECT_EQ(images, policy == "all" ? 16u : policy == "none" ? 0u : 8u);
    EXPECT_EQ(thumbnails, policy == "none" ? 0u : 8u);
    EXPECT_EQ(crops, policy == "none" ? 0u : 5u);
    EXPECT_EQ(pngsUnder(out), expected);
    EXPECT_TRUE(std::filesystem::is_regular_file(folder.path() / out / "index.html"));
  }
}

TEST(ReconcileCli, JUnitHasOneTestCasePerRunAndFailsTheInconsistentOnes) {
  TempFolder folder;
  std::filesystem::create_directory(folder.path() / "ci");
  const auto result = runClipray("reconcile '" + kSource +
                                     "/scenes/water_reflection.json' --conventions zo,zo-reversed "
                                     "--depth-formats 32f --size 64x48 --junit ci/junit.xml",
                                 folder.path());
  ASSERT_EQ(result.status, 1) << result.err;
  const std::string xml = testing::readText(folder.path() / "ci/junit.xml");
  EXPECT_NE(xml.find("<testsuites name=\"clipray reconcile\" tests=\"4\" failures=\"2\""),
            std::string::npos)
      << xml;
  for (const char* name : {"reflection_no zo 32f world", "reflection_zo zo 32f world"}) {
    EXPECT_NE(xml.find("<testcase classname=\"water_reflection\" name=\"" + std::string(name) +
                       "\" time=\""),
              std::string::npos)
        << name;
  }
  EXPECT_NE(xml.find("images: report/water_reflection/reflection_zo-zo-reversed-32f-world/"
                     "raster_depth.png"),
            std::string::npos)
      << xml;
  // The failure text names the largest clusters where to look.
  EXPECT_NE(xml.find("largest unexplained clusters (4 of 4, 8-connected):\n  115 px at GL window "
                     "(24, 15) = image (24, 32), GL bounds (21, 5) - (27, 24): coverage 115, id 0, "
                     "depth 0\n"),
            std::string::npos)
      << xml;
}

TEST(ReconcileCli, AMeshFileWithoutCamerasIsSeenFromTheAutomaticOnes) {
  TempFolder folder;
  const std::string obj = kSource + "/tests/data/meshes/quads.obj";
  const auto result = runClipray("reconcile '" + obj +
                                     "' --depth-formats 32f --size 64x48 "
                                     "--conventions zo --out out",
                                 folder.path());
  ASSERT_EQ(result.status, 0) << result.err;
  EXPECT_NE(result.err.find("clipray: warning: " + obj +
                            ": the file has no cameras; using the automatic cameras "
                            "auto_three_quarter, auto_grazing, auto_orthographic_z, auto_near_cut "
                            "(docs/scene-format.md)"),
            std::string::npos)
      << result.err;
  const auto report = nlohmann::json::parse(testing::readText(folder.path() / "out/report.json"));
  std::set<std::string> cameras;
  for (const auto& run : report["runs"]) {
    cameras.insert(run["camera"].get<std::string>());
    EXPECT_EQ(run["verdict"], "consistent") << run["camera"];
    EXPECT_GT(run["raster_hits"].get<int>(), 0) << run["camera"];
  }
  EXPECT_EQ(cameras, (std::set<std::string>{"auto_three_quarter", "auto_grazing",
                                            "auto_orthographic_z", "auto_near_cut"}));
}

TEST(ReconcileCli, VersionAndTheReportsProvenance) {
  TempFolder folder;
  const auto version = runClipray("--version", folder.path());
  EXPECT_EQ(version.status, 0) << version.err;
  const auto parsed = testing::parseVersionLine(version.out, "clipray");
  ASSERT_TRUE(parsed.has_value()) << version.out;
  const auto result = runClipray("reconcile '" + kSource +
                                     "/scenes/standard.json' --depth-formats 32f --size 64x48 "
                                     "--conventions zo --out 'my out'",
                                 folder.path());
  ASSERT_EQ(result.status, 0) << result.err;
  const auto report =
      nlohmann::json::parse(testing::readText(folder.path() / "my out/report.json"));
  EXPECT_EQ(report["clipray_version"], parsed->first);
  EXPECT_EQ(report["git_commit"], parsed->second);
  EXPECT_EQ(report["command_line"], std::string(CLIPRAY_BINARY) + " reconcile " + kSource +
                                        "/scenes/standard.json --depth-formats 32f --size 64x48 "
                                        "--conventions zo --out 'my out'");
  EXPECT_TRUE(testing::hasShape(report["started_at"].get<std::string>(), "9999-99-99T99:99:99Z"))
      << report["started_at"];
}

TEST(ReconcileCli, DefaultsToEveryShippedScene) {
  TempFolder folder;
  std::filesystem::create_directory_symlink(kSource + "/scenes", folder.path() / "scenes");
  const auto result = runClipray("reconcile --depth-formats 32f --size 64x48", folder.path());
  ASSERT_EQ(result.status, 0) << result.err << result.out;
  const auto report =
      nlohmann::json::parse(testing::readText(folder.path() / "report/report.json"));
  std::set<std::string> scenes;
  for (const auto& run : report["runs"]) scenes.insert(run["scene"].get<std::string>());
  EXPECT_EQ(scenes.size(), 25u);
  EXPECT_TRUE(scenes.count("depth_clamp"));
  EXPECT_TRUE(scenes.count("object_depth_range"));
  EXPECT_TRUE(scenes.count("object_clip_planes"));
  EXPECT_TRUE(scenes.count("polygon_offset"));
  EXPECT_TRUE(scenes.count("logarithmic_depth"));
  EXPECT_TRUE(scenes.count("water_reflection_clipped"));
  EXPECT_TRUE(scenes.count("reversed_z"));
  EXPECT_TRUE(scenes.count("face_culling"));
  EXPECT_TRUE(scenes.count("water_reflection"));
}

TEST(ReconcileCli, AGltfAssetIsCheckedFromItsOwnCameras) {
  TempFolder folder;
  const auto result = runClipray(
      "reconcile '" + kSource + "/scenes/assets/lantern.gltf' --depth-formats 32f --out out",
      folder.path());
  ASSERT_EQ(result.status, 0) << result.err << result.out;
  const auto report = nlohmann::json::parse(testing::readText(folder.path() / "out/report.json"));
  std::set<std::string> cameras;
  for (const auto& run : report["runs"]) {
    EXPECT_EQ(run["scene"], "lantern");
    EXPECT_EQ(run["verdict"], "consistent");
    cameras.insert(run["camera"].get<std::string>());
  }
  EXPECT_EQ(cameras, (std::set<std::string>{"perspective_camera", "orthographic_camera"}));
  EXPECT_EQ(report["runs"].size(), 4u);  // 2 cameras x (no, zo) x 32f
}

TEST(ReconcileCli, ABadSceneAmongGoodOnesStopsEverythingBeforeAnyOutput) {
  TempFolder folder;
  {
    std::ofstream bad(folder.path() / "bad.json");
    bad << R"({"version": 1, "cameras": [{"name": "main", "viewport": [64, 48],
      "view": {"eye": [0, 0, 5], "target": [0, 0, 0], "up": [0, 1, 0]},
      "projection": {"type": "perspective", "fovYDegrees": 60, "near": -1, "far": 10}}],
      "objects": []})";
  }
  const auto result =
      runClipray("reconcile '" + kSource + "/scenes/standard.json' bad.json", folder.path());
  EXPECT_EQ(result.status, 2);
  EXPECT_EQ(result.err,
            "clipray: bad.json: /cameras/0/projection/near: expected a positive number, got -1\n");
  // Only the scene file itself is there: no report folder, no partial files.
  EXPECT_EQ(std::distance(std::filesystem::directory_iterator(folder.path()),
                          std::filesystem::directory_iterator{}),
            1);
}

TEST(ReconcileCli, TwoScenesWithOneFileNameAreRefused) {
  TempFolder folder;
  std::filesystem::create_directories(folder.path() / "a");
  std::filesystem::create_directories(folder.path() / "b");
  std::filesystem::copy_file(kSource + "/scenes/standard.json", folder.path() / "a/x.json");
  std::filesystem::copy_file(kSource + "/scenes/standard.json", folder.path() / "b/x.json");
  const auto result = runClipray("reconcile a/x.json b/x.json", folder.path());
  EXPECT_EQ(result.status, 2);
  EXPECT_EQ(result.err,
            "clipray: a/x.json and b/x.json: both would write their runs under the report folder "
            "\"x/\" (scene names \"x\" and \"x\"); reconcile them separately, or rename one\n");
  EXPECT_FALSE(std::filesystem::exists(folder.path() / "report"));
}

TEST(ReconcileCli, NamesThatCollideOnceMadeSafeAreRefused) {
  TempFolder folder;
  std::string scene = testing::readText(kSource + "/scenes/standard.json");
  const auto named = [&](const std::string& text, const std::string& from, const std::string& to) {
    std::string out = text;
    out.replace(out.find(from), from.size(), to);
    return out;
  };
  // A second camera "a_b" beside one renamed "a/b".
  nlohmann::json document = nlohmann::json::parse(scene);
  document["cameras"][0]["name"] = "a/b";
  nlohmann::json second = document["cameras"][0];
  second["name"] = "a_b";
  document["cameras"].push_back(second);
  std::ofstream(folder.path() / "cams.json") << document.dump();
  auto result = runClipray("reconcile cams.json", folder.path());
  EXPECT_EQ(result.status, 2);
  EXPECT_EQ(result.err,
            "clipray: cams.json: cameras \"a/b\" and \"a_b\" would share the report folders "
            "\"cams/a_b-...\"; rename one\n");
  std::ofstream(folder.path() / "a b.json") << scene;
  std::ofstream(folder.path() / "a_b.json") << named(scene, "\"main\"", "\"other\"");
  result = runClipray("reconcile 'a b.json' a_b.json", folder.path());
  EXPECT_EQ(result.status, 2);
  EXPECT_EQ(result.err,
            "clipray: a b.json and a_b.json: both would write their runs under the report folder "
            "\"a_b/\" (scene names \"a b\" and \"a_b\"); reconcile them separately, or rename "
            "one\n");
  EXPECT_FALSE(std::filesystem::exists(folder.path() / "report"));
}

struct BadInvocation {
  const char* name;
  std::string arguments;
  std::string environment;
  std::string expectedMessage;
};

// Test names stay readable in ctest output instead of a byte dump.
void PrintTo(const BadInvocation& bad, std::ostream* os) {
  *os << bad.name;
}

class ReconcileBadInput : public ::testing::TestWithParam<BadInvocation> {};

TEST_P(ReconcileBadInput, ExitsTwoWithAMessageAndWritesNothing) {
  TempFolder folder;
  const BadInvocation& bad = GetParam();
  const auto result = runClipray(bad.arguments, folder.path(), bad.environment);
  EXPECT_EQ(result.status, 2) << result.err;
  EXPECT_NE(result.err.find(bad.expectedMessage), std::string::npos)
      << "stderr was: " << result.err;
  EXPECT_TRUE(folderIsEmpty(folder.path())) << "outputs were written";
}

const std::string kStandard = "'" + kSource + "/scenes/standard.json'";

INSTANTIATE_TEST_SUITE_P(
    Messages, ReconcileBadInput,
    ::testing::Values(
        BadInvocation{"MissingScene", "reconcile nope.json", "",
                      "clipray: nope.json: cannot open file"},
        BadInvocation{"NoScenesFolder", "reconcile", "",
                      "clipray: no scene given and there is no scenes/ folder here"},
        BadInvocation{"UnknownConvention", "reconcile " + kStandard + " --conventions no,xo", "",
                      "clipray: --conventions: unknown value \"xo\"; expected a comma-separated "
                      "list of: no, zo, "
                      "zo-reversed"},
        BadInvocation{"ReversedWithClassicDepth",
                      "reconcile " + kStandard + " --conventions no-reversed", "",
                      "clipray: --conventions: unknown value \"no-reversed\""},
        BadInvocation{"UnknownDepthFormat", "reconcile " + kStandard + " --depth-formats 24,32", "",
                      "clipray: --depth-formats: unknown value \"32\"; expected a comma-separated "
                      "list of: 16, 24, 32f"},
        BadInvocation{"UnknownVertexMode", "reconcile " + kStandard + " --vertex-modes local", "",
                      "clipray: --vertex-modes: unknown value \"local\""},
        BadInvocation{
            "ZeroSize", "reconcile " + kStandard + " --size 0x10", "",
            "clipray: --size: expected WxH with positive integers (e.g. 1920x1080), got \"0x10\""},
        BadInvocation{
            "MalformedSize", "reconcile " + kStandard + " --size 640", "",
            "clipray: --size: expected WxH with positive integers (e.g. 1920x1080), got \"640\""},
        BadInvocation{"OversizedViewport", "reconcile " + kStandard + " --size 40000x16", "",
                      "clipray: --size: 40000x16 is larger than 16384x16384, the most this "
                      "takes"},
        BadInvocation{"UnknownBackend", "reconcile " + kStandard + " --backend vulkan", "",
                      "clipray: unknown backend \"vulkan\"; expected one of: osmesa, egl"},
        BadInvocation{"OsMesaUnavailable", "reconcile " + kStandard,
                      "CLIPRAY_OSMESA_LIBRARY=/nonexistent/libOSMesa.so.8",
                      "clipray: OSMesa: cannot load /nonexistent/libOSMesa.so.8"},
        BadInvocation{"NoSubcommand", "", "", "\nclipray: no command given; name one of: "},
        BadInvocation{"UnknownOption", "reconcile --frobnicate", "",
                      "clipray: --frobnicate: unknown option (clipray reconcile --help lists the "
                      "options)\n"},
        BadInvocation{"UnknownImagePolicy", "reconcile " + kStandard + " --images some", "",
                      "--images: unknown value \"some\"; expected one of: failing, all, none"},
        BadInvocation{"UnknownKernels", "reconcile " + kStandard + " --kernels fast", "",
                      "clipray: --kernels: unknown value \"fast\"; expected one of: simd, "
                      "portable"},
        BadInvocation{"JUnitInAMissingFolder",
                      "reconcile " + kStandard + " --junit nowhere/junit.xml", "",
                      "--junit: nowhere/junit.xml: the folder nowhere does not exist"},
        BadInvocation{"JUnitIsAFolder", "reconcile " + kStandard + " --junit .", "",
                      "--junit: . is a folder; name the XML file to write"},
        BadInvocation{"ZeroRounds", "reconcile " + kStandard + " --rounds 0", "",
                      "--rounds: Value 0 not in range 1 to 1000"}),
    [](const ::testing::TestParamInfo<BadInvocation>& param) {
      return std::string(param.param.name);
    });

}  // namespace
}  // namespace clipray
