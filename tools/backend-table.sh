#!/usr/bin/env bash
# The backend comparison of the README: every staged scene rendered by dacrt, dacrt-naive and
# embree, each backend in its own process (load, build and render: the whole process), RUNS times
# alternating, and the medians; dacrt's speed-up vs embree (embree's seconds / dacrt's, higher is
# faster: the one convention of dacrt's ratios). Also, from the same runs' statistics, ray
# sampling's gain, dacrt's speed-up vs dacrt-naive per ray type (naive backend seconds / dacrt's),
# and the render's bounce rays against `dacrt bench --rays bounce --count 1048576` on the same
# scene.
#   tools/backend-table.sh [WIDTH] [SPP] [RUNS]     (default 384 16 3; ../shared must be beside)
# Prints a Markdown table on stdout; the runs' JSON stays in $OUT (default /tmp/dacrt-table).
set -euo pipefail
cd "$(dirname "$0")/.."
W=${1:-384}; SPP=${2:-16}; RUNS=${3:-3}
OUT=${OUT:-/tmp/dacrt-table}; mkdir -p "$OUT"
BIN=${BIN:-build/dacrt}
S=../shared/scenes
[ -d "$S" ] || { echo "backend-table: $S not found" >&2; exit 1; }
scenes=("$S/stanford/dragon/dragon.glb" "$S/mcguire/conference/conference.glb"
        "$S/mcguire/dabrovic-sponza/sponza.glb" "$S/mcguire/cornell-box/CornellBox-Original.glb"
        "$S/khronos/DamagedHelmet/DamagedHelmet.glb")
backends=(dacrt dacrt-naive embree)
echo "| scene | dacrt s | embree s | dacrt-naive s | speed-up vs embree, higher is faster | speed-up vs dacrt-naive, primary | speed-up vs dacrt-naive, bounce | speed-up vs dacrt-naive, shadow | bounce Mrays/s render / bench |"
echo "|---|---|---|---|---|---|---|---|---|"
for scene in "${scenes[@]}"; do
  name=$(basename "$scene" .glb)
  for run in $(seq "$RUNS"); do
    for b in "${backends[@]}"; do
      t0=$(date +%s.%N)
      "$BIN" render "$scene" --width "$W" --height "$W" --spp "$SPP" --backend "$b" --quiet \
        -o "$OUT/$name.$b.exr" --stats "$OUT/$name.$b.$run.json"
      t1=$(date +%s.%N)
      echo "$t0 $t1" > "$OUT/$name.$b.$run.time"
    done
  done
  "$BIN" bench "$scene" --rays bounce --count 1048576 --backends dacrt --repeat 3 \
    --json "$OUT/$name.bench.json" > /dev/null 2>&1 || true
  python3 - "$OUT" "$name" "$RUNS" <<'PY'
import json, statistics, sys
out, name, runs = sys.argv[1], sys.argv[2], int(sys.argv[3])
def med(b, f):
    return statistics.median(f(b, r) for r in range(1, runs + 1))
def whole(b, r):
    t0, t1 = map(float, open(f"{out}/{name}.{b}.{r}.time").read().split())
    return t1 - t0
def stats(b, r):
    return json.load(open(f"{out}/{name}.{b}.{r}.json"))
def backend_s(b, r, t):
    return stats(b, r)["rays"][t]["seconds"]
d, e, n = (med(b, whole) for b in ("dacrt", "embree", "dacrt-naive"))
gain = {}
for t in ("primary", "bounce", "shadow"):
    ds, ns = med("dacrt", lambda b, r: backend_s(b, r, t)), med("dacrt-naive", lambda b, r: backend_s(b, r, t))
    gain[t] = f"{ns / ds:.2f}" if ds > 0 else "-"
rate = med("dacrt", lambda b, r: stats(b, r)["rays"]["bounce"]["rays_per_second"]) * 1e-6
bench = "-"
try:
    j = json.load(open(f"{out}/{name}.bench.json"))
    rows = [x for x in j["results"] if x["backend"] == "dacrt" and x["rays"] == "bounce"]
    bench = f"{rows[0]['mrays_per_s']:.2f}"
except Exception:
    pass
print(f"| {name} | {d:.2f} | {e:.2f} | {n:.2f} | {e / d:.2f} | {gain['primary']} | {gain['bounce']} | {gain['shadow']} | {rate:.2f} / {bench} |")
PY
done
