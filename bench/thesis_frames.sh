#!/usr/bin/env bash
# Frame 93 of both thesis scenes at their own 768 x 768 and 64 spp (PNG and EXR), rendered by
# $BLURLAB into DIR, and their sha256 sums on stdout (bench/avx2.sh, bench/lanes.sh).
#
#   BLURLAB=path/to/blurlab bash bench/thesis_frames.sh DIR
set -euo pipefail
out=$(realpath -m "$1")
cd "$(dirname "$0")/.."
for scene in plane spheres; do
  rm -rf "${out:?}/$scene"
  "$BLURLAB" render scene "scenes/thesis/$scene.json" --frames 93 --exr --out "$out/$scene" \
    --no-progress > /dev/null
done
(cd "$out" && find . -type f \( -name '*.png' -o -name '*.exr' \) -print0 | sort -z |
  xargs -0 sha256sum)
