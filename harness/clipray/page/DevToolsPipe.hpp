#pragma once
// A headless chromium driven over the Chrome DevTools protocol on --remote-debugging-pipe: the
// browser reads JSON messages from its file descriptor 3 and writes them to 4, each terminated by
// a NUL byte (chromium, content/browser/devtools/devtools_pipe_handler.cc). Both descriptors are
// one end of a socketpair here, so that a write after the browser died fails with EPIPE instead
// of raising SIGPIPE in clipray (send with MSG_NOSIGNAL).
//
// The browser runs in a process group of its own with a private profile folder; the destructor
// closes it on every path (Browser.close, then SIGTERM and SIGKILL to the group), reaps it and
// removes the folder.

#include <chrono>
#include <stdexcept>
#include <string>
#include <vector>

#include <sys/types.h>
#include <nlohmann/json.hpp>

namespace clipray::page {

using Clock = std::chrono::steady_clock;

class DevToolsPipe {
 public:
  // Starts `executable` headless with `flags` (and the pipe and profile flags). Throws
  // InputError when it cannot be started.
  DevToolsPipe(const std::string& executable, const std::vector<std::string>& flags);
  ~DevToolsPipe();
  DevToolsPipe(const DevToolsPipe&) = delete;
  DevToolsPipe& operator=(const DevToolsPipe&) = delete;

  // Sends a command (to `session`, or to the browser when empty) and waits for its answer until
  // `deadline`. Returns the answer's "result". Throws InputError for a protocol error, a browser
  // that exits (with the end of its stderr) and, past the deadline, TimedOut.
  nlohmann::json call(const std::string& method, const nlohmann::json& params,
                      const std::string& session, Clock::time_point deadline);

  // The last lines of what the browser wrote to stderr (at most `maxBytes`).
  std::string stderrTail(std::size_t maxBytes = 2000) const;

  struct TimedOut : std::runtime_error {
    using std::runtime_error::runtime_error;
  };

 private:
  // Reads one message into `message`; false past the deadline. Throws when the browser exits.
  bool readMessage(nlohmann::json& message, Clock::time_point deadline);
  [[noreturn]] void browserGone(const std::string& what) const;
  void stop();

  pid_t pid_ = -1;
  int socket_ = -1;
  std::string profile_;
  std::string stderrPath_;
  std::string buffer_;
  int nextId_ = 1;
};

}  // namespace clipray::page
