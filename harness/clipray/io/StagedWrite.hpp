#pragma once
// Writing a report's files into a folder as one change. Every file is first written into
// <folder>/.clipray-staging/; then, with SIGINT, SIGTERM, SIGHUP and SIGQUIT held back, each one
// is switched in by rename, the file it replaces moved aside into <folder>/.clipray-previous/, the
// file named last (report.json) last of all. A rename that fails puts everything back, so the
// folder holds the previous report, whole; a Ctrl-C waits for the switch to end. Only a kill
// that cannot be caught (SIGKILL, power loss) can stop the switch half-way, and then the next
// write (or recoverInterruptedWrite) moves the previous files back first.

#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

namespace clipray {

struct FileToWrite {
  std::filesystem::path relative;  // under the folder; folders in it are created as needed
  std::string_view bytes;          // must outlive the call
};

// Writes the files into `folder` (created if missing) as described above; the last file is
// switched in last. Throws std::runtime_error naming the file when a write or a rename fails.
void writeFilesAsOne(const std::filesystem::path& folder, const std::vector<FileToWrite>& files);

// Writes all of bytes to an open file descriptor, through short writes and EINTR; returns 0, or the
// errno of the write that failed (the descriptor stays open).
int writeAllBytes(int fd, std::string_view bytes);

// Undoes what a killed writeFilesAsOne left: moves the files set aside in .clipray-previous back
// in place and removes .clipray-staging. Returns whether there was anything to undo.
bool recoverInterruptedWrite(const std::filesystem::path& folder);

}  // namespace clipray
