#!/usr/bin/env bash
# Compare the suite with Embree 4 (pip `embreex`) and Mitsuba 3 (pip `mitsuba`, `llvm_ad_rgb`)
# on matched workloads, one thread each, CPU time, interleaved rounds: see BENCHMARKS.md, "Peers",
# and docs/benchmarks/peers.md. Optional tooling: not part of the tests, not run by CI.
#
#   bash bench/peers/run.sh [--rounds N] [--skip-embree] [--skip-mitsuba]
#
# Installs nothing system-wide except, when missing, Debian's libllvm19 (Mitsuba's LLVM backend
# refuses LLVM 14 and crashes with 15); the Python packages go to a private venv under
# ${BLURLAB_PEERS_CACHE:-~/.cache/blurlab-peers}. Scratch files go there too.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
repo="$(cd "$here/../.." && pwd)"
cache="${BLURLAB_PEERS_CACHE:-${XDG_CACHE_HOME:-$HOME/.cache}/blurlab-peers}"
mkdir -p "$cache"

source "$here/llvm19.sh"

if [ ! -x "$cache/venv/bin/python" ]; then
  python3 -m venv "$cache/venv"
fi
"$cache/venv/bin/pip" install --quiet --disable-pip-version-check 'embreex>=4.4,<5' 'mitsuba>=3.9,<4' numpy

export CARGO_TARGET_DIR="${CARGO_TARGET_DIR:-$repo/target}"
(cd "$repo" && cargo build --release --quiet -p renderer --example trace_rays --example sample_cost)
# One thread everywhere: the suite's examples use a one-thread pool; Embree's and Dr.Jit's
# pools are limited in peers.py.
exec "$cache/venv/bin/python" "$here/peers.py" --bin "$CARGO_TARGET_DIR/release/examples" --cache "$cache" "$@"
