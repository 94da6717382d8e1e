#!/usr/bin/env python3
"""Runs every Google Benchmark program (BUILD_DIR/bench_*) and writes results/performance.md.

    python3 studies/benchmarks/performance_report.py BUILD_DIR [--min-time SECONDS] [--output PATH]

Python 3 standard library only.  Each program runs once, sequentially, with
--benchmark_format=json and --benchmark_out=<temporary file> --benchmark_out_format=json: the
JSON is read from the file (programs that install their own console reporter, such as
bench_odeint, ignore --benchmark_format, but every program honours --benchmark_out), and stdout
is kept for the lines a program prints besides its table (calibrations, ratio summaries).

The report (written atomically: a temporary file in results/, then os.replace) holds the
machine, one table per program, the headline ratios (reference vs Boost.Odeint, vrv's discrete
raycast vs a bare loop, opacity-correction costs vs Lee & Newman's Table 1), the scaling series
of bench_scaling with exponents fitted by least squares in log-log space, the largest study
that fits the machine's memory, and the start-up times of startup.py (run after the programs).  A program that is not built is listed as "not built" and its
figures are "n/a".
"""
import argparse
import datetime
import json
import math
import os
import platform
import re
import shlex
import subprocess
import sys
import tempfile
import time
from pathlib import Path

REPO = Path(__file__).resolve().parent.parent.parent  # studies/benchmarks/ -> the repository
BENCH_SOURCES = REPO / "studies" / "benchmarks"

# The programs the report knows how to read, in report order; any other bench_* found in the
# build directory is run and tabulated after them.
EXPECTED = [
    "bench_reference",
    "bench_discrete",
    "bench_odeint",
    "bench_discrete_baseline",
    "bench_corrections",
    "bench_scaling",
]

NOMINAL_MEMORY_GIB = 24        # the machine's memory as specified for the largest-study figure
HEADROOM = 0.20                # keep 20 % free
GRIDS_PRE_CLASSIFIED = 3       # the field and the two classified grids (emission, extinction)
ODEINT_TARGET = 1e-10          # bench_odeint's matched accuracy (kTarget)
PAPER_CORRECTION_ONLY = 12.36  # Lee & Newman (WSCG 2007) Table 1, N = 5: Lacroute / quadratic
PAPER_WHOLE_RAYCAST = 1.85

# Google Benchmark's own fields in a JSON run; every other numeric field is a user counter.
STANDARD_KEYS = {
    "name", "family_index", "per_family_instance_index", "run_name", "run_type", "repetitions",
    "repetition_index", "threads", "iterations", "real_time", "cpu_time", "time_unit",
    "aggregate_name", "aggregate_unit", "error_occurred", "error_message", "label", "big_o",
    "rms", "complexity",
}
UNIT_SECONDS = {"ns": 1e-9, "us": 1e-6, "ms": 1e-3, "s": 1.0}


# ---- Small helpers -----------------------------------------------------------------------------

def sh(args, cwd=None, timeout=30):
    """stdout of a command, stripped; '' when it cannot run."""
    try:
        r = subprocess.run(args, cwd=cwd, capture_output=True, text=True, timeout=timeout)
        return r.stdout.strip() if r.returncode == 0 else ""
    except (OSError, subprocess.SubprocessError):
        return ""


def read_text(path):
    try:
        return Path(path).read_text(errors="replace")
    except OSError:
        return ""


def fmt(x, digits=4):
    """A number for a table: 4 significant digits, '–' for None, 'n/a' for NaN."""
    if x is None:
        return "–"
    if isinstance(x, bool):
        return str(x)
    if isinstance(x, int):
        return str(x)
    if isinstance(x, float) and (math.isnan(x) or math.isinf(x)):
        return "n/a"
    if x != 0 and (abs(x) >= 1e6 or abs(x) < 1e-3):
        return f"{x:.{digits - 1}e}"
    return f"{x:.{digits}g}"


def fmt_ratio(x):
    return "n/a" if x is None or (isinstance(x, float) and math.isnan(x)) else f"{x:.2f}×"


def fmt_bytes(b):
    for unit, size in (("GiB", 2**30), ("MiB", 2**20), ("KiB", 2**10)):
        if b >= size:
            return f"{b / size:.2f} {unit}"
    return f"{b:.0f} B"


def fmt_seconds(s):
    if s is None or math.isnan(s):
        return "n/a"
    if s >= 3600:
        return f"{s / 3600:.1f} h"
    if s >= 60:
        return f"{s / 60:.1f} min"
    if s >= 1:
        return f"{s:.2f} s"
    return f"{s * 1e3:.3g} ms"


def table(header, rows):
    """A Markdown table; cells are strings (pipes escaped)."""
    esc = lambda c: str(c).replace("|", "\\|")
    out = ["| " + " | ".join(esc(h) for h in header) + " |",
           "|" + "|".join("---" for _ in header) + "|"]
    out += ["| " + " | ".join(esc(c) for c in row) + " |" for row in rows]
    return "\n".join(out)


def loadavg():
    parts = read_text("/proc/loadavg").split()
    return tuple(float(p) for p in parts[:3]) if len(parts) >= 3 else None


# ---- Machine -----------------------------------------------------------------------------------

def cmake_cache(build_dir):
    values = {}
    for line in read_text(Path(build_dir) / "CMakeCache.txt").splitlines():
        m = re.match(r"^([A-Za-z0-9_]+):[A-Z]+=(.*)$", line)
        if m:
            values[m.group(1)] = m.group(2)
    return values


def compile_flags(build_dir):
    """The flags a benchmark source is actually compiled with (from compile_commands.json)."""
    try:
        entries = json.loads(read_text(Path(build_dir) / "compile_commands.json") or "[]")
    except json.JSONDecodeError:
        return ""
    for e in entries:
        if "/studies/benchmarks/bench_" in e.get("file", ""):
            args = e.get("arguments") or shlex.split(e.get("command", ""))
            keep = [a for a in args[1:] if re.match(r"^-(O|D|W|std|f|m|g)", a)]
            return " ".join(keep)
    return ""


def machine_info(build_dir):
    cpuinfo = read_text("/proc/cpuinfo")
    models = re.findall(r"^model name\s*:\s*(.*)$", cpuinfo, re.M)
    mhz = re.findall(r"^cpu MHz\s*:\s*(.*)$", cpuinfo, re.M)
    meminfo = dict(re.findall(r"^(\w+):\s*(\d+) kB", read_text("/proc/meminfo"), re.M))
    osrel = dict(re.findall(r'^(\w+)="?([^"\n]*)"?', read_text("/etc/os-release"), re.M))
    cache = cmake_cache(build_dir)
    compiler = cache.get("CMAKE_CXX_COMPILER", "")
    try:
        nproc = len(os.sched_getaffinity(0))
    except AttributeError:
        nproc = os.cpu_count()
    status = sh(["git", "status", "--porcelain"], cwd=REPO)
    lines = status.splitlines() if status else []
    return {
        "nproc": nproc,
        "cpu_model": models[0] if models else "unknown",
        "cpu_count": len(models),
        "cpu_mhz": mhz[0] if mhz else "",
        "mem_total": int(meminfo.get("MemTotal", 0)) * 1024,
        "mem_available": int(meminfo.get("MemAvailable", 0)) * 1024,
        "os": osrel.get("PRETTY_NAME", platform.platform()),
        "kernel": platform.release(),
        "compiler": compiler,
        "compiler_version": (sh([compiler, "--version"]).splitlines() or [""])[0] if compiler else "",
        "cxx_version": (sh(["c++", "--version"]).splitlines() or [""])[0],
        "build_type": cache.get("CMAKE_BUILD_TYPE", ""),
        "flags_release": cache.get("CMAKE_CXX_FLAGS_RELEASE", ""),
        "flags": cache.get("CMAKE_CXX_FLAGS", ""),
        "generator": cache.get("CMAKE_GENERATOR", ""),
        "compile_flags": compile_flags(build_dir),
        "commit": sh(["git", "rev-parse", "HEAD"], cwd=REPO) or "unknown",
        "modified": sum(1 for l in lines if not l.startswith("??")),
        "untracked": sum(1 for l in lines if l.startswith("??")),
        "python": platform.python_version(),
    }


# ---- Running the programs ----------------------------------------------------------------------

class Program:
    def __init__(self, name):
        self.name = name
        self.built = False
        self.source = BENCH_SOURCES / f"{name}.cpp"
        self.ran = False
        self.returncode = None
        self.failure = ""
        self.elapsed = 0.0
        self.load_before = self.load_after = None
        self.context = {}
        self.runs = []
        self.stdout = ""
        self.stderr = ""
        self.command = []

    def description(self):
        """The source's opening comment, up to its first blank comment line."""
        lines = []
        for line in read_text(self.source).splitlines():
            if not line.startswith("//"):
                break
            text = line[2:].strip()
            if not text:
                break
            lines.append(text)
        return " ".join(lines)


def discover(build_dir):
    found = {p.name for p in Path(build_dir).glob("bench_*")
             if p.is_file() and os.access(p, os.X_OK)}
    sources = {p.stem for p in BENCH_SOURCES.glob("bench_*.cpp")}
    names = EXPECTED + sorted((found | sources) - set(EXPECTED))
    programs = []
    for n in names:
        p = Program(n)
        p.built = n in found
        programs.append(p)
    return programs


# Programs whose figure is a ratio of two benchmarks of one run: repeated and interleaved, so that
# both sides see the same machine (this shared machine's speed swings by up to 2x between
# processes; one run of each side gave 1.99x and 3.49x where five interleaved repetitions gave
# 1.31x and 1.18x).  Results reads the median aggregate.
SIDE_BY_SIDE = {"bench_discrete_baseline": ["--benchmark_repetitions=5", "--benchmark_enable_random_interleaving=true",
                                            "--benchmark_report_aggregates_only=true"]}


def run_program(prog, build_dir, min_time, timeout):
    exe = Path(build_dir).resolve() / prog.name
    with tempfile.TemporaryDirectory(prefix="vrv-bench-") as tmp:
        out = Path(tmp) / "out.json"
        prog.command = [str(exe), f"--benchmark_min_time={min_time}", "--benchmark_format=json",
                        f"--benchmark_out={out}", "--benchmark_out_format=json"] + SIDE_BY_SIDE.get(prog.name, [])
        print(f"[performance_report] running {prog.name} ...", file=sys.stderr, flush=True)
        prog.load_before = loadavg()
        t0 = time.monotonic()
        try:
            r = subprocess.run(prog.command, cwd=tmp, capture_output=True, text=True, timeout=timeout)
            prog.returncode = r.returncode
            prog.stdout, prog.stderr = r.stdout, r.stderr
            if r.returncode != 0:
                prog.failure = f"exit code {r.returncode}"
        except subprocess.TimeoutExpired as e:
            prog.failure = f"timed out after {timeout} s"
            prog.stdout = e.stdout.decode(errors="replace") if isinstance(e.stdout, bytes) else (e.stdout or "")
        except OSError as e:
            prog.failure = f"could not run: {e}"
        prog.elapsed = time.monotonic() - t0
        prog.load_after = loadavg()
        prog.ran = True
        try:
            data = json.loads(out.read_text())
            prog.context = data.get("context", {})
            prog.runs = data.get("benchmarks", [])
        except (OSError, json.JSONDecodeError) as e:
            if not prog.failure:
                prog.failure = f"no JSON output ({e.__class__.__name__})"
    print(f"[performance_report]   {prog.name}: {prog.elapsed:.1f} s"
          + (f" ({prog.failure})" if prog.failure else ""), file=sys.stderr, flush=True)


# ---- Reading results ---------------------------------------------------------------------------

def base_name(run):
    """run_name without Google Benchmark's option suffixes (min_time:, iterations:, real_time)."""
    parts = (run.get("run_name") or run.get("name", "")).split("/")
    keep = [p for p in parts
            if p not in ("real_time", "manual_time", "process_time")
            and not re.match(r"^(min_time|min_warmup_time|iterations|repeats|threads):", p)]
    return "/".join(keep)


def counters(run):
    return {k: v for k, v in run.items()
            if k not in STANDARD_KEYS and isinstance(v, (int, float)) and not isinstance(v, bool)}


def median(values):
    v = sorted(values)
    if not v:
        return float("nan")
    m = len(v) // 2
    return v[m] if len(v) % 2 else 0.5 * (v[m - 1] + v[m])


class Results:
    """Lookup by base name: the median aggregate if the program reported one, else the median
    over the iteration runs (repetitions) of that name.  Times in seconds per iteration."""

    def __init__(self, runs):
        self.by_name = {}
        for r in runs:
            if r.get("error_occurred"):
                continue
            self.by_name.setdefault(base_name(r), []).append(r)

    def names(self):
        return list(self.by_name)

    def _runs(self, name):
        runs = self.by_name.get(name, [])
        med = [r for r in runs if r.get("run_type") == "aggregate" and r.get("aggregate_name") == "median"]
        if med:
            return med
        return [r for r in runs if r.get("run_type", "iteration") == "iteration"]

    def get(self, name, key):
        values = []
        for r in self._runs(name):
            if key in ("real_time", "cpu_time"):
                values.append(r[key] * UNIT_SECONDS.get(r.get("time_unit", "ns"), 1e-9))
            elif key in r:
                values.append(r[key])
        return median(values) if values else float("nan")

    def has(self, name):
        return bool(self._runs(name))


def printed_lines(prog):
    """What a program printed besides Google Benchmark's context block and table rows."""
    text = prog.stdout
    lines = text.splitlines()
    # Drop a JSON document on stdout (programs that use the default reporter).
    if "{" in lines:
        start = lines.index("{")
        end = max(i for i, l in enumerate(lines) if l == "}") if "}" in lines else len(lines) - 1
        lines = lines[:start] + lines[end + 1:]
    names = {r.get("name", "") for r in prog.runs}
    out = []
    skip_prefixes = ("Running ", "Run on ", "CPU Caches", "  L1 ", "  L2 ", "  L3 ", "  L4 ",
                     "Load Average", "***WARNING***", "-----", "Benchmark ")
    for l in lines:
        s = re.sub(r"\x1b\[[0-9;]*m", "", l).rstrip()  # console reporters colour even into a pipe
        if s.startswith(skip_prefixes):
            continue
        if s and s.split()[0] in names:
            continue
        if not s and (not out or not out[-1]):
            continue  # no leading or doubled blank lines
        out.append(s)
    while out and not out[-1]:
        out.pop()
    return out


# ---- Least squares in log-log space ------------------------------------------------------------

def fit_power(xs, ys):
    """t = c s^k by least squares on (log s, log t): (k, c, r2, standard error of k)."""
    pts = [(math.log(x), math.log(y)) for x, y in zip(xs, ys) if x > 0 and y > 0]
    n = len(pts)
    if n < 2:
        return None
    mx = sum(p[0] for p in pts) / n
    my = sum(p[1] for p in pts) / n
    sxx = sum((p[0] - mx) ** 2 for p in pts)
    sxy = sum((p[0] - mx) * (p[1] - my) for p in pts)
    syy = sum((p[1] - my) ** 2 for p in pts)
    if sxx == 0:
        return None
    k = sxy / sxx
    a = my - k * mx
    ss_res = sum((p[1] - (a + k * p[0])) ** 2 for p in pts)
    r2 = 1 - ss_res / syy if syy > 0 else 1.0
    se = math.sqrt(ss_res / (n - 2) / sxx) if n > 2 else float("nan")
    return {"k": k, "c": math.exp(a), "r2": r2, "se": se, "n": n}


# ---- Report sections ---------------------------------------------------------------------------

def section_machine(m, programs, build_arg, started, programs_elapsed, total_elapsed):
    out = ["## Machine and build", ""]
    rows = [
        ("date (UTC)", started.strftime("%Y-%m-%d %H:%M:%S")),
        ("git commit", f"`{m['commit']}`" + (
            f" — working tree: {m['modified']} modified, {m['untracked']} untracked files "
            "(the benchmarks measured the working tree as built, not the bare commit)"
            if m["modified"] or m["untracked"] else " (clean working tree)")),
        ("nproc", str(m["nproc"])),
        ("CPU", f"{m['cpu_model']} ×{m['cpu_count']}" + (f", {m['cpu_mhz']} MHz (/proc/cpuinfo)" if m["cpu_mhz"] else "")),
        ("memory", f"MemTotal {fmt_bytes(m['mem_total'])}, MemAvailable {fmt_bytes(m['mem_available'])} at start (/proc/meminfo)"),
        ("OS", f"{m['os']}, Linux {m['kernel']}"),
        ("compiler", f"`{m['compiler']}`: {m['compiler_version']}; `c++ --version`: {m['cxx_version']}"),
        ("build", f"{build_arg}: CMAKE_BUILD_TYPE={m['build_type'] or '(empty)'}, "
                  f"CMAKE_CXX_FLAGS_RELEASE=`{m['flags_release']}`, CMAKE_CXX_FLAGS=`{m['flags'] or ''}`"
                  + (f", generator {m['generator']}" if m["generator"] else "")),
        ("benchmark compile flags", f"`{m['compile_flags']}` (compile_commands.json)" if m["compile_flags"] else "n/a"),
        ("report run", f"{fmt_seconds(total_elapsed)} in total, {fmt_seconds(programs_elapsed)} of it the programs "
                       f"(sequentially), Python {m['python']}"),
    ]
    out.append(table(["", ""], rows))
    out += ["", "Google Benchmark's context per program (its `num_cpus`, `mhz_per_cpu` and load "
            "average at program start), and /proc/loadavg before and after each program. Other "
            "jobs may share this machine: a 1-minute load above the number of CPUs means the "
            "times below include waiting for a core.", ""]
    rows = []
    for p in programs:
        if not p.built:
            rows.append((p.name, "not built", "", "", "", "", "", ""))
            continue
        c = p.context
        la = c.get("load_avg")
        rows.append((
            p.name,
            p.failure or "ok",
            fmt_seconds(p.elapsed),
            str(c.get("num_cpus", "")),
            str(c.get("mhz_per_cpu", "")),
            ", ".join(f"{x:.2f}" for x in la) if la else "",
            " → ".join(", ".join(f"{x:.2f}" for x in l) for l in (p.load_before, p.load_after) if l),
            c.get("library_build_type", ""),
        ))
    out.append(table(["program", "status", "wall time", "num_cpus", "mhz_per_cpu",
                      "load avg (benchmark context)", "/proc/loadavg before → after",
                      "benchmark library build"], rows))
    if any(p.context.get("library_build_type") == "debug" for p in programs):
        out += ["", "(\"debug\" is how Debian's Google Benchmark library was built — the harness, not "
                "the timed code, which is compiled with the flags above.)"]
    return "\n".join(out)


def section_program(p):
    out = [f"### {p.name}", ""]
    desc = p.description()
    if desc:
        out += [f"_{desc}_", ""]
    if not p.built:
        out.append(f"**not built** (no executable `{p.name}` in the build directory).")
        return "\n".join(out)
    shown = [p.name] + [a if not a.startswith("--benchmark_out=") else "--benchmark_out=<tmp>.json"
                        for a in p.command[1:]]
    out.append(f"Command: `{' '.join(shown)}` — {fmt_seconds(p.elapsed)} wall.")
    if p.failure:
        out += ["", f"**{p.failure}**."]
        err = [l for l in p.stderr.splitlines() if l.strip()][-5:]
        if err:
            out += ["", "```", *err, "```"]
    if p.runs:
        keys = []
        for r in p.runs:
            for k in counters(r):
                if k not in keys:
                    keys.append(k)
        rows = []
        for r in p.runs:
            unit = r.get("time_unit", "ns")
            name = r.get("name", "")
            if r.get("error_occurred"):
                rows.append([f"`{name}`", "error: " + r.get("error_message", ""), "", ""] + [""] * len(keys))
                continue
            c = counters(r)
            rows.append([f"`{name}`", f"{fmt(r.get('real_time'))} {unit}", f"{fmt(r.get('cpu_time'))} {unit}",
                         str(r.get("iterations", ""))] + [fmt(c.get(k)) for k in keys])
        out += ["", table(["benchmark", "real time / iter", "CPU time / iter", "iterations"] + keys, rows)]
        if any(k.endswith("_per_s") for k in keys):
            out += ["", "Rates (`*_per_s`) are per second of the benchmark's time (CPU time unless the "
                    "name ends in `real_time`)."]
    extra = printed_lines(p)
    if extra:
        out += ["", "Printed by the program:", "", "```", *extra, "```"]
    return "\n".join(out)


def headline_odeint(p):
    out = ["### Reference integrator vs Boost.Odeint (bench_odeint)", ""]
    if not p or not p.built:
        return "\n".join(out + ["n/a — bench_odeint not built."])
    res = Results(p.runs)
    if not res.has("BM_Reference"):
        return "\n".join(out + ["n/a — BM_Reference missing from bench_odeint's output."])
    ref_e = res.get("BM_Reference", "evals_per_ray")
    ref_c = res.get("BM_Reference", "cpu_time")
    ref_r = res.get("BM_Reference", "real_time")
    rows, best_e, best_c = [], None, None
    for label, name in (("RKF78", "BM_Odeint_RKF78"), ("DOPRI5", "BM_Odeint_DOPRI5")):
        if not res.has(name):
            rows.append((label, "n/a", "n/a", "n/a", "n/a", "n/a", "n/a"))
            continue
        err = res.get(name, "max_abs_error")
        matched = err <= ODEINT_TARGET
        e = res.get(name, "evals_per_ray") / ref_e
        c = res.get(name, "cpu_time") / ref_c
        r = res.get(name, "real_time") / ref_r
        rows.append((label, fmt(res.get(name, "tol")), fmt(err), "yes" if matched else "NO",
                     fmt_ratio(e), fmt_ratio(c), fmt_ratio(r)))
        if matched:
            if best_e is None or e < best_e[0]:
                best_e = (e, label)
            if best_c is None or c < best_c[0]:
                best_c = (c, label, r)
    out.append(f"Same 64 rays (Marschner–Lobb, non-proportional transfer function), each method at the "
               f"loosest tolerance whose largest achieved error is ≤ {ODEINT_TARGET:.0e}. Reference: tol "
               f"{fmt(res.get('BM_Reference', 'tol'))}, {fmt(ref_e)} evaluations/ray, "
               f"{fmt(ref_c / 64 * 1e6)} µs CPU/ray. Ratios are odeint stepper / reference (from the JSON "
               f"counters `evals_per_ray`, `max_abs_error`, `tol` and the CPU/real time per iteration).")
    out += ["", table(["stepper", "tol", "max abs error", "matched", "evaluations ratio", "CPU time ratio",
                       "real time ratio"], rows), ""]
    if best_e:
        out.append(f"**Headline:** the better matched stepper needs **{best_e[0]:.1f}×** the reference's "
                   f"evaluations ({best_e[1]}; goal ≥ 10×: {'met' if best_e[0] >= 10 else 'NOT met'}) and "
                   f"**{best_c[0]:.2f}×** its CPU time ({best_c[1]}; goal ≥ 5×: "
                   f"{'met' if best_c[0] >= 5 else 'NOT met'}; real time {best_c[2]:.2f}×).")
    else:
        out.append("**Headline:** no odeint stepper reaches the target accuracy; goal not assessable.")
    return "\n".join(out)


def headline_baseline(p):
    out = ["### vrv discrete raycast vs a bare trilinear loop (bench_discrete_baseline)", ""]
    if not p or not p.built:
        return "\n".join(out + ["n/a — bench_discrete_baseline not built."])
    res = Results(p.runs)
    cases = []
    for n in res.names():
        parts = n.split("/")
        if len(parts) == 3 and parts[1] in ("vrv", "baseline"):
            key = (parts[0], parts[2])
            if key not in cases:
                cases.append(key)
    if not cases:
        return "\n".join(out + ["n/a — no `<field>/vrv|baseline/<threads>` runs in bench_discrete_baseline's output."])
    rows = []
    worst = None
    for field, threads in cases:
        v = res.get(f"{field}/vrv/{threads}", "samples_per_s")
        b = res.get(f"{field}/baseline/{threads}", "samples_per_s")
        slow = b / v if v and not math.isnan(v) and not math.isnan(b) else float("nan")
        if not math.isnan(slow):
            worst = slow if worst is None else max(worst, slow)
        met = lambda goal: "n/a" if math.isnan(slow) else ("met" if slow <= goal else "NOT met")
        rows.append((field, threads, fmt(v), fmt(b), fmt_ratio(slow), met(2),
                     met(1.25) if threads == "1thread" else "—"))
    out.append("Samples per second (wall clock) of `DiscreteRaycaster` and of the bare loop over the same "
               "samples, medians of five repetitions interleaved at random (`SIDE_BY_SIDE`); slowdown = "
               "baseline samples/s ÷ vrv samples/s = vrv time ÷ baseline time (goal ≤ 2; "
               "issue 23's goal: ≤ 1.25 on one thread).")
    out += ["", table(["field", "threads", "vrv samples/s", "baseline samples/s", "slowdown (vrv/baseline time)",
                       "goal ≤ 2×", "issue 23: ≤ 1.25× (one thread)"], rows), ""]
    if worst is not None:
        out.append(f"**Headline:** worst slowdown {worst:.2f}× over {len(rows)} cases.")
    return "\n".join(out)


def headline_corrections(p):
    out = ["### Opacity-correction cost vs Lee & Newman's Table 1 (bench_corrections)", ""]
    if not p or not p.built:
        return "\n".join(out + ["n/a — bench_corrections not built."])
    res = Results(p.runs)
    C = lambda v, N: res.get(f"BM_Correct/{v}/{N}", "ns_per_sample")
    R = lambda v, N: res.get(f"BM_Raycast/{v}/{N}", "ns_per_sample")
    div = lambda a, b: a / b if b and not math.isnan(a) and not math.isnan(b) else float("nan")
    rows = []
    for N in (5, 2):
        paper_c = f"{PAPER_CORRECTION_ONLY}×" if N == 5 else "–"
        paper_r = f"{PAPER_WHOLE_RAYCAST}×" if N == 5 else "–"
        rows.append((N, "correction only: lacroute_vrv / quadratic_vrv", fmt_ratio(div(C("lacroute_vrv", N), C("quadratic_vrv", N))), paper_c))
        rows.append((N, "correction only: lacroute_pow / quadratic_lean", fmt_ratio(div(C("lacroute_pow", N), C("quadratic_lean", N))), paper_c))
        rows.append((N, "correction only: lacroute_lut / quadratic_lean", fmt_ratio(div(C("lacroute_lut", N), C("quadratic_lean", N))), paper_c))
        if res.has(f"BM_BareRaycast/lacroute_pow/{N}"):
            rows.append((N, "bare raycast: lacroute_pow / quadratic_lean",
                         fmt_ratio(div(res.get(f"BM_BareRaycast/lacroute_pow/{N}", "ns_per_sample"),
                                       res.get(f"BM_BareRaycast/quadratic_lean/{N}", "ns_per_sample"))), paper_r))
            rows.append((N, "bare raycast: lacroute_vrv / quadratic_vrv",
                         fmt_ratio(div(res.get(f"BM_BareRaycast/lacroute_vrv/{N}", "ns_per_sample"),
                                       res.get(f"BM_BareRaycast/quadratic_vrv/{N}", "ns_per_sample"))), paper_r))
        rows.append((N, "whole raycast: lacroute / lee_newman_quadratic", fmt_ratio(div(R("lacroute", N), R("lee_newman_quadratic", N))), paper_r))
        with_pow = R("lacroute", N) - C("lacroute_vrv", N) + C("lacroute_pow", N)
        rows.append((N, "whole raycast, lacroute with pow (estimated) / lee_newman_quadratic",
                     fmt_ratio(div(with_pow, R("lee_newman_quadratic", N))), paper_r))
    out.append("Ratios of ns per sample (JSON counter `ns_per_sample`); > 1 means the quadratic fit is faster. "
               "The paper's figures are averages over 40 datasets at N = 5 without lookup tables.")
    out += ["", table(["N", "ratio", "measured", "paper"], rows), ""]
    r5 = div(C("lacroute_vrv", 5), C("quadratic_vrv", 5))
    w5 = div(R("lacroute", 5), R("lee_newman_quadratic", 5))
    lean5 = div(C("lacroute_pow", 5), C("quadratic_lean", 5))
    out.append(f"**Headline (N = 5):** correction alone {fmt_ratio(r5)} with vrv's implementations "
               f"({fmt_ratio(lean5)} textbook pow vs the lean fit; paper {PAPER_CORRECTION_ONLY}×), "
               f"whole raycast {fmt_ratio(w5)} (paper {PAPER_WHOLE_RAYCAST}×).")
    return "\n".join(out)


# bench_scaling's series: (title, family, size counter, what the size is, expected exponent and why)
SCALING_SERIES = [
    ("Image size — reference integrator (analytic field, tol 1e-10), all threads",
     "BM_Image_Reference", "pixels", "pixels", "1 (fixed work per pixel)"),
    ("Image size — riemann, entry_exit_corner rate 1 (analytic field), all threads",
     "BM_Image_Riemann", "pixels", "pixels", "1"),
    ("Refinement — riemann on the 64³ grid, 64² pixels", "BM_Rate_Riemann", "rate", "rate", "1 (samples ∝ rate)"),
    ("Refinement — exact_linear on the 64³ grid, 64² pixels", "BM_Rate_ExactLinear", "rate", "rate", "1"),
    ("Grid size — riemann rate 1, dims = n³, 64² pixels", "BM_Grid_Riemann", "grid_n", "n",
     "1 (samples per ray ∝ n)"),
    ("Grid size — reference integrator (tol 1e-10), 32² pixels", "BM_Grid_Reference", "grid_n", "n",
     "1 (cells crossed ∝ n)"),
    ("Grid size — grid construction (make_grid, one thread)", "BM_Grid_Build", "grid_n", "n", "3 (n³ nodes)"),
]


def scaling_points(res, family, size_key):
    pts = []
    for name in res.names():
        if name.split("/")[0] != family:
            continue
        s = res.get(name, size_key)
        t = res.get(name, "real_time")
        if math.isnan(s) or math.isnan(t):
            continue
        pixels = res.get(name, "pixels")
        wpp = res.get(name, "work_per_pixel")
        if family == "BM_Grid_Build":
            n = res.get(name, "grid_n")
            work = n ** 3
        else:
            work = wpp * pixels if not (math.isnan(wpp) or math.isnan(pixels)) else float("nan")
        pts.append({"name": name, "size": s, "time": t, "cpu": res.get(name, "cpu_time"),
                    "pixels": pixels, "work": work, "wpp": wpp,
                    "grid_bytes": res.get(name, "grid_bytes"), "side": res.get(name, "side"),
                    "iterations": (res._runs(name) or [{}])[0].get("iterations", "")})
    return sorted(pts, key=lambda p: p["size"])


def section_scaling(p):
    out = ["## Scaling (bench_scaling)", ""]
    fits = {}
    if not p or not p.built:
        return "\n".join(out + ["n/a — bench_scaling not built."]), fits
    res = Results(p.runs)
    out.append("Wall-clock time per iteration (one whole image) against the size, and the exponent k of "
               "time ∝ size^k fitted by least squares on (log size, log time): k = Σ(x−x̄)(y−ȳ) / Σ(x−x̄)², "
               "x = ln size, y = ln time (± its standard error; R² of the fit). \"k (largest 3)\" fits only the "
               "three largest points, where fixed per-image costs (thread start-up, plan set-up) matter least. "
               "\"work k\" is the same fit for the work done (field evaluations or samples summed over pixels; "
               "nodes for construction), so k − work k is how much the cost per unit of work drifts with size "
               "(caches, memory bandwidth). Camera: perspective from (0, 0, −4), 35° fov; every pixel hits "
               "the box (`hit_fraction` = 1 in its table below). bench_scaling sets its own minimum time per benchmark "
               "(0.5 s; fixed 1–3 iterations for the largest cases), whatever `--benchmark_min_time` says.")
    summary = []
    for title, family, size_key, size_label, expected in SCALING_SERIES:
        pts = scaling_points(res, family, size_key)
        out += ["", f"### {title}", ""]
        if not pts:
            out.append(f"n/a — no `{family}` runs.")
            summary.append((title, "n/a", "n/a", "n/a", expected))
            continue
        rows = []
        for q in pts:
            size = fmt(q["size"])
            if size_key == "pixels" and not math.isnan(q["side"]):
                size = f"{int(q['side'])}² = {int(q['size'])}"
            if size_key == "grid_n":
                size = f"{int(q['size'])}³ ({fmt_bytes(q['grid_bytes'])})" if not math.isnan(q["grid_bytes"]) else f"{int(q['size'])}³"
            per_work = q["time"] / q["work"] * 1e9 if q["work"] and not math.isnan(q["work"]) else float("nan")
            rows.append((size, fmt(q["time"] * 1e3), fmt(q["cpu"] * 1e3), fmt(q["work"]), fmt(per_work),
                         str(q["iterations"])))
        out.append(table([size_label, "wall ms", "CPU ms (main thread)", "work", "wall ns / unit of work",
                          "iterations"], rows))
        f_all = fit_power([q["size"] for q in pts], [q["time"] for q in pts])
        f_tail = fit_power([q["size"] for q in pts[-3:]], [q["time"] for q in pts[-3:]]) if len(pts) > 3 else f_all
        f_work = fit_power([q["size"] for q in pts], [q["work"] for q in pts if not math.isnan(q["work"])]) \
            if all(not math.isnan(q["work"]) for q in pts) else None
        fits[family] = {"all": f_all, "tail": f_tail, "work": f_work, "points": pts}
        if f_all:
            se = "" if math.isnan(f_all["se"]) else f" ± {f_all['se']:.3f}"
            line = (f"Fit over {f_all['n']} points: time ∝ {size_label}^**{f_all['k']:.3f}**{se} "
                    f"(R² = {f_all['r2']:.4f}); largest 3: k = {f_tail['k']:.3f}")
            if f_work:
                line += f"; work k = {f_work['k']:.3f}"
            out += ["", line + "."]
        summary.append((title, f"{f_all['k']:.3f}" if f_all else "n/a", f"{f_tail['k']:.3f}" if f_tail else "n/a",
                        f"{f_work['k']:.3f}" if f_work else "n/a", expected))
    out += ["", "### Fitted exponents", "",
            table(["series", "k (all points)", "k (largest 3)", "work k", "expected"], summary)]
    return "\n".join(out), fits


def read_constant(path, name):
    m = re.search(rf"{name}\s*=\s*([^;]+);", read_text(path))
    if not m:
        return None
    expr = m.group(1)
    m2 = re.fullmatch(r"\s*(?:std::int64_t\{(\d+)\}|(\d+))\s*<<\s*(\d+)\s*", expr)
    if m2:
        return int(m2.group(1) or m2.group(2)) << int(m2.group(3))
    m3 = re.fullmatch(r"\s*(\d+)\s*", expr)
    return int(m3.group(1)) if m3 else None


def extrapolate(fit_entry, size):
    """Time at `size` from the largest measured point and the tail exponent (rough)."""
    if not fit_entry or not fit_entry["tail"]:
        return float("nan")
    last = fit_entry["points"][-1]
    return last["time"] * (size / last["size"]) ** fit_entry["tail"]["k"]


def section_largest(p, fits, machine):
    out = ["## The largest study that fits in memory", ""]
    res = Results(p.runs) if p and p.built else None
    # Bytes per node: the measured growth of the resident set for the largest grid built.
    b_node, b_source = 8.0, "8 B (one double per node; bench_scaling not run)"
    b_pixel, p_source = 20.0, "20 B (float value + long work + double error estimate, as `vrv render` keeps)"
    if res:
        builds = sorted((res.get(n, "grid_n"), n) for n in res.names() if n.startswith("BM_Grid_Build/"))
        measured = [(g, n) for g, n in builds if not math.isnan(res.get(n, "rss_bytes_per_node"))
                    and res.get(n, "rss_bytes_per_node") > 0]
        if measured:
            g, n = measured[-1]
            rss = res.get(n, "rss_bytes_per_node")
            b_node = max(rss, res.get(n, "grid_bytes") / g ** 3)
            b_source = (f"{rss:.3f} B measured (resident-set growth while one {int(g)}³ grid is built; "
                        f"`grid_bytes` / n³ = {res.get(n, 'grid_bytes') / g ** 3:.0f} B)")
        if builds and not math.isnan(res.get(builds[-1][1], "image_bytes_per_pixel")):
            b_pixel = res.get(builds[-1][1], "image_bytes_per_pixel")
            p_source = f"{b_pixel:.0f} B (`image_bytes_per_pixel`: float value + long work + double error estimate, as `vrv render` keeps)"
    max_side = read_constant(REPO / "lib" / "camera.h", "kMaxImageSide")
    max_file_nodes = read_constant(REPO / "lib" / "scene_file.cpp", "kMaxGridNodes")

    def largest(memory_bytes):
        usable = (1 - HEADROOM) * memory_bytes
        image_px = 256 * 256
        n = int(((usable - b_pixel * image_px) / (GRIDS_PRE_CLASSIFIED * b_node)) ** (1 / 3))
        while GRIDS_PRE_CLASSIFIED * b_node * (n + 1) ** 3 + b_pixel * image_px <= usable:
            n += 1
        while GRIDS_PRE_CLASSIFIED * b_node * n ** 3 + b_pixel * image_px > usable:
            n -= 1
        n_post = int((usable / b_node) ** (1 / 3))
        while b_node * (n_post + 1) ** 3 <= usable:
            n_post += 1
        grid_bytes_256 = GRIDS_PRE_CLASSIFIED * b_node * 256 ** 3
        side = int(math.sqrt((usable - grid_bytes_256) / b_pixel))
        return usable, n, n_post, side

    nominal = NOMINAL_MEMORY_GIB * 2 ** 30
    usable, n, n_post, side = largest(nominal)
    usable_m, n_m, n_post_m, side_m = largest(machine["mem_total"]) if machine["mem_total"] else (0, 0, 0, 0)
    capped = min(side, max_side) if max_side else side
    out += [
        f"Memory M = {NOMINAL_MEMORY_GIB} GiB (the machine's nominal size; /proc/meminfo reports MemTotal = "
        f"{fmt_bytes(machine['mem_total'])}), keeping {HEADROOM:.0%} headroom: usable U = {1 - HEADROOM:.1f} M = "
        f"{fmt_bytes(usable)}.",
        "",
        f"- bytes per grid node b = {b_source}; bytes per image pixel p = {p_source};",
        f"- a pre-classified discrete raycast keeps {GRIDS_PRE_CLASSIFIED} grids alive (the field and the two "
        "classified grids `DiscreteRaycaster` builds with `GridField::mapped`); post-classification and the "
        "reference integrator keep 1.",
        "",
        "Formulas: the largest cubic grid n_max = ⌊∛((U − p·W·H) / (3·b))⌋ (pre-classified, W×H image); "
        "the largest image side W_max = ⌊√((U − 3·b·n³) / p)⌋ for an n³ pre-classified grid, "
        + (f"and at most kMaxImageSide = {max_side} (lib/camera.h)." if max_side else "."),
        "",
        table(["", f"M = {NOMINAL_MEMORY_GIB} GiB", f"M = MemTotal ({fmt_bytes(machine['mem_total'])})"], [
            ("largest cubic grid, pre-classified (3 grids, 256² image)",
             f"**{n}³** = {n ** 3:.3e} nodes, {fmt_bytes(GRIDS_PRE_CLASSIFIED * b_node * n ** 3)}",
             f"{n_m}³, {fmt_bytes(GRIDS_PRE_CLASSIFIED * b_node * n_m ** 3)}"),
            ("largest cubic grid, post-classified (1 grid)", f"{n_post}³, {fmt_bytes(b_node * n_post ** 3)}",
             f"{n_post_m}³"),
            ("largest square image (with a 256³ pre-classified grid)",
             f"{side}² by memory ({fmt_bytes(b_pixel * side ** 2)}); **{capped}²** allowed"
             + (f" (kMaxImageSide)" if max_side and side > max_side else ""),
             f"{side_m}² by memory; {min(side_m, max_side) if max_side else side_m}² allowed"),
        ]),
    ]
    if max_file_nodes:
        c = round(max_file_nodes ** (1 / 3))
        out += ["", f"A grid read from a scene file is further capped at kMaxGridNodes = {max_file_nodes} nodes "
                f"(lib/scene_file.cpp; {c}³ for a cube, {fmt_bytes(8 * max_file_nodes)} of doubles), so the "
                f"{n}³ figure applies to grids built in code (`make_grid`)."]
    # Rough times at the limits, from the tail exponents.
    rows = []
    if fits.get("BM_Grid_Build"):
        rows.append((f"build the {n}³ grid (one thread)", fmt_seconds(extrapolate(fits["BM_Grid_Build"], n))))
    if fits.get("BM_Grid_Riemann"):
        rows.append((f"riemann rate 1 on the {n}³ grid, 64² pixels", fmt_seconds(extrapolate(fits["BM_Grid_Riemann"], n))))
    if fits.get("BM_Grid_Reference"):
        rows.append((f"reference on the {n}³ grid, 32² pixels", fmt_seconds(extrapolate(fits["BM_Grid_Reference"], n))))
    if fits.get("BM_Image_Reference"):
        rows.append((f"reference (analytic field), {capped}² pixels",
                     fmt_seconds(extrapolate(fits["BM_Image_Reference"], float(capped) ** 2))))
    if fits.get("BM_Image_Riemann"):
        rows.append((f"riemann (analytic field), {capped}² pixels",
                     fmt_seconds(extrapolate(fits["BM_Image_Riemann"], float(capped) ** 2))))
    if rows:
        out += ["", "Rough wall times at those limits on this machine (the largest measured point scaled by the "
                "\"largest 3\" exponent; an extrapolation, not a measurement):", "",
                table(["study", "estimated time"], rows)]
    headline = (f"{n}³ pre-classified grid ({fmt_bytes(GRIDS_PRE_CLASSIFIED * b_node * n ** 3)}) or a {capped}² "
                f"image in {NOMINAL_MEMORY_GIB} GiB with {HEADROOM:.0%} headroom")
    return "\n".join(out), headline


# ---- Sections from a script's table -------------------------------------------------------------

def script_section(title, script_name, args, intro, timeout):
    """A benchmark script's Markdown table under `title`, run in this report, with its command."""
    cmd = [sys.executable, str(BENCH_SOURCES / script_name)] + args
    try:
        out = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout)
    except (OSError, subprocess.TimeoutExpired) as e:
        return f"{title}\n\nNot measured: {e}"
    if out.returncode != 0:
        return f"{title}\n\nNot measured: `{shlex.join(cmd)}` exited {out.returncode}: {out.stderr.strip()}"
    shown = shlex.join(["python3", f"studies/benchmarks/{script_name}"] + args)
    return "\n".join([title, "", f"`{shown}`: {intro}", "", out.stdout.strip()])


def section_startup(build_dir, runs=20):
    """startup.py's table (start-up and the image module's cost)."""
    return script_section(
        "## Start-up", "startup.py", [str(build_dir), "--runs", str(runs)],
        "each command's wall and CPU time against `/bin/true`. vrv loads OpenImageIO only in processes "
        "that read or write an image (the image module, lib/io/image_module.h); the `render 1x1` row pays "
        "for loading it.", 600)


def section_reference_image(build_dir, rounds=3):
    """reference_image_cost.py's tables: the reference image against the discrete image it judges,
    on the default scene and on issue 23's 64^3 opacity grid, at 256^2 and 512^2."""
    grid = "studies/benchmarks/grid64_opacity.toml"
    runs = [("the default scene", []), ("the 64³ opacity grid", ["--scene", grid, "--step", "0.00625"])]
    parts = []
    for what, extra in runs:
        for size in (256, 512):
            parts.append(script_section(
                f"### {what}, {size}²", "reference_image_cost.py",
                [str(build_dir), "--rounds", str(rounds), "--size", str(size)] + extra,
                "one thread, median of the rounds.", 1200))
    return "\n\n".join(["## Reference image against the trapezoid image it judges",
                         "The reference image at tol 1e-10 against the trapezoid image about 5e-6 off "
                         "(goals: at most 1x on the analytic default scene, issue 10; at most 2x on a 64³ "
                         "trilinear grid with an opacity transfer function, issue 23). Old against new "
                         "builds side by side: `--before OLD_BUILD`."] + parts)


def section_verify_speed(build_dir, rounds=3):
    """verify_speed.py's table: `vrv verify` with its reference cached, default and grid scene."""
    return script_section(
        "## verify with its reference cached", "verify_speed.py", [str(build_dir), "--rounds", str(rounds)],
        "`vrv verify --out` on 5 images of 256² with the reference cached, with and without the plot, on "
        "the default scene and a 64³ grid scene (issue 23's goal: at most 2 and 3 CPU s). Old against new "
        "builds side by side: `--before OLD_BUILD`.", 1800)


def section_verify_first_run(build_dir):
    """verify_speed.py --first-run: 6 images of 1024² on the grid scene, the reference computed."""
    return script_section(
        "## verify's first run at 1024²", "verify_speed.py",
        [str(build_dir), "--rounds", "1", "--size", "1024", "--images", "6", "--first-run", "--scenes", "grid",
         "--no-plot-rows"],
        "`vrv verify --out` on 6 images of 1024² of the 64³ grid scene with an empty reference cache, so the "
        "reference image is computed in the timed run, as on a user's first run (issue 23's goal: at most "
        "40 CPU s).", 1800)


def section_thread_scaling(build_dir):
    """thread_scaling.py's table: render --reference and a cached verify at 1 and 2 threads."""
    return script_section(
        "## Thread scaling", "thread_scaling.py", [str(build_dir)],
        "wall time at 1 and 2 threads, alternately (issue 23's goal: at least 1.8x on an idle machine, "
        "serial parts named); the load average says whether the machine was idle.", 1800)


def section_study_work(build_dir):
    """study_work.py's table: each shipped study's estimated work against its wall time."""
    return script_section(
        "## Study work against time", "study_work.py", [str(build_dir)],
        "every shipped study (full run, no plots) one after another: the field evaluations its file was "
        "estimated at before it ran (what `vrv study --max-work` is checked against) and the estimate per "
        "second of wall time, which says what the default limit of 1e10 means on this machine.", 1800)


# ---- Main --------------------------------------------------------------------------------------

def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("build_dir", help="the CMake build directory holding bench_* (e.g. build)")
    ap.add_argument("--min-time", default="0.2",
                    help="--benchmark_min_time for every program, in seconds (default 0.2; bench_scaling "
                         "sets its own per benchmark)")
    ap.add_argument("--timeout", type=float, default=1200, help="per program, seconds (default 1200)")
    ap.add_argument("--output", default=str(REPO / "results" / "performance.md"))
    args = ap.parse_args()

    build_dir = Path(args.build_dir)
    if not build_dir.is_dir():
        sys.exit(f"performance_report: {args.build_dir}: not a directory")
    started = datetime.datetime.now(datetime.timezone.utc)
    t0 = time.monotonic()
    machine = machine_info(build_dir)
    programs = discover(build_dir)
    for p in programs:
        if p.built:
            run_program(p, build_dir, args.min_time, args.timeout)
    by_name = {p.name: p for p in programs}
    programs_time = time.monotonic() - t0

    try:
        build_arg = os.path.relpath(build_dir.resolve(), REPO)
        if build_arg.startswith(".."):
            build_arg = str(build_dir)
    except ValueError:
        build_arg = str(build_dir)

    startup_text = section_startup(build_dir)
    reference_image_text = section_reference_image(build_dir)
    verify_speed_text = section_verify_speed(build_dir)
    verify_first_run_text = section_verify_first_run(build_dir)
    thread_scaling_text = section_thread_scaling(build_dir)
    study_work_text = section_study_work(build_dir)
    scaling_text, fits = section_scaling(by_name.get("bench_scaling"))
    largest_text, largest_headline = section_largest(by_name.get("bench_scaling"), fits, machine)
    total = time.monotonic() - t0  # the programs and the sections' own runs (thread scaling, ...)
    built = [p.name for p in programs if p.built]
    missing = [p.name for p in programs if not p.built]

    doc = [
        f"Generated by `python3 studies/benchmarks/performance_report.py {build_arg}` — do not edit by hand.",
        "",
        "# vrv performance",
        "",
        f"Run {started.strftime('%Y-%m-%d %H:%M UTC')} on commit `{machine['commit'][:12]}`; programs run: "
        + (", ".join(f"`{n}`" for n in built) or "none")
        + (f"; not built: {', '.join(f'`{n}`' for n in missing)}" if missing else "")
        + f". Whole report run: {fmt_seconds(total)} (the programs {fmt_seconds(programs_time)}). "
        + f"Largest study: {largest_headline}.",
        "",
        section_machine(machine, programs, build_arg, started, programs_time, total),
        "",
        "## Headline ratios",
        "",
        headline_odeint(by_name.get("bench_odeint")),
        "",
        headline_baseline(by_name.get("bench_discrete_baseline")),
        "",
        headline_corrections(by_name.get("bench_corrections")),
        "",
        startup_text,
        "",
        reference_image_text,
        "",
        verify_speed_text,
        "",
        verify_first_run_text,
        "",
        thread_scaling_text,
        "",
        study_work_text,
        "",
        scaling_text,
        "",
        largest_text,
        "",
        "## Every benchmark",
        "",
        "Times are per iteration as Google Benchmark reports them; counters as the programs define them "
        "(see each source's header comment).",
    ]
    for p in programs:
        doc += ["", section_program(p)]
    text = "\n".join(doc).rstrip() + "\n"

    out_path = Path(args.output)
    out_path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(dir=out_path.parent, prefix=f".{out_path.name}.", suffix=".tmp")
    try:
        with os.fdopen(fd, "w") as f:
            f.write(text)
        os.chmod(tmp, 0o644)
        os.replace(tmp, out_path)
    except BaseException:
        try:
            os.unlink(tmp)
        except OSError:
            pass
        raise
    print(f"[performance_report] wrote {out_path} ({fmt_seconds(time.monotonic() - t0)})", file=sys.stderr)
    return 1 if any(p.failure for p in programs if p.built) else 0


if __name__ == "__main__":
    sys.exit(main())
