#!/bin/bash
# Renders every model of ../shared/khronos-samples and tiles each render beside the reference
# screenshot its authors published (the model's screenshot/ folder; a GIF's first frame) into
# the labelled contact sheet docs/khronos-sheet.jpg, which docs/gltf.md links and judges model by
# model. A maintainer's tool: it needs ImageMagick's montage (installed when missing) and a built
# build/dacrt (or DACRT=path). Nothing of the samples is copied: the renders go to out/, and the
# screenshots are read where they are.
#   tools/khronos-sheet.sh [SPP]        (default 128 samples per pixel)
# Each model is rendered with its own first camera, else the framing camera, under a uniform sky
# of 1, at time 0 (animated models: the pose of the GIF's first frame; --time 0 is the rest pose
# for the others), 256 pixels wide and as high as its screenshot's aspect asks (within 128–384).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
samples=${SAMPLES:-$root/../shared/khronos-samples}
dacrt=${DACRT:-$root/build/dacrt}
out=$root/out/khronos-sheet
spp=${1:-128}
[ -d "$samples" ] || { echo "khronos-sheet: $samples is absent" >&2; exit 1; }
[ -x "$dacrt" ] || { echo "khronos-sheet: $dacrt is not built (or set DACRT=path)" >&2; exit 1; }
command -v montage > /dev/null || "$root/tools/install-deps.sh" imagemagick
mkdir -p "$out"
rm -f "$out"/*.png "$out"/*.exr "$out"/*.log
tiles=()
while IFS= read -r file; do
  name=$(basename "${file%.*}")
  model=${file#"$samples"/}
  model=${model%%/*}
  shot=$(find "$samples/$model/screenshot" -maxdepth 1 -type f | sort | head -n 1)
  [ -n "$shot" ] || { echo "khronos-sheet: $model has no screenshot" >&2; exit 1; }
  # The screenshot's aspect, for the render's height (a GIF: its first frame; identify finds
  # fault with some JPEGs' XMP packets, harmlessly).
  read -r sw sh < <(identify -format '%w %h\n' "${shot}[0]" 2> /dev/null)
  height=$(((256 * sh + sw / 2) / sw))
  height=$((height < 128 ? 128 : height > 384 ? 384 : height))
  start=$(date +%s.%N)
  "$dacrt" render "$file" -o "$out/$name.exr" --preview "$out/$name.png" --width 256 \
    --height "$height" --spp "$spp" --time 0 --environment 1,1,1 --quiet 2> "$out/$name.log"
  printf '%-28s %6.1f s\n' "$name" "$(echo "$(date +%s.%N) - $start" | bc)"
  sed 's/^/    /' "$out/$name.log"  # warnings, if any
  tiles+=(-label "$name: reference" "${shot}[0]" -label "$name: dacrt" "$out/$name.png")
done < <(find "$samples" \( -name '*.gltf' -o -name '*.glb' \) | sort)
# Three pairs a row, each tile fitted into 256 × 256.
montage "${tiles[@]}" -tile 6x -geometry 256x256+3+3 -pointsize 13 -background "#202020" \
  -font DejaVu-Sans -fill white -quality 82 "$root/docs/khronos-sheet.jpg"
echo "wrote docs/khronos-sheet.jpg ($(du -k "$root/docs/khronos-sheet.jpg" | cut -f1) KB)"
