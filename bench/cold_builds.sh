#!/usr/bin/env bash
# Cold builds of one commit (issue 15; BENCHMARKS.md, "Tests and CI"): a clone
# of this repository at <commit>, then each command below from an empty target folder, one
# after another, with CPU (user + sys) and wall time written to $work/<label>.txt.
#   bash bench/cold_builds.sh <commit> <label>      # work folder: ${BLURLAB_COLD:-/tmp/blurlab-cold}
set -uo pipefail
commit=$1
label=$2
repo="$(cd "$(dirname "$0")/.." && pwd)"
work="${BLURLAB_COLD:-/tmp/blurlab-cold}"
src="$work/src_$label"
export CARGO_TARGET_DIR="$work/target_$label"
out="$work/$label.txt"
mkdir -p "$work"
rm -rf "$src" "$CARGO_TARGET_DIR"
git clone -q "$repo" "$src" && cd "$src" && git checkout -q "$commit" || exit 1
: > "$out"
run() {
    local name=$1
    shift
    rm -rf "$CARGO_TARGET_DIR"
    local load
    load=$(cut -d' ' -f1-3 /proc/loadavg)
    /usr/bin/time -f "$name wall %e s user %U s sys %S s" -o "$work/time_$label" "$@" \
        > "$work/${label}_$name.log" 2>&1
    echo "$(cat "$work/time_$label") rc=$? load_start=$load load_end=$(cut -d' ' -f1-3 /proc/loadavg)" >> "$out"
}
run analysis_release cargo build --release -p analysis
run analysis_debug cargo build -p analysis
run build_release cargo build --release
run test_workspace cargo test --workspace
rm -rf "$CARGO_TARGET_DIR"
cat "$out"
