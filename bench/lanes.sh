#!/usr/bin/env bash
# The packet path's two lane widths in one default build: SSE2 (`BLURLAB_LANES=sse2`) against
# AVX2 (chosen at run time where the CPU has it; renderer/src/simd/). The same bytes, no AVX
# intrinsic left out of line, and the time per camera sample (BENCHMARKS.md, "Lanes chosen at
# run time").
#
#   bash bench/lanes.sh WORK_DIR [ROUNDS]
#
# Builds `blurlab` and the `sample_cost` example (target dir WORK_DIR/build), then: fails if the
# example calls an AVX intrinsic as a function (a lane operation that did not inline into the
# AVX2 entry runs, right but slowly, as a call); the demo's outputs hashed with each width
# (bench/demo_hashes.sh); frame 93 of both thesis scenes at their own 768 x 768 and 64 spp
# hashed with each (PNG and EXR); ROUNDS (default 5) alternated timings (bench/interleave.sh,
# SSE2 first). Exits non-zero if any byte differs. Needs scenes/thesis/data/CedarCity.hdr
# (scenes/README.md) and an x86-64 CPU with AVX2.
set -euo pipefail
if [ $# -lt 1 ]; then
  sed -n '2,15p' "$0" >&2
  exit 2
fi
work=$(realpath -m "$1") rounds=${2:-5}
cd "$(dirname "$0")/.."
grep -qw avx2 /proc/cpuinfo || { echo "this CPU has no AVX2" >&2; exit 1; }
for what in "-p blurlab --bin blurlab" "-p renderer --example sample_cost"; do
  # shellcheck disable=SC2086 # `what` is two flags and their values
  CARGO_TARGET_DIR="$work/build" cargo build --quiet --release $what
done
bin="$work/build/release"
calls=$(objdump -d --no-show-raw-insn "$bin/examples/sample_cost" |
  grep -cE 'call.*core_arch.*(x863avx|x864avx2)' || true)
if [ "$calls" != 0 ]; then
  echo "$calls calls to AVX intrinsics out of line: a lane function is not inlined" >&2
  exit 1
fi
export BLURLAB="$bin/blurlab"
for width in sse2 auto; do
  BLURLAB_LANES=$width bash bench/demo_hashes.sh > "$work/$width.demo.sha"
  BLURLAB_LANES=$width bash bench/thesis_frames.sh "$work/$width.frames" > "$work/$width.frames.sha"
done
rm -rf results/demo stimuli/demo
diff "$work/sse2.demo.sha" "$work/auto.demo.sha"
diff "$work/sse2.frames.sha" "$work/auto.frames.sha"
echo "identical: $(wc -l < "$work/sse2.demo.sha") demo files, $(wc -l < "$work/sse2.frames.sha") thesis frames"
printf '#!/bin/sh\nBLURLAB_LANES=sse2 exec %s "$@"\n' "$bin/examples/sample_cost" > "$work/sse2_sample_cost"
chmod +x "$work/sse2_sample_cost"
bash bench/interleave.sh "$rounds" . "$work/sse2_sample_cost" . "$bin/examples/sample_cost"
