#!/usr/bin/env bash
# The builder against Embree's (issue 45): full builds of the same triangles, mount
# size 9 without its spheres (524 288 triangles) and frame 400 of BART's kitchen
# flattened (`nffrt convert`, 110 520 triangles), on 1 and 2 threads. Embree:
# rtcCommitScene through embreex (../shared/bench/embree_anchor.py, `build_ms`, the
# fastest of 5 fresh builds, TBB restricted to the threads); nffrt: `Bvh::new` with
# the scene's conversion to primitives (`nffrt bench`, `build_best_ms`, the fastest of
# 5, on a pool of the threads; and `Bvh::new` alone, `bvh_best_ms`, without the
# conversion, the counterpart of Embree's build from triangles already in its
# buffers). The programs alternate; each figure is the median over RUNS processes. Needs ../shared and a Python with embreex (../shared/bench/README.md).
#
#   scripts/bench-build.sh [RUNS]          RUNS processes per figure (default 5)
#   NFFRT_BASE=/path/to/nffrt              also time another nffrt build (before/after)
#   EMBREE_PY=/path/to/python              Python with embreex (default ../.bench-venv/bin/python)
set -euo pipefail
cd "$(dirname "$0")/.."
runs=${1:-5}
shared=../shared
nffrt=target/release/nffrt
py=${EMBREE_PY:-../.bench-venv/bin/python}
[ -x "$nffrt" ] || cargo build --release -q
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT

echo "== CPU: $(lscpu | sed -n 's/^Model name: *//p'), family $(lscpu | sed -n 's/^CPU family: *//p') model $(lscpu | sed -n 's/^Model: *//p'), $(nproc) threads"
echo "== commit $(git rev-parse --short HEAD 2>/dev/null || echo unknown)$(git diff --quiet 2>/dev/null || echo ' (with uncommitted changes)'), $(date -u '+%Y-%m-%d %H:%M UTC'), load average $(cut -d' ' -f1-3 /proc/loadavg)"

"$nffrt" gen mount --size 9 | grep -v '^s ' > "$tmp/mount9.nff"
"$nffrt" convert "$shared/scenes/bart/kitchen/aff/kitchen.aff" --frame 400 -o "$tmp/kitchen400.nff" 2>/dev/null
# 64 rays: the builds dominate nffrt's run (its queries are not timed here).
"$py" -c "import numpy as n; r = n.zeros((64, 6), n.float32); r[:, 5] = 1; r.tofile('$tmp/rays.f32')"

median() { sort -g | awk '{a[NR]=$1} END {print (NR%2 ? a[(NR+1)/2] : (a[NR/2]+a[NR/2+1])/2)}'; }
key() { tr ' ' '\n' | grep "^$1=" | cut -d= -f2 || true; }
declare -A got
nffrts=("$nffrt"); [ -n "${NFFRT_BASE:-}" ] && nffrts+=("$NFFRT_BASE")
for _ in $(seq "$runs"); do
    for threads in 1 2; do
        for scene in mount9 kitchen400; do
            e=$("$py" "$shared/bench/embree_anchor.py" "$tmp/$scene.nff" --repeat 5 --threads "$threads" --rays primary --no-occlusion 2>/dev/null | tail -1)
            got[embree,$scene,$threads]+="$(echo "$e" | key build_ms) "
            for b in "${nffrts[@]}"; do
                o=$("$b" bench "$tmp/$scene.nff" --rays "$tmp/rays.f32" --rays-only --repeat 5 --threads "$threads" | tail -1)
                got[$b,$scene,$threads]+="$(echo "$o" | key build_best_ms) "
                got[$b,bvh,$scene,$threads]+="$(echo "$o" | key bvh_best_ms) "
            done
        done
    done
done
echo "== full builds, ms: median over $runs processes of the fastest of 5 builds (ratio: Embree's time over nffrt's; above 1, nffrt builds faster); bvh_new: nffrt's Bvh::new alone"
printf '%-10s %7s %10s %10s %7s %10s %7s' scene threads embree nffrt ratio bvh_new ratio
[ -n "${NFFRT_BASE:-}" ] && printf ' %10s %7s' base base_ratio
echo
for scene in mount9 kitchen400; do
    for threads in 1 2; do
        e=$(echo ${got[embree,$scene,$threads]} | tr ' ' '\n' | median)
        o=$(echo ${got[$nffrt,$scene,$threads]} | tr ' ' '\n' | median)
        n=$(echo ${got[$nffrt,bvh,$scene,$threads]} | tr ' ' '\n' | median)
        printf '%-10s %7s %10.1f %10.1f %7.2f %10.1f %7.2f' "$scene" "$threads" "$e" "$o" "$(awk -v a="$e" -v b="$o" 'BEGIN {print a / b}')" \
            "$n" "$(awk -v a="$e" -v b="$n" 'BEGIN {print a / b}')"
        if [ -n "${NFFRT_BASE:-}" ]; then
            b=$(echo ${got[$NFFRT_BASE,$scene,$threads]} | tr ' ' '\n' | median)
            printf ' %10.1f %7.2f' "$b" "$(awk -v a="$e" -v b="$b" 'BEGIN {print a / b}')"
        fi
        echo
    done
done
for k in "${!got[@]}"; do echo "runs $k: ${got[$k]}"; done | sort
