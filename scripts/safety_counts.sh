#!/usr/bin/env bash
# Issue #28's before/after counts: runs the output-path cases, diverged sweeps, a heaped placement,
# crafted results files and truncated or bit-flipped copies of a results file against one demsweep
# binary, and counts the outcomes of the commands:
#   ok     exit 0 where that is right (a readable file, a command that should work)
#   clear  a refusal or error with a message (exit 1, 2 or 3)
#   panic  exit 101
#   abort  a signal, or killed by the time (60 s) or memory (4 GB) limit
#   silent exit 0 where the command should have refused (its output would overwrite an input), or
#          a file written outside the output folder
#   lost   a file that was there before is gone or changed
#
#   scripts/safety_counts.sh BINARY [CRAFTED_DIR]
#
# CRAFTED_DIR: crafted results files (tests/crafted_files.rs leaves them in target/tmp/crafted).
# `export --out /` is left out for binaries that would remove / (set SAFETY_TRY_ROOT=1 to run it).
set -uo pipefail
readonly BIN=$(realpath "$1")
readonly CRAFTED=${2:-}
readonly WORK=$(mktemp -d /tmp/demsweep-counts.XXXXXX)
trap 'rm -rf "$WORK"' EXIT
declare -A COUNT=([ok]=0 [clear]=0 [panic]=0 [abort]=0 [silent]=0 [lost]=0)

# Runs BIN with the arguments in folder $CWD under the limits; sets RC.
limited() {
    (cd "$CWD" && ulimit -v 4000000 && timeout 60 "$BIN" "$@" >/dev/null 2>"$WORK/stderr")
    RC=$?
}

# The listing (path, size, checksum) of every file under a folder.
listing() { (cd "$1" && find . -type f -print0 | sort -z | xargs -0 -r md5sum); }

# classify EXPECT: counts the command just run (EXPECT: refuse or any), given the folder checked.
classify() {
    local expect=$1 outcome
    if [[ $RC -eq 101 ]]; then outcome=panic
    elif [[ $RC -ge 124 ]]; then outcome=abort
    elif [[ -n $GUARD ]] && ! listing "$GUARD" | diff -q - "$WORK/before" >/dev/null; then outcome=lost
    elif [[ $RC -eq 0 && $expect == refuse ]]; then outcome=silent
    elif [[ $RC -eq 0 ]]; then outcome=ok
    else outcome=clear
    fi
    COUNT[$outcome]=$((COUNT[$outcome] + 1))
    [[ $outcome == ok || $outcome == clear ]] || echo "  $outcome: $CASE (exit $RC)"
}

STUDY=$(cat "$(dirname "$0")/../tests/data/paths.toml")

# A fresh work folder with a study and its results in results/; sets CWD, GUARD (what must survive).
fresh() {
    rm -rf "$WORK/w" && mkdir -p "$WORK/w" && CWD=$WORK/w
    echo "$STUDY" >"$CWD/paths.toml"
    (cd "$CWD" && "$BIN" run paths.toml --out results --progress quiet >/dev/null 2>&1)
    GUARD=$CWD
}

# refuse WHERE ARGS...: a case whose command must refuse; the work folder must survive.
refuse() {
    local where=$1
    shift
    fresh
    [[ -n ${SETUP:-} ]] && (cd "$CWD" && eval "$SETUP")
    listing "$GUARD" >"$WORK/before"
    CASE="$*"
    CWD=$CWD/$where limited "$@"
    CWD=$WORK/w classify refuse
}

echo "output paths"
refuse results export paths.h5 --format csv --out . --force
refuse results export paths.h5 --format csv --out .. --force
refuse . export results/paths.h5 --format csv --out results --force
if [[ ${SAFETY_TRY_ROOT:-0} == 1 ]]; then refuse . export results/paths.h5 --format csv --out / --force; fi
refuse results summary paths.h5 --csv paths.h5
refuse results report paths.h5 --out paths.h5
refuse results compare paths.h5 --reference r0000 --csv paths.h5
SETUP='echo precious >precious.txt; rm results/paths.h5.lock; ln -s ../precious.txt results/paths.h5.lock' \
    refuse . run paths.toml --out results --force --progress quiet
SETUP='echo precious >precious.txt; rm results/paths_summary.csv; ln -s ../precious.txt results/paths_summary.csv' \
    refuse . run paths.toml --out results --force --progress quiet
SETUP='mkdir piles.partial; echo theirs >piles.partial/data.txt' \
    refuse . export results/paths.h5 --format csv --out piles
SETUP='mkdir mine; echo notes >mine/notes.txt' \
    refuse . export results/paths.h5 --format csv --out mine --force

# every_command STUDY_TEXT [PLACEMENT]: a sweep run whole and in shards, then every reading command.
every_command() {
    rm -rf "$WORK/d" && mkdir -p "$WORK/d" && CWD=$WORK/d GUARD=
    echo "$1" >"$CWD/blowup.toml"
    [[ -n ${2:-} ]] && echo "$2" >"$CWD/fast.csv"
    for args in "run blowup.toml --out whole --progress quiet" \
        "run blowup.toml --out shards --shard 1/2 --progress quiet" \
        "run blowup.toml --out shards --shard 2/2 --progress quiet" "merge merged shards" \
        "run blowup.toml --out whole --resume --progress quiet" "report whole/blowup.h5 --out page.html" \
        "plot whole/blowup.h5 --all-runs --out plots" "export whole/blowup.h5 --format vtk --out vtk" \
        "compare whole/blowup.h5 --reference r0000"; do
        # shellcheck disable=SC2086
        CASE="diverged: $args"
        limited $args
        classify any
    done
}

echo "diverged runs"
readonly DIVERGED=$(dirname "$0")/../tests/data/diverged
every_command "$(cat "$DIVERGED/stiffness_time_step.toml")"
every_command "$(cat "$DIVERGED/fast_disk.toml")" "$(cat "$DIVERGED/fast.csv")"

echo "heaped placement"
rm -rf "$WORK/h" && mkdir -p "$WORK/h" && CWD=$WORK/h GUARD=
python3 -c "
print('x,y,r')
for i in range(60000): print('0.5,0.5,0.002')" >"$CWD/disks.csv"
printf 'name = "heap"\n[scene]\nparticles.count = 60000\nparticles.radius = 0.002\ndomain.width = 1.0\ndomain.height = 1.0\nplacement.kind = "file"\nplacement.file = "disks.csv"\n' >"$CWD/heap.toml"
CASE="check of 60 000 heaped disks"
limited check heap.toml
classify any

# read_file FILE LABEL: every reading command on a copy of FILE (in its own folder).
read_file() {
    local label=$2
    rm -rf "$WORK/f" && mkdir -p "$WORK/f/in" && cp "$1" "$WORK/f/in/lies.h5" && CWD=$WORK/f GUARD=
    for args in "summary in/lies.h5" "summary in/lies.h5 --by-point" "report in/lies.h5 --out page.html" \
        "plot in/lies.h5 --all-runs --format svg --out plots" "export in/lies.h5 --format vtk --out vtk" \
        "compare in/lies.h5 --reference r000"; do
        # shellcheck disable=SC2086
        CASE="$label: $args"
        limited $args
        classify any
    done
    local outside
    outside=$(cd "$WORK/f" && ls -A | grep -v -x -e in -e page.html -e plots -e vtk -e plots.partial -e vtk.partial)
    [[ -z $outside ]] || { COUNT[silent]=$((COUNT[silent] + 1)); echo "  silent: $label wrote $outside"; }
}

if [[ -n $CRAFTED ]]; then
    echo "crafted files"
    for file in "$CRAFTED"/*.h5; do read_file "$file" "$(basename "$file")"; done
fi

echo "truncated and bit-flipped copies"
fresh
ORIGINAL=$WORK/original.h5
cp "$CWD/results/paths.h5" "$ORIGINAL"
for k in $(seq 1 40); do
    python3 - "$ORIGINAL" "$WORK/variant.h5" "$k" <<'EOF'
import random, sys
data = bytearray(open(sys.argv[1], "rb").read())
rng = random.Random(int(sys.argv[3]))
if rng.random() < 0.3:
    data = data[: rng.randrange(len(data))]
else:
    for _ in range(rng.randint(1, 8)):
        data[rng.randrange(len(data))] ^= 1 << rng.randrange(8)
open(sys.argv[2], "wb").write(data)
EOF
    read_file "$WORK/variant.h5" "variant $k"
done

total=0
for k in "${!COUNT[@]}"; do total=$((total + COUNT[$k])); done
echo "commands $total: ok ${COUNT[ok]}, clear ${COUNT[clear]}, panic ${COUNT[panic]}, abort ${COUNT[abort]}, silent ${COUNT[silent]}, lost ${COUNT[lost]}"
