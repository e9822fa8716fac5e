#pragma once
// Independent tasks on a fixed number of threads: task i writes only its own result slot, and
// the caller reduces the slots in index order afterwards, so the results are the same to the
// bit whatever the thread count (each task itself runs single-threaded).

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

namespace pwsim::diagnose {

/// Runs task(i) for i in [0, n) on min(threads, n) threads (the caller's among them). The
/// first exception thrown by a task is rethrown after every thread has stopped.
template <class Task>
void ParallelFor(std::size_t n, int threads, Task task) {
  std::atomic<std::size_t> next{0};
  std::exception_ptr error;
  std::mutex error_mutex;
  auto work = [&] {
    for (std::size_t i = next++; i < n; i = next++) {
      try {
        task(i);
      } catch (...) {
        const std::lock_guard<std::mutex> lock(error_mutex);
        if (!error) error = std::current_exception();
      }
    }
  };
  const std::size_t extra = std::min<std::size_t>(n, static_cast<std::size_t>(std::max(1, threads))) - (n > 0 ? 1 : 0);
  std::vector<std::thread> pool;
  pool.reserve(extra);
  for (std::size_t t = 0; t < extra; ++t) pool.emplace_back(work);
  work();
  for (std::thread& t : pool) t.join();
  if (error) std::rethrow_exception(error);
}

}  // namespace pwsim::diagnose
