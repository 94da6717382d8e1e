#!/usr/bin/env bash
# The reference cache shared by runs at once (issue 28; docs/verify.md "Reference cache"): runs that
# compute the same reference together each write it whole, leave one entry and no temporary file,
# and report the same results; a damaged entry is noticed by every run reading it, recomputed and
# replaced; runs on different machines (here: separate pid and host-name namespaces, both pid 1)
# never share a temporary name.
# Usage: cache_concurrency_test.sh VRV SOURCE_DIR WORK_DIR
set -u
vrv=$1 src=$2 out=$3
rm -rf "$out" && mkdir -p "$out" && cd "$out" || exit 1
source "$src/tests/studies/cli/robustness_lib.sh"
scene=$src/studies/benchmarks/grid64_opacity.toml
trapezoid_images "$scene" 40 32
verify=("$vrv" verify --scene "$scene" "${images[@]}" --cache-dir cache --no-diagnosis --quiet)

# together NAME N [PREFIX...]: N runs of verify started at once (each behind PREFIX), all waited for.
together() {
  local name=$1 n=$2 pids=() i
  shift 2
  for ((i = 0; i < n; ++i)); do
    timeout 300 "$@" "${verify[@]}" > "$name.$i.json" 2> "$name.$i.err" &
    pids+=($!)
  done
  for ((i = 0; i < n; ++i)); do wait "${pids[$i]}" || fail "$name.$i: exit $?: $(head -c 600 "$name.$i.err")"; done
}
# results NAME N: every run's JSON line is the first's (apart from where the reference came from).
results() {
  python3 - "$@" <<'PY' || fail "$1: the runs' results differ"
import json, sys
name, n = sys.argv[1], int(sys.argv[2])
def load(i):
    j = json.loads(open(f"{name}.{i}.json").read())
    j["reference"].pop("from_cache"); j["reference"].pop("cache_file", None)
    return j
if any(load(i) != load(0) for i in range(n)): sys.exit(1)
PY
}
one_entry() {
  [ "$(find cache -name 'reference-*.bin' | wc -l)" -eq 1 ] || fail "$1: not one cache entry: $(ls -a cache)"
  [ -z "$(find cache -name '*.tmp*')" ] || fail "$1: a temporary file was left: $(ls -a cache)"
}

# Four runs compute the same reference at once: each writes it, none says a word (a sanitizer's own
# notes aside).
together computed 4
results computed 4
one_entry computed
! grep -q "^vrv" computed.*.err || fail "computed: a run complained: $(cat computed.*.err)"

# The entry damaged (one byte of its values): three runs at once; those that meet it say so,
# recompute and replace it; a run after them reads the new entry.
entry=$(find cache -name 'reference-*.bin')
python3 - "$entry" <<'PY'
import sys
b = bytearray(open(sys.argv[1], "rb").read()); b[len(b) // 2] ^= 0x40
open(sys.argv[1], "wb").write(b)
PY
together damaged 3
results damaged 3
one_entry damaged
# Each run either met the damage (said, recomputed) or read the entry another had already replaced.
noticed=0
for i in 0 1 2; do
  if grep -q "fails its checksum (changed or damaged); recomputing it" damaged.$i.err; then
    noticed=$((noticed + 1))
  else
    grep -q '"from_cache":true' damaged.$i.json || fail "damaged.$i: neither noticed nor read a whole entry: $(cat damaged.$i.err)"
  fi
done
[ $noticed -ge 1 ] || fail "damaged: no run noticed the damage"
"${verify[@]}" > after.json 2> after.err || fail "after: $(cat after.err)"
grep -q '"from_cache":true' after.json || fail "after: the replaced entry was not read: $(cat after.json after.err)"

# Two "machines" with the same pid: each run in its own pid and host-name namespaces is pid 1.
if unshare --fork --pid --uts true 2> /dev/null; then
  rm -rf cache
  together machines 2 unshare --fork --pid --uts
  results machines 2
  one_entry machines
  ! grep -q "^vrv" machines.*.err || fail "machines: a run complained: $(cat machines.*.err)"
  echo "cache concurrency: concurrent, damaged and same-pid runs each leave one whole entry"
else
  echo "cache concurrency: concurrent and damaged runs each leave one whole entry (unshare not permitted here: the same-pid case was not run)"
fi
