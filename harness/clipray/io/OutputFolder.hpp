#pragma once
// The --out folder of one `clipray reconcile`, claimed before any work is done: created if missing
// (and then remembered as this run's), proven writable, and locked, so that a second run into the
// same folder fails at once instead of mixing its files with this one's. The lock is an exclusive
// flock(2) on <out>/.clipray.lock, released by the kernel however the process ends, so a killed
// run never leaves a folder locked. A run that fails removes only what it created.

#include <filesystem>
#include <string>
#include <vector>

namespace clipray {

class OutputFolder {
 public:
  // Throws InputError naming `option` (the field that named the folder: --out, or the library's
  // ReconcileOptions: reportDirectory) and the folder: not a folder, cannot be created, not
  // writable, or held by another run ("another clipray run (pid 123) is writing there").
  explicit OutputFolder(const std::filesystem::path& folder, const std::string& option = "--out");
  // Releases the lock. Unless committed, removes the lock file and the folders this run created,
  // where they are empty (a failed run's own files are removed by writeReport).
  ~OutputFolder();
  OutputFolder(const OutputFolder&) = delete;
  OutputFolder& operator=(const OutputFolder&) = delete;

  const std::filesystem::path& path() const { return folder_; }
  // Whether claiming the folder found a report write that a kill had stopped half-way, and put
  // the previous report back (recoverInterruptedWrite).
  bool recoveredInterruptedWrite() const { return recovered_; }
  // The report is written: keep the folder.
  void commit() { committed_ = true; }

 private:
  // What the destructor does; also the constructor's way out when it throws.
  void release();

  std::filesystem::path folder_;
  std::vector<std::filesystem::path> created_;  // outermost first
  int lockFd_ = -1;
  bool createdLockFile_ = false;
  bool committed_ = false;
  bool recovered_ = false;
};

}  // namespace clipray
