// A report's files written as one change: a failing rename puts the previous files back, a
// Ctrl-C during the switch waits for it to end, and what a SIGKILL leaves half-way is undone by
// the next write. The signals are sent by a forked child to itself, at a chosen point of the
// switch (CLIPRAY_TEST_SIGNAL_IN_SWITCH).

#include <sys/wait.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "clipray/io/StagedWrite.hpp"

namespace clipray {
namespace {

namespace fs = std::filesystem;

fs::path freshFolder(const std::string& name) {
  const fs::path folder =
      fs::temp_directory_path() / ("clipray-staged-" + name + "-" + std::to_string(::getpid()));
  fs::remove_all(folder);
  fs::create_directories(folder);
  return folder;
}

std::map<std::string, std::string> filesUnder(const fs::path& folder) {
  std::map<std::string, std::string> files;
  for (const auto& entry : fs::recursive_directory_iterator(folder)) {
    if (!entry.is_regular_file()) continue;
    std::ifstream in(entry.path(), std::ios::binary);
    std::stringstream bytes;
    bytes << in.rdbuf();
    files[fs::relative(entry.path(), folder).generic_string()] = bytes.str();
  }
  return files;
}

// An earlier report: three images and report.json.
const std::vector<std::string> kOld = {"old a", "old b", "old c", "{\"old\": true}"};
const std::vector<std::string> kNew = {"new a", "new b", "new c", "{\"new\": true}"};

std::vector<FileToWrite> reportFiles(const std::vector<std::string>& bytes) {
  return {{"run1/a.png", bytes[0]},
          {"run1/b.png", bytes[1]},
          {"run2/c.png", bytes[2]},
          {"report.json", bytes[3]}};
}

const std::map<std::string, std::string> kOldFiles = {{"run1/a.png", "old a"},
                                                      {"run1/b.png", "old b"},
                                                      {"run2/c.png", "old c"},
                                                      {"report.json", "{\"old\": true}"}};

// Runs writeFilesAsOne in a child that sends itself `signal` after `renames` files were switched
// in; returns the child's wait status.
int writeInChildWithSignal(const fs::path& folder, int signal, int renames) {
  const pid_t child = ::fork();
  if (child == 0) {
    const std::string injected = std::to_string(signal) + ":" + std::to_string(renames);
    ::setenv("CLIPRAY_TEST_SIGNAL_IN_SWITCH", injected.c_str(), 1);
    try {
      writeFilesAsOne(folder, reportFiles(kNew));
    } catch (...) {
      ::_exit(3);
    }
    ::_exit(0);
  }
  int status = 0;
  ::waitpid(child, &status, 0);
  return status;
}

TEST(StagedWrite, WritesEveryFileAndLeavesNoStaging) {
  const fs::path folder = freshFolder("plain");
  writeFilesAsOne(folder / "out", reportFiles(kOld));
  EXPECT_EQ(filesUnder(folder / "out"), kOldFiles);
  writeFilesAsOne(folder / "out", reportFiles(kNew));
  EXPECT_EQ(filesUnder(folder / "out").at("run2/c.png"), "new c");
  EXPECT_EQ(filesUnder(folder / "out").size(), 4u);
  fs::remove_all(folder);
}

TEST(StagedWrite, AFailingRenamePutsThePreviousReportBackWhole) {
  const fs::path folder = freshFolder("failing");
  writeFilesAsOne(folder, reportFiles(kOld));
  std::ofstream(folder / "blocker") << "a file where the new report wants a folder";
  std::vector<FileToWrite> files = reportFiles(kNew);
  // After two files are switched in, the third cannot be: its folder is a file.
  files.insert(files.begin() + 2, FileToWrite{"blocker/d.png", "new d"});
  try {
    writeFilesAsOne(folder, files);
    FAIL() << "no error";
  } catch (const std::runtime_error& error) {
    EXPECT_NE(std::string(error.what()).find((folder / "blocker/d.png").string()),
              std::string::npos)
        << error.what();
  }
  auto expected = kOldFiles;
  expected["blocker"] = "a file where the new report wants a folder";
  EXPECT_EQ(filesUnder(folder), expected);  // no .clipray-staging, no .clipray-previous
  fs::remove_all(folder);
}

TEST(StagedWrite, ACtrlCDuringTheSwitchWaitsForItToEnd) {
  const fs::path folder = freshFolder("sigint");
  writeFilesAsOne(folder, reportFiles(kOld));
  const int status = writeInChildWithSignal(folder, SIGINT, 2);
  ASSERT_TRUE(WIFSIGNALED(status)) << status;
  EXPECT_EQ(WTERMSIG(status), SIGINT);
  const auto files = filesUnder(folder);
  EXPECT_EQ(files.size(), 4u);
  EXPECT_EQ(files.at("report.json"), "{\"new\": true}");
  EXPECT_EQ(files.at("run2/c.png"), "new c");
  fs::remove_all(folder);
}

TEST(StagedWrite, WhatAKillLeavesHalfWayIsUndoneByTheNextWrite) {
  const fs::path folder = freshFolder("sigkill");
  writeFilesAsOne(folder, reportFiles(kOld));
  const int status = writeInChildWithSignal(folder, SIGKILL, 2);
  ASSERT_TRUE(WIFSIGNALED(status)) << status;
  EXPECT_EQ(WTERMSIG(status), SIGKILL);
  // Half-way: two new images in place, the old ones aside, the rest still staged.
  EXPECT_EQ(filesUnder(folder).at("run1/a.png"), "new a");
  EXPECT_TRUE(fs::exists(folder / ".clipray-previous/run1/a.png"));
  EXPECT_TRUE(fs::exists(folder / ".clipray-staging/report.json"));
  EXPECT_TRUE(recoverInterruptedWrite(folder));
  EXPECT_EQ(filesUnder(folder), kOldFiles);
  EXPECT_FALSE(recoverInterruptedWrite(folder));
  // And a write over a half-way folder starts by undoing it.
  ASSERT_TRUE(WIFSIGNALED(writeInChildWithSignal(folder, SIGKILL, 3)));
  writeFilesAsOne(folder, reportFiles(kNew));
  EXPECT_EQ(filesUnder(folder).at("report.json"), "{\"new\": true}");
  EXPECT_EQ(filesUnder(folder).size(), 4u);
  fs::remove_all(folder);
}

}  // namespace
}  // namespace clipray
