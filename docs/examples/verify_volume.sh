#!/bin/sh
# The worked example of docs/volume-example.md: a real MRI scan (nibabel's anatomical.nii, from
# Debian's python3-nibabel) exported by vrv, rendered by VTK, verified by vrv, end to end:
#   docs/examples/verify_volume.sh [VRV] [OUT]      (defaults: build/vrv, build/verify-volume)
# Needs python3-nibabel (the scan), python3-vtk9, python3-openimageio, python3-numpy and xvfb-run
# (xvfb, xauth): VTK's GPU mapper runs on Mesa's llvmpipe under Xvfb.
# STEPS (sample distances in mm, the scan's voxels are 2 mm) and SETS may be overridden; the test
# study.volume_example runs a short version.
set -eu
VRV=$(realpath "${1:-build/vrv}")
OUT=${2:-build/verify-volume}
PY=${PY:-/usr/bin/python3}
STEPS=${STEPS:-"2 1 0.5 0.25 0.125 0.0625"}
# set = layout of the scene : VTK mapper : image prefix : extension
SETS=${SETS:-"node:gpu:gpu:png node:fixed:fixed15:tiff cell:gpu:gpu:png"}
HERE=$(cd "$(dirname "$0")" && pwd)
SCENE=$HERE/volume_scene.toml
LIST=$(echo $STEPS | tr ' ' ',')
TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT

status=0
for set in $SETS; do
  layout=${set%%:*}; rest=${set#*:}; mapper=${rest%%:*}; rest=${rest#*:}; prefix=${rest%%:*}; ext=${rest#*:}
  name=${layout}_${prefix}
  work=$TMP/$layout
  if [ ! -d "$work" ]; then
    mkdir -p "$work"
    # The same scan and transfer function; only the layout differs (node: the scene as committed;
    # cell: the box half a voxel larger on every side, as renderers that draw voxels as cells).
    sed "s/^layout = \"node\"/layout = \"$layout\"/" "$SCENE" > "$work/scene.toml"
    grep -q "^layout = \"$layout\"" "$work/scene.toml"
    "$VRV" export --scene "$work/scene.toml" --out "$work/export" > /dev/null
    "$VRV" render --scene "$work/scene.toml" --reference --quiet -o "$work/reference.exr" > /dev/null
  fi
  [ -f "$work/images/${mapper}_steps.json" ] || \
    xvfb-run -a $PY "$HERE/vtk_render.py" --mapper $mapper "$work/export" "$work/images" $STEPS > /dev/null
  dir=$TMP/out/$name
  mkdir -p "$dir"
  cp "$work/export/scene.toml" "$work/export/export.json" "$work/export/transfer_function.json" \
     "$work/export/camera.json" "$work/images/${mapper}_steps.json" "$dir/"
  images=$(for h in $STEPS; do printf '%s ' "${prefix}_H$h.$ext"; done)
  for f in $images; do cp "$work/images/$f" "$dir/"; done
  # VTK's images against the scene that vrv exported (first order expected: VTK's first sample
  # one step in and its last partial step dropped, vrv's `vtk` placement).
  (cd "$dir" && "$VRV" verify --scene scene.toml $images --steps $LIST --expected-order 1 --out verify \
      --no-cache --threads 2 --quiet > verify.json) && rc=0 || rc=$?
  echo "$rc" > "$dir/verify.exit"
  [ "$rc" -le 1 ] || status=$rc
  # The whole-image figures recomputed in numpy from the images and vrv render's double reference.
  (cd "$dir" && $PY "$HERE/vtk_figures.py" "$work/reference.f64.tiff" verify figures $images \
      --steps $LIST > /dev/null) || status=1
done
$PY "$HERE/volume_summary.py" "$TMP/out" > "$TMP/out/summary.md"
rm -rf "$OUT"
mkdir -p "$(dirname "$OUT")"
cp -r "$TMP/out" "$OUT"
cat "$OUT/summary.md"
exit $status
