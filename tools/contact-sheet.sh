#!/bin/bash
# Renders every scene of ../shared/scenes (with its first camera, or framed when it has none) and
# tiles the sRGB previews, labelled, into docs/contact-sheet.jpg for the README. A maintainer's
# tool: it needs ImageMagick's montage (installed when missing) and a built build/dacrt.
#   tools/contact-sheet.sh [SPP]        (default 64 samples per pixel, 256 × 256 pixels each)
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
scenes=${SCENES:-$root/../shared/scenes}
out=$root/out/contact-sheet
spp=${1:-64}
[ -d "$scenes" ] || { echo "contact-sheet: $scenes is absent" >&2; exit 1; }
command -v montage > /dev/null || "$root/tools/install-deps.sh" imagemagick
mkdir -p "$out"
rm -f "$out"/*.png
while IFS= read -r file; do
  name=$(basename "${file%.*}")
  # Scenes that emit light default to a black sky; a uniform one shows their shapes. The Cornell
  # box is lit from inside and keeps its black sky.
  sky=(--environment 1,1,1)
  [[ $name == CornellBox* ]] && sky=()
  start=$(date +%s.%N)
  "$root/build/dacrt" render "$file" -o "$out/$name.exr" --preview "$out/$name.png" \
    --width 256 --height 256 --spp "$spp" --quiet "${sky[@]}"
  printf '%-40s %6.1f s\n' "${file#"$scenes"/}" "$(echo "$(date +%s.%N) - $start" | bc)"
done < <(find "$scenes" \( -name '*.gltf' -o -name '*.glb' \) | sort)
montage -label '%t' "$out"/*.png -tile 6x -geometry 256x256+3+3 -pointsize 14 \
  -background "#202020" -fill white -quality 85 "$root/docs/contact-sheet.jpg"
echo "wrote docs/contact-sheet.jpg"
