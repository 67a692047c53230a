#pragma once
// `clipray check --page URL|file.html [--frames N] [--timeout S]`: the page loaded in Debian's
// chromium, headless (DevToolsPipe.hpp), with the recorder (PageRecorder.hpp) added before the
// page's own scripts; once the page has drawn, N animation frames are recorded (frame 0 ends
// with the animation frame that drew first); after those, or at the timeout, the recording is
// fetched and checked as a trace is (PageCalls.hpp).
//
// CLIPRAY_CHROMIUM overrides the browser (default /usr/bin/chromium, then
// /usr/bin/chromium-browser).

#include <cstdint>
#include <functional>
#include <memory>
#include <string>

#include <nlohmann/json.hpp>

#include "clipray/page/PageCalls.hpp"

namespace clipray::page {

struct PageOptions {
  std::string target;  // an http(s) or file URL, or the path of a local file
  std::uint64_t frames = 3;
  double timeoutSeconds = 30.0;
  // Read each canvas's depth buffer after the last frame (addDepthImages).
  bool verify = false;
  // Define window.__THREE_DEVTOOLS__ before the page's scripts (reconcile --page).
  bool three = false;
  // With three: flip each observed WebGLRenderer's reversed depth buffer (its state's depth
  // buffer setReversed) when the renderer announces itself, before its first frame
  // (PageToggle.hpp).
  bool toggleReversedDepth = false;
};

class DevToolsPipe;
// Called once the recording is checked, with the browser and the page still open: reconcile
// --page asks the page more (PageReconcile.hpp). It may throw InputError.
using AfterRecording =
    std::function<void(DevToolsPipe& browser, const std::string& session, PageCheckResult&)>;

// The URL to load: http(s) and file URLs as given, a path as an absolute file URL. Throws
// InputError for another scheme (javascript:, data:, ftp:) or a file that does not exist.
std::string pageUrl(const std::string& target);

// Throws InputError (exit 2) for a bad target, chromium missing or failing to start (with the
// end of its stderr), a page that does not load, makes no WebGL context or never draws.
PageCheckResult checkPage(const PageOptions& options, const AfterRecording& after = {});

// One browser for several loads of pages (reconcile --page loads its page twice: as it is and
// with the reversed depth buffer toggled); the browser's start is paid once. The constructor
// checks the options' target, frames and timeout and starts chromium (the InputErrors of
// checkPage); each load() navigates to about:blank, replaces the recorder script with one made
// for its options, loads the page and records and checks it as checkPage does.
class PageBrowser {
 public:
  explicit PageBrowser(const PageOptions& options);
  ~PageBrowser();
  PageBrowser(const PageBrowser&) = delete;
  PageBrowser& operator=(const PageBrowser&) = delete;
  PageCheckResult load(const PageOptions& options, const AfterRecording& after = {});

 private:
  std::unique_ptr<DevToolsPipe> pipe_;
  std::string session_;
  std::string script_;  // the identifier of the recorder script added for the last load
  bool loaded_ = false;
};

nlohmann::json pageCheckJson(const PageCheckResult& result);
std::string pageCheckText(const PageCheckResult& result);

}  // namespace clipray::page
