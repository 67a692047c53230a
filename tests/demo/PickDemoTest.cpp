// clipray-pick without a person: scripted clicks under Xvfb, checked against the library (the
// analytic ray) and OSMesa (the id buffer) on the standard scene, and bad input. The pieces that
// need no window are in PickDemoUnitTest.cpp.

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iterator>
#include <sstream>

#include "GlfwBackend.hpp"
#include "PickDemo.hpp"
#include "PickScript.hpp"
#include "ThreeWayPick.hpp"
#include "XvfbServer.hpp"
#include "clipray/InputError.hpp"
#include "clipray/engine/ReconcileRun.hpp"
#include "clipray/gl/GlContext.hpp"
#include "clipray/gl/Renderer.hpp"
#include "clipray/rays/RayMethods.hpp"
#include "clipray/rays/RobustRays.hpp"
#include "support/RunCommand.hpp"
#include "support/VersionLine.hpp"

namespace clipray {
namespace {

using testing::TempFolder;
using testing::XvfbServer;

const std::string kSource = CLIPRAY_SOURCE_DIR;
const std::string kStandard = kSource + "/scenes/standard.json";

// Runs clipray-pick in `folder` with `environment` prefixed (shell words).
testing::CommandResult runPick(const std::string& arguments, const std::filesystem::path& folder,
                               const std::string& environment) {
  const std::filesystem::path out = folder / ".stdout.txt", err = folder / ".stderr.txt";
  const std::string command = "cd '" + folder.string() + "' && " + environment + " timeout 120 '" +
                              std::string(CLIPRAY_PICK_BINARY) + "' " + arguments + " >'" +
                              out.string() + "' 2>'" + err.string() + "'";
  const int raw = std::system(command.c_str());
  testing::CommandResult result;
  result.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
  result.out = testing::readText(out);
  result.err = testing::readText(err);
  std::filesystem::remove(out);
  std::filesystem::remove(err);
  return result;
}

std::vector<nlohmann::json> jsonLines(const std::string& text) {
  std::vector<nlohmann::json> lines;
  std::istringstream stream(text);
  std::string line;
  while (std::getline(stream, line)) {
    if (!line.empty()) lines.push_back(nlohmann::json::parse(line));
  }
  return lines;
}

void writeText(const std::filesystem::path& path, const std::string& text) {
  std::ofstream(path) << text;
}

// What the library says about a pixel of the standard scene's camera at 320x240 under ZO: the
// robust ray's hit and OSMesa's id (the demo draws through the same renderer).
struct Expected {
  int rayObject = -1;
  glm::dvec3 rayPoint{0.0};
  int idObject = -1;
};

class StandardSceneReference {
 public:
  StandardSceneReference()
      : scene_(loadScene(kStandard)),
        clipFromWorld_(scene_.cameras[0].clipFromWorld(kZeroToOne, kViewport)),
        reference_(engine::nearPlaneCentre(clipFromWorld_, kZeroToOne)),
        intersector_(scene_, reference_),
        ids_(scene_) {
    std::unique_ptr<gl::GlContext> context = gl::createOsMesaContext();
    gl::Renderer renderer(*context);
    gl::RenderRequest request;
    request.scene = &scene_;
    request.clipFromWorld = clipFromWorld_;
    request.mode = kZeroToOne;
    request.depthFormat = DepthFormat::Float32;
    request.vertexReference = reference_;
    request.viewport = kViewport;
    raster_ = renderer.render(request);
  }

  Expected at(glm::ivec2 pixel) const {
    Expected e;
    const Ray ray = RobustRayGenerator(clipFromWorld_, kZeroToOne)
                        .generateForPixel(pixel.x, pixel.y, kViewport);
    const Hit hit = intersector_.closestHit(ray);
    if (hit.hit()) {
      e.rayObject = ids_.decode(hit.primitiveId).object;
      e.rayPoint = ray.origin + hit.t * ray.direction;
    }
    e.idObject = idObjectAt(pixel);
    return e;
  }
  int idObjectAt(glm::ivec2 pixel) const {
    return ids_.decode(raster_.ids[static_cast<std::size_t>(pixel.y) * kViewport.width + pixel.x])
        .object;
  }
  nlohmann::json name(int object) const {
    if (object < 0) return nullptr;
    return scene_.objects[static_cast<std::size_t>(object)].name;
  }
  // A pixel on the box's silhouette against the ground: the box at (i, j), the ground at (i+1, j).
  glm::ivec2 boxEdgePixel() const {
    for (int j = kViewport.height / 2; j < kViewport.height; ++j) {
      for (int i = 0; i + 1 < kViewport.width; ++i) {
        if (idObjectAt({i, j}) == 1 && idObjectAt({i + 1, j}) == 0) return {i, j};
      }
    }
    return {-1, -1};
  }

  static constexpr Viewport kViewport{320, 240};

 private:
  Scene scene_;
  glm::dmat4 clipFromWorld_;
  glm::dvec3 reference_;
  SceneIntersector intersector_;
  PrimitiveIdTable ids_;
  RasterFrame raster_;
};

// The cursor position (top-left origin, window units = pixels under Xvfb) inside pixel (i, j),
// off-centre so that the test also checks the pixel is found by flooring, not rounding.
std::string clickInside(glm::ivec2 pixel, int height) {
  std::ostringstream line;
  line << "click " << pixel.x + 0.2 << " " << (height - 1 - pixel.y) + 0.7 << "\n";
  return line.str();
}

// Clicks inside pixels (20 + k step, 20 + l step) of a 320x240 framebuffer, short of its right
// and top edges: row by row from the bottom.
std::string clickGrid320x240(int step) {
  std::string script;
  for (int j = 20; j < 240; j += step) {
    for (int i = 20; i < 320; i += step) script += clickInside({i, j}, 240);
  }
  return script;
}

class PickDemoUnderX : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!xvfb_.running()) GTEST_SKIP() << xvfb_.failure();
  }
  testing::CommandResult run(const std::string& arguments, const std::string& script) {
    writeText(folder_.path() / "script.txt", script);
    return runPick(arguments + " --script script.txt", folder_.path(),
                   "DISPLAY=" + xvfb_.display() + " LIBGL_ALWAYS_SOFTWARE=1");
  }
  XvfbServer xvfb_;
  TempFolder folder_;
};

TEST_F(PickDemoUnderX, ScriptedPicksAgreeWithTheLibraryAndTheIdBuffer) {
  const StandardSceneReference reference;
  const glm::ivec2 boxCentre{160, 119}, background{5, 234};
  const glm::ivec2 edge = reference.boxEdgePixel();
  ASSERT_GE(edge.x, 0) << "no box/ground edge found";
  const auto result = run(
      "'" + kStandard + "' --size 320x240 --convention zo --depth-format 32f --precision double",
      clickInside(boxCentre, 240) + clickInside(edge, 240) + clickInside(background, 240));
  ASSERT_EQ(result.status, 0) << result.err;
  const std::vector<nlohmann::json> picks = jsonLines(result.out);
  ASSERT_EQ(picks.size(), 3u) << result.out;

  const glm::ivec2 pixels[] = {boxCentre, edge, background};
  for (std::size_t k = 0; k < 3; ++k) {
    const nlohmann::json& p = picks[k];
    const Expected e = reference.at(pixels[k]);
    SCOPED_TRACE(p.dump());
    EXPECT_EQ(p["pixel"], nlohmann::json::array({pixels[k].x, pixels[k].y}));
    EXPECT_EQ(p["framebuffer"], nlohmann::json::array({320, 240}));
    EXPECT_EQ(p["method"], "robust");
    EXPECT_EQ(p["precision"], "double");
    EXPECT_EQ(p["convention"], "zo");
    EXPECT_EQ(p["depth_format"], "32f");
    EXPECT_EQ(p["ray"]["object"], reference.name(e.rayObject));
    EXPECT_EQ(p["id"]["object"], reference.name(e.idObject));
    EXPECT_EQ(p["same_object"], e.rayObject == e.idObject);
    if (e.rayObject >= 0) {
      for (int c = 0; c < 3; ++c) {
        EXPECT_NEAR(p["ray"]["point"][c].get<double>(), e.rayPoint[c], 1e-12);
      }
    }
  }
  // The box's middle: all three agree, and the depth readback lands within a pixel of the hit.
  EXPECT_EQ(picks[0]["ray"]["object"], "box");
  EXPECT_EQ(picks[0]["agree"], true);
  EXPECT_LT(picks[0]["gap_px"].get<double>(), 0.1);
  EXPECT_LT(picks[0]["gap_world"].get<double>(), 1e-3);
  // The edge pixel: the id buffer says box (that is how it was chosen), the ray decides for itself.
  EXPECT_EQ(picks[1]["id"]["object"], "box");
  // The background: nothing anywhere.
  EXPECT_TRUE(picks[2]["ray"]["object"].is_null());
  EXPECT_TRUE(picks[2]["ray"]["point"].is_null());
  EXPECT_TRUE(picks[2]["depth"]["point"].is_null());
  EXPECT_TRUE(picks[2]["id"]["object"].is_null());
  EXPECT_TRUE(picks[2]["gap_world"].is_null());
  EXPECT_TRUE(picks[2]["gap_px"].is_null());
  EXPECT_EQ(picks[2]["agree"], true);
}

TEST_F(PickDemoUnderX, TeleportMakesTwoPointDriftWhileRobustHolds) {
  // Camera-relative vertices keep the raster honest 1e5 from the origin; only the rays differ.
  // robust double, then M twice: unproject_glm float, two_point float.
  const auto result =
      run("'" + kStandard + "' --size 320x240 --vertex-mode camera-relative --precision double",
          "click 160 120\nkey t\nclick 160 120\nkey m\nkey m\nclick 160 120\n");
  ASSERT_EQ(result.status, 0) << result.err;
  const std::vector<nlohmann::json> picks = jsonLines(result.out);
  ASSERT_EQ(picks.size(), 3u) << result.out;
  EXPECT_EQ(picks[0]["teleported"], false);
  EXPECT_EQ(picks[1]["teleported"], true);
  EXPECT_EQ(picks[1]["method"], "robust");
  EXPECT_EQ(picks[2]["method"], "two_point");
  EXPECT_EQ(picks[2]["precision"], "float");
  for (const auto& p : picks) EXPECT_EQ(p["ray"]["object"], "box") << p.dump();
  EXPECT_NEAR(picks[1]["ray"]["point"][0].get<double>(), 1e5, 10.0);
  // robust: the same sub-pixel gap at the origin and 1e5 away; two_point: pixels off.
  EXPECT_LT(picks[0]["gap_px"].get<double>(), 0.1);
  EXPECT_LT(picks[1]["gap_px"].get<double>(), 0.1);
  EXPECT_GT(picks[2]["gap_px"].get<double>(), 1.0);
}

// M cycles through every method of the ray library in float, then robust double, and wraps.
TEST_F(PickDemoUnderX, KeyMCyclesEveryLibraryMethod) {
  const StandardSceneReference reference;
  const glm::ivec2 boxCentre{160, 119};
  ASSERT_EQ(reference.idObjectAt(boxCentre), 1);  // the box
  std::string script = clickInside(boxCentre, 240);
  for (std::size_t k = 0; k < std::size(demo::kDemoRayChoices); ++k) {
    script += "key m\n" + clickInside(boxCentre, 240);
  }
  const auto result = run("'" + kStandard +
                              "' --size 320x240 --convention zo --depth-format 32f "
                              "--method unproject_glm",
                          script);
  ASSERT_EQ(result.status, 0) << result.err;
  const std::vector<nlohmann::json> picks = jsonLines(result.out);
  const std::size_t count = std::size(demo::kDemoRayChoices);
  ASSERT_EQ(picks.size(), count + 1) << result.out;
  const char* const expected[] = {"unproject_glm", "two_point",   "inverse_pv",
                                  "fov_tangent",   "plane_cross", "plane_cross_pre",
                                  "full",          "robust",      "robust"};
  ASSERT_EQ(std::size(expected), count);
  for (std::size_t k = 0; k <= count; ++k) {
    const nlohmann::json& p = picks[k];
    SCOPED_TRACE(p.dump());
    EXPECT_EQ(p["method"], expected[k % count]);
    EXPECT_EQ(p["precision"], k % count == count - 1 ? "double" : "float");
    EXPECT_EQ(p["pixel"], nlohmann::json::array({boxCentre.x, boxCentre.y}));
    EXPECT_EQ(p["id"]["object"], "box");
    // The standard camera supplies projection, view and fov scalars: every method runs.
    ASSERT_TRUE(p["ray"].is_object());
    if (p["method"] == "plane_cross" || p["method"] == "plane_cross_pre") {
      // Seed 002's listings 2 and 3 have no sign fix: for a right-handed camera mx x my points
      // backwards, so the ray leaves the scene behind the camera and hits nothing.
      EXPECT_TRUE(p["ray"]["object"].is_null());
      EXPECT_EQ(p["agree"], false);
    } else {
      EXPECT_EQ(p["ray"]["object"], p["id"]["object"]);
      EXPECT_EQ(p["agree"], true);
      EXPECT_LT(p["gap_px"].get<double>(), 0.1);
    }
  }
}

TEST_F(PickDemoUnderX, TeleportedTwoPointFloatDriftsWhileRobustFloatHolds) {
  // From two_point, M six times reaches robust (float), once more robust double.
  const auto result =
      run("'" + kStandard +
              "' --size 320x240 --convention zo --depth-format 32f --vertex-mode camera-relative "
              "--method two_point",
          "key t\nclick 160 120\nkey m\nkey m\nkey m\nkey m\nkey m\nkey m\nclick 160 120\n"
          "key m\nclick 160 120\n");
  ASSERT_EQ(result.status, 0) << result.err;
  const std::vector<nlohmann::json> picks = jsonLines(result.out);
  ASSERT_EQ(picks.size(), 3u) << result.out;
  const nlohmann::json &twoPoint = picks[0], &robust = picks[1], &robustDouble = picks[2];
  EXPECT_EQ(twoPoint["method"], "two_point");
  EXPECT_EQ(robust["method"], "robust");
  EXPECT_EQ(robust["precision"], "float");
  EXPECT_EQ(robustDouble["precision"], "double");
  for (const auto& p : picks) {
    EXPECT_EQ(p["teleported"], true);
    EXPECT_EQ(p["ray"]["object"], "box") << p.dump();
  }
  // two_point inverts a float matrix with 1e5 in it: the ray lands pixels off the surface. The
  // objects match (the box is large), so only the pixel offset tells: "apart", not "agree".
  EXPECT_GT(twoPoint["gap_px"].get<double>(), 1.0);
  EXPECT_EQ(twoPoint["same_object"], true);
  EXPECT_EQ(twoPoint["agree"], false);
  EXPECT_GT(twoPoint["ray_offset_px"].get<double>(), demo::kPickAgreementPixels);
  EXPECT_EQ(twoPoint["verdict"], "apart");
  EXPECT_EQ(robust["verdict"], "agree");
  EXPECT_EQ(robust["agree"], true);
  EXPECT_LT(robust["ray_offset_px"].get<double>(), demo::kPickAgreementPixels);
  EXPECT_EQ(robustDouble["verdict"], "agree");
  // robust float is as good as float allows 1e5 from the origin: float spacing there is
  // u = 2^-7; the matrix handed over in float and the float origin each place the ray within half
  // a spacing per coordinate, so the hit moves by at most sqrt(3) u (about 0.0135 world units,
  // half a pixel's footprint here). robust double removes even that.
  const double u = std::ldexp(1.0, -7);
  EXPECT_LT(robust["gap_world"].get<double>(), std::sqrt(3.0) * u);
  EXPECT_LT(robust["gap_px"].get<double>(), 1.0);
  EXPECT_LT(robust["gap_px"].get<double>(), twoPoint["gap_px"].get<double>());
  EXPECT_LT(robustDouble["gap_px"].get<double>(), 0.1);
}

// The coplanar scene z-fights by design: where the ray and the id buffer name different quads,
// the reconcile counts the pixel as depth-ambiguous, and so must the demo, instead of "DISAGREE".
TEST_F(PickDemoUnderX, CoplanarMismatchesAreAmbiguousAsTheReconcileSays) {
  const std::string script = clickGrid320x240(20);
  const auto result = run("'" + kSource +
                              "/scenes/coplanar.json' --size 320x240 --convention zo "
                              "--depth-format 24",
                          script);
  ASSERT_EQ(result.status, 0) << result.err;
  const std::vector<nlohmann::json> picks = jsonLines(result.out);
  ASSERT_EQ(picks.size(), 11u * 15u) << result.out;
  int mismatches = 0, agreements = 0;
  for (const nlohmann::json& p : picks) {
    SCOPED_TRACE(p.dump());
    if (p["same_object"] == false) {
      ++mismatches;
      EXPECT_EQ(p["agree"], false);
      EXPECT_EQ(p["reconcile_class"], "id_depth_ambiguous");
      EXPECT_EQ(p["verdict"], "ambiguous");
    } else {
      // The same object (reconcile_class is set only where the primitives differ).
      ++agreements;
      EXPECT_EQ(p["verdict"], "agree");
      if (!p["ray_offset_px"].is_null()) {
        EXPECT_LT(p["ray_offset_px"].get<double>(), demo::kPickAgreementPixels);
      }
    }
  }
  EXPECT_GT(mismatches, 0);
  EXPECT_GT(agreements, 0);
}

// A weapon drawn in glDepthRange(0, 0.1) before a world in [0.1, 1]: the depth readback undoes
// the range of the object the id buffer names, so it lands where the ray does (unprojected through
// the scene's [0, 1], the wall's depths came back 55 pixel footprints short).
TEST_F(PickDemoUnderX, TheDepthReadbackUndoesEachObjectsDepthRange) {
  const std::string script = clickGrid320x240(40);
  const auto result = run("'" + kSource +
                              "/scenes/object_depth_range.json' --size 320x240 --convention zo "
                              "--depth-format 24",
                          script);
  ASSERT_EQ(result.status, 0) << result.err;
  const std::vector<nlohmann::json> picks = jsonLines(result.out);
  ASSERT_EQ(picks.size(), 6u * 8u) << result.out;
  std::set<std::string> objects;
  for (const nlohmann::json& p : picks) {
    SCOPED_TRACE(p.dump());
    if (p["gap_px"].is_null()) continue;
    objects.insert(p["id"]["object"].get<std::string>());
    EXPECT_LT(p["gap_px"].get<double>(), demo::kPickAgreementPixels);
  }
  EXPECT_EQ(objects, (std::set<std::string>{"ground", "wall", "weapon"}));
}

TEST_F(PickDemoUnderX, KeysSwitchConventionAndDepthFormat) {
  const auto result = run("'" + kStandard + "' --size 320x240",
                          "key c\nclick 160 120\nkey c\nkey d\nclick 160 120\n");
  ASSERT_EQ(result.status, 0) << result.err;
  const std::vector<nlohmann::json> picks = jsonLines(result.out);
  ASSERT_EQ(picks.size(), 2u) << result.out;
  EXPECT_EQ(picks[0]["convention"], "zo-reversed");
  EXPECT_EQ(picks[0]["depth_format"], "24");
  EXPECT_EQ(picks[1]["convention"], "no");
  EXPECT_EQ(picks[1]["depth_format"], "32f");
  for (const auto& p : picks) {
    EXPECT_EQ(p["ray"]["object"], "box");
    EXPECT_EQ(p["agree"], true);
    EXPECT_LT(p["gap_px"].get<double>(), 0.5) << p.dump();
  }
  // Reversed-Z stores the near surfaces deeper (closer to 1).
  EXPECT_GT(picks[0]["depth"]["window_depth"].get<double>(), 0.0);
  EXPECT_LT(picks[0]["depth"]["window_depth"].get<double>(), 0.5);
}

TEST_F(PickDemoUnderX, ResizeChangesTheFramebufferAndThePixelUnderTheCursor) {
  const auto result = run("'" + kStandard + "' --size 320x240 --screenshot shot.png",
                          "resize 400 300\nclick 200.5 150.5\n");
  ASSERT_EQ(result.status, 0) << result.err;
  const std::vector<nlohmann::json> picks = jsonLines(result.out);
  ASSERT_EQ(picks.size(), 1u) << result.out;
  EXPECT_EQ(picks[0]["framebuffer"], nlohmann::json::array({400, 300}));
  EXPECT_EQ(picks[0]["pixel"], nlohmann::json::array({200, 149}));
  // The screenshot is a PNG of the resized framebuffer (IHDR width and height, big-endian).
  const std::string png = testing::readText(folder_.path() / "shot.png");
  ASSERT_GT(png.size(), 24u);
  EXPECT_EQ(png.substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8));
  auto be32 = [&](std::size_t at) {
    return (static_cast<unsigned char>(png[at]) << 24) |
           (static_cast<unsigned char>(png[at + 1]) << 16) |
           (static_cast<unsigned char>(png[at + 2]) << 8) | static_cast<unsigned char>(png[at + 3]);
  };
  EXPECT_EQ(be32(16), 400);
  EXPECT_EQ(be32(20), 300);
}

// glClipControl(GL_UPPER_LEFT, ...) with the y-down projection such an app builds shows the same
// upright picture: a click picks the same object at the same depth as under zo, exactly. O switches
// the origin in a running demo as --convention zo-upper-left sets it at the start.
TEST_F(PickDemoUnderX, UpperLeftOriginPicksWhatLowerLeftPicks) {
  const StandardSceneReference reference;
  const glm::ivec2 boxCentre{160, 119}, ground{60, 40};
  ASSERT_EQ(reference.idObjectAt(boxCentre), 1);  // the box
  ASSERT_EQ(reference.idObjectAt(ground), 0);     // the ground
  const std::string clicks = clickInside(boxCentre, 240) + clickInside(ground, 240);
  const std::string options =
      "'" + kStandard + "' --size 320x240 --depth-format 32f --precision double";
  const auto lowerThenUpper = run(options + " --convention zo", clicks + "key o\n" + clicks);
  ASSERT_EQ(lowerThenUpper.status, 0) << lowerThenUpper.err;
  const auto upper = run(options + " --convention zo-upper-left", clicks);
  ASSERT_EQ(upper.status, 0) << upper.err;
  std::vector<nlohmann::json> picks = jsonLines(lowerThenUpper.out);
  ASSERT_EQ(picks.size(), 4u) << lowerThenUpper.out;
  for (const nlohmann::json& p : jsonLines(upper.out)) picks.push_back(p);
  ASSERT_EQ(picks.size(), 6u) << upper.out;

  const char* const objects[] = {"box", "ground"};
  for (std::size_t k = 0; k < picks.size(); ++k) {
    const nlohmann::json& p = picks[k];
    const nlohmann::json& lowerLeft = picks[k % 2];
    SCOPED_TRACE(p.dump());
    const bool upperLeft = k >= 2;
    EXPECT_EQ(p["convention"], upperLeft ? "zo-upper-left" : "zo");
    EXPECT_EQ(p["clip_origin"], upperLeft ? "upper-left" : "lower-left");
    EXPECT_EQ(p["clip_planes"], 0);
    EXPECT_EQ(p["ray"]["object"], objects[k % 2]);
    EXPECT_EQ(p["id"]["object"], objects[k % 2]);
    EXPECT_EQ(p["verdict"], "agree");
    // The same pixel, ray, hit and stored depth as under zo, to the last bit.
    for (const char* field : {"pixel", "ray", "depth", "id", "gap_world", "ray_offset_px"}) {
      EXPECT_EQ(p[field], lowerLeft[field]) << field;
    }
    const Expected e = reference.at(k % 2 == 0 ? boxCentre : ground);
    for (int c = 0; c < 3; ++c) {
      EXPECT_NEAR(p["ray"]["point"][c].get<double>(), e.rayPoint[c], 1e-12);
    }
  }
}

// A raw clipFromWorld is drawn as it is: under an upper-left origin GL puts its NDC y = -1 on the
// top row, so the picture is upside down, pixel row j showing what row 239 - j shows under a
// lower-left origin. The picks follow the picture there too.
TEST_F(PickDemoUnderX, UpperLeftOriginTurnsARawMatrixUpsideDownAndThePicksFollow) {
  const std::string scene = kSource + "/scenes/water_reflection_clipped.json";
  const glm::ivec2 pixel{120, 101}, mirrored{120, 239 - 101};
  const auto result = run(
      "'" + scene + "' --size 320x240 --convention no --depth-format 32f --precision double",
      clickInside(pixel, 240) + "key o\n" + clickInside(mirrored, 240) + clickInside(pixel, 240));
  ASSERT_EQ(result.status, 0) << result.err;
  const std::vector<nlohmann::json> picks = jsonLines(result.out);
  ASSERT_EQ(picks.size(), 3u) << result.out;
  const nlohmann::json &lower = picks[0], &upperMirrored = picks[1], &upperSame = picks[2];
  EXPECT_EQ(lower["convention"], "no");
  EXPECT_EQ(upperMirrored["convention"], "no-upper-left");
  EXPECT_EQ(upperMirrored["clip_origin"], "upper-left");
  EXPECT_EQ(upperMirrored["pixel"], nlohmann::json::array({mirrored.x, mirrored.y}));
  EXPECT_EQ(lower["id"]["object"], "tower");
  EXPECT_EQ(upperMirrored["id"]["object"], lower["id"]["object"]);
  // The mirrored row's clip y' is the negation of the original's up to its rounding (1 - a is not
  // always a - 1 negated bit for bit), so the hit agrees to a few ulps, not to the last bit.
  EXPECT_EQ(upperMirrored["ray"]["object"], lower["ray"]["object"]);
  for (int c = 0; c < 3; ++c) {
    EXPECT_NEAR(upperMirrored["ray"]["point"][c].get<double>(),
                lower["ray"]["point"][c].get<double>(), 1e-12);
  }
  EXPECT_EQ(upperMirrored["depth"]["window_depth"], lower["depth"]["window_depth"]);
  EXPECT_NE(upperSame["id"]["object"], lower["id"]["object"]);
  for (const nlohmann::json& p : picks) EXPECT_EQ(p["verdict"], "agree") << p.dump();
}

// The water reflection is drawn with a clip plane at the water (gl_ClipDistance = y): the
// submerged box and the sea floor, between the mirrored eye and the water, are not in the picture.
// A click on the tower's reflection must pick the tower, not the submerged box in front of it, and
// a click below the horizon nothing, not the sea floor; with every method, two_point float too.
TEST_F(PickDemoUnderX, ClipPlanesCutThePicksWhereTheyCutThePicture) {
  const std::string path = kSource + "/scenes/water_reflection_clipped.json";
  const glm::ivec2 tower{120, 101}, belowHorizon{160, 210};
  {
    // What the clicks would find without the cut (the library's robust rays, uncut and cut).
    const Scene scene = loadScene(path);
    const Camera& camera = scene.cameras[0];
    const Viewport viewport{320, 240};
    const glm::dmat4 clipFromWorld = camera.clipFromWorld(kNegativeOneToOne, viewport);
    const SceneIntersector intersector(scene,
                                       engine::nearPlaneCentre(clipFromWorld, kNegativeOneToOne));
    const PrimitiveIdTable ids(scene);
    auto objectHit = [&](const RobustRayGenerator& rays, glm::ivec2 pixel) -> std::string {
      const Hit hit = intersector.closestHit(rays.generateForPixel(pixel.x, pixel.y, viewport));
      return hit.hit()
                 ? scene.objects[static_cast<std::size_t>(ids.decode(hit.primitiveId).object)].name
                 : "background";
    };
    const RobustRayGenerator uncut(clipFromWorld, kNegativeOneToOne);
    const RobustRayGenerator cut(clipFromWorld, kNegativeOneToOne, camera.clipPlanes);
    ASSERT_EQ(objectHit(uncut, tower), "submerged");
    ASSERT_EQ(objectHit(cut, tower), "tower");
    ASSERT_EQ(objectHit(uncut, belowHorizon), "sea_floor");
    ASSERT_EQ(objectHit(cut, belowHorizon), "background");
  }
  // robust double, then M twice: unproject_glm float (n/a without a separate view), two_point.
  const auto result =
      run("'" + path + "' --size 320x240 --convention no --depth-format 32f --precision double",
          clickInside(tower, 240) + clickInside(belowHorizon, 240) + "key m\nkey m\n" +
              clickInside(tower, 240));
  ASSERT_EQ(result.status, 0) << result.err;
  const std::vector<nlohmann::json> picks = jsonLines(result.out);
  ASSERT_EQ(picks.size(), 3u) << result.out;
  EXPECT_EQ(picks[2]["method"], "two_point");
  EXPECT_EQ(picks[2]["precision"], "float");
  for (std::size_t k : {0u, 2u}) {
    const nlohmann::json& p = picks[k];
    SCOPED_TRACE(p.dump());
    EXPECT_EQ(p["clip_planes"], 1);
    EXPECT_EQ(p["pixel"], nlohmann::json::array({tower.x, tower.y}));
    EXPECT_EQ(p["ray"]["object"], "tower");
    EXPECT_EQ(p["id"]["object"], "tower");
    EXPECT_EQ(p["verdict"], "agree");
    // The hit lies on the kept side of the water.
    EXPECT_GT(p["ray"]["point"][1].get<double>(), 0.0);
    EXPECT_LT(p["gap_px"].get<double>(), 0.5);
  }
  const nlohmann::json& below = picks[1];
  SCOPED_TRACE(below.dump());
  EXPECT_EQ(below["clip_planes"], 1);
  EXPECT_TRUE(below["ray"]["object"].is_null());
  EXPECT_TRUE(below["id"]["object"].is_null());
  EXPECT_TRUE(below["depth"]["point"].is_null());
  EXPECT_EQ(below["verdict"], "agree");
}

// The teleport moves the clip planes with the scene: the standard camera cut at x = 0 (keeping
// x <= 0) shows the ground through the cut half of the box, at the origin and 1e5 away alike.
TEST_F(PickDemoUnderX, TeleportMovesTheClipPlanesWithTheScene) {
  const StandardSceneReference reference;
  const glm::ivec2 cutBox{175, 128};
  ASSERT_EQ(reference.at(cutBox).rayObject, 1);  // the box, uncut
  nlohmann::json scene = nlohmann::json::parse(testing::readText(kStandard));
  scene["cameras"][0]["clipPlanes"] = nlohmann::json::array({{-1.0, 0.0, 0.0, 0.0}});
  writeText(folder_.path() / "standard-cut.json", scene.dump());
  const auto result =
      run("standard-cut.json --size 320x240 --convention zo --depth-format 32f --precision double "
          "--vertex-mode camera-relative",
          clickInside(cutBox, 240) + "key t\n" + clickInside(cutBox, 240));
  ASSERT_EQ(result.status, 0) << result.err;
  const std::vector<nlohmann::json> picks = jsonLines(result.out);
  ASSERT_EQ(picks.size(), 2u) << result.out;
  for (const nlohmann::json& p : picks) {
    SCOPED_TRACE(p.dump());
    EXPECT_EQ(p["clip_planes"], 1);
    EXPECT_EQ(p["ray"]["object"], "ground");
    EXPECT_EQ(p["id"]["object"], "ground");
    EXPECT_EQ(p["verdict"], "agree");
  }
  EXPECT_EQ(picks[0]["teleported"], false);
  EXPECT_EQ(picks[1]["teleported"], true);
  // The same ground point, moved by the teleport.
  EXPECT_NEAR(picks[1]["ray"]["point"][0].get<double>(),
              picks[0]["ray"]["point"][0].get<double>() + demo::kTeleportDistance, 1e-6);
  for (int c = 1; c < 3; ++c) {
    EXPECT_NEAR(picks[1]["ray"]["point"][c].get<double>(),
                picks[0]["ray"]["point"][c].get<double>(), 1e-6);
  }
}

// Bad input is reported before any window opens: these run without a display on purpose.
struct BadPick {
  const char* name;
  std::string arguments;
  std::string script;  // written to script.txt when not empty
  std::string expected;
};

void PrintTo(const BadPick& bad, std::ostream* os) {
  *os << bad.name;
}

class PickBadInput : public ::testing::TestWithParam<BadPick> {};

TEST_P(PickBadInput, ExitsTwoWithAMessageBeforeAnyWindow) {
  TempFolder folder;
  const BadPick& bad = GetParam();
  if (!bad.script.empty()) writeText(folder.path() / "script.txt", bad.script);
  const auto result = runPick(bad.arguments, folder.path(), "env -u DISPLAY -u WAYLAND_DISPLAY");
  EXPECT_EQ(result.status, 2) << result.err;
  EXPECT_EQ(result.err.rfind(bad.expected, 0), 0u) << "stderr was: " << result.err;
  EXPECT_TRUE(result.out.empty()) << result.out;
}

INSTANTIATE_TEST_SUITE_P(
    Messages, PickBadInput,
    ::testing::Values(
        BadPick{"MissingScene", "nope.json", "", "clipray-pick: nope.json: cannot open file\n"},
        BadPick{"MalformedScene", "script.txt", "not json",
                "clipray-pick: script.txt: "},  // the scene loader's own message follows
        BadPick{"UnknownScriptCommand", "'" + kStandard + "' --script script.txt",
                "click 1 2\ntap 3 4\n",
                "clipray-pick: script.txt:2: unknown command \"tap\"; expected one of: resize, "
                "click, drag, scroll, key\n"},
        BadPick{"ScriptNumber", "'" + kStandard + "' --script script.txt", "click 1 y\n",
                "clipray-pick: script.txt:1: y: expected a number, got \"y\"\n"},
        BadPick{"ScriptKey", "'" + kStandard + "' --script script.txt", "key z\n",
                "clipray-pick: script.txt:1: key: expected one of c, o, d, m, v, t, r, h, p, "
                "got \"z\"\n"},
        BadPick{"MissingScript", "'" + kStandard + "' --script none.txt", "",
                "clipray-pick: none.txt: cannot open file\n"},
        BadPick{"UnknownConvention", "'" + kStandard + "' --convention xo", "",
                "clipray-pick: --convention: unknown value \"xo\"; expected one of: no, zo, "
                "zo-reversed (each also with -upper-left)\n"},
        // Reversed-Z needs ZERO_TO_ONE, under either origin.
        BadPick{"NoReversedUpperLeft", "'" + kStandard + "' --convention no-reversed-upper-left",
                "",
                "clipray-pick: --convention: unknown value \"no-reversed-upper-left\"; expected "
                "one of: no, zo, zo-reversed (each also with -upper-left)\n"},
        BadPick{"UnknownDepthFormat", "'" + kStandard + "' --depth-format 32", "",
                "clipray-pick: --depth-format: unknown value \"32\"; expected one of: 16, 24, "
                "32f\n"},
        BadPick{"UnknownMethod", "'" + kStandard + "' --method robust-double", "",
                "clipray-pick: --method: unknown value \"robust-double\"; expected one of: "
                "unproject_glm, two_point, inverse_pv, fov_tangent, plane_cross, "
                "plane_cross_pre, full, robust\n"},
        BadPick{"UnknownPrecision", "'" + kStandard + "' --precision half", "",
                "clipray-pick: --precision: unknown value \"half\"; expected one of: float, "
                "double\n"},
        BadPick{"ScreenshotFolder", "'" + kStandard + "' --screenshot no/such/shot.png", "",
                "clipray-pick: --screenshot: no/such/shot.png: folder no/such does not exist\n"},
        BadPick{"NoDisplay", "'" + kStandard + "'", "",
                "clipray-pick: GLFW: no display available ("},
        // The option parser's errors read the same: one line, with "did you mean".
        BadPick{"MisspeltOption", "--sise 960x640", "",
                "clipray-pick: --sise: unknown option; did you mean --size? (clipray-pick --help "
                "lists the options)\n"},
        BadPick{"OptionWithoutValue", "'" + kStandard + "' --size", "",
                "clipray-pick: --size: expected a value\n"}),
    [](const ::testing::TestParamInfo<BadPick>& param) { return std::string(param.param.name); });

TEST(PickDemoNoDisplay, VersionNeedsNoDisplay) {
  TempFolder folder;
  const auto result = runPick("--version", folder.path(), "DISPLAY=");
  EXPECT_EQ(result.status, 0) << result.err;
  EXPECT_TRUE(testing::parseVersionLine(result.out, "clipray-pick").has_value()) << result.out;
}

TEST(PickDemoNoDisplay, SaysSoAndWritesNoScreenshot) {
  TempFolder folder;
  const auto result = runPick("'" + kStandard + "' --screenshot shot.png", folder.path(),
                              "env -u DISPLAY -u WAYLAND_DISPLAY");
  EXPECT_EQ(result.status, 2);
  EXPECT_NE(result.err.find("run inside a desktop session, or under xvfb-run"), std::string::npos)
      << result.err;
  EXPECT_FALSE(std::filesystem::exists(folder.path() / "shot.png"));
}

// The one place where window coordinates become framebuffer pixels: scale, then flip y once.
}  // namespace
}  // namespace clipray
