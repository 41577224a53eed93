#!/usr/bin/env bash
# The backend comparison of the README: every staged scene rendered by dacrt, dacrt-naive and
# embree, each backend in its own process (load, build and render: the whole process), RUNS times
# alternating, and the medians; dacrt's speed-up vs embree (embree's seconds / dacrt's, higher is
# faster: the one convention of dacrt's ratios). Also, from the same runs' statistics, ray
# sampling's gain, dacrt's speed-up vs dacrt-naive per ray type (naive backend seconds / dacrt's),
# and the render's bounce rays against `dacrt bench --rays bounce --count 1048576` on the same
# scene.
# The last column compares dacrt's bounce rays with Embree's in the same runs, by depth: the
# first bounce, and depths 10 and deeper together (where the frame's last paths trace in small
# batches).
#   tools/backend-table.sh [WIDTH] [SPP] [RUNS]     (default 384 16 3; ../shared must be beside)
#   BACKENDS="dacrt embree" tools/backend-table.sh 1024 64 3   (without dacrt-naive: its columns "-")
#   SCENES="dragon sponza" ...                      (only the staged scenes whose names are given)
#   DACRT_OPTIONS="walk_rays=4 top_triangles=16" ... (--backend-option for dacrt and dacrt-naive)
#   NO_BENCH=1 ...                                  (no `dacrt bench` run: that column "-")
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
read -r -a backends <<< "${BACKENDS:-dacrt dacrt-naive embree}"
options=()
for o in ${DACRT_OPTIONS:-}; do options+=(--backend-option "$o"); done
echo "| scene | dacrt s | embree s | dacrt-naive s | speed-up vs embree, higher is faster | speed-up vs dacrt-naive, primary | speed-up vs dacrt-naive, bounce | speed-up vs dacrt-naive, shadow | bounce Mrays/s render / bench | bounce rate vs embree, depth 1 / depth ≥ 10 |"
echo "|---|---|---|---|---|---|---|---|---|---|"
for scene in "${scenes[@]}"; do
  name=$(basename "$scene" .glb)
  if [ -n "${SCENES:-}" ] && [[ " $SCENES " != *" $name "* ]]; then continue; fi
  for run in $(seq "$RUNS"); do
    for b in "${backends[@]}"; do
      opts=()
      [ "$b" = embree ] || opts=("${options[@]}")
      t0=$(date +%s.%N)
      "$BIN" render "$scene" --width "$W" --height "$W" --spp "$SPP" --backend "$b" --quiet \
        "${opts[@]}" -o "$OUT/$name.$b.exr" --stats "$OUT/$name.$b.$run.json"
      t1=$(date +%s.%N)
      echo "$t0 $t1" > "$OUT/$name.$b.$run.time"
    done
  done
  rm -f "$OUT/$name.bench.json"
  [ -n "${NO_BENCH:-}" ] ||
    "$BIN" bench "$scene" --rays bounce --count 1048576 --backends dacrt --repeat 3 \
      "${options[@]}" --json "$OUT/$name.bench.json" > /dev/null 2>&1 || true
  python3 - "$OUT" "$name" "$RUNS" "${backends[@]}" <<'PY'
import json, os, statistics, sys
out, name, runs, have = sys.argv[1], sys.argv[2], int(sys.argv[3]), sys.argv[4:]
def med(b, f):
    if b not in have:
        return float("nan")
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
    gain[t] = f"{ns / ds:.2f}" if ds > 0 and ns == ns else "-"
# Bounce rays per second by depth (a merged call's time is shared by ray count): the first
# bounce, and every depth from 10 on summed.
def depth_rate(b, r, first, last):
    d = stats(b, r).get("bounces", [])[first:last]
    s = sum(x["seconds"] for x in d)
    return sum(x["rays"] for x in d) / s if s > 0 else float("nan")
depth = []
for first, last in ((0, 1), (9, None)):
    de = med("embree", lambda b, r: depth_rate(b, r, first, last))
    dd = med("dacrt", lambda b, r: depth_rate(b, r, first, last))
    depth.append(f"{dd / de:.2f}" if dd == dd and de == de and de > 0 else "-")
def fmt(x):
    return f"{x:.2f}" if x == x else "-"
rate = med("dacrt", lambda b, r: stats(b, r)["rays"]["bounce"]["rays_per_second"]) * 1e-6
bench = "-"
try:
    j = json.load(open(f"{out}/{name}.bench.json"))
    rows = [x for x in j["results"] if x["backend"] == "dacrt" and x["rays"] == "bounce"]
    bench = f"{rows[0]['mrays_per_s']:.2f}"
except Exception:
    pass
print(f"| {name} | {d:.2f} | {fmt(e)} | {fmt(n)} | {fmt(e / d)} | {gain['primary']} | {gain['bounce']} | {gain['shadow']} | {rate:.2f} / {bench} | {depth[0]} / {depth[1]} |")
PY
done
