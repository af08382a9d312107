#include "apps/supervise.hpp"

#include <fcntl.h>
#include <spawn.h>
#include <sys/prctl.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "methods/core/signal_cleanup.hpp"

extern char** environ;

namespace mfv {
namespace {

constexpr const char* kChannel = "MFV_SUPERVISOR_CHANNEL";  ///< "<fd>:<supervisor pid>"

/// The write end of the completion pipe in a supervised child; -1 elsewhere. Written once,
/// by adopt_supervision at the start of main, before any thread.
int& channel() {
  static int fd = -1;
  return fd;
}

}  // namespace

bool adopt_supervision() {
  const char* v = std::getenv(kChannel);
  if (v == nullptr) return false;
  const std::string text = v;
  ::unsetenv(kChannel);
  // Believed only from the process that set it: a variable left in a user's environment
  // names no pipe of ours (its parent is not the pid it names).
  int fd = -1;
  long parent = -1;
  if (std::sscanf(text.c_str(), "%d:%ld", &fd, &parent) != 2 || parent != ::getppid())
    return false;
  struct stat st {};
  if (fd < 0 || ::fstat(fd, &st) != 0 || !S_ISFIFO(st.st_mode)) return false;
  ::fcntl(fd, F_SETFD, FD_CLOEXEC);
  // A supervisor killed by SIGKILL leaves no one to report to: the command stops too.
  ::prctl(PR_SET_PDEATHSIG, SIGTERM, 0, 0, 0);
  if (::getppid() != parent) std::_Exit(1);
  channel() = fd;
  return true;
}

namespace {
// The channel's messages: 'R' (registered), then 'S' and the status byte (finished).
void send(const unsigned char* bytes, std::size_t n) {
  while (n > 0) {
    const ssize_t w = ::write(channel(), bytes, n);
    if (w < 0 && errno == EINTR) continue;
    if (w <= 0) return;
    bytes += w;
    n -= static_cast<std::size_t>(w);
  }
}
}  // namespace

void report_registered() {
  if (channel() < 0) return;
  const unsigned char r = 'R';
  send(&r, 1);
}

void report_finished(int status) {
  if (channel() < 0) return;
  const unsigned char s[2] = {'S', static_cast<unsigned char>(status & 0xff)};
  send(s, 2);
  ::close(channel());
  channel() = -1;
}

void forget_supervision() {
  if (channel() < 0) return;
  ::close(channel());
  channel() = -1;
}

std::optional<int> supervise(char** argv, const std::vector<std::string>& plugins) {
  if (plugins.empty() || channel() >= 0) return std::nullopt;
  int fds[2];
  if (::pipe2(fds, O_CLOEXEC) != 0) return std::nullopt;  // unsupervised rather than not run
  const std::string value = fmt::format("{}:{}", fds[1], ::getpid());
  std::vector<std::string> env_text;
  for (char** e = environ; *e != nullptr; ++e)
    if (std::strncmp(*e, kChannel, std::strlen(kChannel)) != 0 ||
        (*e)[std::strlen(kChannel)] != '=')
      env_text.emplace_back(*e);
  env_text.push_back(std::string(kChannel) + "=" + value);
  std::vector<char*> env;
  for (auto& e : env_text) env.push_back(e.data());
  env.push_back(nullptr);
  posix_spawn_file_actions_t fa;
  posix_spawn_file_actions_init(&fa);
  posix_spawn_file_actions_addclose(&fa, fds[0]);
  // dup2 of a descriptor onto itself clears its close-on-exec flag in the child only.
  posix_spawn_file_actions_adddup2(&fa, fds[1], fds[1]);
  pid_t pid = 0;
  const int e = posix_spawn(&pid, "/proc/self/exe", &fa, nullptr, argv, env.data());
  posix_spawn_file_actions_destroy(&fa);
  ::close(fds[1]);
  if (e != 0) {
    ::close(fds[0]);
    return std::nullopt;
  }
  // Killed by SIGINT, SIGTERM or SIGHUP (the signal thread of reports/atomic.cpp), the
  // supervisor stops the command and waits for its clean-up before dying of the signal.
  const OnSignal stop_child([pid] {
    ::kill(pid, SIGTERM);
    int ignored = 0;
    while (::waitpid(pid, &ignored, 0) < 0 && errno == EINTR) {
    }
  });
  bool registered = false, finished = false;
  int reported = 0;
  for (;;) {
    unsigned char buf[16];
    const ssize_t got = ::read(fds[0], buf, sizeof buf);
    if (got < 0 && errno == EINTR) continue;
    if (got <= 0) break;
    for (ssize_t i = 0; i < got; ++i) {
      if (buf[i] == 'R') registered = true;
      else if (buf[i] == 'S' && i + 1 < got) {
        finished = true;
        reported = buf[++i];
      } else if (buf[i] == 'S') {  // its status byte in the next read
        unsigned char b = 0;
        ssize_t n = 0;
        while ((n = ::read(fds[0], &b, 1)) < 0 && errno == EINTR) {
        }
        if (n == 1) {
          finished = true;
          reported = b;
        }
      }
    }
  }
  ::close(fds[0]);
  int ws = 0;
  pid_t waited = -1;
  while ((waited = ::waitpid(pid, &ws, 0)) < 0 && errno == EINTR) {
  }
  // ECHILD: the signal thread reaped the child (stop_child) and is about to end this process
  // with its signal.
  if (waited < 0)
    for (;;) ::pause();
  const std::string names = fmt::format("{}", fmt::join(plugins, ", "));
  if (finished) return reported;
  if (WIFSIGNALED(ws)) {
    const int sig = WTERMSIG(ws);
    std::fprintf(stderr,
                 "mfv: error: the command was killed by signal %d (%s) before it finished "
                 "(plugins loaded: %s)\n",
                 sig, strsignal(sig), names.c_str());
    std::fflush(stderr);
    std::signal(sig, SIG_DFL);
    sigset_t one;
    sigemptyset(&one);
    sigaddset(&one, sig);
    pthread_sigmask(SIG_UNBLOCK, &one, nullptr);
    ::raise(sig);
    return 128 + sig;
  }
  const int code = WIFEXITED(ws) ? WEXITSTATUS(ws) : -1;
  if (!registered) {
    std::fprintf(stderr,
                 "mfv: input error: a plugin ended the process (status %d) while the plugins "
                 "were being registered (static initializers, mfv_plugin_register or a "
                 "registration hook; plugins loaded: %s); a plugin's registration must return, "
                 "and report a failure by throwing std::runtime_error\n",
                 code, names.c_str());
    std::fflush(stderr);
    return 2;
  }
  std::fprintf(stderr,
               "mfv: error: the command ended with status %d before it finished: mfv's commands "
               "return, so a plugin's code ended the process (_exit or exit; plugins loaded: "
               "%s)\n",
               code, names.c_str());
  std::fflush(stderr);
  return 1;
}

}  // namespace mfv
