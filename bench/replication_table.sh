#!/usr/bin/env bash
# The replication table of docs/replication.md (issue 26), section 3: every `blurlab predict`
# and `blurlab predict frames` behind its rows, run on the 768 x 768 stimulus sets that
# scenes/jobs/thesis_*.json render, then the rows printed as Markdown on stdout.
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
# Needs jq (the playback rows' designs are the committed ones with playback.fps / loops set).
# A set that is not rendered prints as "not rendered"; which job renders it is in
# docs/replication.md. The predictions are the observer model's as built into BLURLAB.
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

# variant NAME PLAY: the committed design NAME played at PLAY (a rate in fps, or loops2: its
# own rate twice), as a file in OUT.
variant() {
    local file=$OUT/designs/$1_$2.json filter=".playback.fps = $2"
    [[ $2 == loops2 ]] && filter='.playback.loops = 2'
    mkdir -p "$OUT/designs"
    jq "$filter" "scenes/designs/$1.json" >"$file"
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

# --- Viewing distance: the stand-in sky, frames 20, 93, 105, 150, 190 (all three point sets).
STANDIN=(f093:thesis_full_f093 f020_stratified:thesis_full_f020_stratified
    f105_stratified:thesis_full_f105 f150_stratified:thesis_full_f150_stratified
    f190_stratified:thesis_full_f190_stratified f020_hp:thesis_full_f020_hp
    f105_hp:thesis_full_f105_hp f150_hp:thesis_full_f150_hp f190_hp:thesis_full_f190_hp)
declare -A POOLED F093
for d in 0.6 0.7 1.0; do
    dirs=()
    for s in "${STANDIN[@]}"; do
        predict "$OUT/d$d/${s%%:*}" "${s#*:}" "scenes/designs/${s#*:}.json" --distance-m "$d"
        dirs+=("$OUT/d$d/${s%%:*}")
    done
    POOLED[$d]=$(frames "${dirs[@]}")
    F093[$d]=$(frames "$OUT/d$d/f093")
done

# --- Real sky (--asset CedarCity.hdr=...): frames 93 and 150, beside the stand-in's same frames.
# Stratified of both scenes, Hammersley and Poisson of the plane (spheres: not rendered).
for f in 093 150; do
    for s in full_f${f}_real_sky_stratified plane_f${f}_real_sky_hp; do
        predict "$OUT/real_sky/$s" "thesis_$s" "scenes/designs/thesis_$s.json"
    done
done
R=$OUT/real_sky
REAL=$(frames "$R/full_f093_real_sky_stratified" "$R/plane_f093_real_sky_hp" \
    "$R/full_f150_real_sky_stratified" "$R/plane_f150_real_sky_hp")
REAL93=$(frames "$R/full_f093_real_sky_stratified" "$R/plane_f093_real_sky_hp")
REAL150=$(frames "$R/full_f150_real_sky_stratified" "$R/plane_f150_real_sky_hp")
STAND=$(frames "$OUT/d0.7/f093" "$OUT/d0.7/f150_stratified" "$OUT/d0.7/f150_hp")
STAND150=$(frames "$OUT/d0.7/f150_stratified" "$OUT/d0.7/f150_hp")

# --- Playback and shift scope: the plane's crossing, frames 91-96 as one 6-frame video.
declare -A TEMPORAL
for scope in frame sequence; do
    for sets in hammersley sp; do
        set=thesis_plane_f091_096_${sets}_$scope
        for play in 30 15 8.33 loops2; do
            design=scenes/designs/$set.json
            [[ $play == 30 ]] || design=$(variant "$set" "$play")
            predict "$OUT/temporal/$scope/$sets/$play" "$set" "$design"
        done
    done
    for play in 30 15 8.33 loops2; do
        TEMPORAL[$scope/$play]=$(frames "$OUT/temporal/$scope/hammersley/$play" "$OUT/temporal/$scope/sp/$play")
    done
done

# --- Other readings of Figure 13: the crossing frame 93, stratified.
for r in diagonal_fov half_angle_fov; do
    predict "$OUT/readings/$r" "thesis_plane_f093_$r" "scenes/designs/thesis_plane_f093_$r.json"
done

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
for r in diagonal_fov half_angle_fov; do
    t=$(frames "$OUT/readings/$r")
    echo "| reading '${r//_/ }', 0.7 m, frame 93 | - / - / $(cell "$t" plane-stratified-truncated_box 1) | - |"
done
echo
echo "Tables behind the rows (pooled = d' pooled over the frames; most visible frame last):"
for d in 0.6 0.7 1.0; do printf '\n%s m, stand-in sky:\n\n%s\n' "$d" "${POOLED[$d]}"; done
printf '\nreal sky:\n\n%s\n' "$REAL"
