// `clipray check --page` (PageCheck.hpp): the browser session. The DevTools commands are the
// protocol's (chromedevtools.github.io/devtools-protocol): Target.getTargets and
// Target.attachToTarget (flatten: one pipe, commands addressed by sessionId), Page.enable (which
// the added script needs to take effect), Page.bringToFront (a page in the background gets
// requestAnimationFrame ticks only now and then), Page.addScriptToEvaluateOnNewDocument,
// Page.navigate (its errorText says why a page did not load), Runtime.evaluate (returnByValue).

#include "clipray/page/PageCheck.hpp"

#include <unistd.h>

#include <cctype>
#include <cstdlib>
#include <filesystem>
#include <sstream>
#include <thread>

#include "clipray/InputError.hpp"
#include "clipray/page/DevToolsPipe.hpp"
#include "clipray/page/PageRecorder.hpp"
#include "clipray/page/PageVerify.hpp"

namespace clipray::page {

namespace {

namespace fs = std::filesystem;

// After the timeout, fetching the recording may take this much longer (a large recording).
constexpr auto kFetchGrace = std::chrono::seconds(15);
constexpr auto kPollInterval = std::chrono::milliseconds(100);
constexpr auto kStartupTimeout = std::chrono::seconds(60);
constexpr auto kFinalPollGrace = std::chrono::seconds(5);

std::string lowercase(std::string text) {
  for (char& c : text) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return text;
}

// RFC 3986's unreserved characters and '/' stay; every other byte is %XX.
std::string percentEncoded(const std::string& path) {
  static const char* hex = "0123456789ABCDEF";
  std::string out;
  for (const char c : path) {
    const auto byte = static_cast<unsigned char>(c);
    if (std::isalnum(byte) || c == '-' || c == '.' || c == '_' || c == '~' || c == '/') {
      out += c;
    } else {
      out += '%';
      out += hex[byte >> 4];
      out += hex[byte & 15];
    }
  }
  return out;
}

std::string percentDecoded(const std::string& text) {
  std::string out;
  for (std::size_t k = 0; k < text.size(); ++k) {
    if (text[k] == '%' && k + 2 < text.size() &&
        std::isxdigit(static_cast<unsigned char>(text[k + 1])) &&
        std::isxdigit(static_cast<unsigned char>(text[k + 2]))) {
      out += static_cast<char>(std::stoi(text.substr(k + 1, 2), nullptr, 16));
      k += 2;
    } else {
      out += text[k];
    }
  }
  return out;
}

void requirePageFile(const std::string& shown, const std::string& path) {
  std::error_code error;
  const fs::file_status status = fs::status(path, error);
  if (error || !fs::exists(status)) throw InputError(shown + ": no such file");
  if (fs::is_directory(status)) throw InputError(shown + ": is a directory, not a page");
  if (!fs::is_regular_file(status)) throw InputError(shown + ": is not a regular file");
  if (access(path.c_str(), R_OK) != 0) throw InputError(shown + ": cannot read file");
}

std::string findChromium() {
  if (const char* chosen = std::getenv("CLIPRAY_CHROMIUM"); chosen && *chosen) {
    if (access(chosen, X_OK) != 0) {
      throw InputError(std::string("chromium not found at ") + chosen +
                       " (CLIPRAY_CHROMIUM): install Debian's package chromium "
                       "(harness/install-deps.sh does)");
    }
    return chosen;
  }
  for (const char* candidate : {"/usr/bin/chromium", "/usr/bin/chromium-browser"}) {
    if (access(candidate, X_OK) == 0) return candidate;
  }
  throw InputError(
      "chromium not found (/usr/bin/chromium): install Debian's package chromium "
      "(harness/install-deps.sh does)");
}

std::string seconds(double value) {
  std::ostringstream out;
  out << value << " s";
  return out.str();
}

// The value of a Runtime.evaluate answer; nullopt where the expression threw.
std::optional<nlohmann::json> evaluated(const nlohmann::json& answer) {
  if (answer.contains("exceptionDetails") || !answer.contains("result")) return std::nullopt;
  return answer["result"].value("value", nlohmann::json());
}

}  // namespace

std::string pageUrl(const std::string& target) {
  if (target.empty()) throw InputError("--page: empty: give an http(s) or file URL or a file");
  std::size_t schemeEnd = 0;
  if (std::isalpha(static_cast<unsigned char>(target[0]))) {
    schemeEnd = 1;
    while (schemeEnd < target.size() &&
           (std::isalnum(static_cast<unsigned char>(target[schemeEnd])) ||
            target[schemeEnd] == '+' || target[schemeEnd] == '-' || target[schemeEnd] == '.')) {
      ++schemeEnd;
    }
  }
  // A scheme (RFC 3986, 3.1) of two letters or more: one letter would be a drive, not a scheme.
  if (schemeEnd >= 2 && schemeEnd < target.size() && target[schemeEnd] == ':') {
    const std::string scheme = lowercase(target.substr(0, schemeEnd));
    if (scheme == "http" || scheme == "https") {
      if (target.compare(schemeEnd, 3, "://") != 0 || target.size() == schemeEnd + 3) {
        throw InputError(target + ": not a URL (" + scheme + "://host/...)");
      }
      return target;
    }
    if (scheme == "file") {
      if (target.compare(schemeEnd, 4, ":///") != 0) {
        throw InputError(target + ": not a local file URL (file:///path)");
      }
      std::string path = target.substr(schemeEnd + 3);
      path = percentDecoded(path.substr(0, path.find_first_of("?#")));
      requirePageFile(target, path);
      return target;
    }
    throw InputError(target + ": not an http(s) or file URL (" + scheme + ":)");
  }
  requirePageFile(target, target);
  std::error_code error;
  const fs::path absolute = fs::absolute(target, error);
  if (error) throw InputError(target + ": " + error.message());
  return "file://" + percentEncoded(absolute.lexically_normal().string());
}

namespace {

// The options' target as a URL; throws InputError for bad options (checkPage's).
std::string checkedUrl(const PageOptions& options) {
  const std::string url = pageUrl(options.target);
  if (!(options.timeoutSeconds > 0.0) || options.timeoutSeconds > 3600.0) {
    throw InputError("--timeout: expected seconds in (0, 3600], got " +
                     seconds(options.timeoutSeconds));
  }
  if (options.frames == 0 || options.frames > 100000) {
    throw InputError("--frames: expected a number of frames from 1 to 100000 with --page");
  }
  return url;
}

}  // namespace

PageCheckResult checkPage(const PageOptions& options, const AfterRecording& after) {
  PageBrowser browser(options);
  return browser.load(options, after);
}

PageBrowser::~PageBrowser() = default;

PageBrowser::PageBrowser(const PageOptions& options) {
  checkedUrl(options);
  const std::string browser = findChromium();
  // The browser's start has its own allowance: --timeout is the page's (a loaded machine takes
  // seconds to start chromium).
  const auto startDeadline = Clock::now() + kStartupTimeout;
  // Software GL: SwiftShader through ANGLE exposes WebGL2 and EXT_clip_control without a GPU or
  // a display. --no-sandbox: chromium's sandbox refuses to run as root (CI's containers).
  // --disable-dev-shm-usage: containers often give /dev/shm 64 MiB, too little for the
  // renderer. The background flags keep animation frames coming at full rate (a headless page
  // counts as hidden to some of chromium's throttles). --allow-file-access-from-files: a file
  // page's module scripts and import maps (three.js from node_modules) load; without it chromium
  // refuses them as cross-origin.
  pipe_ = std::make_unique<DevToolsPipe>(
      browser, std::vector<std::string>{
                   "--headless=new", "--no-sandbox", "--disable-gpu-sandbox",
                   "--use-angle=swiftshader", "--enable-unsafe-swiftshader", "--no-first-run",
                   "--no-default-browser-check", "--disable-extensions", "--mute-audio",
                   "--hide-scrollbars", "--window-size=800,600", "--disable-dev-shm-usage",
                   "--disable-background-timer-throttling", "--disable-renderer-backgrounding",
                   "--disable-backgrounding-occluded-windows", "--allow-file-access-from-files"});
  DevToolsPipe& browserPipe = *pipe_;
  std::string& session = session_;
  try {
    const nlohmann::json targets = browserPipe.call("Target.getTargets", {}, "", startDeadline);
    std::string pageTarget;
    for (const nlohmann::json& info : targets.value("targetInfos", nlohmann::json::array())) {
      if (info.value("type", "") == "page") {
        pageTarget = info.value("targetId", "");
        break;
      }
    }
    if (pageTarget.empty()) {
      pageTarget =
          browserPipe.call("Target.createTarget", {{"url", "about:blank"}}, "", startDeadline)
              .value("targetId", "");
    }
    session = browserPipe
                  .call("Target.attachToTarget", {{"targetId", pageTarget}, {"flatten", true}}, "",
                        startDeadline)
                  .value("sessionId", "");
    browserPipe.call("Page.enable", nlohmann::json::object(), session, startDeadline);
    browserPipe.call("Page.bringToFront", nlohmann::json::object(), session, startDeadline);
  } catch (const DevToolsPipe::TimedOut&) {
    const std::string tail = browserPipe.stderrTail();
    throw InputError("chromium did not answer on the DevTools pipe in " +
                     std::to_string(kStartupTimeout.count()) + " s" +
                     (tail.empty() ? std::string() : "; its stderr ends:\n" + tail));
  }
}

PageCheckResult PageBrowser::load(const PageOptions& options, const AfterRecording& after) {
  const std::string url = checkedUrl(options);
  const std::string timeout = seconds(options.timeoutSeconds);
  DevToolsPipe& browserPipe = *pipe_;
  const std::string& session = session_;
  try {
    const auto ready = Clock::now() + kStartupTimeout;
    // A second load starts from a blank document: navigating to the page's own URL again may be
    // a same-document navigation (a fragment), which would keep the first load's recorder.
    if (loaded_) browserPipe.call("Page.navigate", {{"url", "about:blank"}}, session, ready);
    if (!script_.empty()) {
      browserPipe.call("Page.removeScriptToEvaluateOnNewDocument", {{"identifier", script_}},
                       session, ready);
    }
    script_ =
        browserPipe
            .call("Page.addScriptToEvaluateOnNewDocument",
                  {{"source", pageRecorderScript(options.frames, options.verify, options.three,
                                                 options.toggleReversedDepth)}},
                  session, ready)
            .value("identifier", "");
  } catch (const DevToolsPipe::TimedOut&) {
    throw InputError("chromium did not answer on the DevTools pipe in " +
                     std::to_string(kStartupTimeout.count()) + " s");
  }
  loaded_ = true;
  const auto deadline = Clock::now() + std::chrono::duration_cast<Clock::duration>(
                                           std::chrono::duration<double>(options.timeoutSeconds));
  try {
    const nlohmann::json navigated =
        browserPipe.call("Page.navigate", {{"url", url}}, session, deadline);
    if (navigated.contains("errorText") && !navigated["errorText"].get<std::string>().empty()) {
      throw InputError(options.target + ": does not load (" +
                       navigated["errorText"].get<std::string>() + ")");
    }
  } catch (const DevToolsPipe::TimedOut&) {
    throw InputError(options.target + ": did not load in " + timeout);
  }

  // Wait for the N frames, or the timeout.
  std::uint64_t frames = 0, draws = 0, contexts = 0;
  std::string done;
  bool answered = false;
  const auto poll = [&](Clock::time_point until) {
    try {
      const auto progress = evaluated(browserPipe.call(
          "Runtime.evaluate",
          {{"expression", "typeof __clipray === 'object' ? __clipray.progress() : ''"},
           {"returnByValue", true}},
          session, until));
      if (progress && progress->is_string() && !progress->get<std::string>().empty()) {
        std::istringstream words(progress->get<std::string>());
        words >> frames >> draws >> contexts >> done;
        answered = true;
      }
    } catch (const DevToolsPipe::TimedOut&) {
      // The page's script is busy: what was counted so far says why.
    }
  };
  while (Clock::now() < deadline && done != "true") {
    poll(deadline);
    if (done != "true") std::this_thread::sleep_for(kPollInterval);
  }
  // The last answer may be older than the deadline (a busy page answers late): once more, with
  // what the page did up to now.
  if (done != "true") poll(Clock::now() + kFinalPollGrace);
  if (!answered) throw InputError(options.target + ": did not answer in " + timeout);
  if (contexts == 0 || draws == 0) {
    // The page's first uncaught error says why, often.
    std::string threw;
    try {
      const auto error = evaluated(browserPipe.call(
          "Runtime.evaluate",
          {{"expression", "__clipray.pageErrors.length ? __clipray.pageErrors[0] : ''"},
           {"returnByValue", true}},
          session, Clock::now() + kFinalPollGrace));
      if (error && error->is_string() && !error->get<std::string>().empty()) {
        threw = "; the page threw: " + error->get<std::string>();
      }
    } catch (const DevToolsPipe::TimedOut&) {
    }
    if (contexts == 0) {
      throw InputError(options.target + ": no WebGL context after " + timeout + threw);
    }
    throw InputError(options.target + ": never drew in " + timeout + " (" +
                     std::to_string(contexts) +
                     (contexts == 1 ? " WebGL context)" : " WebGL contexts)") + threw);
  }
  nlohmann::json recording;
  try {
    const auto snapshot = evaluated(browserPipe.call(
        "Runtime.evaluate", {{"expression", "__clipray.snapshot()"}, {"returnByValue", true}},
        session, std::max(deadline, Clock::now()) + kFetchGrace));
    if (snapshot && snapshot->is_string()) {
      recording = nlohmann::json::parse(snapshot->get<std::string>(), nullptr, false);
    }
  } catch (const DevToolsPipe::TimedOut&) {
    throw InputError(options.target + ": the recording could not be fetched in " + timeout +
                     " and 15 s more");
  }
  if (!recording.is_object()) {
    throw InputError(options.target + ": the recording could not be read back from the page");
  }
  // reconcile --page picks on a page whose matrices the state check cannot read.
  PageCheckResult result = checkRecording(options.target, recording, !options.three);
  if (options.verify) {
    nlohmann::json images;
    try {
      const auto read = evaluated(browserPipe.call(
          "Runtime.evaluate", {{"expression", "__clipray.readDepth()"}, {"returnByValue", true}},
          session, Clock::now() + kFetchGrace));
      if (read && read->is_string()) {
        images = nlohmann::json::parse(read->get<std::string>(), nullptr, false);
      }
    } catch (const DevToolsPipe::TimedOut&) {
      // Each group then says it was not verified.
    }
    addDepthImages(result, images);
  }
  if (after) after(browserPipe, session, result);
  return result;
}

}  // namespace clipray::page
