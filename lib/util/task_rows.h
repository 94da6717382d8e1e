#pragma once
// Independent tasks that each fill a row of doubles (a model cast on a set of pixels), run in
// parallel.  Where image loops are shared over MPI ranks (PixelSharing, lib/util/ranks.h) the
// tasks are dealt to the ranks as an image loop's blocks are, and the rows exchanged, so every rank
// ends with the whole table.  A row is filled by the same code whichever rank fills it, so the
// table is bitwise the same for any number of ranks and threads.
#include <cstddef>
#include <span>
#include <vector>

#include "lib/util/parallel.h"
#include "lib/util/ranks.h"

namespace vrv {

// fill(task, row) for every task of [0, count), `row` being the task's `width` doubles of the
// count x width table returned (row-major).
template <class Fill>
std::vector<double> task_rows(long count, long width, Fill&& fill) {
  std::vector<double> table(static_cast<std::size_t>(count) * static_cast<std::size_t>(width));
  const auto run = [&](long task) {
    fill(task, std::span<double>(table).subspan(static_cast<std::size_t>(task) * static_cast<std::size_t>(width),
                                                static_cast<std::size_t>(width)));
  };
  if (count == 0 || width == 0 || !pixels_shared_over_ranks()) {
    parallel_for_index(count, run);
    return table;
  }
  const std::vector<BlockRange> mine = deal_blocks(count, 1, [&](long first, long last) {
    parallel_for_index(last - first, [&](long i) { run(first + i); });
  });
  share_blocks(reinterpret_cast<std::byte*>(table.data()), count, static_cast<std::size_t>(width) * sizeof(double), 1,
               mine);
  return table;
}

}  // namespace vrv
