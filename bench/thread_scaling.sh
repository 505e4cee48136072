#!/bin/bash
# Wall clock of `blurlab render scene` on one rayon thread against two, for two builds alternated
# (issue 30's 2-thread scaling: 192 x 192, 64 spp, 8 frames of each thesis scene).
#
#   bash bench/thread_scaling.sh ROUNDS BASE_BLURLAB NEW_BLURLAB > runs.txt
#
# Run from a checkout (it reads scenes/thesis/). Prints one line per run:
# scene build threads wall_s user_s sys_s (GNU time, 10 ms resolution). The scaling is
# wall(1 thread) / wall(2 threads) per round; take the median over the rounds, and
# (user + sys) / (2 x wall) of the 2-thread runs for how busy the two cores were.
set -euo pipefail
if [ $# -ne 3 ]; then
  sed -n '2,10p' "$0" >&2
  exit 2
fi
rounds=$1 base=$2 new=$3
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
for _ in $(seq 1 "$rounds"); do
  for case in "plane 93..101" "spheres 100..108"; do
    set -- $case
    for build in base new; do
      bin=$base
      [ "$build" = new ] && bin=$new
      for threads in 1 2; do
        RAYON_NUM_THREADS=$threads /usr/bin/time -o "$out/time" -f "%e %U %S" "$bin" render scene \
          "scenes/thesis/$1.json" --spp 64 --width 192 --height 192 --frames "$2" \
          --out "$out/frames" --no-progress > /dev/null 2>&1
        echo "$1 $build $threads $(tail -1 "$out/time")"
      done
    done
  done
done
