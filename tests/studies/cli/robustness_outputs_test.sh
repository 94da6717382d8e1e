#!/usr/bin/env bash
# Issue 22, the output discipline and memory limits (items 8, 9, 13): `vrv verify --out` and
# `vrv export --out` are published whole (staged beside the folder, exchanged in one step, a lock
# on the folder), so an interruption, a full disk or a second run never leaves a mix of two runs;
# an export too large for memory is refused before anything is allocated (docs/robustness.md).
# Run by robustness_test.sh.  Usage: robustness_outputs_test.sh VRV SOURCE_DIR WORK_DIR
set -u
vrv=$1 src=$2 out=$3
rm -rf "$out" && mkdir -p "$out" || exit 1
source "$(dirname "$0")/robustness_lib.sh"

# A folder's files and their contents, to compare a folder before and after.
fingerprint() { (cd "$1" && find . -type f | sort | xargs md5sum); }
no_temporaries() {
  local left
  left=$(find "$out" -name '*.tmp.*' || true)
  [ -z "$left" ] || fail "$1: left $left"
}

for h in 0.02 0.01; do
  "$vrv" render --method alpha --strategy step --step $h --width 16 --height 16 -o "$out/$h.exr" --quiet \
    > /dev/null 2>&1 || fail "render at step $h"
done
images=("$out/0.02.exr" "$out/0.01.exr")
verify=("$vrv" verify "${images[@]}" --no-plots --no-cache --quiet)
printf '[defaults]\nrms = { warn = 1, fail = 2 }\n' > "$out/b.toml"

# (8) A later run left the earlier run's bounds.csv (and error images) beside its own outputs.
expect first_run 0 "" "${verify[@]}" --bounds "$out/b.toml" --out "$out/v"
[ -f "$out/v/bounds.csv" ] || fail "first_run: no bounds.csv"
expect second_run 0 "" "${verify[@]}" --out "$out/v"
[ ! -e "$out/v/bounds.csv" ] || fail "second_run: the earlier run's bounds.csv is still in --out"
[ -f "$out/v/errors.csv" ] && [ -f "$out/v/meta.json" ] || fail "second_run: outputs missing"
no_temporaries second_run

# A run replaces the whole folder, so a folder vrv did not write is refused, its files untouched.
mkdir -p "$out/mine" && echo "my notes" > "$out/mine/notes.txt"
expect not_vrvs 2 "^vrv: error: --out: $out/mine: holds files vrv did not write \(no meta.json\)" "${verify[@]}" --out "$out/mine"
[ "$(cat "$out/mine/notes.txt")" = "my notes" ] && [ "$(ls "$out/mine")" = notes.txt ] || fail "not_vrvs: touched $out/mine"

# Two runs into one --out had no lock: the second refuses, one line, and the first's folder stays.
before=$(fingerprint "$out/v")
( flock 9 && expect locked 2 "^vrv: error: --out: .*/v: cannot write the results: another vrv .* writing them" \
    "${verify[@]}" --out "$out/v" ) 9> "$out/.v.lock" || exit 1
[ "$(fingerprint "$out/v")" = "$before" ] || fail "locked: --out changed"

# SIGINT mid-write (the third file, its temporary on disk: a test hook) left new and old files
# mixed and a *.tmp.PID; now exit 130 with the previous outputs whole and no temporary file.
VRV_TEST_SIGNAL_AT_WRITE=3 expect interrupted 130 "^vrv: stopped by signal 2; published results are unchanged$" \
  "${verify[@]}" --bounds "$out/b.toml" --out "$out/v"
[ "$(fingerprint "$out/v")" = "$before" ] || fail "interrupted: --out changed"
no_temporaries interrupted
# The staging folder stays hidden beside --out (as a study's does) until the next run removes it.
expect after_interrupted 0 "" "${verify[@]}" --out "$out/v"
[ ! -e "$out/.v.partial" ] || fail "after_interrupted: the staging folder is still there"
VRV_TEST_SIGNAL_AT_WRITE=1:15 expect terminated 143 "^vrv: stopped by signal 15" "${verify[@]}" --out "$out/new"
[ ! -e "$out/new" ] || [ -z "$(ls -A "$out/new")" ] || fail "terminated: a first run left $(ls "$out/new")"
no_temporaries terminated

# A full disk replaced errors.* and orders.* and then failed: now one line, the previous outputs
# whole.  Needs a small file system: a tmpfs, mounted where the test runs as root.
if [ "$(id -u)" = 0 ] && mkdir -p "$out/disk" && mount -t tmpfs -o size=4m tmpfs "$out/disk" 2> /dev/null; then
  trap 'umount "$out/disk" 2> /dev/null' EXIT
  expect disk_first 0 "" "${verify[@]}" --out "$out/disk/v"
  before=$(fingerprint "$out/disk/v")
  dd if=/dev/zero of="$out/disk/fill" bs=4096 2> /dev/null
  truncate -s -16384 "$out/disk/fill"  # room for a few tables, not for the images
  expect disk_full 2 "^vrv: error: --out: $out/disk/v: not written, the previous outputs are unchanged: .*: cannot write: No space left on device$" "${verify[@]}" --bounds "$out/b.toml" --out "$out/disk/v"
  [ "$(fingerprint "$out/disk/v")" = "$before" ] || fail "disk_full: --out changed"
  no_temporaries disk_full
  umount "$out/disk" && trap - EXIT
else
  echo "robustness_outputs: not root or no tmpfs here; the full-disk case is skipped"
fi

# (9) An interrupted export left export.json describing one grid beside another's field: the
# export is published whole too, and a later export leaves none of an earlier one's files.
expect export_first 0 "" "$vrv" export --out "$out/e" --resolution 8,8,8
before=$(fingerprint "$out/e")
VRV_TEST_SIGNAL_AT_WRITE=2 expect export_interrupted 130 "^vrv: stopped by signal 2" \
  "$vrv" export --out "$out/e" --resolution 12,12,12
[ "$(fingerprint "$out/e")" = "$before" ] || fail "export_interrupted: --out changed"
no_temporaries export_interrupted
expect export_detached 0 "" "$vrv" export --out "$out/e" --resolution 8,8,8 --nrrd detached
[ -f "$out/e/field_f32.nhdr" ] && [ ! -e "$out/e/field_f32.nrrd" ] || fail "export_detached: $(ls "$out/e")"
expect export_not_vrvs 2 "^vrv: error: --out: $out/mine: holds files vrv did not write \(no export.json\)" \
  "$vrv" export --out "$out/mine" --resolution 4,4,4

# (13) An export of 2048^3 nodes (hundreds of GiB) or for a 16384^2 camera (rays.npy 12 GiB)
# allocated until bad_alloc or the out-of-memory killer: both are refused before anything is
# allocated or written, in vrv study's words (--max-memory GIB).
expect export_memory 2 "^vrv: error: --resolution: the export needs about [0-9.]+ GiB \(2048x2048x2048 nodes: [0-9.]+ GiB; .*\), more than the limit of [0-9.]+ GiB \(raise it with --max-memory GIB\)$" \
  "$vrv" export --out "$out/huge" --resolution 2048,2048,2048
sed 's/^width = 32/width = 16384/; s/^height = 32/height = 16384/' "$src/studies/gate/ml-oblique.toml" > "$out/big_camera.toml"
expect export_camera_memory 2 "^vrv: error: $out/big_camera.toml: camera: the export needs about [0-9.]+ GiB \(.*rays.npy for 16384 x 16384 pixels: 12.0 GiB\), more than the limit of 4.0 GiB" \
  "$vrv" export --scene "$out/big_camera.toml" --out "$out/huge" --max-memory 4
[ ! -e "$out/huge" ] || fail "export_memory: created $out/huge"
expect export_small_limit 2 "^vrv: error: --resolution: the export needs about [0-9.]+ MiB .*more than the limit of 1.0 MiB" \
  "$vrv" export --out "$out/huge" --resolution 64,64,64 --max-memory 0.001
expect export_limit_raised 0 "" "$vrv" export --out "$out/huge" --resolution 64,64,64 --max-memory 0.1

# vrv render holds the image several times over: refused from the camera's size the same way.
expect render_camera_memory 2 "^vrv: error: $out/big_camera.toml: camera: the render needs about 7.2 GiB \(16384 x 16384 pixels, 29 bytes each\), more than the limit of 4.0 GiB \(raise it with --max-memory GIB\)$" \
  "$vrv" render --scene "$out/big_camera.toml" --method alpha --strategy step --step 0.5 -o "$out/huge.exr" --max-memory 4
expect render_size_memory 2 "^vrv: error: --width/--height: the render needs about 29.0 MiB \(1024 x 1024 pixels, 29 bytes each\), more than the limit of 10.2 MiB" \
  "$vrv" render --method alpha --strategy step --step 0.5 --width 1024 --height 1024 -o "$out/huge.exr" --max-memory 0.01
[ ! -e "$out/huge.exr" ] || fail "render_memory: wrote $out/huge.exr"

# Smaller: a full disk while plotting printed a 40-line Python traceback and exited 0; the plot
# script's output is caught, its last line quoted in one line, exit 1 (as a study's failed plot).
printf '#!/bin/sh\nfor i in $(seq 40); do echo "  File \\"plot_study.py\\", line $i" >&2; done\necho "OSError: [Errno 28] No space left on device" >&2\nexit 1\n' > "$out/python"
chmod +x "$out/python"
VRV_PYTHON="$out/python" expect plot_failed 1 "^vrv verify: .*/plotted: the plot could not be drawn: .*: OSError: \[Errno 28\] No space left on device; or leave out --plots$" \
  "$vrv" verify "${images[@]}" --no-cache --quiet --out "$out/plotted" --plots
grep -q '"plots":"failed: ' "$out/plot_failed.out" || fail "plot_failed: $(cat "$out/plot_failed.out")"

# A PNG cut inside a chunk is refused before libpng reads it (lib/io/image_structure.h), naming the
# chunk; cut where a chunk ends, libpng finds the end itself and printed its own line before vrv's
# (and leaked inside OpenImageIO: the sanitizer build's leak check: suppressed in
# lib/io/image_module.cpp, as it is inside it): one line now.
head -c 200 "$out/0.01.png" > "$out/truncated.png"
expect truncated_png 2 "^vrv: error: $out/truncated.png: PNG chunk 'tEXt' at byte [0-9]+ claims [0-9]+ bytes, [0-9]+ are left \(damaged or truncated\)$" \
  "$vrv" verify "$out/truncated.png" "$out/0.01.exr" --steps 0.02,0.01 --no-cache --quiet
chunk_start=$(sed -E 's/.* at byte ([0-9]+) claims.*/\1/' "$out/truncated_png.err")
head -c "$chunk_start" "$out/0.01.png" > "$out/cut_at_chunk.png"
expect cut_at_chunk_png 2 "^vrv: error: $out/cut_at_chunk.png: cannot read: .*end of file" \
  "$vrv" verify "$out/cut_at_chunk.png" "$out/0.01.exr" --steps 0.02,0.01 --no-cache --quiet

# --steps ...,1e-320 was refused as "--step gives more than 1e12 samples on one ray", naming no image.
expect tiny_step 2 "^vrv: error: $out/0.01.exr: --steps: step .* would take more than 1e\+12 samples along the box's diagonal" \
  "$vrv" verify "${images[@]}" --steps 0.02,1e-320 --no-cache --quiet

echo "robustness_outputs: all passed"
