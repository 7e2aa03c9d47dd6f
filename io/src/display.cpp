#include "strata/io/display.hpp"

#include "strata/config.hpp"
#include "strata/core/error.hpp"
#include "strata/core/log.hpp"

#if STRATA_WITH_RENDER
#include <X11/Xlib.h>
#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <sstream>
#include <thread>
#include <vector>
#endif

namespace strata::io {

#if STRATA_WITH_RENDER
namespace {
constexpr int kStartTimeoutMs = 20000;

/// An Xvfb started by this process; stopped when the process exits (static destruction).
struct XvfbServer {
  pid_t pid = -1;
  std::string display;
  std::string log_file;

  ~XvfbServer() { stop(); }

  void stop() {
    if (pid <= 0) return;
    ::kill(pid, SIGTERM);
    for (int i = 0; i < 200; ++i) {  // up to 2 s, then force
      if (::waitpid(pid, nullptr, WNOHANG) != 0) break;
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
      if (i == 199) {
        ::kill(pid, SIGKILL);
        ::waitpid(pid, nullptr, 0);
      }
    }
    pid = -1;
    if (!log_file.empty()) ::unlink(log_file.c_str());
  }
};

std::mutex g_mutex;
XvfbServer g_server;  // namespace-scope static: destroyed at exit, after main returns

/// Full path of `name` on $PATH, or empty.
std::string find_on_path(const std::string& name) {
  const char* path = std::getenv("PATH");
  std::stringstream ss(path ? path : "/usr/local/bin:/usr/bin:/bin");
  for (std::string dir; std::getline(ss, dir, ':');) {
    if (dir.empty()) dir = ".";
    const std::string full = dir + "/" + name;
    struct stat st {};
    if (::stat(full.c_str(), &st) == 0 && S_ISREG(st.st_mode) && ::access(full.c_str(), X_OK) == 0)
      return full;
  }
  return {};
}

std::string tail_of(const std::string& file, std::size_t max_chars = 600) {
  std::ifstream in(file);
  std::stringstream ss;
  ss << in.rdbuf();
  std::string s = ss.str();
  if (s.size() > max_chars) s = "..." + s.substr(s.size() - max_chars);
  return s;
}

/// Starts Xvfb with -displayfd and returns ":N" once it accepts connections.
void start_xvfb(XvfbServer& server) {
  const std::string exe = find_on_path("Xvfb");
  if (exe.empty())
    fail(ErrorKind::Unsupported,
         "no X display for headless rendering: $DISPLAY is unusable and Xvfb is not installed "
         "(install the Debian package 'xvfb', or set DISPLAY to a running X server)");

  const char* tmpdir = std::getenv("TMPDIR");
  std::string log_template = std::string(tmpdir && *tmpdir ? tmpdir : "/tmp") + "/strata-xvfb-XXXXXX";
  std::vector<char> log_name(log_template.begin(), log_template.end());
  log_name.push_back('\0');
  const int log_fd = ::mkstemp(log_name.data());
  STRATA_CHECK(log_fd >= 0, IO, "cannot create a log file {}: {}", log_template, std::strerror(errno));
  server.log_file = log_name.data();

  int ready[2];     // Xvfb writes its display number here (-displayfd)
  int exec_err[2];  // the child writes errno here if exec fails; closed by a successful exec
  STRATA_CHECK(::pipe2(ready, O_CLOEXEC) == 0 && ::pipe2(exec_err, O_CLOEXEC) == 0, IO, "pipe: {}",
               std::strerror(errno));
  constexpr int kChildFd = 3;
  const std::string fd_arg = std::to_string(kChildFd);
  std::vector<std::string> args = {exe,         "-displayfd", fd_arg,    "-screen", "0", "1600x1200x24",
                                   "-nolisten", "tcp",        "-noreset"};
  std::vector<char*> argv;
  for (auto& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  const pid_t parent = ::getpid();

  const pid_t pid = ::fork();
  STRATA_CHECK(pid >= 0, IO, "fork for Xvfb: {}", std::strerror(errno));
  if (pid == 0) {
    // Child: only async-signal-safe calls from here on.
    ::prctl(PR_SET_PDEATHSIG, SIGTERM);
    if (::getppid() != parent) ::_exit(127);
    const int devnull = ::open("/dev/null", O_RDONLY);
    if (devnull >= 0) ::dup2(devnull, 0);
    ::dup2(log_fd, 1);
    ::dup2(log_fd, 2);
    ::dup2(ready[1], kChildFd);  // dup2 clears FD_CLOEXEC on the copy
    if (ready[1] == kChildFd) ::fcntl(kChildFd, F_SETFD, 0);
    ::setpgid(0, 0);  // Ctrl-C on the terminal goes to strata, which then stops Xvfb
    ::execv(argv[0], argv.data());
    const int e = errno;
    [[maybe_unused]] auto n = ::write(exec_err[1], &e, sizeof e);
    ::_exit(127);
  }
  ::close(log_fd);
  ::close(ready[1]);
  ::close(exec_err[1]);
  server.pid = pid;

  int child_errno = 0;
  const bool exec_failed = ::read(exec_err[0], &child_errno, sizeof child_errno) == sizeof child_errno;
  ::close(exec_err[0]);
  if (exec_failed) {
    ::close(ready[0]);
    ::waitpid(pid, nullptr, 0);
    server.pid = -1;
    fail(ErrorKind::Unsupported, "cannot run {}: {} (install the Debian package 'xvfb')", exe,
         std::strerror(child_errno));
  }

  std::string number;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::milliseconds(kStartTimeoutMs);
  bool ok = false;
  while (true) {
    const auto left =
        std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now());
    if (left.count() <= 0) break;
    pollfd p{ready[0], POLLIN, 0};
    const int r = ::poll(&p, 1, static_cast<int>(left.count()));
    if (r < 0 && errno == EINTR) continue;
    if (r <= 0) break;
    char buf[32];
    const ssize_t n = ::read(ready[0], buf, sizeof buf);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) break;  // Xvfb exited without telling its display
    number.append(buf, static_cast<std::size_t>(n));
    if (number.find('\n') != std::string::npos) {
      ok = true;
      break;
    }
  }
  ::close(ready[0]);
  if (!ok) {
    const std::string log = tail_of(server.log_file);
    server.stop();
    fail(ErrorKind::IO, "Xvfb did not start within {} s (package xvfb); its output:\n{}",
         kStartTimeoutMs / 1000, log);
  }
  server.display = ":" + number.substr(0, number.find('\n'));
}
}  // namespace

bool display_usable() {
  const char* d = std::getenv("DISPLAY");
  if (!d || !*d) return false;
  Display* dpy = XOpenDisplay(d);
  if (!dpy) return false;
  XCloseDisplay(dpy);
  return true;
}

std::string ensure_display() {
  std::lock_guard lock(g_mutex);
  if (g_server.pid > 0) {
    // Ours: still alive?
    if (::waitpid(g_server.pid, nullptr, WNOHANG) == 0) {
      ::setenv("DISPLAY", g_server.display.c_str(), 1);
      return g_server.display;
    }
    log::warn("the Xvfb server on {} has exited; starting a new one", g_server.display);
    g_server.pid = -1;
  }
  if (display_usable()) return std::getenv("DISPLAY");
  if (const char* d = std::getenv("DISPLAY"); d && *d)
    log::info("DISPLAY={} is not usable; starting Xvfb", d);
  start_xvfb(g_server);
  ::setenv("DISPLAY", g_server.display.c_str(), 1);
  log::debug("started Xvfb (pid {}) on DISPLAY={}", g_server.pid, g_server.display);
  STRATA_CHECK(display_usable(), IO, "Xvfb started on {} but it does not accept connections; its output:\n{}",
               g_server.display, tail_of(g_server.log_file));
  // Xvfb keeps its (now nameless) log open; nothing is left in /tmp if we are killed.
  ::unlink(g_server.log_file.c_str());
  g_server.log_file.clear();
  return g_server.display;
}

#else  // !STRATA_WITH_RENDER

bool display_usable() { return false; }
std::string ensure_display() { fail_missing_feature("STRATA_WITH_RENDER", "rendering pictures"); }

#endif

}  // namespace strata::io
