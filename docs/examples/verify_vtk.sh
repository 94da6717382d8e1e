#!/bin/sh
# The worked example of docs/verify-vtk.md, end to end:
#   docs/examples/verify_vtk.sh [VRV] [OUT]      (defaults: build/vrv, results/verify-vtk)
# Needs VTK's Python module, OpenImageIO's and numpy (Debian: python3-vtk9, python3-openimageio,
# python3-numpy) and xvfb-run (the GPU mapper runs on Mesa's llvmpipe under Xvfb).
set -eu
VRV=$(realpath "${1:-build/vrv}")
OUT=${2:-results/verify-vtk}
PY=${PY:-/usr/bin/python3}
VERIFY=${VERIFY:-$VRV}   # the vrv that runs `verify` (the same build once it has both)
SCENE=docs/examples/vtk_scene.toml
STEPS="0.08 0.04 0.02 0.01 0.005 0.0025"
LIST=$(echo $STEPS | tr ' ' ',')
TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT

"$VRV" export --scene $SCENE --out "$TMP/export" > /dev/null
"$VRV" render --scene $SCENE --reference --quiet -o "$TMP/reference.exr" > /dev/null
xvfb-run -a $PY docs/examples/vtk_render.py --mapper fixed "$TMP/export" "$TMP/images" $STEPS > /dev/null
xvfb-run -a $PY docs/examples/vtk_render.py --mapper gpu "$TMP/export" "$TMP/images" $STEPS > /dev/null

mkdir -p "$TMP/out"
cp $SCENE "$TMP/out/scene.toml"
cp "$TMP/export/camera.json" "$TMP/export/transfer_function.json" "$TMP/export/export.json" "$TMP/out/"
cp "$TMP/images/"*_steps.json "$TMP/out/"
status=0
for set in fixed:png fixed15:tiff gpu:png; do
  name=${set%%:*}; ext=${set#*:}
  images=$(for h in $STEPS; do printf '%s ' "$TMP/images/${name}_H$h.$ext"; done)
  mkdir -p "$TMP/out/$name"
  cp $images "$TMP/out/$name/"
  # The renderer's images, as vrv verify reads them; first order expected (VTK places its first
  # sample one step in and drops the last partial step: vrv's `vtk` placement).
  (cd "$TMP/out/$name" && "$VERIFY" verify --scene ../scene.toml $(for h in $STEPS; do printf '%s ' "${name}_H$h.$ext"; done) \
      --steps $LIST --expected-order 1 --out verify --plots --no-cache --threads 2 --quiet > verify.json) \
      && rc=0 || rc=$?
  echo "$rc" > "$TMP/out/$name/verify.exit"
  [ "$rc" -le 1 ] || status=$rc
  # The same figures recomputed in numpy from the images and vrv render's double reference.
  $PY docs/examples/vtk_figures.py "$TMP/reference.f64.tiff" "$TMP/out/$name/verify" "$TMP/out/$name/figures" \
      $images --steps $LIST > /dev/null || status=1
done
rm -rf "$OUT"
mkdir -p "$(dirname "$OUT")"
cp -r "$TMP/out" "$OUT"
echo "$OUT"
exit $status
