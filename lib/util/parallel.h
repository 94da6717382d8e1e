#pragma once
// Parallelism over independent work items (pixels, rays, configurations) with TBB.  Every
// item writes its own slot and any reduction runs afterwards in index order, so results are
// bitwise identical for any number of threads.
#include <memory>
#include <stdexcept>

#include <tbb/blocked_range.h>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>
#include <tbb/task_group.h>

namespace vrv {

// Work whose tbb::task_group was cancelled from another thread (the Python module's Ctrl-C,
// studies/python/module.cpp): the loop stops and returns early, and this unwinds its caller
// instead of letting it go on with the slots left unfilled.
class WorkCancelled : public std::runtime_error {
 public:
  WorkCancelled() : std::runtime_error("cancelled") {}
};

namespace detail {
// How many parallel tasks this thread is running, one inside another (a thread waiting in a
// parallel loop runs the loop's tasks too).
inline thread_local int parallel_task_depth = 0;
struct ParallelTask {
  ParallelTask() { ++parallel_task_depth; }
  ~ParallelTask() { --parallel_task_depth; }
};
}  // namespace detail

// Whether this thread is running a task of parallel_for_index (where the order in which work
// meets other work is not fixed; lib/util/ranks.h).
inline bool inside_parallel_task() { return detail::parallel_task_depth > 0; }

template <class Body>
void parallel_for_index(long count, Body&& body) {
  tbb::parallel_for(tbb::blocked_range<long>(0, count), [&](const tbb::blocked_range<long>& r) {
    const detail::ParallelTask task;
    // A block can be a large share of the items (TBB splits further only when a thread is idle):
    // each item looks, so a cancellation stops the loop within an item or so.
    for (long i = r.begin(); i != r.end() && !tbb::is_current_task_group_canceling(); ++i) body(i);
  });
  if (tbb::is_current_task_group_canceling()) throw WorkCancelled();
}

// The threads parallel_for_index runs on now (all cores, or a ThreadLimit's n).
inline int thread_count() {
  return static_cast<int>(tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism));
}

// Caps TBB at n threads while alive (--threads); n <= 0 leaves TBB's default (all cores).
class ThreadLimit {
 public:
  explicit ThreadLimit(int n) {
    if (n > 0)
      control_ = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism,
                                                       static_cast<std::size_t>(n));
  }

 private:
  std::unique_ptr<tbb::global_control> control_;
};

}  // namespace vrv
