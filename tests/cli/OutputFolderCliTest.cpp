// Two runs, one --out: the folder is locked for the run that claimed it, a second run fails at
// once naming the holder, and a failing run removes nothing of another run's. --out is checked
// before any work.

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>

#include <nlohmann/json.hpp>

#include "support/RunCommand.hpp"

namespace clipray {
namespace {

using testing::readText;
using testing::runClipray;
using testing::TempFolder;

const std::string kSource = CLIPRAY_SOURCE_DIR;
const std::string kBinary = CLIPRAY_BINARY;
const std::string kStandard = "'" + kSource + "/scenes/standard.json'";

// Every file under a folder with its bytes.
std::map<std::string, std::string> snapshot(const std::filesystem::path& folder) {
  std::map<std::string, std::string> files;
  for (const auto& entry : std::filesystem::recursive_directory_iterator(folder)) {
    if (entry.is_regular_file()) {
      files[std::filesystem::relative(entry.path(), folder).string()] = readText(entry.path());
    }
  }
  return files;
}

TEST(OutputFolder, ARunIntoAFolderAnotherRunHoldsFailsAtOnceAndRemovesNothing) {
  TempFolder folder;
  ASSERT_EQ(runClipray("reconcile " + kStandard + " --size 64x48 --out out", folder.path()).status,
            0);
  const auto before = snapshot(folder.path() / "out");
  ASSERT_TRUE(before.count("report.json"));
  // This process plays the run that holds the folder.
  const int fd = ::open((folder.path() / "out/.clipray.lock").c_str(), O_RDWR);
  ASSERT_GE(fd, 0);
  ASSERT_EQ(::flock(fd, LOCK_EX | LOCK_NB), 0);
  const std::string pid = std::to_string(::getpid());
  ASSERT_EQ(::ftruncate(fd, 0), 0);
  ASSERT_EQ(::pwrite(fd, pid.data(), pid.size(), 0), static_cast<ssize_t>(pid.size()));
  const auto second =
      runClipray("reconcile " + kStandard + " --size 64x48 --images all --out out", folder.path());
  ::close(fd);
  EXPECT_EQ(second.status, 2);
  EXPECT_EQ(second.err, "clipray: --out out: another clipray run (pid " + pid +
                            ") is writing there; wait for it to finish or choose another --out\n");
  auto after = snapshot(folder.path() / "out");
  after.erase(".clipray.lock");  // holds the pid this test wrote
  auto expected = before;
  expected.erase(".clipray.lock");
  EXPECT_EQ(after, expected);
}

TEST(OutputFolder, OfTwoRunsStartedTogetherOneWritesAWholeReportAndTheOtherFails) {
  TempFolder folder;
  // Long enough (several rounds at 640x480) that the two surely overlap.
  const std::string run = "'" + kBinary + "' reconcile " + kStandard +
                          " --size 640x480 --rounds 4 --images all --out out";
  std::ofstream(folder.path() / "both.sh") << "cd '" << folder.path().string() << "'\n(" << run
                                           << " >a.out 2>a.err; echo $? >a.status) &\n(" << run
                                           << " >b.out 2>b.err; echo $? >b.status) &\nwait\n";
  ASSERT_EQ(std::system(("bash '" + (folder.path() / "both.sh").string() + "'").c_str()), 0);
  const std::string a = readText(folder.path() / "a.status");
  const std::string b = readText(folder.path() / "b.status");
  ASSERT_TRUE((a == "0\n" && b == "2\n") || (a == "2\n" && b == "0\n")) << a << b;
  const std::string loserErr = readText(folder.path() / (a == "2\n" ? "a.err" : "b.err"));
  EXPECT_NE(loserErr.find("clipray: --out out: another clipray run (pid "), std::string::npos)
      << loserErr;
  // The winner's report is whole: every file it names exists.
  const auto report = nlohmann::json::parse(readText(folder.path() / "out/report.json"));
  int images = 0;
  for (const auto& runRecord : report["runs"]) {
    for (const auto& [kind, path] : runRecord["images"].items()) {
      EXPECT_TRUE(std::filesystem::exists(folder.path() / "out" / path.get<std::string>())) << path;
      ++images;
    }
  }
  EXPECT_GT(images, 0);
  EXPECT_TRUE(std::filesystem::exists(folder.path() / "out/index.html"));
}

// Ctrl-C while the report is switched in: the switch ends, then the signal takes effect; a kill
// (SIGKILL) half-way is undone by the next run that claims the folder, even one that then fails.
TEST(OutputFolder, AnInterruptDuringTheFinalWriteLeavesAWholeReport) {
  TempFolder folder;
  const std::string first = "reconcile " + kStandard + " --size 64x48 --images all --out out";
  ASSERT_EQ(runClipray(first, folder.path()).status, 0);
  auto previous = snapshot(folder.path() / "out");
  previous.erase(".clipray.lock");
  const std::string second =
      "reconcile " + kStandard + " --size 96x72 --images all --conventions zo --out out";

  auto result = runClipray(second, folder.path(), "CLIPRAY_TEST_SIGNAL_IN_SWITCH=2:3");
  EXPECT_EQ(result.status, 128 + 2);  // died of SIGINT, after the switch
  auto after = snapshot(folder.path() / "out");
  const auto report = nlohmann::json::parse(after.at("report.json"));
  EXPECT_EQ(report["runs"].size(), 2u);  // the new report: zo only
  for (const auto& run : report["runs"]) {
    EXPECT_EQ(run["size"]["width"], 96);
    for (const auto& [kind, path] : run["images"].items()) {
      EXPECT_TRUE(after.count(path.get<std::string>())) << path;
    }
  }
  for (const auto& [path, bytes] : after) {
    EXPECT_EQ(path.find(".clipray-"), std::string::npos) << path;  // no staging left
  }

  // Back to the first report, then a kill half-way through writing the second.
  ASSERT_EQ(runClipray(first, folder.path()).status, 0);
  previous = snapshot(folder.path() / "out");
  previous.erase(".clipray.lock");
  result = runClipray(second, folder.path(), "CLIPRAY_TEST_SIGNAL_IN_SWITCH=9:3");
  EXPECT_EQ(result.status, 128 + 9);
  EXPECT_TRUE(std::filesystem::exists(folder.path() / "out/.clipray-previous"));
  result = runClipray("reconcile nope.json --out out", folder.path());
  EXPECT_EQ(result.status, 2);
  EXPECT_EQ(result.err,
            "clipray: warning: --out out: a run was killed while writing its report there; the "
            "previous report is back in place\nclipray: nope.json: cannot open file\n");
  after = snapshot(folder.path() / "out");
  after.erase(".clipray.lock");
  // Every file of the first report is back; the killed run's new files that replaced nothing
  // (the 96x72 zo images under the same names did replace) may remain beside them.
  for (const auto& [path, bytes] : previous) EXPECT_EQ(after[path], bytes) << path;
  EXPECT_FALSE(std::filesystem::exists(folder.path() / "out/.clipray-previous"));
  EXPECT_FALSE(std::filesystem::exists(folder.path() / "out/.clipray-staging"));
}

TEST(OutputFolder, AnUnusableOutFailsBeforeAnyWorkAndLeavesNothing) {
  TempFolder folder;
  std::ofstream(folder.path() / "file.txt") << "x";
  auto result = runClipray("reconcile " + kStandard + " --out file.txt/out", folder.path());
  EXPECT_EQ(result.status, 2);
  EXPECT_EQ(result.err, "clipray: --out file.txt/out: cannot create folder " +
                            (folder.path() / "file.txt/out").string() + ": Not a directory\n");
  result = runClipray("reconcile " + kStandard + " --out file.txt", folder.path());
  EXPECT_EQ(result.status, 2);
  EXPECT_EQ(result.err, "clipray: --out file.txt: exists and is not a folder\n");
  // A failure after the folder was claimed (a missing scene) removes the folders it created.
  result = runClipray("reconcile nope.json --out new/deeper", folder.path());
  EXPECT_EQ(result.status, 2);
  EXPECT_FALSE(std::filesystem::exists(folder.path() / "new"));
}

}  // namespace
}  // namespace clipray
