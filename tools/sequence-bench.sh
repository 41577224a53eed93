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
# PAIRS (default "refit-rebuild refit-refit rebuild-rebuild new-new") chooses the processes: the
# dacrt way and the Embree way of each.
# Scenes: BrainStem (a skinned character, 61 k triangles) and the Stanford dragon turned on a
# turntable (tools/make-turntable.py, 871 k triangles), both at 1920 × 1080.
# SCENES="A.glb B.glb" chooses others. Prints a Markdown table on stdout; the runs' JSON stays in $OUT (default /tmp/dacrt-sequence).
set -euo pipefail
cd "$(dirname "$0")/.."
FRAMES=${1:-6}; SPP=${2:-1}; RUNS=${3:-3}
OUT=${OUT:-/tmp/dacrt-sequence}; mkdir -p "$OUT"
BIN=${BIN:-build/dacrt}
S=../shared
[ -d "$S/scenes" ] || { echo "sequence-bench: $S/scenes not found" >&2; exit 1; }
[ -f "$OUT/dragon-turntable.glb" ] ||
  python3 tools/make-turntable.py "$S/scenes/stanford/dragon/dragon.glb" "$OUT/dragon-turntable.glb"
read -r -a scenes <<< "${SCENES:-$S/khronos-samples/BrainStem/glTF-Binary/BrainStem.glb $OUT/dragon-turntable.glb}"
# Each pair: the dacrt way, the Embree way (one process). PAIRS="refit-rebuild ..." chooses.
read -r -a pairs <<< "${PAIRS:-refit-rebuild refit-refit rebuild-rebuild new-new}"
for scene in "${scenes[@]}"; do
  name=$(basename "$scene" .glb)
  for run in $(seq "$RUNS"); do
    for pair in "${pairs[@]}"; do
      set -- ${pair/-/ }
      "$BIN" render "$scene" --width 1920 --height 1080 --spp "$SPP" --quiet \
        --frames "0:$FRAMES" --fps 12 --backend dacrt,embree \
        --backend-option "dacrt.frames=$1" --backend-option "embree.frames=$2" \
        -o "$OUT/$name.exr" --stats "$OUT/$name.$1-$2.$run.json" > /dev/null  # (the table)
    done
  done
done
python3 - "$OUT" "$RUNS" "${pairs[*]}" "${scenes[@]}" <<'PY'
import json, os, statistics, sys
out, runs, scenes = sys.argv[1], int(sys.argv[2]), sys.argv[4:]
pairs = [tuple(p.split("-")) for p in sys.argv[3].split()]
print("| scene | dacrt frames= | embree frames= | pose ms | dacrt update or build ms | "
      "dacrt render s | dacrt frame s | embree update or build ms | embree render s | "
      "embree frame s | dacrt frame / embree frame |")
print("|---|---|---|---|---|---|---|---|---|---|---|")
for scene in scenes:
    name = os.path.splitext(os.path.basename(scene))[0]
    for d, e in pairs:
        q = {k: [] for k in ("pose", "dprep", "drender", "dframe", "eprep", "erender", "eframe")}
        for run in range(1, runs + 1):
            frames = json.load(open(f"{out}/{name}.{d}-{e}.{run}.json"))["frames"]
            for f in frames[1:]:  # the first frame is the load
                q["pose"].append(f["geometry_seconds"])
                for b in f["backends"]:
                    k = "d" if b["backend"] == "dacrt" else "e"
                    prep = b["update_seconds"] + b["build_seconds"]
                    q[k + "prep"].append(prep)
                    q[k + "render"].append(b["seconds_with_build"] - prep)
                    q[k + "frame"].append(f["geometry_seconds"] + b["seconds_with_build"])
        m = {k: statistics.median(v) for k, v in q.items()}
        print(f"| {name} | {d} | {e} | {1e3 * m['pose']:.0f} | {1e3 * m['dprep']:.0f} | "
              f"{m['drender']:.2f} | {m['dframe']:.2f} | {1e3 * m['eprep']:.0f} | "
              f"{m['erender']:.2f} | {m['eframe']:.2f} | {m['dframe'] / m['eframe']:.2f} |")
PY
