#!/usr/bin/env bash
# dacrt against Blender's Cycles on one glTF scene, in the same run: dacrt (backends dacrt and
# embree) and Cycles (tools/cycles-render.py) each render it twice, seeds 0 and 1, and a table
# gives each renderer's render seconds, noise (RMSE between the two seeds / sqrt 2, linear RGB)
# and image mean per channel, with the mean's ratio to dacrt's.
#   tools/peer-compare.sh SCENE [--spp N] [--width W] [--height H] [--max-depth D] [--threads T]
# Defaults: 64 spp, the camera's size (512 on the longer side), depth 64, 2 threads.
# Environment: BIN (default build/dacrt), BLENDER (default blender), OUT (default
# /tmp/peer-compare: the EXRs, stats, logs, manifest and table.md stay there).
# Optional: needs `apt-get install blender python3-numpy` (Debian 12: Blender 3.4). No test, no
# build step and no CI script runs it.
set -euo pipefail
usage() {
  echo "usage: tools/peer-compare.sh SCENE [--spp N] [--width W] [--height H] [--max-depth D] [--threads T]" >&2
  exit 2
}
ROOT=$(cd "$(dirname "$0")/.." && pwd)
[ $# -ge 1 ] || usage
SCENE=$1; shift
SPP=64; DEPTH=64; THREADS=2; size=()
while [ $# -gt 0 ]; do
  [ $# -ge 2 ] || usage
  case $1 in
    --spp) SPP=$2 ;;
    --width|--height) size+=("$1" "$2") ;;
    --max-depth) DEPTH=$2 ;;
    --threads) THREADS=$2 ;;
    *) usage ;;
  esac
  shift 2
done
BIN=${BIN:-$ROOT/build/dacrt}
BLENDER=${BLENDER:-blender}
OUT=${OUT:-/tmp/peer-compare}
[ -f "$SCENE" ] || { echo "peer-compare: $SCENE: no such file" >&2; exit 1; }
[ -x "$BIN" ] || { echo "peer-compare: $BIN not built (cmake --build build, or set BIN)" >&2; exit 1; }
if ! command -v "$BLENDER" >/dev/null; then
  echo "peer-compare: Blender not found ('$BLENDER'): the Cycles peer is optional;" \
       "install it with 'apt-get install blender python3-numpy' (Debian 12: Blender 3.4)" >&2
  exit 1
fi
mkdir -p "$OUT"
rm -f "$OUT"/manifest.tsv

now() { date +%s.%N; }
blender_py() {  # SCRIPT ARGS...: Blender in the background, its Python's output only
  "$BLENDER" -b -noaudio --factory-startup --python "$ROOT/tools/$1" -- "${@:2}"
}
declare -A render_s whole_s
sizes=${size[*]:-}; [ -n "$sizes" ] || sizes="the camera's size"
echo "peer-compare: $SCENE, $SPP spp, $sizes, depth $DEPTH, $THREADS threads; in $OUT" >&2
echo "load before: $(uptime)"
renderers=(dacrt embree cycles)
for seed in 0 1; do
  for r in "${renderers[@]}"; do
    exr=$OUT/$r.$seed.exr
    echo "peer-compare: $r, seed $seed" >&2
    t0=$(now)
    if [ "$r" = cycles ]; then
      blender_py cycles-render.py "$SCENE" "$exr" --spp "$SPP" "${size[@]}" --seed "$seed" \
        --max-depth "$DEPTH" --threads "$THREADS" > "$OUT/$r.$seed.log" 2>&1 ||
        { echo "peer-compare: Cycles failed, see $OUT/$r.$seed.log:" >&2; tail -5 "$OUT/$r.$seed.log" >&2; exit 1; }
      t1=$(now)
      s=$(sed -n 's/^cycles-seconds \([0-9.]*\)$/\1/p' "$OUT/$r.$seed.log")
    else
      "$BIN" render "$SCENE" -o "$exr" --spp "$SPP" "${size[@]}" --seed "$seed" \
        --max-depth "$DEPTH" --threads "$THREADS" --backend "$r" --quiet \
        --stats "$OUT/$r.$seed.json" > "$OUT/$r.$seed.log" 2>&1 ||
        { echo "peer-compare: dacrt --backend $r failed, see $OUT/$r.$seed.log:" >&2; tail -5 "$OUT/$r.$seed.log" >&2; exit 1; }
      t1=$(now)
      s=$(sed -n 's/.*"seconds_with_build": *\([0-9.eE+-]*\).*/\1/p' "$OUT/$r.$seed.json" | head -1)
    fi
    [ -n "$s" ] || { echo "peer-compare: no render time in $OUT/$r.$seed.*" >&2; exit 1; }
    render_s[$r.$seed]=$s
    whole_s[$r.$seed]=$(awk -v a="$t0" -v b="$t1" 'BEGIN { printf "%.3f", b - a }')
  done
done
echo "load after:  $(uptime)"
for r in "${renderers[@]}"; do
  label=$r; [ "$r" = cycles ] && label="Cycles $("$BLENDER" --version 2>/dev/null | sed -n '1s/^Blender //p')"
  [ "$r" = dacrt ] && label="dacrt (backend dacrt)"
  [ "$r" = embree ] && label="dacrt (backend embree)"
  printf '%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\n' "$label" "$SPP" "${render_s[$r.0]}" "${render_s[$r.1]}" \
    "${whole_s[$r.0]}" "${whole_s[$r.1]}" "$OUT/$r.0.exr" "$OUT/$r.1.exr" >> "$OUT/manifest.tsv"
done
blender_py exr-stats.py --table "$OUT/manifest.tsv" 2>"$OUT/stats.log" | sed -n '/^|/,/^render s:/p' > "$OUT/table.md" ||
  { echo "peer-compare: exr-stats failed, see $OUT/stats.log" >&2; exit 1; }
[ -s "$OUT/table.md" ] || { echo "peer-compare: exr-stats printed nothing, see $OUT/stats.log" >&2; exit 1; }
cat "$OUT/table.md"
echo
echo "per seed (render s / whole process s):"
for r in "${renderers[@]}"; do
  printf '  %-7s seed 0: %.3f / %.3f   seed 1: %.3f / %.3f\n' "$r" "${render_s[$r.0]}" "${whole_s[$r.0]}" \
    "${render_s[$r.1]}" "${whole_s[$r.1]}"
done
