#!/usr/bin/env python3
"""What calling vrv from Python costs: reference values for 100,000 rays through `import vrv`
against the same rays through the C++ API (build/bench_library), best of several runs each,
alternating.  Not a test: run it on an idle machine and read the ratio.

    PYTHONPATH=build/python python3 studies/python/benchmark.py build [--repeats K]
"""
import argparse
import json
import pathlib
import subprocess
import time

import numpy as np

import vrv


def library_rays(n):
    """The rays of studies/benchmarks/bench_library.cpp, bit for bit."""
    i = np.arange(n)
    a, b, c = (i % 317) / 316.0, (i % 331) / 330.0, (i % 337) / 336.0
    origins = np.stack([np.full(n, -3.0), -0.8 + 1.6 * a, -0.8 + 1.6 * b], axis=1)
    directions = np.stack([np.ones(n), 0.2 * c - 0.1, np.full(n, 0.05)], axis=1)
    return origins, directions


def cpp_seconds(build, n):
    out = subprocess.run([str((build / "bench_library").resolve()), f"--benchmark_filter=LibraryReference/{n}",
                          "--benchmark_format=json", "--benchmark_min_time=0"],
                         check=True, capture_output=True, text=True).stdout
    run = json.loads(out)["benchmarks"][0]
    return run["real_time"] / 1e3, run["value_sum"]  # milliseconds -> seconds


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("build", type=pathlib.Path)
    parser.add_argument("--repeats", type=int, default=3)
    args = parser.parse_args()
    args.rays = 100_000  # bench_library's batch
    scene = vrv.Scene.default()
    origins, directions = library_rays(args.rays)
    py_times, cpp_times = [], []
    for _ in range(args.repeats):
        start = time.perf_counter()
        values = scene.reference(origins, directions, tol=1e-12)["value"]
        py_times.append(time.perf_counter() - start)
        seconds, cpp_sum = cpp_seconds(args.build, args.rays)
        cpp_times.append(seconds)
    py_sum = float(np.sum(values))
    assert abs(py_sum - cpp_sum) <= 1e-9 * abs(cpp_sum), (py_sum, cpp_sum)  # the same rays
    ratio = min(py_times) / min(cpp_times)
    print(f"{args.rays} rays, best of {args.repeats}: Python {min(py_times):.3f} s, "
          f"C++ API {min(cpp_times):.3f} s, ratio {ratio:.3f} (goal <= 1.2)")
    print(f"  all runs: Python {', '.join(f'{t:.3f}' for t in py_times)}; "
          f"C++ {', '.join(f'{t:.3f}' for t in cpp_times)}")


if __name__ == "__main__":
    main()
