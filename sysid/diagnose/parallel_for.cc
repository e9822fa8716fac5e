#include "sysid/diagnose/parallel_for.h"

#include <oneapi/tbb/blocked_range.h>
#include <oneapi/tbb/global_control.h>
#include <oneapi/tbb/parallel_for.h>
#include <oneapi/tbb/partitioner.h>
#include <oneapi/tbb/task_arena.h>

#include <algorithm>

namespace pwsim::diagnose {

void ParallelFor(std::size_t n, const std::function<void(std::size_t)>& task, Waiting waiting) {
  if (n == 0) return;
  if (n == 1) {
    task(0);
    return;
  }
  // One index per task (the tasks are whole simulations or fits, of very different sizes).
  auto loop = [&] {
    oneapi::tbb::parallel_for(
        oneapi::tbb::blocked_range<std::size_t>(0, n, 1),
        [&](const oneapi::tbb::blocked_range<std::size_t>& range) {
          for (std::size_t i = range.begin(); i != range.end(); ++i) task(i);
        },
        oneapi::tbb::simple_partitioner());
  };
  // Isolated: a thread waiting here takes none of an enclosing loop's tasks.
  if (waiting == Waiting::kOwnTasks) oneapi::tbb::this_task_arena::isolate(loop);
  else loop();
}

void WithThreads(int threads, const std::function<void()>& work) {
  threads = std::max(1, threads);
  // As many threads as asked, more than the machine's cores included (oneTBB's default limit).
  const oneapi::tbb::global_control limit(oneapi::tbb::global_control::max_allowed_parallelism,
                                          static_cast<std::size_t>(threads));
  oneapi::tbb::task_arena arena(threads);
  arena.execute(work);
}

void ParallelFor(std::size_t n, int threads, const std::function<void(std::size_t)>& task) {
  WithThreads(threads, [&] { ParallelFor(n, task, Waiting::kAnyTask); });
}

}  // namespace pwsim::diagnose
