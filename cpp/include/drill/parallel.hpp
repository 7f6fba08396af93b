// Parallel loop over independent jobs with progress reporting and cancellation.
//
// One OpenMP parallel region: the threads take the jobs in index order from a shared counter, so a
// thread that finishes early takes the next job instead of waiting at a barrier (a region per group
// of jobs cost the Monte Carlo 5-7 % of its 2-thread speed-up: issue 33). The calling thread
// (OpenMP's thread 0) calls `progress(done, n)` between its jobs, at most every `chunk` completed
// jobs, and once at the end; returning false (or throwing, as Ctrl-C does) cancels: no thread takes
// another job. Each job writes its own output slot, so results never depend on the thread count.
// An exception thrown by a job is captured and no job is taken after it; every job of a lower index
// was taken before it and runs to its end, so the exception rethrown, the one of the lowest job
// index, is the same on any thread count.
#pragma once

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <exception>
#include <functional>
#include <vector>

#include "drill/errors.hpp"

#ifdef _OPENMP
#include <omp.h>
#endif

namespace drill {

/// Number of threads OpenMP would use (1 without OpenMP).
inline int max_threads() {
#ifdef _OPENMP
  return omp_get_max_threads();
#else
  return 1;
#endif
}

using ProgressFn = std::function<bool(std::size_t done, std::size_t total)>;

/// Run job(i) for i in [0, n). Returns false when cancelled by the progress callback.
/// threads = 0 uses the OpenMP default; a negative count is refused.
template <class Job>
bool parallel_for(std::size_t n, Job&& job, const ProgressFn& progress = nullptr, int threads = 0,
                  std::size_t chunk = 0) {
  require(threads >= 0, "threads", threads, "must not be negative (0: the OpenMP default)");
  const int nt = threads > 0 ? threads : max_threads();
  if (chunk == 0) chunk = std::max<std::size_t>(static_cast<std::size_t>(nt), std::min<std::size_t>(n, 4 * nt));
  std::vector<std::exception_ptr> errors(n);
  std::exception_ptr progress_error;  // thrown by the callback (Ctrl-C): rethrown after the region
  std::atomic<std::size_t> next{0}, done{0};
  std::atomic<bool> stop{false}, cancelled{false};
  std::size_t reported = 0;  // read and written by the calling thread only
#pragma omp parallel num_threads(nt)
  {
#ifdef _OPENMP
    const bool caller = omp_get_thread_num() == 0;
#else
    const bool caller = true;
#endif
    while (!stop.load(std::memory_order_relaxed)) {
      const std::size_t i = next.fetch_add(1);
      if (i >= n) break;
      try {
        job(i);
      } catch (...) {
        errors[i] = std::current_exception();
        stop = true;
      }
      const std::size_t d = done.fetch_add(1) + 1;
      if (caller && progress && d < n && d >= reported + chunk) {
        reported = d;
        try {
          if (!progress(d, n)) cancelled = stop = true;
        } catch (...) {
          progress_error = std::current_exception();
          cancelled = stop = true;
        }
      }
    }
  }
  for (std::size_t i = 0; i < n; ++i)
    if (errors[i]) std::rethrow_exception(errors[i]);
  if (progress_error) std::rethrow_exception(progress_error);
  if (cancelled) return false;
  return !progress || progress(n, n);
}

}  // namespace drill
