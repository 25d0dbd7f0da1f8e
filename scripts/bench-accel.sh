#!/usr/bin/env bash
# The three acceleration structures on three course scenes, as a teacher would show
# them: `nffrt render --accel bvh|grid|none` at each scene's own size and samples,
# render time (median of RUNS runs, all cores) and the structure's work per camera
# ray from --stats-json (nodes or cells visited, primitive tests). Prints a Markdown
# table (BENCHMARKS.md, "Acceleration structures").
#
#   scripts/bench-accel.sh [RUNS]     RUNS repetitions (default 3)
#
# `none` tests every primitive for every ray: on dragon.p3f (100 005 primitives) it
# would take many minutes, so it renders the 200x150 crop at the picture's centre
# (--region, a sixteenth of the pixels) and the table gives that time times 16,
# marked as an estimate.
set -euo pipefail
if [ $# -gt 1 ] || [[ "${1:-}" == -* ]]; then
    echo "usage: $0 [RUNS]" >&2
    exit 2
fi
cd "$(dirname "$0")/.."
runs=${1:-3}
shared=${NFFRT_SHARED:-../shared}
if [ ! -d "$shared/scenes/p3f" ]; then
    echo "$0: $shared/scenes/p3f is missing (the course scenes)" >&2
    exit 1
fi
cargo build --release --quiet
bin=target/release/nffrt
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT

# One render's JSON report; extra arguments go to nffrt render.
report() {
    "$bin" render "$@" -q -o "$out/picture.png" --stats-json -
}

field() {
    python3 -c 'import json,sys; d=json.load(sys.stdin); print(eval(sys.argv[1]))' "$1"
}

echo "| scene | accel | render s (median of $runs) | nodes or cells / camera ray | primitive tests / camera ray |"
echo "|---|---|---:|---:|---:|"
for scene in 2019/balls_medium 2019/mount_high 2019/dragon; do
    file="$shared/scenes/p3f/$scene.p3f"
    for accel in bvh grid none; do
        args=("$file" --accel "$accel")
        scale=1
        note=""
        if [ "$accel" = none ] && [ "$scene" = 2019/dragon ]; then
            args+=(--region 300,225,500,375)
            scale=16
            note=" (estimate: a 1/16 crop x 16)"
        fi
        times=()
        for _ in $(seq "$runs"); do
            json=$(report "${args[@]}")
            times+=("$(echo "$json" | field "d['render_s'] * $scale")")
        done
        median=$(printf '%s\n' "${times[@]}" | sort -g | awk '{a[NR]=$1} END {print a[int((NR+1)/2)]}')
        nodes=$(echo "$json" | field "round(d['accel']['nodes_per_ray'], 1)")
        prims=$(echo "$json" | field "round(d['accel']['primitive_tests_per_ray'], 1)")
        cells=$(echo "$json" | field "'x'.join(map(str, d['accel'].get('grid_cells', []))) or ''")
        printf '| %s | %s%s | %.3f%s | %s | %s |\n' "$(basename "$scene")" "$accel" "${cells:+ $cells}" "$median" "$note" "$nodes" "$prims"
    done
done
echo
echo "machine: $(lscpu | sed -n 's/^Model name: *//p'), $(nproc) threads"
