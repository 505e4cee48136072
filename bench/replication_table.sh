#!/usr/bin/env bash
# The replication table of docs/replication.md, section 3: every `blurlab predict` and
# `blurlab predict frames` behind its rows, run on the 768 x 768 stimulus sets of the sweep
# (scenes/replication/sweep.txt: the lines for distance, sky, playback and reading, written as
# jobs and designs by bench/replication_sets.sh), then the rows printed as Markdown on stdout.
#
#   bash bench/replication_table.sh [STIMULI [OUT]]
#
# STIMULI  the folder `blurlab render job ... --out` wrote the sets into (default: stimuli;
#          relative paths are taken from the repository's root, where the script runs)
# OUT      where the predictions go (default: $STIMULI/replication_table). A prediction whose
#          predicted.csv exists is reused, so a second run only prints: use a new OUT after the
#          observer model changes.
# BLURLAB  the blurlab binary (default: blurlab on PATH); NICE its niceness (default 15).
#
# Needs jq (the playback rows' designs are the sets' own with playback.fps / loops set). A set
# that is not rendered prints as "not rendered"; how to render them: docs/replication.md. The predictions are the observer model's as built into BLURLAB.
set -euo pipefail
cd "$(dirname "$0")/.."
STIMULI=${1:-stimuli}
OUT=${2:-$STIMULI/replication_table}
BLURLAB=${BLURLAB:-blurlab}
NICE=${NICE:-15}
mkdir -p "$OUT"

# predict OUT_DIR SET DESIGN_FILE [ARGS...]: one prediction, skipped when done or not rendered.
predict() {
    local out=$1 set=$2 design=$3
    shift 3
    [[ -e $STIMULI/$set/manifest.json && ! -e $out/predicted.csv ]] || return 0
    echo "predict $set -> $out $*" >&2
    nice -n "$NICE" "$BLURLAB" predict "$STIMULI/$set" --design "$design" --out "$out" \
        --no-progress "$@" >/dev/null
}

# variant NAME PLAY: the design of set NAME played at PLAY (a rate in fps, or loops2: its own
# rate twice), as a file in OUT.
variant() {
    local file=$SETS/$1/design_$2.json filter=".playback.fps = $2"
    [[ $2 == loops2 ]] && filter='.playback.loops = 2'
    jq "$filter" "$SETS/$1/design.json" >"$file"
    echo "$file"
}

# frames DIR...: `predict frames` over the predictions that exist; prints its table.
frames() {
    local have=()
    for d in "$@"; do [[ -e $d/predicted.csv ]] && have+=("$d"); done
    ((${#have[@]} == 0)) || "$BLURLAB" predict frames "${have[@]}"
}

# cell TABLE CONDITION COLUMN: a JND from a `predict frames` table (COLUMN 1 = pooled, 2 = the
# most visible frame), or "not rendered".
cell() {
    awk -F' [|] ' -v c="$2" -v k="$3" '$1 == "| " c { v = $(NF - 2 + k); sub(/ [|]$/, "", v); print v }' \
        <<<"$1" | grep . || echo "not rendered"
}

# cells TABLE SCENE COLUMN: Hammersley / Poisson / stratified of SCENE.
cells() {
    local out=()
    for p in hammersley poisson stratified; do out+=("$(cell "$1" "$2-$p-truncated_box" "$3")"); done
    echo "${out[0]} / ${out[1]} / ${out[2]}"
}

# The sweep's lines for question $1, each "name frames scenes point_sets scenes_from shifts
# reference for" (scenes/replication/sweep.txt).
rows_for() {
    awk -v q="$1" '{ n = split($8, f, ","); for (i = 1; i <= n; i++) if (f[i] == q) print }' <<<"$ROWS"
}
ROWS=$(bash bench/replication_sets.sh --rows)
SETS=$OUT/sets
STIMULI=$STIMULI bash bench/replication_sets.sh "$SETS" >/dev/null

# --- Viewing distance: the stand-in sky, frames 20, 93, 105, 150, 190 (all three point sets).
declare -A POOLED F093
for d in 0.6 0.7 1.0; do
    dirs=() f93=()
    while read -r name frames _; do
        predict "$OUT/$name/d$d" "$name" "$SETS/$name/design.json" --distance-m "$d"
        dirs+=("$OUT/$name/d$d")
        [[ $frames != 93 ]] || f93+=("$OUT/$name/d$d")
    done < <(rows_for distance)
    POOLED[$d]=$(frames "${dirs[@]}")
    F093[$d]=$(frames "${f93[@]}")
done

# --- Real sky (--asset CedarCity.hdr=...): frames 93 and 150, beside the stand-in's same frames
# (their predictions at 0.7 m above).
stand=() stand150=() real=() real93=() real150=()
while read -r name frames _ _ from _; do
    if [[ $from == thesis ]]; then
        predict "$OUT/$name/d0.7" "$name" "$SETS/$name/design.json" --distance-m 0.7
        stand+=("$OUT/$name/d0.7")
        [[ $frames != 150 ]] || stand150+=("$OUT/$name/d0.7")
    else
        predict "$OUT/$name/design" "$name" "$SETS/$name/design.json"
        real+=("$OUT/$name/design")
        [[ $frames != 93 ]] || real93+=("$OUT/$name/design")
        [[ $frames != 150 ]] || real150+=("$OUT/$name/design")
    fi
done < <(rows_for sky)
REAL=$(frames "${real[@]}")
REAL93=$(frames "${real93[@]}")
REAL150=$(frames "${real150[@]}")
STAND=$(frames "${stand[@]}")
STAND150=$(frames "${stand150[@]}")

# --- Playback and shift scope: the plane's crossing, frames 91-96 as one 6-frame video.
declare -A TEMPORAL
for scope in frame sequence; do
    for play in 30 15 8.33 loops2; do
        dirs=()
        while read -r name _ _ _ _ shifts _; do
            [[ $shifts == "$scope" ]] || continue
            design=$SETS/$name/design.json
            [[ $play == 30 || ! -e $STIMULI/$name/manifest.json ]] || design=$(variant "$name" "$play")
            predict "$OUT/$name/$play" "$name" "$design"
            dirs+=("$OUT/$name/$play")
        done < <(rows_for playback)
        TEMPORAL[$scope/$play]=$(frames "${dirs[@]}")
    done
done

# --- Other readings of Figure 13: the crossing frame 93, stratified.
readings=() reading_tables=()
while read -r name _ _ _ from _; do
    predict "$OUT/$name/design" "$name" "$SETS/$name/design.json"
    readings+=("$from")
    reading_tables+=("$(frames "$OUT/$name/design")")
done < <(rows_for reading)

# --- The rows.
echo "| row | plane H / P / S | spheres H / P / S |"
echo "|---|---|---|"
for d in 0.6 0.7 1.0; do
    echo "| stand-in sky, ${d} m, pooled over frames 20/93/105/150/190 | $(cells "${POOLED[$d]}" plane 1) | $(cells "${POOLED[$d]}" spheres 1) |"
    echo "| stand-in sky, ${d} m, frame 93 | $(cells "${F093[$d]}" plane 1) | $(cells "${F093[$d]}" spheres 1) |"
done
echo "| stand-in sky, 0.7 m, pooled over frames 93/150 | $(cells "$STAND" plane 1) | $(cells "$STAND" spheres 1) |"
echo "| real sky, 0.7 m, pooled over frames 93/150 | $(cells "$REAL" plane 1) | $(cells "$REAL" spheres 1) |"
echo "| real sky, 0.7 m, frame 93 | $(cells "$REAL93" plane 1) | $(cells "$REAL93" spheres 1) |"
echo "| stand-in sky, 0.7 m, frame 150 | $(cells "$STAND150" plane 1) | $(cells "$STAND150" spheres 1) |"
echo "| real sky, 0.7 m, frame 150 | $(cells "$REAL150" plane 1) | $(cells "$REAL150" spheres 1) |"
for scope in frame sequence; do
    for play in 30 15 8.33 loops2; do
        t=${TEMPORAL[$scope/$play]}
        [[ $play == loops2 ]] && rate="30 fps, 2 loops" || rate="$play fps"
        echo "| frames 91-96 as a video, 0.7 m, shifts per $scope, $rate | $(cells "$t" plane 1) | - |"
    done
done
for i in "${!readings[@]}"; do
    r=${readings[$i]} t=${reading_tables[$i]}
    echo "| reading '${r//_/ }', 0.7 m, frame 93 | - / - / $(cell "$t" plane-stratified-truncated_box 1) | - |"
done
echo
echo "Tables behind the rows (pooled = d' pooled over the frames; most visible frame last):"
for d in 0.6 0.7 1.0; do printf '\n%s m, stand-in sky:\n\n%s\n' "$d" "${POOLED[$d]}"; done
printf '\nreal sky:\n\n%s\n' "$REAL"
