#pragma once
// Parallelism over independent work items (pixels, rays, configurations) with TBB.  Every
// item writes its own slot and any reduction runs afterwards in index order, so results are
// bitwise identical for any number of threads.
#include <memory>

#include <tbb/blocked_range.h>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>

namespace vrv {

template <class Body>
void parallel_for_index(long count, Body&& body) {
  tbb::parallel_for(tbb::blocked_range<long>(0, count), [&](const tbb::blocked_range<long>& r) {
    for (long i = r.begin(); i != r.end(); ++i) body(i);
  });
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
