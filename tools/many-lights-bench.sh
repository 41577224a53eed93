#!/bin/bash
# The "Many lights" table of docs/benchmarks.md: next-event estimation picking emitters by a light
# tree against picking them by power (--light-sampler tree / power), by `dacrt converge` without
# a reference (the error is the noise between two seeds), on
# - a generated floor under N small lamps (tools/make_many_lights.py; N from $LAMPS, default
#   "4000 64 16": the target scene, then near the automatic choice's threshold and below it), and
# - the conference room under 72 point lights (/work/shared/scenes/mcguire/conference, or
#   $CONFERENCE; skipped when absent).
# Prints, per scene, both configurations' noise at the longest time both ran and the ratio of
# their noise² at that equal time (tree over power: below 1 the tree wins), and the ratio of
# their seconds for the same samples (what the tree's picks cost).
#
#   tools/many-lights-bench.sh [DACRT] [OUTDIR]
#
# Environment: SIZE (the longer side, default 320), BUDGET (seconds per configuration, default
# 20), REPEATS (default 3), LAMPS, CONFERENCE.
set -euo pipefail
dacrt=${1:-build/dacrt}
out=${2:-/tmp/many-lights-bench}
size=${SIZE:-320}
budget=${BUDGET:-20}
repeats=${REPEATS:-3}
lamps=${LAMPS:-4000 64 16}
conference=${CONFERENCE:-/work/shared/scenes/mcguire/conference}
here=$(cd "$(dirname "$0")" && pwd)
mkdir -p "$out"

# converge SCENE NAME [render options]: one row of the table.
converge() {
  local scene=$1 name=$2
  shift 2
  "$dacrt" converge "$scene" --no-reference --width "$size" --time-budget "$budget" \
    --repeats "$repeats" --quiet --no-plot -o "$out/$name" \
    --config "light-sampler=power" --config "light-sampler=tree" "$@" > "$out/$name.txt"
  # convergence.csv: config,spp,seconds,...,noise,...: each configuration's noise at the longest
  # time both ran, interpolated in log-log between its points (as converge's equal time).
  python3 - "$out/$name/convergence.csv" "$name" <<'EOF'
import csv, math, sys
rows = list(csv.DictReader(open(sys.argv[1])))
curves = {}
for r in rows:
    if r["noise"]:
        curves.setdefault(r["config"], []).append((float(r["seconds"]), float(r["noise"])))
t = min(max(s for s, _ in c) for c in curves.values())
def at(curve, t):
    curve.sort()
    for (s0, e0), (s1, e1) in zip(curve, curve[1:]):
        if s0 <= t <= s1:
            f = (math.log(t) - math.log(s0)) / (math.log(s1) - math.log(s0)) if s1 > s0 else 0
            return math.exp(math.log(e0) + f * (math.log(e1) - math.log(e0)))
    return curve[-1][1]
power, tree = at(curves["light-sampler=power"], t), at(curves["light-sampler=tree"], t)
# The cost of the tree's picks: seconds per sample, tree over power, at the most samples both
# rendered.
seconds = {}
for r in rows:
    seconds.setdefault(r["config"], {})[int(r["spp"])] = float(r["seconds"])
p, q = seconds["light-sampler=power"], seconds["light-sampler=tree"]
spp = max(set(p) & set(q))
print("| %s | %.2f s | %.4g | %.4g | %.3f | %.2f (%d spp) |" %
      (sys.argv[2], t, power, tree, (tree / power) ** 2, q[spp] / p[spp], spp))
EOF
}

echo "| scene | equal time | noise, power | noise, tree | noise² tree / power | time per sample, tree / power |"
echo "|---|---|---|---|---|---|"
for n in $lamps; do
  scene="$out/many-lights-$n.gltf"
  python3 "$here/make_many_lights.py" "$scene" --lamps "$n"
  converge "$scene" "many-lights-$n"
done
# The conference room's file has no emitters (its lamps are grey geometry): it is lit here by a
# grid of 12 x 6 point lights under its ceiling, 72 in all, seen from inside.
if [ -e "$conference/conference.glb" ]; then
  lights=()
  for i in $(seq 0 11); do
    for j in $(seq 0 5); do
      lights+=(--point-light "$((-900 + 220 * i)),600,$((-950 + 280 * j))=12000,11600,10800")
    done
  done
  converge "$conference/conference.glb" conference-72-points --environment 0,0,0 \
    --look-from 1600,420,300 --look-at -600,150,-500 --fov 55 "${lights[@]}"
fi
