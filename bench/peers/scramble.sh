#!/usr/bin/env bash
# Shift against scramble at equal CPU time, against Mitsuba 3 (static diffuse sphere) and
# Blender Cycles (the sphere moving during a box shutter): BENCHMARKS.md "Peers",
# docs/benchmarks/scramble.md. Optional tooling: not part of the tests, not run by CI.
#
#   bash bench/peers/scramble.sh [mitsuba|cycles|both] [options of scramble.py / scramble_cycles.py]
#
# Private venvs under ${BLURLAB_PEERS2_CACHE:-~/.cache/blurlab-peers2}: `venv` (mitsuba, numpy)
# and `cycles-venv` (bpy 5.2, numpy; bpy needs Python 3.13: set PYTHON313, default pyenv's
# 3.13.0). Mitsuba's llvm_ad_rgb needs Debian's libllvm19 (installed when missing, as run.sh).
# Run it under `nice -n 19` on a shared machine: the figures are CPU times, which niceness
# does not change.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
repo="$(cd "$here/../.." && pwd)"
cache="${BLURLAB_PEERS2_CACHE:-${XDG_CACHE_HOME:-$HOME/.cache}/blurlab-peers2}"
which="${1:-both}"
[ $# -gt 0 ] && shift
mkdir -p "$cache"

export CARGO_TARGET_DIR="${CARGO_TARGET_DIR:-$repo/target}"
(cd "$repo" && cargo build --release --quiet -p renderer --example sample_cost)
bin="$CARGO_TARGET_DIR/release/examples"

if [ "$which" = mitsuba ] || [ "$which" = both ]; then
  source "$here/llvm19.sh"
  [ -x "$cache/venv/bin/python" ] || python3 -m venv "$cache/venv"
  "$cache/venv/bin/pip" install --quiet --disable-pip-version-check 'mitsuba>=3.9,<4' numpy
  # Mitsuba's warnings (the orthogonal sampler rounds 16 spp up to 25) go to stdout too.
  "$cache/venv/bin/python" "$here/scramble.py" --bin "$bin" --cache "$cache" "$@" \
    | sed -n '/^{$/,/^}$/p'
fi

if [ "$which" = cycles ] || [ "$which" = both ]; then
  if [ ! -x "$cache/cycles-venv/bin/python" ]; then
    py="${PYTHON313:-}"
    if [ -z "$py" ]; then py="$(PYENV_VERSION=3.13.0 pyenv which python 2>/dev/null || command -v python3.13)"; fi
    "$py" -m venv "$cache/cycles-venv"
  fi
  "$cache/cycles-venv/bin/pip" install --quiet --disable-pip-version-check 'bpy>=5.2,<5.3' numpy
  # Blender prints its render progress on stdout: the report is the last JSON object.
  "$cache/cycles-venv/bin/python" "$here/scramble_cycles.py" --bin "$bin" --cache "$cache" "$@" \
    | sed -n '/^{$/,/^}$/p'
fi
