#pragma once
// Child processes for the sweep engines: start a program (fork + exec, no shell), wait for it
// to end, optionally with a time limit, and run a short command capturing its output (sbatch,
// squeue, sacct). Waiting blocks on the child's exit (waitpid, or poll on a pidfd when there is
// a time limit); nothing here sleeps.

#include <sys/types.h>

#include <filesystem>
#include <string>
#include <vector>

namespace pwsim::sweep {

struct ChildExit {
  bool started{true};   ///< false when exec failed (then `error` says why)
  bool exited{false};   ///< ended by exit(); `code` holds the status
  int code{0};
  int signal{0};        ///< the signal that ended it (when !exited)
  bool timed_out{false};
  std::string error;
};

struct SpawnOptions {
  std::filesystem::path cwd;         ///< empty = inherit
  std::filesystem::path output;      ///< stdout and stderr appended here; empty = inherit
  bool die_with_parent{true};        ///< the child is killed when its parent dies (Linux)
  std::vector<std::string> env;      ///< extra NAME=VALUE entries
};

/// Starts `argv[0]` (a path, or a name looked up on PATH) with `argv`. Returns the child's pid,
/// or -1 with `error` set when the program could not be executed.
pid_t Spawn(const std::vector<std::string>& argv, const SpawnOptions& options, std::string& error);

/// Waits for `pid` to end. With `timeout_s` > 0 the child is killed (SIGKILL) once it has run
/// that long and the result has `timed_out` set.
ChildExit WaitChild(pid_t pid, double timeout_s = 0.0);

/// Decodes a waitpid status.
ChildExit DecodeStatus(int status);

struct Captured {
  ChildExit exit;
  std::string out;
  std::string err;
};

/// Runs `argv` to completion, capturing stdout and stderr; `env` adds NAME=VALUE entries to
/// (or replaces them in) this process's environment for the child.
Captured RunCapture(const std::vector<std::string>& argv, const std::vector<std::string>& env = {});

/// Quotes a word for a POSIX shell (single quotes).
std::string ShellQuote(const std::string& word);

}  // namespace pwsim::sweep
