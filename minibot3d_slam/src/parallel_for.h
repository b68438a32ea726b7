// Runs independent jobs on a few threads: the per-particle scan matching of the filter and the
// second pass of slam_offline. Jobs must not write anything another job reads; a result written
// to job i's own slot is then the same whatever the thread count, so runs stay reproducible.
#ifndef MINIBOT3D_SLAM_PARALLEL_FOR_H_
#define MINIBOT3D_SLAM_PARALLEL_FOR_H_

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

namespace minibot3d_slam {

// `requested` threads, or one per CPU core when it is 0 (at least 1).
inline int ResolveThreads(int requested) {
  if (requested > 0) return requested;
  return static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
}

// Calls fn(i) once for every i in [0, n), on up to `threads` threads (the caller's among them),
// each taking the next index as it becomes free. Returns when all are done; an exception thrown
// by a job is rethrown here (the first one; the remaining indices are skipped).
template <class F>
void ParallelFor(std::size_t n, int threads, F&& fn) {
  const std::size_t workers = std::min<std::size_t>(n, static_cast<std::size_t>(std::max(1, threads)));
  if (workers <= 1) {
    for (std::size_t i = 0; i < n; ++i) fn(i);
    return;
  }
  std::atomic<std::size_t> next{0};
  std::atomic<bool> failed{false};
  std::exception_ptr error;
  std::mutex error_mutex;
  auto work = [&]() {
    for (std::size_t i = next++; i < n && !failed; i = next++) {
      try {
        fn(i);
      } catch (...) {
        std::lock_guard<std::mutex> lock(error_mutex);
        if (!error) error = std::current_exception();
        failed = true;
      }
    }
  };
  std::vector<std::thread> pool;
  pool.reserve(workers - 1);
  for (std::size_t t = 1; t < workers; ++t) pool.emplace_back(work);
  work();
  for (std::thread& t : pool) t.join();
  if (error) std::rethrow_exception(error);
}

}  // namespace minibot3d_slam

#endif  // MINIBOT3D_SLAM_PARALLEL_FOR_H_
