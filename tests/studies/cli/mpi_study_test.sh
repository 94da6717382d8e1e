#!/usr/bin/env bash
# vrv study spread over MPI ranks (docs/distributed.md): studies run as one process and over 2 and
# 3 ranks write the same files (every table, image and check; meta.json apart from its date, wall
# time and rate) and the same stdout JSON line; the ranks share the work; the reference audit
# counts every truth once; the other ranks leave no temporary folder; --resume under several ranks
# and a bad study file are refused with one line, exit 2 and nothing written.
# Label `mpi`: needs a build with -DVRV_WITH_MPI=ON and mpirun.
# Usage: mpi_study_test.sh VRV SOURCE_DIR WORK_DIR [MPIRUN]
set -u
vrv=$1 src=$2 out=$3 mpirun=${4:-mpirun}
rm -rf "$out" && mkdir -p "$out/tmp" && cd "$out" || exit 1
source "$src/tests/studies/cli/robustness_lib.sh"
source "$src/tests/studies/cli/mpi_lib.sh"
export TMPDIR=$out/tmp

# error-prediction: per-ray tasks (task_rows, task_values); segment-rules: checkpointed items and
# image records; hard-cases: loops every rank runs whole, whose truths the audit counts once.
studies="error-prediction segment-rules hard-cases"
export VRV_RANK_SHARES=1
for np in 1 2 3; do
  for s in $studies; do
    on $np "$vrv" study "$s" --quick --no-plots --quiet --out "s_$np" > "$s.$np.json" 2> "$s.$np.err" \
      || fail "study $s: $np ranks: exit $?: $(head -c 600 "$s.$np.err")"
  done
  if [ $np -gt 1 ]; then
    work_was_dealt $np "error-prediction.$np.err"
    work_was_dealt $np "segment-rules.$np.err"
  fi
done
unset VRV_RANK_SHARES
[ -z "$(ls tmp)" ] || fail "the ranks left temporary folders: $(ls tmp)"
STUDIES="$studies" python3 - <<'PY' || fail "the outputs of several ranks differ from one process's"
import json, os, pathlib, sys
studies = os.environ["STUDIES"].split()
def stdout(s, n):
    j = json.loads(pathlib.Path(f"{s}.{n}.json").read_text())
    assert j.pop("out") == f"s_{n}/{s}", j
    return j
def files(n):
    return sorted(p.relative_to(f"s_{n}") for p in pathlib.Path(f"s_{n}").rglob("*") if p.is_file())
def content(n, f):
    p = pathlib.Path(f"s_{n}", f)
    if f.name == "meta.json":
        m = json.loads(p.read_text())
        m.pop("date"); m.pop("wall_seconds"); m["work_estimate"].pop("per_second")
        return m
    return p.read_bytes()
for n in (2, 3):
    for s in studies:
        if stdout(s, n) != stdout(s, 1): sys.exit(f"{s}.{n}.json: {stdout(s, n)} against {stdout(s, 1)}")
    if files(n) != files(1): sys.exit(f"s_{n}: files {files(n)} against {files(1)}")
    for f in files(1):
        if content(n, f) != content(1, f): sys.exit(f"s_{n}/{f} differs")
for s in studies:
    audit = json.loads(pathlib.Path(f"s_1/{s}/meta.json").read_text())["parameters"]["run"]["reference_audit"]
    if audit["truths_computed"] <= 0: sys.exit(f"{s}: the audit counted no truth: {audit}")
if len(files(1)) < 30: sys.exit(f"s_1 holds only {files(1)}")
PY

# --resume keeps checkpoints, which several ranks do not: refused before anything is written.
mpi 2 "$vrv" study hard-cases --quick --resume --out resumed > /dev/null 2> resume.err
rc=$?
[ $rc -eq 2 ] || fail "--resume: exit $rc, expected 2: $(cat resume.err)"
grep -q "^vrv: error: --resume: 2 MPI ranks keep no checkpoints" resume.err || fail "--resume: $(cat resume.err)"
[ ! -e resumed ] || fail "--resume: the output folder was written"

# A bad study file: rank 0's one line, exit 2, nothing written.
printf 'kind = "hard_cases"\nname = "bad"\nunknown = 1\n' > bad.toml
mpi 2 "$vrv" study bad.toml --out bad_out > /dev/null 2> bad.err
rc=$?
[ $rc -eq 2 ] || fail "bad study file: exit $rc, expected 2: $(cat bad.err)"
[ "$(grep -c '^vrv: error: bad.toml' bad.err)" -eq 1 ] || fail "bad study file: $(cat bad.err)"
[ ! -e bad_out ] || fail "bad study file: the output folder was written"
echo "mpi study: the same outputs for 1, 2 and 3 ranks; --resume and a bad file refused"
