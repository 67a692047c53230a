// `clipray check --page`'s target as the URL the browser loads, without a browser: http(s) and
// file URLs as given, a local file as an absolute file URL, anything else refused by name.

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "clipray/InputError.hpp"
#include "clipray/page/PageCheck.hpp"
#include "support/RunCommand.hpp"

namespace clipray::page {
namespace {

namespace fs = std::filesystem;

std::string refusal(const std::string& target) {
  try {
    pageUrl(target);
  } catch (const InputError& error) {
    return error.what();
  }
  return "(accepted)";
}

TEST(PageUrl, HttpAndHttpsUrlsAreLoadedAsGiven) {
  EXPECT_EQ(pageUrl("http://localhost:8000/index.html"), "http://localhost:8000/index.html");
  EXPECT_EQ(pageUrl("HTTPS://example.com/a?b#c"), "HTTPS://example.com/a?b#c");
  EXPECT_EQ(refusal("http://"), "http://: not a URL (http://host/...)");
  EXPECT_EQ(refusal("http:example.com"), "http:example.com: not a URL (http://host/...)");
}

TEST(PageUrl, OtherSchemesAreRefusedByName) {
  EXPECT_EQ(refusal("ftp://example.com/page.html"),
            "ftp://example.com/page.html: not an http(s) or file URL (ftp:)");
  EXPECT_EQ(refusal("data:text/html,<canvas>"),
            "data:text/html,<canvas>: not an http(s) or file URL (data:)");
  EXPECT_EQ(refusal("about:blank"), "about:blank: not an http(s) or file URL (about:)");
  EXPECT_EQ(refusal(""), "--page: empty: give an http(s) or file URL or a file");
}

TEST(PageUrl, FilesBecomeAbsoluteFileUrls) {
  testing::TempFolder folder;
  const fs::path page = folder.path() / "my page #1.html";
  std::ofstream(page) << "<canvas></canvas>";
  // Spaces and '#' percent-encoded: the URL names the file, not a fragment.
  const std::string url = "file://" + folder.path().string() + "/my%20page%20%231.html";
  EXPECT_EQ(pageUrl(page.string()), url);
  EXPECT_EQ(pageUrl(url), url);  // a file URL whose file exists: as given
  EXPECT_EQ(refusal((folder.path() / "missing.html").string()),
            (folder.path() / "missing.html").string() + ": no such file");
  EXPECT_EQ(refusal("file://" + folder.path().string() + "/missing.html"),
            "file://" + folder.path().string() + "/missing.html: no such file");
  EXPECT_EQ(refusal(folder.path().string()),
            folder.path().string() + ": is a directory, not a page");
  EXPECT_EQ(refusal("file://host/page.html"),
            "file://host/page.html: not a local file URL (file:///path)");
}

}  // namespace
}  // namespace clipray::page
