#!/usr/bin/env bash
# The AVX2 build (x86-64-v3 without FMA) against the default build of this checkout: the same
# bytes, and the time per camera sample (BENCHMARKS.md, "Lanes chosen at run time").
#
#   bash bench/avx2.sh WORK_DIR [ROUNDS]
#
# Builds `blurlab` and the `sample_cost` example both ways (target dirs WORK_DIR/base and
# WORK_DIR/avx2), then: the demo's outputs hashed with each (bench/demo_hashes.sh), frame 93 of
# both thesis scenes at their own 768 x 768 and 64 spp hashed with each (PNG and EXR), and ROUNDS
# (default 5) alternated timings (bench/interleave.sh). Exits non-zero if any byte differs.
# Needs scenes/thesis/data/CedarCity.hdr (scenes/README.md) and an x86-64 CPU with AVX2.
set -euo pipefail
if [ $# -lt 1 ]; then
  sed -n '2,11p' "$0" >&2
  exit 2
fi
work=$(realpath -m "$1") rounds=${2:-5}
cd "$(dirname "$0")/.."
grep -qw avx2 /proc/cpuinfo || { echo "this CPU has no AVX2" >&2; exit 1; }
declare -A flags=([base]="" [avx2]="-C target-cpu=x86-64-v3 -C target-feature=-fma")
for build in base avx2; do
  for what in "-p blurlab --bin blurlab" "-p renderer --example sample_cost"; do
    # shellcheck disable=SC2086 # `what` is two flags and their values
    RUSTFLAGS="${flags[$build]}" CARGO_TARGET_DIR="$work/$build" cargo build --quiet --release $what
  done
done
for build in base avx2; do
  export BLURLAB="$work/$build/release/blurlab"
  bash bench/demo_hashes.sh > "$work/$build.demo.sha"
  bash bench/thesis_frames.sh "$work/$build.frames" > "$work/$build.frames.sha"
done
rm -rf results/demo stimuli/demo
diff "$work/base.demo.sha" "$work/avx2.demo.sha"
diff "$work/base.frames.sha" "$work/avx2.frames.sha"
echo "identical: $(wc -l < "$work/base.demo.sha") demo files, $(wc -l < "$work/base.frames.sha") thesis frames"
bash bench/interleave.sh "$rounds" . "$work/base/release/examples/sample_cost" \
  . "$work/avx2/release/examples/sample_cost"
