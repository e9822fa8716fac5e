#pragma once
// A child process for tests that start pwsim processes (the end-to-end tests of the session,
// platform-sim, hmd-peer and drive): its stdout and stderr come back through a pipe read by a
// thread, and the test waits for events only (a line the child wrote, its exit), each bounded by
// a guard against a hang that is generous enough for a machine with every core busy, never for
// a time. The one copy: tests include it as "tests/hardware/child_process.h".

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/syscall.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <condition_variable>
#include <mutex>
#include <optional>
#include <string>
#include <string_view>
#include <thread>
#include <vector>

namespace pwsim::test {

class ChildProcess {
 public:
  static constexpr double kGuardS = 120.0;

  explicit ChildProcess(const std::vector<std::string>& args) {
    // Everything the child needs is prepared before fork: after it, only async-signal-safe calls.
    std::vector<char*> argv;
    for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    int fds[2];
    if (::pipe2(fds, O_CLOEXEC) != 0) return;
    pid_ = ::fork();
    if (pid_ == 0) {
      ::dup2(fds[1], 1);
      ::dup2(fds[1], 2);
      ::execv(argv[0], argv.data());
      ::_exit(127);
    }
    ::close(fds[1]);
    if (pid_ < 0) {
      ::close(fds[0]);
      return;
    }
    pidfd_ = static_cast<int>(::syscall(SYS_pidfd_open, pid_, 0));
    reader_ = std::thread([this, fd = fds[0]] {
      char buffer[4096];
      for (;;) {
        const ssize_t n = ::read(fd, buffer, sizeof(buffer));
        if (n < 0 && errno == EINTR) continue;
        std::lock_guard<std::mutex> lock(mutex_);
        if (n <= 0) {
          eof_ = true;
          changed_.notify_all();
          break;
        }
        output_.append(buffer, static_cast<std::size_t>(n));
        changed_.notify_all();
      }
      ::close(fd);
    });
  }
  ~ChildProcess() {
    if (pid_ > 0 && status_ == kRunning) {
      ::kill(pid_, SIGKILL);
      Wait(kGuardS);
    }
    if (reader_.joinable()) reader_.join();
    if (pidfd_ >= 0) ::close(pidfd_);
  }
  ChildProcess(const ChildProcess&) = delete;
  ChildProcess& operator=(const ChildProcess&) = delete;

  /// Blocks until a line starting with `prefix` was written after the first `skip` such
  /// lines; returns the rest of it, or nullopt when the output closed (or the guard ran out).
  std::optional<std::string> WaitForLine(const std::string& prefix, int skip = 0) {
    return WaitFor(prefix, false, skip);
  }
  /// The same for a line containing `text` anywhere; returns the whole line.
  std::optional<std::string> WaitForLineContaining(const std::string& text) { return WaitFor(text, true, 0); }

  /// Waits for the exit up to `seconds`: the exit code, -2 for a signal, -1 when the guard ran
  /// out (then it is killed).
  int Wait(double seconds = kGuardS) {
    if (pid_ <= 0) return -1;
    if (status_ != kRunning) return status_;
    pollfd p{pidfd_, POLLIN, 0};
    const int ready = pidfd_ < 0 ? 1 : ::poll(&p, 1, static_cast<int>(seconds * 1000));
    int status = 0;
    if (ready <= 0) {
      ::kill(pid_, SIGKILL);
      ::waitpid(pid_, &status, 0);
      status_ = -1;
    } else {
      ::waitpid(pid_, &status, 0);
      status_ = WIFEXITED(status) ? WEXITSTATUS(status) : -2;
    }
    if (reader_.joinable()) reader_.join();
    return status_;
  }

  void Kill() {
    if (pid_ > 0 && status_ == kRunning) ::kill(pid_, SIGKILL);
    Wait();
  }

  /// Sends `signal` (SIGINT for a soft stop, SIGKILL for a crash) while it runs.
  void Signal(int signal) {
    if (pid_ > 0 && status_ == kRunning) ::kill(pid_, signal);
  }

  std::string Output() {
    std::lock_guard<std::mutex> lock(mutex_);
    return output_;
  }
  pid_t pid() const { return pid_; }

 private:
  std::optional<std::string> WaitFor(const std::string& text, bool anywhere, int skip) {
    std::unique_lock<std::mutex> lock(mutex_);
    std::optional<std::string> found;
    changed_.wait_for(lock, std::chrono::duration<double>(kGuardS), [&] {
      std::size_t at = 0;
      int seen = 0;
      for (;;) {
        const std::size_t end = output_.find('\n', at);
        if (end == std::string::npos) break;
        const std::string_view line(output_.data() + at, end - at);
        if ((anywhere ? line.find(text) != std::string_view::npos : line.rfind(text, 0) == 0) && seen++ == skip) {
          found = std::string(anywhere ? line : line.substr(text.size()));
          return true;
        }
        at = end + 1;
      }
      return eof_;
    });
    return found;
  }

  static constexpr int kRunning = -100;
  pid_t pid_{-1};
  int pidfd_{-1};
  int status_{kRunning};
  std::thread reader_;
  std::mutex mutex_;
  std::condition_variable changed_;
  std::string output_;
  bool eof_{false};
};

}  // namespace pwsim::test
