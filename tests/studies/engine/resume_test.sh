#!/usr/bin/env bash
# One study killed midway and resumed (docs/robustness.md, "Interrupted studies resume"):
#  - a SIGKILL after N computed checkpoints (VRV_TEST_KILL_AFTER_CHECKPOINTS, a deterministic
#    "midway") exits 137 and leaves the previous results untouched;
#  - `--resume` reuses the killed run's checkpoints (it says how many) and publishes every file an
#    uninterrupted run publishes, byte for byte (tables and images; meta.json aside), apart from
#    timing columns named on the command line;
#  - no temporary file and no staging folder is left.
# Usage: resume_test.sh VRV STUDY_FILE NAME KILL_AFTER WORK_DIR [EXCEPTION...]
#   EXCEPTION: FILE:COLUMN[,COLUMN...]  compare the CSV FILE without those (timing) columns;
#              FILE                     FILE holds timings throughout (a Markdown or LaTeX copy
#                                       of a CSV compared above): present in both, not compared.
set -u
vrv=$1 file=$2 name=$3 after=$4 out=$5
shift 5
rm -rf "$out" && mkdir -p "$out" || exit 1
fail() { echo "FAIL: $name: $*" >&2; exit 1; }
study() { "$vrv" study "$file" --quick --no-plots "$@" > /dev/null; }

study --quiet --out "$out/a" || fail "uninterrupted run"
study --quiet --out "$out/b" || fail "first run"
cp -r "$out/b/$name" "$out/previous"
VRV_TEST_KILL_AFTER_CHECKPOINTS=$after study --quiet --out "$out/b"
rc=$?
[ $rc -eq 137 ] || fail "the killed run exited $rc, not 137 (fewer than $after checkpoints?)"
diff -r "$out/previous" "$out/b/$name" > /dev/null || fail "SIGKILL changed the previous results"
[ -d "$out/b/.$name.partial/checkpoints" ] || fail "no checkpoints to resume from"
study --resume --out "$out/b" 2> "$out/resume.err" || fail "--resume failed: $(cat "$out/resume.err")"
grep -Eq "resumed: [1-9][0-9]* configurations" "$out/resume.err" ||
  fail "--resume reused no checkpoint: $(cat "$out/resume.err")"

declare -A columns
for e in "$@"; do
  if [[ $e == *:* ]]; then columns[${e%%:*}]=${e#*:}; else columns[$e]=-; fi
done
# CSV without the named columns (python3's csv: quoted fields may hold commas).
without() {
  python3 -c 'import csv, sys
drop = set(sys.argv[2].split(","))
rows = list(csv.reader(open(sys.argv[1], newline="")))
keep = [i for i, c in enumerate(rows[0]) if c not in drop]
missing = drop - set(rows[0])
if missing: sys.exit("no column " + ", ".join(sorted(missing)) + " in " + sys.argv[1])
csv.writer(sys.stdout, lineterminator="\n").writerows([[r[i] for i in keep] for r in rows])' "$1" "$2"
}
a="$out/a/$name" b="$out/b/$name"
diff <(cd "$a" && find . -type f ! -name meta.json | sort) <(cd "$b" && find . -type f ! -name meta.json | sort) ||
  fail "the resumed run published other files"
compared=0
while IFS= read -r f; do
  f=${f#./}
  spec=${columns[$f]:-}
  if [ -z "$spec" ]; then
    cmp -s "$a/$f" "$b/$f" || fail "$f differs after --resume"
  elif [ "$spec" != - ]; then
    diff <(without "$a/$f" "$spec") <(without "$b/$f" "$spec") > "$out/diff.txt" ||
      fail "$f differs after --resume (apart from $spec): $(head -c 2000 "$out/diff.txt")"
  fi
  compared=$((compared + 1))
done < <(cd "$a" && find . -type f ! -name meta.json | sort)
[ $compared -gt 0 ] || fail "nothing published"
! find "$out/b" -name '*.tmp.*' | grep -q . || fail "temporary files left: $(find "$out/b" -name '*.tmp.*')"
[ ! -e "$out/b/.$name.partial" ] || fail "staging folder left after publishing"
echo "$name: resumed after $after checkpoints; $compared files match"
