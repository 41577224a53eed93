#!/usr/bin/env bash
# One change's render time on the textured scenes: an older dacrt binary (BEFORE) and this one
# (BIN) render DamagedHelmet and the Sponza atrium from their framing cameras under the default
# sky, alternating, RUNS times each; a Markdown table gives each binary's median render seconds
# (the statistics' render_seconds) and user CPU seconds (the whole process, from /usr/bin/time:
# steadier than wall time on a loaded machine), and their ratios after / before (lower is faster).
# The last run's two images are compared too: "same" when every pixel is equal (dacrt diff).
#   BEFORE=/path/to/old/dacrt tools/before-after.sh [WIDTH] [SPP] [RUNS]   (default 1024 64 3)
# BIN (default build/dacrt), THREADS (default 2), SCENES (default ../shared/scenes beside the
# checkout), OUT (default /tmp/dacrt-before-after: the images and statistics stay there); FILES
# (glTF files, separated by spaces) renders those instead of the two scenes; VIEWS (names of
# tools/peer-compare.sh's views, separated by spaces, e.g. "helmet sponza-inside") renders those
# views first, each with its own camera, size, spp and sky and peer-compare's depth 64 (WIDTH and
# SPP are then only for FILES, and the two scenes are left out unless FILES names them).
set -euo pipefail
cd "$(dirname "$0")/.."
W=${1:-1024}; SPP=${2:-64}; RUNS=${3:-3}
BIN=${BIN:-build/dacrt}; THREADS=${THREADS:-2}
S=${SCENES:-../shared/scenes}
OUT=${OUT:-/tmp/dacrt-before-after}; mkdir -p "$OUT"
[ -n "${BEFORE:-}" ] && [ -x "$BEFORE" ] || { echo "before-after: set BEFORE to an older dacrt binary" >&2; exit 2; }
[ -x "$BIN" ] || { echo "before-after: $BIN not built" >&2; exit 1; }
scenes=("$S/khronos/DamagedHelmet/DamagedHelmet.glb" "$S/mcguire/dabrovic-sponza/sponza.glb")
[ -n "${VIEWS:-}" ] && scenes=()
[ -n "${FILES:-}" ] && read -ra scenes <<< "$FILES"
# Each case: a name and its render options (a view's from peer-compare, a file's from WIDTH, SPP).
names=(); options=()
for view in ${VIEWS:-}; do
  line=$(SCENES=$S tools/peer-compare.sh --views | grep "^$view: ") ||
    { echo "before-after: no view '$view' (tools/peer-compare.sh --views lists them)" >&2; exit 2; }
  names+=("$view"); options+=("${line#*: } --max-depth 64")
done
for scene in "${scenes[@]}"; do
  name=$(basename "$scene"); names+=("${name%.*}")
  options+=("$scene --width $W --height $W --spp $SPP")
done
what="${W}², $SPP spp"; [ -n "${VIEWS:-}" ] && what="views: their own size and spp; files: $what"
echo "| scene, $what, $THREADS threads | before render s | after render s | after / before | before user s | after user s | after / before (user) | images |"
echo "|---|---|---|---|---|---|---|---|"
for c in "${!names[@]}"; do
  name=${names[$c]}
  read -ra opts <<< "${options[$c]}"  # (no spaces inside paths or values)
  for run in $(seq "$RUNS"); do
    for which in before after; do
      bin=$BIN; [ $which = before ] && bin=$BEFORE
      /usr/bin/time -f %U -o "$OUT/$name.$which.$run.user" "$bin" render "${opts[@]}" \
        --threads "$THREADS" --quiet -o "$OUT/$name.$which.exr" --stats "$OUT/$name.$which.$run.json"
    done
  done
  same=$("$BIN" diff "$OUT/$name.before.exr" "$OUT/$name.after.exr" --json | python3 -c \
    'import json,sys; print("same" if json.load(sys.stdin)["metrics"]["RGB"]["max_abs"] == 0 else "differ")')
  python3 - "$OUT" "$name" "$RUNS" "$same" <<'PY'
import json, statistics, sys
out, name, runs, same = sys.argv[1], sys.argv[2], int(sys.argv[3]), sys.argv[4]
def med(which, what):
    v = []
    for r in range(1, runs + 1):
        if what == 'user':
            v.append(float(open(f'{out}/{name}.{which}.{r}.user').read().split()[-1]))
        else:
            v.append(json.load(open(f'{out}/{name}.{which}.{r}.json'))['render_seconds'])
    return statistics.median(v)
b, a, bu, au = med('before', 'r'), med('after', 'r'), med('before', 'user'), med('after', 'user')
print(f'| {name} | {b:.2f} | {a:.2f} | {a / b:.2f} | {bu:.2f} | {au:.2f} | {au / bu:.2f} | {same} |')
PY
done
