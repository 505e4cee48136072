#!/usr/bin/env bash
# Hashes of every file the demo writes that carries no wall-clock time: frames (PNG, EXR),
# session logs, the report's CSV, JSON, Markdown and figures, the prediction's tables. The
# files left out hold timings (frame records' and the manifest's render seconds, the
# convergence tables and plots against seconds, the summary's and predict.md's run times).
# Used to show that a restructuring changed no output byte (issue 15):
#   bash bench/demo_hashes.sh > /tmp/before.sha   # on the old commit
#   bash bench/demo_hashes.sh > /tmp/after.sha    # on the new one
#   diff /tmp/before.sha /tmp/after.sha && echo identical
# BLURLAB=path/to/blurlab runs that binary instead of `cargo run` (two builds of one commit).
set -euo pipefail
cd "$(dirname "$0")/.."
rm -rf results/demo stimuli/demo
if [ -n "${BLURLAB:-}" ]; then
  "$BLURLAB" demo --no-progress > /dev/null 2>&1
else
  cargo run --quiet -- demo --no-progress > /dev/null 2>&1
fi
find results/demo stimuli/demo -type f \
    ! -name 'frame_*.json' ! -name manifest.json ! -name summary.md ! -name predict.md \
    ! -path '*/convergence/*' -print0 | sort -z | xargs -0 sha256sum
