#!/usr/bin/env bash
# The replication sweep's stimulus sets (docs/replication.md), written from its one table,
# scenes/replication/sweep.txt: per line, a job and the design that plays it.
#
#   bash bench/replication_sets.sh OUT [FOR...]   # OUT/<set>/job.json and design.json; prints the set names
#   bash bench/replication_sets.sh --rows         # the table's lines, each with its set name first
#
# OUT      where the sets go (relative paths are taken from the repository's root, where the
#          script runs); FOR: only the lines for these questions (distance, sky, playback,
#          reading, hold-out).
# STIMULI  the folder the sets are rendered into, for the designs' manifest paths (default:
#          stimuli, where `blurlab render job` writes).
# SWEEP    the table (default scenes/replication/sweep.txt).
#
# Needs only bash and coreutils. A malformed line stops the script with its line number.
set -euo pipefail
cd "$(dirname "$0")/.."
ROOT=$(pwd -P)
SWEEP=${SWEEP:-scenes/replication/sweep.txt}
STIMULI=${STIMULI:-stimuli}
ALL_POINT_SETS=hammersley,stratified,poisson
QUESTIONS=" distance sky playback reading hold-out "

fail() {
    echo "$SWEEP:$LINE: $*" >&2
    exit 1
}

# check FIELD VALUE REGEX EXPECTED
check() {
    [[ $2 =~ ^($3)$ ]] || fail "\`$1\` is \`$2\`; expected $4"
}

# The set's name from its settings (scenes/replication/sweep.txt says how).
name() {
    local n first last
    IFS=- read -r first last <<<"$FRAMES"
    n=thesis_f$(printf %03d "$((10#$first))")
    [[ -z $last ]] || n+=_$(printf %03d "$((10#$last))")
    [[ $SCENES == plane,spheres ]] || n+=_${SCENES//,/_}
    [[ $POINT_SETS == "$ALL_POINT_SETS" ]] || n+=_${POINT_SETS//,/_}
    [[ $FROM == thesis ]] || n+=_$FROM
    [[ $SHIFTS == frame ]] || n+=_shifts_per_$SHIFTS
    [[ $REFERENCE == highest_level ]] || n+=_reference_${REFERENCE/:/_}
    echo "$n"
}

# path DIR FILE: FILE as the set in DIR names it: relative when both are in the repository
# (the sets then move with it), absolute otherwise.
path() {
    local dir file
    dir=$(realpath -m "$1")
    file=$(realpath -m "$2")
    if [[ $dir == "$ROOT"/* && $file == "$ROOT"/* ]]; then
        realpath -m --relative-to="$dir" "$file"
    else
        echo "$file"
    fi
}

# A comma list as JSON strings: a,b -> "a", "b"
quoted() {
    local out="" x
    IFS=, read -ra items <<<"$1"
    for x in "${items[@]}"; do out+="${out:+, }\"$x\""; done
    echo "$out"
}

# parse: the current line's fields, checked.
parse() {
    read -r FRAMES SCENES POINT_SETS FROM SHIFTS REFERENCE FOR EXTRA <<<"$1"
    [[ -n $FOR && -z $EXTRA ]] || fail "7 columns expected (frames scenes point_sets scenes_from shifts reference for)"
    check frames "$FRAMES" '[0-9]+(-[0-9]+)?' "a frame or first-last"
    local first=${FRAMES%-*} last=${FRAMES#*-}
    ((10#$first <= 10#$last)) || fail "\`frames\` $FRAMES: the first frame is after the last"
    check scenes "$SCENES" '(plane|spheres)(,(plane|spheres))*' "plane and/or spheres"
    check point_sets "$POINT_SETS" '[a-z_]+(,[a-z_]+)*' "point set names"
    check scenes_from "$FROM" '[a-z_]+' "thesis or a variant folder of scenes/thesis/"
    check shifts "$SHIFTS" 'frame|sequence' "frame or sequence"
    check reference "$REFERENCE" 'highest_level|[a-z_]+:[0-9]+' "highest_level or point_set:spp"
    local q
    IFS=, read -ra qs <<<"$FOR"
    for q in "${qs[@]}"; do
        [[ $QUESTIONS == *" $q "* ]] || fail "\`for\` names \`$q\`; expected some of:$QUESTIONS"
    done
    local dir=scenes/thesis s
    [[ $FROM == thesis ]] || dir=scenes/thesis/$FROM
    SCENE_FILES=()
    IFS=, read -ra ss <<<"$SCENES"
    for s in "${ss[@]}"; do
        [[ -f $dir/$s.json ]] || fail "\`scenes_from\` $FROM: no $dir/$s.json"
        SCENE_FILES+=("$dir/$s.json")
    done
}

# write DIR NAME: the job and the design of the current line.
write() {
    local dir=$1 name=$2 first=$((10#${FRAMES%-*})) last=$((10#${FRAMES#*-})) scenes="" s
    for s in "${SCENE_FILES[@]}"; do
        scenes+="${scenes:+, }\"$(path "$dir" "$s")\""
    done
    local reference='"highest_level"' design_reference='"highest_level"'
    if [[ $REFERENCE != highest_level ]]; then
        reference="{\"point_set\": \"${REFERENCE%:*}\", \"spp\": ${REFERENCE#*:}, \"time_filter\": \"truncated_box\"}"
        design_reference='"scene_reference"'
    fi
    mkdir -p "$dir"
    cat >"$dir/job.json.tmp" <<JOB
{
  "format": "blurlab-job/1",
  "name": "$name",
  "scenes": [$scenes],
  "levels": [1, 8, 27, 64, 125, 216, 343, 512],
  "point_sets": [$(quoted "$POINT_SETS")],
  "time_filters": ["truncated_box"],
  "reference": $reference,
  "seed": 2013,
  "overrides": {"width": 768, "height": 768, "frames": $((last - first + 1)), "first_frame": $first,
                "sampling": {"point_set_scope": "frame", "shift_scope": "$SHIFTS"}},
  "frames_per_unit": 1
}
JOB
    cat >"$dir/design.json.tmp" <<DESIGN
{
  "format": "blurlab-design/1",
  "name": "$name",
  "manifest": "$(path "$dir" "$STIMULI/$name/manifest.json")",
  "factors": {
    "scenes": [$(quoted "$SCENES")],
    "point_sets": [$(quoted "$POINT_SETS")],
    "time_filters": ["truncated_box"]
  },
  "levels": [1, 8, 27, 64, 125, 216, 343, 512],
  "reference": $design_reference,
  "repeats": 4,
  "layout": "sequential",
  "playback": {"loops": 1, "fixation_ms": 500, "gap_ms": 1000, "spacing_px": 32, "background": [0, 0, 0]},
  "break_every": 48,
  "keys": {"pair1": ["1", "ArrowLeft"], "pair2": ["2", "ArrowRight"]},
  "seed": {"master": 2013, "scheme": "per_subject"},
  "display": {"diagonal_inches": 23, "resolution": [1920, 1080], "distance_m": 0.7,
              "peak_cd_m2": 300, "black_cd_m2": 0.3}
}
DESIGN
    mv "$dir/job.json.tmp" "$dir/job.json"
    mv "$dir/design.json.tmp" "$dir/design.json"
}

# wanted: whether the current line answers one of the requested questions (all without any).
wanted() {
    (($# == 0)) && return 0
    local q
    for q in "$@"; do [[ ,$FOR, == *",$q,"* ]] && return 0; done
    return 1
}

[[ $# -ge 1 ]] || {
    sed -n '4,5p' "$0" | sed 's/^# *//' >&2
    exit 2
}
MODE=$1
shift
[[ -f $SWEEP ]] || {
    echo "no table $SWEEP" >&2
    exit 1
}
# Parse every line first, so that a bad table writes nothing.
declare -a LINES=() NAMES=()
declare -A SEEN=()
LINE=0
while IFS= read -r text || [[ -n $text ]]; do
    LINE=$((LINE + 1))
    text=${text%%#*}
    [[ -n ${text// /} ]] || continue
    parse "$text"
    n=$(name)
    [[ -z ${SEEN[$n]:-} ]] || fail "the same settings as line ${SEEN[$n]} (set $n)"
    SEEN[$n]=$LINE
    LINES+=("$LINE:$text")
    NAMES+=("$n")
done <"$SWEEP"

for i in "${!LINES[@]}"; do
    LINE=${LINES[$i]%%:*}
    parse "${LINES[$i]#*:}"
    if [[ $MODE == --rows ]]; then
        echo "${NAMES[$i]} $FRAMES $SCENES $POINT_SETS $FROM $SHIFTS $REFERENCE $FOR"
    elif wanted "$@"; then
        write "$MODE/${NAMES[$i]}" "${NAMES[$i]}"
        echo "${NAMES[$i]}"
    fi
done
