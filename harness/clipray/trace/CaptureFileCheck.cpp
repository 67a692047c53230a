// `clipray check --capture`: runs the capture reader (harness/renderdoc/) on the .rdc file and
// streams its lines from a pipe into the trace checker. The reader's stderr (and RenderDoc's log
// lines) share the pipe: lines that are no JSON object are kept, the last few, to say why a
// reader that wrote no error line failed.

#include "clipray/trace/CaptureFileCheck.hpp"

#include <fcntl.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <deque>
#include <filesystem>
#include <functional>
#include <map>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "clipray/InputError.hpp"
#include "clipray/check/CheckText.hpp"
#include "clipray/io/InputFile.hpp"
#include "clipray/trace/CaptureDraw.hpp"
#include "clipray/trace/CaptureGeometry.hpp"
#include "clipray/trace/ReplayDepth.hpp"

namespace clipray::trace {

namespace {

constexpr int kExecFailed = 127;
// A draw line holds its shaders' text: longer than this is no line the reader writes.
constexpr std::size_t kMaxReaderLineBytes = 64u << 20;
constexpr std::size_t kKeptOtherLines = 8;
constexpr const char* kReaderName = "clipray-capture-reader.py";
constexpr std::size_t kMaxVerifiedGroups = 8;  // as --trace --verify replays at most

std::string environment(const char* name) {
  const char* value = std::getenv(name);
  return value && *value ? value : "";
}

// The reader installed with clipray: beside the binary (the build tree) or in ../share/clipray
// (an installed tree, harness/CMakeLists.txt).
std::string findReader() {
  if (std::string overridden = environment("CLIPRAY_CAPTURE_READER"); !overridden.empty()) {
    if (access(overridden.c_str(), R_OK) != 0) {
      throw InputError("CLIPRAY_CAPTURE_READER: cannot read " + overridden);
    }
    return overridden;
  }
  std::error_code error;
  const std::filesystem::path binary = std::filesystem::read_symlink("/proc/self/exe", error);
  if (!error) {
    for (const std::filesystem::path& candidate :
         {binary.parent_path() / kReaderName,
          binary.parent_path().parent_path() / "share" / "clipray" / kReaderName}) {
      if (access(candidate.c_str(), R_OK) == 0) return candidate.string();
    }
  }
  throw InputError(std::string(kReaderName) +
                   " not found beside the clipray binary or in ../share/clipray (a broken "
                   "install?): set CLIPRAY_CAPTURE_READER to it");
}

// The reader as a child process, its stdout and stderr into one pipe.
class ReaderProcess {
 public:
  explicit ReaderProcess(std::vector<std::string> words) {
    int fds[2];
    if (pipe2(fds, O_CLOEXEC) != 0) {
      throw std::runtime_error("pipe: " + std::string(strerror(errno)));
    }
    pid_ = fork();
    if (pid_ < 0) {
      const int saved = errno;
      close(fds[0]);
      close(fds[1]);
      throw std::runtime_error("fork: " + std::string(strerror(saved)));
    }
    if (pid_ == 0) {
      dup2(fds[1], STDOUT_FILENO);
      dup2(fds[1], STDERR_FILENO);
      // Headless replay on Mesa: EGL's surfaceless platform (no display, no GPU needed).
      setenv("EGL_PLATFORM", "surfaceless", 0);
      std::vector<char*> argv;
      for (std::string& word : words) argv.push_back(word.data());
      argv.push_back(nullptr);
      execvp(argv[0], argv.data());
      _exit(kExecFailed);
    }
    close(fds[1]);
    fd_ = fds[0];
  }
  ReaderProcess(const ReaderProcess&) = delete;
  ReaderProcess& operator=(const ReaderProcess&) = delete;

  ~ReaderProcess() {
    if (fd_ >= 0) close(fd_);
    if (pid_ > 0 && !reaped_) {
      kill(pid_, SIGTERM);
      int status = 0;
      while (waitpid(pid_, &status, 0) < 0 && errno == EINTR) {
      }
    }
  }

  std::size_t read(char* buffer, std::size_t size) {
    while (true) {
      const ssize_t got = ::read(fd_, buffer, size);
      if (got >= 0) return static_cast<std::size_t>(got);
      if (errno != EINTR) {
        throw std::runtime_error("reading the capture reader's output: " +
                                 std::string(strerror(errno)));
      }
    }
  }

  int finish() {
    close(fd_);
    fd_ = -1;
    int status = 0;
    while (waitpid(pid_, &status, 0) < 0 && errno == EINTR) {
    }
    reaped_ = true;
    return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  }

 private:
  pid_t pid_ = -1;
  int fd_ = -1;
  bool reaped_ = false;
};

// Runs the reader on the capture with `arguments`, hands each output line (without its newline)
// to `onLine` and returns the reader's exit status (128 + the signal for one killed).
// RenderDoc 1.24's replay on llvmpipe now and then dies by a signal while it starts: a SIGSEGV
// before its first line, once in about 800 replays of the capture tests. A reader killed by a
// signal before it wrote a JSON line runs once more; a second such death is reported.
int runReader(const std::string& capturePath, const std::vector<std::string>& arguments,
              const std::function<void(std::string_view)>& onLine) {
  std::string python = environment("CLIPRAY_CAPTURE_PYTHON");
  if (python.empty()) python = "/usr/bin/python3";
  std::vector<std::string> words = {python, findReader(), capturePath};
  words.insert(words.end(), arguments.begin(), arguments.end());
  for (int attempt = 0;; ++attempt) {
    ReaderProcess process(words);
    bool wroteJson = false;
    const auto deliver = [&](std::string_view line) {
      wroteJson = wroteJson || line.starts_with("{");
      onLine(line);
    };
    std::string pending;
    std::vector<char> buffer(1 << 16);
    while (const std::size_t got = process.read(buffer.data(), buffer.size())) {
      pending.append(buffer.data(), got);
      std::size_t start = 0;
      for (std::size_t end = pending.find('\n'); end != std::string::npos;
           end = pending.find('\n', start)) {
        deliver(std::string_view(pending).substr(start, end - start));
        start = end + 1;
      }
      pending.erase(0, start);
      if (pending.size() > kMaxReaderLineBytes) {
        throw InputError(capturePath + ": a capture reader line longer than " +
                         std::to_string(kMaxReaderLineBytes) + " bytes");
      }
    }
    if (!pending.empty()) deliver(pending);
    const int status = process.finish();
    if (status == kExecFailed && !wroteJson) {
      throw InputError(
          python +
          ": cannot run Python for the capture reader: install Debian's python3 and "
          "python3-renderdoc (harness/install-deps.sh), or set CLIPRAY_CAPTURE_PYTHON");
    }
    if (status <= 128 || wroteJson || attempt == 1) return status;
  }
}

// What the state model does not follow, listed per draw.
nlohmann::json drawSummary(const nlohmann::json& line, const TraceDraw& draw) {
  nlohmann::json sources = nlohmann::json::array();
  for (const TracedMatrix& matrix : draw.matrices) sources.push_back(matrix.source);
  const nlohmann::json& state = line["state"];
  return {{"event", draw.call},
          {"name", draw.function},
          {"frame", draw.frame},
          {"program", line.value("program", "")},
          {"depth_write", state.value("depth_write", true)},
          {"polygon_offset", state.value("polygon_offset", nlohmann::json(nullptr))},
          {"projections", sources},
          {"shaders", line.value("shaders", nlohmann::json::object())}};
}

class LineReader {
 public:
  LineReader(const std::string& path, std::optional<FrameRange> range)
      : path_(path), range_(range) {}

  void add(std::string_view text) {
    if (!text.starts_with("{")) {
      others_.emplace_back(text);
      if (others_.size() > kKeptOtherLines) others_.pop_front();
      return;
    }
    const nlohmann::json line = nlohmann::json::parse(text, nullptr, false);
    if (line.is_discarded() || !line.is_object()) {
      throw InputError(path_ + ": the capture reader wrote a line that is no JSON object");
    }
    const std::string kind = line.value("kind", "");
    if (kind == "error") throw InputError(line.value("message", path_ + ": capture reader error"));
    if (kind == "capture") {
      result_.api = line.value("api", std::string("OpenGL"));
      result_.events = line.value("events", std::uint64_t{0});
      sawCapture_ = true;
      return;
    }
    if (kind != "draw") return;
    TraceDraw draw;
    try {
      draw = captureDrawOf(line);
    } catch (const std::invalid_argument& error) {
      throw InputError(path_ + ": the capture reader's draw line " +
                       std::to_string(result_.drawsInCapture + 1) + ": " + error.what());
    }
    ++result_.drawsInCapture;
    firstEvent_ = std::min(firstEvent_, draw.call);
    lastEvent_ = std::max(lastEvent_, draw.call);
    if (range_ && (draw.call < range_->first || draw.call > range_->last)) return;
    if (result_.draws.size() < kMaxListedCaptureDraws) {
      result_.draws.push_back(drawSummary(line, draw));
    }
    ++drawsInRange_;
    const nlohmann::json& viewport = line["state"]["viewport"];
    result_.drawStates.push_back({draw, static_cast<int>(std::lround(viewport[0].get<double>())),
                                  static_cast<int>(std::lround(viewport[1].get<double>())),
                                  line["state"].value("depth_target", std::string())});
    framesSeen_ = std::max(framesSeen_, draw.frame + 1);
  }

  std::string otherLines() const {
    std::string text;
    for (const std::string& line : others_) {
      if (!text.empty()) text += " | ";
      text += line;
    }
    return text.empty() ? "no output" : text;
  }

  CaptureCheckResult finish(const std::string& rangeText) {
    if (!sawCapture_) {
      throw InputError(path_ + ": the capture reader wrote nothing (" + otherLines() + ")");
    }
    if (result_.drawsInCapture == 0) throw InputError(path_ + ": no draws in the capture");
    if (range_ && drawsInRange_ == 0) {
      std::string message = path_ + ": --draws " + rangeText + ": no draw in that range (";
      message += "the capture's ";
      message += std::to_string(result_.drawsInCapture);
      message += " draws are events ";
      message += std::to_string(firstEvent_);
      message += "-";
      message += std::to_string(lastEvent_);
      message += ")";
      throw InputError(message);
    }
    result_.drawRange = range_;
    return std::move(result_);
  }

  std::uint64_t framesSeen() const { return framesSeen_; }

 private:
  std::string path_;
  std::optional<FrameRange> range_;
  CaptureCheckResult result_;
  std::deque<std::string> others_;
  bool sawCapture_ = false;
  std::uint64_t drawsInRange_ = 0, framesSeen_ = 0;
  std::uint64_t firstEvent_ = UINT64_MAX, lastEvent_ = 0;
};

}  // namespace

FrameRange parseDrawRange(const std::string& text) {
  return parseNumberRange(text, "--draws", "RenderDoc event IDs");
}

namespace {

// A draw with more than one projective matrix among its uniforms (a camera and a light's or a
// texture's projection): its vertex shader's output positions tell which one gl_Position is
// computed with (fitsClipPositions); the others are left out of the draw's matrices, so that a
// light's projection is not checked as the camera. One info finding per matrix left out.
std::vector<Finding> keepCameraMatrices(const std::string& capturePath,
                                        CaptureCheckResult& result) {
  std::string events;
  for (const CaptureCheckResult::DrawState& state : result.drawStates) {
    if (state.draw.matrices.size() > 1) {
      events += (events.empty() ? "" : ",") + std::to_string(state.draw.call);
    }
  }
  if (events.empty()) return {};
  std::map<std::uint64_t, CapturedDrawGeometry> geometries;
  for (const nlohmann::json& line : readCaptureLines(capturePath, {"--geometry-of", events})) {
    if (line.value("kind", "") != "geometry") continue;
    try {
      CapturedDrawGeometry geometry = capturedDrawGeometry(line);
      geometries[geometry.event] = std::move(geometry);
    } catch (const std::invalid_argument& error) {
      throw InputError(capturePath + ": the capture reader's geometry line: " + error.what());
    }
  }
  std::vector<Finding> findings;
  std::map<std::string, std::uint64_t> reported;  // a source left out, at its first draw
  for (CaptureCheckResult::DrawState& state : result.drawStates) {
    std::vector<TracedMatrix>& matrices = state.draw.matrices;
    const auto geometry = geometries.find(state.draw.call);
    if (matrices.size() < 2 || geometry == geometries.end()) continue;
    std::vector<TracedMatrix> kept;
    std::vector<std::string> leftOut;
    for (const TracedMatrix& matrix : matrices) {
      if (fitsClipPositions(matrix.matrix, geometry->second.clip) == ClipFit::DoesNotFit) {
        leftOut.push_back(matrix.source);
      } else {
        kept.push_back(matrix);
      }
    }
    // Where none fits, which one is the camera is unknown: all stay.
    if (kept.empty() || leftOut.empty()) continue;
    matrices = std::move(kept);
    for (const std::string& source : leftOut) {
      if (!reported.emplace(source, state.draw.call).second) continue;
      findings.push_back(
          {"info", "matrix-not-the-camera",
           source + " (at draw " + std::to_string(state.draw.call) +
               ") is a projection gl_Position is not computed with: the draw's post-vertex-shader "
               "positions do not fit its depth row (z = A w + B), so it is not checked as the "
               "camera (a light's or a projected texture's matrix)",
           ""});
    }
  }
  return findings;
}

}  // namespace

CaptureCheckResult checkCapture(const std::string& capturePath, const std::string& draws) {
  std::optional<FrameRange> range;
  if (!draws.empty()) range = parseDrawRange(draws);
  requireReadableFile(capturePath);
  LineReader lines(capturePath, range);
  const int status = runReader(capturePath, {}, [&](std::string_view line) { lines.add(line); });
  if (status != 0) {
    throw InputError(capturePath + ": the capture reader exited with status " +
                     std::to_string(status) + " (" + lines.otherLines() + ")");
  }
  CaptureCheckResult result = lines.finish(draws);
  std::vector<Finding> notCameras = keepCameraMatrices(capturePath, result);
  TraceCheckCollector collector(capturePath, FrameRange{});
  for (const CaptureCheckResult::DrawState& state : result.drawStates)
    collector.addDraw(state.draw);
  result.check = collector.finish();
  // The collector counts the frames a dump's swaps end; a capture's draws carry their frame.
  result.check.framesSeen = lines.framesSeen();
  result.check.findings.insert(result.check.findings.end(), notCameras.begin(), notCameras.end());
  return result;
}

std::optional<DepthImage> captureDepthImage(const nlohmann::json& line, std::string& failure) {
  if (line.contains("failure")) {
    failure = line.value("failure", std::string("the reader gave no depth"));
    return std::nullopt;
  }
  DepthImage image;
  image.width = line.value("width", 0);
  image.height = line.value("height", 0);
  image.format = "depth format " + line.value("format", std::string("?"));
  const std::string bytes = decodeBase64(line.value("depth", std::string()));
  const std::size_t count = static_cast<std::size_t>(std::max(image.width, 0)) *
                            static_cast<std::size_t>(std::max(image.height, 0));
  if (count == 0 || bytes.size() != 4 * count) {
    failure = "the reader's depth line holds " + std::to_string(bytes.size()) + " bytes for " +
              std::to_string(image.width) + "x" + std::to_string(image.height) + " floats";
    return std::nullopt;
  }
  image.depth.resize(count);
  std::memcpy(image.depth.data(), bytes.data(), bytes.size());  // little-endian, as the host's
  return image;
}

std::vector<nlohmann::json> readCaptureLines(const std::string& capturePath,
                                             const std::vector<std::string>& arguments) {
  std::vector<nlohmann::json> lines;
  std::deque<std::string> others;
  std::string error;
  const int status = runReader(capturePath, arguments, [&](std::string_view text) {
    const nlohmann::json line =
        text.starts_with("{") ? nlohmann::json::parse(text, nullptr, false) : nlohmann::json();
    if (!line.is_object()) {
      if (!text.empty()) others.emplace_back(text);
      if (others.size() > kKeptOtherLines) others.pop_front();
    } else if (line.value("kind", "") == "error") {
      error = line.value("message", capturePath + ": capture reader error");
    } else if (line.value("kind", "") != "capture") {
      lines.push_back(line);
    }
  });
  if (!error.empty()) throw InputError(error);
  if (status != 0) {
    std::string text;
    for (const std::string& line : others) text += (text.empty() ? "" : " | ") + line;
    throw InputError(capturePath + ": the capture reader exited with status " +
                     std::to_string(status) + " (" + (text.empty() ? "no output" : text) + ")");
  }
  return lines;
}

void verifyCapture(const std::string& capturePath, CaptureCheckResult& result) {
  result.check.verifiedBy = "replayed by RenderDoc";
  std::vector<TracePairGroup*> verified;
  std::string events;
  for (TracePairGroup& group : result.check.groups) {
    const bool textureSpace =
        std::any_of(group.report.findings.begin(), group.report.findings.end(),
                    [](const Finding& f) { return f.code == "texture-space-matrix"; });
    if (!group.unusable.empty() || textureSpace) continue;
    if (verified.size() == kMaxVerifiedGroups) {
      group.verifyObservations.push_back("not replayed: at most " +
                                         std::to_string(kMaxVerifiedGroups) + " groups are");
      continue;
    }
    verified.push_back(&group);
    events += (events.empty() ? "" : ",") + std::to_string(group.first.completedAtCall);
  }
  if (verified.empty()) return;
  std::map<std::uint64_t, nlohmann::json> depthLines;
  std::string others;
  const int status = runReader(capturePath, {"--depth-after", events}, [&](std::string_view text) {
    const nlohmann::json line =
        text.starts_with("{") ? nlohmann::json::parse(text, nullptr, false) : nlohmann::json();
    if (line.is_object() && line.value("kind", "") == "depth") {
      depthLines[line.value("event", std::uint64_t{0})] = line;
    } else if (line.is_object() && line.value("kind", "") == "error") {
      others = line.value("message", std::string());
    } else if (!text.empty() && others.size() < 400) {
      others += (others.empty() ? "" : " | ") + std::string(text);
    }
  });
  for (TracePairGroup* group : verified) {
    const std::uint64_t event = group->first.completedAtCall;
    std::string failure;
    std::optional<DepthImage> image;
    const auto found = depthLines.find(event);
    if (found == depthLines.end()) {
      failure = "the capture reader exited with status " + std::to_string(status) + " (" +
                (others.empty() ? std::string("no output") : others) + ")";
    } else {
      try {
        image = captureDepthImage(found->second, failure);
      } catch (const std::invalid_argument& error) {
        failure = error.what();
      }
    }
    if (!image) {
      group->verifyObservations.push_back("not verified: " + failure);
      group->verify = {{"call", event}, {"failure", failure}};
      continue;
    }
    const DepthUse use = analyseDepthUse(*image, *group);
    group->verifyObservations = use.observations;
    group->verify = depthUseJson(use);
  }
}

nlohmann::json captureCheckJson(const CaptureCheckResult& result) {
  nlohmann::json json = traceCheckJson(result.check);
  json["tool"] = "clipray check --capture";
  json.erase("trace");
  json["capture"] = {
      {"file", result.check.traceName},
      {"api", result.api},
      {"events", result.events},
      {"draws_in_capture", result.drawsInCapture},
      {"draw_range", result.drawRange
                         ? nlohmann::json::array({result.drawRange->first, result.drawRange->last})
                         : nlohmann::json(nullptr)}};
  json["draw_list"] = result.draws;
  return json;
}

std::string captureCheckText(const CaptureCheckResult& result) {
  std::string text = traceCheckText(result.check);
  // The shared report names its input a trace; here it is a capture, its calls event IDs.
  if (text.starts_with("trace ")) text.replace(0, 5, "capture");
  text += "calls are RenderDoc event IDs (EIDs)\n";
  for (const nlohmann::json& draw : result.draws) {
    const nlohmann::json& offset = draw["polygon_offset"];
    text += "  draw ";
    text += std::to_string(draw["event"].get<std::uint64_t>());
    text += " ";
    text += draw["name"].get<std::string>();
    text += ": ";
    text += draw["program"].get<std::string>();
    text += draw["depth_write"].get<bool>() ? ", depth writes on" : ", depth writes off";
    if (offset.is_object() &&
        (offset.value("factor", 0.0) != 0.0 || offset.value("units", 0.0) != 0.0)) {
      text += ", polygon offset ";
      text += detail::checkNumber(offset.value("factor", 0.0));
      text += ", ";
      text += detail::checkNumber(offset.value("units", 0.0));
    }
    text += "\n";
  }
  return text;
}

}  // namespace clipray::trace
