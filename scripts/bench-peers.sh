#!/usr/bin/env bash
# Side-by-side timings of nffrt against its peers, all in one run on one machine.
# Needs ../shared (scenes and bench/), a release build, POV-Ray (apt-get install povray)
# and a Python with embreex (see ../shared/bench/README.md). Prints medians.
#
#   scripts/bench-peers.sh [RUNS]         RUNS repetitions per figure (default 3)
#   EMBREE_PY=/path/to/python             Python with embreex (default .bench-venv/bin/python)
#   EMBREE_ISA=avx2                       Embree restricted to one instruction set (its
#                                         `isa=` device setting, set by scripts/embree_preload.c),
#                                         e.g. to compare like with like on a CPU with AVX-512
#                                         (nffrt's kernels are AVX2, picked at run time)
#   NFFRT_SIMD=avx2|portable              nffrt's kernels (default auto; see docs/speed.md)
#   SECTIONS=embree                       only the sections against Embree (the ones EMBREE_ISA
#                                         changes); SECTIONS=renders only the whole renders
#                                         against POV-Ray; default all
set -euo pipefail
cd "$(dirname "$0")/.."
runs=${1:-3}
shared=../shared
nffrt=target/release/nffrt
py=${EMBREE_PY:-../.bench-venv/bin/python}
[ -x "$nffrt" ] || cargo build --release -q
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT

# The CPU every figure below ran on (BENCHMARKS.md names it beside each column).
cpu=$(awk -F': ' '/^vendor_id/ {v=$2} /^cpu family/ {f=$2} /^model\t/ {m=$2} /^flags/ {a=($2 ~ /avx512f/) ? "AVX-512" : "no AVX-512"; if ($2 !~ /avx2/) a=a ", no AVX2"} END {printf "%s family %s model %s, %s", v, f, m, a}' /proc/cpuinfo)
l2=$(getconf LEVEL2_CACHE_SIZE 2>/dev/null || echo 0)
kernels=$("$nffrt" info "$shared/scenes/spd/tetra.nff" --json | python3 -c "import json,sys; print(json.load(sys.stdin)['kernels'])")
echo "== CPU: $cpu, L2 $((l2 / 1024)) KiB per core, $(nproc) threads; Embree ISA: ${EMBREE_ISA:-its default (the best this CPU has)}; nffrt kernels: $kernels (NFFRT_SIMD=${NFFRT_SIMD:-auto})"
echo "== commit $(git rev-parse --short HEAD 2>/dev/null || echo unknown)$(git diff --quiet 2>/dev/null || echo ' (with uncommitted changes)'), $(date -u '+%Y-%m-%d %H:%M UTC'), load average $(cut -d' ' -f1-3 /proc/loadavg)"
# Embree's instruction set pinned (EMBREE_ISA) and its robust mode for the native
# packets (EMBREE_ROBUST=1): a preloaded wrapper of rtcNewDevice and rtcSetSceneFlags.
preload=0
gcc -O2 -shared -fPIC -o "$tmp/embree_preload.so" scripts/embree_preload.c -ldl && preload=1
embree_env=()
if [ -n "${EMBREE_ISA:-}" ]; then
    [ "$preload" = 1 ] || { echo "bench-peers: EMBREE_ISA needs gcc to build scripts/embree_preload.c" >&2; exit 1; }
    embree_env=(env EMBREE_ISA="$EMBREE_ISA" LD_PRELOAD="$tmp/embree_preload.so")
fi
embree_robust_env=(env EMBREE_ISA="${EMBREE_ISA:-}" EMBREE_ROBUST=1 LD_PRELOAD="$tmp/embree_preload.so")

median() { sort -g | awk '{a[NR]=$1} END {print (NR%2 ? a[(NR+1)/2] : (a[NR/2]+a[NR/2+1])/2)}'; }
# "wall cpu" seconds of a command (cpu: user + system of it and its children).
timed() { /usr/bin/time -f '%e %U %S' -o "$tmp/time" "$@" >/dev/null 2>&1; awk '{printf "%.3f %.3f\n", $1, $2 + $3}' "$tmp/time"; }
# Sums "wall cpu" pairs, one per line.
sum2() { awk '{w += $1; c += $2} END {printf "%.3f %.3f\n", w, c}'; }
total() { for scene in "$@"; do timed "$nffrt" render "$scene" $NFFRT_FLAGS -q -o "$tmp/out.png"; done | sum2; }
# Medians of the two columns of "wall cpu" lines.
median2() { local in; in=$(cat); echo "$(echo "$in" | cut -d' ' -f1 | median) $(echo "$in" | cut -d' ' -f2 | median)"; }

# SECTIONS=embree runs only the sections with Embree (those EMBREE_ISA changes),
# SECTIONS=renders only the whole renders.
if [ "${SECTIONS:-all}" != embree ]; then
spd=(balls gears mount rings teapot tetra tree)
echo "== whole renders (wall and CPU seconds, user + system, median of $runs)"
spd_files=(); for s in "${spd[@]}"; do spd_files+=("$shared/scenes/spd/$s.nff"); done
NFFRT_FLAGS=--spd; read -r nffrt_spd nffrt_spd_cpu < <(for _ in $(seq "$runs"); do total "${spd_files[@]}"; done | median2)
echo "nffrt --spd, 7 SPD scenes:        $nffrt_spd s wall, $nffrt_spd_cpu s CPU"
p3d_files=(); for s in balls_low balls_medium balls_high mount_low mount_high mount_very_high; do p3d_files+=("$shared/scenes/p3d/$s.nff"); done
NFFRT_FLAGS="--width 512 --height 512"; read -r nffrt_p3d nffrt_p3d_cpu < <(for _ in $(seq "$runs"); do total "${p3d_files[@]}"; done | median2)
echo "nffrt, 6 course scenes 512x512:   $nffrt_p3d s wall, $nffrt_p3d_cpu s CPU"
if command -v povray >/dev/null; then
    read -r pov pov_cpu < <(for _ in $(seq "$runs"); do for n in "${spd[@]}"; do timed "$shared/bench/povray_peer.sh" "$n"; done | sum2; done | median2)
    echo "POV-Ray 3.7, 7 SPD scenes:        $pov s wall, $pov_cpu s CPU   (ratio POV-Ray / nffrt = $(awk -v a="$pov" -v b="$nffrt_spd" 'BEGIN {printf "%.1f", a/b}') wall, $(awk -v a="$pov_cpu" -v b="$nffrt_spd_cpu" 'BEGIN {printf "%.1f", a/b}') CPU)"
fi
[ "${SECTIONS:-all}" = renders ] && exit 0

echo "== scale: nffrt gen balls, sizes 4 (7 381 spheres) and 6 (597 871), 1 thread (median of $runs)"
printf '%-8s %10s %10s %10s %12s %12s %14s\n' size spheres parse_s build_s primary_mrays random_mrays primary_packet
for size in 4 5 6; do
    "$nffrt" gen balls --size "$size" -o "$tmp/balls$size.nff"
    st=$(for _ in $(seq "$runs"); do "$nffrt" render "$tmp/balls$size.nff" --width 64 --height 64 -q -o "$tmp/b.png" --stats-json "$tmp/b.json" --threads 1; python3 -c "import json,sys; d=json.load(open(sys.argv[1])); print(d['parse_s'], d['build_s'], d['primitives'])" "$tmp/b.json"; done)
    parse=$(echo "$st" | cut -d' ' -f1 | median); build=$(echo "$st" | cut -d' ' -f2 | median); prims=$(echo "$st" | head -1 | cut -d' ' -f3)
    b=$(for _ in $(seq "$runs"); do "$nffrt" bench "$tmp/balls$size.nff" --repeat 5 | tail -1; done)
    pm=$(echo "$b" | tr ' ' '\n' | grep "^primary_mrays=" | cut -d= -f2 | median)
    rm_=$(echo "$b" | tr ' ' '\n' | grep "^random_mrays=" | cut -d= -f2 | median)
    pp=$(echo "$b" | tr ' ' '\n' | grep "^primary_packet_mrays=" | cut -d= -f2 | median)
    printf '%-8s %10s %10.3f %10.3f %12.2f %12.2f %14.2f\n' "$size" "$prims" "$parse" "$build" "$pm" "$rm_" "$pp"
done

echo "== scale: whole --spd renders of nffrt gen balls and mount at growing sizes, 2 threads (median of $runs)"
printf '%-10s %10s %9s %9s %9s %12s %10s\n' scene prims parse_s build_s render_s ns_per_ray peak_MB
for gen in "balls 3" "balls 4" "balls 5" "balls 6" "mount 5" "mount 7" "mount 9"; do
    set -- $gen
    "$nffrt" gen "$1" --size "$2" -o "$tmp/scale.nff"
    st=$(for _ in $(seq "$runs"); do
        /usr/bin/time -f '%M' -o "$tmp/rss" "$nffrt" render "$tmp/scale.nff" --spd -q -o "$tmp/s.png" --stats-json "$tmp/s.json"
        python3 -c "import json,sys; d=json.load(open(sys.argv[1])); print(d['parse_s'], d['build_s'], d['render_s'], 1e9*d['render_s']/d['total_rays'], d['primitives'], int(open(sys.argv[2]).read().split()[-1])/1024)" "$tmp/s.json" "$tmp/rss"
    done)
    col() { echo "$st" | cut -d' ' -f"$1" | median; }
    printf '%-10s %10s %9.3f %9.3f %9.3f %12.1f %10.0f\n' "$1-$2" "$(echo "$st" | head -1 | cut -d' ' -f5)" "$(col 1)" "$(col 2)" "$(col 3)" "$(col 4)" "$(col 6)"
done

fi

if [ -x "$py" ]; then
    echo "== traversal, single thread, same rays (Mrays/s; each process reports the best and the median of its 10 passes, this table the median over $runs processes; occlusion: best)"
    printf '%-18s %-8s %9s %9s %7s | %9s %9s %7s | %9s %9s\n' scene rays emb-best nff-best ratio emb-med nff-med ratio emb-occl nff-occl
    # Embree's per-set median of its passes, from its "closest  1T ... [median]" lines.
    emb_median() { awk -v set="$1" '/^[a-z]+:/ {cur = $1} cur == set":" && /closest +1T/ {gsub(/[][]/, "", $NF); print $NF}'; }
    key() { tr ' ' '\n' | grep "^$1=" | cut -d= -f2 | median; }
    row() { # label set embree-output nffrt-summaries
        local eb em ob om eo oo
        eb=$(echo "$3" | grep -h '^scene=' | key "${2}_mrays"); em=$(echo "$3" | emb_median "$2" | median)
        eo=$(echo "$3" | grep -h '^scene=' | key "${2}_occl_mrays")
        ob=$(echo "$4" | key rays_best_mrays); om=$(echo "$4" | key rays_mrays); oo=$(echo "$4" | key rays_occl_best_mrays)
        printf '%-18s %-8s %9.2f %9.2f %7.2f | %9.2f %9.2f %7.2f | %9.2f %9.2f\n' "$1" "$2" "$eb" "$ob" "$(awk -v a="$ob" -v b="$eb" 'BEGIN {print a/b}')" \
            "$em" "$om" "$(awk -v a="$om" -v b="$em" 'BEGIN {print a/b}')" "$eo" "$oo"
    }
    for s in p3d/mount_very_high spd/tetra spd/teapot spd/gears; do
        name=${s#*/}; extra=(); [ "$name" = gears ] && extra=(--triangulate ear)
        "${embree_env[@]}" "$py" "$shared/bench/embree_anchor.py" "$shared/scenes/$s.nff" --repeat 1 "${extra[@]}" --dump-rays "$tmp" >/dev/null 2>&1
        # Embree's anchor skips mount's four spheres: the same rays against the same
        # geometry, i.e. the scene without them, make the "triangles only" rows (hits
        # then equal Embree's).
        if [ "$name" = mount_very_high ]; then grep -v '^s ' "$shared/scenes/$s.nff" >"$tmp/mount_tris.nff"; fi
        # The two programs alternate, run by run, so that the host's load falls on both.
        # Embree runs twice: with its default scene flags (NONE) and with
        # RTC_SCENE_FLAG_ROBUST, the counterpart of nffrt's box test, whose exits are
        # stretched against rounding (`accel::traverse::wide::FAR_SCALE`).
        e=""; er=""; declare -A n=() t=()
        for _ in $(seq "$runs"); do
            e+=$("${embree_env[@]}" "$py" "$shared/bench/embree_anchor.py" "$shared/scenes/$s.nff" --repeat 10 "${extra[@]}" 2>/dev/null)$'\n'
            er+=$("${embree_env[@]}" "$py" "$shared/bench/embree_anchor.py" "$shared/scenes/$s.nff" --repeat 10 --robust "${extra[@]}" 2>/dev/null)$'\n'
            for set in primary random; do
                n[$set]+=$("$nffrt" bench "$shared/scenes/$s.nff" --rays "$tmp/${name}_$set.f32" --rays-only --repeat 10 | tail -1)$'\n'
                if [ "$name" = mount_very_high ]; then
                    t[$set]+=$("$nffrt" bench "$tmp/mount_tris.nff" --rays "$tmp/${name}_$set.f32" --rays-only --repeat 10 | tail -1)$'\n'
                fi
            done
        done
        for set in primary random; do
            row "$name" "$set" "$e" "${n[$set]}"
            if [ "$name" = mount_very_high ]; then row "  triangles only" "$set" "$e" "${t[$set]}"; fi
            # Against robust Embree, on the same geometry (mount: triangles only).
            if [ "$name" = mount_very_high ]; then row "  Embree robust" "$set" "$er" "${t[$set]}"; else row "  Embree robust" "$set" "$er" "${n[$set]}"; fi
        done
        unset n t
    done
    # Embree's own best on this machine: native C, no binding, 8-ray coherent packets
    # (needs Debian's libembree-dev; skipped without it).
    if gcc -O2 -o "$tmp/embree_native" "$shared/bench/embree_native.c" -lembree3 2>/dev/null; then
        echo "== Embree native (C): single rays and coherent 8-ray packets, primary rays (Mrays/s, median of $runs; robust: Embree's RTC_SCENE_FLAG_ROBUST, a watertight triangle test as nffrt's, not its default)"
        printf '%-18s %10s %10s %14s %10s %14s\n' scene single packet8 packet8-robust nffrt nffrt-packet8
        # $runs summary lines of embree_native on $name's primary rays, run under "$@"
        # (an `env ...` prefix, or nothing).
        native() { for _ in $(seq "$runs"); do "$@" "$tmp/embree_native" "$tmp/${name}_tris.f32" "$tmp/${name}_primary.f32" --repeat 10 --packet 8 --coherent 2>/dev/null | tail -1; done; }
        for s in p3d/mount_very_high spd/tetra spd/teapot spd/gears; do
            name=${s#*/}; extra=(); [ "$name" = gears ] && extra=(--triangulate ear)
            "${embree_env[@]}" "$py" "$shared/bench/embree_anchor.py" "$shared/scenes/$s.nff" --repeat 1 "${extra[@]}" --dump-rays "$tmp" --dump-tris "$tmp" >/dev/null 2>&1
            e=$(native "${embree_env[@]}")
            single=$(echo "$e" | tr ' ' '\n' | grep "^single_mrays=" | cut -d= -f2 | median)
            packet=$(echo "$e" | tr ' ' '\n' | grep "^packet8_mrays=" | cut -d= -f2 | median)
            robust=nan
            if [ "$preload" = 1 ]; then
                er=$(native "${embree_robust_env[@]}")
                robust=$(echo "$er" | tr ' ' '\n' | grep "^packet8_mrays=" | cut -d= -f2 | median)
            fi
            n=$(for _ in $(seq "$runs"); do "$nffrt" bench "$shared/scenes/$s.nff" --rays "$tmp/${name}_primary.f32" --rays-only --repeat 10 | tail -1; done)
            ours=$(echo "$n" | tr ' ' '\n' | grep "^rays_mrays=" | cut -d= -f2 | median)
            ourp=$(echo "$n" | tr ' ' '\n' | grep "^rays_packet_mrays=" | cut -d= -f2 | median)
            printf '%-18s %10.2f %10.2f %14.2f %10.2f %14.2f\n' "$name" "$single" "$packet" "$robust" "$ours" "$ourp"
        done
    fi
fi

if [ -x "$py" ]; then
    # Scale against Embree: `nffrt gen mount` without its four spheres (the geometry
    # Embree's side traces), sizes 5 to 9 (2 048 to 524 288 triangles), the same
    # primary and random rays through both, one thread, fastest passes.
    echo "== scale: nffrt gen mount sizes 5 to 9 without its spheres, same rays, 1 thread (Mrays/s and ns per ray, fastest passes, median of $runs; Embree flags NONE)"
    printf '%-6s %8s | %9s %9s %7s %7s %7s | %9s %9s %7s %7s %7s\n' size tris emb-prim nff-prim ratio emb-ns nff-ns emb-rand nff-rand ratio emb-ns nff-ns
    key() { tr ' ' '\n' | grep "^$1=" | cut -d= -f2 | median; }
    declare -A ns=()
    for size in 5 6 7 8 9; do
        "$nffrt" gen mount --size "$size" | grep -v '^s ' >"$tmp/mount$size.nff"
        "${embree_env[@]}" "$py" "$shared/bench/embree_anchor.py" "$tmp/mount$size.nff" --repeat 1 --threads 1 --dump-rays "$tmp" >/dev/null 2>&1
        e=""; declare -A n=()
        for _ in $(seq "$runs"); do
            e+=$("${embree_env[@]}" "$py" "$shared/bench/embree_anchor.py" "$tmp/mount$size.nff" --repeat 10 --threads 1 --no-occlusion 2>/dev/null | tail -1)$'\n'
            for set in primary random; do
                n[$set]+=$("$nffrt" bench "$tmp/mount$size.nff" --rays "$tmp/mount${size}_$set.f32" --rays-only --repeat 10 | tail -1)$'\n'
            done
        done
        tris=$(echo "$e" | key tris)
        row=()
        for set in primary random; do
            eb=$(echo "$e" | key "${set}_mrays"); ob=$(echo "${n[$set]}" | key rays_best_mrays)
            ns[emb_${set}_$size]=$(awk -v a="$eb" 'BEGIN {printf "%.1f", 1e3 / a}')
            ns[nff_${set}_$size]=$(awk -v a="$ob" 'BEGIN {printf "%.1f", 1e3 / a}')
            row+=("$eb" "$ob" "$(awk -v a="$ob" -v b="$eb" 'BEGIN {print a / b}')" "${ns[emb_${set}_$size]}" "${ns[nff_${set}_$size]}")
        done
        printf '%-6s %8s | %9.2f %9.2f %7.2f %7s %7s | %9.2f %9.2f %7.2f %7s %7s\n' "$size" "$tris" "${row[@]}"
        unset n
    done
    growth() { awk -v a="${ns[$1_9]}" -v b="${ns[$1_5]}" 'BEGIN {printf "%.2f", a / b}'; }
    echo "time per ray, size 5 -> 9: primary Embree x$(growth emb_primary), nffrt x$(growth nff_primary); random Embree x$(growth emb_random), nffrt x$(growth nff_random)"
    echo "(balls sizes 4 to 6, nffrt alone: the scale table above; Embree's side traces triangles only)"

    # Builds of the same 524 288 triangles: Embree's rtcCommitScene (fastest of 5
    # fresh builds per process) against nffrt's Bvh::new (with the conversion of the
    # scene into primitives; fastest of 5), one thread and two.
    echo "== build: mount size 9 without its spheres (524 288 triangles), ms, median over $runs processes of the fastest of 5 builds"
    printf '%-8s %10s %10s %7s\n' threads embree nffrt ratio
    for threads in 1 2; do
        e=""; o=""
        for _ in $(seq "$runs"); do
            e+=$("${embree_env[@]}" "$py" "$shared/bench/embree_anchor.py" "$tmp/mount9.nff" --repeat 5 --threads "$threads" --rays primary --no-occlusion 2>/dev/null | tail -1)$'\n'
            o+=$("$nffrt" bench "$tmp/mount9.nff" --rays "$tmp/mount9_primary.f32" --rays-only --repeat 5 --threads "$threads" | tail -1)$'\n'
        done
        eb=$(echo "$e" | key build_ms); ob=$(echo "$o" | key build_best_ms)
        printf '%-8s %10.1f %10.1f %7.2f\n' "$threads" "$eb" "$ob" "$(awk -v a="$eb" -v b="$ob" 'BEGIN {print a / b}')"
    done
    echo "(ratio: Embree's time over nffrt's; above 1, nffrt builds faster)"
fi
