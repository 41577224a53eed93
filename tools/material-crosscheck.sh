#!/usr/bin/env bash
# dacrt's material lobes against Blender's Cycles: one small scene per glTF material extension
# (tools/make_material_scenes.py), rendered by both at the same size and samples, and a table of
# each image's mean per channel, and the mean over a window on the sphere (its middle: only the
# material under test, lit by the sky and the floor), with their ratios (dacrt / Cycles). The
# differences the two models explain are in docs/gltf.md ("Cross-checked against Cycles").
#   tools/material-crosscheck.sh [--spp N] [--size S] [NAME...]
# Defaults: 256 spp, 160 x 160, every scene. Environment: BIN (default build/dacrt), BLENDER
# (default blender), OUT (default /tmp/material-crosscheck).
# Optional: needs `apt-get install blender python3-numpy` (Debian 12: Blender 3.4, whose glTF
# importer reads clearcoat, sheen, specular, transmission, volume and unlit, but not anisotropy
# or iridescence: those rows compare against Cycles without the extension). No test, no build
# step and no CI script runs it.
set -euo pipefail
ROOT=$(cd "$(dirname "$0")/.." && pwd)
SPP=256; SIZE=160; names=()
while [ $# -gt 0 ]; do
  case $1 in
    --spp) SPP=$2; shift 2 ;;
    --size) SIZE=$2; shift 2 ;;
    -*) echo "usage: tools/material-crosscheck.sh [--spp N] [--size S] [NAME...]" >&2; exit 2 ;;
    *) names+=("$1"); shift ;;
  esac
done
BIN=${BIN:-$ROOT/build/dacrt}
BLENDER=${BLENDER:-blender}
OUT=${OUT:-/tmp/material-crosscheck}
command -v "$BLENDER" >/dev/null || { echo "material-crosscheck: Blender not found" >&2; exit 1; }
mkdir -p "$OUT"
python3 "$ROOT/tools/make_material_scenes.py" "$OUT/scenes" >/dev/null
[ ${#names[@]} -gt 0 ] || names=(base clearcoat sheen specular volume unlit anisotropy iridescence)
mean() {
  "$BLENDER" -b -noaudio --factory-startup --python "$ROOT/tools/exr-stats.py" -- "$@" 2>/dev/null | sed -n 's/^mean //p'
}
ratio() {
  python3 -c "import sys; d=[float(x) for x in sys.argv[1].split()]; c=[float(x) for x in sys.argv[2].split()]; print(' '.join('%.3f' % (a / b if b else float('nan')) for a, b in zip(d, c)))" "$1" "$2"
}
# The sphere (radius 1, 5 units away, yfov 0.6) spans the middle ~65 % of the frame.
SPHERE=(--crop 0.4 0.4 0.6 0.6)
printf '| scene | dacrt mean R G B | Cycles mean R G B | dacrt / Cycles | sphere: dacrt | sphere: Cycles | sphere: dacrt / Cycles |\n|---|---|---|---|---|---|---|\n'
for name in "${names[@]}"; do
  scene=$OUT/scenes/$name.gltf
  # Both under a sky of 1, also where the sphere emits (unlit): the default would be black there.
  "$BIN" render "$scene" --spp "$SPP" --width "$SIZE" --height "$SIZE" --environment 1,1,1 --quiet \
    -o "$OUT/$name.dacrt.exr" 2>"$OUT/$name.dacrt.log"
  "$BLENDER" -b -noaudio --factory-startup --python "$ROOT/tools/cycles-render.py" -- "$scene" \
    "$OUT/$name.cycles.exr" --spp "$SPP" --width "$SIZE" --height "$SIZE" --environment 1,1,1 \
    >"$OUT/$name.cycles.log" 2>&1
  d=$(mean "$OUT/$name.dacrt.exr"); c=$(mean "$OUT/$name.cycles.exr")
  ds=$(mean "${SPHERE[@]}" "$OUT/$name.dacrt.exr"); cs=$(mean "${SPHERE[@]}" "$OUT/$name.cycles.exr")
  printf '| %s | %s | %s | %s | %s | %s | %s |\n' "$name" "$d" "$c" "$(ratio "$d" "$c")" "$ds" "$cs" \
    "$(ratio "$ds" "$cs")"
done
