#pragma once
// Independent tasks, each filling its own slot of a table: a value, or a row of doubles (a model
// cast on a set of pixels), run in parallel.  Where loops are shared over MPI ranks (PixelSharing,
// lib/util/ranks.h) the tasks are dealt to the ranks as an image loop's blocks are, and the slots
// exchanged, so every rank ends with the whole table.  A slot is filled by the same code whichever
// rank fills it, so the table is bitwise the same for any number of ranks and threads.
#include <algorithm>
#include <cstddef>
#include <span>
#include <type_traits>
#include <vector>

#include "lib/util/parallel.h"
#include "lib/util/ranks.h"

namespace vrv {

namespace detail {

// run(task) for every task of [0, count) in parallel, dealt over the ranks in blocks of `block`
// tasks when they are shared, each task's `slot_bytes` bytes at `slots` exchanged after.
template <class Run>
void dealt_tasks(long count, long block, std::byte* slots, std::size_t slot_bytes, Run&& run) {
  if (count == 0 || slot_bytes == 0 || !pixels_shared_over_ranks()) return parallel_for_index(count, run);
  deal_and_share(slots, count, slot_bytes, block, [&](long first_block, long last_block) {
    const long first = first_block * block, last = std::min(count, last_block * block);
    parallel_for_index(last - first, [&](long i) { run(first + i); });
  });
}

}  // namespace detail

// fill(task, row) for every task of [0, count), `row` being the task's `width` doubles of the
// count x width table returned (row-major).  Tasks are dealt `block` at a time: 1 for tasks that
// are each a whole cast, more for per-ray work.
template <class Fill>
std::vector<double> task_rows(long count, long width, Fill&& fill, long block = 1) {
  std::vector<double> table(static_cast<std::size_t>(count) * static_cast<std::size_t>(width));
  const auto row = [&](long task) {
    return std::span<double>(table).subspan(static_cast<std::size_t>(task) * static_cast<std::size_t>(width),
                                            static_cast<std::size_t>(width));
  };
  detail::dealt_tasks(count, std::max(block, 1L), reinterpret_cast<std::byte*>(table.data()),
                      static_cast<std::size_t>(width) * sizeof(double), [&](long task) { fill(task, row(task)); });
  return table;
}

// Tasks per block for per-ray work: about 16 blocks a rank, so that a study's loop of a few dozen
// costly rays still reaches every rank, and at most 64.  From the count and the ranks alone:
// every rank must cut the same blocks.
inline long task_block(long count) { return std::clamp(count / (16L * rank_count()), 1L, 64L); }

// {f(0), ..., f(count - 1)}: per-ray work (a reference, a discrete cast), dealt in blocks of
// task_block(count) tasks.  The value must be trivially copyable: it is exchanged as bytes.
template <class F, class Value = std::decay_t<std::invoke_result_t<F&, long>>>
std::vector<Value> task_values(long count, F&& f) {
  static_assert(std::is_trivially_copyable_v<Value>, "task_values: values are exchanged between ranks as bytes");
  std::vector<Value> out(static_cast<std::size_t>(count));
  detail::dealt_tasks(count, task_block(count), reinterpret_cast<std::byte*>(out.data()), sizeof(Value),
                      [&](long i) { out[static_cast<std::size_t>(i)] = f(i); });
  return out;
}

}  // namespace vrv
