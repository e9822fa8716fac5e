#pragma once
// One graceful-stop flag for the long-running commands (session, platform-sim, hmd-peer):
// SIGINT and SIGTERM set it; the command's loop polls it and shuts down cleanly.

#include <atomic>
#include <csignal>

namespace pwsim::app {

/// The flag (lock-free, so setting it from a signal handler is safe).
inline std::atomic<bool>& StopRequested() {
  static std::atomic<bool> requested{false};
  return requested;
}

/// Makes SIGINT and SIGTERM set StopRequested().
inline void InstallStopSignalHandlers() {
  static_assert(std::atomic<bool>::is_always_lock_free);
  auto on_signal = [](int) { StopRequested().store(true); };
  std::signal(SIGINT, on_signal);
  std::signal(SIGTERM, on_signal);
}

}  // namespace pwsim::app
