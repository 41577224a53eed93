#!/bin/bash
# film-cost.sh: what the exact film costs, before against after (docs/benchmarks.md, issue 51).
#   BEFORE=/path/to/old/dacrt AFTER=build/dacrt [SPP=2] tools/film-cost.sh [ROUNDS]
# For each binary, alternating, ROUNDS times (default 3):
#  - the share of the process's CPU samples (perf record) in adding samples to the film
#    (Film::accumulate and Film::add_in_order's passes), on DamagedHelmet without AOVs and the
#    Cornell box with every AOV, at 1024² and 1920×1080, SPP samples a pixel;
#  - the peak resident memory (/usr/bin/time -v, in MiB) of the Cornell box at 1920×1080, every
#    AOV, 1 spp.
# Prints one line per measurement and the medians. Needs perf and GNU time.
set -euo pipefail
ROOT=$(cd "$(dirname "$0")/.." && pwd)
BEFORE=${BEFORE:?set BEFORE to the old dacrt binary}
AFTER=${AFTER:-$ROOT/build/dacrt}
ROUNDS=${1:-3}
SPP=${SPP:-2}  # samples a pixel of the shares' renders
HELMET=${HELMET:-$ROOT/../shared/scenes/khronos/DamagedHelmet/DamagedHelmet.glb}
CORNELL=$ROOT/scenes/cornell-box.gltf
AOVS=albedo,normal,depth,position,variance,samples
OUT=$(mktemp -d)
trap 'rm -rf "$OUT"' EXIT

share() {  # share BIN ARGS...: percent of perf samples in the film's adding
  local bin=$1; shift
  perf record -q -o "$OUT/perf.data" "$bin" render "$@" -o "$OUT/x.exr" --threads 2 --quiet \
    >/dev/null 2>&1
  perf report -i "$OUT/perf.data" --no-children --sort symbol --stdio 2>/dev/null |
    grep -E 'Film::accumulate|Film::add_in_order' | awk '{s += $1} END {printf "%.2f", s}'
}
peak() {  # peak BIN: MiB
  /usr/bin/time -v "$1" render "$CORNELL" -o "$OUT/p.exr" --spp 1 --width 1920 --height 1080 \
    --aov $AOVS --threads 2 --quiet 2>&1 >/dev/null |
    awk '/Maximum resident/ {printf "%.0f", $6 / 1024}'
}

declare -A results
cases=("helmet-1024:$HELMET --spp $SPP --width 1024 --height 1024"
       "helmet-1080p:$HELMET --spp $SPP --width 1920 --height 1080"
       "cornell-aov-1024:$CORNELL --spp $SPP --width 1024 --height 1024 --aov $AOVS"
       "cornell-aov-1080p:$CORNELL --spp $SPP --width 1920 --height 1080 --aov $AOVS")
uptime
for round in $(seq "$ROUNDS"); do
  for which in before after; do
    bin=$BEFORE; [ $which = after ] && bin=$AFTER
    for c in "${cases[@]}"; do
      name=${c%%:*}
      # shellcheck disable=SC2086
      s=$(share "$bin" ${c#*:})
      results[$which/$name]+="$s "
      echo "round $round $which $name film share ${s} %"
    done
    p=$(peak "$bin")
    results[$which/peak]+="$p "
    echo "round $round $which peak 1080p every AOV ${p} MiB"
  done
done
uptime
median() { tr ' ' '\n' | grep -v '^$' | sort -g | awk '{a[NR] = $1} END {print a[int((NR + 1) / 2)]}'; }
echo "medians (film share %, peak MiB): before | after"
for name in helmet-1024 helmet-1080p cornell-aov-1024 cornell-aov-1080p peak; do
  echo "$name $(echo "${results[before/$name]}" | median) | $(echo "${results[after/$name]}" | median)"
done
