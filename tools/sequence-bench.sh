#!/usr/bin/env bash
# What a frame of an animation costs: `render --frames` with dacrt (the kept backend refitted,
# frames=refit, the default; and frames=rebuild) against Embree with its rebuild (frames=rebuild)
# and with its refit (frames=refit: RTC_BUILD_QUALITY_REFIT), and each backend created anew every
# frame (frames=new: what --frames did before the backends were kept). A frame's cost is its
# preparation (the pose, then the backend's update or build) plus its render (the integrator's
# set-up and the samples): `geometry_seconds` + `seconds_with_build` of --stats, per frame after
# the first (the first is the load). Each process renders two backends frame by frame, dacrt
# then Embree, so their frames alternate under the same load; RUNS processes of each pair, and
# the medians over every frame of every run.
#   tools/sequence-bench.sh [FRAMES] [SPP] [RUNS]   (default 6 1 3; ../shared must be beside)
# Scenes: BrainStem (a skinned character, 61 k triangles) and the Stanford dragon turned on a
# turntable (tools/make-turntable.py, 871 k triangles), both at 1920 × 1080.
# Prints a Markdown table on stdout; the runs' JSON stays in $OUT (default /tmp/dacrt-sequence).
set -euo pipefail
cd "$(dirname "$0")/.."
FRAMES=${1:-6}; SPP=${2:-1}; RUNS=${3:-3}
OUT=${OUT:-/tmp/dacrt-sequence}; mkdir -p "$OUT"
BIN=${BIN:-build/dacrt}
S=../shared
[ -d "$S/scenes" ] || { echo "sequence-bench: $S/scenes not found" >&2; exit 1; }
[ -f "$OUT/dragon-turntable.glb" ] ||
  python3 tools/make-turntable.py "$S/scenes/stanford/dragon/dragon.glb" "$OUT/dragon-turntable.glb"
scenes=("$S/khronos-samples/BrainStem/glTF-Binary/BrainStem.glb" "$OUT/dragon-turntable.glb")
# Each pair: the dacrt way, the Embree way (one process).
pairs=("refit rebuild" "refit refit" "rebuild rebuild" "new new")
for scene in "${scenes[@]}"; do
  name=$(basename "$scene" .glb)
  for run in $(seq "$RUNS"); do
    for pair in "${pairs[@]}"; do
      set -- $pair
      "$BIN" render "$scene" --width 1920 --height 1080 --spp "$SPP" --quiet \
        --frames "0:$FRAMES" --fps 12 --backend dacrt,embree \
        --backend-option "dacrt.frames=$1" --backend-option "embree.frames=$2" \
        -o "$OUT/$name.exr" --stats "$OUT/$name.$1-$2.$run.json"
    done
  done
done
python3 - "$OUT" "$RUNS" "${scenes[@]}" <<'PY'
import json, os, statistics, sys
out, runs, scenes = sys.argv[1], int(sys.argv[2]), sys.argv[3:]
pairs = [("refit", "rebuild"), ("refit", "refit"), ("rebuild", "rebuild"), ("new", "new")]
print("| scene | backend, frames= | pose ms | update or build ms | render s | frame s | "
      "dacrt refit's frame / this frame |")
print("|---|---|---|---|---|---|---|")
for scene in scenes:
    name = os.path.splitext(os.path.basename(scene))[0]
    rows = {}  # (backend, way) -> lists over frames after the first of every run
    for d, e in pairs:
        for run in range(1, runs + 1):
            frames = json.load(open(f"{out}/{name}.{d}-{e}.{run}.json"))["frames"]
            for f in frames[1:]:
                for b in f["backends"]:
                    way = d if b["backend"] == "dacrt" else e
                    if b["backend"] == "dacrt" and (d, e) == ("refit", "refit"):
                        continue  # dacrt refit is measured beside Embree's rebuild
                    r = rows.setdefault((b["backend"], way), {"pose": [], "prep": [], "render": [], "frame": []})
                    r["pose"].append(f["geometry_seconds"])
                    r["prep"].append(b["update_seconds"] + b["build_seconds"])
                    r["render"].append(b["seconds_with_build"] - b["update_seconds"] - b["build_seconds"])
                    r["frame"].append(f["geometry_seconds"] + b["seconds_with_build"])
    med = {k: {q: statistics.median(v) for q, v in r.items()} for k, r in rows.items()}
    ref = med[("dacrt", "refit")]["frame"]
    for key in [("dacrt", "refit"), ("dacrt", "rebuild"), ("dacrt", "new"),
                ("embree", "rebuild"), ("embree", "refit"), ("embree", "new")]:
        m = med[key]
        print(f"| {name} | {key[0]}, {key[1]} | {1e3 * m['pose']:.0f} | {1e3 * m['prep']:.0f} | "
              f"{m['render']:.3f} | {m['frame']:.3f} | {ref / m['frame']:.2f} |")
PY
