#!/usr/bin/env bash
# Engine speed of two demsweep builds side by side, for a quiet machine (about 5 minutes, plus a
# baseline build if asked for one):
#   1. the reference scene (docs/reference_scene.md: 300 disks, 150 000 steps), baseline and new
#      alternated, ROUNDS times each;
#   2. one big deposition (BIG disks, the box widened with them, BIG_DURATION s) with the new build
#      on --jobs 1 and --jobs 2 (one run: it gets both threads), and the baseline on --jobs 1,
#      alternated, BIG_ROUNDS times each.
# Prints the median (and all) ns per particle-step of each, the 2-thread/1-thread ratio, the load
# before and after, and checks that the baseline and the new build give the reference scene the
# same history to the last digit, and that 1 and 2 threads give the big run the same history.
# Each run's time is its wall_time in the summary (the simulation alone, not the program's start
# or the results file). (No LAMMPS input for the reference scene is in the repository, so LAMMPS is
# not run: docs/reference_scene.md has its figures.)
#
# Usage:
#   scripts/engine_compare.sh BASE_DEMSWEEP NEW_DEMSWEEP   two built `demsweep` programs
#   scripts/engine_compare.sh --build [COMMIT]              builds the baseline from COMMIT (default
#       main) in a temporary git worktree (its build folder: target/engine_compare_base/, kept
#       for the next time) and the new one from this tree (cargo build --release)
# Environment: ROUNDS (5), BIG (40000), BIG_DURATION (0.3), BIG_ROUNDS (3).
# Everything it writes goes to a new temporary folder, which it names at the end.
set -euo pipefail

repo=$(git -C "$(dirname "$0")" rev-parse --show-toplevel)
work=$(mktemp -d "${TMPDIR:-/tmp}/engine_compare.XXXXXX")
rounds=${ROUNDS:-5} big=${BIG:-40000} big_duration=${BIG_DURATION:-0.3} big_rounds=${BIG_ROUNDS:-3}

if [ "${1:-}" = "--build" ]; then
    commit=${2:-main}
    git -C "$repo" worktree add --detach "$work/base" "$commit" >/dev/null
    (cd "$work/base" && CARGO_TARGET_DIR="$repo/target/engine_compare_base" cargo build --release --bin demsweep)
    git -C "$repo" worktree remove --force "$work/base"
    (cd "$repo" && cargo build --release --bin demsweep)
    base="$repo/target/engine_compare_base/release/demsweep" new="$repo/target/release/demsweep"
elif [ $# -eq 2 ]; then
    base=$1 new=$2
else
    sed -n '2,/^set -euo/p' "$0" | sed '$d; s/^# \{0,1\}//' >&2
    exit 2
fi

# The reference scene and the big deposition as studies.
scene() { # NAME, then scene lines
    local name=$1
    shift
    printf 'name = "%s"\n[scene]\nmaterial.restitution = 0.5\nmaterial.friction = 0.5\n' "$name"
    printf 'integrator.time_step = 1e-5\nrun.stop_at_settle = false\n'
    printf '%s\n' "$@"
    printf '[output]\nframes = false\n'
}
scene reference 'placement.kind = "file"' "placement.file = \"$repo/tests/data/deposition_300.csv\"" \
    'run.duration = 1.5' >"$work/reference.toml"
width=$(python3 -c "print(0.4 * $big / 300)")
scene big "particles.count = $big" "domain.width = $width" "run.duration = $big_duration" >"$work/big.toml"

# Runs STUDY with PROGRAM on JOBS workers into runs/LABEL.K; prints its ns per particle-step.
run() { # PROGRAM STUDY JOBS LABEL K
    local out="$work/runs/$4.$5"
    "$1" run "$work/$2.toml" --out "$out" --jobs "$3" --progress quiet >/dev/null 2>"$out.log" || {
        cat "$out.log" >&2
        exit 1
    }
    python3 - "$out/${2}_summary.csv" <<'EOF'
import csv, sys
# The names line, then (builds since the units line) a line of units: the run is the first row with
# a number of particle steps; its time is `wall_time` (`wall_time (s)` in builds before the units line).
row = next(r for r in csv.DictReader(open(sys.argv[1])) if r["particle_steps"].isdigit())
print(float(row.get("wall_time") or row["wall_time (s)"]) * 1e9 / float(row["particle_steps"]))
EOF
}

median() { python3 -c 'import statistics, sys; v = [float(x) for x in sys.argv[1:]]; print("%.2f (all: %s)" % (statistics.median(v), ", ".join("%.2f" % x for x in v)))' "$@"; }

mkdir -p "$work/runs"
echo "load before: $(uptime)"
declare -a ref_base ref_new big_base big_1 big_2
for k in $(seq "$rounds"); do
    ref_base+=("$(run "$base" reference 1 reference_base "$k")")
    ref_new+=("$(run "$new" reference 1 reference_new "$k")")
done
for k in $(seq "$big_rounds"); do
    big_base+=("$(run "$base" big 1 big_base "$k")")
    big_1+=("$(run "$new" big 1 big_new_1 "$k")")
    big_2+=("$(run "$new" big 2 big_new_2 "$k")")
done
echo "load after: $(uptime)"

echo "reference scene, ns per particle-step, median of $rounds:"
echo "  baseline: $(median "${ref_base[@]}")"
echo "  new:      $(median "${ref_new[@]}")"
echo "$big disks, $big_duration s, ns per particle-step, median of $big_rounds:"
echo "  baseline, 1 thread: $(median "${big_base[@]}")"
echo "  new, 1 thread:      $(median "${big_1[@]}")"
echo "  new, 2 threads:     $(median "${big_2[@]}")"
python3 -c "import statistics as s, sys; print(f'  2 threads / 1 thread: {s.median(map(float, sys.argv[2:])) / s.median(map(float, sys.argv[1].split())):.2f} (target <= 0.6)')" \
    "${big_1[*]}" "${big_2[@]}"

# The same bits: histories printed with every digit.
history() { "$1" history "$work/runs/$2/$3.h5" "$("$1" summary "$work/runs/$2/$3.h5" | awk 'NR == 2 { print $1 }')"; }
same() { if cmp -s <(history "$1" "$2" "$4") <(history "$1" "$3" "$4"); then echo "same"; else echo "DIFFERENT"; fi; }
echo "reference scene history, baseline against new: $(same "$new" reference_base.1 reference_new.1 reference)"
echo "big run history, 1 against 2 threads: $(same "$new" big_new_1.1 big_new_2.1 big)"
echo "runs and logs: $work/runs"
