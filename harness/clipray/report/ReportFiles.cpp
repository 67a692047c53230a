// Writing a report to disk: report.json, summary.txt, index.html and the runs' images switched in
// as one change (StagedWrite.hpp), and single files replaced atomically.

#include <atomic>
#include <cerrno>
#include <cstring>
#include <stdexcept>
#include <string>
#include <system_error>
#include <vector>

#include <fcntl.h>
#include <unistd.h>

#include "clipray/io/StagedWrite.hpp"
#include "clipray/report/HtmlReport.hpp"
#include "clipray/report/Report.hpp"

namespace clipray {

namespace {

// Writes bytes to a fresh temp file beside `path` and returns its name; throws naming `path`.
std::filesystem::path writeTempBeside(const std::filesystem::path& path, const std::string& bytes) {
  static std::atomic<unsigned long long> counter{0};
  std::filesystem::path temp = path;
  temp += ".tmp-" + std::to_string(static_cast<long long>(::getpid())) + "-" +
          std::to_string(counter.fetch_add(1));
  const auto fail = [&](const std::string& what, int error, bool removeTemp) {
    if (removeTemp) ::unlink(temp.c_str());
    throw std::runtime_error("cannot " + what + " " + path.string() + ": " + std::strerror(error));
  };
  const int fd = ::open(temp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
  if (fd < 0) fail("create", errno, false);
  if (const int error = writeAllBytes(fd, bytes); error != 0) {
    ::close(fd);
    fail("write", error, true);
  }
  if (::close(fd) != 0) fail("write", errno, true);
  return temp;
}

}  // namespace

void writeFileAtomically(const std::filesystem::path& path, const std::string& bytes) {
  const std::filesystem::path temp = writeTempBeside(path, bytes);
  std::error_code ec;
  std::filesystem::rename(temp, path, ec);
  if (ec) {
    ::unlink(temp.c_str());
    throw std::runtime_error("cannot write " + path.string() + ": " + ec.message());
  }
}

void writeReport(const std::filesystem::path& outDir, const std::vector<RunRecord>& runs,
                 const GlInfo& gl, const ReportProvenance& provenance) {
  // One change (StagedWrite.hpp): a failure or a Ctrl-C leaves the previous report whole, and
  // report.json, which names the rest, is switched in last.
  const std::string summary = textSummary(runs);
  const std::string html = reportHtml(runs, gl, provenance);
  const std::string json = reportJson(runs, gl, provenance)
                               .dump(2, ' ', false, nlohmann::json::error_handler_t::replace) +
                           "\n";
  std::vector<FileToWrite> files;
  for (const RunRecord& run : runs) {
    for (const EncodedImage& image : run.images) {
      files.push_back({std::filesystem::path(image.relativePath), image.pngBytes});
    }
  }
  files.push_back({"summary.txt", summary});
  files.push_back({"index.html", html});
  files.push_back({"report.json", json});
  writeFilesAsOne(outDir, files);
}

}  // namespace clipray
