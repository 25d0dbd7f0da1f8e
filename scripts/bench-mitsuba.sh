#!/usr/bin/env bash
# nffrt's path tracer against Mitsuba 3 on the Cornell box (examples/cornell.p3f and
# Mitsuba's own mi.cornell_box(), scripts/mitsuba_scenes.py): 512x512, 256 samples
# per pixel, max depth 8, whole processes (start, load, render, write a linear EXR),
# every renderer on all cores, Mitsuba's kernel cache warmed by one run first.
# Prints the median wall time of RUNS runs of each and its ratio to nffrt's.
#
#   scripts/bench-mitsuba.sh [RUNS]     RUNS runs of each (default 3)
#   SIZE=512 SPP=256 DEPTH=8            the picture, samples and depth
#   VARIANTS="llvm_ad_rgb scalar_rgb"   the Mitsuba variants to time
# Environment: see scripts/mitsuba-env.sh (MITSUBA_PY, NFFRT, DRJIT_LIBLLVM_PATH).
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/mitsuba-env.sh
runs=${1:-3}
size=${SIZE:-512}
spp=${SPP:-256}
depth=${DEPTH:-8}
variants=${VARIANTS:-llvm_ad_rgb scalar_rgb}
[ -n "${DRJIT_LIBLLVM_PATH:-}" ] || variants=${variants//llvm_ad_rgb/}
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT

median() { sort -g | awk '{a[NR]=$1} END {print (NR%2 ? a[(NR+1)/2] : (a[NR/2]+a[NR/2+1])/2)}'; }
# Wall seconds of a command; a failure shows its output and stops the script (a
# command substitution would otherwise swallow it).
wall() {
    local t0 t1
    t0=$(date +%s%N)
    "$@" >"$tmp/log" 2>&1 || { cat "$tmp/log" >&2; echo "failed: $*" >&2; kill -TERM $$; }
    t1=$(date +%s%N)
    awk -v a="$t0" -v b="$t1" 'BEGIN {printf "%.3f\n", (b-a)/1e9}'
}
nffrt_run() {
    "$NFFRT" render examples/cornell.p3f --integrator path --spp "$spp" --max-depth "$depth" \
        --width "$size" --height "$size" -q -o "$tmp/nffrt.exr"
}
mitsuba_run() { "$MITSUBA_PY" scripts/mitsuba_render.py "$1" cornell "$size" "$spp" "$tmp/$1.exr"; }

load() { awk '{print $1, $2, $3}' /proc/loadavg; }
echo "== load average before: $(load) (another job on the cores skews every figure)"
echo "== CPU: $(lscpu | awk -F': +' '/^Model name/ {print $2}'), $(nproc) cores; Mitsuba $("$MITSUBA_PY" -c 'import mitsuba; print(mitsuba.__version__)')"
echo "== Cornell box ${size}x${size}, $spp spp, max depth $depth: wall seconds, median of $runs"
nffrt_s=$(for _ in $(seq "$runs"); do wall nffrt_run; done | median)
printf '%-22s %9s %12s %14s\n' renderer seconds "vs nffrt" "Msamples/s"
row() { printf '%-22s %9.2f %11.2fx %14.2f\n' "$1" "$2" "$(awk -v a="$2" -v b="$nffrt_s" 'BEGIN {print a/b}')" "$(awk -v t="$2" -v n="$((size * size * spp))" 'BEGIN {print n/t/1e6}')"; }
row nffrt "$nffrt_s"
for v in $variants; do
    wall mitsuba_run "$v" >/dev/null # the kernel cache, warm
    s=$(for _ in $(seq "$runs"); do wall mitsuba_run "$v"; done | median)
    row "mitsuba $v" "$s"
done

echo "== load average after the medians: $(load)"

# Time to equal error, against the converged reference compare-mitsuba.sh leaves.
if ls target/mitsuba-compare/cornell-*-[12].exr >/dev/null 2>&1; then
    "$MITSUBA_PY" scripts/rmse-mitsuba.py "$NFFRT" "$MITSUBA_PY" $variants
else
    echo "(no reference for time to equal RMSE: run scripts/compare-mitsuba.sh first)"
fi
