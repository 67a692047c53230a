// The DevTools pipe client (DevToolsPipe.hpp).

#include "clipray/page/DevToolsPipe.hpp"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>

#include "clipray/InputError.hpp"

namespace clipray::page {

namespace {

// A message longer than this is no answer clipray asks for (the recording is capped well below).
constexpr std::size_t kMaxMessageBytes = 512u << 20;
constexpr int kExecFailed = 127;

std::string errnoText(const char* what) {
  return std::string(what) + ": " + std::strerror(errno);
}

}  // namespace

DevToolsPipe::DevToolsPipe(const std::string& executable, const std::vector<std::string>& flags) {
  std::string folder = (std::filesystem::temp_directory_path() / "clipray-page-XXXXXX").string();
  if (!mkdtemp(folder.data())) throw InputError(errnoText("cannot create a temporary folder"));
  profile_ = folder;
  stderrPath_ = folder + "/chromium-stderr.txt";
  std::vector<std::string> words = {executable};
  words.insert(words.end(), flags.begin(), flags.end());
  words.push_back("--remote-debugging-pipe");
  words.push_back("--user-data-dir=" + folder + "/profile");
  words.push_back("about:blank");

  int fds[2];
  if (socketpair(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0, fds) != 0) {
    std::filesystem::remove_all(profile_);
    throw InputError(errnoText("socketpair"));
  }
  const int errFd = open(stderrPath_.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0600);
  const int nullFd = open("/dev/null", O_RDWR | O_CLOEXEC);
  std::vector<char*> argv;
  for (std::string& word : words) argv.push_back(word.data());
  argv.push_back(nullptr);
  const pid_t parent = getpid();
  pid_ = fork();
  if (pid_ == 0) {
    // Only async-signal-safe calls from here to exec. A group of its own: the browser's helper
    // processes (zygote, GPU, renderers) are ended with it. And killed with clipray, however
    // clipray ends (a signal gives it no chance to run the destructor): prctl(2),
    // PR_SET_PDEATHSIG, which the exec keeps; the helpers follow the browser.
    setpgid(0, 0);
    if (prctl(PR_SET_PDEATHSIG, SIGKILL) != 0 || getppid() != parent) _exit(kExecFailed);
    // Above 4 first, so that dup2 onto 3 and 4 cannot close what the other needs.
    const int high = fcntl(fds[1], F_DUPFD, 10);
    if (high < 0 || dup2(high, 3) < 0 || dup2(high, 4) < 0) _exit(kExecFailed);
    close(high);
    if (nullFd >= 0) {
      dup2(nullFd, STDIN_FILENO);
      dup2(nullFd, STDOUT_FILENO);
    }
    if (errFd >= 0) dup2(errFd, STDERR_FILENO);
    execv(argv[0], argv.data());
    _exit(kExecFailed);
  }
  const int forkErrno = errno;
  close(fds[1]);
  if (errFd >= 0) close(errFd);
  if (nullFd >= 0) close(nullFd);
  socket_ = fds[0];
  if (pid_ < 0) {
    close(socket_);
    socket_ = -1;
    std::filesystem::remove_all(profile_);
    errno = forkErrno;
    throw InputError(errnoText("fork"));
  }
  setpgid(pid_, pid_);  // as the child does: whichever runs first
}

DevToolsPipe::~DevToolsPipe() {
  stop();
}

void DevToolsPipe::stop() {
  if (pid_ > 0) {
    // Browser.close asks for an orderly exit; a browser that does not go in a second is ended.
    if (socket_ >= 0) {
      const std::string close = R"({"id":0,"method":"Browser.close"})" + std::string(1, '\0');
      (void)send(socket_, close.data(), close.size(), MSG_NOSIGNAL);
    }
    int status = 0;
    bool reaped = false;
    for (int wait = 0; wait < 20 && !reaped; ++wait) {
      const pid_t got = waitpid(pid_, &status, WNOHANG);
      reaped = got == pid_ || (got < 0 && errno != EINTR);
      if (!reaped) std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
    if (!reaped) {
      kill(-pid_, SIGTERM);
      for (int wait = 0; wait < 20 && !reaped; ++wait) {
        const pid_t got = waitpid(pid_, &status, WNOHANG);
        reaped = got == pid_ || (got < 0 && errno != EINTR);
        if (!reaped) std::this_thread::sleep_for(std::chrono::milliseconds(50));
      }
    }
    // The browser's helpers may outlive it for a moment: the whole group goes.
    kill(-pid_, SIGKILL);
    if (!reaped) {
      while (waitpid(pid_, &status, 0) < 0 && errno == EINTR) {
      }
    }
    pid_ = -1;
  }
  if (socket_ >= 0) {
    close(socket_);
    socket_ = -1;
  }
  if (!profile_.empty()) {
    std::error_code ignored;
    std::filesystem::remove_all(profile_, ignored);
    profile_.clear();
  }
}

std::string DevToolsPipe::stderrTail(std::size_t maxBytes) const {
  std::ifstream file(stderrPath_, std::ios::binary);
  std::stringstream text;
  text << file.rdbuf();
  std::string all = text.str();
  if (all.size() > maxBytes) all = all.substr(all.size() - maxBytes);
  while (!all.empty() && (all.back() == '\n' || all.back() == '\r')) all.pop_back();
  return all;
}

void DevToolsPipe::browserGone(const std::string& what) const {
  int status = 0;
  std::string how;
  // The pipe closes as the browser exits: its exit status follows within moments.
  bool exited = false;
  for (int wait = 0; wait < 20 && !exited; ++wait) {
    exited = waitpid(pid_, &status, WNOHANG) == pid_;
    if (!exited) std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  if (exited) {
    if (WIFEXITED(status) && WEXITSTATUS(status) == kExecFailed) {
      how = " (could not be run)";
    } else if (WIFEXITED(status)) {
      how = " (exit status ";
      how += std::to_string(WEXITSTATUS(status));
      how += ")";
    } else if (WIFSIGNALED(status)) {
      how = " (signal ";
      how += std::to_string(WTERMSIG(status));
      how += ")";
    }
  }
  const std::string tail = stderrTail();
  throw InputError("chromium " + what + how +
                   (tail.empty() ? std::string() : "; its stderr ends:\n" + tail));
}

bool DevToolsPipe::readMessage(nlohmann::json& message, Clock::time_point deadline) {
  while (true) {
    const std::size_t end = buffer_.find('\0');
    if (end != std::string::npos) {
      message = nlohmann::json::parse(
          buffer_.begin(), buffer_.begin() + static_cast<std::ptrdiff_t>(end), nullptr, false);
      buffer_.erase(0, end + 1);
      if (message.is_discarded()) browserGone("wrote a message that is not JSON");
      return true;
    }
    if (buffer_.size() > kMaxMessageBytes) browserGone("wrote a message over 512 MiB");
    const auto left =
        std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now()).count();
    if (left <= 0) return false;
    pollfd ready{socket_, POLLIN, 0};
    const int polled = poll(&ready, 1, static_cast<int>(std::min<long long>(left, 1000)));
    if (polled < 0 && errno != EINTR) browserGone(errnoText("poll"));
    if (polled <= 0) continue;
    char chunk[65536];
    const ssize_t got = recv(socket_, chunk, sizeof chunk, 0);
    if (got < 0 && errno == EINTR) continue;
    if (got <= 0) browserGone("closed the DevTools pipe");
    buffer_.append(chunk, static_cast<std::size_t>(got));
  }
}

nlohmann::json DevToolsPipe::call(const std::string& method, const nlohmann::json& params,
                                  const std::string& session, Clock::time_point deadline) {
  const int id = nextId_++;
  nlohmann::json message = {{"id", id}, {"method", method}, {"params", params}};
  if (!session.empty()) message["sessionId"] = session;
  const std::string text = message.dump() + std::string(1, '\0');
  for (std::size_t sent = 0; sent < text.size();) {
    const ssize_t wrote = send(socket_, text.data() + sent, text.size() - sent, MSG_NOSIGNAL);
    if (wrote < 0 && errno == EINTR) continue;
    if (wrote <= 0) browserGone("closed the DevTools pipe");
    sent += static_cast<std::size_t>(wrote);
  }
  nlohmann::json answer;
  while (readMessage(answer, deadline)) {
    // Events (no id) and answers to other commands are not needed.
    if (!answer.contains("id") || answer["id"] != id) continue;
    if (answer.contains("error")) {
      throw InputError("chromium: " + method + ": " + answer["error"].value("message", "error"));
    }
    return answer.value("result", nlohmann::json::object());
  }
  throw TimedOut(method);
}

}  // namespace clipray::page
