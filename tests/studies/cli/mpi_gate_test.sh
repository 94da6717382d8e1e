#!/usr/bin/env bash
# vrv gate spread over MPI ranks (docs/distributed.md): a render case (vrv's trapezoid cast at
# three steps) and an images case (vrv's trapezoid images at 40 x 32, read back), gated as one
# process and over 2 and 3 ranks, write the same files (OUT/bounds.*, each case's folder; meta.json
# apart from its date and wall time) and the same stdout JSON; the ranks share the
# pixels; without --out no temporary folder is left; a study case under several ranks is refused
# with one line, exit 2 and nothing written.
# Label `mpi`: needs a build with -DVRV_WITH_MPI=ON and mpirun.
# Usage: mpi_gate_test.sh VRV SOURCE_DIR WORK_DIR [MPIRUN]
set -u
vrv=$1 src=$2 out=$3 mpirun=${4:-mpirun}
rm -rf "$out" && mkdir -p "$out/tmp" && cd "$out" || exit 1
source "$src/tests/studies/cli/robustness_lib.sh"
source "$src/tests/studies/cli/mpi_lib.sh"
export TMPDIR=$out/tmp
scene=$src/studies/benchmarks/grid64_opacity.toml
trapezoid_images "$scene" 40 32
cat > bounds.toml <<TOML
[defaults]
threshold = 1e-3
max_nan = { fail = 0 }

[[case]]
name = "trapezoid"
scene = "$scene"
steps = [0.04, 0.02, 0.01]
width = 48
height = 40
expected_order = 2
render = { method = "trapezoid" }
rms = { warn = 1e-3, fail = 1e-2 }

[[case]]
name = "trapezoid-images"
scene = "$scene"
images = ["t0.04.exr", "t0.02.exr", "t0.01.exr"]
expected_order = 2
steps = [0.04, 0.02, 0.01]
rms = { warn = 1e-2, fail = 1e-1 }
TOML

export VRV_RANK_SHARES=1
for np in 1 2 3; do
  on $np "$vrv" gate --bounds bounds.toml --out "gate_$np" --no-cache --report > "gate_$np.json" 2> "gate_$np.err" \
    || fail "gate: $np ranks: exit $?: $(head -c 600 "gate_$np.err")"
  [ $np -eq 1 ] || work_was_dealt $np "gate_$np.err"
done
unset VRV_RANK_SHARES
python3 - <<'PY' || fail "the outputs of several ranks differ from one process's"
import json, pathlib, sys
def stdout(n):
    j = json.loads(pathlib.Path(n + ".json").read_text())
    assert j.pop("out") == n, j
    return j
def files(n):
    return sorted(p.relative_to(n) for p in pathlib.Path(n).rglob("*") if p.is_file())
def content(n, f):
    p = pathlib.Path(n, f)
    if f.name == "meta.json":
        m = json.loads(p.read_text())
        m.pop("date"); m.pop("wall_seconds")
        return m
    if f.name == "report.html":
        return p.read_text().replace(f"--out {n}", "--out OUT")
    return p.read_bytes()
for n in ("gate_2", "gate_3"):
    if stdout(n) != stdout("gate_1"): sys.exit(f"{n}.json: {stdout(n)} against {stdout('gate_1')}")
    if files(n) != files("gate_1"): sys.exit(f"{n}: files {files(n)} against {files('gate_1')}")
    for f in files("gate_1"):
        if content(n, f) != content("gate_1", f): sys.exit(f"{n}/{f} differs")
if len(files("gate_1")) < 10: sys.exit(f"gate_1 wrote only {files('gate_1')}")
PY
grep -q '"pass":true' gate_1.json || fail "gate: the cases did not pass: $(cat gate_1.json)"

# Without --out: rank 0's temporary folder is removed and no other rank made one.
mpi 2 "$vrv" gate --bounds bounds.toml --case trapezoid --no-cache --quiet > bare.json 2> bare.err \
  || fail "gate without --out: exit $?: $(head -c 600 bare.err)"
[ -z "$(ls tmp)" ] || fail "gate without --out: left $(ls tmp)"

# A study case runs vrv study as a child, outside the MPI run: one line naming the case, exit 2,
# nothing written.
cat > study.toml <<'TOML'
[[case]]
name = "hard"
study = "hard-cases"
TOML
mpi 2 "$vrv" gate --bounds study.toml --out study_out > /dev/null 2> study.err
rc=$?
[ $rc -eq 2 ] || fail "study case: exit $rc, expected 2: $(cat study.err)"
grep -q "^vrv: error: study.toml: case hard: a study case runs vrv study as a child process" study.err \
  || fail "study case: $(cat study.err)"
[ ! -e study_out ] || fail "study case: --out was written"
echo "mpi gate: the same outputs for 1, 2 and 3 ranks; a study case refused"
