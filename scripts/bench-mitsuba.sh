#!/usr/bin/env bash
# nffrt's path tracer against Mitsuba 3 on the Cornell box (examples/cornell.p3f and
# Mitsuba's own mi.cornell_box(), scripts/mitsuba_scenes.py): 512x512, 256 samples
# per pixel, max depth 8, whole processes (start, load, render, write a linear EXR),
# every renderer on all cores, Mitsuba's kernel cache warmed by one run first.
# Prints the median wall and CPU time of RUNS alternating runs of each and the wall
# ratio to nffrt's; then, given compare-mitsuba.sh's converged reference, the time
# each takes to the same RMSE (scripts/rmse-mitsuba.py).
#
#   scripts/bench-mitsuba.sh [RUNS]     RUNS runs of each (default 3)
#   SCENE=cornell|glass-mirror          the scene (default cornell; glass-mirror is
#                                       examples/glass-mirror.p3f, a closed room with a
#                                       mirror sphere, a glass sphere and a quad light)
#   SIZE=512 SPP=256 DEPTH=8            the picture, samples and depth (DEPTH's default:
#                                       8 for cornell, 12 for glass-mirror, as compared)
#   VARIANTS="llvm_ad_rgb scalar_rgb"   the Mitsuba variants to time
#   RMSE=0                              without the time to equal RMSE
# Environment: see scripts/mitsuba-env.sh (MITSUBA_PY, NFFRT, DRJIT_LIBLLVM_PATH).
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/mitsuba-env.sh
runs=${1:-3}
size=${SIZE:-512}
spp=${SPP:-256}
scene=${SCENE:-cornell}
case "$scene" in
    cornell) depth=${DEPTH:-8} ;;
    glass-mirror) depth=${DEPTH:-12} ;;
    *) echo "bench-mitsuba: SCENE must be cornell or glass-mirror, not '$scene'" >&2; exit 2 ;;
esac
variants=${VARIANTS:-llvm_ad_rgb scalar_rgb}
[ -n "${DRJIT_LIBLLVM_PATH:-}" ] || variants=${variants//llvm_ad_rgb/}
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT

median() { sort -g | awk '{a[NR]=$1} END {print (NR%2 ? a[(NR+1)/2] : (a[NR/2]+a[NR/2+1])/2)}'; }
# "WALL CPU" seconds of a command (CPU: user + system of it and its children, which
# another job on the cores inflates less than wall time); appended to $tmp/NAME.
# A failure shows the command's output and stops the script.
timed() {
    local name=$1 t0 t1 c0 c1
    shift
    c0=$(awk '{print $14 + $15 + $16 + $17}' /proc/$$/stat)
    t0=$(date +%s%N)
    ( "$@" >"$tmp/log" 2>&1 ) || { cat "$tmp/log" >&2; echo "failed: $*" >&2; exit 1; }
    t1=$(date +%s%N)
    c1=$(awk '{print $14 + $15 + $16 + $17}' /proc/$$/stat)
    awk -v a="$t0" -v b="$t1" -v c="$c0" -v d="$c1" -v hz="$(getconf CLK_TCK)" \
        'BEGIN {printf "%.3f %.3f\n", (b-a)/1e9, (d-c)/hz}' >>"$tmp/$name"
}
nffrt_run() {
    "$NFFRT" render "examples/$scene.p3f" --integrator path --spp "$spp" --max-depth "$depth" \
        --width "$size" --height "$size" -q -o "$tmp/nffrt.exr"
}
mitsuba_run() { "$MITSUBA_PY" scripts/mitsuba_render.py "$1" "$scene" "$size" "$spp" "$tmp/$1.exr"; }

load() { awk '{print $1, $2, $3}' /proc/loadavg; }
echo "== load average before: $(load) (another job on the cores skews every figure)"
echo "== CPU: $(lscpu | awk -F': +' '/^Model name/ {print $2}'), $(nproc) cores; Mitsuba $("$MITSUBA_PY" -c 'import mitsuba; print(mitsuba.__version__)')"
for v in $variants; do timed warm mitsuba_run "$v"; done # Mitsuba's kernel cache, warm
# The renderers alternate, run after run, so that a passing load falls on all alike.
for _ in $(seq "$runs"); do
    timed nffrt nffrt_run
    for v in $variants; do timed "$v" mitsuba_run "$v"; done
done
echo "== $scene ${size}x${size}, $spp spp, max depth $depth: median of $runs alternating runs"
printf '%-22s %9s %9s %10s %12s\n' renderer "wall s" "CPU s" "wall ratio" "Msamples/s"
nffrt_s=$(cut -d' ' -f1 "$tmp/nffrt" | median)
row() {
    local w c
    w=$(cut -d' ' -f1 "$tmp/$2" | median)
    c=$(cut -d' ' -f2 "$tmp/$2" | median)
    printf '%-22s %9.2f %9.2f %9.2fx %12.2f\n' "$1" "$w" "$c" \
        "$(awk -v a="$w" -v b="$nffrt_s" 'BEGIN {print a/b}')" \
        "$(awk -v t="$w" -v n="$((size * size * spp))" 'BEGIN {print n/t/1e6}')"
}
row nffrt nffrt
for v in $variants; do row "mitsuba $v" "$v"; done
echo "== load average after the medians: $(load)"

# Time to equal error, against the converged reference compare-mitsuba.sh leaves.
if [ "${RMSE:-1}" = 0 ]; then
    echo "(RMSE=0: no time to equal RMSE)"
elif [ "$scene" != cornell ]; then
    echo "(time to equal RMSE: the Cornell box only)"
elif ls target/mitsuba-compare/cornell-*-[12].exr >/dev/null 2>&1; then
    "$MITSUBA_PY" scripts/rmse-mitsuba.py "$NFFRT" "$MITSUBA_PY" $variants
else
    echo "(no reference for time to equal RMSE: run scripts/compare-mitsuba.sh first)"
fi
