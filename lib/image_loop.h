#pragma once
// The one loop over a camera's pixels: render, verify, the library, the studies and the
// benchmarks run their per-pixel function through it.  The pixels (all of them row-major, or a
// subset in its own order) are cut into blocks of consecutive positions; blocks run in parallel
// on TBB (lib/util/parallel.h), the pixels of a block in order, and every position writes its
// own slot, so the output is bitwise the same for any thread count.  A block is the unit a hook
// sees (progress, a stop request, a study's checkpoint of records) and the unit dealt to MPI
// ranks: under PixelSharing each rank computes the blocks it is dealt and then receives the
// others (lib/util/ranks.h), so every rank ends the loop with every value.
#include <algorithm>
#include <atomic>
#include <functional>
#include <new>
#include <span>
#include <type_traits>
#include <vector>

#include "lib/camera.h"
#include "lib/util/parallel.h"
#include "lib/util/ranks.h"

namespace vrv {

// The ray through pixel `pixel` (row-major index y * width + x).
inline Ray pixel_ray(const Camera& camera, long pixel) {
  return camera.ray(static_cast<int>(pixel % camera.width), static_cast<int>(pixel / camera.width));
}

// What a caller hooks into the loop; every hook may be empty.
struct ImageLoopHooks {
  long block = 64;                      // positions per block (a checkpointed study: one image row)
  std::function<void(long)> progress;   // positions finished, once per block, from any thread
  std::function<bool()> stop;           // polled before each block: true ends the loop (WorkCancelled)
  long block_size() const { return std::max(block, 1L); }  // a block of 0 or less is one position
};

// Runs each block of image_records: compute() fills `records` (the block's, from position
// `first`); a study's checkpoint stores them after, or restores them instead of calling it
// (studies/engine/checkpoint.h, checkpoint_blocks).
using BlockStore =
    std::function<void(long first, std::span<double> records, const std::function<void()>& compute)>;

namespace detail {

// f(ray, pixel) when f takes the pixel's row-major index, else f(ray).
template <class PerPixel>
decltype(auto) call_pixel(PerPixel& f, const Ray& ray, long pixel) {
  if constexpr (std::is_invocable_v<PerPixel&, const Ray&, long>) return f(ray, pixel);
  else return f(ray);
}

// What f gives a pixel; no `type` (so the overload drops out) when f is no per-pixel function.
template <class F>
struct PixelValueOf {};
template <class F>
  requires std::is_invocable_v<F&, const Ray&, long>
struct PixelValueOf<F> {
  using type = std::decay_t<std::invoke_result_t<F&, const Ray&, long>>;
};
template <class F>
  requires(!std::is_invocable_v<F&, const Ray&, long> && std::is_invocable_v<F&, const Ray&>)
struct PixelValueOf<F> {
  using type = std::decay_t<std::invoke_result_t<F&, const Ray&>>;
};
template <class PerPixel>
using PixelValue = typename PixelValueOf<std::remove_reference_t<PerPixel>>::type;

// run(first, last) for the blocks [first_block, last_block) of [0, n), in parallel; stops
// between blocks on hooks.stop.
template <class Run>
void for_blocks(long n, long first_block, long last_block, const ImageLoopHooks& hooks, Run&& run) {
  const long block = hooks.block_size();
  std::atomic<bool> stopped{false};
  parallel_for_index(last_block - first_block, [&](long i) {
    if (stopped.load(std::memory_order_relaxed)) return;
    if (hooks.stop && hooks.stop()) {
      stopped = true;
      return;
    }
    const long first = (first_block + i) * block, last = std::min(n, first + block);
    run(first, last);
    if (hooks.progress) hooks.progress(last - first);
  });
  if (stopped) throw WorkCancelled();
}

inline long block_count(long n, const ImageLoopHooks& hooks) {
  const long block = hooks.block_size();
  return (n + block - 1) / block;
}

// run(first, last) for each block of [0, n).
template <class Run>
void for_each_block(long n, const ImageLoopHooks& hooks, Run&& run) {
  for_blocks(n, 0, block_count(n, hooks), hooks, run);
}

// The positions [first, last): put(position, f(ray)).  A cancelled task group (the Python
// module's Ctrl-C) ends the block by WorkCancelled, so a half-filled block is never stored.
template <class PerPixel, class Put>
void run_positions(const Camera& camera, std::span<const long> subset, long first, long last, PerPixel& f,
                   Put& put) {
  for (long k = first; k < last; ++k) {
    if (tbb::is_current_task_group_canceling()) throw WorkCancelled();
    const long pixel = subset.empty() ? k : subset[static_cast<std::size_t>(k)];
    put(k, call_pixel(f, pixel_ray(camera, pixel), pixel));
  }
}

// The blocks of a loop of n positions spread over MPI ranks: run(first, last) for the blocks this
// rank is dealt, then everyone's `value_bytes` per position at `values` (deal_and_share); the
// progress hook also hears of the positions the other ranks computed.
template <class Run>
void shared_blocks(long n, std::byte* values, std::size_t value_bytes, const ImageLoopHooks& hooks, Run&& run) {
  const long block = hooks.block_size();
  const std::vector<BlockRange> mine =
      deal_and_share(values, n, value_bytes, block,
                     [&](long first_block, long last_block) { for_blocks(n, first_block, last_block, hooks, run); });
  long own = 0;
  for (const BlockRange& r : mine) own += std::min(n, r.last * block) - r.first * block;
  if (hooks.progress && n > own) hooks.progress(n - own);
}

// The loop spread over MPI ranks (shared_blocks), then put(position, value) for every position,
// on every rank.
template <class Value, class PerPixel, class Put>
void shared_loop_into(const Camera& camera, std::span<const long> subset, long n, PerPixel& f, Put& put,
                      const ImageLoopHooks& hooks) {
  // Copied as bytes, and created by the allocation itself (implicit-lifetime, as aligned_alloc's).
  static_assert(std::is_trivially_copyable_v<Value> && std::is_trivially_destructible_v<Value>);
  const auto buffer = exchange_buffer(static_cast<std::size_t>(n) * sizeof(Value));
  Value* values = std::launder(reinterpret_cast<Value*>(buffer.get()));
  auto keep = [&](long k, Value v) { values[static_cast<std::size_t>(k)] = std::move(v); };
  shared_blocks(n, buffer.get(), sizeof(Value), hooks,
                [&](long first, long last) { run_positions(camera, subset, first, last, f, keep); });
  parallel_for_index(n, [&](long k) { put(k, values[static_cast<std::size_t>(k)]); });
}

}  // namespace detail

// The number of positions: the subset's size, or every pixel of the camera when it is empty.
inline long pixel_count(const Camera& camera, std::span<const long> subset = {}) {
  return subset.empty() ? static_cast<long>(camera.width) * camera.height : static_cast<long>(subset.size());
}

// value = f(ray) or f(ray, pixel) at every position (pixel = subset[position], or the position
// itself when the subset is empty), handed to put(position, value) from any thread; each
// position is put once.  For callers that keep only part of a value, or keep it in planes.
template <class PerPixel, class Put>
void image_loop_into(const Camera& camera, std::span<const long> subset, PerPixel&& f, Put&& put,
                     const ImageLoopHooks& hooks = {}) {
  // Values that own memory (not trivially copyable) are computed on every rank.
  using Value = detail::PixelValue<PerPixel>;
  if constexpr (std::is_trivially_copyable_v<Value>)
    if (pixels_shared_over_ranks())
      return detail::shared_loop_into<Value>(camera, subset, pixel_count(camera, subset), f, put, hooks);
  detail::for_each_block(pixel_count(camera, subset), hooks, [&](long first, long last) {
    detail::run_positions(camera, subset, first, last, f, put);
  });
}

// The values position by position (row-major for the whole image).
template <class PerPixel, class Value = detail::PixelValue<PerPixel>>
std::vector<Value> image_loop(const Camera& camera, std::span<const long> subset, PerPixel&& f,
                              const ImageLoopHooks& hooks = {}) {
  std::vector<Value> out(static_cast<std::size_t>(pixel_count(camera, subset)));
  image_loop_into(camera, subset, f, [&](long k, Value v) { out[static_cast<std::size_t>(k)] = std::move(v); }, hooks);
  return out;
}

// Every pixel of the camera, row-major.
template <class PerPixel, class Value = detail::PixelValue<PerPixel>>
std::vector<Value> image_loop(const Camera& camera, PerPixel&& f, const ImageLoopHooks& hooks = {}) {
  return image_loop<PerPixel, Value>(camera, {}, std::forward<PerPixel>(f), hooks);
}

// A record of `width` doubles per position, the records one after another: record(ray, out)
// fills out[0, width) (a study's reference and its methods' values per pixel).  `store` sees a
// block's records as one span.  Fixed-width records, unlike values that own memory, are dealt to
// MPI ranks (without a store) and exchanged as bytes.
template <class Record>
std::vector<double> image_records(const Camera& camera, std::span<const long> subset, std::size_t width,
                                  Record&& record, const ImageLoopHooks& hooks = {}, const BlockStore& store = {}) {
  const long n = pixel_count(camera, subset);
  std::vector<double> out(static_cast<std::size_t>(n) * width);
  const auto records = [&](long first, long last) {
    return std::span<double>(out).subspan(static_cast<std::size_t>(first) * width,
                                          static_cast<std::size_t>(last - first) * width);
  };
  const auto compute = [&](long first, long last) {
    for (long k = first; k < last; ++k) {
      if (tbb::is_current_task_group_canceling()) throw WorkCancelled();
      const long pixel = subset.empty() ? k : subset[static_cast<std::size_t>(k)];
      record(pixel_ray(camera, pixel), records(k, k + 1));
    }
  };
  if (!store && width > 0 && pixels_shared_over_ranks()) {
    detail::shared_blocks(n, reinterpret_cast<std::byte*>(out.data()), width * sizeof(double), hooks, compute);
    return out;
  }
  detail::for_each_block(n, hooks, [&](long first, long last) {
    if (!store) return compute(first, last);
    store(first, records(first, last), [&] { compute(first, last); });
  });
  return out;
}

}  // namespace vrv
