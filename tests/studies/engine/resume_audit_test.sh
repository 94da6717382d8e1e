#!/usr/bin/env bash
# A study's reference audit survives --resume (studies/engine/reference_audit.h): the truths of
# tight-reference.toml all miss their tolerance, and all of them are computed in its first five
# checkpoints.
#  - killed after those five, `--resume` computes no truth: it must still fail
#    reference_within_tolerance (exit 1) with the checks.csv of an uninterrupted run, byte for byte
#    (no truth was in flight at the kill, so the counts are exact here);
#  - killed after two (truths in flight may be counted twice): it fails the same check, with at
#    least the uninterrupted run's count;
#  - checkpoints without the audit's snapshot (an older vrv's) are refused (exit 2, one line).
# Usage: resume_audit_test.sh VRV STUDY_FILE WORK_DIR
set -u
vrv=$1 file=$2 out=$3
name=tight-reference
rm -rf "$out" && mkdir -p "$out" || exit 1
fail() { echo "FAIL: $*" >&2; exit 1; }
study() { "$vrv" study "$file" --quick --no-plots --quiet "$@" > /dev/null 2>> "$out/stderr.txt"; }
# The reference_within_tolerance row of a checks.csv.
audit_row() { grep '^reference_within_tolerance,' "$1/$name/checks.csv"; }
missed() { audit_row "$1" | cut -d, -f2; }

study --out "$out/a"
rc=$?
[ $rc -eq 1 ] || fail "the uninterrupted run exited $rc, not 1"
audit_row "$out/a" | grep -q ',false,' || fail "the uninterrupted run passed reference_within_tolerance"
m=$(missed "$out/a")
[ "$m" -ge 1 ] || fail "the uninterrupted run counted $m misses"

for after in 5 2; do
  b="$out/b$after"
  VRV_TEST_KILL_AFTER_CHECKPOINTS=$after study --out "$b"
  rc=$?
  [ $rc -eq 137 ] || fail "killed after $after: exited $rc, not 137"
  "$vrv" study "$file" --quick --no-plots --resume --out "$b" > /dev/null 2> "$out/resume$after.err"
  rc=$?
  [ $rc -eq 1 ] || fail "killed after $after, --resume exited $rc, not 1: $(cat "$out/resume$after.err")"
  grep -q "FAILED: .*reference_within_tolerance" "$out/resume$after.err" ||
    fail "killed after $after, --resume did not name reference_within_tolerance: $(cat "$out/resume$after.err")"
  audit_row "$b" | grep -q ',false,' || fail "killed after $after, --resume passed reference_within_tolerance"
  [ "$(missed "$b")" -ge "$m" ] || fail "killed after $after, --resume counted $(missed "$b") misses, fewer than $m"
done
cmp -s "$out/a/$name/checks.csv" "$out/b5/$name/checks.csv" ||
  fail "killed after 5, --resume: checks.csv differs: $(diff "$out/a/$name/checks.csv" "$out/b5/$name/checks.csv")"

# Checkpoints without a snapshot: refused before anything is computed, the staging folder kept.
c="$out/c"
VRV_TEST_KILL_AFTER_CHECKPOINTS=3 study --out "$c"
rm -f "$c/.$name.partial/checkpoints/reference_audit.snapshot"
"$vrv" study "$file" --quick --no-plots --resume --out "$c" > /dev/null 2> "$out/refused.err"
rc=$?
[ $rc -eq 2 ] || fail "resuming checkpoints without a snapshot exited $rc, not 2"
[ "$(wc -l < "$out/refused.err")" -eq 1 ] && grep -q "reference audit snapshot" "$out/refused.err" ||
  fail "resuming checkpoints without a snapshot: not one line naming the snapshot: $(cat "$out/refused.err")"
echo "$name: --resume after 5 and after 2 checkpoints fails reference_within_tolerance as the uninterrupted run does ($m missed)"
