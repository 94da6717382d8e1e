#!/usr/bin/env bash
# vrv verify spread over MPI ranks (docs/distributed.md): the same outputs as one process for 2 and
# 3 ranks (every file of --out, --report's page, stdout's JSON; apart from meta.json's date and
# wall time and the output names), with the reference computed (--no-cache) and from a cache that
# rank 0 alone wrote.  Label `mpi`: needs a build with -DVRV_WITH_MPI=ON and mpirun.
# Usage: mpi_verify_test.sh VRV SOURCE_DIR WORK_DIR [MPIRUN]
set -u
vrv=$1 src=$2 out=$3 mpirun=${4:-mpirun}
rm -rf "$out" && mkdir -p "$out" && cd "$out" || exit 1
source "$src/tests/studies/cli/robustness_lib.sh"
source "$src/tests/studies/cli/mpi_lib.sh"
scene=$src/studies/benchmarks/grid64_opacity.toml
trapezoid_images "$scene" 48 40

# run NAME NP CACHE_OPTION...: vrv verify into NAME/ and NAME.html, stdout to NAME.json.
run() {
  local name=$1 np=$2
  shift 2
  on "$np" "$vrv" verify --scene "$scene" "${images[@]}" --out "$name" --report "$name.html" --quiet "$@" \
    > "$name.json" 2> "$name.err" || fail "$name: exit $?: $(head -c 600 "$name.err")"
}
# same A B: B's outputs are A's.
same() {
  python3 - "$1" "$2" <<'PY' || fail "$2 differs from $1"
import json, pathlib, sys
a, b = sys.argv[1:]
def stdout(n):
    j = json.loads(pathlib.Path(n + ".json").read_text())
    assert j.pop("out") == n and j.pop("report") == n + ".html"
    return j
def meta(n):
    m = json.loads(pathlib.Path(n, "meta.json").read_text())
    m.pop("date"); m.pop("wall_seconds")
    return m
if stdout(a) != stdout(b): sys.exit(f"stdout: {b} differs from {a}")
if meta(a) != meta(b): sys.exit(f"meta.json: {b} differs from {a}")
fa = sorted(p.relative_to(a) for p in pathlib.Path(a).rglob("*") if p.is_file())
fb = sorted(p.relative_to(b) for p in pathlib.Path(b).rglob("*") if p.is_file())
if fa != fb: sys.exit(f"files: {fb} against {fa}")
for f in fa:
    if f.name != "meta.json" and (pathlib.Path(a) / f).read_bytes() != (pathlib.Path(b) / f).read_bytes():
        sys.exit(f"{b}/{f} differs from {a}/{f}")
ha = pathlib.Path(a + ".html").read_text().replace(f"--out {a} --report {a}.html", "OUT")
hb = pathlib.Path(b + ".html").read_text().replace(f"--out {b} --report {b}.html", "OUT")
if ha != hb: sys.exit(f"{b}.html differs from {a}.html")
PY
}

# The reference computed on every run, its pixels dealt to the ranks (each rank says how many
# blocks it computed: at least two ranks some).
run computed_1 1 --no-cache
export VRV_RANK_SHARES=1
for np in 2 3; do
  run "computed_$np" $np --no-cache
  same computed_1 "computed_$np"
  work_was_dealt $np "computed_$np.err"
done
# The diagnosis's model casts are dealt too (lib/util/task_rows.h): two more dealt loops (the
# ranking and the leaders' casts) than a verify without the diagnosis.
VRV_RANK_SHARES=1 on 2 "$vrv" verify --scene "$scene" "${images[@]}" --no-cache --no-diagnosis --quiet \
  > /dev/null 2> no_diagnosis.err || fail "no diagnosis: $(head -c 600 no_diagnosis.err)"
[ "$(grep -c '^vrv: rank' computed_2.err)" -ge $(($(grep -c '^vrv: rank' no_diagnosis.err) + 4)) ] \
  || fail "the diagnosis was not dealt: $(cat computed_2.err) against $(cat no_diagnosis.err)"
unset VRV_RANK_SHARES

# An X-ray projection's images: its reference and its own model catalogue (dealt as above).
ea_images=("${images[@]}")
images=()
for h in 0.04 0.02 0.01; do
  "$vrv" render --scene "$scene" --mode xray --method trapezoid --step $h --width 40 --height 32 --quiet \
    -o "x$h.exr" > /dev/null 2>&1 || fail "xray render at step $h"
  images+=("x$h.exr")
done
run xray_1 1 --no-cache --mode xray
run xray_2 2 --no-cache --mode xray
same xray_1 xray_2
images=("${ea_images[@]}")

# A cache: 2 ranks compute and rank 0 writes one entry; then 2 ranks and one process read it.
run cache_first_2 2 --cache-dir cache
[ "$(find cache -name 'reference-*.bin' | wc -l)" -eq 1 ] || fail "cache: not one entry: $(ls -a cache)"
[ -z "$(find cache -name '*.tmp*')" ] || fail "cache: a temporary file was left: $(ls -a cache)"
grep -q '"from_cache":false' cache_first_2.json || fail "cache: the first run did not compute"
run cache_2 2 --cache-dir cache
run cache_1 1 --cache-dir cache
grep -q '"from_cache":true' cache_2.json || fail "cache: 2 ranks did not read the entry"
same cache_1 cache_2

# A failed check (exit 1: the trapezoid images do not converge at order 4) is an outcome every rank
# reaches: the same JSON line and exit code as one process, not an abort.
for np in 1 2; do
  on $np "$vrv" verify --scene "$scene" "${images[@]}" --no-cache --expected-order 4 --quiet \
    > "order_$np.json" 2> "order_$np.err"
  rc=$?
  [ $rc -eq 1 ] || fail "expected order: $np ranks: exit $rc, expected 1: $(head -c 600 "order_$np.err")"
done
cmp -s order_1.json order_2.json || fail "expected order: the JSON line of 2 ranks differs: $(cat order_2.json)"
grep -q "MPI_ABORT" order_2.err && fail "expected order: the ranks were aborted: $(cat order_2.err)"

echo "mpi verify: the same outputs for 1, 2 and 3 ranks, computed and cached"
