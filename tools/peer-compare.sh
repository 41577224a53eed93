#!/usr/bin/env bash
# dacrt against Blender's Cycles on one glTF scene, in the same run: dacrt (backends dacrt and
# embree, and optionally an older dacrt binary) and Cycles (tools/cycles-render.py) each render it
# with seeds 0 and 1, ROUNDS times in turn, and a table gives each renderer's median render
# seconds, noise (RMSE between the two seeds / sqrt 2, linear RGB), image mean per channel with its
# ratio to dacrt's, and the figure of the issue tracker: noise² × seconds over Cycles' (the time
# dacrt needs for Cycles' noise, as a fraction of Cycles' time; lower is better).
#
#   tools/peer-compare.sh SCENE [options]       a scene file, with its own camera or these options
#   tools/peer-compare.sh --view NAME [options] a named view (below); options given after it win
#   tools/peer-compare.sh --views               lists the named views
# Options: --spp N, --width W, --height H, --max-depth D, --threads T, --rounds R,
#   --look-from X,Y,Z --look-at X,Y,Z --up X,Y,Z --fov DEGREES (all four: a camera given as a
#   LookAt, for both renderers; `dacrt info SCENE` prints a file's cameras, and the framed one,
#   in this form), --environment R,G,B (a uniform sky for both renderers).
# Defaults: 64 spp, the camera's size (512 on the longer side), depth 64, 2 threads, 1 round.
# Environment: BIN (default build/dacrt), BEFORE (an older dacrt binary, e.g. the commit before a
# change, rendered as one more row with backend dacrt), BLENDER (default blender), SCENES (default
# ../shared/scenes beside the checkout, for the named views), OUT (default /tmp/peer-compare: the
# EXRs, stats, logs, manifest and table.md stay there).
# Optional: needs `apt-get install blender python3-numpy` (Debian 12: Blender 3.4). No test, no
# build step and no CI script runs it.
set -euo pipefail
ROOT=$(cd "$(dirname "$0")/.." && pwd)
SCENES=${SCENES:-$ROOT/../shared/scenes}
usage() {
  echo "usage: tools/peer-compare.sh SCENE|--view NAME [--spp N] [--width W] [--height H]" \
       "[--max-depth D] [--threads T] [--rounds R] [--look-from X,Y,Z --look-at X,Y,Z --up X,Y,Z" \
       "--fov DEGREES] [--environment R,G,B]   (--views lists the views)" >&2
  exit 2
}

# The views of issue 34's table: NAME, then the scene and its options.
declare -A views=(
  [cornell]="$ROOT/scenes/cornell-box.gltf --spp 64"
  [sponza-inside]="$SCENES/mcguire/dabrovic-sponza/sponza.glb --spp 32 --width 384 --height 256
    --look-from -13,3,0 --look-at 10,5.5,0 --up 0,1,0 --fov 60 --environment 1,1,1"
  [helmet]="$SCENES/khronos/DamagedHelmet/DamagedHelmet.glb --spp 32 --width 384 --height 384
    --look-from -0.00248158,1.163265,4.465863 --look-at -0.00248158,1.060963e-05,-0.1871548
    --up 0,1,0 --fov 40.10704 --environment 1,1,1"
)
[ $# -ge 1 ] || usage
if [ "$1" = --views ]; then
  for v in cornell sponza-inside helmet; do echo "$v: ${views[$v]}" | tr -s ' \n' ' '; echo; done
  exit 0
fi
if [ "$1" = --view ]; then
  [ $# -ge 2 ] && [ -n "${views[$2]+x}" ] || { echo "peer-compare: --view wants one of: ${!views[*]}" >&2; exit 2; }
  VIEW=$2; shift 2
  # shellcheck disable=SC2206  # the view's words, split on purpose (no spaces inside values)
  set -- ${views[$VIEW]} "$@"
fi
SCENE=$1; shift
SPP=64; DEPTH=64; THREADS=2; ROUNDS=1; size=(); camera=(); cycles_camera=(); env=()
while [ $# -gt 0 ]; do
  [ $# -ge 2 ] || usage
  case $1 in
    --spp) SPP=$2 ;;
    --width|--height) size+=("$1" "$2") ;;
    --max-depth) DEPTH=$2 ;;
    --threads) THREADS=$2 ;;
    --rounds) ROUNDS=$2 ;;
    --look-from|--look-at|--up|--fov) camera+=("$1" "$2"); cycles_camera+=("$1=$2") ;;  # (argparse: -0.1 is a value)
    --environment) env=("$1" "$2") ;;
    *) usage ;;
  esac
  shift 2
done
[[ $ROUNDS =~ ^[1-9][0-9]*$ ]] || { echo "peer-compare: --rounds wants a count >= 1" >&2; exit 2; }
case ${#camera[@]} in 0|8) ;; *) echo "peer-compare: --look-from, --look-at, --up and --fov go together" >&2; exit 2 ;; esac
BIN=${BIN:-$ROOT/build/dacrt}
BLENDER=${BLENDER:-blender}
OUT=${OUT:-/tmp/peer-compare}
[ -f "$SCENE" ] || { echo "peer-compare: $SCENE: no such file" >&2; exit 1; }
[ -x "$BIN" ] || { echo "peer-compare: $BIN not built (cmake --build build, or set BIN)" >&2; exit 1; }
[ -z "${BEFORE:-}" ] || [ -x "$BEFORE" ] || { echo "peer-compare: BEFORE=$BEFORE is not an executable" >&2; exit 1; }
if ! command -v "$BLENDER" >/dev/null; then
  echo "peer-compare: Blender not found ('$BLENDER'): the Cycles peer is optional;" \
       "install it with 'apt-get install blender python3-numpy' (Debian 12: Blender 3.4)" >&2
  exit 1
fi
mkdir -p "$OUT"
rm -f "$OUT"/manifest.tsv

now() { date +%s.%N; }
median() { tr ' ' '\n' | sort -g | awk '{ v[NR] = $1 } END { printf "%.3f", NR % 2 ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2 }'; }
blender_py() {  # SCRIPT ARGS...: Blender in the background, its Python's output only
  "$BLENDER" -b -noaudio --factory-startup --python "$ROOT/tools/$1" -- "${@:2}"
}
declare -A render_s whole_s
sizes=${size[*]:-}; [ -n "$sizes" ] || sizes="the camera's size"
echo "peer-compare: $SCENE, $SPP spp, $sizes, ${camera[*]:-the camera in the file}, ${env[*]:-default sky}," \
     "depth $DEPTH, $THREADS threads, $ROUNDS round(s); in $OUT" >&2
echo "dacrt: $BIN ($(git -C "$ROOT" describe --always --dirty 2>/dev/null || echo '?'))${BEFORE:+; before: $BEFORE}"
echo "load before: $(uptime)"
renderers=(dacrt embree cycles)
[ -n "${BEFORE:-}" ] && renderers=(dacrt before embree cycles)
for round in $(seq "$ROUNDS"); do
  for seed in 0 1; do
    for r in "${renderers[@]}"; do
      exr=$OUT/$r.$seed.exr
      echo "peer-compare: round $round, $r, seed $seed" >&2
      t0=$(now)
      if [ "$r" = cycles ]; then
        blender_py cycles-render.py "$SCENE" "$exr" --spp "$SPP" "${size[@]}" "${cycles_camera[@]}" "${env[@]}" \
          --seed "$seed" --max-depth "$DEPTH" --threads "$THREADS" > "$OUT/$r.$seed.log" 2>&1 ||
          { echo "peer-compare: Cycles failed, see $OUT/$r.$seed.log:" >&2; tail -5 "$OUT/$r.$seed.log" >&2; exit 1; }
        t1=$(now)
        s=$(sed -n 's/^cycles-seconds \([0-9.]*\)$/\1/p' "$OUT/$r.$seed.log")
      else
        bin=$BIN backend=$r
        [ "$r" = before ] && bin=$BEFORE backend=dacrt
        "$bin" render "$SCENE" -o "$exr" --spp "$SPP" "${size[@]}" "${camera[@]}" "${env[@]}" --seed "$seed" \
          --max-depth "$DEPTH" --threads "$THREADS" --backend "$backend" --quiet \
          --stats "$OUT/$r.$seed.json" > "$OUT/$r.$seed.log" 2>&1 ||
          { echo "peer-compare: dacrt ($r) failed, see $OUT/$r.$seed.log:" >&2; tail -5 "$OUT/$r.$seed.log" >&2; exit 1; }
        t1=$(now)
        s=$(sed -n 's/.*"seconds_with_build": *\([0-9.eE+-]*\).*/\1/p' "$OUT/$r.$seed.json" | head -1)
      fi
      [ -n "$s" ] || { echo "peer-compare: no render time in $OUT/$r.$seed.*" >&2; exit 1; }
      render_s[$r.$seed]="${render_s[$r.$seed]:-} $s"
      whole_s[$r.$seed]="${whole_s[$r.$seed]:-} $(awk -v a="$t0" -v b="$t1" 'BEGIN { printf "%.3f", b - a }')"
    done
  done
done
echo "load after:  $(uptime)"
for r in "${renderers[@]}"; do
  case $r in
    cycles) label="Cycles $("$BLENDER" --version 2>/dev/null | sed -n '1s/^Blender //p')" ;;
    dacrt) label="dacrt (backend dacrt)" ;;
    embree) label="dacrt (backend embree)" ;;
    before) label="dacrt before (backend dacrt)" ;;
  esac
  printf '%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\n' "$label" "$SPP" \
    "$(median <<< "${render_s[$r.0]# }")" "$(median <<< "${render_s[$r.1]# }")" \
    "$(median <<< "${whole_s[$r.0]# }")" "$(median <<< "${whole_s[$r.1]# }")" \
    "$OUT/$r.0.exr" "$OUT/$r.1.exr" >> "$OUT/manifest.tsv"
done
blender_py exr-stats.py --table "$OUT/manifest.tsv" 2>"$OUT/stats.log" | sed -n '/^|/,/^render s:/p' > "$OUT/table.md" ||
  { echo "peer-compare: exr-stats failed, see $OUT/stats.log" >&2; exit 1; }
[ -s "$OUT/table.md" ] || { echo "peer-compare: exr-stats printed nothing, see $OUT/stats.log" >&2; exit 1; }
cat "$OUT/table.md"
echo
echo "each round's render s / whole process s:"
for r in "${renderers[@]}"; do
  printf '  %-7s seed 0: %s / %s   seed 1: %s / %s\n' "$r" "${render_s[$r.0]# }" "${whole_s[$r.0]# }" \
    "${render_s[$r.1]# }" "${whole_s[$r.1]# }"
done
