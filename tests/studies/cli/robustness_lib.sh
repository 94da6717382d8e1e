# What the command-line test scripts share (robustness_*.sh, mpi_*.sh, cache_concurrency_test.sh):
# `out` is the scratch folder, set by the script that sources this.
fail() { echo "FAIL: $*" >&2; exit 1; }

# expect NAME CODE PATTERN CMD...: exits CODE (not a signal), stderr is one line matching PATTERN
# (empty: no line).
expect() {
  local name=$1 code=$2 pattern=$3
  shift 3
  timeout 120 "$@" > "$out/$name.out" 2> "$out/$name.err"
  local rc=$?
  [ $rc -eq "$code" ] || fail "$name: exit $rc, expected $code: $(head -c 600 "$out/$name.err")"
  [ "$(wc -l < "$out/$name.err")" -le 1 ] || fail "$name: stderr is more than one line: $(head -c 600 "$out/$name.err")"
  if [ -z "$pattern" ]; then
    [ ! -s "$out/$name.err" ] || fail "$name: stderr is not empty: $(head -c 600 "$out/$name.err")"
  else
    grep -Eq -- "$pattern" "$out/$name.err" || fail "$name: stderr does not match '$pattern': $(cat "$out/$name.err")"
  fi
}

# trapezoid_images SCENE WIDTH HEIGHT: vrv's trapezoid casts of SCENE at steps 0.04, 0.02 and 0.01
# as t<step>.exr in the current folder, their names in `images` (`vrv` is set by the script).
trapezoid_images() {
  local h
  images=()
  for h in 0.04 0.02 0.01; do
    "$vrv" render --scene "$1" --method trapezoid --step $h --width "$2" --height "$3" --quiet -o "t$h.exr" \
      > /dev/null 2>&1 || fail "render at step $h"
    images+=("t$h.exr")
  done
}
