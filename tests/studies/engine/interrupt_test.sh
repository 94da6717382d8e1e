#!/usr/bin/env bash
# Interrupted studies, end to end (docs/robustness.md):
#  1. a run killed with SIGKILL midway leaves the previous results untouched, and --resume gives
#     tables byte-identical to an uninterrupted run's (the hard cases; the tiny convergence study);
#  2. SIGTERM midway: exit 143, no temporary file left, previous results untouched;
#  3. SIGINT while the plot script runs: exit 130, the child is ended, nothing published;
#  4. a background vrv (SIGINT ignored by the shell) still stops on SIGINT.
# Usage: interrupt_test.sh VRV SOURCE_DIR WORK_DIR
set -u
vrv=$1 src=$2 out=$3
rm -rf "$out" && mkdir -p "$out" || exit 1
fail() { echo "FAIL: $*" >&2; exit 1; }
no_temporaries() { ! find "$1" -name '*.tmp.*' | grep -q . || fail "temporary files left in $1: $(find "$1" -name '*.tmp.*')"; }
study() { "$vrv" study "$@" --quiet --no-plots > /dev/null; }

resume_matches() {  # FILE NAME KILL_AFTER TABLES...
  local file=$1 name=$2 after=$3; shift 3
  study "$file" --quick --out "$out/$name.a" || fail "$name: uninterrupted run"
  study "$file" --quick --out "$out/$name.b" || fail "$name: first run"
  cp -r "$out/$name.b/$name" "$out/$name.previous"
  VRV_TEST_KILL_AFTER_CHECKPOINTS=$after study "$file" --quick --out "$out/$name.b"
  local rc=$?
  [ $rc -eq 137 ] || fail "$name: the killed run exited $rc, not 137"
  diff -r "$out/$name.previous" "$out/$name.b/$name" > /dev/null || fail "$name: SIGKILL changed the previous results"
  [ -d "$out/$name.b/.$name.partial/checkpoints" ] || fail "$name: no checkpoints to resume from"
  "$vrv" study "$file" --quick --quiet --no-plots --resume --out "$out/$name.b" > /dev/null 2> "$out/$name.resume.err" ||
    fail "$name: --resume failed: $(cat "$out/$name.resume.err")"
  for t in "$@"; do
    cmp "$out/$name.a/$name/$t" "$out/$name.b/$name/$t" || fail "$name: $t differs after --resume"
  done
  no_temporaries "$out/$name.b"
  [ ! -e "$out/$name.b/.$name.partial" ] || fail "$name: staging folder left after publishing"
}

resume_matches "$src/studies/hard-cases/hard-cases.toml" hard-cases 5 cases.csv cases.md cases.tex checks.csv checks.md checks.tex
resume_matches "$src/tests/studies/engine/tiny-convergence.toml" tiny-convergence 2 \
  errors.csv orders.csv grid_errors.csv grid_orders.csv checks.csv

# 2. SIGTERM midway.
VRV_TEST_KILL_AFTER_CHECKPOINTS=5:15 study "$src/studies/hard-cases/hard-cases.toml" --quick --out "$out/hard-cases.b"
rc=$?
[ $rc -eq 143 ] || fail "SIGTERM: exit $rc, not 143"
diff -r "$out/hard-cases.a/hard-cases" "$out/hard-cases.b/hard-cases" -x meta.json > /dev/null || fail "SIGTERM changed the results"
no_temporaries "$out/hard-cases.b"

# 3 and 4. SIGINT to a background vrv while its plot script (a stand-in that sleeps) runs.
export VRV_PYTHON="$src/tests/studies/engine/slow_plotter.sh" VRV_TEST_PLOTTER_PID="$out/plotter.pid"
"$vrv" study "$src/tests/studies/engine/tiny-convergence.toml" --quick --quiet --out "$out/plots" > /dev/null 2> "$out/plots.err" &
pid=$!
for _ in $(seq 600); do [ -e "$VRV_TEST_PLOTTER_PID" ] && break; sleep 0.1; done
[ -e "$VRV_TEST_PLOTTER_PID" ] || fail "the plot script never started: $(cat "$out/plots.err")"
kill -INT $pid
wait $pid
rc=$?
[ $rc -eq 130 ] || fail "SIGINT while plotting: exit $rc, not 130"
child=$(cat "$VRV_TEST_PLOTTER_PID")
for _ in $(seq 50); do kill -0 "$child" 2> /dev/null || break; sleep 0.1; done
! kill -0 "$child" 2> /dev/null || fail "the plot script ($child) outlived vrv"
[ ! -e "$out/plots/tiny-convergence" ] || fail "an interrupted run was published"
no_temporaries "$out/plots"
echo "interrupt tests pass"
