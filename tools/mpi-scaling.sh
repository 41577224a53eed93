#!/usr/bin/env bash
# Strong scaling of `mpirun -np R dacrt render` on this machine, and what merging costs.
#   tools/mpi-scaling.sh [SCENE] [WIDTH] [SPP] [RUNS]
# (default scenes/cornell-box.gltf 512 64 5). The same image is rendered by one process without
# mpirun and by R = 1, 2, 4 ranks under mpirun, each rank with T threads (R × T past the cores is
# oversubscribed: ranks share them); RUNS rounds, the configurations alternating within a round,
# and the median seconds of each (the whole process: load, build, render, reduce, write). Every
# image is checked bit for bit against the single process's (`dacrt diff`, max |A-B| 0).
# Then the merge: MERGE_PARTS (default 2 and 4) parts of a 1920 × 1080 render with every AOV,
# 1 spp each, merged by `dacrt merge` RUNS times (median seconds, peak memory, file sizes).
# Prints Markdown tables; the images stay in $OUT (default /tmp/dacrt-mpi-scaling).
set -euo pipefail
cd "$(dirname "$0")/.."
SCENE=${1:-scenes/cornell-box.gltf}; W=${2:-512}; SPP=${3:-64}; RUNS=${4:-5}
BIN=${BIN:-build/dacrt}
OUT=${OUT:-/tmp/dacrt-mpi-scaling}; mkdir -p "$OUT"
command -v mpirun >/dev/null || { echo "mpi-scaling: no mpirun (apt-get install openmpi-bin)" >&2; exit 1; }
# Each rank free to use every core (OpenMPI binds a rank to one core when there are 2 or fewer).
MPIRUN="mpirun -q --allow-run-as-root --oversubscribe --bind-to none"
args=("$SCENE" --width "$W" --height "$W" --spp "$SPP" --quiet)

# name | command prefix | threads per rank
configs=("one process, 1 thread||1" "one process, 2 threads||2"
         "mpirun -np 1, 2 threads|$MPIRUN -np 1|2"
         "mpirun -np 2, 1 thread each|$MPIRUN -np 2|1"
         "mpirun -np 2, 2 threads each|$MPIRUN -np 2|2"
         "mpirun -np 4, 1 thread each|$MPIRUN -np 4|1")
declare -A times
"$BIN" render "${args[@]}" -o "$OUT/reference.exr"
for run in $(seq "$RUNS"); do
  for i in "${!configs[@]}"; do
    IFS='|' read -r name prefix threads <<< "${configs[$i]}"
    t0=$(date +%s.%N)
    $prefix "$BIN" render "${args[@]}" --threads "$threads" -o "$OUT/c$i.exr"
    t1=$(date +%s.%N)
    times[$i]+="$(echo "$t1 - $t0" | bc) "
    max=$("$BIN" diff "$OUT/c$i.exr" "$OUT/reference.exr" --json |
          python3 -c 'import json,sys; print(json.load(sys.stdin)["metrics"]["RGB"]["max_abs"])')
    [ "$max" = 0 ] || [ "$max" = 0.0 ] || { echo "mpi-scaling: $name differs by $max" >&2; exit 1; }
  done
done
median() { tr ' ' '\n' | grep . | sort -g | awk '{a[NR]=$1} END {print (NR%2 ? a[(NR+1)/2] : (a[NR/2]+a[NR/2+1])/2)}'; }
base=$(echo "${times[0]}" | median)
echo "$(basename "$SCENE"), ${W}², $SPP spp, median of $RUNS runs; speed-up = one process on 1 thread's seconds / these"
echo
echo "| configuration | threads in all | seconds | speed-up vs 1 thread | image |"
echo "|---|---|---|---|---|"
for i in "${!configs[@]}"; do
  IFS='|' read -r name prefix threads <<< "${configs[$i]}"
  ranks=$(echo "$prefix" | { grep -o -- '-np [0-9]*' || true; } | awk '{print $2}'); ranks=${ranks:-1}
  m=$(echo "${times[$i]}" | median)
  printf '| %s | %d | %.2f | %.2f | bit for bit |\n' "$name" $((ranks * threads)) "$m" "$(echo "$base / $m" | bc -l)"
done

echo
echo "Merge: 1920 × 1080, every AOV, parts of 1 spp; median of $RUNS merges"
echo
echo "| parts | part file MB | merged file MB | merge seconds | peak MB |"
echo "|---|---|---|---|---|"
aov=albedo,normal,depth,position,variance,samples
for parts in ${MERGE_PARTS:-2 4}; do
  files=()
  for k in $(seq 0 $((parts - 1))); do
    "$BIN" render "$SCENE" --width 1920 --height 1080 --spp "$parts" --samples "$k:$((k + 1))" \
      --aov "$aov" --quiet -o "$OUT/part$k.exr"
    files+=("$OUT/part$k.exr")
  done
  ts=""; peak=0
  for run in $(seq "$RUNS"); do
    t0=$(date +%s.%N)
    /usr/bin/time -f %M -o "$OUT/time.txt" "$BIN" merge "${files[@]}" -o "$OUT/merged.exr" --quiet
    t1=$(date +%s.%N)
    ts+="$(echo "$t1 - $t0" | bc) "
    peak=$(( $(cat "$OUT/time.txt") > peak ? $(cat "$OUT/time.txt") : peak ))
  done
  printf '| %d | %.1f | %.1f | %.2f | %d |\n' "$parts" \
    "$(echo "$(stat -c %s "$OUT/part0.exr") / 1000000" | bc -l)" \
    "$(echo "$(stat -c %s "$OUT/merged.exr") / 1000000" | bc -l)" "$(echo "$ts" | median)" \
    $((peak / 1024))
done
