#!/usr/bin/env bash
# P3F scenes against POV-Ray 3.7, side by side in one run: whole-process wall times
# (start-up, parse, skybox decode, build, render, PNG written), medians of N runs with the
# programs alternating, and the pictures kept for comparison.
#
#   scripts/bench-p3f.sh [RUNS] [OUT_DIR]    RUNS repetitions (default 5), pictures and
#                                            logs to OUT_DIR (default target/bench-p3f)
#
# Rows (see scripts/pov/README.md for the POV-Ray scenes):
#   dof              nffrt on 2025/dof.p3f (800x600, its own spp 4, aperture 12, focal 1.5)
#                    with --accel bvh: the file says `accel none` (the course's switch,
#                    for comparing structures, which nffrt honours: a scan of its 9
#                    primitives, about 2x the BVH's time), and POV-Ray bounds its objects
#                    by its own hierarchy whatever the file says; against POV-Ray on scripts/pov/dof.pov (focal_blur, blur_samples 4)
#   balls_area_low   nffrt on 2019/balls_area_low.p3f --spp 16 (one area-light point per
#                    eye sample) against POV-Ray on scripts/pov/balls_area_low.pov (one eye
#                    ray per pixel, area_light 4x4 jitter adaptive 0, skybox)
#   ... --spp 1      nffrt's default for that scene: one eye ray per pixel, each area light
#                    on its 4x4 grid at every hit, against the same POV-Ray runs
#   ... full grid    the same nffrt runs against POV-Ray on that scene without `adaptive`
#                    (balls_area_low_full.pov, made here): all 16 shadow rays of each
#                    area light at every hit, exactly nffrt's work (like for like)
#   dragon           nffrt on 2025/dragon.p3f and 2019/dragon.p3f (goal: under 1 s)
# POV-Ray runs as the SPD peer does (../shared/bench/povray_peer.sh): +W +H of the scene,
# -A (no antialiasing), +WT2, -D, PNG, in a temporary working directory (its file I/O
# policy reads only there, so the skybox folder is copied in first, outside the timing),
# plus File_Gamma=1.0 (linear output like nffrt's; no effect on speed).
set -euo pipefail
if [ $# -gt 2 ] || [[ "${1:-}" == -* ]]; then
    echo "usage: $0 [RUNS] [OUT_DIR]" >&2
    exit 2
fi
cd "$(dirname "$0")/.."
runs=${1:-5}
out=${2:-target/bench-p3f}
p3f=../shared/scenes/p3f
nffrt=$PWD/target/release/nffrt
[ -d "$p3f" ] || { echo "$p3f is absent: no scenes to time" >&2; exit 2; }
command -v povray >/dev/null || { echo "povray not installed (apt-get install povray)" >&2; exit 2; }
[ -x "$nffrt" ] || cargo build --release -q
mkdir -p "$out"
out=$(cd "$out" && pwd)
work=$(mktemp -d); trap 'rm -rf "$work"' EXIT
cp -r "$p3f/2019/skybox" "$work/"
cp scripts/pov/dof.pov scripts/pov/balls_area_low.pov "$work/"
sed 's/ adaptive 0//' scripts/pov/balls_area_low.pov >"$work/balls_area_low_full.pov"

median() { sort -g | awk '{a[NR]=$1} END {print (NR%2 ? a[(NR+1)/2] : (a[NR/2]+a[NR/2+1])/2)}'; }
now() { date +%s%N; }
secs() { awk -v a="$1" -v b="$2" 'BEGIN {printf "%.3f\n", (b-a)/1e9}'; }

# nffrt NAME SCENE [FLAGS...]: one whole-process run; appends wall seconds to
# $work/NAME.times, CPU seconds (user + system) to $work/NAME.cpu and
# load (read, parse, the skybox faces' headers) / build / render (the faces decoded) seconds to $work/NAME.stages.
run_nffrt() {
    local name=$1 scene=$2 t0 t1; shift 2
    t0=$(now)
    /usr/bin/time -f '%U %S' -o "$work/cpu" \
        "$nffrt" render "$scene" "$@" -q -o "$out/$name-nffrt.png" --stats-json "$work/$name.json" 2>"$out/$name-nffrt.log"
    t1=$(now)
    secs "$t0" "$t1" >>"$work/$name.times"
    awk '{print $1 + $2}' "$work/cpu" >>"$work/$name.cpu"
    python3 -c "import json,sys; d=json.load(open(sys.argv[1])); print(d['load_s'], d['build_s'], d['render_s'])" \
        "$work/$name.json" >>"$work/$name.stages"
}

# povray NAME WIDTH HEIGHT: one whole-process run of $work/NAME.pov in $work.
run_povray() {
    local name=$1 t0 t1 rc=0
    t0=$(now)
    (cd "$work" && /usr/bin/time -f '%U %S' -o "$work/cpu" povray +I"$name.pov" +O"$out/$name-povray.png" \
        +FN +W"$2" +H"$3" -A +WT2 -D File_Gamma=1.0 >"$out/$name-povray.log" 2>&1) || rc=$?
    t1=$(now)
    if [ $rc -ne 0 ]; then
        echo "povray failed on $name (rc=$rc); log tail:" >&2
        tail -20 "$out/$name-povray.log" >&2
        exit 1
    fi
    secs "$t0" "$t1" >>"$work/pov-$name.times"
    awk '{print $1 + $2}' "$work/cpu" >>"$work/pov-$name.cpu"
    sed -n 's/.*Parse Time:.*(\([0-9.]*\) seconds).*/\1/p; s/.*Trace Time:.*(\([0-9.]*\) seconds).*/\1/p' \
        "$out/$name-povray.log" | paste -sd' ' >>"$work/pov-$name.stages"
}

for i in $(seq "$runs"); do
    echo "run $i of $runs" >&2
    run_nffrt dof "$p3f/2025/dof.p3f" --accel bvh
    run_povray dof 800 600
    run_nffrt balls_area_low "$p3f/2019/balls_area_low.p3f" --spp 16
    run_povray balls_area_low 512 512
    run_nffrt balls_area_low-spp1 "$p3f/2019/balls_area_low.p3f" --spp 1
    run_povray balls_area_low_full 512 512
    run_nffrt dragon-2025 "$p3f/2025/dragon.p3f"
    run_nffrt dragon-2019 "$p3f/2019/dragon.p3f"
done

med() { median <"$work/$1.times"; }
cpu() { median <"$work/$1.cpu" | awk '{printf "%.2f", $1}'; }
stage() { cut -d' ' -f"$2" "$work/$1.stages" | median; }
ratio() { awk -v a="$1" -v b="$2" 'BEGIN {printf "%.2f", a/b}'; }
echo
echo "P3F scenes, whole-process wall seconds, medians of $runs runs"
echo "(in brackets: nffrt's load / build / render, its skybox decoded during the render, POV-Ray's parse incl. skybox"
echo "decode / trace; CPU: user + system seconds of the whole process)"
echo "| scene | nffrt wall (stages) | POV-Ray 3.7 wall (stages) | POV-Ray / nffrt, wall | CPU nffrt / POV-Ray | POV-Ray / nffrt, CPU |"
echo "|---|---|---|---|---|---|"
row() {
    local label=$1 name=$2 pov=${3:-} n p stages
    n=$(med "$name")
    stages=$(printf '%.3f / %.3f / %.3f' "$(stage "$name" 1)" "$(stage "$name" 2)" "$(stage "$name" 3)")
    if [ -n "$pov" ]; then
        p=$(med "pov-$pov")
        printf '| %s | %s s (%s) | %s s (%.3f / %.3f) | **%sx** | %s / %s s | %sx |\n' "$label" "$n" "$stages" \
            "$p" "$(stage "pov-$pov" 1)" "$(stage "pov-$pov" 2)" "$(ratio "$p" "$n")" "$(cpu "$name")" \
            "$(cpu "pov-$pov")" "$(ratio "$(cpu "pov-$pov")" "$(cpu "$name")")"
    else
        printf '| %s | %s s (%s) | — | — | %s s | — |\n' "$label" "$n" "$stages" "$(cpu "$name")"
    fi
}
row "2025/dof.p3f, 800x600, spp 4, aperture 12" dof dof
row "2019/balls_area_low.p3f, --spp 16" balls_area_low balls_area_low
row "2019/balls_area_low.p3f, --spp 1 (4x4 grid per hit) vs adaptive 0" balls_area_low-spp1 balls_area_low
row "2019/balls_area_low.p3f, --spp 1 vs POV-Ray's full 4x4 grid (no adaptive)" balls_area_low-spp1 balls_area_low_full
row "2025/dragon.p3f, 800x600" dragon-2025
row "2019/dragon.p3f, 800x600" dragon-2019
echo
echo "pictures and logs: $out"
# Side by side (nffrt left, POV-Ray right) if Python has PIL; skipped otherwise.
if python3 -c "import PIL" 2>/dev/null; then
    for name in dof balls_area_low; do
        python3 - "$out/$name-nffrt.png" "$out/$name-povray.png" "$out/$name-side-by-side.png" <<'PY'
import sys
from PIL import Image
a, b = (Image.open(p).convert("RGB") for p in sys.argv[1:3])
c = Image.new("RGB", (a.width + 8 + b.width, max(a.height, b.height)), "white")
c.paste(a, (0, 0))
c.paste(b, (a.width + 8, 0))
c.save(sys.argv[3])
PY
    done
    echo "side by side (nffrt left, POV-Ray right): $out/dof-side-by-side.png, $out/balls_area_low-side-by-side.png"
else
    echo "side-by-side pictures skipped: python3 has no PIL"
fi
