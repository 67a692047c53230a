#pragma once
// An Xvfb server for one test, on a display number it picks itself (-displayfd), so tests running
// in parallel never collide; stopped when the object dies. Tests skip, with the reason, where no X
// server can start.

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <string>

namespace clipray::testing {

class XvfbServer {
 public:
  XvfbServer() {
    int fds[2];
    if (pipe(fds) != 0) {
      failure_ = "pipe() failed";
      return;
    }
    pid_ = fork();
    if (pid_ == 0) {
      // If the test process dies without running the destructor (an abort), Xvfb goes with it.
      prctl(PR_SET_PDEATHSIG, SIGTERM);
      close(fds[0]);
      const int devNull = open("/dev/null", O_RDWR);
      dup2(devNull, STDIN_FILENO);
      dup2(devNull, STDOUT_FILENO);
      dup2(devNull, STDERR_FILENO);
      const std::string fd = std::to_string(fds[1]);
      execlp("Xvfb", "Xvfb", "-displayfd", fd.c_str(), "-screen", "0", "1280x1024x24", "-nolisten",
             "tcp", static_cast<char*>(nullptr));
      _exit(127);
    }
    close(fds[1]);
    if (pid_ < 0) {
      close(fds[0]);
      failure_ = "fork() failed";
      return;
    }
    // Xvfb writes the display number and a newline once it accepts connections.
    std::string number;
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(20);
    while (std::chrono::steady_clock::now() < deadline) {
      pollfd p{fds[0], POLLIN, 0};
      if (poll(&p, 1, 200) <= 0) continue;
      char c = 0;
      if (read(fds[0], &c, 1) != 1) break;  // closed: Xvfb is gone
      if (c == '\n') break;
      number += c;
    }
    close(fds[0]);
    if (number.empty()) {
      failure_ =
          "no X server could start: Xvfb (Debian's xvfb, harness/install-deps.sh) is missing or "
          "exited before it offered a display";
      stop();
      return;
    }
    display_ = ":" + number;
  }
  ~XvfbServer() { stop(); }
  XvfbServer(const XvfbServer&) = delete;
  XvfbServer& operator=(const XvfbServer&) = delete;

  bool running() const { return !display_.empty(); }
  const std::string& display() const { return display_; }  // ":N"
  const std::string& failure() const { return failure_; }

 private:
  void stop() {
    if (pid_ > 0) {
      kill(pid_, SIGTERM);
      waitpid(pid_, nullptr, 0);
      pid_ = -1;
    }
  }

  pid_t pid_ = -1;
  std::string display_;
  std::string failure_;
};

}  // namespace clipray::testing
