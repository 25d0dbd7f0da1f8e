#!/usr/bin/env bash
# Snapshot pictures: renders a fixed set of NFF and P3F scenes (and option variants)
# to PFM, linear floats bit for bit, and lists their SHA-256 sums. A design change
# that must not alter pictures is checked by comparing the lists of two builds:
#
#   scripts/snapshot.sh BINARY OUTDIR     # e.g. target/release/nffrt /tmp/snap-after
#   diff /tmp/snap-before/SUMS /tmp/snap-after/SUMS
#
# Scenes come from ../shared (the SPD, the course's P3F files) and examples/; a case
# whose scene is absent is listed as `absent`, one that fails as `error`, so lists
# compare line for line.
set -uo pipefail
cd "$(dirname "$0")/.."

bin=${1:?usage: scripts/snapshot.sh BINARY OUTDIR}
out=${2:?usage: scripts/snapshot.sh BINARY OUTDIR}
bin=$(realpath "$bin")
mkdir -p "$out"
: > "$out/SUMS"
shared=../shared/scenes

# name, scene, extra flags
cases=()
for s in balls gears mount rings teapot tetra tree; do
    cases+=("spd-$s|$shared/spd/$s.nff|")
    cases+=("spd-$s-corners|$shared/spd/$s.nff|--spd")
done
for s in balls_low balls_medium balls_high mount_low mount_high mount_very_high test_file; do
    cases+=("p3d-$s|$shared/p3d/$s.nff|")
done
cases+=("showcase-spp4|examples/showcase.nff|--spp 4")
cases+=("tetra-lens-spp4|$shared/spd/tetra.nff|--spp 4 --aperture 8 --focal 0.9")
cases+=("teapot-spp3-depth9|$shared/spd/teapot.nff|--spp 3 --max-depth 9")
for f in "$shared"/p3f/2019/*.p3f "$shared"/p3f/2025/*.p3f "$shared"/p3f/extensions/*.p3f; do
    name=$(basename "$(dirname "$f")")-$(basename "$f" .p3f)
    cases+=("p3f-$name|$f|")
done
cases+=("p3f-2019-balls_area_low-spp4|$shared/p3f/2019/balls_area_low.p3f|--spp 4")
cases+=("p3f-2019-balls_area_low-spp1|$shared/p3f/2019/balls_area_low.p3f|--spp 1")
cases+=("p3f-2019-balls_area_low-ls3|$shared/p3f/2019/balls_area_low.p3f|--light-samples 3")
cases+=("p3f-2019-dof-spp9|$shared/p3f/2019/dof.p3f|--spp 9")
cases+=("p3f-2025-balls_low-spp5-depth3|$shared/p3f/2025/balls_low.p3f|--spp 5 --max-depth 3")
# The path tracer: an emitter sampled by area (the Cornell box), Beer-Lambert glass
# (glass-row), Shirley's weekend scene (rough metals, moving spheres), a course
# scene's point lights.
cases+=("path-cornell-spp4|examples/cornell.p3f|--spp 4")
cases+=("path-glass-row-spp4|examples/glass-row.p3f|--spp 4")
cases+=("path-weekend-spp2|examples/weekend.p3f|--spp 2")
cases+=("path-2025-balls_low-spp3|$shared/p3f/2025/balls_low.p3f|--integrator path --spp 3")

for c in "${cases[@]}"; do
    IFS='|' read -r name scene flags <<< "$c"
    if [ ! -f "$scene" ]; then
        echo "absent  $name" >> "$out/SUMS"
        continue
    fi
    # shellcheck disable=SC2086
    if "$bin" render "$scene" $flags -q -o "$out/$name.pfm" 2> "$out/$name.err"; then
        echo "$(sha256sum < "$out/$name.pfm" | cut -c1-16)  $name" >> "$out/SUMS"
        rm -f "$out/$name.err"
    else
        echo "error   $name" >> "$out/SUMS"
    fi
done
cat "$out/SUMS"
