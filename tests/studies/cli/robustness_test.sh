#!/usr/bin/env bash
# Issue 22, end to end: hostile inputs to the newer surfaces (--rays, verify, gate, --resume) are
# refused with one line and the documented exit code, never a crash, a hang, a write outside
# --out or a lost result (docs/robustness.md).  Each section is one defect of the issue.
# Usage: robustness_test.sh VRV SOURCE_DIR WORK_DIR
set -u
vrv=$1 src=$2 out=$3
rm -rf "$out" && mkdir -p "$out" || exit 1
source "$(dirname "$0")/robustness_lib.sh"

ray='{"origin": [-3, 0.5, 0], "direction": [1, 0, 0]'

# (1) An id nested 70,000 arrays deep overflowed the stack copying it (SIGSEGV).
python3 -c "import sys; n = 70000; sys.stdout.write('$ray, \"id\": ' + '[' * n + ']' * n + '}\n')" > "$out/deep.jsonl"
expect deep_id 2 "^vrv: error: $out/deep.jsonl:1: nested more than 100 arrays or objects deep$" \
  "$vrv" ray --rays "$out/deep.jsonl"

# (2) --resume trusted a checkpoint's values: one holding only `end` (SIGSEGV), one with 5 of its
# 40 values removed (exit 0, another errors.csv), a sample count of 0x1p+1000 (a float-cast
# overflow, exit 0).  Each is refused now, naming the file (exit 2).
study="$src/studies/convergence/convergence.toml"
{ VRV_TEST_KILL_AFTER_CHECKPOINTS=5 "$vrv" study "$study" --quick --no-plots --quiet --out "$out/ck"; } > /dev/null 2>&1
[ -f "$out/ck/.convergence.partial/checkpoints/ray_0.txt" ] || fail "the killed study stored no ray_0 checkpoint"
# A checkpoint holding NaN (sealed with a valid checksum, as a computation that gave NaN stores it)
# was refused naming a table column, not the file.
reseal_with_nan() {
  python3 - "$1" <<'EOF'
import pathlib, sys
p = pathlib.Path(sys.argv[1])
lines = p.read_text().splitlines(True)
lines[0] = 'nan\n'
body = ''.join(lines[:-1])
def crc64(data):  # CRC-64/ECMA-182, not reflected, as lib/util/checksum.h
    c = 0
    for byte in data:
        c ^= byte << 56
        for _ in range(8):
            c = ((c << 1) ^ (0x42F0E1EBA9EA3693 if c >> 63 else 0)) & (2**64 - 1)
    return c
p.write_text(body + 'end %d %016x\n' % (len(lines) - 1, crc64((p.stem + '\n' + body).encode())))
EOF
}
for damage in only_end five_removed huge_count nan_sealed; do
  cp -r "$out/ck" "$out/ck_$damage"
  ck="$out/ck_$damage/.convergence.partial/checkpoints/ray_0.txt"
  case $damage in
    only_end) echo end > "$ck" ;;
    five_removed) sed -i '1,5d' "$ck" ;;
    huge_count) sed -i '21s/.*/0x1p+1000/' "$ck" ;;
    nan_sealed) reseal_with_nan "$ck" ;;
  esac
  expect "resume_$damage" 2 "^vrv: error: $ck: .*run without --resume$" \
    "$vrv" study "$study" --quick --no-plots --quiet --resume --out "$out/ck_$damage"
  [ ! -d "$out/ck_$damage/convergence" ] || fail "resume_$damage: results were published"
done
grep -q "ray_0.txt: value 1 is nan, reused by --resume" "$out/resume_nan_sealed.err" ||
  fail "resume_nan_sealed: the checkpoint's entry is not named: $(cat "$out/resume_nan_sealed.err")"

# (3) verify --out replaced an input image named like one of its outputs (o/reference.exr); an
# input anywhere inside --out is refused before anything is computed, under any spelling.
mkdir -p "$out/o"
for h in 0.02 0.01; do
  "$vrv" render --method alpha --strategy step --step $h --width 16 --height 16 -o "$out/o/$h.exr" --quiet \
    > /dev/null 2>&1 || fail "render at step $h"
done
mv "$out/o/0.02.exr" "$out/o/reference.exr"
before=$(md5sum < "$out/o/reference.exr")
for dir in "$out/o" "$out/o/../o/"; do
  expect input_in_out 2 "^vrv: error: --out: $dir: holds the input $out/o/reference.exr" \
    "$vrv" verify "$out/o/reference.exr" "$out/o/0.01.exr" --out "$dir" --no-plots --no-cache --quiet
done
[ "$(md5sum < "$out/o/reference.exr")" = "$before" ] || fail "input_in_out: the input image was replaced"
expect input_outside_out 0 "" \
  "$vrv" verify "$out/o/reference.exr" "$out/o/0.01.exr" --out "$out/v" --no-plots --no-cache --quiet

# (4) a gate case's name is its folder under --out: "/abs/dir" wrote into /abs/dir, "../x" beside
# --out.  Refused before anything runs.
mkdir -p "$out/gate"
for name in ../x /abs/dir; do
  printf '[[case]]\nname = "%s"\nrender = { method = "alpha", strategy = "step" }\nsteps = [0.2, 0.1]\nwidth = 8\nheight = 8\n' \
    "$name" > "$out/gate/escape.toml"
  expect case_name 2 "^vrv: error: $out/gate/escape.toml: case\[0\]\.name: '$name' (begins with|is not a plain file name)" \
    "$vrv" gate --bounds "$out/gate/escape.toml" --out "$out/gate/out" --no-plots --no-cache --quiet
  [ ! -e "$out/gate/x" ] && [ ! -e "$out/gate/out" ] || fail "case_name $name: something was written"
done

# (5) study = "--help" ran `vrv study --help` and passed: a study case names a known study.
printf '[[case]]\nname = "h"\nstudy = "--help"\n' > "$out/gate/help.toml"
expect study_name 2 "^vrv: error: $out/gate/help.toml: case\[0\]\.study: '--help' is not a study vrv knows \(convergence, " \
  "$vrv" gate --bounds "$out/gate/help.toml" --out "$out/gate/out" --quiet

# A study case runs under gate's --max-memory: it was not passed on to the study, nor checked
# when every case is a study case.
printf '[[case]]\nname = "v"\nstudy = "volume"\n' > "$out/gate/volume.toml"
expect gate_study_memory 2 "^vrv: error: $out/gate/volume.toml: case v: study volume exited with 2: .*allowed \(--max-memory\)" \
  "$vrv" gate --bounds "$out/gate/volume.toml" --out "$out/gate/vout" --quiet --max-memory 0.000001
expect gate_study_memory_bad 2 "^vrv: error: --max-memory: must be a positive number of GiB, got -1$" \
  "$vrv" gate --bounds "$out/gate/volume.toml" --quiet --max-memory -1

# (6) a write error on standard output was ignored: `vrv ray --rays F > /dev/full` exited 0 with
# every result lost.  Every command flushes and checks it: one line, exit 5.
if [ -w /dev/full ]; then
  printf '%s}\n' "$ray" > "$out/one.jsonl"
  full() {
    local name=$1
    shift
    "$@" > /dev/full 2> "$out/$name.err"
    local rc=$?
    [ $rc -eq 5 ] || fail "$name > /dev/full: exit $rc, expected 5: $(head -c 600 "$out/$name.err")"
    tail -n 1 "$out/$name.err" | grep -Eq "^vrv: error: standard output: (a write failed|No space left on device); the results printed are incomplete$" ||
      fail "$name > /dev/full: $(cat "$out/$name.err")"
  }
  full full_rays "$vrv" ray --rays "$out/one.jsonl"
  full full_ray "$vrv" ray --origin -3,0.5,0 --direction 1,0,0 --json
  full full_demo "$vrv" demo
  full full_list "$vrv" study --list
  full full_help "$vrv" --help
  full full_verify "$vrv" verify "$out/o/reference.exr" "$out/o/0.01.exr" --no-plots --no-cache --quiet
  full full_export "$vrv" export --out "$out/export" --resolution 4,4,4
else
  echo "robustness: /dev/full is not writable here; the standard output cases are skipped"
fi

# (14) a character device as an image hung verify; `ray --rays /dev/zero` read one endless line.
expect zero_rays 2 "^vrv: error: /dev/zero:1: longer than 1048576 bytes \(1 MiB\), the longest line read$" \
  "$vrv" ray --rays /dev/zero
expect zero_image 2 "^vrv: error: /dev/zero: is a character device, not an image file$" \
  "$vrv" verify "$out/o/reference.exr" /dev/zero --no-cache --quiet
expect zero_image_steps 2 "^vrv: error: /dev/zero: is a character device, not an image file$" \
  "$vrv" verify /dev/zero "$out/o/0.01.exr" --steps 0.02,0.01 --no-cache --quiet
mkfifo "$out/fifo.exr"
expect fifo_image 2 "^vrv: error: $out/fifo.exr: is a FIFO, not an image file$" \
  "$vrv" verify "$out/o/reference.exr" "$out/fifo.exr" --steps 0.02,0.01 --no-cache --quiet

# A repeated key in a --rays line silently took the second value.
printf '%s, "origin": [-3, 0, 0]}\n' "$ray" > "$out/dup.jsonl"
expect duplicate_key 2 "^vrv: error: $out/dup.jsonl:1: key 'origin' given twice$" "$vrv" ray --rays "$out/dup.jsonl"

# 10 M rays above --max-work were refused only after 219 s and 1.2 GB of parsing, and told to
# "make the image smaller".  A file is counted (unparsed) before it is read: refused before the
# malformed last line is reached, naming the file, its estimate and a rays file's remedy.
line='{"origin":[-3,0.5,0],"direction":[1,0,0]}'
{ yes "$line" | head -n 10000000; echo '{"origin": oops'; } > "$out/many.jsonl"
expect many_rays 2 "^vrv: error: --rays $out/many.jsonl: about 1(\.0[0-9]*)?e\+07 rays .*, above the work limit of 1e\+09; split the file or allow it with --max-work [0-9.]+e\+[0-9]+$" \
  "$vrv" ray --rays "$out/many.jsonl" --quiet
rm -f "$out/many.jsonl"
# ... and a file within the limit is still read whole: its malformed last line is reported.
{ yes "$line" | head -n 1000; echo '{"origin": oops'; } > "$out/few.jsonl"
expect few_rays_bad_end 2 "^vrv: error: $out/few.jsonl:1001: " "$vrv" ray --rays "$out/few.jsonl" --quiet
# ... and standard input (read whole: it cannot be counted first) gets a rays file's remedy too.
expect stdin_rays_over 2 "^vrv: error: --rays <stdin>: about 1e\+03 rays.*split the file or allow it with --max-work" \
  "$vrv" ray --rays - --quiet --max-work 1e3 < <(head -n 1000 "$out/few.jsonl")

# gate's and verify's errors began "vrv gate:" / "vrv verify:" where every other command says
# "vrv: error:".
expect gate_prefix 2 "^vrv: error: $out/none.toml: \(file\): no such bounds file$" "$vrv" gate --bounds "$out/none.toml"
expect verify_prefix 2 "^vrv: error: $out/none.toml: \(file\): no such bounds file$" \
  "$vrv" verify "$out/o/reference.exr" "$out/o/0.01.exr" --bounds "$out/none.toml" --no-cache --quiet
# A bounds "file" that exists but is no file (a device, a directory) was called missing.
expect gate_bounds_device 2 "^vrv: error: /dev/zero: \(file\): not a regular file \(a bounds file is TOML text\)$" \
  "$vrv" gate --bounds /dev/zero
# An option given twice: CLI11's "At Most 1 required but received 2" said in our words.
expect repeated_option 2 "^vrv: error: --origin: given more than once \(give it once\)$" \
  "$vrv" ray --origin 1,2,3 --origin 1,2,3 --direction 1,0,0

# gate without --out left /tmp/vrv-gate-PID behind: it is removed on every way out (a pass, and an
# error after the folder was made: images that cannot be read).
mkdir -p "$out/tmp"
printf '[[case]]\nname = "c"\nrender = { method = "alpha", strategy = "step" }\nsteps = [0.2, 0.1]\nwidth = 8\nheight = 8\n' \
  > "$out/gate/pass.toml"
printf '[[case]]\nname = "c"\nimages = ["no1.exr", "no2.exr"]\nsteps = [0.2, 0.1]\n' > "$out/gate/noimages.toml"
TMPDIR="$out/tmp" expect gate_temporary 0 "" "$vrv" gate --bounds "$out/gate/pass.toml" --no-plots --no-cache --quiet
grep -q '"out":null' "$out/gate_temporary.out" || fail "gate_temporary: $(cat "$out/gate_temporary.out")"
TMPDIR="$out/tmp" expect gate_temporary_error 2 "no1.exr" "$vrv" gate --bounds "$out/gate/noimages.toml" --no-plots --no-cache --quiet
[ -z "$(ls -A "$out/tmp")" ] || fail "gate without --out left $(ls "$out/tmp")"

# An unwritable --cache-dir or --out was found only after the whole reference was computed (and an
# unwritable default cache failed the run): both are checked first; the default cache is optional.
touch "$out/afile"
expect cache_unwritable 2 "^vrv: error: --cache-dir: $out/afile/cache: cannot create the folder: Not a directory$" \
  "$vrv" verify "$out/o/reference.exr" "$out/o/0.01.exr" --cache-dir "$out/afile/cache" --no-plots --quiet
expect out_unwritable 2 "^vrv: error: --out: $out/afile/out: cannot create the folder: Not a directory$" \
  "$vrv" verify "$out/o/reference.exr" "$out/o/0.01.exr" --out "$out/afile/out" --no-cache --no-plots --quiet
expect gate_out_unwritable 2 "^vrv: error: --out: $out/afile/out: cannot create the folder: Not a directory$" \
  "$vrv" gate --bounds "$out/gate/pass.toml" --out "$out/afile/out" --no-plots --no-cache --quiet
HOME="$out/afile" XDG_CACHE_HOME= expect default_cache_unwritable 0 \
  "^vrv: the default reference cache: $out/afile/.cache/vrv: cannot create the folder: Not a directory; running without a cache$" \
  "$vrv" verify "$out/o/reference.exr" "$out/o/0.01.exr" --no-plots --quiet

# (10) verify had no work limit (two 8192^2 images started 67 M reference rays); (11) nor had gate's
# render cases (4096^2 at step 1e-6 started at once).  Both are estimated first, as ray and render.
expect verify_work 2 "^vrv: error: --max-work: about .* field evaluations \(the reference on 16 x 16 pixels at --tol 1e-10: .*\), above the work limit of 1e\+03; .* allow it with --max-work " \
  "$vrv" verify "$out/o/reference.exr" "$out/o/0.01.exr" --max-work 1000 --no-cache --no-plots --quiet
printf '[[case]]\nname = "big"\nrender = { method = "alpha", strategy = "step" }\nsteps = [2e-6, 1e-6]\nwidth = 4096\nheight = 4096\n' \
  > "$out/gate/big.toml"
expect gate_work 2 "^vrv: error: $out/gate/big.toml: case\[0\]: about .* field evaluations \(the reference on 4096 x 4096 pixels .*; the renders: .*\), above the work limit of 1e\+09" \
  "$vrv" gate --bounds "$out/gate/big.toml" --out "$out/gate/big" --no-cache --quiet
[ ! -e "$out/gate/big" ] || fail "gate_work: wrote $out/gate/big"

# (8), (9), (13): outputs published whole, a lock on an output folder, memory limits.
bash "$src/tests/studies/cli/robustness_outputs_test.sh" "$vrv" "$src" "$out/outputs" || fail "robustness_outputs_test.sh"

echo "robustness: all passed"
