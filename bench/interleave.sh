#!/bin/bash
# CPU time per camera sample of two builds of `sample_cost`, alternated round by round so that
# the host's changing speed falls on both alike (issue 30's method; docs/benchmarks/lanes.md).
#
#   bash bench/interleave.sh ROUNDS BASE_DIR BASE_SAMPLE_COST NEW_DIR NEW_SAMPLE_COST
#
# Each *_DIR is a checkout whose scenes/thesis/ the binary reads (run from there). Per round and
# scene it prints the base's and the new build's ns per sample (best of `--rounds 2`), their
# ratio and the load average; take the median ratio over the rounds.
set -euo pipefail
if [ $# -ne 5 ]; then
  sed -n '2,10p' "$0" >&2
  exit 2
fi
rounds=$1 base_dir=$2 base_bin=$3 new_dir=$4 new_bin=$5
ns() {
  (cd "$1" && nice -n 10 "$2" "$3" --frame "$4" --spp 4 --rounds 2 2>&1 |
    awk '/ns_per_sample/ {for (i = 1; i <= NF; i++) if ($i == "ns_per_sample") print $(i + 1)}' |
    sort -g | head -1)
}
for _ in $(seq 1 "$rounds"); do
  for case in "scenes/thesis/spheres.json 100" "scenes/thesis/plane.json 93"; do
    set -- $case
    a=$(ns "$base_dir" "$base_bin" "$1" "$2")
    b=$(ns "$new_dir" "$new_bin" "$1" "$2")
    ratio=$(awk -v a="$a" -v b="$b" 'BEGIN {printf "%.4f", b / a}')
    echo "$(basename "$1" .json) $a $b $ratio load $(cut -d' ' -f1 /proc/loadavg)"
  done
done
