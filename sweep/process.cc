#include "sweep/process.h"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/syscall.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstring>

extern char** environ;

namespace pwsim::sweep {
namespace {

/// Writes all of `text` to `fd` (ignoring errors: used only in the child after fork).
void WriteAll(int fd, const char* text, std::size_t size) {
  while (size > 0) {
    const ssize_t n = ::write(fd, text, size);
    if (n <= 0) return;
    text += n;
    size -= static_cast<std::size_t>(n);
  }
}

std::vector<char*> Pointers(std::vector<std::string>& words) {
  std::vector<char*> pointers;
  for (std::string& w : words) pointers.push_back(w.data());
  pointers.push_back(nullptr);
  return pointers;
}

}  // namespace

pid_t Spawn(const std::vector<std::string>& argv_in, const SpawnOptions& options, std::string& error) {
  std::vector<std::string> argv = argv_in;
  std::vector<char*> args = Pointers(argv);
  std::vector<std::string> env;
  for (char** e = environ; *e != nullptr; ++e) env.emplace_back(*e);
  for (const std::string& extra : options.env) env.push_back(extra);
  std::vector<char*> envp = Pointers(env);
  const std::string cwd = options.cwd.string();
  const std::string output = options.output.string();

  int report[2];  // exec errors travel back through a close-on-exec pipe
  if (::pipe2(report, O_CLOEXEC) != 0) {
    error = std::string("pipe: ") + std::strerror(errno);
    return -1;
  }
  const pid_t parent = ::getpid();
  const pid_t pid = ::fork();
  if (pid < 0) {
    error = std::string("fork: ") + std::strerror(errno);
    ::close(report[0]);
    ::close(report[1]);
    return -1;
  }
  if (pid == 0) {
    ::close(report[0]);
    const char* step = "prctl";
    if (options.die_with_parent) {
      ::prctl(PR_SET_PDEATHSIG, SIGKILL);
      if (::getppid() != parent) ::_exit(127);  // the parent died before prctl took effect
    }
    step = "chdir";
    if (!cwd.empty() && ::chdir(cwd.c_str()) != 0) goto fail;
    if (!output.empty()) {
      step = "open output";
      const int fd = ::open(output.c_str(), O_WRONLY | O_CREAT | O_APPEND, 0644);
      if (fd < 0) goto fail;
      ::dup2(fd, STDOUT_FILENO);
      ::dup2(fd, STDERR_FILENO);
      if (fd > STDERR_FILENO) ::close(fd);
    }
    step = "exec";
    ::execvpe(args[0], args.data(), envp.data());
  fail:
    const int code = errno;
    WriteAll(report[1], step, std::strlen(step));
    WriteAll(report[1], ": ", 2);
    const char* text = std::strerror(code);
    WriteAll(report[1], text, std::strlen(text));
    ::_exit(127);
  }
  ::close(report[1]);
  std::string message;
  char buffer[256];
  ssize_t n = 0;
  while ((n = ::read(report[0], buffer, sizeof(buffer))) != 0) {
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) break;
    message.append(buffer, static_cast<std::size_t>(n));
  }
  ::close(report[0]);
  if (!message.empty()) {
    int status = 0;
    ::waitpid(pid, &status, 0);
    error = argv_in.empty() ? message : argv_in[0] + ": " + message;
    return -1;
  }
  return pid;
}

ChildExit DecodeStatus(int status) {
  ChildExit result;
  if (WIFEXITED(status)) {
    result.exited = true;
    result.code = WEXITSTATUS(status);
  } else if (WIFSIGNALED(status)) {
    result.signal = WTERMSIG(status);
  }
  return result;
}

ChildExit WaitChild(pid_t pid, double timeout_s) {
  bool timed_out = false;
  if (timeout_s > 0.0) {
    const int fd = static_cast<int>(::syscall(SYS_pidfd_open, pid, 0));
    if (fd >= 0) {
      const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
      for (;;) {
        const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
            deadline - std::chrono::steady_clock::now());
        if (left.count() <= 0) {
          ::kill(pid, SIGKILL);
          timed_out = true;
          break;
        }
        pollfd p{fd, POLLIN, 0};
        const int ready = ::poll(&p, 1, static_cast<int>(std::min<long long>(left.count(), 1 << 30)));
        if (ready > 0) break;  // the child ended
        if (ready < 0 && errno != EINTR) break;
      }
      ::close(fd);
    }
  }
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0) {
    if (errno != EINTR) {
      ChildExit lost;
      lost.started = false;
      lost.error = std::string("waitpid: ") + std::strerror(errno);
      return lost;
    }
  }
  ChildExit result = DecodeStatus(status);
  result.timed_out = timed_out;
  return result;
}

Captured RunCapture(const std::vector<std::string>& argv_in, const std::vector<std::string>& extra_env) {
  Captured captured;
  int out_pipe[2], err_pipe[2];
  if (::pipe2(out_pipe, O_CLOEXEC) != 0 || ::pipe2(err_pipe, O_CLOEXEC) != 0) {
    captured.exit.started = false;
    captured.exit.error = std::string("pipe: ") + std::strerror(errno);
    return captured;
  }
  std::vector<std::string> argv = argv_in;
  std::vector<char*> args = Pointers(argv);
  std::vector<std::string> env;
  for (char** e = environ; *e != nullptr; ++e) {
    const std::string entry(*e);
    const std::string name = entry.substr(0, entry.find('='));
    bool replaced = false;
    for (const std::string& extra : extra_env) replaced = replaced || extra.substr(0, extra.find('=')) == name;
    if (!replaced) env.push_back(entry);
  }
  env.insert(env.end(), extra_env.begin(), extra_env.end());
  std::vector<char*> envp = Pointers(env);
  const pid_t pid = ::fork();
  if (pid == 0) {
    ::dup2(out_pipe[1], STDOUT_FILENO);
    ::dup2(err_pipe[1], STDERR_FILENO);
    ::execvpe(args[0], args.data(), envp.data());
    const char* text = std::strerror(errno);
    WriteAll(STDERR_FILENO, text, std::strlen(text));
    ::_exit(127);
  }
  ::close(out_pipe[1]);
  ::close(err_pipe[1]);
  if (pid < 0) {
    ::close(out_pipe[0]);
    ::close(err_pipe[0]);
    captured.exit.started = false;
    captured.exit.error = std::string("fork: ") + std::strerror(errno);
    return captured;
  }
  pollfd fds[2] = {{out_pipe[0], POLLIN, 0}, {err_pipe[0], POLLIN, 0}};
  std::string* sinks[2] = {&captured.out, &captured.err};
  int open_count = 2;
  char buffer[4096];
  while (open_count > 0) {
    if (::poll(fds, 2, -1) < 0) {
      if (errno == EINTR) continue;
      break;
    }
    for (int i = 0; i < 2; ++i) {
      if (fds[i].fd < 0 || fds[i].revents == 0) continue;
      const ssize_t n = ::read(fds[i].fd, buffer, sizeof(buffer));
      if (n > 0) {
        sinks[i]->append(buffer, static_cast<std::size_t>(n));
      } else if (n == 0 || errno != EINTR) {
        ::close(fds[i].fd);
        fds[i].fd = -1;
        --open_count;
      }
    }
  }
  for (const pollfd& p : fds) {
    if (p.fd >= 0) ::close(p.fd);
  }
  captured.exit = WaitChild(pid);
  if (captured.exit.exited && captured.exit.code == 127 && captured.out.empty()) {
    captured.exit.started = false;
    captured.exit.error = argv_in.empty() ? captured.err : argv_in[0] + ": " + captured.err;
  }
  return captured;
}

std::string ShellQuote(const std::string& word) {
  std::string quoted = "'";
  for (char c : word) {
    if (c == '\'') {
      quoted += "'\\''";
    } else {
      quoted += c;
    }
  }
  return quoted + "'";
}

}  // namespace pwsim::sweep
