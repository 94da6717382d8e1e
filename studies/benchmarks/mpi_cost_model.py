#!/usr/bin/env python3
"""A cost model of a reference campaign over MPI ranks, fitted to measured per-ray costs and
checked against a simulation of vrv's own scheduler (issue 28, docs/distributed.md).

    /usr/bin/python3 studies/benchmarks/mpi_cost_model.py BUILD_DIR [--size N] [--rounds N]
        [--campaign K] [--threads T,...]

BUILD_DIR holds a vrv built with -DVRV_WITH_MPI=ON and its Python module.  On the 64^3 grid scene
(studies/benchmarks/grid64_opacity.toml, tol 1e-10) at SIZE^2 (default 1024):

1. Measures: the field evaluations of every pixel's reference ray (the Python module), and in
   ROUNDS rounds (default 3) `vrv render --reference --threads 1` under mpirun with 1 and 2 ranks
   (wall seconds and the pixel loop's seconds).  The seconds per evaluation are fitted from the
   one-rank run: a block's cost is its evaluations times them (the per-ray costs vary from 0 to
   300 evaluations here: empty space, grazing rays, the dense core).
2. Simulates the scheduler (lib/util/ranks.cpp, deal_blocks and share_blocks) event by event: P
   ranks of T threads take chunks of 64-pixel blocks from one counter (a peek and a fetch-and-add
   per chunk, served one at a time on rank 0), each chunk max(4T, left / 8P) blocks run on T
   threads, then every rank sends its blocks to every other.  Checked against the measured run of
   2 ranks.
3. Predicts with a closed-form model (below) and compares it with the simulation at
   P = 1, 2, 4, ..., 1024 for each T (default 1 and 32), and predicts the wall time of a campaign of
   K references (default 24) like this one: one `mpirun ... vrv render --reference` (or verify)
   each, so each pays the launch, vrv's start and the writing (measured: the one-rank run's wall
   less its pixels) and its pixels dealt over all ranks; none or half of them read from the cache.

Network figures for more than one machine are assumptions, not measurements (this machine has
one node): latency 2 us, 10 GB/s per node, 1 us per message, 20 ms per doubling of the ranks to
launch them, a cache entry read at 1 GB/s; loopback on this machine: 1 us and 5 GB/s.  The script
prints what it assumed beside what it measured.

Python 3 with numpy; writes nothing but a scratch directory it removes.
"""
import argparse
import glob
import heapq
import math
import os
import sys
import tempfile
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from mpi_scaling import SCENE, timed  # noqa: E402

BLOCK = 64                 # pixels per block (lib/image_loop.h, ImageLoopHooks::block)
VALUE_BYTES = 64           # bytes exchanged per grey reference pixel: sizeof(ReferenceResult)
LOOPBACK = dict(latency=1e-6, bandwidth=5e9, per_message=1e-6, counter=1e-6, launch=0.0)
CLUSTER = dict(latency=2e-6, bandwidth=10e9, per_message=1e-6, counter=1e-6, launch=0.02)


def chunk_seconds(costs, first, last, threads):
    """Blocks [first, last) on `threads` threads, each block to the first free thread."""
    if threads == 1:
        return float(costs[first:last].sum())
    free = [0.0] * threads
    for c in costs[first:last]:
        heapq.heapreplace(free, free[0] + c)
    return max(free)


def simulate(costs, ranks, threads, net):
    """The scheduler's wall time for one image loop: (compute end, exchange, chunks, ranks that
    computed).  Fetches reach the counter in the order they are sent and are served one at a time."""
    blocks = len(costs)
    if ranks == 1:
        return chunk_seconds(costs, 0, blocks, threads), 0.0, 1, 1
    least, half = 4 * threads, net["latency"] / 2
    taken, counter_free, chunks = 0, 0.0, 0
    own = [0] * ranks
    done = [0.0] * ranks
    events = [(0.0, r, "peek", 0) for r in range(ranks)]
    heapq.heapify(events)
    while events:
        t, r, kind, want = heapq.heappop(events)
        served = max(t + half, counter_free)
        counter_free = served + net["counter"]
        reply = served + half
        if kind == "peek":
            left = blocks - taken
            if left <= 0:
                done[r] = reply
                continue
            heapq.heappush(events, (reply, r, "add", max(least, left // (8 * ranks))))
            continue
        first = taken
        taken += want
        if first >= blocks:
            done[r] = reply
            continue
        last = min(blocks, first + want)
        chunks += 1
        own[r] += last - first
        heapq.heappush(events, (reply + chunk_seconds(costs, first, last, threads), r, "peek", 0))
    exchange = max(((blocks - o) + o * (ranks - 1)) * BLOCK * VALUE_BYTES / net["bandwidth"] for o in own)
    exchange += (ranks - 1) * net["per_message"] + 3 * math.ceil(math.log2(ranks)) * net["latency"]
    return max(done), exchange, chunks, sum(1 for o in own if o)


def model(costs, ranks, threads, net):
    """Closed form in four statistics of the measured block costs (their sum, count, largest block
    and costliest run of 4T consecutive blocks): the work over the ranks that get some, each chunk's
    wait for its slowest block, a tail of the costliest smallest chunk, the counter's round trips,
    and the exchange (each rank sends its share to every other and receives the rest)."""
    blocks, work = len(costs), float(costs.sum())
    if ranks == 1:
        return work / threads
    least = 4 * threads
    busy = min(ranks, math.ceil(blocks / least))
    big = 8 * ranks * least  # below this many blocks left, every chunk is the smallest
    chunks = 8 * ranks * (1 + math.log(blocks / big)) if blocks > big else blocks / least
    window = float(np.convolve(costs, np.ones(min(least, blocks)), "valid").max())
    slowest = (1 - 1 / threads) * float(costs.max())
    compute = work / (busy * threads) + chunks / busy * slowest / 2 + window / threads + slowest
    counter = 2 * chunks / busy * net["latency"]
    exchange = blocks * BLOCK * VALUE_BYTES * (1 + (ranks - 2) / busy) / net["bandwidth"]
    exchange += (ranks - 1) * net["per_message"] + 3 * math.ceil(math.log2(ranks)) * net["latency"]
    return compute + counter + exchange


def evaluations(build, size):
    """Every pixel's field evaluations, row-major (the image loop's order)."""
    found = glob.glob(str(build / "python" / "vrv*.so"))
    if not found:
        sys.exit(f"mpi_cost_model: no Python module in {build}/python (build the vrv_python target)")
    sys.path.insert(0, str(Path(found[0]).parent))
    import vrv
    scene = vrv.Scene.from_file(str(SCENE))
    origins, directions = scene.rays(size, size)
    return np.asarray(scene.reference(origins, directions, tol=1e-10)["evaluations"], dtype=float).ravel()


def measure(build, size, rounds):
    """Best (wall, pixels) seconds of one and two ranks of one thread, one after the other per round."""
    vrv = str(build / "vrv")
    best = {}
    with tempfile.TemporaryDirectory() as tmp:
        for _ in range(rounds):
            for ranks in (1, 2):
                cmd = ["mpirun", "--oversubscribe", "-np", str(ranks), vrv, "render", "--scene", str(SCENE),
                       "--reference", "--width", str(size), "--height", str(size), "--threads", "1", "--quiet",
                       "-o", f"{tmp}/r{ranks}.exr"]
                wall, pixels = timed(cmd)
                old = best.get(ranks, (math.inf, math.inf))
                best[ranks] = (min(old[0], wall), min(old[1], pixels))
    return best


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("build_dir", type=Path)
    ap.add_argument("--size", type=int, default=1024)
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--campaign", type=int, default=24, help="references in the campaign")
    ap.add_argument("--threads", default="1,32", help="threads per rank to tabulate")
    args = ap.parse_args()
    build = args.build_dir.resolve()
    evals = evaluations(build, args.size)
    blocks = evals.reshape(-1, BLOCK).sum(axis=1) if evals.size % BLOCK == 0 else \
        np.add.reduceat(evals, np.arange(0, evals.size, BLOCK))
    load = os.getloadavg()[0]
    best = measure(build, args.size, args.rounds)
    per_eval = best[1][1] / evals.sum()
    costs = blocks * per_eval
    startup = best[1][0] - best[1][1]
    print(f"vrv render --reference, {SCENE.name}, {args.size}^2, tol 1e-10: {evals.sum():.4g} evaluations "
          f"({evals.min():.0f} to {evals.max():.0f} per ray, mean {evals.mean():.0f}); {len(blocks)} blocks of "
          f"{BLOCK} pixels, the costliest {blocks.max() / blocks.mean():.1f}x the mean")
    print(f"measured (best of {args.rounds}, load average {load:.2f} before): 1 rank {best[1][1]:.3f} s pixels, "
          f"{best[1][0]:.3f} s wall; 2 ranks {best[2][1]:.3f} s pixels, {best[2][0]:.3f} s wall; fitted "
          f"{per_eval * 1e9:.1f} ns per evaluation, start-up {startup:.3f} s")
    end, exchange, chunks, _ = simulate(costs, 2, 1, LOOPBACK)
    print(f"check, 2 ranks x 1 thread on this machine: simulated pixels {end + exchange:.3f} s ({chunks} chunks), "
          f"model {model(costs, 2, 1, LOOPBACK):.3f} s, measured {best[2][1]:.3f} s "
          f"(simulated / measured {(end + exchange) / best[2][1]:.2f})\n")
    print(f"assumed network: loopback {LOOPBACK}; across machines {CLUSTER}\n")
    print(f"| threads per rank | ranks P | simulated s | model s | model / simulated | ranks with work | chunks "
          f"| speed-up (simulated) | campaign of {args.campaign}: model s | simulated s | model, half cached s |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    read = len(blocks) * BLOCK * 24 / 1e9  # a cached entry's three planes at 1 GB/s from a shared file system
    for threads in (int(t) for t in args.threads.split(",")):
        base = None
        for p in (2 ** k for k in range(11)):
            end, exchange, chunks, busy = simulate(costs, p, threads, CLUSTER)
            sim = end + exchange
            base = base or sim
            mod = model(costs, p, threads, CLUSTER)
            each = startup + CLUSTER["launch"] * math.log2(p)  # every command's launch, start and writing
            k = args.campaign
            print(f"| {threads} | {p} | {sim:.4g} | {mod:.4g} | {mod / sim:.2f} | {busy} | {chunks} | "
                  f"{base / sim:.1f} | {k * (each + mod):.4g} | {k * (each + sim):.4g} | "
                  f"{k * each + k / 2 * (mod + read):.4g} |")


if __name__ == "__main__":
    main()
