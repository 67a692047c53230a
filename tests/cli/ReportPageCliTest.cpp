// index.html as a person gets it: a real reconcile's page loaded in a headless browser (Debian's
// chromium, harness/install-deps.sh). The page must show every run, resolve every image from the
// output folder alone, and name the known clusters of an inconsistent scene. The screenshot is
// kept in build/<preset>/tests/report-page/<test>/ for a person to look at.

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <cstdlib>
#include <filesystem>
#include <set>
#include <string>
#include <vector>

#define STB_IMAGE_STATIC
#define STB_IMAGE_IMPLEMENTATION
#include <stb_image.h>

#include "support/RunCommand.hpp"

namespace clipray {
namespace {

namespace fs = std::filesystem;
using testing::readText;
using testing::runClipray;

const std::string kSource = CLIPRAY_SOURCE_DIR;

// Runs a shell command with its stdout to `out`; returns the exit status.
int shell(const std::string& command, const fs::path& out) {
  const int raw = std::system((command + " >'" + out.string() + "' 2>/dev/null").c_str());
  return WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
}

std::string chromium() {
  for (const char* candidate : {"/usr/bin/chromium", "/usr/bin/chromium-browser"}) {
    if (fs::exists(candidate)) return candidate;
  }
  return "";
}

// Every value of attribute `name` in the markup, in order.
std::vector<std::string> attributes(const std::string& html, const std::string& name) {
  std::vector<std::string> values;
  const std::string key = " " + name + "=\"";
  for (std::size_t at = html.find(key); at != std::string::npos; at = html.find(key, at + 1)) {
    const std::size_t begin = at + key.size();
    values.push_back(html.substr(begin, html.find('"', begin) - begin));
  }
  return values;
}

std::size_t occurrences(const std::string& text, const std::string& part) {
  std::size_t n = 0;
  for (std::size_t at = text.find(part); at != std::string::npos; at = text.find(part, at + 1)) ++n;
  return n;
}

class ReportPage : public ::testing::Test {
 protected:
  void SetUp() override {
    browser_ = chromium();
    ASSERT_FALSE(browser_.empty())
        << "chromium is not installed: harness/install-deps.sh installs it (Debian's chromium)";
    // One folder per test (ctest may run them at once), kept after the test.
    folder_ = fs::path(CLIPRAY_TEST_OUTPUT_DIR) / "report-page" /
              ::testing::UnitTest::GetInstance()->current_test_info()->name();
    fs::remove_all(folder_);
    fs::create_directories(folder_);
  }
  // Loads out/index.html in the browser: its DOM after loading, and a screenshot.
  std::string load(const fs::path& out, const fs::path& screenshot) {
    const std::string flags = "'" + browser_ +
                              "' --headless --no-sandbox --disable-gpu --hide-scrollbars "
                              "--no-first-run --user-data-dir='" +
                              (folder_ / "profile").string() + "' ";
    const std::string url = "'file://" + (out / "index.html").string() + "'";
    EXPECT_EQ(shell(flags + "--dump-dom " + url, folder_ / "dom.html"), 0);
    EXPECT_EQ(
        shell(flags + "--window-size=1400,2400 --screenshot='" + screenshot.string() + "' " + url,
              folder_ / "screenshot.log"),
        0);
    fs::remove_all(folder_ / "profile");  // the browser's own cache, nothing to look at
    return readText(folder_ / "dom.html");
  }
  std::string browser_;
  fs::path folder_;
};

TEST_F(ReportPage, ShowsEveryRunAndItsClustersAndEveryImageResolves) {
  // Two inconsistent runs (the water reflection under zo-reversed) and two consistent ones.
  const auto result = runClipray("reconcile '" + kSource +
                                     "/scenes/water_reflection.json' --conventions zo,zo-reversed "
                                     "--depth-formats 32f --size 64x48 --out out",
                                 folder_);
  ASSERT_EQ(result.status, 1) << result.err;
  const fs::path out = folder_ / "out";
  const std::string dom = load(out, folder_ / "screenshot.png");
  ASSERT_NE(dom.find("<h1>clipray reconcile</h1>"), std::string::npos) << dom;

  // One row per run, the inconsistent ones first.
  EXPECT_EQ(occurrences(dom, "<tr class=\"run "), 4u);
  const std::vector<std::string> order = attributes(dom, "data-run");
  const std::vector<std::string> expectedOrder = {
      // the rows, worst first
      "water_reflection/reflection_zo-zo-reversed-32f-world",
      "water_reflection/reflection_no-zo-reversed-32f-world",
      "water_reflection/reflection_zo-zo-32f-world",
      "water_reflection/reflection_no-zo-32f-world",
      // then the cluster sections of the inconsistent runs
      "water_reflection/reflection_zo-zo-reversed-32f-world",
      "water_reflection/reflection_no-zo-reversed-32f-world",
  };
  EXPECT_EQ(order, expectedOrder);
  EXPECT_NE(dom.find("<p id=\"verdict\" class=\"verdict inconsistent\">inconsistent: 4 runs, 2 "
                     "consistent, 2 inconsistent</p>"),
            std::string::npos);

  // Every image the browser was asked to show is a file under the output folder: 8 thumbnails
  // and 5 crops.
  const std::vector<std::string> sources = attributes(dom, "src");
  EXPECT_EQ(sources.size(), 13u);
  for (const std::string& source : sources) {
    EXPECT_EQ(source.find(':'), std::string::npos) << source;  // relative: no scheme
    EXPECT_TRUE(fs::is_regular_file(out / source)) << source;
  }
  for (const std::string& link : attributes(dom, "href")) {
    if (link.starts_with("#")) continue;
    EXPECT_TRUE(fs::is_regular_file(out / link)) << link;
  }

  // The clusters of the known scene: 4 and 1, the largest first, in both coordinate systems.
  EXPECT_EQ(occurrences(dom, "<tr class=\"cluster\""), 5u);
  EXPECT_NE(dom.find("<tr class=\"cluster\" data-pixels=\"115\" data-gl-x=\"24\" "
                     "data-gl-y=\"15\" data-image-x=\"24\" data-image-y=\"32\">"),
            std::string::npos);
  EXPECT_NE(dom.find("<tr class=\"cluster\" data-pixels=\"25\" data-gl-x=\"25\" "
                     "data-gl-y=\"7\" data-image-x=\"25\" data-image-y=\"40\">"),
            std::string::npos);
  // The same as report.json's.
  const auto report = nlohmann::json::parse(readText(out / "report.json"));
  const auto& worst = report["runs"][3];  // reflection_zo under zo-reversed, in run order
  ASSERT_EQ(worst["camera"], "reflection_zo");
  ASSERT_EQ(worst["convention"], "zo-reversed");
  EXPECT_EQ(worst["cluster_count"], 4);
  EXPECT_EQ(worst["clusters"][0]["pixel_gl"], nlohmann::json::parse(R"({"x": 24, "y": 15})"));
  EXPECT_EQ(worst["clusters"][0]["pixel_image"], nlohmann::json::parse(R"({"x": 24, "y": 32})"));

  // The legend: every class, the heat-map scale and the depth colours.
  for (const char* entry :
       {"agree", "depth_beyond_tolerance", "coverage_edge_ambiguous", "coverage_unexplained",
        "id_depth_ambiguous", "id_edge_ambiguous", "id_unexplained", "background", "outline"}) {
    EXPECT_NE(dom.find("<tr data-class=\"" + std::string(entry) + "\">"), std::string::npos)
        << entry;
  }
  EXPECT_NE(dom.find("id=\"legend-heatmap\""), std::string::npos);
  EXPECT_NE(dom.find("id=\"legend-depth\""), std::string::npos);
  EXPECT_EQ(dom.find("id=\"no-images\""), std::string::npos);

  // The browser drew the images: the crops of the coverage clusters are mostly pure red, which the
  // page's own CSS shows only in one 28 x 16 legend swatch.
  int width = 0, height = 0, channels = 0;
  stbi_uc* pixels = stbi_load((folder_ / "screenshot.png").c_str(), &width, &height, &channels, 3);
  ASSERT_NE(pixels, nullptr) << "no screenshot";
  EXPECT_EQ(width, 1400);
  EXPECT_EQ(height, 2400);
  std::size_t red = 0;
  for (std::size_t i = 0; i < static_cast<std::size_t>(width) * height; ++i) {
    red += pixels[3 * i] == 255 && pixels[3 * i + 1] == 0 && pixels[3 * i + 2] == 0;
  }
  stbi_image_free(pixels);
  EXPECT_GT(red, 10000u);
}

TEST_F(ReportPage, WithoutImagesThePageSaysSoAndStillNamesTheClusters) {
  const auto result = runClipray("reconcile '" + kSource +
                                     "/scenes/water_reflection.json' --conventions zo-reversed "
                                     "--depth-formats 32f --size 64x48 --images none --out none",
                                 folder_);
  ASSERT_EQ(result.status, 1) << result.err;
  const std::string dom = load(folder_ / "none", folder_ / "screenshot-none.png");
  EXPECT_NE(dom.find("id=\"no-images\""), std::string::npos) << dom;
  EXPECT_TRUE(attributes(dom, "src").empty());
  EXPECT_EQ(occurrences(dom, "<tr class=\"run "), 2u);
  EXPECT_EQ(occurrences(dom, "<tr class=\"cluster\""), 5u);
  // Nothing but report.json, summary.txt and index.html (and the lock of --out).
  std::set<std::string> files;
  for (const auto& entry : fs::recursive_directory_iterator(folder_ / "none")) {
    files.insert(fs::relative(entry.path(), folder_ / "none").string());
  }
  EXPECT_EQ(files,
            (std::set<std::string>{".clipray.lock", "index.html", "report.json", "summary.txt"}));
}

}  // namespace
}  // namespace clipray
