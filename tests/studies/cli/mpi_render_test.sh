#!/usr/bin/env bash
# vrv render spread over MPI ranks (docs/distributed.md): every output byte the same as one
# process's for 2 and 3 ranks (the pixels' values, their provenance, the stdout JSON apart from its
# timing); bad input is one line and exit 2; a rank killed midway ends the run with a non-zero
# exit, no hang and nothing written.  Label `mpi`: needs a build with -DVRV_WITH_MPI=ON and mpirun.
# Usage: mpi_render_test.sh VRV SOURCE_DIR WORK_DIR [MPIRUN]
set -u
vrv=$1 src=$2 out=$3 mpirun=${4:-mpirun}
rm -rf "$out" && mkdir -p "$out" || exit 1
source "$src/tests/studies/cli/robustness_lib.sh"
source "$src/tests/studies/cli/mpi_lib.sh"

grid=$src/studies/benchmarks/grid64_opacity.toml
rgb=$src/tests/fuzz/corpus/scene_ray/rgb-opacity.toml
# NAME, then vrv render's options: the default scene's reference, a 64^3 grid's reference and a
# trapezoid cast of it, an RGB scene, a MIP projection, and an error image against a reference.
cases=(
  "reference|--reference --width 96 --height 80"
  "grid_reference|--scene $grid --reference --width 64 --height 48"
  "grid_trapezoid|--scene $grid --method trapezoid --step 0.01 --width 97 --height 61"
  "rgb|--scene $rgb --reference --width 40 --height 40"
  "mip|--scene $grid --mode mip --reference --width 50 --height 50"
  "error_against|--scene $grid --method riemann --step 0.02 --width 64 --height 48 --error-against $out/grid_reference_1.exr"
)
for c in "${cases[@]}"; do
  name=${c%%|*} args=${c#*|}
  # One process, without mpirun, then 2 and 3 ranks.
  "$vrv" render $args --quiet -o "$out/${name}_1.exr" > "$out/${name}_1.json" 2> "$out/${name}_1.err" \
    || fail "$name: one process: $(cat "$out/${name}_1.err")"
  for np in 2 3; do
    mpi "$np" "$vrv" render $args --quiet -o "$out/${name}_$np.exr" > "$out/${name}_$np.json" 2> "$out/${name}_$np.err" \
      || fail "$name: $np ranks: exit $?: $(head -c 600 "$out/${name}_$np.err")"
    for f in "$out/${name}_1"*; do
      g=${f/_1/_$np}
      case $f in
        *.err) ;;
        *.json) # the same but for the output names and the timing
          a=$(sed -e "s/${name}_1/X/g" -e 's/"seconds":[^,]*,//' "$f") b=$(sed -e "s/${name}_$np/X/g" -e 's/"seconds":[^,]*,//' "$g")
          [ "$a" = "$b" ] || fail "$name: $np ranks: stdout differs: $b against $a" ;;
        *) cmp -s "$f" "$g" || fail "$name: $np ranks: $(basename "$g") differs from one process's" ;;
      esac
    done
  done
done
[ -f "$out/error_against_3_error.exr" ] || fail "error_against: no error image with 3 ranks"

# The work was dealt (equal outputs alone would not show it: every rank computing every pixel
# gives them too): every rank reports its share, the shares add up to every block once, and at
# least two ranks computed some (which ones is the counter's: a rank slowed by the machine's other
# work may find the blocks gone, as dealing by measured cost means).
VRV_RANK_SHARES=1 mpi 3 -x VRV_RANK_SHARES "$vrv" render --scene "$grid" --reference --width 128 --height 96 --quiet \
  -o "$out/shares.exr" > /dev/null 2> "$out/shares.err" || fail "shares: $(head -c 600 "$out/shares.err")"
python3 - "$out/shares.err" <<'PY' || fail "shares: $(cat "$out/shares.err")"
import re, sys
shares = re.findall(r"^vrv: rank (\d) of 3: (\d+) of (\d+) blocks$", open(sys.argv[1]).read(), re.M)
assert sorted(r for r, _, _ in shares) == ["0", "1", "2"], shares
assert sum(int(n) > 0 for _, n, _ in shares) >= 2, shares
assert len({m for _, _, m in shares}) == 1 and sum(int(n) for _, n, _ in shares) == int(shares[0][2]), shares
PY

# Bad input, met by every rank: one line (rank 0's; mpirun's own notice follows it), exit 2.
mpi 2 "$vrv" render --scene "$out/missing.toml" --reference -o "$out/bad.exr" > /dev/null 2> "$out/bad.err"
rc=$?
[ $rc -eq 2 ] || fail "bad input: exit $rc, expected 2"
[ "$(grep -c '^vrv\|^rank' "$out/bad.err")" -eq 1 ] || fail "bad input: not one vrv line: $(cat "$out/bad.err")"
grep -q "^vrv: error: .*missing.toml" "$out/bad.err" || fail "bad input: the file is not named: $(cat "$out/bad.err")"
[ ! -e "$out/bad.exr" ] || fail "bad input: an image was written"
# A command not spread over ranks yet is refused, not run twice.
mpi 2 "$vrv" export --scene default --out "$out/exported" > /dev/null 2> "$out/export.err"
rc=$?
[ $rc -eq 2 ] || fail "export: exit $rc, expected 2"
grep -q "^vrv: error: mpirun: 2 ranks: only vrv render, vrv verify, vrv gate, vrv study are spread over MPI ranks so far; run vrv export as one process" "$out/export.err" \
  || fail "export: $(cat "$out/export.err")"
[ ! -e "$out/exported" ] || fail "export: written under several ranks"

# Rank 1 killed midway: mpirun ends every rank and exits non-zero; no image appears.
mpi 2 "$vrv" render --scene "$grid" --reference --width 1024 --height 1024 --quiet -o "$out/killed.exr" \
  > /dev/null 2> "$out/killed.err" &
run=$!
victim=
for _ in $(seq 100); do
  sleep 0.1
  victim=$(pgrep -f "render --scene $grid --reference --width 1024" | while read -r p; do
    [ "$(tr '\0' '\n' < /proc/$p/environ 2>/dev/null | grep -c '^OMPI_COMM_WORLD_RANK=1$')" -eq 1 ] && echo "$p"; done)
  [ -n "$victim" ] && break
done
[ -n "$victim" ] || fail "killed: rank 1 never started"
sleep 0.5
kill -9 $victim
wait $run
rc=$?
[ $rc -ne 0 ] || fail "killed: exit 0 after rank 1 was killed"
[ $rc -ne 124 ] || fail "killed: the run hung (timeout)"
[ ! -e "$out/killed.exr" ] || fail "killed: an image was written"
echo "mpi render: every output the same for 1, 2 and 3 ranks; bad input, a refused command and a killed rank end cleanly"
