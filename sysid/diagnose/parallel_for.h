#pragma once
// Independent tasks on a pool of threads (oneTBB): task i writes only its own result slot, and
// the caller reduces the slots in index order afterwards, so the results are the same to the
// bit whatever the thread count. Calls nest: the candidate fits of the diagnosis run
// concurrently, and inside each fit the simulations of every trial (and of every parameter
// perturbation of its Jacobian) run concurrently as well, all on one pool whose threads take
// whichever task is ready, so that neither a long fit nor a short round leaves a core idle.
//
//   WithThreads(2, [&] {
//     ParallelFor(fits.size(), [&](std::size_t i) { fits[i] = Fit(i); }, Waiting::kAnyTask);
//   });

#include <cstddef>
#include <functional>

namespace pwsim::diagnose {

/// While it waits for the last of its tasks, the calling thread runs
enum class Waiting {
  kOwnTasks,  ///< only these tasks: the loop ends as soon as they do (a fit's simulations)
  kAnyTask,   ///< any task of the pool, e.g. the simulations of a fit another thread runs (the
              ///< candidate fits: the thread whose fit ended early helps the last one)
};

/// Runs task(i) for i in [0, n) on the threads of the current pool (the caller's among them;
/// the whole machine outside WithThreads). A task's exception is rethrown here.
void ParallelFor(std::size_t n, const std::function<void(std::size_t)>& task,
                 Waiting waiting = Waiting::kOwnTasks);

/// Runs `work` on a pool of `threads` threads (≥ 1; more than the machine's cores if asked):
/// every ParallelFor inside it, nested ones included, shares them. The count is a process-wide
/// limit while `work` runs: one WithThreads at a time.
void WithThreads(int threads, const std::function<void()>& work);

/// WithThreads(threads, ParallelFor(n, task, kAnyTask)).
void ParallelFor(std::size_t n, int threads, const std::function<void(std::size_t)>& task);

}  // namespace pwsim::diagnose
