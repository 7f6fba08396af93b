// Parallel loop over independent jobs with progress reporting and cancellation.
//
// Jobs run in chunks under OpenMP (dynamic schedule). Between chunks, on the calling thread,
// `progress(done)` is called; returning false cancels the remaining chunks. Each job writes its
// own output slot, so results never depend on the thread count. An exception thrown by a job is
// captured (the one of the lowest job index wins) and rethrown after the parallel region.
#pragma once

#include <algorithm>
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
  for (std::size_t begin = 0; begin < n; begin += chunk) {
    const std::size_t end = std::min(n, begin + chunk);
    const long lb = static_cast<long>(begin), le = static_cast<long>(end);
#pragma omp parallel for schedule(dynamic, 1) num_threads(nt)
    for (long i = lb; i < le; ++i) {
      try {
        job(static_cast<std::size_t>(i));
      } catch (...) {
        errors[static_cast<std::size_t>(i)] = std::current_exception();
      }
    }
    for (std::size_t i = begin; i < end; ++i)
      if (errors[i]) std::rethrow_exception(errors[i]);
    if (progress && !progress(end, n)) return false;
  }
  return true;
}

}  // namespace drill
