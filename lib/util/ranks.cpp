#include "lib/util/ranks.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <climits>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <limits>
#include <new>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include <fcntl.h>
#include <sys/mman.h>
#include <unistd.h>

#include "lib/util/parallel.h"

#ifdef VRV_WITH_MPI
#include <mpi.h>
#endif

namespace vrv {
namespace {

int g_rank = 0;
int g_count = 1;
std::thread::id g_mpi_thread;
int g_sharing = 0;  // PixelSharing objects alive
std::atomic<int> g_dealing{0};  // 1 while deal_blocks computes this rank's blocks

#ifdef VRV_WITH_MPI
bool g_mpi = false;              // MPI initialised by RankSession
int g_error_fd = STDERR_FILENO;  // a rank's own error stream (its stderr goes to /dev/null)

// Started by a launcher: Open MPI's mpirun, or a PMI/PMIx one (Slurm's srun).  A plain `vrv`
// of an MPI build stays a single process without MPI's start-up.
bool launched_by_mpi() {
  for (const char* v : {"OMPI_COMM_WORLD_SIZE", "PMIX_RANK", "PMI_SIZE", "PMI_RANK"})
    if (std::getenv(v)) return true;
  return false;
}

// Ranks other than 0 print nothing: their results are rank 0's.
void silence_output() {
  g_error_fd = dup(STDERR_FILENO);
  const int null = open("/dev/null", O_WRONLY);
  if (null < 0 || g_error_fd < 0) return;
  std::fflush(stdout);
  std::fflush(stderr);
  dup2(null, STDOUT_FILENO);
  dup2(null, STDERR_FILENO);
  close(null);
}
#endif

}  // namespace

int rank_index() { return g_rank; }
int rank_count() { return g_count; }

RankSession::RankSession([[maybe_unused]] int* argc, [[maybe_unused]] char*** argv) {
#ifdef VRV_WITH_MPI
  if (!launched_by_mpi()) return;
  int provided = 0;
  // Only this thread calls MPI (the image loop's exchange, after its parallel part).
  MPI_Init_thread(argc, argv, MPI_THREAD_FUNNELED, &provided);
  if (provided < MPI_THREAD_FUNNELED) {
    std::fprintf(stderr, "vrv: error: MPI: this MPI library gives no thread support (MPI_THREAD_FUNNELED)\n");
    MPI_Abort(MPI_COMM_WORLD, 2);
  }
  g_mpi = true;
  g_mpi_thread = std::this_thread::get_id();
  MPI_Comm_rank(MPI_COMM_WORLD, &g_rank);
  MPI_Comm_size(MPI_COMM_WORLD, &g_count);
  if (g_rank != 0) silence_output();
#endif
}

RankSession::~RankSession() {
#ifdef VRV_WITH_MPI
  if (g_mpi) MPI_Finalize();
#endif
}

void FreeBuffer::operator()(std::byte* p) const { std::free(p); }

std::unique_ptr<std::byte[], FreeBuffer> exchange_buffer(std::size_t bytes) {
  constexpr std::size_t huge = std::size_t{1} << 21;
  const std::size_t size = (bytes + huge - 1) / huge * huge;
  auto* p = static_cast<std::byte*>(std::aligned_alloc(huge, std::max(size, huge)));
  if (!p) throw std::bad_alloc();
  madvise(p, std::max(size, huge), MADV_HUGEPAGE);  // advice only: 4 KiB pages if refused
  return std::unique_ptr<std::byte[], FreeBuffer>(p);
}

PixelSharing::PixelSharing() { ++g_sharing; }
PixelSharing::~PixelSharing() { --g_sharing; }

bool pixels_shared_over_ranks() {
  // Inside a parallel task, or on another thread, ranks could meet loops in different orders.
  return g_count > 1 && g_sharing > 0 && !inside_parallel_task() && std::this_thread::get_id() == g_mpi_thread;
}

#ifdef VRV_WITH_MPI
namespace {

// The counter deal_blocks hands blocks out from: one long on rank 0, updated by MPI_Fetch_and_op.
class SharedCounter {
 public:
  SharedCounter() : unwinding_(std::uncaught_exceptions()) {
    MPI_Win_allocate(g_rank == 0 ? sizeof(long) : 0, sizeof(long), MPI_INFO_NULL, MPI_COMM_WORLD, &value_, &window_);
    if (g_rank == 0) {
      MPI_Win_lock(MPI_LOCK_EXCLUSIVE, 0, 0, window_);
      *value_ = 0;
      MPI_Win_unlock(0, window_);
    }
    MPI_Barrier(MPI_COMM_WORLD);
    MPI_Win_lock_all(0, window_);
  }
  ~SharedCounter() {
    // Leaving on an error: freeing the window would wait (it is collective) for the other ranks
    // to finish the loop; the error ends every rank at once instead (end_ranks).
    if (std::uncaught_exceptions() > unwinding_) return;
    MPI_Win_unlock_all(window_);
    MPI_Win_free(&window_);
  }
  SharedCounter(const SharedCounter&) = delete;
  SharedCounter& operator=(const SharedCounter&) = delete;
  long fetch_add(long n) {
    long before = 0;
    MPI_Fetch_and_op(&n, &before, MPI_LONG, 0, 0, MPI_SUM, window_);
    MPI_Win_flush(0, window_);
    return before;
  }

 private:
  int unwinding_;
  long* value_ = nullptr;
  MPI_Win window_;
};

// While alive, the work on this process is a dealt block's (counts_on_this_rank).
struct Dealing {
  Dealing() { g_dealing = 1; }
  ~Dealing() { g_dealing = 0; }
  Dealing(const Dealing&) = delete;
  Dealing& operator=(const Dealing&) = delete;
};

// The ranks met the same loop (a loop met by some ranks only would pair the wrong exchanges):
// the same block count everywhere, or every rank throws.
void check_same_loop(long blocks) {
  long extremes[2] = {blocks, -blocks};
  MPI_Allreduce(MPI_IN_PLACE, extremes, 2, MPI_LONG, MPI_MAX, MPI_COMM_WORLD);
  if (extremes[0] != -extremes[1])
    throw std::logic_error("MPI: the ranks met different image loops (" + std::to_string(-extremes[1]) + " to " +
                           std::to_string(extremes[0]) + " blocks); a loop was dealt on a path some ranks skip");
}

// With VRV_RANK_SHARES set, each rank says how many blocks of a dealt loop it computed (on its
// own error stream): how a user sees the balance, and how the tests see that work was shared.
void report_share(const std::vector<BlockRange>& mine, long blocks) {
  if (!std::getenv("VRV_RANK_SHARES")) return;
  long own = 0;
  for (const BlockRange& r : mine) own += r.last - r.first;
  const std::string line = "vrv: rank " + std::to_string(g_rank) + " of " + std::to_string(g_count) + ": " +
                           std::to_string(own) + " of " + std::to_string(blocks) + " blocks\n";
  [[maybe_unused]] const auto written = write(g_error_fd, line.data(), line.size());
}

}  // namespace
#endif

namespace {

// Deals the blocks of a loop of `count` positions in blocks of `block` (deal_and_share) and runs
// compute(first, last) for each range this rank takes; returns those ranges.
std::vector<BlockRange> deal_blocks(long count, long block, const std::function<void(long first, long last)>& compute) {
  const long blocks = (count + block - 1) / block;
  std::vector<BlockRange> mine;
#ifdef VRV_WITH_MPI
  // The exchange counts values in int (a contiguous type of one value): refused before the work.
  if (count > INT_MAX) throw std::runtime_error("MPI: more than 2^31 pixels in one image loop");
  check_same_loop(blocks);
  // At least enough blocks to keep every thread busy (a share ends with its slowest block), at
  // most an eighth of what is left per rank, so a slowed rank is never left holding much.
  const long least = 4L * static_cast<long>(thread_count());
  SharedCounter next;
  for (;;) {
    const long left = blocks - next.fetch_add(0);
    if (left <= 0) break;
    const long want = std::max(least, left / (8L * g_count));
    const long first = next.fetch_add(want);
    if (first >= blocks) break;
    const long last = std::min(blocks, first + want);
    {
      const Dealing dealing;
      compute(first, last);
    }
    mine.push_back({first, last});
  }
  report_share(mine, blocks);
#else
  compute(0, blocks);
  mine.push_back({0, blocks});
#endif
  return mine;
}

void share_blocks([[maybe_unused]] std::byte* values, [[maybe_unused]] long count,
                  [[maybe_unused]] std::size_t value_bytes, [[maybe_unused]] long block,
                  [[maybe_unused]] std::span<const BlockRange> mine) {
#ifdef VRV_WITH_MPI
  if (g_count <= 1) return;
  const auto ranks = static_cast<std::size_t>(g_count);

  // Which ranges each rank computed.
  const int my_ranges = static_cast<int>(mine.size());
  std::vector<int> range_counts(ranks), range_offsets(ranks, 0);
  MPI_Allgather(&my_ranges, 1, MPI_INT, range_counts.data(), 1, MPI_INT, MPI_COMM_WORLD);
  for (std::size_t r = 1; r < ranks; ++r) range_offsets[r] = range_offsets[r - 1] + range_counts[r - 1];
  std::vector<int> pair_counts(ranks), pair_offsets(ranks);
  for (std::size_t r = 0; r < ranks; ++r) {
    pair_counts[r] = 2 * range_counts[r];
    pair_offsets[r] = 2 * range_offsets[r];
  }
  std::vector<long> dealt(static_cast<std::size_t>(2 * (range_offsets.back() + range_counts.back())));
  static_assert(sizeof(BlockRange) == 2 * sizeof(long));
  MPI_Allgatherv(mine.data(), 2 * my_ranges, MPI_LONG, dealt.data(), pair_counts.data(), pair_offsets.data(),
                 MPI_LONG, MPI_COMM_WORLD);

  // Each rank's ranges as one MPI type over `values`, so its values go from its array straight
  // into the others' (no packing: a fresh buffer's first touch costs as much as the transfer).
  MPI_Datatype value_type;
  MPI_Type_contiguous(static_cast<int>(value_bytes), MPI_BYTE, &value_type);
  std::vector<MPI_Datatype> rank_type(ranks);
  for (std::size_t r = 0; r < ranks; ++r) {
    std::vector<int> lengths;
    std::vector<MPI_Aint> at;
    for (int i = 0; i < range_counts[r]; ++i) {
      const long first = dealt[static_cast<std::size_t>(2 * (range_offsets[r] + i))] * block;
      const long last = std::min(count, dealt[static_cast<std::size_t>(2 * (range_offsets[r] + i) + 1)] * block);
      lengths.push_back(static_cast<int>(last - first));
      at.push_back(static_cast<MPI_Aint>(first) * static_cast<MPI_Aint>(value_bytes));
    }
    MPI_Type_create_hindexed(static_cast<int>(lengths.size()), lengths.data(), at.data(), value_type, &rank_type[r]);
    MPI_Type_commit(&rank_type[r]);
  }
  std::vector<MPI_Request> requests;
  requests.reserve(2 * ranks);
  for (std::size_t r = 0; r < ranks; ++r) {
    if (static_cast<int>(r) == g_rank) continue;
    requests.emplace_back();
    MPI_Irecv(values, 1, rank_type[r], static_cast<int>(r), 0, MPI_COMM_WORLD, &requests.back());
    requests.emplace_back();
    MPI_Isend(values, 1, rank_type[static_cast<std::size_t>(g_rank)], static_cast<int>(r), 0, MPI_COMM_WORLD,
              &requests.back());
  }
  MPI_Waitall(static_cast<int>(requests.size()), requests.data(), MPI_STATUSES_IGNORE);
  for (MPI_Datatype& t : rank_type) MPI_Type_free(&t);
  MPI_Type_free(&value_type);
#endif
}

}  // namespace

std::vector<BlockRange> deal_and_share(std::byte* values, long count, std::size_t value_bytes, long block,
                                       const std::function<void(long first, long last)>& compute) {
  const std::vector<BlockRange> mine = deal_blocks(count, block, compute);
  share_blocks(values, count, value_bytes, block, mine);
  return mine;
}

bool counts_on_this_rank() { return g_rank == 0 || g_dealing.load(std::memory_order_relaxed) != 0; }

long sum_over_ranks(long value) {
#ifdef VRV_WITH_MPI
  if (pixels_shared_over_ranks()) MPI_Allreduce(MPI_IN_PLACE, &value, 1, MPI_LONG, MPI_SUM, MPI_COMM_WORLD);
#endif
  return value;
}

double max_over_ranks(double value) {
#ifdef VRV_WITH_MPI
  if (pixels_shared_over_ranks()) {
    // MPI_MAX leaves NaN's order to the library: whether any rank holds one is reduced apart.
    double v[2] = {std::isnan(value) ? -HUGE_VAL : value, std::isnan(value) ? 1.0 : 0.0};
    MPI_Allreduce(MPI_IN_PLACE, v, 2, MPI_DOUBLE, MPI_MAX, MPI_COMM_WORLD);
    return v[1] > 0 ? std::numeric_limits<double>::quiet_NaN() : v[0];
  }
#endif
  return value;
}

bool on_every_rank(bool value) {
#ifdef VRV_WITH_MPI
  if (pixels_shared_over_ranks()) {
    int all = value ? 1 : 0;
    MPI_Allreduce(MPI_IN_PLACE, &all, 1, MPI_INT, MPI_LAND, MPI_COMM_WORLD);
    return all != 0;
  }
#endif
  return value;
}

void end_ranks(int code, std::string_view line) {
#ifdef VRV_WITH_MPI
  if (g_mpi && g_count > 1) {
    std::string text(line);
    if (g_rank != 0) {
      std::this_thread::sleep_for(std::chrono::seconds(1));
      text = "rank " + std::to_string(g_rank) + " of " + std::to_string(g_count) + ": " + text;
    }
    text += '\n';
    if (!line.empty()) [[maybe_unused]] const auto written = write(g_error_fd, text.data(), text.size());
    MPI_Abort(MPI_COMM_WORLD, code);
  }
#endif
  if (!line.empty()) std::fprintf(stderr, "%.*s\n", static_cast<int>(line.size()), line.data());
  std::exit(code);
}

}  // namespace vrv
