#!/usr/bin/env bash
# BART's animations in frames per second: kitchen, robots and museum5 at 800x600,
# Whitted, 1 sample per pixel, 2 threads, with `nffrt render --frames A..B`, in three
# modes: `fixed` (the default: meshes placed more than once or moving are instances
# of prototypes built once; the objects under no keyframed transform flattened and
# built once, each frame building only what moves, grafted under one root),
# `copied` (`--flatten-meshes`: the same with every mesh copied into world space)
# and `whole` (`--rebuild-whole --flatten-meshes`: every frame flattened, meshes
# copied, and built whole, the comparison). The closing line of each render splits its time into the fixed part
# (once), the per-frame update (flatten + build) and render (+ writing a binary
# PPM, a few ms a frame); the update's share below counts the fixed part in.
#
#   scripts/bench-bart.sh [RUNS] [BINARY]     # default 3 runs, target/release/nffrt
#
# A sample of each animation: BLOCKS blocks of BLOCK consecutive frames spread
# evenly over it (default 4 x 10 frames), the same frames in every run, the modes
# alternating. Prints one line per scene, mode and run, then per scene and mode the
# median over runs of frames/s, of the update's share and of the peak resident
# memory (`/usr/bin/time`, the largest of the blocks). Scenes come from
# ../shared/scenes/bart (absent: said, skipped).
set -euo pipefail
cd "$(dirname "$0")/.."

runs=${1:-3}
bin=$(realpath "${2:-target/release/nffrt}")
blocks=${BLOCKS:-4}
block=${BLOCK:-10}
bart=../shared/scenes/bart
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT

echo "# $(date -u +%FT%TZ) $(git rev-parse --short HEAD) $(lscpu | sed -n 's/^Model name: *//p'), $(nproc) CPUs, load $(cut -d' ' -f1-3 /proc/loadavg)"
echo "# scene mode run frames seconds fps fixed_s flatten_s build_s update_% render_s peak_MB"
for entry in kitchen:kitchen/aff/kitchen.aff:800 robots:robot/aff/Robot.aff:800 museum5:museum/aff/museum5.aff:300; do
    IFS=: read -r name rel frames <<< "$entry"
    if [ ! -f "$bart/$rel" ]; then
        echo "$name: absent ($bart/$rel)"
        continue
    fi
    for run in $(seq "$runs"); do
        for mode in fixed copied whole; do
            flag=()
            [ "$mode" = copied ] && flag=(--flatten-meshes)
            [ "$mode" = whole ] && flag=(--rebuild-whole --flatten-meshes)
            total_frames=0 total_s=0 fixed=0 flatten=0 build=0 render=0 peak=0
            for b in $(seq 0 $((blocks - 1))); do
                first=$((b * frames / blocks))
                last=$((first + block - 1))
                line=$(/usr/bin/time -f 'peak %M' "$bin" render "$bart/$rel" --frames "$first..$last" --width 800 --height 600 \
                    --spp 1 --threads 2 --integrator whitted "${flag[@]}" -o "$out/f_%04d.ppm" 2>&1 | grep '^rendered\|^peak')
                kb=$(sed -n 's/^peak //p' <<< "$line")
                peak=$((kb > peak ? kb : peak))
                line=$(grep '^rendered' <<< "$line")
                # rendered N frames (..) in T s, F frames/s: fixed part X s + flatten A s + build B s (update U %), render and write R s; ...
                read -r n t x a bb r < <(sed -E 's/^rendered ([0-9]+) frames .* in ([0-9.]+) s, .*fixed part ([0-9.]+) s \+ flatten ([0-9.]+) s \+ build ([0-9.]+) s .*render and write ([0-9.]+) s;.*/\1 \2 \3 \4 \5 \6/' <<< "$line")
                total_frames=$((total_frames + n))
                read -r total_s fixed flatten build render < <(echo "$total_s $t $fixed $x $flatten $a $build $bb $render $r" |
                    awk '{ printf "%.3f %.3f %.3f %.3f %.3f\n", $1 + $2, $3 + $4, $5 + $6, $7 + $8, $9 + $10 }')
            done
            awk -v s="$name" -v m="$mode" -v run="$run" -v n="$total_frames" -v t="$total_s" -v x="$fixed" -v a="$flatten" -v b="$build" -v r="$render" -v p="$peak" \
                'BEGIN { printf "%s %s %d %d %.2f %.2f %.2f %.2f %.2f %.1f %.2f %.1f\n", s, m, run, n, t, n / t, x, a, b, 100 * (x + a + b) / t, r, p / 1024 }'
        done
    done
done | tee "$out/lines"
echo "# median over runs: scene mode fps update_% peak_MB"
median() { sort -n | awk '{ v[NR] = $1 } END { print v[int((NR + 1) / 2)] }'; }
for name in $(grep -v '^#' "$out/lines" | grep -v absent | cut -d' ' -f1 | uniq); do
    for mode in fixed copied whole; do
        rows=$(grep "^$name $mode " "$out/lines")
        echo "$name $mode $(cut -d' ' -f6 <<< "$rows" | median) $(cut -d' ' -f10 <<< "$rows" | median) $(cut -d' ' -f12 <<< "$rows" | median)"
    done
done
