#pragma once
// The processes of an MPI run (`mpirun -np P vrv render ...`, docs/distributed.md).  A build with
// -DVRV_WITH_MPI=ON started by an MPI launcher has P ranks; any other run has one, and every
// function here is then a no-op, so the plain build needs no MPI.
//
// Every rank runs the same command on the same inputs.  The image loop (lib/image_loop.h) hands
// each rank its share of the pixel blocks and then gives every rank all of them, so what follows
// the loop is the same on every rank; rank 0 alone prints and writes results.  A value is
// computed by the same code whichever rank computes it, so outputs are bitwise those of one process.
#include <cstddef>
#include <functional>
#include <memory>
#include <span>
#include <string_view>
#include <vector>

namespace vrv {

// This process's rank, 0 .. rank_count() - 1.
int rank_index();
int rank_count();

// Rank 0 prints and writes; the others compute their share and end quietly.
inline bool is_output_rank() { return rank_index() == 0; }

// Initialises MPI when the process was started by an MPI launcher (and the build has MPI) and
// finalises it at the end.  Ranks other than 0 get standard output and error on /dev/null (the
// error stream is kept for end_ranks).  One per process, in main().
class RankSession {
 public:
  RankSession(int* argc, char*** argv);
  ~RankSession();
  RankSession(const RankSession&) = delete;
  RankSession& operator=(const RankSession&) = delete;
};

// While alive, image loops called from the thread that started MPI, outside any parallel task,
// spread their blocks over the ranks.  A command turns it on once it knows every rank meets the
// same loops in the same order (vrv render).
class PixelSharing {
 public:
  PixelSharing();
  ~PixelSharing();
  PixelSharing(const PixelSharing&) = delete;
  PixelSharing& operator=(const PixelSharing&) = delete;
};

// Whether an image loop starting now on this thread shares its blocks (see PixelSharing).
bool pixels_shared_over_ranks();

// Memory for an image loop's values under MPI, in huge pages where the system gives them: the
// first touch of fresh memory costs more than the exchange (0.18 s per 64 MB in 4 KiB pages here).
struct FreeBuffer {
  void operator()(std::byte* p) const;
};
std::unique_ptr<std::byte[], FreeBuffer> exchange_buffer(std::size_t bytes);

// Blocks [first, last) of an image loop.
struct BlockRange {
  long first = 0, last = 0;
};

// Collective: fills `values` (count values of `value_bytes` bytes each, in blocks of `block`) on
// every rank.  The blocks are dealt to the ranks as each asks for more: compute(first, last) runs
// on this thread for each range of blocks this rank takes; then each rank's ranges go to every
// other rank.  Returns this rank's ranges.  Throws, on every rank, when the ranks met loops of
// different sizes or the loop has more than 2^31 positions.  Shares shrink as the work runs out
// (guided self-scheduling on a counter every rank updates atomically through MPI), so a rank that
// is slowed (costly rays, another job on its core, loading the image module) takes less: the
// balance follows the measured cost.
std::vector<BlockRange> deal_and_share(std::byte* values, long count, std::size_t value_bytes, long block,
                                       const std::function<void(long first, long last)>& compute);

// Whether work done now on this process counts as this rank's: on rank 0 always, elsewhere only
// while a dealt block is computed.  Work every rank repeats (a loop that is not dealt) thus counts
// once in a sum over the ranks, as a count a study keeps of its reference rays must.
bool counts_on_this_rank();

// Collective where the ranks are in step (pixels_shared_over_ranks()), elsewhere the value itself:
// the sum over the ranks, and the largest value (NaN when any rank's is NaN).
long sum_over_ranks(long value);
double max_over_ranks(double value);

// Whether `value` holds on every rank, where the ranks are in step (pixels_shared_over_ranks():
// collective); elsewhere `value` itself.  For a choice the ranks must make alike, as using a
// cached reference that one rank might not read.
bool on_every_rank(bool value);

// Ends a run of several ranks on an error with exit code `code`: rank 0 prints `line` and aborts
// every rank.  Another rank waits a second first, so an error every rank meets (bad input) is
// printed once, by rank 0; if it is still running then, it prints `line` naming its rank.
[[noreturn]] void end_ranks(int code, std::string_view line);

}  // namespace vrv
